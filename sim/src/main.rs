//! The `fieldguide` program.
fn main() {}
