//! # fieldguide-sim
//!
//! The kinematic simulator around the `fieldguide` core: worlds, simulated
//! sensors, vehicle plants, scenarios, metrics measured against ground truth,
//! and CSV / JSON / SVG output.
#![forbid(unsafe_code)]

pub mod lidar;
pub mod metrics;
pub mod odometry;
pub mod output;
pub mod plant;
pub mod rng;
pub mod runner;
pub mod scenario;
pub mod sensors;
pub mod world;
