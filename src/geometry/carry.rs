//! Tracking errors carried from a scan's pose to a later pose through
//! odometry (`spec/guidance.md`, GD-ODOMETRY): the geometry every held line
//! ([`crate::perception::HeldLine`]) moves itself with.

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Odom, Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_raw, Meters, Radians};

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
///
/// # Errors
/// `LIB-FINITE` on overflow.
pub fn moved_lateral(error: &TrackingError, pose: &Pose2<Robot>) -> Result<f64, Precondition> {
    let theta = error.angular_deviation.get();
    finite(
        error.y.get() + pose.position.x() * libm::sin(theta) + pose.position.y() * libm::cos(theta),
        "moved lateral error overflows",
    )
}

/// A straight-line error from its parts, θ̃ wrapped (LIB-FRAMES).
///
/// # Errors
/// `LIB-FINITE` when a part is not finite.
pub fn straight(y: f64, angular_deviation: f64) -> Result<TrackingError, Precondition> {
    Ok(TrackingError::to_straight_line(
        Meters::new(y)?,
        Radians::new(wrap_raw(finite(
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
