//! From a parsed scenario file to a typed simulation [`Setup`]: every range is
//! checked here, and a value out of range is an error naming `section.field`.

use std::path::Path;

use fieldguide::control::backstepping::{BacksteppingConfig, Inversion, SteeringLimit};
use fieldguide::control::Gains;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::model::bicycle::{Sideslip, Wheelbase};
use fieldguide::perception::edge::{EdgeConfig, EdgeParameters, Side};
use fieldguide::perception::furrow::{FurrowConfig, FurrowParams, Rows};
use fieldguide::supervisor::switching::PlanTolerance;
use fieldguide::{Meters, MetersPerSecond, Point2, Pose2, Radians, Seconds, World};

use super::check::Checker;
use super::reference::{self, Piece};
use super::schema::{
    CropName, EdgeSection, FurrowSection, HorizontalLidarSection, InversionName, LidarSection,
    ScenarioFile, SideName, WorldSection,
};
use crate::error::ScenarioError;
use crate::guidance::pipeline::{EDGE_CHAIN, EDGE_RAYS, FURROW_RAYS, FURROW_SCANS};
use crate::lidar::horizontal::{HorizontalLidar, HorizontalLidarSpec};
use crate::lidar::inclined::InclinedLidar;
use crate::plant::{SteeringActuator, VehicleParams};
use crate::rng::SimRng;
use crate::sensors::SensorNoise;
use crate::world::crops::{scatter_grass, PlotSpec, Spread};
use crate::world::hedge::{HedgeSpec, Obstacles};
use crate::world::terrain::{SlipPatch, Terrain};
use crate::world::{Hedge, Plot, World as SimWorld};

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
    /// Largest in-plot mean |error to the true centre line| of a successful run, metres.
    pub in_plot_mean_abs_m: Option<f64>,
    /// Largest in-plot max |error to the true centre line| of a successful run, metres.
    pub in_plot_max_abs_m: Option<f64>,
    /// Band on |error to a hedge's true offset line| that counts as converged, metres.
    pub along_hedge_band_m: f64,
    /// Largest mean |error to the true offset line| along the hedges after
    /// convergence of a successful run, metres.
    pub along_hedge_mean_abs_m: Option<f64>,
    /// Largest max |error to the true offset line| along the hedges after
    /// convergence of a successful run, metres.
    pub along_hedge_max_abs_m: Option<f64>,
}

/// The inclined LiDAR and how often it scans.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LidarSetup {
    /// The sensor and its mount.
    pub lidar: InclinedLidar,
    /// A scan every this many control ticks (the scan period over the control period).
    pub scan_every: u64,
}

/// The horizontal LiDAR and how often it scans.
#[derive(Debug, Clone, Copy)]
pub struct HorizontalLidarSetup {
    /// The sensor and its mount.
    pub lidar: HorizontalLidar,
    /// A scan every this many control ticks.
    pub scan_every: u64,
}

/// Edge following: the detector's validated configuration, the side, and the law it drives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeSetup {
    /// The detector (Table 1 with the library's choices), mount taken from `[horizontal_lidar]`.
    pub detector: EdgeConfig,
    /// Where the edge is.
    pub side: Side,
    /// The backstepping law of edge following, without sideslip (Pierre 2022,
    /// section 2.2: "this version of the control law does not include an
    /// estimation of sideslip angles").
    pub backstepping: BacksteppingConfig,
    /// Forward speed while following the edge.
    pub speed: MetersPerSecond,
}

/// Furrow pursuing: the detector's validated configuration and the law it drives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FurrowSetup {
    /// The detector (Table 2 with the library's choices), mount taken from `[lidar]`.
    pub detector: FurrowConfig,
    /// The backstepping law of furrow pursuing: no sideslip, no prediction
    /// (Pierre 2022, section 2.3.1: "this version of the control law does not
    /// include an estimation of sideslip angles or the predictive layer").
    pub backstepping: BacksteppingConfig,
    /// Forward speed while pursuing the furrow.
    pub speed: MetersPerSecond,
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
    /// The inclined LiDAR, if any.
    pub lidar: Option<LidarSetup>,
    /// Furrow pursuing, if configured (then the run's guidance pursues the
    /// furrow while the detector's verdict allows it, see
    /// [`crate::guidance::pipeline`]).
    pub furrow: Option<FurrowSetup>,
    /// The horizontal LiDAR, if any.
    pub horizontal_lidar: Option<HorizontalLidarSetup>,
    /// Edge following, if configured (then the run's guidance follows the
    /// edge while the detector's verdict allows it, see
    /// [`crate::guidance::pipeline`]).
    pub edge: Option<EdgeSetup>,
    /// The switching machine's delays and plan check.
    pub switching: SwitchingSetup,
    /// When the RTK-GNSS has no fix.
    pub gnss_outages: GnssOutages,
}

/// Spans of simulated time `[from, to)` without a GNSS fix, seconds, in
/// increasing order without overlap.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GnssOutages(Vec<(f64, f64)>);

impl GnssOutages {
    /// Whether the GNSS has a fix at time `t_s`.
    #[must_use]
    pub fn has_fix(&self, t_s: f64) -> bool {
        !self.0.iter().any(|(from, to)| t_s >= *from && t_s < *to)
    }

    /// The spans, seconds.
    #[must_use]
    pub fn spans(&self) -> &[(f64, f64)] {
        &self.0
    }
}

/// Plan consistency (SW-PLAN-CONSISTENCY) as configured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanSetup {
    /// Largest offset and heading difference of a consistent line.
    pub tolerance: PlanTolerance,
    /// How long a line may disagree before its behaviour is left.
    pub delay: Seconds,
}

/// `[switching]`, typed (defaults: Tables 1-2 and the library's GD-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchingSetup {
    /// Time to transit to edge following, s.
    pub edge_enter_s: f64,
    /// Time to transit back from edge following, s.
    pub edge_exit_s: f64,
    /// Time to transit to furrow pursuing, s.
    pub furrow_enter_s: f64,
    /// Time to transit back from furrow pursuing, s.
    pub furrow_exit_s: f64,
    /// Stop after this long without a source, s.
    pub stop_delay_s: f64,
    /// Largest age of a held detection, s.
    pub max_scan_age_s: f64,
    /// Plan consistency, when on.
    pub plan: Option<PlanSetup>,
}

fn switching(file: &ScenarioFile, check: &Checker) -> Result<SwitchingSetup, ScenarioError> {
    let s = file.switching.unwrap_or_default();
    let pos = |field: &str, v: Option<f64>, default: f64| -> Result<f64, ScenarioError> {
        check.positive(&format!("switching.{field}"), v.unwrap_or(default))
    };
    let plan = match s.plan_max_offset_m {
        None => {
            if s.plan_max_heading_deg.is_some()
                || s.plan_delay_s.is_some()
                || s.plan_lookahead_m.is_some()
            {
                return Err(check.error(
                    "switching.plan_max_offset_m",
                    "plan consistency needs its offset when its heading, delay or look-ahead is set",
                ));
            }
            None
        }
        Some(offset) => {
            let offset = check.positive("switching.plan_max_offset_m", offset)?;
            let heading = check.range(
                "switching.plan_max_heading_deg",
                s.plan_max_heading_deg.unwrap_or(20.0),
                0.0,
                180.0,
            )?;
            let delay = pos("plan_delay_s", s.plan_delay_s, 0.3)?;
            let lookahead = check.non_negative(
                "switching.plan_lookahead_m",
                s.plan_lookahead_m.unwrap_or(0.0),
            )?;
            let err =
                |f: &'static str| move |e: fieldguide::Precondition| check.error(f, &e.to_string());
            Some(PlanSetup {
                tolerance: PlanTolerance::new(
                    Meters::new(offset).map_err(err("switching.plan_max_offset_m"))?,
                    Radians::new(heading.to_radians())
                        .map_err(err("switching.plan_max_heading_deg"))?,
                )
                .map_err(err("switching.plan_max_offset_m"))?
                .with_lookahead(Meters::new(lookahead).map_err(err("switching.plan_lookahead_m"))?)
                .map_err(err("switching.plan_lookahead_m"))?,
                delay: Seconds::new(delay).map_err(err("switching.plan_delay_s"))?,
            })
        }
    };
    Ok(SwitchingSetup {
        edge_enter_s: pos("edge_enter_s", s.edge_enter_s, 0.4)?,
        edge_exit_s: pos("edge_exit_s", s.edge_exit_s, 0.26)?,
        furrow_enter_s: pos("furrow_enter_s", s.furrow_enter_s, 0.5)?,
        furrow_exit_s: pos("furrow_exit_s", s.furrow_exit_s, 0.3)?,
        stop_delay_s: pos("stop_delay_s", s.stop_delay_s, 0.5)?,
        max_scan_age_s: pos("max_scan_age_s", s.max_scan_age_s, 0.1)?,
        plan,
    })
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

    let plots = plots(file.world.as_ref(), &check)?;
    let specs: Vec<PlotSpec> = plots.iter().map(|p| p.spec.clone()).collect();
    let w = reference::waypoints(&file.path, &specs, PATH_CAPACITY, base_dir, &check, rng)?;
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
    // The plants are drawn after the path's recording noise, the hedges after the plants.
    let plants = plants(file.world.as_ref(), &plots, &check, rng)?;
    let (hedges, obstacles) = hedges(file.world.as_ref(), &check, rng)?;
    let world = SimWorld {
        terrain: terrain(file, &check)?,
        plants,
        plots,
        hedges,
        obstacles,
    };
    let noise = noise(file, &check)?;
    let gnss_outages = gnss_outages(file, &check)?;
    let lidar = match &file.lidar {
        Some(l) => Some(lidar(l, control.period_s, &check)?),
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
            Some(furrow(
                f,
                l,
                vehicle,
                control.backstepping.inversion,
                &check,
            )?)
        }
    };
    let horizontal_lidar = match &file.horizontal_lidar {
        Some(l) => Some(horizontal_lidar(l, control.period_s, &check)?),
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
            if furrow.is_some() {
                return Err(check.error(
                    "edge",
                    "one specialised behaviour per scenario: `[furrow]` is already set (switching between them is issue 5)",
                ));
            }
            Some(edge(e, l, vehicle, control.backstepping.inversion, &check)?)
        }
    };
    let switching = switching(file, &check)?;
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
    let optional_positive = |field: &str, v: Option<f64>| -> Result<Option<f64>, ScenarioError> {
        v.map(|v| check.positive(field, v)).transpose()
    };
    let metrics = MetricsSpec {
        band_m: check.positive("metrics.band_m", file.metrics.band_m)?,
        converge_within_m: check
            .positive("metrics.converge_within_m", file.metrics.converge_within_m)?,
        in_plot_mean_abs_m: optional_positive(
            "metrics.in_plot_mean_abs_m",
            file.metrics.in_plot_mean_abs_m,
        )?,
        in_plot_max_abs_m: optional_positive(
            "metrics.in_plot_max_abs_m",
            file.metrics.in_plot_max_abs_m,
        )?,
        along_hedge_band_m: check.positive(
            "metrics.along_hedge_band_m",
            file.metrics.along_hedge_band_m,
        )?,
        along_hedge_mean_abs_m: optional_positive(
            "metrics.along_hedge_mean_abs_m",
            file.metrics.along_hedge_mean_abs_m,
        )?,
        along_hedge_max_abs_m: optional_positive(
            "metrics.along_hedge_max_abs_m",
            file.metrics.along_hedge_max_abs_m,
        )?,
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
        lidar,
        furrow,
        horizontal_lidar,
        edge,
        switching,
        gnss_outages,
    })
}

fn gnss_outages(file: &ScenarioFile, check: &Checker<'_>) -> Result<GnssOutages, ScenarioError> {
    let mut spans: Vec<(f64, f64)> = Vec::new();
    for (i, [from, to]) in file
        .gnss
        .as_ref()
        .map_or(&[][..], |g| g.outages_s.as_slice())
        .iter()
        .copied()
        .enumerate()
    {
        let field = format!("gnss.outages_s[{i}]");
        let earliest = spans.last().map_or(0.0, |(_, end)| *end);
        let from = check.non_negative(&field, from)?;
        let to = check.finite(&field, to)?;
        if from < earliest {
            return Err(check.error(&field, "must start after the previous outage ends"));
        }
        if to <= from {
            return Err(check.error(&field, "must end after it starts"));
        }
        spans.push((from, to));
    }
    Ok(GnssOutages(spans))
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

/// The plots of `[world]`, validated (no plant drawn yet).
fn plots(world: Option<&WorldSection>, check: &Checker<'_>) -> Result<Vec<Plot>, ScenarioError> {
    let Some(world) = world else {
        return Ok(Vec::new());
    };
    let mut plots = Vec::with_capacity(world.plots.len());
    for (i, p) in world.plots.iter().enumerate() {
        let field = |name: &str| format!("world.plots[{i}].{name}");
        if p.name.trim().is_empty() {
            return Err(check.error(&field("name"), "must not be empty"));
        }
        let start = Point2::<World>::new(
            check.range(&field("start.x_m"), p.start.x_m, -1e6, 1e6)?,
            check.range(&field("start.y_m"), p.start.y_m, -1e6, 1e6)?,
        )
        .map_err(|e| check.error(&field("start"), &e.to_string()))?;
        let heading = check
            .range(
                &field("start.heading_deg"),
                p.start.heading_deg,
                -360.0,
                360.0,
            )?
            .to_radians();
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
            let from = check.range(&field(&format!("bare_m[{k}][0]")), b[0], 0.0, length)?;
            let to = check.range(&field(&format!("bare_m[{k}][1]")), b[1], 0.0, length)?;
            if to <= from {
                return Err(check.error(
                    &field(&format!("bare_m[{k}]")),
                    &format!("must be [from_m, to_m] with from_m < to_m, got [{from}, {to}]"),
                ));
            }
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
fn plants(
    world: Option<&WorldSection>,
    plots: &[Plot],
    check: &Checker<'_>,
    rng: &mut SimRng,
) -> Result<Vec<crate::world::Plant>, ScenarioError> {
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
            v.kind = crate::world::PlantKind::Grass;
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

/// The inclined LiDAR of `[lidar]`; its scan period must be a whole number of
/// control periods `period_s`.
fn lidar(
    l: &LidarSection,
    period_s: f64,
    check: &Checker<'_>,
) -> Result<LidarSetup, ScenarioError> {
    let height = check.open_range("lidar.height_m", l.height_m, 0.0, 10.0)?;
    let pitch = check.open_range("lidar.pitch_deg", l.pitch_deg, 0.0, 90.0)?;
    let fov = check.open_range("lidar.field_of_view_deg", l.field_of_view_deg, 0.0, 360.0)?;
    let (rays, range_min, range_max) =
        rays_and_ranges(check, "lidar", l.rays, l.range_min_m, l.range_max_m)?;
    let scan_every = scan_every(check, "lidar.rate_hz", l.rate_hz, period_s)?;
    Ok(LidarSetup {
        lidar: InclinedLidar {
            mount_x: check.range("lidar.mount_x_m", l.mount_x_m, -20.0, 20.0)?,
            mount_y: check.range("lidar.mount_y_m", l.mount_y_m, -20.0, 20.0)?,
            height,
            pitch: pitch.to_radians(),
            field_of_view: fov.to_radians(),
            rays,
            range_min,
            range_max,
            range_noise: check.range("lidar.range_noise_m", l.range_noise_m, 0.0, 1.0)?,
        },
        scan_every,
    })
}

/// The scan period of a LiDAR scanning at `rate_hz` (field `field`) in
/// control periods of `period_s`: it must be a whole number, at least 1.
fn scan_every(
    check: &Checker<'_>,
    field: &str,
    rate_hz: f64,
    period_s: f64,
) -> Result<u64, ScenarioError> {
    let rate = check.open_range(field, rate_hz, 0.0, 1000.0)?;
    let ticks = 1.0 / (rate * period_s);
    let every = ticks.round();
    if every < 1.0 || (ticks - every).abs() > 1e-6 * ticks {
        return Err(check.error(
            field,
            &format!(
                "the scan period 1/{rate} s must be a whole number of control periods ({period_s} s)"
            ),
        ));
    }
    // A whole number in [1, 1e6 / period]: the conversion is exact.
    Ok(every as u64)
}

/// The hedges of `[world]`, validated, and their outlines drawn from `rng`.
fn hedges(
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
        let mut gaps = Vec::with_capacity(h.gaps_m.len());
        for (k, g) in h.gaps_m.iter().enumerate() {
            let from = check.range(&field(&format!("gaps_m[{k}][0]")), g[0], 0.0, length)?;
            let to = check.range(&field(&format!("gaps_m[{k}][1]")), g[1], 0.0, length)?;
            if to <= from {
                return Err(check.error(
                    &field(&format!("gaps_m[{k}]")),
                    &format!("must be [from_m, to_m] with from_m < to_m, got [{from}, {to}]"),
                ));
            }
            gaps.push([from, to]);
        }
        let spec = HedgeSpec {
            start: [
                check.range(&field("start.x_m"), h.start.x_m, -1e6, 1e6)?,
                check.range(&field("start.y_m"), h.start.y_m, -1e6, 1e6)?,
            ],
            heading: check
                .range(
                    &field("start.heading_deg"),
                    h.start.heading_deg,
                    -360.0,
                    360.0,
                )?
                .to_radians(),
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

/// The horizontal LiDAR of `[horizontal_lidar]`; its scan period must be a
/// whole number of control periods `period_s`.
fn horizontal_lidar(
    l: &HorizontalLidarSection,
    period_s: f64,
    check: &Checker<'_>,
) -> Result<HorizontalLidarSetup, ScenarioError> {
    let fov = check.range(
        "horizontal_lidar.field_of_view_deg",
        l.field_of_view_deg,
        0.0,
        360.0,
    )?;
    if fov <= 0.0 {
        return Err(check.error(
            "horizontal_lidar.field_of_view_deg",
            &format!("must be within (0, 360], got {fov}"),
        ));
    }
    let (rays, range_min, range_max) = rays_and_ranges(
        check,
        "horizontal_lidar",
        l.rays,
        l.range_min_m,
        l.range_max_m,
    )?;
    let spec = HorizontalLidarSpec {
        mount_xy: [
            check.range("horizontal_lidar.mount_x_m", l.mount_x_m, -20.0, 20.0)?,
            check.range("horizontal_lidar.mount_y_m", l.mount_y_m, -20.0, 20.0)?,
        ],
        mount_heading: check
            .range(
                "horizontal_lidar.mount_heading_deg",
                l.mount_heading_deg,
                -180.0,
                180.0,
            )?
            .to_radians(),
        field_of_view: fov.to_radians(),
        rays,
        range_min,
        range_max,
        noise_sigma: check.range("horizontal_lidar.range_noise_m", l.range_noise_m, 0.0, 1.0)?,
    };
    let lidar = HorizontalLidar::new(spec)
        .map_err(|e| check.error(&format!("horizontal_lidar.{}", e.field), e.reason))?;
    Ok(HorizontalLidarSetup {
        lidar,
        scan_every: scan_every(check, "horizontal_lidar.rate_hz", l.rate_hz, period_s)?,
    })
}

/// The edge detector and law of `[edge]`, the mount taken from `[horizontal_lidar]`.
fn edge(
    e: &EdgeSection,
    lidar: &HorizontalLidarSetup,
    vehicle: VehicleParams,
    inversion: Inversion,
    check: &Checker<'_>,
) -> Result<EdgeSetup, ScenarioError> {
    let rays = lidar.lidar.spec().rays;
    if rays > EDGE_RAYS {
        return Err(check.error(
            "horizontal_lidar.rays",
            &format!("edge following takes at most {EDGE_RAYS} rays, got {rays}"),
        ));
    }
    let speed = check.open_range("edge.speed_m_s", e.speed_m_s, 0.0, 20.0)?;
    let g_y = check.positive("edge.lateral_gain", e.lateral_gain)?;
    let g_theta = check.positive("edge.heading_gain", e.heading_gain)?;
    let ratio = check.range("edge.min_gain_ratio", e.min_gain_ratio, 1.0, 1e6)?;
    // Same convention as [control]: table gains g are positive, k = −g.
    let gains = Gains::new(-g_y, -g_theta, ratio).map_err(|err| {
        check.error(
            "edge.heading_gain",
            &format!(
                "heading_gain / lateral_gain = {} is below edge.min_gain_ratio = {ratio} ({err})",
                g_theta / g_y
            ),
        )
    })?;
    let radius = check.open_range("edge.circle_radius_m", e.circle_radius_m, 0.0, 100.0)?;
    let rotation = check.open_range("edge.max_rotation_deg", e.max_rotation_deg, 0.0, 360.0)?;
    let l_max = check.open_range("edge.max_chain_length_m", e.max_chain_length_m, 0.0, 1000.0)?;
    let l_min = check.range("edge.min_chain_length_m", e.min_chain_length_m, 0.0, l_max)?;
    check.below(
        "edge.min_chain_length_m",
        l_min,
        "edge.max_chain_length_m",
        l_max,
    )?;
    let min_points = usize::try_from(e.min_points).unwrap_or(usize::MAX);
    if !(4..=EDGE_CHAIN).contains(&min_points) {
        return Err(check.error(
            "edge.min_points",
            &format!("must be within [4, {EDGE_CHAIN}], got {}", e.min_points),
        ));
    }
    let enter = check.open_range("edge.enter_residual_m", e.enter_residual_m, 0.0, 100.0)?;
    let exit = check.open_range("edge.exit_residual_m", e.exit_residual_m, 0.0, 100.0)?;
    check.above("edge.exit_residual_m", exit, "edge.enter_residual_m", enter)?;
    let params = EdgeParameters {
        radius,
        max_rotation: rotation.to_radians(),
        max_chain_length: l_max,
        search_distance: check.open_range(
            "edge.search_distance_m",
            e.search_distance_m,
            0.0,
            1000.0,
        )?,
        offset: check.range("edge.desired_distance_m", e.desired_distance_m, 0.0, 1000.0)?,
        min_chain_length: l_min,
        max_link: check.open_range("edge.max_link_m", e.max_link_m, 0.0, 1000.0)?,
        max_turn: check
            .range("edge.max_turn_deg", e.max_turn_deg, 0.0, 180.0)
            .and_then(|v| {
                if v > 0.0 {
                    Ok(v)
                } else {
                    Err(check.error("edge.max_turn_deg", "must be within (0, 180], got 0"))
                }
            })?
            .to_radians(),
        max_width: check.open_range("edge.max_width_m", e.max_width_m, 0.0, 1000.0)?,
        min_points,
        sigma_enter: enter,
        sigma_exit: exit,
    };
    // Every value was range-checked above; what the core still refuses is
    // reported against the section, with the requirement it names.
    let detector = EdgeConfig::new(&params).map_err(|err| {
        check.error(
            "edge",
            &format!("the core refuses the configuration: {err}"),
        )
    })?;
    Ok(EdgeSetup {
        detector,
        side: match e.side {
            SideName::Left => Side::Left,
            SideName::Right => Side::Right,
        },
        backstepping: BacksteppingConfig {
            gains,
            wheelbase: vehicle.wheelbase,
            max_steering: vehicle.actuator.limit,
            inversion,
        },
        speed: MetersPerSecond::new(speed)
            .map_err(|err| check.error("edge.speed_m_s", &err.to_string()))?,
    })
}

/// Number of rays of `lidar` whose angle lies within ±`half` rad (the
/// detector's window), counted as the core counts them.
fn window_rays(lidar: &InclinedLidar, half: f64) -> usize {
    (0..lidar.rays)
        .map(|j| lidar.angle_min() + j as f64 * lidar.angle_increment())
        .filter(|a| (-half..=half).contains(a))
        .count()
}

/// The furrow detector and law of `[furrow]`, the mount taken from `[lidar]`.
fn furrow(
    f: &FurrowSection,
    lidar: &LidarSetup,
    vehicle: VehicleParams,
    inversion: Inversion,
    check: &Checker<'_>,
) -> Result<FurrowSetup, ScenarioError> {
    let speed = check.open_range("furrow.speed_m_s", f.speed_m_s, 0.0, 20.0)?;
    let g_y = check.positive("furrow.lateral_gain", f.lateral_gain)?;
    let g_theta = check.positive("furrow.heading_gain", f.heading_gain)?;
    let ratio = check.range("furrow.min_gain_ratio", f.min_gain_ratio, 1.0, 1e6)?;
    // Same convention as [control]: table gains g are positive, k = −g.
    let gains = Gains::new(-g_y, -g_theta, ratio).map_err(|e| {
        check.error(
            "furrow.heading_gain",
            &format!(
                "heading_gain / lateral_gain = {} is below furrow.min_gain_ratio = {ratio} ({e})",
                g_theta / g_y
            ),
        )
    })?;
    let half = check
        .open_range(
            "furrow.window_half_angle_deg",
            f.window_half_angle_deg,
            0.0,
            90.0,
        )?
        .to_radians();
    let in_window = window_rays(&lidar.lidar, half);
    if in_window > FURROW_RAYS {
        return Err(check.error(
            "furrow.window_half_angle_deg",
            &format!(
                "the window holds {in_window} rays of the LiDAR, more than the detector's {FURROW_RAYS}"
            ),
        ));
    }
    let width = f.template_width_rays;
    if width % 2 == 0 || width > 999 {
        return Err(check.error(
            "furrow.template_width_rays",
            &format!("must be odd and at most 999 (the model is centred on a ray), got {width}"),
        ));
    }
    if f.template_margin_rays > 999 {
        return Err(check.error(
            "furrow.template_margin_rays",
            &format!("must be at most 999, got {}", f.template_margin_rays),
        ));
    }
    let h_ref = check.open_range("furrow.template_height_m", f.template_height_m, 0.0, 10.0)?;
    let floor = check.range("furrow.height_floor_m", f.height_floor_m, 0.0, h_ref)?;
    check.below(
        "furrow.height_floor_m",
        floor,
        "furrow.template_height_m",
        h_ref,
    )?;
    let c_t = check.open_range("furrow.peak_threshold", f.peak_threshold, 0.0, 1.0)?;
    let rows = match (f.rows, f.min_row_spacing_m, f.max_row_spacing_m) {
        (1, None, None) => Rows::One,
        (1, _, _) => {
            return Err(check.error(
                "furrow.rows",
                "one row takes no `min_row_spacing_m` / `max_row_spacing_m`",
            ))
        }
        (2, Some(lo), Some(hi)) => {
            let lo = check.open_range("furrow.min_row_spacing_m", lo, 0.0, 100.0)?;
            let hi = check.open_range("furrow.max_row_spacing_m", hi, 0.0, 100.0)?;
            check.above(
                "furrow.max_row_spacing_m",
                hi,
                "furrow.min_row_spacing_m",
                lo,
            )?;
            Rows::Two {
                min_spacing: meters(check, "furrow.min_row_spacing_m", lo)?,
                max_spacing: meters(check, "furrow.max_row_spacing_m", hi)?,
            }
        }
        (2, None, _) => {
            return Err(check.error("furrow.min_row_spacing_m", "required with rows = 2"))
        }
        (2, _, None) => {
            return Err(check.error("furrow.max_row_spacing_m", "required with rows = 2"))
        }
        (n, _, _) => return Err(check.error("furrow.rows", &format!("must be 1 or 2, got {n}"))),
    };
    let scans = usize::try_from(f.averaged_scans).unwrap_or(usize::MAX);
    if !(1..=FURROW_SCANS).contains(&scans) {
        return Err(check.error(
            "furrow.averaged_scans",
            &format!(
                "must be within [1, {FURROW_SCANS}], got {}",
                f.averaged_scans
            ),
        ));
    }
    if !(2..=1000).contains(&f.min_points) {
        return Err(check.error(
            "furrow.min_points",
            &format!("must be within [2, 1000], got {}", f.min_points),
        ));
    }
    let enter = check.range("furrow.enter_correlation", f.enter_correlation, 0.0, 1.0)?;
    let exit = check.range("furrow.exit_correlation", f.exit_correlation, 0.0, 1.0)?;
    check.above(
        "furrow.enter_correlation",
        enter,
        "furrow.exit_correlation",
        exit,
    )?;
    let l = &lidar.lidar;
    let keep = check.open_range("furrow.keep_distance_m", f.keep_distance_m, 0.0, 1000.0)?;
    let extent = check.range("furrow.min_extent_m", f.min_extent_m, 0.0, 100.0)?;
    let params = FurrowParams {
        mount_x: meters(check, "lidar.mount_x_m", l.mount_x)?,
        mount_y: meters(check, "lidar.mount_y_m", l.mount_y)?,
        mount_height: meters(check, "lidar.height_m", l.height)?,
        mount_pitch: Radians::new(l.pitch)
            .map_err(|e| check.error("lidar.pitch_deg", &e.to_string()))?,
        window_half_angle: Radians::new(half)
            .map_err(|e| check.error("furrow.window_half_angle_deg", &e.to_string()))?,
        template_width: usize::try_from(width).unwrap_or(1),
        template_margin: usize::try_from(f.template_margin_rays).unwrap_or(0),
        template_height: meters(check, "furrow.template_height_m", h_ref)?,
        height_floor: meters(check, "furrow.height_floor_m", floor)?,
        peak_threshold: c_t,
        rows,
        averaged_scans: scans,
        keep_distance: meters(check, "furrow.keep_distance_m", keep)?,
        min_points: usize::try_from(f.min_points).unwrap_or(2),
        min_extent: meters(check, "furrow.min_extent_m", extent)?,
        enter,
        exit,
    };
    // Every value was range-checked above; what the core still refuses is
    // reported against the section, with the requirement it names.
    let detector = FurrowConfig::new(&params).map_err(|e| {
        check.error(
            "furrow",
            &format!("the core refuses the configuration: {e}"),
        )
    })?;
    Ok(FurrowSetup {
        detector,
        backstepping: BacksteppingConfig {
            gains,
            wheelbase: vehicle.wheelbase,
            max_steering: vehicle.actuator.limit,
            inversion,
        },
        speed: MetersPerSecond::new(speed)
            .map_err(|e| check.error("furrow.speed_m_s", &e.to_string()))?,
    })
}

/// `value` as core `Meters` (already range-checked, so only a non-finite
/// value could fail), the error naming `field`.
fn meters(check: &Checker<'_>, field: &str, value: f64) -> Result<Meters, ScenarioError> {
    Meters::new(value).map_err(|e| check.error(field, &e.to_string()))
}

/// The ray count and valid range interval shared by both LiDAR sections
/// (`section` names them in errors): 2 to 10 000 rays, 0 ≤ min < max ≤ 1000 m.
fn rays_and_ranges(
    check: &Checker<'_>,
    section: &str,
    rays: u32,
    range_min: f64,
    range_max: f64,
) -> Result<(usize, f64, f64), ScenarioError> {
    let rays = usize::try_from(rays)
        .ok()
        .filter(|r| (2..=10_000).contains(r))
        .ok_or_else(|| {
            check.error(
                &format!("{section}.rays"),
                &format!("must be within [2, 10000], got {rays}"),
            )
        })?;
    let min_field = format!("{section}.range_min_m");
    let max_field = format!("{section}.range_max_m");
    let range_min = check.range(&min_field, range_min, 0.0, 1000.0)?;
    let range_max = check.range(&max_field, range_max, 0.0, 1000.0)?;
    check.above(&max_field, range_max, &min_field, range_min)?;
    Ok((rays, range_min, range_max))
}
