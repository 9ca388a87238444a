//! The vine detector (Iberraken 2022, section 2.1): the correlation of
//! eq. 1 against its direct formula, the RANSAC ground profile, eq. 2, and
//! whole detections on exact synthetic vineyard scans (`vine_scans`), good
//! and bad (`spec/iberraken2022.md`, VINE-*).
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

mod vine_scans;

use fieldguide::geometry::fit::fit_line;
use fieldguide::perception::furrow::lines::RowLine;
use fieldguide::perception::furrow::scan::ScanPoint;
use fieldguide::perception::vine::aggregation::{lateral_deviation, SetPoint, SetPoints};
use fieldguide::perception::vine::correlation::{correlate, VineModel};
use fieldguide::perception::vine::ground::{fit_ground, Ground, GroundParams};
use fieldguide::perception::vine::{
    row_deviation, vine_verdict, VineConfig, VineDetection, VineDetector, VineLine, VineParams,
};
use fieldguide::perception::{Better, HeldLine, QualityThresholds, Verdict};
use fieldguide::{Meters, Odom, Point2, Pose2, Radians, Robot, World as WorldFrame};
use proptest::prelude::*;
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro128PlusPlus;
use vine_scans::{vineyard, Lidar, SplitMix64, World};

type Detector = VineDetector<512, 64>;

// ---------------------------------------------------------------- eq. 1

/// Eq. 1 with Pearson's normalisation, by its definition, in plain f64.
fn pearson_direct(signal: &[f64], model: &[f64], k: usize) -> f64 {
    let z = &signal[k..k + model.len()];
    let n = model.len() as f64;
    let zm = z.iter().sum::<f64>() / n;
    let mm = model.iter().sum::<f64>() / n;
    let num: f64 = z.iter().zip(model).map(|(a, b)| (a - zm) * (b - mm)).sum();
    let sz = z.iter().map(|a| (a - zm) * (a - zm)).sum::<f64>().sqrt();
    let sm = model
        .iter()
        .map(|b| (b - mm) * (b - mm))
        .sum::<f64>()
        .sqrt();
    if sz == 0.0 {
        0.0
    } else {
        num / (sz * sm)
    }
}

fn model_values(m: &VineModel) -> Vec<f64> {
    (0..m.length()).map(|i| m.value(i)).collect()
}

/// Heights on a grid of 2⁻¹⁰ m, which the correlation reads exactly.
fn grid_signal() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(
        prop_oneof![2 => Just(0.0), 3 => (0_i32..2048).prop_map(|q| f64::from(q) / 1024.0)],
        0..160,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    //= spec/iberraken2022.md#vine-correlation-pearson-correlation-by-running-sums
    //= type=test
    //# The score at offset k MUST be
    //# r(k) = Σ_j (z_{k+j} − z̄_k)(m_j − m̄) / (sqrt(Σ_j (z_{k+j} − z̄_k)²) ·
    //# sqrt(Σ_j (m_j − m̄)²)), the sums over the model's rays j, z̄_k the mean of
    //# the window and m̄ the model's, for every offset k where the model lies in
    //# the window of rays; a window of equal samples MUST score 0.
    //= spec/iberraken2022.md#vine-correlation-pearson-correlation-by-running-sums
    //= type=test
    //# The scores MUST be computed with running sums, in O(N) operations
    //# whatever the model's length.
    #[test]
    fn running_sums_give_the_direct_formula(
        signal in grid_signal(), width in 1_usize..14, margin in 1_usize..14, height in 0.1..3.0_f64,
    ) {
        let model = VineModel::new(width, margin, Meters::new(height).unwrap()).unwrap();
        let mut out = vec![f64::NAN; signal.len() + 3];
        correlate(&signal, &model, &mut out).unwrap();
        let m = model_values(&model);
        for (k, &r) in out.iter().enumerate().take(signal.len()) {
            let expected = if k + m.len() <= signal.len() { pearson_direct(&signal, &m, k) } else { 0.0 };
            prop_assert!((r - expected).abs() < 1e-12, "k {k}: {r} vs {expected}");
        }
        // Beyond the signal, nothing is written.
        prop_assert!(out[signal.len()..].iter().all(|v| v.is_nan()));
    }

    //= spec/iberraken2022.md#vine-model-square-vine-model
    //= type=test
    //# The model MUST be m_i = h for the w rays margin ≤ i < margin + w and
    //# m_i = 0 (the ground) for the margin rays on each side.
    #[test]
    fn a_perfect_match_scores_one_whatever_the_scale(
        width in 1_usize..14, margin in 1_usize..14, lead in 0_usize..20, tail in 0_usize..20,
        scale in 1_i32..4096, base in 0_i32..512,
    ) {
        let model = VineModel::new(width, margin, Meters::new(1.0).unwrap()).unwrap();
        let m = model_values(&model);
        prop_assert_eq!(m.iter().filter(|&&v| v == 1.0).count(), width);
        prop_assert!(m[..margin].iter().chain(&m[margin + width..]).all(|&v| v == 0.0));
        // The model, scaled and lifted, inside ground of the same base.
        let b = f64::from(base) / 1024.0;
        let a = f64::from(scale) / 1024.0;
        let mut signal = vec![b; lead];
        signal.extend(m.iter().map(|v| b + a * v));
        signal.extend(vec![b; tail]);
        let mut out = vec![0.0; signal.len()];
        correlate(&signal, &model, &mut out).unwrap();
        prop_assert_eq!(out[lead], 1.0, "a perfect match scores exactly 1");
        prop_assert!(out.iter().all(|r| (-1.0..=1.0).contains(r)));
        // A flat signal scores 0 everywhere.
        let flat = vec![b; signal.len()];
        correlate(&flat, &model, &mut out).unwrap();
        prop_assert!(out.iter().all(|&r| r == 0.0));
    }
}

//= spec/iberraken2022.md#vine-model-square-vine-model
//= type=test
//# A model whose width or margin is zero, whose height is not positive, or
//# whose length exceeds 4096 rays MUST be refused with an error naming
//# VINE-MODEL.
#[test]
fn bad_models_and_outputs_are_refused() {
    let h = Meters::new(1.0).unwrap();
    for (w, m, height) in [
        (0, 3, 1.0),
        (3, 0, 1.0),
        (3, 3, 0.0),
        (3, 3, -1.0),
        (4000, 49, 1.0),
    ] {
        let e = VineModel::new(w, m, Meters::new(height).unwrap()).unwrap_err();
        assert_eq!(e.requirement, "VINE-MODEL");
    }
    assert!(VineModel::new(4000, 48, h).is_ok());
    let model = VineModel::new(10, 10, h).unwrap();
    assert_eq!(
        correlate(&[0.0; 40], &model, &mut [0.0; 39])
            .unwrap_err()
            .requirement,
        "VINE-CORRELATION"
    );
    // Non-finite samples count as 0.
    let mut signal = vec![0.0; 30];
    for v in &mut signal[10..20] {
        *v = 1.0;
    }
    signal[0] = f64::NAN;
    signal[29] = f64::INFINITY;
    let mut out = [0.0; 30];
    correlate(&signal, &model, &mut out).unwrap();
    assert_eq!(out[0], 1.0);
}

// ---------------------------------------------------------------- ground

fn point(y: f64, z: f64) -> Option<ScanPoint> {
    Some(ScanPoint {
        ground: Point2::new(3.0, y).unwrap(),
        height: Meters::new(z).unwrap(),
    })
}

fn ground_params() -> GroundParams {
    GroundParams::new(32, 0.05, 10, 0.4).unwrap()
}

//= spec/iberraken2022.md#vine-ground-ground-compensation-by-ransac
//= type=test
//# The ground profile MUST be the line z = a y + b, |a| ≤ a_max, drawn by
//# RANSAC from pairs of points with the detector's seeded generator over a
//# bounded number of iterations, that has the most points within the
//# tolerance, refined by least squares over those points.
#[test]
fn ransac_recovers_a_sloped_profile_under_a_vine_and_repeats_with_its_seed() {
    // Ground z = 0.3 y − 0.1 on 60 rays, 12 rays of canopy 1 m above it.
    let rays: Vec<_> = (0..60)
        .map(|i| {
            let y = -1.5 + 0.05 * f64::from(i);
            let lift = if (20..32).contains(&i) { 1.0 } else { 0.0 };
            point(y, 0.3 * y - 0.1 + lift)
        })
        .collect();
    let mut rng = Xoshiro128PlusPlus::seed_from_u64(7);
    let Ground::Profile(g) = fit_ground(&rays, &ground_params(), &mut rng) else {
        panic!("a profile");
    };
    assert!(
        (g.slope - 0.3).abs() < 1e-12 && (g.offset + 0.1).abs() < 1e-12,
        "{g:?}"
    );
    assert_eq!(g.inliers, 48);
    assert!((g.height_above(&rays[25].unwrap()) - 1.0).abs() < 1e-12);
    // The same seed gives the same profile; the generator is explicit.
    let again = fit_ground(
        &rays,
        &ground_params(),
        &mut Xoshiro128PlusPlus::seed_from_u64(7),
    );
    assert_eq!(again, Ground::Profile(g));
    // Noisy ground: the refined line is the least-squares line of the inliers.
    let mut noise = SplitMix64(3);
    let noisy: Vec<_> = (0..60)
        .map(|i| {
            let y = -1.5 + 0.05 * f64::from(i);
            point(y, 0.1 * y + 0.02 * (noise.unit() - 0.5))
        })
        .collect();
    let Ground::Profile(g) = fit_ground(&noisy, &ground_params(), &mut rng) else {
        panic!("a profile");
    };
    let profile: Vec<Point2<WorldFrame>> = noisy
        .iter()
        .flatten()
        .map(|p| Point2::new(p.ground.y(), p.height.get()).unwrap())
        .collect();
    let ls = fit_line(&profile).unwrap();
    assert_eq!(g.inliers, 60);
    assert!((g.slope - ls.a).abs() < 1e-12 && (g.offset - ls.b).abs() < 1e-12);
}

//= spec/iberraken2022.md#vine-ground-ground-compensation-by-ransac
//= type=test
//# When no line within the slope limit has at least the configured number
//# of inliers, the scan MUST yield no candidate.
#[test]
fn too_few_inliers_or_too_steep_is_no_profile() {
    let mut rng = Xoshiro128PlusPlus::seed_from_u64(1);
    // Five points only.
    let few: Vec<_> = (0..5).map(|i| point(f64::from(i) * 0.1, 0.0)).collect();
    assert_eq!(
        fit_ground(&few, &ground_params(), &mut rng),
        Ground::TooFewInliers
    );
    // Dropped rays only, and nothing at all.
    assert_eq!(
        fit_ground(&[None; 50], &ground_params(), &mut rng),
        Ground::TooFewInliers
    );
    assert_eq!(
        fit_ground(&[], &ground_params(), &mut rng),
        Ground::TooFewInliers
    );
    // A slope of 0.8 beyond the limit 0.4.
    let steep: Vec<_> = (0..60)
        .map(|i| point(f64::from(i) * 0.05, 0.8 * f64::from(i) * 0.05))
        .collect();
    assert_eq!(
        fit_ground(&steep, &ground_params(), &mut rng),
        Ground::TooFewInliers
    );
    for (it, tol, n, slope) in [
        (0, 0.05, 10, 0.4),
        (2000, 0.05, 10, 0.4),
        (32, 0.0, 10, 0.4),
        (32, 0.05, 1, 0.4),
        (32, 0.05, 10, -0.1),
        (32, f64::NAN, 10, 0.4),
    ] {
        assert_eq!(
            GroundParams::new(it, tol, n, slope)
                .unwrap_err()
                .requirement,
            "VINE-GROUND"
        );
    }
}

// ---------------------------------------------------------------- eq. 2

//= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
//= type=test
//# The lateral deviation of a candidate r from the newest set-point p MUST be
//# l = |−sin θ (x_r − x_p) + cos θ (y_r − y_p)|, both points in the odometry
//# frame and θ the robot's odometry yaw.
#[test]
fn eq_2_by_hand() {
    let p = Point2::<Odom>::new(1.0, 2.0).unwrap();
    let r = Point2::<Odom>::new(2.0, 2.5).unwrap();
    // θ = 0: the difference in y.
    assert!((lateral_deviation(r, p, Radians::ZERO).unwrap().get() - 0.5).abs() < 1e-15);
    // θ = π/2: |−(x_r − x_p)| = 1.
    let l = lateral_deviation(r, p, Radians::new(core::f64::consts::FRAC_PI_2).unwrap()).unwrap();
    assert!((l.get() - 1.0).abs() < 1e-15);
    // θ = π/6: |−0.5 · 1 + 0.866 · 0.5|.
    let l = lateral_deviation(r, p, Radians::new(core::f64::consts::FRAC_PI_6).unwrap()).unwrap();
    assert!((l.get() - (0.5 - 0.75_f64.sqrt() * 0.5).abs()).abs() < 1e-15);
}

//= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
//= type=test
//# A set-point farther than the keep distance from the robot MUST be
//# dropped.
//= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
//= type=test
//# When the store holds its capacity, adding a set-point MUST drop the
//# oldest.
#[test]
fn set_points_are_bounded_in_number_and_distance() {
    let mut s = SetPoints::<3>::new(Meters::new(2.0).unwrap()).unwrap();
    let at = |x: f64| SetPoint {
        point: Point2::new(x, 0.0).unwrap(),
        score: x,
    };
    assert_eq!(s.push(at(0.0)), None);
    s.push(at(1.0));
    s.push(at(2.0));
    assert_eq!(s.push(at(3.0)), Some(at(0.0)));
    assert_eq!(s.len(), 3);
    assert_eq!(s.mean_score(), Some(2.0));
    // The robot at x = 4.5: points 1 and 2 are beyond 2 m.
    assert_eq!(s.forget_far(&Pose2::new(4.5, 0.0, 0.0).unwrap()), 2);
    assert_eq!(s.newest(), Some(at(3.0)));
    let seen: Vec<_> = s
        .in_robot_frame(&Pose2::new(4.5, 0.0, core::f64::consts::PI).unwrap())
        .collect();
    assert!((seen[0].x() - 1.5).abs() < 1e-12 && seen[0].y().abs() < 1e-12);
    assert_eq!(
        SetPoints::<3>::new(Meters::ZERO).unwrap_err().requirement,
        "VINE-AGGREGATE"
    );
}

// ---------------------------------------------------------------- whole detections

/// Runs the detector along the row from x = `x0`, at lateral `y` and
/// heading `heading` (world), one scan every 0.1 m, `scans` scans; the
/// odometry is the world pose moved by `odom_of`.
fn drive(
    params: &VineParams,
    world: &World,
    (x0, y, heading): (f64, f64, f64),
    scans: usize,
    odom_of: impl Fn(f64, f64, f64) -> (f64, f64, f64),
) -> Vec<VineDetection> {
    let lidar = Lidar::table1();
    let mut d = Detector::new(VineConfig::new(params).unwrap()).unwrap();
    (0..scans)
        .map(|k| {
            let (s, c) = heading.sin_cos();
            let t = 0.1 * k as f64;
            let pose = (x0 + c * t, y + s * t, heading);
            let ranges = lidar.cast(world, pose);
            let (ox, oy, oh) = odom_of(pose.0, pose.1, pose.2);
            d.detect(&lidar.scan(&ranges), &Pose2::new(ox, oy, oh).unwrap())
                .unwrap()
        })
        .collect()
}

fn same(x: f64, y: f64, h: f64) -> (f64, f64, f64) {
    (x, y, h)
}

/// Summer and winter canopies that the test LiDAR (1° rays) sees about 10
/// and 5 rays wide, as Table 1's models.
const SUMMER_WIDTH: f64 = 0.25;
const WINTER_WIDTH: f64 = 0.12;

//= spec/iberraken2022.md#vine-line-row-line-and-deviations
//= type=test
//# The row line MUST be the least-squares line y = a x + b through the
//# set-points in the current robot frame, fitted once there are at least
//# the configured number of them spanning at least the configured extent
//# along x.
//= spec/iberraken2022.md#vine-candidates-maxima-above-the-threshold
//= type=test
//# Every local maximum of r(k) above the threshold (Table 1: 0.25) MUST
//# be a candidate.
//= spec/iberraken2022.md#vine-candidates-maxima-above-the-threshold
//= type=test
//# A candidate MUST be located at the mean ground position of the rays whose
//# signal is at least 0.9 times the highest of the contiguous run of positive
//# signal around the highest ray under the model's square.
//= spec/iberraken2022.md#vine-scan-scan-to-points-in-the-field-of-view
//= type=test
//# Each ray whose in-plane angle lies in [−30°, 30°] (the configured half
//# field of view) MUST be converted into a robot-frame point through the
//# mount pose as FUR-SCAN converts it; other rays MUST NOT be used.
#[test]
fn summer_and_winter_rows_are_followed_on_sloped_bumpy_ground() {
    let seasons = [
        ("summer", VineParams::summer(), SUMMER_WIDTH),
        ("winter", VineParams::winter(), WINTER_WIDTH),
    ];
    for (season, params, width) in seasons {
        let (mut worst_y, mut worst_theta, mut valid) = (0.0_f64, 0.0_f64, 0);
        for (along, cross) in [(0.0, 0.0), (0.05, 0.2), (-0.08, -0.25)] {
            let mut ground = World::ground(along, cross);
            SplitMix64(11).bumps(&mut ground, 80, 0.2, 0.08, (0.0, 12.0));
            let world = vineyard(ground, 2.2, width, &[]);
            for (y, heading) in [(0.0, 0.0), (-0.3, 0.05), (0.4, -0.08)] {
                let runs = drive(&params, &world, (0.0, y, heading), 40, same);
                let case = format!("{season} {along} {cross} {y} {heading}");
                assert!(
                    runs.iter().filter(|d| d.joined.is_some()).count() >= 30,
                    "{case}"
                );
                // Every scan from the tenth on holds the row, within 3 cm and 0.02 rad
                // of the truth: the robot at 0.1 k m along its heading.
                for (k, d) in runs.iter().enumerate().skip(10) {
                    assert!(d.verdict.estimate_is_valid(), "{case} scan {k}: {d:?}");
                    let e = d.error.unwrap();
                    let (ty, th) = (y + 0.1 * k as f64 * heading.sin(), heading);
                    worst_y = worst_y.max((e.y.get() - ty).abs());
                    worst_theta = worst_theta.max((e.angular_deviation.get() - th).abs());
                    valid += 1;
                }
                // The ground profile seen is the cross slope along the robot's y.
                let last = runs.last().unwrap();
                assert!(
                    matches!(last.ground, Ground::Profile(g) if (g.slope - cross * heading.cos()).abs() < 0.05),
                    "{case}: {:?}",
                    last.ground
                );
            }
        }
        println!(
            "{season}: {valid} detections, worst lateral error {:.1} mm, worst angular error {:.1} mrad",
            1e3 * worst_y,
            1e3 * worst_theta
        );
        assert!(
            worst_y < 0.03 && worst_theta < 0.02,
            "{season}: {worst_y} m, {worst_theta} rad"
        );
    }
}

//= spec/iberraken2022.md#vine-line-row-line-and-deviations
//= type=test
//# The deviations MUST be y = −(a X − Y + b) / sqrt(a² + 1) and
//# θ̃ = θ − arctan(a) for the line y = a x + b and the robot at (X, Y) with
//# yaw θ in the frame of the line; with the line in the robot frame,
//# y = −b / sqrt(a² + 1) and θ̃ = −arctan(a).
#[test]
fn eqs_3_and_4_in_the_odometry_frame_agree_with_the_robot_frame() {
    // The set-points the detector kept, fitted in the odometry frame by the
    // test, give by eqs. 3-4 the detector's deviations.
    let world = vineyard(World::ground(0.0, 0.1), 2.2, SUMMER_WIDTH, &[]);
    let lidar = Lidar::table1();
    let params = VineParams::summer();
    let mut d = Detector::new(VineConfig::new(&params).unwrap()).unwrap();
    let mut last = None;
    for k in 0..30 {
        let pose = (0.1 * f64::from(k), 0.25, 0.06);
        let ranges = lidar.cast(&world, pose);
        let odom = Pose2::<Odom>::new(pose.0, pose.1, pose.2).unwrap();
        last = Some((d.detect(&lidar.scan(&ranges), &odom).unwrap(), odom));
    }
    let (det, odom) = last.unwrap();
    let pts: Vec<Point2<Odom>> = d.set_points().iter().map(|p| p.point).collect();
    let f = fit_line(&pts).unwrap();
    let (x, y, th) = (odom.position.x(), odom.position.y(), odom.heading.get());
    let eq3 = (f.a * x - y + f.b) / (f.a * f.a + 1.0).sqrt();
    let eq4 = th - f.a.atan();
    let e = det.error.unwrap();
    assert!((e.y.get() + eq3).abs() < 1e-9, "{} vs {}", e.y.get(), -eq3);
    assert!((e.angular_deviation.get() - eq4).abs() < 1e-9);
    // And by hand in the robot frame: y = 2x + 1 gives y = −1/√5, θ̃ = −atan 2.
    let e = row_deviation(&RowLine::new(2.0, Meters::new(1.0).unwrap()).unwrap()).unwrap();
    assert!((e.y.get() + 1.0 / 5.0_f64.sqrt()).abs() < 1e-15);
    assert!((e.angular_deviation.get() + 2.0_f64.atan()).abs() < 1e-15);
    // The held line moved by odometry: 1 m ahead along y = 0 from y = 0.5.
    let line = VineLine(RowLine::new(0.0, Meters::new(-0.5).unwrap()).unwrap());
    let moved = line
        .error_at(&Pose2::<Robot>::new(1.0, 0.0, 0.1).unwrap())
        .unwrap();
    assert!(
        (moved.y.get() - 0.5).abs() < 1e-12 && (moved.angular_deviation.get() - 0.1).abs() < 1e-12
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// The same drive with its odometry expressed in any frame rotated and
    /// moved from the world's: the same deviations (rigid motion).
    #[test]
    fn the_deviations_do_not_depend_on_the_odometry_frame(
        angle in -3.1..3.1_f64, tx in -100.0..100.0_f64, ty in -100.0..100.0_f64,
        y0 in -0.3..0.3_f64, heading in -0.05..0.05_f64,
    ) {
        let world = vineyard(World::ground(0.02, -0.15), 2.2, SUMMER_WIDTH, &[]);
        let params = VineParams::summer();
        let (s, c) = angle.sin_cos();
        let moved = |x: f64, y: f64, h: f64| (tx + c * x - s * y, ty + s * x + c * y, h + angle);
        let a = drive(&params, &world, (0.0, y0, heading), 30, same);
        let b = drive(&params, &world, (0.0, y0, heading), 30, moved);
        for (a, b) in a.iter().zip(&b) {
            prop_assert_eq!(a.verdict, b.verdict);
            prop_assert_eq!(a.candidates, b.candidates);
            if let (Some(ea), Some(eb)) = (a.error, b.error) {
                prop_assert!((ea.y.get() - eb.y.get()).abs() < 1e-9);
                prop_assert!((ea.angular_deviation.get() - eb.angular_deviation.get()).abs() < 1e-9);
            }
        }
        // Not vacuous: from a start within 0.3 m and 0.05 rad of the row the
        // row is found (0.4 m and 0.08 rad can leave it out of view).
        prop_assert!(a.iter().any(|d| d.verdict.estimate_is_valid()));
    }
}

//= spec/iberraken2022.md#vine-signal-levelled-heights-with-a-noise-floor
//= type=test
//# The signal of a ray MUST be its height above the ground profile when
//# that height is above the floor, and 0 otherwise, for a dropped ray and
//# for every ray of a scan without a ground profile.
#[test]
fn ground_alone_levelled_gives_no_candidate() {
    let lidar = Lidar::table1();
    let mut bumps = World::ground(0.1, 0.3);
    SplitMix64(5).bumps(&mut bumps, 60, 0.2, 0.1, (0.0, 6.0));
    for world in [
        World::ground(0.0, 0.0),
        World::ground(0.1, 0.3),
        World::ground(-0.1, -0.35),
        bumps,
    ] {
        let mut d = Detector::new(VineConfig::new(&VineParams::summer()).unwrap()).unwrap();
        for k in 0..20 {
            let pose = (0.1 * f64::from(k), 0.0, 0.0);
            let ranges = lidar.cast(&world, pose);
            let det = d
                .detect(&lidar.scan(&ranges), &Pose2::new(pose.0, 0.0, 0.0).unwrap())
                .unwrap();
            assert_eq!(det.candidates, 0, "{world:?}");
            assert_eq!(det.verdict, Verdict::Absent);
            assert!(matches!(det.ground, Ground::Profile(_)));
        }
    }
}

#[test]
fn bad_scenes_give_absent() {
    let lidar = Lidar::table1();
    let params = VineParams::summer();
    // A slope steeper than the RANSAC's limit (0.4): no profile, no candidate.
    let steep = vineyard(World::ground(0.0, 0.7), 2.2, SUMMER_WIDTH, &[]);
    // All foliage: a hedge wider than the field of view.
    let mut hedge = World::ground(0.0, 0.0);
    hedge.stand((-5.0, 60.0), (-4.0, 4.0), 1.0); // flat ground: one box
    for (name, world) in [("steep", steep), ("foliage", hedge)] {
        let mut d = Detector::new(VineConfig::new(&params).unwrap()).unwrap();
        for k in 0..20 {
            let pose = (0.1 * f64::from(k), 0.0, 0.0);
            let ranges = lidar.cast(&world, pose);
            let det = d
                .detect(&lidar.scan(&ranges), &Pose2::new(pose.0, 0.0, 0.0).unwrap())
                .unwrap();
            assert_eq!(det.verdict, Verdict::Absent, "{name}");
            assert_eq!(det.candidates, 0, "{name}");
            if name == "steep" {
                assert_eq!(det.ground, Ground::TooFewInliers);
            }
        }
    }
    // Too few inliers: most rays give no return.
    let world = vineyard(World::ground(0.0, 0.0), 2.2, SUMMER_WIDTH, &[]);
    let mut ranges = lidar.cast(&world, (0.0, 0.0, 0.0));
    for (k, r) in ranges.iter_mut().enumerate() {
        if k % 8 != 0 {
            *r = f64::NAN;
        }
    }
    let mut d = Detector::new(VineConfig::new(&params).unwrap()).unwrap();
    let det = d
        .detect(&lidar.scan(&ranges), &Pose2::new(0.0, 0.0, 0.0).unwrap())
        .unwrap();
    assert_eq!(det.ground, Ground::TooFewInliers);
    assert_eq!(det.verdict, Verdict::Absent);
}

//= spec/iberraken2022.md#vine-verdict-verdict-from-the-set-points
//= type=test
//# The verdict MUST be Absent when there is no row line, and otherwise the
//# mean score of the kept set-points graded by the entry and exit thresholds
//# as SW-CLASSIFY grades it.
#[test]
fn gaps_of_missing_vines_hold_then_lose_the_row() {
    // Vines missing from x = 4 to 14 m: a long gap, beyond the 5 m kept.
    // No posts: they stand in the gap and mark the row.
    let mut world = World::ground(0.0, 0.1);
    for y in [-2.2, 0.0, 2.2] {
        world.vine_row(y, SUMMER_WIDTH, 1.0, (-5.0, 60.0), &[(4.0, 14.0)]);
    }
    let runs = drive(&VineParams::summer(), &world, (-2.0, 0.1, 0.0), 200, same);
    // x of the robot at scan k: −2 + 0.1 k; the LiDAR looks ~2.4 m ahead of R.
    let at = |x: f64| &runs[((x + 2.0) / 0.1).round() as usize];
    assert!(at(1.0).verdict.estimate_is_valid());
    // Entering the gap, the kept set-points still give the row.
    assert!(at(2.5).verdict.estimate_is_valid(), "{:?}", at(2.5));
    // Deep in the gap, everything kept is behind by more than 5 m: Absent.
    assert_eq!(at(11.0).verdict, Verdict::Absent);
    assert_eq!(at(11.0).error, None);
    // After the gap, the row is found again.
    assert!(at(17.0).verdict.estimate_is_valid(), "{:?}", at(17.0));
    let e = at(17.0).error.unwrap();
    assert!((e.y.get() - 0.1).abs() < 0.03);
    // The verdict is the mean score graded.
    let t = QualityThresholds::new(0.5, 0.35, Better::Higher).unwrap();
    assert_eq!(vine_verdict(&t, true, Some(0.9)), Verdict::Enter);
    assert_eq!(vine_verdict(&t, true, Some(0.4)), Verdict::Hold);
    assert_eq!(vine_verdict(&t, true, Some(0.3)), Verdict::Exit);
    assert_eq!(vine_verdict(&t, false, Some(0.9)), Verdict::Absent);
    assert_eq!(vine_verdict(&t, true, None), Verdict::Absent);
}

//= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
//= type=test
//# The candidate of least deviation l from the newest set-point MUST join
//# the set-points, stored in the odometry frame, when l is at most the
//# configured bound; with no set-point, the candidate of least |y| in the
//# robot frame MUST join when |y| is at most the first-point bound.
#[test]
fn the_row_straddled_is_kept_next_to_others() {
    // Rows 1.6 m apart, the robot 0.6 m right of the middle one: the first
    // set-point is the closest row, and the others never join.
    let world = vineyard(World::ground(0.0, 0.0), 1.6, SUMMER_WIDTH, &[]);
    let runs = drive(&VineParams::summer(), &world, (0.0, -0.6, 0.0), 40, same);
    let first = runs.iter().find_map(|d| d.joined).unwrap();
    assert!((first.point.y() - 0.6).abs() < 0.05, "{first:?}");
    // Seen from 0.6 m aside, the canopy's face near its top joins the top's
    // rays: a bias of about a centimetre toward the robot.
    let e = runs.last().unwrap().error.unwrap();
    assert!((e.y.get() + 0.6).abs() < 0.03, "{}", e.y.get());
    // The first-point bound: a row 1.5 m off is not taken.
    let mut params = VineParams::summer();
    params.first_lateral = Meters::new(0.3).unwrap();
    let runs = drive(&params, &world, (0.0, -0.6, 0.0), 10, same);
    assert!(runs.iter().all(|d| d.joined.is_none()));
}

//= spec/iberraken2022.md#vine-config-configuration-validated-once
//= type=test
//# A vine configuration MUST be validated once, at construction, and a
//# configuration that breaks a precondition of VINE-SCAN, VINE-MODEL,
//# VINE-SIGNAL, VINE-CANDIDATES, VINE-GROUND, VINE-AGGREGATE, VINE-LINE or
//# SW-THRESHOLDS MUST be refused with an error naming that requirement.
#[test]
fn bad_configurations_name_their_requirement() {
    let base = VineParams::summer();
    type Edit = fn(&mut VineParams);
    let cases: Vec<(Edit, &str)> = vec![
        (|p| p.mount_height = Meters::ZERO, "FUR-SCAN"),
        (|p| p.mount_pitch = Radians::ZERO, "FUR-SCAN"),
        (|p| p.half_fov = Radians::new(1.6).unwrap(), "FUR-SCAN"),
        (|p| p.model_width = 0, "VINE-MODEL"),
        (|p| p.model_margin = 0, "VINE-MODEL"),
        (
            |p| p.height_floor = Meters::new(1.0).unwrap(),
            "VINE-SIGNAL",
        ),
        (
            |p| p.height_floor = Meters::new(-0.1).unwrap(),
            "VINE-SIGNAL",
        ),
        (|p| p.threshold = 1.0, "VINE-CANDIDATES"),
        (|p| p.threshold = f64::NAN, "VINE-CANDIDATES"),
        (|p| p.ransac_iterations = 0, "VINE-GROUND"),
        (|p| p.ransac_min_inliers = 1, "VINE-GROUND"),
        (|p| p.max_cross_slope = -1.0, "VINE-GROUND"),
        (|p| p.max_deviation = Meters::ZERO, "VINE-AGGREGATE"),
        (|p| p.first_lateral = Meters::ZERO, "VINE-AGGREGATE"),
        (|p| p.keep_distance = Meters::ZERO, "VINE-AGGREGATE"),
        (|p| p.min_points = 1, "VINE-LINE"),
        (|p| p.min_extent = Meters::new(-1.0).unwrap(), "VINE-LINE"),
        (|p| p.enter = 0.3, "SW-THRESHOLDS"),
    ];
    for (edit, requirement) in cases {
        let mut p = base;
        edit(&mut p);
        assert_eq!(
            VineConfig::new(&p).unwrap_err().requirement,
            requirement,
            "{p:?}"
        );
    }
    let mut p = base;
    p.min_points = 65;
    assert_eq!(
        Detector::new(VineConfig::new(&p).unwrap())
            .unwrap_err()
            .requirement,
        "VINE-LINE"
    );
    let c = VineConfig::new(&VineParams::winter()).unwrap();
    assert_eq!(c.model().width(), 5);
    assert_eq!(c.params().threshold, 0.25);
    assert_eq!(c.ground().iterations(), 32);
    assert_eq!(c.thresholds().enter(), 0.5);
}

#[test]
fn a_mirrored_vineyard_gives_mirrored_deviations() {
    // The world mirrored left-right (cross slope negated, bumps and rows
    // mirrored), the robot's lateral position and heading negated: the LiDAR's
    // rays are symmetric about its axis, so every deviation is negated.
    let mut ground = World::ground(0.03, 0.2);
    SplitMix64(17).bumps(&mut ground, 60, 0.2, 0.08, (0.0, 8.0));
    let world = vineyard(ground, 2.2, SUMMER_WIDTH, &[]);
    let mut mirror = world.clone();
    mirror.cross = -world.cross;
    for b in &mut mirror.boxes {
        let (lo, hi) = (b.min[1], b.max[1]);
        b.min[1] = -hi;
        b.max[1] = -lo;
    }
    let params = VineParams::summer();
    let a = drive(&params, &world, (0.0, 0.25, 0.04), 35, same);
    let b = drive(&params, &mirror, (0.0, -0.25, -0.04), 35, same);
    for (a, b) in a.iter().zip(&b) {
        assert_eq!(a.verdict, b.verdict);
        if let (Some(ea), Some(eb)) = (a.error, b.error) {
            assert!((ea.y.get() + eb.y.get()).abs() < 1e-6, "{ea:?} {eb:?}");
            assert!((ea.angular_deviation.get() + eb.angular_deviation.get()).abs() < 1e-6);
        }
    }
    assert!(a.last().unwrap().verdict.estimate_is_valid());
}

#[test]
fn range_noise_of_two_centimetres_keeps_the_row() {
    // Every range off by up to ±2 cm (uniform), a cross slope and bumps: the
    // RANSAC's 5 cm tolerance and the 0.2 m floor absorb it.
    let mut ground = World::ground(0.02, 0.15);
    SplitMix64(23).bumps(&mut ground, 60, 0.2, 0.08, (0.0, 8.0));
    let world = vineyard(ground, 2.2, SUMMER_WIDTH, &[]);
    let lidar = Lidar::table1();
    let mut noise = SplitMix64(99);
    let mut d = Detector::new(VineConfig::new(&VineParams::summer()).unwrap()).unwrap();
    let (y, heading) = (-0.2, 0.03_f64);
    let mut worst = 0.0_f64;
    for k in 0..40 {
        let t = 0.1 * f64::from(k);
        let pose = (t * heading.cos(), y + t * heading.sin(), heading);
        let mut ranges = lidar.cast(&world, pose);
        for r in &mut ranges {
            *r += 0.04 * (noise.unit() - 0.5);
        }
        let det = d
            .detect(
                &lidar.scan(&ranges),
                &Pose2::new(pose.0, pose.1, pose.2).unwrap(),
            )
            .unwrap();
        if k >= 10 {
            assert!(det.verdict.estimate_is_valid(), "scan {k}: {det:?}");
            let e = det.error.unwrap();
            worst = worst.max((e.y.get() - pose.1).abs());
            assert!((e.angular_deviation.get() - heading).abs() < 0.03);
        }
    }
    assert!(worst < 0.03, "worst lateral error {worst}");
}
