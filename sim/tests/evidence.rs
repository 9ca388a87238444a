//! `fieldguide evidence`: every requirement of spec/ appears with its checks,
//! and an incomplete input (a requirement without a test, no duvet, stale or
//! failed proof records, no benchmark results) is red and exits non-zero.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, SystemTime};

use fieldguide_sim::evidence::{
    benchmarks, closed_loop, html, proofs, provenance, requirements, Options, Report, Status,
};

/// The project's root (this crate's parent).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// duvet: on PATH, or where `cargo install` puts it.
fn duvet() -> PathBuf {
    let installed = std::env::var_os("HOME")
        .map(|h| PathBuf::from(h).join(".cargo/bin/duvet"))
        .filter(|p| p.is_file());
    installed.unwrap_or_else(|| PathBuf::from("duvet"))
}

/// A fresh, empty folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "fieldguide-evidence-test-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A project of two requirements, both implemented, only X-ONE tested.
fn fixture(name: &str) -> PathBuf {
    let dir = scratch(name);
    write(
        &dir.join(".duvet/config.toml"),
        "'$schema' = \"https://awslabs.github.io/duvet/config/v0.4.json\"\n\n\
         [[source]]\npattern = \"src/**/*.rs\"\n\n[[source]]\npattern = \"tests/**/*.rs\"\n\
         type = \"test\"\n\n[[specification]]\nsource = \"spec/a.md\"\n",
    );
    write(
        &dir.join("spec/a.md"),
        "# Fixture\n\n## Section\n\n### X-ONE: the first\n\nThe first value MUST be one.\n\n\
         - Source: eq. 1.\n- Reading: one is\n  exactly one.\n\n### X-TWO: the second\n\n\
         The second value MUST be two.\n",
    );
    // The comment marker is built here so that duvet, reading this file
    // for the project's own citations, does not take the fixture's for them.
    let c = "//";
    write(
        &dir.join("src/lib.rs"),
        &format!(
            "{c}= spec/a.md#x-one-the-first\n{c}# The first value MUST be one.\n\
             pub fn one() {{}}\n\n{c}= spec/a.md#x-two-the-second\n\
             {c}# The second value MUST be two.\npub fn two() {{}}\n"
        ),
    );
    write(
        &dir.join("tests/t.rs"),
        &format!(
            "{c}= spec/a.md#x-one-the-first\n{c}= type=test\n\
             {c}# The first value MUST be one.\n#[test]\nfn one() {{}}\n"
        ),
    );
    dir
}

#[test]
fn every_requirement_of_spec_appears_with_its_checks() {
    let root = root();
    // The `### ID: title` headings, counted here independently of the parser.
    let mut headings = 0;
    for entry in std::fs::read_dir(root.join("spec")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|x| x == "md") {
            let text = std::fs::read_to_string(&path).unwrap();
            headings += text
                .lines()
                .filter(|l| l.starts_with("### ") && l.contains(": "))
                .count();
        }
    }
    let matrix = requirements::gather(&root, &duvet());
    assert_eq!(matrix.requirements.len(), headings);
    assert!(headings > 100, "{headings}");
    let counted: usize = matrix.files.iter().map(|f| f.requirements).sum();
    assert_eq!(counted, headings);
    assert_eq!(matrix.status, Status::Pass, "{:?}", matrix.problems);
    for r in &matrix.requirements {
        assert!(!r.implementations.is_empty(), "{}", r.id);
        assert!(
            !(r.tests.is_empty() && r.proofs.is_empty() && r.scenarios.is_empty()),
            "{}",
            r.id
        );
    }
    // A proof's and a scenario's citations are sorted by where they are.
    let s1 = matrix
        .requirements
        .iter()
        .find(|r| r.id == "SW-S1")
        .unwrap();
    assert!(s1.proofs.iter().all(|c| c.at.starts_with("proofs/tests/")));
    assert!(!s1.proofs.is_empty());
    let model = matrix
        .requirements
        .iter()
        .find(|r| r.id == "PT-MODEL")
        .unwrap();
    assert!(model.source.as_deref().unwrap().starts_with("eq. 1"));
    assert!(model.reading.as_deref().unwrap().contains("world-frame"));
}

#[test]
fn a_requirement_without_a_test_is_red() {
    let dir = fixture("untested");
    let matrix = requirements::gather(&dir, &duvet());
    assert_eq!(matrix.requirements.len(), 2);
    assert_eq!(matrix.status, Status::Fail);
    let one = &matrix.requirements[0];
    let two = &matrix.requirements[1];
    assert_eq!(
        (one.id.as_str(), one.status),
        ("X-ONE", Status::Pass),
        "{matrix:?}"
    );
    assert_eq!(one.implementations[0].item, "pub fn one() {}");
    assert_eq!(one.tests[0].at, "tests/t.rs:5");
    assert_eq!(one.source.as_deref(), Some("eq. 1."));
    assert_eq!(one.reading.as_deref(), Some("one is exactly one."));
    assert_eq!((two.id.as_str(), two.status), ("X-TWO", Status::Fail));
    assert!(two.tests.is_empty());
    assert!(matrix
        .problems
        .iter()
        .any(|p| p.contains("X-TWO") && p.contains("no test citation")));
    // duvet's own check failed too, and says so.
    assert!(matrix.problems.iter().any(|p| p.starts_with("duvet:")));
    assert_eq!(
        (matrix.files[0].requirements, matrix.files[0].complete),
        (2, 1)
    );

    // The command exits non-zero, its report marked incomplete.
    let out = scratch("untested-out");
    let status = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["--out", out.to_str().unwrap(), "evidence", "--root"])
        .arg(&dir)
        .arg("--duvet")
        .arg(duvet())
        .args(["--no-closed-loop", "--no-benchmarks"])
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(1));
    let page = std::fs::read_to_string(out.join("evidence/index.html")).unwrap();
    assert!(page.contains("INCOMPLETE"));
    assert!(page.contains("<tr class=\"fail\"><td><b>X-TWO</b>"));
}

#[test]
fn a_missing_duvet_is_red_and_exits_non_zero() {
    let dir = fixture("no-duvet");
    let matrix = requirements::gather(&dir, Path::new("/nonexistent/duvet"));
    assert_eq!(matrix.status, Status::Fail);
    assert!(
        matrix.problems[0].contains("could not run"),
        "{:?}",
        matrix.problems
    );
    // On a PATH without duvet (nor anything else), the command fails.
    let out = scratch("no-duvet-out");
    let status = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .env("PATH", "")
        .args(["--out", out.to_str().unwrap(), "evidence", "--root"])
        .arg(&dir)
        .args(["--no-closed-loop", "--no-benchmarks"])
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(1));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("evidence/evidence.json")).unwrap())
            .unwrap();
    assert_eq!(json["status"], "fail");
    assert_eq!(json["requirements"]["status"], "fail");
}

/// A record as `fieldguide_proofs::evidence` writes it.
fn record(name: &str, status: &str, commit: &str) -> String {
    serde_json::json!({
        "name": name, "kind": "bolero harness", "status": status, "commit": commit,
        "dirty": false, "duration_s": 1.5, "properties": ["SW-S1"], "states": null,
        "transitions": null, "depth": 12, "sequences": 16_777_216, "mutant": null,
    })
    .to_string()
}

#[test]
fn proof_records_missing_failed_or_from_another_commit_are_red() {
    let dir = scratch("proofs");
    write(
        &dir.join("proofs/tests/p.rs"),
        "let run = evidence::start(\n    \"fresh\", Kind::Harness);\n\
         evidence::start(\"stale\", Kind::Model);\nevidence::start(\"failed\", Kind::Mutant);\n\
         evidence::start(\"missing\", Kind::Harness);\n",
    );
    let records = dir.join("records");
    write(&records.join("a.json"), &record("fresh", "passed", "abc"));
    write(&records.join("b.json"), &record("stale", "passed", "old"));
    write(&records.join("c.json"), &record("failed", "running", "abc"));
    let section = proofs::gather(&dir, &records, &Some("abc".to_owned()));
    assert_eq!(section.status, Status::Fail);
    let by_name = |n: &str| section.proofs.iter().find(|p| p.name == n).unwrap();
    assert_eq!(by_name("fresh").status, Status::Pass);
    assert_eq!(
        by_name("fresh").record.as_ref().unwrap().sequences,
        Some(16_777_216)
    );
    assert!(by_name("stale")
        .problem
        .as_ref()
        .unwrap()
        .starts_with("stale"));
    assert!(by_name("failed")
        .problem
        .as_ref()
        .unwrap()
        .contains("failed or was cut off"));
    assert!(by_name("missing")
        .problem
        .as_ref()
        .unwrap()
        .starts_with("no record"));
    assert_eq!(section.problems.len(), 3);

    // All fresh: green.
    write(&records.join("b.json"), &record("stale", "passed", "abc"));
    write(&records.join("c.json"), &record("failed", "passed", "abc"));
    write(&records.join("d.json"), &record("missing", "passed", "abc"));
    let section = proofs::gather(&dir, &records, &Some("abc".to_owned()));
    assert_eq!(section.status, Status::Pass, "{:?}", section.problems);
}

#[test]
fn the_proofs_of_the_project_are_found_by_name() {
    let names: Vec<String> = std::fs::read_dir(root().join("proofs/tests"))
        .unwrap()
        .flat_map(|e| proofs::declared(&std::fs::read_to_string(e.unwrap().path()).unwrap()))
        .collect();
    // Models, harnesses and mutants of the switching machine and the speed profile.
    for name in [
        "edge + furrow, stop 0.2 s",
        "edge following, every verdict sequence",
        "speed profile, every move sequence",
        "mutant NeverStop, stateright",
    ] {
        assert!(names.iter().any(|n| n == name), "{name} in {names:?}");
    }
}

#[test]
fn no_benchmark_results_are_red_unless_skipped() {
    let dir = scratch("criterion");
    let section = benchmarks::gather(&dir);
    assert_eq!(section.status, Status::Fail);
    assert!(section.problems[0].contains("no benchmark results yet"));
    assert_eq!(benchmarks::Benchmarks::skipped().status, Status::Skipped);

    let bench = dir.join("group/case");
    write(
        &bench.join("new/estimates.json"),
        "{\"median\":{\"point_estimate\":1234.5,\"confidence_interval\":\
         {\"lower_bound\":1200.0,\"upper_bound\":1300.0,\"confidence_level\":0.95}}}",
    );
    write(
        &bench.join("new/benchmark.json"),
        "{\"full_id\":\"group/case\"}",
    );
    // Criterion's previous run and its report are not results.
    write(&bench.join("base/estimates.json"), "{}");
    write(&dir.join("report/index.html"), "");
    let section = benchmarks::gather(&dir);
    assert_eq!(section.status, Status::Pass, "{:?}", section.problems);
    assert_eq!(section.benchmarks.len(), 1);
    let b = &section.benchmarks[0];
    assert_eq!(b.id, "group/case");
    assert!((b.median_ns - 1234.5).abs() < 1e-9);
    assert_eq!(b.interval_ns, (1200.0, 1300.0));
}

#[test]
fn the_page_has_no_script_and_names_each_section() {
    let dir = fixture("page");
    let mut options = Options::new(&dir, &scratch("page-out"));
    options.duvet = duvet();
    options.sweep_seeds = None;
    options.skip_benchmarks = true;
    let report = Report::gather(&options).unwrap();
    assert_eq!(report.closed_loop.status, Status::Skipped);
    assert_eq!(report.status, Status::Fail);
    let page = html::render(&report);
    assert!(!page.to_ascii_lowercase().contains("<script"));
    for id in [
        "provenance",
        "requirements",
        "proofs",
        "closed-loop",
        "benchmarks",
    ] {
        assert!(page.contains(&format!("id=\"{id}\"")), "{id}");
    }
    assert!(page.starts_with("<!DOCTYPE html>") && page.ends_with("</html>\n"));
    assert_eq!(html::escape("<a & \"b\">"), "&lt;a &amp; &quot;b&quot;&gt;");
}

#[test]
fn dates_are_civil_utc() {
    let at = |s: u64| provenance::utc(SystemTime::UNIX_EPOCH + Duration::from_secs(s));
    assert_eq!(at(0), "1970-01-01 00:00:00 UTC");
    // 2000-02-29 (a leap day of a century leap year), 12:34:56.
    assert_eq!(at(951_782_400 + 45_296), "2000-02-29 12:34:56 UTC");
    assert_eq!(at(1_798_761_599), "2026-12-31 23:59:59 UTC");
}

#[test]
fn the_runs_expected_to_break_their_bounds_are_built_in() {
    for (name, why) in closed_loop::EXPECTED_TO_BREAK {
        assert!(
            fieldguide_sim::scenario::BUILTIN
                .iter()
                .any(|(n, _)| *n == name),
            "{name}"
        );
        assert!(!why.is_empty());
    }
}
