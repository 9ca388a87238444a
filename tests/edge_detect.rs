//! Properties of the whole edge detection (Pierre 2022, section 2.2 and
//! eq. 21; `spec/pierre2022.md`, EDGE-SCAN, EDGE-ERRORS, EDGE-OFFSET,
//! EDGE-QUALITY, EDGE-DETECT): straight walls give exactly their offset and
//! angle, mirroring mirrors, rigid motions change nothing, and bad input gives
//! Absent or a `Precondition` error, never a panic or a NaN.
#![allow(
    clippy::arithmetic_side_effects,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::float_cmp,
    clippy::panic
)]

mod edge_support;

use edge_support::{cast_line, hedge, pt, wall};
use fieldguide::perception::edge::{
    detect, detect_points, ChainEnd, EdgeConfig, EdgeDetection, EdgeDetector, EdgeDetectorConfig,
    EdgeParameters, Side,
};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Odom, Point2, Pose2, Radians, Robot, Sensor, Transform2, Verdict, World};
use proptest::prelude::*;

const N: usize = 1024;
const M: usize = 128;

fn config() -> EdgeConfig {
    EdgeConfig::pierre2022().unwrap()
}

fn side() -> impl Strategy<Value = Side> {
    prop_oneof![Just(Side::Left), Just(Side::Right)]
}

fn limits() -> RangeLimits {
    RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap()
}

/// Every number a detection reports is finite, and a usable error exists
/// exactly when the verdict is Enter or Hold.
fn check_sane(det: &EdgeDetection<M>) {
    match det.fit {
        None => {
            assert_eq!(det.verdict, Verdict::Absent);
            assert!(det.usable_error().is_none());
        }
        Some(fit) => {
            assert_ne!(det.verdict, Verdict::Absent);
            for v in [
                fit.parabola.a,
                fit.parabola.b,
                fit.parabola.c,
                fit.error.y.get(),
                fit.error.angular_deviation.get(),
                fit.quality.length.get(),
                fit.quality.width.get(),
                fit.quality.residual_std.get(),
            ] {
                assert!(v.is_finite());
            }
            assert_eq!(
                det.usable_error().is_some(),
                det.verdict.estimate_is_valid()
            );
        }
    }
}

//= spec/pierre2022.md#edge-offset-desired-lateral-distance
//= type=test
//# The lateral error MUST be y = s·D − (a x_r² + b x_r + c) cos φ with
//# φ = arctan(2 a x_r + b), s = +1 for an edge on the left and −1 on the
//# right, so that y > 0 when the robot is left of the line it follows.
//= spec/pierre2022.md#edge-errors-lateral-and-angular-errors-at-the-robot
//= type=test
//# The angular error MUST be θ̃ = −arctan(2 a x_r + b), the robot's heading
//# minus the heading of the parabola's tangent at x_r.
proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A straight wall at perpendicular distance d and heading φ gives
    /// y = s (D − d) and θ̃ = −φ, with Enter (a perfect fit).
    #[test]
    fn straight_wall_gives_its_offset_and_angle(
        side in side(),
        dist in 0.3..3.5f64,
        angle in -0.45..0.45f64,
        spacing in 0.02..0.3f64,
        from in -3.0..-1.0f64,
    ) {
        // The wall stays on the requested side for 6 m ahead.
        prop_assume!(side.sign() * angle >= 0.0 || dist > 6.0 * angle.abs().sin());
        let config = config();
        let points = wall(side, dist, angle, spacing, from, 8.0);
        let det = detect_points::<M>(&points, side, &config).unwrap();
        check_sane(&det);
        let fit = det.fit.unwrap();
        let expected_y = side.sign() * (config.offset().get() - dist);
        prop_assert!((fit.error.y.get() - expected_y).abs() < 1e-9, "{:?}", fit);
        prop_assert!((fit.error.angular_deviation.get() + angle).abs() < 1e-9);
        prop_assert!(fit.quality.residual_std.get() < 1e-9);
        prop_assert_eq!(fit.error.curvature.get(), 0.0);
    }

    /// Mirroring the points about the robot's x axis and swapping the side
    /// gives the same chain and the mirrored errors.
    #[test]
    fn mirroring_mirrors_the_result(
        side in side(),
        dist in 0.6..2.8f64,
        angle in -0.5..0.5f64,
        xj in prop::collection::vec((-2.0..6.0f64, -0.3..0.3f64), 3..60),
    ) {
        let config = config();
        let (xs, js): (Vec<f64>, Vec<f64>) = xj.into_iter().unzip();
        let points = hedge(side, dist, angle, &xs, &js);
        let mirrored: Vec<Point2<Robot>> = points.iter().map(|p| p.mirrored()).collect();
        let a = detect_points::<M>(&points, side, &config).unwrap();
        let b = detect_points::<M>(&mirrored, side.mirrored(), &config).unwrap();
        check_sane(&a);
        check_sane(&b);
        prop_assert_eq!(a.chain.indices(), b.chain.indices());
        prop_assert_eq!(a.verdict, b.verdict);
        if let (Some(fa), Some(fb)) = (a.fit, b.fit) {
            let m = fa.error.mirrored();
            prop_assert!((m.y.get() - fb.error.y.get()).abs() < 1e-9);
            prop_assert!((m.angular_deviation.get() - fb.error.angular_deviation.get()).abs() < 1e-9);
            prop_assert!((fa.quality.residual_std.get() - fb.quality.residual_std.get()).abs() < 1e-12);
        } else {
            prop_assert!(a.fit.is_none() && b.fit.is_none());
        }
    }

    /// Moving the robot and the hedge together by a rigid motion of the world
    /// leaves the chain and the errors unchanged.
    #[test]
    fn rigid_motion_of_robot_and_hedge_changes_nothing(
        side in side(),
        dist in 0.6..2.8f64,
        angle in -0.5..0.5f64,
        xj in prop::collection::vec((-2.0..6.0f64, -0.3..0.3f64), 3..60),
        robot in (-50.0..50.0f64, -50.0..50.0f64, -3.1..3.1f64),
        motion in (-50.0..50.0f64, -50.0..50.0f64, -3.1..3.1f64),
    ) {
        let config = config();
        let (xs, js): (Vec<f64>, Vec<f64>) = xj.into_iter().unzip();
        let local = hedge(side, dist, angle, &xs, &js);
        let pose = Pose2::<World>::new(robot.0, robot.1, robot.2).unwrap();
        let to_world: Transform2<Robot, World> = pose.body_to_frame();
        let world: Vec<Point2<World>> = local.iter().map(|p| to_world.apply(*p).unwrap()).collect();
        let m = Transform2::<World, World>::new(motion.0, motion.1, motion.2).unwrap();
        let moved_pose = m.apply_pose(pose).unwrap();
        let moved_world: Vec<Point2<World>> = world.iter().map(|p| m.apply(*p).unwrap()).collect();
        let see = |pose: Pose2<World>, pts: &[Point2<World>]| -> Vec<Point2<Robot>> {
            let inv = pose.body_to_frame::<Robot>().inverse().unwrap();
            pts.iter().map(|p| inv.apply(*p).unwrap()).collect()
        };
        let a = detect_points::<M>(&see(pose, &world), side, &config).unwrap();
        let b = detect_points::<M>(&see(moved_pose, &moved_world), side, &config).unwrap();
        check_sane(&a);
        check_sane(&b);
        prop_assert_eq!(a.chain.indices(), b.chain.indices());
        prop_assert_eq!(a.verdict, b.verdict);
        if let (Some(fa), Some(fb)) = (a.fit, b.fit) {
            prop_assert!((fa.error.y.get() - fb.error.y.get()).abs() < 1e-6);
            prop_assert!((fa.error.angular_deviation.get() - fb.error.angular_deviation.get()).abs() < 1e-6);
        }
    }

    //= spec/pierre2022.md#edge-scan-scan-to-robot-frame-points
    //= type=test
    //# Each range MUST be converted into the point `range · (cos φ_k, sin φ_k)`
    //# of the sensor frame, with `φ_k = start + k · increment`, and then into
    //# the robot frame through the LiDAR's mount pose.
    /// A scan of a straight wall, through any mount pose, gives the wall's
    /// offset and angle: the mount is undone exactly.
    #[test]
    fn scanned_wall_gives_its_offset_and_angle_through_any_mount(
        side in side(),
        dist in 0.6..2.5f64,
        angle in -0.4..0.4f64,
        mount in (-0.5..2.0f64, -0.3..0.3f64, -3.1..3.1f64),
    ) {
        let config = config();
        let s = side.sign();
        // Wall: n·p = dist with n the unit normal towards the wall. It stays
        // on the requested side for 6 m ahead and the LiDAR is on the robot's
        // side of it.
        let n = (-s * angle.sin(), s * angle.cos());
        prop_assume!(s * angle >= 0.0 || dist > 6.0 * angle.abs().sin());
        prop_assume!(n.0 * mount.0 + n.1 * mount.1 < dist - 0.1);
        let rays = 720;
        let inc = core::f64::consts::TAU / 720.0;
        let ranges = cast_line(mount, n, dist, -core::f64::consts::PI, inc, rays, 30.0);
        let scan = Scan {
            start: Radians::new(-core::f64::consts::PI).unwrap(),
            increment: Radians::new(inc).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        let mount_tf = Transform2::<Sensor, Robot>::new(mount.0, mount.1, mount.2).unwrap();
        // A LiDAR 0.1 m from a wall sees it with millimetre spacing, and the
        // exact chain takes every point of a straight wall: room for 1024.
        let det = detect::<N, 1024>(&scan, &mount_tf, side, &config).unwrap();
        prop_assert_ne!(det.chain.end(), ChainEnd::Capacity);
        let fit = det.fit.unwrap();
        prop_assert!((fit.error.y.get() - s * (config.offset().get() - dist)).abs() < 1e-9);
        prop_assert!((fit.error.angular_deviation.get() + angle).abs() < 1e-9);
        // Within about 20° of the robot's axis the 3 m chain is narrower than
        // w_max = 1 m and fits exactly: Enter.
        if angle.abs() < 0.25 {
            prop_assert_eq!(det.verdict, Verdict::Enter);
        }
    }

    //= spec/pierre2022.md#edge-detect-one-detection
    //= type=test
    //# A detection MUST be Absent, with no fit, when the chain has fewer points
    //# than the configured fewest or cannot be fitted (fewer than 3 distinct
    //# abscissae).
    /// Any ranges at all, NaN and infinities included, and any scan angles:
    /// a sane detection or an EDGE-SCAN error, never a panic or a NaN.
    #[test]
    fn any_scan_gives_a_sane_detection_or_an_error(
        side in side(),
        ranges in prop::collection::vec(
            prop_oneof![
                4 => 0.0..10.0f64,
                1 => Just(f64::NAN),
                1 => Just(f64::INFINITY),
                1 => Just(f64::NEG_INFINITY),
                1 => any::<f64>(),
            ],
            0..400,
        ),
        start in -10.0..10.0f64,
        inc in -0.1..0.1f64,
        mount in (-1e3..1e3f64, -1e3..1e3f64, -10.0..10.0f64),
    ) {
        let scan = Scan {
            start: Radians::new(start).unwrap(),
            increment: Radians::new(inc).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        let mount = Transform2::<Sensor, Robot>::new(mount.0, mount.1, mount.2).unwrap();
        match detect::<512, M>(&scan, &mount, side, &config()) {
            Ok(det) => check_sane(&det),
            Err(e) => prop_assert_eq!(e.requirement, "EDGE-SCAN"),
        }
    }

    /// Any finite points, huge ones included: a sane detection or an EDGE-SCAN error.
    #[test]
    fn any_points_give_a_sane_detection_or_an_error(
        side in side(),
        points in prop::collection::vec(
            (prop_oneof![3 => -5.0..5.0f64, 1 => -1e300..1e300f64], prop_oneof![3 => -5.0..5.0f64, 1 => -1e300..1e300f64]),
            0..80,
        ),
    ) {
        let points: Vec<_> = points.into_iter().map(|(x, y)| pt(x, y)).collect();
        match detect_points::<M>(&points, side, &config()) {
            Ok(det) => check_sane(&det),
            Err(e) => prop_assert_eq!(e.requirement, "EDGE-SCAN"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any parameters at all: refused at construction, or a detector that
    /// gives sane detections on a hedge.
    #[test]
    fn any_configuration_is_refused_or_sane(
        values in prop::collection::vec(
            prop_oneof![
                4 => 0.0..5.0f64,
                1 => Just(f64::NAN),
                1 => Just(f64::INFINITY),
                1 => Just(0.0),
                1 => any::<f64>(),
            ],
            11,
        ),
        min_points in 0usize..10,
        side in side(),
        xj in prop::collection::vec((-2.0..6.0f64, -0.3..0.3f64), 3..60),
    ) {
        let params = EdgeParameters {
            radius: values[0],
            max_rotation: values[1],
            max_chain_length: values[2],
            search_distance: values[3],
            offset: values[4],
            min_chain_length: values[5],
            max_width: values[6],
            sigma_enter: values[7],
            sigma_exit: values[8],
            max_link: values[9],
            max_turn: values[10],
            min_points,
            ..EdgeParameters::PIERRE2022
        };
        match EdgeConfig::new(&params) {
            Err(e) => prop_assert!(e.requirement == "EDGE-CONFIG" || e.requirement == "SW-THRESHOLDS"),
            Ok(config) => {
                let (xs, js): (Vec<f64>, Vec<f64>) = xj.into_iter().unzip();
                let points = hedge(side, 1.4, 0.1, &xs, &js);
                check_sane(&detect_points::<M>(&points, side, &config).unwrap());
            }
        }
    }
}

//= spec/pierre2022.md#edge-detect-one-detection
//= type=test
//# A tracking error MUST be offered for commanding only when the verdict is
//# Enter or Hold.
#[test]
fn the_detector_agrees_with_the_free_functions_and_forgets_failed_scans() {
    let config = config();
    let mount = Transform2::<Sensor, Robot>::new(1.2, 0.0, 0.0).unwrap();
    // One detector per side (the side is part of a detector's configuration),
    // each reused across scans; the edge detector ignores the odometry pose.
    let detector_on = |side| {
        EdgeDetector::<N, M>::new(EdgeDetectorConfig {
            edge: config,
            mount,
            side,
        })
    };
    let mut left = detector_on(Side::Left);
    let mut right = detector_on(Side::Right);
    let odom = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    let inc = core::f64::consts::TAU / 360.0;
    for (k, (dist, angle)) in [(1.4, 0.0), (1.0, 0.2), (2.2, -0.1), (0.8, 0.05)]
        .into_iter()
        .enumerate()
    {
        let side = if k % 2 == 0 { Side::Left } else { Side::Right };
        let s = side.sign();
        let n = (-s * f64::sin(angle), s * f64::cos(angle));
        let ranges = cast_line(
            (1.2, 0.0, 0.0),
            n,
            dist,
            -core::f64::consts::PI,
            inc,
            360,
            30.0,
        );
        let scan = Scan {
            start: Radians::new(-core::f64::consts::PI).unwrap(),
            increment: Radians::new(inc).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        let detector = match side {
            Side::Left => &mut left,
            Side::Right => &mut right,
        };
        let outcome = detector.detect(&scan, &odom).unwrap();
        let free = detect::<N, M>(&scan, &mount, side, &config).unwrap();
        assert_eq!(outcome.verdict, free.verdict);
        assert_eq!(outcome.fit, free.fit);
        assert_eq!(outcome.usable_error(), free.usable_error());
        assert_eq!(detector.chain().indices(), free.chain.indices());
        assert_eq!(outcome.chain_points, free.chain.len());
        assert_eq!(outcome.chain_end, free.chain.end());
        assert_eq!(outcome.verdict, Verdict::Enter);
    }
    // A scan with more valid rays than the buffer: an error, and no chain
    // from the previous scan is left behind.
    let mut small = EdgeDetector::<8, M>::new(EdgeDetectorConfig {
        edge: config,
        mount,
        side: Side::Left,
    });
    let good = [f64::INFINITY; 8];
    let scan = Scan {
        start: Radians::new(0.0).unwrap(),
        increment: Radians::new(0.1).unwrap(),
        ranges: &good,
        limits: limits(),
    };
    small.detect(&scan, &odom).unwrap();
    let many = [1.5; 20];
    let scan = Scan {
        start: Radians::new(0.0).unwrap(),
        increment: Radians::new(0.1).unwrap(),
        ranges: &many,
        limits: limits(),
    };
    assert_eq!(
        small.detect(&scan, &odom).unwrap_err().requirement,
        "EDGE-SCAN"
    );
    assert!(small.chain().is_empty());
    assert_eq!(small.chain().end(), ChainEnd::NoEdge);
}

#[test]
fn bad_input_gives_absent() {
    let config = config();
    let mount = Transform2::<Sensor, Robot>::new(1.0, 0.0, 0.0).unwrap();
    let scan_of = |ranges: &[f64]| {
        let scan = Scan {
            start: Radians::new(-3.0).unwrap(),
            increment: Radians::new(0.0175).unwrap(),
            ranges,
            limits: limits(),
        };
        detect::<N, M>(&scan, &mount, Side::Left, &config).unwrap()
    };
    // Empty scan, all invalid.
    assert_eq!(scan_of(&[]).verdict, Verdict::Absent);
    let invalid = [f64::NAN, f64::INFINITY, -1.0, 0.0, 31.0, f64::NEG_INFINITY];
    assert_eq!(scan_of(&invalid).verdict, Verdict::Absent);
    // Nothing on the requested side: a wall on the right only.
    let right = wall(Side::Right, 1.4, 0.0, 0.05, -1.0, 5.0);
    let det = detect_points::<M>(&right, Side::Left, &config).unwrap();
    assert_eq!(det.verdict, Verdict::Absent);
    assert!(det.chain.is_empty() && det.usable_error().is_none());
    // Duplicate points: the same point many times.
    let dup = vec![pt(0.5, 1.2); 50];
    let det = detect_points::<M>(&dup, Side::Left, &config).unwrap();
    check_sane(&det);
    assert_eq!(det.verdict, Verdict::Absent);
    // Duplicates along a wall: every wall point twice.
    let twice: Vec<_> = wall(Side::Left, 1.4, 0.1, 0.05, -1.0, 5.0)
        .into_iter()
        .flat_map(|p| [p, p])
        .collect();
    let det = detect_points::<M>(&twice, Side::Left, &config).unwrap();
    check_sane(&det);
    assert_eq!(det.verdict, Verdict::Enter);
    // Points exactly on the starting circle (radius 1 about the rear point).
    let on_circle: Vec<_> = (1..36)
        .map(|k| {
            let a = f64::from(k) * core::f64::consts::PI / 36.0;
            pt(a.cos(), a.sin())
        })
        .collect();
    let det = detect_points::<M>(&on_circle, Side::Left, &config).unwrap();
    check_sane(&det);
    // Four points 0.5 m apart (fewer than the 5 required): Absent, though a
    // parabola would fit them.
    let four: Vec<_> = (0..4).map(|k| pt(0.5 * f64::from(k), 1.5)).collect();
    let det = detect_points::<M>(&four, Side::Left, &config).unwrap();
    assert_eq!(det.chain.len(), 4);
    assert_eq!(det.verdict, Verdict::Absent);
    let five: Vec<_> = (0..5).map(|k| pt(0.5 * f64::from(k), 1.5)).collect();
    let det = detect_points::<M>(&five, Side::Left, &config).unwrap();
    assert_eq!(det.verdict, Verdict::Enter);
    // Extreme but valid configurations: a huge circle, a huge chain.
    for (radius, l_max) in [(1e300, 3.0), (1e-300, 3.0), (1.0, 1e300), (1e150, 1e300)] {
        let p = EdgeParameters {
            radius,
            max_chain_length: l_max,
            ..EdgeParameters::PIERRE2022
        };
        let extreme = EdgeConfig::new(&p).unwrap();
        let wall_points = wall(Side::Left, 1.4, 0.1, 0.05, -1.0, 5.0);
        check_sane(&detect_points::<M>(&wall_points, Side::Left, &extreme).unwrap());
    }
    // Two points: a chain that cannot be fitted.
    let two = [pt(0.0, 1.5), pt(0.3, 1.5)];
    let det = detect_points::<M>(&two, Side::Left, &config).unwrap();
    assert_eq!(det.chain.len(), 2);
    assert_eq!(det.verdict, Verdict::Absent);
    // Points on a line across the robot (same x): a singular fit.
    let across: Vec<_> = (0..20)
        .map(|k| pt(0.5, 1.2 + 0.05 * f64::from(k)))
        .collect();
    let det = detect_points::<M>(&across, Side::Left, &config).unwrap();
    check_sane(&det);
}

//= spec/pierre2022.md#edge-detect-one-detection
//= type=test
//# A tracking error MUST be offered for commanding only when the verdict is
//# Enter or Hold.
#[test]
fn rejected_detections_offer_no_error() {
    let config = config();
    // A short piece of hedge (0.6 m): fitted but shorter than l_min → Exit.
    let short = wall(Side::Left, 1.4, 0.0, 0.05, -0.3, 0.3);
    let det = detect_points::<M>(&short, Side::Left, &config).unwrap();
    assert!(det.fit.is_some());
    assert_eq!(det.verdict, Verdict::Exit);
    assert!(det.usable_error().is_none());
    // The same box-shaped hedge graded with σ_edge = 1 cm: its residual
    // (a few cm) is between the thresholds → Hold, and the error is usable.
    // (The box's sides are corners, its far end is left by a link longer
    // than 1 m: the paper's chain, φ_turn = π and l_link = 2r, follows them.)
    let strict = EdgeConfig::new(&EdgeParameters {
        sigma_enter: 0.01,
        max_turn: core::f64::consts::PI,
        max_link: 2.0,
        ..EdgeParameters::PIERRE2022
    })
    .unwrap();
    let xs: Vec<f64> = (0..80).map(|k| -1.0 + 0.05 * f64::from(k)).collect();
    let js: Vec<f64> = xs
        .iter()
        .map(|&x| if (0.8..1.8).contains(&x) { -0.7 } else { 0.0 })
        .collect();
    let boxy = hedge(Side::Left, 1.4, 0.0, &xs, &js);
    let det = detect_points::<M>(&boxy, Side::Left, &strict).unwrap();
    check_sane(&det);
    let fit = det.fit.unwrap();
    assert!(fit.quality.residual_std.get() > 0.01 && fit.quality.residual_std.get() < 0.5);
    assert_eq!(det.verdict, Verdict::Hold);
    assert_eq!(det.usable_error(), Some(fit.error));
    // A wall at 80° to the robot: long enough, but wider than w_max → Exit.
    let steep = wall(Side::Left, 1.4, 1.4, 0.05, -1.0, 5.0);
    let det = detect_points::<M>(&steep, Side::Left, &config).unwrap();
    assert!(det.fit.unwrap().quality.width.get() >= config.max_width().get());
    assert_eq!(det.verdict, Verdict::Exit);
    assert!(det.usable_error().is_none());
}
