//! The drivable corridor of a road leg: its centreline and half-width
//! (`spec/emmi2024.md`, EM-OBST-ROAD). A detour on a road must keep the
//! footprint inside it by the safety margin, or the robot stops.

use heapless::Vec;

use super::areas::{point_segment, Footprint, Xy};
use crate::error::Precondition;
use crate::geometry::frame::{Point2, World};
use crate::geometry::units::Meters;

/// Most vertices of a corridor's centreline (EM-OBST-ROAD).
pub const MAX_CORRIDOR_POINTS: usize = 8;

/// Largest accepted coordinate of a centreline vertex, metres (the Dubins
/// planner's range, EM-DUBINS-RANGE).
const MAX_COORDINATE: f64 = 1e7;

/// Largest accepted half-width, metres.
const MAX_HALF_WIDTH: f64 = 1e3;

/// A road's drivable corridor in the world frame: every point within
/// `half_width` of one stretch of the centreline (EM-OBST-ROAD).
#[derive(Debug, Clone, PartialEq)]
pub struct Corridor {
    points: Vec<Xy, MAX_CORRIDOR_POINTS>,
    half_width: f64,
}

impl Corridor {
    /// The corridor `half_width` either side of the polyline `centreline`.
    ///
    /// # Errors
    /// `EM-OBST-ROAD` for fewer than 2 or more than
    /// [`MAX_CORRIDOR_POINTS`] vertices, a vertex beyond 1e7 m, or a
    /// half-width outside (0, 1e3] m.
    //= spec/emmi2024.md#em-obst-road-detours-inside-the-road
    //# A corridor MUST be given by 2 to 8 centreline vertices of the world
    //# frame, each coordinate within 1e7 m, and a half-width in (0, 1e3] m;
    //# other values MUST be refused with the `EM-OBST-ROAD` error.
    pub fn new(centreline: &[Point2<World>], half_width: Meters) -> Result<Self, Precondition> {
        let refuse = |why| Err(Precondition::new("EM-OBST-ROAD", why));
        if centreline.len() < 2 {
            return refuse("a corridor needs at least 2 centreline vertices");
        }
        let mut points = Vec::new();
        for p in centreline {
            let (x, y) = (p.x(), p.y());
            if !(libm::fabs(x) <= MAX_COORDINATE && libm::fabs(y) <= MAX_COORDINATE) {
                return refuse("centreline vertex beyond 1e7 m");
            }
            if points.push((x, y)).is_err() {
                return refuse("more than 8 centreline vertices");
            }
        }
        let w = half_width.get();
        if !(w > 0.0 && w <= MAX_HALF_WIDTH) {
            return refuse("half-width outside (0, 1e3] m");
        }
        Ok(Self {
            points,
            half_width: w,
        })
    }

    /// The half-width, metres.
    #[must_use]
    pub const fn half_width(&self) -> Meters {
        Meters(self.half_width)
    }

    /// The room left round the footprint at `pose` (`(x, y, θ)`): over the
    /// stretches, the largest `half_width − d`, `d` the farthest footprint
    /// corner's distance from that stretch, metres (negative: outside).
    ///
    /// A stretch with every corner within `half_width − m` of it holds the
    /// whole rectangle by that much (the distance to a segment is convex),
    /// and each term changes by at most the corners' motion.
    //= spec/emmi2024.md#em-obst-road-detours-inside-the-road
    //# The room of a pose MUST be the largest, over the centreline's
    //# stretches, of the half-width less the distance from that stretch to
    //# the farthest of the footprint's four corners.
    pub(super) fn room(&self, pose: (f64, f64, f64), footprint: &Footprint) -> f64 {
        let (c, s) = (libm::cos(pose.2), libm::sin(pose.2));
        let b = footprint.body_box();
        let corners = [
            (b.x0, -b.half_width),
            (b.x0, b.half_width),
            (b.x1, -b.half_width),
            (b.x1, b.half_width),
        ]
        .map(|(u, v)| (pose.0 + c * u - s * v, pose.1 + s * u + c * v));
        self.points
            .windows(2)
            .filter_map(|w| match w {
                [a, b] => Some(
                    corners
                        .iter()
                        .map(|&q| point_segment(q, *a, *b))
                        .fold(f64::NEG_INFINITY, max_or_nan),
                ),
                _ => None,
            })
            .map(|far| self.half_width - far)
            .fold(f64::NEG_INFINITY, max_or_nan)
    }
}

/// The larger of two numbers, NaN when either is (so a non-finite pose has
/// no room).
fn max_or_nan(m: f64, x: f64) -> f64 {
    if m.is_nan() || x.is_nan() {
        f64::NAN
    } else if x > m {
        x
    } else {
        m
    }
}
