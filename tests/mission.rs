//! The mission supervisor driven in closed loop by a robot that follows each
//! plan exactly, over seed sweeps of missions, and its rules one by one
//! (`spec/emmi2024.md`, EM-MISSION-* and EM-LOC-*). The machine's
//! properties over every reachable state are in `fieldguide-proofs`.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects,
    clippy::float_cmp,
    clippy::as_conversions
)]

use core::f64::consts::PI;

use fieldguide::perception::obstacles::Hazard;
use fieldguide::supervisor::mission::{
    Command, Fix, Localiser, MachineConfig, Mission, MissionConfig, MissionInput, MissionOutput,
    Phase, Plan, Row, StopReason, Task, TaskKind,
};
use fieldguide::{Meters, Pose2, Robot, Seconds, World};

const DT: f64 = 0.1;

fn pose(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

/// A robot that drives each plan exactly at the commanded speed.
struct Driver {
    pose: Pose2<World>,
    plan: Option<Plan>,
    s: f64,
}

impl Driver {
    fn new(pose: Pose2<World>) -> Self {
        Self {
            pose,
            plan: None,
            s: 0.0,
        }
    }

    /// The remaining distance along the plan followed, as a pipeline reports it.
    fn remaining(&self) -> Option<Meters> {
        self.plan.map(|p| m(p.length().get() - self.s))
    }

    /// Moves along the plan of `out` for one tick; returns the odometry
    /// increment in the robot frame of the previous pose.
    fn drive(&mut self, out: &MissionOutput) -> Pose2<Robot> {
        let before = self.pose;
        if out.plan != self.plan {
            self.plan = out.plan;
            self.s = 0.0;
        }
        if let Some(plan) = self.plan {
            assert!(out.speed.get() >= 0.0);
            self.s = (self.s + out.speed.get() * DT).min(plan.length().get());
            self.pose = match plan {
                Plan::GoToGoal { path, .. } => path.pose_at(m(self.s)).unwrap(),
                Plan::Line { start, goal } => {
                    let len = plan.length().get().max(1e-12);
                    let f = self.s / len;
                    let (dx, dy) = (
                        goal.position.x() - start.position.x(),
                        goal.position.y() - start.position.y(),
                    );
                    pose(
                        start.position.x() + f * dx,
                        start.position.y() + f * dy,
                        libm::atan2(dy, dx),
                    )
                }
            };
        }
        before
            .body_to_frame::<Robot>()
            .inverse()
            .unwrap()
            .apply_pose(self.pose)
            .unwrap()
    }
}

fn input(
    gnss: Option<Pose2<World>>,
    odometry: Pose2<Robot>,
    hazard: Hazard,
    field: bool,
) -> MissionInput {
    MissionInput {
        gnss,
        odometry,
        hazard,
        in_field: field,
        remaining: None,
    }
}

fn still() -> Pose2<Robot> {
    Pose2::new(0.0, 0.0, 0.0).unwrap()
}

/// A small deterministic generator for the seed sweeps.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1_u64 << 53) as f64)
    }
}

/// A road of three waypoints to a field of `rows` serpentine rows.
fn mission_of(seed: u64, rows: usize) -> (Vec<Task>, Vec<Row>) {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let road = [
        pose(rng.uniform(15.0, 25.0), rng.uniform(-1.0, 1.0), 0.0),
        pose(
            rng.uniform(30.0, 35.0),
            rng.uniform(3.0, 6.0),
            rng.uniform(0.0, 0.4),
        ),
        pose(rng.uniform(35.0, 40.0), rng.uniform(20.0, 25.0), PI / 2.0),
    ];
    let spacing = rng.uniform(1.0, 4.0);
    let length = rng.uniform(8.0, 25.0);
    let (x0, y0) = (45.0, 30.0);
    let field: Vec<Row> = (0..rows)
        .map(|k| {
            let y = y0 + spacing * k as f64;
            if k % 2 == 0 {
                Row {
                    start: pose(x0, y, 0.0),
                    length: m(length),
                }
            } else {
                Row {
                    start: pose(x0 + length, y, PI),
                    length: m(length),
                }
            }
        })
        .collect();
    let tasks = vec![
        Task::approximation(&road).unwrap(),
        Task::treatment(&field).unwrap(),
    ];
    (tasks, field)
}

/// Runs `mission` from `start` with GNSS and no obstacle until it is no
/// longer Running; returns the outputs.
fn run(mission: &mut Mission, driver: &mut Driver, ticks: usize) -> Vec<MissionOutput> {
    let mut outputs = Vec::new();
    let mut odometry = still();
    for _ in 0..ticks {
        let (task, _) = mission.state().leg();
        let field = task == 1;
        let out = mission.tick(&MissionInput {
            remaining: driver.remaining(),
            ..input(Some(driver.pose), odometry, Hazard::Clear, field)
        });
        odometry = driver.drive(&out);
        outputs.push(out);
        if out.phase != Phase::Running {
            break;
        }
    }
    outputs
}

//= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
//= type=test
//# Reached MUST end a detour, or else move to the next leg, the next task after
//# a task's last leg, and Done after the last task; no leg and no task MUST be
//# skipped, and the machine MUST never return to an earlier leg.
//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# An Approximation leg MUST be planned with the planner EM-PLANNER chooses from
//# the robot's pose to the waypoint; a Treatment turn MUST be planned with
//# GoToGoal to the row's start, and a pass with LineFollowing along the row with
//# the tool on; the tool MUST be off in every other leg and whenever the command
//# is Stop.
//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# A planned leg MUST be forward only: a Dubins path of non-negative segment
//# lengths or a straight line ahead, and the commanded speed MUST never be
//# negative.
//= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
//= type=test
//# While Running, the command MUST be Follow of the current leg (and detour)
//# unless a rule of EM-MISSION-OBSTACLE, EM-LOC-STOP or EM-MISSION-MONITOR
//# makes it Stop with a reason; Done and Aborted MUST command Stop, Aborted
//# with its reason.
#[test]
fn missions_of_a_road_and_a_field_are_done_leg_by_leg() {
    for seed in 0..24 {
        let rows = 2 + (seed as usize % 5);
        let (tasks, field) = mission_of(seed, rows);
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &tasks).unwrap();
        let mut driver = Driver::new(pose(0.0, 0.0, 0.0));
        let outputs = run(&mut mission, &mut driver, 40_000);
        let last = outputs.last().unwrap();
        assert_eq!(last.phase, Phase::Done, "seed {seed}");
        assert_eq!(last.command, Command::Stop(StopReason::Finished));

        // Every leg, in order, none skipped, none revisited.
        let mut legs: Vec<(u8, u8)> = Vec::new();
        for out in &outputs {
            if let Command::Follow(leg) = out.command {
                assert!(!leg.detour);
                if legs.last() != Some(&(leg.task, leg.leg)) {
                    legs.push((leg.task, leg.leg));
                }
                let plan = out.plan.unwrap();
                assert!(plan.is_forward(), "seed {seed}");
                // The pipeline's reference path ends at the leg's goal.
                if plan.length().get() >= 1e-3 {
                    let path = plan.to_reference_path::<512>(m(0.1)).unwrap();
                    let end = path.vertices().last().unwrap().position;
                    assert!(end.distance_to(plan.goal().position).unwrap().get() < 1e-6);
                    let (a, b) = (path.length().get(), plan.length().get());
                    assert!((a - b).abs() <= 1e-3 * b + 1e-6, "{a} vs {b}");
                }
                assert!(out.speed.get() > 0.0);
                // The tool is on exactly on the passes, which are lines along the row.
                let pass = leg.task == 1 && leg.leg % 2 == 1;
                assert_eq!(leg.tool_on, pass);
                assert_eq!(out.command.tool_on(), pass);
                if leg.task == 1 {
                    let row = field[usize::from(leg.leg / 2)];
                    match plan {
                        Plan::Line { start, .. } => {
                            assert!(pass);
                            assert_eq!(start, row.start);
                        }
                        Plan::GoToGoal { goal, .. } => {
                            assert!(!pass);
                            assert_eq!(goal, row.start);
                        }
                    }
                }
            } else {
                assert!(out.plan.is_none());
                assert_eq!(out.speed.get(), 0.0);
                assert!(!out.command.tool_on());
            }
        }
        let expected: Vec<(u8, u8)> = (0..3)
            .map(|l| (0, l))
            .chain((0..2 * rows as u8).map(|l| (1, l)))
            .collect();
        assert_eq!(legs, expected, "seed {seed}");

        // Ground truth: the robot ends at the end of the last row.
        let row = field[rows - 1];
        let h = row.start.heading.get();
        let end = (
            row.start.position.x() + row.length.get() * h.cos(),
            row.start.position.y() + row.length.get() * h.sin(),
        );
        let miss = (driver.pose.position.x() - end.0).hypot(driver.pose.position.y() - end.1);
        assert!(miss <= 0.05, "seed {seed}: {miss}");
    }
}

//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# An Approximation leg MUST be planned with the planner EM-PLANNER chooses from
//# the robot's pose to the waypoint; a Treatment turn MUST be planned with
//# GoToGoal to the row's start, and a pass with LineFollowing along the row with
//# the tool on; the tool MUST be off in every other leg and whenever the command
//# is Stop.
#[test]
fn road_legs_use_the_45_degree_choice() {
    let near = pose(10.0, 1.0, 0.0); // bearing 5.7°: LineFollowing
    let turn = pose(10.0, 10.0, PI / 2.0); // 90°: GoToGoal
    for (goal, line) in [(near, true), (turn, false)] {
        let task = Task::approximation(&[goal]).unwrap();
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
        let out = mission.tick(&input(
            Some(pose(0.0, 0.0, 0.0)),
            still(),
            Hazard::Clear,
            false,
        ));
        let plan = out.plan.unwrap();
        assert_eq!(matches!(plan, Plan::Line { .. }), line);
        assert_eq!(plan.goal(), goal);
        let speed = if line { 0.5 } else { 0.2 };
        assert_eq!(out.speed.get(), speed);
    }
}

//= spec/emmi2024.md#em-mission-tasks-tasks-and-legs
//= type=test
//# A mission MUST be a list of at most 8 tasks, each an Approximation (at most
//# 16 waypoints, one leg per waypoint, on roads) or a Treatment (at most 16
//# rows, two legs per row: a turn to the row's start, then the pass along it,
//# inside the field); a task with no waypoint or no row MUST be refused with
//# the `EM-MISSION-TASKS` error.
#[test]
fn tasks_are_bounded_and_never_empty() {
    let p = pose(1.0, 0.0, 0.0);
    let row = Row {
        start: p,
        length: m(5.0),
    };
    assert_eq!(
        Task::approximation(&[]).unwrap_err().requirement,
        "EM-MISSION-TASKS"
    );
    assert_eq!(
        Task::treatment(&[]).unwrap_err().requirement,
        "EM-MISSION-TASKS"
    );
    assert!(Task::approximation(&[p; 17]).is_err());
    assert!(Task::treatment(&[row; 17]).is_err());
    let short = Row {
        start: p,
        length: m(1e-4),
    };
    assert!(Task::treatment(&[short]).is_err());
    let a = Task::approximation(&[p; 16]).unwrap();
    let t = Task::treatment(&[row; 16]).unwrap();
    assert_eq!((a.kind(), a.legs()), (TaskKind::Approximation, 16));
    assert_eq!((t.kind(), t.legs()), (TaskKind::Treatment, 32));
    let config = MissionConfig::carob().unwrap();
    let nine = vec![a.clone(); 9];
    assert_eq!(
        Mission::new(config, &nine).unwrap_err().requirement,
        "EM-MISSION-TASKS"
    );
    assert!(Mission::new(config, &nine[..8]).is_ok());
}

//= spec/emmi2024.md#em-mission-monitor-malfunctions
//= type=test
//# The delays MUST be positive and converted once to ticks n = ⌈delay /
//# period⌉, at most 65 535, and the tolerance and the longest leg MUST be
//# positive; other values MUST be refused with the `EM-MISSION-CONFIG` error.
#[test]
fn the_configuration_is_checked() {
    let s = |v| Seconds::new(v).unwrap();
    let c = MachineConfig::new(s(0.1), s(10.0), s(600.0)).unwrap();
    assert_eq!((c.stall_ticks(), c.leg_ticks()), (100, 6000));
    assert_eq!(
        MachineConfig::new(s(0.1), s(0.25), s(1.0))
            .unwrap()
            .stall_ticks(),
        3
    );
    for (p, a, b) in [
        (0.0, 1.0, 1.0),
        (0.1, 0.0, 1.0),
        (0.1, 1.0, -1.0),
        (0.001, 1.0, 100.0),
    ] {
        let e = MachineConfig::new(s(p), s(a), s(b)).unwrap_err();
        assert_eq!(e.requirement, "EM-MISSION-CONFIG");
    }
    assert!(MachineConfig::from_ticks(0, 5).is_err());
    let carob = MissionConfig::carob().unwrap();
    let speeds = (carob.cruise_speed, carob.turn_speed);
    for (tol, longest, odo) in [(0.0, 1.0, 1.0), (0.1, 0.0, 1.0), (0.1, 1.0, -1.0)] {
        let e = MissionConfig::new(c, m(tol), m(longest), m(odo), carob.radius, speeds);
        assert_eq!(e.unwrap_err().requirement, "EM-MISSION-CONFIG");
    }
}

//= spec/emmi2024.md#em-loc-choice-gnss-or-odometry
//= type=test
//# The pose MUST be the GNSS fix while it is valid; without a valid fix, the
//# last valid fix moved by the odometry increments since, as long as the
//# distance driven since that fix is at most the configured odometry
//# distance; beyond it, or before any valid fix, the localisation MUST be
//# Lost.
#[test]
fn odometry_bridges_a_bounded_distance_from_the_last_fix() {
    for seed in 0..16 {
        let mut rng = Rng(seed * 7919 + 3);
        let limit = rng.uniform(1.0, 6.0);
        let mut loc = Localiser::new(m(limit));
        // Before any fix: Lost.
        assert_eq!(loc.update(None, &still()), Fix::Lost);
        // The true robot drives an arc; odometry reports exact increments.
        let mut truth = pose(
            rng.uniform(-50.0, 50.0),
            rng.uniform(-50.0, 50.0),
            rng.uniform(-3.0, 3.0),
        );
        assert_eq!(loc.update(Some(truth), &still()), Fix::Gnss(truth));
        let step = Pose2::<Robot>::new(0.05, 0.0, rng.uniform(-0.02, 0.02)).unwrap();
        let mut driven = 0.0;
        for _ in 0..200 {
            truth = truth.body_to_frame::<Robot>().apply_pose(step).unwrap();
            driven += 0.05;
            match loc.update(None, &step) {
                Fix::Odometry { pose: p, driven: d } => {
                    assert!(driven <= limit + 1e-9);
                    assert!((d.get() - driven).abs() < 1e-9);
                    let err = (p.position.x() - truth.position.x())
                        .hypot(p.position.y() - truth.position.y());
                    assert!(err < 1e-6, "{err}");
                }
                Fix::Lost => assert!(driven > limit - 1e-9),
                Fix::Gnss(_) => panic!("no fix was given"),
            }
        }
        // Lost stays lost without a fix, even standing still; a fix restores it.
        assert_eq!(loc.update(None, &still()), Fix::Lost);
        assert_eq!(
            loc.update(Some(truth), &still()).status(),
            fieldguide::supervisor::mission::LocalisationStatus::Gnss
        );
        assert!(matches!(loc.update(None, &step), Fix::Odometry { .. }));
    }
}

/// A mission on a road from the origin to (30, 0) and the first output.
fn straight_road() -> (Mission, Driver) {
    let task = Task::approximation(&[pose(30.0, 0.0, 0.0)]).unwrap();
    let mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
    (mission, Driver::new(pose(0.0, 0.0, 0.0)))
}

//= spec/emmi2024.md#em-loc-stop-lost-localisation-stops
//= type=test
//# While the localisation is Lost the command MUST be Stop with the reason
//# LocalisationLost, and the mission MUST go on from the current leg when a
//# valid fix returns.
#[test]
fn lost_localisation_stops_and_the_leg_goes_on_after_a_fix() {
    let (mut mission, mut driver) = straight_road();
    let mut odometry = still();
    // 5 m of odometry at 0.05 m per tick: 100 ticks with odometry, then Lost.
    let mut lost_at = None;
    for tick in 0..150 {
        let gnss = if tick < 10 { Some(driver.pose) } else { None };
        let out = mission.tick(&input(gnss, odometry, Hazard::Clear, false));
        if out.command == Command::Stop(StopReason::LocalisationLost) {
            lost_at.get_or_insert(tick);
            assert_eq!(out.phase, Phase::Running);
            assert!(out.plan.is_none());
        } else {
            assert!(lost_at.is_none(), "tick {tick}: {out:?}");
        }
        odometry = driver.drive(&out);
    }
    let lost_at = lost_at.unwrap();
    // 9 ticks of motion with GNSS (0.45 m), then 5 m of odometry.
    assert!((108..=112).contains(&lost_at), "{lost_at}");
    let out = mission.tick(&input(Some(driver.pose), still(), Hazard::Clear, false));
    assert!(matches!(out.command, Command::Follow(l) if (l.task, l.leg) == (0, 0)));
}

//= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
//= type=test
//# In each tick it MUST read the events: the hazard (Clear, Warning with or
//# without a detour, Critical), whether the robot is inside the task's field,
//# the localisation (GNSS, odometry, Lost), whether the leg's plan exists,
//# whether the robot progressed, and the arrival (en route, reached within the
//# tolerance, missed).
//= spec/emmi2024.md#em-mission-obstacle-obstacles
//= type=test
//# With the hazard Critical the command MUST be Stop with the reason Obstacle,
//# for as long as the hazard lasts.
#[test]
fn a_critical_obstacle_stops_for_as_long_as_it_is_there() {
    for seed in 0..8_u64 {
        let (mut mission, mut driver) = straight_road();
        let mut odometry = still();
        let (from, to) = (5 + seed as usize * 3, 30 + seed as usize * 20);
        for tick in 0..60 + seed as usize * 20 {
            let hazard = if (from..to).contains(&tick) {
                Hazard::Critical
            } else {
                Hazard::Clear
            };
            let out = mission.tick(&input(Some(driver.pose), odometry, hazard, false));
            if hazard == Hazard::Critical {
                assert_eq!(out.command, Command::Stop(StopReason::Obstacle));
                assert_eq!(out.speed.get(), 0.0);
            } else {
                assert!(matches!(out.command, Command::Follow(_)), "{tick}");
            }
            assert_eq!(out.phase, Phase::Running);
            odometry = driver.drive(&out);
        }
    }
}

//= spec/emmi2024.md#em-mission-obstacle-obstacles
//= type=test
//# With the hazard Warning on a road, the machine MUST re-plan the leg through
//# the detour waypoint, and stop with the reason NoDetour when there is none;
//# inside a field it MUST NOT re-plan but stop with the reason ObstacleInField.
//= spec/emmi2024.md#em-mission-obstacle-obstacles
//= type=test
//# A detour MUST end when its waypoint is reached, the leg being planned again
//# from there to its goal, and a detour MUST be dropped when the robot is in a
//# field.
#[test]
fn a_warning_detours_on_roads_and_stops_in_fields() {
    let goal = pose(30.0, 0.0, 0.0);
    let via = pose(12.0, 3.0, 0.0);
    let warning = Hazard::Warning { detour: Some(via) };
    // In a field: stop, never a detour, whatever the detour offered.
    let (mut mission, mut driver) = straight_road();
    let mut odometry = still();
    for tick in 0..40 {
        let hazard = if tick >= 10 { warning } else { Hazard::Clear };
        let out = mission.tick(&input(Some(driver.pose), odometry, hazard, true));
        if tick >= 10 {
            assert_eq!(out.command, Command::Stop(StopReason::ObstacleInField));
        }
        odometry = driver.drive(&out);
    }
    // No detour on a road: stop with NoDetour.
    let (mut mission, driver) = straight_road();
    mission.tick(&input(Some(driver.pose), still(), Hazard::Clear, false));
    let out = mission.tick(&input(
        Some(driver.pose),
        still(),
        Hazard::Warning { detour: None },
        false,
    ));
    assert_eq!(out.command, Command::Stop(StopReason::NoDetour));

    // On a road: re-plan to the detour waypoint with GoToGoal, reach it, then
    // the leg is planned again from there to its goal, and the goal is reached.
    let (mut mission, mut driver) = straight_road();
    let mut odometry = still();
    let mut phases = Vec::new();
    for tick in 0..3000 {
        let hazard = if (20..25).contains(&tick) {
            warning
        } else {
            Hazard::Clear
        };
        let out = mission.tick(&MissionInput {
            remaining: driver.remaining(),
            ..input(Some(driver.pose), odometry, hazard, false)
        });
        if let Command::Follow(leg) = out.command {
            let plan = out.plan.unwrap();
            if leg.detour {
                assert!(matches!(plan, Plan::GoToGoal { .. }));
                assert_eq!(plan.goal(), via);
            } else {
                assert_eq!(plan.goal(), goal);
            }
            if phases.last() != Some(&leg.detour) {
                phases.push(leg.detour);
            }
        }
        odometry = driver.drive(&out);
        if out.phase == Phase::Done {
            break;
        }
    }
    assert_eq!(phases, [false, true, false]);
    assert_eq!(mission.state().phase(), Phase::Done);
    let miss = driver
        .pose
        .position
        .distance_to(goal.position)
        .unwrap()
        .get();
    assert!(miss <= 0.05, "{miss}");
}

//= spec/emmi2024.md#em-mission-obstacle-obstacles
//= type=test
//# A detour MUST be planned once per obstacle: the machine MUST ask for a
//# plan only when the leg or the detour changes, and while a detour is
//# followed a further warning MUST NOT re-plan it unless its waypoint lies
//# farther than the tolerance from the one followed.
#[test]
fn a_detour_is_planned_once_per_obstacle() {
    for seed in 0..8_u64 {
        let mut rng = Rng(seed * 7_919 + 5);
        let goal = pose(30.0, 0.0, 0.0);
        let (mut mission, mut driver) = straight_road();
        let mut odometry = still();
        let mut detour_plans: Vec<Plan> = Vec::new();
        let mut followed = Vec::new();
        for tick in 0..3000 {
            // One obstacle seen for 30 ticks, its waypoint jittering by up
            // to 5 cm (scan noise); from tick 60, for 10 ticks, a second one
            // whose waypoint lies 1 m further on.
            let hazard = match tick {
                20..50 => Hazard::Warning {
                    detour: Some(pose(
                        12.0 + rng.uniform(-0.05, 0.05),
                        3.0 + rng.uniform(-0.05, 0.05),
                        0.0,
                    )),
                },
                60..70 if mission.state().detour() => Hazard::Warning {
                    detour: Some(pose(13.0, 3.0, 0.0)),
                },
                _ => Hazard::Clear,
            };
            let out = mission.tick(&MissionInput {
                remaining: driver.remaining(),
                ..input(Some(driver.pose), odometry, hazard, false)
            });
            if let (Command::Follow(leg), Some(plan)) = (out.command, out.plan) {
                if leg.detour && detour_plans.last() != Some(&plan) {
                    detour_plans.push(plan);
                }
                followed.push(leg.detour);
            }
            odometry = driver.drive(&out);
            if out.phase == Phase::Done {
                break;
            }
        }
        assert_eq!(mission.state().phase(), Phase::Done, "seed {seed}");
        // The first waypoint as first seen, then the moved one: two plans.
        assert_eq!(detour_plans.len(), 2, "seed {seed}: {detour_plans:?}");
        assert!((detour_plans[0].goal().position.x() - 12.0).abs() <= 0.05);
        assert_eq!(detour_plans[1].goal(), pose(13.0, 3.0, 0.0));
        assert!(
            driver
                .pose
                .position
                .distance_to(goal.position)
                .unwrap()
                .get()
                <= 0.05
        );
    }
}

//= spec/emmi2024.md#em-mission-monitor-malfunctions
//= type=test
//# While Follow is commanded, a run of ticks without progress as long as the
//# stall delay MUST abort the mission with the reason NoProgress, and a leg
//# followed for the leg time limit without being reached MUST abort it with the
//# reason LegTimeout.
//= spec/emmi2024.md#em-mission-monitor-malfunctions
//= type=test
//# A leg whose end is passed without its goal being within the tolerance MUST
//# abort the mission with the reason GoalMissed.
#[test]
fn malfunctions_abort_with_their_reason() {
    // A robot that does not move: NoProgress after 10 s = 100 ticks.
    let (mut mission, driver) = straight_road();
    let reasons: Vec<_> = (0..120)
        .map(|_| mission.tick(&input(Some(driver.pose), still(), Hazard::Clear, false)))
        .collect();
    assert!(reasons[..99]
        .iter()
        .all(|o| matches!(o.command, Command::Follow(_))));
    assert_eq!(reasons[99].command, Command::Stop(StopReason::NoProgress));
    assert!(reasons[99..]
        .iter()
        .all(|o| o.phase == Phase::Aborted(StopReason::NoProgress)));

    // A robot that crawls: LegTimeout after 600 s = 6000 ticks.
    let (mut mission, _) = straight_road();
    let crawl = Pose2::<Robot>::new(0.002, 0.0, 0.0).unwrap();
    let mut truth = pose(0.0, 0.0, 0.0);
    let mut out = None;
    for tick in 0..6100 {
        let o = mission.tick(&input(Some(truth), crawl, Hazard::Clear, false));
        truth = pose(truth.position.x() + 0.002, 0.0, 0.0);
        if o.phase != Phase::Running {
            out = Some((tick, o));
            break;
        }
    }
    let (tick, o) = out.unwrap();
    assert_eq!(tick, 5999);
    assert_eq!(o.command, Command::Stop(StopReason::LegTimeout));

    // A robot 0.1 m beside the line reaches its goal when the pipeline says
    // the end is passed; 0.3 m beside, it misses it (tolerance 0.25 m).
    for (offset, arrival) in [
        (0.1, Phase::Done),
        (0.3, Phase::Aborted(StopReason::GoalMissed)),
    ] {
        let (mut mission, _) = straight_road();
        let mut x = 0.0;
        let mut last = None;
        let step = Pose2::<Robot>::new(0.05, 0.0, 0.0).unwrap();
        for _ in 0..700 {
            let o = mission.tick(&MissionInput {
                remaining: Some(m(30.0 - x)),
                ..input(Some(pose(x, offset, 0.0)), step, Hazard::Clear, false)
            });
            last = Some((x, o));
            if o.phase != Phase::Running {
                break;
            }
            x += 0.05;
        }
        let (x, o) = last.unwrap();
        assert_eq!(o.phase, arrival);
        assert!((29.94..30.0).contains(&x), "{x}");
    }
    // Without the pipeline's distance, 0.3 m beside: missed once driven past
    // the length by twice the tolerance.
    let (mut mission, _) = straight_road();
    let mut x = 0.0;
    let mut last = None;
    let step = Pose2::<Robot>::new(0.05, 0.0, 0.0).unwrap();
    for _ in 0..700 {
        let o = mission.tick(&input(Some(pose(x, 0.3, 0.0)), step, Hazard::Clear, false));
        last = Some((x, o));
        if o.phase != Phase::Running {
            break;
        }
        x += 0.05;
    }
    let (x, o) = last.unwrap();
    assert_eq!(o.phase, Phase::Aborted(StopReason::GoalMissed));
    assert!(x > 30.5 && x < 30.6, "{x}");
}

//= spec/emmi2024.md#em-mission-monitor-malfunctions
//= type=test
//# The end of a leg MUST count as passed when the pipeline's remaining
//# distance along it is at most the speed profile's reach distance
//# (EM-SPEED-REACH), and a tolerance not above that reach distance MUST be
//# refused with the `EM-MISSION-CONFIG` error.
#[test]
fn the_end_of_a_leg_is_judged_at_the_reach_distance_inside_the_tolerance() {
    let carob = MissionConfig::carob().unwrap();
    let speeds = (carob.cruise_speed, carob.turn_speed);
    for tol in [0.01, 0.05] {
        let e = MissionConfig::new(
            carob.machine,
            m(tol),
            m(500.0),
            m(5.0),
            carob.radius,
            speeds,
        );
        assert_eq!(e.unwrap_err().requirement, "EM-MISSION-CONFIG", "{tol}");
    }
    // The simulator's tolerance, 0.15 m: the end is passed at 0.05 m, not at
    // the tolerance's edge.
    let config = MissionConfig::new(
        carob.machine,
        m(0.15),
        m(500.0),
        m(5.0),
        carob.radius,
        speeds,
    )
    .unwrap();
    assert_eq!(config.reach_distance, m(0.05));
    // A robot whose pose runs 0.03 m beside and 0.02 m behind what the
    // pipeline's distance says (two estimates of one robot): the end is
    // judged once 0.05 m remain, the goal 0.07 m away, reached; judged at
    // the tolerance (0.15 m remaining) it would be 0.17 m away, missed.
    for lag in [0.0, 0.02, 0.04] {
        let task = Task::approximation(&[pose(30.0, 0.0, 0.0)]).unwrap();
        let mut mission = Mission::new(config, &[task]).unwrap();
        let step = Pose2::<Robot>::new(0.01, 0.0, 0.0).unwrap();
        let mut x = 0.0;
        let mut judged = None;
        for _ in 0..4000 {
            let o = mission.tick(&MissionInput {
                remaining: Some(m(30.0 - x)),
                ..input(Some(pose(x - lag, 0.03, 0.0)), step, Hazard::Clear, false)
            });
            if o.phase != Phase::Running {
                judged = Some((x, o.phase));
                break;
            }
            x += 0.01;
        }
        let (x, phase) = judged.unwrap();
        assert_eq!(phase, Phase::Done, "lag {lag}");
        assert!(30.0 - x <= 0.05 + 1e-9 && 30.0 - x > 0.03, "lag {lag}: {x}");
    }
}

//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# A leg whose goal is within the tolerance of the pose it is planned from,
//# with a heading change below the planner threshold, MUST count as reached
//# in the next tick, its path not followed.
#[test]
fn a_leg_planned_at_its_goal_is_reached_without_a_loop() {
    let row = Row {
        start: pose(10.0, 5.0, 0.0),
        length: m(12.0),
    };
    // The robot stands 1 cm past, on, or 4 cm short of the row's start (where
    // a road ended): the turn to it is reached at once, not a loop.
    for past in [0.01, 0.0, -0.04] {
        let task = Task::treatment(&[row]).unwrap();
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
        let here = Some(pose(10.0 + past, 5.0, 0.02));
        let first = mission.tick(&input(here, still(), Hazard::Clear, true));
        assert_eq!(mission.state().leg(), (0, 0), "{past}");
        // The Dubins path to the row's start from 1 cm past it is a loop.
        if past > 0.0 {
            assert!(first.plan.unwrap().length().get() > 4.0, "{past}");
        }
        let second = mission.tick(&MissionInput {
            remaining: first.plan.map(|p| p.length()),
            ..input(here, still(), Hazard::Clear, true)
        });
        assert_eq!(mission.state().leg(), (0, 1), "{past}");
        assert!(matches!(second.plan, Some(Plan::Line { .. })), "{past}");
        assert!(second.command.tool_on(), "{past}");
    }
    // 0.5 m short, or facing across: the turn is driven.
    for here in [pose(9.5, 5.0, 0.0), pose(10.0, 5.0, 1.0)] {
        let task = Task::treatment(&[row]).unwrap();
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
        let first = mission.tick(&input(Some(here), still(), Hazard::Clear, true));
        let _ = mission.tick(&MissionInput {
            remaining: first.plan.map(|p| p.length()),
            ..input(Some(here), still(), Hazard::Clear, true)
        });
        assert_eq!(mission.state().leg(), (0, 0));
    }
}

//= spec/emmi2024.md#em-mission-monitor-malfunctions
//= type=test
//# The progress of a tick and the distance driven on a leg MUST be taken
//# from the odometry increments, never from differences of localised poses,
//# so that the noise of a standing robot's fix is neither progress nor
//# distance.
#[test]
fn a_standing_robot_on_a_noisy_fix_neither_progresses_nor_drives() {
    for seed in 0..8_u64 {
        let mut rng = Rng(seed * 104_729 + 11);
        // A short leg of 1 m, the robot 0.3 m from its goal, standing on a
        // fix with 2 cm of noise: the sum of the fixes' jumps would pass
        // 1 m + twice the tolerance in under 100 ticks.
        let task = Task::approximation(&[pose(1.0, 0.0, 0.0)]).unwrap();
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
        let mut outs = Vec::new();
        for _ in 0..120 {
            let noisy = pose(
                0.7 + rng.uniform(-0.02, 0.02),
                rng.uniform(-0.02, 0.02),
                0.0,
            );
            outs.push(mission.tick(&input(Some(noisy), still(), Hazard::Clear, false)));
        }
        // Never missed; no progress for the stall delay (100 ticks) aborts.
        assert!(
            outs[..99].iter().all(|o| o.phase == Phase::Running),
            "seed {seed}"
        );
        assert_eq!(
            outs[99].phase,
            Phase::Aborted(StopReason::NoProgress),
            "seed {seed}"
        );
        // The same robot held by a critical obstacle (no Follow, so no
        // stall) waits as long as it must, and its leg is never missed.
        let task = Task::approximation(&[pose(1.0, 0.0, 0.0)]).unwrap();
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
        for _ in 0..3000 {
            let noisy = pose(
                0.7 + rng.uniform(-0.02, 0.02),
                rng.uniform(-0.02, 0.02),
                0.0,
            );
            let o = mission.tick(&input(Some(noisy), still(), Hazard::Critical, false));
            assert_eq!(o.command, Command::Stop(StopReason::Obstacle));
            assert_eq!(o.phase, Phase::Running);
        }
        // Then it drives on by odometry and reaches the goal.
        let mut x = 0.7;
        let step = Pose2::<Robot>::new(0.05, 0.0, 0.0).unwrap();
        let mut done = false;
        for _ in 0..40 {
            let o = mission.tick(&input(Some(pose(x, 0.0, 0.0)), step, Hazard::Clear, false));
            if o.phase == Phase::Done {
                done = true;
                break;
            }
            x += 0.05;
        }
        assert!(done, "seed {seed}");
    }
}

//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# A leg that cannot be planned, or whose path is longer than the configured
//# longest leg (a goal unreachable with the turning radius), MUST stop the
//# mission with the reason Unplannable.
//= spec/emmi2024.md#em-mission-machine-states-events-and-transitions
//= type=test
//# The machine MUST have the phases Running, Done and Aborted, and start
//# Running at the first leg of the first task, or Aborted with the reason
//# EmptyMission when the mission has no task.
/// Bad input: a defined Stop with a named reason, no panic, no task skipped.
#[test]
fn bad_missions_stop_with_a_reason() {
    let config = MissionConfig::carob().unwrap();
    let here = Some(pose(0.0, 0.0, 0.0));
    // No task.
    let mut empty = Mission::new(config, &[]).unwrap();
    for _ in 0..5 {
        let out = empty.tick(&input(here, still(), Hazard::Clear, false));
        assert_eq!(out.command, Command::Stop(StopReason::EmptyMission));
        assert_eq!(out.phase, Phase::Aborted(StopReason::EmptyMission));
    }
    // A goal farther than the longest leg (500 m), then a task after it that
    // must not be reached: the mission stops on the first.
    let far = Task::approximation(&[pose(2000.0, 0.0, 0.0)]).unwrap();
    let near = Task::approximation(&[pose(5.0, 0.0, 0.0)]).unwrap();
    let mut mission = Mission::new(config, &[far, near]).unwrap();
    let first = mission.tick(&input(here, still(), Hazard::Clear, false));
    assert_eq!(first.command, Command::Stop(StopReason::Unplannable));
    for _ in 0..5 {
        let out = mission.tick(&input(here, still(), Hazard::Clear, false));
        assert_eq!(out.command, Command::Stop(StopReason::Unplannable));
        assert_eq!(out.phase, Phase::Aborted(StopReason::Unplannable));
        assert_eq!(mission.state().leg(), (0, 0));
    }
    // A U-turn to a row beside the robot needs a loop (spacing 0.5 m < 2 r):
    // with a longest leg of 5 m it cannot be planned.
    let short = MissionConfig {
        longest_leg: m(5.0),
        ..config
    };
    let row = Row {
        start: pose(0.0, 0.5, PI),
        length: m(10.0),
    };
    let mut mission = Mission::new(short, &[Task::treatment(&[row]).unwrap()]).unwrap();
    let out = mission.tick(&input(here, still(), Hazard::Clear, true));
    assert_eq!(out.command, Command::Stop(StopReason::Unplannable));
    // An obstacle inside the footprint at start (critical), obstacles on every
    // side (no detour), an obstacle covering the goal (no detour): Stop.
    for (hazard, reason) in [
        (Hazard::Critical, StopReason::Obstacle),
        (Hazard::Warning { detour: None }, StopReason::NoDetour),
    ] {
        let (mut mission, _) = straight_road();
        for _ in 0..5 {
            let out = mission.tick(&input(here, still(), hazard, false));
            assert_eq!(out.command, Command::Stop(reason));
            assert_eq!(out.phase, Phase::Running);
        }
    }
    // No fix at start: Stop, LocalisationLost.
    let (mut mission, _) = straight_road();
    let out = mission.tick(&input(None, still(), Hazard::Clear, false));
    assert_eq!(out.command, Command::Stop(StopReason::LocalisationLost));
}

/// A task of no leg (possible only in a hand-made shape) stops the mission
/// when it is reached: the task after it is never started.
#[test]
fn a_task_of_no_leg_aborts_and_nothing_is_skipped() {
    use fieldguide::supervisor::mission::{step, Arrival, Events, MissionState, Shape};
    let shape = Shape::from_legs(&[
        (TaskKind::Approximation, 1),
        (TaskKind::Treatment, 0),
        (TaskKind::Approximation, 1),
    ]);
    let config = MachineConfig::from_ticks(10, 10).unwrap();
    let state = MissionState::initial(&shape);
    let (state, out) = step(&config, &shape, &state, &Events::NOMINAL);
    assert!(matches!(out.command, Command::Follow(l) if (l.task, l.leg) == (0, 0)));
    let reached = Events {
        arrival: Arrival::Reached,
        ..Events::NOMINAL
    };
    let (mut state, out) = step(&config, &shape, &state, &reached);
    assert_eq!(out.command, Command::Stop(StopReason::EmptyTask));
    for _ in 0..20 {
        let (next, out) = step(&config, &shape, &state, &reached);
        assert_eq!(out.phase, Phase::Aborted(StopReason::EmptyTask));
        assert_eq!(next.leg(), (1, 0));
        state = next;
    }
    let empty_first = Shape::from_legs(&[(TaskKind::Treatment, 0)]);
    assert_eq!(
        MissionState::initial(&empty_first).phase(),
        Phase::Aborted(StopReason::EmptyTask)
    );
}
