//! Validates `[path]`, the reference path built by the core from the
//! waypoints of [`crate::scenario::reference`], and `[initial]`, the robot's
//! start pose beside it.

use std::path::Path;

use fieldguide::geometry::path::PathConfig;
use fieldguide::{Meters, Point2, Pose2, World};

use crate::capacity::{Reference, PATH_CAPACITY};
use crate::error::ScenarioError;
use crate::rng::SimRng;
use crate::scenario::check::Checker;
use crate::scenario::reference::{self, Piece};
use crate::scenario::schema::ScenarioFile;
use crate::world::crops::PlotSpec;

/// The reference path of `[path]` (`plots` for a path along them joined
/// with `min_turn_radius`, the vehicle's least turning radius, `base_dir`
/// resolving a waypoint CSV, the recording noise drawn from `rng`) and its
/// nominal pieces with their abscissas on it.
pub(super) fn path(
    file: &ScenarioFile,
    plots: &[PlotSpec],
    min_turn_radius: f64,
    base_dir: Option<&Path>,
    check: &Checker<'_>,
    rng: &mut SimRng,
) -> Result<(Box<Reference>, Vec<Piece>), ScenarioError> {
    let w = reference::waypoints(
        &file.path,
        plots,
        min_turn_radius,
        PATH_CAPACITY,
        base_dir,
        check,
        rng,
    )?;
    let window = check.positive("path.smoothing_window_m", file.path.smoothing_window_m)?;
    let points = w
        .points
        .iter()
        .map(|p| Point2::<World>::new(p[0], p[1]))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| check.error("path", &e.to_string()))?;
    let config = PathConfig::new(
        Meters::new(window).map_err(|e| check.error("path.smoothing_window_m", &e.to_string()))?,
    )
    .map_err(|e| check.error("path.smoothing_window_m", &e.to_string()))?;
    let path = Box::new(
        Reference::from_waypoints(&points, config)
            .map_err(|e| check.refused("path", "waypoints", &e))?,
    );
    let pieces = w
        .pieces
        .iter()
        .map(|p| project_piece(&path, p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| check.error("path.segments", &e.to_string()))?;
    Ok((path, pieces))
}

/// `piece` with its abscissas those of its nominal end points projected on `path`
/// (searched within 2 m of the nominal abscissa, so a U-turn's other leg cannot capture them).
fn project_piece(path: &Reference, piece: &Piece) -> Result<Piece, fieldguide::Precondition> {
    let at = |p: [f64; 2], s: f64| -> Result<f64, fieldguide::Precondition> {
        let pose = Pose2::<World>::new(p[0], p[1], 0.0)?;
        Ok(path
            .project_near(&pose, Meters::ZERO, Meters::new(s)?, Meters::new(2.0)?)?
            .s
            .get())
    };
    Ok(Piece {
        s_start: at(piece.start, piece.s_start)?,
        s_end: at(piece.end, piece.s_end)?,
        ..*piece
    })
}

/// The start pose: offsets in the Frénet frame of the path's first point.
pub(super) fn initial_pose(
    file: &ScenarioFile,
    check: &Checker<'_>,
    path: &Reference,
) -> Result<Pose2<World>, ScenarioError> {
    let i = &file.initial;
    let long = check.range("initial.longitudinal_m", i.longitudinal_m, -1e4, 1e4)?;
    let lat = check.range("initial.lateral_m", i.lateral_m, -1e4, 1e4)?;
    let dh = check.open_range("initial.heading_deg", i.heading_deg, -90.0, 90.0)?;
    let p0 = path
        .point_at(Meters::ZERO)
        .map_err(|e| check.error("path", &e.to_string()))?;
    let h0 = path.heading_at(Meters::ZERO).get();
    let (s, c) = h0.sin_cos();
    Pose2::new(
        p0.x() + long * c - lat * s,
        p0.y() + long * s + lat * c,
        h0 + dh.to_radians(),
    )
    .map_err(|e| check.error("initial", &e.to_string()))
}
