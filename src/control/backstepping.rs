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
use crate::geometry::units::{MetersPerSecond, Radians, RadiansPerSecond, Seconds};
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

/// How much faster than the steering's rate limit allows at full lock the
/// heading loop may be: its time-domain gain v |k_θ| is at most
/// `RATE_FACTOR` times max rate / max steering, so that the law's steering
/// rate, v |k_θ| δ in the linearised loop, stays within the rate limit for
/// steering excursions up to half the saturation (PT-SCHEDULE).
pub const SCHEDULE_RATE_FACTOR: f64 = 2.0;

/// The largest product v |k_θ| τ of the heading loop's time-domain gain and
/// the steering's time constant: at 1, the loop through a first-order lag
/// keeps a phase margin of at least 45° (PT-SCHEDULE).
pub const SCHEDULE_LAG_PRODUCT: f64 = 1.0;

/// A speed schedule of the gains (PT-SCHEDULE): the range of speeds the law
/// is valid for, and the largest time-domain heading gain v |k_θ| (1/s, held
/// as a rate in rad/s per radian of heading error) the steering actuator can
/// follow.
///
/// Below v₀ = bandwidth / |k_θ| the gains per metre apply as they are
/// (convergence in distance, eqs. 2 and 4); above it both gains are scaled
/// by v₀ / v, so that their ratio (the loop's damping) is kept and the
/// time-domain bandwidth stays at the bandwidth: gains per metre would ask
/// the steering for a rate that grows like v k_θ².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedSchedule {
    min_speed: MetersPerSecond,
    max_speed: MetersPerSecond,
    bandwidth: RadiansPerSecond,
}

impl SpeedSchedule {
    /// The schedule valid for speeds in [`min_speed`, `max_speed`] whose
    /// heading loop is at most `bandwidth` fast in time.
    ///
    /// # Errors
    /// `PT-SCHEDULE` unless 0 < `min_speed` ≤ `max_speed` and `bandwidth` > 0.
    //= spec/pierre2022.md#pt-schedule-speed-schedule-of-the-gains
    //# A speed schedule MUST be refused at construction unless
    //# 0 < v_min ≤ v_max and Ω > 0.
    pub fn new(
        min_speed: MetersPerSecond,
        max_speed: MetersPerSecond,
        bandwidth: RadiansPerSecond,
    ) -> Result<Self, Precondition> {
        if !(min_speed.get() > 0.0 && max_speed.get() >= min_speed.get()) {
            return Err(Precondition::new(
                "PT-SCHEDULE",
                "need 0 < min_speed <= max_speed",
            ));
        }
        if bandwidth.get() <= 0.0 {
            return Err(Precondition::new(
                "PT-SCHEDULE",
                "the schedule's bandwidth must be > 0",
            ));
        }
        Ok(Self {
            min_speed,
            max_speed,
            bandwidth,
        })
    }

    /// The schedule of the steering actuator of `vehicle` (its rate limit
    /// and saturation) with first-order time constant `time_constant`:
    /// Ω = min(2 R / δ_max, 1 / τ) ([`SCHEDULE_RATE_FACTOR`],
    /// [`SCHEDULE_LAG_PRODUCT`]; τ = 0: the rate limit alone).
    ///
    /// # Errors
    /// `PT-SCHEDULE` when the vehicle's steering rate is unknown, the time
    /// constant is negative or the speeds are out of order.
    //= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
    //# From 0.8 m off a straight, and from 1.5 m off heading 20° away from it,
    //# path tracking with a schedule derived from the actuator MUST converge
    //# (|y| < 0.05 m and staying) within the longest of 10 m, 5 s of travel and
    //# 1.3 times the linearised loop's time, with an overshoot below 10 % of the
    //# initial error from 0.8 m and 12 % from 1.5 m, at every speed of the schedule.
    //= spec/pierre2022.md#pt-schedule-speed-schedule-of-the-gains
    //# A schedule derived from the actuator MUST take
    //# Ω = min(2 R / δ_max, 1 / τ) for a steering rate limit R, saturation
    //# δ_max and first-order time constant τ (the rate limit alone when τ = 0).
    pub fn for_actuator(
        min_speed: MetersPerSecond,
        max_speed: MetersPerSecond,
        vehicle: &Bicycle,
        time_constant: Seconds,
    ) -> Result<Self, Precondition> {
        let Some(rate) = vehicle.max_steering_rate else {
            return Err(Precondition::new(
                "PT-SCHEDULE",
                "the schedule needs the vehicle's steering rate limit",
            ));
        };
        let tau = time_constant.get();
        if tau < 0.0 {
            return Err(Precondition::new(
                "PT-SCHEDULE",
                "the steering's time constant must not be negative",
            ));
        }
        let by_rate = finite(
            SCHEDULE_RATE_FACTOR * rate.get() / vehicle.max_steering.get().get(),
            "schedule bandwidth overflows",
        )?;
        let bandwidth = if tau > 0.0 {
            libm::fmin(by_rate, SCHEDULE_LAG_PRODUCT / tau)
        } else {
            by_rate
        };
        Self::new(
            min_speed,
            max_speed,
            RadiansPerSecond::new(finite(bandwidth, "schedule bandwidth overflows")?)?,
        )
    }

    /// The lowest speed the schedule is valid for.
    #[must_use]
    pub const fn min_speed(&self) -> MetersPerSecond {
        self.min_speed
    }

    /// The highest speed the schedule is valid for.
    #[must_use]
    pub const fn max_speed(&self) -> MetersPerSecond {
        self.max_speed
    }

    /// The largest time-domain heading gain Ω = v |k_θ|.
    #[must_use]
    pub const fn bandwidth(&self) -> RadiansPerSecond {
        self.bandwidth
    }

    /// The gains to apply at `speed`: `gains` when v |k_θ| ≤ Ω, else both
    /// scaled by Ω / (v |k_θ|).
    ///
    /// # Errors
    /// `PT-SPEED` when v ≤ 0, `PT-SCHEDULE-RANGE` when v is outside the
    /// schedule's range, `LIB-FINITE` when a scaled gain would under- or
    /// overflow.
    //= spec/pierre2022.md#pt-schedule-speed-schedule-of-the-gains
    //# At a speed v the law MUST use the gains per metre k_y, k_θ where
    //# v |k_θ| ≤ Ω, and both scaled by Ω / (v |k_θ|) where v |k_θ| > Ω.
    //= spec/pierre2022.md#pt-schedule-range-speeds-outside-the-schedule
    //# A scheduled law MUST refuse a speed below v_min or above v_max with the
    //# `PT-SCHEDULE-RANGE` error instead of a value.
    pub fn gains_at(&self, gains: &Gains, speed: MetersPerSecond) -> Result<Gains, Precondition> {
        let v = check_speed(speed)?;
        if v < self.min_speed.get() || v > self.max_speed.get() {
            return Err(Precondition::new(
                "PT-SCHEDULE-RANGE",
                "speed outside the range of the gains' speed schedule",
            ));
        }
        let demand = finite(v * libm::fabs(gains.k_theta), "v |k_theta| overflows")?;
        if demand <= self.bandwidth.get() {
            return Ok(*gains);
        }
        let factor = self.bandwidth.get() / demand;
        let (k_y, k_theta) = (gains.k_y * factor, gains.k_theta * factor);
        if k_y < 0.0 && k_theta < 0.0 {
            Ok(Gains { k_y, k_theta })
        } else {
            Err(Precondition::new(
                "LIB-FINITE",
                "a scheduled gain underflows to zero",
            ))
        }
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
    /// The speed schedule of the gains (PT-SCHEDULE); `None`: the gains per
    /// metre at every speed, as the paper writes them.
    pub schedule: Option<SpeedSchedule>,
}

impl BacksteppingConfig {
    /// The gains the law applies at `speed`: the configured ones, or those
    /// of the speed schedule (PT-SCHEDULE).
    ///
    /// # Errors
    /// `PT-SPEED` when v ≤ 0; with a schedule, `PT-SCHEDULE-RANGE` outside
    /// its range and `LIB-FINITE`.
    pub fn gains_at(&self, speed: MetersPerSecond) -> Result<Gains, Precondition> {
        match self.schedule {
            Some(schedule) => schedule.gains_at(&self.gains, speed),
            None => check_speed(speed).map(|_| self.gains),
        }
    }
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
/// The gains are those of [`BacksteppingConfig::gains_at`] at `speed`.
///
/// Errors: `PT-DENOM` (1 − y c(s) ≤ 0), `PT-HEADING` (cos θ̃₂ ≤ 0), `PT-SPEED`
/// (v ≤ 0), `PT-SIDESLIP` (|β| ≥ π/2), `PT-SCHEDULE-RANGE` (a speed outside
/// the schedule), `LIB-FINITE` on overflow.
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
    let gains = config.gains_at(speed)?;
    let terms = LawTerms::new(&gains, error, sideslip, speed)?;
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

    fn check_speed(&self, speed: MetersPerSecond) -> Result<(), Precondition> {
        self.gains_at(speed).map(|_| ())
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
