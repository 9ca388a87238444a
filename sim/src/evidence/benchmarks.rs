//! The benchmark figures of the last criterion run
//! (`target/criterion/**/new/estimates.json`, the median and its confidence
//! interval) and the machine that produced the report (`/proc/cpuinfo`).
//!
//! No results at all is red unless the benchmarks were deliberately skipped
//! (`--no-benchmarks`), which shows them as skipped.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use serde::Serialize;
use serde_json::Value;

use super::provenance::utc;
use super::Status;

/// One benchmark's figures.
#[derive(Debug, Clone, Serialize)]
pub struct Benchmark {
    /// Criterion's id (`group/function/parameter`).
    pub id: String,
    /// Median time per iteration, nanoseconds.
    pub median_ns: f64,
    /// The median's 95 % confidence interval, nanoseconds.
    pub interval_ns: (f64, f64),
}

/// The machine the figures were read on.
#[derive(Debug, Clone, Serialize)]
pub struct Machine {
    /// `/proc/cpuinfo`'s `model name`.
    pub cpu: String,
    /// Logical cores.
    pub cores: usize,
}

/// The section.
#[derive(Debug, Clone, Serialize)]
pub struct Benchmarks {
    /// `fail` without results, `skipped` when told.
    pub status: Status,
    /// What is wrong.
    pub problems: Vec<String>,
    /// When the newest result was written (UTC).
    pub measured: Option<String>,
    /// The machine.
    pub machine: Option<Machine>,
    /// Every benchmark, by id.
    pub benchmarks: Vec<Benchmark>,
}

impl Benchmarks {
    /// Deliberately skipped.
    #[must_use]
    pub const fn skipped() -> Self {
        Self {
            status: Status::Skipped,
            problems: Vec::new(),
            measured: None,
            machine: None,
            benchmarks: Vec::new(),
        }
    }
}

/// Reads every `new/estimates.json` under `criterion`.
#[must_use]
pub fn gather(criterion: &Path) -> Benchmarks {
    let mut files = Vec::new();
    find_estimates(criterion, &mut files);
    files.sort();
    let mut benchmarks = Vec::new();
    let mut problems = Vec::new();
    let mut newest: Option<SystemTime> = None;
    for file in files {
        let Some(dir) = file.parent().and_then(Path::parent) else {
            continue;
        };
        let id = std::fs::read_to_string(dir.join("new").join("benchmark.json"))
            .ok()
            .and_then(|t| serde_json::from_str::<Value>(&t).ok())
            .and_then(|v| v.get("full_id").and_then(Value::as_str).map(str::to_owned))
            .unwrap_or_else(|| {
                dir.strip_prefix(criterion)
                    .unwrap_or(dir)
                    .display()
                    .to_string()
            });
        let median = std::fs::read_to_string(&file)
            .ok()
            .and_then(|t| serde_json::from_str::<Value>(&t).ok())
            .and_then(|v| v.get("median").cloned());
        let number = |m: &Value, path: &[&str]| {
            path.iter()
                .try_fold(m, |v, k| v.get(k))
                .and_then(Value::as_f64)
        };
        match median.as_ref().and_then(|m| {
            Some((
                number(m, &["point_estimate"])?,
                number(m, &["confidence_interval", "lower_bound"])?,
                number(m, &["confidence_interval", "upper_bound"])?,
            ))
        }) {
            Some((median_ns, low, high)) => benchmarks.push(Benchmark {
                id,
                median_ns,
                interval_ns: (low, high),
            }),
            None => problems.push(format!("{}: no median", file.display())),
        }
        if let Ok(modified) = std::fs::metadata(&file).and_then(|m| m.modified()) {
            newest = Some(newest.map_or(modified, |n| n.max(modified)));
        }
    }
    if benchmarks.is_empty() {
        problems.push(format!(
            "no benchmark results yet in {} (run `cargo bench`, or pass --no-benchmarks)",
            criterion.display()
        ));
    }
    Benchmarks {
        status: Status::of(&problems),
        problems,
        measured: newest.map(utc),
        machine: machine(),
        benchmarks,
    }
}

/// Every `*/new/estimates.json` below `dir`, skipping criterion's `report`.
fn find_estimates(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for path in entries.filter_map(Result::ok).map(|e| e.path()) {
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n == "report") {
                continue;
            }
            let estimates = path.join("estimates.json");
            if path.file_name().is_some_and(|n| n == "new") && estimates.is_file() {
                out.push(estimates);
            } else {
                find_estimates(&path, out);
            }
        }
    }
}

/// The CPU model and the number of logical cores, from `/proc/cpuinfo`.
fn machine() -> Option<Machine> {
    let text = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    let cpu = text
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map_or_else(|| "unknown".to_owned(), |(_, v)| v.trim().to_owned());
    let cores = text.lines().filter(|l| l.starts_with("processor")).count();
    Some(Machine { cpu, cores })
}
