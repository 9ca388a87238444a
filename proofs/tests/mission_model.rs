//! Stateright: every reachable state of the real mission machine on a
//! mission of a road (2 legs) and a field (1 row: a turn and a pass), with
//! short limits so that timeouts are reached; every property
//! EM-MISSION-M1 to M5 of `spec/emmi2024.md` is an `always` check, and
//! deliberately wrong machines are reported with a counterexample.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeSet;

use fieldguide::supervisor::mission::{
    Arrival, Command, Events, Fault, HazardLevel, MachineConfig, Shape, StopReason, TaskKind,
};
use fieldguide_proofs::evidence::{self, Kind};
use fieldguide_proofs::mission::{check_run, MissionModel, Property};
use stateright::{Checker, HasDiscoveries, Model};

/// Legs per task: a road of two waypoints, a field of one row.
const LEGS: [u8; 2] = [2, 2];
/// Stall delay and leg time limit, ticks.
const STALL: u16 = 3;
const LEG: u16 = 5;

fn shape() -> Shape {
    Shape::from_legs(&[
        (TaskKind::Approximation, LEGS[0]),
        (TaskKind::Treatment, LEGS[1]),
    ])
}

fn config() -> MachineConfig {
    MachineConfig::from_ticks(STALL, LEG).unwrap()
}

fn model(config: MachineConfig) -> MissionModel {
    MissionModel::new(config, shape(), &LEGS, LEG)
}

//= spec/emmi2024.md#em-mission-m1-a-critical-obstacle-always-stops
//= type=test
//# In every reachable state, a tick with the hazard Critical MUST command Stop.
//= spec/emmi2024.md#em-mission-m2-no-re-planning-in-a-field
//= type=test
//# In every reachable state, a tick inside a field MUST NOT start a detour nor
//# command one.
//= spec/emmi2024.md#em-mission-m3-lost-localisation-stops
//= type=test
//# In every reachable state, a tick with the localisation Lost MUST command
//# Stop.
//= spec/emmi2024.md#em-mission-m4-every-task-ends-within-a-bound
//= type=test
//# When every tick of a task has the hazard Clear and a valid localisation, the
//# task MUST end (the next task, Done or Aborted) within its number of legs
//# times the leg time limit, plus one tick per leg, ticks.
//= spec/emmi2024.md#em-mission-m5-never-backwards
//= type=test
//# In every reachable state, the command MUST be Stop or Follow of a leg no
//# earlier than any leg commanded before, at a speed that is never negative.
#[test]
fn every_reachable_state_keeps_m1_to_m5() {
    let states = evidence::explore(
        evidence::start("mission (2 + 2 legs, stall 3, leg 5 ticks)", Kind::Model),
        model(config()),
    );
    assert!(states > 1_000, "{states}");
}

/// The counterexample the checker reports for `property` on `config`, if
/// any, replayed through the real machine to confirm that it violates
/// `violated`.
fn counterexample(
    config: MachineConfig,
    property: &'static str,
    violated: Property,
) -> Option<Vec<Events>> {
    let model = model(config);
    assert!(model.properties().iter().any(|p| p.name == property));
    let checker = model
        .checker()
        .finish_when(HasDiscoveries::AnyOf(BTreeSet::from([property])))
        .spawn_bfs()
        .join();
    let events = checker.discovery(property)?.into_actions();
    let violation = check_run(&config, &shape(), &LEGS, events.iter().copied()).unwrap_err();
    assert_eq!(violation.property, violated);
    assert_eq!(violation.tick + 1, events.len());
    println!("{property}: counterexample of {} ticks", events.len());
    Some(events)
}

//= spec/emmi2024.md#em-mission-obstacle-obstacles
//= type=test
//# With the hazard Warning on a road, the machine MUST re-plan the leg through
//# the detour waypoint, and stop with the reason NoDetour when there is none;
//# inside a field it MUST NOT re-plan but stop with the reason ObstacleInField.
#[test]
fn a_machine_that_replans_inside_a_field_is_reported() {
    let run = evidence::start("mutant ReplanInField, stateright", Kind::Mutant);
    let name = "EM-MISSION-M2 no re-planning in a field";
    let mutant = config().with_fault(Fault::ReplanInField);
    let path = counterexample(mutant, name, Property::M2NoReplanInField)
        .expect("the re-planning in a field must be found");
    let last = path.last().unwrap();
    assert!(last.in_field);
    assert_eq!(last.hazard, HazardLevel::Warning { detour: true });
    // The smallest counterexample: one tick in a field with a warning and a detour.
    let warned = Events {
        in_field: true,
        hazard: HazardLevel::Warning { detour: true },
        ..Events::NOMINAL
    };
    let violation = check_run(&mutant, &shape(), &LEGS, [warned]).unwrap_err();
    assert_eq!(
        (violation.tick, violation.property),
        (0, Property::M2NoReplanInField)
    );
    // The honest machine has no counterexample, and stops instead.
    assert!(counterexample(config(), name, Property::M2NoReplanInField).is_none());
    let (_, out) = fieldguide::supervisor::mission::step(
        &config(),
        &shape(),
        &fieldguide::supervisor::mission::MissionState::initial(&shape()),
        &warned,
    );
    assert_eq!(out.command, Command::Stop(StopReason::ObstacleInField));
    run.finish(&evidence::mutant_caught(name, "Fault::ReplanInField"));
}

#[test]
fn a_machine_that_ignores_a_critical_obstacle_is_reported() {
    let run = evidence::start("mutant IgnoreCritical, stateright", Kind::Mutant);
    let name = "EM-MISSION-M1 a critical obstacle always stops";
    let mutant = config().with_fault(Fault::IgnoreCritical);
    assert!(counterexample(mutant, name, Property::M1CriticalStops).is_some());
    assert!(counterexample(config(), name, Property::M1CriticalStops).is_none());
    run.finish(&evidence::mutant_caught(name, "Fault::IgnoreCritical"));
}

/// The bound of M4 is tight: a leg never reached aborts at the leg time
/// limit, and the road's two legs take at most 2 × (5 + 1) ticks.
#[test]
fn the_task_bound_is_reached_by_timeouts() {
    let en_route = Events::NOMINAL;
    let reached = Events {
        arrival: Arrival::Reached,
        ..Events::NOMINAL
    };
    // First leg: 4 followed ticks, reached in the 5th; second leg times out.
    let run = [en_route; 4]
        .into_iter()
        .chain([reached])
        .chain([en_route; 5]);
    assert!(check_run(&config(), &shape(), &LEGS, run).is_ok());
    // A specification of a shorter leg limit catches the honest machine.
    let events: Vec<Events> = [en_route; 4]
        .into_iter()
        .chain([reached])
        .chain([en_route; 5])
        .collect();
    let tight = MachineConfig::from_ticks(STALL, LEG + 1).unwrap();
    let violation = check_run(&tight, &shape(), &[1, 2], events).unwrap_err();
    assert_eq!(violation.property, Property::M4TaskBound);
}
