//! Localisation lost in the middle of a plot, closed loop ("Bad
//! input"): the built-in scenario `gnss-outage` is the furrow-pursuing field
//! with the GNSS fix lost twice, once mid-plot (the rows keep steering) and
//! once over the bare stretch (no source is left: Stop until the fix
//! returns). Every figure is ground truth.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

mod common;

use fieldguide::guidance::{FixKind, FixUse, Mode};
use fieldguide_sim::guidance::pipeline::FURROW;
use fieldguide_sim::metrics::summarize;
use fieldguide_sim::runner::{self, RunEnd, RunOutput, TickRecord};
use fieldguide_sim::scenario::{Setup, Source};

fn run(name: &str) -> (Setup, RunOutput) {
    let (setup, mut rng) = runner::prepare(&Source::builtin(name).unwrap()).unwrap();
    let out = runner::run(&setup, &mut rng);
    assert_eq!(out.end, RunEnd::PathEnd, "{name}");
    (setup, out)
}

/// Whether a source gave the command of this tick (the record carries the
/// source's error exactly then).
fn has_source(r: &TickRecord) -> bool {
    r.command.estimated_error.is_some()
}

//= spec/pierre2022.md#sw-command-valid-command-only-from-a-valid-estimate
//= type=test
//# The command source MUST be the active behaviour when the mode is its
//# specialised mode and its verdict is Enter or Hold; otherwise path tracking
//# when the mode is not Stop and localisation is valid; otherwise there MUST be
//# no command source.
//= spec/pierre2022.md#sw-s4-stop-exactly-after-the-stop-delay-without-a-source
//= type=test
//# The mode MUST be Stop exactly when, in each of the last Stop-delay ticks,
//# localisation was invalid and the mode was not a specialised mode whose
//# behaviour gave a valid estimate.
//= spec/guidance.md#gd-stop-the-stop-command
//= type=test
//# In Stop the command MUST be the stop of the last command made (every speed
//# zero, steering angles held, a yaw rate zero), or the vehicle at rest before
//# any command, never saturated.
#[test]
fn the_rows_steer_through_a_lost_fix_and_the_robot_stops_when_nothing_is_left() {
    let (setup, out) = run("gnss-outage");
    let t = &out.trace;
    let period = setup.control.period_s;
    let spans = setup.gnss_outages.spans().to_vec();
    assert_eq!(spans.len(), 2);
    let during = |span: (f64, f64)| -> Vec<&TickRecord> {
        t.iter()
            .filter(|r| r.t_s >= span.0 - 1e-9 && r.t_s < span.1 - 1e-9)
            .collect()
    };
    // The fix is missing exactly in the spans.
    for r in t {
        let lost = spans
            .iter()
            .any(|(a, b)| r.t_s >= *a - 1e-9 && r.t_s < *b - 1e-9);
        assert_eq!(r.readings.gnss.is_none(), lost, "t = {}", r.t_s);
    }

    // 1. Mid-plot: furrow pursuing steers throughout, within 0.1 m of the rows.
    let first = during(spans[0]);
    assert!(first.len() > 1000);
    for r in &first {
        assert_eq!(
            r.command.switching_mode,
            Mode::Behaviour(FURROW),
            "t = {}",
            r.t_s
        );
        assert_eq!(r.mode(), Mode::Behaviour(FURROW), "t = {}", r.t_s);
        let e = r.plot.expect("inside the maize plot").lateral_error_m;
        assert!(e.abs() < 0.1, "t = {}: {e}", r.t_s);
    }

    // 2. Over the bare stretch: no source, then Stop after the Stop delay.
    let second = during(spans[1]);
    let stop_at = second
        .iter()
        .position(|r| r.command.switching_mode == Mode::Stop)
        .expect("Stop while nothing can steer");
    let last_source = second[..stop_at]
        .iter()
        .rposition(|r| has_source(r))
        .expect("the rows steered before they vanished");
    let stop_ticks = (setup.switching.stop_delay_s / period).round() as usize;
    assert_eq!(
        stop_at - last_source,
        stop_ticks,
        "Stop after exactly the Stop delay"
    );
    assert!(second[last_source..stop_at]
        .iter()
        .skip(1)
        .all(|r| !has_source(r)));
    // Stop until the fix returns, at 0 m/s, the robot standing still.
    let stopped = &second[stop_at..];
    for r in stopped {
        assert_eq!(r.command.switching_mode, Mode::Stop, "t = {}", r.t_s);
        assert_eq!(r.command.speed().get(), 0.0);
        assert!(!r.command.saturated);
    }
    let moved = stopped.last().unwrap().distance_m - stopped[0].distance_m;
    assert!(moved < 0.01, "moved {moved} m in Stop");
    // Where it stopped: inside the bean plot, short of its bare stretch
    // (the inclined LiDAR sees the rows end about 4 m ahead).
    let beans = &setup.world.plots[1].spec;
    let bare_x = beans.centre_line(beans.bare[0].0).0;
    let stop_x = stopped[0].truth.position.x();
    assert!(
        stop_x > beans.centre_line(0.0).0 && stop_x < bare_x,
        "{stop_x}"
    );
    eprintln!(
        "gnss-outage: rows vanished at t = {:.2} s, Stop at t = {:.2} s, x = {stop_x:.2} m, \
         held {:.1} s until the fix returned",
        second[last_source].t_s,
        stopped[0].t_s,
        stopped.len() as f64 * period
    );
    // The first tick with the fix back: path tracking steers again.
    let back = t.iter().find(|r| r.t_s >= spans[1].1 - 1e-9).unwrap();
    assert_eq!(back.command.switching_mode, Mode::PathTracking);
    assert!(has_source(back) && back.command.speed().get() > 0.0);
    // ... and furrow pursuing takes the rows again after the bare stretch.
    assert!(t
        .iter()
        .filter(|r| r.t_s > back.t_s)
        .any(|r| r.mode() == Mode::Behaviour(FURROW)));

    // The whole run: rows followed within 0.1 m, no plant run over, and the
    // summary's times measured.
    let worst = t
        .iter()
        .filter_map(|r| r.plot.map(|p| p.lateral_error_m.abs()))
        .fold(0.0, f64::max);
    assert!(worst < 0.1, "{worst}");
    assert_eq!(out.plants_crushed, 0);
    let summary = summarize(&setup, &out);
    let lost: f64 = spans.iter().map(|(a, b)| b - a).sum();
    assert!((summary.gnss_lost_s - lost).abs() < 2.0 * period);
    assert!((summary.stop_s - stopped.len() as f64 * period).abs() < 1e-9);
    // The same field with a fix throughout never stops.
    let (setup, out) = run("furrow-pursuing");
    let summary = summarize(&setup, &out);
    assert_eq!((summary.gnss_lost_s, summary.stop_s), (0.0, 0.0));
}

/// The plots show what happened: the outages shaded and named in the
/// legend of `lateral_error.svg`, and each spell in Stop marked on both
/// plots with its length, which the trace confirms.
#[test]
fn the_plots_shade_the_outages_and_mark_each_stop_with_its_length() {
    let (setup, out) = run("gnss-outage");
    let period = setup.control.period_s;
    let stopped = out
        .trace
        .iter()
        .filter(|r| r.command.switching_mode == Mode::Stop)
        .count();
    assert!(stopped > 0);
    // One spell here: its length as the plots print it.
    let label = format!("stop {:.1} s", stopped as f64 * period);
    let lateral = fieldguide_sim::output::plots::lateral_error_svg(&setup, &out.trace);
    assert!(lateral.contains("GNSS fix lost"), "no outage in the legend");
    assert!(lateral.contains(&label), "{label} missing");
    let trajectory = fieldguide_sim::output::plots::trajectory_svg(&setup, &out.trace);
    assert!(trajectory.contains(&label), "{label} missing");
    // The path-tracking field has no outage and no stop: neither is drawn.
    let (clear, clear_out) = run("path-tracking");
    let lateral = fieldguide_sim::output::plots::lateral_error_svg(&clear, &clear_out.trace);
    assert!(!lateral.contains("GNSS fix lost") && !lateral.contains("stop "));
}

/// The float fix's plants: those the wheels reach while the fix of
/// `gnss-drift-random-walk` is float (path abscissa 34-46 m, the front axle
/// 2 m ahead of O): x from 28 to 44 m.
const FLOAT_PLANTS_X: (f64, f64) = (28.0, 44.0);

//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# When a fix rule is configured, a tick whose fix is not good MUST be
//# processed as a tick without a fix: it MUST NOT be projected for path
//# tracking or for the plan check, nor become the last fix of
//# GD-PLAN-DEAD-RECKONING; without a rule every fix MUST be taken.
/// The receiver says when its fix is float, and the fix rule keeps that fix
/// from path tracking: over seeds 1-5 of `gnss-drift-random-walk`, no plant
/// the wheels reach during the float span is crushed with the rule; without
/// it, path tracking follows the float fix's 0.3-1 m jump into the beans.
#[test]
fn a_float_fix_reported_as_such_crushes_nothing_with_the_fix_rule() {
    let source = common::stress_source("gnss-drift-random-walk");
    let mut crushed_without = 0;
    for seed in 1..=5 {
        let (setup, mut rng) = runner::prepare_with_seed(&source, seed).unwrap();
        let noise = setup.noise.gnss_position_m;
        let out = runner::run(&setup, &mut rng);
        assert_eq!(out.end, RunEnd::PathEnd, "seed {seed}");
        let mut float_ticks = 0;
        for r in &out.trace {
            let q = r.readings.gnss_quality;
            let sigma = q.accuracy.unwrap().get();
            if r.gnss_float {
                float_ticks += 1;
                // Float, with the span's spread: √(0.015² + 0.1² + 0.3²).
                assert_eq!(q.kind, FixKind::RtkFloat);
                assert!((sigma - noise.hypot(0.1_f64.hypot(0.3))).abs() < 1e-12);
                assert!(
                    !matches!(r.command.fix, FixUse::Fix),
                    "seed {seed}, t {}: path tracking on a float fix",
                    r.t_s
                );
            } else {
                // Fixed, with the receiver's white noise: the drift is not in it.
                assert_eq!(q.kind, FixKind::RtkFixed);
                assert_eq!(sigma, noise);
                assert_eq!(r.command.fix, FixUse::Fix, "seed {seed}, t {}", r.t_s);
            }
        }
        assert!(float_ticks > 1000, "seed {seed}: {float_ticks} float ticks");
        let in_span = |out: &RunOutput| {
            out.crushed
                .iter()
                .filter(|p| p.x_m >= FLOAT_PLANTS_X.0 && p.x_m < FLOAT_PLANTS_X.1)
                .count()
        };
        assert_eq!(
            in_span(&out),
            0,
            "seed {seed}: plants crushed over the float span"
        );
        // The same field and seed without the rule.
        let mut off = source.clone();
        off.text = common::without_key(&off.text, "fix_");
        let (setup, mut rng) = runner::prepare_with_seed(&off, seed).unwrap();
        assert!(setup.switching.fix.is_none());
        crushed_without += in_span(&runner::run(&setup, &mut rng));
    }
    // 20 over seeds 1-5 (the field's line hold, GD-HANDOVER-LINE, keeps a
    // few at the maize's end).
    assert!(crushed_without >= 15, "without the rule: {crushed_without}");
}
