//! A specialised behaviour (edge following, furrow pursuing) with path
//! tracking on the recorded path standing in while its detector has no usable
//! estimate: the logic both behaviours share, written once.
//!
//! # The stand-in for switching
//!
//! Behaviour switching (Pierre 2022, section 3: transit delays, the state
//! machine) is issue 5's. Until then [`Specialised`] selects the behaviour by
//! the latest scan's verdict alone, with no delay: the specialised behaviour
//! while it is Enter or Hold (an estimate that may be used), path tracking
//! while it is Exit or Absent (no line, or a line that must not be used).
//! Path tracking is stepped every tick, in charge or not, so its projection
//! follows the robot.
//!
//! # Between scans
//!
//! A detector steps on its LiDAR's scan ticks (10 Hz in the built-in
//! scenarios) while the control loop runs every control period (50 Hz). On
//! the ticks between two scans, the latest scan's lines, fitted in the robot
//! frame of that scan, are moved into the current robot frame through the
//! odometry poses of both ticks, and the error to them is recomputed. No
//! command is ever made from a scan older than the latest one, nor from a
//! verdict of Exit or Absent: [`DetectorStatus`] records which scan each
//! command came from.
//!
//! # The law
//!
//! Backstepping (eqs. 2-7) with the behaviour's own gains and speed, no
//! sideslip and no prediction: the detected line is straight, so
//! c(s) = c(s + vT) = 0 (sections 2.2 and 2.3: "this version of the control
//! law does not include an estimation of sideslip angles").

use fieldguide::control::backstepping::{steering_command, BacksteppingConfig};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::perception::furrow::lines::{mean_tracking_error, tracking_error, RowLine};
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::perception::furrow::RowLines;
use fieldguide::{
    Meters, MetersPerSecond, Odom, Point2, Pose2, Precondition, Robot, TrackingError, Verdict,
};

use super::{Command, DetectorStatus, Guidance, Mode, PathTracking, TickInput};

/// What a detector concluded from one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection {
    /// The verdict for the switching machine.
    pub verdict: Verdict,
    /// The detector's quality measure, if it has one (see [`DetectorStatus::quality`]).
    pub quality: Option<f64>,
    /// The detector's tracking error at the scan, if it fitted a line.
    pub error: Option<TrackingError>,
    /// The lines to follow in the robot frame of the scan, if any: one line
    /// (one row, or the line kept at the desired distance from an edge) or
    /// two rows whose middle is followed.
    pub lines: Option<RowLines>,
}

/// A detector seen from the stand-in: it senses on its scan ticks.
pub trait Sensing {
    /// The mode recorded while this behaviour is in charge.
    const MODE: Mode;

    /// The detection of this tick's scan, `None` on ticks without one. An
    /// error is a violated precondition of the core; the run stops there.
    fn sense(&mut self, input: &TickInput<'_>) -> Result<Option<Detection>, Precondition>;
}

/// The latest scan's detection, with the odometry pose of its robot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Latest {
    detection: Detection,
    /// Odometry pose of the scan: the frame the lines are expressed in.
    odom: Pose2<Odom>,
    t_s: f64,
}

/// A specialised behaviour with path tracking standing in while its detector
/// has no usable line (see the module documentation).
#[derive(Debug, Clone)]
pub struct Specialised<'p, S> {
    sensing: S,
    law: BacksteppingConfig,
    speed: MetersPerSecond,
    fallback: PathTracking<'p>,
    latest: Option<Latest>,
}

impl<'p, S: Sensing> Specialised<'p, S> {
    /// The behaviour of `sensing` driving `law` at `speed`, with `fallback`
    /// in charge while the verdict is Exit or Absent.
    #[must_use]
    pub fn with_sensing(
        sensing: S,
        law: BacksteppingConfig,
        speed: MetersPerSecond,
        fallback: PathTracking<'p>,
    ) -> Self {
        Self {
            sensing,
            law,
            speed,
            fallback,
            latest: None,
        }
    }

    /// The detector's side.
    #[must_use]
    pub const fn sensing(&self) -> &S {
        &self.sensing
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
/// robot at odometry pose `now` (FUR-ERRORS for one line, FUR-TWO-ROWS for two).
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

impl<S: Sensing> Guidance for Specialised<'_, S> {
    fn step(&mut self, input: &TickInput<'_>) -> Result<Command, Precondition> {
        let odom = input.readings.odometry;
        let detection = self.sensing.sense(input)?;
        let scanned = detection.is_some();
        if let Some(detection) = detection {
            self.latest = Some(Latest {
                detection,
                odom,
                t_s: input.time_s,
            });
        }
        // Stepped every tick so that its projection follows the robot.
        let fallback = self.fallback.step(input);
        let status = self.latest.map(|l| DetectorStatus {
            verdict: l.detection.verdict,
            scanned,
            age_s: input.time_s - l.t_s,
            quality: l.detection.quality,
            error: l.detection.error,
        });
        let usable = self
            .latest
            .filter(|l| l.detection.verdict.estimate_is_valid())
            .and_then(|l| l.detection.lines.map(|lines| (l.odom, lines)));
        match usable {
            Some((then, lines)) => {
                let error = error_now(&lines, &then, &odom)?;
                let cmd = steering_command(&self.law, &error, Sideslip::ZERO, self.speed)?;
                Ok(Command {
                    steering: cmd.steering.get(),
                    speed: self.speed,
                    mode: S::MODE,
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
