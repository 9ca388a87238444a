//! Ruby's multi-line fitting (Guyonneau 2022, section 2.1, Alg. 1, eqs. 1-9)
//! and its refinements (section 2.2: eq. 10, Algs. 2-3) as options of one
//! algorithm (`spec/guyonneau2022.md`, RUBY-*).
//!
//! A set of models holds at most [`MAX_MODELS`] lines in fixed slots; which
//! models a point belongs to is a bit mask per point (one bit for Ruby, RG,
//! RGOP and RGOPPN; any number for RGOPPNI), so merging, deleting and
//! re-attaching never move a model and never allocate.

use heapless::Vec;

use rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro128PlusPlus;

use super::count_f64;
use super::points::RowPoint;
use crate::error::Precondition;
use crate::geometry::fit::MIN_RELATIVE_X_SPREAD;
use crate::geometry::frame::{Point2, Robot};
use crate::geometry::units::Meters;
use crate::perception::furrow::lines::RowLine;

/// Models a set holds at most (the width of a point's mask).
pub const MAX_MODELS: usize = 64;

/// The smallest residual a re-weighting divides by, m (RUBY-FIT).
pub const LAD_FLOOR: f64 = 1.0e-3;

/// Points a new model is seeded with (Alg. 1, line 6), and the fewest a
/// model keeps after re-attachment (RUBY-REATTACH).
pub const SEED_POINTS: usize = 3;

/// The line-finding algorithms of the paper (section 4.2), each a set of
/// refinements of Ruby (RUBY-VARIANT).
//= spec/guyonneau2022.md#ruby-variant-one-algorithm-five-variants
//# The line finder MUST run one algorithm whose refinements are chosen by the
//# variant: Ruby (deletion by eq. 7, on Z), RG (deletion by the fitness of
//# eq. 10, on Z), RGOP (RG on Z*), RGOPPN (RGOP with seeds sampled left and right
//# separately) and RGOPPNI (RGOPPN where a point may belong to several models).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Ruby (Alg. 1): deletion by eq. 7.
    Ruby,
    /// Ruby Genetic: deletion by the fitness of eq. 10.
    Rg,
    /// Ruby Genetic One Point: RG on Z* (Alg. 2).
    Rgop,
    /// RGOP with the search split left and right of the robot (Alg. 3).
    Rgoppn,
    /// RGOPPN where a point may belong to several models.
    Rgoppni,
}

impl Variant {
    /// Every variant, in the paper's order.
    pub const ALL: [Self; 5] = [
        Self::Ruby,
        Self::Rg,
        Self::Rgop,
        Self::Rgoppn,
        Self::Rgoppni,
    ];

    /// The paper's name of the variant.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Ruby => "Ruby",
            Self::Rg => "RG",
            Self::Rgop => "RGOP",
            Self::Rgoppn => "RGOPPN",
            Self::Rgoppni => "RGOPPNI",
        }
    }

    /// The variant of a name, as [`Variant::name`] spells it, case ignored.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|v| v.name().eq_ignore_ascii_case(name))
    }

    /// Deletion by fitness (eq. 10) instead of eq. 7.
    #[must_use]
    pub const fn genetic(self) -> bool {
        !matches!(self, Self::Ruby)
    }

    /// Z* instead of Z (Alg. 2).
    #[must_use]
    pub const fn one_point(self) -> bool {
        matches!(self, Self::Rgop | Self::Rgoppn | Self::Rgoppni)
    }

    /// Seeds sampled left and right of the robot separately (Alg. 3).
    #[must_use]
    pub const fn split_sides(self) -> bool {
        matches!(self, Self::Rgoppn | Self::Rgoppni)
    }

    /// A point may belong to several models (section 2.2.4).
    #[must_use]
    pub const fn shared_points(self) -> bool {
        matches!(self, Self::Rgoppni)
    }
}

/// The line finder's constants as a user writes them; [`RubyParams::authors`]
/// gives the defaults of the authors' implementation (RUBY-DEFAULTS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RubyParams {
    /// Which refinements run.
    pub variant: Variant,
    /// ρ, the energy of one outlier (eq. 2), > 0.
    pub outlier_energy: f64,
    /// λ, the weight of the neighbourhood penalty (eq. 3), ≥ 0.
    pub neighbour_penalty: f64,
    /// ζ, the distance scale of the neighbour weight (eq. 5), m, > 0.
    pub neighbour_scale: Meters,
    /// A point farther than this from every model is an outlier (Alg. 1,
    /// line 23), m, > 0.
    pub outlier_distance: Meters,
    /// β: models are parallel when their slopes differ by less (eq. 9), > 0.
    pub parallel_slope: f64,
    /// Parallel models whose intercepts differ by less are one model (Alg. 1,
    /// line 13), m, > 0.
    pub same_intercept: Meters,
    /// α of eq. 7 (Ruby's deletion), > 0.
    pub alpha: f64,
    /// τ of eq. 10 (the genetic fitness), ≥ 0.
    pub fitness_weight: f64,
    /// Share of the models the genetic deletion keeps, in (0, 1].
    pub kept_share: f64,
    /// The fewest models the genetic deletion keeps (when there are as many).
    pub min_kept: u8,
    /// Iterations of Alg. 1 per scan, ≥ 1.
    pub iterations: u16,
    /// New models seeded per iteration at most, ≥ 1.
    pub models_per_iteration: u16,
    /// The search stops once the outliers left are at most this share of
    /// those it started with (Alg. 1, line 5), in [0, 1).
    pub search_until: f64,
    /// Z*'s merge distance (Alg. 2, line 8), m, > 0.
    pub merge_distance: Meters,
    /// Re-weightings of each model fit towards least absolute deviations
    /// (RUBY-FIT); 0 keeps plain least squares.
    pub fit_rounds: u8,
    /// A call that starts from a set holding a model ends after this many
    /// discarded iterations in a row (RUBY-ITERATION); 0 never ends early.
    pub converged_after: u16,
    /// The seed of the detector's random generator.
    pub seed: u64,
}

impl RubyParams {
    /// The constants of the authors' implementation for `variant`
    /// (RUBY-DEFAULTS): ρ = 3, λ = 4, ζ = 3 m, outliers beyond 0.2 m,
    /// parallel below 0.1 in slope, the same model below 0.2 m in intercept
    /// as well, α = 0.7, τ = 10, the best quarter kept (at least 6 for RG,
    /// 4 for the one-point variants), 10 iterations, 40 models per
    /// iteration, Z* merge distance 0.05 m; the search runs until half the
    /// outliers are attached. The library's own: four re-weightings of a
    /// fit (RUBY-FIT), and a call of a one-point variant ends after three
    /// discarded iterations in a row (RUBY-ITERATION).
    //= spec/guyonneau2022.md#ruby-defaults-constants-of-the-authors-implementation
    //# `RubyParams::authors` MUST give ρ = 3, λ = 4, ζ = 3 m, an outlier distance of
    //# 0.2 m, β = 0.1, a same-model intercept of 0.2 m, α = 0.7, τ = 10, a kept share
    //# of a quarter with at least 6 models for RG and 4 for the one-point variants,
    //# 10 iterations, 40 models per iteration, a search share of one half and a Z*
    //# merge distance of 0.05 m.
    //= spec/guyonneau2022.md#ruby-iteration-alg-1-iterations
    //# `RubyParams::authors` MUST set `converged_after` to 3 for the one-point
    //# variants and to 0 for Ruby and RG.
    #[must_use]
    pub const fn authors(variant: Variant) -> Self {
        Self {
            variant,
            outlier_energy: 3.0,
            neighbour_penalty: 4.0,
            neighbour_scale: Meters(3.0),
            outlier_distance: Meters(0.2),
            parallel_slope: 0.1,
            same_intercept: Meters(0.2),
            alpha: 0.7,
            fitness_weight: 10.0,
            kept_share: 0.25,
            min_kept: if matches!(variant, Variant::Rg) { 6 } else { 4 },
            iterations: 10,
            models_per_iteration: 40,
            search_until: 0.5,
            merge_distance: Meters(0.05),
            fit_rounds: 4,
            converged_after: if variant.one_point() { 3 } else { 0 },
            seed: 20_221_118,
        }
    }
}

/// Validated [`RubyParams`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RubyConfig {
    params: RubyParams,
}

impl RubyConfig {
    /// Checks every constant's domain (RUBY-PARAMS).
    ///
    /// # Errors
    /// `RUBY-PARAMS`, naming the constant out of its domain.
    //= spec/guyonneau2022.md#ruby-params-constants-checked-once
    //# A line finder MUST be refused at construction, with an error naming
    //# RUBY-PARAMS, unless ρ, ζ, the outlier distance, β, the same-model
    //# intercept, α and the merge distance are finite and > 0, λ and τ are
    //# finite and ≥ 0, the kept share is in (0, 1], the search share is in
    //# [0, 1), and the iterations and models per iteration are ≥ 1.
    pub fn new(params: RubyParams) -> Result<Self, Precondition> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let non_negative = |v: f64| v.is_finite() && v >= 0.0;
        let checks = [
            (
                positive(params.outlier_energy),
                "ρ (outlier energy) must be > 0",
            ),
            (
                non_negative(params.neighbour_penalty),
                "λ (neighbour penalty) must be ≥ 0",
            ),
            (
                positive(params.neighbour_scale.get()),
                "ζ (neighbour scale) must be > 0",
            ),
            (
                positive(params.outlier_distance.get()),
                "the outlier distance must be > 0",
            ),
            (
                positive(params.parallel_slope),
                "β (parallel slope) must be > 0",
            ),
            (
                positive(params.same_intercept.get()),
                "the same-model intercept must be > 0",
            ),
            (positive(params.alpha), "α must be > 0"),
            (non_negative(params.fitness_weight), "τ must be ≥ 0"),
            (
                positive(params.kept_share) && params.kept_share <= 1.0,
                "the kept share must be in (0, 1]",
            ),
            (
                non_negative(params.search_until) && params.search_until < 1.0,
                "the search share must be in [0, 1)",
            ),
            (params.iterations >= 1, "at least one iteration"),
            (
                params.models_per_iteration >= 1,
                "at least one model per iteration",
            ),
            (
                positive(params.merge_distance.get()),
                "the merge distance must be > 0",
            ),
        ];
        match checks.into_iter().find(|(ok, _)| !ok) {
            Some((_, why)) => Err(Precondition::new("RUBY-PARAMS", why)),
            None => Ok(Self { params }),
        }
    }

    /// The constants.
    #[must_use]
    pub const fn params(&self) -> &RubyParams {
        &self.params
    }
}

/// A line y = a x + b with its normalisation 1 / sqrt(a² + 1).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Line {
    a: f64,
    b: f64,
    inv_norm: f64,
}

impl Line {
    const NONE: Self = Self {
        a: 0.0,
        b: 0.0,
        inv_norm: 1.0,
    };

    fn new(a: f64, b: f64) -> Option<Self> {
        let inv_norm = 1.0 / libm::sqrt(a * a + 1.0);
        (a.is_finite() && b.is_finite() && inv_norm > 0.0).then_some(Self { a, b, inv_norm })
    }

    /// ‖p − L‖, the Euclidean distance of `p` to the line (eq. 6).
    fn distance(&self, p: Point2<Robot>) -> f64 {
        self.distance_xy(p.x(), p.y())
    }

    /// The same for the point (x, y).
    fn distance_xy(&self, x: f64, y: f64) -> f64 {
        libm::fabs(self.a * x + self.b - y) * self.inv_norm
    }

    /// The line of least absolute deviations in y through the points of
    /// columns `xs`, `ys`, by `rounds` re-weightings of a least-squares
    /// start (RUBY-FIT), if determined.
    //= spec/guyonneau2022.md#ruby-fit-models-fitted-by-least-absolute-deviations
    //# A model's line MUST be fitted to its points by iteratively reweighted
    //# least squares: a least-squares start, then the configured number of
    //# weighted fits with w = 1 / max(|r|, 1 mm), r the point's residual in y
    //# to the line before.
    //= spec/guyonneau2022.md#ruby-fit-models-fitted-by-least-absolute-deviations
    //# Each fit MUST be the weighted least-squares line of the sums about the
    //# model's first point (x₀, y₀) in ray order: with u = x − x₀ and v = y − y₀,
    //# S = Σ w, S_u = Σ w u, S_v = Σ w v, S_uu = Σ w u u and S_uv = Σ w u v summed
    //# in ray order (w u computed once per point), D = S S_uu − S_u S_u, the slope
    //# a = (S S_uv − S_u S_v) / D, c = (S_v − a S_u) / S and the intercept
    //# b = y₀ + c − a x₀; the least-squares start has every w = 1, and a fit with
    //# D ≤ 10⁻¹² S S_uu (the points' x the same) or a result not finite MUST give
    //# no line (the start) or end the re-weighting with the line before.
    ///
    /// Each fit is one pass over the points (RUBY-FIT's sums about the first
    /// point, in its order): no division by the spread of x, and a
    /// re-weighting computes its weights in the pass that sums them.
    #[inline]
    fn fit(xs: &[f64], ys: &[f64], rounds: u8) -> Option<Self> {
        let (&x0, &y0) = (xs.first()?, ys.first()?);
        let uv = xs.iter().zip(ys).map(|(&x, &y)| (x - x0, y - y0));
        Self::fit_about((x0, y0), uv, rounds)
    }

    /// [`Line::fit`] on the points (u, v) = (x − x₀, y − y₀) about the
    /// first point (x₀, y₀), as `uv` gives them in ray order.
    fn fit_about(
        (x0, y0): (f64, f64),
        uv: impl Iterator<Item = (f64, f64)> + Clone,
        rounds: u8,
    ) -> Option<Self> {
        let mut sums = Moments::ZERO;
        for (u, v) in uv.clone() {
            sums.add(1.0, u, v);
        }
        let (mut a, mut c) = sums.line()?;
        for _ in 0..rounds {
            let mut sums = Moments::ZERO;
            // A weight is finite, and > 0 unless the residual overflows.
            let mut valid = true;
            for (u, v) in uv.clone() {
                let r = libm::fabs(v - a * u - c);
                let w = 1.0 / if r > LAD_FLOOR { r } else { LAD_FLOOR };
                valid &= w > 0.0;
                sums.add(w, u, v);
            }
            match sums.line().filter(|_| valid) {
                Some(next) => (a, c) = next,
                None => break,
            }
        }
        Self::new(a, y0 + c - a * x0)
    }
}

/// The weighted sums of a fit about its first point (x₀, y₀) (RUBY-FIT):
/// Σ w, Σ w u, Σ w v, Σ w u², Σ w u v with u = x − x₀, v = y − y₀.
#[derive(Debug, Clone, Copy)]
struct Moments {
    w: f64,
    u: f64,
    v: f64,
    uu: f64,
    uv: f64,
}

impl Moments {
    const ZERO: Self = Self {
        w: 0.0,
        u: 0.0,
        v: 0.0,
        uu: 0.0,
        uv: 0.0,
    };

    /// Adds the point (u, v) with weight `w`, in RUBY-FIT's order.
    #[inline]
    fn add(&mut self, w: f64, u: f64, v: f64) {
        let wu = w * u;
        self.w += w;
        self.u += wu;
        self.v += w * v;
        self.uu += wu * u;
        self.uv += wu * v;
    }

    /// The line v = a u + c of least weighted squares, as (a, c): `None`
    /// when the points' x are the same to [`MIN_RELATIVE_X_SPREAD`] or an
    /// operation overflows (RUBY-FIT).
    fn line(&self) -> Option<(f64, f64)> {
        let det = self.w * self.uu - self.u * self.u;
        let determined = det > MIN_RELATIVE_X_SPREAD * self.w * self.uu;
        let a = (self.w * self.uv - self.u * self.v) / det;
        let c = (self.v - a * self.u) / self.w;
        (determined && a.is_finite() && c.is_finite()).then_some((a, c))
    }
}

/// One model of a set, with its points' count and energy (eq. 6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// The line, robot frame.
    pub line: RowLine,
    /// |P(L)|, the points attached to it.
    pub points: usize,
    /// E_L(L) = Σ ‖p − L‖ over its points (eq. 6), m.
    pub energy: f64,
}

/// What one call of [`Ruby::find`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Found {
    /// E(L) of the returned set on this scan's points (eq. 1).
    pub energy: f64,
    /// E(L) of the set it started from (the previous scan's lines on this
    /// scan's points).
    pub start_energy: f64,
    /// The points it worked on (|Z| or |Z*|).
    pub points: usize,
    /// Iterations whose set was kept (Alg. 1, lines 26-27).
    pub accepted: u16,
    /// Iterations run: the configured number, or fewer when the call ended
    /// early (RUBY-ITERATION, RUBY-BOUND).
    pub iterations: u16,
}

/// Bit `k` of a mask.
fn bit(k: usize) -> u64 {
    u32::try_from(k)
        .ok()
        .and_then(|k| 1_u64.checked_shl(k))
        .unwrap_or(0)
}

/// The slots set in `mask`, ascending.
fn slots(mask: u64) -> impl Iterator<Item = usize> + Clone {
    let mut rest = mask;
    core::iter::from_fn(move || {
        if rest == 0 {
            None
        } else {
            let k = rest.trailing_zeros();
            rest &= rest.wrapping_sub(1);
            usize::try_from(k).ok()
        }
    })
}

/// The slot of a mask with one bit set, `MAX_MODELS` (the sink of
/// [`Stats`]) for no bit.
#[inline]
fn slot_of(mask: u64) -> usize {
    usize::try_from(mask.trailing_zeros()).map_or(MAX_MODELS, |k| k.min(MAX_MODELS))
}

/// The points' coordinates in columns, for the re-attachment's inner loops
/// and the fits.
#[derive(Debug, Clone)]
struct Columns<const N: usize> {
    xs: [f64; N],
    ys: [f64; N],
}

/// A set of models and which points belong to each.
#[derive(Debug, Clone)]
struct ModelSet<const N: usize> {
    alive: u64,
    /// Models whose line is the fit of their points as `fit_masks` holds
    /// them: unless their points changed since, a refit would give the same
    /// line, so it is skipped.
    fitted: u64,
    /// Models whose line (or points, by a merge) changed since the points
    /// were last attached: only they can take a point from its model.
    moved: u64,
    lines: [Line; MAX_MODELS],
    masks: [u64; N],
    /// The masks when the models were last fitted.
    fit_masks: [u64; N],
    /// Without shared points: each point's distance to its model, or the
    /// outlier distance for an outlier, as the last re-attachment left it.
    /// Only the points of models moved since may be out of date.
    dist: [f64; N],
    /// Models seeded by this iteration's search (until the merge that
    /// follows it).
    seeded: u64,
}

/// Per-model sums of one pass over the points: |P(L)| and E_L(L).
/// Slot `MAX_MODELS` is a sink for the outliers, so that a pass over the
/// points adds every point without a branch; without shared points its
/// count is the number of outliers (its energy is never read).
#[derive(Debug, Clone, Copy)]
struct Stats {
    count: [usize; MAX_MODELS + 1],
    energy: [f64; MAX_MODELS + 1],
}

impl Stats {
    const ZERO: Self = Self {
        count: [0; MAX_MODELS + 1],
        energy: [0.0; MAX_MODELS + 1],
    };

    fn add(&mut self, k: usize, distance: f64) {
        if let (Some(c), Some(e)) = (self.count.get_mut(k), self.energy.get_mut(k)) {
            // At most `N` points: no overflow.
            *c = c.wrapping_add(1);
            *e += distance;
        }
    }

    fn clear(&mut self, k: usize) {
        if let (Some(c), Some(e)) = (self.count.get_mut(k), self.energy.get_mut(k)) {
            *c = 0;
            *e = 0.0;
        }
    }
}

impl<const N: usize> ModelSet<N> {
    /// No model, no point attached.
    const EMPTY: Self = Self {
        alive: 0,
        fitted: 0,
        moved: 0,
        lines: [Line::NONE; MAX_MODELS],
        masks: [0; N],
        fit_masks: [0; N],
        dist: [0.0; N],
        seeded: 0,
    };

    fn line(&self, k: usize) -> Line {
        self.lines.get(k).copied().unwrap_or(Line::NONE)
    }

    /// Copies `other`'s models and the masks of its first `n` points.
    fn copy_from(&mut self, other: &Self, n: usize) {
        self.alive = other.alive;
        self.fitted = other.fitted;
        self.moved = other.moved;
        // The lines of live models alone: a dead slot's line is never read.
        for k in slots(other.alive) {
            if let (Some(l), Some(o)) = (self.lines.get_mut(k), other.lines.get(k)) {
                *l = *o;
            }
        }
        copy_first(&mut self.masks, &other.masks, n);
        copy_first(&mut self.fit_masks, &other.fit_masks, n);
        copy_first(&mut self.dist, &other.dist, n);
    }

    /// The line of model `k` fitted to its points (RUBY-FIT), the points'
    /// coordinates taken from `cols` (the first `n`) into `scratch` about
    /// the model's first point.
    fn fit(
        &self,
        k: usize,
        cols: &Columns<N>,
        n: usize,
        scratch: &mut Scratch<N>,
        rounds: u8,
    ) -> Option<Line> {
        let b = bit(k);
        let masks = self.masks.get(..n).unwrap_or(&[]);
        let first = masks.iter().position(|&m| m & b != 0)?;
        let last = masks.iter().rposition(|&m| m & b != 0)?;
        let origin = (*cols.xs.get(first)?, *cols.ys.get(first)?);
        let count = gather_about(cols, masks, first..=last, b, origin, scratch);
        let us = scratch.xs.get(..count).unwrap_or(&[]);
        let vs = scratch.ys.get(..count).unwrap_or(&[]);
        Line::fit_about(origin, us.iter().copied().zip(vs.iter().copied()), rounds)
    }
}

/// Writes (x − x₀, y − y₀) of the points of `range` whose mask has bit `b`
/// into `scratch`, in ray order, and returns how many: every point is
/// written at the end of the list, which grows by the model's points (no
/// branch on the masks; at most `N` points: no overflow). Not inlined:
/// inside the merge its loop reloads the columns' addresses each point.
#[inline(never)]
fn gather_about<const N: usize>(
    cols: &Columns<N>,
    masks: &[u64],
    range: core::ops::RangeInclusive<usize>,
    b: u64,
    (x0, y0): (f64, f64),
    scratch: &mut Scratch<N>,
) -> usize {
    let xs = cols.xs.get(range.clone()).unwrap_or(&[]);
    let ys = cols.ys.get(range.clone()).unwrap_or(&[]);
    let masks = masks.get(range).unwrap_or(&[]);
    let mut count = 0_usize;
    for ((&x, &y), &m) in xs.iter().zip(ys).zip(masks) {
        if let (Some(u), Some(v)) = (scratch.xs.get_mut(count), scratch.ys.get_mut(count)) {
            (*u, *v) = (x - x0, y - y0);
        }
        count = count.wrapping_add(usize::from(m & b != 0));
    }
    count
}

/// Copies the first `n` entries of `from` into `to`, as one block copy
/// (a loop over the entries is not made one).
fn copy_first<T: Copy, const N: usize>(to: &mut [T; N], from: &[T; N], n: usize) {
    let n = n.min(N);
    if let (Some(to), Some(from)) = (to.get_mut(..n), from.get(..n)) {
        // The same length: `copy_from_slice`'s one panic, on lengths that
        // differ, cannot happen.
        if to.len() == from.len() {
            to.copy_from_slice(from);
        }
    }
}

/// Room for one model's fit: its points' coordinates.
#[derive(Debug, Clone)]
struct Scratch<const N: usize> {
    xs: [f64; N],
    ys: [f64; N],
}

/// Ruby's line finder with its seeded generator and the set it carries from
/// scan to scan; `N` points at most per scan.
#[derive(Debug, Clone)]
pub struct Ruby<const N: usize> {
    config: RubyConfig,
    rng: Xoshiro128PlusPlus,
    models: Vec<Model, MAX_MODELS>,
    /// Working sets, kept here so a call needs no large stack frame.
    /// The set kept and the candidate, by index (never moved: a swap of
    /// two sets would copy their masks).
    sets: [ModelSet<N>; 2],
    /// Each set's |P(L)| and E_L(L), by the same index (read for the live
    /// models alone: a re-attachment clears theirs).
    stats: [Stats; 2],
    /// Which of `sets` is the kept one.
    kept: usize,
    /// w_pq of each pair of consecutive points (eq. 5).
    weights: [f64; N],
    /// One model's points, gathered for its fit, and their weights.
    scratch: Scratch<N>,
    /// The points in columns, for the re-attachment.
    columns: Columns<N>,
}

impl<const N: usize> Ruby<N> {
    /// A line finder with no lines yet, its generator seeded from the
    /// configuration.
    //= spec/guyonneau2022.md#ruby-random-a-seeded-generator
    //# The line finder's random draws MUST come from a generator held in its
    //# state and seeded from its configuration, so that the same seed and the same
    //# scans give the same lines, bit for bit.
    #[must_use]
    pub fn new(config: RubyConfig) -> Self {
        let empty = ModelSet::EMPTY;
        Self {
            config,
            rng: Xoshiro128PlusPlus::seed_from_u64(config.params.seed),
            models: Vec::new(),
            sets: [empty.clone(), empty],
            stats: [Stats::ZERO; 2],
            kept: 0,
            weights: [0.0; N],
            scratch: Scratch {
                xs: [0.0; N],
                ys: [0.0; N],
            },
            columns: Columns {
                xs: [0.0; N],
                ys: [0.0; N],
            },
        }
    }

    /// The constants.
    #[must_use]
    pub const fn config(&self) -> &RubyConfig {
        &self.config
    }

    /// The set returned by the last call, in slot order.
    #[must_use]
    pub fn models(&self) -> &[Model] {
        &self.models
    }

    /// Adds `lines` to the set carried to the next call, each unless a
    /// carried model is the same (RUBY-MERGE's test) or the set is full.
    //= spec/guyonneau2022.md#ruby-seeded-expected-lines-carried-to-the-next-scan
    //# Lines handed to the line finder between two calls MUST join the set the
    //# next call starts from, except a line the same as one already in it and
    //# any line beyond the set's capacity.
    pub fn carry(&mut self, lines: &[RowLine]) {
        let p = self.config.params;
        for line in lines {
            let Some(new) = Line::new(line.slope(), line.intercept().get()) else {
                continue;
            };
            let known = self.models.iter().any(|m| {
                Line::new(m.line.slope(), m.line.intercept().get())
                    .is_some_and(|old| same(&old, &new, &p))
            });
            if !known {
                let _ = self.models.push(Model {
                    line: *line,
                    points: 0,
                    energy: 0.0,
                });
            }
        }
    }

    /// Moves the lines carried to the next call into the frame of the robot
    /// at `motion` (its pose in the frame of the last scan) with `moved`; a
    /// line `moved` cannot carry is dropped.
    pub fn move_by(&mut self, mut moved: impl FnMut(&RowLine) -> Option<RowLine>) {
        let mut kept: Vec<Model, MAX_MODELS> = Vec::new();
        for m in &self.models {
            if let Some(line) = moved(&m.line) {
                let _ = kept.push(Model { line, ..*m });
            }
        }
        self.models = kept;
    }

    /// Forgets the lines carried from the last scan (the next call starts
    /// from the empty set).
    pub fn reset(&mut self) {
        self.models.clear();
    }

    /// Alg. 1 on `points` (Z, or Z* for the one-point variants: the caller
    /// merges them, see [`super::points::merge_runs`]), seeded by the last
    /// call's set. Points beyond `N` are ignored (the caller sized the buffer
    /// to `N`).
    //= spec/guyonneau2022.md#ruby-bound-bounded-work-per-scan
    //# Every loop of the line finder MUST have a bound fixed by its configuration
    //# and capacities: at most `N` points, 64 models, the configured iterations,
    //# and per iteration at most the model budget of draws, at most 65 merge
    //# passes, one pass of deletion and two of re-attachment.
    //= spec/guyonneau2022.md#ruby-iteration-alg-1-iterations
    //# Each call MUST start from the previous call's set of lines (the empty
    //# set on the first call), refitted to the points they attach on this scan,
    //# and
    //# MUST run the configured number of iterations, unless it ends early
    //# (below), each of which seeds new models, merges, re-attaches, deletes and
    //# re-attaches again, and is kept only when its energy is not above the
    //# energy of the set kept before it.
    pub fn find(&mut self, points: &[RowPoint]) -> Found {
        let points = points.get(..N.min(points.len())).unwrap_or(&[]);
        let n = points.len();
        let p = self.config.params;
        self.neighbour_weights(points);

        let (best, _) = pair(&mut self.sets, self.kept);
        best.alive = 0;
        best.fitted = 0;
        best.seeded = 0;
        for m in best.masks.iter_mut().take(n) {
            *m = 0;
        }
        for m in best.fit_masks.iter_mut().take(n) {
            *m = 0;
        }
        for d in best.dist.iter_mut().take(n) {
            *d = p.outlier_distance.get();
        }
        for (k, m) in self.models.iter().enumerate().take(MAX_MODELS) {
            if let (Some(slot), Some(line)) = (
                best.lines.get_mut(k),
                Line::new(m.line.slope(), m.line.intercept().get()),
            ) {
                *slot = line;
                best.alive |= bit(k);
            }
        }
        best.moved = best.alive;
        for ((x, y), q) in self
            .columns
            .xs
            .iter_mut()
            .zip(self.columns.ys.iter_mut())
            .zip(points)
        {
            (*x, *y) = (q.position.x(), q.position.y());
        }
        // The previous lines, refitted to the points they attach on this
        // scan (RUBY-ITERATION).
        let (stats, _) = pair(&mut self.stats, self.kept);
        reattach(best, points, &mut self.columns, &p, stats);
        merge(best, &self.columns, n, &mut self.scratch, &p);
        reattach(best, points, &mut self.columns, &p, stats);
        let start = energy(best, stats, n, &self.weights, &mut self.scratch.xs, &p);
        let start_energy = start.total;
        // The kept set's outliers and neighbour sum, for an iteration that
        // ends with its models and points.
        let mut kept_terms = start;
        let mut best_energy = start_energy;
        let mut accepted = 0_u16;
        let mut iterations = 0_u16;
        // Discarded iterations in a row, counted when the call starts from
        // a set holding a model.
        let tracking = best.alive != 0;
        let mut discarded = 0_u16;

        for _ in 0..p.iterations {
            iterations = iterations.saturating_add(1);
            let (best, candidate) = pair(&mut self.sets, self.kept);
            let (kept_stats, candidate_stats) = pair(&mut self.stats, self.kept);
            candidate.copy_from(best, n);
            let drew = search(candidate, points, &mut self.rng, &p);
            merge(candidate, &self.columns, n, &mut self.scratch, &p);
            reattach(candidate, points, &mut self.columns, &p, candidate_stats);
            let gone = delete(candidate, candidate_stats, &p);
            // An iteration whose deletion leaves the kept set's models with
            // their points ends as the kept set (the deleted models' points
            // were its outliers): its energy is the kept set's terms with
            // the sums of this re-attachment, and the kept set stands for
            // it, with those sums, where the deleted models' re-attachment
            // and the energy's passes would give the same, bit for bit.
            let same_set = ends_as(best, kept_stats, candidate, candidate_stats, gone);
            let terms = if same_set {
                Energy {
                    total: total(
                        &p,
                        kept_terms.outliers,
                        kept_terms.neighbour,
                        model_sum(best.alive, candidate_stats),
                    ),
                    ..kept_terms
                }
            } else {
                reattach_deleted(candidate, gone, points, candidate_stats, &p);
                energy(
                    candidate,
                    candidate_stats,
                    n,
                    &self.weights,
                    &mut self.scratch.xs,
                    &p,
                )
            };
            let e = terms.total;
            //= spec/guyonneau2022.md#ruby-iteration-alg-1-iterations
            //# An iteration whose set has a higher energy than the set kept
            //# before it MUST be discarded (Alg. 1, lines 26-27).
            if e <= best_energy {
                if same_set {
                    // The same counts; the sums of this re-attachment, in
                    // ray order, where the kept ones may have added a
                    // deleted model's points last.
                    for k in slots(best.alive) {
                        if let (Some(e), Some(&c)) =
                            (kept_stats.energy.get_mut(k), candidate_stats.energy.get(k))
                        {
                            *e = c;
                        }
                    }
                } else {
                    self.kept = 1_usize.saturating_sub(self.kept);
                }
                kept_terms = terms;
                best_energy = e;
                accepted = accepted.saturating_add(1);
                discarded = 0;
            } else if !drew {
                // The next iterations would start from the same set with the
                // generator where it was: the same set, discarded again.
                break;
            } else {
                //= spec/guyonneau2022.md#ruby-iteration-alg-1-iterations
                //# When the set a call starts from holds at least one model,
                //# the call MUST end once `converged_after` iterations in a row
                //# have been discarded (never when it is 0).
                discarded = discarded.saturating_add(1);
                if tracking && discarded == p.converged_after {
                    break;
                }
            }
        }

        let (best, _) = pair(&mut self.sets, self.kept);
        let (stats, _) = pair(&mut self.stats, self.kept);
        self.models.clear();
        for k in slots(best.alive) {
            let line = best.line(k);
            if let Ok(row) = Meters::new(line.b).and_then(|b| RowLine::new(line.a, b)) {
                let _ = self.models.push(Model {
                    line: row,
                    points: stats.count.get(k).copied().unwrap_or(0),
                    energy: stats.energy.get(k).copied().unwrap_or(0.0),
                });
            }
        }
        Found {
            energy: best_energy,
            start_energy,
            points: n,
            accepted,
            iterations,
        }
    }

    /// w_pq = exp(−‖p − q‖² / ζ²) of each pair of consecutive points (eq. 5).
    fn neighbour_weights(&mut self, points: &[RowPoint]) {
        let zeta = self.config.params.neighbour_scale.get();
        for (w, pair) in self.weights.iter_mut().zip(points.windows(2)) {
            *w = match pair {
                [p, q] => {
                    let dx = p.position.x() - q.position.x();
                    let dy = p.position.y() - q.position.y();
                    libm::exp(-(dx * dx + dy * dy) / (zeta * zeta))
                }
                _ => 0.0,
            };
        }
    }
}

/// The kept one and the candidate among `sets` (of models, or their stats).
fn pair<T>(sets: &mut [T; 2], kept: usize) -> (&mut T, &mut T) {
    let [first, second] = sets;
    if kept == 0 {
        (first, second)
    } else {
        (second, first)
    }
}

/// E(L) of eq. 1: ρ·|P(L∅)| (eq. 2) + λ Σ w_pq δ≠ over consecutive points
/// (eqs. 3-5) + Σ_j E_L(L_j) (eq. 6).
//= spec/guyonneau2022.md#ruby-energy-energy-of-a-set-of-models
//# The energy of a set MUST be ρ times the number of outliers, plus λ times
//# the sum over consecutive points p, q of exp(−‖p − q‖²/ζ²) for each pair
//# whose models differ, plus the sum over models of the distances of their
//# points to them.
fn energy<const N: usize>(
    set: &ModelSet<N>,
    stats: &Stats,
    n: usize,
    weights: &[f64; N],
    terms: &mut [f64; N],
    p: &RubyParams,
) -> Energy {
    let alive = set.alive;
    let masks = set.masks.get(..n).unwrap_or(&[]);
    // Without shared points, the re-attachments count the outliers in the
    // sink.
    let outliers = if p.variant.shared_points() {
        masks.iter().filter(|&&m| m & alive == 0).count()
    } else {
        stats.count.get(MAX_MODELS).copied().unwrap_or(0)
    };
    // Each pair's term, w or +0, in a pass the compiler vectorises; then
    // their sum in ray order, where adding +0 leaves the sum as it was,
    // bit for bit.
    let after = masks.get(1..).unwrap_or(&[]);
    for ((t, &w), (&m, &q)) in terms.iter_mut().zip(weights).zip(masks.iter().zip(after)) {
        *t = if (m & alive) == (q & alive) { 0.0 } else { w };
    }
    let mut neighbour = 0.0;
    for &t in terms.get(..after.len()).unwrap_or(&[]) {
        neighbour += t;
    }
    Energy {
        outliers,
        neighbour,
        total: total(p, outliers, neighbour, model_sum(alive, stats)),
    }
}

/// E(L) of a set (eq. 1) and the two terms of it that depend on its points'
/// masks alone: its outliers and its neighbour sum (without λ).
#[derive(Debug, Clone, Copy)]
struct Energy {
    outliers: usize,
    neighbour: f64,
    total: f64,
}

/// Σ_j E_L(L_j) over the models of `alive`, in slot order.
fn model_sum(alive: u64, stats: &Stats) -> f64 {
    slots(alive).filter_map(|k| stats.energy.get(k)).sum()
}

/// E(L) from its terms: ρ·|P(L∅)| + λ·(neighbour sum) + Σ_j E_L(L_j).
fn total(p: &RubyParams, outliers: usize, neighbour: f64, models: f64) -> f64 {
    p.outlier_energy * count_f64(outliers) + p.neighbour_penalty * neighbour + models
}

/// Whether `candidate`, once the models of `gone` are removed and their
/// points re-attached, is `kept`: the same live models with the same lines,
/// bit for bit, each holding as many points as in `kept` (`counts`,
/// `kept`'s). With the same lines, a model of `kept` can only lose points to
/// the models it does not share (a point is attached to its closest models,
/// RUBY-REATTACH), so the same count is the same points; the removed models'
/// points were then `kept`'s outliers, which the models left leave outliers.
fn ends_as<const N: usize>(
    kept: &ModelSet<N>,
    counts: &Stats,
    candidate: &ModelSet<N>,
    stats: &Stats,
    gone: u64,
) -> bool {
    let alive = kept.alive;
    let bits = |l: Line| (l.a.to_bits(), l.b.to_bits(), l.inv_norm.to_bits());
    candidate.alive & !gone == alive
        && slots(alive).all(|k| {
            bits(candidate.line(k)) == bits(kept.line(k))
                && stats.count.get(k) == counts.count.get(k)
        })
}

/// A uniform index below `len` (> 0) from 32 random bits (Lemire's
/// multiply-shift; the bias is below len / 2³², negligible for len ≤ 2¹⁶).
pub(crate) fn pick(rng: &mut Xoshiro128PlusPlus, len: usize) -> usize {
    let len64 = u64::try_from(len).unwrap_or(u64::MAX);
    let r = u64::from(rng.next_u32());
    usize::try_from(r.wrapping_mul(len64) >> 32).unwrap_or(0)
}

/// Seeds new models from triples of outliers (Alg. 1, lines 5-10; Alg. 3
/// with split sides).
//= spec/guyonneau2022.md#ruby-search-new-models-from-outliers
//# The search MUST draw three distinct outliers at random with the
//# detector's generator, remove them from the outliers and add the
//# least-squares line through them as a new model holding them, until the
//# outliers left are at most the search share of those it started with,
//# fewer than three remain, the iteration's model budget is spent or the set
//# is full.
fn search<const N: usize>(
    set: &mut ModelSet<N>,
    points: &[RowPoint],
    rng: &mut Xoshiro128PlusPlus,
    p: &RubyParams,
) -> bool {
    set.seeded = 0;
    if p.variant.split_sides() {
        //= spec/guyonneau2022.md#ruby-split-sides-seeds-left-and-right
        //# With split sides, the search MUST run on the outliers left of the
        //# robot (y > 0), then on those right of it (y < 0), each with half
        //# the iteration's model budget, rounded up.
        let budget = p.models_per_iteration.div_ceil(2);
        let left = search_side(set, points, rng, p, budget, |y| y > 0.0);
        let right = search_side(set, points, rng, p, budget, |y| y < 0.0);
        left || right
    } else {
        search_side(set, points, rng, p, p.models_per_iteration, |_| true)
    }
}

fn search_side<const N: usize>(
    set: &mut ModelSet<N>,
    points: &[RowPoint],
    rng: &mut Xoshiro128PlusPlus,
    p: &RubyParams,
    budget: u16,
    side: impl Fn(f64) -> bool,
) -> bool {
    let mut outliers: Vec<u16, N> = Vec::new();
    for (i, (pt, &m)) in points.iter().zip(set.masks.iter()).enumerate() {
        if m & set.alive == 0 && side(pt.position.y()) {
            if let Ok(i) = u16::try_from(i) {
                let _ = outliers.push(i);
            }
        }
    }
    let stop = p.search_until * count_f64(outliers.len());
    let mut added = 0_u16;
    while outliers.len() >= SEED_POINTS && count_f64(outliers.len()) > stop && added < budget {
        let free = !set.alive;
        if free == 0 {
            break;
        }
        let slot = usize::try_from(free.trailing_zeros()).unwrap_or(MAX_MODELS);
        let mut seed = [0_usize; SEED_POINTS];
        for s in &mut seed {
            *s = usize::from(outliers.swap_remove(pick(rng, outliers.len())));
        }
        added = added.saturating_add(1);
        let seeds = seed.map(|i| points.get(i).map(|q| q.position));
        if let [Some(a), Some(b), Some(c)] = seeds {
            let xs = [a.x(), b.x(), c.x()];
            let ys = [a.y(), b.y(), c.y()];
            if let (Some(line), Some(l)) = (Line::fit(&xs, &ys, 0), set.lines.get_mut(slot)) {
                *l = line;
                set.seeded |= bit(slot);
                set.alive |= bit(slot);
                set.fitted |= bit(slot);
                set.moved |= bit(slot);
                // A seed's fit mask keeps the models it was fitted with:
                // a model that lost it has changed and is refitted
                // (RUBY-MERGE); the new model keeps its line as seeded.
                for i in seed {
                    if let Some(m) = set.masks.get_mut(i) {
                        *m = bit(slot);
                    }
                }
            }
        }
    }
    added > 0
}

/// Whether two models are one (Alg. 1, line 13).
fn same(x: &Line, y: &Line, p: &RubyParams) -> bool {
    // Both tests evaluated, without a branch between them.
    (libm::fabs(x.a - y.a) < p.parallel_slope) & (libm::fabs(x.b - y.b) < p.same_intercept.get())
}

/// Merges models that are the same and refits every model to its points
/// (Alg. 1, lines 11-16), then merges again, refitting each merged model,
/// until no two are the same.
//= spec/guyonneau2022.md#ruby-merge-close-models-merged
//# Two models whose slopes differ by less than β and whose intercepts differ
//# by less than the same-model intercept MUST be merged: the lower slot takes
//# the other's points and is refitted by least squares over them; merging
//# MUST repeat until no two models of the set are the same, so that merging a
//# merged set changes nothing.
//= spec/guyonneau2022.md#ruby-merge-close-models-merged
//# Every model MUST be refitted by least squares to its points in each
//# iteration's first merge pass, merged or not, except a model seeded by
//# this iteration's search, which keeps the least-squares line of its seeds
//# unless it absorbs another.
fn merge<const N: usize>(
    set: &mut ModelSet<N>,
    cols: &Columns<N>,
    n: usize,
    scratch: &mut Scratch<N>,
    p: &RubyParams,
) {
    // Models whose points changed since they were fitted: the fit masks
    // still hold, at a point the search seeded, the models it was fitted
    // with. A model seeded by the search holds the seeds its line was fitted
    // to, whatever bits the fit masks hold for its slot (RUBY-MERGE).
    let changed = set
        .masks
        .get(..n)
        .unwrap_or(&[])
        .iter()
        .zip(set.fit_masks.get(..n).unwrap_or(&[]))
        .fold(0_u64, |acc, (m, f)| acc | (m ^ f));
    set.fitted &= !changed | set.seeded;
    // The first pass refits; each later pass but the last merges, removing
    // a model: at most MAX_MODELS + 1 passes.
    for pass in 0..=MAX_MODELS {
        let mut merged_any = false;
        for j in slots(set.alive) {
            if set.alive & bit(j) == 0 {
                continue;
            }
            let mut absorbed = 0_u64;
            let lj = set.line(j);
            // The models of the slots above j.
            for k in slots(set.alive & bit(j).wrapping_neg() & !bit(j)) {
                absorbed |= bit(k) & 0_u64.wrapping_sub(u64::from(same(&lj, &set.line(k), p)));
            }
            if absorbed != 0 {
                merged_any = true;
                for m in set.masks.iter_mut().take(n) {
                    if *m & absorbed != 0 {
                        *m = (*m & !absorbed) | bit(j);
                    }
                }
                set.alive &= !absorbed;
                set.moved |= bit(j);
            }
            if absorbed != 0 || (pass == 0 && set.fitted & bit(j) == 0) {
                if let Some(line) = set.fit(j, cols, n, scratch, p.fit_rounds) {
                    if let Some(l) = set.lines.get_mut(j) {
                        // A line moved may now be the same as one before it.
                        if *l != line {
                            merged_any = true;
                            set.moved |= bit(j);
                        }
                        *l = line;
                    }
                }
                set.fitted |= bit(j);
            }
        }
        if !merged_any {
            break;
        }
    }
    copy_first(&mut set.fit_masks, &set.masks, n);
    set.fitted = set.alive;
    set.seeded = 0;
}

/// ψ(L_j) of eq. 8, counting the model itself: the models whose slope
/// differs from `a` by less than β (eq. 9).
fn parallel_count<const N: usize>(set: &ModelSet<N>, a: f64, p: &RubyParams) -> f64 {
    count_f64(
        slots(set.alive)
            .filter(|&k| libm::fabs(set.line(k).a - a) < p.parallel_slope)
            .count(),
    )
}

/// Deletes models (Alg. 1, lines 17-20): by eq. 7 for Ruby, by the fitness
/// of eq. 10 for the genetic variants.
/// Returns the models deleted; the caller re-attaches their points
/// ([`reattach_deleted`]).
fn delete<const N: usize>(set: &ModelSet<N>, stats: &Stats, p: &RubyParams) -> u64 {
    let score = |k: usize| -> Option<f64> {
        let n = count_f64(stats.count.get(k).copied().unwrap_or(0));
        let e = stats.energy.get(k).copied().unwrap_or(0.0);
        let line = set.line(k);
        let psi = parallel_count(set, line.a, p);
        (n > 0.0).then(|| {
            if p.variant.genetic() {
                (line.b * line.b + p.fitness_weight * e) / (n * n * psi)
            } else {
                e / (psi * n)
            }
        })
    };
    let mut gone = 0_u64;
    if p.variant.genetic() {
        //= spec/guyonneau2022.md#ruby-fitness-genetic-deletion
        //# The genetic variants MUST keep the models of lowest fitness
        //# φ = (b² + τ E_L) / (n² ψ), n the model's points and ψ the models
        //# parallel to it, itself included: the kept share of the models,
        //# rounded up, and at least the configured fewest when there are as
        //# many, ties going to the lower slot; the others MUST be deleted.
        let mut ranked: Vec<(f64, usize), MAX_MODELS> = Vec::new();
        for k in slots(set.alive) {
            match score(k) {
                Some(phi) if phi.is_finite() => {
                    let _ = ranked.push((phi, k));
                }
                _ => gone |= bit(k),
            }
        }
        ranked.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let share = libm::ceil(p.kept_share * count_f64(ranked.len()));
        let keep = (0..=ranked.len())
            .find(|&k| count_f64(k) >= share)
            .unwrap_or(ranked.len())
            .max(usize::from(p.min_kept));
        for &(_, k) in ranked.iter().skip(keep) {
            gone |= bit(k);
        }
    } else {
        //= spec/guyonneau2022.md#ruby-delete-deletion-by-eq-7
        //# Ruby MUST delete every model with E_L / (ψ n) − α ≥ 0, n its
        //# points and ψ the models parallel to it, itself included, and every
        //# model with no point.
        for k in slots(set.alive) {
            match score(k) {
                Some(s) if s - p.alpha < 0.0 => {}
                _ => gone |= bit(k),
            }
        }
    }
    gone
}

/// Removes the models of `gone` and re-attaches their points to the models
/// left, updating `stats`: the same assignment as re-attaching every point
/// (a point of a model left keeps it, being closest among more models;
/// outliers stay outliers), at the cost of the points moved alone.
fn reattach_deleted<const N: usize>(
    set: &mut ModelSet<N>,
    gone: u64,
    points: &[RowPoint],
    stats: &mut Stats,
    p: &RubyParams,
) {
    if gone == 0 {
        return;
    }
    set.alive &= !gone;
    set.fitted &= !gone;
    for k in slots(gone) {
        stats.clear(k);
    }
    let limit = p.outlier_distance.get();
    let mut packed: Vec<(u64, usize, Line), MAX_MODELS> = Vec::new();
    for k in slots(set.alive) {
        let _ = packed.push((bit(k), k, set.line(k)));
    }
    for ((pt, m), dist) in points
        .iter()
        .zip(set.masks.iter_mut())
        .zip(set.dist.iter_mut())
    {
        if *m & gone == 0 {
            continue;
        }
        if p.variant.shared_points() {
            *m &= !gone;
            continue;
        }
        let mut closest = (f64::INFINITY, MAX_MODELS, 0_u64);
        for &(b, k, line) in &packed {
            let d = line.distance(pt.position);
            if d <= limit && d < closest.0 {
                closest = (d, k, b);
            }
        }
        *m = closest.2;
        // An outlier (slot `MAX_MODELS`) is counted in the sink.
        *dist = if closest.2 == 0 { limit } else { closest.0 };
        stats.add(closest.1, *dist);
    }
}

/// The float after `x` (> 0 and finite, as the outlier distance is): a
/// distance is at most `x` when it is below it.
fn float_after(x: f64) -> f64 {
    f64::from_bits(x.to_bits().saturating_add(1))
}

/// Whether a distance equals the one to beat: a tie for the slot order
/// (RUBY-REATTACH). Exact equality is the point: a test by difference
/// costs the vectorised pass an instruction more.
#[allow(clippy::float_cmp)]
#[inline]
fn tied(d: f64, best: f64) -> bool {
    d == best
}

/// After a strict pass of `models` (bits and lines) over the points, the
/// lowest slot among the models at each point's distance: the ties the
/// strict pass left to the first model (an outlier's distance, the limit,
/// is a tie with no model).
fn lowest_on_ties(xs: &[f64], ys: &[f64], best: &[f64], masks: &mut [u64], models: &[(u64, Line)]) {
    for ((&x, &y), (&best, m)) in xs.iter().zip(ys).zip(best.iter().zip(masks.iter_mut())) {
        for &(k, line) in models {
            if tied(line.distance_xy(x, y), best) && (k < *m || *m == 0) {
                *m = k;
            }
        }
    }
}

/// Defines a pass of moved models, in slot order, over the points of
/// columns `xs`, `ys`: each point takes a model strictly closer than its
/// distance to beat, in one loop without branches (a minimum and a select
/// per point and model) which the compiler vectorises; then, if any
/// distance equalled the one to beat, the lowest slot among each point's
/// closest. One function per number of models: a loop over an array of
/// models inside the points' loop is not vectorised as well.
macro_rules! closer {
    ($name:ident, $doc:literal, $(($k:ident, $l:ident)),+) => {
        #[doc = $doc]
        #[inline]
        fn $name(
            xs: &[f64],
            ys: &[f64],
            best: &mut [f64],
            masks: &mut [u64],
            $(($k, $l): (u64, Line)),+
        ) {
            let mut tie = false;
            for ((&x, &y), (best, m)) in
                xs.iter().zip(ys).zip(best.iter_mut().zip(masks.iter_mut()))
            {
                let (mut b, mut q) = (*best, *m);
                $(
                    let d = $l.distance_xy(x, y);
                    tie |= tied(d, b);
                    let take = d < b;
                    b = if take { d } else { b };
                    q = if take { $k } else { q };
                )+
                (*best, *m) = (b, q);
            }
            if tie {
                lowest_on_ties(xs, ys, best, masks, &[$(($k, $l)),+]);
            }
        }
    };
}

closer!(closer1, "A pass of one moved model.", (k1, l1));
closer!(closer2, "A pass of two moved models.", (k1, l1), (k2, l2));
closer!(
    closer3,
    "A pass of three moved models.",
    (k1, l1),
    (k2, l2),
    (k3, l3)
);

/// Re-attaches every point (Alg. 1, lines 21-24), then removes the models
/// left with fewer than [`SEED_POINTS`] points and re-attaches theirs.
//= spec/guyonneau2022.md#ruby-reattach-points-re-attached
//# Every point MUST be attached to the model closest to it, or to several
//# models (every model within the outlier distance) when points are shared,
//# and MUST be an outlier when no model lies within the outlier distance;
//# a model left with fewer than three points MUST then be removed and its
//# points re-attached to the models left.
fn reattach<const N: usize>(
    set: &mut ModelSet<N>,
    points: &[RowPoint],
    cols: &mut Columns<N>,
    p: &RubyParams,
    stats: &mut Stats,
) {
    let limit = p.outlier_distance.get();
    let n = points.len();
    let moved = set.moved & set.alive;
    let mut changed: Vec<(u64, Line), MAX_MODELS> = Vec::new();
    let mut steady: Vec<(u64, Line), MAX_MODELS> = Vec::new();
    for k in slots(set.alive) {
        if moved & bit(k) != 0 {
            let _ = changed.push((bit(k), set.line(k)));
        } else {
            let _ = steady.push((bit(k), set.line(k)));
        }
    }
    let xy = cols.xs.iter().zip(cols.ys.iter()).take(n);
    // The sums of the live models and the sink start again; no other slot's
    // is read.
    for k in slots(set.alive) {
        stats.clear(k);
    }
    stats.clear(MAX_MODELS);
    if p.variant.shared_points() {
        // Models that did not move keep their points; the moved ones take
        // those within the limit.
        for m in set.masks.iter_mut().take(n) {
            *m &= !moved;
        }
        for &(b, line) in &changed {
            for ((&x, &y), m) in xy.clone().zip(set.masks.iter_mut()) {
                if line.distance_xy(x, y) <= limit {
                    *m |= b;
                }
            }
        }
        for ((&x, &y), &m) in xy.zip(set.masks.iter()) {
            for k in slots(m) {
                stats.add(k, set.line(k).distance_xy(x, y));
            }
        }
    } else {
        // A point of a model that did not move is closest to it among the
        // models that did not move: only the moved ones can take it. The
        // closest is the least (distance, slot), as a scan of every model
        // in slot order finds it.
        let xs = cols.xs.get(..n).unwrap_or(&[]);
        let ys = cols.ys.get(..n).unwrap_or(&[]);
        let best = set.dist.get_mut(..n).unwrap_or(&mut []);
        let masks = set.masks.get_mut(..n).unwrap_or(&mut []);
        // The points of the models that did not move, and the outliers,
        // hold their distance from the last re-attachment (the same line,
        // the same bits); the points of a moved model start from the
        // closest model that did not move.
        if moved != 0 {
            for (((&x, &y), m), best) in
                xs.iter().zip(ys).zip(masks.iter_mut()).zip(best.iter_mut())
            {
                if *m & moved == 0 {
                    continue;
                }
                // The first model in slot order at the least distance
                // within the limit (at most the limit: below the float
                // after it), by a minimum and a select.
                let (mut d_best, mut m_best) = (float_after(limit), 0_u64);
                for &(k, line) in &steady {
                    let d = line.distance_xy(x, y);
                    let take = d < d_best;
                    d_best = if take { d } else { d_best };
                    m_best = if take { k } else { m_best };
                }
                // With no model yet, the limit stands for the distance to
                // beat: a moved model takes the point when within it
                // (RUBY-REATTACH), and no test of the limit is left in the
                // loop below.
                (*best, *m) = if m_best == 0 {
                    (limit, 0)
                } else {
                    (d_best, m_best)
                };
            }
        }
        // Each moved model over every point: one loop per model on columns
        // alone, without branches (a minimum and a select per point), which
        // the compiler vectorises; the masks, one bit each, are ordered as
        // the slots are. A point's distance to beat is never above the
        // limit: the closest within it wins, ties to the lower slot. Two
        // models per pass over the points, in slot order, halve the loads
        // and stores of the columns; an odd number, three or more, starts
        // with three in one pass, and a model alone has a pass of its own.
        // The pass takes a model strictly closer alone and notes whether
        // any distance equalled the one to beat; only then does a second
        // pass give each tied point the lowest slot among its closest (the
        // least (distance, slot), as a scan of every model in slot order
        // finds it).
        let odd = changed.len() % 2 == 1;
        let (three, rest) = changed
            .split_at_checked(if odd { 3 } else { 0 })
            .unwrap_or((&[], changed.as_slice()));
        if let [one, two, three] = *three {
            closer3(xs, ys, best, masks, one, two, three);
        }
        for pair in rest.chunks(2) {
            match *pair {
                [one, two] => closer2(xs, ys, best, masks, one, two),
                [one] => closer1(xs, ys, best, masks, one),
                _ => {}
            }
        }
        // An outlier (no bit: slot `MAX_MODELS`) goes to the sink.
        for (&m, &best) in masks.iter().zip(best.iter()) {
            stats.add(slot_of(m), best);
        }
    }
    set.moved = 0;
    let few = slots(set.alive)
        .filter(|&k| stats.count.get(k).copied().unwrap_or(0) < SEED_POINTS)
        .fold(0_u64, |acc, k| acc | bit(k));
    reattach_deleted(set, few, points, stats, p);
}

#[cfg(test)]
mod tests {
    //! The re-attachment's strict pass and its second pass on ties
    //! (RUBY-REATTACH): a point at the same distance from a model that did
    //! not move and from a moved one of a lower slot goes to the lower slot.

    use super::*;

    const N: usize = 16;

    /// The points `pts` as columns and as row points, in their order.
    fn laid_out<const K: usize>(
        pts: &[(f64, f64); K],
    ) -> Result<(Columns<N>, [RowPoint; K]), Precondition> {
        let mut cols = Columns::<N> {
            xs: [0.0; N],
            ys: [0.0; N],
        };
        let mut points = [RowPoint {
            position: Point2::origin(),
            returns: 1,
        }; K];
        for (i, &(x, y)) in pts.iter().enumerate() {
            cols.xs[i] = x;
            cols.ys[i] = y;
            points[i].position = Point2::new(x, y)?;
        }
        Ok((cols, points))
    }

    /// Room for a fit.
    const SCRATCH: Scratch<N> = Scratch {
        xs: [0.0; N],
        ys: [0.0; N],
    };

    /// Row A (y = 0, slot 1, steady) holding every point of y = 0, the
    /// point (4, 0) included, which lies on row B (y = x/2 − 2, slot 0,
    /// moved) as well; B's own points; with `others` (0 to 2), as many
    /// moved models in slots 2 and 3 far from every point, so that B is
    /// re-attached alone, in a pair or in a pass of three.
    fn reattached(others: usize) -> Result<(ModelSet<N>, [(f64, f64); 9]), Precondition> {
        let pts = [
            (1.0, 0.0),
            (2.0, 0.0),
            (3.0, 0.0),
            (4.0, 0.0),
            (5.0, 0.0),
            (2.0, -1.0),
            (3.0, -0.5),
            (5.0, 0.5),
            (6.0, 1.0),
        ];
        let p = RubyParams::authors(Variant::Rgop);
        let flat =
            Line::new(0.0, 0.0).ok_or(Precondition::new("RUBY-REATTACH", "a finite line"))?;
        let slanted =
            Line::new(0.5, -2.0).ok_or(Precondition::new("RUBY-REATTACH", "a finite line"))?;
        let mut set = ModelSet::<N> {
            alive: 0b11,
            fitted: 0b11,
            moved: 0b01,
            ..ModelSet::EMPTY
        };
        set.lines[0] = slanted;
        set.lines[1] = flat;
        for (k, b) in [(2, 3.0), (3, 5.0)].into_iter().take(others) {
            set.lines[k] =
                Line::new(0.0, b).ok_or(Precondition::new("RUBY-REATTACH", "a finite line"))?;
            set.alive |= bit(k);
            set.moved |= bit(k);
        }
        let (mut cols, points) = laid_out(&pts)?;
        for (i, &(x, y)) in pts.iter().enumerate() {
            // The flat row's points are attached to it, the others to B.
            if y == 0.0 {
                set.masks[i] = bit(1);
                set.dist[i] = flat.distance_xy(x, y);
            } else {
                set.masks[i] = bit(0);
            }
        }
        let mut stats = Stats::ZERO;
        reattach(&mut set, &points, &mut cols, &p, &mut stats);
        Ok((set, pts))
    }

    /// Every point on the model of least (distance, slot) within the
    /// outlier distance.
    fn assert_closest(set: &ModelSet<N>, pts: &[(f64, f64)]) {
        let limit = RubyParams::authors(Variant::Rgop).outlier_distance.get();
        for (i, &(x, y)) in pts.iter().enumerate() {
            let expected = slots(set.alive)
                .map(|k| (set.line(k).distance_xy(x, y), k))
                .filter(|&(d, _)| d <= limit)
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
                .map_or(0, |(_, k)| bit(k));
            assert_eq!(set.masks[i], expected, "point {i} at ({x}, {y})");
        }
    }

    //= spec/guyonneau2022.md#ruby-fit-models-fitted-by-least-absolute-deviations
    //= type=test
    //# Each fit MUST be the weighted least-squares line of the sums about the
    //# model's first point (x₀, y₀) in ray order: with u = x − x₀ and v = y − y₀,
    //# S = Σ w, S_u = Σ w u, S_v = Σ w v, S_uu = Σ w u u and S_uv = Σ w u v summed
    //# in ray order (w u computed once per point), D = S S_uu − S_u S_u, the slope
    //# a = (S S_uv − S_u S_v) / D, c = (S_v − a S_u) / S and the intercept
    //# b = y₀ + c − a x₀; the least-squares start has every w = 1, and a fit with
    //# D ≤ 10⁻¹² S S_uu (the points' x the same) or a result not finite MUST give
    //# no line (the start) or end the re-weighting with the line before.
    #[test]
    fn a_fit_is_the_line_of_the_sums_about_the_first_point() -> Result<(), Precondition> {
        use crate::geometry::fit::fit_line;
        // Points on y = 0.3 x − 1.2 far from the origin: the line itself.
        let xs = [100.0, 100.5, 101.25, 102.0, 103.5];
        let ys = xs.map(|x| 0.3 * x - 1.2);
        let line = Line::fit(&xs, &ys, 4);
        assert!(line.is_some_and(|l| (l.a - 0.3).abs() < 1e-12 && (l.b + 1.2).abs() < 1e-9));
        // The start is the least-squares line of FIT-LINE, to rounding.
        let noisy = [0.3, -0.2, 0.25, 0.0, -0.1];
        let ys: [f64; 5] = core::array::from_fn(|i| ys[i] + noisy[i]);
        let points: [Point2<Robot>; 5] = [
            Point2::new(xs[0], ys[0])?,
            Point2::new(xs[1], ys[1])?,
            Point2::new(xs[2], ys[2])?,
            Point2::new(xs[3], ys[3])?,
            Point2::new(xs[4], ys[4])?,
        ];
        let lsq = fit_line(points);
        let start = Line::fit(&xs, &ys, 0);
        assert!(matches!((lsq, start), (Ok(q), Some(l))
            if (l.a - q.a).abs() < 1e-9 && (l.b - q.b).abs() < 1e-7));
        // Re-weighting pulls the line to the points on it: three on
        // y = 0.3 x − 1.2, one 1 m off, a fifth 0.5 m off.
        let ys = [
            0.3 * 100.0 - 1.2,
            0.3 * 100.5 - 1.2,
            0.3 * 101.25 - 1.2 + 1.0,
            0.3 * 102.0 - 1.2,
            0.3 * 103.5 - 1.2 - 0.5,
        ];
        let lad = Line::fit(&xs, &ys, 4);
        let ls = Line::fit(&xs, &ys, 0);
        let off = |l: Line| (l.a * 100.5 + l.b - (0.3 * 100.5 - 1.2)).abs();
        assert!(matches!((lad, ls), (Some(lad), Some(ls)) if off(lad) < off(ls) / 2.0));
        // The same x: no line.
        assert!(Line::fit(&[2.0; 4], &[0.0, 1.0, 2.0, 3.0], 4).is_none());
        Ok(())
    }

    //= spec/guyonneau2022.md#ruby-merge-close-models-merged
    //= type=test
    //# Every model MUST be refitted by least squares to its points in each
    //# iteration's first merge pass, merged or not, except a model seeded by
    //# this iteration's search, which keeps the least-squares line of its seeds
    //# unless it absorbs another.
    #[test]
    fn a_seed_keeps_its_line_wherever_it_is_stored() -> Result<(), Precondition> {
        let p = RubyParams::authors(Variant::Rgop);
        // Seeds (0, 0), (1, 0.1), (2, 0.05) in slot 1, whose fit masks an
        // older model of slot 1 left on points 3-5; slot 0 a far row whose
        // points did not change.
        let pts = [
            (0.0, 0.0),
            (1.0, 0.1),
            (2.0, 0.05),
            (0.5, 3.0),
            (1.5, 3.0),
            (2.5, 3.0),
        ];
        let (cols, _) = laid_out(&pts)?;
        let seed = Line::fit(&cols.xs[..3], &cols.ys[..3], 0)
            .ok_or(Precondition::new("RUBY-FIT", "a seed's line"))?;
        let row = Line::new(0.0, 3.0).ok_or(Precondition::new("RUBY-FIT", "a finite line"))?;
        let mut set = ModelSet::<N> {
            alive: 0b11,
            fitted: 0b11,
            moved: 0b10,
            seeded: 0b10,
            ..ModelSet::EMPTY
        };
        set.lines[0] = row;
        set.lines[1] = seed;
        set.masks[..6].copy_from_slice(&[2, 2, 2, 1, 1, 1]);
        set.fit_masks[..6].copy_from_slice(&[2, 2, 2, 3, 3, 3]);
        let mut scratch = SCRATCH;
        merge(&mut set, &cols, pts.len(), &mut scratch, &p);
        // The seed keeps its least-squares line; re-weighted, its three
        // points would give another.
        assert_eq!(set.lines[1], seed);
        assert_ne!(
            Line::fit(&cols.xs[..3], &cols.ys[..3], p.fit_rounds),
            Some(seed)
        );
        // The row, whose points changed since its fit (the old bits), is
        // refitted to its points: y = 3.
        assert!((set.lines[0].b - 3.0).abs() < 1e-12 && set.lines[0].a.abs() < 1e-12);
        Ok(())
    }

    //= spec/guyonneau2022.md#ruby-merge-close-models-merged
    //= type=test
    //# Every model MUST be refitted by least squares to its points in each
    //# iteration's first merge pass, merged or not, except a model seeded by
    //# this iteration's search, which keeps the least-squares line of its seeds
    //# unless it absorbs another.
    #[test]
    fn a_model_that_lost_a_point_to_a_seed_is_refitted() -> Result<(), Precondition> {
        let p = RubyParams::authors(Variant::Rgop);
        // Row A (slot 0) was fitted to points 0-5 (y = 0.05 stands for
        // that line); point 5 has since become an outlier, and with the
        // two other outliers it is all the search can seed.
        let pts = [
            (0.0, 0.0),
            (1.0, 0.0),
            (2.0, 0.0),
            (3.0, 0.0),
            (4.0, 0.0),
            (0.5, 0.5),
            (1.0, 3.0),
            (2.0, 3.5),
        ];
        let (cols, points) = laid_out(&pts)?;
        let mut set = ModelSet::<N> {
            alive: 0b1,
            fitted: 0b1,
            ..ModelSet::EMPTY
        };
        set.lines[0] =
            Line::new(0.0, 0.05).ok_or(Precondition::new("RUBY-MERGE", "a finite line"))?;
        set.masks[..8].copy_from_slice(&[1, 1, 1, 1, 1, 0, 0, 0]);
        set.fit_masks[..8].copy_from_slice(&[1, 1, 1, 1, 1, 1, 0, 0]);
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(p.seed);
        assert!(search(&mut set, &points, &mut rng, &p));
        assert_eq!((set.alive, &set.masks[5..8]), (0b11, &[2, 2, 2][..]));
        let mut scratch = SCRATCH;
        merge(&mut set, &cols, pts.len(), &mut scratch, &p);
        // A's points changed: it is the line of the five it holds, y = 0.
        assert_eq!(
            Some(set.lines[0]),
            Line::fit(&cols.xs[..5], &cols.ys[..5], p.fit_rounds)
        );
        assert_eq!((set.lines[0].a, set.lines[0].b), (0.0, 0.0));
        Ok(())
    }

    /// A kept row (slot 0, y = 0) and a candidate with a new model in
    /// slot 1, re-attached, slot 1 then deleted: it ends as the kept set
    /// when the new model took the kept set's outliers alone, and not when
    /// it took a point of the row or the row's line moved.
    #[test]
    fn an_iteration_ends_as_the_kept_set_only_with_its_points_and_lines() -> Result<(), Precondition>
    {
        let p = RubyParams::authors(Variant::Rgop);
        // The row's four points (the last 0.1 off it), then four outliers.
        let xs = [0.0, 1.0, 2.0, 3.0, 0.5, 1.5, 2.25, 2.5];
        let ys = [0.0, 0.0, 0.0, 0.1, 1.0, 1.0, 0.55, 1.0];
        let pts: [(f64, f64); 8] = core::array::from_fn(|i| (xs[i], ys[i]));
        let line = |a: f64, b: f64| Line::new(a, b).ok_or(Precondition::new("RUBY-FIT", "a line"));
        let (cols, points) = laid_out(&pts)?;
        let mut kept = ModelSet::<N> {
            alive: 0b1,
            fitted: 0b1,
            moved: 0b1,
            dist: [p.outlier_distance.get(); N],
            ..ModelSet::EMPTY
        };
        kept.lines[0] = line(0.0, 0.0)?;
        let mut kept_stats = Stats::ZERO;
        reattach(&mut kept, &points, &mut cols.clone(), &p, &mut kept_stats);
        assert_eq!(&kept.masks[..8], &[1, 1, 1, 1, 0, 0, 0, 0]);
        let ends = |new: Line, row: Line| -> bool {
            let mut candidate = kept.clone();
            candidate.lines[1] = new;
            candidate.alive |= 0b10;
            candidate.moved = 0b10;
            if row != kept.lines[0] {
                candidate.lines[0] = row;
                candidate.moved |= 0b1;
            }
            let mut stats = Stats::ZERO;
            reattach(&mut candidate, &points, &mut cols.clone(), &p, &mut stats);
            // The new model kept its three points: the deletion removes it.
            assert_eq!(stats.count[1], 3);
            ends_as(&kept, &kept_stats, &candidate, &stats, 0b10)
        };
        // y = 1 takes the three outliers on it.
        assert!(ends(line(0.0, 1.0)?, kept.lines[0]));
        // y = −0.6 x + 1.9 takes two outliers and the row's (3, 0.1).
        assert!(!ends(line(-0.6, 1.9)?, kept.lines[0]));
        // The row refitted to a line a bit off.
        assert!(!ends(line(0.0, 1.0)?, line(0.0, 1.0e-9)?));
        Ok(())
    }

    //= spec/guyonneau2022.md#ruby-reattach-points-re-attached
    //= type=test
    //# Every point MUST be attached to the model closest to it, or to several
    //# models (every model within the outlier distance) when points are shared,
    //# and MUST be an outlier when no model lies within the outlier distance;
    //# a model left with fewer than three points MUST then be removed and its
    //# points re-attached to the models left.
    #[test]
    fn a_tie_goes_to_the_lower_slot_alone_in_a_pair_or_three() -> Result<(), Precondition> {
        for others in 0..=2 {
            let (set, pts) = reattached(others)?;
            // (4, 0) lies on both rows: slot 0 takes it from slot 1.
            assert_eq!(set.masks[3], bit(0), "other moved models: {others}");
            assert_closest(&set, &pts);
        }
        Ok(())
    }
}
