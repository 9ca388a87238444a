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
//! - [`mission`]: the mission machine of Emmi 2024, sections 3.1-3.2
//!   (`spec/emmi2024.md`, EM-MISSION-M1 to M5): a [`mission::Monitor`] of the
//!   properties and the stateright [`mission::MissionModel`] whose transitions
//!   call the real `step`.
//! - [`evidence`]: the record of what each proof explored, for
//!   `fieldguide evidence`.
#![forbid(unsafe_code)]

pub mod evidence;
pub mod mission;
pub mod switching;
