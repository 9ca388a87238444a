//! The core pipeline [`fieldguide::guidance::Guidance`] driving the simulated
//! robot: detections, switching (Pierre 2022, section 3, with the transit
//! delays of Tables 1-2), backstepping and command, all in the library. The
//! simulator only feeds it each tick's scans (on their scan ticks), the GNSS
//! pose, the odometry pose and the sideslip estimate, and maps its
//! [`TickOutput`] to the sim's [`Command`] and trace fields. No switching
//! logic lives in the simulator.

use fieldguide::guidance::{
    ActiveMode, BehaviourStatus, EdgeFollowingParams, FurrowPursuingParams, Guidance as Core,
    GuidanceConfig, GuidanceParams, PathTrackingParams, PlanCheck, Priority, TickOutput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::{Meters, Precondition, Seconds};

use super::{Command, DetectorStatus, Guidance, Mode, TickInput, SEARCH_WINDOW_M};
use crate::scenario::setup::{Setup, PATH_CAPACITY};

/// Most valid rays of a horizontal scan (a LiDAR with more rays is refused,
/// naming `horizontal_lidar.rays`).
pub const EDGE_RAYS: usize = 2048;

/// Most chain points (`edge.min_points` at most this).
pub const EDGE_CHAIN: usize = 256;

/// Most rays of the furrow detector's angular window (a scenario whose window
/// holds more is refused, naming `furrow.window_half_angle_deg`).
pub const FURROW_RAYS: usize = 1024;

/// Most selections the furrow detector keeps (`furrow.averaged_scans` at most this).
pub const FURROW_SCANS: usize = 64;

/// The core pipeline at the simulator's capacities.
pub type CorePipeline<'p> =
    Core<'p, PATH_CAPACITY, EDGE_RAYS, EDGE_CHAIN, FURROW_RAYS, FURROW_SCANS>;

/// The core pipeline as one simulator [`Guidance`].
#[derive(Debug, Clone)]
pub struct Pipeline<'p> {
    core: Box<CorePipeline<'p>>,
    period_s: f64,
    last: Option<TickOutput>,
    /// The latest command sent (steering, speed, saturated).
    held: Option<(f64, fieldguide::MetersPerSecond, bool)>,
}

/// The pipeline's parameters for `setup`: path tracking from `[control]`,
/// edge following from `[edge]` with the horizontal LiDAR's mount, furrow
/// pursuing from `[furrow]`, the transit delays and plan check of
/// `[switching]`, the control period of `[control]`.
///
/// # Errors
/// A value the core refuses (named by its requirement).
pub fn params(setup: &Setup) -> Result<GuidanceParams, Precondition> {
    let c = &setup.control;
    let sw = &setup.switching;
    let path = PathTrackingParams {
        law: c.backstepping,
        speed: c.speed,
        horizon: Seconds::new(c.horizon_s)?,
        sideslip_compensation: c.sideslip_compensation,
        search_window: Meters::new(SEARCH_WINDOW_M)?,
    };
    let edge = match (&setup.edge, &setup.horizontal_lidar) {
        (Some(e), Some(l)) => Some(EdgeFollowingParams {
            detector: e.detector,
            mount: l.lidar.mount(),
            side: e.side,
            law: e.backstepping,
            speed: e.speed,
            enter_delay: Seconds::new(sw.edge_enter_s)?,
            exit_delay: Seconds::new(sw.edge_exit_s)?,
        }),
        _ => None,
    };
    let furrow = match &setup.furrow {
        Some(f) => Some(FurrowPursuingParams {
            detector: f.detector,
            law: f.backstepping,
            speed: f.speed,
            enter_delay: Seconds::new(sw.furrow_enter_s)?,
            exit_delay: Seconds::new(sw.furrow_exit_s)?,
        }),
        None => None,
    };
    Ok(GuidanceParams {
        period: Seconds::new(c.period_s)?,
        path,
        edge,
        furrow,
        priority: Priority::FurrowFirst,
        stop_delay: Seconds::new(sw.stop_delay_s)?,
        plan: sw.plan.map(|p| PlanCheck {
            tolerance: p.tolerance,
            delay: p.delay,
        }),
        max_scan_age: Seconds::new(sw.max_scan_age_s)?,
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
        Ok(Self {
            core: Box::new(CorePipeline::new(config, &setup.path)?),
            period_s: setup.control.period_s,
            last: None,
            held: None,
        })
    }

    /// The core pipeline (its switching machine, detectors, held detections).
    #[must_use]
    pub fn core(&self) -> &CorePipeline<'p> {
        &self.core
    }

    /// The core's output of the latest tick.
    #[must_use]
    pub const fn last(&self) -> Option<&TickOutput> {
        self.last.as_ref()
    }
}

/// The sim's mode of the core's.
#[must_use]
pub const fn mode_of(mode: ActiveMode) -> Mode {
    match mode {
        ActiveMode::PathTracking => Mode::PathTracking,
        ActiveMode::EdgeFollowing => Mode::EdgeFollowing,
        ActiveMode::FurrowPursuing => Mode::FurrowPursuing,
        ActiveMode::Stop => Mode::Stop,
    }
}

impl Guidance for Pipeline<'_> {
    fn step(&mut self, input: &TickInput<'_>) -> Result<Command, Precondition> {
        let r = input.readings;
        let inclined = match input.scan {
            Some(s) => Some(s.as_scan()?),
            None => None,
        };
        let out = self.core.step(&fieldguide::guidance::TickInput {
            horizontal: input.horizontal,
            inclined,
            gnss: r.gnss,
            odometry: r.odometry,
            sideslip: r.sideslip,
        })?;
        self.last = Some(out);
        let switching_mode = mode_of(out.mode);
        let mode = match out.source {
            Some(fieldguide::guidance::Source::PathTracking) => Mode::PathTracking,
            Some(fieldguide::guidance::Source::EdgeFollowing) => Mode::EdgeFollowing,
            Some(fieldguide::guidance::Source::FurrowPursuing) => Mode::FurrowPursuing,
            None => switching_mode,
        };
        // The behaviour whose status is recorded: the one in charge, else the
        // configured detector (furrow first, as the priority).
        let status = |b: &BehaviourStatus| -> Option<DetectorStatus> {
            b.configured.then(|| DetectorStatus {
                verdict: b.reported,
                scanned: b.scan_age == Some(0),
                age_s: b
                    .scan_age
                    .map_or(f64::INFINITY, |a| f64::from(a) * self.period_s),
                quality: None,
                error: b.error,
            })
        };
        let detector = match out.mode {
            ActiveMode::EdgeFollowing => status(&out.edge),
            ActiveMode::FurrowPursuing => status(&out.furrow),
            _ => status(&out.furrow).or_else(|| status(&out.edge)),
        };
        let estimated_error = match out.source {
            Some(fieldguide::guidance::Source::PathTracking) => {
                out.path.frenet.map(fieldguide::TrackingError::from)
            }
            Some(fieldguide::guidance::Source::EdgeFollowing) => out.edge.error,
            Some(fieldguide::guidance::Source::FurrowPursuing) => out.furrow.error,
            None => None,
        };
        let sideslip_used = if out.source == Some(fieldguide::guidance::Source::PathTracking) {
            out.path.sideslip_used
        } else {
            Sideslip::ZERO
        };
        // A tick without a source outside Stop (GD-COMMAND): the vehicle
        // keeps the previous command.
        let (steering, speed, saturated) = match (out.command, self.held) {
            (Some(c), _) => (c.steering.get(), c.speed, c.saturated),
            (None, Some(held)) => held,
            (None, None) => (0.0, fieldguide::MetersPerSecond::ZERO, false),
        };
        self.held = Some((steering, speed, saturated));
        Ok(Command {
            steering,
            speed,
            mode,
            switching_mode,
            saturated,
            estimated_error,
            sideslip_used,
            detector,
        })
    }
}
