//! The rows detector on exact synthetic crops (Guyonneau 2022, section 4;
//! `spec/guyonneau2022.md`): the paper's four crops at three row spacings,
//! the robot standing still while it measures the row distance, then
//! driving along two rows with a smooth weave, every scan ray-cast from the
//! ground truth with σ = 1 cm of range noise.
//!
//! The figure is the share of scans in which both rows either side of the
//! robot are found within 5 cm (at the robot and 2 m ahead) of the truth,
//! and the error of the lateral offset to the middle line. The stems' near
//! faces put each row's line about one stem radius (2 cm) inside the row's
//! centre line; the detector reports the faces it sees, and the bias cancels
//! in the middle line, which is what the robot follows.
//!
//! `cargo test --release --test rows_accuracy -- --nocapture` prints the
//! table the README quotes.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp,
    clippy::cast_precision_loss
)]

mod crop_scans;

use core::f64::consts::TAU;

use crop_scans::{crop, crop4, uneven, Field, FieldSpec, Lidar, Line, Mount, Pose};
use fieldguide::perception::rows::ruby::Variant;
use fieldguide::perception::rows::{RowsConfig, RowsDetector, RowsParams};
use fieldguide::{Odom, Pose2};

/// The most scans the robot waits at rest for the row distance (the
/// initialisation averages 10 scans that show a pair of rows).
const MAX_STILL_SCANS: usize = 60;
/// Scans while driving: 7.5 m at 2.5 cm per scan (1 m/s at 40 Hz).
const DRIVE_SCANS: usize = 300;

/// How the robot drives and what its LiDARs see.
#[derive(Debug, Clone, Copy)]
struct Drive {
    /// Distance per scan, m (speed / 40 Hz).
    step: f64,
    /// Scans driven.
    scans: usize,
    /// The weave: lateral amplitude, m, and wavelength, m.
    weave: (f64, f64),
    /// Scans (counted from the start of the drive) in which every LiDAR is
    /// blind (every range NaN).
    blind: (usize, usize),
    /// The LiDARs' distance ahead of (and behind) O, m.
    mount: f64,
}

/// The paper's drive: 1 m/s, a weave of ±6 cm over 4 m, LiDARs 0.3 m from O.
const PAPER: Drive = Drive {
    step: 0.025,
    scans: DRIVE_SCANS,
    weave: (0.06, 4.0),
    blind: (0, 0),
    mount: 0.3,
};
/// The tolerance on a row, m.
const TOLERANCE: f64 = 0.05;

/// One campaign's tally.
#[derive(Debug, Default, Clone, Copy)]
struct Tally {
    scans: usize,
    both_found: usize,
    estimate: usize,
    worst_offset: f64,
    sum_sq_offset: f64,
    /// Drives whose row distance was never measured at rest.
    unmeasured: usize,
    /// Estimates whose offset is off by more than the tolerance.
    beyond: usize,
}

impl Tally {
    fn add(&mut self, other: &Self) {
        self.scans += other.scans;
        self.both_found += other.both_found;
        self.estimate += other.estimate;
        self.worst_offset = self.worst_offset.max(other.worst_offset);
        self.sum_sq_offset += other.sum_sq_offset;
        self.unmeasured += other.unmeasured;
        self.beyond += other.beyond;
    }

    /// The share of estimates off by more than the tolerance, %.
    fn beyond_share(&self) -> f64 {
        100.0 * self.beyond as f64 / self.estimate.max(1) as f64
    }

    fn share(&self) -> f64 {
        100.0 * self.both_found as f64 / self.scans as f64
    }

    fn rms_mm(&self) -> f64 {
        1000.0 * (self.sum_sq_offset / self.estimate.max(1) as f64).sqrt()
    }
}

/// The robot's pose `k` scans into the drive, between rows 1 and 2: the
/// weave ramps in over the first metre, so the robot starts parallel to the
/// rows and midway between them, as the paper's initialisation assumes.
fn pose(field: &Field, drive: &Drive, k: usize) -> Pose {
    let (amp, wave) = drive.weave;
    // A smooth ramp (3t² − 2t³): no step in heading where the weave starts.
    let ramp = |u: f64| {
        let t = u.min(1.0);
        t * t * (3.0 - 2.0 * t)
    };
    let lateral = |u: f64| amp * ramp(u) * (TAU * u / wave).sin();
    let u = drive.step * k as f64;
    let h = 1e-4;
    let heading =
        ((lateral(u + h) - lateral((u - h).max(0.0))) / (u + h - (u - h).max(0.0))).atan();
    field
        .between(1, 2, 1.0 + u)
        .compose(&Pose::new(0.0, lateral(u), heading))
}

/// Whether `found` lies within the tolerance of `truth` at x = 0 and 2 m.
fn near(found: (f64, f64), truth: &Line) -> bool {
    [0.0, 2.0]
        .iter()
        .all(|&x| (found.0 * x + found.1 - truth.y(x)).abs() <= TOLERANCE)
}

/// One drive of `variant` over crop `n` at `spacing`, with the front LiDAR
/// alone or the front and back ones.
fn campaign(variant: Variant, n: usize, spacing: f64, seed: u64, both_lidars: bool) -> Tally {
    let t = drive(variant, &crop(n, seed, spacing), &PAPER, seed, both_lidars);
    assert_eq!(
        t.unmeasured,
        0,
        "{} crop {n} spacing {spacing} seed {seed}: no row distance at rest",
        variant.name()
    );
    t
}

/// One drive of `variant` over `spec`.
fn drive(variant: Variant, spec: &FieldSpec, drive: &Drive, seed: u64, both_lidars: bool) -> Tally {
    let field = spec.build();
    let mut blind_verdicts = Vec::new();
    let lidar = Lidar::paper();
    let mounts: Vec<Mount> = if both_lidars {
        vec![Mount::front(drive.mount), Mount::back(drive.mount)]
    } else {
        vec![Mount::front(drive.mount)]
    };
    let mut params = RowsParams::authors(variant, mounts[0].transform());
    if both_lidars {
        params = params.with_second(mounts[1].transform());
    }
    params.ruby.seed = seed;
    let mut detector: RowsDetector<1024> = RowsDetector::new(RowsConfig::new(params).unwrap());
    let mut tally = Tally::default();
    let mut still = 0;
    let mut k = 0;
    while k < drive.scans {
        let robot = pose(&field, drive, k);
        let mut raws: Vec<_> = mounts
            .iter()
            .enumerate()
            .map(|(i, m)| {
                field.cast(
                    &robot,
                    m,
                    &lidar,
                    seed * 10_007 + ((k + still) * 2 + i) as u64,
                )
            })
            .collect();
        if (drive.blind.0..drive.blind.1).contains(&k) {
            for r in &mut raws {
                r.ranges.iter_mut().for_each(|x| *x = f64::NAN);
            }
        }
        let scans: Vec<_> = raws.iter().map(|r| r.scan()).collect();
        let odometry = Pose2::<Odom>::new(robot.x, robot.y, robot.heading).unwrap();
        let out = detector.observe_scans(&scans, &odometry).unwrap();
        // The robot waits at rest until the row distance is known.
        if k == 0 && out.outcome.is_none() {
            still += 1;
            if still == MAX_STILL_SCANS {
                // Never measured: the robot never drives, and no scan of
                // the drive found its rows.
                return Tally {
                    scans: drive.scans,
                    unmeasured: 1,
                    ..Tally::default()
                };
            }
            continue;
        }
        k += 1;
        tally.scans += 1;
        if (drive.blind.0..drive.blind.1).contains(&(k - 1)) {
            blind_verdicts.push(out.detection.verdict);
        }
        let (left, right) = (
            field.left_row(&robot).unwrap().1,
            field.right_row(&robot).unwrap().1,
        );
        if let Some(rows) = detector.rows() {
            let sides = fieldguide::perception::rows::filter::side_rows(rows);
            if let Some(p) = sides {
                let l = (p.left.slope(), p.left.intercept().get());
                let r = (p.right.slope(), p.right.intercept().get());
                if near(l, &left) && near(r, &right) {
                    tally.both_found += 1;
                }
            }
        }
        if let (Some(error), true) = (
            out.detection.error,
            out.detection.verdict.estimate_is_valid(),
        ) {
            let middle = field.middle_line(&robot).unwrap();
            let truth = -middle.b / (1.0 + middle.a * middle.a).sqrt();
            let off = (error.y.get() - truth).abs();
            tally.estimate += 1;
            tally.beyond += usize::from(off > TOLERANCE);
            tally.worst_offset = tally.worst_offset.max(off);
            tally.sum_sq_offset += off * off;
        }
    }
    // A blind LiDAR never gives an estimate: the verdict says the rows were
    // not seen (Exit), or lost (Absent) when the blindness outlasts the
    // filter's patience.
    assert!(
        blind_verdicts.iter().all(|v| !v.estimate_is_valid()),
        "blind scans gave {blind_verdicts:?}"
    );
    tally
}

/// Every crop at three spacings and three seeds.
fn sweep(variant: Variant, both_lidars: bool) -> [Tally; 4] {
    let mut out = [Tally::default(); 4];
    for (i, t) in out.iter_mut().enumerate() {
        for seed in 0..3 {
            for spacing in [0.75, 1.1, 1.5] {
                t.add(&campaign(variant, i + 1, spacing, seed, both_lidars));
            }
        }
    }
    out
}

fn row(variant: Variant, tallies: &[Tally; 4]) -> String {
    let mut all = Tally::default();
    let mut line = format!("| {:7} |", variant.name());
    for t in tallies {
        all.add(t);
        line += &format!(" {:5.1} % |", t.share());
    }
    line += &format!(
        " {:5.1} % | {:4.1} | {:4.2} % | {:4.0} |",
        all.share(),
        all.rms_mm(),
        all.beyond_share(),
        1000.0 * all.worst_offset
    );
    line
}

/// RGOP, the paper's best, finds both rows either side within 5 cm in at
/// least 99 % of scans on every crop, weeds and holes included, with the
/// front LiDAR alone; its lateral offset to the middle line has an RMS error
/// within 1 cm, and at most 0.5 % of its estimates are off by more than
/// 5 cm, none by more than 10 cm.
#[test]
fn rgop_finds_both_neighbouring_rows_in_99_percent_of_scans() {
    let tallies = sweep(Variant::Rgop, false);
    for (i, t) in tallies.iter().enumerate() {
        let crop = i + 1;
        assert!(
            t.share() >= 99.0,
            "crop {crop}: {:.2} % of {} scans",
            t.share(),
            t.scans
        );
        assert!(
            t.estimate * 100 >= t.scans * 99,
            "crop {crop}: {} estimates",
            t.estimate
        );
        assert!(t.rms_mm() <= 10.0, "crop {crop}: {:.1} mm RMS", t.rms_mm());
        assert!(
            t.beyond_share() <= 0.5,
            "crop {crop}: {:.2} % beyond 5 cm",
            t.beyond_share()
        );
        assert!(
            t.worst_offset <= 0.1,
            "crop {crop}: {:.3} m",
            t.worst_offset
        );
    }
}

/// The README's table: every variant, one LiDAR and two. Each variant keeps
/// the rows in most scans; the figures are printed for the README.
#[test]
fn table_of_every_variant() {
    for both in [false, true] {
        println!(
            "{}\n| variant | crop 1 | crop 2 | crop 3 | crop 4 | all | offset RMS (mm) | offset > 5 cm | worst (mm) |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
            if both { "front and back LiDARs" } else { "front LiDAR" }
        );
        for v in Variant::ALL {
            let t = sweep(v, both);
            println!("{}", row(v, &t));
            let verdicts_ok = t.iter().all(|x| x.scans == DRIVE_SCANS * 9);
            assert!(verdicts_ok);
            let mut all = Tally::default();
            for x in &t {
                all.add(x);
            }
            assert!(all.share() >= 80.0, "{}: {:.1} %", v.name(), all.share());
        }
    }
}

/// An own field: its name, its field from a seed and a spacing, the drive,
/// and the least share of scans with both rows found, %.
type OwnField = (&'static str, fn(u64, f64) -> FieldSpec, Drive, f64);

/// Fields written apart from the built-in crops, the way a real farm
/// differs: rows sown unevenly and not quite parallel, a faster robot
/// weaving more, LiDARs mounted farther out, and the LiDAR blinded (dust,
/// a leaf on the window) for a quarter of a second in the middle of the
/// row. RGOP on the front LiDAR alone.
#[test]
fn own_fields_beyond_the_paper() {
    let fast = Drive {
        step: 0.0625,
        scans: 110,
        weave: (0.1, 3.0),
        ..PAPER
    };
    let far = Drive {
        mount: 0.8,
        ..PAPER
    };
    let blind = Drive {
        blind: (120, 130),
        ..PAPER
    };
    let cases: [OwnField; 4] = [
        ("uneven rows", uneven, PAPER, 95.0),
        ("2.5 m/s, ±10 cm weave", crop4, fast, 95.0),
        ("LiDAR 0.8 m ahead", crop4, far, 0.0),
        ("blind 0.25 s", crop4, blind, 95.0),
    ];
    println!("| field | both rows within 5 cm | drives never started | offset RMS (mm) | offset > 5 cm | worst (mm) |\n| --- | --- | --- | --- | --- | --- |");
    for (name, field, d, bound) in cases {
        let mut all = Tally::default();
        for seed in 0..3 {
            for spacing in [0.75, 1.1, 1.5] {
                all.add(&drive(
                    Variant::Rgop,
                    &field(seed, spacing),
                    &d,
                    seed,
                    false,
                ));
            }
        }
        println!(
            "| {name} | {:5.1} % | {} of 9 | {:4.1} | {:4.2} % | {:4.0} |",
            all.share(),
            all.unmeasured,
            all.rms_mm(),
            all.beyond_share(),
            1000.0 * all.worst_offset
        );
        assert!(all.share() >= bound, "{name}: {:.1} %", all.share());
        // Whatever the field, an estimate is rarely off by more than 5 cm
        // and never by more than 10 cm.
        assert!(
            all.beyond_share() <= 0.5,
            "{name}: {:.2} %",
            all.beyond_share()
        );
        assert!(all.worst_offset <= 0.1, "{name}: {:.3} m", all.worst_offset);
    }
}
