//! Exact synthetic scans of an inclined 2D LiDAR over a vineyard, the
//! ground truth for testing and benchmarking the vine detector (Iberraken et
//! al. 2022, section 2.1).
//!
//! Plain `f64` geometry, written independently of the detector: the world is
//! a ground plane with a cross slope and an along-row slope, on which stand
//! axis-aligned boxes (vine canopies, posts, bumps); the robot stays level at
//! the ground height under its rear axle; each ray is cast from the sensor,
//! pitched down about the robot's y axis, and its range is the nearest hit
//! of the plane and of every box (closed-form slab test). Everything random
//! comes from an explicit seed.
//!
//! Frames: the world frame is fixed (x along the rows, y left, z up); the
//! robot frame is x forward, y left at the robot's pose; the sensor's scan
//! plane is its x-y plane. Angles are counter-clockwise, radians.

#![allow(
    dead_code,
    clippy::unwrap_used,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::indexing_slicing,
    clippy::cast_precision_loss,
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    clippy::panic
)]

use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Radians};

/// An axis-aligned box of the world, m.
#[derive(Debug, Clone, Copy)]
pub struct Box3 {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// A ground plane z = along · x + cross · y and boxes on it.
#[derive(Debug, Clone, Default)]
pub struct World {
    /// dz/dx of the ground.
    pub along: f64,
    /// dz/dy of the ground.
    pub cross: f64,
    pub boxes: Vec<Box3>,
}

impl World {
    /// A world of ground only.
    pub fn ground(along: f64, cross: f64) -> Self {
        Self {
            along,
            cross,
            boxes: Vec::new(),
        }
    }

    /// The ground height at (x, y).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        self.along * x + self.cross * y
    }

    /// A box standing on the ground: footprint [x0, x1] × [y0, y1], `height`
    /// m above the ground at its centre, its base sunk below the lowest
    /// ground corner so that it meets the ground everywhere.
    pub fn stand(&mut self, x: (f64, f64), y: (f64, f64), height: f64) {
        let corners = [
            self.height(x.0, y.0),
            self.height(x.0, y.1),
            self.height(x.1, y.0),
            self.height(x.1, y.1),
        ];
        let low = corners.iter().copied().fold(f64::INFINITY, f64::min);
        let centre = self.height(0.5 * (x.0 + x.1), 0.5 * (y.0 + y.1));
        self.boxes.push(Box3 {
            min: [x.0, y.0, low - 0.5],
            max: [x.1, y.1, centre + height],
        });
    }

    /// Boxes standing along x from `x0` to `x1` at most 1 m long each (one
    /// vine each), so that each follows the ground's along slope.
    fn stand_along(&mut self, (x0, x1): (f64, f64), y: (f64, f64), height: f64) {
        let mut x = x0;
        while x < x1 {
            let end = (x + 1.0).min(x1);
            self.stand((x, end), y, height);
            x = end;
        }
    }

    /// A row of vines along x at lateral `y`: a canopy `width` m wide and
    /// `height` m high from `x0` to `x1`, missing over each gap (from, to).
    pub fn vine_row(
        &mut self,
        y: f64,
        width: f64,
        height: f64,
        (x0, x1): (f64, f64),
        gaps: &[(f64, f64)],
    ) {
        let mut start = x0;
        let mut gaps = gaps.to_vec();
        gaps.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (g0, g1) in gaps {
            if g0 > start {
                self.stand_along(
                    (start, g0.min(x1)),
                    (y - 0.5 * width, y + 0.5 * width),
                    height,
                );
            }
            start = start.max(g1);
        }
        if start < x1 {
            self.stand_along((start, x1), (y - 0.5 * width, y + 0.5 * width), height);
        }
    }

    /// A square post of side `side` at (x, y), `height` m high.
    pub fn post(&mut self, x: f64, y: f64, side: f64, height: f64) {
        let h = 0.5 * side;
        self.stand((x - h, x + h), (y - h, y + h), height);
    }

    /// Distance along the unit ray (o, d) to the first hit, if any.
    pub fn hit(&self, o: [f64; 3], d: [f64; 3]) -> Option<f64> {
        let mut best = f64::INFINITY;
        // The plane z − along x − cross y = 0.
        let num = o[2] - self.along * o[0] - self.cross * o[1];
        let den = d[2] - self.along * d[0] - self.cross * d[1];
        if den < 0.0 {
            let t = -num / den;
            if t > 0.0 {
                best = t;
            }
        }
        for b in &self.boxes {
            if let Some(t) = slab(o, d, b) {
                best = best.min(t);
            }
        }
        best.is_finite().then_some(best)
    }
}

/// The entry distance of the ray into the box (slab method), if it enters
/// ahead of the origin.
fn slab(o: [f64; 3], d: [f64; 3], b: &Box3) -> Option<f64> {
    let (mut t0, mut t1) = (0.0_f64, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-15 {
            if o[k] < b.min[k] || o[k] > b.max[k] {
                return None;
            }
        } else {
            let a = (b.min[k] - o[k]) / d[k];
            let c = (b.max[k] - o[k]) / d[k];
            t0 = t0.max(a.min(c));
            t1 = t1.min(a.max(c));
        }
    }
    (t0 <= t1 && t0 > 0.0).then_some(t0)
}

/// An inclined 2D LiDAR: its mount on the robot and its rays.
#[derive(Debug, Clone, Copy)]
pub struct Lidar {
    /// Position in the robot frame, m.
    pub x: f64,
    pub y: f64,
    pub z: f64,
    /// Pitch, rad, nose down.
    pub pitch: f64,
    /// First ray's angle and the increment, rad.
    pub start: f64,
    pub increment: f64,
    pub rays: usize,
    /// Ranges at or beyond this are no return.
    pub max_range: f64,
}

impl Lidar {
    /// Table 1's mount (x = 1.0 m, y = 0, z = 2.0 m, 45°), 271 rays one
    /// degree apart over 270°, 20 m.
    pub fn table1() -> Self {
        Self {
            x: 1.0,
            y: 0.0,
            z: 2.0,
            pitch: core::f64::consts::FRAC_PI_4,
            start: -135.0_f64.to_radians(),
            increment: 1.0_f64.to_radians(),
            rays: 271,
            max_range: 20.0,
        }
    }

    /// The ray's in-plane angle.
    pub fn angle(&self, k: usize) -> f64 {
        self.start + k as f64 * self.increment
    }

    /// The scan of `world` from the robot at world pose (x, y, heading),
    /// standing level at the ground height under it; no return is
    /// `max_range`.
    pub fn cast(&self, world: &World, (x, y, heading): (f64, f64, f64)) -> Vec<f64> {
        let (s, c) = heading.sin_cos();
        let origin = [
            x + c * self.x - s * self.y,
            y + s * self.x + c * self.y,
            world.height(x, y) + self.z,
        ];
        let (sp, cp) = self.pitch.sin_cos();
        (0..self.rays)
            .map(|k| {
                let (sa, ca) = self.angle(k).sin_cos();
                // Robot frame: (cos a cos p, sin a, −cos a sin p).
                let r = [ca * cp, sa, -ca * sp];
                let d = [c * r[0] - s * r[1], s * r[0] + c * r[1], r[2]];
                world
                    .hit(origin, d)
                    .filter(|&t| t < self.max_range)
                    .unwrap_or(self.max_range)
            })
            .collect()
    }

    /// The core's scan message for `ranges`.
    pub fn scan<'a>(&self, ranges: &'a [f64]) -> Scan<'a> {
        Scan {
            start: Radians::new(self.start).unwrap(),
            increment: Radians::new(self.increment).unwrap(),
            ranges,
            limits: RangeLimits::new(
                Meters::new(0.05).unwrap(),
                Meters::new(self.max_range).unwrap(),
            )
            .unwrap(),
        }
    }
}

/// A vineyard: rows `spacing` m apart with the robot's row at y = 0, from
/// x = −5 to 60 m, canopies `width` m wide and 1.0 m high, posts every 6 m.
pub fn vineyard(world: World, spacing: f64, width: f64, gaps: &[(f64, f64)]) -> World {
    let mut w = world;
    for row in [-1.0, 0.0, 1.0] {
        w.vine_row(row * spacing, width, 1.0, (-5.0, 60.0), gaps);
        let mut x = -5.0;
        while x < 60.0 {
            w.post(x, row * spacing, 0.08, 1.6);
            x += 6.0;
        }
    }
    w
}

/// SplitMix64: a small seeded generator (Steele, Lea and Flood 2014).
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1_u64 << 53) as f64
    }

    /// Scatters `count` low bumps (boxes `size` m square, `height` m high)
    /// over x in [x0, x1], y in [−1.5, 1.5] m.
    pub fn bumps(
        &mut self,
        world: &mut World,
        count: usize,
        size: f64,
        height: f64,
        (x0, x1): (f64, f64),
    ) {
        for _ in 0..count {
            let x = x0 + (x1 - x0) * self.unit();
            let y = -1.5 + 3.0 * self.unit();
            world.stand((x, x + size), (y, y + size), height);
        }
    }
}
