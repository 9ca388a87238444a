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
use std::sync::atomic::{AtomicUsize, Ordering};

use fieldguide::control::backstepping::{
    steering_command, BacksteppingConfig, Inversion, SteeringLimit,
};
use fieldguide::control::Gains;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::model::bicycle::{world_rates, Sideslip, Wheelbase};
use fieldguide::{Meters, MetersPerSecond, Point2, Pose2, TrackingError, World};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static WATCHING: Cell<bool> = const { Cell::new(false) };
}

// SAFETY: every call is forwarded unchanged to the system allocator; the
// wrapper only counts, and the thread-local read cannot allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if WATCHING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if WATCHING.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Runs `f` and returns how many heap allocations this thread made inside it.
fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    WATCHING.with(|w| w.set(true));
    f();
    WATCHING.with(|w| w.set(false));
    ALLOCATIONS.load(Ordering::SeqCst) - before
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
        wheelbase: Wheelbase::new(2.0).unwrap(),
        max_steering: SteeringLimit::new(0.6).unwrap(),
        inversion: Inversion::Exact,
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
            let rates = world_rates(&pose, speed, cmd.steering, slip, config.wheelbase).unwrap();
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
