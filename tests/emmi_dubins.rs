//! GoToGoal (Dubins) and LineFollowing (`spec/emmi2024.md`, EM-DUBINS-*,
//! EM-LINE): lengths and words against the `dubins_paths` crate over 10 000
//! seeded pose pairs, geometric properties, degenerate problems and the
//! conversion into a reference path with exact curvature.
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::float_cmp,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::panic
)]

use core::f64::consts::{FRAC_PI_2, PI, TAU};

use dubins_paths::f64::{DubinsPath as OraclePath, PosRot};
use dubins_paths::PathType;
use fieldguide::geometry::path::ReferencePath;
use fieldguide::model::skid_steer::SkidSteer;
use fieldguide::planning::dubins::{
    path_with_word, shortest, DubinsPath, Turn, TurningRadius, Word,
};
use fieldguide::planning::line_following::{goal_ahead, line_ahead};
use fieldguide::{Meters, MetersPerSecond, Pose2, World};
use proptest::prelude::*;
use rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Two words are tied when their lengths differ by less than this (metres).
const TIE: f64 = 1e-9;

fn pose(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

fn radius(r: f64) -> TurningRadius {
    TurningRadius::new(Meters::new(r).unwrap()).unwrap()
}

fn oracle_type(w: Word) -> PathType {
    match w {
        Word::Lsl => PathType::LSL,
        Word::Lsr => PathType::LSR,
        Word::Rsl => PathType::RSL,
        Word::Rsr => PathType::RSR,
        Word::Rlr => PathType::RLR,
        Word::Lrl => PathType::LRL,
    }
}

fn pos_rot(p: &Pose2<World>) -> PosRot {
    PosRot::from_floats(p.position.x(), p.position.y(), p.heading.get())
}

fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// Every existing word's length, and the best one.
fn lengths(a: &Pose2<World>, b: &Pose2<World>, r: TurningRadius) -> Vec<(Word, f64)> {
    Word::ALL
        .iter()
        .filter_map(|&w| {
            path_with_word(a, b, r, w)
                .ok()
                .map(|p| (w, p.length().get()))
        })
        .collect()
}

/// Whether the shortest length is shared (to `TIE`) by another word.
fn tied(a: &Pose2<World>, b: &Pose2<World>, r: TurningRadius) -> bool {
    let mut l: Vec<f64> = lengths(a, b, r).into_iter().map(|(_, x)| x).collect();
    l.sort_by(f64::total_cmp);
    l.len() > 1 && l[1] - l[0] < TIE
}

struct Uniform(Xoshiro256PlusPlus);

impl Uniform {
    fn next(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.0.next_u64() >> 11) as f64 / (1_u64 << 53) as f64;
        lo + (hi - lo) * u
    }
}

//= spec/emmi2024.md#em-dubins-shortest-the-shortest-word
//= type=test
//# GoToGoal MUST return the path of least length among the words that exist;
//# among words of equal computed length it MUST return the first in the order
//# LSL, LSR, RSL, RSR, RLR, LRL.
//= spec/emmi2024.md#em-dubins-words-the-six-words
//= type=test
//# For each of the six words LSL, LSR, RSL, RSR, RLR and LRL the planner MUST
//# compute the segment lengths of the path of that word from the start pose to
//# the goal pose, or report that the word does not exist.
//= spec/emmi2024.md#em-dubins-shortest-the-shortest-word
//= type=test
//# The length of a path MUST be r times the sum of its three normalised
//# segment lengths.
#[test]
fn lengths_and_words_agree_with_dubins_paths_over_ten_thousand_pairs() {
    let mut g = Uniform(Xoshiro256PlusPlus::seed_from_u64(2024));
    let (mut ties, mut words_checked, mut worst) = (0, 0, 0.0_f64);
    for _ in 0..10_000 {
        let a = pose(g.next(-20.0, 20.0), g.next(-20.0, 20.0), g.next(-PI, PI));
        let b = pose(g.next(-20.0, 20.0), g.next(-20.0, 20.0), g.next(-PI, PI));
        let rho = g.next(0.5, 5.0);
        let r = radius(rho);
        let ours = shortest(&a, &b, r).unwrap();
        let theirs = OraclePath::shortest_from(pos_rot(&a), pos_rot(&b), rho).unwrap();
        worst = worst.max((ours.length().get() - theirs.length()).abs());
        assert!(
            (ours.length().get() - theirs.length()).abs() < 1e-9,
            "{a:?} {b:?} {rho}: {} vs {}",
            ours.length().get(),
            theirs.length()
        );
        if oracle_type(ours.word()) != theirs.path_type {
            // A different word is only allowed for a tie: the oracle's
            // length of our word equals its shortest.
            let same =
                OraclePath::new(pos_rot(&a), pos_rot(&b), rho, oracle_type(ours.word())).unwrap();
            assert!(
                (same.length() - theirs.length()).abs() < TIE,
                "{a:?} {b:?} {rho}"
            );
            ties += 1;
        }
        // Each word: exists for both or for neither, with equal lengths.
        for w in Word::ALL {
            let mine = path_with_word(&a, &b, r, w);
            let other = OraclePath::new(pos_rot(&a), pos_rot(&b), rho, oracle_type(w));
            match (mine, other) {
                (Ok(m), Ok(o)) => {
                    worst = worst.max((m.length().get() - o.length()).abs());
                    assert!((m.length().get() - o.length()).abs() < 1e-9, "{w:?}");
                    words_checked += 1;
                }
                (Err(e), Err(_)) => assert_eq!(e.requirement, "EM-DUBINS-WORDS"),
                (m, o) => panic!("{w:?} {a:?} {b:?} {rho}: {m:?} vs {o:?}"),
            }
        }
    }
    eprintln!(
        "10 000 pairs: {words_checked} words of both, largest length difference {worst:e} m, {ties} ties won by another word"
    );
    assert!(words_checked > 40_000, "{words_checked}");
    assert!(ties < 10, "{ties} ties");
}

fn any_pose() -> impl Strategy<Value = Pose2<World>> {
    (-20.0..20.0_f64, -20.0..20.0_f64, -PI..PI).prop_map(|(x, y, h)| pose(x, y, h))
}

fn mirrored(p: &Pose2<World>) -> Pose2<World> {
    pose(p.position.x(), -p.position.y(), -p.heading.get())
}

fn turned(p: &Pose2<World>) -> Pose2<World> {
    pose(p.position.x(), p.position.y(), p.heading.get() + PI)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    //= spec/emmi2024.md#em-dubins-sample-poses-along-the-path
    //= type=test
    //# The pose at arc length s MUST be the start pose moved along the segments of
    //# the word, each arc of radius r turning by its length over r; the pose at
    //# s = L MUST be the goal pose.
    #[test]
    fn every_word_ends_at_the_goal_pose(a in any_pose(), b in any_pose(), rho in 0.5..5.0_f64) {
        for w in Word::ALL {
            let Ok(p) = path_with_word(&a, &b, radius(rho), w) else { continue };
            let end = p.end().unwrap();
            prop_assert!(end.position.distance_to(b.position).unwrap().get() < 1e-9, "{w:?}");
            prop_assert!(angle_diff(end.heading.get(), b.heading.get()) < 1e-9, "{w:?}");
            let start = p.pose_at(Meters::ZERO).unwrap();
            prop_assert_eq!(start, a);
            // Segments chain: each starts where the previous one ends.
            let segs = p.segments();
            let mut s = 0.0;
            for g in segs {
                let q = p.pose_at(Meters::new(s).unwrap()).unwrap();
                prop_assert!(q.position.distance_to(g.start.position).unwrap().get() < 1e-9);
                prop_assert!(angle_diff(q.heading.get(), g.start.heading.get()) < 1e-9);
                s += g.length.get();
            }
        }
    }

    //= spec/emmi2024.md#em-dubins-shortest-the-shortest-word
    //= type=test
    //# GoToGoal MUST return the path of least length among the words that exist;
    //# among words of equal computed length it MUST return the first in the order
    //# LSL, LSR, RSL, RSR, RLR, LRL.
    #[test]
    fn the_shortest_path_is_no_longer_than_any_word_nor_shorter_than_the_distance(
        a in any_pose(), b in any_pose(), c in any_pose(), rho in 0.5..5.0_f64,
    ) {
        let r = radius(rho);
        let best = shortest(&a, &b, r).unwrap();
        for (w, l) in lengths(&a, &b, r) {
            prop_assert!(best.length().get() <= l, "{w:?}");
        }
        let straight = a.position.distance_to(b.position).unwrap().get();
        prop_assert!(best.length().get() >= straight - 1e-12);
        // Triangle inequality: going through c is a feasible path.
        let via = shortest(&a, &c, r).unwrap().length().get() + shortest(&c, &b, r).unwrap().length().get();
        prop_assert!(best.length().get() <= via + 1e-9);
        // Curvature of every segment: ±1/r or 0, never above 1/r.
        for g in best.segments() {
            let k = g.curvature.get();
            match g.turn {
                Turn::Left => prop_assert_eq!(k, 1.0 / rho),
                Turn::Right => prop_assert_eq!(k, -1.0 / rho),
                Turn::Straight => prop_assert_eq!(k, 0.0),
            }
        }
    }

    /// Mirror image about the x axis: the mirrored word, the same length.
    /// Reversal (goal to start, both headings turned by π): the same path
    /// driven backwards, so the same length and the reversed word.
    #[test]
    fn mirrored_and_reversed_problems_have_equal_lengths(
        a in any_pose(), b in any_pose(), rho in 0.5..5.0_f64,
    ) {
        let r = radius(rho);
        let best = shortest(&a, &b, r).unwrap();
        let m = shortest(&mirrored(&a), &mirrored(&b), r).unwrap();
        prop_assert!((m.length().get() - best.length().get()).abs() < 1e-9);
        if !tied(&a, &b, r) {
            prop_assert_eq!(m.word(), best.word().mirrored());
        }
        let back = shortest(&turned(&b), &turned(&a), r).unwrap();
        prop_assert!((back.length().get() - best.length().get()).abs() < 1e-9);
        if !tied(&a, &b, r) {
            prop_assert_eq!(back.word(), best.word().reversed());
        }
    }

    //= spec/emmi2024.md#em-dubins-path-the-path-as-a-reference-path
    //= type=test
    //# The reference path of a Dubins path MUST have vertices on the path,
    //# segment ends included, at most the requested spacing apart along each
    //# segment (1 mm more where a sample within 1 mm of the previous one was
    //# merged), each carrying the exact heading of the path there and the
    //# curvature of the segment that starts there (+1/r, −1/r or 0).
    #[test]
    fn the_reference_path_carries_exact_headings_and_curvatures(
        a in any_pose(), b in any_pose(), rho in 0.5..5.0_f64,
    ) {
        let p = shortest(&a, &b, radius(rho)).unwrap();
        prop_assume!(p.length().get() > 0.01);
        let path: ReferencePath<4096> = p.to_reference_path(Meters::new(0.1).unwrap()).unwrap();
        let v = path.vertices();
        let first = v[0];
        let last = v[v.len() - 1];
        prop_assert_eq!(first.position, a.position);
        prop_assert!(last.position.distance_to(b.position).unwrap().get() < 1e-9);
        prop_assert!(angle_diff(last.heading.get(), b.heading.get()) < 1e-9);
        for pair in v.windows(2) {
            // Chords of at most 0.1 m of path.
            let d = pair[0].position.distance_to(pair[1].position).unwrap().get();
            prop_assert!(d <= 0.1 + 1e-3 + 1e-9, "{d} {:?}", p);
        }
        for x in v {
            let k = x.curvature.get();
            prop_assert!(k == 0.0 || k == 1.0 / rho || k == -1.0 / rho, "{k}");
            // The vertex lies on the Dubins path, with its heading.
            let here = path.project(&Pose2 { position: x.position, heading: x.heading }, Meters::ZERO).unwrap();
            prop_assert!(here.y.get().abs() < 1e-9);
        }
        // The curvature between vertices is the starting vertex's, never smoothed.
        for pair in v.windows(2) {
            let mid = Meters::new(0.5 * (pair[0].s.get() + pair[1].s.get())).unwrap();
            prop_assert_eq!(path.curvature_at(mid), pair[0].curvature);
        }
        // Polyline length within (h/r)²/24 of the arc length (relative).
        let rel = (path.length().get() - p.length().get()).abs() / p.length().get();
        prop_assert!(rel <= (0.1 / rho).powi(2) / 24.0 + 1e-12, "{rel}");
    }
}

//= spec/emmi2024.md#em-dubins-path-the-path-as-a-reference-path
//= type=test
//# A reference path built from exact samples MUST return, at a vertex, the
//# vertex's heading and, for s in [0, L], the curvature of the vertex that
//# starts the segment holding s, instead of smoothed values.
#[test]
fn an_exact_path_keeps_the_arc_curvature_up_to_the_arc_ends() {
    // Straight 2 m, then a left quarter circle of radius 1 m: LS... built by hand.
    let a = pose(0.0, 0.0, 0.0);
    let b = pose(3.0, 1.0, FRAC_PI_2);
    let p = shortest(&a, &b, radius(1.0)).unwrap();
    // The goal lies on the left circle after 2 m of straight: S then L.
    assert!(
        (p.length().get() - (2.0 + FRAC_PI_2)).abs() < 1e-12,
        "{:?}",
        p
    );
    let exact: ReferencePath<256> = p.to_reference_path(Meters::new(0.05).unwrap()).unwrap();
    let smooth: ReferencePath<256> = ReferencePath::from_waypoints(
        &exact
            .vertices()
            .iter()
            .map(|v| v.position)
            .collect::<Vec<_>>(),
        Default::default(),
    )
    .unwrap();
    // 1 cm before the arc: exact 0, smoothed already bent; 1 cm after: exact 1/r.
    assert_eq!(exact.curvature_at(Meters::new(1.99).unwrap()).get(), 0.0);
    assert!(smooth.curvature_at(Meters::new(1.99).unwrap()).get() > 0.2);
    assert_eq!(exact.curvature_at(Meters::new(2.01).unwrap()).get(), 1.0);
    assert!(smooth.curvature_at(Meters::new(2.01).unwrap()).get() < 0.8);
    // Heading at a vertex is the vertex's, exactly.
    for v in exact.vertices() {
        assert_eq!(exact.heading_at(v.s), v.heading);
    }
    // A sample within 1 mm of the last kept one replaces it, so the last
    // sample always ends the path.
    let c = fieldguide::Curvature::ZERO;
    let q: ReferencePath<8> = ReferencePath::from_exact([
        (pose(0.0, 0.0, 0.0), c),
        (pose(1.0, 0.0, 0.0), c),
        (pose(1.0005, 0.0, 0.0), c),
    ])
    .unwrap();
    assert_eq!(q.vertices().len(), 2);
    assert_eq!(q.vertices()[1].position.x(), 1.0005);
    assert_eq!(q.length().get(), 1.0005);
    let err =
        ReferencePath::<8>::from_exact([(pose(0.0, 0.0, 0.0), c), (pose(0.0005, 0.0, 0.0), c)])
            .unwrap_err();
    assert_eq!(err.requirement, "PATH-WAYPOINTS");
    let err =
        ReferencePath::<2>::from_exact([(a, c), (b, c), (pose(9.0, 9.0, 0.0), c)]).unwrap_err();
    assert_eq!(err.requirement, "PATH-CAPACITY");
}

//= spec/emmi2024.md#em-dubins-degenerate-degenerate-problems
//= type=test
//# When the goal pose equals the start pose, GoToGoal MUST return a path of
//# length 0.
#[test]
fn degenerate_problems_have_defined_results() {
    let a = pose(3.0, -2.0, 0.7);
    let p = shortest(&a, &a, radius(1.5)).unwrap();
    assert_eq!(p.length().get(), 0.0);
    assert_eq!(p.word(), Word::Lsl);
    assert_eq!(p.end().unwrap(), a);
    // No reference path of length 0.
    let e = p
        .to_reference_path::<16>(Meters::new(0.1).unwrap())
        .unwrap_err();
    assert_eq!(e.requirement, "PATH-WAYPOINTS");
    // Goal on the start's left circle, a quarter turn on: one arc, r π/2.
    let r = 2.0;
    let on_circle = pose(r, r, FRAC_PI_2);
    let p = shortest(&pose(0.0, 0.0, 0.0), &on_circle, radius(r)).unwrap();
    assert!((p.length().get() - r * FRAC_PI_2).abs() < 1e-12, "{p:?}");
    // One arc: LSL and LSR (straight and last arc of length 0) tie.
    assert!(matches!(p.word(), Word::Lsl | Word::Lsr), "{p:?}");
    assert!((p.segments()[0].length.get() - r * FRAC_PI_2).abs() < 1e-12);
    // The closed form alone (as the oracle computes it) may add a full turn
    // here, from the direction between two coincident centres.
    let o =
        OraclePath::shortest_from(pos_rot(&pose(0.0, 0.0, 0.0)), pos_rot(&on_circle), r).unwrap();
    eprintln!(
        "a quarter turn along the circle: {} m here, {} m by dubins_paths",
        p.length().get(),
        o.length()
    );
    assert!(
        p.length().get() <= o.length() + 1e-12,
        "oracle {}",
        o.length()
    );
    for k in 1..40 {
        // Every arc of the left circle, either way round.
        let turn = f64::from(k) * TAU / 40.0;
        let g = pose(r * turn.sin(), r - r * turn.cos(), turn);
        let p = shortest(&pose(0.0, 0.0, 0.0), &g, radius(r)).unwrap();
        assert!(
            (p.length().get() - r * turn).abs() < 1e-9 || p.length().get() < r * turn,
            "{k}: {p:?}"
        );
        assert!(
            p.end()
                .unwrap()
                .position
                .distance_to(g.position)
                .unwrap()
                .get()
                < 1e-9
        );
    }
    // Goal behind the robot within its turning circle: still a forward path,
    // longer than the distance (a CCC word).
    let behind = pose(-0.3, 0.0, 0.0);
    let p = shortest(&pose(0.0, 0.0, 0.0), &behind, radius(1.0)).unwrap();
    assert!(p.length().get() > 2.0 * PI);
    // Straight ahead: a straight of the distance.
    let p = shortest(&pose(0.0, 0.0, 0.0), &pose(5.0, 0.0, 0.0), radius(1.0)).unwrap();
    assert!((p.length().get() - 5.0).abs() < 1e-12);
    assert_eq!(p.segments()[1].length.get(), 5.0);
}

//= spec/emmi2024.md#em-dubins-words-the-six-words
//= type=test
//# A word that does not exist between the two poses MUST be reported with the
//# `EM-DUBINS-WORDS` error.
#[test]
fn words_that_do_not_exist_are_refused() {
    // Two close poses facing each other's left: LSR needs circles 2r apart.
    let a = pose(0.0, 0.0, 0.0);
    // The start's left circle is centred at (0, 1), the goal's right circle
    // at (0.5, 1): 0.5 m apart, less than 2r.
    let b = pose(0.5, 0.0, PI);
    let e = path_with_word(&a, &b, radius(1.0), Word::Lsr).unwrap_err();
    assert_eq!(e.requirement, "EM-DUBINS-WORDS");
    // Far apart: no CCC word (circles more than 4r apart).
    let far = pose(50.0, 0.0, 0.0);
    for w in [Word::Rlr, Word::Lrl] {
        let e = path_with_word(&a, &far, radius(1.0), w).unwrap_err();
        assert_eq!(e.requirement, "EM-DUBINS-WORDS");
    }
}

//= spec/emmi2024.md#em-dubins-radius-turning-radius
//= type=test
//# The turning radius r MUST lie in [1e−3 m, 1e4 m]; another radius, zero
//# included, MUST be refused with the `EM-DUBINS-RADIUS` error.
//= spec/emmi2024.md#em-dubins-range-coordinates-within-range
//= type=test
//# Poses with a coordinate of magnitude above 1e7 m MUST be refused with the
//# `EM-DUBINS-RANGE` error.
//= spec/emmi2024.md#em-skid-forward-both-tracks-forward-in-turns
//= type=test
//# A planner option MUST refuse a turning radius below the track distance b
//# with the `EM-SKID-FORWARD` error.
#[test]
fn radii_and_ranges_are_checked() {
    for bad in [0.0, -1.0, 1e-4, 2e4] {
        let e = TurningRadius::new(Meters::new(bad).unwrap()).unwrap_err();
        assert_eq!(e.requirement, "EM-DUBINS-RADIUS");
    }
    assert_eq!(
        TurningRadius::new(Meters::new(1e-3).unwrap())
            .unwrap()
            .get()
            .get(),
        1e-3
    );
    let robot = SkidSteer::new(
        Meters::new(1.48).unwrap(),
        MetersPerSecond::new(1.67).unwrap(),
    )
    .unwrap();
    let e = TurningRadius::for_vehicle(Meters::new(0.75).unwrap(), &robot).unwrap_err();
    assert_eq!(e.requirement, "EM-SKID-FORWARD");
    assert!(TurningRadius::for_vehicle(Meters::new(1.48).unwrap(), &robot).is_ok());
    assert!(TurningRadius::for_vehicle(Meters::new(2.0).unwrap(), &robot).is_ok());
    let e = shortest(&pose(2e7, 0.0, 0.0), &pose(0.0, 0.0, 0.0), radius(1.0)).unwrap_err();
    assert_eq!(e.requirement, "EM-DUBINS-RANGE");
    // The far corners of the range still give a finite path.
    let p = shortest(&pose(-1e7, -1e7, 0.0), &pose(1e7, 1e7, 1.0), radius(1e-3)).unwrap();
    assert!(p.length().get().is_finite());
    for spacing in [1e-4, 1.9e-3] {
        let e = p
            .to_reference_path::<4>(Meters::new(spacing).unwrap())
            .unwrap_err();
        assert_eq!(e.requirement, "EM-DUBINS-PATH");
    }
    // 2.8e7 m at 2 mm: refused at the capacity, after N + 1 samples, not
    // after sampling the whole path.
    let t = std::time::Instant::now();
    let e = p
        .to_reference_path::<4>(Meters::new(2e-3).unwrap())
        .unwrap_err();
    assert_eq!(e.requirement, "PATH-CAPACITY");
    assert!(t.elapsed().as_secs_f64() < 0.1);
    // A spacing larger than a turn still samples each arc at least every
    // quarter turn: a U-turn of radius 1 m sampled "every 100 m".
    let u = shortest(&pose(0.0, 0.0, 0.0), &pose(0.0, 2.0, PI), radius(1.0)).unwrap();
    let path: ReferencePath<16> = u.to_reference_path(Meters::new(100.0).unwrap()).unwrap();
    assert_eq!(path.vertices().len(), 3, "{:?}", path.vertices());
    assert!((path.vertices()[1].position.x() - 1.0).abs() < 1e-12);
}

//= spec/emmi2024.md#em-line-linefollowing
//= type=test
//# LineFollowing MUST return the goal pose at the requested distance ahead of
//# the robot along its heading, with the robot's heading, and refuse a distance
//# below 1 mm with the `EM-LINE` error.
//= spec/emmi2024.md#em-line-linefollowing
//= type=test
//# The LineFollowing path MUST be the straight segment from the robot's
//# position to the goal, heading the robot's heading, curvature 0.
#[test]
fn line_following_goes_straight_ahead() {
    let robot = pose(1.0, 2.0, FRAC_PI_2);
    let goal = goal_ahead(&robot, Meters::new(10.0).unwrap()).unwrap();
    assert!((goal.position.x() - 1.0).abs() < 1e-12);
    assert_eq!(goal.position.y(), 12.0);
    assert_eq!(goal.heading, robot.heading);
    let path: ReferencePath<4> = line_ahead(&robot, Meters::new(10.0).unwrap()).unwrap();
    assert_eq!(path.length().get(), 10.0);
    assert_eq!(path.heading_at(Meters::new(5.0).unwrap()), robot.heading);
    assert_eq!(path.curvature_at(Meters::new(5.0).unwrap()).get(), 0.0);
    let e = goal_ahead(&robot, Meters::new(1e-4).unwrap()).unwrap_err();
    assert_eq!(e.requirement, "EM-LINE");
    let _: DubinsPath = shortest(&robot, &goal, radius(1.0)).unwrap();
}
