//! Tracking errors carried from a scan's pose to the current pose through
//! odometry (`spec/guidance.md`, GD-ODOMETRY).

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Odom, Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_angle, Meters, Radians};
use crate::perception::edge::{self, EdgeFit, Side};
use crate::perception::furrow::lines;
use crate::perception::furrow::selection::Pair;
use crate::perception::furrow::RowLines;

/// The odometry pose `now` expressed in the robot frame of the odometry pose
/// `then` (the frame a scan taken at `then` is expressed in).
///
/// # Errors
/// `LIB-FINITE` when the poses are so far apart that the result overflows.
pub fn pose_in_scan_frame(
    then: &Pose2<Odom>,
    now: &Pose2<Odom>,
) -> Result<Pose2<Robot>, Precondition> {
    then.body_to_frame::<Robot>().inverse()?.apply_pose(*now)
}

/// The signed left distance y₀ + p_x sin θ̃₀ + p_y cos θ̃₀ of the robot moved
/// to `pose`, from the error (y₀, θ̃₀) to a straight line seen at the origin.
fn moved_lateral(error: &TrackingError, pose: &Pose2<Robot>) -> Result<f64, Precondition> {
    let theta = error.angular_deviation.get();
    finite(
        error.y.get() + pose.position.x() * libm::sin(theta) + pose.position.y() * libm::cos(theta),
        "moved lateral error overflows",
    )
}

/// A straight-line error from its parts, θ̃ wrapped (LIB-FRAMES).
fn straight(y: f64, angular_deviation: f64) -> Result<TrackingError, Precondition> {
    Ok(TrackingError::to_straight_line(
        Meters::new(y)?,
        Radians::new(wrap_angle(finite(
            angular_deviation,
            "moved angular error overflows",
        )?))?,
    ))
}

/// The error to a straight line, given as `error` at the scan's pose, for the
/// robot at `pose` in the scan's robot frame: y = y₀ + p_x sin θ̃₀ +
/// p_y cos θ̃₀, θ̃ = wrap(θ̃₀ + ψ) (GD-ODOMETRY).
///
/// # Errors
/// `LIB-FINITE` on overflow.
//= spec/guidance.md#gd-odometry-errors-moved-by-odometry
//# For a straight line with error (y₀, θ̃₀) at the scan's pose, the robot at
//# (p_x, p_y, ψ) in the scan's robot frame MUST get y = y₀ + p_x sin θ̃₀ +
//# p_y cos θ̃₀ and θ̃ = wrap(θ̃₀ + ψ); for two rows, the mean of the two moved
//# errors; for an edge parabola, y = y₀(p_x) + p_y cos θ̃₀(p_x) and θ̃ =
//# wrap(θ̃₀(p_x) + ψ), where (y₀(p_x), θ̃₀(p_x)) is the error of EDGE-OFFSET at
//# x_r = p_x.
pub fn moved_line_error(
    error: &TrackingError,
    pose: &Pose2<Robot>,
) -> Result<TrackingError, Precondition> {
    straight(
        moved_lateral(error, pose)?,
        error.angular_deviation.get() + pose.heading.get(),
    )
}

/// The error to furrow row lines seen at the scan's pose, for the robot at
/// `pose` in the scan's robot frame: one row as [`moved_line_error`]; two
/// rows, the mean of both moved errors, the angles averaged before ψ is
/// added (FUR-ERRORS, FUR-TWO-ROWS, GD-ODOMETRY).
///
/// # Errors
/// `LIB-FINITE` on overflow.
pub fn moved_rows_error(
    rows: &RowLines,
    pose: &Pose2<Robot>,
) -> Result<TrackingError, Precondition> {
    match rows {
        RowLines::One(line) => moved_line_error(&lines::tracking_error(line)?, pose),
        RowLines::Two(Pair { left, right }) => {
            let l = lines::tracking_error(left)?;
            let r = lines::tracking_error(right)?;
            let y = 0.5 * moved_lateral(&l, pose)? + 0.5 * moved_lateral(&r, pose)?;
            let theta = 0.5 * l.angular_deviation.get() + 0.5 * r.angular_deviation.get();
            straight(y, theta + pose.heading.get())
        }
    }
}

/// The error to an edge's line (the parabola's tangent shifted by `offset`
/// towards the robot) for the robot at `pose` in the scan's robot frame:
/// y = y₀(p_x) + p_y cos θ̃₀(p_x), θ̃ = wrap(θ̃₀(p_x) + ψ), with eq. 11's error
/// at x_r = p_x (EDGE-ERRORS, EDGE-OFFSET, GD-ODOMETRY).
///
/// # Errors
/// `LIB-FINITE` on overflow.
pub fn moved_edge_error(
    fit: &EdgeFit,
    side: Side,
    offset: Meters,
    pose: &Pose2<Robot>,
) -> Result<TrackingError, Precondition> {
    let at = edge::tracking_error(&fit.parabola, side, offset, pose.position.x())?;
    let theta = at.angular_deviation.get();
    straight(
        finite(
            at.y.get() + pose.position.y() * libm::cos(theta),
            "moved edge error overflows",
        )?,
        theta + pose.heading.get(),
    )
}
