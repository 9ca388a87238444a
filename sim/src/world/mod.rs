//! Worlds: terrain, hedges and walls, crop plots.
//!
//! A [`World`] is everything around the vehicle that the simulator measures
//! against: the ground's sideslip and the plants a wheel may run over.

pub mod crops;
pub mod grid;
pub mod hedge;
pub mod terrain;

use terrain::Terrain;

/// A plant on the ground: a disc that a wheel crushes when it overlaps it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plant {
    /// East coordinate of the stem, metres, world frame.
    pub x: f64,
    /// North coordinate of the stem, metres, world frame.
    pub y: f64,
    /// Radius of the plant's footprint, metres.
    pub radius: f64,
    /// Height, metres (seen by an inclined LiDAR).
    pub height: f64,
}

/// The simulated world of one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct World {
    /// Ground sideslip.
    pub terrain: Terrain,
    /// Plants (none until crop plots are added to scenarios).
    pub plants: Vec<Plant>,
}
