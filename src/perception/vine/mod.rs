//! Vine-row detection on an inclined 2D LiDAR (Iberraken 2022, section 2.1,
//! eqs. 1-4 and Table 1; `spec/iberraken2022.md`, VINE-*).
//!
//! One tick of [`VineDetector::detect`]:
//!
//! 1. the rays within the field of view [−30°, 30°] become robot-frame 3D
//!    points through the mount pose (VINE-SCAN, the conversion of furrow
//!    pursuing's [`scan_to_points`]);
//! 2. [`ground`]: a RANSAC line through the terrain profile, and each point's
//!    height above it, a noise floor applied (VINE-GROUND, VINE-SIGNAL);
//! 3. [`correlation`]: the Pearson correlation of eq. 1 with the square vine
//!    model at every offset, by running sums (VINE-MODEL, VINE-CORRELATION);
//!    local maxima above the threshold are candidates (VINE-CANDIDATES);
//! 4. [`aggregation`]: the candidate closest laterally to the newest
//!    set-point (eq. 2) joins the set-points, kept in the odometry frame
//!    (VINE-AGGREGATE);
//! 5. the row line by least squares through the set-points, and the
//!    deviations of eqs. 3-4 (VINE-LINE); the verdict (VINE-VERDICT).
//!
//! Nothing allocates: the rays of the field of view live in stack arrays of
//! `RAYS` entries, the set-points in a `heapless::Deque` of `POINTS`.

pub mod aggregation;
pub mod correlation;
pub mod ground;

use heapless::Vec;
use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro128PlusPlus;

use self::aggregation::{lateral_deviation, SetPoint, SetPoints};
use self::correlation::{correlate, VineModel};
use self::ground::{fit_ground, Ground, GroundParams};
use crate::error::Precondition;
use crate::geometry::carry::moved_line_error;
use crate::geometry::frame::{Odom, Point2, Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{Meters, Radians};
use crate::perception::detector::{Detection, Detector, HeldLine};
use crate::perception::furrow::correlation::height_signal;
use crate::perception::furrow::lines::{fit_row_line, tracking_error, RowLine};
use crate::perception::furrow::scan::{scan_to_points, MountPose, ScanPoint, ScanWindow};
use crate::perception::furrow::selection::{local_maxima, MAX_MAXIMA};
use crate::perception::{Better, QualityThresholds, Scan, Verdict};

/// The vine detector's parameters as a user writes them;
/// [`VineConfig::new`] validates them once. [`VineParams::summer`] and
/// [`VineParams::winter`] give Table 1 of Iberraken 2022 and the library's
/// choices for what the paper leaves open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineParams {
    /// Sensor position forward of R, m (Table 1: 1.0).
    pub mount_x: Meters,
    /// Sensor position left of R, m (Table 1: 0).
    pub mount_y: Meters,
    /// Sensor height above the ground, m (Table 1: 2.0).
    pub mount_height: Meters,
    /// Sensor pitch, rad, nose down (Table 1: 45°).
    pub mount_pitch: Radians,
    /// Half the field of view, rad (section 2.1.1: 30°).
    pub half_fov: Radians,
    /// The model's width, rays (Table 1: 10 summer, 5 winter).
    pub model_width: usize,
    /// Rays of ground on each side of the model.
    pub model_margin: usize,
    /// The model's height, m (Table 1: 1.0).
    pub model_height: Meters,
    /// Levelled heights at or below this count as ground, m.
    pub height_floor: Meters,
    /// A maximum is a candidate above this score (Table 1: 0.25).
    pub threshold: f64,
    /// RANSAC hypotheses per scan.
    pub ransac_iterations: usize,
    /// RANSAC inlier distance, m.
    pub ransac_tolerance: Meters,
    /// Fewest inliers of a ground profile.
    pub ransac_min_inliers: usize,
    /// Steepest cross slope |dz/dy| taken for ground.
    pub max_cross_slope: f64,
    /// The seed of the detector's generator.
    pub seed: u64,
    /// A candidate joins when eq. 2's deviation is at most this, m.
    pub max_deviation: Meters,
    /// With no set-point yet, the first one must lie within this lateral
    /// distance of the robot, m.
    pub first_lateral: Meters,
    /// Set-points farther than this from the robot are dropped, m.
    pub keep_distance: Meters,
    /// Fewest set-points (≥ 2) before the line is fitted.
    pub min_points: usize,
    /// Shortest extent along x of the set-points before the line is fitted, m.
    pub min_extent: Meters,
    /// Mean set-point score above which the detection may enter vine following.
    pub enter: f64,
    /// Mean set-point score below which it must leave.
    pub exit: f64,
}

impl VineParams {
    /// Table 1 (summer): model 10 rays × 1.0 m, threshold 0.25, LiDAR at
    /// (1.0, 0, 2.0) m pitched 45°, field of view ±30°; the library's
    /// choices: margins of one model width, floor 0.2 m, 32 RANSAC
    /// iterations, 5 cm tolerance, 20 inliers, cross slope up to 0.4, joining
    /// within 0.25 m, first set-point within 1.0 m, kept over 5 m, a line
    /// from 5 set-points over 0.5 m, verdict at mean scores 0.5 / 0.35.
    #[must_use]
    pub const fn summer() -> Self {
        Self {
            mount_x: Meters(1.0),
            mount_y: Meters(0.0),
            mount_height: Meters(2.0),
            mount_pitch: Radians(core::f64::consts::FRAC_PI_4),
            half_fov: Radians(core::f64::consts::FRAC_PI_6),
            model_width: 10,
            model_margin: 10,
            model_height: Meters(1.0),
            height_floor: Meters(0.2),
            threshold: 0.25,
            ransac_iterations: 32,
            ransac_tolerance: Meters(0.05),
            ransac_min_inliers: 20,
            max_cross_slope: 0.4,
            seed: 20_220_922,
            max_deviation: Meters(0.25),
            first_lateral: Meters(1.0),
            keep_distance: Meters(5.0),
            min_points: 5,
            min_extent: Meters(0.5),
            enter: 0.5,
            exit: 0.35,
        }
    }

    /// Table 1 (winter): as [`VineParams::summer`] with a model 5 rays wide
    /// and margins of 5 rays.
    #[must_use]
    pub const fn winter() -> Self {
        let mut p = Self::summer();
        p.model_width = 5;
        p.model_margin = 5;
        p
    }
}

/// A validated vine configuration (VINE-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineConfig {
    params: VineParams,
    mount: MountPose,
    window: ScanWindow,
    model: VineModel,
    ground: GroundParams,
    thresholds: QualityThresholds,
}

impl VineConfig {
    /// Validates `params` once.
    ///
    /// # Errors
    /// `FUR-SCAN` (mount height ≤ 0, pitch or half field of view outside
    /// (0, π/2)), `VINE-MODEL`, `VINE-SIGNAL` (floor outside [0, h)),
    /// `VINE-CANDIDATES` (threshold outside (0, 1)), `VINE-GROUND`,
    /// `VINE-AGGREGATE` (deviations or keep distance not positive),
    /// `VINE-LINE` (fewer than 2 points, negative extent), `SW-THRESHOLDS`.
    //= spec/iberraken2022.md#vine-config-configuration-validated-once
    //# A vine configuration MUST be validated once, at construction, and a
    //# configuration that breaks a precondition of VINE-SCAN, VINE-MODEL,
    //# VINE-SIGNAL, VINE-CANDIDATES, VINE-GROUND, VINE-AGGREGATE, VINE-LINE or
    //# SW-THRESHOLDS MUST be refused with an error naming that requirement.
    pub fn new(params: &VineParams) -> Result<Self, Precondition> {
        let mount = MountPose::new(
            params.mount_x,
            params.mount_y,
            params.mount_height,
            params.mount_pitch,
        )?;
        let window = ScanWindow::new(params.half_fov)?;
        let model = VineModel::new(params.model_width, params.model_margin, params.model_height)?;
        let floor = params.height_floor.get();
        if !(floor >= 0.0 && floor < params.model_height.get()) {
            return Err(Precondition::new(
                "VINE-SIGNAL",
                "the height floor must lie in [0, model height)",
            ));
        }
        if !(params.threshold > 0.0 && params.threshold < 1.0) {
            return Err(Precondition::new(
                "VINE-CANDIDATES",
                "the correlation threshold must lie in (0, 1)",
            ));
        }
        let ground = GroundParams::new(
            params.ransac_iterations,
            params.ransac_tolerance.get(),
            params.ransac_min_inliers,
            params.max_cross_slope,
        )?;
        if params.max_deviation.get() <= 0.0
            || params.first_lateral.get() <= 0.0
            || params.keep_distance.get() <= 0.0
        {
            return Err(Precondition::new(
                "VINE-AGGREGATE",
                "deviation bounds and keep distance must be > 0",
            ));
        }
        if params.min_points < 2 || params.min_extent.get() < 0.0 {
            return Err(Precondition::new(
                "VINE-LINE",
                "a row line needs at least 2 points and a non-negative extent",
            ));
        }
        let thresholds = QualityThresholds::new(params.enter, params.exit, Better::Higher)?;
        Ok(Self {
            params: *params,
            mount,
            window,
            model,
            ground,
            thresholds,
        })
    }

    /// The parameters this configuration was built from.
    #[must_use]
    pub const fn params(&self) -> &VineParams {
        &self.params
    }

    /// The validated vine model.
    #[must_use]
    pub const fn model(&self) -> &VineModel {
        &self.model
    }

    /// The validated RANSAC parameters.
    #[must_use]
    pub const fn ground(&self) -> &GroundParams {
        &self.ground
    }

    /// The validated hysteresis thresholds on the mean set-point score.
    #[must_use]
    pub const fn thresholds(&self) -> &QualityThresholds {
        &self.thresholds
    }
}

/// The row line of one tick, `y = a x + b` in the robot frame of its scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineLine(pub RowLine);

impl HeldLine for VineLine {
    /// The deviations of eqs. 3-4 moved by odometry (GD-ODOMETRY).
    fn error_at(&self, pose: &Pose2<Robot>) -> Result<TrackingError, Precondition> {
        moved_line_error(&row_deviation(&self.0)?, pose)
    }
}

/// The lateral and angular deviations of the robot to the row line
/// (Iberraken 2022, eqs. 3-4), with the line fitted in the robot frame (the
/// robot at the origin, heading 0) and the library's signs:
/// y = −b / sqrt(a² + 1), θ̃ = −arctan(a).
///
/// # Errors
/// `LIB-FINITE` on overflow.
//= spec/iberraken2022.md#vine-line-row-line-and-deviations
//# The deviations MUST be y = −(a X − Y + b) / sqrt(a² + 1) and
//# θ̃ = θ − arctan(a) for the line y = a x + b and the robot at (X, Y) with
//# yaw θ in the frame of the line; with the line in the robot frame,
//# y = −b / sqrt(a² + 1) and θ̃ = −arctan(a).
pub fn row_deviation(line: &RowLine) -> Result<TrackingError, Precondition> {
    tracking_error(line)
}

/// A candidate of one scan: a local maximum of the correlation above the
/// threshold, located in the robot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// The offset k of the maximum (the model's first ray in the field of view).
    pub offset: usize,
    /// Its score r(k).
    pub score: f64,
    /// The vine's position: the mean ground position of the top of the run
    /// of rays matched (VINE-CANDIDATES), robot frame.
    pub point: Point2<Robot>,
}

/// What one tick of the vine detector found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineDetection {
    /// The verdict for the switching machine (VINE-VERDICT).
    pub verdict: Verdict,
    /// The robot's error to the row line; `None` exactly when Absent.
    pub error: Option<TrackingError>,
    /// The row line; `None` exactly when Absent.
    pub line: Option<VineLine>,
    /// The mean score of the kept set-points, when there are any.
    pub quality: Option<f64>,
    /// The ground profile found, or too few inliers.
    pub ground: Ground,
    /// How many candidates this scan gave.
    pub candidates: usize,
    /// The candidate that joined the set-points this scan, if any.
    pub joined: Option<Candidate>,
    /// How many set-points are kept.
    pub set_points: usize,
}

/// The vine detector: a state machine over scans and odometry poses, with
/// its seeded generator.
///
/// `RAYS` bounds the rays in the field of view (a wider one is the
/// `FUR-SCAN` error); `POINTS` is the set-points' capacity.
#[derive(Debug, Clone)]
pub struct VineDetector<const RAYS: usize, const POINTS: usize> {
    config: VineConfig,
    rng: Xoshiro128PlusPlus,
    set_points: SetPoints<POINTS>,
}

impl<const RAYS: usize, const POINTS: usize> VineDetector<RAYS, POINTS> {
    /// A detector with no set-point, its generator seeded from the
    /// configuration.
    ///
    /// `POINTS` must be at least 1 (a capacity of 0 does not compile).
    ///
    /// # Errors
    /// `VINE-LINE` when `min_points` exceeds `POINTS`.
    pub fn new(config: VineConfig) -> Result<Self, Precondition> {
        if config.params.min_points > POINTS {
            return Err(Precondition::new(
                "VINE-LINE",
                "min_points exceeds the set-points' capacity",
            ));
        }
        Ok(Self {
            config,
            rng: Xoshiro128PlusPlus::seed_from_u64(config.params.seed),
            set_points: SetPoints::new(config.params.keep_distance)?,
        })
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &VineConfig {
        &self.config
    }

    /// The kept set-points.
    #[must_use]
    pub const fn set_points(&self) -> &SetPoints<POINTS> {
        &self.set_points
    }

    /// Forgets every set-point (the generator goes on).
    pub fn reset(&mut self) {
        self.set_points.clear();
    }

    /// The ground profile and the candidates of one scan (steps 1 to 3),
    /// drawing from the detector's generator only.
    ///
    /// # Errors
    /// `FUR-SCAN` when the scan's increment is ≤ 0 or its field of view
    /// holds more than `RAYS` rays.
    //= spec/iberraken2022.md#vine-scan-scan-to-points-in-the-field-of-view
    //# Each ray whose in-plane angle lies in [−30°, 30°] (the configured half
    //# field of view) MUST be converted into a robot-frame point through the
    //# mount pose as FUR-SCAN converts it; other rays MUST NOT be used.
    //= spec/iberraken2022.md#vine-signal-levelled-heights-with-a-noise-floor
    //# The signal of a ray MUST be its height above the ground profile when
    //# that height is above the floor, and 0 otherwise, for a dropped ray and
    //# for every ray of a scan without a ground profile.
    pub fn candidates(
        &mut self,
        scan: &Scan<'_>,
    ) -> Result<(Ground, Vec<Candidate, MAX_MAXIMA>), Precondition> {
        let mut rays: [Option<ScanPoint>; RAYS] = [None; RAYS];
        let window = scan_to_points(scan, &self.config.mount, &self.config.window, &mut rays)?;
        let rays = rays.get(..window.count).unwrap_or_default();
        let ground = fit_ground(rays, &self.config.ground, &mut self.rng);
        let mut signal = [0.0_f64; RAYS];
        if let Ground::Profile(profile) = ground {
            let floor = self.config.params.height_floor;
            for (s, ray) in signal.iter_mut().zip(rays) {
                let h = ray.and_then(|p| Meters::new(profile.height_above(&p)).ok());
                *s = height_signal(h, floor);
            }
        }
        let signal = signal.get(..window.count).unwrap_or_default();
        let mut scores = [0.0_f64; RAYS];
        correlate(signal, &self.config.model, &mut scores)?;
        let model = &self.config.model;
        let offsets = window
            .count
            .saturating_sub(model.length())
            .saturating_add(1)
            .min(window.count);
        let scores = scores.get(..offsets).unwrap_or_default();
        let mut found = Vec::new();
        //= spec/iberraken2022.md#vine-candidates-maxima-above-the-threshold
        //# Every local maximum of r(k) above the threshold (Table 1: 0.25) MUST
        //# be a candidate.
        for k in local_maxima(scores, self.config.params.threshold, model.width() / 2) {
            let start = k.saturating_add(model.margin());
            let end = start.saturating_add(model.width());
            if let Some(point) = locate(rays, signal, start, end) {
                let score = scores.get(k).copied().unwrap_or(0.0);
                let _ = found.push(Candidate {
                    offset: k,
                    score,
                    point,
                });
            }
        }
        Ok((ground, found))
    }

    /// One tick: the candidates of `scan`, seen at odometry pose `odom`, the
    /// set-points updated, the row line fitted and the detection graded
    /// (steps 1 to 5 of the module doc).
    ///
    /// # Errors
    /// `FUR-SCAN` as [`VineDetector::candidates`] (the set-points are then
    /// left as they were).
    pub fn detect(
        &mut self,
        scan: &Scan<'_>,
        odom: &Pose2<Odom>,
    ) -> Result<VineDetection, Precondition> {
        let (ground, candidates) = self.candidates(scan)?;
        self.set_points.forget_far(odom);
        let joined = self.join(&candidates, odom);
        if let Some(c) = joined {
            if let Ok(point) = odom.body_to_frame::<Robot>().apply(c.point) {
                self.set_points.push(SetPoint {
                    point,
                    score: c.score,
                });
            }
        }
        // A line whose deviations overflow is no line.
        let estimate = self
            .line(odom)
            .and_then(|l| row_deviation(&l.0).ok().map(|e| (l, e)));
        let quality = self.set_points.mean_score();
        let verdict = vine_verdict(&self.config.thresholds, estimate.is_some(), quality);
        Ok(VineDetection {
            verdict,
            error: estimate.map(|(_, e)| e),
            line: estimate.map(|(l, _)| l),
            quality,
            ground,
            candidates: candidates.len(),
            joined,
            set_points: self.set_points.len(),
        })
    }

    /// The candidate that joins the set-points (eq. 2): with a newest
    /// set-point, the candidate of least lateral deviation from it, if at
    /// most `max_deviation`; with none, the candidate of least |y| in the
    /// robot frame, if at most `first_lateral`. Ties go to the first.
    //= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
    //# The candidate of least deviation l from the newest set-point MUST join
    //# the set-points, stored in the odometry frame, when l is at most the
    //# configured bound; with no set-point, the candidate of least |y| in the
    //# robot frame MUST join when |y| is at most the first-point bound.
    fn join(&self, candidates: &[Candidate], odom: &Pose2<Odom>) -> Option<Candidate> {
        let to_odom = odom.body_to_frame::<Robot>();
        let params = &self.config.params;
        let measure = |c: &Candidate| -> Option<f64> {
            match self.set_points.newest() {
                Some(p) => {
                    let r = to_odom.apply(c.point).ok()?;
                    let l = lateral_deviation(r, p.point, odom.heading).ok()?.get();
                    (l <= params.max_deviation.get()).then_some(l)
                }
                None => {
                    let y = libm::fabs(c.point.y());
                    (y <= params.first_lateral.get()).then_some(y)
                }
            }
        };
        let mut best: Option<(f64, Candidate)> = None;
        for c in candidates {
            if let Some(l) = measure(c) {
                if best.is_none_or(|(b, _)| l < b) {
                    best = Some((l, *c));
                }
            }
        }
        best.map(|(_, c)| c)
    }

    /// The row line through the set-points in the robot frame at `odom`, once
    /// there are `min_points` of them spanning `min_extent` along x.
    //= spec/iberraken2022.md#vine-line-row-line-and-deviations
    //# The row line MUST be the least-squares line y = a x + b through the
    //# set-points in the current robot frame, fitted once there are at least
    //# the configured number of them spanning at least the configured extent
    //# along x.
    fn line(&self, odom: &Pose2<Odom>) -> Option<VineLine> {
        let points = self.set_points.in_robot_frame(odom);
        let (n, lo, hi) = points.clone().fold(
            (0_usize, f64::INFINITY, f64::NEG_INFINITY),
            |(n, lo, hi), p| (n.saturating_add(1), lo.min(p.x()), hi.max(p.x())),
        );
        let enough =
            n >= self.config.params.min_points && hi - lo >= self.config.params.min_extent.get();
        if enough {
            fit_row_line(points).ok().map(VineLine)
        } else {
            None
        }
    }
}

/// The share of a vine's highest levelled height above which its rays count
/// as its top (VINE-CANDIDATES).
pub const TOP_SHARE: f64 = 0.9;

/// Where a vine matched under the model's square `[start, end)` stands: the
/// contiguous run of rays of positive signal around the square's highest
/// ray, and the mean ground position of the rays of that run whose signal
/// is at least [`TOP_SHARE`] of the run's highest (the vine's top, not the
/// face the LiDAR sees from the side). `None` when the square holds no
/// signal.
//= spec/iberraken2022.md#vine-candidates-maxima-above-the-threshold
//# A candidate MUST be located at the mean ground position of the rays whose
//# signal is at least 0.9 times the highest of the contiguous run of positive
//# signal around the highest ray under the model's square.
fn locate(
    rays: &[Option<ScanPoint>],
    signal: &[f64],
    start: usize,
    end: usize,
) -> Option<Point2<Robot>> {
    let square = signal.get(start..end)?;
    let (offset, _) = square.iter().enumerate().filter(|(_, &s)| s > 0.0).fold(
        None,
        |best: Option<(usize, f64)>, (i, &s)| match best {
            Some((_, b)) if b >= s => best,
            _ => Some((i, s)),
        },
    )?;
    let peak = start.saturating_add(offset);
    let positive = |i: usize| signal.get(i).is_some_and(|&s| s > 0.0);
    let mut lo = peak;
    while lo > 0 && positive(lo.saturating_sub(1)) {
        lo = lo.saturating_sub(1);
    }
    let mut hi = peak.saturating_add(1);
    while positive(hi) {
        hi = hi.saturating_add(1);
    }
    let run = signal.get(lo..hi)?;
    let top = run.iter().copied().fold(0.0_f64, f64::max);
    let (mut n, mut sx, mut sy) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (ray, &s) in rays.get(lo..hi)?.iter().zip(run) {
        if let Some(p) = ray {
            if s >= TOP_SHARE * top {
                n += 1.0;
                sx += p.ground.x();
                sy += p.ground.y();
            }
        }
    }
    if n > 0.0 {
        Point2::new(sx / n, sy / n).ok()
    } else {
        None
    }
}

/// The verdict (VINE-VERDICT): Absent without a row line, else the mean
/// set-point score graded by the thresholds (Enter above the entry one,
/// Exit below the exit one, Hold between).
//= spec/iberraken2022.md#vine-verdict-verdict-from-the-set-points
//# The verdict MUST be Absent when there is no row line, and otherwise the
//# mean score of the kept set-points graded by the entry and exit thresholds
//# as SW-CLASSIFY grades it.
#[must_use]
pub fn vine_verdict(
    thresholds: &QualityThresholds,
    has_line: bool,
    quality: Option<f64>,
) -> Verdict {
    match (has_line, quality) {
        (true, Some(q)) => thresholds.classify(q),
        _ => Verdict::Absent,
    }
}

impl<const RAYS: usize, const POINTS: usize> Detector for VineDetector<RAYS, POINTS> {
    type Config = VineConfig;
    type Line = VineLine;

    fn configure(config: &VineConfig) -> Result<Self, Precondition> {
        Self::new(*config)
    }

    fn observe(
        &mut self,
        scan: &Scan<'_>,
        odometry: &Pose2<Odom>,
    ) -> Result<Detection<VineLine>, Precondition> {
        let d = self.detect(scan, odometry)?;
        Ok(Detection {
            verdict: d.verdict,
            error: d.error,
            quality: d.quality,
            line: d.line,
            ahead: None,
        })
    }
}
