//! The centre line of a plot or a hedge: straight from a start pose, or a
//! polyline with rounded corners given inline (`centre`) or by a CSV file
//! (`centre_csv`); errors about a vertex name it (`centre[k]`, or the CSV
//! file's line).

use std::path::Path;

use crate::error::{ScenarioError, TableError};
use crate::scenario::check::Checker;
use crate::scenario::schema::StartPose;
use crate::scenario::table::Table;
use crate::world::curve::{Curve, CurveError};

/// The most vertices a centre line may have.
const MAX_VERTICES: usize = 10_000;

/// The longest centre line, m.
const MAX_LENGTH: f64 = 10_000.0;

/// The shape fields of one `[[world.plots]]` or `[[world.hedges]]`.
#[derive(Debug, Clone, Copy)]
pub(super) struct ShapeFields<'a> {
    /// `start`.
    pub start: Option<&'a StartPose>,
    /// `length_m`.
    pub length_m: Option<f64>,
    /// `centre`.
    pub centre: Option<&'a [[f64; 2]]>,
    /// `centre_csv`.
    pub centre_csv: Option<&'a str>,
    /// `corner_radius_m`.
    pub corner_radius_m: Option<f64>,
}

/// Where a centre line's vertices came from, to name one in an error.
#[derive(Debug, Clone)]
pub(super) struct Vertices {
    /// `world.plots[i].centre` or `world.hedges[i].centre_csv`.
    field: String,
    /// The CSV file and each vertex's line in it.
    csv: Option<(String, Vec<usize>)>,
}

impl Vertices {
    /// Vertices written inline in the field `field`.
    pub fn inline(field: &str) -> Self {
        Self {
            field: field.to_owned(),
            csv: None,
        }
    }

    /// The error `e` of the curve, at the vertex it names.
    pub fn error(&self, check: &Checker<'_>, e: &CurveError) -> ScenarioError {
        let vertex = match *e {
            CurveError::TooFewVertices => 0,
            CurveError::NotFinite { vertex }
            | CurveError::RepeatedVertex { vertex }
            | CurveError::FoldsBack { vertex, .. }
            | CurveError::NoRoom { vertex }
            | CurveError::TooTight { vertex, .. }
            | CurveError::Crosses { vertex, .. } => vertex,
        };
        let reason = match (&self.csv, *e) {
            (Some((_, lines)), CurveError::Crosses { other, .. }) => format!(
                "{e} (the vertices on lines {} and {})",
                lines.get(vertex).copied().unwrap_or(0),
                lines.get(other).copied().unwrap_or(0)
            ),
            _ => e.to_string(),
        };
        match &self.csv {
            None => check.error(&format!("{}[{vertex}]", self.field), &reason),
            Some((file, lines)) => ScenarioError::Table(Box::new(TableError {
                origin: check.origin().to_owned(),
                field: self.field.clone(),
                file: file.clone(),
                line: lines.get(vertex).or(lines.last()).copied().unwrap_or(1),
                column: (1, "x_m".to_owned()),
                reason,
            })),
        }
    }
}

/// A checked centre line.
#[derive(Debug, Clone)]
pub(super) enum Shape {
    /// Straight from `start` ([x, y], m) along `heading` (rad) for `length` m.
    Straight {
        /// Start, world frame, m.
        start: [f64; 2],
        /// Heading, rad.
        heading: f64,
        /// Length, m.
        length: f64,
    },
    /// Along a rounded polyline.
    Curved {
        /// The curve.
        curve: Curve,
        /// Where its vertices came from.
        vertices: Vertices,
    },
}

impl Shape {
    /// Start, heading at the start and length.
    pub fn start_heading_length(&self) -> ([f64; 2], f64, f64) {
        match self {
            Self::Straight {
                start,
                heading,
                length,
            } => (*start, *heading, *length),
            Self::Curved { curve, .. } => {
                let (x, y, h) = curve.pose_at(0.0);
                ([x, y], h, curve.length())
            }
        }
    }

    /// The curve, if any.
    pub fn curve(&self) -> Option<&Curve> {
        match self {
            Self::Straight { .. } => None,
            Self::Curved { curve, .. } => Some(curve),
        }
    }

    /// Checks that a band of `half_width` m along the centre line neither
    /// folds nor crosses itself (always true of a straight one).
    pub fn check_band(&self, check: &Checker<'_>, half_width: f64) -> Result<(), ScenarioError> {
        match self {
            Self::Straight { .. } => Ok(()),
            Self::Curved { curve, vertices } => curve
                .check_band(half_width)
                .map_err(|e| vertices.error(check, &e)),
        }
    }
}

/// The centre line of the plot or hedge `prefix` (`world.plots[3]`): exactly
/// one of `start` with `length_m`, `centre` and `centre_csv` (read relative
/// to `base_dir`).
pub(super) fn shape(
    check: &Checker<'_>,
    prefix: &str,
    fields: ShapeFields<'_>,
    base_dir: Option<&Path>,
) -> Result<Shape, ScenarioError> {
    let field = |name: &str| format!("{prefix}.{name}");
    let radius = match fields.corner_radius_m {
        Some(r) => Some(check.range(&field("corner_radius_m"), r, 0.0, 1000.0)?),
        None => None,
    };
    let (points, vertices) = match (
        fields.start,
        fields.length_m,
        fields.centre,
        fields.centre_csv,
    ) {
        (Some(start), Some(length), None, None) => {
            if radius.is_some() {
                return Err(check.error(
                    &field("corner_radius_m"),
                    "only with `centre` or `centre_csv`",
                ));
            }
            let ([x, y], heading) = start_pose(check, &field("start"), start)?;
            let length = check.open_range(&field("length_m"), length, 0.0, 1000.0)?;
            return Ok(Shape::Straight {
                start: [x, y],
                heading,
                length,
            });
        }
        (None, None, Some(centre), None) => {
            let name = field("centre");
            for (k, v) in centre.iter().enumerate() {
                check.range(&format!("{name}[{k}][0]"), v[0], -1e6, 1e6)?;
                check.range(&format!("{name}[{k}][1]"), v[1], -1e6, 1e6)?;
            }
            (
                centre.to_vec(),
                Vertices {
                    field: name,
                    csv: None,
                },
            )
        }
        (None, None, None, Some(file)) => {
            let name = field("centre_csv");
            let table = Table::read(file, base_dir, &name, &["x_m", "y_m"], *check)?;
            let rows = table.points()?;
            (
                rows.iter().map(|(_, p)| *p).collect(),
                Vertices {
                    field: name,
                    csv: Some((file.to_owned(), rows.iter().map(|(l, _)| *l).collect())),
                },
            )
        }
        (Some(_), None, None, None) => {
            return Err(check.error(&field("length_m"), "required with `start`"))
        }
        (None, Some(_), None, None) => {
            return Err(check.error(&field("start"), "required with `length_m`"))
        }
        _ => {
            return Err(check.error(
                prefix,
                "give either `start` and `length_m`, or `centre`, or `centre_csv`",
            ))
        }
    };
    if points.len() > MAX_VERTICES {
        return Err(check.error(
            &vertices.field,
            &format!("more than {MAX_VERTICES} vertices"),
        ));
    }
    let curve =
        Curve::new(&points, radius.unwrap_or(0.0)).map_err(|e| vertices.error(check, &e))?;
    if curve.length() > MAX_LENGTH {
        return Err(check.error(
            &vertices.field,
            &format!(
                "the centre line is {} m long, more than {MAX_LENGTH} m",
                curve.length()
            ),
        ));
    }
    Ok(Shape::Curved { curve, vertices })
}

/// The start of a plot's or a hedge's centre line, `field` naming it: its
/// position `[x, y]` within ±1e6 m and its heading (radians) within ±360°.
pub(super) fn start_pose(
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
