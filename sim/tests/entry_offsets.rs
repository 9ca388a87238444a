//! Closed loop: where both axles are when they reach a plot's first plants,
//! entering rows that lie off the path (`spec/guidance.md`, GD-ENTRY), on the
//! stress fields `sim/scenarios/stress/rows-offset-*.toml` over seeds.
//!
//! Every figure is ground truth: the true pose against the plots' true
//! centre lines, and the plants the tyres overlapped.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::cast_precision_loss
)]

mod common;

use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, RunEnd, RunOutput};
use fieldguide_sim::scenario::Setup;

/// The seeds, `ENTRY_SEEDS=a..=b` in the environment for a longer sweep.
fn seeds() -> std::ops::RangeInclusive<u64> {
    std::env::var("ENTRY_SEEDS")
        .ok()
        .and_then(|s| {
            let (a, b) = s.split_once("..=")?;
            Some(a.parse().ok()?..=b.parse().ok()?)
        })
        .unwrap_or(1..=5)
}

/// One plot's entry: the signed distance of the rear axle's middle (O) and
/// of the front axle's middle to the rows' centre line when each reaches the
/// first plants (abscissa 0 of the plot), m, positive to the left.
#[derive(Debug, Clone, Copy)]
struct AtEntry {
    rear: f64,
    front: f64,
}

/// The entry of every plot O drove into.
fn at_entry(setup: &Setup, out: &RunOutput) -> Vec<AtEntry> {
    let l = setup.vehicle.wheelbase.get().get();
    let plots = &setup.world.plots;
    let first = |point: &dyn Fn(&fieldguide_sim::runner::TickRecord) -> (f64, f64)| {
        plots
            .iter()
            .map(|plot| {
                out.trace.iter().find_map(|r| {
                    let (x, y) = point(r);
                    plot.spec.project(x, y).map(|q| q.lateral)
                })
            })
            .collect::<Vec<_>>()
    };
    let rear = first(&|r| (r.truth.position.x(), r.truth.position.y()));
    let front = first(&|r| {
        let h = r.truth.heading.get();
        (
            r.truth.position.x() + l * h.cos(),
            r.truth.position.y() + l * h.sin(),
        )
    });
    rear.into_iter()
        .zip(front)
        .filter_map(|(r, f)| {
            Some(AtEntry {
                rear: r?,
                front: f?,
            })
        })
        .collect()
}

fn run(name: &str, seed: u64) -> (Setup, RunOutput) {
    let mut source = common::stress_source(name);
    // `ENTRY_SET="key = value;..."`: other `[switching]` values (a sweep by hand).
    if let Ok(set) = std::env::var("ENTRY_SET") {
        for pair in set.split(';').filter(|p| !p.is_empty()) {
            let key = pair.split('=').next().unwrap().trim();
            source.text = common::without_key(&source.text, key);
            source.text.push_str(&format!("\n{pair}\n"));
        }
    }
    let (setup, mut rng): (Setup, SimRng) = runner::prepare_with_seed(&source, seed).unwrap();
    let out = runner::run(&setup, &mut rng);
    assert_eq!(out.end, RunEnd::PathEnd, "{name} seed {seed}");
    (setup, out)
}

fn sweep(name: &str) {
    let (mut rear, mut front, mut crushed) = (0.0_f64, 0.0_f64, Vec::new());
    for seed in seeds() {
        let (setup, out) = run(name, seed);
        let entries = at_entry(&setup, &out);
        assert_eq!(entries.len(), setup.world.plots.len(), "{name} seed {seed}");
        for e in &entries {
            rear = rear.max(e.rear.abs());
            front = front.max(e.front.abs());
        }
        println!(
            "{name} seed {seed}: {:?}, {} crushed",
            entries
                .iter()
                .map(|e| format!("rear {:+.3} front {:+.3}", e.rear, e.front))
                .collect::<Vec<_>>(),
            out.plants_crushed
        );
        crushed.push(out.plants_crushed);
    }
    println!(
        "{name}: worst |rear| {rear:.3} m, |front| {front:.3} m at the first plants; crushed {}-{}",
        crushed.iter().min().unwrap(),
        crushed.iter().max().unwrap()
    );
}

#[test]
fn rows_offset_entry() {
    sweep("rows-offset-entry");
}

#[test]
fn rows_offset_maize_beans() {
    sweep("rows-offset-maize-beans");
}

#[test]
fn rows_offset_right_slow() {
    sweep("rows-offset-right-slow");
}

#[test]
fn rows_offset_handover() {
    sweep("rows-offset-handover");
}

#[test]
fn debug_trace() {
    let Ok(name) = std::env::var("ENTRY_DEBUG") else {
        return;
    };
    let seed: u64 = std::env::var("ENTRY_DEBUG_SEED").unwrap().parse().unwrap();
    let (setup, out) = run(&name, seed);
    let plot = &setup.world.plots[0];
    let x0 = plot.spec.start.x();
    let mut last = String::new();
    for r in &out.trace {
        let x = r.truth.position.x() - x0;
        if !(-5.0..6.0).contains(&x) {
            continue;
        }
        let h = r.truth.heading.get();
        let l = setup.vehicle.wheelbase.get().get();
        let d = r.command.detector;
        let line = format!(
            "{:?} {} {:?} ref {:?}",
            r.command.mode,
            d.map_or("-".into(), |d| format!("{:?}", d.verdict)),
            d.and_then(|d| d.error).map(|e| (
                format!("{:.3}", e.y.get()),
                format!("{:.3}", e.angular_deviation.get())
            )),
            r.command.reference_offset.map(|o| format!("{o:.3}")),
        );
        if line != last || (r.t_s * 100.0).round() as i64 % 25 == 0 {
            println!(
                "t {:.2} x {:+.2} y {:+.3} h {:+.3} yf {:+.3} steer {:+.3} | {line}",
                r.t_s,
                x,
                r.truth.position.y(),
                h,
                r.truth.position.y() + l * h.sin(),
                r.steering_rad,
            );
            last = line;
        }
    }
}
