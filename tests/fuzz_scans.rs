//! Fuzz targets (bolero) for the scan ingestion of every detector and for
//! the pipeline that routes scans to them (LIB-SCAN, EDGE-SCAN, FUR-SCAN,
//! GD-DETECTOR, GD-INPUT, LIB-FINITE, and the vine detector's VINE-*).
//!
//! Each target builds its input from a structure that bolero generates and
//! mutates: a scan is one of a few real ones (walls for the edge detector,
//! crop rows for the furrow detector) or a constant, cut or stretched to a
//! ray count (up to each detector's capacity and past it), with rays
//! replaced by faults (NaN, ±∞, negative, ±0, subnormal, 1e−300, 1e300,
//! `f64::MAX`, the limits themselves, any bit pattern), any angles and any
//! range limits; odometry and GNSS poses go from ordinary to `f64::MAX`.
//! The targets assert what the core claims, not only the absence of a
//! panic: an `Ok` holds finite values only, a detection has an error and a
//! line exactly when its verdict is not Absent, a full buffer is an error
//! naming its requirement, and a command is within the vehicle's limits.
//!
//! `cargo test` runs each for bolero's default budget (one second of random
//! inputs); `.ci/fuzz` runs each as a coverage-guided libFuzzer target
//! (README.md, "Fuzzing").
#![allow(
    clippy::arithmetic_side_effects,
    clippy::as_conversions,
    clippy::float_cmp,
    clippy::indexing_slicing,
    clippy::unwrap_used,
    clippy::expect_used
)]

mod crop_scans;
mod edge_support;
mod furrow_common;
mod vine_scans;

use core::f64::consts::{FRAC_PI_2, PI, TAU};
use std::sync::OnceLock;

use bolero::{check, produce_with, TypeGenerator};
use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::guidance::{
    BehaviourId, Guidance, GuidanceConfig, LawOutcome, Mode, RoutedScan, TickInput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::model::Vehicle;
use fieldguide::perception::edge::{
    EdgeConfig, EdgeDetector, EdgeDetectorConfig, EdgeOutcome, Side, MAX_COORDINATE,
};
use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector, FurrowParams, RowLines, Rows};
use fieldguide::perception::{
    AnyDetector, AnyDetectorConfig, Detection, Detector, HeldLine, RangeLimits, Scan, Verdict,
};
use fieldguide::presets::{pierre2022_both, Pierre2022Params, EDGE, FURROW};
use fieldguide::{
    Frame, Meters, Odom, Point2, Pose2, Precondition, Radians, Robot, Seconds, TrackingError,
    Transform2, World,
};

/// Rays of every real scan.
const RAYS: usize = 360;

/// The horizontal LiDAR's mount, 1.2 m ahead of O.
const MOUNT_X: f64 = 1.2;

/// Scans of one furrow sequence (the detector accumulates them).
const SEQUENCE: usize = 10;

// ---------------------------------------------------------------- inputs --

/// A value that applies in one case out of eight: the rest of the input
/// stays realistic often enough for the detectors to detect (a furrow
/// needs five good scans in a row), while mutation still reaches it.
#[derive(Debug, Clone, Copy, TypeGenerator)]
struct Rare<T> {
    roll: u8,
    value: T,
}

impl<T> Rare<T> {
    fn get(&self) -> Option<&T> {
        (self.roll < 32).then_some(&self.value)
    }
}

/// One range as a faulty or hostile LiDAR may send it.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Wild {
    /// An ordinary range, k mm.
    Millimetres(u16),
    Nan,
    Infinity,
    NegInfinity,
    /// −k cm.
    Negative(u16),
    Zero,
    NegZero,
    /// A subnormal (bits k + 1).
    Subnormal(u32),
    /// 10^−k, down to 1e−300.
    Tiny(u8),
    /// 10^k, up to 1e300, either sign.
    Huge(u8, bool),
    Max,
    /// The limits themselves and their neighbours.
    AtMin,
    AtMax,
    BelowMax,
    /// Any bit pattern.
    Bits(u64),
}

impl Wild {
    fn value(self, limits: &RangeLimits) -> f64 {
        match self {
            Self::Millimetres(k) => f64::from(k) / 1000.0,
            Self::Nan => f64::NAN,
            Self::Infinity => f64::INFINITY,
            Self::NegInfinity => f64::NEG_INFINITY,
            Self::Negative(k) => -f64::from(k) / 100.0,
            Self::Zero => 0.0,
            Self::NegZero => -0.0,
            Self::Subnormal(k) => f64::from_bits(u64::from(k) + 1),
            Self::Tiny(k) => 10_f64.powi(-i32::from(k % 151) * 2),
            Self::Huge(k, negative) => huge(k, negative),
            Self::Max => f64::MAX,
            Self::AtMin => limits.min(),
            Self::AtMax => limits.max(),
            // The largest `f64` below max (max > 0).
            Self::BelowMax => f64::from_bits(limits.max().to_bits() - 1),
            Self::Bits(b) => f64::from_bits(b),
        }
    }
}

/// ±10^(2 (k mod 151)), up to 1e300.
fn huge(k: u8, negative: bool) -> f64 {
    let v = 10_f64.powi(i32::from(k % 151) * 2);
    if negative {
        -v
    } else {
        v
    }
}

/// A coordinate or angle of a pose or a mount, ordinary to extreme.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Coord {
    /// k cm.
    Near(i16),
    /// k m.
    Far(i32),
    /// ±10^k, up to 1e300.
    Huge(u8, bool),
    Max(bool),
    Subnormal(u32),
    /// Any bit pattern (NaN and infinities are refused by the constructors).
    Bits(u64),
}

impl Coord {
    fn value(self) -> f64 {
        match self {
            Self::Near(k) => f64::from(k) / 100.0,
            Self::Far(k) => f64::from(k),
            Self::Huge(k, negative) => huge(k, negative),
            Self::Max(negative) => {
                if negative {
                    f64::MIN
                } else {
                    f64::MAX
                }
            }
            Self::Subnormal(k) => f64::from_bits(u64::from(k) + 1),
            Self::Bits(b) => f64::from_bits(b),
        }
    }
}

/// A pose: a small jitter about a nominal one, or (rarely) anything.
#[derive(Debug, Clone, Copy, TypeGenerator)]
struct PoseCase {
    /// The nominal pose moved by (k mm, k mm, k mrad).
    jitter: (i8, i8, i8),
    any: Rare<(Coord, Coord, Coord)>,
}

impl PoseCase {
    /// The pose about `nominal` (x, y, heading), or `None` when its
    /// constructor refuses it (it must, exactly for non-finite values).
    fn pose<F: Frame>(self, nominal: (f64, f64, f64)) -> Option<Pose2<F>> {
        let (dx, dy, dh) = self.jitter;
        let (x, y, h) = match self.any.get() {
            None => (
                nominal.0 + f64::from(dx) / 1000.0,
                nominal.1 + f64::from(dy) / 1000.0,
                nominal.2 + f64::from(dh) / 1000.0,
            ),
            Some((x, y, h)) => (x.value(), y.value(), h.value()),
        };
        let pose = Pose2::new(x, y, h);
        let finite = x.is_finite() && y.is_finite() && h.is_finite();
        assert_eq!(pose.is_ok(), finite, "({x}, {y}, {h}): {pose:?}");
        let pose = pose.ok()?;
        assert!(pose.heading.get().abs() <= PI);
        Some(pose)
    }
}

/// How many rays the scan has.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum RayCount {
    /// The real scan's.
    Real,
    /// 0 to 255 rays.
    Few(u8),
    /// Exactly the larger detector's capacity (512), and one more.
    Capacity,
    JustOver,
    /// Up to 4 095 rays.
    Many(u16),
}

impl RayCount {
    fn count(self) -> usize {
        match self {
            Self::Real => RAYS,
            Self::Few(k) => usize::from(k),
            Self::Capacity => 512,
            Self::JustOver => 513,
            Self::Many(k) => usize::from(k % 4096),
        }
    }
}

/// The scan's angles.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Angles {
    /// The sensor's own.
    Real,
    /// The same rays read the other way round (a LiDAR mounted upside down).
    Reversed,
    /// Every ray at nearly the same angle (k µrad apart) about `start`.
    Bunched(i16, u8),
    Any(Coord, Coord),
}

/// The sensor's valid interval of ranges.
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Limits {
    Real,
    /// [0, 1e6), the widest accepted.
    Widest,
    /// [k dm, k dm + (j + 1) dm).
    Tight(u8, u8),
    /// Any two values (most are refused, LIB-SCAN).
    Any(Coord, Coord),
}

impl Limits {
    /// The limits, or `None` when `RangeLimits::new` refuses them (it must,
    /// exactly unless 0 ≤ min < max ≤ 1e6).
    fn limits(self, real: RangeLimits) -> Option<RangeLimits> {
        let (lo, hi) = match self {
            Self::Real => return Some(real),
            Self::Widest => (0.0, fieldguide::perception::MAX_RANGE),
            Self::Tight(lo, span) => (
                f64::from(lo) / 10.0,
                f64::from(lo) / 10.0 + f64::from(span) / 10.0 + 0.1,
            ),
            Self::Any(lo, hi) => (lo.value(), hi.value()),
        };
        let (Ok(min), Ok(max)) = (Meters::new(lo), Meters::new(hi)) else {
            return None;
        };
        let limits = RangeLimits::new(min, max);
        let valid = lo >= 0.0 && lo < hi && hi <= fieldguide::perception::MAX_RANGE;
        match limits {
            Ok(l) => {
                assert!(valid, "[{lo}, {hi}) accepted");
                Some(l)
            }
            Err(e) => {
                assert!(!valid && e.requirement == "LIB-SCAN", "[{lo}, {hi}): {e}");
                None
            }
        }
    }
}

/// One scan: a real one (chosen by index) with a few rays replaced by
/// faults, and (rarely) distorted.
#[derive(Debug, Clone, TypeGenerator)]
struct ScanCase {
    base: u8,
    #[generator(produce_with::<Vec<(u16, Wild)>>().len(0usize..=8))]
    faults: Vec<(u16, Wild)>,
    distortion: Rare<Distortion>,
}

/// A scan cut or stretched to a ray count (new rays get `fill`), every
/// `stride`-th ray replaced by `fill`, any angles and limits.
#[derive(Debug, Clone, Copy, TypeGenerator)]
struct Distortion {
    rays: RayCount,
    fill: Wild,
    /// Every `k`-th ray (k ≥ 2) replaced by `fill`.
    stride: Option<u8>,
    angles: Angles,
    limits: Limits,
}

impl Distortion {
    /// The real scan as it is.
    const NONE: Self = Self {
        rays: RayCount::Real,
        fill: Wild::Infinity,
        stride: None,
        angles: Angles::Real,
        limits: Limits::Real,
    };
}

/// A scan's ranges and geometry, owned: [`Self::scan`] borrows it.
struct OwnedScan {
    ranges: Vec<f64>,
    start: f64,
    increment: f64,
    limits: Option<RangeLimits>,
}

impl OwnedScan {
    /// The scan of `case` over real scans `bases` of a sensor whose first
    /// ray, increment and limits are `real`.
    fn new(case: &ScanCase, base: &[f64], real: (f64, f64, RangeLimits)) -> Self {
        let d = case.distortion.get().copied().unwrap_or(Distortion::NONE);
        let limits = d.limits.limits(real.2);
        let fill = d.fill.value(&limits.unwrap_or(real.2));
        let mut ranges: Vec<f64> = base.iter().copied().take(d.rays.count()).collect();
        ranges.resize(d.rays.count(), fill);
        if let Some(k) = d.stride.filter(|k| *k >= 2) {
            for r in ranges.iter_mut().step_by(usize::from(k)) {
                *r = fill;
            }
        }
        let n = ranges.len();
        for &(i, wild) in &case.faults {
            if let Some(r) = ranges.get_mut(usize::from(i) % n.max(1)) {
                *r = wild.value(&limits.unwrap_or(real.2));
            }
        }
        let (start, increment) = match d.angles {
            Angles::Real => (real.0, real.1),
            Angles::Reversed => (real.0 + real.1 * (RAYS as f64 - 1.0), -real.1),
            Angles::Bunched(start, k) => (f64::from(start) / 1000.0, f64::from(k) * 1e-6),
            Angles::Any(start, increment) => (start.value(), increment.value()),
        };
        Self {
            ranges,
            start,
            increment,
            limits,
        }
    }

    /// The scan, or `None` when its angles or limits are refused (exactly
    /// when not finite, or limits out of order).
    fn scan(&self) -> Option<Scan<'_>> {
        let start = Radians::new(self.start);
        let increment = Radians::new(self.increment);
        assert_eq!(start.is_ok(), self.start.is_finite());
        assert_eq!(increment.is_ok(), self.increment.is_finite());
        Some(Scan {
            start: start.ok()?,
            increment: increment.ok()?,
            ranges: &self.ranges,
            limits: self.limits?,
        })
    }

    /// How many rays the limits accept.
    fn valid(&self) -> usize {
        self.limits
            .map_or(0, |l| self.ranges.iter().filter(|r| l.accepts(**r)).count())
    }
}

// ------------------------------------------------------------ real scans --

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

/// The horizontal LiDAR's valid ranges.
fn sensor_limits() -> RangeLimits {
    RangeLimits::new(m(0.05), m(30.0)).unwrap()
}

/// The inclined LiDAR's valid ranges.
fn furrow_limits() -> RangeLimits {
    RangeLimits::new(m(0.1), m(20.0)).unwrap()
}

fn edge_geometry() -> (f64, f64, RangeLimits) {
    (-PI, TAU / RAYS as f64, sensor_limits())
}

fn furrow_lidar() -> furrow_common::Lidar {
    furrow_common::Lidar::centred(RAYS, FRAC_PI_2)
}

fn furrow_geometry() -> (f64, f64, RangeLimits) {
    let l = furrow_lidar();
    (l.angle_min, l.increment, furrow_limits())
}

/// Real horizontal scans: straight walls left and right at 1, 1.5 and
/// 2.5 m, turned by −0.3, 0 and 0.3 rad, each also as a hedge whose
/// returns scatter by up to ±0.1, ±0.3, ±0.45 and ±0.6 m, and a scan of
/// no return.
fn walls() -> &'static [Vec<f64>] {
    static WALLS: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    WALLS.get_or_init(|| {
        let (start, increment, _) = edge_geometry();
        let mut out = vec![vec![f64::INFINITY; RAYS]];
        // A fixed pseudo-random sequence in [-1, 1) (a linear congruence).
        let mut state = 0x2545_f491_u64;
        let mut scatter = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            (state >> 11) as f64 / (1_u64 << 52) as f64 - 1.0
        };
        for side in [1.0, -1.0] {
            for dist in [1.0, 1.5, 2.5] {
                for angle in [-0.3_f64, 0.0, 0.3] {
                    let n = (-side * angle.sin(), side * angle.cos());
                    let wall = edge_support::cast_line(
                        (MOUNT_X, 0.0, 0.0),
                        n,
                        dist,
                        start,
                        increment,
                        RAYS,
                        30.0,
                    );
                    for amplitude in [0.1, 0.3, 0.45, 0.6] {
                        let hedge = wall.iter().map(|r| r + amplitude * scatter()).collect();
                        out.push(hedge);
                    }
                    out.push(wall);
                }
            }
        }
        out
    })
}

/// Real inclined scans, [`SEQUENCE`] per field, taken at odometry poses
/// 0.1 m apart ([`furrow_pose`]): two rows 0.75 m apart, the same 0.1 m to
/// the left, one row, and bare ground.
fn fields() -> &'static [[Vec<f64>; SEQUENCE]] {
    static FIELDS: OnceLock<Vec<[Vec<f64>; SEQUENCE]>> = OnceLock::new();
    FIELDS.get_or_init(|| {
        let ridge = |center_y| furrow_common::Ridge {
            center_y,
            half_width: 0.08,
            height: 0.4,
        };
        let layouts = [
            vec![ridge(-0.375), ridge(0.375)],
            vec![ridge(-0.275), ridge(0.475)],
            vec![ridge(0.0)],
            vec![],
        ];
        layouts
            .iter()
            .map(|rows| {
                core::array::from_fn(|k| {
                    furrow_common::ridge_scan(
                        &FurrowParams::table2(),
                        &furrow_lidar(),
                        furrow_pose(k),
                        rows,
                    )
                })
            })
            .collect()
    })
}

/// The nominal odometry pose of scan `k` of a furrow sequence.
fn furrow_pose(k: usize) -> (f64, f64, f64) {
    (0.1 * k as f64, 0.0, 0.0)
}

fn edge_scan(case: &ScanCase) -> OwnedScan {
    let bases = walls();
    OwnedScan::new(
        case,
        &bases[usize::from(case.base) % bases.len()],
        edge_geometry(),
    )
}

fn furrow_scan(case: &ScanCase, k: usize) -> OwnedScan {
    let bases = fields();
    let field = &bases[usize::from(case.base) % bases.len()];
    OwnedScan::new(case, &field[k % SEQUENCE], furrow_geometry())
}

// ------------------------------------------------------------ the claims --

fn assert_finite_error(e: &TrackingError) {
    for v in [
        e.y.get(),
        e.angular_deviation.get(),
        e.curvature.get(),
        e.curvature_ahead.get(),
    ] {
        assert!(v.is_finite(), "{e:?}");
    }
    assert!(e.angular_deviation.get().abs() <= PI, "{e:?}");
}

fn assert_refusal(e: &Precondition, allowed: &[&str]) {
    assert!(allowed.contains(&e.requirement), "{e}");
}

/// An edge detector's outcome on `scan` (of `valid` accepted rays), as
/// EDGE-SCAN, EDGE-DETECT and LIB-FINITE claim it.
fn check_edge<const N: usize, const M: usize>(
    detector: &mut EdgeDetector<N, M>,
    scan: &Scan<'_>,
    valid: usize,
    odometry: &Pose2<Odom>,
) {
    match detector.detect(scan, odometry) {
        Ok(outcome) => {
            assert!(valid <= N, "{valid} valid rays in a buffer of {N}");
            assert_eq!(detector.points().len(), valid);
            for p in detector.points() {
                assert!(p.x().abs() <= MAX_COORDINATE && p.y().abs() <= MAX_COORDINATE);
            }
            check_edge_outcome(&outcome, detector.chain().points(), M);
        }
        Err(e) => {
            assert_refusal(&e, &["EDGE-SCAN", "LIB-FINITE"]);
            assert!(detector.chain().is_empty());
        }
    }
}

fn check_edge_outcome(outcome: &EdgeOutcome, chain: &[Point2<Robot>], capacity: usize) {
    assert_eq!(outcome.chain_points, chain.len());
    assert!(chain.len() <= capacity);
    assert_eq!(outcome.fit.is_none(), outcome.verdict == Verdict::Absent);
    if let Some(fit) = outcome.fit {
        let p = fit.parabola;
        assert!(
            p.a.is_finite() && p.b.is_finite() && p.c.is_finite(),
            "{p:?}"
        );
        let q = fit.quality;
        for v in [q.length.get(), q.width.get(), q.residual_std.get()] {
            assert!(v.is_finite() && v >= 0.0, "{q:?}");
        }
        assert_finite_error(&fit.error);
    }
    assert_eq!(
        outcome.usable_error().is_some(),
        outcome.verdict.estimate_is_valid()
    );
}

/// One detection through the generic seam, as GD-DETECTOR claims it: an
/// error and a line exactly when the verdict is not Absent, finite, and the
/// line moved anywhere gives a finite error or an error.
fn check_detection<L: HeldLine>(d: &Detection<L>, moves: &[PoseCase]) {
    let absent = d.verdict == Verdict::Absent;
    assert_eq!(d.error.is_none(), absent);
    assert_eq!(d.line.is_none(), absent);
    if let Some(e) = &d.error {
        assert_finite_error(e);
    }
    if let Some(q) = d.quality {
        assert!(q.is_finite(), "quality {q}");
    }
    let Some(line) = d.line else { return };
    for case in moves {
        let Some(pose) = case.pose::<Robot>((0.0, 0.0, 0.0)) else {
            continue;
        };
        match line.error_at(&pose) {
            Ok(e) => assert_finite_error(&e),
            Err(e) => assert_refusal(&e, &["LIB-FINITE"]),
        }
    }
    // Not moved at all: the detection's own error.
    let here = line.error_at(&Pose2::new(0.0, 0.0, 0.0).unwrap()).unwrap();
    let own = d.error.unwrap();
    assert!((here.y.get() - own.y.get()).abs() <= 1e-9 * (1.0 + own.y.get().abs()));
}

fn row_lines_finite(lines: &RowLines) -> bool {
    let finite = |l: &fieldguide::perception::furrow::lines::RowLine| {
        l.slope().is_finite() && l.intercept().get().is_finite()
    };
    match lines {
        RowLines::One(l) => finite(l),
        RowLines::Two(p) => finite(&p.left) && finite(&p.right),
    }
}

// ---------------------------------------------------------- edge target --

#[derive(Debug, Clone, TypeGenerator)]
struct EdgeCase {
    side: bool,
    /// The LiDAR turned half a turn on its mount.
    flipped: bool,
    scan: ScanCase,
    odometry: PoseCase,
}

fn edge_config(side: bool, flipped: bool) -> EdgeDetectorConfig {
    EdgeDetectorConfig {
        edge: EdgeConfig::pierre2022().unwrap(),
        mount: Transform2::new(MOUNT_X, 0.0, if flipped { PI } else { 0.0 }).unwrap(),
        side: if side { Side::Left } else { Side::Right },
    }
}

/// The edge detector, with the simulator's capacities' order of magnitude
/// (512 points, 64 chain points) and with small ones (64, 8) that real
/// scans overflow, on any scan at any odometry pose.
#[test]
fn fuzz_edge_detector() {
    check!().with_type::<EdgeCase>().for_each(|case| {
        let owned = edge_scan(&case.scan);
        let Some(scan) = owned.scan() else { return };
        let Some(odometry) = case.odometry.pose::<Odom>((0.0, 0.0, 0.0)) else {
            return;
        };
        let config = edge_config(case.side, case.flipped);
        let valid = owned.valid();
        check_edge(
            &mut EdgeDetector::<512, 64>::new(config),
            &scan,
            valid,
            &odometry,
        );
        check_edge(
            &mut EdgeDetector::<64, 8>::new(config),
            &scan,
            valid,
            &odometry,
        );
    });
}

// -------------------------------------------------------- furrow target --

#[derive(Debug, Clone, TypeGenerator)]
struct FurrowCase {
    one_row: bool,
    #[generator(produce_with::<Vec<(ScanCase, PoseCase)>>().len(1usize..=SEQUENCE))]
    scans: Vec<(ScanCase, PoseCase)>,
}

fn furrow_config(one_row: bool) -> FurrowConfig {
    let mut params = FurrowParams::table2();
    if one_row {
        params.rows = Rows::One;
    }
    FurrowConfig::new(&params).unwrap()
}

/// The furrow detector (512 window rays, 32 kept selections) over a
/// sequence of scans and odometry poses: FUR-SCAN refusals leave the state
/// as it was, the accumulation stays within n, and every detection holds
/// finite values only.
#[test]
fn fuzz_furrow_detector() {
    check!().with_type::<FurrowCase>().for_each(|case| {
        let config = furrow_config(case.one_row);
        let n = config.params().averaged_scans;
        let mut detector = FurrowDetector::<512, 32>::new(config).unwrap();
        for (k, (scan_case, pose_case)) in case.scans.iter().enumerate() {
            let owned = furrow_scan(scan_case, k);
            let Some(scan) = owned.scan() else { continue };
            let Some(odometry) = pose_case.pose::<Odom>(furrow_pose(k)) else {
                continue;
            };
            let before = detector.accumulated();
            match detector.detect(&scan, &odometry) {
                Ok(d) => {
                    assert!(scan.increment.get() > 0.0);
                    assert!(d.window.count <= 512);
                    assert_eq!(d.error.is_none(), d.verdict == Verdict::Absent);
                    assert_eq!(d.lines.is_none(), d.verdict == Verdict::Absent);
                    if let Some(e) = &d.error {
                        assert_finite_error(e);
                    }
                    if let Some(lines) = &d.lines {
                        assert!(row_lines_finite(lines), "{lines:?}");
                    }
                    if let Some(q) = d.quality {
                        assert!(q.is_finite() && q.abs() <= 1.0, "quality {q}");
                    }
                    assert_eq!(d.quality.is_some(), d.selected.is_some());
                }
                Err(e) => {
                    assert_refusal(&e, &["FUR-SCAN", "LIB-FINITE"]);
                    if e.requirement == "FUR-SCAN" {
                        assert_eq!(detector.accumulated(), before, "{e}");
                    }
                }
            }
            assert!(detector.accumulated() <= n);
        }
    });
}

// ------------------------------------------------------ the rows detector --

/// One crop's drive: the front and back ranges of each scan.
type Drive = Vec<(Vec<f64>, Vec<f64>)>;

/// Real front and back scans of the paper's crops (`crop_scans`), the robot
/// between the middle rows, [`SEQUENCE`] per crop, 2.5 cm apart.
fn crop_drives() -> &'static [Drive] {
    static DRIVES: OnceLock<Vec<Drive>> = OnceLock::new();
    DRIVES.get_or_init(|| {
        (1..=4)
            .map(|n| {
                let field = crop_scans::crop(n, 7, 0.75).build();
                let lidar = crop_scans::Lidar::paper();
                (0..SEQUENCE)
                    .map(|k| {
                        let robot = field.between(1, 2, 2.0 + 0.025 * k as f64);
                        let front =
                            field.cast(&robot, &crop_scans::Mount::front(0.3), &lidar, k as u64);
                        let back = field.cast(
                            &robot,
                            &crop_scans::Mount::back(0.3),
                            &lidar,
                            k as u64 + 99,
                        );
                        (front.ranges, back.ranges)
                    })
                    .collect()
            })
            .collect()
    })
}

#[derive(Debug, Clone, TypeGenerator)]
struct RowsCase {
    variant: u8,
    both_lidars: bool,
    crop: u8,
    #[generator(produce_with::<Vec<(ScanCase, ScanCase, PoseCase)>>().len(1usize..=SEQUENCE))]
    scans: Vec<(ScanCase, ScanCase, PoseCase)>,
}

/// The rows detector (any variant, one LiDAR or two) over a sequence of
/// real crop scans with faults and distortions, and any odometry: a
/// detection holds finite values only, the filtered rows and the row
/// distance are finite, and a refusal names ROWS-MOUNTS or LIB-FINITE.
#[test]
fn fuzz_rows_detector() {
    use fieldguide::perception::rows::ruby::Variant;
    use fieldguide::perception::rows::spacing::SpacingConfig;
    use fieldguide::perception::rows::{RowsConfig, RowsDetector, RowsParams};
    check!().with_type::<RowsCase>().for_each(|case| {
        let variant = Variant::ALL[usize::from(case.variant) % Variant::ALL.len()];
        let front = Transform2::new(0.3, 0.0, 0.0).unwrap();
        let mut params = RowsParams::authors(variant, front);
        if case.both_lidars {
            params = params.with_second(Transform2::new(-0.3, 0.0, PI).unwrap());
        }
        // Two scans measure the row distance, so that short sequences reach
        // the filter; any odometry is taken as at rest.
        params.spacing = SpacingConfig::new(0.05, 0.25, 2, 4).unwrap();
        params.still = m(1e6);
        let mut detector = RowsDetector::<1024>::new(RowsConfig::new(params).unwrap());
        let lidar = crop_scans::Lidar::paper();
        let real = (
            lidar.angle(0),
            lidar.angle(1) - lidar.angle(0),
            RangeLimits::new(m(0.1), m(4.0)).unwrap(),
        );
        let drive = &crop_drives()[usize::from(case.crop) % 4];
        for (k, (f, b, pose)) in case.scans.iter().enumerate() {
            let (fr, br) = &drive[k % drive.len()];
            let (fo, bo) = (OwnedScan::new(f, fr, real), OwnedScan::new(b, br, real));
            let (Some(fs), Some(bs)) = (fo.scan(), bo.scan()) else {
                continue;
            };
            let Some(odometry) = pose.pose::<Odom>((0.0, 0.0, 0.0)) else {
                continue;
            };
            let scans = if case.both_lidars {
                vec![fs, bs]
            } else {
                vec![fs]
            };
            match detector.observe_scans(&scans, &odometry) {
                Ok(out) => {
                    let d = out.detection;
                    assert_eq!(d.error.is_none(), d.verdict == Verdict::Absent);
                    assert_eq!(d.line.is_none(), d.verdict == Verdict::Absent);
                    if let Some(e) = &d.error {
                        assert_finite_error(e);
                    }
                    if let Some(lines) = &d.line {
                        assert!(row_lines_finite(lines), "{lines:?}");
                    }
                    if let Some(q) = d.quality {
                        assert!(q.is_finite() && (0.0..=8.0).contains(&q), "quality {q}");
                    }
                    assert!(out.found.energy.is_finite());
                    assert!(out.gathered.kept <= 1024);
                }
                Err(e) => assert_refusal(&e, &["LIB-FINITE"]),
            }
            if let Some(rows) = detector.rows() {
                assert!(rows
                    .iter()
                    .all(|r| r.slope().is_finite() && r.intercept().get().is_finite()));
            }
            if let Some(d) = detector.row_distance() {
                assert!(d.get().is_finite() && d.get() > 0.0);
            }
        }
    });
}

// ---------------------------------------------------------- vine target --

/// Real inclined scans of vineyards (`vine_scans`, Table 1's mount): flat
/// ground, a cross slope with bumps, and rows with a gap, [`SEQUENCE`] per
/// vineyard, the robot 0.1 m off the row, 0.1 m apart.
fn vineyards() -> &'static [Vec<Vec<f64>>] {
    static VINES: OnceLock<Vec<Vec<Vec<f64>>>> = OnceLock::new();
    VINES.get_or_init(|| {
        let mut bumpy = vine_scans::World::ground(0.03, 0.2);
        vine_scans::SplitMix64(3).bumps(&mut bumpy, 40, 0.2, 0.08, (0.0, 6.0));
        let worlds = [
            vine_scans::vineyard(vine_scans::World::ground(0.0, 0.0), 2.2, 0.25, &[]),
            vine_scans::vineyard(bumpy, 2.2, 0.25, &[]),
            vine_scans::vineyard(
                vine_scans::World::ground(0.0, -0.1),
                2.2,
                0.12,
                &[(2.0, 4.0)],
            ),
        ];
        let lidar = vine_scans::Lidar::table1();
        worlds
            .iter()
            .map(|w| {
                (0..SEQUENCE)
                    .map(|k| lidar.cast(w, (0.1 * k as f64, 0.1, 0.0)))
                    .collect()
            })
            .collect()
    })
}

fn vine_scan(case: &ScanCase, k: usize) -> OwnedScan {
    let bases = vineyards();
    let lidar = vine_scans::Lidar::table1();
    let limits = RangeLimits::new(
        Meters::new(0.05).unwrap(),
        Meters::new(lidar.max_range).unwrap(),
    )
    .unwrap();
    OwnedScan::new(
        case,
        &bases[usize::from(case.base) % bases.len()][k % SEQUENCE],
        (lidar.start, lidar.increment, limits),
    )
}

#[derive(Debug, Clone, TypeGenerator)]
struct VineCase {
    winter: bool,
    #[generator(produce_with::<Vec<(ScanCase, PoseCase)>>().len(1usize..=SEQUENCE))]
    scans: Vec<(ScanCase, PoseCase)>,
    #[generator(produce_with::<Vec<PoseCase>>().len(0usize..=4))]
    moves: Vec<PoseCase>,
}

/// The vine detector (256 field-of-view rays, 64 set-points) over a
/// sequence of vineyard scans with faults and distortions and any odometry:
/// each detection keeps GD-DETECTOR's claims, a FUR-SCAN refusal leaves the
/// set-points as they were, and they never exceed their capacity.
#[test]
fn fuzz_vine_detector() {
    use fieldguide::perception::vine::{VineConfig, VineDetector, VineParams};
    check!().with_type::<VineCase>().for_each(|case| {
        let params = if case.winter {
            VineParams::winter()
        } else {
            VineParams::summer()
        };
        let mut detector = VineDetector::<256, 64>::new(VineConfig::new(&params).unwrap()).unwrap();
        for (k, (scan_case, pose_case)) in case.scans.iter().enumerate() {
            let owned = vine_scan(scan_case, k);
            let Some(scan) = owned.scan() else { continue };
            let Some(odometry) = pose_case.pose::<Odom>((0.1 * k as f64, 0.1, 0.0)) else {
                continue;
            };
            let before: Vec<_> = detector.set_points().iter().copied().collect();
            match detector.observe(&scan, &odometry) {
                Ok(d) => check_detection(&d, &case.moves),
                Err(e) => {
                    assert_refusal(&e, &["FUR-SCAN", "LIB-FINITE"]);
                    if e.requirement == "FUR-SCAN" {
                        let after: Vec<_> = detector.set_points().iter().copied().collect();
                        assert_eq!(after, before, "{e}");
                    }
                }
            }
            assert!(detector.set_points().len() <= 64);
            assert!(detector
                .set_points()
                .iter()
                .all(|p| p.score.is_finite() && p.score > 0.0 && p.score <= 1.0));
        }
    });
}

// ---------------------------------------------------- the generic seam --

#[derive(Debug, Clone, TypeGenerator)]
struct SeamCase {
    furrow: bool,
    side: bool,
    #[generator(produce_with::<Vec<(ScanCase, PoseCase)>>().len(1usize..=SEQUENCE))]
    scans: Vec<(ScanCase, PoseCase)>,
    #[generator(produce_with::<Vec<PoseCase>>().len(0usize..=4))]
    moves: Vec<PoseCase>,
}

/// Either detector in an `AnyDetector` slot through `Detector::observe`
/// (GD-DETECTOR), its held line moved to any pose.
#[test]
fn fuzz_any_detector() {
    check!().with_type::<SeamCase>().for_each(|case| {
        let config = if case.furrow {
            AnyDetectorConfig::Furrow(furrow_config(false))
        } else {
            AnyDetectorConfig::Edge(edge_config(case.side, false))
        };
        let mut detector = AnyDetector::<512, 64, 512, 32>::configure(&config).unwrap();
        for (k, (scan_case, pose_case)) in case.scans.iter().enumerate() {
            let (owned, nominal) = if case.furrow {
                (furrow_scan(scan_case, k), furrow_pose(k))
            } else {
                (edge_scan(scan_case), (0.0, 0.0, 0.0))
            };
            let Some(scan) = owned.scan() else { continue };
            let Some(odometry) = pose_case.pose::<Odom>(nominal) else {
                continue;
            };
            match detector.observe(&scan, &odometry) {
                Ok(d) => check_detection(&d, &case.moves),
                Err(e) => assert_refusal(&e, &["EDGE-SCAN", "FUR-SCAN", "LIB-FINITE"]),
            }
        }
    });
}

// -------------------------------------------------------- the pipeline --

/// Path length, points.
const PATH_N: usize = 256;

/// A straight path along the world x axis from −20 m to 300 m.
fn straight_path() -> &'static ReferencePath<PATH_N> {
    static PATH: OnceLock<ReferencePath<PATH_N>> = OnceLock::new();
    PATH.get_or_init(|| {
        let points: Vec<Point2<World>> = (0..=64)
            .map(|i| Point2::new(-20.0 + 5.0 * f64::from(i), 0.0).unwrap())
            .collect();
        ReferencePath::from_waypoints(&points, PathConfig::default()).unwrap()
    })
}

type Config = GuidanceConfig<AnyDetectorConfig, BacksteppingConfig, 2>;

/// The pipelines fuzzed: both behaviours of the presets in either priority,
/// with the paper's delays or delays of one tick (so that a short sequence
/// reaches the behaviours and Stop), with and without a plan check.
fn configs() -> &'static [Config] {
    static CONFIGS: OnceLock<Vec<Config>> = OnceLock::new();
    CONFIGS.get_or_init(|| {
        let mount = Transform2::new(MOUNT_X, 0.0, 0.0).unwrap();
        let mut out = Vec::new();
        for priority in [[FURROW, EDGE], [EDGE, FURROW]] {
            for short in [false, true] {
                let mut params: Pierre2022Params = pierre2022_both(Side::Left, mount).unwrap();
                params.priority = heapless::Vec::from_slice(&priority).unwrap();
                if short {
                    let tick = Seconds::new(0.01).unwrap();
                    for b in &mut params.behaviours {
                        b.enter_delay = tick;
                        b.exit_delay = tick;
                    }
                    params.stop_delay = Seconds::new(0.03).unwrap();
                }
                out.push(GuidanceConfig::new(&params).unwrap());
            }
        }
        out
    })
}

/// A tick's scan for one behaviour, if any, routed to it or (rarely)
/// misrouted.
#[derive(Debug, Clone, TypeGenerator)]
struct Route {
    scan: Option<ScanCase>,
    misroute: Rare<Misroute>,
}

/// Malformed routing (GD-INPUT).
#[derive(Debug, Clone, Copy, TypeGenerator)]
enum Misroute {
    /// To a behaviour that is not configured.
    Stray(u8),
    /// To its behaviour twice.
    Twice,
}

#[derive(Debug, Clone, TypeGenerator)]
struct Tick {
    edge: Route,
    furrow: Route,
    /// The odometry pose moved by a GNSS error; rarely no fix.
    gnss: PoseCase,
    lost: Rare<()>,
    /// The robot's pose 0.1 m on from the last (the furrow scans' spacing),
    /// jittered, or anything.
    odometry: PoseCase,
    /// The sideslip estimate, k cmrad, or (rarely) anything.
    extra: (i8, i8),
    wild_extra: Rare<(Coord, Coord)>,
}

#[derive(Debug, Clone, TypeGenerator)]
struct PipelineCase {
    config: u8,
    /// Start this far left of the path, k cm.
    lateral: i8,
    #[generator(produce_with::<Vec<Tick>>().len(1usize..=SEQUENCE))]
    ticks: Vec<Tick>,
}

/// The ranges of one tick's scans: (behaviour, ranges, routed twice).
fn tick_scans(tick: &Tick, k: usize) -> Vec<(BehaviourId, OwnedScan, bool)> {
    let mut out = Vec::new();
    for (route, own) in [(&tick.edge, EDGE), (&tick.furrow, FURROW)] {
        let owned = |case: &ScanCase| {
            if own == EDGE {
                edge_scan(case)
            } else {
                furrow_scan(case, k)
            }
        };
        let Some(case) = &route.scan else { continue };
        match route.misroute.get() {
            None => out.push((own, owned(case), false)),
            // Ids 1 and 2 are configured: any other is stray.
            Some(Misroute::Stray(id)) => {
                out.push((BehaviourId(3 + u16::from(*id)), owned(case), false))
            }
            Some(Misroute::Twice) => out.push((own, owned(case), true)),
        }
    }
    out
}

/// The tick's sideslip and whether the law accepts it, or `None` when it
/// is not finite.
fn sideslip(tick: &Tick) -> Option<(Sideslip, bool)> {
    let (front, rear) = match tick.wild_extra.get() {
        None => (
            f64::from(tick.extra.0) / 100.0,
            f64::from(tick.extra.1) / 100.0,
        ),
        Some((f, r)) => (f.value(), r.value()),
    };
    let valid = front.abs() < FRAC_PI_2 && rear.abs() < FRAC_PI_2;
    Some((
        Sideslip {
            front: Radians::new(front).ok()?,
            rear: Radians::new(rear).ok()?,
        },
        valid,
    ))
}

/// The full pipeline of the presets (edge following and furrow pursuing,
/// backstepping on the 2 m bicycle) over a sequence of ticks: scans routed
/// to their behaviours, to none or twice, GNSS lost or anywhere, odometry
/// in small steps or jumps, any sideslip. Only malformed input is refused
/// (GD-INPUT), and then nothing changes; every output is finite and every
/// command within the vehicle's limits, at zero speed in Stop.
#[test]
fn fuzz_guidance_sequence() {
    check!().with_type::<PipelineCase>().for_each(|case| {
        let configs = configs();
        let config = configs[usize::from(case.config) % configs.len()].clone();
        let vehicle = config.params().vehicle;
        let mut guidance: Guidance<'_, PATH_N, AnyDetector, BacksteppingConfig, 2> =
            Guidance::new(config, straight_path()).unwrap();
        let lateral = f64::from(case.lateral) / 100.0;
        for (k, tick) in case.ticks.iter().enumerate() {
            let (x, _, h) = furrow_pose(k);
            let Some(odometry) = tick.odometry.pose::<Odom>((x, lateral, h)) else {
                continue;
            };
            let here = (
                odometry.position.x(),
                odometry.position.y(),
                odometry.heading.get(),
            );
            let gnss = match tick.lost.get() {
                Some(()) => None,
                None => match tick.gnss.pose::<World>(here) {
                    Some(pose) => Some(pose),
                    None => continue,
                },
            };
            let Some((extra, extra_valid)) = sideslip(tick) else {
                continue;
            };
            let owned = tick_scans(tick, k);
            let mut routed = Vec::new();
            for (behaviour, scan, twice) in &owned {
                let Some(scan) = scan.scan() else { continue };
                routed.push(RoutedScan {
                    behaviour: *behaviour,
                    scan,
                });
                if *twice {
                    routed.push(RoutedScan {
                        behaviour: *behaviour,
                        scan,
                    });
                }
            }
            let malformed = routed.iter().enumerate().any(|(i, r)| {
                !matches!(r.behaviour, EDGE | FURROW)
                    || routed[i + 1..].iter().any(|o| o.behaviour == r.behaviour)
            });
            let mode = guidance.mode();
            let result = guidance.step(&TickInput {
                scans: &routed,
                gnss,
                odometry,
                extra,
            });
            match result {
                Ok(out) => {
                    assert!(extra_valid && !malformed);
                    check_tick(&out, &vehicle);
                    assert_eq!(out.mode, guidance.mode());
                }
                Err(e) => {
                    assert!(!extra_valid || malformed, "{e}");
                    assert_refusal(&e, &["PT-SIDESLIP", "GD-INPUT"]);
                    assert_eq!(guidance.mode(), mode, "a refused tick changes nothing");
                }
            }
        }
    });
}

fn check_law(law: &LawOutcome, vehicle: &Vehicle) {
    if let LawOutcome::Commanded(c) = law {
        assert!(vehicle.check(&c.command).is_ok(), "{c:?}");
        assert!(c.command.speed().get().is_finite());
    }
}

fn check_tick(out: &fieldguide::guidance::TickOutput<Sideslip, 2>, vehicle: &Vehicle) {
    if let Some(c) = &out.command {
        assert!(vehicle.check(&c.command).is_ok(), "{c:?}");
        assert!(c.command.speed().get().is_finite());
    }
    if out.mode == Mode::Stop {
        let c = out.command.expect("Stop commands the stop");
        assert_eq!(c.command.speed().get(), 0.0);
        assert!(out.source.is_none());
    } else {
        assert_eq!(out.source.is_some(), out.command.is_some());
    }
    if let Some(f) = &out.path.frenet {
        assert!(f.s.get().is_finite());
        assert_finite_error(&f.tracking_error());
    }
    check_law(&out.path.law, vehicle);
    assert_eq!(
        out.path.localisation_valid,
        out.path.law.command().is_some()
    );
    for b in &out.behaviours {
        assert_eq!(b.error.is_none(), b.detected == Verdict::Absent);
        if let Some(e) = &b.error {
            assert_finite_error(e);
        }
        if let Some(q) = b.quality {
            assert!(q.is_finite());
        }
        if let Some(p) = &b.plan {
            assert!(p.offset.get().is_finite() && p.heading.get().is_finite());
        }
        check_law(&b.law, vehicle);
    }
}
