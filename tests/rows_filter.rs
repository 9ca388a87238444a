//! Row-distance initialisation and the row filter of Guyonneau 2022,
//! sections 3.1-3.2 (ROWS-SPACING-*, ROWS-FILTER-*, ROWS-VERDICT,
//! ROWS-ERROR): hand-computed cases and properties.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use fieldguide::perception::furrow::lines::{mean_tracking_error, RowLine};
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::perception::rows::filter::{
    side_indices, side_rows, tracking_error, FilterConfig, Outcome, RowFilter, MAX_ROWS,
    MAX_TOLERANCE_STEPS,
};
use fieldguide::perception::rows::spacing::{
    closest_pair, row_distance, SpacingConfig, SpacingEstimator,
};
use fieldguide::{Meters, Verdict};
use proptest::prelude::*;

fn line(a: f64, b: f64) -> RowLine {
    RowLine::new(a, Meters::new(b).unwrap()).unwrap()
}

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn close(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs()))
}

/// Four rows of slope 0, 0.75 m apart, the robot in the middle of rows 2 and 3.
fn grid() -> Vec<RowLine> {
    [1.125, 0.375, -0.375, -1.125]
        .iter()
        .map(|&b| line(0.0, b))
        .collect()
}

fn filter(rows: &[RowLine], lost_after: u32) -> RowFilter {
    let config = FilterConfig::new(0.05, 0.3, 6, lost_after).unwrap();
    RowFilter::new(m(0.75), rows, config).unwrap()
}

fn intercepts(rows: &[RowLine]) -> Vec<f64> {
    rows.iter().map(|r| r.intercept().get()).collect()
}

//= spec/guyonneau2022.md#rows-spacing-distance-the-row-distance-of-one-pair-eq-14
//= type=test
//# The row distance of a pair MUST be d = |b_1 − b_2| / sqrt(ā² + 1) with
//# ā = (a_1 + a_2)/2.
#[test]
fn row_distance_by_hand() {
    let pair = Pair {
        left: line(0.03, 0.375),
        right: line(0.01, -0.375),
    };
    // ā = 0.02: d = 0.75 / sqrt(1.0004).
    let d = row_distance(&pair).unwrap().get();
    assert!(close(d, 0.75 / 1.0004_f64.sqrt()), "{d}");
    let parallel = Pair {
        left: line(0.0, 0.4),
        right: line(0.0, -0.35),
    };
    assert!(close(row_distance(&parallel).unwrap().get(), 0.75));
    let huge = Pair {
        left: line(0.0, f64::MAX),
        right: line(0.0, -f64::MAX),
    };
    assert_eq!(row_distance(&huge).unwrap_err().requirement, "LIB-FINITE");
}

//= spec/guyonneau2022.md#rows-spacing-pair-the-closest-equidistant-pair-either-side-of-the-robot
//= type=test
//# A pair MUST be two lines L_1 with b_1 > 0 and L_2 with b_2 < 0, both with
//# |a| < a_max, equidistant from the robot: | |b_1| − |b_2| | ≤ ε (|b_1| + |b_2|).
#[test]
fn pairs_refused_when_not_equidistant_or_too_steep() {
    let config = SpacingConfig::default();
    // |0.5 − 0.2| = 0.3 > 0.25 · 0.7: the robot is not in the middle.
    assert_eq!(
        closest_pair(&[line(0.0, 0.5), line(0.0, -0.2)], &config),
        None
    );
    // |0.45 − 0.3| = 0.15 ≤ 0.25 · 0.75 = 0.1875: accepted.
    let pair = closest_pair(&[line(0.0, -0.3), line(0.0, 0.45)], &config).unwrap();
    assert_eq!((pair.left, pair.right), (line(0.0, 0.45), line(0.0, -0.3)));
    // |a| < 0.05 strictly, on either line.
    for steep in [0.05, -0.05, 0.2] {
        assert_eq!(
            closest_pair(&[line(steep, 0.4), line(0.0, -0.4)], &config),
            None
        );
        assert_eq!(
            closest_pair(&[line(0.0, 0.4), line(steep, -0.4)], &config),
            None
        );
    }
    assert!(closest_pair(&[line(0.049, 0.4), line(-0.049, -0.4)], &config).is_some());
    // Both on one side, or a line under the robot: no pair.
    assert_eq!(
        closest_pair(&[line(0.0, 0.4), line(0.0, 0.3)], &config),
        None
    );
    assert_eq!(
        closest_pair(&[line(0.0, 0.0), line(0.0, -0.0)], &config),
        None
    );
    assert_eq!(closest_pair(&[], &config), None);
}

//= spec/guyonneau2022.md#rows-spacing-pair-the-closest-equidistant-pair-either-side-of-the-robot
//= type=test
//# Among the pairs, the one found MUST be the one with the smallest
//# |b_1| + |b_2|, ties going to the first in the order of the lines.
#[test]
fn the_closest_pair_is_found() {
    let config = SpacingConfig::default();
    let lines = [
        line(0.0, 1.1),
        line(0.2, 0.05),
        line(0.01, 0.4),
        line(0.0, -1.15),
        line(0.0, -0.38),
        line(0.0, -0.1),
    ];
    let pair = closest_pair(&lines, &config).unwrap();
    assert_eq!((pair.left, pair.right), (lines[2], lines[4]));
    // Two pairs with the same gap: the first left line wins, then the first right one.
    let tie = [line(0.0, 0.4), line(0.01, 0.4), line(0.0, -0.4)];
    assert_eq!(closest_pair(&tie, &config).unwrap().left, tie[0]);
    let tie = [line(0.0, 0.4), line(0.01, -0.4), line(0.02, -0.4)];
    assert_eq!(closest_pair(&tie, &config).unwrap().right, tie[1]);
}

//= spec/guyonneau2022.md#rows-spacing-average-the-mean-over-scans-and-the-initial-rows
//= type=test
//# The row distance MUST be the mean of the d of the first N scans in which a
//# pair was found; a scan without a pair, or whose pair would make a sum not
//# finite, MUST NOT count.
#[test]
fn the_distance_is_the_mean_of_ten_scans() {
    let mut estimator = SpacingEstimator::new(SpacingConfig::default());
    let mut expected = 0.0;
    for k in 0..10 {
        // A scan without a pair between two that count.
        assert_eq!(estimator.observe(&[line(0.0, 0.4)]), None);
        let half = 0.35 + 0.01 * f64::from(k);
        let d = estimator
            .observe(&[line(0.0, half), line(0.0, -half)])
            .unwrap();
        assert!(close(d.get(), 2.0 * half));
        expected += 2.0 * half / 10.0;
    }
    assert_eq!(estimator.count(), 10);
    assert!(close(estimator.distance().unwrap().get(), expected));
    // The eleventh scan changes nothing, though its d (1.8 m) would count.
    assert_eq!(estimator.observe(&[line(0.0, 0.9), line(0.0, -0.9)]), None);
    assert!(close(estimator.distance().unwrap().get(), expected));
    // A pair whose d overflows does not count: the range of plausible
    // distances widened to the largest f64, so that only the sums refuse.
    let wide = SpacingConfig::new(0.05, 0.25, 2, 4)
        .unwrap()
        .with_distance_range(m(1.0), m(f64::MAX))
        .unwrap();
    let mut estimator = SpacingEstimator::new(wide);
    let huge = [line(0.0, f64::MAX), line(0.0, -f64::MAX)];
    assert_eq!(estimator.observe(&huge), None);
    assert_eq!(estimator.count(), 0);
    let big = [line(0.0, 0.5e308), line(0.0, -0.5e308)];
    assert!(estimator.observe(&big).is_some());
    assert_eq!(estimator.observe(&big), None, "the sum would overflow");
    assert_eq!(estimator.count(), 1);
}

//= spec/guyonneau2022.md#rows-spacing-average-the-mean-over-scans-and-the-initial-rows
//= type=test
//# Before N scans have given a pair, the row distance and the initial rows MUST
//# be refused with an error naming ROWS-SPACING-AVERAGE.
#[test]
fn nothing_before_n_scans() {
    let mut estimator = SpacingEstimator::new(SpacingConfig::default());
    for _ in 0..9 {
        assert_eq!(
            estimator.distance().unwrap_err().requirement,
            "ROWS-SPACING-AVERAGE"
        );
        assert_eq!(
            estimator.initial_rows().unwrap_err().requirement,
            "ROWS-SPACING-AVERAGE"
        );
        estimator.observe(&[line(0.0, 0.4), line(0.0, -0.4)]);
        assert!(!estimator.is_ready());
    }
    estimator.observe(&[line(0.0, 0.4), line(0.0, -0.4)]);
    assert!(estimator.is_ready());
    assert!(close(estimator.distance().unwrap().get(), 0.8));
}

//= spec/guyonneau2022.md#rows-spacing-average-the-mean-over-scans-and-the-initial-rows
//= type=test
//# The initial rows MUST be n lines of slope ā, the mean of the pairs' mean
//# slopes, with intercepts b^i = b_m + d (k + 1/2 − i) sqrt(ā² + 1) for
//# i = 1, …, n, where k = ⌊n/2⌋ and b_m is the mean of the pairs' middle
//# intercepts (b_1 + b_2)/2.
#[test]
fn initial_rows_around_the_pair() {
    let mut estimator = SpacingEstimator::new(SpacingConfig::new(0.05, 0.25, 2, 4).unwrap());
    // Pairs: (0.02, 0.4) / (0.0, −0.36), then (0.04, 0.42) / (0.02, −0.38).
    estimator.observe(&[line(0.02, 0.4), line(0.0, -0.36)]);
    estimator.observe(&[line(0.04, 0.42), line(0.02, -0.38)]);
    let a: f64 = (0.01 + 0.03) / 2.0;
    let s = (a * a + 1.0).sqrt();
    let d = (0.76 / (0.01_f64 * 0.01 + 1.0).sqrt() + 0.8 / (0.03_f64 * 0.03 + 1.0).sqrt()) / 2.0;
    let middle = (0.02 + 0.02) / 2.0;
    assert!(close(estimator.distance().unwrap().get(), d));
    let rows = estimator.initial_rows().unwrap();
    assert_eq!(rows.len(), 4);
    for (i, row) in rows.iter().enumerate() {
        let offset = 2.5 - (i as f64 + 1.0);
        assert!(close(row.slope(), a));
        assert!(
            close(row.intercept().get(), middle + d * s * offset),
            "row {i}"
        );
    }
    // The pair is rows 2 and 3: the robot between them.
    assert_eq!(side_indices(&rows), Some(Pair { left: 1, right: 2 }));
    // n = 3: the pair is rows 1 and 2, the third on the right.
    let mut estimator = SpacingEstimator::new(SpacingConfig::new(0.05, 0.25, 1, 3).unwrap());
    estimator.observe(&[line(0.0, 0.4), line(0.0, -0.4)]);
    let b = intercepts(&estimator.initial_rows().unwrap());
    assert!(
        close(b[0], 0.4) && close(b[1], -0.4) && close(b[2], -1.2),
        "{b:?}"
    );
}

//= spec/guyonneau2022.md#rows-spacing-params-initialisation-parameters
//= type=test
//# A configuration MUST be refused with an error naming ROWS-SPACING-PARAMS
//# unless a_max and ε are finite and strictly positive, N ≥ 1 and
//# 2 ≤ n ≤ MAX_ROWS.
#[test]
fn bad_spacing_parameters_are_refused() {
    for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        assert_eq!(
            SpacingConfig::new(bad, 0.25, 10, 4)
                .unwrap_err()
                .requirement,
            "ROWS-SPACING-PARAMS"
        );
        assert_eq!(
            SpacingConfig::new(0.05, bad, 10, 4)
                .unwrap_err()
                .requirement,
            "ROWS-SPACING-PARAMS"
        );
    }
    for (estimates, rows) in [(0, 4), (10, 0), (10, 1), (10, MAX_ROWS + 1)] {
        let e = SpacingConfig::new(0.05, 0.25, estimates, rows).unwrap_err();
        assert_eq!(e.requirement, "ROWS-SPACING-PARAMS");
    }
    assert!(SpacingConfig::new(0.05, 0.25, 1, MAX_ROWS).is_ok());
    assert!(SpacingConfig::new(0.05, 0.25, 1, 2).is_ok());
    let d = SpacingConfig::default();
    assert_eq!(
        (d.max_slope(), d.equidistance(), d.estimates(), d.rows()),
        (0.05, 0.25, 10, 4)
    );
}

//= spec/guyonneau2022.md#rows-filter-params-filter-parameters
//= type=test
//# A filter MUST be refused with an error naming ROWS-FILTER-PARAMS unless
//# d > 0, 2 ≤ n ≤ MAX_ROWS, 0 < δ_min ≤ δ_max are finite, 1 ≤ s ≤ 16 and
//# K ≥ 1.
#[test]
fn bad_filter_parameters_are_refused() {
    let refused = |r: Result<FilterConfig, fieldguide::Precondition>| {
        assert_eq!(r.unwrap_err().requirement, "ROWS-FILTER-PARAMS");
    };
    for bad in [0.0, -0.05, f64::NAN, f64::INFINITY] {
        refused(FilterConfig::new(bad, 0.3, 6, 20));
        refused(FilterConfig::new(0.05, bad, 6, 20));
    }
    refused(FilterConfig::new(0.3, 0.05, 6, 20));
    refused(FilterConfig::new(0.05, 0.3, 0, 20));
    refused(FilterConfig::new(0.05, 0.3, MAX_TOLERANCE_STEPS + 1, 20));
    refused(FilterConfig::new(0.05, 0.3, 6, 0));
    assert!(FilterConfig::new(0.1, 0.1, 1, 1).is_ok());
    assert_eq!(
        FilterConfig::default(),
        FilterConfig::new(0.05, 0.3, 6, 20).unwrap()
    );
    let config = FilterConfig::default();
    for d in [0.0, -0.75] {
        let e = RowFilter::new(m(d), &grid(), config).unwrap_err();
        assert_eq!(e.requirement, "ROWS-FILTER-PARAMS");
    }
    let nine = [line(0.0, 0.0); MAX_ROWS + 1];
    for rows in [&[][..], &grid()[..1], &nine[..]] {
        let e = RowFilter::new(m(0.75), rows, config).unwrap_err();
        assert_eq!(e.requirement, "ROWS-FILTER-PARAMS");
    }
    assert_eq!(
        RowFilter::new(m(0.75), &nine[..MAX_ROWS], config)
            .unwrap()
            .rows()
            .len(),
        MAX_ROWS
    );
}

//= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
//= type=test
//# A line L_j MUST match row i at tolerance δ when |a_j − a^{i,−1}| < δ and
//# |b_j − b^{i,−1}| < 1.2 δ.
#[test]
fn the_gates() {
    // One tolerance, 0.05: gates 0.05 on a and 0.06 m on b, strict.
    let config = FilterConfig::new(0.05, 0.05, 1, 20).unwrap();
    let cases = [
        (0.049, 0.375 + 0.059, true),
        (-0.049, 0.375 - 0.059, true),
        (0.051, 0.375, false),
        (0.0, 0.375 + 0.061, false),
        (0.0, 0.375 - 0.061, false),
    ];
    for (a, b, matches) in cases {
        let mut f = RowFilter::new(m(0.75), &grid(), config).unwrap();
        let out = f.update(&[line(a, b)]);
        assert_eq!(out.found[1], matches, "({a}, {b})");
        assert_eq!(out.matched(), usize::from(matches));
    }
}

//= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
//= type=test
//# The tolerance MUST be, among δ_k = δ_min + (δ_max − δ_min) k/(s − 1),
//# k = 0, …, s − 1 (δ_min alone when s = 1), the smallest at which the most
//# found rows agree (ROWS-FILTER-CONSENSUS), when any line matches a row.
#[test]
fn the_tolerance_grows_until_a_match() {
    let config = FilterConfig::default();
    let expected = [0.05, 0.1, 0.15, 0.2, 0.25, 0.3];
    for (k, delta) in expected.iter().enumerate() {
        assert!(close(config.tolerance(k), *delta), "{k}");
    }
    assert_eq!(config.tolerance(5), 0.3);
    assert_eq!(
        FilterConfig::new(0.1, 0.3, 1, 20).unwrap().tolerance(3),
        0.1
    );
    // Rows 2 and 3 seen with a slope 0.12 off, 0.75 m apart along their
    // normal (so they agree): not at δ = 0.05 nor 0.10, found at δ = 0.15,
    // the smallest of the tolerances at which both are found.
    let turned = [
        line(0.12, 0.375),
        line(0.12, 0.375 - 0.75 * (0.12_f64 * 0.12 + 1.0).sqrt()),
    ];
    let mut f = filter(&grid(), 20);
    let out = f.update(&turned);
    assert!(close(out.tolerance.unwrap(), 0.15), "{:?}", out.tolerance);
    assert_eq!(&out.found[..4], &[false, true, true, false]);
    assert_eq!((f.rows()[1], f.rows()[2]), (turned[0], turned[1]));
    // With a close line for row 2, the first tolerance matches it only; at
    // δ = 0.15 the line 0.12 off for row 3 is matched too, but the two rows
    // disagree (slopes 0.12 apart): no tolerance finds more rows that agree,
    // so the first stands and row 3 is computed.
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.0, 0.38), line(0.12, -0.375)]);
    assert_eq!(out.tolerance, Some(0.05));
    assert_eq!(&out.found[..4], &[false, true, false, false]);
    assert!(close(f.rows()[2].slope(), 0.0));
    // Nothing within 0.3: no match at all.
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.31, 0.375), line(0.0, 0.375 + 0.37)]);
    assert_eq!((out.tolerance, out.matched()), (None, 0));
}

/// Every tolerance of an accepted configuration is finite (LIB-FINITE),
/// however wide the range δ_min..δ_max.
#[test]
fn every_tolerance_is_finite() {
    let config = FilterConfig::new(9.3, f64::MAX, 13, 1).unwrap();
    for k in 0..13 {
        let delta = config.tolerance(k);
        assert!(delta.is_finite() && delta >= 9.3, "δ_{k} = {delta}");
    }
}

//= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
//= type=test
//# Matches MUST be assigned in increasing distance
//# D = |a_j − a^{i,−1}| + |b_j − b^{i,−1}| / 1.2, each row taking at most one
//# line and each line at most one row; a found row MUST be its line.
#[test]
fn one_line_per_row_and_one_row_per_line() {
    // Rows 0.3 m apart: a line between rows 2 and 3 passes both gates at
    // δ = 0.15 (0.16 and 0.14 < 0.18); it becomes one row, the closer one
    // (D = 0.14/1.2 to row 3, 0.16/1.2 to row 2). A second line, 0.13 above
    // row 1, is found at δ = 0.15 too and agrees with the first as row 3
    // (0.58 − 2 · 0.3 = −0.02, within 0.2 d of −0.01), so the match counts
    // beyond the first tolerance. Given to row 2 instead, the line would
    // contradict row 1 (0.28 expected) and nothing would count.
    let rows: Vec<RowLine> = [0.45, 0.15, -0.15, -0.45]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    let config = FilterConfig::default();
    let mut f = RowFilter::new(m(0.3), &rows, config).unwrap();
    let above = line(0.0, 0.58);
    let between = line(0.0, -0.01);
    let out = f.update(&[between, above]);
    assert_eq!(out.matched(), 2);
    assert!(close(out.tolerance.unwrap(), 0.15), "{:?}", out.tolerance);
    assert_eq!(&out.found[..4], &[true, false, true, false]);
    assert_eq!((f.rows()[0], f.rows()[2]), (above, between));
    assert!(close(f.rows()[1].intercept().get(), 0.28));
    // Two lines near row 2: the closer in D is taken; the other is within
    // the gates of no other row.
    let mut f = filter(&grid(), 20);
    let near = line(0.01, 0.38); // D to row 2: 0.01 + 0.005/1.2
    let far = line(0.0, 0.40); // D to row 2: 0.025/1.2 = 0.0208
    let out = f.update(&[far, near]);
    assert_eq!(out.matched(), 1);
    assert_eq!(f.rows()[1], near);
    // Each found row is its line, exactly.
    let lines = [line(0.01, 1.1), line(-0.02, -0.39)];
    let mut f = filter(&grid(), 20);
    let out = f.update(&lines);
    assert_eq!(&out.found[..4], &[true, false, true, false]);
    assert_eq!((f.rows()[0], f.rows()[2]), (lines[0], lines[1]));
}

//= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
//= type=test
//# A row without a match MUST be L^i: y = ā x + b^{i_best} + d (i_best − i)
//# sqrt(ā² + 1), with ā the mean slope of the rows found this scan.
#[test]
fn missing_rows_by_eq_15() {
    let mut f = filter(&grid(), 20);
    // Row 2 (index 1): D = 0.02 + 0.015/1.2 = 0.0325; row 3 (index 2):
    // D = 0.04 + 0.005/1.2 = 0.0442. i_best = row 2, ā = 0.03.
    let out = f.update(&[line(0.04, -0.38), line(0.02, 0.39)]);
    assert_eq!(out.best, Some(1));
    let s = (0.03_f64 * 0.03 + 1.0).sqrt();
    let rows = f.rows();
    assert_eq!(rows.len(), 4);
    assert!(close(rows[0].slope(), 0.03) && close(rows[3].slope(), 0.03));
    assert!(close(rows[0].intercept().get(), 0.39 + 0.75 * s));
    assert!(close(rows[3].intercept().get(), 0.39 - 2.0 * 0.75 * s));
    // With the sign of (i_best − i) flipped, row 1 would be right of row 2.
    assert!(rows[0].intercept().get() > rows[1].intercept().get());
    assert!(rows[3].intercept().get() < rows[2].intercept().get());
}

//= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
//= type=test
//# The best match i_best MUST be the found row whose line has the smallest D to
//# its previous row, unless ROWS-FILTER-CONSENSUS names another.
#[test]
fn the_best_match_is_the_closest() {
    let mut f = filter(&grid(), 20);
    // Row 4 is matched almost exactly, row 1 loosely: i_best = row 4.
    let out = f.update(&[line(0.03, 1.14), line(0.001, -1.126)]);
    assert_eq!(out.best, Some(3));
    let a = (0.03 + 0.001) / 2.0;
    let s = (a * a + 1.0_f64).sqrt();
    assert!(close(
        f.rows()[1].intercept().get(),
        -1.126 + 2.0 * 0.75 * s
    ));
}

//= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
//= type=test
//# A found row i MUST be dropped (and computed instead) unless its slope
//# differs from the reference row r's by less than 0.05 and its intercept
//# lies within 0.2 d of b^r + d (r − i) sqrt(a^r² + 1); the reference MUST
//# be the found row with which the most found rows agree, ties going to the
//# earlier match, and it MUST be i_best.
#[test]
fn a_row_contradicting_two_agreeing_rows_is_computed() {
    // Rows 2 and 3 agree (slope −0.01, 0.75 m apart); row 1's line passes
    // the gates at δ = 0.05 but its slope is 0.055 from theirs: dropped, and
    // computed from row 2 (the reference, the first of the two matched).
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.045, 1.125), line(-0.01, 0.375), line(-0.01, -0.38)]);
    assert_eq!(out.tolerance, Some(0.05));
    assert_eq!(&out.found[..4], &[false, true, true, false]);
    assert_eq!(out.best, Some(1));
    let s = (0.01_f64 * 0.01 + 1.0).sqrt();
    let rows = f.rows();
    assert!(close(rows[0].slope(), -0.01), "{:?}", rows[0]);
    assert!(close(rows[0].intercept().get(), 0.375 + 0.75 * s));
    assert!(close(rows[3].intercept().get(), 0.375 - 2.0 * 0.75 * s));
    // The same by the intercept: rows 0.25 m apart, so 0.2 d = 0.05 m is
    // tighter than the gate (0.06 m); row 1 seen 0.055 m off its place.
    let rows: Vec<RowLine> = [0.375, 0.125, -0.125, -0.375]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    let mut f = RowFilter::new(m(0.25), &rows, FilterConfig::default()).unwrap();
    let out = f.update(&[line(0.0, 0.43), line(0.0, 0.126), line(0.0, -0.125)]);
    assert_eq!(&out.found[..4], &[false, true, true, false]);
    assert!(close(f.rows()[0].intercept().get(), 0.375));
    // 0.045 m off instead, within 0.05 m: it agrees and is found.
    let mut f = RowFilter::new(m(0.25), &rows, FilterConfig::default()).unwrap();
    let out = f.update(&[line(0.0, 0.42), line(0.0, 0.126), line(0.0, -0.125)]);
    assert_eq!(&out.found[..4], &[true, true, true, false]);
    assert_eq!(f.rows()[0], line(0.0, 0.42));
}

//= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
//= type=test
//# A found row i MUST be dropped (and computed instead) unless its slope
//# differs from the reference row r's by less than 0.05 and its intercept
//# lies within 0.2 d of b^r + d (r − i) sqrt(a^r² + 1); the reference MUST
//# be the found row with which the most found rows agree, ties going to the
//# earlier match, and it MUST be i_best.
//= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
//= type=test
//# The best match i_best MUST be the found row whose line has the smallest D to
//# its previous row, unless ROWS-FILTER-CONSENSUS names another.
#[test]
fn the_reference_is_the_row_most_agree_with() {
    // Row 1 has the smallest D (0.02) but agrees with no other row (slope
    // −0.02 against 0.04); rows 2, 3 and 4 agree with each other (slope 0.04,
    // d sqrt(a² + 1) apart): row 2 is the reference and i_best, row 1 is
    // computed from it.
    let s = (0.04_f64 * 0.04 + 1.0).sqrt();
    let b2 = 0.365;
    let lines = [
        line(-0.02, 1.125),
        line(0.04, b2),
        line(0.04, b2 - 0.75 * s),
        line(0.04, b2 - 1.5 * s),
    ];
    let mut f = filter(&grid(), 20);
    let out = f.update(&lines);
    assert_eq!(out.tolerance, Some(0.05));
    assert_eq!(&out.found[..4], &[false, true, true, true]);
    assert_eq!(out.best, Some(1));
    assert!(close(f.rows()[0].slope(), 0.04));
    assert!(close(f.rows()[0].intercept().get(), b2 + 0.75 * s));
    assert_eq!(&f.rows()[1..], &lines[1..]);
    // Without the three, row 1 alone is found and is i_best.
    let mut f = filter(&grid(), 20);
    let out = f.update(&lines[..1]);
    assert_eq!((out.best, out.matched()), (Some(0), 1));
    // All four agreeing: i_best is the smallest D, here row 4 (D = 0).
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.01, 1.13), line(0.01, 0.38), line(0.0, -1.125)]);
    assert_eq!(&out.found[..4], &[true, true, false, true]);
    assert_eq!(out.best, Some(3));
}

//= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
//= type=test
//# A found row i MUST be dropped (and computed instead) unless its slope
//# differs from the reference row r's by less than 0.05 and its intercept
//# lies within 0.2 d of b^r + d (r − i) sqrt(a^r² + 1); the reference MUST
//# be the found row with which the most found rows agree, ties going to the
//# earlier match, and it MUST be i_best.
#[test]
fn a_tie_between_references_goes_to_the_earlier_match() {
    // Row 4 (D = 0.02) agrees with no other row; rows 1 and 2 agree with each
    // other, two votes each. Matched in increasing D: row 4, row 2
    // (D = 0.04), row 1 (D = 0.045 + 0.01/1.2): the earlier of the tied pair
    // is row 2, which becomes the reference, and rows 3 and 4 are computed
    // from its intercept.
    let lines = [line(0.045, 1.135), line(0.04, 0.375), line(-0.02, -1.125)];
    let mut f = filter(&grid(), 20);
    let out = f.update(&lines);
    assert_eq!(&out.found[..4], &[true, true, false, false]);
    assert_eq!(out.best, Some(1));
    let a = (0.045 + 0.04) / 2.0;
    let s = (a * a + 1.0_f64).sqrt();
    assert!(close(f.rows()[2].intercept().get(), 0.375 - 0.75 * s));
}

//= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
//= type=test
//# Beyond the first tolerance, a match MUST count only when at least two
//# found rows agree.
#[test]
fn a_lone_match_counts_at_the_first_tolerance_only() {
    // A line 0.12 off in slope matches row 2 from δ = 0.15 only, alone: no
    // match, the rows are kept and the miss counted.
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.12, 0.375)]);
    assert_eq!((out.matched(), out.tolerance, out.best), (0, None, None));
    assert_eq!((out.misses, f.rows()), (1, &grid()[..]));
    // Two lines matched beyond δ_min that disagree (slopes 0.24 apart): no
    // two rows agree, nothing counts.
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.12, 0.375), line(-0.12, -0.375)]);
    assert_eq!((out.matched(), out.misses), (0, 1));
    // At the first tolerance a lone match counts.
    let mut f = filter(&grid(), 20);
    let out = f.update(&[line(0.04, 0.375)]);
    assert_eq!((out.matched(), out.tolerance), (1, Some(0.05)));
    // With a single tolerance, 0.15, it is the first: the lone line counts.
    let one = FilterConfig::new(0.15, 0.15, 1, 20).unwrap();
    let mut f = RowFilter::new(m(0.75), &grid(), one).unwrap();
    let out = f.update(&[line(0.12, 0.375)]);
    assert_eq!((out.matched(), out.tolerance), (1, Some(0.15)));
    assert_eq!(f.rows()[1], line(0.12, 0.375));
}

//= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
//= type=test
//# The tolerance MUST be, among δ_k = δ_min + (δ_max − δ_min) k/(s − 1),
//# k = 0, …, s − 1 (δ_min alone when s = 1), the smallest at which the most
//# found rows agree (ROWS-FILTER-CONSENSUS), when any line matches a row.
#[test]
fn the_tolerance_where_the_most_rows_agree() {
    // The robot has turned: rows 2, 3 and 4 are seen with slope 0.08, which
    // only δ ≥ 0.10 lets through; row 1's line lies on its previous row and
    // matches at δ_min, alone. At δ = 0.10 the three agree (and outvote row
    // 1, whose slope is 0.08 from theirs): δ = 0.10 is taken, not δ_min, and
    // not a larger δ at which the same three agree.
    let s = (0.08_f64 * 0.08 + 1.0).sqrt();
    let lines = [
        line(0.0, 1.125),
        line(0.08, 0.375),
        line(0.08, 0.375 - 0.75 * s),
        line(0.08, 0.375 - 1.5 * s),
    ];
    let mut f = filter(&grid(), 20);
    let out = f.update(&lines);
    assert!(close(out.tolerance.unwrap(), 0.1), "{:?}", out.tolerance);
    assert_eq!(&out.found[..4], &[false, true, true, true]);
    assert_eq!(out.best, Some(1));
    assert!(close(f.rows()[0].slope(), 0.08));
    assert!(close(f.rows()[0].intercept().get(), 0.375 + 0.75 * s));
    // Row 1's line alone: δ_min.
    let mut f = filter(&grid(), 20);
    assert_eq!(f.update(&lines[..1]).tolerance, Some(0.05));
    // The three alone at a slope of 0.18: found at δ = 0.20, the smallest.
    let s = (0.18_f64 * 0.18 + 1.0).sqrt();
    let steep = [
        line(0.18, 0.375),
        line(0.18, 0.375 - 0.75 * s),
        line(0.18, 0.375 - 1.5 * s),
    ];
    let mut f = filter(&grid(), 20);
    let out = f.update(&steep);
    assert!(close(out.tolerance.unwrap(), 0.2), "{:?}", out.tolerance);
    assert_eq!(out.matched(), 3);
}

//= spec/guyonneau2022.md#rows-spacing-range-plausible-row-distances
//= type=test
//# A pair whose d lies outside [d_min, d_max] MUST NOT be a candidate: a
//# pair farther out whose d lies inside may be the one found.
#[test]
fn pairs_outside_the_range_do_not_count() {
    let config = SpacingConfig::default();
    assert_eq!(config.distance_range(), (0.3, 2.0));
    // Two weed lines 0.2 m apart around the robot and the rows 0.8 m apart:
    // the closest pair is out of range, the rows are the pair found.
    let pair = closest_pair(
        &[
            line(0.0, 0.1),
            line(0.0, -0.1),
            line(0.0, 0.4),
            line(0.0, -0.4),
        ],
        &config,
    )
    .unwrap();
    assert_eq!(pair.left.intercept().get(), 0.4);
    assert_eq!(pair.right.intercept().get(), -0.4);
    let mut estimator = SpacingEstimator::new(config);
    // d = 0.28 m and 2.1 m: outside 0.3-2 m, not counted.
    for half in [0.14, 1.05] {
        assert_eq!(
            estimator.observe(&[line(0.0, half), line(0.0, -half)]),
            None
        );
    }
    assert_eq!(estimator.count(), 0);
    // The bounds themselves count.
    for half in [0.15, 1.0] {
        assert!(estimator
            .observe(&[line(0.0, half), line(0.0, -half)])
            .is_some());
    }
    assert_eq!(estimator.count(), 2);
    // A narrower range: 0.8 m counts, 0.4 m and 1.2 m do not.
    let narrow = SpacingConfig::new(0.05, 0.25, 3, 4)
        .unwrap()
        .with_distance_range(m(0.5), m(1.0))
        .unwrap();
    assert_eq!(narrow.distance_range(), (0.5, 1.0));
    let mut estimator = SpacingEstimator::new(narrow);
    for half in [0.2, 0.6] {
        assert_eq!(
            estimator.observe(&[line(0.0, half), line(0.0, -half)]),
            None
        );
    }
    for _ in 0..3 {
        assert!(estimator
            .observe(&[line(0.0, 0.4), line(0.0, -0.4)])
            .is_some());
    }
    assert!(estimator.is_ready());
    assert!(close(estimator.distance().unwrap().get(), 0.8));
    // The range is kept by the other settings (and by none of them set).
    assert_eq!(
        SpacingConfig::new(0.05, 0.25, 3, 4)
            .unwrap()
            .distance_range(),
        (0.3, 2.0)
    );
}

//= spec/guyonneau2022.md#rows-spacing-range-plausible-row-distances
//= type=test
//# A range of row distances MUST be refused with an error naming
//# ROWS-SPACING-RANGE unless 0 < d_min < d_max are finite.
#[test]
fn bad_distance_ranges_are_refused() {
    let config = SpacingConfig::default();
    for (lo, hi) in [
        (0.0, 1.0),
        (-0.0, 1.0),
        (-0.3, 2.0),
        (1.0, 1.0),
        (2.0, 0.3),
        (-2.0, -0.3),
        (0.3, 0.0),
    ] {
        let e = config.with_distance_range(m(lo), m(hi)).unwrap_err();
        assert_eq!(e.requirement, "ROWS-SPACING-RANGE", "[{lo}, {hi}]");
    }
    for (lo, hi) in [
        (f64::MIN_POSITIVE, 1e-300),
        (0.3, f64::MAX),
        (1.0, 1.0 + 1e-15),
    ] {
        let c = config.with_distance_range(m(lo), m(hi)).unwrap();
        assert_eq!(c.distance_range(), (lo, hi));
    }
}

//= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
//= type=test
//# A scan whose computed rows would not be finite MUST count as a scan without
//# any match.
#[test]
fn computed_rows_that_overflow_count_as_no_match() {
    let rows = [line(0.0, 0.0), line(0.0, -1.0), line(0.0, -2.0)];
    // Row 1 found at b = 0: with d = 1, row 3 is at −2.
    let mut f = RowFilter::new(m(1.0), &rows, FilterConfig::default()).unwrap();
    assert_eq!(f.update(&[line(0.0, 0.0)]).matched(), 1);
    // With d = f64::MAX, row 3 would be at −2 f64::MAX: no match, rows kept.
    let mut f = RowFilter::new(m(f64::MAX), &rows, FilterConfig::default()).unwrap();
    let out = f.update(&[line(0.0, 0.0)]);
    assert_eq!((out.matched(), out.best, out.misses), (0, None, 1));
    assert_eq!(f.rows(), &rows);
    assert_eq!(
        out.verdict(),
        Verdict::Absent,
        "row 1 passes under the robot"
    );
}

//= spec/guyonneau2022.md#rows-filter-lost-no-match-and-lost
//= type=test
//# When no line matches any row, the filter MUST keep the previous rows.
#[test]
fn no_match_keeps_the_previous_rows() {
    let mut f = filter(&grid(), 20);
    for k in 1..=5 {
        let out = f.update(&[line(0.5, 0.375), line(0.0, 3.0)]);
        assert_eq!(f.rows(), &grid()[..]);
        assert_eq!((out.matched(), out.misses, out.lost), (0, k, false));
        assert_eq!(out.verdict(), Verdict::Exit);
    }
    let out = f.update(&[]);
    assert_eq!((out.misses, f.misses()), (6, 6));
    // A match resets the count.
    let out = f.update(&[line(0.0, 0.375)]);
    assert_eq!((out.misses, f.misses(), out.matched()), (0, 0, 1));
}

//= spec/guyonneau2022.md#rows-filter-lost-no-match-and-lost
//= type=test
//# After K consecutive scans without any match the filter MUST be lost, and a
//# lost filter MUST keep its rows and stay lost.
#[test]
fn lost_after_k_empty_scans() {
    let mut f = filter(&grid(), 3);
    assert!(!f.update(&[]).lost);
    assert!(!f.update(&[]).lost);
    let out = f.update(&[]);
    assert!(out.lost && f.is_lost());
    assert_eq!(out.verdict(), Verdict::Absent);
    // Even a perfect scan no longer changes anything.
    let out = f.update(&grid());
    assert!(out.lost && out.matched() == 0);
    assert_eq!(out.verdict(), Verdict::Absent);
    assert_eq!(f.rows(), &grid()[..]);
    // Default K = 20.
    let mut f = RowFilter::new(m(0.75), &grid(), FilterConfig::default()).unwrap();
    for _ in 0..19 {
        assert!(!f.update(&[]).lost);
    }
    assert!(f.update(&[]).lost);
}

//= spec/guyonneau2022.md#rows-filter-bound-bounded-work-per-scan
//= type=test
//# One update MUST evaluate at most s n² m gates for m lines, and compute at
//# most n rows.
#[test]
fn the_largest_filter_on_many_lines() {
    let rows: Vec<RowLine> = (0..MAX_ROWS)
        .map(|i| line(0.0, 2.0 - 0.5 * i as f64))
        .collect();
    let config = FilterConfig::new(0.01, 0.3, MAX_TOLERANCE_STEPS, 20).unwrap();
    let mut f = RowFilter::new(m(0.5), &rows, config).unwrap();
    // Ten thousand lines, one near each row: every row found, n rows out.
    let mut lines: Vec<RowLine> = (0..10_000).map(|k| line(1.0 + f64::from(k), 0.0)).collect();
    lines.extend(
        rows.iter()
            .map(|r| line(0.001, r.intercept().get() + 0.002)),
    );
    let out = f.update(&lines);
    assert_eq!((out.matched(), f.rows().len()), (MAX_ROWS, MAX_ROWS));
    let out = f.update(&lines[..10_000]);
    assert_eq!((out.matched(), f.rows().len()), (0, MAX_ROWS));
}

//= spec/guyonneau2022.md#rows-verdict-the-rows-detector-s-verdict
//= type=test
//# The verdict MUST be Absent when the filter is lost or no pair of rows is
//# either side of the robot, Enter when both rows either side were found this
//# scan, Hold when at least one row was found, and Exit otherwise.
#[test]
fn the_verdict_table() {
    let outcome = |found: &[usize], sides: bool, lost: bool| {
        let mut f = [false; MAX_ROWS];
        for &i in found {
            f[i] = true;
        }
        Outcome {
            found: f,
            best: found.first().copied(),
            tolerance: None,
            sides: sides.then_some(Pair { left: 1, right: 2 }),
            misses: 0,
            lost,
        }
    };
    let table: [(&[usize], bool, bool, Verdict); 10] = [
        (&[1, 2], true, false, Verdict::Enter),
        (&[0, 1, 2, 3], true, false, Verdict::Enter),
        (&[1], true, false, Verdict::Hold),
        (&[2, 3], true, false, Verdict::Hold),
        (&[0], true, false, Verdict::Hold),
        (&[], true, false, Verdict::Exit),
        (&[1, 2], false, false, Verdict::Absent),
        (&[], false, false, Verdict::Absent),
        (&[1, 2], true, true, Verdict::Absent),
        (&[], true, true, Verdict::Absent),
    ];
    for (found, sides, lost, verdict) in table {
        assert_eq!(
            outcome(found, sides, lost).verdict(),
            verdict,
            "{found:?} {sides} {lost}"
        );
    }
    // Through the filter: both rows around the robot found, then only row 1.
    let mut f = filter(&grid(), 20);
    assert_eq!(
        f.update(&[line(0.0, 0.38), line(0.0, -0.37)]).verdict(),
        Verdict::Enter
    );
    assert_eq!(f.update(&[line(0.0, 1.12)]).verdict(), Verdict::Hold);
    assert_eq!(f.update(&[]).verdict(), Verdict::Exit);
}

//= spec/guyonneau2022.md#rows-error-the-rows-either-side-and-the-error-to-their-middle
//= type=test
//# The row left of the robot MUST be the row with the smallest positive
//# intercept and the row right of it the row with the largest negative
//# intercept, and they MUST form a pair only when the right row's index is the
//# left row's plus one.
//= spec/guyonneau2022.md#rows-frame-the-paper-s-left-and-right-in-the-library-s-frame
//= type=test
//# The library MUST read every "left" and "right" of the paper in the robot
//# frame x forward, y left: a point or line with y > 0 (b > 0) is left of the
//# robot.
#[test]
fn the_rows_either_side() {
    assert_eq!(side_indices(&grid()), Some(Pair { left: 1, right: 2 }));
    let shifted: Vec<RowLine> = [0.9, 0.15, -0.6, -1.35]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    assert_eq!(side_indices(&shifted), Some(Pair { left: 1, right: 2 }));
    let right_edge: Vec<RowLine> = [2.0, 1.25, 0.5, -0.25]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    assert_eq!(side_indices(&right_edge), Some(Pair { left: 2, right: 3 }));
    let pair = side_rows(&right_edge).unwrap();
    assert_eq!((pair.left, pair.right), (right_edge[2], right_edge[3]));
    // The robot outside all rows, or on a row: no pair.
    let outside: Vec<RowLine> = [3.0, 2.25, 1.5, 0.75]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    assert_eq!(side_indices(&outside), None);
    let on_a_row: Vec<RowLine> = [1.5, 0.75, 0.0, -0.75]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    assert_eq!(side_indices(&on_a_row), None);
    assert_eq!(side_indices(&[]), None);
    let mut f = RowFilter::new(m(0.75), &outside, FilterConfig::default()).unwrap();
    assert_eq!(f.sides(), None);
    let out = f.update(&outside);
    assert_eq!(
        (out.matched(), out.sides, out.verdict()),
        (4, None, Verdict::Absent)
    );
}

//= spec/guyonneau2022.md#rows-error-the-rows-either-side-and-the-error-to-their-middle
//= type=test
//# The tracking error MUST be the mean of the errors to the left and the right
//# row (FUR-TWO-ROWS); without a pair it MUST be refused with an error naming
//# ROWS-ERROR.
#[test]
fn the_error_to_the_middle() {
    // Rows 2 and 3 at 0.3 and −0.45: the robot is 0.075 m left of the middle.
    let rows: Vec<RowLine> = [1.05, 0.3, -0.45, -1.2]
        .iter()
        .map(|&b| line(0.0, b))
        .collect();
    let e = tracking_error(&rows).unwrap();
    assert!(close(e.y.get(), 0.075), "{}", e.y.get());
    assert!(close(e.angular_deviation.get(), 0.0));
    let tilted = [line(0.1, 0.4), line(0.1, -0.35)];
    assert_eq!(
        tracking_error(&tilted).unwrap(),
        mean_tracking_error(&tilted[0], &tilted[1]).unwrap()
    );
    let outside = [line(0.0, 1.0), line(0.0, 0.25)];
    assert_eq!(
        tracking_error(&outside).unwrap_err().requirement,
        "ROWS-ERROR"
    );
}

// ------------------------------------------------------------ properties

/// A filter of n rows of slope `a`, `d` apart, shifted by `shift`, and a
/// scan's lines: a noisy copy of some rows and some clutter.
#[derive(Debug, Clone)]
struct Scene {
    rows: Vec<RowLine>,
    d: f64,
    lines: Vec<RowLine>,
}

fn scene() -> impl Strategy<Value = Scene> {
    (
        2..=MAX_ROWS,
        -0.3_f64..0.3,
        0.25_f64..1.5,
        -1.0_f64..1.0,
        prop::collection::vec((any::<bool>(), -0.2_f64..0.2, -0.25_f64..0.25), MAX_ROWS),
        prop::collection::vec((-2.0_f64..2.0, -5.0_f64..5.0), 0..6),
    )
        .prop_map(|(n, a, d, shift, noise, clutter)| {
            let s = (a * a + 1.0).sqrt();
            let rows: Vec<RowLine> = (0..n)
                .map(|i| line(a, shift + d * s * (n as f64 / 2.0 - 0.5 - i as f64)))
                .collect();
            let mut lines: Vec<RowLine> = rows
                .iter()
                .zip(&noise)
                .filter(|(_, (seen, _, _))| *seen)
                .map(|(r, (_, da, db))| line(r.slope() + da, r.intercept().get() + db))
                .collect();
            lines.extend(clutter.iter().map(|&(ca, cb)| line(ca, cb)));
            Scene { rows, d, lines }
        })
}

/// A filter's n rows as in [`scene`] (slope within ±0.15), and a scan of a
/// robot that has moved since: the rows seen turned by one slope (±0.15) and
/// slid by one intercept (±0.2 d), each with a little noise of its own
/// (±0.01, ±0.05 d), so that each line stays closest to its own row (less
/// than d/2 off at x = 0) and the rows seen agree with each other
/// (ROWS-FILTER-CONSENSUS); and clutter steeper than any gate lets through.
fn moved_scene() -> impl Strategy<Value = Scene> {
    (
        2..=MAX_ROWS,
        -0.15_f64..0.15,
        0.25_f64..1.5,
        -1.0_f64..1.0,
        (-0.15_f64..0.15, -0.2_f64..0.2),
        prop::collection::vec((any::<bool>(), -0.01_f64..0.01, -0.05_f64..0.05), MAX_ROWS),
        prop::collection::vec((1.0_f64..3.0, -5.0_f64..5.0, any::<bool>()), 0..6),
    )
        .prop_map(|(n, a, d, shift, (turn, slide), noise, clutter)| {
            let place = |a: f64, shift: f64, i: usize| {
                shift + d * (a * a + 1.0).sqrt() * (n as f64 / 2.0 - 0.5 - i as f64)
            };
            let rows: Vec<RowLine> = (0..n).map(|i| line(a, place(a, shift, i))).collect();
            let mut lines: Vec<RowLine> = (0..n)
                .zip(&noise)
                .filter(|(_, (seen, _, _))| *seen)
                .map(|(i, (_, da, db))| {
                    line(
                        a + turn + da,
                        place(a + turn, shift + slide * d, i) + db * d,
                    )
                })
                .collect();
            lines.extend(
                clutter
                    .iter()
                    .map(|&(ca, cb, flip)| line(if flip { -ca } else { ca }, cb)),
            );
            Scene { rows, d, lines }
        })
}

/// Any finite value, from the ordinary to the extremes of `f64`.
fn extreme() -> impl Strategy<Value = f64> {
    prop_oneof![
        -3.0_f64..3.0,
        Just(0.0),
        Just(-0.0),
        Just(f64::MAX),
        Just(f64::MIN),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        (-308.0_f64..308.0, any::<bool>()).prop_map(|(e, neg)| if neg {
            -(10f64.powf(e))
        } else {
            10f64.powf(e)
        }),
    ]
}

fn mirror(l: &RowLine) -> RowLine {
    line(-l.slope(), -l.intercept().get())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    //= spec/guyonneau2022.md#rows-filter-bound-bounded-work-per-scan
    //= type=test
    //# One update MUST evaluate at most s n² m gates for m lines, and compute at
    //# most n rows.
    #[test]
    fn the_filter_always_returns_n_rows(sc in scene(), scans in 1_usize..4) {
        let mut f = RowFilter::new(m(sc.d), &sc.rows, FilterConfig::default()).unwrap();
        for _ in 0..scans {
            let out = f.update(&sc.lines);
            prop_assert_eq!(f.rows().len(), sc.rows.len());
            prop_assert!(out.found[sc.rows.len()..].iter().all(|&x| !x));
            prop_assert!(out.matched() <= sc.lines.len());
        }
    }

    //= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
    //= type=test
    //# A row without a match MUST be L^i: y = ā x + b^{i_best} + d (i_best − i)
    //# sqrt(ā² + 1), with ā the mean slope of the rows found this scan.
    #[test]
    fn computed_rows_are_d_apart_along_their_normal(sc in scene()) {
        let mut f = RowFilter::new(m(sc.d), &sc.rows, FilterConfig::default()).unwrap();
        let out = f.update(&sc.lines);
        let Some(best) = out.best else { return Ok(()) };
        let rows = f.rows();
        let found: Vec<&RowLine> = (0..rows.len()).filter(|&i| out.found[i]).map(|i| &rows[i]).collect();
        let a = found.iter().map(|r| r.slope()).sum::<f64>() / found.len() as f64;
        let s = (a * a + 1.0).sqrt();
        for (i, row) in rows.iter().enumerate().filter(|(i, _)| !out.found[*i]) {
            prop_assert!((row.slope() - a).abs() < 1e-12);
            let along_normal = (rows[best].intercept().get() - row.intercept().get()) / s;
            prop_assert!((along_normal - sc.d * (i as f64 - best as f64)).abs() < 1e-9);
            // Rows to the right (larger i) have smaller intercepts.
            if i > best {
                prop_assert!(row.intercept().get() < rows[best].intercept().get());
            } else {
                prop_assert!(row.intercept().get() > rows[best].intercept().get());
            }
        }
    }

    //= spec/guyonneau2022.md#rows-filter-match-lines-matched-to-the-expected-rows-alg-4-lines-4-8
    //= type=test
    //# Matches MUST be assigned in increasing distance
    //# D = |a_j − a^{i,−1}| + |b_j − b^{i,−1}| / 1.2, each row taking at most one
    //# line and each line at most one row; a found row MUST be its line.
    #[test]
    fn mirrored_scenes_give_mirrored_rows(sc in moved_scene()) {
        mirrored(&sc)?;
    }

    //= spec/guyonneau2022.md#rows-filter-consensus-found-rows-agree-with-each-other
    //= type=test
    //# A found row i MUST be dropped (and computed instead) unless its slope
    //# differs from the reference row r's by less than 0.05 and its intercept
    //# lies within 0.2 d of b^r + d (r − i) sqrt(a^r² + 1); the reference MUST
    //# be the found row with which the most found rows agree, ties going to the
    //# earlier match, and it MUST be i_best.
    #[test]
    fn any_mirrored_scenes_give_mirrored_rows(sc in scene()) {
        mirrored(&sc)?;
    }
}

/// The filter of a scene and the filter of its mirror image (y → −y, rows in
/// reverse order) see mirrored rows, verdicts, tolerances and best matches.
fn mirrored(sc: &Scene) -> Result<(), TestCaseError> {
    let n = sc.rows.len();
    let mut f = RowFilter::new(m(sc.d), &sc.rows, FilterConfig::default()).unwrap();
    let mirrored: Vec<RowLine> = sc.rows.iter().rev().map(mirror).collect();
    let mut g = RowFilter::new(m(sc.d), &mirrored, FilterConfig::default()).unwrap();
    let lines: Vec<RowLine> = sc.lines.iter().map(mirror).collect();
    let (out, mout) = (f.update(&sc.lines), g.update(&lines));
    prop_assert_eq!(out.verdict(), mout.verdict());
    prop_assert_eq!(out.tolerance, mout.tolerance);
    prop_assert_eq!(out.best.map(|b| n - 1 - b), mout.best);
    for i in 0..n {
        prop_assert_eq!(out.found[i], mout.found[n - 1 - i]);
        let (r, mr) = (f.rows()[i], g.rows()[n - 1 - i]);
        prop_assert!(close(r.slope(), -mr.slope()), "{:?} {:?}", r, mr);
        prop_assert!(
            close(r.intercept().get(), -mr.intercept().get()),
            "{:?} {:?}",
            r,
            mr
        );
        if out.found[i] {
            prop_assert!(sc.lines.contains(&r));
        }
    }
    if let (Ok(e), Ok(me)) = (tracking_error(f.rows()), tracking_error(g.rows())) {
        prop_assert!(close(e.y.get(), -me.y.get()));
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    //= spec/guyonneau2022.md#rows-filter-missing-computed-rows-eqs-15-17
    //= type=test
    //# A scan whose computed rows would not be finite MUST count as a scan without
    //# any match.
    #[test]
    fn extreme_lines_never_give_a_non_finite_row(
        rows in prop::collection::vec((extreme(), extreme()), 2..=MAX_ROWS),
        lines in prop::collection::vec((extreme(), extreme()), 0..12),
        d in extreme(),
        scans in 1_usize..4,
    ) {
        let rows: Vec<RowLine> = rows.iter().map(|&(a, b)| line(a, b)).collect();
        let lines: Vec<RowLine> = lines.iter().map(|&(a, b)| line(a, b)).collect();
        let Ok(mut f) = RowFilter::new(m(d.abs()), &rows, FilterConfig::default()) else {
            prop_assert!(d == 0.0);
            return Ok(());
        };
        for _ in 0..scans {
            let out = f.update(&lines);
            prop_assert_eq!(f.rows().len(), rows.len());
            prop_assert!(f.rows().iter().all(|r| r.slope().is_finite() && r.intercept().get().is_finite()));
            prop_assert!(out.tolerance.is_none_or(f64::is_finite));
            if out.matched() == 0 {
                prop_assert!(out.misses > 0);
            }
            if let Ok(e) = tracking_error(f.rows()) {
                prop_assert!(e.y.get().is_finite() && e.angular_deviation.get().is_finite());
            }
        }
        let mut estimator = SpacingEstimator::new(SpacingConfig::new(0.05, 0.25, 1, 4).unwrap());
        if estimator.observe(&lines).is_some() {
            if let Ok(initial) = estimator.initial_rows() {
                prop_assert!(initial.iter().all(|r| r.intercept().get().is_finite()));
            }
        }
    }
}

//= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
//= type=test
//# A line y = a x + b of the last scan's robot frame MUST be carried to the
//# frame of the robot at pose (t, ψ) of that frame as the line of the same
//# points: n′ = Rᵀ(ψ) n and c′ = c − n·t, with n = (−a, 1) and c = b.
#[test]
fn lines_seen_from_a_moved_robot() {
    use fieldguide::perception::rows::filter::seen_from;
    use fieldguide::{Pose2, Robot};
    // One metre forward: y = 0.1 x + 0.5 becomes y = 0.1 x′ + 0.6.
    let l = seen_from(
        &line(0.1, 0.5),
        &Pose2::<Robot>::new(1.0, 0.0, 0.0).unwrap(),
    )
    .unwrap();
    assert!(
        close(l.slope(), 0.1) && close(l.intercept().get(), 0.6),
        "{l:?}"
    );
    // 0.2 m to the left: the line is 0.2 m closer on the left.
    let l = seen_from(
        &line(0.0, 0.5),
        &Pose2::<Robot>::new(0.0, 0.2, 0.0).unwrap(),
    )
    .unwrap();
    assert!(
        close(l.slope(), 0.0) && close(l.intercept().get(), 0.3),
        "{l:?}"
    );
    // Turned by 0.1 rad to the left: the row's direction is −0.1 rad.
    let l = seen_from(
        &line(0.0, 0.5),
        &Pose2::<Robot>::new(0.0, 0.0, 0.1).unwrap(),
    )
    .unwrap();
    assert!(close(l.slope(), (-0.1_f64).tan()), "{l:?}");
    // Across the new frame: no y = a x + b form.
    let across = Pose2::<Robot>::new(0.0, 0.0, core::f64::consts::FRAC_PI_2).unwrap();
    assert!(seen_from(&line(0.0, 0.5), &across).is_none());
}

proptest! {
    //= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
    //= type=test
    //# A line y = a x + b of the last scan's robot frame MUST be carried to the
    //# frame of the robot at pose (t, ψ) of that frame as the line of the same
    //# points: n′ = Rᵀ(ψ) n and c′ = c − n·t, with n = (−a, 1) and c = b.
    #[test]
    fn a_moved_line_holds_the_same_points(
        a in -0.5..0.5_f64, b in -2.0..2.0_f64,
        tx in -1.0..1.0_f64, ty in -1.0..1.0_f64, psi in -0.5..0.5_f64,
        xs in prop::collection::vec(-4.0..4.0_f64, 1..6),
    ) {
        use fieldguide::perception::rows::filter::seen_from;
        use fieldguide::{Pose2, Robot};
        let moved = seen_from(&line(a, b), &Pose2::<Robot>::new(tx, ty, psi).unwrap()).unwrap();
        for x in xs {
            // A point of the old line, written in the new frame by hand.
            let (px, py) = (x - tx, a * x + b - ty);
            let (c, s) = (psi.cos(), psi.sin());
            let (qx, qy) = (c * px + s * py, -s * px + c * py);
            prop_assert!((moved.slope() * qx + moved.intercept().get() - qy).abs() < 1e-9);
        }
    }
}

//= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
//= type=test
//# Before a scan's lines are matched, the filter's rows MUST be carried by
//# the odometry motion since the last scan; when a row would be across
//# the new robot frame, the rows MUST be left as they were.
#[test]
fn the_filter_moves_its_rows() {
    use fieldguide::{Pose2, Robot};
    let mut f = filter(&grid(), 20);
    f.move_by(&Pose2::<Robot>::new(0.5, 0.1, 0.0).unwrap());
    let b = intercepts(f.rows());
    for (moved, was) in b.iter().zip([1.125, 0.375, -0.375, -1.125]) {
        assert!(close(*moved, was - 0.1), "{b:?}");
    }
    let before = f.rows().to_vec();
    f.move_by(&Pose2::<Robot>::new(0.0, 0.0, core::f64::consts::FRAC_PI_2).unwrap());
    assert_eq!(f.rows(), &before[..]);
}

//= spec/guyonneau2022.md#rows-motion-rows-moved-by-odometry-between-scans
//= type=test
//# The line finder's carried lines MUST be carried by the same motion.
#[test]
fn the_line_finder_moves_its_lines() {
    use fieldguide::perception::rows::filter::seen_from;
    use fieldguide::perception::rows::ruby::{Ruby, RubyConfig, RubyParams, Variant};
    use fieldguide::{Pose2, Robot};
    let mut r: Ruby<64> = Ruby::new(RubyConfig::new(RubyParams::authors(Variant::Rgop)).unwrap());
    r.carry(&grid());
    let motion = Pose2::<Robot>::new(0.3, -0.05, 0.02).unwrap();
    r.move_by(|l| seen_from(l, &motion));
    for (m, row) in r.models().iter().zip(grid()) {
        let expected = seen_from(&row, &motion).unwrap();
        assert!(close(m.line.slope(), expected.slope()));
        assert!(close(m.line.intercept().get(), expected.intercept().get()));
    }
    // A motion that puts the lines across the robot drops them.
    let across = Pose2::<Robot>::new(0.0, 0.0, core::f64::consts::FRAC_PI_2).unwrap();
    r.reset();
    r.carry(&grid());
    r.move_by(|l| seen_from(l, &across));
    assert!(r.models().is_empty());
}
