//! The robot's side of a tick: from sensor readings to a command.
//!
//! The runner calls a [`Guidance`] once per control period and knows nothing
//! of the laws inside; the one implementation is the core's pipeline
//! ([`pipeline::Pipeline`]), configured from the scenario's behaviour
//! sections.

pub mod pipeline;

use fieldguide::guidance::{FixUse, Mode, PlanPose, RoutedScan};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::{MetersPerSecond, Precondition, TrackingError, Verdict};

use crate::sensors::Readings;

/// What the guidance sees at one tick.
#[derive(Debug, Clone, Copy)]
pub struct TickInput<'a> {
    /// Time since the start, seconds.
    pub time_s: f64,
    /// The sensors' readings (never the ground truth).
    pub readings: &'a Readings,
    /// The scans of the LiDARs that scanned in this tick, each routed to
    /// its behaviour.
    pub scans: &'a [RoutedScan<'a>],
}

/// What the guidance sends to the vehicle at one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Command {
    /// The core's command to the vehicle (held from the previous tick when
    /// no source may command, GD-COMMAND).
    pub drive: fieldguide::model::Command,
    /// The behaviour whose law made the command (the plots' colour), or
    /// Stop.
    pub mode: Mode,
    /// The label of `mode` (traces, summaries, legends).
    pub label: &'static str,
    /// The switching machine's mode (differs from `mode` while an exit delay
    /// runs without a valid estimate: path tracking steers, SW-COMMAND).
    pub switching_mode: Mode,
    /// The label of `switching_mode`.
    pub switching_label: &'static str,
    /// Whether the law saturated the command.
    pub saturated: bool,
    /// The tracking error the law used (from the estimated pose).
    pub estimated_error: Option<TrackingError>,
    /// The sideslip the law used (zero without compensation).
    pub sideslip_used: Sideslip,
    /// What a row detector reported, when the guidance has one.
    pub detector: Option<DetectorStatus>,
    /// The pose the plan check judged the lines from (GD-PLAN-DEAD-RECKONING).
    pub plan_pose: PlanPose,
    /// The shift of path tracking's reference from the path during a
    /// hand-over, m, positive to the left (GD-HANDOVER); `None` without one.
    pub reference_offset: Option<f64>,
    /// What path tracking steered on: the fix, the last good fix carried,
    /// or nothing and why (GD-FIX-QUALITY).
    pub fix: FixUse,
}

impl Command {
    /// The commanded forward speed.
    #[must_use]
    pub fn speed(&self) -> MetersPerSecond {
        self.drive.speed()
    }

    /// The commanded steering angle, radians (0 for a vehicle that does not
    /// steer with an angle).
    #[must_use]
    pub fn steering(&self) -> f64 {
        self.drive.steering().map_or(0.0, fieldguide::Radians::get)
    }
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

/// The plot colour of a mode's label (Pierre 2022, Figs. 8 and 10: path
/// tracking in red, the specialised behaviour in blue; edge following a
/// lighter blue, so the two specialised behaviours stay apart in one
/// legend); other behaviours take greens and purples by label.
#[must_use]
pub fn colour(label: &str) -> &'static str {
    match label {
        "path_tracking" => "#d62728",
        "furrow_pursuing" => "#1f3fd0",
        "edge_following" => "#1f8fd0",
        "stop" => "#222222",
        other => {
            const OTHERS: [&str; 4] = ["#2ca02c", "#9467bd", "#8c564b", "#e377c2"];
            let hash = other.bytes().fold(0_usize, |h, b| {
                h.wrapping_mul(31).wrapping_add(usize::from(b))
            });
            OTHERS[hash % OTHERS.len()]
        }
    }
}

/// Half-width of the abscissa window searched around the last projection,
/// metres: far more than a tick's travel, far less than a U-turn's length, so
/// the projection cannot jump to the other leg (the core's search window, and
/// the runner's for the ground truth).
pub const SEARCH_WINDOW_M: f64 = 3.0;
