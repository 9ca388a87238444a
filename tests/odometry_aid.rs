//! The odometry's heading aided by the good fix's (`spec/guidance.md`,
//! GD-ODOMETRY-AID): the filter alone on wheel odometry whose heading
//! drifts, with fixes, through an outage, without fixes, at overflow, and
//! its configuration.
#![allow(
    clippy::unwrap_used,
    clippy::as_conversions,
    clippy::cast_precision_loss
)]

use core::f64::consts::PI;

use fieldguide::guidance::Guidance;
use fieldguide::guidance::{
    AidedOdometry, FixKind, FixQuality, GuidanceConfig, OdometryAid, OdometryAidParams, TickInput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::presets::{pierre2022_path, Pierre2022};
use fieldguide::{Odom, Point2, Pose2, RadiansPerSecond, Seconds, World};
use proptest::prelude::*;
use rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

const PERIOD: f64 = 0.01;

/// τ = 1 s and 0.5 °/s, the simulator's fields' aid.
fn aid() -> OdometryAid {
    OdometryAid::new(
        &OdometryAidParams {
            time_constant: Seconds::new(1.0).unwrap(),
            max_rate: RadiansPerSecond::new(0.5_f64.to_radians()).unwrap(),
        },
        Seconds::new(PERIOD).unwrap(),
    )
    .unwrap()
}

/// A uniform noise of standard deviation `sigma`.
fn noise(rng: &mut Xoshiro256PlusPlus, sigma: f64) -> f64 {
    let u = (rng.next_u64() >> 11) as f64 / (1_u64 << 53) as f64;
    (2.0 * u - 1.0) * sigma * 3.0_f64.sqrt()
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// Wheel odometry with a heading bias (rad/s) and a white noise per tick
/// (rad) on its heading increments, integrating the true motion.
struct Wheels {
    pose: (f64, f64, f64),
    bias: f64,
    sigma: f64,
}

impl Wheels {
    fn step(&mut self, ds: f64, dtheta: f64, rng: &mut Xoshiro256PlusPlus) -> Pose2<Odom> {
        let (x, y, th) = self.pose;
        let dth = dtheta + self.bias * PERIOD + noise(rng, self.sigma);
        let mid = th + 0.5 * dth;
        self.pose = (x + ds * mid.cos(), y + ds * mid.sin(), th + dth);
        Pose2::new(self.pose.0, self.pose.1, self.pose.2).unwrap()
    }
}

/// One run at 1 m/s on a slow S-curve for `seconds`, the fix given when
/// `fixed(t)`, its heading with white noise of 0.2°: the largest change of
/// the aided and of the raw frame's rotation against the world from 9 s on
/// (the first fix's noise is in the reference offset, which the frame
/// settles to over a few τ), rad, and every tick's correction (the aided
/// heading's increment less the raw one's).
fn run(seed: u64, seconds: f64, bias: f64, sigma: f64, fixed: &dyn Fn(f64) -> bool) -> Run {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut wheels = Wheels {
        pose: (0.0, 0.0, 0.0),
        bias,
        sigma,
    };
    let mut truth = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut aided = AidedOdometry::new();
    let aid = aid();
    let mut first: Option<(f64, f64)> = None;
    let mut last: Option<(Pose2<Odom>, Pose2<Odom>)> = None;
    let mut out = Run {
        aided: 0.0,
        raw: 0.0,
        corrections: Vec::new(),
        rotations: Vec::new(),
    };
    let ticks = (seconds / PERIOD).round() as u32;
    for k in 0..ticks {
        let t = f64::from(k) * PERIOD;
        let turn = 0.1 * (0.05 * t).sin() * PERIOD;
        let mid = truth.2 + 0.5 * turn;
        truth = (
            truth.0 + PERIOD * mid.cos(),
            truth.1 + PERIOD * mid.sin(),
            truth.2 + turn,
        );
        let raw = wheels.step(PERIOD, turn, &mut rng);
        let fix = fixed(t).then(|| {
            Pose2::<World>::new(
                truth.0,
                truth.1,
                truth.2 + noise(&mut rng, 0.2_f64.to_radians()),
            )
            .unwrap()
        });
        let pose = aided.step(&aid, raw, fix.as_ref());
        assert!(pose.heading.get().is_finite() && pose.position.x().is_finite());
        if let Some((raw0, aided0)) = last {
            let correction = (pose.heading.get() - aided0.heading.get())
                - (raw.heading.get() - raw0.heading.get());
            out.corrections.push((t, fix.is_some(), wrap(correction)));
            // The aided pose moves by the odometry's distance.
            let d_raw = raw.position.distance_to(raw0.position).unwrap().get();
            let d_aided = pose.position.distance_to(aided0.position).unwrap().get();
            assert!((d_raw - d_aided).abs() < 1e-9, "{d_raw} {d_aided}");
        }
        last = Some((raw, pose));
        let rotation = (
            wrap(pose.heading.get() - truth.2),
            wrap(raw.heading.get() - truth.2),
        );
        if t >= 9.0 && first.is_none() {
            first = Some(rotation);
        }
        if let Some((a0, r0)) = first {
            out.aided = out.aided.max(wrap(rotation.0 - a0).abs());
            out.raw = out.raw.max(wrap(rotation.1 - r0).abs());
            out.rotations.push((t, wrap(rotation.0 - a0)));
        }
    }
    out
}

struct Run {
    aided: f64,
    raw: f64,
    corrections: Vec<(f64, bool, f64)>,
    rotations: Vec<(f64, f64)>,
}

//= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
//= type=test
//# When an odometry aid is configured, every step of a tick MUST use, in place
//# of the tick's odometry pose, the aided pose: in the first tick the odometry
//# pose itself, in every later tick the previous aided pose moved by the
//# odometry's increment since the previous tick (the tick's odometry pose in
//# the robot frame of the previous tick's), its heading then turned by the
//# tick's correction.
//= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
//= type=test
//# The correction MUST be zero in a tick without a good fix (GD-FIX-QUALITY)
//# and in the tick of the first good fix, which fixes the reference offset: the
//# aided heading less the fix's heading. In a tick with a later good fix it
//# MUST be α e with α = 1 − exp(−Δt / τ), Δt the period, τ the aid's time
//# constant and e the reference offset less the tick's offset, wrapped to
//# (−π, π], limited in magnitude to the aid's largest rate times the period.
#[test]
fn the_aided_frame_keeps_its_rotation_against_the_world_the_wheels_do_not() {
    // The wheels of the simulator's built-ins: 0.05°/s and 0.02° a tick at
    // 100 Hz, over three minutes with a fix in every tick.
    for seed in 1..=10 {
        let r = run(
            seed,
            180.0,
            0.05_f64.to_radians(),
            0.02_f64.to_radians(),
            &|_| true,
        );
        assert!(
            r.aided < 0.8_f64.to_radians(),
            "seed {seed}: {}°",
            r.aided.to_degrees()
        );
        assert!(
            r.raw > 6.0_f64.to_radians(),
            "seed {seed}: {}°",
            r.raw.to_degrees()
        );
        // The bias alone: the aided frame settles within its lag b τ.
        let b = run(seed, 180.0, 0.05_f64.to_radians(), 0.0, &|_| true);
        assert!(
            b.aided < 0.1_f64.to_radians(),
            "seed {seed}: {}°",
            b.aided.to_degrees()
        );
        assert!(b.raw > 8.0_f64.to_radians());
    }
}

#[test]
fn a_returning_fix_turns_the_frame_back_at_the_largest_rate_at_most() {
    // 10 s of fixes, 40 s of outage with 0.05°/s of bias (2° of drift),
    // then the fixes again: the drift is taken out at 0.5°/s, never in a step.
    let outage = |t: f64| !(10.0..50.0).contains(&t);
    let step = aid().max_step().get();
    assert!((step - 0.005_f64.to_radians()).abs() < 1e-15);
    for seed in 1..=5 {
        let r = run(seed, 70.0, 0.05_f64.to_radians(), 0.0, &outage);
        for &(t, fix, c) in &r.corrections {
            assert!(c.abs() <= step * (1.0 + 1e-9), "t {t}: {c}");
            if !fix {
                assert!(c.abs() < 1e-12, "t {t}: {c}");
            }
        }
        let at = |when: f64| {
            r.rotations
                .iter()
                .find(|(t, _)| *t >= when)
                .map(|(_, a)| a.abs())
                .unwrap()
        };
        assert!(at(49.99) > 1.95_f64.to_radians());
        // Limited by the rate for 4 s: still more than 1° off after 2 s.
        assert!(at(52.0) > 0.95_f64.to_radians());
        // Back within 0.1° of the reference 4 s + 5 τ after the return.
        assert!(at(59.0) < 0.1_f64.to_radians(), "{}", at(59.0).to_degrees());
        // The largest move of a point held 4 m ahead in one tick: 0.35 mm.
        let worst = r.corrections.iter().map(|c| c.2.abs()).fold(0.0, f64::max);
        assert!(4.0 * worst < 0.00035, "{worst}");
    }
}

#[test]
fn without_a_fix_the_aided_pose_is_the_odometry_pose() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let mut wheels = Wheels {
        pose: (3.0, -2.0, 1.0),
        bias: 0.01,
        sigma: 0.001,
    };
    let mut aided = AidedOdometry::new();
    let first = Pose2::new(3.0, -2.0, 1.0).unwrap();
    assert_eq!(aided.step(&aid(), first, None), first);
    for k in 0..5000 {
        let raw = wheels.step(0.01, 0.002 * (f64::from(k) * 0.003).cos(), &mut rng);
        let pose = aided.step(&aid(), raw, None);
        assert!(pose.position.distance_to(raw.position).unwrap().get() < 1e-9);
        assert!(wrap(pose.heading.get() - raw.heading.get()).abs() < 1e-12);
    }
    assert_eq!(aided.reference(), None);
}

//= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
//= type=test
//# A tick whose aided pose overflows MUST take the tick's odometry pose as its
//# aided pose and forget the reference offset, so that the next good fix fixes
//# a new one.
#[test]
fn an_aided_pose_that_overflows_restarts_from_the_odometry() {
    let aid = aid();
    let mut aided = AidedOdometry::new();
    let fix = Pose2::<World>::new(0.0, 0.0, 0.3).unwrap();
    aided.step(&aid, Pose2::new(-1.0e308, 0.0, PI).unwrap(), Some(&fix));
    assert!(aided.reference().is_some());
    let far = Pose2::new(1.0e308, 1.0e308, 0.0).unwrap();
    assert_eq!(aided.step(&aid, far, None), far);
    assert_eq!(aided.reference(), None);
    // The next good fix fixes the new reference: no correction in its tick.
    let next = Pose2::new(1.0e308, 1.0e308, 0.1).unwrap();
    assert_eq!(aided.step(&aid, next, Some(&fix)), next);
    assert!((aided.reference().unwrap().get() - (0.1 - 0.3)).abs() < 1e-12);
}

//= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
//= type=test
//# An odometry aid whose time constant or largest rate is not positive MUST be
//# refused with `GD-ODOMETRY-AID`.
#[test]
fn an_aid_without_a_positive_time_constant_or_rate_is_refused() {
    let period = Seconds::new(PERIOD).unwrap();
    let good = *aid().params();
    for (tau, rate) in [(0.0, 0.01), (-1.0, 0.01), (1.0, 0.0), (1.0, -0.01)] {
        let params = OdometryAidParams {
            time_constant: Seconds::new(tau).unwrap(),
            max_rate: RadiansPerSecond::new(rate).unwrap(),
        };
        let e = OdometryAid::new(&params, period).unwrap_err();
        assert_eq!(e.requirement, "GD-ODOMETRY-AID", "{tau} {rate}");
        let mut p = pierre2022_path().unwrap();
        p.odometry_aid = Some(params);
        assert_eq!(
            GuidanceConfig::new(&p).unwrap_err().requirement,
            "GD-ODOMETRY-AID"
        );
    }
    let a = OdometryAid::new(&good, period).unwrap();
    assert!((a.gain() - (1.0 - (-0.01_f64).exp())).abs() < 1e-15);
    let mut p = pierre2022_path().unwrap();
    p.odometry_aid = Some(good);
    assert_eq!(GuidanceConfig::new(&p).unwrap().odometry_aid(), Some(&a));
}

/// A pose from any three numbers, as a caller would build it: refused when
/// one is not finite (LIB-FINITE).
fn pose<F: fieldguide::geometry::frame::Frame>(v: (f64, f64, f64)) -> Option<Pose2<F>> {
    Pose2::new(v.0, v.1, v.2).ok()
}

fn any_number() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0..10.0_f64,
        -1.0e308..1.0e308_f64,
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(-f64::MAX),
        Just(f64::MAX),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any sequence of poses and fixes, finite or not: non-finite ones are
    /// refused where they are built, the aid never panics and its pose is
    /// finite with a wrapped heading, alone and in the pipeline.
    #[test]
    fn the_aid_never_panics_nor_gives_a_nan(
        ticks in proptest::collection::vec(
            ((any_number(), any_number(), any_number()),
             proptest::option::of((any_number(), any_number(), any_number()))),
            1..40,
        ),
        tau in 1.0e-9..1.0e3_f64,
        rate in 1.0e-9..1.0e3_f64,
    ) {
        let params = OdometryAidParams {
            time_constant: Seconds::new(tau).unwrap(),
            max_rate: RadiansPerSecond::new(rate).unwrap(),
        };
        let aid = OdometryAid::new(&params, Seconds::new(PERIOD).unwrap()).unwrap();
        let mut aided = AidedOdometry::new();
        let waypoints = [Point2::<World>::new(0.0, 0.0).unwrap(), Point2::new(50.0, 0.0).unwrap()];
        let path = fieldguide::geometry::path::ReferencePath::<16>::from_waypoints(
            &waypoints,
            fieldguide::geometry::path::PathConfig::default(),
        )
        .unwrap();
        let mut p = pierre2022_path().unwrap();
        p.odometry_aid = Some(params);
        let mut g: Pierre2022<'_, 16> = Guidance::new(GuidanceConfig::new(&p).unwrap(), &path).unwrap();
        for (o, f) in ticks {
            let Some(odometry) = pose::<Odom>(o) else { continue };
            let fix = f.and_then(pose::<World>);
            let a = aided.step(&aid, odometry, fix.as_ref());
            prop_assert!(a.position.x().is_finite() && a.position.y().is_finite());
            prop_assert!(a.heading.get() > -PI - 1e-12 && a.heading.get() <= PI + 1e-12);
            let out = g.step_with_fix(
                &TickInput { scans: &[], gnss: fix, odometry, extra: Sideslip::ZERO },
                &FixQuality { kind: FixKind::RtkFixed, accuracy: None },
            );
            prop_assert!(out.is_ok());
        }
    }
}
