//! Benchmark of furrow detection.
fn main() {}
