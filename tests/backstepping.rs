//! Example and property tests of the extended kinematic model (Pierre 2022,
//! eq. 1) and the backstepping law (eqs. 2-7): `spec/pierre2022.md`, PT-*.
#![allow(clippy::unwrap_used, clippy::indexing_slicing, clippy::float_cmp)]

use approx::assert_relative_eq;
use fieldguide::control::backstepping::{
    steering_command, target_angular_deviation, yaw_rate_objective, BacksteppingConfig, Gains,
    Inversion, SpeedSchedule,
};
use fieldguide::control::ControlLaw;
use fieldguide::model::bicycle::{
    frenet_rates, yaw_rate, Bicycle, Sideslip, SteeringLimit, Wheelbase,
};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Radians, RadiansPerSecond, Seconds, TrackingError,
};
use proptest::prelude::*;

fn tracking(y: f64, theta: f64, c: f64, c_ahead: f64) -> TrackingError {
    TrackingError {
        y: Meters::new(y).unwrap(),
        angular_deviation: Radians::new(theta).unwrap(),
        curvature: Curvature::new(c).unwrap(),
        curvature_ahead: Curvature::new(c_ahead).unwrap(),
    }
}

fn config(k_y: f64, k_theta: f64, inversion: Inversion) -> BacksteppingConfig {
    BacksteppingConfig {
        gains: Gains::new(k_y, k_theta, 1.0).unwrap(),
        vehicle: Bicycle::new(
            Wheelbase::new(2.0).unwrap(),
            SteeringLimit::new(1.5).unwrap(),
            None,
        )
        .unwrap(),
        inversion,
        schedule: None,
    }
}

fn speed(v: f64) -> MetersPerSecond {
    MetersPerSecond::new(v).unwrap()
}

/// Inputs inside the law's domain: |y c| < 1, |θ̃₂| < π/2, v > 0, |β| small.
fn in_domain() -> impl Strategy<Value = (f64, f64, f64, f64, f64, f64, f64, f64)> {
    (
        -2.0..2.0f64,   // y
        -1.0..1.0f64,   // θ̃
        -0.4..0.4f64,   // c
        -0.4..0.4f64,   // c(s + vT)
        -0.2..0.2f64,   // β_F
        -0.2..0.2f64,   // β_R
        -3.0..-0.05f64, // k_y
        0.1..8.0f64,    // speed
    )
}

/// A hand computation from the formulas of eqs. 3, 5, 6 and 7 (done
/// independently in Python with the same inputs): L = 2 m, k_y = −0.5,
/// k_θ = −2, y = 0.1 m, θ̃ = 0.05 rad, c = 0.1, c(s+vT) = 0.12, β_F = 0.02,
/// β_R = 0.03, v = 0.8 m/s.
//= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
//= type=test
//# The steering angle MUST be
//# δ = arctan(tan β_R + L [k_θ e + c(s + vT)] cos θ̃₂ / ((1 − y c(s)) cos β_R)) − β_F
//# in the exact reading, the library's default.
//= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
//= type=test
//# The law as printed in eq. 6, without the factor cos θ̃₂ / cos β_R, SHOULD be
//# available as an explicit option for comparison with the paper.
//= spec/pierre2022.md#pt-target-target-angular-deviation
//= type=test
//# The target angular deviation MUST be
//# θ̃_obj = arctan(k_y y / (1 − y c(s))) − β_R.
//= spec/pierre2022.md#pt-yaw-objective-yaw-rate-objective
//= type=test
//# The yaw-rate objective MUST be u_θ^obj = [k_θ e + c(s + vT)] v cos θ̃₂ / (1 − y c(s)),
//# with e = θ̃ − θ̃_obj.
#[test]
fn hand_computed_example() {
    let error = tracking(0.1, 0.05, 0.1, 0.12);
    let slip = Sideslip::new(0.02, 0.03).unwrap();
    let exact = steering_command(
        &config(-0.5, -2.0, Inversion::Exact),
        &error,
        slip,
        speed(0.8),
    )
    .unwrap();
    let printed = steering_command(
        &config(-0.5, -2.0, Inversion::Printed),
        &error,
        slip,
        speed(0.8),
    )
    .unwrap();
    assert_relative_eq!(
        exact.target_angular_deviation.get(),
        -0.080_462_174_016_855_85,
        epsilon = 1e-12
    );
    assert_relative_eq!(
        exact.steering.get(),
        -0.268_649_496_169_632_35,
        epsilon = 1e-12
    );
    assert_relative_eq!(
        printed.steering.get(),
        -0.269_384_739_917_258_75,
        epsilon = 1e-12
    );
    assert_relative_eq!(
        exact.yaw_rate_objective.get(),
        -0.113_514_044_912_798_4,
        epsilon = 1e-12
    );
    assert!(!exact.saturated);
}

//= spec/pierre2022.md#pt-gains-gain-sign-and-ratio
//= type=test
//# Both gains MUST be finite and strictly negative (convergent in equation
//# form), and |k_θ| MUST be at least a configured ratio r ≥ 1 times |k_y|;
//# other gains MUST be refused at construction.
#[test]
fn gains_are_validated_once() {
    assert!(Gains::new(-0.7, -1.4, 2.0).is_ok());
    for (k_y, k_theta) in [(0.7, -1.4), (-0.7, 1.4), (0.0, -1.0), (-0.7, f64::NAN)] {
        assert_eq!(
            Gains::new(k_y, k_theta, 1.0).unwrap_err().requirement,
            "PT-GAINS-SIGN"
        );
    }
    assert_eq!(
        Gains::new(-0.7, -1.0, 2.0).unwrap_err().requirement,
        "PT-GAINS-RATIO"
    );
    assert_eq!(
        Gains::new(-0.7, -1.4, 0.5).unwrap_err().requirement,
        "PT-GAINS-RATIO"
    );
    assert_eq!(
        Gains::new(-0.7, -1.4, f64::INFINITY)
            .unwrap_err()
            .requirement,
        "PT-GAINS-RATIO"
    );
}

//= spec/pierre2022.md#pt-denom-robot-inside-the-radius-of-curvature
//= type=test
//# Where 1 − y c(s) ≤ 0 the model and the law MUST return the `PT-DENOM`
//# error instead of a value.
//= spec/pierre2022.md#pt-heading-robot-heading-along-the-path
//= type=test
//# Where cos θ̃₂ ≤ 0 the model and the law MUST return the `PT-HEADING` error
//# instead of a value.
//= spec/pierre2022.md#pt-speed-forward-speed
//= type=test
//# Where v ≤ 0 the law MUST return the `PT-SPEED` error instead of a value.
//= spec/pierre2022.md#pt-sideslip-sideslip-angles-below-a-right-angle
//= type=test
//# The sideslip angles β_F and β_R MUST satisfy |β| < π/2; a larger angle
//# MUST be the `PT-SIDESLIP` error.
//= spec/pierre2022.md#pt-wheelbase-positive-wheelbase
//= type=test
//# The wheelbase L MUST be finite and strictly positive.
#[test]
fn preconditions_name_their_requirement() {
    let cfg = config(-0.7, -1.4, Inversion::Exact);
    let law = |e: TrackingError, s: Sideslip, v: f64| {
        steering_command(&cfg, &e, s, speed(v))
            .unwrap_err()
            .requirement
    };
    // 1 − y c = 0 and < 0.
    assert_eq!(
        law(tracking(2.0, 0.0, 0.5, 0.5), Sideslip::ZERO, 1.0),
        "PT-DENOM"
    );
    assert_eq!(
        law(tracking(3.0, 0.0, 0.5, 0.5), Sideslip::ZERO, 1.0),
        "PT-DENOM"
    );
    // cos θ̃₂ = 0 and < 0.
    let right_angle = core::f64::consts::FRAC_PI_2;
    assert_eq!(
        law(tracking(0.0, right_angle, 0.0, 0.0), Sideslip::ZERO, 1.0),
        "PT-HEADING"
    );
    assert_eq!(
        law(tracking(0.0, 2.5, 0.0, 0.0), Sideslip::ZERO, 1.0),
        "PT-HEADING"
    );
    let slip = Sideslip::new(0.0, 0.3).unwrap();
    assert_eq!(
        law(tracking(0.0, right_angle - 0.2, 0.0, 0.0), slip, 1.0),
        "PT-HEADING"
    );
    // v = 0 and v < 0.
    assert_eq!(
        law(tracking(0.1, 0.0, 0.0, 0.0), Sideslip::ZERO, 0.0),
        "PT-SPEED"
    );
    assert_eq!(
        law(tracking(0.1, 0.0, 0.0, 0.0), Sideslip::ZERO, -1.0),
        "PT-SPEED"
    );
    assert_eq!(
        Sideslip::new(1.6, 0.0).unwrap_err().requirement,
        "PT-SIDESLIP"
    );
    assert_eq!(Wheelbase::new(0.0).unwrap_err().requirement, "PT-WHEELBASE");
    assert_eq!(
        Wheelbase::new(f64::NAN).unwrap_err().requirement,
        "PT-WHEELBASE"
    );
    let e = tracking(0.1, 0.0, 0.0, 0.0);
    assert_eq!(
        frenet_rates(
            &e,
            speed(0.0),
            Radians::ZERO,
            Sideslip::ZERO,
            cfg.vehicle.wheelbase
        )
        .unwrap_err()
        .requirement,
        "PT-SPEED"
    );
}

//= spec/pierre2022.md#pt-steer-domain-steering-within-the-domain-of-the-model
//= type=test
//# Where |δ + β_F| ≥ π/2 the model MUST return the `PT-STEER-DOMAIN` error
//# instead of a value.
#[test]
fn model_refuses_steering_beyond_a_right_angle() {
    let r = yaw_rate(
        speed(1.0),
        Radians::new(1.5).unwrap(),
        Sideslip::new(0.1, 0.0).unwrap(),
        Wheelbase::new(2.0).unwrap(),
    );
    assert_eq!(r.unwrap_err().requirement, "PT-STEER-DOMAIN");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Step 1: with θ̃ = θ̃_obj, the first row of eq. 1 gives y' = k_y y (eq. 2).
    //= spec/pierre2022.md#pt-target-target-angular-deviation
    //= type=test
    //# The target angular deviation MUST be
    //# θ̃_obj = arctan(k_y y / (1 − y c(s))) − β_R.
    //= spec/pierre2022.md#pt-model-extended-kinematic-model-with-sideslip
    //= type=test
    //# The model MUST give y' = (1 − y c(s)) tan θ̃₂ and
    //# θ̃' = u_θ (1 − y c(s)) / (v cos θ̃₂) − c(s), with θ̃₂ = θ̃ + β_R.
    #[test]
    fn target_deviation_gives_exponential_lateral_convergence(
        (y, _theta, c, _c_ahead, beta_f, beta_r, k_y, v) in in_domain()
    ) {
        prop_assume!(1.0 - y * c > 0.05);
        let gains = Gains::new(k_y, 2.0 * k_y, 2.0).unwrap();
        let slip = Sideslip::new(beta_f, beta_r).unwrap();
        let target = target_angular_deviation(&gains, &tracking(y, 0.0, c, c), slip).unwrap();
        let at_target = tracking(y, target.get(), c, c);
        let rates = frenet_rates(&at_target, speed(v), Radians::ZERO, slip,
            Wheelbase::new(2.0).unwrap()).unwrap();
        prop_assert!((rates.y - k_y * y).abs() <= 1e-9 * (1.0 + (k_y * y).abs()));
    }

    /// Step 2: the exact law put into eq. 1 gives the yaw rate of eq. 5 and so
    /// θ̃' = k_θ e + c(s + vT) − c(s), which is e' = k_θ e − θ̃_obj' with no look-ahead.
    //= spec/pierre2022.md#pt-yaw-rate-yaw-rate-of-the-model
    //= type=test
    //# The yaw rate MUST be u_θ = v cos β_R (tan(δ + β_F) − tan β_R) / L.
    //= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
    //= type=test
    //# The steering angle MUST be
    //# δ = arctan(tan β_R + L [k_θ e + c(s + vT)] cos θ̃₂ / ((1 − y c(s)) cos β_R)) − β_F
    //# in the exact reading, the library's default.
    //= spec/pierre2022.md#pt-feedforward-curvature-feed-forward
    //= type=test
    //# The law MUST feed forward the curvature c(s + vT) in the numerator and use
    //# 1 − y c(s) in the denominator.
    #[test]
    fn exact_law_closes_the_angular_loop(
        (y, theta, c, c_ahead, beta_f, beta_r, k_y, v) in in_domain()
    ) {
        prop_assume!(1.0 - y * c > 0.05 && (theta + beta_r).cos() > 0.05);
        let cfg = config(k_y, 3.0 * k_y, Inversion::Exact);
        let slip = Sideslip::new(beta_f, beta_r).unwrap();
        let error = tracking(y, theta, c, c_ahead);
        let cmd = steering_command(&cfg, &error, slip, speed(v)).unwrap();
        prop_assume!(!cmd.saturated);
        let u = yaw_rate(speed(v), cmd.steering, slip, cfg.vehicle.wheelbase).unwrap();
        let u_obj = yaw_rate_objective(&cfg.gains, &error, slip, speed(v)).unwrap();
        prop_assert!((u.get() - u_obj.get()).abs() <= 1e-9 * (1.0 + u_obj.get().abs()));
        let rates = frenet_rates(&error, speed(v), cmd.steering, slip, cfg.vehicle.wheelbase).unwrap();
        let e = theta - cmd.target_angular_deviation.get();
        let wanted = cfg.gains.k_theta() * e + c_ahead - c;
        prop_assert!((rates.angular_deviation - wanted).abs() <= 1e-8 * (1.0 + wanted.abs()),
            "theta' = {} but k_theta e + c_ahead - c = {}", rates.angular_deviation, wanted);
    }

    /// The printed law misses k_θ e by exactly (k_θ e + c)(cos β_R / cos θ̃₂ − 1),
    /// below 0.6 % of |k_θ e + c| when |θ̃₂|, |β_R| ≤ 0.1 rad.
    //= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
    //= type=test
    //# The law as printed in eq. 6, without the factor cos θ̃₂ / cos β_R, SHOULD be
    //# available as an explicit option for comparison with the paper.
    #[test]
    fn printed_law_is_exact_only_for_small_angles(
        (y, theta, c, _c_ahead, beta_f, beta_r, k_y, v) in in_domain()
    ) {
        prop_assume!(1.0 - y * c > 0.05 && (theta + beta_r).cos() > 0.05);
        let cfg = config(k_y, 3.0 * k_y, Inversion::Printed);
        let slip = Sideslip::new(beta_f, beta_r).unwrap();
        let error = tracking(y, theta, c, c);
        let cmd = steering_command(&cfg, &error, slip, speed(v)).unwrap();
        prop_assume!(!cmd.saturated);
        let rates = frenet_rates(&error, speed(v), cmd.steering, slip, cfg.vehicle.wheelbase).unwrap();
        let drive = cfg.gains.k_theta() * (theta - cmd.target_angular_deviation.get()) + c;
        let theta2 = theta + beta_r;
        let miss = drive * (beta_r.cos() / theta2.cos() - 1.0);
        let got = rates.angular_deviation - (drive - c);
        prop_assert!((got - miss).abs() <= 1e-8 * (1.0 + drive.abs()));
        if theta2.abs() <= 0.1 && beta_r.abs() <= 0.1 {
            prop_assert!(got.abs() <= 0.006 * drive.abs() + 1e-12);
        }
    }

    /// β = 0 reduces the law to the classical one, δ = arctan(L [k_θ e + c] cos θ̃ / (1 − y c)).
    //= spec/pierre2022.md#pt-steering-steering-law-with-sideslip-compensation
    //= type=test
    //# The steering angle MUST be
    //# δ = arctan(tan β_R + L [k_θ e + c(s + vT)] cos θ̃₂ / ((1 − y c(s)) cos β_R)) − β_F
    //# in the exact reading, the library's default.
    #[test]
    fn zero_sideslip_gives_the_classical_law(
        (y, theta, c, c_ahead, _bf, _br, k_y, v) in in_domain()
    ) {
        prop_assume!(1.0 - y * c > 0.05 && theta.cos() > 0.05);
        let cfg = config(k_y, 2.0 * k_y, Inversion::Exact);
        let cmd = steering_command(&cfg, &tracking(y, theta, c, c_ahead), Sideslip::ZERO, speed(v))
            .unwrap();
        let alpha = 1.0 - y * c;
        let e = theta - (k_y * y / alpha).atan();
        let classical = (2.0 * (2.0 * k_y * e + c_ahead) * theta.cos() / alpha).atan();
        let classical = classical.clamp(-1.5, 1.5);
        prop_assert!((cmd.steering.get() - classical).abs() <= 1e-12);
    }

    /// Mirror symmetry: y, θ̃, c and β negated give −δ; and |δ| ≤ δ_max always.
    //= spec/library.md#lib-frames-frames-and-sign-conventions
    //= type=test
    //# The lateral error y MUST be positive when the robot is left of the path, the
    //# path curvature MUST be positive for a left turn, and the steering angle MUST
    //# be positive to the left.
    //= spec/pierre2022.md#pt-saturation-steering-saturation
    //= type=test
    //# The steering command MUST lie within [−δ_max, δ_max]; a law output
    //# beyond it MUST be clamped to the nearer bound and reported as saturated.
    #[test]
    fn mirror_symmetry_and_saturation(
        (y, theta, c, c_ahead, beta_f, beta_r, k_y, v) in in_domain(),
        limit in 0.05..1.5f64,
        printed in any::<bool>(),
    ) {
        prop_assume!(1.0 - y * c > 0.0 && (theta + beta_r).cos() > 0.0);
        let mut cfg = config(k_y, 2.0 * k_y,
            if printed { Inversion::Printed } else { Inversion::Exact });
        cfg.vehicle.max_steering = SteeringLimit::new(limit).unwrap();
        let slip = Sideslip::new(beta_f, beta_r).unwrap();
        let error = tracking(y, theta, c, c_ahead);
        let cmd = steering_command(&cfg, &error, slip, speed(v)).unwrap();
        let mirror = steering_command(&cfg, &error.mirrored(), slip.mirrored(), speed(v)).unwrap();
        prop_assert!((cmd.steering.get() + mirror.steering.get()).abs() <= 1e-12);
        prop_assert!(cmd.steering.get().abs() <= limit);
        prop_assert_eq!(cmd.saturated, mirror.saturated);
        if cmd.saturated {
            prop_assert!((cmd.steering.get().abs() - limit).abs() <= 0.0);
        }
    }

    /// Any f64, NaN and infinities included, gives a finite value or an error.
    //= spec/library.md#lib-no-panic-no-panic
    //= type=test
    //# The core MUST NOT panic for any input: a function whose domain is restricted
    //# MUST return `Result<_, Precondition>` naming the requirement it protects.
    //= spec/library.md#lib-finite-no-nan-or-infinity
    //= type=test
    //# A value returned by the core MUST be finite: a computation whose result
    //# would be NaN or infinite MUST return a `Precondition` error instead.
    //= spec/library.md#lib-units-typed-quantities
    //= type=test
    //# Constructors of unit types MUST reject NaN and infinite values with a
    //# `Precondition` error.
    #[test]
    fn any_input_gives_a_value_or_an_error(
        raw in proptest::collection::vec(proptest::num::f64::ANY, 11),
    ) {
        let build = || -> Result<_, fieldguide::Precondition> {
            let error = TrackingError {
                y: Meters::new(raw[0])?,
                angular_deviation: Radians::new(raw[1])?,
                curvature: Curvature::new(raw[2])?,
                curvature_ahead: Curvature::new(raw[3])?,
            };
            let slip = Sideslip::new(raw[4], raw[5])?;
            let cfg = BacksteppingConfig {
                gains: Gains::new(raw[6], raw[7], 1.0)?,
                vehicle: Bicycle::new(Wheelbase::new(raw[8])?, SteeringLimit::new(raw[9])?, None)?,
                inversion: Inversion::Exact,
                schedule: None,
            };
            let v = MetersPerSecond::new(raw[10])?;
            let cmd = steering_command(&cfg, &error, slip, v)?;
            let rates = frenet_rates(&error, v, cmd.steering, slip, cfg.vehicle.wheelbase)?;
            Ok((cmd, rates))
        };
        if let Ok((cmd, rates)) = build() {
            prop_assert!(cmd.steering.get().is_finite());
            prop_assert!(cmd.target_angular_deviation.get().is_finite());
            prop_assert!(cmd.yaw_rate_objective.get().is_finite());
            prop_assert!(rates.y.is_finite() && rates.angular_deviation.is_finite());
        }
    }
}

proptest! {
    /// The world-frame form moves O at heading + β_R, and on a straight path it
    /// reproduces the first row of eq. 1: (dy/dt) / (ds/dt) = tan θ̃₂.
    //= spec/pierre2022.md#pt-model-extended-kinematic-model-with-sideslip
    //= type=test
    //# The velocity of the controlled point O MUST point at the heading plus β_R.
    #[test]
    fn world_velocity_points_at_heading_plus_rear_sideslip(
        heading in -3.1..3.1f64,
        (beta_f, beta_r) in (-0.3..0.3f64, -0.3..0.3f64),
        steering in -0.5..0.5f64,
        v in 0.1..5.0f64,
    ) {
        let pose = fieldguide::Pose2::<fieldguide::World>::new(1.0, 2.0, heading).unwrap();
        let slip = Sideslip::new(beta_f, beta_r).unwrap();
        let wheelbase = Wheelbase::new(2.0).unwrap();
        let steer = Radians::new(steering).unwrap();
        let rates = fieldguide::model::bicycle::world_rates(&pose, speed(v), steer, slip, wheelbase)
            .unwrap();
        let course = rates.y_dot.atan2(rates.x_dot);
        let wrap = |a: f64| fieldguide::geometry::units::wrap_angle(Radians::new(a).unwrap()).get();
        let wanted = wrap(heading + beta_r);
        prop_assert!(wrap(course - wanted).abs() < 1e-12);
        prop_assert!((rates.x_dot.hypot(rates.y_dot) - v).abs() < 1e-12);
        prop_assert!((rates.heading_dot - yaw_rate(speed(v), steer, slip, wheelbase).unwrap().get())
            .abs() < 1e-15);
        // Path = the world x axis: s grows with x, y with y, θ̃ = heading.
        prop_assume!((heading + beta_r).cos() > 0.05);
        let rates_s = frenet_rates(&tracking(0.3, heading, 0.0, 0.0), speed(v), steer, slip, wheelbase)
            .unwrap();
        prop_assert!((rates.y_dot / rates.x_dot - rates_s.y).abs() < 1e-9 * (1.0 + rates_s.y.abs()));
    }
}

/// The same, on inputs near the domain's edges (tiny 1 − y c, θ̃₂ near ±π/2,
/// huge gains), where an unchecked division would overflow.
#[test]
fn edges_of_the_domain_give_values_or_errors() {
    let cfg = BacksteppingConfig {
        gains: Gains::new(-1e300, -1e301, 1.0).unwrap(),
        vehicle: Bicycle::new(
            Wheelbase::new(1e300).unwrap(),
            SteeringLimit::new(0.5).unwrap(),
            None,
        )
        .unwrap(),
        inversion: Inversion::Exact,
        schedule: None,
    };
    for (y, theta, c) in [
        (1e300, 0.0, 0.0),
        (1.0, 0.0, 1.0 - 1e-16),
        (0.5, core::f64::consts::FRAC_PI_2 - 1e-7, 0.0),
        (-1e-300, -1.5, 1e300),
    ] {
        match steering_command(
            &cfg,
            &tracking(y, theta, c, c),
            Sideslip::ZERO,
            speed(1e300),
        ) {
            Ok(cmd) => assert!(cmd.steering.get().abs() <= 0.5),
            Err(e) => assert!(!e.requirement.is_empty()),
        }
    }
}

/// The schedule of the Pierre 2022 tractor's steering (30°/s, 30°) for
/// 0.3-3 m/s with a lag of time constant `tau`.
fn tractor_schedule(tau: f64) -> SpeedSchedule {
    let thirty = 30_f64.to_radians();
    let vehicle = Bicycle::new(
        Wheelbase::new(2.0).unwrap(),
        SteeringLimit::new(thirty).unwrap(),
        Some(RadiansPerSecond::new(thirty).unwrap()),
    )
    .unwrap();
    SpeedSchedule::for_actuator(speed(0.3), speed(3.0), &vehicle, Seconds::new(tau).unwrap())
        .unwrap()
}

//= spec/pierre2022.md#pt-schedule-speed-schedule-of-the-gains
//= type=test
//# A speed schedule MUST be refused at construction unless
//# 0 < v_min ≤ v_max and Ω > 0.
#[test]
fn schedules_are_validated() {
    let omega = RadiansPerSecond::new(2.0).unwrap();
    assert!(SpeedSchedule::new(speed(0.3), speed(3.0), omega).is_ok());
    assert!(SpeedSchedule::new(speed(1.0), speed(1.0), omega).is_ok());
    for (lo, hi, w) in [
        (0.0, 3.0, 2.0),
        (-1.0, 3.0, 2.0),
        (3.0, 0.3, 2.0),
        (0.3, 3.0, 0.0),
        (0.3, 3.0, -1.0),
    ] {
        let e = SpeedSchedule::new(speed(lo), speed(hi), RadiansPerSecond::new(w).unwrap())
            .unwrap_err();
        assert_eq!(e.requirement, "PT-SCHEDULE", "{lo} {hi} {w}");
    }
    // Derived from an actuator whose rate is unknown, or a negative lag.
    let unknown = Bicycle::new(
        Wheelbase::new(2.0).unwrap(),
        SteeringLimit::new(0.5).unwrap(),
        None,
    )
    .unwrap();
    let e =
        SpeedSchedule::for_actuator(speed(0.3), speed(3.0), &unknown, Seconds::ZERO).unwrap_err();
    assert_eq!(e.requirement, "PT-SCHEDULE");
    let known = Bicycle {
        max_steering_rate: Some(RadiansPerSecond::new(0.5).unwrap()),
        ..unknown
    };
    let e =
        SpeedSchedule::for_actuator(speed(0.3), speed(3.0), &known, Seconds::new(-0.1).unwrap())
            .unwrap_err();
    assert_eq!(e.requirement, "PT-SCHEDULE");
}

//= spec/pierre2022.md#pt-schedule-speed-schedule-of-the-gains
//= type=test
//# A schedule derived from the actuator MUST take
//# Ω = min(2 R / δ_max, 1 / τ) for a steering rate limit R, saturation
//# δ_max and first-order time constant τ (the rate limit alone when τ = 0).
#[test]
fn the_actuator_gives_the_bandwidth() {
    // 30°/s over 30°: 2 R / δ_max = 2 1/s; a 1 s settling (τ = 1/3 s) allows 3.
    assert_relative_eq!(
        tractor_schedule(0.0).bandwidth().get(),
        2.0,
        max_relative = 1e-12
    );
    assert_relative_eq!(
        tractor_schedule(1.0 / 3.0).bandwidth().get(),
        2.0,
        max_relative = 1e-12
    );
    // A 2 s settling (τ = 2/3 s): 1 / τ = 1.5 1/s.
    assert_relative_eq!(
        tractor_schedule(2.0 / 3.0).bandwidth().get(),
        1.5,
        max_relative = 1e-12
    );
    let s = tractor_schedule(0.0);
    assert_eq!((s.min_speed().get(), s.max_speed().get()), (0.3, 3.0));
}

//= spec/pierre2022.md#pt-schedule-speed-schedule-of-the-gains
//= type=test
//# At a speed v the law MUST use the gains per metre k_y, k_θ where
//# v |k_θ| ≤ Ω, and both scaled by Ω / (v |k_θ|) where v |k_θ| > Ω.
#[test]
fn the_schedule_keeps_the_gains_below_v0_and_the_bandwidth_above() {
    let gains = Gains::new(-0.7, -2.8, 2.0).unwrap();
    let s = tractor_schedule(0.0);
    // v0 = 2 / 2.8 = 0.714 m/s.
    for v in [0.3, 0.5, 0.714] {
        assert_eq!(s.gains_at(&gains, speed(v)).unwrap(), gains, "{v}");
    }
    for v in [0.8, 1.0, 2.0, 3.0] {
        let g = s.gains_at(&gains, speed(v)).unwrap();
        assert_relative_eq!(v * g.k_theta(), -2.0, max_relative = 1e-12);
        assert_relative_eq!(g.k_theta() / g.k_y(), 4.0, max_relative = 1e-12);
    }
    // The law steers with the scheduled gains: the same command as the law
    // without a schedule given those gains.
    let mut law = config(-0.7, -2.8, Inversion::Exact);
    law.schedule = Some(s);
    let e = tracking(-0.3, 0.05, 0.02, 0.03);
    let at_3 = BacksteppingConfig {
        gains: s.gains_at(&gains, speed(3.0)).unwrap(),
        schedule: None,
        ..law
    };
    assert_eq!(
        steering_command(&law, &e, Sideslip::ZERO, speed(3.0)).unwrap(),
        steering_command(&at_3, &e, Sideslip::ZERO, speed(3.0)).unwrap()
    );
    assert_eq!(law.gains_at(speed(3.0)).unwrap(), at_3.gains);
    assert_eq!(
        config(-0.7, -2.8, Inversion::Exact)
            .gains_at(speed(3.0))
            .unwrap(),
        gains
    );
}

//= spec/pierre2022.md#pt-schedule-range-speeds-outside-the-schedule
//= type=test
//# A scheduled law MUST refuse a speed below v_min or above v_max with the
//# `PT-SCHEDULE-RANGE` error instead of a value.
#[test]
fn speeds_outside_the_schedule_are_refused() {
    let gains = Gains::new(-0.7, -2.8, 2.0).unwrap();
    let s = tractor_schedule(0.0);
    let mut law = config(-0.7, -2.8, Inversion::Exact);
    law.schedule = Some(s);
    let e = tracking(0.1, 0.0, 0.0, 0.0);
    for v in [0.1, 0.299, 3.001, 20.0] {
        assert_eq!(
            s.gains_at(&gains, speed(v)).unwrap_err().requirement,
            "PT-SCHEDULE-RANGE"
        );
        let err = steering_command(&law, &e, Sideslip::ZERO, speed(v)).unwrap_err();
        assert_eq!(err.requirement, "PT-SCHEDULE-RANGE", "{v}");
        assert_eq!(
            law.check_speed(speed(v)).unwrap_err().requirement,
            "PT-SCHEDULE-RANGE"
        );
    }
    // v <= 0 stays PT-SPEED, with or without a schedule.
    for v in [0.0, -1.0] {
        assert_eq!(law.gains_at(speed(v)).unwrap_err().requirement, "PT-SPEED");
        let plain = config(-0.7, -2.8, Inversion::Exact);
        assert_eq!(
            plain.gains_at(speed(v)).unwrap_err().requirement,
            "PT-SPEED"
        );
    }
    assert!(law.check_speed(speed(0.3)).is_ok() && law.check_speed(speed(3.0)).is_ok());
    // Extreme gains: a scheduled gain that underflows is an error, not zero.
    let huge = Gains::new(-1e-300, -1e300, 1.0).unwrap();
    let wide = SpeedSchedule::new(
        speed(1e-300),
        speed(1e300),
        RadiansPerSecond::new(1e-300).unwrap(),
    )
    .unwrap();
    assert_eq!(
        wide.gains_at(&huge, speed(1e300)).unwrap_err().requirement,
        "LIB-FINITE"
    );
}
