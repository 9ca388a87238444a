//! One shortest Dubins path by this library, by the `dubins_paths` crate and
//! by OMPL's Dubins state space, side by side in one run on the same 1 000
//! pose pairs (x, y in [−20, 20] m, any headings, radius 1.48 m, the tracked
//! robot's track distance) (README.md, "Tracking and planning on a tracked
//! robot"; the goal: at least as fast as the faster peer).
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::cast_precision_loss,
    clippy::arithmetic_side_effects
)]

use core::f64::consts::PI;
use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use dubins_paths::f64::{DubinsPath as PeerPath, PosRot};
use fieldguide::planning::dubins::{shortest, TurningRadius};
use fieldguide::{Meters, Pose2};
use fieldguide_ompl::OmplDubins;

const RADIUS: f64 = 1.48;

/// 1 000 pose pairs from a fixed xorshift sequence.
fn pairs() -> Vec<([f64; 3], [f64; 3])> {
    let mut s = 0x2024_u64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1_u64 << 53) as f64
    };
    (0..1000)
        .map(|_| {
            let mut pose = || {
                [
                    40.0 * next() - 20.0,
                    40.0 * next() - 20.0,
                    2.0 * PI * next() - PI,
                ]
            };
            (pose(), pose())
        })
        .collect()
}

fn peers(c: &mut Criterion) {
    let pairs = pairs();
    let poses: Vec<_> = pairs
        .iter()
        .map(|(a, b)| {
            (
                Pose2::new(a[0], a[1], a[2]).unwrap(),
                Pose2::new(b[0], b[1], b[2]).unwrap(),
            )
        })
        .collect();
    let r = TurningRadius::new(Meters::new(RADIUS).unwrap()).unwrap();
    let mut group = c.benchmark_group("dubins_peers");
    let mut k = 0;
    group.bench_function("fieldguide", |b| {
        b.iter(|| {
            k = (k + 1) % poses.len();
            let (a, g) = &poses[k];
            black_box(shortest(black_box(a), black_box(g), r).unwrap().length())
        });
    });
    let rots: Vec<_> = pairs
        .iter()
        .map(|(a, b)| {
            (
                PosRot::from_floats(a[0], a[1], a[2]),
                PosRot::from_floats(b[0], b[1], b[2]),
            )
        })
        .collect();
    let mut k = 0;
    group.bench_function("dubins_paths", |b| {
        b.iter(|| {
            k = (k + 1) % rots.len();
            let (a, g) = rots[k];
            black_box(
                PeerPath::shortest_from(black_box(a), black_box(g), RADIUS)
                    .unwrap()
                    .length(),
            )
        });
    });
    let mut space = OmplDubins::new(RADIUS).unwrap();
    let mut k = 0;
    group.bench_function("ompl", |b| {
        b.iter(|| {
            k = (k + 1) % pairs.len();
            let (a, g) = pairs[k];
            black_box(space.shortest(black_box(a), black_box(g)).unwrap().length)
        });
    });
    group.finish();
}

criterion_group!(benches, peers);
criterion_main!(benches);
