//! Benchmark of one full guidance tick (`spec/guidance.md`): a 360-ray
//! horizontal scan of a ragged hedge 1.4 m to the left, a 360-ray inclined
//! scan of two rows of plants 0.75 m apart, the GNSS pose projected on a
//! 200 m path, odometry, plan check, three laws, the switching machine and
//! the command. The world repeats every plant spacing (0.2 m): the robot
//! advances by that much each tick, so the scans stay valid while the furrow
//! detector accumulates as in the field.
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss
)]

use core::f64::consts::{FRAC_PI_2, PI, TAU};
use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::guidance::{
    ActiveMode, EdgeFollowingParams, Guidance, GuidanceConfig, GuidanceParams, PlanCheck, TickInput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::edge::{RangeLimits, Scan as EdgeScan, Side};
use fieldguide::perception::furrow::scan::Scan as FurrowScan;
use fieldguide::perception::furrow::FurrowParams;
use fieldguide::supervisor::switching::PlanTolerance;
use fieldguide::{Meters, Odom, Point2, Pose2, Radians, Robot, Seconds, Sensor, Transform2, World};

const MOUNT_X: f64 = 1.2;
const RAYS: usize = 360;
const FOV: f64 = FRAC_PI_2;
const SPACING: f64 = 0.2;

/// The left hedge's face at robot-frame abscissa `x`: 1.4 m with a ragged
/// profile of a few centimetres.
fn hedge_face(x: f64) -> f64 {
    1.4 - 0.04 * (3.1 * x).sin() - 0.03 * (7.7 * x + 1.0).sin() - 0.02 * (19.3 * x).sin()
}

/// Range of the horizontal ray at angle `a` to the left hedge (bisection) or
/// to a straight hedge 2.5 m to the right, +inf beyond 30 m.
fn hedge_range(a: f64) -> f64 {
    let (dx, dy) = (a.cos(), a.sin());
    if dy > 1e-3 {
        let (mut lo, mut hi) = (0.0, 30.0);
        if hi * dy < hedge_face(MOUNT_X + hi * dx) {
            return f64::INFINITY;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if mid * dy < hedge_face(MOUNT_X + mid * dx) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    } else if dy < -1e-3 && -2.5 / dy <= 30.0 {
        -2.5 / dy
    } else {
        f64::INFINITY
    }
}

/// The interval of r where `lo ≤ a + b r ≤ hi`.
fn slab(a: f64, b: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if b.abs() < 1e-15 {
        (a >= lo && a <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else {
        let (u, v) = ((lo - a) / b, (hi - a) / b);
        Some((u.min(v), u.max(v)))
    }
}

/// Inclined ranges from a robot at the origin: plants 0.16 m square, 0.3 m
/// tall, every 0.2 m in rows at y = ±0.375 m, with a few millimetres of noise.
fn rows_ranges(params: &FurrowParams) -> Vec<f64> {
    let (xm, h, p) = (
        params.mount_x.get(),
        params.mount_height.get(),
        params.mount_pitch.get(),
    );
    let increment = FOV / (RAYS as f64 - 1.0);
    (0..RAYS)
        .map(|j| {
            let a = -FOV / 2.0 + j as f64 * increment;
            let (dx, dy, c) = (a.cos() * p.cos(), a.sin(), a.cos() * p.sin());
            let mut best = h / c;
            for row in [-0.375, 0.375] {
                let Some((y0, y1)) = slab(0.0, dy, row - 0.08, row + 0.08) else {
                    continue;
                };
                let rz = (h - 0.3) / c;
                let mut k = 0;
                while (k as f64) * SPACING <= xm + dx * best + 0.1 {
                    let cx = k as f64 * SPACING;
                    if let Some((x0, x1)) = slab(xm, dx, cx - 0.08, cx + 0.08) {
                        let entry = y0.max(x0).max(rz).max(0.0);
                        if entry <= y1.min(x1) && entry < best {
                            best = entry;
                        }
                    }
                    k += 1;
                }
            }
            best + 0.005 * ((j as f64) * 12.9898).sin()
        })
        .collect()
}

fn guidance(c: &mut Criterion) {
    let horizontal: Vec<f64> = (0..RAYS)
        .map(|k| hedge_range(-PI + TAU * k as f64 / RAYS as f64))
        .collect();
    let inclined = rows_ranges(&FurrowParams::table2());
    let limits = RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap();
    let waypoints: Vec<Point2<World>> = (0..=400)
        .map(|i| Point2::new(0.5 * f64::from(i), 0.0).unwrap())
        .collect();
    let path = ReferencePath::<512>::from_waypoints(&waypoints, PathConfig::default()).unwrap();
    let params = GuidanceParams {
        edge: Some(
            EdgeFollowingParams::pierre2022(
                Side::Left,
                Transform2::<Sensor, Robot>::new(MOUNT_X, 0.0, 0.0).unwrap(),
            )
            .unwrap(),
        ),
        plan: Some(PlanCheck {
            tolerance: PlanTolerance::new(Meters::new(0.5).unwrap(), Radians::new(0.3).unwrap())
                .unwrap(),
            delay: Seconds::new(1.0).unwrap(),
        }),
        ..GuidanceParams::pierre2022_furrow().unwrap()
    };
    let config = GuidanceConfig::new(&params).unwrap();
    let mut pipeline = Guidance::<512>::new(config, &path).unwrap();
    let mut x = 0.0;
    let tick = |pipeline: &mut Guidance<'_, 512>, x: f64| {
        pipeline
            .step(&TickInput {
                horizontal: Some(EdgeScan {
                    start: Radians::new(-PI).unwrap(),
                    increment: Radians::new(TAU / RAYS as f64).unwrap(),
                    ranges: &horizontal,
                    limits,
                }),
                inclined: Some(FurrowScan {
                    ranges: &inclined,
                    angle_min: Radians::new(-FOV / 2.0).unwrap(),
                    angle_increment: Radians::new(FOV / (RAYS as f64 - 1.0)).unwrap(),
                }),
                gnss: Some(Pose2::<World>::new(x, 0.02, 0.01).unwrap()),
                odometry: Pose2::<Odom>::new(x, 0.0, 0.0).unwrap(),
                sideslip: Sideslip::new(0.01, -0.02).unwrap(),
            })
            .unwrap()
    };
    let mut last = None;
    for _ in 0..100 {
        last = Some(tick(&mut pipeline, x));
        x += SPACING;
    }
    let out = last.unwrap();
    eprintln!(
        "after warm-up: mode {:?}, edge {:?} (y {:?}), furrow {:?} (y {:?}), command {:?}",
        out.mode,
        out.edge.detected,
        out.edge.error.map(|e| e.y.get()),
        out.furrow.detected,
        out.furrow.error.map(|e| e.y.get()),
        out.command
    );
    assert_eq!(out.mode, ActiveMode::FurrowPursuing);
    assert!(out.edge.detected.estimate_is_valid());
    assert!(out.path.localisation_valid);

    c.bench_function("guidance/tick_360_horizontal_360_inclined", |b| {
        b.iter(|| {
            x += SPACING;
            black_box(tick(&mut pipeline, black_box(x)))
        });
    });
}

criterion_group!(benches, guidance);
criterion_main!(benches);
