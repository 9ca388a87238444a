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

use core::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use fieldguide::guidance::{Guidance, GuidanceConfig, Mode, RoutedScan, TickInput};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::furrow::FurrowParams;
use fieldguide::presets::{Pierre2022, EDGE, FURROW};
use fieldguide::{Odom, Pose2, World};

mod common;

use common::PLANT_SPACING as SPACING;

fn guidance(c: &mut Criterion) {
    let horizontal = common::hedge_ranges();
    let inclined = common::rows_ranges(&FurrowParams::table2());
    let path = common::straight_path();
    let params = common::pipeline_params();
    let config = GuidanceConfig::new(&params).unwrap();
    let mut pipeline: Pierre2022<'_, 512> = Guidance::new(config, &path).unwrap();
    let mut x = 0.0;
    let tick = |pipeline: &mut Pierre2022<'_, 512>, x: f64| {
        pipeline
            .step(&TickInput {
                scans: &[
                    RoutedScan {
                        behaviour: EDGE,
                        scan: common::hedge_scan(&horizontal),
                    },
                    RoutedScan {
                        behaviour: FURROW,
                        scan: common::rows_scan(&inclined),
                    },
                ],
                gnss: Some(Pose2::<World>::new(x, 0.02, 0.01).unwrap()),
                odometry: Pose2::<Odom>::new(x, 0.0, 0.0).unwrap(),
                extra: Sideslip::new(0.01, -0.02).unwrap(),
            })
            .unwrap()
    };
    let mut last = None;
    for _ in 0..100 {
        last = Some(tick(&mut pipeline, x));
        x += SPACING;
    }
    let out = last.unwrap();
    let edge = out.behaviour(EDGE).expect("edge following is configured");
    let furrow = out
        .behaviour(FURROW)
        .expect("furrow pursuing is configured");
    eprintln!(
        "after warm-up: mode {:?}, edge {:?} (y {:?}), furrow {:?} (y {:?}), command {:?}",
        out.mode,
        edge.detected,
        edge.error.map(|e| e.y.get()),
        furrow.detected,
        furrow.error.map(|e| e.y.get()),
        out.command
    );
    assert_eq!(out.mode, Mode::Behaviour(FURROW));
    assert!(edge.detected.estimate_is_valid());
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
