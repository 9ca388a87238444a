//! Helpers shared by the pipeline's closed-loop tests (`fix_quality.rs`,
//! `handover.rs`): lengths and a straight reference path along x.
#![allow(dead_code, clippy::unwrap_used)]

use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::{Meters, Point2, World};

/// The capacity of the tests' reference paths.
pub const PATH_N: usize = 256;

/// A length in metres, finite by the test's construction.
pub fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

/// A straight path along the world x axis (y = 0) from `from` to `to`,
/// waypoints every 5 m.
pub fn straight_path(from: f64, to: f64) -> ReferencePath<PATH_N> {
    let count = ((to - from) / 5.0).round() as u32;
    let points: Vec<Point2<World>> = (0..=count)
        .map(|i| Point2::new(from + 5.0 * f64::from(i), 0.0).unwrap())
        .collect();
    ReferencePath::from_waypoints(&points, PathConfig::default()).unwrap()
}
