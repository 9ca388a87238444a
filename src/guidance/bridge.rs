//! Regular gaps bridged by the held line (`spec/guidance.md`, GD-BRIDGE):
//! across trunks, posts and short gaps, the active behaviour keeps steering
//! on a line carried by odometry instead of handing the command to path
//! tracking and flipping modes. The line carried is the structure's line
//! (GD-BRIDGE-STEADY): the least-squares straight line through the points
//! the valid detections of the last bridge length put on the followed line,
//! and a valid detection that disagrees with it (the bent line of a ragged
//! end of a piece) is bridged over like a gap. While it is carried, the
//! next piece's line seen ahead (EDGE-LOOK-AHEAD) levels it: the structure
//! line is shifted sideways through that line's point (GD-BRIDGE-LEVEL).

use heapless::Deque;

use crate::geometry::carry::moved_line_error;
use crate::geometry::carry::pose_in_scan_frame;
use crate::geometry::carry::straight;
use crate::geometry::frame::{Odom, Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_raw, Meters};
use crate::perception::Detection;

/// The most anchors kept: two bridge lengths at [`ANCHORS_PER_BRIDGE`].
const ANCHOR_CAPACITY: usize = 32;

/// Anchors per bridge length: one is kept every `bridge / 16` of odometry.
const ANCHORS_PER_BRIDGE: f64 = 16.0;

/// The fewest anchors of a structure line.
const MIN_ANCHORS: f64 = 3.0;

/// The structure line is fitted to the anchors of this many bridge lengths
/// of odometry up to the newest one (GD-BRIDGE-STEADY).
const WINDOW_BRIDGES: f64 = 2.0;

/// The fewest bridge lengths the anchors of a structure line must span
/// (GD-BRIDGE-STEADY).
const MIN_SPAN_BRIDGES: f64 = 0.25;

/// The weight of the heading prior (GD-BRIDGE-PRIOR) in squared bridge
/// lengths: Σ(u − ū)² of anchors spread evenly over one bridge length at
/// [`ANCHORS_PER_BRIDGE`], n L² / 12 = 16 / 12.
const PRIOR_WEIGHT_BRIDGES2: f64 = ANCHORS_PER_BRIDGE / 12.0;

/// The largest angle between the path's heading and the anchors' own line
/// for the path's heading to be a prior (GD-BRIDGE-PRIOR), rad.
const PRIOR_RAD: f64 = 0.3;

/// Anchors farther than this from the first fit are outliers, left out of
/// the refit (GD-BRIDGE-STEADY), m.
const OUTLIER_M: f64 = 0.15;

/// The largest difference in lateral error, at the robot, between a valid
/// detection and the structure line for the detection to agree with it
/// (GD-BRIDGE-AGREE), m.
pub(super) const AGREE_M: f64 = 0.15;

/// The largest difference in angular deviation between a valid detection
/// and the structure line for the detection to agree with it
/// (GD-BRIDGE-AGREE), rad.
pub(super) const AGREE_RAD: f64 = 0.15;

/// A behaviour's latest valid detection (Enter or Hold, steady): its
/// tracking error at its scan's pose, where the robot was then, and the
/// odometry distance since.
#[derive(Debug, Clone, Copy)]
struct LastValid {
    error: TrackingError,
    odom: Pose2<Odom>,
    travelled: f64,
}

/// The point a valid detection puts on the followed line, abeam the robot,
/// with that line's heading, odometry frame, and the odometer reading then.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Anchor {
    x: f64,
    y: f64,
    heading: f64,
    at: f64,
}

impl Anchor {
    /// The foot on the line of the robot at `odom`, its error being `error`:
    /// the line's heading is φ = h − θ̃, and the robot lies y to its left.
    fn of(error: &TrackingError, odom: &Pose2<Odom>, at: f64) -> Self {
        let heading = odom.heading.get() - error.angular_deviation.get();
        let y = error.y.get();
        Self {
            x: odom.position.x() + y * libm::sin(heading),
            y: odom.position.y() - y * libm::cos(heading),
            heading,
            at,
        }
    }
}

/// A straight line of the odometry frame: a point and a heading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StructureLine {
    x: f64,
    y: f64,
    heading: f64,
}

impl StructureLine {
    /// The error of the robot at `odom` to this line: y its signed left
    /// distance, θ̃ = wrap(h − φ).
    fn error_at(&self, odom: &Pose2<Odom>) -> Option<TrackingError> {
        let (s, c) = (libm::sin(self.heading), libm::cos(self.heading));
        let (dx, dy) = (odom.position.x() - self.x, odom.position.y() - self.y);
        straight(-dx * s + dy * c, odom.heading.get() - self.heading).ok()
    }
}

/// What the tick's scan did to a behaviour's line.
#[derive(Debug, Clone, Copy)]
pub(super) enum ScanOutcome<'a, L> {
    /// No scan in this tick.
    None,
    /// The detector read the scan.
    Read(&'a Detection<L>),
    /// The detector refused the scan.
    Refused,
}

/// A behaviour's bridge: its last valid line and the anchors of its valid
/// detections (GD-BRIDGE, GD-BRIDGE-STEADY).
#[derive(Debug, Clone, Default)]
pub(super) struct Bridge {
    last: Option<LastValid>,
    anchors: Deque<Anchor, ANCHOR_CAPACITY>,
    odometer: f64,
    /// Whether the latest scan was a valid detection that disagreed with
    /// the structure line (GD-BRIDGE-AGREE): held until the next scan.
    disagreed: bool,
    /// The latest point of the next piece's line seen ahead, odometry frame
    /// (GD-BRIDGE-LEVEL): the carried structure line passes through it.
    level: Option<Pose2<Odom>>,
    /// `Some` when the scan of this tick put an anchor, which the plan
    /// check may take back (GD-BRIDGE-PLAN), holding the oldest anchor
    /// dropped to make room for it, if one was.
    anchored: Option<Option<Anchor>>,
    /// The path's heading in the odometry frame (GD-EXPECTED-HEADING), the
    /// structure line's heading prior (GD-BRIDGE-PRIOR); `None` without one.
    prior: Option<f64>,
}

impl Bridge {
    /// Updates the bridge after a tick whose odometry pose is `odometry`,
    /// the robot having moved `travelled` metres since the previous tick: a
    /// valid detection becomes an anchor, and the last valid line when it
    /// agrees with the structure line (GD-BRIDGE-AGREE); a refused scan ends both
    /// (a failing sensor is not a gap), otherwise the distance grows.
    /// Returns `true` while the latest scan (this tick's or the one held
    /// since) was a valid detection that disagreed with the structure line:
    /// bridged over like a gap until the next scan.
    pub(super) fn record<L>(
        &mut self,
        scan: ScanOutcome<'_, L>,
        odometry: &Pose2<Odom>,
        travelled: f64,
        bridge: Meters,
    ) -> bool {
        self.odometer += travelled;
        self.anchored = None;
        if let Some(l) = self.last.as_mut() {
            l.travelled += travelled;
        }
        if !matches!(scan, ScanOutcome::None) {
            self.disagreed = false;
        }
        match scan {
            ScanOutcome::Read(d) if d.verdict.estimate_is_valid() => {
                if let Some(error) = d.error {
                    self.disagreed = self.disagrees(&error, odometry, bridge);
                    if !self.disagreed {
                        self.level = None;
                        self.last = Some(LastValid {
                            error,
                            odom: *odometry,
                            travelled: 0.0,
                        });
                    }
                    self.push(Anchor::of(&error, odometry, self.odometer), bridge);
                }
            }
            ScanOutcome::Refused => {
                self.last = None;
                self.anchors.clear();
                self.level = None;
            }
            ScanOutcome::Read(d) => {
                if let Some(ahead) = &d.ahead {
                    self.level = self.level_of(ahead, odometry, bridge);
                }
            }
            ScanOutcome::None => {}
        }
        //= spec/guidance.md#gd-bridge-level-the-next-piece-s-line-levels-the-structure-line
        //# The level MUST be cleared by a valid detection that becomes the
        //# latest valid line (GD-BRIDGE-AGREE), by a refused scan, and whenever
        //# there is no latest valid line within the bridge length.
        if self
            .last
            .as_ref()
            .is_none_or(|l| l.travelled > bridge.get())
        {
            self.level = None;
        }
        self.disagreed
    }

    /// Sets the structure line's heading prior, the path's heading in the
    /// odometry frame (GD-BRIDGE-PRIOR), or none.
    pub(super) fn expect_heading(&mut self, heading: Option<f64>) {
        self.prior = heading;
    }

    /// Takes back the anchor the scan of this tick put, if it put one, and
    /// restores the oldest one it displaced: its line is not consistent
    /// with the plan (GD-BRIDGE-PLAN).
    pub(super) fn take_back_anchor(&mut self) {
        if let Some(displaced) = self.anchored.take() {
            self.anchors.pop_back();
            if let Some(oldest) = displaced {
                // Cannot fail: the slot was freed just above.
                let _ = self.anchors.push_front(oldest);
            }
        }
    }

    /// The level after a scan that saw the next piece's line `ahead` in the
    /// robot frame of its pose `odometry`: that line moved to the odometry
    /// frame, unless its heading disagrees with the structure line's by
    /// more than [`AGREE_RAD`] (then the level is kept as it was).
    //= spec/guidance.md#gd-bridge-level-the-next-piece-s-line-levels-the-structure-line
    //# A scan whose detection reports the next piece's line ahead
    //# (EDGE-LOOK-AHEAD) MUST set the level to that line's point and heading
    //# moved to the odometry frame at the scan's pose, replacing the previous
    //# level, unless there is a structure line whose heading differs from that
    //# heading by more than 0.15 rad.
    fn level_of(
        &self,
        ahead: &Pose2<Robot>,
        odometry: &Pose2<Odom>,
        bridge: Meters,
    ) -> Option<Pose2<Odom>> {
        let level = odometry.body_to_frame::<Robot>().apply_pose(*ahead).ok()?;
        let agrees = self
            .structure(bridge)
            .is_none_or(|s| libm::fabs(wrap_raw(level.heading.get() - s.heading)) <= AGREE_RAD);
        if agrees {
            Some(level)
        } else {
            self.level
        }
    }

    /// Whether `error`, a valid detection's error at `odometry`, differs
    /// from the structure line's there by more than [`AGREE_M`] laterally or
    /// [`AGREE_RAD`] in heading, while the bridge could carry that line (its
    /// last valid line at most `bridge` metres back). Without a structure
    /// line, or past the bridge, every detection agrees.
    //= spec/guidance.md#gd-bridge-agree-a-line-that-disagrees-with-the-structure-line-is-bridged
    //# While the bridge could carry the structure line (GD-BRIDGE-STEADY), a
    //# valid detection whose tracking error at the current pose differs from
    //# the structure line's by more than 0.15 m in lateral error or by more
    //# than 0.15 rad in angular deviation MUST NOT become the latest valid
    //# line; it still puts its anchor.
    fn disagrees(&self, error: &TrackingError, odometry: &Pose2<Odom>, bridge: Meters) -> bool {
        if self
            .last
            .as_ref()
            .is_none_or(|l| l.travelled > bridge.get())
        {
            return false;
        }
        let Some(held) = self.structure(bridge).and_then(|s| s.error_at(odometry)) else {
            return false;
        };
        let dy = libm::fabs(error.y.get() - held.y.get());
        let dt = libm::fabs(wrap_raw(
            error.angular_deviation.get() - held.angular_deviation.get(),
        ));
        !(dy <= AGREE_M && dt <= AGREE_RAD)
    }

    //= spec/guidance.md#gd-bridge-steady-the-structure-line-carried-across-a-gap
    //# Every valid detection of a behaviour MUST put an anchor on its line: the
    //# foot of the robot's perpendicular on the followed line, with the line's
    //# heading and the odometry distance, in the odometry frame, one anchor kept
    //# per sixteenth of the bridge length.
    /// Keeps `anchor` when it lies at least `bridge / 16` of odometry after
    /// the newest one, dropping the oldest when full.
    fn push(&mut self, anchor: Anchor, bridge: Meters) {
        let spacing = bridge.get() / ANCHORS_PER_BRIDGE;
        if self
            .anchors
            .back()
            .is_some_and(|b| anchor.at - b.at < spacing)
        {
            return;
        }
        let displaced = if self.anchors.is_full() {
            self.anchors.pop_front()
        } else {
            None
        };
        // Cannot fail: a slot was freed above when full.
        if self.anchors.push_back(anchor).is_ok() {
            self.anchored = Some(displaced);
        }
    }

    /// The structure line `line` shifted sideways through the level's
    /// point, its heading kept (GD-BRIDGE-LEVEL); `line` without a level.
    //= spec/guidance.md#gd-bridge-level-the-next-piece-s-line-levels-the-structure-line
    //# While the bridge carries the structure line (GD-BRIDGE-STEADY) and a
    //# level is set, the line carried MUST be the structure line shifted
    //# sideways through the level's point, its heading kept.
    fn levelled(&self, line: StructureLine) -> StructureLine {
        match &self.level {
            Some(level) => StructureLine {
                x: level.position.x(),
                y: level.position.y(),
                ..line
            },
            None => line,
        }
    }

    //= spec/guidance.md#gd-bridge-steady-the-structure-line-carried-across-a-gap
    //# The structure line MUST be the
    //# least-squares straight line through the anchors within two bridge lengths of
    //# odometry up to the newest one, refitted once without the anchors farther
    //# than 0.15 m from the first fit.
    /// The structure line (GD-BRIDGE-STEADY): the least-squares straight
    /// line through the anchors of two `bridge` lengths of odometry up to the
    /// newest one, fitted in the newest anchor's frame, then refitted
    /// without the anchors farther than 0.15 m from it, its slope pulled
    /// towards the path's heading when there is one (GD-BRIDGE-PRIOR);
    /// `None` with fewer than 3 anchors or a span under a quarter of `bridge`.
    //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
    //# When the pipeline has a path heading (GD-EXPECTED-HEADING), both fits
    //# of the structure line (GD-BRIDGE-STEADY) MUST minimise, over the slope
    //# m and the offset q of the line v = m u + q in the newest anchor's frame
    //# (u along its heading, v to its left), the sum of the squared residuals
    //# v − m u − q of their anchors plus W (m − m₀)², with m₀ the slope of the
    //# path's heading in that frame and W = 4 b² / 3, b the bridge length.
    fn structure(&self, bridge: Meters) -> Option<StructureLine> {
        let newest = *self.anchors.back()?;
        let (s, c) = (libm::sin(newest.heading), libm::cos(newest.heading));
        let from = newest.at - WINDOW_BRIDGES * bridge.get();
        let frame = |a: &Anchor| {
            let (dx, dy) = (a.x - newest.x, a.y - newest.y);
            (dx * c + dy * s, -dx * s + dy * c)
        };
        let window = || self.anchors.iter().filter(|a| a.at >= from).map(frame);
        //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
        //# A path heading more than 0.3 rad from the heading of the anchors'
        //# own least-squares line MUST NOT be used.
        let plain = fit(window(), bridge, None, None)?;
        let prior = self.prior.and_then(|h| {
            let along = wrap_raw(h - newest.heading);
            (libm::fabs(wrap_raw(along - libm::atan(plain.0))) <= PRIOR_RAD).then(|| {
                (
                    libm::tan(along),
                    PRIOR_WEIGHT_BRIDGES2 * bridge.get() * bridge.get(),
                )
            })
        });
        let first = if prior.is_some() {
            fit(window(), bridge, None, prior)?
        } else {
            plain
        };
        let (slope, intercept) = fit(window(), bridge, Some(first), prior)?;
        let line = StructureLine {
            x: newest.x - intercept * s,
            y: newest.y + intercept * c,
            heading: wrap_raw(newest.heading + libm::atan(slope)),
        };
        (line.x.is_finite() && line.y.is_finite() && line.heading.is_finite()).then_some(line)
    }

    /// The error to carry to `odometry` and the distance since the last
    /// valid line, while that distance is at most `bridge` (GD-BRIDGE): the
    /// error to the structure line (GD-BRIDGE-STEADY), else to the last
    /// valid line carried straight; `None` beyond it, without a line, or
    /// when moving it overflows.
    //= spec/guidance.md#gd-bridge-regular-gaps-bridged-by-the-held-line
    //# When a bridge length is configured, a tick in which the behaviour of the
    //# active specialised mode has no valid estimate MUST report Hold with the
    //# tracking error of that behaviour's latest scan with an Enter or Hold verdict,
    //# moved to the current pose through odometry as the error to a straight line
    //# (GD-ODOMETRY), as long as the odometry distance summed over the ticks since
    //# that scan is at most the bridge length and no scan of that behaviour was
    //# refused since; otherwise, and for a behaviour that is not active, the
    //# estimate MUST be that of GD-SCAN-AGE.
    //= spec/guidance.md#gd-bridge-steady-the-structure-line-carried-across-a-gap
    //# While the valid detections of that behaviour put at least 3 anchors
    //# spanning at least a quarter of the bridge length within two bridge
    //# lengths of odometry up to the newest anchor, the line carried MUST be the
    //# structure line instead of the latest valid line.
    pub(super) fn carried(
        &self,
        odometry: &Pose2<Odom>,
        bridge: Meters,
    ) -> Option<(TrackingError, Meters)> {
        let last = self.last.as_ref()?;
        if last.travelled > bridge.get() {
            return None;
        }
        let error = match self
            .structure(bridge)
            .map(|s| self.levelled(s))
            .and_then(|s| s.error_at(odometry))
        {
            Some(error) => error,
            None => {
                let pose = pose_in_scan_frame(&last.odom, odometry).ok()?;
                moved_line_error(&last.error, &pose).ok()?
            }
        };
        Some((error, Meters::new(last.travelled).ok()?))
    }
}

/// The least-squares line v = m u + q through `points` (u along the newest
/// anchor's heading, v to its left), leaving out the points farther than
/// 0.15 m from `first` when given, with the pseudo-observation m = m₀ of
/// weight W when `prior` is (m₀, W) (GD-BRIDGE-PRIOR): the normal equations
/// (Σu² + W) m + Σu q = Σuv + W m₀ and Σu m + n q = Σv. `None` with fewer
/// than 3 points, a span of less than a quarter of `bridge`, or a
/// degenerate fit.
fn fit(
    points: impl Iterator<Item = (f64, f64)>,
    bridge: Meters,
    first: Option<(f64, f64)>,
    prior: Option<(f64, f64)>,
) -> Option<(f64, f64)> {
    let (mut n, mut su, mut sv, mut suu, mut suv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for (u, v) in points {
        if first.is_some_and(|(m, q)| (v - m * u - q).abs() > OUTLIER_M) {
            continue;
        }
        n += 1.0;
        su += u;
        sv += v;
        suu += u * u;
        suv += u * v;
        low = low.min(u);
        high = high.max(u);
    }
    if n < MIN_ANCHORS || high - low < MIN_SPAN_BRIDGES * bridge.get() {
        return None;
    }
    //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
    //# Without a path heading, the fits MUST be those of GD-BRIDGE-STEADY
    //# alone.
    let (m0, w) = prior.unwrap_or((0.0, 0.0));
    let denominator = n * (suu + w) - su * su;
    if denominator.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
        return None;
    }
    let slope = (n * (suv + w * m0) - su * sv) / denominator;
    Some((slope, (sv - slope * su) / n))
}

#[cfg(test)]
mod tests {
    //! The structure line (GD-BRIDGE-STEADY): anchors of a straight edge
    //! seen with noisy headings and a bent piece end give the true line.

    use super::*;
    use crate::error::Precondition;
    use crate::perception::Verdict;

    /// A valid detection of error (y, θ̃).
    fn valid(y: f64, theta: f64) -> Detection<()> {
        Detection {
            verdict: Verdict::Hold,
            error: straight(y, theta).ok(),
            quality: Some(0.02),
            line: Some(()),
            ahead: None,
        }
    }

    /// A bridge of 4 m after 6 m of detections of the x axis, the bridge
    /// length and the last pose.
    fn along_the_x_axis() -> Result<(Bridge, Meters, Pose2<Odom>), Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        let last = drive(&mut bridge, length, 6.0, |_, _| (0.0, 0.0))?;
        Ok((bridge, length, last))
    }

    /// A scan graded Exit (a piece's end) that saw the next piece's line
    /// `ahead` (EDGE-LOOK-AHEAD).
    fn exit_seeing(ahead: Pose2<Robot>) -> Detection<()> {
        Detection {
            verdict: Verdict::Exit,
            ahead: Some(ahead),
            ..valid(0.4, 0.5)
        }
    }

    /// The robot driving along x at lateral `y_of(x)` and heading `h`,
    /// detecting a line along the x axis: the detection's error is the
    /// truth plus `noise(k)` in offset and heading.
    fn drive(
        bridge: &mut Bridge,
        length: Meters,
        to: f64,
        noise: impl Fn(f64, bool) -> (f64, f64),
    ) -> Result<Pose2<Odom>, Precondition> {
        let step = 0.04;
        let mut pose = Pose2::new(0.0, 0.0, 0.0)?;
        for k in 0_u16..=u16::MAX {
            let x = step * f64::from(k);
            if x > to {
                break;
            }
            let y = 0.1 * libm::sin(x);
            let heading = 0.1 * libm::cos(x);
            pose = Pose2::new(x, y, heading)?;
            let (dy, dt) = noise(x, k % 2 == 0);
            let d = valid(y * libm::cos(heading) + dy, heading + dt);
            bridge.record(ScanOutcome::Read(&d), &pose, step, length);
        }
        Ok(pose)
    }

    //= spec/guidance.md#gd-bridge-steady-the-structure-line-carried-across-a-gap
    //= type=test
    //# The structure line MUST be the
    //# least-squares straight line through the anchors within two bridge lengths of
    //# odometry up to the newest one, refitted once without the anchors farther
    //# than 0.15 m from the first fit.
    //= spec/guidance.md#gd-bridge-steady-the-structure-line-carried-across-a-gap
    //= type=test
    //# Every valid detection of a behaviour MUST put an anchor on its line: the
    //# foot of the robot's perpendicular on the followed line, with the line's
    //# heading and the odometry distance, in the odometry frame, one anchor kept
    //# per sixteenth of the bridge length.
    #[test]
    fn noisy_headings_and_a_bent_piece_end_give_the_true_line() -> Result<(), Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        // Headings off by ±0.12 rad scan to scan, offsets by ±2 cm, and the
        // last 0.3 m a piece end bent 0.25 m off.
        let last = drive(&mut bridge, length, 6.0, |x, even| {
            let sign = if even { 1.0 } else { -1.0 };
            let bend = if x > 5.7 { 0.25 } else { 0.0 };
            (0.02 * sign + bend, 0.12 * sign)
        })?;
        // One anchor per 0.25 m (7 steps of 0.04 m) over 6 m.
        assert_eq!(bridge.anchors.len(), 22);
        let ats: heapless::Vec<f64, ANCHOR_CAPACITY> =
            bridge.anchors.iter().map(|a| a.at).collect();
        assert!(ats.windows(2).all(|w| matches!(w, [a, b] if b - a >= 0.25)));
        let line = bridge
            .structure(length)
            .ok_or_else(|| Precondition::new("T", "no line"))?;
        assert!(line.heading.abs() < 0.01, "{line:?}");
        for x in [2.0, 6.0] {
            let y = line.y + (x - line.x) * libm::tan(line.heading);
            assert!(y.abs() < 0.02, "{line:?}");
        }
        // Carried 2 m on: the error is the truth's, not the bent end's.
        let ahead = Pose2::new(last.position.x() + 2.0, 0.3, 0.05)?;
        let (error, _) = bridge
            .carried(&ahead, length)
            .ok_or_else(|| Precondition::new("T", "not carried"))?;
        assert!((error.y.get() - 0.3).abs() < 0.03, "{error:?}");
        assert!(
            (error.angular_deviation.get() - 0.05).abs() < 0.01,
            "{error:?}"
        );
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-steady-the-structure-line-carried-across-a-gap
    //= type=test
    //# While the valid detections of that behaviour put at least 3 anchors
    //# spanning at least a quarter of the bridge length within two bridge
    //# lengths of odometry up to the newest anchor, the line carried MUST be the
    //# structure line instead of the latest valid line.
    #[test]
    fn too_short_a_span_carries_the_latest_line() -> Result<(), Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        // 0.8 m of detections (a fifth of the bridge), the last one 0.2 rad off.
        let last = drive(&mut bridge, length, 0.8, |x, _| {
            if x >= 0.8 - 1e-9 {
                (0.0, 0.2)
            } else {
                (0.0, 0.0)
            }
        })?;
        assert!(bridge.structure(length).is_none());
        let (error, _) = bridge
            .carried(&last, length)
            .ok_or_else(|| Precondition::new("T", "not carried"))?;
        assert!(
            (error.angular_deviation.get() - (0.1 * libm::cos(last.position.x()) + 0.2)).abs()
                < 1e-9
        );
        // A refused scan clears the anchors and the line.
        bridge.record(ScanOutcome::<()>::Refused, &last, 0.04, length);
        assert!(bridge.anchors.is_empty() && bridge.carried(&last, length).is_none());
        Ok(())
    }

    /// The structure line's heading after `to` metres of detections of
    /// the line through the origin at 0.05 rad to the x axis, with the path's
    /// heading along x given or not (GD-BRIDGE-PRIOR).
    fn tilted_structure(to: f64, path: Option<f64>) -> Result<f64, Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        bridge.expect_heading(path);
        // The line y = x tan(0.05): the robot lies y − x tan(0.05) to its
        // left (times its cosine), and the line's heading is 0.05 rad.
        let tilt = 0.05_f64;
        drive(&mut bridge, length, to, |x, _| {
            (-x * libm::tan(tilt) * libm::cos(tilt), -tilt)
        })?;
        bridge
            .structure(length)
            .map(|s| s.heading)
            .ok_or_else(|| Precondition::new("T", "no line"))
    }

    //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
    //= type=test
    //# When the pipeline has a path heading (GD-EXPECTED-HEADING), both fits
    //# of the structure line (GD-BRIDGE-STEADY) MUST minimise, over the slope
    //# m and the offset q of the line v = m u + q in the newest anchor's frame
    //# (u along its heading, v to its left), the sum of the squared residuals
    //# v − m u − q of their anchors plus W (m − m₀)², with m₀ the slope of the
    //# path's heading in that frame and W = 4 b² / 3, b the bridge length.
    //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
    //= type=test
    //# Without a path heading, the fits MUST be those of GD-BRIDGE-STEADY
    //# alone.
    #[test]
    fn the_path_heading_holds_a_short_line_and_yields_to_a_long_one() -> Result<(), Precondition> {
        // 1.5 m of anchors (three eighths of the 4 m bridge) along a line
        // 0.05 rad off the path: without the path's heading the structure
        // line takes the anchors' 0.05 rad; with it, its data weigh
        // Σ(u − ū)² ≈ 1.6 m² against W = 21.3 m², so it keeps the path's
        // heading within 0.005 rad.
        let plain = tilted_structure(1.5, None)?;
        assert!((plain - 0.05).abs() < 1e-3, "{plain}");
        let held = tilted_structure(1.5, Some(0.0))?;
        assert!(held.abs() < 0.005, "{held}");
        // Over two bridge lengths (8 m, Σ(u − ū)² ≈ 160 m²) the anchors win:
        // the line is within 0.007 rad of theirs, and a path heading on the
        // line's own side of it moves it the other way.
        let long = tilted_structure(8.0, Some(0.0))?;
        assert!((long - 0.05).abs() < 0.007 && long < 0.05, "{long}");
        let beyond = tilted_structure(8.0, Some(0.1))?;
        assert!(beyond > 0.05 && beyond - 0.05 < 0.007, "{beyond}");
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
    //= type=test
    //# A path heading more than 0.3 rad from the heading of the anchors'
    //# own least-squares line MUST NOT be used.
    #[test]
    fn a_path_across_the_structure_is_no_prior() -> Result<(), Precondition> {
        // Anchors 0.05 rad off x over 1.5 m: a path 0.15 rad from them
        // pulls the line; one beyond 0.3 rad, or across it, leaves the
        // anchors' own line.
        let plain = tilted_structure(1.5, None)?;
        let near = tilted_structure(1.5, Some(0.2))?;
        assert!(near > 0.15, "{near}");
        for path in [0.46, -0.4, 1.6, core::f64::consts::PI] {
            let line = tilted_structure(1.5, Some(path))?;
            assert!((line - plain).abs() < 1e-12, "{path}: {line} {plain}");
        }
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-prior-the-path-s-heading-steadies-a-short-structure-line
    //= type=test
    //# When the pipeline has a path heading (GD-EXPECTED-HEADING), both fits
    //# of the structure line (GD-BRIDGE-STEADY) MUST minimise, over the slope
    //# m and the offset q of the line v = m u + q in the newest anchor's frame
    //# (u along its heading, v to its left), the sum of the squared residuals
    //# v − m u − q of their anchors plus W (m − m₀)², with m₀ the slope of the
    //# path's heading in that frame and W = 4 b² / 3, b the bridge length.
    #[test]
    fn the_fit_minimises_the_residuals_and_the_prior() -> Result<(), Precondition> {
        let bridge = Meters::new(4.0)?;
        let points = [
            (-3.0, 0.02),
            (-2.1, -0.05),
            (-1.4, 0.11),
            (-0.6, 0.04),
            (0.0, 0.09),
        ];
        let (m0, w) = (-0.03, 4.0 / 3.0 * 16.0);
        let cost = |m: f64, q: f64| {
            points
                .iter()
                .map(|(u, v)| (v - m * u - q).powi(2))
                .sum::<f64>()
                + w * (m - m0).powi(2)
        };
        let (m, q) = fit(points.iter().copied(), bridge, None, Some((m0, w)))
            .ok_or_else(|| Precondition::new("T", "no fit"))?;
        let best = cost(m, q);
        for (dm, dq) in [
            (1e-3, 0.0),
            (-1e-3, 0.0),
            (0.0, 1e-3),
            (0.0, -1e-3),
            (1e-3, -1e-3),
        ] {
            assert!(cost(m + dm, q + dq) > best, "({dm}, {dq})");
        }
        // Without the prior, the plain least-squares line, another one.
        let (m1, _) = fit(points.iter().copied(), bridge, None, None)
            .ok_or_else(|| Precondition::new("T", "no fit"))?;
        assert!((m1 - m).abs() > 0.01, "{m1} {m}");
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-agree-a-line-that-disagrees-with-the-structure-line-is-bridged
    //= type=test
    //# While the bridge could carry the structure line (GD-BRIDGE-STEADY), a
    //# valid detection whose tracking error at the current pose differs from
    //# the structure line's by more than 0.15 m in lateral error or by more
    //# than 0.15 rad in angular deviation MUST NOT become the latest valid
    //# line; it still puts its anchor.
    //= spec/guidance.md#gd-bridge-agree-a-line-that-disagrees-with-the-structure-line-is-bridged
    //= type=test
    //# Until the behaviour's next scan, the
    //# behaviour of the active specialised mode MUST then report Hold with the
    //# error of GD-BRIDGE, as for a scan that found nothing.
    #[test]
    fn a_piece_end_line_is_bridged_and_still_anchored() -> Result<(), Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        let last = drive(&mut bridge, length, 6.0, |_, _| (0.0, 0.0))?;
        let before = bridge.last.map(|l| l.odom);
        let anchors = bridge.anchors.len();
        // One more step: the piece end's line, 0.4 m and 0.5 rad off.
        let next = |dx: f64| {
            Pose2::new(
                last.position.x() + dx,
                0.1 * libm::sin(last.position.x() + dx),
                0.1 * libm::cos(last.position.x() + dx),
            )
        };
        let pose = next(0.3)?;
        let truth =
            |p: &Pose2<Odom>| (p.position.y() * libm::cos(p.heading.get()), p.heading.get());
        let (y, theta) = truth(&pose);
        assert!(bridge.record(
            ScanOutcome::Read(&valid(y + 0.4, theta - 0.5)),
            &pose,
            0.3,
            length
        ));
        assert_eq!(bridge.last.map(|l| l.odom), before);
        assert_eq!(bridge.anchors.len(), anchors + 1);
        // Until the next scan the flag holds, and what is carried is the
        // structure line: the truth, not the piece end's line.
        let pose = next(0.34)?;
        assert!(bridge.record(ScanOutcome::<()>::None, &pose, 0.04, length));
        let (error, _) = bridge
            .carried(&pose, length)
            .ok_or_else(|| Precondition::new("T", "not carried"))?;
        let (y, theta) = truth(&pose);
        assert!((error.y.get() - y).abs() < 0.02, "{error:?}");
        assert!(
            (error.angular_deviation.get() - theta).abs() < 0.02,
            "{error:?}"
        );
        // Lines just inside both bounds agree and become the latest line.
        let pose = next(0.38)?;
        let (y, theta) = truth(&pose);
        assert!(!bridge.record(
            ScanOutcome::Read(&valid(y + 0.13, theta - 0.13)),
            &pose,
            0.04,
            length
        ));
        assert_eq!(bridge.last.map(|l| l.odom), Some(pose));
        // Either bound alone makes a line disagree.
        for (dy, dt) in [(0.17, 0.0), (0.0, 0.17), (-0.17, 0.0), (0.0, -0.17)] {
            let mut copy = bridge.clone();
            assert!(copy.record(
                ScanOutcome::Read(&valid(y + dy, theta + dt)),
                &pose,
                0.0,
                length
            ));
        }
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-agree-a-line-that-disagrees-with-the-structure-line-is-bridged
    //= type=test
    //# While the bridge could carry the structure line (GD-BRIDGE-STEADY), a
    //# valid detection whose tracking error at the current pose differs from
    //# the structure line's by more than 0.15 m in lateral error or by more
    //# than 0.15 rad in angular deviation MUST NOT become the latest valid
    //# line; it still puts its anchor.
    #[test]
    fn past_the_bridge_length_every_line_is_taken_again() -> Result<(), Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        let last = drive(&mut bridge, length, 6.0, |_, _| (0.0, 0.0))?;
        // 4.5 m of scans that found nothing: the bridge has lapsed.
        let pose = Pose2::new(last.position.x() + 4.5, 0.0, 0.0)?;
        assert!(!bridge.record(ScanOutcome::<()>::None, &pose, 4.5, length));
        assert!(bridge.carried(&pose, length).is_none());
        // A line 0.4 m off the old structure line is taken: a structure
        // that really moved is followed.
        assert!(!bridge.record(ScanOutcome::Read(&valid(0.4, 0.0)), &pose, 0.04, length));
        assert_eq!(bridge.last.map(|l| l.odom), Some(pose));
        // A refused scan clears the flag with the rest.
        bridge.record(ScanOutcome::Read(&valid(5.0, 0.0)), &pose, 0.04, length);
        assert!(!bridge.record(ScanOutcome::<()>::Refused, &pose, 0.04, length));
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-plan-only-lines-consistent-with-the-plan-anchor-the-structure-line
    //= type=test
    //# The anchor of a valid detection whose line is not consistent with the
    //# plan in its tick (GD-PLAN, GD-PLAN-ENTRY) MUST be taken back once that
    //# tick's plan consistency is known, so that it takes no part in the
    //# structure line of the later ticks.
    #[test]
    fn an_anchor_taken_back_leaves_the_structure_line_as_it_was() -> Result<(), Precondition> {
        let length = Meters::new(4.0)?;
        let mut bridge = Bridge::default();
        let last = drive(&mut bridge, length, 3.0, |_, _| (0.0, 0.0))?;
        let (n, newest) = (bridge.anchors.len(), bridge.anchors.back().map(|a| a.at));
        // A line 0.3 m off, one spacing further: anchored, then taken back.
        let pose = Pose2::new(last.position.x() + 0.3, 0.0, 0.0)?;
        bridge.record(ScanOutcome::Read(&valid(0.3, 0.0)), &pose, 0.3, length);
        assert_eq!(bridge.anchors.len(), n + 1);
        bridge.take_back_anchor();
        assert_eq!(bridge.anchors.len(), n);
        assert_eq!(bridge.anchors.back().map(|a| a.at), newest);
        // Once only: a second call in the same tick takes nothing more.
        bridge.take_back_anchor();
        assert_eq!(bridge.anchors.len(), n);
        // A tick without a scan put no anchor: nothing to take back.
        let later = Pose2::new(pose.position.x() + 0.3, 0.0, 0.0)?;
        bridge.record(ScanOutcome::<()>::None, &later, 0.3, length);
        bridge.take_back_anchor();
        assert_eq!(bridge.anchors.len(), n);
        // With every slot taken, the oldest anchor dropped for the new one
        // comes back with the take-back.
        let far = drive(&mut bridge, length, 12.0, |_, _| (0.0, 0.0))?;
        assert_eq!(bridge.anchors.len(), ANCHOR_CAPACITY);
        let oldest = bridge.anchors.front().map(|a| a.at);
        let end = Pose2::new(far.position.x() + 0.3, 0.0, 0.0)?;
        bridge.record(ScanOutcome::Read(&valid(0.3, 0.0)), &end, 0.3, length);
        assert_ne!(bridge.anchors.front().map(|a| a.at), oldest);
        bridge.take_back_anchor();
        assert_eq!(bridge.anchors.len(), ANCHOR_CAPACITY);
        assert_eq!(bridge.anchors.front().map(|a| a.at), oldest);
        let later = Pose2::new(end.position.x() + 0.3, 0.0, 0.0)?;
        // A scan too close to the newest anchor put none either.
        bridge.record(ScanOutcome::Read(&valid(0.0, 0.0)), &later, 0.01, length);
        let kept = bridge.anchors.len();
        bridge.record(ScanOutcome::Read(&valid(0.0, 0.0)), &later, 0.01, length);
        bridge.take_back_anchor();
        assert_eq!(bridge.anchors.len(), kept);
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-level-the-next-piece-s-line-levels-the-structure-line
    //= type=test
    //# A scan whose detection reports the next piece's line ahead
    //# (EDGE-LOOK-AHEAD) MUST set the level to that line's point and heading
    //# moved to the odometry frame at the scan's pose, replacing the previous
    //# level, unless there is a structure line whose heading differs from that
    //# heading by more than 0.15 rad.
    //= spec/guidance.md#gd-bridge-level-the-next-piece-s-line-levels-the-structure-line
    //= type=test
    //# While the bridge carries the structure line (GD-BRIDGE-STEADY) and a
    //# level is set, the line carried MUST be the structure line shifted
    //# sideways through the level's point, its heading kept.
    #[test]
    fn the_line_ahead_moves_the_carried_line_through_its_point() -> Result<(), Precondition> {
        let (mut bridge, length, last) = along_the_x_axis()?;
        let line = bridge
            .structure(length)
            .ok_or_else(|| Precondition::new("T", "no line"))?;
        // In the gap, a scan sees the next piece's line 2 m ahead and 0.25 m
        // to the left, its heading 0.1 rad off the robot's.
        let pose = Pose2::new(last.position.x() + 0.3, 0.05, 0.02)?;
        let ahead = Pose2::<Robot>::new(2.0, 0.25, 0.1)?;
        bridge.record(ScanOutcome::Read(&exit_seeing(ahead)), &pose, 0.3, length);
        let level = pose.body_to_frame::<Robot>().apply_pose(ahead)?;
        assert_eq!(bridge.level, Some(level));
        // Carried 1 m on: the structure line's heading, through the level.
        let on = Pose2::new(pose.position.x() + 1.0, 0.1, -0.03)?;
        bridge.record(ScanOutcome::<()>::None, &on, 1.0, length);
        let (error, _) = bridge
            .carried(&on, length)
            .ok_or_else(|| Precondition::new("T", "not carried"))?;
        let (sin, cos) = (libm::sin(line.heading), libm::cos(line.heading));
        let (dx, dy) = (
            on.position.x() - level.position.x(),
            on.position.y() - level.position.y(),
        );
        assert!(
            (error.y.get() - (-dx * sin + dy * cos)).abs() < 1e-9,
            "{error:?}"
        );
        assert!(
            (error.angular_deviation.get() - wrap_raw(on.heading.get() - line.heading)).abs()
                < 1e-9,
            "{error:?}"
        );
        // The unlevelled line lies as far from it as the level's point
        // from the structure line: 0.25 m seen from the scan, 0.34 m here.
        let plain = line
            .error_at(&on)
            .ok_or_else(|| Precondition::new("T", "no error"))?;
        let apart = line
            .error_at(&level)
            .ok_or_else(|| Precondition::new("T", "no error"))?;
        assert!((apart.y.get() - 0.34).abs() < 0.01, "{apart:?}");
        assert!((plain.y.get() - error.y.get() - apart.y.get()).abs() < 1e-9);
        // A line ahead 0.2 rad off the structure line's heading is not
        // taken: the level stays.
        let askew = Pose2::<Robot>::new(2.0, -0.3, 0.2 + 0.03)?;
        bridge.record(ScanOutcome::Read(&exit_seeing(askew)), &on, 0.0, length);
        assert_eq!(bridge.level, Some(level));
        // One within 0.15 rad replaces it.
        let close = Pose2::<Robot>::new(2.0, -0.1, 0.1)?;
        bridge.record(ScanOutcome::Read(&exit_seeing(close)), &on, 0.0, length);
        assert_eq!(
            bridge.level,
            Some(on.body_to_frame::<Robot>().apply_pose(close)?)
        );
        Ok(())
    }

    //= spec/guidance.md#gd-bridge-level-the-next-piece-s-line-levels-the-structure-line
    //= type=test
    //# The level MUST be cleared by a valid detection that becomes the
    //# latest valid line (GD-BRIDGE-AGREE), by a refused scan, and whenever
    //# there is no latest valid line within the bridge length.
    #[test]
    fn the_level_ends_with_an_agreeing_line_a_refused_scan_or_the_bridge(
    ) -> Result<(), Precondition> {
        let (bridge, length, last) = along_the_x_axis()?;
        let pose = Pose2::new(last.position.x() + 0.3, 0.0, 0.0)?;
        let ahead = Pose2::<Robot>::new(2.0, 0.25, 0.0)?;
        let seeing = exit_seeing(ahead);
        let mut set = bridge.clone();
        set.record(ScanOutcome::Read(&seeing), &pose, 0.3, length);
        assert!(set.level.is_some());
        // A disagreeing valid line (0.3 m off) keeps it.
        let mut copy = set.clone();
        assert!(copy.record(ScanOutcome::Read(&valid(0.3, 0.0)), &pose, 0.0, length));
        assert!(copy.level.is_some());
        // An agreeing one ends it: the structure line is carried again.
        let mut copy = set.clone();
        assert!(!copy.record(ScanOutcome::Read(&valid(0.0, 0.0)), &pose, 0.0, length));
        assert_eq!(copy.level, None);
        copy.record(ScanOutcome::<()>::None, &pose, 0.0, length);
        let line = copy
            .structure(length)
            .ok_or_else(|| Precondition::new("T", "no line"))?;
        assert_eq!(
            copy.carried(&pose, length).map(|(e, _)| e),
            line.error_at(&pose)
        );
        // A refused scan ends it.
        let mut copy = set.clone();
        copy.record(ScanOutcome::<()>::Refused, &pose, 0.0, length);
        assert_eq!(copy.level, None);
        // So does the bridge's end: 4.5 m without a valid line.
        let mut copy = set.clone();
        let far = Pose2::new(pose.position.x() + 4.5, 0.0, 0.0)?;
        copy.record(ScanOutcome::<()>::None, &far, 4.5, length);
        assert_eq!(copy.level, None);
        // A line ahead seen past the bridge sets none.
        copy.record(ScanOutcome::Read(&seeing), &far, 0.0, length);
        assert_eq!(copy.level, None);
        Ok(())
    }
}
