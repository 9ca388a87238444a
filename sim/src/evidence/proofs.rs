//! The proofs' results: the records `fieldguide_proofs::evidence` wrote
//! while `cargo test -p fieldguide-proofs` ran.
//!
//! The expected proofs are the names given to `evidence::start("…"` in
//! `proofs/tests/*.rs`. A proof without a record, with a record still
//! `running` (it failed or was cut off) or stamped with another commit is
//! red: the report never shows an old or partial run as complete.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::Status;

/// What one proof explored, as it recorded it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// The proof's name.
    pub name: String,
    /// `stateright model`, `bolero harness` or `mutant`.
    pub kind: String,
    /// `passed`, or `running` when it never finished.
    pub status: String,
    /// `git rev-parse HEAD` when it ran.
    pub commit: Option<String>,
    /// Uncommitted changes in the tree when it ran.
    pub dirty: Option<bool>,
    /// How long it ran, seconds.
    pub duration_s: f64,
    /// The properties it checked.
    #[serde(default)]
    pub properties: Vec<String>,
    /// Distinct states (a model).
    pub states: Option<u64>,
    /// Transitions (a model).
    pub transitions: Option<u64>,
    /// Deepest path, ticks.
    pub depth: Option<u64>,
    /// Sequences or cases (a harness).
    pub sequences: Option<u64>,
    /// The fault a mutant injects (caught when the record passed).
    pub mutant: Option<String>,
}

/// One expected proof and its verdict.
#[derive(Debug, Clone, Serialize)]
pub struct Proof {
    /// The proof's name.
    pub name: String,
    /// The test file declaring it.
    pub file: String,
    /// Its record, if any.
    pub record: Option<Record>,
    /// `pass`, or `fail` with why.
    pub status: Status,
    /// Why it is red.
    pub problem: Option<String>,
}

/// The section.
#[derive(Debug, Clone, Serialize)]
pub struct Proofs {
    /// `fail` when a proof is missing, failed or stale.
    pub status: Status,
    /// What is wrong.
    pub problems: Vec<String>,
    /// Every expected proof.
    pub proofs: Vec<Proof>,
}

/// The proofs named in `root/proofs/tests/*.rs` with their records in
/// `records`, checked against the current `commit`.
#[must_use]
pub fn gather(root: &Path, records: &Path, commit: &Option<String>) -> Proofs {
    let mut problems = Vec::new();
    let expected = expected(&root.join("proofs").join("tests")).unwrap_or_else(|e| {
        problems.push(e);
        Vec::new()
    });
    if expected.is_empty() {
        problems.push("no proof declares `evidence::start(\"…\"` in proofs/tests".to_owned());
    }
    let found = read_records(records);
    let proofs: Vec<Proof> = expected
        .into_iter()
        .map(|(file, name)| {
            let record = found.get(&name).cloned();
            let problem = judge(record.as_ref(), commit, records);
            if let Some(p) = &problem {
                problems.push(format!("{name}: {p}"));
            }
            Proof {
                status: if problem.is_some() {
                    Status::Fail
                } else {
                    Status::Pass
                },
                name,
                file,
                record,
                problem,
            }
        })
        .collect();
    Proofs {
        status: Status::of(&problems),
        problems,
        proofs,
    }
}

/// Why `record` does not stand for a passed proof at `commit`, if so.
#[must_use]
pub fn judge(record: Option<&Record>, commit: &Option<String>, records: &Path) -> Option<String> {
    let Some(r) = record else {
        return Some(format!(
            "no record in {} (run `cargo test --release -p fieldguide-proofs` first)",
            records.display()
        ));
    };
    if r.status != "passed" {
        return Some(format!(
            "recorded `{}`: the proof failed or was cut off",
            r.status
        ));
    }
    match (&r.commit, commit) {
        (Some(a), Some(b)) if a == b => None,
        (Some(a), Some(b)) => Some(format!("stale: recorded at commit {a}, the tree is at {b}")),
        _ => Some("no commit to compare the record with (git unavailable)".to_owned()),
    }
}

/// (file, name) of every `evidence::start("name"` in the `*.rs` files of `dir`.
fn expected(dir: &Path) -> Result<Vec<(String, String)>, String> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    files.sort();
    let mut out = Vec::new();
    for path in files {
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let file = path.file_name().map_or_else(String::new, |n| {
            format!("proofs/tests/{}", n.to_string_lossy())
        });
        for name in declared(&text) {
            out.push((file.clone(), name));
        }
    }
    Ok(out)
}

/// The string literals given to `evidence::start(` in `text`.
#[must_use]
pub fn declared(text: &str) -> Vec<String> {
    text.split("evidence::start(")
        .skip(1)
        .filter_map(|rest| {
            let rest = rest.trim_start().strip_prefix('"')?;
            rest.split_once('"').map(|(name, _)| name.to_owned())
        })
        .collect()
}

/// Every readable record in `dir`, by name.
fn read_records(dir: &Path) -> BTreeMap<String, Record> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return BTreeMap::new();
    };
    entries
        .filter_map(Result::ok)
        .filter_map(|e| std::fs::read_to_string(e.path()).ok())
        .filter_map(|text| serde_json::from_str::<Record>(&text).ok())
        .map(|r| (r.name.clone(), r))
        .collect()
}
