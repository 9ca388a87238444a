//! Closed-loop tests of path tracking over the speed range 0.3-3 m/s with
//! the steering's rate limit (30°/s) and lag (`spec/pierre2022.md`,
//! PT-SCHEDULE, PT-FEEDFORWARD-LAG, PT-SPEED-RANGE): the stress campaign's
//! path-tracking classes (the built-in `tracking-*` scenarios with the
//! bounds of `fieldguide_sim::stress::bounds`), each over seeds 1-10.
//!
//! Every error is ground truth: the true pose projected on the reference path.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

mod common;

use common::prepare_seed;
use fieldguide_sim::stress::{self, bounds};
use fieldguide_sim::sweep::Seeds;

/// Runs every case of the stress class `name` over seeds 1-10 and asserts
/// that no seed breaks a bound; prints the worst figures.
fn class_holds(name: &str) {
    let seeds = Seeds::new(1, 10).unwrap();
    let classes = stress::select(Some(name)).unwrap();
    let results = stress::campaign(&classes, seeds, |_| {}).unwrap();
    eprintln!("{}", stress::table_md(&results));
    for r in &results {
        assert!(r.pass(), "{}: {:?}", r.scenario, r.bounds);
    }
}

//= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
//= type=test
//# From 0.8 m off a straight, and from 1.5 m off heading 20° away from it,
//# path tracking with a schedule derived from the actuator MUST converge
//# (|y| < 0.05 m and staying) within the longest of 10 m, 5 s of travel and
//# 1.3 times the linearised loop's time, with an overshoot below 10 % of the
//# initial error from 0.8 m and 12 % from 1.5 m, at every speed of the schedule.
#[test]
fn converges_from_0_8_m_at_every_speed() {
    class_holds("speed-offset");
}

//= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
//= type=test
//# From 0.8 m off a straight, and from 1.5 m off heading 20° away from it,
//# path tracking with a schedule derived from the actuator MUST converge
//# (|y| < 0.05 m and staying) within the longest of 10 m, 5 s of travel and
//# 1.3 times the linearised loop's time, with an overshoot below 10 % of the
//# initial error from 0.8 m and 12 % from 1.5 m, at every speed of the schedule.
#[test]
fn converges_from_1_5_m_and_20_degrees_at_every_speed() {
    class_holds("speed-heading");
}

//= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
//= type=test
//# Started on the path, |y| MUST stay below the larger of 0.05 m and 1.25
//# times the offset Δκ d² / 24 of a rate-limited ramp through each curvature
//# step Δκ, and below the larger of 0.05 m and 1.25 times the drift of a
//# sideslip step.
#[test]
fn stays_in_the_band_through_s_bends_and_a_u_turn() {
    class_holds("s-bends");
    class_holds("tight-u-turn");
}

//= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
//= type=test
//# Started on the path, |y| MUST stay below the larger of 0.05 m and 1.25
//# times the offset Δκ d² / 24 of a rate-limited ramp through each curvature
//# step Δκ, and below the larger of 0.05 m and 1.25 times the drift of a
//# sideslip step.
#[test]
fn slip_steps_give_at_most_the_drift_the_steering_allows() {
    class_holds("slip-patches");
}

/// The bounds are the physics the spec derives, not figures fitted to runs:
/// the linear loop's time from 0.8 m at Ω = 2 1/s, the ramp offset of the
/// 8 m S-bend at 3 m/s and the drift of a 6° slip step at 2 m/s.
#[test]
fn the_bounds_follow_the_actuator() {
    let rate = 30.0_f64.to_radians();
    // A critically damped pair at Ω / 2 = 1 1/s from 0.8 m at rest: (0.8 + 0.8 t) e^-t = 0.05 at t ≈ 4.47 s.
    let t = bounds::linear_time_s(0.8, 0.0, 2.0);
    assert!((t - 4.472).abs() < 0.002, "{t}");
    // At 3 m/s the linear loop (1.3 × 3 × 4.47 = 17.4 m) outlasts 15 m (5 s).
    let allowed = bounds::allowed_convergence_m(3.0, -0.8, 0.0, 2.0);
    assert!((allowed - 1.3 * 3.0 * t).abs() < 1e-9, "{allowed}");
    assert!((bounds::allowed_convergence_m(0.3, -0.8, 0.0, 2.0) - 10.0).abs() < 1e-12);
    // d = 0.25 × 2 × 3 / R = 2.86 m; offset 0.25 d² / 24 = 0.085 m.
    let ramp = bounds::ramp_offset_m(0.25, 3.0, 2.0, rate);
    assert!((ramp - 0.0851).abs() < 1e-3, "{ramp}");
    // Slower steering, more drift; faster driving, more offset.
    assert!(bounds::ramp_offset_m(0.25, 3.0, 2.0, rate / 2.0) > ramp);
    let drift = bounds::slip_drift_m(6.0_f64.to_radians(), 2.0, 2.0, rate, 0.5 / 3.0);
    assert!((drift - 0.1286).abs() < 1e-3, "{drift}");
}

//= spec/pierre2022.md#pt-feedforward-lag-feed-forward-timed-for-the-steering-lag
//= type=test
//# The curvature MUST be fed forward at s + v (T + τ), with T the
//# prediction horizon and τ ≥ 0 the steering's configured time constant.
#[test]
fn a_slow_steering_converges_and_holds_the_straights() {
    let (setup, _) = prepare_seed("tracking-lag-2s", 1);
    let v = setup.control.speed.get();
    let bandwidth = setup
        .control
        .backstepping
        .schedule
        .unwrap()
        .bandwidth()
        .get();
    // Ω = min(2 R / δ_max, 1 / τ) = 1 / (2 / 3) = 1.5 1/s.
    assert!((bandwidth - 1.5).abs() < 1e-3, "{bandwidth}");
    let lead = setup.control.horizon_s + setup.control.steering_lag_s;
    assert!((setup.control.lookahead.get() - v * lead).abs() < 1e-9);
    assert!((setup.control.steering_lag_s - 2.0 / 3.0).abs() < 1e-3);
    // Converged on the first straight (s < 40 m) within PT-SPEED-RANGE's
    // distance; the S-bend's 0.15 m is measured, not derived.
    class_holds("steering-lag-2s");
}
