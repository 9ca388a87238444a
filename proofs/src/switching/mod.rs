//! Proofs of the behaviour-switching machine (`fieldguide::supervisor::switching`;
//! `spec/pierre2022.md`, SW-S1 to SW-P1).
//!
//! - [`Spec`]: the delays in ticks, computed in integer milliseconds,
//!   independently of the core's f64 conversion;
//! - [`Monitor`]: the history counters and the properties as predicates on them,
//!   shared by the stateright model and the bolero harnesses;
//! - [`SwitchingModel`]: the stateright model whose `next_state` calls the real
//!   `step`.

mod model;
mod monitor;
mod run;
mod spec;

pub use model::{all_concretisations, all_ticks, ModelState, SwitchingModel, Sym, Tick};
pub use monitor::{Monitor, Property};
pub use run::{check_run, Violation};
pub use spec::{config_from_millis, Spec, EDGE_MS, FURROW_MS};
