//! `fieldguide evidence`: one report for a safety assessor (README.md,
//! "Evidence for a safety assessor"), written as `index.html` (no scripts,
//! plots inline) and `evidence.json`.
//!
//! Sections, one module each: [`requirements`] (the matrix of `spec/` from
//! duvet's own JSON report), [`proofs`] (the records the proofs wrote),
//! [`closed_loop`] (the built-in scenarios and the sweeps, run here),
//! [`benchmarks`] (the last criterion run) and [`provenance`] (commit,
//! toolchain, dependencies with licences, date). Each section is
//! [`Status::Pass`], [`Status::Fail`] with its problems, or
//! [`Status::Skipped`] when a flag said so; any failed section makes the
//! report incomplete, shown in red, and the command exit non-zero.

pub mod benchmarks;
pub mod closed_loop;
pub mod html;
pub mod proofs;
pub mod provenance;
pub mod requirements;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::sweep::Seeds;
use crate::SimError;

/// A section's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Everything it shows is fresh and complete.
    Pass,
    /// Something is missing, stale or failed (its problems say what).
    Fail,
    /// Deliberately not produced (a flag); the report is not complete.
    Skipped,
}

impl Status {
    /// `Fail` when `problems` is not empty, `Pass` otherwise.
    #[must_use]
    pub fn of(problems: &[String]) -> Self {
        if problems.is_empty() {
            Self::Pass
        } else {
            Self::Fail
        }
    }

    /// Its label in the report.
    #[must_use]
    pub const fn label(self) -> &'static str {
        match self {
            Self::Pass => "pass",
            Self::Fail => "FAIL",
            Self::Skipped => "skipped",
        }
    }
}

/// What to put in the report, and where its inputs are.
#[derive(Debug, Clone)]
pub struct Options {
    /// The project's root: `spec/`, `.duvet/`, `proofs/tests/`.
    pub root: PathBuf,
    /// Where the scenarios write their files; the report goes to
    /// `<out>/evidence/`.
    pub out: PathBuf,
    /// The proofs' records (`FIELDGUIDE_EVIDENCE_DIR`, default
    /// `<root>/target/evidence`).
    pub records: PathBuf,
    /// Criterion's folder (default `criterion/` in `$CARGO_TARGET_DIR`, or
    /// else in `<root>/target`).
    pub criterion: PathBuf,
    /// The duvet program (found on `PATH` by default).
    pub duvet: PathBuf,
    /// The seeds of each sweep; `None` skips the closed loop.
    pub sweep_seeds: Option<Seeds>,
    /// Benchmarks deliberately skipped.
    pub skip_benchmarks: bool,
}

impl Options {
    /// The defaults for the project at `root`, scenarios written to `out`.
    #[must_use]
    pub fn new(root: &Path, out: &Path) -> Self {
        Self {
            root: root.to_path_buf(),
            out: out.to_path_buf(),
            records: std::env::var_os("FIELDGUIDE_EVIDENCE_DIR")
                .map_or_else(|| root.join("target").join("evidence"), PathBuf::from),
            criterion: std::env::var_os("CARGO_TARGET_DIR")
                .map_or_else(|| root.join("target"), PathBuf::from)
                .join("criterion"),
            duvet: PathBuf::from("duvet"),
            sweep_seeds: Seeds::new(1, 10).ok(),
            skip_benchmarks: false,
        }
    }
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// `pass` only when every section passed.
    pub status: Status,
    /// Commit, toolchain, dependencies, date.
    pub provenance: provenance::Provenance,
    /// The requirement matrix.
    pub requirements: requirements::Matrix,
    /// The proofs' results.
    pub proofs: proofs::Proofs,
    /// The scenarios' and the sweeps' figures.
    pub closed_loop: closed_loop::ClosedLoop,
    /// The last criterion run.
    pub benchmarks: benchmarks::Benchmarks,
}

impl Report {
    /// Gathers every section.
    ///
    /// # Errors
    /// When a scenario cannot be set up or its files cannot be written.
    pub fn gather(options: &Options) -> Result<Self, SimError> {
        let provenance = provenance::gather(&options.root);
        let requirements = requirements::gather(&options.root, &options.duvet);
        let proofs = proofs::gather(&options.root, &options.records, &provenance.commit);
        let closed_loop = match options.sweep_seeds {
            Some(seeds) => closed_loop::gather(&options.out, seeds)?,
            None => closed_loop::ClosedLoop::skipped(),
        };
        let benchmarks = if options.skip_benchmarks {
            benchmarks::Benchmarks::skipped()
        } else {
            benchmarks::gather(&options.criterion)
        };
        let statuses = [
            provenance.status,
            requirements.status,
            proofs.status,
            closed_loop.status,
            benchmarks.status,
        ];
        let status = if statuses.contains(&Status::Fail) {
            Status::Fail
        } else if statuses.contains(&Status::Skipped) {
            Status::Skipped
        } else {
            Status::Pass
        };
        Ok(Self {
            status,
            provenance,
            requirements,
            proofs,
            closed_loop,
            benchmarks,
        })
    }

    /// Writes `index.html` and `evidence.json` into `dir` (created; earlier
    /// files replaced) and returns `dir`.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub fn write(&self, dir: &Path) -> Result<PathBuf, SimError> {
        let json = serde_json::to_string_pretty(self).map_err(|e| SimError::Write {
            file: dir.join("evidence.json"),
            source: e.into(),
        })?;
        crate::output::write_files(
            dir,
            &[("evidence.json", json), ("index.html", html::render(self))],
        )?;
        Ok(dir.to_path_buf())
    }
}

/// Runs `program` with `args` in `dir`; its standard output, or why it
/// failed (not found, or its exit status and standard error).
pub(crate) fn command(program: &Path, args: &[&str], dir: &Path) -> Result<String, String> {
    let out = std::process::Command::new(program)
        .args(args)
        .current_dir(dir)
        .output()
        .map_err(|e| format!("`{}` could not run: {e}", program.display()))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).trim().to_owned())
    } else {
        Err(format!(
            "`{} {}` failed ({}): {}",
            program.display(),
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}
