//! The parabola fitted to the chain (Pierre 2022, eqs. 8-10; EDGE-PARABOLA)
//! and the robot's errors to the line it follows at the desired lateral
//! distance (eq. 11 as corrected; EDGE-ERRORS, EDGE-OFFSET).

use super::config::Side;
use crate::error::Precondition;
use crate::geometry::fit::{fit_line, fit_parabola, ParabolaFit};
use crate::geometry::frame::{Point2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, Radians};

/// The tracking error of the robot, at abscissa `x_r` of the robot frame
/// (0: the controlled point), to the line it must follow: the parabola's
/// tangent at `x_r` shifted by the desired lateral distance `offset`
/// towards the robot (eq. 11 as corrected; EDGE-ERRORS, EDGE-OFFSET).
///
/// With `y_e = a x_r² + b x_r + c`, `φ = arctan(2 a x_r + b)` and `s = ±1`
/// for a left or right edge: `y = s·D − y_e cos φ` (positive when the
/// robot is left of the line) and `θ̃ = −φ` (robot heading minus line
/// heading). Curvature is reported as zero (the laws get a straight line).
/// Errors with `LIB-FINITE` if the result overflows.
//= spec/pierre2022.md#edge-errors-lateral-and-angular-errors-at-the-robot
//# The angular error MUST be θ̃ = −arctan(2 a x_r + b), the robot's heading
//# minus the heading of the parabola's tangent at x_r.
//= spec/pierre2022.md#edge-offset-desired-lateral-distance
//# The lateral error MUST be y = s·D − (a x_r² + b x_r + c) cos φ with
//# φ = arctan(2 a x_r + b), s = +1 for an edge on the left and −1 on the
//# right, so that y > 0 when the robot is left of the line it follows.
pub fn tracking_error(
    parabola: &ParabolaFit,
    side: Side,
    offset: Meters,
    x_r: f64,
) -> Result<TrackingError, Precondition> {
    let edge_y = parabola.value_at(x_r)?;
    let phi = libm::atan(parabola.slope_at(x_r)?);
    let y = side.sign() * offset.get() - edge_y * libm::cos(phi);
    Ok(TrackingError::to_straight_line(
        Meters::new(y)?,
        Radians::new(-phi)?,
    ))
}

/// Least-squares parabola through the chain points, eqs. 8-10:
/// `[a b c]ᵀ = (XᵀX)⁻¹ XᵀY`, solved by the library's shared fit
/// ([`fit_parabola`], `spec/geometry.md` FIT-PARABOLA: centred and scaled
/// abscissa, condition-checked normal equations).
///
/// Errors with `FIT-DEGENERATE` for fewer than 3 points or fewer than 3
/// distinct abscissae, and with `LIB-FINITE` on overflow.
//= spec/pierre2022.md#edge-parabola-least-squares-parabola-of-the-chain
//# The parabola y = a x² + b x + c MUST be the least-squares fit of the
//# chain points, [a b c]ᵀ = (XᵀX)⁻¹ XᵀY with rows (p_x², p_x, 1) of X.
//= spec/pierre2022.md#edge-parabola-least-squares-parabola-of-the-chain
//# Fewer than 3 points or a singular normal matrix MUST give an error, not a
//# parabola.
pub(super) fn fit_chain_parabola(points: &[Point2<Robot>]) -> Result<ParabolaFit, Precondition> {
    fit_parabola(points.iter())
}

/// The chain read as its least-squares straight line y = b x + c
/// (EDGE-STRAIGHT): the parabola with a = 0, so that its errors, its
/// residual and the line held between scans are those of that line
/// ([`fit_line`], `spec/geometry.md` FIT-LINE).
///
/// Errors with `FIT-DEGENERATE` for fewer than 2 points or a single
/// abscissa, and with `LIB-FINITE` on overflow.
//= spec/pierre2022.md#edge-straight-the-chain-read-as-a-straight-line
//# When the straight reading is on, a fitted chain MUST be read as the
//# parabola with a = 0 whose b and c are those of the least-squares
//# straight line y = b x + c through the chain points, for its errors
//# (EDGE-ERRORS, EDGE-OFFSET), its residual (EDGE-QUALITY) and the line
//# held between scans.
pub(super) fn fit_chain_line(points: &[Point2<Robot>]) -> Result<ParabolaFit, Precondition> {
    let line = fit_line(points.iter())?;
    Ok(ParabolaFit {
        a: 0.0,
        b: line.a,
        c: line.b,
    })
}
