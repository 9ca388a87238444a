//! What each proof explored, written as a small JSON record that
//! `fieldguide evidence` reads (README.md, "Evidence for a safety assessor").
//!
//! A proof calls [`start`] with its name as a string literal (the report
//! finds the expected names by reading `proofs/tests/*.rs` for
//! `evidence::start("…"`), runs, then calls [`Run::finish`] with what it
//! explored. [`start`] writes a `running` record at once, so a proof that
//! fails never leaves a passed record behind: the report shows it failed.
//! Records go to `$FIELDGUIDE_EVIDENCE_DIR` (default `target/evidence/` of
//! the workspace), one file per proof, stamped with the commit
//! (`git rev-parse HEAD`) and whether the tree had uncommitted changes.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use serde_json::{json, Value};

/// The environment variable naming the records' folder.
pub const DIR_VAR: &str = "FIELDGUIDE_EVIDENCE_DIR";

/// What kind of proof a record is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A stateright model, every reachable state explored.
    Model,
    /// A bolero harness (exhaustive here, a Kani proof where Kani runs).
    Harness,
    /// A deliberately wrong machine the checks must report.
    Mutant,
}

impl Kind {
    const fn label(self) -> &'static str {
        match self {
            Self::Model => "stateright model",
            Self::Harness => "bolero harness",
            Self::Mutant => "mutant",
        }
    }
}

/// What a proof explored; the fields that do not apply stay `None`/empty.
#[derive(Clone, Debug, Default)]
pub struct Explored {
    /// The properties checked (stateright names or requirement IDs).
    pub properties: Vec<String>,
    /// Distinct states (a model).
    pub states: Option<u64>,
    /// Transitions taken (a model).
    pub transitions: Option<u64>,
    /// Deepest path explored, in ticks.
    pub depth: Option<u64>,
    /// Input sequences or cases run (a harness).
    pub sequences: Option<u64>,
    /// For a mutant: the fault injected, and it was caught.
    pub mutant: Option<String>,
}

/// A proof under way; [`Run::finish`] records it as passed.
#[derive(Debug)]
pub struct Run {
    name: &'static str,
    kind: Kind,
    started: Instant,
}

/// Starts the record of proof `name`: writes it as `running` (a failed
/// proof leaves it so).
#[must_use]
pub fn start(name: &'static str, kind: Kind) -> Run {
    let run = Run {
        name,
        kind,
        started: Instant::now(),
    };
    write(&run, "running", &Explored::default());
    run
}

impl Run {
    /// The proof's name.
    #[must_use]
    pub const fn name(&self) -> &'static str {
        self.name
    }

    /// Records the proof as passed, with what it explored and how long it took.
    pub fn finish(self, explored: &Explored) {
        write(&self, "passed", explored);
    }
}

/// The records' folder.
#[must_use]
pub fn dir() -> PathBuf {
    std::env::var_os(DIR_VAR).map_or_else(
        || workspace().join("target").join("evidence"),
        PathBuf::from,
    )
}

/// The workspace root (this crate's parent folder).
fn workspace() -> PathBuf {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    crate_dir.parent().unwrap_or(crate_dir).to_path_buf()
}

/// The file of proof `name` in `dir`.
#[must_use]
pub fn file(dir: &Path, name: &str) -> PathBuf {
    let slug: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    dir.join(format!("{slug}.json"))
}

/// `git` in the workspace, its output trimmed; `None` when it fails.
fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(workspace())
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// Under Kani the proofs run symbolically: nothing is recorded.
#[cfg(kani)]
fn write(_: &Run, _: &str, _: &Explored) {}

#[cfg(not(kani))]
fn write(run: &Run, status: &str, explored: &Explored) {
    let record: Value = json!({
        "name": run.name,
        "kind": run.kind.label(),
        "status": status,
        "commit": git(&["rev-parse", "HEAD"]),
        "dirty": git(&["status", "--porcelain"]).map(|s| !s.is_empty()),
        "duration_s": run.started.elapsed().as_secs_f64(),
        "properties": explored.properties,
        "states": explored.states,
        "transitions": explored.transitions,
        "depth": explored.depth,
        "sequences": explored.sequences,
        "mutant": explored.mutant,
    });
    let dir = dir();
    // A record that cannot be written shows as missing in the report, which
    // is red: the proof itself is not failed for it.
    if std::fs::create_dir_all(&dir).is_ok() {
        let _ = std::fs::write(file(&dir, run.name), record.to_string());
    }
}

/// What a harness explored: `sequences` inputs of `depth` ticks (none for
/// a single case), checking `properties`.
#[must_use]
pub fn harness(properties: &[&str], sequences: u64, depth: Option<u64>) -> Explored {
    Explored {
        properties: properties.iter().map(|p| (*p).to_owned()).collect(),
        sequences: Some(sequences),
        depth,
        ..Explored::default()
    }
}

/// Explores every reachable state of `model`, asserts every property,
/// prints what was explored, records it in `run`, and returns the number of
/// distinct states.
pub fn explore<M>(run: Run, model: M) -> usize
where
    M: stateright::Model + Send + Sync + 'static,
    M::State: Clone + core::fmt::Debug + core::hash::Hash + PartialEq + Send + Sync + 'static,
    M::Action: Clone + core::fmt::Debug + PartialEq + Send + Sync + 'static,
{
    use stateright::Checker;
    let properties = model
        .properties()
        .iter()
        .map(|p| p.name.to_owned())
        .collect();
    let checker = model.checker().spawn_bfs().join();
    checker.assert_properties();
    let states = checker.unique_state_count();
    println!(
        "{}: {states} states, {} transitions, depth {}, {:.1?}",
        run.name(),
        checker.state_count(),
        checker.max_depth(),
        run.started.elapsed()
    );
    run.finish(&Explored {
        properties,
        states: u64::try_from(states).ok(),
        transitions: u64::try_from(checker.state_count()).ok(),
        depth: u64::try_from(checker.max_depth()).ok(),
        ..Explored::default()
    });
    states
}

/// A mutant's record: the `fault` injected was caught breaking `property`.
#[must_use]
pub fn mutant_caught(property: &str, fault: &str) -> Explored {
    Explored {
        properties: vec![property.to_owned()],
        mutant: Some(fault.to_owned()),
        ..Explored::default()
    }
}
