//! Matches of the plant model in one scan: local maxima of the correlation
//! above c_t, and the choice of one row (eq. 14) or of a pair of rows
//! (eqs. 17-19), as corrected in the errata (Pierre 2022, section 2.3;
//! `spec/pierre2022.md` FUR-MAXIMA, FUR-SELECT-ONE, FUR-SELECT-PAIR).

use heapless::Vec;

use super::correlation::Template;
use super::scan::ScanPoint;
use crate::error::{finite, Precondition};
use crate::geometry::frame::{Frame, Point2, Robot};
use crate::geometry::units::Meters;

/// How many maxima one scan can yield; further maxima (to the left, the
/// highest ray indices) are ignored (FUR-MAXIMA).
pub const MAX_MAXIMA: usize = 32;

/// A local maximum of the correlation: the window ray at its centre, its
/// score `c[k]`, and where the matched plant stands in the robot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Maximum {
    /// Window ray index k of the template's centre.
    pub ray: usize,
    /// Correlation score `c[k]`, in (c_t, 1].
    pub score: f64,
    /// Ground position of the match, robot frame, m.
    pub point: Point2<Robot>,
}

/// The shifts `k` that are local maxima of `scores` above `threshold`
/// (FUR-MAXIMA), in increasing order, at most [`MAX_MAXIMA`].
///
/// `k` is a maximum when `scores[k] > threshold`, no score within `radius`
/// rays on either side is higher, and every score within `radius` rays
/// before it is strictly lower: a flat top (the correlation of a plant
/// narrower than the template is flat while the plant lies inside the
/// support) yields its first shift only. `radius` 0 is taken as 1.
//= spec/pierre2022.md#fur-maxima-local-maxima-above-the-threshold
//# A shift k MUST be a maximum when c[k] > c_t, no score within r rays of k
//# is higher, and every score within r rays before k is strictly lower,
//# with r = max((w − 1)/2, 1).
#[must_use]
pub fn local_maxima(scores: &[f64], threshold: f64, radius: usize) -> Vec<usize, MAX_MAXIMA> {
    let radius = radius.max(1);
    let mut peaks = Vec::new();
    for (k, &c) in scores.iter().enumerate() {
        if c.is_nan() || c <= threshold {
            continue;
        }
        let before = scores.get(k.saturating_sub(radius)..k).unwrap_or_default();
        let after_end = k.saturating_add(radius).saturating_add(1).min(scores.len());
        let after = scores
            .get(k.saturating_add(1)..after_end)
            .unwrap_or_default();
        let is_peak = before.iter().all(|&b| b.is_nan() || b < c)
            && after.iter().all(|&a| a.is_nan() || a <= c);
        if is_peak && peaks.push(k).is_err() {
            break;
        }
    }
    peaks
}

/// Where the plant matched at centre ray `k` stands: the centroid of the
/// ground positions of the rays under the template's support, weighted by
/// their signal `z_a` (FUR-MAXIMA). Only rays with a point and a positive
/// signal count; `None` when there is none.
///
/// The centre ray alone would wander along a flat top of the correlation;
/// the weighted centroid is the middle of the plant whatever the shift.
//= spec/pierre2022.md#fur-maxima-local-maxima-above-the-threshold
//# The position of a maximum MUST be the z_a-weighted centroid of the
//# ground positions of the valid rays under the template's support centred
//# on k.
#[must_use]
pub fn locate(
    k: usize,
    rays: &[Option<ScanPoint>],
    signal: &[f64],
    template: &Template,
) -> Option<Point2<Robot>> {
    let start = k.saturating_sub(template.half_width());
    let end = k
        .saturating_add(template.half_width())
        .saturating_add(1)
        .min(rays.len())
        .min(signal.len());
    let rays = rays.get(start..end)?;
    let weights = signal.get(start..end)?;
    let (mut sw, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for (ray, &w) in rays.iter().zip(weights) {
        if let Some(p) = ray {
            if w > 0.0 {
                sw += w;
                sx += w * p.ground.x();
                sy += w * p.ground.y();
            }
        }
    }
    if sw > 0.0 {
        Point2::new(sx / sw, sy / sw).ok()
    } else {
        None
    }
}

/// The row to follow in one scan (eq. 14 as corrected): the maximum whose y
/// is closest to `reference_y`, which is 0 (the robot) at the start and the
/// previous selection's y, moved into the current robot frame, afterwards.
/// Ties go to the first maximum. `None` when there are no maxima.
//= spec/pierre2022.md#fur-select-one-one-row-the-closest-maximum-in-y
//# The selected maximum MUST minimise |m_y| when there is no previous
//# selection, and |m_y − m_{y,t−1}| otherwise, with m_{t−1} moved into the
//# current robot frame.
#[must_use]
pub fn select_one(maxima: &[Maximum], reference_y: f64) -> Option<Maximum> {
    let mut best: Option<(f64, Maximum)> = None;
    for m in maxima {
        let d = libm::fabs(m.point.y() - reference_y);
        if best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, *m));
        }
    }
    best.map(|(_, m)| m)
}

/// The accepted lateral distances between two rows, `[d_min, d_max]` (eq. 17).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spacing {
    min: Meters,
    max: Meters,
}

impl Spacing {
    /// Rows `min` to `max` m apart. Errors with `FUR-SELECT-PAIR` unless `0 < min < max`.
    pub fn new(min: Meters, max: Meters) -> Result<Self, Precondition> {
        if min.get() > 0.0 && min.get() < max.get() {
            Ok(Self { min, max })
        } else {
            Err(Precondition::new(
                "FUR-SELECT-PAIR",
                "row spacing must satisfy 0 < d_min < d_max",
            ))
        }
    }

    /// d_min, m.
    #[must_use]
    pub const fn min(&self) -> Meters {
        self.min
    }

    /// d_max, m.
    #[must_use]
    pub const fn max(&self) -> Meters {
        self.max
    }

    /// Whether `distance` lies in `[d_min, d_max]`.
    #[must_use]
    pub fn contains(&self, distance: f64) -> bool {
        distance >= self.min.get() && distance <= self.max.get()
    }
}

/// Two rows seen together: `left` has the larger y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair<T> {
    /// The left row's item (larger y).
    pub left: T,
    /// The right row's item (smaller y).
    pub right: T,
}

impl<F: Frame> Pair<Point2<F>> {
    /// `mid(P) = (p₁ + p₂)/2` (eq. 18).
    #[must_use]
    pub fn mid(&self) -> Point2<F> {
        let x = 0.5 * self.left.x() + 0.5 * self.right.x();
        let y = 0.5 * self.left.y() + 0.5 * self.right.y();
        // Halves of finite values added: finite, so `new` cannot fail; fall back to `left`.
        Point2::new(x, y).unwrap_or(self.left)
    }
}

impl Pair<Maximum> {
    /// The pair's ground positions.
    #[must_use]
    pub fn points(&self) -> Pair<Point2<Robot>> {
        Pair {
            left: self.left.point,
            right: self.right.point,
        }
    }

    /// The weaker of the two maxima's scores (the furrow quality, FUR-QUALITY).
    /// Errors with `LIB-FINITE` when a score is not finite (a maximum built
    /// by hand: the correlation's scores are in [−1, 1]).
    pub fn weaker_score(&self) -> Result<f64, Precondition> {
        let left = finite(self.left.score, "left maximum's score must be finite")?;
        let right = finite(self.right.score, "right maximum's score must be finite")?;
        Ok(left.min(right))
    }
}

/// The pair of rows to follow in one scan (eqs. 17-19 as corrected): among the
/// pairs of maxima whose lateral distance `|y₁ − y₂|` lies in `spacing`, the
/// one whose middle has the y closest to `reference_y` (0 at the start, the
/// previous pair's middle moved into the current robot frame afterwards).
/// Ties go to the first pair in ray order. `None` when no pair qualifies.
//= spec/pierre2022.md#fur-select-pair-two-rows-a-pair-within-the-spacing-closest-in-y
//# Only pairs of maxima whose lateral distance |m_{1,y} − m_{2,y}| lies in
//# [d_min, d_max] MUST be candidates.
//= spec/pierre2022.md#fur-select-pair-two-rows-a-pair-within-the-spacing-closest-in-y
//# The selected pair MUST minimise |mid(P)_y| when there is no previous
//# selection, and |mid(P)_y − mid(P_{t−1})_y| otherwise, with P_{t−1} moved
//# into the current robot frame.
#[must_use]
pub fn select_pair(
    maxima: &[Maximum],
    spacing: &Spacing,
    reference_y: f64,
) -> Option<Pair<Maximum>> {
    let mut best: Option<(f64, Pair<Maximum>)> = None;
    for (i, a) in maxima.iter().enumerate() {
        for b in maxima.get(i.saturating_add(1)..).unwrap_or_default() {
            if !spacing.contains(libm::fabs(a.point.y() - b.point.y())) {
                continue;
            }
            let pair = if a.point.y() >= b.point.y() {
                Pair {
                    left: *a,
                    right: *b,
                }
            } else {
                Pair {
                    left: *b,
                    right: *a,
                }
            };
            let d = libm::fabs(pair.points().mid().y() - reference_y);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, pair));
            }
        }
    }
    best.map(|(_, p)| p)
}
