//! Holding an estimate through what the sensors lose, on synthetic scans
//! (`spec/guidance.md`): regular gaps bridged by the active behaviour's held
//! line (GD-BRIDGE), and the wheels steered at standstill before moving
//! after a Stop (GD-RESUME).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp,
    clippy::cast_precision_loss
)]

use core::f64::consts::{FRAC_PI_6, PI, TAU};

mod common;

use common::edge_scan;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::guidance::{Guidance, GuidanceConfig, Mode, RoutedScan, TickInput, TickOutput};
use fieldguide::model::bicycle::{Bicycle, Sideslip, SteeringLimit, Wheelbase};
use fieldguide::model::Vehicle;
use fieldguide::perception::edge::Side;
use fieldguide::perception::RangeLimits;
use fieldguide::presets::{pierre2022_edge, Pierre2022, Pierre2022Params, EDGE};
use fieldguide::{
    Meters, Odom, Point2, Pose2, RadiansPerSecond, Robot, Seconds, Sensor, Transform2, Verdict,
    World,
};

const PATH_N: usize = 256;
const MOUNT_X: f64 = 1.2;
const RAYS: usize = 360;
/// Edge following's 0.4 m/s at 100 Hz.
const STEP_M: f64 = 0.004;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn straight_path() -> ReferencePath<PATH_N> {
    let points: Vec<Point2<World>> = (0..=64)
        .map(|i| Point2::new(-20.0 + 5.0 * f64::from(i), 0.0).unwrap())
        .collect();
    ReferencePath::from_waypoints(&points, PathConfig::default()).unwrap()
}

fn params() -> Pierre2022Params {
    let mount: Transform2<Sensor, Robot> = Transform2::new(MOUNT_X, 0.0, 0.0).unwrap();
    pierre2022_edge(Side::Left, mount).unwrap()
}

fn pipeline<'p>(p: &Pierre2022Params, path: &'p ReferencePath<PATH_N>) -> Pierre2022<'p, PATH_N> {
    Guidance::new(GuidanceConfig::new(p).unwrap(), path).unwrap()
}

/// Exact ranges from the LiDAR of a robot at (x, 0, 0) to a wall along x
/// at y = 1.5 m, present where `present(x)` holds.
fn wall_ranges(x: f64, present: impl Fn(f64) -> bool) -> Vec<f64> {
    (0..RAYS)
        .map(|k| {
            let a = -PI + TAU * k as f64 / RAYS as f64;
            let (c, s) = (a.cos(), a.sin());
            if s.abs() < 1e-9 {
                return f64::INFINITY;
            }
            let t = 1.5 / s;
            let hit = x + MOUNT_X + t * c;
            if t > 0.0 && t <= 30.0 && present(hit) {
                t
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

fn tick<'a>(x: f64, scans: &'a [RoutedScan<'a>], gnss: bool) -> TickInput<'a, Sideslip> {
    TickInput {
        scans,
        gnss: gnss.then(|| Pose2::<World>::new(x, 0.0, 0.0).unwrap()),
        odometry: Pose2::<Odom>::new(x, 0.0, 0.0).unwrap(),
        extra: Sideslip::ZERO,
    }
}

/// Drives along x at 0.4 m/s beside a wall present where `present` holds,
/// scanning every 10th tick, for `ticks` ticks from x = 0.
fn drive(
    g: &mut Pierre2022<'_, PATH_N>,
    ticks: usize,
    present: impl Fn(f64) -> bool + Copy,
) -> Vec<(f64, TickOutput<Sideslip, 2>)> {
    let limits = RangeLimits::new(m(0.05), m(30.0)).unwrap();
    (0..ticks)
        .map(|k| {
            let x = STEP_M * k as f64;
            let ranges = wall_ranges(x, present);
            let scans = [edge_scan(&ranges, limits)];
            let scans: &[RoutedScan<'_>] = if k % 10 == 0 { &scans } else { &[] };
            (x, g.step(&tick(x, scans, true)).unwrap())
        })
        .collect()
}

/// A wall that ends at x = 4 m (entered long before): the robot's LiDAR
/// loses it as it passes the end.
fn ends_at_4(x: f64) -> bool {
    x < 4.0
}

//= spec/guidance.md#gd-bridge-regular-gaps-bridged-by-the-held-line
//= type=test
//# When a bridge length is configured, a tick in which the behaviour of the
//# active specialised mode has no valid estimate MUST report Hold with the
//# tracking error of that behaviour's latest scan with an Enter or Hold verdict,
//# moved to the current pose through odometry as the error to a straight line
//# (GD-ODOMETRY), as long as the odometry distance summed over the ticks since
//# that scan is at most the bridge length and no scan of that behaviour was
//# refused since; otherwise, and for a behaviour that is not active, the
//# estimate MUST be that of GD-SCAN-AGE.
#[test]
fn a_gap_shorter_than_the_bridge_is_held_and_a_longer_one_is_left() {
    let path = straight_path();
    let bridge = 1.0;
    let mut p = params();
    p.bridge = Some(m(bridge));
    let mut bridged = pipeline(&p, &path);
    let mut plain = pipeline(&params(), &path);
    // 2000 ticks: 8 m, the wall's end at 4 m.
    let with = drive(&mut bridged, 2000, ends_at_4);
    let without = drive(&mut plain, 2000, ends_at_4);
    // Both enter edge following beside the wall, on the same ticks.
    let entered = with
        .iter()
        .position(|(_, o)| o.mode == Mode::Behaviour(EDGE))
        .unwrap();
    assert_eq!(
        entered,
        without
            .iter()
            .position(|(_, o)| o.mode == Mode::Behaviour(EDGE))
            .unwrap()
    );
    // The first scan that finds no edge (the scans are the same in both
    // runs: the robot drives the same poses), and the last valid scan before it.
    let lost = without
        .iter()
        .position(|(x, o)| {
            *x > 1.0
                && o.behaviours[0].scan_age == Some(0)
                && !o.behaviours[0].detected.estimate_is_valid()
        })
        .unwrap();
    // The wall's end: a chain too short (Exit), then nothing (Absent).
    assert_eq!(without[lost].1.behaviours[0].detected, Verdict::Exit);
    assert!(without
        .iter()
        .any(|(_, o)| o.behaviours[0].detected == Verdict::Absent));
    let last_valid = (0..lost)
        .rev()
        .find(|&k| with[k].1.behaviours[0].scan_age == Some(0))
        .unwrap();
    let x_valid = with[last_valid].0;
    let line_error = with[last_valid].1.behaviours[0].error.unwrap();
    for (k, (x, o)) in with.iter().enumerate().skip(lost) {
        let b = &o.behaviours[0];
        let carried = x - x_valid;
        if carried <= bridge - 1e-9 {
            // Bridged: Hold, steering on the held line moved by odometry (a
            // straight drive along a parallel line keeps its error).
            assert_eq!(b.detected, Verdict::Hold, "tick {k}");
            assert_eq!(b.reported, Verdict::Hold);
            assert_eq!(o.mode, Mode::Behaviour(EDGE));
            assert_eq!(o.source, Some(Mode::Behaviour(EDGE)));
            assert!(
                (b.bridged.unwrap().get() - carried).abs() < 1e-9,
                "tick {k}"
            );
            let e = b.error.unwrap();
            assert!((e.y.get() - line_error.y.get()).abs() < 1e-9);
            assert!((e.angular_deviation.get() - line_error.angular_deviation.get()).abs() < 1e-9);
        } else if carried > bridge + 1e-9 {
            // Beyond the bridge: the detector's verdict, then the exit.
            assert!(!b.detected.estimate_is_valid(), "tick {k}");
            assert_eq!(b.bridged, None);
            assert_ne!(o.source, Some(Mode::Behaviour(EDGE)), "tick {k}");
        }
    }
    // Left 0.26 s (26 ticks) after the bridge ends.
    let end = with
        .iter()
        .position(|(x, _)| x - x_valid > bridge + 1e-9)
        .unwrap();
    let left = with
        .iter()
        .skip(lost)
        .position(|(_, o)| o.mode == Mode::PathTracking)
        .unwrap()
        + lost;
    assert_eq!(left, end + 25);
    // Without the bridge, path tracking steers from the first Absent scan on
    // and the mode is left 26 ticks later.
    assert_eq!(without[lost].1.source, Some(Mode::PathTracking));
    assert_eq!(without[lost].1.behaviours[0].bridged, None);
    let left_plain = without
        .iter()
        .position(|(x, o)| *x > 1.0 && o.mode == Mode::PathTracking)
        .unwrap();
    assert_eq!(left_plain, lost + 25);
}

/// Only the active behaviour bridges: in path tracking, an edge seen and
/// lost stays lost (entering still needs Enter verdicts).
#[test]
fn a_behaviour_that_is_not_active_is_not_bridged() {
    let path = straight_path();
    let mut p = params();
    p.bridge = Some(m(5.0));
    // Never entered: a 100 s entry delay.
    p.behaviours[0].enter_delay = Seconds::new(100.0).unwrap();
    let mut g = pipeline(&p, &path);
    let outs = drive(&mut g, 2000, ends_at_4);
    let first_absent = outs
        .iter()
        .position(|(x, o)| *x > 1.0 && o.behaviours[0].detected == Verdict::Absent)
        .unwrap();
    for (_, o) in &outs[first_absent..] {
        assert_eq!(o.mode, Mode::PathTracking);
        assert_eq!(o.behaviours[0].bridged, None);
        assert_ne!(o.behaviours[0].detected, Verdict::Hold);
    }
}

//= spec/guidance.md#gd-bridge-regular-gaps-bridged-by-the-held-line
//= type=test
//# A bridge length that is not positive MUST be refused with `GD-BRIDGE`.
//= spec/guidance.md#gd-resume-steering-before-moving-after-a-stop
//= type=test
//# A configuration whose 3 τ is longer than 65 535 ticks MUST be refused with
//# `GD-RESUME`.
#[test]
fn a_bad_bridge_or_settling_time_is_refused() {
    for bad in [0.0, -1.0] {
        let mut p = params();
        p.bridge = Some(m(bad));
        assert_eq!(
            GuidanceConfig::new(&p).unwrap_err().requirement,
            "GD-BRIDGE"
        );
    }
    let mut p = params();
    // 3 τ = 655.36 s is 65 536 ticks of 0.01 s; 655.35 s still fits.
    p.path.steering_lag = Seconds::new(655.36 / 3.0).unwrap();
    assert_eq!(
        GuidanceConfig::new(&p).unwrap_err().requirement,
        "GD-RESUME"
    );
    p.path.steering_lag = Seconds::new(655.3 / 3.0).unwrap();
    let config = GuidanceConfig::new(&p).unwrap();
    assert_eq!(config.settle_ticks(), 65_530);
    assert_eq!(GuidanceConfig::new(&params()).unwrap().settle_ticks(), 0);
}

/// A behaviour selected after a Stop commands at once: the robot stopped
/// without a fix beside no wall, its wheels held; a wall 1.5 m to its left
/// appears and edge following, entered at standstill, steers towards its
/// line (0.1 m off the 1.4 m offset) and moves in the same tick, where path
/// tracking would have turned the wheels first.
#[test]
fn after_a_stop_a_behaviour_commands_at_once() {
    let p = rate_limited(params(), 0.1);
    let path = straight_path();
    let mut g = pipeline(&p, &path);
    let limits = RangeLimits::new(m(0.05), m(30.0)).unwrap();
    let mut held = None;
    for _ in 0..10 {
        let out = g.step(&tick(0.0, &[], true)).unwrap();
        held = out.command.and_then(|c| c.command.steering());
    }
    for _ in 0..60 {
        g.step(&tick(0.0, &[], false)).unwrap();
    }
    assert_eq!(g.mode(), Mode::Stop);
    let held = held.unwrap().get();
    let ranges = wall_ranges(0.0, |_| true);
    let scans = [edge_scan(&ranges, limits)];
    for k in 0..2000 {
        let scans: &[RoutedScan<'_>] = if k % 10 == 0 { &scans } else { &[] };
        let out = g.step(&tick(0.0, scans, false)).unwrap();
        if out.mode == Mode::Stop {
            continue;
        }
        assert_eq!(out.source, Some(Mode::Behaviour(EDGE)));
        let c = out.command.unwrap().command;
        let steering = c.steering().unwrap().get();
        assert!(
            (steering - held).abs() > PI / 6.0 * 0.01,
            "{held} {steering}"
        );
        assert!(c.speed().get() > 0.0, "{c:?}");
        return;
    }
    panic!("edge following never entered");
}

/// The preset's tractor with a 30°/s steering rate limit.
fn rate_limited(mut p: Pierre2022Params, tau: f64) -> Pierre2022Params {
    p.vehicle = Vehicle::Bicycle(
        Bicycle::new(
            Wheelbase::new(2.0).unwrap(),
            SteeringLimit::new(FRAC_PI_6).unwrap(),
            Some(RadiansPerSecond::new(PI / 6.0).unwrap()),
        )
        .unwrap(),
    );
    p.path.steering_lag = Seconds::new(tau).unwrap();
    p.steer_before_resuming = true;
    p
}

/// Ticks until the speed is no longer zero after a Stop, with the held and
/// the first commanded steering angles, on a robot that stopped 5 cm left of
/// a straight path heading along it and whose fix returns 0.4 m right of it
/// (a jump: the path-tracking command wants another angle than the held one).
fn resume(p: &Pierre2022Params) -> (usize, f64, f64) {
    let path = straight_path();
    let mut g = pipeline(p, &path);
    let at = |y: f64, gnss: bool| TickInput {
        scans: &[],
        gnss: gnss.then(|| Pose2::<World>::new(2.0, y, 0.0).unwrap()),
        odometry: Pose2::<Odom>::new(2.0, y, 0.0).unwrap(),
        extra: Sideslip::ZERO,
    };
    let mut held = 0.0;
    for _ in 0..10 {
        let out = g.step(&at(0.05, true)).unwrap();
        held = out
            .command
            .unwrap_or_else(|| panic!("{:?}", out.path))
            .command
            .steering()
            .unwrap()
            .get();
    }
    for _ in 0..60 {
        g.step(&at(0.05, false)).unwrap();
    }
    assert_eq!(g.mode(), Mode::Stop);
    for k in 0..1000 {
        let out = g.step(&at(-0.4, true)).unwrap();
        assert_eq!(out.mode, Mode::PathTracking);
        let c = out.command.unwrap().command;
        // The source's own steering angle, from the first tick.
        assert_eq!(
            c.steering(),
            out.path.law.command().unwrap().command.steering()
        );
        if c.speed().get() > 0.0 {
            return (k, held, c.steering().unwrap().get());
        }
    }
    panic!("never moved");
}

//= spec/guidance.md#gd-resume-steering-before-moving-after-a-stop
//= type=test
//# When steering before resuming is configured and the vehicle is a bicycle
//# with a known steering rate limit, the commands of path tracking after a Stop
//# MUST keep the speed zero, with path tracking's steering angle, while an angle
//# moved from the held one towards each tick's commanded angle by the rate
//# limit times the period per tick is farther than that step from the
//# commanded angle, and for ⌈3 τ / period⌉ ticks more; the next command, and
//# every command of a behaviour, MUST be the source's as it is.
#[test]
fn after_a_stop_the_wheels_turn_at_standstill_first() {
    let step = PI / 6.0 * 0.01;
    // Zero speed while more than a step away: ⌈gap / step⌉ − 1 ticks; with
    // τ = 0.1 s, 30 ticks more to settle.
    for (tau, settle) in [(0.0, 0), (0.1, 30)] {
        let (ticks, held, target) = resume(&rate_limited(params(), tau));
        let gap = (target - held).abs();
        assert!(gap > 0.2, "{held} {target}");
        assert_eq!(ticks, (gap / step).ceil() as usize - 1 + settle, "{gap}");
    }
    // Not configured, or without a known rate limit: moving at once.
    let mut off = rate_limited(params(), 0.1);
    off.steer_before_resuming = false;
    assert_eq!(resume(&off).0, 0);
    let mut unknown = params();
    unknown.steer_before_resuming = true;
    assert_eq!(resume(&unknown).0, 0);
}
