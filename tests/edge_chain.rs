//! Properties of the exact rolling-circle chain (Pierre 2022, Algorithm 1;
//! `spec/pierre2022.md`, EDGE-CHAIN-TRANSLATE, EDGE-CHAIN-ROTATE,
//! EDGE-CHAIN-STOP), against the paper's stepped version as a reference.
#![allow(
    clippy::arithmetic_side_effects,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::float_cmp,
    clippy::panic
)]

mod edge_support;

use edge_support::{hedge, pt, stepped_chain, wall};
use fieldguide::perception::edge::{
    build_chain, rotation_contact, translation_contact, Chain, ChainEnd, EdgeConfig,
    EdgeParameters, Side,
};
use fieldguide::{Meters, Point2, Robot};
use proptest::prelude::*;

const M: usize = 128;

fn config() -> EdgeConfig {
    EdgeConfig::pierre2022().unwrap()
}

fn side() -> impl Strategy<Value = Side> {
    prop_oneof![Just(Side::Left), Just(Side::Right)]
}

/// A ragged hedge: 5..60 points, along-hedge abscissae in [−2, 6] m, jitter
/// ±`j` around a line 0.6..2.8 m away, heading within ±0.5 rad.
fn ragged(j: f64) -> impl Strategy<Value = (Side, Vec<Point2<Robot>>)> {
    (
        side(),
        0.6..2.8f64,
        -0.5..0.5f64,
        prop::collection::vec((-2.0..6.0f64, -1.0..1.0f64), 5..60),
    )
        .prop_map(move |(s, d, a, xj)| {
            let (xs, js): (Vec<f64>, Vec<f64>) = xj.into_iter().map(|(x, u)| (x, u * j)).unzip();
            (s, hedge(s, d, a, &xs, &js))
        })
}

/// The checks every chain must pass, whatever the input.
fn check_invariants(points: &[Point2<Robot>], side: Side, config: &EdgeConfig, chain: &Chain<M>) {
    let r = config.radius().get();
    let s = side.sign();
    assert_eq!(chain.points().len(), chain.indices().len());
    assert_eq!(chain.points().len(), chain.centers().len());
    assert!(chain.len() <= M);
    // Every chain point is a scan point of the requested side, taken once.
    for (k, (&i, p)) in chain.indices().iter().zip(chain.points()).enumerate() {
        assert_eq!(points[i], *p);
        assert!(s * p.y() > 0.0);
        assert!(!chain.indices()[..k].contains(&i));
    }
    // Each circle position touches its point(s) and holds no point strictly inside.
    for (k, c) in chain.centers().iter().enumerate() {
        let tol = 1e-9 * (1.0 + c.x().abs() + c.y().abs());
        assert!((c.distance_to(chain.points()[k]).unwrap().get() - r).abs() < tol);
        if k > 0 {
            assert!((c.distance_to(chain.points()[k - 1]).unwrap().get() - r).abs() < tol);
        }
        for q in points.iter().filter(|q| s * q.y() > 0.0) {
            assert!(
                c.distance_to(*q).unwrap().get() >= r - tol,
                "point {q:?} inside circle {k} at {c:?}"
            );
        }
    }
    // Links are shorter than 2r; the length is their sum and is bounded.
    let mut length = 0.0;
    for w in chain.points().windows(2) {
        let d = w[0].distance_to(w[1]).unwrap().get();
        assert!(d > 0.0 && d < 2.0 * r);
        length += d;
    }
    assert!((chain.length().get() - length).abs() < 1e-9);
    let l_max = config.max_chain_length().get();
    assert!(chain.length().get() < l_max + 2.0 * r);
    // No link is longer than l_link (EDGE-GAP) or turns from the chord by
    // more than φ_turn (EDGE-CORNER).
    let pts = chain.points();
    for k in 1..pts.len() {
        assert!(pts[k - 1].distance_to(pts[k]).unwrap().get() <= config.max_link().get());
        if k >= 2 {
            assert!(turn(pts[0], pts[k - 1], pts[k]) <= config.max_turn().get() + 1e-9);
        }
    }
    match chain.end() {
        ChainEnd::NoEdge => assert!(chain.is_empty()),
        ChainEnd::LengthLimit => assert!(chain.length().get() >= l_max),
        ChainEnd::Capacity => assert_eq!(chain.len(), M),
        ChainEnd::RotationLimit | ChainEnd::Closed | ChainEnd::Gap | ChainEnd::Corner => {
            assert!(chain.length().get() < l_max && !chain.is_empty())
        }
    }
}

/// The angle, in [0, π], between the link `pivot → next` and the chord `first → pivot`.
fn turn(first: Point2<Robot>, pivot: Point2<Robot>, next: Point2<Robot>) -> f64 {
    let a = (pivot.y() - first.y()).atan2(pivot.x() - first.x());
    let b = (next.y() - pivot.y()).atan2(next.x() - pivot.x());
    let mut d = (b - a).abs();
    if d > core::f64::consts::PI {
        d = core::f64::consts::TAU - d;
    }
    d
}

/// The next contact about the last pivot of `chain` (the point the chain
/// refused, when it stopped at a gap or a corner): its index and point.
fn refused_contact(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    chain: &Chain<M>,
) -> Option<(usize, Point2<Robot>)> {
    let k = chain.len().checked_sub(1)?;
    let (p, c) = (chain.points()[k], chain.centers()[k]);
    points
        .iter()
        .enumerate()
        .filter(|(i, q)| *i != chain.indices()[k] && side.sign() * q.y() > 0.0)
        .filter_map(|(i, q)| {
            rotation_contact(p, c, *q, side, config.radius())
                .map(|t| (t.get(), p.distance_to(*q).unwrap().get(), i, *q))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)))
        .map(|(_, _, i, q)| (i, q))
}

//= spec/pierre2022.md#edge-chain-translate-first-point-by-translation
//= type=test
//# The first chain point MUST be the point with the smallest translation
//# contact t(q), and there MUST be no chain when that smallest t(q) exceeds
//# the search distance.
//= spec/pierre2022.md#edge-chain-rotate-next-point-by-rotation
//= type=test
//# Each next chain point MUST be the point with the smallest contact angle
//# about the current pivot, and the circle MUST move to the position where it
//# touches both the pivot and that point.
/// Each contact is the minimum of the closed-form contacts over all points.
fn check_minimal_contacts(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    chain: &Chain<M>,
) {
    let r = config.radius();
    let first = points
        .iter()
        .filter_map(|q| translation_contact(*q, side, r).map(|t| t.get()))
        .fold(f64::INFINITY, f64::min);
    if chain.is_empty() {
        assert!(first.is_infinite() || first > config.search_distance().get());
        return;
    }
    let t0 = translation_contact(chain.points()[0], side, r)
        .unwrap()
        .get();
    assert_eq!(t0, first);
    for k in 1..chain.len() {
        let (p, c) = (chain.points()[k - 1], chain.centers()[k - 1]);
        let theta = rotation_contact(p, c, chain.points()[k], side, r)
            .unwrap()
            .get();
        assert!(theta < config.max_rotation().get());
        for (i, q) in points.iter().enumerate() {
            if i == chain.indices()[k - 1] || side.sign() * q.y() <= 0.0 {
                continue;
            }
            if let Some(other) = rotation_contact(p, c, *q, side, r) {
                assert!(other.get() >= theta - 1e-12, "point {i} touches first");
            }
        }
    }
    check_stop_at_gap_or_corner(points, side, config, chain);
}

//= spec/pierre2022.md#edge-gap-the-chain-stops-at-a-gap-in-the-edge
//= type=test
//# The chain MUST stop, before taking it, at a next contact farther than
//# l_link from the pivot: a link longer than l_link is a gap, and the two
//# sides of a gap are two edges.
//= spec/pierre2022.md#edge-corner-the-chain-stops-at-a-corner-or-the-end-of-the-edge
//= type=test
//# The chain MUST stop, before taking it, at a next contact q whose link
//# from the pivot p_k turns from the chain's direction, the vector from its
//# first point p_0 to p_k, by more than φ_turn: (q − p_k) · (p_k − p_0) <
//# cos φ_turn · |q − p_k| |p_k − p_0|.
/// A chain that ended at a gap or a corner refused the point the circle
/// touched next, and that point is beyond the gap or round the corner.
fn check_stop_at_gap_or_corner(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    chain: &Chain<M>,
) {
    let refused = refused_contact(points, side, config, chain);
    let last = chain.len().saturating_sub(1);
    match chain.end() {
        ChainEnd::Gap => {
            let (_, q) = refused.unwrap();
            let theta = rotation_contact(
                chain.points()[last],
                chain.centers()[last],
                q,
                side,
                config.radius(),
            )
            .unwrap();
            assert!(theta.get() < config.max_rotation().get());
            assert!(chain.points()[last].distance_to(q).unwrap().get() > config.max_link().get());
        }
        ChainEnd::Corner => {
            let (_, q) = refused.unwrap();
            assert!(chain.len() >= 2, "the first link cannot turn");
            assert!(chain.points()[last].distance_to(q).unwrap().get() <= config.max_link().get());
            assert!(
                turn(chain.points()[0], chain.points()[last], q) > config.max_turn().get() - 1e-9
            );
        }
        _ => {}
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    //= spec/pierre2022.md#edge-chain-stop-rotation-and-length-limits
    //= type=test
    //# The chain MUST stop when no point has a contact angle below θ_max, when
    //# its polyline length reaches l_max, when the next contact is a point
    //# already in the chain, or when its buffer is full.
    #[test]
    fn chains_of_ragged_hedges_keep_their_invariants((side, points) in ragged(0.3)) {
        let config = config();
        let chain = build_chain::<M>(&points, side, &config);
        check_invariants(&points, side, &config, &chain);
        check_minimal_contacts(&points, side, &config, &chain);
    }

    #[test]
    fn chains_of_arbitrary_points_keep_their_invariants(
        side in side(),
        points in prop::collection::vec((-4.0..4.0f64, -4.0..4.0f64), 0..40),
        radius in 0.2..2.0f64,
        max_rotation in 0.1..6.2f64,
        max_link in 0.1..4.0f64,
        max_turn in 0.1..=core::f64::consts::PI,
    ) {
        let points: Vec<_> = points.into_iter().map(|(x, y)| pt(x, y)).collect();
        let config = EdgeConfig::new(&EdgeParameters {
            radius,
            max_rotation,
            max_link,
            max_turn,
            ..EdgeParameters::PIERRE2022
        })
        .unwrap();
        let chain = build_chain::<M>(&points, side, &config);
        check_invariants(&points, side, &config, &chain);
        check_minimal_contacts(&points, side, &config, &chain);
    }

    /// A chain along a gently jittered hedge runs forward along it.
    #[test]
    fn chain_points_are_in_order_along_the_edge((side, points) in ragged(0.05)) {
        let config = config();
        let chain = build_chain::<M>(&points, side, &config);
        // Recover the hedge heading from the generator: the along-hedge
        // abscissa is the projection on the chain's overall direction.
        if chain.len() >= 2 {
            let (a, b) = (chain.points()[0], *chain.points().last().unwrap());
            let (dx, dy) = (b.x() - a.x(), b.y() - a.y());
            let along: Vec<f64> = chain.points().iter().map(|p| p.x() * dx + p.y() * dy).collect();
            for w in along.windows(2) {
                prop_assert!(w[1] > w[0], "chain goes backward: {:?}", along);
            }
        }
    }

    //= spec/pierre2022.md#edge-chain-rotate-next-point-by-rotation
    //= type=test
    //# The contact angle of a point q at distance 0 < d < 2r from the pivot MUST
    //# be the smallest θ ≥ 0 at which |c(θ) − q| = r with q entering the disk,
    //# where c(θ) is the centre rotated by s·θ about the pivot; a point at d = 0
    //# or d ≥ 2r MUST have no contact.
    #[test]
    fn rotation_contact_solves_the_circle_equation(
        side in side(),
        phi in -3.1..3.1f64,
        qx in -2.5..2.5f64,
        qy in -2.5..2.5f64,
    ) {
        let r = 1.0;
        let s = side.sign();
        let p = pt(0.3, 0.7);
        let c = pt(0.3 + r * phi.cos(), 0.7 + r * phi.sin());
        let q = pt(qx, qy);
        let d = p.distance_to(q).unwrap().get();
        let inside_now = c.distance_to(q).unwrap().get() < r;
        match rotation_contact(p, c, q, side, fieldguide::Meters::new(r).unwrap()) {
            None => prop_assert!(d >= 2.0 * r || d == 0.0),
            Some(theta) if !inside_now => {
                let th = theta.get();
                prop_assert!((0.0..core::f64::consts::TAU).contains(&th));
                let at = |t: f64| {
                    let (ux, uy) = (c.x() - p.x(), c.y() - p.y());
                    let (cs, sn) = (t.cos(), (s * t).sin());
                    pt(p.x() + cs * ux - sn * uy, p.y() + sn * ux + cs * uy)
                };
                // On the circle at θ, outside just before, inside just after.
                prop_assert!((at(th).distance_to(q).unwrap().get() - r).abs() < 1e-9);
                if th > 1e-6 {
                    prop_assert!(at(th - 1e-6).distance_to(q).unwrap().get() > r);
                    // Never inside between 0 and θ.
                    for k in 1..50 {
                        prop_assert!(at(th * f64::from(k) / 50.0).distance_to(q).unwrap().get() >= r - 1e-12);
                    }
                }
                prop_assert!(at(th + 1e-6).distance_to(q).unwrap().get() < r);
            }
            Some(_) => {}
        }
    }

}

/// A straight wall on `side` at distance `dist` and heading `angle`, sampled
/// every 5 cm from −1 m to 6 m along it, without the points strictly inside
/// the gap `(g0, g0 + width)`; with each point's along-wall abscissa.
fn wall_with_gap(
    side: Side,
    dist: f64,
    angle: f64,
    g0: f64,
    width: f64,
) -> (Vec<Point2<Robot>>, Vec<f64>) {
    let along: Vec<f64> = (0..=140)
        .map(|k| -1.0 + 0.05 * f64::from(k))
        .filter(|a| *a <= g0 + 1e-9 || *a >= g0 + width - 1e-9)
        .collect();
    let zeros = vec![0.0; along.len()];
    (hedge(side, dist, angle, &along, &zeros), along)
}

/// Two straight legs on `side`: from 1 m behind the robot's abscissa along
/// the robot's x axis at distance `dist` to the corner at x = `c`, then 2 m
/// turning by `turn` (positive: away from the robot), points every 5 cm;
/// with whether each point is on the second leg (the corner excluded).
fn corner(side: Side, dist: f64, c: f64, turn: f64) -> (Vec<Point2<Robot>>, Vec<bool>) {
    let s = side.sign();
    let mut points = Vec::new();
    let mut second = Vec::new();
    let mut x = -1.0;
    while x < c - 1e-9 {
        points.push(pt(x, s * dist));
        second.push(false);
        x += 0.05;
    }
    points.push(pt(c, s * dist));
    second.push(false);
    for k in 1..=40 {
        let a = 0.05 * f64::from(k);
        points.push(pt(c + a * turn.cos(), s * (dist + a * turn.sin())));
        second.push(true);
    }
    (points, second)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    //= spec/pierre2022.md#edge-gap-the-chain-stops-at-a-gap-in-the-edge
    //= type=test
    //# The chain MUST stop, before taking it, at a next contact farther than
    //# l_link from the pivot: a link longer than l_link is a gap, and the two
    //# sides of a gap are two edges.
    /// A wall with a gap wider than l_link ahead gives a chain that stops at
    /// the gap; the paper's rules alone (l_link = 2r) chain across it; a gap
    /// narrower than l_link is chained across.
    #[test]
    fn a_wall_with_a_gap_gives_a_chain_that_stops_at_the_gap(
        side in side(),
        dist in 0.8..2.5f64,
        angle in -0.3..0.3f64,
        g0 in 0.3..2.0f64,
        width in 1.05..1.9f64,
    ) {
        let config = config();
        let (points, along) = wall_with_gap(side, dist, angle, g0, width);
        // The wall beyond the gap stays on the requested side over a metre.
        prop_assume!(points
            .iter()
            .zip(&along)
            .filter(|(_, a)| **a >= g0 + width - 1e-9)
            .take(20)
            .all(|(p, _)| side.sign() * p.y() > 0.2));
        let chain = build_chain::<M>(&points, side, &config);
        check_invariants(&points, side, &config, &chain);
        prop_assert_eq!(chain.end(), ChainEnd::Gap);
        // Every chain point is before the gap, the last one at its edge.
        for &i in chain.indices() {
            prop_assert!(along[i] <= g0 + 1e-9);
        }
        prop_assert!(along[*chain.indices().last().unwrap()] > g0 - 0.05 - 1e-9);
        // The paper's chain (every contact closer than 2r taken) crosses it.
        let paper = EdgeConfig::new(&EdgeParameters { max_link: 2.0, ..EdgeParameters::PIERRE2022 }).unwrap();
        let across = build_chain::<M>(&points, side, &paper);
        prop_assert!(across.indices().iter().any(|&i| along[i] >= g0 + width - 1e-9));
        // A gap narrower than l_link is part of the edge.
        let (narrow, along) = wall_with_gap(side, dist, angle, g0, 0.9);
        let chain = build_chain::<M>(&narrow, side, &config);
        prop_assert_ne!(chain.end(), ChainEnd::Gap);
        prop_assert!(chain.indices().iter().any(|&i| along[i] >= g0 + 0.9 - 1e-9));
    }

    //= spec/pierre2022.md#edge-corner-the-chain-stops-at-a-corner-or-the-end-of-the-edge
    //= type=test
    //# The chain MUST stop, before taking it, at a next contact q whose link
    //# from the pivot p_k turns from the chain's direction, the vector from its
    //# first point p_0 to p_k, by more than φ_turn: (q − p_k) · (p_k − p_0) <
    //# cos φ_turn · |q − p_k| |p_k − p_0|.
    /// A wall that turns away from the robot by more than φ_turn (the end of
    /// a hedge, a building's corner) gives a chain that stops at the corner;
    /// with φ_turn = π, a turn below θ_max is wrapped round.
    #[test]
    fn a_corner_stops_the_chain(
        side in side(),
        dist in 1.0..2.0f64,
        c in 0.8..2.2f64,
        turn_deg in 50.0..150.0f64,
    ) {
        let config = config();
        let (points, second) = corner(side, dist, c, turn_deg.to_radians());
        let chain = build_chain::<M>(&points, side, &config);
        check_invariants(&points, side, &config, &chain);
        check_minimal_contacts(&points, side, &config, &chain);
        for &i in chain.indices() {
            prop_assert!(!second[i], "chain point {i} on the second leg: {:?}", chain.end());
        }
        if turn_deg < 80.0 {
            prop_assert_eq!(chain.end(), ChainEnd::Corner);
            let paper = EdgeConfig::new(&EdgeParameters { max_turn: core::f64::consts::PI, ..EdgeParameters::PIERRE2022 }).unwrap();
            let wraps = build_chain::<M>(&points, side, &paper);
            prop_assert!(wraps.indices().iter().any(|&i| second[i]));
        }
    }

    /// A gently curved edge (radius ≥ 3 m, either way) is not cut by the
    /// corner rule: the chain runs to l_max.
    #[test]
    fn a_gently_curved_edge_is_not_a_corner(
        side in side(),
        dist in 1.0..2.0f64,
        radius in 3.0..20.0f64,
        away in any::<bool>(),
    ) {
        let config = config();
        let s = side.sign();
        // Centre of curvature beyond the edge (curving away) or on the robot's side.
        let k = if away { 1.0 } else { -1.0 };
        // Curving towards the robot, the edge must stay on its side over the chain.
        prop_assume!(away || dist - radius * (1.0 - (4.5 / radius).cos()) > 0.3);
        let points: Vec<_> = (0..=120)
            .map(|i| {
                let a = -1.0 + 0.05 * f64::from(i);
                let phi = a / radius;
                pt(radius * phi.sin(), s * (dist + k * radius * (1.0 - phi.cos())))
            })
            .collect();
        let chain = build_chain::<M>(&points, side, &config);
        check_invariants(&points, side, &config, &chain);
        prop_assert_eq!(chain.end(), ChainEnd::LengthLimit);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// The exact and the stepped chains agree once the step is smaller than
    /// the gap between competing contacts.
    #[test]
    fn exact_and_stepped_chains_agree_as_the_step_shrinks((side, points) in ragged(0.3)) {
        // The library's rules, and the paper's alone (no gap, no corner rule).
        let paper = EdgeConfig::new(&EdgeParameters {
            max_link: 2.0,
            max_turn: core::f64::consts::PI,
            ..EdgeParameters::PIERRE2022
        })
        .unwrap();
        for config in [config(), paper] {
            let exact = build_chain::<M>(&points, side, &config);
            let step = 1e-4;
            prop_assume!(well_separated(&points, side, &config, &exact));
            let stepped = stepped_chain(&points, side, &config, step, step, M);
            prop_assert_eq!(exact.indices(), &stepped[..]);
        }
    }
}

/// Whether every decision of the exact chain wins by more than `gap`: the
/// first translation contact and each rotation contact against the runner-up
/// and against θ_max, and the final length against l_max.
fn well_separated(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    chain: &Chain<M>,
) -> bool {
    let r = config.radius();
    let s = side.sign();
    let mut ts: Vec<f64> = points
        .iter()
        .filter_map(|q| translation_contact(*q, side, r).map(|t| t.get()))
        .collect();
    ts.sort_by(f64::total_cmp);
    if ts.len() >= 2 && ts[1] - ts[0] < gap_t(config) {
        return false;
    }
    if let Some(t) = ts.first() {
        if (t - config.search_distance().get()).abs() < gap_t(config) {
            return false;
        }
    }
    let theta_max = config.max_rotation().get();
    for k in 0..chain.len() {
        let (p, c) = (chain.points()[k], chain.centers()[k]);
        let mut th: Vec<f64> = points
            .iter()
            .enumerate()
            .filter(|(i, q)| *i != chain.indices()[k] && s * q.y() > 0.0)
            .filter_map(|(_, q)| rotation_contact(p, c, *q, side, r).map(|t| t.get()))
            .collect();
        th.sort_by(f64::total_cmp);
        let gap = 2e-3;
        if th.len() >= 2 && th[1] - th[0] < gap {
            return false;
        }
        if th.first().is_some_and(|t| (t - theta_max).abs() < gap) {
            return false;
        }
    }
    (chain.length().get() - config.max_chain_length().get()).abs() > 1e-3
}

fn gap_t(_config: &EdgeConfig) -> f64 {
    2e-3
}

#[test]
fn straight_wall_is_chained_point_by_point_in_order() {
    let config = config();
    for side in [Side::Left, Side::Right] {
        let points = wall(side, 1.4, 0.2, 0.05, -1.0, 5.0);
        let chain = build_chain::<M>(&points, side, &config);
        check_invariants(&points, side, &config, &chain);
        assert_eq!(chain.end(), ChainEnd::LengthLimit);
        // Consecutive wall points, from the one abeam of the robot's rear point.
        for w in chain.indices().windows(2) {
            assert_eq!(w[1], w[0] + 1);
        }
    }
}

//= spec/pierre2022.md#edge-corner-the-chain-stops-at-a-corner-or-the-end-of-the-edge
//= type=test
//# The chain MUST stop, before taking it, at a next contact q whose link
//# from the pivot p_k turns from the chain's direction, the vector from its
//# first point p_0 to p_k, by more than φ_turn: (q − p_k) · (p_k − p_0) <
//# cos φ_turn · |q − p_k| |p_k − p_0|.
#[test]
fn the_end_face_of_a_hedge_is_not_climbed() {
    // The face of a hedge 1.4 m to the left ends at x = 1.5; its end face
    // runs away from the robot, its points scattered by ±1 cm along x as a
    // LiDAR's range noise scatters them. θ_max = π/2 does not stop the
    // circle: it climbs the end face by small rotations, each below θ_max.
    let mut points: Vec<_> = (0..=50)
        .map(|k| pt(-1.0 + 0.05 * f64::from(k), 1.4))
        .collect();
    let face = points.len();
    for k in 1..=20 {
        let jitter = if k % 2 == 0 { -0.006 } else { 0.01 };
        points.push(pt(1.5 + jitter, 1.4 + 0.05 * f64::from(k)));
    }
    let paper = EdgeConfig::new(&EdgeParameters {
        max_turn: core::f64::consts::PI,
        ..EdgeParameters::PIERRE2022
    })
    .unwrap();
    let climbs = build_chain::<M>(&points, Side::Left, &paper);
    check_invariants(&points, Side::Left, &paper, &climbs);
    let top = climbs.points().iter().map(|p| p.y()).fold(0.0, f64::max);
    assert!(top > 1.4 + 0.3, "the paper's chain climbs {top}");
    let config = config();
    let chain = build_chain::<M>(&points, Side::Left, &config);
    check_invariants(&points, Side::Left, &config, &chain);
    check_minimal_contacts(&points, Side::Left, &config, &chain);
    assert_eq!(chain.end(), ChainEnd::Corner);
    assert!(chain.indices().iter().all(|&i| i < face));
    assert_eq!(
        *chain.indices().last().unwrap(),
        face - 1,
        "it stops at the corner"
    );
}

#[test]
fn circle_rolling_round_a_post_closes_or_stops() {
    // A post of radius 0.1 m at (1, 1.2), 24 points round it.
    let config = EdgeConfig::new(&EdgeParameters {
        max_rotation: 6.0,
        max_chain_length: 50.0,
        max_turn: core::f64::consts::PI,
        ..EdgeParameters::PIERRE2022
    })
    .unwrap();
    let points: Vec<_> = (0..24)
        .map(|k| {
            let a = f64::from(k) * core::f64::consts::TAU / 24.0;
            pt(1.0 + 0.1 * a.cos(), 1.2 + 0.1 * a.sin())
        })
        .collect();
    let chain = build_chain::<M>(&points, Side::Left, &config);
    check_invariants(&points, Side::Left, &config, &chain);
    assert_eq!(chain.end(), ChainEnd::Closed);
    assert_eq!(chain.len(), 24);
}

#[test]
fn nothing_within_the_search_distance_gives_no_chain() {
    let config = config();
    // 3 m search + 1 m radius: a wall 4.2 m away is out of reach, 3.8 m is in.
    let far = wall(Side::Left, 4.2, 0.0, 0.1, -1.0, 5.0);
    assert_eq!(
        build_chain::<M>(&far, Side::Left, &config).end(),
        ChainEnd::NoEdge
    );
    let near = wall(Side::Left, 3.8, 0.0, 0.1, -1.0, 5.0);
    assert!(!build_chain::<M>(&near, Side::Left, &config).is_empty());
    // Right side asked, only left points.
    assert_eq!(
        build_chain::<M>(&near, Side::Right, &config).end(),
        ChainEnd::NoEdge
    );
}

#[test]
fn a_full_buffer_stops_the_chain() {
    let config = config();
    let points = wall(Side::Left, 1.4, 0.0, 0.01, -1.0, 5.0);
    let chain = build_chain::<8>(&points, Side::Left, &config);
    assert_eq!(chain.end(), ChainEnd::Capacity);
    assert_eq!(chain.len(), 8);
    let none = build_chain::<0>(&points, Side::Left, &config);
    assert!(none.is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    //= spec/library.md#lib-bounded-tick-every-loop-of-a-tick-has-a-bound-fixed-before-the-first-tick
    //= type=test
    //# Every loop the core runs in one guidance tick MUST be bounded by the length
    //# of an input slice, a const-generic capacity or a count validated at
    //# configuration, so that the cost of the worst tick is known before the first
    //# tick.
    /// Dense scans, where the bounded sweep skips whole blocks of candidates
    /// (LIB-BOUNDED-TICK): a hedge seen by 512 rays over 60° with a few
    /// millimetres of noise, and a blob of 512 points within 0.4 m. The chain
    /// is the one of the closed-form contacts over every point.
    #[test]
    fn dense_scans_give_minimal_contacts(
        side in side(),
        face in 0.8..1.8f64,
        noise in prop::collection::vec(-0.003..0.003f64, 512),
        blob in prop::collection::vec((-0.4..0.4f64, -0.4..0.4f64), 512),
    ) {
        let s = side.sign();
        let hedge: Vec<_> = noise
            .iter()
            .enumerate()
            .map(|(k, n)| {
                let a = core::f64::consts::FRAC_PI_3 * (f64::from(u16::try_from(k).unwrap()) / 511.0 - 0.5);
                let range = face / a.cos() + n;
                pt(range * a.sin(), s * range * a.cos())
            })
            .collect();
        let blob: Vec<_> = blob.iter().map(|(x, y)| pt(0.3 + x, s * (1.2 + y))).collect();
        for points in [hedge, blob] {
            let chain = build_chain::<M>(&points, side, &config());
            prop_assert!(chain.len() >= 2);
            check_minimal_contacts(&points, side, &config(), &chain);
        }
    }
}

#[test]
fn more_points_than_the_candidate_buffer_still_give_minimal_contacts() {
    // 2000 points of a ragged wall within reach: beyond the 1024-point buffer.
    let config = config();
    let xs: Vec<f64> = (0..2000).map(|k| -1.0 + 0.003 * f64::from(k)).collect();
    let js: Vec<f64> = (0..2000)
        .map(|k| 0.05 * (f64::from(k) * 0.37).sin())
        .collect();
    let points = hedge(Side::Left, 1.4, 0.1, &xs, &js);
    let chain = build_chain::<M>(&points, Side::Left, &config);
    assert!(chain.len() > 10);
    check_invariants(&points, Side::Left, &config, &chain);
    check_minimal_contacts(&points, Side::Left, &config, &chain);
}

//= spec/pierre2022.md#edge-chain-rotate-next-point-by-rotation
//= type=test
//# The contact angle of a point q at distance 0 < d < 2r from the pivot MUST
//# be the smallest θ ≥ 0 at which |c(θ) − q| = r with q entering the disk,
//# where c(θ) is the centre rotated by s·θ about the pivot; a point at d = 0
//# or d ≥ 2r MUST have no contact.
#[test]
fn rotation_contact_by_hand() {
    use core::f64::consts::{FRAC_PI_6, PI, TAU};
    let r = Meters::new(1.0).unwrap();
    // Pivot (0, 1), centre (0, 0): a point 1 m ahead of the pivot enters
    // after π/2 − arccos(1/2) = π/6 of counter-clockwise rotation.
    let th = rotation_contact(pt(0.0, 1.0), pt(0.0, 0.0), pt(1.0, 1.0), Side::Left, r).unwrap();
    assert!((th.get() - FRAC_PI_6).abs() < 1e-12);
    // The centre rotated by θ about the pivot is the contact centre
    // (0.5, 1 − sqrt(0.75)), on the circle through the pivot and the point.
    let (sin, cos) = th.get().sin_cos();
    let (ux, uy) = (0.0, -1.0); // centre − pivot
    let (cx, cy) = (0.0 + cos * ux - sin * uy, 1.0 + sin * ux + cos * uy);
    assert!((cx - 0.5).abs() < 1e-12 && (cy - (1.0 - 0.75_f64.sqrt())).abs() < 1e-12);
    // The chain moves its circle to that centre: from the rear point, the
    // translation touches (0, 1) with the centre at (0, 0), and the rotation
    // about (0, 1) then touches (1, 1).
    let config = EdgeConfig::new(&EdgeParameters {
        max_link: 1.5,
        ..EdgeParameters::PIERRE2022
    })
    .unwrap();
    let points = [pt(0.0, 1.0), pt(1.0, 1.0)];
    let chain = build_chain::<M>(&points, Side::Left, &config);
    assert_eq!(chain.indices(), &[0, 1]);
    let c0 = chain.centers()[0];
    assert!(c0.x().abs() < 1e-12 && c0.y().abs() < 1e-12);
    let c = chain.centers()[1];
    assert!((c.x() - 0.5).abs() < 1e-12 && (c.y() - (1.0 - 0.75_f64.sqrt())).abs() < 1e-12);
    // Behind the pivot it enters only after 2π − π/3 − π/2 (past the top).
    let back = rotation_contact(pt(0.0, 1.0), pt(0.0, 0.0), pt(-1.0, 1.0), Side::Left, r).unwrap();
    assert!((back.get() - (TAU - PI / 3.0 - PI / 2.0)).abs() < 1e-12);
    // Mirrored: right side, clockwise.
    let m = rotation_contact(pt(0.0, -1.0), pt(0.0, 0.0), pt(1.0, -1.0), Side::Right, r).unwrap();
    assert!((m.get() - FRAC_PI_6).abs() < 1e-12);
    assert!(rotation_contact(pt(0.0, 1.0), pt(0.0, 0.0), pt(0.0, 1.0), Side::Left, r).is_none());
    assert!(rotation_contact(pt(0.0, 1.0), pt(0.0, 0.0), pt(2.0, 1.0), Side::Left, r).is_none());
}

//= spec/pierre2022.md#edge-chain-translate-first-point-by-translation
//= type=test
//# A point q strictly on the requested side (s·q_y > 0) with |q_x| ≤ r MUST
//# be touched at the translation t(q) = s·q_y − sqrt(r² − q_x²); other points
//# MUST NOT be touched by the translation.
#[test]
fn translation_contact_by_hand() {
    let r = Meters::new(1.0).unwrap();
    let t = translation_contact(pt(0.6, 2.0), Side::Left, r).unwrap();
    assert!((t.get() - 1.2).abs() < 1e-12);
    let t = translation_contact(pt(0.0, -0.5), Side::Right, r).unwrap();
    assert!((t.get() + 0.5).abs() < 1e-12);
    assert!(translation_contact(pt(0.0, -0.5), Side::Left, r).is_none());
    assert!(translation_contact(pt(1.5, 2.0), Side::Left, r).is_none());
    assert!(translation_contact(pt(0.5, 0.0), Side::Left, r).is_none());
}
