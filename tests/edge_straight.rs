//! The chain read as a straight line (`spec/pierre2022.md`, EDGE-STRAIGHT,
//! beyond Pierre 2022 section 2.2): synthetic scans of a straight hedge's
//! last metres whose face dips before the piece's end, with the straight
//! reading on and off.
#![allow(clippy::unwrap_used, clippy::indexing_slicing, clippy::panic)]

mod edge_support;

use edge_support::pt;
use fieldguide::geometry::fit::{fit_line, ParabolaFit};
use fieldguide::perception::edge::{
    detect_points, tracking_error, EdgeConfig, EdgeDetection, EdgeParameters, Side,
};
use fieldguide::perception::Verdict;
use fieldguide::{Point2, Robot};

const M: usize = 128;

/// The stress fields' detector (x_ahead = 0.5 m), read straight when `on`.
fn params(on: bool) -> EdgeParameters {
    EdgeParameters {
        max_start_ahead: 0.5,
        straight: on,
        ..EdgeParameters::PIERRE2022
    }
}

fn detect(points: &[Point2<Robot>], side: Side, p: &EdgeParameters) -> EdgeDetection<M> {
    detect_points::<M>(points, side, &EdgeConfig::new(p).unwrap()).unwrap()
}

/// The vertices of a ragged face's last metres before a piece's end at
/// x = 2.7 m, (x, distance from the robot's x axis): 1.4 m, then 0.2 m
/// deeper between x = 1.6 and 2.1 m and back out to 1.42 m at the end, as
/// the chain of `hedge-ragged.toml`, seed 7, 2.7 m before a piece's end.
const FACE: [(f64, f64); 12] = [
    (-1.0, 1.40),
    (0.05, 1.415),
    (0.30, 1.38),
    (0.73, 1.43),
    (0.95, 1.443),
    (1.02, 1.483),
    (1.64, 1.632),
    (2.04, 1.585),
    (2.17, 1.555),
    (2.42, 1.505),
    (2.62, 1.417),
    (2.70, 1.422),
];

/// That piece on `side`: its face sampled every 2 cm along the segments
/// between [`FACE`]'s vertices, with an end wall 1 m deep; nothing beyond.
fn piece_end(side: Side) -> Vec<Point2<Robot>> {
    let s = side.sign();
    let mut points = Vec::new();
    for w in FACE.windows(2) {
        let [(x0, y0), (x1, y1)] = [w[0], w[1]];
        let mut x = x0;
        while x < x1 - 1e-9 {
            points.push(pt(x, s * (y0 + (x - x0) / (x1 - x0) * (y1 - y0))));
            x += 0.02;
        }
    }
    for k in 0..20 {
        points.push(pt(2.7, s * (1.422 + 0.05 * f64::from(k))));
    }
    points
}

//= spec/pierre2022.md#edge-straight-the-chain-read-as-a-straight-line
//= type=test
//# When the straight reading is on, a fitted chain MUST be read as the
//# parabola with a = 0 whose b and c are those of the least-squares
//# straight line y = b x + c through the chain points, for its errors
//# (EDGE-ERRORS, EDGE-OFFSET), its residual (EDGE-QUALITY) and the line
//# held between scans.
#[test]
fn before_a_piece_end_the_straight_line_keeps_the_face_heading() {
    for side in [Side::Left, Side::Right] {
        let points = piece_end(side);
        let on = detect(&points, side, &params(true));
        let off = detect(&points, side, &params(false));
        let (f_on, f_off) = (on.fit.unwrap(), off.fit.unwrap());
        // The same chain, read two ways.
        assert_eq!(on.chain.points(), off.chain.points());
        // Read straight: the chain's least-squares line, a = 0.
        let line = fit_line(on.chain.points().iter()).unwrap();
        assert_eq!(
            f_on.parabola,
            ParabolaFit {
                a: 0.0,
                b: line.a,
                c: line.b
            }
        );
        let config = EdgeConfig::new(&params(true)).unwrap();
        assert_eq!(
            f_on.error,
            tracking_error(&f_on.parabola, side, config.offset(), 0.0).unwrap()
        );
        let n = f64::from(u32::try_from(on.chain.len()).unwrap());
        let rms = (on
            .chain
            .points()
            .iter()
            .map(|p| (p.y() - line.a * p.x() - line.b).powi(2))
            .sum::<f64>()
            / n)
            .sqrt();
        assert!((f_on.quality.residual_std.get() - rms).abs() < 1e-12);
        assert!(matches!(on.verdict, Verdict::Enter | Verdict::Hold));
        // The face's own least-squares line over the chain's extent (what
        // the followed line is): the straight reading is within 2 cm and
        // 0.02 rad of it (1 cm and 0.006 rad); the parabola, bent by the
        // dip, more than 0.15 m and 0.2 rad off it at the robot (0.20 m
        // and 0.26 rad).
        let (from, to) = (on.chain.points()[0].x(), 2.7 - 1e-9);
        let truth = fit_line(points.iter().filter(|p| (from..to).contains(&p.x()))).unwrap();
        let truth = ParabolaFit {
            a: 0.0,
            b: truth.a,
            c: truth.b,
        };
        let truth = tracking_error(&truth, side, config.offset(), 0.0).unwrap();
        let apart = |e: &fieldguide::TrackingError| {
            (
                (e.y.get() - truth.y.get()).abs(),
                (e.angular_deviation.get() - truth.angular_deviation.get()).abs(),
            )
        };
        eprintln!(
            "{side:?}: straight {:?}, parabola {:?} off the face's line",
            apart(&f_on.error),
            apart(&f_off.error)
        );
        let (dy, dt) = apart(&f_on.error);
        assert!(dy < 0.02 && dt < 0.02, "{dy} {dt}");
        let (dy, dt) = apart(&f_off.error);
        assert!(dy > 0.15 && dt > 0.2, "{dy} {dt}");
    }
}

/// Off (the default, the paper's detector), a curved face keeps its
/// parabola's curvature.
#[test]
fn off_by_default_the_parabola_is_kept() {
    const { assert!(!EdgeParameters::PIERRE2022.straight) };
    let side = Side::Left;
    // A face curving away: y = 1.4 + 0.1 x².
    let points: Vec<Point2<Robot>> = (0..=60)
        .map(|k| {
            let x = -0.5 + 0.05 * f64::from(k);
            pt(x, 1.4 + 0.1 * x * x)
        })
        .collect();
    let off = detect(&points, side, &EdgeParameters::PIERRE2022);
    let a = off.fit.unwrap().parabola.a;
    assert!((a - 0.1).abs() < 0.01, "{a}");
    let on = detect(&points, side, &params(true));
    assert!(on.fit.unwrap().parabola.a.abs() < f64::MIN_POSITIVE);
}
