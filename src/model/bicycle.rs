//! The extended kinematic bicycle model with sideslip (Pierre 2022, section 2.1,
//! eq. 1), as pure functions.
//!
//! The controlled point O is the middle of the rear axle. Its velocity, of
//! magnitude v, points at the heading plus the rear sideslip angle β_R; the
//! front wheels steer by δ and slip by β_F (`spec/pierre2022.md`, PT-MODEL and
//! PT-YAW-RATE). The same functions drive the simulator's plant and the
//! property tests of the control law, so both see one model.

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Pose2, World};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, MetersPerSecond, Radians, RadiansPerSecond};

/// The wheelbase L of the bicycle model, metres, strictly positive and finite.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct Wheelbase(Meters);

impl Wheelbase {
    /// A wheelbase of `meters`; zero, negative or non-finite is the `PT-WHEELBASE` error.
    //= spec/pierre2022.md#pt-wheelbase-positive-wheelbase
    //# The wheelbase L MUST be finite and strictly positive.
    pub fn new(meters: f64) -> Result<Self, Precondition> {
        if meters.is_finite() && meters > 0.0 {
            Ok(Self(Meters(meters)))
        } else {
            Err(Precondition::new(
                "PT-WHEELBASE",
                "wheelbase must be finite and > 0",
            ))
        }
    }

    /// The wheelbase in metres.
    #[must_use]
    pub const fn get(self) -> Meters {
        self.0
    }
}

/// A steering saturation |δ| ≤ δ_max with 0 < δ_max < π/2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteeringLimit(Radians);

impl SteeringLimit {
    /// A limit of `max` radians; outside (0, π/2) or non-finite is `PT-SATURATION`.
    pub fn new(max: f64) -> Result<Self, Precondition> {
        if max.is_finite() && max > 0.0 && max < core::f64::consts::FRAC_PI_2 {
            Ok(Self(Radians(max)))
        } else {
            Err(Precondition::new(
                "PT-SATURATION",
                "steering limit must be in (0, pi/2)",
            ))
        }
    }

    /// The limit δ_max.
    #[must_use]
    pub const fn get(self) -> Radians {
        self.0
    }

    /// δ clamped to [−δ_max, δ_max], and whether it was clamped.
    //= spec/pierre2022.md#pt-saturation-steering-saturation
    //# The steering command MUST lie within [−δ_max, δ_max]; a law output
    //# beyond it MUST be clamped to the nearer bound and reported as saturated.
    #[must_use]
    pub fn clamp(self, steering: Radians) -> (Radians, bool) {
        let max = self.0.get();
        if steering.get() > max {
            (Radians(max), true)
        } else if steering.get() < -max {
            (Radians(-max), true)
        } else {
            (steering, false)
        }
    }
}

/// A front-steered vehicle as the bicycle model sees it: its wheelbase and
/// the limits of its steering actuator (GD-VEHICLE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bicycle {
    /// The wheelbase L.
    pub wheelbase: Wheelbase,
    /// The steering saturation |δ| ≤ δ_max.
    pub max_steering: SteeringLimit,
    /// The steering actuator's rate limit, rad/s, when known (> 0).
    pub max_steering_rate: Option<RadiansPerSecond>,
}

impl Bicycle {
    /// A bicycle of wheelbase L and steering limit, rate `max_steering_rate`
    /// when known.
    ///
    /// # Errors
    /// `PT-SATURATION` when the rate is not positive.
    pub fn new(
        wheelbase: Wheelbase,
        max_steering: SteeringLimit,
        max_steering_rate: Option<RadiansPerSecond>,
    ) -> Result<Self, Precondition> {
        if max_steering_rate.is_some_and(|r| r.get() <= 0.0) {
            return Err(Precondition::new(
                "PT-SATURATION",
                "steering rate limit must be > 0",
            ));
        }
        Ok(Self {
            wheelbase,
            max_steering,
            max_steering_rate,
        })
    }
}

/// The front and rear sideslip angles β_F and β_R, radians: the angle from each
/// wheel's orientation to its actual velocity, counter-clockwise positive.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sideslip {
    /// Front sideslip β_F.
    pub front: Radians,
    /// Rear sideslip β_R.
    pub rear: Radians,
}

impl Sideslip {
    /// No sideslip: rolling without sliding.
    pub const ZERO: Self = Self {
        front: Radians::ZERO,
        rear: Radians::ZERO,
    };

    /// The sideslip `(front, rear)` from raw radians; non-finite is `LIB-FINITE`,
    /// |β| ≥ π/2 is `PT-SIDESLIP`.
    pub fn new(front: f64, rear: f64) -> Result<Self, Precondition> {
        let s = Self {
            front: Radians::new(front)?,
            rear: Radians::new(rear)?,
        };
        s.check()?;
        Ok(s)
    }

    /// Checks |β_F| < π/2 and |β_R| < π/2 (`PT-SIDESLIP`).
    //= spec/pierre2022.md#pt-sideslip-sideslip-angles-below-a-right-angle
    //# The sideslip angles β_F and β_R MUST satisfy |β| < π/2; a larger angle
    //# MUST be the `PT-SIDESLIP` error.
    pub fn check(&self) -> Result<(), Precondition> {
        let limit = core::f64::consts::FRAC_PI_2;
        if self.front.get().abs() < limit && self.rear.get().abs() < limit {
            Ok(())
        } else {
            Err(Precondition::new(
                "PT-SIDESLIP",
                "|sideslip| must be < pi/2",
            ))
        }
    }

    /// The mirror image (left and right swapped).
    #[must_use]
    pub fn mirrored(self) -> Self {
        Self {
            front: self.front.negated(),
            rear: self.rear.negated(),
        }
    }
}

/// The yaw rate u_θ = v cos β_R (tan(δ + β_F) − tan β_R) / L (Pierre 2022, eq. 1).
///
/// Errors: `PT-SIDESLIP` for |β| ≥ π/2, `PT-STEER-DOMAIN` when δ + β_F is not
/// within (−π/2, π/2), `LIB-FINITE` if the result overflows.
//= spec/pierre2022.md#pt-yaw-rate-yaw-rate-of-the-model
//# The yaw rate MUST be u_θ = v cos β_R (tan(δ + β_F) − tan β_R) / L.
pub fn yaw_rate(
    speed: MetersPerSecond,
    steering: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<RadiansPerSecond, Precondition> {
    sideslip.check()?;
    //= spec/pierre2022.md#pt-steer-domain-steering-within-the-domain-of-the-model
    //# Where |δ + β_F| ≥ π/2 the model MUST return the `PT-STEER-DOMAIN` error
    //# instead of a value.
    let front = steering.get() + sideslip.front.get();
    if front.abs() >= core::f64::consts::FRAC_PI_2 {
        return Err(Precondition::new(
            "PT-STEER-DOMAIN",
            "|steering + front sideslip| must be < pi/2",
        ));
    }
    let beta_r = sideslip.rear.get();
    let rate = speed.get() * libm::cos(beta_r) * (libm::tan(front) - libm::tan(beta_r))
        / wheelbase.get().get();
    RadiansPerSecond::new(finite(rate, "yaw rate overflows")?)
}

/// Derivatives of the Frénet state with respect to the curvilinear abscissa s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrenetRates {
    /// y' = dy/ds, dimensionless (metres per metre).
    pub y: f64,
    /// θ̃' = dθ̃/ds, radians per metre.
    pub angular_deviation: f64,
}

/// The extended kinematic model (Pierre 2022, eq. 1), derivatives in distance:
/// y' = (1 − y c(s)) tan θ̃₂ and θ̃' = u_θ (1 − y c(s)) / (v cos θ̃₂) − c(s), with
/// θ̃₂ = θ̃ + β_R.
///
/// `error.curvature` is c(s); `curvature_ahead` is not used by the model.
/// Errors: `PT-DENOM` when 1 − y c(s) ≤ 0, `PT-HEADING` when cos θ̃₂ ≤ 0,
/// `PT-SPEED` when v ≤ 0, and the errors of [`yaw_rate`].
//= spec/pierre2022.md#pt-model-extended-kinematic-model-with-sideslip
//# The model MUST give y' = (1 − y c(s)) tan θ̃₂ and
//# θ̃' = u_θ (1 − y c(s)) / (v cos θ̃₂) − c(s), with θ̃₂ = θ̃ + β_R.
pub fn frenet_rates(
    error: &TrackingError,
    speed: MetersPerSecond,
    steering: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<FrenetRates, Precondition> {
    let alpha = check_denominator(error)?;
    let theta2 = check_heading(error.angular_deviation, sideslip)?;
    let v = check_speed(speed)?;
    let u = yaw_rate(speed, steering, sideslip, wheelbase)?.get();
    let c = error.curvature.get();
    Ok(FrenetRates {
        y: finite(alpha * libm::tan(theta2), "y' overflows")?,
        angular_deviation: finite(
            u * alpha / (v * libm::cos(theta2)) - c,
            "angular deviation rate overflows",
        )?,
    })
}

/// Time derivatives of a world pose under the model: the velocity of O, at
/// heading + β_R, and the yaw rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldRates {
    /// dx/dt, m/s (world frame).
    pub x_dot: f64,
    /// dy/dt, m/s (world frame).
    pub y_dot: f64,
    /// dθ/dt, rad/s.
    pub heading_dot: f64,
}

/// The world-frame kinematics of the same model, for integrating a pose in time
/// (the simulator's plant): ẋ = v cos(θ + β_R), ẏ = v sin(θ + β_R), θ̇ = u_θ.
//= spec/pierre2022.md#pt-model-extended-kinematic-model-with-sideslip
//# The velocity of the controlled point O MUST point at the heading plus β_R.
pub fn world_rates(
    pose: &Pose2<World>,
    speed: MetersPerSecond,
    steering: Radians,
    sideslip: Sideslip,
    wheelbase: Wheelbase,
) -> Result<WorldRates, Precondition> {
    let heading_dot = yaw_rate(speed, steering, sideslip, wheelbase)?.get();
    let course = pose.heading.get() + sideslip.rear.get();
    Ok(WorldRates {
        x_dot: speed.get() * libm::cos(course),
        y_dot: speed.get() * libm::sin(course),
        heading_dot,
    })
}

/// 1 − y c(s), checked strictly positive (`PT-DENOM`).
//= spec/pierre2022.md#pt-denom-robot-inside-the-radius-of-curvature
//# Where 1 − y c(s) ≤ 0 the model and the law MUST return the `PT-DENOM`
//# error instead of a value.
pub(crate) fn check_denominator(error: &TrackingError) -> Result<f64, Precondition> {
    let alpha = 1.0 - error.y.get() * error.curvature.get();
    if alpha > 0.0 && alpha.is_finite() {
        Ok(alpha)
    } else {
        Err(Precondition::new("PT-DENOM", "1 - y c(s) must be > 0"))
    }
}

/// θ̃₂ = θ̃ + β_R, checked with cos θ̃₂ > 0 (`PT-HEADING`) and |β| < π/2.
//= spec/pierre2022.md#pt-heading-robot-heading-along-the-path
//# Where cos θ̃₂ ≤ 0 the model and the law MUST return the `PT-HEADING` error
//# instead of a value.
pub(crate) fn check_heading(
    angular_deviation: Radians,
    sideslip: Sideslip,
) -> Result<f64, Precondition> {
    sideslip.check()?;
    let theta2 = angular_deviation.get() + sideslip.rear.get();
    if libm::cos(theta2) > f64::EPSILON {
        Ok(theta2)
    } else {
        Err(Precondition::new(
            "PT-HEADING",
            "cos(theta~ + beta_R) must be > 0: robot not heading along the path",
        ))
    }
}

/// The speed v, checked strictly positive (`PT-SPEED`).
//= spec/pierre2022.md#pt-speed-forward-speed
//# Where v ≤ 0 the law MUST return the `PT-SPEED` error instead of a value.
pub(crate) fn check_speed(speed: MetersPerSecond) -> Result<f64, Precondition> {
    let v = speed.get();
    if v > 0.0 {
        Ok(v)
    } else {
        Err(Precondition::new("PT-SPEED", "speed must be > 0"))
    }
}
