//! First step of furrow detection: an inclined 2D LiDAR scan turned into 3D
//! points of the robot frame, restricted to an angular window around the
//! forward axis (Pierre 2022, section 2.3; `spec/pierre2022.md` FUR-SCAN).

use crate::error::Precondition;
use crate::geometry::frame::{Point2, Robot};
use crate::geometry::units::{Meters, Radians};
use crate::perception::scan::Scan;

/// Where an inclined LiDAR sits on the robot (FUR-SCAN).
///
/// The sensor origin is at `(x, y, height)` in the robot frame (x forward,
/// y left, z up, origin O at the middle of the rear axle, on the ground). The
/// scan plane is the sensor's x-y plane, pitched by `pitch` about the robot's
/// y axis: a right-handed rotation about y (left), so a positive pitch turns
/// the sensor's x axis down toward the ground. No roll, no yaw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MountPose {
    x: Meters,
    y: Meters,
    height: Meters,
    pitch: Radians,
    cos_pitch: f64,
    sin_pitch: f64,
}

impl MountPose {
    /// A mount `x` m forward and `y` m left of O, `height` m above the ground,
    /// pitched down by `pitch` rad.
    ///
    /// Errors with `FUR-SCAN` unless `height > 0` and `0 < pitch < π/2` (the
    /// scan plane must meet the ground ahead of the sensor).
    pub fn new(x: Meters, y: Meters, height: Meters, pitch: Radians) -> Result<Self, Precondition> {
        if height.get() <= 0.0 {
            return Err(Precondition::new("FUR-SCAN", "mount height must be > 0"));
        }
        let p = pitch.get();
        if !(p > 0.0 && p < core::f64::consts::FRAC_PI_2) {
            return Err(Precondition::new(
                "FUR-SCAN",
                "mount pitch must lie in (0, pi/2), nose down",
            ));
        }
        Ok(Self {
            x,
            y,
            height,
            pitch,
            cos_pitch: libm::cos(p),
            sin_pitch: libm::sin(p),
        })
    }

    /// Forward offset of the sensor from O, m.
    #[must_use]
    pub const fn x(&self) -> Meters {
        self.x
    }

    /// Left offset of the sensor from O, m.
    #[must_use]
    pub const fn y(&self) -> Meters {
        self.y
    }

    /// Height of the sensor above the ground, m.
    #[must_use]
    pub const fn height(&self) -> Meters {
        self.height
    }

    /// Pitch, rad, positive nose down.
    #[must_use]
    pub const fn pitch(&self) -> Radians {
        self.pitch
    }

    /// The range at which the ray of in-plane angle `angle` (rad) meets flat
    /// ground z = 0: `height / (cos(angle) sin(pitch))`, or `None` when the
    /// ray does not go down.
    #[must_use]
    pub fn ground_range(&self, angle: Radians) -> Option<f64> {
        let down = libm::cos(angle.get()) * self.sin_pitch;
        let r = self.height.get() / down;
        (down > 0.0 && r.is_finite()).then_some(r)
    }

    /// The point of the robot frame hit by the ray of in-plane angle with
    /// cosine `cos_a` and sine `sin_a` at range `r` m:
    /// `x = x_m + r cos a cos p`, `y = y_m + r sin a`, `z = h − r cos a sin p`.
    fn point(&self, r: f64, cos_a: f64, sin_a: f64) -> Option<ScanPoint> {
        let x = self.x.get() + r * cos_a * self.cos_pitch;
        let y = self.y.get() + r * sin_a;
        let z = self.height.get() - r * cos_a * self.sin_pitch;
        let ground = Point2::new(x, y).ok()?;
        let height = Meters::new(z).ok()?;
        Some(ScanPoint { ground, height })
    }
}

/// Which rays of a scan the furrow detector looks at: those within a
/// half-angle of the forward axis (FUR-SCAN). Which ranges are trusted is the
/// sensor's business: the scan's [`RangeLimits`](crate::perception::RangeLimits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanWindow {
    half_angle: Radians,
}

impl ScanWindow {
    /// Rays with `|angle| ≤ half_angle`.
    ///
    /// Errors with `FUR-SCAN` unless `0 < half_angle < π/2`.
    pub fn new(half_angle: Radians) -> Result<Self, Precondition> {
        let h = half_angle.get();
        if h > 0.0 && h < core::f64::consts::FRAC_PI_2 {
            Ok(Self { half_angle })
        } else {
            Err(Precondition::new(
                "FUR-SCAN",
                "window half angle must lie in (0, pi/2)",
            ))
        }
    }

    /// Half the angular width of the window, rad.
    #[must_use]
    pub const fn half_angle(&self) -> Radians {
        self.half_angle
    }
}

/// A LiDAR return as a 3D point of the robot frame: its ground position
/// (x forward, y left) and its height z above the ground plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanPoint {
    /// Position projected on the ground, robot frame, m.
    pub ground: Point2<Robot>,
    /// Height above the ground plane z = 0 of the robot frame, m.
    pub height: Meters,
}

/// The rays of a scan that fall in the window: `first` is the scan index of
/// window ray 0, `count` how many window rays were written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WindowRays {
    /// Index in the scan of the first ray inside the window.
    pub first: usize,
    /// Number of rays inside the window (also the length written to `out`).
    pub count: usize,
}

/// Converts the rays of `scan` inside `window` into robot-frame points through
/// `mount`, writing one entry per window ray to `out` in scan order (Pierre
/// 2022, section 2.3, first step).
///
/// A ray whose range the sensor's limits do not accept
/// ([`RangeLimits::accepts`](crate::perception::RangeLimits::accepts)) keeps its place
/// as `None`: window ray `i` is always scan ray `first + i`, so ray indices,
/// and the correlation shifts built on them, stay those of the sensor.
///
/// Errors with `FUR-SCAN` when the angles do not grow with the ray index
/// (`increment ≤ 0`)
/// or when the window holds more rays than `out` can take.
//= spec/pierre2022.md#fur-scan-scan-to-robot-frame-points-in-an-angular-window
//# Each ray of the scan whose in-plane angle a satisfies |a| ≤ a_w MUST be
//# converted into the robot-frame point x = x_m + r cos a cos p,
//# y = y_m + r sin a, z = h_m − r cos a sin p, where (x_m, y_m, h_m) is the
//# mount position and p its pitch (positive down).
//= spec/pierre2022.md#fur-scan-scan-to-robot-frame-points-in-an-angular-window
//# A ray whose range is not finite or lies outside the sensor's [min, max)
//# MUST be dropped while keeping its index, so that window ray i is scan ray
//# first + i.
pub fn scan_to_points(
    scan: &Scan<'_>,
    mount: &MountPose,
    window: &ScanWindow,
    out: &mut [Option<ScanPoint>],
) -> Result<WindowRays, Precondition> {
    let increment = scan.increment.get();
    if increment <= 0.0 {
        return Err(Precondition::new(
            "FUR-SCAN",
            "scan angle increment must be > 0",
        ));
    }
    let (cos_inc, sin_inc) = (libm::cos(increment), libm::sin(increment));
    let half = window.half_angle.get();
    let mut first = None;
    let mut count = 0_usize;
    // Running trigonometry: the first window ray is evaluated directly, each
    // next one by one rotation of `increment`, which keeps a ray at a few
    // multiply-adds (error below 1e-13 over thousands of rays).
    let (mut cos_a, mut sin_a) = (1.0, 0.0);
    let mut k = 0.0_f64;
    for (j, &range) in scan.ranges.iter().enumerate() {
        let angle = scan.start.get() + k * increment;
        k += 1.0;
        if angle > half {
            break;
        }
        if angle < -half {
            continue;
        }
        if first.is_none() {
            first = Some(j);
            cos_a = libm::cos(angle);
            sin_a = libm::sin(angle);
        } else {
            let next_cos = cos_a * cos_inc - sin_a * sin_inc;
            sin_a = sin_a * cos_inc + cos_a * sin_inc;
            cos_a = next_cos;
        }
        let slot = out.get_mut(count).ok_or(Precondition::new(
            "FUR-SCAN",
            "the window holds more rays than the detector's capacity",
        ))?;
        *slot = if scan.limits.accepts(range) {
            mount.point(range, cos_a, sin_a)
        } else {
            None
        };
        count = count.saturating_add(1);
    }
    Ok(WindowRays {
        first: first.unwrap_or(0),
        count,
    })
}
