//! The state and the transition function of the switching machine
//! (`spec/pierre2022.md`, SW-ENTER, SW-EXIT, SW-COMMAND-VALID, SW-STOP,
//! SW-PLAN-CONSISTENCY).

#[cfg(feature = "fault-injection")]
use super::config::Fault;
use super::config::SwitchingConfig;
use super::{CommandSource, Input, Mode, Output, Report};
use crate::perception::Verdict;

/// Everything the machine remembers between ticks: its mode and four kinds of
/// tick counters, each saturating at the delay it is compared with, so the
/// state space is finite (the proofs explore all of it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SwitchingState<const K: usize> {
    mode: Mode,
    entry_run: [u16; K],
    exit_run: u16,
    plan_run: u16,
    sourceless_run: u16,
}

impl<const K: usize> SwitchingState<K> {
    /// The initial state: path tracking, every counter at zero.
    //= spec/pierre2022.md#sw-modes-modes-and-priority
    //# The switching machine MUST have exactly these modes: path tracking, one
    //# specialised mode per configured specialised behaviour, and Stop; it MUST
    //# start in path tracking.
    #[must_use]
    pub const fn initial() -> Self {
        Self {
            mode: Mode::PathTracking,
            entry_run: [0; K],
            exit_run: 0,
            plan_run: 0,
            sourceless_run: 0,
        }
    }

    /// The current mode.
    #[must_use]
    pub const fn mode(&self) -> Mode {
        self.mode
    }

    /// Consecutive ticks of entry evidence of behaviour `index`, up to its
    /// entry delay (SW-ENTER); `None` for an index that does not exist.
    #[must_use]
    pub fn entry_run(&self, index: usize) -> Option<u16> {
        self.entry_run.get(index).copied()
    }

    /// Consecutive ticks of exit evidence of the active behaviour, up to its
    /// exit delay (SW-EXIT); 0 outside specialised modes.
    #[must_use]
    pub const fn exit_run(&self) -> u16 {
        self.exit_run
    }

    /// Ticks of plan-inconsistent valid estimates of the active behaviour, up
    /// to the plan delay (SW-PLAN-CONSISTENCY); 0 outside specialised modes.
    #[must_use]
    pub const fn plan_run(&self) -> u16 {
        self.plan_run
    }

    /// Consecutive ticks without a command source, up to the Stop delay (SW-STOP).
    #[must_use]
    pub const fn sourceless_run(&self) -> u16 {
        self.sourceless_run
    }
}

impl<const K: usize> Default for SwitchingState<K> {
    fn default() -> Self {
        Self::initial()
    }
}

/// A switching machine: its validated configuration and its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switching<const K: usize> {
    config: SwitchingConfig<K>,
    state: SwitchingState<K>,
}

impl<const K: usize> Switching<K> {
    /// A machine in its initial state (path tracking).
    #[must_use]
    pub const fn new(config: SwitchingConfig<K>) -> Self {
        Self {
            config,
            state: SwitchingState::initial(),
        }
    }

    /// One control tick: consumes this tick's reports, returns the mode and
    /// the command source ([`step`]).
    pub fn step(&mut self, input: &Input<K>) -> Output {
        let (state, output) = step(&self.config, &self.state, input);
        self.state = state;
        output
    }

    /// The current mode.
    #[must_use]
    pub const fn mode(&self) -> Mode {
        self.state.mode
    }

    /// The current state.
    #[must_use]
    pub const fn state(&self) -> &SwitchingState<K> {
        &self.state
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &SwitchingConfig<K> {
        &self.config
    }
}

/// Whether a report is entry evidence (SW-ENTER): an Enter verdict whose line,
/// when plan consistency is configured, agrees with the plan.
//= spec/pierre2022.md#sw-enter-entering-a-specialised-mode
//# A tick MUST count as entry evidence for a behaviour only when its verdict is
//# Enter and, when plan consistency is configured, its line is consistent with
//# the planned path; any other verdict, Hold included, MUST restart the count.
fn is_entry_evidence(report: &Report, plan_check: bool) -> bool {
    report.verdict == Verdict::Enter && (!plan_check || report.plan_consistent)
}

/// Whether behaviour `index`'s entry evidence has lasted its entry delay.
fn entry_is_complete<const K: usize>(
    config: &SwitchingConfig<K>,
    state: &SwitchingState<K>,
    index: usize,
) -> bool {
    let needed = config.ticks(index).map_or(1, |t| t.enter);
    #[cfg(feature = "fault-injection")]
    let needed = if config.fault() == Some(Fault::EnterOneTickEarly) {
        needed.saturating_sub(1)
    } else {
        needed
    };
    state
        .entry_run(index)
        .is_some_and(|run| run > 0 && run >= needed)
}

/// The command source of `mode` for this tick's input (SW-COMMAND-VALID).
//= spec/pierre2022.md#sw-command-valid-command-only-from-a-valid-estimate
//# The command source MUST be the active behaviour when the mode is its
//# specialised mode and its verdict is Enter or Hold; otherwise path tracking
//# when the mode is not Stop and localisation is valid; otherwise there MUST be
//# no command source.
fn command_source<const K: usize>(
    #[allow(unused_variables)] config: &SwitchingConfig<K>,
    mode: Mode,
    input: &Input<K>,
) -> CommandSource {
    let path_tracking = if input.localisation_valid {
        CommandSource::PathTracking
    } else {
        CommandSource::None
    };
    match mode {
        Mode::Stop => CommandSource::None,
        Mode::PathTracking => path_tracking,
        Mode::Behaviour(active) => {
            let valid = input
                .behaviours
                .get(active)
                .is_some_and(|r| r.verdict.estimate_is_valid());
            #[cfg(feature = "fault-injection")]
            let valid = valid || config.fault() == Some(Fault::SteerWithInvalidEstimate);
            if valid {
                CommandSource::Behaviour(active)
            } else {
                path_tracking
            }
        }
    }
}

/// One control tick of the switching machine (Pierre 2022, section 3), as a
/// pure function: the next state and this tick's output.
///
/// In order: entry evidence is counted for every behaviour (SW-ENTER); the
/// active behaviour's exit and plan-inconsistency evidence is counted
/// (SW-EXIT, SW-PLAN-CONSISTENCY); the mode changes by those rules; the
/// command source of the new mode is chosen (SW-COMMAND-VALID); after the
/// Stop delay without a source the mode is Stop (SW-STOP). Total, no panic,
/// no allocation; the properties SW-S1 to SW-P1 are proven over every
/// reachable state by `fieldguide-proofs`.
//= spec/pierre2022.md#sw-enter-entering-a-specialised-mode
//# The entry candidate MUST be the highest-priority behaviour with entry
//# evidence in the current tick, and the machine MUST enter the candidate's
//# mode in the tick where its evidence has lasted its entry delay, from path
//# tracking, from Stop, or from the mode of a lower-priority behaviour.
//= spec/pierre2022.md#sw-enter-entering-a-specialised-mode
//# A lower-priority behaviour MUST NOT take over the mode of a higher-priority
//# behaviour, except instead of a Stop (SW-STOP), and no behaviour MUST be
//# entered while a higher-priority behaviour has entry evidence in the same
//# tick.
//= spec/pierre2022.md#sw-exit-leaving-a-specialised-mode
//# In a specialised mode, a tick MUST count as exit evidence when the active
//# behaviour's verdict is Exit or Absent, and any Enter or Hold verdict MUST
//# restart that count.
//= spec/pierre2022.md#sw-exit-leaving-a-specialised-mode
//# When the exit evidence has lasted the behaviour's exit delay, or its plan
//# inconsistency has lasted the plan delay (SW-PLAN-CONSISTENCY), the machine
//# MUST leave the mode: to the entry candidate's mode when the candidate's
//# evidence has lasted its entry delay, to path tracking when no behaviour has
//# entry evidence, and otherwise it MUST stay until one of these holds.
//= spec/pierre2022.md#sw-plan-consistency-line-consistent-with-the-planned-path
//# When plan consistency is configured, the machine MUST leave the active
//# specialised mode (as in SW-EXIT) once that behaviour has given a valid
//# estimate inconsistent with the plan in as many ticks as the plan delay, with
//# no consistent valid estimate between them; a tick without a valid estimate
//# MUST neither add to nor restart that count.
//= spec/pierre2022.md#sw-stop-stop-without-a-valid-source
//# When no command source has existed for the Stop delay, converted to ticks as
//# in SW-DELAYS, the mode MUST be Stop, unless a behaviour whose entry evidence
//# has lasted its entry delay can take over, and then the machine MUST enter
//# that behaviour's mode; Stop MUST NOT be entered otherwise.
//= spec/pierre2022.md#sw-stop-stop-without-a-valid-source
//# The machine MUST stay in Stop until localisation is valid, then go to path
//# tracking, or until a behaviour's entry evidence has lasted its entry delay,
//# then go to its mode.
//= spec/pierre2022.md#sw-s1-no-chattering
//# Any two mode changes, neither of them to or from Stop and with no Stop
//# between them, MUST be at least D ticks apart, D being the shortest entry,
//# exit and plan delay of the configuration in ticks, and, with two or more
//# specialised behaviours, the Stop delay if it is shorter.
//= spec/pierre2022.md#sw-s2-entry-needs-its-delay-of-evidence
//# Every change into a specialised mode MUST happen in a tick where that
//# behaviour's entry evidence has lasted at least its entry delay, and where no
//# higher-priority behaviour has entry evidence.
//= spec/pierre2022.md#sw-s3-commands-only-from-valid-estimates
//# Every command source MUST be valid in its tick: a behaviour only in its own
//# mode with an Enter or Hold verdict, path tracking only with valid
//# localisation and outside Stop.
//= spec/pierre2022.md#sw-s4-stop-exactly-after-the-stop-delay-without-a-source
//# The mode MUST be Stop exactly when, in each of the last Stop-delay ticks,
//# localisation was invalid and the mode was not a specialised mode whose
//# behaviour gave a valid estimate.
//= spec/pierre2022.md#sw-l1-enter-verdicts-bring-the-mode
//# When a behaviour's entry evidence has lasted its entry delay and no
//# higher-priority behaviour has entry evidence in the current tick, the mode
//# MUST be that behaviour's mode or a higher-priority one; for the
//# highest-priority behaviour it MUST be its mode.
//= spec/pierre2022.md#sw-l2-exit-or-absent-verdicts-bring-path-tracking
//# When a behaviour has given Exit or Absent verdicts with valid localisation,
//# and no other behaviour has given entry evidence, in as many consecutive
//# ticks as its exit delay, the mode MUST be neither that behaviour's mode nor
//# Stop.
//= spec/pierre2022.md#sw-p1-an-inconsistent-line-is-left
//# When plan consistency is configured and a behaviour has given valid
//# estimates inconsistent with the plan, and no other behaviour has given
//# entry evidence, in as many consecutive ticks as the plan delay, the mode
//# MUST NOT be that behaviour's mode.
#[must_use]
pub fn step<const K: usize>(
    config: &SwitchingConfig<K>,
    state: &SwitchingState<K>,
    input: &Input<K>,
) -> (SwitchingState<K>, Output) {
    let plan_ticks = config.plan_ticks();
    let mut next = *state;

    // Entry evidence of every behaviour, each run saturating at its delay.
    for ((run, report), ticks) in next
        .entry_run
        .iter_mut()
        .zip(input.behaviours.iter())
        .zip(config.all_ticks().iter())
    {
        *run = if is_entry_evidence(report, plan_ticks.is_some()) {
            run.saturating_add(1).min(ticks.enter)
        } else {
            0
        };
    }
    let candidate = next.entry_run.iter().position(|&run| run > 0);
    let complete = candidate.filter(|&index| entry_is_complete(config, &next, index));

    let mode = match state.mode {
        Mode::PathTracking => complete.map_or(Mode::PathTracking, Mode::Behaviour),
        Mode::Stop => match complete {
            Some(index) => Mode::Behaviour(index),
            None if input.localisation_valid => Mode::PathTracking,
            None => Mode::Stop,
        },
        Mode::Behaviour(active) => {
            let report = input.behaviours.get(active);
            let valid = report.is_some_and(|r| r.verdict.estimate_is_valid());
            let exit_ticks = config.ticks(active).map_or(1, |t| t.exit);
            next.exit_run = if valid {
                0
            } else {
                next.exit_run.saturating_add(1).min(exit_ticks)
            };
            if let (Some(plan_ticks), Some(report), true) = (plan_ticks, report, valid) {
                next.plan_run = if report.plan_consistent {
                    0
                } else {
                    next.plan_run.saturating_add(1).min(plan_ticks)
                };
            }
            let leave = next.exit_run >= exit_ticks
                || plan_ticks.is_some_and(|ticks| next.plan_run >= ticks);
            // Staying would reach the Stop delay without a command source.
            let starving = !valid
                && !input.localisation_valid
                && state.sourceless_run.saturating_add(1) >= config.stop_ticks();
            match (candidate, complete) {
                // A higher-priority behaviour whose entry is complete takes over.
                (_, Some(index)) if index < active => Mode::Behaviour(index),
                // Rather than stop, a behaviour whose entry is complete takes over.
                (_, Some(index)) if starving => Mode::Behaviour(index),
                (_, _) if !leave => Mode::Behaviour(active),
                // Leaving: hand over to a complete entry, wait for one under
                // way, or fall back to path tracking.
                (_, Some(index)) => Mode::Behaviour(index),
                (Some(_), None) => Mode::Behaviour(active),
                (None, None) => Mode::PathTracking,
            }
        }
    };

    let mut source = command_source(config, mode, input);
    next.sourceless_run = if source == CommandSource::None {
        next.sourceless_run
            .saturating_add(1)
            .min(config.stop_ticks())
    } else {
        0
    };
    let stop = next.sourceless_run >= config.stop_ticks();
    #[cfg(feature = "fault-injection")]
    let stop = stop && config.fault() != Some(Fault::NeverStop);
    let mode = if stop {
        source = CommandSource::None;
        Mode::Stop
    } else {
        mode
    };

    if mode != state.mode {
        // Exit and plan evidence belong to the mode they were counted in.
        next.exit_run = 0;
        next.plan_run = 0;
    }
    next.mode = mode;
    (next, Output { mode, source })
}
