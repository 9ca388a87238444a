//! A horizontal LiDAR scan turned into 2D points of the robot frame
//! (Pierre 2022, section 2.2: "These measurements are converted into 2D points
//! on a plane parallel to the ground"; requirement EDGE-SCAN).

use heapless::Vec;

use crate::error::Precondition;
use crate::geometry::frame::{Point2, Robot, Sensor, Transform2};
use crate::perception::scan::Scan;

/// Largest coordinate magnitude, in metres, that the edge detector accepts
/// for a point (EDGE-SCAN). It keeps every squared distance of the chain far
/// from overflow.
pub const MAX_COORDINATE: f64 = 1.0e6;

/// How many rays are converted with the rotation recurrence before the ray
/// direction is recomputed from `sin`/`cos` (bounds the rounding drift).
const REANCHOR_EVERY: u32 = 32;

/// The valid points of a scan in the robot frame, in ray order, with the
/// number of rays that were dropped.
#[derive(Debug, Clone)]
pub struct ScanPoints<const N: usize> {
    points: Vec<Point2<Robot>, N>,
    dropped: usize,
}

impl<const N: usize> Default for ScanPoints<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> ScanPoints<N> {
    /// No point yet.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            points: Vec::new(),
            dropped: 0,
        }
    }

    /// The points, robot frame, in ray order.
    #[must_use]
    pub fn as_slice(&self) -> &[Point2<Robot>] {
        self.points.as_slice()
    }

    /// How many rays had an invalid range (NaN, infinite, or outside the
    /// scan's [`RangeLimits`](crate::perception::RangeLimits)).
    #[must_use]
    pub const fn dropped(&self) -> usize {
        self.dropped
    }
}

/// Converts a scan into points of the robot frame through the LiDAR's mount
/// pose `mount` (sensor → robot), dropping invalid ranges (Pierre 2022,
/// section 2.2; EDGE-SCAN).
///
/// Ray `k` gives `mount(range_k · (cos φ_k, sin φ_k))` with
/// `φ_k = start + k · increment`. Ray directions are advanced by rotation and
/// recomputed exactly every 32 rays, so the drift stays below 1e-14 rad.
///
/// Errors with `EDGE-SCAN` when more than `N` rays are valid (the buffer is
/// full) or when a point would lie farther than [`MAX_COORDINATE`] from the
/// robot (a mount pose far off the robot).
pub fn scan_to_points<const N: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
) -> Result<ScanPoints<N>, Precondition> {
    let mut out = ScanPoints::new();
    scan_into(scan, mount, &mut out)?;
    Ok(out)
}

/// [`scan_to_points`] into a caller's buffer (cleared first), so that a
/// detector reuses one buffer instead of returning a large value. On error
/// the buffer holds the points converted so far.
//= spec/pierre2022.md#edge-scan-scan-to-robot-frame-points
//# Each range MUST be converted into the point `range · (cos φ_k, sin φ_k)`
//# of the sensor frame, with `φ_k = start + k · increment`, and then into
//# the robot frame through the LiDAR's mount pose.
//= spec/pierre2022.md#edge-scan-scan-to-robot-frame-points
//# A range that is NaN, infinite, or outside the sensor's `[min, max)`
//# interval MUST be dropped.
pub fn scan_into<const N: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
    out: &mut ScanPoints<N>,
) -> Result<(), Precondition> {
    out.points.clear();
    out.dropped = 0;
    let (step_cos, step_sin) = (
        libm::cos(scan.increment.get()),
        libm::sin(scan.increment.get()),
    );
    let mut k_f = 0.0_f64;
    let mut since_anchor = 0_u32;
    let mut dir = (libm::cos(scan.start.get()), libm::sin(scan.start.get()));
    for &range in scan.ranges {
        if since_anchor >= REANCHOR_EVERY {
            let angle = scan.start.get() + k_f * scan.increment.get();
            dir = (libm::cos(angle), libm::sin(angle));
            since_anchor = 0;
        }
        if scan.limits.accepts(range) {
            let sensor = Point2::<Sensor>::new(range * dir.0, range * dir.1)?;
            let robot = mount.apply(sensor)?;
            if libm::fabs(robot.x()) > MAX_COORDINATE || libm::fabs(robot.y()) > MAX_COORDINATE {
                return Err(Precondition::new(
                    "EDGE-SCAN",
                    "point farther than 1e6 m from the robot",
                ));
            }
            if out.points.push(robot).is_err() {
                return Err(Precondition::new(
                    "EDGE-SCAN",
                    "more valid rays than the point buffer holds",
                ));
            }
        } else {
            out.dropped = out.dropped.saturating_add(1);
        }
        dir = (
            dir.0 * step_cos - dir.1 * step_sin,
            dir.0 * step_sin + dir.1 * step_cos,
        );
        k_f += 1.0;
        since_anchor = since_anchor.saturating_add(1);
    }
    Ok(())
}

/// Checks that every point is within [`MAX_COORDINATE`] of the robot (EDGE-SCAN).
pub(crate) fn check_bounded(points: &[Point2<Robot>]) -> Result<(), Precondition> {
    if points
        .iter()
        .all(|p| libm::fabs(p.x()) <= MAX_COORDINATE && libm::fabs(p.y()) <= MAX_COORDINATE)
    {
        Ok(())
    } else {
        Err(Precondition::new(
            "EDGE-SCAN",
            "point farther than 1e6 m from the robot",
        ))
    }
}
