//! Every public function and method of the core, called with values of every
//! kind (`spec/library.md`, LIB-FINITE and LIB-NO-PANIC): ordinary ones,
//! magnitudes from 1e-300 to 1e300 of either sign, subnormals, ±0, the
//! extremes of `f64` and, wherever a raw `f64` is accepted, NaN and ±∞.
//! Values of the unit types are drawn from the same finite mix, so a huge
//! `Meters` or a subnormal `Radians` reaches every function that takes one.
//!
//! Each call goes through `check!`, which asserts that what comes back holds
//! no NaN and no infinity anywhere, private fields included: a finite value,
//! or an error. A panic fails the property like a failed assertion.
//!
//! `the_property_tests_call_every_public_function` keeps this file complete:
//! it scans `src/**/*.rs` for `pub fn` and `pub const fn` (outside
//! `#[cfg(test)]` and `#[cfg(doctest)]`) and for the methods declared by
//! public traits, and fails when one has no `check!` here, or when a
//! `check!` names a function that no longer exists. A new public function
//! therefore needs a call below before CI passes.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp,
    clippy::too_many_lines,
    clippy::too_many_arguments
)]
// `check!` gives back every result it checked, used or not.
#![allow(unused_must_use)]

mod edge_support;
mod furrow_common;
mod vine_scans;

use std::collections::BTreeSet;
use std::path::Path;

use core::f64::consts::{FRAC_PI_2, PI};
use core::fmt::Debug;

use fieldguide::control::backstepping::{
    steering_command, target_angular_deviation, yaw_rate_objective, BacksteppingConfig, Gains,
    Inversion, SpeedSchedule,
};
use fieldguide::control::lateral_pd::{LateralGains, LateralPd, LateralRate};
use fieldguide::control::speed_profile::{Braking, SpeedProfile, SpeedState};
use fieldguide::control::spiral::{spiral_command, spiral_state, Spiral};
use fieldguide::control::ControlLaw;
use fieldguide::error::finite;
use fieldguide::geometry::carry::{moved_lateral, moved_line_error, pose_in_scan_frame, straight};
use fieldguide::geometry::fit::{fit_line, fit_line_weighted, fit_parabola, LineFit, ParabolaFit};
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::geometry::units::wrap_angle;
use fieldguide::guidance::{AidedOdometry, OdometryAid, OdometryAidParams};
use fieldguide::guidance::{
    BehaviourId, Guidance, GuidanceConfig, GuidanceParams, Mode as GuidanceMode, RoutedScan,
    TickInput,
};
use fieldguide::guidance::{Entry, EntryParams, Handover, HandoverParams};
use fieldguide::guidance::{FixKind, FixQuality, FixRule, FixRuleParams};
use fieldguide::model::bicycle::{
    frenet_rates, world_rates, yaw_rate, Bicycle, Sideslip, SteeringLimit, Wheelbase,
};
use fieldguide::model::skid_steer::{unicycle_rates, SkidSteer};
use fieldguide::model::{Actuation, Command, Vehicle};
use fieldguide::perception::edge::{
    build_chain, build_chain_into, detect, detect_points, rotation_contact, scan_into,
    scan_to_points as edge_scan_to_points, tracking_error as edge_tracking_error,
    translation_contact, Chain, ChainEnd, EdgeConfig, EdgeDetector, EdgeDetectorConfig, EdgeLine,
    EdgeParameters, EdgeQuality, LookAhead, ScanPoints, Side,
};
use fieldguide::perception::furrow::accumulation::{Accumulator, Selected};
use fieldguide::perception::furrow::correlation::{
    correlate, correlate_direct, height_signal, Template,
};
use fieldguide::perception::furrow::lines::{
    fit_row_line, fit_row_line_toward, mean_tracking_error, tracking_error as row_tracking_error,
    RowLine,
};
use fieldguide::perception::furrow::quality::furrow_verdict;
use fieldguide::perception::furrow::scan::{
    scan_to_points as furrow_scan_to_points, MountPose, ScanPoint, ScanWindow,
};
use fieldguide::perception::furrow::selection::{
    local_maxima, locate, select_one, select_pair, Maximum, Pair, Spacing,
};
use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector, FurrowParams, RowLines, Rows};
use fieldguide::perception::obstacles::{
    assess, assess_within, cluster, detour, detour_within, AreaLength, ClusterConfig, Corridor,
    Footprint, Hazard, Obstacle, ObstacleConfig, Obstacles,
};
use fieldguide::perception::rows::filter::{
    seen_from, side_indices, side_rows, tracking_error as rows_tracking_error, FilterConfig,
    RowFilter,
};
use fieldguide::perception::rows::points::{
    merge_runs, scan_points, scan_points_with, Points, Rays, RowPoint,
};
use fieldguide::perception::rows::ruby::{Ruby, RubyConfig, RubyParams, Variant};
use fieldguide::perception::rows::spacing::{
    closest_pair, row_distance, SpacingConfig, SpacingEstimator,
};
use fieldguide::perception::rows::{RowsConfig, RowsDetector, RowsParams};
use fieldguide::perception::{
    AnyDetector, AnyDetectorConfig, AnyLine, Better, Detection, Detector, HeldLine,
    QualityThresholds, RangeLimits, Scan, Verdict,
};
use fieldguide::planning::dubins::{path_with_word, shortest, TurningRadius, Word};
use fieldguide::planning::line_following::{goal_ahead, line_ahead};
use fieldguide::planning::manager::{
    choose_planner, direction_change, tracker_for, PlannerThreshold,
};
use fieldguide::presets;
use fieldguide::supervisor::switching::{
    delay_ticks, line_relative_to_path, line_relative_to_path_ahead, step as machine_step,
    BehaviourConfig, Input, PathAhead, PlanTolerance, Report, Switching, SwitchingConfig,
    SwitchingState,
};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Odom, Point2, Pose2, Precondition, Radians,
    RadiansPerSecond, Robot, Seconds, Sensor, TrackingError, Transform2, World,
};
use proptest::prelude::*;

// ---------------------------------------------------------------- the check

/// Calls the public function named by `key` (as the coverage test below
/// finds it in `src/`: module, type or trait, name) and asserts that the
/// result holds no NaN and no infinity; gives the result back.
macro_rules! check {
    ($key:literal, $call:expr) => {{
        let value = $call;
        finite_or_error($key, stringify!($call), &value);
        value
    }};
}

/// Asserts that the `Debug` form of `value` (every field, private ones
/// included, down to each `f64`) names no NaN and no infinity, and that the
/// call really is the function its key names.
fn finite_or_error<T: Debug>(key: &str, call: &str, value: &T) {
    let name = key.rsplit("::").next().unwrap_or(key);
    assert!(call.contains(name), "check!({key}) calls `{call}`");
    all_finite(&format!("{key} (`{call}`)"), value);
}

/// Asserts that the `Debug` form of `value` names no NaN and no infinity.
fn all_finite<T: Debug>(what: &str, value: &T) {
    let text = format!("{value:?}");
    let non_finite = text
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .any(|token| token == "NaN" || token == "inf");
    if non_finite {
        let shown: String = text.chars().take(600).collect();
        panic!("{what} gave a non-finite value: {shown}");
    }
}

/// Asserts that an error names a requirement, as `spec/` spells them
/// (upper-case words joined by hyphens).
fn names_a_requirement<T: Debug>(what: &str, result: &Result<T, Precondition>) {
    if let Err(e) = result {
        let id = e.requirement;
        let spelt = id.contains('-')
            && id
                .chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '-');
        assert!(spelt, "{what} gave an error naming no requirement: {e:?}");
    }
}

// ---------------------------------------------------------------- values

/// 10^e with a sign.
fn signed_power(e: f64, negative: bool) -> f64 {
    let v = 10f64.powf(e);
    if negative {
        -v
    } else {
        v
    }
}

/// Any finite `f64`: ordinary values, 1e-300 to 1e300 of either sign,
/// subnormals, ±0 and the extremes.
fn fin() -> BoxedStrategy<f64> {
    prop_oneof![
        4 => -10.0..10.0_f64,
        3 => (-300.0..300.0_f64, any::<bool>()).prop_map(|(e, n)| signed_power(e, n)),
        1 => (1_u64..(1 << 52), any::<bool>()).prop_map(|(bits, n)| {
            let v = f64::from_bits(bits);
            if n { -v } else { v }
        }),
        1 => prop::sample::select(vec![
            0.0, -0.0, f64::MAX, -f64::MAX, f64::MIN_POSITIVE, -f64::MIN_POSITIVE,
            f64::EPSILON, 1e7, -1e7, FRAC_PI_2, PI, -PI,
        ]),
    ]
    .boxed()
}

/// Any `f64`, NaN and infinities included.
fn raw() -> BoxedStrategy<f64> {
    prop_oneof![
        6 => fin(),
        1 => prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
    ]
    .boxed()
}

/// A value that is usually plausible for a field robot (within `scale`), sometimes anything finite.
fn near(scale: f64) -> BoxedStrategy<f64> {
    prop_oneof![3 => -scale..scale, 1 => fin()].boxed()
}

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn rad(v: f64) -> Radians {
    Radians::new(v).unwrap()
}

fn meters() -> BoxedStrategy<Meters> {
    fin().prop_map(m).boxed()
}

fn radians() -> BoxedStrategy<Radians> {
    fin().prop_map(rad).boxed()
}

fn point<F: fieldguide::Frame>() -> BoxedStrategy<Point2<F>> {
    (near(20.0), near(20.0))
        .prop_map(|(x, y)| Point2::new(x, y).unwrap())
        .boxed()
}

/// A pose with any finite heading, wrapped or not (the fields are public).
fn pose<F: fieldguide::Frame>() -> BoxedStrategy<Pose2<F>> {
    (point::<F>(), near(4.0))
        .prop_map(|(position, h)| Pose2 {
            position,
            heading: rad(h),
        })
        .boxed()
}

fn tracking() -> BoxedStrategy<TrackingError> {
    (near(2.0), near(1.5), near(0.5), near(0.5))
        .prop_map(|(y, a, c, ca)| TrackingError {
            y: m(y),
            angular_deviation: rad(a),
            curvature: Curvature::new(c).unwrap(),
            curvature_ahead: Curvature::new(ca).unwrap(),
        })
        .boxed()
}

fn side() -> impl Strategy<Value = Side> {
    prop_oneof![Just(Side::Left), Just(Side::Right)]
}

fn verdict() -> impl Strategy<Value = Verdict> {
    prop::sample::select(Verdict::ALL.to_vec())
}

/// A range as a LiDAR may send it, hostile ones included.
fn range() -> BoxedStrategy<f64> {
    prop_oneof![6 => 0.05..30.0_f64, 1 => raw()].boxed()
}

/// A scan's parts: first angle, increment, ranges (a plausible LiDAR or anything).
/// A scan's first angle, increment and ranges.
type ScanParts = (Radians, Radians, Vec<f64>);

fn scan_parts(rays: usize) -> BoxedStrategy<ScanParts> {
    (
        prop_oneof![3 => Just(-FRAC_PI_2), 1 => fin()],
        prop_oneof![3 => Just(PI / rays as f64), 1 => fin()],
        prop::collection::vec(range(), 0..=rays),
    )
        .prop_map(|(s, i, r)| (rad(s), rad(i), r))
        .boxed()
}

fn limits() -> BoxedStrategy<RangeLimits> {
    (near(1.0), near(40.0))
        .prop_map(|(lo, hi)| {
            RangeLimits::new(m(lo), m(hi))
                .unwrap_or_else(|_| RangeLimits::new(m(0.05), m(30.0)).unwrap())
        })
        .boxed()
}

/// Ranges of a straight wall `d` m to the left of a sensor at the robot's
/// origin (Side::Left hedge), with some rays replaced by anything.
fn wall_ranges(d: f64, rays: usize, faults: &[(usize, f64)]) -> Vec<f64> {
    let mut r: Vec<f64> = (0..rays)
        .map(|k| {
            let a = -FRAC_PI_2 + PI * (k as f64 + 0.5) / rays as f64;
            if a.sin() > 0.05 {
                d / a.sin()
            } else {
                f64::INFINITY
            }
        })
        .collect();
    for &(i, v) in faults {
        if let Some(slot) = r.get_mut(i % rays.max(1)) {
            *slot = v;
        }
    }
    r
}

/// Waypoints: a plausible drive (a random walk of 0.2-2 m steps) or anything finite.
fn waypoints() -> BoxedStrategy<Vec<Point2<World>>> {
    prop_oneof![
        3 => (near(5.0), near(5.0), prop::collection::vec((0.2..2.0_f64, -0.3..0.3_f64), 1..40))
            .prop_map(|(x0, y0, steps)| {
                let (mut x, mut y, mut h) = (x0, y0, 0.0_f64);
                let mut out = vec![Point2::new(x, y).unwrap()];
                for (d, turn) in steps {
                    h += turn;
                    x += d * h.cos();
                    y += d * h.sin();
                    if let Ok(p) = Point2::new(x, y) {
                        out.push(p);
                    }
                }
                out
            }),
        1 => prop::collection::vec((fin(), fin()), 0..8).prop_map(|v| {
            v.into_iter().map(|(x, y)| Point2::new(x, y).unwrap()).collect()
        }),
    ]
    .boxed()
}

type SmallPath = ReferencePath<64>;

/// A path of the waypoints, or a straight 30 m one when they are refused.
fn path_of(points: &[Point2<World>]) -> SmallPath {
    ReferencePath::from_waypoints(points, PathConfig::default()).unwrap_or_else(|_| {
        ReferencePath::from_waypoints(
            &[
                Point2::new(0.0, 0.0).unwrap(),
                Point2::new(30.0, 0.0).unwrap(),
            ],
            PathConfig::default(),
        )
        .unwrap()
    })
}

// ---------------------------------------------------------------- fuzzy control

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn fuzzy_engine_and_row_controller(
        v in raw(), w in raw(), f in fin(), g in fin(), h in fin(), k in 0_u16..300,
    ) {
        use fieldguide::control::fuzzy::{Defuzzifier, Engine, Rule, Term, Variable, MAX_VARIABLES};
        use fieldguide::control::fuzzy_rows::{orientation, position, FuzzyRowController, Orientation};
        use fieldguide::perception::furrow::selection::Pair;
        let (lo, hi) = (f.min(g), f.max(g));
        let tri = Term::Triangle { left: lo, peak: 0.5 * lo + 0.5 * hi, right: hi };
        let ramp = Term::Ramp { start: f, end: g };
        check!("control::fuzzy::Term::membership", tri.membership(v));
        check!("control::fuzzy::Term::membership", ramp.membership(w));
        let variable = Variable { min: lo, max: hi, terms: [tri, ramp].into_iter().collect() };
        let mut rule = Rule { when: [None; MAX_VARIABLES], then: [None; MAX_VARIABLES] };
        (rule.when[0], rule.then[0]) = (Some(0), Some(1));
        let engine = check!("control::fuzzy::Engine::new", Engine::new(core::slice::from_ref(&variable), core::slice::from_ref(&variable), &[rule], &[h]));
        if let Ok(e) = engine {
            for d in [Defuzzifier::Exact, Defuzzifier::Sampled { resolution: k }] {
                check!("control::fuzzy::Engine::evaluate", e.evaluate(&[v], d));
            }
        }
        let speed = MetersPerSecond::new(h.abs().min(1e6)).unwrap();
        for how in [Orientation::SidesMeanSlope, Orientation::AllRowsMeanAngle] {
            let c = check!("control::fuzzy_rows::FuzzyRowController::authors", FuzzyRowController::authors(how, Defuzzifier::Exact, speed));
            let Ok(c) = c else { continue };
            check!("control::fuzzy_rows::FuzzyRowController::engine", c.engine());
            check!("control::fuzzy_rows::FuzzyRowController::wheels", c.wheels(v, w));
            let (Ok(a), Ok(b1), Ok(b2)) = (RowLine::new(f.clamp(-1e6, 1e6), m(0.0)), Meters::new(g), Meters::new(-h)) else { continue };
            let (Ok(l), Ok(r)) = (RowLine::new(a.slope(), b1), RowLine::new(a.slope(), b2)) else { continue };
            let sides = Pair { left: l, right: r };
            check!("control::fuzzy_rows::orientation", orientation(&sides, &[l, r], how));
            check!("control::fuzzy_rows::position", position(&sides));
            check!("control::fuzzy_rows::FuzzyRowController::command", c.command(&sides, &[l, r]));
        }
    }
}

// ---------------------------------------------------------------- units, errors, frames

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    #[test]
    fn units_errors_and_angles(v in raw(), w in raw(), f in fin()) {
        macro_rules! unit {
            ($t:ty) => {
                if let Ok(u) = check!("geometry::units::$name::new", <$t>::new(v)) {
                    check!("geometry::units::$name::get", u.get());
                    check!("geometry::units::$name::abs", u.abs());
                    check!("geometry::units::$name::negated", u.negated());
                }
            };
        }
        unit!(Meters);
        unit!(Radians);
        unit!(Curvature);
        unit!(MetersPerSecond);
        unit!(RadiansPerSecond);
        unit!(Seconds);
        check!("error::finite", finite(v, "a value"));
        check!("error::finite", finite(w, "another value"));
        check!("error::Precondition::new", Precondition::new("LIB-FINITE", "anything"));
        let a = rad(f);
        let wrapped = check!("geometry::units::wrap_angle", wrap_angle(a));
        prop_assert!(wrapped.get() > -PI && wrapped.get() <= PI);
        let same = check!("geometry::units::Radians::wrapped", a.wrapped());
        prop_assert_eq!(same, wrapped);
    }

    #[test]
    fn points_poses_and_transforms(
        x in raw(), y in raw(), h in raw(),
        p in point::<World>(), q in point::<World>(), far in (fin(), fin()),
        pose_a in pose::<Robot>(), heading in radians(),
        t1 in (near(5.0), near(5.0), near(4.0)), t2 in (fin(), fin(), fin()),
        e in tracking(), ym in meters(), am in radians(),
    ) {
        check!("geometry::frame::Point2::new", Point2::<World>::new(x, y));
        check!("geometry::frame::Point2::origin", Point2::<World>::origin());
        let wide = Point2::<World>::new(far.0, far.1).unwrap();
        check!("geometry::frame::Point2::from_meters", Point2::<World>::from_meters(ym, m(far.0)));
        check!("geometry::frame::Point2::x", wide.x());
        check!("geometry::frame::Point2::y", wide.y());
        check!("geometry::frame::Point2::distance_to", p.distance_to(q));
        check!("geometry::frame::Point2::distance_to", wide.distance_to(p));
        check!("geometry::frame::Point2::distance_to", wide.distance_to(wide.mirrored()));
        check!("geometry::frame::Point2::mirrored", wide.mirrored());
        check!("geometry::frame::Pose2::new", Pose2::<World>::new(x, y, h));
        let body: Transform2<Sensor, Robot> =
            check!("geometry::frame::Pose2::body_to_frame", pose_a.body_to_frame());
        check!("geometry::frame::Transform2::new", Transform2::<Robot, World>::new(x, y, h));
        for (tx, ty, ta) in [t1, t2] {
            let t = Transform2::<Robot, World>::new(tx, ty, ta).unwrap();
            check!("geometry::frame::Transform2::angle", t.angle());
            check!("geometry::frame::Transform2::apply", t.apply(Point2::from_meters(ym, m(far.1))));
            check!("geometry::frame::Transform2::apply_heading", t.apply_heading(heading));
            check!("geometry::frame::Transform2::apply_pose", t.apply_pose(pose_a));
            check!("geometry::frame::Transform2::inverse", t.inverse());
            check!("geometry::frame::Transform2::then", body.then(&t));
        }
        check!("geometry::tracking::TrackingError::to_straight_line", TrackingError::to_straight_line(ym, am));
        check!("geometry::tracking::TrackingError::mirrored", e.mirrored());
    }

    #[test]
    fn errors_carried_by_odometry(
        then in pose::<Odom>(), now in pose::<Odom>(), moved in pose::<Robot>(),
        e in tracking(), y in raw(), a in raw(),
    ) {
        check!("geometry::carry::pose_in_scan_frame", pose_in_scan_frame(&then, &now));
        check!("geometry::carry::moved_lateral", moved_lateral(&e, &moved));
        check!("geometry::carry::straight", straight(y, a));
        check!("geometry::carry::moved_line_error", moved_line_error(&e, &moved));
    }

    #[test]
    fn least_squares_fits(
        xy in prop::collection::vec((near(10.0), near(10.0)), 0..12),
        coefficients in (raw(), raw(), raw()), x in raw(), p in point::<Robot>(),
        weights in prop::collection::vec(prop_oneof![3 => 0.0..10.0_f64, 1 => raw()], 0..12),
    ) {
        let points: Vec<Point2<Robot>> =
            xy.iter().map(|&(x, y)| Point2::new(x, y).unwrap()).collect();
        check!("geometry::fit::fit_line", fit_line(points.iter()));
        let weighted = check!("geometry::fit::fit_line_weighted", fit_line_weighted(points.iter().zip(weights.iter().copied())));
        names_a_requirement("fit_line_weighted", &weighted);
        check!("geometry::fit::fit_line_weighted", fit_line_weighted(points.iter().map(|q| (q, 1.0))));
        check!("geometry::fit::fit_parabola", fit_parabola(points.iter()));
        let (a, b, c) = coefficients;
        let lines = [LineFit { a, b }, fit_line(points.iter()).unwrap_or(LineFit { a: 0.5, b: 1.0 })];
        for line in lines {
            check!("geometry::fit::LineFit::value_at", line.value_at(x));
            check!("geometry::fit::LineFit::residual", line.residual(p));
            check!("geometry::fit::LineFit::mean_squared_residual", line.mean_squared_residual(points.iter()));
        }
        let parabolas = [
            ParabolaFit { a, b, c },
            fit_parabola(points.iter()).unwrap_or(ParabolaFit { a: 0.1, b: 0.5, c: 1.0 }),
        ];
        for parabola in parabolas {
            check!("geometry::fit::ParabolaFit::value_at", parabola.value_at(x));
            check!("geometry::fit::ParabolaFit::slope_at", parabola.slope_at(x));
            check!("geometry::fit::ParabolaFit::residual", parabola.residual(p));
            check!("geometry::fit::ParabolaFit::mean_squared_residual", parabola.mean_squared_residual(points.iter()));
        }
    }

    #[test]
    fn reference_paths_and_projection(
        points in waypoints(), window in meters(), s in prop::collection::vec(meters(), 1..6),
        poses in prop::collection::vec(pose::<World>(), 1..6), lookahead in meters(),
        hint in meters(), search in meters(),
    ) {
        check!("geometry::path::PathConfig::new", PathConfig::new(window));
        let config = PathConfig::new(window).unwrap_or_default();
        check!("geometry::path::ReferencePath::from_waypoints", SmallPath::from_waypoints(&points, config));
        let path = path_of(&points);
        check!("geometry::path::ReferencePath::config", path.config());
        check!("geometry::path::ReferencePath::length", path.length());
        check!("geometry::path::ReferencePath::vertices", path.vertices());
        for &s in &s {
            check!("geometry::path::ReferencePath::heading_at", path.heading_at(s));
            check!("geometry::path::ReferencePath::curvature_at", path.curvature_at(s));
            check!("geometry::path::ReferencePath::point_at", path.point_at(s));
        }
        for pose in &poses {
            let frenet = check!("geometry::path::ReferencePath::project", path.project(pose, lookahead));
            check!("geometry::path::ReferencePath::project_near", path.project_near(pose, lookahead, hint, search));
            if let Ok(f) = frenet {
                check!("geometry::path::FrenetError::tracking_error", f.tracking_error());
            }
        }
    }
}

// ---------------------------------------------------------------- vehicles and laws

fn commands() -> BoxedStrategy<Command> {
    (0..4_u8, prop::array::uniform4(fin()))
        .prop_map(|(kind, [a, b, c, _])| {
            let speed = MetersPerSecond::new(a).unwrap();
            match kind {
                0 => Command::Bicycle {
                    speed,
                    steering: rad(b),
                },
                1 => Command::FourWheelSteering {
                    speed,
                    front: rad(b),
                    rear: rad(c),
                },
                2 => Command::Differential {
                    left: speed,
                    right: MetersPerSecond::new(b).unwrap(),
                },
                _ => Command::SkidSteer {
                    speed,
                    yaw_rate: RadiansPerSecond::new(b).unwrap(),
                },
            }
        })
        .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    #[test]
    fn vehicles_and_the_kinematic_model(
        wheelbase in raw(), limit in raw(), rate in fin(), command in commands(),
        clamp_at in radians(), slip in (raw(), raw()), wild_slip in (radians(), radians()),
        speed in prop_oneof![3 => 0.1..3.0_f64, 1 => fin()], steering in radians(),
        e in tracking(), at in pose::<World>(),
    ) {
        for actuation in [
            Actuation::Bicycle, Actuation::FourWheelSteering, Actuation::Differential, Actuation::SkidSteer,
        ] {
            check!("model::Actuation::at_rest", actuation.at_rest());
            check!("model::Actuation::label", actuation.label());
        }
        check!("model::Command::actuation", command.actuation());
        check!("model::Command::speed", command.speed());
        check!("model::Command::steering", command.steering());
        check!("model::Command::stopped", command.stopped());
        check!("model::bicycle::Wheelbase::new", Wheelbase::new(wheelbase));
        check!("model::bicycle::SteeringLimit::new", SteeringLimit::new(limit));
        let wb = Wheelbase::new(wheelbase).unwrap_or(Wheelbase::new(2.0).unwrap());
        let sl = SteeringLimit::new(limit).unwrap_or(SteeringLimit::new(0.5).unwrap());
        check!("model::bicycle::Wheelbase::get", wb.get());
        check!("model::bicycle::SteeringLimit::get", sl.get());
        check!("model::bicycle::SteeringLimit::clamp", sl.clamp(clamp_at));
        let rate = RadiansPerSecond::new(rate).unwrap();
        check!("model::bicycle::Bicycle::new", Bicycle::new(wb, sl, Some(rate)));
        let bicycle = Bicycle::new(wb, sl, None).unwrap();
        let vehicle = Vehicle::Bicycle(bicycle);
        check!("model::Vehicle::actuation", vehicle.actuation());
        check!("model::Vehicle::check", vehicle.check(&command));
        check!("model::bicycle::Sideslip::new", Sideslip::new(slip.0, slip.1));
        let sideslip = Sideslip { front: wild_slip.0, rear: wild_slip.1 };
        check!("model::bicycle::Sideslip::check", sideslip.check());
        check!("model::bicycle::Sideslip::mirrored", sideslip.mirrored());
        let small = Sideslip::new(slip.0, slip.1).unwrap_or(Sideslip::ZERO);
        let v = MetersPerSecond::new(speed).unwrap();
        for s in [sideslip, small] {
            check!("model::bicycle::yaw_rate", yaw_rate(v, steering, s, wb));
            check!("model::bicycle::frenet_rates", frenet_rates(&e, v, steering, s, wb));
            check!("model::bicycle::world_rates", world_rates(&at, v, steering, s, wb));
        }
    }

    #[test]
    fn backstepping_laws(
        gains in (raw(), raw(), raw()), e in tracking(), slip in (radians(), radians()),
        speed in prop_oneof![3 => 0.1..3.0_f64, 1 => fin()], printed in any::<bool>(),
    ) {
        let (k_y, k_theta, ratio) = gains;
        check!("control::backstepping::Gains::new", Gains::new(k_y, k_theta, ratio));
        #[cfg(feature = "fault-injection")]
        check!("control::backstepping::Gains::with_unchecked_sign", Gains::with_unchecked_sign(k_y, k_theta, ratio));
        let gains = Gains::new(k_y, k_theta, ratio).unwrap_or(Gains::new(-0.7, -2.8, 2.0).unwrap());
        check!("control::backstepping::Gains::k_y", gains.k_y());
        check!("control::backstepping::Gains::k_theta", gains.k_theta());
        let config = BacksteppingConfig {
            gains,
            vehicle: presets::vehicle().unwrap(),
            inversion: if printed { Inversion::Printed } else { Inversion::Exact },
            schedule: None,
        };
        let v = MetersPerSecond::new(speed).unwrap();
        let wild = Sideslip { front: slip.0, rear: slip.1 };
        for s in [wild, Sideslip::new(0.05 * slip.0.get().sin(), 0.05 * slip.1.get().cos()).unwrap()] {
            check!("control::backstepping::target_angular_deviation", target_angular_deviation(&gains, &e, s));
            check!("control::backstepping::yaw_rate_objective", yaw_rate_objective(&gains, &e, s, v));
            check!("control::backstepping::steering_command", steering_command(&config, &e, s, v));
            check!("control::ControlLaw::check_extra", BacksteppingConfig::check_extra(&s));
            check!("control::ControlLaw::command", config.command(&e, &s, v));
        }
        check!("control::ControlLaw::actuation", config.actuation());
        check!("control::backstepping::BacksteppingConfig::gains_at", config.gains_at(v));
    }

    #[test]
    fn four_wheel_steering_model_and_laws(
        gains in (raw(), raw(), raw(), raw()), k2 in (raw(), raw()), e in tracking(),
        slip in (radians(), radians()), angles in (radians(), radians()), obj in (meters(), radians()),
        speed in prop_oneof![3 => 0.1..3.0_f64, 1 => fin()], held in any::<bool>(),
        limits in (raw(), raw(), raw(), raw()), at in pose::<World>(),
    ) {
        use fieldguide::control::four_ws::{
            front_lateral_error, strategy1_command, strategy1_front, strategy1_rear,
            strategy2_command, strategy2_front, strategy2_rear, velocity_objective, Objectives,
            RearSteering, Strategy1, Strategy1Gains, Strategy2, Strategy2Gains,
        };
        use fieldguide::model::four_ws::{
            frenet_rates as fws_frenet_rates, time_rates, world_rates as fws_world_rates,
            yaw_rate as fws_yaw_rate, FourWheelSteering,
        };
        let wb = Wheelbase::new(limits.0).unwrap_or(Wheelbase::new(1.2).unwrap());
        let front_limit = SteeringLimit::new(limits.1).unwrap_or(SteeringLimit::new(0.5).unwrap());
        let rear_limit = SteeringLimit::new(limits.2).unwrap_or(SteeringLimit::new(0.3).unwrap());
        let rate = RadiansPerSecond::new(limits.3).ok();
        check!("model::four_ws::FourWheelSteering::new", FourWheelSteering::new(wb, front_limit, rear_limit, rate, rate));
        let vehicle = FourWheelSteering::new(wb, front_limit, rear_limit, None, None).unwrap();
        check!("model::four_ws::FourWheelSteering::within_limits", vehicle.within_limits(angles.0, angles.1));
        let v = MetersPerSecond::new(speed).unwrap();
        let wild = Sideslip { front: slip.0, rear: slip.1 };
        let small = Sideslip::new(0.05 * slip.0.get().sin(), 0.05 * slip.1.get().cos()).unwrap();
        let (k_y, k_theta, k_r, ratio) = gains;
        check!("control::four_ws::Strategy1Gains::new", Strategy1Gains::new(k_y, k_theta, k_r, ratio));
        check!("control::four_ws::Strategy1Gains::table1", Strategy1Gains::table1());
        let g1 = Strategy1Gains::new(k_y, k_theta, k_r, ratio).unwrap_or(Strategy1Gains::table1().unwrap());
        check!("control::four_ws::Strategy1Gains::k_y", g1.k_y());
        check!("control::four_ws::Strategy1Gains::k_theta", g1.k_theta());
        check!("control::four_ws::Strategy1Gains::k_r", g1.k_r());
        check!("control::four_ws::Strategy2Gains::new", Strategy2Gains::new(k2.0, k2.1));
        check!("control::four_ws::Strategy2Gains::table1", Strategy2Gains::table1());
        let g2 = Strategy2Gains::new(k2.0, k2.1).unwrap_or(Strategy2Gains::table1().unwrap());
        check!("control::four_ws::Strategy2Gains::k_front", g2.k_front());
        check!("control::four_ws::Strategy2Gains::k_rear", g2.k_rear());
        let law1 = Strategy1 { gains: g1, vehicle, rear: if held { RearSteering::Held } else { RearSteering::Backstepping } };
        let law2 = Strategy2 { gains: g2, vehicle };
        let veh = Vehicle::FourWheelSteering(vehicle);
        check!("control::four_ws::front_lateral_error", front_lateral_error(&e, &vehicle));
        for s in [wild, small] {
            let o = Objectives { sideslip: s, lateral_offset: obj.0, orientation: obj.1 };
            check!("control::four_ws::Objectives::check", o.check());
            check!("control::four_ws::Objectives::mirrored", o.mirrored());
            check!("control::four_ws::velocity_objective", velocity_objective(&g1, &e, obj.0));
            check!("control::four_ws::strategy1_rear", strategy1_rear(&g1, &e, &o));
            check!("control::four_ws::strategy1_front", strategy1_front(&law1, &e, &o, angles.1));
            if let Ok(c) = check!("control::four_ws::strategy1_command", strategy1_command(&law1, &e, &o, v)) {
                let within = veh.check(&Command::FourWheelSteering { speed: v, front: c.front, rear: c.rear }).is_ok();
                prop_assert!(within, "{:?}", c);
            }
            check!("control::four_ws::strategy2_rear", strategy2_rear(&g2, &e, s));
            check!("control::four_ws::strategy2_front", strategy2_front(&law2, &e, s, angles.1));
            if let Ok(c) = check!("control::four_ws::strategy2_command", strategy2_command(&law2, &e, s, v)) {
                let within = veh.check(&Command::FourWheelSteering { speed: v, front: c.front, rear: c.rear }).is_ok();
                prop_assert!(within, "{:?}", c);
            }
            names_a_requirement("strategy1_command", &strategy1_command(&law1, &e, &o, v));
            names_a_requirement("strategy2_command", &strategy2_command(&law2, &e, s, v));
            check!("model::four_ws::yaw_rate", fws_yaw_rate(v, angles.0, angles.1, s, wb));
            check!("model::four_ws::time_rates", time_rates(&e, v, angles.0, angles.1, s, wb));
            check!("model::four_ws::frenet_rates", fws_frenet_rates(&e, v, angles.0, angles.1, s, wb));
            check!("model::four_ws::world_rates", fws_world_rates(&at, v, angles.0, angles.1, s, wb));
        }
    }

    #[test]
    fn speed_schedules(
        bounds in (raw(), raw(), raw()), tau in raw(), rate in raw(), speed in raw(),
        gains in (raw(), raw()),
    ) {
        let (lo, hi, w) = bounds;
        let vehicle = presets::vehicle().unwrap();
        let rated = RadiansPerSecond::new(rate)
            .ok()
            .and_then(|r| Bicycle::new(vehicle.wheelbase, vehicle.max_steering, Some(r)).ok());
        let gains = Gains::new(gains.0, gains.1, 1.0).unwrap_or(Gains::new(-0.7, -2.8, 2.0).unwrap());
        if let (Ok(lo), Ok(hi)) = (MetersPerSecond::new(lo), MetersPerSecond::new(hi)) {
            let mut schedules = std::vec::Vec::new();
            if let Ok(w) = RadiansPerSecond::new(w) {
                schedules.extend(check!("control::backstepping::SpeedSchedule::new", SpeedSchedule::new(lo, hi, w)));
            }
            if let Ok(tau) = Seconds::new(tau) {
                for b in [vehicle].into_iter().chain(rated) {
                    schedules.extend(check!(
                        "control::backstepping::SpeedSchedule::for_actuator",
                        SpeedSchedule::for_actuator(lo, hi, &b, tau)
                    ));
                }
            }
            for sched in schedules {
                check!("control::backstepping::SpeedSchedule::min_speed", sched.min_speed());
                check!("control::backstepping::SpeedSchedule::max_speed", sched.max_speed());
                check!("control::backstepping::SpeedSchedule::bandwidth", sched.bandwidth());
                for v in [speed, lo.get(), hi.get(), 0.5 * (lo.get() + hi.get())] {
                    if let Ok(v) = MetersPerSecond::new(v) {
                        check!("control::backstepping::SpeedSchedule::gains_at", sched.gains_at(&gains, v));
                        let law = BacksteppingConfig {
                            gains,
                            vehicle,
                            inversion: Inversion::Exact,
                            schedule: Some(sched),
                        };
                        check!("control::ControlLaw::check_speed", law.check_speed(v));
                        check!("control::backstepping::BacksteppingConfig::gains_at", law.gains_at(v));
                    }
                }
            }
        }
    }

    #[test]
    fn quality_thresholds_and_scan_limits(
        enter in raw(), exit in raw(), quality in raw(), lo in meters(), hi in meters(), r in raw(),
    ) {
        for better in [Better::Lower, Better::Higher] {
            if let Ok(t) = check!("perception::QualityThresholds::new", QualityThresholds::new(enter, exit, better)) {
                check!("perception::QualityThresholds::enter", t.enter());
                check!("perception::QualityThresholds::exit", t.exit());
                check!("perception::QualityThresholds::classify", t.classify(quality));
            }
        }
        for v in Verdict::ALL {
            check!("perception::Verdict::estimate_is_valid", v.estimate_is_valid());
        }
        if let Ok(l) = check!("perception::scan::RangeLimits::new", RangeLimits::new(lo, hi)) {
            check!("perception::scan::RangeLimits::min", l.min());
            check!("perception::scan::RangeLimits::max", l.max());
            check!("perception::scan::RangeLimits::accepts", l.accepts(r));
        }
    }
}

// ---------------------------------------------------------------- edge following

/// Edge parameters: Table 1's, one of them replaced by anything.
fn edge_parameters() -> BoxedStrategy<EdgeParameters> {
    (0..21_usize, raw(), 0..8_usize)
        .prop_map(|(field, v, points)| {
            let mut p = EdgeParameters::PIERRE2022;
            let ahead = LookAhead::HEDGE;
            match field {
                0 => p.radius = v,
                1 => p.max_rotation = v,
                2 => p.max_chain_length = v,
                3 => p.search_distance = v,
                4 => p.offset = v,
                5 => p.min_chain_length = v,
                6 => p.max_link = v,
                7 => p.max_turn = v,
                8 => p.max_width = v,
                9 => p.sigma_enter = v,
                10 => p.sigma_exit = v,
                11 => p.min_points = points,
                12 => p.min_end_chain_length = v,
                13 => p.max_start_ahead = v,
                14 => {
                    p.look_ahead = Some(LookAhead {
                        end_cap: v,
                        ..ahead
                    })
                }
                15 => p.look_ahead = Some(LookAhead { step: v, ..ahead }),
                16 => {
                    p.look_ahead = Some(LookAhead {
                        farthest: v,
                        ..ahead
                    })
                }
                17 => {
                    p.look_ahead = Some(LookAhead {
                        min_span: v,
                        ..ahead
                    })
                }
                18 => {
                    p.look_ahead = Some(ahead);
                    p.max_start_ahead = 0.5;
                }
                19 => {
                    p.look_ahead = Some(ahead);
                    p.max_start_ahead = 0.5;
                    p.straight = true;
                }
                _ => {}
            }
            p
        })
        .boxed()
}

/// Robot-frame points: a ragged hedge on either side, or anything finite.
fn edge_points() -> BoxedStrategy<Vec<Point2<Robot>>> {
    prop_oneof![
        3 => (side(), 0.5..3.0_f64, -0.3..0.3_f64, prop::collection::vec(-0.05..0.05_f64, 5..60))
            .prop_map(|(s, d, angle, jitter)| {
                let xs: Vec<f64> = (0..jitter.len()).map(|k| -1.0 + 0.08 * k as f64).collect();
                edge_support::hedge(s, d, angle, &xs, &jitter)
            }),
        1 => prop::collection::vec((fin(), fin()), 0..20)
            .prop_map(|v| v.into_iter().map(|(x, y)| Point2::new(x, y).unwrap()).collect()),
    ]
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    #[test]
    fn edge_detection(
        parameters in edge_parameters(), s in side(), points in edge_points(),
        q in point::<Robot>(), pivot in point::<Robot>(), centre in point::<Robot>(),
        radius in meters(), d in 0.5..3.0_f64,
        faults in prop::collection::vec((0..360_usize, raw()), 0..20),
        parts in scan_parts(360), limits in limits(), wall in any::<bool>(),
        mount in (near(2.0), near(1.0), near(4.0)), odometry in pose::<Odom>(),
        parabola in (raw(), raw(), raw()), offset in meters(), x_r in raw(),
    ) {
        check!("perception::edge::config::EdgeConfig::new", EdgeConfig::new(&parameters));
        check!("perception::edge::config::EdgeConfig::pierre2022", EdgeConfig::pierre2022());
        let config = EdgeConfig::new(&parameters).unwrap_or(EdgeConfig::pierre2022().unwrap());
        check!("perception::edge::config::EdgeConfig::radius", config.radius());
        check!("perception::edge::config::EdgeConfig::max_rotation", config.max_rotation());
        check!("perception::edge::config::EdgeConfig::max_chain_length", config.max_chain_length());
        check!("perception::edge::config::EdgeConfig::search_distance", config.search_distance());
        check!("perception::edge::config::EdgeConfig::offset", config.offset());
        check!("perception::edge::config::EdgeConfig::min_chain_length", config.min_chain_length());
        check!("perception::edge::config::EdgeConfig::max_link", config.max_link());
        check!("perception::edge::config::EdgeConfig::max_turn", config.max_turn());
        check!("perception::edge::config::EdgeConfig::max_width", config.max_width());
        check!("perception::edge::config::EdgeConfig::min_points", config.min_points());
        check!("perception::edge::config::EdgeConfig::thresholds", config.thresholds());
        check!("perception::edge::config::EdgeConfig::min_end_chain_length", config.min_end_chain_length());
        check!("perception::edge::config::EdgeConfig::max_start_ahead", config.max_start_ahead());
        check!("perception::edge::config::EdgeConfig::look_ahead", config.look_ahead());
        check!("perception::edge::config::EdgeConfig::straight", config.straight());
        check!("perception::edge::config::Side::sign", s.sign());
        check!("perception::edge::config::Side::mirrored", s.mirrored());
        check!("perception::edge::chain::translation_contact", translation_contact(q, s, radius));
        check!("perception::edge::chain::rotation_contact", rotation_contact(pivot, centre, q, s, radius));
        let chain: Chain<64> = check!("perception::edge::chain::build_chain", build_chain(&points, s, &config));
        check!("perception::edge::chain::Chain::points", chain.points());
        check!("perception::edge::chain::Chain::indices", chain.indices());
        check!("perception::edge::chain::Chain::centers", chain.centers());
        check!("perception::edge::chain::Chain::length", chain.length());
        check!("perception::edge::chain::Chain::end", chain.end());
        check!("perception::edge::chain::Chain::len", chain.len());
        check!("perception::edge::chain::Chain::is_empty", chain.is_empty());
        let mut reused = check!("perception::edge::chain::Chain::empty", Chain::<64>::empty(ChainEnd::NoEdge));
        check!("perception::edge::chain::build_chain_into", build_chain_into(&points, s, &config, &mut reused));
        prop_assert_eq!(reused.indices(), chain.indices());
        let found = check!("perception::edge::detect_points", detect_points::<64>(&points, s, &config));
        if let Ok(found) = found {
            check!("perception::edge::EdgeDetection::usable_error", found.usable_error());
        }
        let fit = ParabolaFit { a: parabola.0, b: parabola.1, c: parabola.2 };
        check!("perception::edge::parabola::tracking_error", edge_tracking_error(&fit, s, offset, x_r));
        let quality = check!("perception::edge::quality::EdgeQuality::measure", EdgeQuality::measure(&points, offset, &fit));
        if let Ok(quality) = quality {
            check!("perception::edge::quality::EdgeQuality::grade", quality.grade(&config));
        }

        // Scans: a wall on the left with faults, or anything.
        let (start, increment, wild) = parts;
        // A wall is seen by a LiDAR at the robot's origin, looking for it on the left.
        let ranges = if wall { wall_ranges(d, 360, &faults) } else { wild };
        let scan = Scan {
            start: if wall { rad(-FRAC_PI_2 + PI / 720.0) } else { start },
            increment: if wall { rad(PI / 360.0) } else { increment },
            ranges: &ranges,
            limits: if wall { RangeLimits::new(m(0.05), m(30.0)).unwrap() } else { limits },
        };
        let mount = if wall { (0.0, 0.0, 0.0) } else { mount };
        let mount = Transform2::<Sensor, Robot>::new(mount.0, mount.1, mount.2).unwrap();
        let s = if wall { Side::Left } else { s };
        check!("perception::edge::scan::scan_to_points", edge_scan_to_points::<512>(&scan, &mount));
        let mut buffer = check!("perception::edge::scan::ScanPoints::new", ScanPoints::<512>::new());
        check!("perception::edge::scan::scan_into", scan_into(&scan, &mount, &mut buffer));
        check!("perception::edge::scan::ScanPoints::as_slice", buffer.as_slice());
        check!("perception::edge::scan::ScanPoints::dropped", buffer.dropped());
        check!("perception::edge::detect", detect::<512, 64>(&scan, &mount, s, &config));
        let detector_config = EdgeDetectorConfig { edge: config, mount, side: s };
        let mut detector = check!("perception::edge::EdgeDetector::new", EdgeDetector::<512, 64>::new(detector_config));
        check!("perception::edge::EdgeDetector::config", detector.config());
        let outcome = check!("perception::edge::EdgeDetector::detect", detector.detect(&scan, &odometry));
        if let Ok(outcome) = outcome {
            check!("perception::edge::EdgeOutcome::usable_error", outcome.usable_error());
        }
        check!("perception::edge::EdgeDetector::points", detector.points());
        check!("perception::edge::EdgeDetector::chain", detector.chain());
    }
}

// ---------------------------------------------------------------- furrow pursuing

/// Furrow parameters: Table 2's, one of them replaced by anything.
fn furrow_parameters() -> BoxedStrategy<FurrowParams> {
    (0..19_usize, raw(), 0..40_usize, any::<bool>())
        .prop_map(|(field, v, n, one)| {
            let mut p = FurrowParams::table2();
            let (mv, rv) = (Meters::new(v).ok(), Radians::new(v).ok());
            match field {
                0 => p.mount_x = mv.unwrap_or(p.mount_x),
                1 => p.mount_y = mv.unwrap_or(p.mount_y),
                2 => p.mount_height = mv.unwrap_or(p.mount_height),
                3 => p.mount_pitch = rv.unwrap_or(p.mount_pitch),
                4 => p.window_half_angle = rv.unwrap_or(p.window_half_angle),
                5 => p.template_width = n,
                6 => p.template_margin = n,
                7 => p.template_height = mv.unwrap_or(p.template_height),
                8 => p.height_floor = mv.unwrap_or(p.height_floor),
                9 => p.peak_threshold = v,
                10 => p.averaged_scans = n,
                11 => p.keep_distance = mv.unwrap_or(p.keep_distance),
                12 => p.min_points = n,
                13 => p.min_extent = mv.unwrap_or(p.min_extent),
                14 => p.enter = v,
                15 => p.exit = v,
                16 => {
                    p.rows = Rows::Two {
                        min_spacing: mv.unwrap_or(m(0.66)),
                        max_spacing: m(0.9),
                    }
                }
                17 => p.min_span = mv.unwrap_or(p.min_span),
                _ => {}
            }
            if one {
                p.rows = Rows::One;
            }
            p
        })
        .boxed()
}

/// The same maximum, bit for bit (a NaN score included).
fn same(a: &Maximum, b: &Maximum) -> bool {
    a.ray == b.ray && a.point == b.point && a.score.to_bits() == b.score.to_bits()
}

fn maxima() -> BoxedStrategy<Vec<Maximum>> {
    prop::collection::vec((0..400_usize, raw(), point::<Robot>()), 0..8)
        .prop_map(|v| {
            v.into_iter()
                .map(|(ray, score, point)| Maximum { ray, score, point })
                .collect()
        })
        .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    #[test]
    fn furrow_detection(
        parameters in furrow_parameters(),
        template in (0..20_usize, 0..10_usize, meters()),
        signal in prop::collection::vec(raw(), 0..80),
        heights in (prop::option::of(meters()), meters()),
        offset in any::<isize>(), k in 0..100_usize,
        angle in radians(), mount in (meters(), meters(), meters(), radians()), half in radians(),
        scores in prop::collection::vec(raw(), 0..60), threshold in raw(), radius in 0..10_usize,
        maxima in maxima(), reference_y in raw(), spacing in (meters(), meters()),
        line in (raw(), meters()), other in (raw(), meters()), x in raw(),
        line_points in prop::collection::vec(point::<Robot>(), 0..10),
        weakest in prop::option::of(raw()), fitted in any::<bool>(),
        ridge in (0.2..1.2_f64, 0.02..0.1_f64), parts in scan_parts(300), rows in any::<bool>(),
        odometry in prop::collection::vec(pose::<Odom>(), 1..5),
        limit in 0..12_usize, keep in meters(),
    ) {
        check!("perception::furrow::FurrowParams::table2", FurrowParams::table2());
        check!("perception::furrow::FurrowConfig::new", FurrowConfig::new(&parameters));
        let config = FurrowConfig::new(&parameters).unwrap_or(FurrowConfig::new(&FurrowParams::table2()).unwrap());
        check!("perception::furrow::FurrowConfig::params", config.params());
        let mp = check!("perception::furrow::FurrowConfig::mount", config.mount());
        check!("perception::furrow::FurrowConfig::window", config.window());
        check!("perception::furrow::FurrowConfig::template", config.template());
        check!("perception::furrow::FurrowConfig::thresholds", config.thresholds());

        // The parts of one scan.
        check!("perception::furrow::scan::MountPose::new", MountPose::new(mount.0, mount.1, mount.2, mount.3));
        check!("perception::furrow::scan::MountPose::x", mp.x());
        check!("perception::furrow::scan::MountPose::y", mp.y());
        check!("perception::furrow::scan::MountPose::height", mp.height());
        check!("perception::furrow::scan::MountPose::pitch", mp.pitch());
        check!("perception::furrow::scan::MountPose::ground_range", mp.ground_range(angle));
        if let Ok(window) = check!("perception::furrow::scan::ScanWindow::new", ScanWindow::new(half)) {
            check!("perception::furrow::scan::ScanWindow::half_angle", window.half_angle());
        }
        let (width, margin, height) = template;
        check!("perception::furrow::correlation::Template::new", Template::new(width, margin, height));
        let t = Template::new(width, margin, height).unwrap_or(*config.template());
        check!("perception::furrow::correlation::Template::width", t.width());
        check!("perception::furrow::correlation::Template::margin", t.margin());
        check!("perception::furrow::correlation::Template::height", t.height());
        check!("perception::furrow::correlation::Template::half_width", t.half_width());
        check!("perception::furrow::correlation::Template::half_length", t.half_length());
        check!("perception::furrow::correlation::Template::length", t.length());
        check!("perception::furrow::correlation::Template::value", t.value(offset));
        check!("perception::furrow::correlation::Template::energy", t.energy());
        check!("perception::furrow::correlation::height_signal", height_signal(heights.0, heights.1));
        let mut out = vec![f64::NAN; signal.len()];
        check!("perception::furrow::correlation::correlate", correlate(&signal, &t, &mut out));
        all_finite("the scores of correlate", &out);
        check!("perception::furrow::correlation::correlate_direct", correlate_direct(&signal, &t, &mut out));
        all_finite("the scores of correlate_direct", &out);

        // A scan over two ridges (or anything), through the configured mount.
        let lidar = furrow_common::Lidar::centred(300, 1.2);
        let (start, increment, wild) = parts;
        let (ridge_spacing, half_width) = ridge;
        let ridges = [
            furrow_common::Ridge { center_y: -ridge_spacing / 2.0, half_width, height: 0.25 },
            furrow_common::Ridge { center_y: ridge_spacing / 2.0, half_width, height: 0.3 },
        ];
        let ranges = if rows {
            // Cast through Table 2's mount (a perturbed one may look nowhere near the ground).
            furrow_common::ridge_scan(&FurrowParams::table2(), &lidar, (0.0, 0.0, 0.0), &ridges)
        } else {
            wild
        };
        let scan = Scan {
            start: if rows { rad(lidar.angle_min) } else { start },
            increment: if rows { rad(lidar.increment) } else { increment },
            ranges: &ranges,
            limits: RangeLimits::new(m(0.05), m(30.0)).unwrap(),
        };
        let mut rays = [None::<ScanPoint>; 512];
        let window = check!(
            "perception::furrow::scan::scan_to_points",
            furrow_scan_to_points(&scan, config.mount(), config.window(), &mut rays)
        );
        let count = window.map_or(0, |w| w.count);
        let rays = &rays[..count];
        all_finite("the rays of scan_to_points", &rays);
        let heights: Vec<f64> = rays
            .iter()
            .map(|r| height_signal(r.map(|p| p.height), config.params().height_floor))
            .collect();
        check!("perception::furrow::selection::locate", locate(k, rays, &heights, config.template()));
        check!("perception::furrow::selection::locate", locate(k, rays, &signal, &t));

        // Selection.
        check!("perception::furrow::selection::local_maxima", local_maxima(&scores, threshold, radius));
        // A selection passes one of the given maxima through, unchanged, its
        // score included (the caller's, any f64 here): its point is checked.
        check!("perception::furrow::selection::select_one", select_one(&maxima, reference_y).map(|o| o.point));
        let one = select_one(&maxima, reference_y);
        prop_assert!(one.is_none_or(|o| maxima.iter().any(|m| same(m, &o))));
        check!("perception::furrow::selection::Spacing::new", Spacing::new(spacing.0, spacing.1));
        let spacing = Spacing::new(spacing.0, spacing.1).unwrap_or(Spacing::new(m(0.66), m(0.9)).unwrap());
        check!("perception::furrow::selection::Spacing::min", spacing.min());
        check!("perception::furrow::selection::Spacing::max", spacing.max());
        check!("perception::furrow::selection::Spacing::contains", spacing.contains(x));
        // The pair's maxima are given ones, scores included: their points are checked.
        check!("perception::furrow::selection::select_pair", select_pair(&maxima, &spacing, reference_y).map(|p| p.points()));
        let pair = select_pair(&maxima, &spacing, reference_y);
        let given = |p: Pair<Maximum>| {
            maxima.iter().any(|m| same(m, &p.left)) && maxima.iter().any(|m| same(m, &p.right))
        };
        prop_assert!(pair.is_none_or(given));
        if let Some(pair) = pair {
            check!("perception::furrow::selection::Pair::weaker_score", pair.weaker_score());
            let points = check!("perception::furrow::selection::Pair::points", pair.points());
            check!("perception::furrow::selection::Pair::mid", points.mid());
        }
        if let [a, b, ..] = maxima.as_slice() {
            let pair = Pair { left: *a, right: *b };
            check!("perception::furrow::selection::Pair::weaker_score", pair.weaker_score());
            check!("perception::furrow::selection::Pair::mid", pair.points().mid());
        }

        // Row lines.
        check!("perception::furrow::lines::RowLine::new", RowLine::new(line.0, line.1));
        let rows_seen: Vec<RowLine> = [line, other]
            .iter()
            .map(|&(a, b)| RowLine::new(a, b).unwrap_or(RowLine::new(0.1, m(0.4)).unwrap()))
            .collect();
        for row in &rows_seen {
            check!("perception::furrow::lines::RowLine::slope", row.slope());
            check!("perception::furrow::lines::RowLine::intercept", row.intercept());
            check!("perception::furrow::lines::RowLine::y_at", row.y_at(x));
            check!("perception::furrow::lines::tracking_error", row_tracking_error(row));
        }
        check!("perception::furrow::lines::mean_tracking_error", mean_tracking_error(&rows_seen[0], &rows_seen[1]));
        check!("perception::furrow::lines::fit_row_line", fit_row_line(line_points.iter()));
        check!(
            "perception::furrow::lines::fit_row_line_toward",
            fit_row_line_toward(line_points.iter(), Radians::new(x).unwrap_or(Radians::ZERO), keep)
        );
        check!("perception::furrow::quality::furrow_verdict", furrow_verdict(config.thresholds(), fitted, weakest));

        // Accumulation through odometry.
        check!("perception::furrow::accumulation::Accumulator::new", Accumulator::<8>::new(limit, keep));
        if let Ok(acc) = Accumulator::<8>::new(limit.clamp(1, 8), m(6.0)) {
            check!("perception::furrow::accumulation::Accumulator::with_span", acc.with_span(keep));
        }
        let mut kept = Accumulator::<8>::new(limit.clamp(1, 8), keep).unwrap_or(Accumulator::new(4, m(6.0)).unwrap());
        for (i, odom) in odometry.iter().enumerate() {
            let selection = if i % 2 == 0 {
                Selected::One(line_points.first().copied().unwrap_or(Point2::origin()))
            } else {
                Selected::Two(Pair { left: Point2::new(4.0, 0.4).unwrap(), right: Point2::new(4.0, -0.4).unwrap() })
            };
            check!("perception::furrow::accumulation::Selected::reference", selection.reference());
            check!("perception::furrow::accumulation::Accumulator::odom_to_robot", Accumulator::<8>::odom_to_robot(odom));
            let to_odom: Transform2<Robot, Odom> = odom.body_to_frame();
            check!("perception::furrow::accumulation::Selected::moved", selection.moved(&to_odom));
            check!("perception::furrow::accumulation::Accumulator::push", kept.push(&selection, odom));
            check!("perception::furrow::accumulation::Accumulator::len", kept.len());
            check!("perception::furrow::accumulation::Accumulator::is_empty", kept.is_empty());
            check!("perception::furrow::accumulation::Accumulator::newest", kept.newest(odom));
            check!("perception::furrow::accumulation::Accumulator::newest_heading", kept.newest_heading());
            check!("perception::furrow::accumulation::Accumulator::recent_turn", kept.recent_turn(i));
            check!(
                "perception::furrow::accumulation::Accumulator::in_robot_frame",
                kept.in_robot_frame(odom).collect::<Vec<_>>()
            );
            check!("perception::furrow::accumulation::Accumulator::forget_far", kept.forget_far(odom));
        }
        check!("perception::furrow::accumulation::Accumulator::clear", kept.clear());
        prop_assert!(kept.is_empty());

        // The detector over the scan, seen from each odometry pose.
        let detector = check!("perception::furrow::FurrowDetector::new", FurrowDetector::<512, 32>::new(config));
        let mut detector = detector.unwrap_or(FurrowDetector::new(FurrowConfig::new(&FurrowParams::table2()).unwrap()).unwrap());
        check!("perception::furrow::FurrowDetector::config", detector.config());
        check!("perception::furrow::FurrowDetector::maxima", detector.maxima(&scan));
        // Along the rows, 0.1 m per scan (enough scans for row lines), or the
        // same scan from each of the odometry poses.
        let drive: Vec<(Pose2<Odom>, Vec<f64>)> = if rows {
            (0..8)
                .map(|k| {
                    let at = (0.1 * f64::from(k), 0.0, 0.0);
                    let ranges = furrow_common::ridge_scan(&FurrowParams::table2(), &lidar, at, &ridges);
                    (Pose2::new(at.0, at.1, at.2).unwrap(), ranges)
                })
                .collect()
        } else {
            odometry.iter().map(|o| (*o, ranges.clone())).collect()
        };
        for (odom, ranges) in &drive {
            let scan = Scan { ranges, ..scan };
            check!("perception::furrow::FurrowDetector::expect_heading", detector.expect_heading(Some(odom.heading)));
            check!("perception::furrow::FurrowDetector::detect", detector.detect(&scan, odom));
            check!("perception::furrow::FurrowDetector::accumulated", detector.accumulated());
        }
        check!("perception::furrow::FurrowDetector::reset", detector.reset());
        prop_assert_eq!(detector.accumulated(), 0);
    }
}

// ---------------------------------------------------------------- the detector seam

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn any_detector_and_held_lines(
        edge in any::<bool>(), s in side(), d in 0.5..3.0_f64,
        faults in prop::collection::vec((0..360_usize, raw()), 0..20),
        parts in scan_parts(360), odometry in prop::collection::vec(pose::<Odom>(), 1..4),
        moves in prop::collection::vec(pose::<Robot>(), 1..4),
        parabola in (raw(), raw(), raw()), offset in meters(), rows in prop::collection::vec((raw(), meters()), 2),
    ) {
        let config = if edge {
            AnyDetectorConfig::Edge(EdgeDetectorConfig {
                edge: EdgeConfig::pierre2022().unwrap(),
                mount: Transform2::new(0.0, 0.0, 0.0).unwrap(),
                side: s,
            })
        } else {
            AnyDetectorConfig::Furrow(FurrowConfig::new(&FurrowParams::table2()).unwrap())
        };
        let mut detector = check!("perception::detector::Detector::configure", AnyDetector::<512, 64, 512, 32>::configure(&config)).unwrap();
        check!("perception::detector::AnyDetector::as_edge", detector.as_edge().map(EdgeDetector::config));
        check!("perception::detector::AnyDetector::as_furrow", detector.as_furrow().map(FurrowDetector::config));
        check!("perception::detector::AnyDetector::as_vine", detector.as_vine().map(|d| d.config()));
        let (start, increment, wild) = parts;
        let ranges = if edge { wall_ranges(d, 360, &faults) } else { wild };
        let scan = Scan { start, increment, ranges: &ranges, limits: RangeLimits::new(m(0.05), m(30.0)).unwrap() };
        for odom in &odometry {
            check!("perception::detector::Detector::expect_heading", detector.expect_heading(Some(odom.heading)));
            let seen = check!("perception::detector::Detector::observe", detector.observe(&scan, odom));
            if let Ok(seen) = seen {
                let kind: Detection<&str> = check!("perception::detector::Detection::map_line", seen.map_line(|_| "held"));
                prop_assert_eq!(kind.line.is_some(), seen.line.is_some());
                if let Some(line) = seen.line {
                    for p in &moves {
                        check!("perception::detector::HeldLine::error_at", line.error_at(p));
                    }
                }
            }
        }
        // Lines built by hand, with any coefficients.
        let fit = ParabolaFit { a: parabola.0, b: parabola.1, c: parabola.2 };
        let rows: Vec<RowLine> = rows
            .iter()
            .map(|&(a, b)| RowLine::new(a, b).unwrap_or(RowLine::new(0.0, b).unwrap()))
            .collect();
        let lines = [
            AnyLine::Edge(EdgeLine { parabola: fit, side: s, offset }),
            AnyLine::Furrow(RowLines::One(rows[0])),
            AnyLine::Furrow(RowLines::Two(Pair { left: rows[0], right: rows[1] })),
        ];
        for line in lines {
            for p in &moves {
                check!("perception::detector::HeldLine::error_at", line.error_at(p));
            }
        }
    }
}

// ---------------------------------------------------------------- vine rows

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn vine_detection(
        model in (0..40_usize, 0..40_usize, raw()), floor in raw(), threshold in raw(),
        ransac in (0..2000_usize, raw(), 0..80_usize, raw()), bounds in (raw(), raw(), raw()),
        line in (0..8_usize, raw()), verdict in (raw(), raw()), winter in any::<bool>(),
        parts in scan_parts(271), clean in any::<bool>(), poses in prop::collection::vec(pose::<Odom>(), 1..4),
        at in pose::<Robot>(), signal in prop::collection::vec(raw(), 0..80), points in prop::collection::vec((point::<Odom>(), raw()), 0..8),
        yaw in radians(), coefficients in (raw(), meters()),
    ) {
        use fieldguide::perception::furrow::scan::ScanPoint;
        use fieldguide::perception::vine::aggregation::{lateral_deviation, SetPoint, SetPoints};
        use fieldguide::perception::vine::correlation::{correlate as vine_correlate, VineModel};
        use fieldguide::perception::vine::ground::{fit_ground, Ground, GroundParams};
        use fieldguide::perception::vine::{row_deviation, vine_verdict, VineConfig, VineDetector, VineLine, VineParams};
        use rand_core::SeedableRng;
        check!("perception::vine::VineParams::summer", VineParams::summer());
        check!("perception::vine::VineParams::winter", VineParams::winter());
        let mut p = if winter { VineParams::winter() } else { VineParams::summer() };
        p.model_width = model.0;
        p.model_margin = model.1;
        p.model_height = Meters::new(model.2).unwrap_or(p.model_height);
        p.height_floor = Meters::new(floor).unwrap_or(p.height_floor);
        p.threshold = threshold;
        p.ransac_iterations = ransac.0;
        p.ransac_tolerance = Meters::new(ransac.1).unwrap_or(p.ransac_tolerance);
        p.ransac_min_inliers = ransac.2;
        p.max_cross_slope = ransac.3;
        p.max_deviation = Meters::new(bounds.0).unwrap_or(p.max_deviation);
        p.first_lateral = Meters::new(bounds.1).unwrap_or(p.first_lateral);
        p.keep_distance = Meters::new(bounds.2).unwrap_or(p.keep_distance);
        p.min_points = line.0;
        p.min_extent = Meters::new(line.1).unwrap_or(p.min_extent);
        p.enter = verdict.0;
        p.exit = verdict.1;
        let built = check!("perception::vine::VineConfig::new", VineConfig::new(&p));
        names_a_requirement("VineConfig::new", &built);
        let config = built.unwrap_or(VineConfig::new(&VineParams::summer()).unwrap());
        check!("perception::vine::VineConfig::params", config.params());
        check!("perception::vine::VineConfig::model", config.model());
        check!("perception::vine::VineConfig::ground", config.ground());
        check!("perception::vine::VineConfig::thresholds", config.thresholds());
        let mut d = check!("perception::vine::VineDetector::new", VineDetector::<512, 16>::new(config)).unwrap_or(VineDetector::new(VineConfig::new(&VineParams::summer()).unwrap()).unwrap());
        check!("perception::vine::VineDetector::config", d.config());
        let lidar = vine_scans::Lidar::table1();
        let world = vine_scans::vineyard(vine_scans::World::ground(0.0, 0.1), 2.2, 0.25, &[]);
        let (start, increment, wild) = parts;
        for (i, odom) in poses.iter().enumerate() {
            let ranges = if clean { lidar.cast(&world, (0.1 * i as f64, 0.0, 0.0)) } else { wild.clone() };
            let scan = if clean { lidar.scan(&ranges) } else { Scan { start, increment, ranges: &ranges, limits: RangeLimits::new(m(0.05), m(30.0)).unwrap() } };
            check!("perception::vine::VineDetector::candidates", d.candidates(&scan));
            let seen = check!("perception::vine::VineDetector::detect", d.detect(&scan, odom));
            names_a_requirement("VineDetector::detect", &seen);
            if let Ok(Some(line)) = seen.map(|s| s.line) {
                check!("perception::detector::HeldLine::error_at", line.error_at(&at));
            }
        }
        let kept = check!("perception::vine::VineDetector::set_points", d.set_points());
        check!("perception::vine::aggregation::SetPoints::len", kept.len());
        check!("perception::vine::aggregation::SetPoints::is_empty", kept.is_empty());
        check!("perception::vine::aggregation::SetPoints::newest", kept.newest());
        check!("perception::vine::aggregation::SetPoints::mean_score", kept.mean_score());
        check!("perception::vine::aggregation::SetPoints::iter", kept.iter().collect::<Vec<_>>());
        check!("perception::vine::aggregation::SetPoints::in_robot_frame", kept.in_robot_frame(&poses[0]).collect::<Vec<_>>());
        check!("perception::vine::VineDetector::reset", d.reset());
        // The parts, with any values.
        let vm = check!("perception::vine::correlation::VineModel::new", VineModel::new(model.0, model.1, Meters::new(model.2).unwrap_or(Meters::ZERO)));
        let vm = vm.unwrap_or(VineModel::new(10, 10, m(1.0)).unwrap());
        check!("perception::vine::correlation::VineModel::width", vm.width());
        check!("perception::vine::correlation::VineModel::margin", vm.margin());
        check!("perception::vine::correlation::VineModel::height", vm.height());
        check!("perception::vine::correlation::VineModel::length", vm.length());
        check!("perception::vine::correlation::VineModel::value", vm.value(model.0));
        let mut out = vec![0.0; signal.len()];
        check!("perception::vine::correlation::correlate", vine_correlate(&signal, &vm, &mut out));
        all_finite("vine correlation", &out);
        prop_assert!(out.iter().all(|r| r.abs() <= 1.0));
        let gp = check!("perception::vine::ground::GroundParams::new", GroundParams::new(ransac.0, ransac.1, ransac.2, ransac.3));
        let gp = gp.unwrap_or(GroundParams::new(32, 0.05, 20, 0.4).unwrap());
        check!("perception::vine::ground::GroundParams::iterations", gp.iterations());
        check!("perception::vine::ground::GroundParams::tolerance", gp.tolerance());
        check!("perception::vine::ground::GroundParams::min_inliers", gp.min_inliers());
        check!("perception::vine::ground::GroundParams::max_slope", gp.max_slope());
        let rays: Vec<Option<ScanPoint>> = points
            .iter()
            .map(|(q, h)| Meters::new(*h).ok().map(|height| ScanPoint { ground: Point2::new(q.x(), q.y()).unwrap(), height }))
            .collect();
        let mut rng = rand_xoshiro::Xoshiro128PlusPlus::seed_from_u64(1);
        if let Ground::Profile(g) = check!("perception::vine::ground::fit_ground", fit_ground(&rays, &gp, &mut rng)) {
            for r in rays.iter().flatten() {
                check!("perception::vine::ground::GroundLine::height_above", g.height_above(r));
            }
        }
        let mut store = check!("perception::vine::aggregation::SetPoints::new", SetPoints::<4>::new(Meters::new(bounds.2).unwrap_or(Meters::ZERO))).unwrap_or(SetPoints::new(m(1.0)).unwrap());
        for (q, score) in &points {
            // A set-point's score is a correlation, in [−1, 1].
            let score = if score.is_finite() { score.clamp(-1.0, 1.0) } else { 0.0 };
            check!("perception::vine::aggregation::SetPoints::push", store.push(SetPoint { point: *q, score }));
            check!("perception::vine::aggregation::lateral_deviation", lateral_deviation(*q, points[0].0, yaw));
        }
        check!("perception::vine::aggregation::SetPoints::forget_far", store.forget_far(&poses[0]));
        check!("perception::vine::aggregation::SetPoints::clear", store.clear());
        let row = RowLine::new(coefficients.0, coefficients.1).unwrap_or(RowLine::new(0.0, coefficients.1).unwrap());
        check!("perception::vine::row_deviation", row_deviation(&row));
        check!("perception::detector::HeldLine::error_at", VineLine(row).error_at(&at));
        check!("perception::detector::HeldLine::error_at", AnyLine::Vine(VineLine(row)).error_at(&at));
        let t = QualityThresholds::new(0.5, 0.35, Better::Higher).unwrap();
        check!("perception::vine::vine_verdict", vine_verdict(&t, clean, Some(verdict.0)));
    }
}

// ---------------------------------------------------------------- rows

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn rows_initialisation_and_filter(
        spacing in (raw(), raw(), 0..12_usize, 0..10_usize), range in (meters(), meters()),
        filtering in (raw(), raw(), 0..18_usize, 0..4_u32, meters()),
        lines in prop::collection::vec((raw(), meters()), 0..10),
        k in 0..20_usize, scans in 1..4_usize,
    ) {
        let lines: Vec<RowLine> = lines
            .iter()
            .map(|&(a, b)| RowLine::new(a, b).unwrap_or(RowLine::new(0.0, b).unwrap()))
            .collect();
        // Initialisation.
        check!("perception::rows::spacing::SpacingConfig::new", SpacingConfig::new(spacing.0, spacing.1, spacing.2, spacing.3));
        let config = SpacingConfig::new(spacing.0, spacing.1, spacing.2, spacing.3).unwrap_or_default();
        let ranged = check!("perception::rows::spacing::SpacingConfig::with_distance_range", config.with_distance_range(range.0, range.1));
        names_a_requirement("with_distance_range", &ranged);
        let config = ranged.unwrap_or(config);
        check!("perception::rows::spacing::SpacingConfig::distance_range", config.distance_range());
        check!("perception::rows::spacing::SpacingConfig::max_slope", config.max_slope());
        check!("perception::rows::spacing::SpacingConfig::equidistance", config.equidistance());
        check!("perception::rows::spacing::SpacingConfig::estimates", config.estimates());
        check!("perception::rows::spacing::SpacingConfig::rows", config.rows());
        let pair = check!("perception::rows::spacing::closest_pair", closest_pair(&lines, &config));
        if let Some(pair) = pair {
            check!("perception::rows::spacing::row_distance", row_distance(&pair));
        }
        let mut estimator = check!("perception::rows::spacing::SpacingEstimator::new", SpacingEstimator::new(config));
        check!("perception::rows::spacing::SpacingEstimator::config", estimator.config());
        for _ in 0..scans {
            check!("perception::rows::spacing::SpacingEstimator::observe", estimator.observe(&lines));
        }
        check!("perception::rows::spacing::SpacingEstimator::count", estimator.count());
        check!("perception::rows::spacing::SpacingEstimator::is_ready", estimator.is_ready());
        check!("perception::rows::spacing::SpacingEstimator::distance", estimator.distance());
        check!("perception::rows::spacing::SpacingEstimator::initial_rows", estimator.initial_rows());

        // The filter, from the lines themselves as previous rows.
        let (d_min, d_max, steps, lost_after, d) = filtering;
        check!("perception::rows::filter::FilterConfig::new", FilterConfig::new(d_min, d_max, steps, lost_after));
        let config = FilterConfig::new(d_min, d_max, steps, lost_after).unwrap_or_default();
        check!("perception::rows::filter::FilterConfig::delta_min", config.delta_min());
        check!("perception::rows::filter::FilterConfig::delta_max", config.delta_max());
        check!("perception::rows::filter::FilterConfig::steps", config.steps());
        check!("perception::rows::filter::FilterConfig::lost_after", config.lost_after());
        check!("perception::rows::filter::FilterConfig::tolerance", config.tolerance(k));
        check!("perception::rows::filter::side_indices", side_indices(&lines));
        check!("perception::rows::filter::side_rows", side_rows(&lines));
        check!("perception::rows::filter::tracking_error", rows_tracking_error(&lines));
        check!("perception::rows::filter::RowFilter::new", RowFilter::new(d, &lines, config));
        if let Ok(mut filter) = RowFilter::new(d, &lines, config) {
            for _ in 0..scans {
                let outcome = check!("perception::rows::filter::RowFilter::update", filter.update(&lines[..k.min(lines.len())]));
                check!("perception::rows::filter::Outcome::matched", outcome.matched());
                check!("perception::rows::filter::Outcome::verdict", outcome.verdict());
            }
            check!("perception::rows::filter::RowFilter::rows", filter.rows());
            check!("perception::rows::filter::RowFilter::distance", filter.distance());
            check!("perception::rows::filter::RowFilter::config", filter.config());
            check!("perception::rows::filter::RowFilter::misses", filter.misses());
            check!("perception::rows::filter::RowFilter::is_lost", filter.is_lost());
            check!("perception::rows::filter::RowFilter::sides", filter.sides());
            let motion = Pose2::<Robot>::new(d.get() * 0.1, -d.get() * 0.05, 0.01 * k as f64).unwrap();
            check!("perception::rows::filter::RowFilter::move_by", { filter.move_by(&motion); filter.rows().to_vec() });
            for line in &lines {
                check!("perception::rows::filter::seen_from", seen_from(line, &motion));
            }
        }
    }
}

// ---------------------------------------------------------------- rows: points, line finder, detector

fn variant() -> impl Strategy<Value = Variant> {
    prop::sample::select(Variant::ALL.to_vec())
}

/// The line finder's constants: the authors' for a variant, or every one
/// drawn (small iteration counts, so that a case stays quick).
fn ruby_params() -> BoxedStrategy<RubyParams> {
    let drawn = (
        (
            raw(),
            raw(),
            meters(),
            meters(),
            raw(),
            meters(),
            raw(),
            raw(),
        ),
        (
            raw(),
            any::<u8>(),
            0..4_u16,
            0..50_u16,
            raw(),
            meters(),
            0..6_u8,
        ),
    );
    (variant(), any::<u64>(), prop::option::of(drawn))
        .prop_map(|(variant, seed, drawn)| {
            let authors = RubyParams {
                seed,
                ..RubyParams::authors(variant)
            };
            let Some((
                (rho, lambda, zeta, outlier, beta, same, alpha, tau),
                (kept, min_kept, iterations, models, until, merge, rounds),
            )) = drawn
            else {
                return authors;
            };
            RubyParams {
                outlier_energy: rho,
                neighbour_penalty: lambda,
                neighbour_scale: zeta,
                outlier_distance: outlier,
                parallel_slope: beta,
                same_intercept: same,
                alpha,
                fitness_weight: tau,
                kept_share: kept,
                min_kept,
                iterations,
                models_per_iteration: models,
                search_until: until,
                merge_distance: merge,
                fit_rounds: rounds,
                ..authors
            }
        })
        .boxed()
}

fn sensor_mount() -> BoxedStrategy<Transform2<Sensor, Robot>> {
    (near(2.0), near(2.0), near(4.0))
        .prop_map(|(x, y, h)| {
            Transform2::new(x, y, h).unwrap_or(Transform2::new(0.3, 0.0, 0.0).unwrap())
        })
        .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn rows_points_and_line_finder(
        v in variant(), name in prop_oneof![Just(String::from("RGOP")), Just(String::from("rgoppni")), "[A-Za-z]{0,8}"],
        params in ruby_params(), parts in scan_parts(64), limits in limits(), mount in sensor_mount(),
        merge in meters(), carried in prop::collection::vec((raw(), meters()), 0..10),
        xy in prop::collection::vec((near(10.0), near(10.0)), 0..40), scans in 1..4_usize,
    ) {
        check!("perception::rows::ruby::Variant::name", v.name());
        check!("perception::rows::ruby::Variant::from_name", Variant::from_name(&name));
        prop_assert_eq!(Variant::from_name(v.name()), Some(v));
        check!("perception::rows::ruby::Variant::genetic", v.genetic());
        check!("perception::rows::ruby::Variant::one_point", v.one_point());
        check!("perception::rows::ruby::Variant::split_sides", v.split_sides());
        check!("perception::rows::ruby::Variant::shared_points", v.shared_points());
        check!("perception::rows::ruby::RubyParams::authors", RubyParams::authors(v));

        // The scan's points and Z*.
        let (start, increment, ranges) = parts;
        let scan = Scan { start, increment, ranges: &ranges, limits };
        let mut points: Points<64> = Points::new();
        let gathered = check!("perception::rows::points::scan_points", scan_points(&scan, &mount, &mut points));
        names_a_requirement("scan_points", &gathered);
        all_finite("scan_points' points", &points);
        // The same points through a table of the rays, shorter than the scan.
        let mut rays: Rays<16> = check!("perception::rows::points::Rays::new", Rays::new());
        let mut tabled: Points<64> = Points::new();
        let again = check!("perception::rows::points::scan_points_with", scan_points_with(&scan, &mount, &mut rays, &mut tabled));
        prop_assert_eq!(&again, &gathered);
        prop_assert_eq!(&tabled, &points);
        check!("perception::rows::points::merge_runs", { merge_runs(&mut points, merge); points.clone() });
        let mut drawn: Points<64> = xy
            .iter()
            .map(|&(x, y)| RowPoint { position: Point2::new(x, y).unwrap(), returns: 1 })
            .collect();
        check!("perception::rows::points::merge_runs", { merge_runs(&mut drawn, merge); drawn.clone() });

        // The line finder, on the scan's points and on points drawn anywhere.
        let config = check!("perception::rows::ruby::RubyConfig::new", RubyConfig::new(params));
        names_a_requirement("RubyConfig::new", &config);
        let config = config.unwrap_or(RubyConfig::new(RubyParams::authors(v)).unwrap());
        check!("perception::rows::ruby::RubyConfig::params", config.params());
        let mut ruby = check!("perception::rows::ruby::Ruby::new", Ruby::<64>::new(config));
        check!("perception::rows::ruby::Ruby::config", ruby.config());
        let lines: Vec<RowLine> = carried
            .iter()
            .map(|&(a, b)| RowLine::new(a, b).unwrap_or(RowLine::new(0.0, b).unwrap()))
            .collect();
        for _ in 0..scans {
            check!("perception::rows::ruby::Ruby::find", ruby.find(&points));
            check!("perception::rows::ruby::Ruby::models", ruby.models());
            check!("perception::rows::ruby::Ruby::carry", { ruby.carry(&lines); ruby.models().to_vec() });
            let motion = Pose2::<Robot>::new(0.02, -0.01, 0.005).unwrap();
            check!("perception::rows::ruby::Ruby::move_by", {
                ruby.move_by(|line| fieldguide::perception::rows::filter::seen_from(line, &motion));
                ruby.models().to_vec()
            });
            check!("perception::rows::ruby::Ruby::find", ruby.find(&drawn));
        }
        check!("perception::rows::ruby::Ruby::reset", { ruby.reset(); ruby.models().to_vec() });
        prop_assert!(ruby.models().is_empty());
    }

    #[test]
    fn rows_detector(
        v in variant(), params in ruby_params(), mounts in (sensor_mount(), sensor_mount(), any::<bool>()),
        still in meters(), min_support in 0..8_usize, count in 0..4_usize,
        parts in scan_parts(64), odometry in prop::collection::vec(pose::<Odom>(), 1..14),
    ) {
        let (first, second, two) = mounts;
        let authors = check!("perception::rows::RowsParams::authors", RowsParams::authors(v, first));
        let mut p = if two {
            check!("perception::rows::RowsParams::with_second", authors.with_second(second))
        } else {
            authors
        };
        p.ruby = params;
        p.still = still;
        p.min_support = min_support;
        let config = check!("perception::rows::RowsConfig::new", RowsConfig::new(p));
        names_a_requirement("RowsConfig::new", &config);
        let config = config.unwrap_or(RowsConfig::new(authors).unwrap());
        check!("perception::rows::RowsConfig::params", config.params());
        let mut detector = check!("perception::rows::RowsDetector::new", RowsDetector::<64>::new(config));
        let mut through_trait = check!("perception::detector::Detector::configure", RowsDetector::<64>::configure(&config)).unwrap();
        let (start, increment, ranges) = parts;
        let scan = Scan { start, increment, ranges: &ranges, limits: RangeLimits::new(m(0.05), m(30.0)).unwrap() };
        // Most ticks with one scan per LiDAR, the last with `count` scans.
        let lidars = config.params().mounts.iter().flatten().count();
        for (k, odom) in odometry.iter().enumerate() {
            let n = if k + 1 == odometry.len() { count } else { lidars };
            let scans = vec![scan; n];
            let seen = check!("perception::rows::RowsDetector::observe_scans", detector.observe_scans(&scans, odom));
            names_a_requirement("observe_scans", &seen);
            if n != lidars {
                prop_assert_eq!(seen.unwrap_err().requirement, "ROWS-MOUNTS");
            }
            let one = check!("perception::detector::Detector::observe", through_trait.observe(&scan, odom));
            names_a_requirement("Detector::observe", &one);
            check!("perception::rows::RowsDetector::line_finder", detector.line_finder().models());
            check!("perception::rows::RowsDetector::points", detector.points());
            check!("perception::rows::RowsDetector::row_distance", detector.row_distance());
            check!("perception::rows::RowsDetector::rows", detector.rows());
        }
    }

    #[test]
    fn differential_robot_and_crop_navigator(
        limits in (meters(), fin()), motion in (fin(), fin(), fin(), fin()),
        v in variant(), mounts in (sensor_mount(), sensor_mount()),
        knobs in (0_u8..4, fin(), fin(), fin(), 0_u8..4, 0_u16..4),
        parts in scan_parts(64), ticks in prop::collection::vec((pose::<Odom>(), 0..3_usize), 1..30),
        points in prop::collection::vec((near(5.0), near(5.0)), 0..8), reach in fin(), backward in any::<bool>(),
    ) {
        use fieldguide::model::differential::Differential;
        use fieldguide::perception::furrow::selection::Pair;
        use fieldguide::perception::rows::points::RowPoint;
        use fieldguide::supervisor::crop_navigation::{in_travel_frame, nearest_point_behind, to_body, CropNavigator, NavParams};
        let (track, top) = limits;
        let d = check!("model::differential::Differential::new", Differential::new(track, MetersPerSecond::new(top).unwrap()));
        names_a_requirement("Differential::new", &d);
        let (sv, sw, sl, sr) = motion;
        if let Ok(d) = d {
            check!("model::differential::Differential::track", d.track());
            check!("model::differential::Differential::max_wheel_speed", d.max_wheel_speed());
            let wheels = check!("model::differential::Differential::wheels", d.wheels(MetersPerSecond::new(sv).unwrap(), RadiansPerSecond::new(sw).unwrap()));
            if let Ok((Command::Differential { left, right }, _)) = wheels {
                prop_assert!(d.within(left, right));
            }
            let (l, r) = (MetersPerSecond::new(sl).unwrap(), MetersPerSecond::new(sr).unwrap());
            check!("model::differential::Differential::motion", d.motion(l, r));
            check!("model::differential::Differential::within", d.within(l, r));
        }
        let rows = RowsConfig::new(RowsParams::authors(v, mounts.0).with_second(mounts.1)).unwrap();
        let authors = check!("supervisor::crop_navigation::NavParams::authors", NavParams::authors(rows)).unwrap();
        let (inter_rows, speed, body, margin, end_scans, blind) = knobs;
        let p = NavParams {
            inter_rows,
            top_speed: MetersPerSecond::new(speed).unwrap(),
            body_length: m(body),
            end_margin: m(margin),
            end_scans,
            blind_ticks: blind,
            ..authors
        };
        let nav = check!("supervisor::crop_navigation::CropNavigator::new", CropNavigator::<64>::new(p));
        names_a_requirement("CropNavigator::new", &nav);
        let mut nav = nav.unwrap_or(CropNavigator::<64>::new(authors).unwrap());
        let (start, increment, ranges) = parts;
        let scan = Scan { start, increment, ranges: &ranges, limits: RangeLimits::new(m(0.05), m(30.0)).unwrap() };
        for (odom, n) in &ticks {
            let tick = check!("supervisor::crop_navigation::CropNavigator::step", nav.step(&vec![scan; *n], odom));
            names_a_requirement("CropNavigator::step", &tick);
            if let Ok(t) = tick {
                prop_assert!(Vehicle::Differential(p.vehicle).check(&t.command).is_ok());
            }
            check!("supervisor::crop_navigation::CropNavigator::phase", nav.phase());
            check!("supervisor::crop_navigation::CropNavigator::detector", nav.detector().points());
        }
        let pts: Vec<RowPoint> = points.iter().map(|&(x, y)| RowPoint { position: Point2::new(x, y).unwrap(), returns: 1 }).collect();
        check!("supervisor::crop_navigation::nearest_point_behind", nearest_point_behind(&pts, backward, reach));
        let (Ok(a), Ok(b)) = (RowLine::new(sl.clamp(-1e6, 1e6), m(sv)), RowLine::new(sl.clamp(-1e6, 1e6), m(sw))) else { return Ok(()) };
        let sides = Pair { left: a, right: b };
        check!("supervisor::crop_navigation::in_travel_frame", in_travel_frame(&sides, &[a, b], backward));
        let c = Command::Differential { left: MetersPerSecond::new(sl).unwrap(), right: MetersPerSecond::new(sr).unwrap() };
        check!("supervisor::crop_navigation::to_body", to_body(&c, backward));
    }
}

// ---------------------------------------------------------------- mission supervisor

fn hazard() -> BoxedStrategy<Hazard> {
    prop_oneof![
        Just(Hazard::Clear),
        Just(Hazard::Critical),
        Just(Hazard::NoDetourOnRoad),
        prop::option::of(pose::<World>()).prop_map(|detour| Hazard::Warning { detour }),
    ]
    .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn mission_supervisor(
        period in seconds(), stall in seconds(), leg in seconds(), ticks16 in (0..20_u16, 0..20_u16),
        lengths in (meters(), meters(), meters()), waypoints in prop::collection::vec(pose::<World>(), 0..4),
        row_start in pose::<World>(), gnss_poses in prop::collection::vec((prop::option::of(pose::<World>()), pose::<Robot>(), hazard(), any::<bool>(), prop::option::of(meters())), 1..40),
        index in 0..4_u8,
    ) {
        use fieldguide::supervisor::mission as mi;
        check!("supervisor::mission::config::MachineConfig::from_ticks", mi::MachineConfig::from_ticks(ticks16.0, ticks16.1));
        check!("supervisor::mission::config::MachineConfig::new", mi::MachineConfig::new(period, stall, leg));
        let carob = check!("supervisor::mission::config::MissionConfig::carob", mi::MissionConfig::carob()).unwrap();
        let machine = mi::MachineConfig::new(period, stall, leg).unwrap_or(carob.machine);
        check!("supervisor::mission::config::MachineConfig::stall_ticks", machine.stall_ticks());
        check!("supervisor::mission::config::MachineConfig::leg_ticks", machine.leg_ticks());
        #[cfg(feature = "fault-injection")]
        {
            let faulty = check!("supervisor::mission::config::MachineConfig::with_fault", machine.with_fault(mi::Fault::ReplanInField));
            check!("supervisor::mission::config::MachineConfig::fault", faulty.fault());
        }
        let speeds = (carob.cruise_speed, carob.turn_speed);
        let config = check!("supervisor::mission::config::MissionConfig::new", mi::MissionConfig::new(machine, lengths.0, lengths.1, lengths.2, carob.radius, speeds)).unwrap_or(carob);
        let config = check!("supervisor::mission::config::MissionConfig::with_road_radius", config.with_road_radius(TurningRadius::new(lengths.0).unwrap_or(carob.radius)));
        let road = check!("supervisor::mission::tasks::Task::approximation", mi::Task::approximation(&waypoints));
        let row = mi::Row { start: row_start, length: lengths.0 };
        let field = check!("supervisor::mission::tasks::Task::treatment", mi::Task::treatment(&[row, row]));
        let tasks: Vec<mi::Task> = [road, field].into_iter().filter_map(Result::ok).collect();
        for task in &tasks {
            check!("supervisor::mission::tasks::Task::kind", task.kind());
            check!("supervisor::mission::tasks::Task::legs", task.legs());
        }
        let shape = check!("supervisor::mission::tasks::Shape::of", mi::Shape::of(&tasks));
        check!("supervisor::mission::tasks::Shape::from_legs", mi::Shape::from_legs(&[(mi::TaskKind::Treatment, index)]));
        check!("supervisor::mission::tasks::Shape::len", shape.len());
        check!("supervisor::mission::tasks::Shape::is_empty", shape.is_empty());
        check!("supervisor::mission::tasks::Shape::task", shape.task(index));
        let mut localiser = check!("supervisor::mission::localisation::Localiser::new", mi::Localiser::new(lengths.2));
        let mut mission = check!("supervisor::mission::supervisor::Mission::new", mi::Mission::new(config, &tasks)).unwrap();
        let mut state = check!("supervisor::mission::machine::MissionState::initial", mi::MissionState::initial(&shape));
        for (gnss, odometry, hazard, in_field, remaining) in gnss_poses {
            let fix = check!("supervisor::mission::localisation::Localiser::update", localiser.update(gnss, &odometry));
            check!("supervisor::mission::localisation::Fix::pose", fix.pose());
            check!("supervisor::mission::localisation::Fix::status", fix.status());
            let out = check!("supervisor::mission::supervisor::Mission::tick", mission.tick(&mi::MissionInput { gnss, odometry, hazard, in_field, remaining }));
            prop_assert!(out.speed.get() >= 0.0);
            check!("supervisor::mission::Command::tool_on", out.command.tool_on());
            if let Some(plan) = out.plan {
                check!("supervisor::mission::supervisor::Plan::goal", plan.goal());
                check!("supervisor::mission::supervisor::Plan::length", plan.length());
                prop_assert!(check!("supervisor::mission::supervisor::Plan::is_forward", plan.is_forward()));
                check!("supervisor::mission::supervisor::Plan::to_reference_path", plan.to_reference_path::<64>(lengths.1));
            }
            let events = mi::Events { in_field, localisation: fix.status(), ..mi::Events::NOMINAL };
            let (next, _) = check!("supervisor::mission::machine::step", mi::step(&machine, &shape, &state, &events));
            state = next;
        }
        let s = check!("supervisor::mission::supervisor::Mission::state", mission.state());
        check!("supervisor::mission::machine::MissionState::phase", s.phase());
        check!("supervisor::mission::machine::MissionState::leg", s.leg());
        check!("supervisor::mission::machine::MissionState::detour", s.detour());
        check!("supervisor::mission::machine::MissionState::leg_ticks", s.leg_ticks());
        check!("supervisor::mission::machine::MissionState::stall_ticks", s.stall_ticks());
    }
}

// ---------------------------------------------------------------- switching and plan

fn seconds() -> BoxedStrategy<Seconds> {
    prop_oneof![3 => 0.005..2.0_f64, 1 => fin()]
        .prop_map(|v| Seconds::new(v).unwrap())
        .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn switching_machine(
        delay in seconds(), period in seconds(), enter in seconds(), exit in seconds(),
        stop in seconds(), plan in prop::option::of(seconds()),
        thresholds in (raw(), raw()), ticks in prop::collection::vec((verdict(), verdict(), any::<bool>(), any::<bool>()), 1..60),
        index in 0..4_usize,
    ) {
        check!("supervisor::switching::config::delay_ticks", delay_ticks(delay, period, "SW-DELAYS"));
        let q = QualityThresholds::new(thresholds.0, thresholds.1, Better::Higher)
            .unwrap_or(QualityThresholds::new(0.4, 0.2, Better::Higher).unwrap());
        check!("perception::QualityThresholds::classify", q.classify(thresholds.0));
        check!("supervisor::switching::config::BehaviourConfig::new", BehaviourConfig::new(enter, exit));
        let edge = check!("supervisor::switching::config::BehaviourConfig::edge_following", BehaviourConfig::edge_following()).unwrap();
        let furrow = check!("supervisor::switching::config::BehaviourConfig::furrow_pursuing", BehaviourConfig::furrow_pursuing()).unwrap();
        let mine = BehaviourConfig::new(enter, exit).unwrap_or(edge);
        check!("supervisor::switching::config::BehaviourConfig::enter_delay", mine.enter_delay());
        check!("supervisor::switching::config::BehaviourConfig::exit_delay", mine.exit_delay());
        check!("supervisor::switching::config::SwitchingConfig::new", SwitchingConfig::new(period, [mine, furrow], stop, plan));
        let config = SwitchingConfig::new(period, [mine, furrow], stop, plan).unwrap_or(
            SwitchingConfig::new(Seconds::new(0.01).unwrap(), [edge, furrow], Seconds::new(0.5).unwrap(), plan.map(|_| Seconds::new(1.0).unwrap())).unwrap(),
        );
        #[cfg(feature = "fault-injection")]
        {
            let faulty = check!(
                "supervisor::switching::config::SwitchingConfig::with_fault",
                config.with_fault(fieldguide::supervisor::switching::Fault::NeverStop)
            );
            check!("supervisor::switching::config::SwitchingConfig::fault", faulty.fault());
        }
        check!("supervisor::switching::config::SwitchingConfig::period", config.period());
        check!("supervisor::switching::config::SwitchingConfig::behaviour", config.behaviour(index));
        check!("supervisor::switching::config::SwitchingConfig::ticks", config.ticks(index));
        check!("supervisor::switching::config::SwitchingConfig::all_ticks", config.all_ticks());
        check!("supervisor::switching::config::SwitchingConfig::stop_delay", config.stop_delay());
        check!("supervisor::switching::config::SwitchingConfig::stop_ticks", config.stop_ticks());
        check!("supervisor::switching::config::SwitchingConfig::plan_delay", config.plan_delay());
        check!("supervisor::switching::config::SwitchingConfig::plan_ticks", config.plan_ticks());
        check!("supervisor::switching::config::SwitchingConfig::min_dwell_ticks", config.min_dwell_ticks());
        let mut machine = check!("supervisor::switching::machine::Switching::new", Switching::new(config));
        let mut state = check!("supervisor::switching::machine::SwitchingState::initial", SwitchingState::<2>::initial());
        for (a, b, consistent, localised) in ticks {
            let input = Input {
                behaviours: [Report { verdict: a, plan_consistent: consistent }, check!("supervisor::switching::Report::consistent", Report::consistent(b))],
                localisation_valid: localised,
            };
            let out = check!("supervisor::switching::machine::Switching::step", machine.step(&input));
            let (next, same) = check!("supervisor::switching::machine::step", machine_step(&config, &state, &input));
            prop_assert_eq!(out, same);
            state = next;
            prop_assert_eq!(machine.state(), &state);
        }
        check!("supervisor::switching::machine::Switching::mode", machine.mode());
        check!("supervisor::switching::machine::Switching::config", machine.config());
        let s = check!("supervisor::switching::machine::Switching::state", machine.state());
        check!("supervisor::switching::machine::SwitchingState::mode", s.mode());
        check!("supervisor::switching::machine::SwitchingState::entry_run", s.entry_run(index));
        check!("supervisor::switching::machine::SwitchingState::exit_run", s.exit_run());
        check!("supervisor::switching::machine::SwitchingState::plan_run", s.plan_run());
        check!("supervisor::switching::machine::SwitchingState::sourceless_run", s.sourceless_run());
    }

    #[test]
    fn plan_consistency(
        points in waypoints(), s in meters(), d in meters(), line in tracking(), at_path in tracking(),
        max_offset in meters(), max_heading in radians(), lookahead in meters(),
    ) {
        let path = path_of(&points);
        let ahead = check!("supervisor::switching::plan::PathAhead::on_path", PathAhead::on_path(&path, s, d));
        let ahead = ahead.unwrap_or(PathAhead::HERE);
        check!("supervisor::switching::plan::PathAhead::distance", ahead.distance());
        check!("supervisor::switching::plan::line_relative_to_path", line_relative_to_path(&line, &at_path));
        check!("supervisor::switching::plan::line_relative_to_path_ahead", line_relative_to_path_ahead(&line, &at_path, &ahead));
        check!("supervisor::switching::plan::PlanTolerance::new", PlanTolerance::new(max_offset, max_heading));
        let tolerance = PlanTolerance::new(max_offset, max_heading)
            .unwrap_or(PlanTolerance::new(m(0.3), rad(0.3)).unwrap());
        check!("supervisor::switching::plan::PlanTolerance::with_lookahead", tolerance.with_lookahead(lookahead));
        let tolerance = tolerance.with_lookahead(lookahead).unwrap_or(tolerance);
        check!("supervisor::switching::plan::PlanTolerance::with_entry_heading", tolerance.with_entry_heading(max_heading));
        let tolerance = tolerance.with_entry_heading(max_heading).unwrap_or(tolerance);
        check!("supervisor::switching::plan::PlanTolerance::entry_heading", tolerance.entry_heading());
        check!("supervisor::switching::plan::PlanTolerance::max_offset", tolerance.max_offset());
        check!("supervisor::switching::plan::PlanTolerance::max_heading", tolerance.max_heading());
        check!("supervisor::switching::plan::PlanTolerance::lookahead", tolerance.lookahead());
        check!("supervisor::switching::plan::PlanTolerance::is_consistent", tolerance.is_consistent(&line, &at_path, &ahead));
    }
}

// ---------------------------------------------------------------- presets and the pipeline

/// Path tracking and both behaviours as the presets give them, with some
/// values replaced by anything finite.
fn guidance_params(
    side: Side,
    mount: Transform2<Sensor, Robot>,
    change: usize,
    v: f64,
) -> GuidanceParams<AnyDetectorConfig, BacksteppingConfig, 2> {
    let mut p = presets::pierre2022_both(side, mount).unwrap();
    let seconds = Seconds::new(v).unwrap();
    match change {
        0 => p.period = seconds,
        1 => p.path.speed = MetersPerSecond::new(v).unwrap(),
        2 => p.path.horizon = seconds,
        3 => p.path.search_window = m(v),
        4 => p.stop_delay = seconds,
        5 => p.max_scan_age = seconds,
        6 => p.behaviours[0].speed = MetersPerSecond::new(v).unwrap(),
        7 => p.behaviours[1].enter_delay = seconds,
        8 => {
            p.plan_delay = Some(seconds);
            p.behaviours[0].plan = PlanTolerance::new(m(0.3), rad(0.3)).ok();
        }
        9 => {
            p.fix = Some(FixRuleParams {
                worst_kind: FixKind::RtkFloat,
                max_accuracy: m(v),
                path_dead_reckoning: m(v),
                rejoin_slope: v,
                rejoin_curvature: v,
                float_averaging: Some(m(v)),
            });
        }
        10 => {
            p.plan_dead_reckoning = Some(m(3.0));
            p.fix = Some(FixRuleParams {
                worst_kind: FixKind::RtkFixed,
                max_accuracy: m(0.05),
                path_dead_reckoning: m(2.0),
                rejoin_slope: 0.1,
                rejoin_curvature: 0.05,
                float_averaging: Some(m(0.5)),
            });
        }
        11 => {
            p.odometry_aid = Some(OdometryAidParams {
                time_constant: seconds,
                max_rate: RadiansPerSecond::new(v).unwrap(),
            });
        }
        _ => {}
    }
    p
}

type Pipeline<'p> = Guidance<'p, 64, AnyDetector<512, 64, 512, 32>, BacksteppingConfig, 2>;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn presets_and_the_guidance_pipeline(
        s in side(),
        mount in prop_oneof![3 => Just((0.0, 0.0, 0.0)), 1 => (near(2.0), near(1.0), near(4.0))],
        change in 0..13_usize, v in prop_oneof![2 => 0.01..2.0_f64, 1 => fin()],
        points in waypoints(), other in waypoints(),
        ticks in prop::collection::vec((
            gnss(), pose::<Odom>(), (slip(), slip()),
            any::<bool>(), any::<bool>(), 0..8_u16, parts_or_wall(),
        ), 1..12),
    ) {
        let mount = Transform2::<Sensor, Robot>::new(mount.0, mount.1, mount.2).unwrap();
        check!("presets::vehicle", presets::vehicle());
        check!("presets::path_tracking", presets::path_tracking());
        check!("presets::edge_following", presets::edge_following(s, mount));
        check!("presets::furrow_pursuing", presets::furrow_pursuing());
        check!("presets::pierre2022_path", presets::pierre2022_path());
        check!("presets::pierre2022_edge", presets::pierre2022_edge(s, mount));
        check!("presets::pierre2022_furrow", presets::pierre2022_furrow());
        check!("presets::pierre2022_both", presets::pierre2022_both(s, mount));
        let params = guidance_params(s, mount, change, v);
        let config = check!("guidance::config::GuidanceConfig::new", GuidanceConfig::new(&params));
        let config = config.unwrap_or(
            GuidanceConfig::new(&presets::pierre2022_both(s, mount).unwrap()).unwrap(),
        );
        check!("guidance::config::GuidanceConfig::params", config.params());
        check!("guidance::config::GuidanceConfig::behaviours", config.behaviours());
        check!("guidance::config::GuidanceConfig::switching", config.switching());
        check!("guidance::config::GuidanceConfig::lookahead", config.lookahead());
        check!("guidance::config::GuidanceConfig::max_scan_age_ticks", config.max_scan_age_ticks());
        check!("guidance::config::GuidanceConfig::settle_ticks", config.settle_ticks());
        check!("guidance::config::GuidanceConfig::handover", config.handover());
        check!("guidance::config::GuidanceConfig::entry", config.entry());
        check!("guidance::config::GuidanceConfig::fix", config.fix());
        check!("guidance::config::GuidanceConfig::odometry_aid", config.odometry_aid());
        let (path, replacement) = (path_of(&points), path_of(&other));
        let mut guidance: Pipeline<'_> = check!("guidance::Guidance::new", Guidance::new(config, &path)).unwrap();
        check!("guidance::Guidance::config", guidance.config());
        check!("guidance::Guidance::path", guidance.path());
        for (i, (gnss, odometry, (front, rear), edge_scan, furrow_scan, stranger, (wall, parts))) in ticks.into_iter().enumerate() {
            if i == 3 {
                check!("guidance::Guidance::set_path", guidance.set_path(&replacement));
            }
            if i == 2 {
                // Any finite speed: refused (GD-SPEED, PT-SCHEDULE-RANGE) or taken.
                let speed = MetersPerSecond::new(v).unwrap_or(MetersPerSecond::ZERO);
                check!("guidance::Guidance::set_path_speed", guidance.set_path_speed(speed));
            }
            let (start, increment, ranges) = parts;
            let ranges = if wall { wall_ranges(1.5, 360, &[]) } else { ranges };
            let scan = Scan { start, increment, ranges: &ranges, limits: RangeLimits::new(m(0.05), m(30.0)).unwrap() };
            let mut scans = Vec::new();
            if edge_scan {
                scans.push(RoutedScan { behaviour: presets::EDGE, scan });
            }
            if furrow_scan {
                scans.push(RoutedScan { behaviour: presets::FURROW, scan });
            }
            if stranger == 0 {
                scans.push(RoutedScan { behaviour: BehaviourId(7), scan });
            }
            // On the path (a few decimetres off, nearly along it), or anywhere.
            let on_path = if i >= 3 { &replacement } else { &path };
            let gnss = match gnss {
                Gnss::None => None,
                Gnss::Anywhere(p) => Some(p),
                Gnss::Near { s, left, turn } => {
                    let q = on_path.point_at(m(s * on_path.length().get())).unwrap();
                    let h = on_path.heading_at(m(s * on_path.length().get())).get();
                    Pose2::new(q.x() - left * h.sin(), q.y() + left * h.cos(), h + turn).ok()
                }
            };
            let input = TickInput {
                scans: &scans,
                gnss,
                odometry,
                extra: Sideslip { front, rear },
            };
            let out = if stranger % 2 == 0 {
                check!("guidance::Guidance::step", guidance.step(&input))
            } else {
                // Any kind, an accuracy of any finite size or none.
                let kind = [FixKind::RtkFixed, FixKind::RtkFloat, FixKind::Single, FixKind::DeadReckoned][usize::from(stranger) % 4];
                let accuracy = (stranger < 7).then(|| m(v));
                check!("guidance::Guidance::step_with_fix", guidance.step_with_fix(&input, &FixQuality { kind, accuracy }))
            };
            if let Ok(out) = out {
                check!("guidance::LawOutcome::command", out.path.law.command());
                for id in [presets::EDGE, presets::FURROW, BehaviourId(7)] {
                    check!("guidance::TickOutput::behaviour", out.behaviour(id));
                }
            }
        }
        check!("guidance::Guidance::switching", guidance.switching());
        let mode = check!("guidance::Guidance::mode", guidance.mode());
        for mode in [mode, GuidanceMode::PathTracking, GuidanceMode::Stop, GuidanceMode::Behaviour(BehaviourId(7))] {
            check!("guidance::Guidance::label", guidance.label(mode));
        }
        for id in [presets::EDGE, presets::FURROW, BehaviourId(7)] {
            check!("guidance::Guidance::detector", guidance.detector(id));
            check!("guidance::Guidance::held", guidance.held(id));
        }
    }
}

/// Where the GNSS puts the robot in a tick.
#[derive(Debug, Clone, Copy)]
enum Gnss {
    /// No fix.
    None,
    /// At a fraction `s` of the path, `left` m to its left, `turn` rad from its heading.
    Near { s: f64, left: f64, turn: f64 },
    /// Anywhere.
    Anywhere(Pose2<World>),
}

fn gnss() -> BoxedStrategy<Gnss> {
    prop_oneof![
        1 => Just(Gnss::None),
        4 => (0.0..1.0_f64, -0.5..0.5_f64, -0.3..0.3_f64)
            .prop_map(|(s, left, turn)| Gnss::Near { s, left, turn }),
        1 => pose::<World>().prop_map(Gnss::Anywhere),
    ]
    .boxed()
}

/// A sideslip angle: a plausible one, or any finite angle (|β| ≥ π/2 is refused).
fn slip() -> BoxedStrategy<Radians> {
    prop_oneof![4 => (-0.1..0.1_f64).prop_map(rad), 1 => radians()].boxed()
}

/// Whether a scan is a wall on the left, and the parts of a scan otherwise.
fn parts_or_wall() -> BoxedStrategy<(bool, ScanParts)> {
    (any::<bool>(), scan_parts(360)).boxed()
}

// ---------------------------------------------------------------- Emmi 2024: tracked robot, planners, controllers

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn skid_steer_and_its_controllers(
        track in raw(), limit in raw(), v in fin(), w in fin(), at in pose::<World>(),
        gains in prop::array::uniform5(raw()), cp in meters(), e in tracking(),
        rate in fin(), speed in prop_oneof![3 => 0.0..2.0_f64, 1 => fin()],
        ticks in (meters(), meters(), fin()), lambda in raw(), alpha_d in radians(),
        centre in point::<World>(), radius in meters(),
    ) {
        let t = Meters::new(track).unwrap_or(Meters::ZERO);
        let l = MetersPerSecond::new(limit).unwrap_or(MetersPerSecond::ZERO);
        check!("model::skid_steer::SkidSteer::new", SkidSteer::new(t, l));
        let k = SkidSteer::new(t, l).unwrap_or(
            SkidSteer::new(m(1.48), MetersPerSecond::new(1.67).unwrap()).unwrap(),
        );
        let (vv, ww) = (MetersPerSecond::new(v).unwrap(), RadiansPerSecond::new(w).unwrap());
        check!("model::skid_steer::SkidSteer::track", k.track());
        check!("model::skid_steer::SkidSteer::max_track_speed", k.max_track_speed());
        check!("model::skid_steer::SkidSteer::track_speeds", k.track_speeds(vv, ww));
        let sat = check!("model::skid_steer::SkidSteer::saturate", k.saturate(v, w));
        if let Ok(s) = sat {
            prop_assert!(Vehicle::SkidSteer(k).check(&s.command).is_ok());
        }
        check!("model::skid_steer::SkidSteer::saturate", k.saturate(f64::NAN, w));
        check!("model::skid_steer::SkidSteer::check_turn_radius", k.check_turn_radius(radius));
        check!("model::skid_steer::unicycle_rates", unicycle_rates(&at, vv, ww));
        check!("model::Vehicle::check", Vehicle::SkidSteer(k).check(&Command::SkidSteer { speed: vv, yaw_rate: ww }));

        let [g0, g1, g2, g3, g4] = gains;
        let lg = check!("control::lateral_pd::LateralGains::new", LateralGains::new(g0, g1, g2, g3, g4));
        names_a_requirement("LateralGains::new", &lg);
        let law = LateralPd {
            gains: lg.unwrap_or(LateralGains::new(1.0, 1.0, 0.1, 1.0, 0.5).unwrap()),
            control_point: cp,
            vehicle: k,
        };
        let r = LateralRate(MetersPerSecond::new(rate).unwrap());
        let sp = MetersPerSecond::new(speed).unwrap();
        check!("control::lateral_pd::LateralPd::control_point_error", law.control_point_error(&e));
        check!("control::lateral_pd::LateralPd::raw_command", law.raw_command(&e, r, sp));
        let c = check!("control::ControlLaw::command", law.command(&e, &r, sp));
        if let Ok(c) = c {
            prop_assert!(Vehicle::SkidSteer(k).check(&c.command).is_ok());
        }
        check!("control::ControlLaw::check_extra", LateralPd::check_extra(&r));
        check!("control::ControlLaw::actuation", law.actuation());
        check!("control::ControlLaw::check_speed", law.check_speed(sp));
        let (a, b, period) = ticks;
        let between = check!(
            "control::lateral_pd::LateralRate::between_ticks",
            LateralRate::between_ticks(a, b, Seconds::new(period).unwrap())
        );
        names_a_requirement("between_ticks", &between);

        let sv = check!("control::spiral::Spiral::new", Spiral::new(lambda, alpha_d, k));
        names_a_requirement("Spiral::new", &sv);
        let spiral = sv.unwrap_or(Spiral::new(1.0, rad(FRAC_PI_2), k).unwrap());
        check!("control::spiral::Spiral::lambda", spiral.lambda());
        check!("control::spiral::Spiral::desired_angle", spiral.desired_angle());
        let spiral = check!("control::spiral::Spiral::towards", spiral.towards(alpha_d));
        check!("control::spiral::spiral_state", spiral_state(&at, centre));
        let yaw = check!("control::spiral::Spiral::raw_yaw_rate", spiral.raw_yaw_rate(&at, centre, sp));
        names_a_requirement("raw_yaw_rate", &yaw);
        let c = check!("control::spiral::spiral_command", spiral_command(&spiral, &at, centre, sp));
        if let Ok(c) = c {
            prop_assert!(Vehicle::SkidSteer(k).check(&c.command).is_ok());
        }
    }

    #[test]
    fn speed_profiles(
        v_th in fin(), v_d in fin(), ramp in meters(), d_b in fin(), fixed in any::<bool>(),
        reach in meters(), travelled in meters(), remaining in meters(), braking_from in fin(),
    ) {
        let braking = if fixed {
            Braking::Fixed(m(d_b))
        } else {
            Braking::Proportional(Seconds::new(d_b).unwrap())
        };
        let (t, d) = (MetersPerSecond::new(v_th).unwrap(), MetersPerSecond::new(v_d).unwrap());
        let made = check!("control::speed_profile::SpeedProfile::new", SpeedProfile::new(t, d, ramp, braking, reach));
        names_a_requirement("SpeedProfile::new", &made);
        let p = made.unwrap_or(
            SpeedProfile::new(
                MetersPerSecond::new(0.1).unwrap(), MetersPerSecond::new(0.5).unwrap(),
                m(1.0), Braking::Fixed(m(1.0)), m(0.05),
            ).unwrap(),
        );
        check!("control::speed_profile::SpeedProfile::ramp_speed", p.ramp_speed(travelled));
        check!("control::speed_profile::SpeedProfile::braking_distance", p.braking_distance(d));
        let states = [
            SpeedState::Moving,
            SpeedState::Reached,
            SpeedState::Braking { from: MetersPerSecond::new(braking_from).unwrap(), over: ramp },
        ];
        for s in states {
            check!("control::speed_profile::SpeedProfile::step", p.step(s, travelled, remaining));
        }
    }

    #[test]
    fn planners(
        a in pose::<World>(), b in pose::<World>(), r in meters(), spacing in meters(),
        word in prop::sample::select(Word::ALL.to_vec()), s in meters(), ahead in meters(),
        threshold in radians(), track in meters(),
    ) {
        let made = check!("planning::dubins::TurningRadius::new", TurningRadius::new(r));
        names_a_requirement("TurningRadius::new", &made);
        let k = SkidSteer::new(track, MetersPerSecond::new(1.0).unwrap())
            .unwrap_or(SkidSteer::new(m(1.0), MetersPerSecond::new(1.0).unwrap()).unwrap());
        check!("planning::dubins::TurningRadius::for_vehicle", TurningRadius::for_vehicle(r, &k));
        let radius = made.unwrap_or(TurningRadius::new(m(1.0)).unwrap());
        check!("planning::dubins::TurningRadius::get", radius.get());
        check!("planning::dubins::Word::turns", word.turns());
        check!("planning::dubins::Word::mirrored", word.mirrored());
        check!("planning::dubins::Word::reversed", word.reversed());
        let one = check!("planning::dubins::path_with_word", path_with_word(&a, &b, radius, word));
        names_a_requirement("path_with_word", &one);
        let best = check!("planning::dubins::shortest", shortest(&a, &b, radius));
        names_a_requirement("shortest", &best);
        for p in [one, best].into_iter().flatten() {
            check!("planning::dubins::DubinsPath::word", p.word());
            check!("planning::dubins::DubinsPath::start", p.start());
            check!("planning::dubins::DubinsPath::radius", p.radius());
            check!("planning::dubins::DubinsPath::length", p.length());
            check!("planning::dubins::DubinsPath::segments", p.segments());
            check!("planning::dubins::DubinsPath::pose_at", p.pose_at(s));
            check!("planning::dubins::DubinsPath::end", p.end());
            let path = check!("planning::dubins::DubinsPath::to_reference_path", p.to_reference_path::<64>(spacing));
            names_a_requirement("to_reference_path", &path);
            for g in p.segments() {
                check!("planning::manager::tracker_for", tracker_for(&g));
            }
        }
        let exact = check!(
            "geometry::path::ReferencePath::from_exact",
            ReferencePath::<8>::from_exact([(a, Curvature::ZERO), (b, Curvature::new(0.5).unwrap())])
        );
        names_a_requirement("from_exact", &exact);
        if let Ok(path) = exact {
            check!("geometry::path::ReferencePath::project", path.project(&a, s));
        }
        check!("planning::line_following::goal_ahead", goal_ahead(&a, ahead));
        let line = check!("planning::line_following::line_ahead", line_ahead::<4>(&a, ahead));
        names_a_requirement("line_ahead", &line);
        let t = check!("planning::manager::PlannerThreshold::new", PlannerThreshold::new(threshold));
        names_a_requirement("PlannerThreshold::new", &t);
        let t = t.unwrap_or(PlannerThreshold::DEFAULT);
        check!("planning::manager::PlannerThreshold::get", t.get());
        check!("planning::manager::direction_change", direction_change(&a, &b));
        check!("planning::manager::choose_planner", choose_planner(&a, &b, t));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn obstacles(
        parts in scan_parts(360), limits in limits(), mount in (near(2.0), near(2.0), near(4.0)),
        lengths in prop::collection::vec(meters(), 8), gains in (fin(), fin()), n in 0_usize..6,
        shapes in prop::collection::vec((point::<Robot>(), point::<Robot>(), meters(), any::<bool>()), 0..6),
        a in pose::<World>(), b in pose::<World>(), v in raw(), in_field in any::<bool>(),
    ) {
        let (start, increment, ranges) = parts;
        let scan = Scan { start, increment, ranges: &ranges, limits };
        let mount = Transform2::<Sensor, Robot>::new(mount.0, mount.1, mount.2).unwrap();
        let made = check!("perception::obstacles::cluster::ClusterConfig::new", ClusterConfig::new(lengths[0], n, lengths[1], lengths[2]));
        names_a_requirement("ClusterConfig::new", &made);
        let cc = made.unwrap_or(check!("perception::obstacles::cluster::ClusterConfig::emmi2024", ClusterConfig::emmi2024()));
        let mut found = check!("perception::obstacles::cluster::cluster", cluster::<4>(&scan, &mount, &cc));
        check!("perception::obstacles::cluster::Obstacles::as_slice", found.as_slice());
        check!("perception::obstacles::cluster::Obstacles::nearest_dropped", found.nearest_dropped());
        check!("perception::obstacles::cluster::Obstacles::spurious", found.spurious());
        let mut list = check!("perception::obstacles::cluster::Obstacles::new", Obstacles::<4>::new());
        for (p, q, r, round) in shapes {
            let o = if round { Obstacle::Circle { centre: p, radius: r } } else { Obstacle::Segment { start: p, end: q } };
            check!("perception::obstacles::cluster::Obstacles::insert", list.insert(o));
            check!("perception::obstacles::cluster::Obstacles::insert", found.insert(o));
        }
        let fp = check!("perception::obstacles::areas::Footprint::new", Footprint::new(lengths[3], lengths[4], lengths[5]));
        names_a_requirement("Footprint::new", &fp);
        let seconds = |g: f64| Seconds::new(g).unwrap();
        let critical = check!("perception::obstacles::areas::AreaLength::new", AreaLength::new(lengths[6], seconds(gains.0)));
        names_a_requirement("AreaLength::new", &critical);
        let warning = AreaLength::new(lengths[7], seconds(gains.1));
        let radius = TurningRadius::new(lengths[2]).unwrap_or(TurningRadius::new(m(1.0)).unwrap());
        let fallback = check!("perception::obstacles::areas::ObstacleConfig::emmi2024", ObstacleConfig::emmi2024(radius));
        let config = match (fp, critical, warning) {
            (Ok(fp), Ok(c), Ok(w)) => {
                let made = check!("perception::obstacles::areas::ObstacleConfig::new", ObstacleConfig::new(fp, lengths[0], c, w, radius, lengths[1]));
                names_a_requirement("ObstacleConfig::new", &made);
                made.unwrap_or(fallback)
            }
            _ => fallback,
        };
        check!("perception::obstacles::areas::ObstacleConfig::footprint", config.footprint());
        check!("perception::obstacles::areas::ObstacleConfig::margin", config.margin());
        check!("perception::obstacles::areas::ObstacleConfig::radius", config.radius());
        let f = config.footprint();
        check!("perception::obstacles::areas::Footprint::front", f.front());
        check!("perception::obstacles::areas::Footprint::rear", f.rear());
        check!("perception::obstacles::areas::Footprint::width", f.width());
        let speed = MetersPerSecond::new(v).unwrap_or(MetersPerSecond::new(0.5).unwrap());
        let areas = check!("perception::obstacles::areas::ObstacleConfig::areas", config.areas(speed));
        names_a_requirement("areas", &areas);
        if let Ok(areas) = areas {
            check!("perception::obstacles::areas::SafetyAreas::critical_end", areas.critical_end());
            check!("perception::obstacles::areas::SafetyAreas::warning_end", areas.warning_end());
            for o in list.as_slice() {
                check!("perception::obstacles::areas::SafetyAreas::in_critical", areas.in_critical(o));
                check!("perception::obstacles::areas::SafetyAreas::in_warning", areas.in_warning(o));
            }
        }
        for o in list.as_slice() {
            let plan = check!("perception::obstacles::detour::detour", detour(o, list.as_slice(), &a, &b, lengths[3], &config));
            names_a_requirement("detour", &plan);
        }
        let corridor = check!("perception::obstacles::corridor::Corridor::new", Corridor::new(&[a.position, b.position], lengths[2]));
        names_a_requirement("Corridor::new", &corridor);
        if let Ok(corridor) = &corridor {
            check!("perception::obstacles::corridor::Corridor::half_width", corridor.half_width());
            for o in list.as_slice() {
                let plan = check!("perception::obstacles::detour::detour_within", detour_within(o, list.as_slice(), &a, &b, lengths[3], Some(corridor), &config));
                names_a_requirement("detour_within", &plan);
            }
            for l in [&list, &found] {
                let verdict = check!("perception::obstacles::assess_within", assess_within(l, &a, &b, speed, in_field, Some(corridor), &config));
                names_a_requirement("assess_within", &verdict);
            }
        }
        for l in [&list, &found] {
            let verdict = check!("perception::obstacles::assess", assess(l, &a, &b, speed, in_field, &config));
            names_a_requirement("assess", &verdict);
            if let Ok(verdict) = verdict {
                check!("perception::obstacles::Assessment::stops", verdict.stops());
            }
        }
    }
}

// ---------------------------------------------------------------- coverage

/// One public function of the core, as `module::Type::name`,
/// `module::Trait::name` or `module::name` (the module from the file's path
/// under `src/`; `$name` for the unit types' shared methods).
fn public_functions(src: &Path) -> BTreeSet<String> {
    let mut keys = BTreeSet::new();
    let mut files = Vec::new();
    collect_rust_files(src, &mut files);
    for file in files {
        let relative = file.strip_prefix(src).unwrap().with_extension("");
        let mut parts: Vec<String> = relative
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
            parts.pop();
        }
        let module = parts.join("::");
        let text = std::fs::read_to_string(&file).unwrap();
        scan_file(&module, &text, &mut keys);
    }
    keys
}

fn collect_rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect_rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// A line without its comment and the contents of its string and char
/// literals (`in_string` carries an open string over lines).
fn code_of(line: &str, in_string: &mut bool) -> String {
    let chars: Vec<char> = line.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if *in_string {
            if c == '\\' {
                i += 2;
                continue;
            }
            if c == '"' {
                *in_string = false;
            }
            i += 1;
            continue;
        }
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            break;
        }
        if c == '"' {
            *in_string = true;
        } else if c == '\'' && chars.get(i + 2) == Some(&'\'') {
            i += 3;
            continue;
        } else {
            out.push(c);
        }
        i += 1;
    }
    out
}

/// The identifier at the start of `s`.
fn identifier(s: &str) -> String {
    s.chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == '$')
        .collect()
}

/// The type an `impl` header is for: the last path segment after `for`, or
/// after `impl`, generics removed.
fn impl_type(header: &str) -> String {
    let mut h = header.split('{').next().unwrap_or("").to_string();
    // Remove generic arguments, innermost first.
    while let Some(close) = h.find('>') {
        let Some(open) = h[..close].rfind('<') else {
            break;
        };
        h.replace_range(open..=close, "");
    }
    let h = h.split(" where").next().unwrap_or("");
    let after_impl = h.trim_start().trim_start_matches("impl").trim_start();
    let target = after_impl.split(" for ").last().unwrap_or(after_impl);
    let path = target.split_whitespace().next().unwrap_or("");
    identifier(path.rsplit("::").next().unwrap_or(path))
}

#[derive(Debug, PartialEq)]
enum Block {
    /// An `impl` of the named type.
    Impl(String),
    /// A public trait's declaration.
    Trait(String),
    /// A `#[cfg(test)]` or `#[cfg(doctest)]` module.
    Skipped,
}

/// Adds the public functions of one file (rustfmt's layout: one item
/// header per line, braces counted outside comments and literals).
fn scan_file(module: &str, text: &str, keys: &mut BTreeSet<String>) {
    let mut in_string = false;
    let mut depth = 0_usize;
    let mut blocks: Vec<(usize, Block)> = Vec::new();
    let mut header: Option<String> = None;
    let mut test_only = false;
    for raw in text.lines() {
        let code = code_of(raw, &mut in_string);
        let line = code.trim();
        if line.starts_with("#[cfg(test)]") || line.starts_with("#[cfg(doctest)]") {
            test_only = true;
            continue;
        }
        let skipped = blocks.iter().any(|(_, b)| *b == Block::Skipped);
        if let Some(h) = header.as_mut() {
            h.push(' ');
            h.push_str(line);
        } else if (line.starts_with("impl") && !line.starts_with("impl_"))
            || line.starts_with("pub trait ")
            || (test_only && line.contains("mod "))
        {
            header = Some(line.to_string());
        }
        if !skipped && header.is_none() {
            let owner = blocks.iter().rev().find_map(|(_, b)| match b {
                Block::Impl(t) => Some((t.clone(), false)),
                Block::Trait(t) => Some((t.clone(), true)),
                Block::Skipped => None,
            });
            let public = line
                .strip_prefix("pub fn ")
                .or_else(|| line.strip_prefix("pub const fn "));
            let name = match (&owner, public) {
                (_, Some(rest)) => Some(identifier(rest)),
                (Some((_, true)), None) => line.strip_prefix("fn ").map(identifier),
                _ => None,
            };
            if let Some(name) = name {
                let key = match owner {
                    Some((t, _)) => format!("{module}::{t}::{name}"),
                    None => format!("{module}::{name}"),
                };
                keys.insert(key);
            }
        }
        let opens = code.matches('{').count();
        let closes = code.matches('}').count();
        if let Some(h) = header.take() {
            if opens > 0 {
                let block = if test_only && h.contains("mod ") {
                    Block::Skipped
                } else if let Some(rest) = h.strip_prefix("pub trait ") {
                    Block::Trait(identifier(rest))
                } else {
                    Block::Impl(impl_type(&h))
                };
                blocks.push((depth + 1, block));
                test_only = false;
            } else if h.ends_with(';') {
                test_only = false;
            } else {
                header = Some(h);
            }
        } else if test_only
            && !line.is_empty()
            && !line.starts_with("#[")
            && !line.starts_with("///")
        {
            // The attribute belonged to an item without a body (`mod x;`, a struct).
            if line.ends_with(';') || opens == closes {
                test_only = false;
            }
        }
        depth = (depth + opens).saturating_sub(closes);
        while blocks.last().is_some_and(|(d, _)| *d > depth) {
            blocks.pop();
        }
    }
}

/// The keys of every `check!` in this file.
fn checked_keys(this_file: &str) -> BTreeSet<String> {
    // Spelt in two parts, so that this line is not a call itself.
    let marker = concat!("check", "!(");
    this_file
        .match_indices(marker)
        .filter_map(|(i, _)| {
            let rest = this_file[i + marker.len()..]
                .trim_start()
                .strip_prefix('"')?;
            rest.find('"').map(|end| rest[..end].to_string())
        })
        .collect()
}

//= spec/library.md#lib-finite-no-nan-or-infinity
//= type=test
//# A value returned by the core MUST be finite: a computation whose result
//# would be NaN or infinite MUST return a `Precondition` error instead.
//= spec/library.md#lib-no-panic-no-panic
//= type=test
//# The core MUST NOT panic for any input: a function whose domain is restricted
//# MUST return `Result<_, Precondition>` naming the requirement it protects.
#[test]
fn the_property_tests_call_every_public_function() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let public = public_functions(&root.join("src"));
    let this_file = std::fs::read_to_string(root.join("tests/public_api.rs")).unwrap();
    let checked = checked_keys(&this_file);
    // The scan must see the API (a broken scanner would pass vacuously).
    assert!(
        public.len() > 250,
        "only {} public functions found",
        public.len()
    );
    for known in [
        "geometry::frame::Point2::distance_to",
        "geometry::units::wrap_angle",
        "geometry::units::$name::new",
        "perception::detector::Detector::observe",
        "guidance::Guidance::step",
    ] {
        assert!(public.contains(known), "the scan misses {known}");
    }
    let missing: Vec<&String> = public.difference(&checked).collect();
    let stale: Vec<&String> = checked.difference(&public).collect();
    assert!(
        missing.is_empty(),
        "public functions without a check! in tests/public_api.rs: {missing:#?}"
    );
    assert!(
        stale.is_empty(),
        "check! names that are no public function of src/: {stale:#?}"
    );
}

#[test]
fn the_scan_reads_impls_traits_and_test_modules() {
    let text = r#"
impl<const N: usize> Thing<N> {
    /// A doc comment with pub fn inside { and braces }.
    pub fn visible(&self) -> f64 { 1.0 }
    fn private(&self) {}
    pub(crate) fn crate_only(&self) {}
    pub const fn constant() -> u8 { 0 }
}
impl<const A: usize, const B: usize>
    Detector for Other<A, B>
{
    fn observe(&self) {}
}
impl<'p, D, const K: usize> Guidance<'p, D, K>
where
    D: Detector,
    D::Config: Copy,
{
    pub fn step(&mut self) {}
}
pub trait Seam: Copy {
    fn method(&self) -> Result<(), ()>;
}
pub fn free(s: &str) -> bool { s == "}" }
#[cfg(test)]
mod tests {
    pub fn hidden() {}
}
pub fn after() {}
"#;
    let mut keys = BTreeSet::new();
    scan_file("m", text, &mut keys);
    let expected: BTreeSet<String> = [
        "m::Thing::visible",
        "m::Thing::constant",
        "m::Guidance::step",
        "m::Seam::method",
        "m::free",
        "m::after",
    ]
    .iter()
    .map(ToString::to_string)
    .collect();
    assert_eq!(keys, expected);
}

// ---------------------------------------------------------------- hand-over (GD-HANDOVER)

proptest! {
    #[test]
    fn handover(hold in meters(), slope in raw(), averaging in meters(), line in meters(), start in meters(), travelled in meters(), path in tracking()) {
        let params = HandoverParams { hold, slope, averaging, line_hold: Some(line) };
        check!("guidance::handover::Handover::new", Handover::new(&params));
        let rule = Handover::new(&params)
            .unwrap_or(Handover::new(&HandoverParams { hold: m(4.0), slope: 0.1, averaging: m(1.0), line_hold: None }).unwrap());
        check!("guidance::handover::Handover::averaged", rule.averaged(Some(start), hold, travelled));
        check!("guidance::handover::Handover::averaged", rule.averaged(None, start, travelled));
        check!("guidance::handover::Handover::params", rule.params());
        check!("guidance::handover::Handover::offset", rule.offset(start, travelled));
        check!("guidance::handover::Handover::is_over", rule.is_over(start, travelled));
        check!("guidance::handover::Handover::reference_error", rule.reference_error(&path, start, travelled));
    }
}

// ---------------------------------------------------------------- fix quality (GD-FIX-QUALITY)

proptest! {
    #[test]
    fn odometry_aid(tau in seconds(), rate in fin(), period in seconds(), ticks in prop::collection::vec((pose::<Odom>(), prop::option::of(pose::<World>())), 1..12)) {
        let params = OdometryAidParams { time_constant: tau, max_rate: RadiansPerSecond::new(rate).unwrap() };
        check!("guidance::odometry::OdometryAid::new", OdometryAid::new(&params, period));
        let fallback = OdometryAidParams { time_constant: Seconds::new(1.0).unwrap(), max_rate: RadiansPerSecond::new(0.01).unwrap() };
        let aid = OdometryAid::new(&params, period).unwrap_or(OdometryAid::new(&fallback, Seconds::new(0.01).unwrap()).unwrap());
        check!("guidance::odometry::OdometryAid::params", aid.params());
        check!("guidance::odometry::OdometryAid::gain", aid.gain());
        check!("guidance::odometry::OdometryAid::max_step", aid.max_step());
        let mut aided = check!("guidance::odometry::AidedOdometry::new", AidedOdometry::new());
        for (odometry, fix) in ticks {
            check!("guidance::odometry::AidedOdometry::step", aided.step(&aid, odometry, fix.as_ref()));
            check!("guidance::odometry::AidedOdometry::reference", aided.reference());
        }
    }

    #[test]
    fn fix_rule(max_accuracy in meters(), carry in meters(), slope in raw(), float in meters(), sigma in meters(), start in meters(), travelled in meters(), path in tracking(), p in pose::<World>()) {
        let params = FixRuleParams { worst_kind: FixKind::RtkFloat, max_accuracy, path_dead_reckoning: carry, rejoin_slope: slope, rejoin_curvature: slope, float_averaging: Some(float) };
        check!("guidance::fix::FixRule::new", FixRule::new(&params));
        let rule = FixRule::new(&params).unwrap_or(
            FixRule::new(&FixRuleParams { worst_kind: FixKind::RtkFixed, max_accuracy: m(0.05), path_dead_reckoning: m(10.0), rejoin_slope: 0.1, rejoin_curvature: 0.05, float_averaging: None }).unwrap(),
        );
        check!("guidance::fix::FixRule::params", rule.params());
        for quality in [FixQuality::RTK_FIXED, FixQuality { kind: FixKind::Single, accuracy: Some(sigma) }] {
            check!("guidance::fix::FixRule::accepts", rule.accepts(&quality));
            check!("guidance::fix::FixRule::filter", rule.filter(Some(p), &quality));
        }
        check!("guidance::fix::FixRule::rejoin_offset", rule.rejoin_offset(start, travelled));
        check!("guidance::fix::FixRule::rejoin_error", rule.rejoin_error(&path, start, travelled));
    }
}

// ---------------------------------------------------------------- entry (GD-ENTRY)

proptest! {
    #[test]
    fn entry(closing in meters(), lead in meters(), start in meters(), travelled in meters(), path in tracking(), heading in radians()) {
        let params = EntryParams { closing, lead };
        check!("guidance::entry::Entry::new", Entry::new(&params));
        let rule = Entry::new(&params)
            .unwrap_or(Entry::new(&EntryParams { closing: m(1.0), lead: m(2.0) }).unwrap());
        check!("guidance::entry::Entry::params", rule.params());
        check!("guidance::entry::Entry::reference", rule.reference(start, travelled));
        check!("guidance::entry::Entry::reference_with_heading", rule.reference_with_heading(start, heading.get().tan(), travelled));
        check!("guidance::entry::Entry::is_over", rule.is_over(start, travelled));
        check!("guidance::entry::Entry::reference_error", rule.reference_error(&path, start, travelled, heading));
    }
}

proptest! {
    #[test]
    fn furrow_reach(increment in radians(), half in radians(), height in meters(), pitch in radians(), mount_y in meters()) {
        let params = FurrowParams {
            window_half_angle: half,
            mount_height: height,
            mount_pitch: pitch,
            mount_y,
            ..FurrowParams::table2()
        };
        if let Ok(config) = FurrowConfig::new(&params) {
            check!("perception::furrow::FurrowConfig::lateral_reach", config.lateral_reach(increment));
        }
        let config = FurrowConfig::new(&FurrowParams::table2()).unwrap();
        check!("perception::furrow::FurrowConfig::lateral_reach", config.lateral_reach(increment));
    }
}
