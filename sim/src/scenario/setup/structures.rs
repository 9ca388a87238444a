//! Validates the world's posts, fences and the plants of a CSV file:
//! `[[world.posts]]` (cylinders along a polyline, or read from a CSV file),
//! `[[world.fences]]` (posts with a wall or wires between them) and
//! `[world] plants_csv`. Errors about a CSV cell name its file, line and column.

use std::collections::HashMap;
use std::path::Path;

use fieldguide::{Point2, Pose2, World};
use rand::Rng;

use super::shape::Vertices;
use crate::error::ScenarioError;
use crate::plant::VehicleParams;
use crate::rng::SimRng;
use crate::scenario::check::Checker;
use crate::scenario::schema::{FenceKind, PostsSection, WorldSection};
use crate::scenario::table::Table;
use crate::world::curve::Curve;
use crate::world::hedge::{fence, posts_along, Circle, Obstacles};
use crate::world::{Plant, PlantKind};

/// The most posts of one `[[world.posts]]` or `[[world.fences]]`.
const MAX_POSTS: usize = 100_000;

/// The most plants of a plants CSV file.
const MAX_PLANTS: usize = 1_000_000;

/// Two stems closer than this are the same plant written twice, m.
const DUPLICATE_M: f64 = 1e-3;

/// The polyline `line` of the field `field` (`world.posts[0].line`): each
/// vertex within ±10⁶ m, sharp corners allowed.
fn polyline(check: &Checker<'_>, field: &str, line: &[[f64; 2]]) -> Result<Curve, ScenarioError> {
    for (k, v) in line.iter().enumerate() {
        check.range(&format!("{field}[{k}][0]"), v[0], -1e6, 1e6)?;
        check.range(&format!("{field}[{k}][1]"), v[1], -1e6, 1e6)?;
    }
    Curve::new(line, 0.0).map_err(|e| Vertices::inline(field).error(check, &e))
}

/// Adds the posts of `[[world.posts]]` and the fences of `[[world.fences]]`
/// to `obstacles`; a post missing by chance is drawn from `rng` (only with a
/// `missing_fraction` above 0).
pub(super) fn posts_and_fences(
    world: Option<&WorldSection>,
    check: &Checker<'_>,
    base_dir: Option<&Path>,
    rng: &mut SimRng,
    obstacles: &mut Obstacles,
) -> Result<(), ScenarioError> {
    let Some(world) = world else {
        return Ok(());
    };
    for (i, p) in world.posts.iter().enumerate() {
        let posts = post_row(p, i, check, base_dir, rng)?;
        obstacles.circles.extend(posts);
    }
    for (i, f) in world.fences.iter().enumerate() {
        let field = |name: &str| format!("world.fences[{i}].{name}");
        if f.name.trim().is_empty() {
            return Err(check.error(&field("name"), "must not be empty"));
        }
        let curve = polyline(check, &field("line"), &f.line)?;
        let spacing = check.open_range(&field("post_spacing_m"), f.post_spacing_m, 0.0, 1000.0)?;
        let radius = check.open_range(&field("post_radius_m"), f.post_radius_m, 0.0, 5.0)?;
        if 2.0 * radius >= spacing {
            return Err(check.error(
                &field("post_radius_m"),
                &format!("a post's diameter must be below post_spacing_m = {spacing}, got radius {radius}"),
            ));
        }
        if curve.length() / spacing > MAX_POSTS as f64 {
            return Err(check.error(
                &field("post_spacing_m"),
                &format!("gives more than {MAX_POSTS} posts; use a larger spacing"),
            ));
        }
        obstacles.extend(fence(&f.line, spacing, radius, f.kind == FenceKind::Wall));
    }
    Ok(())
}

/// The posts of `[[world.posts]]` number `i`.
fn post_row(
    p: &PostsSection,
    i: usize,
    check: &Checker<'_>,
    base_dir: Option<&Path>,
    rng: &mut SimRng,
) -> Result<Vec<Circle>, ScenarioError> {
    let field = |name: &str| format!("world.posts[{i}].{name}");
    if p.name.trim().is_empty() {
        return Err(check.error(&field("name"), "must not be empty"));
    }
    let radius = match p.radius_m {
        Some(r) => Some(check.open_range(&field("radius_m"), r, 0.0, 5.0)?),
        None => None,
    };
    match (&p.line, &p.csv) {
        (Some(line), None) => {
            let curve = polyline(check, &field("line"), line)?;
            let Some(spacing) = p.spacing_m else {
                return Err(check.error(&field("spacing_m"), "required with `line`"));
            };
            let spacing = check.open_range(&field("spacing_m"), spacing, 0.0, 1000.0)?;
            let Some(radius) = radius else {
                return Err(check.error(&field("radius_m"), "required with `line`"));
            };
            if 2.0 * radius >= spacing {
                return Err(check.error(
                    &field("radius_m"),
                    &format!("a post's diameter must be below spacing_m = {spacing}, got radius {radius}"),
                ));
            }
            if curve.length() / spacing > MAX_POSTS as f64 {
                return Err(check.error(
                    &field("spacing_m"),
                    &format!("gives more than {MAX_POSTS} posts; use a larger spacing"),
                ));
            }
            let all = posts_along(&curve, spacing, radius);
            for (j, &m) in p.missing.iter().enumerate() {
                if m >= all.len() {
                    return Err(check.error(
                        &field(&format!("missing[{j}]")),
                        &format!(
                            "no post {m}: the line holds posts 0 to {}",
                            all.len().saturating_sub(1)
                        ),
                    ));
                }
            }
            let fraction = check.range(
                &field("missing_fraction"),
                p.missing_fraction.unwrap_or(0.0),
                0.0,
                1.0,
            )?;
            let mut kept = Vec::with_capacity(all.len());
            for (k, post) in all.into_iter().enumerate() {
                if p.missing.contains(&k) {
                    continue;
                }
                if fraction > 0.0 && rng.random::<f64>() < fraction {
                    continue;
                }
                kept.push(post);
            }
            Ok(kept)
        }
        (None, Some(file)) => {
            for (name, given) in [
                ("line", p.line.is_some()),
                ("spacing_m", p.spacing_m.is_some()),
                ("missing", !p.missing.is_empty()),
                ("missing_fraction", p.missing_fraction.is_some()),
            ] {
                if given {
                    return Err(check.error(
                        &field(name),
                        "not with `csv`: the file lists the posts that stand",
                    ));
                }
            }
            let table = Table::read(
                file,
                base_dir,
                &field("csv"),
                &["x_m", "y_m", "radius_m"],
                *check,
            )?;
            let points = table.points()?;
            let radius_column = table.optional("radius_m");
            if radius_column.is_none() && radius.is_none() {
                return Err(table.column("radius_m").err().unwrap_or_else(|| {
                    check.error(&field("radius_m"), "required without a `radius_m` column")
                }));
            }
            let mut posts = Vec::with_capacity(points.len());
            for (record, (_, [x, y])) in table.records.iter().zip(&points) {
                let r = match radius_column {
                    Some(k) => table.number(record, k, 1e-3, 5.0)?,
                    None => radius.unwrap_or(0.05),
                };
                posts.push(Circle {
                    center: [*x, *y],
                    radius: r,
                });
            }
            // Two posts overlapping are a survey written twice.
            let lines: Vec<usize> = points.iter().map(|(l, _)| *l).collect();
            let discs: Vec<([f64; 2], f64)> = posts.iter().map(|c| (c.center, c.radius)).collect();
            if let Some((a, b)) = first_overlap(&discs, 5.0, |d, ra, rb| d < ra + rb) {
                let (la, lb) = (
                    lines.get(a).copied().unwrap_or(0),
                    lines.get(b).copied().unwrap_or(0),
                );
                return Err(table.at(lb, 0, &format!("this post overlaps the post of line {la}")));
            }
            Ok(posts)
        }
        _ => Err(check.error(
            &format!("world.posts[{i}]"),
            "give either `line` (with `spacing_m` and `radius_m`) or `csv`",
        )),
    }
}

/// The first pair `(a, b)`, `a < b`, of discs `(centre, radius)` for which
/// `clash(distance, radius_a, radius_b)` holds, looking only at centres
/// closer than `reach` m (a grid of `reach` cells).
fn first_overlap(
    discs: &[([f64; 2], f64)],
    reach: f64,
    clash: impl Fn(f64, f64, f64) -> bool,
) -> Option<(usize, usize)> {
    let cell_of = |p: [f64; 2]| ((p[0] / reach).floor() as i64, (p[1] / reach).floor() as i64);
    let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (b, (p, rb)) in discs.iter().enumerate() {
        let (cx, cy) = cell_of(*p);
        for nx in cx - 1..=cx + 1 {
            for ny in cy - 1..=cy + 1 {
                for &a in cells.get(&(nx, ny)).map_or(&[][..], Vec::as_slice) {
                    if let Some((q, ra)) = discs.get(a) {
                        if clash((p[0] - q[0]).hypot(p[1] - q[1]), *ra, *rb) {
                            return Some((a, b));
                        }
                    }
                }
            }
        }
        cells.entry((cx, cy)).or_default().push(b);
    }
    None
}

/// The plants of `[world] plants_csv` (columns `x_m`, `y_m`, `radius_m`,
/// `height_m`, optionally `kind`: `crop` or `grass`, default `crop`),
/// refused when two stems repeat one another or a crop plant stands under
/// the robot at its start pose `initial` (it would count as crushed before
/// the robot moves).
pub(super) fn csv_plants(
    world: Option<&WorldSection>,
    check: &Checker<'_>,
    base_dir: Option<&Path>,
    initial: &Pose2<World>,
    vehicle: &VehicleParams,
) -> Result<Vec<Plant>, ScenarioError> {
    let Some(file) = world.and_then(|w| w.plants_csv.as_deref()) else {
        return Ok(Vec::new());
    };
    let table = Table::read(
        file,
        base_dir,
        "world.plants_csv",
        &["x_m", "y_m", "radius_m", "height_m", "kind"],
        *check,
    )?;
    if table.records.len() > MAX_PLANTS {
        return Err(check.error(
            "world.plants_csv",
            &format!("more than {MAX_PLANTS} plants"),
        ));
    }
    let points = table.points()?;
    let (r, h) = (table.column("radius_m")?, table.column("height_m")?);
    let kind = table.optional("kind");
    let mut plants = Vec::with_capacity(points.len());
    for (record, (_, [x, y])) in table.records.iter().zip(&points) {
        let radius = table.number(record, r, 1e-3, 1.0)?;
        let height = table.number(record, h, 1e-3, 5.0)?;
        let kind = match kind.map(|k| (k, table.text(record, k))) {
            None | Some((_, "crop")) => PlantKind::Crop,
            Some((_, "grass")) => PlantKind::Grass,
            Some((k, other)) => {
                return Err(table.at(
                    record.line,
                    k,
                    &format!("`{other}` is neither `crop` nor `grass`"),
                ))
            }
        };
        let position = Point2::new(*x, *y).map_err(|e| table.at(record.line, 0, &e.to_string()))?;
        plants.push(Plant {
            position,
            radius,
            height,
            kind,
        });
    }
    let discs: Vec<([f64; 2], f64)> = points.iter().map(|(_, p)| (*p, 0.0)).collect();
    if let Some((a, b)) = first_overlap(&discs, 0.01, |d, _, _| d < DUPLICATE_M) {
        let line = |i: usize| points.get(i).map_or(0, |(l, _)| *l);
        return Err(table.at(
            line(b),
            0,
            &format!(
                "duplicate plant: the stem of line {} stands within 1 mm",
                line(a)
            ),
        ));
    }
    for ((line, _), plant) in points.iter().zip(&plants) {
        if plant.kind == PlantKind::Crop && under_robot(plant, initial, vehicle) {
            return Err(table.at(
                *line,
                0,
                "this crop plant stands under the robot at its start pose (initial): it would be crushed before the run begins",
            ));
        }
    }
    Ok(plants)
}

/// Whether `plant`'s footprint overlaps the rectangle the wheels' contact
/// patches span at pose `pose` (rear axle to a wheelbase ahead, track wide,
/// widened by half a tyre all round).
fn under_robot(plant: &Plant, pose: &Pose2<World>, vehicle: &VehicleParams) -> bool {
    let (s, c) = pose.heading.get().sin_cos();
    let (dx, dy) = (
        plant.position.x() - pose.position.x(),
        plant.position.y() - pose.position.y(),
    );
    let (fwd, left) = (dx * c + dy * s, -dx * s + dy * c);
    let half_tyre = 0.5 * vehicle.tyre_width_m;
    let length = vehicle.wheelbase.get().get();
    let half_width = 0.5 * vehicle.track_m + half_tyre;
    // Distance from the plant's stem to the rectangle.
    let ex = (-half_tyre - fwd).max(fwd - length - half_tyre).max(0.0);
    let ey = (left.abs() - half_width).max(0.0);
    ex.hypot(ey) < plant.radius
}
