//! Obstacles seen by a front LiDAR and what they mean for the mission (Emmi
//! 2024, section 3.2; `spec/emmi2024.md`).
//!
//! The scan's points are clustered into obstacles: a small cluster becomes a
//! circle, a large one a segment, both in the robot frame. Two areas ahead of
//! the robot, whose lengths grow with the nominal speed, turn them into one
//! [`Hazard`] per tick, which the mission supervisor
//! ([`crate::supervisor`]) consumes.

use crate::geometry::frame::{Point2, Pose2, Robot, World};
use crate::geometry::units::Meters;

/// One obstacle in the robot frame (x forward, y left, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Obstacle {
    /// A small obstacle: the circle enclosing its points.
    Circle {
        /// The circle's centre.
        centre: Point2<Robot>,
        /// The circle's radius, metres, at least 0.
        radius: Meters,
    },
    /// A large obstacle: the segment along its points.
    Segment {
        /// One end.
        start: Point2<Robot>,
        /// The other end.
        end: Point2<Robot>,
    },
}

/// What the safety areas say in one tick, the most severe obstacle deciding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Hazard {
    /// No obstacle in either area, or none on the planned path in the
    /// warning area.
    Clear,
    /// An obstacle in the warning area and on the planned path: avoid it by
    /// re-planning through `detour`, the intermediate waypoint in the world
    /// frame, or stop when no detour exists (`None`).
    Warning {
        /// The intermediate waypoint going round the obstacle, if any.
        detour: Option<Pose2<World>>,
    },
    /// An obstacle in the critical area: stop for as long as it is there.
    Critical,
}
