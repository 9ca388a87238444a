//! Obstacles seen by a front LiDAR and what they mean for the mission (Emmi
//! 2024, section 3.2; `spec/emmi2024.md`).
//!
//! The scan's points are clustered into obstacles: a small cluster becomes a
//! circle, a large one a segment, both in the robot frame. Two areas ahead of
//! the robot, whose lengths grow with the nominal speed, turn them into one
//! [`Hazard`] per tick, which the mission supervisor
//! ([`crate::supervisor`]) consumes.

pub mod areas;
pub mod cluster;
pub mod corridor;
pub mod detour;

pub use areas::{AreaLength, Footprint, ObstacleConfig, SafetyAreas};
pub use cluster::{cluster, ClusterConfig, Obstacles};
pub use corridor::{Corridor, MAX_CORRIDOR_POINTS};
pub use detour::{detour, detour_within, DetourPlan};

use crate::error::Precondition;
use crate::geometry::frame::{Point2, Pose2, Robot, World};
use crate::geometry::units::{Meters, MetersPerSecond};
use crate::planning::dubins::shortest;

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
    /// An obstacle in the warning area and on the planned path on a road,
    /// and no detour keeps the footprint inside the road's corridor: stop
    /// for as long as it is there (EM-OBST-ROAD).
    NoDetourOnRoad,
}

/// Why the safety areas said what they said (EM-OBST-HAZARD): the named
/// reason of a stop, or of going on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reason {
    /// No obstacle in either area.
    NoObstacle,
    /// Obstacles in the warning area, none on the planned path.
    OffPath,
    /// An obstacle in the critical area: stop.
    CriticalArea,
    /// More obstacles than the list holds, one left out possibly within the
    /// areas: stop.
    Unseen,
    /// An obstacle on the path in the warning area inside a crop field: stop
    /// rather than re-plan over the plants.
    InCropField,
    /// An obstacle on the path in the warning area: re-plan through the
    /// detour waypoint.
    Detour,
    /// An obstacle on the path, and one covers the goal: stop.
    GoalBlocked,
    /// An obstacle on the path, and no side is clear: stop.
    NoClearSide,
    /// An obstacle on the path on a road, and no detour keeps the footprint
    /// inside the road's corridor by the margin: stop.
    NoDetourOnRoad,
}

/// The hazard of one tick and its reason (EM-OBST-HAZARD).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Assessment {
    /// What the mission supervisor acts on.
    pub hazard: Hazard,
    /// Why.
    pub reason: Reason,
}

impl Assessment {
    const fn new(hazard: Hazard, reason: Reason) -> Self {
        Self { hazard, reason }
    }

    /// Whether the robot must stop this tick: a critical hazard, a warning
    /// without a detour, or no detour on the road.
    #[must_use]
    pub const fn stops(&self) -> bool {
        matches!(
            self.hazard,
            Hazard::Critical | Hazard::Warning { detour: None } | Hazard::NoDetourOnRoad
        )
    }
}

/// The hazard of the `obstacles` (robot frame at `pose`) for a robot at
/// `pose` going to `goal` at nominal `speed`, `in_field` saying whether it
/// is inside a crop field (Emmi 2024, section 3.2): the most severe obstacle
/// decides.
///
/// # Errors
/// `EM-OBST-AREAS` for a speed outside [0, 100] m/s; the errors of the
/// Dubins planner for `pose` or `goal` beyond 1e7 m (`EM-DUBINS-RANGE`).
pub fn assess<const N: usize>(
    obstacles: &Obstacles<N>,
    pose: &Pose2<World>,
    goal: &Pose2<World>,
    speed: MetersPerSecond,
    in_field: bool,
    config: &ObstacleConfig,
) -> Result<Assessment, Precondition> {
    assess_within(obstacles, pose, goal, speed, in_field, None, config)
}

/// [`assess`] on a leg whose drivable `corridor` is known (a road's,
/// EM-OBST-ROAD): a detour must keep the footprint inside it by the margin,
/// or the hazard is [`Hazard::NoDetourOnRoad`]; without one, the paper's
/// behaviour.
///
/// # Errors
/// As [`assess`].
//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//# An obstacle in the critical area MUST give `Critical`, whatever the other
//# obstacles, unless the footprint moving along the planned path for the
//# critical area's length L_c(v) is clear of it (EM-OBST-CLEAR).
//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//# Otherwise, an obstacle in the warning area on which the footprint moving
//# along the planned path up to the warning area's far edge is not clear
//# (EM-OBST-CLEAR) MUST give `Warning`; without such an obstacle the hazard
//# MUST be `Clear`.
//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//# The detour of a `Warning` MUST be the waypoint of EM-OBST-DETOUR round the
//# obstacle of the path nearest to the robot, or `None` with the reason when
//# there is none.
//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//# The horizon of the second leg MUST be the warning area's far edge.
pub fn assess_within<const N: usize>(
    obstacles: &Obstacles<N>,
    pose: &Pose2<World>,
    goal: &Pose2<World>,
    speed: MetersPerSecond,
    in_field: bool,
    corridor: Option<&Corridor>,
    config: &ObstacleConfig,
) -> Result<Assessment, Precondition> {
    let areas = config.areas(speed)?;
    //= spec/emmi2024.md#em-obst-unseen-obstacles-left-out
    //# When the list of obstacles dropped one whose distance from the robot
    //# is not beyond the farthest point of the areas, the hazard MUST be
    //# `Critical`.
    if obstacles.dropped_any()
        && !obstacles
            .nearest_dropped()
            .is_some_and(|d| d.get() > areas.reach())
    {
        return Ok(Assessment::new(Hazard::Critical, Reason::Unseen));
    }
    let all = obstacles.as_slice();
    let mut critical = all.iter().filter(|o| areas.in_critical(o)).peekable();
    if critical.peek().is_some() {
        // The critical area along the path: a rectangle ahead sweeps up to
        // L²/2r outside an arc the robot follows. No path: Critical.
        let length = areas.critical_end().get() - config.footprint().front().get();
        let hit = shortest(pose, goal, config.radius()).map_or(true, |path| {
            critical.any(|o| detour::on_path(o, pose, &path, length, config))
        });
        if hit {
            return Ok(Assessment::new(Hazard::Critical, Reason::CriticalArea));
        }
    }
    let mut warned = all.iter().filter(|o| areas.in_warning(o)).peekable();
    if warned.peek().is_none() {
        return Ok(Assessment::new(Hazard::Clear, Reason::NoObstacle));
    }
    let nominal = shortest(pose, goal, config.radius())?;
    let upto = areas.warning_end().get();
    let target = warned
        .filter(|o| detour::on_path(o, pose, &nominal, upto, config))
        .map(|o| (cluster::distance(o), o))
        .fold(None, |best: Option<(f64, &Obstacle)>, (d, o)| match best {
            Some((bd, _)) if !areas::above(bd, d) => best,
            _ => Some((d, o)),
        });
    let Some((_, target)) = target else {
        return Ok(Assessment::new(Hazard::Clear, Reason::OffPath));
    };
    //= spec/emmi2024.md#em-obst-field-no-re-planning-in-a-crop-field
    //# Inside a crop field, a `Warning` MUST carry no detour, with the reason
    //# `InCropField`, so that the robot stops instead of crossing the crop.
    if in_field {
        return Ok(Assessment::new(
            Hazard::Warning { detour: None },
            Reason::InCropField,
        ));
    }
    Ok(
        match detour_within(
            target,
            all,
            pose,
            goal,
            areas.warning_end(),
            corridor,
            config,
        )? {
            DetourPlan::Waypoint(w) => {
                Assessment::new(Hazard::Warning { detour: Some(w) }, Reason::Detour)
            }
            DetourPlan::GoalBlocked => {
                Assessment::new(Hazard::Warning { detour: None }, Reason::GoalBlocked)
            }
            DetourPlan::NoClearSide => {
                Assessment::new(Hazard::Warning { detour: None }, Reason::NoClearSide)
            }
            //= spec/emmi2024.md#em-obst-road-detours-inside-the-road
            //# When re-planning reports that no detour fits on the road, the
            //# hazard MUST be `NoDetourOnRoad`, with the reason
            //# `NoDetourOnRoad`.
            DetourPlan::NoDetourOnRoad => {
                Assessment::new(Hazard::NoDetourOnRoad, Reason::NoDetourOnRoad)
            }
        },
    )
}
