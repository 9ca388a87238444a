//! # fieldguide-proofs
//!
//! Evidence beyond example tests for the `fieldguide` core: stateright models
//! that explore every reachable state of the real state machines, and bolero
//! harnesses that run exhaustively here and as Kani proofs wherever the Kani
//! toolchain is installed (`cargo kani -p fieldguide-proofs`).
#![forbid(unsafe_code)]
