//! A straightforward reference of Ruby's line finder and its refinements
//! (Guyonneau et al. 2022, "LiDAR-Only Crop Navigation for Symmetrical
//! Robot", section 2, Alg. 1 with the choices of `spec/guyonneau2022.md`,
//! RUBY-*), for checking the library's `ruby::Ruby` bit for bit and timing
//! it beside it.
//!
//! Plain `std` code: every re-attachment compares every point with every
//! model in slot order, every energy and fitness is computed afresh, nothing
//! is cached between the steps. The first merge pass refits every model
//! whose points are not those its line was last fitted to (RUBY-MERGE): each
//! model keeps the list of the points it was fitted to, its seeds for a new
//! model, and the pass compares it with the points the model holds.
//! The floating-point operations are those the spec states, in the order
//! it states them (points in ray order, models in slot order), so that the
//! same scans and seed give the same bits.

// Test and bench code may index.
#![allow(
    dead_code,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss,
    clippy::cast_possible_truncation,
    clippy::unwrap_used
)]

use fieldguide::geometry::fit::MIN_RELATIVE_X_SPREAD;
use fieldguide::perception::rows::points::RowPoint;
use fieldguide::perception::rows::ruby::{RubyParams, LAD_FLOOR, MAX_MODELS, SEED_POINTS};
use fieldguide::{Point2, Robot};
use rand_core::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro128PlusPlus;

/// A line y = a x + b with 1 / sqrt(a² + 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    pub a: f64,
    pub b: f64,
    inv_norm: f64,
}

impl Line {
    fn new(a: f64, b: f64) -> Option<Self> {
        let inv_norm = 1.0 / (a * a + 1.0).sqrt();
        (a.is_finite() && b.is_finite() && inv_norm > 0.0).then_some(Self { a, b, inv_norm })
    }

    /// ‖p − L‖ (eq. 6).
    fn distance(&self, p: &RowPoint) -> f64 {
        (self.a * p.position.x() + self.b - p.position.y()).abs() * self.inv_norm
    }

    /// Least squares, then `rounds` re-weightings by 1 / max(|r|, 1 mm)
    /// (RUBY-FIT), each the weighted least-squares line of the sums about
    /// the first point.
    fn fit(points: &[Point2<Robot>], rounds: u8) -> Option<Self> {
        let first = points.first()?;
        let (x0, y0) = (first.x(), first.y());
        let shifted: Vec<(f64, f64)> = points.iter().map(|p| (p.x() - x0, p.y() - y0)).collect();
        let mut weights = vec![1.0; points.len()];
        let (mut a, mut c) = weighted_line(&shifted, &weights)?;
        for _ in 0..rounds {
            for (w, &(u, v)) in weights.iter_mut().zip(&shifted) {
                *w = 1.0 / (v - a * u - c).abs().max(LAD_FLOOR);
            }
            if weights.iter().any(|&w| w <= 0.0 || w.is_nan()) {
                break;
            }
            match weighted_line(&shifted, &weights) {
                Some(next) => (a, c) = next,
                None => break,
            }
        }
        Self::new(a, y0 + c - a * x0)
    }

    fn same(&self, other: &Self, p: &RubyParams) -> bool {
        (self.a - other.a).abs() < p.parallel_slope
            && (self.b - other.b).abs() < p.same_intercept.get()
    }
}

/// The weighted least-squares line v = a u + c through `points` (u, v),
/// as (a, c), from Σ w, Σ w u, Σ w v, Σ w u², Σ w u v summed in point order
/// (RUBY-FIT); none when the u are all the same (to MIN_RELATIVE_X_SPREAD)
/// or a result is not finite.
fn weighted_line(points: &[(f64, f64)], weights: &[f64]) -> Option<(f64, f64)> {
    let (mut sw, mut su, mut sv, mut suu, mut suv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (&(u, v), &w) in points.iter().zip(weights) {
        sw += w;
        su += w * u;
        sv += w * v;
        suu += w * u * u;
        suv += w * u * v;
    }
    let det = sw * suu - su * su;
    let a = (sw * suv - su * sv) / det;
    let c = (sv - a * su) / sw;
    (det > MIN_RELATIVE_X_SPREAD * sw * suu && a.is_finite() && c.is_finite()).then_some((a, c))
}

/// One model returned: line, points, energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefModel {
    pub a: f64,
    pub b: f64,
    pub points: usize,
    pub energy: f64,
}

/// What one call did (as `ruby::Found`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefFound {
    pub energy: f64,
    pub start_energy: f64,
    pub points: usize,
    pub accepted: u16,
}

fn bit(k: usize) -> u64 {
    1_u64 << k
}

/// A set of models: a line per slot, which points each holds (a mask per
/// point) and, per slot, the points its line was last fitted to (none for a
/// line not fitted on this scan's points).
#[derive(Debug, Clone)]
struct Set {
    lines: [Option<Line>; MAX_MODELS],
    masks: Vec<u64>,
    fitted_to: Vec<Option<Vec<usize>>>,
}

impl Set {
    fn alive(&self) -> u64 {
        (0..MAX_MODELS)
            .filter(|&k| self.lines[k].is_some())
            .fold(0, |acc, k| acc | bit(k))
    }

    fn slots(&self) -> Vec<usize> {
        (0..MAX_MODELS)
            .filter(|&k| self.lines[k].is_some())
            .collect()
    }

    fn remove(&mut self, k: usize) {
        self.lines[k] = None;
        self.fitted_to[k] = None;
    }

    /// The points model `k` holds, in ray order.
    fn members(&self, k: usize) -> Vec<usize> {
        (0..self.masks.len())
            .filter(|&i| self.masks[i] & bit(k) != 0)
            .collect()
    }
}

/// |P(L)| and E_L(L) per slot.
#[derive(Debug, Clone, Copy)]
struct Stats {
    count: [usize; MAX_MODELS],
    energy: [f64; MAX_MODELS],
}

impl Stats {
    fn add(&mut self, k: usize, d: f64) {
        self.count[k] += 1;
        self.energy[k] += d;
    }
}

/// The reference line finder and its generator.
#[derive(Debug, Clone)]
pub struct Reference {
    p: RubyParams,
    rng: Xoshiro128PlusPlus,
    carried: Vec<(f64, f64)>,
    models: Vec<RefModel>,
}

impl Reference {
    pub fn new(p: RubyParams) -> Self {
        Self {
            p,
            rng: Xoshiro128PlusPlus::seed_from_u64(p.seed),
            carried: Vec::new(),
            models: Vec::new(),
        }
    }

    pub fn models(&self) -> &[RefModel] {
        &self.models
    }

    /// Alg. 1 on `points`, from the last call's lines (RUBY-ITERATION).
    pub fn find(&mut self, points: &[RowPoint]) -> RefFound {
        let p = self.p;
        let n = points.len();
        let zeta = p.neighbour_scale.get();
        let weights: Vec<f64> = points
            .windows(2)
            .map(|w| {
                let dx = w[0].position.x() - w[1].position.x();
                let dy = w[0].position.y() - w[1].position.y();
                libm::exp(-(dx * dx + dy * dy) / (zeta * zeta))
            })
            .collect();
        let mut best = Set {
            lines: [None; MAX_MODELS],
            masks: vec![0; n],
            fitted_to: vec![None; MAX_MODELS],
        };
        for (k, &(a, b)) in self.carried.iter().enumerate().take(MAX_MODELS) {
            best.lines[k] = Line::new(a, b);
        }
        attach(&mut best, points, &p);
        merge(&mut best, points, &p);
        let mut stats = attach(&mut best, points, &p);
        let start_energy = energy(&best, &stats, &weights, &p);
        let mut best_energy = start_energy;
        let mut accepted = 0_u16;
        // A call from a set holding a model ends after `converged_after`
        // discarded iterations in a row (RUBY-ITERATION).
        let tracking = !best.slots().is_empty();
        let mut discarded = 0_u16;
        for _ in 0..p.iterations {
            let mut candidate = best.clone();
            search(&mut candidate, points, &mut self.rng, &p);
            merge(&mut candidate, points, &p);
            let mut candidate_stats = attach(&mut candidate, points, &p);
            let gone = delete(&candidate, &candidate_stats, &p);
            reattach_removed(&mut candidate, gone, points, &mut candidate_stats, &p);
            let e = energy(&candidate, &candidate_stats, &weights, &p);
            if e <= best_energy {
                best = candidate;
                best_energy = e;
                stats = candidate_stats;
                accepted += 1;
                discarded = 0;
            } else {
                discarded += 1;
                if tracking && discarded == p.converged_after {
                    break;
                }
            }
        }
        self.models = best
            .slots()
            .into_iter()
            .map(|k| {
                let line = best.lines[k].unwrap();
                RefModel {
                    a: line.a,
                    b: line.b,
                    points: stats.count[k],
                    energy: stats.energy[k],
                }
            })
            .collect();
        self.carried = self.models.iter().map(|m| (m.a, m.b)).collect();
        RefFound {
            energy: best_energy,
            start_energy,
            points: n,
            accepted,
        }
    }
}

/// Every point to the closest model within the outlier distance (ties to
/// the lower slot), or to every model within it when points are shared;
/// then the models of fewer than three points removed and their points
/// re-attached (RUBY-REATTACH).
fn attach(set: &mut Set, points: &[RowPoint], p: &RubyParams) -> Stats {
    let limit = p.outlier_distance.get();
    let slots = set.slots();
    let mut stats = Stats {
        count: [0; MAX_MODELS],
        energy: [0.0; MAX_MODELS],
    };
    for (i, pt) in points.iter().enumerate() {
        if p.variant.shared_points() {
            let mut mask = 0;
            for &k in &slots {
                let d = set.lines[k].unwrap().distance(pt);
                if d <= limit {
                    mask |= bit(k);
                    stats.add(k, d);
                }
            }
            set.masks[i] = mask;
        } else {
            set.masks[i] = closest(set, &slots, pt, limit, &mut stats);
        }
    }
    let few = slots
        .iter()
        .filter(|&&k| stats.count[k] < SEED_POINTS)
        .fold(0, |acc, &k| acc | bit(k));
    reattach_removed(set, few, points, &mut stats, p);
    stats
}

/// The mask of the model closest to `pt` among `slots` (0 if none lies
/// within `limit`), its distance added to `stats`.
fn closest(set: &Set, slots: &[usize], pt: &RowPoint, limit: f64, stats: &mut Stats) -> u64 {
    let mut found: Option<(f64, usize)> = None;
    for &k in slots {
        let d = set.lines[k].unwrap().distance(pt);
        if d <= limit && found.is_none_or(|(best, _)| d < best) {
            found = Some((d, k));
        }
    }
    found.map_or(0, |(d, k)| {
        stats.add(k, d);
        bit(k)
    })
}

/// Removes the models of `gone` and re-attaches their points to the models
/// left (points in order, their distances added after the others').
fn reattach_removed(
    set: &mut Set,
    gone: u64,
    points: &[RowPoint],
    stats: &mut Stats,
    p: &RubyParams,
) {
    if gone == 0 {
        return;
    }
    for k in 0..MAX_MODELS {
        if gone & bit(k) != 0 {
            set.remove(k);
            stats.count[k] = 0;
            stats.energy[k] = 0.0;
        }
    }
    let slots = set.slots();
    for (i, pt) in points.iter().enumerate() {
        if set.masks[i] & gone == 0 {
            continue;
        }
        if p.variant.shared_points() {
            set.masks[i] &= !gone;
        } else {
            set.masks[i] = closest(set, &slots, pt, p.outlier_distance.get(), stats);
        }
    }
}

/// New models from random triples of outliers (RUBY-SEARCH, RUBY-SPLIT-SIDES).
fn search(set: &mut Set, points: &[RowPoint], rng: &mut Xoshiro128PlusPlus, p: &RubyParams) {
    if p.variant.split_sides() {
        let budget = p.models_per_iteration.div_ceil(2);
        search_side(set, points, rng, p, budget, |y| y > 0.0);
        search_side(set, points, rng, p, budget, |y| y < 0.0);
    } else {
        search_side(set, points, rng, p, p.models_per_iteration, |_| true);
    }
}

fn search_side(
    set: &mut Set,
    points: &[RowPoint],
    rng: &mut Xoshiro128PlusPlus,
    p: &RubyParams,
    budget: u16,
    side: impl Fn(f64) -> bool,
) {
    let alive = set.alive();
    let mut outliers: Vec<usize> = (0..points.len())
        .filter(|&i| set.masks[i] & alive == 0 && side(points[i].position.y()))
        .collect();
    let stop = p.search_until * outliers.len() as f64;
    let mut added = 0;
    while outliers.len() >= SEED_POINTS && outliers.len() as f64 > stop && added < budget {
        let Some(slot) = (0..MAX_MODELS).find(|&k| set.lines[k].is_none()) else {
            break;
        };
        let mut seed = [0; SEED_POINTS];
        for s in &mut seed {
            // Lemire's multiply-shift on 32 random bits.
            let r = u64::from(rng.next_u32());
            let at = ((r * outliers.len() as u64) >> 32) as usize;
            *s = outliers.swap_remove(at);
        }
        added += 1;
        let three = seed.map(|i| points[i].position);
        if let Some(line) = Line::fit(&three, 0) {
            set.lines[slot] = Some(line);
            for i in seed {
                set.masks[i] = bit(slot);
            }
            // The new model's line is fitted to its seeds.
            let mut fitted_to = seed.to_vec();
            fitted_to.sort_unstable();
            set.fitted_to[slot] = Some(fitted_to);
        }
    }
}

/// Merges the same models into the lower slot and refits (RUBY-MERGE): in
/// the first pass every model whose points are not those it was last
/// fitted to (a seed holds its seeds: it keeps its line).
fn merge(set: &mut Set, points: &[RowPoint], p: &RubyParams) {
    for pass in 0..=MAX_MODELS {
        let mut again = false;
        for j in 0..MAX_MODELS {
            let Some(lj) = set.lines[j] else { continue };
            let mut absorbed = 0;
            for k in j + 1..MAX_MODELS {
                if set.lines[k].is_some_and(|lk| lj.same(&lk, p)) {
                    absorbed |= bit(k);
                }
            }
            if absorbed != 0 {
                again = true;
                for m in &mut set.masks {
                    if *m & absorbed != 0 {
                        *m = (*m & !absorbed) | bit(j);
                    }
                }
                for k in 0..MAX_MODELS {
                    if absorbed & bit(k) != 0 {
                        set.remove(k);
                    }
                }
            }
            let members = set.members(j);
            let stale = set.fitted_to[j].as_ref() != Some(&members);
            if absorbed != 0 || (pass == 0 && stale) {
                let positions: Vec<Point2<Robot>> =
                    members.iter().map(|&i| points[i].position).collect();
                if let Some(line) = Line::fit(&positions, p.fit_rounds) {
                    again |= line != lj;
                    set.lines[j] = Some(line);
                }
                // A model its points give no line keeps the one it has.
                set.fitted_to[j] = Some(members);
            }
        }
        if !again {
            break;
        }
    }
}

/// The models to delete: eq. 7 for Ruby, the fitness ranking of eq. 10 for
/// the genetic variants (RUBY-DELETE, RUBY-FITNESS).
fn delete(set: &Set, stats: &Stats, p: &RubyParams) -> u64 {
    let slots = set.slots();
    let score = |k: usize| -> Option<f64> {
        let n = stats.count[k] as f64;
        let e = stats.energy[k];
        let line = set.lines[k].unwrap();
        let psi = slots
            .iter()
            .filter(|&&q| (set.lines[q].unwrap().a - line.a).abs() < p.parallel_slope)
            .count() as f64;
        (n > 0.0).then(|| {
            if p.variant.genetic() {
                (line.b * line.b + p.fitness_weight * e) / (n * n * psi)
            } else {
                e / (psi * n)
            }
        })
    };
    let mut gone = 0;
    if p.variant.genetic() {
        let mut ranked = Vec::new();
        for &k in &slots {
            match score(k) {
                Some(phi) if phi.is_finite() => ranked.push((phi, k)),
                _ => gone |= bit(k),
            }
        }
        ranked.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let keep = ((p.kept_share * ranked.len() as f64).ceil() as usize)
            .min(ranked.len())
            .max(usize::from(p.min_kept));
        for &(_, k) in ranked.iter().skip(keep) {
            gone |= bit(k);
        }
    } else {
        for &k in &slots {
            match score(k) {
                Some(s) if s - p.alpha < 0.0 => {}
                _ => gone |= bit(k),
            }
        }
    }
    gone
}

/// E(L) of eq. 1 (RUBY-ENERGY).
fn energy(set: &Set, stats: &Stats, weights: &[f64], p: &RubyParams) -> f64 {
    let alive = set.alive();
    let outliers = set.masks.iter().filter(|&&m| m & alive == 0).count();
    let mut neighbour = 0.0;
    for (w, pair) in weights.iter().zip(set.masks.windows(2)) {
        if pair[0] & alive != pair[1] & alive {
            neighbour += w;
        }
    }
    let models: f64 = set.slots().into_iter().map(|k| stats.energy[k]).sum();
    p.outlier_energy * outliers as f64 + p.neighbour_penalty * neighbour + models
}
