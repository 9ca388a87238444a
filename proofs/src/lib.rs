//! # fieldguide-proofs
//!
//! Evidence beyond example tests for the `fieldguide` core: stateright models
//! that explore every reachable state of the real state machines, and bolero
//! harnesses that run exhaustively here and as Kani proofs wherever the Kani
//! toolchain is installed (`cargo kani -p fieldguide-proofs --tests`).
//!
//! - [`switching`]: the behaviour-switching machine of Pierre 2022, section 3
//!   (`spec/pierre2022.md`, SW-S1 to SW-P1): an independent [`switching::Spec`]
//!   of its delays, a [`switching::Monitor`] that keeps the history counters
//!   the properties need, and the stateright [`switching::SwitchingModel`]
//!   whose transitions call the real `step`.
//! - [`evidence`]: the record of what each proof explored, for
//!   `fieldguide evidence`.
#![forbid(unsafe_code)]

pub mod evidence;
pub mod switching;
