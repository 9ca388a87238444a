//! The per-tick pipeline a vehicle stack calls: sensors in, command out
//! (`spec/guidance.md`, GD-*), for any set of detectors, laws and vehicle.
//!
//! The pipeline holds path tracking, always present, and a list of behaviour
//! slots ([`BehaviourParams`]): each a detector behind
//! [`crate::perception::Detector`], a law behind
//! [`crate::control::ControlLaw`], a desired speed, two transit delays and a
//! plan tolerance, identified by a [`BehaviourId`] and a label. Once per
//! control period, [`Guidance::step`] takes a [`TickInput`] (the scans that
//! arrived in this tick, each routed to its behaviour, the GNSS pose if
//! localisation has one, the odometry pose and the law's extra input, such as
//! a sideslip estimate) and, in this order (GD-ORDER), with the odometry
//! pose aided by the good fix's heading when an aid is configured
//! (GD-ODOMETRY-AID):
//!
//! 1. runs each behaviour's detector on its scan; on ticks without a scan,
//!    carries the latest detection to the current pose through odometry, for
//!    at most the maximal scan age (GD-SCAN-AGE, GD-ODOMETRY);
//! 2. projects the GNSS pose on the reference path near the last abscissa
//!    (GD-LOCALISATION);
//! 3. checks each detected line against the path (GD-PLAN);
//! 4. runs the law of every source with a valid estimate: path tracking with
//!    the extra input and the curvature c(s + vT), the behaviours on a
//!    straight line with the law's neutral input (GD-PREDICTION); a
//!    behaviour whose law refuses its error reports Exit (GD-COMMAND);
//! 5. steps the switching machine with the behaviours in priority order
//!    (GD-BEHAVIOURS);
//! 6. returns the command of the source the machine selects, at that
//!    source's desired speed (GD-SPEED), the stop of the last command in Stop
//!    (GD-STOP), or no command when no source may command in this tick.
//!
//! The [`TickOutput`] carries everything a log or a simulator needs: the
//! command, the mode and the source, each behaviour's verdict, quality and
//! error, the path's Frénet error and each law's result. Nothing allocates
//! and no clock is read (GD-NO-ALLOC); `step` refuses only malformed input
//! (GD-INPUT). The reference path is borrowed and may be replaced between
//! ticks ([`Guidance::set_path`], GD-PATH).
//!
//! ```
//! use fieldguide::guidance::{Guidance, GuidanceConfig, Mode, TickInput};
//! use fieldguide::geometry::path::{PathConfig, ReferencePath};
//! use fieldguide::model::bicycle::Sideslip;
//! use fieldguide::presets::{pierre2022_furrow, Pierre2022};
//! use fieldguide::{Odom, Point2, Pose2, World};
//!
//! # fn main() -> Result<(), fieldguide::Precondition> {
//! let waypoints = [Point2::<World>::new(0.0, 0.0)?, Point2::new(50.0, 0.0)?];
//! let path = ReferencePath::<16>::from_waypoints(&waypoints, PathConfig::default())?;
//! let config = GuidanceConfig::new(&pierre2022_furrow()?)?;
//! let mut guidance: Pierre2022<'_, 16> = Guidance::new(config, &path)?;
//! let tick = guidance.step(&TickInput {
//!     scans: &[], // no scan in this tick
//!     gnss: Some(Pose2::new(1.0, 0.3, 0.0)?),
//!     odometry: Pose2::<Odom>::new(1.0, 0.3, 0.0)?,
//!     extra: Sideslip::ZERO,
//! })?;
//! assert_eq!(tick.mode, Mode::PathTracking);
//! let command = tick.command.ok_or(fieldguide::Precondition::new("GD-COMMAND", "none"))?;
//! assert!((command.command.speed().get() - 0.8).abs() < 1e-12); // Table 2: 0.8 m/s
//! let steering = command.command.steering().map_or(0.0, |s| s.get());
//! assert!(steering < 0.0); // 0.3 m left of the path: steer right
//! # Ok(())
//! # }
//! ```

mod bridge;
mod config;
pub mod entry;
pub mod fix;
pub mod handover;
pub mod odometry;
mod resume;

pub use config::{
    BehaviourId, BehaviourParams, GuidanceConfig, GuidanceParams, PathTrackingParams,
    MAX_SCAN_AGE_TICKS,
};
pub use entry::{Entry, EntryParams};
pub use fix::{FixKind, FixQuality, FixRule, FixRuleParams, FixUse};
pub use handover::{Handover, HandoverParams};
pub use odometry::{AidedOdometry, OdometryAid, OdometryAidParams};

use heapless::Vec;

use crate::control::ControlLaw;
use crate::error::Precondition;
use crate::geometry::carry::pose_in_scan_frame;
use crate::geometry::frame::{Odom, Pose2, Robot, World};
use crate::geometry::path::{FrenetError, ReferencePath};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_angle, Meters, MetersPerSecond, Radians};
use crate::model::{Command, Saturated, Vehicle};
use crate::perception::{Detection, Detector, HeldLine, Scan, Verdict};
use crate::supervisor::switching::{
    line_relative_to_path, CommandSource, Input, LineRelativeToPath, Mode as MachineMode, Output,
    PathAhead, PlanTolerance, Report, Switching,
};

/// A scan, and the behaviour whose detector reads it.
#[derive(Debug, Clone, Copy)]
pub struct RoutedScan<'a> {
    /// The behaviour the scan is for (GD-INPUT: it must be configured).
    pub behaviour: BehaviourId,
    /// The scan, in its sensor's frame.
    pub scan: Scan<'a>,
}

/// What the sensors and estimators give in one tick; `X` is the law's extra
/// input ([`ControlLaw::Extra`]).
#[derive(Debug, Clone, Copy)]
pub struct TickInput<'a, X> {
    /// The scans that arrived in this tick, at most one per behaviour.
    pub scans: &'a [RoutedScan<'a>],
    /// The robot's pose from GNSS-RTK localisation, `World` frame; `None`
    /// when localisation has no valid pose (GD-LOCALISATION).
    pub gnss: Option<Pose2<World>>,
    /// The robot's pose from wheel odometry, `Odom` frame, every tick (the
    /// pipeline moves by its aided pose when an aid is configured,
    /// GD-ODOMETRY-AID).
    pub odometry: Pose2<Odom>,
    /// The law's extra input (backstepping: the observer's sideslip
    /// estimate, |β| < π/2); used only by path tracking with compensation on
    /// (GD-PREDICTION).
    pub extra: X,
}

/// The mode after a tick, or the source of its command, by behaviour id.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Mode {
    /// Path tracking on the planned path.
    PathTracking,
    /// The behaviour of this id.
    Behaviour(BehaviourId),
    /// Standstill (SW-STOP, GD-STOP); never a command's source.
    Stop,
}

/// What a control law made of its error in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LawOutcome {
    /// The law was not run: no valid estimate (or no projection).
    NotRun,
    /// The law's command, within the vehicle's limits.
    Commanded(Saturated),
    /// The law refused the error (PT-HEADING, PT-DENOM, ...): the source
    /// could not command in this tick (GD-COMMAND, GD-LOCALISATION).
    Refused(Precondition),
}

impl LawOutcome {
    /// The law's command, when it gave one.
    #[must_use]
    pub const fn command(&self) -> Option<&Saturated> {
        match self {
            Self::Commanded(command) => Some(command),
            Self::NotRun | Self::Refused(_) => None,
        }
    }

    /// The law's outcome on `error`; a command the vehicle refuses (another
    /// actuation, beyond a limit: a law built for other limits) is the law's
    /// refusal, `GD-VEHICLE` (GD-VEHICLE).
    fn run<L: ControlLaw>(
        law: &L,
        vehicle: &Vehicle,
        error: &TrackingError,
        extra: &L::Extra,
        speed: MetersPerSecond,
    ) -> Self {
        match law
            .command(error, extra, speed)
            .and_then(|c| vehicle.check(&c.command).map(|()| c))
        {
            Ok(command) => Self::Commanded(command),
            Err(e) => Self::Refused(e),
        }
    }
}

/// Path tracking in one tick; `X` is the law's extra input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathStatus<X> {
    /// The Frénet error of the GNSS pose (with c(s + vT)), or of the last
    /// good fix carried by odometry (`fix`, GD-FIX-QUALITY), corrected by a
    /// float fix once it measured its offset (GD-FIX-FLOAT); `None` without
    /// a pose or when the projection was refused.
    pub frenet: Option<FrenetError>,
    /// Why the projection was refused, if it was (overflow).
    pub projection_refused: Option<Precondition>,
    /// The path-tracking law's result.
    pub law: LawOutcome,
    /// Whether localisation is valid for path tracking (GD-LOCALISATION).
    pub localisation_valid: bool,
    /// The extra input the law used: the tick's with compensation on, else
    /// the law's neutral input.
    pub extra_used: X,
    /// The pose the plan check judged the lines from (GD-PLAN-DEAD-RECKONING).
    pub plan_pose: PlanPose,
    /// The shift of path tracking's reference from the path in this tick,
    /// when a hand-over rule is configured and one applies (GD-HANDOVER),
    /// or while a returning good fix is rejoined (GD-FIX-QUALITY).
    pub reference_offset: Option<Meters>,
    /// What path tracking steered on: the fix, the last good fix carried,
    /// or nothing and why (GD-FIX-QUALITY).
    pub fix: FixUse,
}

/// The pose a tick's plan check judged the behaviours' lines from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlanPose {
    /// The tick's GNSS pose, projected on the path.
    Gnss,
    /// No fix in the tick: the last fix moved by the odometry since it,
    /// `travelled` metres of odometry, projected on the path as `frenet`
    /// (never used by path tracking).
    DeadReckoned {
        /// Odometry distance since the fix.
        travelled: Meters,
        /// The dead-reckoned pose's Frénet error.
        frenet: FrenetError,
    },
    /// Neither: no fix yet, a refused projection, no dead reckoning
    /// configured, or the fix carried farther than configured. The check
    /// cannot judge, and every line counts as consistent (GD-PLAN).
    Unjudged,
}

/// A behaviour in one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BehaviourStatus {
    /// The behaviour's id.
    pub id: BehaviourId,
    /// The behaviour's label.
    pub label: &'static str,
    /// The verdict of the held detection: the latest scan's, or Absent
    /// without one, when too old or refused (GD-SCAN-AGE); Hold while the
    /// bridge carries the last valid line (GD-BRIDGE).
    pub detected: Verdict,
    /// The verdict the switching machine got: `detected`, or Exit when the
    /// law refused a valid estimate (GD-COMMAND).
    pub reported: Verdict,
    /// The tracking error to the behaviour's line at the current pose;
    /// `None` exactly when `detected` is Absent.
    pub error: Option<TrackingError>,
    /// The quality figure of the held detection's scan, when it has one and
    /// that scan is at most the maximal scan age old (also for an Absent
    /// verdict: a furrow selection not yet long enough for a line).
    pub quality: Option<f64>,
    /// Ticks since the scan of the held detection (0: this tick's scan).
    pub scan_age: Option<u16>,
    /// Why this tick's scan was refused by the detector, if it was.
    pub scan_refused: Option<Precondition>,
    /// The line relative to the planned path, when both errors exist.
    pub plan: Option<LineRelativeToPath>,
    /// The plan-consistency flag given to the machine (GD-PLAN).
    pub plan_consistent: bool,
    /// When the estimate is the last valid line carried across a scan that
    /// found nothing (GD-BRIDGE), or whose line disagreed with the structure
    /// line (GD-BRIDGE-AGREE): the odometry distance since that line's scan.
    pub bridged: Option<Meters>,
    /// The behaviour's law on its error, run only for a valid estimate.
    pub law: LawOutcome,
}

/// Everything one tick produced; `X` is the law's extra input, `K` the most
/// behaviours.
#[derive(Debug, Clone, PartialEq)]
pub struct TickOutput<X, const K: usize> {
    /// The command to apply: the selected source's (GD-COMMAND), a stop in
    /// Stop (GD-STOP), `None` when no source may command in this tick.
    pub command: Option<Saturated>,
    /// The mode after this tick.
    pub mode: Mode,
    /// The source of `command` (never Stop); `None` in Stop and without a
    /// command.
    pub source: Option<Mode>,
    /// The switching machine's own output (behaviour indices in priority order).
    pub switching: Output,
    /// Path tracking: projection, law, localisation.
    pub path: PathStatus<X>,
    /// The configured behaviours, in priority order.
    pub behaviours: Vec<BehaviourStatus, K>,
}

impl<X, const K: usize> TickOutput<X, K> {
    /// The status of behaviour `id`, when it is configured.
    #[must_use]
    pub fn behaviour(&self, id: BehaviourId) -> Option<&BehaviourStatus> {
        self.behaviours.iter().find(|b| b.id == id)
    }
}

/// The latest detection of a behaviour and where the robot was when its
/// scan was taken.
#[derive(Debug, Clone, Copy)]
struct Held<L> {
    detection: Detection<L>,
    odom: Pose2<Odom>,
    age: u16,
}

/// One behaviour slot's state: its detector and the detection it holds.
#[derive(Debug, Clone)]
struct Slot<D: Detector> {
    detector: D,
    held: Option<Held<D::Line>>,
    /// The latest valid line and the structure line, for the bridge
    /// (GD-BRIDGE, GD-BRIDGE-STEADY).
    bridge: bridge::Bridge,
}

/// A behaviour's estimate in the current tick, before plan and law.
#[derive(Debug, Clone, Copy)]
struct Estimate {
    verdict: Verdict,
    error: Option<TrackingError>,
    quality: Option<f64>,
    age: Option<u16>,
    refused: Option<Precondition>,
    bridged: Option<Meters>,
}

impl Estimate {
    const NONE: Self = Self {
        verdict: Verdict::Absent,
        error: None,
        quality: None,
        age: None,
        refused: None,
        bridged: None,
    };
}

/// What a slot needs besides its scan to make its estimate in one tick.
#[derive(Debug, Clone, Copy)]
struct Carry {
    odometry: Pose2<Odom>,
    travelled: f64,
    max_age: u16,
    /// The bridge length, when configured (GD-BRIDGE).
    bridge: Option<Meters>,
    /// Whether the slot's behaviour is the machine's active mode.
    active: bool,
    /// The path's heading in the odometry frame (GD-EXPECTED-HEADING).
    expected_heading: Option<Radians>,
}

impl<D: Detector> Slot<D> {
    /// This slot's estimate in this tick: the detection of `scan` when one
    /// came, else the held one aged by a tick and moved to `odometry`, Absent
    /// when older than `max_age` or when it cannot be moved (GD-SCAN-AGE,
    /// GD-ODOMETRY).
    //= spec/guidance.md#gd-scan-age-held-detections
    //# In a tick without a new scan, a behaviour MUST report the verdict of its
    //# latest scan, with the tracking error to that scan's line moved to the current
    //# pose through odometry, as long as that scan is at most the maximal scan age
    //# old; an older scan, a scan the detector refused, or no scan at all MUST give
    //# Absent.
    //= spec/guidance.md#gd-input-malformed-input
    //# Sensor data MUST NOT be malformed input: any range, NaN and infinities
    //# included, and any scan a detector refuses MUST give a tick output, the
    //# refused scan counting as no estimate.
    fn estimate(&mut self, scan: Option<&Scan<'_>>, carry: &Carry) -> Estimate {
        let estimate = self.held_estimate(scan, &carry.odometry, carry.max_age);
        let Some(bridge) = carry.bridge else {
            return estimate;
        };
        self.bridge
            .expect_heading(carry.expected_heading.map(Radians::get));
        let outcome = match (scan, &self.held) {
            (None, _) => bridge::ScanOutcome::None,
            (Some(_), Some(held)) if estimate.refused.is_none() => {
                bridge::ScanOutcome::Read(&held.detection)
            }
            (Some(_), _) => bridge::ScanOutcome::Refused,
        };
        let disagreed = self
            .bridge
            .record(outcome, &carry.odometry, carry.travelled, bridge);
        // A valid line that disagrees with the structure line is bridged
        // over like a gap until the next scan (GD-BRIDGE-AGREE).
        //= spec/guidance.md#gd-bridge-agree-a-line-that-disagrees-with-the-structure-line-is-bridged
        //# Until the behaviour's next scan, the
        //# behaviour of the active specialised mode MUST then report Hold with the
        //# error of GD-BRIDGE, as for a scan that found nothing.
        if !carry.active || (estimate.verdict.estimate_is_valid() && !disagreed) {
            return estimate;
        }
        match self.bridge.carried(&carry.odometry, bridge) {
            Some((error, carried)) => Estimate {
                verdict: Verdict::Hold,
                error: Some(error),
                bridged: Some(carried),
                ..estimate
            },
            None => estimate,
        }
    }

    /// The estimate of GD-SCAN-AGE, without the bridge.
    fn held_estimate(
        &mut self,
        scan: Option<&Scan<'_>>,
        odometry: &Pose2<Odom>,
        max_age: u16,
    ) -> Estimate {
        if let Some(scan) = scan {
            match self.detector.observe(scan, odometry) {
                Ok(detection) => {
                    self.held = Some(Held {
                        detection,
                        odom: *odometry,
                        age: 0,
                    });
                }
                Err(e) => {
                    self.held = None;
                    return Estimate {
                        refused: Some(e),
                        ..Estimate::NONE
                    };
                }
            }
        } else if let Some(held) = self.held.as_mut() {
            held.age = held.age.saturating_add(1);
        }
        let Some(held) = self.held else {
            return Estimate::NONE;
        };
        let aged = Estimate {
            age: Some(held.age),
            ..Estimate::NONE
        };
        let d = held.detection;
        if held.age > max_age {
            return aged;
        }
        let aged = Estimate {
            quality: d.quality,
            ..aged
        };
        if d.verdict == Verdict::Absent {
            return aged;
        }
        let error = if held.age == 0 {
            d.error
        } else {
            d.line.and_then(|line| {
                let pose = pose_in_scan_frame(&held.odom, odometry).ok()?;
                line.error_at(&pose).ok()
            })
        };
        match error {
            Some(error) => Estimate {
                verdict: d.verdict,
                error: Some(error),
                ..aged
            },
            // Moving overflowed (or a detector gave no error): no estimate.
            None => aged,
        }
    }
}

/// How far ahead of the projection the path's chord is taken for the
/// heading given to the detectors, m (GD-EXPECTED-HEADING): about where an
/// inclined LiDAR meets the ground.
const EXPECTED_HEADING_CHORD: f64 = 4.0;

/// The per-tick guidance pipeline (`spec/guidance.md`).
///
/// `PATH` is the capacity of the borrowed reference path, `D` the detector
/// type of every slot (one detector, or [`crate::perception::AnyDetector`]
/// for several kinds), `L` the law of path tracking and of every behaviour,
/// `K` the most behaviour slots (1 to 8).
#[derive(Debug, Clone)]
pub struct Guidance<'p, const PATH: usize, D: Detector, L: ControlLaw, const K: usize> {
    config: GuidanceConfig<D::Config, L, K>,
    path: &'p ReferencePath<PATH>,
    machine: Switching<K>,
    slots: Vec<Slot<D>, K>,
    /// Abscissa of the last successful projection.
    s_hint: Option<Meters>,
    /// Odometry distance travelled since that projection, m.
    since_projection: f64,
    last_odometry: Option<Pose2<Odom>>,
    /// The last GNSS fix and the odometry since it (GD-PLAN-DEAD-RECKONING).
    last_fix: Option<LastFix>,
    /// The last command made; its stop is held in Stop (GD-STOP).
    last_command: Command,
    /// The wheels turning at standstill after a Stop (GD-RESUME).
    turning: Option<resume::Turning>,
    /// The commanding behaviour's line offset from the path, last known, m.
    line_offset: Option<Meters>,
    /// The hand-over in progress (GD-HANDOVER).
    handing_over: Option<handover::Active>,
    /// The commanding behaviour's line in its latest commanding tick, and
    /// the line a hand-over holds (GD-HANDOVER-LINE).
    last_line: Option<handover::CarriedLine>,
    held_line: Option<handover::CarriedLine>,
    /// The entry in progress into the active behaviour (GD-ENTRY).
    entering: Option<entry::Entering>,
    /// Path tracking's lateral error on the carried pose in the last tick
    /// that steered on it, until a good fix returns (GD-FIX-QUALITY).
    carried_y: Option<Meters>,
    /// The rejoin in progress after a good fix returned (GD-FIX-QUALITY).
    rejoining: Option<fix::Rejoin>,
    /// The float span since the last good fix (GD-FIX-FLOAT).
    floating: Option<fix::FloatSpan>,
    /// The path's heading in the odometry frame at the last tick path
    /// tracking had a pose, given to the detectors (GD-EXPECTED-HEADING).
    expected_heading: Option<Radians>,
    /// The aided odometry, when an aid is configured (GD-ODOMETRY-AID).
    aided: AidedOdometry,
}

/// A GNSS fix, the odometry pose of its tick and the odometry distance
/// travelled since.
#[derive(Debug, Clone, Copy)]
struct LastFix {
    world: Pose2<World>,
    odometry: Pose2<Odom>,
    travelled: f64,
}

impl<'p, const PATH: usize, D, L, const K: usize> Guidance<'p, PATH, D, L, K>
where
    D: Detector,
    L: ControlLaw + Copy,
    D::Config: Copy,
{
    /// A pipeline on `path` in its initial state: path tracking, no
    /// detection held, no projection yet.
    ///
    /// # Errors
    /// The error of a detector's [`Detector::configure`] (for example
    /// `FUR-ACCUMULATE` when its capacity is too small for its
    /// configuration).
    pub fn new(
        config: GuidanceConfig<D::Config, L, K>,
        path: &'p ReferencePath<PATH>,
    ) -> Result<Self, Precondition> {
        let mut slots = Vec::new();
        for b in config.behaviours() {
            let slot = Slot {
                detector: D::configure(&b.detector)?,
                held: None,
                bridge: bridge::Bridge::default(),
            };
            // The configuration holds at most K behaviours.
            if slots.push(slot).is_err() {
                return Err(Precondition::new("GD-BEHAVIOURS", "more than K behaviours"));
            }
        }
        Ok(Self {
            machine: Switching::new(*config.switching()),
            last_command: config.params().vehicle.actuation().at_rest(),
            config,
            path,
            slots,
            s_hint: None,
            since_projection: 0.0,
            last_odometry: None,
            last_fix: None,
            turning: None,
            line_offset: None,
            handing_over: None,
            last_line: None,
            held_line: None,
            entering: None,
            carried_y: None,
            rejoining: None,
            floating: None,
            expected_heading: None,
            aided: AidedOdometry::new(),
        })
    }

    /// The configuration (behaviours in priority order).
    #[must_use]
    pub const fn config(&self) -> &GuidanceConfig<D::Config, L, K> {
        &self.config
    }

    /// The reference path.
    #[must_use]
    pub const fn path(&self) -> &'p ReferencePath<PATH> {
        self.path
    }

    /// Replaces the reference path between two ticks (a planner hands a new
    /// one); the next projection searches the whole new path (GD-PATH).
    //= spec/guidance.md#gd-path-a-reference-path-replaced-between-ticks
    //# The reference path MUST be replaceable between ticks without rebuilding the
    //# pipeline, keeping the mode, the switching counters and the held
    //# detections, and the first projection on a new path MUST search the whole
    //# path.
    pub fn set_path(&mut self, path: &'p ReferencePath<PATH>) {
        self.path = path;
        self.s_hint = None;
        self.since_projection = 0.0;
        self.line_offset = None;
        self.handing_over = None;
        self.last_line = None;
        self.held_line = None;
        self.entering = None;
        self.carried_y = None;
        self.rejoining = None;
    }

    /// Replaces the desired speed of path tracking between ticks (a path
    /// recorded with a speed per stretch); the mode, the switching counters
    /// and the held detections are kept, and the next tick's command and
    /// curvature look-ahead v (T + τ) use the new speed (GD-SPEED-CHANGE).
    ///
    /// # Errors
    /// `GD-SPEED` when `speed` is not positive, the path-tracking law's error
    /// when it refuses it (`PT-SCHEDULE-RANGE` outside a backstepping law's
    /// speed schedule); the configured speed is then unchanged.
    //= spec/guidance.md#gd-speed-change-desired-speed-of-path-tracking-changed-between-ticks
    //# The desired speed of path tracking MUST be replaceable between ticks without
    //# rebuilding the pipeline, keeping the mode, the switching counters and the held
    //# detections; a speed that is not positive MUST be refused with `GD-SPEED` and a
    //# speed the path-tracking law refuses with the law's error, leaving the
    //# configured speed unchanged; after a change, the command of path tracking and
    //# the look-ahead v (T + τ) of its curvature MUST use the new speed.
    pub fn set_path_speed(&mut self, speed: MetersPerSecond) -> Result<(), Precondition> {
        self.config.set_path_speed(speed)
    }

    /// The switching machine (its mode and counters).
    #[must_use]
    pub const fn switching(&self) -> &Switching<K> {
        &self.machine
    }

    /// The current mode.
    #[must_use]
    pub fn mode(&self) -> Mode {
        self.mode_of(self.machine.mode())
    }

    /// The label of `mode`: `"path_tracking"`, `"stop"` or the behaviour's.
    #[must_use]
    pub fn label(&self, mode: Mode) -> &'static str {
        match mode {
            Mode::PathTracking => "path_tracking",
            Mode::Stop => "stop",
            Mode::Behaviour(id) => self
                .config
                .behaviours()
                .iter()
                .find(|b| b.id == id)
                .map_or("unknown", |b| b.label),
        }
    }

    /// The detector of behaviour `id`, when it is configured.
    #[must_use]
    pub fn detector(&self, id: BehaviourId) -> Option<&D> {
        self.slot(id).map(|s| &s.detector)
    }

    /// The latest detection behaviour `id` holds, if any.
    #[must_use]
    pub fn held(&self, id: BehaviourId) -> Option<&Detection<D::Line>> {
        self.slot(id)?.held.as_ref().map(|h| &h.detection)
    }

    fn slot(&self, id: BehaviourId) -> Option<&Slot<D>> {
        self.config
            .behaviours()
            .iter()
            .position(|b| b.id == id)
            .and_then(|i| self.slots.get(i))
    }

    /// The machine's mode with its priority index resolved to the id; an
    /// index beyond the configured behaviours (never entered: they report
    /// Absent) reads as Stop, the safe reading.
    fn mode_of(&self, mode: MachineMode) -> Mode {
        match mode {
            MachineMode::PathTracking => Mode::PathTracking,
            MachineMode::Stop => Mode::Stop,
            MachineMode::Behaviour(i) => self
                .config
                .behaviours()
                .get(i)
                .map_or(Mode::Stop, |b| Mode::Behaviour(b.id)),
        }
    }

    /// The heading in the odometry frame of the path's chord from the
    /// projection `frenet` to [`EXPECTED_HEADING_CHORD`] ahead, as seen
    /// from the robot at `odometry` (GD-EXPECTED-HEADING); `None` on overflow.
    fn path_heading_in_odometry(
        &self,
        frenet: &FrenetError,
        odometry: &Pose2<Odom>,
    ) -> Option<Radians> {
        let from = self.path.point_at(frenet.s).ok()?;
        let ahead = Meters::new(frenet.s.get() + EXPECTED_HEADING_CHORD).ok()?;
        let to = self.path.point_at(ahead).ok()?;
        let chord = libm::atan2(to.y() - from.y(), to.x() - from.x());
        let tangent = self.path.heading_at(frenet.s).get();
        Radians::new(odometry.heading.get() - frenet.angular_deviation.get() - tangent + chord)
            .ok()
            .map(wrap_angle)
    }

    /// One control tick (`spec/guidance.md`; the module documentation lists
    /// the steps).
    ///
    /// # Errors
    /// Only for malformed input, before any state changes (GD-INPUT): the
    /// law's refusal of the extra input (`PT-SIDESLIP` when |β| ≥ π/2 for
    /// backstepping), `GD-INPUT` when a scan is routed to a behaviour that is
    /// not configured or two scans to one behaviour. Scans with any values,
    /// refused scans and laws that refuse their errors all give an output.
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
    //= spec/library.md#lib-bounded-tick-every-loop-of-a-tick-has-a-bound-fixed-before-the-first-tick
    //# Every loop the core runs in one guidance tick MUST be bounded by the length
    //# of an input slice, a const-generic capacity or a count validated at
    //# configuration, so that the cost of the worst tick is known before the first
    //# tick.
    pub fn step(
        &mut self,
        input: &TickInput<'_, L::Extra>,
    ) -> Result<TickOutput<L::Extra, K>, Precondition> {
        self.step_with_fix(input, &FixQuality::RTK_FIXED)
    }

    /// One control tick whose GNSS pose, if any, has the quality `quality`
    /// the receiver reports: with a fix rule configured, a fix the rule
    /// refuses counts as no fix (GD-FIX-QUALITY); [`Guidance::step`] is this
    /// with an RTK-fixed quality.
    ///
    /// # Errors
    /// As [`Guidance::step`]: only for malformed input (GD-INPUT).
    //= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
    //# When a fix rule is configured, a tick whose fix is not good MUST be
    //# processed as a tick without a fix: it MUST NOT be projected for path
    //# tracking or for the plan check, nor become the last fix of
    //# GD-PLAN-DEAD-RECKONING; without a rule every fix MUST be taken.
    pub fn step_with_fix(
        &mut self,
        input: &TickInput<'_, L::Extra>,
        quality: &FixQuality,
    ) -> Result<TickOutput<L::Extra, K>, Precondition> {
        self.check_input(input)?;
        let gnss = match self.config.fix() {
            Some(rule) => rule.filter(input.gnss, quality),
            None => input.gnss,
        };
        // Every step below moves by this pose, never by the tick's own.
        let odometry = match self.config.odometry_aid() {
            Some(aid) => self.aided.step(aid, input.odometry, gnss.as_ref()),
            None => input.odometry,
        };
        let travelled = self.last_odometry.map_or(0.0, |p| {
            // A distance that overflows is an absurd jump: the whole path is searched.
            p.position
                .distance_to(odometry.position)
                .map_or(f64::INFINITY, Meters::get)
        });
        self.last_odometry = Some(odometry);
        match (gnss, self.last_fix.as_mut()) {
            (Some(world), _) => {
                self.last_fix = Some(LastFix {
                    world,
                    odometry,
                    travelled: 0.0,
                });
            }
            (None, Some(fix)) => fix.travelled += travelled,
            (None, None) => {}
        }

        // 1. Detections, or the held ones aged and moved (GD-SCAN-AGE).
        let max_age = self.config.max_scan_age_ticks();
        let was_stopped = self.machine.mode() == MachineMode::Stop;
        let mut estimates = [Estimate::NONE; K];
        for (i, ((estimate, slot), b)) in estimates
            .iter_mut()
            .zip(self.slots.iter_mut())
            .zip(self.config.behaviours())
            .enumerate()
        {
            let scan = input
                .scans
                .iter()
                .find(|s| s.behaviour == b.id)
                .map(|s| &s.scan);
            let carry = Carry {
                odometry,
                travelled,
                max_age,
                bridge: self.config.params().bridge,
                active: self.machine.mode() == MachineMode::Behaviour(i),
                expected_heading: self.expected_heading,
            };
            //= spec/guidance.md#gd-expected-heading-the-path-s-heading-given-to-the-detectors
            //# Before each behaviour's scan, the pipeline MUST give its detector the
            //# heading of the path's chord from path tracking's projection to 4 m ahead of
            //# it, in the odometry frame (the odometry heading less the angular deviation,
            //# less the path's heading at the projection, plus the chord's), from the
            //# latest tick that had a path pose, or none when no tick had one.
            slot.detector.expect_heading(self.expected_heading);
            *estimate = slot.estimate(scan, &carry);
        }

        // 2. The path (GD-LOCALISATION).
        let (frenet, projection_refused) = self.project(gnss.as_ref(), travelled);
        self.track_float(
            input.gnss.as_ref(),
            quality,
            gnss.is_some(),
            &odometry,
            travelled,
        );
        let (path_frenet, fix_use) = self.path_pose(frenet, gnss.is_some(), &odometry);
        if let Some(f) = &path_frenet {
            self.expected_heading = self.path_heading_in_odometry(f, &odometry);
        }
        let rejoin = self.rejoin(path_frenet.as_ref(), &fix_use, travelled);
        for active in [
            self.handing_over.as_mut(),
            self.entering.as_mut().map(|e| &mut e.ramp),
        ]
        .into_iter()
        .flatten()
        {
            active.travelled += travelled;
        }
        let held_line = self.line_hold(path_frenet.as_ref(), &odometry);

        // 3-4. Plan consistency and the laws.
        let params = self.config.params();
        let extra_used = if params.path.compensation {
            input.extra
        } else {
            L::NEUTRAL
        };
        //= spec/guidance.md#gd-prediction-extra-input-and-prediction-only-in-path-tracking
        //# Path tracking MUST use the tick's extra input, when compensation is
        //# configured, and the curvature c(s + vT) with v its desired speed and T the
        //# prediction horizon; every other behaviour MUST use its law's neutral input
        //# and a straight line, c = c(s + vT) = 0.
        //= spec/guidance.md#gd-plan-dead-reckoning-the-plan-checked-through-a-gnss-outage
        //# Path tracking MUST NOT use the dead-reckoned pose: localisation stays
        //# invalid without a fix (GD-LOCALISATION).
        let plan_pose = match (&frenet, gnss) {
            (Some(_), _) => PlanPose::Gnss,
            (None, Some(_)) => PlanPose::Unjudged,
            (None, None) => self.dead_reckoned(&odometry),
        };
        let mut behaviours = Vec::<BehaviourStatus, K>::new();
        let mut ahead = None;
        let plan_frenet = match &plan_pose {
            PlanPose::Gnss => frenet,
            PlanPose::DeadReckoned { frenet, .. } => Some(*frenet),
            PlanPose::Unjudged => None,
        };
        // Path tracking's carried pose when the plan pose has no projection
        // (GD-FIX-QUALITY): it places the lines on the path.
        let carried = path_frenet
            .filter(|_| plan_frenet.is_none())
            .map(|f| f.tracking_error());
        for (i, (estimate, b)) in estimates.iter().zip(self.config.behaviours()).enumerate() {
            let reference = plan_frenet.as_ref().map(|f| {
                PlanReference::new(self.path, f, b.plan, estimate.error.is_some(), &mut ahead)
            });
            let entry = self.entry_reference(i, estimate.error.as_ref());
            // One status per configured behaviour, at most K.
            let _ = behaviours.push(behaviour_status(
                estimate,
                reference.as_ref(),
                carried.as_ref(),
                b,
                &params.vehicle,
                entry,
                self.machine.mode() == MachineMode::Behaviour(i),
            ));
        }
        //= spec/guidance.md#gd-bridge-plan-only-lines-consistent-with-the-plan-anchor-the-structure-line
        //# The anchor of a valid detection whose line is not consistent with the
        //# plan in its tick (GD-PLAN, GD-PLAN-ENTRY) MUST be taken back once that
        //# tick's plan consistency is known, so that it takes no part in the
        //# structure line of the later ticks.
        for (slot, status) in self.slots.iter_mut().zip(behaviours.iter()) {
            if !status.plan_consistent {
                slot.bridge.take_back_anchor();
            }
        }
        let approach = self.approach(&behaviours);
        let held_line = held_line.filter(|_| approach.is_none());
        let reference_offset = self.reference_offset();
        let rejoin = rejoin.filter(|_| approach.is_none() && reference_offset.is_none());
        let path_law = match &path_frenet {
            Some(f) => match held_line.map_or_else(
                || self.rejoined_error(f, rejoin, reference_offset, approach),
                Ok,
            ) {
                Ok(error) => LawOutcome::run(
                    &params.path.law,
                    &params.vehicle,
                    &error,
                    &extra_used,
                    params.path.speed,
                ),
                Err(e) => LawOutcome::Refused(e),
            },
            None => LawOutcome::NotRun,
        };
        //= spec/guidance.md#gd-localisation-localisation-for-path-tracking
        //# Localisation MUST be valid in a tick exactly when a GNSS pose is given, its
        //# projection on the path succeeds and the path-tracking law gives a command
        //# from it.
        let localisation_valid = path_law.command().is_some();
        let path = PathStatus {
            frenet: path_frenet,
            projection_refused,
            law: path_law,
            localisation_valid,
            extra_used,
            plan_pose,
            reference_offset: approach
                .map(|(o, _)| o)
                .or_else(|| self.shift(reference_offset))
                .or_else(|| self.rejoin_shift(rejoin)),
            fix: fix_use,
        };

        // 5. The switching machine (GD-BEHAVIOURS).
        //= spec/guidance.md#gd-behaviours-behaviour-slots-in-a-priority-order
        //# The pipeline MUST hold a list of behaviour slots, each with an id unique in
        //# the pipeline, a label, a detector, a law, a desired speed, two transit
        //# delays and an optional plan tolerance, and MUST run a switching machine over
        //# them in the configured priority order; a slot beyond the configured
        //# behaviours MUST report Absent in every tick.
        let mut reports = [Report::consistent(Verdict::Absent); K];
        for (report, status) in reports.iter_mut().zip(behaviours.iter()) {
            *report = Report {
                verdict: status.reported,
                plan_consistent: status.plan_consistent,
            };
        }
        let before = self.machine.mode();
        let switching = self.machine.step(&Input {
            behaviours: reports,
            localisation_valid,
        });
        self.track_handover(before, &switching, &behaviours, travelled, &odometry);
        self.track_entry(before, &switching, &behaviours, path.reference_offset);

        // 6. The command of the selected source.
        //= spec/guidance.md#gd-command-the-command-of-the-selected-source
        //# The command MUST be the saturated output of the selected source's control law
        //# on that source's error of the tick, and no other; when the machine selects no
        //# source outside Stop, there MUST be no command.
        //= spec/guidance.md#gd-speed-desired-speed-per-mode
        //# The speed of a command MUST be the desired speed of its source.
        let (command, source) = match switching.source {
            CommandSource::PathTracking => (path.law.command().copied(), Some(Mode::PathTracking)),
            CommandSource::Behaviour(i) => match behaviours.get(i) {
                Some(status) => (
                    status.law.command().copied(),
                    Some(Mode::Behaviour(status.id)),
                ),
                None => (None, None),
            },
            CommandSource::None => (None, None),
        };
        // A selected source always has a command (its law ran and gave one:
        // GD-COMMAND); should it not, nothing is commanded and no source named.
        let source = command.and(source);
        let mode = self.mode_of(switching.mode);
        let command = match command {
            Some(c) => {
                let params = self.config.params();
                let c = if params.steer_before_resuming && source == Some(Mode::PathTracking) {
                    resume::command(
                        &mut self.turning,
                        was_stopped,
                        &self.last_command,
                        c,
                        &params.vehicle,
                        params.period,
                        self.config.settle_ticks(),
                    )
                } else {
                    // A behaviour's command, at once (GD-RESUME).
                    self.turning = None;
                    c
                };
                self.last_command = c.command;
                Some(c)
            }
            //= spec/guidance.md#gd-stop-the-stop-command
            //# In Stop the command MUST be the stop of the last command made (every speed
            //# zero, steering angles held, a yaw rate zero), or the vehicle at rest before
            //# any command, never saturated.
            None if mode == Mode::Stop => Some(Saturated {
                command: self.last_command.stopped(),
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
            behaviours,
        })
    }

    /// GD-INPUT: refuse malformed input before anything changes.
    //= spec/guidance.md#gd-input-malformed-input
    //# A tick whose input is malformed MUST be refused with an error before any
    //# state changes: an extra input the law refuses (for backstepping a sideslip
    //# outside |β| < π/2, `PT-SIDESLIP`), a scan routed to a behaviour that is not
    //# configured, or two scans routed to one behaviour in one tick (`GD-INPUT`).
    fn check_input(&self, input: &TickInput<'_, L::Extra>) -> Result<(), Precondition> {
        L::check_extra(&input.extra)?;
        for (i, routed) in input.scans.iter().enumerate() {
            if !self
                .config
                .behaviours()
                .iter()
                .any(|b| b.id == routed.behaviour)
            {
                return Err(Precondition::new(
                    "GD-INPUT",
                    "scan routed to a behaviour that is not configured",
                ));
            }
            let again = input.scans.iter().skip(i.saturating_add(1));
            if again.into_iter().any(|o| o.behaviour == routed.behaviour) {
                return Err(Precondition::new(
                    "GD-INPUT",
                    "two scans routed to one behaviour in one tick",
                ));
            }
        }
        Ok(())
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
        match self.project_locally(pose) {
            Ok(frenet) => {
                self.s_hint = Some(frenet.s);
                self.since_projection = 0.0;
                (Some(frenet), None)
            }
            Err(e) => (None, Some(e)),
        }
    }

    /// The projection of `pose` within the search window plus the odometry
    /// distance since the last projection, around its abscissa; the whole
    /// path before the first one or when the window overflows.
    fn project_locally(&self, pose: &Pose2<World>) -> Result<FrenetError, Precondition> {
        let lookahead = self.config.lookahead();
        let base = self.config.params().path.search_window.get();
        // A window that overflows (absurd odometry) searches the whole path.
        let window = Meters::new(base + self.since_projection).ok();
        match (self.s_hint, window) {
            (Some(hint), Some(window)) => self.path.project_near(pose, lookahead, hint, window),
            _ => self.path.project(pose, lookahead),
        }
    }

    /// The plan check's pose in a tick without a fix (GD-PLAN-DEAD-RECKONING):
    /// the last fix moved by the odometry since it, while that distance is
    /// within the configured one.
    //= spec/guidance.md#gd-plan-dead-reckoning-the-plan-checked-through-a-gnss-outage
    //# When a dead-reckoning distance is configured and a tick has no GNSS pose,
    //# the plan consistency of GD-PLAN MUST be judged from the pose of the last
    //# fix moved by odometry: the tick's odometry pose in the robot frame of the
    //# fix's odometry pose, placed at the fix, as long as the odometry distance
    //# summed over the ticks since the fix is at most the configured distance;
    //# beyond it, and before the first fix, the check MUST NOT judge.
    fn dead_reckoned(&self, odometry: &Pose2<Odom>) -> PlanPose {
        let Some(limit) = self.config.params().plan_dead_reckoning else {
            return PlanPose::Unjudged;
        };
        match self.carried(odometry, limit, None) {
            Ok((travelled, frenet)) => PlanPose::DeadReckoned { travelled, frenet },
            Err(_) => PlanPose::Unjudged,
        }
    }

    /// The last fix moved by the odometry since it to the tick's odometry
    /// pose, then by `correction` (GD-FIX-FLOAT) when given, projected on
    /// the path, with the odometry distance since the fix, while that
    /// distance is at most `limit`.
    ///
    /// # Errors
    /// As [`Guidance::carried_pose`], or `GD-FIX-QUALITY` when the pose has
    /// no projection.
    fn carried(
        &self,
        odometry: &Pose2<Odom>,
        limit: Meters,
        correction: Option<fix::Offset>,
    ) -> Result<(Meters, FrenetError), Precondition> {
        let (travelled, pose) = self.carried_pose(odometry, limit)?;
        let frenet = correction
            .map_or(Ok(pose), |c| c.applied(&pose))
            .and_then(|pose| self.project_locally(&pose))
            .map_err(|_| {
                Precondition::new("GD-FIX-QUALITY", "the carried pose has no projection")
            })?;
        Ok((travelled, frenet))
    }

    /// The last fix moved by the odometry since it to the tick's odometry
    /// pose, with the odometry distance since the fix, while that distance
    /// is at most `limit`.
    ///
    /// # Errors
    /// `GD-FIX-QUALITY` naming why nothing can be carried: no fix yet,
    /// carried farther than `limit`, or the move refused.
    fn carried_pose(
        &self,
        odometry: &Pose2<Odom>,
        limit: Meters,
    ) -> Result<(Meters, Pose2<World>), Precondition> {
        let Some(fix) = self.last_fix else {
            return Err(Precondition::new("GD-FIX-QUALITY", "no good fix yet"));
        };
        if fix.travelled > limit.get() {
            return Err(Precondition::new(
                "GD-FIX-QUALITY",
                "no good fix within the dead-reckoning distance",
            ));
        }
        let pose = pose_in_scan_frame(&fix.odometry, odometry)
            .and_then(|moved| fix.world.body_to_frame::<Robot>().apply_pose(moved))
            .map_err(|_| Precondition::new("GD-FIX-QUALITY", "the carried pose overflows"))?;
        let travelled = Meters::new(fix.travelled)
            .map_err(|_| Precondition::new("GD-FIX-QUALITY", "carried distance overflows"))?;
        Ok((travelled, pose))
    }
}

/// What a tick's line is compared with: the path's error and, when the
/// behaviour has a plan tolerance, that tolerance and the path at its
/// look-ahead (`None` when that overflowed).
struct PlanReference {
    path: TrackingError,
    check: Option<(PlanTolerance, Option<PathAhead>)>,
}

impl PlanReference {
    /// The reference of a behaviour with tolerance `plan` in a tick whose
    /// projection is `frenet`.
    //= spec/guidance.md#gd-plan-plan-consistency-of-the-detected-lines
    //# The path ahead MUST be taken at the tolerance's look-ahead from the
    //# projection's abscissa.
    ///
    /// The path ahead is computed only for a behaviour with a line to check
    /// (`needed`), and once per tick for each look-ahead: `cache` holds the
    /// last one (look-ahead bits, path ahead).
    fn new<const N: usize>(
        path: &ReferencePath<N>,
        frenet: &FrenetError,
        plan: Option<PlanTolerance>,
        needed: bool,
        cache: &mut Option<(u64, Option<PathAhead>)>,
    ) -> Self {
        let check = plan.map(|tolerance| {
            let lookahead = tolerance.lookahead();
            // A Meters is finite: not above zero is at or below it.
            let ahead = if lookahead.get() <= 0.0 {
                Some(PathAhead::HERE)
            } else if !needed {
                // Never read: without a line the behaviour is consistent.
                None
            } else {
                match *cache {
                    Some((bits, ahead)) if bits == lookahead.get().to_bits() => ahead,
                    _ => {
                        let ahead = PathAhead::on_path(path, frenet.s, lookahead).ok();
                        *cache = Some((lookahead.get().to_bits(), ahead));
                        ahead
                    }
                }
            };
            (tolerance, ahead)
        });
        Self {
            path: frenet.tracking_error(),
            check,
        }
    }
}

/// Plan consistency and the law of one configured behaviour (GD-PLAN,
/// GD-PLAN-ENTRY, GD-PREDICTION, GD-COMMAND); `in_mode` when the tick
/// started in that behaviour's mode.
fn behaviour_status<C, L: ControlLaw>(
    estimate: &Estimate,
    plan_reference: Option<&PlanReference>,
    carried: Option<&TrackingError>,
    behaviour: &BehaviourParams<C, L>,
    vehicle: &Vehicle,
    entry: Option<entry::EntryReference>,
    in_mode: bool,
) -> BehaviourStatus {
    //= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
    //# In a tick in which path tracking steers on the carried pose and the plan
    //# check's pose has no projection, a behaviour's line MUST be placed on the
    //# path against the carried pose: its offset from the path as
    //# `line_relative_to_path` gives it from the carried pose's error, its heading
    //# from the path's zero.
    // The carried heading drifts with the odometry's yaw: the line is taken
    // parallel to the path, so that GD-ENTRY's t₀ and h come from the line.
    let plan = match (&estimate.error, plan_reference, carried) {
        (Some(line), Some(r), _) => line_relative_to_path(line, &r.path).ok(),
        (Some(line), None, Some(path)) => {
            line_relative_to_path(line, path)
                .ok()
                .map(|p| LineRelativeToPath {
                    heading: Radians::ZERO,
                    ..p
                })
        }
        _ => None,
    };
    //= spec/guidance.md#gd-plan-plan-consistency-of-the-detected-lines
    //# A behaviour's line MUST be reported consistent with the plan when the
    //# behaviour has no plan tolerance or when the path has no projection in the
    //# tick; otherwise it MUST be reported as `PlanTolerance::is_consistent` judges
    //# its tracking error against the path's.
    let plan_consistent = match (&estimate.error, plan_reference) {
        (Some(line), Some(r)) => match &r.check {
            //= spec/guidance.md#gd-plan-entry-a-line-entered-only-near-the-path-s-heading
            //# When a behaviour's plan tolerance has an entry heading, its line MUST be
            //# reported consistent with the plan in a tick that starts outside that
            //# behaviour's mode only when, in addition to GD-PLAN, its heading differs
            //# from the path's by at most the entry heading; in a tick that starts in
            //# the behaviour's mode, GD-PLAN alone MUST judge it.
            Some((tolerance, Some(ahead))) => {
                tolerance.is_consistent(line, &r.path, ahead)
                    && (in_mode
                        || tolerance.entry_heading().is_none_or(|entry| {
                            line_relative_to_path(line, &r.path)
                                .is_ok_and(|p| p.heading.abs().get() <= entry.get())
                        }))
            }
            Some((_, None)) => false,
            None => true,
        },
        _ => true,
    };
    let law = match &estimate.error {
        // Straight line, neutral input, no prediction (GD-PREDICTION).
        Some(e) if estimate.verdict.estimate_is_valid() => {
            let line = TrackingError::to_straight_line(e.y, e.angular_deviation);
            let error = match entry {
                Some(reference) => reference.line_error(&line, plan.as_ref()),
                None => Ok(line),
            };
            match error {
                Ok(error) => LawOutcome::run(
                    &behaviour.law,
                    vehicle,
                    &error,
                    &L::NEUTRAL,
                    behaviour.speed,
                ),
                Err(e) => LawOutcome::Refused(e),
            }
        }
        _ => LawOutcome::NotRun,
    };
    //= spec/guidance.md#gd-command-the-command-of-the-selected-source
    //# A behaviour whose law refuses its error MUST be reported to the switching
    //# machine as Exit in that tick, so that a command source is always a source
    //# whose law gave a command.
    let reported = match law {
        LawOutcome::Refused(_) => Verdict::Exit,
        LawOutcome::NotRun | LawOutcome::Commanded(_) => estimate.verdict,
    };
    BehaviourStatus {
        id: behaviour.id,
        label: behaviour.label,
        detected: estimate.verdict,
        reported,
        error: estimate.error,
        quality: estimate.quality,
        scan_age: estimate.age,
        scan_refused: estimate.refused,
        plan,
        plan_consistent,
        law,
        bridged: estimate.bridged,
    }
}
