//! The delays the properties are checked against, computed independently of
//! the core's conversion (`delay_ticks`, f64): here in integer milliseconds.

use fieldguide::supervisor::switching::{BehaviourConfig, SwitchingConfig};
use fieldguide::{Precondition, Seconds};

/// Table 1 (edge following): 400 ms to enter, 260 ms to leave.
pub const EDGE_MS: (u32, u32) = (400, 260);
/// Table 2 (furrow pursuing): 500 ms to enter, 300 ms to leave.
pub const FURROW_MS: (u32, u32) = (500, 300);

/// The specified delays of a machine with `K` behaviours, in control ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Spec<const K: usize> {
    /// Ticks of entry evidence each behaviour needs (SW-ENTER).
    pub enter: [u16; K],
    /// Ticks of exit evidence after which each behaviour's mode is left (SW-EXIT).
    pub exit: [u16; K],
    /// Ticks without a command source before Stop (SW-STOP).
    pub stop: u16,
    /// Ticks of plan-inconsistent estimates before leaving, when configured.
    pub plan: Option<u16>,
}

/// ⌈a / b⌉ for delays in milliseconds, as SW-DELAYS specifies (b > 0).
fn ceil_ticks(delay_ms: u32, period_ms: u32) -> u16 {
    let ticks = delay_ms.div_ceil(period_ms.max(1));
    u16::try_from(ticks).unwrap_or(u16::MAX)
}

impl<const K: usize> Spec<K> {
    /// The specified ticks for delays in milliseconds at a period in milliseconds.
    #[must_use]
    pub fn from_millis(
        period_ms: u32,
        behaviours: [(u32, u32); K],
        stop_ms: u32,
        plan_ms: Option<u32>,
    ) -> Self {
        Self {
            enter: behaviours.map(|(enter, _)| ceil_ticks(enter, period_ms)),
            exit: behaviours.map(|(_, exit)| ceil_ticks(exit, period_ms)),
            stop: ceil_ticks(stop_ms, period_ms),
            plan: plan_ms.map(|ms| ceil_ticks(ms, period_ms)),
        }
    }

    /// D of SW-S1: the shortest entry, exit and plan delay, and with two or
    /// more behaviours the Stop delay if shorter.
    #[must_use]
    pub fn min_dwell(&self) -> u16 {
        let stop = if K >= 2 { Some(self.stop) } else { None };
        self.enter
            .iter()
            .chain(self.exit.iter())
            .chain(self.plan.iter())
            .chain(stop.iter())
            .copied()
            .min()
            .unwrap_or(1)
    }
}

/// The core's configuration for the same delays, built from `Seconds` through
/// the real constructor (whose tick conversion the tests compare with [`Spec`]).
///
/// # Errors
/// Whatever [`SwitchingConfig::new`] refuses.
pub fn config_from_millis<const K: usize>(
    period_ms: u32,
    behaviours: [(u32, u32); K],
    stop_ms: u32,
    plan_ms: Option<u32>,
) -> Result<SwitchingConfig<K>, Precondition> {
    let seconds = |ms: u32| Seconds::new(f64::from(ms) / 1000.0);
    let edge = BehaviourConfig::edge_following()?;
    let mut built = [edge; K];
    for (slot, (enter, exit)) in built.iter_mut().zip(behaviours) {
        *slot = BehaviourConfig::new(seconds(enter)?, seconds(exit)?)?;
    }
    let plan = match plan_ms {
        Some(ms) => Some(seconds(ms)?),
        None => None,
    };
    SwitchingConfig::new(seconds(period_ms)?, built, seconds(stop_ms)?, plan)
}
