//! Synthetic scans shared by the benchmarks (`mod common;` in each): a ragged
//! hedge seen by a horizontal LiDAR and two rows of plants seen by an
//! inclined one, both generated deterministically from the geometry alone,
//! as `fieldguide::perception::Scan` values.

// Each benchmark uses only some of the generators; bench code may unwrap.
#![allow(
    dead_code,
    clippy::unwrap_used,
    clippy::as_conversions,
    clippy::arithmetic_side_effects
)]

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::perception::edge::Side;
use fieldguide::perception::furrow::FurrowParams;
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::presets::{pierre2022_both, Pierre2022Params};
use fieldguide::supervisor::switching::PlanTolerance;
use fieldguide::{Meters, Point2, Radians, Robot, Seconds, Sensor, Transform2, World};

// The furrow tests' exact ray caster over straight rows of square plants.
#[path = "../../tests/furrow_common/mod.rs"]
pub mod furrow_common;
use furrow_common::{ridge_scan, Lidar, Ridge, SPACING};

/// The horizontal LiDAR's mount: 1.2 m ahead of the rear axle, facing forward.
pub const HEDGE_MOUNT_X: f64 = 1.2;

/// Rays of either scan.
pub const RAYS: usize = 360;

/// The inclined LiDAR's field of view, rad, centred on the forward axis.
pub const ROWS_FOV: f64 = FRAC_PI_2;

/// Distance between consecutive plants of a row, m: the rows world repeats
/// itself every `PLANT_SPACING` along x.
pub const PLANT_SPACING: f64 = SPACING;

/// The horizontal LiDAR's mount pose (sensor → robot).
pub fn hedge_mount() -> Transform2<Sensor, Robot> {
    Transform2::new(HEDGE_MOUNT_X, 0.0, 0.0).unwrap()
}

/// Lateral position of the left hedge's face at robot-frame abscissa `x`:
/// 1.4 m with a deterministic ragged profile of a few centimetres.
fn hedge_face(x: f64) -> f64 {
    1.4 - 0.04 * (3.1 * x).sin() - 0.03 * (7.7 * x + 1.0).sin() - 0.02 * (19.3 * x).sin()
}

/// Range along the horizontal ray of angle `a` (sensor = robot orientation)
/// to the left hedge (found by bisection on the ray), to a straight hedge
/// 2.5 m to the right, or +inf beyond 30 m.
fn hedge_range(a: f64) -> f64 {
    let (dx, dy) = (a.cos(), a.sin());
    if dy > 1e-3 {
        // Left: f(t) = t dy − face(mount + t dx) changes sign once.
        let (mut lo, mut hi) = (0.0, 30.0);
        if hi * dy < hedge_face(HEDGE_MOUNT_X + hi * dx) {
            return f64::INFINITY;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if mid * dy < hedge_face(HEDGE_MOUNT_X + mid * dx) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    } else if dy < -1e-3 && -2.5 / dy <= 30.0 {
        -2.5 / dy
    } else {
        f64::INFINITY
    }
}

/// First ray of the horizontal scan, rad: all round, from −π.
const HEDGE_START: f64 = -PI;
/// Angle between the horizontal scan's rays, rad.
const HEDGE_INCREMENT: f64 = TAU / 360.0;

/// The 360 ranges of the horizontal scan of the hedges.
pub fn hedge_ranges() -> Vec<f64> {
    (0..RAYS)
        .map(|k| hedge_range(HEDGE_START + HEDGE_INCREMENT * k as f64))
        .collect()
}

/// The horizontal scan over `ranges` (from [`hedge_ranges`]), 0.05-30 m.
pub fn hedge_scan(ranges: &[f64]) -> Scan<'_> {
    Scan {
        start: Radians::new(HEDGE_START).unwrap(),
        increment: Radians::new(HEDGE_INCREMENT).unwrap(),
        ranges,
        limits: RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap(),
    }
}

/// The inclined LiDAR's rays: both edges of the view included.
fn rows_lidar() -> Lidar {
    Lidar::centred(RAYS, ROWS_FOV)
}

/// Inclined ranges from a robot at the origin, seen from the mount of
/// `params`: flat ground and plants 0.16 m square, 0.3 m tall, every
/// [`PLANT_SPACING`] in two rows at y = ±0.375 m (the tests' exact ray
/// caster), with a few millimetres of deterministic noise.
pub fn rows_ranges(params: &FurrowParams) -> Vec<f64> {
    let row = |center_y| Ridge {
        center_y,
        half_width: 0.08,
        height: 0.3,
    };
    ridge_scan(
        params,
        &rows_lidar(),
        (0.0, 0.0, 0.0),
        &[row(-0.375), row(0.375)],
    )
    .into_iter()
    .enumerate()
    .map(|(j, r)| r + 0.005 * ((j as f64) * 12.9898).sin())
    .collect()
}

/// The inclined scan over `ranges` (from [`rows_ranges`]), 0.1-20 m.
pub fn rows_scan(ranges: &[f64]) -> Scan<'_> {
    Scan {
        start: Radians::new(-ROWS_FOV / 2.0).unwrap(),
        increment: Radians::new(rows_lidar().increment).unwrap(),
        ranges,
        limits: RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(20.0).unwrap()).unwrap(),
    }
}

/// The full tick's pipeline: both behaviours of the presets, furrow pursuing
/// first, the plan checked for both at the robot and 2 m ahead
/// (SW-PLAN-AHEAD), as in exp2-acre.
pub fn pipeline_params() -> Pierre2022Params {
    let mut params = pierre2022_both(Side::Left, hedge_mount()).unwrap();
    let tolerance = PlanTolerance::new(Meters::new(0.5).unwrap(), Radians::new(0.3).unwrap())
        .unwrap()
        .with_lookahead(Meters::new(2.0).unwrap())
        .unwrap();
    for behaviour in &mut params.behaviours {
        behaviour.plan = Some(tolerance);
    }
    params.plan_delay = Some(Seconds::new(1.0).unwrap());
    params
}

/// A straight path of 401 waypoints 0.5 m apart along the world's x axis.
pub fn straight_path() -> ReferencePath<512> {
    let waypoints: Vec<Point2<World>> = (0..=400)
        .map(|i| Point2::new(0.5 * f64::from(i), 0.0).unwrap())
        .collect();
    ReferencePath::from_waypoints(&waypoints, PathConfig::default()).unwrap()
}
