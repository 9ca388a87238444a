//! A chain that sees a piece's end is not followed (`spec/pierre2022.md`,
//! EDGE-PIECE-END, beyond Pierre 2022 section 2.2): synthetic scans of a
//! hedge piece that ends (its face, then its end wall and a gap) and of one
//! that starts ahead of the robot, with the rule on and off.
#![allow(clippy::unwrap_used, clippy::indexing_slicing, clippy::panic)]

mod edge_support;

use edge_support::{pt, wall};
use fieldguide::perception::edge::{
    detect_points, ChainEnd, EdgeConfig, EdgeDetection, EdgeParameters, Side,
};
use fieldguide::{Point2, Robot, Verdict};

const M: usize = 128;

/// The rule on: l_end = 2.5 m, x_ahead = 0.5 m.
fn with_rule() -> EdgeConfig {
    EdgeConfig::new(&EdgeParameters {
        min_end_chain_length: 2.5,
        max_start_ahead: 0.5,
        ..EdgeParameters::PIERRE2022
    })
    .unwrap()
}

/// A piece of hedge on `side` whose face, 1.4 m off, runs from x = `from`
/// to x = `to`, with a bump of 0.1 m towards the robot over its last 0.4 m
/// and an end wall 1 m deep at x = `to`; nothing beyond (a gap).
fn piece(side: Side, from: f64, to: f64) -> Vec<Point2<Robot>> {
    let s = side.sign();
    let mut points: Vec<Point2<Robot>> = wall(side, 1.4, 0.0, 0.05, from, to)
        .into_iter()
        .map(|p| {
            if p.x() > to - 0.4 {
                pt(p.x(), p.y() - s * 0.1)
            } else {
                p
            }
        })
        .collect();
    let mut d = 0.05;
    while d < 1.0 {
        points.push(pt(to, s * (1.4 + d)));
        d += 0.05;
    }
    points
}

fn usable(det: &EdgeDetection<M>) -> bool {
    det.usable_error().is_some()
}

//= spec/pierre2022.md#edge-piece-end-a-chain-at-a-piece-s-end-is-not-followed
//= type=test
//# A fitted chain MUST be graded Exit when it stopped at a gap, a corner or
//# the rotation limit while its length is not greater than l_end, or when
//# its first point lies more than x_ahead ahead of the robot (p_x > x_ahead).
#[test]
fn a_short_chain_stopped_at_a_piece_end_is_exit() {
    for side in [Side::Left, Side::Right] {
        // The piece ends 2 m ahead: the chain stops at its end, 2 m long.
        let points = piece(side, -1.0, 2.0);
        let paper = detect_points::<M>(&points, side, &EdgeConfig::pierre2022().unwrap()).unwrap();
        assert!(
            matches!(
                paper.chain.end(),
                ChainEnd::Gap | ChainEnd::Corner | ChainEnd::RotationLimit
            ),
            "{:?}",
            paper.chain.end()
        );
        let length = paper.fit.unwrap().quality.length.get();
        assert!(length > 1.5 && length <= 2.5, "{length}");
        assert!(
            usable(&paper),
            "the paper's detector follows it: {:?}",
            paper.verdict
        );
        let ruled = detect_points::<M>(&points, side, &with_rule()).unwrap();
        assert_eq!(ruled.verdict, Verdict::Exit);
        assert!(ruled.fit.is_some() && !usable(&ruled));
        // Just over l_end, the same chain is followed again.
        let shorter = EdgeConfig::new(&EdgeParameters {
            min_end_chain_length: length - 0.01,
            ..EdgeParameters::PIERRE2022
        })
        .unwrap();
        assert!(usable(
            &detect_points::<M>(&points, side, &shorter).unwrap()
        ));
    }
}

//= spec/pierre2022.md#edge-piece-end-a-chain-at-a-piece-s-end-is-not-followed
//= type=test
//# A fitted chain MUST be graded Exit when it stopped at a gap, a corner or
//# the rotation limit while its length is not greater than l_end, or when
//# its first point lies more than x_ahead ahead of the robot (p_x > x_ahead).
#[test]
fn a_long_chain_and_a_chain_abeam_keep_their_verdicts_and_one_ahead_is_exit() {
    for side in [Side::Left, Side::Right] {
        // A long face: the chain stops at l_max, not at a break.
        let long = wall(side, 1.4, 0.0, 0.05, -1.0, 8.0);
        let det = detect_points::<M>(&long, side, &with_rule()).unwrap();
        assert_eq!(det.chain.end(), ChainEnd::LengthLimit);
        assert_eq!(det.verdict, Verdict::Enter);
        // A piece that starts 0.8 m ahead of the robot: its first contact is
        // there, past x_ahead.
        let ahead = wall(side, 1.4, 0.0, 0.05, 0.8, 8.0);
        let paper = detect_points::<M>(&ahead, side, &EdgeConfig::pierre2022().unwrap()).unwrap();
        assert!(paper.chain.points()[0].x() > 0.5);
        assert!(
            usable(&paper),
            "{:?} {:?} {:?}",
            paper.verdict,
            paper.chain.end(),
            paper.fit
        );
        let ruled = detect_points::<M>(&ahead, side, &with_rule()).unwrap();
        assert_eq!(ruled.verdict, Verdict::Exit);
        // Starting 0.3 m ahead is within x_ahead.
        let near = wall(side, 1.4, 0.0, 0.05, 0.3, 8.0);
        let det = detect_points::<M>(&near, side, &with_rule()).unwrap();
        assert!(det.chain.points()[0].x() <= 0.5);
        assert_eq!(det.verdict, Verdict::Enter);
    }
}

//= spec/pierre2022.md#edge-piece-end-a-chain-at-a-piece-s-end-is-not-followed
//= type=test
//# A configuration MUST be refused with `EDGE-CONFIG` unless l_end ≥ 0 and
//# x_ahead > 0, both finite.
#[test]
fn bad_piece_end_parameters_are_refused() {
    let good = EdgeParameters::PIERRE2022;
    for (l_end, x_ahead, ok) in [
        (0.0, f64::MAX, true),
        (2.5, 0.5, true),
        (-0.1, 0.5, false),
        (f64::NAN, 0.5, false),
        (f64::INFINITY, 0.5, false),
        (2.5, 0.0, false),
        (2.5, -1.0, false),
        (2.5, f64::NAN, false),
        (2.5, f64::INFINITY, false),
    ] {
        let result = EdgeConfig::new(&EdgeParameters {
            min_end_chain_length: l_end,
            max_start_ahead: x_ahead,
            ..good
        });
        match (result, ok) {
            (Ok(_), true) => {}
            (Err(e), false) => assert_eq!(e.requirement, "EDGE-CONFIG"),
            (r, _) => panic!("l_end {l_end}, x_ahead {x_ahead}: {r:?}"),
        }
    }
}
