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
    edited_error_of(builtin_text(), edit)
}

/// The error of `text` changed by `edit`, as the file `edited.toml`.
fn edited_error_of(text: String, edit: impl Fn(String) -> String) -> ScenarioError {
    let source = Source {
        origin: "edited.toml".to_owned(),
        text: edit(text),
        base_dir: None,
    };
    source
        .setup(&mut SimRng::from_seed(1))
        .expect_err("the edited scenario must be refused")
}

/// The byte span of the section of `text` whose header is `header`: from the
/// header to the next header (or the end).
fn section_span(text: &str, header: &str) -> (usize, usize) {
    let start = text.find(header).unwrap();
    let end = text[start + 1..]
        .find("\n[")
        .map_or(text.len(), |i| start + 1 + i);
    (start, end)
}

/// `text` without the section whose header is `header`.
fn without_section(text: &str, header: &str) -> String {
    let (start, end) = section_span(text, header);
    format!("{}{}", &text[..start], &text[end..])
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
            .replace("period_s = 0.01\n", "")
            .replace("band_m = 0.05\n", ""),
        base_dir: None,
    };
    let setup = source.setup(&mut SimRng::from_seed(1)).unwrap();
    assert!((setup.control.period_s - 0.01).abs() < 1e-15);
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

/// An empty key is named as TOML spells it, `""`: the field an error names
/// is never blank (found by the loader's fuzz target, `tests/fuzz_loader.rs`).
#[test]
fn an_empty_key_is_named_as_toml_spells_it() {
    let e = error_of(|t| format!("\"\" = \"\"\n{t}"));
    assert_field(&e, "\"\"", "unknown field");
    let e = error_of(|t| t.replace("track_m = 1.5", "track_m = 1.5\n\"\" = 1"));
    assert_field(&e, "vehicle.\"\"", "unknown field");
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

/// What a new user mistypes: a near-miss name gets the closest built-in, a
/// folder or a missing path the operating system's reason, and a copied file
/// that keeps its built-in's name a warning that it replaces that output.
#[test]
fn the_program_says_what_it_could_not_find_and_what_it_replaces() {
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_fieldguide"))
            .args(args)
            .output()
            .unwrap()
    };
    let typo = run(&["run", "exp2-acr"]);
    assert!(!typo.status.success());
    let stderr = String::from_utf8_lossy(&typo.stderr);
    assert!(stderr.contains("did you mean `exp2-acre`?"), "{stderr}");
    let far = run(&["run", "orchard"]);
    assert!(!String::from_utf8_lossy(&far.stderr).contains("did you mean"));
    let dir = scratch("resolve");
    let folder = run(&["run", dir.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&folder.stderr);
    assert!(!folder.status.success());
    assert!(
        stderr.contains("cannot read") && stderr.contains("os error"),
        "{stderr}"
    );
    let missing = dir.join("nowhere").join("x.toml");
    let stderr =
        String::from_utf8_lossy(&run(&["run", missing.to_str().unwrap()]).stderr).into_owned();
    assert!(
        stderr.contains("cannot read") && stderr.contains("os error"),
        "{stderr}"
    );
    // A copy of the first built-in under its own name: run, with a warning.
    let copy = dir.join("copy.toml");
    std::fs::write(&copy, builtin_text()).unwrap();
    let out = dir.join("out");
    let copied = run(&[
        "run",
        copy.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(copied.status.success());
    let stderr = String::from_utf8_lossy(&copied.stderr);
    assert!(
        stderr.contains("keeps the built-in name `path-tracking`"),
        "{stderr}"
    );
}

/// A failed run says which bound it broke, in the table and in
/// `summary.json`.
#[test]
fn a_failed_run_names_the_bound_it_broke() {
    let dir = scratch("failure");
    let run = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args([
            "run",
            "path-tracking-no-compensation",
            "--out",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(run.status.success());
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.contains("path-tracking-no-compensation: converged after")
            && stdout.contains("metrics.converge_within_m"),
        "{stdout}"
    );
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("path-tracking-no-compensation/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(summary["success"], false);
    let failures = summary["failures"].as_array().unwrap();
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0]
        .as_str()
        .unwrap()
        .contains("metrics.converge_within_m"));
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

/// The error of the built-in `furrow-pursuing` text changed by `edit`.
fn furrow_error_of(edit: impl Fn(String) -> String) -> ScenarioError {
    edited_error_of(Source::builtin("furrow-pursuing").unwrap().text, edit)
}

#[test]
fn world_lidar_and_furrow_fields_are_named() {
    let text = Source::builtin("furrow-pursuing").unwrap().text;
    // (text in the built-in, replacement, field named, part of the reason)
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "length_m = 30.0",
            "length_m = 0.0",
            "world.plots[0].length_m",
            "between",
        ),
        (
            "crop = \"beans\"",
            "crop = \"wheat\"",
            "world.plots[1].crop",
            "unknown variant",
        ),
        (
            "bare_m = [[14.0, 15.5]]",
            "bare_m = [[15.5, 14.0]]",
            "world.plots[1].bare_m[0]",
            "from_m < to_m",
        ),
        (
            "bare_m = [[14.0, 15.5]]",
            "bare_m = [[14.0, 45.5]]",
            "world.plots[1].bare_m[0][1]",
            "within",
        ),
        (
            "missing_fraction = 0.05\nbare_m",
            "missing_fraction = 1.5\nbare_m",
            "world.plots[1].missing_fraction",
            "within",
        ),
        (
            "bend_wavelength_m = 40.0",
            "bend_wavelength_m = 0.0",
            "world.plots[0].bend_wavelength_m",
            "> 0",
        ),
        (
            "density_per_m2 = 3.0",
            "density_per_m2 = -3.0",
            "world.grass[0].density_per_m2",
            "within",
        ),
        (
            "radius_m = 0.02",
            "radius_m = 0.0",
            "world.grass[0].radius_m",
            "between",
        ),
        (
            "lead_in_m = 6.0",
            "lead_in_m = -6.0",
            "path.along_plots.lead_in_m",
            "within",
        ),
        (
            "pitch_deg = 21.8",
            "pitch_deg = 0.0",
            "lidar.pitch_deg",
            "between",
        ),
        ("rays = 360", "rays = 1", "lidar.rays", "within"),
        (
            "range_max_m = 20.0",
            "range_max_m = 0.05",
            "lidar.range_max_m",
            "above",
        ),
        (
            "rate_hz = 10.0",
            "rate_hz = 15.0",
            "lidar.rate_hz",
            "whole number",
        ),
        (
            "rate_hz = 10.0",
            "rate_hz = \"fast\"",
            "lidar.rate_hz",
            "invalid type",
        ),
        (
            "speed_m_s = 0.7",
            "speed_m_s = 0.0",
            "furrow.speed_m_s",
            "between",
        ),
        (
            "heading_gain = 3.2",
            "heading_gain = 1.0",
            "furrow.heading_gain",
            "min_gain_ratio",
        ),
        (
            "template_width_rays = 15",
            "template_width_rays = 14",
            "furrow.template_width_rays",
            "odd",
        ),
        (
            "template_height_m = 0.3",
            "template_height_m = 0.0",
            "furrow.template_height_m",
            "between",
        ),
        (
            "height_floor_m = 0.15",
            "height_floor_m = 0.3",
            "furrow.height_floor_m",
            "below",
        ),
        (
            "peak_threshold = 0.5",
            "peak_threshold = 1.0",
            "furrow.peak_threshold",
            "between",
        ),
        ("rows = 2", "rows = 3", "furrow.rows", "1 or 2"),
        ("rows = 2", "rows = 1", "furrow.rows", "one row"),
        (
            "max_row_spacing_m = 0.9",
            "max_row_spacing_m = 0.6",
            "furrow.max_row_spacing_m",
            "above",
        ),
        (
            "averaged_scans = 25",
            "averaged_scans = 0",
            "furrow.averaged_scans",
            "within",
        ),
        (
            "averaged_scans = 25",
            "averaged_scans = 65",
            "furrow.averaged_scans",
            "within",
        ),
        (
            "min_points = 5",
            "min_points = 1",
            "furrow.min_points",
            "within",
        ),
        (
            "enter_correlation = 0.4",
            "enter_correlation = 0.1",
            "furrow.enter_correlation",
            "above",
        ),
        // 4000 rays over 90°: the ±20° window holds 1778, above the detector's 1024.
        (
            "rays = 360",
            "rays = 4000",
            "furrow.window_half_angle_deg",
            "1778 rays",
        ),
        (
            "in_plot_max_abs_m = 0.1",
            "in_plot_max_abs_m = 0.0",
            "metrics.in_plot_max_abs_m",
            "> 0",
        ),
        (
            "keep_distance_m = 6.0",
            "keep_distance_m = 6.0\nkeep_m = 6.0",
            "furrow.keep_m",
            "unknown field",
        ),
        (
            "min_row_spacing_m = 0.66\n",
            "",
            "furrow.min_row_spacing_m",
            "required",
        ),
        (
            "exit_correlation = 0.2\n",
            "",
            "furrow.exit_correlation",
            "missing field",
        ),
    ];
    for (from, to, field, reason) in cases {
        assert!(
            text.contains(from),
            "the built-in no longer contains `{from}`"
        );
        let e = furrow_error_of(|t| t.replacen(from, to, 1));
        assert_field(&e, field, reason);
    }
}

#[test]
fn furrow_pursuing_needs_its_sensor_and_its_world() {
    let e = furrow_error_of(|t| without_section(&t, "[lidar]"));
    assert_field(&e, "furrow", "[lidar]");
    // Without plots the path along them has nothing to follow.
    let e = furrow_error_of(|t| {
        let start = t.find("[[world.plots]]").unwrap();
        let end = t.find("# Grass in the headlands").unwrap();
        format!("{}{}", &t[..start], &t[end..])
    });
    assert_field(&e, "path.along_plots", "world.plots");
    // Plots that overlap backwards cannot be joined by a recorded path.
    let e = furrow_error_of(|t| t.replace("x_m = 38.0, y_m = 0.25", "x_m = 10.0, y_m = 0.25"));
    assert_field(&e, "world.plots[1].start", "ahead");
    let e = furrow_error_of(|t| {
        t.replace(
            "along_plots = { lead_in_m = 6.0, run_out_m = 6.0 }",
            "along_plots = { lead_in_m = 6.0, run_out_m = 6.0 }\nsegments = [{ straight_m = 10.0 }]",
        )
    });
    assert_field(&e, "path", "exactly one");
}

#[test]
fn the_program_writes_the_furrow_figures_and_summary() {
    let dir = scratch("furrow");
    let run = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["run", "furrow-pursuing", "--out", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = dir.join("furrow-pursuing");
    for f in fieldguide_sim::output::FILES
        .iter()
        .chain([&fieldguide_sim::output::ROWS_FILE])
    {
        assert!(out.join(f).is_file(), "{f}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(
        summary["in_plot_lateral_error_m"]["max_abs"]
            .as_f64()
            .unwrap()
            < 0.1
    );
    assert_eq!(summary["plots"][0]["name"], "maize");
    assert_eq!(summary["plots"][1]["name"], "beans");
    assert!(
        summary["mode_distance_m"]["furrow_pursuing"]
            .as_f64()
            .unwrap()
            > 40.0
    );
    assert!(summary["verdicts"]["enter"].as_u64().unwrap() > 100);
    assert_eq!(summary["plants_crushed"], 0);
    assert!(summary["crop_plants"].as_u64().unwrap() > 500);
    assert_eq!(summary["success"], true);
    let trace = std::fs::read_to_string(out.join("trace.csv")).unwrap();
    let columns = trace.lines().next().unwrap().split(',').count();
    assert!(trace.lines().all(|l| l.split(',').count() == columns));
    assert!(trace.contains(",furrow_pursuing,enter,1,0.00,"));
    assert!(trace.contains(",maize,") && trace.contains(",beans,"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The error of the built-in `hedge-following` text changed by `edit`.
fn hedge_error_of(edit: impl Fn(String) -> String) -> ScenarioError {
    edited_error_of(Source::builtin("hedge-following").unwrap().text, edit)
}

#[test]
fn hedge_horizontal_lidar_and_edge_fields_are_named() {
    let text = Source::builtin("hedge-following").unwrap().text;
    // (text in the built-in, replacement, field named, part of the reason)
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "length_m = 40.0",
            "length_m = 0.0",
            "world.hedges[0].length_m",
            "between",
        ),
        (
            "thickness_m = 1.0",
            "thickness_m = -1.0",
            "world.hedges[0].thickness_m",
            "between",
        ),
        (
            "raggedness_m = 0.05",
            "raggedness_m = 0.5",
            "world.hedges[0].raggedness_m",
            "half of thickness_m",
        ),
        (
            "vertex_spacing_m = 0.2",
            "vertex_spacing_m = 0.0",
            "world.hedges[0].vertex_spacing_m",
            "between",
        ),
        (
            "gaps_m = [[18.0, 20.0]]",
            "gaps_m = [[20.0, 18.0]]",
            "world.hedges[0].gaps_m[0]",
            "from_m < to_m",
        ),
        (
            "gaps_m = [[18.0, 20.0]]",
            "gaps_m = [[18.0, 41.0]]",
            "world.hedges[0].gaps_m[0][1]",
            "within",
        ),
        (
            "name = \"hedge\"",
            "name = \" \"",
            "world.hedges[0].name",
            "empty",
        ),
        (
            "mount_heading_deg = 0.0",
            "mount_heading_deg = 200.0",
            "horizontal_lidar.mount_heading_deg",
            "within",
        ),
        (
            "field_of_view_deg = 360.0",
            "field_of_view_deg = 0.0",
            "horizontal_lidar.field_of_view_deg",
            "(0, 360]",
        ),
        ("rays = 360", "rays = 1", "horizontal_lidar.rays", "within"),
        (
            "rays = 360",
            "rays = 3000",
            "horizontal_lidar.rays",
            "at most 2048",
        ),
        (
            "range_max_m = 30.0",
            "range_max_m = 0.01",
            "horizontal_lidar.range_max_m",
            "above",
        ),
        (
            "rate_hz = 10.0",
            "rate_hz = 15.0",
            "horizontal_lidar.rate_hz",
            "whole number",
        ),
        (
            "speed_m_s = 0.4",
            "speed_m_s = 0.0",
            "edge.speed_m_s",
            "between",
        ),
        (
            "heading_gain = 1.5",
            "heading_gain = 1.0",
            "edge.heading_gain",
            "min_gain_ratio",
        ),
        (
            "side = \"left\"",
            "side = \"up\"",
            "edge.side",
            "unknown variant",
        ),
        (
            "desired_distance_m = 1.4",
            "desired_distance_m = -1.4",
            "edge.desired_distance_m",
            "within",
        ),
        (
            "circle_radius_m = 1.0",
            "circle_radius_m = 0.0",
            "edge.circle_radius_m",
            "between",
        ),
        (
            "max_rotation_deg = 90.0",
            "max_rotation_deg = 360.0",
            "edge.max_rotation_deg",
            "between",
        ),
        (
            "max_chain_length_m = 3.0",
            "max_chain_length_m = 0.0",
            "edge.max_chain_length_m",
            "between",
        ),
        (
            "search_distance_m = 3.0",
            "search_distance_m = 0.0",
            "edge.search_distance_m",
            "between",
        ),
        (
            "min_chain_length_m = 1.5",
            "min_chain_length_m = 3.0",
            "edge.min_chain_length_m",
            "below",
        ),
        (
            "max_width_m = 1.0",
            "max_width_m = 0.0",
            "edge.max_width_m",
            "between",
        ),
        (
            "min_points = 5",
            "min_points = 3",
            "edge.min_points",
            "within",
        ),
        (
            "max_link_m = 1.0",
            "max_link_m = 0.0",
            "edge.max_link_m",
            "between",
        ),
        (
            "max_turn_deg = 45.0",
            "max_turn_deg = 0.0",
            "edge.max_turn_deg",
            "(0, 180]",
        ),
        (
            "max_turn_deg = 45.0",
            "max_turn_deg = 200.0",
            "edge.max_turn_deg",
            "within",
        ),
        (
            "exit_residual_m = 0.5",
            "exit_residual_m = 0.1",
            "edge.exit_residual_m",
            "above",
        ),
        (
            "max_link_m = 1.0",
            "max_link_m = 1.0\nlook_ahead = true\nlook_ahead_end_cap_m = -0.5",
            "edge.look_ahead_end_cap_m",
            "within",
        ),
        (
            "max_link_m = 1.0",
            "max_link_m = 1.0\nlook_ahead = true\nlook_ahead_step_m = 0.0",
            "edge.look_ahead_step_m",
            "between",
        ),
        (
            "max_link_m = 1.0",
            "max_link_m = 1.0\nlook_ahead = true\nlook_ahead_farthest_m = 40.0",
            "edge.look_ahead_farthest_m",
            "within [0.5, 32]",
        ),
        (
            "max_link_m = 1.0",
            "max_link_m = 1.0\nlook_ahead = true\nlook_ahead_min_span_m = 0.0",
            "edge.look_ahead_min_span_m",
            "between",
        ),
        ("max_link_m = 1.0\n", "", "edge.max_link_m", "missing field"),
        (
            "max_link_m = 1.0",
            "max_link_m = 1.0\nmax_gap_m = 1.0",
            "edge.max_gap_m",
            "unknown field",
        ),
        (
            "along_hedge_band_m = 0.05",
            "along_hedge_band_m = 0.0",
            "metrics.along_hedge_band_m",
            "> 0",
        ),
        (
            "along_hedge_max_abs_m = 0.15",
            "along_hedge_max_abs_m = -0.15",
            "metrics.along_hedge_max_abs_m",
            "> 0",
        ),
    ];
    for (from, to, field, reason) in cases {
        assert!(
            text.contains(from),
            "the built-in no longer contains `{from}`"
        );
        let e = hedge_error_of(|t| t.replacen(from, to, 1));
        assert_field(&e, field, reason);
    }
}

#[test]
fn edge_following_needs_its_sensor_and_the_priority_names_each_behaviour_once() {
    let e = hedge_error_of(|t| without_section(&t, "[horizontal_lidar]"));
    assert_field(&e, "edge", "[horizontal_lidar]");
    // The furrow-pursuing scenario's LiDAR and furrow sections added: both
    // behaviours, furrow first unless `switching.priority` says otherwise.
    let furrow = Source::builtin("furrow-pursuing").unwrap().text;
    let (l0, l1) = section_span(&furrow, "[lidar]");
    let (f0, f1) = section_span(&furrow, "[furrow]");
    let both = |priority: &str| {
        let hedge = Source::builtin("hedge-following").unwrap().text;
        assert!(!hedge.contains("\n[switching]\n"));
        format!(
            "{hedge}\n[switching]\n{priority}\n{}\n{}",
            &furrow[l0..l1],
            &furrow[f0..f1]
        )
    };
    let setup = |text: String| {
        Source {
            origin: "edited.toml".to_owned(),
            text,
            base_dir: None,
        }
        .setup(&mut SimRng::from_seed(1))
    };
    use fieldguide_sim::guidance::pipeline::{EDGE, FURROW};
    let default = setup(both("")).unwrap();
    assert_eq!(default.switching.priority, vec![FURROW, EDGE]);
    let edge_first = setup(both(r#"priority = ["edge", "furrow"]"#)).unwrap();
    assert_eq!(edge_first.switching.priority, vec![EDGE, FURROW]);
    for (priority, reason) in [
        (r#"priority = ["edge", "edge"]"#, "named twice"),
        (r#"priority = ["edge"]"#, "every configured behaviour"),
        (
            r#"priority = ["edge", "furrow", "vines"]"#,
            "unknown behaviour `vines`",
        ),
    ] {
        let e = setup(both(priority)).unwrap_err();
        assert_field(&e, "switching.priority", reason);
    }
    // A priority naming a behaviour whose section is missing.
    let e = hedge_error_of(|t| format!("{t}\n[switching]\npriority = [\"furrow\", \"edge\"]\n"));
    assert_field(&e, "switching.priority", "`furrow` is not configured");
}

#[test]
fn the_program_writes_the_hedge_figures_and_summary() {
    let dir = scratch("hedge");
    let run = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["run", "hedge-following", "--out", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = dir.join("hedge-following");
    for f in fieldguide_sim::output::FILES {
        assert!(out.join(f).is_file(), "{f}");
    }
    // No plants: no rows figure.
    assert!(!out.join(fieldguide_sim::output::ROWS_FILE).exists());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let after = &summary["along_hedge_after_convergence_m"];
    assert!(after["mean_abs"].as_f64().unwrap() < 0.05);
    assert!(after["max_abs"].as_f64().unwrap() < 0.15);
    assert!(summary["along_hedge_converged_after_m"].as_f64().unwrap() > 10.0);
    assert_eq!(summary["hedges"][0]["name"], "hedge");
    assert!(
        summary["mode_distance_m"]["edge_following"]
            .as_f64()
            .unwrap()
            > 30.0
    );
    assert!(summary["verdicts"]["enter"].as_u64().unwrap() > 500);
    assert_eq!(summary["success"], true);
    let trace = std::fs::read_to_string(out.join("trace.csv")).unwrap();
    let columns = trace.lines().next().unwrap().split(',').count();
    assert!(trace.lines().all(|l| l.split(',').count() == columns));
    assert!(trace.contains(",edge_following,enter,1,0.00,"));
    assert!(trace.contains(",hedge,"));
    let svg = std::fs::read_to_string(out.join("trajectory.svg")).unwrap();
    assert!(svg.contains("edge following") && svg.contains("true offset line"));
    let svg = std::fs::read_to_string(out.join("lateral_error.svg")).unwrap();
    assert!(svg.contains("beside a hedge: to the true offset line"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gnss_outages_are_checked_and_named() {
    let with = |spans: &'static str| move |t: String| format!("{t}\n[gnss]\noutages_s = {spans}\n");
    let e = error_of(with("[[5.0, 4.0]]"));
    assert_field(&e, "gnss.outages_s[0]", "end after it starts");
    let e = error_of(with("[[-1.0, 4.0]]"));
    assert_field(&e, "gnss.outages_s[0]", "");
    let e = error_of(with("[[1.0, 4.0], [3.0, 6.0]]"));
    assert_field(&e, "gnss.outages_s[1]", "after the previous outage");
    let e = error_of(with("[[1.0, inf]]"));
    assert_field(&e, "gnss.outages_s[0]", "finite");
    // Accepted: the spans as given, and a fix outside them only.
    let source = Source {
        origin: "edited.toml".into(),
        text: with("[[1.0, 2.0], [2.0, 3.5]]")(builtin_text()),
        base_dir: None,
    };
    let outages = source
        .setup(&mut SimRng::from_seed(1))
        .unwrap()
        .gnss_outages;
    assert_eq!(outages.spans(), &[(1.0, 2.0), (2.0, 3.5)]);
    assert!(outages.has_fix(0.99) && !outages.has_fix(1.0) && !outages.has_fix(3.49));
    assert!(outages.has_fix(3.5));
}

#[test]
fn switching_fields_are_checked_and_named() {
    let with = |section: &'static str| move |t: String| format!("{t}\n[switching]\n{section}\n");
    let e = error_of(with("plan_max_heading_deg = 5.0"));
    assert_field(&e, "switching.plan_max_offset_m", "needs its offset");
    let e = error_of(with("furrow_enter_s = -0.5"));
    assert_field(&e, "switching.furrow_enter_s", "");
    let e = error_of(with(
        "plan_max_offset_m = 0.2\nplan_max_heading_deg = 200.0",
    ));
    assert_field(&e, "switching.plan_max_heading_deg", "");
    let e = error_of(with("plan_lookahead_m = 2.0"));
    assert_field(&e, "switching.plan_max_offset_m", "look-ahead");
    let e = error_of(with("plan_max_offset_m = 0.2\nplan_lookahead_m = -1.0"));
    assert_field(&e, "switching.plan_lookahead_m", "");
    let e = error_of(with("plan_dead_reckoning_m = 20.0"));
    assert_field(&e, "switching.plan_max_offset_m", "dead reckoning");
    // The entry heading (GD-PLAN-ENTRY): within [0, plan_max_heading_deg].
    let e = error_of(with("plan_entry_heading_deg = 5.0"));
    assert_field(&e, "switching.plan_max_offset_m", "entry heading");
    for bad in ["-1.0", "20.5", "nan"] {
        let e = error_of(move |t: String| {
            format!("{t}\n[switching]\nplan_max_offset_m = 0.2\nplan_entry_heading_deg = {bad}\n")
        });
        assert_field(&e, "switching.plan_entry_heading_deg", "");
    }
    let e = error_of(with(
        "plan_max_offset_m = 0.2\nplan_max_heading_deg = 10.0\nplan_entry_heading_deg = 12.0",
    ));
    assert_field(&e, "switching.plan_entry_heading_deg", "");
    for bad in ["0.0", "-5.0", "1001.0", "nan"] {
        let e = error_of(move |t: String| {
            format!("{t}\n[switching]\nplan_max_offset_m = 0.2\nplan_dead_reckoning_m = {bad}\n")
        });
        assert_field(&e, "switching.plan_dead_reckoning_m", "");
    }
    // The hand-over (GD-HANDOVER): its slope and averaging need its hold.
    let e = error_of(with("handover_slope = 0.2"));
    assert_field(&e, "switching.handover_hold_m", "hold distance");
    for (text, field) in [
        ("handover_hold_m = -1.0", "switching.handover_hold_m"),
        (
            "handover_hold_m = 5.0\nhandover_slope = 0.0",
            "switching.handover_slope",
        ),
        (
            "handover_hold_m = 5.0\nhandover_slope = 1.5",
            "switching.handover_slope",
        ),
        (
            "handover_hold_m = 5.0\nhandover_averaging_m = 0.0",
            "switching.handover_averaging_m",
        ),
        (
            "handover_hold_m = 5.0\nhandover_line_m = 0.0",
            "switching.handover_line_m",
        ),
        (
            "handover_hold_m = 5.0\nhandover_line_m = -3.0",
            "switching.handover_line_m",
        ),
        (
            "handover_hold_m = 5.0\nhandover_line_m = 1001.0",
            "switching.handover_line_m",
        ),
        ("handover_line_m = 3.0", "switching.handover_hold_m"),
    ] {
        let e = error_of(move |t: String| format!("{t}\n[switching]\n{text}\n"));
        assert_field(&e, field, "");
    }
    // Defaults: Tables 1-2 and no plan check.
    let source = Source {
        origin: "edited.toml".into(),
        text: builtin_text(),
        base_dir: None,
    };
    let s = source.setup(&mut SimRng::from_seed(1)).unwrap().switching;
    assert!((s.edge_enter_s - 0.4).abs() < 1e-15 && (s.edge_exit_s - 0.26).abs() < 1e-15);
    assert!((s.furrow_enter_s - 0.5).abs() < 1e-15 && (s.furrow_exit_s - 0.3).abs() < 1e-15);
    assert!(s.plan.is_none());
}

#[test]
fn a_segment_along_a_missing_plot_is_named() {
    let e = error_of(|t| {
        let start = t.find("segments = [").unwrap();
        let end = start + t[start..].find("\n]").unwrap() + 2;
        format!(
            "{}segments = [{{ along_plot = 0 }}]{}",
            &t[..start],
            &t[end..]
        )
    });
    assert_field(&e, "path.segments[0].along_plot", "no plot 0");
}

#[test]
fn lidars_without_their_behaviour_and_bad_ground_are_named() {
    // A LiDAR whose behaviour is missing: its scans would go nowhere.
    let furrow = Source::builtin("furrow-pursuing").unwrap().text;
    let e = edited_error_of(furrow.clone(), |t| without_section(&t, "[furrow]"));
    assert_field(&e, "lidar", "needs a `[furrow]` section");
    let e = hedge_error_of(|t| without_section(&t, "[edge]"));
    assert_field(&e, "horizontal_lidar", "needs an `[edge]` section");
    // The ground's shape and the obstacles' height.
    let terrain = |extra: &'static str| {
        move |t: String| t.replacen("[terrain]\n", &format!("[terrain]\n{extra}\n"), 1)
    };
    for (extra, field, reason) in [
        ("slope_x_percent = 150.0", "terrain.slope_x_percent", ""),
        (
            "undulation_amplitude_m = 0.1",
            "terrain.undulation_wavelength_m",
            "needed",
        ),
        (
            "undulation_wavelength_m = 5.0",
            "terrain.undulation_wavelength_m",
            "amplitude",
        ),
        (
            "undulation_amplitude_m = 0.1\nundulation_wavelength_m = 0.1",
            "terrain.undulation_wavelength_m",
            "",
        ),
    ] {
        let e = edited_error_of(furrow.clone(), terrain(extra));
        assert_field(&e, field, reason);
    }
    // A sensor mounted at a non-finite pose.
    let e = hedge_error_of(|t| t.replacen("mount_x_m = 1.2", "mount_x_m = nan", 1));
    assert_field(&e, "horizontal_lidar.mount_x_m", "");
    let e = edited_error_of(furrow.clone(), |t| {
        t.replacen("pitch_deg = 21.8", "pitch_deg = inf", 1)
    });
    assert_field(&e, "lidar.pitch_deg", "");
    let e = hedge_error_of(|t| t.replacen("[world]\n", "[world]\nobstacle_height_m = -1.0\n", 1));
    assert_field(&e, "world.obstacle_height_m", "");
    let e = hedge_error_of(|t| {
        t.replacen(
            "[horizontal_lidar]\n",
            "[horizontal_lidar]\nmount_height_m = 99.0\n",
            1,
        )
    });
    assert_field(&e, "horizontal_lidar.mount_height_m", "");
}

/// Files the loader would once accept but the run could not hold (memory:
/// vertices, samples, trace rows) or would refuse only at its first tick
/// are refused at load, naming the field and the limit.
#[test]
fn counts_the_file_implies_are_bounded_and_delays_named_at_load() {
    let hedge = |from: &'static str, to: &'static str| {
        move |t: String| {
            assert!(t.contains(from), "{from}");
            t.replacen(from, to, 1)
        }
    };
    let cases: [(&str, &str, &str, &str, &str); 6] = [
        (
            "hedge-following",
            "vertex_spacing_m = 0.2",
            "vertex_spacing_m = 1e-9",
            "world.hedges[0].vertex_spacing_m",
            "vertices per face",
        ),
        (
            "furrow-pursuing",
            "sample_step_m = 0.1",
            "sample_step_m = 1e-9",
            "path.sample_step_m",
            "waypoints",
        ),
        (
            "hedge-following",
            "duration_s = 250.0",
            "duration_s = 999999.0",
            "run.duration_s",
            "control ticks",
        ),
        (
            "hedge-following",
            "period_s = 0.01",
            "period_s = 1e-9",
            "control.period_s",
            "",
        ),
        (
            "hedge-following",
            "recording_noise_m = 0.005",
            "recording_noise_m = 1e308",
            "path.recording_noise_m",
            "",
        ),
        (
            "exp1-hedge",
            "edge_enter_s = 0.4",
            "edge_enter_s = 1000.0",
            "switching.edge_enter_s",
            "control ticks",
        ),
    ];
    for (name, from, to, field, reason) in cases {
        let text = Source::builtin(name).unwrap().text;
        let e = edited_error_of(text, hedge(from, to));
        assert_field(&e, field, reason);
    }
    // A Stop delay of 700 s is 70 000 ticks at 100 Hz.
    let e = hedge_error_of(|t| format!("{t}\n[switching]\nstop_delay_s = 700.0\n"));
    assert_field(&e, "switching.stop_delay_s", "control ticks");
}

/// The built-in `tracking-v2-offset` (a speed schedule over 0.3-3 m/s)
/// changed by `edit`.
fn scheduled_error_of(edit: impl Fn(String) -> String) -> ScenarioError {
    let text = Source::builtin("tracking-v2-offset").unwrap().text;
    edited_error_of(text, edit)
}

#[test]
fn the_speed_schedule_and_the_steering_lag_are_checked() {
    let schedule_end = "max_speed_m_s = 3.0";
    // (text, its replacement, the field named, part of the reason)
    let cases = [
        // A speed above the scheduled range (PT-SCHEDULE-RANGE).
        (
            "speed_m_s = 2.0",
            "speed_m_s = 3.5",
            "control.speed_m_s",
            "PT-SCHEDULE-RANGE",
        ),
        (
            schedule_end,
            "max_speed_m_s = 0.2",
            "control.schedule.max_speed_m_s",
            "must be >= control.schedule.min_speed_m_s",
        ),
        (
            "min_speed_m_s = 0.3",
            "min_speed_m_s = 0.0",
            "control.schedule.min_speed_m_s",
            "",
        ),
        (
            schedule_end,
            "max_speed_m_s = 3.0\nbandwidth_per_s = -1.0",
            "control.schedule.bandwidth_per_s",
            "",
        ),
        (
            "steering_lag_s = 0.3333",
            "steering_lag_s = -0.1",
            "control.steering_lag_s",
            "",
        ),
        (
            "steering_lag_s = 0.3333",
            "steering_lag_s = 25.0",
            "control.steering_lag_s",
            "",
        ),
        // The plant's lag is checked where it is configured.
        (
            "steering_settling_s = 1.0",
            "steering_settling_s = 61.0",
            "vehicle.steering_settling_s",
            "",
        ),
    ];
    for (from, to, field, reason) in cases {
        let e = scheduled_error_of(|t| t.replace(from, to));
        assert_field(&e, field, reason);
    }
    let e = scheduled_error_of(|t| t.replace(schedule_end, "max_speed_m_s = 3.0\nrate = 1"));
    assert!(e.to_string().contains("rate"), "{e}");
}

/// The fix rule (GD-FIX-QUALITY): its kind, carry and slope need its
/// largest accuracy; each out-of-range value is named; off by default.
#[test]
fn fix_rule_fields_are_checked_and_named() {
    let with = |section: &'static str| move |t: String| format!("{t}\n[switching]\n{section}\n");
    let e = error_of(with("fix_dead_reckoning_m = 10.0"));
    assert_field(&e, "switching.fix_max_accuracy_m", "largest accuracy");
    let e = error_of(with("fix_worst_kind = \"rtk_float\""));
    assert_field(&e, "switching.fix_max_accuracy_m", "largest accuracy");
    for (text, field) in [
        ("fix_max_accuracy_m = 0.0", "switching.fix_max_accuracy_m"),
        ("fix_max_accuracy_m = -0.1", "switching.fix_max_accuracy_m"),
        ("fix_max_accuracy_m = nan", "switching.fix_max_accuracy_m"),
        (
            "fix_max_accuracy_m = 0.05\nfix_dead_reckoning_m = -1.0",
            "switching.fix_dead_reckoning_m",
        ),
        (
            "fix_max_accuracy_m = 0.05\nfix_rejoin_slope = 0.0",
            "switching.fix_rejoin_slope",
        ),
        (
            "fix_max_accuracy_m = 0.05\nfix_rejoin_slope = 1.5",
            "switching.fix_rejoin_slope",
        ),
        (
            "fix_max_accuracy_m = 0.05\nfix_rejoin_curvature = 0.0",
            "switching.fix_rejoin_curvature",
        ),
        (
            "fix_max_accuracy_m = 0.05\nfix_rejoin_curvature = nan",
            "switching.fix_rejoin_curvature",
        ),
        (
            "fix_rejoin_curvature = 0.05",
            "switching.fix_max_accuracy_m",
        ),
        (
            "fix_max_accuracy_m = 0.05\nfix_float_averaging_m = 0.0",
            "switching.fix_float_averaging_m",
        ),
        (
            "fix_max_accuracy_m = 0.05\nfix_float_averaging_m = nan",
            "switching.fix_float_averaging_m",
        ),
        (
            "fix_float_averaging_m = 2.0",
            "switching.fix_max_accuracy_m",
        ),
    ] {
        let e = error_of(move |t: String| format!("{t}\n[switching]\n{text}\n"));
        assert_field(&e, field, "");
    }
    let e = error_of(with(
        "fix_max_accuracy_m = 0.05\nfix_worst_kind = \"rtk_bad\"",
    ));
    assert!(e.to_string().contains("fix_worst_kind"), "{e}");
    // Off by default; set, its defaults: RTK fixed, no carry, slope 0.1,
    // curvature 0.05 /m.
    let setup = switching_of;
    assert!(setup(builtin_text()).fix.is_none());
    let fix = setup(format!(
        "{}\n[switching]\nfix_max_accuracy_m = 0.05\n",
        builtin_text()
    ))
    .fix
    .unwrap();
    assert_eq!(fix.worst_kind, fieldguide::guidance::FixKind::RtkFixed);
    assert_eq!(fix.path_dead_reckoning.get(), 0.0);
    assert!((fix.rejoin_slope - 0.1).abs() < 1e-15);
    assert!((fix.rejoin_curvature - 0.05).abs() < 1e-15);
    assert!((fix.max_accuracy.get() - 0.05).abs() < 1e-15);
    assert_eq!(fix.float_averaging, None);
    // The float averaging and the hand-over's line hold, given.
    let s = setup(format!(
        "{}\n[switching]\nfix_max_accuracy_m = 0.05\nfix_float_averaging_m = 2.0\nhandover_hold_m = 4.0\nhandover_line_m = 3.0\n",
        builtin_text()
    ));
    assert_eq!(
        s.fix.unwrap().float_averaging.map(fieldguide::Meters::get),
        Some(2.0)
    );
    assert_eq!(
        s.handover.unwrap().line_hold.map(fieldguide::Meters::get),
        Some(3.0)
    );
}

/// The `[switching]` of the scenario `text`, which must be accepted.
fn switching_of(text: String) -> fieldguide_sim::scenario::setup::SwitchingSetup {
    let source = Source {
        origin: "edited.toml".into(),
        text,
        base_dir: None,
    };
    source.setup(&mut SimRng::from_seed(1)).unwrap().switching
}

/// The odometry aid (GD-ODOMETRY-AID): its rate needs its time constant;
/// each out-of-range value is named; off by default, 0.5°/s when only the
/// time constant is given.
#[test]
fn odometry_aid_fields_are_checked_and_named() {
    let e = error_of(|t: String| format!("{t}\n[switching]\nodometry_aid_max_rate_deg_s = 1.0\n"));
    assert_field(
        &e,
        "switching.odometry_aid_time_constant_s",
        "time constant",
    );
    let aid = |tau: &'static str, rate: &'static str| {
        move |t: String| {
            format!("{t}\n[switching]\nodometry_aid_time_constant_s = {tau}\nodometry_aid_max_rate_deg_s = {rate}\n")
        }
    };
    for tau in ["0.0", "nan", "1001.0", "-1.0"] {
        let e = error_of(aid(tau, "0.5"));
        assert_field(&e, "switching.odometry_aid_time_constant_s", "");
    }
    for rate in ["0.0", "-1.0", "181.0", "inf"] {
        let e = error_of(aid("1.0", rate));
        assert_field(&e, "switching.odometry_aid_max_rate_deg_s", "");
    }
    assert!(switching_of(builtin_text()).odometry_aid.is_none());
    // The rate left out: 0.5°/s.
    let text = builtin_text() + "\n[switching]\nodometry_aid_time_constant_s = 2.0\n";
    let given = switching_of(text)
        .odometry_aid
        .map(|a| (a.time_constant, a.max_rate));
    let (tau, rate) = given.unwrap();
    assert!((tau.get() - 2.0).abs() < 1e-15);
    assert!((rate.get() - 0.5_f64.to_radians()).abs() < 1e-15);
}
