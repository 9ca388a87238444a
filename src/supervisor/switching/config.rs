//! Configuration of the switching machine, validated once at construction
//! (`spec/pierre2022.md`, SW-MODES, SW-DELAYS, SW-STOP, SW-PLAN-CONSISTENCY).
//!
//! Delays are given in [`Seconds`], as in the paper's Tables 1 and 2, and are
//! converted here, once, to control ticks; the machine never sees a duration.

use crate::error::Precondition;
use crate::geometry::units::Seconds;

/// The largest number of specialised behaviours a machine may have (SW-MODES).
pub const MAX_BEHAVIOURS: usize = 8;

/// The longest delay, in control ticks (SW-DELAYS): 655 s at 100 Hz.
pub const MAX_DELAY_TICKS: u16 = u16::MAX;

/// Relative shrink applied to `delay / period` before rounding up, so that the
/// representation error of a quotient that is mathematically an integer does
/// not add a tick (SW-DELAYS, Reading).
const ROUNDING_SLACK: f64 = 1e-9;

/// Converts a delay to whole control ticks, n = ⌈delay / period⌉ (SW-DELAYS).
///
/// The quotient is shrunk by a relative 10⁻⁹ before rounding up, so
/// 0.07 s / 0.01 s (7.000000000000001 in f64) gives 7 ticks, never 8, while
/// 0.305 s / 0.01 s gives 31.
///
/// # Errors
/// `requirement` with the reason when `period` or `delay` is not positive or
/// when the delay is longer than [`MAX_DELAY_TICKS`] ticks.
//= spec/pierre2022.md#sw-delays-transit-delays-in-control-ticks
//# Each specialised behaviour MUST have a positive delay to enter its mode and
//# a positive delay to leave it, and every delay MUST be converted once, at
//# construction, to a whole number of control ticks n = ⌈delay / period⌉.
pub fn delay_ticks(
    delay: Seconds,
    period: Seconds,
    requirement: &'static str,
) -> Result<u16, Precondition> {
    if period.get() <= 0.0 {
        return Err(Precondition::new(
            "SW-DELAYS",
            "control period must be positive",
        ));
    }
    if delay.get() <= 0.0 {
        return Err(Precondition::new(requirement, "delay must be positive"));
    }
    let quotient = delay.get() / period.get();
    let wanted = libm::ceil(quotient * (1.0 - ROUNDING_SLACK));
    // `wanted` is ≥ 1 (a positive quotient shrinks to a positive number) and
    // may be +inf, never NaN, when the period is tiny; the comparisons below are
    // exact on the integer-valued f64.
    if wanted > f64::from(MAX_DELAY_TICKS) {
        return Err(Precondition::new(
            requirement,
            "delay longer than 65535 control ticks",
        ));
    }
    // Smallest n in [1, MAX_DELAY_TICKS] with n ≥ wanted, by bisection (no `as`).
    let mut low: u16 = 1;
    let mut high: u16 = MAX_DELAY_TICKS;
    while low < high {
        let middle = low.midpoint(high);
        if f64::from(middle) >= wanted {
            high = middle;
        } else {
            low = middle.saturating_add(1);
        }
    }
    Ok(low)
}

/// One specialised behaviour as the switching machine sees it: its two
/// transit delays (Pierre 2022, Tables 1-2; SW-DELAYS). The machine reads
/// verdicts only; the hysteresis thresholds that grade a quality into a
/// verdict belong to the behaviour's detector (SW-THRESHOLDS, SW-CLASSIFY).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BehaviourConfig {
    enter_delay: Seconds,
    exit_delay: Seconds,
}

impl BehaviourConfig {
    /// A behaviour whose mode is entered after `enter_delay` of Enter
    /// verdicts and left after `exit_delay` of Exit or Absent verdicts.
    ///
    /// # Errors
    /// `SW-DELAYS` when a delay is not positive.
    pub fn new(enter_delay: Seconds, exit_delay: Seconds) -> Result<Self, Precondition> {
        if enter_delay.get() <= 0.0 {
            return Err(Precondition::new(
                "SW-DELAYS",
                "enter_delay must be positive",
            ));
        }
        if exit_delay.get() <= 0.0 {
            return Err(Precondition::new(
                "SW-DELAYS",
                "exit_delay must be positive",
            ));
        }
        Ok(Self {
            enter_delay,
            exit_delay,
        })
    }

    /// Edge following as in Pierre 2022, Table 1: 0.4 s to enter, 0.26 s to
    /// leave.
    ///
    /// # Errors
    /// None in practice: the table's values satisfy every precondition.
    pub fn edge_following() -> Result<Self, Precondition> {
        Self::new(Seconds(0.4), Seconds(0.26))
    }

    /// Furrow pursuing as in Pierre 2022, Table 2: 0.5 s to enter, 0.3 s to
    /// leave.
    ///
    /// # Errors
    /// None in practice: the table's values satisfy every precondition.
    pub fn furrow_pursuing() -> Result<Self, Precondition> {
        Self::new(Seconds(0.5), Seconds(0.3))
    }

    /// The delay to enter the mode, seconds.
    #[must_use]
    pub const fn enter_delay(&self) -> Seconds {
        self.enter_delay
    }

    /// The delay to leave the mode, seconds.
    #[must_use]
    pub const fn exit_delay(&self) -> Seconds {
        self.exit_delay
    }
}

/// A behaviour's delays in control ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DelayTicks {
    /// Ticks of entry evidence needed to enter (SW-ENTER).
    pub enter: u16,
    /// Ticks of exit evidence needed to leave (SW-EXIT).
    pub exit: u16,
}

/// A deliberate defect, to show that the proofs detect a wrong machine. Only
/// with the `fault-injection` feature; never enable it in a vehicle.
#[cfg(feature = "fault-injection")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Fault {
    /// Enter a specialised mode one tick before its entry delay has elapsed.
    EnterOneTickEarly,
    /// Keep commanding from the active behaviour when its estimate is invalid.
    SteerWithInvalidEstimate,
    /// Never stop, whatever the time without a command source.
    NeverStop,
}

/// The validated configuration of a switching machine with `K` specialised
/// behaviours in priority order (index 0 first; SW-MODES).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchingConfig<const K: usize> {
    period: Seconds,
    behaviours: [BehaviourConfig; K],
    ticks: [DelayTicks; K],
    stop_delay: Seconds,
    stop_ticks: u16,
    plan_delay: Option<Seconds>,
    plan_ticks: Option<u16>,
    #[cfg(feature = "fault-injection")]
    fault: Option<Fault>,
}

impl<const K: usize> SwitchingConfig<K> {
    /// A machine running every `period`, with `behaviours` in priority order,
    /// stopping after `stop_delay` without a command source, and, when
    /// `plan_delay` is given, leaving a behaviour whose line has disagreed with
    /// the planned path for that long (SW-PLAN-CONSISTENCY).
    ///
    /// # Errors
    /// - `SW-MODES` when `K` is 0 or larger than [`MAX_BEHAVIOURS`];
    /// - `SW-DELAYS` when `period` is not positive, or a behaviour's delay
    ///   is longer than [`MAX_DELAY_TICKS`] ticks;
    /// - `SW-STOP` when `stop_delay` is not positive or too long;
    /// - `SW-PLAN-CONSISTENCY` when `plan_delay` is not positive or too long.
    //= spec/pierre2022.md#sw-modes-modes-and-priority
    //# The specialised behaviours MUST be configured in priority order, index 0
    //# being the highest priority, and a configuration with no specialised
    //# behaviour or with more than `MAX_BEHAVIOURS` (8) MUST be refused at
    //# construction with an error naming this requirement.
    //= spec/pierre2022.md#sw-delays-transit-delays-in-control-ticks
    //# A non-positive control period or delay, or a delay longer than 65 535
    //# ticks, MUST be refused at construction with an error naming the
    //# requirement that owns the delay.
    pub fn new(
        period: Seconds,
        behaviours: [BehaviourConfig; K],
        stop_delay: Seconds,
        plan_delay: Option<Seconds>,
    ) -> Result<Self, Precondition> {
        if K == 0 {
            return Err(Precondition::new(
                "SW-MODES",
                "at least one specialised behaviour is needed",
            ));
        }
        if K > MAX_BEHAVIOURS {
            return Err(Precondition::new(
                "SW-MODES",
                "at most MAX_BEHAVIOURS (8) specialised behaviours",
            ));
        }
        let mut ticks = [DelayTicks { enter: 1, exit: 1 }; K];
        for (slot, behaviour) in ticks.iter_mut().zip(behaviours.iter()) {
            *slot = DelayTicks {
                enter: delay_ticks(behaviour.enter_delay, period, "SW-DELAYS")?,
                exit: delay_ticks(behaviour.exit_delay, period, "SW-DELAYS")?,
            };
        }
        let stop_ticks = delay_ticks(stop_delay, period, "SW-STOP")?;
        let plan_ticks = match plan_delay {
            Some(delay) => Some(delay_ticks(delay, period, "SW-PLAN-CONSISTENCY")?),
            None => None,
        };
        Ok(Self {
            period,
            behaviours,
            ticks,
            stop_delay,
            stop_ticks,
            plan_delay,
            plan_ticks,
            #[cfg(feature = "fault-injection")]
            fault: None,
        })
    }

    /// The same configuration with a deliberate defect (tests of the proofs only).
    #[cfg(feature = "fault-injection")]
    #[must_use]
    pub const fn with_fault(mut self, fault: Fault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The injected defect, if any.
    #[cfg(feature = "fault-injection")]
    #[must_use]
    pub const fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// The control period, seconds.
    #[must_use]
    pub const fn period(&self) -> Seconds {
        self.period
    }

    /// Behaviour `index` (0 = highest priority), if it exists.
    #[must_use]
    pub fn behaviour(&self, index: usize) -> Option<&BehaviourConfig> {
        self.behaviours.get(index)
    }

    /// The delays of behaviour `index` in ticks, if it exists.
    #[must_use]
    pub fn ticks(&self, index: usize) -> Option<DelayTicks> {
        self.ticks.get(index).copied()
    }

    /// The delays of every behaviour in ticks, in priority order.
    #[must_use]
    pub const fn all_ticks(&self) -> &[DelayTicks; K] {
        &self.ticks
    }

    /// The Stop delay, seconds (SW-STOP).
    #[must_use]
    pub const fn stop_delay(&self) -> Seconds {
        self.stop_delay
    }

    /// The Stop delay in ticks (SW-STOP).
    #[must_use]
    pub const fn stop_ticks(&self) -> u16 {
        self.stop_ticks
    }

    /// The plan-inconsistency delay, seconds, when plan consistency is on.
    #[must_use]
    pub const fn plan_delay(&self) -> Option<Seconds> {
        self.plan_delay
    }

    /// The plan-inconsistency delay in ticks, when plan consistency is on.
    #[must_use]
    pub const fn plan_ticks(&self) -> Option<u16> {
        self.plan_ticks
    }

    /// D of SW-S1: the shortest entry, exit and plan delay, and with two or
    /// more behaviours the Stop delay if shorter, in ticks. Any two mode
    /// changes that do not involve Stop are at least this far apart.
    #[must_use]
    pub fn min_dwell_ticks(&self) -> u16 {
        let stop = if K >= 2 { Some(self.stop_ticks) } else { None };
        let delays = self
            .ticks
            .iter()
            .flat_map(|t| [t.enter, t.exit])
            .chain(self.plan_ticks)
            .chain(stop);
        delays.min().unwrap_or(1)
    }
}
