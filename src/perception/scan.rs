//! One planar LiDAR scan, the message every detector of [`crate::perception`]
//! takes (`spec/library.md`, LIB-SCAN): the first ray's angle, the signed
//! angle between rays, the ranges as measured, and the sensor's valid range
//! interval. It is the shape LiDAR drivers deliver (a ROS `LaserScan` is
//! `angle_min`, `angle_increment`, `range_min`, `range_max`, `ranges`), so a
//! vehicle stack fills it once per message for whichever detector reads it.

use crate::error::Precondition;
use crate::geometry::units::{Meters, Radians};

/// Largest `max` of [`RangeLimits`], metres (LIB-SCAN). It keeps every point
/// a detector builds from a valid range far from overflow.
pub const MAX_RANGE: f64 = 1.0e6;

/// The sensor's valid interval of ranges, `[min, max)` metres (LIB-SCAN).
///
/// The upper bound is excluded: many drivers report "no return" as exactly
/// `max`, and such a ray must not become a point at the end of the beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RangeLimits {
    min: f64,
    max: f64,
}

impl RangeLimits {
    /// Ranges in `[min, max)` metres are valid.
    ///
    /// Errors with `LIB-SCAN` unless `0 ≤ min < max ≤ MAX_RANGE`.
    //= spec/library.md#lib-scan-one-planar-lidar-scan
    //# Range limits MUST be refused, with an error naming the requirement,
    //# unless 0 ≤ min < max ≤ 1e6 m.
    pub fn new(min: Meters, max: Meters) -> Result<Self, Precondition> {
        let (min, max) = (min.get(), max.get());
        if min >= 0.0 && min < max && max <= MAX_RANGE {
            Ok(Self { min, max })
        } else {
            Err(Precondition::new(
                "LIB-SCAN",
                "range limits must satisfy 0 <= min < max <= 1e6 m",
            ))
        }
    }

    /// The smallest valid range, metres.
    #[must_use]
    pub const fn min(&self) -> f64 {
        self.min
    }

    /// The bound valid ranges stay below, metres.
    #[must_use]
    pub const fn max(&self) -> f64 {
        self.max
    }

    /// Whether `range` is a valid measurement: finite and within `[min, max)`.
    //= spec/library.md#lib-scan-one-planar-lidar-scan
    //# A range MUST be used only when it is finite and lies in the sensor's
    //# valid interval [min, max); any other range, `max` itself included,
    //# MUST be treated as no return.
    #[must_use]
    pub fn accepts(&self, range: f64) -> bool {
        range.is_finite() && range >= self.min && range < self.max
    }
}

/// One planar LiDAR scan as the sensor delivers it (LIB-SCAN): ray `k` (from
/// 0) points at `start + k · increment` radians in the scan plane,
/// counter-clockwise from the sensor's x axis, and measured `ranges[k]`
/// metres.
///
/// The increment is signed, as drivers give it (a LiDAR mounted upside down
/// scans clockwise): the edge detector takes any increment; the furrow
/// detector needs the angles to grow with the ray index (its window of rays
/// is then contiguous and ordered right to left) and refuses an increment
/// `≤ 0` with `FUR-SCAN`.
//= spec/library.md#lib-scan-one-planar-lidar-scan
//# Ray k of a scan (k from 0) MUST be read at the angle start + k · increment
//# of the scan plane, counter-clockwise from the sensor's x axis, with the
//# increment signed as the sensor delivers it.
#[derive(Debug, Clone, Copy)]
pub struct Scan<'a> {
    /// Direction of the first ray in the scan plane, rad, counter-clockwise
    /// from the sensor's x axis.
    pub start: Radians,
    /// Signed angle between consecutive rays, rad.
    pub increment: Radians,
    /// The measured ranges, metres; any value (NaN, infinities, out of
    /// limits) is allowed and only [`RangeLimits::accepts`]'s are used.
    pub ranges: &'a [f64],
    /// The sensor's valid interval of ranges.
    pub limits: RangeLimits,
}
