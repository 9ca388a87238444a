//! Proofs of the mission machine (`fieldguide::supervisor::mission`;
//! `spec/emmi2024.md`, EM-MISSION-M1 to EM-MISSION-M5).
//!
//! - [`Monitor`]: the history the properties need, kept from the events and
//!   the outputs only, and the properties as predicates on it;
//! - [`MissionModel`]: the stateright model whose `next_state` calls the real
//!   `step` with abstract events;
//! - [`check_run`]: a sequence of events replayed through the real machine
//!   under the monitor (the bolero harnesses and the counterexamples).

mod model;
mod monitor;

pub use model::{all_events, MissionModel, ModelState};
pub use monitor::{check_run, Monitor, Property, Violation};
