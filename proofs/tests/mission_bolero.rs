//! Bolero harnesses over the real mission machine and supervisor: every
//! sequence of 9 abstract ticks over a compact alphabet, checked
//! exhaustively here (`check!().exhaustive()`), and Kani proofs wherever
//! Kani is installed (`cargo kani -p fieldguide-proofs --tests`); then
//! generated sequences of ticks through the whole supervisor (localisation,
//! planning), whose commands must stop for critical obstacles and lost
//! localisation, never detour in a field, and never reverse.
//!
//! The mission is a road of two legs and a field of one row (a turn and a
//! pass); the stall delay is 3 ticks and the leg time limit 5, so that 9
//! ticks reach every phase.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::atomic::{AtomicU64, Ordering};

use bolero::{check, generator::TypeGenerator};
use fieldguide::perception::obstacles::Hazard;
use fieldguide::supervisor::mission::{
    Arrival, Command, Events, Fault, HazardLevel, LocalisationStatus, MachineConfig, Mission,
    MissionConfig, MissionInput, Row, Shape, Task, TaskKind,
};
use fieldguide::{Meters, Pose2, Robot, World};
use fieldguide_proofs::evidence::{self, Kind};
use fieldguide_proofs::mission::{check_run, Property};

/// Ticks per sequence.
const DEPTH: usize = 9;
/// The properties the harnesses check.
const PROPERTIES: [&str; 5] = [
    "EM-MISSION-M1",
    "EM-MISSION-M2",
    "EM-MISSION-M3",
    "EM-MISSION-M4",
    "EM-MISSION-M5",
];
const LEGS: [u8; 2] = [2, 2];

fn shape() -> Shape {
    Shape::from_legs(&[
        (TaskKind::Approximation, LEGS[0]),
        (TaskKind::Treatment, LEGS[1]),
    ])
}

fn config() -> MachineConfig {
    MachineConfig::from_ticks(3, 5).unwrap()
}

/// One abstract tick of the compact alphabet.
#[derive(Clone, Copy, Debug, TypeGenerator)]
enum Sym {
    /// All well, en route.
    Nominal,
    /// All well, the leg's goal reached.
    Reached,
    /// An obstacle in the critical area, goal reached (both at once).
    CriticalReached,
    /// An obstacle in the warning area with a detour, in a field.
    WarningInField,
    /// An obstacle in the warning area with a detour, on a road.
    WarningOnRoad,
    /// Localisation lost, no progress.
    LostStill,
}

impl Sym {
    fn events(self) -> Events {
        let n = Events::NOMINAL;
        let warning = HazardLevel::Warning { detour: true };
        match self {
            Self::Nominal => n,
            Self::Reached => Events {
                arrival: Arrival::Reached,
                ..n
            },
            Self::CriticalReached => Events {
                hazard: HazardLevel::Critical,
                arrival: Arrival::Reached,
                ..n
            },
            Self::WarningInField => Events {
                hazard: warning,
                in_field: true,
                ..n
            },
            Self::WarningOnRoad => Events {
                hazard: warning,
                ..n
            },
            Self::LostStill => Events {
                localisation: LocalisationStatus::Lost,
                progressing: false,
                ..n
            },
        }
    }
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
/// Every sequence of 6^9 = 10 077 696 abstract ticks through the real step.
#[test]
#[cfg_attr(kani, kani::proof, kani::unwind(10))]
fn every_sequence_keeps_m1_to_m5() {
    let run = evidence::start("mission machine, every 9-tick sequence", Kind::Harness);
    let (config, shape) = (config(), shape());
    let count = AtomicU64::new(0);
    check!()
        .with_type::<[Sym; DEPTH]>()
        .exhaustive()
        .for_each(|sequence| {
            count.fetch_add(1, Ordering::Relaxed);
            let result = check_run(&config, &shape, &LEGS, sequence.iter().map(|s| s.events()));
            assert!(result.is_ok(), "{result:?}");
        });
    run.finish(&evidence::harness(
        &PROPERTIES,
        count.into_inner(),
        u64::try_from(DEPTH).ok(),
    ));
}

/// The mutant that re-plans inside a field fails on some sequence of the
/// same alphabet: the harness would report it.
#[test]
fn the_harness_catches_a_machine_that_replans_in_a_field() {
    let run = evidence::start("mutant ReplanInField, bolero", Kind::Mutant);
    let mutant = config().with_fault(Fault::ReplanInField);
    let failing = [Sym::Nominal, Sym::WarningInField]
        .into_iter()
        .map(Sym::events);
    let violation = check_run(&mutant, &shape(), &LEGS, failing).unwrap_err();
    assert_eq!(violation.property, Property::M2NoReplanInField);
    assert_eq!(violation.tick, 1);
    run.finish(&evidence::mutant_caught(
        "EM-MISSION-M2",
        "Fault::ReplanInField",
    ));
}

/// One tick of the whole supervisor, from a small alphabet.
#[derive(Clone, Copy, Debug, TypeGenerator)]
struct Tick {
    /// Whether the GNSS fix is valid.
    gnss: bool,
    /// Motion this tick: 0 none, 1 straight 5 cm, 2 a turning 2 cm, 3 a 1 m jump.
    motion: u8,
    /// 0 clear, 1 critical, 2 warning with a detour, 3 warning without one.
    hazard: u8,
    /// Whether the robot is in the field.
    in_field: bool,
    /// Whether the pipeline says the leg's end is passed.
    end: bool,
}

fn pose(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

//= spec/emmi2024.md#em-mission-m5-never-backwards
//= type=test
//# In every reachable state, the command MUST be Stop or Follow of a leg no
//# earlier than any leg commanded before, at a speed that is never negative.
//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# A planned leg MUST be forward only: a Dubins path of non-negative segment
//# lengths or a straight line ahead, and the commanded speed MUST never be
//# negative.
//= spec/emmi2024.md#em-loc-stop-lost-localisation-stops
//= type=test
//# While the localisation is Lost the command MUST be Stop with the reason
//# LocalisationLost, and the mission MUST go on from the current leg when a
//# valid fix returns.
/// Generated sequences through the whole supervisor.
#[test]
fn the_supervisor_never_reverses_and_stops_when_it_must() {
    let road = Task::approximation(&[pose(3.0, 0.0, 0.0), pose(6.0, 3.0, 1.5)]).unwrap();
    let row = Row {
        start: pose(6.0, 6.0, 1.5),
        length: Meters::new(4.0).unwrap(),
    };
    let field = Task::treatment(&[
        row,
        Row {
            start: pose(8.0, 10.0, -1.6),
            ..row
        },
    ])
    .unwrap();
    let tasks = [road, field];
    let run = evidence::start(
        "mission supervisor, generated tick sequences",
        Kind::Harness,
    );
    let count = AtomicU64::new(0);
    check!().with_type::<Vec<Tick>>().for_each(|ticks| {
        count.fetch_add(1, Ordering::Relaxed);
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &tasks).unwrap();
        let mut truth = pose(0.0, 0.0, 0.0);
        let mut latest = (0_u8, 0_u8);
        for tick in ticks.iter().take(200) {
            let odometry = match tick.motion % 4 {
                0 => Pose2::<Robot>::new(0.0, 0.0, 0.0),
                1 => Pose2::new(0.05, 0.0, 0.0),
                2 => Pose2::new(0.02, 0.001, 0.1),
                _ => Pose2::new(1.0, 0.0, 0.0),
            }
            .unwrap();
            truth = truth.body_to_frame::<Robot>().apply_pose(odometry).unwrap();
            let hazard = match tick.hazard % 5 {
                0 => Hazard::Clear,
                1 => Hazard::Critical,
                2 => Hazard::Warning {
                    detour: Some(pose(
                        truth.position.x() + 2.0,
                        truth.position.y() + 1.0,
                        0.0,
                    )),
                },
                3 => Hazard::Warning { detour: None },
                _ => Hazard::NoDetourOnRoad,
            };
            let input = MissionInput {
                gnss: tick.gnss.then_some(truth),
                odometry,
                hazard,
                in_field: tick.in_field,
                remaining: tick.end.then_some(Meters::ZERO),
            };
            let out = mission.tick(&input);
            assert!(out.speed.get() >= 0.0);
            match out.command {
                Command::Stop(_) => {
                    assert_eq!(out.speed.get(), 0.0);
                    assert!(out.plan.is_none() && !out.command.tool_on());
                }
                Command::Follow(leg) => {
                    assert!(out.plan.unwrap().is_forward());
                    assert!((leg.task, leg.leg) >= latest);
                    latest = (leg.task, leg.leg);
                    assert!(!(tick.in_field && leg.detour));
                    assert!(hazard != Hazard::Critical && hazard != Hazard::NoDetourOnRoad);
                    assert!(out.fix.pose().is_some());
                }
            }
            if out.fix.pose().is_none() {
                assert!(matches!(out.command, Command::Stop(_)));
            }
        }
    });
    run.finish(&evidence::harness(
        &[
            "EM-MISSION-M5",
            "EM-MISSION-LEGS",
            "EM-LOC-STOP",
            "EM-MISSION-OBSTACLE",
        ],
        count.into_inner(),
        Some(200),
    ));
}
