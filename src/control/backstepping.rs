//! Backstepping path tracking with sideslip compensation (Pierre 2022, section
//! 2.1, eqs. 2-7; `spec/pierre2022.md`, PT-*).
//!
//! Step 1 picks the angular deviation θ̃_obj that makes the lateral error obey
//! y' = k_y y (eqs. 2-3). Step 2 picks the yaw rate, then the steering angle,
//! that make e = θ̃ − θ̃_obj obey e' = k_θ e (eqs. 4-6), with the curvature fed
//! forward at s + vT (eq. 7), and saturates the result.
//!
//! # Gain sign convention (`spec/pierre2022.md`, PT-GAINS)
//!
//! Gains are written in the *equation form* of the papers: the law imposes
//! y' = k_y y (Pierre 2022, eq. 2) and e' = k_θ e (eq. 4), where ' is the
//! derivative with respect to the distance travelled along the path. An error
//! decays only for a **negative** gain, so convergent gains are negative, and
//! 1/|k| is the distance over which the error falls by a factor e.
//!
//! The papers' tables list positive "proportional gains" g (Table 1: 0.7): a
//! configuration that takes table values maps them once as k = −g (the
//! simulator's scenario schema does this). [`Gains::new`] refuses positive or
//! zero gains, and requires |k_θ| ≥ r |k_y| for a configured minimum ratio r ≥ 1,
//! which is how the library reads the paper's "k_θ ≫ k_y".

use crate::error::{finite, Precondition};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{MetersPerSecond, Radians, RadiansPerSecond};
use crate::model::bicycle::{check_denominator, check_heading, check_speed, Bicycle, Sideslip};
use crate::model::{Actuation, Command, Saturated};

/// The two convergence gains of the backstepping law, per metre, in equation
/// form (negative = convergent), validated once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    k_y: f64,
    k_theta: f64,
}

impl Gains {
    /// Gains `k_y` (lateral, eq. 2) and `k_theta` (angular, eq. 4), per metre,
    /// with `min_ratio` the least accepted |k_θ| / |k_y|.
    ///
    /// Errors: `PT-GAINS-SIGN` unless both gains are finite and strictly
    /// negative; `PT-GAINS-RATIO` unless `min_ratio` is finite and ≥ 1 and
    /// |k_θ| ≥ `min_ratio` |k_y|.
    //= spec/pierre2022.md#pt-gains-gain-sign-and-ratio
    //# Both gains MUST be finite and strictly negative (convergent in equation
    //# form), and |k_θ| MUST be at least a configured ratio r ≥ 1 times |k_y|;
    //# other gains MUST be refused at construction.
    pub fn new(k_y: f64, k_theta: f64, min_ratio: f64) -> Result<Self, Precondition> {
        let finite_negative = |k: f64| k.is_finite() && k < 0.0;
        if !(finite_negative(k_y) && finite_negative(k_theta)) {
            return Err(Precondition::new(
                "PT-GAINS-SIGN",
                "gains must be finite and < 0 (equation form: y' = k_y y)",
            ));
        }
        Self::with_ratio(k_y, k_theta, min_ratio)
    }

    /// Like [`Gains::new`] but without the sign check, so a test can show that
    /// a wrong sign makes the closed loop diverge. Only with the
    /// `fault-injection` feature; never in a vehicle.
    #[cfg(feature = "fault-injection")]
    pub fn with_unchecked_sign(
        k_y: f64,
        k_theta: f64,
        min_ratio: f64,
    ) -> Result<Self, Precondition> {
        if !(k_y.is_finite() && k_theta.is_finite() && k_y != 0.0 && k_theta != 0.0) {
            return Err(Precondition::new(
                "PT-GAINS-SIGN",
                "gains must be finite and non-zero",
            ));
        }
        Self::with_ratio(k_y, k_theta, min_ratio)
    }

    fn with_ratio(k_y: f64, k_theta: f64, min_ratio: f64) -> Result<Self, Precondition> {
        let ratio_ok = min_ratio.is_finite()
            && min_ratio >= 1.0
            && libm::fabs(k_theta) >= min_ratio * libm::fabs(k_y);
        if ratio_ok {
            Ok(Self { k_y, k_theta })
        } else {
            Err(Precondition::new(
                "PT-GAINS-RATIO",
                "need min_ratio >= 1 and |k_theta| >= min_ratio |k_y|",
            ))
        }
    }

    /// k_y, per metre (negative).
    #[must_use]
    pub const fn k_y(&self) -> f64 {
        self.k_y
    }

    /// k_θ, per metre (negative).
    #[must_use]
    pub const fn k_theta(&self) -> f64 {
        self.k_theta
    }
}

/// Which reading of eq. 6 the steering law implements (see the errata in
/// `spec/pierre2022.md`, PT-STEERING).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Inversion {
    /// The exact inversion of the yaw rate of eq. 1 against eq. 5:
    /// tan(δ + β_F) = tan β_R + L [k_θ e + c] cos θ̃₂ / ((1 − y c(s)) cos β_R).
    /// Gives e' = k_θ e exactly (up to θ̃_obj'). The library's default.
    #[default]
    Exact,
    //= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
    //# The law as printed in eq. 6, without the factor cos θ̃₂ / cos β_R, SHOULD be
    //# available as an explicit option for comparison with the paper.
    /// The law as printed: tan(δ + β_F) = tan β_R + L [k_θ e + c] / (1 − y c(s)),
    /// which drops the factor cos θ̃₂ / cos β_R (equal to 1 for small angles).
    Printed,
}

/// Everything the steering law needs besides the tracking error, validated once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BacksteppingConfig {
    /// The convergence gains (sign convention in [`Gains`]).
    pub gains: Gains,
    /// The vehicle the law steers: its wheelbase L and steering saturation.
    pub vehicle: Bicycle,
    /// Which reading of eq. 6.
    pub inversion: Inversion,
}

/// The output of the steering law for one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteeringCommand {
    /// The steering angle δ to send, saturated, radians, positive to the left.
    pub steering: Radians,
    /// Whether the law's output was beyond the limit and clamped.
    pub saturated: bool,
    /// The target angular deviation θ̃_obj of eq. 3.
    pub target_angular_deviation: Radians,
    /// The yaw-rate objective u_θ^obj of eq. 5 (with the feed-forward curvature).
    pub yaw_rate_objective: RadiansPerSecond,
}

/// The target angular deviation θ̃_obj = arctan(k_y y / (1 − y c(s))) − β_R
/// (Pierre 2022, eq. 3), radians.
///
/// With θ̃ = θ̃_obj, eq. 1 gives y' = k_y y (eq. 2).
/// Errors: `PT-DENOM` when 1 − y c(s) ≤ 0, `PT-SIDESLIP` when |β| ≥ π/2.
//= spec/pierre2022.md#pt-target-target-angular-deviation
//# The target angular deviation MUST be
//# θ̃_obj = arctan(k_y y / (1 − y c(s))) − β_R.
pub fn target_angular_deviation(
    gains: &Gains,
    error: &TrackingError,
    sideslip: Sideslip,
) -> Result<Radians, Precondition> {
    sideslip.check()?;
    let alpha = check_denominator(error)?;
    let target = libm::atan(gains.k_y() * error.y.get() / alpha) - sideslip.rear.get();
    Radians::new(target)
}

/// The terms of step 2 shared by eq. 5 and eq. 6, every precondition checked.
struct LawTerms {
    /// θ̃_obj (eq. 3).
    target: Radians,
    /// k_θ e + c(s + vT).
    drive: f64,
    /// 1 − y c(s) > 0.
    alpha: f64,
    /// θ̃₂ = θ̃ + β_R, with cos θ̃₂ > 0.
    theta2: f64,
    /// v > 0.
    speed: f64,
}

impl LawTerms {
    fn new(
        gains: &Gains,
        error: &TrackingError,
        sideslip: Sideslip,
        speed: MetersPerSecond,
    ) -> Result<Self, Precondition> {
        let speed = check_speed(speed)?;
        let theta2 = check_heading(error.angular_deviation, sideslip)?;
        let alpha = check_denominator(error)?;
        let target = target_angular_deviation(gains, error, sideslip)?;
        let e = error.angular_deviation.get() - target.get();
        let drive = finite(
            gains.k_theta() * e + error.curvature_ahead.get(),
            "heading drive overflows",
        )?;
        Ok(Self {
            target,
            drive,
            alpha,
            theta2,
            speed,
        })
    }

    /// u_θ^obj = drive v cos θ̃₂ / (1 − y c(s)) (eq. 5).
    fn yaw_rate_objective(&self) -> Result<RadiansPerSecond, Precondition> {
        RadiansPerSecond::new(self.drive * self.speed * libm::cos(self.theta2) / self.alpha)
    }
}

/// The yaw-rate objective u_θ^obj = [k_θ e + c] v cos θ̃₂ / (1 − y c(s)) (Pierre
/// 2022, eq. 5), where e = θ̃ − θ̃_obj and c is the feed-forward curvature
/// c(s + vT) of eq. 7 (pass `curvature_ahead = curvature` for eq. 5 as printed).
///
/// Errors: `PT-DENOM`, `PT-HEADING`, `PT-SPEED`, `PT-SIDESLIP`, `LIB-FINITE`.
//= spec/pierre2022.md#pt-yaw-objective-yaw-rate-objective
//# The yaw-rate objective MUST be u_θ^obj = [k_θ e + c(s + vT)] v cos θ̃₂ / (1 − y c(s)),
//# with e = θ̃ − θ̃_obj.
pub fn yaw_rate_objective(
    gains: &Gains,
    error: &TrackingError,
    sideslip: Sideslip,
    speed: MetersPerSecond,
) -> Result<RadiansPerSecond, Precondition> {
    LawTerms::new(gains, error, sideslip, speed)?.yaw_rate_objective()
}

/// The steering angle of the backstepping law (Pierre 2022, eqs. 6-7), saturated:
/// δ = arctan(tan β_R + L [k_θ e + c(s + vT)] g / (1 − y c(s))) − β_F, where
/// g = cos θ̃₂ / cos β_R for [`Inversion::Exact`] and g = 1 for
/// [`Inversion::Printed`].
///
/// With β_F = β_R = 0 and c(s + vT) = c(s) this is the classical law
/// δ = arctan(L [k_θ e + c] cos θ̃ / (1 − y c(s))) (exact reading).
/// Errors: `PT-DENOM` (1 − y c(s) ≤ 0), `PT-HEADING` (cos θ̃₂ ≤ 0), `PT-SPEED`
/// (v ≤ 0), `PT-SIDESLIP` (|β| ≥ π/2), `LIB-FINITE` on overflow.
//= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
//# The steering angle MUST be
//# δ = arctan(tan β_R + L [k_θ e + c(s + vT)] cos θ̃₂ / ((1 − y c(s)) cos β_R)) − β_F
//# in the exact reading, the library's default.
//= spec/pierre2022.md#pt-feedforward-curvature-feed-forward
//# The law MUST feed forward the curvature c(s + vT) in the numerator and use
//# 1 − y c(s) in the denominator.
pub fn steering_command(
    config: &BacksteppingConfig,
    error: &TrackingError,
    sideslip: Sideslip,
    speed: MetersPerSecond,
) -> Result<SteeringCommand, Precondition> {
    let terms = LawTerms::new(&config.gains, error, sideslip, speed)?;
    let beta_r = sideslip.rear.get();
    let factor = match config.inversion {
        Inversion::Exact => libm::cos(terms.theta2) / libm::cos(beta_r),
        Inversion::Printed => 1.0,
    };
    let length = config.vehicle.wheelbase.get().get();
    let tangent = finite(
        libm::tan(beta_r) + length * terms.drive * factor / terms.alpha,
        "steering tangent overflows",
    )?;
    let raw = Radians::new(libm::atan(tangent) - sideslip.front.get())?;
    let (steering, saturated) = config.vehicle.max_steering.clamp(raw);
    Ok(SteeringCommand {
        steering,
        saturated,
        target_angular_deviation: terms.target,
        yaw_rate_objective: terms.yaw_rate_objective()?,
    })
}

//= spec/guidance.md#gd-law-one-trait-for-every-control-law
//# Backstepping MUST be a control law for the bicycle, reading the sideslip
//# estimate as its extra input, zero sideslip being its neutral input.
impl super::ControlLaw for BacksteppingConfig {
    type Extra = Sideslip;

    const NEUTRAL: Sideslip = Sideslip::ZERO;

    fn actuation(&self) -> Actuation {
        Actuation::Bicycle
    }

    fn check_extra(extra: &Sideslip) -> Result<(), Precondition> {
        extra.check()
    }

    fn command(
        &self,
        error: &TrackingError,
        extra: &Sideslip,
        speed: MetersPerSecond,
    ) -> Result<Saturated, Precondition> {
        let c = steering_command(self, error, *extra, speed)?;
        Ok(Saturated {
            command: Command::Bicycle {
                speed,
                steering: c.steering,
            },
            saturated: c.saturated,
        })
    }
}
