//! svg output.
