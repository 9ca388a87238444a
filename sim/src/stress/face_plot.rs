//! A ragged hedge's worst seed drawn as the campaign judges it: the robot's
//! error along the hedge to the followed line and to the envelope's offset
//! line ([`super::envelope`]), with the bounds, the gaps and the worst ticks
//! marked. The run's `lateral_error.svg` shows the error to the nominal
//! face's offset line, which is not the one judged.

use crate::output::plots::shade;
use crate::output::svg::{Axes, Stroke, Svg};

use super::envelope::FaceErrors;

/// The file written beside a kept run's plots.
pub const FACE_FILE: &str = "face.svg";

const FOLLOWED: Stroke<'static> = Stroke {
    colour: "#1f77b4",
    width: 1.4,
    dash: None,
};
const ENVELOPE: Stroke<'static> = Stroke {
    colour: "#2e6b2e",
    width: 1.0,
    dash: None,
};
const FOLLOWED_BOUND: Stroke<'static> = Stroke {
    colour: "#1f77b4",
    width: 1.0,
    dash: Some("6 4"),
};
const TOWARDS_BOUND: Stroke<'static> = Stroke {
    colour: "#d62728",
    width: 1.0,
    dash: Some("6 4"),
};
const GAP_COLOUR: &str = "#7f7f7f";
/// Two measured ticks farther apart along the hedge than this are not
/// joined (a gap, or a stretch outside edge following), m.
const JOIN_M: f64 = 0.3;
/// The share of the data's height added above it, for the legend.
const LEGEND_ROOM: f64 = 0.6;

/// The bounds a case judged its hedge by, m.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FaceBounds {
    /// Largest |error| to the followed line.
    pub followed: Option<f64>,
    /// Largest error towards the hedge from the envelope's offset line.
    pub towards: Option<f64>,
}

/// Splits `points` where consecutive ones are more than [`JOIN_M`] apart
/// along the hedge.
fn pieces(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=points.len() {
        let split = match (points.get(i - 1), points.get(i)) {
            (Some(a), Some(b)) => (b.0 - a.0).abs() > JOIN_M,
            _ => true,
        };
        if split {
            if let Some(piece) = points.get(start..i) {
                out.push(piece);
            }
            start = i;
        }
    }
    out
}

/// The point of largest `key`, if any.
fn worst(points: &[(f64, f64)], key: impl Fn(f64) -> f64) -> Option<(f64, f64)> {
    points
        .iter()
        .copied()
        .max_by(|a, b| key(a.1).total_cmp(&key(b.1)))
}

/// The figure of `errors` along a hedge of `length` metres cut by `gaps`
/// (errors positive away from the hedge), titled with the run's `name`.
#[must_use]
pub fn face_svg(
    name: &str,
    length: f64,
    gaps: &[[f64; 2]],
    errors: &[FaceErrors],
    bounds: FaceBounds,
) -> String {
    let followed: Vec<(f64, f64)> = errors.iter().map(|e| (e.along, e.followed)).collect();
    let envelope: Vec<(f64, f64)> = errors.iter().map(|e| (e.along, e.envelope)).collect();
    let limit = bounds
        .followed
        .unwrap_or(0.0)
        .max(bounds.towards.unwrap_or(0.0));
    let values = || followed.iter().chain(&envelope).map(|p| p.1);
    let y_lo = values().fold(-limit, f64::min);
    // Headroom above the data for the legend.
    let y_hi = values().fold(limit, f64::max);
    let y_hi = y_hi + LEGEND_ROOM * (y_hi - y_lo);
    let axes = Axes::new((0.0, length), (y_lo, y_hi), 900.0, 380.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    for gap in gaps {
        shade(&mut svg, &axes, gap[0], gap[1], GAP_COLOUR);
    }
    svg.frame(
        &axes,
        "distance along the hedge (m)",
        "error (m), > 0 away from the hedge",
        &format!("{name}: the offset along the hedge, as judged"),
    );
    let zero = Stroke {
        colour: "black",
        width: 0.8,
        dash: None,
    };
    svg.polyline(&axes, &[(axes.x.0, 0.0), (axes.x.1, 0.0)], zero);
    let mut entries: Vec<(Stroke<'_>, bool, String)> = Vec::new();
    if let Some(l) = bounds.followed {
        svg.polyline(&axes, &[(axes.x.0, l), (axes.x.1, l)], FOLLOWED_BOUND);
        svg.polyline(&axes, &[(axes.x.0, -l), (axes.x.1, -l)], FOLLOWED_BOUND);
        entries.push((
            FOLLOWED_BOUND,
            false,
            format!("±{l} m to the followed line"),
        ));
    }
    if let Some(l) = bounds.towards {
        svg.polyline(&axes, &[(axes.x.0, -l), (axes.x.1, -l)], TOWARDS_BOUND);
        entries.push((TOWARDS_BOUND, false, format!("{l} m towards the hedge")));
    }
    for piece in pieces(&envelope) {
        svg.polyline(&axes, piece, ENVELOPE);
    }
    for piece in pieces(&followed) {
        svg.polyline(&axes, piece, FOLLOWED);
    }
    if let Some(p) = worst(&followed, f64::abs) {
        svg.dots(&axes, &[p], 4.0, FOLLOWED.colour);
    }
    if let Some(p) = worst(&envelope, |v| -v) {
        svg.dots(&axes, &[p], 4.0, TOWARDS_BOUND.colour);
    }
    entries.push((
        FOLLOWED,
        false,
        "to the followed line (dot: its worst)".to_owned(),
    ));
    entries.push((
        ENVELOPE,
        false,
        "to the envelope's offset line (dot: nearest the hedge)".to_owned(),
    ));
    if !gaps.is_empty() {
        entries.push((
            Stroke {
                colour: GAP_COLOUR,
                width: 1.0,
                dash: None,
            },
            true,
            "gap in the hedge".to_owned(),
        ));
    }
    let labelled: Vec<(Stroke<'_>, bool, &str)> = entries
        .iter()
        .map(|(s, f, l)| (*s, *f, l.as_str()))
        .collect();
    let occupied: Vec<(f64, f64)> = followed.iter().chain(&envelope).copied().collect();
    svg.legend(&axes, &labelled, &occupied);
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(along: f64, followed: f64, envelope: f64) -> FaceErrors {
        FaceErrors {
            along,
            envelope,
            followed,
        }
    }

    #[test]
    fn the_ticks_across_a_gap_are_not_joined() {
        let points = [(1.0, 0.0), (1.1, 0.0), (1.2, 0.0), (3.0, 0.0), (3.1, 0.0)];
        let split = pieces(&points);
        assert_eq!(split.len(), 2);
        assert_eq!(split[0].len(), 3);
        assert_eq!(split[1], &points[3..]);
    }

    #[test]
    fn the_worst_ticks_and_the_bounds_are_drawn() {
        let gaps = [[4.0, 5.0]];
        let errors = [
            at(1.0, 0.02, 0.05),
            at(1.1, -0.18, -0.2),
            at(1.2, 0.01, 0.0),
        ];
        let bounds = FaceBounds {
            followed: Some(0.15),
            towards: Some(0.15),
        };
        let svg = face_svg("seed-3", 10.0, &gaps, &errors, bounds);
        assert!(svg.contains("seed-3: the offset along the hedge"));
        assert!(svg.contains("±0.15 m to the followed line"));
        assert!(svg.contains("0.15 m towards the hedge"));
        assert!(svg.contains("gap in the hedge"));
        // One dot per worst tick: the followed line's at 1.1 m, -0.18 m.
        assert_eq!(svg.matches("<circle").count(), 2);
        let axes = Axes::new((0.0, 10.0), (-0.2, 0.15 + 0.6 * 0.35), 900.0, 380.0);
        let (px, py) = axes.px(1.1, -0.18);
        assert!(svg.contains(&format!(r#"<circle cx="{px:.1}" cy="{py:.1}""#)));
        let unbounded = face_svg("seed-3", 10.0, &[], &errors, FaceBounds::default());
        assert!(!unbounded.contains('±'));
        assert!(!unbounded.contains("m towards the hedge"));
        assert!(!unbounded.contains("gap in the hedge"));
    }
}
