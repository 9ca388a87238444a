//! The symmetric robot's drive through a crop (Guyonneau 2022, sections
//! 3-4; `spec/guyonneau2022.md` DIFF-*, ROWS-RECENTRE, NAV-*): the
//! differential robot's kinematics and limits, the rows re-indexed across
//! the crop, the row end, the frame of travel, the navigator's refusals and
//! its blind ticks, and a whole drive of five inter-rows on exact scans
//! (`crop_scans`) with the robot moved by its own wheel speeds.
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

use crop_scans::{crop1, crop4, FieldSpec, Lidar, Pose};
use fieldguide::control::fuzzy::Defuzzifier;
use fieldguide::control::fuzzy_rows::{FuzzyRowController, Orientation};
use fieldguide::model::differential::Differential;
use fieldguide::model::{Command, Vehicle};
use fieldguide::perception::furrow::lines::RowLine;
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::perception::rows::filter::{FilterConfig, RowFilter};
use fieldguide::perception::rows::points::RowPoint;
use fieldguide::perception::rows::ruby::Variant;
use fieldguide::perception::rows::{RowsConfig, RowsParams};
use fieldguide::supervisor::crop_navigation::{
    in_travel_frame, nearest_point_behind, to_body, CropNavigator, Halt, NavParams, Phase,
};
use fieldguide::{Meters, MetersPerSecond, Odom, Point2, Pose2, RadiansPerSecond, Robot};
use proptest::prelude::*;

fn line(a: f64, b: f64) -> RowLine {
    RowLine::new(a, Meters::new(b).unwrap()).unwrap()
}

fn robot() -> Differential {
    Differential::new(
        Meters::new(0.5).unwrap(),
        MetersPerSecond::new(1.0).unwrap(),
    )
    .unwrap()
}

fn speeds(c: &Command) -> (f64, f64) {
    match *c {
        Command::Differential { left, right } => (left.get(), right.get()),
        _ => panic!("not a differential command: {c:?}"),
    }
}

#[test]
fn a_differential_robot_needs_a_positive_track_and_speed_limit() {
    //= spec/guyonneau2022.md#diff-limits-a-differential-robot-s-limits
    //= type=test
    //# A differential robot MUST be refused with an error naming DIFF-LIMITS
    //# unless its track and its largest wheel speed are finite and > 0.
    for (w, v) in [(0.0, 1.0), (-0.5, 1.0), (0.5, 0.0), (0.5, -1.0)] {
        let e = Differential::new(Meters::new(w).unwrap(), MetersPerSecond::new(v).unwrap());
        assert_eq!(e.unwrap_err().requirement, "DIFF-LIMITS");
    }
    //= spec/guyonneau2022.md#diff-limits-a-differential-robot-s-limits
    //= type=test
    //# A differential command MUST have both wheel speeds within
    //# [−v_max, v_max].
    let vehicle = Vehicle::Differential(robot());
    let command = |l: f64, r: f64| Command::Differential {
        left: MetersPerSecond::new(l).unwrap(),
        right: MetersPerSecond::new(r).unwrap(),
    };
    assert!(vehicle.check(&command(1.0, -1.0)).is_ok());
    assert_eq!(
        vehicle
            .check(&command(1.0001, 0.0))
            .unwrap_err()
            .requirement,
        "GD-VEHICLE"
    );
    assert_eq!(
        vehicle.check(&command(0.0, -1.5)).unwrap_err().requirement,
        "GD-VEHICLE"
    );
    let bicycle = Command::Bicycle {
        speed: MetersPerSecond::ZERO,
        steering: fieldguide::Radians::ZERO,
    };
    assert_eq!(
        vehicle.check(&bicycle).unwrap_err().requirement,
        "GD-VEHICLE"
    );
}

proptest! {
    //= spec/guyonneau2022.md#diff-kinematics-wheel-speeds-speed-and-yaw-rate
    //= type=test
    //# The speed of O MUST be (v_l + v_r)/2 and its yaw rate (v_r − v_l)/w.
    //= spec/guyonneau2022.md#diff-kinematics-wheel-speeds-speed-and-yaw-rate
    //= type=test
    //# The wheel speeds of a speed v and a yaw rate ω MUST be v_l = v − ω w/2
    //# and v_r = v + ω w/2, both scaled by one factor into the limits when
    //# either exceeds it.
    #[test]
    fn wheel_speeds_give_back_the_motion_and_keep_the_curvature(
        v in -3.0..3.0_f64,
        omega in -8.0..8.0_f64,
    ) {
        let d = robot();
        let (c, saturated) = d
            .wheels(MetersPerSecond::new(v).unwrap(), RadiansPerSecond::new(omega).unwrap())
            .unwrap();
        let (l, r) = speeds(&c);
        prop_assert!(l.abs() <= 1.0 + 1e-12 && r.abs() <= 1.0 + 1e-12);
        let raw = (v - 0.25 * omega, v + 0.25 * omega);
        prop_assert_eq!(saturated, raw.0.abs().max(raw.1.abs()) > 1.0);
        let (speed, yaw) = d.motion(
            MetersPerSecond::new(l).unwrap(),
            MetersPerSecond::new(r).unwrap(),
        ).unwrap();
        let k = if saturated { 1.0 / raw.0.abs().max(raw.1.abs()) } else { 1.0 };
        prop_assert!((speed.get() - k * v).abs() < 1e-9);
        prop_assert!((yaw.get() - k * omega).abs() < 1e-9);
    }
}

/// Four rows d apart around the robot, slope `a`, the robot between the
/// middle two, `shift` m left of their middle.
fn four_rows(d: f64, a: f64, shift: f64) -> RowFilter {
    let step = d * (a * a + 1.0).sqrt();
    let rows: Vec<RowLine> = (0..4)
        .map(|i| {
            line(
                a,
                (1.5 - f64::from(i)) * step - shift * (a * a + 1.0).sqrt(),
            )
        })
        .collect();
    RowFilter::new(Meters::new(d).unwrap(), &rows, FilterConfig::default()).unwrap()
}

#[test]
fn the_rows_are_reindexed_when_the_robot_crosses_into_the_next_inter_row() {
    //= spec/guyonneau2022.md#rows-recentre-the-rows-follow-the-robot-across-the-crop
    //= type=test
    //# When the rows either side of the robot are rows j and j + 1 (1-based)
    //# with j ≠ ⌊n/2⌋, the rows MUST be re-indexed by j − ⌊n/2⌋ whole rows: a
    //# row whose index stays within 1..n MUST keep its line, and a row that
    //# enters MUST be y = ā x + b^c + d (c − i) sqrt(ā² + 1) from the nearest
    //# kept row c, with ā the mean slope of the rows.
    let d = 1.2;
    // One row to the left: the rows seen at 0.6, -0.6, -1.8, -3.0 become
    // 1.8 (entering), 0.6, -0.6, -1.8.
    let mut f = four_rows(d, 0.0, 0.0);
    f.move_by(&Pose2::<Robot>::new(0.0, d, 0.0).unwrap());
    let b: Vec<f64> = f.rows().iter().map(|r| r.intercept().get()).collect();
    for (got, want) in b.iter().zip([1.8, 0.6, -0.6, -1.8]) {
        assert!((got - want).abs() < 1e-12, "{b:?}");
    }
    // Twice more, and once to the right: always between the middle rows.
    for dy in [d, d, -d] {
        f.move_by(&Pose2::<Robot>::new(0.3, dy, 0.0).unwrap());
        let b: Vec<f64> = f.rows().iter().map(|r| r.intercept().get()).collect();
        assert!(b[1] > 0.0 && b[2] < 0.0, "{b:?}");
        assert!((b[0] - b[1] - d).abs() < 1e-9 && (b[2] - b[3] - d).abs() < 1e-9);
    }
    // A slope: the entering row keeps the spacing along the normal.
    let a = 0.1;
    let mut f = four_rows(d, a, 0.0);
    let before: Vec<RowLine> = f.rows().to_vec();
    f.move_by(&Pose2::<Robot>::new(0.0, d * (a * a + 1.0).sqrt(), 0.0).unwrap());
    let after = f.rows();
    let step = d * (a * a + 1.0).sqrt();
    for i in 1..4 {
        let want = before[i - 1].intercept().get() - step;
        assert!((after[i].intercept().get() - want).abs() < 1e-9);
    }
    assert!((after[0].intercept().get() - (after[1].intercept().get() + step)).abs() < 1e-9);
    assert!(after.iter().all(|r| (r.slope() - a).abs() < 1e-12));
    // Staying in the inter-row changes nothing but the motion.
    let mut f = four_rows(d, 0.0, 0.0);
    f.move_by(&Pose2::<Robot>::new(1.0, 0.3, 0.0).unwrap());
    let b: Vec<f64> = f.rows().iter().map(|r| r.intercept().get()).collect();
    for (got, want) in b.iter().zip([1.5, 0.3, -0.9, -2.1]) {
        assert!((got - want).abs() < 1e-12, "{b:?}");
    }
}

fn point(x: f64, y: f64) -> RowPoint {
    RowPoint {
        position: Point2::<Robot>::new(x, y).unwrap(),
        returns: 1,
    }
}

#[test]
fn the_row_ends_when_the_nearest_point_is_far_enough_behind() {
    //= spec/guyonneau2022.md#nav-row-end-no-plant-beside-the-robot
    //= type=test
    //# A scan MUST see the inter-row's end when the point of the scans nearest to
    //# O lies more than the end margin plus half the body length behind O along
    //# the direction of travel, and the inter-row MUST end after the configured
    //# number of such scans in a row.
    let reach = 0.9 + 0.55;
    // Plants beside the robot: not the end.
    assert!(!nearest_point_behind(
        &[point(0.1, 0.6), point(-2.0, 0.6)],
        false,
        reach
    ));
    // The nearest plant 1.5 m behind (farther ones too): the end going
    // forward, not going backward, where it is ahead.
    let behind = [point(-1.5, 0.1), point(-2.5, 0.6), point(-3.0, -0.6)];
    assert!(nearest_point_behind(&behind, false, reach));
    assert!(!nearest_point_behind(&behind, true, reach));
    let ahead = [point(1.5, 0.1), point(2.5, -0.6)];
    assert!(nearest_point_behind(&ahead, true, reach));
    // Just within the reach: not yet.
    assert!(!nearest_point_behind(&[point(-1.44, 0.0)], false, reach));
    // The nearest decides, not the farthest: a point ahead but far does not
    // hide the end; a near one beside does.
    assert!(nearest_point_behind(
        &[point(-1.6, 0.0), point(3.5, 0.0)],
        false,
        reach
    ));
    assert!(!nearest_point_behind(
        &[point(-1.6, 0.0), point(0.0, 1.0)],
        false,
        reach
    ));
    // No point: never the end.
    assert!(!nearest_point_behind(&[], false, reach));
}

#[test]
fn driving_backward_reads_the_rows_turned_by_pi_and_steers_the_right_way() {
    //= spec/guyonneau2022.md#nav-travel-frame-the-rows-seen-in-the-direction-of-travel
    //= type=test
    //# Driving backward, the controller MUST read the rows in the frame turned by
    //# π: each row y = a x + b as y = a x − b, left and right swapped; its left
    //# and right wheel speeds (v_l′, v_r′) MUST be applied as the body's
    //# (−v_r′, −v_l′).
    let sides = Pair {
        left: line(0.02, 0.3),
        right: line(0.02, -0.7),
    };
    let rows = [line(0.02, 1.3), sides.left, sides.right, line(0.02, -1.7)];
    let (turned, all) = in_travel_frame(&sides, &rows, true).unwrap();
    assert_eq!(turned.left, line(0.02, 0.7));
    assert_eq!(turned.right, line(0.02, -0.3));
    let b: Vec<f64> = all.iter().map(|r| r.intercept().get()).collect();
    assert_eq!(b, vec![1.7, 0.7, -0.3, -1.3]);
    // Turned twice: the rows themselves.
    let (back, again) = in_travel_frame(&turned, &all, true).unwrap();
    assert_eq!(back, sides);
    assert_eq!(again.as_slice(), &rows);
    // Forward: unchanged.
    let (same, _) = in_travel_frame(&sides, &rows, false).unwrap();
    assert_eq!(same, sides);
    // The robot 0.2 m left of the middle, parallel. Forward it turns right
    // (v_r < v_l, both forward); backward, to reach the middle (y < 0) with
    // its back first, it turns left (yaw > 0) with both wheels backward.
    let c = FuzzyRowController::authors(
        Orientation::SidesMeanSlope,
        Defuzzifier::Exact,
        MetersPerSecond::new(0.5).unwrap(),
    )
    .unwrap();
    let level = Pair {
        left: line(0.0, 0.3),
        right: line(0.0, -0.7),
    };
    let forward = speeds(&c.command(&level, &[]).unwrap().command);
    assert!(forward.0 > 0.0 && forward.1 > 0.0 && forward.1 < forward.0);
    let (t, _) = in_travel_frame(&level, &[], true).unwrap();
    let back = speeds(&to_body(&c.command(&t, &[]).unwrap().command, true));
    assert!(back.0 < 0.0 && back.1 < 0.0, "{back:?}");
    assert!(back.1 - back.0 > 0.0, "yaw rate must be > 0: {back:?}");
    // Seen from the back the robot is 0.2 m right of the middle: the
    // controller's mirror image (its wheels swap), then each body wheel is
    // the other travel wheel reversed: the forward speeds, negated.
    assert!((back.0 + forward.0).abs() < 1e-12 && (back.1 + forward.1).abs() < 1e-12);
    // A forward command is untouched.
    assert_eq!(
        to_body(&c.command(&level, &[]).unwrap().command, false),
        c.command(&level, &[]).unwrap().command
    );
}

/// The paper's robot with RGOP on LiDARs 0.55 m ahead and behind.
fn params(variant: Variant) -> NavParams {
    let [front, back] = crop_scans::paper_mounts(0.55);
    let rows = RowsParams::authors(variant, front.transform()).with_second(back.transform());
    NavParams::authors(RowsConfig::new(rows).unwrap()).unwrap()
}

#[test]
fn a_navigator_refuses_parameters_out_of_range() {
    //= spec/guyonneau2022.md#nav-params-the-navigator-s-parameters
    //= type=test
    //# A navigator MUST be refused with an error naming NAV-PARAMS unless it
    //# drives at least one inter-row, its top speed and its manoeuvre speed are
    //# > 0 and within the vehicle's wheel-speed limit, its body length is > 0,
    //# its end margin ≥ 0, and it counts at least one end scan and one blind
    //# tick.
    let good = params(Variant::Rgop);
    assert!(CropNavigator::<1024>::new(good).is_ok());
    let v = |x: f64| MetersPerSecond::new(x).unwrap();
    let m = |x: f64| Meters::new(x).unwrap();
    let bad = [
        NavParams {
            inter_rows: 0,
            ..good
        },
        NavParams {
            top_speed: v(0.0),
            ..good
        },
        NavParams {
            top_speed: v(1.2),
            ..good
        },
        NavParams {
            manoeuvre_speed: v(-0.1),
            ..good
        },
        NavParams {
            body_length: m(0.0),
            ..good
        },
        NavParams {
            end_margin: m(-0.1),
            ..good
        },
        NavParams {
            end_scans: 0,
            ..good
        },
        NavParams {
            blind_ticks: 0,
            ..good
        },
    ];
    for p in bad {
        let e = CropNavigator::<1024>::new(p).unwrap_err();
        assert_eq!(e.requirement, "NAV-PARAMS", "{p:?}");
    }
}

#[test]
fn a_lidar_that_stops_sending_stops_the_robot_after_the_blind_ticks() {
    //= spec/guyonneau2022.md#nav-blind-a-lidar-that-stops-sending
    //= type=test
    //# A tick without a scan, or whose scans hold no point, MUST keep the last
    //# command for at most the configured number of blind ticks in a row; the
    //# next such tick MUST stop the robot for good with the reason Blind.
    let p = params(Variant::Rgop);
    let mut nav = CropNavigator::<1024>::new(p).unwrap();
    let odometry = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    for k in 0..p.blind_ticks {
        let tick = nav.step(&[], &odometry).unwrap();
        assert_eq!(tick.phase, Phase::Measuring, "tick {k}");
    }
    let tick = nav.step(&[], &odometry).unwrap();
    assert_eq!(tick.phase, Phase::Stopped(Halt::Blind));
    assert_eq!(speeds(&tick.command), (0.0, 0.0));
    // Stopped for good: scans do not restart it.
    let field = FieldSpec {
        rows: 6,
        ..crop1(1, 1.2)
    }
    .build();
    let robot = field.between(0, 1, 0.5);
    let lidar = Lidar::paper();
    let [front, back] = crop_scans::paper_mounts(0.55);
    let (f, b) = (
        field.cast(&robot, &front, &lidar, 1),
        field.cast(&robot, &back, &lidar, 2),
    );
    let tick = nav.step(&[f.scan(), b.scan()], &odometry).unwrap();
    assert_eq!(tick.phase, Phase::Stopped(Halt::Blind));
}

/// What a drive did.
struct Drive {
    end: Phase,
    phases: Vec<Phase>,
    /// The largest |offset| from the middle of the true rows either side
    /// while driving inside the field, m.
    worst_offset: f64,
    /// Crop stems the robot's footprint touched.
    touched: usize,
    seconds: f64,
}

/// The robot's footprint: 1.1 m × 0.6 m centred on O.
const HALF_LENGTH: f64 = 0.55;
const HALF_WIDTH: f64 = 0.3;

/// A drive on `spec` (six rows) from the middle of the first inter-row,
/// 0.3 m into it, the robot moved exactly by its wheel speeds at 40 Hz and
/// its odometry exact, for at most `limit` s.
fn drive(spec: &FieldSpec, variant: Variant, limit: f64) -> Drive {
    let field = spec.build();
    let p = params(variant);
    let mut nav = CropNavigator::<1024>::new(p).unwrap();
    let lidar = Lidar::paper();
    let [front, back] = crop_scans::paper_mounts(0.55);
    let dt = 0.025;
    let mut pose = field.between(0, 1, 0.3);
    let start = pose;
    let mut phases: Vec<Phase> = Vec::new();
    let mut touched = vec![false; field.stems.len()];
    let mut worst: f64 = 0.0;
    let mut t = 0.0;
    let mut k = 0_u64;
    while t < limit {
        let local = start.local(pose.x, pose.y);
        let odometry = Pose2::<Odom>::new(local.0, local.1, pose.heading - start.heading).unwrap();
        let (f, b) = (
            field.cast(&pose, &front, &lidar, 2 * k + 1),
            field.cast(&pose, &back, &lidar, 2 * k + 2),
        );
        let tick = nav.step(&[f.scan(), b.scan()], &odometry).unwrap();
        if phases.last() != Some(&tick.phase) {
            phases.push(tick.phase);
        }
        if matches!(tick.phase, Phase::Done | Phase::Stopped(_)) {
            break;
        }
        if let (Phase::Driving { .. }, Some(middle)) = (tick.phase, field.middle_line(&pose)) {
            let inside = (0.0..spec.length).contains(&pose.x);
            if inside {
                worst = worst.max(middle.b.abs());
            }
        }
        for (i, s) in field.stems[..field.plants].iter().enumerate() {
            let (x, y) = pose.local(s.x, s.y);
            if x.abs() <= HALF_LENGTH + s.r && y.abs() <= HALF_WIDTH + s.r {
                touched[i] = true;
            }
        }
        let (l, r) = speeds(&tick.command);
        let (v, w) = (0.5 * (l + r), (r - l) / 0.5);
        let h = pose.heading;
        let (x, y) = if w.abs() < 1e-12 {
            (pose.x + v * dt * h.cos(), pose.y + v * dt * h.sin())
        } else {
            let rho = v / w;
            (
                pose.x + rho * ((h + w * dt).sin() - h.sin()),
                pose.y - rho * ((h + w * dt).cos() - h.cos()),
            )
        };
        pose = Pose::new(x, y, h + w * dt);
        t += dt;
        k += 1;
    }
    Drive {
        end: nav.phase(),
        phases,
        worst_offset: worst,
        touched: touched.iter().filter(|t| **t).count(),
        seconds: t,
    }
}

#[test]
fn the_robot_drives_five_inter_rows_changing_row_backwards() {
    //= spec/guyonneau2022.md#nav-phases-measure-drive-change-done
    //= type=test
    //# The navigator MUST stand still while it measures the row distance,
    //# then drive the first inter-row forward, change row at each inter-row's
    //# end, drive each next inter-row in the direction opposite to the last,
    //# and stand still once the configured number of inter-rows is driven.
    //= spec/guyonneau2022.md#nav-phases-measure-drive-change-done
    //= type=test
    //# The last inter-row's end MUST give Done, with the robot standing
    //# still.
    //= spec/guyonneau2022.md#nav-row-change-a-row-change-without-turning-round
    //= type=test
    //# A row change MUST turn in place by a quarter turn towards the next
    //# inter-row, drive straight on by the row distance d, and turn in place back
    //# to the heading it started from, each step on odometry alone; each turn
    //# MUST end within 0.01 rad of its heading and the crossing within 0.005 m of
    //# its length.
    for (spec, name) in [
        (
            FieldSpec {
                rows: 6,
                length: 8.0,
                ..crop1(3, 1.2)
            },
            "crop 1, 1.2 m",
        ),
        (
            FieldSpec {
                rows: 6,
                length: 8.0,
                ..crop4(5, 1.0)
            },
            "crop 4, 1.0 m",
        ),
    ] {
        let d = drive(&spec, Variant::Rgop, 400.0);
        assert_eq!(d.end, Phase::Done, "{name}: {:?}", d.phases);
        assert_eq!(d.phases[0], Phase::Measuring);
        let driven: Vec<(u8, bool)> = d
            .phases
            .iter()
            .filter_map(|p| match *p {
                Phase::Driving { row, backward } => Some((row, backward)),
                _ => None,
            })
            .collect();
        assert_eq!(
            driven,
            vec![(1, false), (2, true), (3, false), (4, true), (5, false)],
            "{name}"
        );
        assert_eq!(d.touched, 0, "{name}: plants touched");
        assert!(d.worst_offset < 0.15, "{name}: offset {}", d.worst_offset);
        println!(
            "{name}: done in {:.1} s, worst offset {:.3} m",
            d.seconds, d.worst_offset
        );
    }
}
