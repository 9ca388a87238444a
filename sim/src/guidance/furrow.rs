//! Furrow pursuing (Pierre 2022, section 2.3): the core's furrow detector on
//! the inclined LiDAR's scans, its row lines fed to the backstepping law.
//!
//! # The stand-in for switching
//!
//! Behaviour switching (section 3: transit delays, the state machine) is
//! issue 5's. Until then [`FurrowPursuing`] selects the behaviour by the
//! latest scan's verdict alone, with no delay: furrow pursuing while it is
//! Enter or Hold (an estimate that may be used), path tracking on the
//! recorded path while it is Exit or Absent (no line, or a line that must not
//! be used). Path tracking is stepped every tick, in charge or not, so its
//! projection follows the robot.
//!
//! # Between scans
//!
//! The detector steps on scan ticks (10 Hz in the built-in scenario) while the
//! control loop runs every control period (50 Hz). On the ticks between two
//! scans, the latest scan's row lines, fitted in the robot frame of that
//! scan, are moved into the current robot frame through the odometry poses of
//! both ticks (the same odometry the detector accumulates with), and the error
//! to them is recomputed (FUR-ERRORS, FUR-TWO-ROWS). No command is ever made
//! from a scan older than the latest one, nor from a verdict of Exit or
//! Absent: [`DetectorStatus`] records which scan each command came from.
//!
//! # The law
//!
//! Backstepping (eqs. 2-7) with the furrow's gains (Table 2: 0.8, mapped as
//! k = −g like path tracking), no sideslip and no prediction: the detected
//! line is straight, so c(s) = c(s + vT) = 0 ("this version of the control law
//! does not include an estimation of sideslip angles or the predictive
//! layer").

use fieldguide::control::backstepping::{steering_command, BacksteppingConfig};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::furrow::lines::{mean_tracking_error, tracking_error, RowLine};
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::perception::furrow::{FurrowDetector, RowLines};
use fieldguide::{
    Meters, MetersPerSecond, Odom, Point2, Pose2, Precondition, Robot, TrackingError, Verdict,
};

use super::{Command, DetectorStatus, Guidance, Mode, PathTracking, TickInput};
use crate::scenario::setup::FurrowSetup;

/// Most rays of the detector's angular window (a scenario whose window holds
/// more is refused, naming `furrow.window_half_angle_deg`).
pub const FURROW_RAYS: usize = 1024;

/// Most selections the detector keeps (`furrow.averaged_scans` at most this).
pub const FURROW_SCANS: usize = 64;

/// The simulator's furrow detector.
pub type Detector = FurrowDetector<FURROW_RAYS, FURROW_SCANS>;

/// The latest scan's detection.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Latest {
    verdict: Verdict,
    lines: Option<RowLines>,
    error: Option<TrackingError>,
    quality: Option<f64>,
    /// Odometry pose of the scan: the frame the lines are expressed in.
    odom: Pose2<Odom>,
    t_s: f64,
}

/// Furrow pursuing with path tracking standing in while the detector has no
/// usable line (see the module documentation).
#[derive(Debug, Clone)]
pub struct FurrowPursuing<'p> {
    detector: Box<Detector>,
    law: BacksteppingConfig,
    speed: MetersPerSecond,
    fallback: PathTracking<'p>,
    latest: Option<Latest>,
}

impl<'p> FurrowPursuing<'p> {
    /// Furrow pursuing as `setup` configures it, with `fallback` in charge
    /// while the verdict is Exit or Absent. Errors with the core's
    /// `FUR-ACCUMULATE` when the configured averaged scans exceed [`FURROW_SCANS`].
    pub fn new(setup: &FurrowSetup, fallback: PathTracking<'p>) -> Result<Self, Precondition> {
        Ok(Self {
            detector: Box::new(Detector::new(setup.detector)?),
            law: setup.backstepping,
            speed: setup.speed,
            fallback,
            latest: None,
        })
    }

    /// The detector's state.
    #[must_use]
    pub fn detector(&self) -> &Detector {
        &self.detector
    }
}

/// The row line `line`, expressed in the robot frame at odometry pose `then`,
/// in the robot frame at odometry pose `now`.
fn moved_line(
    line: &RowLine,
    then: &Pose2<Odom>,
    now: &Pose2<Odom>,
) -> Result<RowLine, Precondition> {
    let to_now = then
        .body_to_frame::<Robot>()
        .then(&now.body_to_frame::<Robot>().inverse()?)?;
    let p0 = to_now.apply(Point2::<Robot>::new(0.0, line.y_at(0.0))?)?;
    let p1 = to_now.apply(Point2::<Robot>::new(1.0, line.y_at(1.0))?)?;
    // The robot turns far less than 90° between two scans: p1.x − p0.x ≈ 1.
    let slope = (p1.y() - p0.y()) / (p1.x() - p0.x());
    RowLine::new(slope, Meters::new(p0.y() - slope * p0.x())?)
}

/// The tracking error to `lines` (seen at odometry pose `then`) from the
/// robot at odometry pose `now` (FUR-ERRORS for one row, FUR-TWO-ROWS for two).
pub fn error_now(
    lines: &RowLines,
    then: &Pose2<Odom>,
    now: &Pose2<Odom>,
) -> Result<TrackingError, Precondition> {
    match lines {
        RowLines::One(line) => tracking_error(&moved_line(line, then, now)?),
        RowLines::Two(Pair { left, right }) => mean_tracking_error(
            &moved_line(left, then, now)?,
            &moved_line(right, then, now)?,
        ),
    }
}

impl Guidance for FurrowPursuing<'_> {
    fn step(&mut self, input: &TickInput<'_>) -> Result<Command, Precondition> {
        let odom = input.readings.odometry;
        if let Some(scan) = input.scan {
            let d = self.detector.step(&scan.as_scan()?, &odom)?;
            self.latest = Some(Latest {
                verdict: d.verdict,
                lines: d.lines,
                error: d.error,
                quality: d.quality,
                odom,
                t_s: input.time_s,
            });
        }
        // Stepped every tick so that its projection follows the robot.
        let fallback = self.fallback.step(input);
        let status = self.latest.map(|l| DetectorStatus {
            verdict: l.verdict,
            scanned: input.scan.is_some(),
            age_s: input.time_s - l.t_s,
            quality: l.quality,
            error: l.error,
        });
        let usable = self
            .latest
            .filter(|l| l.verdict.estimate_is_valid())
            .and_then(|l| l.lines.map(|lines| (l.odom, lines)));
        match usable {
            Some((then, lines)) => {
                let error = error_now(&lines, &then, &odom)?;
                let cmd = steering_command(&self.law, &error, Sideslip::ZERO, self.speed)?;
                Ok(Command {
                    steering: cmd.steering.get(),
                    speed: self.speed,
                    mode: Mode::FurrowPursuing,
                    saturated: cmd.saturated,
                    estimated_error: Some(error),
                    sideslip_used: Sideslip::ZERO,
                    detector: status,
                })
            }
            None => fallback.map(|c| Command {
                detector: status,
                ..c
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_moved_by_odometry_gives_the_error_of_the_new_pose() {
        // A row along the odometry x axis at y = 0.5; the robot at (2, 0.1)
        // heading 0.05 rad sees it, then moves to (2.07, 0.104) heading 0.06.
        let row_in = |pose: (f64, f64, f64)| {
            let (c, s) = (pose.2.cos(), pose.2.sin());
            let to_robot = |x: f64, y: f64| {
                let (dx, dy) = (x - pose.0, y - pose.1);
                (c * dx + s * dy, -s * dx + c * dy)
            };
            let (a0, a1) = (to_robot(0.0, 0.5), to_robot(1.0, 0.5));
            let slope = (a1.1 - a0.1) / (a1.0 - a0.0);
            RowLine::new(slope, Meters::new(a0.1 - slope * a0.0).unwrap()).unwrap()
        };
        let then = (2.0, 0.1, 0.05);
        let now = (2.07, 0.104, 0.06);
        let odom = |p: (f64, f64, f64)| Pose2::<Odom>::new(p.0, p.1, p.2).unwrap();
        let e = error_now(&RowLines::One(row_in(then)), &odom(then), &odom(now)).unwrap();
        // The robot is 0.396 m right of the row, heading 0.06 rad left of it.
        assert!((e.y.get() + 0.396).abs() < 1e-12, "{}", e.y.get());
        assert!((e.angular_deviation.get() - 0.06).abs() < 1e-12);
        // Two rows at ±0.375 about y = 0.1: the error to their middle.
        let row_at = |y0: f64, pose: (f64, f64, f64)| {
            let shifted = (pose.0, pose.1 - y0 + 0.5, pose.2);
            row_in(shifted)
        };
        let lines = RowLines::Two(Pair {
            left: row_at(0.475, then),
            right: row_at(-0.275, then),
        });
        let e = error_now(&lines, &odom(then), &odom(now)).unwrap();
        assert!((e.y.get() - 0.004).abs() < 1e-12, "{}", e.y.get());
        assert!((e.angular_deviation.get() - 0.06).abs() < 1e-12);
    }
}
