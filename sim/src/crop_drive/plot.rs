//! A crop drive drawn as the paper's Figs. 15-16: the plants seen from
//! above, the path of O coloured by what the robot was doing, and every
//! crop plant it ran over.

use fieldguide::supervisor::crop_navigation::Phase;

use super::field::ROWS;
use super::{CropOutcome, CropRun};
use crate::output::svg::{Axes, Stroke, Svg};
use crate::world::PlantKind;

const FORWARD: &str = "#1f77b4";
const BACKWARD: &str = "#9467bd";
const CHANGING: &str = "#ff7f0e";
const STILL: &str = "#7f7f7f";

/// The colour and legend of a phase.
fn style(phase: Phase) -> (&'static str, &'static str) {
    match phase {
        Phase::Driving {
            backward: false, ..
        } => (FORWARD, "inter-row, forward"),
        Phase::Driving { backward: true, .. } => (BACKWARD, "inter-row, backward"),
        Phase::Changing { .. } => (CHANGING, "row change"),
        Phase::Measuring | Phase::Done | Phase::Stopped(_) => (STILL, "standing"),
    }
}

/// The drive of `run` over its crop, as an SVG document.
#[must_use]
pub fn trajectory_svg(run: &CropRun, outcome: &CropOutcome) -> String {
    let spec = &run.crop;
    let path: Vec<(f64, f64)> = outcome
        .ticks
        .iter()
        .map(|t| (t.truth.position.x(), t.truth.position.y()))
        .collect();
    let top = spec.row_y(ROWS - 1);
    let (mut x0, mut x1, mut y0, mut y1): (f64, f64, f64, f64) =
        (-1.0, spec.length + 1.0, -1.0, top + 1.0);
    for &(x, y) in &path {
        (x0, x1, y0, y1) = (
            x0.min(x - 1.0),
            x1.max(x + 1.0),
            y0.min(y - 1.0),
            y1.max(y + 1.0),
        );
    }
    let axes = Axes::equal((x0, x1), (y0, y1), 1000.0, 700.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    let verdict = if outcome.success() {
        "success".to_owned()
    } else {
        format!(
            "failed ({:?}, {} plants run over)",
            outcome.end, outcome.crushed
        )
    };
    svg.frame(
        &axes,
        "x (m), along the rows",
        "y (m), across",
        &format!(
            "{}: crop {}, {}, seed {}: {verdict}",
            run.name,
            spec.crop,
            super::campaign::variant_name(run.variant),
            run.seed
        ),
    );
    let of = |kind: PlantKind| -> Vec<(f64, f64)> {
        outcome
            .plants
            .iter()
            .filter(|p| p.kind == kind)
            .map(|p| (p.position.x(), p.position.y()))
            .collect()
    };
    svg.dots(&axes, &of(PlantKind::Crop), 2.2, "#2ca02c");
    svg.dots(&axes, &of(PlantKind::Grass), 2.0, "#d62728");
    // The path, one polyline per stretch of one phase.
    let mut start = 0;
    for k in 1..=outcome.ticks.len() {
        let same = match (outcome.ticks.get(k), outcome.ticks.get(start)) {
            (Some(a), Some(b)) => style(a.phase).1 == style(b.phase).1,
            _ => false,
        };
        if !same {
            if let Some(first) = outcome.ticks.get(start) {
                let end = (k + 1).min(path.len());
                svg.polyline(
                    &axes,
                    path.get(start..end).unwrap_or(&[]),
                    Stroke {
                        colour: style(first.phase).0,
                        width: 2.0,
                        dash: None,
                    },
                );
            }
            start = k;
        }
    }
    let line = |colour| Stroke {
        colour,
        width: 3.0,
        dash: None,
    };
    let green = line("#2ca02c");
    let red = line("#d62728");
    svg.legend(
        &axes,
        &[
            (line(FORWARD), false, "O, inter-row forward"),
            (line(BACKWARD), false, "O, inter-row backward"),
            (line(CHANGING), false, "O, row change"),
            (green, true, "crop plants"),
            (red, true, "weeds (may be run over)"),
        ],
        &path
            .iter()
            .copied()
            .chain(
                outcome
                    .plants
                    .iter()
                    .map(|p| (p.position.x(), p.position.y())),
            )
            .collect::<Vec<_>>(),
    );
    svg.finish()
}
