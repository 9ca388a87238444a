//! An observer of the switching machine that keeps the history the properties
//! need (counters of consecutive ticks, the previous mode, the last tick's
//! facts) and states each property of `spec/pierre2022.md` as a predicate on
//! that history. It never looks inside the machine: it sees inputs and outputs
//! only, and counts with the independently computed [`Spec`].
//!
//! Bounded response ("after n ticks of X, Y") is a counter of consecutive
//! ticks of X, saturating at n, and a state predicate "counter ≥ n ⇒ Y": a
//! safety property, checked with `always`, never with `eventually`.

use fieldguide::supervisor::switching::{CommandSource, Input, Mode, Output};
use fieldguide::Verdict;

use super::Spec;

/// The properties, named as in `spec/pierre2022.md`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Property {
    /// SW-S1: mode changes (Stop aside) at least D ticks apart.
    S1NoChattering,
    /// SW-S2: entry only after the entry delay of evidence, priority respected.
    S2EntryNeedsEvidence,
    /// SW-S3: every command source valid in its tick.
    S3CommandsValid,
    /// SW-COMMAND-VALID: the source is exactly the one the rule names.
    CommandSourceRule,
    /// SW-S4: Stop exactly after the Stop delay without a source.
    S4StopExactly,
    /// SW-L1: entry evidence for the entry delay brings the mode.
    L1EnterBringsMode,
    /// SW-L2: exit evidence for the exit delay brings path tracking.
    L2ExitBringsPathTracking,
    /// SW-P1: a plan-inconsistent line is left after the plan delay.
    P1InconsistentLineLeft,
}

impl Property {
    /// Every property.
    pub const ALL: [Self; 8] = [
        Self::S1NoChattering,
        Self::S2EntryNeedsEvidence,
        Self::S3CommandsValid,
        Self::CommandSourceRule,
        Self::S4StopExactly,
        Self::L1EnterBringsMode,
        Self::L2ExitBringsPathTracking,
        Self::P1InconsistentLineLeft,
    ];
}

/// The observed history of one run, after its last tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Monitor<const K: usize> {
    /// Mode before the last tick.
    pub prev_mode: Mode,
    /// Mode after the last tick.
    pub mode: Mode,
    /// Command source of the last tick.
    pub source: CommandSource,
    /// Whether each behaviour's estimate was valid (Enter or Hold) in the last tick.
    pub valid: [bool; K],
    /// Whether localisation was valid in the last tick.
    pub localisation_valid: bool,
    /// Consecutive ticks of entry evidence per behaviour, saturating at its entry delay.
    pub entry: [u16; K],
    /// Consecutive ticks of Exit/Absent with valid localisation and no other
    /// behaviour's entry evidence, per behaviour, saturating at its exit delay.
    pub quiet: [u16; K],
    /// Consecutive ticks of valid plan-inconsistent estimates with no other
    /// behaviour's entry evidence, per behaviour, saturating at the plan delay.
    pub inconsistent: [u16; K],
    /// Consecutive ticks without an available source, saturating at the Stop delay.
    pub sourceless: u16,
    /// Ticks since the last counted mode change (Stop aside), saturating at D.
    pub since_change: u16,
    /// Gap before the last counted mode change, saturating at D (D initially).
    pub last_gap: u16,
}

/// Whether a verdict lets a behaviour command (Enter or Hold).
const fn is_valid(verdict: Verdict) -> bool {
    verdict.estimate_is_valid()
}

/// One more tick of a run, saturating at `limit`.
fn bump(counter: u16, condition: bool, limit: u16) -> u16 {
    if condition {
        counter.saturating_add(1).min(limit)
    } else {
        0
    }
}

impl<const K: usize> Monitor<K> {
    /// The history before the first tick: path tracking, no change yet.
    #[must_use]
    pub fn new(spec: &Spec<K>) -> Self {
        Self {
            prev_mode: Mode::PathTracking,
            mode: Mode::PathTracking,
            source: CommandSource::None,
            valid: [false; K],
            localisation_valid: false,
            entry: [0; K],
            quiet: [0; K],
            inconsistent: [0; K],
            sourceless: 0,
            since_change: spec.min_dwell(),
            last_gap: spec.min_dwell(),
        }
    }

    /// Records one tick: its input and the machine's output.
    pub fn observe(&mut self, spec: &Spec<K>, input: &Input<K>, output: &Output) {
        let plan_check = spec.plan.is_some();
        let evidence: [bool; K] = input
            .behaviours
            .map(|r| r.verdict == Verdict::Enter && (!plan_check || r.plan_consistent));
        let others_evidence = |i: usize| evidence.iter().enumerate().any(|(j, &e)| j != i && e);
        let loc = input.localisation_valid;

        for (i, report) in input.behaviours.iter().enumerate() {
            let valid = is_valid(report.verdict);
            let calm = !others_evidence(i);
            self.valid[i] = valid;
            self.entry[i] = bump(self.entry[i], evidence[i], spec.enter[i]);
            self.quiet[i] = bump(self.quiet[i], !valid && loc && calm, spec.exit[i]);
            self.inconsistent[i] = match spec.plan {
                Some(plan) => bump(
                    self.inconsistent[i],
                    valid && !report.plan_consistent && calm,
                    plan,
                ),
                None => 0,
            };
        }
        self.localisation_valid = loc;

        let available = loc
            || match output.mode {
                Mode::Behaviour(i) => self.valid.get(i).copied().unwrap_or(false),
                Mode::PathTracking | Mode::Stop => false,
            };
        self.sourceless = bump(self.sourceless, !available, spec.stop);

        let dwell = spec.min_dwell();
        self.prev_mode = self.mode;
        self.mode = output.mode;
        self.source = output.source;
        self.since_change = self.since_change.saturating_add(1).min(dwell);
        if self.prev_mode != self.mode {
            if self.prev_mode == Mode::Stop || self.mode == Mode::Stop {
                // SW-S1: a Stop restarts the count; the next change is free.
                self.since_change = dwell;
            } else {
                self.last_gap = self.since_change;
                self.since_change = 0;
            }
        }
    }

    /// Whether `property` holds after the last tick.
    #[must_use]
    pub fn holds(&self, spec: &Spec<K>, property: Property) -> bool {
        match property {
            Property::S1NoChattering => self.last_gap >= spec.min_dwell(),
            Property::S2EntryNeedsEvidence => self.entry_is_justified(spec),
            Property::S3CommandsValid => self.source_is_valid(),
            Property::CommandSourceRule => self.source == self.rule_source(),
            Property::S4StopExactly => (self.sourceless >= spec.stop) == (self.mode == Mode::Stop),
            Property::L1EnterBringsMode => self.entry_brings_mode(spec),
            Property::L2ExitBringsPathTracking => self
                .quiet
                .iter()
                .zip(spec.exit.iter())
                .enumerate()
                .all(|(i, (&quiet, &exit))| {
                    quiet < exit || !(self.mode == Mode::Behaviour(i) || self.mode == Mode::Stop)
                }),
            Property::P1InconsistentLineLeft => match spec.plan {
                Some(plan) => self
                    .inconsistent
                    .iter()
                    .enumerate()
                    .all(|(i, &run)| run < plan || self.mode != Mode::Behaviour(i)),
                None => true,
            },
        }
    }

    /// The first property that fails after the last tick, if any.
    #[must_use]
    pub fn first_violation(&self, spec: &Spec<K>) -> Option<Property> {
        Property::ALL
            .into_iter()
            .find(|&property| !self.holds(spec, property))
    }

    /// SW-S2: a change into mode i happens only with i's evidence complete and
    /// no higher-priority evidence in that tick.
    fn entry_is_justified(&self, spec: &Spec<K>) -> bool {
        match self.mode {
            Mode::Behaviour(i) if self.prev_mode != self.mode => {
                let complete = self
                    .entry
                    .get(i)
                    .is_some_and(|&run| spec.enter.get(i).is_some_and(|&needed| run >= needed));
                let priority = self.entry.iter().take(i).all(|&run| run == 0);
                complete && priority
            }
            _ => true,
        }
    }

    /// SW-S3: the last tick's source was valid in that tick.
    fn source_is_valid(&self) -> bool {
        match self.source {
            CommandSource::Behaviour(i) => {
                self.mode == Mode::Behaviour(i) && self.valid.get(i).copied().unwrap_or(false)
            }
            CommandSource::PathTracking => self.localisation_valid && self.mode != Mode::Stop,
            CommandSource::None => true,
        }
    }

    /// SW-COMMAND-VALID: the source the rule names for the last tick.
    fn rule_source(&self) -> CommandSource {
        let path = if self.localisation_valid {
            CommandSource::PathTracking
        } else {
            CommandSource::None
        };
        match self.mode {
            Mode::Stop => CommandSource::None,
            Mode::PathTracking => path,
            Mode::Behaviour(i) if self.valid.get(i).copied().unwrap_or(false) => {
                CommandSource::Behaviour(i)
            }
            Mode::Behaviour(_) => path,
        }
    }

    /// SW-L1: a complete run of evidence with no higher-priority evidence
    /// means that behaviour's mode or a higher-priority one.
    fn entry_brings_mode(&self, spec: &Spec<K>) -> bool {
        self.entry
            .iter()
            .zip(spec.enter.iter())
            .enumerate()
            .all(|(j, (&run, &needed))| {
                let higher_quiet = self.entry.iter().take(j).all(|&r| r == 0);
                let obliged = run >= needed && higher_quiet;
                !obliged || matches!(self.mode, Mode::Behaviour(m) if m <= j)
            })
    }
}
