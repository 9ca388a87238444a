//! Worlds: terrain, hedges and walls, crop plots.

pub mod crops;
pub mod hedge;
pub mod terrain;
