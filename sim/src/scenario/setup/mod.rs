//! Validates a whole scenario file into a typed simulation [`Setup`]: its
//! top-level fields (`name`, `description`, `seed`) here, every section by its
//! own module; a value out of range is an error naming `section.field`.
//!
//! [`build`] checks the name and puts the sections together. One module per
//! section: `path` (`[path]` and `[initial]`), `vehicle`, `control`,
//! `terrain`, `sensors` (`[noise]` and `[gnss]`), `world`, `lidar` (`[lidar]`
//! and `[horizontal_lidar]`), `edge`, `furrow`, `switching`, `run` (`[run]`
//! and `[metrics]`).

mod control;
mod edge;
mod furrow;
mod lidar;
mod path;
mod run;
mod sensors;
mod shape;
mod speeds;
mod structures;
mod switching;
mod terrain;
mod vehicle;
mod world;

use std::path::Path;

use fieldguide::{Pose2, World};

use super::check::Checker;
use super::reference::Piece;
use super::schema::ScenarioFile;
use crate::error::ScenarioError;
use crate::plant::VehicleParams;
use crate::rng::SimRng;
use crate::sensors::SensorNoise;
use crate::world::crops::PlotSpec;
use crate::world::World as SimWorld;

pub use self::control::ControlSetup;
pub use self::edge::EdgeSetup;
pub use self::furrow::FurrowSetup;
pub use self::lidar::{HorizontalLidarSetup, LidarSetup};
pub use self::run::{MetricsSpec, RunLimits};
pub use self::speeds::PathSpeeds;
pub use self::switching::{PlanSetup, SwitchingSetup, EDGE, FURROW};
pub use crate::capacity::{Reference, PATH_CAPACITY};
pub use crate::gnss::{GnssErrors, GnssOutages};
use crate::lidar::{Mounted, MountedLidar};

/// Everything a run needs, validated and typed.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Scenario name (output folder).
    pub name: String,
    /// What the scenario shows.
    pub description: String,
    /// Seed of the run's generator.
    pub seed: u64,
    /// The reference path (boxed: it holds up to [`PATH_CAPACITY`] vertices).
    pub path: Box<Reference>,
    /// Nominal pieces of a segment path (empty for a CSV path).
    pub pieces: Vec<Piece>,
    /// The robot's initial pose (O), world frame.
    pub initial: Pose2<World>,
    /// The vehicle.
    pub vehicle: VehicleParams,
    /// The guidance.
    pub control: ControlSetup,
    /// Terrain and plants.
    pub world: SimWorld,
    /// Sensor noise.
    pub noise: SensorNoise,
    /// Duration and integration.
    pub run: RunLimits,
    /// Convergence and success bounds.
    pub metrics: MetricsSpec,
    /// The inclined LiDAR, if any.
    pub lidar: Option<LidarSetup>,
    /// Furrow pursuing, if configured (then the run's guidance pursues the
    /// furrow while the detector's verdict allows it).
    pub furrow: Option<FurrowSetup>,
    /// The horizontal LiDAR, if any.
    pub horizontal_lidar: Option<HorizontalLidarSetup>,
    /// Edge following, if configured (then the run's guidance follows the
    /// edge while the detector's verdict allows it).
    pub edge: Option<EdgeSetup>,
    /// The switching machine's delays and plan check.
    pub switching: SwitchingSetup,
    /// When the RTK-GNSS has no fix.
    pub gnss_outages: GnssOutages,
    /// The RTK-GNSS's errors beyond its white noise.
    pub gnss_errors: GnssErrors,
    /// The desired speed of path tracking along the path (`speed_m_s` of `[path] segments`).
    pub path_speeds: PathSpeeds,
}

impl Setup {
    /// The LiDARs on the robot, in the order they scan in a tick: the
    /// inclined one of `[lidar]`, its scans routed to furrow pursuing, then
    /// the horizontal one of `[horizontal_lidar]`, routed to edge following.
    #[must_use]
    pub fn lidars(&self) -> Vec<MountedLidar> {
        let inclined = self.lidar.map(|l| MountedLidar {
            sensor: Mounted::Inclined(l.lidar),
            route: FURROW,
            scan_every: l.scan_every,
        });
        let horizontal = self.horizontal_lidar.map(|l| MountedLidar {
            sensor: Mounted::Horizontal(l.lidar),
            route: EDGE,
            scan_every: l.scan_every,
        });
        inclined.into_iter().chain(horizontal).collect()
    }
}

/// Builds the setup of `file` (called `origin` in messages; `base_dir` resolves
/// a waypoint CSV). Draws the path's recording noise from `rng`, the run's generator.
pub fn build(
    file: &ScenarioFile,
    origin: &str,
    base_dir: Option<&Path>,
    rng: &mut SimRng,
) -> Result<Setup, ScenarioError> {
    let check = Checker::new(origin);
    check_name(&check, &file.name)?;

    let plots = world::plots(file.world.as_ref(), &check, base_dir)?;
    let specs: Vec<PlotSpec> = plots.iter().map(|p| p.spec.clone()).collect();
    let vehicle = vehicle::vehicle(file, &check)?;
    let (path, pieces) = path::path(
        file,
        &specs,
        min_turn_radius(&vehicle),
        base_dir,
        &check,
        rng,
    )?;
    let control = control::control(file, &check, vehicle)?;
    let initial = path::initial_pose(file, &check, &path)?;
    // The plants are drawn after the path's recording noise, the hedges after the plants.
    let mut plants = world::plants(file.world.as_ref(), &plots, &check, rng)?;
    plants.extend(structures::csv_plants(
        file.world.as_ref(),
        &check,
        base_dir,
        &initial,
        &vehicle,
    )?);
    let (hedges, mut obstacles) = world::hedges(file.world.as_ref(), &check, base_dir, rng)?;
    // Posts and fences after the hedges (drawn only for posts missing by chance).
    structures::posts_and_fences(file.world.as_ref(), &check, base_dir, rng, &mut obstacles)?;
    let world = SimWorld {
        terrain: terrain::terrain(file, &check)?,
        plants,
        plots,
        hedges,
        obstacles,
        obstacle_height: world::obstacle_height(file.world.as_ref(), &check)?,
    };
    let noise = sensors::noise(file, &check)?;
    let gnss_outages = sensors::gnss_outages(file, &check, &path, &specs)?;
    let gnss_errors = sensors::gnss_errors(file, &check, &path)?;
    let path_speeds = speeds::path_speeds(file, &check, &control, &pieces, &specs)?;
    let lidar = match &file.lidar {
        Some(l) => Some(lidar::lidar(l, control.period_s, &check)?),
        None => None,
    };
    let furrow = match &file.furrow {
        None => None,
        Some(f) => {
            let Some(l) = &lidar else {
                return Err(check.error("furrow", "needs a `[lidar]` section to see the rows"));
            };
            if file.world.is_none() {
                return Err(check.error("furrow", "needs a `[world]` section with plots"));
            }
            Some(furrow::furrow(f, l, &control.backstepping, &check)?)
        }
    };
    let horizontal_lidar = match &file.horizontal_lidar {
        Some(l) => Some(lidar::horizontal_lidar(l, control.period_s, &check)?),
        None => None,
    };
    let edge = match &file.edge {
        None => None,
        Some(e) => {
            let Some(l) = &horizontal_lidar else {
                return Err(check.error(
                    "edge",
                    "needs a `[horizontal_lidar]` section to see the edge",
                ));
            };
            Some(edge::edge(e, l, &control.backstepping, &check)?)
        }
    };
    // Every LiDAR's scans go to a configured behaviour (GD-INPUT).
    if lidar.is_some() && furrow.is_none() {
        return Err(check.error(
            "lidar",
            "its scans go to furrow pursuing: needs a `[furrow]` section",
        ));
    }
    if horizontal_lidar.is_some() && edge.is_none() {
        return Err(check.error(
            "horizontal_lidar",
            "its scans go to edge following: needs an `[edge]` section",
        ));
    }
    let configured: Vec<_> = [
        furrow.map(|_| switching::FURROW),
        edge.map(|_| switching::EDGE),
    ]
    .into_iter()
    .flatten()
    .collect();
    let switching = switching::switching(file, &configured, control.period_s, &check)?;
    let run = run::run(file, control.period_s, &check)?;
    let metrics = run::metrics(file, &check)?;
    Ok(Setup {
        name: file.name.clone(),
        description: file.description.clone(),
        seed: file.seed,
        path,
        pieces,
        initial,
        vehicle,
        control,
        world,
        noise,
        run,
        metrics,
        lidar,
        furrow,
        horizontal_lidar,
        edge,
        switching,
        gnss_outages,
        gnss_errors,
        path_speeds,
    })
}

/// The vehicle's least turning radius, m: wheelbase / tan(max steering).
fn min_turn_radius(vehicle: &VehicleParams) -> f64 {
    vehicle.wheelbase.get().get() / vehicle.actuator.limit.get().get().tan()
}

/// Checks the scenario's `name`: it names the output folder.
pub(crate) fn check_name(check: &Checker<'_>, name: &str) -> Result<(), ScenarioError> {
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if ok {
        Ok(())
    } else {
        Err(check.error(
            "name",
            "must be non-empty and use only letters, digits, `-` and `_` (it names the output folder)",
        ))
    }
}
