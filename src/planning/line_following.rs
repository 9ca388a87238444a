//! LineFollowing: a straight line from the robot's pose to a point ahead of
//! it along its heading (Emmi 2024, section 3.1; `spec/emmi2024.md`, EM-LINE).

use crate::error::Precondition;
use crate::geometry::frame::{Pose2, World};
use crate::geometry::path::{ReferencePath, MIN_WAYPOINT_SPACING};
use crate::geometry::units::{Curvature, Meters};

/// The goal of LineFollowing: the pose `distance` metres ahead of `pose`
/// along its heading, with the same heading.
///
/// # Errors
/// `EM-LINE` for a distance below 1 mm; `LIB-FINITE` when the goal overflows.
//= spec/emmi2024.md#em-line-linefollowing
//# LineFollowing MUST return the goal pose at the requested distance ahead of
//# the robot along its heading, with the robot's heading, and refuse a distance
//# below 1 mm with the `EM-LINE` error.
pub fn goal_ahead(pose: &Pose2<World>, distance: Meters) -> Result<Pose2<World>, Precondition> {
    let d = distance.get();
    if d < MIN_WAYPOINT_SPACING {
        return Err(Precondition::new(
            "EM-LINE",
            "distance ahead must be at least 1 mm",
        ));
    }
    let h = pose.heading.get();
    Pose2::new(
        pose.position.x() + d * libm::cos(h),
        pose.position.y() + d * libm::sin(h),
        h,
    )
}

/// The straight reference path from `pose` to [`goal_ahead`], curvature 0.
///
/// # Errors
/// As [`goal_ahead`], and those of [`ReferencePath::from_exact`].
//= spec/emmi2024.md#em-line-linefollowing
//# The LineFollowing path MUST be the straight segment from the robot's
//# position to the goal, heading the robot's heading, curvature 0.
pub fn line_ahead<const N: usize>(
    pose: &Pose2<World>,
    distance: Meters,
) -> Result<ReferencePath<N>, Precondition> {
    let goal = goal_ahead(pose, distance)?;
    ReferencePath::from_exact([(*pose, Curvature::ZERO), (goal, Curvature::ZERO)])
}
