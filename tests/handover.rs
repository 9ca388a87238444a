//! Hand-overs without a jolt (`spec/guidance.md`, GD-HANDOVER) on the whole
//! pipeline: edge following along a wall 0.3 m beside its offset line on the
//! path, the wall ending; path tracking takes over on the line's offset,
//! holds it for the hold distance, then brings it to the path at the slope;
//! the rule's functions alone; the furrow window's lateral reach (FUR-REACH);
//! a line seen while path tracking steers on the carried pose, placed on the
//! path by that pose (GD-FIX-QUALITY).
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

use core::f64::consts::{PI, TAU};

mod common;

use common::{edge_scan, fix_rule, m, straight_path, PATH_N};
use fieldguide::guidance::{
    EntryParams, FixKind, FixQuality, FixUse, Guidance, GuidanceConfig, Handover, HandoverParams,
    Mode, TickInput, TickOutput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::edge::Side;
use fieldguide::perception::furrow::{FurrowConfig, FurrowParams};
use fieldguide::perception::RangeLimits;
use fieldguide::presets::{pierre2022_edge, Pierre2022, Pierre2022Params, EDGE};
use fieldguide::{Curvature, TrackingError};
use fieldguide::{Meters, Odom, Pose2, Radians, Robot, Sensor, Transform2, World};

const MOUNT_X: f64 = 1.2;
const RAYS: usize = 360;
/// The wall's near face: the edge line (1.4 m to its right) lies 0.3 m left of the path.
const WALL_Y: f64 = 1.7;
const WALL_END: f64 = 20.0;
const LINE_OFFSET: f64 = 0.3;

fn mount() -> Transform2<Sensor, Robot> {
    Transform2::new(MOUNT_X, 0.0, 0.0).unwrap()
}

/// Exact ranges to the wall (y = `WALL_Y`, x ≤ `WALL_END`) from the robot at `pose`.
fn ranges(pose: (f64, f64, f64)) -> Vec<f64> {
    wall_ranges(pose, f64::NEG_INFINITY)
}

/// Exact ranges to the wall (y = `WALL_Y`, `from` ≤ x ≤ `WALL_END`) from the robot at `pose`.
fn wall_ranges(pose: (f64, f64, f64), from: f64) -> Vec<f64> {
    let (x, y, psi) = pose;
    let (sx, sy) = (x + MOUNT_X * psi.cos(), y + MOUNT_X * psi.sin());
    (0..RAYS)
        .map(|k| {
            let a = psi - PI + TAU * k as f64 / RAYS as f64;
            let (c, s) = (a.cos(), a.sin());
            let t = if s.abs() < 1e-9 {
                f64::INFINITY
            } else {
                (WALL_Y - sy) / s
            };
            let hit = sx + t * c;
            if t > 0.0 && t <= 30.0 && hit >= from && hit <= WALL_END {
                t
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

fn params(handover: Option<HandoverParams>) -> Pierre2022Params {
    let mut p = pierre2022_edge(Side::Left, mount()).unwrap();
    p.handover = handover;
    p
}

/// Drives straight along the edge's offset line (y = 0.3 m) from x = 0 to
/// `to`, 8 mm per tick, a scan every tenth tick; the output of every tick,
/// with the x it was taken at.
fn drive(g: &mut Pierre2022<'_, PATH_N>, to: f64) -> Vec<(f64, TickOutput<Sideslip, 2>)> {
    drive_drifting(g, to, &|_| 0.0)
}

/// As [`drive`], the fix `drift(x)` north of the true pose.
fn drive_drifting(
    g: &mut Pierre2022<'_, PATH_N>,
    to: f64,
    drift: &dyn Fn(f64) -> f64,
) -> Vec<(f64, TickOutput<Sideslip, 2>)> {
    let mut outs = Vec::new();
    let mut k = 0_u32;
    loop {
        let x = 0.008 * f64::from(k);
        if x > to {
            return outs;
        }
        let pose = (x, LINE_OFFSET, 0.0);
        let r = ranges(pose);
        let scan = [edge_scan(&r, RangeLimits::new(m(0.05), m(30.0)).unwrap())];
        let out = g
            .step(&TickInput {
                scans: if k % 10 == 0 { &scan } else { &[] },
                gnss: Some(Pose2::<World>::new(pose.0, pose.1 + drift(x), pose.2).unwrap()),
                odometry: Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap(),
                extra: Sideslip::ZERO,
            })
            .unwrap();
        outs.push((x, out));
        k += 1;
    }
}

//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# When a hand-over rule is configured and the machine leaves a behaviour, a
//# hand-over MUST start from the offset from the path of that behaviour's line
//# in the last tick the behaviour commanded; it MUST end when the shift reaches
//# zero, when a behaviour is entered or when the path is replaced.
//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# During a hand-over, path tracking's error MUST be the error to the path
//# shifted sideways by the hand-over's shift: the lateral error less the
//# shift, the angular deviation less the angle of the shift's change per metre
//# travelled, and the curvatures c / (1 − o c) of the shifted path.
#[test]
fn path_tracking_takes_over_on_the_line_then_blends_to_the_path() {
    let path = straight_path(-20.0, 300.0);
    let rule = HandoverParams {
        hold: m(4.0),
        slope: 0.1,
        averaging: m(1.0),
        line_hold: None,
    };
    let mut g: Pierre2022<'_, PATH_N> =
        Guidance::new(GuidanceConfig::new(&params(Some(rule))).unwrap(), &path).unwrap();
    let outs = drive(&mut g, 40.0);
    // Edge following steers beside the wall, then hands back after its end.
    let last_edge = outs
        .iter()
        .rposition(|(_, o)| o.mode == Mode::Behaviour(EDGE))
        .expect("edge following entered");
    let (x0, _) = outs[last_edge + 1];
    assert!(x0 > 10.0 && x0 < WALL_END + 3.0, "handed back at {x0}");
    let offset = outs[last_edge]
        .1
        .behaviour(EDGE)
        .unwrap()
        .plan
        .unwrap()
        .offset;
    assert!((offset.get() - LINE_OFFSET).abs() < 0.05, "{offset:?}");
    for (x, out) in &outs[last_edge + 1..] {
        assert_eq!(out.mode, Mode::PathTracking, "x = {x}");
        let d = x - x0;
        let shift = out.path.reference_offset.map_or(0.0, Meters::get);
        let expected = if d <= 4.0 - 1e-9 {
            offset.get()
        } else {
            (offset.get() - 0.1 * (d - 4.0)).max(0.0)
        };
        assert!(
            (shift - expected).abs() < 1e-6,
            "x = {x}: {shift} != {expected}"
        );
        // The law's error is to the shifted path: at the line the robot
        // drives on, 0 during the hold.
        let frenet = out.path.frenet.unwrap();
        if d < 4.0 {
            assert!((frenet.y.get() - shift - (LINE_OFFSET - offset.get())).abs() < 1e-9);
            let c = out.command.unwrap().command.steering().unwrap().get();
            assert!(c.abs() < 0.05, "x = {x}: steering {c}");
        }
    }
    // Over: the shift reached zero after 4 m + offset / slope, and stays unset.
    let (x_end, last) = outs.last().unwrap();
    assert!(x_end - x0 > 4.0 + offset.get() / 0.1 + 0.1);
    assert_eq!(last.path.reference_offset, None);
    // Without the rule, the first tick of path tracking steers hard to the path.
    let mut plain: Pierre2022<'_, PATH_N> =
        Guidance::new(GuidanceConfig::new(&params(None)).unwrap(), &path).unwrap();
    let outs = drive(&mut plain, 25.0);
    let first_pt = outs
        .iter()
        .position(|(x, o)| *x > 10.0 && o.mode == Mode::PathTracking)
        .unwrap();
    let c = outs[first_pt]
        .1
        .command
        .unwrap()
        .command
        .steering()
        .unwrap()
        .get();
    assert!(c < -0.1, "steering {c}");
    assert_eq!(outs[first_pt].1.path.reference_offset, None);
}

/// The index of the last tick edge following was the mode in.
fn last_edge(outs: &[(f64, TickOutput<Sideslip, 2>)]) -> usize {
    outs.iter()
        .rposition(|(_, o)| o.mode == Mode::Behaviour(EDGE))
        .expect("edge following entered")
}

//= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
//= type=test
//# While the odometry distance since a hand-over that started on leaving a
//# behaviour is at most the line hold, path tracking's error MUST be the error
//# to that behaviour's line in the last tick it commanded, moved to the current
//# pose through odometry as GD-ODOMETRY moves a straight line, whatever the
//# fix, unless an entry (GD-ENTRY) shifts the reference.
//= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
//= type=test
//# In each such tick in which the path has a projection, the hand-over's shift
//# MUST be re-evaluated as that carried line's offset from the path.
//= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
//= type=test
//# With a line hold, the shift MUST be held while the odometry distance since
//# the hand-over is at most the longer of the hold distance and the line hold.
#[test]
fn the_line_hold_follows_the_last_line_whatever_the_fix_does() {
    let path = straight_path(-20.0, 300.0);
    let rule = |line_hold: Option<f64>| HandoverParams {
        hold: m(2.0),
        slope: 0.1,
        averaging: m(1.0),
        line_hold: line_hold.map(m),
    };
    // Where edge following hands over with an exact fix.
    let mut g: Pierre2022<'_, PATH_N> = Guidance::new(
        GuidanceConfig::new(&params(Some(rule(None)))).unwrap(),
        &path,
    )
    .unwrap();
    let outs = drive(&mut g, 30.0);
    let x0 = outs[last_edge(&outs) + 1].0;
    // From there the fix drifts north by 0.05 m per metre.
    let drift = move |x: f64| 0.05 * (x - x0).max(0.0);
    let mut largest = [0.0_f64; 2];
    for (j, line_hold) in [Some(3.0), None].into_iter().enumerate() {
        let mut g: Pierre2022<'_, PATH_N> = Guidance::new(
            GuidanceConfig::new(&params(Some(rule(line_hold)))).unwrap(),
            &path,
        )
        .unwrap();
        let outs = drive_drifting(&mut g, 30.0, &drift);
        let last = last_edge(&outs);
        assert_eq!(outs[last + 1].0, x0);
        let offset = outs[last].1.behaviour(EDGE).unwrap().plan.unwrap().offset;
        let mut end_of_hold = None;
        for (x, out) in &outs[last + 1..] {
            let d = x - x0;
            let shift = out.path.reference_offset.map_or(0.0, Meters::get);
            let steering = out.command.unwrap().command.steering().unwrap().get();
            if d < 3.0 - 1e-9 {
                largest[j] = largest[j].max(steering.abs());
            }
            match line_hold {
                Some(hold) if d <= hold + 1e-9 => {
                    // The line as the drifting fix places it.
                    assert!(
                        (shift - offset.get() - drift(*x)).abs() < 1e-6,
                        "d {d}: {shift} vs {offset:?}"
                    );
                    end_of_hold = Some(shift);
                }
                Some(hold) => {
                    // Held to 3 m (longer than the hold, 2 m), then the slope
                    // from the line's last offset.
                    let start = end_of_hold.unwrap();
                    let expected = (start - 0.1 * (d - hold)).max(0.0);
                    assert!(
                        (shift - expected).abs() < 1e-6,
                        "d {d}: {shift} vs {expected}"
                    );
                }
                None => {
                    let expected = (offset.get() - 0.1 * (d - 2.0).max(0.0)).max(0.0);
                    assert!(
                        (shift - expected).abs() < 1e-6,
                        "d {d}: {shift} vs {expected}"
                    );
                }
            }
        }
    }
    // On the line, path tracking holds the wheels straight; on the shifted
    // path the drift steers them off.
    eprintln!(
        "largest steering over 3 m: with the line hold {:.4} rad, without {:.4} rad",
        largest[0], largest[1]
    );
    assert!(largest[0] < 0.02, "{largest:?}");
    assert!(
        largest[1] > 5.0 * largest[0] && largest[1] > 0.05,
        "{largest:?}"
    );
}

//= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
//= type=test
//# A hand-over rule whose line hold is given and not positive MUST be refused
//# with `GD-HANDOVER-LINE`.
#[test]
fn a_line_hold_not_positive_is_refused() {
    for length in [0.0, -3.0] {
        let p = HandoverParams {
            hold: m(4.0),
            slope: 0.1,
            averaging: m(1.0),
            line_hold: Some(m(length)),
        };
        assert_eq!(
            Handover::new(&p).unwrap_err().requirement,
            "GD-HANDOVER-LINE"
        );
        let config = GuidanceConfig::new(&params(Some(p)));
        assert_eq!(config.unwrap_err().requirement, "GD-HANDOVER-LINE");
    }
}

#[test]
fn a_replaced_path_ends_the_hand_over() {
    let path = straight_path(-20.0, 300.0);
    let rule = HandoverParams {
        hold: m(50.0),
        slope: 0.1,
        averaging: m(1.0),
        line_hold: None,
    };
    let mut g: Pierre2022<'_, PATH_N> =
        Guidance::new(GuidanceConfig::new(&params(Some(rule))).unwrap(), &path).unwrap();
    let outs = drive(&mut g, 25.0);
    assert!(outs.last().unwrap().1.path.reference_offset.is_some());
    let other = straight_path(-20.0, 300.0);
    g.set_path(&other);
    let out = g
        .step(&TickInput {
            scans: &[],
            gnss: Some(Pose2::<World>::new(25.0, LINE_OFFSET, 0.0).unwrap()),
            odometry: Pose2::<Odom>::new(25.0, LINE_OFFSET, 0.0).unwrap(),
            extra: Sideslip::ZERO,
        })
        .unwrap();
    assert_eq!(out.path.reference_offset, None);
}

// ---------------------------------------------------------------- the rule alone

fn rule(hold: f64, slope: f64) -> Handover {
    Handover::new(&HandoverParams {
        hold: m(hold),
        slope,
        averaging: m(1.0),
        line_hold: None,
    })
    .unwrap()
}

//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# A hand-over rule whose hold distance is negative, whose averaging length is
//# not positive or whose slope is not in (0, 1] MUST be refused with
//# `GD-HANDOVER`.
#[test]
fn bad_rules_are_refused() {
    for (hold, slope, averaging) in [
        (-0.1, 0.1, 1.0),
        (1.0, 0.0, 1.0),
        (1.0, -0.1, 1.0),
        (1.0, 1.01, 1.0),
        (1.0, f64::NAN, 1.0),
        (1.0, f64::INFINITY, 1.0),
        (1.0, 0.1, 0.0),
        (1.0, 0.1, -1.0),
    ] {
        let e = Handover::new(&HandoverParams {
            hold: m(hold),
            slope,
            averaging: m(averaging),
            line_hold: None,
        })
        .unwrap_err();
        assert_eq!(e.requirement, "GD-HANDOVER");
    }
    assert!(Handover::new(&HandoverParams {
        hold: m(0.0),
        slope: 1.0,
        averaging: m(1e-9),
        line_hold: None,
    })
    .is_ok());
}

//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# The shift MUST equal the line's offset from the path while the odometry
//# distance since the hand-over is at most the hold distance, and MUST then
//# shrink toward zero by the slope times the distance past the hold, never
//# changing sign.
#[test]
fn the_shift_is_held_then_shrinks_at_the_slope() {
    let h = rule(5.0, 0.1);
    for d in [-1.0, 0.0, 2.5, 5.0] {
        assert_eq!(h.offset(m(0.45), m(d)).get(), 0.45);
        assert_eq!(h.offset(m(-0.3), m(d)).get(), -0.3);
    }
    assert!((h.offset(m(0.45), m(6.0)).get() - 0.35).abs() < 1e-12);
    assert!((h.offset(m(-0.45), m(7.0)).get() + 0.25).abs() < 1e-12);
    assert_eq!(h.offset(m(0.45), m(9.5)).get(), 0.0);
    assert_eq!(h.offset(m(-0.45), m(100.0)).get(), 0.0);
    assert!(!h.is_over(m(0.45), m(9.4)));
    assert!(h.is_over(m(0.45), m(9.5)));
    assert!(h.is_over(m(0.0), m(0.0)));
}

//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# The offset MUST be averaged over the odometry distance: each tick the
//# behaviour commands moves it toward that tick's offset by the weight
//# 1 − exp(−Δd / λ), Δd the tick's odometry distance and λ the averaging
//# length; the first such tick after the behaviour was entered sets it.
#[test]
fn the_offset_is_averaged_over_distance() {
    let h = rule(5.0, 0.1);
    assert_eq!(h.averaged(None, m(0.3), m(0.0)).get(), 0.3);
    assert_eq!(h.averaged(Some(m(0.2)), m(0.3), m(0.0)).get(), 0.2);
    assert_eq!(h.averaged(Some(m(0.2)), m(0.3), m(-1.0)).get(), 0.2);
    let one = h.averaged(Some(m(0.2)), m(0.3), m(1.0)).get();
    assert!((one - (0.2 + 0.1 * (1.0 - (-1.0_f64).exp()))).abs() < 1e-12);
    // A jump of 0.1 m seen for 8 mm moves the average by less than 1 mm.
    let tick = h.averaged(Some(m(0.4)), m(0.3), m(0.008)).get();
    assert!((0.4 - tick) < 1e-3 && tick < 0.4);
    assert_eq!(h.averaged(Some(m(0.2)), m(0.3), m(1e300)).get(), 0.3);
}

//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# During a hand-over, path tracking's error MUST be the error to the path
//# shifted sideways by the hand-over's shift: the lateral error less the
//# shift, the angular deviation less the angle of the shift's change per metre
//# travelled, and the curvatures c / (1 − o c) of the shifted path.
#[test]
fn the_error_is_to_the_shifted_path() {
    let h = rule(5.0, 0.1);
    let path = TrackingError {
        y: m(0.4),
        angular_deviation: Radians::new(0.02).unwrap(),
        curvature: Curvature::new(0.1).unwrap(),
        curvature_ahead: Curvature::new(-0.2).unwrap(),
    };
    // Held: on the line 0.45 m left of the path, 5 cm right of the line.
    let e = h.reference_error(&path, m(0.45), m(1.0)).unwrap();
    assert!((e.y.get() + 0.05).abs() < 1e-12);
    assert!((e.angular_deviation.get() - 0.02).abs() < 1e-12);
    assert!((e.curvature.get() - 0.1 / (1.0 - 0.045)).abs() < 1e-12);
    assert!((e.curvature_ahead.get() + 0.2 / (1.0 + 0.09)).abs() < 1e-12);
    // Shrinking: the reference heads toward the path at atan(0.1).
    let e = h.reference_error(&path, m(0.45), m(6.0)).unwrap();
    assert!((e.y.get() - 0.05).abs() < 1e-12);
    assert!((e.angular_deviation.get() - (0.02 + 0.1_f64.atan())).abs() < 1e-12);
    // Over: the path's own error.
    let e = h.reference_error(&path, m(0.45), m(50.0)).unwrap();
    assert_eq!(e, path);
    // A shift past the centre of curvature (radius 2 m) is refused.
    let tight = TrackingError {
        curvature: Curvature::new(0.5).unwrap(),
        ..path
    };
    let e = h.reference_error(&tight, m(2.0), m(0.0)).unwrap_err();
    assert_eq!(e.requirement, "GD-HANDOVER");
}

// ---------------------------------------------------------------- the furrow window's reach (FUR-REACH)

//= spec/pierre2022.md#fur-reach-lateral-reach-of-the-window
//= type=test
//# The lateral reach of a furrow configuration for a ray increment Δ MUST be
//# min(h tan α / sin p − m_y, h tan α / sin p + m_y), at least 0, with α = a_w −
//# (⌊w_ref / 2⌋ + margin) Δ, h the mount height, p its pitch and m_y its
//# lateral position; 0 when α ≤ 0.
#[test]
fn the_reach_is_the_outermost_whole_template_on_the_ground() {
    let quarter_degree = Radians::new(0.25_f64.to_radians()).unwrap();
    let at = |half_angle_deg: f64, mount_y: f64| {
        let params = FurrowParams {
            window_half_angle: Radians::new(half_angle_deg.to_radians()).unwrap(),
            mount_pitch: Radians::new(21.8_f64.to_radians()).unwrap(),
            mount_y: Meters::new(mount_y).unwrap(),
            ..FurrowParams::table2()
        };
        FurrowConfig::new(&params)
            .unwrap()
            .lateral_reach(quarter_degree)
            .unwrap()
            .get()
    };
    // ±20°: 7 + 7 rays of 0.25° inset, α = 16.5°, 1 m high, pitched 21.8°.
    let expected = 16.5_f64.to_radians().tan() / 21.8_f64.to_radians().sin();
    assert!((at(20.0, 0.0) - expected).abs() < 1e-12);
    assert!((at(20.0, 0.0) - 0.7975).abs() < 1e-3);
    assert!((at(30.0, 0.0) - 1.3425).abs() < 1e-3);
    // A mount 0.1 m left of O reaches 0.1 m less to the right.
    assert!((at(20.0, 0.1) - (expected - 0.1)).abs() < 1e-12);
    // A window no wider than the template's inset reaches nothing.
    assert!(at(3.5, 0.0).abs() < f64::MIN_POSITIVE);
    let config = FurrowConfig::new(&FurrowParams::table2()).unwrap();
    for bad in [0.0, -0.01] {
        let e = config
            .lateral_reach(Radians::new(bad).unwrap())
            .unwrap_err();
        assert_eq!(e.requirement, "FUR-REACH");
    }
}

//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# In a tick in which path tracking steers on the carried pose and the plan
//# check's pose has no projection, a behaviour's line MUST be placed on the
//# path against the carried pose: its offset from the path as
//# `line_relative_to_path` gives it from the carried pose's error, its heading
//# from the path's zero.
/// The robot on the path (y = 0), the wall's edge line 0.3 m left of it
/// from x = 6 m on, the fix float (0.3 m off, refused by the fix rule) from
/// x = 2 m: path tracking steers on the carried pose, its heading drifting
/// with the odometry's, and the plan check's pose (no plan dead reckoning)
/// has no projection. The edge line is placed
/// on the path from the carried pose, parallel to it, and the entry starts
/// in path tracking from the first usable line, before the machine enters
/// edge following (without the placement, only once it had entered).
#[test]
fn a_line_seen_on_the_carried_pose_is_placed_on_the_path_and_entered_from_it() {
    // The odometry's heading drifts 0.005 rad per metre, its positions exact.
    const YAW_DRIFT: f64 = 0.005;
    let path = straight_path(-10.0, 190.0);
    let mut p = params(None);
    p.fix = Some(fix_rule());
    p.entry = Some(EntryParams {
        closing: m(1.0),
        lead: m(2.0),
    });
    let mut g: Pierre2022<'_, PATH_N> =
        Guidance::new(GuidanceConfig::new(&p).unwrap(), &path).unwrap();
    let (mut placed, mut approached) = (0, 0);
    for k in 0..1500_u32 {
        let x = 0.008 * f64::from(k);
        let r = wall_ranges((x, 0.0, 0.0), 6.0);
        let scan = [edge_scan(&r, RangeLimits::new(m(0.05), m(30.0)).unwrap())];
        let float = x > 2.0;
        let quality = FixQuality {
            kind: if float {
                FixKind::RtkFloat
            } else {
                FixKind::RtkFixed
            },
            accuracy: Some(m(if float { 0.3 } else { 0.01 })),
        };
        let out = g
            .step_with_fix(
                &TickInput {
                    scans: if k % 10 == 0 { &scan } else { &[] },
                    gnss: Some(Pose2::<World>::new(x, if float { 0.3 } else { 0.0 }, 0.0).unwrap()),
                    odometry: Pose2::<Odom>::new(x, 0.0, YAW_DRIFT * x).unwrap(),
                    extra: Sideslip::ZERO,
                },
                &quality,
            )
            .unwrap();
        if float {
            assert!(matches!(out.path.fix, FixUse::Carried { .. }), "x {x}");
        }
        let edge = &out.behaviours[0];
        if out.mode != Mode::PathTracking || !edge.reported.estimate_is_valid() {
            continue;
        }
        // The line placed by the carried pose, whose heading has drifted
        // (0.02 rad at 6 m): the offset from its error, the heading zero.
        let plan = edge.plan.expect("a line placed on the path");
        let carried = out.path.frenet.unwrap();
        let line = edge.error.unwrap();
        assert!(carried.angular_deviation.get().abs() > 0.015, "x {x}");
        assert!(
            (plan.offset.get() - (carried.y.get() - line.y.get())).abs() < 1e-3,
            "x {x}: {plan:?}"
        );
        assert!(
            (plan.offset.get() - LINE_OFFSET).abs() < 0.05,
            "x {x}: {plan:?}"
        );
        assert_eq!(plan.heading.get(), 0.0);
        placed += 1;
        // From the tick after the first usable line: path tracking steers on
        // the entry's shift, which starts at the robot (the carried pose's
        // error) and moves toward the line.
        if placed > 1 {
            let shift = out.path.reference_offset.expect("the entry's shift").get();
            if approached == 0 {
                assert!(
                    (shift - carried.y.get()).abs() < 0.01,
                    "x {x}: shift {shift}"
                );
            }
            assert!(
                shift > -0.06 && shift < LINE_OFFSET + 0.05,
                "x {x}: shift {shift}"
            );
            approached += 1;
        }
    }
    assert!(
        approached > 0,
        "{placed} ticks with a placed line in path tracking"
    );
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
}
