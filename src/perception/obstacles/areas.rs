//! The robot's footprint and the two safety areas ahead of it (Emmi 2024,
//! section 3.2; `spec/emmi2024.md`, EM-OBST-CONFIG and EM-OBST-AREAS).
//!
//! Both areas are rectangles of the robot frame as wide as the robot plus the
//! safety margin on each side. The critical area covers the footprint and
//! `critical(v)` metres ahead of the front; the warning area the next
//! `warning(v)` metres. Each length is `base + gain · v` for the nominal
//! speed `v`.

use super::Obstacle;
use crate::error::Precondition;
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};
use crate::planning::dubins::TurningRadius;

/// Largest accepted length of the configuration, metres (EM-OBST-CONFIG).
pub const MAX_LENGTH: f64 = 1e3;

/// Largest accepted gain of an area's length over the speed, s (EM-OBST-CONFIG).
pub const MAX_GAIN: f64 = 100.0;

/// Smallest and largest accepted step of the clearance checks, metres
/// (EM-OBST-CONFIG).
pub const STEP_RANGE: (f64, f64) = (1e-3, 1.0);

/// The error of a configuration out of range.
const fn config_error(violated: &'static str) -> Precondition {
    Precondition::new("EM-OBST-CONFIG", violated)
}

/// `value` when finite and in `[lo, hi]`, else the `EM-OBST-CONFIG` error.
fn within(value: f64, lo: f64, hi: f64, violated: &'static str) -> Result<f64, Precondition> {
    if value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(config_error(violated))
    }
}

/// The robot's outline seen from above: a rectangle from `rear` metres behind
/// the robot frame's origin to `front` metres ahead of it, `width` wide,
/// centred on the x axis (EM-OBST-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    front: f64,
    rear: f64,
    half_width: f64,
}

impl Footprint {
    /// The footprint from the origin's distances to the front and the rear
    /// and the width, metres.
    ///
    /// # Errors
    /// `EM-OBST-CONFIG` unless `front`, `rear` lie in [0, 1e3] m with
    /// `front + rear > 0` and `width` in (0, 1e3] m.
    //= spec/emmi2024.md#em-obst-config-footprint-margin-and-areas
    //# The footprint's front and rear distances MUST lie in [0, 1e3] m with
    //# a positive sum, and its width in (0, 1e3] m; other values MUST be
    //# refused with the `EM-OBST-CONFIG` error.
    pub fn new(front: Meters, rear: Meters, width: Meters) -> Result<Self, Precondition> {
        let front = within(front.get(), 0.0, MAX_LENGTH, "front outside [0, 1e3] m")?;
        let rear = within(rear.get(), 0.0, MAX_LENGTH, "rear outside [0, 1e3] m")?;
        if front + rear <= 0.0 {
            return Err(config_error("footprint of zero length"));
        }
        let width = within(width.get(), 0.0, MAX_LENGTH, "width outside (0, 1e3] m")?;
        if width <= 0.0 {
            return Err(config_error("footprint of zero width"));
        }
        Ok(Self {
            front,
            rear,
            half_width: 0.5 * width,
        })
    }

    /// Distance from the origin to the front edge, metres.
    #[must_use]
    pub const fn front(&self) -> Meters {
        Meters(self.front)
    }

    /// Distance from the origin to the rear edge, metres.
    #[must_use]
    pub const fn rear(&self) -> Meters {
        Meters(self.rear)
    }

    /// The width, metres.
    #[must_use]
    pub fn width(&self) -> Meters {
        Meters(2.0 * self.half_width)
    }

    /// The footprint as a box of its own body frame.
    pub(super) const fn body_box(&self) -> Box2 {
        Box2 {
            x0: -self.rear,
            x1: self.front,
            half_width: self.half_width,
        }
    }

    /// The largest distance of a footprint point from the origin, metres.
    pub(super) fn radius(&self) -> f64 {
        libm::hypot(self.front.max(self.rear), self.half_width)
    }
}

/// The length of one safety area: `base + gain · v` metres for the nominal
/// speed `v` (EM-OBST-AREAS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLength {
    base: f64,
    gain: f64,
}

impl AreaLength {
    /// A length of `base` metres at rest, growing by `gain` seconds times the
    /// nominal speed.
    ///
    /// # Errors
    /// `EM-OBST-CONFIG` unless `base` lies in [0, 1e3] m and `gain` in
    /// [0, 100] s.
    //= spec/emmi2024.md#em-obst-config-footprint-margin-and-areas
    //# An area's base length MUST lie in [0, 1e3] m and its gain in
    //# [0, 100] s; other values MUST be refused with the `EM-OBST-CONFIG`
    //# error.
    pub fn new(base: Meters, gain: Seconds) -> Result<Self, Precondition> {
        Ok(Self {
            base: within(base.get(), 0.0, MAX_LENGTH, "base outside [0, 1e3] m")?,
            gain: within(gain.get(), 0.0, MAX_GAIN, "gain outside [0, 100] s")?,
        })
    }

    /// The length at nominal speed `v`, m/s (`v` at least 0).
    fn at(&self, v: f64) -> f64 {
        self.base + self.gain * v
    }
}

/// Everything the obstacle handling needs besides the obstacles and the
/// robot's state (EM-OBST-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObstacleConfig {
    footprint: Footprint,
    margin: f64,
    critical: AreaLength,
    warning: AreaLength,
    radius: TurningRadius,
    step: f64,
}

impl ObstacleConfig {
    /// A configuration: the footprint, the safety margin (metres, kept
    /// between the footprint and any obstacle), the two areas' lengths, the
    /// Dubins turning radius of re-planning and the step of the clearance
    /// checks (metres).
    ///
    /// # Errors
    /// `EM-OBST-CONFIG` unless the margin lies in [0, 1e3] m and the step in
    /// [1e−3, 1] m.
    //= spec/emmi2024.md#em-obst-config-footprint-margin-and-areas
    //# The safety margin MUST lie in [0, 1e3] m and the step of the clearance
    //# checks in [1e−3, 1] m; other values MUST be refused with the
    //# `EM-OBST-CONFIG` error.
    pub fn new(
        footprint: Footprint,
        margin: Meters,
        critical: AreaLength,
        warning: AreaLength,
        radius: TurningRadius,
        step: Meters,
    ) -> Result<Self, Precondition> {
        Ok(Self {
            footprint,
            margin: within(margin.get(), 0.0, MAX_LENGTH, "margin outside [0, 1e3] m")?,
            critical,
            warning,
            radius,
            step: within(
                step.get(),
                STEP_RANGE.0,
                STEP_RANGE.1,
                "step outside [1e-3, 1] m",
            )?,
        })
    }

    /// The values of `spec/emmi2024.md` (EM-OBST-CONFIG) for the paper's
    /// platform (Table 1: 1.76 m wide, 1.5 m long, origin at its centre):
    /// margin 0.3 m, critical area 0.5 m + 1 s · v, warning area
    /// 2 m + 3 s · v, step 0.02 m, with the vehicle's turning `radius`.
    #[must_use]
    pub const fn emmi2024(radius: TurningRadius) -> Self {
        Self {
            footprint: Footprint {
                front: 0.75,
                rear: 0.75,
                half_width: 0.88,
            },
            margin: 0.3,
            critical: AreaLength {
                base: 0.5,
                gain: 1.0,
            },
            warning: AreaLength {
                base: 2.0,
                gain: 3.0,
            },
            radius,
            step: 0.02,
        }
    }

    /// The footprint.
    #[must_use]
    pub const fn footprint(&self) -> Footprint {
        self.footprint
    }

    /// The safety margin, metres.
    #[must_use]
    pub const fn margin(&self) -> Meters {
        Meters(self.margin)
    }

    /// The turning radius of re-planning.
    #[must_use]
    pub const fn radius(&self) -> TurningRadius {
        self.radius
    }

    /// The step of the clearance checks, metres.
    pub(super) const fn step(&self) -> f64 {
        self.step
    }

    /// The two areas at nominal speed `speed`.
    ///
    /// # Errors
    /// `EM-OBST-AREAS` for a negative speed or one above 100 m/s.
    //= spec/emmi2024.md#em-obst-areas-the-critical-and-the-warning-area
    //# At nominal speed v, the critical area MUST be the rectangle of the
    //# robot frame x ∈ [−rear, front + L_c(v)], |y| ≤ width/2 + margin, and
    //# the warning area the rectangle x ∈ [front + L_c(v), front + L_c(v) +
    //# L_w(v)] of the same width, with L(v) = base + gain · v for each area.
    pub fn areas(&self, speed: MetersPerSecond) -> Result<SafetyAreas, Precondition> {
        let v = speed.get();
        if !(0.0..=100.0).contains(&v) {
            return Err(Precondition::new(
                "EM-OBST-AREAS",
                "nominal speed outside [0, 100] m/s",
            ));
        }
        let half_width = self.footprint.half_width + self.margin;
        let critical_end = self.footprint.front + self.critical.at(v);
        Ok(SafetyAreas {
            critical: Box2 {
                x0: -self.footprint.rear,
                x1: critical_end,
                half_width,
            },
            warning: Box2 {
                x0: critical_end,
                x1: critical_end + self.warning.at(v),
                half_width,
            },
        })
    }
}

/// The critical and the warning area at one nominal speed, robot frame
/// (EM-OBST-AREAS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetyAreas {
    critical: Box2,
    warning: Box2,
}

impl SafetyAreas {
    /// How far the critical area reaches ahead of the robot frame's origin, metres.
    #[must_use]
    pub const fn critical_end(&self) -> Meters {
        Meters(self.critical.x1)
    }

    /// How far the warning area reaches ahead of the robot frame's origin, metres.
    #[must_use]
    pub const fn warning_end(&self) -> Meters {
        Meters(self.warning.x1)
    }

    /// Whether `obstacle` touches or overlaps the critical area (a shape
    /// whose distance is not a number counts as inside).
    //= spec/emmi2024.md#em-obst-areas-the-critical-and-the-warning-area
    //# An obstacle MUST be in an area when the closed rectangle and the
    //# obstacle's circle or segment have a point in common.
    #[must_use]
    pub fn in_critical(&self, obstacle: &Obstacle) -> bool {
        touches(Shape::of(obstacle), &self.critical)
    }

    /// Whether `obstacle` touches or overlaps the warning area.
    #[must_use]
    pub fn in_warning(&self, obstacle: &Obstacle) -> bool {
        touches(Shape::of(obstacle), &self.warning)
    }

    /// The farthest distance of a point of either area from the origin, metres.
    pub(super) fn reach(&self) -> f64 {
        let w = self.warning.half_width;
        libm::hypot(self.warning.x1.max(self.critical.x0.abs()), w)
    }
}

/// Whether the shape's distance to the box is 0 or not a number.
fn touches(shape: Shape, b: &Box2) -> bool {
    !above(shape.box_distance(b), 0.0)
}

/// `a > b`, false when either is not a number.
pub(super) fn above(a: f64, b: f64) -> bool {
    a > b
}

/// `a ≥ b`, false when either is not a number.
pub(super) fn at_least(a: f64, b: f64) -> bool {
    a >= b
}

/// An axis-aligned box `x ∈ [x0, x1]`, `|y| ≤ half_width`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Box2 {
    pub(super) x0: f64,
    pub(super) x1: f64,
    pub(super) half_width: f64,
}

/// A point as raw coordinates of whichever frame the caller works in.
pub(super) type Xy = (f64, f64);

/// An obstacle's shape as raw coordinates, in any frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Shape {
    /// Centre and radius (at least 0).
    Circle(Xy, f64),
    /// The two ends.
    Segment(Xy, Xy),
}

impl Shape {
    /// The shape of an obstacle (a negative radius read as 0).
    pub(super) fn of(obstacle: &Obstacle) -> Self {
        match *obstacle {
            Obstacle::Circle { centre, radius } => {
                Self::Circle((centre.x(), centre.y()), radius.get().max(0.0))
            }
            Obstacle::Segment { start, end } => {
                Self::Segment((start.x(), start.y()), (end.x(), end.y()))
            }
        }
    }

    /// The image under `p ↦ R(θ) p + t` with `(cos θ, sin θ)` given.
    pub(super) fn moved(self, cos: f64, sin: f64, t: Xy) -> Self {
        let f = |p: Xy| (cos * p.0 - sin * p.1 + t.0, sin * p.0 + cos * p.1 + t.1);
        match self {
            Self::Circle(c, r) => Self::Circle(f(c), r),
            Self::Segment(a, b) => Self::Segment(f(a), f(b)),
        }
    }

    /// The shape in the body frame of a body at `(x, y, θ)`.
    pub(super) fn into_body(self, x: f64, y: f64, heading: f64) -> Self {
        let (c, s) = (libm::cos(heading), libm::sin(heading));
        self.moved(c, -s, (-(c * x + s * y), s * x - c * y))
    }

    /// The distance to the box, 0 when they meet, metres.
    pub(super) fn box_distance(self, b: &Box2) -> f64 {
        match self {
            Self::Circle(c, r) => (point_box(c, b) - r).max(0.0),
            Self::Segment(p, q) => segment_box(p, q, b),
        }
    }
}

/// Distance from a point to a box (0 inside).
fn point_box(p: Xy, b: &Box2) -> f64 {
    let dx = (b.x0 - p.0).max(p.0 - b.x1).max(0.0);
    let dy = (libm::fabs(p.1) - b.half_width).max(0.0);
    libm::hypot(dx, dy)
}

/// Distance from a point to a segment.
pub(super) fn point_segment(p: Xy, a: Xy, b: Xy) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    libm::hypot(p.0 - (a.0 + t * dx), p.1 - (a.1 + t * dy))
}

/// Whether the segment meets the box (Liang–Barsky clipping).
fn segment_meets_box(p: Xy, q: Xy, b: &Box2) -> bool {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    // Each slab: −d t ≤ p − lo and d t ≤ hi − p.
    for (d, lo, hi, p0) in [
        (dx, b.x0, b.x1, p.0),
        (dy, -b.half_width, b.half_width, p.1),
    ] {
        for (num, den) in [(p0 - lo, -d), (hi - p0, d)] {
            if den == 0.0 {
                if num < 0.0 {
                    return false;
                }
            } else {
                let t = num / den;
                if den < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
    }
    t0 <= t1
}

/// Distance from a segment to a box: 0 when they meet, otherwise the least
/// distance between a vertex of one and the other.
fn segment_box(p: Xy, q: Xy, b: &Box2) -> f64 {
    if segment_meets_box(p, q, b) {
        return 0.0;
    }
    let corners = [
        (b.x0, -b.half_width),
        (b.x0, b.half_width),
        (b.x1, -b.half_width),
        (b.x1, b.half_width),
    ];
    corners
        .iter()
        .map(|&c| point_segment(c, p, q))
        .fold(point_box(p, b).min(point_box(q, b)), f64::min)
}
