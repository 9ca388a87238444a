//! A guided mission drawn: the field from above with the planned paths, the
//! true path of O and the tracks' outer edges; and histograms of the
//! per-manoeuvre indicators like Emmi 2024's Figs. 16-20.

use super::{GuidingRun, Outcome};
use crate::output::svg::{Axes, Stroke, Svg};

const TRUE_PATH: &str = "#1f77b4";
const PLANNED: &str = "#7f7f7f";
const TRACKS: &str = "#ff7f0e";
const CROP: &str = "#2ca02c";
const CRUSHED: &str = "#d62728";
const ROAD: &str = "#e3ddd0";

/// The x and y ranges holding every point, `pad` m beyond them.
pub(crate) fn bounds<'a>(
    points: impl Iterator<Item = &'a (f64, f64)>,
    pad: f64,
) -> ((f64, f64), (f64, f64)) {
    points.fold(
        (
            (f64::INFINITY, f64::NEG_INFINITY),
            (f64::INFINITY, f64::NEG_INFINITY),
        ),
        |((x0, x1), (y0, y1)), &(x, y)| {
            (
                (x0.min(x - pad), x1.max(x + pad)),
                (y0.min(y - pad), y1.max(y + pad)),
            )
        },
    )
}

/// The mission of `run` over its field, as an SVG document.
#[must_use]
pub fn trajectory_svg(run: &GuidingRun, outcome: &Outcome) -> String {
    let fields = run.placed_fields();
    let path: Vec<(f64, f64)> = outcome
        .ticks
        .iter()
        .map(|t| (t.truth.position.x(), t.truth.position.y()))
        .collect();
    let corners: Vec<(f64, f64)> = fields.iter().flat_map(|f| f.outline().vertices).collect();
    let (xs, ys) = bounds(corners.iter().chain(&path), 1.0);
    let axes = Axes::equal(xs, ys, 1000.0, 900.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    svg.frame(
        &axes,
        if run.farm.is_some() {
            "x (m), east"
        } else {
            "x (m), along the rows"
        },
        if run.farm.is_some() {
            "y (m), north"
        } else {
            "y (m), across"
        },
        &format!(
            "{}, seed {}: {}, {} of {} goals, {} crop plants run over",
            run.name,
            run.seed,
            super::end_label(&outcome.end),
            outcome.reaches.len(),
            outcome.goals.len(),
            outcome.crushed.len()
        ),
    );
    // The roads, as wide as they are.
    if let Some(farm) = &run.farm {
        let metre = axes.px(1.0, 0.0).0 - axes.px(0.0, 0.0).0;
        for line in farm.road_polylines().unwrap_or_default() {
            svg.polyline(
                &axes,
                &line,
                Stroke {
                    colour: ROAD,
                    width: farm.road_width_m * metre,
                    dash: None,
                },
            );
        }
    }
    // Each field's outline and its headlands' inner edges.
    let outline = |colour| Stroke {
        colour,
        width: 1.0,
        dash: Some("4 3"),
    };
    for placed in &fields {
        let mut edge = placed.outline().vertices;
        edge.extend(edge.first().copied());
        svg.polyline(&axes, &edge, outline("#000000"));
        let f = &placed.field;
        for x in [f.headland_m, f.length_m - f.headland_m] {
            svg.polyline(
                &axes,
                &[placed.to_world((x, 0.0)), placed.to_world((x, f.width_m))],
                outline(PLANNED),
            );
        }
    }
    let crop: Vec<(f64, f64)> = outcome
        .plants
        .iter()
        .map(|p| (p.position.x(), p.position.y()))
        .collect();
    for p in &outcome.paths {
        svg.polyline(
            &axes,
            p,
            Stroke {
                colour: PLANNED,
                width: 2.5,
                dash: None,
            },
        );
    }
    // The tracks' outer edges.
    let half = run.robot.track_m / 2.0 + run.robot.track_width_m / 2.0;
    for side in [1.0, -1.0] {
        let edge: Vec<(f64, f64)> = outcome
            .ticks
            .iter()
            .map(|t| {
                let (s, c) = t.truth.heading.get().sin_cos();
                (
                    t.truth.position.x() - side * half * s,
                    t.truth.position.y() + side * half * c,
                )
            })
            .collect();
        svg.polyline(
            &axes,
            &edge,
            Stroke {
                colour: TRACKS,
                width: 0.8,
                dash: None,
            },
        );
    }
    svg.polyline(
        &axes,
        &path,
        Stroke {
            colour: TRUE_PATH,
            width: 1.0,
            dash: None,
        },
    );
    svg.dots(&axes, &crop, 1.3, CROP);
    let crushed: Vec<(f64, f64)> = outcome
        .crushed
        .iter()
        .filter_map(|&i| outcome.plants.get(i))
        .map(|p| (p.position.x(), p.position.y()))
        .collect();
    svg.dots(&axes, &crushed, 3.0, CRUSHED);
    let goals: Vec<(f64, f64)> = outcome
        .goals
        .iter()
        .map(|g| (g.goal.pose.position.x(), g.goal.pose.position.y()))
        .collect();
    svg.dots(&axes, &goals, 3.0, "#000000");
    let line = |colour| Stroke {
        colour,
        width: 3.0,
        dash: None,
    };
    svg.legend(
        &axes,
        &[
            (line(PLANNED), false, "planned paths"),
            (line(TRUE_PATH), false, "O, true"),
            (line(TRACKS), false, "tracks' outer edges"),
            (line(CROP), true, "crop plants"),
            (line(CRUSHED), true, "crop plants run over"),
            (line("#000000"), true, "goals"),
        ],
        &[path.as_slice(), crop.as_slice()].concat(),
    );
    svg.finish()
}

/// A histogram of `values` (shown times `scale`, in unit `short`) in `bins` bins,
/// titled `title`, x labelled `unit`.
#[must_use]
pub fn histogram_svg(
    values: &[f64],
    (scale, short): (f64, &str),
    bins: u32,
    title: &str,
    unit: &str,
) -> String {
    let shown: Vec<f64> = values.iter().map(|v| v.abs() * scale).collect();
    let top = shown.iter().fold(0.0_f64, |m, &v| m.max(v));
    let hi = if top > 0.0 { top * 1.05 } else { 1.0 };
    let n = bins.max(1);
    let width = hi / f64::from(n);
    let mut counts = vec![0_u32; usize::try_from(n).unwrap_or(1)];
    for &v in &shown {
        let k = (1..n).filter(|&j| f64::from(j) * width <= v).count();
        if let Some(c) = counts.get_mut(k) {
            *c += 1;
        }
    }
    let most = counts.iter().copied().max().unwrap_or(0).max(1);
    let axes = Axes::new((0.0, hi), (0.0, f64::from(most) * 1.1), 640.0, 420.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    let mean = if shown.is_empty() {
        0.0
    } else {
        shown.iter().sum::<f64>() / f64::from(u32::try_from(shown.len()).unwrap_or(u32::MAX))
    };
    svg.frame(
        &axes,
        unit,
        "count",
        &format!("{title}: {} values, mean {mean:.2} {short}", shown.len()),
    );
    for (k, &c) in counts.iter().enumerate() {
        let a = f64::from(u32::try_from(k).unwrap_or(0)) * width;
        let b = a + width;
        let h = f64::from(c);
        svg.polygon(&axes, &[(a, 0.0), (b, 0.0), (b, h), (a, h)], TRUE_PATH, 0.8);
    }
    svg.polyline(
        &axes,
        &[(mean, 0.0), (mean, f64::from(most) * 1.1)],
        Stroke {
            colour: CRUSHED,
            width: 1.5,
            dash: Some("5 3"),
        },
    );
    svg.finish()
}

/// The five histograms of a mission: `(file name, SVG)`.
#[must_use]
pub fn histograms(outcome: &Outcome) -> Vec<(&'static str, String)> {
    vec![
        (
            "hist_reach.svg",
            histogram_svg(
                &outcome.reach_values(),
                (100.0, "cm"),
                12,
                "Reach error at each goal (Figs. 16-17)",
                "distance from the goal to the robot's axis (cm)",
            ),
        ),
        (
            "hist_lateral_line.svg",
            histogram_svg(
                &outcome.values(true, true),
                (100.0, "cm"),
                12,
                "Mean lateral error of each line (Fig. 18)",
                "mean |lateral error| (cm)",
            ),
        ),
        (
            "hist_lateral_spiral.svg",
            histogram_svg(
                &outcome.values(false, true),
                (100.0, "cm"),
                12,
                "Mean lateral error of each spiral (Fig. 19)",
                "mean |d - r| (cm)",
            ),
        ),
        (
            "hist_angular_line.svg",
            histogram_svg(
                &outcome.values(true, false),
                (1000.0, "mrad"),
                12,
                "Mean angular error of each line (Fig. 20a)",
                "mean |heading error| (mrad)",
            ),
        ),
        (
            "hist_angular_spiral.svg",
            histogram_svg(
                &outcome.values(false, false),
                (1000.0, "mrad"),
                12,
                "Mean angular error of each spiral (Fig. 20b)",
                "mean |alpha - alpha_d| (mrad)",
            ),
        ),
    ]
}
