//! Benchmark of Emmi 2024's mission supervisor: one tick of the pure machine
//! (`step`), one supervisor tick en route (localisation, events, step, no
//! planning), and one supervisor tick that starts a leg and plans it with
//! GoToGoal (README.md, "Benchmarks").
#![allow(missing_docs, clippy::unwrap_used)]

use core::f64::consts::PI;
use core::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use fieldguide::perception::obstacles::Hazard;
use fieldguide::supervisor::mission::{
    step, Events, Mission, MissionConfig, MissionInput, MissionState, Row, Task,
};
use fieldguide::{Meters, Pose2, Robot, World};

fn pose(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

fn mission() -> Mission {
    let road = Task::approximation(&[pose(20.0, 0.0, 0.0), pose(30.0, 10.0, PI / 2.0)]).unwrap();
    let rows: Vec<Row> = (0..16)
        .map(|k| Row {
            start: pose(40.0, 20.0 + 2.0 * f64::from(k), 0.0),
            length: Meters::new(20.0).unwrap(),
        })
        .collect();
    let field = Task::treatment(&rows).unwrap();
    Mission::new(MissionConfig::carob().unwrap(), &[road, field]).unwrap()
}

fn bench(c: &mut Criterion) {
    let config = MissionConfig::carob().unwrap();
    let shape =
        fieldguide::supervisor::mission::Shape::of(&[
            Task::approximation(&[pose(20.0, 0.0, 0.0)]).unwrap()
        ]);
    let state = MissionState::initial(&shape);
    c.bench_function("mission/step", |b| {
        b.iter(|| {
            step(
                &config.machine,
                &shape,
                black_box(&state),
                black_box(&Events::NOMINAL),
            )
        });
    });

    let input = |x: f64| MissionInput {
        gnss: Some(pose(x, 0.0, 0.0)),
        odometry: Pose2::<Robot>::new(0.05, 0.0, 0.0).unwrap(),
        hazard: Hazard::Clear,
        in_field: false,
        remaining: None,
    };
    // En route: the first leg is planned in the first tick, not measured.
    let mut started = mission();
    started.tick(&input(0.0));
    c.bench_function("mission/tick_en_route", |b| {
        b.iter_batched_ref(
            || started.clone(),
            |m| m.tick(black_box(&input(0.05))),
            BatchSize::SmallInput,
        );
    });
    // The tick that reaches the first waypoint and plans the GoToGoal turn.
    c.bench_function("mission/tick_planning_a_leg", |b| {
        b.iter_batched_ref(
            || started.clone(),
            |m| m.tick(black_box(&input(20.0))),
            BatchSize::SmallInput,
        );
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
