//! The per-tick guidance pipeline end to end on synthetic scans
//! (`spec/guidance.md`, GD-*): path tracking without detections, entry into a
//! behaviour after its delay with the command the law gives for that
//! detector's error, held detections moved by odometry, localisation lost in a
//! behaviour, Stop, priority, plan flags, malformed input, configuration, a
//! path replaced between ticks, the vehicle's actuation, and properties over
//! random tick sequences and arbitrary scans.
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

mod furrow_common;

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use fieldguide::control::backstepping::{steering_command, BacksteppingConfig, SteeringCommand};
use fieldguide::control::ControlLaw;
use fieldguide::geometry::carry::{moved_line_error, pose_in_scan_frame};
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::guidance::{
    BehaviourId, BehaviourParams, BehaviourStatus, Guidance, GuidanceConfig, GuidanceParams,
    LawOutcome, Mode, OdometryAidParams, PlanPose, RoutedScan, TickInput, TickOutput,
    MAX_SCAN_AGE_TICKS,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::model::{Actuation, Command, Saturated, Vehicle};
use fieldguide::perception::edge::{
    EdgeConfig, EdgeDetector, EdgeDetectorConfig, EdgeLine, ParabolaFit, Side,
};
use fieldguide::perception::furrow::lines::{self, RowLine};
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::perception::furrow::{FurrowDetector, FurrowParams, RowLines};
use fieldguide::perception::{AnyDetector, AnyDetectorConfig, HeldLine, RangeLimits, Scan};
use fieldguide::presets::{
    furrow_pursuing, pierre2022_both, pierre2022_edge, pierre2022_furrow, pierre2022_path,
    Pierre2022, Pierre2022Params, EDGE, FURROW,
};
use fieldguide::supervisor::switching::{Mode as MachineMode, PathAhead, PlanTolerance};
use fieldguide::{
    Meters, MetersPerSecond, Odom, Point2, Pose2, Precondition, Radians, RadiansPerSecond, Robot,
    Seconds, Sensor, TrackingError, Transform2, Verdict, World,
};
use furrow_common::{ridge_scan, Lidar, Ridge};
use proptest::prelude::*;

const PATH_N: usize = 256;
type Pipeline<'p> = Pierre2022<'p, PATH_N>;
type Params = Pierre2022Params;
type Behaviour = BehaviourParams<AnyDetectorConfig, BacksteppingConfig>;
type Out = TickOutput<Sideslip, 2>;

/// The priority orders of the two behaviours of the presets.
const FURROW_FIRST: [BehaviourId; 2] = [FURROW, EDGE];
const EDGE_FIRST: [BehaviourId; 2] = [EDGE, FURROW];

/// The horizontal LiDAR: 360 rays over a full turn, 1.2 m ahead of O.
const MOUNT_X: f64 = 1.2;
const RAYS: usize = 360;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn mount() -> Transform2<Sensor, Robot> {
    Transform2::new(MOUNT_X, 0.0, 0.0).unwrap()
}

/// The horizontal LiDAR's valid ranges.
fn limits() -> RangeLimits {
    RangeLimits::new(m(0.05), m(30.0)).unwrap()
}

/// The inclined LiDAR's valid ranges.
fn furrow_limits() -> RangeLimits {
    RangeLimits::new(m(0.1), m(20.0)).unwrap()
}

fn edge_scan(ranges: &[f64]) -> Scan<'_> {
    Scan {
        start: Radians::new(-PI).unwrap(),
        increment: Radians::new(TAU / RAYS as f64).unwrap(),
        ranges,
        limits: limits(),
    }
}

/// `scan` routed to behaviour `behaviour`.
fn routed(behaviour: BehaviourId, scan: Scan<'_>) -> RoutedScan<'_> {
    RoutedScan { behaviour, scan }
}

/// A wall along the world x axis at `y`, from `x_min` to `x_max`.
#[derive(Clone, Copy)]
struct Wall {
    y: f64,
    x_min: f64,
    x_max: f64,
}

/// Exact ranges to `wall` from the LiDAR of a robot at `pose` (x, y, heading).
fn wall_ranges(pose: (f64, f64, f64), wall: Wall) -> Vec<f64> {
    let (x, y, psi) = pose;
    let (sx, sy) = (x + MOUNT_X * psi.cos(), y + MOUNT_X * psi.sin());
    (0..RAYS)
        .map(|k| {
            let a = psi - PI + TAU * k as f64 / RAYS as f64;
            let (c, s) = (a.cos(), a.sin());
            if s.abs() < 1e-9 {
                return f64::INFINITY;
            }
            let t = (wall.y - sy) / s;
            let hit = sx + t * c;
            if t > 0.0 && t <= 30.0 && hit >= wall.x_min && hit <= wall.x_max {
                t
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

fn long_wall(y: f64) -> Wall {
    Wall {
        y,
        x_min: -100.0,
        x_max: 500.0,
    }
}

fn furrow_params() -> FurrowParams {
    FurrowParams::table2()
}

fn furrow_lidar() -> Lidar {
    Lidar::centred(360, FRAC_PI_2)
}

fn furrow_scan<'a>(ranges: &'a [f64], l: &Lidar) -> Scan<'a> {
    Scan {
        start: Radians::new(l.angle_min).unwrap(),
        increment: Radians::new(l.increment).unwrap(),
        ranges,
        limits: furrow_limits(),
    }
}

/// Two rows 0.75 m apart about the world x axis, 0.3 m tall.
fn two_rows() -> Vec<Ridge> {
    [-0.375, 0.375]
        .iter()
        .map(|&c| Ridge {
            center_y: c,
            half_width: 0.08,
            height: 0.3,
        })
        .collect()
}

/// A straight path along the world x axis from −20 m to 300 m.
fn straight_path() -> ReferencePath<PATH_N> {
    let points: Vec<Point2<World>> = (0..=64)
        .map(|i| Point2::new(-20.0 + 5.0 * f64::from(i), 0.0).unwrap())
        .collect();
    ReferencePath::from_waypoints(&points, PathConfig::default()).unwrap()
}

fn world(p: (f64, f64, f64)) -> Pose2<World> {
    Pose2::new(p.0, p.1, p.2).unwrap()
}

fn odom(p: (f64, f64, f64)) -> Pose2<Odom> {
    Pose2::new(p.0, p.1, p.2).unwrap()
}

/// A speed schedule over [lo, hi] m/s of bandwidth 2 1/s.
fn schedule(lo: f64, hi: f64) -> fieldguide::control::backstepping::SpeedSchedule {
    fieldguide::control::backstepping::SpeedSchedule::new(
        MetersPerSecond::new(lo).unwrap(),
        MetersPerSecond::new(hi).unwrap(),
        fieldguide::RadiansPerSecond::new(2.0).unwrap(),
    )
    .unwrap()
}

fn edge_params() -> Params {
    pierre2022_edge(Side::Left, mount()).unwrap()
}

/// Both behaviours of the presets, in `priority` order.
fn both_params(priority: [BehaviourId; 2]) -> Params {
    let mut params = pierre2022_both(Side::Left, mount()).unwrap();
    params.priority = heapless::Vec::from_slice(&priority).unwrap();
    params
}

/// `params` with the plan checked for every behaviour with `tolerance`, a
/// disagreement left after `delay`.
fn with_plan(mut params: Params, tolerance: PlanTolerance, delay: Seconds) -> Params {
    for b in &mut params.behaviours {
        b.plan = Some(tolerance);
    }
    params.plan_delay = Some(delay);
    params
}

/// The parameters of behaviour `id`.
fn behaviour(params: &Params, id: BehaviourId) -> &Behaviour {
    params.behaviours.iter().find(|b| b.id == id).unwrap()
}

fn behaviour_mut(params: &mut Params, id: BehaviourId) -> &mut Behaviour {
    params.behaviours.iter_mut().find(|b| b.id == id).unwrap()
}

/// The status of behaviour `id` in a tick; it must be configured.
fn status(out: &Out, id: BehaviourId) -> &BehaviourStatus {
    out.behaviour(id).expect("a configured behaviour")
}

fn pipeline<'p>(params: &Params, path: &'p ReferencePath<PATH_N>) -> Pipeline<'p> {
    Guidance::new(GuidanceConfig::new(params).unwrap(), path).unwrap()
}

/// A tick with only poses: no scan.
fn bare(pose: (f64, f64, f64), gnss: bool) -> TickInput<'static, Sideslip> {
    TickInput {
        scans: &[],
        gnss: gnss.then(|| world(pose)),
        odometry: odom(pose),
        extra: Sideslip::ZERO,
    }
}

fn command(out: &Out) -> Saturated {
    out.command.expect("a command")
}

/// The steering angle of a bicycle command.
fn steering(c: &Saturated) -> Radians {
    c.command.steering().expect("a bicycle command")
}

/// The command the pipeline makes of the backstepping law's output `c` at
/// the desired speed `speed`.
fn bicycle(c: &SteeringCommand, speed: MetersPerSecond) -> Saturated {
    Saturated {
        command: Command::Bicycle {
            speed,
            steering: c.steering,
        },
        saturated: c.saturated,
    }
}

/// The edge detector's own error on a scan, straight from the detector.
fn edge_error_of(ranges: &[f64]) -> (Verdict, TrackingError) {
    let mut detector = EdgeDetector::<512, 64>::new(EdgeDetectorConfig {
        edge: EdgeConfig::pierre2022().unwrap(),
        mount: mount(),
        side: Side::Left,
    });
    let outcome = detector
        .detect(&edge_scan(ranges), &odom((0.0, 0.0, 0.0)))
        .unwrap();
    (outcome.verdict, outcome.fit.unwrap().error)
}

//= spec/guidance.md#gd-prediction-extra-input-and-prediction-only-in-path-tracking
//= type=test
//# Path tracking MUST use the tick's extra input, when compensation is
//# configured, and the curvature c(s + vT) with v its desired speed and T the
//# prediction horizon; every other behaviour MUST use its law's neutral input
//# and a straight line, c = c(s + vT) = 0.
//= spec/guidance.md#gd-speed-desired-speed-per-mode
//= type=test
//# The speed of a command MUST be the desired speed of its source.
#[test]
fn path_tracking_without_detections_uses_sideslip_and_prediction() {
    // 10 m straight, then a left arc of radius 5 m: at s = 9 the smoothed
    // curvature is still small but 0.8 m ahead (v T = 0.8 m/s × 1 s) it is not.
    let mut points: Vec<Point2<World>> = (0..=20)
        .map(|i| Point2::new(0.5 * f64::from(i), 0.0).unwrap())
        .collect();
    for i in 1..=30 {
        let a = f64::from(i) * 0.05;
        points.push(Point2::new(10.0 + 5.0 * a.sin(), 5.0 - 5.0 * a.cos()).unwrap());
    }
    let path = ReferencePath::<PATH_N>::from_waypoints(&points, PathConfig::default()).unwrap();
    let params = both_params(FURROW_FIRST);
    let mut g = pipeline(&params, &path);
    let pose = (9.0, 0.02, 0.0);
    let slip = Sideslip::new(-0.02, -0.03).unwrap();
    let out = g
        .step(&TickInput {
            extra: slip,
            ..bare(pose, true)
        })
        .unwrap();
    assert_eq!(out.mode, Mode::PathTracking);
    assert_eq!(out.source, Some(Mode::PathTracking));
    assert!(out.path.localisation_valid);
    assert_eq!(status(&out, EDGE).detected, Verdict::Absent);
    assert_eq!(status(&out, FURROW).detected, Verdict::Absent);

    // The same computation by hand: global projection with look-ahead 0.8 m,
    // the law of Table 1 with the sideslip, at 0.8 m/s.
    let frenet = path.project(&world(pose), m(0.8)).unwrap();
    assert!(
        frenet.curvature_ahead.get() > frenet.curvature.get() + 0.05,
        "{frenet:?}"
    );
    let law = params.path.law;
    let v = MetersPerSecond::new(0.8).unwrap();
    let expected = steering_command(&law, &frenet.tracking_error(), slip, v).unwrap();
    let c = command(&out);
    assert_eq!(c.command.speed(), v);
    assert_eq!(steering(&c), expected.steering);
    assert_eq!(c, bicycle(&expected, v));
    assert_eq!(out.path.frenet, Some(frenet));
    assert_eq!(out.path.extra_used, slip);
    // Both the sideslip and the prediction change the command.
    let no_slip = steering_command(&law, &frenet.tracking_error(), Sideslip::ZERO, v).unwrap();
    assert!(!c.saturated, "{c:?}");
    assert!((no_slip.steering.get() - steering(&c).get()).abs() > 1e-3);
    let now = path.project(&world(pose), Meters::ZERO).unwrap();
    let no_prediction = steering_command(&law, &now.tracking_error(), slip, v).unwrap();
    assert!((no_prediction.steering.get() - steering(&c).get()).abs() > 1e-3);

    // Compensation off: the law's neutral input, zero sideslip.
    let mut off = params;
    off.path.compensation = false;
    let mut g = pipeline(&off, &path);
    let out = g
        .step(&TickInput {
            extra: slip,
            ..bare(pose, true)
        })
        .unwrap();
    assert_eq!(out.path.extra_used, Sideslip::ZERO);
    assert_eq!(out.path.extra_used, BacksteppingConfig::NEUTRAL);
    assert_eq!(steering(&command(&out)), no_slip.steering);
}

//= spec/guidance.md#gd-command-the-command-of-the-selected-source
//= type=test
//# The command MUST be the saturated output of the selected source's control law
//# on that source's error of the tick, and no other; when the machine selects no
//# source outside Stop, there MUST be no command.
//= spec/guidance.md#gd-order-pipeline-order
//= type=test
//# Each call of `step` MUST process one control tick in this order: the
//# detections of the tick's scans (or the ageing of the held ones), the Frénet
//# projection of the GNSS pose, the plan consistency of each detected line, the
//# control law of each source whose estimate is valid, one step of the switching
//# machine, and the command of the source the machine selects.
//= spec/guidance.md#gd-prediction-extra-input-and-prediction-only-in-path-tracking
//= type=test
//# Path tracking MUST use the tick's extra input, when compensation is
//# configured, and the curvature c(s + vT) with v its desired speed and T the
//# prediction horizon; every other behaviour MUST use its law's neutral input
//# and a straight line, c = c(s + vT) = 0.
#[test]
fn forty_enter_ticks_bring_edge_following_with_the_laws_command() {
    let path = straight_path();
    let params = edge_params();
    let mut g = pipeline(&params, &path);
    let pose = (0.0, 0.0, 0.0);
    let ranges = wall_ranges(pose, long_wall(1.5));
    let (verdict, error) = edge_error_of(&ranges);
    assert_eq!(verdict, Verdict::Enter);
    // Eq. 11 by hand: a parallel wall 1.5 m left, D = 1.4 m: y = 1.4 − 1.5.
    assert!((error.y.get() + 0.1).abs() < 1e-9, "{error:?}");
    assert!(error.angular_deviation.get().abs() < 1e-9);
    let slip = Sideslip::new(0.05, -0.04).unwrap();
    let scans = [routed(EDGE, edge_scan(&ranges))];
    let tick = TickInput {
        scans: &scans,
        extra: slip,
        ..bare(pose, true)
    };
    // Table 1: 0.4 s at 100 Hz is 40 ticks of Enter verdicts.
    for k in 1..=39 {
        let out = g.step(&tick).unwrap();
        assert_eq!(out.mode, Mode::PathTracking, "tick {k}");
        assert_eq!(out.source, Some(Mode::PathTracking));
        assert_eq!(status(&out, EDGE).detected, Verdict::Enter);
        assert_eq!(status(&out, EDGE).error, Some(error));
        assert_eq!(command(&out).command.speed().get(), 0.8);
    }
    let out = g.step(&tick).unwrap();
    assert_eq!(out.mode, Mode::Behaviour(EDGE));
    assert_eq!(out.source, Some(Mode::Behaviour(EDGE)));
    // The law of Table 1 on the detector's error: no sideslip, straight line,
    // at 0.4 m/s, whatever the input's sideslip.
    let v = MetersPerSecond::new(0.4).unwrap();
    let law = behaviour(&params, EDGE).law;
    let expected = steering_command(&law, &error, Sideslip::ZERO, v).unwrap();
    let c = command(&out);
    assert_eq!(c.command.speed(), v);
    assert_eq!(steering(&c), expected.steering);
    assert_eq!(c.saturated, expected.saturated);
    assert_eq!(
        status(&out, EDGE).law,
        LawOutcome::Commanded(bicycle(&expected, v))
    );
    // The path law ran too (the pipeline runs every valid source's law).
    assert!(matches!(out.path.law, LawOutcome::Commanded(_)));
}

/// The robot drives along x at 0.7 m/s (0.007 m per 10 ms tick), 5 cm left of
/// the rows' middle; the inclined LiDAR scans every 10th tick.
fn furrow_drive(
    params: &Params,
    path: &ReferencePath<PATH_N>,
    ticks: usize,
    mut each: impl FnMut(usize, (f64, f64, f64), bool, &Out),
) {
    let mut g = pipeline(params, path);
    let lidar = furrow_lidar();
    let rows = two_rows();
    for k in 0..ticks {
        let pose = (0.007 * k as f64, 0.05, 0.0);
        let scanned = k % 10 == 0;
        let ranges = ridge_scan(&furrow_params(), &lidar, pose, &rows);
        let scans = scanned.then(|| routed(FURROW, furrow_scan(&ranges, &lidar)));
        let out = g
            .step(&TickInput {
                scans: scans.as_slice(),
                ..bare(pose, true)
            })
            .unwrap();
        each(k, pose, scanned, &out);
    }
}

//= spec/guidance.md#gd-scan-age-held-detections
//= type=test
//# In a tick without a new scan, a behaviour MUST report the verdict of its
//# latest scan, with the tracking error to that scan's line moved to the current
//# pose through odometry, as long as that scan is at most the maximal scan age
//# old; an older scan, a scan the detector refused, or no scan at all MUST give
//# Absent.
#[test]
fn furrow_scans_at_10_hz_are_held_and_entered_after_50_enter_ticks() {
    let path = straight_path();
    let params = pierre2022_furrow().unwrap();
    let furrow = *behaviour(&params, FURROW);
    let AnyDetectorConfig::Furrow(detector) = furrow.detector else {
        panic!("furrow pursuing has a furrow detector");
    };
    let mut twin = FurrowDetector::<512, 32>::new(detector).unwrap();
    let lidar = furrow_lidar();
    let rows = two_rows();
    let mut latest = None;
    let mut first_enter: Option<usize> = None;
    let mut entered: Option<usize> = None;
    furrow_drive(&params, &path, 400, |k, pose, scanned, out| {
        if scanned {
            let ranges = ridge_scan(&furrow_params(), &lidar, pose, &rows);
            let d = twin
                .detect(&furrow_scan(&ranges, &lidar), &odom(pose))
                .unwrap();
            latest = Some((d, pose));
        }
        let (d, at) = latest.unwrap();
        let furrow_status = status(out, FURROW);
        assert_eq!(furrow_status.scan_age, Some((k % 10) as u16));
        assert_eq!(furrow_status.detected, d.verdict, "tick {k}");
        // The quality of the held scan, Absent verdicts included.
        assert_eq!(furrow_status.quality, d.quality, "tick {k}");
        match d.error {
            None => assert_eq!(furrow_status.error, None),
            Some(e) => {
                let got = furrow_status.error.unwrap();
                if scanned {
                    assert_eq!(got, e);
                } else {
                    // Moved straight ahead by dx: each row's y = y₀ + dx sin θ̃₀,
                    // then the mean of the two rows (GD-ODOMETRY).
                    let dx = pose.0 - at.0;
                    let Some(RowLines::Two(Pair { left, right })) = d.lines else {
                        panic!("two rows expected");
                    };
                    let (l, r) = (
                        lines::tracking_error(&left).unwrap(),
                        lines::tracking_error(&right).unwrap(),
                    );
                    let moved = |e: TrackingError| e.y.get() + dx * e.angular_deviation.get().sin();
                    let y = 0.5 * moved(l) + 0.5 * moved(r);
                    assert!((got.y.get() - y).abs() < 1e-12);
                    assert!(
                        (got.angular_deviation.get() - e.angular_deviation.get()).abs() < 1e-12
                    );
                    assert!(
                        (got.y.get() - e.y.get() - dx * e.angular_deviation.get().sin()).abs()
                            < 1e-3
                    );
                }
            }
        }
        if furrow_status.reported == Verdict::Enter {
            first_enter.get_or_insert(k);
        } else if entered.is_none() {
            first_enter = None;
        }
        if out.mode == Mode::Behaviour(FURROW) && entered.is_none() {
            entered = Some(k);
            let error = furrow_status.error.unwrap();
            let v = MetersPerSecond::new(0.7).unwrap();
            let expected = steering_command(&furrow.law, &error, Sideslip::ZERO, v).unwrap();
            assert_eq!(steering(&command(out)), expected.steering);
            assert_eq!(command(out).command.speed(), v);
            assert_eq!(out.source, Some(Mode::Behaviour(FURROW)));
        }
    });
    // Table 2: 0.5 s at 100 Hz, 50 consecutive ticks of Enter, held between scans.
    let (first, entered) = (first_enter.unwrap(), entered.unwrap());
    assert_eq!(
        entered,
        first + 49,
        "first Enter {first}, entered {entered}"
    );
}

//= spec/guidance.md#gd-scan-age-held-detections
//= type=test
//# In a tick without a new scan, a behaviour MUST report the verdict of its
//# latest scan, with the tracking error to that scan's line moved to the current
//# pose through odometry, as long as that scan is at most the maximal scan age
//# old; an older scan, a scan the detector refused, or no scan at all MUST give
//# Absent.
//= spec/guidance.md#gd-input-malformed-input
//= type=test
//# Sensor data MUST NOT be malformed input: any range, NaN and infinities
//# included, and any scan a detector refuses MUST give a tick output, the
//# refused scan counting as no estimate.
#[test]
fn a_held_edge_detection_expires_after_the_maximal_age_and_a_refused_scan_drops_it() {
    let path = straight_path();
    let params = edge_params();
    let config = GuidanceConfig::new(&params).unwrap();
    assert_eq!(config.max_scan_age_ticks(), 10); // 0.1 s at 0.01 s
    let mut g = pipeline(&params, &path);
    let pose = (0.0, 0.0, 0.0);
    let ranges = wall_ranges(pose, long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    let out = g
        .step(&TickInput {
            scans: &scans,
            ..bare(pose, true)
        })
        .unwrap();
    assert_eq!(
        (status(&out, EDGE).detected, status(&out, EDGE).scan_age),
        (Verdict::Enter, Some(0))
    );
    for age in 1..=10 {
        let out = g.step(&bare(pose, true)).unwrap();
        assert_eq!(status(&out, EDGE).detected, Verdict::Enter, "age {age}");
        assert_eq!(status(&out, EDGE).scan_age, Some(age));
        assert!(status(&out, EDGE).error.is_some());
    }
    let out = g.step(&bare(pose, true)).unwrap();
    assert_eq!(status(&out, EDGE).detected, Verdict::Absent);
    assert_eq!(status(&out, EDGE).error, None);
    assert_eq!(status(&out, EDGE).scan_age, Some(11));

    // A detector with room for 200 points takes the wall (about 177 valid
    // rays), then refuses a scan of 360 valid rays: the held wall is dropped.
    let mut small: Guidance<'_, PATH_N, AnyDetector<200>, BacksteppingConfig, 2> =
        Guidance::new(GuidanceConfig::new(&params).unwrap(), &path).unwrap();
    small
        .step(&TickInput {
            scans: &scans,
            ..bare(pose, true)
        })
        .unwrap();
    assert_eq!(small.held(EDGE).map(|d| d.verdict), Some(Verdict::Enter));
    let circle = vec![5.0; RAYS];
    let out = small
        .step(&TickInput {
            scans: &[routed(EDGE, edge_scan(&circle))],
            ..bare(pose, true)
        })
        .unwrap();
    let edge_status = status(&out, EDGE);
    assert_eq!(edge_status.scan_refused.unwrap().requirement, "EDGE-SCAN");
    assert_eq!(edge_status.detected, Verdict::Absent);
    assert_eq!(edge_status.error, None);
    assert!(small.held(EDGE).is_none());
    // The refused scan left no chain behind in the detector either.
    let detector = small.detector(EDGE).and_then(AnyDetector::as_edge).unwrap();
    assert!(detector.chain().is_empty());
    assert_eq!(out.mode, Mode::PathTracking);
}

//= spec/guidance.md#gd-localisation-localisation-for-path-tracking
//= type=test
//# Localisation MUST be valid in a tick exactly when a GNSS pose is given, its
//# projection on the path succeeds and the path-tracking law gives a command
//# from it.
#[test]
fn losing_localisation_in_edge_following_keeps_the_behaviour() {
    let path = straight_path();
    let params = edge_params();
    let mut g = pipeline(&params, &path);
    let pose = (0.0, 0.0, 0.0);
    let ranges = wall_ranges(pose, long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    let scan = |gnss: bool| TickInput {
        scans: &scans,
        ..bare(pose, gnss)
    };
    for _ in 0..40 {
        g.step(&scan(true)).unwrap();
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
    let with_gnss = command(&g.step(&scan(true)).unwrap());
    for k in 0..300 {
        let out = g.step(&scan(false)).unwrap();
        assert!(!out.path.localisation_valid);
        assert_eq!(out.path.frenet, None);
        assert_eq!(out.path.law, LawOutcome::NotRun);
        assert_eq!(out.mode, Mode::Behaviour(EDGE), "tick {k}");
        assert_eq!(out.source, Some(Mode::Behaviour(EDGE)));
        assert_eq!(command(&out), with_gnss);
    }
    // Facing backwards along the path: the projection exists but the law
    // refuses it (PT-HEADING), so localisation is not valid.
    let mut g = pipeline(&params, &path);
    let out = g.step(&bare((5.0, 0.1, PI), true)).unwrap();
    assert!(out.path.frenet.is_some());
    match out.path.law {
        LawOutcome::Refused(e) => assert_eq!(e.requirement, "PT-HEADING"),
        other => panic!("{other:?}"),
    }
    assert!(!out.path.localisation_valid);
    assert_eq!(out.command, None);
    assert_eq!(out.source, None);
}

/// A U-turn: out along y = 0, a half circle of radius 1.5 m, back along y = 3.
fn u_turn() -> ReferencePath<PATH_N> {
    let mut points: Vec<Point2<World>> = (0..=40)
        .map(|i| Point2::new(0.5 * f64::from(i), 0.0).unwrap())
        .collect();
    for i in 1..20 {
        let a = PI * f64::from(i) / 20.0;
        points.push(Point2::new(20.0 + 1.5 * a.sin(), 1.5 - 1.5 * a.cos()).unwrap());
    }
    for i in 0..=40 {
        points.push(Point2::new(20.0 - 0.5 * f64::from(i), 3.0).unwrap());
    }
    ReferencePath::<PATH_N>::from_waypoints(&points, PathConfig::default()).unwrap()
}

//= spec/guidance.md#gd-localisation-localisation-for-path-tracking
//= type=test
//# The projection MUST search the path locally, within the search window plus
//# the odometry distance travelled since the last successful projection, around
//# that projection's abscissa, and globally only before the first one.
#[test]
fn projection_is_local_and_its_window_grows_with_the_odometry_travelled() {
    let path = u_turn();
    let mut g = pipeline(&pierre2022_path().unwrap(), &path);
    // First tick: global search, on the first leg.
    let out = g.step(&bare((5.0, 0.0, 0.0), true)).unwrap();
    assert!((out.path.frenet.unwrap().s.get() - 5.0).abs() < 1e-9);
    // Drift to 1.6 m left of the first leg, 1.4 m from the return leg: the
    // local search keeps the first leg.
    for k in 1..=16 {
        let y = 0.1 * f64::from(k);
        let out = g.step(&bare((5.0, y, 0.0), true)).unwrap();
        let f = out.path.frenet.unwrap();
        assert!((f.s.get() - 5.0).abs() < 1e-9 && (f.y.get() - y).abs() < 1e-9);
    }
    // A pipeline starting there would take the return leg (global search).
    let mut fresh = pipeline(&pierre2022_path().unwrap(), &path);
    let out = fresh.step(&bare((5.0, 1.6, 0.0), true)).unwrap();
    assert!(out.path.frenet.unwrap().s.get() > 30.0);

    // GNSS lost over 12 m of odometry: the window grows by that distance, so
    // the next pose is found at s = 17, beyond the 3 m base window.
    let mut g = pipeline(&pierre2022_path().unwrap(), &path);
    g.step(&bare((5.0, 0.0, 0.0), true)).unwrap();
    for k in 1..=120 {
        g.step(&bare((5.0 + 0.1 * f64::from(k), 0.0, 0.0), false))
            .unwrap();
    }
    let out = g.step(&bare((17.0, 0.0, 0.0), true)).unwrap();
    let f = out.path.frenet.unwrap();
    assert!((f.s.get() - 17.0).abs() < 1e-9, "{f:?}");
    assert!(out.path.localisation_valid);
}

//= spec/guidance.md#gd-path-a-reference-path-replaced-between-ticks
//= type=test
//# The reference path MUST be replaceable between ticks without rebuilding the
//# pipeline, keeping the mode, the switching counters and the held
//# detections, and the first projection on a new path MUST search the whole
//# path.
#[test]
fn a_path_replaced_between_ticks_keeps_the_state_and_is_searched_whole() {
    let straight = straight_path();
    let turn = u_turn();
    let params = edge_params();
    let mut g = pipeline(&params, &straight);
    let pose = (5.0, 1.6, 0.0);
    let ranges = wall_ranges(pose, long_wall(3.1));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    let tick = TickInput {
        scans: &scans,
        ..bare(pose, true)
    };
    // 20 of the 40 Enter ticks edge following needs, on the straight path.
    for _ in 0..20 {
        let out = g.step(&tick).unwrap();
        assert_eq!(status(&out, EDGE).detected, Verdict::Enter);
        assert!((out.path.frenet.unwrap().s.get() - 25.0).abs() < 1e-9);
    }
    let (mode, machine, held) = (g.mode(), *g.switching(), *g.held(EDGE).unwrap());
    assert_eq!(machine.state().entry_run(0), Some(20));
    g.set_path(&turn);
    // Nothing but the path changed.
    assert!(core::ptr::eq(g.path(), &turn));
    assert_eq!(g.mode(), mode);
    assert_eq!(*g.switching(), machine);
    assert_eq!(*g.held(EDGE).unwrap(), held);
    // The first projection on the new path is global: 1.6 m left of its first
    // leg at s = 5 but 1.4 m from its return leg, it takes the return leg (a
    // local search around the old abscissa s = 25 would not), as a pipeline
    // built on that path does.
    let held_tick = bare(pose, true);
    let out = g.step(&held_tick).unwrap();
    let mut fresh = pipeline(&params, &turn);
    let first = fresh.step(&held_tick).unwrap();
    assert!(out.path.frenet.unwrap().s.get() > 30.0);
    assert_eq!(out.path.frenet, first.path.frenet);
    // The held detection was kept: the scan of before the change is one tick old.
    assert_eq!(status(&out, EDGE).scan_age, Some(1));
    assert_eq!(status(&out, EDGE).detected, Verdict::Enter);
    // The counters were kept: the 40th Enter tick enters edge following.
    for k in 22..=40 {
        let out = g.step(&tick).unwrap();
        assert_eq!(out.mode == Mode::Behaviour(EDGE), k == 40, "tick {k}");
    }
}

//= spec/guidance.md#gd-speed-change-desired-speed-of-path-tracking-changed-between-ticks
//= type=test
//# The desired speed of path tracking MUST be replaceable between ticks without
//# rebuilding the pipeline, keeping the mode, the switching counters and the held
//# detections; a speed that is not positive MUST be refused with `GD-SPEED` and a
//# speed the path-tracking law refuses with the law's error, leaving the
//# configured speed unchanged; after a change, the command of path tracking and
//# the look-ahead v (T + τ) of its curvature MUST use the new speed.
#[test]
fn path_trackings_speed_replaced_between_ticks_keeps_the_state() {
    let path = straight_path();
    let mut params = edge_params();
    params.path.law.schedule = Some(
        fieldguide::control::backstepping::SpeedSchedule::new(
            MetersPerSecond::new(0.3).unwrap(),
            MetersPerSecond::new(3.0).unwrap(),
            fieldguide::RadiansPerSecond::new(2.0).unwrap(),
        )
        .unwrap(),
    );
    let lead = params.path.horizon.get() + params.path.steering_lag.get();
    assert!(lead > 0.0);
    let mut g = pipeline(&params, &path);
    let pose = (5.0, 1.6, 0.0);
    let ranges = wall_ranges(pose, long_wall(3.1));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    let tick = TickInput {
        scans: &scans,
        ..bare(pose, true)
    };
    for _ in 0..20 {
        g.step(&tick).unwrap();
    }
    let (mode, machine, held) = (g.mode(), *g.switching(), *g.held(EDGE).unwrap());
    let before = g.config().params().path;
    // Refused: not positive (GD-SPEED), outside the schedule (the law's own error).
    for (v, id) in [
        (0.0, "GD-SPEED"),
        (-1.0, "GD-SPEED"),
        (3.5, "PT-SCHEDULE-RANGE"),
    ] {
        let e = g
            .set_path_speed(MetersPerSecond::new(v).unwrap())
            .unwrap_err();
        assert_eq!(e.requirement, id, "{v} m/s");
        assert_eq!(g.config().params().path.speed, before.speed);
        assert!((g.config().lookahead().get() - before.speed.get() * lead).abs() < 1e-12);
    }
    g.set_path_speed(MetersPerSecond::new(2.5).unwrap())
        .unwrap();
    // Nothing but the speed and its look-ahead changed.
    assert_eq!(g.mode(), mode);
    assert_eq!(*g.switching(), machine);
    assert_eq!(*g.held(EDGE).unwrap(), held);
    assert!((g.config().params().path.speed.get() - 2.5).abs() < 1e-15);
    assert!((g.config().lookahead().get() - 2.5 * lead).abs() < 1e-12);
    // Path tracking commands the new speed, with the law's output of a
    // pipeline built at that speed.
    let mut fast = params.clone();
    fast.path.speed = MetersPerSecond::new(2.5).unwrap();
    let mut fresh = pipeline(&fast, &path);
    let off = bare((5.0, 0.3, 0.05), true);
    let out = g.step(&off).unwrap();
    let first = fresh.step(&off).unwrap();
    assert_eq!(out.mode, Mode::PathTracking);
    assert!((command(&out).command.speed().get() - 2.5).abs() < 1e-15);
    assert_eq!(out.path.frenet, first.path.frenet);
    assert_eq!(out.path.law, first.path.law);
    // The held detection was kept: the scan of before the change is one tick old.
    assert_eq!(status(&out, EDGE).scan_age, Some(1));
}

//= spec/guidance.md#gd-stop-the-stop-command
//= type=test
//# In Stop the command MUST be the stop of the last command made (every speed
//# zero, steering angles held, a yaw rate zero), or the vehicle at rest before
//# any command, never saturated.
#[test]
fn without_a_source_for_the_stop_delay_the_command_is_a_stop() {
    let path = straight_path();
    let params = edge_params();
    let mut g = pipeline(&params, &path);
    let mut last = None;
    for _ in 0..10 {
        last = Some(command(&g.step(&bare((2.0, 0.4, 0.0), true)).unwrap()));
    }
    let last = last.unwrap();
    let held = steering(&last);
    assert!(held.get() < -0.01);
    // No GNSS, no scan: no source. 0.5 s at 100 Hz: Stop in the 50th tick.
    for k in 1..=49 {
        let out = g.step(&bare((2.0, 0.4, 0.0), false)).unwrap();
        assert_eq!(out.mode, Mode::PathTracking, "tick {k}");
        assert_eq!((out.command, out.source), (None, None));
    }
    for _ in 0..20 {
        let out = g.step(&bare((2.0, 0.4, 0.0), false)).unwrap();
        assert_eq!(out.mode, Mode::Stop);
        assert_eq!(out.source, None);
        assert_eq!(
            out.command,
            Some(Saturated {
                command: Command::Bicycle {
                    speed: MetersPerSecond::ZERO,
                    steering: held,
                },
                saturated: false,
            })
        );
        assert_eq!(command(&out).command, last.command.stopped());
    }
    // Localisation returns: path tracking at once.
    let out = g.step(&bare((2.0, 0.4, 0.0), true)).unwrap();
    assert_eq!(out.mode, Mode::PathTracking);
    assert_eq!(command(&out).command.speed().get(), 0.8);

    // Before any command, the stop steers straight: the vehicle at rest.
    let mut g = pipeline(&params, &path);
    let mut out = g.step(&bare((2.0, 0.4, 0.0), false)).unwrap();
    for _ in 1..50 {
        out = g.step(&bare((2.0, 0.4, 0.0), false)).unwrap();
    }
    assert_eq!(out.mode, Mode::Stop);
    assert_eq!(steering(&command(&out)), Radians::ZERO);
    assert_eq!(command(&out).command.speed(), MetersPerSecond::ZERO);
    assert_eq!(command(&out).command, Actuation::Bicycle.at_rest());
    assert!(!command(&out).saturated);
}

/// Drives along x with a wall 1.5 m left and two rows under the inclined
/// LiDAR, the rows' scans from 0.7 m on (after the wall's entry has begun:
/// FUR-FIRST-LINE gives a line from the fifth scan); returns the modes.
fn both_detectors(priority: [BehaviourId; 2]) -> Vec<Out> {
    let path = straight_path();
    let params = both_params(priority);
    let mut g = pipeline(&params, &path);
    let lidar = furrow_lidar();
    let rows = two_rows();
    (0..300)
        .map(|k| {
            let pose = (0.007 * k as f64, 0.0, 0.0);
            let inclined = ridge_scan(&furrow_params(), &lidar, pose, &rows);
            let horizontal = wall_ranges(pose, long_wall(1.5));
            let mut scans = Vec::new();
            if k % 10 == 5 {
                scans.push(routed(EDGE, edge_scan(&horizontal)));
            }
            if k % 10 == 0 && k >= 100 {
                scans.push(routed(FURROW, furrow_scan(&inclined, &lidar)));
            }
            g.step(&TickInput {
                scans: &scans,
                ..bare(pose, true)
            })
            .unwrap()
        })
        .collect()
}

//= spec/guidance.md#gd-behaviours-behaviour-slots-in-a-priority-order
//= type=test
//# The pipeline MUST hold a list of behaviour slots, each with an id unique in
//# the pipeline, a label, a detector, a law, a desired speed, two transit
//# delays and an optional plan tolerance, and MUST run a switching machine over
//# them in the configured priority order; a slot beyond the configured
//# behaviours MUST report Absent in every tick.
#[test]
fn both_detectors_at_once_follow_the_priority_order() {
    // Furrow first: the wall is entered first (the rows are scanned later),
    // then furrow pursuing takes over as soon as its entry is complete.
    let outs = both_detectors(FURROW_FIRST);
    let furrow_at = outs
        .iter()
        .position(|o| o.mode == Mode::Behaviour(FURROW))
        .unwrap();
    let edge_at = outs
        .iter()
        .position(|o| o.mode == Mode::Behaviour(EDGE))
        .unwrap();
    assert!(edge_at < furrow_at);
    assert!(outs[furrow_at..]
        .iter()
        .all(|o| o.mode == Mode::Behaviour(FURROW)));
    assert!(outs[furrow_at..]
        .iter()
        .all(|o| status(o, EDGE).detected == Verdict::Enter));
    assert_eq!(outs[furrow_at].switching.mode, MachineMode::Behaviour(0));
    // The statuses are in priority order.
    assert!(outs
        .iter()
        .all(|o| o.behaviours.iter().map(|b| b.id).eq(FURROW_FIRST)));
    // Edge first: once in edge following, the rows never take over.
    let outs = both_detectors(EDGE_FIRST);
    let edge_at = outs
        .iter()
        .position(|o| o.mode == Mode::Behaviour(EDGE))
        .unwrap();
    assert!(outs[edge_at..]
        .iter()
        .all(|o| o.mode == Mode::Behaviour(EDGE)));
    assert_eq!(outs[edge_at].switching.mode, MachineMode::Behaviour(0));
    assert!(status(outs.last().unwrap(), FURROW).detected == Verdict::Enter);
    assert!(outs
        .iter()
        .all(|o| o.behaviours.iter().map(|b| b.id).eq(EDGE_FIRST)));

    // Not configured: no status, and the slot beyond edge following reports
    // Absent every tick, whatever happens (no entry evidence, never entered).
    let path = straight_path();
    let mut g = pipeline(&edge_params(), &path);
    let ranges = wall_ranges((0.0, 0.0, 0.0), long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    for _ in 0..60 {
        let out = g
            .step(&TickInput {
                scans: &scans,
                ..bare((0.0, 0.0, 0.0), true)
            })
            .unwrap();
        assert!(out.behaviour(FURROW).is_none());
        assert_eq!(out.behaviours.len(), 1);
        assert_eq!(g.switching().state().entry_run(1), Some(0));
        assert_ne!(out.switching.mode, MachineMode::Behaviour(1));
        assert_ne!(out.mode, Mode::Behaviour(FURROW));
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
    assert!(g.detector(FURROW).is_none() && g.held(FURROW).is_none());
}

//= spec/guidance.md#gd-behaviours-behaviour-slots-in-a-priority-order
//= type=test
//# A configuration with two behaviours of one id, or a priority that names an
//# unknown behaviour, names one twice or leaves one out, MUST be refused with
//# `GD-BEHAVIOURS`.
#[test]
fn behaviour_ids_and_the_priority_are_validated() {
    let refused = |p: &Params| GuidanceConfig::new(p).unwrap_err().requirement;
    // Two behaviours of one id, with or without a priority.
    let mut p = both_params(FURROW_FIRST);
    behaviour_mut(&mut p, EDGE).id = FURROW;
    assert_eq!(refused(&p), "GD-BEHAVIOURS");
    p.priority.clear();
    assert_eq!(refused(&p), "GD-BEHAVIOURS");
    // A priority naming an unknown behaviour, one twice, or leaving one out.
    for priority in [
        &[FURROW, BehaviourId(7)][..],
        &[FURROW, FURROW][..],
        &[EDGE][..],
        &[BehaviourId(7)][..],
    ] {
        let mut p = both_params(FURROW_FIRST);
        p.priority = heapless::Vec::from_slice(priority).unwrap();
        assert_eq!(refused(&p), "GD-BEHAVIOURS", "{priority:?}");
    }
    let mut p = edge_params();
    p.priority = heapless::Vec::from_slice(&[FURROW]).unwrap();
    assert_eq!(refused(&p), "GD-BEHAVIOURS");

    // The configuration holds the behaviours in priority order; an empty
    // priority keeps the order of the list.
    let ids = |p: &Params| -> Vec<BehaviourId> {
        let config = GuidanceConfig::new(p).unwrap();
        assert!(config.params().priority.is_empty());
        config.behaviours().iter().map(|b| b.id).collect()
    };
    assert_eq!(ids(&both_params(FURROW_FIRST)), FURROW_FIRST);
    assert_eq!(ids(&both_params(EDGE_FIRST)), EDGE_FIRST);
    let mut listed = edge_params();
    listed.behaviours.push(furrow_pursuing().unwrap()).unwrap();
    assert_eq!(ids(&listed), EDGE_FIRST);
    listed.priority = heapless::Vec::from_slice(&FURROW_FIRST).unwrap();
    assert_eq!(ids(&listed), FURROW_FIRST);
    assert_eq!(ids(&pierre2022_path().unwrap()), []);
    // The machine's behaviour 0 is the first in priority: edge's delays
    // (0.4 s / 0.26 s, in ticks at 100 Hz).
    let config = GuidanceConfig::new(&both_params(EDGE_FIRST)).unwrap();
    let t = config.switching().ticks(0).unwrap();
    assert_eq!((t.enter, t.exit), (40, 26));
    // Each slot has its label.
    let path = straight_path();
    let g = pipeline(&both_params(EDGE_FIRST), &path);
    assert_eq!(g.label(Mode::Behaviour(EDGE)), "edge_following");
    assert_eq!(g.label(Mode::Behaviour(FURROW)), "furrow_pursuing");
    assert_eq!(g.label(Mode::PathTracking), "path_tracking");
    assert_eq!(g.label(Mode::Stop), "stop");
}

//= spec/guidance.md#gd-plan-plan-consistency-of-the-detected-lines
//= type=test
//# A behaviour's line MUST be reported consistent with the plan when the
//# behaviour has no plan tolerance or when the path has no projection in the
//# tick; otherwise it MUST be reported as `PlanTolerance::is_consistent` judges
//# its tracking error against the path's.
#[test]
fn a_line_far_from_the_plan_is_not_entered() {
    let path = straight_path();
    let tolerance = PlanTolerance::new(m(0.3), Radians::new(0.2).unwrap()).unwrap();
    let params = with_plan(edge_params(), tolerance, Seconds::new(0.5).unwrap());
    let pose = (0.0, 0.0, 0.0);
    // The wall 2.5 m left: the line to follow is 1.1 m left of the path.
    let far = wall_ranges(pose, long_wall(2.5));
    let far_scans = [routed(EDGE, edge_scan(&far))];
    let mut g = pipeline(&params, &path);
    for _ in 0..100 {
        let out = g
            .step(&TickInput {
                scans: &far_scans,
                ..bare(pose, true)
            })
            .unwrap();
        let edge = status(&out, EDGE);
        assert_eq!(edge.detected, Verdict::Enter);
        let plan = edge.plan.unwrap();
        assert!((plan.offset.get() - 1.1).abs() < 1e-9, "{plan:?}");
        let line = edge.error.unwrap();
        let path_error = out.path.frenet.unwrap().tracking_error();
        assert!(!tolerance.is_consistent(&line, &path_error, &PathAhead::HERE));
        assert!(!edge.plan_consistent);
        assert_eq!(out.mode, Mode::PathTracking);
    }
    // Without GNSS the check cannot be made: consistent, and entered.
    let mut g = pipeline(&params, &path);
    let mut out = None;
    for _ in 0..40 {
        out = Some(
            g.step(&TickInput {
                scans: &far_scans,
                ..bare(pose, false)
            })
            .unwrap(),
        );
    }
    let out = out.unwrap();
    assert!(status(&out, EDGE).plan_consistent && status(&out, EDGE).plan.is_none());
    assert_eq!(out.mode, Mode::Behaviour(EDGE));
    // Without a plan check: consistent, and entered, with GNSS.
    let mut g = pipeline(&edge_params(), &path);
    for _ in 0..40 {
        g.step(&TickInput {
            scans: &far_scans,
            ..bare(pose, true)
        })
        .unwrap();
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
    // A plan delay but no tolerance for this behaviour: consistent, and
    // entered, with GNSS.
    let mut no_tolerance = edge_params();
    no_tolerance.plan_delay = Some(Seconds::new(0.5).unwrap());
    let mut g = pipeline(&no_tolerance, &path);
    for _ in 0..40 {
        let out = g
            .step(&TickInput {
                scans: &far_scans,
                ..bare(pose, true)
            })
            .unwrap();
        assert!(status(&out, EDGE).plan_consistent);
        assert!(status(&out, EDGE).plan.is_some());
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
    // A wall 1.5 m left: the line is 0.1 m from the path, consistent.
    let near = wall_ranges(pose, long_wall(1.5));
    let mut g = pipeline(&params, &path);
    for _ in 0..40 {
        let out = g
            .step(&TickInput {
                scans: &[routed(EDGE, edge_scan(&near))],
                ..bare(pose, true)
            })
            .unwrap();
        assert!(status(&out, EDGE).plan_consistent);
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
}

//= spec/guidance.md#gd-plan-dead-reckoning-the-plan-checked-through-a-gnss-outage
//= type=test
//# When a dead-reckoning distance is configured and a tick has no GNSS pose,
//# the plan consistency of GD-PLAN MUST be judged from the pose of the last
//# fix moved by odometry: the tick's odometry pose in the robot frame of the
//# fix's odometry pose, placed at the fix, as long as the odometry distance
//# summed over the ticks since the fix is at most the configured distance;
//# beyond it, and before the first fix, the check MUST NOT judge.
//= spec/guidance.md#gd-plan-dead-reckoning-the-plan-checked-through-a-gnss-outage
//= type=test
//# Path tracking MUST NOT use the dead-reckoned pose: localisation stays
//# invalid without a fix (GD-LOCALISATION).
#[test]
fn through_an_outage_the_plan_is_checked_from_the_last_fix_moved_by_odometry() {
    let path = straight_path();
    let tolerance = PlanTolerance::new(m(0.3), Radians::new(0.2).unwrap()).unwrap();
    let mut params = with_plan(edge_params(), tolerance, Seconds::new(0.5).unwrap());
    params.plan_dead_reckoning = Some(m(5.0));
    // The robot drives 2 cm per tick along the world's x axis, 0.1 m left of
    // the path, heading 0.05 rad; odometry is exact but in a frame rotated by
    // 0.7 rad and shifted from the world's.
    let to_odom = Transform2::<World, Odom>::new(3.0, -2.0, 0.7).unwrap();
    let truth = |k: u32| world((0.02 * f64::from(k), 0.1, 0.05));
    // A wall 2.5 m left of the robot: its line is 1.1 m or more from the path.
    let far = wall_ranges((0.0, 0.0, 0.0), long_wall(2.5));
    let far_scans = [routed(EDGE, edge_scan(&far))];
    let tick = |g: &mut Pipeline<'_>, k: u32, fix: bool| {
        g.step(&TickInput {
            scans: &far_scans,
            gnss: fix.then(|| truth(k)),
            odometry: to_odom.apply_pose(truth(k)).unwrap(),
            extra: Sideslip::ZERO,
        })
        .unwrap()
    };
    // Before any fix: nothing to judge from, the line counts as consistent.
    let mut g = pipeline(&params, &path);
    let out = tick(&mut g, 0, false);
    assert_eq!(out.path.plan_pose, PlanPose::Unjudged);
    assert!(status(&out, EDGE).plan_consistent);
    let mut g = pipeline(&params, &path);
    for k in 0..=20 {
        let out = tick(&mut g, k, true);
        assert_eq!(out.path.plan_pose, PlanPose::Gnss);
    }
    let mut judged = 0;
    for k in 21..400 {
        let out = tick(&mut g, k, false);
        assert!(!out.path.localisation_valid && out.path.frenet.is_none());
        let travelled = 0.02 * f64::from(k - 20);
        match out.path.plan_pose {
            PlanPose::DeadReckoned {
                travelled: t,
                frenet,
            } => {
                judged += 1;
                assert!(travelled <= 5.0 + 1e-9, "tick {k}");
                assert!((t.get() - travelled).abs() < 1e-9);
                // The pose carried by exact odometry is the true one.
                let expected = path.project(&truth(k), m(0.8)).unwrap();
                assert!((frenet.s.get() - expected.s.get()).abs() < 1e-9);
                assert!((frenet.y.get() - expected.y.get()).abs() < 1e-9);
                assert!(
                    (frenet.angular_deviation.get() - expected.angular_deviation.get()).abs()
                        < 1e-9
                );
                assert!(!status(&out, EDGE).plan_consistent, "tick {k}");
            }
            PlanPose::Unjudged => {
                assert!(travelled > 5.0 - 1e-9, "tick {k}");
                assert!(status(&out, EDGE).plan_consistent);
            }
            PlanPose::Gnss => panic!("no fix in tick {k}"),
        }
        // The far line is never followed while it can be judged.
        if travelled <= 5.0 {
            assert_ne!(out.mode, Mode::Behaviour(EDGE), "tick {k}");
        }
    }
    assert_eq!(judged, 250);
    // Without dead reckoning, the outage cannot be judged and the line is
    // entered.
    let mut blind = params.clone();
    blind.plan_dead_reckoning = None;
    let mut g = pipeline(&blind, &path);
    for k in 0..=20 {
        tick(&mut g, k, true);
    }
    let mut out = tick(&mut g, 21, false);
    assert_eq!(out.path.plan_pose, PlanPose::Unjudged);
    for k in 22..100 {
        out = tick(&mut g, k, false);
    }
    assert_eq!(out.mode, Mode::Behaviour(EDGE));
}

//= spec/guidance.md#gd-plan-plan-consistency-of-the-detected-lines
//= type=test
//# The path ahead MUST be taken at the tolerance's look-ahead from the
//# projection's abscissa.
#[test]
fn a_line_going_straight_on_where_the_path_turns_is_not_entered() {
    // The path runs along x and turns left (radius 6 m) at x = 0; the robot
    // is at the turn's start with a straight wall 1.5 m to its left: the line
    // to follow is 0.1 m left of the path here, but 2 m ahead the path has
    // turned ≈ 0.23 m away from it (R (1 − cos φ) − d sin φ + 0.1 cos φ).
    let mut points: Vec<Point2<World>> = (0..=40)
        .map(|i| Point2::new(-20.0 + 0.5 * f64::from(i), 0.0).unwrap())
        .collect();
    points.extend((1..=40).map(|i| {
        let a = f64::from(i) * 0.05;
        Point2::new(6.0 * a.sin(), 6.0 * (1.0 - a.cos())).unwrap()
    }));
    let path: ReferencePath<PATH_N> =
        ReferencePath::from_waypoints(&points, PathConfig::new(m(0.2)).unwrap()).unwrap();
    let pose = (0.0, 0.0, 0.0);
    let wall = wall_ranges(pose, long_wall(1.5));
    let check = |lookahead: f64| {
        let tolerance = PlanTolerance::new(m(0.2), Radians::new(0.2).unwrap())
            .unwrap()
            .with_lookahead(m(lookahead))
            .unwrap();
        let params = with_plan(edge_params(), tolerance, Seconds::new(0.5).unwrap());
        let mut g = pipeline(&params, &path);
        let mut last = None;
        for _ in 0..60 {
            last = Some(
                g.step(&TickInput {
                    scans: &[routed(EDGE, edge_scan(&wall))],
                    ..bare(pose, true)
                })
                .unwrap(),
            );
        }
        let out = last.unwrap();
        let edge = status(&out, EDGE);
        // The offset reported is the one at the robot, whatever the look-ahead.
        let plan = edge.plan.unwrap();
        assert!((plan.offset.get() - 0.1).abs() < 1e-3, "{plan:?}");
        // The pipeline's flag is the tolerance's judgement with the path 2 m
        // ahead of the projection's abscissa.
        let frenet = out.path.frenet.unwrap();
        let ahead = PathAhead::on_path(&path, frenet.s, m(lookahead)).unwrap();
        let line = edge.error.unwrap();
        assert_eq!(
            edge.plan_consistent,
            tolerance.is_consistent(&line, &frenet.tracking_error(), &ahead)
        );
        (edge.plan_consistent, out.mode)
    };
    // Checked at the robot only: consistent, edge following entered.
    assert_eq!(check(0.0), (true, Mode::Behaviour(EDGE)));
    // Checked 2 m ahead too: inconsistent, never entered.
    assert_eq!(check(2.0), (false, Mode::PathTracking));
}

/// A straight path through the origin at `heading` radians from the world x
/// axis, from 20 m behind to 200 m ahead.
fn tilted_path(heading: f64) -> ReferencePath<PATH_N> {
    let points: Vec<Point2<World>> = (0..=44)
        .map(|i| {
            let t = -20.0 + 5.0 * f64::from(i);
            Point2::new(t * heading.cos(), t * heading.sin()).unwrap()
        })
        .collect();
    ReferencePath::from_waypoints(&points, PathConfig::default()).unwrap()
}

//= spec/guidance.md#gd-plan-entry-a-line-entered-only-near-the-path-s-heading
//= type=test
//# When a behaviour's plan tolerance has an entry heading, its line MUST be
//# reported consistent with the plan in a tick that starts outside that
//# behaviour's mode only when, in addition to GD-PLAN, its heading differs
//# from the path's by at most the entry heading; in a tick that starts in
//# the behaviour's mode, GD-PLAN alone MUST judge it.
#[test]
fn a_line_tilted_from_the_path_is_not_entered_but_is_kept() {
    // A wall along the world x axis 1.5 m left of the robot: the line to
    // follow is 0.1 m left of it, 0.1 rad from a path turned by −0.1 rad.
    let pose = (0.0, 0.0, 0.0);
    let wall = wall_ranges(pose, long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&wall))];
    let tick = TickInput {
        scans: &scans,
        ..bare(pose, true)
    };
    let (tilted, straight) = (tilted_path(-0.1), straight_path());
    let tolerance = PlanTolerance::new(m(0.3), Radians::new(0.2).unwrap()).unwrap();
    let with_entry = |entry: f64| {
        with_plan(
            edge_params(),
            tolerance
                .with_entry_heading(Radians::new(entry).unwrap())
                .unwrap(),
            Seconds::new(0.5).unwrap(),
        )
    };
    // An entry heading of 0.09 rad: within GD-PLAN's 0.2 rad, but never
    // entered.
    let params = with_entry(0.09);
    let mut g = pipeline(&params, &tilted);
    for _ in 0..200 {
        let out = g.step(&tick).unwrap();
        let edge = status(&out, EDGE);
        assert_eq!(edge.detected, Verdict::Enter);
        assert!((edge.plan.unwrap().heading.get() - 0.1).abs() < 1e-6);
        assert!(!edge.plan_consistent);
        assert_eq!(out.mode, Mode::PathTracking);
    }
    // 0.11 rad: entered after the 40 ticks of the entry delay.
    let mut g = pipeline(&with_entry(0.11), &tilted);
    let modes: Vec<Mode> = (0..40).map(|_| g.step(&tick).unwrap().mode).collect();
    assert_eq!(modes[38], Mode::PathTracking);
    assert_eq!(modes[39], Mode::Behaviour(EDGE));
    // Entered along a path parallel to the line, then the path turned: in
    // the mode only GD-PLAN's 0.2 rad judges, and the line is kept.
    let mut g = pipeline(&params, &straight);
    for _ in 0..40 {
        g.step(&tick).unwrap();
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
    g.set_path(&tilted);
    for _ in 0..200 {
        let out = g.step(&tick).unwrap();
        assert!(status(&out, EDGE).plan_consistent);
        assert_eq!(out.mode, Mode::Behaviour(EDGE));
    }
}

//= spec/guidance.md#gd-command-the-command-of-the-selected-source
//= type=test
//# A behaviour whose law refuses its error MUST be reported to the switching
//# machine as Exit in that tick, so that a command source is always a source
//# whose law gave a command.
#[test]
fn a_law_that_refuses_a_held_estimate_reports_exit() {
    let path = straight_path();
    let mut g = pipeline(&edge_params(), &path);
    let pose = (0.0, 0.0, 0.0);
    let ranges = wall_ranges(pose, long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    for _ in 0..40 {
        g.step(&TickInput {
            scans: &scans,
            ..bare(pose, true)
        })
        .unwrap();
    }
    assert_eq!(g.mode(), Mode::Behaviour(EDGE));
    // Odometry says the robot has turned 2 rad since the scan: the held line is
    // now behind its side, |θ̃| > π/2, and the law refuses it.
    let out = g
        .step(&TickInput {
            odometry: odom((0.0, 0.0, 2.0)),
            ..bare(pose, true)
        })
        .unwrap();
    let edge = status(&out, EDGE);
    assert_eq!(edge.detected, Verdict::Enter);
    assert!((edge.error.unwrap().angular_deviation.get() - 2.0).abs() < 1e-9);
    match edge.law {
        LawOutcome::Refused(e) => assert_eq!(e.requirement, "PT-HEADING"),
        other => panic!("{other:?}"),
    }
    assert_eq!(edge.reported, Verdict::Exit);
    // Still in edge following (its exit delay runs), steered by path tracking.
    assert_eq!(out.mode, Mode::Behaviour(EDGE));
    assert_eq!(out.source, Some(Mode::PathTracking));
    assert_eq!(command(&out).command.speed().get(), 0.8);
}

//= spec/guidance.md#gd-input-malformed-input
//= type=test
//# A tick whose input is malformed MUST be refused with an error before any
//# state changes: an extra input the law refuses (for backstepping a sideslip
//# outside |β| < π/2, `PT-SIDESLIP`), a scan routed to a behaviour that is not
//# configured, or two scans routed to one behaviour in one tick (`GD-INPUT`).
#[test]
fn malformed_input_is_refused_and_changes_nothing() {
    let path = straight_path();
    let mut g = pipeline(&edge_params(), &path);
    let pose = (0.0, 0.0, 0.0);
    let wall = wall_ranges(pose, long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&wall))];
    let good = TickInput {
        scans: &scans,
        ..bare(pose, true)
    };
    for _ in 0..20 {
        g.step(&good).unwrap();
    }
    let before = g.clone();
    let slip = Sideslip {
        front: Radians::new(1.7).unwrap(),
        rear: Radians::ZERO,
    };
    let err = g
        .step(&TickInput {
            extra: slip,
            ..good
        })
        .unwrap_err();
    assert_eq!(err.requirement, "PT-SIDESLIP");
    // A scan routed to a behaviour that is not configured, alone or with a
    // good one.
    let ridges = vec![2.0; 360];
    let l = furrow_lidar();
    let unconfigured = routed(FURROW, furrow_scan(&ridges, &l));
    for scans in [vec![unconfigured], vec![scans[0], unconfigured]] {
        let err = g
            .step(&TickInput {
                scans: &scans,
                ..good
            })
            .unwrap_err();
        assert_eq!(err.requirement, "GD-INPUT");
    }
    // Two scans routed to one behaviour in one tick.
    let err = g
        .step(&TickInput {
            scans: &[scans[0], scans[0]],
            ..good
        })
        .unwrap_err();
    assert_eq!(err.requirement, "GD-INPUT");
    // The refused ticks did not count: both pipelines continue identically
    // and enter edge following in the same (40th accepted) tick.
    let mut before = before;
    for k in 21..=45 {
        let a = g.step(&good).unwrap();
        let b = before.step(&good).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.mode == Mode::Behaviour(EDGE), k >= 40, "tick {k}");
    }
    // A horizontal scan for a pipeline without edge following.
    let mut p = pipeline(&pierre2022_furrow().unwrap(), &path);
    let err = p.step(&good).unwrap_err();
    assert_eq!(err.requirement, "GD-INPUT");
}

fn s(v: f64) -> Seconds {
    Seconds::new(v).unwrap()
}

fn v(x: f64) -> MetersPerSecond {
    MetersPerSecond::new(x).unwrap()
}

//= spec/guidance.md#gd-config-configuration-validated-once
//= type=test
//# A guidance configuration MUST be validated once, at construction, and refused
//# with an error naming the requirement that fails: a speed that is not positive
//# (`GD-SPEED`), a negative prediction horizon (`GD-PREDICTION`), a search window
//# that is not positive (`GD-LOCALISATION`), a maximal scan age that is negative
//# or longer than 65 534 ticks (`GD-SCAN-AGE`), or a delay of the switching
//# machine (`SW-DELAYS`, `SW-STOP`, `SW-PLAN-CONSISTENCY`).
//= spec/guidance.md#gd-plan-dead-reckoning-the-plan-checked-through-a-gnss-outage
//= type=test
//# A dead-reckoning distance that is not positive MUST be refused with
//# `GD-PLAN-DEAD-RECKONING`.
#[test]
fn each_bad_parameter_is_refused_naming_its_requirement() {
    let good = both_params(FURROW_FIRST);
    assert!(GuidanceConfig::new(&good).is_ok());
    type Change = Box<dyn Fn(&mut Params)>;
    let tolerance = PlanTolerance::new(m(0.3), Radians::new(0.2).unwrap()).unwrap();
    let cases: Vec<(Change, &str)> = vec![
        (Box::new(|p| p.path.speed = v(0.0)), "GD-SPEED"),
        (Box::new(|p| p.path.speed = v(-0.8)), "GD-SPEED"),
        (
            Box::new(|p| behaviour_mut(p, EDGE).speed = v(0.0)),
            "GD-SPEED",
        ),
        (
            Box::new(|p| behaviour_mut(p, FURROW).speed = v(-1.0)),
            "GD-SPEED",
        ),
        (Box::new(|p| p.path.horizon = s(-0.1)), "GD-PREDICTION"),
        (Box::new(|p| p.path.steering_lag = s(-0.1)), "GD-PREDICTION"),
        // A desired speed outside its law's speed schedule (PT-SCHEDULE-RANGE).
        (
            Box::new(|p| p.path.law.schedule = Some(schedule(1.0, 3.0))),
            "PT-SCHEDULE-RANGE",
        ),
        (
            Box::new(|p| behaviour_mut(p, EDGE).law.schedule = Some(schedule(0.5, 3.0))),
            "PT-SCHEDULE-RANGE",
        ),
        (
            Box::new(|p| p.path.search_window = m(0.0)),
            "GD-LOCALISATION",
        ),
        (Box::new(|p| p.max_scan_age = s(-0.01)), "GD-SCAN-AGE"),
        (Box::new(|p| p.max_scan_age = s(655.36)), "GD-SCAN-AGE"),
        (Box::new(|p| p.max_scan_age = s(655.35)), "GD-SCAN-AGE"),
        (
            Box::new(|p| p.plan_dead_reckoning = Some(m(0.0))),
            "GD-PLAN-DEAD-RECKONING",
        ),
        (
            Box::new(|p| p.plan_dead_reckoning = Some(m(-1.0))),
            "GD-PLAN-DEAD-RECKONING",
        ),
        (Box::new(|p| p.period = s(0.0)), "SW-DELAYS"),
        (
            Box::new(|p| behaviour_mut(p, EDGE).enter_delay = s(0.0)),
            "SW-DELAYS",
        ),
        (
            Box::new(|p| behaviour_mut(p, FURROW).exit_delay = s(-0.3)),
            "SW-DELAYS",
        ),
        (Box::new(|p| p.stop_delay = s(0.0)), "SW-STOP"),
        (
            Box::new(move |p| *p = with_plan(p.clone(), tolerance, s(0.0))),
            "SW-PLAN-CONSISTENCY",
        ),
        // A plan tolerance without a plan delay.
        (
            Box::new(move |p| behaviour_mut(p, EDGE).plan = Some(tolerance)),
            "SW-PLAN-CONSISTENCY",
        ),
    ];
    for (change, requirement) in cases {
        let mut p = good.clone();
        change(&mut p);
        assert_eq!(
            GuidanceConfig::new(&p).unwrap_err().requirement,
            requirement
        );
    }
    // The scan age in ticks: ⌊age / period⌋ without representation error.
    for (age, ticks) in [
        (0.0, 0),
        (0.004, 0),
        (0.01, 1),
        (0.095, 9),
        (0.1, 10),
        (0.07, 7),
    ] {
        let p = GuidanceParams {
            max_scan_age: s(age),
            plan_dead_reckoning: None,
            bridge: None,
            steer_before_resuming: false,
            handover: None,
            entry: None,
            fix: None,
            odometry_aid: None,
            ..good.clone()
        };
        assert_eq!(GuidanceConfig::new(&p).unwrap().max_scan_age_ticks(), ticks);
    }
    // The furrow detector's storage is checked when the pipeline is built.
    let path = straight_path();
    let config = GuidanceConfig::new(&good).unwrap();
    let small = Guidance::<'_, PATH_N, AnyDetector<512, 64, 512, 8>, BacksteppingConfig, 2>::new(
        config, &path,
    );
    assert_eq!(small.unwrap_err().requirement, "FUR-ACCUMULATE");
}

/// The longest maximal scan age, 65 534 ticks, is accepted and expires: the
/// age counter can always count one tick beyond it.
//= spec/guidance.md#gd-config-configuration-validated-once
//= type=test
//# A guidance configuration MUST be validated once, at construction, and refused
//# with an error naming the requirement that fails: a speed that is not positive
//# (`GD-SPEED`), a negative prediction horizon (`GD-PREDICTION`), a search window
//# that is not positive (`GD-LOCALISATION`), a maximal scan age that is negative
//# or longer than 65 534 ticks (`GD-SCAN-AGE`), or a delay of the switching
//# machine (`SW-DELAYS`, `SW-STOP`, `SW-PLAN-CONSISTENCY`).
//= spec/guidance.md#gd-scan-age-held-detections
//= type=test
//# In a tick without a new scan, a behaviour MUST report the verdict of its
//# latest scan, with the tracking error to that scan's line moved to the current
//# pose through odometry, as long as that scan is at most the maximal scan age
//# old; an older scan, a scan the detector refused, or no scan at all MUST give
//# Absent.
#[test]
fn the_longest_scan_age_of_65_534_ticks_is_accepted_and_expires() {
    // 655.35 s at 100 Hz is 65 535 ticks: refused.
    let too_long = GuidanceParams {
        max_scan_age: s(655.35),
        plan_dead_reckoning: None,
        bridge: None,
        steer_before_resuming: false,
        ..edge_params()
    };
    assert_eq!(
        GuidanceConfig::new(&too_long).unwrap_err().requirement,
        "GD-SCAN-AGE"
    );
    // 655.34 s is 65 534 ticks: accepted.
    let params = GuidanceParams {
        max_scan_age: s(655.34),
        plan_dead_reckoning: None,
        bridge: None,
        steer_before_resuming: false,
        ..edge_params()
    };
    let config = GuidanceConfig::new(&params).unwrap();
    assert_eq!(config.max_scan_age_ticks(), 65_534);
    assert_eq!(config.max_scan_age_ticks(), MAX_SCAN_AGE_TICKS);
    let path = straight_path();
    let mut g = pipeline(&params, &path);
    let pose = (0.0, 0.0, 0.0);
    let ranges = wall_ranges(pose, long_wall(1.5));
    let out = g
        .step(&TickInput {
            scans: &[routed(EDGE, edge_scan(&ranges))],
            ..bare(pose, false)
        })
        .unwrap();
    assert_eq!(status(&out, EDGE).detected, Verdict::Enter);
    // Held for 65 534 ticks without a scan.
    for age in 1..=65_534_u16 {
        let out = g.step(&bare(pose, false)).unwrap();
        let edge = status(&out, EDGE);
        assert_eq!(
            (edge.detected, edge.scan_age),
            (Verdict::Enter, Some(age)),
            "age {age}"
        );
    }
    // Expired in the next tick, and it stays expired as the counter saturates.
    for _ in 0..3 {
        let out = g.step(&bare(pose, false)).unwrap();
        let edge = status(&out, EDGE);
        assert_eq!(edge.detected, Verdict::Absent);
        assert_eq!(edge.error, None);
        assert_eq!(edge.scan_age, Some(u16::MAX));
    }
}

//= spec/guidance.md#gd-speed-desired-speed-per-mode
//= type=test
//# The speed of a command MUST be the desired speed of its source.
#[test]
fn the_presets_are_tables_1_and_2() {
    let p = both_params(FURROW_FIRST);
    assert_eq!(p.path.speed.get(), 0.8);
    assert_eq!(p.path.horizon.get(), 1.0);
    assert_eq!(p.path.law.gains.k_y(), -0.7);
    assert!(p.path.compensation);
    let e = behaviour(&p, EDGE);
    assert_eq!(e.label, "edge_following");
    assert_eq!(e.speed.get(), 0.4);
    assert_eq!(e.law.gains.k_y(), -0.75);
    let AnyDetectorConfig::Edge(edge) = e.detector else {
        panic!("edge following has an edge detector");
    };
    assert_eq!(edge.edge.offset().get(), 1.4);
    assert_eq!(edge.edge.radius().get(), 1.0);
    assert_eq!(edge.edge.max_chain_length().get(), 3.0);
    assert_eq!((edge.side, edge.mount), (Side::Left, mount()));
    let f = behaviour(&p, FURROW);
    assert_eq!(f.label, "furrow_pursuing");
    assert_eq!(f.speed.get(), 0.7);
    assert_eq!(f.law.gains.k_y(), -0.8);
    let AnyDetectorConfig::Furrow(furrow) = f.detector else {
        panic!("furrow pursuing has a furrow detector");
    };
    assert_eq!(furrow.params().averaged_scans, 25);
    // One vehicle for every law: wheelbase 2 m, steering limit 30°.
    let Vehicle::Bicycle(vehicle) = p.vehicle else {
        panic!("Pierre 2022's tractor is a bicycle");
    };
    assert_eq!(vehicle.wheelbase.get().get(), 2.0);
    assert_eq!(
        vehicle.max_steering.get().get(),
        core::f64::consts::FRAC_PI_6
    );
    assert!([p.path.law, e.law, f.law]
        .iter()
        .all(|l| l.vehicle == vehicle));
    let config = GuidanceConfig::new(&p).unwrap();
    assert_eq!(config.lookahead().get(), 0.8);
    // The steering's lag adds to the horizon (PT-FEEDFORWARD-LAG), and a
    // schedule holding the speeds is accepted.
    let mut lagged = p.clone();
    lagged.path.steering_lag = Seconds::new(0.25).unwrap();
    lagged.path.law.schedule = Some(schedule(0.3, 3.0));
    assert_eq!(
        GuidanceConfig::new(&lagged).unwrap().lookahead().get(),
        0.8 * 1.25
    );
    // Priority furrow first: behaviour 0 is furrow (0.5 s / 0.3 s), 1 is edge
    // (0.4 s / 0.26 s), in ticks at 100 Hz.
    let ticks = config.switching().all_ticks();
    assert_eq!((ticks[0].enter, ticks[0].exit), (50, 30));
    assert_eq!((ticks[1].enter, ticks[1].exit), (40, 26));
    assert_eq!(config.switching().stop_ticks(), 50);
    let path = straight_path();
    let g = pipeline(&p, &path);
    assert_eq!(g.label(Mode::Behaviour(FURROW)), "furrow_pursuing");
}

/// A test-only law: backstepping's, declared for `actuation`; for a
/// differential vehicle it commands both wheels at the desired speed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Declared {
    law: BacksteppingConfig,
    actuation: Actuation,
}

impl ControlLaw for Declared {
    type Extra = Sideslip;

    const NEUTRAL: Sideslip = Sideslip::ZERO;

    fn actuation(&self) -> Actuation {
        self.actuation
    }

    fn check_extra(extra: &Sideslip) -> Result<(), Precondition> {
        extra.check()
    }

    fn command(
        &self,
        error: &TrackingError,
        extra: &Sideslip,
        speed: MetersPerSecond,
    ) -> Result<Saturated, Precondition> {
        let bicycle = self.law.command(error, extra, speed)?;
        Ok(match self.actuation {
            Actuation::Differential => Saturated {
                command: Command::Differential {
                    left: speed,
                    right: speed,
                },
                saturated: bicycle.saturated,
            },
            _ => bicycle,
        })
    }
}

/// `params` with every law declared for the bicycle, except the path's law
/// (`path`) or behaviour `behaviour`'s, declared for a differential vehicle.
fn declared(
    params: &Params,
    path: bool,
    behaviour: Option<BehaviourId>,
) -> GuidanceParams<AnyDetectorConfig, Declared, 2> {
    let declare = |law, differential: bool| Declared {
        law,
        actuation: if differential {
            Actuation::Differential
        } else {
            Actuation::Bicycle
        },
    };
    GuidanceParams {
        period: params.period,
        vehicle: params.vehicle,
        path: fieldguide::guidance::PathTrackingParams {
            law: declare(params.path.law, path),
            speed: params.path.speed,
            horizon: params.path.horizon,
            steering_lag: params.path.steering_lag,
            compensation: params.path.compensation,
            search_window: params.path.search_window,
        },
        behaviours: params
            .behaviours
            .iter()
            .map(|b| BehaviourParams {
                id: b.id,
                label: b.label,
                detector: b.detector,
                law: declare(b.law, behaviour == Some(b.id)),
                speed: b.speed,
                enter_delay: b.enter_delay,
                exit_delay: b.exit_delay,
                plan: b.plan,
            })
            .collect(),
        priority: params.priority.clone(),
        stop_delay: params.stop_delay,
        plan_delay: params.plan_delay,
        max_scan_age: params.max_scan_age,
        plan_dead_reckoning: params.plan_dead_reckoning,
        bridge: params.bridge,
        steer_before_resuming: params.steer_before_resuming,
        handover: params.handover,
        entry: params.entry,
        fix: params.fix,
        odometry_aid: params.odometry_aid,
    }
}

//= spec/guidance.md#gd-vehicle-one-vehicle-one-command-type
//= type=test
//# A configuration whose path-tracking law or any behaviour's law commands
//# another actuation than the configured vehicle's MUST be refused with
//# `GD-VEHICLE`.
#[test]
fn a_law_for_another_actuation_than_the_vehicles_is_refused() {
    let params = both_params(FURROW_FIRST);
    for (path, behaviour) in [(true, None), (false, Some(EDGE)), (false, Some(FURROW))] {
        let p = declared(&params, path, behaviour);
        assert_eq!(
            GuidanceConfig::new(&p).unwrap_err().requirement,
            "GD-VEHICLE",
            "{path} {behaviour:?}"
        );
    }
    // Every law for the bicycle: accepted, and it drives the pipeline as
    // backstepping does.
    let p = declared(&params, false, None);
    let path = straight_path();
    let mut g: Guidance<'_, PATH_N, AnyDetector, Declared, 2> =
        Guidance::new(GuidanceConfig::new(&p).unwrap(), &path).unwrap();
    let mut reference = pipeline(&params, &path);
    for k in 0..20 {
        let tick = bare((0.1 * f64::from(k), 0.3, 0.05), true);
        let (a, b) = (g.step(&tick).unwrap(), reference.step(&tick).unwrap());
        assert_eq!(a.command, b.command);
        assert_eq!(a.command.unwrap().command.actuation(), Actuation::Bicycle);
    }
}

//= spec/guidance.md#gd-vehicle-one-vehicle-one-command-type
//= type=test
//# A command MUST be of the actuation of the vehicle it is sent to and
//# within that vehicle's actuator limits.
#[test]
fn commands_are_of_the_vehicles_actuation_and_within_its_limits() {
    let params = both_params(FURROW_FIRST);
    let path = straight_path();
    let mut g = pipeline(&params, &path);
    // Far off the path, steering saturates at the vehicle's limit; then Stop.
    let (mut saturated, mut stopped) = (false, false);
    for k in 0..120 {
        let out = g.step(&bare((1.0, 4.0, 0.0), k < 60)).unwrap();
        if let Some(c) = out.command {
            saturated |= c.saturated;
            stopped |= out.mode == Mode::Stop;
            assert_eq!(c.command.actuation(), params.vehicle.actuation());
            assert!(params.vehicle.check(&c.command).is_ok(), "{c:?}");
        }
    }
    assert!(saturated && stopped);
    // The vehicle refuses a command of another actuation or beyond its limit.
    let wheels = Command::Differential {
        left: v(0.5),
        right: v(0.5),
    };
    assert_eq!(
        params.vehicle.check(&wheels).unwrap_err().requirement,
        "GD-VEHICLE"
    );
    let beyond = Command::Bicycle {
        speed: v(0.5),
        steering: Radians::new(0.6).unwrap(),
    };
    assert_eq!(
        params.vehicle.check(&beyond).unwrap_err().requirement,
        "GD-VEHICLE"
    );
}

fn error(y: f64, theta: f64) -> TrackingError {
    TrackingError::to_straight_line(m(y), Radians::new(theta).unwrap())
}

/// The error to the line through `q` with heading `phi` (both in some frame)
/// of a robot at `(x, y, psi)` in that frame, by vectors.
fn error_to_line(q: (f64, f64), phi: f64, robot: (f64, f64, f64)) -> (f64, f64) {
    let n = (-phi.sin(), phi.cos());
    let y = (robot.0 - q.0) * n.0 + (robot.1 - q.1) * n.1;
    let mut t = robot.2 - phi;
    while t > PI {
        t -= TAU;
    }
    while t <= -PI {
        t += TAU;
    }
    (y, t)
}

//= spec/guidance.md#gd-odometry-errors-moved-by-odometry
//= type=test
//# For a straight line with error (y₀, θ̃₀) at the scan's pose, the robot at
//# (p_x, p_y, ψ) in the scan's robot frame MUST get y = y₀ + p_x sin θ̃₀ +
//# p_y cos θ̃₀ and θ̃ = wrap(θ̃₀ + ψ); for two rows, the mean of the two moved
//# errors; for an edge parabola, y = y₀(p_x) + p_y cos θ̃₀(p_x) and θ̃ =
//# wrap(θ̃₀(p_x) + ψ), where (y₀(p_x), θ̃₀(p_x)) is the error of EDGE-OFFSET at
//# x_r = p_x.
#[test]
fn moved_errors_by_hand() {
    // A line 0.5 m to the robot's right (robot left of it: y₀ = 0.5), heading
    // 0.2 rad left of the robot (θ̃₀ = −0.2). The robot moves 1 m forward,
    // 0.1 m left and turns 0.05 rad.
    let pose = Pose2::<Robot>::new(1.0, 0.1, 0.05).unwrap();
    let e = moved_line_error(&error(0.5, -0.2), &pose).unwrap();
    let y = 0.5 + 1.0 * (-0.2_f64).sin() + 0.1 * (-0.2_f64).cos();
    assert!((e.y.get() - y).abs() < 1e-15);
    assert!((e.angular_deviation.get() + 0.15).abs() < 1e-15);
    // Wrapped: θ̃₀ = 3 and ψ = 0.5 give 3.5 − 2π.
    let turned = Pose2::<Robot>::new(0.0, 0.0, 0.5).unwrap();
    let e = moved_line_error(&error(0.0, 3.0), &turned).unwrap();
    assert!((e.angular_deviation.get() - (3.5 - TAU)).abs() < 1e-12);

    // A left wall y = 0.1 x + 1.5 (a straight parabola), D = 1.4: eq. 11 at
    // x_r = 1 gives y₀ = 1.4 − 1.6 cos φ, θ̃₀ = −φ, φ = arctan 0.1.
    let edge = EdgeLine {
        parabola: ParabolaFit {
            a: 0.0,
            b: 0.1,
            c: 1.5,
        },
        side: Side::Left,
        offset: m(1.4),
    };
    let e = edge.error_at(&pose).unwrap();
    let phi = 0.1_f64.atan();
    assert!((e.y.get() - (1.4 - 1.6 * phi.cos() + 0.1 * phi.cos())).abs() < 1e-12);
    assert!((e.angular_deviation.get() - (0.05 - phi)).abs() < 1e-12);
    // The same by vectors: the wall line shifted 1.4 m to its right.
    let q = (0.0 + 1.4 * phi.sin(), 1.5 - 1.4 * phi.cos());
    let (y, t) = error_to_line(q, phi, (1.0, 0.1, 0.05));
    assert!((e.y.get() - y).abs() < 1e-12 && (e.angular_deviation.get() - t).abs() < 1e-12);

    // Two rows: the mean of both moved errors.
    let left = RowLine::new(0.05, m(0.4)).unwrap();
    let right = RowLine::new(-0.02, m(-0.35)).unwrap();
    let two = RowLines::Two(Pair { left, right }).error_at(&pose).unwrap();
    let l = moved_line_error(&lines::tracking_error(&left).unwrap(), &pose).unwrap();
    let r = moved_line_error(&lines::tracking_error(&right).unwrap(), &pose).unwrap();
    assert!((two.y.get() - 0.5 * (l.y.get() + r.y.get())).abs() < 1e-15);
    assert!(
        (two.angular_deviation.get()
            - 0.5 * (l.angular_deviation.get() + r.angular_deviation.get()))
        .abs()
            < 1e-15
    );
    let one = RowLines::One(left).error_at(&pose).unwrap();
    assert_eq!(one, l);
}

proptest! {
    /// The moved error equals the error computed afresh in the new robot
    /// frame: the row line transformed into it, then FUR-ERRORS (an oracle
    /// that shares nothing with the motion formula).
    //= spec/guidance.md#gd-odometry-errors-moved-by-odometry
    //= type=test
    //# For a straight line with error (y₀, θ̃₀) at the scan's pose, the robot at
    //# (p_x, p_y, ψ) in the scan's robot frame MUST get y = y₀ + p_x sin θ̃₀ +
    //# p_y cos θ̃₀ and θ̃ = wrap(θ̃₀ + ψ); for two rows, the mean of the two moved
    //# errors; for an edge parabola, y = y₀(p_x) + p_y cos θ̃₀(p_x) and θ̃ =
    //# wrap(θ̃₀(p_x) + ψ), where (y₀(p_x), θ̃₀(p_x)) is the error of EDGE-OFFSET at
    //# x_r = p_x.
    #[test]
    fn moving_a_row_line_agrees_with_recomputing_it(
        slope in -1.0..1.0_f64,
        intercept in -3.0..3.0_f64,
        then in (-50.0..50.0_f64, -50.0..50.0_f64, -PI..PI),
        step in (-2.0..2.0_f64, -0.5..0.5_f64, -0.6..0.6_f64),
    ) {
        let line = RowLine::new(slope, m(intercept)).unwrap();
        let then_pose = odom(then);
        // The new pose: `step` in the old robot frame, into Odom.
        let (c, s) = (then.2.cos(), then.2.sin());
        let now_pose = odom((
            then.0 + c * step.0 - s * step.1,
            then.1 + s * step.0 + c * step.1,
            then.2 + step.2,
        ));
        let pose = pose_in_scan_frame(&then_pose, &now_pose).unwrap();
        prop_assert!((pose.position.x() - step.0).abs() < 1e-9);
        prop_assert!((pose.position.y() - step.1).abs() < 1e-9);
        let moved = RowLines::One(line).error_at(&pose).unwrap();
        // Oracle: two points of the line into the new frame, a new RowLine.
        let to_new = |x: f64, y: f64| {
            let (dx, dy) = (x - step.0, y - step.1);
            let (c, s) = (step.2.cos(), step.2.sin());
            (c * dx + s * dy, -s * dx + c * dy)
        };
        let p0 = to_new(0.0, line.y_at(0.0).unwrap());
        let p1 = to_new(1.0, line.y_at(1.0).unwrap());
        let new_slope = (p1.1 - p0.1) / (p1.0 - p0.0);
        let new_line = RowLine::new(new_slope, m(p0.1 - new_slope * p0.0)).unwrap();
        let fresh = lines::tracking_error(&new_line).unwrap();
        prop_assert!((moved.y.get() - fresh.y.get()).abs() < 1e-9);
        prop_assert!((moved.angular_deviation.get() - fresh.angular_deviation.get()).abs() < 1e-9);
    }
}

/// What one synthetic tick holds.
#[derive(Debug, Clone, Copy)]
enum Gnss {
    On,
    Off,
    Backwards,
}

#[derive(Debug, Clone, Copy)]
enum Horizontal {
    None,
    Wall,
    Garbage,
}

#[derive(Debug, Clone, Copy)]
enum Inclined {
    None,
    Rows,
    Flat,
    Garbage,
}

#[derive(Debug, Clone, Copy)]
struct Segment {
    gnss: Gnss,
    horizontal: Horizontal,
    inclined: Inclined,
    scan_every: usize,
    ticks: usize,
}

fn segment() -> impl Strategy<Value = Segment> {
    (
        prop_oneof![3 => Just(Gnss::On), 2 => Just(Gnss::Off), 1 => Just(Gnss::Backwards)],
        prop_oneof![
            Just(Horizontal::None),
            Just(Horizontal::Wall),
            Just(Horizontal::Garbage)
        ],
        prop_oneof![
            Just(Inclined::None),
            Just(Inclined::Rows),
            Just(Inclined::Flat),
            Just(Inclined::Garbage)
        ],
        1..12usize,
        1..90usize,
    )
        .prop_map(|(gnss, horizontal, inclined, scan_every, ticks)| Segment {
            gnss,
            horizontal,
            inclined,
            scan_every,
            ticks,
        })
}

/// Deterministic garbage: any f64, NaN, infinities, negatives, huge values.
fn garbage(seed: u64, n: usize) -> Vec<f64> {
    let mut x = seed | 1;
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            match x % 8 {
                0 => f64::NAN,
                1 => f64::INFINITY,
                2 => -1.0,
                3 => f64::from_bits(x),
                4 => 1e300,
                _ => (x % 3000) as f64 / 100.0,
            }
        })
        .collect()
}

fn finite_error(e: &Option<TrackingError>) -> bool {
    e.is_none_or(|e| e.y.get().is_finite() && e.angular_deviation.get().is_finite())
}

/// The property checks of one tick (GD-COMMAND, GD-SPEED, GD-STOP,
/// GD-VEHICLE).
fn check_tick(out: &Out, params: &Params) -> Result<(), TestCaseError> {
    match out.source {
        Some(Mode::PathTracking) => {
            prop_assert!(out.path.localisation_valid);
            prop_assert_ne!(out.mode, Mode::Stop);
            prop_assert_eq!(out.command, out.path.law.command().copied());
            prop_assert_eq!(out.command.unwrap().command.speed(), params.path.speed);
        }
        Some(Mode::Behaviour(id)) => {
            prop_assert_eq!(out.mode, Mode::Behaviour(id));
            let b = status(out, id);
            prop_assert!(b.reported.estimate_is_valid());
            prop_assert!(b.detected.estimate_is_valid());
            prop_assert_eq!(out.command, b.law.command().copied());
            prop_assert_eq!(
                out.command.unwrap().command.speed(),
                behaviour(params, id).speed
            );
        }
        Some(Mode::Stop) => prop_assert!(false, "Stop is never a source"),
        None => match out.command {
            Some(c) => {
                prop_assert_eq!(out.mode, Mode::Stop);
                prop_assert_eq!(c.command.speed(), MetersPerSecond::ZERO);
                prop_assert!(!c.saturated);
            }
            None => prop_assert_ne!(out.mode, Mode::Stop),
        },
    }
    if let Some(c) = out.command {
        let steering = c.command.steering();
        prop_assert!(steering.is_some_and(|s| s.get().is_finite()));
        prop_assert!(c.command.speed().get().is_finite());
        prop_assert!(
            steering.is_some_and(|s| s.get().abs() <= core::f64::consts::FRAC_PI_6 + 1e-12)
        );
        prop_assert!(params.vehicle.check(&c.command).is_ok());
    }
    prop_assert_eq!(out.behaviours.len(), params.behaviours.len());
    for b in &out.behaviours {
        prop_assert_eq!(b.detected == Verdict::Absent, b.error.is_none());
        prop_assert!(finite_error(&b.error));
        match b.law {
            LawOutcome::Refused(_) => prop_assert_eq!(b.reported, Verdict::Exit),
            LawOutcome::Commanded(_) => prop_assert_eq!(b.reported, b.detected),
            LawOutcome::NotRun => prop_assert!(!b.detected.estimate_is_valid()),
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Every command comes from a source valid in its tick, is that source's
    /// law output at that source's speed, and a command without a source is a
    /// stop; over random sequences of GNSS outages, walls, rows and garbage.
    //= spec/guidance.md#gd-command-the-command-of-the-selected-source
    //= type=test
    //# The command MUST be the saturated output of the selected source's control law
    //# on that source's error of the tick, and no other; when the machine selects no
    //# source outside Stop, there MUST be no command.
    //= spec/guidance.md#gd-stop-the-stop-command
    //= type=test
    //# In Stop the command MUST be the stop of the last command made (every speed
    //# zero, steering angles held, a yaw rate zero), or the vehicle at rest before
    //# any command, never saturated.
    //= spec/guidance.md#gd-vehicle-one-vehicle-one-command-type
    //= type=test
    //# A command MUST be of the actuation of the vehicle it is sent to and
    //# within that vehicle's actuator limits.
    #[test]
    fn every_command_comes_from_a_source_valid_in_its_tick(
        segments in prop::collection::vec(segment(), 1..8),
        edge_first in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let priority = if edge_first { EDGE_FIRST } else { FURROW_FIRST };
        let params = both_params(priority);
        let path = straight_path();
        let mut g = pipeline(&params, &path);
        let lidar = furrow_lidar();
        let rows = two_rows();
        let mut k = 0usize;
        let mut last = Actuation::Bicycle.at_rest();
        for seg in segments {
            for i in 0..seg.ticks {
                let pose = (0.007 * k as f64, 0.05 * (k as f64 * 0.01).sin(), 0.0);
                let scan_now = i % seg.scan_every == 0;
                let h = match seg.horizontal {
                    Horizontal::Wall => Some(wall_ranges(pose, long_wall(1.5))),
                    Horizontal::Garbage => Some(garbage(seed ^ k as u64, RAYS)),
                    Horizontal::None => None,
                };
                let f = match seg.inclined {
                    Inclined::Rows => Some(ridge_scan(&furrow_params(), &lidar, pose, &rows)),
                    Inclined::Flat => Some(vec![1.0 / (0.38_f64).sin(); 360]),
                    Inclined::Garbage => Some(garbage(seed.rotate_left(7) ^ k as u64, 360)),
                    Inclined::None => None,
                };
                let gnss = match seg.gnss {
                    Gnss::On => Some(world(pose)),
                    Gnss::Off => None,
                    Gnss::Backwards => Some(world((pose.0, pose.1, PI))),
                };
                let mut scans = Vec::new();
                if let Some(h) = h.as_deref().filter(|_| scan_now) {
                    scans.push(routed(EDGE, edge_scan(h)));
                }
                if let Some(f) = f.as_deref().filter(|_| scan_now) {
                    scans.push(routed(FURROW, furrow_scan(f, &lidar)));
                }
                let input = TickInput {
                    scans: &scans,
                    gnss,
                    odometry: odom(pose),
                    extra: Sideslip::new(0.01, -0.02).unwrap(),
                };
                let out = g.step(&input).unwrap();
                check_tick(&out, &params)?;
                if out.mode == Mode::Stop {
                    prop_assert_eq!(out.command.unwrap().command, last.stopped());
                } else if let Some(c) = out.command {
                    last = c.command;
                }
                k += 1;
            }
        }
    }

    /// Scans of any f64 (NaN, infinities, negatives, huge values) and any ray
    /// geometry give an output, never a panic, and finite numbers.
    //= spec/guidance.md#gd-input-malformed-input
    //= type=test
    //# Sensor data MUST NOT be malformed input: any range, NaN and infinities
    //# included, and any scan a detector refuses MUST give a tick output, the
    //# refused scan counting as no estimate.
    #[test]
    fn any_scan_gives_an_output(
        horizontal in prop::collection::vec(any::<f64>(), 0..400),
        inclined in prop::collection::vec(any::<f64>(), 0..400),
        start in -10.0..10.0_f64,
        increment in prop_oneof![Just(0.0), -1.0..1.0_f64, Just(1e300)],
        angle_min in -10.0..10.0_f64,
        angle_increment in prop_oneof![Just(0.0), -1.0..1.0_f64, Just(1e-300)],
        pose in (-1e6..1e6_f64, -1e6..1e6_f64, -10.0..10.0_f64),
        ticks in 1..4usize,
    ) {
        let params = both_params(FURROW_FIRST);
        let path = straight_path();
        let mut g = pipeline(&params, &path);
        for _ in 0..ticks {
            let scans = [
                routed(
                    EDGE,
                    Scan {
                        start: Radians::new(start).unwrap(),
                        increment: Radians::new(increment).unwrap(),
                        ranges: &horizontal,
                        limits: limits(),
                    },
                ),
                routed(
                    FURROW,
                    Scan {
                        start: Radians::new(angle_min).unwrap(),
                        increment: Radians::new(angle_increment).unwrap(),
                        ranges: &inclined,
                        limits: furrow_limits(),
                    },
                ),
            ];
            let out = g
                .step(&TickInput {
                    scans: &scans,
                    gnss: Some(world(pose)),
                    odometry: odom(pose),
                    extra: Sideslip::ZERO,
                })
                .unwrap();
            check_tick(&out, &params)?;
            if let Some(f) = out.path.frenet {
                prop_assert!(f.y.get().is_finite() && f.s.get().is_finite());
            }
        }
    }
}

/// A robot at 0.08 rad across the path and the rows along it, its odometry
/// frame turned 0.5 rad from the world's and shifted: the furrow detector's
/// first line is the rows', θ̃ the robot's heading to them, since the
/// pipeline gives it the path's heading in the odometry frame (along the
/// robot's own heading, θ̃ would be 0 and y 0.2 m off).
//= spec/guidance.md#gd-expected-heading-the-path-s-heading-given-to-the-detectors
//= type=test
//# Before each behaviour's scan, the pipeline MUST give its detector the
//# heading of the path's chord from path tracking's projection to 4 m ahead of
//# it, in the odometry frame (the odometry heading less the angular deviation,
//# less the path's heading at the projection, plus the chord's), from the
//# latest tick that had a path pose, or none when no tick had one.
#[test]
fn the_furrow_first_line_is_taken_along_the_path() {
    let path = straight_path();
    let params = pierre2022_furrow().unwrap();
    let mut g = pipeline(&params, &path);
    let lidar = furrow_lidar();
    let rows = two_rows();
    let (psi, turn, shift) = (0.08_f64, 0.5_f64, (3.0, -2.0));
    let in_odom = |p: (f64, f64, f64)| {
        let (s, c) = turn.sin_cos();
        (
            shift.0 + c * p.0 - s * p.1,
            shift.1 + s * p.0 + c * p.1,
            p.2 + turn,
        )
    };
    let mut first = None;
    for k in 0..200 {
        let pose = (
            0.007 * k as f64 * psi.cos(),
            0.05 + 0.007 * k as f64 * psi.sin(),
            psi,
        );
        let ranges = ridge_scan(&furrow_params(), &lidar, pose, &rows);
        let scans = (k % 10 == 0).then(|| routed(FURROW, furrow_scan(&ranges, &lidar)));
        let out = g
            .step(&TickInput {
                scans: scans.as_slice(),
                gnss: Some(world(pose)),
                odometry: odom(in_odom(pose)),
                extra: Sideslip::ZERO,
            })
            .unwrap();
        if let Some(e) = status(&out, FURROW).error {
            first.get_or_insert((e, pose));
        }
    }
    let (e, pose) = first.expect("a first line");
    assert!((e.angular_deviation.get() - psi).abs() < 0.01, "{e:?}");
    assert!((e.y.get() - pose.1).abs() < 0.06, "{e:?} at {pose:?}");
}

//= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
//= type=test
//# When an odometry aid is configured, every step of a tick MUST use, in place
//# of the tick's odometry pose, the aided pose: in the first tick the odometry
//# pose itself, in every later tick the previous aided pose moved by the
//# odometry's increment since the previous tick (the tick's odometry pose in
//# the robot frame of the previous tick's), its heading then turned by the
//# tick's correction.
#[test]
fn a_held_detection_is_carried_by_the_aided_odometry() {
    let path = straight_path();
    let pose = (0.0, 0.0, 0.0);
    let ranges = wall_ranges(pose, long_wall(1.5));
    let scans = [routed(EDGE, edge_scan(&ranges))];
    // The robot and its fix stand still; the wheels turn the odometry
    // 0.01 rad a tick. The held wall's heading error turns with the pose
    // the pipeline carries it by: the raw one, or the aided one, held by
    // the fix's heading at most the largest step a tick.
    let turned = |aid: Option<(f64, f64)>| {
        let mut params = edge_params();
        params.odometry_aid = aid.map(|(tau, rate)| OdometryAidParams {
            time_constant: Seconds::new(tau).unwrap(),
            max_rate: RadiansPerSecond::new(rate).unwrap(),
        });
        let mut g = pipeline(&params, &path);
        let first = g
            .step(&TickInput {
                scans: &scans,
                ..bare(pose, true)
            })
            .unwrap();
        let seen = status(&first, EDGE).error.unwrap().angular_deviation.get();
        let mut held = seen;
        for k in 1..=5 {
            let out = g
                .step(&TickInput {
                    odometry: odom((0.0, 0.0, 0.01 * f64::from(k))),
                    ..bare(pose, true)
                })
                .unwrap();
            held = status(&out, EDGE).error.unwrap().angular_deviation.get();
        }
        held - seen
    };
    assert!((turned(None) - 0.05).abs() < 1e-9);
    assert!(turned(Some((1.0e-6, 100.0))).abs() < 1e-9);
    // 0.5 rad/s: 0.005 rad a tick taken out of the wheels' 0.01.
    assert!((turned(Some((1.0e-6, 0.5))) - 0.025).abs() < 1e-9);
}
