//! The mission supervisor driving the farm with obstacles (EM-SIM-MISSION,
//! EM-SIM-MISSION-SAFE).

use fieldguide::supervisor::mission::StopReason;
use fieldguide_sim::guiding::mission::{
    campaign, drive_mission, welaser_mission, Shape, WorldObstacle,
};

const SEEDS: std::ops::RangeInclusive<u64> = 1..=5;
const LATERAL_LINE_M: f64 = 0.038;
const LATERAL_SPIRAL_M: f64 = 0.06;
const REACH_M: f64 = 0.045;

//= spec/emmi2024.md#em-sim-mission-safe-closed-loop-safety-of-a-mission
//= type=test
//# Over every seed of a sweep of at least five, the built-in mission with
//# obstacles MUST complete every task; the robot's footprint MUST never
//# overlap an obstacle; every stop MUST have its cause in the world; no
//# re-plan MUST start inside a field; no crop plant MUST be run over; and the
//# lateral and reach figures of EM-SIM-FIGURES MUST hold.
//= spec/emmi2024.md#em-sim-mission-the-supervisor-drives-the-farm
//= type=test
//# Every stop MUST be recorded with its reason and whether ground
//# truth agrees: a real obstacle in the critical area (or, for a
//# warning's stop, in the warning area), or no fix.
//= spec/emmi2024.md#em-sim-mission-the-supervisor-drives-the-farm
//= type=test
//# The farm's roads MUST become Approximation tasks through their goals and
//# its fields Treatment tasks of one row per pass, and the core's mission
//# supervisor MUST decide every tick; the simulator MUST follow its plan with
//# the controllers of the guided missions and stand still on its Stop.
//= spec/emmi2024.md#em-sim-mission-safe-closed-loop-safety-of-a-mission
//= type=test
//# The closed-loop figures MUST be measured over the paths
//# followed to their end, detours left out.
#[test]
fn the_built_in_mission_is_safe_over_five_seeds() {
    for seed in SEEDS {
        let run = welaser_mission(seed).expect("built-in");
        let o = drive_mission(&run);
        let d = &o.drive;
        eprintln!(
            "seed {seed}: {:?}, stops {:?}, replans {}, collisions {}, crushed {}, reach {:.4}, line {:.4}, spiral {:.4}, angular spiral {:.4}",
            o.phase,
            o.stops_by_reason(),
            o.replans.len(),
            o.collisions.len(),
            d.crushed.len(),
            d.reach_error().mean_abs,
            d.lateral_line().mean_abs,
            d.lateral_spiral().mean_abs,
            d.angular_spiral().mean_abs
        );
        assert!(o.complete(), "seed {seed}: {:?}", o.phase);
        assert!(
            o.tasks.iter().all(|t| t.result == "done"),
            "seed {seed}: {:?}",
            o.tasks
        );
        assert_eq!(o.tasks.len(), 5);
        assert!(o.collisions.is_empty(), "seed {seed}: {:?}", o.collisions);
        assert!(
            o.stops.iter().all(|s| s.justified),
            "seed {seed}: {:?}",
            o.stops
        );
        assert!(o.replans.iter().all(|r| !r.in_field), "seed {seed}");
        assert!(d.crushed.is_empty(), "seed {seed}");
        // The scenario's three events: the box re-planned round, the
        // crossing person a stop, the person in the field a stop.
        assert!(!o.replans.is_empty(), "seed {seed}: no re-plan");
        let reasons: Vec<StopReason> = o.stops.iter().map(|s| s.reason).collect();
        assert!(
            reasons.contains(&StopReason::Obstacle),
            "seed {seed}: {reasons:?}"
        );
        assert!(
            reasons.contains(&StopReason::ObstacleInField),
            "seed {seed}: {reasons:?}"
        );
        assert!(
            d.lateral_line().count >= 8,
            "seed {seed}: {:?}",
            d.lateral_line()
        );
        assert!(
            d.lateral_spiral().count >= 6,
            "seed {seed}: {:?}",
            d.lateral_spiral()
        );
        assert!(d.lateral_line().mean_abs <= LATERAL_LINE_M, "seed {seed}");
        assert!(
            d.lateral_spiral().mean_abs <= LATERAL_SPIRAL_M,
            "seed {seed}"
        );
        assert!(d.reach_error().mean_abs <= REACH_M, "seed {seed}");
        assert!(
            d.reaches.len() >= 20,
            "seed {seed}: {} goals",
            d.reaches.len()
        );
    }
}

//= spec/emmi2024.md#em-sim-mission-the-supervisor-drives-the-farm
//= type=test
//# The supervisor MUST get every tick the localisation of the vehicle
//# stack (odometry corrected by each valid GNSS fix), the odometry
//# increment, and the hazard the core assesses from the clusters of a
//# front LiDAR's scan of the world's obstacles.
#[test]
fn a_post_on_the_first_road_is_seen_and_the_overlap_check_bites() {
    let mut run = welaser_mission(1).expect("built-in");
    run.guiding.duration_s = 120.0;
    let post = WorldObstacle {
        name: "post".to_owned(),
        shape: Shape::Circle { radius: 0.2 },
        at: (8.0, -3.0),
        walk: None,
        present_s: (0.0, f64::INFINITY),
    };
    run.obstacles = vec![post.clone()];
    let o = drive_mission(&run);
    assert!(o.collisions.is_empty(), "{:?}", o.collisions);
    assert!(!o.replans.is_empty() || !o.stops.is_empty());
    assert!(o.stops.iter().all(|s| s.justified), "{:?}", o.stops);
    // Without the LiDAR's obstacle (present only at the robot's start,
    // under it), the ground-truth overlap is found.
    run.obstacles = vec![WorldObstacle {
        at: (0.0, -3.0),
        present_s: (0.0, 0.05),
        ..post
    }];
    let o = drive_mission(&run);
    assert_eq!(o.collisions.len(), 1, "{:?}", o.collisions);
}

//= spec/emmi2024.md#em-sim-mission-safe-closed-loop-safety-of-a-mission
//= type=test
//# A campaign of missions with obstacles placed at random along the roads
//# and in the fields MUST end each mission complete or stopped with a reason,
//# with no collision and no crop plant run over.
#[test]
fn a_reduced_campaign_has_no_collision_and_no_crushed_plant() {
    let rows = campaign(10);
    assert_eq!(rows.len(), 10);
    for r in &rows {
        eprintln!("{r:?}");
        assert_eq!(r.collisions, 0, "{r:?}");
        assert_eq!(r.crushed, 0, "{r:?}");
        assert_eq!(r.replans_in_field, 0, "{r:?}");
        assert_eq!(r.unjustified, 0, "{r:?}");
        assert!(r.complete || r.reason.is_some(), "{r:?}");
    }
    assert!(rows.iter().filter(|r| r.complete).count() >= 5);
}
