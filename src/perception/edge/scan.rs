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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::units::{Meters, Radians};
    use crate::perception::scan::RangeLimits;
    use core::f64::consts::FRAC_PI_2;

    fn limits() -> RangeLimits {
        RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(30.0).unwrap()).unwrap()
    }

    //= spec/pierre2022.md#edge-scan-scan-to-robot-frame-points
    //= type=test
    //# A range that is NaN, infinite, or outside the sensor's `[min, max)`
    //# interval MUST be dropped.
    #[test]
    fn invalid_ranges_are_dropped_and_points_are_mounted() {
        // 30.0 is the limit itself: "no return" for many drivers.
        let ranges = [2.0, f64::NAN, f64::INFINITY, 0.05, 31.0, 1.0, 30.0];
        let scan = Scan {
            start: Radians::new(0.0).unwrap(),
            increment: Radians::new(FRAC_PI_2).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        // LiDAR 1.5 m ahead of the rear axle, turned left by 90°.
        let mount = Transform2::<Sensor, Robot>::new(1.5, 0.0, FRAC_PI_2).unwrap();
        let pts = scan_to_points::<8>(&scan, &mount).unwrap();
        assert_eq!(pts.dropped(), 5);
        let p = pts.as_slice();
        assert_eq!(p.len(), 2);
        // Ray 0: 2 m along the sensor x axis = robot +y.
        assert!((p[0].x() - 1.5).abs() < 1e-12 && (p[0].y() - 2.0).abs() < 1e-12);
        // Ray 5 points at 5·90° = 90° (mod 360°) in the sensor: robot −x.
        assert!((p[1].x() - 0.5).abs() < 1e-9 && p[1].y().abs() < 1e-9);
    }

    #[test]
    fn full_buffer_is_an_error() {
        let ranges = [1.0; 5];
        let scan = Scan {
            start: Radians::new(0.0).unwrap(),
            increment: Radians::new(0.01).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        let mount = Transform2::<Sensor, Robot>::new(0.0, 0.0, 0.0).unwrap();
        let err = scan_to_points::<4>(&scan, &mount).unwrap_err();
        assert_eq!(err.requirement, "EDGE-SCAN");
    }

    //= spec/library.md#lib-scan-one-planar-lidar-scan
    //= type=test
    //# Ray k of a scan (k from 0) MUST be read at the angle start + k · increment
    //# of the scan plane, counter-clockwise from the sensor's x axis, with the
    //# increment signed as the sensor delivers it.
    #[test]
    fn recurrence_matches_direct_trigonometry() {
        let ranges = [3.0; 1000];
        // Counter-clockwise and clockwise (a LiDAR mounted upside down).
        for (start, increment) in [(-3.0, 0.00614), (3.0, -0.00614)] {
            let scan = Scan {
                start: Radians::new(start).unwrap(),
                increment: Radians::new(increment).unwrap(),
                ranges: &ranges,
                limits: limits(),
            };
            let mount = Transform2::<Sensor, Robot>::new(0.0, 0.0, 0.0).unwrap();
            let pts = scan_to_points::<1000>(&scan, &mount).unwrap();
            assert_eq!(pts.as_slice().len(), 1000);
            let mut k = 0.0;
            for p in pts.as_slice() {
                let a = start + k * increment;
                assert!((p.x() - 3.0 * libm::cos(a)).abs() < 1e-12);
                assert!((p.y() - 3.0 * libm::sin(a)).abs() < 1e-12);
                k += 1.0;
            }
        }
    }
}
