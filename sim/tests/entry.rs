//! Closed loop: entries without a swing (`spec/guidance.md`, GD-ENTRY) on
//! the stress field `sim/scenarios/stress/rows-offset-entry.toml`: maize then
//! beans whose rows start 0.3 m left of a straight A-B path. The same fields
//! and noise with and without the entry rule.
//!
//! Every figure is ground truth: the plants the tyres overlapped, and the
//! true pose against the plots' true centre lines.
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

/// Ten other fields and other noise.
const SEEDS: std::ops::RangeInclusive<u64> = 1..=10;

/// How far into a plot O's entry runs.
const ENTRY_M: f64 = 4.0;

fn run(seed: u64, with_rule: bool) -> (Setup, RunOutput) {
    let mut source = common::stress_source("rows-offset-entry");
    if !with_rule {
        source.text = common::without_key(&source.text, "entry_");
    }
    let (setup, mut rng): (Setup, SimRng) = runner::prepare_with_seed(&source, seed).unwrap();
    assert_eq!(setup.switching.entry.is_some(), with_rule);
    let out = runner::run(&setup, &mut rng);
    assert_eq!(out.end, RunEnd::PathEnd);
    (setup, out)
}

/// Over the first `ENTRY_M` metres O drives in each plot: how far the front
/// axle's middle swings past the rows' centre line to the side away from the
/// path (the rows start left of the path: the near row lies right of the
/// centre, so a swing past it is positive), m.
fn front_swing(setup: &Setup, out: &RunOutput) -> f64 {
    let l = setup.vehicle.wheelbase.get().get();
    out.trace
        .iter()
        .filter_map(|r| r.plot.filter(|p| p.s_m < ENTRY_M))
        .map(|p| p.lateral_error_m + l * p.angular_error_rad.sin())
        .fold(f64::NEG_INFINITY, f64::max)
}

//= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
//= type=test
//# While an entry closes on a behaviour the machine has not entered,
//# path tracking's error MUST be the error to the path shifted sideways by
//# that behaviour's line offset from the path plus the reference, changing by
//# the reference's change per metre seen from the path,
//# r'(d) + (1 − s(d)) tan h.
//= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
//= type=test
//# When an entry rule is configured, an entry MUST start from the robot's
//# lateral error to a behaviour's line in the first tick that line is usable
//# (a valid estimate consistent with the plan, with an offset from the path)
//# while path tracking commands, the first usable behaviour in priority order,
//# ending any hand-over in progress, or in the tick the machine enters a
//# behaviour no entry closes on; it MUST end when its closing shape reaches
//# zero in the behaviour, when the machine leaves the behaviour or stops, when
//# the line stops being usable before the machine entered (a hand-over then
//# starts from the shift, when a hand-over rule is configured) or when the
//# path is replaced.
#[test]
fn rows_0_3_m_off_the_path_are_entered_without_a_swing() {
    let (mut with, mut without) = (Vec::new(), Vec::new());
    for seed in SEEDS {
        let (setup, out) = run(seed, true);
        let (swing, crushed) = (front_swing(&setup, &out), out.plants_crushed);
        let (setup, out) = run(seed, false);
        let (swing_without, crushed_without) = (front_swing(&setup, &out), out.plants_crushed);
        println!(
            "seed {seed}: front axle past the centre {swing:.3} m, {crushed} crushed; without the rule {swing_without:.3} m, {crushed_without} crushed"
        );
        // Without the rule the front axle swung 0.2-0.3 m past the rows'
        // centre with FUR-LINE's late first line; with FUR-FIRST-LINE's, a
        // metre earlier, the swing is smaller, but the near-side wheel still
        // runs over the near row's first plants.
        assert!(swing < 0.1, "seed {seed}: {swing}");
        assert!(crushed < crushed_without, "seed {seed}");
        with.push(crushed);
        without.push(crushed_without);
    }
    println!("crushed with the rule {with:?}, without {without:?}");
    assert!(with.iter().sum::<usize>() * 2 < without.iter().sum::<usize>());
}
