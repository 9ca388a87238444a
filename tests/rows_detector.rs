//! The rows detector (Guyonneau 2022, Fig. 5; `spec/guyonneau2022.md`
//! ROWS-DETECTOR, ROWS-MOUNTS, ROWS-INIT-STILL, ROWS-SUPPORT): the row
//! distance measured at rest, then the rows followed; moving while it
//! measures, blind scans and a lost filter; configurations and ticks
//! refused. The Detector trait's contract on any scan is checked with the
//! other detectors' in `tests/seams.rs` and fuzzed in `tests/fuzz_scans.rs`.
//!
//! Scans are ray-cast from exact crop fields (`crop_scans`): five rows of
//! stems 0.75 m apart, the robot midway between rows 1 and 2 (0-based),
//! facing along them.
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

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use crop_scans::{crop1, Field, FieldSpec, Lidar, Mount, Pose, RawScan, STEM_RADIUS};
use fieldguide::perception::rows::ruby::Variant;
use fieldguide::perception::rows::{RowsConfig, RowsDetection, RowsDetector, RowsParams};
use fieldguide::perception::{Detector, HeldLine, RangeLimits, Scan, Verdict};
use fieldguide::{Meters, Odom, Pose2, Radians, Transform2};

/// The row distance of the crops, m.
const SPACING: f64 = 0.75;
/// Scans the measurement averages (N, the default).
const N: usize = 10;
/// Scans without a match before the filter is lost (K, the default).
const K: usize = 20;

type Rows = RowsDetector<512>;

fn front() -> Mount {
    Mount::front(0.3)
}

fn params() -> RowsParams {
    RowsParams::authors(Variant::Rgop, front().transform())
}

fn detector() -> Rows {
    Rows::new(RowsConfig::new(params()).unwrap())
}

/// Crop 1 (five regular rows, no weeds), 10 m long.
fn field() -> Field {
    crop1(7, SPACING).build()
}

/// The robot `along` m into the rows, midway between rows 1 and 2, moved
/// sideways by `lateral` m.
fn robot(field: &Field, along: f64, lateral: f64) -> Pose {
    field
        .between(1, 2, along)
        .compose(&Pose::new(0.0, lateral, 0.0))
}

fn odometry(p: &Pose) -> Pose2<Odom> {
    Pose2::new(p.x, p.y, p.heading).unwrap()
}

/// The front LiDAR's scan at `robot`, noiseless.
fn cast(field: &Field, robot: &Pose) -> RawScan {
    field.cast(robot, &front(), &Lidar::paper().noiseless(), 0)
}

/// One tick on the front LiDAR's scan at `robot`, odometry `odom`.
fn tick(d: &mut Rows, field: &Field, robot: &Pose, odom: &Pose2<Odom>) -> RowsDetection {
    let raw = cast(field, robot);
    d.observe_scans(&[raw.scan()], odom).unwrap()
}

/// The true error to the middle line of the rows either side (the library's
/// sign: y > 0 when the robot is left of the middle).
fn true_error(field: &Field, robot: &Pose) -> f64 {
    let middle = field.middle_line(robot).unwrap();
    -middle.b / (1.0 + middle.a * middle.a).sqrt()
}

fn absent(out: &RowsDetection) -> bool {
    let d = &out.detection;
    d.verdict == Verdict::Absent && d.error.is_none() && d.line.is_none() && d.quality.is_none()
}

/// Ticks at rest at `robot` until the detector follows the rows; returns
/// the ticks it took, each Absent.
fn measure(d: &mut Rows, field: &Field, robot: &Pose, most: usize) -> usize {
    for k in 1..=most {
        let out = tick(d, field, robot, &odometry(robot));
        assert!(
            absent(&out),
            "tick {k} while measuring: {:?}",
            out.detection
        );
        if d.row_distance().is_some() {
            return k;
        }
        assert!(d.rows().is_none());
    }
    panic!("no row distance in {most} scans at rest");
}

//= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
//= type=test
//# The row distance MUST be measured over scans taken while the robot
//# stands still: when the robot is farther than the still tolerance (in
//# metres, and in radians of heading) from the pose of the first scan
//# counted, the measurement MUST start again from the current scan; until
//# it is complete the verdict MUST be Absent.
//= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
//= type=test
//# Each tick MUST gather the points of every configured LiDAR's scan, in the
//# order of the mounts, merge them into Z* for the one-point variants, run
//# the line finder on them, and then either count the lines towards the row
//# distance or pass them to the row filter, whose verdict and tracking error
//# are the tick's.
#[test]
fn absent_while_measuring_then_the_rows_are_followed() {
    let field = field();
    let mut d = detector();
    let start = robot(&field, 2.0, 0.0);
    // Every scan at rest shows the pair: N scans, each Absent.
    assert_eq!(measure(&mut d, &field, &start, 3 * N), N);
    // The stems' near faces put each line up to a stem radius inside its
    // row: d is the spacing less at most two radii.
    let measured = d.row_distance().unwrap().get();
    assert!(
        measured > SPACING - 2.0 * STEM_RADIUS - 0.005 && measured < SPACING + 0.005,
        "d = {measured}"
    );
    assert_eq!(d.rows().unwrap().len(), 4);
    // Then the filter: the rows either side found, the error the truth's.
    for k in 0..40 {
        let lateral = 0.05 * (TAU * k as f64 / 40.0).sin();
        let at = robot(&field, 2.0 + 0.025 * k as f64, lateral);
        let out = tick(&mut d, &field, &at, &odometry(&at));
        let detection = out.detection;
        assert_eq!(detection.verdict, Verdict::Enter, "tick {k}");
        let outcome = out.outcome.unwrap();
        assert_eq!(detection.quality, Some(outcome.matched() as f64));
        assert!(outcome.matched() >= 2);
        let e = detection.error.unwrap();
        let truth = true_error(&field, &at);
        assert!(
            (e.y.get() - truth).abs() < 0.01,
            "tick {k}: {} vs {truth}",
            e.y.get()
        );
        // The held line is the pair either side; not moved, its error is
        // the tick's.
        let held = detection.line.unwrap();
        let here = held.error_at(&Pose2::new(0.0, 0.0, 0.0).unwrap()).unwrap();
        assert!((here.y.get() - e.y.get()).abs() < 1e-9);
    }
}

//= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
//= type=test
//# Each tick MUST gather the points of every configured LiDAR's scan, in the
//# order of the mounts, merge them into Z* for the one-point variants, run
//# the line finder on them, and then either count the lines towards the row
//# distance or pass them to the row filter, whose verdict and tracking error
//# are the tick's.
#[test]
fn points_of_each_lidar_in_the_order_of_the_mounts() {
    let limits = RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(4.0).unwrap()).unwrap();
    let scan = |ranges: &'static [f64]| Scan {
        start: Radians::new(0.0).unwrap(),
        increment: Radians::new(FRAC_PI_2).unwrap(),
        ranges,
        limits,
    };
    let at = Pose2::new(0.0, 0.0, 0.0).unwrap();
    let origin = Transform2::new(0.0, 0.0, 0.0).unwrap();
    // A scan of a single return, 1 m ahead, seen by two LiDARs on the same
    // mount: Z* is computed per LiDAR, so two points, not one.
    let ahead: &'static [f64] = &[1.0];
    for variant in [Variant::Rgop, Variant::Rg] {
        let both = RowsParams::authors(variant, origin).with_second(origin);
        let mut d = Rows::new(RowsConfig::new(both).unwrap());
        let out = d.observe_scans(&[scan(ahead), scan(ahead)], &at).unwrap();
        assert_eq!(out.gathered.kept, 2, "{}", variant.name());
        assert_eq!(d.points().len(), 2);
    }
    // The first LiDAR's points come first: the second sees its return 2 m
    // to the left (ray 1 at 90°).
    let left: &'static [f64] = &[f64::NAN, 2.0];
    let back = Transform2::new(-0.5, 0.0, PI).unwrap();
    let both = RowsParams::authors(Variant::Rg, origin).with_second(back);
    let mut d = Rows::new(RowsConfig::new(both).unwrap());
    d.observe_scans(&[scan(ahead), scan(left)], &at).unwrap();
    let p = d.points();
    assert_eq!(p.len(), 2);
    assert!((p[0].position.x() - 1.0).abs() < 1e-12 && p[0].position.y().abs() < 1e-12);
    // Ray 1 of the back LiDAR (yaw π): (0, 2) in its frame, (−0.5, −2) on
    // the robot.
    assert!((p[1].position.x() + 0.5).abs() < 1e-12);
    assert!((p[1].position.y() + 2.0).abs() < 1e-12);
    // The one-point variants merge each LiDAR's runs: a crop's scan gives
    // fewer points to RGOP than to RG.
    let field = field();
    let raw = cast(&field, &robot(&field, 2.0, 0.0));
    let count = |variant| {
        let mut d =
            Rows::new(RowsConfig::new(RowsParams::authors(variant, front().transform())).unwrap());
        let out = d.observe_scans(&[raw.scan()], &at).unwrap();
        (d.points().len(), out.gathered.kept)
    };
    let (z, _) = count(Variant::Rg);
    let (z_star, kept) = count(Variant::Rgop);
    assert_eq!(z, raw.points().len());
    assert!(z_star < z, "Z* {z_star}, Z {z}");
    assert_eq!(kept, z_star);
}

//= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
//= type=test
//# The row distance MUST be measured over scans taken while the robot
//# stands still: when the robot is farther than the still tolerance (in
//# metres, and in radians of heading) from the pose of the first scan
//# counted, the measurement MUST start again from the current scan; until
//# it is complete the verdict MUST be Absent.
#[test]
fn moving_while_measuring_starts_it_again() {
    let field = field();
    let at = robot(&field, 2.0, 0.0);
    let still = odometry(&at);
    // The ticks to the row distance when the odometry says the robot moved
    // to `moved` (x, y, heading offsets) at tick `when` (0-based) and stayed.
    let ticks = |when: usize, moved: (f64, f64, f64)| {
        let mut d = detector();
        let there = Pose2::<Odom>::new(
            still.position.x() + moved.0,
            still.position.y() + moved.1,
            still.heading.get() + moved.2,
        )
        .unwrap();
        for k in 0..4 * N {
            let odom = if k < when { still } else { there };
            let out = tick(&mut d, &field, &at, &odom);
            assert!(absent(&out), "tick {k}");
            if d.row_distance().is_some() {
                return k + 1;
            }
        }
        panic!("no row distance");
    };
    assert_eq!(ticks(4, (0.0, 0.0, 0.0)), N);
    // Within the tolerance (0.05 m and 0.05 rad): nothing restarts.
    assert_eq!(ticks(4, (0.03, -0.03, 0.0)), N);
    assert_eq!(ticks(4, (0.0, 0.0, -0.049)), N);
    // Beyond it, in position or in heading, at tick 4: the measurement
    // starts again from tick 4, N scans later.
    assert_eq!(ticks(4, (0.06, 0.0, 0.0)), 4 + N);
    assert_eq!(ticks(4, (0.0, -0.06, 0.0)), 4 + N);
    assert_eq!(ticks(4, (0.0, 0.0, 0.06)), 4 + N);
    assert_eq!(ticks(7, (0.0, 0.0, -0.06)), 7 + N);
    // A robot creeping 1 cm a scan is more than 5 cm from the first scan
    // counted every sixth scan: it never completes the measurement.
    let mut d = detector();
    for k in 0..4 * N {
        let odom = Pose2::<Odom>::new(
            still.position.x() + 0.01 * k as f64,
            still.position.y(),
            still.heading.get(),
        )
        .unwrap();
        let out = tick(&mut d, &field, &at, &odom);
        assert!(absent(&out), "tick {k}");
        assert!(d.row_distance().is_none(), "tick {k}");
    }
    // With a still tolerance of zero any motion restarts, none does not.
    let mut p = params();
    p.still = Meters::new(0.0).unwrap();
    let mut d = Rows::new(RowsConfig::new(p).unwrap());
    assert_eq!(measure(&mut d, &field, &at, 3 * N), N);
}

//= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
//= type=test
//# When as many scans in a row as the measurement averages show no pair,
//# the line finder's lines MUST be forgotten, so that its next scan
//# starts from the empty set.
#[test]
fn lines_forgotten_after_n_scans_without_a_pair() {
    // One row only, 0.4 m left of the robot: a line, never a pair.
    let field = FieldSpec::regular(1, SPACING, 10.0, 0.2, 3).build();
    let at = field.between(0, 0, 2.0).compose(&Pose::new(0.0, -0.4, 0.0));
    let mut d = detector();
    for k in 1..=3 * N {
        let out = tick(&mut d, &field, &at, &odometry(&at));
        assert!(absent(&out));
        let models = d.line_finder().models().len();
        if k % N == 0 {
            assert_eq!(models, 0, "tick {k}: the lines are forgotten");
        } else {
            assert!(models > 0, "tick {k}: the row's line is kept");
        }
    }
    assert!(d.row_distance().is_none());
}

//= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
//= type=test
//# A lost filter MUST give the verdict Absent and restart the row
//# distance's measurement, with the line finder's lines forgotten.
#[test]
fn blind_scans_exit_then_absent_when_lost_then_measured_again() {
    let field = field();
    let at = robot(&field, 2.0, 0.0);
    let mut d = detector();
    measure(&mut d, &field, &at, 3 * N);
    let out = tick(&mut d, &field, &at, &odometry(&at));
    assert_eq!(out.detection.verdict, Verdict::Enter);
    let blind = vec![f64::NAN; 360];
    let lidar = Lidar::paper();
    let scan = Scan {
        start: Radians::new(lidar.start).unwrap(),
        increment: Radians::new(lidar.increment).unwrap(),
        ranges: &blind,
        limits: cast(&field, &at).scan().limits,
    };
    // Blind: the rows are kept, none found: Exit with the kept rows' error,
    // for K − 1 scans; the K-th loses the filter: Absent, measuring again.
    for k in 1..K {
        let out = d.observe_scans(&[scan], &odometry(&at)).unwrap();
        assert_eq!(out.detection.verdict, Verdict::Exit, "blind tick {k}");
        assert_eq!(out.outcome.unwrap().misses, k as u32);
        assert!(out.detection.error.is_some());
        assert_eq!(out.gathered.kept, 0);
    }
    let out = d.observe_scans(&[scan], &odometry(&at)).unwrap();
    assert!(out.outcome.unwrap().lost);
    assert!(absent(&out));
    assert!(d.row_distance().is_none() && d.rows().is_none());
    assert!(d.line_finder().models().is_empty());
    // Still blind: measuring, Absent.
    let out = d.observe_scans(&[scan], &odometry(&at)).unwrap();
    assert!(absent(&out) && out.outcome.is_none());
    // The rows back in sight: measured again from scratch, N scans, then
    // followed.
    assert_eq!(measure(&mut d, &field, &at, 3 * N), N);
    let out = tick(&mut d, &field, &at, &odometry(&at));
    assert_eq!(out.detection.verdict, Verdict::Enter);
    let e = out.detection.error.unwrap().y.get();
    assert!((e - true_error(&field, &at)).abs() < 0.01, "{e}");
}

//= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
//= type=test
//# While it follows the rows, the detector MUST hand the filter's n rows
//# to the line finder as lines carried to the next scan.
#[test]
fn the_filtered_rows_are_carried_to_the_next_scan() {
    let field = field();
    let at = robot(&field, 2.0, 0.0);
    let mut d = detector();
    measure(&mut d, &field, &at, 3 * N);
    let blind = vec![f64::NAN; 360];
    let raw = cast(&field, &at);
    let scan = Scan {
        ranges: &blind,
        ..raw.scan()
    };
    // Following: after a blind scan the line finder's set is exactly the
    // filter's rows (its own lines lost their points), carried as models
    // holding no point yet.
    tick(&mut d, &field, &at, &odometry(&at));
    d.observe_scans(&[scan], &odometry(&at)).unwrap();
    let rows = d.rows().unwrap().to_vec();
    let models = d.line_finder().models();
    assert_eq!(models.len(), rows.len());
    for (m, r) in models.iter().zip(&rows) {
        assert_eq!((m.line, m.points), (*r, 0));
    }
    // The next scan starts from them: the rows are found again at once.
    let out = tick(&mut d, &field, &at, &odometry(&at));
    assert_eq!(out.detection.verdict, Verdict::Enter);
    // While measuring nothing is carried: a blind scan leaves no line.
    let mut fresh = detector();
    fresh.observe_scans(&[scan], &odometry(&at)).unwrap();
    assert!(fresh.line_finder().models().is_empty());
}

//= spec/guyonneau2022.md#rows-mounts-one-scan-per-mounted-lidar
//= type=test
//# A tick MUST be refused with an error naming ROWS-MOUNTS unless it is
//# given exactly one scan per configured LiDAR.
#[test]
fn one_scan_per_lidar() {
    let field = field();
    let at = robot(&field, 2.0, 0.0);
    let raw = cast(&field, &at);
    let scan = raw.scan();
    let odom = odometry(&at);
    let mut one = detector();
    for scans in [&[][..], &[scan, scan][..], &[scan, scan, scan][..]] {
        let e = one.observe_scans(scans, &odom).unwrap_err();
        assert_eq!(e.requirement, "ROWS-MOUNTS", "{} scans", scans.len());
    }
    assert!(one.observe_scans(&[scan], &odom).is_ok());
    let mut two =
        Rows::new(RowsConfig::new(params().with_second(Mount::back(0.3).transform())).unwrap());
    for scans in [&[][..], &[scan][..], &[scan, scan, scan][..]] {
        let e = two.observe_scans(scans, &odom).unwrap_err();
        assert_eq!(e.requirement, "ROWS-MOUNTS", "{} scans", scans.len());
    }
    assert!(two.observe_scans(&[scan, scan], &odom).is_ok());
    // The Detector trait's tick is one scan: refused for two LiDARs.
    let e = Detector::observe(&mut two, &scan, &odom).unwrap_err();
    assert_eq!(e.requirement, "ROWS-MOUNTS");
}

//= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
//= type=test
//# Each tick MUST gather the points of every configured LiDAR's scan, in the
//# order of the mounts, merge them into Z* for the one-point variants, run
//# the line finder on them, and then either count the lines towards the row
//# distance or pass them to the row filter, whose verdict and tracking error
//# are the tick's.
#[test]
fn the_detector_trait_for_one_lidar() {
    let field = field();
    let at = robot(&field, 2.0, 0.03);
    let config = RowsConfig::new(params()).unwrap();
    let mut d = <Rows as Detector>::configure(&config).unwrap();
    let mut direct = Rows::new(config);
    let raw = cast(&field, &at);
    for k in 0..=N {
        let seen = Detector::observe(&mut d, &raw.scan(), &odometry(&at)).unwrap();
        let same = direct.observe_scans(&[raw.scan()], &odometry(&at)).unwrap();
        assert_eq!(seen, same.detection, "tick {k}");
        assert_eq!(seen.verdict == Verdict::Absent, k < N, "tick {k}");
    }
    let e = Detector::observe(&mut d, &raw.scan(), &odometry(&at))
        .unwrap()
        .error
        .unwrap();
    assert!((e.y.get() - true_error(&field, &at)).abs() < 0.01);
}

//= spec/guyonneau2022.md#rows-mounts-one-scan-per-mounted-lidar
//= type=test
//# A configuration without a first LiDAR's mount MUST be refused with an
//# error naming ROWS-MOUNTS.
#[test]
fn a_configuration_without_a_first_mount_is_refused() {
    let back = Mount::back(0.3).transform();
    for mounts in [[None, None], [None, Some(back)]] {
        let p = RowsParams { mounts, ..params() };
        assert_eq!(RowsConfig::new(p).unwrap_err().requirement, "ROWS-MOUNTS");
    }
    assert!(RowsConfig::new(params().with_second(back)).is_ok());
    assert_eq!(params().with_second(back).mounts[1], Some(back));
}

//= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
//= type=test
//# A still tolerance that is not finite and ≥ 0 MUST be refused with an error
//# naming ROWS-INIT-STILL.
#[test]
fn a_negative_still_tolerance_is_refused() {
    // `Meters` holds finite values only, so NaN and ±∞ cannot be written:
    // the negative ones are what a user can get wrong.
    for still in [-0.05, -1e-300, -f64::MAX, f64::MIN_POSITIVE.copysign(-1.0)] {
        let p = RowsParams {
            still: Meters::new(still).unwrap(),
            ..params()
        };
        let e = RowsConfig::new(p).unwrap_err();
        assert_eq!(e.requirement, "ROWS-INIT-STILL", "{still}");
    }
    for still in [0.0, -0.0, 0.05, f64::MAX] {
        let p = RowsParams {
            still: Meters::new(still).unwrap(),
            ..params()
        };
        assert!(RowsConfig::new(p).is_ok(), "{still}");
    }
    assert!(Meters::new(f64::NAN).is_err() && Meters::new(f64::INFINITY).is_err());
    assert_eq!(params().still, Meters::new(0.05).unwrap());
}

//= spec/guyonneau2022.md#rows-support-rows-from-lines-of-enough-points
//= type=test
//# A configuration whose fewest points is below three MUST be refused
//# with an error naming ROWS-SUPPORT.
#[test]
fn fewer_than_three_points_per_row_is_refused() {
    for min_support in [0, 1, 2] {
        let p = RowsParams {
            min_support,
            ..params()
        };
        assert_eq!(
            RowsConfig::new(p).unwrap_err().requirement,
            "ROWS-SUPPORT",
            "{min_support}"
        );
    }
    let p = RowsParams {
        min_support: 3,
        ..params()
    };
    assert!(RowsConfig::new(p).is_ok());
    // The line finder's own constants are checked too.
    let mut p = params();
    p.ruby.iterations = 0;
    assert_eq!(RowsConfig::new(p).unwrap_err().requirement, "RUBY-PARAMS");
}

//= spec/guyonneau2022.md#rows-support-rows-from-lines-of-enough-points
//= type=test
//# Only the lines holding at least the configured fewest points MUST be
//# passed to the row distance's measurement and to the row filter.
#[test]
fn lines_of_too_few_points_are_not_rows() {
    let field = field();
    let at = robot(&field, 2.0, 0.0);
    // The rows' lines hold some tens of points each (one per stem in Z*).
    let mut d = detector();
    tick(&mut d, &field, &at, &odometry(&at));
    let most = d
        .line_finder()
        .models()
        .iter()
        .map(|m| m.points)
        .max()
        .unwrap();
    assert!(most >= 5, "{most}");
    // Asking for more points than any line holds: the lines are found, but
    // no pair is ever counted.
    let p = RowsParams {
        min_support: most + 1,
        ..params()
    };
    let mut d = Rows::new(RowsConfig::new(p).unwrap());
    for k in 0..2 * N {
        let out = tick(&mut d, &field, &at, &odometry(&at));
        assert!(absent(&out), "tick {k}");
        assert!(d.row_distance().is_none(), "tick {k}");
    }
    // Exactly as many: they count.
    let p = RowsParams {
        min_support: most,
        ..params()
    };
    let mut d = Rows::new(RowsConfig::new(p).unwrap());
    measure(&mut d, &field, &at, 3 * N);
}
