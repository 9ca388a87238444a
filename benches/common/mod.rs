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

use fieldguide::perception::furrow::FurrowParams;
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Radians, Robot, Sensor, Transform2};

/// The horizontal LiDAR's mount: 1.2 m ahead of the rear axle, facing forward.
pub const HEDGE_MOUNT_X: f64 = 1.2;

/// Rays of either scan.
pub const RAYS: usize = 360;

/// The inclined LiDAR's field of view, rad, centred on the forward axis.
pub const ROWS_FOV: f64 = FRAC_PI_2;

/// Distance between consecutive plants of a row, m: the rows world repeats
/// itself every `PLANT_SPACING` along x.
pub const PLANT_SPACING: f64 = 0.2;

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

/// The interval of r where `lo ≤ a + b r ≤ hi`.
fn slab(a: f64, b: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if b.abs() < 1e-15 {
        (a >= lo && a <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else {
        let (u, v) = ((lo - a) / b, (hi - a) / b);
        Some((u.min(v), u.max(v)))
    }
}

/// Angle between the inclined scan's rays, rad: both edges of the view included.
fn rows_increment() -> f64 {
    ROWS_FOV / (RAYS as f64 - 1.0)
}

/// Inclined ranges from a robot at the origin, seen from the mount of
/// `params`: flat ground and plants 0.16 m square, 0.3 m tall, every
/// [`PLANT_SPACING`] in two rows at y = ±0.375 m, with a few millimetres of
/// deterministic noise.
pub fn rows_ranges(params: &FurrowParams) -> Vec<f64> {
    let (xm, h, p) = (
        params.mount_x.get(),
        params.mount_height.get(),
        params.mount_pitch.get(),
    );
    (0..RAYS)
        .map(|j| {
            let a = -ROWS_FOV / 2.0 + j as f64 * rows_increment();
            let (dx, dy, c) = (a.cos() * p.cos(), a.sin(), a.cos() * p.sin());
            let mut best = h / c;
            for row in [-0.375, 0.375] {
                let Some((y0, y1)) = slab(0.0, dy, row - 0.08, row + 0.08) else {
                    continue;
                };
                let rz = (h - 0.3) / c;
                let mut k = 0;
                while (k as f64) * PLANT_SPACING <= xm + dx * best + 0.1 {
                    let cx = k as f64 * PLANT_SPACING;
                    if let Some((x0, x1)) = slab(xm, dx, cx - 0.08, cx + 0.08) {
                        let entry = y0.max(x0).max(rz).max(0.0);
                        if entry <= y1.min(x1) && entry < best {
                            best = entry;
                        }
                    }
                    k += 1;
                }
            }
            best + 0.005 * ((j as f64) * 12.9898).sin()
        })
        .collect()
}

/// The inclined scan over `ranges` (from [`rows_ranges`]), 0.1-20 m.
pub fn rows_scan(ranges: &[f64]) -> Scan<'_> {
    Scan {
        start: Radians::new(-ROWS_FOV / 2.0).unwrap(),
        increment: Radians::new(rows_increment()).unwrap(),
        ranges,
        limits: RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(20.0).unwrap()).unwrap(),
    }
}
