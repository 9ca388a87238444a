//! Closed-loop tests of path tracking over the speed range 0.3-3 m/s with
//! the steering's rate limit (30°/s) and lag (`spec/pierre2022.md`,
//! PT-SCHEDULE, PT-FEEDFORWARD-LAG, PT-SPEED-RANGE): the built-in
//! `tracking-*` scenarios, each over the seeds 2022 and 1-10.
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
use fieldguide_sim::metrics::summarize;
use fieldguide_sim::runner::{self, RunEnd, RunOutput};
use fieldguide_sim::scenario::Setup;

/// The seeds of every sweep: the scenarios' own and ten more.
const SEEDS: [u64; 11] = [2022, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10];

/// The convergence band, m.
const BAND_M: f64 = 0.05;

/// The steering's rate limit R (30°/s), its saturation (30°) and the wheelbase.
const RATE: f64 = std::f64::consts::FRAC_PI_6;
const WHEELBASE_M: f64 = 2.0;

/// What one run gives: converged distance, overshoot (the largest error on
/// the far side of the path, m), largest |y| after convergence and overall.
#[derive(Debug, Clone, Copy)]
struct Figures {
    converged_m: f64,
    overshoot_m: f64,
    after_m: f64,
    max_m: f64,
}

fn run(name: &str, seed: u64) -> (Setup, RunOutput, Figures) {
    let (setup, mut rng) = prepare_seed(name, seed);
    let out = runner::run(&setup, &mut rng);
    assert_eq!(
        out.end,
        RunEnd::Duration,
        "{name} seed {seed}: {:?}",
        out.end
    );
    let summary = summarize(&setup, &out);
    let y0 = out.trace[0].lateral_error_m;
    let side = if y0 < 0.0 { -1.0 } else { 1.0 };
    let figures = Figures {
        converged_m: summary.converged_after_m.unwrap_or(f64::INFINITY),
        overshoot_m: out
            .trace
            .iter()
            .map(|r| -side * r.lateral_error_m)
            .fold(0.0, f64::max),
        after_m: summary
            .lateral_error_after_convergence_m
            .map_or(f64::INFINITY, |e| e.max_abs),
        max_m: summary.lateral_error_m.max_abs,
    };
    (setup, out, figures)
}

/// The worst figures of `name` over the seeds.
fn sweep(name: &str) -> Figures {
    let mut worst = Figures {
        converged_m: 0.0,
        overshoot_m: 0.0,
        after_m: 0.0,
        max_m: 0.0,
    };
    for seed in SEEDS {
        let (_, _, f) = run(name, seed);
        worst.converged_m = worst.converged_m.max(f.converged_m);
        worst.overshoot_m = worst.overshoot_m.max(f.overshoot_m);
        worst.after_m = worst.after_m.max(f.after_m);
        worst.max_m = worst.max_m.max(f.max_m);
    }
    eprintln!("{name}: worst over {} seeds {worst:?}", SEEDS.len());
    worst
}

/// The time the linearised scheduled loop (a critically damped pair at
/// Ω / 2, PT-SPEED-RANGE) needs to bring (y0, ẏ0) within the band for good.
fn linear_time_s(y0: f64, y_dot0: f64, bandwidth: f64) -> f64 {
    let p = bandwidth / 2.0;
    let y = |t: f64| (y0 + (y_dot0 + p * y0) * t).abs() * (-p * t).exp();
    let mut t = 60.0;
    while t > 0.0 && y(t) < BAND_M {
        t -= 1e-3;
    }
    t
}

/// The convergence distance PT-SPEED-RANGE allows from (y0, θ0) at `v`:
/// 10 m or 5 s of travel, or 1.3 times the linearised loop's time at the
/// schedule's bandwidth, whichever is longest.
fn allowed_m(v: f64, y0: f64, theta0: f64, bandwidth: f64) -> f64 {
    let linear = linear_time_s(y0.abs(), v * theta0.sin() * y0.signum(), bandwidth);
    10.0_f64.max(5.0 * v).max(1.3 * v * linear)
}

/// Sweeps one straight-line scenario and checks PT-SPEED-RANGE's bounds,
/// the overshoot below `overshoot` times |y0|.
fn straight(name: &str, y0: f64, theta0_deg: f64, overshoot: f64) {
    let (setup, _, _) = run(name, 2022);
    let v = setup.control.speed.get();
    let schedule = setup.control.backstepping.schedule.unwrap();
    let allowed = allowed_m(v, y0, theta0_deg.to_radians(), schedule.bandwidth().get());
    let w = sweep(name);
    eprintln!("{name}: allowed {allowed:.2} m");
    assert!(w.converged_m <= allowed, "{name}: {w:?}, allowed {allowed}");
    assert!(w.overshoot_m < overshoot * y0.abs(), "{name}: {w:?}");
    assert!(w.after_m < BAND_M, "{name}: {w:?}");
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
    for v in ["0_3", "1", "2", "3"] {
        straight(&format!("tracking-v{v}-offset"), -0.8, 0.0, 0.1);
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
fn converges_from_1_5_m_and_20_degrees_at_every_speed() {
    for v in ["0_3", "1", "2", "3"] {
        straight(&format!("tracking-v{v}-heading"), -1.5, -20.0, 0.12);
    }
}

/// What the feedback may add to the drift a step allows (PT-SPEED-RANGE).
const MARGIN: f64 = 1.25;

/// The lateral offset a curvature step Δκ leaves when the steering follows
/// it at its rate limit in a ramp centred on the step (PT-SPEED-RANGE):
/// Δκ d² / 24 over the ramp's length d = Δκ L v / R.
fn ramp_offset_m(delta_kappa: f64, v: f64) -> f64 {
    let d = delta_kappa * WHEELBASE_M * v / RATE;
    delta_kappa * d * d / 24.0
}

//= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
//= type=test
//# Started on the path, |y| MUST stay below the larger of 0.05 m and 1.25
//# times the offset Δκ d² / 24 of a rate-limited ramp through each curvature
//# step Δκ, and below the larger of 0.05 m and 1.25 times the drift of a
//# sideslip step.
#[test]
fn stays_in_the_band_through_s_bends_and_a_u_turn() {
    // The S-bend's curvature jumps by 2 / 8 1/m; the U-turn's by 1 / 4.5.
    for (name, v, step) in [
        ("tracking-sbend-v1_5", 1.5, 0.25),
        ("tracking-sbend-v3", 3.0, 0.25),
        ("tracking-uturn", 1.5, 1.0 / 4.5),
    ] {
        let bound = BAND_M.max(MARGIN * ramp_offset_m(step, v));
        let w = sweep(name);
        eprintln!("{name}: bound {bound:.3} m");
        assert!(w.max_m < bound, "{name}: {w:?}, bound {bound}");
    }
}

/// The lateral drift of a step Δβ of the rear sideslip at speed v (PT-SPEED-RANGE):
/// the heading must turn by Δβ, which at the steering's rate limit takes
/// t = 2 √(Δβ L / (R v)), drifting v Δβ t / 2 meanwhile; the observer's lag
/// τ_o adds v Δβ τ_o.
fn slip_drift_m(delta_beta: f64, v: f64, observer_tau_s: f64) -> f64 {
    let turn_s = 2.0 * (delta_beta * WHEELBASE_M / (RATE * v)).sqrt();
    v * delta_beta * (turn_s / 2.0 + observer_tau_s)
}

//= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
//= type=test
//# Started on the path, |y| MUST stay below the larger of 0.05 m and 1.25
//# times the offset Δκ d² / 24 of a rate-limited ramp through each curvature
//# step Δκ, and below the larger of 0.05 m and 1.25 times the drift of a
//# sideslip step.
#[test]
fn slip_steps_give_at_most_the_drift_the_steering_allows() {
    let (setup, _, _) = run("tracking-slip", 2022);
    let v = setup.control.speed.get();
    // β_R steps by 6°; the observer settles (5 %) in 0.5 s: τ_o = 0.5 / 3.
    let bound = BAND_M.max(MARGIN * slip_drift_m(6.0_f64.to_radians(), v, 0.5 / 3.0));
    let w = sweep("tracking-slip");
    eprintln!("tracking-slip: bound {bound:.3} m");
    assert!(w.max_m < bound, "{w:?}, bound {bound}");
}

//= spec/pierre2022.md#pt-feedforward-lag-feed-forward-timed-for-the-steering-lag
//= type=test
//# The curvature MUST be fed forward at s + v (T + τ), with T the
//# prediction horizon and τ ≥ 0 the steering's configured time constant.
#[test]
fn a_slow_steering_converges_and_holds_the_straights() {
    let name = "tracking-lag-2s";
    let (setup, _, _) = run(name, 2022);
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
    let within_m = allowed_m(v, -0.8, 0.0, bandwidth);
    // The first straight ends at s = 40 m, where the S-bend starts.
    let mut worst_curve: f64 = 0.0;
    let mut worst_settled: f64 = 0.0;
    for seed in SEEDS {
        let (_, out, _) = run(name, seed);
        let settled = out
            .trace
            .iter()
            .filter(|r| r.s_m < 40.0 && r.lateral_error_m.abs() >= BAND_M)
            .map(|r| r.distance_m)
            .fold(0.0, f64::max);
        assert!(settled <= within_m, "seed {seed}: settled at {settled} m");
        worst_settled = worst_settled.max(settled);
        let curve = out
            .trace
            .iter()
            .filter(|r| r.s_m >= 40.0)
            .map(|r| r.lateral_error_m.abs())
            .fold(0.0, f64::max);
        worst_curve = worst_curve.max(curve);
    }
    eprintln!(
        "{name}: settled after {worst_settled:.2} m (allowed {within_m:.2} m), worst |y| \
         from the S-bend on {worst_curve:.3} m"
    );
    // Measured, not derived: with the lag the S-bend reaches 0.14 m (PT-SPEED-RANGE).
    assert!(worst_curve < 0.15, "{worst_curve}");
}
