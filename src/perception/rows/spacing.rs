//! Row-distance initialisation (Guyonneau 2022, section 3.1, eqs. 13-14;
//! `spec/guyonneau2022.md` ROWS-SPACING-PAIR, ROWS-SPACING-DISTANCE,
//! ROWS-SPACING-AVERAGE, ROWS-SPACING-PARAMS).
//!
//! Before the robot moves, each scan's lines give the closest pair of rows
//! either side of the robot ([`closest_pair`]) and its row distance
//! ([`row_distance`]); [`SpacingEstimator`] averages the first N of them and
//! places the filter's first n rows around the pair.
//!
//! Frame: the robot frame, x forward, y left (ROWS-FRAME); a line
//! `y = a x + b` with b > 0 is left of the robot.

use heapless::Vec;

use super::count_f64;
use super::filter::MAX_ROWS;
use crate::error::{finite, Precondition};
use crate::geometry::units::Meters;
use crate::perception::furrow::lines::RowLine;
use crate::perception::furrow::selection::Pair;

/// Largest |slope| of a line of the pair, dimensionless (authors' implementation).
pub const DEFAULT_MAX_SLOPE: f64 = 0.05;
/// Tolerance ε of equidistance, a fraction of the gap |b_1| + |b_2| (library choice).
pub const DEFAULT_EQUIDISTANCE: f64 = 0.25;
/// Number N of scans averaged (authors' implementation).
pub const DEFAULT_ESTIMATES: usize = 10;
/// Number n of filtered rows (authors' implementation).
pub const DEFAULT_ROWS: usize = 4;
/// Default range of row distances a pair may show, m (ROWS-SPACING-RANGE).
pub const DEFAULT_DISTANCE_RANGE: (f64, f64) = (0.3, 2.0);

/// The parameters of the initialisation: a_max, ε, N and n (ROWS-SPACING-PARAMS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpacingConfig {
    max_slope: f64,
    equidistance: f64,
    estimates: usize,
    rows: usize,
    distance_range: (f64, f64),
}

impl SpacingConfig {
    /// Pairs of lines with |a| < `max_slope` whose |b| differ by at most
    /// `equidistance` times the gap, averaged over `estimates` scans, giving
    /// `rows` initial rows.
    ///
    /// Errors with `ROWS-SPACING-PARAMS` unless `max_slope` and
    /// `equidistance` are finite and strictly positive, `estimates ≥ 1` and
    /// `2 ≤ rows ≤ MAX_ROWS`.
    //= spec/guyonneau2022.md#rows-spacing-params-initialisation-parameters
    //# A configuration MUST be refused with an error naming ROWS-SPACING-PARAMS
    //# unless a_max and ε are finite and strictly positive, N ≥ 1 and
    //# 2 ≤ n ≤ MAX_ROWS.
    pub fn new(
        max_slope: f64,
        equidistance: f64,
        estimates: usize,
        rows: usize,
    ) -> Result<Self, Precondition> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(max_slope) || !positive(equidistance) {
            Err(Precondition::new(
                "ROWS-SPACING-PARAMS",
                "a_max and ε must be finite and strictly positive",
            ))
        } else if estimates == 0 {
            Err(Precondition::new(
                "ROWS-SPACING-PARAMS",
                "at least one estimate must be averaged",
            ))
        } else if !(2..=MAX_ROWS).contains(&rows) {
            Err(Precondition::new(
                "ROWS-SPACING-PARAMS",
                "the number of rows must be in 2..=MAX_ROWS",
            ))
        } else {
            Ok(Self {
                max_slope,
                equidistance,
                estimates,
                rows,
                distance_range: DEFAULT_DISTANCE_RANGE,
            })
        }
    }

    /// The same with pairs counted only when their d lies in `[min, max]` m.
    ///
    /// Errors with `ROWS-SPACING-RANGE` unless `0 < min < max` are finite.
    //= spec/guyonneau2022.md#rows-spacing-range-plausible-row-distances
    //# A range of row distances MUST be refused with an error naming
    //# ROWS-SPACING-RANGE unless 0 < d_min < d_max are finite.
    pub fn with_distance_range(mut self, min: Meters, max: Meters) -> Result<Self, Precondition> {
        let (min, max) = (min.get(), max.get());
        if !(min > 0.0 && min < max && max.is_finite()) {
            return Err(Precondition::new(
                "ROWS-SPACING-RANGE",
                "the row distances must satisfy 0 < d_min < d_max, finite",
            ));
        }
        self.distance_range = (min, max);
        Ok(self)
    }

    /// [d_min, d_max], m.
    #[must_use]
    pub const fn distance_range(&self) -> (f64, f64) {
        self.distance_range
    }

    /// a_max, dimensionless.
    #[must_use]
    pub const fn max_slope(&self) -> f64 {
        self.max_slope
    }

    /// ε, a fraction of the gap between the pair.
    #[must_use]
    pub const fn equidistance(&self) -> f64 {
        self.equidistance
    }

    /// N, the number of scans averaged.
    #[must_use]
    pub const fn estimates(&self) -> usize {
        self.estimates
    }

    /// n, the number of initial rows.
    #[must_use]
    pub const fn rows(&self) -> usize {
        self.rows
    }
}

impl Default for SpacingConfig {
    /// a_max = 0.05, ε = 0.25, N = 10, n = 4.
    fn default() -> Self {
        Self {
            max_slope: DEFAULT_MAX_SLOPE,
            equidistance: DEFAULT_EQUIDISTANCE,
            estimates: DEFAULT_ESTIMATES,
            rows: DEFAULT_ROWS,
            distance_range: DEFAULT_DISTANCE_RANGE,
        }
    }
}

/// The closest pair of `lines` either side of the robot, equidistant from it
/// and nearly parallel to it, `left` with b > 0 and `right` with b < 0;
/// `None` when there is none.
///
/// The equidistance test is `| |b_1| − |b_2| | ≤ ε (|b_1| + |b_2|)`: the robot
/// stands within ε/2 of the gap from the middle.
//= spec/guyonneau2022.md#rows-spacing-pair-the-closest-equidistant-pair-either-side-of-the-robot
//# A pair MUST be two lines L_1 with b_1 > 0 and L_2 with b_2 < 0, both with
//# |a| < a_max, equidistant from the robot: | |b_1| − |b_2| | ≤ ε (|b_1| + |b_2|).
//= spec/guyonneau2022.md#rows-spacing-pair-the-closest-equidistant-pair-either-side-of-the-robot
//# Among the pairs, the one found MUST be the one with the smallest
//# |b_1| + |b_2|, ties going to the first in the order of the lines.
#[must_use]
pub fn closest_pair(lines: &[RowLine], config: &SpacingConfig) -> Option<Pair<RowLine>> {
    let flat = |l: &&RowLine| libm::fabs(l.slope()) < config.max_slope;
    let mut best: Option<(f64, Pair<RowLine>)> = None;
    for left in lines
        .iter()
        .filter(flat)
        .filter(|l| l.intercept().get() > 0.0)
    {
        for right in lines
            .iter()
            .filter(flat)
            .filter(|l| l.intercept().get() < 0.0)
        {
            let (b1, b2) = (left.intercept().get(), -right.intercept().get());
            let gap = b1 + b2;
            let equidistant = libm::fabs(b1 - b2) <= config.equidistance * gap;
            let pair = Pair {
                left: *left,
                right: *right,
            };
            //= spec/guyonneau2022.md#rows-spacing-range-plausible-row-distances
            //# A pair whose d lies outside [d_min, d_max] MUST NOT be a candidate: a
            //# pair farther out whose d lies inside may be the one found.
            let (min, max) = config.distance_range;
            let plausible = row_distance(&pair).is_ok_and(|d| (min..=max).contains(&d.get()));
            if equidistant && plausible && best.is_none_or(|(g, _)| gap < g) {
                best = Some((gap, pair));
            }
        }
    }
    best.map(|(_, pair)| pair)
}

/// The row distance of a pair (eq. 14), `|b_1 − b_2| / sqrt(ā² + 1)` with ā
/// the mean of the two slopes, m along the rows' normal. Errors with
/// `LIB-FINITE` when it overflows.
//= spec/guyonneau2022.md#rows-spacing-distance-the-row-distance-of-one-pair-eq-14
//# The row distance of a pair MUST be d = |b_1 − b_2| / sqrt(ā² + 1) with
//# ā = (a_1 + a_2)/2.
pub fn row_distance(pair: &Pair<RowLine>) -> Result<Meters, Precondition> {
    let a = mean_slope(pair);
    let gap = libm::fabs(pair.left.intercept().get() - pair.right.intercept().get());
    Meters::new(gap / libm::sqrt(a * a + 1.0))
}

/// The mean slope of a pair, without overflow.
fn mean_slope(pair: &Pair<RowLine>) -> f64 {
    0.5 * pair.left.slope() + 0.5 * pair.right.slope()
}

/// The mean row distance over the first N scans with a pair, before the
/// robot moves, and the filter's initial rows (ROWS-SPACING-AVERAGE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpacingEstimator {
    config: SpacingConfig,
    count: usize,
    counted: f64,
    sum_distance: f64,
    sum_middle: f64,
    sum_slope: f64,
}

impl SpacingEstimator {
    /// An estimator with no scan counted yet.
    #[must_use]
    pub const fn new(config: SpacingConfig) -> Self {
        Self {
            config,
            count: 0,
            counted: 0.0,
            sum_distance: 0.0,
            sum_middle: 0.0,
            sum_slope: 0.0,
        }
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &SpacingConfig {
        &self.config
    }

    /// Counts one scan's lines: the d of its closest pair, when it has one
    /// and N scans have not counted yet. Returns that d (m), or `None` when
    /// the scan did not count.
    //= spec/guyonneau2022.md#rows-spacing-average-the-mean-over-scans-and-the-initial-rows
    //# The row distance MUST be the mean of the d of the first N scans in which a
    //# pair was found; a scan without a pair, or whose pair would make a sum not
    //# finite, MUST NOT count.
    pub fn observe(&mut self, lines: &[RowLine]) -> Option<Meters> {
        if self.is_ready() {
            return None;
        }
        let pair = closest_pair(lines, &self.config)?;
        let d = row_distance(&pair).ok()?;

        let middle = 0.5 * pair.left.intercept().get() + 0.5 * pair.right.intercept().get();
        let sums = (
            self.sum_distance + d.get(),
            self.sum_middle + middle,
            self.sum_slope + mean_slope(&pair),
        );
        if !(sums.0.is_finite() && sums.1.is_finite() && sums.2.is_finite()) {
            return None;
        }
        (self.sum_distance, self.sum_middle, self.sum_slope) = sums;
        self.count = self.count.saturating_add(1);
        self.counted += 1.0;
        Some(d)
    }

    /// How many scans have counted, at most N.
    #[must_use]
    pub const fn count(&self) -> usize {
        self.count
    }

    /// Whether N scans have counted.
    #[must_use]
    pub const fn is_ready(&self) -> bool {
        self.count >= self.config.estimates
    }

    /// The mean of `sum` over the counted scans, once N have counted.
    fn mean(&self, sum: f64) -> Result<f64, Precondition> {
        //= spec/guyonneau2022.md#rows-spacing-average-the-mean-over-scans-and-the-initial-rows
        //# Before N scans have given a pair, the row distance and the initial rows MUST
        //# be refused with an error naming ROWS-SPACING-AVERAGE.
        if !self.is_ready() {
            return Err(Precondition::new(
                "ROWS-SPACING-AVERAGE",
                "fewer than N scans have given a pair",
            ));
        }
        finite(sum / self.counted, "mean over the scans overflows")
    }

    /// The row distance d, m: the mean over the N scans. Errors with
    /// `ROWS-SPACING-AVERAGE` before N scans have counted.
    pub fn distance(&self) -> Result<Meters, Precondition> {
        Meters::new(self.mean(self.sum_distance)?)
    }

    /// The filter's initial rows, left to right: n lines of the pairs' mean
    /// slope ā, spaced d along their normal, symmetric about the pairs' mean
    /// middle line, the pair being rows ⌊n/2⌋ and ⌊n/2⌋ + 1 (1-based).
    ///
    /// Errors with `ROWS-SPACING-AVERAGE` before N scans have counted and
    /// with `LIB-FINITE` when a row overflows.
    //= spec/guyonneau2022.md#rows-spacing-average-the-mean-over-scans-and-the-initial-rows
    //# The initial rows MUST be n lines of slope ā, the mean of the pairs' mean
    //# slopes, with intercepts b^i = b_m + d (k + 1/2 − i) sqrt(ā² + 1) for
    //# i = 1, …, n, where k = ⌊n/2⌋ and b_m is the mean of the pairs' middle
    //# intercepts (b_1 + b_2)/2.
    pub fn initial_rows(&self) -> Result<Vec<RowLine, MAX_ROWS>, Precondition> {
        let d = self.distance()?.get();
        let middle = self.mean(self.sum_middle)?;
        let a = self.mean(self.sum_slope)?;
        let step = d * libm::sqrt(a * a + 1.0);
        let k = count_f64(self.config.rows.checked_div(2).unwrap_or(0)) + 0.5;
        let mut rows = Vec::new();
        for i in 1..=self.config.rows {
            let b = Meters::new(middle + step * (k - count_f64(i)))?;
            rows.push(RowLine::new(a, b)?)
                .map_err(|_| Precondition::new("ROWS-SPACING-PARAMS", "n > MAX_ROWS"))?;
        }
        Ok(rows)
    }
}
