//! Geometry: unit types, frames, reference paths with their Frénet projection,
//! and least-squares fits.

pub mod carry;
pub mod fit;
pub mod frame;
pub mod path;
pub mod tracking;
pub mod units;
