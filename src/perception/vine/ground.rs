//! Ground compensation (Iberraken 2022, section 2.1.1): a RANSAC line
//! through the scan's terrain profile, height against lateral position, and
//! every point's height measured from it (`spec/iberraken2022.md`,
//! VINE-GROUND).
//!
//! The generator is the detector's own, seeded from its configuration and
//! carried from scan to scan: the same seed and the same scans give the same
//! grounds. The iterations are bounded; a profile with too few inliers is a
//! value ([`Ground::TooFewInliers`]), not an error.

use rand_xoshiro::Xoshiro128PlusPlus;

use crate::error::Precondition;
use crate::geometry::fit::fit_line;
use crate::geometry::frame::{Point2, Sensor};
use crate::perception::furrow::scan::ScanPoint;
use crate::perception::rows::ruby::pick;

/// Most RANSAC iterations a configuration may ask for per scan.
pub const MAX_ITERATIONS: usize = 1024;

/// The RANSAC parameters, validated once (VINE-GROUND).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundParams {
    iterations: usize,
    tolerance: f64,
    min_inliers: usize,
    max_slope: f64,
}

impl GroundParams {
    /// `iterations` hypotheses per scan, inliers within `tolerance` m of a
    /// line, at least `min_inliers` of them, and a cross slope |dz/dy| of at
    /// most `max_slope`.
    ///
    /// # Errors
    /// `VINE-GROUND` unless 1 ≤ iterations ≤ [`MAX_ITERATIONS`],
    /// tolerance > 0, min_inliers ≥ 2 and max_slope ≥ 0, all finite.
    pub fn new(
        iterations: usize,
        tolerance: f64,
        min_inliers: usize,
        max_slope: f64,
    ) -> Result<Self, Precondition> {
        let ok = (1..=MAX_ITERATIONS).contains(&iterations)
            && tolerance.is_finite()
            && tolerance > 0.0
            && min_inliers >= 2
            && max_slope.is_finite()
            && max_slope >= 0.0;
        if ok {
            Ok(Self {
                iterations,
                tolerance,
                min_inliers,
                max_slope,
            })
        } else {
            Err(Precondition::new(
                "VINE-GROUND",
                "need 1..=1024 iterations, tolerance > 0, >= 2 inliers, slope >= 0",
            ))
        }
    }

    /// Hypotheses drawn per scan.
    #[must_use]
    pub const fn iterations(&self) -> usize {
        self.iterations
    }

    /// The inlier distance, m.
    #[must_use]
    pub const fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The fewest inliers of an accepted profile.
    #[must_use]
    pub const fn min_inliers(&self) -> usize {
        self.min_inliers
    }

    /// The steepest accepted cross slope |dz/dy|.
    #[must_use]
    pub const fn max_slope(&self) -> f64 {
        self.max_slope
    }
}

/// The terrain profile of one scan: z = slope · y + offset in the robot
/// frame (y left, z up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundLine {
    /// dz/dy, dimensionless.
    pub slope: f64,
    /// z at y = 0, m.
    pub offset: f64,
    /// How many points lie within the tolerance of the hypothesis kept.
    pub inliers: usize,
}

impl GroundLine {
    /// The height of `point` above the profile, m: z − (slope · y + offset).
    #[must_use]
    pub fn height_above(&self, point: &ScanPoint) -> f64 {
        point.height.get() - (self.slope * point.ground.y() + self.offset)
    }
}

/// What ground compensation found in one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ground {
    /// A profile with enough inliers.
    Profile(GroundLine),
    /// No hypothesis within the slope limit gathered `min_inliers` points.
    TooFewInliers,
}

/// The RANSAC profile of `rays` (Iberraken 2022, section 2.1.1; Fischler
/// and Bolles 1981): `iterations` times, two rays drawn with `rng` give the
/// line through their (y, z); a line steeper than `max_slope`, or through
/// two points at the same y or a dropped ray, is skipped; the line with the
/// most points within `tolerance` (the first on ties) is refined by least
/// squares over its inliers, and kept when the refined line still has the
/// slope allowed (else the hypothesis itself is kept).
//= spec/iberraken2022.md#vine-ground-ground-compensation-by-ransac
//# The ground profile MUST be the line z = a y + b, |a| ≤ a_max, drawn by
//# RANSAC from pairs of points with the detector's seeded generator over a
//# bounded number of iterations, that has the most points within the
//# tolerance, refined by least squares over those points.
//= spec/iberraken2022.md#vine-ground-ground-compensation-by-ransac
//# When no line within the slope limit has at least the configured number
//# of inliers, the scan MUST yield no candidate.
#[must_use]
pub fn fit_ground(
    rays: &[Option<ScanPoint>],
    params: &GroundParams,
    rng: &mut Xoshiro128PlusPlus,
) -> Ground {
    let n = rays.len();
    if n < 2 {
        return Ground::TooFewInliers;
    }
    let mut best: Option<(f64, f64, usize)> = None;
    for _ in 0..params.iterations {
        let i = pick(rng, n);
        let j = pick(rng, n);
        let (Some(Some(p)), Some(Some(q))) = (rays.get(i), rays.get(j)) else {
            continue;
        };
        let dy = q.ground.y() - p.ground.y();
        if libm::fabs(dy) < 1.0e-9 {
            continue;
        }
        let slope = (q.height.get() - p.height.get()) / dy;
        if !(slope.is_finite() && libm::fabs(slope) <= params.max_slope) {
            continue;
        }
        let offset = p.height.get() - slope * p.ground.y();
        let count = inliers(rays, slope, offset, params.tolerance).count();
        if best.is_none_or(|(_, _, c)| count > c) {
            best = Some((slope, offset, count));
        }
    }
    let Some((slope, offset, count)) = best else {
        return Ground::TooFewInliers;
    };
    if count < params.min_inliers {
        return Ground::TooFewInliers;
    }
    let profile = |p: &ScanPoint| Point2::<Sensor>::new(p.ground.y(), p.height.get()).ok();
    let refined = fit_line(inliers(rays, slope, offset, params.tolerance).filter_map(profile))
        .ok()
        .filter(|f| libm::fabs(f.a) <= params.max_slope);
    let (slope, offset) = refined.map_or((slope, offset), |f| (f.a, f.b));
    Ground::Profile(GroundLine {
        slope,
        offset,
        inliers: count,
    })
}

/// The points of `rays` within `tolerance` of z = slope · y + offset.
fn inliers(
    rays: &[Option<ScanPoint>],
    slope: f64,
    offset: f64,
    tolerance: f64,
) -> impl Iterator<Item = &ScanPoint> + Clone {
    rays.iter()
        .flatten()
        .filter(move |p| libm::fabs(p.height.get() - (slope * p.ground.y() + offset)) <= tolerance)
}
