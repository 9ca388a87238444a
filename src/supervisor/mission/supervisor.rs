//! The geometric layer of the mission supervisor: localisation, events,
//! the pure machine and the plan of each leg (Emmi 2024, sections 3.1-3.2;
//! EM-MISSION-LEGS, EM-LOC-CHOICE).

use heapless::Vec;

use crate::error::Precondition;
use crate::geometry::frame::{Pose2, Robot, World};
use crate::geometry::path::ReferencePath;
use crate::geometry::units::{Curvature, Meters, MetersPerSecond};
use crate::perception::obstacles::Hazard;
use crate::planning::dubins::{shortest, DubinsPath};
use crate::planning::line_following::goal_ahead;
use crate::planning::manager::{choose_planner, Planner};

use super::config::MissionConfig;
use super::localisation::{Fix, Localiser};
use super::machine::{step, MissionState};
use super::tasks::{Shape, Task, MAX_TASKS};
use super::{Arrival, Command, Events, HazardLevel, LegRef, Phase, StopReason};

/// The least motion in a tick that counts as progress, metres.
const MIN_PROGRESS: f64 = 1e-3;

/// The plan of one leg, as a value the pipeline follows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plan {
    /// GoToGoal: a Dubins path (forward only) to `goal`.
    GoToGoal {
        /// The path.
        path: DubinsPath,
        /// Its goal.
        goal: Pose2<World>,
    },
    /// LineFollowing: the straight line from `start` to `goal`.
    Line {
        /// Where the line starts.
        start: Pose2<World>,
        /// Its goal.
        goal: Pose2<World>,
    },
}

impl Plan {
    /// The goal of the leg.
    #[must_use]
    pub const fn goal(&self) -> Pose2<World> {
        match self {
            Self::GoToGoal { goal, .. } | Self::Line { goal, .. } => *goal,
        }
    }

    /// The length of the leg (0 for a line whose length overflows, which
    /// [`Mission`] never plans).
    #[must_use]
    pub fn length(&self) -> Meters {
        match self {
            Self::GoToGoal { path, .. } => path.length(),
            Self::Line { start, goal } => start
                .position
                .distance_to(goal.position)
                .unwrap_or(Meters::ZERO),
        }
    }

    /// Whether the leg is driven forward only: every Dubins segment of
    /// non-negative length, or a line whose goal is not behind its start.
    //= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
    //# A planned leg MUST be forward only: a Dubins path of non-negative segment
    //# lengths or a straight line ahead, and the commanded speed MUST never be
    //# negative.
    #[must_use]
    pub fn is_forward(&self) -> bool {
        match self {
            Self::GoToGoal { path, .. } => path.segments().iter().all(|s| s.length.get() >= 0.0),
            Self::Line { start, goal } => {
                let h = start.heading.get();
                let dx = goal.position.x() - start.position.x();
                let dy = goal.position.y() - start.position.y();
                dx * libm::cos(h) + dy * libm::sin(h) >= 0.0
            }
        }
    }
}

impl Plan {
    /// The plan as a reference path of at most `N` vertices for the
    /// trackers: the Dubins path sampled at most `spacing` apart
    /// ([`DubinsPath::to_reference_path`]), or the line's two ends, heading
    /// along the line, curvature 0.
    ///
    /// # Errors
    /// Those of [`DubinsPath::to_reference_path`] and
    /// [`ReferencePath::from_exact`] (`PATH-WAYPOINTS` for a leg shorter than
    /// 1 mm: it is reached already).
    pub fn to_reference_path<const N: usize>(
        &self,
        spacing: Meters,
    ) -> Result<ReferencePath<N>, Precondition> {
        match self {
            Self::GoToGoal { path, .. } => path.to_reference_path(spacing),
            Self::Line { start, goal } => {
                let heading = libm::atan2(
                    goal.position.y() - start.position.y(),
                    goal.position.x() - start.position.x(),
                );
                let at = |p: &Pose2<World>| Pose2::new(p.position.x(), p.position.y(), heading);
                ReferencePath::from_exact([
                    (at(start)?, Curvature::ZERO),
                    (at(goal)?, Curvature::ZERO),
                ])
            }
        }
    }
}

/// The supervisor's input in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MissionInput {
    /// The GNSS fix when it is valid.
    pub gnss: Option<Pose2<World>>,
    /// The odometry increment: the motion since the previous tick, in the
    /// robot frame of the previous tick.
    pub odometry: Pose2<Robot>,
    /// The obstacle hazard of the safety areas.
    pub hazard: Hazard,
    /// Whether the robot is inside the current task's field.
    pub in_field: bool,
    /// The pipeline's remaining distance along the plan it followed in the
    /// previous tick (negative past the goal), when it has one.
    pub remaining: Option<Meters>,
}

/// The supervisor's answer in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MissionOutput {
    /// The command.
    pub command: Command,
    /// The phase; `Aborted` carries the malfunction.
    pub phase: Phase,
    /// The plan to follow when the command is Follow.
    pub plan: Option<Plan>,
    /// The pose used and where it came from.
    pub fix: Fix,
    /// The speed to drive at, m/s, never negative (0 with Stop).
    pub speed: MetersPerSecond,
}

/// The key of a planned leg: task, leg, detour.
type LegKey = (u8, u8, bool);

/// The mission supervisor: the tasks, the pure machine's state, the
/// localisation choice and the plan of the current leg.
#[derive(Debug, Clone, PartialEq)]
pub struct Mission {
    config: MissionConfig,
    tasks: Vec<Task, MAX_TASKS>,
    shape: Shape,
    state: MissionState,
    localiser: Localiser,
    plan: Option<(LegKey, Plan)>,
    plan_failed: bool,
    at_goal: bool,
    detour_goal: Option<Pose2<World>>,
    driven: f64,
}

impl Mission {
    /// A supervisor of `tasks`, in order; an empty list gives a mission that
    /// stops at once with the reason EmptyMission.
    ///
    /// # Errors
    /// `EM-MISSION-TASKS` for more than [`MAX_TASKS`] tasks.
    pub fn new(config: MissionConfig, tasks: &[Task]) -> Result<Self, Precondition> {
        let tasks: Vec<Task, MAX_TASKS> = Vec::from_slice(tasks)
            .map_err(|_| Precondition::new("EM-MISSION-TASKS", "more than 8 tasks"))?;
        let shape = Shape::of(&tasks);
        Ok(Self {
            config,
            state: MissionState::initial(&shape),
            shape,
            tasks,
            localiser: Localiser::new(config.odometry_distance),
            plan: None,
            plan_failed: false,
            at_goal: false,
            detour_goal: None,
            driven: 0.0,
        })
    }

    /// The machine's state.
    #[must_use]
    pub const fn state(&self) -> &MissionState {
        &self.state
    }

    /// One control tick (EM-MISSION-MACHINE): localisation, events, the
    /// machine's [`step`], then the plan of the leg to follow.
    pub fn tick(&mut self, input: &MissionInput) -> MissionOutput {
        let fix = self.localiser.update(input.gnss, &input.odometry);
        let pose = fix.pose();
        //= spec/emmi2024.md#em-mission-monitor-malfunctions
        //# The progress of a tick and the distance driven on a leg MUST be taken
        //# from the odometry increments, never from differences of localised poses,
        //# so that the noise of a standing robot's fix is neither progress nor
        //# distance.
        let moved = libm::hypot(input.odometry.position.x(), input.odometry.position.y());
        self.driven += moved;
        let arrival = match (pose, &self.plan) {
            (Some(p), Some((key, plan))) if *key == self.key() => {
                let to_goal = libm::hypot(
                    plan.goal().position.x() - p.position.x(),
                    plan.goal().position.y() - p.position.y(),
                );
                let tolerance = self.config.tolerance.get();
                let close = to_goal <= tolerance;
                match input.remaining {
                    // Planned where it ends: reached without a path.
                    _ if self.at_goal => Arrival::Reached,
                    // The end is passed along the path: reached or missed.
                    Some(r) if r.get() <= self.config.reach_distance.get() => {
                        if close {
                            Arrival::Reached
                        } else {
                            Arrival::Missed
                        }
                    }
                    Some(_) => Arrival::EnRoute,
                    // Without the pipeline's distance: reached when close,
                    // missed once driven well past the leg's length.
                    None if close => Arrival::Reached,
                    None if self.driven > plan.length().get() + 2.0 * tolerance => Arrival::Missed,
                    None => Arrival::EnRoute,
                }
            }
            _ => Arrival::EnRoute,
        };
        // A new detour's waypoint is kept; one followed is replaced (and
        // re-planned) only when the new waypoint moved beyond the tolerance.
        let mut invalid = false;
        let hazard = match input.hazard {
            Hazard::Clear => HazardLevel::Clear,
            Hazard::Critical => HazardLevel::Critical,
            Hazard::NoDetourOnRoad => HazardLevel::NoDetourOnRoad,
            Hazard::Warning { detour } => {
                if let Some(w) = detour {
                    let followed = self.detour_goal.filter(|_| self.state.detour());
                    match followed {
                        None => self.detour_goal = Some(w),
                        Some(g) => {
                            let apart = libm::hypot(
                                w.position.x() - g.position.x(),
                                w.position.y() - g.position.y(),
                            );
                            if apart > self.config.tolerance.get() {
                                self.detour_goal = Some(w);
                                invalid = true;
                            }
                        }
                    }
                }
                HazardLevel::Warning {
                    detour: detour.is_some(),
                }
            }
        };
        let events = Events {
            hazard,
            in_field: input.in_field,
            localisation: fix.status(),
            plan_ready: !self.plan_failed,
            progressing: moved >= MIN_PROGRESS,
            arrival,
        };
        let (state, out) = step(&self.config.machine, &self.shape, &self.state, &events);
        self.state = state;
        let mut command = out.command;
        if let (Command::Follow(leg), Some(pose)) = (command, pose) {
            let key = (leg.task, leg.leg, leg.detour);
            let stale = self.plan.as_ref().is_none_or(|(k, _)| *k != key);
            if out.replan || stale || (invalid && leg.detour) {
                match self.plan_leg(&leg, &pose) {
                    Ok(plan) => {
                        self.at_goal = self.starts_at_goal(&pose, &plan.goal());
                        self.plan = Some((key, plan));
                        self.driven = 0.0;
                    }
                    Err(_) => {
                        // The machine aborts with Unplannable in the next tick.
                        self.plan = None;
                        self.plan_failed = true;
                        command = Command::Stop(StopReason::Unplannable);
                    }
                }
            }
        }
        let plan = match command {
            Command::Follow(_) => self.plan.as_ref().map(|(_, plan)| *plan),
            Command::Stop(_) => None,
        };
        let speed = match plan {
            Some(Plan::GoToGoal { .. }) => self.config.turn_speed,
            Some(Plan::Line { .. }) => self.config.cruise_speed,
            None => MetersPerSecond::ZERO,
        };
        MissionOutput {
            command,
            phase: out.phase,
            plan,
            fix,
            speed,
        }
    }

    /// Whether a leg planned from `pose` to `goal` starts at its goal: within
    /// the tolerance, heading within the planner threshold.
    //= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
    //# A leg whose goal is within the tolerance of the pose it is planned from,
    //# with a heading change below the planner threshold, MUST count as reached
    //# in the next tick, its path not followed.
    fn starts_at_goal(&self, pose: &Pose2<World>, goal: &Pose2<World>) -> bool {
        let near = libm::hypot(
            goal.position.x() - pose.position.x(),
            goal.position.y() - pose.position.y(),
        ) <= self.config.tolerance.get();
        let turn = libm::fabs(crate::geometry::units::wrap_raw(
            goal.heading.get() - pose.heading.get(),
        ));
        near && turn < self.config.threshold.get().get()
    }

    /// The key of the machine's current leg.
    fn key(&self) -> LegKey {
        let (task, leg) = self.state.leg();
        (task, leg, self.state.detour())
    }

    /// The plan of `leg` from `pose` (EM-MISSION-LEGS).
    //= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
    //# A leg that cannot be planned, or whose path is longer than the configured
    //# longest leg (a goal unreachable with the turning radius), MUST stop the
    //# mission with the reason Unplannable.
    fn plan_leg(&self, leg: &LegRef, pose: &Pose2<World>) -> Result<Plan, Precondition> {
        //= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
        //# An Approximation's GoToGoal leg MUST be planned with the road radius,
        //# a Treatment's turns and the detours with the turning radius.
        let go_to = |goal: Pose2<World>, radius| -> Result<Plan, Precondition> {
            Ok(Plan::GoToGoal {
                path: shortest(pose, &goal, radius)?,
                goal,
            })
        };
        let (radius, road) = (self.config.radius, self.config.road_radius);
        let missing = Precondition::new("EM-MISSION-TASKS", "no such leg");
        let plan = if leg.detour {
            go_to(self.detour_goal.ok_or(missing)?, radius)?
        } else {
            match self.tasks.get(usize::from(leg.task)).ok_or(missing)? {
                Task::Approximation(waypoints) => {
                    let goal = *waypoints.get(usize::from(leg.leg)).ok_or(missing)?;
                    match choose_planner(pose, &goal, self.config.threshold) {
                        Planner::GoToGoal => go_to(goal, road)?,
                        Planner::LineFollowing => Plan::Line { start: *pose, goal },
                    }
                }
                Task::Treatment(rows) => {
                    let row = rows.get(usize::from(leg.leg >> 1)).ok_or(missing)?;
                    if leg.leg & 1 == 0 {
                        go_to(row.start, radius)?
                    } else {
                        Plan::Line {
                            start: row.start,
                            goal: goal_ahead(&row.start, row.length)?,
                        }
                    }
                }
            }
        };
        if plan.length().get() > self.config.longest_leg.get() || !plan.is_forward() {
            return Err(Precondition::new(
                "EM-MISSION-LEGS",
                "leg longer than the longest leg",
            ));
        }
        Ok(plan)
    }
}
