//! The four-wheel-steering model (Iberraken 2022, eqs. 5-8) and its two laws
//! (eqs. 9-16 and 17-23): values computed by hand, the convergence each law
//! imposes in the model of eq. 7, mirror symmetry, saturation and the
//! refusals of bad input (`spec/iberraken2022.md`).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use approx::assert_abs_diff_eq;
use fieldguide::control::four_ws::{
    front_lateral_error, strategy1_command, strategy1_front, strategy1_rear, strategy2_command,
    strategy2_front, strategy2_rear, velocity_objective, Objectives, RearSteering, Strategy1,
    Strategy1Gains, Strategy2, Strategy2Gains,
};
use fieldguide::model::bicycle::{Sideslip, SteeringLimit, Wheelbase};
use fieldguide::model::four_ws::{
    frenet_rates, time_rates, world_rates, yaw_rate, FourWheelSteering,
};
use fieldguide::model::{Command, Vehicle};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Pose2, Radians, RadiansPerSecond, TrackingError,
};
use proptest::prelude::*;

const L: f64 = 1.2;

fn vehicle(limit: f64) -> FourWheelSteering {
    FourWheelSteering::new(
        Wheelbase::new(L).unwrap(),
        SteeringLimit::new(limit).unwrap(),
        SteeringLimit::new(limit).unwrap(),
        None,
        None,
    )
    .unwrap()
}

fn s1(limit: f64) -> Strategy1 {
    Strategy1 {
        gains: Strategy1Gains::table1().unwrap(),
        vehicle: vehicle(limit),
        rear: RearSteering::Backstepping,
    }
}

fn s2(limit: f64) -> Strategy2 {
    Strategy2 {
        gains: Strategy2Gains::table1().unwrap(),
        vehicle: vehicle(limit),
    }
}

fn error(y: f64, theta: f64, c: f64) -> TrackingError {
    TrackingError {
        y: Meters::new(y).unwrap(),
        angular_deviation: Radians::new(theta).unwrap(),
        curvature: Curvature::new(c).unwrap(),
        curvature_ahead: Curvature::new(c).unwrap(),
    }
}

fn v() -> MetersPerSecond {
    MetersPerSecond::new(1.0).unwrap()
}

fn rad(x: f64) -> Radians {
    Radians::new(x).unwrap()
}

// ---------------------------------------------------------------- hand values

//= spec/iberraken2022.md#s2-rear-rear-steering-of-the-rear-error
//= type=test
//# The rear angle of strategy 2 MUST be
//# δ_R = arctan(−K_R y^R / (1 − c(s) y^R)) − θ̃ − β_R.
//= spec/iberraken2022.md#s2-front-front-steering-of-the-front-error
//= type=test
//# The front angle of strategy 2 MUST be
//# δ_F = arctan(L λ₂ / cos(δ_R + β_R) − K_F y^F cos θ̃₂ / ((1 − c(s) y^R)
//# cos(δ_R + β_R) cos θ̃) − B₁) − β_F, with
//# B₁ = sin θ̃₂ / (cos(δ_R + β_R) cos θ̃) − tan(δ_R + β_R) and δ_R the rear
//# angle applied.
#[test]
fn strategy_2_crabs_parallel_to_a_straight_line_it_faces() {
    // y = 0.5 m, θ̃ = 0, K_F = K_R = 0.35: δ_R = atan(−0.175); then θ̃₂ = δ_R,
    // y^F = 0.5, λ₂ = 0, B₁ = 0, and δ_F = atan(−0.35 · 0.5) as well.
    let c = strategy2_command(&s2(1.0), &error(0.5, 0.0, 0.0), Sideslip::ZERO, v()).unwrap();
    assert_abs_diff_eq!(c.rear.get(), -0.173_245_666_452_364_94, epsilon = 1e-12);
    assert_abs_diff_eq!(c.front.get(), -0.173_245_666_452_364_94, epsilon = 1e-12);
    assert!(!c.saturated);
    // Sideslip is subtracted at each axle.
    let slip = Sideslip::new(0.02, -0.03).unwrap();
    let r = strategy2_rear(
        &Strategy2Gains::table1().unwrap(),
        &error(0.5, 0.0, 0.0),
        slip,
    )
    .unwrap();
    assert_abs_diff_eq!(r.get(), -0.173_245_666_452_364_94 + 0.03, epsilon = 1e-12);
}

//= spec/iberraken2022.md#s1-target-objective-of-the-velocity-direction
//= type=test
//# The objective of the velocity's angular deviation MUST be
//# θ̃₂^obj = arctan(k_y e_y / α), with e_y = y − y_d and α = 1 − c(s) y.
//= spec/iberraken2022.md#s1-front-front-steering-of-the-velocity-direction
//= type=test
//# The front angle of strategy 1 MUST be
//# δ_F = arctan(tan(δ_R + β_R) + L cos³(θ̃₂) / (α cos(δ_R + β_R))
//# (k_θ e_θ + c(s) / cos²(θ̃₂))) − β_F, with e_θ = tan θ̃₂ − tan θ̃₂^obj and
//# δ_R the rear angle applied.
#[test]
fn strategy_1_by_hand() {
    // Straight line, y = 0.5, θ̃ = 0: θ̃₂^obj = atan(−0.45), e_θ = 0.45,
    // δ_R = 0 (k_r = k_θ), δ_F = atan(L k_θ e_θ) = atan(−0.54).
    let c = strategy1_command(&s1(1.0), &error(0.5, 0.0, 0.0), &Objectives::NEUTRAL, v()).unwrap();
    assert_abs_diff_eq!(c.rear.get(), 0.0, epsilon = 1e-15);
    assert_abs_diff_eq!(c.front.get(), -0.495_133_263_468_404_14, epsilon = 1e-12);
    let obj = velocity_objective(
        &Strategy1Gains::table1().unwrap(),
        &error(0.2, 0.05, 0.1),
        Meters::ZERO,
    )
    .unwrap();
    assert_abs_diff_eq!(obj.get(), -0.181_648_830_000_011_97, epsilon = 1e-12);
    // A curve: y = 0.2, c = 0.1, θ̃ = 0.05, α = 0.98, rear held at 0 by k_r = k_θ.
    let c = strategy1_command(&s1(1.0), &error(0.2, 0.05, 0.1), &Objectives::NEUTRAL, v()).unwrap();
    assert_abs_diff_eq!(c.rear.get(), 0.0, epsilon = 1e-15);
    assert_abs_diff_eq!(c.front.get(), -0.161_398_085_842_897_75, epsilon = 1e-12);
    // A desired lateral offset moves the objective: y = y_d gives θ̃₂^obj = 0.
    let at = Objectives {
        lateral_offset: Meters::new(0.5).unwrap(),
        ..Objectives::NEUTRAL
    };
    let c = strategy1_command(&s1(1.0), &error(0.5, 0.0, 0.0), &at, v()).unwrap();
    assert_abs_diff_eq!(c.front.get(), 0.0, epsilon = 1e-15);
}

//= spec/iberraken2022.md#s1-rear-rear-steering-toward-a-desired-orientation
//= type=test
//# The rear angle of strategy 1 MUST be
//# δ_R = arctan(k_r e_r / k_θ + tan θ̃_d) − θ̃ − β_R, with
//# e_r = tan θ̃ − tan θ̃_d.
#[test]
fn strategy_1_rear_by_hand() {
    // k_r = −2, k_θ = −1, θ̃ = 0.1: δ_R = atan(2 tan 0.1) − 0.1.
    let gains = Strategy1Gains::new(-0.9, -1.0, -2.0, 1.0).unwrap();
    let r = strategy1_rear(&gains, &error(0.0, 0.1, 0.0), &Objectives::NEUTRAL).unwrap();
    assert_abs_diff_eq!(r.get(), 0.098_039_077_091_806_81, epsilon = 1e-12);
    // Table 1 (k_r = k_θ): the rear axle only cancels β_R.
    let slip = Objectives {
        sideslip: Sideslip::new(0.0, 0.04).unwrap(),
        ..Objectives::NEUTRAL
    };
    let r = strategy1_rear(
        &Strategy1Gains::table1().unwrap(),
        &error(0.3, 0.2, 0.0),
        &slip,
    )
    .unwrap();
    assert_abs_diff_eq!(r.get(), -0.04, epsilon = 1e-12);
}

//= spec/iberraken2022.md#fws-yaw-rate-yaw-rate-of-the-model
//= type=test
//# The yaw rate MUST be
//# u_θ = v cos(δ_R + β_R) (tan(δ_F + β_F) − tan(δ_R + β_R)) / L.
#[test]
fn yaw_rate_by_hand() {
    // Opposite angles of 0.1 rad at 2 m/s: 2 cos(−0.1) (2 tan 0.1) / 1.2.
    let u = yaw_rate(
        MetersPerSecond::new(2.0).unwrap(),
        rad(0.1),
        rad(-0.1),
        Sideslip::ZERO,
        Wheelbase::new(L).unwrap(),
    )
    .unwrap();
    assert_abs_diff_eq!(
        u.get(),
        2.0 * 0.1_f64.cos() * 2.0 * 0.1_f64.tan() / 1.2,
        epsilon = 1e-14
    );
    // Parallel steering (crab): no yaw.
    let u = yaw_rate(
        v(),
        rad(0.3),
        rad(0.3),
        Sideslip::ZERO,
        Wheelbase::new(L).unwrap(),
    )
    .unwrap();
    assert_abs_diff_eq!(u.get(), 0.0, epsilon = 1e-15);
}

// ---------------------------------------------------------------- model

fn small_state() -> impl Strategy<Value = (f64, f64, f64)> {
    (-1.0..1.0_f64, -0.6..0.6_f64, -0.3..0.3_f64)
}

fn slip() -> impl Strategy<Value = Sideslip> {
    (-0.1..0.1_f64, -0.1..0.1_f64).prop_map(|(f, r)| Sideslip::new(f, r).unwrap())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    //= spec/iberraken2022.md#fws-model-model-in-distance
    //= type=test
    //# The model in distance MUST give y' = (1 − y c(s)) tan θ̃₂ and
    //# θ̃' = u_θ (1 − y c(s)) / (v cos θ̃₂) − c(s), with θ̃₂ = θ̃ + δ_R + β_R.
    //= spec/iberraken2022.md#fws-model-time-model-in-time
    //= type=test
    //# The model in time MUST give ṡ = v cos θ̃₂ / (1 − c(s) y),
    //# ẏ = v sin θ̃₂ and dθ̃/dt = v [cos(δ_R + β_R) λ₁ − λ₂], with
    //# λ₁ = (tan(δ_F + β_F) − tan(δ_R + β_R)) / L,
    //# λ₂ = c(s) cos θ̃₂ / (1 − c(s) y) and θ̃₂ = θ̃ + δ_R + β_R.
    //= spec/iberraken2022.md#fws-model-time-model-in-time
    //= type=test
    //# The velocity of R MUST point at the heading plus δ_R + β_R.
    #[test]
    fn the_model_in_distance_is_the_model_in_time_over_s_rate(
        (y, theta, c) in small_state(), front in -0.5..0.5_f64, rear in -0.5..0.5_f64,
        slip in slip(), speed in 0.1..3.0_f64, heading in -3.0..3.0_f64,
    ) {
        let e = error(y, theta, c);
        let v = MetersPerSecond::new(speed).unwrap();
        let wb = Wheelbase::new(L).unwrap();
        let Ok(d) = frenet_rates(&e, v, rad(front), rad(rear), slip, wb) else {
            return Ok(());
        };
        let t = time_rates(&e, v, rad(front), rad(rear), slip, wb).unwrap();
        prop_assert!((d.y - t.y / t.s).abs() < 1e-9 * (1.0 + d.y.abs()));
        prop_assert!((d.angular_deviation - t.angular_deviation / t.s).abs()
            < 1e-9 * (1.0 + d.angular_deviation.abs()));
        // By hand: y' = α tan θ̃₂.
        let t2 = theta + rear + slip.rear.get();
        prop_assert!((d.y - (1.0 - c * y) * t2.tan()).abs() < 1e-12 * (1.0 + d.y.abs()));
        // The world form: speed v along heading + δ_R + β_R, yaw rate u_θ.
        let w = world_rates(&Pose2::new(0.0, 0.0, heading).unwrap(), v, rad(front), rad(rear), slip, wb).unwrap();
        prop_assert!((w.x_dot - speed * (heading + t2 - theta).cos()).abs() < 1e-12);
        prop_assert!((w.y_dot - speed * (heading + t2 - theta).sin()).abs() < 1e-12);
        let u = yaw_rate(v, rad(front), rad(rear), slip, wb).unwrap();
        prop_assert_eq!(w.heading_dot, u.get());
    }

    //= spec/iberraken2022.md#s1-target-objective-of-the-velocity-direction
    //= type=test
    //# With θ̃₂ = θ̃₂^obj the model MUST give e_y' = k_y e_y (y_d constant).
    //= spec/iberraken2022.md#s1-front-front-steering-of-the-velocity-direction
    //= type=test
    //# With δ_R constant, the model MUST give (tan θ̃₂)' = k_θ e_θ, so that
    //# e_θ' = k_θ e_θ − (tan θ̃₂^obj)'; on a straight line the neglected term is
    //# (tan θ̃₂^obj)' = k_y y'.
    #[test]
    fn strategy_1_imposes_its_error_dynamics_in_the_model(
        (y, theta, c) in small_state(), slip in slip(), y_d in -0.3..0.3_f64,
        theta_d in -0.3..0.3_f64, held in any::<bool>(),
    ) {
        let mut law = s1(1.5);
        law.gains = Strategy1Gains::new(-0.9, -2.0, -1.3, 2.0).unwrap();
        if held {
            law.rear = RearSteering::Held;
        }
        let e = error(y, theta, c);
        let obj = Objectives {
            sideslip: slip,
            lateral_offset: Meters::new(y_d).unwrap(),
            orientation: rad(theta_d),
        };
        let Ok(cmd) = strategy1_command(&law, &e, &obj, v()) else {
            return Ok(());
        };
        prop_assume!(!cmd.saturated);
        let d = frenet_rates(&e, v(), cmd.front, cmd.rear, slip, law.vehicle.wheelbase).unwrap();
        let alpha = 1.0 - c * y;
        let t2 = theta + cmd.rear.get() + slip.rear.get();
        let target = velocity_objective(&law.gains, &e, obj.lateral_offset).unwrap();
        let e_theta = t2.tan() - target.get().tan();
        let k = law.gains;
        // (tan θ̃₂)' = θ̃₂' / cos²θ̃₂ with δ_R, β_R constant.
        let tan_rate = d.angular_deviation / (t2.cos() * t2.cos());
        prop_assert!((tan_rate - k.k_theta() * e_theta).abs() < 1e-9 * (1.0 + tan_rate.abs()),
            "{tan_rate} vs {}", k.k_theta() * e_theta);
        // e_y' = α tan θ̃₂ = k_y e_y + α e_θ: exactly k_y e_y once e_θ = 0.
        prop_assert!((d.y - (k.k_y() * (y - y_d) + alpha * e_theta)).abs() < 1e-9);
        // On a straight line, e_θ' = k_θ e_θ − k_y y': a finite difference of
        // e_θ along the model, both angles held, over 1 µm.
        let straight = error(y, theta, 0.0);
        if let Ok(cmd) = strategy1_command(&law, &straight, &obj, v()) {
            let t2 = theta + cmd.rear.get() + slip.rear.get();
            if !cmd.saturated && t2.abs() < 1.2 {
                let wb = law.vehicle.wheelbase;
                let d = frenet_rates(&straight, v(), cmd.front, cmd.rear, slip, wb).unwrap();
                let e_theta_at = |y: f64, th: f64| {
                    let t2 = th + cmd.rear.get() + slip.rear.get();
                    let target = velocity_objective(&k, &error(y, th, 0.0), obj.lateral_offset).unwrap();
                    t2.tan() - target.get().tan()
                };
                let h = 1e-6;
                let e0 = e_theta_at(y, theta);
                let fd = (e_theta_at(y + h * d.y, theta + h * d.angular_deviation) - e0) / h;
                let expected = k.k_theta() * e0 - k.k_y() * d.y;
                prop_assert!((fd - expected).abs() < 1e-3 * (1.0 + expected.abs()), "{fd} vs {expected}");
            }
        }
    }

    //= spec/iberraken2022.md#s1-rear-rear-steering-toward-a-desired-orientation
    //= type=test
    //# With the rear law, the model of eq. 15, k_θ (tan θ̃₂ − tan θ̃_d), MUST equal
    //# k_r e_r.
    #[test]
    fn strategy_1_rear_law_gives_eq_15(
        (y, theta, c) in small_state(), slip in slip(), theta_d in -0.3..0.3_f64,
        k_r in -3.0..-0.1_f64,
    ) {
        let gains = Strategy1Gains::new(-0.9, -2.0, k_r, 2.0).unwrap();
        let obj = Objectives { sideslip: slip, lateral_offset: Meters::ZERO, orientation: rad(theta_d) };
        let r = strategy1_rear(&gains, &error(y, theta, c), &obj).unwrap();
        let t2 = theta + r.get() + slip.rear.get();
        let e_r = theta.tan() - theta_d.tan();
        prop_assert!((gains.k_theta() * (t2.tan() - theta_d.tan()) - k_r * e_r).abs() < 1e-9);
    }

    //= spec/iberraken2022.md#s2-rear-rear-steering-of-the-rear-error
    //= type=test
    //# With it, the model MUST give y^R' = −K_R y^R.
    //= spec/iberraken2022.md#s2-front-front-steering-of-the-front-error
    //= type=test
    //# With it, the model MUST give y^F' = −K_F y^F.
    //= spec/iberraken2022.md#s2-front-error-front-lateral-error
    //= type=test
    //# The front lateral error MUST be y^F = y^R + L sin θ̃.
    //= spec/iberraken2022.md#s2-front-error-front-lateral-error
    //= type=test
    //# With any steering, the model MUST give
    //# y^F' = α / cos θ̃₂ (sin θ̃₂ + L cos θ̃ (cos(δ_R + β_R) λ₁ − λ₂)).
    #[test]
    fn strategy_2_imposes_both_lateral_dynamics_in_the_model(
        (y, theta, c) in small_state(), slip in slip(), k_f in 0.05..2.0_f64, k_r in 0.05..2.0_f64,
    ) {
        let law = Strategy2 { gains: Strategy2Gains::new(k_f, k_r).unwrap(), vehicle: vehicle(1.5) };
        let e = error(y, theta, c);
        let Ok(cmd) = strategy2_command(&law, &e, slip, v()) else {
            return Ok(());
        };
        prop_assume!(!cmd.saturated);
        let d = frenet_rates(&e, v(), cmd.front, cmd.rear, slip, law.vehicle.wheelbase).unwrap();
        prop_assert!((d.y + k_r * y).abs() < 1e-9, "y' {} vs {}", d.y, -k_r * y);
        let y_f = front_lateral_error(&e, &law.vehicle).unwrap().get();
        prop_assert!((y_f - (y + L * theta.sin())).abs() < 1e-12);
        let y_f_rate = d.y + L * theta.cos() * d.angular_deviation;
        prop_assert!((y_f_rate + k_f * y_f).abs() < 1e-9, "yF' {} vs {}", y_f_rate, -k_f * y_f);
        // Eq. 18 as printed, with eq. 6's λ₁, λ₂.
        let alpha = 1.0 - c * y;
        let r = cmd.rear.get() + slip.rear.get();
        let t2 = theta + r;
        let l1 = ((cmd.front.get() + slip.front.get()).tan() - r.tan()) / L;
        let l2 = c * t2.cos() / alpha;
        let eq18 = alpha / t2.cos() * (t2.sin() + L * theta.cos() * (r.cos() * l1 - l2));
        prop_assert!((eq18 - y_f_rate).abs() < 1e-9 * (1.0 + eq18.abs()));
    }

    //= spec/iberraken2022.md#fws-mirror-mirror-symmetry
    //= type=test
    //# Both laws MUST be mirror symmetric: the mirrored error, sideslip and
    //# objectives MUST give the negated front and rear angles.
    #[test]
    fn both_laws_are_mirror_symmetric(
        (y, theta, c) in small_state(), slip in slip(), y_d in -0.3..0.3_f64, theta_d in -0.3..0.3_f64,
        limit in 0.1..1.5_f64,
    ) {
        let e = error(y, theta, c);
        let obj = Objectives { sideslip: slip, lateral_offset: Meters::new(y_d).unwrap(), orientation: rad(theta_d) };
        let a = strategy1_command(&s1(limit), &e, &obj, v());
        let b = strategy1_command(&s1(limit), &e.mirrored(), &obj.mirrored(), v());
        match (a, b) {
            (Ok(a), Ok(b)) => {
                prop_assert!((a.front.get() + b.front.get()).abs() < 1e-12);
                prop_assert!((a.rear.get() + b.rear.get()).abs() < 1e-12);
                prop_assert_eq!(a.saturated, b.saturated);
            }
            (Err(a), Err(b)) => prop_assert_eq!(a.requirement, b.requirement),
            (a, b) => prop_assert!(false, "{a:?} vs {b:?}"),
        }
        let a = strategy2_command(&s2(limit), &e, slip, v());
        let b = strategy2_command(&s2(limit), &e.mirrored(), slip.mirrored(), v());
        match (a, b) {
            (Ok(a), Ok(b)) => {
                prop_assert!((a.front.get() + b.front.get()).abs() < 1e-12);
                prop_assert!((a.rear.get() + b.rear.get()).abs() < 1e-12);
            }
            (Err(a), Err(b)) => prop_assert_eq!(a.requirement, b.requirement),
            (a, b) => prop_assert!(false, "{a:?} vs {b:?}"),
        }
    }

    //= spec/iberraken2022.md#s1-saturation-saturated-command
    //= type=test
    //# Each steering angle MUST lie within its limit; a law output beyond it MUST
    //# be clamped to the nearer bound and reported as saturated, and the front
    //# angle MUST be computed for the rear angle after its saturation.
    //= spec/iberraken2022.md#s2-saturation-saturated-command
    //= type=test
    //# Each steering angle of strategy 2 MUST lie within its limit; a law output
    //# beyond it MUST be clamped to the nearer bound and reported as saturated,
    //# and the front angle MUST be computed for the rear angle after its
    //# saturation.
    #[test]
    fn both_laws_saturate(
        y in -5.0..5.0_f64, theta in -1.4..1.4_f64, c in -0.5..0.5_f64, slip in slip(),
        limit in 0.05..0.6_f64, theta_d in -0.3..0.3_f64,
    ) {
        let e = error(y, theta, c);
        let obj = Objectives { sideslip: slip, lateral_offset: Meters::ZERO, orientation: rad(theta_d) };
        let law = s1(limit);
        if let Ok(cmd) = strategy1_command(&law, &e, &obj, v()) {
            prop_assert!(cmd.front.get().abs() <= limit && cmd.rear.get().abs() <= limit);
            let raw_rear = strategy1_rear(&law.gains, &e, &obj).unwrap();
            let raw_front = strategy1_front(&law, &e, &obj, cmd.rear).unwrap();
            let beyond = raw_rear.get().abs() > limit || raw_front.get().abs() > limit;
            prop_assert_eq!(cmd.saturated, beyond);
            prop_assert_eq!(cmd.rear.get(), raw_rear.get().clamp(-limit, limit));
            prop_assert_eq!(cmd.front.get(), raw_front.get().clamp(-limit, limit));
        }
        let law = s2(limit);
        if let Ok(cmd) = strategy2_command(&law, &e, slip, v()) {
            prop_assert!(cmd.front.get().abs() <= limit && cmd.rear.get().abs() <= limit);
            let raw_rear = strategy2_rear(&law.gains, &e, slip).unwrap();
            let raw_front = strategy2_front(&law, &e, slip, cmd.rear).unwrap();
            prop_assert_eq!(cmd.saturated, raw_rear.get().abs() > limit || raw_front.get().abs() > limit);
            prop_assert_eq!(cmd.front.get(), raw_front.get().clamp(-limit, limit));
        }
    }
}

// ---------------------------------------------------------------- closed loop in the model

/// Integrates the model of eq. 7 in s (Euler, 1 cm steps) on a straight
/// line from (y, θ̃) with the law `law` recomputed at each step.
fn drive(
    mut y: f64,
    mut theta: f64,
    law: impl Fn(&TrackingError) -> (Radians, Radians),
) -> (f64, f64, f64) {
    let mut max_theta = 0.0_f64;
    for _ in 0..2000 {
        let e = error(y, theta, 0.0);
        let (front, rear) = law(&e);
        let d = frenet_rates(
            &e,
            v(),
            front,
            rear,
            Sideslip::ZERO,
            Wheelbase::new(L).unwrap(),
        )
        .unwrap();
        y += 0.01 * d.y;
        theta += 0.01 * d.angular_deviation;
        max_theta = max_theta.max(theta.abs());
    }
    (y, theta, max_theta)
}

//= spec/iberraken2022.md#s1-two-wheel-steering-rear-angle-held-at-zero
//= type=test
//# With the rear steering held, strategy 1 MUST command δ_R = 0 and the
//# front angle of eq. 14 for δ_R = 0.
#[test]
fn from_0_7_m_off_both_strategies_and_the_2ws_law_converge_in_the_model() {
    let four = s1(0.6);
    let mut two = s1(0.6);
    two.rear = RearSteering::Held;
    // Rear steering toward θ̃_d = 0 that acts (k_r ≠ k_θ).
    let mut active = s1(0.6);
    active.gains = Strategy1Gains::new(-0.9, -1.0, -3.0, 1.0).unwrap();
    let second = s2(0.6);
    let run1 = |law: Strategy1| {
        drive(0.7, 0.0, move |e| {
            let c = strategy1_command(&law, e, &Objectives::NEUTRAL, v()).unwrap();
            (c.front, c.rear)
        })
    };
    for (name, (y, theta, _)) in [
        ("strategy 1", run1(four)),
        ("2WS", run1(two)),
        ("strategy 1 with rear steering", run1(active)),
        (
            "strategy 2",
            drive(0.7, 0.0, |e| {
                let c = strategy2_command(&second, e, Sideslip::ZERO, v()).unwrap();
                (c.front, c.rear)
            }),
        ),
    ] {
        assert!(
            y.abs() < 0.01 && theta.abs() < 0.01,
            "{name}: y {y}, θ̃ {theta}"
        );
    }
    // The rear axle held: δ_R = 0 and δ_F is eq. 14's for δ_R = 0.
    let mut held = s1(0.6);
    held.rear = RearSteering::Held;
    let e = error(0.4, 0.1, 0.05);
    let c = strategy1_command(&held, &e, &Objectives::NEUTRAL, v()).unwrap();
    assert_eq!(c.rear.get(), 0.0);
    assert_eq!(
        c.front,
        strategy1_front(&held, &e, &Objectives::NEUTRAL, Radians::ZERO).unwrap()
    );
    // Steering the rear axle toward the line's direction keeps the robot
    // more parallel to it than the 2WS law while converging.
    let (_, _, turned_2ws) = run1(two);
    let (_, _, turned_4ws) = run1(active);
    assert!(
        turned_4ws < turned_2ws,
        "4WS {turned_4ws} vs 2WS {turned_2ws}"
    );
}

// ---------------------------------------------------------------- refusals

//= spec/iberraken2022.md#fws-denom-robot-inside-the-radius-of-curvature
//= type=test
//# Where α = 1 − c(s) y ≤ 0 the model and the laws MUST return the
//# `FWS-DENOM` error instead of a value.
//= spec/iberraken2022.md#fws-heading-velocity-along-the-path
//= type=test
//# Where cos θ̃₂ ≤ 0 the model and the laws MUST return the `FWS-HEADING`
//# error instead of a value.
//= spec/iberraken2022.md#fws-speed-forward-speed
//= type=test
//# Where v ≤ 0 the model in distance and the laws MUST return the
//# `FWS-SPEED` error instead of a value.
//= spec/iberraken2022.md#fws-steer-domain-steering-within-the-domain-of-the-model
//= type=test
//# Where |δ_F + β_F| ≥ π/2 or |δ_R + β_R| ≥ π/2 the model and the laws MUST
//# return the `FWS-STEER-DOMAIN` error instead of a value.
//= spec/iberraken2022.md#s1-rear-rear-steering-toward-a-desired-orientation
//= type=test
//# Where cos θ̃ ≤ 0 or |θ̃_d| ≥ π/2 the rear law MUST return the `S1-REAR`
//# error instead of a value.
//= spec/iberraken2022.md#s2-front-front-steering-of-the-front-error
//= type=test
//# Where cos θ̃ ≤ 0 the front law MUST return the `S2-FRONT` error instead
//# of a value.
#[test]
fn bad_input_names_its_requirement() {
    let wb = Wheelbase::new(L).unwrap();
    fn req(r: Result<(), fieldguide::Precondition>) -> &'static str {
        r.unwrap_err().requirement
    }
    let n = Objectives::NEUTRAL;
    // 1 − c y ≤ 0: y = 2 on a curve of radius 2 m.
    let centre = error(2.0, 0.0, 0.5);
    assert_eq!(
        req(strategy1_command(&s1(0.6), &centre, &n, v()).map(|_| ())),
        "FWS-DENOM"
    );
    assert_eq!(
        req(strategy2_command(&s2(0.6), &centre, Sideslip::ZERO, v()).map(|_| ())),
        "FWS-DENOM"
    );
    assert_eq!(
        req(frenet_rates(&centre, v(), rad(0.0), rad(0.0), Sideslip::ZERO, wb).map(|_| ())),
        "FWS-DENOM"
    );
    // cos θ̃₂ = 0 with the rear held: θ̃ = π/2.
    let mut held = s1(0.6);
    held.rear = RearSteering::Held;
    let across = error(0.0, core::f64::consts::FRAC_PI_2, 0.0);
    assert_eq!(
        req(strategy1_command(&held, &across, &n, v()).map(|_| ())),
        "FWS-HEADING"
    );
    assert_eq!(
        req(frenet_rates(&across, v(), rad(0.0), rad(0.0), Sideslip::ZERO, wb).map(|_| ())),
        "FWS-HEADING"
    );
    // cos θ̃ = 0 for the rear law of strategy 1 and the front law of strategy 2.
    assert_eq!(
        req(strategy1_command(&s1(0.6), &across, &n, v()).map(|_| ())),
        "S1-REAR"
    );
    assert_eq!(
        req(strategy2_front(&s2(0.6), &across, Sideslip::ZERO, rad(0.0)).map(|_| ())),
        "S2-FRONT"
    );
    let tilted = Objectives {
        orientation: rad(1.6),
        ..n
    };
    assert_eq!(
        req(strategy1_command(&s1(0.6), &error(0.0, 0.0, 0.0), &tilted, v()).map(|_| ())),
        "S1-REAR"
    );
    // v ≤ 0.
    for speed in [0.0, -1.0] {
        let s = MetersPerSecond::new(speed).unwrap();
        assert_eq!(
            req(strategy1_command(&s1(0.6), &error(0.1, 0.0, 0.0), &n, s).map(|_| ())),
            "FWS-SPEED"
        );
        assert_eq!(
            req(strategy2_command(&s2(0.6), &error(0.1, 0.0, 0.0), Sideslip::ZERO, s).map(|_| ())),
            "FWS-SPEED"
        );
        assert_eq!(
            req(frenet_rates(
                &error(0.1, 0.0, 0.0),
                s,
                rad(0.0),
                rad(0.0),
                Sideslip::ZERO,
                wb
            )
            .map(|_| ())),
            "FWS-SPEED"
        );
    }
    // Steering at a right angle.
    assert_eq!(
        req(yaw_rate(v(), rad(1.6), rad(0.0), Sideslip::ZERO, wb).map(|_| ())),
        "FWS-STEER-DOMAIN"
    );
    assert_eq!(
        req(yaw_rate(v(), rad(0.0), rad(-1.6), Sideslip::ZERO, wb).map(|_| ())),
        "FWS-STEER-DOMAIN"
    );
    assert_eq!(
        req(strategy2_front(&s2(0.6), &error(0.0, 0.0, 0.0), Sideslip::ZERO, rad(1.6)).map(|_| ())),
        "FWS-STEER-DOMAIN"
    );
}

//= spec/iberraken2022.md#s1-gains-gain-sign-and-ratio
//= type=test
//# The gains k_y, k_θ and k_r MUST be finite and strictly negative, and
//# |k_θ| MUST be at least a configured ratio r ≥ 1 times |k_y|; other
//# gains MUST be refused at construction with the `S1-GAINS` error.
//= spec/iberraken2022.md#s2-gains-gain-sign
//= type=test
//# The gains K_F and K_R MUST be finite and strictly positive; other gains
//# MUST be refused at construction with the `S2-GAINS` error.
//= spec/iberraken2022.md#fws-vehicle-four-wheel-steering-vehicle
//= type=test
//# A four-wheel-steering vehicle MUST have a positive finite wheelbase,
//# front and rear steering limits in (0, π/2) and, when known, positive
//# front and rear steering rate limits; other values MUST be refused at
//# construction.
#[test]
fn gains_and_vehicles_are_validated_once() {
    let g = Strategy1Gains::table1().unwrap();
    assert_eq!((g.k_y(), g.k_theta(), g.k_r()), (-0.9, -1.0, -1.0));
    for (k_y, k_t, k_r, r) in [
        (0.9, -1.0, -1.0, 1.0),
        (-0.9, 1.0, -1.0, 1.0),
        (-0.9, -1.0, 1.0, 1.0),
        (-0.9, -1.0, 0.0, 1.0),
        (f64::NAN, -1.0, -1.0, 1.0),
        (-0.9, f64::NEG_INFINITY, -1.0, 1.0),
        (-0.9, -1.0, -1.0, 2.0),
        (-0.9, -1.0, -1.0, 0.5),
        (-0.9, -1.0, -1.0, f64::NAN),
    ] {
        assert_eq!(
            Strategy1Gains::new(k_y, k_t, k_r, r)
                .unwrap_err()
                .requirement,
            "S1-GAINS"
        );
    }
    // Table 1's gains pass only a ratio up to 1/0.9.
    assert!(Strategy1Gains::new(-0.9, -1.0, -1.0, 1.11).is_ok());
    assert!(Strategy1Gains::new(-0.9, -1.0, -1.0, 1.12).is_err());
    let g = Strategy2Gains::table1().unwrap();
    assert_eq!((g.k_front(), g.k_rear()), (0.35, 0.35));
    for (f, r) in [
        (0.0, 0.35),
        (0.35, -0.1),
        (f64::NAN, 0.35),
        (0.35, f64::INFINITY),
    ] {
        assert_eq!(
            Strategy2Gains::new(f, r).unwrap_err().requirement,
            "S2-GAINS"
        );
    }
    let wb = Wheelbase::new(L).unwrap();
    let sl = SteeringLimit::new(0.5).unwrap();
    let bad = RadiansPerSecond::new(0.0).unwrap();
    let good = RadiansPerSecond::new(1.0).unwrap();
    assert_eq!(
        FourWheelSteering::new(wb, sl, sl, Some(bad), None)
            .unwrap_err()
            .requirement,
        "FWS-VEHICLE"
    );
    assert_eq!(
        FourWheelSteering::new(wb, sl, sl, None, Some(bad))
            .unwrap_err()
            .requirement,
        "FWS-VEHICLE"
    );
    assert!(FourWheelSteering::new(wb, sl, sl, Some(good), Some(good)).is_ok());
    assert!(SteeringLimit::new(1.6).is_err() && Wheelbase::new(0.0).is_err());
    // The vehicle checks its commands' angles against each limit.
    let narrow =
        FourWheelSteering::new(wb, sl, SteeringLimit::new(0.2).unwrap(), None, None).unwrap();
    let veh = Vehicle::FourWheelSteering(narrow);
    let cmd = |f: f64, r: f64| Command::FourWheelSteering {
        speed: v(),
        front: rad(f),
        rear: rad(r),
    };
    assert!(veh.check(&cmd(0.5, 0.2)).is_ok());
    assert!(veh.check(&cmd(0.51, 0.0)).is_err());
    assert!(veh.check(&cmd(0.0, -0.21)).is_err());
    assert!(veh
        .check(&Command::Bicycle {
            speed: v(),
            steering: rad(0.0)
        })
        .is_err());
}

//= spec/iberraken2022.md#s1-law-strategy-1-behind-the-law-seam
//= type=test
//# Strategy 1 MUST be a control law for the four-wheel-steering vehicle,
//# reading the sideslip estimate and the objectives y_d and θ̃_d as its
//# extra input, zero sideslip on the line and parallel to it being its
//# neutral input.
//= spec/iberraken2022.md#s2-law-strategy-2-behind-the-law-seam
//= type=test
//# Strategy 2 MUST be a control law for the four-wheel-steering vehicle,
//# reading the sideslip estimate as its extra input, zero sideslip being its
//# neutral input.
#[test]
fn both_strategies_sit_behind_the_law_seam() {
    use fieldguide::control::ControlLaw;
    use fieldguide::model::Actuation;
    let e = error(0.3, 0.05, 0.02);
    let slip = Sideslip::new(0.02, -0.03).unwrap();
    let obj = Objectives {
        sideslip: slip,
        lateral_offset: Meters::new(0.1).unwrap(),
        orientation: rad(0.05),
    };
    let law1 = s1(0.6);
    assert_eq!(law1.actuation(), Actuation::FourWheelSteering);
    assert_eq!(Strategy1::NEUTRAL, Objectives::NEUTRAL);
    assert_eq!(Objectives::NEUTRAL.sideslip, Sideslip::ZERO);
    let direct = strategy1_command(&law1, &e, &obj, v()).unwrap();
    let c = law1.command(&e, &obj, v()).unwrap();
    assert_eq!(
        c.command,
        Command::FourWheelSteering {
            speed: v(),
            front: direct.front,
            rear: direct.rear
        }
    );
    assert_ne!(c, law1.command(&e, &Objectives::NEUTRAL, v()).unwrap());
    assert!(Strategy1::check_extra(&Objectives {
        orientation: rad(1.6),
        ..obj
    })
    .is_err());
    let law2 = s2(0.6);
    assert_eq!(law2.actuation(), Actuation::FourWheelSteering);
    assert_eq!(Strategy2::NEUTRAL, Sideslip::ZERO);
    let direct = strategy2_command(&law2, &e, slip, v()).unwrap();
    let c = law2.command(&e, &slip, v()).unwrap();
    assert_eq!(
        c.command,
        Command::FourWheelSteering {
            speed: v(),
            front: direct.front,
            rear: direct.rear
        }
    );
    assert_ne!(c, law2.command(&e, &Sideslip::ZERO, v()).unwrap());
    assert!(Strategy2::check_extra(&Sideslip {
        front: rad(1.6),
        rear: rad(0.0)
    })
    .is_err());
}
