//! Which planner and which tracking controller run (Emmi 2024, sections 3.1,
//! 3.3 and 4; `spec/emmi2024.md`, EM-PLANNER and EM-TRACKER).
//!
//! A change of direction of at least a threshold (45° by default) is planned
//! with GoToGoal (a Dubins path), a smaller one with LineFollowing. Along
//! the planned path, straight segments are tracked by the lateral PD
//! controller ([`crate::control::lateral_pd`]) and arcs by the spiral
//! controller ([`crate::control::spiral`]) on a circle around the arc's
//! centre; the linear speed controller ([`crate::control::speed_profile`])
//! shapes the speed over the whole path.

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use crate::error::Precondition;
use crate::geometry::frame::{Point2, Pose2, World};
use crate::geometry::units::{wrap_raw, Radians};
use crate::planning::dubins::{Segment, Turn};

/// The planner that reaches the next goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Planner {
    /// A Dubins path ([`crate::planning::dubins::shortest`]).
    GoToGoal,
    /// A straight line ahead ([`crate::planning::line_following::line_ahead`]).
    LineFollowing,
}

/// The least change of direction planned with GoToGoal, radians in (0, π].
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct PlannerThreshold(f64);

impl PlannerThreshold {
    /// The paper's threshold, 45° (section 4).
    pub const DEFAULT: Self = Self(FRAC_PI_4);

    /// A threshold of `angle` radians.
    ///
    /// # Errors
    /// `EM-PLANNER` outside (0, π].
    //= spec/emmi2024.md#em-planner-gotogoal-or-linefollowing
    //# The threshold MUST lie in (0, π], 45° by default; another value MUST be
    //# refused with the `EM-PLANNER` error.
    pub fn new(angle: Radians) -> Result<Self, Precondition> {
        let a = angle.get();
        if a > 0.0 && a <= PI {
            Ok(Self(a))
        } else {
            Err(Precondition::new(
                "EM-PLANNER",
                "planner threshold outside (0, pi]",
            ))
        }
    }

    /// The threshold in radians.
    #[must_use]
    pub const fn get(self) -> Radians {
        Radians(self.0)
    }
}

/// The change of direction from `robot` to `goal`: the larger of the heading
/// change |wrap(θ_goal − θ)| and the bearing change |wrap(bearing − θ)|, the
/// bearing being the direction from the robot to the goal (0 for a goal at
/// the robot's position).
//= spec/emmi2024.md#em-planner-gotogoal-or-linefollowing
//# The change of direction MUST be the larger of |wrap(θ_goal − θ)| and
//# |wrap(b − θ)|, where b is the direction from the robot to the goal (b = θ
//# when the goal is at the robot's position).
#[must_use]
pub fn direction_change(robot: &Pose2<World>, goal: &Pose2<World>) -> Radians {
    let h = robot.heading.get();
    let dx = goal.position.x() - robot.position.x();
    let dy = goal.position.y() - robot.position.y();
    let bearing = if dx == 0.0 && dy == 0.0 {
        h
    } else {
        libm::atan2(dy, dx)
    };
    let heading_change = libm::fabs(wrap_raw(goal.heading.get() - h));
    let bearing_change = libm::fabs(wrap_raw(bearing - h));
    Radians(heading_change.max(bearing_change))
}

/// The planner for the next goal (Emmi 2024, section 4).
//= spec/emmi2024.md#em-planner-gotogoal-or-linefollowing
//# A change of direction at or above the threshold MUST be planned with
//# GoToGoal, a smaller one with LineFollowing.
#[must_use]
pub fn choose_planner(
    robot: &Pose2<World>,
    goal: &Pose2<World>,
    threshold: PlannerThreshold,
) -> Planner {
    if direction_change(robot, goal).get() >= threshold.0 {
        Planner::GoToGoal
    } else {
        Planner::LineFollowing
    }
}

/// The tracking controller of one planned segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tracker {
    /// The lateral PD controller (straight segments).
    Lateral,
    /// The spiral controller on the circle of the arc: its centre and the
    /// desired angle α_d (+π/2 for a left arc, −π/2 for a right arc).
    Spiral {
        /// The arc's centre, `World` frame.
        centre: Point2<World>,
        /// The desired spiral angle α_d, radians.
        desired_angle: Radians,
    },
}

/// The controller that tracks `segment` (Emmi 2024, section 3.3): the
/// lateral controller on a straight, the spiral controller with α_d = ±π/2
/// around the arc's centre on an arc.
//= spec/emmi2024.md#em-tracker-which-controller-runs
//# A straight segment MUST be tracked by the lateral controller, and an arc by
//# the spiral controller around the arc's centre with α_d = +π/2 for a left arc
//# and α_d = −π/2 for a right arc.
#[must_use]
pub fn tracker_for(segment: &Segment) -> Tracker {
    match (segment.turn, segment.centre) {
        (Turn::Left, Some(centre)) => Tracker::Spiral {
            centre,
            desired_angle: Radians(FRAC_PI_2),
        },
        (Turn::Right, Some(centre)) => Tracker::Spiral {
            centre,
            desired_angle: Radians(-FRAC_PI_2),
        },
        _ => Tracker::Lateral,
    }
}
