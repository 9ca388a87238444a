//! Detours that stay on the road (`spec/emmi2024.md`, EM-OBST-ROAD): the
//! corridor's preconditions, every detour on a road checked against an
//! independent oracle of the footprint's corners and the obstacles, the
//! stop when none fits, and the mission's stop while the obstacle is there.
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::float_cmp,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::panic
)]

use fieldguide::perception::obstacles::{
    assess, assess_within, detour, detour_within, Corridor, DetourPlan, Hazard, Obstacle,
    ObstacleConfig, Obstacles, Reason,
};
use fieldguide::planning::dubins::{shortest, TurningRadius};
use fieldguide::supervisor::mission::{
    Command, Mission, MissionConfig, MissionInput, Phase, StopReason, Task,
};
use fieldguide::{Meters, MetersPerSecond, Point2, Pose2, Robot, World};
use proptest::prelude::*;

/// The footprint of `ObstacleConfig::emmi2024`: 0.75 m ahead and behind,
/// 0.88 m either side; its margin.
const HALF_LENGTH: f64 = 0.75;
const HALF_WIDTH: f64 = 0.88;
const MARGIN: f64 = 0.3;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn world(x: f64, y: f64, h: f64) -> Pose2<World> {
    Pose2::new(x, y, h).unwrap()
}

fn config() -> ObstacleConfig {
    ObstacleConfig::emmi2024(TurningRadius::new(m(1.0)).unwrap())
}

fn post(x: f64, y: f64, r: f64) -> Obstacle {
    Obstacle::Circle {
        centre: Point2::<Robot>::new(x, y).unwrap(),
        radius: m(r),
    }
}

fn list(obstacles: &[Obstacle]) -> Obstacles<16> {
    let mut out = Obstacles::new();
    for o in obstacles {
        out.insert(*o);
    }
    out
}

/// A straight road along x from −20 m to 60 m, `half` m either side.
fn road(half: f64) -> Corridor {
    Corridor::new(
        &[
            Point2::new(-20.0, 0.0).unwrap(),
            Point2::new(60.0, 0.0).unwrap(),
        ],
        m(half),
    )
    .unwrap()
}

/// Oracle: the footprint's corners at `pose`.
fn corners(pose: &Pose2<World>) -> [(f64, f64); 4] {
    let (s, c) = pose.heading.get().sin_cos();
    [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)].map(|(u, v)| {
        let (u, v) = (u * HALF_LENGTH, v * HALF_WIDTH);
        (
            pose.position.x() + u * c - v * s,
            pose.position.y() + u * s + v * c,
        )
    })
}

/// Oracle: the least distance between the footprint at `pose` and a circle
/// of the world, by the footprint's own frame.
fn circle_distance(pose: &Pose2<World>, centre: (f64, f64), r: f64) -> f64 {
    let (s, c) = pose.heading.get().sin_cos();
    let (dx, dy) = (centre.0 - pose.position.x(), centre.1 - pose.position.y());
    let (x, y) = (c * dx + s * dy, -s * dx + c * dy);
    let ex = (x.abs() - HALF_LENGTH).max(0.0);
    let ey = (y.abs() - HALF_WIDTH).max(0.0);
    ex.hypot(ey) - r
}

/// Oracle, over both legs `pose → waypoint → goal` sampled every 5 mm: the
/// largest |y| of a footprint corner (the road runs along y = 0) and the
/// least distance to the world circle `(centre, r)`.
fn sweep(
    pose: &Pose2<World>,
    waypoint: &Pose2<World>,
    goal: &Pose2<World>,
    centre: (f64, f64),
    r: f64,
) -> (f64, f64) {
    let (mut widest, mut nearest) = (0.0_f64, f64::INFINITY);
    for (a, b) in [(pose, waypoint), (waypoint, goal)] {
        let leg = shortest(a, b, TurningRadius::new(m(1.0)).unwrap()).unwrap();
        let n = (leg.length().get() / 5e-3).ceil().max(1.0) as usize;
        for i in 0..=n {
            let p = leg
                .pose_at(m(leg.length().get() * i as f64 / n as f64))
                .unwrap();
            for q in corners(&p) {
                widest = widest.max(q.1.abs());
            }
            nearest = nearest.min(circle_distance(&p, centre, r));
        }
    }
    (widest, nearest)
}

//= spec/emmi2024.md#em-obst-road-detours-inside-the-road
//= type=test
//# A corridor MUST be given by 2 to 8 centreline vertices of the world
//# frame, each coordinate within 1e7 m, and a half-width in (0, 1e3] m;
//# other values MUST be refused with the `EM-OBST-ROAD` error.
#[test]
fn corridors_out_of_range_are_refused() {
    let p = |x: f64, y: f64| Point2::<World>::new(x, y).unwrap();
    let refused = |points: &[Point2<World>], half: f64| {
        let e = Corridor::new(points, m(half)).unwrap_err();
        assert_eq!(e.requirement, "EM-OBST-ROAD", "{points:?} {half}");
    };
    refused(&[], 2.0);
    refused(&[p(0.0, 0.0)], 2.0);
    refused(&[p(0.0, 0.0); 9], 2.0);
    refused(&[p(0.0, 0.0), p(2e7, 0.0)], 2.0);
    refused(&[p(0.0, -1.1e7), p(1.0, 0.0)], 2.0);
    // A non-finite half-width is no `Meters` at all.
    assert!(Meters::new(f64::NAN).is_err() && Meters::new(f64::INFINITY).is_err());
    for half in [0.0, -1.0, 1e3 + 1e-9, -1e300] {
        refused(&[p(0.0, 0.0), p(1.0, 0.0)], half);
    }
    let ok = Corridor::new(&[p(0.0, 0.0); 8], m(1e3)).unwrap();
    assert_eq!(ok.half_width().get(), 1e3);
    let ok = Corridor::new(&[p(-1e7, 1e7), p(1e7, -1e7)], m(1e-9)).unwrap();
    assert_eq!(ok.half_width().get(), 1e-9);
}

//= spec/emmi2024.md#em-obst-road-detours-inside-the-road
//= type=test
//# With a corridor, the clearance of EM-OBST-CLEAR MUST be the lesser of
//# the clearance to the obstacles and the room of the pose plus the
//# margin, so that a clear path keeps the whole footprint inside the
//# corridor.
//= spec/emmi2024.md#em-obst-road-detours-inside-the-road
//= type=test
//# The room of a pose MUST be the largest, over the centreline's
//# stretches, of the half-width less the distance from that stretch to
//# the farthest of the footprint's four corners.
//= spec/emmi2024.md#em-obst-road-detours-inside-the-road
//= type=test
//# When no candidate qualifies inside the corridor but one would without
//# it, re-planning MUST report that no detour fits on the road.
/// Posts across roads 3.5-6 m wide (324 scenes): every detour keeps the
/// footprint's corners inside the road and the margin from the
/// post (oracle, 5 mm samples); no detour on the road only when one off it
/// exists; both outcomes occur.
#[test]
fn every_detour_on_a_road_stays_on_it() {
    let start = world(0.0, 0.0, 0.0);
    let goal = world(25.0, 0.0, 0.0);
    let (mut taken, mut stopped) = (0, 0);
    for x in [4.0, 6.0, 8.0] {
        for j in 0..9 {
            let y = -1.2 + 0.3 * f64::from(j);
            for r in [0.05, 0.2, 0.4] {
                for half in [1.75, 2.25, 2.5, 3.0] {
                    let obstacles = [post(x, y, r)];
                    let corridor = road(half);
                    let plan = detour_within(
                        &obstacles[0],
                        &obstacles,
                        &start,
                        &goal,
                        m(4.0),
                        Some(&corridor),
                        &config(),
                    )
                    .unwrap();
                    match plan {
                        DetourPlan::Waypoint(w) => {
                            taken += 1;
                            let (widest, nearest) = sweep(&start, &w, &goal, (x, y), r);
                            assert!(widest <= half + 1e-9, "{widest} on {half}");
                            assert!(nearest >= MARGIN - 1e-9, "{nearest}");
                        }
                        DetourPlan::NoDetourOnRoad => {
                            stopped += 1;
                            let free =
                                detour(&obstacles[0], &obstacles, &start, &goal, m(4.0), &config());
                            assert!(matches!(free, Ok(DetourPlan::Waypoint(_))), "{free:?}");
                        }
                        other => panic!("{other:?}"),
                    }
                }
            }
        }
    }
    println!("detours on the road: {taken} taken, {stopped} stopped (NoDetourOnRoad)");
    assert!(taken > 0 && stopped > 0, "{taken} {stopped}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Without a corridor, and with one too wide to matter, the detour and
    /// the hazard are the paper's (`detour`, `assess`).
    #[test]
    fn without_a_corridor_the_paper_behaviour_is_kept(
        x in 3.5..8.0_f64,
        y in -1.5..1.5_f64,
        r in 0.05..0.4_f64,
        heading in -0.5..0.5_f64,
    ) {
        let start = world(0.0, 0.0, heading);
        let goal = world(25.0, 1.0, 0.0);
        let obstacles = [post(x, y, r)];
        let paper = detour(&obstacles[0], &obstacles, &start, &goal, m(4.0), &config()).unwrap();
        for corridor in [None, Some(&road(1e3))] {
            let plan = detour_within(
                &obstacles[0], &obstacles, &start, &goal, m(4.0), corridor, &config(),
            ).unwrap();
            prop_assert_eq!(plan, paper);
            let speed = MetersPerSecond::new(0.5).unwrap();
            let a = assess_within(&list(&obstacles), &start, &goal, speed, false, corridor, &config());
            let b = assess(&list(&obstacles), &start, &goal, speed, false, &config());
            prop_assert_eq!(a, b);
        }
    }
}

//= spec/emmi2024.md#em-obst-road-detours-inside-the-road
//= type=test
//# When re-planning reports that no detour fits on the road, the
//# hazard MUST be `NoDetourOnRoad`, with the reason
//# `NoDetourOnRoad`.
#[test]
fn a_box_across_a_narrow_road_stops_the_robot_with_its_reason() {
    let start = world(0.0, 0.0, 0.0);
    let goal = world(25.0, 0.0, 0.0);
    let speed = MetersPerSecond::new(0.5).unwrap();
    // A box 0.8 m across in the middle of a 4 m road.
    let obstacles = [Obstacle::Segment {
        start: Point2::new(5.0, -0.4).unwrap(),
        end: Point2::new(5.0, 0.4).unwrap(),
    }];
    // The paper's detour leaves the road: a corner 2 m or more off the centre.
    let free = assess(&list(&obstacles), &start, &goal, speed, false, &config()).unwrap();
    let Hazard::Warning { detour: Some(w) } = free.hazard else {
        panic!("{free:?}");
    };
    let (widest, _) = sweep(&start, &w, &goal, (5.0, 0.0), 0.4);
    assert!(widest > 2.0, "{widest}");
    // On the road: stop, with the reason.
    let corridor = road(2.0);
    let a = assess_within(
        &list(&obstacles),
        &start,
        &goal,
        speed,
        false,
        Some(&corridor),
        &config(),
    )
    .unwrap();
    assert_eq!(a.hazard, Hazard::NoDetourOnRoad);
    assert_eq!(a.reason, Reason::NoDetourOnRoad);
    assert!(a.stops());
    // A road 7 m wide has room: the detour is taken and stays on it.
    let wide = road(3.5);
    let a = assess_within(
        &list(&obstacles),
        &start,
        &goal,
        speed,
        false,
        Some(&wide),
        &config(),
    )
    .unwrap();
    let Hazard::Warning { detour: Some(w) } = a.hazard else {
        panic!("{a:?}");
    };
    let (widest, _) = sweep(&start, &w, &goal, (5.0, 0.0), 0.4);
    assert!(widest <= 3.5 + 1e-9, "{widest}");
}

/// The other outcomes keep their reasons on a road: the goal covered, walls
/// on both sides, a crop field.
#[test]
fn on_a_road_the_other_stops_keep_their_reasons() {
    let start = world(0.0, 0.0, 0.0);
    let goal = world(12.0, 0.0, 0.0);
    let speed = MetersPerSecond::new(0.5).unwrap();
    let corridor = road(2.0);
    let on = |obstacles: &[Obstacle], field: bool| {
        assess_within(
            &list(obstacles),
            &start,
            &goal,
            speed,
            field,
            Some(&corridor),
            &config(),
        )
        .unwrap()
        .reason
    };
    assert_eq!(
        on(&[post(5.0, 0.0, 0.2), post(12.0, 0.0, 0.3)], false),
        Reason::GoalBlocked
    );
    let walls = [
        post(5.0, 0.0, 0.2),
        Obstacle::Segment {
            start: Point2::new(3.0, 1.3).unwrap(),
            end: Point2::new(9.0, 1.3).unwrap(),
        },
        Obstacle::Segment {
            start: Point2::new(3.0, -1.3).unwrap(),
            end: Point2::new(9.0, -1.3).unwrap(),
        },
    ];
    assert_eq!(on(&walls, false), Reason::NoClearSide);
    assert_eq!(on(&[post(5.0, 0.0, 0.2)], true), Reason::InCropField);
}

fn input(gnss: Pose2<World>, odometry: Pose2<Robot>, hazard: Hazard) -> MissionInput {
    MissionInput {
        gnss: Some(gnss),
        odometry,
        hazard,
        in_field: false,
        remaining: None,
    }
}

//= spec/emmi2024.md#em-mission-obstacle-obstacles
//= type=test
//# With the hazard NoDetourOnRoad the command MUST be Stop with the
//# reason NoDetourOnRoad, for as long as the hazard lasts, without
//# re-planning.
#[test]
fn no_detour_on_the_road_holds_the_robot_while_the_obstacle_is_there() {
    for held in [1_usize, 7, 60, 600] {
        let task = Task::approximation(&[world(30.0, 0.0, 0.0)]).unwrap();
        let mut mission = Mission::new(MissionConfig::carob().unwrap(), &[task]).unwrap();
        let at = world(2.0, 0.0, 0.0);
        let still = Pose2::<Robot>::new(0.0, 0.0, 0.0).unwrap();
        let first = mission.tick(&input(at, still, Hazard::Clear));
        let Command::Follow(leg) = first.command else {
            panic!("{first:?}");
        };
        // A person on the road (or a box): stopped for as long as it is
        // there, however long, the leg kept, nothing re-planned.
        for _ in 0..held {
            let out = mission.tick(&input(at, still, Hazard::NoDetourOnRoad));
            assert_eq!(out.command, Command::Stop(StopReason::NoDetourOnRoad));
            assert_eq!(out.phase, Phase::Running);
            assert!(out.plan.is_none() && out.speed.get() == 0.0);
            assert!(!mission.state().detour());
            assert_eq!(mission.state().leg(), (leg.task, leg.leg));
        }
        // The person walked away: the same leg goes on, no detour.
        let out = mission.tick(&input(at, still, Hazard::Clear));
        assert_eq!(out.command, Command::Follow(leg));
        assert_eq!(out.plan, first.plan);
    }
}

//= spec/emmi2024.md#em-mission-legs-the-plan-of-each-leg
//= type=test
//# An Approximation's GoToGoal leg MUST be planned with the road radius,
//# a Treatment's turns and the detours with the turning radius.
#[test]
fn road_corners_turn_on_the_road_radius_and_the_rest_on_the_turning_radius() {
    use fieldguide::supervisor::mission::{Plan, Row};
    let radius_of = |plan: Option<Plan>| match plan {
        Some(Plan::GoToGoal { path, .. }) => path.radius().get(),
        other => panic!("{other:?}"),
    };
    let still = Pose2::<Robot>::new(0.0, 0.0, 0.0).unwrap();
    let base = MissionConfig::carob().unwrap();
    assert_eq!(base.road_radius, base.radius);
    for road in [0.75, 2.0, 4.0] {
        let config = base.with_road_radius(TurningRadius::new(m(road)).unwrap());
        assert_eq!(config.radius, base.radius);
        // A road's 90° corner: GoToGoal on the road radius.
        let corner = Task::approximation(&[world(6.0, 6.0, core::f64::consts::FRAC_PI_2)]).unwrap();
        let row = Row {
            start: world(20.0, 20.0, 0.0),
            length: m(10.0),
        };
        let field = Task::treatment(&[row]).unwrap();
        let mut mission = Mission::new(config, &[corner.clone(), field.clone()]).unwrap();
        let at = world(0.0, 0.0, 0.0);
        let out = mission.tick(&input(at, still, Hazard::Clear));
        assert_eq!(radius_of(out.plan), road);
        // A detour on the road: the turning radius.
        let via = world(3.0, 1.0, 0.5);
        let out = mission.tick(&input(at, still, Hazard::Warning { detour: Some(via) }));
        assert!(matches!(out.command, Command::Follow(l) if l.detour));
        assert_eq!(radius_of(out.plan), 1.5);
        // A Treatment's turn: the turning radius.
        let mut mission = Mission::new(config, &[field]).unwrap();
        let out = mission.tick(&MissionInput {
            in_field: true,
            ..input(at, still, Hazard::Clear)
        });
        assert_eq!(radius_of(out.plan), 1.5);
    }
}
