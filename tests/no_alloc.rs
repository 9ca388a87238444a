//! The core allocates nothing on the heap per tick (`spec/library.md`,
//! LIB-NO-ALLOC): a counting global allocator watches the calls a vehicle
//! stack makes every control period.
//!
//! This test crate needs `unsafe` to implement `GlobalAlloc`; the core itself
//! forbids it.
#![allow(
    unsafe_code,
    clippy::unwrap_used,
    clippy::arithmetic_side_effects,
    clippy::std_instead_of_core
)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use fieldguide::control::backstepping::{steering_command, BacksteppingConfig, Gains, Inversion};
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::guidance::{Guidance, GuidanceConfig, Mode, RoutedScan, TickInput};
use fieldguide::model::bicycle::{world_rates, Bicycle, Sideslip, SteeringLimit, Wheelbase};
use fieldguide::perception::edge::{EdgeConfig, EdgeDetector, EdgeDetectorConfig, Side};
use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector, FurrowParams};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::presets::{pierre2022_both, Pierre2022, EDGE, FURROW};
use fieldguide::supervisor::switching::{
    BehaviourConfig, Input, Report, Switching, SwitchingConfig,
};
use fieldguide::{
    Meters, MetersPerSecond, Odom, Point2, Pose2, Radians, Robot, Seconds, Sensor, TrackingError,
    Transform2, World,
};

struct Counting;

// Both the switch and the counter are per thread: tests run in parallel, and
// another test's allocations must not be counted in this one's section.
thread_local! {
    static WATCHING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

/// Counts one allocation if this thread is watching.
fn count_one() {
    if WATCHING.with(Cell::get) {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
    }
}

// SAFETY: every call is forwarded unchanged to the system allocator; the
// wrapper only counts, and the const-initialised thread-locals cannot allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count_one();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count_one();
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `f` and returns how many heap allocations this thread made inside it.
fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    WATCHING.with(|w| w.set(true));
    f();
    WATCHING.with(|w| w.set(false));
    ALLOCATIONS.with(Cell::get) - before
}

//= spec/library.md#lib-no-alloc-no-allocation
//= type=test
//# The core MUST be `no_std` and MUST NOT allocate on the heap: buffers have a
//# fixed capacity, and a full buffer is a returned value, not a panic.
#[test]
fn path_tracking_tick_does_not_allocate() {
    // The counter works: a Vec allocates.
    assert_eq!(
        allocations_in(|| drop(std::hint::black_box(vec![1u8; 8]))),
        1
    );

    let waypoints: Vec<Point2<World>> = (0..400)
        .map(|i| {
            let s = f64::from(i) * 0.1;
            Point2::new(s, 2.0 * (s / 10.0).sin()).unwrap()
        })
        .collect();
    let config = BacksteppingConfig {
        gains: Gains::new(-0.7, -1.4, 2.0).unwrap(),
        vehicle: Bicycle::new(
            Wheelbase::new(2.0).unwrap(),
            SteeringLimit::new(0.6).unwrap(),
            None,
        )
        .unwrap(),
        inversion: Inversion::Exact,
        schedule: None,
    };
    let speed = MetersPerSecond::new(0.8).unwrap();
    let slip = Sideslip::new(-0.03, -0.05).unwrap();

    let mut steered = 0;
    let count = allocations_in(|| {
        // Building the path is part of the watched section too: fixed capacity.
        let path = ReferencePath::<512>::from_waypoints(&waypoints, PathConfig::default()).unwrap();
        let mut pose = Pose2::<World>::new(0.0, 0.8, 0.0).unwrap();
        let mut s_hint = Meters::ZERO;
        for _ in 0..200 {
            let frenet = path
                .project_near(
                    &pose,
                    Meters::new(0.8).unwrap(),
                    s_hint,
                    Meters::new(3.0).unwrap(),
                )
                .unwrap();
            s_hint = frenet.s;
            let cmd = steering_command(&config, &TrackingError::from(frenet), slip, speed).unwrap();
            let rates =
                world_rates(&pose, speed, cmd.steering, slip, config.vehicle.wheelbase).unwrap();
            pose = Pose2::new(
                pose.position.x() + 0.05 * rates.x_dot,
                pose.position.y() + 0.05 * rates.y_dot,
                pose.heading.get() + 0.05 * rates.heading_dot,
            )
            .unwrap();
            steered += 1;
        }
    });
    assert_eq!(steered, 200);
    assert_eq!(
        count, 0,
        "the per-tick path tracking calls allocated {count} times"
    );
}

/// The two synthetic scans of the allocation tests, built before counting:
/// horizontal, 360 rays over a full turn with a wall along y = 1.5 m;
/// inclined, 360 rays over ±0.6 rad with bumps every 40 rays. Returns
/// (horizontal increment, horizontal ranges, inclined increment, inclined ranges).
fn scans() -> (f64, Vec<f64>, f64, Vec<f64>) {
    let step = 2.0 * std::f64::consts::PI / 360.0;
    let wall = (0..360)
        .map(|k| {
            let angle = -std::f64::consts::PI + step * f64::from(k);
            if angle.sin() > 0.05 {
                1.5 / angle.sin()
            } else {
                f64::NAN
            }
        })
        .collect();
    let ridges = (0..360)
        .map(|k| if (k / 8) % 5 == 0 { 2.4 } else { 2.7 })
        .collect();
    (step, wall, 1.2 / 360.0, ridges)
}

/// The detectors and the switching machine, one tick after another, on a
/// wall 1.5 m to the left (horizontal scan) and a ridged field (inclined scan).
//= spec/library.md#lib-no-alloc-no-allocation
//= type=test
//# The core MUST be `no_std` and MUST NOT allocate on the heap: buffers have a
//# fixed capacity, and a full buffer is a returned value, not a panic.
#[test]
fn detectors_and_switching_do_not_allocate() {
    let (step, wall, furrow_step, ridges) = scans();
    let mut edge = EdgeDetector::<512, 128>::new(EdgeDetectorConfig {
        edge: EdgeConfig::pierre2022().unwrap(),
        mount: Transform2::<Sensor, Robot>::new(1.2, 0.0, 0.0).unwrap(),
        side: Side::Left,
    });
    // The edge detector does not read the odometry pose.
    let origin = Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap();
    let mut furrow =
        FurrowDetector::<512, 25>::new(FurrowConfig::new(&FurrowParams::table2()).unwrap())
            .unwrap();
    let mut switching = Switching::<2>::new(
        SwitchingConfig::new(
            Seconds::new(0.01).unwrap(),
            [
                BehaviourConfig::edge_following().unwrap(),
                BehaviourConfig::furrow_pursuing().unwrap(),
            ],
            Seconds::new(0.5).unwrap(),
            Some(Seconds::new(1.0).unwrap()),
        )
        .unwrap(),
    );
    let limits = RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap();
    let furrow_limits =
        RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(20.0).unwrap()).unwrap();

    // A fixed array: a Vec made here could be allocated lazily inside the
    // watched section by the optimiser.
    let mut modes = [None; 100];
    let count = allocations_in(|| {
        for tick in 0..100u32 {
            let horizontal = Scan {
                start: Radians::new(-std::f64::consts::PI).unwrap(),
                increment: Radians::new(step).unwrap(),
                ranges: &wall,
                limits,
            };
            let edge_outcome = edge.detect(&horizontal, &origin).unwrap();
            let inclined = Scan {
                start: Radians::new(-0.6).unwrap(),
                increment: Radians::new(furrow_step).unwrap(),
                ranges: &ridges,
                limits: furrow_limits,
            };
            let odom = Pose2::<Odom>::new(0.007 * f64::from(tick), 0.0, 0.0).unwrap();
            let furrow_outcome = furrow.detect(&inclined, &odom).unwrap();
            let output = switching.step(&Input {
                behaviours: [
                    Report::consistent(edge_outcome.verdict),
                    Report::consistent(furrow_outcome.verdict),
                ],
                localisation_valid: true,
            });
            modes[usize::try_from(tick).unwrap()] = Some(output.mode);
        }
    });
    assert!(modes.iter().all(Option::is_some));
    assert_eq!(count, 0, "detectors and switching allocated {count} times");
    // The wall was seen: the edge detector's verdicts drove the machine.
    assert!(edge
        .detect(
            &Scan {
                start: Radians::new(-std::f64::consts::PI).unwrap(),
                increment: Radians::new(step).unwrap(),
                ranges: &wall,
                limits,
            },
            &origin
        )
        .unwrap()
        .verdict
        .estimate_is_valid());
}

/// The whole per-tick pipeline, 100 ticks: both detectors on 360-ray scans
/// (a wall 1.5 m to the left, ridges under the inclined LiDAR), GNSS,
/// odometry, switching, laws and command.
//= spec/guidance.md#gd-no-alloc-no-allocation-no-clock
//= type=test
//# A tick MUST NOT allocate on the heap and MUST NOT read a clock: the
//# pipeline's buffers are fixed by its const parameters and time is counted in
//# ticks.
#[test]
fn guidance_pipeline_does_not_allocate() {
    let (step, wall, furrow_step, ridges) = scans();
    let waypoints: Vec<Point2<World>> = (0..200)
        .map(|i| Point2::new(0.5 * f64::from(i), 0.0).unwrap())
        .collect();
    let path = ReferencePath::<256>::from_waypoints(&waypoints, PathConfig::default()).unwrap();
    // Both behaviours, edge following first.
    let mut params = pierre2022_both(
        Side::Left,
        Transform2::<Sensor, Robot>::new(1.2, 0.0, 0.0).unwrap(),
    )
    .unwrap();
    params.priority = heapless::Vec::from_slice(&[EDGE, FURROW]).unwrap();
    let config = GuidanceConfig::new(&params).unwrap();
    let mut guidance: Pierre2022<'_, 256> = Guidance::new(config, &path).unwrap();
    let limits = RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap();
    let furrow_limits =
        RangeLimits::new(Meters::new(0.1).unwrap(), Meters::new(20.0).unwrap()).unwrap();

    let mut outputs = Vec::with_capacity(100);
    let count = allocations_in(|| {
        for tick in 0..100u32 {
            let x = 0.007 * f64::from(tick);
            let horizontal = RoutedScan {
                behaviour: EDGE,
                scan: Scan {
                    start: Radians::new(-std::f64::consts::PI).unwrap(),
                    increment: Radians::new(step).unwrap(),
                    ranges: &wall,
                    limits,
                },
            };
            let inclined = RoutedScan {
                behaviour: FURROW,
                scan: Scan {
                    start: Radians::new(-0.6).unwrap(),
                    increment: Radians::new(furrow_step).unwrap(),
                    ranges: &ridges,
                    limits: furrow_limits,
                },
            };
            // The horizontal scan every tick, the inclined one every tenth.
            let both = [horizontal, inclined];
            let scans: &[RoutedScan<'_>] = if tick % 10 == 0 {
                &both
            } else {
                core::slice::from_ref(&horizontal)
            };
            let input = TickInput {
                scans,
                gnss: (tick < 60).then(|| Pose2::<World>::new(x, 0.05, 0.0).unwrap()),
                odometry: Pose2::<Odom>::new(x, 0.05, 0.0).unwrap(),
                extra: Sideslip::new(0.01, -0.02).unwrap(),
            };
            outputs.push(guidance.step(&input).unwrap());
        }
    });
    assert_eq!(outputs.len(), 100);
    assert_eq!(count, 0, "the guidance pipeline allocated {count} times");
    // The wall was followed: the ticks went through detection, switching and
    // the edge law, not only path tracking.
    assert!(outputs
        .iter()
        .any(|o| o.mode == Mode::Behaviour(EDGE) && o.command.is_some()));
}

mod crop_scans;

#[test]
fn crop_navigator_does_not_allocate() {
    use fieldguide::perception::rows::ruby::Variant;
    use fieldguide::perception::rows::{RowsConfig, RowsParams};
    use fieldguide::supervisor::crop_navigation::{CropNavigator, NavParams, Phase};
    let field = crop_scans::FieldSpec {
        rows: 6,
        ..crop_scans::crop4(3, 1.2)
    }
    .build();
    let lidar = crop_scans::Lidar::paper();
    let [front, back] = crop_scans::paper_mounts(0.55);
    let rows = RowsParams::authors(Variant::Rgop, front.transform()).with_second(back.transform());
    let mut nav: CropNavigator<1024> =
        CropNavigator::new(NavParams::authors(RowsConfig::new(rows).unwrap()).unwrap()).unwrap();
    // The robot at rest, then 0.0125 m further every tick (0.5 m/s at 40 Hz):
    // measuring, then driving.
    let ticks: Vec<_> = (0_u32..240)
        .map(|k| {
            let along = 0.5 + 0.0125 * f64::from(k.max(20) - 20);
            let robot = field.between(0, 1, along);
            let odometry = Pose2::<Odom>::new(along - 0.5, 0.0, 0.0).unwrap();
            let f = field.cast(&robot, &front, &lidar, 2 * u64::from(k));
            let b = field.cast(&robot, &back, &lidar, 2 * u64::from(k) + 1);
            (f, b, odometry)
        })
        .collect();
    let mut phases = Vec::with_capacity(ticks.len());
    let n = allocations_in(|| {
        for (f, b, odometry) in &ticks {
            let tick = nav.step(&[f.scan(), b.scan()], odometry).unwrap();
            phases.push(tick.phase);
        }
    });
    assert_eq!(n, 0);
    assert_eq!(phases[0], Phase::Measuring);
    assert!(matches!(phases.last(), Some(Phase::Driving { row: 1, .. })));
}

mod vine_scans;

/// The vine detector and both four-wheel-steering laws, 60 ticks along a
/// summer vine row on a cross slope (`vine_scans`): no allocation.
//= spec/library.md#lib-no-alloc-no-allocation
//= type=test
//# The core MUST be `no_std` and MUST NOT allocate on the heap: buffers have a
//# fixed capacity, and a full buffer is a returned value, not a panic.
#[test]
fn vine_detection_and_four_wheel_steering_laws_do_not_allocate() {
    use fieldguide::control::four_ws::{
        strategy1_command, strategy2_command, Objectives, RearSteering, Strategy1, Strategy1Gains,
        Strategy2, Strategy2Gains,
    };
    use fieldguide::model::four_ws::FourWheelSteering;
    use fieldguide::perception::vine::{VineConfig, VineDetector, VineParams};
    let lidar = vine_scans::Lidar::table1();
    let world = vine_scans::vineyard(vine_scans::World::ground(0.0, 0.15), 2.2, 0.25, &[]);
    // The scans are made before the watched section.
    let scans: Vec<Vec<f64>> = (0..60)
        .map(|k| lidar.cast(&world, (0.1 * f64::from(k), 0.2, 0.0)))
        .collect();
    let mut vine =
        VineDetector::<512, 64>::new(VineConfig::new(&VineParams::summer()).unwrap()).unwrap();
    let vehicle = FourWheelSteering::new(
        Wheelbase::new(1.2).unwrap(),
        SteeringLimit::new(0.5).unwrap(),
        SteeringLimit::new(0.3).unwrap(),
        None,
        None,
    )
    .unwrap();
    let s1 = Strategy1 {
        gains: Strategy1Gains::table1().unwrap(),
        vehicle,
        rear: RearSteering::Backstepping,
    };
    let s2 = Strategy2 {
        gains: Strategy2Gains::table1().unwrap(),
        vehicle,
    };
    let v = MetersPerSecond::new(1.0).unwrap();
    let mut commands = [None; 60];
    let count = allocations_in(|| {
        for ((k, ranges), slot) in (0_u32..).zip(&scans).zip(commands.iter_mut()) {
            let odom = Pose2::<Odom>::new(0.1 * f64::from(k), 0.2, 0.0).unwrap();
            let d = vine.detect(&lidar.scan(ranges), &odom).unwrap();
            if let Some(e) = d.error {
                let a = strategy1_command(&s1, &e, &Objectives::NEUTRAL, v).unwrap();
                let b = strategy2_command(&s2, &e, Sideslip::ZERO, v).unwrap();
                *slot = Some((a, b));
            }
        }
    });
    assert_eq!(
        count, 0,
        "vine detection and 4WS laws allocated {count} times"
    );
    assert!(commands.iter().filter(|c| c.is_some()).count() > 40);
}

//= spec/library.md#lib-no-alloc-no-allocation
//= type=test
//# The core MUST be `no_std` and MUST NOT allocate on the heap: buffers have a
//# fixed capacity, and a full buffer is a returned value, not a panic.
#[test]
fn mission_supervisor_does_not_allocate() {
    use fieldguide::perception::obstacles::Hazard;
    use fieldguide::supervisor::mission::{
        Command, Mission, MissionConfig, MissionInput, Row, Task,
    };
    let p = |x: f64, y: f64, h: f64| Pose2::<World>::new(x, y, h).unwrap();
    let road = Task::approximation(&[p(4.0, 0.0, 0.0), p(8.0, 0.0, 0.0)]).unwrap();
    let row = Row {
        start: p(12.0, 0.0, 0.0),
        length: Meters::new(5.0).unwrap(),
    };
    let tasks = [road, Task::treatment(&[row]).unwrap()];
    let mut mission = Mission::new(MissionConfig::carob().unwrap(), &tasks).unwrap();
    let step = Pose2::<Robot>::new(0.05, 0.0, 0.0).unwrap();
    let mut truth = p(0.0, 0.0, 0.0);
    let mut follows = 0;
    // Fixes, odometry, every hazard, lines and Dubins detours planned.
    let count = allocations_in(|| {
        for k in 0_u32..300 {
            let hazard = match k % 50 {
                10 => Hazard::Critical,
                20 => Hazard::Warning {
                    detour: Some(p(truth.position.x() + 1.0, truth.position.y(), 0.0)),
                },
                _ => Hazard::Clear,
            };
            let out = mission.tick(&MissionInput {
                gnss: (k % 7 != 0).then_some(truth),
                odometry: step,
                hazard,
                in_field: false,
                remaining: None,
            });
            if matches!(out.command, Command::Follow(_)) {
                follows += 1;
            }
            truth = truth.body_to_frame::<Robot>().apply_pose(step).unwrap();
        }
    });
    assert_eq!(count, 0, "the mission supervisor allocated {count} times");
    assert!(follows > 200, "{follows}");
}
