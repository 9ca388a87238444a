//! The two four-wheel-steering laws of Iberraken 2022 (section 2.2;
//! `spec/iberraken2022.md`, S1-* and S2-*), for the model of
//! [`crate::model::four_ws`].
//!
//! - [`Strategy1`], backstepping position/orientation (eqs. 9-16): the front
//!   angle makes the velocity's angular deviation θ̃₂ = θ̃ + δ_R + β_R follow
//!   an objective that brings the lateral error to y_d; the rear angle turns
//!   the robot's own heading toward a desired θ̃_d. With the rear angle held
//!   at 0 ([`RearSteering::Held`]) it is the two-wheel-steering law.
//! - [`Strategy2`], front and rear lateral errors (eqs. 17-23): the rear
//!   angle brings the rear axle's middle R onto the line, the front angle
//!   brings the front axle's middle F onto it.
//!
//! Both compute the rear angle first, saturate it, and compute the front
//! angle from the saturated rear angle, so that the front loop holds even
//! when the rear actuator saturates.
//!
//! # Gain sign convention (`spec/iberraken2022.md`, S1-GAINS, S2-GAINS)
//!
//! Each strategy's gains are written in the form of its own equations, as
//! the paper prints them; ' is the derivative with respect to the distance s
//! travelled along the line.
//!
//! - Strategy 1 imposes e_y' = k_y e_y (eq. 11), e_θ' = k_θ e_θ (eq. 14) and
//!   e_r' = k_r e_r (eqs. 15-16): as for [`crate::control::backstepping`],
//!   these decay only for **negative** gains. Table 1 prints k_y = −0.9 (in
//!   this form) and k_θ = k_r = 1.0 (magnitudes): the library reads
//!   k_y = −0.9, k_θ = −1.0, k_r = −1.0. "|k_θ| ≫ |k_y|" is a configured
//!   least ratio r ≥ 1 ([`Strategy1Gains::new`]); Table 1's gains pass only
//!   r ≤ 1.11.
//! - Strategy 2 imposes y^R' = −K_R y^R (eq. 19) and y^F' = −K_F y^F
//!   (eq. 21): these decay for **positive** gains, as Table 1 prints them
//!   (K_F = K_R = 0.35).
//!
//! 1/|k| is, in both forms, the distance over which the error falls by a
//! factor e.

use crate::error::{finite, Precondition};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, MetersPerSecond, Radians};
use crate::model::bicycle::Sideslip;
use crate::model::four_ws::{
    alpha, axle_angle, positive_speed, velocity_deviation, FourWheelSteering,
};
use crate::model::{Actuation, Command, Saturated};

/// The three gains of strategy 1, per metre, in equation form (negative =
/// convergent), validated once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategy1Gains {
    k_y: f64,
    k_theta: f64,
    k_r: f64,
}

impl Strategy1Gains {
    /// Gains `k_y` (lateral, eq. 10), `k_theta` (velocity direction,
    /// eq. 14) and `k_r` (orientation, eq. 16), with `min_ratio` the least
    /// accepted |k_θ| / |k_y|.
    ///
    /// # Errors
    /// `S1-GAINS` unless the three gains are finite and strictly negative,
    /// `min_ratio` is finite and ≥ 1 and |k_θ| ≥ `min_ratio` |k_y|.
    //= spec/iberraken2022.md#s1-gains-gain-sign-and-ratio
    //# The gains k_y, k_θ and k_r MUST be finite and strictly negative, and
    //# |k_θ| MUST be at least a configured ratio r ≥ 1 times |k_y|; other
    //# gains MUST be refused at construction with the `S1-GAINS` error.
    pub fn new(k_y: f64, k_theta: f64, k_r: f64, min_ratio: f64) -> Result<Self, Precondition> {
        let negative = |k: f64| k.is_finite() && k < 0.0;
        if !(negative(k_y) && negative(k_theta) && negative(k_r)) {
            return Err(Precondition::new(
                "S1-GAINS",
                "gains must be finite and < 0 (equation form: e' = k e)",
            ));
        }
        let ratio_ok = min_ratio.is_finite()
            && min_ratio >= 1.0
            && libm::fabs(k_theta) >= min_ratio * libm::fabs(k_y);
        if ratio_ok {
            Ok(Self { k_y, k_theta, k_r })
        } else {
            Err(Precondition::new(
                "S1-GAINS",
                "need |k_theta| >= min_ratio |k_y| with a finite min_ratio >= 1",
            ))
        }
    }

    /// Table 1 of Iberraken 2022 in equation form: k_y = −0.9, k_θ = −1.0,
    /// k_r = −1.0, with the least ratio 1.
    ///
    /// # Errors
    /// None in practice (the values are valid); the signature keeps the check.
    pub fn table1() -> Result<Self, Precondition> {
        Self::new(-0.9, -1.0, -1.0, 1.0)
    }

    /// k_y, per metre.
    #[must_use]
    pub const fn k_y(&self) -> f64 {
        self.k_y
    }

    /// k_θ, per metre.
    #[must_use]
    pub const fn k_theta(&self) -> f64 {
        self.k_theta
    }

    /// k_r, per metre.
    #[must_use]
    pub const fn k_r(&self) -> f64 {
        self.k_r
    }
}

/// How strategy 1 drives the rear axle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RearSteering {
    /// The rear law of eq. 16.
    #[default]
    Backstepping,
    /// δ_R held at 0: the two-wheel-steering law (section 2.2.2, step 2).
    Held,
}

/// Strategy 1, validated once: gains, vehicle, rear mode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategy1 {
    /// The gains (sign convention in the module doc).
    pub gains: Strategy1Gains,
    /// The vehicle: wheelbase and steering limits.
    pub vehicle: FourWheelSteering,
    /// Whether the rear axle steers.
    pub rear: RearSteering,
}

/// What strategy 1 reads besides the error: the sideslip estimate and the
/// objectives y_d and θ̃_d (section 2.2.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Objectives {
    /// β_F and β_R.
    pub sideslip: Sideslip,
    /// The desired lateral deviation y_d, m.
    pub lateral_offset: Meters,
    /// The desired orientation θ̃_d, rad, |θ̃_d| < π/2.
    pub orientation: Radians,
}

impl Objectives {
    /// No sideslip, y_d = 0, θ̃_d = 0: on the line, parallel to it.
    pub const NEUTRAL: Self = Self {
        sideslip: Sideslip::ZERO,
        lateral_offset: Meters::ZERO,
        orientation: Radians::ZERO,
    };

    /// Checks |β| < π/2 (`PT-SIDESLIP`) and |θ̃_d| < π/2 (`S1-REAR`).
    ///
    /// # Errors
    /// The requirement broken.
    pub fn check(&self) -> Result<(), Precondition> {
        self.sideslip.check()?;
        if self.orientation.get().abs() < core::f64::consts::FRAC_PI_2 {
            Ok(())
        } else {
            Err(Precondition::new(
                "S1-REAR",
                "the desired orientation must satisfy |theta_d| < pi/2",
            ))
        }
    }

    /// The mirror image (left and right swapped).
    #[must_use]
    pub fn mirrored(self) -> Self {
        Self {
            sideslip: self.sideslip.mirrored(),
            lateral_offset: self.lateral_offset.negated(),
            orientation: self.orientation.negated(),
        }
    }
}

/// The output of a four-wheel-steering law for one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourWsCommand {
    /// δ_F, saturated, rad, positive to the left.
    pub front: Radians,
    /// δ_R, saturated, rad, positive to the left.
    pub rear: Radians,
    /// Whether either raw angle was beyond its limit and clamped.
    pub saturated: bool,
}

/// The objective of the velocity's angular deviation,
/// θ̃₂^obj = arctan(k_y e_y / α), e_y = y − y_d, α = 1 − c(s) y (Iberraken
/// 2022, eq. 10), radians.
///
/// # Errors
/// `FWS-DENOM`, `LIB-FINITE`.
//= spec/iberraken2022.md#s1-target-objective-of-the-velocity-direction
//# The objective of the velocity's angular deviation MUST be
//# θ̃₂^obj = arctan(k_y e_y / α), with e_y = y − y_d and α = 1 − c(s) y.
//= spec/iberraken2022.md#s1-target-objective-of-the-velocity-direction
//# With θ̃₂ = θ̃₂^obj the model MUST give e_y' = k_y e_y (y_d constant).
pub fn velocity_objective(
    gains: &Strategy1Gains,
    error: &TrackingError,
    lateral_offset: Meters,
) -> Result<Radians, Precondition> {
    let a = alpha(error)?;
    let e_y = finite(
        error.y.get() - lateral_offset.get(),
        "lateral error overflows",
    )?;
    Radians::new(libm::atan(finite(
        gains.k_y * e_y / a,
        "velocity objective overflows",
    )?))
}

/// The rear angle of strategy 1 before saturation,
/// δ_R = arctan(k_r e_r / k_θ + tan θ̃_d) − θ̃ − β_R with
/// e_r = tan θ̃ − tan θ̃_d (Iberraken 2022, eqs. 15-16), radians.
///
/// # Errors
/// `S1-REAR` when cos θ̃ ≤ 0 or |θ̃_d| ≥ π/2, `PT-SIDESLIP`, `LIB-FINITE`.
//= spec/iberraken2022.md#s1-rear-rear-steering-toward-a-desired-orientation
//# The rear angle of strategy 1 MUST be
//# δ_R = arctan(k_r e_r / k_θ + tan θ̃_d) − θ̃ − β_R, with
//# e_r = tan θ̃ − tan θ̃_d.
//= spec/iberraken2022.md#s1-rear-rear-steering-toward-a-desired-orientation
//# Where cos θ̃ ≤ 0 or |θ̃_d| ≥ π/2 the rear law MUST return the `S1-REAR`
//# error instead of a value.
//= spec/iberraken2022.md#s1-rear-rear-steering-toward-a-desired-orientation
//# With the rear law, the model of eq. 15, k_θ (tan θ̃₂ − tan θ̃_d), MUST equal
//# k_r e_r.
pub fn strategy1_rear(
    gains: &Strategy1Gains,
    error: &TrackingError,
    objectives: &Objectives,
) -> Result<Radians, Precondition> {
    objectives.check()?;
    let theta = error.angular_deviation.get();
    if libm::cos(theta) <= f64::EPSILON {
        return Err(Precondition::new(
            "S1-REAR",
            "cos(theta~) must be > 0: robot not heading along the line",
        ));
    }
    let tan_d = libm::tan(objectives.orientation.get());
    let e_r = finite(libm::tan(theta) - tan_d, "orientation error overflows")?;
    let target = finite(
        gains.k_r * e_r / gains.k_theta + tan_d,
        "rear target overflows",
    )?;
    Radians::new(libm::atan(target) - theta - objectives.sideslip.rear.get())
}

/// The front angle of strategy 1 before saturation, given the rear angle
/// `rear` actually applied (Iberraken 2022, eqs. 12-14):
/// δ_F = arctan(tan(δ_R + β_R) + L cos³θ̃₂ / (α cos(δ_R + β_R))
/// (k_θ e_θ + c(s) / cos²θ̃₂)) − β_F, with e_θ = tan θ̃₂ − tan θ̃₂^obj.
///
/// # Errors
/// `FWS-DENOM`, `FWS-HEADING`, `FWS-STEER-DOMAIN` (rear), `PT-SIDESLIP`,
/// `LIB-FINITE`.
//= spec/iberraken2022.md#s1-front-front-steering-of-the-velocity-direction
//# The front angle of strategy 1 MUST be
//# δ_F = arctan(tan(δ_R + β_R) + L cos³(θ̃₂) / (α cos(δ_R + β_R))
//# (k_θ e_θ + c(s) / cos²(θ̃₂))) − β_F, with e_θ = tan θ̃₂ − tan θ̃₂^obj and
//# δ_R the rear angle applied.
//= spec/iberraken2022.md#s1-front-front-steering-of-the-velocity-direction
//# With δ_R constant, the model MUST give (tan θ̃₂)' = k_θ e_θ, so that
//# e_θ' = k_θ e_θ − (tan θ̃₂^obj)'; on a straight line the neglected term is
//# (tan θ̃₂^obj)' = k_y y'.
pub fn strategy1_front(
    law: &Strategy1,
    error: &TrackingError,
    objectives: &Objectives,
    rear: Radians,
) -> Result<Radians, Precondition> {
    let slip = objectives.sideslip;
    slip.check()?;
    let a = alpha(error)?;
    let r = axle_angle(rear, slip.rear)?;
    let t2 = velocity_deviation(error.angular_deviation, r)?;
    let objective = velocity_objective(&law.gains, error, objectives.lateral_offset)?;
    let e_theta = finite(
        libm::tan(t2) - libm::tan(objective.get()),
        "velocity error overflows",
    )?;
    let (cos2, cos_r) = (libm::cos(t2), libm::cos(r));
    let length = law.vehicle.wheelbase.get().get();
    let drive = law.gains.k_theta * e_theta * cos2 * cos2 * cos2 + error.curvature.get() * cos2;
    let tangent = finite(
        libm::tan(r) + length * drive / (a * cos_r),
        "front tangent overflows",
    )?;
    Radians::new(libm::atan(tangent) - slip.front.get())
}

/// The command of strategy 1 (Iberraken 2022, eqs. 9-16): the rear angle of
/// eq. 16 (or 0 when held), saturated, then the front angle of eq. 14 for
/// it, saturated.
///
/// # Errors
/// `FWS-SPEED`, and those of [`strategy1_rear`] and [`strategy1_front`].
//= spec/iberraken2022.md#s1-saturation-saturated-command
//# Each steering angle MUST lie within its limit; a law output beyond it MUST
//# be clamped to the nearer bound and reported as saturated, and the front
//# angle MUST be computed for the rear angle after its saturation.
//= spec/iberraken2022.md#fws-mirror-mirror-symmetry
//# Both laws MUST be mirror symmetric: the mirrored error, sideslip and
//# objectives MUST give the negated front and rear angles.
pub fn strategy1_command(
    law: &Strategy1,
    error: &TrackingError,
    objectives: &Objectives,
    speed: MetersPerSecond,
) -> Result<FourWsCommand, Precondition> {
    positive_speed(speed)?;
    objectives.check()?;
    //= spec/iberraken2022.md#s1-two-wheel-steering-rear-angle-held-at-zero
    //# With the rear steering held, strategy 1 MUST command δ_R = 0 and the
    //# front angle of eq. 14 for δ_R = 0.
    let raw_rear = match law.rear {
        RearSteering::Backstepping => strategy1_rear(&law.gains, error, objectives)?,
        RearSteering::Held => Radians::ZERO,
    };
    let (rear, rear_clamped) = law.vehicle.max_rear.clamp(raw_rear);
    let raw_front = strategy1_front(law, error, objectives, rear)?;
    let (front, front_clamped) = law.vehicle.max_front.clamp(raw_front);
    Ok(FourWsCommand {
        front,
        rear,
        saturated: rear_clamped || front_clamped,
    })
}

//= spec/iberraken2022.md#s1-law-strategy-1-behind-the-law-seam
//# Strategy 1 MUST be a control law for the four-wheel-steering vehicle,
//# reading the sideslip estimate and the objectives y_d and θ̃_d as its
//# extra input, zero sideslip on the line and parallel to it being its
//# neutral input.
impl super::ControlLaw for Strategy1 {
    type Extra = Objectives;

    const NEUTRAL: Objectives = Objectives::NEUTRAL;

    fn actuation(&self) -> Actuation {
        Actuation::FourWheelSteering
    }

    fn check_extra(extra: &Objectives) -> Result<(), Precondition> {
        extra.check()
    }

    fn command(
        &self,
        error: &TrackingError,
        extra: &Objectives,
        speed: MetersPerSecond,
    ) -> Result<Saturated, Precondition> {
        let c = strategy1_command(self, error, extra, speed)?;
        Ok(Saturated {
            command: Command::FourWheelSteering {
                speed,
                front: c.front,
                rear: c.rear,
            },
            saturated: c.saturated,
        })
    }
}

/// The two gains of strategy 2, per metre, in the form y' = −K y (positive =
/// convergent), validated once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategy2Gains {
    k_front: f64,
    k_rear: f64,
}

impl Strategy2Gains {
    /// Gains K_F (front, eq. 21) and K_R (rear, eq. 19), per metre.
    ///
    /// # Errors
    /// `S2-GAINS` unless both are finite and strictly positive.
    //= spec/iberraken2022.md#s2-gains-gain-sign
    //# The gains K_F and K_R MUST be finite and strictly positive; other gains
    //# MUST be refused at construction with the `S2-GAINS` error.
    pub fn new(k_front: f64, k_rear: f64) -> Result<Self, Precondition> {
        let positive = |k: f64| k.is_finite() && k > 0.0;
        if positive(k_front) && positive(k_rear) {
            Ok(Self { k_front, k_rear })
        } else {
            Err(Precondition::new(
                "S2-GAINS",
                "gains must be finite and > 0 (equation form: y' = -K y)",
            ))
        }
    }

    /// Table 1 of Iberraken 2022: K_F = K_R = 0.35.
    ///
    /// # Errors
    /// None in practice (the values are valid); the signature keeps the check.
    pub fn table1() -> Result<Self, Precondition> {
        Self::new(0.35, 0.35)
    }

    /// K_F, per metre.
    #[must_use]
    pub const fn k_front(&self) -> f64 {
        self.k_front
    }

    /// K_R, per metre.
    #[must_use]
    pub const fn k_rear(&self) -> f64 {
        self.k_rear
    }
}

/// Strategy 2, validated once: gains and vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategy2 {
    /// The gains (sign convention in the module doc).
    pub gains: Strategy2Gains,
    /// The vehicle: wheelbase and steering limits.
    pub vehicle: FourWheelSteering,
}

/// The front lateral error y^F = y^R + L sin θ̃: the deviation of F, at L
/// ahead of R along the heading, measured along the line's normal at R's
/// projection (Iberraken 2022, Fig. 7b and eq. 18), metres.
///
/// # Errors
/// `LIB-FINITE` on overflow.
//= spec/iberraken2022.md#s2-front-error-front-lateral-error
//# The front lateral error MUST be y^F = y^R + L sin θ̃.
//= spec/iberraken2022.md#s2-front-error-front-lateral-error
//# With any steering, the model MUST give
//# y^F' = α / cos θ̃₂ (sin θ̃₂ + L cos θ̃ (cos(δ_R + β_R) λ₁ − λ₂)).
pub fn front_lateral_error(
    error: &TrackingError,
    vehicle: &FourWheelSteering,
) -> Result<Meters, Precondition> {
    let length = vehicle.wheelbase.get().get();
    Meters::new(error.y.get() + length * libm::sin(error.angular_deviation.get()))
}

/// The rear angle of strategy 2 before saturation,
/// δ_R = arctan(−K_R y^R / (1 − c(s) y^R)) − θ̃ − β_R (Iberraken 2022,
/// eqs. 19-20), radians.
///
/// # Errors
/// `FWS-DENOM`, `PT-SIDESLIP`, `LIB-FINITE`.
//= spec/iberraken2022.md#s2-rear-rear-steering-of-the-rear-error
//# The rear angle of strategy 2 MUST be
//# δ_R = arctan(−K_R y^R / (1 − c(s) y^R)) − θ̃ − β_R.
//= spec/iberraken2022.md#s2-rear-rear-steering-of-the-rear-error
//# With it, the model MUST give y^R' = −K_R y^R.
pub fn strategy2_rear(
    gains: &Strategy2Gains,
    error: &TrackingError,
    sideslip: Sideslip,
) -> Result<Radians, Precondition> {
    sideslip.check()?;
    let a = alpha(error)?;
    let target = finite(-gains.k_rear * error.y.get() / a, "rear target overflows")?;
    Radians::new(libm::atan(target) - error.angular_deviation.get() - sideslip.rear.get())
}

/// The front angle of strategy 2 before saturation, given the rear angle
/// `rear` actually applied (Iberraken 2022, eqs. 21-23):
/// δ_F = arctan(L λ₂ / cos(δ_R + β_R)
/// − K_F y^F cos θ̃₂ / ((1 − c(s) y^R) cos(δ_R + β_R) cos θ̃) − B₁) − β_F,
/// B₁ = sin θ̃₂ / (cos(δ_R + β_R) cos θ̃) − tan(δ_R + β_R).
///
/// # Errors
/// `S2-FRONT` when cos θ̃ ≤ 0, `FWS-DENOM`, `FWS-STEER-DOMAIN` (rear),
/// `PT-SIDESLIP`, `LIB-FINITE`.
//= spec/iberraken2022.md#s2-front-front-steering-of-the-front-error
//# The front angle of strategy 2 MUST be
//# δ_F = arctan(L λ₂ / cos(δ_R + β_R) − K_F y^F cos θ̃₂ / ((1 − c(s) y^R)
//# cos(δ_R + β_R) cos θ̃) − B₁) − β_F, with
//# B₁ = sin θ̃₂ / (cos(δ_R + β_R) cos θ̃) − tan(δ_R + β_R) and δ_R the rear
//# angle applied.
//= spec/iberraken2022.md#s2-front-front-steering-of-the-front-error
//# Where cos θ̃ ≤ 0 the front law MUST return the `S2-FRONT` error instead
//# of a value.
//= spec/iberraken2022.md#s2-front-front-steering-of-the-front-error
//# With it, the model MUST give y^F' = −K_F y^F.
pub fn strategy2_front(
    law: &Strategy2,
    error: &TrackingError,
    sideslip: Sideslip,
    rear: Radians,
) -> Result<Radians, Precondition> {
    sideslip.check()?;
    let a = alpha(error)?;
    let r = axle_angle(rear, sideslip.rear)?;
    let theta = error.angular_deviation.get();
    let cos_t = libm::cos(theta);
    if cos_t <= f64::EPSILON {
        return Err(Precondition::new(
            "S2-FRONT",
            "cos(theta~) must be > 0: robot not heading along the line",
        ));
    }
    let t2 = theta + r;
    let cos_r = libm::cos(r);
    let length = law.vehicle.wheelbase.get().get();
    let y_front = front_lateral_error(error, &law.vehicle)?.get();
    let lambda2 = error.curvature.get() * libm::cos(t2) / a;
    let b1 = libm::sin(t2) / (cos_r * cos_t) - libm::tan(r);
    let tangent = finite(
        length * lambda2 / cos_r
            - law.gains.k_front * y_front * libm::cos(t2) / (a * cos_r * cos_t)
            - b1,
        "front tangent overflows",
    )?;
    Radians::new(libm::atan(tangent) - sideslip.front.get())
}

/// The command of strategy 2 (Iberraken 2022, eqs. 17-23): the rear angle
/// of eq. 20, saturated, then the front angle of eq. 22 for it, saturated.
///
/// # Errors
/// `FWS-SPEED`, and those of [`strategy2_rear`] and [`strategy2_front`].
//= spec/iberraken2022.md#s2-saturation-saturated-command
//# Each steering angle of strategy 2 MUST lie within its limit; a law output
//# beyond it MUST be clamped to the nearer bound and reported as saturated,
//# and the front angle MUST be computed for the rear angle after its
//# saturation.
pub fn strategy2_command(
    law: &Strategy2,
    error: &TrackingError,
    sideslip: Sideslip,
    speed: MetersPerSecond,
) -> Result<FourWsCommand, Precondition> {
    positive_speed(speed)?;
    let raw_rear = strategy2_rear(&law.gains, error, sideslip)?;
    let (rear, rear_clamped) = law.vehicle.max_rear.clamp(raw_rear);
    let raw_front = strategy2_front(law, error, sideslip, rear)?;
    let (front, front_clamped) = law.vehicle.max_front.clamp(raw_front);
    Ok(FourWsCommand {
        front,
        rear,
        saturated: rear_clamped || front_clamped,
    })
}

//= spec/iberraken2022.md#s2-law-strategy-2-behind-the-law-seam
//# Strategy 2 MUST be a control law for the four-wheel-steering vehicle,
//# reading the sideslip estimate as its extra input, zero sideslip being its
//# neutral input.
impl super::ControlLaw for Strategy2 {
    type Extra = Sideslip;

    const NEUTRAL: Sideslip = Sideslip::ZERO;

    fn actuation(&self) -> Actuation {
        Actuation::FourWheelSteering
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
        let c = strategy2_command(self, error, *extra, speed)?;
        Ok(Saturated {
            command: Command::FourWheelSteering {
                speed,
                front: c.front,
                rear: c.rear,
            },
            saturated: c.saturated,
        })
    }
}
