//! The lateral controller of Emmi 2024 (section 3.3.1, eqs. 1-2): a PD law on
//! the distance d_t of a control point CP ahead of the robot to a straight
//! path, and on the angle φ between the path and the robot's heading
//! (`spec/emmi2024.md`, EM-LATERAL-*).
//!
//! # Signs and units (EM-LATERAL-GAINS)
//!
//! The law is written with the signed lateral error of CP, y_cp (m, positive
//! when CP is left of the path): dir·d_t = −y_cp, since dir = −1 on the left.
//! φ is the path heading minus the robot heading (φ = −θ̃), so that with every
//! gain positive the law turns the robot towards the path:
//!
//! ω_s = K_φ φ − KP_d y_cp − KD_d ẏ_cp,  l_s = K_v v_d cos(min(K_w |ω_s|, π/2)).
//!
//! K_φ is in (rad/s)/rad, KP_d in (rad/s)/m, KD_d in (rad/s)/(m/s): Δd_t is
//! taken per second (the change between ticks over the tick period, the
//! [`LateralRate`] extra input), so the gains do not depend on the control
//! rate. K_v has no unit; K_w is in s/rad.

use core::f64::consts::FRAC_PI_2;

use crate::control::ControlLaw;
use crate::error::{finite, Precondition};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};
use crate::model::skid_steer::SkidSteer;
use crate::model::{Actuation, Saturated};

/// The gains of eqs. 1-2, validated once (EM-LATERAL-GAINS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LateralGains {
    k_phi: f64,
    kp_d: f64,
    kd_d: f64,
    k_v: f64,
    k_w: f64,
}

impl LateralGains {
    /// Gains K_φ ((rad/s)/rad), KP_d ((rad/s)/m), KD_d ((rad/s)/(m/s)),
    /// K_v (no unit) and K_w (s/rad).
    ///
    /// # Errors
    /// `EM-LATERAL-GAINS` unless K_φ, KP_d and K_v are finite and > 0 and KD_d
    /// and K_w finite and ≥ 0.
    //= spec/emmi2024.md#em-lateral-gains-gains-signs-and-units
    //# K_φ, KP_d and K_v MUST be finite and strictly positive, KD_d and K_w
    //# finite and non-negative; other gains MUST be refused with the
    //# `EM-LATERAL-GAINS` error.
    pub fn new(k_phi: f64, kp_d: f64, kd_d: f64, k_v: f64, k_w: f64) -> Result<Self, Precondition> {
        let positive = |k: f64| k.is_finite() && k > 0.0;
        let non_negative = |k: f64| k.is_finite() && k >= 0.0;
        if positive(k_phi)
            && positive(kp_d)
            && positive(k_v)
            && non_negative(kd_d)
            && non_negative(k_w)
        {
            Ok(Self {
                k_phi,
                kp_d,
                kd_d,
                k_v,
                k_w,
            })
        } else {
            Err(Precondition::new(
                "EM-LATERAL-GAINS",
                "K_phi, KP_d, K_v must be > 0 and KD_d, K_w >= 0, all finite",
            ))
        }
    }
}

/// The rate of change of the control point's signed lateral error, m/s: the
/// Δd_t of eq. 1 per second (EM-LATERAL-RATE).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LateralRate(pub MetersPerSecond);

impl LateralRate {
    /// No change: the rate of the first tick.
    pub const ZERO: Self = Self(MetersPerSecond::ZERO);

    /// (y_cp now − y_cp at the previous tick) / T.
    ///
    /// # Errors
    /// `EM-LATERAL-RATE` for a period that is not > 0; `LIB-FINITE` when the
    /// rate overflows.
    //= spec/emmi2024.md#em-lateral-rate-change-of-the-lateral-error
    //# The derivative term MUST use the change of the control point's signed
    //# lateral error between two consecutive ticks divided by the tick period T,
    //# and a period that is not strictly positive MUST be refused with the
    //# `EM-LATERAL-RATE` error.
    pub fn between_ticks(
        previous: Meters,
        current: Meters,
        period: Seconds,
    ) -> Result<Self, Precondition> {
        if period.get() <= 0.0 {
            return Err(Precondition::new(
                "EM-LATERAL-RATE",
                "tick period must be > 0",
            ));
        }
        let rate = finite(
            (current.get() - previous.get()) / period.get(),
            "lateral rate overflows",
        )?;
        Ok(Self(MetersPerSecond(rate)))
    }
}

/// The lateral controller: gains, control point and vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LateralPd {
    /// The gains of eqs. 1-2.
    pub gains: LateralGains,
    /// Distance of the control point CP ahead of the robot's centre, metres (≥ 0).
    pub control_point: Meters,
    /// The tracked robot it commands.
    pub vehicle: SkidSteer,
}

impl LateralPd {
    /// The signed lateral error of the control point: y_cp = y + l_cp sin θ̃,
    /// exact for a straight path.
    ///
    /// # Errors
    /// `EM-LATERAL-CP` for a negative control point distance; `LIB-FINITE` on
    /// overflow.
    //= spec/emmi2024.md#em-lateral-cp-control-point
    //# The control point MUST lie l_cp ≥ 0 ahead of the robot's centre on its
    //# heading, and its signed lateral error to a straight path MUST be
    //# y_cp = y + l_cp sin θ̃.
    pub fn control_point_error(&self, error: &TrackingError) -> Result<Meters, Precondition> {
        let l = self.control_point.get();
        if l < 0.0 {
            return Err(Precondition::new(
                "EM-LATERAL-CP",
                "control point distance must be >= 0",
            ));
        }
        let y = finite(
            error.y.get() + l * libm::sin(error.angular_deviation.get()),
            "control point error overflows",
        )?;
        Ok(Meters(y))
    }

    /// The raw commands (l_s, ω_s) of eqs. 1-2 before the vehicle's limits.
    ///
    /// # Errors
    /// `EM-LATERAL-EQ2` for a negative desired speed; the errors of
    /// [`LateralPd::control_point_error`]; `LIB-FINITE` on overflow.
    //= spec/emmi2024.md#em-lateral-eq1-angular-speed
    //# The angular speed MUST be ω_s = K_φ φ − KP_d y_cp − KD_d ẏ_cp with
    //# φ = −θ̃, which is eq. 1 with dir d_t = −y_cp and dir Δd_t read as the
    //# change of −y_cp per second.
    //= spec/emmi2024.md#em-lateral-eq2-linear-speed
    //# The linear speed MUST be l_s = K_v v_d cos(min(K_w |ω_s|, π/2)), never
    //# negative, and a negative desired speed v_d MUST be refused with the
    //# `EM-LATERAL-EQ2` error.
    pub fn raw_command(
        &self,
        error: &TrackingError,
        rate: LateralRate,
        speed: MetersPerSecond,
    ) -> Result<(f64, f64), Precondition> {
        if speed.get() < 0.0 {
            return Err(Precondition::new(
                "EM-LATERAL-EQ2",
                "desired speed must be >= 0",
            ));
        }
        let y_cp = self.control_point_error(error)?.get();
        let g = self.gains;
        let phi = -error.angular_deviation.get();
        let omega = finite(
            g.k_phi * phi - g.kp_d * y_cp - g.kd_d * rate.0.get(),
            "angular speed overflows",
        )?;
        let slow = (g.k_w * libm::fabs(omega)).min(FRAC_PI_2);
        let linear = finite(
            g.k_v * speed.get() * libm::cos(slow),
            "linear speed overflows",
        )?;
        Ok((linear.max(0.0), omega))
    }
}

impl ControlLaw for LateralPd {
    type Extra = LateralRate;

    const NEUTRAL: Self::Extra = LateralRate::ZERO;

    fn actuation(&self) -> Actuation {
        Actuation::SkidSteer
    }

    fn check_extra(_extra: &Self::Extra) -> Result<(), Precondition> {
        Ok(())
    }

    //= spec/emmi2024.md#em-lateral-saturation-commands-within-the-track-limits
    //# The lateral controller MUST return its command saturated to the skid-steer
    //# vehicle's track limits (EM-SKID-SATURATION).
    fn command(
        &self,
        error: &TrackingError,
        extra: &Self::Extra,
        speed: MetersPerSecond,
    ) -> Result<Saturated, Precondition> {
        let (linear, omega) = self.raw_command(error, *extra, speed)?;
        self.vehicle.saturate(linear, omega)
    }
}
