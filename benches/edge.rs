//! Benchmark of edge detection (Pierre 2022, section 2.2): one 360-ray scan
//! of a ragged hedge 1.4 m to the left of the robot (and another 2.5 m to
//! the right), converted, chained, fitted and graded.
#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::perception::edge::{detect, EdgeConfig, EdgeDetector, EdgeDetectorConfig, Side};
use fieldguide::{Odom, Pose2};

mod common;

fn edge(c: &mut Criterion) {
    let ranges = common::hedge_ranges();
    let scan = common::hedge_scan(&ranges);
    let mount = common::hedge_mount();
    let config = EdgeConfig::pierre2022().unwrap();
    let det = detect::<512, 256>(&scan, &mount, Side::Left, &config).unwrap();
    let fit = det.fit.expect("the hedge is detected");
    eprintln!(
        "chain: {} points, {:.2} m, {:?}; verdict {:?}; y = {:.3} m, θ̃ = {:.4} rad, σ = {:.3} m",
        det.chain.len(),
        det.chain.length().get(),
        det.chain.end(),
        det.verdict,
        fit.error.y.get(),
        fit.error.angular_deviation.get(),
        fit.quality.residual_std.get()
    );
    // Per tick, as a vehicle stack calls it: buffers owned by the detector.
    let mut detector = EdgeDetector::<512, 256>::new(EdgeDetectorConfig {
        edge: config,
        mount,
        side: Side::Left,
    });
    // The edge detector does not read the odometry pose.
    let odom = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    c.bench_function("edge/detector_360_rays_hedge", |b| {
        b.iter(|| detector.detect(black_box(&scan), &odom))
    });
    // The same through the free function, which returns the chain by value.
    c.bench_function("edge/detect_fn_360_rays_hedge", |b| {
        b.iter(|| detect::<512, 256>(black_box(&scan), &mount, Side::Left, &config))
    });
}

criterion_group!(benches, edge);
criterion_main!(benches);
