//! Control laws.

pub mod backstepping;
