//! A bolero harness over the obstacle handling of Emmi 2024, section 3.2
//! (EM-OBST-*, LIB-FINITE): for any `f64` inputs, NaN and infinities
//! included, a scan of 24 rays clusters into a bounded list of finite
//! obstacles, and the hazard of that list and of three circles, for any
//! pose, goal and speed, is a value or a named error, never a panic. A
//! detour waypoint keeps the footprint the margin away from every obstacle
//! (an oracle of its own here), and an obstacle in the critical area at one
//! speed still stops the robot at any higher speed.
//!
//! Random search here (`cargo test`); with `cargo bolero test` it is a
//! coverage-guided fuzz target. Not a Kani proof: the geometry goes through
//! libm's trigonometry.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::atomic::{AtomicU64, Ordering};

use bolero::check;
use fieldguide::perception::obstacles::{
    assess, cluster, ClusterConfig, Hazard, Obstacle, ObstacleConfig, Obstacles, Reason,
};
use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::planning::dubins::TurningRadius;
use fieldguide::{
    Meters, MetersPerSecond, Point2, Pose2, Radians, Robot, Sensor, Transform2, World,
};
use fieldguide_proofs::evidence::{self, Kind};

/// One case: the ranges, the scan's start and increment (any `f64`); three
/// circles (x, y, r), the pose and the goal (x, y, heading) on a grid of
/// plausible values; two speeds (any `f64`); in a field or not.
type Case = ([f64; 24], [f64; 2], [u8; 9], [u8; 6], [f64; 2], bool);

/// `u` of 0-255 mapped onto [lo, hi].
fn grid(u: u8, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * f64::from(u) / 255.0
}

/// A finite value folded into [−bound, bound]; any other kept as it is.
fn fold(v: f64, bound: f64) -> f64 {
    if v.is_finite() {
        v % bound
    } else {
        v
    }
}

/// The oracle's distance from a circle (robot frame at `seen_from`) to the
/// footprint at `pose`: 0.75 m ahead and behind, 0.88 m each side.
fn footprint_distance(pose: &Pose2<World>, seen_from: &Pose2<World>, c: (f64, f64), r: f64) -> f64 {
    let (ch, sh) = (seen_from.heading.get().cos(), seen_from.heading.get().sin());
    let w = (
        seen_from.position.x() + ch * c.0 - sh * c.1,
        seen_from.position.y() + sh * c.0 + ch * c.1,
    );
    let (cp, sp) = (pose.heading.get().cos(), pose.heading.get().sin());
    let (dx, dy) = (w.0 - pose.position.x(), w.1 - pose.position.y());
    let b = (cp * dx + sp * dy, -sp * dx + cp * dy);
    let ex = (-0.75 - b.0).max(b.0 - 0.75).max(0.0);
    let ey = (b.1.abs() - 0.88).max(0.0);
    (ex.hypot(ey) - r).max(0.0)
}

#[test]
fn obstacle_handling_is_total_and_detours_keep_the_margin() {
    let config = ObstacleConfig::emmi2024(TurningRadius::new(Meters::new(1.0).unwrap()).unwrap());
    let limits = RangeLimits::new(Meters::new(0.05).unwrap(), Meters::new(30.0).unwrap()).unwrap();
    let mount = Transform2::<Sensor, Robot>::new(0.3, 0.0, 0.0).unwrap();
    let run = evidence::start(
        "obstacles: hostile scans, hazards and detours",
        Kind::Harness,
    );
    let count = AtomicU64::new(0);
    check!().with_type::<Case>().for_each(
        |&(ranges, [start, increment], circles, poses, [v, dv], in_field)| {
            count.fetch_add(1, Ordering::Relaxed);
            let ranges = ranges.map(|r| fold(r.abs(), 12.0));
            let (Ok(start), Ok(increment)) =
                (Radians::new(start), Radians::new(fold(increment, 0.2)))
            else {
                return;
            };
            let scan = Scan {
                start,
                increment,
                ranges: &ranges,
                limits,
            };
            let found = cluster::<4>(&scan, &mount, &ClusterConfig::emmi2024());
            let text = format!("{found:?}");
            assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");

            let mut given = Obstacles::<4>::new();
            let mut shapes = Vec::new();
            for c in circles.chunks_exact(3) {
                let centre = Point2::new(grid(c[0], -1.0, 8.0), grid(c[1], -3.0, 3.0)).unwrap();
                let radius = Meters::new(grid(c[2], 0.0, 0.6)).unwrap();
                shapes.push(((centre.x(), centre.y()), radius.get()));
                given.insert(Obstacle::Circle { centre, radius });
            }
            let heading = grid(poses[2], -4.0, 4.0);
            let pose = Pose2::<World>::new(
                grid(poses[0], -20.0, 20.0),
                grid(poses[1], -20.0, 20.0),
                heading,
            )
            .unwrap();
            // The goal 0-40 m away, mostly ahead.
            let (d, bearing) = (
                grid(poses[3], 0.0, 40.0),
                heading + grid(poses[4], -1.5, 1.5),
            );
            let goal = Pose2::<World>::new(
                pose.position.x() + d * bearing.cos(),
                pose.position.y() + d * bearing.sin(),
                heading + grid(poses[5], -3.2, 3.2),
            )
            .unwrap();
            let Ok(slow) = MetersPerSecond::new(fold(v.abs(), 2.0)) else {
                return;
            };
            let fast = MetersPerSecond::new(slow.get() + fold(dv.abs(), 2.0)).unwrap_or(slow);
            for list in [&found, &given] {
                let at = |speed| assess(list, &pose, &goal, speed, in_field, &config);
                let (a, b) = match (at(slow), at(fast)) {
                    (Ok(a), Ok(b)) => (a, b),
                    (Err(e), _) | (_, Err(e)) => {
                        assert!(
                            ["EM-DUBINS-RANGE", "LIB-FINITE"].contains(&e.requirement),
                            "{e}"
                        );
                        continue;
                    }
                };
                if a.reason == Reason::CriticalArea {
                    assert_eq!(b.hazard, Hazard::Critical, "{a:?} then {b:?}");
                }
                if let Hazard::Warning { detour: Some(w) } = a.hazard {
                    assert!(!in_field);
                    if core::ptr::eq(list, &given) {
                        for &(c, r) in &shapes {
                            assert!(footprint_distance(&w, &pose, c, r) >= 0.3 - 1e-9, "{w:?}");
                        }
                    }
                }
            }
        },
    );
    run.finish(&evidence::harness(
        &[
            "EM-OBST-CLUSTER",
            "EM-OBST-AREAS",
            "EM-OBST-HAZARD",
            "EM-OBST-DETOUR",
            "EM-OBST-FIELD",
        ],
        count.into_inner(),
        None,
    ));
}
