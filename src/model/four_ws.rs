//! The extended kinematic model of a four-wheel-steering robot with sideslip
//! (Iberraken 2022, section 2.2.1, eqs. 5-8; `spec/iberraken2022.md`, FWS-*),
//! as pure functions, and the vehicle's actuator limits.
//!
//! The robot is a bicycle steered at both ends: δ_F at the front axle's
//! middle F, δ_R at the rear axle's middle R, the controlled point, whose
//! velocity v points at the heading plus δ_R + β_R. The same functions drive
//! the simulator's plant and the property tests of the two laws of
//! [`crate::control::four_ws`], so both see one model.

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Pose2, World};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{MetersPerSecond, Radians, RadiansPerSecond};
use crate::model::bicycle::{FrenetRates, Sideslip, SteeringLimit, Wheelbase, WorldRates};

/// A four-wheel-steering vehicle: its wheelbase and the limits of its front
/// and rear steering actuators (FWS-VEHICLE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourWheelSteering {
    /// The wheelbase L, distance from R to F.
    pub wheelbase: Wheelbase,
    /// The front steering saturation |δ_F| ≤ δ_F,max.
    pub max_front: SteeringLimit,
    /// The rear steering saturation |δ_R| ≤ δ_R,max.
    pub max_rear: SteeringLimit,
    /// The front steering rate limit, rad/s, when known (> 0).
    pub max_front_rate: Option<RadiansPerSecond>,
    /// The rear steering rate limit, rad/s, when known (> 0).
    pub max_rear_rate: Option<RadiansPerSecond>,
}

impl FourWheelSteering {
    /// A vehicle of wheelbase L, front and rear saturations, and rate limits
    /// when known.
    ///
    /// # Errors
    /// `FWS-VEHICLE` when a rate limit is not positive.
    //= spec/iberraken2022.md#fws-vehicle-four-wheel-steering-vehicle
    //# A four-wheel-steering vehicle MUST have a positive finite wheelbase,
    //# front and rear steering limits in (0, π/2) and, when known, positive
    //# front and rear steering rate limits; other values MUST be refused at
    //# construction.
    pub fn new(
        wheelbase: Wheelbase,
        max_front: SteeringLimit,
        max_rear: SteeringLimit,
        max_front_rate: Option<RadiansPerSecond>,
        max_rear_rate: Option<RadiansPerSecond>,
    ) -> Result<Self, Precondition> {
        let bad = |r: Option<RadiansPerSecond>| r.is_some_and(|r| r.get() <= 0.0);
        if bad(max_front_rate) || bad(max_rear_rate) {
            return Err(Precondition::new(
                "FWS-VEHICLE",
                "steering rate limits must be > 0",
            ));
        }
        Ok(Self {
            wheelbase,
            max_front,
            max_rear,
            max_front_rate,
            max_rear_rate,
        })
    }

    /// Whether both angles are within the saturations.
    #[must_use]
    pub fn within_limits(&self, front: Radians, rear: Radians) -> bool {
        front.get().abs() <= self.max_front.get().get()
            && rear.get().abs() <= self.max_rear.get().get()
    }
}

/// δ + β of one axle, checked within (−π/2, π/2) (`FWS-STEER-DOMAIN`).
//= spec/iberraken2022.md#fws-steer-domain-steering-within-the-domain-of-the-model
//# Where |δ_F + β_F| ≥ π/2 or |δ_R + β_R| ≥ π/2 the model and the laws MUST
//# return the `FWS-STEER-DOMAIN` error instead of a value.
pub(crate) fn axle_angle(steering: Radians, slip: Radians) -> Result<f64, Precondition> {
    let a = steering.get() + slip.get();
    if a.abs() < core::f64::consts::FRAC_PI_2 {
        Ok(a)
    } else {
        Err(Precondition::new(
            "FWS-STEER-DOMAIN",
            "|steering + sideslip| must be < pi/2 at each axle",
        ))
    }
}

/// 1 − c(s) y, checked strictly positive (`FWS-DENOM`): the α of eqs. 9-14.
//= spec/iberraken2022.md#fws-denom-robot-inside-the-radius-of-curvature
//# Where α = 1 − c(s) y ≤ 0 the model and the laws MUST return the
//# `FWS-DENOM` error instead of a value.
pub(crate) fn alpha(error: &TrackingError) -> Result<f64, Precondition> {
    let a = 1.0 - error.curvature.get() * error.y.get();
    if a > 0.0 && a.is_finite() {
        Ok(a)
    } else {
        Err(Precondition::new("FWS-DENOM", "1 - c(s) y must be > 0"))
    }
}

/// θ̃₂ = θ̃ + δ_R + β_R (eq. 6), checked with cos θ̃₂ > 0 (`FWS-HEADING`).
//= spec/iberraken2022.md#fws-heading-velocity-along-the-path
//# Where cos θ̃₂ ≤ 0 the model and the laws MUST return the `FWS-HEADING`
//# error instead of a value.
pub(crate) fn velocity_deviation(
    angular_deviation: Radians,
    rear: f64,
) -> Result<f64, Precondition> {
    let t2 = angular_deviation.get() + rear;
    if libm::cos(t2) > f64::EPSILON {
        Ok(t2)
    } else {
        Err(Precondition::new(
            "FWS-HEADING",
            "cos(theta~ + delta_R + beta_R) must be > 0",
        ))
    }
}

/// The speed v, checked strictly positive (`FWS-SPEED`).
//= spec/iberraken2022.md#fws-speed-forward-speed
//# Where v ≤ 0 the model in distance and the laws MUST return the
//# `FWS-SPEED` error instead of a value.
pub(crate) fn positive_speed(speed: MetersPerSecond) -> Result<f64, Precondition> {
    if speed.get() > 0.0 {
        Ok(speed.get())
    } else {
        Err(Precondition::new("FWS-SPEED", "speed must be > 0"))
    }
}

/// λ₁ = (tan(δ_F + β_F) − tan(δ_R + β_R)) / L (eq. 6), per metre.
fn lambda1(front: f64, rear: f64, wheelbase: Wheelbase) -> Result<f64, Precondition> {
    finite(
        (libm::tan(front) - libm::tan(rear)) / wheelbase.get().get(),
        "lambda_1 overflows",
    )
}

/// The yaw rate u_θ = v cos(δ_R + β_R) (tan(δ_F + β_F) − tan(δ_R + β_R)) / L
/// (Iberraken 2022, eq. 8), rad/s.
///
/// # Errors
/// `PT-SIDESLIP` for |β| ≥ π/2, `FWS-STEER-DOMAIN`, `LIB-FINITE` on overflow.
//= spec/iberraken2022.md#fws-yaw-rate-yaw-rate-of-the-model
//# The yaw rate MUST be
//# u_θ = v cos(δ_R + β_R) (tan(δ_F + β_F) − tan(δ_R + β_R)) / L.
pub fn yaw_rate(
    speed: MetersPerSecond,
    front: Radians,
    rear: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<RadiansPerSecond, Precondition> {
    sideslip.check()?;
    let f = axle_angle(front, sideslip.front)?;
    let r = axle_angle(rear, sideslip.rear)?;
    let rate = speed.get() * libm::cos(r) * lambda1(f, r, wheelbase)?;
    RadiansPerSecond::new(finite(rate, "yaw rate overflows")?)
}

/// Time derivatives of the Frénet state (eqs. 5-6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeRates {
    /// ṡ, m/s.
    pub s: f64,
    /// ẏ, m/s.
    pub y: f64,
    /// dθ̃/dt, rad/s.
    pub angular_deviation: f64,
}

/// The model in time (Iberraken 2022, eqs. 5-6): ṡ = v cos θ̃₂ / α,
/// ẏ = v sin θ̃₂, dθ̃/dt = v [cos(δ_R + β_R) λ₁ − λ₂], with
/// λ₂ = c(s) cos θ̃₂ / α and α = 1 − c(s) y.
///
/// # Errors
/// `FWS-DENOM`, `PT-SIDESLIP`, `FWS-STEER-DOMAIN`, `LIB-FINITE`.
//= spec/iberraken2022.md#fws-model-time-model-in-time
//# The model in time MUST give ṡ = v cos θ̃₂ / (1 − c(s) y),
//# ẏ = v sin θ̃₂ and dθ̃/dt = v [cos(δ_R + β_R) λ₁ − λ₂], with
//# λ₁ = (tan(δ_F + β_F) − tan(δ_R + β_R)) / L,
//# λ₂ = c(s) cos θ̃₂ / (1 − c(s) y) and θ̃₂ = θ̃ + δ_R + β_R.
pub fn time_rates(
    error: &TrackingError,
    speed: MetersPerSecond,
    front: Radians,
    rear: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<TimeRates, Precondition> {
    sideslip.check()?;
    let a = alpha(error)?;
    let f = axle_angle(front, sideslip.front)?;
    let r = axle_angle(rear, sideslip.rear)?;
    let t2 = error.angular_deviation.get() + r;
    let v = speed.get();
    let l2 = error.curvature.get() * libm::cos(t2) / a;
    Ok(TimeRates {
        s: finite(v * libm::cos(t2) / a, "s rate overflows")?,
        y: finite(v * libm::sin(t2), "y rate overflows")?,
        angular_deviation: finite(
            v * (libm::cos(r) * lambda1(f, r, wheelbase)? - l2),
            "angular rate overflows",
        )?,
    })
}

/// The model in distance (Iberraken 2022, eq. 7): y' = (1 − y c(s)) tan θ̃₂,
/// θ̃' = u_θ (1 − y c(s)) / (v cos θ̃₂) − c(s), derivatives per metre of s.
///
/// # Errors
/// `FWS-DENOM`, `FWS-HEADING`, `FWS-SPEED`, `PT-SIDESLIP`,
/// `FWS-STEER-DOMAIN`, `LIB-FINITE`.
//= spec/iberraken2022.md#fws-model-model-in-distance
//# The model in distance MUST give y' = (1 − y c(s)) tan θ̃₂ and
//# θ̃' = u_θ (1 − y c(s)) / (v cos θ̃₂) − c(s), with θ̃₂ = θ̃ + δ_R + β_R.
pub fn frenet_rates(
    error: &TrackingError,
    speed: MetersPerSecond,
    front: Radians,
    rear: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<FrenetRates, Precondition> {
    sideslip.check()?;
    let a = alpha(error)?;
    positive_speed(speed)?;
    let f = axle_angle(front, sideslip.front)?;
    let r = axle_angle(rear, sideslip.rear)?;
    let t2 = velocity_deviation(error.angular_deviation, r)?;
    // u_θ / v = cos(δ_R + β_R) λ₁: v cancels.
    let per_metre = libm::cos(r) * lambda1(f, r, wheelbase)?;
    Ok(FrenetRates {
        y: finite(a * libm::tan(t2), "y' overflows")?,
        angular_deviation: finite(
            per_metre * a / libm::cos(t2) - error.curvature.get(),
            "angular deviation rate overflows",
        )?,
    })
}

/// The world-frame kinematics of the same model, for integrating a pose in
/// time (the simulator's plant): ẋ = v cos(θ + δ_R + β_R),
/// ẏ = v sin(θ + δ_R + β_R), θ̇ = u_θ.
///
/// # Errors
/// Those of [`yaw_rate`].
//= spec/iberraken2022.md#fws-model-time-model-in-time
//# The velocity of R MUST point at the heading plus δ_R + β_R.
pub fn world_rates(
    pose: &Pose2<World>,
    speed: MetersPerSecond,
    front: Radians,
    rear: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<WorldRates, Precondition> {
    let heading_dot = yaw_rate(speed, front, rear, sideslip, wheelbase)?.get();
    let course = pose.heading.get() + rear.get() + sideslip.rear.get();
    Ok(WorldRates {
        x_dot: finite(speed.get() * libm::cos(course), "x rate overflows")?,
        y_dot: finite(speed.get() * libm::sin(course), "y rate overflows")?,
        heading_dot,
    })
}
