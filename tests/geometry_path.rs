//! Reference paths and the Frénet projection (`spec/geometry.md`, PATH-* and FRENET-*).
//!
//! Expected values come from hand computation on simple geometry (lines,
//! circles, a right-angle corner, a U-turn), from symmetry (mirror image) and
//! invariance (rigid motions), and from "any f64 gives a value or an error".
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::arithmetic_side_effects,
    clippy::as_conversions,
    clippy::float_cmp
)]

use core::f64::consts::{FRAC_PI_2, PI};

use fieldguide::control::backstepping::steering_command;
use fieldguide::geometry::path::{
    FrenetError, PathConfig, PathPosition, ReferencePath, MAX_PATH_COORDINATE, MAX_PATH_LENGTH,
    MIN_WAYPOINT_SPACING,
};
use fieldguide::geometry::units::wrap_angle;
use fieldguide::model::bicycle::Sideslip;
use fieldguide::{
    Meters, MetersPerSecond, Point2, Pose2, Radians, TrackingError, Transform2, World,
};
use proptest::prelude::*;

const CAP: usize = 2048;
type Path = ReferencePath<CAP>;

fn m(x: f64) -> Meters {
    Meters::new(x).unwrap()
}

fn pt(x: f64, y: f64) -> Point2<World> {
    Point2::new(x, y).unwrap()
}

fn pose(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

fn path(points: &[Point2<World>]) -> Path {
    ReferencePath::from_waypoints(points, PathConfig::default()).unwrap()
}

fn path_w(points: &[Point2<World>], w: f64) -> Path {
    ReferencePath::from_waypoints(points, PathConfig::new(m(w)).unwrap()).unwrap()
}

/// |wrap(a − b)|: the distance between two angles.
fn angle_diff(a: f64, b: f64) -> f64 {
    wrap_angle(Radians::new(a - b).unwrap()).get().abs()
}

/// Waypoints every `step` metres on the straight line from `(x0, y0)` with heading `phi`.
fn line_points(x0: f64, y0: f64, phi: f64, n: usize, step: f64) -> Vec<Point2<World>> {
    (0..n)
        .map(|i| {
            let d = step * i as f64;
            pt(x0 + d * phi.cos(), y0 + d * phi.sin())
        })
        .collect()
}

/// Waypoints every `step` metres of arc on a circle of radius `r` centred at the
/// origin, starting at angle `a0` and covering `sweep` radians (negative: clockwise).
fn arc_points(r: f64, a0: f64, sweep: f64, step: f64) -> Vec<Point2<World>> {
    let n = (r * sweep.abs() / step).round() as usize;
    (0..=n)
        .map(|i| {
            let a = a0 + sweep * i as f64 / n as f64;
            pt(r * a.cos(), r * a.sin())
        })
        .collect()
}

/// A small deterministic generator (xorshift64*) with Box–Muller normals, for noise.
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        ((v >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
}

fn noisy(points: &[Point2<World>], sigma: f64, seed: u64) -> Vec<Point2<World>> {
    let mut n = Noise(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    points
        .iter()
        .map(|p| pt(p.x() + sigma * n.normal(), p.y() + sigma * n.normal()))
        .collect()
}

/// A recorded U-turn: east along y = 0 for 20 m, a left semicircle of
/// radius 3 m centred at (20, 3), then west along y = 6 for 20 m; every 0.1 m.
fn u_turn_points() -> Vec<Point2<World>> {
    let mut pts = line_points(0.0, 0.0, 0.0, 200, 0.1);
    for p in arc_points(3.0, -FRAC_PI_2, PI, 0.1) {
        pts.push(pt(p.x() + 20.0, p.y() + 3.0));
    }
    for p in line_points(20.0, 6.0, PI, 201, 0.1).into_iter().skip(1) {
        pts.push(p);
    }
    pts
}

fn assert_finite(e: &FrenetError) {
    assert!(e.s.get().is_finite());
    assert!(e.y.get().is_finite());
    assert!(e.angular_deviation.get().is_finite());
    assert!(e.angular_deviation.get() > -PI && e.angular_deviation.get() <= PI);
    assert!(e.curvature.get().is_finite());
    assert!(e.curvature_ahead.get().is_finite());
}

// ---------------------------------------------------------------- construction

//= spec/geometry.md#path-config-path-configuration
//= type=test
//# The smoothing window w MUST be strictly positive; a path configuration
//# where it is not MUST be refused with the `PATH-CONFIG` error.
#[test]
fn non_positive_window_is_refused() {
    for w in [0.0, -1.0, -1e-300] {
        assert_eq!(
            PathConfig::new(m(w)).unwrap_err().requirement,
            "PATH-CONFIG"
        );
        // A config built by hand is validated again by the constructor.
        let bad = PathConfig {
            smoothing_window: m(w),
        };
        let err = Path::from_waypoints(&[pt(0.0, 0.0), pt(1.0, 0.0)], bad).unwrap_err();
        assert_eq!(err.requirement, "PATH-CONFIG");
    }
    assert_eq!(PathConfig::default().smoothing_window.get(), 1.0);
    assert!(PathConfig::new(m(1e-6)).is_ok());
}

//= spec/geometry.md#path-waypoints-distinct-waypoints
//= type=test
//# A waypoint closer than `MIN_WAYPOINT_SPACING` (1 mm) to the last kept
//# waypoint MUST be dropped, not reported as an error.
#[test]
fn consecutive_duplicates_are_dropped() {
    let p = path(&[
        pt(0.0, 0.0),
        pt(0.0, 0.0),
        pt(0.0, 0.0004),
        pt(1.0, 0.0),
        pt(1.0, 0.0),
        pt(1.0 + 0.9 * MIN_WAYPOINT_SPACING, 0.0),
        pt(2.0, 0.0),
    ]);
    let s: Vec<f64> = p.vertices().iter().map(|v| v.s.get()).collect();
    assert_eq!(s.len(), 3);
    assert!((s[1] - 1.0).abs() < 1e-12 && (s[2] - 2.0).abs() < 1e-12);
    assert!((p.length().get() - 2.0).abs() < 1e-12);
    // The comparison is with the last kept point: 0.6 mm steps advance every other step.
    let crawl: Vec<_> = (0..=10).map(|i| pt(0.0006 * f64::from(i), 0.0)).collect();
    let c = path(&crawl);
    assert_eq!(c.vertices().len(), 6);
    // Non-consecutive coincident points (a path crossing itself) are kept.
    let loop_pts = [pt(0.0, 0.0), pt(1.0, 0.0), pt(1.0, 1.0), pt(0.0, 0.0)];
    assert_eq!(path(&loop_pts).vertices().len(), 4);
}

//= spec/geometry.md#path-waypoints-distinct-waypoints
//= type=test
//# A path MUST be refused with the `PATH-WAYPOINTS` error when fewer than 2
//# distinct waypoints remain.
#[test]
fn fewer_than_two_distinct_waypoints_are_refused() {
    let cfg = PathConfig::default();
    for pts in [
        vec![],
        vec![pt(1.0, 2.0)],
        vec![pt(1.0, 2.0), pt(1.0, 2.0), pt(1.0005, 2.0)],
    ] {
        let err = Path::from_waypoints(&pts, cfg).unwrap_err();
        assert_eq!(err.requirement, "PATH-WAYPOINTS");
    }
}

//= spec/geometry.md#path-capacity-fixed-capacity
//= type=test
//# A path of capacity N MUST be refused with the `PATH-CAPACITY` error when
//# more than N distinct waypoints are given.
#[test]
fn more_than_capacity_is_refused() {
    let cfg = PathConfig::default();
    let pts = line_points(0.0, 0.0, 0.3, 5, 1.0);
    assert!(ReferencePath::<5>::from_waypoints(&pts, cfg).is_ok());
    let err = ReferencePath::<4>::from_waypoints(&pts, cfg).unwrap_err();
    assert_eq!(err.requirement, "PATH-CAPACITY");
    // Duplicates do not count against the capacity.
    let mut dup = pts.clone();
    dup.insert(2, pts[2]);
    assert!(ReferencePath::<5>::from_waypoints(&dup, cfg).is_ok());
    // Capacities below 2 can never hold a path.
    let e1 = ReferencePath::<1>::from_waypoints(&pts[..2], cfg).unwrap_err();
    assert_eq!(e1.requirement, "PATH-CAPACITY");
}

//= spec/geometry.md#path-arc-length-curvilinear-abscissa
//= type=test
//# The curvilinear abscissa s of a vertex MUST be the length of the polyline
//# through the kept waypoints from the first one to that vertex.
#[test]
fn arc_length_is_the_polyline_length() {
    let p = path(&[pt(0.0, 0.0), pt(3.0, 4.0), pt(3.0, 10.0), pt(-1.0, 7.0)]);
    let s: Vec<f64> = p.vertices().iter().map(|v| v.s.get()).collect();
    assert_eq!(s, vec![0.0, 5.0, 11.0, 16.0]);
    assert_eq!(p.length().get(), 16.0);
    // p(s) is linear between vertices.
    let q = p.point_at(m(8.0)).unwrap();
    assert!((q.x() - 3.0).abs() < 1e-12 && (q.y() - 7.0).abs() < 1e-12);
    let q = p.point_at(m(2.5)).unwrap();
    assert!((q.x() - 1.5).abs() < 1e-12 && (q.y() - 2.0).abs() < 1e-12);
}

/// The next `f64` above a positive `x`.
fn next_up(x: f64) -> f64 {
    f64::from_bits(x.to_bits() + 1)
}

/// A serpentine between x = −1e7 and x = 1e7, 1 m between its rows, whose
/// last row is shortened so that the length is exactly `length` (an integer
/// number of metres, computed exactly in `f64`).
fn serpentine(length: f64) -> Vec<Point2<World>> {
    let (half, row) = (MAX_PATH_COORDINATE, 2.0 * MAX_PATH_COORDINATE);
    let mut points = vec![pt(-half, 0.0)];
    let (mut x, mut y, mut total) = (-half, 0.0, 0.0);
    loop {
        let rest = length - total;
        let direction = if x < 0.0 { 1.0 } else { -1.0 };
        if rest <= row {
            points.push(pt(x + direction * rest, y));
            return points;
        }
        x += direction * row;
        points.push(pt(x, y));
        y += 1.0;
        points.push(pt(x, y));
        total += row + 1.0;
    }
}

//= spec/geometry.md#path-range-coordinates-and-length-within-range
//= type=test
//# A path MUST be refused with the `PATH-RANGE` error when a waypoint has a
//# coordinate of magnitude above `MAX_PATH_COORDINATE` (1e7 m) or when its
//# length L exceeds `MAX_PATH_LENGTH` (1e9 m).
#[test]
fn coordinates_and_lengths_beyond_the_range_are_refused_at_the_boundary() {
    let (c, above) = (MAX_PATH_COORDINATE, next_up(MAX_PATH_COORDINATE));
    assert_eq!(c, 1e7);
    assert_eq!(MAX_PATH_LENGTH, 1e9);
    for (a, b) in [(c, 0.0), (0.0, c), (-c, 0.0), (0.0, -c)] {
        assert!(Path::from_waypoints(&[pt(0.0, 0.0), pt(a, b)], PathConfig::default()).is_ok());
    }
    for (a, b) in [(above, 0.0), (0.0, above), (-above, 0.0), (0.0, -above)] {
        for points in [[pt(0.0, 0.0), pt(a, b)], [pt(a, b), pt(0.0, 0.0)]] {
            let e = Path::from_waypoints(&points, PathConfig::default()).unwrap_err();
            assert_eq!(e.requirement, "PATH-RANGE", "{a} {b}");
        }
    }
    // A duplicate, dropped by PATH-WAYPOINTS, is checked too.
    let dup = [pt(c, 0.0), pt(above, 0.0), pt(0.0, 0.0)];
    assert_eq!(
        Path::from_waypoints(&dup, PathConfig::default())
            .unwrap_err()
            .requirement,
        "PATH-RANGE"
    );
    // Waypoints 3.4e17 m apart, where s stopped growing.
    let far = [
        pt(0.0, 0.0),
        pt(3.4e17, 0.0),
        pt(3.4e17, 0.01),
        pt(3.4e17, 0.02),
    ];
    assert_eq!(
        Path::from_waypoints(&far, PathConfig::default())
            .unwrap_err()
            .requirement,
        "PATH-RANGE"
    );
    // Exactly 1e9 m is a path; one metre more is not.
    let longest =
        ReferencePath::<128>::from_waypoints(&serpentine(1e9), PathConfig::default()).unwrap();
    assert_eq!(longest.length().get(), 1e9);
    let too_long =
        ReferencePath::<128>::from_waypoints(&serpentine(1e9 + 1.0), PathConfig::default())
            .unwrap_err();
    assert_eq!(too_long.requirement, "PATH-RANGE");
}

//= spec/geometry.md#path-range-coordinates-and-length-within-range
//= type=test
//# The abscissae of consecutive vertices of a path MUST increase strictly.
#[test]
fn millimetre_steps_at_the_longest_length_still_advance_s() {
    // 1e9 − 1 m of serpentine, then steps just above 1 mm: each is kept and
    // each adds to s, where f64's spacing is 1.2e−7 m.
    let mut points = serpentine(1e9 - 1.0);
    let last = *points.last().unwrap();
    for k in 1..=100 {
        points.push(pt(last.x(), last.y() + 1.0001e-3 * k as f64));
    }
    let p = ReferencePath::<256>::from_waypoints(&points, PathConfig::default()).unwrap();
    assert_eq!(p.vertices().len(), points.len());
    for w in p.vertices().windows(2) {
        assert!(w[1].s.get() - w[0].s.get() >= MIN_WAYPOINT_SPACING - 1.2e-7);
    }
}

/// A coordinate offset of any scale, 1 mm to 1e300 m, either sign.
fn any_scale() -> impl Strategy<Value = f64> {
    (-3.0_f64..300.0, any::<bool>()).prop_map(|(e, negative)| {
        let v = 10f64.powf(e);
        if negative {
            -v
        } else {
            v
        }
    })
}

proptest! {
    //= spec/geometry.md#path-range-coordinates-and-length-within-range
    //= type=test
    //# The abscissae of consecutive vertices of a path MUST increase strictly.
    #[test]
    fn abscissae_increase_strictly_on_every_path_accepted(
        start in (any_scale(), any_scale()),
        steps in prop::collection::vec((any_scale(), any_scale()), 1..40),
    ) {
        let mut points = vec![Point2::<World>::new(start.0, start.1)];
        let (mut x, mut y) = start;
        for (dx, dy) in steps {
            x += dx;
            y += dy;
            points.push(Point2::new(x, y));
        }
        let Some(points) = points.into_iter().collect::<Result<Vec<_>, _>>().ok() else {
            return Ok(());
        };
        match Path::from_waypoints(&points, PathConfig::default()) {
            Ok(p) => {
                for w in p.vertices().windows(2) {
                    prop_assert!(w[1].s.get() > w[0].s.get(), "{:?}", w);
                }
                prop_assert!(p.length().get() <= MAX_PATH_LENGTH);
            }
            Err(e) => prop_assert!(
                ["PATH-RANGE", "PATH-WAYPOINTS"].contains(&e.requirement),
                "{e}"
            ),
        }
    }
}

// ---------------------------------------------------------------- heading, curvature

//= spec/geometry.md#path-heading-smoothed-heading
//= type=test
//# The heading at s MUST be the direction of the chord p(b) − p(a) of the
//# polyline, where [a, b] = [s − w/2, s + w/2] ∩ [0, L].
#[test]
fn heading_is_the_chord_over_the_window_on_a_sparse_corner() {
    // East 10 m, then north 10 m: sparse waypoints at the corners only.
    let p = path(&[pt(0.0, 0.0), pt(10.0, 0.0), pt(10.0, 10.0)]);
    // Along the straight parts the heading is exact, not interpolated between vertices.
    assert!(p.heading_at(m(5.0)).get().abs() < 1e-12);
    assert!(p.heading_at(m(9.5)).get().abs() < 1e-12);
    assert!((p.heading_at(m(15.0)).get() - FRAC_PI_2).abs() < 1e-12);
    // At the corner: chord (9.5, 0) → (10, 0.5), 45°.
    assert!((p.heading_at(m(10.0)).get() - PI / 4.0).abs() < 1e-12);
    // At s = 9.75: chord (9.25, 0) → (10, 0.25): atan2(0.25, 0.75).
    assert!((p.heading_at(m(9.75)).get() - 0.25_f64.atan2(0.75)).abs() < 1e-12);
    // Clipped at the start: chord (0, 0) → (0.5, 0).
    assert!(p.heading_at(m(0.0)).get().abs() < 1e-12);
    // The stored vertex headings are the same definition.
    for v in p.vertices() {
        assert!(angle_diff(v.heading.get(), p.heading_at(v.s).get()) < 1e-12);
    }
    // A wider window: w = 4, at s = 10 the chord (8, 0) → (10, 2).
    let p4 = path_w(&[pt(0.0, 0.0), pt(10.0, 0.0), pt(10.0, 10.0)], 4.0);
    assert!((p4.heading_at(m(10.0)).get() - PI / 4.0).abs() < 1e-12);
    assert!((p4.heading_at(m(9.0)).get() - 1.0_f64.atan2(3.0)).abs() < 1e-12);
}

//= spec/geometry.md#path-heading-smoothed-heading
//= type=test
//# When that chord is shorter than 1e−9 m, the heading MUST be the direction
//# of the polyline segment containing s.
#[test]
fn heading_falls_back_to_the_segment_where_the_path_doubles_back() {
    // Out 1 m east and straight back: at the cusp (s = 1) the chord over
    // [0.5, 1.5] is zero.
    let p = path(&[pt(0.0, 0.0), pt(1.0, 0.0), pt(0.0, 0.0)]);
    let h = p.heading_at(m(1.0)).get();
    // s = 1 is the start of the second segment (heading π).
    assert!(angle_diff(h, PI) < 1e-12, "{h}");
    // Elsewhere the heading is a real chord and everything stays finite.
    for i in 0..=20 {
        let s = m(0.1 * f64::from(i));
        assert!(p.heading_at(s).get().is_finite());
        assert!(p.curvature_at(s).get().is_finite());
    }
}

//= spec/geometry.md#path-curvature-smoothed-curvature
//= type=test
//# For s in [0, L] the curvature MUST be c(s) = wrap(θ_Γ(b) − θ_Γ(a)) / (m(b) − m(a)),
//# where [a, b] = [s − w/2, s + w/2] ∩ [0, L], θ_Γ is the smoothed heading and
//# m(x) is the centre of the clipped window around x.
#[test]
fn curvature_at_a_sparse_corner_by_hand() {
    let p = path(&[pt(0.0, 0.0), pt(10.0, 0.0), pt(10.0, 10.0)]);
    // s = 10: θ(9.5) = chord (9, 0)→(10, 0) = 0; θ(10.5) = chord (10, 0)→(10, 1) = π/2;
    // window centres 9.5 and 10.5: c = (π/2) / 1.
    assert!((p.curvature_at(m(10.0)).get() - FRAC_PI_2).abs() < 1e-12);
    // s = 9.5: θ(9) = 0, θ(10) = π/4, arc 1: c = π/4.
    assert!((p.curvature_at(m(9.5)).get() - PI / 4.0).abs() < 1e-12);
    // Straight parts farther than w from the corner: zero.
    assert!(p.curvature_at(m(5.0)).get().abs() < 1e-12);
    assert!(p.curvature_at(m(15.0)).get().abs() < 1e-12);
    // Turning right instead: negative.
    let r = path(&[pt(0.0, 0.0), pt(10.0, 0.0), pt(10.0, -10.0)]);
    assert!((r.curvature_at(m(10.0)).get() + FRAC_PI_2).abs() < 1e-12);
    // Near the start: s = 0.2 on a path turning at s = 0.5 (w = 1):
    // a = 0, b = 0.7; θ(0) = chord [0, 0.5] = 0, m(0) = 0.25;
    // θ(0.7) = chord (0.2, 0) → (0.5, 0.7); m(0.7) = 0.7.
    let q = path(&[pt(0.0, 0.0), pt(0.5, 0.0), pt(0.5, 10.0)]);
    let expected = 0.7_f64.atan2(0.3) / (0.7 - 0.25);
    assert!((q.curvature_at(m(0.2)).get() - expected).abs() < 1e-12);
}

//= spec/geometry.md#path-curvature-smoothed-curvature
//= type=test
//# When m(b) − m(a) is below 1e−9 m, the curvature MUST be 0.
#[test]
fn curvature_of_a_path_shorter_than_the_window() {
    // L = 0.2 < w = 1: every clipped window is [0, L], the centres coincide.
    let p = path(&[pt(0.0, 0.0), pt(0.1, 0.0), pt(0.1, 0.1)]);
    for i in 0..=4 {
        let s = m(0.05 * f64::from(i));
        assert_eq!(p.curvature_at(s).get(), 0.0);
    }
}

/// Circles sampled every 0.1 m: exact waypoints give c = ±1/R everywhere,
/// ends included; the sign follows the turning direction.
//= spec/geometry.md#path-curvature-smoothed-curvature
//= type=test
//# For s in [0, L] the curvature MUST be c(s) = wrap(θ_Γ(b) − θ_Γ(a)) / (m(b) − m(a)),
//# where [a, b] = [s − w/2, s + w/2] ∩ [0, L], θ_Γ is the smoothed heading and
//# m(x) is the centre of the clipped window around x.
#[test]
fn circle_curvature_without_noise() {
    for r in [2.0, 3.0, 5.0, 20.0] {
        for (sweep, sign) in [(1.5 * PI, 1.0), (-1.5 * PI, -1.0)] {
            let p = path(&arc_points(r, 0.3, sweep, 0.1));
            for v in p.vertices() {
                let c = v.curvature.get();
                // Relative bound 1e-3: the chords of the sampled polygon are
                // 2 r sin(0.05 / r) long instead of 0.1 (relative 1e-4 for r = 2).
                assert!(
                    (c - sign / r).abs() < 1e-3 / r,
                    "r {r} sign {sign} s {} c {c}",
                    v.s.get()
                );
                // The heading is the tangent: angle of the radius + π/2 (CCW) or − π/2 (CW),
                // taken at the centre of the clipped window (w/4 inside at the ends).
                let l = p.length().get();
                let centre = 0.5 * ((v.s.get() - 0.5).max(0.0) + (v.s.get() + 0.5).min(l));
                let radial = v.position.y().atan2(v.position.x()) + sign * (centre - v.s.get()) / r;
                let tangent = radial + sign * FRAC_PI_2;
                assert!(
                    angle_diff(v.heading.get(), tangent) < 1e-3 / r,
                    "r {r} s {} diff {}",
                    v.s.get(),
                    angle_diff(v.heading.get(), tangent)
                );
            }
        }
    }
}

/// With 1.5 cm GNSS noise per coordinate, over 20 seeds.
///
/// Bound: away from the ends by w, |c − 1/R| < 6 · √6 σ / w² + 0.03 / R:
/// six standard deviations of the second difference of PATH-CURVATURE, plus
/// 3 % for the lengthening of a noisy polyline (about 2 % at 0.1 m spacing).
/// The mean over the interior is within 0.01 1/m + 3 % of 1/R.
#[test]
fn circle_curvature_with_gnss_noise() {
    let sigma = 0.015;
    for (w, r) in [(1.0, 3.0), (1.0, 5.0), (2.0, 5.0), (2.0, 10.0)] {
        let bound = 6.0 * 6.0_f64.sqrt() * sigma / (w * w) + 0.03 / r;
        let mut worst: f64 = 0.0;
        for seed in 1..=20 {
            for (sweep, sign) in [(1.5 * PI, 1.0), (-1.5 * PI, -1.0)] {
                let clean = arc_points(r, -1.0, sweep, 0.1);
                let p = path_w(&noisy(&clean, sigma, seed), w);
                let l = p.length().get();
                let interior: Vec<f64> = p
                    .vertices()
                    .iter()
                    .filter(|v| v.s.get() > w && v.s.get() < l - w)
                    .map(|v| v.curvature.get())
                    .collect();
                for &c in &interior {
                    worst = worst.max((c - sign / r).abs());
                    // Sign by turning direction, everywhere in the interior.
                    assert!(c * sign > 0.0, "w {w} r {r} seed {seed}: c {c}");
                }
                let mean = interior.iter().sum::<f64>() / interior.len() as f64;
                assert!(
                    (mean - sign / r).abs() < 0.01 + 0.03 / r,
                    "w {w} r {r} seed {seed}: mean {mean}"
                );
            }
        }
        assert!(worst < bound, "w {w} r {r}: worst {worst} bound {bound}");
    }
}

//= spec/geometry.md#path-extension-straight-extensions
//= type=test
//# Before s = 0 and after s = L the path MUST continue as straight half-lines
//# along the smoothed headings at s = 0 and s = L, with zero curvature.
#[test]
fn path_continues_straight_beyond_its_ends() {
    // A quarter circle of radius 5 from (5, 0) counter-clockwise to (0, 5).
    let p = path(&arc_points(5.0, 0.0, FRAC_PI_2, 0.1));
    let l = p.length().get();
    let h0 = p.heading_at(m(0.0)).get();
    let h_end = p.heading_at(m(l)).get();
    // Clipped windows: the chord over [0, w/2] of a circle has the tangent at w/4.
    assert!(angle_diff(h0, FRAC_PI_2 + 0.25 / 5.0) < 1e-4);
    assert!(angle_diff(h_end, PI - 0.25 / 5.0) < 1e-4);
    for d in [0.5, 3.0, 100.0] {
        assert_eq!(p.curvature_at(m(-d)).get(), 0.0);
        assert_eq!(p.curvature_at(m(l + d)).get(), 0.0);
        assert_eq!(p.heading_at(m(-d)).get(), h0);
        assert_eq!(p.heading_at(m(l + d)).get(), h_end);
        let q = p.point_at(m(-d)).unwrap();
        assert!((q.x() - (5.0 - d * h0.cos())).abs() < 1e-9);
        assert!((q.y() - (0.0 - d * h0.sin())).abs() < 1e-9);
        let last = p.vertices().last().unwrap().position;
        let q = p.point_at(m(l + d)).unwrap();
        assert!((q.x() - (last.x() + d * h_end.cos())).abs() < 1e-9);
        assert!((q.y() - (last.y() + d * h_end.sin())).abs() < 1e-9);
    }
    // Far out the point is still finite: waypoints lie within 1e7 m of the
    // origin (PATH-RANGE), so a point at any finite s never overflows.
    let far = path(&[pt(1e7, 1e7), pt(-1e7, -1e7)]);
    for s in [f64::MAX, -f64::MAX] {
        let q = far.point_at(m(s)).unwrap();
        assert!(q.x().is_finite() && q.y().is_finite());
    }
}

// ---------------------------------------------------------------- projection

//= spec/geometry.md#frenet-lateral-signed-lateral-error
//= type=test
//# The lateral error y MUST be the distance from the robot position to the
//# closest point, positive when the robot is left of the path direction at
//# that point and negative when it is right.
//= spec/geometry.md#frenet-angular-angular-deviation
//= type=test
//# The angular deviation MUST be θ̃ = θ − θ_Γ(s), the robot heading minus
//# the smoothed path heading at s, wrapped to (−π, π].
#[test]
fn straight_path_by_hand() {
    let p = path(&[pt(0.0, 0.0), pt(10.0, 0.0)]);
    let e = p.project(&pose(3.0, 2.0, 0.5), m(0.0)).unwrap();
    assert_eq!(e.s.get(), 3.0);
    assert_eq!(e.y.get(), 2.0);
    assert_eq!(e.angular_deviation.get(), 0.5);
    assert_eq!(e.curvature.get(), 0.0);
    assert_eq!(e.position, PathPosition::Within);
    let e = p.project(&pose(7.5, -1.25, PI), m(0.0)).unwrap();
    assert_eq!(e.s.get(), 7.5);
    assert_eq!(e.y.get(), -1.25);
    assert_eq!(e.angular_deviation.get(), PI);
    // Heading −3 rad against path heading 0.
    let e = p.project(&pose(1.0, 0.0, -3.0), m(0.0)).unwrap();
    assert_eq!(e.y.get(), 0.0);
    assert!((e.angular_deviation.get() + 3.0).abs() < 1e-15);
    // A diagonal path, 3-4-5: the robot at (0, 5) is 4 left of s = 3.
    let d = path(&[pt(0.0, 0.0), pt(6.0, 8.0)]);
    let e = d.project(&pose(0.0, 5.0, 0.0), m(0.0)).unwrap();
    assert!((e.s.get() - 4.0).abs() < 1e-12);
    assert!((e.y.get() - 3.0).abs() < 1e-12);
    assert!((e.angular_deviation.get() + 8.0_f64.atan2(6.0)).abs() < 1e-12);
    // Conversion to the control laws' input keeps every field.
    let t: fieldguide::TrackingError = e.into();
    assert_eq!(t.y, e.y);
    assert_eq!(t.angular_deviation, e.angular_deviation);
}

proptest! {
    /// On a straight path in any direction, y is the exact signed distance and
    /// θ̃ the exact wrapped heading difference.
    //= spec/geometry.md#frenet-lateral-signed-lateral-error
    //= type=test
    //# The lateral error y MUST be the distance from the robot position to the
    //# closest point, positive when the robot is left of the path direction at
    //# that point and negative when it is right.
    //= spec/geometry.md#frenet-closest-closest-point
    //= type=test
    //# `project` MUST return the abscissa s of a point of the extended path
    //# (the polyline and its two end extensions) closest to the robot position.
    #[test]
    fn straight_line_exact(
        x0 in -1e3..1e3_f64, y0 in -1e3..1e3_f64, phi in -PI..PI,
        n in 2_usize..40, step in 0.05..3.0_f64,
        along in -0.2..1.2_f64, offset in -20.0..20.0_f64, theta in -10.0..10.0_f64,
    ) {
        let p = path(&line_points(x0, y0, phi, n, step));
        let l = p.length().get();
        let s0 = along * l;
        let (c, s) = (phi.cos(), phi.sin());
        let q = pose(x0 + s0 * c - offset * s, y0 + s0 * s + offset * c, theta);
        let e = p.project(&q, m(1.0)).unwrap();
        assert_finite(&e);
        let tol = 1e-9 * (1.0 + x0.abs() + y0.abs() + l);
        prop_assert!((e.s.get() - s0).abs() < tol, "s {} vs {}", e.s.get(), s0);
        prop_assert!((e.y.get() - offset).abs() < tol, "y {} vs {}", e.y.get(), offset);
        prop_assert!(angle_diff(e.angular_deviation.get(), theta - phi) < 1e-9);
        prop_assert!(e.curvature.get().abs() < 1e-9);
        prop_assert!(e.curvature_ahead.get().abs() < 1e-9);
        let expected = if s0 < -tol { PathPosition::BeforeStart }
            else if s0 > l + tol { PathPosition::PastEnd } else { PathPosition::Within };
        if (s0).abs() > tol && (s0 - l).abs() > tol {
            prop_assert_eq!(e.position, expected);
        }
    }
}

//= spec/geometry.md#frenet-ends-before-the-start-and-past-the-end
//= type=test
//# The position MUST be `BeforeStart` when s < 0, `PastEnd` when s > L and
//# `Within` otherwise.
#[test]
fn ends_before_start_and_past_end() {
    let p = path(&[pt(0.0, 0.0), pt(10.0, 0.0)]);
    let e = p.project(&pose(-3.0, 1.0, 0.0), m(0.0)).unwrap();
    assert_eq!((e.s.get(), e.y.get()), (-3.0, 1.0));
    assert_eq!(e.position, PathPosition::BeforeStart);
    // Ahead by 5 m the curvature is still zero (straight path).
    let e = p.project(&pose(14.0, -2.0, 0.1), m(5.0)).unwrap();
    assert_eq!((e.s.get(), e.y.get()), (14.0, -2.0));
    assert_eq!(e.position, PathPosition::PastEnd);
    assert_eq!(e.curvature.get(), 0.0);
    let e = p.project(&pose(10.0, 3.0, 0.0), m(0.0)).unwrap();
    assert_eq!(e.position, PathPosition::Within);
    assert_eq!(e.s.get(), 10.0);
    let e = p.project(&pose(0.0, -3.0, 0.0), m(0.0)).unwrap();
    assert_eq!(e.position, PathPosition::Within);

    // A curved end: quarter circle of radius 5 (left turn). Past the end,
    // along the end tangent, the robot is 2 m beyond and 1 m left.
    let c = path(&arc_points(5.0, 0.0, FRAC_PI_2, 0.1));
    let l = c.length().get();
    let h = c.heading_at(m(l)).get();
    let last = c.vertices().last().unwrap().position;
    let q = pose(
        last.x() + 2.0 * h.cos() - 1.0 * h.sin(),
        last.y() + 2.0 * h.sin() + 1.0 * h.cos(),
        h + 0.2,
    );
    let e = c.project(&q, m(0.0)).unwrap();
    assert_eq!(e.position, PathPosition::PastEnd);
    assert!((e.s.get() - (l + 2.0)).abs() < 1e-9);
    assert!((e.y.get() - 1.0).abs() < 1e-9);
    assert!((e.angular_deviation.get() - 0.2).abs() < 1e-9);
    assert_eq!(e.curvature.get(), 0.0);
    // Before the start, looking 3 m ahead lands on the arc: c ahead ≈ 1/5.
    let h0 = c.heading_at(m(0.0)).get();
    let q = pose(5.0 - h0.cos(), -h0.sin(), h0);
    let e = c.project(&q, m(3.0)).unwrap();
    assert_eq!(e.position, PathPosition::BeforeStart);
    assert!((e.s.get() + 1.0).abs() < 1e-9);
    assert_eq!(e.curvature.get(), 0.0);
    assert!((e.curvature_ahead.get() - 0.2).abs() < 1e-3);
}

//= spec/geometry.md#frenet-corner-corners
//= type=test
//# Where the closest point is a vertex on the outside of a corner, y MUST be
//# the signed distance to that vertex with its side taken from the smoothed
//# heading at the vertex, and θ̃ MUST use the smoothed heading at the vertex.
#[test]
fn outside_of_a_corner() {
    // East then north (a left turn at (10, 0)); the outside is to the south-east.
    let p = path(&[pt(0.0, 0.0), pt(10.0, 0.0), pt(10.0, 10.0)]);
    let e = p.project(&pose(11.0, -1.0, 0.0), m(0.0)).unwrap();
    assert_eq!(e.s.get(), 10.0);
    assert!((e.y.get() + 2.0_f64.sqrt()).abs() < 1e-12);
    assert!((e.angular_deviation.get() + PI / 4.0).abs() < 1e-12);
    assert!((e.curvature.get() - FRAC_PI_2).abs() < 1e-12);
    // Going round the corner at 1 m (from south of the vertex to east of it),
    // heading turning with the circle: s stays at the vertex, y = −1, and θ̃
    // moves continuously.
    let mut previous: Option<FrenetError> = None;
    for i in 0..=90 {
        let a = -FRAC_PI_2 + FRAC_PI_2 * f64::from(i) / 90.0;
        let q = pose(10.0 + a.cos(), a.sin(), a + FRAC_PI_2);
        let e = p.project(&q, m(0.0)).unwrap();
        assert!((e.s.get() - 10.0).abs() < 1e-9);
        assert!((e.y.get() + 1.0).abs() < 1e-9);
        assert!((e.angular_deviation.get() - (a + FRAC_PI_2 - PI / 4.0)).abs() < 1e-9);
        if let Some(prev) = previous {
            let step = FRAC_PI_2 / 90.0;
            assert!(
                angle_diff(e.angular_deviation.get(), prev.angular_deviation.get()) < 1.01 * step
            );
        }
        previous = Some(e);
    }
    // Mirror: a right turn, the outside is to the north-east, y > 0.
    let r = path(&[pt(0.0, 0.0), pt(10.0, 0.0), pt(10.0, -10.0)]);
    let e = r.project(&pose(11.0, 1.0, 0.0), m(0.0)).unwrap();
    assert!((e.y.get() - 2.0_f64.sqrt()).abs() < 1e-12);
    assert!((e.angular_deviation.get() - PI / 4.0).abs() < 1e-12);
}

/// Driving parallel to a path through vertices and corners, θ̃ never jumps.
//= spec/geometry.md#frenet-angular-angular-deviation
//= type=test
//# The angular deviation MUST be θ̃ = θ − θ_Γ(s), the robot heading minus
//# the smoothed path heading at s, wrapped to (−π, π].
#[test]
fn angular_deviation_is_continuous_along_a_smooth_drive() {
    let p = path(&u_turn_points());
    let l = p.length().get();
    let mut previous: Option<(f64, f64)> = None;
    let mut s_hint = 0.0;
    for i in 0..=2000 {
        let s = l * f64::from(i) / 2000.0;
        let base = p.point_at(m(s)).unwrap();
        let h = p.heading_at(m(s)).get();
        // 0.4 m to the right (outside of the U-turn), heading off by 0.1 rad.
        let q = pose(base.x() + 0.4 * h.sin(), base.y() - 0.4 * h.cos(), h + 0.1);
        let e = p.project_near(&q, m(0.0), m(s_hint), m(1.0)).unwrap();
        s_hint = e.s.get();
        assert!((e.y.get() + 0.4).abs() < 0.01, "s {s}: y {}", e.y.get());
        if let Some((prev_theta, prev_s)) = previous {
            assert!(e.s.get() >= prev_s);
            assert!(angle_diff(e.angular_deviation.get(), prev_theta) < 0.01);
        }
        previous = Some((e.angular_deviation.get(), e.s.get()));
    }
}

//= spec/geometry.md#frenet-local-local-search
//= type=test
//# `project_near` MUST return the abscissa of a point closest to the robot
//# among the points of the extended path whose abscissa lies in
//# [s_hint − window, s_hint + window].
#[test]
fn u_turn_local_search_keeps_the_leg_and_s_is_monotone() {
    let p = path(&u_turn_points());
    let l = p.length().get();
    assert!((l - (40.0 + 3.0 * PI)).abs() < 0.01);
    // Between the legs, nearer the return leg, while driving out at s = 10:
    // the global projection jumps to the return leg, the local one stays.
    let q = pose(10.0, 3.2, 0.0);
    let global = p.project(&q, m(0.0)).unwrap();
    assert!(global.s.get() > 20.0 + 3.0 * PI, "{}", global.s.get());
    assert!((global.y.get() - 2.8).abs() < 1e-9); // left of the westbound leg
    let local = p.project_near(&q, m(0.0), m(10.0), m(2.0)).unwrap();
    assert!((local.s.get() - 10.0).abs() < 1e-9);
    assert!((local.y.get() - 3.2).abs() < 1e-9);
    // The returned abscissa stays in the window even when the robot is far.
    let far = p
        .project_near(&pose(0.0, 6.0, 0.0), m(0.0), m(10.0), m(2.0))
        .unwrap();
    assert!(far.s.get() >= 8.0 - 1e-12 && far.s.get() <= 12.0 + 1e-12);

    // A robot weaving along the U-turn on the inside, up to 2.5 m off the path
    // (0.5 m from the other leg's half-way), 5 cm per tick.
    let mut s_hint = 0.0;
    let mut last_s = f64::NEG_INFINITY;
    let n = 1200;
    for i in 0..=n {
        let s = l * f64::from(i) / f64::from(n);
        let base = p.point_at(m(s)).unwrap();
        let h = p.heading_at(m(s)).get();
        let off = 2.5 * (0.5 + 0.5 * (s / 3.0).sin()).min(1.0);
        let q = pose(base.x() - off * h.sin(), base.y() + off * h.cos(), h);
        let e = p.project_near(&q, m(1.0), m(s_hint), m(0.5)).unwrap();
        assert_finite(&e);
        assert!(
            e.s.get() >= last_s - 1e-9,
            "tick {i}: s {} after {last_s}",
            e.s.get()
        );
        assert!(e.y.get() > 0.0 && e.y.get() < 3.0);
        last_s = e.s.get();
        s_hint = e.s.get();
    }
    assert!((last_s - l).abs() < 0.05);
}

//= spec/geometry.md#frenet-local-local-search
//= type=test
//# A negative window MUST be refused with the `FRENET-LOCAL` error.
#[test]
fn negative_window_is_refused() {
    let p = path(&[pt(0.0, 0.0), pt(10.0, 0.0)]);
    let err = p
        .project_near(&pose(1.0, 1.0, 0.0), m(0.0), m(1.0), m(-0.1))
        .unwrap_err();
    assert_eq!(err.requirement, "FRENET-LOCAL");
    // A zero window pins s to the hint, wherever the hint is.
    for hint in [-5.0, 0.0, 4.0, 10.0, 25.0] {
        let e = p
            .project_near(&pose(1.0, 1.0, 0.0), m(0.0), m(hint), m(0.0))
            .unwrap();
        assert_eq!(e.s.get(), hint);
    }
}

//= spec/geometry.md#frenet-curvature-curvature-at-and-ahead-of-s
//= type=test
//# The Frénet error MUST carry c(s), the path's smoothed curvature at s, zero
//# beyond the ends.
//= spec/geometry.md#frenet-curvature-curvature-at-and-ahead-of-s
//= type=test
//# The Frénet error MUST carry the curvature ahead c(min(max(s + lookahead,
//# 0), L)): the smoothed curvature at s + lookahead, held at the curvature of
//# the nearer end when s + lookahead lies beyond an end.
#[test]
fn curvature_here_and_ahead_on_the_u_turn() {
    let p = path(&u_turn_points());
    let l = p.length().get();
    // On the outbound leg at s = 17, lookahead 5 m: in the semicircle.
    let e = p.project(&pose(17.0, 0.3, 0.0), m(5.0)).unwrap();
    assert!(e.curvature.get().abs() < 1e-9);
    assert!((e.curvature_ahead.get() - 1.0 / 3.0).abs() < 1e-3);
    assert_eq!(e.curvature_ahead, p.curvature_at(m(e.s.get() + 5.0)));
    // In the middle of the semicircle, looking back 4 m (reversing): still on the arc.
    let mid = 20.0 + 1.5 * PI;
    let q = p.point_at(m(mid)).unwrap();
    let e = p.project(&pose(q.x(), q.y(), FRAC_PI_2), m(-2.0)).unwrap();
    assert!((e.curvature.get() - 1.0 / 3.0).abs() < 1e-3);
    assert!((e.curvature_ahead.get() - 1.0 / 3.0).abs() < 1e-3);
    // Near the end, looking past it: the curvature of the end, a straight one.
    let e = p.project(&pose(1.0, 6.0, PI), m(5.0)).unwrap();
    assert!(e.s.get() > l - 1.5);
    assert_eq!(e.curvature_ahead, p.curvature_at(m(l)));
    assert!(e.curvature_ahead.get().abs() < 1e-9);
    // A look-ahead that overflows lies beyond the end: no error.
    for far in [f64::MAX, -f64::MAX] {
        let e = p.project(&pose(1.0, 6.0, PI), m(far)).unwrap();
        let end = if far > 0.0 { l } else { 0.0 };
        assert_eq!(e.curvature_ahead, p.curvature_at(m(end)));
    }
}

/// 10 m east along y = 0, then 5 m of a left arc of radius 5 m (c = 0.2 1/m):
/// a path that ends in a curve. Mirrored end for end (`reversed`), it starts
/// with the curve.
fn ending_on_an_arc(reversed: bool) -> Path {
    let mut points = line_points(0.0, 0.0, 0.0, 100, 0.1);
    for q in arc_points(5.0, -FRAC_PI_2, 1.0, 0.1) {
        points.push(pt(q.x() + 10.0, q.y() + 5.0));
    }
    if reversed {
        points.reverse();
    }
    path(&points)
}

/// The curvature ahead for a robot on the (extended) path at abscissa `s`,
/// heading along it, with look-ahead `lookahead`.
fn curvature_ahead_at(p: &Path, s: f64, lookahead: f64) -> f64 {
    let q = p.point_at(m(s)).unwrap();
    let h = p.heading_at(m(s)).get();
    p.project(&pose(q.x(), q.y(), h), m(lookahead))
        .unwrap()
        .curvature_ahead
        .get()
}

//= spec/geometry.md#frenet-curvature-curvature-at-and-ahead-of-s
//= type=test
//# The Frénet error MUST carry the curvature ahead c(min(max(s + lookahead,
//# 0), L)): the smoothed curvature at s + lookahead, held at the curvature of
//# the nearer end when s + lookahead lies beyond an end.
#[test]
fn curvature_ahead_does_not_jump_where_the_look_ahead_crosses_an_end() {
    let v_t = 0.8;
    for reversed in [false, true] {
        let p = ending_on_an_arc(reversed);
        let l = p.length().get();
        // The curved end: c = ±0.2 there (the arc is exact up to the ends).
        let (curved_end, straight_end) = if reversed { (0.0, l) } else { (l, 0.0) };
        assert!((p.curvature_at(m(curved_end)).get().abs() - 0.2).abs() < 1e-3);
        assert!(p.curvature_at(m(straight_end)).get().abs() < 1e-9);
        // The robot where s + lookahead crosses each end, looking either way.
        for (end, lookahead) in [(l, v_t), (l, -v_t), (0.0, v_t), (0.0, -v_t)] {
            let held = p.curvature_at(m(end)).get();
            let crossing = end - lookahead;
            let mut previous = curvature_ahead_at(&p, crossing - 0.05, lookahead);
            for i in -499..=500 {
                let s = crossing + 1e-4 * f64::from(i);
                let c = curvature_ahead_at(&p, s, lookahead);
                assert!(
                    (c - previous).abs() < 1e-3,
                    "reversed {reversed}, end {end}, lookahead {lookahead}: c(s + vT) jumps from {previous} to {c} at s = {s}"
                );
                previous = c;
            }
            // Beyond the end the curvature of the end is held.
            let past = if end > 0.0 { 0.5 } else { -0.5 };
            let beyond = curvature_ahead_at(&p, crossing + past, lookahead);
            assert_eq!(beyond, held);
        }
    }
}

//= spec/geometry.md#frenet-curvature-curvature-at-and-ahead-of-s
//= type=test
//# The Frénet error MUST carry the curvature ahead c(min(max(s + lookahead,
//# 0), L)): the smoothed curvature at s + lookahead, held at the curvature of
//# the nearer end when s + lookahead lies beyond an end.
#[test]
fn steering_does_not_jump_where_the_look_ahead_reaches_the_end_of_an_arc() {
    // Pierre 2022's path tracking (0.8 m/s, T = 1 s, 2 m wheelbase) on a path
    // ending in an arc of radius 5 m: the feed-forward alone is
    // atan(2 m · 0.2 1/m) = 0.38 rad, which a zero curvature past the end
    // dropped within one millimetre of travel.
    let law = fieldguide::presets::path_tracking().unwrap();
    let (v, v_t) = (MetersPerSecond::new(0.8).unwrap(), 0.8);
    let p = ending_on_an_arc(false);
    let l = p.length().get();
    let steer = |s: f64| {
        // 5 cm left of the path, heading along it.
        let q = p.point_at(m(s)).unwrap();
        let h = p.heading_at(m(s)).get();
        let e = p
            .project(
                &pose(q.x() - 0.05 * h.sin(), q.y() + 0.05 * h.cos(), h),
                m(v_t),
            )
            .unwrap();
        steering_command(&law.law, &TrackingError::from(e), Sideslip::ZERO, v)
            .unwrap()
            .steering
            .get()
    };
    let crossing = l - v_t;
    let mut previous = steer(crossing - 0.05);
    for i in -499..=500 {
        let s = crossing + 1e-4 * f64::from(i);
        let delta = steer(s);
        // At most 0.01 rad per 0.1 mm of travel (the polyline's vertices
        // every 0.1 m, seen through y and θ̃, move it by about 1e-3 rad).
        assert!(
            (delta - previous).abs() < 0.01,
            "steering jumps from {previous} to {delta} rad at s = {s}"
        );
        previous = delta;
    }
}

// ---------------------------------------------------------------- properties

/// A random smooth path: 2 to 200 points spaced 0.05–1 m, turning by at most
/// 0.3 rad per point, starting anywhere.
fn smooth_path() -> impl Strategy<Value = Vec<Point2<World>>> {
    (
        -100.0..100.0_f64,
        -100.0..100.0_f64,
        -PI..PI,
        prop::collection::vec((0.05..1.0_f64, -0.3..0.3_f64), 1..200),
    )
        .prop_map(|(x0, y0, h0, steps)| {
            let mut pts = vec![pt(x0, y0)];
            let (mut x, mut y, mut h) = (x0, y0, h0);
            for (d, dh) in steps {
                h += dh;
                x += d * h.cos();
                y += d * h.sin();
                pts.push(pt(x, y));
            }
            pts
        })
}

fn close_angle(a: f64, b: f64, tol: f64) -> bool {
    angle_diff(a, b) < tol
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Reflecting path and pose about the x axis negates y, θ̃ and c, and keeps s.
    //= spec/geometry.md#frenet-lateral-signed-lateral-error
    //= type=test
    //# The lateral error y MUST be the distance from the robot position to the
    //# closest point, positive when the robot is left of the path direction at
    //# that point and negative when it is right.
    //= spec/geometry.md#path-curvature-smoothed-curvature
    //= type=test
    //# For s in [0, L] the curvature MUST be c(s) = wrap(θ_Γ(b) − θ_Γ(a)) / (m(b) − m(a)),
    //# where [a, b] = [s − w/2, s + w/2] ∩ [0, L], θ_Γ is the smoothed heading and
    //# m(x) is the centre of the clipped window around x.
    #[test]
    fn mirror_symmetry(
        pts in smooth_path(), qx in -150.0..150.0_f64, qy in -150.0..150.0_f64,
        th in -PI..PI, look in -3.0..3.0_f64, w in 0.2..3.0_f64,
    ) {
        let p = path_w(&pts, w);
        let mirrored: Vec<_> = pts.iter().map(|p| p.mirrored()).collect();
        let pm = path_w(&mirrored, w);
        let e = p.project(&pose(qx, qy, th), m(look)).unwrap();
        let em = pm.project(&pose(qx, -qy, -th), m(look)).unwrap();
        let tol = 1e-9;
        prop_assert!((e.s.get() - em.s.get()).abs() < tol);
        prop_assert!((e.y.get() + em.y.get()).abs() < tol);
        prop_assert!(close_angle(e.angular_deviation.get(), -em.angular_deviation.get(), tol));
        prop_assert!((e.curvature.get() + em.curvature.get()).abs() < tol);
        prop_assert!((e.curvature_ahead.get() + em.curvature_ahead.get()).abs() < tol);
        prop_assert_eq!(e.position, em.position);
    }

    /// s, y, θ̃ and c do not change when path and pose move together rigidly.
    //= spec/geometry.md#frenet-closest-closest-point
    //= type=test
    //# `project` MUST return the abscissa s of a point of the extended path
    //# (the polyline and its two end extensions) closest to the robot position.
    //= spec/geometry.md#frenet-angular-angular-deviation
    //= type=test
    //# The angular deviation MUST be θ̃ = θ − θ_Γ(s), the robot heading minus
    //# the smoothed path heading at s, wrapped to (−π, π].
    #[test]
    fn rigid_motion_invariance(
        pts in smooth_path(), qx in -150.0..150.0_f64, qy in -150.0..150.0_f64,
        th in -PI..PI, look in -3.0..3.0_f64,
        tx in -1e3..1e3_f64, ty in -1e3..1e3_f64, rot in -PI..PI,
    ) {
        let motion = Transform2::<World, World>::new(tx, ty, rot).unwrap();
        let p = path(&pts);
        let moved: Vec<_> = pts.iter().map(|p| motion.apply(*p).unwrap()).collect();
        let pm = path(&moved);
        let q = pose(qx, qy, th);
        let e = p.project(&q, m(look)).unwrap();
        let em = pm.project(&motion.apply_pose(q).unwrap(), m(look)).unwrap();
        // Rounding of the moved coordinates (|.| ≲ 1.5e3) can move a near-tie
        // between two closest points; such cases are rare and skipped.
        let scale = 1e-9 * 2e3;
        if (e.s.get() - em.s.get()).abs() < 1e-6 {
            prop_assert!((e.y.get() - em.y.get()).abs() < 10.0 * scale);
            prop_assert!(close_angle(e.angular_deviation.get(), em.angular_deviation.get(), 1e-6));
            prop_assert!((e.curvature.get() - em.curvature.get()).abs() < 1e-5);
            prop_assert_eq!(e.position, em.position);
        } else {
            // Only a genuine tie can move s: both must be equally close.
            prop_assert!((e.y.get().abs() - em.y.get().abs()).abs() < 1e-6,
                "s {} vs {}, y {} vs {}", e.s.get(), em.s.get(), e.y.get(), em.y.get());
        }
    }

    /// The returned point is at least as close as every vertex and every sampled
    /// point of the path (an independent brute-force oracle).
    //= spec/geometry.md#frenet-closest-closest-point
    //= type=test
    //# `project` MUST return the abscissa s of a point of the extended path
    //# (the polyline and its two end extensions) closest to the robot position.
    #[test]
    fn projection_is_the_closest_point(
        pts in smooth_path(), qx in -150.0..150.0_f64, qy in -150.0..150.0_f64,
    ) {
        let p = path(&pts);
        let q = pose(qx, qy, 0.0);
        let e = p.project(&q, m(0.0)).unwrap();
        let foot = p.point_at(e.s).unwrap();
        let d = foot.distance_to(q.position).unwrap().get();
        prop_assert!((d - e.y.get().abs()).abs() < 1e-9 * (1.0 + d));
        let l = p.length().get();
        for i in 0..=400 {
            let s = -20.0 + (l + 40.0) * f64::from(i) / 400.0;
            let other = p.point_at(m(s)).unwrap();
            prop_assert!(d <= other.distance_to(q.position).unwrap().get() + 1e-9);
        }
        // The local search with a window covering everything agrees.
        let near = p.project_near(&q, m(0.0), m(0.5 * l), m(l + 1e6)).unwrap();
        prop_assert!((near.y.get().abs() - e.y.get().abs()).abs() < 1e-9);
    }

    /// The local search never leaves its window and is no farther than needed.
    //= spec/geometry.md#frenet-local-local-search
    //= type=test
    //# `project_near` MUST return the abscissa of a point closest to the robot
    //# among the points of the extended path whose abscissa lies in
    //# [s_hint − window, s_hint + window].
    #[test]
    fn local_search_stays_in_its_window(
        pts in smooth_path(), qx in -150.0..150.0_f64, qy in -150.0..150.0_f64,
        hint in -50.0..250.0_f64, window in 0.0..20.0_f64,
    ) {
        let p = path(&pts);
        let q = pose(qx, qy, 0.0);
        let e = p.project_near(&q, m(0.0), m(hint), m(window)).unwrap();
        let tol = 1e-9 * (1.0 + hint.abs() + window);
        prop_assert!(e.s.get() >= hint - window - tol && e.s.get() <= hint + window + tol);
        let d = e.y.get().abs();
        for i in 0..=100 {
            let s = hint - window + 2.0 * window * f64::from(i) / 100.0;
            let other = p.point_at(m(s)).unwrap();
            prop_assert!(d <= other.distance_to(q.position).unwrap().get() + 1e-9);
        }
    }

    /// Any f64, NaN and infinities included: a value or an error, never a panic
    /// or a non-finite field.
    #[test]
    fn any_input_gives_a_value_or_an_error(
        raw in prop::collection::vec((any::<f64>(), any::<f64>()), 0..12),
        qx in any::<f64>(), qy in any::<f64>(), th in any::<f64>(),
        look in any::<f64>(), hint in any::<f64>(), window in any::<f64>(), w in any::<f64>(),
    ) {
        let pts: Vec<_> = raw.iter().filter_map(|&(x, y)| Point2::<World>::new(x, y).ok()).collect();
        let Ok(w) = Meters::new(w) else { return Ok(()); };
        let Ok(p) = ReferencePath::<16>::from_waypoints(&pts, PathConfig { smoothing_window: w }) else {
            return Ok(());
        };
        prop_assert!(p.length().get().is_finite() && p.length().get() > 0.0);
        for v in p.vertices() {
            prop_assert!(v.heading.get().is_finite() && v.curvature.get().is_finite());
        }
        if let (Ok(q), Ok(look)) = (Pose2::<World>::new(qx, qy, th), Meters::new(look)) {
            if let Ok(e) = p.project(&q, look) {
                assert_finite(&e);
            }
            if let (Ok(hint), Ok(window)) = (Meters::new(hint), Meters::new(window)) {
                match p.project_near(&q, look, hint, window) {
                    Ok(e) => assert_finite(&e),
                    Err(err) => prop_assert!(
                        ["FRENET-LOCAL", "LIB-FINITE"].contains(&err.requirement)
                    ),
                }
                let _ = p.point_at(hint);
                prop_assert!(p.heading_at(hint).get().is_finite());
                prop_assert!(p.curvature_at(hint).get().is_finite());
            }
        }
    }

    /// Huge but finite coordinates: a value or an error, never a non-finite field.
    #[test]
    fn huge_coordinates_give_a_value_or_an_error(
        scale in prop::sample::select(vec![1e100, 1e154, 1e200, 1e300, f64::MAX]),
        a in -1.0..1.0_f64, b in -1.0..1.0_f64, c in -1.0..1.0_f64, d in -1.0..1.0_f64,
        qx in -1.0..1.0_f64, qy in -1.0..1.0_f64,
    ) {
        let pts = [pt(a * scale, b * scale), pt(c * scale, d * scale)];
        if let Ok(p) = ReferencePath::<4>::from_waypoints(&pts, PathConfig::default()) {
            if let Ok(e) = p.project(&pose(qx * scale, qy * scale, 0.0), m(1.0)) {
                assert_finite(&e);
            }
        }
    }
}
