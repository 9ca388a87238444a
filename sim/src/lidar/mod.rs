//! Simulated 2D LiDARs.

pub mod horizontal;
pub mod inclined;
