//! The classifier from a detector's continuous quality to a verdict is
//! consistent with its thresholds (SW-THRESHOLDS, SW-CLASSIFY). This is what
//! justifies proving the switching machine over verdicts only: every quality
//! maps to exactly one of Enter, Hold, Exit (a total function, so every
//! concrete run is a run over verdicts), each of the three is produced by some
//! quality (no abstract verdict is spurious), and Absent only comes from a
//! detector that has no estimate.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use fieldguide::perception::{Better, QualityThresholds};
use fieldguide::supervisor::switching::{BehaviourConfig, Input, Report, SwitchingConfig};
use fieldguide::{Seconds, Verdict};
use fieldguide_proofs::switching::{check_run, Spec, EDGE_MS, FURROW_MS};
use proptest::prelude::*;

fn any_better() -> impl Strategy<Value = Better> {
    prop_oneof![Just(Better::Lower), Just(Better::Higher)]
}

/// Any f64 a detector could compute, the special values included.
fn any_quality() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        2 => any::<f64>(),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0f64),
    ]
}

/// Valid thresholds: two distinct finite values, ordered for `better`.
fn valid_thresholds() -> impl Strategy<Value = QualityThresholds> {
    (-1e6..1e6f64, 1e-9..1e3f64, any_better()).prop_map(|(a, gap, better)| {
        let (enter, exit) = match better {
            Better::Lower => (a, a + gap),
            Better::Higher => (a + gap, a),
        };
        QualityThresholds::new(enter, exit, better).unwrap()
    })
}

/// `a` is strictly better than `b` for this direction.
fn strictly_better(better: Better, a: f64, b: f64) -> bool {
    match better {
        Better::Lower => a < b,
        Better::Higher => a > b,
    }
}

proptest! {
    //= spec/pierre2022.md#sw-thresholds-hysteresis-thresholds-ordered
    //= type=test
    //# A detector's entry threshold MUST be strictly stricter than its exit
    //# threshold; a configuration where it is not MUST be refused at construction
    //# with an error naming the requirement.
    #[test]
    fn thresholds_are_accepted_exactly_when_ordered(
        enter in any_quality(),
        exit in any_quality(),
        better in any_better(),
    ) {
        let result = QualityThresholds::new(enter, exit, better);
        let ordered = enter.is_finite() && exit.is_finite() && strictly_better(better, enter, exit);
        prop_assert_eq!(result.is_ok(), ordered);
        if let Err(error) = result {
            prop_assert_eq!(error.requirement, "SW-THRESHOLDS");
        }
    }

    //= spec/pierre2022.md#sw-classify-quality-to-verdict
    //= type=test
    //# The verdict of an existing estimate MUST be Enter when its quality is
    //# strictly better than the entry threshold, Exit when it is strictly worse
    //# than the exit threshold or is not a number, and Hold otherwise.
    #[test]
    fn the_verdict_is_the_one_the_thresholds_name(
        thresholds in valid_thresholds(),
        quality in any_quality(),
    ) {
        let better = match thresholds.enter() < thresholds.exit() {
            true => Better::Lower,
            false => Better::Higher,
        };
        let expected = if quality.is_nan() || strictly_better(better, thresholds.exit(), quality) {
            Verdict::Exit
        } else if strictly_better(better, quality, thresholds.enter()) {
            Verdict::Enter
        } else {
            Verdict::Hold
        };
        prop_assert_eq!(thresholds.classify(quality), expected);
        prop_assert_ne!(thresholds.classify(quality), Verdict::Absent);
    }

    /// A better quality never gets a worse verdict (Enter < Hold < Exit).
    #[test]
    fn the_verdict_is_monotone_in_the_quality(
        thresholds in valid_thresholds(),
        a in -2e6..2e6f64,
        b in -2e6..2e6f64,
    ) {
        let better = if thresholds.enter() < thresholds.exit() { Better::Lower } else { Better::Higher };
        let (good, bad) = if strictly_better(better, a, b) { (a, b) } else { (b, a) };
        prop_assert!(thresholds.classify(good) <= thresholds.classify(bad));
    }

    /// Each abstract verdict Enter, Hold and Exit is the image of some quality,
    /// so exploring all three over-approximates nothing the detectors cannot do.
    #[test]
    fn every_estimate_verdict_is_reachable(thresholds in valid_thresholds()) {
        let (best, worst) = if thresholds.enter() < thresholds.exit() {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (f64::INFINITY, f64::NEG_INFINITY)
        };
        prop_assert_eq!(thresholds.classify(best), Verdict::Enter);
        prop_assert_eq!(thresholds.classify(thresholds.enter()), Verdict::Hold);
        prop_assert_eq!(thresholds.classify(thresholds.exit()), Verdict::Hold);
        prop_assert_eq!(thresholds.classify(worst), Verdict::Exit);
        prop_assert_eq!(thresholds.classify(f64::NAN), Verdict::Exit);
    }

    /// End to end with continuous qualities: residual standard deviations of
    /// the edge detector and correlations of the furrow detector, classified
    /// with Tables 1-2 and fed to the machine at 100 Hz, keep every property.
    #[test]
    fn continuous_qualities_through_the_classifier_keep_the_properties(
        ticks in prop::collection::vec(
            (prop::option::weighted(0.9, 0.0..0.7f64),
             prop::option::weighted(0.9, 0.0..0.6f64),
             prop::bool::weighted(0.9)),
            0..400,
        ),
    ) {
        let edge = BehaviourConfig::edge_following().unwrap();
        let furrow = BehaviourConfig::furrow_pursuing().unwrap();
        let config = SwitchingConfig::new(
            Seconds::new(0.01).unwrap(),
            [edge, furrow],
            Seconds::new(0.2).unwrap(),
            None,
        ).unwrap();
        let spec = Spec::from_millis(10, [EDGE_MS, FURROW_MS], 200, None);
        let grade = |thresholds: &QualityThresholds, quality: Option<f64>| {
            Report::consistent(quality.map_or(Verdict::Absent, |q| thresholds.classify(q)))
        };
        let inputs = ticks.iter().map(|&(sigma, correlation, localisation_valid)| Input {
            behaviours: [grade(&edge_thresholds(), sigma), grade(&furrow_thresholds(), correlation)],
            localisation_valid,
        });
        let result = check_run(config, &spec, inputs);
        prop_assert!(result.is_ok(), "{:?}", result);
    }
}

/// The edge detector's thresholds of Table 1 (`EdgeConfig::pierre2022`).
fn edge_thresholds() -> QualityThresholds {
    fieldguide::perception::edge::EdgeConfig::pierre2022()
        .unwrap()
        .thresholds()
}

/// The furrow detector's thresholds of Table 2 (`FurrowParams::table2`).
fn furrow_thresholds() -> QualityThresholds {
    use fieldguide::perception::furrow::{FurrowConfig, FurrowParams};
    *FurrowConfig::new(&FurrowParams::table2())
        .unwrap()
        .thresholds()
}

#[test]
fn the_tables_classify_as_the_paper_reads() {
    let (edge, furrow) = (edge_thresholds(), furrow_thresholds());
    // Table 1: enter below σ_edge = 0.15 m, leave above σ_path = 0.5 m.
    assert_eq!(edge.classify(0.10), Verdict::Enter);
    assert_eq!(edge.classify(0.15), Verdict::Hold);
    assert_eq!(edge.classify(0.30), Verdict::Hold);
    assert_eq!(edge.classify(0.51), Verdict::Exit);
    // Table 2 (eq. 22 as in the errata): enter above 0.4, leave below 0.2.
    assert_eq!(furrow.classify(0.45), Verdict::Enter);
    assert_eq!(furrow.classify(0.30), Verdict::Hold);
    assert_eq!(furrow.classify(0.19), Verdict::Exit);
}
