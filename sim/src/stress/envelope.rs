//! The true line of a ragged hedge: the offset line of its face's envelope
//! (README, "Choices beyond the papers"). A rolling circle of radius r
//! rests on the vertices that stand out most, so the face the edge detector
//! traces is the envelope of the circle rolled along the face, not the
//! nominal face the vertices scatter about. The line at the desired
//! distance D from every vertex (the clearance) is the same construction
//! with radius D: it lies up to a few centimetres farther from the hedge
//! than this line, where the circle of radius r dips between two vertices.

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

/// The vertices of hedge 0's right face (the near one, within 1 m of it):
/// (along, protrusion beyond the nominal face), metres.
#[must_use]
pub fn near_face(setup: &Setup) -> Vec<(f64, f64)> {
    let Some(hedge) = setup.world.hedges.first() else {
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
        .filter(|(_, across)| *across < 0.0 && *across > -half - 1.0)
        .map(|(along, across)| (along, -across - half))
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

/// The errors of the robot's controlled point to the envelope's offset
/// line of hedge 0's right face (the robot follows it on its left), over
/// the ticks in edge following at least [`SETTLED_M`] after entering it with
/// the hedge present abeam, metres, positive away from the hedge (clearance
/// beyond the offset), negative towards it; empty without a hedge or edge
/// following.
#[must_use]
pub fn envelope_errors(setup: &Setup, trace: &[TickRecord]) -> Vec<f64> {
    let (Some(hedge), Some(edge)) = (setup.world.hedges.first(), setup.edge.as_ref()) else {
        return Vec::new();
    };
    let spec = &hedge.spec;
    let half = 0.5 * spec.thickness;
    let (radius, offset) = (edge.detector.radius().get(), edge.detector.offset().get());
    let face = near_face(setup);
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
        if let Some(e) = envelope(&face, radius, u) {
            errors.push((-half - across) - offset - e);
        }
    }
    errors
}
