//! The two figures of a run, in the style of Pierre 2022 Fig. 8: the
//! trajectory over the reference path (equal axis scales, coloured by mode) and
//! the lateral error against the curvilinear abscissa s.

use crate::guidance::Mode;
use crate::runner::TickRecord;
use crate::scenario::Setup;

use super::svg::{Axes, Stroke, Svg};

const REFERENCE: Stroke<'static> = Stroke {
    colour: "black",
    width: 1.4,
    dash: None,
};
const PATCH_COLOUR: &str = "#1f77b4";

/// Consecutive ticks of one mode, each with the first point of the next run
/// so the coloured pieces join.
fn runs_by_mode(trace: &[TickRecord]) -> Vec<(Mode, &[TickRecord])> {
    let mut runs = Vec::new();
    let mut start = 0;
    for i in 1..=trace.len() {
        let changed = match (trace.get(i - 1), trace.get(i)) {
            (Some(a), Some(b)) => a.mode() != b.mode(),
            _ => true,
        };
        if changed {
            if let (Some(first), Some(run)) =
                (trace.get(start), trace.get(start..=i.min(trace.len() - 1)))
            {
                runs.push((first.mode(), run));
            }
            start = i;
        }
    }
    runs
}

/// Legend entries: the reference, each mode present, the slip patches if any.
fn legend_entries<'a>(
    trace: &[TickRecord],
    has_patches: bool,
    reference: &'a str,
) -> Vec<(Stroke<'a>, bool, &'a str)> {
    let mut modes: Vec<Mode> = trace.iter().map(TickRecord::mode).collect();
    modes.sort();
    modes.dedup();
    let mut entries = vec![(REFERENCE, false, reference)];
    for m in modes {
        entries.push((
            Stroke {
                colour: m.colour(),
                width: 1.6,
                dash: None,
            },
            false,
            m.label(),
        ));
    }
    if has_patches {
        entries.push((
            Stroke {
                colour: PATCH_COLOUR,
                width: 1.0,
                dash: None,
            },
            true,
            "slipping ground",
        ));
    }
    entries
}

/// `trajectory.svg`: reference path (black), true trajectory of O coloured by
/// mode, slip patches shaded, start marked; x east and y north in metres.
#[must_use]
pub fn trajectory_svg(setup: &Setup, trace: &[TickRecord]) -> String {
    let reference: Vec<(f64, f64)> = setup
        .path
        .vertices()
        .iter()
        .map(|v| (v.position.x(), v.position.y()))
        .collect();
    let all = reference.iter().copied().chain(
        trace
            .iter()
            .map(|r| (r.truth.position.x(), r.truth.position.y())),
    );
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let axes = Axes::equal((x0, x1), (y0, y1), 900.0, 800.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    for p in &setup.world.terrain.patches {
        let pts: Vec<(f64, f64)> = p.polygon.iter().map(|v| (v[0], v[1])).collect();
        svg.polygon(&axes, &pts, PATCH_COLOUR, 0.15);
    }
    svg.frame(
        &axes,
        "x (m), east",
        "y (m), north",
        &format!("{}: trajectory of the rear-axle midpoint", setup.name),
    );
    svg.polyline(&axes, &reference, REFERENCE);
    for (mode, run) in runs_by_mode(trace) {
        let pts: Vec<(f64, f64)> = run
            .iter()
            .map(|r| (r.truth.position.x(), r.truth.position.y()))
            .collect();
        svg.polyline(
            &axes,
            &pts,
            Stroke {
                colour: mode.colour(),
                width: 1.6,
                dash: None,
            },
        );
    }
    if let Some(first) = trace.first() {
        let (px, py) = axes.px(first.truth.position.x(), first.truth.position.y());
        svg.text(px + 6.0, py + 14.0, "start", "start", 11.0);
    }
    let has_patches = !setup.world.terrain.patches.is_empty();
    let points: Vec<(f64, f64)> = trace
        .iter()
        .map(|r| (r.truth.position.x(), r.truth.position.y()))
        .chain(reference.iter().copied())
        .collect();
    svg.legend(
        &axes,
        &legend_entries(trace, has_patches, "reference path"),
        &points,
    );
    svg.finish()
}

/// `lateral_error.svg`: true lateral error y against the abscissa s, coloured
/// by mode, with the convergence band dashed and the stretches where O was on
/// slipping ground shaded.
#[must_use]
pub fn lateral_error_svg(setup: &Setup, trace: &[TickRecord]) -> String {
    let band = setup.metrics.band_m;
    let s_max = setup
        .path
        .length()
        .get()
        .max(trace.iter().map(|r| r.s_m).fold(0.0, f64::max));
    let s_min = trace.iter().map(|r| r.s_m).fold(0.0, f64::min);
    let y_lo = trace
        .iter()
        .map(|r| r.lateral_error_m)
        .fold(-band, f64::min);
    let y_hi = trace.iter().map(|r| r.lateral_error_m).fold(band, f64::max);
    let axes = Axes::new((s_min, s_max), (y_lo, y_hi), 900.0, 420.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    // Shade the s-stretches spent on slipping ground.
    let mut start: Option<f64> = None;
    for (i, r) in trace.iter().enumerate() {
        let on = r.patch.is_some();
        let last = i + 1 == trace.len();
        match (start, on) {
            (None, true) => start = Some(r.s_m),
            (Some(s0), false) => {
                shade(&mut svg, &axes, s0, r.s_m);
                start = None;
            }
            _ => {}
        }
        if last {
            if let Some(s0) = start {
                shade(&mut svg, &axes, s0, r.s_m);
            }
        }
    }
    svg.frame(
        &axes,
        "curvilinear abscissa s (m)",
        "lateral error y (m)",
        &format!(
            "{}: lateral error (ground truth, y > 0 left of the path)",
            setup.name
        ),
    );
    let dashed = Stroke {
        colour: "#555",
        width: 1.0,
        dash: Some("6 4"),
    };
    svg.polyline(&axes, &[(axes.x.0, band), (axes.x.1, band)], dashed);
    svg.polyline(&axes, &[(axes.x.0, -band), (axes.x.1, -band)], dashed);
    svg.polyline(
        &axes,
        &[(axes.x.0, 0.0), (axes.x.1, 0.0)],
        Stroke {
            colour: "black",
            width: 0.8,
            dash: None,
        },
    );
    for (mode, run) in runs_by_mode(trace) {
        let pts: Vec<(f64, f64)> = run.iter().map(|r| (r.s_m, r.lateral_error_m)).collect();
        svg.polyline(
            &axes,
            &pts,
            Stroke {
                colour: mode.colour(),
                width: 1.4,
                dash: None,
            },
        );
    }
    let has_patches = trace.iter().any(|r| r.patch.is_some());
    let band_label = format!("band ±{band} m");
    let mut entries = legend_entries(trace, has_patches, "");
    entries.remove(0);
    entries.push((dashed, false, &band_label));
    let points: Vec<(f64, f64)> = trace.iter().map(|r| (r.s_m, r.lateral_error_m)).collect();
    svg.legend(&axes, &entries, &points);
    svg.finish()
}

fn shade(svg: &mut Svg, axes: &Axes, s0: f64, s1: f64) {
    svg.polygon(
        axes,
        &[
            (s0, axes.y.0),
            (s1, axes.y.0),
            (s1, axes.y.1),
            (s0, axes.y.1),
        ],
        PATCH_COLOUR,
        0.15,
    );
}
