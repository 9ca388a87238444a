//! The search for the next contact about one pivot (EDGE-CHAIN-ROTATE):
//! the same angle as [`super::rotation_contact`], found among the candidates
//! with bounds that reject most points without trigonometry.

use core::cmp::Ordering;
use core::f64::consts::{FRAC_PI_2, PI, TAU};

use heapless::Vec;

use crate::geometry::frame::{Point2, Robot};

/// The best contact so far: the point's index, its angle and its squared
/// distance to the pivot.
pub(super) struct Candidate {
    pub(super) index: usize,
    pub(super) theta: f64,
    pub(super) d2: f64,
}

/// How many candidate points [`super::build_chain`] copies out once per chain (12 KiB
/// of stack); with more, every step scans all the points (same result, slower).
pub(super) const CANDIDATES: usize = 512;

/// How many scan-order neighbours on each side of the pivot are tried first.
pub(super) const SEEDS: usize = 2;

/// Consecutive candidates (in x order) that share one bounding box.
const BLOCK: usize = 16;

/// A candidate point, copied out and sorted by x for a bounded sweep.
pub(super) struct Near {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) index: usize,
}

/// The bounding box of `BLOCK` consecutive candidates (sorted by x), so that a
/// sweep skips every point of a block the distance bound excludes as a whole:
/// a thin block along a hedge, 1 m from the circle's centre, is rejected by
/// one test instead of sixteen.
pub(super) struct Block {
    start: usize,
    end: usize,
    x_lo: f64,
    x_hi: f64,
    y_lo: f64,
    y_hi: f64,
}

/// The blocks of a sorted candidate list.
pub(super) type Blocks = Vec<Block, { CANDIDATES / BLOCK }>;

/// Cuts `near` (sorted by x) into blocks of `BLOCK` candidates.
pub(super) fn blocks(near: &[Near]) -> Blocks {
    let mut blocks = Blocks::new();
    let mut start = 0_usize;
    for chunk in near.chunks(BLOCK) {
        let (Some(first), Some(last)) = (chunk.first(), chunk.last()) else {
            continue;
        };
        let (y_lo, y_hi) = chunk
            .iter()
            .fold((first.y, first.y), |(lo, hi), n| (lo.min(n.y), hi.max(n.y)));
        let end = start.saturating_add(chunk.len());
        // At most CANDIDATES / BLOCK chunks: the push cannot fail.
        let _ = blocks.push(Block {
            start,
            end,
            x_lo: first.x,
            x_hi: last.x,
            y_lo,
            y_hi,
        });
        start = end;
    }
    blocks
}

/// The search for the next contact about one pivot: the best candidate so
/// far and the bounds that let most points be rejected without trigonometry.
pub(super) struct Step {
    pivot: (f64, f64),
    u: (f64, f64),
    s: f64,
    r: f64,
    theta_max: f64,
    pub(super) best: Option<Candidate>,
    /// Centre of the circle rotated by half the angle to beat.
    pub(super) mid: (f64, f64),
    /// Squared distance from `mid` beyond which no point can beat the angle
    /// to beat: the centres c(θ') for θ' ≤ θ lie within 2r sin(θ/4) of
    /// `mid`, so a point they touch lies within r (1 + 2 sin(θ/4)).
    pub(super) bound2: f64,
    /// cos of the angle to beat when it is ≤ π (entering contacts with a
    /// smaller cosine are farther), −2 otherwise.
    cos_to_beat: f64,
}

/// θ_max with its half-angle terms and cosine, computed once per chain.
pub(super) struct Limit {
    pub(super) theta: f64,
    pub(super) half: Half,
    pub(super) cos: f64,
}

/// cos(θ/2), sin(θ/2) and sin(θ/4) of an angle θ ∈ [0, 2π).
pub(super) struct Half {
    cos2: f64,
    sin2: f64,
    sin4: f64,
}

impl Half {
    /// From θ, with trigonometry (θ_max, and the rare contacts beyond π/2).
    pub(super) fn of(theta: f64) -> Self {
        Self {
            cos2: libm::cos(theta / 2.0),
            sin2: libm::sin(theta / 2.0),
            sin4: libm::sin(theta / 4.0),
        }
    }

    /// From cos θ and sin θ ≥ 0 (θ ∈ [0, π]) without trigonometry, each term
    /// by the formula that keeps its accuracy near 0 and near π.
    fn from_cos_sin(cos: f64, sin: f64) -> Self {
        let (cos2, sin2) = if cos >= 0.0 {
            let c2 = libm::sqrt(0.5 * (1.0 + cos));
            (c2, sin / (2.0 * c2))
        } else {
            let s2 = libm::sqrt(0.5 * (1.0 - cos));
            (sin / (2.0 * s2), s2)
        };
        let cos4 = libm::sqrt(0.5 * (1.0 + cos2));
        Self {
            cos2,
            sin2,
            sin4: sin2 / (2.0 * cos4),
        }
    }
}

impl Step {
    /// The search about `pivot` with the circle at `center`, bounded by θ_max.
    pub(super) fn new(
        pivot: Point2<Robot>,
        center: Point2<Robot>,
        s: f64,
        r: f64,
        limit: &Limit,
    ) -> Self {
        let mut step = Self {
            pivot: (pivot.x(), pivot.y()),
            u: (center.x() - pivot.x(), center.y() - pivot.y()),
            s,
            r,
            theta_max: limit.theta,
            best: None,
            mid: (center.x(), center.y()),
            bound2: 0.0,
            cos_to_beat: limit.cos,
        };
        step.set_bound(&limit.half);
        step
    }

    /// Moves the distance bound to the angle whose half-angle terms are `h`,
    /// widened by a relative 1e-9 so that rounding never excludes a contact.
    fn set_bound(&mut self, h: &Half) {
        let (u, s) = (self.u, self.s);
        self.mid = (
            self.pivot.0 + h.cos2 * u.0 - s * h.sin2 * u.1,
            self.pivot.1 + s * h.sin2 * u.0 + h.cos2 * u.1,
        );
        let reach = self.r * (1.0 + 2.0 * h.sin4.max(0.0)) * (1.0 + 1e-9);
        self.bound2 = reach * reach;
    }

    /// Whether every point of `block` lies outside the distance bound: its
    /// box is. Rounding is monotone, so a point's computed distance is never
    /// below its box's, and skipping the block changes nothing.
    fn excludes(&self, block: &Block) -> bool {
        let dx = (block.x_lo - self.mid.0)
            .max(self.mid.0 - block.x_hi)
            .max(0.0);
        let dy = (block.y_lo - self.mid.1)
            .max(self.mid.1 - block.y_hi)
            .max(0.0);
        dx * dx + dy * dy >= self.bound2
    }

    /// Whether no point of `block` can beat the best so far because each lies
    /// on the exiting side of the pivot (s (w × u) ≥ 0, where a contact needs
    /// θ ≥ π/2) and the angle to beat is at most π/2. The half-plane is
    /// convex, so the box lies in it when its corners do; the margin, far
    /// above the rounding of w × u, keeps every point's computed side the
    /// same as its box's.
    fn behind(&self, block: &Block) -> bool {
        let to_beat = self.best.as_ref().map_or(self.theta_max, |b| b.theta);
        if to_beat > FRAC_PI_2 {
            return false;
        }
        let (p, u, s) = (self.pivot, self.u, self.s);
        let scale = 1.0
            + libm::fabs(p.0).max(libm::fabs(p.1))
            + libm::fabs(block.x_lo).max(libm::fabs(block.x_hi))
            + libm::fabs(block.y_lo).max(libm::fabs(block.y_hi));
        let margin = 1e-9 * self.r * scale;
        [
            (block.x_lo, block.y_lo),
            (block.x_lo, block.y_hi),
            (block.x_hi, block.y_lo),
            (block.x_hi, block.y_hi),
        ]
        .iter()
        .all(|&(x, y)| s * ((x - p.0) * u.1 - (y - p.1) * u.0) > margin)
    }

    /// Whether `block` can be skipped: outside the distance bound, or behind.
    fn skips(&self, block: &Block) -> bool {
        self.excludes(block) || self.behind(block)
    }

    /// Considers the candidates from `pos` upwards in x (all but the pivot),
    /// stopping where |x − mid_x| alone puts every further point outside the
    /// bound, and skipping the blocks outside it.
    pub(super) fn sweep_up(&mut self, near: &[Near], blocks: &[Block], pos: usize, pivot: usize) {
        for block in blocks.iter().filter(|b| b.end > pos) {
            if self.skips(block) {
                let dx = block.x_lo - self.mid.0;
                if dx > 0.0 && dx * dx >= self.bound2 {
                    return;
                }
                continue;
            }
            for n in near.get(block.start.max(pos)..block.end).unwrap_or(&[]) {
                let dx = n.x - self.mid.0;
                if dx > 0.0 && dx * dx >= self.bound2 {
                    return;
                }
                if n.index != pivot {
                    self.consider(n.index, n.x, n.y);
                }
            }
        }
    }

    /// Considers the candidates below `end` downwards in x, the mirror of
    /// [`Step::sweep_up`].
    pub(super) fn sweep_down(&mut self, near: &[Near], blocks: &[Block], end: usize) {
        for block in blocks.iter().rev().filter(|b| b.start < end) {
            if self.skips(block) {
                let dx = self.mid.0 - block.x_hi;
                if dx > 0.0 && dx * dx >= self.bound2 {
                    return;
                }
                continue;
            }
            for n in near
                .get(block.start..block.end.min(end))
                .unwrap_or(&[])
                .iter()
                .rev()
            {
                let dx = self.mid.0 - n.x;
                if dx > 0.0 && dx * dx >= self.bound2 {
                    return;
                }
                self.consider(n.index, n.x, n.y);
            }
        }
    }

    /// Takes the point `(x, y)` (index `i`, not the pivot) into account.
    #[inline]
    pub(super) fn consider(&mut self, i: usize, x: f64, y: f64) {
        let (mx, my) = (x - self.mid.0, y - self.mid.1);
        if mx * mx + my * my >= self.bound2 {
            return;
        }
        self.evaluate(i, x, y);
    }

    /// The full evaluation of a point that passed the distance bound. The
    /// angle is the one of [`super::rotation_contact`], computed without `acos`
    /// for entering points.
    #[inline]
    fn evaluate(&mut self, i: usize, x: f64, y: f64) {
        let w = (x - self.pivot.0, y - self.pivot.1);
        let d2 = w.0 * w.0 + w.1 * w.1;
        let r2 = self.r * self.r;
        if d2 <= 0.0 || d2 >= 4.0 * r2 {
            return;
        }
        let u = self.u;
        let cross = w.0 * u.1 - w.1 * u.0;
        let dot = w.0 * u.0 + w.1 * u.1;
        if self.s * cross < 0.0 {
            // Entering side (β < 0): the contact centre is
            // p + w/2 − s k w⊥ with k = sqrt(r²/d² − 1/4), at angle θ ∈ [0, π)
            // from u: r² cos θ = u·w/2 + k |w × u|, r² sin θ = |w × u|/2 − k u·w.
            // It cannot beat the best when cos θ < cos_to_beat, i.e. when
            // k |w × u| < need; squared (k² d² = r² − d²/4) to spare a
            // square root and a division on most points.
            let need = (self.cos_to_beat - 1e-12) * r2 - 0.5 * dot;
            if need > 0.0 && (r2 - 0.25 * d2) * cross * cross < need * need * d2 {
                return;
            }
            let k = libm::sqrt((r2 / d2 - 0.25).max(0.0));
            let cos_r2 = 0.5 * dot + k * libm::fabs(cross);
            let sin_r2 = 0.5 * libm::fabs(cross) - k * dot;
            let theta = libm::atan2(sin_r2, cos_r2).max(0.0);
            if self.is_better(theta, d2) {
                let (cos, sin) = if theta > 0.0 {
                    (cos_r2 / r2, sin_r2 / r2)
                } else {
                    (1.0, 0.0)
                };
                self.cos_to_beat = cos;
                self.set_bound(&Half::from_cos_sin(cos, sin.max(0.0)));
                self.best = Some(Candidate {
                    index: i,
                    theta,
                    d2,
                });
            }
        } else {
            // Exiting side: the contact needs θ ≥ π − α ≥ π/2.
            let to_beat = self.best.as_ref().map_or(self.theta_max, |b| b.theta);
            if to_beat <= FRAC_PI_2 {
                return;
            }
            let theta = contact_angle(u, w, d2, self.s, self.r);
            if self.is_better(theta, d2) {
                self.cos_to_beat = cos_below_pi(theta);
                self.set_bound(&Half::of(theta));
                self.best = Some(Candidate {
                    index: i,
                    theta,
                    d2,
                });
            }
        }
    }

    /// Whether a contact at `theta` (distance² `d2` from the pivot) beats the
    /// best so far: a smaller angle, or the same angle nearer the pivot; the
    /// first one must be below θ_max.
    fn is_better(&self, theta: f64, d2: f64) -> bool {
        match &self.best {
            None => theta < self.theta_max,
            Some(b) => match theta.total_cmp(&b.theta) {
                Ordering::Less => true,
                Ordering::Equal => d2 < b.d2,
                Ordering::Greater => false,
            },
        }
    }
}

/// `cos θ` for θ ≤ π, −2 (below any cosine) beyond.
pub(super) fn cos_below_pi(theta: f64) -> f64 {
    if theta <= PI {
        libm::cos(theta)
    } else {
        -2.0
    }
}

/// The contact angle for `u = c − p`, `w = q − p`, `d2 = |w|² ∈ (0, 4r²)`.
pub(super) fn contact_angle(u: (f64, f64), w: (f64, f64), d2: f64, s: f64, r: f64) -> f64 {
    let d = libm::sqrt(d2);
    let alpha = libm::acos((d / (2.0 * r)).min(1.0));
    // Angle from w to u: atan2(w × u, w · u).
    let cross_wu = w.0 * u.1 - w.1 * u.0;
    let dot = w.0 * u.0 + w.1 * u.1;
    let beta = s * libm::atan2(cross_wu, dot);
    if beta < 0.0 {
        (-alpha - beta).max(0.0)
    } else {
        TAU - alpha - beta
    }
}
