//! The parabola fitted to the chain (Pierre 2022, eqs. 8-10; EDGE-PARABOLA)
//! and the robot's errors to the line it follows at the desired lateral
//! distance (eq. 11 as corrected; EDGE-ERRORS, EDGE-OFFSET).

use super::config::Side;
use crate::error::Precondition;
use crate::geometry::fit::{fit_parabola, ParabolaFit};
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

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::FRAC_PI_6;
    use nalgebra::{Matrix3, Vector3};

    fn pts(xy: &[(f64, f64)]) -> heapless::Vec<Point2<Robot>, 16> {
        xy.iter()
            .map(|&(x, y)| Point2::new(x, y).unwrap())
            .collect()
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
        let fit = fit_chain_parabola(&p).unwrap();
        assert!((fit.a - 0.3).abs() < 1e-12 && (fit.b + 0.2).abs() < 1e-12);
        assert!((fit.c - 1.7).abs() < 1e-12);
        // Noisy points: compare with eq. 9 computed literally.
        let xy = [
            (0.1, 1.0),
            (0.7, 1.3),
            (1.1, 1.1),
            (1.9, 1.6),
            (2.4, 1.5),
            (3.0, 2.1),
        ];
        let p = pts(&xy);
        let fit = fit_chain_parabola(&p).unwrap();
        let mut xtx = Matrix3::zeros();
        let mut xty = Vector3::zeros();
        for &(x, y) in &xy {
            let row = Vector3::new(x * x, x, 1.0);
            xtx += row * row.transpose();
            xty += row * y;
        }
        let literal = xtx.try_inverse().unwrap() * xty;
        assert!((fit.a - literal[0]).abs() < 1e-9);
        assert!((fit.b - literal[1]).abs() < 1e-9);
        assert!((fit.c - literal[2]).abs() < 1e-9);
    }

    //= spec/pierre2022.md#edge-parabola-least-squares-parabola-of-the-chain
    //= type=test
    //# Fewer than 3 points or a singular normal matrix MUST give an error, not a
    //# parabola.
    #[test]
    fn too_few_or_repeated_abscissae_are_refused() {
        let two = pts(&[(0.0, 1.0), (1.0, 2.0)]);
        assert_eq!(
            fit_chain_parabola(&two).unwrap_err().requirement,
            "FIT-DEGENERATE"
        );
        let same_x = pts(&[(1.0, 1.0), (1.0, 2.0), (1.0, 3.0), (1.0, 4.0)]);
        assert_eq!(
            fit_chain_parabola(&same_x).unwrap_err().requirement,
            "FIT-DEGENERATE"
        );
        let two_x = pts(&[(1.0, 1.0), (1.0, 2.0), (2.0, 3.0), (2.0, 4.0)]);
        assert_eq!(
            fit_chain_parabola(&two_x).unwrap_err().requirement,
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
        let d = Meters::new(1.4).unwrap();
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
}
