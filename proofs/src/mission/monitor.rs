//! An observer of the mission machine that keeps the history the properties
//! need and states EM-MISSION-M1 to M5 as predicates on it. It sees the
//! events and the outputs only, and counts with the leg time limit and the
//! number of legs per task given to it, independently of the machine.

use fieldguide::supervisor::mission::{
    step, Command, Events, HazardLevel, LocalisationStatus, MachineConfig, MissionState, Output,
    Phase, Shape,
};

/// The properties, named as in `spec/emmi2024.md`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Property {
    /// EM-MISSION-M1: a critical obstacle always stops.
    M1CriticalStops,
    /// EM-MISSION-M2: no re-planning in a field.
    M2NoReplanInField,
    /// EM-MISSION-M3: lost localisation stops.
    M3LostStops,
    /// EM-MISSION-M4: every task ends within a bound.
    M4TaskBound,
    /// EM-MISSION-M5: never backwards.
    M5NeverBackwards,
}

impl Property {
    /// Every property.
    pub const ALL: [Self; 5] = [
        Self::M1CriticalStops,
        Self::M2NoReplanInField,
        Self::M3LostStops,
        Self::M4TaskBound,
        Self::M5NeverBackwards,
    ];
}

/// The observed history of one run, after its last tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Monitor {
    /// The last tick's events, when there was a tick.
    pub events: Option<Events>,
    /// The last tick's output.
    pub output: Option<Output>,
    /// Whether the last tick started or kept a detour in a field.
    pub detour_in_field: bool,
    /// The latest leg commanded before the last tick.
    pub latest: Option<(u8, u8)>,
    /// The task being executed, as last commanded.
    pub task: Option<u8>,
    /// Ticks since that task was first commanded, saturating past its bound.
    pub task_ticks: u32,
    /// Whether every tick since had the hazard Clear and a valid localisation.
    pub clean: bool,
    /// The leg time limit, ticks.
    pub leg_ticks: u16,
    /// The number of legs of each task (at most 8 tasks).
    pub legs: [u8; 8],
}

impl Monitor {
    /// A monitor of a mission of `legs` legs per task (the first 8) with a
    /// leg time limit of `leg_ticks`.
    #[must_use]
    pub fn new(legs: &[u8], leg_ticks: u16) -> Self {
        let mut all = [0; 8];
        for (slot, n) in all.iter_mut().zip(legs) {
            *slot = *n;
        }
        Self {
            events: None,
            output: None,
            detour_in_field: false,
            latest: None,
            task: None,
            task_ticks: 0,
            clean: true,
            leg_ticks,
            legs: all,
        }
    }

    /// The bound of EM-MISSION-M4 for `task`: legs × (leg time limit + 1).
    #[must_use]
    pub fn bound(&self, task: u8) -> u32 {
        let legs = self.legs.get(usize::from(task)).copied().unwrap_or(0);
        u32::from(legs).saturating_mul(u32::from(self.leg_ticks).saturating_add(1))
    }

    /// Records one tick: its events, the machine's output and whether the
    /// state after it holds a detour.
    pub fn observe(&mut self, events: &Events, output: &Output, detour_after: bool) {
        if let Some(Output {
            command: Command::Follow(leg),
            ..
        }) = self.output
        {
            let leg = (leg.task, leg.leg);
            if self.latest.is_none_or(|latest| leg > latest) {
                self.latest = Some(leg);
            }
        }
        let followed_detour = matches!(output.command, Command::Follow(l) if l.detour);
        self.detour_in_field = events.in_field && (followed_detour || detour_after);
        let clean_tick =
            events.hazard == HazardLevel::Clear && events.localisation != LocalisationStatus::Lost;
        if output.phase != Phase::Running {
            self.task = None;
            self.task_ticks = 0;
            self.clean = true;
        } else {
            let commanded = match output.command {
                Command::Follow(leg) => Some(leg.task),
                Command::Stop(_) => self.task,
            };
            if commanded.is_some() && commanded != self.task {
                self.task = commanded;
                self.task_ticks = 1;
                self.clean = clean_tick;
            } else if self.task.is_some() {
                let cap = self.task.map_or(0, |t| self.bound(t)).saturating_add(1);
                self.task_ticks = self.task_ticks.saturating_add(1).min(cap);
                self.clean = self.clean && clean_tick;
            }
        }
        self.events = Some(*events);
        self.output = Some(*output);
    }

    /// Whether `property` holds after the last tick.
    #[must_use]
    pub fn holds(&self, property: Property) -> bool {
        let (Some(events), Some(output)) = (self.events, self.output) else {
            return true;
        };
        let stops = matches!(output.command, Command::Stop(_));
        match property {
            Property::M1CriticalStops => events.hazard != HazardLevel::Critical || stops,
            Property::M2NoReplanInField => !self.detour_in_field,
            Property::M3LostStops => events.localisation != LocalisationStatus::Lost || stops,
            Property::M4TaskBound => match self.task {
                Some(task) if self.clean && output.phase == Phase::Running => {
                    self.task_ticks <= self.bound(task)
                }
                _ => true,
            },
            Property::M5NeverBackwards => match output.command {
                Command::Stop(_) => true,
                Command::Follow(leg) => self.latest.is_none_or(|l| (leg.task, leg.leg) >= l),
            },
        }
    }

    /// The first property that fails, if any.
    #[must_use]
    pub fn first_violation(&self) -> Option<Property> {
        Property::ALL.into_iter().find(|p| !self.holds(*p))
    }
}

/// A property that failed, the tick (0-based) and the history at that point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Violation {
    /// Index of the tick after which the property failed.
    pub tick: usize,
    /// The failed property.
    pub property: Property,
    /// The history after that tick.
    pub monitor: Monitor,
}

/// Runs `events` through the real machine from its initial state, checking
/// every property after each tick.
///
/// # Errors
/// The first violated property, with its tick.
pub fn check_run(
    config: &MachineConfig,
    shape: &Shape,
    legs: &[u8],
    events: impl IntoIterator<Item = Events>,
) -> Result<(), Violation> {
    let mut state = MissionState::initial(shape);
    let mut monitor = Monitor::new(legs, config.leg_ticks());
    for (tick, ev) in events.into_iter().enumerate() {
        let (next, output) = step(config, shape, &state, &ev);
        state = next;
        monitor.observe(&ev, &output, state.detour());
        if let Some(property) = monitor.first_violation() {
            return Err(Violation {
                tick,
                property,
                monitor,
            });
        }
    }
    Ok(())
}
