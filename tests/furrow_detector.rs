//! The furrow detector end to end on exact synthetic scans: convergence of
//! the error on one and two rows, the verdict, bad input, configuration
//! validation, and no panic or NaN for any scan (Pierre 2022 section 2.3;
//! FUR-SCAN, FUR-QUALITY, FUR-CONFIG and the rest through them).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

mod furrow_common;

use fieldguide::perception::furrow::quality::furrow_verdict;
use fieldguide::perception::furrow::scan::{scan_to_points, MountPose, ScanWindow, WindowRays};
use fieldguide::perception::furrow::{
    FurrowConfig, FurrowDetection, FurrowDetector, FurrowParams, RowLines, Rows,
};
use fieldguide::perception::{Better, QualityThresholds, RangeLimits, Scan};
use fieldguide::{Meters, Odom, Pose2, Radians, Verdict};
use furrow_common::{flat_scan, ridge_scan, Lidar, Ridge};
use proptest::prelude::*;

type Detector = FurrowDetector<256, 32>;

/// A change to a parameter set.
type Change = Box<dyn Fn(&mut FurrowParams)>;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn lidar() -> Lidar {
    Lidar::centred(360, core::f64::consts::FRAC_PI_2)
}

/// The sensor's valid ranges, 0.1-20 m.
fn limits() -> RangeLimits {
    RangeLimits::new(m(0.1), m(20.0)).unwrap()
}

fn scan<'a>(ranges: &'a [f64], l: &Lidar) -> Scan<'a> {
    Scan {
        start: Radians::new(l.angle_min).unwrap(),
        increment: Radians::new(l.increment).unwrap(),
        ranges,
        limits: limits(),
    }
}

/// Two rows 0.75 m apart of plants `height` m tall.
fn rows(height: f64) -> Vec<Ridge> {
    [-0.375, 0.375]
        .iter()
        .map(|&c| Ridge {
            center_y: c,
            half_width: 0.08,
            height,
        })
        .collect()
}

fn maize() -> Vec<Ridge> {
    rows(0.5)
}

/// Drives straight from `(0, y0)` at heading `psi` for `ticks` scans of 0.028 m
/// (0.7 m/s at 25 Hz) and returns the last detection and pose.
fn drive(
    params: &FurrowParams,
    ridges: &[Ridge],
    y0: f64,
    psi: f64,
    ticks: usize,
) -> (FurrowDetection, (f64, f64, f64)) {
    let mut det = Detector::new(FurrowConfig::new(params).unwrap()).unwrap();
    let l = lidar();
    let mut pose = (0.0, y0, psi);
    let mut last = None;
    for _ in 0..ticks {
        let ranges = ridge_scan(params, &l, pose, ridges);
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        last = Some(det.detect(&scan(&ranges, &l), &odom).unwrap());
        pose = (pose.0 + 0.028 * psi.cos(), pose.1 + 0.028 * psi.sin(), psi);
    }
    (last.unwrap(), pose)
}

//= spec/pierre2022.md#fur-two-rows-error-to-the-middle-of-two-rows
//= type=test
//# With two rows, the tracking error MUST be the mean of the errors to the
//# left and right lines: y = (y_l + y_r)/2 and θ̃ = (θ̃_l + θ̃_r)/2.
#[test]
fn two_rows_give_the_error_to_the_centre_line() {
    let params = FurrowParams::table2();
    // Parallel to the rows, the plants are seen symmetrically: the error is
    // the robot's offset from the centre line, to a centimetre.
    // With a heading, a ray meets the near row's plants on their inner faces:
    // the line found is the visible surface, up to a plant half width
    // (0.08 m) off the plants' axes, and the error carries half of it.
    for (y0, psi, tolerance) in [
        (0.0, 0.0, 0.01),
        (0.12, 0.0, 0.01),
        (-0.15, 0.0, 0.01),
        (-0.15, 0.05, 0.04),
        (0.05, -0.08, 0.05),
    ] {
        let (d, pose) = drive(&params, &rows(0.3), y0, psi, 60);
        let before = (pose.0 - 0.028 * psi.cos(), pose.1 - 0.028 * psi.sin());
        assert_eq!(d.verdict, Verdict::Enter, "{y0} {psi}");
        let e = d.error.unwrap();
        assert!(
            (e.y.get() - before.1).abs() < tolerance,
            "y {} vs {}",
            e.y.get(),
            before.1
        );
        assert!(
            (e.angular_deviation.get() - psi).abs() < 0.01,
            "θ̃ {} vs {psi}",
            e.angular_deviation.get()
        );
        assert!(matches!(d.lines, Some(RowLines::Two(_))));
        assert!(d.quality.unwrap() > 0.4);
    }
    // Maize, 0.5 m tall, is taller than the plant model: still Enter, and the
    // error still has the offset's sign.
    for y0 in [-0.1, 0.1] {
        let (d, _) = drive(&params, &maize(), y0, 0.0, 60);
        assert_eq!(d.verdict, Verdict::Enter);
        assert!(d.error.unwrap().y.get() * y0 > 0.0);
    }
}

//= spec/pierre2022.md#fur-errors-tracking-error-to-a-row-line
//= type=test
//# The tracking error to the line y = a x + b of the robot frame MUST be
//# y = −b / sqrt(a² + 1) and θ̃ = −arctan(a).
#[test]
fn one_row_gives_the_error_to_that_row() {
    let mut params = FurrowParams::table2();
    params.rows = Rows::One;
    let row = [Ridge {
        center_y: 0.3,
        half_width: 0.08,
        height: 0.3,
    }];
    for (y0, psi) in [(0.0, 0.0), (0.5, -0.04)] {
        let (d, pose) = drive(&params, &row, y0, psi, 60);
        let before_y = pose.1 - 0.028 * psi.sin();
        assert_eq!(d.verdict, Verdict::Enter);
        let e = d.error.unwrap();
        // The robot is right of the row when y0 < 0.3: negative error.
        assert!(
            (e.y.get() - (before_y - 0.3)).abs() < 0.03,
            "y {} vs {}",
            e.y.get(),
            before_y - 0.3
        );
        assert!((e.angular_deviation.get() - psi).abs() < 0.01);
    }
}

//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//= type=test
//# The verdict MUST be Absent when no row line could be fitted from the
//# accumulated points.
#[test]
fn bad_scans_are_absent() {
    let params = FurrowParams::table2();
    let l = lidar();
    let odom = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    let flat = flat_scan(&params, &l, 0.02);
    let nan = vec![f64::NAN; 360];
    let inf = vec![f64::INFINITY; 360];
    let empty: Vec<f64> = vec![];
    for ranges in [&flat, &nan, &inf, &empty] {
        let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
        for _ in 0..30 {
            let d = det.detect(&scan(ranges, &l), &odom).unwrap();
            assert_eq!(d.verdict, Verdict::Absent);
            assert!(d.error.is_none() && d.lines.is_none());
            assert_eq!(d.maxima, 0);
        }
    }
    // Rows closer than d_min: maxima, but never a pair.
    let close: Vec<Ridge> = [-0.2, 0.2]
        .iter()
        .map(|&c| Ridge {
            center_y: c,
            half_width: 0.08,
            height: 0.5,
        })
        .collect();
    let (d, _) = drive(&params, &close, 0.0, 0.0, 40);
    assert_eq!(d.verdict, Verdict::Absent);
    assert!(d.maxima >= 2 && d.selected.is_none());
    // A template wider than the window: no score, no maxima.
    let mut wide = params;
    wide.template_width = 171;
    let (d, _) = drive(&wide, &maize(), 0.0, 0.0, 40);
    assert_eq!((d.verdict, d.maxima), (Verdict::Absent, 0));
    // A standing robot sees the same slice: the points do not spread along x.
    let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    let ranges = ridge_scan(
        &params,
        &l,
        (0.0, 0.0, 0.0),
        &[
            Ridge {
                center_y: 0.375,
                half_width: 0.08,
                height: 0.0001,
            },
            Ridge {
                center_y: -0.375,
                half_width: 0.3,
                height: 0.3,
            },
        ],
    );
    for _ in 0..30 {
        let d = det.detect(&scan(&ranges, &l), &odom).unwrap();
        assert_eq!(d.verdict, Verdict::Absent);
    }
}

//= spec/pierre2022.md#fur-scan-scan-to-robot-frame-points-in-an-angular-window
//= type=test
//# A ray whose range is not finite or lies outside the sensor's [min, max)
//# MUST be dropped while keeping its index, so that window ray i is scan ray
//# first + i.
#[test]
fn scans_the_detector_cannot_read_are_errors_and_dropped_rays_keep_indices() {
    let params = FurrowParams::table2();
    let l = lidar();
    let odom = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    let ranges = ridge_scan(&params, &l, (0.0, 0.0, 0.0), &maize());
    // A window of 161 rays does not fit in 64.
    let mut small = FurrowDetector::<64, 32>::new(FurrowConfig::new(&params).unwrap()).unwrap();
    assert_eq!(
        small
            .detect(&scan(&ranges, &l), &odom)
            .unwrap_err()
            .requirement,
        "FUR-SCAN"
    );
    let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    for inc in [0.0, -0.01] {
        let bad = Scan {
            start: Radians::new(-0.5).unwrap(),
            increment: Radians::new(inc).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        assert_eq!(det.detect(&bad, &odom).unwrap_err().requirement, "FUR-SCAN");
    }
    // Dropping rays far from the plants moves no maximum.
    let (clean, w) = det.maxima(&scan(&ranges, &l)).unwrap();
    let mut holed = ranges.clone();
    for j in (w.first..w.first + w.count).step_by(7) {
        let near_max = clean.iter().any(|mx| (w.first + mx.ray).abs_diff(j) <= 30);
        if !near_max {
            // Not a number, beyond the sensor's range, or its "no return" max.
            holed[j] = match j % 3 {
                0 => f64::NAN,
                1 => 1e9,
                _ => limits().max(),
            };
        }
    }
    let (with_holes, w2) = det.maxima(&scan(&holed, &l)).unwrap();
    assert_eq!(w, w2);
    assert_eq!(clean.len(), with_holes.len());
    for (a, b) in clean.iter().zip(&with_holes) {
        assert_eq!(a.ray, b.ray);
        assert!(a.point.distance_to(b.point).unwrap().get() < 1e-12);
    }
}

//= spec/pierre2022.md#fur-scan-scan-to-robot-frame-points-in-an-angular-window
//= type=test
//# Each ray of the scan whose in-plane angle a satisfies |a| ≤ a_w MUST be
//# converted into the robot-frame point x = x_m + r cos a cos p,
//# y = y_m + r sin a, z = h_m − r cos a sin p, where (x_m, y_m, h_m) is the
//# mount position and p its pitch (positive down).
#[test]
fn prepending_rays_shifts_the_window_not_the_plants() {
    let params = FurrowParams::table2();
    let l = lidar();
    let det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    let ranges = ridge_scan(&params, &l, (0.0, 0.05, 0.02), &maize());
    let (a, wa) = det.maxima(&scan(&ranges, &l)).unwrap();
    for s in [1_usize, 13, 40] {
        let mut longer = vec![f64::NAN; s];
        longer.extend_from_slice(&ranges);
        let shifted = Scan {
            start: Radians::new(l.angle_min - s as f64 * l.increment).unwrap(),
            increment: Radians::new(l.increment).unwrap(),
            ranges: &longer,
            limits: limits(),
        };
        let (b, wb) = det.maxima(&shifted).unwrap();
        assert_eq!(wb.first, wa.first + s);
        assert_eq!(wb.count, wa.count);
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.ray, y.ray);
            assert!(x.point.distance_to(y.point).unwrap().get() < 1e-9);
        }
    }
    // The window holds the rays with |a| ≤ 0.35 rad, and its points follow the formula.
    assert!(wa.count > 150 && wa.count < 170);
    let a0 = l.angle_min + wa.first as f64 * l.increment;
    assert!(a0 >= -0.35 && a0 - l.increment < -0.35);
}

//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//= type=test
//# Otherwise the verdict MUST be Exit when the scan yielded no selection,
//# and else the classification (SW-CLASSIFY, larger is better) of the
//# weaker score of the selection: min(c[k_l], c[k_r]) for a pair, c[k] for
//# one row.
#[test]
fn verdicts_from_the_weaker_maximum() {
    let t = QualityThresholds::new(0.4, 0.2, Better::Higher).unwrap();
    assert_eq!(furrow_verdict(&t, true, Some(0.41)), Verdict::Enter);
    assert_eq!(furrow_verdict(&t, true, Some(0.4)), Verdict::Hold);
    assert_eq!(furrow_verdict(&t, true, Some(0.3)), Verdict::Hold);
    assert_eq!(furrow_verdict(&t, true, Some(0.2)), Verdict::Hold);
    assert_eq!(furrow_verdict(&t, true, Some(0.19)), Verdict::Exit);
    assert_eq!(furrow_verdict(&t, true, None), Verdict::Exit);
    assert_eq!(furrow_verdict(&t, false, Some(0.9)), Verdict::Absent);
    assert_eq!(furrow_verdict(&t, false, None), Verdict::Absent);
}

//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//= type=test
//# Otherwise the verdict MUST be Exit when the scan yielded no selection,
//# and else the classification (SW-CLASSIFY, larger is better) of the
//# weaker score of the selection: min(c[k_l], c[k_r]) for a pair, c[k] for
//# one row.
#[test]
fn a_stretch_without_plants_is_exit_then_absent_never_a_line() {
    let params = FurrowParams::table2();
    let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    let l = lidar();
    let mut x = 0.0;
    for _ in 0..60 {
        let ranges = ridge_scan(&params, &l, (x, 0.0, 0.0), &maize());
        let d = det
            .detect(&scan(&ranges, &l), &Pose2::new(x, 0.0, 0.0).unwrap())
            .unwrap();
        let (c_l, c_r) = match d.selected {
            Some(_) => (d.quality.unwrap(), d.quality.unwrap()),
            None => (0.0, 0.0),
        };
        assert!(c_l.min(c_r) >= 0.0);
        x += 0.028;
    }
    // Bare ground: Exit while the old line lasts (its points were seen about
    // 4 m ahead and are kept until 6 m behind), then Absent.
    let mut seen = Vec::new();
    while x < 60.0 * 0.028 + 11.0 {
        let flat = flat_scan(&params, &l, 0.01);
        let d = det
            .detect(&scan(&flat, &l), &Pose2::new(x, 0.0, 0.0).unwrap())
            .unwrap();
        assert!(matches!(d.verdict, Verdict::Exit | Verdict::Absent));
        seen.push(d.verdict);
        x += 0.028;
    }
    assert_eq!(seen[0], Verdict::Exit);
    assert_eq!(*seen.last().unwrap(), Verdict::Absent);
    assert_eq!(det.accumulated(), 0);
}

//= spec/pierre2022.md#fur-config-configuration-validated-once
//= type=test
//# A furrow configuration MUST be validated once, at construction, and a
//# configuration that breaks a precondition of FUR-SCAN, FUR-TEMPLATE,
//# FUR-SIGNAL, FUR-MAXIMA, FUR-SELECT-PAIR, FUR-ACCUMULATE, FUR-LINE or
//# SW-THRESHOLDS MUST be refused with an error naming that requirement.
#[test]
fn bad_configurations_name_their_requirement() {
    let base = FurrowParams::table2();
    assert!(FurrowConfig::new(&base).is_ok());
    let cases: Vec<(&str, Change)> = vec![
        ("FUR-SCAN", Box::new(|p| p.mount_height = m(0.0))),
        (
            "FUR-SCAN",
            Box::new(|p| p.mount_pitch = Radians::new(-0.1).unwrap()),
        ),
        (
            "FUR-SCAN",
            Box::new(|p| p.window_half_angle = Radians::new(2.0).unwrap()),
        ),
        ("FUR-TEMPLATE", Box::new(|p| p.template_width = 14)),
        ("FUR-TEMPLATE", Box::new(|p| p.template_width = 0)),
        ("FUR-TEMPLATE", Box::new(|p| p.template_height = m(-0.3))),
        ("FUR-SIGNAL", Box::new(|p| p.height_floor = m(0.3))),
        ("FUR-SIGNAL", Box::new(|p| p.height_floor = m(-0.01))),
        ("FUR-MAXIMA", Box::new(|p| p.peak_threshold = 1.0)),
        ("FUR-MAXIMA", Box::new(|p| p.peak_threshold = f64::NAN)),
        (
            "FUR-SELECT-PAIR",
            Box::new(|p| {
                p.rows = Rows::Two {
                    min_spacing: m(0.9),
                    max_spacing: m(0.66),
                }
            }),
        ),
        ("FUR-ACCUMULATE", Box::new(|p| p.averaged_scans = 0)),
        ("FUR-ACCUMULATE", Box::new(|p| p.keep_distance = m(0.0))),
        ("FUR-SPAN", Box::new(|p| p.min_span = m(-0.5))),
        ("FUR-LINE", Box::new(|p| p.min_points = 1)),
        ("FUR-LINE", Box::new(|p| p.min_extent = m(-1.0))),
        ("SW-THRESHOLDS", Box::new(|p| p.enter = 0.1)),
    ];
    for (requirement, change) in cases {
        let mut p = base;
        change(&mut p);
        assert_eq!(
            FurrowConfig::new(&p).unwrap_err().requirement,
            requirement,
            "{p:?}"
        );
    }
    let mut p = base;
    p.averaged_scans = 33;
    assert_eq!(
        Detector::new(FurrowConfig::new(&p).unwrap())
            .unwrap_err()
            .requirement,
        "FUR-ACCUMULATE"
    );
}

fn range_strategy() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(f64::MAX),
        any::<f64>(),
        0.0_f64..30.0,
        2.0_f64..3.5,
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    //= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
    //= type=test
    //# The verdict MUST be Absent when no row line could be fitted from the
    //# accumulated points.
    #[test]
    fn no_panic_and_no_nan_for_any_scan(
        scans in prop::collection::vec(prop::collection::vec(range_strategy(), 0..400), 1..6),
        angle_min in prop_oneof![Just(-0.785), -10.0_f64..10.0],
        increment in prop_oneof![Just(0.004_37), -0.1_f64..0.1, Just(1e-300)],
        pose in (-1e6_f64..1e6, -1e6_f64..1e6, -4.0_f64..4.0),
        one_row in any::<bool>(),
    ) {
        let mut params = FurrowParams::table2();
        if one_row {
            params.rows = Rows::One;
        }
        let mut det = FurrowDetector::<512, 32>::new(FurrowConfig::new(&params).unwrap()).unwrap();
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        for ranges in &scans {
            let s = Scan {
                start: Radians::new(angle_min).unwrap(),
                increment: Radians::new(increment).unwrap(),
                ranges,
                limits: limits(),
            };
            match det.detect(&s, &odom) {
                Ok(d) => {
                    prop_assert_eq!(d.error.is_none(), d.verdict == Verdict::Absent);
                    prop_assert_eq!(d.lines.is_none(), d.verdict == Verdict::Absent);
                    if let Some(q) = d.quality {
                        prop_assert!(q.is_finite() && q > params.peak_threshold && q <= 1.0);
                    }
                    if let Some(e) = d.error {
                        prop_assert!(e.y.get().is_finite() && e.angular_deviation.get().is_finite());
                    }
                }
                Err(e) => prop_assert_eq!(e.requirement, "FUR-SCAN"),
            }
        }
    }
}

fn rad(v: f64) -> Radians {
    Radians::new(v).unwrap()
}

#[test]
fn ground_ray_lands_at_zero_height() {
    let mount = MountPose::new(m(1.5), m(0.2), m(1.0), rad(0.4)).unwrap();
    let window = ScanWindow::new(rad(0.3)).unwrap();
    let r = mount.ground_range(rad(0.0)).unwrap();
    let ranges = [r];
    let scan = Scan {
        start: rad(0.0),
        increment: rad(0.01),
        ranges: &ranges,
        limits: RangeLimits::new(m(0.0), m(30.0)).unwrap(),
    };
    let mut out = [None; 4];
    let w = scan_to_points(&scan, &mount, &window, &mut out).unwrap();
    assert_eq!(w, WindowRays { first: 0, count: 1 });
    let p = out[0].unwrap();
    assert!(p.height.get().abs() < 1e-12);
    assert!((p.ground.x() - (1.5 + 1.0 / libm::tan(0.4))).abs() < 1e-12);
    assert!((p.ground.y() - 0.2).abs() < 1e-12);
}

#[test]
fn bad_mounts_and_windows_are_refused() {
    assert!(MountPose::new(m(0.0), m(0.0), m(0.0), rad(0.3)).is_err());
    assert!(MountPose::new(m(0.0), m(0.0), m(1.0), rad(0.0)).is_err());
    assert!(MountPose::new(m(0.0), m(0.0), m(1.0), rad(1.6)).is_err());
    assert!(ScanWindow::new(rad(0.0)).is_err());
    assert!(ScanWindow::new(rad(1.6)).is_err());
    assert!(ScanWindow::new(rad(0.2)).is_ok());
}

/// The first line on two rows: with FUR-LINE alone, 0.3 m of travel (11
/// scans of 0.028 m) before the points span the minimum extent; with
/// FUR-FIRST-LINE, at the fifth scan (`min_points`), along the heading, and
/// on the rows' centre.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# The row line MUST be the (a, b) that minimises
//# Σ (a p_x + b − p_y)² + Λ (a − tan φ)² over the row's accumulated points,
//# with φ the first-line heading read in the current robot frame,
//# Λ = n max(E² − D², 0) / 12, n the number of points, D their extent along x
//# and E the larger of the minimum extent and 2 m.
#[test]
fn the_first_line_comes_with_the_fifth_scan_on_the_rows_centre() {
    let params = FurrowParams::table2();
    for y0 in [-0.15, 0.12, 0.0] {
        let (d4, _) = drive(&params, &rows(0.3), y0, 0.0, 4);
        assert_eq!(d4.verdict, Verdict::Absent, "{y0}");
        let (d5, _) = drive(&params, &rows(0.3), y0, 0.0, 5);
        assert_eq!(d5.verdict, Verdict::Enter, "{y0}");
        let e = d5.error.unwrap();
        // Four scans of 0.028 m: 0.11 m of points, well under E = 0.3 m. The
        // rows' centre within 0.02 m (the near row is seen on its inner face,
        // 0.08 m wide), and where the line settles after 60 scans within 5 mm.
        let (settled, _) = drive(&params, &rows(0.3), y0, 0.0, 60);
        let settled = settled.error.unwrap().y.get();
        assert!((e.y.get() - y0).abs() < 0.02, "{y0}: {}", e.y.get());
        assert!(
            (e.y.get() - settled).abs() < 0.005,
            "{y0}: {} vs {settled}",
            e.y.get()
        );
        assert!(
            e.angular_deviation.get().abs() < 0.01,
            "{y0}: {}",
            e.angular_deviation.get()
        );
    }
}

/// A robot turning as it first sees the rows gets no first line: the line
/// waits for the points to span the minimum extent, as with FUR-LINE alone.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# While the points span less than the minimum extent, the detector MUST give
//# no line before the first-line heading is set, and none once the accumulation
//# has held its capacity of selections since it was last empty.
#[test]
fn no_first_line_while_the_robot_turns() {
    let params = FurrowParams::table2();
    let l = lidar();
    for (rate, first_line_at) in [(0.004, 12), (-0.004, 12), (0.002, 5), (0.0, 5)] {
        let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
        let mut pose = (0.0_f64, 0.1_f64, -0.01_f64);
        let mut first = None;
        for tick in 1..=14 {
            let ranges = ridge_scan(&params, &l, pose, &rows(0.3));
            let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
            let d = det.detect(&scan(&ranges, &l), &odom).unwrap();
            if first.is_none() && d.verdict != Verdict::Absent {
                first = Some(tick);
            }
            pose = (
                pose.0 + 0.028 * pose.2.cos(),
                pose.1 + 0.028 * pose.2.sin(),
                pose.2 + rate,
            );
        }
        // 0.004 rad a scan: 0.016 rad over the first five, no line before the
        // points span 0.3 m (11 steps of 0.028 m); 0.002: 0.008 rad, the
        // fifth scan.
        let first = first.unwrap();
        if first_line_at == 5 {
            assert_eq!(first, 5, "rate {rate}");
        } else {
            assert!(first >= first_line_at, "rate {rate}: {first}");
        }
    }
}

/// The first-line heading is the robot's once it goes straight, and the line
/// stays put while the robot turns afterwards; a robot standing still after
/// its accumulation was full gets no line from the points of one spot.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# The first-line heading MUST be the odometry heading of the newest kept
//# selection at the first tick at which the robot's heading changed by at
//# most 0.01 rad over its last `min_points` kept selections.
#[test]
fn the_first_line_keeps_the_heading_of_the_straight_entry() {
    let params = FurrowParams::table2();
    let l = lidar();
    let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    // Straight for five scans at 0.1 m left of the centre, then turning
    // right by 0.01 rad a scan: the line, fixed in odometry, is the rows'
    // (θ̃ the robot's heading, y its offset), not turned with the robot.
    let mut pose = (0.0_f64, 0.1_f64, 0.0_f64);
    for tick in 1..=10 {
        let ranges = ridge_scan(&params, &l, pose, &rows(0.3));
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        let d = det.detect(&scan(&ranges, &l), &odom).unwrap();
        if tick >= 5 {
            let e = d.error.unwrap();
            // y within the inner faces' share of a heading (the 0.08 m
            // half width, as in the two-row test); θ̃ the robot's heading,
            // 0.05 rad at the end: a line turned with the robot would give 0.
            assert!((e.y.get() - pose.1).abs() < 0.03, "{tick}: {}", e.y.get());
            assert!(
                (e.angular_deviation.get() - pose.2).abs() < 0.005,
                "{tick}: {e:?}"
            );
        }
        let turn = if tick >= 5 { -0.01 } else { 0.0 };
        pose = (
            pose.0 + 0.028 * pose.2.cos(),
            pose.1 + 0.028 * pose.2.sin(),
            pose.2 + turn,
        );
    }
    // Standing still once the 25 selections were held: the points gather on
    // one spot, and no line comes of them.
    let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    let mut pose = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut last = None;
    for tick in 0..80 {
        let ranges = ridge_scan(&params, &l, pose, &rows(0.3));
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        last = Some(det.detect(&scan(&ranges, &l), &odom).unwrap().verdict);
        if tick < 30 {
            pose.0 += 0.028;
        }
    }
    assert_eq!(last, Some(Verdict::Absent));
}

/// A robot slower than its accumulation (0.028 m a scan: 25 scans span
/// 0.7 m, less than E = 2 m) driving straight at 0.05 rad to the rows: the
/// line does not jump when the accumulation fills (the first line carries
/// on, its prior fading over the next 25 scans), and after twice its
/// capacity it is FUR-LINE's, the rows' own direction rather than the
/// robot's heading. Ending at the fill or at twice it, θ̃ jumped 0.018 rad.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# The first line MUST be given from the tick the first-line heading is set
//# until the first tick, after the accumulation has held its capacity, at which
//# the kept selections' reference points span E along x, or at which twice its
//# capacity of selections have been kept since it was last empty; after that,
//# the line MUST be FUR-LINE's.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# Once the accumulation has held its capacity c, Λ MUST be multiplied by
//# (1 − k/c)², k the number of selections kept beyond c since it was last empty.
#[test]
fn the_first_line_ends_without_a_jump_when_the_accumulation_fills() {
    let params = FurrowParams::table2();
    let l = lidar();
    let psi = 0.05_f64;
    let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
    let mut pose = (0.0_f64, 0.1_f64, psi);
    let mut errors = Vec::new();
    for _ in 0..60 {
        let ranges = ridge_scan(&params, &l, pose, &rows(0.3));
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        let d = det.detect(&scan(&ranges, &l), &odom).unwrap();
        errors.push(d.error.map(|e| (e.y.get(), e.angular_deviation.get())));
        pose = (pose.0 + 0.028 * psi.cos(), pose.1 + 0.028 * psi.sin(), psi);
    }
    // From the fifth scan on, one scan turns the line by at most 0.008 rad
    // (the ridges' faces move the fit by up to 0.005 rad a scan).
    assert!(errors[3].is_none());
    for k in 5..60 {
        let (a, b) = (errors[k - 1].unwrap(), errors[k].unwrap());
        assert!(
            (b.1 - a.1).abs() < 0.008,
            "θ̃ at scan {}: {a:?} -> {b:?}",
            k + 1
        );
    }
    // After 50 selections, the plain fit: the robot's heading to the rows.
    let last = errors[59].unwrap();
    assert!((last.1 - psi).abs() < 0.01, "{last:?}");
}

/// A robot driving straight at 0.08 rad across the rows when it first sees
/// them (path tracking still swinging back to the path): along its own
/// heading the first line lies beside the rows at O; along the expected
/// heading, the rows' own, it is on them.
//= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
//= type=test
//# When an expected heading was given before the scan, the first-line
//# heading MUST be that heading instead.
#[test]
fn the_first_line_takes_the_expected_heading() {
    let params = FurrowParams::table2();
    let l = lidar();
    let psi = 0.08_f64;
    for expected in [None, Some(0.0)] {
        let mut det = Detector::new(FurrowConfig::new(&params).unwrap()).unwrap();
        det.expect_heading(expected.map(rad));
        let mut pose = (0.0_f64, 0.05_f64, psi);
        for _ in 1..5 {
            let ranges = ridge_scan(&params, &l, pose, &rows(0.3));
            let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
            det.detect(&scan(&ranges, &l), &odom).unwrap();
            pose = (pose.0 + 0.028 * psi.cos(), pose.1 + 0.028 * psi.sin(), psi);
        }
        let ranges = ridge_scan(&params, &l, pose, &rows(0.3));
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        let e = det
            .detect(&scan(&ranges, &l), &odom)
            .unwrap()
            .error
            .unwrap();
        let (y, th) = (e.y.get(), e.angular_deviation.get());
        if expected.is_some() {
            // On the rows within the ridges' faces seen at 0.08 rad (0.05 m),
            // θ̃ the robot's heading to them.
            assert!((y - pose.1).abs() < 0.06, "{y} vs {}", pose.1);
            assert!((th - psi).abs() < 0.005, "{th}");
        } else {
            // Along the robot: θ̃ 0 and y off by psi times the distance
            // from O to the first points.
            assert!(th.abs() < 0.005, "{th}");
            assert!((y - pose.1).abs() > 0.15, "{y} vs {}", pose.1);
        }
    }
}
