//! Benchmark of edge detection (Pierre 2022, section 2.2): one 360-ray scan
//! of a ragged hedge 1.4 m to the left of the robot (and another 2.5 m to
//! the right), converted, chained, fitted and graded.
#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use core::f64::consts::{PI, TAU};
use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::perception::edge::{detect, EdgeConfig, EdgeDetector, RangeLimits, Scan, Side};
use fieldguide::{Meters, Radians, Robot, Sensor, Transform2};

/// The LiDAR's mount: 1.2 m ahead of the rear axle, facing forward.
const MOUNT_X: f64 = 1.2;

/// Lateral position of the left hedge's face at abscissa `x` (robot frame):
/// 1.4 m with a deterministic ragged profile of a few centimetres.
fn hedge_face(x: f64) -> f64 {
    1.4 - 0.04 * (3.1 * x).sin() - 0.03 * (7.7 * x + 1.0).sin() - 0.02 * (19.3 * x).sin()
}

/// Range along the ray of angle `a` (sensor = robot orientation) to the left
/// hedge (found by bisection on the ray), to a straight hedge 2.5 m to the
/// right, or +inf beyond 30 m.
fn range(a: f64) -> f64 {
    let (dx, dy) = (a.cos(), a.sin());
    if dy > 1e-3 {
        // Left: f(t) = t dy − face(MOUNT_X + t dx) changes sign once.
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
    } else if dy < -1e-3 {
        let t = -2.5 / dy;
        if t <= 30.0 {
            t
        } else {
            f64::INFINITY
        }
    } else {
        f64::INFINITY
    }
}

fn edge(c: &mut Criterion) {
    let increment = TAU / 360.0;
    let ranges: Vec<f64> = (0..360)
        .map(|k| range(-PI + increment * f64::from(k)))
        .collect();
    let scan = Scan {
        start: Radians::new(-PI).unwrap(),
        increment: Radians::new(increment).unwrap(),
        ranges: &ranges,
        limits: RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap(),
    };
    let mount = Transform2::<Sensor, Robot>::new(MOUNT_X, 0.0, 0.0).unwrap();
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
    let mut detector = EdgeDetector::<512, 256>::new(config, mount);
    c.bench_function("edge/detector_360_rays_hedge", |b| {
        b.iter(|| detector.detect(black_box(&scan), Side::Left))
    });
    // The same through the free function, which returns the chain by value.
    c.bench_function("edge/detect_fn_360_rays_hedge", |b| {
        b.iter(|| detect::<512, 256>(black_box(&scan), &mount, Side::Left, &config))
    });
}

criterion_group!(benches, edge);
criterion_main!(benches);
