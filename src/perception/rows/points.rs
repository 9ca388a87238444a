//! A horizontal scan's rays as robot-frame points (ROWS-POINTS), and the
//! one-point merge of Ruby Genetic One Point (Guyonneau 2022, section 2.2.2,
//! Alg. 2; RUBY-ONE-POINT).

use heapless::Vec;

use crate::error::Precondition;
use crate::geometry::frame::{Point2, Robot, Sensor, Transform2};
use crate::geometry::units::Meters;
use crate::perception::Scan;

/// A point of Z or Z*: a position in the robot frame and the number of
/// returns it stands for (1 in Z; the size of its run in Z*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowPoint {
    /// Position in the robot frame, m.
    pub position: Point2<Robot>,
    /// Returns merged into it (≥ 1).
    pub returns: u16,
}

/// The points of one scan, at most `N`, in ray order.
pub type Points<const N: usize> = Vec<RowPoint, N>;

/// What [`scan_points`] kept and what it had no room for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gathered {
    /// Valid returns kept as points.
    pub kept: usize,
    /// Valid returns dropped because the buffer was full.
    pub dropped: usize,
}

/// The scan's valid returns as robot-frame points through the sensor mount,
/// in ray order, appended to `out` (cleared first).
///
/// A ray is used only when the scan's limits accept its range (LIB-SCAN);
/// a valid return beyond `out`'s capacity is counted in
/// [`Gathered::dropped`], never lost silently. Errors with `LIB-FINITE` only
/// when a transformed point overflows.
pub fn scan_points<const N: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
    out: &mut Points<N>,
) -> Result<Gathered, Precondition> {
    gather(scan, mount, out, |_, phi| libm::sincos(phi))
}

/// [`scan_points`] with the rays' sines and cosines taken from `rays`, which
/// keeps them from scan to scan while the scan's start, increment and ray
/// count stay the same (a LiDAR's rays do not move): the same points, bit
/// for bit, without a sine and a cosine per ray. Rays beyond `R` are
/// computed as [`scan_points`] computes them.
///
/// # Errors
/// As [`scan_points`].
pub fn scan_points_with<const N: usize, const R: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
    rays: &mut Rays<R>,
    out: &mut Points<N>,
) -> Result<Gathered, Precondition> {
    rays.prepare(scan);
    gather(scan, mount, out, |k, phi| {
        rays.directions
            .get(k)
            .copied()
            .unwrap_or_else(|| libm::sincos(phi))
    })
}

/// The (sin φ, cos φ) of the first `R` rays of a scan's geometry, φ = start
/// + k · increment as [`scan_points`] computes it.
#[derive(Debug, Clone)]
pub struct Rays<const R: usize> {
    /// The geometry the table holds: start and increment (their bits) and
    /// the number of rays; `None` before the first scan.
    key: Option<(u64, u64, usize)>,
    directions: heapless::Vec<(f64, f64), R>,
}

impl<const R: usize> Rays<R> {
    /// An empty table (filled by the first scan).
    #[must_use]
    pub const fn new() -> Self {
        Self {
            key: None,
            directions: heapless::Vec::new(),
        }
    }

    /// Fills the table for `scan`'s geometry unless it holds it already.
    fn prepare(&mut self, scan: &Scan<'_>) {
        let (start, step) = (scan.start.get(), scan.increment.get());
        let key = Some((start.to_bits(), step.to_bits(), scan.ranges.len()));
        if self.key == key {
            return;
        }
        self.key = key;
        self.directions.clear();
        let mut k = 0.0_f64;
        for _ in scan.ranges.iter().take(R) {
            let _ = self.directions.push(libm::sincos(start + k * step));
            k += 1.0;
        }
    }
}

impl<const R: usize> Default for Rays<R> {
    fn default() -> Self {
        Self::new()
    }
}

/// The points of [`scan_points`], ray `k`'s (sin φ, cos φ) from
/// `direction(k, φ)`.
//= spec/guyonneau2022.md#rows-points-scan-points-in-the-robot-frame
//# Every ray whose range the scan's limits accept MUST become the point
//# (r cos φ, r sin φ) of the sensor frame, φ = start + k · increment, moved into
//# the robot frame through the sensor's mount; rays are kept in ray order.
//= spec/guyonneau2022.md#rows-points-scan-points-in-the-robot-frame
//# A valid return that does not fit in the point buffer MUST be counted as
//# dropped in the result.
fn gather<const N: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
    out: &mut Points<N>,
    mut direction: impl FnMut(usize, f64) -> (f64, f64),
) -> Result<Gathered, Precondition> {
    out.clear();
    let mut dropped = 0_usize;
    let (start, step) = (scan.start.get(), scan.increment.get());
    // k as a float, exact for any slice length.
    let mut k = 0.0_f64;
    for (index, &range) in scan.ranges.iter().enumerate() {
        if scan.limits.accepts(range) {
            let (sin, cos) = direction(index, start + k * step);
            let p = Point2::<Sensor>::new(range * cos, range * sin)?;
            let point = RowPoint {
                position: mount.apply(p)?,
                returns: 1,
            };
            if out.push(point).is_err() {
                dropped = dropped.saturating_add(1);
            }
        }
        k += 1.0;
    }
    Ok(Gathered {
        kept: out.len(),
        dropped,
    })
}

/// Z* from Z (Alg. 2): consecutive points, in ray order, closer than
/// `merge_distance` to the running centroid of their run are merged into it,
/// in place; the centroid weighs every return of the run equally.
//= spec/guyonneau2022.md#ruby-one-point-consecutive-returns-merged
//# With the one-point refinement, each point of Z, in ray order, MUST join the
//# current run when it lies strictly closer than the merge distance to the
//# run's centroid, and MUST start a new run otherwise; Z* MUST hold one point
//# per run, at the centroid of the run's returns, weighted by their counts.
pub fn merge_runs<const N: usize>(points: &mut Points<N>, merge_distance: Meters) {
    let limit = merge_distance.get();
    let limit_sq = limit * limit;
    let mut runs = 0_usize;
    let mut current: Option<(f64, f64, u16)> = None;
    let mut index = 0_usize;
    while let Some(p) = points.get(index).copied() {
        let (x, y) = (p.position.x(), p.position.y());
        current = match current {
            Some((cx, cy, n)) if (x - cx) * (x - cx) + (y - cy) * (y - cy) < limit_sq => {
                let total = n.saturating_add(p.returns);
                let share = f64::from(p.returns) / f64::from(total);
                Some((cx + (x - cx) * share, cy + (y - cy) * share, total))
            }
            previous => {
                if let Some(run) = previous {
                    store_run(points, runs, run);
                    runs = runs.saturating_add(1);
                }
                Some((x, y, p.returns))
            }
        };
        index = index.saturating_add(1);
    }
    if let Some(run) = current {
        store_run(points, runs, run);
        runs = runs.saturating_add(1);
    }
    points.truncate(runs);
}

/// Writes the centroid `(x, y)` of run `slot` and its count of returns over
/// `points[slot]` (every run starts at or after its slot, so nothing unread
/// is overwritten).
fn store_run<const N: usize>(
    points: &mut Points<N>,
    slot: usize,
    (x, y, returns): (f64, f64, u16),
) {
    if let (Some(p), Ok(position)) = (points.get_mut(slot), Point2::new(x, y)) {
        *p = RowPoint { position, returns };
    }
}
