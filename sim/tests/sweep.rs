//! Seed sweeps: the library's `sweep::sweep` and the program's
//! `fieldguide sweep <scenario> --seeds FIRST..=LAST`, against single runs
//! with the same seeds.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]

use std::path::PathBuf;
use std::process::Command;

use fieldguide_sim::metrics::{summarize, Summary};
use fieldguide_sim::output::{FILES, SWEEP_FILE};
use fieldguide_sim::runner;
use fieldguide_sim::scenario::Source;
use fieldguide_sim::sweep::{self, sweep_csv, Seeds};

const SCENARIO: &str = "path-tracking";

/// One run of the built-in scenario with `seed`, summarised.
fn single(seed: u64) -> Summary {
    let source = Source::builtin(SCENARIO).unwrap();
    let (setup, mut rng) = runner::prepare_with_seed(&source, seed).unwrap();
    summarize(&setup, &runner::run(&setup, &mut rng))
}

/// An empty scratch folder for this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "fieldguide-sweep-test-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_sweep_of_two_seeds_is_the_two_single_runs() {
    let singles = [single(1), single(2)];
    // Two seeds, two fields: the rows differ (the comparison below means something).
    assert_ne!(singles[0], singles[1]);
    assert_eq!((singles[0].seed, singles[1].seed), (1, 2));

    // The library: one summary per seed, in order, each handed over as measured.
    let source = Source::builtin(SCENARIO).unwrap();
    let mut seen = Vec::new();
    let result = sweep::sweep(&source, Seeds::new(1, 2).unwrap(), |s| seen.push(s.seed)).unwrap();
    assert_eq!(seen, [1, 2]);
    assert_eq!(result.scenario, SCENARIO);
    assert_eq!(result.rows, singles);

    // The program: the same rows in `sweep.csv`, a row per seed and the worst
    // row on screen, and no per-seed trace or plot.
    let dir = scratch("two");
    let out = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["sweep", SCENARIO, "--seeds", "1..=2", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join(SCENARIO).join(SWEEP_FILE)).unwrap();
    assert_eq!(csv, sweep_csv(&singles));
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(
        lines[1].starts_with("1,") && lines[2].starts_with("2,"),
        "{csv}"
    );
    for f in FILES {
        assert!(!dir.join(SCENARIO).join(f).exists(), "{f} written");
    }
    let first_cell = |l: &str| l.split_whitespace().next().unwrap_or("").to_owned();
    let rows: Vec<String> = stdout.lines().map(first_cell).collect();
    for expected in ["seed", "1", "2", "worst", "at"] {
        assert!(rows.iter().any(|r| r == expected), "{expected}: {stdout}");
    }
    // The worst row holds the larger maximum |y| of the two runs, to 4 decimals.
    let worst_max = singles
        .iter()
        .map(|s| s.lateral_error_m.max_abs)
        .fold(0.0, f64::max);
    let worst_line = stdout.lines().find(|l| first_cell(l) == "worst").unwrap();
    assert!(
        worst_line.contains(&format!("{worst_max:.4}")),
        "{worst_line}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_seed_ranges_and_unknown_scenarios_exit_with_code_2() {
    let dir = scratch("bad");
    for (args, says) in [
        (vec!["sweep", SCENARIO, "--seeds", "5..=4"], "empty range"),
        (vec!["sweep", SCENARIO, "--seeds", "20"], "FIRST..=LAST"),
        (vec!["sweep", SCENARIO, "--seeds", "1..=x"], "whole numbers"),
        (vec!["sweep", SCENARIO], "--seeds"),
        (
            vec!["sweep", "no-such-scenario", "--seeds", "1..=2"],
            "path-tracking",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
            .args(&args)
            .arg("--out")
            .arg(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
    // Nothing was written.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(&dir);
}
