//! Row lines fitted to the accumulated points (eq. 15), the robot's error to
//! a line (eq. 16) and to the middle of two rows (eq. 20) (Pierre 2022,
//! sections 2.3.1-2.3.2; `spec/pierre2022.md` FUR-LINE, FUR-ERRORS,
//! FUR-TWO-ROWS).

use core::borrow::Borrow;

use crate::error::{finite, Precondition};
use crate::geometry::fit::fit_line;
use crate::geometry::frame::{Point2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, Radians};

/// The smallest variance of the points' x (m²) for which the slope of eq. 15
/// is taken as determined: (1 mm)².
pub const MIN_X_VARIANCE: f64 = 1.0e-6;

/// A row as the line `y = a x + b` of the robot frame (eq. 15).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowLine {
    slope: f64,
    intercept: Meters,
}

impl RowLine {
    /// The line `y = slope · x + intercept`. Errors with `LIB-FINITE` on a non-finite slope.
    pub fn new(slope: f64, intercept: Meters) -> Result<Self, Precondition> {
        Ok(Self {
            slope: finite(slope, "row line slope must be finite")?,
            intercept,
        })
    }

    /// a, dimensionless (dy/dx).
    #[must_use]
    pub const fn slope(&self) -> f64 {
        self.slope
    }

    /// b, the line's y at x = 0, m.
    #[must_use]
    pub const fn intercept(&self) -> Meters {
        self.intercept
    }

    /// The line's y at `x` m. Errors with `LIB-FINITE` when `x` is not finite
    /// or the value overflows.
    pub fn y_at(&self, x: f64) -> Result<f64, Precondition> {
        finite(
            self.slope * finite(x, "row line abscissa must be finite")? + self.intercept.get(),
            "row line value overflows",
        )
    }
}

/// The row line `a p_x + b = p_y` through `points` (eq. 15): the
/// least-squares line of the library's shared fit
/// ([`crate::geometry::fit::fit_line`], FIT-LINE), minimising the squared
/// residuals in y, as a [`RowLine`] of the robot frame.
///
/// The furrow adds its own precondition to the fit's: the points must spread
/// along x with a variance of at least [`MIN_X_VARIANCE`], since a slope from
/// points a millimetre apart, extrapolated metres back to the robot, would be
/// noise.
///
/// `points` is anything iterable twice (a slice, `heapless::Vec::iter()`)
/// yielding `Point2<Robot>` or `&Point2<Robot>`, metres. Errors with
/// `FUR-LINE` when fewer than two points are given or when the variance of
/// their x is below [`MIN_X_VARIANCE`]; otherwise the fit's own errors
/// (`FIT-DEGENERATE` only for points so far away, beyond 10⁹ m, that a
/// millimetre of spread is lost in rounding; `LIB-FINITE` on overflow).
//= spec/pierre2022.md#fur-line-row-line-by-least-squares
//# The row line MUST be the least-squares solution (a, b) of a p_x + b = p_y
//# over the accumulated points, minimising the squared residuals in y.
//= spec/pierre2022.md#fur-line-row-line-by-least-squares
//# A fit over fewer than two points, or over points whose x variance is below
//# (1 mm)², MUST be refused with an error naming FUR-LINE.
pub fn fit_row_line<I, P>(points: I) -> Result<RowLine, Precondition>
where
    I: IntoIterator<Item = P>,
    I::IntoIter: Clone,
    P: Borrow<Point2<Robot>>,
{
    let points = points.into_iter();
    check_x_spread(points.clone())?;
    let fit = fit_line(points)?;
    RowLine::new(fit.a, Meters::new(fit.b)?)
}

/// The largest angle, rad, between the first-line heading and the robot's
/// current one for which [`fit_row_line_toward`] still draws the rows toward
/// it: π/4.
pub const FIRST_LINE_MAX_TURN: f64 = core::f64::consts::FRAC_PI_4;

/// The largest turn of the robot, rad, over its last `min_points` kept
/// selections for which the detector takes its heading for a row's first line
/// (FUR-FIRST-LINE): 0.01 rad. A robot turning as it first sees the rows (path
/// tracking converging, after a turn) is not along them.
pub const FIRST_LINE_STRAIGHT: f64 = 0.01;

/// The extent along x, m, over which the detector's first line fades from the
/// heading to the points' own direction (FUR-FIRST-LINE), unless the minimum
/// extent is longer: 2 m. Bean plants 0.15 m apart spread the first points
/// over 0.3 m in five scans, and a slope from 0.3 m of points, extrapolated
/// 3 m back to O, is 0.1-0.2 m off there; over 1 m, the odometry's heading
/// drift, which turns the older points most, still put the lines at O
/// 0.06-0.09 m off (FUR-FIRST-LINE, "Reason (odometry drift)").
pub const FIRST_LINE_SPREAD: f64 = 2.0;

/// A row line whose direction is drawn toward the heading the robot had when
/// it first went straight beside the rows (FUR-FIRST-LINE): the (a, b) minimising
/// `Σ (a p_x + b − p_y)² + Λ (a − tan φ)²`, with φ = `direction` (that
/// heading in the current robot frame) and
/// `Λ = n max(E² − D², 0) / 12` for n points spanning D along x and
/// E = `spread`: the heading's weight, that of n points spread evenly over
/// E less the spread they have, vanishes once they span E.
///
/// At a plot's entry the scan meets each row's first plant metres ahead and
/// sees it over many scans before the next plants come into view: the
/// points' lateral position is known at once, their direction only once they
/// spread along the row. Points on one plant give a line along the heading of
/// the robot entering the rows (which path tracking keeps along the path)
/// through their mean; points spanning E, the least-squares line of eq. 15
/// ([`fit_row_line`]), whose errors it then returns.
/// Errors with
/// `FUR-FIRST-LINE` when there is no point or when `|direction|` is not below
/// [`FIRST_LINE_MAX_TURN`]; `LIB-FINITE` on overflow.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//# The row line MUST be the (a, b) that minimises
//# Σ (a p_x + b − p_y)² + Λ (a − tan φ)² over the row's accumulated points,
//# with φ the first-line heading read in the current robot frame,
//# Λ = n max(E² − D², 0) / 12, n the number of points, D their extent along x
//# and E the larger of the minimum extent and 2 m.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//# A fit over no point, or whose direction φ is π/4 or more from the robot's
//# current heading, MUST be refused with an error naming FUR-FIRST-LINE.
pub fn fit_row_line_toward<I, P>(
    points: I,
    direction: Radians,
    spread: Meters,
) -> Result<RowLine, Precondition>
where
    I: IntoIterator<Item = P>,
    I::IntoIter: Clone,
    P: Borrow<Point2<Robot>>,
{
    let phi = direction.get();
    // φ is finite by its type.
    if libm::fabs(phi) >= FIRST_LINE_MAX_TURN {
        return Err(Precondition::new(
            "FUR-FIRST-LINE",
            "the first-line heading is pi/4 or more from the robot's",
        ));
    }
    let points = points.into_iter();
    let (mut count, mut sx, mut sy) = (0.0_f64, 0.0_f64, 0.0_f64);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in points.clone() {
        let (x, y) = (p.borrow().x(), p.borrow().y());
        count += 1.0;
        sx += x;
        sy += y;
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if count < 1.0 {
        return Err(Precondition::new("FUR-FIRST-LINE", "no point"));
    }
    let (e, d) = (spread.get(), hi - lo);
    let prior = count * (e * e - d * d) / 12.0;
    if prior.is_nan() || prior <= 0.0 {
        return fit_row_line(points);
    }
    let (mx, my) = (sx / count, sy / count);
    let (mut sxx, mut sxy) = (0.0_f64, 0.0_f64);
    for p in points {
        let dx = p.borrow().x() - mx;
        sxx += dx * dx;
        sxy += dx * (p.borrow().y() - my);
    }
    let slope = finite(
        (sxy + prior * libm::tan(phi)) / (sxx + prior),
        "first line overflows",
    )?;
    let intercept = finite(my - slope * mx, "first line overflows")?;
    RowLine::new(slope, Meters::new(intercept)?)
}

/// FUR-LINE's precondition: at least two points whose x variance
/// `(1/n) Σ (x − x̄)²` is at least [`MIN_X_VARIANCE`].
fn check_x_spread<I, P>(points: I) -> Result<(), Precondition>
where
    I: Iterator<Item = P> + Clone,
    P: Borrow<Point2<Robot>>,
{
    let (mut count, mut sum) = (0.0_f64, 0.0_f64);
    for p in points.clone() {
        count += 1.0;
        sum += p.borrow().x();
    }
    if count < 2.0 {
        return Err(Precondition::new("FUR-LINE", "fewer than two points"));
    }
    let mean = sum / count;
    let spread = points.fold(0.0_f64, |acc, p| {
        let d = p.borrow().x() - mean;
        acc + d * d
    });
    let variance = spread / count;
    if variance.is_nan() || variance < MIN_X_VARIANCE {
        return Err(Precondition::new(
            "FUR-LINE",
            "the points do not spread along x: slope undetermined",
        ));
    }
    Ok(())
}

/// The robot's tracking error to a row line (eq. 16, in the library's signs).
///
/// The paper gives `y = b / sqrt(a² + 1)` and `θ̃ = arctan(a)`: the line's
/// offset and direction seen from the robot. The library's
/// [`TrackingError`] is the robot seen from the line (y > 0 when the robot is
/// left of the line, θ̃ = robot heading − line heading), so both change sign:
/// `y = −b / sqrt(a² + 1)`, `θ̃ = −arctan(a)`.
//= spec/pierre2022.md#fur-errors-tracking-error-to-a-row-line
//# The tracking error to the line y = a x + b of the robot frame MUST be
//# y = −b / sqrt(a² + 1) and θ̃ = −arctan(a).
pub fn tracking_error(line: &RowLine) -> Result<TrackingError, Precondition> {
    let a = line.slope();
    let y = -line.intercept().get() / libm::sqrt(a * a + 1.0);
    Ok(TrackingError::to_straight_line(
        Meters::new(y)?,
        Radians::new(-libm::atan(a))?,
    ))
}

/// The robot's tracking error to the middle of two rows (eq. 20): the mean of
/// the errors to the left and to the right line.
//= spec/pierre2022.md#fur-two-rows-error-to-the-middle-of-two-rows
//# With two rows, the tracking error MUST be the mean of the errors to the
//# left and right lines: y = (y_l + y_r)/2 and θ̃ = (θ̃_l + θ̃_r)/2.
pub fn mean_tracking_error(left: &RowLine, right: &RowLine) -> Result<TrackingError, Precondition> {
    let l = tracking_error(left)?;
    let r = tracking_error(right)?;
    // Both angles come from arctan, in (−π/2, π/2): their mean needs no wrapping.
    Ok(TrackingError::to_straight_line(
        Meters::new(0.5 * l.y.get() + 0.5 * r.y.get())?,
        Radians::new(0.5 * l.angular_deviation.get() + 0.5 * r.angular_deviation.get())?,
    ))
}
