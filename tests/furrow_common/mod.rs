//! Test helpers for the furrow detector: an exact ray caster for an inclined
//! LiDAR over flat ground and straight ridges (rows as continuous boxes),
//! written independently of the detector's own geometry.
#![allow(dead_code)]

use fieldguide::perception::furrow::FurrowParams;

/// A row of square plants along the odometry x axis: plants centred at
/// `(k · spacing, center_y)` for every integer k, `2 half_width` wide on both
/// axes, `height` tall.
#[derive(Debug, Clone, Copy)]
pub struct Ridge {
    pub center_y: f64,
    pub half_width: f64,
    pub height: f64,
}

/// Plant spacing along a row, m.
pub const SPACING: f64 = 0.2;

/// Scan geometry.
#[derive(Debug, Clone, Copy)]
pub struct Lidar {
    pub rays: usize,
    pub angle_min: f64,
    pub increment: f64,
}

impl Lidar {
    /// `rays` rays spread evenly over `fov` rad, centred on the forward axis.
    pub fn centred(rays: usize, fov: f64) -> Self {
        let increment = fov / (rays as f64 - 1.0);
        Self {
            rays,
            angle_min: -fov / 2.0,
            increment,
        }
    }
}

/// The interval of r where `lo ≤ a + b r ≤ hi`, or `None`.
fn slab(a: f64, b: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if b.abs() < 1e-15 {
        (a >= lo && a <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else {
        let (u, v) = ((lo - a) / b, (hi - a) / b);
        Some((u.min(v), u.max(v)))
    }
}

/// The ranges seen from the robot at odometry pose `(px, py, heading)`.
pub fn ridge_scan(
    params: &FurrowParams,
    lidar: &Lidar,
    pose: (f64, f64, f64),
    ridges: &[Ridge],
) -> Vec<f64> {
    let (px, py, psi) = pose;
    let (xm, ym, h, p) = (
        params.mount_x.get(),
        params.mount_y.get(),
        params.mount_height.get(),
        params.mount_pitch.get(),
    );
    (0..lidar.rays)
        .map(|j| {
            let a = lidar.angle_min + j as f64 * lidar.increment;
            let (dx, dy) = (a.cos() * p.cos(), a.sin());
            let c = a.cos() * p.sin();
            let ground = h / c;
            // The ray in the odometry frame: x = ax + bx r, y = ay + by r, z = h − c r.
            let (ax, bx) = (
                px + psi.cos() * xm - psi.sin() * ym,
                psi.cos() * dx - psi.sin() * dy,
            );
            let (ay, by) = (
                py + psi.sin() * xm + psi.cos() * ym,
                psi.sin() * dx + psi.cos() * dy,
            );
            let mut best = ground;
            for ridge in ridges {
                let Some((y0, y1)) = slab(
                    ay,
                    by,
                    ridge.center_y - ridge.half_width,
                    ridge.center_y + ridge.half_width,
                ) else {
                    continue;
                };
                let rz = (h - ridge.height) / c;
                // Plants whose x slab the ray crosses before the ground.
                let x_near = ax.min(ax + bx * ground) - ridge.half_width;
                let x_far = ax.max(ax + bx * ground) + ridge.half_width;
                let mut k = (x_near / SPACING).floor() as i64;
                while (k as f64) * SPACING <= x_far {
                    let cx = k as f64 * SPACING;
                    if let Some((x0, x1)) =
                        slab(ax, bx, cx - ridge.half_width, cx + ridge.half_width)
                    {
                        let entry = y0.max(x0).max(rz).max(0.0);
                        if entry <= y1.min(x1) && entry < best {
                            best = entry;
                        }
                    }
                    k += 1;
                }
            }
            best
        })
        .collect()
}

/// Flat ground ranges with a deterministic "noise" of amplitude `amp` m in range.
pub fn flat_scan(params: &FurrowParams, lidar: &Lidar, amp: f64) -> Vec<f64> {
    let (h, p) = (params.mount_height.get(), params.mount_pitch.get());
    (0..lidar.rays)
        .map(|j| {
            let a = lidar.angle_min + j as f64 * lidar.increment;
            h / (a.cos() * p.sin()) + amp * ((j as f64) * 12.9898).sin()
        })
        .collect()
}
