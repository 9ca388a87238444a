//! Properties of the plant model, the height signal and the normalised
//! correlation of Pierre 2022 eqs. 12-13 (FUR-TEMPLATE, FUR-SIGNAL,
//! FUR-CORRELATION).
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use fieldguide::perception::furrow::correlation::{
    correlate, correlate_direct, height_signal, Template, MAX_SAMPLE, SAMPLE_QUANTUM,
};
use fieldguide::Meters;
use proptest::prelude::*;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn scores(signal: &[f64], t: &Template) -> (Vec<f64>, Vec<f64>) {
    let mut fast = vec![f64::NAN; signal.len()];
    let mut slow = vec![f64::NAN; signal.len()];
    correlate(signal, t, &mut fast).unwrap();
    correlate_direct(signal, t, &mut slow).unwrap();
    (fast, slow)
}

//= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
//= type=test
//# The score at centre ray k MUST be c[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)
//# with A = Σ_i z_a[k+i]² and R = Σ_i z_r[i]², both sums over the template
//# index i ∈ [−L/2, L/2], for every k where the whole template lies in the
//# window; elsewhere, and where A = 0, c[k] MUST be 0.
#[test]
fn hand_computed_scores() {
    // w = 3, m = 1, h = 1: L = 5, half = 2, R = 3.
    let t = Template::new(3, 1, m(1.0)).unwrap();
    let signal = [0.0, 0.0, 2.0, 2.0, 2.0, 0.0, 0.0];
    let (fast, slow) = scores(&signal, &t);
    // Centre 3: window [0,2,2,2,0], S = 6, A = 12: c = 6 / sqrt(12 · 3) = 1.
    assert!((fast[3] - 1.0).abs() < 1e-12);
    // Centre 2: window [0,0,2,2,2], support [0,2,2]: S = 4, A = 12: c = 4 / 6.
    assert!((fast[2] - 4.0 / 6.0).abs() < 1e-12);
    // Centre 4: window [2,2,2,0,0], support [2,2,0]: also 4 / 6.
    assert!((fast[4] - 4.0 / 6.0).abs() < 1e-12);
    // Where the template does not fit (k < 2 or k > 4): 0.
    for k in [0, 1, 5, 6] {
        assert_eq!(fast[k], 0.0);
        assert_eq!(slow[k], 0.0);
    }
    for k in 0..signal.len() {
        assert!((fast[k] - slow[k]).abs() < 1e-12);
    }
    // A one-ray spike in a margin only: S = 0, A > 0: score 0, not NaN.
    let spike = [5.0, 0.0, 0.0, 0.0, 0.0];
    let (fast, slow) = scores(&spike, &t);
    assert_eq!(fast[2], 0.0);
    assert_eq!(slow[2], 0.0);
    // Negative heights anti-correlate: the score is −1 for an inverted plant.
    let hole = [0.0, -1.0, -1.0, -1.0, 0.0];
    let (fast, _) = scores(&hole, &t);
    assert!((fast[2] + 1.0).abs() < 1e-12);
}

//= spec/pierre2022.md#fur-template-rectangular-plant-model-with-zero-margins
//= type=test
//# The template MUST be z_r[i] = h_ref for |i| ≤ (w_ref − 1)/2 and z_r[i] = 0
//# for the m zero rays on each side, with i ∈ [−L/2, L/2] and L = w_ref + 2m.
#[test]
fn template_shape() {
    let t = Template::new(15, 7, m(0.3)).unwrap();
    assert_eq!(t.length(), 29);
    assert_eq!(t.half_length(), 14);
    assert_eq!(t.half_width(), 7);
    for i in -14_isize..=14 {
        let expected = if i.abs() <= 7 { 0.3 } else { 0.0 };
        assert_eq!(t.value(i), expected, "offset {i}");
    }
    assert!((t.energy() - 15.0 * 0.09).abs() < 1e-12);
}

//= spec/pierre2022.md#fur-template-rectangular-plant-model-with-zero-margins
//= type=test
//# A template whose width is even or zero, whose height is not positive,
//# or whose length overflows MUST be refused with an error naming
//# FUR-TEMPLATE.
#[test]
fn bad_templates_are_refused() {
    for (w, margin, h) in [
        (0, 3, 0.3),
        (14, 3, 0.3),
        (15, 3, 0.0),
        (15, 3, -0.1),
        (15, usize::MAX, 0.3),
        (15, 0, 1e200),
    ] {
        let e = Template::new(w, margin, m(h)).unwrap_err();
        assert_eq!(e.requirement, "FUR-TEMPLATE", "{w} {margin} {h}");
    }
    assert!(Template::new(1, 0, m(0.1)).is_ok());
}

//= spec/pierre2022.md#fur-signal-height-signal-with-a-noise-floor
//= type=test
//# The signal z_a of a window ray MUST be its height z when z > z_floor and
//# 0 otherwise; a dropped ray MUST count as 0.
#[test]
fn height_signal_floor() {
    let floor = m(0.05);
    assert_eq!(height_signal(Some(m(0.3)), floor), 0.3);
    assert_eq!(height_signal(Some(m(0.05)), floor), 0.0);
    assert_eq!(height_signal(Some(m(0.049)), floor), 0.0);
    assert_eq!(height_signal(Some(m(-0.2)), floor), 0.0);
    assert_eq!(height_signal(None, floor), 0.0);
}

//= spec/pierre2022.md#fur-signal-height-signal-with-a-noise-floor
//= type=test
//# The signal z_a of a window ray MUST be its height z when z > z_floor and
//# 0 otherwise; a dropped ray MUST count as 0.
#[test]
fn flat_noisy_ground_gives_no_score() {
    let t = Template::new(15, 7, m(0.3)).unwrap();
    let floor = m(0.05);
    // Ground heights within ±4 cm of zero, and a few dropped rays.
    let signal: Vec<f64> = (0..200)
        .map(|j| {
            let z = 0.04 * ((j as f64) * 7.31).sin();
            height_signal(if j % 17 == 0 { None } else { Some(m(z)) }, floor)
        })
        .collect();
    let (fast, slow) = scores(&signal, &t);
    assert!(fast.iter().chain(&slow).all(|&c| c == 0.0));
}

//= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
//= type=test
//# The score at centre ray k MUST be c[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)
//# with A = Σ_i z_a[k+i]² and R = Σ_i z_r[i]², both sums over the template
//# index i ∈ [−L/2, L/2], for every k where the whole template lies in the
//# window; elsewhere, and where A = 0, c[k] MUST be 0.
#[test]
fn template_wider_than_the_window_scores_nothing_and_short_output_is_refused() {
    let t = Template::new(15, 7, m(0.3)).unwrap();
    let signal = [0.3; 28];
    let (fast, slow) = scores(&signal, &t);
    assert!(fast.iter().chain(&slow).all(|&c| c == 0.0));
    let mut short = [0.0; 10];
    assert_eq!(
        correlate(&signal, &t, &mut short).unwrap_err().requirement,
        "FUR-CORRELATION"
    );
    assert_eq!(
        correlate_direct(&signal, &t, &mut short)
            .unwrap_err()
            .requirement,
        "FUR-CORRELATION"
    );
    let mut out: [f64; 0] = [];
    assert!(correlate(&[], &t, &mut out).is_ok());
}

//= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
//= type=test
//# Each sample z_a MUST be read as the nearest multiple of `SAMPLE_QUANTUM`
//# (2⁻²⁴ m), and the running sums MUST equal the sums of the definition
//# exactly, whatever the heights.
#[test]
fn a_tall_sample_that_left_the_window_leaves_nothing_behind() {
    assert_eq!(SAMPLE_QUANTUM, 2f64.powi(-24));
    // A 0.16 m height beside 1e-122 m ones. The running sums lost the
    // tiny heights under the rounding of the tall ones and scored 0 where the
    // definition scored 0.58 (at k = 5) and 0.82 (at k = 4).
    let t = Template::new(3, 0, m(0.3)).unwrap();
    let signal = [0.0, 0.3, 0.16, 1e-122, 0.0, 1e-122, 0.0];
    let (fast, slow) = scores(&signal, &t);
    assert_eq!(fast, slow);
    // On the grid 1e-122 m is 0: the windows of k = 4 and 5 hold 0.16 or nothing.
    let grid = [0.0, 0.3, 0.16, 0.0, 0.0, 0.0, 0.0];
    assert_eq!(scores(&grid, &t).0, fast);
    // Heights on the grid, 19 orders of magnitude apart: the smallest one
    // alone in a window still scores 1, after any number of tall ones slid by.
    let q = SAMPLE_QUANTUM;
    let mut signal = vec![0.0; 3];
    for _ in 0..50 {
        signal.extend_from_slice(&[MAX_SAMPLE, 1000.0 + q, 0.75, 3.0 * q]);
    }
    signal.extend_from_slice(&[0.0, 0.0, q, 0.0, 0.0, 0.0]);
    let (fast, slow) = scores(&signal, &t);
    assert_eq!(fast, slow);
    let alone = signal.len() - 4;
    assert_eq!(fast[alone], 1.0 / 3.0_f64.sqrt());
    assert_eq!(fast[alone - 1], 1.0 / 3.0_f64.sqrt());
    // Heights below half a quantum are ground, above it one quantum; half a
    // quantum exactly goes to the even multiple, 0.
    let t1 = Template::new(1, 1, m(0.3)).unwrap();
    for (z, expected) in [
        (0.49 * q, 0.0),
        (0.5 * q, 0.0),
        (0.51 * q, 1.0),
        (0.9 * q, 1.0),
        (1e-300, 0.0),
    ] {
        assert_eq!(scores(&[0.0, z, 0.0], &t1).0[1], expected, "{z}");
    }
}

/// The score of eq. 13 computed by its definition in plain `f64`, on the
/// samples as FUR-CORRELATION reads them (on the grid, 0 when not finite or
/// beyond 10⁶ m): an independent reference.
fn reference(signal: &[f64], t: &Template) -> Vec<f64> {
    let q = SAMPLE_QUANTUM;
    let z: Vec<f64> = signal
        .iter()
        .map(|&v| {
            if v.is_finite() && v.abs() <= MAX_SAMPLE {
                (v / q).round_ties_even() * q
            } else {
                0.0
            }
        })
        .collect();
    let (half, hw) = (t.half_length(), t.half_width());
    (0..signal.len())
        .map(|k| {
            if k < half || k + half >= signal.len() {
                return 0.0;
            }
            let window = &z[k - half..=k + half];
            let a: f64 = window.iter().map(|v| v * v).sum();
            let support: f64 = z[k - hw..=k + hw].iter().sum();
            if a == 0.0 {
                0.0
            } else {
                (t.height().get() * support / (a * t.energy()).sqrt()).clamp(-1.0, 1.0)
            }
        })
        .collect()
}

/// Adversarial samples: zeros, heights of every scale from 1e-300 m to 10⁶ m
/// (subnormals included), tall and tiny ones side by side, either sign, and
/// values the correlation ignores (NaN, infinities, beyond 10⁶ m).
fn adversarial_sample() -> impl Strategy<Value = f64> {
    let scale = (-300.0_f64..6.0, any::<bool>()).prop_map(|(e, negative)| {
        let v = 10f64.powf(e);
        if negative {
            -v
        } else {
            v
        }
    });
    prop_oneof![
        4 => Just(0.0),
        3 => scale,
        2 => 0.0_f64..1.0,
        1 => (1_u64..1 << 20).prop_map(|k| k as f64 * SAMPLE_QUANTUM),
        1 => prop::sample::select(vec![
            MAX_SAMPLE, -MAX_SAMPLE, 1e-122, 5e-324, f64::MIN_POSITIVE, -0.0,
            f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 2.0 * MAX_SAMPLE, f64::MAX,
        ]),
    ]
}

fn template_strategy() -> impl Strategy<Value = Template> {
    (0_usize..10, 0_usize..8, 0.01_f64..2.0).prop_map(|(hw, margin, h)| {
        Template::new(2 * hw + 1, margin, Meters::new(h).unwrap()).unwrap()
    })
}

/// Sparse, plant-like signals: zeros with runs of heights.
fn sparse_signal() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(
        prop_oneof![3 => Just(0.0), 2 => -5.0_f64..5.0, 1 => 0.0_f64..1e-3],
        0..300,
    )
}

proptest! {
    //= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
    //= type=test
    //# The scores of a window of N rays MUST be computed with running sums, in
    //# O(N) operations whatever the template length.
    #[test]
    fn running_sums_equal_the_definition(t in template_strategy(), signal in sparse_signal()) {
        let (fast, slow) = scores(&signal, &t);
        for k in 0..signal.len() {
            prop_assert!((fast[k] - slow[k]).abs() < 1e-9, "k {} fast {} slow {}", k, fast[k], slow[k]);
        }
    }

    //= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
    //= type=test
    //# Each sample z_a MUST be read as the nearest multiple of `SAMPLE_QUANTUM`
    //# (2⁻²⁴ m), and the running sums MUST equal the sums of the definition
    //# exactly, whatever the heights.
    #[test]
    fn running_sums_are_exact_on_adversarial_signals(
        t in template_strategy(),
        signal in prop::collection::vec(adversarial_sample(), 0..200),
    ) {
        let (fast, slow) = scores(&signal, &t);
        let exact = reference(&signal, &t);
        for k in 0..signal.len() {
            // The running sums are the definition's, bit for bit.
            prop_assert_eq!(fast[k].to_bits(), slow[k].to_bits(), "k {}", k);
            // Against the definition in plain f64: |Σ_support z| ≤ sqrt(w A)
            // bounds the rounding of the reference's sums, relative to the score.
            prop_assert!((fast[k] - exact[k]).abs() <= 1e-12, "k {} fast {} reference {}", k, fast[k], exact[k]);
        }
    }

    //= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
    //= type=test
    //# The score at centre ray k MUST be c[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)
    //# with A = Σ_i z_a[k+i]² and R = Σ_i z_r[i]², both sums over the template
    //# index i ∈ [−L/2, L/2], for every k where the whole template lies in the
    //# window; elsewhere, and where A = 0, c[k] MUST be 0.
    #[test]
    fn a_perfect_match_scores_one_at_any_scale_and_place(
        t in template_strategy(),
        scale in 1e-3_f64..1e3,
        before in 0_usize..40,
        after in 0_usize..40,
    ) {
        // The template itself (support scaled, margins zero) inside flat ground.
        let mut signal = vec![0.0; before];
        for i in -(t.half_length() as isize)..=(t.half_length() as isize) {
            signal.push(scale * t.value(i) / t.height().get());
        }
        signal.extend(core::iter::repeat_n(0.0, after));
        let (fast, slow) = scores(&signal, &t);
        let centre = before + t.half_length();
        prop_assert!((fast[centre] - 1.0).abs() < 1e-12);
        prop_assert!((slow[centre] - 1.0).abs() < 1e-12);
        // It is the highest score of the scan.
        prop_assert!(fast.iter().all(|&c| c <= fast[centre]));
    }

    //= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
    //= type=test
    //# The score at centre ray k MUST be c[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)
    //# with A = Σ_i z_a[k+i]² and R = Σ_i z_r[i]², both sums over the template
    //# index i ∈ [−L/2, L/2], for every k where the whole template lies in the
    //# window; elsewhere, and where A = 0, c[k] MUST be 0.
    #[test]
    fn scores_stay_in_range_for_any_input(
        t in template_strategy(),
        signal in prop::collection::vec(prop_oneof![
            Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(f64::MAX),
            Just(MAX_SAMPLE), Just(0.0), any::<f64>(), -10.0_f64..10.0
        ], 0..200),
    ) {
        let (fast, slow) = scores(&signal, &t);
        for c in fast.iter().chain(&slow) {
            prop_assert!(c.is_finite() && (-1.0..=1.0).contains(c));
        }
    }

    //= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
    //= type=test
    //# The score at centre ray k MUST be c[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)
    //# with A = Σ_i z_a[k+i]² and R = Σ_i z_r[i]², both sums over the template
    //# index i ∈ [−L/2, L/2], for every k where the whole template lies in the
    //# window; elsewhere, and where A = 0, c[k] MUST be 0.
    #[test]
    fn shifting_the_signal_shifts_the_scores(
        t in template_strategy(),
        signal in sparse_signal(),
        shift in 0_usize..30,
    ) {
        let mut shifted = vec![0.0; shift];
        shifted.extend_from_slice(&signal);
        let (a, _) = scores(&signal, &t);
        let (b, _) = scores(&shifted, &t);
        for k in 0..signal.len() {
            // Where the template fitted before, it fits after the shift too.
            prop_assert!((a[k] - b[k + shift]).abs() < 1e-9 || a[k] == 0.0);
        }
    }
}
