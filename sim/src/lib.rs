//! # fieldguide-sim
//!
//! The kinematic simulator around the `fieldguide` core: worlds, simulated
//! sensors, vehicle plants, scenarios, metrics measured against ground truth,
//! and CSV / JSON / SVG output.
//!
//! A run: [`scenario::Source`] (a built-in or a TOML file) →
//! [`runner::prepare`] (validated [`scenario::Setup`] and the run's one seeded
//! generator) → [`runner::run`] (the closed loop, one [`runner::TickRecord`]
//! per control tick) → [`metrics::summarize`] → [`output::write_run`].
//! [`sweep::sweep`] repeats a scenario over a range of seeds
//! ([`runner::prepare_with_seed`]), one summary per seed.
#![forbid(unsafe_code)]

pub mod capacity;
pub mod crop_drive;
pub mod error;
pub mod evidence;
pub mod gnss;
pub mod guidance;
pub mod guiding;
pub mod lidar;
pub mod metrics;
pub mod odometry;
pub mod output;
pub mod parallel;
pub mod plant;
pub mod rng;
pub mod runner;
pub mod scenario;
pub mod sensors;
pub mod stress;
pub mod sweep;
pub mod vineyard;
pub mod world;

pub use error::{ScenarioError, SimError};
