//! Stateright: every reachable state of the real switching machine, at the
//! paper's delays (Pierre 2022, Tables 1-2) and a 100 Hz control period, for
//! one and for two specialised behaviours; every property of
//! `spec/pierre2022.md` section 3 is an `always` check, and deliberately wrong
//! machines are reported with a counterexample.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeSet;

use fieldguide::supervisor::switching::{CommandSource, Fault, Mode, Switching, SwitchingConfig};
use fieldguide_proofs::evidence::{self, Kind};
use fieldguide_proofs::switching::{
    check_run, config_from_millis, Monitor, Property, Spec, SwitchingModel, Sym, Tick, Violation,
    EDGE_MS, FURROW_MS,
};
use stateright::{Checker, HasDiscoveries, Model};

/// 100 Hz.
const PERIOD_MS: u32 = 10;

/// Explores every reachable state, asserts every property, records what was
/// explored in `run`, and returns the number of distinct states.
fn explore<const K: usize>(run: evidence::Run, config: SwitchingConfig<K>, spec: Spec<K>) -> usize {
    evidence::explore(run, SwitchingModel::new(config, spec))
}

/// The model of `behaviours` at 100 Hz, with its configuration built from
/// `Seconds` by the core and its specification computed in milliseconds.
fn model_parts<const K: usize>(
    behaviours: [(u32, u32); K],
    stop_ms: u32,
    plan_ms: Option<u32>,
) -> (SwitchingConfig<K>, Spec<K>) {
    let config = config_from_millis(PERIOD_MS, behaviours, stop_ms, plan_ms).unwrap();
    let spec = Spec::from_millis(PERIOD_MS, behaviours, stop_ms, plan_ms);
    (config, spec)
}

//= spec/pierre2022.md#sw-delays-transit-delays-in-control-ticks
//= type=test
//# Each specialised behaviour MUST have a positive delay to enter its mode and
//# a positive delay to leave it, and every delay MUST be converted once, at
//# construction, to a whole number of control ticks n = ⌈delay / period⌉.
#[test]
fn the_core_converts_the_tables_to_the_specified_ticks() {
    let (config, spec) = model_parts([EDGE_MS, FURROW_MS], 200, Some(100));
    assert_eq!(spec.enter, [40, 50]);
    assert_eq!(spec.exit, [26, 30]);
    assert_eq!((spec.stop, spec.plan), (20, Some(10)));
    for i in 0..2 {
        let ticks = config.ticks(i).unwrap();
        assert_eq!((ticks.enter, ticks.exit), (spec.enter[i], spec.exit[i]));
    }
    assert_eq!(config.stop_ticks(), spec.stop);
    assert_eq!(config.plan_ticks(), spec.plan);
    assert_eq!(config.min_dwell_ticks(), spec.min_dwell());
    assert_eq!(spec.min_dwell(), 10);
}

//= spec/pierre2022.md#sw-s1-no-chattering
//= type=test
//# Any two mode changes, neither of them to or from Stop and with no Stop
//# between them, MUST be at least D ticks apart, D being the shortest entry,
//# exit and plan delay of the configuration in ticks, and, with two or more
//# specialised behaviours, the Stop delay if it is shorter.
//= spec/pierre2022.md#sw-s2-entry-needs-its-delay-of-evidence
//= type=test
//# Every change into a specialised mode MUST happen in a tick where that
//# behaviour's entry evidence has lasted at least its entry delay, and where no
//# higher-priority behaviour has entry evidence.
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
//= spec/pierre2022.md#sw-command-valid-command-only-from-a-valid-estimate
//= type=test
//# The command source MUST be the active behaviour when the mode is its
//# specialised mode and its verdict is Enter or Hold; otherwise path tracking
//# when the mode is not Stop and localisation is valid; otherwise there MUST be
//# no command source.
#[test]
fn edge_following_alone_table_1() {
    let (config, spec) = model_parts([EDGE_MS], 200, None);
    let states = explore(
        evidence::start("edge (Table 1), stop 0.2 s", Kind::Model),
        config,
        spec,
    );
    // Entry runs 0..=40 alone already give 41 states in path tracking.
    assert!(states > 1_000, "{states}");
}

//= spec/pierre2022.md#sw-p1-an-inconsistent-line-is-left
//= type=test
//# When plan consistency is configured and a behaviour has given valid
//# estimates inconsistent with the plan, and no other behaviour has given
//# entry evidence, in as many consecutive ticks as the plan delay, the mode
//# MUST NOT be that behaviour's mode.
//= spec/pierre2022.md#sw-plan-consistency-line-consistent-with-the-planned-path
//= type=test
//# When plan consistency is configured, the machine MUST leave the active
//# specialised mode (as in SW-EXIT) once that behaviour has given a valid
//# estimate inconsistent with the plan in as many ticks as the plan delay, with
//# no consistent valid estimate between them; a tick without a valid estimate
//# MUST neither add to nor restart that count.
#[test]
fn furrow_pursuing_alone_table_2_with_plan_consistency() {
    let (config, spec) = model_parts([FURROW_MS], 300, Some(200));
    explore(
        evidence::start("furrow (Table 2), stop 0.3 s, plan 0.2 s", Kind::Model),
        config,
        spec,
    );
}

#[test]
fn edge_following_alone_with_plan_consistency() {
    let (config, spec) = model_parts([EDGE_MS], 200, Some(200));
    explore(
        evidence::start("edge (Table 1), stop 0.2 s, plan 0.2 s", Kind::Model),
        config,
        spec,
    );
}

//= spec/pierre2022.md#sw-enter-entering-a-specialised-mode
//= type=test
//# The entry candidate MUST be the highest-priority behaviour with entry
//# evidence in the current tick, and the machine MUST enter the candidate's
//# mode in the tick where its evidence has lasted its entry delay, from path
//# tracking, from Stop, or from the mode of a lower-priority behaviour.
//= spec/pierre2022.md#sw-exit-leaving-a-specialised-mode
//= type=test
//# When the exit evidence has lasted the behaviour's exit delay, or its plan
//# inconsistency has lasted the plan delay (SW-PLAN-CONSISTENCY), the machine
//# MUST leave the mode: to the entry candidate's mode when the candidate's
//# evidence has lasted its entry delay, to path tracking when no behaviour has
//# entry evidence, and otherwise it MUST stay until one of these holds.
//= spec/pierre2022.md#sw-stop-stop-without-a-valid-source
//= type=test
//# When no command source has existed for the Stop delay, converted to ticks as
//# in SW-DELAYS, the mode MUST be Stop, unless a behaviour whose entry evidence
//# has lasted its entry delay can take over, and then the machine MUST enter
//# that behaviour's mode; Stop MUST NOT be entered otherwise.
#[test]
fn edge_and_furrow_tables_1_and_2() {
    let (config, spec) = model_parts([EDGE_MS, FURROW_MS], 200, None);
    let states = explore(
        evidence::start("edge + furrow, stop 0.2 s", Kind::Model),
        config,
        spec,
    );
    assert!(states > 100_000, "{states}");
}

#[test]
fn edge_and_furrow_with_plan_consistency() {
    let (config, spec) = model_parts([EDGE_MS, FURROW_MS], 100, Some(100));
    explore(
        evidence::start("edge + furrow, stop 0.1 s, plan 0.1 s", Kind::Model),
        config,
        spec,
    );
}

/// The counterexample the checker reports for `property`, if any, replayed
/// through the real machine under the monitor to confirm that it ends in a
/// state violating `violated`.
fn counterexample<const K: usize>(
    config: SwitchingConfig<K>,
    spec: Spec<K>,
    property: &'static str,
    violated: Property,
) -> Option<Vec<Tick<K>>> {
    let model = SwitchingModel::new(config, spec);
    assert!(
        model.properties().iter().any(|p| p.name == property),
        "unknown property {property}"
    );
    let checker = model
        .checker()
        .finish_when(HasDiscoveries::AnyOf(BTreeSet::from([property])))
        .spawn_bfs()
        .join();
    let ticks = checker.discovery(property)?.into_actions();
    let mut machine = Switching::new(config);
    let mut monitor = Monitor::new(&spec);
    for tick in &ticks {
        let input = tick.input();
        monitor.observe(&spec, &input, &machine.step(&input));
    }
    assert!(
        !monitor.holds(&spec, violated),
        "replay must violate {violated:?}"
    );
    println!("{property}: counterexample of {} ticks", ticks.len());
    Some(ticks)
}

/// Replays `ticks` and returns the first violation, if any.
fn replay<const K: usize>(
    config: SwitchingConfig<K>,
    spec: &Spec<K>,
    ticks: impl IntoIterator<Item = Tick<K>>,
) -> Result<(), Violation<K>> {
    check_run(config, spec, ticks.into_iter().map(|tick| tick.input()))
}

const fn edge(sym: Sym, localisation_valid: bool) -> Tick<1> {
    Tick {
        behaviours: [sym],
        localisation_valid,
    }
}

//= spec/pierre2022.md#sw-s2-entry-needs-its-delay-of-evidence
//= type=test
//# Every change into a specialised mode MUST happen in a tick where that
//# behaviour's entry evidence has lasted at least its entry delay, and where no
//# higher-priority behaviour has entry evidence.
#[test]
fn a_machine_entering_one_tick_early_is_reported() {
    let run = evidence::start("mutant EnterOneTickEarly, stateright", Kind::Mutant);
    let (config, spec) = model_parts([EDGE_MS], 200, None);
    let mutant = config.with_fault(Fault::EnterOneTickEarly);
    let name = "SW-S2 entry needs its delay of evidence";
    let path = counterexample(mutant, spec, name, Property::S2EntryNeedsEvidence)
        .expect("the early entry must be found");
    assert!(path.iter().any(|tick| tick.behaviours[0] == Sym::Enter));

    // The smallest counterexample: 39 Enter verdicts, one fewer than Table 1's
    // 0.4 s at 100 Hz, and the mutant is in edge following.
    let violation = replay(mutant, &spec, [edge(Sym::Enter, true); 39]).unwrap_err();
    assert_eq!(violation.tick, 38);
    assert_eq!(violation.property, Property::S2EntryNeedsEvidence);
    assert_eq!(violation.monitor.mode, Mode::Behaviour(0));
    assert_eq!(violation.monitor.entry, [39]);

    // The honest machine has no counterexample, and enters at the 40th tick.
    assert!(counterexample(config, spec, name, Property::S2EntryNeedsEvidence).is_none());
    assert!(replay(config, &spec, [edge(Sym::Enter, true); 40]).is_ok());
    run.finish(&evidence::mutant_caught(name, "Fault::EnterOneTickEarly"));
}

#[test]
fn a_machine_configured_one_tick_short_is_reported() {
    let run = evidence::start(
        "mutant configured 0.39 s for 0.4 s, stateright",
        Kind::Mutant,
    );
    // The machine is built for 0.39 s while Table 1 says 0.4 s.
    let config = config_from_millis(PERIOD_MS, [(390, 260)], 200, None).unwrap();
    let spec = Spec::from_millis(PERIOD_MS, [EDGE_MS], 200, None);
    let name = "SW-S2 entry needs its delay of evidence";
    assert!(counterexample(config, spec, name, Property::S2EntryNeedsEvidence).is_some());
    let violation = replay(config, &spec, [edge(Sym::Enter, true); 39]).unwrap_err();
    assert_eq!(violation.property, Property::S2EntryNeedsEvidence);
    run.finish(&evidence::mutant_caught(
        name,
        "configured 0.39 s instead of Table 1's 0.4 s",
    ));
}

#[test]
fn a_machine_steering_with_an_invalid_estimate_is_reported() {
    let run = evidence::start("mutant SteerWithInvalidEstimate, stateright", Kind::Mutant);
    let (config, spec) = model_parts([EDGE_MS], 200, None);
    let mutant = config.with_fault(Fault::SteerWithInvalidEstimate);
    let name = "SW-S3 commands only from valid estimates";
    assert!(counterexample(mutant, spec, name, Property::S3CommandsValid).is_some());
    // 40 Enter ticks to enter, then one tick without an estimate.
    let ticks = [edge(Sym::Enter, true); 40]
        .into_iter()
        .chain([edge(Sym::Out, true)]);
    let violation = replay(mutant, &spec, ticks).unwrap_err();
    assert_eq!(violation.tick, 40);
    assert_eq!(violation.property, Property::S3CommandsValid);
    run.finish(&evidence::mutant_caught(
        name,
        "Fault::SteerWithInvalidEstimate",
    ));
}

#[test]
fn a_machine_that_never_stops_is_reported() {
    let run = evidence::start("mutant NeverStop, stateright", Kind::Mutant);
    let (config, spec) = model_parts([EDGE_MS, FURROW_MS], 200, None);
    let mutant = config.with_fault(Fault::NeverStop);
    let name = "SW-S4 stop exactly after the stop delay";
    assert!(counterexample(mutant, spec, name, Property::S4StopExactly).is_some());
    // 0.2 s at 100 Hz without localisation, nothing entered.
    let lost = Tick {
        behaviours: [Sym::Out, Sym::Out],
        localisation_valid: false,
    };
    let violation = replay(mutant, &spec, [lost; 20]).unwrap_err();
    assert_eq!(violation.tick, 19);
    assert_eq!(violation.property, Property::S4StopExactly);
    assert!(replay(config, &spec, [lost; 60]).is_ok());
    run.finish(&evidence::mutant_caught(name, "Fault::NeverStop"));
}

#[test]
fn the_take_over_instead_of_a_stop_is_needed() {
    // Without the take-over of SW-STOP, a lower-priority behaviour whose entry
    // is complete would wait in Stop; the model reaches the take-over.
    let (config, spec) = model_parts([EDGE_MS, FURROW_MS], 200, None);
    let mut machine = Switching::new(config);
    let both = Tick {
        behaviours: [Sym::Enter, Sym::Enter],
        localisation_valid: true,
    };
    let furrow_only_no_gnss = Tick {
        behaviours: [Sym::Out, Sym::Enter],
        localisation_valid: false,
    };
    for _ in 0..50 {
        machine.step(&both.input());
    }
    assert_eq!(machine.mode(), Mode::Behaviour(0));
    for _ in 0..19 {
        let out = machine.step(&furrow_only_no_gnss.input());
        assert_eq!(out.mode, Mode::Behaviour(0));
        assert_eq!(out.source, CommandSource::None);
    }
    // The 20th tick without a source: the furrow behaviour takes over.
    let out = machine.step(&furrow_only_no_gnss.input());
    assert_eq!(out.mode, Mode::Behaviour(1));
    assert_eq!(out.source, CommandSource::Behaviour(1));
    assert_eq!(spec.stop, 20);
}

/// The machine keeps every property for more than two behaviours: three
/// behaviours (the pipeline's slots are any K up to 8), with short delays so
/// that every reachable state is explored in seconds, with and without the
/// plan check.
#[test]
fn three_behaviours_keep_every_property() {
    let behaviours = [(40, 30), (50, 20), (30, 40)];
    let (config, spec) = model_parts(behaviours, 50, None);
    let plain = explore(
        evidence::start("three behaviours, stop 0.05 s", Kind::Model),
        config,
        spec,
    );
    let (config, spec) = model_parts(behaviours, 50, Some(20));
    let planned = explore(
        evidence::start("three behaviours with plan check", Kind::Model),
        config,
        spec,
    );
    // Each behaviour's entry run alone gives a few states: the three
    // together give many more than any one.
    assert!(plain > 1_000, "{plain}");
    assert!(planned > plain, "{planned} vs {plain}");
}
