//! A bad scenario stops with an error naming the field: missing, unknown,
//! mistyped and out-of-range values, in the library and through the program.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

use std::path::PathBuf;
use std::process::Command;

use fieldguide_sim::rng::SimRng;
use fieldguide_sim::scenario::{Source, BUILTIN};
use fieldguide_sim::ScenarioError;

fn builtin_text() -> String {
    BUILTIN[0].1.to_owned()
}

/// The error of the built-in text changed by `edit`.
fn error_of(edit: impl Fn(String) -> String) -> ScenarioError {
    let source = Source {
        origin: "edited.toml".to_owned(),
        text: edit(builtin_text()),
        base_dir: None,
    };
    source
        .setup(&mut SimRng::from_seed(1))
        .expect_err("the edited scenario must be refused")
}

fn assert_field(e: &ScenarioError, field: &str, reason_part: &str) {
    assert_eq!(e.field(), Some(field), "{e}");
    let message = e.to_string();
    assert!(message.contains("edited.toml"), "{message}");
    assert!(message.contains(field), "{message}");
    assert!(message.contains(reason_part), "{message}");
}

#[test]
fn the_unedited_builtin_is_accepted() {
    let source = Source {
        origin: "edited.toml".into(),
        text: builtin_text(),
        base_dir: None,
    };
    assert!(source.setup(&mut SimRng::from_seed(1)).is_ok());
}

#[test]
fn missing_fields_are_named() {
    let e = error_of(|t| t.replace("wheelbase_m = 2.0\n", ""));
    assert_field(&e, "vehicle.wheelbase_m", "missing field");
    let e = error_of(|t| t.replace("seed = 2022\n", ""));
    assert_field(&e, "seed", "missing field");
    let e = error_of(|t| t.replace("horizon_s = 1.0\n", ""));
    assert_field(&e, "control.horizon_s", "missing field");
}

#[test]
fn optional_fields_take_their_documented_defaults() {
    let source = Source {
        origin: "edited.toml".into(),
        text: builtin_text()
            .replace("period_s = 0.02\n", "")
            .replace("band_m = 0.05\n", ""),
        base_dir: None,
    };
    let setup = source.setup(&mut SimRng::from_seed(1)).unwrap();
    assert!((setup.control.period_s - 0.02).abs() < 1e-15);
    assert!((setup.metrics.band_m - 0.05).abs() < 1e-15);
}

#[test]
fn mistyped_fields_are_named() {
    let e = error_of(|t| t.replace("wheelbase_m = 2.0", "wheelbase_m = \"two\""));
    assert_field(&e, "vehicle.wheelbase_m", "invalid type");
    let e = error_of(|t| t.replace("sideslip_compensation = true", "sideslip_compensation = 1"));
    assert_field(&e, "control.sideslip_compensation", "invalid type");
    let e = error_of(|t| t.replace("inversion = \"exact\"", "inversion = \"exactly\""));
    assert_field(&e, "control.inversion", "unknown variant");
    let e = error_of(|t| {
        t.replace(
            "{ straight_m = 15.0 },\n  { arc_radius_m = 10.0",
            "{ straight_m = 15.0 },\n  { arc_radius_m = \"ten\"",
        )
    });
    assert_field(&e, "path.segments[1].arc_radius_m", "invalid type");
}

#[test]
fn unknown_fields_are_named() {
    let e = error_of(|t| t.replace("track_m = 1.5", "track_m = 1.5\ntrack_width_m = 1.5"));
    assert_field(&e, "vehicle.track_width_m", "unknown field");
}

#[test]
fn out_of_range_fields_are_named() {
    let cases: [(&str, &str, &str); 9] = [
        (
            "wheelbase_m = 2.0",
            "wheelbase_m = -2.0",
            "vehicle.wheelbase_m",
        ),
        ("speed_m_s = 0.8", "speed_m_s = 0.0", "control.speed_m_s"),
        (
            "max_steering_deg = 30.0",
            "max_steering_deg = 95.0",
            "vehicle.max_steering_deg",
        ),
        (
            "gnss_position_m = 0.015",
            "gnss_position_m = -0.015",
            "noise.gnss_position_m",
        ),
        (
            "lateral_gain = 0.7",
            "lateral_gain = -0.7",
            "control.lateral_gain",
        ),
        (
            "heading_gain = 2.8",
            "heading_gain = 1.0",
            "control.heading_gain",
        ),
        ("substeps = 10", "substeps = 0", "run.substeps"),
        (
            "rear_sideslip_deg = -3.0",
            "rear_sideslip_deg = -60.0",
            "terrain.patches[0].rear_sideslip_deg",
        ),
        (
            "{ straight_m = 15.0 },\n  { arc_radius_m = 10.0",
            "{ straight_m = 15.0 },\n  { arc_radius_m = 0.0",
            "path.segments[1].arc_radius_m",
        ),
    ];
    for (from, to, field) in cases {
        let text = builtin_text();
        assert!(
            text.contains(from),
            "the built-in no longer contains `{from}`"
        );
        let e = error_of(|t| t.replacen(from, to, 1));
        assert_eq!(e.field(), Some(field), "{from} -> {to}: {e}");
        assert!(e.to_string().contains(field));
    }
    let e = error_of(|t| {
        t.replace(
            "polygon = [[15.0, -3.0], [28.0, -3.0], [28.0, 10.0], [15.0, 10.0]]",
            "polygon = [[15.0, -3.0], [28.0, -3.0]]",
        )
    });
    assert_field(&e, "terrain.patches[0].polygon", "at least 3");
    let e = error_of(|t| {
        t.replace(
            "{ straight_m = 15.0 },\n  { arc_radius_m = 10.0, arc_angle_deg = 90.0 }",
            "{ straight_m = 15.0 },\n  { arc_radius_m = 10.0 }",
        )
    });
    assert_field(&e, "path.segments[1]", "arc_angle_deg");
}

#[test]
fn syntax_errors_say_where() {
    let e = error_of(|t| t.replace("seed = 2022", "seed = = 2022"));
    assert!(matches!(e, ScenarioError::Syntax { .. }), "{e}");
    assert!(e.to_string().contains("line"), "{e}");
}

/// A fresh folder under the system's temporary directory.
fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("fieldguide-sim-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_program_names_the_file_and_the_field_and_exits_non_zero() {
    let dir = scratch("bad");
    let file = dir.join("bad.toml");
    std::fs::write(
        &file,
        builtin_text().replace("wheelbase_m = 2.0", "wheelbase_m = 0.0"),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["run", file.to_str().unwrap(), "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.toml"), "{stderr}");
    assert!(stderr.contains("vehicle.wheelbase_m"), "{stderr}");
    assert!(
        !dir.join("out").exists(),
        "nothing written for a refused scenario"
    );

    let missing = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["run", "no-such-scenario"])
        .output()
        .unwrap();
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("path-tracking"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_program_lists_and_runs_a_scenario_file_with_a_csv_path() {
    let list = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .arg("list")
        .output()
        .unwrap();
    assert!(list.status.success());
    let listed = String::from_utf8_lossy(&list.stdout);
    for (name, _) in BUILTIN {
        assert!(listed.contains(name), "{listed}");
    }

    // A short straight path from a CSV file beside the scenario.
    let dir = scratch("csv");
    let csv: String = std::iter::once("x_m,y_m\n".to_owned())
        .chain((0..=200).map(|i| format!("{},{}\n", f64::from(i) * 0.1, 0.0)))
        .collect();
    std::fs::write(dir.join("line.csv"), csv).unwrap();
    let text = builtin_text()
        .replace("name = \"path-tracking\"", "name = \"csv-line\"")
        .replace("start = { x_m = 0.0, y_m = 0.0, heading_deg = 0.0 }\n", "")
        .replace(
            &builtin_text()[builtin_text().find("segments = [").unwrap()
                ..builtin_text().find("sample_step_m").unwrap()],
            "csv = \"line.csv\"\n",
        )
        .replace("lateral_m = -0.8", "lateral_m = 0.3");
    std::fs::write(dir.join("csv-line.toml"), text).unwrap();
    let out_dir = dir.join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args([
            "run",
            dir.join("csv-line.toml").to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for f in fieldguide_sim::output::FILES {
        assert!(out_dir.join("csv-line").join(f).is_file(), "{f}");
    }
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out_dir.join("csv-line/summary.json")).unwrap(),
    )
    .unwrap();
    for key in [
        "scenario",
        "seed",
        "distance_m",
        "duration_s",
        "lateral_error_m",
        "converged_after_m",
        "mode_distance_m",
        "mode_switches",
        "plants_crushed",
        "success",
    ] {
        assert!(summary.get(key).is_some(), "summary.json lacks {key}");
    }
    for key in ["mean_abs", "rms", "max_abs", "p95_abs"] {
        assert!(summary["lateral_error_m"][key].is_number(), "{key}");
    }
    assert_eq!(summary["scenario"], "csv-line");
    assert!(
        summary["mode_distance_m"]["path_tracking"]
            .as_f64()
            .unwrap()
            > 15.0
    );
    let trace = std::fs::read_to_string(out_dir.join("csv-line/trace.csv")).unwrap();
    let header = trace.lines().next().unwrap();
    assert_eq!(header, fieldguide_sim::output::csv::HEADER);
    let columns = header.split(',').count();
    assert!(trace
        .lines()
        .skip(1)
        .all(|l| l.split(',').count() == columns));
    let _ = std::fs::remove_dir_all(&dir);
}
