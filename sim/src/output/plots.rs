//! The figures of a run, in the style of Pierre 2022 Figs. 8 and 10: the
//! trajectory over the reference path (equal axis scales, coloured by mode),
//! the lateral error against the curvilinear abscissa s, and, in a world
//! with plants, the rows and the wheels' tracks along the path.

use fieldguide::{Meters, Pose2, World};

use fieldguide::guidance::Mode;

use crate::guidance::colour;
use crate::runner::{CrushedPlant, LineTruth, TickRecord};
use crate::scenario::Setup;
use crate::world::PlantKind;

use super::svg::{Axes, Stroke, Svg};

const REFERENCE: Stroke<'static> = Stroke {
    colour: "black",
    width: 1.4,
    dash: None,
};
const PATCH_COLOUR: &str = "#1f77b4";
const OUTAGE_COLOUR: &str = "#7f7f7f";
const CROP_COLOUR: &str = "#2ca02c";
const GRASS_COLOUR: &str = "#bcbd22";
const PLOT_COLOUR: &str = "#2ca02c";
const TRUTH: Stroke<'static> = Stroke {
    colour: "black",
    width: 0.9,
    dash: None,
};
const HEDGE: Stroke<'static> = Stroke {
    colour: "#2e6b2e",
    width: 1.2,
    dash: None,
};
const POST_COLOUR: &str = "#6b4423";
const POST: Stroke<'static> = Stroke {
    colour: POST_COLOUR,
    width: 1.2,
    dash: None,
};
const WIRE: Stroke<'static> = Stroke {
    colour: "#7a7a7a",
    width: 0.8,
    dash: Some("4 2"),
};
const OFFSET_LINE: Stroke<'static> = Stroke {
    colour: "#2e6b2e",
    width: 1.0,
    dash: Some("6 4"),
};

/// Consecutive ticks of one mode, each with the first point of the next run
/// so the coloured pieces join.
fn runs_by_mode(trace: &[TickRecord]) -> Vec<(&'static str, &[TickRecord])> {
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
                runs.push((first.label(), run));
            }
            start = i;
        }
    }
    runs
}

/// A mode's label in words for a legend (`furrow_pursuing` → `furrow
/// pursuing`); a label the simulator does not know is shown as it is.
fn in_words(label: &'static str) -> &'static str {
    match label {
        "path_tracking" => "path tracking",
        "furrow_pursuing" => "furrow pursuing",
        "edge_following" => "edge following",
        "stop" => "stop (dots: where, and for how long)",
        other => other,
    }
}

/// Legend entries: the reference, each mode present, the slip patches if any.
fn legend_entries<'a>(
    trace: &[TickRecord],
    has_patches: bool,
    reference: &'a str,
) -> Vec<(Stroke<'a>, bool, &'a str)> {
    let mut modes: Vec<(Mode, &'static str)> =
        trace.iter().map(|r| (r.mode(), r.label())).collect();
    modes.sort_unstable();
    modes.dedup();
    let mut entries = vec![(REFERENCE, false, reference)];
    for (_, label) in modes {
        entries.push((
            Stroke {
                colour: colour(label),
                width: 1.6,
                dash: None,
            },
            false,
            in_words(label),
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

/// Legend entries for the kinds of plants the world holds.
fn plant_legend(setup: &Setup) -> Vec<(Stroke<'static>, bool, &'static str)> {
    [
        (PlantKind::Crop, CROP_COLOUR, "crop plants"),
        (PlantKind::Grass, GRASS_COLOUR, "grass and weeds"),
    ]
    .into_iter()
    .filter(|(kind, _, _)| setup.world.plants.iter().any(|p| p.kind == *kind))
    .map(|(_, colour, label)| {
        (
            Stroke {
                colour,
                width: 1.0,
                dash: None,
            },
            true,
            label,
        )
    })
    .collect()
}

/// Colour of the crosses marking crushed crop plants.
pub const CRUSHED_COLOUR: &str = "#e000e0";

/// The SVG class of the group of crosses marking crushed crop plants.
pub const CRUSHED_CLASS: &str = "crushed-plants";

/// The legend entry of the crushed plants' crosses.
const CRUSHED_ENTRY: (Stroke<'static>, bool, &str) = (
    Stroke {
        colour: CRUSHED_COLOUR,
        width: 2.0,
        dash: None,
    },
    false,
    "crushed crop plant (×)",
);

/// [`trajectory_svg_marked`] without crushed plants to mark.
#[must_use]
pub fn trajectory_svg(setup: &Setup, trace: &[TickRecord]) -> String {
    trajectory_svg_marked(setup, trace, &[])
}

/// `trajectory.svg`: reference path (black), true trajectory of O coloured by
/// mode, slip patches shaded, start marked, each of `crushed` marked by a
/// cross; x east and y north in metres.
#[must_use]
pub fn trajectory_svg_marked(
    setup: &Setup,
    trace: &[TickRecord],
    crushed: &[CrushedPlant],
) -> String {
    let reference: Vec<(f64, f64)> = setup
        .path
        .vertices()
        .iter()
        .map(|v| (v.position.x(), v.position.y()))
        .collect();
    let hedge_points: Vec<(f64, f64)> = setup
        .world
        .obstacles
        .segments
        .iter()
        .flat_map(|g| [(g.a[0], g.a[1]), (g.b[0], g.b[1])])
        .chain(
            setup
                .world
                .obstacles
                .circles
                .iter()
                .map(|c| (c.center[0], c.center[1])),
        )
        .collect();
    let all = reference
        .iter()
        .copied()
        .chain(
            trace
                .iter()
                .map(|r| (r.truth.position.x(), r.truth.position.y())),
        )
        .chain(hedge_points.iter().copied());
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
    // A long thin layout (plots in line) would leave no room for the legend:
    // each side spans at least a third of the other.
    let (w, h) = (x1 - x0, y1 - y0);
    if h < w / 3.0 {
        let pad = (w / 3.0 - h) / 2.0;
        (y0, y1) = (y0 - pad, y1 + pad);
    } else if w < h / 3.0 {
        let pad = (h / 3.0 - w) / 2.0;
        (x0, x1) = (x0 - pad, x1 + pad);
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
    let plants = |kind: PlantKind| -> Vec<(f64, f64)> {
        setup
            .world
            .plants
            .iter()
            .filter(|p| p.kind == kind)
            .map(|p| (p.position.x(), p.position.y()))
            .collect()
    };
    svg.dots(&axes, &plants(PlantKind::Grass), 0.8, GRASS_COLOUR);
    svg.dots(&axes, &plants(PlantKind::Crop), 1.0, CROP_COLOUR);
    for g in &setup.world.obstacles.segments {
        svg.polyline(&axes, &[(g.a[0], g.a[1]), (g.b[0], g.b[1])], HEDGE);
    }
    for g in &setup.world.obstacles.wires {
        svg.polyline(&axes, &[(g.a[0], g.a[1]), (g.b[0], g.b[1])], WIRE);
    }
    let posts: Vec<(f64, f64, f64)> = setup
        .world
        .obstacles
        .circles
        .iter()
        .map(|c| (c.center[0], c.center[1], c.radius))
        .collect();
    svg.circles(&axes, &posts, POST_COLOUR);
    let offset_lines = offset_lines(setup);
    for line in &offset_lines {
        svg.polyline(&axes, line, OFFSET_LINE);
    }
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
                colour: colour(mode),
                width: 1.6,
                dash: None,
            },
        );
    }
    mark_stops(&mut svg, &axes, trace, setup.control.period_s, |r| {
        (r.truth.position.x(), r.truth.position.y())
    });
    let crosses: Vec<(f64, f64)> = crushed.iter().map(|c| (c.x_m, c.y_m)).collect();
    svg.crosses(&axes, &crosses, 9.0, CRUSHED_COLOUR, CRUSHED_CLASS);
    if let Some(first) = trace.first() {
        let (px, py) = axes.px(first.truth.position.x(), first.truth.position.y());
        svg.text(px + 6.0, py + 14.0, "start", "start", 11.0);
    }
    let has_patches = !setup.world.terrain.patches.is_empty();
    let points: Vec<(f64, f64)> = trace
        .iter()
        .map(|r| (r.truth.position.x(), r.truth.position.y()))
        .chain(reference.iter().copied())
        .chain(
            setup
                .world
                .plants
                .iter()
                .map(|p| (p.position.x(), p.position.y())),
        )
        .chain(hedge_points.iter().copied())
        .collect();
    let mut entries = legend_entries(trace, has_patches, "reference path");
    entries.extend(plant_legend(setup));
    if !setup.world.hedges.is_empty() {
        entries.push((HEDGE, false, "hedge"));
    }
    if !posts.is_empty() {
        entries.push((POST, false, "posts and trunks"));
    }
    if !setup.world.obstacles.wires.is_empty() {
        entries.push((WIRE, false, "fence wire"));
    }
    if !offset_lines.is_empty() {
        entries.push((OFFSET_LINE, false, "true offset line"));
    }
    if !crushed.is_empty() {
        entries.push(CRUSHED_ENTRY);
    }
    svg.legend(&axes, &entries, &points);
    svg.finish()
}

/// The true lines an edge follower keeps (each hedge's nominal face on the
/// reference path's side, moved by the desired distance), piece by piece
/// between the gaps; none without `[edge]`.
fn offset_lines(setup: &Setup) -> Vec<Vec<(f64, f64)>> {
    let Some(edge) = setup.edge else {
        return Vec::new();
    };
    let d = edge.detector.offset().get();
    let start = setup
        .path
        .vertices()
        .first()
        .map_or((0.0, 0.0), |v| (v.position.x(), v.position.y()));
    let mut lines = Vec::new();
    for h in &setup.world.hedges {
        let spec = &h.spec;
        // The side of the hedge where the path starts.
        let line = if spec.across(start.0, start.1) >= 0.0 {
            0.5 * spec.thickness + d
        } else {
            -0.5 * spec.thickness - d
        };
        for [a, b] in spec.pieces() {
            lines.push(spec.line(a, b, line).iter().map(|p| (p[0], p[1])).collect());
        }
    }
    lines
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
    let errors = || {
        trace.iter().flat_map(|r| {
            [
                Some(r.lateral_error_m),
                r.plot.map(|p| p.lateral_error_m),
                r.hedge.map(|h| h.lateral_error_m),
            ]
            .into_iter()
            .flatten()
        })
    };
    let y_lo = errors().fold(-band, f64::min);
    let y_hi = errors().fold(band, f64::max);
    let axes = Axes::new((s_min, s_max), (y_lo, y_hi), 900.0, 420.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    // Shade the s-stretches spent on slipping ground and without a fix.
    shade_runs(&mut svg, &axes, trace, |r| r.patch.is_some(), PATCH_COLOUR);
    shade_runs(
        &mut svg,
        &axes,
        trace,
        |r| r.readings.gnss.is_none(),
        OUTAGE_COLOUR,
    );
    // Shade the s-stretches spent beside a hedge.
    let along_hedge = truth_pieces(trace, |r| r.hedge);
    for piece in &along_hedge {
        if let (Some(a), Some(b)) = (piece.first(), piece.last()) {
            svg.polygon(
                &axes,
                &[
                    (a.0, axes.y.0),
                    (b.0, axes.y.0),
                    (b.0, axes.y.1),
                    (a.0, axes.y.1),
                ],
                HEDGE.colour,
                0.10,
            );
        }
    }
    // Shade the s-stretches spent inside a crop plot.
    for i in 0..setup.world.plots.len() {
        let inside: Vec<f64> = trace
            .iter()
            .filter(|r| r.plot.is_some_and(|p| p.index == i))
            .map(|r| r.s_m)
            .collect();
        if let (Some(a), Some(b)) = (inside.first(), inside.last()) {
            svg.polygon(
                &axes,
                &[
                    (*a, axes.y.0),
                    (*b, axes.y.0),
                    (*b, axes.y.1),
                    (*a, axes.y.1),
                ],
                PLOT_COLOUR,
                0.10,
            );
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
                colour: colour(mode),
                width: 1.4,
                dash: None,
            },
        );
    }
    // Stop covers no distance: a dot where each spell began, with its length.
    mark_stops(&mut svg, &axes, trace, setup.control.period_s, |r| {
        (r.s_m, r.lateral_error_m)
    });
    // Inside the plots, the error to the true centre line of the followed
    // rows; beside the hedges, to the true offset line.
    let in_plot = truth_pieces(trace, |r| r.plot);
    for piece in in_plot.iter().chain(&along_hedge) {
        svg.polyline(&axes, piece, TRUTH);
    }
    let has_patches = trace.iter().any(|r| r.patch.is_some());
    let band_label = format!("band ±{band} m");
    let mut entries = legend_entries(trace, has_patches, "");
    entries.remove(0);
    entries.push((dashed, false, &band_label));
    if trace.iter().any(|r| r.readings.gnss.is_none()) {
        entries.push((
            Stroke {
                colour: OUTAGE_COLOUR,
                width: 1.0,
                dash: None,
            },
            true,
            "GNSS fix lost",
        ));
    }
    if !along_hedge.is_empty() {
        entries.push((TRUTH, false, "beside a hedge: to the true offset line"));
        entries.push((
            Stroke {
                colour: HEDGE.colour,
                width: 1.0,
                dash: None,
            },
            true,
            "hedge present",
        ));
    }
    if !in_plot.is_empty() {
        entries.push((TRUTH, false, "in a plot: to the rows' true centre line"));
        entries.push((
            Stroke {
                colour: PLOT_COLOUR,
                width: 1.0,
                dash: None,
            },
            true,
            "crop plot",
        ));
    }
    let points: Vec<(f64, f64)> = trace.iter().map(|r| (r.s_m, r.lateral_error_m)).collect();
    svg.legend(&axes, &entries, &points);
    svg.finish()
}

/// `(s, error to the true line)` over each unbroken stretch of ticks with the
/// truth `truth` picks (a plot's centre line, a hedge's offset line) of one item.
fn truth_pieces(
    trace: &[TickRecord],
    truth: impl Fn(&TickRecord) -> Option<LineTruth>,
) -> Vec<Vec<(f64, f64)>> {
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Option<usize> = None;
    for r in trace {
        match truth(r) {
            Some(p) => {
                if current != Some(p.index) {
                    pieces.push(Vec::new());
                    current = Some(p.index);
                }
                if let Some(piece) = pieces.last_mut() {
                    piece.push((r.s_m, p.lateral_error_m));
                }
            }
            None => current = None,
        }
    }
    pieces
}

/// `rows.svg`, for a world with plants: the plants and the four wheels'
/// tracks in the Frénet frame of the reference path (s along it, y to its
/// left), the lateral axis stretched so the rows and the clearances show.
/// Crop plants in green (their footprint radius to scale on y), grass in
/// olive, the tracks of the wheels' contact patches (tyre width to scale on
/// y) coloured by mode.
#[must_use]
pub fn rows_svg(setup: &Setup, trace: &[TickRecord]) -> String {
    rows_svg_marked(setup, trace, &[])
}

/// `rows.svg` with each of `crushed` marked by a cross at its place along the path.
#[must_use]
pub fn rows_svg_marked(setup: &Setup, trace: &[TickRecord], crushed: &[CrushedPlant]) -> String {
    let path = &setup.path;
    let frenet = |x: f64, y: f64, hint: Option<f64>| -> Option<(f64, f64)> {
        let pose = Pose2::<World>::new(x, y, 0.0).ok()?;
        let e = match hint.and_then(|h| Meters::new(h).ok()) {
            Some(h) => path.project_near(&pose, Meters::ZERO, h, Meters::new(5.0).ok()?),
            None => path.project(&pose, Meters::ZERO),
        }
        .ok()?;
        Some((e.s.get(), e.y.get()))
    };
    let s_lo = trace.first().map_or(0.0, |r| r.s_m);
    let s_hi = trace.last().map_or(path.length().get(), |r| r.s_m);
    // Wide enough for the rows beside the wheels and for the widest swing of
    // O off the path (an excursion stays in the frame), at most 6 m.
    let wheels = setup.vehicle.track_m / 2.0 + setup.vehicle.tyre_width_m + 0.3;
    let swing = trace
        .iter()
        .map(|r| r.lateral_error_m.abs())
        .fold(0.0, f64::max);
    let half_width = (swing + wheels).min(6.0).max(wheels);
    let axes = Axes::new((s_lo, s_hi), (-half_width, half_width), 1400.0, 420.0);
    let mut svg = Svg::new(&axes);
    svg.clip_to(&axes);
    svg.frame(
        &axes,
        "curvilinear abscissa s (m)",
        "y (m), left of the path",
        &format!("{}: plants and wheel tracks along the path", setup.name),
    );
    let px_per_m = {
        let (_, a) = axes.px(0.0, 0.0);
        let (_, b) = axes.px(0.0, 1.0);
        (a - b).abs()
    };
    for kind in [PlantKind::Grass, PlantKind::Crop] {
        let (colour, fallback) = match kind {
            PlantKind::Crop => (CROP_COLOUR, 0.1),
            PlantKind::Grass => (GRASS_COLOUR, 0.02),
        };
        let mut by_size: Vec<(f64, Vec<(f64, f64)>)> = Vec::new();
        for p in setup.world.plants.iter().filter(|p| p.kind == kind) {
            let Some(q) = frenet(p.position.x(), p.position.y(), None) else {
                continue;
            };
            if q.0 < s_lo || q.0 > s_hi || q.1.abs() > half_width {
                continue;
            }
            // Radii rounded to a tenth of a pixel, so plants group by size.
            let r = ((if p.radius > 0.0 { p.radius } else { fallback }) * px_per_m * 10.0).round()
                / 10.0;
            match by_size.iter_mut().find(|(size, _)| (size - r).abs() < 1e-9) {
                Some((_, pts)) => pts.push(q),
                None => by_size.push((r, vec![q])),
            }
        }
        for (r, pts) in &by_size {
            svg.dots(&axes, pts, r.max(0.6), colour);
        }
    }
    // The wheels' tracks, each a band of the tyre width, by mode.
    let half_tyre = setup.vehicle.tyre_width_m / 2.0;
    for (mode, run) in runs_by_mode(trace) {
        for wheel in 0..4 {
            let track: Vec<(f64, f64)> = run
                .iter()
                .filter_map(|r| {
                    let w = setup.vehicle.wheel_centres(&r.truth);
                    let c = w.get(wheel)?;
                    frenet(c[0], c[1], Some(r.s_m))
                })
                .collect();
            let band: Vec<(f64, f64)> = track
                .iter()
                .map(|&(s, y)| (s, y + half_tyre))
                .chain(track.iter().rev().map(|&(s, y)| (s, y - half_tyre)))
                .collect();
            svg.polygon(&axes, &band, colour(mode), 0.3);
        }
        let centre: Vec<(f64, f64)> = run.iter().map(|r| (r.s_m, r.lateral_error_m)).collect();
        svg.polyline(
            &axes,
            &centre,
            Stroke {
                colour: colour(mode),
                width: 1.0,
                dash: Some("4 3"),
            },
        );
    }
    let mut entries = legend_entries(trace, false, "");
    entries.remove(0);
    entries.push((
        Stroke {
            colour: "#888",
            width: 1.0,
            dash: None,
        },
        true,
        "wheel tracks (tyre width), coloured by mode",
    ));
    entries.push((
        Stroke {
            colour: "#888",
            width: 1.0,
            dash: Some("4 3"),
        },
        false,
        "rear-axle centre O",
    ));
    entries.extend(plant_legend(setup));
    // Each crushed plant at its place along the path, near the tick that crushed it.
    let crosses: Vec<(f64, f64)> = crushed
        .iter()
        .filter_map(|c| {
            let hint = trace.iter().find(|r| r.t_s >= c.t_s).map(|r| r.s_m);
            frenet(c.x_m, c.y_m, hint)
        })
        .collect();
    svg.crosses(&axes, &crosses, 9.0, CRUSHED_COLOUR, CRUSHED_CLASS);
    if !crushed.is_empty() {
        entries.push(CRUSHED_ENTRY);
    }
    let occupied: Vec<(f64, f64)> = trace
        .iter()
        .map(|r| (r.s_m, r.lateral_error_m))
        .chain(
            setup
                .world
                .plants
                .iter()
                .filter_map(|p| frenet(p.position.x(), p.position.y(), None)),
        )
        .collect();
    svg.legend(&axes, &entries, &occupied);
    svg.finish()
}

/// Shades, in `fill`, each s-stretch of consecutive ticks where `on` holds.
fn shade_runs(
    svg: &mut Svg,
    axes: &Axes,
    trace: &[TickRecord],
    on: impl Fn(&TickRecord) -> bool,
    fill: &str,
) {
    let mut start: Option<f64> = None;
    for (i, r) in trace.iter().enumerate() {
        let last = i + 1 == trace.len();
        match (start, on(r)) {
            (None, true) => start = Some(r.s_m),
            (Some(s0), false) => {
                shade(svg, axes, s0, r.s_m, fill);
                start = None;
            }
            _ => {}
        }
        if last {
            if let Some(s0) = start {
                shade(svg, axes, s0, r.s_m, fill);
            }
        }
    }
}

/// Shades, in `fill`, the whole height of the plot between abscissae `s0`
/// and `s1`.
pub fn shade(svg: &mut Svg, axes: &Axes, s0: f64, s1: f64, fill: &str) {
    svg.polygon(
        axes,
        &[
            (s0, axes.y.0),
            (s1, axes.y.0),
            (s1, axes.y.1),
            (s0, axes.y.1),
        ],
        fill,
        0.15,
    );
}

/// Each spell in Stop: the index of its first tick and how long it lasted, s.
fn stops(trace: &[TickRecord], period_s: f64) -> Vec<(usize, f64)> {
    let mut spells = Vec::new();
    let mut current: Option<(usize, usize)> = None;
    for (i, r) in trace.iter().enumerate() {
        match (r.command.switching_mode == Mode::Stop, current.as_mut()) {
            (true, Some((_, ticks))) => *ticks += 1,
            (true, None) => current = Some((i, 1)),
            (false, Some(&mut (first, ticks))) => {
                spells.push((first, ticks as f64 * period_s));
                current = None;
            }
            (false, None) => {}
        }
    }
    if let Some((first, ticks)) = current {
        spells.push((first, ticks as f64 * period_s));
    }
    spells
}

/// Marks each spell in Stop with a dot at `at(tick)` and its length.
fn mark_stops(
    svg: &mut Svg,
    axes: &Axes,
    trace: &[TickRecord],
    period_s: f64,
    at: impl Fn(&TickRecord) -> (f64, f64),
) {
    for (first, seconds) in stops(trace, period_s) {
        if let Some(r) = trace.get(first) {
            let (x, y) = at(r);
            svg.dots(axes, &[(x, y)], 4.0, colour("stop"));
            let (px, py) = axes.px(x, y);
            svg.text(
                px + 6.0,
                py - 6.0,
                &format!("stop {seconds:.1} s"),
                "start",
                11.0,
            );
        }
    }
}
