//! Closed-loop drives of a whole crop on LiDAR alone (Guyonneau 2022,
//! section 4; `spec/guyonneau2022.md` NAV-*): the paper's four crops with
//! RGOP over a seed sweep, a broken controller caught, fields of our own
//! (other spacing, rows ending at different places, a robot off the
//! middle, faster, slow wheels, more slip, worse
//! odometry, longer rows, noisier LiDARs, both LiDARs silent mid-row), and a robot that cannot start or whose
//! LiDARs stop. Every figure is measured against the true rows.
//!
//! `cargo test --release -p fieldguide-sim --test crop_drive -- --nocapture`
//! prints the figures the README quotes.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic
)]

use fieldguide::perception::rows::ruby::Variant;
use fieldguide::supervisor::crop_navigation::{Phase, Waiting};
use fieldguide_sim::crop_drive::campaign::{self, CROPS};
use fieldguide_sim::crop_drive::file::{is_crop_drive, CropDriveFile, BUILTIN};
use fieldguide_sim::crop_drive::{drive, CropEnd, CropOutcome, CropRun, Fault, LidarMount};
use fieldguide_sim::odometry::OdometryErrors;

/// Seeds of the sweep: the campaign's five runs per crop.
const SEEDS: std::ops::RangeInclusive<u32> = 1..=5;

fn runs_on(crop: u8) -> Vec<CropRun> {
    SEEDS
        .map(|k| CropRun::paper(crop, Variant::Rgop, campaign::seed(crop, k)).unwrap())
        .collect()
}

fn drive_all(runs: &[CropRun]) -> Vec<CropOutcome> {
    fieldguide_sim::parallel::map_in_order(runs, drive, |_, _| {})
}

#[test]
fn rgop_drives_every_crop_to_the_end_without_running_over_a_plant() {
    //= spec/guyonneau2022.md#nav-phases-measure-drive-change-done
    //= type=test
    //# The navigator MUST stand still while it measures the row distance,
    //# then drive the first inter-row forward, change row at each inter-row's
    //# end, drive each next inter-row in the direction opposite to the last,
    //# and stand still once the configured number of inter-rows is driven.
    //= spec/guyonneau2022.md#nav-row-change-a-row-change-without-turning-round
    //= type=test
    //# A row change MUST turn in place by a quarter turn towards the next
    //# inter-row, drive straight on by the row distance d, and turn in place back
    //# to the heading it started from, each step on odometry alone; each turn
    //# MUST end within 0.01 rad of its heading and the crossing within 0.005 m of
    //# its length.
    for crop in CROPS {
        let runs = runs_on(crop);
        let outcomes = drive_all(&runs);
        let mut worst_mse: f64 = 0.0;
        let mut worst_offset: f64 = 0.0;
        for (run, out) in runs.iter().zip(&outcomes) {
            assert_eq!(out.end, CropEnd::Done, "crop {crop} seed {}", run.seed);
            assert_eq!(out.crushed, 0, "crop {crop} seed {}", run.seed);
            // Five inter-rows, alternately forward and backward.
            let mut driven: Vec<(u8, bool)> = Vec::new();
            for t in &out.ticks {
                if let Phase::Driving { row, backward } = t.phase {
                    if driven.last() != Some(&(row, backward)) {
                        driven.push((row, backward));
                    }
                }
            }
            assert_eq!(
                driven,
                vec![(1, false), (2, true), (3, false), (4, true), (5, false)]
            );
            worst_mse = worst_mse.max(out.mse_mm2().unwrap());
            worst_offset = worst_offset.max(out.max_offset_m().unwrap());
        }
        println!(
            "crop {crop}: {} runs done, none run over; worst mean squared offset {worst_mse:.1} mm², worst offset {worst_offset:.4} m",
            runs.len()
        );
        // The paper's best crop with RGOP: 65 mm².
        assert!(worst_mse <= 65.0, "crop {crop}: {worst_mse} mm²");
        assert!(worst_offset < 0.1, "crop {crop}: {worst_offset} m");
    }
}

#[test]
fn a_controller_with_its_wheels_swapped_fails_the_run() {
    for crop in [1, 4] {
        let mut run = CropRun::paper(crop, Variant::Rgop, campaign::seed(crop, 1)).unwrap();
        run.fault = Some(Fault::SwappedWheels);
        run.duration_s = 120.0;
        let out = drive(&run);
        assert!(!out.success(), "crop {crop}: {:?}", out.end);
        println!(
            "crop {crop}, wheels swapped: {:?}, {} plants run over",
            out.end, out.crushed
        );
    }
}

/// The largest |offset| from the middle of the rows once the robot is 3 m
/// into the first inter-row (a robot put down off the middle converges
/// first), m.
fn settled_offset(out: &CropOutcome) -> f64 {
    out.ticks
        .iter()
        .filter(|t| !matches!(t.phase, Phase::Driving { row: 1, .. }) || t.truth.position.x() > 3.5)
        .filter_map(|t| t.offset_m)
        .fold(0.0, |m, o| m.max(o.abs()))
}

/// A field of our own: `name`, the crop and run changed by `change`.
struct OwnField {
    name: &'static str,
    crop: u8,
    change: fn(&mut CropRun),
}

#[test]
fn fields_of_our_own() {
    let fields = [
        OwnField {
            name: "crop 4, rows 0.9 m apart (0.15 m beside the body)",
            crop: 4,
            change: |r| r.crop.spacing = 0.9,
        },
        OwnField {
            name: "crop 3, 25 m rows, odometry 2 % long drifting 0.01 rad/m",
            crop: 3,
            change: |r| {
                r.crop.length = 25.0;
                r.odometry = OdometryErrors {
                    scale: 0.02,
                    yaw_drift: 0.01,
                    distance_noise: 0.005,
                    yaw_noise: 0.005,
                };
            },
        },
        OwnField {
            name: "crop 4, start 0.12 m left of the middle, wheels settling in 0.9 s",
            crop: 4,
            change: |r| {
                r.start = (0.5, 0.12);
                r.wheel_lag_s = 0.3;
            },
        },
        OwnField {
            name: "crop 2, LiDARs silent for 0.2 s mid-row",
            crop: 2,
            change: |r| r.outage_s = Some((20.0, 20.2)),
        },
        OwnField {
            name: "crop 3, rows ending anywhere in the last 2 m (a headland that is not square)",
            crop: 3,
            change: |r| r.crop.ragged_ends = 2.0,
        },
        OwnField {
            name: "crop 4 at twice the speed (top wheel speed 1 m/s)",
            crop: 4,
            change: |r| r.top_speed_m_s = 1.0,
        },
        OwnField {
            name: "crop 4, wheels slipping by 5 % (σ, 1 s correlation)",
            crop: 4,
            change: |r| r.wheel_slip = 0.05,
        },
        OwnField {
            name: "crop 3, LiDAR noise 3 cm",
            crop: 3,
            change: |r| r.lidar_noise_m = 0.03,
        },
    ];
    for f in &fields {
        let runs: Vec<CropRun> = (1..=3)
            .map(|k| {
                let mut r = CropRun::paper(f.crop, Variant::Rgop, 7000 + k).unwrap();
                (f.change)(&mut r);
                r
            })
            .collect();
        let outs = drive_all(&runs);
        let worst_mse = outs
            .iter()
            .filter_map(CropOutcome::mse_mm2)
            .fold(0.0, f64::max);
        let worst = outs.iter().map(settled_offset).fold(0.0, f64::max);
        for (r, o) in runs.iter().zip(&outs) {
            assert!(
                o.success(),
                "{}: seed {}: {:?}, {} run over",
                f.name,
                r.seed,
                o.end,
                o.crushed
            );
        }
        println!(
            "{}: 3 of 3 done, none run over; worst mean squared offset {worst_mse:.1} mm², worst offset {worst:.4} m once 3 m into the first inter-row",
            f.name
        );
        assert!(worst < 0.1, "{}: {worst} m", f.name);
    }
}

#[test]
fn a_robot_that_sees_no_rows_stands_still_and_says_why() {
    // Weeds but no row; a robot put down 0.2 m off the middle of rows 1.3 m
    // apart (the row distance is measured only from rows about equidistant,
    // ROWS-SPACING-PAIR); a field with nothing in it.
    let mut weeds = CropRun::paper(4, Variant::Rgop, 1).unwrap();
    weeds.crop.missing = 1.0;
    let mut off = CropRun::paper(4, Variant::Rgop, 1).unwrap();
    off.start = (0.5, 0.2);
    for mut run in [weeds, off] {
        run.duration_s = 10.0;
        let out = drive(&run);
        assert_eq!(out.end, CropEnd::Timeout);
        let first = out.ticks.first().unwrap().truth;
        assert!(
            out.ticks.iter().all(|t| t.truth == first),
            "the robot moved"
        );
        assert!(out
            .ticks
            .iter()
            .all(|t| t.phase == Phase::Measuring && t.waiting == Some(Waiting::MeasuringRows)));
    }
    let mut empty = CropRun::paper(1, Variant::Rgop, 1).unwrap();
    empty.crop.length = 0.0;
    empty.crop.weeds = 0;
    let out = drive(&empty);
    assert_eq!(out.end, CropEnd::Stopped("blind: no usable scan".into()));
    let first = out.ticks.first().unwrap().truth;
    assert!(
        out.ticks.iter().all(|t| t.truth == first),
        "the robot moved"
    );
}

#[test]
fn lidars_that_stop_sending_stop_the_robot() {
    //= spec/guyonneau2022.md#nav-blind-a-lidar-that-stops-sending
    //= type=test
    //# A tick without a scan, or whose scans hold no point, MUST keep the last
    //# command for at most the configured number of blind ticks in a row; the
    //# next such tick MUST stop the robot for good with the reason Blind.
    let mut run = CropRun::paper(2, Variant::Rgop, 3).unwrap();
    run.outage_s = Some((20.0, 1e9));
    let out = drive(&run);
    assert_eq!(out.end, CropEnd::Stopped("blind: no usable scan".into()));
    assert_eq!(out.crushed, 0);
    let last = out.ticks.last().unwrap();
    assert_eq!(last.command, (0.0, 0.0));
    // Ten blind ticks keep the last command; the eleventh, 0.25 s into the
    // outage, stops.
    assert!((last.t_s - 20.25).abs() < 1e-6, "{}", last.t_s);
    // Before it, the robot was driving, not waiting.
    assert!(out
        .ticks
        .iter()
        .filter(|t| t.t_s > 5.0 && t.t_s < 20.0)
        .all(|t| t.waiting != Some(Waiting::MeasuringRows)));
}

#[test]
fn the_built_in_crop_drives_are_the_papers_runs() {
    for (k, (name, text)) in BUILTIN.iter().enumerate() {
        assert!(is_crop_drive(text));
        let run = CropDriveFile::parse(text, name).unwrap().run(name).unwrap();
        let crop = u8::try_from(k + 1).unwrap();
        let mut paper = CropRun::paper(crop, Variant::Rgop, 2022).unwrap();
        paper.name = (*name).to_owned();
        assert_eq!(run, paper, "{name}");
    }
    // A path-tracking scenario is not a crop drive.
    assert!(!is_crop_drive(fieldguide_sim::scenario::BUILTIN[0].1));
}

#[test]
fn a_crop_drive_file_changes_what_it_says_and_refuses_what_is_wrong() {
    let head = "name = \"mine\"\ndescription = \"d\"\nseed = 9\n[crop_drive]\ncrop = 3\nvariant = \"RG\"\n";
    let text = format!(
        "{head}[field]\nspacing_m = 0.9\nweeds = 7\n[robot]\nstart_offset_m = -0.05\ntop_speed_m_s = 0.8\nlidar_outage_s = [3.0, 3.5]\n\
         [odometry]\nscale = 0.01\nyaw_drift_rad_m = 0.0\ndistance_noise = 0.0\nyaw_noise = 0.0\n\
         [[lidar]]\nmount_x_m = 0.4\nheading_deg = 0\n[[lidar]]\nmount_x_m = -0.4\nmount_y_m = 0.1\nheading_deg = 180\n"
    );
    let run = CropDriveFile::parse(&text, "mine.toml")
        .unwrap()
        .run("mine.toml")
        .unwrap();
    assert_eq!(run.name, "mine");
    assert_eq!(run.variant, Variant::Rg);
    assert_eq!(
        (run.crop.crop, run.crop.spacing, run.crop.weeds),
        (3, 0.9, 7)
    );
    assert_eq!(run.start, (0.5, -0.05));
    assert_eq!(run.top_speed_m_s, 0.8);
    assert_eq!(run.outage_s, Some((3.0, 3.5)));
    assert_eq!(run.odometry.scale, 0.01);
    assert_eq!(run.lidars.len(), 2);
    assert_eq!(run.lidars[1].y_m, 0.1);
    assert!((run.lidars[1].heading_rad - core::f64::consts::PI).abs() < 1e-12);
    // Nothing said: the paper's LiDARs.
    let plain = CropDriveFile::parse(head, "p").unwrap().run("p").unwrap();
    assert_eq!(plain.lidars, LidarMount::PAPER.to_vec());
    // Each wrong value names its field.
    let bad = [
        (format!("{head}[field]\nspacing_m = 0.1\n"), "field.spacing_m"),
        (format!("{head}[field]\nrows = 7\n"), "field.rows"),
        (head.replace("RG\"", "Pearl\""), "crop_drive.variant"),
        (head.replace("crop = 3", "crop = 0"), "crop_drive.crop"),
        (head.replace("\"mine\"", "\"a b\""), "name"),
        (format!("{head}[robot]\nlidar_outage_s = [5.0, 4.0]\n"), "robot.lidar_outage_s"),
        (
            format!("{head}[[lidar]]\nmount_x_m = 0.5\nheading_deg = 0\n[[lidar]]\nmount_x_m = -0.5\nheading_deg = 180\n[[lidar]]\nmount_x_m = 0.0\nheading_deg = 90\n"),
            "lidar",
        ),
        (format!("{head}[[lidar]]\nmount_x_m = 50.0\nheading_deg = 0\n"), "lidar[0].mount_x_m"),
    ];
    for (text, field) in bad {
        let e = CropDriveFile::parse(&text, "bad.toml").and_then(|f| f.run("bad.toml"));
        assert_eq!(e.unwrap_err().field(), Some(field), "{text}");
    }
}

#[test]
fn a_robot_with_a_front_lidar_only_stops_at_the_first_row_end_and_waits() {
    // Past the end of the first inter-row nothing is left in view: the row
    // end cannot be called (NAV-ROW-END needs a point behind), the rows are
    // lost, and the robot stands waiting for a row distance it cannot
    // measure, without running over anything.
    let mut run = CropRun::paper(1, Variant::Rgop, 5).unwrap();
    run.lidars = vec![LidarMount::PAPER[0]];
    run.duration_s = 60.0;
    let out = drive(&run);
    assert_eq!(out.end, CropEnd::Timeout);
    assert_eq!(out.crushed, 0);
    let last = out.ticks.last().unwrap();
    assert_eq!(last.waiting, Some(Waiting::MeasuringRows));
    assert_eq!(last.command, (0.0, 0.0));
    assert!(matches!(
        last.phase,
        Phase::Driving {
            row: 1,
            backward: false
        }
    ));
}
