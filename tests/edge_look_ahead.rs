//! The next piece's line seen ahead (`spec/pierre2022.md`, EDGE-LOOK-AHEAD,
//! beyond Pierre 2022 section 2.2): synthetic scans of a hedge broken by a
//! 2 m gap, the robot in the gap, with the look-ahead on and off.
#![allow(clippy::unwrap_used, clippy::indexing_slicing, clippy::panic)]

mod edge_support;

use edge_support::pt;
use fieldguide::geometry::fit::fit_line;
use fieldguide::perception::edge::{
    build_chain, detect_points, Chain, EdgeConfig, EdgeDetection, EdgeParameters, LookAhead, Side,
};
use fieldguide::{Point2, Pose2, Robot};

const M: usize = 128;

/// The stress fields' detector: x_ahead = 0.5 m, and the look-ahead of
/// [`LookAhead::HEDGE`] when `on`.
fn params(on: bool) -> EdgeParameters {
    EdgeParameters {
        max_start_ahead: 0.5,
        look_ahead: on.then_some(LookAhead::HEDGE),
        ..EdgeParameters::PIERRE2022
    }
}

/// The lateral offset of the face of the next piece at `x`: 1.6 m and a
/// slope of 0.03, with a ragged `jitter(x)`.
fn face(x: f64, jitter: &dyn Fn(f64) -> f64) -> f64 {
    1.6 + 0.03 * x + jitter(x)
}

/// A hedge on `side`: a piece whose face, 1.4 m off, ends at x = -0.8 m
/// with an end wall 1 m deep; a 2 m gap; when `next_to` is given, the next
/// piece from x = 1.2 m to `next_to`, its face at [`face`], with its end
/// wall 1 m deep at its start.
fn gap_scene(side: Side, next_to: Option<f64>, jitter: &dyn Fn(f64) -> f64) -> Vec<Point2<Robot>> {
    let s = side.sign();
    let mut points = Vec::new();
    for k in 0..=64 {
        points.push(pt(-4.0 + 0.05 * f64::from(k), s * 1.4));
    }
    for k in 1..20 {
        points.push(pt(-0.8, s * (1.4 + 0.05 * f64::from(k))));
    }
    if let Some(to) = next_to {
        let start = face(1.2, jitter);
        for k in 1..20 {
            points.push(pt(1.2, s * (start + 0.05 * f64::from(k))));
        }
        let mut x = 1.2;
        while x <= to + 1e-9 {
            points.push(pt(x, s * face(x, jitter)));
            x += 0.05;
        }
    }
    points
}

fn none(_: f64) -> f64 {
    0.0
}

/// ±4 cm bumps every 0.5 m.
fn ragged(x: f64) -> f64 {
    0.04 * (x * 4.0 * core::f64::consts::PI).sin()
}

/// A face waving ±8 cm over 1.6 m: the chain follows it.
fn wavy(x: f64) -> f64 {
    0.08 * (x * 2.0 * core::f64::consts::PI / 1.6).sin()
}

fn detect(points: &[Point2<Robot>], side: Side, p: &EdgeParameters) -> EdgeDetection<M> {
    detect_points::<M>(points, side, &EdgeConfig::new(p).unwrap()).unwrap()
}

/// The signed distance of `q` from the next piece's straight face line
/// (without jitter), positive to the line's left, and that line's heading.
fn from_face(q: &Pose2<Robot>, side: Side) -> (f64, f64) {
    let s = side.sign();
    let heading = (s * 0.03_f64).atan();
    let (dx, dy) = (q.position.x(), q.position.y() - s * 1.6);
    (-dx * heading.sin() + dy * heading.cos(), heading)
}

//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//= type=test
//# The detection MUST then report, besides its own verdict and fit, the
//# point of the line at the desired distance D from that straight line on
//# the robot's side, abeam the middle of the points' extent along x, with
//# the line's heading arctan a; otherwise, and when the look-ahead is off
//# or the verdict is Enter or Hold, it MUST report none.
#[test]
fn across_a_gap_the_next_piece_line_is_seen_at_the_offset() {
    for side in [Side::Left, Side::Right] {
        let points = gap_scene(side, Some(6.0), &none);
        let on = detect(&points, side, &params(true));
        assert!(!on.verdict.estimate_is_valid(), "{:?}", on.verdict);
        let q = on.ahead.unwrap();
        let (distance, heading) = from_face(&q, side);
        // On the followed line: D = 1.4 m from the face, on the robot's side.
        assert!(
            (distance + side.sign() * 1.4).abs() < 1e-6,
            "{side:?}: {distance}"
        );
        assert!((q.heading.get() - heading).abs() < 1e-6, "{q:?}");
        // Beyond the end cap, within the piece: not the robot's abscissa.
        assert!(q.position.x() > 1.7 && q.position.x() < 6.0, "{q:?}");
        // The detection's own verdict and fit are those without the look-ahead.
        let off = detect(&points, side, &params(false));
        assert_eq!(off.ahead, None, "{side:?}: off");
        assert_eq!((on.verdict, on.fit), (off.verdict, off.fit));
        // Beside an unbroken face the verdict is valid: nothing ahead.
        let beside = gap_scene(side, Some(6.0), &none)
            .into_iter()
            .filter(|p| p.x() > 1.0)
            .map(|p| pt(p.x() - 3.0, p.y()))
            .collect::<Vec<_>>();
        let along = detect(&beside, side, &params(true));
        assert!(along.verdict.estimate_is_valid(), "{:?}", along.verdict);
        assert_eq!(along.ahead, None);
    }
}

//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//= type=test
//# When the look-ahead is on and the verdict of a detection is not Enter or
//# Hold, the detector MUST build chains as in EDGE-CHAIN-TRANSLATE,
//# EDGE-CHAIN-ROTATE and EDGE-CHAIN-STOP with the circle's translation
//# starting at (k Δx, 0) instead of the robot's rear point, for k = 1, 2, …
//# while k Δx ≤ x_far, and take the first of them that has a point.
#[test]
fn the_line_is_that_of_the_first_chain_of_the_points_shifted_back() {
    let config = EdgeConfig::new(&params(true)).unwrap();
    for side in [Side::Left, Side::Right] {
        let points = gap_scene(side, Some(6.0), &ragged);
        // The oracle: the scan's points shifted back by k Δx, chained from
        // the robot's rear point by the library's own chain.
        let (dx, chain) = (1..=8)
            .map(|k| {
                let dx = 0.5 * f64::from(k);
                let shifted: Vec<_> = points.iter().map(|p| pt(p.x() - dx, p.y())).collect();
                (dx, build_chain::<M>(&shifted, side, &config))
            })
            .find(|(_, c): &(f64, Chain<M>)| !c.is_empty())
            .unwrap();
        let first = chain.points()[0].x();
        let part: Vec<_> = chain
            .points()
            .iter()
            .filter(|p| p.x() > first + 0.5)
            .map(|p| pt(p.x() + dx, p.y()))
            .collect();
        let line = fit_line(part.iter()).unwrap();
        let (lo, hi) = part.iter().fold((f64::MAX, f64::MIN), |(l, h), p| {
            (l.min(p.x()), h.max(p.x()))
        });
        let x = (lo + hi) / 2.0;
        let phi = line.a.atan();
        let s = side.sign();
        let expected = (
            x + s * 1.4 * phi.sin(),
            line.a * x + line.b - s * 1.4 * phi.cos(),
        );
        let q = detect(&points, side, &params(true)).ahead.unwrap();
        assert!(
            (q.position.x() - expected.0).abs() < 1e-9
                && (q.position.y() - expected.1).abs() < 1e-9
                && (q.heading.get() - phi).abs() < 1e-9,
            "{side:?}: {q:?} against {expected:?}"
        );
        // The circle touches the bumps nearest the robot: the line lies
        // at the offset from them, within their 4 cm.
        let (distance, _) = from_face(&q, side);
        assert!((distance + s * 1.4).abs() < 0.045, "{distance}");
    }
}

//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//= type=test
//# The points of that chain lying more than l_cap along x beyond its first
//# point MUST give the next piece's line only when they are at least the
//# fewest chain points, span at least l_fit along x, and the residual
//# standard deviation of their least-squares straight line y = a x + b is
//# graded Enter or Hold by σ_edge and σ_path.
#[test]
fn no_next_piece_a_short_one_or_a_ragged_one_gives_nothing() {
    for side in [Side::Left, Side::Right] {
        // Nothing within 4 m + r ahead.
        let alone = gap_scene(side, None, &none);
        let det = detect(&alone, side, &params(true));
        assert!(!det.verdict.estimate_is_valid());
        assert_eq!(det.ahead, None, "{side:?}: no next piece");
        // The next piece 0.8 m long: 0.3 m beyond its end cap.
        let short = gap_scene(side, Some(2.0), &none);
        assert_eq!(
            detect(&short, side, &params(true)).ahead,
            None,
            "{side:?}: short"
        );
        // 2.3 m long: enough once l_fit is 1 m, not at 2 m.
        let longer = gap_scene(side, Some(3.5), &none);
        assert!(detect(&longer, side, &params(true)).ahead.is_some());
        let mut span = params(true);
        span.look_ahead = Some(LookAhead {
            min_span: 2.0,
            ..LookAhead::HEDGE
        });
        assert_eq!(detect(&longer, side, &span).ahead, None);
        // A wavy face graded Exit (σ_path = 1 cm) gives nothing; its
        // straight twin does.
        let strict = EdgeParameters {
            sigma_enter: 0.005,
            sigma_exit: 0.01,
            ..params(true)
        };
        let bumpy = gap_scene(side, Some(6.0), &wavy);
        assert_eq!(detect(&bumpy, side, &strict).ahead, None, "{side:?}");
        let straight = gap_scene(side, Some(6.0), &none);
        assert!(detect(&straight, side, &strict).ahead.is_some());
        // Too few points for the fewest chain points.
        let many = EdgeParameters {
            min_points: 60,
            ..params(true)
        };
        assert_eq!(detect(&straight, side, &many).ahead, None);
    }
}

//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//= type=test
//# A configuration with the look-ahead on MUST be refused with
//# `EDGE-LOOK-AHEAD` unless l_cap ≥ 0, Δx > 0, Δx ≤ x_far ≤ 64 Δx and
//# l_fit > 0, every value finite.
#[test]
fn look_ahead_parameters_out_of_their_domain_are_refused() {
    // Each case: one parameter of LookAhead::HEDGE replaced.
    let with = |field: &str, v: f64| {
        let mut a = LookAhead::HEDGE;
        match field {
            "end_cap" => a.end_cap = v,
            "step" => a.step = v,
            "farthest" => a.farthest = v,
            _ => a.min_span = v,
        }
        a
    };
    let cases = [
        ("end_cap", 0.5, true),
        ("end_cap", 0.0, true),
        ("end_cap", -0.1, false),
        ("end_cap", f64::NAN, false),
        ("step", 0.0, false),
        ("step", -0.5, false),
        ("step", f64::INFINITY, false),
        ("farthest", 0.5, true),
        ("farthest", 0.4, false),
        ("farthest", 32.0, true),
        ("farthest", 32.5, false),
        ("farthest", f64::NAN, false),
        ("min_span", 0.0, false),
        ("min_span", f64::INFINITY, false),
    ]
    .map(|(field, v, ok)| (with(field, v), ok));
    for (look, ok) in cases {
        let result = EdgeConfig::new(&EdgeParameters {
            look_ahead: Some(look),
            ..EdgeParameters::PIERRE2022
        });
        match (result, ok) {
            (Ok(c), true) => assert_eq!(c.look_ahead(), Some(&look)),
            (Err(e), false) => assert_eq!(e.requirement, "EDGE-LOOK-AHEAD", "{look:?}"),
            (r, _) => panic!("{look:?}: {r:?}"),
        }
    }
    // Off: nothing to check.
    assert_eq!(EdgeConfig::pierre2022().unwrap().look_ahead(), None);
}
