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
