//! Crop rows from a horizontal LiDAR without GNSS (Guyonneau, Mercier,
//! Oliveira Freitas 2022, sections 2 and 3.1-3.2; `spec/guyonneau2022.md`).
//!
//! The data flow of one scan:
//!
//! 1. [`points`]: the scan's rays become robot-frame points through the
//!    sensor's mount (ROWS-POINTS); with the one-point refinement, runs of
//!    consecutive points closer than a merge distance become one (Alg. 2,
//!    RUBY-ONE-POINT);
//! 2. [`ruby`]: Ruby's energy minimisation (Alg. 1, eqs. 1-9) and its
//!    refinements RG, RGOP, RGOPPN, RGOPPNI (eq. 10, Algs. 2-3) fit a set of
//!    lines, seeded by the previous scan's set;
//! 3. [`spacing`]: before the robot moves, the distance between rows from
//!    the closest pair of lines either side of the robot (eqs. 13-14);
//! 4. [`filter`]: n expected rows kept from scan to scan, the missing ones
//!    computed from the found ones (Alg. 4, eqs. 15-17), and the verdict.
//!
//! Frames: the library's robot frame, x forward, y left (LIB-FRAMES); the
//! paper's eqs. 11-12 call y < 0 "left" (ROWS-FRAME).

pub mod filter;
pub mod points;
pub mod ruby;
pub mod spacing;

use heapless::Vec;

use self::filter::{seen_from, tracking_error, FilterConfig, Outcome, RowFilter};
use self::points::{merge_runs, scan_points_with, Gathered, Points, Rays};
use self::ruby::{Found, Ruby, RubyConfig, RubyParams, Variant, MAX_MODELS};
use self::spacing::{SpacingConfig, SpacingEstimator};
use crate::error::Precondition;
use crate::geometry::carry::pose_in_scan_frame;
use crate::geometry::frame::{Odom, Pose2, Robot, Sensor, Transform2};
use crate::geometry::units::{Meters, Radians};
use crate::perception::detector::{Detection, Detector};
use crate::perception::furrow::lines::RowLine;
use crate::perception::furrow::selection::Pair;
use crate::perception::furrow::RowLines;
use crate::perception::{Scan, Verdict};

/// LiDARs a rows detector reads at once at most (the paper's robot has one
/// at the front and one at the back).
pub const MAX_LIDARS: usize = 2;

/// The rows detector's parameters as a user writes them; [`RowsParams::authors`]
/// gives the defaults of the authors' implementation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowsParams {
    /// Each LiDAR's mount on the robot, in the order its scans are given.
    pub mounts: [Option<Transform2<Sensor, Robot>>; MAX_LIDARS],
    /// The line finder's constants.
    pub ruby: RubyParams,
    /// The row-distance initialisation's.
    pub spacing: SpacingConfig,
    /// The row filter's.
    pub filter: FilterConfig,
    /// The farthest the robot may move (m, and as much in rad of turn)
    /// while the row distance is measured (ROWS-INIT-STILL).
    pub still: Meters,
    /// The fewest points a line must hold to be taken as a row
    /// (ROWS-SUPPORT), ≥ 3.
    pub min_support: usize,
}

impl RowsParams {
    /// One LiDAR at `mount` and the authors' constants for `variant`: RGOP
    /// is the paper's best (Table 2); still within 5 cm (and 0.05 rad).
    #[must_use]
    pub fn authors(variant: Variant, mount: Transform2<Sensor, Robot>) -> Self {
        Self {
            mounts: [Some(mount), None],
            ruby: RubyParams::authors(variant),
            spacing: SpacingConfig::default(),
            filter: FilterConfig::default(),
            still: Meters(0.05),
            min_support: 5,
        }
    }

    /// The same with a second LiDAR at `back`, whose points follow the first's.
    #[must_use]
    pub const fn with_second(mut self, back: Transform2<Sensor, Robot>) -> Self {
        self.mounts[1] = Some(back);
        self
    }
}

/// Validated [`RowsParams`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowsConfig {
    params: RowsParams,
    ruby: RubyConfig,
}

impl RowsConfig {
    /// Checks the parameters once.
    ///
    /// # Errors
    /// `ROWS-MOUNTS` without a first mount, `ROWS-INIT-STILL` unless the
    /// still tolerance is finite and ≥ 0, and the line finder's own
    /// (`RUBY-PARAMS`).
    //= spec/guyonneau2022.md#rows-mounts-one-scan-per-mounted-lidar
    //# A configuration without a first LiDAR's mount MUST be refused with an
    //# error naming ROWS-MOUNTS.
    pub fn new(params: RowsParams) -> Result<Self, Precondition> {
        if params.mounts[0].is_none() {
            return Err(Precondition::new(
                "ROWS-MOUNTS",
                "the first LiDAR's mount is missing",
            ));
        }
        let still = params.still.get();
        //= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
        //# A still tolerance that is not finite and ≥ 0 MUST be refused with an error
        //# naming ROWS-INIT-STILL.
        if !(still.is_finite() && still >= 0.0) {
            return Err(Precondition::new(
                "ROWS-INIT-STILL",
                "the still tolerance must be finite and ≥ 0",
            ));
        }
        //= spec/guyonneau2022.md#rows-support-rows-from-lines-of-enough-points
        //# A configuration whose fewest points is below three MUST be refused
        //# with an error naming ROWS-SUPPORT.
        if params.min_support < ruby::SEED_POINTS {
            return Err(Precondition::new(
                "ROWS-SUPPORT",
                "a row needs at least three points",
            ));
        }
        Ok(Self {
            ruby: RubyConfig::new(params.ruby)?,
            params,
        })
    }

    /// The parameters.
    #[must_use]
    pub const fn params(&self) -> &RowsParams {
        &self.params
    }

    /// The LiDARs configured.
    fn lidars(&self) -> usize {
        self.params.mounts.iter().flatten().count()
    }
}

/// Where the detector is: measuring the row distance while the robot stands
/// still, or following the rows.
#[derive(Debug, Clone, PartialEq)]
enum Phase {
    /// Measuring d: the estimator, the pose of the first scan counted, if
    /// any, and the scans in a row that showed no pair.
    Measuring(SpacingEstimator, Option<Pose2<Odom>>, u32),
    /// Following n rows.
    Following(RowFilter),
}

/// What the rows detector made of one scan, beyond the [`Detection`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowsDetection {
    /// The detection the pipeline reads.
    pub detection: Detection<RowLines>,
    /// The points gathered from the scans (and dropped for lack of room).
    pub gathered: Gathered,
    /// What the line finder did.
    pub found: Found,
    /// What the filter did, once it follows the rows.
    pub outcome: Option<Outcome>,
}

/// Crop rows from one or two horizontal LiDARs (Guyonneau 2022): Ruby's
/// line finding, the row distance measured at rest, the row filter and the
/// error to the middle of the rows either side of the robot; `POINTS`
/// points at most per tick, both LiDARs together.
#[derive(Debug, Clone)]
pub struct RowsDetector<const POINTS: usize = 512> {
    config: RowsConfig,
    ruby: Ruby<POINTS>,
    points: Points<POINTS>,
    one: Points<POINTS>,
    /// Each LiDAR's rays' sines and cosines.
    rays: [Rays<POINTS>; MAX_LIDARS],
    phase: Phase,
    /// The odometry pose of the last tick.
    last: Option<Pose2<Odom>>,
}

impl<const POINTS: usize> RowsDetector<POINTS> {
    /// A detector of `config` with nothing seen yet.
    #[must_use]
    pub fn new(config: RowsConfig) -> Self {
        Self {
            ruby: Ruby::new(config.ruby),
            points: Points::new(),
            one: Points::new(),
            rays: [const { Rays::new() }; MAX_LIDARS],
            phase: Phase::Measuring(SpacingEstimator::new(config.params.spacing), None, 0),
            config,
            last: None,
        }
    }

    /// The line finder, with the lines of the last tick.
    #[must_use]
    pub const fn line_finder(&self) -> &Ruby<POINTS> {
        &self.ruby
    }

    /// The points of the last tick (Z, or Z* for the one-point variants).
    #[must_use]
    pub fn points(&self) -> &[points::RowPoint] {
        &self.points
    }

    /// The n filtered rows, left to right, once the row distance is known.
    #[must_use]
    pub fn rows(&self) -> Option<&[RowLine]> {
        match &self.phase {
            Phase::Following(f) => Some(f.rows()),
            Phase::Measuring(..) => None,
        }
    }

    /// The row distance d, m, once measured.
    #[must_use]
    pub fn row_distance(&self) -> Option<Meters> {
        match &self.phase {
            Phase::Following(f) => Some(f.distance()),
            Phase::Measuring(..) => None,
        }
    }

    /// One tick on `scans`, one per configured LiDAR in the order of the
    /// mounts, all taken at odometry pose `odometry`.
    ///
    /// # Errors
    /// `ROWS-MOUNTS` when the number of scans is not the number of mounts;
    /// `LIB-FINITE` when a point overflows.
    //= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
    //# Each tick MUST gather the points of every configured LiDAR's scan, in the
    //# order of the mounts, merge them into Z* for the one-point variants, run
    //# the line finder on them, and then either count the lines towards the row
    //# distance or pass them to the row filter, whose verdict and tracking error
    //# are the tick's.
    pub fn observe_scans(
        &mut self,
        scans: &[Scan<'_>],
        odometry: &Pose2<Odom>,
    ) -> Result<RowsDetection, Precondition> {
        //= spec/guyonneau2022.md#rows-mounts-one-scan-per-mounted-lidar
        //# A tick MUST be refused with an error naming ROWS-MOUNTS unless it is
        //# given exactly one scan per configured LiDAR.
        if scans.len() != self.config.lidars() {
            return Err(Precondition::new(
                "ROWS-MOUNTS",
                "one scan per configured LiDAR, in the order of the mounts",
            ));
        }
        let p = self.config.params;
        //= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
        //# The line finder's carried lines MUST be carried by the same motion.
        if let Some(motion) = self
            .last
            .and_then(|then| pose_in_scan_frame(&then, odometry).ok())
        {
            self.ruby.move_by(|line| seen_from(line, &motion));
            if let Phase::Following(filter) = &mut self.phase {
                filter.move_by(&motion);
            }
        }
        self.last = Some(*odometry);
        let mut gathered = Gathered {
            kept: 0,
            dropped: 0,
        };
        self.points.clear();
        for ((scan, mount), rays) in scans
            .iter()
            .zip(p.mounts.iter().flatten())
            .zip(self.rays.iter_mut())
        {
            let g = scan_points_with(scan, mount, rays, &mut self.one)?;
            if p.ruby.variant.one_point() {
                merge_runs(&mut self.one, p.ruby.merge_distance);
            }
            // The points in order while there is room, in one copy; those
            // after, dropped (one by one, each would be refused).
            let one: &[points::RowPoint] = &self.one;
            let room = self.points.capacity().saturating_sub(self.points.len());
            let (fit, rest) = one
                .split_at_checked(room.min(one.len()))
                .unwrap_or((&[], one));
            let refused = if self.points.extend_from_slice(fit).is_ok() {
                rest.len()
            } else {
                one.len()
            };
            gathered.dropped = gathered.dropped.saturating_add(refused);
            gathered.kept = self.points.len();
            gathered.dropped = gathered.dropped.saturating_add(g.dropped);
        }
        let found = self.ruby.find(&self.points);
        let mut lines: Vec<RowLine, MAX_MODELS> = Vec::new();
        //= spec/guyonneau2022.md#rows-support-rows-from-lines-of-enough-points
        //# Only the lines holding at least the configured fewest points MUST be
        //# passed to the row distance's measurement and to the row filter.
        for m in self
            .ruby
            .models()
            .iter()
            .filter(|m| m.points >= p.min_support)
        {
            let _ = lines.push(m.line);
        }
        let (detection, outcome) = self.follow(&lines, odometry, p.still.get());
        Ok(RowsDetection {
            detection,
            gathered,
            found,
            outcome,
        })
    }

    /// The row distance or the filter's step on one tick's lines.
    fn follow(
        &mut self,
        lines: &[RowLine],
        odometry: &Pose2<Odom>,
        still: f64,
    ) -> (Detection<RowLines>, Option<Outcome>) {
        let absent = Detection {
            verdict: Verdict::Absent,
            error: None,
            quality: None,
            line: None,
            ahead: None,
        };
        match &mut self.phase {
            Phase::Measuring(estimator, first, barren) => {
                //= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
                //# The row distance MUST be measured over scans taken while the robot
                //# stands still: when the robot is farther than the still tolerance (in
                //# metres, and in radians of heading) from the pose of the first scan
                //# counted, the measurement MUST start again from the current scan; until
                //# it is complete the verdict MUST be Absent.
                if let Some(start) = first {
                    if moved(start, odometry) > still {
                        *estimator = SpacingEstimator::new(self.config.params.spacing);
                        *first = None;
                    }
                }
                if estimator.observe(lines).is_some() {
                    first.get_or_insert(*odometry);
                    *barren = 0;
                } else {
                    *barren = barren.saturating_add(1);
                }
                //= spec/guyonneau2022.md#rows-init-still-the-row-distance-measured-at-rest
                //# When as many scans in a row as the measurement averages show no pair,
                //# the line finder's lines MUST be forgotten, so that its next scan
                //# starts from the empty set.
                let patience =
                    u32::try_from(self.config.params.spacing.estimates()).unwrap_or(u32::MAX);
                if *barren >= patience {
                    *barren = 0;
                    self.ruby.reset();
                }
                if estimator.is_ready() {
                    let start = estimator.distance().and_then(|d| {
                        let rows = estimator.initial_rows()?;
                        RowFilter::new(d, &rows, self.config.params.filter)
                    });
                    match start {
                        Ok(filter) => self.phase = Phase::Following(filter),
                        Err(_) => self.restart(),
                    }
                }
                (absent, None)
            }
            Phase::Following(filter) => {
                let outcome = filter.update(lines);
                //= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
                //# While it follows the rows, the detector MUST hand the filter's n rows
                //# to the line finder as lines carried to the next scan.
                self.ruby.carry(filter.rows());
                let verdict = outcome.verdict();
                let rows = filter.rows();
                let sides = filter.sides();
                //= spec/guyonneau2022.md#rows-detector-one-tick-of-the-rows-detector
                //# A lost filter MUST give the verdict Absent and restart the row
                //# distance's measurement, with the line finder's lines forgotten.
                if outcome.lost {
                    self.restart();
                    return (absent, Some(outcome));
                }
                match (verdict, tracking_error(rows), sides) {
                    (Verdict::Absent, _, _) | (_, Err(_), _) | (_, _, None) => {
                        (absent, Some(outcome))
                    }
                    (verdict, Ok(error), Some(Pair { left, right })) => (
                        Detection {
                            verdict,
                            error: Some(error),
                            quality: Some(count_f64(outcome.matched())),
                            line: Some(RowLines::Two(Pair { left, right })),
                            ahead: None,
                        },
                        Some(outcome),
                    ),
                }
            }
        }
    }

    /// Back to measuring the row distance, with no line carried.
    fn restart(&mut self) {
        self.phase = Phase::Measuring(SpacingEstimator::new(self.config.params.spacing), None, 0);
        self.ruby.reset();
    }
}

/// The larger of the distance and the turn between two poses (m, rad).
fn moved(a: &Pose2<Odom>, b: &Pose2<Odom>) -> f64 {
    let d = libm::hypot(
        b.position.x() - a.position.x(),
        b.position.y() - a.position.y(),
    );
    let turn = Radians(b.heading.get() - a.heading.get()).wrapped().get();
    d.max(libm::fabs(turn))
}

/// A count (of points, models or rows) as an f64: exact below 2³², which no
/// buffer here reaches.
#[inline]
pub(crate) fn count_f64(n: usize) -> f64 {
    u32::try_from(n).map_or(f64::from(u32::MAX), f64::from)
}

impl<const POINTS: usize> Detector for RowsDetector<POINTS> {
    type Config = RowsConfig;
    type Line = RowLines;

    fn configure(config: &RowsConfig) -> Result<Self, Precondition> {
        Ok(Self::new(*config))
    }

    /// One tick on one LiDAR's scan (a detector configured with two LiDARs
    /// takes [`RowsDetector::observe_scans`]).
    fn observe(
        &mut self,
        scan: &Scan<'_>,
        odometry: &Pose2<Odom>,
    ) -> Result<Detection<RowLines>, Precondition> {
        self.observe_scans(core::slice::from_ref(scan), odometry)
            .map(|d| d.detection)
    }
}
