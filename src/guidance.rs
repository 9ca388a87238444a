//! The per-tick pipeline a vehicle stack calls: sensors in, command out
//! (DESIGN.md, "One tick"; `spec/guidance.md`, GD-*).
//!
//! Once per control period, [`Guidance::step`] takes a [`TickInput`] (the
//! scans that arrived in this tick, the GNSS pose if localisation has one,
//! the odometry pose and the sideslip estimate) and, in this order
//! (GD-ORDER):
//!
//! 1. runs the edge detector on the horizontal scan and the furrow detector
//!    on the inclined one; on ticks without a scan, carries the latest
//!    detection to the current pose through odometry, for at most the maximal
//!    scan age (GD-SCAN-AGE, GD-ODOMETRY);
//! 2. projects the GNSS pose on the reference path near the last abscissa
//!    (GD-LOCALISATION);
//! 3. checks each detected line against the path (GD-PLAN);
//! 4. runs the backstepping law of every source with a valid estimate: path
//!    tracking with the sideslip estimate and the curvature c(s + vT), the
//!    specialised behaviours on a straight line without sideslip
//!    (GD-PREDICTION); a behaviour whose law refuses its error reports Exit
//!    (GD-COMMAND);
//! 5. steps the switching machine with two specialised behaviours in the
//!    configured priority order (GD-BEHAVIOURS);
//! 6. returns the command of the source the machine selects, at that
//!    source's desired speed (GD-SPEED), a stop command in Stop (GD-STOP), or
//!    no command when no source may command in this tick.
//!
//! The [`TickOutput`] carries everything a log or a simulator needs: the
//! command, the mode and the source, each detector's verdict and error, the
//! path's Frénet error and each law's result. Nothing allocates and no clock
//! is read (GD-NO-ALLOC); `step` refuses only malformed input (GD-INPUT).
//!
//! ```
//! use fieldguide::guidance::{ActiveMode, Guidance, GuidanceConfig, GuidanceParams, TickInput};
//! use fieldguide::geometry::path::{PathConfig, ReferencePath};
//! use fieldguide::model::bicycle::Sideslip;
//! use fieldguide::{Odom, Point2, Pose2, World};
//!
//! # fn main() -> Result<(), fieldguide::Precondition> {
//! let waypoints = [Point2::<World>::new(0.0, 0.0)?, Point2::new(50.0, 0.0)?];
//! let path = ReferencePath::<16>::from_waypoints(&waypoints, PathConfig::default())?;
//! let config = GuidanceConfig::new(&GuidanceParams::pierre2022_furrow()?)?;
//! let mut guidance = Guidance::<16>::new(config, &path)?;
//! let tick = guidance.step(&TickInput {
//!     horizontal: None,
//!     inclined: None, // no scan in this tick
//!     gnss: Some(Pose2::new(1.0, 0.3, 0.0)?),
//!     odometry: Pose2::<Odom>::new(1.0, 0.3, 0.0)?,
//!     sideslip: Sideslip::ZERO,
//! })?;
//! assert_eq!(tick.mode, ActiveMode::PathTracking);
//! let command = tick.command.ok_or(fieldguide::Precondition::new("GD-COMMAND", "none"))?;
//! assert!((command.speed.get() - 0.8).abs() < 1e-12); // Table 2: path tracking at 0.8 m/s
//! assert!(command.steering.get() < 0.0);               // 0.3 m left of the path: steer right
//! # Ok(())
//! # }
//! ```

mod config;
pub mod odometry;

pub use config::{
    Behaviour, EdgeFollowingParams, FurrowPursuingParams, GuidanceConfig, GuidanceParams,
    PathTrackingParams, PlanCheck, Priority,
};

use crate::control::backstepping::{steering_command, BacksteppingConfig, SteeringCommand};
use crate::error::Precondition;
use crate::geometry::frame::{Odom, Pose2, World};
use crate::geometry::path::{FrenetError, ReferencePath};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, MetersPerSecond, Radians};
use crate::model::bicycle::Sideslip;
use crate::perception::edge::{EdgeDetector, EdgeOutcome};
use crate::perception::furrow::{FurrowDetection, FurrowDetector};
use crate::perception::{Scan, Verdict};
use crate::supervisor::switching::{
    line_relative_to_path, CommandSource, Input, LineRelativeToPath, Mode, Output, PathAhead,
    PlanTolerance, Report, Switching,
};

/// What the sensors and estimators give in one tick.
#[derive(Debug, Clone, Copy)]
pub struct TickInput<'a> {
    /// The horizontal LiDAR's scan, in the ticks where one arrived; only with
    /// edge following configured (GD-INPUT).
    pub horizontal: Option<Scan<'a>>,
    /// The inclined LiDAR's scan, in the ticks where one arrived; only with
    /// furrow pursuing configured (GD-INPUT).
    pub inclined: Option<Scan<'a>>,
    /// The robot's pose from GNSS-RTK localisation, `World` frame; `None`
    /// when localisation has no valid pose (GD-LOCALISATION).
    pub gnss: Option<Pose2<World>>,
    /// The robot's pose from wheel odometry, `Odom` frame, every tick.
    pub odometry: Pose2<Odom>,
    /// The observer's sideslip estimate, |β| < π/2 (GD-INPUT); used only by
    /// path tracking with compensation on (GD-PREDICTION).
    pub sideslip: Sideslip,
}

/// What the vehicle is asked to do in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command {
    /// Desired forward speed, m/s: the source's (GD-SPEED), 0 in Stop (GD-STOP).
    pub speed: MetersPerSecond,
    /// Steering angle δ, rad, positive to the left, within the law's saturation.
    pub steering: Radians,
    /// Whether the law's output was clamped to the saturation.
    pub saturated: bool,
}

/// The mode after a tick, by name (the switching machine's mode with its
/// behaviour indices resolved through the priority order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActiveMode {
    /// Path tracking on the planned path.
    PathTracking,
    /// Edge following.
    EdgeFollowing,
    /// Furrow pursuing.
    FurrowPursuing,
    /// Standstill (SW-STOP, GD-STOP).
    Stop,
}

impl ActiveMode {
    /// A label for logs and traces.
    #[must_use]
    pub const fn label(self) -> &'static str {
        match self {
            Self::PathTracking => "path_tracking",
            Self::EdgeFollowing => "edge_following",
            Self::FurrowPursuing => "furrow_pursuing",
            Self::Stop => "stop",
        }
    }
}

/// The source of a tick's command, by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Source {
    /// Path tracking, with valid localisation.
    PathTracking,
    /// Edge following, with a valid estimate.
    EdgeFollowing,
    /// Furrow pursuing, with a valid estimate.
    FurrowPursuing,
}

impl Behaviour {
    /// The mode of this behaviour.
    #[must_use]
    pub const fn mode(self) -> ActiveMode {
        match self {
            Self::EdgeFollowing => ActiveMode::EdgeFollowing,
            Self::FurrowPursuing => ActiveMode::FurrowPursuing,
        }
    }

    /// This behaviour as a command source.
    #[must_use]
    pub const fn source(self) -> Source {
        match self {
            Self::EdgeFollowing => Source::EdgeFollowing,
            Self::FurrowPursuing => Source::FurrowPursuing,
        }
    }
}

/// What a control law made of its error in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LawOutcome {
    /// The law was not run: no valid estimate (or no projection).
    NotRun,
    /// The law's command (saturated).
    Steer(SteeringCommand),
    /// The law refused the error (PT-HEADING, PT-DENOM, ...): the source
    /// could not command in this tick (GD-COMMAND, GD-LOCALISATION).
    Refused(Precondition),
}

impl LawOutcome {
    /// The law's command, when it gave one.
    #[must_use]
    pub const fn command(&self) -> Option<&SteeringCommand> {
        match self {
            Self::Steer(command) => Some(command),
            Self::NotRun | Self::Refused(_) => None,
        }
    }

    fn run(
        law: &BacksteppingConfig,
        error: &TrackingError,
        sideslip: Sideslip,
        speed: MetersPerSecond,
    ) -> Self {
        match steering_command(law, error, sideslip, speed) {
            Ok(command) => Self::Steer(command),
            Err(e) => Self::Refused(e),
        }
    }
}

/// Path tracking in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathStatus {
    /// The Frénet error of the GNSS pose (with c(s + vT)); `None` without a
    /// pose or when the projection was refused.
    pub frenet: Option<FrenetError>,
    /// Why the projection was refused, if it was (overflow).
    pub projection_refused: Option<Precondition>,
    /// The path-tracking law's result.
    pub law: LawOutcome,
    /// Whether localisation is valid for path tracking (GD-LOCALISATION).
    pub localisation_valid: bool,
    /// The sideslip the law used: the estimate with compensation on, else zero.
    pub sideslip_used: Sideslip,
}

/// A specialised behaviour in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BehaviourStatus {
    /// Whether the behaviour is configured (an unconfigured one is Absent).
    pub configured: bool,
    /// The verdict of the held detection: the latest scan's, or Absent
    /// without one, when too old, refused or unconfigured (GD-SCAN-AGE).
    pub detected: Verdict,
    /// The verdict the switching machine got: `detected`, or Exit when the
    /// law refused a valid estimate (GD-COMMAND).
    pub reported: Verdict,
    /// The tracking error to the behaviour's line at the current pose;
    /// `None` exactly when `detected` is Absent.
    pub error: Option<TrackingError>,
    /// Ticks since the scan of the held detection (0: this tick's scan).
    pub scan_age: Option<u16>,
    /// Why this tick's scan was refused by the detector, if it was.
    pub scan_refused: Option<Precondition>,
    /// The line relative to the planned path, when both errors exist.
    pub plan: Option<LineRelativeToPath>,
    /// The plan-consistency flag given to the machine (GD-PLAN).
    pub plan_consistent: bool,
    /// The behaviour's law on its error, run only for a valid estimate.
    pub law: LawOutcome,
}

impl BehaviourStatus {
    const UNCONFIGURED: Self = Self {
        configured: false,
        detected: Verdict::Absent,
        reported: Verdict::Absent,
        error: None,
        scan_age: None,
        scan_refused: None,
        plan: None,
        plan_consistent: true,
        law: LawOutcome::NotRun,
    };
}

/// Everything one tick produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickOutput {
    /// The command to apply: the selected source's (GD-COMMAND), a stop in
    /// Stop (GD-STOP), `None` when no source may command in this tick.
    pub command: Option<Command>,
    /// The mode after this tick.
    pub mode: ActiveMode,
    /// The source of `command`; `None` in Stop and without a command.
    pub source: Option<Source>,
    /// The switching machine's own output (behaviour indices in priority order).
    pub switching: Output,
    /// Path tracking: projection, law, localisation.
    pub path: PathStatus,
    /// Edge following: detection, plan, law.
    pub edge: BehaviourStatus,
    /// Furrow pursuing: detection, plan, law.
    pub furrow: BehaviourStatus,
}

/// The latest edge detection and where the robot was when its scan was taken.
#[derive(Debug, Clone, Copy)]
struct HeldEdge {
    outcome: EdgeOutcome,
    odom: Pose2<Odom>,
    age: u16,
}

/// The latest furrow detection and where the robot was when its scan was taken.
#[derive(Debug, Clone, Copy)]
struct HeldFurrow {
    detection: FurrowDetection,
    odom: Pose2<Odom>,
    age: u16,
}

/// A behaviour's estimate in the current tick, before plan and law.
#[derive(Debug, Clone, Copy)]
struct Estimate {
    verdict: Verdict,
    error: Option<TrackingError>,
    age: Option<u16>,
    refused: Option<Precondition>,
}

impl Estimate {
    const NONE: Self = Self {
        verdict: Verdict::Absent,
        error: None,
        age: None,
        refused: None,
    };

    /// A held detection's verdict and its error moved to the current pose
    /// (`moved`), Absent when it is too old or cannot be moved.
    fn held(
        verdict: Verdict,
        age: u16,
        max_age: u16,
        fresh: Option<TrackingError>,
        moved: impl FnOnce() -> Result<TrackingError, Precondition>,
    ) -> Self {
        if age > max_age || verdict == Verdict::Absent {
            return Self {
                age: Some(age),
                ..Self::NONE
            };
        }
        let error = if age == 0 { fresh } else { moved().ok() };
        match error {
            Some(error) => Self {
                verdict,
                error: Some(error),
                age: Some(age),
                refused: None,
            },
            // Moving overflowed (or a detector gave no error): no estimate.
            None => Self {
                age: Some(age),
                ..Self::NONE
            },
        }
    }
}

/// The per-tick guidance pipeline (`spec/guidance.md`).
///
/// `PATH` is the capacity of the borrowed reference path; `EDGE_POINTS` and
/// `EDGE_CHAIN` bound the edge detector's valid scan points and chain points;
/// `FURROW_RAYS` bounds the rays in the furrow detector's angular window and
/// `FURROW_SCANS` its kept selections (at least `averaged_scans`).
#[derive(Debug, Clone)]
pub struct Guidance<
    'p,
    const PATH: usize,
    const EDGE_POINTS: usize = 512,
    const EDGE_CHAIN: usize = 64,
    const FURROW_RAYS: usize = 512,
    const FURROW_SCANS: usize = 32,
> {
    config: GuidanceConfig,
    path: &'p ReferencePath<PATH>,
    machine: Switching<2>,
    edge: Option<EdgeDetector<EDGE_POINTS, EDGE_CHAIN>>,
    furrow: Option<FurrowDetector<FURROW_RAYS, FURROW_SCANS>>,
    held_edge: Option<HeldEdge>,
    held_furrow: Option<HeldFurrow>,
    /// Abscissa of the last successful projection.
    s_hint: Option<Meters>,
    /// Odometry distance travelled since that projection, m.
    since_projection: f64,
    last_odometry: Option<Pose2<Odom>>,
    /// Steering of the last command made, held in Stop (GD-STOP).
    last_steering: Radians,
}

impl<
        'p,
        const PATH: usize,
        const EDGE_POINTS: usize,
        const EDGE_CHAIN: usize,
        const FURROW_RAYS: usize,
        const FURROW_SCANS: usize,
    > Guidance<'p, PATH, EDGE_POINTS, EDGE_CHAIN, FURROW_RAYS, FURROW_SCANS>
{
    /// A pipeline on `path` in its initial state: path tracking, no
    /// detection held, no projection yet.
    ///
    /// # Errors
    /// `FUR-ACCUMULATE` when furrow pursuing keeps more scans than
    /// `FURROW_SCANS`.
    pub fn new(
        config: GuidanceConfig,
        path: &'p ReferencePath<PATH>,
    ) -> Result<Self, Precondition> {
        let params = config.params();
        let edge = params
            .edge
            .as_ref()
            .map(|e| EdgeDetector::new(e.detector, e.mount));
        let furrow = match &params.furrow {
            Some(f) => Some(FurrowDetector::new(f.detector)?),
            None => None,
        };
        Ok(Self {
            machine: Switching::new(*config.switching()),
            config,
            path,
            edge,
            furrow,
            held_edge: None,
            held_furrow: None,
            s_hint: None,
            since_projection: 0.0,
            last_odometry: None,
            last_steering: Radians::ZERO,
        })
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &GuidanceConfig {
        &self.config
    }

    /// The reference path.
    #[must_use]
    pub const fn path(&self) -> &'p ReferencePath<PATH> {
        self.path
    }

    /// The switching machine (its mode and counters).
    #[must_use]
    pub const fn switching(&self) -> &Switching<2> {
        &self.machine
    }

    /// The current mode.
    #[must_use]
    pub fn mode(&self) -> ActiveMode {
        self.active_mode(self.machine.mode())
    }

    /// The edge detector (its last points and chain), when configured.
    #[must_use]
    pub const fn edge_detector(&self) -> Option<&EdgeDetector<EDGE_POINTS, EDGE_CHAIN>> {
        self.edge.as_ref()
    }

    /// The furrow detector (its accumulated selections), when configured.
    #[must_use]
    pub const fn furrow_detector(&self) -> Option<&FurrowDetector<FURROW_RAYS, FURROW_SCANS>> {
        self.furrow.as_ref()
    }

    /// The latest edge detection held (its scan's outcome), if any.
    #[must_use]
    pub fn last_edge(&self) -> Option<&EdgeOutcome> {
        self.held_edge.as_ref().map(|h| &h.outcome)
    }

    /// The latest furrow detection held (its scan's detection), if any.
    #[must_use]
    pub fn last_furrow(&self) -> Option<&FurrowDetection> {
        self.held_furrow.as_ref().map(|h| &h.detection)
    }

    fn active_mode(&self, mode: Mode) -> ActiveMode {
        match mode {
            Mode::PathTracking => ActiveMode::PathTracking,
            Mode::Stop => ActiveMode::Stop,
            // Index 2 and beyond cannot occur with K = 2; Stop is the safe reading.
            Mode::Behaviour(i) => self
                .config
                .params()
                .priority
                .order()
                .get(i)
                .map_or(ActiveMode::Stop, |b| b.mode()),
        }
    }

    /// One control tick (`spec/guidance.md`; the module documentation lists
    /// the steps).
    ///
    /// # Errors
    /// Only for malformed input, before any state changes (GD-INPUT):
    /// `PT-SIDESLIP` when |β| ≥ π/2, `GD-INPUT` when a scan is given for a
    /// behaviour that is not configured. Scans with any values, refused
    /// scans and laws that refuse their errors all give an output.
    //= spec/guidance.md#gd-order-pipeline-order
    //# Each call of `step` MUST process one control tick in this order: the
    //# detections of the tick's scans (or the ageing of the held ones), the Frénet
    //# projection of the GNSS pose, the plan consistency of each detected line, the
    //# control law of each source whose estimate is valid, one step of the switching
    //# machine, and the command of the source the machine selects.
    //= spec/guidance.md#gd-no-alloc-no-allocation-no-clock
    //# A tick MUST NOT allocate on the heap and MUST NOT read a clock: the
    //# pipeline's buffers are fixed by its const parameters and time is counted in
    //# ticks.
    pub fn step(&mut self, input: &TickInput<'_>) -> Result<TickOutput, Precondition> {
        self.check_input(input)?;
        let travelled = self
            .last_odometry
            .map_or(0.0, |p| p.position.distance_to(input.odometry.position));
        self.last_odometry = Some(input.odometry);

        // 1. Detections, or the held ones aged and moved (GD-SCAN-AGE).
        let edge = self.edge_estimate(input);
        let furrow = self.furrow_estimate(input);

        // 2. The path (GD-LOCALISATION).
        let (frenet, projection_refused) = self.project(input.gnss.as_ref(), travelled);

        // 3-4. Plan consistency and the laws.
        let params = *self.config.params();
        let path_error = frenet.map(|f| f.tracking_error());
        let sideslip_used = if params.path.sideslip_compensation {
            input.sideslip
        } else {
            Sideslip::ZERO
        };
        let path_law = match &path_error {
            //= spec/guidance.md#gd-prediction-sideslip-and-prediction-only-in-path-tracking
            //# Path tracking MUST use the sideslip estimate, when compensation is
            //# configured, and the curvature c(s + vT) with v its desired speed and T the
            //# prediction horizon; edge following and furrow pursuing MUST use zero sideslip
            //# and a straight line, c = c(s + vT) = 0.
            Some(error) => {
                LawOutcome::run(&params.path.law, error, sideslip_used, params.path.speed)
            }
            None => LawOutcome::NotRun,
        };
        //= spec/guidance.md#gd-localisation-localisation-for-path-tracking
        //# Localisation MUST be valid in a tick exactly when a GNSS pose is given, its
        //# projection on the path succeeds and the path-tracking law gives a command
        //# from it.
        let localisation_valid = path_law.command().is_some();
        let path = PathStatus {
            frenet,
            projection_refused,
            law: path_law,
            localisation_valid,
            sideslip_used,
        };
        let plan = self.plan_reference(frenet.as_ref());
        let edge = match &params.edge {
            Some(e) => behaviour_status(&edge, plan.as_ref(), &e.law, e.speed),
            None => BehaviourStatus::UNCONFIGURED,
        };
        let furrow = match &params.furrow {
            Some(f) => behaviour_status(&furrow, plan.as_ref(), &f.law, f.speed),
            None => BehaviourStatus::UNCONFIGURED,
        };

        // 5. The switching machine (GD-BEHAVIOURS).
        let order = params.priority.order();
        let status_of = |b: Behaviour| match b {
            Behaviour::EdgeFollowing => &edge,
            Behaviour::FurrowPursuing => &furrow,
        };
        let report = |b: Behaviour| Report {
            verdict: status_of(b).reported,
            plan_consistent: status_of(b).plan_consistent,
        };
        let [first, second] = order;
        //= spec/guidance.md#gd-behaviours-two-behaviours-in-a-priority-order
        //# The pipeline MUST run a switching machine with exactly two specialised
        //# behaviours, edge following and furrow pursuing, in the configured priority
        //# order, and a behaviour that is not configured MUST report Absent in every
        //# tick.
        let switching = self.machine.step(&Input {
            behaviours: [report(first), report(second)],
            localisation_valid,
        });

        // 6. The command of the selected source.
        let drive = |law: &LawOutcome, speed: MetersPerSecond| {
            law.command().map(|c| Command {
                speed,
                steering: c.steering,
                saturated: c.saturated,
            })
        };
        //= spec/guidance.md#gd-command-the-command-of-the-selected-source
        //# The command MUST be the saturated output of the selected source's control law
        //# on that source's error of the tick, and no other; when the machine selects no
        //# source outside Stop, there MUST be no command.
        //= spec/guidance.md#gd-speed-desired-speed-per-mode
        //# The speed of a command MUST be the desired speed of its source: path
        //# tracking, edge following or furrow pursuing (Tables 1 and 2: 0.8, 0.4 and
        //# 0.7 m/s).
        let (command, source) = match switching.source {
            CommandSource::PathTracking => (
                drive(&path.law, params.path.speed),
                Some(Source::PathTracking),
            ),
            CommandSource::Behaviour(i) => match order.get(i) {
                Some(&b) => {
                    let speed = match b {
                        Behaviour::EdgeFollowing => params.edge.map(|e| e.speed),
                        Behaviour::FurrowPursuing => params.furrow.map(|f| f.speed),
                    };
                    let command = speed.and_then(|v| drive(&status_of(b).law, v));
                    (command, Some(b.source()))
                }
                None => (None, None),
            },
            CommandSource::None => (None, None),
        };
        // A selected source always has a command (its law ran and gave one:
        // GD-COMMAND); should it not, nothing is commanded and no source named.
        let source = command.and(source);
        let mode = self.active_mode(switching.mode);
        let command = match command {
            Some(c) => {
                self.last_steering = c.steering;
                Some(c)
            }
            //= spec/guidance.md#gd-stop-the-stop-command
            //# In Stop the command MUST be a speed of 0 m/s with the steering of the last
            //# command made, or 0 rad before any command, never saturated.
            None if mode == ActiveMode::Stop => Some(Command {
                speed: MetersPerSecond::ZERO,
                steering: self.last_steering,
                saturated: false,
            }),
            None => None,
        };
        Ok(TickOutput {
            command,
            mode,
            source,
            switching,
            path,
            edge,
            furrow,
        })
    }

    /// GD-INPUT: refuse malformed input before anything changes.
    //= spec/guidance.md#gd-input-malformed-input
    //# A tick whose input is malformed MUST be refused with an error before any
    //# state changes: a sideslip estimate outside |β| < π/2 (`PT-SIDESLIP`), or a
    //# scan for a behaviour that is not configured (`GD-INPUT`).
    fn check_input(&self, input: &TickInput<'_>) -> Result<(), Precondition> {
        input.sideslip.check()?;
        if input.horizontal.is_some() && self.edge.is_none() {
            return Err(Precondition::new(
                "GD-INPUT",
                "horizontal scan given but edge following is not configured",
            ));
        }
        if input.inclined.is_some() && self.furrow.is_none() {
            return Err(Precondition::new(
                "GD-INPUT",
                "inclined scan given but furrow pursuing is not configured",
            ));
        }
        Ok(())
    }

    /// Edge following's estimate in this tick (GD-SCAN-AGE, GD-ODOMETRY).
    //= spec/guidance.md#gd-input-malformed-input
    //# Sensor data MUST NOT be malformed input: any range, NaN and infinities
    //# included, and any scan a detector refuses MUST give a tick output, the
    //# refused scan counting as no estimate.
    fn edge_estimate(&mut self, input: &TickInput<'_>) -> Estimate {
        let (Some(detector), Some(params)) = (self.edge.as_mut(), self.config.params().edge) else {
            return Estimate::NONE;
        };
        if let Some(scan) = &input.horizontal {
            match detector.detect(scan, params.side) {
                Ok(outcome) => {
                    self.held_edge = Some(HeldEdge {
                        outcome,
                        odom: input.odometry,
                        age: 0,
                    });
                }
                Err(e) => {
                    self.held_edge = None;
                    return Estimate {
                        refused: Some(e),
                        ..Estimate::NONE
                    };
                }
            }
        } else if let Some(held) = self.held_edge.as_mut() {
            held.age = held.age.saturating_add(1);
        }
        let Some(held) = self.held_edge else {
            return Estimate::NONE;
        };
        Estimate::held(
            held.outcome.verdict,
            held.age,
            self.config.max_scan_age_ticks(),
            held.outcome.fit.map(|f| f.error),
            || {
                let fit = held
                    .outcome
                    .fit
                    .ok_or(Precondition::new("GD-SCAN-AGE", "no fit to move"))?;
                let pose = odometry::pose_in_scan_frame(&held.odom, &input.odometry)?;
                odometry::moved_edge_error(&fit, params.side, params.detector.offset(), &pose)
            },
        )
    }

    /// Furrow pursuing's estimate in this tick (GD-SCAN-AGE, GD-ODOMETRY).
    //= spec/guidance.md#gd-scan-age-held-detections
    //# In a tick without a new scan, a behaviour MUST report the verdict of its
    //# latest scan, with the tracking error to that scan's line moved to the current
    //# pose through odometry, as long as that scan is at most the maximal scan age
    //# old; an older scan, a scan the detector refused, or no scan at all MUST give
    //# Absent.
    fn furrow_estimate(&mut self, input: &TickInput<'_>) -> Estimate {
        let Some(detector) = self.furrow.as_mut() else {
            return Estimate::NONE;
        };
        if let Some(scan) = &input.inclined {
            match detector.step(scan, &input.odometry) {
                Ok(detection) => {
                    self.held_furrow = Some(HeldFurrow {
                        detection,
                        odom: input.odometry,
                        age: 0,
                    });
                }
                Err(e) => {
                    self.held_furrow = None;
                    return Estimate {
                        refused: Some(e),
                        ..Estimate::NONE
                    };
                }
            }
        } else if let Some(held) = self.held_furrow.as_mut() {
            held.age = held.age.saturating_add(1);
        }
        let Some(held) = self.held_furrow else {
            return Estimate::NONE;
        };
        Estimate::held(
            held.detection.verdict,
            held.age,
            self.config.max_scan_age_ticks(),
            held.detection.error,
            || {
                let lines = held
                    .detection
                    .lines
                    .ok_or(Precondition::new("GD-SCAN-AGE", "no lines to move"))?;
                let pose = odometry::pose_in_scan_frame(&held.odom, &input.odometry)?;
                odometry::moved_rows_error(&lines, &pose)
            },
        )
    }

    /// The path's error of the tick and, with plan consistency configured, the
    /// path at its look-ahead (GD-PLAN); `None` without a projection.
    //= spec/guidance.md#gd-plan-plan-consistency-of-the-detected-lines
    //# The path ahead MUST be taken at the tolerance's look-ahead from the
    //# projection's abscissa.
    fn plan_reference(&self, frenet: Option<&FrenetError>) -> Option<PlanReference> {
        let frenet = frenet?;
        let path = frenet.tracking_error();
        let check = self.config.params().plan.map(|p| {
            let tolerance = p.tolerance;
            let ahead = if tolerance.lookahead().get() > 0.0 {
                PathAhead::on_path(self.path, frenet.s, tolerance.lookahead()).ok()
            } else {
                Some(PathAhead::HERE)
            };
            (tolerance, ahead)
        });
        Some(PlanReference { path, check })
    }

    /// The Frénet error of the GNSS pose, searched near the last abscissa
    /// (GD-LOCALISATION), and why it was refused if it was.
    //= spec/guidance.md#gd-localisation-localisation-for-path-tracking
    //# The projection MUST search the path locally, within the search window plus
    //# the odometry distance travelled since the last successful projection, around
    //# that projection's abscissa, and globally only before the first one.
    fn project(
        &mut self,
        gnss: Option<&Pose2<World>>,
        travelled: f64,
    ) -> (Option<FrenetError>, Option<Precondition>) {
        self.since_projection += travelled;
        let Some(pose) = gnss else {
            return (None, None);
        };
        let lookahead = self.config.lookahead();
        let base = self.config.params().path.search_window.get();
        // A window that overflows (absurd odometry) searches the whole path.
        let window = Meters::new(base + self.since_projection).ok();
        let projection = match (self.s_hint, window) {
            (Some(hint), Some(window)) => self.path.project_near(pose, lookahead, hint, window),
            _ => self.path.project(pose, lookahead),
        };
        match projection {
            Ok(frenet) => {
                self.s_hint = Some(frenet.s);
                self.since_projection = 0.0;
                (Some(frenet), None)
            }
            Err(e) => (None, Some(e)),
        }
    }
}

/// What a tick's lines are compared with: the path's error and, when plan
/// consistency is configured, its tolerance and the path at its look-ahead
/// (`None` when that overflowed).
struct PlanReference {
    path: TrackingError,
    check: Option<(PlanTolerance, Option<PathAhead>)>,
}

/// Plan consistency and the law of one configured behaviour (GD-PLAN,
/// GD-PREDICTION, GD-COMMAND).
fn behaviour_status(
    estimate: &Estimate,
    plan_reference: Option<&PlanReference>,
    law: &BacksteppingConfig,
    speed: MetersPerSecond,
) -> BehaviourStatus {
    let plan = match (&estimate.error, plan_reference) {
        (Some(line), Some(r)) => line_relative_to_path(line, &r.path).ok(),
        _ => None,
    };
    //= spec/guidance.md#gd-plan-plan-consistency-of-the-detected-lines
    //# A behaviour's line MUST be reported consistent with the plan when plan
    //# consistency is not configured or when the path has no projection in the tick;
    //# otherwise it MUST be reported as `PlanTolerance::is_consistent` judges its
    //# tracking error against the path's.
    let plan_consistent = match (&estimate.error, plan_reference) {
        (Some(line), Some(r)) => match &r.check {
            Some((tolerance, Some(ahead))) => tolerance.is_consistent(line, &r.path, ahead),
            Some((_, None)) => false,
            None => true,
        },
        _ => true,
    };
    let law = match &estimate.error {
        // Straight line, no sideslip, no prediction (GD-PREDICTION).
        Some(e) if estimate.verdict.estimate_is_valid() => LawOutcome::run(
            law,
            &TrackingError::to_straight_line(e.y, e.angular_deviation),
            Sideslip::ZERO,
            speed,
        ),
        _ => LawOutcome::NotRun,
    };
    //= spec/guidance.md#gd-command-the-command-of-the-selected-source
    //# A behaviour whose law refuses its error MUST be reported to the switching
    //# machine as Exit in that tick, so that a command source is always a source
    //# whose law gave a command.
    let reported = match law {
        LawOutcome::Refused(_) => Verdict::Exit,
        LawOutcome::NotRun | LawOutcome::Steer(_) => estimate.verdict,
    };
    BehaviourStatus {
        configured: true,
        detected: estimate.verdict,
        reported,
        error: estimate.error,
        scan_age: estimate.age,
        scan_refused: estimate.refused,
        plan,
        plan_consistent,
        law,
    }
}
