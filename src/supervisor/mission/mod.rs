//! The mission supervisor (Emmi 2024, sections 3.1, 3.2 and 4;
//! `spec/emmi2024.md`, EM-MISSION-* and EM-LOC-*).
//!
//! A mission is a list of tasks ([`Task`]): an Approximation reaches a field
//! along roads, one leg per waypoint; a Treatment works a field, a GoToGoal
//! turn to each row's start then the pass along the row with the tool on.
//!
//! Two layers:
//! - [`step`], a pure function of abstract [`Events`] counted in ticks, whose
//!   properties (EM-MISSION-M1 to M5) the proofs crate (`fieldguide-proofs`)
//!   checks over every reachable state;
//! - [`Mission`], which chooses the localisation ([`Localiser`], EM-LOC-CHOICE),
//!   turns poses and the obstacle [`Hazard`](crate::perception::obstacles::Hazard)
//!   into those events, calls [`step`] and plans each leg with the real
//!   planners ([`Plan`], EM-MISSION-LEGS).
//!
//! ```
//! use fieldguide::supervisor::mission::{Command, Mission, MissionConfig, MissionInput, Task};
//! use fieldguide::perception::obstacles::Hazard;
//! use fieldguide::{Pose2, Robot, World};
//!
//! # fn main() -> Result<(), fieldguide::Precondition> {
//! let road = Task::approximation(&[Pose2::<World>::new(10.0, 0.0, 0.0)?])?;
//! let mut mission = Mission::new(MissionConfig::carob()?, &[road])?;
//! let input = MissionInput {
//!     gnss: Some(Pose2::new(0.0, 0.0, 0.0)?),
//!     odometry: Pose2::<Robot>::new(0.0, 0.0, 0.0)?,
//!     hazard: Hazard::Clear,
//!     in_field: false,
//!     remaining: None,
//! };
//! let out = mission.tick(&input);
//! assert!(matches!(out.command, Command::Follow(_)));
//! let critical = MissionInput { hazard: Hazard::Critical, ..input };
//! assert!(matches!(mission.tick(&critical).command, Command::Stop(_)));
//! # Ok(())
//! # }
//! ```

mod config;
mod localisation;
mod machine;
mod supervisor;
mod tasks;

#[cfg(feature = "fault-injection")]
pub use config::Fault;
pub use config::{MachineConfig, MissionConfig};
pub use localisation::{Fix, Localiser};
pub use machine::{step, MissionState};
pub use supervisor::{Mission, MissionInput, MissionOutput, Plan};
pub use tasks::{Row, Shape, Task, TaskKind, MAX_LEGS, MAX_ROWS, MAX_TASKS, MAX_WAYPOINTS};

/// The phase of a mission (EM-MISSION-MACHINE).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Phase {
    /// Executing a leg of a task.
    Running,
    /// Every task has ended: the robot stands still.
    Done,
    /// The mission stopped for good with a malfunction the vehicle stack reads.
    Aborted(StopReason),
}

/// Why the command is Stop (EM-MISSION-MACHINE, EM-MISSION-OBSTACLE,
/// EM-MISSION-MONITOR, EM-LOC-STOP).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StopReason {
    /// The mission has no task.
    EmptyMission,
    /// A task has no leg.
    EmptyTask,
    /// An obstacle in the critical area (held while it is there).
    Obstacle,
    /// An obstacle in the warning area on a road with no detour (held).
    NoDetour,
    /// An obstacle in the warning area on a road, and no detour keeps the
    /// footprint inside the road's corridor (held while it is there).
    NoDetourOnRoad,
    /// An obstacle in the warning area inside a field (held; no re-planning).
    ObstacleInField,
    /// No GNSS fix and odometry beyond its distance (held until a fix).
    LocalisationLost,
    /// No progress for the stall delay (abort).
    NoProgress,
    /// A leg not reached within the leg time limit (abort).
    LegTimeout,
    /// A leg's end passed without reaching its goal within the tolerance (abort).
    GoalMissed,
    /// A leg that cannot be planned or is longer than allowed (abort).
    Unplannable,
    /// Every task has ended.
    Finished,
}

/// The obstacle hazard as the machine sees it (EM-MISSION-OBSTACLE).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HazardLevel {
    /// No obstacle to act on.
    Clear,
    /// An obstacle in the warning area on the planned path; whether a detour
    /// waypoint exists.
    Warning {
        /// A detour waypoint exists.
        detour: bool,
    },
    /// An obstacle in the critical area.
    Critical,
    /// An obstacle in the warning area on the planned path on a road, and no
    /// detour inside the road's corridor.
    NoDetourOnRoad,
}

/// The localisation in one tick (EM-LOC-CHOICE).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LocalisationStatus {
    /// A valid GNSS fix.
    Gnss,
    /// Odometry from the last valid fix, within the allowed distance.
    Odometry,
    /// Neither.
    Lost,
}

/// Where the robot stands with respect to the goal of the leg it follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Arrival {
    /// Not there yet.
    EnRoute,
    /// Within the tolerance of the goal.
    Reached,
    /// The leg's end is passed without reaching the goal.
    Missed,
}

/// The abstract events of one tick (EM-MISSION-MACHINE).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Events {
    /// The obstacle hazard.
    pub hazard: HazardLevel,
    /// Whether the robot is inside the task's field.
    pub in_field: bool,
    /// The localisation.
    pub localisation: LocalisationStatus,
    /// Whether the current leg's plan exists (false: it could not be planned).
    pub plan_ready: bool,
    /// Whether the robot moved since the previous tick.
    pub progressing: bool,
    /// The arrival at the current leg's goal.
    pub arrival: Arrival,
}

impl Events {
    /// A tick where all goes well: no obstacle, on a road, GNSS, the plan
    /// exists, the robot moves and is en route.
    pub const NOMINAL: Self = Self {
        hazard: HazardLevel::Clear,
        in_field: false,
        localisation: LocalisationStatus::Gnss,
        plan_ready: true,
        progressing: true,
        arrival: Arrival::EnRoute,
    };
}

/// One leg of the mission being followed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LegRef {
    /// Index of the task.
    pub task: u8,
    /// Index of the leg within the task.
    pub leg: u8,
    /// Whether the robot follows a detour of that leg.
    pub detour: bool,
    /// Whether the treatment tool is on.
    pub tool_on: bool,
}

/// The command to the pipeline (EM-MISSION-MACHINE).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// Follow the plan of this leg.
    Follow(LegRef),
    /// Stand still, for this reason; the tool is off.
    Stop(StopReason),
}

impl Command {
    /// Whether the treatment tool is on.
    #[must_use]
    pub const fn tool_on(&self) -> bool {
        matches!(self, Self::Follow(LegRef { tool_on: true, .. }))
    }
}

/// The machine's answer in one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Output {
    /// The command.
    pub command: Command,
    /// The phase after this tick; `Aborted` carries the malfunction.
    pub phase: Phase,
    /// Whether the leg must be (re-)planned from the current pose in this
    /// tick: a new leg, a detour started, ended or dropped.
    pub replan: bool,
}
