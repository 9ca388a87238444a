//! Properties of the maxima and of the one-row and two-row selections of
//! Pierre 2022 eqs. 14 and 17-19, as corrected (FUR-MAXIMA, FUR-SELECT-ONE,
//! FUR-SELECT-PAIR).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use fieldguide::perception::furrow::correlation::Template;
use fieldguide::perception::furrow::scan::ScanPoint;
use fieldguide::perception::furrow::selection::{
    local_maxima, locate, select_one, select_pair, Maximum, Pair, Spacing, MAX_MAXIMA,
};
use fieldguide::{Meters, Point2};
use proptest::prelude::*;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn maximum(ray: usize, score: f64, x: f64, y: f64) -> Maximum {
    Maximum {
        ray,
        score,
        point: Point2::new(x, y).unwrap(),
    }
}

//= spec/pierre2022.md#fur-maxima-local-maxima-above-the-threshold
//= type=test
//# A shift k MUST be a maximum when c[k] > c_t, no score within r rays of k
//# is higher, and every score within r rays before k is strictly lower,
//# with r = max((w − 1)/2, 1).
#[test]
fn hand_computed_maxima() {
    //           0    1    2    3    4    5    6    7    8    9   10   11
    let c = [0.0, 0.5, 0.9, 0.9, 0.9, 0.2, 0.1, 0.35, 0.25, 0.6, 0.1, 0.7];
    // r = 1: the flat top 2-4 gives its first shift, 7 (0.35) and 9 and 11 are
    // peaks; 1 is not (2 is higher), nor is anything at or below c_t = 0.3.
    assert_eq!(local_maxima(&c, 0.3, 1).as_slice(), &[2, 7, 9, 11]);
    // r = 2: 7 has 9 (0.6) within two rays: suppressed; 9 has 11 within two rays.
    assert_eq!(local_maxima(&c, 0.3, 2).as_slice(), &[2, 11]);
    // r = 0 is taken as 1.
    assert_eq!(local_maxima(&c, 0.3, 0).as_slice(), &[2, 7, 9, 11]);
    // Nothing above the threshold: no maxima.
    assert!(local_maxima(&c, 0.95, 1).is_empty());
    assert!(local_maxima(&[], 0.3, 1).is_empty());
    // NaN scores are never maxima and never block one.
    assert_eq!(
        local_maxima(&[f64::NAN, 0.5, f64::NAN], 0.3, 1).as_slice(),
        &[1]
    );
    // More peaks than the capacity: the first MAX_MAXIMA are kept.
    let many: Vec<f64> = (0..200)
        .map(|i| if i % 2 == 0 { 0.9 } else { 0.0 })
        .collect();
    let peaks = local_maxima(&many, 0.3, 1);
    assert_eq!(peaks.len(), MAX_MAXIMA);
    assert_eq!(peaks[0], 0);
}

//= spec/pierre2022.md#fur-maxima-local-maxima-above-the-threshold
//= type=test
//# The position of a maximum MUST be the z_a-weighted centroid of the
//# ground positions of the valid rays under the template's support centred
//# on k.
#[test]
fn a_maximum_stands_at_the_weighted_centroid() {
    let t = Template::new(3, 2, m(0.3)).unwrap();
    let p = |x: f64, y: f64| {
        Some(ScanPoint {
            ground: Point2::new(x, y).unwrap(),
            height: m(0.0),
        })
    };
    let rays = [
        p(4.0, -0.2),
        p(4.0, -0.1),
        p(3.0, 0.0),
        None,
        p(5.0, 0.2),
        p(4.0, 0.3),
    ];
    let signal = [0.3, 0.1, 0.3, 0.9, 0.1, 0.5];
    // Support of centre 2: rays 1, 2, 3; ray 3 has no point: weights 0.1 and 0.3.
    let c = locate(2, &rays, &signal, &t).unwrap();
    assert!((c.x() - (0.1 * 4.0 + 0.3 * 3.0) / 0.4).abs() < 1e-12);
    assert!((c.y() - (0.1 * -0.1 + 0.3 * 0.0) / 0.4).abs() < 1e-12);
    // Support of centre 5 is cut by the window's end: rays 4 and 5.
    let c = locate(5, &rays, &signal, &t).unwrap();
    assert!((c.y() - (0.1 * 0.2 + 0.5 * 0.3) / 0.6).abs() < 1e-12);
    // No positive weight: no position.
    assert!(locate(3, &rays, &[0.0; 6], &t).is_none());
}

//= spec/pierre2022.md#fur-select-one-one-row-the-closest-maximum-in-y
//= type=test
//# The selected maximum MUST minimise |m_y| when there is no previous
//# selection, and |m_y − m_{y,t−1}| otherwise, with m_{t−1} moved into the
//# current robot frame.
#[test]
fn one_row_selection() {
    let maxima = [
        maximum(10, 0.5, 4.0, -0.40),
        maximum(30, 0.9, 4.0, 0.30),
        maximum(50, 0.6, 4.0, 0.70),
    ];
    // At start: closest to the robot, not the highest score.
    assert_eq!(select_one(&maxima, 0.0).unwrap().ray, 30);
    // After: closest to the previous selection.
    assert_eq!(select_one(&maxima, 0.6).unwrap().ray, 50);
    assert_eq!(select_one(&maxima, -0.3).unwrap().ray, 10);
    // Ties go to the first maximum.
    let tie = [maximum(1, 0.5, 4.0, -0.2), maximum(2, 0.5, 4.0, 0.2)];
    assert_eq!(select_one(&tie, 0.0).unwrap().ray, 1);
    assert!(select_one(&[], 0.0).is_none());
}

//= spec/pierre2022.md#fur-select-pair-two-rows-a-pair-within-the-spacing-closest-in-y
//= type=test
//# Only pairs of maxima whose lateral distance |m_{1,y} − m_{2,y}| lies in
//# [d_min, d_max] MUST be candidates.
#[test]
fn pairs_use_the_lateral_distance() {
    let spacing = Spacing::new(m(0.66), m(0.9)).unwrap();
    // Three bean rows 0.375 m apart: only the outer two make a pair; the x
    // difference (plants hit at different heights) does not count.
    let beans = [
        maximum(10, 0.5, 3.2, -0.375),
        maximum(30, 0.9, 4.0, 0.0),
        maximum(50, 0.6, 4.4, 0.375),
    ];
    let pair = select_pair(&beans, &spacing, 0.0).unwrap();
    assert_eq!((pair.left.ray, pair.right.ray), (50, 10));
    assert!((pair.weaker_score().unwrap() - 0.5).abs() < 1e-12);
    // A maximum built by hand with a score that is not a number: an error,
    // not the other score and not a NaN (LIB-FINITE).
    for bad in [f64::NAN, f64::INFINITY] {
        let odd = Pair {
            left: maximum(50, bad, 4.4, 0.375),
            right: maximum(10, bad, 3.2, -0.375),
        };
        assert_eq!(odd.weaker_score().unwrap_err().requirement, "LIB-FINITE");
        let one = Pair {
            left: beans[0],
            ..odd
        };
        assert!(one.weaker_score().is_err());
    }
    // Rows closer than d_min: no pair at all.
    let close = [maximum(10, 0.9, 4.0, -0.3), maximum(20, 0.9, 4.0, 0.3)];
    assert!(select_pair(&close, &spacing, 0.0).is_none());
    // One maximum, or none: no pair.
    assert!(select_pair(&close[..1], &spacing, 0.0).is_none());
    assert!(select_pair(&[], &spacing, 0.0).is_none());
    // Bad spacings are refused.
    assert_eq!(
        Spacing::new(m(0.9), m(0.66)).unwrap_err().requirement,
        "FUR-SELECT-PAIR"
    );
    assert!(Spacing::new(m(0.0), m(0.66)).is_err());
    assert!(Spacing::new(m(0.5), m(0.5)).is_err());
}

//= spec/pierre2022.md#fur-select-pair-two-rows-a-pair-within-the-spacing-closest-in-y
//= type=test
//# The selected pair MUST minimise |mid(P)_y| when there is no previous
//# selection, and |mid(P)_y − mid(P_{t−1})_y| otherwise, with P_{t−1} moved
//# into the current robot frame.
#[test]
fn pair_selection_prefers_the_closest_middle() {
    let spacing = Spacing::new(m(0.66), m(0.9)).unwrap();
    // Rows at −1.15, −0.4, 0.35, 1.1: pairs (−1.15, −0.4) mid −0.775,
    // (−0.4, 0.35) mid −0.025, (0.35, 1.1) mid 0.725.
    let rows = [
        maximum(5, 0.5, 4.0, -1.15),
        maximum(20, 0.5, 4.0, -0.4),
        maximum(35, 0.5, 4.0, 0.35),
        maximum(50, 0.5, 4.0, 1.1),
    ];
    let p = select_pair(&rows, &spacing, 0.0).unwrap();
    assert_eq!((p.left.ray, p.right.ray), (35, 20));
    let p = select_pair(&rows, &spacing, 0.6).unwrap();
    assert_eq!((p.left.ray, p.right.ray), (50, 35));
    let p = select_pair(&rows, &spacing, -0.7).unwrap();
    assert_eq!((p.left.ray, p.right.ray), (20, 5));
}

fn maxima_strategy() -> impl Strategy<Value = Vec<Maximum>> {
    prop::collection::vec((0.0_f64..1.0, 2.0_f64..6.0, -2.0_f64..2.0), 0..MAX_MAXIMA).prop_map(
        |v| {
            v.into_iter()
                .enumerate()
                .map(|(i, (s, x, y))| maximum(i, s, x, y))
                .collect()
        },
    )
}

proptest! {
    //= spec/pierre2022.md#fur-select-pair-two-rows-a-pair-within-the-spacing-closest-in-y
    //= type=test
    //# Only pairs of maxima whose lateral distance |m_{1,y} − m_{2,y}| lies in
    //# [d_min, d_max] MUST be candidates.
    #[test]
    fn every_selected_pair_respects_the_spacing(
        maxima in maxima_strategy(),
        d_min in 0.05_f64..1.0,
        width in 0.01_f64..1.0,
        reference in -2.0_f64..2.0,
    ) {
        let spacing = Spacing::new(m(d_min), m(d_min + width)).unwrap();
        let chosen = select_pair(&maxima, &spacing, reference);
        // Brute force over every pair.
        let mut best: Option<f64> = None;
        for (i, a) in maxima.iter().enumerate() {
            for b in &maxima[i + 1..] {
                let d = (a.point.y() - b.point.y()).abs();
                if d >= d_min && d <= d_min + width {
                    let cost = ((a.point.y() + b.point.y()) / 2.0 - reference).abs();
                    best = Some(best.map_or(cost, |c: f64| c.min(cost)));
                }
            }
        }
        match (chosen, best) {
            (None, None) => {}
            (Some(p), Some(cost)) => {
                let d = p.left.point.y() - p.right.point.y();
                prop_assert!(d >= d_min && d <= d_min + width, "spacing {}", d);
                let mid = (p.left.point.y() + p.right.point.y()) / 2.0;
                prop_assert!(((mid - reference).abs() - cost).abs() < 1e-12);
            }
            (c, b) => prop_assert!(false, "selection {:?} vs brute force {:?}", c, b),
        }
    }

    //= spec/pierre2022.md#fur-maxima-local-maxima-above-the-threshold
    //= type=test
    //# A shift k MUST be a maximum when c[k] > c_t, no score within r rays of k
    //# is higher, and every score within r rays before k is strictly lower,
    //# with r = max((w − 1)/2, 1).
    #[test]
    fn shifting_the_scores_shifts_the_maxima(
        scores in prop::collection::vec(prop_oneof![Just(0.0), 0.0_f64..1.0], 0..120),
        shift in 0_usize..40,
        radius in 0_usize..8,
        threshold in 0.05_f64..0.95,
    ) {
        let mut shifted = vec![0.0; shift];
        shifted.extend_from_slice(&scores);
        let a = local_maxima(&scores, threshold, radius);
        let b = local_maxima(&shifted, threshold, radius);
        prop_assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            prop_assert_eq!(x + shift, *y);
        }
        // And every maximum obeys the definition, checked directly.
        let r = radius.max(1);
        for &k in &a {
            prop_assert!(scores[k] > threshold);
            for i in k.saturating_sub(r)..(k + r + 1).min(scores.len()) {
                prop_assert!(scores[i] <= scores[k]);
                if i < k {
                    prop_assert!(scores[i] < scores[k]);
                }
            }
        }
    }
}
