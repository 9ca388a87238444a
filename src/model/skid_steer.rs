//! A tracked (skid-steer) robot commanded in linear and angular speed
//! (Emmi 2024, sections 2.1 and 3.3.2; `spec/emmi2024.md`, EM-SKID-*).
//!
//! The two tracks, a track distance b apart, move at v_l = v − ω b/2 and
//! v_r = v + ω b/2; each is limited to |v_i| ≤ v_max. A turn of radius
//! R = v/ω keeps the inner track moving forward when R ≥ b/2; the paper asks
//! for R ≥ b (EM-SKID-FORWARD), which [`SkidSteer::check_turn_radius`] applies.
//! The unicycle model ([`unicycle_rates`]) is the kinematics the spiral law is
//! derived in (Emmi 2024, eqs. 4-9).

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Pose2, World};
use crate::geometry::units::{Meters, MetersPerSecond, RadiansPerSecond};
use crate::model::{Command, Saturated};

/// Relative margin a checked track speed may exceed its limit by: the
/// rounding of v ± ω b/2 after a saturation that put it exactly at the limit.
const TRACK_ROUNDING: f64 = 1e-9;

/// A skid-steer vehicle: track distance and track speed limit (EM-SKID-LIMITS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkidSteer {
    track: f64,
    max_track_speed: f64,
}

impl SkidSteer {
    /// A vehicle whose tracks are `track` metres apart (centre to centre),
    /// each limited to `max_track_speed` m/s.
    ///
    /// # Errors
    /// `EM-SKID-LIMITS` unless both lie in [1e−3, 1e3] (m and m/s).
    //= spec/emmi2024.md#em-skid-limits-track-distance-and-speed-limit
    //# The track distance b MUST lie in [1e−3 m, 1e3 m] and the track speed limit
    //# v_max in [1e−3 m/s, 1e3 m/s]; other values MUST be refused with the
    //# `EM-SKID-LIMITS` error.
    pub fn new(track: Meters, max_track_speed: MetersPerSecond) -> Result<Self, Precondition> {
        // Bounds far beyond any vehicle, which keep the saturation's
        // products away from overflow and subnormal rounding.
        let ok = |x: f64| (1e-3..=1e3).contains(&x);
        if ok(track.get()) && ok(max_track_speed.get()) {
            Ok(Self {
                track: track.get(),
                max_track_speed: max_track_speed.get(),
            })
        } else {
            Err(Precondition::new(
                "EM-SKID-LIMITS",
                "track distance and track speed limit must lie in [1e-3, 1e3]",
            ))
        }
    }

    /// The track distance b, metres.
    #[must_use]
    pub const fn track(&self) -> Meters {
        Meters(self.track)
    }

    /// The track speed limit v_max, m/s.
    #[must_use]
    pub const fn max_track_speed(&self) -> MetersPerSecond {
        MetersPerSecond(self.max_track_speed)
    }

    /// The left and right track speeds (v − ω b/2, v + ω b/2), m/s.
    ///
    /// # Errors
    /// `LIB-FINITE` when a track speed overflows.
    //= spec/emmi2024.md#em-skid-skid-steer-kinematics
    //# The left and right track speeds of a command (v, ω) MUST be
    //# v_l = v − ω b/2 and v_r = v + ω b/2.
    pub fn track_speeds(
        &self,
        speed: MetersPerSecond,
        yaw_rate: RadiansPerSecond,
    ) -> Result<(MetersPerSecond, MetersPerSecond), Precondition> {
        let half = yaw_rate.get() * (0.5 * self.track);
        let left = finite(speed.get() - half, "left track speed overflows")?;
        let right = finite(speed.get() + half, "right track speed overflows")?;
        Ok((MetersPerSecond(left), MetersPerSecond(right)))
    }

    /// Whether (v, ω) keeps both tracks within the limit (up to rounding).
    pub(crate) fn within_limits(&self, speed: f64, yaw_rate: f64) -> bool {
        let half = yaw_rate * (0.5 * self.track);
        let limit = self.max_track_speed * (1.0 + TRACK_ROUNDING);
        libm::fabs(speed - half) <= limit && libm::fabs(speed + half) <= limit
    }

    /// The command (v, ω) within the track limits: a command beyond them is
    /// scaled, v and ω by one factor, so that the faster track runs at v_max
    /// and the turn radius v/ω is kept.
    ///
    /// # Errors
    /// `LIB-FINITE` when an input is not finite.
    //= spec/emmi2024.md#em-skid-saturation-saturation-keeps-the-turn-radius
    //# A command whose faster track exceeds v_max MUST be replaced by the command
    //# (k v, k ω) with k = v_max / max(|v_l|, |v_r|), reported as saturated;
    //# a command within the limits MUST be returned unchanged.
    pub fn saturate(&self, speed: f64, yaw_rate: f64) -> Result<Saturated, Precondition> {
        let v = finite(speed, "commanded speed must be finite")?;
        let w = finite(yaw_rate, "commanded yaw rate must be finite")?;
        if self.within_limits(v, w) {
            return Ok(Saturated {
                command: Command::SkidSteer {
                    speed: MetersPerSecond(v),
                    yaw_rate: RadiansPerSecond(w),
                },
                saturated: false,
            });
        }
        // Divide by a = max(|v|, |ω|) first, so that no product overflows;
        // then (v, ω) k = (v/a, ω/a) v_max / max(|v_l/a|, |v_r/a|).
        let half = 0.5 * self.track;
        let a = libm::fabs(v).max(libm::fabs(w));
        let (vs, ws) = (v / a, w / a);
        let fastest = libm::fabs(vs - ws * half).max(libm::fabs(vs + ws * half));
        let speed = finite(vs / fastest * self.max_track_speed, "saturated speed")?;
        let yaw_rate = finite(ws / fastest * self.max_track_speed, "saturated yaw rate")?;
        Ok(Saturated {
            command: Command::SkidSteer {
                speed: MetersPerSecond(speed),
                yaw_rate: RadiansPerSecond(yaw_rate),
            },
            saturated: true,
        })
    }

    /// Refuses a planning turn radius below the track distance (Emmi 2024,
    /// section 3.3.2): at R ≥ b both tracks move forward.
    ///
    /// # Errors
    /// `EM-SKID-FORWARD` when `radius` < b.
    //= spec/emmi2024.md#em-skid-forward-both-tracks-forward-in-turns
    //# A planner option MUST refuse a turning radius below the track distance b
    //# with the `EM-SKID-FORWARD` error.
    pub fn check_turn_radius(&self, radius: Meters) -> Result<(), Precondition> {
        if radius.get() >= self.track {
            Ok(())
        } else {
            Err(Precondition::new(
                "EM-SKID-FORWARD",
                "turning radius below the track distance",
            ))
        }
    }
}

/// The unicycle model's world-frame rates (ẋ, ẏ, θ̇) = (v cos θ, v sin θ, ω)
/// of a skid-steer robot without slip (Emmi 2024, Fig. 11).
///
/// # Errors
/// `LIB-FINITE` when a rate overflows (never for finite inputs; kept for the
/// single exit gate).
//= spec/emmi2024.md#em-unicycle-unicycle-kinematics
//# The robot's kinematics without slip MUST be ẋ = v cos θ, ẏ = v sin θ,
//# θ̇ = ω in the `World` frame.
pub fn unicycle_rates(
    pose: &Pose2<World>,
    speed: MetersPerSecond,
    yaw_rate: RadiansPerSecond,
) -> Result<(MetersPerSecond, MetersPerSecond, RadiansPerSecond), Precondition> {
    let h = pose.heading.get();
    let vx = finite(speed.get() * libm::cos(h), "x rate")?;
    let vy = finite(speed.get() * libm::sin(h), "y rate")?;
    Ok((
        MetersPerSecond(vx),
        MetersPerSecond(vy),
        RadiansPerSecond(yaw_rate.get()),
    ))
}
