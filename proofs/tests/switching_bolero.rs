//! Bolero harnesses over the real switching machine: every input sequence of
//! 12 ticks over a compact alphabet, checked exhaustively here
//! (`check!().exhaustive()`), and Kani proofs wherever Kani is installed
//! (`cargo kani -p fieldguide-proofs --tests`).
//!
//! The control period is 10 Hz so that 12 ticks are long enough to enter,
//! leave and stop with the paper's delays: Table 1 gives 4 ticks to enter
//! edge following and 3 to leave it, Table 2 gives 5 and 3 for furrow
//! pursuing; the Stop delay and the plan delay are 0.3 s (3 ticks). After
//! every tick the monitor checks SW-S1 to SW-P1 and SW-COMMAND-VALID.
//!
//! Alphabets: harness 1 uses all four verdicts. The others use symbols the
//! stateright model shows to be enough (Exit and Absent give the same state
//! and output in every reachable state; the plan flag of an invalid estimate
//! is ignored), so that 4^12 = 16 777 216 sequences stay within seconds.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::atomic::{AtomicU64, Ordering};

use bolero::{check, generator::TypeGenerator};
use fieldguide::supervisor::switching::{Fault, Input, Report, SwitchingConfig};
use fieldguide::Verdict;
use fieldguide_proofs::evidence::{self, Kind};
use fieldguide_proofs::switching::{check_run, config_from_millis, Spec, EDGE_MS, FURROW_MS};

/// Ticks per sequence.
const DEPTH: usize = 12;
/// 10 Hz.
const PERIOD_MS: u32 = 100;
/// Stop and plan delays, 3 ticks at 10 Hz.
const STOP_MS: u32 = 300;
const PLAN_MS: u32 = 300;
/// What every harness checks after every tick.
const PROPERTIES: [&str; 8] = [
    "SW-S1",
    "SW-S2",
    "SW-S3",
    "SW-S4",
    "SW-L1",
    "SW-L2",
    "SW-P1",
    "SW-COMMAND-VALID",
];

/// Runs `body` on every sequence of `T` and records the harness `run`.
fn exhaustive<T>(run: evidence::Run, body: impl Fn(&T) + std::panic::RefUnwindSafe)
where
    T: TypeGenerator + core::fmt::Debug,
{
    let count = AtomicU64::new(0);
    check!().with_type::<T>().exhaustive().for_each(|sequence| {
        count.fetch_add(1, Ordering::Relaxed);
        body(sequence);
    });
    run.finish(&evidence::harness(
        &PROPERTIES,
        count.into_inner(),
        u64::try_from(DEPTH).ok(),
    ));
}

fn parts<const K: usize>(
    behaviours: [(u32, u32); K],
    plan_ms: Option<u32>,
) -> (SwitchingConfig<K>, Spec<K>) {
    (
        config_from_millis(PERIOD_MS, behaviours, STOP_MS, plan_ms).unwrap(),
        Spec::from_millis(PERIOD_MS, behaviours, STOP_MS, plan_ms),
    )
}

/// Runs the inputs through a fresh machine and asserts every property after
/// every tick.
fn assert_properties<const K: usize>(
    config: SwitchingConfig<K>,
    spec: &Spec<K>,
    inputs: impl IntoIterator<Item = Input<K>>,
) {
    let result = check_run(config, spec, inputs);
    assert!(result.is_ok(), "{result:?}");
}

/// One verdict, all four of them.
#[derive(Clone, Copy, Debug, TypeGenerator)]
enum AnyVerdict {
    Enter,
    Hold,
    Exit,
    Absent,
}

impl AnyVerdict {
    fn input(self) -> Input<1> {
        let verdict = match self {
            Self::Enter => Verdict::Enter,
            Self::Hold => Verdict::Hold,
            Self::Exit => Verdict::Exit,
            Self::Absent => Verdict::Absent,
        };
        Input {
            behaviours: [Report::consistent(verdict)],
            localisation_valid: true,
        }
    }
}

fn edge_verdicts(config: SwitchingConfig<1>, spec: &Spec<1>, sequence: &[AnyVerdict; DEPTH]) {
    assert_properties(config, spec, sequence.iter().map(|v| v.input()));
}

//= spec/pierre2022.md#sw-s2-entry-needs-its-delay-of-evidence
//= type=test
//# Every change into a specialised mode MUST happen in a tick where that
//# behaviour's entry evidence has lasted at least its entry delay, and where no
//# higher-priority behaviour has entry evidence.
//= spec/pierre2022.md#sw-l1-enter-verdicts-bring-the-mode
//= type=test
//# When a behaviour's entry evidence has lasted its entry delay and no
//# higher-priority behaviour has entry evidence in the current tick, the mode
//# MUST be that behaviour's mode or a higher-priority one; for the
//# highest-priority behaviour it MUST be its mode.
//= spec/pierre2022.md#sw-l2-exit-or-absent-verdicts-bring-path-tracking
//= type=test
//# When a behaviour has given Exit or Absent verdicts with valid localisation,
//# and no other behaviour has given entry evidence, in as many consecutive
//# ticks as its exit delay, the mode MUST be neither that behaviour's mode nor
//# Stop.
/// Edge following (Table 1) with localisation: every sequence of the four
/// verdicts.
#[test]
#[cfg_attr(kani, kani::proof, kani::unwind(13))]
fn every_verdict_sequence_of_edge_following() {
    let (config, spec) = parts([EDGE_MS], None);
    exhaustive::<[AnyVerdict; DEPTH]>(
        evidence::start("edge following, every verdict sequence", Kind::Harness),
        |sequence| edge_verdicts(config, &spec, sequence),
    );
}

/// A tick of edge following with the localisation varying: an estimate is
/// entered with localisation lost (so a Stop can end by an entry), holds with
/// it valid, and disappears with it valid (path tracking steers through the
/// exit delay) or lost (nothing can steer).
#[derive(Clone, Copy, Debug, TypeGenerator)]
enum LocalisedTick {
    EnterLost,
    HoldLocalised,
    OutLocalised,
    OutLost,
}

impl LocalisedTick {
    fn input(self) -> Input<1> {
        let (verdict, localisation_valid) = match self {
            Self::EnterLost => (Verdict::Enter, false),
            Self::HoldLocalised => (Verdict::Hold, true),
            Self::OutLocalised => (Verdict::Exit, true),
            Self::OutLost => (Verdict::Absent, false),
        };
        Input {
            behaviours: [Report::consistent(verdict)],
            localisation_valid,
        }
    }
}

//= spec/pierre2022.md#sw-s3-commands-only-from-valid-estimates
//= type=test
//# Every command source MUST be valid in its tick: a behaviour only in its own
//# mode with an Enter or Hold verdict, path tracking only with valid
//# localisation and outside Stop.
//= spec/pierre2022.md#sw-s4-stop-exactly-after-the-stop-delay-without-a-source
//= type=test
//# The mode MUST be Stop exactly when, in each of the last Stop-delay ticks,
//# localisation was invalid and the mode was not a specialised mode whose
//# behaviour gave a valid estimate.
//= spec/pierre2022.md#sw-command-valid-command-only-from-a-valid-estimate
//= type=test
//# The command source MUST be the active behaviour when the mode is its
//# specialised mode and its verdict is Enter or Hold; otherwise path tracking
//# when the mode is not Stop and localisation is valid; otherwise there MUST be
//# no command source.
/// Edge following with localisation lost and regained: every sequence.
#[test]
#[cfg_attr(kani, kani::proof, kani::unwind(13))]
fn every_sequence_with_localisation_lost_and_regained() {
    let (config, spec) = parts([EDGE_MS], None);
    exhaustive::<[LocalisedTick; DEPTH]>(
        evidence::start(
            "localisation lost and regained, every sequence",
            Kind::Harness,
        ),
        |sequence| {
            assert_properties(config, &spec, sequence.iter().map(|t| t.input()));
        },
    );
}

/// A tick of edge following (index 0, higher priority) and furrow pursuing
/// (index 1): both, either or neither reporting Enter.
#[derive(Clone, Copy, Debug, TypeGenerator)]
enum PairTick {
    Both,
    EdgeOnly,
    FurrowOnly,
    Neither,
}

impl PairTick {
    fn input(self) -> Input<2> {
        let (edge, furrow) = match self {
            Self::Both => (Verdict::Enter, Verdict::Enter),
            Self::EdgeOnly => (Verdict::Enter, Verdict::Absent),
            Self::FurrowOnly => (Verdict::Exit, Verdict::Enter),
            Self::Neither => (Verdict::Absent, Verdict::Exit),
        };
        Input {
            behaviours: [Report::consistent(edge), Report::consistent(furrow)],
            localisation_valid: true,
        }
    }
}

//= spec/pierre2022.md#sw-s1-no-chattering
//= type=test
//# Any two mode changes, neither of them to or from Stop and with no Stop
//# between them, MUST be at least D ticks apart, D being the shortest entry,
//# exit and plan delay of the configuration in ticks, and, with two or more
//# specialised behaviours, the Stop delay if it is shorter.
//= spec/pierre2022.md#sw-enter-entering-a-specialised-mode
//= type=test
//# A lower-priority behaviour MUST NOT take over the mode of a higher-priority
//# behaviour, except instead of a Stop (SW-STOP), and no behaviour MUST be
//# entered while a higher-priority behaviour has entry evidence in the same
//# tick.
/// Edge following and furrow pursuing together: priority, take-over and
/// hand-over, every sequence.
#[test]
#[cfg_attr(kani, kani::proof, kani::unwind(13))]
fn every_sequence_of_edge_and_furrow_together() {
    let (config, spec) = parts([EDGE_MS, FURROW_MS], None);
    exhaustive::<[PairTick; DEPTH]>(
        evidence::start("edge and furrow together, every sequence", Kind::Harness),
        |sequence| {
            assert_properties(config, &spec, sequence.iter().map(|t| t.input()));
        },
    );
}

/// A tick of edge following with plan consistency configured.
#[derive(Clone, Copy, Debug, TypeGenerator)]
enum PlanTick {
    Enter,
    EnterInconsistent,
    HoldInconsistent,
    Out,
}

impl PlanTick {
    fn input(self) -> Input<1> {
        let (verdict, plan_consistent) = match self {
            Self::Enter => (Verdict::Enter, true),
            Self::EnterInconsistent => (Verdict::Enter, false),
            Self::HoldInconsistent => (Verdict::Hold, false),
            Self::Out => (Verdict::Absent, true),
        };
        Input {
            behaviours: [Report {
                verdict,
                plan_consistent,
            }],
            localisation_valid: true,
        }
    }
}

//= spec/pierre2022.md#sw-p1-an-inconsistent-line-is-left
//= type=test
//# When plan consistency is configured and a behaviour has given valid
//# estimates inconsistent with the plan, and no other behaviour has given
//# entry evidence, in as many consecutive ticks as the plan delay, the mode
//# MUST NOT be that behaviour's mode.
/// Edge following with plan consistency: every sequence.
#[test]
#[cfg_attr(kani, kani::proof, kani::unwind(13))]
fn every_sequence_with_plan_consistency() {
    let (config, spec) = parts([EDGE_MS], Some(PLAN_MS));
    exhaustive::<[PlanTick; DEPTH]>(
        evidence::start("plan consistency, every sequence", Kind::Harness),
        |sequence| {
            assert_properties(config, &spec, sequence.iter().map(|t| t.input()));
        },
    );
}

/// The first harness, run on a machine that enters one tick early, fails:
/// bolero reports the sequence (three Enter verdicts instead of four).
#[test]
fn the_verdict_harness_reports_a_machine_entering_one_tick_early() {
    let run = evidence::start("mutant EnterOneTickEarly, bolero", Kind::Mutant);
    let (config, spec) = parts([EDGE_MS], None);
    let mutant = config.with_fault(Fault::EnterOneTickEarly);
    let outcome = std::panic::catch_unwind(|| {
        check!()
            .with_type::<[AnyVerdict; DEPTH]>()
            .exhaustive()
            .for_each(|sequence| edge_verdicts(mutant, &spec, sequence));
    });
    assert!(outcome.is_err(), "the early entry must be reported");

    // The same check on the shortest counterexample, by hand.
    let violation = check_run(mutant, &spec, [AnyVerdict::Enter.input(); 3]).unwrap_err();
    assert_eq!(violation.tick, 2);
    assert_eq!(spec.enter, [4]);
    run.finish(&evidence::Explored {
        properties: vec!["SW-S2".to_owned()],
        mutant: Some("Fault::EnterOneTickEarly".to_owned()),
        ..evidence::Explored::default()
    });
}
