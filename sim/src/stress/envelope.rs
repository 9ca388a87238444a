//! The true line of a ragged hedge (README, "Choices beyond the papers").
//!
//! A rolling circle of radius r rests on the vertices that stand out most,
//! so the face the edge detector traces is the envelope of the circle
//! rolled along the face, not the nominal face the vertices scatter about.
//! The line at the desired distance D from every vertex (the clearance) is
//! the same construction with radius D: it lies up to a few centimetres
//! farther from the hedge than the envelope's offset line, where the circle
//! of radius r dips between two vertices.
//!
//! The envelope of a face ragged vertex by vertex wiggles on the scale of
//! its vertices, which no vehicle follows: a steered vehicle keeps a line
//! over its own length, and the detector fits one over its longest chain
//! l_max. The line the robot is judged against for its offset is therefore
//! the followed line: at each point of a piece of hedge, the least-squares
//! straight line of the envelope over l_max centred there, slid to stay
//! within the piece (the whole piece when it is shorter). How near the
//! robot comes to the hedge is still judged against the envelope itself.

use fieldguide::guidance::Mode;

use crate::guidance::pipeline::EDGE;
use crate::runner::TickRecord;
use crate::scenario::Setup;

/// How far into edge following the errors are measured from, m: the entry
/// transient is the switching machine's and the law's, not the line's.
pub const SETTLED_M: f64 = 3.0;

/// (along, across) of a world point in the frame of hedge `h` (across > 0
/// to the hedge's left); `None` without that hedge.
#[must_use]
pub fn hedge_frame(setup: &Setup, h: usize, x: f64, y: f64) -> Option<(f64, f64)> {
    let spec = &setup.world.hedges.get(h)?.spec;
    let (c, s) = (spec.heading.cos(), spec.heading.sin());
    let (dx, dy) = (x - spec.start[0], y - spec.start[1]);
    Some((dx * c + dy * s, -dx * s + dy * c))
}

/// Which face of hedge 0 the robot follows: `-1.0` for its right face
/// (across < 0, the robot starting to the hedge's right), `1.0` for its
/// left; `None` without a hedge.
#[must_use]
pub fn near_side(setup: &Setup) -> Option<f64> {
    let p = setup.initial.position;
    let (_, across) = hedge_frame(setup, 0, p.x(), p.y())?;
    Some(if across < 0.0 { -1.0 } else { 1.0 })
}

/// The vertices of the face of hedge 0 the robot follows ([`near_side`];
/// those within 1 m of the nominal face): (along, protrusion beyond the
/// nominal face), metres.
#[must_use]
pub fn near_face(setup: &Setup) -> Vec<(f64, f64)> {
    let (Some(hedge), Some(side)) = (setup.world.hedges.first(), near_side(setup)) else {
        return Vec::new();
    };
    let half = 0.5 * hedge.spec.thickness;
    setup
        .world
        .obstacles
        .segments
        .iter()
        .flat_map(|s| [s.a, s.b])
        .filter_map(|p| hedge_frame(setup, 0, p[0], p[1]))
        .map(|(along, across)| (along, side * across))
        .filter(|(_, out)| *out > 0.0 && *out < half + 1.0)
        .map(|(along, out)| (along, out - half))
        .collect()
}

/// How far the envelope of a face stands out beyond the nominal face at
/// along-hedge distance `u`: the largest p_v − (r − √(r² − d²)) over the
/// face's vertices v within r of `u` (d the along distance, p_v the
/// vertex's protrusion); `None` with no vertex within r.
#[must_use]
pub fn envelope(face: &[(f64, f64)], radius: f64, u: f64) -> Option<f64> {
    face.iter()
        .filter(|(a, _)| (a - u).abs() < radius)
        .map(|(a, p)| p - (radius - (radius * radius - (a - u).powi(2)).sqrt()))
        .reduce(f64::max)
}

/// Where the profile samples the face along the hedge, metres apart.
pub const SAMPLE_M: f64 = 0.02;

/// The face at one point along the hedge: how far its envelope stands out
/// beyond the nominal face ([`envelope`]) and how far the followed line
/// does, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FacePoint {
    /// Along-hedge distance, metres.
    pub along: f64,
    /// The envelope's protrusion beyond the nominal face, metres.
    pub envelope: f64,
    /// The followed line's protrusion there, metres.
    pub followed: f64,
}

/// The pieces of a hedge between its gaps: (start, end) along it, metres.
#[must_use]
pub fn pieces(length: f64, gaps: &[[f64; 2]]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut start = 0.0;
    for g in gaps {
        if g[0] > start {
            out.push((start, g[0]));
        }
        start = g[1];
    }
    if length > start {
        out.push((start, length));
    }
    out
}

/// The followed line over one piece: for each sampled (along, envelope) of
/// the piece, in order, the least-squares line of the samples within
/// `window` metres centred on it, the window slid to stay within the piece
/// (all of them when the piece is shorter), evaluated there.
#[must_use]
pub fn followed(samples: &[(f64, f64)], window: f64) -> Vec<f64> {
    let (Some(first), Some(last)) = (samples.first(), samples.last()) else {
        return Vec::new();
    };
    let (start, end) = (first.0, last.0);
    // Prefix sums of 1, u, e, u², u e, with u from the piece's start.
    let mut sums = vec![[0.0; 5]];
    for &(u, e) in samples {
        let (u, prev) = (u - start, sums[sums.len() - 1]);
        sums.push([
            prev[0] + 1.0,
            prev[1] + u,
            prev[2] + e,
            prev[3] + u * u,
            prev[4] + u * e,
        ]);
    }
    samples
        .iter()
        .map(|&(u, e)| {
            let a = (u - 0.5 * window).min(end - window).max(start);
            let lo = samples.partition_point(|s| s.0 < a - 1e-9);
            let hi = samples.partition_point(|s| s.0 <= a + window + 1e-9);
            let [n, su, se, suu, sue] = [0, 1, 2, 3, 4].map(|k| sums[hi][k] - sums[lo][k]);
            let det = n * suu - su * su;
            if n < 2.0 || det.abs() < 1e-12 {
                return e;
            }
            let slope = (n * sue - su * se) / det;
            let at = (se - slope * su) / n;
            at + slope * (u - start)
        })
        .collect()
}

/// The profile of hedge 0's near face, sampled every [`SAMPLE_M`] where
/// the hedge is present: its envelope for a circle of radius `radius` and
/// the followed line over `window` metres; empty without a hedge.
#[must_use]
pub fn profile(setup: &Setup, radius: f64, window: f64) -> Vec<FacePoint> {
    let Some(hedge) = setup.world.hedges.first() else {
        return Vec::new();
    };
    let spec = &hedge.spec;
    let face = near_face(setup);
    let mut out = Vec::new();
    for (start, end) in pieces(spec.length, &spec.gaps) {
        let steps = ((end - start) / SAMPLE_M).floor() as usize;
        let samples: Vec<(f64, f64)> = (0..=steps)
            .map(|k| (start + k as f64 * SAMPLE_M).min(end))
            .filter_map(|u| envelope(&face, radius, u).map(|e| (u, e)))
            .collect();
        let line = followed(&samples, window);
        out.extend(
            samples
                .iter()
                .zip(line)
                .map(|(&(along, envelope), followed)| FacePoint {
                    along,
                    envelope,
                    followed,
                }),
        );
    }
    out
}

/// The robot's controlled point against the face at one tick, metres,
/// positive away from the hedge (clearance beyond the offset), negative
/// towards it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceErrors {
    /// Along-hedge distance of the controlled point, metres.
    pub along: f64,
    /// Error to the envelope's offset line.
    pub envelope: f64,
    /// Error to the followed line's offset line.
    pub followed: f64,
}

/// The errors of the robot's controlled point to the offset lines of the
/// face of hedge 0 it follows ([`near_side`]), over the ticks in
/// edge following at least [`SETTLED_M`] after entering it with the hedge
/// present abeam; empty without a hedge or edge following. The followed
/// line is fitted over the detector's longest chain l_max.
#[must_use]
pub fn face_errors(setup: &Setup, trace: &[TickRecord]) -> Vec<FaceErrors> {
    let (Some(hedge), Some(edge)) = (setup.world.hedges.first(), setup.edge.as_ref()) else {
        return Vec::new();
    };
    let spec = &hedge.spec;
    let half = 0.5 * spec.thickness;
    let detector = &edge.detector;
    let offset = detector.offset().get();
    let (face, Some(side)) = (near_face(setup), near_side(setup)) else {
        return Vec::new();
    };
    let profile = profile(
        setup,
        detector.radius().get(),
        detector.max_chain_length().get(),
    );
    let mut errors = Vec::new();
    let mut since_entry = 0.0;
    for w in trace.windows(2) {
        let [a, b] = w else { continue };
        since_entry = if a.command.switching_mode == Mode::Behaviour(EDGE) {
            since_entry + (b.distance_m - a.distance_m)
        } else {
            0.0
        };
        if since_entry <= SETTLED_M {
            continue;
        }
        let Some((u, across)) = hedge_frame(setup, 0, a.truth.position.x(), a.truth.position.y())
        else {
            continue;
        };
        if !(0.0..=spec.length).contains(&u) || !spec.is_present(u) {
            continue;
        }
        let k = profile.partition_point(|p| p.along < u);
        let nearest = [k.checked_sub(1), Some(k)]
            .into_iter()
            .flatten()
            .filter_map(|i| profile.get(i))
            .filter(|p| (p.along - u).abs() <= SAMPLE_M)
            .min_by(|p, q| (p.along - u).abs().total_cmp(&(q.along - u).abs()));
        if let (Some(p), Some(e)) = (nearest, envelope(&face, detector.radius().get(), u)) {
            let beyond = (side * across - half) - offset;
            errors.push(FaceErrors {
                along: u,
                envelope: beyond - e,
                followed: beyond - p.followed,
            });
        }
    }
    errors
}

#[cfg(test)]
mod tests {
    use super::{followed, pieces};

    fn sampled(from: f64, to: f64, e: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
        let n = ((to - from) / 0.02).round() as usize;
        (0..=n)
            .map(|k| from + k as f64 * 0.02)
            .map(|u| (u, e(u)))
            .collect()
    }

    #[test]
    fn the_pieces_lie_between_the_gaps() {
        assert_eq!(
            pieces(10.0, &[[2.0, 3.0], [6.0, 7.5]]),
            vec![(0.0, 2.0), (3.0, 6.0), (7.5, 10.0)]
        );
        assert_eq!(pieces(10.0, &[[0.0, 1.0], [9.0, 10.0]]), vec![(1.0, 9.0)]);
        assert_eq!(pieces(4.0, &[]), vec![(0.0, 4.0)]);
    }

    /// A straight envelope is its own followed line, tilted or not.
    #[test]
    fn a_straight_envelope_is_followed_exactly() {
        let s = sampled(3.0, 9.0, |u| 0.1 - 0.02 * u);
        for ((_, e), f) in s.iter().zip(followed(&s, 3.0)) {
            assert!((e - f).abs() < 1e-9, "{e} {f}");
        }
    }

    /// A wiggle shorter than the window is straightened out; one longer is
    /// followed: the followed line is a vehicle's line, not a low pass that
    /// flattens every bend.
    #[test]
    fn wiggles_shorter_than_the_window_are_straightened() {
        let short = sampled(0.0, 12.0, |u| {
            0.1 * (u * core::f64::consts::TAU / 0.6).sin()
        });
        let f = followed(&short, 3.0);
        let worst = |f: &[f64]| f.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
        // Within 0.01 m of straight where the window is centred, 0.025 m
        // (a quarter of the amplitude) where it slides at the piece's ends.
        assert!(
            worst(&f[75..f.len() - 75]) < 0.01,
            "{}",
            worst(&f[75..f.len() - 75])
        );
        assert!(worst(&f) < 0.025, "{}", worst(&f));
        let long = sampled(0.0, 60.0, |u| {
            0.1 * (u * core::f64::consts::TAU / 30.0).sin()
        });
        let f = followed(&long, 3.0);
        let worst = long
            .iter()
            .zip(&f)
            .skip(100)
            .take(2800)
            .map(|((_, e), f)| (e - f).abs())
            .fold(0.0, f64::max);
        assert!(worst < 0.002, "{worst}");
    }

    /// At a piece's ends the window slides inside the piece: a straight
    /// piece stays exact to its ends, and a piece shorter than the window
    /// is fitted whole.
    #[test]
    fn the_window_stays_within_the_piece() {
        let s = sampled(5.0, 10.0, |u| 0.3 * u - 2.0);
        let f = followed(&s, 3.0);
        assert!((f[0] - s[0].1).abs() < 1e-9 && (f[f.len() - 1] - s[s.len() - 1].1).abs() < 1e-9);
        let step = sampled(0.0, 2.0, |u| if u < 1.0 { 0.0 } else { 0.1 });
        let f = followed(&step, 3.0);
        // The whole piece's least-squares line: through the mean, 0.05 at 1 m.
        assert!((f[50] - 0.05).abs() < 2e-3, "{}", f[50]);
        assert!(followed(&[], 3.0).is_empty());
    }
}
