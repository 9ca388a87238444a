//! The robot's side of a tick: from sensor readings to a command.
//!
//! The runner calls a [`Guidance`] once per control period and knows nothing of
//! the law inside, so later behaviours (edge following, furrow pursuing, a mode
//! selector fed by LiDAR detectors) plug in as new implementations and new
//! [`Mode`] labels without touching the runner.

pub mod pipeline;

use fieldguide::control::backstepping::{steering_command, BacksteppingConfig};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::Scan as HorizontalScan;
use fieldguide::{Meters, MetersPerSecond, Precondition, TrackingError, Verdict};

use crate::lidar::inclined::InclinedScan;
use crate::scenario::setup::Reference;
use crate::sensors::Readings;

/// The behaviour that produced a tick's command (the colour of the plots and
/// the keys of `mode_distance_m`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Mode {
    /// Tracking the recorded reference path (Pierre 2022, section 2.1).
    PathTracking,
    /// Following crop rows seen by the inclined LiDAR (Pierre 2022, section 2.3).
    FurrowPursuing,
    /// Following a hedge or a wall seen by the horizontal LiDAR (Pierre 2022, section 2.2).
    EdgeFollowing,
    /// Standstill: no valid command source for the Stop delay (SW-STOP, GD-STOP).
    Stop,
}

impl Mode {
    /// The label used in CSV traces and JSON summaries.
    #[must_use]
    pub const fn label(self) -> &'static str {
        match self {
            Self::PathTracking => "path_tracking",
            Self::FurrowPursuing => "furrow_pursuing",
            Self::EdgeFollowing => "edge_following",
            Self::Stop => "stop",
        }
    }

    /// Plot colour (Pierre 2022, Figs. 8 and 10: path tracking in red, the
    /// specialised behaviour in blue; edge following a lighter blue, so the
    /// two specialised behaviours stay apart in one legend).
    #[must_use]
    pub const fn colour(self) -> &'static str {
        match self {
            Self::PathTracking => "#d62728",
            Self::FurrowPursuing => "#1f3fd0",
            Self::EdgeFollowing => "#1f8fd0",
            Self::Stop => "#222222",
        }
    }
}

/// What the guidance sees at one tick.
#[derive(Debug, Clone, Copy)]
pub struct TickInput<'a> {
    /// Time since the start, seconds.
    pub time_s: f64,
    /// The sensors' readings (never the ground truth).
    pub readings: &'a Readings,
    /// The inclined LiDAR's scan, on the ticks it scans (`None` in between
    /// and without a LiDAR).
    pub scan: Option<&'a InclinedScan>,
    /// The horizontal LiDAR's scan as the core's edge detector reads it, on
    /// the ticks it scans (`None` in between and without a horizontal LiDAR).
    pub horizontal: Option<HorizontalScan<'a>>,
}

/// What the guidance sends to the vehicle at one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command {
    /// Steering angle δ, radians, positive to the left, within the saturation.
    pub steering: f64,
    /// Forward speed, m/s.
    pub speed: MetersPerSecond,
    /// The behaviour whose law made the command (the plots' colour), or
    /// Stop.
    pub mode: Mode,
    /// The switching machine's mode (differs from `mode` while an exit delay
    /// runs without a valid estimate: path tracking steers, SW-COMMAND).
    pub switching_mode: Mode,
    /// Whether the law saturated the steering.
    pub saturated: bool,
    /// The tracking error the law used (from the estimated pose).
    pub estimated_error: Option<TrackingError>,
    /// The sideslip the law used (zero without compensation).
    pub sideslip_used: Sideslip,
    /// What a row detector reported, when the guidance has one.
    pub detector: Option<DetectorStatus>,
}

/// A detector's state at one tick, recorded with the command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetectorStatus {
    /// The verdict of the latest scan (FUR-QUALITY, EDGE-QUALITY).
    pub verdict: Verdict,
    /// Whether that scan arrived at this tick.
    pub scanned: bool,
    /// Time since that scan, seconds.
    pub age_s: f64,
    /// That scan's quality measure, if it has one: the weaker correlation of
    /// the selection (furrow), the residual standard deviation of the chain's
    /// parabola in metres (edge).
    pub quality: Option<f64>,
    /// The detector's own tracking error from that scan, if it fitted a line
    /// (reported whatever the verdict; only Enter and Hold may be used).
    pub error: Option<TrackingError>,
}

/// A per-tick guidance: readings in, command out. State lives in the implementor.
pub trait Guidance {
    /// The command for this tick. An error is a violated precondition of the
    /// core (for example 1 − y c(s) ≤ 0 far off a curve); the runner ends the
    /// run and reports it.
    fn step(&mut self, input: &TickInput<'_>) -> Result<Command, Precondition>;
}

/// Backstepping path tracking (Pierre 2022, eqs. 2-7) on the estimated pose.
#[derive(Debug, Clone)]
pub struct PathTracking<'p> {
    path: &'p Reference,
    config: BacksteppingConfig,
    speed: MetersPerSecond,
    lookahead: Meters,
    compensate: bool,
    /// Abscissa of the last projection, to search near it.
    s_hint: Option<Meters>,
}

/// Half-width of the abscissa window searched around the last projection,
/// metres: far more than a tick's travel, far less than a U-turn's length, so
/// the projection cannot jump to the other leg.
pub const SEARCH_WINDOW_M: f64 = 3.0;

impl<'p> PathTracking<'p> {
    /// Tracking of `path` at `speed` with the law `config`, curvature fed
    /// forward `lookahead` metres ahead (v T), using the observer's sideslip
    /// only when `compensate`.
    #[must_use]
    pub fn new(
        path: &'p Reference,
        config: BacksteppingConfig,
        speed: MetersPerSecond,
        lookahead: Meters,
        compensate: bool,
    ) -> Self {
        Self {
            path,
            config,
            speed,
            lookahead,
            compensate,
            s_hint: None,
        }
    }
}

impl Guidance for PathTracking<'_> {
    fn step(&mut self, input: &TickInput<'_>) -> Result<Command, Precondition> {
        let Some(pose) = &input.readings.gnss else {
            return Err(Precondition::new(
                "GD-LOCALISATION",
                "path tracking alone cannot steer without a GNSS pose",
            ));
        };
        let frenet = match self.s_hint {
            None => self.path.project(pose, self.lookahead)?,
            Some(hint) => {
                self.path
                    .project_near(pose, self.lookahead, hint, Meters::new(SEARCH_WINDOW_M)?)?
            }
        };
        self.s_hint = Some(frenet.s);
        let error = TrackingError::from(frenet);
        let sideslip = if self.compensate {
            input.readings.sideslip
        } else {
            Sideslip::ZERO
        };
        let cmd = steering_command(&self.config, &error, sideslip, self.speed)?;
        Ok(Command {
            steering: cmd.steering.get(),
            speed: self.speed,
            mode: Mode::PathTracking,
            switching_mode: Mode::PathTracking,
            saturated: cmd.saturated,
            estimated_error: Some(error),
            sideslip_used: sideslip,
            detector: None,
        })
    }
}
