//! Worlds: terrain, hedges and walls, crop plots.

pub mod crops;
pub mod grid;
pub mod hedge;
pub mod terrain;
