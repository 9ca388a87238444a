//! The worst guidance tick, not only the typical one (`spec/library.md`,
//! LIB-BOUNDED-TICK): at least 10⁶ ticks of the full Pierre 2022 pipeline
//! (edge following, furrow pursuing, path tracking, the plan checked 2 m
//! ahead) on adversarial scans, each tick timed, beside the typical tick of
//! the `guidance` benchmark's field.
//!
//! Every tick gets both scans, drawn at random (seeded, so every run sees the
//! same sequence) from families that push each bounded loop to its bound:
//! - horizontal, 512 valid rays (the edge detector's capacity): the ragged
//!   hedge of the benchmark; a dense hedge (512 rays over 60°, so the chain
//!   fills its 64 links); a clutter blob (every point within 0.4 m, so every
//!   rotation step considers every point); clutter all round; garbage
//!   (NaN, ±∞, negative, out of range);
//! - inclined, 512 rays in the window (the furrow detector's capacity):
//!   the benchmark's two rows; a comb of narrow plants (a correlation maximum
//!   every few rays, so the maxima buffer fills and every pair is tried); random
//!   heights; garbage.
//!
//! The sequence runs `RUNS` times from a fresh pipeline. It is deterministic,
//! so tick i does the same work in every run, and the minimum over the runs
//! is its cost without the preemptions of a shared machine. The slowest
//! ticks are then timed `REPEATS` times more, each on a copy of the pipeline
//! as it was before the tick, for the ticks that a busy machine preempted in
//! every run. The raw maximum of each run is printed too. Run: `cargo bench --bench worst_tick`
//! (`WORST_TICKS=100000` for a shorter run).
#![allow(
    missing_docs,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss,
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    clippy::float_cmp
)]

use core::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI, TAU};
use core::hint::black_box;
use std::time::Instant;

use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::geometry::path::ReferencePath;
use fieldguide::guidance::{Guidance, GuidanceConfig, RoutedScan, TickInput};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::detector::AnyDetectorConfig;
use fieldguide::perception::furrow::FurrowParams;
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::presets::{Pierre2022, EDGE, FURROW};
use fieldguide::{Meters, Odom, Pose2, Radians, World};

mod common;

use common::furrow_common::{ridge_scan, Lidar, Ridge};

/// Runs of the whole sequence; a tick's cost is its minimum over them.
const RUNS: usize = 3;
/// The slowest ticks after the runs, timed again one by one.
const SLOWEST: usize = 2000;
/// Times each of them is timed again, each on a copy of the pipeline as it
/// was before that tick.
const REPEATS: usize = 15;
/// Variants drawn per family.
const VARIANTS: usize = 24;
/// Rays of every adversarial scan: the pipeline's edge points and furrow rays.
const RAYS: usize = 512;

/// xorshift64*: the sequence's only randomness.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn between(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// One scan's rays and angles, owned.
struct Owned {
    start: f64,
    increment: f64,
    ranges: Vec<f64>,
    limits: (f64, f64),
}

impl Owned {
    fn scan(&self) -> Scan<'_> {
        Scan {
            start: Radians::new(self.start).unwrap(),
            increment: Radians::new(self.increment).unwrap(),
            ranges: &self.ranges,
            limits: RangeLimits::new(
                Meters::new(self.limits.0).unwrap(),
                Meters::new(self.limits.1).unwrap(),
            )
            .unwrap(),
        }
    }
}

/// A garbage range: NaN, ±∞, negative, zero, beyond the limits or ordinary.
fn garbage_range(rng: &mut Rng) -> f64 {
    match rng.below(7) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -rng.between(0.0, 5.0),
        3 => 0.0,
        4 => 1e300,
        5 => f64::from_bits(rng.next()),
        _ => rng.between(0.05, 30.0),
    }
}

/// The horizontal scan's families (named in the report).
const HORIZONTAL: [&str; 5] = ["hedge", "dense hedge", "blob", "clutter", "garbage"];

/// A horizontal scan of family `family`, seen from the benchmark's mount.
fn horizontal(family: usize, rng: &mut Rng) -> Owned {
    // Range along the ray of angle a from the mount to the point (x, y).
    let towards = |a: f64| (a.cos(), a.sin());
    match family {
        0 => Owned {
            start: -PI,
            increment: TAU / 360.0,
            ranges: common::hedge_ranges(),
            limits: (0.05, 30.0),
        },
        1 => {
            // A straight hedge 1.0-1.6 m to the left, a few mm of noise, seen
            // by 512 rays over 60° around the left.
            let face = rng.between(1.0, 1.6);
            let start = FRAC_PI_2 - FRAC_PI_3 / 2.0;
            let increment = FRAC_PI_3 / (RAYS as f64 - 1.0);
            let ranges = (0..RAYS)
                .map(|k| {
                    let (_, dy) = towards(start + increment * k as f64);
                    face / dy + rng.between(-0.003, 0.003)
                })
                .collect();
            Owned {
                start,
                increment,
                ranges,
                limits: (0.05, 30.0),
            }
        }
        2 => {
            // Every point within 0.4 m of one spot 1.2 m to the left.
            let start = FRAC_PI_2 - 0.3;
            let increment = 0.6 / (RAYS as f64 - 1.0);
            let ranges = (0..RAYS).map(|_| rng.between(1.0, 1.8)).collect();
            Owned {
                start,
                increment,
                ranges,
                limits: (0.05, 30.0),
            }
        }
        3 => Owned {
            start: -PI,
            increment: TAU / RAYS as f64,
            ranges: (0..RAYS).map(|_| rng.between(0.3, 4.0)).collect(),
            limits: (0.05, 30.0),
        },
        _ => Owned {
            start: -PI,
            increment: TAU / RAYS as f64,
            ranges: (0..RAYS).map(|_| garbage_range(rng)).collect(),
            limits: (0.05, 30.0),
        },
    }
}

/// The inclined scan's families (named in the report).
const INCLINED: [&str; 4] = ["rows", "comb", "random heights", "garbage"];

/// An inclined scan of family `family`: 512 rays across the window of
/// `params` (the benchmark's 360 rays over 90° for the two rows).
fn inclined(family: usize, params: &FurrowParams, rng: &mut Rng) -> Owned {
    let half = params.window_half_angle.get() * 0.999;
    let lidar = Lidar::centred(RAYS, 2.0 * half);
    let cast = |ridges: &[Ridge]| ridge_scan(params, &lidar, (0.0, 0.0, 0.0), ridges);
    let (start, increment) = (lidar.angle_min, lidar.increment);
    let owned = |ranges| Owned {
        start,
        increment,
        ranges,
        limits: (0.1, 20.0),
    };
    match family {
        0 => {
            let ranges = common::rows_ranges(params);
            let scan = common::rows_scan(&ranges);
            Owned {
                start: scan.start.get(),
                increment: scan.increment.get(),
                ranges,
                limits: (0.1, 20.0),
            }
        }
        1 => {
            // Narrow plants every 4-12 cm across the whole view.
            let pitch = rng.between(0.04, 0.12);
            let ridges: Vec<Ridge> = (0..200)
                .map(|k| Ridge {
                    center_y: -6.0 + pitch * k as f64,
                    half_width: pitch * rng.between(0.2, 0.4),
                    height: rng.between(0.15, 0.5),
                })
                .filter(|r| r.center_y < 6.0)
                .collect();
            owned(cast(&ridges))
        }
        2 => {
            let flat = cast(&[]);
            owned(flat.iter().map(|r| r * rng.between(0.7, 1.0)).collect())
        }
        _ => owned((0..RAYS).map(|_| garbage_range(rng)).collect()),
    }
}

/// One tick's inputs: which variant of each family, and where the robot is.
#[derive(Clone, Copy)]
struct Draw {
    horizontal: (usize, usize),
    inclined: (usize, usize),
    x: f64,
    y: f64,
}

/// Times every tick of `draws` from a fresh pipeline, in nanoseconds.
fn run(
    draws: &[Draw],
    path: &ReferencePath<512>,
    config: &GuidanceConfig<AnyDetectorConfig, BacksteppingConfig, 2>,
    horizontal: &[Vec<Owned>],
    inclined: &[Vec<Owned>],
) -> Vec<u64> {
    let mut pipeline: Pierre2022<'_, 512> = Guidance::new(config.clone(), path).unwrap();
    let mut times = Vec::with_capacity(draws.len());
    for d in draws {
        let scans = scans(d, horizontal, inclined);
        let input = input(d, &scans);
        let begin = Instant::now();
        let out = pipeline.step(black_box(&input));
        let spent = begin.elapsed();
        black_box(out.unwrap());
        times.push(u64::try_from(spent.as_nanos()).unwrap_or(u64::MAX));
    }
    times
}

/// Times again each tick whose index is in `slowest` (sorted): `REPEATS`
/// times on a copy of the pipeline as it was before the tick, keeping the
/// minimum, which leaves out what preempted the tick in every run.
fn replay(
    draws: &[Draw],
    slowest: &[usize],
    path: &ReferencePath<512>,
    config: &GuidanceConfig<AnyDetectorConfig, BacksteppingConfig, 2>,
    horizontal: &[Vec<Owned>],
    inclined: &[Vec<Owned>],
) -> Vec<(usize, u64)> {
    let mut pipeline: Pierre2022<'_, 512> = Guidance::new(config.clone(), path).unwrap();
    let mut again = Vec::with_capacity(slowest.len());
    let mut next = slowest.iter().peekable();
    for (k, d) in draws.iter().enumerate() {
        let scans = scans(d, horizontal, inclined);
        let input = input(d, &scans);
        if next.peek() == Some(&&k) {
            next.next();
            let best = (0..REPEATS)
                .map(|_| {
                    let mut copy = pipeline.clone();
                    let begin = Instant::now();
                    let out = copy.step(black_box(&input));
                    let spent = begin.elapsed();
                    black_box(out.unwrap());
                    u64::try_from(spent.as_nanos()).unwrap_or(u64::MAX)
                })
                .min()
                .unwrap();
            again.push((k, best));
        }
        pipeline.step(&input).unwrap();
    }
    again
}

/// The two scans of the tick `d`.
fn scans<'a>(
    d: &Draw,
    horizontal: &'a [Vec<Owned>],
    inclined: &'a [Vec<Owned>],
) -> [RoutedScan<'a>; 2] {
    [
        RoutedScan {
            behaviour: EDGE,
            scan: horizontal[d.horizontal.0][d.horizontal.1].scan(),
        },
        RoutedScan {
            behaviour: FURROW,
            scan: inclined[d.inclined.0][d.inclined.1].scan(),
        },
    ]
}

/// The input of the tick `d` with its scans.
fn input<'a>(d: &Draw, scans: &'a [RoutedScan<'a>]) -> TickInput<'a, Sideslip> {
    TickInput {
        scans,
        gnss: Some(Pose2::<World>::new(d.x, d.y, 0.01).unwrap()),
        odometry: Pose2::<Odom>::new(d.x, 0.0, 0.0).unwrap(),
        extra: Sideslip::new(0.01, -0.02).unwrap(),
    }
}

/// The value at quantile `q` of sorted `values`.
fn quantile(sorted: &[u64], q: f64) -> u64 {
    let k = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[k]
}

fn micros(ns: u64) -> f64 {
    ns as f64 / 1000.0
}

fn main() {
    // `cargo bench` passes `--bench`; a test build runs nothing heavy.
    if !std::env::args().any(|a| a == "--bench") {
        return;
    }
    let ticks: usize = std::env::var("WORST_TICKS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let furrow = FurrowParams::table2();
    let mut rng = Rng(0x05ee_d0ff_1e1d);
    let horizontal: Vec<Vec<Owned>> = (0..HORIZONTAL.len())
        .map(|f| {
            (0..VARIANTS)
                .map(|_| self::horizontal(f, &mut rng))
                .collect()
        })
        .collect();
    let inclined: Vec<Vec<Owned>> = (0..INCLINED.len())
        .map(|f| {
            (0..VARIANTS)
                .map(|_| self::inclined(f, &furrow, &mut rng))
                .collect()
        })
        .collect();
    let path = common::straight_path();
    let config = GuidanceConfig::new(&common::pipeline_params()).unwrap();

    // The typical tick: the benchmark's field, the robot advancing one plant
    // spacing per tick so the scans stay valid.
    let typical: Vec<Draw> = (0..ticks.min(100_000))
        .map(|k| Draw {
            horizontal: (0, 0),
            inclined: (0, 0),
            x: (k % 500) as f64 * common::PLANT_SPACING,
            y: 0.02,
        })
        .collect();
    // Adversarial ticks: families and variants at random, the robot moving
    // along the path with a lateral error of up to ±1 m.
    let adversarial: Vec<Draw> = (0..ticks)
        .map(|k| {
            let hf = rng.below(HORIZONTAL.len());
            let inf = rng.below(INCLINED.len());
            Draw {
                horizontal: (hf, rng.below(VARIANTS)),
                inclined: (inf, rng.below(VARIANTS)),
                x: (k % 900) as f64 * 0.2,
                y: rng.between(-1.0, 1.0),
            }
        })
        .collect();

    let measure = |draws: &[Draw]| {
        let runs: Vec<Vec<u64>> = (0..RUNS)
            .map(|_| run(draws, &path, &config, &horizontal, &inclined))
            .collect();
        let raw_max: Vec<u64> = runs.iter().map(|r| *r.iter().max().unwrap()).collect();
        let mut best: Vec<u64> = (0..draws.len())
            .map(|k| runs.iter().map(|r| r[k]).min().unwrap())
            .collect();
        let mut order: Vec<usize> = (0..draws.len()).collect();
        order.sort_unstable_by_key(|&k| core::cmp::Reverse(best[k]));
        let mut slowest: Vec<usize> = order.into_iter().take(SLOWEST).collect();
        slowest.sort_unstable();
        for (k, t) in replay(draws, &slowest, &path, &config, &horizontal, &inclined) {
            best[k] = best[k].min(t);
        }
        (best, raw_max)
    };

    let (typical_best, typical_raw) = measure(&typical);
    let (best, raw) = measure(&adversarial);
    let mut typical_sorted = typical_best.clone();
    typical_sorted.sort_unstable();
    let mut sorted = best.clone();
    sorted.sort_unstable();
    let typical_median = quantile(&typical_sorted, 0.5);
    let worst = *sorted.last().unwrap();
    let worst_tick = best.iter().position(|&t| t == worst).unwrap();

    println!(
        "worst tick: {ticks} adversarial ticks, each the minimum of {RUNS} runs \
         (the {SLOWEST} slowest: of {REPEATS} more on a copy of the pipeline)"
    );
    println!(
        "typical tick ({} ticks): median {:.1} µs, max {:.1} µs (raw maxima per run {:?} µs)",
        typical.len(),
        micros(typical_median),
        micros(*typical_sorted.last().unwrap()),
        typical_raw.iter().map(|&t| micros(t)).collect::<Vec<_>>()
    );
    println!(
        "adversarial: median {:.1} µs, p99 {:.1} µs, p99.9 {:.1} µs, p99.99 {:.1} µs, max {:.1} µs (raw maxima per run {:?} µs)",
        micros(quantile(&sorted, 0.5)),
        micros(quantile(&sorted, 0.99)),
        micros(quantile(&sorted, 0.999)),
        micros(quantile(&sorted, 0.9999)),
        micros(worst),
        raw.iter().map(|&t| micros(t)).collect::<Vec<_>>()
    );
    let d = adversarial[worst_tick];
    println!(
        "worst tick {worst_tick}: horizontal {}, inclined {}",
        HORIZONTAL[d.horizontal.0], INCLINED[d.inclined.0]
    );
    println!(
        "worst / typical median: {:.2} (goal ≤ 5)",
        worst as f64 / typical_median as f64
    );
    // Per family pair, the median and the worst, to show which loop costs.
    println!("per family (horizontal × inclined): median / max µs");
    for (hf, hname) in HORIZONTAL.iter().enumerate() {
        for (inf, iname) in INCLINED.iter().enumerate() {
            let mut these: Vec<u64> = adversarial
                .iter()
                .zip(&best)
                .filter(|(d, _)| d.horizontal.0 == hf && d.inclined.0 == inf)
                .map(|(_, &t)| t)
                .collect();
            these.sort_unstable();
            if let Some(&max) = these.last() {
                println!(
                    "  {hname:>12} × {iname:<15} {:>7.1} / {:>7.1}",
                    micros(quantile(&these, 0.5)),
                    micros(max)
                );
            }
        }
    }
}
