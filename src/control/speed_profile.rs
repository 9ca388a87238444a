//! The linear speed controller of Emmi 2024 (section 3.3.3, Fig. 12): a
//! linear ramp from the threshold speed v_th to the desired speed v_d when
//! starting, a linear ramp from the current speed down to v_th over the
//! braking distance d_b before the goal, then a stop
//! (`spec/emmi2024.md`, EM-SPEED-*).
//!
//! The ramps are linear in distance: the paper gives no time base, and
//! distance is what both the start (distance travelled) and the approach
//! (distance remaining) are measured in.

use crate::error::Precondition;
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};

/// The goal-reached distance of the paper's tests, metres (section 5.1).
pub const REACH_DISTANCE: f64 = 0.05;

/// How the braking distance d_b is chosen (section 3.3.3: "a fixed distance
/// or a function of v_c").
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Braking {
    /// d_b fixed, metres.
    Fixed(Meters),
    /// d_b = k v_c, with k in seconds.
    Proportional(Seconds),
}

/// A validated linear speed profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedProfile {
    threshold: f64,
    desired: f64,
    ramp: f64,
    braking: Braking,
    reach: f64,
}

/// Where the profile is between ticks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpeedState {
    /// Starting or cruising: the ramp up from v_th, then v_d.
    Moving,
    /// Braking from `from` over `over` metres before the goal.
    Braking {
        /// The speed when braking started, m/s.
        from: MetersPerSecond,
        /// The braking distance d_b fixed when braking started, metres.
        over: Meters,
    },
    /// The goal is reached: stopped for good.
    Reached,
}

/// The speed controller's output for one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpeedCommand {
    /// Move at this speed (between v_th and v_d).
    Go(MetersPerSecond),
    /// Stop: the goal is reached.
    Stop,
}

impl SpeedProfile {
    /// A profile from `threshold` v_th up to `desired` v_d over `ramp` metres,
    /// braking as `braking` says, the goal reached within `reach` metres.
    ///
    /// # Errors
    /// `EM-SPEED-CONFIG` unless 0 < v_th ≤ v_d, the ramp, the braking distance
    /// (or factor) and the reach distance are > 0.
    //= spec/emmi2024.md#em-speed-config-speed-profile-configuration
    //# A profile MUST satisfy 0 < v_th ≤ v_d and have a strictly positive ramp
    //# distance, braking distance or braking factor, and reach distance; another
    //# MUST be refused with the `EM-SPEED-CONFIG` error.
    pub fn new(
        threshold: MetersPerSecond,
        desired: MetersPerSecond,
        ramp: Meters,
        braking: Braking,
        reach: Meters,
    ) -> Result<Self, Precondition> {
        let braking_ok = match braking {
            Braking::Fixed(d) => d.get() > 0.0,
            Braking::Proportional(k) => k.get() > 0.0,
        };
        let (v_th, v_d) = (threshold.get(), desired.get());
        if v_th > 0.0 && v_th <= v_d && ramp.get() > 0.0 && reach.get() > 0.0 && braking_ok {
            Ok(Self {
                threshold: v_th,
                desired: v_d,
                ramp: ramp.get(),
                braking,
                reach: reach.get(),
            })
        } else {
            Err(Precondition::new(
                "EM-SPEED-CONFIG",
                "need 0 < v_th <= v_d and positive ramp, braking and reach",
            ))
        }
    }

    /// The ramp-up speed after `travelled` metres:
    /// v_th + (v_d − v_th) min(max(travelled / ramp, 0), 1).
    //= spec/emmi2024.md#em-speed-ramp-starting-ramp
    //# After a distance travelled s_t from the start, the speed MUST be
    //# v_th + (v_d − v_th) min(max(s_t / d_a, 0), 1), d_a being the ramp distance.
    #[must_use]
    pub fn ramp_speed(&self, travelled: Meters) -> MetersPerSecond {
        let f = (travelled.get() / self.ramp).clamp(0.0, 1.0);
        MetersPerSecond(self.threshold + (self.desired - self.threshold) * f)
    }

    /// The braking distance d_b for the current speed `v_c`.
    //= spec/emmi2024.md#em-speed-brake-braking-ramp
    //# The braking distance MUST be the fixed d_b, or k v_c for the proportional
    //# choice.
    #[must_use]
    pub fn braking_distance(&self, current: MetersPerSecond) -> Meters {
        match self.braking {
            Braking::Fixed(d) => d,
            Braking::Proportional(k) => Meters((k.get() * current.get().max(0.0)).min(f64::MAX)),
        }
    }

    /// One tick: the state after it and the command, given the distance
    /// `travelled` since the start and the distance `remaining` to the goal
    /// along the path (≤ 0 once level with the goal or past it).
    //= spec/emmi2024.md#em-speed-brake-braking-ramp
    //# Once the remaining distance is at most the braking distance d_b of the
    //# current speed v_c, the speed MUST be v_th + (v_c − v_th) min(max(r / d_b,
    //# 0), 1) for a remaining distance r, with v_c and d_b those of the tick
    //# braking started.
    //= spec/emmi2024.md#em-speed-reach-goal-reached
    //# The goal MUST count as reached, and the command MUST be Stop from then on,
    //# once the remaining distance is at most the reach distance (0.05 m by
    //# default), which includes being level with the goal or past it.
    #[must_use]
    pub fn step(
        &self,
        state: SpeedState,
        travelled: Meters,
        remaining: Meters,
    ) -> (SpeedState, SpeedCommand) {
        let r = remaining.get();
        if matches!(state, SpeedState::Reached) || r <= self.reach {
            return (SpeedState::Reached, SpeedCommand::Stop);
        }
        let (from, over) = match state {
            SpeedState::Braking { from, over } => (from.get(), over.get()),
            _ => {
                let v = self.ramp_speed(travelled);
                let d_b = self.braking_distance(v).get();
                if r > d_b {
                    return (SpeedState::Moving, SpeedCommand::Go(v));
                }
                (v.get(), d_b)
            }
        };
        let f = if over > 0.0 {
            (r / over).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let v = self.threshold + (from - self.threshold) * f;
        (
            SpeedState::Braking {
                from: MetersPerSecond(from),
                over: Meters(over),
            },
            SpeedCommand::Go(MetersPerSecond(v)),
        )
    }
}
