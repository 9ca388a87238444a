//! From a parsed scenario file to a typed simulation [`Setup`]: every range is
//! checked here, and a value out of range is an error naming `section.field`.

use std::path::Path;

use fieldguide::control::backstepping::{BacksteppingConfig, Inversion, SteeringLimit};
use fieldguide::control::Gains;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::model::bicycle::{Sideslip, Wheelbase};
use fieldguide::{Meters, MetersPerSecond, Point2, Pose2, World};

use super::check::Checker;
use super::reference::{self, Piece};
use super::schema::{InversionName, ScenarioFile};
use crate::error::ScenarioError;
use crate::plant::{SteeringActuator, VehicleParams};
use crate::rng::SimRng;
use crate::sensors::SensorNoise;
use crate::world::terrain::{SlipPatch, Terrain};
use crate::world::World as SimWorld;

/// Most waypoints a reference path may hold (409.6 m at the usual 0.1 m spacing).
pub const PATH_CAPACITY: usize = 4096;

/// The reference path type of the simulator.
pub type Reference = ReferencePath<PATH_CAPACITY>;

/// The guidance settings, typed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlSetup {
    /// The backstepping law's configuration (gains in equation form, k = −g).
    pub backstepping: BacksteppingConfig,
    /// Forward speed v.
    pub speed: MetersPerSecond,
    /// Control period, seconds.
    pub period_s: f64,
    /// Prediction horizon T, seconds.
    pub horizon_s: f64,
    /// Curvature look-ahead distance v T.
    pub lookahead: Meters,
    /// Whether the law uses the observer's sideslip estimate.
    pub sideslip_compensation: bool,
}

/// How long a run lasts and how finely the plant is integrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunLimits {
    /// Longest simulated time, seconds.
    pub duration_s: f64,
    /// Stop when the robot's projection reaches the end of the path.
    pub stop_at_path_end: bool,
    /// Plant sub-steps per control period.
    pub substeps: u32,
}

/// Bounds of the summary's convergence and success (`sim/scenarios/README.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricsSpec {
    /// Convergence band on |y|, metres.
    pub band_m: f64,
    /// Largest `converged_after_m` of a successful run, metres.
    pub converge_within_m: f64,
}

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

    let w = reference::waypoints(&file.path, PATH_CAPACITY, base_dir, &check, rng)?;
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
            .map_err(|e| check.error("path", &format!("the core refuses the waypoints: {e}")))?,
    );

    let pieces = w
        .pieces
        .iter()
        .map(|p| project_piece(&path, p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| check.error("path.segments", &e.to_string()))?;
    let vehicle = vehicle(file, &check)?;
    let control = control(file, &check, vehicle)?;
    let initial = initial_pose(file, &check, &path)?;
    let world = SimWorld {
        terrain: terrain(file, &check)?,
        plants: Vec::new(),
    };
    let noise = noise(file, &check)?;
    let run = RunLimits {
        duration_s: check.open_range("run.duration_s", file.run.duration_s, 0.0, 1e6)?,
        stop_at_path_end: file.run.stop_at_path_end,
        substeps: if (1..=1000).contains(&file.run.substeps) {
            file.run.substeps
        } else {
            return Err(check.error(
                "run.substeps",
                &format!("must be within [1, 1000], got {}", file.run.substeps),
            ));
        },
    };
    let metrics = MetricsSpec {
        band_m: check.positive("metrics.band_m", file.metrics.band_m)?,
        converge_within_m: check
            .positive("metrics.converge_within_m", file.metrics.converge_within_m)?,
    };
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
    })
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

fn check_name(check: &Checker<'_>, name: &str) -> Result<(), ScenarioError> {
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

fn vehicle(file: &ScenarioFile, check: &Checker<'_>) -> Result<VehicleParams, ScenarioError> {
    let v = &file.vehicle;
    let wheelbase = Wheelbase::new(check.positive("vehicle.wheelbase_m", v.wheelbase_m)?)
        .map_err(|e| check.error("vehicle.wheelbase_m", &e.to_string()))?;
    let max = check.open_range("vehicle.max_steering_deg", v.max_steering_deg, 0.0, 90.0)?;
    let limit = SteeringLimit::new(max.to_radians())
        .map_err(|e| check.error("vehicle.max_steering_deg", &e.to_string()))?;
    let settling = check.range(
        "vehicle.steering_settling_s",
        v.steering_settling_s,
        0.0,
        60.0,
    )?;
    let rate = check.positive("vehicle.steering_rate_deg_s", v.steering_rate_deg_s)?;
    Ok(VehicleParams {
        wheelbase,
        track_m: check.positive("vehicle.track_m", v.track_m)?,
        tyre_width_m: check.non_negative("vehicle.tyre_width_m", v.tyre_width_m)?,
        actuator: SteeringActuator::from_settling(settling, rate.to_radians(), limit),
    })
}

fn control(
    file: &ScenarioFile,
    check: &Checker<'_>,
    vehicle: VehicleParams,
) -> Result<ControlSetup, ScenarioError> {
    let c = &file.control;
    let speed = check.open_range("control.speed_m_s", c.speed_m_s, 0.0, 20.0)?;
    let period_s = check.open_range("control.period_s", c.period_s, 0.0, 1.0)?;
    let g_y = check.positive("control.lateral_gain", c.lateral_gain)?;
    let g_theta = check.positive("control.heading_gain", c.heading_gain)?;
    let ratio = check.range("control.min_gain_ratio", c.min_gain_ratio, 1.0, 1e6)?;
    // Table gains are positive; the law's equation-form gains are k = −g.
    let gains = Gains::new(-g_y, -g_theta, ratio).map_err(|e| {
        check.error(
            "control.heading_gain",
            &format!(
                "heading_gain / lateral_gain = {} is below control.min_gain_ratio = {ratio} ({e})",
                g_theta / g_y
            ),
        )
    })?;
    let horizon_s = check.range("control.horizon_s", c.horizon_s, 0.0, 10.0)?;
    let lookahead = Meters::new(speed * horizon_s)
        .map_err(|e| check.error("control.horizon_s", &e.to_string()))?;
    Ok(ControlSetup {
        backstepping: BacksteppingConfig {
            gains,
            wheelbase: vehicle.wheelbase,
            max_steering: vehicle.actuator.limit,
            inversion: match c.inversion {
                InversionName::Exact => Inversion::Exact,
                InversionName::Printed => Inversion::Printed,
            },
        },
        speed: MetersPerSecond::new(speed)
            .map_err(|e| check.error("control.speed_m_s", &e.to_string()))?,
        period_s,
        horizon_s,
        lookahead,
        sideslip_compensation: c.sideslip_compensation,
    })
}

/// The start pose: offsets in the Frénet frame of the path's first point.
fn initial_pose(
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

fn sideslip(
    check: &Checker<'_>,
    prefix: &str,
    front_deg: f64,
    rear_deg: f64,
) -> Result<Sideslip, ScenarioError> {
    let front = check.range(
        &format!("{prefix}front_sideslip_deg"),
        front_deg,
        -45.0,
        45.0,
    )?;
    let rear = check.range(&format!("{prefix}rear_sideslip_deg"), rear_deg, -45.0, 45.0)?;
    Sideslip::new(front.to_radians(), rear.to_radians())
        .map_err(|e| check.error(&format!("{prefix}front_sideslip_deg"), &e.to_string()))
}

fn terrain(file: &ScenarioFile, check: &Checker<'_>) -> Result<Terrain, ScenarioError> {
    let t = &file.terrain;
    let base = sideslip(check, "terrain.", t.front_sideslip_deg, t.rear_sideslip_deg)?;
    let mut patches = Vec::with_capacity(t.patches.len());
    for (i, p) in t.patches.iter().enumerate() {
        let prefix = format!("terrain.patches[{i}].");
        if p.polygon.len() < 3 {
            return Err(check.error(&format!("{prefix}polygon"), "needs at least 3 vertices"));
        }
        for (k, v) in p.polygon.iter().enumerate() {
            check.finite(&format!("{prefix}polygon[{k}][0]"), v[0])?;
            check.finite(&format!("{prefix}polygon[{k}][1]"), v[1])?;
        }
        patches.push(SlipPatch {
            name: p.name.clone(),
            polygon: p.polygon.clone(),
            sideslip: sideslip(check, &prefix, p.front_sideslip_deg, p.rear_sideslip_deg)?,
        });
    }
    Ok(Terrain { base, patches })
}

fn noise(file: &ScenarioFile, check: &Checker<'_>) -> Result<SensorNoise, ScenarioError> {
    let n = &file.noise;
    Ok(SensorNoise {
        gnss_position_m: check.range("noise.gnss_position_m", n.gnss_position_m, 0.0, 10.0)?,
        gnss_heading_rad: check
            .range("noise.gnss_heading_deg", n.gnss_heading_deg, 0.0, 45.0)?
            .to_radians(),
        sideslip_rad: check
            .range("noise.sideslip_deg", n.sideslip_deg, 0.0, 45.0)?
            .to_radians(),
        sideslip_observer_settling_s: check.range(
            "noise.sideslip_observer_settling_s",
            n.sideslip_observer_settling_s,
            0.0,
            60.0,
        )?,
        odometry_scale_error: check.range(
            "noise.odometry_scale_error",
            n.odometry_scale_error,
            -0.5,
            0.5,
        )?,
        odometry_yaw_bias_rad_s: check
            .range(
                "noise.odometry_yaw_bias_deg_s",
                n.odometry_yaw_bias_deg_s,
                -90.0,
                90.0,
            )?
            .to_radians(),
        odometry_yaw_noise_rad: check
            .range(
                "noise.odometry_yaw_noise_deg",
                n.odometry_yaw_noise_deg,
                0.0,
                45.0,
            )?
            .to_radians(),
    })
}
