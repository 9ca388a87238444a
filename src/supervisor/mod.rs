//! Supervision: the switching between behaviours (Pierre 2022, section 3).

pub mod switching;
