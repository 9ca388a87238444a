//! The state and the transition function of the mission machine
//! (`spec/emmi2024.md`, EM-MISSION-MACHINE, EM-MISSION-OBSTACLE,
//! EM-MISSION-MONITOR, EM-LOC-STOP).

#[cfg(feature = "fault-injection")]
use super::config::Fault;
use super::config::MachineConfig;
use super::tasks::{Shape, TaskKind};
use super::{
    Arrival, Command, Events, HazardLevel, LegRef, LocalisationStatus, Output, Phase, StopReason,
};

/// Everything the machine remembers between ticks: its phase, the leg it is
/// on, whether it follows a detour, and two tick counters saturating at their
/// limits, so the state space is finite (the proofs explore all of it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MissionState {
    phase: Phase,
    task: u8,
    leg: u8,
    detour: bool,
    leg_ticks: u16,
    stall_ticks: u16,
}

impl MissionState {
    /// The initial state of a mission of `shape`: Running at its first leg, or
    /// Aborted when it has no task or its first task no leg.
    //= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
    //# The machine MUST have the phases Running, Done and Aborted, and start
    //# Running at the first leg of the first task, or Aborted with the reason
    //# EmptyMission when the mission has no task.
    #[must_use]
    pub fn initial(shape: &Shape) -> Self {
        let phase = match shape.task(0) {
            None => Phase::Aborted(StopReason::EmptyMission),
            Some((_, 0)) => Phase::Aborted(StopReason::EmptyTask),
            Some(_) => Phase::Running,
        };
        Self {
            phase,
            task: 0,
            leg: 0,
            detour: false,
            leg_ticks: 0,
            stall_ticks: 0,
        }
    }

    /// The phase.
    #[must_use]
    pub const fn phase(&self) -> Phase {
        self.phase
    }

    /// The current task and leg.
    #[must_use]
    pub const fn leg(&self) -> (u8, u8) {
        (self.task, self.leg)
    }

    /// Whether a detour is being followed.
    #[must_use]
    pub const fn detour(&self) -> bool {
        self.detour
    }

    /// Followed ticks on the current leg, up to the leg time limit.
    #[must_use]
    pub const fn leg_ticks(&self) -> u16 {
        self.leg_ticks
    }

    /// Consecutive followed ticks without progress, up to the stall delay.
    #[must_use]
    pub const fn stall_ticks(&self) -> u16 {
        self.stall_ticks
    }

    fn abort(&mut self, reason: StopReason) {
        self.phase = Phase::Aborted(reason);
        self.detour = false;
    }

    /// Moves to the next leg, the next task or Done; a task of no leg aborts.
    //= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
    //# Reached MUST end a detour, or else move to the next leg, the next task after
    //# a task's last leg, and Done after the last task; no leg and no task MUST be
    //# skipped, and the machine MUST never return to an earlier leg.
    fn advance(&mut self, shape: &Shape) {
        self.leg_ticks = 0;
        self.stall_ticks = 0;
        if self.detour {
            self.detour = false;
            return;
        }
        let legs = shape.task(self.task).map_or(0, |(_, legs)| legs);
        if self.leg.saturating_add(1) < legs {
            self.leg = self.leg.saturating_add(1);
            return;
        }
        self.leg = 0;
        self.task = self.task.saturating_add(1);
        match shape.task(self.task) {
            None => self.phase = Phase::Done,
            Some((_, 0)) => self.abort(StopReason::EmptyTask),
            Some(_) => {}
        }
    }
}

/// The stop a hazard or the localisation imposes in this tick, and whether a
/// detour starts.
//= spec/emmi2024.md#em-mission-obstacle-obstacles
//# With the hazard Critical the command MUST be Stop with the reason Obstacle,
//# for as long as the hazard lasts.
//= spec/emmi2024.md#em-mission-obstacle-obstacles
//# With the hazard Warning on a road, the machine MUST re-plan the leg through
//# the detour waypoint, and stop with the reason NoDetour when there is none;
//# inside a field it MUST NOT re-plan but stop with the reason ObstacleInField.
//= spec/emmi2024.md#em-loc-stop-lost-localisation-stops
//# While the localisation is Lost the command MUST be Stop with the reason
//# LocalisationLost, and the mission MUST go on from the current leg when a
//# valid fix returns.
fn hold(config: &MachineConfig, events: &Events) -> Result<bool, StopReason> {
    if events.hazard == HazardLevel::Critical && !ignores_critical(config) {
        return Err(StopReason::Obstacle);
    }
    if events.localisation == LocalisationStatus::Lost {
        return Err(StopReason::LocalisationLost);
    }
    match events.hazard {
        HazardLevel::Warning { .. } if events.in_field && !replans_in_field(config) => {
            Err(StopReason::ObstacleInField)
        }
        HazardLevel::Warning { detour: true } => Ok(true),
        HazardLevel::Warning { detour: false } => Err(StopReason::NoDetour),
        //= spec/emmi2024.md#em-mission-obstacle-obstacles
        //# With the hazard NoDetourOnRoad the command MUST be Stop with the
        //# reason NoDetourOnRoad, for as long as the hazard lasts, without
        //# re-planning.
        HazardLevel::NoDetourOnRoad => Err(StopReason::NoDetourOnRoad),
        HazardLevel::Clear | HazardLevel::Critical => Ok(false),
    }
}

#[cfg(feature = "fault-injection")]
fn ignores_critical(config: &MachineConfig) -> bool {
    config.fault() == Some(Fault::IgnoreCritical)
}

#[cfg(not(feature = "fault-injection"))]
const fn ignores_critical(_: &MachineConfig) -> bool {
    false
}

#[cfg(feature = "fault-injection")]
fn replans_in_field(config: &MachineConfig) -> bool {
    config.fault() == Some(Fault::ReplanInField)
}

#[cfg(not(feature = "fault-injection"))]
const fn replans_in_field(_: &MachineConfig) -> bool {
    false
}

/// One control tick of the mission machine (Emmi 2024, sections 3.1-3.2), as
/// a pure function: the next state and this tick's output.
///
/// In order: a detour is dropped in a field; an unplannable leg aborts; the
/// arrival ends the detour or the leg (GoalMissed aborts); obstacles and the
/// localisation may hold the robot or start a detour; a followed tick counts
/// toward the stall delay and the leg time limit. Total, no panic, no
/// allocation; EM-MISSION-M1 to M5 are checked over every reachable state by
/// `fieldguide-proofs`.
//= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
//# In each tick it MUST read the events: the hazard (Clear, Warning with or
//# without a detour, Critical), whether the robot is inside the task's field,
//# the localisation (GNSS, odometry, Lost), whether the leg's plan exists,
//# whether the robot progressed, and the arrival (en route, reached within the
//# tolerance, missed).
//= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
//# While Running, the command MUST be Follow of the current leg (and detour)
//# unless a rule of EM-MISSION-OBSTACLE, EM-LOC-STOP or EM-MISSION-MONITOR
//# makes it Stop with a reason; Done and Aborted MUST command Stop, Aborted
//# with its reason.
//= spec/emmi2024.md#em-mission-obstacle-obstacles
//# A detour MUST end when its waypoint is reached, the leg being planned again
//# from there to its goal, and a detour MUST be dropped when the robot is in a
//# field.
//= spec/emmi2024.md#em-mission-monitor-malfunctions
//# While Follow is commanded, a run of ticks without progress as long as the
//# stall delay MUST abort the mission with the reason NoProgress, and a leg
//# followed for the leg time limit without being reached MUST abort it with the
//# reason LegTimeout.
//= spec/emmi2024.md#em-mission-monitor-malfunctions
//# A leg whose end is passed without its goal being within the tolerance MUST
//# abort the mission with the reason GoalMissed.
//= spec/emmi2024.md#em-mission-m1-a-critical-obstacle-always-stops
//# In every reachable state, a tick with the hazard Critical MUST command Stop.
//= spec/emmi2024.md#em-mission-m2-no-re-planning-in-a-field
//# In every reachable state, a tick inside a field MUST NOT start a detour nor
//# command one.
//= spec/emmi2024.md#em-mission-m3-lost-localisation-stops
//# In every reachable state, a tick with the localisation Lost MUST command
//# Stop.
//= spec/emmi2024.md#em-mission-m4-every-task-ends-within-a-bound
//# When every tick of a task has the hazard Clear and a valid localisation, the
//# task MUST end (the next task, Done or Aborted) within its number of legs
//# times the leg time limit, plus one tick per leg, ticks.
//= spec/emmi2024.md#em-mission-m5-never-backwards
//# In every reachable state, the command MUST be Stop or Follow of a leg no
//# earlier than any leg commanded before, at a speed that is never negative.
#[must_use]
pub fn step(
    config: &MachineConfig,
    shape: &Shape,
    state: &MissionState,
    events: &Events,
) -> (MissionState, Output) {
    let mut next = *state;
    let before = (state.task, state.leg, state.detour);
    if next.phase == Phase::Running {
        if events.in_field && next.detour {
            next.detour = false;
        }
        if !events.plan_ready {
            next.abort(StopReason::Unplannable);
        } else {
            match events.arrival {
                Arrival::EnRoute => {}
                Arrival::Reached => next.advance(shape),
                Arrival::Missed => next.abort(StopReason::GoalMissed),
            }
        }
    }
    let command = match next.phase {
        Phase::Done => Command::Stop(StopReason::Finished),
        Phase::Aborted(reason) => Command::Stop(reason),
        Phase::Running => match hold(config, events) {
            Err(reason) => Command::Stop(reason),
            Ok(detour) => {
                next.detour = next.detour || detour;
                follow(config, shape, &mut next, events)
            }
        },
    };
    //= spec/emmi2024.md#em-mission-obstacle-obstacles
    //# A detour MUST be planned once per obstacle: the machine MUST ask for a
    //# plan only when the leg or the detour changes, and while a detour is
    //# followed a further warning MUST NOT re-plan it unless its waypoint lies
    //# farther than the tolerance from the one followed.
    let replan =
        matches!(command, Command::Follow(_)) && (next.task, next.leg, next.detour) != before;
    let output = Output {
        command,
        phase: next.phase,
        replan,
    };
    (next, output)
}

/// A followed tick: counts toward the stall delay and the leg time limit and
/// aborts when one is reached; otherwise Follow of the current leg.
fn follow(
    config: &MachineConfig,
    shape: &Shape,
    next: &mut MissionState,
    events: &Events,
) -> Command {
    next.leg_ticks = next.leg_ticks.saturating_add(1).min(config.leg_ticks());
    next.stall_ticks = if events.progressing {
        0
    } else {
        next.stall_ticks.saturating_add(1).min(config.stall_ticks())
    };
    if next.stall_ticks >= config.stall_ticks() {
        next.abort(StopReason::NoProgress);
        return Command::Stop(StopReason::NoProgress);
    }
    if next.leg_ticks >= config.leg_ticks() {
        next.abort(StopReason::LegTimeout);
        return Command::Stop(StopReason::LegTimeout);
    }
    //= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
    //# An Approximation leg MUST be planned with the planner EM-PLANNER chooses from
    //# the robot's pose to the waypoint; a Treatment turn MUST be planned with
    //# GoToGoal to the row's start, and a pass with LineFollowing along the row with
    //# the tool on; the tool MUST be off in every other leg and whenever the command
    //# is Stop.
    let treatment = shape
        .task(next.task)
        .is_some_and(|(kind, _)| kind == TaskKind::Treatment);
    Command::Follow(LegRef {
        task: next.task,
        leg: next.leg,
        detour: next.detour,
        tool_on: treatment && next.leg & 1 == 1 && !next.detour,
    })
}
