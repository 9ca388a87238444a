//! The row filter (Guyonneau 2022, section 3.2, Algorithm 4 and eqs. 15-17
//! as corrected in the errata; `spec/guyonneau2022.md` ROWS-FILTER-PARAMS,
//! ROWS-FILTER-MATCH, ROWS-FILTER-MISSING, ROWS-FILTER-LOST,
//! ROWS-FILTER-BOUND), the rows detector's verdict (ROWS-VERDICT) and the
//! error to the middle of the rows either side of the robot (ROWS-ERROR).
//!
//! [`RowFilter`] keeps n rows from scan to scan: each scan the line finder's
//! lines are matched to the previous rows, the rows without a match are
//! computed from the best match and the row distance d, and when nothing
//! matches for K scans the filter is lost. [`Outcome::verdict`] turns a
//! scan's outcome into the switching machine's verdict; [`tracking_error`]
//! gives the error to the middle of the two rows around the robot.
//!
//! Frame: the robot frame, x forward, y left; rows are indexed left to right
//! (ROWS-FRAME), index 0 here being the paper's i = 1, so intercepts
//! decrease with the index. Slopes are dimensionless, intercepts and d in m.

use heapless::Vec;

use super::count_f64;
use crate::error::Precondition;
use crate::geometry::frame::{Pose2, Robot};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::Meters;
use crate::perception::furrow::lines::{mean_tracking_error, RowLine};
use crate::perception::furrow::selection::Pair;
use crate::perception::Verdict;

/// The most rows a filter holds: its fixed capacity (LIB-NO-ALLOC).
pub const MAX_ROWS: usize = 8;
/// The most tolerance steps s of a configuration (ROWS-FILTER-BOUND).
pub const MAX_TOLERANCE_STEPS: usize = 16;
/// δ_min, the first tolerance on the slope (authors' implementation).
pub const DEFAULT_DELTA_MIN: f64 = 0.05;
/// δ_max, the last tolerance on the slope (authors' implementation).
pub const DEFAULT_DELTA_MAX: f64 = 0.3;
/// s, the number of tolerances from δ_min to δ_max: steps of 0.05.
pub const DEFAULT_TOLERANCE_STEPS: usize = 6;
/// The intercept gate is this factor times δ, in m (authors' implementation).
pub const INTERCEPT_GATE: f64 = 1.2;
/// K, the scans without a match before the filter is lost: 0.5 s at 40 Hz.
pub const DEFAULT_LOST_AFTER: u32 = 20;
/// A found row agrees with the reference row when their slopes differ by
/// less than this (ROWS-FILTER-CONSENSUS).
pub const CONSENSUS_SLOPE: f64 = 0.05;
/// ... and its intercept is within this share of d of where the reference
/// and d put it (ROWS-FILTER-CONSENSUS).
pub const CONSENSUS_SHARE: f64 = 0.2;

/// The parameters of the filter: δ_min, δ_max, s and K (ROWS-FILTER-PARAMS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterConfig {
    delta_min: f64,
    delta_max: f64,
    steps: usize,
    lost_after: u32,
}

impl FilterConfig {
    /// Tolerances from `delta_min` to `delta_max` in `steps` equal steps, and
    /// lost after `lost_after` scans without a match.
    ///
    /// Errors with `ROWS-FILTER-PARAMS` unless `0 < delta_min ≤ delta_max`
    /// are finite, `1 ≤ steps ≤ MAX_TOLERANCE_STEPS` and `lost_after ≥ 1`.
    //= spec/guyonneau2022.md#rows-filter-params-filter-parameters
    //# A filter MUST be refused with an error naming ROWS-FILTER-PARAMS unless
    //# d > 0, 2 ≤ n ≤ MAX_ROWS, 0 < δ_min ≤ δ_max are finite, 1 ≤ s ≤ 16 and
    //# K ≥ 1.
    pub fn new(
        delta_min: f64,
        delta_max: f64,
        steps: usize,
        lost_after: u32,
    ) -> Result<Self, Precondition> {
        if !(delta_min.is_finite() && delta_max.is_finite() && 0.0 < delta_min)
            || delta_min > delta_max
        {
            Err(Precondition::new(
                "ROWS-FILTER-PARAMS",
                "tolerances must satisfy 0 < δ_min ≤ δ_max, finite",
            ))
        } else if !(1..=MAX_TOLERANCE_STEPS).contains(&steps) {
            Err(Precondition::new(
                "ROWS-FILTER-PARAMS",
                "tolerance steps must be in 1..=MAX_TOLERANCE_STEPS",
            ))
        } else if lost_after == 0 {
            Err(Precondition::new(
                "ROWS-FILTER-PARAMS",
                "lost after at least one scan",
            ))
        } else {
            Ok(Self {
                delta_min,
                delta_max,
                steps,
                lost_after,
            })
        }
    }

    /// δ_min, dimensionless.
    #[must_use]
    pub const fn delta_min(&self) -> f64 {
        self.delta_min
    }

    /// δ_max, dimensionless.
    #[must_use]
    pub const fn delta_max(&self) -> f64 {
        self.delta_max
    }

    /// s, the number of tolerances tried.
    #[must_use]
    pub const fn steps(&self) -> usize {
        self.steps
    }

    /// K, scans without a match before the filter is lost.
    #[must_use]
    pub const fn lost_after(&self) -> u32 {
        self.lost_after
    }

    /// δ_k = δ_min + (δ_max − δ_min) k/(s − 1); δ_max itself for the last k
    /// (and beyond), δ_min when s = 1.
    #[must_use]
    pub fn tolerance(&self, k: usize) -> f64 {
        let last = self.steps.saturating_sub(1);
        if last == 0 || k == 0 {
            self.delta_min
        } else if k >= last {
            self.delta_max
        } else {
            // The share first: span × k could overflow when δ_max is huge.
            let span = self.delta_max - self.delta_min;
            self.delta_min + span * (count_f64(k) / count_f64(last))
        }
    }
}

impl Default for FilterConfig {
    /// δ from 0.05 to 0.3 in 6 steps, lost after 20 scans.
    fn default() -> Self {
        Self {
            delta_min: DEFAULT_DELTA_MIN,
            delta_max: DEFAULT_DELTA_MAX,
            steps: DEFAULT_TOLERANCE_STEPS,
            lost_after: DEFAULT_LOST_AFTER,
        }
    }
}

/// D, the distance of `line` to a previous row, when it passes the gates at
/// tolerance `delta`.
//= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
//# A line L_j MUST match row i at tolerance δ when |a_j − a^{i,−1}| < δ and
//# |b_j − b^{i,−1}| < 1.2 δ.
fn gate(line: &RowLine, previous: &RowLine, delta: f64) -> Option<f64> {
    let da = libm::fabs(line.slope() - previous.slope());
    let db = libm::fabs(line.intercept().get() - previous.intercept().get());
    (da < delta && db < INTERCEPT_GATE * delta).then_some(da + db / INTERCEPT_GATE)
}

/// The lines matched to the rows at one tolerance.
struct Assignment {
    /// For each row, the index of its line.
    lines: [Option<usize>; MAX_ROWS],
    /// The first row assigned, with the smallest D: i_best.
    best: Option<usize>,
    /// The rows in the order they were matched (increasing D).
    order: Vec<usize, MAX_ROWS>,
}

impl Assignment {
    /// The line matched to row `i`.
    fn line<'l>(&self, i: usize, lines: &'l [RowLine]) -> Option<&'l RowLine> {
        self.lines
            .get(i)
            .copied()
            .flatten()
            .and_then(|j| lines.get(j))
    }
}

/// The lines matched to `rows` at tolerance `delta`, in increasing D; ties
/// to the lower row index, then the first line.
//= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
//# Matches MUST be assigned in increasing distance
//# D = |a_j − a^{i,−1}| + |b_j − b^{i,−1}| / 1.2, each row taking at most one
//# line and each line at most one row; a found row MUST be its line.
//= spec/guyonneau2022.md#rows-filter-bound-bounded-work-per-scan
//# One update MUST evaluate at most s n² m gates for m lines, and compute at
//# most n rows.
fn assign(rows: &[RowLine], lines: &[RowLine], delta: f64) -> Assignment {
    // Every pair through the gates once, (D, row, line), in increasing D,
    // ties to the lower row, then the first line: the greedy walk of the
    // list takes, at each match, the least D among the pairs left free, as
    // a pass over every free pair per match finds it (below, when more
    // pairs pass than the list holds).
    let mut pairs: Vec<(f64, usize, usize), GATED_PAIRS> = Vec::new();
    for (i, previous) in rows.iter().enumerate().take(MAX_ROWS) {
        for (j, line) in lines.iter().enumerate() {
            if let Some(d) = gate(line, previous, delta) {
                if pairs.push((d, i, j)).is_err() {
                    return assign_by_passes(rows, lines, delta);
                }
            }
        }
    }
    pairs.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut assignment = Assignment {
        lines: [None; MAX_ROWS],
        best: None,
        order: Vec::new(),
    };
    let mut taken = 0_u64;
    for &(_, i, j) in &pairs {
        let line_taken = is_taken(taken, &assignment, j);
        let Some(slot) = assignment.lines.get_mut(i) else {
            continue;
        };
        if slot.is_some() || line_taken {
            continue;
        }
        *slot = Some(j);
        taken |= line_bit(j);
        assignment.best.get_or_insert(i);
        let _ = assignment.order.push(i);
    }
    assignment
}

/// Line `j`'s bit in a set of taken lines; 0 beyond the 64th line, whose
/// use is looked up in the assignment instead ([`is_taken`]).
fn line_bit(j: usize) -> u64 {
    u32::try_from(j)
        .ok()
        .and_then(|j| 1_u64.checked_shl(j))
        .unwrap_or(0)
}

/// Whether line `j` is taken: its bit in `taken`, or beyond the 64th line,
/// whether a row of `assignment` has it.
fn is_taken(taken: u64, assignment: &Assignment, j: usize) -> bool {
    match u32::try_from(j).ok().and_then(|j| 1_u64.checked_shl(j)) {
        Some(b) => taken & b != 0,
        None => assignment.lines.contains(&Some(j)),
    }
}

/// Gated pairs [`assign`] lists at most.
const GATED_PAIRS: usize = 64;

/// [`assign`] by one pass over the n × m pairs per match.
fn assign_by_passes(rows: &[RowLine], lines: &[RowLine], delta: f64) -> Assignment {
    let mut assignment = Assignment {
        lines: [None; MAX_ROWS],
        best: None,
        order: Vec::new(),
    };
    // The lines taken, as bits (lines beyond 64 looked up in the rows').
    let mut taken = 0_u64;
    // At most n assignments, each one pass over the n × m pairs.
    for _ in rows {
        let mut best: Option<(f64, usize, usize)> = None;
        for (i, previous) in rows.iter().enumerate() {
            if assignment.lines.get(i).is_none_or(Option::is_some) {
                continue;
            }
            for (j, line) in lines.iter().enumerate() {
                if is_taken(taken, &assignment, j) {
                    continue;
                }
                if let Some(d) = gate(line, previous, delta) {
                    if best.is_none_or(|(bd, _, _)| d < bd) {
                        best = Some((d, i, j));
                    }
                }
            }
        }
        let Some((_, i, j)) = best else { break };
        if let Some(slot) = assignment.lines.get_mut(i) {
            *slot = Some(j);
            taken |= line_bit(j);
        }
        //= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
        //# The best match i_best MUST be the found row whose line has the smallest D to
        //# its previous row, unless ROWS-FILTER-CONSENSUS names another.
        assignment.best.get_or_insert(i);
        let _ = assignment.order.push(i);
    }
    assignment
}

/// What one scan did to the filter, from which the verdict follows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// For each row index, whether a line was found for it this scan.
    pub found: [bool; MAX_ROWS],
    /// The index of the best match i_best (0-based), when a row was found.
    pub best: Option<usize>,
    /// The tolerance δ at which the rows were found.
    pub tolerance: Option<f64>,
    /// The indices of the rows left and right of the robot (ROWS-ERROR).
    pub sides: Option<Pair<usize>>,
    /// Consecutive scans without any match, this one included.
    pub misses: u32,
    /// Whether the filter is lost (ROWS-FILTER-LOST).
    pub lost: bool,
}

impl Outcome {
    /// How many rows were found this scan.
    #[must_use]
    pub fn matched(&self) -> usize {
        self.found.iter().filter(|&&f| f).count()
    }

    /// The verdict for the switching machine: Absent when lost or when no
    /// pair of rows is either side of the robot, Enter when both were
    /// found, Hold when another row was, Exit when none was.
    //= spec/guyonneau2022.md#rows-verdict-the-rows-detector-s-verdict
    //# The verdict MUST be Absent when the filter is lost or no pair of rows is
    //# either side of the robot, Enter when both rows either side were found this
    //# scan, Hold when at least one row was found, and Exit otherwise.
    #[must_use]
    pub fn verdict(&self) -> Verdict {
        let found = |i: usize| self.found.get(i).copied().unwrap_or(false);
        match self.sides {
            _ if self.lost => Verdict::Absent,
            None => Verdict::Absent,
            Some(p) if found(p.left) && found(p.right) => Verdict::Enter,
            Some(_) if self.matched() > 0 => Verdict::Hold,
            Some(_) => Verdict::Exit,
        }
    }
}

/// The n filtered rows of the previous scan, the row distance d and the
/// count of scans without a match (Algorithm 4).
#[derive(Debug, Clone, PartialEq)]
pub struct RowFilter {
    rows: Vec<RowLine, MAX_ROWS>,
    distance: Meters,
    config: FilterConfig,
    misses: u32,
    lost: bool,
}

impl RowFilter {
    /// A filter starting from `rows` (left to right, as
    /// [`super::spacing::SpacingEstimator::initial_rows`] gives them), rows
    /// `distance` m apart along their normal.
    ///
    /// Errors with `ROWS-FILTER-PARAMS` unless `distance > 0` and
    /// `2 ≤ rows.len() ≤ MAX_ROWS`.
    //= spec/guyonneau2022.md#rows-filter-params-filter-parameters
    //# A filter MUST be refused with an error naming ROWS-FILTER-PARAMS unless
    //# d > 0, 2 ≤ n ≤ MAX_ROWS, 0 < δ_min ≤ δ_max are finite, 1 ≤ s ≤ 16 and
    //# K ≥ 1.
    pub fn new(
        distance: Meters,
        rows: &[RowLine],
        config: FilterConfig,
    ) -> Result<Self, Precondition> {
        let count = Precondition::new(
            "ROWS-FILTER-PARAMS",
            "the number of rows must be in 2..=MAX_ROWS",
        );
        if distance.get() <= 0.0 {
            return Err(Precondition::new(
                "ROWS-FILTER-PARAMS",
                "the row distance must be strictly positive",
            ));
        }
        if rows.len() < 2 {
            return Err(count);
        }
        Ok(Self {
            rows: Vec::from_slice(rows).map_err(|_| count)?,
            distance,
            config,
            misses: 0,
            lost: false,
        })
    }

    /// The n rows, left to right (index 0 is the paper's i = 1).
    #[must_use]
    pub fn rows(&self) -> &[RowLine] {
        &self.rows
    }

    /// d, m.
    #[must_use]
    pub const fn distance(&self) -> Meters {
        self.distance
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &FilterConfig {
        &self.config
    }

    /// Consecutive scans without any match.
    #[must_use]
    pub const fn misses(&self) -> u32 {
        self.misses
    }

    /// Whether the filter is lost: K consecutive scans without any match.
    #[must_use]
    pub const fn is_lost(&self) -> bool {
        self.lost
    }

    /// Moves the rows into the frame of the robot at `motion` (its pose in
    /// the frame of the last scan); rows left as they are if one of them
    /// would be across the new robot frame (ROWS-MOTION).
    //= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
    //# Before a scan's lines are matched, the filter's rows MUST be carried by
    //# the odometry motion since the last scan; when a row would be across
    //# the new robot frame, the rows MUST be left as they were.
    pub fn move_by(&mut self, motion: &Pose2<Robot>) {
        let mut moved: Vec<RowLine, MAX_ROWS> = Vec::new();
        for row in &self.rows {
            match seen_from(row, motion) {
                Some(line) if moved.push(line).is_ok() => {}
                _ => return,
            }
        }
        self.rows = moved;
        self.recentre();
    }

    /// Re-indexes the rows by whole rows when the robot has crossed into
    /// another inter-row, so that it is again between rows ⌊n/2⌋ and
    /// ⌊n/2⌋ + 1 (1-based), as the initial rows place it (ROWS-RECENTRE).
    //= spec/guyonneau2022.md#rows-recentre-the-rows-follow-the-robot-across-the-crop
    //# When the rows either side of the robot are rows j and j + 1 (1-based)
    //# with j ≠ ⌊n/2⌋, the rows MUST be re-indexed by j − ⌊n/2⌋ whole rows: a
    //# row whose index stays within 1..n MUST keep its line, and a row that
    //# enters MUST be y = ā x + b^c + d (c − i) sqrt(ā² + 1) from the nearest
    //# kept row c, with ā the mean slope of the rows.
    fn recentre(&mut self) {
        let n = self.rows.len();
        let target = n.checked_div(2).and_then(|k| k.checked_sub(1));
        let (Some(sides), Some(target)) = (side_indices(&self.rows), target) else {
            return;
        };
        if sides.left == target {
            return;
        }
        let count = count_f64(n);
        let a = self
            .rows
            .iter()
            .fold(0.0, |sum, row| sum + row.slope() / count);
        let step = self.distance.get() * libm::sqrt(a * a + 1.0);
        let last = n.saturating_sub(1);
        let mut rows: Vec<RowLine, MAX_ROWS> = Vec::new();
        for i in 0..n {
            // The old index of new row i is i + left − target: kept when in
            // 0..n, else computed from the nearest kept row, `rows` beyond it
            // (positive past the last row, to the right).
            let shifted = i.saturating_add(sides.left);
            let (old, beyond) = match shifted.checked_sub(target) {
                Some(j) if j <= last => (j, None),
                Some(j) => (last, Some(count_f64(j.saturating_sub(last)))),
                None => (0, Some(-count_f64(target.saturating_sub(shifted)))),
            };
            let Some(kept) = self.rows.get(old) else {
                return;
            };
            let line = match beyond {
                None => Some(*kept),
                Some(rows) => Meters::new(kept.intercept().get() - step * rows)
                    .and_then(|b| RowLine::new(a, b))
                    .ok(),
            };
            match line {
                Some(line) if rows.push(line).is_ok() => {}
                // A row that would not be finite: the rows stay as they are.
                _ => return,
            }
        }
        self.rows = rows;
    }

    /// The rows left and right of the robot ([`side_rows`]).
    #[must_use]
    pub fn sides(&self) -> Option<Pair<RowLine>> {
        side_rows(&self.rows)
    }

    /// One scan of Algorithm 4 on the line finder's `lines`: the rows
    /// matched at the first tolerance where any matches, the others computed
    /// by eq. 15; the previous rows kept when nothing matches.
    //= spec/guyonneau2022.md#rows-filter-bound-bounded-work-per-scan
    //# One update MUST evaluate at most s n² m gates for m lines, and compute at
    //# most n rows.
    pub fn update(&mut self, lines: &[RowLine]) -> Outcome {
        if !self.lost {
            if let Some((assignment, delta)) = self.first_match(lines) {
                if let Some(rows) = self.rebuild(lines, &assignment) {
                    self.rows = rows;
                    self.misses = 0;
                    let mut found = [false; MAX_ROWS];
                    for (i, f) in found.iter_mut().enumerate() {
                        *f = assignment.line(i, lines).is_some();
                    }
                    return self.outcome(found, assignment.best, Some(delta));
                }
            }
            //= spec/guyonneau2022.md#rows-filter-lost-no-match-and-lost
            //# When no line matches any row, the filter MUST keep the previous rows.
            self.misses = self.misses.saturating_add(1);
            //= spec/guyonneau2022.md#rows-filter-lost-no-match-and-lost
            //# After K consecutive scans without any match the filter MUST be lost, and a
            //# lost filter MUST keep its rows and stay lost.
            self.lost = self.misses >= self.config.lost_after;
        }
        self.outcome([false; MAX_ROWS], None, None)
    }

    /// The assignment at the tolerance where the most found rows agree (the
    /// smallest such tolerance), and that tolerance.
    //= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
    //# The tolerance MUST be, among δ_k = δ_min + (δ_max − δ_min) k/(s − 1),
    //# k = 0, …, s − 1 (δ_min alone when s = 1), the smallest at which the most
    //# found rows agree (ROWS-FILTER-CONSENSUS), when any line matches a row.
    fn first_match(&self, lines: &[RowLine]) -> Option<(Assignment, f64)> {
        let mut best: Option<(Assignment, f64, usize)> = None;
        for k in 0..self.config.steps {
            let delta = self.config.tolerance(k);
            let mut assignment = assign(&self.rows, lines, delta);
            let agreeing = self.consensus(&mut assignment, lines);
            //= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
            //# Beyond the first tolerance, a match MUST count only when at least two
            //# found rows agree.
            let counts = assignment.best.is_some() && (k == 0 || agreeing >= 2);
            if counts && best.as_ref().is_none_or(|(_, _, most)| agreeing > *most) {
                best = Some((assignment, delta, agreeing));
            }
        }
        best.map(|(assignment, delta, _)| (assignment, delta))
    }

    /// Keeps only the found rows that agree with the reference row (the
    /// found row most others agree with) on the crop's geometry, and makes
    /// that row i_best; returns how many agree (the reference included).
    //= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
    //# A found row i MUST be dropped (and computed instead) unless its slope
    //# differs from the reference row r's by less than 0.05 and its intercept
    //# lies within 0.2 d of b^r + d (r − i) sqrt(a^r² + 1); the reference MUST
    //# be the found row with which the most found rows agree, ties going to the
    //# earlier match, and it MUST be i_best.
    fn consensus(&self, assignment: &mut Assignment, lines: &[RowLine]) -> usize {
        let d = self.distance.get();
        let agree = |r: usize, i: usize| -> bool {
            match (assignment.line(r, lines), assignment.line(i, lines)) {
                (Some(reference), Some(row)) => {
                    let a = reference.slope();
                    let offset = count_f64(r) - count_f64(i);
                    let expected =
                        reference.intercept().get() + d * offset * libm::sqrt(a * a + 1.0);
                    libm::fabs(row.slope() - a) < CONSENSUS_SLOPE
                        && libm::fabs(row.intercept().get() - expected) <= CONSENSUS_SHARE * d
                }
                _ => false,
            }
        };
        let n = self.rows.len();
        // The candidates in match order: i_best first, then by row index.
        // The candidates in match order, i_best first.
        let order = assignment.order.clone();
        let mut reference: Option<(usize, usize)> = None;
        for r in order {
            let votes = (0..n).filter(|&i| agree(r, i)).count();
            if votes > 0 && reference.is_none_or(|(_, v)| votes > v) {
                reference = Some((r, votes));
            }
        }
        let Some((r, votes)) = reference else {
            return 0;
        };
        let keep: [bool; MAX_ROWS] = core::array::from_fn(|i| agree(r, i));
        for (slot, kept) in assignment.lines.iter_mut().zip(keep) {
            if !kept {
                *slot = None;
            }
        }
        assignment.best = Some(r);
        votes
    }

    /// The new rows: the found ones, and the others by eq. 15; `None` when a
    /// computed row is not finite.
    //= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
    //# A row without a match MUST be L^i: y = ā x + b^{i_best} + d (i_best − i)
    //# sqrt(ā² + 1), with ā the mean slope of the rows found this scan.
    //= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
    //# A scan whose computed rows would not be finite MUST count as a scan without
    //# any match.
    fn rebuild(
        &self,
        lines: &[RowLine],
        assignment: &Assignment,
    ) -> Option<Vec<RowLine, MAX_ROWS>> {
        let best = assignment.best?;
        let b_best = assignment.line(best, lines)?.intercept().get();
        let found = || (0..self.rows.len()).filter_map(|i| assignment.line(i, lines));
        let count = count_f64(found().count());
        // Each slope divided first: the mean of finite slopes cannot overflow.
        let a = found().fold(0.0, |sum, line| sum + line.slope() / count);
        let step = self.distance.get() * libm::sqrt(a * a + 1.0);
        let mut rows = Vec::new();
        for i in 0..self.rows.len() {
            let line = match assignment.line(i, lines) {
                Some(line) => *line,
                None => {
                    let offset = count_f64(best) - count_f64(i);
                    RowLine::new(a, Meters::new(b_best + step * offset).ok()?).ok()?
                }
            };
            rows.push(line).ok()?;
        }
        Some(rows)
    }

    /// The outcome of a scan that found `found`, with the current rows.
    fn outcome(
        &self,
        found: [bool; MAX_ROWS],
        best: Option<usize>,
        tolerance: Option<f64>,
    ) -> Outcome {
        Outcome {
            found,
            best,
            tolerance,
            sides: side_indices(&self.rows),
            misses: self.misses,
            lost: self.lost,
        }
    }
}

/// The line `line` of one robot frame as seen from the robot at `pose` of
/// that frame: with n = (−a, 1) and c = b, the line n·p = c becomes
/// (Rᵀn)·p′ = c − n·t; `None` when it would be parallel to the new y axis
/// (no y = a x + b form) or not finite.
//= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
//# A line y = a x + b of the last scan's robot frame MUST be carried to the
//# frame of the robot at pose (t, ψ) of that frame as the line of the same
//# points: n′ = Rᵀ(ψ) n and c′ = c − n·t, with n = (−a, 1) and c = b.
#[must_use]
pub fn seen_from(line: &RowLine, pose: &Pose2<Robot>) -> Option<RowLine> {
    let (nx, ny, c) = (-line.slope(), 1.0, line.intercept().get());
    let (sin, cos) = libm::sincos(pose.heading.get());
    let (tx, ty) = (pose.position.x(), pose.position.y());
    let (mx, my) = (cos * nx + sin * ny, -sin * nx + cos * ny);
    let c2 = c - (nx * tx + ny * ty);
    if libm::fabs(my) < 1e-9 {
        return None;
    }
    let b = Meters::new(c2 / my).ok()?;
    RowLine::new(-mx / my, b).ok()
}

/// The indices of the rows left and right of the robot: the smallest
/// positive intercept and the largest negative one, when they are
/// consecutive (ties to the lower index). `None` when the robot is outside
/// all rows, or a row passes under it (b = 0).
//= spec/guyonneau2022.md#rows-error-the-rows-either-side-and-the-error-to-their-middle
//# The row left of the robot MUST be the row with the smallest positive
//# intercept and the row right of it the row with the largest negative
//# intercept, and they MUST form a pair only when the right row's index is the
//# left row's plus one.
//= spec/guyonneau2022.md#rows-frame-the-paper-s-left-and-right-in-the-library-s-frame
//# The library MUST read every "left" and "right" of the paper in the robot
//# frame x forward, y left: a point or line with y > 0 (b > 0) is left of the
//# robot.
#[must_use]
pub fn side_indices(rows: &[RowLine]) -> Option<Pair<usize>> {
    let mut left: Option<(usize, f64)> = None;
    let mut right: Option<(usize, f64)> = None;
    for (i, row) in rows.iter().enumerate() {
        let b = row.intercept().get();
        if b > 0.0 && left.is_none_or(|(_, lb)| b < lb) {
            left = Some((i, b));
        }
        if b < 0.0 && right.is_none_or(|(_, rb)| b > rb) {
            right = Some((i, b));
        }
    }
    let (l, r) = (left?.0, right?.0);
    (l.checked_add(1) == Some(r)).then_some(Pair { left: l, right: r })
}

/// The rows left and right of the robot ([`side_indices`]).
#[must_use]
pub fn side_rows(rows: &[RowLine]) -> Option<Pair<RowLine>> {
    let sides = side_indices(rows)?;
    Some(Pair {
        left: *rows.get(sides.left)?,
        right: *rows.get(sides.right)?,
    })
}

/// The robot's tracking error to the middle of the rows either side of it:
/// the mean of the errors to the two rows (FUR-TWO-ROWS), y > 0 when the
/// robot is left of the middle line.
///
/// Errors with `ROWS-ERROR` when there is no such pair ([`side_indices`]).
//= spec/guyonneau2022.md#rows-error-the-rows-either-side-and-the-error-to-their-middle
//# The tracking error MUST be the mean of the errors to the left and the right
//# row (FUR-TWO-ROWS); without a pair it MUST be refused with an error naming
//# ROWS-ERROR.
pub fn tracking_error(rows: &[RowLine]) -> Result<TrackingError, Precondition> {
    let pair = side_rows(rows).ok_or(Precondition::new(
        "ROWS-ERROR",
        "no pair of rows either side of the robot",
    ))?;
    mean_tracking_error(&pair.left, &pair.right)
}

#[cfg(test)]
mod tests {
    //! The walk of the gated pairs against a pass over every free pair per
    //! match (ROWS-FILTER-MATCH), on lines of a coarse grid (ties of D).

    use super::*;
    use rand_core::{RngCore, SeedableRng};
    use rand_xoshiro::Xoshiro128PlusPlus;

    /// A line of slope k · 0.05 (|k| ≤ 2) and intercept k · 0.1 m (|k| ≤ 3).
    fn grid_line(rng: &mut Xoshiro128PlusPlus) -> Result<RowLine, Precondition> {
        let slope = f64::from(rng.next_u32() % 5) * 0.05 - 0.1;
        let intercept = f64::from(rng.next_u32() % 7) * 0.1 - 0.3;
        RowLine::new(slope, Meters::new(intercept)?)
    }

    //= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
    //= type=test
    //# Matches MUST be assigned in increasing distance
    //# D = |a_j − a^{i,−1}| + |b_j − b^{i,−1}| / 1.2, each row taking at most one
    //# line and each line at most one row; a found row MUST be its line.
    #[test]
    fn the_walk_of_the_gated_pairs_assigns_as_the_passes_do() -> Result<(), Precondition> {
        let mut rng = Xoshiro128PlusPlus::seed_from_u64(7);
        let mut walked = 0;
        for _ in 0..3000 {
            let mut rows: Vec<RowLine, MAX_ROWS> = Vec::new();
            let mut lines: Vec<RowLine, 16> = Vec::new();
            for _ in 0..rng.next_u32() % 9 {
                let _ = rows.push(grid_line(&mut rng)?);
            }
            for _ in 0..rng.next_u32() % 17 {
                let _ = lines.push(grid_line(&mut rng)?);
            }
            for delta in [0.05, 0.12, 0.3] {
                let (walk, passes) = (
                    assign(&rows, &lines, delta),
                    assign_by_passes(&rows, &lines, delta),
                );
                assert_eq!(walk.lines, passes.lines);
                assert_eq!(walk.best, passes.best);
                assert_eq!(walk.order, passes.order);
                walked += usize::from(rows.len() * lines.len() <= GATED_PAIRS);
            }
        }
        // Most cases fit the list, so the walk itself is compared.
        assert!(walked > 6000);
        Ok(())
    }
}
