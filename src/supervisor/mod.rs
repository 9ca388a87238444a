//! Supervision: the switching between behaviours.

pub mod switching;
