//! The parts of the edge detector one at a time, by hand (Pierre 2022,
//! section 2.2, eqs. 8-11 and 21): the validated configuration
//! (EDGE-CONFIG), the scan turned into robot-frame points (EDGE-SCAN,
//! LIB-SCAN), the chain's parabola (EDGE-PARABOLA), the errors to the line
//! to follow (EDGE-ERRORS, EDGE-OFFSET) and the chain's quality and verdict
//! (EDGE-QUALITY).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

mod edge_support;

use core::f64::consts::{FRAC_PI_2, FRAC_PI_6, TAU};

use edge_support::hedge;
use fieldguide::geometry::fit::fit_parabola;
use fieldguide::perception::edge::{
    detect_points, scan_to_points, tracking_error, EdgeConfig, EdgeParameters, EdgeQuality,
    ParabolaFit, Side,
};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Point2, Radians, Robot, Sensor, Transform2, Verdict};
use nalgebra::{Matrix3, Vector3};

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn pts(xy: &[(f64, f64)]) -> Vec<Point2<Robot>> {
    xy.iter()
        .map(|&(x, y)| Point2::new(x, y).unwrap())
        .collect()
}

/// Eq. 9 computed literally: `(XᵀX)⁻¹ XᵀY` with rows `(x², x, 1)` of X.
fn literal_parabola(points: &[Point2<Robot>]) -> Vector3<f64> {
    let mut xtx = Matrix3::zeros();
    let mut xty = Vector3::zeros();
    for p in points {
        let row = Vector3::new(p.x() * p.x(), p.x(), 1.0);
        xtx += row * row.transpose();
        xty += row * p.y();
    }
    xtx.try_inverse().unwrap() * xty
}

//= spec/pierre2022.md#edge-config-detector-configuration
//= type=test
//# A configuration MUST be refused at construction, with an error naming
//# the requirement, unless r > 0, 0 < θ_max < 2π, l_max > 0, the search
//# distance is > 0, D ≥ 0, 0 ≤ l_min < l_max, l_link > 0,
//# 0 < φ_turn ≤ π, w_max > 0, the fewest chain points is at least 4 and
//# 0 < σ_edge < σ_path, every value being finite.
#[test]
fn each_bad_parameter_is_refused_with_its_requirement() {
    let good = EdgeParameters::PIERRE2022;
    assert!(EdgeConfig::new(&good).is_ok());
    let bad: [(EdgeParameters, &str); 17] = [
        (
            EdgeParameters {
                max_turn: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_turn: 3.2,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_link: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_link: f64::NAN,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                min_points: 3,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                radius: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                radius: f64::NAN,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_rotation: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_rotation: TAU,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_chain_length: -1.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                search_distance: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                offset: -0.1,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                min_chain_length: 3.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                max_width: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                sigma_enter: 0.0,
                ..good
            },
            "EDGE-CONFIG",
        ),
        (
            EdgeParameters {
                sigma_exit: 0.15,
                ..good
            },
            "SW-THRESHOLDS",
        ),
        (
            EdgeParameters {
                sigma_exit: f64::INFINITY,
                ..good
            },
            "EDGE-CONFIG",
        ),
    ];
    for (p, id) in bad {
        assert_eq!(EdgeConfig::new(&p).unwrap_err().requirement, id, "{p:?}");
    }
}

//= spec/pierre2022.md#edge-parabola-least-squares-parabola-of-the-chain
//= type=test
//# The parabola y = a x² + b x + c MUST be the least-squares fit of the
//# chain points, [a b c]ᵀ = (XᵀX)⁻¹ XᵀY with rows (p_x², p_x, 1) of X.
#[test]
fn fit_recovers_an_exact_parabola_and_matches_the_textbook_formula() {
    let f = |x: f64| 0.3 * x * x - 0.2 * x + 1.7;
    let p = pts(&[
        (0.0, f(0.0)),
        (0.5, f(0.5)),
        (1.2, f(1.2)),
        (2.0, f(2.0)),
        (3.1, f(3.1)),
    ]);
    let fit = fit_parabola(p.iter()).unwrap();
    assert!((fit.a - 0.3).abs() < 1e-12 && (fit.b + 0.2).abs() < 1e-12);
    assert!((fit.c - 1.7).abs() < 1e-12);
    // Noisy points: compare with eq. 9 computed literally.
    let p = pts(&[
        (0.1, 1.0),
        (0.7, 1.3),
        (1.1, 1.1),
        (1.9, 1.6),
        (2.4, 1.5),
        (3.0, 2.1),
    ]);
    let fit = fit_parabola(p.iter()).unwrap();
    let literal = literal_parabola(&p);
    assert!((fit.a - literal[0]).abs() < 1e-9);
    assert!((fit.b - literal[1]).abs() < 1e-9);
    assert!((fit.c - literal[2]).abs() < 1e-9);
    // The detector's parabola is that fit of its chain's points.
    let config = EdgeConfig::pierre2022().unwrap();
    let xs: Vec<f64> = (0..50).map(|k| -1.0 + 0.1 * f64::from(k)).collect();
    let js: Vec<f64> = (0..50)
        .map(|k| 0.05 * (f64::from(k) * 0.37).sin())
        .collect();
    for side in [Side::Left, Side::Right] {
        let points = hedge(side, 1.4, 0.1, &xs, &js);
        let det = detect_points::<128>(&points, side, &config).unwrap();
        assert!(det.chain.len() >= config.min_points());
        let fit = det.fit.unwrap().parabola;
        let literal = literal_parabola(det.chain.points());
        assert!((fit.a - literal[0]).abs() < 1e-9, "{side:?}");
        assert!((fit.b - literal[1]).abs() < 1e-9, "{side:?}");
        assert!((fit.c - literal[2]).abs() < 1e-9, "{side:?}");
    }
}

//= spec/pierre2022.md#edge-parabola-least-squares-parabola-of-the-chain
//= type=test
//# Fewer than 3 points or a singular normal matrix MUST give an error, not a
//# parabola.
#[test]
fn too_few_or_repeated_abscissae_are_refused() {
    let two = pts(&[(0.0, 1.0), (1.0, 2.0)]);
    assert_eq!(
        fit_parabola(two.iter()).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
    let same_x = pts(&[(1.0, 1.0), (1.0, 2.0), (1.0, 3.0), (1.0, 4.0)]);
    assert_eq!(
        fit_parabola(same_x.iter()).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
    let two_x = pts(&[(1.0, 1.0), (1.0, 2.0), (2.0, 3.0), (2.0, 4.0)]);
    assert_eq!(
        fit_parabola(two_x.iter()).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
}

//= spec/pierre2022.md#edge-errors-lateral-and-angular-errors-at-the-robot
//= type=test
//# The angular error MUST be θ̃ = −arctan(2 a x_r + b), the robot's heading
//# minus the heading of the parabola's tangent at x_r.
//= spec/pierre2022.md#edge-offset-desired-lateral-distance
//= type=test
//# The lateral error MUST be y = s·D − (a x_r² + b x_r + c) cos φ with
//# φ = arctan(2 a x_r + b), s = +1 for an edge on the left and −1 on the
//# right, so that y > 0 when the robot is left of the line it follows.
#[test]
fn errors_by_hand() {
    let d = m(1.4);
    // A wall on the left, 1 m away (perpendicular), heading 30° to the left
    // of the robot: y_e = 1 / cos 30°, slope tan 30°.
    let wall = ParabolaFit {
        a: 0.0,
        b: libm::tan(FRAC_PI_6),
        c: 1.0 / libm::cos(FRAC_PI_6),
    };
    let e = tracking_error(&wall, Side::Left, d, 0.0).unwrap();
    // Too close to the wall: the line to follow is 0.4 m to the robot's right.
    assert!((e.y.get() - 0.4).abs() < 1e-12);
    assert!((e.angular_deviation.get() + FRAC_PI_6).abs() < 1e-12);
    // The same wall on the right, mirrored.
    let right = ParabolaFit {
        a: 0.0,
        b: -wall.b,
        c: -wall.c,
    };
    let e = tracking_error(&right, Side::Right, d, 0.0).unwrap();
    assert!((e.y.get() + 0.4).abs() < 1e-12);
    assert!((e.angular_deviation.get() - FRAC_PI_6).abs() < 1e-12);
    // Eq. 11 at x_r ≠ 0 uses the derivative 2 a x_r + b, not 2 a x_r² + b.
    let p = ParabolaFit {
        a: 0.25,
        b: 0.0,
        c: 2.0,
    };
    let e = tracking_error(&p, Side::Left, d, 2.0).unwrap();
    let phi = libm::atan(1.0);
    assert!((e.angular_deviation.get() + phi).abs() < 1e-12);
    assert!((e.y.get() - (1.4 - 3.0 * libm::cos(phi))).abs() < 1e-12);
}

//= spec/pierre2022.md#edge-quality-detection-quality-and-verdict
//= type=test
//# The residual standard deviation MUST be the square root of the mean of
//# the squared residuals (p_y − (a p_x² + b p_x + c))² over the chain, and
//# the width MUST be the largest difference p_{y,1} − p_{y,2} over pairs of
//# chain points.
//= spec/pierre2022.md#edge-quality-detection-quality-and-verdict
//= type=test
//# The verdict of a fitted chain MUST be Exit when its length is not greater
//# than l_min or its width is not less than w_max, and otherwise the
//# classification of its residual standard deviation against σ_edge (enter)
//# and σ_path (exit), smaller being better.
#[test]
fn measures_and_verdicts_by_hand() {
    let line = ParabolaFit {
        a: 0.0,
        b: 0.0,
        c: 1.0,
    };
    let config = EdgeConfig::pierre2022().unwrap();
    let make = |ys: &[f64]| -> Vec<Point2<Robot>> {
        let mut x = 0.0;
        ys.iter()
            .map(|&y| {
                x += 0.5;
                Point2::new(x, y).unwrap()
            })
            .collect()
    };
    // Residuals ±0.1: σ = 0.1 < 0.15 → Enter.
    let q = EdgeQuality::measure(&make(&[1.1, 0.9, 1.1, 0.9]), m(2.0), &line).unwrap();
    assert!((q.residual_std.get() - 0.1).abs() < 1e-12);
    assert!((q.width.get() - 0.2).abs() < 1e-12);
    assert_eq!(q.grade(&config), Verdict::Enter);
    // Residuals ±0.3: between σ_edge and σ_path → Hold.
    let q = EdgeQuality::measure(&make(&[1.3, 0.7, 1.3, 0.7]), m(2.0), &line).unwrap();
    assert!((q.residual_std.get() - 0.3).abs() < 1e-12);
    assert_eq!(q.grade(&config), Verdict::Hold);
    // Residuals 0.6 → Exit.
    let q = EdgeQuality::measure(&make(&[1.6, 0.4, 1.6, 0.4]), m(2.0), &line).unwrap();
    assert_eq!(q.grade(&config), Verdict::Exit);
    // Good fit but too short (l_min = 1 m), or too wide (w_max = 1.5 m).
    let good = make(&[1.1, 0.9, 1.1, 0.9]);
    let short = EdgeQuality::measure(&good, m(1.0), &line).unwrap();
    assert_eq!(short.grade(&config), Verdict::Exit);
    let wide = EdgeQuality {
        width: m(1.5),
        ..EdgeQuality::measure(&good, m(2.0), &line).unwrap()
    };
    assert_eq!(wide.grade(&config), Verdict::Exit);
    assert!(EdgeQuality::measure(&[], m(0.0), &line).is_err());
}

fn limits() -> RangeLimits {
    RangeLimits::new(m(0.1), m(30.0)).unwrap()
}

//= spec/pierre2022.md#edge-scan-scan-to-robot-frame-points
//= type=test
//# A range that is NaN, infinite, or outside the sensor's `[min, max)`
//# interval MUST be dropped.
#[test]
fn invalid_ranges_are_dropped_and_points_are_mounted() {
    // 30.0 is the limit itself: "no return" for many drivers.
    let ranges = [2.0, f64::NAN, f64::INFINITY, 0.05, 31.0, 1.0, 30.0];
    let scan = Scan {
        start: Radians::new(0.0).unwrap(),
        increment: Radians::new(FRAC_PI_2).unwrap(),
        ranges: &ranges,
        limits: limits(),
    };
    // LiDAR 1.5 m ahead of the rear axle, turned left by 90°.
    let mount = Transform2::<Sensor, Robot>::new(1.5, 0.0, FRAC_PI_2).unwrap();
    let pts = scan_to_points::<8>(&scan, &mount).unwrap();
    assert_eq!(pts.dropped(), 5);
    let p = pts.as_slice();
    assert_eq!(p.len(), 2);
    // Ray 0: 2 m along the sensor x axis = robot +y.
    assert!((p[0].x() - 1.5).abs() < 1e-12 && (p[0].y() - 2.0).abs() < 1e-12);
    // Ray 5 points at 5·90° = 90° (mod 360°) in the sensor: robot −x.
    assert!((p[1].x() - 0.5).abs() < 1e-9 && p[1].y().abs() < 1e-9);
}

#[test]
fn full_buffer_is_an_error() {
    let ranges = [1.0; 5];
    let scan = Scan {
        start: Radians::new(0.0).unwrap(),
        increment: Radians::new(0.01).unwrap(),
        ranges: &ranges,
        limits: limits(),
    };
    let mount = Transform2::<Sensor, Robot>::new(0.0, 0.0, 0.0).unwrap();
    let err = scan_to_points::<4>(&scan, &mount).unwrap_err();
    assert_eq!(err.requirement, "EDGE-SCAN");
}

//= spec/library.md#lib-scan-one-planar-lidar-scan
//= type=test
//# Ray k of a scan (k from 0) MUST be read at the angle start + k · increment
//# of the scan plane, counter-clockwise from the sensor's x axis, with the
//# increment signed as the sensor delivers it.
#[test]
fn recurrence_matches_direct_trigonometry() {
    let ranges = [3.0; 1000];
    // Counter-clockwise and clockwise (a LiDAR mounted upside down).
    for (start, increment) in [(-3.0, 0.00614), (3.0, -0.00614)] {
        let scan = Scan {
            start: Radians::new(start).unwrap(),
            increment: Radians::new(increment).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        let mount = Transform2::<Sensor, Robot>::new(0.0, 0.0, 0.0).unwrap();
        let pts = scan_to_points::<1000>(&scan, &mount).unwrap();
        assert_eq!(pts.as_slice().len(), 1000);
        let mut k = 0.0;
        for p in pts.as_slice() {
            let a = start + k * increment;
            assert!((p.x() - 3.0 * libm::cos(a)).abs() < 1e-12);
            assert!((p.y() - 3.0 * libm::sin(a)).abs() < 1e-12);
            k += 1.0;
        }
    }
}
