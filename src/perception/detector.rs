//! The one interface every detector implements, and the closed set of the
//! library's detectors behind it (`spec/guidance.md`, GD-DETECTOR).
//!
//! A detector is configured and validated once ([`Detector::configure`]);
//! each scan, with the odometry pose it was taken at, gives a [`Detection`]:
//! a verdict, the tracking error to its line at the robot, the quality figure
//! the verdict graded, and the line itself as a [`HeldLine`], which moves
//! itself to a later pose so that the pipeline can carry the estimate between
//! scans. A detector that needs 3D points (an inclined scan levelled on the
//! ground) makes them from the scan through its own mount pose, as furrow
//! pursuing does.

use crate::error::Precondition;
use crate::geometry::frame::{Odom, Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::Radians;
use crate::perception::edge::{EdgeDetector, EdgeDetectorConfig, EdgeLine};
use crate::perception::furrow::{FurrowConfig, FurrowDetector, RowLines};
use crate::perception::vine::{VineConfig, VineDetector, VineLine};
use crate::perception::{Scan, Verdict};

/// A detected line, held between scans: it gives the robot's tracking error
/// to itself from any pose in the robot frame of the scan it was seen in
/// (GD-ODOMETRY).
pub trait HeldLine: Copy + core::fmt::Debug + PartialEq {
    /// The tracking error to this line of the robot at `pose`, expressed in
    /// the robot frame of the scan's pose.
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    fn error_at(&self, pose: &Pose2<Robot>) -> Result<TrackingError, Precondition>;
}

/// What a detector made of one scan, in the detector-independent form the
/// pipeline reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detection<L> {
    /// The verdict on the estimate (its quality against the thresholds).
    pub verdict: Verdict,
    /// The tracking error to the line at the scan's pose; `None` exactly when
    /// the verdict is Absent.
    pub error: Option<TrackingError>,
    /// The quality figure graded, in the detector's own unit, when there is
    /// one (edge: the residual standard deviation, m; furrow: the weaker
    /// correlation score).
    pub quality: Option<f64>,
    /// The line, to carry the estimate to later poses; `None` exactly when
    /// the verdict is Absent.
    pub line: Option<L>,
    /// The structure's next line seen ahead while the verdict is not valid,
    /// as a point of the followed line and its heading, robot frame of the
    /// scan (EDGE-LOOK-AHEAD, GD-BRIDGE-LEVEL); `None` for a detector that
    /// does not look ahead.
    pub ahead: Option<Pose2<Robot>>,
}

/// A detector: a scan and its odometry pose in, a [`Detection`] out.
//= spec/guidance.md#gd-detector-one-trait-for-every-detector
//# Every detector MUST be configured and validated once, and MUST turn any
//# scan, with the odometry pose it was taken at, into a detection (a verdict,
//# a finite tracking error and line exactly when the verdict is not Absent, a
//# finite quality figure when it has one) or a `Precondition` error.
pub trait Detector: Sized {
    /// The detector's configuration, as validated by its own constructor.
    type Config: Copy + core::fmt::Debug + PartialEq;
    /// The line it holds between scans.
    type Line: HeldLine;

    /// A detector of `config` with nothing seen yet.
    ///
    /// # Errors
    /// The requirement the configuration breaks (for example a capacity too
    /// small for it).
    fn configure(config: &Self::Config) -> Result<Self, Precondition>;

    /// Detects in one scan taken at odometry pose `odometry`.
    ///
    /// # Errors
    /// The requirement a malformed scan breaks; the pipeline counts it as no
    /// estimate (GD-INPUT).
    fn observe(
        &mut self,
        scan: &Scan<'_>,
        odometry: &Pose2<Odom>,
    ) -> Result<Detection<Self::Line>, Precondition>;

    /// The heading, in the odometry frame, that the pipeline expects the
    /// followed structure to have (the path's), or `None`; given before each
    /// scan (GD-EXPECTED-HEADING). A detector that has no use for it keeps
    /// this default, which ignores it.
    fn expect_heading(&mut self, heading: Option<Radians>) {
        let _ = heading;
    }
}

/// The configuration of one of the library's detectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyDetectorConfig {
    /// Edge following on a horizontal LiDAR (Pierre 2022, section 2.2).
    Edge(EdgeDetectorConfig),
    /// Furrow pursuing on an inclined LiDAR (Pierre 2022, section 2.3).
    Furrow(FurrowConfig),
    /// Vine-row detection on an inclined LiDAR (Iberraken 2022, section 2.1).
    Vine(VineConfig),
}

/// The line held by one of the library's detectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyLine {
    /// An edge's parabola and the offset line beside it.
    Edge(EdgeLine),
    /// One or two crop rows.
    Furrow(RowLines),
    /// A vine row.
    Vine(VineLine),
}

impl HeldLine for AnyLine {
    fn error_at(&self, pose: &Pose2<Robot>) -> Result<TrackingError, Precondition> {
        match self {
            Self::Edge(l) => l.error_at(pose),
            Self::Furrow(l) => l.error_at(pose),
            Self::Vine(l) => l.error_at(pose),
        }
    }
}

/// One of the library's detectors, with its buffers: `EDGE_POINTS` scan
/// points and `EDGE_CHAIN` chain points for an edge detector, `FURROW_RAYS`
/// rays and `FURROW_SCANS` kept selections for a furrow detector, `VINE_RAYS`
/// rays and `VINE_POINTS` set-points for a vine detector. A pipeline
/// holding several kinds of detector holds this type in each slot (static
/// dispatch, no allocation).
#[derive(Debug, Clone)]
// The variants are the two detectors' own buffers, each sized by its const
// parameters; boxing is not available without allocation.
#[allow(clippy::large_enum_variant)]
pub enum AnyDetector<
    const EDGE_POINTS: usize = 512,
    const EDGE_CHAIN: usize = 64,
    const FURROW_RAYS: usize = 512,
    const FURROW_SCANS: usize = 32,
    const VINE_RAYS: usize = 256,
    const VINE_POINTS: usize = 64,
> {
    /// An edge detector.
    Edge(EdgeDetector<EDGE_POINTS, EDGE_CHAIN>),
    /// A furrow detector.
    Furrow(FurrowDetector<FURROW_RAYS, FURROW_SCANS>),
    /// A vine detector.
    Vine(VineDetector<VINE_RAYS, VINE_POINTS>),
}

impl<
        const EP: usize,
        const EC: usize,
        const FR: usize,
        const FS: usize,
        const VR: usize,
        const VP: usize,
    > AnyDetector<EP, EC, FR, FS, VR, VP>
{
    /// The edge detector, when this is one.
    #[must_use]
    pub const fn as_edge(&self) -> Option<&EdgeDetector<EP, EC>> {
        match self {
            Self::Edge(d) => Some(d),
            Self::Furrow(_) | Self::Vine(_) => None,
        }
    }

    /// The furrow detector, when this is one.
    #[must_use]
    pub const fn as_furrow(&self) -> Option<&FurrowDetector<FR, FS>> {
        match self {
            Self::Furrow(d) => Some(d),
            Self::Edge(_) | Self::Vine(_) => None,
        }
    }

    /// The vine detector, when this is one.
    #[must_use]
    pub const fn as_vine(&self) -> Option<&VineDetector<VR, VP>> {
        match self {
            Self::Vine(d) => Some(d),
            Self::Edge(_) | Self::Furrow(_) => None,
        }
    }
}

impl<
        const EP: usize,
        const EC: usize,
        const FR: usize,
        const FS: usize,
        const VR: usize,
        const VP: usize,
    > Detector for AnyDetector<EP, EC, FR, FS, VR, VP>
{
    type Config = AnyDetectorConfig;
    type Line = AnyLine;

    fn configure(config: &AnyDetectorConfig) -> Result<Self, Precondition> {
        Ok(match config {
            AnyDetectorConfig::Edge(c) => Self::Edge(EdgeDetector::configure(c)?),
            AnyDetectorConfig::Furrow(c) => Self::Furrow(FurrowDetector::configure(c)?),
            AnyDetectorConfig::Vine(c) => Self::Vine(VineDetector::configure(c)?),
        })
    }

    fn observe(
        &mut self,
        scan: &Scan<'_>,
        odometry: &Pose2<Odom>,
    ) -> Result<Detection<AnyLine>, Precondition> {
        match self {
            Self::Edge(d) => d.observe(scan, odometry).map(|x| x.map_line(AnyLine::Edge)),
            Self::Furrow(d) => d
                .observe(scan, odometry)
                .map(|x| x.map_line(AnyLine::Furrow)),
            Self::Vine(d) => d.observe(scan, odometry).map(|x| x.map_line(AnyLine::Vine)),
        }
    }

    fn expect_heading(&mut self, heading: Option<Radians>) {
        match self {
            Self::Edge(d) => d.expect_heading(heading),
            Self::Furrow(d) => d.expect_heading(heading),
            Self::Vine(d) => d.expect_heading(heading),
        }
    }
}

impl<L> Detection<L> {
    /// The same detection holding `f` of its line.
    #[must_use]
    pub fn map_line<M>(self, f: impl FnOnce(L) -> M) -> Detection<M> {
        Detection {
            verdict: self.verdict,
            error: self.error,
            quality: self.quality,
            line: self.line.map(f),
            ahead: self.ahead,
        }
    }
}
