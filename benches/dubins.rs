//! Benchmark of Emmi 2024's planner and controllers: one shortest Dubins path
//! (six words tried, the shortest kept) by this library and by the
//! `dubins_paths` crate side by side, on the same 1 000 pose pairs (x, y in
//! [−20, 20] m, any headings, r in [0.5, 5] m); one evaluation of the lateral
//! PD law, the spiral law and the speed profile (README.md, "Tracking and
//! planning on a tracked robot").
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss
)]

use core::f64::consts::{FRAC_PI_2, PI};
use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use dubins_paths::f64::{DubinsPath as OraclePath, PosRot};
use fieldguide::control::lateral_pd::{LateralGains, LateralPd, LateralRate};
use fieldguide::control::speed_profile::{Braking, SpeedProfile, SpeedState};
use fieldguide::control::spiral::{spiral_command, Spiral};
use fieldguide::control::ControlLaw;
use fieldguide::model::skid_steer::SkidSteer;
use fieldguide::planning::dubins::{shortest, TurningRadius};
use fieldguide::{Meters, MetersPerSecond, Point2, Pose2, Radians, TrackingError, World};

/// 1 000 uniform draws from a fixed linear congruential sequence.
fn draws(n: usize) -> Vec<[f64; 7]> {
    let mut s = 2024_u64;
    let mut next = || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1_u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let mut d = [0.0; 7];
            for x in &mut d {
                *x = next();
            }
            d
        })
        .collect()
}

type Problem = (
    Pose2<World>,
    Pose2<World>,
    TurningRadius,
    PosRot,
    PosRot,
    f64,
);

fn problems() -> Vec<Problem> {
    draws(1000)
        .into_iter()
        .map(|d| {
            let a =
                Pose2::new(40.0 * d[0] - 20.0, 40.0 * d[1] - 20.0, 2.0 * PI * d[2] - PI).unwrap();
            let b =
                Pose2::new(40.0 * d[3] - 20.0, 40.0 * d[4] - 20.0, 2.0 * PI * d[5] - PI).unwrap();
            let rho = 0.5 + 4.5 * d[6];
            let r = TurningRadius::new(Meters::new(rho).unwrap()).unwrap();
            let pr = |p: &Pose2<World>| {
                PosRot::from_floats(p.position.x(), p.position.y(), p.heading.get())
            };
            (a, b, r, pr(&a), pr(&b), rho)
        })
        .collect()
}

fn dubins(c: &mut Criterion) {
    let problems = problems();
    let mut k = 0;
    c.bench_function("dubins/shortest_fieldguide", |b| {
        b.iter(|| {
            k = (k + 1) % problems.len();
            let (a, g, r, ..) = &problems[k];
            black_box(shortest(black_box(a), black_box(g), *r).unwrap().length())
        });
    });
    let mut k = 0;
    c.bench_function("dubins/shortest_dubins_paths", |b| {
        b.iter(|| {
            k = (k + 1) % problems.len();
            let (.., a, g, rho) = &problems[k];
            black_box(
                OraclePath::shortest_from(black_box(*a), black_box(*g), *rho)
                    .unwrap()
                    .length(),
            )
        });
    });
}

fn controllers(c: &mut Criterion) {
    let vehicle = SkidSteer::new(
        Meters::new(1.48).unwrap(),
        MetersPerSecond::new(1.67).unwrap(),
    )
    .unwrap();
    let lateral = LateralPd {
        gains: LateralGains::new(1.2, 0.8, 0.3, 1.0, 0.5).unwrap(),
        control_point: Meters::new(1.0).unwrap(),
        vehicle,
    };
    let inputs = draws(1000);
    let v = MetersPerSecond::new(0.5).unwrap();
    let mut k = 0;
    c.bench_function("emmi/lateral_pd_command", |b| {
        b.iter(|| {
            k = (k + 1) % inputs.len();
            let d = inputs[k];
            let e = TrackingError::to_straight_line(
                Meters::new(d[0] - 0.5).unwrap(),
                Radians::new(0.6 * d[1] - 0.3).unwrap(),
            );
            let rate = LateralRate(MetersPerSecond::new(0.2 * d[2] - 0.1).unwrap());
            black_box(lateral.command(black_box(&e), &rate, v).unwrap())
        });
    });
    let spiral = Spiral::new(1.0, Radians::new(FRAC_PI_2).unwrap(), vehicle).unwrap();
    let centre = Point2::new(0.0, 2.0).unwrap();
    let mut k = 0;
    c.bench_function("emmi/spiral_command", |b| {
        b.iter(|| {
            k = (k + 1) % inputs.len();
            let d = inputs[k];
            let p = Pose2::new(d[0] - 0.5, d[1] - 0.5, d[2] - 0.5).unwrap();
            black_box(spiral_command(&spiral, black_box(&p), centre, v).unwrap())
        });
    });
    let profile = SpeedProfile::new(
        MetersPerSecond::new(0.1).unwrap(),
        MetersPerSecond::new(0.5).unwrap(),
        Meters::new(1.0).unwrap(),
        Braking::Fixed(Meters::new(2.0).unwrap()),
        Meters::new(0.05).unwrap(),
    )
    .unwrap();
    let mut k = 0;
    c.bench_function("emmi/speed_profile_step", |b| {
        b.iter(|| {
            k = (k + 1) % inputs.len();
            let d = inputs[k];
            let travelled = Meters::new(10.0 * d[0]).unwrap();
            let remaining = Meters::new(10.0 * d[1]).unwrap();
            black_box(profile.step(
                SpeedState::Moving,
                black_box(travelled),
                black_box(remaining),
            ))
        });
    });
}

criterion_group!(benches, dubins, controllers);
criterion_main!(benches);
