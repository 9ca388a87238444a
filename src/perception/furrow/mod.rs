//! Furrow pursuing: one or two rows of small plants (or wheel prints) seen by
//! a 2D LiDAR tilted toward the ground (Pierre 2022, section 2.3, eqs. 12-20,
//! with the criteria of section 3, eq. 22 and Table 2; `spec/pierre2022.md`,
//! section "Section 2.3 — Furrow pursuing").
//!
//! One tick of [`FurrowDetector::detect`]:
//!
//! 1. [`scan`]: the rays of a [`Scan`] (the shared LiDAR message, LIB-SCAN)
//!    in an angular window become robot-frame 3D points through the mount
//!    pose (FUR-SCAN);
//! 2. [`correlation`]: their heights above a noise floor (FUR-SIGNAL) are
//!    correlated with a rectangular plant model framed by zeros (FUR-TEMPLATE)
//!    by running sums (FUR-CORRELATION);
//! 3. [`selection`]: local maxima above c_t (FUR-MAXIMA) give the row closest
//!    to the previous one (FUR-SELECT-ONE) or the pair of rows whose spacing
//!    is in [d_min, d_max] and whose middle is closest (FUR-SELECT-PAIR);
//! 4. [`accumulation`]: the selection joins the last ones, kept in the
//!    odometry frame (FUR-ACCUMULATE);
//! 5. [`lines`]: least-squares row lines (FUR-LINE) give the tracking error
//!    (FUR-ERRORS, FUR-TWO-ROWS);
//! 6. [`quality`]: the verdict (FUR-QUALITY).
//!
//! Nothing allocates: the window's rays live in stack arrays of `RAYS`
//! entries, the selections in a `heapless::Deque` of `SCANS` entries.

pub mod accumulation;
pub mod correlation;
pub mod lines;
pub mod quality;
pub mod scan;
pub mod selection;

use heapless::Vec;

use self::accumulation::{Accumulator, Selected};
use self::correlation::{correlate, height_signal, Template};
use self::lines::{
    fit_row_line, fit_row_line_toward, mean_tracking_error, tracking_error, RowLine,
    FIRST_LINE_SPREAD, FIRST_LINE_STRAIGHT,
};
use self::quality::furrow_verdict;
use self::scan::{scan_to_points, MountPose, ScanPoint, ScanWindow, WindowRays};
use self::selection::{
    local_maxima, locate, select_one, select_pair, Maximum, Pair, Spacing, MAX_MAXIMA,
};
use crate::error::{finite, Precondition};
use crate::geometry::carry::{moved_lateral, moved_line_error, straight};
use crate::geometry::frame::{Odom, Point2, Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_angle, Meters, Radians};
use crate::perception::detector::{Detection, Detector, HeldLine};
use crate::perception::{Better, QualityThresholds, Scan, Verdict};

/// How many rows the detector follows (Pierre 2022, sections 2.3.1 and 2.3.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rows {
    /// One row (eq. 14).
    One,
    /// Two rows whose lateral distance lies in `[min_spacing, max_spacing]` m (eq. 17).
    Two {
        /// d_min, m.
        min_spacing: Meters,
        /// d_max, m.
        max_spacing: Meters,
    },
}

/// The furrow detector's parameters as a user writes them; [`FurrowConfig::new`]
/// validates them once. [`FurrowParams::table2`] gives Pierre 2022's Table 2
/// and the library's choices for what the paper leaves open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FurrowParams {
    /// Sensor position forward of O, m.
    pub mount_x: Meters,
    /// Sensor position left of O, m.
    pub mount_y: Meters,
    /// Sensor height above the ground, m (> 0).
    pub mount_height: Meters,
    /// Sensor pitch, rad, positive nose down, in (0, π/2).
    pub mount_pitch: Radians,
    /// Half width a_w of the angular window around the forward axis, rad, in
    /// (0, π/2). The ranges trusted are the sensor's, carried by each [`Scan`].
    pub window_half_angle: Radians,
    /// w_ref: rectangle width in rays (odd, eq. 12).
    pub template_width: usize,
    /// Zero rays framing the rectangle on each side (FUR-TEMPLATE).
    pub template_margin: usize,
    /// h_ref: rectangle height, m (> 0, eq. 12).
    pub template_height: Meters,
    /// Heights at or below this count as ground, m, in [0, h_ref) (FUR-SIGNAL).
    pub height_floor: Meters,
    /// c_t: a maximum must score above this, in (0, 1) (FUR-MAXIMA).
    pub peak_threshold: f64,
    /// One row or two rows.
    pub rows: Rows,
    /// n: how many last selections the lines are fitted to (Table 2: 25 averaged scans).
    pub averaged_scans: usize,
    /// Selections farther than this from the robot are dropped, m (> 0).
    pub keep_distance: Meters,
    /// The least travel the kept selections span, m (≥ 0; 0: the count n
    /// alone, as Table 2): past n, the oldest is kept while the rest span
    /// less, up to the storage `SCANS` (FUR-SPAN).
    pub min_span: Meters,
    /// Fewest points per row line (≥ 2) before a line is fitted.
    pub min_points: usize,
    /// E, m (≥ 0): the extent along x of a row's points from which its line
    /// is the plain least-squares line (FUR-LINE); below it, the robot's
    /// heading weighs in the line's direction (FUR-FIRST-LINE).
    pub min_extent: Meters,
    /// Correlation above which the detection may enter furrow pursuing (Table 2: 0.4).
    pub enter: f64,
    /// Correlation below which the detection must leave it (Table 2: 0.2).
    pub exit: f64,
}

impl FurrowParams {
    /// Table 2 of Pierre 2022 (two rows 0.66-0.9 m apart, template 15 rays ×
    /// 0.3 m, 25 averaged scans, transit at 0.4 / 0.2), with the library's
    /// choices where the paper is silent: sensor 1.5 m ahead of O, 1.0 m high,
    /// pitched 0.38 rad so that it looks at the ground about 4 m ahead of O
    /// ("the Lidar observed about 4 m ahead"), window ±0.35 rad, margins of
    /// 7 rays, noise floor 0.05 m, c_t = 0.5 (above the
    /// score √(3/15) ≈ 0.45 of a grass tuft three rays wide), keep distance
    /// 6 m, lines from 5 points over at least 0.3 m.
    #[must_use]
    pub const fn table2() -> Self {
        Self {
            mount_x: Meters(1.5),
            mount_y: Meters(0.0),
            mount_height: Meters(1.0),
            mount_pitch: Radians(0.38),
            window_half_angle: Radians(0.35),
            template_width: 15,
            template_margin: 7,
            template_height: Meters(0.3),
            height_floor: Meters(0.05),
            peak_threshold: 0.5,
            rows: Rows::Two {
                min_spacing: Meters(0.66),
                max_spacing: Meters(0.9),
            },
            averaged_scans: 25,
            keep_distance: Meters(6.0),
            min_span: Meters(0.0),
            min_points: 5,
            min_extent: Meters(0.3),
            enter: 0.4,
            exit: 0.2,
        }
    }
}

/// The row count as validated.
#[derive(Debug, Clone, Copy, PartialEq)]
enum RowMode {
    One,
    Two(Spacing),
}

/// A validated furrow configuration (FUR-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FurrowConfig {
    params: FurrowParams,
    mount: MountPose,
    window: ScanWindow,
    template: Template,
    rows: RowMode,
    thresholds: QualityThresholds,
}

impl FurrowConfig {
    /// Validates `params` once.
    ///
    /// Errors name the requirement whose precondition fails: `FUR-SCAN` (mount
    /// height ≤ 0, pitch outside (0, π/2), window outside (0, π/2)),
    /// `FUR-TEMPLATE` (even width, height ≤ 0),
    /// `FUR-SIGNAL` (floor outside [0, h_ref)), `FUR-MAXIMA` (c_t outside
    /// (0, 1)), `FUR-SELECT-PAIR` (not `0 < d_min < d_max`), `FUR-ACCUMULATE`
    /// (n = 0, keep distance ≤ 0), `FUR-LINE` (fewer than 2 points, negative
    /// extent), `SW-THRESHOLDS` (entry not above exit).
    //= spec/pierre2022.md#fur-config-configuration-validated-once
    //# A furrow configuration MUST be validated once, at construction, and a
    //# configuration that breaks a precondition of FUR-SCAN, FUR-TEMPLATE,
    //# FUR-SIGNAL, FUR-MAXIMA, FUR-SELECT-PAIR, FUR-ACCUMULATE, FUR-LINE or
    //# SW-THRESHOLDS MUST be refused with an error naming that requirement.
    pub fn new(params: &FurrowParams) -> Result<Self, Precondition> {
        let mount = MountPose::new(
            params.mount_x,
            params.mount_y,
            params.mount_height,
            params.mount_pitch,
        )?;
        let window = ScanWindow::new(params.window_half_angle)?;
        let template = Template::new(
            params.template_width,
            params.template_margin,
            params.template_height,
        )?;
        let floor = params.height_floor.get();
        if !(floor >= 0.0 && floor < params.template_height.get()) {
            return Err(Precondition::new(
                "FUR-SIGNAL",
                "the height floor must lie in [0, h_ref)",
            ));
        }
        let c_t = params.peak_threshold;
        if !(c_t > 0.0 && c_t < 1.0) {
            return Err(Precondition::new(
                "FUR-MAXIMA",
                "the correlation threshold c_t must lie in (0, 1)",
            ));
        }
        let rows = match params.rows {
            Rows::One => RowMode::One,
            Rows::Two {
                min_spacing,
                max_spacing,
            } => RowMode::Two(Spacing::new(min_spacing, max_spacing)?),
        };
        if params.averaged_scans == 0 || params.keep_distance.get() <= 0.0 {
            return Err(Precondition::new(
                "FUR-ACCUMULATE",
                "need n >= 1 kept selections and a keep distance > 0",
            ));
        }
        if params.min_span.get() < 0.0 {
            return Err(Precondition::new("FUR-SPAN", "the span must be >= 0"));
        }
        if params.min_points < 2 || params.min_extent.get() < 0.0 {
            return Err(Precondition::new(
                "FUR-LINE",
                "a row line needs at least 2 points and a non-negative extent",
            ));
        }
        let thresholds = QualityThresholds::new(params.enter, params.exit, Better::Higher)?;
        Ok(Self {
            params: *params,
            mount,
            window,
            template,
            rows,
            thresholds,
        })
    }

    /// The parameters this configuration was built from.
    #[must_use]
    pub const fn params(&self) -> &FurrowParams {
        &self.params
    }

    /// The validated mount pose.
    #[must_use]
    pub const fn mount(&self) -> &MountPose {
        &self.mount
    }

    /// The validated angular window.
    #[must_use]
    pub const fn window(&self) -> &ScanWindow {
        &self.window
    }

    /// The validated plant model.
    #[must_use]
    pub const fn template(&self) -> &Template {
        &self.template
    }

    /// The validated hysteresis thresholds on the weaker maximum's score.
    #[must_use]
    pub const fn thresholds(&self) -> &QualityThresholds {
        &self.thresholds
    }

    /// How far beside O, on flat ground, a row can stand and still be matched
    /// by the whole plant model with its margins inside the window, for a
    /// LiDAR whose rays are `increment` apart (FUR-REACH): the ground y of
    /// the ray at a_w − (w_ref / 2 + margin) increments, h tan α / sin p,
    /// from the mount's y, on the nearer side; 0 when no shift fits.
    ///
    /// # Errors
    /// `FUR-REACH` when `increment` is not positive; `LIB-FINITE` on overflow.
    //= spec/pierre2022.md#fur-reach-lateral-reach-of-the-window
    //# The lateral reach of a furrow configuration for a ray increment Δ MUST be
    //# min(h tan α / sin p − m_y, h tan α / sin p + m_y), at least 0, with α = a_w −
    //# (⌊w_ref / 2⌋ + margin) Δ, h the mount height, p its pitch and m_y its
    //# lateral position; 0 when α ≤ 0.
    pub fn lateral_reach(&self, increment: Radians) -> Result<Meters, Precondition> {
        if increment.get() <= 0.0 {
            return Err(Precondition::new(
                "FUR-REACH",
                "the ray increment must be > 0",
            ));
        }
        let rays = self
            .template
            .half_width()
            .saturating_add(self.template.margin());
        let inset = finite(
            increment.get() * f64::from(u32::try_from(rays).unwrap_or(u32::MAX)),
            "template inset overflows",
        )?;
        let alpha = self.params.window_half_angle.get() - inset;
        if alpha <= 0.0 {
            return Ok(Meters::ZERO);
        }
        let p = &self.params;
        let side = finite(
            p.mount_height.get() * libm::tan(alpha) / libm::sin(p.mount_pitch.get()),
            "lateral reach overflows",
        )?;
        let m_y = p.mount_y.get();
        let reach = (side - m_y).min(side + m_y).max(0.0);
        Meters::new(finite(reach, "lateral reach overflows")?)
    }
}

/// The fitted row lines of one tick, robot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowLines {
    /// The line of the one row followed.
    One(RowLine),
    /// The lines of the left and right rows.
    Two(Pair<RowLine>),
}

impl HeldLine for RowLines {
    /// One row as [`moved_line_error`]; two rows, the mean of both moved
    /// errors, the angles averaged before ψ is added (FUR-ERRORS,
    /// FUR-TWO-ROWS, GD-ODOMETRY).
    fn error_at(&self, pose: &Pose2<Robot>) -> Result<TrackingError, Precondition> {
        match self {
            Self::One(line) => moved_line_error(&tracking_error(line)?, pose),
            Self::Two(Pair { left, right }) => {
                let l = tracking_error(left)?;
                let r = tracking_error(right)?;
                let y = 0.5 * moved_lateral(&l, pose)? + 0.5 * moved_lateral(&r, pose)?;
                let theta = 0.5 * l.angular_deviation.get() + 0.5 * r.angular_deviation.get();
                straight(y, theta + pose.heading.get())
            }
        }
    }
}

/// What one tick of the furrow detector found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FurrowDetection {
    /// The verdict for the switching machine (FUR-QUALITY).
    pub verdict: Verdict,
    /// The robot's error to the row line(s); `None` exactly when the verdict is `Absent`.
    pub error: Option<TrackingError>,
    /// The fitted lines; `None` exactly when the verdict is `Absent`.
    pub lines: Option<RowLines>,
    /// This scan's selection in the robot frame, if any.
    pub selected: Option<Selected<Robot>>,
    /// The weaker score of this scan's selection (the quality graded), if any.
    pub quality: Option<f64>,
    /// How many maxima this scan yielded.
    pub maxima: usize,
    /// Which rays of the scan the window covered.
    pub window: WindowRays,
}

/// The furrow detector: a state machine over scans and odometry poses.
///
/// `RAYS` bounds the rays in the angular window (a wider window is the
/// `FUR-SCAN` error); `SCANS` bounds the selections kept (the configured
/// `averaged_scans` must not exceed it).
#[derive(Debug, Clone)]
pub struct FurrowDetector<const RAYS: usize, const SCANS: usize> {
    config: FurrowConfig,
    accumulator: Accumulator<SCANS>,
    first: FirstLine,
    /// The rows' heading the pipeline expects, odometry frame (the path's,
    /// GD-EXPECTED-HEADING); `None` when it gives none.
    expected: Option<Radians>,
}

/// Where the first line of an accumulation stands (FUR-FIRST-LINE): the
/// odometry heading the rows are taken along, once the robot went straight
/// over `min_points` selections; whether the accumulation has been full
/// since it was last empty (then a first line only from points spanning the
/// minimum extent); how many selections were kept since it was last empty;
/// and whether the first line has ended (its points spanned E once the
/// accumulation was full, or twice its capacity were kept).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct FirstLine {
    heading: Option<Radians>,
    filled: bool,
    kept: usize,
    spanned: bool,
}

impl<const RAYS: usize, const SCANS: usize> FurrowDetector<RAYS, SCANS> {
    /// A detector with nothing accumulated.
    ///
    /// Errors with `FUR-ACCUMULATE` when `averaged_scans` exceeds `SCANS`.
    pub fn new(config: FurrowConfig) -> Result<Self, Precondition> {
        let accumulator =
            Accumulator::new(config.params.averaged_scans, config.params.keep_distance)?
                .with_span(config.params.min_span)?;
        Ok(Self {
            config,
            accumulator,
            first: FirstLine::default(),
            expected: None,
        })
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &FurrowConfig {
        &self.config
    }

    /// How many selections are accumulated.
    #[must_use]
    pub fn accumulated(&self) -> usize {
        self.accumulator.len()
    }

    /// Forgets every accumulated selection: the next selection is a first one (t = 0).
    pub fn reset(&mut self) {
        self.accumulator.clear();
        self.first = FirstLine::default();
    }

    /// The maxima of one scan (steps 1 to 3 of the module doc), without
    /// touching the detector's state. Errors with `FUR-SCAN` when the scan's
    /// angles do not grow with the ray index (increment ≤ 0) or its window
    /// holds more than `RAYS` rays.
    pub fn maxima(
        &self,
        scan: &Scan<'_>,
    ) -> Result<(Vec<Maximum, MAX_MAXIMA>, WindowRays), Precondition> {
        let mut rays: [Option<ScanPoint>; RAYS] = [None; RAYS];
        let window = scan_to_points(scan, &self.config.mount, &self.config.window, &mut rays)?;
        let rays = rays.get(..window.count).unwrap_or_default();
        let mut signal = [0.0_f64; RAYS];
        let floor = self.config.params.height_floor;
        for (s, ray) in signal.iter_mut().zip(rays) {
            *s = height_signal(ray.map(|p| p.height), floor);
        }
        let signal = signal.get(..window.count).unwrap_or_default();
        let mut scores = [0.0_f64; RAYS];
        correlate(signal, &self.config.template, &mut scores)?;
        let scores = scores.get(..window.count).unwrap_or_default();
        let template = &self.config.template;
        let mut maxima = Vec::new();
        for k in local_maxima(
            scores,
            self.config.params.peak_threshold,
            template.half_width(),
        ) {
            let score = scores.get(k).copied().unwrap_or(0.0);
            if let Some(point) = locate(k, rays, signal, template) {
                let _ = maxima.push(Maximum {
                    ray: k,
                    score,
                    point,
                });
            }
        }
        Ok((maxima, window))
    }

    /// One tick: detects the rows in `scan`, seen at odometry pose `odom`,
    /// updates the accumulated selections, fits the row lines and grades the
    /// detection (steps 1 to 6 of the module doc).
    ///
    /// Errors with `FUR-SCAN` when the scan's angles do not grow with the ray
    /// index (increment ≤ 0) or its window holds more than `RAYS` rays (the
    /// state is then left as it was); `LIB-FINITE` only on overflow of a transformed point.
    pub fn detect(
        &mut self,
        scan: &Scan<'_>,
        odom: &Pose2<Odom>,
    ) -> Result<FurrowDetection, Precondition> {
        let (maxima, window) = self.maxima(scan)?;
        self.accumulator.forget_far(odom);
        if self.accumulator.is_empty() {
            self.first = FirstLine::default();
        }
        let previous = self.accumulator.newest(odom);
        let reference_y = previous.map_or(0.0, |p| p.reference().y());
        let (selected, quality) = match self.config.rows {
            RowMode::One => match select_one(&maxima, reference_y) {
                Some(m) => (Some(Selected::One(m.point)), Some(m.score)),
                None => (None, None),
            },
            RowMode::Two(spacing) => match select_pair(&maxima, &spacing, reference_y) {
                // Scores of the correlation are finite: `weaker_score` cannot fail here.
                Some(p) => (Some(Selected::Two(p.points())), p.weaker_score().ok()),
                None => (None, None),
            },
        };
        if let Some(s) = &selected {
            self.accumulator.push(s, odom)?;
            self.first.kept = self.first.kept.saturating_add(1);
        }
        self.settle_first_line(odom);
        let estimate = self.estimate(odom);
        let verdict = furrow_verdict(&self.config.thresholds, estimate.is_some(), quality);
        Ok(FurrowDetection {
            verdict,
            error: estimate.map(|(e, _)| e),
            lines: estimate.map(|(_, l)| l),
            selected,
            quality,
            maxima: maxima.len(),
            window,
        })
    }

    /// Updates the first line's state after this tick's selection
    /// (FUR-FIRST-LINE): the accumulation is marked filled once it holds
    /// `averaged_scans` selections, and the first line ends once it is filled
    /// and its selections span E along x, or once twice `averaged_scans`
    /// were kept; until filled, the first time the robot
    /// turned at most [`FIRST_LINE_STRAIGHT`] over its last `min_points`
    /// selections, the newest one's heading is kept for the first line.
    //= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
    //# The first-line heading MUST be the odometry heading of the newest kept
    //# selection at the first tick at which the robot's heading changed by at
    //# most 0.01 rad over its last `min_points` kept selections.
    //= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
    //# While the points span less than the minimum extent, the detector MUST give
    //# no line before the first-line heading is set, and none once the accumulation
    //# has held its capacity of selections since it was last empty.
    //= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
    //# The first line MUST be given from the tick the first-line heading is set
    //# until the first tick, after the accumulation has held its capacity, at which
    //# the kept selections' reference points span E along x, or at which twice its
    //# capacity of selections have been kept since it was last empty; after that,
    //# the line MUST be FUR-LINE's.
    fn settle_first_line(&mut self, odom: &Pose2<Odom>) {
        if self.accumulator.len() >= self.config.params.averaged_scans {
            self.first.filled = true;
        }
        if self.first.filled && !self.first.spanned {
            let (lo, hi) = self
                .accumulator
                .in_robot_frame(odom)
                .map(|s| s.reference().x())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                });
            let e = self.config.params.min_extent.get().max(FIRST_LINE_SPREAD);
            let twice = self.config.params.averaged_scans.saturating_mul(2);
            self.first.spanned = hi - lo >= e || self.first.kept >= twice;
        }
        if self.first.filled || self.first.heading.is_some() {
            return;
        }
        let straight = self
            .accumulator
            .recent_turn(self.config.params.min_points)
            .is_some_and(|turn| libm::fabs(turn.get()) <= FIRST_LINE_STRAIGHT);
        //= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
        //# When an expected heading was given before the scan, the first-line
        //# heading MUST be that heading instead.
        if straight {
            self.first.heading = self.expected.or_else(|| self.accumulator.newest_heading());
        }
    }

    /// Sets the rows' heading expected in the odometry frame (the path's,
    /// GD-EXPECTED-HEADING), or `None`: the first line is taken along it
    /// rather than along the robot's heading (FUR-FIRST-LINE).
    pub fn expect_heading(&mut self, heading: Option<Radians>) {
        self.expected = heading;
    }

    /// The row lines and tracking error from the accumulated selections, or
    /// `None` while they are too few or too short for a regression.
    fn estimate(&self, odom: &Pose2<Odom>) -> Option<(TrackingError, RowLines)> {
        match self.config.rows {
            RowMode::One => {
                let line = self.row_line(odom, |s| match s {
                    Selected::One(p) => Some(p),
                    Selected::Two(_) => None,
                })?;
                Some((tracking_error(&line).ok()?, RowLines::One(line)))
            }
            RowMode::Two(_) => {
                let left = self.row_line(odom, |s| match s {
                    Selected::Two(p) => Some(p.left),
                    Selected::One(_) => None,
                })?;
                let right = self.row_line(odom, |s| match s {
                    Selected::Two(p) => Some(p.right),
                    Selected::One(_) => None,
                })?;
                Some((
                    mean_tracking_error(&left, &right).ok()?,
                    RowLines::Two(Pair { left, right }),
                ))
            }
        }
    }

    /// The line through the accumulated points that `pick` takes from each
    /// selection, once there are `min_points` of them: the least-squares line
    /// (FUR-LINE) once they span `min_extent` in x; before that, the first
    /// line, its direction drawn toward the heading kept by
    /// [`Self::settle_first_line`] (FUR-FIRST-LINE).
    fn row_line(
        &self,
        odom: &Pose2<Odom>,
        pick: impl Fn(Selected<Robot>) -> Option<Point2<Robot>>,
    ) -> Option<RowLine> {
        // At most one point per kept selection, and at most SCANS are kept.
        let mut points = Vec::<Point2<Robot>, SCANS>::new();
        for p in self.accumulator.in_robot_frame(odom).filter_map(pick) {
            let _ = points.push(p);
        }
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.x()), hi.max(p.x()))
            });
        if points.len() < self.config.params.min_points {
            return None;
        }
        let min_extent = self.config.params.min_extent;
        let spread_enough = hi - lo >= min_extent.get();
        // The first line once the robot went straight over `min_points`
        // selections, until the points spanned E after the accumulation was
        // full (from then on, or before the heading, the plain fit).
        let heading = match self.first.heading {
            Some(h) if !self.first.spanned && (!self.first.filled || spread_enough) => h,
            _ => return spread_enough.then(|| fit_row_line(points.iter()).ok())?,
        };
        let direction = wrap_angle(Radians::new(heading.get() - odom.heading.get()).ok()?);
        // Past the capacity n, the prior's weight fades as (1 − k/n)² over
        // the next k selections, its last steps small:
        // E'² − D² = w (E² − D²) gives Λ' = w Λ.
        //= spec/pierre2022.md#fur-first-line-a-row-line-from-its-first-points
        //# Once the accumulation has held its capacity c, Λ MUST be multiplied by
        //# (1 − k/c)², k the number of selections kept beyond c since it was last empty.
        let e = min_extent.get().max(FIRST_LINE_SPREAD);
        let n = self.config.params.averaged_scans;
        let beyond = self.first.kept.saturating_sub(n);
        let count = |k: usize| u32::try_from(k).map_or(f64::from(u32::MAX), f64::from);
        let weight = if n == 0 {
            0.0
        } else {
            let left = (1.0 - count(beyond) / count(n)).clamp(0.0, 1.0);
            left * left
        };
        let d = hi - lo;
        let faded = libm::sqrt(d * d + weight * (e * e - d * d).max(0.0));
        let spread = Meters::new(faded).ok()?;
        fit_row_line_toward(points.iter(), direction, spread).ok()
    }
}

impl<const RAYS: usize, const SCANS: usize> Detector for FurrowDetector<RAYS, SCANS> {
    type Config = FurrowConfig;
    type Line = RowLines;

    fn configure(config: &FurrowConfig) -> Result<Self, Precondition> {
        Self::new(*config)
    }

    fn observe(
        &mut self,
        scan: &Scan<'_>,
        odometry: &Pose2<Odom>,
    ) -> Result<Detection<RowLines>, Precondition> {
        let d = self.detect(scan, odometry)?;
        Ok(Detection {
            verdict: d.verdict,
            error: d.error,
            quality: d.quality,
            line: d.lines,
            ahead: None,
        })
    }

    fn expect_heading(&mut self, heading: Option<Radians>) {
        FurrowDetector::expect_heading(self, heading);
    }
}
