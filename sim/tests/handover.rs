//! Closed loop: hand-overs without a jolt (`spec/guidance.md`, GD-HANDOVER)
//! and the entry into plots whose rows lie off the path, on the stress fields
//! `sim/scenarios/stress/rows-offset-*.toml`: maize then beans beside a
//! straight A-B path, the rows bending 0.25-0.3 m away from it over 30 m.
//!
//! Every figure is ground truth: the plants the tyres' contact discs
//! overlapped, and the true pose against the plots' true centre lines.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::cast_precision_loss
)]

mod common;

use fieldguide::guidance::Mode;
use fieldguide_sim::guidance::pipeline::FURROW;
use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, RunEnd, RunOutput};
use fieldguide_sim::scenario::Setup;
use fieldguide_sim::world::PlantKind;

/// Ten other fields and other noise for each bound.
const SEEDS: std::ops::RangeInclusive<u64> = 1..=10;

/// How far into a plot its entry runs: the front axle (2 m ahead of O) meets
/// the first plants while furrow pursuing turns onto rows seen 4 m ahead.
const ENTRY_M: f64 = 3.0;

/// `name` with its text edited by `edit`, with `seed`.
fn prepare(name: &str, seed: u64, edit: impl FnOnce(String) -> String) -> (Setup, SimRng) {
    let mut source = common::stress_source(name);
    source.text = edit(source.text);
    runner::prepare_with_seed(&source, seed).unwrap()
}

fn run(setup: &Setup, rng: &mut SimRng) -> RunOutput {
    let out = runner::run(setup, rng);
    assert_eq!(out.end, RunEnd::PathEnd);
    out
}

/// Without the hand-over rule: `[switching]`'s hand-over lines removed.
fn without_handover(text: String) -> String {
    common::without_key(&text, "handover_")
}

/// The crop plants a tyre's contact disc overlapped, each as (plot index,
/// abscissa along that plot), by brute force over the trace.
fn crushed(setup: &Setup, out: &RunOutput) -> Vec<(usize, f64)> {
    let half_tyre = setup.vehicle.tyre_width_m / 2.0;
    let wheels: Vec<[[f64; 2]; 4]> = out
        .trace
        .iter()
        .map(|r| setup.vehicle.wheel_centres(&r.truth))
        .collect();
    setup
        .world
        .plants
        .iter()
        .filter(|p| p.kind == PlantKind::Crop)
        .filter(|p| {
            wheels.iter().flatten().any(|w| {
                (w[0] - p.position.x()).hypot(w[1] - p.position.y()) < p.radius + half_tyre
            })
        })
        .map(|p| {
            let (x, y) = (p.position.x(), p.position.y());
            setup
                .world
                .plots
                .iter()
                .enumerate()
                .find_map(|(i, plot)| plot.spec.project(x, y).map(|q| (i, q.s)))
                .unwrap()
        })
        .collect()
}

/// Distance O drives inside plot `i`, and the share of it furrow pursuing
/// steers.
fn furrow_share(out: &RunOutput, i: usize) -> (f64, f64) {
    let (mut all, mut furrow) = (0.0, 0.0);
    for w in out.trace.windows(2) {
        if w[0].plot.is_some_and(|p| p.index == i) {
            let d = w[1].distance_m - w[0].distance_m;
            all += d;
            if w[0].mode() == Mode::Behaviour(FURROW) {
                furrow += d;
            }
        }
    }
    (all, furrow / all)
}

/// Over the ticks path tracking steers with O inside a plot past its entry
/// (after the hand-over at its end): the largest distance of O and of the
/// front axle's middle from the rows' true centre line, m.
fn after_handover_excursion(setup: &Setup, out: &RunOutput) -> f64 {
    let l = setup.vehicle.wheelbase.get().get();
    out.trace
        .iter()
        .filter(|r| r.mode() == Mode::PathTracking)
        .filter_map(|r| r.plot.filter(|p| p.s_m > ENTRY_M))
        .map(|p| {
            p.lateral_error_m
                .abs()
                .max((p.lateral_error_m + l * p.angular_error_rad.sin()).abs())
        })
        .fold(0.0, f64::max)
}

/// The clearance the layout leaves on each side: the tyre's inner edge (half
/// the track less half the tyre) beyond the outer row's plants, for beans
/// (3 rows 0.375 m apart, plants 0.07 m in radius), the tighter crop.
fn layout_clearance(setup: &Setup) -> f64 {
    let v = &setup.vehicle;
    v.track_m / 2.0 - v.tyre_width_m / 2.0 - (0.375 + 0.07)
}

//= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
//= type=test
//# When a hand-over rule is configured and the machine leaves a behaviour, a
//# hand-over MUST start from the offset from the path of that behaviour's line
//# in the last tick the behaviour commanded; it MUST end when the shift reaches
//# zero, when a behaviour is entered or when the path is replaced.
#[test]
fn rows_bending_off_the_path_are_left_without_crushing_a_plant() {
    let mut without = Vec::new();
    for seed in SEEDS {
        let (setup, mut rng) = prepare("rows-offset-handover", seed, |t| t);
        let out = run(&setup, &mut rng);
        let crushed_with = crushed(&setup, &out);
        assert_eq!(out.plants_crushed, crushed_with.len());
        let excursion = after_handover_excursion(&setup, &out);
        println!(
            "seed {seed}: {} crushed; after the hand-over O and the front axle within {excursion:.3} m of the rows' centre",
            crushed_with.len()
        );
        assert!(crushed_with.is_empty(), "seed {seed}: {crushed_with:?}");
        // Never steered across a row: the axles stay within the clearance
        // the crop's layout leaves.
        assert!(
            excursion < layout_clearance(&setup),
            "seed {seed}: {excursion}"
        );
        for i in 0..2 {
            let (all, share) = furrow_share(&out, i);
            assert!(all > 29.0 && share > 0.85, "seed {seed}, plot {i}: {share}");
        }
        let (setup, mut rng) = prepare("rows-offset-handover", seed, without_handover);
        assert!(setup.switching.handover.is_none());
        let out = run(&setup, &mut rng);
        without.push(crushed(&setup, &out).len());
    }
    // Straight back to the A-B line, the wheels cross the rows' ends.
    println!("without the hand-over rule: {without:?} crushed");
    assert!(without.iter().all(|&n| n > 0), "{without:?}");
}

#[test]
fn the_issue_field_crushes_nothing_past_a_plot_entry() {
    for seed in SEEDS {
        let (setup, mut rng) = prepare("rows-offset-maize-beans", seed, |t| t);
        let out = run(&setup, &mut rng);
        let crushed = crushed(&setup, &out);
        println!("seed {seed}: crushed at (plot, s) {crushed:.2?}");
        // Seed 5 lost a bean 20.5 m into the beans to the detector's line
        // wobbling 0.1 m before the lines spanned 2.2 m of travel (FUR-SPAN).
        assert!(
            crushed.iter().all(|&(_, s)| s < ENTRY_M),
            "seed {seed}: {crushed:?}"
        );
        let excursion = after_handover_excursion(&setup, &out);
        assert!(
            excursion < layout_clearance(&setup),
            "seed {seed}: {excursion}"
        );
    }
}

#[test]
fn rows_0_3_m_off_the_path_are_locked_on() {
    let mut entry_crushes = Vec::new();
    let mut narrow_shares = Vec::new();
    for seed in SEEDS {
        let (setup, mut rng) = prepare("rows-offset-entry", seed, |t| t);
        let out = run(&setup, &mut rng);
        for i in 0..2 {
            let (all, share) = furrow_share(&out, i);
            assert!(all > 29.0 && share > 0.85, "seed {seed}, plot {i}: {share}");
        }
        let crushed = crushed(&setup, &out);
        // Within ENTRY_M of a plot's start, but for the bean line's swing (one
        // bean 22.6 m into the bean plot in seed 3: an open question of the
        // furrow detector, as seed 5 of `furrow-pursuing`).
        assert!(
            crushed.iter().filter(|&&(_, s)| s >= ENTRY_M).count() <= 1,
            "seed {seed}: {crushed:?}"
        );
        entry_crushes.push(crushed.len());
        // The built-in scenarios' ±20° window: the plant model fits only to
        // about 0.7 m beside the robot, and the far row (0.675 m) is lost
        // (without the entry rule, GD-ENTRY, as FUR-REACH measured it).
        let (setup, mut rng) = prepare("rows-offset-entry", seed, |t| {
            common::without_key(
                &t.replace(
                    "window_half_angle_deg = 30.0",
                    "window_half_angle_deg = 20.0",
                ),
                "entry_",
            )
        });
        let out = run(&setup, &mut rng);
        narrow_shares.push(furrow_share(&out, 0).1.min(furrow_share(&out, 1).1));
    }
    println!("entry crushes per seed (within {ENTRY_M} m of a plot's start): {entry_crushes:?}");
    println!("±20° window, least share of a plot in furrow pursuing: {narrow_shares:.2?}");
    // Fields lose a whole plot: the window is the cause (6 of 10 with
    // FUR-LINE's late first line, 4 with FUR-FIRST-LINE's).
    let lost = narrow_shares.iter().filter(|&&s| s < 0.5).count();
    assert!(lost >= 4, "{narrow_shares:?}");
}
