//! The checks every detector and every control law gets by implementing the
//! core's traits (`spec/guidance.md`, GD-DETECTOR, GD-LAW): one property
//! generic over `perception::Detector` and one over `control::ControlLaw`,
//! run here on each of the library's detectors and laws. A later detector or
//! law adds one line to the list at the bottom of each.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

mod crop_scans;
mod edge_support;
mod furrow_common;
mod vine_scans;

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::control::ControlLaw;
use fieldguide::model::Vehicle;
use fieldguide::perception::edge::{EdgeConfig, EdgeDetector, EdgeDetectorConfig, Side};
use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector, FurrowParams};
use fieldguide::perception::rows::ruby::Variant;
use fieldguide::perception::rows::spacing::SpacingConfig;
use fieldguide::perception::rows::{RowsConfig, RowsDetector, RowsParams};
use fieldguide::perception::{
    AnyDetector, AnyDetectorConfig, Detector, HeldLine, RangeLimits, Scan, Verdict,
};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Odom, Pose2, Radians, Robot, TrackingError, Transform2,
};
use proptest::prelude::*;

/// Scans per case, 0.1 m apart.
const SCANS: usize = 10;

/// A range as a faulty or hostile LiDAR may send it.
fn wild_range() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.0..30.0_f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::MIN_POSITIVE / 4.0),
        1 => Just(-0.0_f64),
        1 => any::<f64>(),
        1 => prop_oneof![Just(1e300), Just(-1e300), Just(f64::MAX)],
    ]
}

/// A scan's worth of ranges: a real one (a wall for the edge detector,
/// ridges for the furrow detector) with some rays replaced by wild values,
/// or wild values throughout.
#[derive(Debug, Clone)]
struct Frames {
    /// The rays' first angle and increment, rad.
    start: f64,
    increment: f64,
    /// One range vector per scan, fed in order.
    scans: Vec<Vec<f64>>,
    /// The odometry pose of each scan, (x, y, heading).
    poses: Vec<(f64, f64, f64)>,
    /// Poses to move the last held line to, in its scan's robot frame.
    moves: Vec<(f64, f64, f64)>,
}

fn corrupt(base: Vec<f64>, faults: &[(usize, f64)]) -> Vec<f64> {
    let mut r = base;
    let n = r.len();
    for &(i, v) in faults {
        if let Some(slot) = r.get_mut(i % n.max(1)) {
            *slot = v;
        }
    }
    r
}

fn pose() -> impl Strategy<Value = (f64, f64, f64)> {
    prop_oneof![
        4 => (-5.0..5.0_f64, -5.0..5.0_f64, -PI..PI),
        1 => (
            prop_oneof![Just(1e300), Just(-1e300), -1e6..1e6_f64],
            prop_oneof![Just(1e300), Just(-1e300), -1e6..1e6_f64],
            -1e6..1e6_f64
        ),
    ]
}

fn frames(
    base: impl Fn(usize, (f64, f64, f64)) -> Vec<f64> + Clone + 'static,
    rays: usize,
) -> impl Strategy<Value = Frames> {
    let scan = move |k: usize| {
        let base = base.clone();
        (
            prop::collection::vec((0..rays, wild_range()), 0..12),
            prop::collection::vec(wild_range(), 0..rays),
            0..4_u8,
            (-0.05..0.05_f64, -0.3..0.3_f64, -0.05..0.05_f64),
        )
            .prop_map(move |(faults, wild, kind, (dx, dy, dh))| {
                let pose = (0.1 * k as f64 + dx, dy, dh);
                let ranges = match kind {
                    0 => wild,
                    _ => corrupt(base(k, pose), &faults),
                };
                (ranges, pose)
            })
    };
    let scans = (0..SCANS).map(scan).collect::<Vec<_>>();
    (
        prop_oneof![4 => Just(None), 1 => (-10.0..10.0_f64, -1.0..1.0_f64).prop_map(Some)],
        scans,
        prop::collection::vec(pose(), 1..6),
    )
        .prop_map(move |(angles, scans, moves)| {
            let (start, increment) = angles.unwrap_or((-PI, TAU / rays as f64));
            let (scans, poses) = scans.into_iter().unzip();
            Frames {
                start,
                increment,
                scans,
                poses,
                moves,
            }
        })
}

/// The property of GD-DETECTOR for detector type `D`: any scans give a
/// detection or an error, never a panic; a detection has a finite error and
/// a line exactly when its verdict is not Absent, and a finite quality when
/// it has one; a held line moved anywhere gives a finite error or an error.
fn check_detector<D: Detector>(
    config: &D::Config,
    limits: RangeLimits,
    frames: &Frames,
) -> Result<(), TestCaseError> {
    let mut detector = D::configure(config).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let (Ok(start), Ok(increment)) = (Radians::new(frames.start), Radians::new(frames.increment))
    else {
        return Ok(());
    };
    for (ranges, &(x, y, h)) in frames.scans.iter().zip(&frames.poses) {
        let scan = Scan {
            start,
            increment,
            ranges,
            limits,
        };
        let odometry = Pose2::<Odom>::new(x, y, h).unwrap();
        let Ok(d) = detector.observe(&scan, &odometry) else {
            continue;
        };
        let absent = d.verdict == Verdict::Absent;
        prop_assert_eq!(d.error.is_none(), absent);
        prop_assert_eq!(d.line.is_none(), absent);
        if let Some(e) = d.error {
            prop_assert!(e.y.get().is_finite() && e.angular_deviation.get().is_finite());
            prop_assert!(e.angular_deviation.get().abs() <= PI);
        }
        if let Some(q) = d.quality {
            prop_assert!(q.is_finite(), "quality {q}");
        }
        if let Some(line) = d.line {
            for &(px, py, ph) in &frames.moves {
                let Ok(p) = Pose2::<Robot>::new(px, py, ph) else {
                    continue;
                };
                if let Ok(e) = line.error_at(&p) {
                    prop_assert!(e.y.get().is_finite());
                    prop_assert!(e.angular_deviation.get().abs() <= PI);
                }
            }
            // Not moved at all: the detection's own error.
            let here = line.error_at(&Pose2::new(0.0, 0.0, 0.0).unwrap());
            if let (Ok(moved), Some(e)) = (here, d.error) {
                prop_assert!((moved.y.get() - e.y.get()).abs() <= 1e-9 * (1.0 + e.y.get().abs()));
            }
        }
    }
    Ok(())
}

fn edge_config() -> EdgeDetectorConfig {
    EdgeDetectorConfig {
        edge: EdgeConfig::pierre2022().unwrap(),
        mount: Transform2::new(1.2, 0.0, 0.0).unwrap(),
        side: Side::Left,
    }
}

fn edge_limits() -> RangeLimits {
    RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap()
}

/// A wall 1.5 m to the left of O, seen from the mount, at the scan's pose.
fn wall(_k: usize, (_, y, h): (f64, f64, f64)) -> Vec<f64> {
    let rays = 360;
    let (s, c) = h.sin_cos();
    // The wall y = 1.5 in the odometry frame, in the robot frame of the pose.
    let n = (-s, c);
    let k = 1.5 - y;
    edge_support::cast_line((1.2, 0.0, 0.0), n, k, -PI, TAU / rays as f64, rays, 30.0)
}

fn furrow_params() -> FurrowParams {
    FurrowParams::table2()
}

fn furrow_lidar() -> furrow_common::Lidar {
    furrow_common::Lidar::centred(360, FRAC_PI_2)
}

fn furrow_limits() -> RangeLimits {
    RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(20.0).unwrap()).unwrap()
}

/// Two rows of maize 0.75 m apart either side of the odometry x axis, at the scan's pose.
fn ridges(_k: usize, pose: (f64, f64, f64)) -> Vec<f64> {
    let ridge = |y| furrow_common::Ridge {
        center_y: y,
        half_width: 0.08,
        height: 0.5,
    };
    furrow_common::ridge_scan(
        &furrow_params(),
        &furrow_lidar(),
        pose,
        &[ridge(0.375), ridge(-0.375)],
    )
}

fn furrow_frames() -> impl Strategy<Value = Frames> {
    let lidar = furrow_lidar();
    frames(ridges, lidar.rays).prop_map(move |mut f| {
        if f.start == -PI {
            f.start = lidar.angle_min;
            f.increment = lidar.increment;
        }
        f
    })
}

//= spec/guidance.md#gd-detector-one-trait-for-every-detector
//= type=test
//# Every detector MUST be configured and validated once, and MUST turn any
//# scan, with the odometry pose it was taken at, into a detection (a verdict,
//# a finite tracking error and line exactly when the verdict is not Absent, a
//# finite quality figure when it has one) or a `Precondition` error.
proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn the_edge_detector_keeps_the_detector_contract(f in frames(wall, 360)) {
        check_detector::<EdgeDetector<512, 64>>(&edge_config(), edge_limits(), &f)?;
        check_detector::<AnyDetector>(&AnyDetectorConfig::Edge(edge_config()), edge_limits(), &f)?;
    }

    #[test]
    fn the_rows_detector_keeps_the_detector_contract(f in rows_frames()) {
        // Two scans measure the row distance, whatever the odometry says,
        // so that the frames reach the filter.
        let mut params = RowsParams::authors(Variant::Rgop, Transform2::new(0.3, 0.0, 0.0).unwrap());
        params.spacing = SpacingConfig::new(0.05, 0.25, 2, 4).unwrap();
        params.still = Meters::new(10.0).unwrap();
        check_detector::<RowsDetector<512>>(&RowsConfig::new(params).unwrap(), rows_limits(), &f)?;
    }

    #[test]
    fn the_furrow_detector_keeps_the_detector_contract(f in furrow_frames()) {
        let config = FurrowConfig::new(&furrow_params()).unwrap();
        check_detector::<FurrowDetector<512, 32>>(&config, furrow_limits(), &f)?;
        check_detector::<AnyDetector>(&AnyDetectorConfig::Furrow(config), furrow_limits(), &f)?;
    }

    #[test]
    fn the_vine_detector_keeps_the_detector_contract(f in vine_frames()) {
        let config = fieldguide::perception::vine::VineConfig::new(&fieldguide::perception::vine::VineParams::summer()).unwrap();
        check_detector::<fieldguide::perception::vine::VineDetector<512, 64>>(&config, vine_limits(), &f)?;
        check_detector::<AnyDetector>(&AnyDetectorConfig::Vine(config), vine_limits(), &f)?;
    }
}

fn vine_limits() -> RangeLimits {
    RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(20.0).unwrap()).unwrap()
}

/// Three rows of summer vines 2.2 m apart, the robot straddling the middle
/// one, at the scan's pose (`vine_scans`).
fn vine_rows(_k: usize, pose: (f64, f64, f64)) -> Vec<f64> {
    use std::sync::OnceLock;
    static WORLD: OnceLock<vine_scans::World> = OnceLock::new();
    let world = WORLD.get_or_init(|| {
        vine_scans::vineyard(vine_scans::World::ground(0.02, 0.15), 2.2, 0.25, &[])
    });
    vine_scans::Lidar::table1().cast(world, pose)
}

fn vine_frames() -> impl Strategy<Value = Frames> {
    let lidar = vine_scans::Lidar::table1();
    frames(vine_rows, lidar.rays).prop_map(move |mut f| {
        if f.start == -PI {
            f.start = lidar.start;
            f.increment = lidar.increment;
        }
        f
    })
}

/// The vine contract scans, clean, do detect once enough set-points are kept.
#[test]
fn the_vine_contract_scans_are_detected_when_clean() {
    use fieldguide::perception::vine::{VineConfig, VineDetector, VineParams};
    let lidar = vine_scans::Lidar::table1();
    let mut vine =
        VineDetector::<512, 64>::configure(&VineConfig::new(&VineParams::summer()).unwrap())
            .unwrap();
    let mut seen = 0;
    for k in 0..SCANS {
        let pose = (0.1 * k as f64, 0.0, 0.0);
        let ranges = vine_rows(k, pose);
        let odometry = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        let d = vine.observe(&lidar.scan(&ranges), &odometry).unwrap();
        seen += usize::from(d.verdict.estimate_is_valid());
    }
    // Five set-points over 0.5 m: from the sixth scan on.
    assert!(seen >= SCANS - 6, "{seen} of {SCANS}");
}

fn rows_limits() -> RangeLimits {
    RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(4.0).unwrap()).unwrap()
}

/// A crop of four rows 0.75 m apart seen by the paper's front LiDAR from
/// between the middle rows (`crop_scans`), the robot at `pose` along them.
fn crop_rows(k: usize, (x, y, h): (f64, f64, f64)) -> Vec<f64> {
    use std::sync::OnceLock;
    static FIELD: OnceLock<crop_scans::Field> = OnceLock::new();
    let field = FIELD.get_or_init(|| crop_scans::crop1(3, 0.75).build());
    let start = field.between(1, 2, 2.0);
    let robot = start.compose(&crop_scans::Pose::new(x, y, h));
    field
        .cast(
            &robot,
            &crop_scans::Mount::front(0.3),
            &crop_scans::Lidar::paper(),
            k as u64,
        )
        .ranges
}

fn rows_frames() -> impl Strategy<Value = Frames> {
    let lidar = crop_scans::Lidar::paper();
    // At rest for the measurement: the base scans are taken at the first pose.
    frames(|k, _| crop_rows(k, (0.0, 0.0, 0.0)), lidar.rays).prop_map(move |mut f| {
        if f.start == -PI {
            f.start = lidar.angle(0);
            f.increment = lidar.angle(1) - lidar.angle(0);
        }
        f
    })
}

/// The real scans the contract is checked on do detect: the property above
/// is not satisfied vacuously by Absent verdicts.
#[test]
fn the_contract_scans_are_detected_when_clean() {
    let frames = |base: fn(usize, (f64, f64, f64)) -> Vec<f64>| {
        (0..SCANS).map(move |k| {
            let pose = (0.1 * k as f64, 0.0, 0.0);
            (base(k, pose), pose)
        })
    };
    let mut edge = EdgeDetector::<512, 64>::configure(&edge_config()).unwrap();
    let lidar = furrow_lidar();
    let mut furrow =
        FurrowDetector::<512, 32>::configure(&FurrowConfig::new(&furrow_params()).unwrap())
            .unwrap();
    let mut seen = (0, 0);
    for ((w, (x, y, h)), (r, _)) in frames(wall).zip(frames(ridges)) {
        let odometry = Pose2::<Odom>::new(x, y, h).unwrap();
        let wall_scan = Scan {
            start: Radians::new(-PI).unwrap(),
            increment: Radians::new(TAU / 360.0).unwrap(),
            ranges: &w,
            limits: edge_limits(),
        };
        if edge
            .observe(&wall_scan, &odometry)
            .unwrap()
            .verdict
            .estimate_is_valid()
        {
            seen.0 += 1;
        }
        let ridge_scan = Scan {
            start: Radians::new(lidar.angle_min).unwrap(),
            increment: Radians::new(lidar.increment).unwrap(),
            ranges: &r,
            limits: furrow_limits(),
        };
        if furrow
            .observe(&ridge_scan, &odometry)
            .unwrap()
            .verdict
            .estimate_is_valid()
        {
            seen.1 += 1;
        }
    }
    assert_eq!(
        seen.0, SCANS,
        "the wall is followed in every clean scan: {seen:?}"
    );
    assert!(
        seen.1 >= 1,
        "the ridges are pursued once enough scans accumulate"
    );
}

/// A tracking error with any finite parts, extremes included.
fn any_error() -> impl Strategy<Value = TrackingError> {
    let part = || {
        prop_oneof![
            4 => -3.0..3.0_f64,
            1 => Just(0.0),
            1 => Just(f64::MIN_POSITIVE),
            1 => prop_oneof![Just(1e300), Just(-1e300), Just(f64::MAX), Just(f64::MIN)],
            1 => -1e6..1e6_f64,
        ]
    };
    (part(), part(), part(), part()).prop_map(|(y, t, c, ca)| TrackingError {
        y: Meters::new(y).unwrap(),
        angular_deviation: Radians::new(t).unwrap(),
        curvature: Curvature::new(c).unwrap(),
        curvature_ahead: Curvature::new(ca).unwrap(),
    })
}

fn any_speed() -> impl Strategy<Value = MetersPerSecond> {
    prop_oneof![
        4 => 0.01..5.0_f64,
        1 => Just(0.0),
        1 => -5.0..0.0_f64,
        1 => prop_oneof![Just(f64::MAX), Just(1e-300)],
    ]
    .prop_map(|v| MetersPerSecond::new(v).unwrap())
}

/// The property of GD-LAW for law type `L` on `vehicle`: any error, extra
/// input and speed give a command of the vehicle's actuation within its
/// limits, or an error; the extra input the law refuses is refused by
/// `check_extra` too, and the neutral input is accepted.
fn check_law<L: ControlLaw>(
    law: &L,
    vehicle: &Vehicle,
    error: &TrackingError,
    extra: &L::Extra,
    speed: MetersPerSecond,
) -> Result<(), TestCaseError> {
    prop_assert!(L::check_extra(&L::NEUTRAL).is_ok());
    prop_assert_eq!(law.actuation(), vehicle.actuation());
    if L::check_extra(extra).is_err() {
        return Ok(());
    }
    if let Ok(c) = law.command(error, extra, speed) {
        prop_assert_eq!(c.command.actuation(), vehicle.actuation());
        prop_assert!(vehicle.check(&c.command).is_ok(), "{:?}", c);
        prop_assert!(c.command.speed().get().is_finite());
    }
    Ok(())
}

//= spec/guidance.md#gd-law-one-trait-for-every-control-law
//= type=test
//# A control law MUST turn a tracking error, its extra input and a desired
//# speed into a command of its vehicle's actuation within that vehicle's
//# limits, or refuse them with a `Precondition` error; it MUST NOT give a
//# non-finite command.
proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn backstepping_keeps_the_law_contract(
        error in any_error(),
        speed in any_speed(),
        front in prop_oneof![-1.0..1.0_f64, -2.0..2.0_f64],
        rear in prop_oneof![-1.0..1.0_f64, -2.0..2.0_f64],
        printed in any::<bool>(),
    ) {
        let mut law = fieldguide::presets::path_tracking().unwrap().law;
        if printed {
            law.inversion = fieldguide::control::backstepping::Inversion::Printed;
        }
        let vehicle = Vehicle::Bicycle(law.vehicle);
        let sideslip = fieldguide::model::bicycle::Sideslip {
            front: Radians::new(front).unwrap(),
            rear: Radians::new(rear).unwrap(),
        };
        check_law::<BacksteppingConfig>(&law, &vehicle, &error, &sideslip, speed)?;
    }

    #[test]
    fn the_four_wheel_steering_laws_keep_the_law_contract(
        error in any_error(),
        speed in any_speed(),
        slip in (prop_oneof![-1.0..1.0_f64, -2.0..2.0_f64], prop_oneof![-1.0..1.0_f64, -2.0..2.0_f64]),
        objectives in (-3.0..3.0_f64, -2.0..2.0_f64),
        held in any::<bool>(),
    ) {
        use fieldguide::control::four_ws::{Objectives, RearSteering, Strategy1, Strategy1Gains, Strategy2, Strategy2Gains};
        let vehicle = fieldguide::model::four_ws::FourWheelSteering::new(
            fieldguide::model::bicycle::Wheelbase::new(1.2).unwrap(),
            fieldguide::model::bicycle::SteeringLimit::new(0.5).unwrap(),
            fieldguide::model::bicycle::SteeringLimit::new(0.3).unwrap(),
            None,
            None,
        ).unwrap();
        let sideslip = fieldguide::model::bicycle::Sideslip {
            front: Radians::new(slip.0).unwrap(),
            rear: Radians::new(slip.1).unwrap(),
        };
        let rear = if held { RearSteering::Held } else { RearSteering::Backstepping };
        let s1 = Strategy1 { gains: Strategy1Gains::table1().unwrap(), vehicle, rear };
        let extra = Objectives { sideslip, lateral_offset: Meters::new(objectives.0).unwrap(), orientation: Radians::new(objectives.1).unwrap() };
        check_law::<Strategy1>(&s1, &Vehicle::FourWheelSteering(vehicle), &error, &extra, speed)?;
        let s2 = Strategy2 { gains: Strategy2Gains::table1().unwrap(), vehicle };
        check_law::<Strategy2>(&s2, &Vehicle::FourWheelSteering(vehicle), &error, &sideslip, speed)?;
    }

    #[test]
    fn lateral_pd_keeps_the_law_contract(error in any_error(), speed in any_speed(), rate in any_speed()) {
        use fieldguide::control::lateral_pd::{LateralGains, LateralPd, LateralRate};
        use fieldguide::model::skid_steer::SkidSteer;
        let vehicle = SkidSteer::new(Meters::new(1.48).unwrap(), MetersPerSecond::new(1.67).unwrap()).unwrap();
        let law = LateralPd { gains: LateralGains::new(1.2, 0.8, 0.3, 1.0, 0.5).unwrap(), control_point: Meters::new(1.0).unwrap(), vehicle };
        check_law::<LateralPd>(&law, &Vehicle::SkidSteer(vehicle), &error, &LateralRate(rate), speed)?;
    }
}

//= spec/guidance.md#gd-law-one-trait-for-every-control-law
//= type=test
//# Backstepping MUST be a control law for the bicycle, reading the sideslip
//# estimate as its extra input, zero sideslip being its neutral input.
#[test]
fn backstepping_is_the_bicycle_law_with_sideslip_as_extra_input() {
    use fieldguide::model::bicycle::Sideslip;
    use fieldguide::model::{Actuation, Command};
    let law = fieldguide::presets::path_tracking().unwrap().law;
    assert_eq!(law.actuation(), Actuation::Bicycle);
    assert_eq!(BacksteppingConfig::NEUTRAL, Sideslip::ZERO);
    let error = TrackingError::to_straight_line(Meters::new(0.05).unwrap(), Radians::ZERO);
    let v = MetersPerSecond::new(0.8).unwrap();
    let slip = Sideslip::new(0.02, -0.03).unwrap();
    for extra in [Sideslip::ZERO, slip] {
        let direct =
            fieldguide::control::backstepping::steering_command(&law, &error, extra, v).unwrap();
        let c = law.command(&error, &extra, v).unwrap();
        assert_eq!(
            c.command,
            Command::Bicycle {
                speed: v,
                steering: direct.steering
            }
        );
        assert_eq!(c.saturated, direct.saturated);
    }
    // The sideslip changes the command: it is read.
    assert_ne!(
        law.command(&error, &Sideslip::ZERO, v).unwrap(),
        law.command(&error, &slip, v).unwrap()
    );
    assert!(BacksteppingConfig::check_extra(&Sideslip {
        front: Radians::new(FRAC_PI_2).unwrap(),
        rear: Radians::ZERO
    })
    .is_err());
}

/// A pipeline with no behaviour slot at all (K = 0) is refused at
/// construction, naming the requirement (SW-MODES); path tracking alone is
/// K ≥ 1 slots with none configured.
#[test]
fn a_pipeline_without_behaviour_slots_is_refused() {
    use fieldguide::guidance::{GuidanceConfig, GuidanceParams};
    let two = fieldguide::presets::pierre2022_path().unwrap();
    let none: GuidanceParams<AnyDetectorConfig, BacksteppingConfig, 0> = GuidanceParams {
        period: two.period,
        vehicle: two.vehicle,
        path: two.path,
        behaviours: heapless::Vec::new(),
        priority: heapless::Vec::new(),
        stop_delay: two.stop_delay,
        plan_delay: None,
        max_scan_age: two.max_scan_age,
        plan_dead_reckoning: None,
        bridge: None,
        steer_before_resuming: false,
        handover: None,
        entry: None,
        fix: None,
        odometry_aid: None,
    };
    let e = GuidanceConfig::new(&none).unwrap_err();
    assert_eq!(e.requirement, "SW-MODES");
    assert!(GuidanceConfig::new(&two).is_ok());
}

/// The rows detector's contract scans, clean, do detect: after the two
/// scans of its measurement it follows the rows.
#[test]
fn the_rows_contract_scans_are_detected_when_clean() {
    let mut params = RowsParams::authors(Variant::Rgop, Transform2::new(0.3, 0.0, 0.0).unwrap());
    params.spacing = SpacingConfig::new(0.05, 0.25, 2, 4).unwrap();
    params.still = Meters::new(10.0).unwrap();
    let mut rows = RowsDetector::<512>::configure(&RowsConfig::new(params).unwrap()).unwrap();
    let lidar = crop_scans::Lidar::paper();
    let mut seen = 0;
    for k in 0..SCANS {
        let ranges = crop_rows(k, (0.0, 0.0, 0.0));
        let scan = Scan {
            start: Radians::new(lidar.angle(0)).unwrap(),
            increment: Radians::new(lidar.angle(1) - lidar.angle(0)).unwrap(),
            ranges: &ranges,
            limits: rows_limits(),
        };
        let odometry = Pose2::<Odom>::new(0.1 * k as f64, 0.0, 0.0).unwrap();
        seen += usize::from(
            rows.observe(&scan, &odometry)
                .unwrap()
                .verdict
                .estimate_is_valid(),
        );
    }
    assert!(seen >= SCANS - 3, "{seen} of {SCANS}");
}
