//! The tracking error of the robot relative to a line to follow, whatever
//! produced that line: the reference path (Frénet projection), an edge
//! parabola (Pierre 2022, eq. 11) or crop-row lines (eqs. 16 and 20).
//!
//! It is the input of every control law in [`crate::control`].

use super::units::{Curvature, Meters, Radians};

//= spec/library.md#lib-frames-frames-and-sign-conventions
//# The lateral error y MUST be positive when the robot is left of the path, the
//# path curvature MUST be positive for a left turn, and the steering angle MUST
//# be positive to the left.
/// The error of the controlled point O (middle of the rear axle) relative to the
/// line to follow, in that line's Frénet frame (`spec/library.md`, LIB-FRAMES).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackingError {
    /// Lateral error y, metres, positive when the robot is left of the line.
    pub y: Meters,
    /// Angular deviation θ̃ = robot heading − line heading, radians, wrapped to (−π, π].
    pub angular_deviation: Radians,
    /// Curvature c(s) of the line at the closest point, 1/m, positive for a left turn.
    pub curvature: Curvature,
    /// Curvature ahead, c(s + v T), used as feed-forward (Pierre 2022, eq. 7).
    /// Equal to `curvature` when the source has no prediction horizon.
    pub curvature_ahead: Curvature,
}

impl TrackingError {
    /// A tracking error to a straight line (zero curvature), as detectors give.
    #[must_use]
    pub const fn to_straight_line(y: Meters, angular_deviation: Radians) -> Self {
        Self {
            y,
            angular_deviation,
            curvature: Curvature::ZERO,
            curvature_ahead: Curvature::ZERO,
        }
    }

    /// The mirror image: left and right swapped, so every signed quantity negates.
    #[must_use]
    pub fn mirrored(self) -> Self {
        Self {
            y: self.y.negated(),
            angular_deviation: self.angular_deviation.negated(),
            curvature: self.curvature.negated(),
            curvature_ahead: self.curvature_ahead.negated(),
        }
    }
}
