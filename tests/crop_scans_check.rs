//! Self-tests of the synthetic crop scans: the ray caster on hand-computed
//! cases, the rows' true lines, the noise, determinism and the presets.

// Counts become f64 for statistics.
#![allow(clippy::as_conversions, clippy::cast_precision_loss)]

mod crop_scans;

use core::f64::consts::{FRAC_PI_2, PI};

use crop_scans::{
    crop, crop1, crop4, paper_mounts, uneven, Field, FieldSpec, Lidar, Mount, Pose, Row, Stem,
    NO_RETURN, STEM_RADIUS,
};

/// A field of the given stems and no rows.
fn stems(at: &[(f64, f64)]) -> Field {
    Field {
        rows: Vec::new(),
        stems: at
            .iter()
            .map(|&(x, y)| Stem {
                x,
                y,
                r: STEM_RADIUS,
                row: Some(0),
            })
            .collect(),
        plants: at.len(),
    }
}

/// One noiseless ray along the sensor's x axis, paper range limits.
fn one_ray() -> Lidar {
    Lidar {
        rays: 1,
        start: 0.0,
        increment: 0.0,
        ..Lidar::paper().noiseless()
    }
}

const ORIGIN: Pose = Pose::new(0.0, 0.0, 0.0);

#[test]
fn a_stem_straight_ahead_at_two_metres_is_seen_at_its_near_face() {
    let scan = stems(&[(2.0, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &one_ray(), 1);
    assert!((scan.ranges[0] - (2.0 - STEM_RADIUS)).abs() < 1e-12);

    // The paper's LiDAR has no ray at 0: its two middle rays are at ±π/718.
    let lidar = Lidar::paper().noiseless();
    let scan = stems(&[(2.0, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &lidar, 1);
    let a = PI / 718.0;
    let expected = 2.0 * a.cos() - (STEM_RADIUS.powi(2) - (2.0 * a.sin()).powi(2)).sqrt();
    for k in [179, 180] {
        assert!((lidar.angle(k).abs() - a).abs() < 1e-12);
        assert!(
            (scan.ranges[k] - expected).abs() < 1e-12,
            "{}",
            scan.ranges[k]
        );
    }
    let hits = scan.ranges.iter().filter(|r| r.is_finite()).count();
    // The stem subtends 2 asin(0.01) ≈ 0.02 rad, a little over two rays.
    assert!((2..=3).contains(&hits), "{hits}");
}

#[test]
fn a_stem_beyond_the_maximum_range_gives_no_return() {
    let scan = stems(&[(5.0, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &one_ray(), 1);
    assert!(scan.ranges[0].is_infinite() && scan.ranges[0] > 0.0);
    assert!(!scan.scan().limits.accepts(scan.ranges[0]));
    // Just inside the range is a return; just outside is not.
    let inside = stems(&[(4.01, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &one_ray(), 1);
    assert!((inside.ranges[0] - 3.99).abs() < 1e-12);
    let outside = stems(&[(4.03, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &one_ray(), 1);
    assert_eq!(outside.ranges[0].to_bits(), NO_RETURN.to_bits());
    // Nothing at all, or a stem behind the sensor: no return.
    for field in [stems(&[]), stems(&[(-2.0, 0.0)])] {
        let scan = field.cast(&ORIGIN, &Mount::CENTRE, &one_ray(), 1);
        assert!(scan.ranges[0].is_infinite());
    }
}

#[test]
fn a_stem_behind_a_nearer_one_is_occluded() {
    let lidar = one_ray();
    let both = stems(&[(3.0, 0.0), (2.0, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &lidar, 1);
    assert!((both.ranges[0] - 1.98).abs() < 1e-12);
    let far = stems(&[(3.0, 0.0)]).cast(&ORIGIN, &Mount::CENTRE, &lidar, 1);
    assert!((far.ranges[0] - 2.98).abs() < 1e-12);
    // Grazing the nearer stem's edge still hits it.
    let graze = stems(&[(3.0, 0.0), (2.0, 0.019)]).cast(&ORIGIN, &Mount::CENTRE, &lidar, 1);
    assert!(graze.ranges[0] < 2.0);
}

#[test]
fn the_mount_and_the_robot_pose_place_the_sensor() {
    // Robot at (1, 1) facing +y; the back LiDAR, 0.5 m behind, faces −y.
    let robot = Pose::new(1.0, 1.0, FRAC_PI_2);
    let [front, back] = paper_mounts(0.5);
    let field = stems(&[(1.0, -1.5), (1.0, 4.0)]);
    let b = field.cast(&robot, &back, &one_ray(), 1);
    assert!((b.sensor.x - 1.0).abs() < 1e-12 && (b.sensor.y - 0.5).abs() < 1e-12);
    assert!((b.ranges[0] - 1.98).abs() < 1e-12, "{}", b.ranges[0]);
    let f = field.cast(&robot, &front, &one_ray(), 1);
    assert!((f.ranges[0] - 2.48).abs() < 1e-12, "{}", f.ranges[0]);
    // A mount turned left by 90° from the robot at the origin looks along +y.
    let side = Mount {
        x: 0.0,
        y: 0.0,
        yaw: FRAC_PI_2,
    };
    let s = stems(&[(0.0, 1.0)]).cast(&ORIGIN, &side, &one_ray(), 1);
    assert!((s.ranges[0] - 0.98).abs() < 1e-12);
}

#[test]
fn every_noiseless_return_lies_on_a_stem_surface() {
    let field = crop(3, 7, 0.75).build();
    let robot = field.between(1, 2, 5.0);
    let scan = field.cast(&robot, &Mount::front(0.3), &Lidar::paper().noiseless(), 1);
    let mut returns = 0;
    for (k, r) in scan.ranges.iter().enumerate() {
        if !r.is_finite() {
            continue;
        }
        returns += 1;
        let a = scan.sensor.heading + scan.lidar.angle(k);
        let (x, y) = (scan.sensor.x + r * a.cos(), scan.sensor.y + r * a.sin());
        let gap = field
            .stems
            .iter()
            .map(|s| ((x - s.x).hypot(y - s.y) - s.r).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(gap < 1e-9, "ray {k}: {gap}");
    }
    assert!(returns > 50, "{returns}");
}

#[test]
fn row_lines_in_the_robot_frame_by_hand() {
    // Rows along x at y = 0, 0.75, 1.5, …; robot at y = 1.0 facing +x.
    let field = crop1(1, 0.75).build();
    let robot = Pose::new(3.0, 1.0, 0.0);
    for (i, line) in field.row_lines(&robot) {
        assert!(line.a.abs() < 1e-12);
        assert!((line.b - (i as f64 * 0.75 - 1.0)).abs() < 1e-12);
    }
    let (left, l) = field.left_row(&robot).unwrap();
    let (right, r) = field.right_row(&robot).unwrap();
    assert_eq!((right, left), (1, 2));
    assert!((l.b - 0.5).abs() < 1e-12 && (r.b + 0.25).abs() < 1e-12);
    let mid = field.middle_line(&robot).unwrap();
    assert!(mid.a.abs() < 1e-12 && (mid.b - 0.125).abs() < 1e-12);
    // Turned by 0.1 rad to the left, the rows slope down by tan 0.1.
    let turned = Pose::new(3.0, 1.0, 0.1);
    for (_, line) in field.row_lines(&turned) {
        assert!((line.a + 0.1f64.tan()).abs() < 1e-12);
    }
    // Facing across the rows, no row has a line y = a x + b.
    assert!(field.row_line(0, &Pose::new(0.0, 0.0, FRAC_PI_2)).is_none());
    assert!(field.left_row(&Pose::new(0.0, 0.0, FRAC_PI_2)).is_none());
}

#[test]
fn row_lines_pass_through_their_plants_in_the_robot_frame() {
    let mut skewed = uneven(11, 1.2);
    skewed.direction = 0.3;
    for spec in [crop1(3, 0.9), skewed] {
        let field = spec.build();
        let robot = field.between(1, 2, 4.0);
        let robot = Pose::new(robot.x + 0.1, robot.y - 0.05, robot.heading + 0.07);
        let (c, s) = (robot.heading.cos(), robot.heading.sin());
        for stem in &field.stems[..field.plants] {
            let line = field.row_line(stem.row.unwrap(), &robot).unwrap();
            let (dx, dy) = (stem.x - robot.x, stem.y - robot.y);
            let (x, y) = (c * dx + s * dy, -s * dx + c * dy);
            assert!((y - line.y(x)).abs() < 1e-9, "{stem:?}");
        }
        // The rows directly left and right are the ones the robot is between.
        assert_eq!(field.left_row(&robot).unwrap().0, 2);
        assert_eq!(field.right_row(&robot).unwrap().0, 1);
    }
}

#[test]
fn noise_has_the_lidar_standard_deviation() {
    // A wide stem 2 m ahead fills the middle of the scan.
    let field = Field {
        rows: Vec::new(),
        stems: vec![Stem {
            x: 2.5,
            y: 0.0,
            r: 1.0,
            row: None,
        }],
        plants: 0,
    };
    let lidar = Lidar::paper();
    let exact = field.cast(&ORIGIN, &Mount::CENTRE, &lidar.noiseless(), 0);
    let mut residuals = Vec::new();
    for seed in 0..40 {
        let noisy = field.cast(&ORIGIN, &Mount::CENTRE, &lidar, seed);
        for (n, e) in noisy.ranges.iter().zip(&exact.ranges) {
            assert_eq!(n.is_finite(), e.is_finite());
            if e.is_finite() {
                residuals.push(n - e);
            }
        }
    }
    let n = residuals.len() as f64;
    assert!(n > 3000.0, "{n}");
    let mean = residuals.iter().sum::<f64>() / n;
    let sd = (residuals.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    // Standard errors: σ/√n ≈ 1.7e-4 on the mean, σ/√(2n) ≈ 1.2e-4 on σ.
    assert!(mean.abs() < 6e-4, "mean {mean}");
    assert!((sd - 0.01).abs() < 5e-4, "sd {sd}");
    let beyond = residuals.iter().filter(|r| r.abs() > 0.02).count() as f64 / n;
    assert!((beyond - 0.0455).abs() < 0.01, "beyond 2σ: {beyond}");
}

#[test]
fn the_same_seed_gives_the_same_scan_bit_for_bit() {
    let bits = |v: &[f64]| v.iter().map(|r| r.to_bits()).collect::<Vec<_>>();
    let robot = Pose::new(5.0, 1.1, 0.02);
    let one = crop4(5, 0.75).build();
    let two = crop4(5, 0.75).build();
    assert_eq!(one, two);
    let a = one.cast(&robot, &Mount::front(0.3), &Lidar::paper(), 9);
    let b = two.cast(&robot, &Mount::front(0.3), &Lidar::paper(), 9);
    assert_eq!(bits(&a.ranges), bits(&b.ranges));
    let c = one.cast(&robot, &Mount::front(0.3), &Lidar::paper(), 10);
    assert_ne!(bits(&a.ranges), bits(&c.ranges));
    assert_ne!(crop4(6, 0.75).build(), one);
    let drive = |seed| {
        one.drive_between(
            1,
            1.0,
            0.5,
            4,
            (0.05, 0.05),
            &paper_mounts(0.3),
            &Lidar::paper(),
            seed,
        )
    };
    assert_eq!(drive(3), drive(3));
    assert_ne!(drive(3), drive(4));
}

#[test]
fn presets_have_their_features() {
    for seed in [1, 2] {
        let fields: Vec<(FieldSpec, Field)> = (1..=4)
            .map(|n| {
                let spec = crop(n, seed, 0.75);
                let field = spec.build();
                (spec, field)
            })
            .collect();
        // Crop 1: every 0.2 m on 10 m, 51 plants a row.
        assert_eq!(fields[0].1.plants, 5 * 51);
        assert_eq!(fields[0].1.stems.len(), 5 * 51);
        let gaps_regular = fields[0]
            .1
            .stems
            .windows(2)
            .all(|w| w[0].row != w[1].row || ((w[1].x - w[0].x) - 0.2).abs() < 1e-9);
        assert!(gaps_regular);
        // Crop 2: irregular gaps.
        let gaps: Vec<f64> = fields[1]
            .1
            .stems
            .windows(2)
            .filter(|w| w[0].row == w[1].row)
            .map(|w| w[1].x - w[0].x)
            .collect();
        assert!(gaps.iter().any(|g| (g - 0.2).abs() > 0.05));
        // Crops 3 and 4: 50 and 100 weeds of radius 0.01-0.02 m.
        for (i, weeds) in [(2, 50), (3, 100)] {
            let f = &fields[i].1;
            assert_eq!(f.stems.len() - f.plants, weeds);
            assert!(f.stems[f.plants..]
                .iter()
                .all(|s| s.row.is_none() && (0.01..=0.02).contains(&s.r)));
        }
        // Crop 4: fewer plants, rows evenly spaced and parallel; the uneven
        // field moves and turns them.
        let f = &fields[3].1;
        assert!(f.plants < 5 * 51 - 5 * 3 - 10, "{}", f.plants);
        let even = |f: &Field| {
            let offsets: Vec<f64> = f.rows.iter().map(|r: &Row| r.y0).collect();
            offsets
                .windows(2)
                .all(|w| ((w[1] - w[0]) - 0.75).abs() < 1e-12)
                && f.rows.iter().all(|r| r.direction == 0.0)
        };
        assert!(even(f));
        assert!(!even(&uneven(seed, 0.75).build()));
        for h in &fields[3].0.holes {
            assert!(!f.stems[..f.plants].iter().any(|s| {
                let row = &f.rows[h.row];
                let t = (s.x - row.x0) * row.direction.cos() + (s.y - row.y0) * row.direction.sin();
                s.row == Some(h.row) && t >= h.from && t <= h.to
            }));
        }
    }
}

#[test]
fn each_preset_seen_from_between_two_rows_has_returns_on_both_sides() {
    for n in 1..=4 {
        for spacing in [0.75, 1.5] {
            let field = crop(n, 21, spacing).build();
            let robot = field.between(1, 2, 5.0);
            let mid = field.middle_line(&robot).unwrap();
            assert!(
                mid.a.abs() < 0.02 && mid.b.abs() < 1e-3,
                "crop {n}: {mid:?}"
            );
            for mount in paper_mounts(0.3) {
                let scan = field.cast(&robot, &mount, &Lidar::paper(), 5);
                let points = scan.points();
                let left = points.iter().filter(|p| p.1 > 0.0).count();
                let right = points.iter().filter(|p| p.1 < 0.0).count();
                assert!(
                    left >= 20 && right >= 20,
                    "crop {n}, {spacing} m: {left} left, {right} right"
                );
                let lib = scan.scan();
                let valid = lib
                    .ranges
                    .iter()
                    .filter(|r| lib.limits.accepts(**r))
                    .count();
                assert_eq!(valid, points.len());
            }
        }
    }
}

#[test]
fn a_drive_between_two_rows_stays_between_them() {
    let field = crop(4, 8, 0.75).build();
    let lidar = Lidar::paper();
    let samples = field.drive_between(1, 1.0, 0.1, 60, (0.05, 0.03), &paper_mounts(0.3), &lidar, 2);
    assert_eq!(samples.len(), 60);
    for (i, s) in samples.iter().enumerate() {
        let centre = field.between(1, 2, 1.0 + i as f64 * 0.1);
        let (along, across) = centre.local(s.robot.x, s.robot.y);
        assert!(along.abs() < 1e-9 && across.abs() <= 0.05 + 1e-12);
        assert!((s.robot.heading - centre.heading).abs() <= 0.03 + 1e-12);
        let (l, r) = (
            field.left_row(&s.robot).unwrap(),
            field.right_row(&s.robot).unwrap(),
        );
        assert_eq!((l.0, r.0), (2, 1));
        assert_eq!(s.scans.len(), 2);
        assert!(s.scans.iter().all(|scan| scan.points().len() > 30));
    }
}
