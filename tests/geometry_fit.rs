//! Least-squares fits and residuals (`spec/geometry.md`, FIT-*).
//!
//! Expected values come from the normal equations solved by hand, from exact
//! data (coefficients recovered), from optimality (no nearby coefficients do
//! better: an oracle independent of the solver) and from "any f64 gives a
//! value or an error".
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::arithmetic_side_effects,
    clippy::as_conversions,
    clippy::float_cmp,
    // `&points` is the call a user writes; the fits also take arrays by value.
    clippy::needless_borrows_for_generic_args
)]

use fieldguide::geometry::fit::{fit_line, fit_parabola, LineFit, ParabolaFit};
use fieldguide::{Odom, Point2, Robot, Sensor, World};
use proptest::prelude::*;

fn rp(x: f64, y: f64) -> Point2<Robot> {
    Point2::new(x, y).unwrap()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

fn sse_line(f: &LineFit, pts: &[Point2<Robot>]) -> f64 {
    pts.iter()
        .map(|p| (p.y() - f.a * p.x() - f.b).powi(2))
        .sum()
}

fn sse_parabola(f: &ParabolaFit, pts: &[Point2<Robot>]) -> f64 {
    pts.iter()
        .map(|p| (p.y() - f.a * p.x() * p.x() - f.b * p.x() - f.c).powi(2))
        .sum()
}

//= spec/geometry.md#fit-line-least-squares-line
//= type=test
//# `fit_line` MUST return the coefficients (a, b) that minimise
//# Σ (p_y − a p_x − b)² over the given points.
#[test]
fn line_by_hand() {
    // Exact: y = 2 x + 1.
    let f = fit_line(&[rp(0.0, 1.0), rp(1.0, 3.0), rp(2.0, 5.0)]).unwrap();
    assert!(close(f.a, 2.0, 1e-14) && close(f.b, 1.0, 1e-14));
    // Not exact: (0, 0), (1, 1), (2, 0): x̄ = 1, ȳ = 1/3,
    // a = Σ(x − x̄)(y − ȳ) / Σ(x − x̄)² = (1/3 − 1/3) / 2 = 0, b = 1/3.
    let pts = [rp(0.0, 0.0), rp(1.0, 1.0), rp(2.0, 0.0)];
    let f = fit_line(&pts).unwrap();
    assert!(f.a.abs() < 1e-15 && close(f.b, 1.0 / 3.0, 1e-15));
    // (0, 0), (1, 1), (3, 2): x̄ = 4/3, ȳ = 1, Sxx = 16/9 + 1/9 + 25/9 = 42/9,
    // Sxy = 4/3 + 0 + 5/3 = 3, a = 27/42 = 9/14, b = 1 − (9/14)(4/3) = 1/7.
    let f = fit_line(&[rp(0.0, 0.0), rp(1.0, 1.0), rp(3.0, 2.0)]).unwrap();
    assert!(close(f.a, 9.0 / 14.0, 1e-14) && close(f.b, 1.0 / 7.0, 1e-14));
    assert!(close(
        f.value_at(3.0).unwrap(),
        27.0 / 14.0 + 1.0 / 7.0,
        1e-14
    ));
}

//= spec/geometry.md#fit-parabola-least-squares-parabola
//= type=test
//# `fit_parabola` MUST return the coefficients (a, b, c) that minimise
//# Σ (p_y − a p_x² − b p_x − c)² over the given points.
#[test]
fn parabola_by_hand() {
    // x = −2..2, y = (4, 1, 1, 1, 4). Normal equations (eq. 9):
    // Σx⁴ = 34, Σx³ = 0, Σx² = 10, Σx = 0, n = 5; Σx²y = 34, Σxy = 0, Σy = 11:
    // 34 a + 10 c = 34, 10 b = 0, 10 a + 5 c = 11 ⇒ a = 6/7, b = 0, c = 17/35.
    let pts = [
        rp(-2.0, 4.0),
        rp(-1.0, 1.0),
        rp(0.0, 1.0),
        rp(1.0, 1.0),
        rp(2.0, 4.0),
    ];
    let f = fit_parabola(&pts).unwrap();
    assert!(close(f.a, 6.0 / 7.0, 1e-14), "{f:?}");
    assert!(f.b.abs() < 1e-14);
    assert!(close(f.c, 17.0 / 35.0, 1e-14));
    // Exact data: y = 0.5 x² − 3 x + 2 at x = 1, 2, 4, 7.
    let exact: Vec<_> = [1.0, 2.0, 4.0, 7.0]
        .iter()
        .map(|&x| rp(x, 0.5 * x * x - 3.0 * x + 2.0))
        .collect();
    let f = fit_parabola(&exact).unwrap();
    assert!(close(f.a, 0.5, 1e-13) && close(f.b, -3.0, 1e-13) && close(f.c, 2.0, 1e-13));
    assert!(close(f.value_at(3.0).unwrap(), -2.5, 1e-13));
    // Slope 2 a x + b (eq. 11 as corrected): at x = 3, 0.
    assert!(f.slope_at(3.0).unwrap().abs() < 1e-12);
    assert!(close(f.slope_at(1.0).unwrap(), -2.0, 1e-12));
}

//= spec/geometry.md#fit-residual-mean-squared-residual
//= type=test
//# The mean squared residual MUST be (1/n) Σ (p_y − f(p_x))² over the n given
//# points, where f is the fitted line or parabola.
#[test]
fn mean_squared_residual_by_hand() {
    // Line (0, 0), (1, 1), (2, 0): y = 1/3, residuals −1/3, 2/3, −1/3: mean of squares 2/9.
    let pts = [rp(0.0, 0.0), rp(1.0, 1.0), rp(2.0, 0.0)];
    let f = fit_line(&pts).unwrap();
    assert!(close(
        f.mean_squared_residual(&pts).unwrap(),
        2.0 / 9.0,
        1e-14
    ));
    assert!(close(f.residual(pts[1]).unwrap(), 2.0 / 3.0, 1e-14));
    // Parabola above: residuals 3/35 (x = ±2), −12/35 (x = ±1), 18/35 (x = 0):
    // (2·9 + 2·144 + 324) / (35² · 5) = 18/175.
    let pts = [
        rp(-2.0, 4.0),
        rp(-1.0, 1.0),
        rp(0.0, 1.0),
        rp(1.0, 1.0),
        rp(2.0, 4.0),
    ];
    let f = fit_parabola(&pts).unwrap();
    assert!(close(
        f.mean_squared_residual(&pts).unwrap(),
        18.0 / 175.0,
        1e-14
    ));
    assert!(close(f.residual(pts[2]).unwrap(), 18.0 / 35.0, 1e-14));
    // Residuals can be taken over other points than the fitted ones, from an iterator.
    let other = (0..4).map(|i| rp(f64::from(i), 0.0));
    let expected = (0..4)
        .map(|i| {
            let x = f64::from(i);
            (6.0 / 7.0 * x * x + 17.0 / 35.0).powi(2)
        })
        .sum::<f64>()
        / 4.0;
    assert!(close(
        f.mean_squared_residual(other).unwrap(),
        expected,
        1e-13
    ));
}

//= spec/geometry.md#fit-residual-mean-squared-residual
//= type=test
//# The mean squared residual of no points MUST be the `FIT-RESIDUAL` error.
#[test]
fn residual_of_no_points_is_an_error() {
    let none: [Point2<Robot>; 0] = [];
    let l = LineFit { a: 1.0, b: 0.0 };
    let p = ParabolaFit {
        a: 1.0,
        b: 0.0,
        c: 0.0,
    };
    assert_eq!(
        l.mean_squared_residual(&none).unwrap_err().requirement,
        "FIT-RESIDUAL"
    );
    assert_eq!(
        p.mean_squared_residual(&none).unwrap_err().requirement,
        "FIT-RESIDUAL"
    );
    // Overflow is an error too, not an infinity.
    let huge = [rp(1e200, 0.0)];
    assert_eq!(
        p.mean_squared_residual(&huge).unwrap_err().requirement,
        "LIB-FINITE"
    );
    assert_eq!(p.value_at(1e200).unwrap_err().requirement, "LIB-FINITE");
}

//= spec/geometry.md#fit-degenerate-degenerate-point-sets
//= type=test
//# A fit MUST return the `FIT-DEGENERATE` error when it is given fewer points
//# than it has coefficients (2 for a line, 3 for a parabola), or when the
//# spread of x, max |x − x̄|, is below 1e−12 · max(1, |x̄|).
#[test]
fn too_few_points_or_no_x_spread_are_refused() {
    let empty: [Point2<Robot>; 0] = [];
    for pts in [&empty[..], &[rp(1.0, 2.0)][..]] {
        assert_eq!(fit_line(pts).unwrap_err().requirement, "FIT-DEGENERATE");
    }
    for pts in [
        &empty[..],
        &[rp(1.0, 2.0)][..],
        &[rp(1.0, 2.0), rp(2.0, 1.0)][..],
    ] {
        assert_eq!(fit_parabola(pts).unwrap_err().requirement, "FIT-DEGENERATE");
    }
    // All the same x (a vertical line): no function y(x) fits.
    let vertical = [rp(3.0, 0.0), rp(3.0, 1.0), rp(3.0, 5.0), rp(3.0, -2.0)];
    assert_eq!(
        fit_line(&vertical).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
    assert_eq!(
        fit_parabola(&vertical).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
    // Spread below 1e-12 relative to |x̄| = 1e6.
    let tiny = [rp(1e6, 0.0), rp(1e6 + 1e-7, 1.0)];
    assert_eq!(fit_line(&tiny).unwrap_err().requirement, "FIT-DEGENERATE");
    // Just above: accepted.
    let small = [rp(0.0, 0.0), rp(1e-9, 1e-9)];
    let f = fit_line(&small).unwrap();
    assert!(close(f.a, 1.0, 1e-6));
}

//= spec/geometry.md#fit-degenerate-degenerate-point-sets
//= type=test
//# `fit_parabola` MUST return the `FIT-DEGENERATE` error when the normal
//# matrix of the centred and scaled problem is singular or its 1-norm
//# condition number exceeds `MAX_CONDITION` (1e10).
#[test]
fn parabola_through_two_distinct_x_is_refused() {
    // Many points, only two distinct x: the normal matrix is singular.
    let two_x = [
        rp(0.0, 0.0),
        rp(0.0, 1.0),
        rp(2.0, 1.0),
        rp(2.0, 3.0),
        rp(0.0, 0.5),
    ];
    assert_eq!(
        fit_parabola(&two_x).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
    // The line through the same points is fine.
    assert!(fit_line(&two_x).is_ok());
    // A third x within 1e-7 of another: ill-conditioned, refused.
    let near = [rp(0.0, 0.0), rp(1e-7, 0.0), rp(2.0, 1.0), rp(2.0, 3.0)];
    assert_eq!(
        fit_parabola(&near).unwrap_err().requirement,
        "FIT-DEGENERATE"
    );
    // Well separated: accepted.
    let ok = [rp(0.0, 0.0), rp(1.0, 0.0), rp(2.0, 1.0), rp(2.0, 3.0)];
    assert!(fit_parabola(&ok).is_ok());
}

/// The fits accept any frame and any cloneable source of points or references.
#[test]
fn any_frame_and_any_iterable() {
    let xs = [0.5, 1.0, 2.0, 3.5, 5.0];
    let world: Vec<Point2<World>> = xs
        .iter()
        .map(|&x| Point2::new(x, 0.1 * x * x - x).unwrap())
        .collect();
    let mut odom: heapless::Vec<Point2<Odom>, 8> = heapless::Vec::new();
    for &x in &xs {
        odom.push(Point2::new(x, 0.1 * x * x - x).unwrap()).unwrap();
    }
    let a = fit_parabola(&world).unwrap();
    let b = fit_parabola(odom.iter()).unwrap();
    let c = fit_parabola(
        xs.iter()
            .map(|&x| Point2::<Sensor>::new(x, 0.1 * x * x - x).unwrap()),
    )
    .unwrap();
    assert_eq!(a, b);
    assert_eq!(a, c);
    assert!(close(a.a, 0.1, 1e-13) && close(a.b, -1.0, 1e-13) && a.c.abs() < 1e-12);
    let l = fit_line(odom.iter().copied()).unwrap();
    assert!(l.a.is_finite() && l.b.is_finite());
}

proptest! {
    /// Exact data: the line's coefficients come back.
    //= spec/geometry.md#fit-line-least-squares-line
    //= type=test
    //# `fit_line` MUST return the coefficients (a, b) that minimise
    //# Σ (p_y − a p_x − b)² over the given points.
    #[test]
    fn line_recovers_exact_coefficients(
        a in -10.0..10.0_f64, b in -10.0..10.0_f64, shift in -1e3..1e3_f64,
        xs in prop::collection::vec(-20.0..20.0_f64, 2..60),
    ) {
        let xs: Vec<f64> = xs.iter().map(|x| x + shift).collect();
        let spread = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - xs.iter().cloned().fold(f64::INFINITY, f64::min);
        prop_assume!(spread > 1e-3);
        let pts: Vec<_> = xs.iter().map(|&x| rp(x, a * x + b)).collect();
        let f = fit_line(&pts).unwrap();
        // Conditioning: relative error grows with |x̄| / spread.
        let tol = 1e-12 * (1.0 + shift.abs()) / spread.min(1.0);
        prop_assert!(close(f.a, a, tol), "a {} vs {a}", f.a);
        prop_assert!((f.b - b).abs() < tol * (1.0 + a.abs()) * (1.0 + shift.abs()), "b {} vs {b}", f.b);
        prop_assert!(f.mean_squared_residual(&pts).unwrap() < 1e-18 * (1.0 + shift * shift) * (1.0 + a * a) / spread.min(1.0).powi(2));
    }

    /// Exact data: the parabola's coefficients come back.
    //= spec/geometry.md#fit-parabola-least-squares-parabola
    //= type=test
    //# `fit_parabola` MUST return the coefficients (a, b, c) that minimise
    //# Σ (p_y − a p_x² − b p_x − c)² over the given points.
    #[test]
    fn parabola_recovers_exact_coefficients(
        a in -2.0..2.0_f64, b in -5.0..5.0_f64, c in -5.0..5.0_f64,
        xs in prop::collection::vec(-10.0..10.0_f64, 3..60),
    ) {
        let mut sorted = xs.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup_by(|p, q| (*p - *q).abs() < 0.05);
        prop_assume!(sorted.len() >= 3);
        let pts: Vec<_> = xs.iter().map(|&x| rp(x, a * x * x + b * x + c)).collect();
        let f = fit_parabola(&pts).unwrap();
        prop_assert!((f.a - a).abs() < 1e-7, "{f:?} vs {a} {b} {c}");
        prop_assert!((f.b - b).abs() < 1e-6, "{f:?} vs {a} {b} {c}");
        prop_assert!((f.c - c).abs() < 1e-6, "{f:?} vs {a} {b} {c}");
    }

    /// Noisy data: no nearby coefficients give a smaller sum of squares
    /// (optimality, checked without the solver).
    //= spec/geometry.md#fit-parabola-least-squares-parabola
    //= type=test
    //# `fit_parabola` MUST return the coefficients (a, b, c) that minimise
    //# Σ (p_y − a p_x² − b p_x − c)² over the given points.
    //= spec/geometry.md#fit-line-least-squares-line
    //= type=test
    //# `fit_line` MUST return the coefficients (a, b) that minimise
    //# Σ (p_y − a p_x − b)² over the given points.
    #[test]
    fn fits_are_least_squares_optimal(
        pts in prop::collection::vec((0.0..10.0_f64, -3.0..3.0_f64), 4..40),
        da in -1e-3..1e-3_f64, db in -1e-3..1e-3_f64, dc in -1e-3..1e-3_f64,
    ) {
        let pts: Vec<_> = pts.iter().map(|&(x, y)| rp(x, y)).collect();
        if let Ok(f) = fit_parabola(&pts) {
            let best = sse_parabola(&f, &pts);
            let other = ParabolaFit { a: f.a + da, b: f.b + db, c: f.c + dc };
            prop_assert!(best <= sse_parabola(&other, &pts) + 1e-9 * (1.0 + best));
            let n = pts.len() as f64;
            prop_assert!(close(f.mean_squared_residual(&pts).unwrap(), best / n, 1e-12));
        }
        if let Ok(f) = fit_line(&pts) {
            let best = sse_line(&f, &pts);
            let other = LineFit { a: f.a + da, b: f.b + db };
            prop_assert!(best <= sse_line(&other, &pts) + 1e-9 * (1.0 + best));
        }
    }

    /// Any f64 coordinates (NaN and infinities cannot be points): a finite
    /// value or an error, never a panic.
    #[test]
    fn any_input_gives_a_value_or_an_error(
        raw in prop::collection::vec((any::<f64>(), any::<f64>()), 0..10),
        x in any::<f64>(),
    ) {
        let pts: Vec<_> = raw.iter().filter_map(|&(x, y)| Point2::<Robot>::new(x, y).ok()).collect();
        match fit_line(&pts) {
            Ok(f) => {
                prop_assert!(f.a.is_finite() && f.b.is_finite());
                if let Ok(v) = f.mean_squared_residual(&pts) { prop_assert!(v.is_finite() && v >= 0.0); }
                if let Ok(v) = f.value_at(x) { prop_assert!(v.is_finite()); }
            }
            Err(e) => prop_assert!(["FIT-DEGENERATE", "LIB-FINITE"].contains(&e.requirement)),
        }
        match fit_parabola(&pts) {
            Ok(f) => {
                prop_assert!(f.a.is_finite() && f.b.is_finite() && f.c.is_finite());
                if let Ok(v) = f.mean_squared_residual(&pts) { prop_assert!(v.is_finite() && v >= 0.0); }
                if let Ok(v) = f.slope_at(x) { prop_assert!(v.is_finite()); }
            }
            Err(e) => prop_assert!(["FIT-DEGENERATE", "LIB-FINITE"].contains(&e.requirement)),
        }
    }

    /// Huge coordinates: a finite value or an error.
    #[test]
    fn huge_inputs_give_a_value_or_an_error(
        scale in prop::sample::select(vec![1e100, 1e150, 1e200, 1e300, f64::MAX]),
        raw in prop::collection::vec((-1.0..1.0_f64, -1.0..1.0_f64), 3..8),
    ) {
        let pts: Vec<_> = raw.iter().map(|&(x, y)| rp(x * scale, y * scale)).collect();
        if let Ok(f) = fit_line(&pts) { prop_assert!(f.a.is_finite() && f.b.is_finite()); }
        if let Ok(f) = fit_parabola(&pts) {
            prop_assert!(f.a.is_finite() && f.b.is_finite() && f.c.is_finite());
        }
    }
}

//= spec/geometry.md#fit-weights-weighted-least-squares-line
//= type=test
//# `fit_line_weighted` MUST return the coefficients (a, b) that minimise
//# Σ w (p_y − a p_x − b)² over the given points and weights, and MUST
//# return the `FIT-WEIGHTS` error when a weight is not finite and > 0.
#[test]
fn weighted_line_by_hand() {
    use fieldguide::geometry::fit::fit_line_weighted;
    // Weighted normal equations solved by hand: points (0, 0), (1, 1), (2, 0)
    // with weights 1, 2, 1 give the weighted means x̄ = 1, ȳ = 0.5 and
    // Σ w (x − x̄)(y − ȳ) = 0: the line y = 0.5.
    let pts = [rp(0.0, 0.0), rp(1.0, 1.0), rp(2.0, 0.0)];
    let f = fit_line_weighted(pts.iter().zip([1.0, 2.0, 1.0])).unwrap();
    assert!(close(f.a, 0.0, 1e-12) && close(f.b, 0.5, 1e-12), "{f:?}");
    // Heavier weight on the last point tilts the line towards it: the
    // weighted SSE is below that of the unweighted fit, by the definition.
    let w = [1.0, 1.0, 10.0];
    let weighted = fit_line_weighted(pts.iter().zip(w)).unwrap();
    let plain = fit_line(&pts).unwrap();
    let wsse = |f: &LineFit| {
        pts.iter()
            .zip(w)
            .map(|(p, w)| w * (p.y() - f.a * p.x() - f.b).powi(2))
            .sum::<f64>()
    };
    assert!(wsse(&weighted) < wsse(&plain));
    // Unit weights are `fit_line`, bit for bit.
    let unit = fit_line_weighted(pts.iter().zip([1.0; 3])).unwrap();
    assert_eq!(
        (unit.a.to_bits(), unit.b.to_bits()),
        (plain.a.to_bits(), plain.b.to_bits())
    );
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = fit_line_weighted(pts.iter().zip([1.0, bad, 1.0])).unwrap_err();
        assert_eq!(err.requirement, "FIT-WEIGHTS");
    }
}

proptest! {
    //= spec/geometry.md#fit-weights-weighted-least-squares-line
    //= type=test
    //# `fit_line_weighted` MUST return the coefficients (a, b) that minimise
    //# Σ w (p_y − a p_x − b)² over the given points and weights, and MUST
    //# return the `FIT-WEIGHTS` error when a weight is not finite and > 0.
    #[test]
    fn weighted_fit_minimises_the_weighted_sse(
        pts in prop::collection::vec((-10.0..10.0_f64, -10.0..10.0_f64, 0.01..100.0_f64), 3..30),
        da in -0.1..0.1_f64,
        db in -0.1..0.1_f64,
    ) {
        use fieldguide::geometry::fit::fit_line_weighted;
        let points: Vec<_> = pts.iter().map(|&(x, y, _)| rp(x, y)).collect();
        let weights: Vec<f64> = pts.iter().map(|p| p.2).collect();
        if let Ok(f) = fit_line_weighted(points.iter().zip(weights.iter().copied())) {
            let wsse = |a: f64, b: f64| {
                points.iter().zip(&weights).map(|(p, w)| w * (p.y() - a * p.x() - b).powi(2)).sum::<f64>()
            };
            let best = wsse(f.a, f.b);
            prop_assert!(best <= wsse(f.a + da, f.b + db) * (1.0 + 1e-9) + 1e-9);
        }
    }
}
