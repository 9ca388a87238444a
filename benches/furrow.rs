//! Benchmark of furrow detection (Pierre 2022, section 2.3): one tick of the
//! detector on a 360-ray inclined scan of two rows of plants, generated
//! deterministically by `common::rows_ranges` (flat ground and square plants every 0.2 m in two
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
use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector, FurrowParams};
use fieldguide::{Odom, Pose2};

mod common;

use common::PLANT_SPACING as SPACING;

fn furrow(c: &mut Criterion) {
    let params = FurrowParams::table2();
    let ranges = common::rows_ranges(&params);
    let scan = common::rows_scan(&ranges);
    let config = FurrowConfig::new(&params).unwrap();
    let mut detector = FurrowDetector::<256, 32>::new(config).unwrap();
    // The world repeats every plant spacing: advancing the odometry by 0.2 m a
    // scan keeps the scan valid, so the accumulation fills as in the field.
    let mut x = 0.0;
    for _ in 0..30 {
        detector
            .detect(&scan, &Pose2::<Odom>::new(x, 0.0, 0.0).unwrap())
            .unwrap();
        x += SPACING;
    }
    let first = detector
        .detect(&scan, &Pose2::<Odom>::new(x, 0.0, 0.0).unwrap())
        .unwrap();
    assert!(first.verdict.estimate_is_valid(), "{first:?}");

    c.bench_function("furrow/step_two_rows_360_rays", |b| {
        b.iter(|| {
            x += SPACING;
            let odom = Pose2::<Odom>::new(x, 0.0, 0.0).unwrap();
            black_box(detector.detect(black_box(&scan), &odom).unwrap())
        });
    });
    c.bench_function("furrow/maxima_360_rays", |b| {
        b.iter(|| black_box(detector.maxima(black_box(&scan)).unwrap()));
    });
}

criterion_group!(benches, furrow);
criterion_main!(benches);
