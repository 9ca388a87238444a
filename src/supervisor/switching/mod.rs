//! The behaviour-switching state machine (Pierre 2022, section 3, Tables 1-2;
//! `spec/pierre2022.md`, SW-MODES to SW-P1).
//!
//! Each control tick, every specialised behaviour (edge following, furrow
//! pursuing, ...) reports its detector's [`Verdict`] and whether its line
//! agrees with the planned path, and the caller says whether localisation for
//! path tracking is valid. The machine answers with a [`Mode`] and the
//! [`CommandSource`] whose command to apply:
//!
//! - path tracking is the default mode; a specialised mode is entered after
//!   its entry delay of consecutive Enter verdicts (SW-ENTER) and left after
//!   its exit delay of consecutive Exit or Absent verdicts (SW-EXIT), or after
//!   its line has disagreed with the plan for the plan delay
//!   (SW-PLAN-CONSISTENCY);
//! - a command only ever comes from a source valid in that tick: while an
//!   exit delay runs without a valid estimate, path tracking steers
//!   (SW-COMMAND-VALID);
//! - with no command source for the Stop delay, the mode is Stop until a
//!   source returns (SW-STOP).
//!
//! Delays are converted once to control ticks ([`SwitchingConfig::new`],
//! SW-DELAYS); the machine counts ticks and reads no clock. The proofs crate
//! (`fieldguide-proofs`) explores every reachable state of [`step`] with
//! stateright and runs Kani-ready bolero harnesses over it.
//!
//! ```
//! use fieldguide::supervisor::switching::{
//!     BehaviourConfig, CommandSource, Input, Mode, Report, Switching, SwitchingConfig,
//! };
//! use fieldguide::{Seconds, Verdict};
//!
//! # fn main() -> Result<(), fieldguide::Precondition> {
//! let config = SwitchingConfig::new(
//!     Seconds::new(0.01)?,                 // 100 Hz
//!     [BehaviourConfig::edge_following()?], // Table 1: 0.4 s in, 0.26 s out
//!     Seconds::new(0.5)?,                  // Stop after 0.5 s without a source
//!     None,                                // no plan-consistency check
//! )?;
//! let mut machine = Switching::new(config);
//! let hedge = Input {
//!     behaviours: [Report::consistent(Verdict::Enter)],
//!     localisation_valid: true,
//! };
//! for _ in 0..39 {
//!     assert_eq!(machine.step(&hedge).mode, Mode::PathTracking);
//! }
//! let out = machine.step(&hedge); // the 40th tick: 0.4 s of Enter verdicts
//! assert_eq!(out.mode, Mode::Behaviour(0));
//! assert_eq!(out.source, CommandSource::Behaviour(0));
//! # Ok(())
//! # }
//! ```

mod config;
mod machine;
mod plan;

#[cfg(feature = "fault-injection")]
pub use config::Fault;
pub use config::{
    delay_ticks, BehaviourConfig, DelayTicks, SwitchingConfig, MAX_BEHAVIOURS, MAX_DELAY_TICKS,
};
pub use machine::{step, Switching, SwitchingState};
pub use plan::{
    line_relative_to_path, line_relative_to_path_ahead, LineRelativeToPath, PathAhead,
    PlanTolerance,
};

use crate::perception::Verdict;

/// The mode of the machine (SW-MODES).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Mode {
    /// Path tracking on the planned path: the default mode.
    #[default]
    PathTracking,
    /// The specialised mode of behaviour `i` (0 = highest priority).
    Behaviour(usize),
    /// Standstill: no command source has existed for the Stop delay (SW-STOP).
    Stop,
}

/// The behaviour whose command the vehicle applies in this tick
/// (SW-COMMAND-VALID).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum CommandSource {
    /// Path tracking's command, made with valid localisation.
    PathTracking,
    /// Behaviour `i`'s command, made from an estimate valid in this tick.
    Behaviour(usize),
    /// No behaviour may command in this tick: keep the vehicle's safe state.
    #[default]
    None,
}

/// What one specialised behaviour reports in one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Report {
    /// The detector's verdict on its estimate (SW-CLASSIFY).
    pub verdict: Verdict,
    /// Whether the behaviour's line agrees with the planned path
    /// ([`PlanTolerance::is_consistent`]); ignored when plan consistency is not
    /// configured or when the estimate is not valid.
    pub plan_consistent: bool,
}

impl Report {
    /// A report of `verdict` whose line agrees with the plan.
    #[must_use]
    pub const fn consistent(verdict: Verdict) -> Self {
        Self {
            verdict,
            plan_consistent: true,
        }
    }
}

/// The machine's input in one tick: one report per specialised behaviour, in
/// priority order, and the validity of path tracking's localisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Input<const K: usize> {
    /// The reports of the specialised behaviours, index 0 first.
    pub behaviours: [Report; K],
    /// Whether localisation (GNSS pose) is valid for path tracking this tick.
    pub localisation_valid: bool,
}

/// The machine's answer in one tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Output {
    /// The mode after this tick.
    pub mode: Mode,
    /// Whose command to apply in this tick.
    pub source: CommandSource,
}
