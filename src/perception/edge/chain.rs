//! The chain of Algorithm 1 (Pierre 2022, section 2.2), with exact contacts:
//! a circle of radius r is translated sideways from the robot's rear point
//! until its front semicircle touches a point (EDGE-CHAIN-TRANSLATE), then
//! rotated about the last pivot until another point touches it
//! (EDGE-CHAIN-ROTATE), until θ_max or l_max stops it (EDGE-CHAIN-STOP), or
//! a gap (EDGE-GAP) or a corner (EDGE-CORNER) in the edge.
//!
//! Contacts are solved in closed form instead of by small steps, so a chain
//! does not depend on a step size and every circle position where the chain
//! stopped rotating has no point of the requested side strictly inside it.

use core::cmp::Ordering;

use heapless::Vec;

use super::config::{EdgeConfig, Side};
use super::search::{
    blocks, contact_angle, cos_below_pi, Half, Limit, Near, Step, CANDIDATES, SEEDS,
};
use crate::geometry::frame::{Point2, Robot};
use crate::geometry::units::{Meters, Radians};

/// Why the chain stopped growing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChainEnd {
    /// No point of the requested side is touched within the search distance: no chain.
    NoEdge,
    /// No new point touches the circle before a rotation of θ_max.
    RotationLimit,
    /// The chain reached the length l_max.
    LengthLimit,
    /// The next contact is a point already in the chain (the circle went round a cluster).
    Closed,
    /// The next contact is farther from the pivot than the longest link
    /// l_link: a gap in the edge (EDGE-GAP).
    Gap,
    /// The next link turns from the chain's direction by more than φ_turn:
    /// a corner or the end of the edge (EDGE-CORNER).
    Corner,
    /// The chain buffer is full.
    Capacity,
}

/// A chain of LiDAR points along an edge, in the order the circle touched them.
#[derive(Debug, Clone)]
pub struct Chain<const M: usize> {
    indices: Vec<usize, M>,
    points: Vec<Point2<Robot>, M>,
    centers: Vec<Point2<Robot>, M>,
    length: f64,
    end: ChainEnd,
}

impl<const M: usize> Chain<M> {
    /// An empty chain, as before any detection.
    #[must_use]
    pub const fn empty(end: ChainEnd) -> Self {
        Self {
            indices: Vec::new(),
            points: Vec::new(),
            centers: Vec::new(),
            length: 0.0,
            end,
        }
    }

    fn clear(&mut self, end: ChainEnd) {
        self.indices.clear();
        self.points.clear();
        self.centers.clear();
        self.length = 0.0;
        self.end = end;
    }

    /// The chain's points, robot frame, in the order they were touched.
    #[must_use]
    pub fn points(&self) -> &[Point2<Robot>] {
        self.points.as_slice()
    }

    /// For each chain point, its index in the input point slice.
    #[must_use]
    pub fn indices(&self) -> &[usize] {
        self.indices.as_slice()
    }

    /// For each chain point, the centre of the circle at the moment it
    /// touched that point (the translation contact, then each rotation contact).
    #[must_use]
    pub fn centers(&self) -> &[Point2<Robot>] {
        self.centers.as_slice()
    }

    /// The polyline length of the chain, metres.
    #[must_use]
    pub const fn length(&self) -> Meters {
        Meters(self.length)
    }

    /// Why the chain stopped.
    #[must_use]
    pub const fn end(&self) -> ChainEnd {
        self.end
    }

    /// Number of points in the chain.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the chain has no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// The signed translation `t` (metres, along the robot's y axis towards
/// `side`) at which a circle of radius `radius` centred at the robot's rear
/// point `(0, 0)` first touches `q` (EDGE-CHAIN-TRANSLATE).
///
/// `t = s·q_y − sqrt(r² − q_x²)` when `q` is strictly on `side`
/// (`s·q_y > 0`) and `|q_x| ≤ r`; `None` otherwise (the point is on the
/// other side or the moving circle never reaches it). `t` is negative when
/// `q` already lies inside the circle at the rear point; it is always > −r.
//= spec/pierre2022.md#edge-chain-translate-first-point-by-translation
//# A point q strictly on the requested side (s·q_y > 0) with |q_x| ≤ r MUST
//# be touched at the translation t(q) = s·q_y − sqrt(r² − q_x²); other points
//# MUST NOT be touched by the translation.
#[must_use]
pub fn translation_contact(q: Point2<Robot>, side: Side, radius: Meters) -> Option<Meters> {
    contact_from(q, 0.0, side, radius.get()).and_then(|t| Meters::new(t).ok())
}

/// [`translation_contact`] of a circle whose translation starts at `(x0, 0)`.
fn contact_from(q: Point2<Robot>, x0: f64, side: Side, r: f64) -> Option<f64> {
    let lateral = side.sign() * q.y();
    let dx = q.x() - x0;
    if lateral > 0.0 && libm::fabs(dx) <= r {
        let t = lateral - libm::sqrt(r * r - dx * dx);
        t.is_finite().then_some(t)
    } else {
        None
    }
}

/// The rotation angle θ in [0, 2π) (counter-clockwise about `pivot` for the
/// left side, clockwise for the right) at which the circle of radius `radius`
/// centred at `center`, with `pivot` on it, first touches `q` from outside
/// (EDGE-CHAIN-ROTATE).
///
/// With `u = center − pivot`, `w = q − pivot`, `d = |w|`, `α = arccos(d / 2r)`
/// and `β = s · atan2(w × u, w · u)` the angle from `w` to `u`
/// (signed by the side `s`): `θ = −α − β` when `β < 0` (clamped at 0),
/// `θ = 2π − α − β` otherwise. `None` when `q` coincides with the pivot or
/// `d ≥ 2r` (the circle can never contain it).
//= spec/pierre2022.md#edge-chain-rotate-next-point-by-rotation
//# The contact angle of a point q at distance 0 < d < 2r from the pivot MUST
//# be the smallest θ ≥ 0 at which |c(θ) − q| = r with q entering the disk,
//# where c(θ) is the centre rotated by s·θ about the pivot; a point at d = 0
//# or d ≥ 2r MUST have no contact.
#[must_use]
pub fn rotation_contact(
    pivot: Point2<Robot>,
    center: Point2<Robot>,
    q: Point2<Robot>,
    side: Side,
    radius: Meters,
) -> Option<Radians> {
    let r = radius.get();
    let (wx, wy) = (q.x() - pivot.x(), q.y() - pivot.y());
    let d2 = wx * wx + wy * wy;
    if d2 > 0.0 && d2 < 4.0 * r * r {
        let theta = contact_angle(
            (center.x() - pivot.x(), center.y() - pivot.y()),
            (wx, wy),
            d2,
            side.sign(),
            r,
        );
        Radians::new(theta).ok()
    } else {
        None
    }
}

/// The centre of the circle of radius `r` through `p` and `q` (distance
/// `d ∈ (0, 2r)`) reached by rotating about `p` in the sense of `s`: the
/// entering one of the two circles through both points.
fn contact_center(p: Point2<Robot>, q: Point2<Robot>, s: f64, r: f64) -> Option<Point2<Robot>> {
    let (wx, wy) = (q.x() - p.x(), q.y() - p.y());
    let d2 = wx * wx + wy * wy;
    let k = libm::sqrt((r * r - d2 / 4.0).max(0.0) / d2);
    // c − p = w/2 − s (h/d) w⊥ with w⊥ = (−w_y, w_x).
    Point2::new(p.x() + wx / 2.0 + s * k * wy, p.y() + wy / 2.0 - s * k * wx).ok()
}

/// Builds the chain of Algorithm 1 on `side` over `points` (robot frame),
/// with exact contacts (EDGE-CHAIN-TRANSLATE, EDGE-CHAIN-ROTATE, EDGE-CHAIN-STOP).
///
/// Only points strictly on `side` (s·y > 0) take part. The first pivot is the
/// point with the smallest translation contact (ties: the smallest |x|, then
/// the lowest index); no chain when that translation exceeds the search
/// distance. Each next pivot is the point with the smallest rotation contact
/// (ties: the nearest to the pivot, then the lowest index), accepted when
/// that angle is below θ_max; the chain stops when its length reaches l_max,
/// when the next contact is already a chain point, when it is farther than
/// l_link from the pivot (EDGE-GAP), when its link turns more than φ_turn
/// from the chain's direction (EDGE-CORNER), or when `M` points are held.
/// Never panics; points are assumed within `MAX_COORDINATE` (checked by the callers).
#[must_use]
pub fn build_chain<const M: usize>(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
) -> Chain<M> {
    let mut chain = Chain::empty(ChainEnd::NoEdge);
    build_chain_into(points, side, config, &mut chain);
    chain
}

/// [`build_chain`] into a caller's chain (cleared first), so that a
/// detector reuses one buffer instead of returning a large value.
//= spec/pierre2022.md#edge-chain-translate-first-point-by-translation
//# The first chain point MUST be the point with the smallest translation
//# contact t(q), and there MUST be no chain when that smallest t(q) exceeds
//# the search distance.
//= spec/pierre2022.md#edge-chain-rotate-next-point-by-rotation
//# Each next chain point MUST be the point with the smallest contact angle
//# about the current pivot, and the circle MUST move to the position where it
//# touches both the pivot and that point.
//= spec/pierre2022.md#edge-chain-stop-rotation-and-length-limits
//# The chain MUST stop when no point has a contact angle below θ_max, when
//# its polyline length reaches l_max, when the next contact is a point
//# already in the chain, or when its buffer is full.
//= spec/pierre2022.md#edge-gap-the-chain-stops-at-a-gap-in-the-edge
//# The chain MUST stop, before taking it, at a next contact farther than
//# l_link from the pivot: a link longer than l_link is a gap, and the two
//# sides of a gap are two edges.
pub fn build_chain_into<const M: usize>(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    chain: &mut Chain<M>,
) {
    build_chain_from(points, side, config, 0.0, chain);
}

/// [`build_chain_into`] with the circle's translation starting at `(x0, 0)`
/// instead of the robot's rear point: the chain of the points shifted back
/// by `x0`, without copying them (EDGE-LOOK-AHEAD).
pub(super) fn build_chain_from<const M: usize>(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    x0: f64,
    chain: &mut Chain<M>,
) {
    chain.clear(ChainEnd::NoEdge);
    let r = config.radius().get();
    let s = side.sign();

    // Translation (EDGE-CHAIN-TRANSLATE).
    let mut first: Option<(f64, f64, usize)> = None;
    for (i, q) in points.iter().enumerate() {
        if let Some(t) = contact_from(*q, x0, side, r) {
            let dx = libm::fabs(q.x() - x0);
            let better = match first {
                None => true,
                Some((bt, bdx, _)) => match t.total_cmp(&bt) {
                    Ordering::Less => true,
                    Ordering::Equal => dx < bdx,
                    Ordering::Greater => false,
                },
            };
            if better {
                first = Some((t, dx, i));
            }
        }
    }
    let (t0, i0) = match first {
        Some((t, _, i)) if t <= config.search_distance().get() => (t, i),
        _ => return,
    };
    let (Some(&p0), Ok(c0)) = (points.get(i0), Point2::new(x0, s * t0)) else {
        return;
    };
    if push(chain, i0, p0, c0).is_err() {
        chain.end = ChainEnd::Capacity;
        return;
    }

    // Only points of the side within l_max + 2r of the first pivot can be
    // touched: every pivot before the last is less than l_max (along the
    // chain) from it and a contact is less than 2r from its pivot.
    let reach_all = (config.max_chain_length().get() + 2.0 * r) * (1.0 + 1e-9);
    let mut near: Vec<Near, CANDIDATES> = Vec::new();
    let mut all = false;
    for (i, q) in points.iter().enumerate() {
        let (dx, dy) = (q.x() - p0.x(), q.y() - p0.y());
        if s * q.y() > 0.0
            && dx * dx + dy * dy < reach_all * reach_all
            && near
                .push(Near {
                    x: q.x(),
                    y: q.y(),
                    index: i,
                })
                .is_err()
        {
            all = true;
            break;
        }
    }

    near.sort_unstable_by(|a, b| a.x.total_cmp(&b.x));
    let blocks = blocks(&near);

    // Rotation (EDGE-CHAIN-ROTATE) until a limit (EDGE-CHAIN-STOP).
    let theta_max = config.max_rotation().get();
    let limit = Limit {
        theta: theta_max,
        half: Half::of(theta_max),
        cos: cos_below_pi(theta_max),
    };
    let max_link2 = config.max_link().get() * config.max_link().get();
    let (mut pivot, mut pivot_index, mut center) = (p0, i0, c0);
    loop {
        if chain.length >= config.max_chain_length().get() {
            chain.end = ChainEnd::LengthLimit;
            return;
        }
        let mut step = Step::new(pivot, center, s, r, &limit);
        if all {
            for (i, q) in points.iter().enumerate() {
                if i != pivot_index && s * q.y() > 0.0 {
                    step.consider(i, q.x(), q.y());
                }
            }
        } else {
            // Candidates are sorted by x. The pivot's neighbours in x first:
            // they usually touch first, which shrinks the bound. Then sweep
            // outwards from the pivot in both directions, stopping where
            // |x − mid_x| alone puts every further point outside the bound.
            let px = pivot.x();
            let start = near.partition_point(|n| n.x < px);
            let pos = near
                .get(start..)
                .unwrap_or(&[])
                .iter()
                .position(|n| n.index == pivot_index)
                .map_or(start, |k| start.saturating_add(k));
            let lo = pos.saturating_sub(SEEDS);
            let hi = pos.saturating_add(SEEDS).saturating_add(1).min(near.len());
            for n in near.get(lo..hi).unwrap_or(&[]) {
                if n.index != pivot_index {
                    step.consider(n.index, n.x, n.y);
                }
            }
            step.sweep_up(&near, &blocks, pos, pivot_index);
            step.sweep_down(&near, &blocks, pos.min(near.len()));
        }
        let Some(next) = step.best else {
            chain.end = ChainEnd::RotationLimit;
            return;
        };
        if chain.indices.contains(&next.index) {
            chain.end = ChainEnd::Closed;
            return;
        }
        let Some(&q) = points.get(next.index) else {
            chain.end = ChainEnd::RotationLimit;
            return;
        };
        if next.d2 > max_link2 {
            chain.end = ChainEnd::Gap;
            return;
        }
        if turns_too_much(p0, pivot, q, config.cos_max_turn()) {
            chain.end = ChainEnd::Corner;
            return;
        }
        let Some(c) = contact_center(pivot, q, s, r) else {
            chain.end = ChainEnd::RotationLimit;
            return;
        };
        if push(chain, next.index, q, c).is_err() {
            chain.end = ChainEnd::Capacity;
            return;
        }
        chain.length += libm::sqrt(next.d2);
        (pivot, pivot_index, center) = (q, next.index, c);
    }
}

/// Whether the link from `pivot` to `next` turns from the chain's direction,
/// from its `first` point to `pivot`, by more than the angle whose cosine is
/// `cos_max` (EDGE-CORNER). The first link (pivot = first point) has no
/// direction to turn from.
//= spec/pierre2022.md#edge-corner-the-chain-stops-at-a-corner-or-the-end-of-the-edge
//# The chain MUST stop, before taking it, at a next contact q whose link
//# from the pivot p_k turns from the chain's direction, the vector from its
//# first point p_0 to p_k, by more than φ_turn: (q − p_k) · (p_k − p_0) <
//# cos φ_turn · |q − p_k| |p_k − p_0|.
fn turns_too_much(
    first: Point2<Robot>,
    pivot: Point2<Robot>,
    next: Point2<Robot>,
    cos_max: f64,
) -> bool {
    let (cx, cy) = (pivot.x() - first.x(), pivot.y() - first.y());
    let (lx, ly) = (next.x() - pivot.x(), next.y() - pivot.y());
    let norms = libm::sqrt((cx * cx + cy * cy) * (lx * lx + ly * ly));
    // cos(turn) = (c · l) / (|c| |l|) < cos φ_turn, without a division.
    norms > 0.0 && cx * lx + cy * ly < cos_max * norms
}

fn push<const M: usize>(
    chain: &mut Chain<M>,
    index: usize,
    p: Point2<Robot>,
    c: Point2<Robot>,
) -> Result<(), ()> {
    if chain.indices.is_full() {
        return Err(());
    }
    chain.indices.push(index).map_err(|_| ())?;
    chain.points.push(p).map_err(|_| ())?;
    chain.centers.push(c).map_err(|_| ())?;
    Ok(())
}
