//! The campaign's table (Markdown, one line per bound of every case: the
//! worst figure, the seed it came from, the limit, pass or the failing
//! seeds) and its files.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{keep_worst, CaseResult};
use crate::error::SimError;

/// A figure as the table prints it.
fn figure(value: f64) -> String {
    if value.is_infinite() {
        "never".to_owned()
    } else if value.fract() == 0.0 && value.abs() < 1e9 {
        format!("{value:.0}")
    } else {
        format!("{value:.3}")
    }
}

/// The Markdown table of `results`.
#[must_use]
pub fn table_md(results: &[CaseResult]) -> String {
    let mut text = String::from(
        "| class | scenario | seeds | figure | worst | at seed | limit | result |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for r in results {
        for w in &r.bounds {
            let known = if r.known_failure.is_some()
                && w.failed_seeds
                    .iter()
                    .all(|s| r.expected_failures.contains(s))
            {
                "known "
            } else {
                ""
            };
            let result = if w.failed_seeds.is_empty() {
                "pass".to_owned()
            } else {
                format!(
                    "{known}FAIL (seeds {})",
                    w.failed_seeds
                        .iter()
                        .map(u64::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            // No seed is to blame for a figure that is nothing on every seed.
            let seed = if w.judged.value == 0.0 {
                "-".to_owned()
            } else {
                w.seed.to_string()
            };
            let _ = writeln!(
                text,
                "| {} | `{}` | {} | {} | {} | {seed} | {} | {result} |",
                r.class,
                r.scenario,
                r.seeds,
                w.judged.what.replace('|', "\\|"),
                figure(w.judged.value),
                figure(w.judged.limit),
            );
        }
    }
    text
}

/// Writes `stress.md` and `stress.json` to `out/stress/`, and the trace,
/// summary and plots of every case's worst seed to
/// `out/stress/<scenario>-seed-<n>/`; returns the folder.
///
/// # Errors
/// When a file cannot be written or a worst seed cannot be run again.
pub fn write(out: &Path, results: &[CaseResult]) -> Result<PathBuf, SimError> {
    let dir = out.join("stress");
    let json = serde_json::to_string_pretty(results).map_err(|e| SimError::Write {
        file: dir.join("stress.json"),
        source: std::io::Error::other(e),
    })?;
    crate::output::write_files(
        &dir,
        &[("stress.md", table_md(results)), ("stress.json", json)],
    )?;
    for result in results {
        keep_worst(result, &dir)?;
    }
    Ok(dir)
}
