//! Exact synthetic 2D LiDAR scans of crop fields, the ground truth for
//! testing and benchmarking a crop-row line finder (Guyonneau et al. 2022,
//! "LiDAR-Only Crop Navigation for Symmetrical Robot", section 4.1).
//!
//! Plain `f64` geometry, written independently of any detector: a field is a
//! set of stems (circles) along straight rows plus scattered weeds; a ray
//! caster finds each ray's first stem in closed form and adds seeded Gaussian
//! noise; helpers give each row's true line in the robot frame. Everything
//! random comes from an explicit seed through the SplitMix64 generator below.
//!
//! Frames: the field frame is fixed; the robot frame is x forward, y left,
//! at the robot's pose; the sensor frame is the robot frame moved by the
//! LiDAR's mount. Angles are counter-clockwise, radians.

// Each user takes only some of the helpers; test and bench code may unwrap.
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

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Radians};

/// The range a ray that hits nothing reports.
pub const NO_RETURN: f64 = f64::INFINITY;

/// A crop stem's radius, m.
pub const STEM_RADIUS: f64 = 0.02;

/// SplitMix64: a small, fast, seeded generator (Steele, Lea and Flood 2014).
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator started from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Standard normal, by Box-Muller (one draw per call).
    pub fn gaussian(&mut self) -> f64 {
        // u1 in (0, 1] keeps the logarithm finite.
        let u1 = 1.0 - self.unit();
        let u2 = self.unit();
        (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }
}

/// The seed of the `index`-th independent stream derived from `seed`.
pub fn sub_seed(seed: u64, index: u64) -> u64 {
    SplitMix64::new(seed ^ index.wrapping_mul(0xD1B5_4A32_D192_ED03)).next_u64()
}

/// A stem: a circle in the field frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stem {
    /// Centre, field frame, m.
    pub x: f64,
    /// Centre, field frame, m.
    pub y: f64,
    /// Radius, m.
    pub r: f64,
    /// The row the stem is a plant of, or `None` for a weed.
    pub row: Option<usize>,
}

/// A row's centre line: from `(x0, y0)` along `direction` for `length` m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Start point, field frame, m.
    pub x0: f64,
    /// Start point, field frame, m.
    pub y0: f64,
    /// Direction of the row, field frame, rad.
    pub direction: f64,
    /// Length of the row, m.
    pub length: f64,
}

/// A stretch of a row with no plants: along-row distances `[from, to]` m
/// from the row's start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hole {
    /// Row index, from 0.
    pub row: usize,
    /// Start of the hole along the row, m.
    pub from: f64,
    /// End of the hole along the row, m.
    pub to: f64,
}

/// How to build a field. Row `i` (from 0) nominally starts at lateral offset
/// `i · spacing` to the left of the field origin and runs along `direction`.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldSpec {
    /// Number of rows.
    pub rows: usize,
    /// Nominal distance between neighbouring rows, m.
    pub spacing: f64,
    /// Length of every row, m.
    pub length: f64,
    /// Nominal direction of the rows, field frame, rad.
    pub direction: f64,
    /// Nominal distance between consecutive plants of a row, m.
    pub plant_gap: f64,
    /// Each plant moves along its row by a uniform draw in `±plant_jitter` m.
    pub plant_jitter: f64,
    /// Radius of a plant's stem, m.
    pub stem_radius: f64,
    /// Probability that each plant is missing.
    pub missing: f64,
    /// Stretches of rows without plants.
    pub holes: Vec<Hole>,
    /// Each row's start moves sideways by a uniform draw in
    /// `±spacing_jitter` m (uneven spacing).
    pub spacing_jitter: f64,
    /// Each row turns from `direction` by a uniform draw in `±row_skew` rad
    /// about its start (rows not quite parallel).
    pub row_skew: f64,
    /// Number of weeds, uniform over the field's rectangle (half a spacing
    /// beyond the outer rows).
    pub weeds: usize,
    /// Weed stem radii, uniform in `[min, max]` m.
    pub weed_radius: (f64, f64),
    /// Seed of every random choice of the field.
    pub seed: u64,
}

impl FieldSpec {
    /// Regular rows along the field's x axis, no jitter, holes or weeds.
    pub fn regular(rows: usize, spacing: f64, length: f64, plant_gap: f64, seed: u64) -> Self {
        Self {
            rows,
            spacing,
            length,
            direction: 0.0,
            plant_gap,
            plant_jitter: 0.0,
            stem_radius: STEM_RADIUS,
            missing: 0.0,
            holes: Vec::new(),
            spacing_jitter: 0.0,
            row_skew: 0.0,
            weeds: 0,
            weed_radius: (0.01, 0.02),
            seed,
        }
    }

    /// The field: rows first, then plants row by row, then weeds, each from
    /// its own stream of the seed.
    pub fn build(&self) -> Field {
        let mut rng_rows = SplitMix64::new(sub_seed(self.seed, 1));
        let mut rng_plants = SplitMix64::new(sub_seed(self.seed, 2));
        let mut rng_weeds = SplitMix64::new(sub_seed(self.seed, 3));
        let (c, s) = (self.direction.cos(), self.direction.sin());
        let mut rows = Vec::with_capacity(self.rows);
        for i in 0..self.rows {
            let lateral = i as f64 * self.spacing
                + rng_rows.uniform(-self.spacing_jitter, self.spacing_jitter);
            let direction = self.direction + rng_rows.uniform(-self.row_skew, self.row_skew);
            rows.push(Row {
                x0: -s * lateral,
                y0: c * lateral,
                direction,
                length: self.length,
            });
        }
        let mut stems = Vec::new();
        let count = (self.length / self.plant_gap).floor() as usize;
        for (i, row) in rows.iter().enumerate() {
            let (rc, rs) = (row.direction.cos(), row.direction.sin());
            for k in 0..=count {
                let t = k as f64 * self.plant_gap
                    + rng_plants.uniform(-self.plant_jitter, self.plant_jitter);
                // Always draw, so one plant's removal leaves the others put.
                let gone = rng_plants.unit() < self.missing;
                let in_hole = self
                    .holes
                    .iter()
                    .any(|h| h.row == i && t >= h.from && t <= h.to);
                if gone || in_hole || t < 0.0 || t > row.length {
                    continue;
                }
                stems.push(Stem {
                    x: row.x0 + rc * t,
                    y: row.y0 + rs * t,
                    r: self.stem_radius,
                    row: Some(i),
                });
            }
        }
        let plants = stems.len();
        let lat_lo = -0.5 * self.spacing;
        let lat_hi = (self.rows as f64 - 0.5) * self.spacing;
        for _ in 0..self.weeds {
            let along = rng_weeds.uniform(0.0, self.length);
            let lateral = rng_weeds.uniform(lat_lo, lat_hi);
            let r = rng_weeds.uniform(self.weed_radius.0, self.weed_radius.1);
            stems.push(Stem {
                x: c * along - s * lateral,
                y: s * along + c * lateral,
                r,
                row: None,
            });
        }
        Field {
            rows,
            stems,
            plants,
        }
    }
}

/// A built field: its rows' centre lines and all its stems.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    /// The rows, in order of increasing nominal lateral offset.
    pub rows: Vec<Row>,
    /// Plants first (`stems[..plants]`), then weeds.
    pub stems: Vec<Stem>,
    /// Number of plants.
    pub plants: usize,
}

/// A pose in the field frame: position, m, and heading, rad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Position, m.
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Heading, rad, counter-clockwise from the field's x axis.
    pub heading: f64,
}

impl Pose {
    /// The pose `(x, y, heading)`.
    pub const fn new(x: f64, y: f64, heading: f64) -> Self {
        Self { x, y, heading }
    }

    /// This pose composed with `local`, a pose in this pose's frame.
    pub fn compose(&self, local: &Self) -> Self {
        let (c, s) = (self.heading.cos(), self.heading.sin());
        Self {
            x: self.x + c * local.x - s * local.y,
            y: self.y + s * local.x + c * local.y,
            heading: self.heading + local.heading,
        }
    }

    /// Field point `(x, y)` in this pose's frame.
    pub fn local(&self, x: f64, y: f64) -> (f64, f64) {
        let (c, s) = (self.heading.cos(), self.heading.sin());
        let (dx, dy) = (x - self.x, y - self.y);
        (c * dx + s * dy, -s * dx + c * dy)
    }
}

/// Where a LiDAR sits on the robot: position, m, and yaw, rad, in the robot
/// frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// Position, robot frame, m.
    pub x: f64,
    /// Position, robot frame, m.
    pub y: f64,
    /// Yaw relative to the robot, rad.
    pub yaw: f64,
}

impl Mount {
    /// At the robot's origin, facing forward.
    pub const CENTRE: Self = Self {
        x: 0.0,
        y: 0.0,
        yaw: 0.0,
    };

    /// `dist` m ahead of the robot's origin, facing forward.
    pub const fn front(dist: f64) -> Self {
        Self {
            x: dist,
            y: 0.0,
            yaw: 0.0,
        }
    }

    /// `dist` m behind the robot's origin, facing backward.
    pub const fn back(dist: f64) -> Self {
        Self {
            x: -dist,
            y: 0.0,
            yaw: PI,
        }
    }

    /// The mount as a pose in the robot frame.
    pub const fn pose(&self) -> Pose {
        Pose::new(self.x, self.y, self.yaw)
    }

    /// The mount as the library's sensor-to-robot transform.
    pub fn transform(&self) -> fieldguide::Transform2<fieldguide::Sensor, fieldguide::Robot> {
        fieldguide::Transform2::new(self.x, self.y, self.yaw).unwrap()
    }
}

/// A planar LiDAR: ray `k` (from 0) points at `start + k · increment` rad in
/// the sensor frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lidar {
    /// Number of rays.
    pub rays: usize,
    /// First ray's angle, sensor frame, rad.
    pub start: f64,
    /// Angle between consecutive rays, rad.
    pub increment: f64,
    /// Smallest valid range, m.
    pub min_range: f64,
    /// Ranges at or beyond this are no return, m.
    pub max_range: f64,
    /// Standard deviation of the Gaussian noise on each return, m.
    pub sigma: f64,
}

impl Lidar {
    /// The paper's LiDAR: 360 rays from −π/2 to π/2 (both included), ranges
    /// 0.1-4 m, σ = 0.01 m (it runs at 40 Hz). Ranges are not quantised.
    pub fn paper() -> Self {
        Self {
            rays: 360,
            start: -FRAC_PI_2,
            increment: PI / 359.0,
            min_range: 0.1,
            max_range: 4.0,
            sigma: 0.01,
        }
    }

    /// The same LiDAR without noise.
    pub fn noiseless(self) -> Self {
        Self { sigma: 0.0, ..self }
    }

    /// Ray `k`'s angle in the sensor frame, rad.
    pub fn angle(&self, k: usize) -> f64 {
        self.start + k as f64 * self.increment
    }
}

/// Ranges as a LiDAR delivered them, with its geometry; `scan` lends them as
/// the library's `Scan`.
#[derive(Debug, Clone, PartialEq)]
pub struct RawScan {
    /// Ray `k`'s range, m, or [`NO_RETURN`].
    pub ranges: Vec<f64>,
    /// The LiDAR that took it.
    pub lidar: Lidar,
    /// The sensor's pose in the field frame.
    pub sensor: Pose,
}

impl RawScan {
    /// The library's view of this scan.
    pub fn scan(&self) -> Scan<'_> {
        Scan {
            start: Radians::new(self.lidar.start).unwrap(),
            increment: Radians::new(self.lidar.increment).unwrap(),
            ranges: &self.ranges,
            limits: RangeLimits::new(
                Meters::new(self.lidar.min_range).unwrap(),
                Meters::new(self.lidar.max_range).unwrap(),
            )
            .unwrap(),
        }
    }

    /// Sensor-frame points of the valid returns, `(x, y)` m.
    pub fn points(&self) -> Vec<(f64, f64)> {
        self.ranges
            .iter()
            .enumerate()
            .filter(|(_, r)| {
                r.is_finite() && **r >= self.lidar.min_range && **r < self.lidar.max_range
            })
            .map(|(k, r)| {
                let a = self.lidar.angle(k);
                (r * a.cos(), r * a.sin())
            })
            .collect()
    }
}

/// Distance along the unit ray `(ox, oy) + t (ux, uy)` to the first crossing
/// of `stem`'s circle, if ahead of the origin; a sensor inside a stem does
/// not see it.
pub fn ray_circle(ox: f64, oy: f64, ux: f64, uy: f64, stem: &Stem) -> Option<f64> {
    let (wx, wy) = (stem.x - ox, stem.y - oy);
    let tc = wx * ux + wy * uy;
    let d2 = wx * wx + wy * wy - tc * tc;
    let r2 = stem.r * stem.r;
    if d2 > r2 {
        return None;
    }
    let t = tc - (r2 - d2).sqrt();
    (t >= 0.0).then_some(t)
}

impl Field {
    /// The scan taken by `lidar` on `mount` with the robot at `robot`, noise
    /// drawn from `seed`. A ray whose first stem is at or beyond the maximum
    /// range (or that hits none) is [`NO_RETURN`]; noise is added to the
    /// others, so a noisy return may fall outside the valid interval.
    pub fn cast(&self, robot: &Pose, mount: &Mount, lidar: &Lidar, seed: u64) -> RawScan {
        let sensor = robot.compose(&mount.pose());
        // Only stems that a ray can reach within the maximum range.
        let near: Vec<Stem> = self
            .stems
            .iter()
            .filter(|s| {
                let reach = lidar.max_range + s.r;
                let (dx, dy) = (s.x - sensor.x, s.y - sensor.y);
                dx * dx + dy * dy <= reach * reach
            })
            .copied()
            .collect();
        let mut rng = SplitMix64::new(seed);
        let ranges = (0..lidar.rays)
            .map(|k| {
                let a = sensor.heading + lidar.angle(k);
                let (ux, uy) = (a.cos(), a.sin());
                let hit = near
                    .iter()
                    .filter_map(|s| ray_circle(sensor.x, sensor.y, ux, uy, s))
                    .fold(NO_RETURN, f64::min);
                if hit < lidar.max_range {
                    hit + lidar.sigma * rng.gaussian()
                } else {
                    NO_RETURN
                }
            })
            .collect();
        RawScan {
            ranges,
            lidar: *lidar,
            sensor,
        }
    }

    /// Row `row`'s centre line in the frame of `frame` (a field pose) as
    /// `y = a x + b`, or `None` when the row is perpendicular to that frame's
    /// x axis (within 1e-9 of the cosine).
    ///
    /// A line fitted to LiDAR returns sits about one stem radius inside the
    /// centre line, towards the sensor: the rays hit the stems' near faces.
    pub fn row_line_in(&self, row: usize, frame: &Pose) -> Option<Line> {
        let r = &self.rows[row];
        let (x, y) = frame.local(r.x0, r.y0);
        let phi = r.direction - frame.heading;
        if phi.cos().abs() < 1e-9 {
            return None;
        }
        let a = phi.tan();
        Some(Line { a, b: y - a * x })
    }

    /// Row `row`'s centre line in the robot frame at `robot` (see
    /// [`Field::row_line_in`]).
    pub fn row_line(&self, row: usize, robot: &Pose) -> Option<Line> {
        self.row_line_in(row, robot)
    }

    /// Every row's line in the robot frame, with its index, skipping rows
    /// perpendicular to the robot.
    pub fn row_lines(&self, robot: &Pose) -> Vec<(usize, Line)> {
        (0..self.rows.len())
            .filter_map(|i| self.row_line(i, robot).map(|l| (i, l)))
            .collect()
    }

    /// The row directly left of the robot: the smallest positive intercept.
    pub fn left_row(&self, robot: &Pose) -> Option<(usize, Line)> {
        self.row_lines(robot)
            .into_iter()
            .filter(|(_, l)| l.b > 0.0)
            .min_by(|p, q| p.1.b.total_cmp(&q.1.b))
    }

    /// The row directly right of the robot: the largest negative intercept.
    pub fn right_row(&self, robot: &Pose) -> Option<(usize, Line)> {
        self.row_lines(robot)
            .into_iter()
            .filter(|(_, l)| l.b < 0.0)
            .max_by(|p, q| p.1.b.total_cmp(&q.1.b))
    }

    /// The middle line between the rows directly left and right: at every x,
    /// halfway between their two lines.
    pub fn middle_line(&self, robot: &Pose) -> Option<Line> {
        let (_, l) = self.left_row(robot)?;
        let (_, r) = self.right_row(robot)?;
        Some(Line {
            a: 0.5 * (l.a + r.a),
            b: 0.5 * (l.b + r.b),
        })
    }

    /// The point halfway between rows `left` and `right` at distance `along`
    /// from their start, and the mean of their directions.
    pub fn between(&self, right: usize, left: usize, along: f64) -> Pose {
        let point = |r: &Row| {
            (
                r.x0 + r.direction.cos() * along,
                r.y0 + r.direction.sin() * along,
            )
        };
        let (p, q) = (point(&self.rows[right]), point(&self.rows[left]));
        Pose::new(
            0.5 * (p.0 + q.0),
            0.5 * (p.1 + q.1),
            0.5 * (self.rows[right].direction + self.rows[left].direction),
        )
    }

    /// `count` scans as the robot drives between rows `right` and `right + 1`
    /// from `from` m along them, one every `step` m, each pose moved sideways
    /// by a uniform draw in `±lateral` m and turned by one in `±yaw` rad; one
    /// scan per mount, all from `seed`.
    #[allow(clippy::too_many_arguments)]
    pub fn drive_between(
        &self,
        right: usize,
        from: f64,
        step: f64,
        count: usize,
        wobble: (f64, f64),
        mounts: &[Mount],
        lidar: &Lidar,
        seed: u64,
    ) -> Vec<DriveSample> {
        let mut rng = SplitMix64::new(sub_seed(seed, 0));
        (0..count)
            .map(|i| {
                let centre = self.between(right, right + 1, from + i as f64 * step);
                let shift = rng.uniform(-wobble.0, wobble.0);
                let turn = rng.uniform(-wobble.1, wobble.1);
                let robot = centre.compose(&Pose::new(0.0, shift, turn));
                let scans = mounts
                    .iter()
                    .enumerate()
                    .map(|(m, mount)| {
                        let noise = sub_seed(seed, 1 + (i * mounts.len() + m) as u64);
                        self.cast(&robot, mount, lidar, noise)
                    })
                    .collect();
                DriveSample { robot, scans }
            })
            .collect()
    }
}

/// A line `y = a x + b` in some frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Slope.
    pub a: f64,
    /// Intercept, m.
    pub b: f64,
}

impl Line {
    /// The line's y at `x`.
    pub fn y(&self, x: f64) -> f64 {
        self.a * x + self.b
    }

    /// Signed distance from the point to the line, positive above it.
    pub fn distance(&self, x: f64, y: f64) -> f64 {
        (y - self.y(x)) / (1.0 + self.a * self.a).sqrt()
    }
}

/// One step of a drive: the robot's true pose and one scan per mount.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveSample {
    /// The robot's pose, field frame.
    pub robot: Pose,
    /// The scans, in the order of the mounts.
    pub scans: Vec<RawScan>,
}

/// The paper's two LiDARs, `dist` m ahead facing forward and `dist` m behind
/// facing backward (the paper gives no offsets).
pub fn paper_mounts(dist: f64) -> [Mount; 2] {
    [Mount::front(dist), Mount::back(dist)]
}

/// Length of the preset fields' rows, m.
pub const PRESET_LENGTH: f64 = 10.0;

/// Distance between consecutive plants in the preset fields, m.
pub const PRESET_GAP: f64 = 0.2;

/// Crop 1: five equal rows, regularly placed plants, no weeds.
pub fn crop1(seed: u64, spacing: f64) -> FieldSpec {
    FieldSpec::regular(5, spacing, PRESET_LENGTH, PRESET_GAP, seed)
}

/// Crop 2: crop 1 with plants randomly spaced along the rows (each moved by
/// up to 40 % of the gap).
pub fn crop2(seed: u64, spacing: f64) -> FieldSpec {
    FieldSpec {
        plant_jitter: 0.4 * PRESET_GAP,
        ..crop1(seed, spacing)
    }
}

/// Crop 3: crop 2 with 50 weeds (a count: a longer field has them sparser).
pub fn crop3(seed: u64, spacing: f64) -> FieldSpec {
    FieldSpec {
        weeds: 50,
        ..crop2(seed, spacing)
    }
}

/// Crop 4: five rows with holes and weeds: crop 2's randomly spaced plants,
/// 10 % of them missing, one 0.6 m hole per row at a random place, and 100
/// weeds. The paper calls its rows "uneven" but keeps the distance between
/// rows constant within a crop (section 4.1.2), so the rows stay parallel
/// and evenly spaced here; [`uneven`] moves and turns them.
pub fn crop4(seed: u64, spacing: f64) -> FieldSpec {
    let mut rng = SplitMix64::new(sub_seed(seed, 4));
    let holes = (0..5)
        .map(|row| {
            let from = rng.uniform(0.0, PRESET_LENGTH - 0.6);
            Hole {
                row,
                from,
                to: from + 0.6,
            }
        })
        .collect();
    FieldSpec {
        missing: 0.1,
        holes,
        weeds: 100,
        ..crop2(seed, spacing)
    }
}

/// Beyond the paper's assumptions: crop 4 with each row's start moved
/// sideways by up to 5 % of the spacing and its direction turned by up to
/// 0.005 rad, 5 cm over the 10 m (a drill that wandered, passes that did
/// not quite join).
pub fn uneven(seed: u64, spacing: f64) -> FieldSpec {
    FieldSpec {
        spacing_jitter: 0.05 * spacing,
        row_skew: 0.005,
        ..crop4(seed, spacing)
    }
}

/// The preset of crop `n` (1 to 4).
pub fn crop(n: usize, seed: u64, spacing: f64) -> FieldSpec {
    match n {
        1 => crop1(seed, spacing),
        2 => crop2(seed, spacing),
        3 => crop3(seed, spacing),
        4 => crop4(seed, spacing),
        _ => panic!("the paper has crops 1 to 4, not {n}"),
    }
}
