//! Helpers shared by the pipeline's closed-loop tests (`fix_quality.rs`,
//! `handover.rs`, `holds.rs`): lengths, a straight reference path along x,
//! a fix rule and an edge scan.
#![allow(dead_code, clippy::unwrap_used)]

use core::f64::consts::{PI, TAU};
use fieldguide::geometry::path::{PathConfig, ReferencePath};

use fieldguide::guidance::{FixKind, FixRuleParams, RoutedScan};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::presets::EDGE;
use fieldguide::{Meters, Point2, Radians, World};

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

/// A fix rule taking only RTK fixed within 0.05 m, carrying the pose up to
/// 15 m, rejoining at 0.1 m per metre and 0.05 /m.
pub fn fix_rule() -> FixRuleParams {
    FixRuleParams {
        worst_kind: FixKind::RtkFixed,
        max_accuracy: m(0.05),
        path_dead_reckoning: m(15.0),
        rejoin_slope: 0.1,
        rejoin_curvature: 0.05,
        float_averaging: None,
    }
}

/// The scan `ranges` (rays evenly all round from −π), routed to edge following.
pub fn edge_scan(ranges: &[f64], limits: RangeLimits) -> RoutedScan<'_> {
    RoutedScan {
        behaviour: EDGE,
        scan: Scan {
            start: Radians::new(-PI).unwrap(),
            increment: Radians::new(TAU / ranges.len() as f64).unwrap(),
            ranges,
            limits,
        },
    }
}
