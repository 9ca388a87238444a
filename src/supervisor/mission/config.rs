//! The mission's configuration (EM-MISSION-MONITOR, EM-MISSION-LEGS,
//! EM-LOC-CHOICE).

use crate::control::speed_profile::REACH_DISTANCE;
use crate::error::Precondition;
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};
use crate::planning::dubins::TurningRadius;
use crate::planning::manager::PlannerThreshold;
use crate::supervisor::switching::delay_ticks;

/// A deliberate defect, to show that the proofs detect a wrong machine. Only
/// with the `fault-injection` feature; never enable it in a vehicle.
#[cfg(feature = "fault-injection")]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Fault {
    /// Re-plan through a detour inside a crop field.
    ReplanInField,
    /// Keep following with an obstacle in the critical area.
    IgnoreCritical,
}

/// What the pure machine needs: its two limits in ticks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MachineConfig {
    stall_ticks: u16,
    leg_ticks: u16,
    #[cfg(feature = "fault-injection")]
    fault: Option<Fault>,
}

impl MachineConfig {
    /// Limits given in ticks: abort after `stall_ticks` followed ticks without
    /// progress, or `leg_ticks` followed ticks on one leg.
    ///
    /// # Errors
    /// `EM-MISSION-CONFIG` for a limit of 0 ticks.
    pub fn from_ticks(stall_ticks: u16, leg_ticks: u16) -> Result<Self, Precondition> {
        if stall_ticks == 0 || leg_ticks == 0 {
            return Err(Precondition::new(
                "EM-MISSION-CONFIG",
                "limits must be at least one tick",
            ));
        }
        Ok(Self {
            stall_ticks,
            leg_ticks,
            #[cfg(feature = "fault-injection")]
            fault: None,
        })
    }

    /// Limits given as durations at a control `period`, each converted once
    /// to n = ⌈delay / period⌉ ticks.
    ///
    /// # Errors
    /// `EM-MISSION-CONFIG` for a delay or period that is not positive or a
    /// delay beyond 65 535 ticks.
    //= spec/emmi2024.md#em-mission-monitor-malfunctions
    //# The delays MUST be positive and converted once to ticks n = ⌈delay /
    //# period⌉, at most 65 535, and the tolerance and the longest leg MUST be
    //# positive; other values MUST be refused with the `EM-MISSION-CONFIG` error.
    pub fn new(period: Seconds, stall: Seconds, leg_limit: Seconds) -> Result<Self, Precondition> {
        let ticks = |delay| {
            delay_ticks(delay, period, "EM-MISSION-CONFIG")
                .map_err(|e| Precondition::new("EM-MISSION-CONFIG", e.violated))
        };
        Self::from_ticks(ticks(stall)?, ticks(leg_limit)?)
    }

    /// The stall delay in ticks.
    #[must_use]
    pub const fn stall_ticks(&self) -> u16 {
        self.stall_ticks
    }

    /// The leg time limit in ticks.
    #[must_use]
    pub const fn leg_ticks(&self) -> u16 {
        self.leg_ticks
    }

    /// The same configuration with a deliberate defect.
    #[cfg(feature = "fault-injection")]
    #[must_use]
    pub const fn with_fault(self, fault: Fault) -> Self {
        Self {
            fault: Some(fault),
            ..self
        }
    }

    /// The deliberate defect, if any.
    #[cfg(feature = "fault-injection")]
    #[must_use]
    pub const fn fault(&self) -> Option<Fault> {
        self.fault
    }
}

/// The whole supervisor's configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MissionConfig {
    /// The pure machine's limits.
    pub machine: MachineConfig,
    /// The distance within which a goal counts as reached, metres (> 0).
    pub tolerance: Meters,
    /// The remaining distance along a leg at which its end counts as passed
    /// (EM-SPEED-REACH), metres; [`MissionConfig::new`] sets the speed
    /// profile's [`REACH_DISTANCE`], below the tolerance.
    pub reach_distance: Meters,
    /// The longest leg that may be planned, metres (> 0).
    pub longest_leg: Meters,
    /// The distance odometry may be used since the last fix, metres (≥ 0).
    pub odometry_distance: Meters,
    /// The GoToGoal / LineFollowing threshold.
    pub threshold: PlannerThreshold,
    /// The turning radius of GoToGoal in the fields and of detours.
    pub radius: TurningRadius,
    /// The turning radius of an Approximation's GoToGoal legs (a road's
    /// corners); [`MissionConfig::new`] sets it to `radius`.
    pub road_radius: TurningRadius,
    /// The speed on straight legs, m/s (≥ 0).
    pub cruise_speed: MetersPerSecond,
    /// The speed on GoToGoal legs, m/s (≥ 0).
    pub turn_speed: MetersPerSecond,
}

impl MissionConfig {
    /// A configuration, checked.
    ///
    /// # Errors
    /// `EM-MISSION-CONFIG` for a tolerance or longest leg that is not
    /// positive, or an odometry distance or a speed that is negative.
    pub fn new(
        machine: MachineConfig,
        tolerance: Meters,
        longest_leg: Meters,
        odometry_distance: Meters,
        radius: TurningRadius,
        speeds: (MetersPerSecond, MetersPerSecond),
    ) -> Result<Self, Precondition> {
        let (cruise_speed, turn_speed) = speeds;
        if tolerance.get() <= 0.0 || longest_leg.get() <= 0.0 {
            return Err(Precondition::new(
                "EM-MISSION-CONFIG",
                "tolerance and longest leg must be positive",
            ));
        }
        //= spec/emmi2024.md#em-mission-monitor-malfunctions
        //# The end of a leg MUST count as passed when the pipeline's remaining
        //# distance along it is at most the speed profile's reach distance
        //# (EM-SPEED-REACH), and a tolerance not above that reach distance MUST be
        //# refused with the `EM-MISSION-CONFIG` error.
        if tolerance.get() <= REACH_DISTANCE {
            return Err(Precondition::new(
                "EM-MISSION-CONFIG",
                "the tolerance must exceed the reach distance (0.05 m)",
            ));
        }
        if odometry_distance.get() < 0.0 || cruise_speed.get() < 0.0 || turn_speed.get() < 0.0 {
            return Err(Precondition::new(
                "EM-MISSION-CONFIG",
                "odometry distance and speeds must not be negative",
            ));
        }
        Ok(Self {
            machine,
            tolerance,
            reach_distance: Meters::new(REACH_DISTANCE)?,
            longest_leg,
            odometry_distance,
            threshold: PlannerThreshold::DEFAULT,
            radius,
            road_radius: radius,
            cruise_speed,
            turn_speed,
        })
    }

    /// The same configuration, an Approximation's GoToGoal legs planned
    /// with `road_radius` (EM-MISSION-LEGS): a road's corner turned on its
    /// own fillet rather than on the field's tight U-turn radius.
    #[must_use]
    pub const fn with_road_radius(self, road_radius: TurningRadius) -> Self {
        Self {
            road_radius,
            ..self
        }
    }

    /// The field robot of the paper at 10 Hz (sections 2 and 4): a leg's end
    /// 0.05 m before its goal along the path, turning radius 1.5 m, 0.5 m/s on
    /// lines and 0.2 m/s in turns; chosen here: goals within 0.25 m (about
    /// three times the paper's mean lateral error, 0.076 m), abort after 10 s
    /// without progress or 600 s on one leg, legs up to 500 m, odometry for up
    /// to 5 m.
    ///
    /// # Errors
    /// None in practice; the constructors' errors are passed on.
    pub fn carob() -> Result<Self, Precondition> {
        let machine = MachineConfig::new(
            Seconds::new(0.1)?,
            Seconds::new(10.0)?,
            Seconds::new(600.0)?,
        )?;
        Self::new(
            machine,
            Meters::new(0.25)?,
            Meters::new(500.0)?,
            Meters::new(5.0)?,
            TurningRadius::new(Meters::new(1.5)?)?,
            (MetersPerSecond::new(0.5)?, MetersPerSecond::new(0.2)?),
        )
    }
}
