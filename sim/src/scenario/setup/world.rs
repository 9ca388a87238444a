//! Validates `[world]`: the crop plots, the grass and the hedges, and draws
//! their plants and outlines.

use std::path::Path;

use fieldguide::{Point2, World};

use super::shape::{self, ShapeFields};
use crate::error::ScenarioError;
use crate::rng::SimRng;
use crate::scenario::check::Checker;
use crate::scenario::schema::{CropName, PlotSection, WorldSection};
use crate::world::crops::{scatter_grass, PlotSpec, Spread};
use crate::world::hedge::{HedgeSpec, Obstacles};
use crate::world::{Hedge, Plant, PlantKind, Plot};

/// The most vertices a hedge face may have (a 1 km hedge at 1 cm).
const MAX_HEDGE_VERTICES: f64 = 100_000.0;

/// The plots of `[world]`, validated (no plant drawn yet); a centre line
/// CSV is read relative to `base_dir`.
pub(super) fn plots(
    world: Option<&WorldSection>,
    check: &Checker<'_>,
    base_dir: Option<&Path>,
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
        let shape = shape::shape(
            check,
            &format!("world.plots[{i}]"),
            ShapeFields {
                start: p.start.as_ref(),
                length_m: p.length_m,
                centre: p.centre.as_deref(),
                centre_csv: p.centre_csv.as_deref(),
                corner_radius_m: p.corner_radius_m,
            },
            base_dir,
        )?;
        let ([x, y], heading, length) = shape.start_heading_length();
        let start =
            Point2::<World>::new(x, y).map_err(|e| check.error(&field("start"), &e.to_string()))?;
        let mut spec = match p.crop {
            CropName::Maize => PlotSpec::maize(start, heading, length),
            CropName::Beans => PlotSpec::beans(start, heading, length),
        };
        if let Some(curve) = shape.curve() {
            for (name, given) in [
                ("bend_amplitude_m", p.bend_amplitude_m),
                ("bend_wavelength_m", p.bend_wavelength_m),
            ] {
                if given.is_some() {
                    return Err(check.error(
                        &field(name),
                        "not with a centre line: its polyline gives the rows' shape",
                    ));
                }
            }
            spec.bend_amplitude = 0.0;
            spec.centre = Some(curve.clone());
        }
        if let Some(a) = p.bend_amplitude_m {
            spec.bend_amplitude = check.range(&field("bend_amplitude_m"), a, 0.0, 5.0)?;
        }
        if let Some(w) = p.bend_wavelength_m {
            spec.bend_wavelength = check.positive(&field("bend_wavelength_m"), w)?;
        }
        if let Some(m) = p.missing_fraction {
            spec.missing = check.range(&field("missing_fraction"), m, 0.0, 1.0)?;
        }
        layout(&mut spec, p, check, &field)?;
        // The band of rows: the outer rows' offset and a stem's radius.
        let half_width = spec.row_offset(0).abs() + spec.plant_radius.mean;
        shape.check_band(check, half_width)?;
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

/// The optional layout fields of a `[[world.plots]]` (rows, row spacing,
/// plant spacing, height and stem radius), each replacing the crop's value
/// when given; `field` names a field of this plot.
fn layout(
    spec: &mut PlotSpec,
    p: &PlotSection,
    check: &Checker<'_>,
    field: &dyn Fn(&str) -> String,
) -> Result<(), ScenarioError> {
    if let Some(rows) = p.rows {
        spec.rows = check.count(&field("rows"), rows, 1, 50)?;
    }
    check.replace(
        &mut spec.row_spacing,
        p.row_spacing_m,
        &field("row_spacing_m"),
        0.05,
        10.0,
    )?;
    check.replace(
        &mut spec.plant_spacing.mean,
        p.plant_spacing_m,
        &field("plant_spacing_m"),
        0.01,
        10.0,
    )?;
    let mean = spec.plant_spacing.mean;
    check.replace(
        &mut spec.plant_spacing.std_dev,
        p.plant_spacing_std_m,
        &field("plant_spacing_std_m"),
        0.0,
        mean,
    )?;
    check.replace(
        &mut spec.plant_height.mean,
        p.plant_height_m,
        &field("plant_height_m"),
        0.02,
        3.0,
    )?;
    check.replace(
        &mut spec.plant_height.std_dev,
        p.plant_height_std_m,
        &field("plant_height_std_m"),
        0.0,
        1.0,
    )?;
    check.replace(
        &mut spec.plant_radius.mean,
        p.stem_radius_m,
        &field("stem_radius_m"),
        0.01,
        1.0,
    )?;
    check.replace(
        &mut spec.plant_radius.std_dev,
        p.stem_radius_std_m,
        &field("stem_radius_std_m"),
        0.0,
        0.5,
    )?;
    // Neighbouring rows' plants must not overlap: a row spacing below a
    // stem's diameter would merge two rows into one.
    if spec.rows > 1 && spec.row_spacing <= 2.0 * spec.plant_radius.mean {
        return Err(check.error(
            &field("row_spacing_m"),
            &format!(
                "must exceed a stem's diameter (2 × {} m) so that rows stay apart, got {}",
                spec.plant_radius.mean, spec.row_spacing
            ),
        ));
    }
    Ok(())
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
            centre: None,
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
    base_dir: Option<&Path>,
    rng: &mut SimRng,
) -> Result<(Vec<Hedge>, Obstacles), ScenarioError> {
    let mut hedges = Vec::new();
    let mut obstacles = Obstacles::default();
    for (i, h) in world.map_or(&[][..], |w| &w.hedges[..]).iter().enumerate() {
        let field = |name: &str| format!("world.hedges[{i}].{name}");
        if h.name.trim().is_empty() {
            return Err(check.error(&field("name"), "must not be empty"));
        }
        let shape = shape::shape(
            check,
            &format!("world.hedges[{i}]"),
            ShapeFields {
                start: h.start.as_ref(),
                length_m: h.length_m,
                centre: h.centre.as_deref(),
                centre_csv: h.centre_csv.as_deref(),
                corner_radius_m: h.corner_radius_m,
            },
            base_dir,
        )?;
        let (start, heading, length) = shape.start_heading_length();
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
        shape.check_band(check, 0.5 * thickness + raggedness)?;
        let spec = HedgeSpec {
            start,
            heading,
            length,
            thickness,
            raggedness,
            vertex_spacing: spacing,
            gaps,
            centre: shape.curve().cloned(),
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
