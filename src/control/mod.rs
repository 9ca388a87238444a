//! Control laws: one trait for every law, and the laws behind it
//! (`spec/guidance.md`, GD-LAW).
//!
//! A law turns a tracking error (and what else it reads, such as a sideslip
//! estimate) into the command of the vehicle it is written for, saturated to
//! that vehicle's limits ([`crate::model`]), or refuses the error with the
//! [`Precondition`] that failed. Each law family documents its own gain
//! convention: [`backstepping`] for Pierre 2022's, [`four_ws`] for the two
//! four-wheel-steering strategies of Iberraken 2022.

pub mod backstepping;
pub mod four_ws;
pub mod fuzzy;
pub mod fuzzy_rows;
pub mod lateral_pd;
pub mod speed_profile;
pub mod spiral;

use crate::error::Precondition;
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::MetersPerSecond;
use crate::model::{Actuation, Saturated};

/// A control law: error in, the command of its vehicle out (GD-LAW).
pub trait ControlLaw {
    /// What the law reads besides the error, in every tick (the observer's
    /// sideslip estimate for backstepping).
    type Extra: Copy + core::fmt::Debug + PartialEq;

    /// The extra input of a behaviour that has none: a straight line seen by a
    /// detector is followed without sideslip (GD-PREDICTION).
    const NEUTRAL: Self::Extra;

    /// The actuation of the vehicle this law commands.
    fn actuation(&self) -> Actuation;

    /// Checks a tick's extra input before anything runs (GD-INPUT).
    ///
    /// # Errors
    /// The requirement the input breaks.
    fn check_extra(extra: &Self::Extra) -> Result<(), Precondition>;

    /// Checks a desired speed once, when a configuration is built: a law
    /// valid over a range of speeds refuses the others (for backstepping
    /// with a speed schedule, PT-SCHEDULE-RANGE). Every speed by default.
    ///
    /// # Errors
    /// The requirement the speed breaks.
    fn check_speed(&self, speed: MetersPerSecond) -> Result<(), Precondition> {
        let _ = speed;
        Ok(())
    }

    /// The command for `error` at the desired `speed`, within the vehicle's
    /// limits.
    ///
    /// # Errors
    /// The requirement the error breaks (for backstepping PT-DENOM,
    /// PT-HEADING, PT-SPEED, ...).
    //= spec/guidance.md#gd-law-one-trait-for-every-control-law
    //# A control law MUST turn a tracking error, its extra input and a desired
    //# speed into a command of its vehicle's actuation within that vehicle's
    //# limits, or refuse them with a `Precondition` error; it MUST NOT give a
    //# non-finite command.
    fn command(
        &self,
        error: &TrackingError,
        extra: &Self::Extra,
        speed: MetersPerSecond,
    ) -> Result<Saturated, Precondition>;
}
