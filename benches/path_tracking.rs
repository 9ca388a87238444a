//! Benchmarks of path tracking.
fn main() {}
