//! A vine-row run drawn as the paper's Figs. 10, 12 and 14: the lateral and
//! angular deviations to the true row, and both steering angles, against the
//! distance travelled; and the path over the vineyard seen from above.

use super::{VineOutcome, VineyardRun};
use crate::output::svg::{Axes, Stroke, Svg};

const LATERAL: &str = "#1f77b4";
const ANGULAR: &str = "#d62728";
const FRONT: &str = "#2ca02c";
const REAR: &str = "#ff7f0e";

fn line(colour: &str) -> Stroke<'_> {
    Stroke {
        colour,
        width: 2.0,
        dash: None,
    }
}

/// A curve: its colour, its legend and its points.
type Curve<'a> = (&'a str, &'a str, Vec<(f64, f64)>);

/// One panel of curves against the distance travelled by R.
fn panel(title: &str, y_label: &str, curves: &[Curve<'_>], band: Option<f64>) -> String {
    let all: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.2.iter().copied())
        .filter(|p| p.1.is_finite())
        .collect();
    let x1 = all.iter().map(|p| p.0).fold(1.0, f64::max);
    let lim = all.iter().map(|p| p.1.abs()).fold(0.05, f64::max);
    let axes = Axes::new((0.0, x1), (-lim, lim), 1000.0, 380.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    svg.frame(&axes, "distance travelled by R (m)", y_label, title);
    if let Some(b) = band {
        svg.polygon(
            &axes,
            &[(0.0, -b), (x1, -b), (x1, b), (0.0, b)],
            "#bbbbbb",
            0.3,
        );
    }
    // A NaN splits a curve (a stretch where the figure has no meaning).
    for (colour, _, points) in curves {
        for piece in points.split(|p| !p.1.is_finite()) {
            svg.polyline(&axes, piece, line(colour));
        }
    }
    let legend: Vec<(Stroke<'_>, bool, &str)> =
        curves.iter().map(|c| (line(c.0), false, c.1)).collect();
    svg.legend(&axes, &legend, &all);
    svg.finish()
}

/// The distance travelled by R at each tick, m.
fn distance(outcome: &VineOutcome) -> Vec<f64> {
    let mut d = 0.0;
    let mut last = outcome.ticks.first().map(|t| t.truth.position);
    outcome
        .ticks
        .iter()
        .map(|t| {
            if let Some(p) = last {
                d += (t.truth.position.x() - p.x()).hypot(t.truth.position.y() - p.y());
            }
            last = Some(t.truth.position);
            d
        })
        .collect()
}

/// The lateral (m) and angular (rad) deviations to the true row against the
/// distance, the ±0.03 band shaded (Figs. 10, 12, 14, top); left out in a
/// headland turn, where no row is followed.
#[must_use]
pub fn deviations_svg(run: &VineyardRun, outcome: &VineOutcome) -> String {
    let d = distance(outcome);
    let length = run.field.length;
    let of = |f: fn(&super::VineTick) -> f64| -> Vec<(f64, f64)> {
        d.iter()
            .zip(&outcome.ticks)
            .map(|(s, t)| {
                let turning = run.turns && t.truth.position.x() > length;
                (*s, if turning { f64::NAN } else { f(t) })
            })
            .collect()
    };
    panel(
        &format!(
            "{}: deviations to the true row (seed {}; vines touched past the entry {}, in all {})",
            run.name, run.seed, outcome.touched_in_row, outcome.touched
        ),
        "lateral (m) / angular (rad)",
        &[
            (LATERAL, "lateral deviation of R, m", of(|t| t.lateral_m)),
            (ANGULAR, "angular deviation, rad", of(|t| t.angular_rad)),
        ],
        Some(0.03),
    )
}

/// The front and rear steering angles against the distance (Figs. 10, 12,
/// 14, bottom).
#[must_use]
pub fn steering_svg(run: &VineyardRun, outcome: &VineOutcome) -> String {
    let d = distance(outcome);
    let of = |f: fn(&super::VineTick) -> f64| -> Vec<(f64, f64)> {
        d.iter()
            .zip(&outcome.ticks)
            .map(|(s, t)| (*s, f(t)))
            .collect()
    };
    panel(
        &format!("{}: steering angles (seed {})", run.name, run.seed),
        "steering (rad)",
        &[
            (FRONT, "front δ_F", of(|t| t.steering.0)),
            (REAR, "rear δ_R", of(|t| t.steering.1)),
        ],
        None,
    )
}

/// The path of R over the vineyard seen from above (y stretched).
#[must_use]
pub fn trajectory_svg(run: &VineyardRun, outcome: &VineOutcome) -> String {
    let spec = &run.field;
    let path: Vec<(f64, f64)> = outcome
        .ticks
        .iter()
        .map(|t| (t.truth.position.x(), t.truth.position.y()))
        .collect();
    let x0 = path.first().map_or(-3.0, |p| p.0 - 0.5);
    let x1 = path
        .iter()
        .map(|p| p.0 + 0.5)
        .fold(spec.length + 0.5, f64::max);
    let y0 = spec.row_y(spec.rows.saturating_sub(1)).min(-1.0) - 0.5;
    let axes = Axes::new((x0, x1), (y0, 1.5), 1000.0, 420.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    svg.frame(
        &axes,
        "x (m), along the rows",
        "y (m), across",
        &format!(
            "{}: the path of R over the vineyard ({} season)",
            run.name,
            spec.season.name()
        ),
    );
    let plants: Vec<(f64, f64)> = outcome
        .plants
        .iter()
        .map(|p| (p.position.x(), p.position.y()))
        .collect();
    svg.dots(&axes, &plants, 1.5, "#2ca02c");
    svg.polyline(&axes, &path, line(LATERAL));
    // With the switching pipeline: the stretches on the vines over it.
    let mut on_vines = Vec::new();
    for (t, p) in outcome.ticks.iter().zip(&path) {
        if t.following == Some(true) {
            on_vines.push(*p);
        } else if !on_vines.is_empty() {
            svg.polyline(&axes, &on_vines, line(REAR));
            on_vines.clear();
        }
    }
    svg.polyline(&axes, &on_vines, line(REAR));
    let mut legend = vec![
        (line(LATERAL), false, "R"),
        (line("#2ca02c"), true, "canopies, trunks, posts"),
    ];
    if outcome.ticks.iter().any(|t| t.following.is_some()) {
        legend[0].2 = "R, path tracking";
        legend.push((line(REAR), false, "R, vine following"));
    }
    svg.legend(&axes, &legend, &path);
    svg.finish()
}
