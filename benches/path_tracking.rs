//! Benchmarks of path tracking.
//!
//! - `bench_frenet_projection`: one global Frénet projection
//!   (`ReferencePath::project`) of a pose on a 1 000-point path.
//! - `bench_steering`: one evaluation of the backstepping law with sideslip
//!   compensation and curvature feed-forward (`steering_command`).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::control::backstepping::{steering_command, BacksteppingConfig, Gains, Inversion};
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::model::bicycle::{Bicycle, Sideslip, SteeringLimit, Wheelbase};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Point2, Pose2, Radians, TrackingError, World,
};

/// A 1 000-point path recorded every 0.1 m: a 100 m serpentine y = 2 sin(x / 5).
fn serpentine_1000() -> ReferencePath<1000> {
    let mut points = Vec::with_capacity(1000);
    let mut x = 0.0_f64;
    for _ in 0..1000 {
        points.push(Point2::<World>::new(x, 2.0 * (x / 5.0).sin()).unwrap());
        x += 0.1;
    }
    ReferencePath::from_waypoints(&points, PathConfig::default()).unwrap()
}

/// One global projection (O(N) closest-segment search, then s, y, θ̃, c(s),
/// c(s + vT)) of a pose near the middle of a 1 000-point path.
fn bench_frenet_projection(c: &mut Criterion) {
    let path = serpentine_1000();
    let pose = Pose2::<World>::new(47.3, 0.8, 0.4).unwrap();
    let lookahead = Meters::new(0.5).unwrap();
    c.bench_function("frenet_projection_1000_points", |b| {
        b.iter(|| black_box(&path).project(black_box(&pose), black_box(lookahead)))
    });
}

/// One steering evaluation (eqs. 3, 5, 6, 7 and saturation) with the
/// tractor of Pierre 2022 (L = 2 m, 0.8 m/s) on a curve with sideslip.
fn bench_steering(c: &mut Criterion) {
    let config = BacksteppingConfig {
        gains: Gains::new(-0.7, -1.4, 2.0).unwrap(),
        vehicle: Bicycle::new(
            Wheelbase::new(2.0).unwrap(),
            SteeringLimit::new(0.6).unwrap(),
            None,
        )
        .unwrap(),
        inversion: Inversion::Exact,
        schedule: None,
    };
    let error = TrackingError {
        y: Meters::new(0.12).unwrap(),
        angular_deviation: Radians::new(-0.05).unwrap(),
        curvature: Curvature::new(0.1).unwrap(),
        curvature_ahead: Curvature::new(0.12).unwrap(),
    };
    let slip = Sideslip::new(-0.03, -0.05).unwrap();
    let speed = MetersPerSecond::new(0.8).unwrap();
    c.bench_function("steering_command", |b| {
        b.iter(|| {
            steering_command(
                black_box(&config),
                black_box(&error),
                black_box(slip),
                black_box(speed),
            )
        })
    });
}

criterion_group!(benches, bench_frenet_projection, bench_steering);
criterion_main!(benches);
