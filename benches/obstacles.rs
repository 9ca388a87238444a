//! Benchmark of the obstacle handling of Emmi 2024, section 3.2: clustering
//! one 360-ray scan (two posts in front of a wall, exact ranges) into
//! obstacles; one re-plan (the hazard of one tick with a post on a straight
//! path in the warning area, its detour waypoint and both Dubins legs
//! checked clear), and the worst re-plan measured here: walls on both sides,
//! every candidate waypoint tried and refused.
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss
)]

use core::f64::consts::{PI, TAU};
use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::perception::obstacles::{
    assess, cluster, ClusterConfig, Obstacle, ObstacleConfig, Obstacles, Reason,
};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::planning::dubins::TurningRadius;
use fieldguide::{Meters, MetersPerSecond, Point2, Pose2, Radians, Robot, Sensor, Transform2};

const RAYS: usize = 360;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn circle(x: f64, y: f64, r: f64) -> Obstacle {
    Obstacle::Circle {
        centre: Point2::new(x, y).unwrap(),
        radius: m(r),
    }
}

fn segment(a: (f64, f64), b: (f64, f64)) -> Obstacle {
    Obstacle::Segment {
        start: Point2::new(a.0, a.1).unwrap(),
        end: Point2::new(b.0, b.1).unwrap(),
    }
}

/// Range along direction `angle` to a circle `(x, y, r)` or a wall at x = `d`.
fn ranges() -> Vec<f64> {
    let posts = [(3.0, -1.0, 0.3), (5.0, 1.5, 0.2)];
    (0..RAYS)
        .map(|k| {
            let a = -PI + TAU * k as f64 / RAYS as f64;
            let (c, s) = (a.cos(), a.sin());
            let mut best = f64::INFINITY;
            for (x, y, r) in posts {
                let b = c * x + s * y;
                let disc = b * b - (x * x + y * y - r * r);
                if disc >= 0.0 && b - disc.sqrt() > 0.0 {
                    best = best.min(b - disc.sqrt());
                }
            }
            // A wall 8 m ahead, 10 m long.
            if c > 0.0 && (8.0 * s / c).abs() <= 5.0 {
                best = best.min(8.0 / c);
            }
            best
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let ranges = ranges();
    let scan = Scan {
        start: Radians::new(-PI).unwrap(),
        increment: Radians::new(TAU / RAYS as f64).unwrap(),
        ranges: &ranges,
        limits: RangeLimits::new(m(0.05), m(30.0)).unwrap(),
    };
    let mount = Transform2::<Sensor, Robot>::new(0.0, 0.0, 0.0).unwrap();
    let config = ClusterConfig::emmi2024();
    // The posts hide two stretches of the wall: three segments, two circles.
    let found = cluster::<16>(&scan, &mount, &config);
    assert_eq!(found.as_slice().len(), 5, "{:?}", found.as_slice());
    c.bench_function("obstacles: cluster one 360-ray scan", |b| {
        b.iter(|| cluster::<16>(black_box(&scan), &mount, &config));
    });

    let obstacles = ObstacleConfig::emmi2024(TurningRadius::new(m(1.0)).unwrap());
    let pose = Pose2::new(0.0, 0.0, 0.0).unwrap();
    let goal = Pose2::new(30.0, 0.0, 0.0).unwrap();
    let speed = MetersPerSecond::new(0.5).unwrap();
    let mut one = Obstacles::<16>::new();
    one.insert(circle(4.0, 0.2, 0.3));
    let a = assess(&one, &pose, &goal, speed, false, &obstacles).unwrap();
    assert_eq!(a.reason, Reason::Detour);
    c.bench_function("obstacles: one re-plan round a post", |b| {
        b.iter(|| assess(black_box(&one), &pose, &goal, speed, false, &obstacles));
    });

    let mut walled = Obstacles::<16>::new();
    walled.insert(circle(4.0, 0.2, 0.3));
    walled.insert(segment((-1.0, 1.3), (20.0, 1.3)));
    walled.insert(segment((-1.0, -1.3), (20.0, -1.3)));
    let a = assess(&walled, &pose, &goal, speed, false, &obstacles).unwrap();
    assert_eq!(a.reason, Reason::NoClearSide);
    c.bench_function("obstacles: re-plan refused between two walls", |b| {
        b.iter(|| assess(black_box(&walled), &pose, &goal, speed, false, &obstacles));
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
