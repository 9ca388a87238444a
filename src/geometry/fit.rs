//! Least-squares line and parabola fits (nalgebra), with their residuals.
//!
//! - [`fit_line`]: y = a x + b, the linear regression of Pierre 2022 eq. 15
//!   (furrow pursuing), `spec/geometry.md` FIT-LINE.
//! - [`fit_parabola`]: y = a x² + b x + c, the regression of eqs. 8–10 (edge
//!   following), FIT-PARABOLA.
//! - [`LineFit::mean_squared_residual`], [`ParabolaFit::mean_squared_residual`]:
//!   the mean of the squared residuals in y, the quantity that eq. 21 (as
//!   corrected in the errata) compares with σ_max², FIT-RESIDUAL.
//!
//! Points are given in any frame `F`; the fits are computed in two passes
//! (means, then centred and scaled sums) so the normal equations stay well
//! conditioned, and allocate nothing. Degenerate point sets are the
//! `FIT-DEGENERATE` error.

use core::borrow::Borrow;

use nalgebra::{Matrix3, Vector3};

use super::frame::{Frame, Point2};
use crate::error::{finite, Precondition};

/// Largest 1-norm condition number of the scaled normal matrix of a parabola fit
/// accepted by [`fit_parabola`] (FIT-DEGENERATE).
pub const MAX_CONDITION: f64 = 1e10;

/// Smallest spread of x, relative to max(1, |mean x|), that a fit accepts
/// (FIT-DEGENERATE): below it all points share the same x.
pub const MIN_RELATIVE_X_SPREAD: f64 = 1e-12;

/// The line y = a x + b (Pierre 2022, eq. 15), in the frame of the fitted points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineFit {
    /// Slope a (dimensionless: metres of y per metre of x).
    pub a: f64,
    /// Intercept b, metres: the value of y at x = 0.
    pub b: f64,
}

/// The parabola y = a x² + b x + c (Pierre 2022, eq. 8), in the frame of the fitted points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParabolaFit {
    /// Quadratic coefficient a, 1/m.
    pub a: f64,
    /// Linear coefficient b (dimensionless).
    pub b: f64,
    /// Constant c, metres: the value of y at x = 0.
    pub c: f64,
}

/// Weighted means and spread of the x and y coordinates of a point set
/// (first pass).
struct Moments {
    count: f64,
    mean_x: f64,
    mean_y: f64,
    /// Largest |x − mean x|.
    half_spread: f64,
}

/// First pass: count, weighted means and the spread of x. `FIT-WEIGHTS` on
/// a weight that is not finite and > 0, `LIB-FINITE` on overflow.
fn moments<F, I, P>(points: I) -> Result<Moments, Precondition>
where
    F: Frame,
    I: Iterator<Item = (P, f64)> + Clone,
    P: Borrow<Point2<F>>,
{
    let (mut count, mut weight) = (0.0_f64, 0.0_f64);
    let (mut sum_x, mut sum_y) = (0.0_f64, 0.0_f64);
    let (mut min_x, mut max_x) = (f64::INFINITY, f64::NEG_INFINITY);
    for (p, w) in points {
        let p = *p.borrow();
        if !(w.is_finite() && w > 0.0) {
            return Err(Precondition::new(
                "FIT-WEIGHTS",
                "a fit weight must be finite and > 0",
            ));
        }
        count += 1.0;
        weight += w;
        sum_x += w * p.x();
        sum_y += w * p.y();
        min_x = min_x.min(p.x());
        max_x = max_x.max(p.x());
    }
    if count < 1.0 {
        return Ok(Moments {
            count,
            mean_x: 0.0,
            mean_y: 0.0,
            half_spread: 0.0,
        });
    }
    let mean_x = finite(sum_x / weight, "mean x of the fitted points overflows")?;
    let mean_y = finite(sum_y / weight, "mean y of the fitted points overflows")?;
    let half_spread = finite(
        (max_x - mean_x).max(mean_x - min_x),
        "spread of x of the fitted points overflows",
    )?;
    Ok(Moments {
        count,
        mean_x,
        mean_y,
        half_spread,
    })
}

/// The moments of `points`, checked for a fit of `needed` coefficients
/// (`few`: the message when there are fewer points), and the points centred
/// and scaled, (u, v, w) = ((x − x̄)/h, y − ȳ, w) with u ∈ [−1, 1], which
/// keeps both fits well conditioned far from the origin.
fn centred<F, I, P>(
    points: I,
    needed: f64,
    few: &'static str,
) -> Result<(Moments, impl Iterator<Item = (f64, f64, f64)>), Precondition>
where
    F: Frame,
    I: IntoIterator<Item = (P, f64)>,
    I::IntoIter: Clone,
    P: Borrow<Point2<F>>,
{
    let points = points.into_iter();
    let m = moments(points.clone())?;
    check_spread(&m, needed, few)?;
    let (mean_x, mean_y, h) = (m.mean_x, m.mean_y, m.half_spread);
    let centred = points.map(move |(p, w)| {
        let p = *p.borrow();
        ((p.x() - mean_x) / h, p.y() - mean_y, w)
    });
    Ok((m, centred))
}

/// Checks the point count and the x spread shared by both fits.
//= spec/geometry.md#fit-degenerate-degenerate-point-sets
//# A fit MUST return the `FIT-DEGENERATE` error when it is given fewer points
//# than it has coefficients (2 for a line, 3 for a parabola), or when the
//# spread of x, max |x − x̄|, is below 1e−12 · max(1, |x̄|).
fn check_spread(m: &Moments, needed: f64, few: &'static str) -> Result<(), Precondition> {
    if m.count < needed {
        return Err(Precondition::new("FIT-DEGENERATE", few));
    }
    if m.half_spread < MIN_RELATIVE_X_SPREAD * m.mean_x.abs().max(1.0) {
        return Err(Precondition::new(
            "FIT-DEGENERATE",
            "all fitted points have the same x",
        ));
    }
    Ok(())
}

/// Least-squares line y = a x + b through `points` (Pierre 2022, eq. 15):
/// minimises Σ (p_y − a p_x − b)².
///
/// `points` is anything iterable twice (a slice, `heapless::Vec::iter()`,
/// a cloneable adapter) yielding `Point2<F>` or `&Point2<F>`, in any frame `F`,
/// metres. Errors: fewer than 2 points or all x equal (`FIT-DEGENERATE`),
/// overflow (`LIB-FINITE`).
//= spec/geometry.md#fit-line-least-squares-line
//# `fit_line` MUST return the coefficients (a, b) that minimise
//# Σ (p_y − a p_x − b)² over the given points.
pub fn fit_line<F, I, P>(points: I) -> Result<LineFit, Precondition>
where
    F: Frame,
    I: IntoIterator<Item = P>,
    I::IntoIter: Clone,
    P: Borrow<Point2<F>>,
{
    fit_line_weighted(points.into_iter().map(|p| (p, 1.0)))
}

/// Weighted least-squares line y = a x + b through `points`, each given with
/// its weight w > 0: minimises Σ w (p_y − a p_x − b)². With every weight 1 it
/// is [`fit_line`], bit for bit.
///
/// Errors: a weight that is not finite and > 0 (`FIT-WEIGHTS`); otherwise
/// those of [`fit_line`].
//= spec/geometry.md#fit-weights-weighted-least-squares-line
//# `fit_line_weighted` MUST return the coefficients (a, b) that minimise
//# Σ w (p_y − a p_x − b)² over the given points and weights, and MUST
//# return the `FIT-WEIGHTS` error when a weight is not finite and > 0.
pub fn fit_line_weighted<F, I, P>(points: I) -> Result<LineFit, Precondition>
where
    F: Frame,
    I: IntoIterator<Item = (P, f64)>,
    I::IntoIter: Clone,
    P: Borrow<Point2<F>>,
{
    let (m, centred) = centred(points, 2.0, "a line fit needs at least 2 points")?;
    let h = m.half_spread;
    // v = α u.
    let (mut suu, mut suv) = (0.0_f64, 0.0_f64);
    for (u, v, w) in centred {
        suu += w * u * u;
        suv += w * u * v;
    }
    if suu.is_nan() || suu <= 0.0 {
        return Err(Precondition::new(
            "FIT-DEGENERATE",
            "the weighted spread of x vanishes",
        ));
    }
    let alpha = suv / suu;
    let a = finite(alpha / h, "line slope overflows")?;
    let b = finite(m.mean_y - a * m.mean_x, "line intercept overflows")?;
    Ok(LineFit { a, b })
}

/// 1-norm of a 3×3 matrix: the largest column sum of absolute values.
fn norm1(m: &Matrix3<f64>) -> f64 {
    m.column_iter()
        .map(|c| c.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Least-squares parabola y = a x² + b x + c through `points` (Pierre 2022,
/// eqs. 8–10): minimises Σ (p_y − a p_x² − b p_x − c)², i.e. solves the normal
/// equations (XᵀX) [a b c]ᵀ = XᵀY of eq. 9, after centring and scaling x.
///
/// `points` as for [`fit_line`]. Errors: fewer than 3 points, all x equal,
/// a singular or ill-conditioned normal matrix, as with fewer than 3 distinct x
/// (`FIT-DEGENERATE`); overflow of a sum or a coefficient (`LIB-FINITE`).
//= spec/geometry.md#fit-parabola-least-squares-parabola
//# `fit_parabola` MUST return the coefficients (a, b, c) that minimise
//# Σ (p_y − a p_x² − b p_x − c)² over the given points.
//= spec/geometry.md#fit-degenerate-degenerate-point-sets
//# `fit_parabola` MUST return the `FIT-DEGENERATE` error when the normal
//# matrix of the centred and scaled problem is singular or its 1-norm
//# condition number exceeds `MAX_CONDITION` (1e10).
pub fn fit_parabola<F, I, P>(points: I) -> Result<ParabolaFit, Precondition>
where
    F: Frame,
    I: IntoIterator<Item = P>,
    I::IntoIter: Clone,
    P: Borrow<Point2<F>>,
{
    let (m, centred) = centred(
        points.into_iter().map(|p| (p, 1.0)),
        3.0,
        "a parabola fit needs at least 3 points",
    )?;
    let h = m.half_spread;
    // Basis (u², u, 1).
    let mut normal = Matrix3::<f64>::zeros();
    let mut rhs = Vector3::<f64>::zeros();
    for (u, v, _) in centred {
        let row = Vector3::new(u * u, u, 1.0);
        normal.ger(1.0, &row, &row, 1.0);
        rhs.axpy(v, &row, 1.0);
    }
    let degenerate = || {
        Precondition::new(
            "FIT-DEGENERATE",
            "parabola normal matrix is singular or ill-conditioned",
        )
    };
    if !normal.iter().chain(rhs.iter()).all(|x| x.is_finite()) {
        return Err(Precondition::new(
            "LIB-FINITE",
            "parabola normal equations overflow",
        ));
    }
    let inverse = normal.try_inverse().ok_or_else(degenerate)?;
    let condition = norm1(&normal) * norm1(&inverse);
    if condition.is_nan() || condition > MAX_CONDITION {
        return Err(degenerate());
    }
    let mut coef = Vector3::<f64>::zeros();
    coef.gemv(1.0, &inverse, &rhs, 0.0);
    let (alpha, beta, gamma) = (coef.x, coef.y, coef.z);
    // Back to x: v = α u² + β u + γ with u = (x − x̄)/h.
    let (xm, h2) = (m.mean_x, h * h);
    let a = alpha / h2;
    let b = beta / h - 2.0 * alpha * xm / h2;
    let c = m.mean_y + gamma - beta * xm / h + alpha * xm * xm / h2;
    Ok(ParabolaFit {
        a: finite(a, "parabola coefficient a overflows")?,
        b: finite(b, "parabola coefficient b overflows")?,
        c: finite(c, "parabola coefficient c overflows")?,
    })
}

/// Mean over `points` of the squared residual computed by `residual`.
fn mean_squared<F, I, P>(
    points: I,
    residual: impl Fn(Point2<F>) -> f64,
) -> Result<f64, Precondition>
where
    F: Frame,
    I: IntoIterator<Item = P>,
    P: Borrow<Point2<F>>,
{
    let (mut count, mut sum) = (0.0_f64, 0.0_f64);
    for p in points {
        let r = residual(*p.borrow());
        count += 1.0;
        sum += r * r;
    }
    if count < 1.0 {
        return Err(Precondition::new(
            "FIT-RESIDUAL",
            "mean squared residual of no points",
        ));
    }
    finite(sum / count, "mean squared residual overflows")
}

impl LineFit {
    /// a x + b at `x` (metres). `LIB-FINITE` on overflow.
    pub fn value_at(&self, x: f64) -> Result<f64, Precondition> {
        finite(self.a * x + self.b, "line value overflows")
    }

    /// The residual in y of `p`: p_y − (a p_x + b), metres. `LIB-FINITE` on overflow.
    pub fn residual<F: Frame>(&self, p: Point2<F>) -> Result<f64, Precondition> {
        finite(p.y() - (self.a * p.x() + self.b), "line residual overflows")
    }

    /// Mean of the squared residuals in y over `points`, m²:
    /// (1/n) Σ (p_y − (a p_x + b))². Errors: no points (`FIT-RESIDUAL`),
    /// overflow (`LIB-FINITE`).
    //= spec/geometry.md#fit-residual-mean-squared-residual
    //# The mean squared residual MUST be (1/n) Σ (p_y − f(p_x))² over the n given
    //# points, where f is the fitted line or parabola.
    //= spec/geometry.md#fit-residual-mean-squared-residual
    //# The mean squared residual of no points MUST be the `FIT-RESIDUAL` error.
    pub fn mean_squared_residual<F, I, P>(&self, points: I) -> Result<f64, Precondition>
    where
        F: Frame,
        I: IntoIterator<Item = P>,
        P: Borrow<Point2<F>>,
    {
        mean_squared(points, |p: Point2<F>| p.y() - (self.a * p.x() + self.b))
    }
}

impl ParabolaFit {
    /// a x² + b x + c at `x` (metres). `LIB-FINITE` on overflow.
    pub fn value_at(&self, x: f64) -> Result<f64, Precondition> {
        finite(
            self.a * x * x + self.b * x + self.c,
            "parabola value overflows",
        )
    }

    /// The slope dy/dx = 2 a x + b at `x` (Pierre 2022, eq. 11 as corrected in
    /// the errata). `LIB-FINITE` on overflow.
    pub fn slope_at(&self, x: f64) -> Result<f64, Precondition> {
        finite(2.0 * self.a * x + self.b, "parabola slope overflows")
    }

    /// The residual in y of `p`: p_y − (a p_x² + b p_x + c), metres. `LIB-FINITE` on overflow.
    pub fn residual<F: Frame>(&self, p: Point2<F>) -> Result<f64, Precondition> {
        finite(
            p.y() - (self.a * p.x() * p.x() + self.b * p.x() + self.c),
            "parabola residual overflows",
        )
    }

    /// Mean of the squared residuals in y over `points`, m²:
    /// (1/n) Σ (p_y − (a p_x² + b p_x + c))² (Pierre 2022, eq. 21 third line as
    /// corrected in the errata). Errors: no points (`FIT-RESIDUAL`), overflow
    /// (`LIB-FINITE`).
    //= spec/geometry.md#fit-residual-mean-squared-residual
    //# The mean squared residual MUST be (1/n) Σ (p_y − f(p_x))² over the n given
    //# points, where f is the fitted line or parabola.
    pub fn mean_squared_residual<F, I, P>(&self, points: I) -> Result<f64, Precondition>
    where
        F: Frame,
        I: IntoIterator<Item = P>,
        P: Borrow<Point2<F>>,
    {
        mean_squared(points, |p: Point2<F>| {
            p.y() - (self.a * p.x() * p.x() + self.b * p.x() + self.c)
        })
    }
}
