//! Benchmarks of Iberraken 2022: one tick of the vine detector (section 2.1)
//! on a 271-ray inclined scan (61 rays in the ±30° field of view) of summer
//! vine rows on a cross slope, made by the exact caster of
//! `tests/vine_scans`, and one command of each four-wheel-steering law
//! (sections 2.2.2-2.2.3).
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects
)]

use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::control::four_ws::{
    strategy1_command, strategy2_command, Objectives, RearSteering, Strategy1, Strategy1Gains,
    Strategy2, Strategy2Gains,
};
use fieldguide::model::bicycle::{Sideslip, SteeringLimit, Wheelbase};
use fieldguide::model::four_ws::FourWheelSteering;
use fieldguide::perception::vine::{VineConfig, VineDetector, VineParams};
use fieldguide::{Curvature, Meters, MetersPerSecond, Odom, Pose2, Radians, TrackingError};

#[path = "../tests/vine_scans/mod.rs"]
mod vine_scans;

fn vine(c: &mut Criterion) {
    // Rows without posts: the scene, hence the scan, is the same at every x,
    // so advancing the odometry fills and renews the set-points as in a row.
    let mut world = vine_scans::World::ground(0.0, 0.15);
    for y in [-2.2, 0.0, 2.2] {
        world.vine_row(y, 0.25, 1.0, (-5.0, 1000.0), &[]);
    }
    let lidar = vine_scans::Lidar::table1();
    let ranges = lidar.cast(&world, (0.0, 0.2, 0.0));
    let scan = lidar.scan(&ranges);
    let mut detector =
        VineDetector::<512, 64>::new(VineConfig::new(&VineParams::summer()).unwrap()).unwrap();
    let mut x = 0.0;
    for _ in 0..80 {
        detector
            .detect(&scan, &Pose2::<Odom>::new(x, 0.2, 0.0).unwrap())
            .unwrap();
        x += 0.1;
    }
    let first = detector
        .detect(&scan, &Pose2::<Odom>::new(x, 0.2, 0.0).unwrap())
        .unwrap();
    assert!(first.verdict.estimate_is_valid(), "{first:?}");

    c.bench_function("vine/detect_summer_271_rays", |b| {
        b.iter(|| {
            x += 0.1;
            let odom = Pose2::<Odom>::new(x, 0.2, 0.0).unwrap();
            black_box(detector.detect(black_box(&scan), &odom).unwrap())
        });
    });

    let vehicle = FourWheelSteering::new(
        Wheelbase::new(1.2).unwrap(),
        SteeringLimit::new(0.5).unwrap(),
        SteeringLimit::new(0.3).unwrap(),
        None,
        None,
    )
    .unwrap();
    let s1 = Strategy1 {
        gains: Strategy1Gains::table1().unwrap(),
        vehicle,
        rear: RearSteering::Backstepping,
    };
    let s2 = Strategy2 {
        gains: Strategy2Gains::table1().unwrap(),
        vehicle,
    };
    let error = TrackingError {
        y: Meters::new(0.3).unwrap(),
        angular_deviation: Radians::new(0.05).unwrap(),
        curvature: Curvature::new(0.02).unwrap(),
        curvature_ahead: Curvature::new(0.02).unwrap(),
    };
    let objectives = Objectives {
        sideslip: Sideslip::new(0.01, -0.02).unwrap(),
        ..Objectives::NEUTRAL
    };
    let v = MetersPerSecond::new(1.0).unwrap();
    c.bench_function("vine/strategy1_command", |b| {
        b.iter(|| black_box(strategy1_command(&s1, black_box(&error), &objectives, v).unwrap()));
    });
    c.bench_function("vine/strategy2_command", |b| {
        b.iter(|| {
            black_box(strategy2_command(&s2, black_box(&error), objectives.sideslip, v).unwrap())
        });
    });
}

criterion_group!(benches, vine);
criterion_main!(benches);
