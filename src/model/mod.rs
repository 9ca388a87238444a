//! Kinematic models of the vehicles, as pure functions.

pub mod bicycle;
