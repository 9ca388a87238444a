//! Open loop: the core's furrow detector (Table 2 defaults) on the simulated
//! inclined LiDAR in the simulated maize and bean plots, the robot driven
//! along known straight paths at 0.7 m/s with drifting wheel odometry and a
//! scan every 0.1 s. What the detector reports is compared with the true
//! centre line. No controller and no scenario runner: the closed loop is
//! `furrow_pursuing.rs`, on the `furrow-pursuing` scenario.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::FurrowRig;
use fieldguide::perception::furrow::FurrowParams;
use fieldguide::{Point2, Pose2, Verdict, World};
use fieldguide_sim::world::crops::{scatter_grass, PlotSpec, Spread};
use fieldguide_sim::world::Plant;
use rand::rngs::StdRng;
use rand::SeedableRng;

/// Scans per second; 25 averaged scans then span 1.75 m of row at 0.7 m/s.
const RATE: f64 = 10.0;
/// Forward distance from the robot origin to where the scan meets the ground, m.
const LOOK_AHEAD: f64 = 4.0;

/// One tick of a run: where the robot truly was and what the detector said.
struct Tick {
    x: f64,
    y: f64,
    psi: f64,
    verdict: Verdict,
    estimate: Option<(f64, f64)>,
}

/// Drives along x from `(0, y0)` at heading `psi` for `distance` m among `plants`.
fn drive(plants: Vec<Plant>, y0: f64, psi: f64, distance: f64, seed: u64) -> Vec<Tick> {
    let mut rng = StdRng::seed_from_u64(seed);
    let mut rig = FurrowRig::new(plants, &FurrowParams::table2());
    let step = 0.7 / RATE;
    let mut pose = Pose2::<World>::new(0.0, y0, psi).unwrap();
    let mut ticks = Vec::new();
    while pose.position.x() < distance {
        let d = rig.detect(&pose, &mut rng);
        ticks.push(Tick {
            x: pose.position.x(),
            y: pose.position.y(),
            psi,
            verdict: d.verdict,
            estimate: d.error.map(|e| (e.y.get(), e.angular_deviation.get())),
        });
        let next = Pose2::<World>::new(
            pose.position.x() + step * psi.cos(),
            pose.position.y() + step * psi.sin(),
            psi,
        )
        .unwrap();
        rig.drive(&pose, &next, &mut rng);
        pose = next;
    }
    ticks
}

/// A straight plot along x, centre line y = 0, from x = −5 m.
fn plot(beans: bool, length: f64) -> PlotSpec {
    let start = Point2::new(-5.0, 0.0).unwrap();
    let mut p = if beans {
        PlotSpec::beans(start, 0.0, length)
    } else {
        PlotSpec::maize(start, 0.0, length)
    };
    p.bend_amplitude = 0.0;
    p
}

/// Mean and max |estimated − true lateral error|, mean |estimated − true θ̃|,
/// and the fraction of Enter, over the ticks past `from` m.
fn stats(ticks: &[Tick], from: f64) -> (f64, f64, f64, f64) {
    let used: Vec<&Tick> = ticks.iter().filter(|t| t.x >= from).collect();
    let with: Vec<(f64, f64)> = used
        .iter()
        .filter_map(|t| {
            t.estimate
                .map(|(y, th)| ((y - t.y).abs(), (th - t.psi).abs()))
        })
        .collect();
    let n = with.len() as f64;
    let enter =
        used.iter().filter(|t| t.verdict == Verdict::Enter).count() as f64 / used.len() as f64;
    (
        with.iter().map(|e| e.0).sum::<f64>() / n,
        with.iter().map(|e| e.0).fold(0.0, f64::max),
        with.iter().map(|e| e.1).sum::<f64>() / n,
        enter,
    )
}

#[test]
fn maize_and_beans_are_seen_where_they_are() {
    for beans in [false, true] {
        for (i, (y0, psi)) in [(0.0, 0.0), (0.08, 0.0), (-0.05, 0.01)]
            .into_iter()
            .enumerate()
        {
            let mut rng = StdRng::seed_from_u64(100 + i as u64);
            let plants = plot(beans, 40.0).generate(&mut rng);
            let ticks = drive(plants, y0, psi, 25.0, 7 + i as u64);
            // Past the first 2 m, where the accumulation fills.
            let (mean_y, max_y, mean_th, enter) = stats(&ticks, 2.0);
            let name = if beans { "beans" } else { "maize" };
            println!("{name} y0 {y0} psi {psi}: mean |dy| {mean_y:.3} max {max_y:.3} mean |dθ| {mean_th:.4} Enter {enter:.2}");
            assert!(enter > 0.8, "Enter on {enter} of the ticks");
            assert!(
                mean_y < if beans { 0.05 } else { 0.07 },
                "mean |dy| {mean_y}"
            );
            assert!(max_y < 0.2, "max |dy| {max_y}");
            assert!(mean_th < 0.03, "mean |dθ| {mean_th}");
        }
    }
}

#[test]
fn a_stretch_of_missing_plants_gives_exit_or_a_true_line() {
    let mut rng = StdRng::seed_from_u64(5);
    let mut spec = plot(false, 40.0);
    // 1.5 m with no plant, 15 m into the plot: x from 10 to 11.5.
    spec.bare = vec![(15.0, 16.5)];
    let ticks = drive(spec.generate(&mut rng), 0.0, 0.0, 20.0, 5);
    let mut lost = 0;
    for t in &ticks {
        // While the scan looks into the bare stretch.
        let view = t.x + LOOK_AHEAD;
        if (10.0..11.5).contains(&view) {
            match (t.verdict, t.estimate) {
                (Verdict::Enter | Verdict::Hold, Some((y, _))) => {
                    assert!((y - t.y).abs() < 0.15, "a wrong line at x {}: {y}", t.x);
                }
                (Verdict::Exit | Verdict::Absent, _) => lost += 1,
                other => panic!("{other:?}"),
            }
        }
    }
    assert!(lost >= 3, "only {lost} ticks without a line in the gap");
}

#[test]
fn grass_in_a_headland_never_holds_long() {
    let mut rng = StdRng::seed_from_u64(9);
    let grass = scatter_grass(
        ((-2.0, -3.0), (30.0, 3.0)),
        5.0,
        Spread::new(0.02, 0.01),
        Spread::new(0.1, 0.03),
        &mut rng,
    );
    let ticks = drive(grass, 0.0, 0.0, 25.0, 9);
    let (mut run, mut longest) = (0, 0);
    for t in &ticks {
        run = if t.verdict.estimate_is_valid() {
            run + 1
        } else {
            0
        };
        longest = longest.max(run);
    }
    // Table 2 waits 0.5 s (5 scans) before entering furrow pursuing.
    println!("grass: longest run of valid verdicts {longest} ticks");
    assert!(longest < 5, "{longest}");
}
