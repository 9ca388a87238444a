//! Test helpers for the furrow detector: an exact ray caster for an inclined
//! LiDAR over flat ground and straight ridges (rows as continuous boxes),
//! written independently of the detector's own geometry.
#![allow(dead_code)]

use fieldguide::perception::furrow::FurrowParams;

/// A straight ridge along the odometry x axis: `|y − center_y| ≤ half_width`, `0 ≤ z ≤ height`.
#[derive(Debug, Clone, Copy)]
pub struct Ridge {
    pub center_y: f64,
    pub half_width: f64,
    pub height: f64,
}

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

/// The ranges seen from the robot at odometry pose `(px, py, heading)`.
pub fn ridge_scan(params: &FurrowParams, lidar: &Lidar, pose: (f64, f64, f64), ridges: &[Ridge]) -> Vec<f64> {
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
            // y in the odometry frame along the ray: A + B r.
            let big_a = py + psi.sin() * xm + psi.cos() * ym;
            let big_b = psi.sin() * dx + psi.cos() * dy;
            let _ = px;
            let mut best = ground;
            for ridge in ridges {
                let (lo_y, hi_y) = (ridge.center_y - ridge.half_width, ridge.center_y + ridge.half_width);
                let (r0, r1) = if big_b.abs() < 1e-15 {
                    if big_a >= lo_y && big_a <= hi_y {
                        (f64::NEG_INFINITY, f64::INFINITY)
                    } else {
                        continue;
                    }
                } else {
                    let (u, v) = ((lo_y - big_a) / big_b, (hi_y - big_a) / big_b);
                    (u.min(v), u.max(v))
                };
                let rz = (h - ridge.height) / c;
                let entry = r0.max(rz).max(0.0);
                if entry <= r1 && entry < best {
                    best = entry;
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
