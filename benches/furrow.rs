//! Benchmark of furrow detection (Pierre 2022, section 2.3): one tick of the
//! detector on a 360-ray inclined scan of two rows of plants, generated
//! deterministically here (flat ground and square plants every 0.2 m in two
//! rows 0.75 m apart, seen from the `FurrowParams::table2` mount).
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
use fieldguide::perception::furrow::scan::Scan;
use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector, FurrowParams};
use fieldguide::{Odom, Pose2, Radians};

const RAYS: usize = 360;
const FOV: f64 = core::f64::consts::FRAC_PI_2;
const SPACING: f64 = 0.2;

/// The interval of r where `lo ≤ a + b r ≤ hi`.
fn slab(a: f64, b: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    if b.abs() < 1e-15 {
        (a >= lo && a <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else {
        let (u, v) = ((lo - a) / b, (hi - a) / b);
        Some((u.min(v), u.max(v)))
    }
}

/// Ranges from a robot at the origin: plants 0.16 m square, 0.3 m tall, in rows at y = ±0.375 m.
fn scan_ranges(params: &FurrowParams) -> Vec<f64> {
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

fn furrow(c: &mut Criterion) {
    let params = FurrowParams::table2();
    let ranges = scan_ranges(&params);
    let scan = Scan {
        ranges: &ranges,
        angle_min: Radians::new(-FOV / 2.0).unwrap(),
        angle_increment: Radians::new(FOV / (RAYS as f64 - 1.0)).unwrap(),
    };
    let config = FurrowConfig::new(&params).unwrap();
    let mut detector = FurrowDetector::<256, 32>::new(config).unwrap();
    // The world repeats every plant spacing: advancing the odometry by 0.2 m a
    // scan keeps the scan valid, so the accumulation fills as in the field.
    let mut x = 0.0;
    for _ in 0..30 {
        detector
            .step(&scan, &Pose2::<Odom>::new(x, 0.0, 0.0).unwrap())
            .unwrap();
        x += SPACING;
    }
    let first = detector
        .step(&scan, &Pose2::<Odom>::new(x, 0.0, 0.0).unwrap())
        .unwrap();
    assert!(first.verdict.estimate_is_valid(), "{first:?}");

    c.bench_function("furrow/step_two_rows_360_rays", |b| {
        b.iter(|| {
            x += SPACING;
            let odom = Pose2::<Odom>::new(x, 0.0, 0.0).unwrap();
            black_box(detector.step(black_box(&scan), &odom).unwrap())
        });
    });
    c.bench_function("furrow/maxima_360_rays", |b| {
        b.iter(|| black_box(detector.maxima(black_box(&scan)).unwrap()));
    });
}

criterion_group!(benches, furrow);
criterion_main!(benches);
