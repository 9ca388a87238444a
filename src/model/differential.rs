//! A differential robot: two driven wheels on one axle, steering by their
//! speed difference (Guyonneau 2022, section 4.1.1; `spec/guyonneau2022.md`,
//! DIFF-*).
//!
//! The controlled point O is the middle of the axle. With wheel speeds v_l
//! and v_r and the track w between the wheels, O moves at v = (v_l + v_r)/2
//! along the heading and turns at ω = (v_r − v_l)/w (positive to the left).

use crate::error::{finite, Precondition};
use crate::geometry::units::{Meters, MetersPerSecond, RadiansPerSecond};
use crate::model::Command;

/// The limits of a differential robot (DIFF-LIMITS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Differential {
    track: Meters,
    max_wheel_speed: MetersPerSecond,
}

impl Differential {
    /// A robot whose wheels are `track` m apart, each at most
    /// `max_wheel_speed` m/s forward or backward.
    ///
    /// # Errors
    /// `DIFF-LIMITS` unless both are finite and > 0.
    //= spec/guyonneau2022.md#diff-limits-a-differential-robot-s-limits
    //# A differential robot MUST be refused with an error naming DIFF-LIMITS
    //# unless its track and its largest wheel speed are finite and > 0.
    pub fn new(track: Meters, max_wheel_speed: MetersPerSecond) -> Result<Self, Precondition> {
        if track.get() > 0.0 && max_wheel_speed.get() > 0.0 {
            Ok(Self {
                track,
                max_wheel_speed,
            })
        } else {
            Err(Precondition::new(
                "DIFF-LIMITS",
                "track and largest wheel speed must be > 0",
            ))
        }
    }

    /// The distance between the wheels' contact points, m.
    #[must_use]
    pub const fn track(&self) -> Meters {
        self.track
    }

    /// The largest wheel speed, forward or backward, m/s.
    #[must_use]
    pub const fn max_wheel_speed(&self) -> MetersPerSecond {
        self.max_wheel_speed
    }

    /// Whether both wheel speeds are within the limit.
    //= spec/guyonneau2022.md#diff-limits-a-differential-robot-s-limits
    //# A differential command MUST have both wheel speeds within
    //# [−v_max, v_max].
    #[must_use]
    pub fn within(&self, left: MetersPerSecond, right: MetersPerSecond) -> bool {
        let max = self.max_wheel_speed.get();
        libm::fabs(left.get()) <= max && libm::fabs(right.get()) <= max
    }

    /// The wheel speeds that move O at `speed` and turn at `yaw_rate`,
    /// v ∓ ω w/2, both scaled down by the same factor when one exceeds the
    /// limit so that the path's curvature is kept; whether they were scaled.
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    //= spec/guyonneau2022.md#diff-kinematics-wheel-speeds-speed-and-yaw-rate
    //# The wheel speeds of a speed v and a yaw rate ω MUST be v_l = v − ω w/2
    //# and v_r = v + ω w/2, both scaled by one factor into the limits when
    //# either exceeds it.
    pub fn wheels(
        &self,
        speed: MetersPerSecond,
        yaw_rate: RadiansPerSecond,
    ) -> Result<(Command, bool), Precondition> {
        let half = 0.5 * self.track.get() * yaw_rate.get();
        let (l, r) = (
            finite(speed.get() - half, "left wheel speed")?,
            finite(speed.get() + half, "right wheel speed")?,
        );
        let largest = libm::fmax(libm::fabs(l), libm::fabs(r));
        let max = self.max_wheel_speed.get();
        let (scale, saturated) = if largest > max {
            (max / largest, true)
        } else {
            (1.0, false)
        };
        // Clamped too: the scaled speed can exceed the limit by a rounding
        // error (a subnormal limit).
        Ok((
            Command::Differential {
                left: MetersPerSecond::new((l * scale).clamp(-max, max))?,
                right: MetersPerSecond::new((r * scale).clamp(-max, max))?,
            },
            saturated,
        ))
    }

    /// The speed of O and the yaw rate of wheel speeds `left` and `right`:
    /// ((v_l + v_r)/2, (v_r − v_l)/w).
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    //= spec/guyonneau2022.md#diff-kinematics-wheel-speeds-speed-and-yaw-rate
    //# The speed of O MUST be (v_l + v_r)/2 and its yaw rate (v_r − v_l)/w.
    pub fn motion(
        &self,
        left: MetersPerSecond,
        right: MetersPerSecond,
    ) -> Result<(MetersPerSecond, RadiansPerSecond), Precondition> {
        let (l, r) = (left.get(), right.get());
        Ok((
            MetersPerSecond::new(0.5 * l + 0.5 * r)?,
            RadiansPerSecond::new(finite(r - l, "wheel speed difference")? / self.track.get())?,
        ))
    }
}
