//! The vehicle plants, one per actuation behind [`Plant`], each taking the
//! core's [`Command`]: the extended kinematic bicycle of Pierre 2022 (eq. 1,
//! through the core's `world_rates`) with a first-order steering actuator, a
//! rate limit and saturation, integrated with RK4 sub-steps; and the
//! differential robot of Guyonneau 2022 ([`DifferentialPlant`]: wheels with
//! a first-order lag and a speed limit, the unicycle integrated exactly).
//!
//! Pure and deterministic: the next state is a function of the state, the
//! command held over the control period, the speed and the terrain.

use fieldguide::model::bicycle::{world_rates, Bicycle, Sideslip, SteeringLimit, Wheelbase};
use fieldguide::model::{Actuation, Command};
use fieldguide::{MetersPerSecond, Pose2, Precondition, Radians, RadiansPerSecond, World};

use crate::world::terrain::Terrain;

/// The steering actuator: first-order lag towards the saturated command, rate
/// limited, saturated.
///
/// The lag's time constant is τ = T_s / 3 for a 5 % settling time T_s (a
/// first-order step response reaches 95 % at 3τ, since e⁻³ ≈ 0.05).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteeringActuator {
    /// Time constant τ, seconds (0: no lag).
    pub time_constant_s: f64,
    /// Rate limit, rad/s (> 0).
    pub rate_limit_rad_s: f64,
    /// Saturation |δ| ≤ δ_max.
    pub limit: SteeringLimit,
}

impl SteeringActuator {
    /// The actuator of 5 % settling time `settling_s`, rate limit and saturation.
    #[must_use]
    pub fn from_settling(settling_s: f64, rate_limit_rad_s: f64, limit: SteeringLimit) -> Self {
        Self {
            time_constant_s: settling_s / 3.0,
            rate_limit_rad_s,
            limit,
        }
    }

    /// The steering angle after `h` seconds from `current` with `command` held,
    /// radians: the exact first-order response over `h`, its change limited to
    /// ±rate·h, then saturated.
    #[must_use]
    pub fn advance(&self, current: f64, command: f64, h: f64) -> f64 {
        let target =
            fieldguide::Radians::new(command).map_or(f64::NAN, |c| self.limit.clamp(c).0.get());
        let lagged = if self.time_constant_s > 0.0 {
            target + (current - target) * (-h / self.time_constant_s).exp()
        } else {
            target
        };
        let max_step = self.rate_limit_rad_s * h;
        let next = current + (lagged - current).clamp(-max_step, max_step);
        fieldguide::Radians::new(next).map_or(f64::NAN, |n| self.limit.clamp(n).0.get())
    }
}

/// The vehicle's parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleParams {
    /// Wheelbase L.
    pub wheelbase: Wheelbase,
    /// Track (left to right wheel centres), metres.
    pub track_m: f64,
    /// Tyre width, metres.
    pub tyre_width_m: f64,
    /// The steering actuator.
    pub actuator: SteeringActuator,
}

impl VehicleParams {
    /// Centres of the four wheels' contact patches `[x, y]`, world frame:
    /// rear left, rear right (on the rear axle, at O), front left, front right
    /// (a wheelbase ahead).
    #[must_use]
    pub fn wheel_centres(&self, pose: &Pose2<World>) -> [[f64; 2]; 4] {
        let (s, c) = pose.heading.get().sin_cos();
        let (x, y) = (pose.position.x(), pose.position.y());
        let half = self.track_m / 2.0;
        let l = self.wheelbase.get().get();
        let at = |fwd: f64, left: f64| [x + fwd * c - left * s, y + fwd * s + left * c];
        [at(0.0, half), at(0.0, -half), at(l, half), at(l, -half)]
    }
}

impl VehicleParams {
    /// The vehicle as the core's model describes it: its wheelbase and the
    /// steering actuator's saturation and rate limit.
    #[must_use]
    pub fn bicycle(&self) -> Bicycle {
        Bicycle {
            wheelbase: self.wheelbase,
            max_steering: self.actuator.limit,
            max_steering_rate: RadiansPerSecond::new(self.actuator.rate_limit_rad_s)
                .ok()
                .filter(|r| r.get() > 0.0),
        }
    }
}

/// A simulated vehicle: the core's command in, the true state one control
/// period later out.
pub trait Plant {
    /// The actuation this plant takes.
    fn actuation(&self) -> Actuation;

    /// Advances `state` by `period` seconds in `substeps` sub-steps with
    /// `command` held.
    ///
    /// # Errors
    /// `GD-VEHICLE` for a command of another actuation; the model's
    /// preconditions otherwise.
    fn advance(
        &self,
        state: &VehicleState,
        command: &Command,
        terrain: &Terrain,
        period: f64,
        substeps: u32,
    ) -> Result<VehicleState, Precondition>;
}

impl Plant for VehicleParams {
    fn actuation(&self) -> Actuation {
        Actuation::Bicycle
    }

    fn advance(
        &self,
        state: &VehicleState,
        command: &Command,
        terrain: &Terrain,
        period: f64,
        substeps: u32,
    ) -> Result<VehicleState, Precondition> {
        match *command {
            Command::Bicycle { speed, steering } => step(
                self,
                state,
                steering.get(),
                speed,
                terrain,
                period,
                substeps,
            ),
            _ => Err(Precondition::new(
                "GD-VEHICLE",
                "the bicycle plant takes bicycle commands only",
            )),
        }
    }
}

/// A differential robot (Guyonneau 2022, section 4.1.1): two wheels `track_m`
/// apart, each following its commanded speed with a first-order lag of time
/// constant `time_constant_s`, saturated to `max_wheel_speed`; O (the middle
/// of the axle) moves as the unicycle of the actual wheel speeds, integrated
/// exactly over each sub-step (an arc). The ground does not slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DifferentialPlant {
    /// Distance between the wheels, m (> 0).
    pub track_m: f64,
    /// Time constant of each wheel's speed, s (0: none).
    pub time_constant_s: f64,
    /// Largest wheel speed, m/s (> 0).
    pub max_wheel_speed: f64,
}

impl Plant for DifferentialPlant {
    fn actuation(&self) -> Actuation {
        Actuation::Differential
    }

    fn advance(
        &self,
        state: &VehicleState,
        command: &Command,
        _terrain: &Terrain,
        period: f64,
        substeps: u32,
    ) -> Result<VehicleState, Precondition> {
        let Command::Differential { left, right } = *command else {
            return Err(Precondition::new(
                "GD-VEHICLE",
                "the differential plant takes differential commands only",
            ));
        };
        let n = substeps.max(1);
        let h = period / f64::from(n);
        let max = self.max_wheel_speed;
        let (target_l, target_r) = (left.get().clamp(-max, max), right.get().clamp(-max, max));
        let track = self.track_m;
        two_sides(
            state,
            (target_l, target_r),
            lag_keep(self.time_constant_s, h),
            (h, n),
            |l, r| (0.5 * (l + r), (r - l) / track),
        )
    }
}

/// e^{−h/τ}: the share of a first-order lag's error kept over `h` seconds
/// (0 without lag).
fn lag_keep(time_constant_s: f64, h: f64) -> f64 {
    if time_constant_s > 0.0 {
        (-h / time_constant_s).exp()
    } else {
        0.0
    }
}

/// `n` sub-steps of `h` seconds of a vehicle on two wheels or tracks: each
/// side's speed follows its target with a first-order lag (`keep` of the
/// error kept per sub-step), and O moves on the arc of the speed and yaw
/// rate that `motion` makes of the sides' actual speeds, integrated exactly
/// (the chord of the arc along the mean heading).
fn two_sides(
    state: &VehicleState,
    (target_l, target_r): (f64, f64),
    keep: f64,
    (h, n): (f64, u32),
    motion: impl Fn(f64, f64) -> (f64, f64),
) -> Result<VehicleState, Precondition> {
    let mut next = *state;
    for _ in 0..n {
        let (l, r) = next.wheel_speeds;
        let (l, r) = (
            target_l + (l - target_l) * keep,
            target_r + (r - target_r) * keep,
        );
        next.wheel_speeds = (l, r);
        let (v, w) = motion(l, r);
        let p = next.pose;
        let (x, y, th) = (p.position.x(), p.position.y(), p.heading.get());
        let turn = w * h;
        // The chord of the arc: its length 2 sin(turn/2)/w, along the mean
        // heading (exactly v h straight ahead when w = 0).
        let chord = if turn.abs() < 1e-9 {
            v * h
        } else {
            2.0 * v * (turn / 2.0).sin() / w
        };
        let mid = th + turn / 2.0;
        next.pose = Pose2::new(x + chord * mid.cos(), y + chord * mid.sin(), th + turn)?;
        next.distance_m += v.abs() * h;
    }
    Ok(next)
}

/// A tracked (skid-steer) robot (Emmi 2024, section 2): commanded by its
/// linear and angular speed, each track asked for v ∓ ω B/2 (`track_m` B
/// apart), saturated to `max_track_speed`, followed with a first-order lag
/// of time constant `time_constant_s`; the ground delivers each track's
/// speed times 1 − its slip, and the tracks' skidding widens the effective
/// track to `icr_factor` B (χ ≥ 1). O (the middle between the tracks) moves
/// as the unicycle of the delivered speeds, integrated exactly over each
/// sub-step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkidSteerPlant {
    /// Distance between the tracks' centres, m (> 0).
    pub track_m: f64,
    /// Time constant of each track's speed, s (0: none).
    pub time_constant_s: f64,
    /// Largest track speed, m/s (> 0).
    pub max_track_speed: f64,
    /// Longitudinal slip of the left and right tracks, share of their speed.
    pub slip: (f64, f64),
    /// Effective track over geometric track, χ ≥ 1 (1: no skidding).
    pub icr_factor: f64,
}

impl Plant for SkidSteerPlant {
    fn actuation(&self) -> Actuation {
        Actuation::SkidSteer
    }

    fn advance(
        &self,
        state: &VehicleState,
        command: &Command,
        _terrain: &Terrain,
        period: f64,
        substeps: u32,
    ) -> Result<VehicleState, Precondition> {
        let Command::SkidSteer { speed, yaw_rate } = *command else {
            return Err(Precondition::new(
                "GD-VEHICLE",
                "the skid-steer plant takes skid-steer commands only",
            ));
        };
        let n = substeps.max(1);
        let h = period / f64::from(n);
        let max = self.max_track_speed;
        let half = 0.5 * self.track_m * yaw_rate.get();
        let (target_l, target_r) = (
            (speed.get() - half).clamp(-max, max),
            (speed.get() + half).clamp(-max, max),
        );
        let width = self.track_m * self.icr_factor.max(1.0);
        let slip = self.slip;
        two_sides(
            state,
            (target_l, target_r),
            lag_keep(self.time_constant_s, h),
            (h, n),
            |l, r| {
                let (dl, dr) = (l * (1.0 - slip.0), r * (1.0 - slip.1));
                (0.5 * (dl + dr), (dr - dl) / width)
            },
        )
    }
}

/// A four-wheel-steering robot (Iberraken 2022, section 2.2.1): a bicycle
/// steered at both ends, each axle's angle following its command through its
/// own [`SteeringActuator`] (lag, rate limit, saturation), the pose of R
/// integrated by RK4 sub-steps of the core's `model::four_ws::world_rates`
/// with the terrain's sideslip at the sub-step's start (low grip).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourWsPlant {
    /// The wheelbase L, R to F.
    pub wheelbase: Wheelbase,
    /// The front steering actuator.
    pub front: SteeringActuator,
    /// The rear steering actuator.
    pub rear: SteeringActuator,
}

impl Plant for FourWsPlant {
    fn actuation(&self) -> Actuation {
        Actuation::FourWheelSteering
    }

    fn advance(
        &self,
        state: &VehicleState,
        command: &Command,
        terrain: &Terrain,
        period: f64,
        substeps: u32,
    ) -> Result<VehicleState, Precondition> {
        let Command::FourWheelSteering { speed, front, rear } = *command else {
            return Err(Precondition::new(
                "GD-VEHICLE",
                "the four-wheel-steering plant takes four-wheel-steering commands only",
            ));
        };
        let n = substeps.max(1);
        let h = period / f64::from(n);
        let mut next = *state;
        for _ in 0..n {
            next.steering = self.front.advance(next.steering, front.get(), h);
            next.rear_steering = self.rear.advance(next.rear_steering, rear.get(), h);
            let p = next.pose;
            next.sideslip = terrain.sideslip_at(p.position.x(), p.position.y());
            let (f, r, slip) = (
                Radians::new(next.steering)?,
                Radians::new(next.rear_steering)?,
                next.sideslip,
            );
            let rates = |q: &Pose2<World>| {
                fieldguide::model::four_ws::world_rates(q, speed, f, r, slip, self.wheelbase)
            };
            next.pose = rk4_with(&p, h, rates)?;
            next.distance_m += speed.get().abs() * h;
        }
        Ok(next)
    }
}

/// One RK4 step of length `h` of the world-frame rates `f`.
fn rk4_with(
    pose: &Pose2<World>,
    h: f64,
    f: impl Fn(&Pose2<World>) -> Result<fieldguide::model::bicycle::WorldRates, Precondition>,
) -> Result<Pose2<World>, Precondition> {
    let (x, y, th) = (pose.position.x(), pose.position.y(), pose.heading.get());
    let shift = |k: &fieldguide::model::bicycle::WorldRates, a: f64| {
        Pose2::<World>::new(x + a * k.x_dot, y + a * k.y_dot, th + a * k.heading_dot)
    };
    let k1 = f(pose)?;
    let k2 = f(&shift(&k1, h / 2.0)?)?;
    let k3 = f(&shift(&k2, h / 2.0)?)?;
    let k4 = f(&shift(&k3, h)?)?;
    let w = h / 6.0;
    Pose2::new(
        x + w * (k1.x_dot + 2.0 * k2.x_dot + 2.0 * k3.x_dot + k4.x_dot),
        y + w * (k1.y_dot + 2.0 * k2.y_dot + 2.0 * k3.y_dot + k4.y_dot),
        th + w * (k1.heading_dot + 2.0 * k2.heading_dot + 2.0 * k3.heading_dot + k4.heading_dot),
    )
}

/// The true state of the vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleState {
    /// Pose of the middle of the rear axle O, world frame.
    pub pose: Pose2<World>,
    /// Actual steering angle δ, radians, positive to the left (the front
    /// angle δ_F of a four-wheel-steering robot).
    pub steering: f64,
    /// Actual rear steering angle δ_R of a four-wheel-steering robot,
    /// radians (0 for the other vehicles).
    pub rear_steering: f64,
    /// The sideslip acting at the start of the last sub-step.
    pub sideslip: Sideslip,
    /// Distance travelled by O since the start, metres.
    pub distance_m: f64,
    /// Actual left and right wheel speeds of a differential robot, m/s (0
    /// for the other vehicles).
    pub wheel_speeds: (f64, f64),
}

impl VehicleState {
    /// The state at rest pose `pose`, wheels straight, sideslip of the terrain there.
    #[must_use]
    pub fn at(pose: Pose2<World>, terrain: &Terrain) -> Self {
        Self {
            pose,
            steering: 0.0,
            rear_steering: 0.0,
            sideslip: terrain.sideslip_at(pose.position.x(), pose.position.y()),
            distance_m: 0.0,
            wheel_speeds: (0.0, 0.0),
        }
    }
}

/// Advances the vehicle by `period` seconds in `substeps` equal sub-steps with
/// `command` (radians) held and constant `speed`. In each sub-step the steering
/// actuator moves first, then the pose is integrated by RK4 with that steering
/// and the sideslip of the terrain at the sub-step's start.
///
/// Errors: the core's preconditions (`PT-STEER-DOMAIN` when δ + β_F reaches
/// ±π/2, `LIB-FINITE` on overflow).
pub fn step(
    params: &VehicleParams,
    state: &VehicleState,
    command: f64,
    speed: MetersPerSecond,
    terrain: &Terrain,
    period: f64,
    substeps: u32,
) -> Result<VehicleState, Precondition> {
    let n = substeps.max(1);
    let h = period / f64::from(n);
    let mut next = *state;
    for _ in 0..n {
        next.steering = params.actuator.advance(next.steering, command, h);
        let p = next.pose;
        next.sideslip = terrain.sideslip_at(p.position.x(), p.position.y());
        next.pose = rk4(
            params,
            &p,
            Radians::new(next.steering)?,
            next.sideslip,
            speed,
            h,
        )?;
        next.distance_m += speed.get().abs() * h;
    }
    Ok(next)
}

/// One RK4 step of length `h` of the bicycle's world-frame model.
fn rk4(
    params: &VehicleParams,
    pose: &Pose2<World>,
    steering: Radians,
    sideslip: Sideslip,
    speed: MetersPerSecond,
    h: f64,
) -> Result<Pose2<World>, Precondition> {
    rk4_with(pose, h, |p| {
        world_rates(p, speed, steering, sideslip, params.wheelbase)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::terrain::SlipPatch;

    fn params(settling: f64, rate: f64) -> VehicleParams {
        VehicleParams {
            wheelbase: Wheelbase::new(2.0).unwrap(),
            track_m: 1.5,
            tyre_width_m: 0.3,
            actuator: SteeringActuator::from_settling(
                settling,
                rate,
                SteeringLimit::new(0.5).unwrap(),
            ),
        }
    }

    #[test]
    fn actuator_settles_to_95_percent_at_the_settling_time() {
        let a = params(1.0, 100.0).actuator;
        let mut d = 0.0;
        for _ in 0..50 {
            d = a.advance(d, 0.2, 0.02);
        }
        // After T_s = 1 s: 1 − e⁻³ of the step.
        assert!((d - 0.2 * (1.0 - (-3.0_f64).exp())).abs() < 1e-12);
    }

    #[test]
    fn actuator_rate_limit_and_saturation() {
        let a = params(0.0, 0.35).actuator;
        // No lag: moves at the rate limit.
        let d = a.advance(0.0, 0.3, 0.1);
        assert!((d - 0.035).abs() < 1e-12);
        // Saturated command: never beyond the limit.
        let mut d = 0.0;
        for _ in 0..1000 {
            d = a.advance(d, 3.0, 0.02);
            assert!(d <= 0.5);
        }
        assert!((d - 0.5).abs() < 1e-12);
    }

    #[test]
    fn straight_and_circle_without_slip() {
        let p = params(0.0, 100.0);
        let terrain = Terrain::default();
        let v = MetersPerSecond::new(1.0).unwrap();
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        for _ in 0..100 {
            s = step(&p, &s, 0.0, v, &terrain, 0.02, 5).unwrap();
        }
        assert!((s.pose.position.x() - 2.0).abs() < 1e-9 && s.pose.position.y().abs() < 1e-12);
        assert!((s.distance_m - 2.0).abs() < 1e-9);
        // Full lock from rest steering 0 with no lag reaches δ at once: a circle
        // of radius L / tan δ, so after a quarter turn O is at (R, R).
        let delta: f64 = 0.4;
        let r = 2.0 / delta.tan();
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        s.steering = delta;
        let quarter = r * std::f64::consts::FRAC_PI_2;
        let ticks = (quarter / 0.02).round() as u32;
        let period = quarter / f64::from(ticks);
        for _ in 0..ticks {
            s = step(&p, &s, delta, v, &terrain, period, 4).unwrap();
        }
        assert!((s.pose.position.x() - r).abs() < 1e-6, "{:?}", s.pose);
        assert!((s.pose.position.y() - r).abs() < 1e-6);
        assert!((s.pose.heading.get() - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn rear_sideslip_turns_the_velocity() {
        let p = params(0.0, 100.0);
        let beta_r = -0.05;
        let terrain = Terrain {
            base: Sideslip::ZERO,
            patches: vec![SlipPatch {
                name: "wet".into(),
                polygon: vec![[-10.0, -10.0], [10.0, -10.0], [10.0, 10.0], [-10.0, 10.0]],
                sideslip: Sideslip::new(-beta_r, beta_r).unwrap(),
            }],
            ..Terrain::default()
        };
        // Steering straight, β_F = −β_R: tan(β_F) − tan(β_R) = 2 tan|β| gives
        // a yaw rate; with β_F = β_R the yaw rate is zero and O crabs at β_R.
        let crab = Terrain {
            base: Sideslip::new(beta_r, beta_r).unwrap(),
            patches: vec![],
            ..Terrain::default()
        };
        let v = MetersPerSecond::new(1.0).unwrap();
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &crab);
        for _ in 0..50 {
            s = step(&p, &s, 0.0, v, &crab, 0.02, 2).unwrap();
        }
        assert!(s.pose.heading.get().abs() < 1e-12);
        assert!((s.pose.position.y() - beta_r.sin()).abs() < 1e-9);
        assert!((s.pose.position.x() - beta_r.cos()).abs() < 1e-9);
        // On the patch the yaw rate is v cos β_R (tan β_F − tan β_R) / L.
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        s = step(&p, &s, 0.0, v, &terrain, 0.02, 1).unwrap();
        let expected = beta_r.cos() * (2.0 * (-beta_r).tan()) / 2.0 * 0.02;
        assert!((s.pose.heading.get() - expected).abs() < 1e-9);
        assert_eq!(s.sideslip.rear.get(), beta_r);
    }

    #[test]
    fn a_differential_robot_drives_the_arc_of_its_wheel_speeds() {
        let plant = DifferentialPlant {
            track_m: 0.5,
            time_constant_s: 0.0,
            max_wheel_speed: 1.0,
        };
        let terrain = Terrain::default();
        let command = |l: f64, r: f64| Command::Differential {
            left: MetersPerSecond::new(l).unwrap(),
            right: MetersPerSecond::new(r).unwrap(),
        };
        // v = 0.5 m/s, ω = 0.4 rad/s: a circle of 1.25 m; a quarter turn
        // ends at (R, R) heading north, whatever the sub-steps.
        let quarter = std::f64::consts::FRAC_PI_2 / 0.4;
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        for _ in 0..10 {
            s = plant
                .advance(&s, &command(0.4, 0.6), &terrain, quarter / 10.0, 3)
                .unwrap();
        }
        assert!((s.pose.position.x() - 1.25).abs() < 1e-9, "{:?}", s.pose);
        assert!((s.pose.position.y() - 1.25).abs() < 1e-9);
        assert!((s.pose.heading.get() - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        assert!((s.distance_m - 0.5 * quarter).abs() < 1e-9);
        // Backward and saturated: both wheels at −1 m/s.
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        s = plant
            .advance(&s, &command(-3.0, -1.5), &terrain, 1.0, 4)
            .unwrap();
        assert!((s.pose.position.x() + 1.0).abs() < 1e-12 && s.pose.heading.get().abs() < 1e-12);
        // A lag of 0.1 s: after 0.3 s each wheel is at 1 − e⁻³ of its step.
        let lagged = DifferentialPlant {
            time_constant_s: 0.1,
            ..plant
        };
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        for _ in 0..3 {
            s = lagged
                .advance(&s, &command(0.2, 0.4), &terrain, 0.1, 5)
                .unwrap();
        }
        let k = 1.0 - (-3.0_f64).exp();
        assert!((s.wheel_speeds.0 - 0.2 * k).abs() < 1e-12);
        assert!((s.wheel_speeds.1 - 0.4 * k).abs() < 1e-12);
        // Another actuation is refused.
        let bicycle = Command::Bicycle {
            speed: MetersPerSecond::new(1.0).unwrap(),
            steering: Radians::ZERO,
        };
        assert_eq!(
            plant
                .advance(&s, &bicycle, &terrain, 0.1, 1)
                .unwrap_err()
                .requirement,
            "GD-VEHICLE"
        );
    }

    #[test]
    fn a_four_wheel_steering_robot_crabs_and_turns_as_its_two_axles_say() {
        let limit = SteeringLimit::new(0.5).unwrap();
        let plant = FourWsPlant {
            wheelbase: Wheelbase::new(1.2).unwrap(),
            front: SteeringActuator::from_settling(0.0, 1e6, limit),
            rear: SteeringActuator::from_settling(0.0, 1e6, limit),
        };
        let terrain = Terrain::default();
        let s0 = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        let cmd = |f: f64, r: f64| Command::FourWheelSteering {
            speed: MetersPerSecond::new(1.0).unwrap(),
            front: Radians::new(f).unwrap(),
            rear: Radians::new(r).unwrap(),
        };
        // Both axles at 0.2 rad: a crab walk, straight along 0.2 rad, heading kept.
        let s = plant
            .advance(&s0, &cmd(0.2, 0.2), &terrain, 2.0, 200)
            .unwrap();
        assert!((s.pose.heading.get()).abs() < 1e-12);
        assert!((s.pose.position.x() - 2.0 * 0.2_f64.cos()).abs() < 1e-9);
        assert!((s.pose.position.y() - 2.0 * 0.2_f64.sin()).abs() < 1e-9);
        assert_eq!((s.steering, s.rear_steering), (0.2, 0.2));
        // Opposite angles: yaw rate v cos(δ_R)(tan δ_F − tan δ_R)/L.
        let s = plant
            .advance(&s0, &cmd(0.2, -0.2), &terrain, 0.5, 100)
            .unwrap();
        let rate = 0.2_f64.cos() * 2.0 * 0.2_f64.tan() / 1.2;
        assert!((s.pose.heading.get() - 0.5 * rate).abs() < 1e-9);
        // Saturation, and the rate limit on a slow actuator.
        let slow = FourWsPlant {
            rear: SteeringActuator::from_settling(0.0, 0.1, limit),
            ..plant
        };
        let s = slow
            .advance(&s0, &cmd(0.9, 0.9), &terrain, 1.0, 10)
            .unwrap();
        assert!((s.steering - 0.5).abs() < 1e-12);
        assert!((s.rear_steering - 0.1).abs() < 1e-12);
        // Another actuation is refused.
        let diff = Command::Differential {
            left: MetersPerSecond::new(1.0).unwrap(),
            right: MetersPerSecond::new(1.0).unwrap(),
        };
        assert_eq!(
            plant
                .advance(&s0, &diff, &terrain, 0.1, 1)
                .unwrap_err()
                .requirement,
            "GD-VEHICLE"
        );
    }

    #[test]
    fn wheel_centres_follow_the_pose() {
        let p = params(0.0, 1.0);
        let w = p.wheel_centres(&Pose2::new(1.0, 1.0, std::f64::consts::FRAC_PI_2).unwrap());
        // Heading north: left is west.
        assert!((w[0][0] - 0.25).abs() < 1e-12 && (w[0][1] - 1.0).abs() < 1e-12);
        assert!((w[1][0] - 1.75).abs() < 1e-12);
        assert!((w[2][1] - 3.0).abs() < 1e-12 && (w[3][0] - 1.75).abs() < 1e-12);
    }
    #[test]
    fn a_tracked_robot_drives_the_arc_of_its_delivered_track_speeds() {
        let plant = SkidSteerPlant {
            track_m: 0.8,
            time_constant_s: 0.0,
            max_track_speed: 1.0,
            slip: (0.0, 0.0),
            icr_factor: 1.0,
        };
        let terrain = Terrain::default();
        let command = |v: f64, w: f64| Command::SkidSteer {
            speed: MetersPerSecond::new(v).unwrap(),
            yaw_rate: RadiansPerSecond::new(w).unwrap(),
        };
        // v = 0.5 m/s, ω = 0.4 rad/s: tracks at 0.34 and 0.66 m/s, a circle
        // of 1.25 m; a quarter turn ends at (R, R) heading north.
        let quarter = std::f64::consts::FRAC_PI_2 / 0.4;
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        for _ in 0..10 {
            s = plant
                .advance(&s, &command(0.5, 0.4), &terrain, quarter / 10.0, 3)
                .unwrap();
        }
        assert!((s.wheel_speeds.0 - 0.34).abs() < 1e-12);
        assert!((s.wheel_speeds.1 - 0.66).abs() < 1e-12);
        assert!((s.pose.position.x() - 1.25).abs() < 1e-9, "{:?}", s.pose);
        assert!((s.pose.position.y() - 1.25).abs() < 1e-9);
        assert!((s.pose.heading.get() - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        // A turn in place beyond the limit: each track saturated at 1 m/s,
        // so ω = 2 / 0.8 = 2.5 rad/s instead of 4.
        let s = plant
            .advance(
                &VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain),
                &command(0.0, 4.0),
                &terrain,
                0.1,
                1,
            )
            .unwrap();
        assert!((s.pose.heading.get() - 0.25).abs() < 1e-12);
        assert!(s.pose.position.x().abs() < 1e-12);
        // Slip of 10 % on the right track and a wider effective track
        // (χ = 1.25): straight ahead at 1 m/s becomes v = 0.95 m/s and
        // ω = −0.1 / 1.0 rad/s, the robot drifting right.
        let slipping = SkidSteerPlant {
            slip: (0.0, 0.1),
            icr_factor: 1.25,
            ..plant
        };
        let s = slipping
            .advance(
                &VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain),
                &command(1.0, 0.0),
                &terrain,
                1.0,
                1,
            )
            .unwrap();
        assert!((s.pose.heading.get() + 0.1).abs() < 1e-12);
        assert!((s.distance_m - 0.95).abs() < 1e-12);
        // A lag of 0.1 s: after 0.3 s each track is at 1 − e⁻³ of its step.
        let lagged = SkidSteerPlant {
            time_constant_s: 0.1,
            ..plant
        };
        let mut s = VehicleState::at(Pose2::new(0.0, 0.0, 0.0).unwrap(), &terrain);
        for _ in 0..3 {
            s = lagged
                .advance(&s, &command(0.5, 0.0), &terrain, 0.1, 5)
                .unwrap();
        }
        let k = 1.0 - (-3.0_f64).exp();
        assert!((s.wheel_speeds.0 - 0.5 * k).abs() < 1e-12);
        // Another actuation is refused.
        let wheels = Command::Differential {
            left: MetersPerSecond::new(1.0).unwrap(),
            right: MetersPerSecond::new(1.0).unwrap(),
        };
        assert_eq!(
            plant
                .advance(&s, &wheels, &terrain, 0.1, 1)
                .unwrap_err()
                .requirement,
            "GD-VEHICLE"
        );
    }
}
