//! Closed-loop tests of furrow pursuing (Pierre 2022, section 2.3) on the
//! built-in scenario `furrow-pursuing`: Table 2's configuration (0.7 m/s,
//! gain 0.8, plant model 15 rays × 0.3 m, 25 averaged scans, rows 0.66-0.9 m
//! apart) through a maize plot then a bean plot with slightly curved rows,
//! missing plants, a 1.5 m bare stretch and grass in the headlands, the
//! inclined LiDAR scanning at 10 Hz.
//!
//! Every error is ground truth: the true pose of O against the true centre
//! line of the rows followed (`PlotSpec::centre_line`), never the robot's
//! estimate.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

mod common;

use fieldguide::control::backstepping::Gains;
use fieldguide::guidance::Mode;
use fieldguide::perception::furrow::Rows;
use fieldguide::{MetersPerSecond, Precondition, Verdict};
use fieldguide_sim::guidance::pipeline::FURROW;
use fieldguide_sim::guidance::{Command, Guidance, TickInput};
use fieldguide_sim::metrics::{error_stats, in_plot_errors, summarize};
use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, RunEnd, RunOutput, TickRecord};
use fieldguide_sim::scenario::{Setup, Source};
use fieldguide_sim::world::PlantKind;

/// The paper: "a lateral error of less than 0.1 m"; the bounds.
const MEAN_BOUND_M: f64 = 0.05;
const MAX_BOUND_M: f64 = 0.1;

const SCENARIO: &str = "furrow-pursuing";

/// The built-in scenario's own seed.
const BUILTIN_SEED: u64 = 2022;

/// The seed sweep of the bounds: 100 other fields with other noise.
const SWEEP: std::ops::RangeInclusive<u64> = 1..=100;

// No seed may run over a crop plant; the smallest tyre-to-crop clearance
// is printed, since the rear-axle metrics cannot show how close a front
// tyre came.
//
// The closest is seed 5: 17-19 m into the beans the row detector's
// estimate is off the true centre line by up to 0.093 m, then 0.106 m, for
// about half a second each while its verdict stays Enter (a cluster of four
// wide beans, footprint radius 0.102-0.115 m, 2-3σ of the generator's
// 0.07 ± 0.015 m, lies in the LiDAR's view band then). Furrow pursuing
// follows it and the heading swings off the rows while O stays within
// 0.03 m of the centre line, moving the front axle 2 m ahead sideways. With
// Table 2's gains unscheduled the front-left tyre overlapped the 0.115 m
// bean of the left row at 21.1 m; with the gains scheduled for the
// steering (PT-SCHEDULE, the scenario's `[control.schedule]`) it clears it.

fn prepare() -> (Setup, SimRng) {
    runner::prepare(&Source::builtin(SCENARIO).unwrap()).unwrap()
}

fn run(setup: &Setup, rng: &mut SimRng) -> RunOutput {
    let out = runner::run(setup, rng);
    assert_eq!(
        out.end,
        RunEnd::PathEnd,
        "the run must reach the path's end"
    );
    out
}

/// Distance driven with O inside plot `i` in `mode`, and in all, metres.
fn plot_distance(out: &RunOutput, i: usize, mode: Option<Mode>) -> f64 {
    out.trace
        .windows(2)
        .filter(|w| w[0].plot.is_some_and(|p| p.index == i))
        .filter(|w| mode.is_none_or(|m| w[0].mode() == m))
        .map(|w| w[1].distance_m - w[0].distance_m)
        .sum()
}

#[test]
fn the_scenario_is_table_2_through_maize_then_beans() {
    let (setup, _) = prepare();
    let f = setup.furrow.unwrap();
    let p = f.detector.params();
    assert!((f.speed.get() - 0.7).abs() < 1e-12);
    assert!(
        (f.backstepping.gains.k_y() + 0.8).abs() < 1e-12,
        "k_y = -0.8"
    );
    assert!(
        (f.backstepping.gains.k_theta() + 3.2).abs() < 1e-12,
        "k_theta = 4 k_y, the path-tracking convention"
    );
    assert_eq!(p.template_width, 15);
    assert!((p.template_height.get() - 0.3).abs() < 1e-12);
    assert_eq!(p.averaged_scans, 25);
    let Rows::Two {
        min_spacing,
        max_spacing,
    } = p.rows
    else {
        panic!("two rows")
    };
    assert!((min_spacing.get() - 0.66).abs() < 1e-12 && (max_spacing.get() - 0.9).abs() < 1e-12);
    assert!((p.enter - 0.4).abs() < 1e-12 && (p.exit - 0.2).abs() < 1e-12);
    // The LiDAR scans at 10 Hz, every 10 control ticks of 0.01 s.
    assert_eq!(setup.lidar.unwrap().scan_every, 10);
    assert!((setup.control.period_s - 0.01).abs() < 1e-12);
    // Maize (2 rows 0.75 m apart) then beans (3 rows 0.375 m apart), bent rows,
    // missing plants, a 1.5 m bare stretch in the beans, grass in the headlands.
    let plots = &setup.world.plots;
    assert_eq!(plots.len(), 2);
    assert_eq!((plots[0].spec.rows, plots[1].spec.rows), (2, 3));
    assert!((plots[0].spec.row_spacing - 0.75).abs() < 1e-12);
    assert!((plots[1].spec.row_spacing - 0.375).abs() < 1e-12);
    assert!(plots
        .iter()
        .all(|p| p.spec.bend_amplitude > 0.0 && p.spec.missing > 0.0));
    assert_eq!(plots[1].spec.bare.len(), 1);
    let (a, b) = plots[1].spec.bare[0];
    assert!((b - a - 1.5).abs() < 1e-12);
    assert!(setup
        .world
        .plants
        .iter()
        .any(|p| p.kind == PlantKind::Grass));
    // The robot starts in the headland, before the first plot.
    let first = plots[0].spec.centre_line(0.0);
    assert!(setup.initial.position.x() < first.0 - 3.0);
}

//= spec/pierre2022.md#fur-two-rows-error-to-the-middle-of-two-rows
//= type=test
//# With two rows, the tracking error MUST be the mean of the errors to the
//# left and right lines: y = (y_l + y_r)/2 and θ̃ = (θ̃_l + θ̃_r)/2.
//= spec/pierre2022.md#fur-select-pair-two-rows-a-pair-within-the-spacing-closest-in-y
//= type=test
//# Only pairs of maxima whose lateral distance |m_{1,y} − m_{2,y}| lies in
//# [d_min, d_max] MUST be candidates.
//= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
//= type=test
//# Each selection MUST be stored in the odometry frame through the
//# odometry pose of its scan, and read back in the current robot frame
//# through the inverse of the current odometry pose.
#[test]
fn two_rows_are_followed_within_5_cm_on_average_and_10_cm_at_most() {
    // The built-in seed and the sweep; every seed is measured before any
    // bound is asserted, so a failure lists all the seeds that fail.
    let (mut means, mut maxes, mut crushed, mut shares) = (vec![], vec![], vec![], vec![]);
    let mut clearances = Vec::new();
    let mut failures = Vec::new();
    for seed in std::iter::once(BUILTIN_SEED).chain(SWEEP) {
        let (setup, mut rng) = common::prepare_seed(SCENARIO, seed);
        let out = runner::run(&setup, &mut rng);
        let mut fail = |what: String| failures.push(format!("seed {seed}: {what}"));
        if out.end != RunEnd::PathEnd {
            fail(format!("the run ended with {:?}", out.end));
        }
        for (i, plot) in setup.world.plots.iter().enumerate() {
            let Some(e) = error_stats(in_plot_errors(&out.trace, Some(i))) else {
                fail(format!("never inside {}", plot.name));
                continue;
            };
            let furrow = plot_distance(&out, i, Some(Mode::Behaviour(FURROW)));
            let all = plot_distance(&out, i, None);
            eprintln!(
                "seed {seed}, {}: |y| mean {:.4} m, max {:.4} m; furrow pursuing over {furrow:.1} of {all:.1} m",
                plot.name, e.mean_abs, e.max_abs
            );
            means.push((seed, e.mean_abs));
            maxes.push((seed, e.max_abs));
            shares.push((seed, 1.0 - furrow / all));
            if e.mean_abs >= MEAN_BOUND_M {
                fail(format!("{}: mean |y| {:.4} m", plot.name, e.mean_abs));
            }
            if e.max_abs >= MAX_BOUND_M {
                fail(format!("{}: max |y| {:.4} m", plot.name, e.max_abs));
            }
            // The rows, not the recorded path, steer through most of each plot:
            // path tracking stands in only where the scans see no rows (the
            // last 3-4 m of a plot, seen from 4 m behind, and the bare stretch).
            if all <= plot.spec.length - 0.5 || furrow <= 0.8 * all {
                fail(format!(
                    "{}: furrow pursuing over {furrow:.1} of {all:.1} m",
                    plot.name
                ));
            }
        }
        // In the beans, within 0.1 m of the centre line means the two outer
        // rows, 0.75 m apart, were paired: a pair of the middle row (0.375 m
        // from either, below d_min) and an outer one would be 0.19 m off.
        let summary = summarize(&setup, &out);
        let gap = clearance(&setup, &out);
        eprintln!(
            "seed {seed}: {} plants crushed; smallest tyre-to-crop clearance {gap:.4} m",
            summary.plants_crushed
        );
        crushed.push((seed, summary.plants_crushed as f64));
        clearances.push((seed, -gap));
        if summary.plants_crushed != 0 {
            fail(format!("{} plants crushed", summary.plants_crushed));
        }
        if !summary.success {
            fail(format!("not a success: {summary:?}"));
        }
        if !summary
            .converged_after_m
            .is_some_and(|d| d <= setup.metrics.converge_within_m)
        {
            fail(format!("converged after {:?} m", summary.converged_after_m));
        }
    }
    let (mean_seed, mean) = common::worst_of(means);
    let (max_seed, max) = common::worst_of(maxes);
    let (crushed_seed, most_crushed) = common::worst_of(crushed);
    let (share_seed, share) = common::worst_of(shares);
    let (gap_seed, gap) = common::worst_of(clearances);
    eprintln!(
        "furrow-pursuing, seeds {BUILTIN_SEED} and {}-{}: worst in-plot |y| (per plot): mean {mean:.4} m \
         (seed {mean_seed}), max {max:.4} m (seed {max_seed}); at most {most_crushed} plants crushed \
         (seed {crushed_seed}); smallest tyre-to-crop clearance {:.4} m (seed {gap_seed}); furrow pursuing over at least {:.1} % of a plot (seed {share_seed})",
        SWEEP.start(),
        SWEEP.end(),
        -gap,
        100.0 * (1.0 - share)
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The smallest clearance between a tyre's contact disc (the runner's
/// crushing model: a disc of the tyre width at each wheel centre) and a crop
/// plant's footprint over the run, metres; negative when they overlapped.
fn clearance(setup: &Setup, out: &RunOutput) -> f64 {
    let half_tyre = setup.vehicle.tyre_width_m / 2.0;
    let mut crops: Vec<&fieldguide_sim::world::Plant> = setup
        .world
        .plants
        .iter()
        .filter(|p| p.kind == PlantKind::Crop)
        .collect();
    crops.sort_by(|a, b| a.position.x().total_cmp(&b.position.x()));
    let reach = 1.0 + half_tyre;
    let mut smallest = f64::INFINITY;
    for r in &out.trace {
        for w in setup.vehicle.wheel_centres(&r.truth) {
            let from = crops.partition_point(|p| p.position.x() < w[0] - reach);
            let to = crops.partition_point(|p| p.position.x() < w[0] + reach);
            for p in &crops[from..to] {
                let gap =
                    (w[0] - p.position.x()).hypot(w[1] - p.position.y()) - p.radius - half_tyre;
                smallest = smallest.min(gap);
            }
        }
    }
    smallest
}

#[test]
fn the_rows_steer_not_the_recorded_path() {
    // A recorded path 0.2 m left of the plots' centre lines (a GNSS offset):
    // where furrow pursuing is in charge, the robot stays on the rows; where
    // path tracking stands in, it drifts towards the wrong path.
    let (mut setup, mut rng) = prepare();
    common::shift_recorded_path(&mut setup, 0.2);
    let out = run(&setup, &mut rng);
    // Furrow-pursuing ticks well inside the plots, 3 m after taking over.
    let mut checked = 0;
    for tick in common::settled_in(&out.trace, Mode::Behaviour(FURROW), 3.0) {
        if let Some(p) = tick.plot {
            assert!(p.lateral_error_m.abs() < MAX_BOUND_M / 2.0, "{p:?}");
            checked += 1;
        }
    }
    assert!(checked > 2000, "{checked} ticks checked");
    // At the end, after 6 m of path tracking in the run-out, the robot is on
    // the shifted path (0.2 m left of where the rows were).
    let last = out.trace.last().unwrap();
    assert_eq!(last.mode(), Mode::PathTracking);
    assert!(
        last.lateral_error_m.abs() < 0.05,
        "{}",
        last.lateral_error_m
    );
}

/// The ground stretch ahead of O where the LiDAR can hit a plant of height
/// up to `h`, metres from O along its heading: from where the centre ray
/// passes at height `h` to where it meets the ground (the window is ±20°, so
/// off-centre rays reach a few centimetres less far; widened by `margin`).
fn view_band(setup: &Setup, h: f64, margin: f64) -> (f64, f64) {
    let l = setup.lidar.unwrap().lidar;
    let near = l.mount_x + (l.height - h) / l.pitch.tan();
    let far = l.mount_x + l.height / l.pitch.tan();
    (near - margin, far + margin)
}

/// The scan ticks of a run with their true view band in world x (the plots
/// run east) and the detector's status.
fn scans(out: &RunOutput, band: (f64, f64)) -> Vec<(&TickRecord, f64, f64)> {
    out.trace
        .iter()
        .filter(|r| r.command.detector.is_some_and(|d| d.scanned))
        .map(|r| {
            let (x, h) = (r.truth.position.x(), r.truth.heading.get());
            (r, x + band.0 * h.cos(), x + band.1 * h.cos())
        })
        .collect()
}

//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//= type=test
//# Otherwise the verdict MUST be Exit when the scan yielded no selection,
//# and else the classification (SW-CLASSIFY, larger is better) of the
//# weaker score of the selection: min(c[k_l], c[k_r]) for a pair, c[k] for
//# one row.
#[test]
fn a_bare_stretch_gives_exit_or_absent_rather_than_a_wrong_line() {
    let (setup, mut rng) = prepare();
    let out = run(&setup, &mut rng);
    let beans = &setup.world.plots[1];
    let (a, b) = beans.spec.bare[0];
    let x0 = beans.spec.centre_line(0.0).0;
    let (gap_from, gap_to) = (x0 + a, x0 + b);
    let tallest = setup
        .world
        .plants
        .iter()
        .filter(|p| p.position.x() > x0 && p.kind == PlantKind::Crop)
        .map(|p| p.height)
        .fold(0.0, f64::max);
    // Scans whose whole view band (any plant height, 5 cm of margin for the
    // plants' radius and the range noise) lies in the bare stretch.
    let band = view_band(&setup, tallest, 0.05);
    let blind: Vec<_> = scans(&out, band)
        .into_iter()
        .filter(|(_, near, far)| *near >= gap_from && *far <= gap_to)
        .collect();
    eprintln!(
        "view band {:.2}-{:.2} m ahead; {} scans see only the bare stretch",
        band.0,
        band.1,
        blind.len()
    );
    assert!(blind.len() >= 3, "{} scans", blind.len());
    for (r, _, _) in &blind {
        let d = r.command.detector.unwrap();
        assert!(
            matches!(d.verdict, Verdict::Exit | Verdict::Absent),
            "t = {}: {:?}",
            r.t_s,
            d.verdict
        );
        assert_eq!(r.mode(), Mode::PathTracking, "t = {}", r.t_s);
    }
    // Around the stretch (the view band within 2 m of it), a scan that does
    // give a valid verdict gives the true line: its error is within 0.1 m of
    // the truth, where pairing the middle bean row with an outer one would be
    // 0.19 m off.
    let mut valid = 0;
    for (r, near, far) in scans(&out, view_band(&setup, tallest, 0.0)) {
        let d = r.command.detector.unwrap();
        if far < gap_from - 2.0 || near > gap_to + 2.0 || !d.verdict.estimate_is_valid() {
            continue;
        }
        let truth = r.plot.unwrap().lateral_error_m;
        let estimate = d.error.unwrap().y.get();
        assert!(
            (estimate - truth).abs() < 0.1,
            "t = {}: estimate {estimate}, truth {truth}",
            r.t_s
        );
        valid += 1;
    }
    assert!(valid > 20, "{valid}");
}

//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//= type=test
//# The verdict MUST be Absent when no row line could be fitted from the
//# accumulated points.
#[test]
fn no_command_comes_from_a_stale_or_invalid_estimate() {
    let (setup, mut rng) = prepare();
    let period = setup.control.period_s * setup.lidar.unwrap().scan_every as f64;
    let out = run(&setup, &mut rng);
    // In the headland, before the LiDAR reaches the maize, no line: Absent.
    // Table 2: 0.5 s (50 ticks) to enter, 0.7 m/s, path tracking 0.8 m/s.
    let furrow = common::Behaviour {
        mode: Mode::Behaviour(FURROW),
        enter_ticks: 50,
        speed: 0.7,
        path_speed: 0.8,
    };
    let verdicts = common::assert_commands_from_fresh_valid_estimates(&out.trace, period, &furrow);
    eprintln!("verdicts [enter, hold, exit, absent]: {verdicts:?}");
    // Table 2's thresholds with c_t = 0.5: every selection is Enter.
    assert!(verdicts[0] > 700 && verdicts[1] == 0 && verdicts[2] > 20 && verdicts[3] > 20);
}

/// Drives straight ahead at 0.7 m/s whatever the sensors say.
struct Straight;

impl Guidance for Straight {
    fn step(&mut self, _input: &TickInput<'_>) -> Result<Command, Precondition> {
        Ok(Command {
            drive: fieldguide::model::Command::Bicycle {
                speed: MetersPerSecond::new(0.7)?,
                steering: fieldguide::Radians::ZERO,
            },
            mode: Mode::PathTracking,
            label: "path_tracking",
            switching_mode: Mode::PathTracking,
            switching_label: "path_tracking",
            saturated: false,
            estimated_error: None,
            sideslip_used: fieldguide::model::bicycle::Sideslip::ZERO,
            detector: None,
            plan_pose: fieldguide::guidance::PlanPose::Unjudged,
            reference_offset: None,
            fix: fieldguide::guidance::FixUse::Fix,
        })
    }
}

/// The crop and grass plants a wheel's contact patch overlapped in `out`, by brute force.
fn touched(setup: &Setup, out: &RunOutput) -> (usize, usize) {
    let half_tyre = setup.vehicle.tyre_width_m / 2.0;
    let hit = |p: &fieldguide_sim::world::Plant| {
        out.trace.iter().any(|r| {
            setup.vehicle.wheel_centres(&r.truth).iter().any(|w| {
                (w[0] - p.position.x()).hypot(w[1] - p.position.y()) < p.radius + half_tyre
            })
        })
    };
    let count = |kind| {
        setup
            .world
            .plants
            .iter()
            .filter(|p| p.kind == kind && hit(p))
            .count()
    };
    (count(PlantKind::Crop), count(PlantKind::Grass))
}

#[test]
fn no_plant_is_run_over_and_the_counter_counts_crops_under_the_wheels() {
    let (setup, mut rng) = prepare();
    let out = run(&setup, &mut rng);
    assert_eq!(out.plants_crushed, 0);
    let (crops, grass) = touched(&setup, &out);
    eprintln!(
        "furrow pursuing: {crops} crop plants under a wheel, {grass} grass tufts (never counted)"
    );
    assert_eq!(crops, 0);
    // The same field driven straight east with the right wheels on the right
    // maize row (0.375 m right of the centre line): they crush it.
    let (mut blind, mut rng) = prepare();
    blind.initial = fieldguide::Pose2::new(
        blind.initial.position.x(),
        blind.world.plots[0].spec.centre_line(0.0).1 + blind.vehicle.track_m / 2.0 - 0.375,
        0.0,
    )
    .unwrap();
    blind.run.duration_s = 60.0;
    let out = runner::run_with(&blind, &mut Straight, &mut rng);
    let (crops, grass) = touched(&blind, &out);
    eprintln!("driven straight on a row: {} crop plants crushed ({crops} by brute force), {grass} grass tufts driven over", out.plants_crushed);
    assert!(out.plants_crushed > 100, "{}", out.plants_crushed);
    assert_eq!(out.plants_crushed, crops, "crops only, each once");
    assert!(
        grass > 0,
        "the run also drives over grass, which never counts"
    );
}

//= spec/pierre2022.md#pt-gains-gain-sign-and-ratio
//= type=test
//# Both gains MUST be finite and strictly negative (convergent in equation
//# form), and |k_θ| MUST be at least a configured ratio r ≥ 1 times |k_y|;
//# other gains MUST be refused at construction.
#[test]
fn a_wrong_furrow_gain_sign_leaves_the_rows() {
    let (mut setup, mut rng) = prepare();
    let good = setup.furrow.unwrap().backstepping.gains;
    assert!(Gains::new(-good.k_y(), -good.k_theta(), 2.0).is_err());
    setup.furrow.as_mut().unwrap().backstepping.gains =
        Gains::with_unchecked_sign(-good.k_y(), -good.k_theta(), 2.0).unwrap();
    let out = runner::run(&setup, &mut rng);
    let summary = summarize(&setup, &out);
    eprintln!(
        "wrong sign: end {:?}, in-plot {:?}, {} plants crushed",
        out.end, summary.in_plot_lateral_error_m, summary.plants_crushed
    );
    let worst = summary
        .in_plot_lateral_error_m
        .map_or(f64::INFINITY, |e| e.max_abs);
    assert!(worst > MAX_BOUND_M || summary.plants_crushed > 0 || out.end != RunEnd::PathEnd);
    assert!(!summary.success);
}

#[test]
fn same_seed_same_run() {
    let (a, mut ra) = prepare();
    let (b, mut rb) = prepare();
    assert_eq!(a.world.plants, b.world.plants);
    assert_eq!(runner::run(&a, &mut ra), runner::run(&b, &mut rb));
    // The override with the file's own seed is the built-in scenario itself;
    // another seed, another field.
    let (own, _) = common::prepare_seed(SCENARIO, BUILTIN_SEED);
    assert_eq!((a.seed, &a.world.plants), (BUILTIN_SEED, &own.world.plants));
    let (c, _) = common::prepare_seed(SCENARIO, 7);
    assert_ne!(a.world.plants, c.world.plants);
}

/// The same field on ground rising 2 % along the rows (each scan's ground
/// 4 m ahead stands 8 cm above the ground under the robot, which the
/// flat-ground detector reads as height): every bound still holds over
/// seeds 1-10. Steeper ground is beyond this detector: at 3 % two seeds of
/// ten run over plants, and at 4 % with 5 cm undulations every seed does
/// (the inclined LiDAR reads the rising ground as plants); levelling the
/// ground before the correlation is the vine-row detector's method.
#[test]
fn a_two_percent_slope_along_the_rows_keeps_every_bound() {
    for seed in 1..=10 {
        let (setup, mut rng) = common::prepare_edited(SCENARIO, seed, |t| {
            t.replacen("[terrain]\n", "[terrain]\nslope_x_percent = 2.0\n", 1)
        });
        assert!((setup.world.terrain.ground.slope[0] - 0.02).abs() < 1e-12);
        let out = run(&setup, &mut rng);
        let summary = fieldguide_sim::metrics::summarize(&setup, &out);
        assert!(summary.success, "seed {seed}: {summary:?}");
        assert_eq!(out.plants_crushed, 0, "seed {seed}");
    }
}
