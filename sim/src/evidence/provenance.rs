//! What the report is evidence for: the commit (and whether the tree had
//! uncommitted changes, which is red: the report is then for no commit),
//! the toolchain (`rustc -V`, `cargo -V`), every dependency with its
//! licence (`cargo metadata --format-version 1`), and the date (UTC).

use std::path::Path;
use std::time::SystemTime;

use serde::Serialize;
use serde_json::Value;

use super::{command, Status};

/// One package of the dependency graph.
#[derive(Debug, Clone, Serialize)]
pub struct Dependency {
    /// Package name.
    pub name: String,
    /// Version.
    pub version: String,
    /// SPDX licence expression (`None`: none declared).
    pub license: Option<String>,
}

/// The section.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// `fail` on a dirty tree or a tool that cannot run.
    pub status: Status,
    /// What is wrong.
    pub problems: Vec<String>,
    /// `git rev-parse HEAD`.
    pub commit: Option<String>,
    /// Uncommitted changes (`git status --porcelain` not empty).
    pub dirty: Option<bool>,
    /// `rustc -V`.
    pub rustc: Option<String>,
    /// `cargo -V`.
    pub cargo: Option<String>,
    /// When the report was made, UTC.
    pub date: String,
    /// The workspace's packages and every dependency, by name.
    pub dependencies: Vec<Dependency>,
}

/// Reads the provenance of the project at `root`.
#[must_use]
pub fn gather(root: &Path) -> Provenance {
    let mut problems = Vec::new();
    let mut run = |program: &str, args: &[&str]| {
        command(Path::new(program), args, root)
            .map_err(|e| problems.push(e))
            .ok()
    };
    let commit = run("git", &["rev-parse", "HEAD"]);
    let dirty = run("git", &["status", "--porcelain"]).map(|s| !s.is_empty());
    let rustc = run("rustc", &["-V"]);
    let cargo = run("cargo", &["-V"]);
    let metadata = run("cargo", &["metadata", "--format-version", "1", "--locked"]);
    if dirty == Some(true) {
        problems.push(
            "the tree has uncommitted changes: this report is the evidence of no commit".to_owned(),
        );
    }
    let dependencies = metadata.map_or_else(Vec::new, |m| dependencies(&m));
    Provenance {
        status: Status::of(&problems),
        problems,
        commit,
        dirty,
        rustc,
        cargo,
        date: utc(SystemTime::now()),
        dependencies,
    }
}

/// The packages of `cargo metadata`'s JSON, by name then version.
fn dependencies(metadata: &str) -> Vec<Dependency> {
    let Ok(v) = serde_json::from_str::<Value>(metadata) else {
        return Vec::new();
    };
    let mut out: Vec<Dependency> = v
        .get("packages")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .map(|p| {
            let text = |k: &str| p.get(k).and_then(Value::as_str).map(str::to_owned);
            Dependency {
                name: text("name").unwrap_or_default(),
                version: text("version").unwrap_or_default(),
                license: text("license"),
            }
        })
        .collect();
    out.sort_by(|a, b| (&a.name, &a.version).cmp(&(&b.name, &b.version)));
    out
}

/// `time` as `YYYY-MM-DD hh:mm:ss UTC`.
#[must_use]
pub fn utc(time: SystemTime) -> String {
    let secs = time
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let days = i64::try_from(secs / 86_400).unwrap_or(0);
    let rest = secs % 86_400;
    // Days since 1970-01-01 to a civil date (proleptic Gregorian calendar).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rest / 3_600,
        rest % 3_600 / 60,
        rest % 60
    )
}
