//! Row lines (eq. 15), errors to a line (eq. 16) and to two rows (eq. 20) of
//! Pierre 2022 (FUR-LINE, FUR-ERRORS, FUR-TWO-ROWS), and the accumulation of
//! selections through odometry (FUR-ACCUMULATE).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use fieldguide::geometry::fit::fit_line;
use fieldguide::perception::furrow::accumulation::{Accumulator, Selected};
use fieldguide::perception::furrow::lines::{
    fit_row_line, fit_row_line_toward, mean_tracking_error, tracking_error, RowLine,
    FIRST_LINE_MAX_TURN,
};
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::{Meters, Odom, Point2, Pose2, Radians, Robot};
use proptest::prelude::*;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn pts(v: &[(f64, f64)]) -> Vec<Point2<Robot>> {
    v.iter().map(|&(x, y)| Point2::new(x, y).unwrap()).collect()
}

/// A world point seen from a robot at `(px, py, psi)`, by hand (independent of `Transform2`).
fn to_robot(pose: (f64, f64, f64), q: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (q.0 - pose.0, q.1 - pose.1);
    let (c, s) = (pose.2.cos(), pose.2.sin());
    (c * dx + s * dy, -s * dx + c * dy)
}

/// The line y = a x + b through two robot-frame points.
fn line_through(p: (f64, f64), q: (f64, f64)) -> (f64, f64) {
    let a = (q.1 - p.1) / (q.0 - p.0);
    (a, p.1 - a * p.0)
}

//= spec/pierre2022.md#fur-line-row-line-by-least-squares
//= type=test
//# The row line MUST be the least-squares solution (a, b) of a p_x + b = p_y
//# over the accumulated points, minimising the squared residuals in y.
#[test]
fn hand_computed_fits() {
    let l = fit_row_line(pts(&[(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)])).unwrap();
    assert!((l.slope() - 1.0).abs() < 1e-12 && (l.intercept().get() - 1.0).abs() < 1e-12);
    // (0,0), (1,1), (2,0): x̄ = 1, ȳ = 1/3, S_xy = 0: a = 0, b = 1/3.
    let l = fit_row_line(pts(&[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)])).unwrap();
    assert!(l.slope().abs() < 1e-12 && (l.intercept().get() - 1.0 / 3.0).abs() < 1e-12);
    // (1,0), (2,1), (3,1), (4,2): x̄ = 2.5, ȳ = 1, S_xx = 5, S_xy = 3: a = 0.6, b = −0.5.
    let l = fit_row_line(pts(&[(1.0, 0.0), (2.0, 1.0), (3.0, 1.0), (4.0, 2.0)])).unwrap();
    assert!((l.slope() - 0.6).abs() < 1e-12 && (l.intercept().get() + 0.5).abs() < 1e-12);
    assert!((l.y_at(2.0).unwrap() - 0.7).abs() < 1e-12);
}

//= spec/library.md#lib-finite-no-nan-or-infinity
//= type=test
//# A value returned by the core MUST be finite: a computation whose result
//# would be NaN or infinite MUST return a `Precondition` error instead.
#[test]
fn a_row_line_value_that_overflows_is_an_error() {
    let steep = RowLine::new(1e308, Meters::new(0.5).unwrap()).unwrap();
    for x in [4.93, -4.93, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(steep.y_at(x).unwrap_err().requirement, "LIB-FINITE", "{x}");
    }
    assert!((steep.y_at(0.0).unwrap() - 0.5).abs() < 1e-15);
}

//= spec/pierre2022.md#fur-line-row-line-by-least-squares
//= type=test
//# A fit over fewer than two points, or over points whose x variance is below
//# (1 mm)², MUST be refused with an error naming FUR-LINE.
#[test]
fn degenerate_fits_are_refused() {
    for bad in [
        vec![],
        pts(&[(4.0, 0.3)]),
        pts(&[(4.0, 0.3), (4.0, 0.5), (4.0005, 0.1)]),
    ] {
        assert_eq!(fit_row_line(bad).unwrap_err().requirement, "FUR-LINE");
    }
    assert!(fit_row_line(pts(&[(4.0, 0.3), (4.01, 0.3)])).is_ok());
    // Beyond FUR-LINE's conditions, the shared fit's own refusal passes
    // through: 10¹¹ m away, 1 cm of spread is below its relative 1e−12.
    let far = pts(&[(1.0e11 - 0.01, 0.3), (1.0e11, 0.2), (1.0e11 + 0.01, 0.1)]);
    assert_eq!(
        fit_row_line(&far).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
}

//= spec/pierre2022.md#fur-errors-tracking-error-to-a-row-line
//= type=test
//# The tracking error to the line y = a x + b of the robot frame MUST be
//# y = −b / sqrt(a² + 1) and θ̃ = −arctan(a).
#[test]
fn hand_computed_errors() {
    // A row 0.5 m to the left, parallel: the robot is right of it.
    let e = tracking_error(&RowLine::new(0.0, m(0.5)).unwrap()).unwrap();
    assert!((e.y.get() + 0.5).abs() < 1e-12 && e.angular_deviation.get().abs() < 1e-12);
    // y = x + 1: distance 1/√2, the row crosses ahead-left going left: the
    // robot points 45° right of the row.
    let e = tracking_error(&RowLine::new(1.0, m(1.0)).unwrap()).unwrap();
    assert!((e.y.get() + 1.0 / 2.0_f64.sqrt()).abs() < 1e-12);
    assert!((e.angular_deviation.get() + core::f64::consts::FRAC_PI_4).abs() < 1e-12);
    assert_eq!(e.curvature.get(), 0.0);
}

//= spec/pierre2022.md#fur-two-rows-error-to-the-middle-of-two-rows
//= type=test
//# With two rows, the tracking error MUST be the mean of the errors to the
//# left and right lines: y = (y_l + y_r)/2 and θ̃ = (θ̃_l + θ̃_r)/2.
#[test]
fn hand_computed_two_row_error() {
    // Rows at +0.5 and −0.25, parallel: errors −0.5 and +0.25, mean −0.125.
    let l = RowLine::new(0.0, m(0.5)).unwrap();
    let r = RowLine::new(0.0, m(-0.25)).unwrap();
    let e = mean_tracking_error(&l, &r).unwrap();
    assert!((e.y.get() + 0.125).abs() < 1e-12);
    let l = RowLine::new(0.2, m(0.5)).unwrap();
    let r = RowLine::new(-0.1, m(-0.5)).unwrap();
    let e = mean_tracking_error(&l, &r).unwrap();
    assert!((e.angular_deviation.get() + (0.2_f64.atan() - 0.1_f64.atan()) / 2.0).abs() < 1e-12);
}

//= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
//= type=test
//# A capacity of zero, a capacity above the storage N, or a non-positive
//# keep distance MUST be refused with an error naming FUR-ACCUMULATE.
#[test]
fn bad_accumulators_are_refused() {
    assert_eq!(
        Accumulator::<4>::new(0, m(5.0)).unwrap_err().requirement,
        "FUR-ACCUMULATE"
    );
    assert!(Accumulator::<4>::new(5, m(5.0)).is_err());
    assert!(Accumulator::<4>::new(4, m(0.0)).is_err());
    assert!(Accumulator::<4>::new(4, m(5.0)).is_ok());
}

//= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
//= type=test
//# When the buffer already holds its capacity of selections, storing a new
//# one MUST drop the oldest.
#[test]
fn a_full_buffer_drops_the_oldest() {
    let mut acc = Accumulator::<8>::new(3, m(100.0)).unwrap();
    let pose = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    for i in 0..3 {
        let p = Point2::<Robot>::new(f64::from(i), 0.0).unwrap();
        assert!(acc.push(&Selected::One(p), &pose).unwrap().is_none());
    }
    let dropped = acc
        .push(&Selected::One(Point2::new(3.0, 0.0).unwrap()), &pose)
        .unwrap();
    assert_eq!(dropped, Some(Selected::One(Point2::new(0.0, 0.0).unwrap())));
    assert_eq!(acc.len(), 3);
    let xs: Vec<f64> = acc
        .in_robot_frame(&pose)
        .map(|s| s.reference().x())
        .collect();
    assert_eq!(xs, vec![1.0, 2.0, 3.0]);
    acc.clear();
    assert!(acc.is_empty() && acc.newest(&pose).is_none());
}

/// Selections every 0.25 m of travel: with n = 3 and a span of 1 m the
/// buffer holds the 5 that span 1 m; with span 0 the 3 of the count; with
/// 10 m the storage's 8. Whatever the span, it never holds fewer than n.
//= spec/pierre2022.md#fur-span-the-kept-selections-span-a-distance-of-travel
//= type=test
//# When the buffer holds its n selections and has room for more, storing a
//# new one MUST drop the oldest only if the robot's odometry positions at the
//# scans of the second oldest and of the new selection are at least the
//# configured span apart.
#[test]
fn the_buffer_keeps_the_selections_of_its_span() {
    for (span, kept) in [(0.0, 3), (1.0, 5), (10.0, 8)] {
        let mut acc = Accumulator::<8>::new(3, m(100.0))
            .unwrap()
            .with_span(m(span))
            .unwrap();
        for i in 0..20 {
            let x = 0.25 * f64::from(i);
            let pose = Pose2::<Odom>::new(x, 0.0, 0.0).unwrap();
            acc.push(&Selected::One(Point2::new(3.0, 0.0).unwrap()), &pose)
                .unwrap();
            assert_eq!(
                acc.len(),
                (i as usize + 1).min(kept),
                "span {span}, push {i}"
            );
        }
        // The oldest kept was seen (kept − 1) × 0.25 m back: its point, 3 m
        // ahead of the robot then, is 3 − that ahead now.
        let pose = Pose2::<Odom>::new(0.25 * 19.0, 0.0, 0.0).unwrap();
        let oldest = acc.in_robot_frame(&pose).next().unwrap().reference().x();
        assert!(
            (oldest - (3.0 - 0.25 * (kept as f64 - 1.0))).abs() < 1e-12,
            "span {span}"
        );
    }
}

//= spec/pierre2022.md#fur-span-the-kept-selections-span-a-distance-of-travel
//= type=test
//# A negative span MUST be refused with an error naming FUR-SPAN.
#[test]
fn a_negative_span_is_refused() {
    let acc = Accumulator::<4>::new(4, m(5.0)).unwrap();
    assert_eq!(
        acc.clone().with_span(m(-0.1)).unwrap_err().requirement,
        "FUR-SPAN"
    );
    assert!(acc.with_span(m(0.0)).is_ok());
}

/// Stores, seen from the odometry origin, a pair of rows whose middle is
/// 4 m ahead and then one row's point 1 m ahead.
fn push_pair_and_point(acc: &mut Accumulator<8>) {
    let start = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    let pair = Selected::Two(Pair {
        left: Point2::<Robot>::new(4.0, 0.4).unwrap(),
        right: Point2::<Robot>::new(4.0, -0.4).unwrap(),
    });
    acc.push(&pair, &start).unwrap();
    acc.push(&Selected::One(Point2::new(1.0, 0.0).unwrap()), &start)
        .unwrap();
}

//= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
//= type=test
//# A selection whose reference point lies farther than the keep distance
//# from the robot MUST be dropped.
#[test]
fn far_selections_are_dropped() {
    let mut acc = Accumulator::<8>::new(8, m(5.0)).unwrap();
    push_pair_and_point(&mut acc);
    // 2 m back, the pair is 6 m ahead (dropped), the point 3 m (kept).
    let back = Pose2::<Odom>::new(-2.0, 0.0, 0.0).unwrap();
    assert_eq!(acc.forget_far(&back), 1);
    assert_eq!(acc.len(), 1);
    let newest = acc.newest(&back).unwrap();
    assert!((newest.reference().x() - 3.0).abs() < 1e-12);
}

/// Points the robot has passed are dropped even within the keep distance:
/// they are no row ahead of it (a plot left behind in the headland).
//= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
//= type=test
//# A selection whose reference point lies behind the robot (x < 0 in the
//# current robot frame) MUST be dropped.
#[test]
fn selections_behind_the_robot_are_dropped() {
    let mut acc = Accumulator::<8>::new(8, m(6.0)).unwrap();
    push_pair_and_point(&mut acc);
    // On O: both kept (x = 0 is not behind).
    let on = Pose2::<Odom>::new(1.0, 0.0, 0.0).unwrap();
    assert_eq!(acc.forget_far(&on), 0);
    // 2 m on, the point is 1 m behind (dropped, 1 m from the robot), the pair 2 m ahead.
    let later = Pose2::<Odom>::new(2.0, 0.0, 0.0).unwrap();
    assert_eq!(acc.forget_far(&later), 1);
    assert_eq!(acc.len(), 1);
    let newest = acc.newest(&later).unwrap();
    assert!((newest.reference().x() - 2.0).abs() < 1e-12);
    // Turned half a turn on the spot: the pair is now behind, and dropped.
    let turned = Pose2::<Odom>::new(2.0, 0.0, core::f64::consts::PI).unwrap();
    assert_eq!(acc.forget_far(&turned), 1);
    assert!(acc.is_empty());
}

proptest! {
    //= spec/pierre2022.md#fur-line-row-line-by-least-squares
    //= type=test
    //# The row line MUST be the least-squares solution (a, b) of a p_x + b = p_y
    //# over the accumulated points, minimising the squared residuals in y.
    #[test]
    fn the_row_line_is_the_least_squares_line(
        raw in prop::collection::vec((0.5_f64..8.0, -2.0_f64..2.0), 2..40),
        nudge in (-0.1_f64..0.1, -0.1_f64..0.1),
    ) {
        let points = pts(&raw);
        match fit_row_line(&points) {
            Ok(line) => {
                // The shared fit's coefficients, as a row line of the robot frame.
                let shared = fit_line(&points).unwrap();
                prop_assert!((line.slope() - shared.a).abs() < 1e-12);
                prop_assert!((line.intercept().get() - shared.b).abs() < 1e-12);
                // Normal equations (independent of the fit's centring and
                // scaling): the residuals sum to zero and are orthogonal to x.
                let residual = |p: &Point2<Robot>| p.y() - line.y_at(p.x()).unwrap();
                let n = points.len() as f64;
                let scale = points.iter().map(|p| p.x().abs()).sum::<f64>() / n;
                prop_assert!(points.iter().map(residual).sum::<f64>().abs() < 1e-9 * n);
                prop_assert!(
                    points.iter().map(|p| residual(p) * p.x()).sum::<f64>().abs()
                        < 1e-9 * n * scale
                );
                // No other line does better.
                let other = RowLine::new(line.slope() + nudge.0, m(line.intercept().get() + nudge.1)).unwrap();
                let cost = |l: &RowLine| points.iter().map(|p| (p.y() - l.y_at(p.x()).unwrap()).powi(2)).sum::<f64>();
                prop_assert!(cost(&line) <= cost(&other) + 1e-12);
            }
            Err(e) => {
                // Only the furrow's precondition may refuse these points.
                let mean = raw.iter().map(|q| q.0).sum::<f64>() / raw.len() as f64;
                let var = raw.iter().map(|q| (q.0 - mean).powi(2)).sum::<f64>() / raw.len() as f64;
                prop_assert_eq!(e.requirement, "FUR-LINE");
                prop_assert!(var < 1e-6 * (1.0 + 1e-9));
            }
        }
    }

    //= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
    //= type=test
    //# Each selection MUST be stored in the odometry frame through the
    //# odometry pose of its scan, and read back in the current robot frame
    //# through the inverse of the current odometry pose.
    #[test]
    fn known_odometry_reproduces_a_straight_row_exactly(
        start in (-50.0_f64..50.0, -50.0_f64..50.0, -3.0_f64..3.0),
        row_offset in -1.0_f64..1.0,
        row_angle in -0.5_f64..0.5,
        moves in prop::collection::vec((0.0_f64..0.1, -0.02_f64..0.02), 5..40),
    ) {
        // The row: through the start pose's point `row_offset` to its left,
        // heading `row_angle` from the robot's start heading.
        let (x0, y0, h0) = start;
        let heading = h0 + row_angle;
        let q0 = (x0 - row_offset * h0.sin(), y0 + row_offset * h0.cos());
        let on_row = |s: f64| (q0.0 + s * heading.cos(), q0.1 + s * heading.sin());
        let mut acc = Accumulator::<64>::new(64, m(1000.0)).unwrap();
        let mut pose = (x0, y0, h0);
        for (i, &(ds, dpsi)) in moves.iter().enumerate() {
            pose = (pose.0 + ds * pose.2.cos(), pose.1 + ds * pose.2.sin(), pose.2 + dpsi);
            let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
            let (rx, ry) = to_robot(pose, on_row(4.0 + 0.07 * i as f64));
            acc.push(&Selected::One(Point2::new(rx, ry).unwrap()), &odom).unwrap();
        }
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        let (a, b) = line_through(to_robot(pose, on_row(0.0)), to_robot(pose, on_row(1.0)));
        // Every point read back lies on the true row in the current robot frame.
        for s in acc.in_robot_frame(&odom) {
            let p = s.reference();
            prop_assert!((p.y() - (a * p.x() + b)).abs() < 1e-9);
        }
        let kept: Vec<Point2<Robot>> = acc.in_robot_frame(&odom).map(|s| s.reference()).collect();
        let line = fit_row_line(&kept).unwrap();
        prop_assert!((line.slope() - a).abs() < 1e-7, "slope {} vs {}", line.slope(), a);
        prop_assert!((line.intercept().get() - b).abs() < 1e-7);
    }

    //= spec/pierre2022.md#fur-errors-tracking-error-to-a-row-line
    //= type=test
    //# The tracking error to the line y = a x + b of the robot frame MUST be
    //# y = −b / sqrt(a² + 1) and θ̃ = −arctan(a).
    #[test]
    fn errors_match_the_robot_pose_relative_to_the_row(
        along in -10.0_f64..10.0,
        lateral in -2.0_f64..2.0,
        psi in -1.3_f64..1.3,
    ) {
        // The row is the world x axis; the robot is `lateral` to its left,
        // heading `psi`: the library's error is (lateral, psi).
        let pose = (along, lateral, psi);
        let (a, b) = line_through(to_robot(pose, (0.0, 0.0)), to_robot(pose, (1.0, 0.0)));
        let e = tracking_error(&RowLine::new(a, m(b)).unwrap()).unwrap();
        prop_assert!((e.y.get() - lateral).abs() < 1e-9);
        prop_assert!((e.angular_deviation.get() - psi).abs() < 1e-9);
        // Mirror: a row seen on the other side gives the opposite error.
        let mirrored = tracking_error(&RowLine::new(-a, m(-b)).unwrap()).unwrap();
        prop_assert!((mirrored.y.get() + lateral).abs() < 1e-9);
    }

    //= spec/pierre2022.md#fur-two-rows-error-to-the-middle-of-two-rows
    //= type=test
    //# With two rows, the tracking error MUST be the mean of the errors to the
    //# left and right lines: y = (y_l + y_r)/2 and θ̃ = (θ̃_l + θ̃_r)/2.
    #[test]
    fn two_parallel_rows_give_the_error_to_their_centre_line(
        along in -10.0_f64..10.0,
        lateral in -1.0_f64..1.0,
        psi in -1.0_f64..1.0,
        half_spacing in 0.2_f64..0.6,
    ) {
        let pose = (along, lateral, psi);
        let line = |y: f64| {
            let (a, b) = line_through(to_robot(pose, (0.0, y)), to_robot(pose, (1.0, y)));
            RowLine::new(a, m(b)).unwrap()
        };
        let e = mean_tracking_error(&line(half_spacing), &line(-half_spacing)).unwrap();
        prop_assert!((e.y.get() - lateral).abs() < 1e-9);
        prop_assert!((e.angular_deviation.get() - psi).abs() < 1e-9);
    }
}

//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# The row line MUST be the (a, b) that minimises
//# Σ (a p_x + b − p_y)² + Λ (a − tan φ)² over the row's accumulated points,
//# with φ the first-line heading read in the current robot frame,
//# Λ = n max(E² − D², 0) / 12, n the number of points, D their extent along x
//# and E the larger of the minimum extent and 2 m.
#[test]
fn first_lines_lean_on_the_heading_until_the_points_spread() {
    let rad = |v: f64| Radians::new(v).unwrap();
    // Five points on one plant 3.4 m ahead, 0.66 m left: the line through
    // their mean along the heading φ, whatever the points' own slope.
    let plant = pts(&[
        (3.40, 0.66),
        (3.41, 0.67),
        (3.39, 0.65),
        (3.40, 0.665),
        (3.41, 0.655),
    ]);
    for phi in [0.0, 0.05, -0.1] {
        let line = fit_row_line_toward(plant.iter(), rad(phi), m(0.3)).unwrap();
        // Λ = 5 (0.09 − 0.0004) / 12 ≈ 0.037 against Σ(x − x̄)² = 0.0004: the
        // heading carries 99 % of the slope.
        assert!(
            (line.slope() - phi.tan()).abs() < 0.02 * (1.0 + phi.tan().abs()),
            "{phi}: {}",
            line.slope()
        );
        let mean = (3.402, 0.66);
        assert!((line.y_at(mean.0).unwrap() - mean.1).abs() < 1e-9);
    }
    // The minimiser by hand: a = (Sxy + Λ tan φ) / (Sxx + Λ), b = ȳ − a x̄.
    let p = pts(&[(3.0, 0.5), (3.1, 0.52), (3.2, 0.5), (3.25, 0.55)]);
    let (n, e, phi) = (4.0, 0.6, 0.02_f64);
    let xm = (3.0 + 3.1 + 3.2 + 3.25) / n;
    let ym = (0.5 + 0.52 + 0.5 + 0.55) / n;
    let sxx: f64 = p.iter().map(|q| (q.x() - xm).powi(2)).sum();
    let sxy: f64 = p.iter().map(|q| (q.x() - xm) * (q.y() - ym)).sum();
    let lambda = n * (e * e - 0.25_f64 * 0.25) / 12.0;
    let a = (sxy + lambda * phi.tan()) / (sxx + lambda);
    let line = fit_row_line_toward(p.iter(), rad(phi), m(e)).unwrap();
    assert!((line.slope() - a).abs() < 1e-12);
    assert!((line.intercept().get() - (ym - a * xm)).abs() < 1e-12);
    // Points spanning E or more: eq. 15's least-squares line, exactly.
    let spread = pts(&[(2.0, 0.1), (2.5, 0.15), (3.0, 0.18), (3.4, 0.26)]);
    for e in [0.0, 0.3, 1.4] {
        let toward = fit_row_line_toward(spread.iter(), rad(0.3), m(e)).unwrap();
        let plain = fit_row_line(spread.iter()).unwrap();
        assert_eq!(toward, plain, "E = {e}");
    }
}

//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# A fit over no point, or whose direction φ is π/4 or more from the robot's
//# current heading, MUST be refused with an error naming FUR-FIRST-LINE.
#[test]
fn first_lines_need_a_point_and_a_heading_within_a_quarter_turn() {
    let rad = |v: f64| Radians::new(v).unwrap();
    let none: Vec<Point2<Robot>> = Vec::new();
    assert_eq!(
        fit_row_line_toward(none.iter(), rad(0.0), m(0.3))
            .unwrap_err()
            .requirement,
        "FUR-FIRST-LINE"
    );
    let one = pts(&[(3.0, 0.4)]);
    for phi in [FIRST_LINE_MAX_TURN, -FIRST_LINE_MAX_TURN, 1.0, -3.0] {
        assert_eq!(
            fit_row_line_toward(one.iter(), rad(phi), m(0.3))
                .unwrap_err()
                .requirement,
            "FUR-FIRST-LINE"
        );
    }
    // Just inside the quarter turn, one point is enough: the line through it.
    let line = fit_row_line_toward(one.iter(), rad(0.7), m(0.3)).unwrap();
    assert!((line.y_at(3.0).unwrap() - 0.4).abs() < 1e-12);
    assert!((line.slope() - 0.7_f64.tan()).abs() < 1e-12);
}

#[test]
fn the_newest_heading_and_the_recent_turn() {
    let mut acc = Accumulator::<8>::new(3, m(100.0)).unwrap();
    let odom = |x: f64, h: f64| Pose2::<Odom>::new(x, 0.0, h).unwrap();
    assert!(acc.newest_heading().is_none());
    assert!(acc.recent_turn(1).is_none());
    let s = Selected::One(Point2::<Robot>::new(3.0, 0.2).unwrap());
    acc.push(&s, &odom(0.0, 3.1)).unwrap();
    assert!(acc.recent_turn(2).is_none());
    assert!(acc.recent_turn(0).is_none());
    acc.push(&s, &odom(0.1, -3.1)).unwrap();
    assert_eq!(acc.newest_heading().unwrap().get(), -3.1);
    // −3.1 − 3.1 wraps to 2π − 6.2; one selection has turned by nothing.
    let t = acc.recent_turn(2).unwrap().get();
    assert!((t - (core::f64::consts::TAU - 6.2)).abs() < 1e-12, "{t}");
    assert_eq!(acc.recent_turn(1).unwrap().get(), 0.0);
    // The oldest dropped at capacity: the turn over the last three.
    acc.push(&s, &odom(0.2, 0.0)).unwrap();
    acc.push(&s, &odom(0.3, 0.25)).unwrap();
    let t = acc.recent_turn(3).unwrap().get();
    assert!(
        (t - (0.25 + 3.1 - core::f64::consts::TAU)).abs() < 1e-12,
        "{t}"
    );
    assert!(acc.recent_turn(4).is_none());
}
