//! The firmware example's field, shared by the firmware and the host.
//!
//! A robot on a straight reference path along the world's x axis passes a
//! ragged hedge on its left (seen by a horizontal LiDAR, for edge following),
//! then drives into two crop rows (seen by an inclined LiDAR, for furrow
//! pursuing). Each tick, [`Field::tick`] casts both scans from the robot's
//! pose (at 10 Hz), runs one tick of the Pierre 2022 pipeline
//! ([`fieldguide::presets::pierre2022_both`]), applies the command to a
//! kinematic bicycle and returns a [`TickLine`], whose `Display` is the line
//! the firmware prints over semihosting.
//!
//! Everything here is `no_std`, allocation-free and computed with `libm`
//! and IEEE-754 arithmetic only, so the Cortex-M4F (soft `f64`) and the host
//! print the same lines bit for bit; `.ci/run` compares them.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};
use core::fmt;

use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::guidance::{Guidance, GuidanceConfig, RoutedScan, TickInput};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::edge::Side;
use fieldguide::perception::furrow::FurrowParams;
use fieldguide::perception::{AnyDetector, AnyDetectorConfig, Detector, RangeLimits, Scan};
use fieldguide::presets::{pierre2022_both, EDGE, FURROW};
use fieldguide::{
    Meters, Odom, Point2, Pose2, Precondition, Radians, Robot, Sensor, Transform2, World,
};

/// Control ticks the example runs (100 Hz: 8 s).
pub const TICKS: u32 = 800;

/// Control ticks between two scans of either LiDAR (10 Hz, within the
/// presets' 0.1 s scan age).
pub const SCAN_EVERY: u32 = 10;

/// Rays of either scan.
pub const RAYS: usize = 360;

/// Capacity of the reference path, in vertices.
pub const PATH_CAPACITY: usize = 128;

/// Waypoints of the straight path: every 0.5 m from x = 0 to 60 m.
const WAYPOINTS: usize = 121;

/// The control period, s (the presets' 100 Hz).
const PERIOD: f64 = 0.01;

/// The simulated bicycle's wheelbase, m (the presets' vehicle).
const WHEELBASE: f64 = 2.0;

/// The horizontal LiDAR's mount: 1.2 m ahead of the rear axle, facing forward.
const HEDGE_MOUNT_X: f64 = 1.2;

/// The hedge's face runs along world x from here...
const HEDGE_FROM: f64 = -5.0;
/// ...to here, m.
const HEDGE_TO: f64 = 3.5;

/// The crop rows start at this world x, m, and run on past the path's end.
const ROWS_FROM: f64 = 7.0;
/// Lateral positions of the two rows' centre lines, m.
const ROWS_Y: [f64; 2] = [-0.375, 0.375];
/// Half the width of a row, m.
const ROW_HALF_WIDTH: f64 = 0.08;
/// Height of a row, m.
const ROW_HEIGHT: f64 = 0.3;

/// Range noise amplitude of the inclined scan, m (peak to peak).
const ROWS_NOISE: f64 = 0.004;

/// The pipeline of the example on its path of [`PATH_CAPACITY`] vertices,
/// for detector capacities `D`.
pub type Pipeline<'p, D> = Guidance<'p, PATH_CAPACITY, D, BacksteppingConfig, 2>;

/// The detector of [`fieldguide::presets::Pierre2022`]: the default
/// capacities (512 edge points, 64 chain points, 512 furrow rays, 32 scans).
pub type FullDetector = AnyDetector;

/// Capacities that still hold every valid ray of this example's 360-ray scans
/// and the furrow detector's 25 averaged scans: 384 edge points, 64 chain
/// points, 192 furrow window rays, 25 scans.
pub type CompactDetector = AnyDetector<384, 64, 192, 25>;

/// `core::mem::size_of` of the pipeline for detector capacities `D`.
#[must_use]
pub const fn pipeline_size<D: Detector<Config = AnyDetectorConfig>>() -> usize {
    core::mem::size_of::<Pipeline<'static, D>>()
}

/// `core::mem::size_of` of the reference path.
#[must_use]
pub const fn path_size() -> usize {
    core::mem::size_of::<ReferencePath<PATH_CAPACITY>>()
}

/// `core::mem::size_of` of the field (the robot's pose and both scans' ranges).
#[must_use]
pub const fn field_size() -> usize {
    core::mem::size_of::<Field>()
}

/// The straight reference path: [`WAYPOINTS`] waypoints 0.5 m apart along x.
///
/// Not inlined, like [`pipeline`]: the waypoints and the construction's
/// temporaries live in this function's frame, popped before the first tick,
/// instead of staying in the caller's for the whole run (the worst stack
/// measured under QEMU falls from 108 to 83 KiB).
///
/// # Errors
/// None in practice: the waypoints satisfy every precondition.
#[inline(never)]
pub fn straight_path() -> Result<ReferencePath<PATH_CAPACITY>, Precondition> {
    let mut waypoints = [Point2::<World>::new(0.0, 0.0)?; WAYPOINTS];
    for (point, i) in waypoints.iter_mut().zip(0_u16..) {
        *point = Point2::new(0.5 * f64::from(i), 0.0)?;
    }
    ReferencePath::from_waypoints(&waypoints, PathConfig::default())
}

/// The horizontal LiDAR's mount pose (sensor → robot).
///
/// # Errors
/// None in practice.
pub fn hedge_mount() -> Result<Transform2<Sensor, Robot>, Precondition> {
    Transform2::new(HEDGE_MOUNT_X, 0.0, 0.0)
}

/// The pipeline on `path`: both behaviours of the presets, furrow pursuing
/// first, the hedge on the left.
///
/// Not inlined: the parameters and the configuration it is built from live
/// in this function's frame, popped before the first tick.
///
/// # Errors
/// None in practice: the presets satisfy every precondition.
#[inline(never)]
pub fn pipeline<D: Detector<Config = AnyDetectorConfig>>(
    path: &ReferencePath<PATH_CAPACITY>,
) -> Result<Pipeline<'_, D>, Precondition> {
    let params = pierre2022_both(Side::Left, hedge_mount()?)?;
    Guidance::new(GuidanceConfig::new(&params)?, path)
}

/// What one tick printed: its number, the mode after it and the command
/// applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickLine {
    /// The tick's number, from 0.
    pub tick: u32,
    /// The mode's label (`path_tracking`, `edge_following`, ...).
    pub mode: &'static str,
    /// The label of the command's source, `-` without one (during a
    /// behaviour's exit delay, path tracking commands in the behaviour's mode).
    pub source: &'static str,
    /// The command's speed (m/s) and steering angle (rad), or `None` when
    /// no source could command.
    pub command: Option<(f64, f64)>,
}

impl fmt::Display for TickLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:3} {:<15} {:<15}", self.tick, self.mode, self.source)?;
        match self.command {
            Some((speed, steering)) => write!(f, " v {speed:.3} delta {steering:+.6}"),
            None => f.write_str(" v - delta -"),
        }
    }
}

/// The world and the robot in it: its true pose (GNSS and odometry read it
/// exactly, both frames coincide with the world's) and the ranges of the
/// latest scans.
#[derive(Debug, Clone)]
pub struct Field {
    tick: u32,
    x: f64,
    y: f64,
    heading: f64,
    horizontal: [f64; RAYS],
    inclined: [f64; RAYS],
}

impl Default for Field {
    fn default() -> Self {
        Self::new()
    }
}

impl Field {
    /// The robot at the path's start, 0.15 m to its left, heading along it.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            tick: 0,
            x: 0.0,
            y: 0.15,
            heading: 0.0,
            horizontal: [f64::INFINITY; RAYS],
            inclined: [f64::INFINITY; RAYS],
        }
    }

    /// One control tick: on every [`SCAN_EVERY`]-th tick both scans cast
    /// from the current pose, one step of `pipeline`, the command applied for
    /// one period.
    ///
    /// Not inlined: the tick's output and scans live in this function's
    /// frame, popped after each tick.
    ///
    /// # Errors
    /// Whatever the pipeline refuses (nothing, for the inputs made here).
    #[inline(never)]
    pub fn tick<D: Detector<Config = AnyDetectorConfig>>(
        &mut self,
        pipeline: &mut Pipeline<'_, D>,
    ) -> Result<TickLine, Precondition> {
        let scanning = self.tick % SCAN_EVERY == 0;
        if scanning {
            self.cast_hedge();
            self.cast_rows(&FurrowParams::table2());
        }
        let scans = [
            RoutedScan {
                behaviour: EDGE,
                scan: Scan {
                    start: Radians::new(-PI)?,
                    increment: Radians::new(hedge_increment())?,
                    ranges: &self.horizontal,
                    limits: RangeLimits::new(Meters::new(0.05)?, Meters::new(30.0)?)?,
                },
            },
            RoutedScan {
                behaviour: FURROW,
                scan: Scan {
                    start: Radians::new(-FRAC_PI_4)?,
                    increment: Radians::new(rows_increment())?,
                    ranges: &self.inclined,
                    limits: RangeLimits::new(Meters::new(0.1)?, Meters::new(20.0)?)?,
                },
            },
        ];
        let out = pipeline.step(&TickInput {
            scans: if scanning { &scans } else { &[] },
            gnss: Some(Pose2::<World>::new(self.x, self.y, self.heading)?),
            odometry: Pose2::<Odom>::new(self.x, self.y, self.heading)?,
            extra: Sideslip::ZERO,
        })?;
        let command = out.command.map(|c| {
            let steering = c.command.steering().map_or(0.0, Radians::get);
            (c.command.speed().get(), steering)
        });
        let line = TickLine {
            tick: self.tick,
            mode: pipeline.label(out.mode),
            source: out.source.map_or("-", |s| pipeline.label(s)),
            command,
        };
        if let Some((speed, steering)) = command {
            self.drive(speed, steering);
        }
        self.tick = self.tick.wrapping_add(1);
        Ok(line)
    }

    /// The kinematic bicycle (rear axle) for one period.
    fn drive(&mut self, speed: f64, steering: f64) {
        let step = speed * PERIOD;
        self.x += step * libm::cos(self.heading);
        self.y += step * libm::sin(self.heading);
        self.heading += step * libm::tan(steering) / WHEELBASE;
    }

    /// The horizontal scan: all round from −π, returns from the hedge's face
    /// only (nothing else within 30 m).
    fn cast_hedge(&mut self) {
        let (cos_h, sin_h) = (libm::cos(self.heading), libm::sin(self.heading));
        let origin_x = self.x + cos_h * HEDGE_MOUNT_X;
        let origin_y = self.y + sin_h * HEDGE_MOUNT_X;
        for (range, j) in self.horizontal.iter_mut().zip(0_u32..) {
            let angle = self.heading + (f64::from(j) * hedge_increment() - PI);
            *range = hedge_range(origin_x, origin_y, angle);
        }
    }

    /// The inclined scan over the ground and the rows, with a few
    /// millimetres of deterministic noise.
    fn cast_rows(&mut self, params: &FurrowParams) {
        let (h, pitch) = (params.mount_height.get(), params.mount_pitch.get());
        let (mount_x, mount_y) = (params.mount_x.get(), params.mount_y.get());
        let (cos_h, sin_h) = (libm::cos(self.heading), libm::sin(self.heading));
        let origin_x = self.x + cos_h * mount_x - sin_h * mount_y;
        let origin_y = self.y + sin_h * mount_x + cos_h * mount_y;
        let (cos_p, sin_p) = (libm::cos(pitch), libm::sin(pitch));
        let tick = self.tick;
        for (range, j) in self.inclined.iter_mut().zip(0_u32..) {
            let angle = f64::from(j) * rows_increment() - FRAC_PI_4;
            let (cos_a, sin_a) = (libm::cos(angle), libm::sin(angle));
            // Per metre of range: down by `drop`, forward and left in the
            // robot's frame by (fx, fy), in the world's by (dx, dy).
            let drop = cos_a * sin_p;
            let (fx, fy) = (cos_a * cos_p, sin_a);
            let (dx, dy) = (cos_h * fx - sin_h * fy, sin_h * fx + cos_h * fy);
            let hit = rows_range(origin_x, origin_y, dx, dy, h, drop);
            *range = hit + ROWS_NOISE * noise(tick, j);
        }
    }
}

/// Angle between the horizontal scan's rays.
fn hedge_increment() -> f64 {
    TAU / 360.0
}

/// Angle between the inclined scan's rays: both edges of a 90° view.
fn rows_increment() -> f64 {
    FRAC_PI_2 / 359.0
}

/// The hedge face's lateral position at world abscissa `x`: 1.4 m with a
/// deterministic ragged profile of a few centimetres.
fn hedge_face(x: f64) -> f64 {
    1.4 - 0.02 * libm::sin(2.3 * x) - 0.01 * libm::sin(6.1 * x + 1.0)
}

/// Range from (`ox`, `oy`) along world direction `angle` to the hedge's face,
/// or +inf (no hedge on the ray, a grazing ray, or beyond 30 m).
fn hedge_range(ox: f64, oy: f64, angle: f64) -> f64 {
    let (dx, dy) = (libm::cos(angle), libm::sin(angle));
    if dy < 0.15 {
        return f64::INFINITY;
    }
    // Fixed point of t = (face(ox + t dx) − oy) / dy: the face's slope is
    // below 0.11 and |dx / dy| below 6.6, so a few steps settle it.
    let mut t = (1.4 - oy) / dy;
    for _ in 0..4 {
        t = (hedge_face(ox + t * dx) - oy) / dy;
    }
    let x = ox + t * dx;
    if t > 0.0 && t <= 30.0 && (HEDGE_FROM..=HEDGE_TO).contains(&x) {
        t
    } else {
        f64::INFINITY
    }
}

/// The interval of r where `lo ≤ a + b r ≤ hi`, or `None`.
fn slab(a: f64, b: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if libm::fabs(b) < 1e-12 {
        (lo..=hi)
            .contains(&a)
            .then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else {
        let (u, v) = ((lo - a) / b, (hi - a) / b);
        Some((libm::fmin(u, v), libm::fmax(u, v)))
    }
}

/// Range of a ray from (`ox`, `oy`) at height `h`, going (`dx`, `dy`) and
/// down by `drop` per metre, to flat ground or the first row it enters.
fn rows_range(ox: f64, oy: f64, dx: f64, dy: f64, h: f64, drop: f64) -> f64 {
    if drop < 1e-6 {
        return f64::INFINITY;
    }
    let ground = h / drop;
    let top = (h - ROW_HEIGHT) / drop;
    let start = if dx > 1e-12 {
        (ROWS_FROM - ox) / dx
    } else if ox >= ROWS_FROM {
        0.0
    } else {
        return ground;
    };
    let mut best = ground;
    for centre in ROWS_Y {
        let Some((y0, y1)) = slab(oy, dy, centre - ROW_HALF_WIDTH, centre + ROW_HALF_WIDTH) else {
            continue;
        };
        let entry = libm::fmax(libm::fmax(y0, top), libm::fmax(start, 0.0));
        if entry <= y1 && entry < best {
            best = entry;
        }
    }
    best
}

/// A deterministic value in [−0.5, 0.5] for ray `ray` of tick `tick`.
fn noise(tick: u32, ray: u32) -> f64 {
    let mut h = tick.wrapping_mul(0x9E37_79B9) ^ ray.wrapping_mul(0x85EB_CA6B);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 12;
    f64::from(h) / f64::from(u32::MAX) - 0.5
}

/// Runs the whole example with detector capacities `D`, handing each tick's
/// line to `emit`.
///
/// # Errors
/// Whatever the pipeline refuses (nothing, for the inputs made here).
pub fn run<D: Detector<Config = AnyDetectorConfig>>(
    mut emit: impl FnMut(&TickLine),
) -> Result<(), Precondition> {
    let path = straight_path()?;
    let mut pipeline = pipeline::<D>(&path)?;
    let mut field = Field::new();
    for _ in 0..TICKS {
        let line = field.tick(&mut pipeline)?;
        emit(&line);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::string::{String, ToString};
    use std::vec::Vec;

    use super::*;

    fn lines<D: Detector<Config = AnyDetectorConfig>>() -> Vec<String> {
        let mut out = Vec::new();
        run::<D>(|line| out.push(line.to_string())).unwrap();
        out
    }

    #[test]
    fn the_run_passes_every_mode_and_commands_every_tick() {
        let mut modes = Vec::new();
        let mut count = 0;
        run::<FullDetector>(|line| {
            count += 1;
            assert!(line.command.is_some(), "tick {} has no command", line.tick);
            if modes.last() != Some(&line.mode) {
                modes.push(line.mode);
            }
        })
        .unwrap();
        assert_eq!(count, TICKS);
        assert_eq!(
            modes,
            [
                "path_tracking",
                "edge_following",
                "path_tracking",
                "furrow_pursuing"
            ]
        );
    }

    #[test]
    fn compact_capacities_print_the_same_lines() {
        assert_eq!(lines::<FullDetector>(), lines::<CompactDetector>());
    }

    #[test]
    fn lines_have_fixed_decimals() {
        let line = TickLine {
            tick: 7,
            mode: "edge_following",
            source: "path_tracking",
            command: Some((0.4, -0.012_345_67)),
        };
        assert_eq!(
            line.to_string(),
            "  7 edge_following  path_tracking   v 0.400 delta -0.012346"
        );
        let none = TickLine {
            tick: 12,
            mode: "stop",
            source: "-",
            command: None,
        };
        assert_eq!(
            none.to_string(),
            " 12 stop            -               v - delta -"
        );
    }
}
