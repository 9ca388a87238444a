//! The stateright model of the mission machine: its transitions call the
//! real `fieldguide::supervisor::mission::step` with abstract events, its
//! state is the machine's state plus the [`Monitor`]'s history, and each
//! property EM-MISSION-M1 to M5 is an `always` check on that state.

use fieldguide::supervisor::mission::{
    step, Arrival, Command, Events, HazardLevel, LocalisationStatus, MachineConfig, MissionState,
    Phase, Shape, StopReason,
};
use stateright::{Model, Property as StaterightProperty};

use super::{Monitor, Property};

/// Every abstract tick: each hazard (Clear, Warning with and without a
/// detour, Critical, no detour on the road), in a field or on a road, each localisation, the plan
/// ready or not, progress or not, and each arrival.
#[must_use]
pub fn all_events() -> Vec<Events> {
    let hazards = [
        HazardLevel::Clear,
        HazardLevel::Warning { detour: true },
        HazardLevel::Warning { detour: false },
        HazardLevel::Critical,
        HazardLevel::NoDetourOnRoad,
    ];
    let locs = [
        LocalisationStatus::Gnss,
        LocalisationStatus::Odometry,
        LocalisationStatus::Lost,
    ];
    let arrivals = [Arrival::EnRoute, Arrival::Reached, Arrival::Missed];
    let mut all = Vec::new();
    for hazard in hazards {
        for in_field in [false, true] {
            for localisation in locs {
                for plan_ready in [true, false] {
                    for progressing in [true, false] {
                        for arrival in arrivals {
                            all.push(Events {
                                hazard,
                                in_field,
                                localisation,
                                plan_ready,
                                progressing,
                                arrival,
                            });
                        }
                    }
                }
            }
        }
    }
    all
}

/// A state of the model: the machine's state and the monitor's history.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ModelState {
    /// The real machine's state.
    pub machine: MissionState,
    /// The history the properties read.
    pub monitor: Monitor,
}

/// The mission machine as a stateright model.
#[derive(Debug, Clone)]
pub struct MissionModel {
    /// The configuration the real `step` runs with.
    pub config: MachineConfig,
    /// The mission's shape.
    pub shape: Shape,
    /// The legs per task and the leg time limit the properties count with.
    pub legs: Vec<u8>,
    /// The leg time limit, ticks, as specified.
    pub leg_ticks: u16,
    /// The abstract ticks explored from every state.
    pub events: Vec<Events>,
}

impl MissionModel {
    /// A model of `config` on a mission of `shape`, checked against `legs`
    /// legs per task and a leg time limit of `leg_ticks`, over every abstract
    /// tick.
    #[must_use]
    pub fn new(config: MachineConfig, shape: Shape, legs: &[u8], leg_ticks: u16) -> Self {
        Self {
            config,
            shape,
            legs: legs.to_vec(),
            leg_ticks,
            events: all_events(),
        }
    }
}

fn holds(state: &ModelState, property: Property) -> bool {
    state.monitor.holds(property)
}

impl Model for MissionModel {
    type State = ModelState;
    type Action = Events;

    fn init_states(&self) -> Vec<Self::State> {
        vec![ModelState {
            machine: MissionState::initial(&self.shape),
            monitor: Monitor::new(&self.legs, self.leg_ticks),
        }]
    }

    fn actions(&self, _state: &Self::State, actions: &mut Vec<Self::Action>) {
        actions.extend(self.events.iter().copied());
    }

    fn next_state(&self, last: &Self::State, events: Self::Action) -> Option<Self::State> {
        let (machine, output) = step(&self.config, &self.shape, &last.machine, &events);
        let mut monitor = last.monitor;
        monitor.observe(&events, &output, machine.detour());
        Some(ModelState { machine, monitor })
    }

    fn properties(&self) -> Vec<StaterightProperty<Self>> {
        vec![
            StaterightProperty::always("EM-MISSION-M1 a critical obstacle always stops", |_, s| {
                holds(s, Property::M1CriticalStops)
            }),
            StaterightProperty::always("EM-MISSION-M2 no re-planning in a field", |_, s| {
                holds(s, Property::M2NoReplanInField)
            }),
            StaterightProperty::always("EM-MISSION-M3 lost localisation stops", |_, s| {
                holds(s, Property::M3LostStops)
            }),
            StaterightProperty::always("EM-MISSION-M4 every task ends within a bound", |_, s| {
                holds(s, Property::M4TaskBound)
            }),
            StaterightProperty::always("EM-MISSION-M5 never backwards", |_, s| {
                holds(s, Property::M5NeverBackwards)
            }),
            // Non-vacuity: the interesting situations are reached.
            StaterightProperty::sometimes("reaches Done", |_, s: &ModelState| {
                s.machine.phase() == Phase::Done
            }),
            StaterightProperty::sometimes(
                "follows a detour on a road",
                |_, s: &ModelState| matches!(s.monitor.output, Some(o) if matches!(o.command, Command::Follow(l) if l.detour)),
            ),
            StaterightProperty::sometimes(
                "stops for an obstacle in a field",
                |_, s: &ModelState| matches!(s.monitor.output, Some(o) if o.command == Command::Stop(StopReason::ObstacleInField)),
            ),
            StaterightProperty::sometimes("aborts on a leg timeout", |_, s: &ModelState| {
                s.machine.phase() == Phase::Aborted(StopReason::LegTimeout)
            }),
            StaterightProperty::sometimes("aborts without progress", |_, s: &ModelState| {
                s.machine.phase() == Phase::Aborted(StopReason::NoProgress)
            }),
            StaterightProperty::sometimes(
                "treats a row with the tool on",
                |_, s: &ModelState| matches!(s.monitor.output, Some(o) if o.command.tool_on()),
            ),
        ]
    }
}
