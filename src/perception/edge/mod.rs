//! Edge following perception on a horizontal 2D LiDAR (Pierre 2022,
//! section 2.2, Algorithm 1, eqs. 8-11, and eq. 21 with Table 1;
//! `spec/pierre2022.md`, section "Edge following").
//!
//! One tick: [`scan_to_points`] turns a [`Scan`] (the shared LiDAR message of
//! [`crate::perception`], LIB-SCAN) into robot-frame points (EDGE-SCAN); [`build_chain`] rolls a circle along the edge on the requested
//! side with exact contacts (EDGE-CHAIN-*), stopping where the edge breaks at
//! a gap or a corner (EDGE-GAP, EDGE-CORNER); a least-squares parabola is fitted
//! to the chain (EDGE-PARABOLA); [`tracking_error`] gives the
//! robot's errors to the line at the desired lateral distance (EDGE-ERRORS,
//! EDGE-OFFSET); [`EdgeQuality`] grades the detection (EDGE-QUALITY); when
//! the verdict is not valid, the next piece's line may be sought ahead
//! ([`LookAhead`], EDGE-LOOK-AHEAD).
//! [`EdgeDetector`] does all of it per tick in buffers it owns (the form a
//! vehicle stack uses); [`detect`] and [`detect_points`] do the same and
//! return the chain by value. Nothing allocates and nothing panics; invalid
//! data gives [`Verdict::Absent`] or a [`Precondition`] error.

pub mod chain;
pub mod config;
pub mod parabola;
pub mod quality;
pub mod scan;
pub mod search;

pub use crate::geometry::fit::ParabolaFit;
pub use chain::{
    build_chain, build_chain_into, rotation_contact, translation_contact, Chain, ChainEnd,
};
pub use config::{EdgeConfig, EdgeParameters, LookAhead, Side, MAX_LOOK_AHEAD_STEPS};
pub use parabola::tracking_error;
pub use quality::EdgeQuality;
pub use scan::{scan_into, scan_to_points, ScanPoints, MAX_COORDINATE};

use crate::error::{finite, Precondition};
use crate::geometry::carry;
use crate::geometry::fit::fit_line;
use crate::geometry::frame::{Odom, Point2, Pose2, Robot, Sensor, Transform2};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::Meters;
use crate::perception::detector::{Detection, Detector, HeldLine};
use crate::perception::{Scan, Verdict};

/// The robot's abscissa in its own frame, x_r of eq. 11: the controlled point
/// O is the robot frame's origin.
const ROBOT_X: f64 = 0.0;

/// The parabola, its quality and the robot's errors, when the chain could be fitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeFit {
    /// The parabola of the chain, robot frame (eqs. 8-10).
    pub parabola: ParabolaFit,
    /// The measures of eq. 21.
    pub quality: EdgeQuality,
    /// The robot's error to the line at the desired lateral distance (eq. 11).
    pub error: TrackingError,
}

/// What one detection concludes, without the chain: a small `Copy` value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeOutcome {
    /// The side searched.
    pub side: Side,
    /// The fit of the chain; `None` when the verdict is `Absent`.
    pub fit: Option<EdgeFit>,
    /// Enter / Hold / Exit from eq. 21, or Absent when there is no fit.
    pub verdict: Verdict,
    /// Why the chain stopped.
    pub chain_end: ChainEnd,
    /// Number of chain points.
    pub chain_points: usize,
    /// The next piece's line seen ahead when the verdict is not valid
    /// (EDGE-LOOK-AHEAD): a point of the line at the desired distance from
    /// it and that line's heading, robot frame.
    pub ahead: Option<Pose2<Robot>>,
}

impl EdgeOutcome {
    /// The error to command from, only when the verdict allows it (Enter or
    /// Hold): a rejected or missing detection never yields a command.
    #[must_use]
    pub fn usable_error(&self) -> Option<TrackingError> {
        if self.verdict.estimate_is_valid() {
            self.fit.map(|f| f.error)
        } else {
            None
        }
    }
}

/// What an edge detector is configured with: the detector's parameters, the
/// horizontal LiDAR's mount pose (sensor → robot) and the side of the robot
/// where the edge is followed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeDetectorConfig {
    /// The detector (Algorithm 1, eqs. 8-11, eq. 21).
    pub edge: EdgeConfig,
    /// The LiDAR's mount pose, sensor → robot.
    pub mount: Transform2<Sensor, Robot>,
    /// The side searched.
    pub side: Side,
}

/// An edge seen in one scan, as the pipeline holds it between scans: the
/// chain's parabola and the line at the desired distance beside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeLine {
    /// The parabola of the chain, robot frame of the scan (eqs. 8-10).
    pub parabola: ParabolaFit,
    /// The side of the robot the edge is on.
    pub side: Side,
    /// The desired lateral distance to the edge, m (EDGE-OFFSET).
    pub offset: Meters,
}

impl HeldLine for EdgeLine {
    /// y = y₀(p_x) + p_y cos θ̃₀(p_x), θ̃ = wrap(θ̃₀(p_x) + ψ), with eq. 11's
    /// error at x_r = p_x (EDGE-ERRORS, EDGE-OFFSET, GD-ODOMETRY).
    fn error_at(&self, pose: &Pose2<Robot>) -> Result<TrackingError, Precondition> {
        let at = tracking_error(&self.parabola, self.side, self.offset, pose.position.x())?;
        let theta = at.angular_deviation.get();
        carry::straight(
            finite(
                at.y.get() + pose.position.y() * libm::cos(theta),
                "moved edge error overflows",
            )?,
            theta + pose.heading.get(),
        )
    }
}

/// An edge detector with its buffers: up to `N` scan points and `M` chain
/// points, reused every tick (Pierre 2022, section 2.2; EDGE-DETECT), and
/// a second chain of `M` points for the look-ahead (EDGE-LOOK-AHEAD).
#[derive(Debug, Clone)]
pub struct EdgeDetector<const N: usize, const M: usize> {
    config: EdgeDetectorConfig,
    points: ScanPoints<N>,
    chain: Chain<M>,
    ahead: Chain<M>,
}

impl<const N: usize, const M: usize> EdgeDetector<N, M> {
    /// A detector with a validated configuration, its LiDAR's mount and the
    /// side it searches.
    #[must_use]
    pub const fn new(config: EdgeDetectorConfig) -> Self {
        Self {
            config,
            points: ScanPoints::new(),
            chain: Chain::empty(ChainEnd::NoEdge),
            ahead: Chain::empty(ChainEnd::NoEdge),
        }
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &EdgeDetectorConfig {
        &self.config
    }

    /// Detects the edge in `scan` on the configured side; `odometry` is not
    /// read (the edge detector keeps nothing between scans) and is taken for
    /// the same shape as every detector's. The points and the chain stay in
    /// the detector ([`Self::points`], [`Self::chain`]) until the next call.
    ///
    /// Errors with `EDGE-SCAN` when more than `N` rays are valid or a point
    /// lies beyond [`MAX_COORDINATE`]; the chain is then empty.
    pub fn detect(
        &mut self,
        scan: &Scan<'_>,
        _odometry: &Pose2<Odom>,
    ) -> Result<EdgeOutcome, Precondition> {
        let EdgeDetectorConfig { edge, mount, side } = self.config;
        if let Err(e) = scan::scan_into(scan, &mount, &mut self.points) {
            build_chain_into(&[], side, &edge, &mut self.chain);
            return Err(e);
        }
        Ok(evaluate(
            self.points.as_slice(),
            side,
            &edge,
            &mut self.chain,
            &mut self.ahead,
        ))
    }

    /// The robot-frame points of the last scan.
    #[must_use]
    pub fn points(&self) -> &[Point2<Robot>] {
        self.points.as_slice()
    }

    /// The chain of the last detection.
    #[must_use]
    pub const fn chain(&self) -> &Chain<M> {
        &self.chain
    }
}

/// Chain, fit and grade `points` (already checked to be bounded) into
/// `chain`; when the verdict is not valid, look ahead with `scratch`.
fn evaluate<const M: usize>(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    chain: &mut Chain<M>,
    scratch: &mut Chain<M>,
) -> EdgeOutcome {
    build_chain_into(points, side, config, chain);
    let fit = if chain.len() >= config.min_points() {
        fit_chain(chain, side, config)
    } else {
        None
    };
    let verdict = match &fit {
        Some(_) if at_piece_end(chain, config) => Verdict::Exit,
        Some(f) => f.quality.grade(config),
        None => Verdict::Absent,
    };
    let ahead = if verdict.estimate_is_valid() {
        None
    } else {
        look_ahead(points, side, config, scratch)
    };
    EdgeOutcome {
        side,
        fit,
        verdict,
        chain_end: chain.end(),
        chain_points: chain.len(),
        ahead,
    }
}

/// The next piece's line ahead (EDGE-LOOK-AHEAD): chains built with the
/// circle's translation starting at x = Δx, 2Δx, … ≤ x_far (at most
/// [`MAX_LOOK_AHEAD_STEPS`] chains, built over `points` in place); the
/// first chain found, without its first l_cap metres along x, gives it.
//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//# When the look-ahead is on and the verdict of a detection is not Enter or
//# Hold, the detector MUST build chains as in EDGE-CHAIN-TRANSLATE,
//# EDGE-CHAIN-ROTATE and EDGE-CHAIN-STOP with the circle's translation
//# starting at (k Δx, 0) instead of the robot's rear point, for k = 1, 2, …
//# while k Δx ≤ x_far, and take the first of them that has a point.
fn look_ahead<const M: usize>(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    scratch: &mut Chain<M>,
) -> Option<Pose2<Robot>> {
    let a = config.look_ahead()?;
    let farthest = a.farthest * (1.0 + 1e-9);
    let mut x0 = 0.0;
    for _ in 0..MAX_LOOK_AHEAD_STEPS {
        x0 += a.step;
        if x0 > farthest {
            return None;
        }
        chain::build_chain_from(points, side, config, x0, scratch);
        if let Some(first) = scratch.points().first() {
            return next_piece_line(scratch.points(), first.x() + a.end_cap, side, config);
        }
    }
    None
}

/// The line of the chain points beyond abscissa `from` (EDGE-LOOK-AHEAD):
/// with at least the fewest chain points spanning at least l_fit along x,
/// the least-squares straight line through them, when its residual
/// standard deviation grades Enter or Hold; given as the point of the line
/// at the desired distance abeam the middle of their extent along x, and
/// its heading.
//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//# The points of that chain lying more than l_cap along x beyond its first
//# point MUST give the next piece's line only when they are at least the
//# fewest chain points, span at least l_fit along x, and the residual
//# standard deviation of their least-squares straight line y = a x + b is
//# graded Enter or Hold by σ_edge and σ_path.
//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//# The detection MUST then report, besides its own verdict and fit, the
//# point of the line at the desired distance D from that straight line on
//# the robot's side, abeam the middle of the points' extent along x, with
//# the line's heading arctan a; otherwise, and when the look-ahead is off
//# or the verdict is Enter or Hold, it MUST report none.
fn next_piece_line(
    chain: &[Point2<Robot>],
    from: f64,
    side: Side,
    config: &EdgeConfig,
) -> Option<Pose2<Robot>> {
    let span = config.look_ahead()?.min_span;
    let part = || chain.iter().filter(move |p| p.x() > from);
    let (mut n, mut low, mut high) = (0.0_f64, f64::INFINITY, f64::NEG_INFINITY);
    for p in part() {
        n += 1.0;
        low = low.min(p.x());
        high = high.max(p.x());
    }
    // An empty part spans −∞.
    if part().count() < config.min_points() || high - low < span {
        return None;
    }
    let line = fit_line(part()).ok()?;
    let squares: f64 = part()
        .map(|p| {
            let r = p.y() - line.a * p.x() - line.b;
            r * r
        })
        .sum();
    if !config
        .thresholds()
        .classify(libm::sqrt(squares / n))
        .estimate_is_valid()
    {
        return None;
    }
    let x = (low + high) / 2.0;
    let heading = libm::atan(line.a);
    let shift = side.sign() * config.offset().get();
    // The face's point minus s·D along the line's left normal (−sin φ, cos φ).
    Pose2::new(
        x + shift * libm::sin(heading),
        line.a * x + line.b - shift * libm::cos(heading),
        heading,
    )
    .ok()
}

/// Whether `chain` sees a piece's end (EDGE-PIECE-END): it stopped at a
/// break of the edge (a gap, a corner, the rotation limit) while not longer
/// than l_end, or its first point lies more than x_ahead ahead of the robot.
//= spec/pierre2022.md#edge-piece-end-a-chain-at-a-piece-s-end-is-not-followed
//# A fitted chain MUST be graded Exit when it stopped at a gap, a corner or
//# the rotation limit while its length is not greater than l_end, or when
//# its first point lies more than x_ahead ahead of the robot (p_x > x_ahead).
fn at_piece_end<const M: usize>(chain: &Chain<M>, config: &EdgeConfig) -> bool {
    let at_break = matches!(
        chain.end(),
        ChainEnd::Gap | ChainEnd::Corner | ChainEnd::RotationLimit
    );
    let short = chain.length().get() <= config.min_end_chain_length().get();
    let ahead = chain
        .points()
        .first()
        .is_some_and(|p| p.x() > config.max_start_ahead().get());
    (at_break && short) || ahead
}

/// The result of one edge detection: the chain, the fit when there is one,
/// and the verdict for the switching machine.
#[derive(Debug, Clone)]
pub struct EdgeDetection<const M: usize> {
    /// The side searched.
    pub side: Side,
    /// The chain of Algorithm 1.
    pub chain: Chain<M>,
    /// The fit of the chain; `None` when the verdict is `Absent`.
    pub fit: Option<EdgeFit>,
    /// Enter / Hold / Exit from eq. 21, or Absent when there is no fit.
    pub verdict: Verdict,
    /// The next piece's line seen ahead (EDGE-LOOK-AHEAD), as in [`EdgeOutcome`].
    pub ahead: Option<Pose2<Robot>>,
}

impl<const M: usize> EdgeDetection<M> {
    /// The error to command from, only when the verdict allows it (Enter or
    /// Hold): a rejected or missing detection never yields a command.
    #[must_use]
    pub fn usable_error(&self) -> Option<TrackingError> {
        if self.verdict.estimate_is_valid() {
            self.fit.map(|f| f.error)
        } else {
            None
        }
    }
}

/// Detects the edge on `side` in a scan taken by a LiDAR mounted at `mount`
/// (sensor → robot), holding at most `N` valid points and `M` chain points.
///
/// Errors with `EDGE-SCAN` when more than `N` rays are valid or a point lies
/// beyond [`MAX_COORDINATE`]. An empty scan, a scan of invalid ranges or
/// nothing on `side` gives `Ok` with [`Verdict::Absent`].
pub fn detect<const N: usize, const M: usize>(
    scan: &Scan<'_>,
    mount: &Transform2<Sensor, Robot>,
    side: Side,
    config: &EdgeConfig,
) -> Result<EdgeDetection<M>, Precondition> {
    let points = scan_to_points::<N>(scan, mount)?;
    detect_points(points.as_slice(), side, config)
}

/// Detects the edge on `side` among robot-frame `points` (EDGE-DETECT).
///
/// Errors with `EDGE-SCAN` when a point lies beyond [`MAX_COORDINATE`].
//= spec/pierre2022.md#edge-detect-one-detection
//# A detection MUST be Absent, with no fit, when the chain has fewer points
//# than the configured fewest or cannot be fitted (fewer than 3 distinct
//# abscissae).
//= spec/pierre2022.md#edge-detect-one-detection
//# A tracking error MUST be offered for commanding only when the verdict is
//# Enter or Hold.
pub fn detect_points<const M: usize>(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
) -> Result<EdgeDetection<M>, Precondition> {
    scan::check_bounded(points)?;
    let mut chain = Chain::empty(ChainEnd::NoEdge);
    let mut scratch: Chain<M> = Chain::empty(ChainEnd::NoEdge);
    let outcome = evaluate(points, side, config, &mut chain, &mut scratch);
    Ok(EdgeDetection {
        side,
        chain,
        fit: outcome.fit,
        verdict: outcome.verdict,
        ahead: outcome.ahead,
    })
}

fn fit_chain<const M: usize>(chain: &Chain<M>, side: Side, config: &EdgeConfig) -> Option<EdgeFit> {
    let parabola = if config.straight() {
        parabola::fit_chain_line(chain.points()).ok()?
    } else {
        parabola::fit_chain_parabola(chain.points()).ok()?
    };
    let quality = EdgeQuality::measure(chain.points(), chain.length(), &parabola).ok()?;
    let error = tracking_error(&parabola, side, config.offset(), ROBOT_X).ok()?;
    Some(EdgeFit {
        parabola,
        quality,
        error,
    })
}

impl<const N: usize, const M: usize> Detector for EdgeDetector<N, M> {
    type Config = EdgeDetectorConfig;
    type Line = EdgeLine;

    fn configure(config: &EdgeDetectorConfig) -> Result<Self, Precondition> {
        Ok(Self::new(*config))
    }

    fn observe(
        &mut self,
        scan: &Scan<'_>,
        odometry: &Pose2<Odom>,
    ) -> Result<Detection<EdgeLine>, Precondition> {
        let outcome = self.detect(scan, odometry)?;
        let (side, offset) = (self.config.side, self.config.edge.offset());
        Ok(Detection {
            verdict: outcome.verdict,
            error: outcome.fit.map(|f| f.error),
            quality: outcome.fit.map(|f| f.quality.residual_std.get()),
            line: outcome.fit.map(|f| EdgeLine {
                parabola: f.parabola,
                side,
                offset,
            }),
            ahead: outcome.ahead,
        })
    }
}
