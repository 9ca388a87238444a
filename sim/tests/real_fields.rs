//! The simulator expresses real fields: GNSS errors beyond white noise
//! (bias, drift, float-fix spans), outages placed along the path, a speed
//! per segment of the path, crushed plants located, turn metrics, the
//! sweep's worst seeds kept and an odometry heading from a yaw gyro. Every figure is against ground truth; closed
//! loop bounds over seeds.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

use std::path::PathBuf;
use std::process::Command;

use fieldguide::guidance::Mode;
use fieldguide_sim::metrics::{summarize, turns};
use fieldguide_sim::output::plots::{rows_svg_marked, trajectory_svg_marked, CRUSHED_CLASS};
use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, RunEnd, RunOutput, TickRecord, WHEELS};
use fieldguide_sim::scenario::{Setup, Source};
use fieldguide_sim::world::{Plant, PlantKind};
use fieldguide_sim::ScenarioError;

/// The text of the stress scenario `name` (`sim/scenarios/stress/`).
fn stress(name: &str) -> String {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios/stress")
        .join(format!("{name}.toml"));
    std::fs::read_to_string(file).unwrap()
}

/// The built-in scenario `name`'s text.
fn builtin(name: &str) -> String {
    Source::builtin(name).unwrap().text
}

fn source(text: &str) -> Source {
    Source {
        origin: "edited.toml".to_owned(),
        text: text.to_owned(),
        base_dir: None,
    }
}

/// `text` run with `seed`.
fn run(text: &str, seed: u64) -> (Setup, RunOutput) {
    let (setup, mut rng) = runner::prepare_with_seed(&source(text), seed).unwrap();
    let out = runner::run(&setup, &mut rng);
    (setup, out)
}

/// The error `text` is refused with.
fn refused(text: &str) -> ScenarioError {
    source(text)
        .setup(&mut SimRng::from_seed(1))
        .expect_err("the scenario must be refused")
}

fn assert_field(e: &ScenarioError, field: &str, reason_part: &str) {
    assert_eq!(e.field(), Some(field), "{e}");
    assert!(e.to_string().contains(reason_part), "{e}");
}

/// GNSS position error of each tick (estimate minus truth), `None` without a fix.
fn gnss_errors(trace: &[TickRecord]) -> Vec<Option<(f64, f64)>> {
    trace
        .iter()
        .map(|r| {
            r.readings.gnss.map(|g| {
                (
                    g.position.x() - r.truth.position.x(),
                    g.position.y() - r.truth.position.y(),
                )
            })
        })
        .collect()
}

/// The differences, tick by tick, between the GNSS errors of `with` and
/// `without` (same seed: the same white noise in every tick).
fn added_error(with: &[TickRecord], without: &[TickRecord]) -> Vec<(f64, f64, f64)> {
    gnss_errors(with)
        .into_iter()
        .zip(gnss_errors(without))
        .zip(with)
        .map(|((a, b), r)| {
            let (a, b) = (a.unwrap(), b.unwrap());
            (r.t_s, a.0 - b.0, a.1 - b.1)
        })
        .collect()
}

/// The path-tracking built-in, 30 s long, with `gnss` as its `[gnss]` section.
fn path_tracking_with(gnss: &str) -> String {
    let text = builtin("path-tracking").replace("duration_s = 150.0", "duration_s = 30.0");
    format!("{text}\n[gnss]\n{gnss}\n")
}

#[test]
fn a_bias_moves_every_reported_position_by_the_bias_and_nothing_else() {
    for seed in [1, 2, 3] {
        let (_, plain) = run(&path_tracking_with(""), seed);
        let (_, biased) = run(&path_tracking_with("bias_m = [0.3, -0.2]"), seed);
        // The closed loop follows the biased fix: the true trajectory moves.
        assert_ne!(plain.trace, biased.trace);
        for (t, dx, dy) in added_error(&biased.trace, &plain.trace) {
            assert!(
                (dx - 0.3).abs() < 1e-9 && (dy + 0.2).abs() < 1e-9,
                "seed {seed}, t = {t}: ({dx}, {dy})"
            );
        }
    }
}

#[test]
fn a_biased_fix_drives_the_wheels_onto_the_rows_and_every_crushed_plant_is_located() {
    for seed in [2022, 1, 2] {
        let (setup, out) = run(&stress("gnss-drift-bias-maize"), seed);
        let summary = summarize(&setup, &out);
        // The fix 0.4 m north of the truth: path tracking holds the truth
        // 0.4 m south of the rows' centre line (ground truth, in the plots).
        let in_plot = summary.in_plot_lateral_error_m.unwrap();
        assert!(
            (in_plot.mean_abs - 0.4).abs() < 0.03,
            "seed {seed}: {in_plot:?}"
        );
        assert!(summary.plants_crushed > 100, "seed {seed}");
        assert_eq!(summary.crushed_plants.len(), summary.plants_crushed);
        let period = setup.control.period_s;
        let half_tyre = setup.vehicle.tyre_width_m / 2.0;
        for c in &summary.crushed_plants {
            // The plant as the world holds it: a crop plant of that plot.
            let plant = &setup.world.plants[c.index];
            assert_eq!(plant.kind, PlantKind::Crop);
            assert_eq!((plant.position.x(), plant.position.y()), (c.x_m, c.y_m));
            let (plot, _) = setup.world.plot_at(c.x_m, c.y_m, 2.0).unwrap();
            assert_eq!(
                c.plot.as_deref(),
                Some(setup.world.plots[plot].name.as_str())
            );
            // Under the named wheel at the tick named, and under no wheel the tick before.
            let k = (c.t_s / period).round() as usize;
            let wheel = WHEELS.iter().position(|w| *w == c.wheel).unwrap();
            let reach = plant.radius + half_tyre;
            let under = |r: &TickRecord, w: usize| {
                let p = setup.vehicle.wheel_centres(&r.truth)[w];
                (p[0] - c.x_m).hypot(p[1] - c.y_m) < reach
            };
            assert!((out.trace[k].t_s - c.t_s).abs() < 1e-9);
            assert!(under(&out.trace[k], wheel), "seed {seed}: {c:?}");
            if k > 0 {
                assert!((0..4).all(|w| !under(&out.trace[k - 1], w)), "{c:?}");
            }
        }
        // One cross per crushed plant on both figures.
        for svg in [
            trajectory_svg_marked(&setup, &out.trace, &out.crushed),
            rows_svg_marked(&setup, &out.trace, &out.crushed),
        ] {
            let group = svg
                .lines()
                .find(|l| l.contains(CRUSHED_CLASS))
                .expect("the crosses' group");
            assert_eq!(group.matches("<path d=\"M").count(), summary.plants_crushed);
        }
    }
}

#[test]
fn plants_placed_under_the_wheels_are_located_under_those_wheels() {
    let text = builtin("path-tracking").replace("duration_s = 150.0", "duration_s = 10.0");
    let (mut setup, mut rng) = runner::prepare(&source(&text)).unwrap();
    // Started 0.8 m right of the path heading east, rear axle at x = 0,
    // front axle at x = 2 m, wheels 0.75 m each side of O.
    let y0 = setup.initial.position.y();
    let plant = |x: f64, y: f64| Plant {
        position: fieldguide::Point2::new(x, y).unwrap(),
        radius: 0.05,
        height: 0.3,
        kind: PlantKind::Crop,
    };
    setup.world.plants = vec![plant(0.3, y0 - 0.75), plant(2.2, y0 + 0.75), plant(0.3, y0)];
    let out = runner::run(&setup, &mut rng);
    let located: Vec<(usize, &str)> = out.crushed.iter().map(|c| (c.index, c.wheel)).collect();
    assert_eq!(located, [(1, "front_left"), (0, "rear_right")]);
    assert!(out.crushed.iter().all(|c| c.plot.is_none() && c.t_s < 1.0));
}

#[test]
fn a_float_span_jumps_once_and_a_sinusoidal_drift_has_its_amplitude_and_period() {
    let (_, plain) = run(&path_tracking_with(""), 7);
    let (setup, float) = run(
        &path_tracking_with("float_s = [[2.0, 4.0]]\nfloat_noise_m = 0.0\nfloat_jump_m = 0.3"),
        7,
    );
    let added = added_error(&float.trace, &plain.trace);
    let inside: Vec<_> = added
        .iter()
        .filter(|(t, _, _)| (2.0..4.0).contains(t))
        .collect();
    let (_, jx, jy) = *inside[0];
    assert!(jx.hypot(jy) > 1e-3, "a jump when the fix turns float");
    assert!(inside
        .iter()
        .all(|(_, x, y)| (x - jx).abs() < 1e-9 && (y - jy).abs() < 1e-9));
    assert!(added
        .iter()
        .filter(|(t, _, _)| !(2.0..4.0).contains(t))
        .all(|(_, x, y)| x.abs() < 1e-9 && y.abs() < 1e-9));
    let summary = summarize(&setup, &float);
    assert!((summary.gnss_float_s - 2.0).abs() < 1.5 * setup.control.period_s);

    let (_, drift) = run(
        &path_tracking_with(
            "drift = \"sinusoid\"\ndrift_m = 0.2\ndrift_time_constant_s = 10.0\ndrift_heading_deg = 90.0",
        ),
        7,
    );
    for (t, x, y) in added_error(&drift.trace, &plain.trace) {
        let expected = 0.2 * (std::f64::consts::TAU * t / 10.0).sin();
        assert!(x.abs() < 1e-9 && (y - expected).abs() < 1e-9, "t = {t}");
    }
}

#[test]
fn gnss_errors_are_checked_and_named() {
    let with = |gnss: &str| path_tracking_with(gnss);
    assert_field(
        &refused(&with("drift_m = 0.1")),
        "gnss.drift_m",
        "needs `gnss.drift`",
    );
    assert_field(
        &refused(&with("drift = \"random_walk\"\ndrift_m = 0.1")),
        "gnss.drift_time_constant_s",
        "needed",
    );
    assert_field(
        &refused(&with(
            "drift = \"random_walk\"\ndrift_m = 0.1\ndrift_time_constant_s = 0.0",
        )),
        "gnss.drift_time_constant_s",
        "",
    );
    assert_field(
        &refused(&with("float_jump_m = 0.3")),
        "gnss.float_jump_m",
        "needs float spans",
    );
    assert_field(&refused(&with("bias_m = [0.0, inf]")), "gnss.bias_m", "");
}

/// The ticks of `trace` without a fix.
fn lost(trace: &[TickRecord]) -> Vec<bool> {
    trace.iter().map(|r| r.readings.gnss.is_none()).collect()
}

#[test]
fn an_outage_placed_by_distance_starts_and_ends_where_the_ground_truth_crosses_it() {
    for seed in [2022, 1, 2] {
        let (setup, out) = run(&stress("gnss-outage-distance"), seed);
        assert_eq!(out.end, RunEnd::PathEnd, "seed {seed}");
        // The plot-end outage: from 12 m before the true end of plot 1 (its
        // centre line's end projected on the path), 6 m long.
        let plot = &setup.world.plots[1].spec;
        let (x, y, h) = plot.centre_line(plot.length);
        let end = setup
            .path
            .project(
                &fieldguide::Pose2::new(x, y, h).unwrap(),
                fieldguide::Meters::ZERO,
            )
            .unwrap()
            .s
            .get();
        let spans = [(20.0, 26.0), (end - 12.0, end - 6.0)];
        let expected = |s: f64| spans.iter().any(|(a, b)| s >= *a && s < *b);
        for (r, lost) in out.trace.iter().zip(lost(&out.trace)) {
            assert_eq!(lost, expected(r.s_m), "seed {seed}, s = {}", r.s_m);
        }
        // Each span is crossed: the fix is lost at the first tick past its start.
        for (from, to) in spans {
            let first = out.trace.iter().position(|r| r.s_m >= from).unwrap();
            assert!(out.trace[first].readings.gnss.is_none());
            assert!(out.trace[first - 1].readings.gnss.is_some());
            assert!(out.trace.iter().any(|r| r.s_m >= to));
        }
        // Inside the plots, the rows steer through the outages.
        let summary = summarize(&setup, &out);
        assert!(summary.success, "seed {seed}: {:?}", summary.failures);
    }
}

#[test]
fn an_outage_the_robot_cannot_drive_out_of_stops_the_run_and_names_it() {
    // From 3 m before the end of the beans into the run-out: the rows end,
    // no source is left, Stop, and the robot never crosses the outage's end.
    let text = stress("gnss-outage-distance").replace("before_m = 12.0", "before_m = 3.0");
    for seed in [2022, 1] {
        let (setup, out) = run(&text, seed);
        let RunEnd::Aborted(why) = &out.end else {
            panic!("seed {seed}: {:?}", out.end);
        };
        assert!(
            why.contains("gnss.plot_end_outages[0]") && why.contains("never ends"),
            "{why}"
        );
        // Stopped after the stall time, standing in Stop without a fix.
        let last = out.trace.last().unwrap();
        assert_eq!(last.command.switching_mode, Mode::Stop);
        assert!(last.readings.gnss.is_none());
        let stop_ticks = out
            .trace
            .iter()
            .rev()
            .take_while(|r| r.command.switching_mode == Mode::Stop)
            .count();
        let stalled = stop_ticks as f64 * setup.control.period_s;
        assert!(
            (stalled - runner::OUTAGE_STALL_S).abs() < 1.5 * setup.control.period_s,
            "{stalled}"
        );
        assert!(!summarize(&setup, &out).success);
    }
}

#[test]
fn outages_the_run_cannot_outlast_are_refused_and_named() {
    let furrow = stress("gnss-outage-distance");
    let time = path_tracking_with("outages_s = [[100.0, 200.0]]");
    assert_field(&refused(&time), "gnss.outages_s[0]", "after run.duration_s");
    let beyond = furrow.replace("outages_m = [[20.0, 26.0]]", "outages_m = [[70.0, 90.0]]");
    assert_field(&refused(&beyond), "gnss.outages_m[0]", "leaves the path");
    let overlap = furrow.replace("outages_m = [[20.0, 26.0]]", "outages_m = [[60.0, 65.0]]");
    assert_field(
        &refused(&overlap),
        "gnss.plot_end_outages[0]",
        "overlaps gnss.outages_m[0]",
    );
    let no_plot = furrow.replace("plot = 1", "plot = 5");
    assert_field(
        &refused(&no_plot),
        "gnss.plot_end_outages[0].plot",
        "no plot 5",
    );
}

#[test]
fn each_segment_is_tracked_at_its_own_speed() {
    for seed in [2022, 1, 2] {
        let (setup, out) = run(&stress("speed-segments-uturn"), seed);
        assert_eq!(out.end, RunEnd::PathEnd);
        // The arc covers s in [15, 15 + 4.5 pi]; margins for the tick of lag
        // and the estimate's noise.
        let arc_end = 15.0 + 4.5 * std::f64::consts::PI;
        for r in &out.trace {
            let expected = if (0.5..14.5).contains(&r.s_m) || r.s_m > arc_end + 0.5 {
                2.5
            } else if (15.5..arc_end - 0.5).contains(&r.s_m) {
                0.8
            } else {
                continue;
            };
            assert!(
                (r.command.speed().get() - expected).abs() < 1e-12,
                "seed {seed}, s = {}",
                r.s_m
            );
        }
        let summary = summarize(&setup, &out);
        assert!(summary.success, "seed {seed}: {:?}", summary.failures);
        // The arc takes its length at 0.8 m/s (turn metrics: |c| >= 0.1 on it).
        assert!(
            (summary.turn_s - 4.5 * std::f64::consts::PI / 0.8).abs() < 1.0,
            "{}",
            summary.turn_s
        );
    }
}

#[test]
fn segment_speeds_outside_the_schedule_are_refused_and_named() {
    let text = stress("speed-segments-uturn");
    for bad in ["3.5", "0.2"] {
        let e = refused(&text.replace(
            "arc_angle_deg = 180.0, speed_m_s = 0.8",
            &format!("arc_angle_deg = 180.0, speed_m_s = {bad}"),
        ));
        assert_field(&e, "path.segments[1].speed_m_s", "PT-SCHEDULE-RANGE");
    }
    let e = refused(&text.replace("speed_m_s = 2.5 }", "speed_m_s = -1.0 }"));
    assert_field(&e, "path.segments[0].speed_m_s", "");
}

#[test]
fn turn_metrics_split_the_ticks_by_the_paths_curvature() {
    let (setup, out) = run(&builtin("furrow-pursuing"), 2022);
    let period = setup.control.period_s;
    let trace = &out.trace;
    // Every tick a turn: the specialised time is the time in furrow pursuing.
    let all = turns(trace, 0.0, period);
    let furrow = trace
        .iter()
        .filter(|r| matches!(r.mode(), Mode::Behaviour(_)))
        .count() as f64
        * period;
    assert!(furrow > 10.0);
    assert!((all.specialised_s - furrow).abs() < 1e-6);
    assert!((all.time_s - trace.len() as f64 * period).abs() < 1e-6);
    assert!(all.straight.is_none());
    // No tick a turn.
    let none = turns(trace, 1e9, period);
    assert_eq!((none.time_s, none.specialised_s), (0.0, 0.0));
    assert!(none.curve.is_none());
    // The U-turn: the curve's |y| over the ticks with |c| >= 0.1 only.
    let (setup, out) = run(&stress("speed-segments-uturn"), 2022);
    let summary = summarize(&setup, &out);
    let curve: Vec<f64> = out
        .trace
        .iter()
        .filter(|r| r.curvature.abs() >= 0.1)
        .map(|r| r.lateral_error_m.abs())
        .collect();
    let max = curve.iter().copied().fold(0.0, f64::max);
    assert_eq!(summary.lateral_error_curve_m.unwrap().max_abs, max);
    assert_eq!(
        summary.turn_mode_s.keys().copied().collect::<Vec<_>>(),
        ["path_tracking"]
    );
}

#[test]
fn a_sweep_keeps_the_trace_and_plots_of_each_columns_worst_seed() {
    let dir = std::env::temp_dir().join(format!("fieldguide-real-fields-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = Command::new(env!("CARGO_BIN_EXE_fieldguide"))
        .args(["sweep", "path-tracking", "--seeds", "1..=3", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let root = dir.join("path-tracking");
    let sweep = std::fs::read_to_string(root.join("sweep.csv")).unwrap();
    let header: Vec<&str> = sweep.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|c| *c == "max_abs_y_m").unwrap();
    let (worst_seed, worst) = sweep
        .lines()
        .skip(1)
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            (cells[0].to_owned(), cells[column].parse::<f64>().unwrap())
        })
        .fold((String::new(), f64::NEG_INFINITY), |a, b| {
            if b.1 > a.1 {
                b
            } else {
                a
            }
        });
    let index = std::fs::read_to_string(root.join("worst/worst.csv")).unwrap();
    assert!(
        index.contains(&format!("max_abs_y_m,{worst_seed},seed-{worst_seed}")),
        "{index}"
    );
    let kept = root.join(format!("worst/seed-{worst_seed}"));
    for f in [
        "trace.csv",
        "summary.json",
        "trajectory.svg",
        "lateral_error.svg",
    ] {
        assert!(kept.join(f).exists(), "{f}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(kept.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["seed"].as_u64().unwrap().to_string(), worst_seed);
    assert_eq!(
        summary["lateral_error_m"]["max_abs"].as_f64().unwrap(),
        worst
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The path-tracking built-in, 30 s long, its odometry heading from a gyro
/// with the `[noise]` fields `gyro`.
fn path_tracking_with_gyro(gyro: &str) -> String {
    let text = builtin("path-tracking").replace("duration_s = 150.0", "duration_s = 30.0");
    let wheels = "odometry_yaw_bias_deg_s = 0.05\nodometry_yaw_noise_deg = 0.02";
    assert!(text.contains(wheels));
    text.replace(
        wheels,
        &format!("odometry_yaw_bias_deg_s = 0.0\nodometry_yaw_noise_deg = 0.0\nodometry_heading = \"gyro\"\n{gyro}"),
    )
}

/// Each tick's odometry heading error (to the true heading change since the
/// start), wrapped, with its time.
fn odometry_heading_errors(trace: &[TickRecord]) -> Vec<(f64, f64)> {
    let start = trace[0].truth.heading.get();
    trace
        .iter()
        .map(|r| {
            let e = r.readings.odometry.heading.get() - (r.truth.heading.get() - start);
            (r.t_s, e.sin().atan2(e.cos()))
        })
        .collect()
}

#[test]
fn a_gyro_heading_drifts_by_its_datasheet_figures() {
    // 36 °/h of bias, no random walk: 0.01 °/s, exactly, whatever the turns.
    let (_, out) = run(
        &path_tracking_with_gyro("gyro_random_walk_deg_sqrt_h = 0.0\ngyro_bias_deg_h = 36.0"),
        3,
    );
    let errors = odometry_heading_errors(&out.trace);
    assert!(errors.len() > 1000);
    for (t, e) in &errors {
        assert!((e - 0.01_f64.to_radians() * t).abs() < 1e-9, "t = {t}: {e}");
    }
    // 30 °/√h of random walk, no bias: each tick adds a white error of
    // σ (0.5 °/√s) √Δt; over the ticks of one run its estimate is within 10 %.
    let (setup, out) = run(
        &path_tracking_with_gyro("gyro_random_walk_deg_sqrt_h = 30.0\ngyro_bias_deg_h = 0.0"),
        3,
    );
    let errors = odometry_heading_errors(&out.trace);
    let steps: Vec<f64> = errors.windows(2).map(|w| w[1].1 - w[0].1).collect();
    let sigma = (steps.iter().map(|d| d * d).sum::<f64>() / steps.len() as f64).sqrt();
    let expected = 0.5_f64.to_radians() * setup.control.period_s.sqrt();
    assert!(
        (sigma / expected - 1.0).abs() < 0.1,
        "{sigma} vs {expected}"
    );
}

#[test]
fn gyro_fields_are_checked_and_named() {
    let wheels = builtin("path-tracking").replace(
        "odometry_yaw_noise_deg = 0.02",
        "odometry_yaw_noise_deg = 0.02\ngyro_bias_deg_h = 8.0",
    );
    assert_field(
        &refused(&wheels),
        "noise.gyro_bias_deg_h",
        "needs `noise.odometry_heading = \"gyro\"`",
    );
    let gyro = |fields: &str| path_tracking_with_gyro(fields);
    let both = "gyro_random_walk_deg_sqrt_h = 0.3\ngyro_bias_deg_h = 8.0";
    assert_field(
        &refused(&gyro(both).replace(
            "odometry_yaw_noise_deg = 0.0",
            "odometry_yaw_noise_deg = 0.02",
        )),
        "noise.odometry_yaw_noise_deg",
        "must be 0",
    );
    assert_field(
        &refused(&gyro("gyro_bias_deg_h = 8.0")),
        "noise.gyro_random_walk_deg_sqrt_h",
        "needed",
    );
    assert_field(
        &refused(&gyro(
            "gyro_random_walk_deg_sqrt_h = 61.0\ngyro_bias_deg_h = 8.0",
        )),
        "noise.gyro_random_walk_deg_sqrt_h",
        "within",
    );
    assert_field(
        &refused(&gyro(&format!("{both}\ngyro_bias_time_constant_s = 100.0"))),
        "noise.gyro_bias_time_constant_s",
        "needs `noise.gyro_bias_instability_deg_h`",
    );
    assert_field(
        &refused(&gyro(&format!("{both}\ngyro_bias_instability_deg_h = 4.0"))),
        "noise.gyro_bias_time_constant_s",
        "needed",
    );
    assert_field(
        &refused(&gyro(&format!(
            "{both}\ngyro_bias_instability_deg_h = 4.0\ngyro_bias_time_constant_s = 0.0"
        ))),
        "noise.gyro_bias_time_constant_s",
        "strictly between",
    );
    assert!(source(&gyro(&format!(
        "{both}\ngyro_bias_instability_deg_h = 4.0\ngyro_bias_time_constant_s = 300.0"
    )))
    .setup(&mut SimRng::from_seed(1))
    .is_ok());
}
