//! The fuzzy engine and Guyonneau 2022's wheel-speed controller (section
//! 3.3; `spec/guyonneau2022.md`, FUZZY-* and ROWS-FUZZY-*): terms, inference,
//! exact and sampled centroids, FuzzyLite 6 as an oracle (its command line
//! evaluates `tests/fuzzy/guyonneau2022.fll`, written by hand from Table 1),
//! the inputs of eqs. 18-19, and a differential robot steered between two
//! rows by it.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp,
    clippy::cast_precision_loss
)]

use std::process::Command as Process;

use fieldguide::control::fuzzy::{Defuzzifier, Engine, Rule, Term, Variable, MAX_VARIABLES};
use fieldguide::control::fuzzy_rows::{
    orientation, position, FuzzyRowController, Orientation, TABLE_1,
};
use fieldguide::model::Command;
use fieldguide::perception::furrow::lines::RowLine;
use fieldguide::perception::furrow::selection::Pair;
use fieldguide::{Meters, MetersPerSecond};
use proptest::prelude::*;

const SAMPLED: Defuzzifier = Defuzzifier::Sampled { resolution: 100 };

fn controller(d: Defuzzifier) -> FuzzyRowController {
    FuzzyRowController::authors(
        Orientation::SidesMeanSlope,
        d,
        MetersPerSecond::new(1.0).unwrap(),
    )
    .unwrap()
}

fn row(a: f64, b: f64) -> RowLine {
    RowLine::new(a, Meters::new(b).unwrap()).unwrap()
}

//= spec/guyonneau2022.md#fuzzy-terms-triangles-and-ramps
//= type=test
//# A triangle (l, p, r) MUST have membership (x − l)/(p − l) on [l, p],
//# (r − x)/(r − p) on [p, r] and 0 elsewhere (1 at x = p); a ramp (s, e)
//# MUST have membership 0 on the side of s away from e, 1 on the side of e
//# away from s, and (x − s)/(e − s) between.
#[test]
fn terms_by_hand() {
    let t = Term::Triangle {
        left: -1.0,
        peak: -0.5,
        right: 0.0,
    };
    let c = Term::Triangle {
        left: -0.5,
        peak: 0.0,
        right: 0.5,
    };
    // The paper's one fixed point: −0.25 is 0.5 left and 0.5 centre.
    assert_eq!(t.membership(-0.25), 0.5);
    assert_eq!(c.membership(-0.25), 0.5);
    assert_eq!(t.membership(-0.5), 1.0);
    assert_eq!(t.membership(-0.75), 0.5);
    assert_eq!(t.membership(0.3), 0.0);
    let falling = Term::Ramp {
        start: -0.5,
        end: -1.0,
    };
    assert_eq!(falling.membership(-0.75), 0.5);
    assert_eq!(falling.membership(-3.0), 1.0);
    assert_eq!(falling.membership(0.0), 0.0);
    let rising = Term::Ramp {
        start: 0.5,
        end: 1.0,
    };
    assert_eq!(rising.membership(0.75), 0.5);
    assert_eq!(rising.membership(9.0), 1.0);
    assert_eq!(rising.membership(f64::NAN), 0.0);
    // A degenerate side: a right triangle.
    let edge = Term::Triangle {
        left: 0.0,
        peak: 0.0,
        right: 1.0,
    };
    assert_eq!(edge.membership(0.0), 1.0);
    assert_eq!(edge.membership(0.5), 0.5);
}

fn var(terms: &[Term], min: f64, max: f64) -> Variable {
    Variable {
        min,
        max,
        terms: terms.iter().copied().collect(),
    }
}

fn rule(when: &[Option<u8>], then: &[Option<u8>]) -> Rule {
    let mut r = Rule {
        when: [None; MAX_VARIABLES],
        then: [None; MAX_VARIABLES],
    };
    r.when[..when.len()].copy_from_slice(when);
    r.then[..then.len()].copy_from_slice(then);
    r
}

/// An engine's parts: inputs, outputs, rules, stop values.
type Case = (Vec<Variable>, Vec<Variable>, Vec<Rule>, Vec<f64>);

//= spec/guyonneau2022.md#fuzzy-engine-an-engine-checked-once
//= type=test
//# An engine MUST be refused at construction, with an error naming
//# FUZZY-ENGINE, when a range is not finite and increasing, a term's
//# parameters are not finite and ordered, a rule names a term or a
//# variable that does not exist, or an output has no stop value.
#[test]
fn bad_engines_are_refused() {
    let good = var(
        &[Term::Triangle {
            left: 0.0,
            peak: 0.5,
            right: 1.0,
        }],
        0.0,
        1.0,
    );
    let r = rule(&[Some(0)], &[Some(0)]);
    let one = core::slice::from_ref(&good);
    assert!(Engine::new(one, one, &[r], &[0.0]).is_ok());
    let cases: Vec<Case> = vec![
        (
            vec![var(&[], 1.0, 0.0)],
            vec![good.clone()],
            vec![r],
            vec![0.0],
        ),
        (
            vec![var(&[], 0.0, f64::INFINITY)],
            vec![good.clone()],
            vec![r],
            vec![0.0],
        ),
        (
            vec![var(
                &[Term::Triangle {
                    left: 1.0,
                    peak: 0.5,
                    right: 0.0,
                }],
                0.0,
                1.0,
            )],
            vec![good.clone()],
            vec![r],
            vec![0.0],
        ),
        (
            vec![var(
                &[Term::Ramp {
                    start: 0.5,
                    end: 0.5,
                }],
                0.0,
                1.0,
            )],
            vec![good.clone()],
            vec![r],
            vec![0.0],
        ),
        (
            vec![good.clone()],
            vec![good.clone()],
            vec![rule(&[Some(3)], &[Some(0)])],
            vec![0.0],
        ),
        (
            vec![good.clone()],
            vec![good.clone()],
            vec![rule(&[Some(0), Some(0)], &[Some(0)])],
            vec![0.0],
        ),
        (vec![good.clone()], vec![good.clone()], vec![r], vec![]),
        (
            vec![good.clone()],
            vec![good.clone()],
            vec![r],
            vec![f64::NAN],
        ),
    ];
    for (i, o, rules, stop) in cases {
        let err = Engine::new(&i, &o, &rules, &stop).unwrap_err();
        assert_eq!(
            err.requirement, "FUZZY-ENGINE",
            "{i:?} {o:?} {rules:?} {stop:?}"
        );
    }
    let e = Engine::new(one, one, &[r], &[0.0]).unwrap();
    //= spec/guyonneau2022.md#fuzzy-input-inputs-checked-each-evaluation
    //= type=test
    //# An evaluation MUST be refused with an error naming FUZZY-INPUT unless it
    //# is given one finite value per input variable.
    for bad in [vec![], vec![0.5, 0.5], vec![f64::NAN]] {
        assert_eq!(
            e.evaluate(&bad, Defuzzifier::Exact)
                .unwrap_err()
                .requirement,
            "FUZZY-INPUT"
        );
    }
}

//= spec/guyonneau2022.md#fuzzy-inference-min-product-max
//= type=test
//# A rule's firing MUST be the minimum of its antecedent terms'
//# memberships; an output's aggregate MUST be, at each y, the maximum over
//# the rules concluding on it of the firing times the consequent term's
//# membership.
//= spec/guyonneau2022.md#fuzzy-centroid-exact-and-sampled-centroids
//= type=test
//# The exact centroid MUST be ∫ y A(y) dy / ∫ A(y) dy over the output's range,
//# integrated piece by piece between the terms' vertices and the points where
//# two scaled terms cross, where A is linear.
#[test]
fn inference_and_exact_centroid_by_hand() {
    let up = Term::Ramp {
        start: 0.0,
        end: 1.0,
    };
    let down = Term::Ramp {
        start: 1.0,
        end: 0.0,
    };
    let input = var(&[up, down], 0.0, 1.0);
    // Output terms: a triangle on [0, 1] and one on [1, 2].
    let low = Term::Triangle {
        left: 0.0,
        peak: 0.5,
        right: 1.0,
    };
    let high = Term::Triangle {
        left: 1.0,
        peak: 1.5,
        right: 2.0,
    };
    let output = var(&[low, high], 0.0, 2.0);
    // Rule 1: x is up and z is up → low; rule 2: x is down → high.
    let rules = [
        rule(&[Some(0), Some(0)], &[Some(0)]),
        rule(&[Some(1)], &[Some(1)]),
    ];
    let e = Engine::new(&[input.clone(), input], &[output], &rules, &[0.0]).unwrap();
    // x = 0.8, z = 0.6: rule 1 fires min(0.8, 0.6) = 0.6, rule 2 fires 0.2;
    // A = 0.6 low + 0.2 high (disjoint): centroid (0.6·0.5·0.5 + 0.2·0.5·1.5)
    // / (0.6·0.5 + 0.2·0.5) = (0.15 + 0.15) / 0.4 = 0.75.
    let out = e.evaluate(&[0.8, 0.6], Defuzzifier::Exact).unwrap();
    assert!((out[0].value - 0.75).abs() < 1e-12, "{out:?}");
    assert!(out[0].fired);
    // Overlapping terms crossing inside a piece: the exact centroid agrees
    // with a very fine sampling.
    let a = Term::Triangle {
        left: 0.0,
        peak: 1.0,
        right: 2.0,
    };
    let b = Term::Ramp {
        start: 0.5,
        end: 1.8,
    };
    let output = var(&[a, b], 0.0, 2.0);
    let rules = [rule(&[Some(0)], &[Some(0)]), rule(&[Some(1)], &[Some(1)])];
    let e = Engine::new(&[var(&[up, down], 0.0, 1.0)], &[output], &rules, &[0.0]).unwrap();
    for x in [0.1, 0.35, 0.5, 0.9] {
        let exact = e.evaluate(&[x], Defuzzifier::Exact).unwrap()[0].value;
        let fine = e
            .evaluate(
                &[x],
                Defuzzifier::Sampled {
                    resolution: u16::MAX,
                },
            )
            .unwrap()[0]
            .value;
        assert!((exact - fine).abs() < 1e-6, "{x}: {exact} vs {fine}");
    }
}

//= spec/guyonneau2022.md#fuzzy-centroid-exact-and-sampled-centroids
//= type=test
//# When no rule gives an output a non-zero aggregate, the output MUST be
//# its stop value, flagged as not fired, never a NaN.
#[test]
fn no_rule_fired_is_a_flagged_stop() {
    let narrow = Term::Triangle {
        left: 0.4,
        peak: 0.5,
        right: 0.6,
    };
    let out = var(
        &[Term::Triangle {
            left: -1.0,
            peak: 0.0,
            right: 1.0,
        }],
        -1.0,
        1.0,
    );
    let e = Engine::new(
        &[var(&[narrow], 0.0, 1.0)],
        &[out],
        &[rule(&[Some(0)], &[Some(0)])],
        &[0.25],
    )
    .unwrap();
    for d in [Defuzzifier::Exact, SAMPLED] {
        let o = e.evaluate(&[0.9], d).unwrap()[0];
        assert!(!o.fired);
        assert_eq!(o.value, 0.25);
    }
}

/// The inputs on a grid of at least 200 pairs, beyond the ranges too.
fn grid() -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for i in 0..=20 {
        for j in 0..=14 {
            let theta = -1.0 + 2.0 * f64::from(i) / 20.0;
            let x = -1.2 + 2.4 * f64::from(j) / 14.0;
            v.push((theta, x));
        }
    }
    v
}

/// FuzzyLite 6's outputs on `inputs` for the hand-written FLL engine.
fn fuzzylite(inputs: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let dir = std::env::temp_dir().join(format!("fieldguide-fuzzylite-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (fld, out) = (dir.join("in.fld"), dir.join("out.fld"));
    let mut text = String::from("angle position\n");
    for (t, x) in inputs {
        text += &format!("{t:.17e} {x:.17e}\n");
    }
    std::fs::write(&fld, text).unwrap();
    let fll = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fuzzy/guyonneau2022.fll");
    let status = Process::new("fuzzylite")
        .args(["-i", fll, "-of", "fld", "-d"])
        .arg(&fld)
        .arg("-o")
        .arg(&out)
        .args(["-decimals", "15", "-dheader", "false", "-dinputs", "false"])
        .status()
        .expect("the fuzzylite command (Debian package fuzzylite) runs; .ci/run installs it");
    assert!(status.success());
    let text = std::fs::read_to_string(&out).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            (v[0], v[1])
        })
        .collect()
}

//= spec/guyonneau2022.md#rows-fuzzy-rules-membership-functions-and-table-1
//= type=test
//# The controller MUST use, for the orientation over ±π/4, a falling ramp
//# from −π/12 to −π/6 (very left), triangles (−π/6, −π/12, 0), (−π/12, 0,
//# π/12), (0, π/12, π/6) and a rising ramp from π/12 to π/6 (very right);
//# the same shapes at ±0.5 and ±1 for the position over ±1; seven wheel
//# terms over ±1 with vertices at ±1 (ramps from ±0.666), ±0.666, ±0.333
//# and 0; and the 25 rules of Table 1.
//= spec/guyonneau2022.md#fuzzy-centroid-exact-and-sampled-centroids
//= type=test
//# The sampled centroid MUST be Σ y_i A(y_i) / Σ A(y_i) over the middles
//# y_i = min + (i + 1/2)(max − min)/N, i = 0, …, N − 1, of N equal steps.
#[test]
fn the_controller_matches_fuzzylite() {
    let inputs = grid();
    assert!(inputs.len() >= 200);
    // FuzzyLite's outputs on the grid, kept in the tree so that the test
    // runs where FuzzyLite is not installed; where it is (CI installs it),
    // they are computed again and must not have changed. After a change of
    // the FLL engine, `FUZZY_WRITE=1 cargo test --release --test fuzzy`
    // stores FuzzyLite's new outputs.
    let stored = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fuzzy/guyonneau2022.out");
    if std::env::var("FUZZY_WRITE").is_ok() {
        let out: String = fuzzylite(&inputs)
            .iter()
            .map(|(l, r)| format!("{l:.15} {r:.15}\n"))
            .collect();
        std::fs::write(stored, out).unwrap();
    }
    let oracle: Vec<(f64, f64)> = std::fs::read_to_string(stored)
        .unwrap()
        .lines()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            (v[0], v[1])
        })
        .collect();
    assert_eq!(oracle.len(), inputs.len());
    if Process::new("fuzzylite").arg("-h").output().is_ok() {
        let fresh = fuzzylite(&inputs);
        for (a, b) in fresh.iter().zip(&oracle) {
            assert!(
                (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
                "{a:?} vs {b:?}"
            );
        }
    }
    let (sampled, exact) = (controller(SAMPLED), controller(Defuzzifier::Exact));
    let (mut worst, mut worst_exact) = (0.0_f64, 0.0_f64);
    for (&(t, x), &(l, r)) in inputs.iter().zip(&oracle) {
        let ours = sampled.wheels(t, x).unwrap().fractions;
        worst = worst.max((ours.0 - l).abs()).max((ours.1 - r).abs());
        let e = exact.wheels(t, x).unwrap().fractions;
        worst_exact = worst_exact
            .max((e.0 - ours.0).abs())
            .max((e.1 - ours.1).abs());
    }
    println!("largest difference to FuzzyLite 6: {worst:.2e}; exact vs sampled centroid: {worst_exact:.2e}");
    assert!(worst < 1e-6, "{worst}");
    // The sampled centroid is a midpoint rule: close to the exact one, not equal.
    assert!(worst_exact > 0.0 && worst_exact < 0.02, "{worst_exact}");
}

proptest! {
    /// Mirror symmetry: the table and the terms are symmetric, so mirrored
    /// inputs swap the wheels (exactly for the exact centroid).
    #[test]
    fn mirrored_inputs_swap_the_wheels(t in -1.0..1.0_f64, x in -1.2..1.2_f64) {
        let c = controller(Defuzzifier::Exact);
        let (l, r) = c.wheels(t, x).unwrap().fractions;
        let (ml, mr) = c.wheels(-t, -x).unwrap().fractions;
        prop_assert!((l - mr).abs() < 1e-9 && (r - ml).abs() < 1e-9);
    }

    /// Any finite inputs give wheel speeds within ±1 of the top speed.
    #[test]
    fn outputs_stay_in_range(t in -1e6..1e6_f64, x in -1e6..1e6_f64) {
        for d in [Defuzzifier::Exact, SAMPLED] {
            let w = controller(d).wheels(t, x).unwrap();
            prop_assert!(w.fired);
            prop_assert!(w.fractions.0.abs() <= 1.0 && w.fractions.1.abs() <= 1.0);
        }
    }
}

#[test]
fn table_1_is_mirror_symmetric() {
    for o in 0..5 {
        for p in 0..5 {
            assert_eq!(TABLE_1[o][p].0, TABLE_1[4 - o][4 - p].1, "({o}, {p})");
        }
    }
}

//= spec/guyonneau2022.md#rows-fuzzy-inputs-orientation-and-position-eqs-18-19
//= type=test
//# The orientation MUST be atan((a_left + a_right)/2) of the rows either side
//# (the default), or (1/n) Σ atan(a_i) over the n filtered rows; with the
//# library's slopes it is negative when the robot heads left of the rows.
//= spec/guyonneau2022.md#rows-fuzzy-inputs-orientation-and-position-eqs-18-19
//= type=test
//# The position MUST be x_r = |b_l|/|b_r| − 1 when |b_l| < |b_r| and
//# x_r = 1 − |b_r|/|b_l| otherwise, and MUST be refused with an error naming
//# ROWS-FUZZY-INPUTS when a row passes through the robot (b = 0).
#[test]
fn inputs_of_eqs_18_and_19() {
    // A robot turned 0.1 rad to the left sees the rows with slope −tan 0.1.
    let a = -(0.1_f64).tan();
    let sides = Pair {
        left: row(a, 0.25),
        right: row(a, -0.5),
    };
    let theta = orientation(&sides, &[], Orientation::SidesMeanSlope).unwrap();
    assert!((theta + 0.1).abs() < 1e-12);
    let rows = [row(0.2, 1.0), row(0.0, 0.25), row(-0.2, -0.5)];
    let mean = orientation(&sides, &rows, Orientation::AllRowsMeanAngle).unwrap();
    assert!(mean.abs() < 1e-12);
    assert_eq!(
        orientation(&sides, &[], Orientation::AllRowsMeanAngle)
            .unwrap_err()
            .requirement,
        "ROWS-FUZZY-INPUTS"
    );
    // Nearer the left row: 0.25/0.5 − 1 = −0.5; nearer the right: 1 − 0.25/0.5.
    assert!((position(&sides).unwrap() + 0.5).abs() < 1e-12);
    let right = Pair {
        left: row(0.0, 0.5),
        right: row(0.0, -0.25),
    };
    assert!((position(&right).unwrap() - 0.5).abs() < 1e-12);
    let centred = Pair {
        left: row(0.0, 0.4),
        right: row(0.0, -0.4),
    };
    assert_eq!(position(&centred).unwrap(), 0.0);
    let through = Pair {
        left: row(0.0, 0.0),
        right: row(0.0, -0.4),
    };
    assert_eq!(
        position(&through).unwrap_err().requirement,
        "ROWS-FUZZY-INPUTS"
    );
}

/// A differential robot (track 0.6 m, 40 Hz) between two straight rows
/// 0.75 m apart along x, steered by `c`; returns the largest |offset| over
/// the last half of 20 s and whether it stayed between the rows.
fn drive(c: &FuzzyRowController, y0: f64, psi0: f64) -> (f64, bool) {
    let (track, dt) = (0.6, 0.025);
    let (mut y, mut psi) = (y0, psi0);
    let mut late = 0.0_f64;
    let mut inside = true;
    for k in 0..800 {
        // The rows y = ±0.375 seen from the robot: slope −tan ψ, intercepts.
        let a = -psi.tan();
        let sides = Pair {
            left: row(a, (0.375 - y) / psi.cos()),
            right: row(a, (-0.375 - y) / psi.cos()),
        };
        let Command::Differential { left, right } = c.command(&sides, &[]).unwrap().command else {
            panic!("a differential command")
        };
        let (vl, vr) = (left.get(), right.get());
        let v = 0.5 * (vl + vr);
        psi += (vr - vl) / track * dt;
        y += v * psi.sin() * dt;
        inside &= y.abs() < 0.35;
        if k >= 400 {
            late = late.max(y.abs());
        }
    }
    (late, inside)
}

//= spec/guyonneau2022.md#rows-fuzzy-command-wheel-speeds
//= type=test
//# The command MUST be the differential command whose wheel speeds are
//# the two outputs times the top speed.
#[test]
fn the_controller_keeps_a_robot_between_the_rows() {
    let c = FuzzyRowController::authors(
        Orientation::SidesMeanSlope,
        Defuzzifier::Exact,
        MetersPerSecond::new(0.5).unwrap(),
    )
    .unwrap();
    //= spec/guyonneau2022.md#rows-fuzzy-command-wheel-speeds
    //= type=test
    //# A top speed that is not > 0 MUST be refused with an error naming
    //# ROWS-FUZZY-SPEED.
    for bad in [0.0, -1.0] {
        let err = FuzzyRowController::authors(
            Orientation::SidesMeanSlope,
            Defuzzifier::Exact,
            MetersPerSecond::new(bad).unwrap(),
        )
        .unwrap_err();
        assert_eq!(err.requirement, "ROWS-FUZZY-SPEED");
    }
    let w = c.wheels(0.0, 0.0).unwrap();
    let Command::Differential { left, right } = w.command else {
        panic!()
    };
    assert!((left.get() - 0.5 * w.fractions.0).abs() < 1e-12);
    assert!((right.get() - 0.5 * w.fractions.1).abs() < 1e-12);
    for (y0, psi0) in [(0.15, 0.0), (-0.15, 0.1), (0.0, -0.2), (0.2, 0.2)] {
        let (late, inside) = drive(&c, y0, psi0);
        assert!(inside, "start ({y0}, {psi0}) left the rows");
        assert!(
            late < 0.03,
            "start ({y0}, {psi0}): {late:.3} m off the middle"
        );
    }
}

/// The check bites: a controller whose wheels are swapped (the rules for
/// left and right exchanged) drives the robot out of the rows.
#[test]
fn swapped_wheels_leave_the_rows() {
    let c = controller(Defuzzifier::Exact);
    let (_, inside) = {
        let (track, dt) = (0.6, 0.025);
        let (mut y, mut psi, mut inside) = (0.15_f64, 0.0_f64, true);
        for _ in 0..800 {
            let a = -psi.tan();
            let sides = Pair {
                left: row(a, (0.375 - y) / psi.cos()),
                right: row(a, (-0.375 - y) / psi.cos()),
            };
            let (r, l) = c.command(&sides, &[]).unwrap().fractions;
            psi += (r - l) / track * dt;
            y += 0.5 * (l + r) * psi.sin() * dt;
            inside &= y.abs() < 0.35;
            if !inside {
                break;
            }
        }
        ((), inside)
    };
    assert!(!inside);
}
