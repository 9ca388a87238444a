//! The core pipeline [`fieldguide::guidance::Guidance`] driving the simulated
//! robot: detections, switching (Pierre 2022, section 3, with the transit
//! delays of Tables 1-2), laws and command, all in the library. The
//! simulator only feeds it each tick's scans (on their scan ticks, routed to
//! their behaviours), the GNSS pose, the odometry pose and the sideslip
//! estimate, and maps its [`TickOutput`] to the sim's [`Command`] and trace
//! fields. No switching logic lives in the simulator. With a speed per
//! segment of the path, it hands path tracking the speed of the stretch the
//! robot's own latest projection is on (GD-SPEED-CHANGE).

use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::guidance::{
    BehaviourParams, BehaviourStatus, Guidance as Core, GuidanceConfig, GuidanceParams, Mode,
    PathTrackingParams, TickOutput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::model::Vehicle;
use fieldguide::perception::edge::EdgeDetectorConfig;
use fieldguide::perception::{AnyDetector, AnyDetectorConfig};
use fieldguide::{Meters, Precondition, Seconds};

use super::{Command, DetectorStatus, Guidance, TickInput, SEARCH_WINDOW_M};
use crate::capacity::{EDGE_CHAIN, EDGE_RAYS, FURROW_RAYS, FURROW_SCANS, PATH_CAPACITY};
use crate::plant::Plant;
use crate::scenario::setup::{PathSpeeds, Setup};
pub use crate::scenario::setup::{EDGE, FURROW};

/// Most behaviours a scenario configures.
pub const BEHAVIOURS: usize = 2;

/// The detectors at the simulator's capacities.
pub type SimDetector = AnyDetector<EDGE_RAYS, EDGE_CHAIN, FURROW_RAYS, FURROW_SCANS>;

/// The core pipeline at the simulator's capacities.
pub type CorePipeline<'p> = Core<'p, PATH_CAPACITY, SimDetector, BacksteppingConfig, BEHAVIOURS>;

/// The core's output of one tick, as the simulator's pipeline holds it.
pub type CoreOutput = TickOutput<Sideslip, BEHAVIOURS>;

/// The core pipeline as one simulator [`Guidance`].
#[derive(Debug, Clone)]
pub struct Pipeline<'p> {
    core: Box<CorePipeline<'p>>,
    period_s: f64,
    last: Option<CoreOutput>,
    /// The latest command sent and whether it was saturated.
    held: Option<(fieldguide::model::Command, bool)>,
    /// The desired speed of path tracking along the path (empty: one speed).
    speeds: PathSpeeds,
}

/// The pipeline's parameters for `setup`: path tracking from `[control]`,
/// furrow pursuing from `[furrow]`, edge following from `[edge]` with the
/// horizontal LiDAR's mount, the transit delays, priority and plan check of
/// `[switching]`, the control period of `[control]`, the vehicle of
/// `[vehicle]`.
///
/// # Errors
/// A value the core refuses (named by its requirement).
pub fn params(
    setup: &Setup,
) -> Result<GuidanceParams<AnyDetectorConfig, BacksteppingConfig, BEHAVIOURS>, Precondition> {
    let c = &setup.control;
    let sw = &setup.switching;
    let plan = sw.plan.map(|p| p.tolerance);
    let mut behaviours = heapless::Vec::new();
    if let Some(f) = &setup.furrow {
        let furrow = BehaviourParams {
            id: FURROW,
            label: "furrow_pursuing",
            detector: AnyDetectorConfig::Furrow(f.detector),
            law: f.backstepping,
            speed: f.speed,
            enter_delay: Seconds::new(sw.furrow_enter_s)?,
            exit_delay: Seconds::new(sw.furrow_exit_s)?,
            plan,
        };
        behaviours
            .push(furrow)
            .map_err(|_| Precondition::new("GD-BEHAVIOURS", "more than K behaviours"))?;
    }
    if let (Some(e), Some(l)) = (&setup.edge, &setup.horizontal_lidar) {
        let edge = BehaviourParams {
            id: EDGE,
            label: "edge_following",
            detector: AnyDetectorConfig::Edge(EdgeDetectorConfig {
                edge: e.detector,
                mount: l.lidar.mount(),
                side: e.side,
            }),
            law: e.backstepping,
            speed: e.speed,
            enter_delay: Seconds::new(sw.edge_enter_s)?,
            exit_delay: Seconds::new(sw.edge_exit_s)?,
            plan,
        };
        behaviours
            .push(edge)
            .map_err(|_| Precondition::new("GD-BEHAVIOURS", "more than K behaviours"))?;
    }
    let priority = heapless::Vec::from_slice(&sw.priority)
        .map_err(|_| Precondition::new("GD-BEHAVIOURS", "more than K behaviours in priority"))?;
    Ok(GuidanceParams {
        period: Seconds::new(c.period_s)?,
        vehicle: Vehicle::Bicycle(setup.vehicle.bicycle()),
        path: PathTrackingParams {
            law: c.backstepping,
            speed: c.speed,
            horizon: Seconds::new(c.horizon_s)?,
            steering_lag: Seconds::new(c.steering_lag_s)?,
            compensation: c.sideslip_compensation,
            search_window: Meters::new(SEARCH_WINDOW_M)?,
        },
        behaviours,
        priority,
        stop_delay: Seconds::new(sw.stop_delay_s)?,
        plan_delay: sw.plan.map(|p| p.delay),
        max_scan_age: Seconds::new(sw.max_scan_age_s)?,
        plan_dead_reckoning: sw.plan.and_then(|p| p.dead_reckoning),
        bridge: sw.bridge,
        steer_before_resuming: sw.steer_before_resuming,
        handover: sw.handover,
        entry: sw.entry,
        fix: sw.fix,
        odometry_aid: sw.odometry_aid,
    })
}

impl<'p> Pipeline<'p> {
    /// The pipeline configured by `setup` on its reference path.
    ///
    /// # Errors
    /// A configuration the core refuses (GD-CONFIG and the detectors'
    /// requirements), named by its requirement ID.
    pub fn new(setup: &'p Setup) -> Result<Self, Precondition> {
        let config = GuidanceConfig::new(&params(setup)?)?;
        // The laws command the configured vehicle; the plant must take its commands.
        if config.params().vehicle.actuation() != setup.vehicle.actuation() {
            return Err(Precondition::new(
                "GD-VEHICLE",
                "the plant takes another actuation than the pipeline's vehicle",
            ));
        }
        let mut core = Box::new(CorePipeline::new(config, &setup.path)?);
        // The first tick drives at the speed of the path's first stretch.
        if let Some(v) = setup.path_speeds.at(0.0) {
            core.set_path_speed(v)?;
        }
        Ok(Self {
            core,
            period_s: setup.control.period_s,
            last: None,
            held: None,
            speeds: setup.path_speeds.clone(),
        })
    }

    /// The core pipeline (its switching machine, detectors, held detections).
    #[must_use]
    pub fn core(&self) -> &CorePipeline<'p> {
        &self.core
    }

    /// The core's output of the latest tick.
    #[must_use]
    pub const fn last(&self) -> Option<&CoreOutput> {
        self.last.as_ref()
    }
}

impl Guidance for Pipeline<'_> {
    fn step(&mut self, input: &TickInput<'_>) -> Result<Command, Precondition> {
        let r = input.readings;
        // The speed of the stretch of the robot's own latest projection (kept
        // through a tick without one).
        let reached = self
            .last
            .as_ref()
            .and_then(|o| o.path.frenet)
            .map(|f| f.s.get());
        if let Some(v) = reached.and_then(|s| self.speeds.at(s)) {
            if v != self.core.config().params().path.speed {
                self.core.set_path_speed(v)?;
            }
        }
        let out = self.core.step_with_fix(
            &fieldguide::guidance::TickInput {
                scans: input.scans,
                gnss: r.gnss,
                odometry: r.odometry,
                extra: r.sideslip,
            },
            &r.gnss_quality,
        )?;
        let mode = out.source.unwrap_or(out.mode);
        // The behaviour whose status is recorded: the one in charge, else the
        // one of highest priority.
        let status = |b: &BehaviourStatus| DetectorStatus {
            verdict: b.reported,
            scanned: b.scan_age == Some(0),
            age_s: b
                .scan_age
                .map_or(f64::INFINITY, |a| f64::from(a) * self.period_s),
            quality: b.quality,
            error: b.error,
        };
        let in_charge = match out.mode {
            Mode::Behaviour(id) => out.behaviour(id),
            Mode::PathTracking | Mode::Stop => None,
        };
        let detector = in_charge.or(out.behaviours.first()).map(status);
        let estimated_error = match out.source {
            Some(Mode::PathTracking) => out.path.frenet.map(fieldguide::TrackingError::from),
            Some(Mode::Behaviour(id)) => out.behaviour(id).and_then(|b| b.error),
            Some(Mode::Stop) | None => None,
        };
        let sideslip_used = if out.source == Some(Mode::PathTracking) {
            out.path.extra_used
        } else {
            Sideslip::ZERO
        };
        // A tick without a source outside Stop (GD-COMMAND): the vehicle
        // keeps the previous command.
        let rest = self.core.config().params().vehicle.actuation().at_rest();
        let (drive, saturated) = match (out.command, self.held) {
            (Some(c), _) => (c.command, c.saturated),
            (None, Some(held)) => held,
            (None, None) => (rest, false),
        };
        self.held = Some((drive, saturated));
        let command = Command {
            drive,
            mode,
            label: self.core.label(mode),
            switching_mode: out.mode,
            switching_label: self.core.label(out.mode),
            saturated,
            estimated_error,
            sideslip_used,
            detector,
            plan_pose: out.path.plan_pose,
            reference_offset: out.path.reference_offset.map(fieldguide::Meters::get),
            fix: out.path.fix,
        };
        self.last = Some(out);
        Ok(command)
    }
}
