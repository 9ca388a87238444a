//! From one front LiDAR scan to obstacles, circles and segments of the robot
//! frame (Emmi 2024, section 3.2; `spec/emmi2024.md`, EM-OBST-CLUSTER,
//! EM-OBST-SHAPE and EM-OBST-CAPACITY).
//!
//! Consecutive valid points closer than a gap form a cluster; a cluster of
//! too few points is a spurious return and is dropped. A cluster that fits
//! in a small circle becomes that circle, any other is split at its point
//! farthest from the chord until each part is a straight segment. Nothing is
//! stored but the obstacles: the points of a cluster are recomputed from its
//! rays for each pass.

use heapless::Vec;

use super::areas::{above, point_segment, Box2, Shape, Xy};
use super::Obstacle;
use crate::error::Precondition;
use crate::geometry::frame::{Point2, Robot, Sensor, Transform2};
use crate::geometry::units::Meters;
use crate::perception::scan::Scan;

/// How many parts one cluster may be split into at most (EM-OBST-SHAPE).
const MAX_PARTS: usize = 16;

/// A circle fit whose normal matrix has a determinant below this fraction of
/// its squared trace is singular (collinear points).
const SINGULAR: f64 = 1e-12;

/// How scan points are grouped into obstacles (EM-OBST-CLUSTER, EM-OBST-SHAPE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterConfig {
    gap: f64,
    min_points: usize,
    max_circle_radius: f64,
    split_tolerance: f64,
}

impl ClusterConfig {
    /// Consecutive valid points at most `gap` metres apart join one cluster;
    /// clusters of fewer than `min_points` points are spurious; a cluster
    /// inside a circle of at most `max_circle_radius` metres is a circle;
    /// a segment leaves no point farther than `split_tolerance` metres.
    ///
    /// # Errors
    /// `EM-OBST-CLUSTER` unless the three lengths lie in (0, 1e3] m and
    /// `min_points` is at least 2.
    //= spec/emmi2024.md#em-obst-cluster-clusters-of-scan-points
    //# The gap, the largest circle radius and the split tolerance MUST lie in
    //# (0, 1e3] m and the least number of points in a cluster MUST be at least
    //# 2; other values MUST be refused with the `EM-OBST-CLUSTER` error.
    pub fn new(
        gap: Meters,
        min_points: usize,
        max_circle_radius: Meters,
        split_tolerance: Meters,
    ) -> Result<Self, Precondition> {
        let ok = |v: f64| v > 0.0 && v <= super::areas::MAX_LENGTH;
        if ok(gap.get()) && ok(max_circle_radius.get()) && ok(split_tolerance.get()) {
            if min_points >= 2 {
                return Ok(Self {
                    gap: gap.get(),
                    min_points,
                    max_circle_radius: max_circle_radius.get(),
                    split_tolerance: split_tolerance.get(),
                });
            }
            return Err(Precondition::new(
                "EM-OBST-CLUSTER",
                "fewer than 2 points per cluster",
            ));
        }
        Err(Precondition::new(
            "EM-OBST-CLUSTER",
            "gap, circle radius or split tolerance outside (0, 1e3] m",
        ))
    }

    /// The values of `spec/emmi2024.md` (EM-OBST-CLUSTER): gap 0.2 m, at
    /// least 3 points, circles up to 0.5 m, split tolerance 0.1 m.
    #[must_use]
    pub const fn emmi2024() -> Self {
        Self {
            gap: 0.2,
            min_points: 3,
            max_circle_radius: 0.5,
            split_tolerance: 0.1,
        }
    }
}

/// At most `N` obstacles, the nearest to the robot frame's origin, and what
/// was left out (EM-OBST-CAPACITY).
#[derive(Debug, Clone, PartialEq)]
pub struct Obstacles<const N: usize> {
    items: Vec<Obstacle, N>,
    nearest_dropped: Option<f64>,
    spurious: usize,
}

impl<const N: usize> Default for Obstacles<N> {
    fn default() -> Self {
        Self::new()
    }
}

/// Distance from the robot frame's origin to the obstacle, metres.
pub(super) fn distance(o: &Obstacle) -> f64 {
    Shape::of(o).box_distance(&Box2 {
        x0: 0.0,
        x1: 0.0,
        half_width: 0.0,
    })
}

impl<const N: usize> Obstacles<N> {
    /// No obstacle.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            items: Vec::new(),
            nearest_dropped: None,
            spurious: 0,
        }
    }

    /// Adds `obstacle`; when `N` are held, the farthest of the `N + 1` from
    /// the origin is dropped and its distance remembered. Returns whether
    /// `obstacle` is held.
    //= spec/emmi2024.md#em-obst-capacity-a-bounded-list-of-obstacles
    //# When more obstacles are found than the list holds, the list MUST keep
    //# those nearest to the robot frame's origin and MUST report the least
    //# distance of a dropped one.
    pub fn insert(&mut self, obstacle: Obstacle) -> bool {
        let Err(obstacle) = self.items.push(obstacle) else {
            return true;
        };
        let d = distance(&obstacle);
        let farthest = self
            .items
            .iter()
            .enumerate()
            .map(|(i, o)| (i, distance(o)))
            .fold(None, |best: Option<(usize, f64)>, (i, di)| match best {
                Some((_, db)) if !above(di, db) => best,
                _ => Some((i, di)),
            });
        let (held, dropped) = match (farthest, self.items.is_empty()) {
            (Some((i, df)), false) if d < df => {
                if let Some(slot) = self.items.get_mut(i) {
                    *slot = obstacle;
                }
                (true, df)
            }
            _ => (false, d),
        };
        // A distance that is not a number (never from finite shapes) counts as 0.
        let dropped = if dropped.is_nan() { 0.0 } else { dropped };
        self.nearest_dropped = Some(self.nearest_dropped.map_or(dropped, |n| n.min(dropped)));
        held
    }

    /// The obstacles held.
    #[must_use]
    pub fn as_slice(&self) -> &[Obstacle] {
        &self.items
    }

    /// The least distance of a dropped obstacle from the origin, metres;
    /// `None` when none was dropped.
    #[must_use]
    pub fn nearest_dropped(&self) -> Option<Meters> {
        self.nearest_dropped.and_then(|d| Meters::new(d).ok())
    }

    /// Whether an obstacle was dropped (even one too far to measure).
    pub(super) const fn dropped_any(&self) -> bool {
        self.nearest_dropped.is_some()
    }

    /// How many clusters were dropped as spurious (too few points).
    #[must_use]
    pub const fn spurious(&self) -> usize {
        self.spurious
    }
}

/// The scan's rays as robot-frame points, recomputed on demand.
struct Rays<'s, 'a> {
    scan: &'s Scan<'a>,
    mount: &'s Transform2<Sensor, Robot>,
}

impl Rays<'_, '_> {
    /// The point of ray `k`, if its range is valid and the point finite.
    fn point(&self, k: usize) -> Option<Xy> {
        let range = *self.scan.ranges.get(k)?;
        if !self.scan.limits.accepts(range) {
            return None;
        }
        let kf = f64::from(u32::try_from(k).ok()?);
        let angle = self.scan.start.get() + kf * self.scan.increment.get();
        let p = Point2::<Sensor>::new(range * libm::cos(angle), range * libm::sin(angle)).ok()?;
        let p = self.mount.apply(p).ok()?;
        Some((p.x(), p.y()))
    }

    /// The valid points of rays `a..=b`.
    fn points(&self, a: usize, b: usize) -> impl Iterator<Item = (usize, Xy)> + '_ {
        (a..=b).filter_map(move |k| self.point(k).map(|p| (k, p)))
    }
}

/// Clusters `scan` (read through the LiDAR's `mount` pose) into at most `N`
/// obstacles of the robot frame (Emmi 2024, section 3.2).
//= spec/emmi2024.md#em-obst-cluster-clusters-of-scan-points
//# Two consecutive valid points of the scan (invalid rays between them
//# skipped) MUST belong to one cluster when they are at most the gap apart,
//# and to two otherwise.
//= spec/emmi2024.md#em-obst-cluster-clusters-of-scan-points
//# A cluster of fewer points than the least number MUST be dropped as
//# spurious and counted.
#[must_use]
pub fn cluster<const N: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
    config: &ClusterConfig,
) -> Obstacles<N> {
    let rays = Rays { scan, mount };
    let sensor = mount
        .apply(Point2::origin())
        .map_or((0.0, 0.0), |p| (p.x(), p.y()));
    let mut out = Obstacles::new();
    // The current cluster: its first ray, its last point and its size.
    let mut current: Option<(usize, (usize, Xy), usize)> = None;
    for (k, p) in rays.points(0, scan.ranges.len().saturating_sub(1)) {
        current = match current {
            Some((first, (_, last), n))
                if libm::hypot(p.0 - last.0, p.1 - last.1) <= config.gap =>
            {
                Some((first, (k, p), n.saturating_add(1)))
            }
            Some((first, (end, _), n)) => {
                close(&rays, sensor, config, (first, end), n, &mut out);
                Some((k, (k, p), 1))
            }
            None => Some((k, (k, p), 1)),
        };
    }
    if let Some((first, (end, _), n)) = current {
        close(&rays, sensor, config, (first, end), n, &mut out);
    }
    out
}

/// Ends the cluster of rays `first..=end` holding `n` valid points.
fn close<const N: usize>(
    rays: &Rays<'_, '_>,
    sensor: Xy,
    config: &ClusterConfig,
    (first, end): (usize, usize),
    n: usize,
    out: &mut Obstacles<N>,
) {
    if n < config.min_points {
        out.spurious = out.spurious.saturating_add(1);
        return;
    }
    let mut parts: Vec<(usize, usize), MAX_PARTS> = Vec::new();
    // One slot is free: the push cannot fail.
    let _ = parts.push((first, end));
    while let Some((a, b)) = parts.pop() {
        if let Some(o) = shape(rays, sensor, config, (a, b), &mut parts) {
            out.insert(o);
        }
    }
}

/// The obstacle of rays `a..=b` (valid at both ends), or `None` after
/// pushing its two halves on `parts`.
//= spec/emmi2024.md#em-obst-shape-circles-and-segments
//# A cluster whose points all lie within a circle of at most the largest
//# circle radius MUST become such a circle, enclosing every point of the
//# cluster.
//= spec/emmi2024.md#em-obst-shape-circles-and-segments
//# Any other cluster MUST be split at its point farthest from the chord
//# joining its first and last points until no point of a part is farther
//# than the split tolerance from the part's chord; each such part MUST
//# become the segment of its chord.
fn shape<const P: usize>(
    rays: &Rays<'_, '_>,
    sensor: Xy,
    config: &ClusterConfig,
    (a, b): (usize, usize),
    parts: &mut Vec<(usize, usize), P>,
) -> Option<Obstacle> {
    let circle = enclosing_circle(rays, sensor, (a, b), config.max_circle_radius);
    if let Some((c, r)) = circle {
        if r <= config.max_circle_radius {
            return circle_obstacle(c, r);
        }
    }
    let (pa, pb) = (rays.point(a)?, rays.point(b)?);
    let (m, deviation) = rays
        .points(a, b)
        .map(|(k, p)| (k, point_segment(p, pa, pb)))
        .fold(
            (a, 0.0_f64),
            |(km, dm), (k, d)| {
                if d > dm {
                    (k, d)
                } else {
                    (km, dm)
                }
            },
        );
    if deviation <= config.split_tolerance || m == a || m == b {
        return segment_obstacle(pa, pb);
    }
    if parts.len().saturating_add(2) <= P {
        let _ = parts.push((m, b));
        let _ = parts.push((a, m));
        return None;
    }
    // No room to split further: the enclosing circle covers every point.
    circle.and_then(|(c, r)| circle_obstacle(c, r))
}

/// The circle obstacle, if finite.
fn circle_obstacle(c: Xy, r: f64) -> Option<Obstacle> {
    Some(Obstacle::Circle {
        centre: Point2::new(c.0, c.1).ok()?,
        radius: Meters::new(r).ok()?,
    })
}

/// The segment obstacle, if finite.
fn segment_obstacle(a: Xy, b: Xy) -> Option<Obstacle> {
    Some(Obstacle::Segment {
        start: Point2::new(a.0, a.1).ok()?,
        end: Point2::new(b.0, b.1).ok()?,
    })
}

/// A circle enclosing the valid points of rays `a..=b`: centred on the
/// least-squares circle (Kåsa fit) when that centre lies behind the points
/// as the sensor sees them and the circle is at most `max_radius`, otherwise
/// on the centroid; the radius reaches the farthest point.
fn enclosing_circle(
    rays: &Rays<'_, '_>,
    sensor: Xy,
    (a, b): (usize, usize),
    max_radius: f64,
) -> Option<(Xy, f64)> {
    let (n, sx, sy) = rays
        .points(a, b)
        .fold((0.0_f64, 0.0_f64, 0.0_f64), |(n, sx, sy), (_, p)| {
            (n + 1.0, sx + p.0, sy + p.1)
        });
    if !above(n, 0.0) {
        return None;
    }
    let mean = (sx / n, sy / n);
    // Centred sums of the Kåsa fit: uu, uv, vv, uuu + uvv, vvv + uuv.
    let mut s = [0.0_f64; 5];
    for (_, p) in rays.points(a, b) {
        let (u, v) = (p.0 - mean.0, p.1 - mean.1);
        let r2 = u * u + v * v;
        s = [
            s[0] + u * u,
            s[1] + u * v,
            s[2] + v * v,
            s[3] + u * r2,
            s[4] + v * r2,
        ];
    }
    let [suu, suv, svv, bu, bv] = s;
    let det = suu * svv - suv * suv;
    let trace = suu + svv;
    let fitted = if det > SINGULAR * trace * trace {
        let uc = 0.5 * (bu * svv - bv * suv) / det;
        let vc = 0.5 * (bv * suu - bu * suv) / det;
        let c = (mean.0 + uc, mean.1 + vc);
        let behind = libm::hypot(c.0 - sensor.0, c.1 - sensor.1)
            > libm::hypot(mean.0 - sensor.0, mean.1 - sensor.1);
        behind.then_some(c)
    } else {
        None
    };
    let reach = |c: Xy| {
        rays.points(a, b)
            .map(|(_, p)| libm::hypot(p.0 - c.0, p.1 - c.1))
            .fold(0.0_f64, f64::max)
    };
    let best = match fitted.map(|c| (c, reach(c))) {
        Some((c, r)) if r <= max_radius => (c, r),
        _ => (mean, reach(mean)),
    };
    (best.0 .0.is_finite() && best.0 .1.is_finite() && best.1.is_finite()).then_some(best)
}
