//! Validates `[world]`: the crop plots, the grass and the hedges, and draws
//! their plants and outlines.

use fieldguide::{Point2, World};

use crate::error::ScenarioError;

/// The most vertices a hedge face may have (a 1 km hedge at 1 cm).
const MAX_HEDGE_VERTICES: f64 = 100_000.0;
use crate::rng::SimRng;
use crate::scenario::check::Checker;
use crate::scenario::schema::{CropName, StartPose, WorldSection};
use crate::world::crops::{scatter_grass, PlotSpec, Spread};
use crate::world::hedge::{HedgeSpec, Obstacles};
use crate::world::{Hedge, Plant, PlantKind, Plot};

/// The plots of `[world]`, validated (no plant drawn yet).
pub(super) fn plots(
    world: Option<&WorldSection>,
    check: &Checker<'_>,
) -> Result<Vec<Plot>, ScenarioError> {
    let Some(world) = world else {
        return Ok(Vec::new());
    };
    let mut plots = Vec::with_capacity(world.plots.len());
    for (i, p) in world.plots.iter().enumerate() {
        let field = |name: &str| format!("world.plots[{i}].{name}");
        if p.name.trim().is_empty() {
            return Err(check.error(&field("name"), "must not be empty"));
        }
        let ([x, y], heading) = start(check, &field("start"), &p.start)?;
        let start =
            Point2::<World>::new(x, y).map_err(|e| check.error(&field("start"), &e.to_string()))?;
        let length = check.open_range(&field("length_m"), p.length_m, 0.0, 1000.0)?;
        let mut spec = match p.crop {
            CropName::Maize => PlotSpec::maize(start, heading, length),
            CropName::Beans => PlotSpec::beans(start, heading, length),
        };
        if let Some(a) = p.bend_amplitude_m {
            spec.bend_amplitude = check.range(&field("bend_amplitude_m"), a, 0.0, 5.0)?;
        }
        if let Some(w) = p.bend_wavelength_m {
            spec.bend_wavelength = check.positive(&field("bend_wavelength_m"), w)?;
        }
        if let Some(m) = p.missing_fraction {
            spec.missing = check.range(&field("missing_fraction"), m, 0.0, 1.0)?;
        }
        for (k, b) in p.bare_m.iter().enumerate() {
            let [from, to] = stretch(check, &field(&format!("bare_m[{k}]")), *b, length)?;
            spec.bare.push((from, to));
        }
        plots.push(Plot {
            name: p.name.clone(),
            spec,
        });
    }
    Ok(plots)
}

/// The plants of `plots` and of the grass rectangles of `[world]`, drawn from `rng`.
pub(super) fn plants(
    world: Option<&WorldSection>,
    plots: &[Plot],
    check: &Checker<'_>,
    rng: &mut SimRng,
) -> Result<Vec<Plant>, ScenarioError> {
    let mut plants = Vec::new();
    for p in plots {
        plants.extend(p.spec.generate(rng));
    }
    // Volunteer plants continuing the rows past a plot's end (drawn after
    // every plot, so a scenario without them draws as before).
    let sections = world.map_or(&[][..], |w| &w.plots[..]);
    for (i, (p, section)) in plots.iter().zip(sections).enumerate() {
        let Some(length) = section.volunteers_m else {
            continue;
        };
        let length = check.range(
            &format!("world.plots[{i}].volunteers_m"),
            length,
            0.0,
            100.0,
        )?;
        let (x, y, heading) = p.spec.centre_line(p.spec.length);
        let Ok(start) = Point2::new(x, y) else {
            continue;
        };
        let tail = PlotSpec {
            start,
            heading,
            length,
            missing: 0.0,
            bare: Vec::new(),
            bend_amplitude: 0.0,
            ..p.spec.clone()
        };
        plants.extend(tail.generate(rng).into_iter().map(|mut v| {
            v.kind = PlantKind::Grass;
            v
        }));
    }
    for (i, g) in world.map_or(&[][..], |w| &w.grass[..]).iter().enumerate() {
        let field = |name: &str| format!("world.grass[{i}].{name}");
        for (k, corner) in g.corners.iter().enumerate() {
            check.range(&field(&format!("corners[{k}][0]")), corner[0], -1e6, 1e6)?;
            check.range(&field(&format!("corners[{k}][1]")), corner[1], -1e6, 1e6)?;
        }
        let [[x0, y0], [x1, y1]] = g.corners;
        let area = ((x1 - x0) * (y1 - y0)).abs();
        let density = check.range(&field("density_per_m2"), g.density_per_m2, 0.0, 1000.0)?;
        if area * density > 1e6 {
            return Err(check.error(
                &field("density_per_m2"),
                &format!("{density} tufts/m² over {area} m² is more than a million tufts"),
            ));
        }
        let radius = Spread::new(
            check.open_range(&field("radius_m"), g.radius_m, 0.0, 0.5)?,
            check.range(&field("radius_std_m"), g.radius_std_m, 0.0, 0.5)?,
        );
        let height = Spread::new(
            check.open_range(&field("height_m"), g.height_m, 0.0, 1.0)?,
            check.range(&field("height_std_m"), g.height_std_m, 0.0, 1.0)?,
        );
        plants.extend(scatter_grass(
            ((x0.min(x1), y0.min(y1)), (x0.max(x1), y0.max(y1))),
            density,
            radius,
            height,
            rng,
        ));
    }
    Ok(plants)
}

/// The hedges of `[world]`, validated, and their outlines drawn from `rng`.
pub(super) fn hedges(
    world: Option<&WorldSection>,
    check: &Checker<'_>,
    rng: &mut SimRng,
) -> Result<(Vec<Hedge>, Obstacles), ScenarioError> {
    let mut hedges = Vec::new();
    let mut obstacles = Obstacles::default();
    for (i, h) in world.map_or(&[][..], |w| &w.hedges[..]).iter().enumerate() {
        let field = |name: &str| format!("world.hedges[{i}].{name}");
        if h.name.trim().is_empty() {
            return Err(check.error(&field("name"), "must not be empty"));
        }
        let length = check.open_range(&field("length_m"), h.length_m, 0.0, 1000.0)?;
        let thickness = check.open_range(&field("thickness_m"), h.thickness_m, 0.0, 20.0)?;
        let raggedness = check.range(&field("raggedness_m"), h.raggedness_m, 0.0, 20.0)?;
        if raggedness >= 0.5 * thickness {
            return Err(check.error(
                &field("raggedness_m"),
                &format!("must be below half of thickness_m = {thickness}, got {raggedness}"),
            ));
        }
        let spacing =
            check.open_range(&field("vertex_spacing_m"), h.vertex_spacing_m, 0.0, 100.0)?;
        // Two faces of `length / spacing` vertices each: bounded, so that a
        // file the loader accepts cannot exhaust the memory.
        if length / spacing > MAX_HEDGE_VERTICES {
            return Err(check.error(
                &field("vertex_spacing_m"),
                &format!(
                    "gives more than {MAX_HEDGE_VERTICES} vertices per face (length_m / vertex_spacing_m); use a larger spacing"
                ),
            ));
        }
        let mut gaps = Vec::with_capacity(h.gaps_m.len());
        for (k, g) in h.gaps_m.iter().enumerate() {
            gaps.push(stretch(check, &field(&format!("gaps_m[{k}]")), *g, length)?);
        }
        let (start, heading) = start(check, &field("start"), &h.start)?;
        let spec = HedgeSpec {
            start,
            heading,
            length,
            thickness,
            raggedness,
            vertex_spacing: spacing,
            gaps,
        };
        obstacles
            .add_hedge(&spec, rng)
            .map_err(|e| check.error(&field(e.field), e.reason))?;
        hedges.push(Hedge {
            name: h.name.clone(),
            spec,
        });
    }
    Ok((hedges, obstacles))
}

/// The start of a plot's or a hedge's centre line, `field` naming it: its
/// position `[x, y]` within ±1e6 m and its heading (radians) within ±360°.
fn start(
    check: &Checker<'_>,
    field: &str,
    start: &StartPose,
) -> Result<([f64; 2], f64), ScenarioError> {
    let x = check.range(&format!("{field}.x_m"), start.x_m, -1e6, 1e6)?;
    let y = check.range(&format!("{field}.y_m"), start.y_m, -1e6, 1e6)?;
    let heading = check.range(
        &format!("{field}.heading_deg"),
        start.heading_deg,
        -360.0,
        360.0,
    )?;
    Ok(([x, y], heading.to_radians()))
}

/// A stretch `[from_m, to_m]` along a plot or a hedge of length `length`,
/// `field` naming it: 0 ≤ from_m < to_m ≤ length.
fn stretch(
    check: &Checker<'_>,
    field: &str,
    [from, to]: [f64; 2],
    length: f64,
) -> Result<[f64; 2], ScenarioError> {
    let from = check.range(&format!("{field}[0]"), from, 0.0, length)?;
    let to = check.range(&format!("{field}[1]"), to, 0.0, length)?;
    if to <= from {
        return Err(check.error(
            field,
            &format!("must be [from_m, to_m] with from_m < to_m, got [{from}, {to}]"),
        ));
    }
    Ok([from, to])
}

/// The obstacles' height of `[world] obstacle_height_m`: within (0, 50) m,
/// 2 m when absent.
pub(super) fn obstacle_height(
    world: Option<&WorldSection>,
    check: &Checker<'_>,
) -> Result<f64, ScenarioError> {
    let h = world.and_then(|w| w.obstacle_height_m).unwrap_or(2.0);
    check.open_range("world.obstacle_height_m", h, 0.0, 50.0)
}
