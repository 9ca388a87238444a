//! Benchmark of the rows detector (Guyonneau 2022): one tick per variant on
//! the paper's four crops, a 360-ray front LiDAR (0.1-4 m, σ = 1 cm) seen
//! from between two rows 0.75 m apart as the robot drives (the scans of
//! `tests/crop_scans`, the accuracy tests' ground truth).
//!
//! A tick's state depends on the scans before it, so the ticks run in the
//! order of a 30 m drive along 40 m rows, each timed alone. `cargo bench
//! --bench rows` prints, before the timings, the mean number of points after
//! Z* per crop and variant.
//!
//! `crop<n>/RGOP/find` times the line finder alone on the drive's Z*, in
//! order, and `crop<n>/RGOP/reference` the straightforward reference of the
//! tests (`tests/rows_reference`, the same outputs bit for bit) on the same
//! points: the ratio of the two, measured in one run, is the optimisation's.
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
use core::time::Duration;
use std::time::Instant;

use criterion::{criterion_group, Criterion};
use fieldguide::perception::rows::points::{
    merge_runs, scan_points, scan_points_with, Points, Rays,
};
use fieldguide::perception::rows::ruby::{Ruby, RubyConfig, RubyParams, Variant};
use fieldguide::perception::rows::{RowsConfig, RowsDetector, RowsParams};
use fieldguide::perception::Detector;
use fieldguide::{Odom, Pose2};

#[path = "../tests/crop_scans/mod.rs"]
mod crop_scans;
#[path = "../tests/rows_reference/mod.rs"]
mod rows_reference;

use crop_scans::{crop, Lidar, Mount, Pose, RawScan};
use rows_reference::Reference;

/// Scans at rest (the row distance), then scans along the drive.
const STILL: usize = 40;
const DRIVE: usize = 1200;

type Rows = RowsDetector<512>;

/// The detector once it follows the rows, the scans of a 30 m drive after
/// that, and the mean number of points after Z* over the drive.
fn drive(variant: Variant, n: usize) -> (Rows, Vec<(RawScan, Pose2<Odom>)>, f64) {
    let mut spec = crop(n, 1, 0.75);
    // 40 m rows, weeds as dense as on the 10 m preset.
    spec.weeds *= 4;
    spec.length = 40.0;
    let field = spec.build();
    let mount = Mount::front(0.3);
    let lidar = Lidar::paper();
    let params = RowsParams::authors(variant, mount.transform());
    let mut detector = Rows::new(RowsConfig::new(params).unwrap());
    let scan_at = |k: usize| {
        let along = 1.0 + 0.025 * k.saturating_sub(STILL) as f64;
        let robot =
            field
                .between(1, 2, along)
                .compose(&Pose::new(0.0, 0.05 * (along * 1.5).sin(), 0.0));
        let raw = field.cast(&robot, &mount, &lidar, k as u64);
        (
            raw,
            Pose2::<Odom>::new(robot.x, robot.y, robot.heading).unwrap(),
        )
    };
    // At rest until the row distance is known.
    for k in 0..10 * STILL {
        if detector.row_distance().is_some() {
            break;
        }
        let (raw, odometry) = scan_at(0);
        let _ = k;
        detector.observe(&raw.scan(), &odometry).unwrap();
    }
    assert!(
        detector.row_distance().is_some(),
        "{} crop {n}",
        variant.name()
    );
    let scans: Vec<_> = (STILL..STILL + DRIVE).map(scan_at).collect();
    let mut probe = detector.clone();
    let mut points = 0.0;
    for (raw, odometry) in &scans {
        probe.observe(&raw.scan(), odometry).unwrap();
        points += probe.points().len() as f64;
    }
    (detector, scans, points / DRIVE as f64)
}

fn rows(c: &mut Criterion) {
    let mut group = c.benchmark_group("rows");
    for n in 1..=4 {
        for variant in Variant::ALL {
            let (start, scans, points) = drive(variant, n);
            println!(
                "rows/crop{n}/{}: {points:.1} points after Z*",
                variant.name()
            );
            group.bench_function(format!("crop{n}/{}", variant.name()), |b| {
                // Scans in the order of the drive, the detector warm; at the
                // end of the drive (untimed) it starts again from the start.
                // The drive goes on from one sample to the next, so that
                // every sample, short or long, takes its ticks from the whole
                // drive in turn: a sample that always started at the drive's
                // start would weigh its first ticks by how many iterations
                // the warm-up chose.
                let mut detector = start.clone();
                let mut k = 0;
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        if k == scans.len() {
                            detector = start.clone();
                            k = 0;
                        }
                        let (raw, odometry) = &scans[k];
                        let scan = raw.scan();
                        let t = Instant::now();
                        black_box(detector.observe(black_box(&scan), odometry).unwrap());
                        total += t.elapsed();
                        k += 1;
                    }
                    total
                });
            });
        }
    }
    // The line finder alone, and the reference, on each crop's Z*.
    let mount = Mount::front(0.3).transform();
    let params = RubyParams::authors(Variant::Rgop);
    for n in 1..=4 {
        let (_, scans, _) = drive(Variant::Rgop, n);
        let z_star: Vec<Points<512>> = scans
            .iter()
            .map(|(raw, _)| {
                let mut points = Points::<512>::new();
                scan_points(&raw.scan(), &mount, &mut points).unwrap();
                merge_runs(&mut points, params.merge_distance);
                points
            })
            .collect();
        let config = RubyConfig::new(params).unwrap();
        group.bench_function(format!("crop{n}/RGOP/find"), |b| {
            let mut finder = Ruby::<512>::new(config);
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % z_star.len();
                black_box(finder.find(black_box(&z_star[k])))
            });
        });
        group.bench_function(format!("crop{n}/RGOP/reference"), |b| {
            let mut finder = Reference::new(params);
            let mut k = 0;
            b.iter(|| {
                k = (k + 1) % z_star.len();
                black_box(finder.find(black_box(&z_star[k])))
            });
        });
    }
    // The share of a tick spent making Z* (the rays to points and the
    // one-point merge, the rays' sines and cosines kept as the detector
    // keeps them), for the line finder's own cost.
    let (_, scans, _) = drive(Variant::Rgop, 4);
    let mut k = 0;
    group.bench_function("crop4/points_and_z_star", |b| {
        let mut points = Points::<512>::new();
        let mut rays = Rays::<512>::new();
        b.iter(|| {
            k = (k + 1) % scans.len();
            let scan = scans[k].0.scan();
            scan_points_with(black_box(&scan), &mount, &mut rays, &mut points).unwrap();
            merge_runs(
                &mut points,
                RubyParams::authors(Variant::Rgop).merge_distance,
            );
            black_box(points.len())
        });
    });
    group.finish();
}

/// The drive's ticks once, in order, from the detector that follows the
/// rows; the mean time per tick. Alone in its function for a profiler:
/// `valgrind --tool=callgrind --toggle-collect='*drive_once*'` counts the
/// instructions of these ticks alone.
#[inline(never)]
fn drive_once(start: &Rows, scans: &[(RawScan, Pose2<Odom>)]) -> Duration {
    let mut detector = start.clone();
    let t = Instant::now();
    for (raw, odometry) in scans {
        black_box(detector.observe(black_box(&raw.scan()), odometry).unwrap());
    }
    t.elapsed() / scans.len() as u32
}

criterion_group!(benches, rows);

/// `ROWS_DRIVE=<crop>/<variant>` (e.g. `4/RGOP`) runs that drive once and
/// prints its mean tick, without criterion: a deterministic workload for an
/// instruction count on a busy machine (`ROWS_REPEAT=<r>`: see below).
///
/// `ROWS_HASH=1` prints, for every variant and crop, a hash of the drive's
/// ticks: each tick's detection, the line finder's lines (with their points
/// and energies), the rows and the row distance, so that a change meant to
/// keep every output, bit for bit, can be checked by the same 20 hashes
/// before and after it.
fn main() {
    if std::env::var("ROWS_HASH").is_ok() {
        use core::hash::{Hash, Hasher};
        for variant in Variant::ALL {
            for n in 1..=4 {
                let (start, scans, _) = drive(variant, n);
                let mut detector = start.clone();
                let mut h = std::collections::hash_map::DefaultHasher::new();
                for (raw, odometry) in &scans {
                    let d = detector.observe_scans(&[raw.scan()], odometry).unwrap();
                    format!("{d:?}").hash(&mut h);
                    format!("{:?}", detector.line_finder().models()).hash(&mut h);
                    format!("{:?} {:?}", detector.rows(), detector.row_distance()).hash(&mut h);
                }
                println!("{} crop{n} {:016x}", variant.name(), h.finish());
            }
        }
        return;
    }
    if let Ok(which) = std::env::var("ROWS_DRIVE") {
        let (n, name) = which.split_once('/').expect("ROWS_DRIVE=<crop>/<variant>");
        let n: usize = n.parse().expect("a crop number");
        let variant = Variant::from_name(name).expect("a variant's name");
        let (start, scans, points) = drive(variant, n);
        let tick = drive_once(&start, &scans);
        println!(
            "crop{n}/{}: {} ticks, {points:.1} points, {tick:?} per tick",
            variant.name(),
            scans.len()
        );
        // `ROWS_REPEAT=<r>` drives it r more times, each tick timed alone:
        // the mean over the ticks of each one's least time, which a busy
        // machine's interruptions (a tick here, a tick there) leave out.
        let repeat: usize =
            std::env::var("ROWS_REPEAT").map_or(0, |r| r.parse().expect("a number"));
        if repeat > 0 {
            let mut least = vec![Duration::MAX; scans.len()];
            for _ in 0..repeat {
                let mut detector = start.clone();
                for ((raw, odometry), least) in scans.iter().zip(&mut least) {
                    let scan = raw.scan();
                    let t = Instant::now();
                    black_box(detector.observe(black_box(&scan), odometry).unwrap());
                    *least = (*least).min(t.elapsed());
                }
            }
            let mean = least.iter().sum::<Duration>() / scans.len() as u32;
            println!(
                "crop{n}/{}: {mean:?} per tick, each tick's least of {repeat}",
                variant.name()
            );
            // What timing a tick alone adds to it: a clock read and an
            // elapsed time, as the criterion benchmark takes them.
            let reads = 100_000_u32;
            let t = Instant::now();
            for _ in 0..reads {
                black_box(Instant::now().elapsed());
            }
            println!("one tick's timing: {:?}", t.elapsed() / reads);
        }
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
