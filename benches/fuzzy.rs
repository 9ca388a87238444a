//! Benchmark of Guyonneau 2022's fuzzy wheel-speed controller: one
//! evaluation (two inputs, 25 rules, two wheels) with the exact and the
//! sampled (N = 100) centroid, on 1 000 inputs drawn uniformly over
//! θ ∈ [−0.8, 0.8] rad and x ∈ [−1, 1]. FuzzyLite 6 times the same engine
//! on 1 000 inputs drawn the same way with `fuzzylite benchmark
//! tests/fuzzy/guyonneau2022.fll tests/fuzzy/bench_inputs.fld 10` (README.md,
//! "Benchmarks").
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss
)]

use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::control::fuzzy::Defuzzifier;
use fieldguide::control::fuzzy_rows::{FuzzyRowController, Orientation};
use fieldguide::MetersPerSecond;

/// 1 000 inputs from a fixed linear congruential sequence.
fn inputs() -> Vec<(f64, f64)> {
    let mut s = 12_345_u64;
    let mut next = || {
        s = s
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (s >> 11) as f64 / (1_u64 << 53) as f64
    };
    (0..1000)
        .map(|_| (-0.8 + 1.6 * next(), -1.0 + 2.0 * next()))
        .collect()
}

fn fuzzy(c: &mut Criterion) {
    let inputs = inputs();
    for (name, d) in [
        ("exact", Defuzzifier::Exact),
        ("sampled_100", Defuzzifier::Sampled { resolution: 100 }),
    ] {
        let controller = FuzzyRowController::authors(
            Orientation::SidesMeanSlope,
            d,
            MetersPerSecond::new(1.0).unwrap(),
        )
        .unwrap();
        let mut k = 0;
        c.bench_function(&format!("fuzzy/wheels_{name}"), |b| {
            b.iter(|| {
                k = (k + 1) % inputs.len();
                let (t, x) = inputs[k];
                black_box(controller.wheels(black_box(t), black_box(x)).unwrap())
            });
        });
    }
}

criterion_group!(benches, fuzzy);
criterion_main!(benches);
