//! Obstacles (`spec/emmi2024.md`, EM-OBST-*): clustering on exact synthetic
//! scans (ray-cast here), the two safety areas, the detour waypoint and its
//! Dubins legs checked against an independent footprint oracle, and the
//! hazard of hostile scenes (goal covered, walls on both sides, an obstacle
//! under the robot, spurious returns).
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::float_cmp,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::panic
)]

use core::f64::consts::{PI, TAU};

use fieldguide::perception::obstacles::{
    assess, cluster, AreaLength, Assessment, ClusterConfig, DetourPlan, Footprint, Hazard,
    Obstacle, ObstacleConfig, Obstacles, Reason,
};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::planning::dubins::{shortest, TurningRadius};
use fieldguide::{
    Meters, MetersPerSecond, Point2, Pose2, Robot, Seconds, Sensor, Transform2, World,
};
use proptest::prelude::*;

// ---------------------------------------------------------------- scenes

/// Rays of the synthetic LiDAR: 0.25° apart over the whole turn.
const RAYS: usize = 1440;
const MAX_RANGE: f64 = 30.0;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn pt(x: f64, y: f64) -> Point2<Robot> {
    Point2::new(x, y).unwrap()
}

fn circle(x: f64, y: f64, r: f64) -> Obstacle {
    Obstacle::Circle {
        centre: pt(x, y),
        radius: m(r),
    }
}

fn segment(a: (f64, f64), b: (f64, f64)) -> Obstacle {
    Obstacle::Segment {
        start: pt(a.0, a.1),
        end: pt(b.0, b.1),
    }
}

fn identity() -> Transform2<Sensor, Robot> {
    Transform2::new(0.0, 0.0, 0.0).unwrap()
}

fn limits() -> RangeLimits {
    RangeLimits::new(m(0.05), m(MAX_RANGE)).unwrap()
}

/// Distance along the ray of direction `d` from the origin to the shape, if hit.
fn hit(shape: &Obstacle, d: (f64, f64)) -> Option<f64> {
    match *shape {
        Obstacle::Circle { centre, radius } => {
            let (cx, cy, r) = (centre.x(), centre.y(), radius.get());
            let b = d.0 * cx + d.1 * cy;
            let disc = b * b - (cx * cx + cy * cy - r * r);
            (disc >= 0.0 && b - disc.sqrt() > 0.0).then(|| b - disc.sqrt())
        }
        Obstacle::Segment { start, end } => {
            let (ax, ay, ex, ey) = (
                start.x(),
                start.y(),
                end.x() - start.x(),
                end.y() - start.y(),
            );
            let den = d.0 * ey - d.1 * ex;
            if den.abs() < 1e-15 {
                return None;
            }
            let t = (ax * ey - ay * ex) / den;
            let u = (ax * d.1 - ay * d.0) / den;
            (t > 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
        }
    }
}

/// Exact ranges of `shapes` seen from the robot origin (infinity: no return).
fn ray_cast(shapes: &[Obstacle]) -> Vec<f64> {
    (0..RAYS)
        .map(|k| {
            let a = -PI + TAU * k as f64 / RAYS as f64;
            shapes
                .iter()
                .filter_map(|s| hit(s, (a.cos(), a.sin())))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

fn scan(ranges: &[f64]) -> Scan<'_> {
    Scan {
        start: fieldguide::Radians::new(-PI).unwrap(),
        increment: fieldguide::Radians::new(TAU / RAYS as f64).unwrap(),
        ranges,
        limits: limits(),
    }
}

fn found<const N: usize>(shapes: &[Obstacle]) -> Obstacles<N> {
    let ranges = ray_cast(shapes);
    cluster::<N>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024())
}

// ---------------------------------------------------------------- clustering

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    //= spec/emmi2024.md#em-obst-shape-circles-and-segments
    //= type=test
    //# A cluster whose points all lie within a circle of at most the largest
    //# circle radius MUST become such a circle, enclosing every point of the
    //# cluster.
    #[test]
    fn a_post_is_a_circle_of_its_radius(
        d in 1.5..8.0_f64, bearing in -2.5..2.5_f64, r in 0.08..0.4_f64,
    ) {
        let (x, y) = (d * bearing.cos(), d * bearing.sin());
        let obs = found::<8>(&[circle(x, y, r)]);
        prop_assert_eq!(obs.as_slice().len(), 1);
        let Obstacle::Circle { centre, radius } = obs.as_slice()[0] else {
            panic!("a post gave {:?}", obs.as_slice());
        };
        prop_assert!((radius.get() - r).abs() < 1e-6, "radius {} for {r}", radius.get());
        prop_assert!(centre.distance_to(pt(x, y)).unwrap().get() < 1e-6);
        prop_assert_eq!(obs.spurious(), 0);
    }

    //= spec/emmi2024.md#em-obst-shape-circles-and-segments
    //= type=test
    //# Any other cluster MUST be split at its point farthest from the chord
    //# joining its first and last points until no point of a part is farther
    //# than the split tolerance from the part's chord; each such part MUST
    //# become the segment of its chord.
    #[test]
    fn a_wall_is_a_segment_on_it(
        d in 2.0..8.0_f64, tilt in -0.6..0.6_f64, half in 1.0..4.0_f64,
    ) {
        // A wall d ahead, tilted, `2 half` long, centred on the x axis.
        let (ux, uy) = (tilt.sin(), tilt.cos());
        let a = (d - half * ux, -half * uy);
        let b = (d + half * ux, half * uy);
        let obs = found::<8>(&[segment(a, b)]);
        prop_assert_eq!(obs.as_slice().len(), 1);
        let Obstacle::Segment { start, end } = obs.as_slice()[0] else {
            panic!("a wall gave {:?}", obs.as_slice());
        };
        // Both ends on the wall's line and within two rays' spacing of its ends.
        let on_line = |p: Point2<Robot>| ((p.x() - a.0) * uy - (p.y() - a.1) * ux).abs();
        prop_assert!(on_line(start) < 1e-9 && on_line(end) < 1e-9);
        let ends = [start, end];
        for e in [a, b] {
            // Two rays' spacing along the wall at that end's incidence.
            let dist = e.0.hypot(e.1);
            let incidence = (e.0 * uy - e.1 * ux).abs() / dist;
            let spacing = 2.0 * dist * (TAU / RAYS as f64) / incidence;
            let near = ends.iter().map(|p| p.distance_to(pt(e.0, e.1)).unwrap().get()).fold(f64::INFINITY, f64::min);
            prop_assert!(near < spacing, "end {e:?} missed by {near}");
        }
    }
}

//= spec/emmi2024.md#em-obst-shape-circles-and-segments
//= type=test
//# Any other cluster MUST be split at its point farthest from the chord
//# joining its first and last points until no point of a part is farther
//# than the split tolerance from the part's chord; each such part MUST
//# become the segment of its chord.
#[test]
fn a_corner_is_two_segments_meeting_at_it() {
    let corner = (4.0, 0.5);
    let obs = found::<8>(&[segment((4.0, -3.0), corner), segment(corner, (1.5, 3.0))]);
    let segments: Vec<_> = obs
        .as_slice()
        .iter()
        .filter_map(|o| match o {
            Obstacle::Segment { start, end } => Some((*start, *end)),
            Obstacle::Circle { .. } => None,
        })
        .collect();
    assert_eq!(segments.len(), 2, "{:?}", obs.as_slice());
    for (s, e) in segments {
        let to_corner = s
            .distance_to(pt(corner.0, corner.1))
            .unwrap()
            .get()
            .min(e.distance_to(pt(corner.0, corner.1)).unwrap().get());
        assert!(to_corner < 0.05, "no end at the corner: {s:?} {e:?}");
    }
}

//= spec/emmi2024.md#em-obst-cluster-clusters-of-scan-points
//= type=test
//# Two consecutive valid points of the scan (invalid rays between them
//# skipped) MUST belong to one cluster when they are at most the gap apart,
//# and to two otherwise.
#[test]
fn two_posts_apart_are_two_circles_and_close_ones_one_cluster() {
    let obs = found::<8>(&[circle(4.0, -1.0, 0.2), circle(4.0, 1.0, 0.2)]);
    assert_eq!(obs.as_slice().len(), 2);
    assert!(obs.as_slice().iter().all(
        |o| matches!(o, Obstacle::Circle { radius, .. } if (radius.get() - 0.2).abs() < 1e-6)
    ));
    // 0.1 m apart (below the 0.2 m gap): one cluster, which covers both.
    let obs = found::<8>(&[circle(4.0, -0.15, 0.1), circle(4.0, 0.15, 0.1)]);
    assert_eq!(obs.as_slice().len(), 1, "{:?}", obs.as_slice());
    // A dropout in the middle of a post (invalid rays) does not split it.
    let mut ranges = ray_cast(&[circle(4.0, 0.0, 0.3)]);
    let mid = RAYS / 2;
    for r in &mut ranges[mid - 1..=mid + 1] {
        *r = f64::NAN;
    }
    let obs = cluster::<8>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
    assert_eq!(obs.as_slice().len(), 1);
}

//= spec/emmi2024.md#em-obst-cluster-clusters-of-scan-points
//= type=test
//# A cluster of fewer points than the least number MUST be dropped as
//# spurious and counted.
#[test]
fn spurious_single_returns_are_dropped_and_counted() {
    let post = circle(5.0, 0.5, 0.25);
    let clean = found::<8>(&[post]);
    for seed in 0..20_u64 {
        let mut ranges = ray_cast(&[post]);
        // Isolated returns (one or two rays) on rays that see nothing.
        let mut placed = 0;
        let mut k = (seed as usize * 37) % 90;
        while k + 2 < RAYS {
            if ranges[k].is_infinite()
                && ranges[k + 1].is_infinite()
                && (k == 0 || ranges[k - 1].is_infinite())
            {
                ranges[k] = 1.0 + (k % 7) as f64;
                if seed % 2 == 0 {
                    ranges[k + 1] = ranges[k];
                }
                placed += 1;
            }
            k += 60 + (seed as usize % 11);
        }
        let obs = cluster::<8>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
        assert_eq!(obs.as_slice(), clean.as_slice(), "seed {seed}");
        assert_eq!(obs.spurious(), placed, "seed {seed}");
    }
}

//= spec/emmi2024.md#em-obst-capacity-a-bounded-list-of-obstacles
//= type=test
//# When more obstacles are found than the list holds, the list MUST keep
//# those nearest to the robot frame's origin and MUST report the least
//# distance of a dropped one.
#[test]
fn a_full_list_keeps_the_nearest() {
    // Twelve posts on a spiral, distances 2 to 7.5 m.
    let posts: Vec<Obstacle> = (0..12)
        .map(|i| {
            let (d, a) = (2.0 + 0.5 * i as f64, -2.5 + 0.45 * i as f64);
            circle(d * a.cos(), d * a.sin(), 0.15)
        })
        .collect();
    let obs = found::<4>(&posts);
    let dist = |o: &Obstacle| match o {
        Obstacle::Circle { centre, radius } => {
            centre.distance_to(Point2::origin()).unwrap().get() - radius.get()
        }
        Obstacle::Segment { .. } => panic!("a post became a segment"),
    };
    let mut kept: Vec<f64> = obs.as_slice().iter().map(dist).collect();
    kept.sort_by(f64::total_cmp);
    let expected = [1.85, 2.35, 2.85, 3.35];
    assert_eq!(kept.len(), 4);
    for (k, e) in kept.iter().zip(expected) {
        assert!((k - e).abs() < 1e-6, "kept {kept:?}");
    }
    assert!((obs.nearest_dropped().unwrap().get() - 3.85).abs() < 1e-6);
    // Inserted by hand, in any order, the same.
    let mut by_hand = Obstacles::<4>::new();
    for p in posts.iter().rev() {
        by_hand.insert(*p);
    }
    let mut again: Vec<f64> = by_hand.as_slice().iter().map(dist).collect();
    again.sort_by(f64::total_cmp);
    for (a, k) in again.iter().zip(&kept) {
        assert!((a - k).abs() < 1e-6, "{again:?} vs {kept:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Any 10 000 ranges, NaN and infinities included, with any increment:
    /// a bounded list of finite obstacles, never a panic.
    //= spec/emmi2024.md#em-obst-capacity-a-bounded-list-of-obstacles
    //= type=test
    //# When more obstacles are found than the list holds, the list MUST keep
    //# those nearest to the robot frame's origin and MUST report the least
    //# distance of a dropped one.
    #[test]
    fn any_long_scan_gives_a_bounded_finite_list(
        ranges in prop::collection::vec(prop_oneof![
            4 => 0.0..40.0_f64,
            1 => prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1.0, 1e300]),
        ], 10_000),
        increment in prop_oneof![Just(TAU / 10_000.0), -1.0..1.0_f64, Just(1e300)],
    ) {
        let s = Scan {
            start: fieldguide::Radians::new(-PI).unwrap(),
            increment: fieldguide::Radians::new(increment).unwrap(),
            ranges: &ranges,
            limits: limits(),
        };
        let obs = cluster::<16>(&s, &identity(), &ClusterConfig::emmi2024());
        prop_assert!(obs.as_slice().len() <= 16);
        let text = format!("{obs:?}");
        prop_assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    }
}

//= spec/emmi2024.md#em-obst-cluster-clusters-of-scan-points
//= type=test
//# The gap, the largest circle radius and the split tolerance MUST lie in
//# (0, 1e3] m and the least number of points in a cluster MUST be at least
//# 2; other values MUST be refused with the `EM-OBST-CLUSTER` error.
#[test]
fn cluster_configurations_out_of_range_are_refused() {
    let ok = ClusterConfig::new(m(0.2), 3, m(0.5), m(0.1));
    assert_eq!(ok.unwrap(), ClusterConfig::emmi2024());
    for (gap, n, r, tol) in [
        (0.0, 3, 0.5, 0.1),
        (0.2, 1, 0.5, 0.1),
        (0.2, 3, -0.5, 0.1),
        (0.2, 3, 0.5, 2e3),
    ] {
        let e = ClusterConfig::new(m(gap), n, m(r), m(tol)).unwrap_err();
        assert_eq!(e.requirement, "EM-OBST-CLUSTER");
    }
}

// ---------------------------------------------------------------- areas

fn radius(r: f64) -> TurningRadius {
    TurningRadius::new(m(r)).unwrap()
}

fn config() -> ObstacleConfig {
    ObstacleConfig::emmi2024(radius(1.0))
}

fn speed(v: f64) -> MetersPerSecond {
    MetersPerSecond::new(v).unwrap()
}

/// Independent oracle: distance from a circle to the box x ∈ [x0, x1], |y| ≤ w.
fn circle_box(c: (f64, f64), r: f64, x0: f64, x1: f64, w: f64) -> f64 {
    let dx = (x0 - c.0).max(c.0 - x1).max(0.0);
    let dy = (c.1.abs() - w).max(0.0);
    (dx.hypot(dy) - r).max(0.0)
}

//= spec/emmi2024.md#em-obst-config-footprint-margin-and-areas
//= type=test
//# The footprint's front and rear distances MUST lie in [0, 1e3] m with
//# a positive sum, and its width in (0, 1e3] m; other values MUST be
//# refused with the `EM-OBST-CONFIG` error.
//= spec/emmi2024.md#em-obst-config-footprint-margin-and-areas
//= type=test
//# An area's base length MUST lie in [0, 1e3] m and its gain in
//# [0, 100] s; other values MUST be refused with the `EM-OBST-CONFIG`
//# error.
//= spec/emmi2024.md#em-obst-config-footprint-margin-and-areas
//= type=test
//# The safety margin MUST lie in [0, 1e3] m and the step of the clearance
//# checks in [1e−3, 1] m; other values MUST be refused with the
//# `EM-OBST-CONFIG` error.
#[test]
fn configurations_out_of_range_are_refused() {
    let fp = Footprint::new(m(0.75), m(0.75), m(1.76)).unwrap();
    let len = |b: f64, g: f64| AreaLength::new(m(b), Seconds::new(g).unwrap());
    let same = ObstacleConfig::new(
        fp,
        m(0.3),
        len(0.5, 1.0).unwrap(),
        len(2.0, 3.0).unwrap(),
        radius(1.0),
        m(0.02),
    )
    .unwrap();
    assert_eq!(same, config());
    let errors = [
        Footprint::new(m(-0.1), m(0.75), m(1.76)).map(|_| ()),
        Footprint::new(m(0.0), m(0.0), m(1.76)).map(|_| ()),
        Footprint::new(m(0.75), m(0.75), m(0.0)).map(|_| ()),
        Footprint::new(m(0.75), m(2e3), m(1.0)).map(|_| ()),
        len(-1.0, 1.0).map(|_| ()),
        len(1.0, 101.0).map(|_| ()),
        ObstacleConfig::new(
            fp,
            m(-0.1),
            len(0.5, 1.0).unwrap(),
            len(2.0, 3.0).unwrap(),
            radius(1.0),
            m(0.02),
        )
        .map(|_| ()),
        ObstacleConfig::new(
            fp,
            m(0.3),
            len(0.5, 1.0).unwrap(),
            len(2.0, 3.0).unwrap(),
            radius(1.0),
            m(0.0),
        )
        .map(|_| ()),
        ObstacleConfig::new(
            fp,
            m(0.3),
            len(0.5, 1.0).unwrap(),
            len(2.0, 3.0).unwrap(),
            radius(1.0),
            m(1.5),
        )
        .map(|_| ()),
    ];
    for e in errors {
        assert_eq!(e.unwrap_err().requirement, "EM-OBST-CONFIG");
    }
    for v in [-0.1, 100.5] {
        assert_eq!(
            config().areas(speed(v)).unwrap_err().requirement,
            "EM-OBST-AREAS"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    //= spec/emmi2024.md#em-obst-areas-the-critical-and-the-warning-area
    //= type=test
    //# At nominal speed v, the critical area MUST be the rectangle of the
    //# robot frame x ∈ [−rear, front + L_c(v)], |y| ≤ width/2 + margin, and
    //# the warning area the rectangle x ∈ [front + L_c(v), front + L_c(v) +
    //# L_w(v)] of the same width, with L(v) = base + gain · v for each area.
    //= spec/emmi2024.md#em-obst-areas-the-critical-and-the-warning-area
    //= type=test
    //# An obstacle MUST be in an area when the closed rectangle and the
    //# obstacle's circle or segment have a point in common.
    #[test]
    fn areas_grow_with_speed_and_match_the_oracle(
        v in 0.0..1.67_f64, dv in 0.0..1.0_f64,
        x in -2.0..10.0_f64, y in -3.0..3.0_f64, r in 0.0..0.5_f64,
    ) {
        let (slow, fast) = (config().areas(speed(v)).unwrap(), config().areas(speed(v + dv)).unwrap());
        prop_assert!(fast.critical_end().get() >= slow.critical_end().get());
        prop_assert!(fast.warning_end().get() >= slow.warning_end().get());
        prop_assert!((slow.critical_end().get() - (0.75 + 0.5 + v)).abs() < 1e-12);
        prop_assert!((slow.warning_end().get() - (0.75 + 0.5 + v + 2.0 + 3.0 * v)).abs() < 1e-12);
        let w = 0.88 + 0.3;
        let c = circle(x, y, r);
        let (ce, we) = (slow.critical_end().get(), slow.warning_end().get());
        prop_assert_eq!(slow.in_critical(&c), circle_box((x, y), r, -0.75, ce, w) == 0.0);
        prop_assert_eq!(slow.in_warning(&c), circle_box((x, y), r, ce, we, w) == 0.0);
        // Mirror symmetry.
        let mirrored = circle(x, -y, r);
        prop_assert_eq!(slow.in_critical(&c), slow.in_critical(&mirrored));
        prop_assert_eq!(slow.in_warning(&c), slow.in_warning(&mirrored));
        // A segment meets an area when a point of it, sampled finely, does.
        let s = segment((x, y), (x + 2.0 * r - 0.5, y - 3.0 * r + 0.7));
        let Obstacle::Segment { start, end } = s else { unreachable!() };
        let sampled = (0..=4000).any(|i| {
            let t = f64::from(i) / 4000.0;
            let p = (start.x() + t * (end.x() - start.x()), start.y() + t * (end.y() - start.y()));
            circle_box(p, 0.0, ce, we, w) == 0.0
        });
        if sampled {
            prop_assert!(slow.in_warning(&s));
        }
        let len = start.distance_to(end).unwrap().get();
        let near = (0..=4000).map(|i| {
            let t = f64::from(i) / 4000.0;
            circle_box((start.x() + t * (end.x() - start.x()), start.y() + t * (end.y() - start.y())), 0.0, ce, we, w)
        }).fold(f64::INFINITY, f64::min);
        if near > len / 4000.0 {
            prop_assert!(!slow.in_warning(&s));
        }
    }
}

// ---------------------------------------------------------------- hazard and detour

/// The distance between the footprint at `pose` (world) and an obstacle of
/// the robot frame at `seen_from`, by an oracle independent of the core:
/// segments are sampled every millimetre.
fn footprint_distance(pose: &Pose2<World>, seen_from: &Pose2<World>, o: &Obstacle) -> f64 {
    let to_world = |p: Point2<Robot>| {
        let (c, s) = (seen_from.heading.get().cos(), seen_from.heading.get().sin());
        (
            seen_from.position.x() + c * p.x() - s * p.y(),
            seen_from.position.y() + s * p.x() + c * p.y(),
        )
    };
    let to_body = |p: (f64, f64)| {
        let (c, s) = (pose.heading.get().cos(), pose.heading.get().sin());
        let (dx, dy) = (p.0 - pose.position.x(), p.1 - pose.position.y());
        (c * dx + s * dy, -s * dx + c * dy)
    };
    match *o {
        Obstacle::Circle { centre, radius } => {
            circle_box(to_body(to_world(centre)), radius.get(), -0.75, 0.75, 0.88)
        }
        Obstacle::Segment { start, end } => {
            let (a, b) = (to_body(to_world(start)), to_body(to_world(end)));
            let n = ((b.0 - a.0).hypot(b.1 - a.1) / 1e-3).ceil().max(1.0) as usize;
            (0..=n)
                .map(|i| {
                    let t = i as f64 / n as f64;
                    circle_box(
                        (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)),
                        0.0,
                        -0.75,
                        0.75,
                        0.88,
                    )
                })
                .fold(f64::INFINITY, f64::min)
        }
    }
}

/// The least footprint distance to `obstacles` along the two legs
/// `pose → waypoint → goal`, sampled every 5 mm.
fn legs_clearance(
    pose: &Pose2<World>,
    waypoint: &Pose2<World>,
    goal: &Pose2<World>,
    obstacles: &[Obstacle],
) -> f64 {
    let mut least = f64::INFINITY;
    for (a, b) in [(pose, waypoint), (waypoint, goal)] {
        let leg = shortest(a, b, radius(1.0)).unwrap();
        let n = (leg.length().get() / 5e-3).ceil() as usize;
        for i in 0..=n {
            let p = leg
                .pose_at(m(leg.length().get() * i as f64 / n.max(1) as f64))
                .unwrap();
            for o in obstacles {
                least = least.min(footprint_distance(&p, pose, o));
            }
        }
    }
    least
}

fn world(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

fn list(obstacles: &[Obstacle]) -> Obstacles<16> {
    let mut out = Obstacles::new();
    for o in obstacles {
        out.insert(*o);
    }
    out
}

fn run(
    obstacles: &[Obstacle],
    pose: &Pose2<World>,
    goal: &Pose2<World>,
    in_field: bool,
) -> Assessment {
    assess(
        &list(obstacles),
        pose,
        goal,
        speed(0.5),
        in_field,
        &config(),
    )
    .unwrap()
}

fn waypoint_of(a: &Assessment) -> Pose2<World> {
    match a.hazard {
        Hazard::Warning { detour: Some(w) } => w,
        _ => panic!("no detour: {a:?}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    //= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
    //= type=test
    //# The waypoint of a circle of radius ρ MUST lie beside its centre, at
    //# ρ + width/2 + margin + k · step (plus, in turn, 0, 0.125, 0.25, 0.375,
    //# 0.5, 1 and 2 times width/2 + margin) to the left or the right of the
    //# planned path's heading
    //# where the path passes nearest to the centre, with that heading.
    //= spec/emmi2024.md#em-obst-clear-clear-legs
    //= type=test
    //# A path MUST be clear only when, at samples s_0 = 0 < s_1 < … ending at
    //# the checked length, the footprint's clearance c_i to every obstacle
    //# satisfies c_i ≥ margin + k · step and s_{i+1} − s_i ≤ (c_i − margin) / k,
    //# with k = 1 + ρ/r, ρ the footprint's largest distance from its origin and
    //# r the turning radius.
    //= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
    //= type=test
    //# Otherwise, an obstacle in the warning area on which the footprint moving
    //# along the planned path up to the warning area's far edge is not clear
    //# (EM-OBST-CLEAR) MUST give `Warning`; without such an obstacle the hazard
    //# MUST be `Clear`.
    #[test]
    fn a_post_on_the_path_is_passed_with_the_margin(
        x in 2.3..5.0_f64, y in -0.8..0.8_f64, r in 0.05..0.5_f64,
        px in -20.0..20.0_f64, py in -20.0..20.0_f64, h in -PI..PI,
    ) {
        let pose = world(px, py, h);
        let goal = world(px + 30.0 * h.cos(), py + 30.0 * h.sin(), h);
        let post = circle(x, y, r);
        let a = run(&[post], &pose, &goal, false);
        // Seen as it enters the warning area, a post is always passed; seen
        // late, the robot may have no room to swerve and stops instead.
        if x - r >= 3.5 {
            prop_assert_eq!(a.reason, Reason::Detour, "{:?}", a);
        }
        if a.reason != Reason::Detour {
            prop_assert_eq!(a.reason, Reason::NoClearSide);
            prop_assert!(a.stops());
            return Ok(());
        }
        let w = waypoint_of(&a);
        // Beside the post, on the side away from it, with the path's heading.
        let k = 1.0 + 0.75_f64.hypot(0.88);
        let base = r + 0.88 + 0.3 + k * 0.02;
        let (c, s) = (h.cos(), h.sin());
        let centre = (px + c * x - s * y, py + s * x + c * y);
        let lateral = -s * (w.position.x() - centre.0) + c * (w.position.y() - centre.1);
        let along = c * (w.position.x() - centre.0) + s * (w.position.y() - centre.1);
        prop_assert!(along.abs() < 1e-6, "waypoint {along} m along");
        prop_assert!([0.0, 0.125, 0.25, 0.375, 0.5, 1.0, 2.0].iter().any(|e| (lateral.abs() - base - e * 1.18).abs() < 1e-6), "lateral {lateral}");
        prop_assert!((w.heading.get() - h).rem_euclid(TAU).min((h - w.heading.get()).rem_euclid(TAU)) < 1e-9);
        prop_assert!(footprint_distance(&w, &pose, &post) >= 0.3 - 1e-9);
        prop_assert!(legs_clearance(&pose, &w, &goal, &[post]) >= 0.3 - 1e-9);
    }
}

//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//= type=test
//# Among the candidate waypoints whose two legs are clear, the one of least
//# total length start → waypoint → goal MUST be chosen.
#[test]
fn a_post_left_of_the_path_is_passed_on_the_right_and_mirrors() {
    let (pose, goal) = (world(0.0, 0.0, 0.0), world(30.0, 0.0, 0.0));
    for y in [0.1, 0.3, 0.6] {
        let a = run(&[circle(4.0, y, 0.2)], &pose, &goal, false);
        let w = waypoint_of(&a);
        assert!(w.position.y() < 0.0, "post at y = {y}: {w:?}");
        let b = run(&[circle(4.0, -y, 0.2)], &pose, &goal, false);
        let v = waypoint_of(&b);
        assert!((v.position.x() - w.position.x()).abs() < 1e-9);
        assert!((v.position.y() + w.position.y()).abs() < 1e-9);
        assert!((v.heading.get() + w.heading.get()).abs() < 1e-9);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Moving the robot and its goal rigidly moves the detour the same way.
    //= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
    //= type=test
    //# The waypoint of a segment MUST lie beyond one of its ends, along the
    //# segment, or beside one of its ends, to the left or the right of the
    //# planned path's heading, at width/2 + margin + k · step (plus the same
    //# extra offsets) from that end, with the planned path's heading where it
    //# passes nearest to the segment's midpoint.
    #[test]
    fn a_wall_across_the_path_is_rounded_at_an_end_and_moves_rigidly(
        x in 3.0..4.5_f64, left in 0.2..1.5_f64, right in 0.2..1.5_f64,
        px in -50.0..50.0_f64, py in -50.0..50.0_f64, h in -PI..PI,
    ) {
        let wall = segment((x, -right), (x, left));
        let base = run(&[wall], &world(0.0, 0.0, 0.0), &world(30.0, 0.0, 0.0), false);
        let w = waypoint_of(&base);
        // On the wall's line (along it, or across the path from an end:
        // the same line here), at the offsets from one end, and past the
        // end it goes round by at least the first offset.
        let k = 1.0 + 0.75_f64.hypot(0.88);
        let off = 0.88 + 0.3 + k * 0.02;
        prop_assert!((w.position.x() - x).abs() < 1e-9);
        let from_an_end = [left, -right].iter().any(|end| {
            [0.0, 0.125, 0.25, 0.375, 0.5, 1.0, 2.0].iter().any(|e| ((w.position.y() - end).abs() - off - e * 1.18).abs() < 1e-6)
        });
        prop_assert!(from_an_end, "{w:?}");
        let beyond = if w.position.y() > 0.0 { w.position.y() - left } else { -right - w.position.y() };
        prop_assert!(beyond >= off - 1e-9, "beyond {beyond}");
        prop_assert!(legs_clearance(&world(0.0, 0.0, 0.0), &w, &world(30.0, 0.0, 0.0), &[wall]) >= 0.3 - 1e-9);
        // The shorter end when the wall is clearly lopsided.
        if (left - right).abs() > 0.3 {
            prop_assert_eq!(w.position.y() > 0.0, left < right);
        }
        let (c, s) = (h.cos(), h.sin());
        let moved = |p: &Pose2<World>| world(px + c * p.position.x() - s * p.position.y(), py + s * p.position.x() + c * p.position.y(), p.heading.get() + h);
        let a = run(&[wall], &moved(&world(0.0, 0.0, 0.0)), &moved(&world(30.0, 0.0, 0.0)), false);
        let v = waypoint_of(&a);
        let expected = moved(&w);
        prop_assert!(v.position.distance_to(expected.position).unwrap().get() < 1e-6, "{v:?} vs {expected:?}");
    }
}

//= spec/emmi2024.md#em-obst-no-detour-no-way-round
//= type=test
//# When the footprint at the goal is less than margin + k · step from an
//# obstacle, re-planning MUST report that the goal is blocked.
#[test]
fn an_obstacle_covering_the_goal_stops_the_robot() {
    let pose = world(0.0, 0.0, 0.0);
    for (gx, o) in [
        (4.0, circle(4.0, 0.0, 0.3)),
        (4.5, segment((4.0, -0.5), (4.0, 0.5))),
        (4.0, circle(4.0, 0.9, 0.2)),
    ] {
        let a = run(&[o], &pose, &world(gx, 0.0, 0.0), false);
        assert_eq!(a.hazard, Hazard::Warning { detour: None });
        assert_eq!(a.reason, Reason::GoalBlocked);
        assert!(a.stops());
    }
}

//= spec/emmi2024.md#em-obst-no-detour-no-way-round
//= type=test
//# When no candidate waypoint qualifies, re-planning MUST report that no
//# side is clear.
#[test]
fn walls_on_both_sides_leave_no_detour() {
    let pose = world(0.0, 0.0, 0.0);
    let goal = world(30.0, 0.0, 0.0);
    for gap in [1.3, 1.6, 2.0] {
        let walls = [
            segment((-1.0, gap), (20.0, gap)),
            segment((-1.0, -gap), (20.0, -gap)),
            circle(4.0, 0.1, 0.25),
        ];
        let a = run(&walls, &pose, &goal, false);
        assert_eq!(a.hazard, Hazard::Warning { detour: None }, "gap {gap}");
        assert_eq!(a.reason, Reason::NoClearSide);
        // Without the walls there is a way round.
        assert_eq!(run(&walls[2..], &pose, &goal, false).reason, Reason::Detour);
    }
    // Posts all round the robot at the edge of the areas: no way out either.
    let ring: Vec<Obstacle> = (0..12)
        .map(|i| {
            let a = TAU * f64::from(i) / 12.0;
            circle(3.0 * a.cos(), 3.0 * a.sin(), 0.4)
        })
        .filter(|o| !config().areas(speed(0.5)).unwrap().in_critical(o))
        .collect();
    let a = run(&ring, &pose, &goal, false);
    assert!(a.stops(), "{a:?}");
}

//= spec/emmi2024.md#em-obst-field-no-re-planning-in-a-crop-field
//= type=test
//# Inside a crop field, a `Warning` MUST carry no detour, with the reason
//# `InCropField`, so that the robot stops instead of crossing the crop.
#[test]
fn inside_a_crop_field_there_is_no_detour() {
    let (pose, goal) = (world(2.0, -1.0, 0.3), world(30.0, 7.0, 0.3));
    for o in [circle(4.0, 0.2, 0.2), segment((3.5, -1.0), (3.5, 1.0))] {
        assert_eq!(run(&[o], &pose, &goal, false).reason, Reason::Detour);
        let a = run(&[o], &pose, &goal, true);
        assert_eq!(a.hazard, Hazard::Warning { detour: None });
        assert_eq!(a.reason, Reason::InCropField);
    }
}

//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//= type=test
//# An obstacle in the critical area MUST give `Critical`, whatever the other
//# obstacles, unless the footprint moving along the planned path for the
//# critical area's length L_c(v) is clear of it (EM-OBST-CLEAR).
#[test]
fn an_obstacle_in_the_critical_area_or_under_the_robot_stops_it() {
    let (pose, goal) = (world(0.0, 0.0, 0.0), world(30.0, 0.0, 0.0));
    for o in [
        circle(0.0, 0.0, 0.1),
        circle(-0.7, 0.8, 0.05),
        circle(1.5, 0.5, 0.1),
        segment((1.0, -3.0), (1.0, 3.0)),
    ] {
        for in_field in [false, true] {
            let a = run(&[circle(4.0, 0.0, 0.2), o], &pose, &goal, in_field);
            assert_eq!(a.hazard, Hazard::Critical, "{o:?}");
            assert_eq!(a.reason, Reason::CriticalArea);
        }
    }
    // A post in the critical area's front right corner, outside a path
    // turning left at once (radius 1 m): the footprint swept along the path
    // for L_c = 1 m is clear of it, so it is not critical; on a straight
    // path it is.
    let corner = circle(1.65, -1.1, 0.05);
    let left = world(1.0, 3.0, PI / 2.0);
    let a = run(&[corner], &pose, &left, false);
    assert_ne!(a.hazard, Hazard::Critical, "{a:?}");
    assert_eq!(run(&[corner], &pose, &goal, false).hazard, Hazard::Critical);
    // Nothing ahead: clear.
    assert_eq!(run(&[], &pose, &goal, false).reason, Reason::NoObstacle);
    assert_eq!(
        run(
            &[circle(-3.0, 0.0, 0.2), circle(2.0, 4.0, 0.3)],
            &pose,
            &goal,
            false
        )
        .hazard,
        Hazard::Clear
    );
}

//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//= type=test
//# The detour of a `Warning` MUST be the waypoint of EM-OBST-DETOUR round the
//# obstacle of the path nearest to the robot, or `None` with the reason when
//# there is none.
#[test]
fn an_obstacle_off_a_turning_path_is_clear_and_the_nearest_is_rounded() {
    // The path turns left at once; a post on the right of the warning area is off it.
    let pose = world(0.0, 0.0, 0.0);
    let a = run(
        &[circle(4.5, -1.0, 0.1)],
        &pose,
        &world(2.0, 6.0, PI / 2.0),
        false,
    );
    assert_eq!(a.hazard, Hazard::Clear, "{a:?}");
    assert_eq!(a.reason, Reason::OffPath);
    // Two posts on a straight path: the detour goes round the nearer one.
    let goal = world(30.0, 0.0, 0.0);
    let (near, far) = (circle(2.5, 0.3, 0.2), circle(5.0, -0.3, 0.2));
    let w = waypoint_of(&run(&[far, near], &pose, &goal, false));
    assert!((w.position.x() - 2.5).abs() < 1e-9, "{w:?}");
}

//= spec/emmi2024.md#em-obst-unseen-obstacles-left-out
//= type=test
//# When the list of obstacles dropped one whose distance from the robot
//# is not beyond the farthest point of the areas, the hazard MUST be
//# `Critical`.
#[test]
fn obstacles_left_out_near_the_robot_stop_it() {
    let (pose, goal) = (world(0.0, 0.0, 0.0), world(30.0, 0.0, 0.0));
    let mut few = Obstacles::<2>::new();
    for o in [
        circle(-3.0, 3.0, 0.1),
        circle(-3.0, -3.0, 0.1),
        circle(-3.5, 0.0, 0.1),
    ] {
        few.insert(o);
    }
    let a = assess(&few, &pose, &goal, speed(0.5), false, &config()).unwrap();
    assert_eq!((a.hazard, a.reason), (Hazard::Critical, Reason::Unseen));
    // Dropped beyond the areas' reach (about 5.4 m): no stop.
    let mut far = Obstacles::<2>::new();
    for o in [
        circle(-3.0, 3.0, 0.1),
        circle(-3.0, -3.0, 0.1),
        circle(-20.0, 0.0, 0.1),
    ] {
        far.insert(o);
    }
    let a = assess(&far, &pose, &goal, speed(0.5), false, &config()).unwrap();
    assert_eq!((a.hazard, a.reason), (Hazard::Clear, Reason::NoObstacle));
}

/// A burst of spurious returns: isolated ones are dropped, a dense burst in
/// front of the robot is an obstacle and stops it; both with a named reason.
#[test]
fn a_burst_of_spurious_points_gives_a_defined_outcome() {
    let (pose, goal) = (world(0.0, 0.0, 0.0), world(30.0, 0.0, 0.0));
    let mut ranges = vec![f64::INFINITY; RAYS];
    // Every 9th ray ahead returns, at ranges 1 to 2.5 m in turn: single
    // returns at least 0.16 m apart, none joining another.
    for (i, k) in (RAYS / 2 - 90..RAYS / 2 + 90).step_by(9).enumerate() {
        ranges[k] = 1.0 + 0.5 * (i % 4) as f64;
    }
    let obs = cluster::<16>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
    assert!(obs.as_slice().is_empty(), "{:?}", obs.as_slice());
    assert_eq!(obs.spurious(), 20);
    let a = assess(&obs, &pose, &goal, speed(0.5), false, &config()).unwrap();
    assert_eq!(a.reason, Reason::NoObstacle);
    // A dense burst (dust) 1.2 m ahead.
    for r in &mut ranges[RAYS / 2 - 40..RAYS / 2 + 40] {
        *r = 1.2;
    }
    let obs = cluster::<16>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
    let a = assess(&obs, &pose, &goal, speed(0.5), false, &config()).unwrap();
    assert_eq!(
        (a.hazard, a.reason),
        (Hazard::Critical, Reason::CriticalArea)
    );
    assert!(a.stops());
}

/// The detour entry point on its own gives the same waypoint as `assess`.
#[test]
fn detour_is_what_assess_uses() {
    let (pose, goal) = (
        world(1.0, 2.0, 0.5),
        world(1.0 + 30.0 * 0.5_f64.cos(), 2.0 + 30.0 * 0.5_f64.sin(), 0.5),
    );
    let post = circle(4.0, 0.2, 0.3);
    let w = waypoint_of(&run(&[post], &pose, &goal, false));
    let d = fieldguide::perception::obstacles::detour(
        &post,
        &[post],
        &pose,
        &goal,
        config().areas(speed(0.5)).unwrap().warning_end(),
        &config(),
    )
    .unwrap();
    assert_eq!(d, DetourPlan::Waypoint(w));
}

/// Standard normal draws (Box–Muller) from a seeded generator.
fn gaussian(rng: &mut rand_xoshiro::Xoshiro256PlusPlus) -> f64 {
    use rand_core::RngCore;
    let u = |r: &mut rand_xoshiro::Xoshiro256PlusPlus| {
        ((r.next_u64() >> 11) as f64 + 0.5) / (1_u64 << 53) as f64
    };
    let (a, b) = (u(rng), u(rng));
    (-2.0 * a.ln()).sqrt() * (TAU * b).cos()
}

/// Posts seen through 1 cm of range noise (σ), 200 seeds: one circle each,
/// centre and radius against the ground truth.
//= spec/emmi2024.md#em-obst-shape-circles-and-segments
//= type=test
//# A cluster whose points all lie within a circle of at most the largest
//# circle radius MUST become such a circle, enclosing every point of the
//# cluster.
#[test]
fn posts_through_range_noise() {
    use rand_core::SeedableRng;
    let (mut worst_centre, mut worst_radius, mut sum_radius) = (0.0_f64, 0.0_f64, 0.0_f64);
    for seed in 0..200_u64 {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let d = 2.0 + 4.0 * (seed % 17) as f64 / 16.0;
        let bearing = -1.0 + 2.0 * (seed % 13) as f64 / 12.0;
        let r = 0.1 + 0.3 * (seed % 7) as f64 / 6.0;
        let (x, y) = (d * bearing.cos(), d * bearing.sin());
        let mut ranges = ray_cast(&[circle(x, y, r)]);
        for v in &mut ranges {
            if v.is_finite() {
                *v += 0.01 * gaussian(&mut rng);
            }
        }
        let obs = cluster::<8>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
        assert_eq!(obs.as_slice().len(), 1, "seed {seed}: {:?}", obs.as_slice());
        let Obstacle::Circle { centre, radius } = obs.as_slice()[0] else {
            panic!("seed {seed}: {:?}", obs.as_slice());
        };
        let e = centre.distance_to(pt(x, y)).unwrap().get();
        worst_centre = worst_centre.max(e);
        worst_radius = worst_radius.max((radius.get() - r).abs());
        sum_radius += radius.get() - r;
        // The circle always covers the true post's visible face.
        assert!(radius.get() + e >= r - 0.03, "seed {seed}");
    }
    println!(
        "posts through 1 cm noise, 200 seeds: centre error <= {worst_centre:.4} m, radius error <= {worst_radius:.4} m, mean radius bias {:.4} m",
        sum_radius / 200.0
    );
    assert!(worst_centre < 0.07 && worst_radius < 0.05);
}

/// The closed loop on a perfect tracker: a robot drives 30 m at 0.5 m/s
/// (10 Hz) past one to three posts of a seeded world, seeing them through
/// exact scans, clustering, assessing each tick, stopping when told and
/// following the two Dubins legs of a detour. Over 100 seeds: the footprint
/// never comes within the margin of a post, and every run ends at the goal
/// or stopped with a named reason.
//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//= type=test
//# The detour of a `Warning` MUST be the waypoint of EM-OBST-DETOUR round the
//# obstacle of the path nearest to the robot, or `None` with the reason when
//# there is none.
#[test]
fn closed_loop_past_posts_keeps_the_margin() {
    let (reached, least) = closed_loop(0.0);
    assert!(least >= 0.3 - 1e-9, "footprint within {least} m of a post");
    assert!(reached >= 95, "only {reached} runs reached the goal");
}

/// The same loop through 1 cm of range noise: the circles are estimates, so
/// the margin to the true posts may shrink by the estimates' error (a few
/// centimetres), never to contact.
#[test]
fn closed_loop_through_range_noise_never_touches_a_post() {
    let (reached, least) = closed_loop(0.01);
    assert!(least >= 0.25, "footprint within {least} m of a post");
    assert!(reached >= 95, "only {reached} runs reached the goal");
}

/// Runs the closed loop over 100 seeds with range noise `sigma` (metres);
/// gives the runs at the goal and the least footprint-post distance.
fn closed_loop(sigma: f64) -> (usize, f64) {
    use rand_core::{RngCore, SeedableRng};
    let goal = world(30.0, 0.0, 0.0);
    let (mut reached, mut stopped, mut least) = (0, Vec::new(), f64::INFINITY);
    let mut detours = 0;
    for seed in 0..100_u64 {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut noise = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed + 1000);
        let mut u = || (rng.next_u64() >> 11) as f64 / (1_u64 << 53) as f64;
        let count = 1 + (seed % 3) as usize;
        let posts: Vec<((f64, f64), f64)> = (0..count)
            .map(|i| {
                let x = 7.0 + 7.0 * i as f64 + 3.0 * u();
                ((x, -0.9 + 1.8 * u()), 0.1 + 0.3 * u())
            })
            .collect();
        let mut pose = world(0.0, 0.0, 0.0);
        let mut target = goal;
        let mut outcome = None;
        for _ in 0..1500 {
            // The posts in the robot frame, seen by an exact scan.
            let (c, s) = (pose.heading.get().cos(), pose.heading.get().sin());
            let seen: Vec<Obstacle> = posts
                .iter()
                .map(|&((x, y), r)| {
                    let (dx, dy) = (x - pose.position.x(), y - pose.position.y());
                    circle(c * dx + s * dy, -s * dx + c * dy, r)
                })
                .collect();
            let mut ranges = ray_cast(&seen);
            for v in &mut ranges {
                if v.is_finite() {
                    *v += sigma * gaussian(&mut noise);
                }
            }
            let obs = cluster::<16>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
            let a = assess(&obs, &pose, &target, speed(0.5), false, &config()).unwrap();
            match a.hazard {
                Hazard::Critical | Hazard::Warning { detour: None } | Hazard::NoDetourOnRoad => {
                    outcome = Some(a.reason);
                    break;
                }
                Hazard::Warning { detour: Some(w) } => {
                    detours += 1;
                    target = w;
                }
                Hazard::Clear => {}
            }
            let path = shortest(&pose, &target, radius(1.0)).unwrap();
            let step = path.length().get().min(0.05);
            pose = path.pose_at(m(step)).unwrap();
            if path.length().get() <= 0.05 {
                if target == goal {
                    break;
                }
                target = goal;
            }
            for &(centre, r) in &posts {
                let d = circle_box(
                    {
                        let (c, s) = (pose.heading.get().cos(), pose.heading.get().sin());
                        let (dx, dy) = (centre.0 - pose.position.x(), centre.1 - pose.position.y());
                        (c * dx + s * dy, -s * dx + c * dy)
                    },
                    r,
                    -0.75,
                    0.75,
                    0.88,
                );
                least = least.min(d);
            }
        }
        if pose.position.distance_to(goal.position).unwrap().get() < 1e-6 {
            reached += 1;
        } else {
            let reason =
                outcome.unwrap_or_else(|| panic!("seed {seed}: neither at the goal nor stopped"));
            stopped.push((seed, reason));
        }
    }
    println!(
        "closed loop, range noise {sigma} m, 100 seeds: {reached} at the goal, stopped {stopped:?}, {detours} detour waypoints, least footprint-post distance {least:.3} m"
    );
    (reached, least)
}

/// Posts a few metres apart along the path: no waypoint round the first has
/// a second leg clear of the others all the way to the goal 26 m on, so the
/// shortest whose second leg is clear over the horizon is taken.
//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//= type=test
//# When no candidate has two clear legs, the candidate of least total length
//# whose first leg is clear and whose second leg is clear of the obstacle
//# gone round, and of every obstacle over its first `horizon` metres, MUST
//# be chosen.
//= spec/emmi2024.md#em-obst-hazard-the-hazard-of-one-tick
//= type=test
//# The horizon of the second leg MUST be the warning area's far edge.
#[test]
fn a_detour_may_leave_far_obstacles_for_later() {
    let (pose, goal) = (world(0.0, 0.0, 0.0), world(26.05, 0.0, 0.0));
    let posts = [
        circle(5.609, -0.646, 0.361),
        circle(11.38, 0.791, 0.360),
        circle(19.34, -0.758, 0.148),
    ];
    let a = run(&posts, &pose, &goal, false);
    assert_eq!(a.reason, Reason::Detour, "{a:?}");
    let w = waypoint_of(&a);
    let horizon = config().areas(speed(0.5)).unwrap().warning_end().get();
    // The first leg clear of every post, the second of the one gone round.
    let first = shortest(&pose, &w, radius(1.0)).unwrap();
    let second = shortest(&w, &goal, radius(1.0)).unwrap();
    let sampled = |leg: &fieldguide::planning::dubins::DubinsPath, upto: f64, o: &Obstacle| {
        let end = leg.length().get().min(upto);
        let n = (end / 5e-3).ceil() as usize;
        (0..=n)
            .map(|i| {
                footprint_distance(
                    &leg.pose_at(m(end * i as f64 / n.max(1) as f64)).unwrap(),
                    &pose,
                    o,
                )
            })
            .fold(f64::INFINITY, f64::min)
    };
    for o in &posts {
        assert!(sampled(&first, f64::INFINITY, o) >= 0.3 - 1e-9);
        assert!(sampled(&second, horizon, o) >= 0.3 - 1e-9);
    }
    assert!(sampled(&second, f64::INFINITY, &posts[0]) >= 0.3 - 1e-9);
    // And no waypoint would have kept both legs clear of all posts: with
    // the horizon at the goal, nothing qualifies.
    let far = fieldguide::perception::obstacles::detour(
        &posts[0],
        &posts,
        &pose,
        &goal,
        m(1e3),
        &config(),
    )
    .unwrap();
    assert_eq!(far, DetourPlan::NoClearSide);
}

/// A long object alongside the path (a parked trailer) reaching into the
/// robot's corridor: no waypoint along it helps, one beside an end does.
//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//= type=test
//# The waypoint of a segment MUST lie beyond one of its ends, along the
//# segment, or beside one of its ends, to the left or the right of the
//# planned path's heading, at width/2 + margin + k · step (plus the same
//# extra offsets) from that end, with the planned path's heading where it
//# passes nearest to the segment's midpoint.
#[test]
fn a_long_object_alongside_is_passed_beside_an_end() {
    let (pose, goal) = (world(0.0, 0.0, 0.0), world(30.0, 0.0, 0.0));
    for y in [0.6, 0.8, 1.0] {
        for sign in [1.0, -1.0] {
            let trailer = segment((3.5, sign * y), (9.0, sign * y));
            let a = run(&[trailer], &pose, &goal, false);
            let w = waypoint_of(&a);
            // Beside an end, on the side away from the trailer, heading along the path.
            let k = 1.0 + 0.75_f64.hypot(0.88);
            let off = 0.88 + 0.3 + k * 0.02;
            assert!(
                [3.5, 9.0].iter().any(|x| (w.position.x() - x).abs() < 1e-9),
                "{w:?}"
            );
            let beside = sign * (sign * y - w.position.y());
            assert!(
                [0.0, 0.125, 0.25, 0.375, 0.5, 1.0, 2.0]
                    .iter()
                    .any(|e| (beside - off - e * 1.18).abs() < 1e-6),
                "y {y}, sign {sign}: {w:?}"
            );
            assert!(w.heading.get().abs() < 1e-9);
            assert!(legs_clearance(&pose, &w, &goal, &[trailer]) >= 0.3 - 1e-9);
        }
    }
}

/// Walls seen through 1 cm of range noise, 100 seeds: one segment each, its
/// ends near the wall's line and its ends.
//= spec/emmi2024.md#em-obst-shape-circles-and-segments
//= type=test
//# Any other cluster MUST be split at its point farthest from the chord
//# joining its first and last points until no point of a part is farther
//# than the split tolerance from the part's chord; each such part MUST
//# become the segment of its chord.
#[test]
fn walls_through_range_noise() {
    use rand_core::SeedableRng;
    let (mut worst_line, mut worst_end) = (0.0_f64, 0.0_f64);
    for seed in 0..100_u64 {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let d = 2.0 + 4.0 * (seed % 11) as f64 / 10.0;
        let tilt = -0.5 + (seed % 9) as f64 / 8.0;
        let (ux, uy) = (tilt.sin(), tilt.cos());
        let (a, b) = ((d - 2.0 * ux, -2.0 * uy), (d + 2.0 * ux, 2.0 * uy));
        let mut ranges = ray_cast(&[segment(a, b)]);
        for v in &mut ranges {
            if v.is_finite() {
                *v += 0.01 * gaussian(&mut rng);
            }
        }
        let obs = cluster::<8>(&scan(&ranges), &identity(), &ClusterConfig::emmi2024());
        assert_eq!(obs.as_slice().len(), 1, "seed {seed}: {:?}", obs.as_slice());
        let Obstacle::Segment { start, end } = obs.as_slice()[0] else {
            panic!("seed {seed}: {:?}", obs.as_slice());
        };
        let on_line = |p: Point2<Robot>| ((p.x() - a.0) * uy - (p.y() - a.1) * ux).abs();
        worst_line = worst_line.max(on_line(start)).max(on_line(end));
        for e in [a, b] {
            let near = [start, end]
                .iter()
                .map(|p| p.distance_to(pt(e.0, e.1)).unwrap().get())
                .fold(f64::INFINITY, f64::min);
            worst_end = worst_end.max(near);
        }
    }
    println!("walls through 1 cm noise, 100 seeds: ends within {worst_line:.4} m of the line, {worst_end:.4} m of the true ends");
    assert!(worst_line < 0.04 && worst_end < 0.08);
}
