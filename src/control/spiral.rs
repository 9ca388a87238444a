//! The spiral controller of Emmi 2024 (section 3.3.2, eqs. 3-11): the robot
//! keeps the angle α from its heading to the spiral's centre at a desired α_d
//! (`spec/emmi2024.md`, EM-SPIRAL-*).
//!
//! α(t) = wrap(b(t) − θ(t)), where b is the direction from the robot to the
//! centre (eq. 5: α = π − θ + β with β the direction from the centre to the
//! robot). With e = α − α_d (eq. 3) and the unicycle model, ė = −ω + (v/d) sin α
//! (eq. 9), so the law ω = λ e + (v/d) sin α (eq. 11) gives ė = −λ e: the
//! error decays for λ > 0 (the errata's reading). α_d = +π/2 circles the
//! centre counter-clockwise at the radius d(0), α_d = −π/2 clockwise; other
//! values give inward (|α_d| < π/2) or outward (|α_d| > π/2) spirals.
//!
//! The law reads a centre and the robot's pose, not a tracking error, so it
//! is a typed function of its own ([`spiral_command`]) rather than a
//! [`crate::control::ControlLaw`].

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Point2, Pose2, World};
use crate::geometry::units::{wrap_raw, Meters, MetersPerSecond, Radians};
use crate::model::skid_steer::SkidSteer;
use crate::model::Saturated;

/// The smallest distance to the centre at which the law is defined, metres
/// (EM-SPIRAL-CENTRE).
pub const MIN_CENTRE_DISTANCE: f64 = 1e-3;

/// The spiral controller: gain λ, desired angle α_d and vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spiral {
    lambda: f64,
    desired_angle: f64,
    vehicle: SkidSteer,
}

/// The spiral angle α and the distance d of a pose to a centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpiralState {
    /// α, from the robot's heading to the direction of the centre, radians in (−π, π].
    pub angle: Radians,
    /// d, the distance from the robot to the centre.
    pub distance: Meters,
}

/// The angle α from the heading of `pose` to the direction of `centre`, and
/// the distance d between them (Emmi 2024, eq. 5).
///
/// # Errors
/// `EM-SPIRAL-CENTRE` when d < 1 mm (the robot on the centre);
/// `LIB-FINITE` when d overflows.
//= spec/emmi2024.md#em-spiral-angle-spiral-angle
//# The spiral angle MUST be α = wrap(b − θ), where b is the direction from the
//# robot to the spiral's centre and θ the robot's heading.
//= spec/emmi2024.md#em-spiral-centre-robot-away-from-the-centre
//# A robot closer than 1 mm to the spiral's centre MUST be refused with the
//# `EM-SPIRAL-CENTRE` error.
pub fn spiral_state(
    pose: &Pose2<World>,
    centre: Point2<World>,
) -> Result<SpiralState, Precondition> {
    let dx = centre.x() - pose.position.x();
    let dy = centre.y() - pose.position.y();
    let d = finite(libm::hypot(dx, dy), "distance to the centre overflows")?;
    if d < MIN_CENTRE_DISTANCE {
        return Err(Precondition::new(
            "EM-SPIRAL-CENTRE",
            "robot on the spiral's centre",
        ));
    }
    let angle = wrap_raw(libm::atan2(dy, dx) - pose.heading.get());
    Ok(SpiralState {
        angle: Radians(angle),
        distance: Meters(d),
    })
}

impl Spiral {
    /// A spiral controller of gain `lambda` (1/s) towards `desired_angle` α_d
    /// (wrapped to (−π, π]) for `vehicle`.
    ///
    /// # Errors
    /// `EM-SPIRAL-GAIN` unless λ is finite and > 0.
    //= spec/emmi2024.md#em-spiral-gain-convergent-gain
    //# The gain λ MUST be finite and strictly positive; another gain MUST be
    //# refused with the `EM-SPIRAL-GAIN` error.
    pub fn new(
        lambda: f64,
        desired_angle: Radians,
        vehicle: SkidSteer,
    ) -> Result<Self, Precondition> {
        if lambda.is_finite() && lambda > 0.0 {
            Ok(Self {
                lambda,
                desired_angle: wrap_raw(desired_angle.get()),
                vehicle,
            })
        } else {
            Err(Precondition::new(
                "EM-SPIRAL-GAIN",
                "lambda must be finite and > 0",
            ))
        }
    }

    /// The gain λ, 1/s.
    #[must_use]
    pub const fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The desired angle α_d, radians in (−π, π].
    #[must_use]
    pub const fn desired_angle(&self) -> Radians {
        Radians(self.desired_angle)
    }

    /// The same controller towards another desired angle (a new arc).
    #[must_use]
    pub fn towards(&self, desired_angle: Radians) -> Self {
        Self {
            desired_angle: wrap_raw(desired_angle.get()),
            ..*self
        }
    }

    /// The raw angular speed ω = λ e + (v/d) sin α with e = wrap(α − α_d).
    ///
    /// # Errors
    /// `EM-SPIRAL-LAW` for a negative speed; the errors of
    /// [`spiral_state`]; `LIB-FINITE` on overflow.
    //= spec/emmi2024.md#em-spiral-law-spiral-law
    //# The angular speed MUST be ω = λ e + (v/d) sin α with e = wrap(α − α_d),
    //# v the desired linear speed, which is commanded unchanged.
    //= spec/emmi2024.md#em-spiral-law-spiral-law
    //# A negative desired speed MUST be refused with the `EM-SPIRAL-LAW` error.
    pub fn raw_yaw_rate(
        &self,
        pose: &Pose2<World>,
        centre: Point2<World>,
        speed: MetersPerSecond,
    ) -> Result<f64, Precondition> {
        if speed.get() < 0.0 {
            return Err(Precondition::new(
                "EM-SPIRAL-LAW",
                "desired speed must be >= 0",
            ));
        }
        let state = spiral_state(pose, centre)?;
        let alpha = state.angle.get();
        let e = wrap_raw(alpha - self.desired_angle);
        finite(
            self.lambda * e + speed.get() / state.distance.get() * libm::sin(alpha),
            "spiral yaw rate overflows",
        )
    }
}

/// The spiral controller's command: speed v and ω of eq. 11, saturated to the
/// vehicle's track limits (EM-SKID-SATURATION).
///
/// # Errors
/// Those of [`Spiral::raw_yaw_rate`].
//= spec/emmi2024.md#em-spiral-law-spiral-law
//# The spiral controller MUST return its command saturated to the skid-steer
//# vehicle's track limits.
pub fn spiral_command(
    spiral: &Spiral,
    pose: &Pose2<World>,
    centre: Point2<World>,
    speed: MetersPerSecond,
) -> Result<Saturated, Precondition> {
    let omega = spiral.raw_yaw_rate(pose, centre, speed)?;
    spiral.vehicle.saturate(speed.get(), omega)
}
