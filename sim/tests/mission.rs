//! The mission supervisor driving the farm with obstacles (EM-SIM-MISSION,
//! EM-SIM-MISSION-SAFE).

use fieldguide::supervisor::mission::StopReason;
use fieldguide_sim::guiding::file::{builtin_mission, GuidingFile, BUILTIN};
use fieldguide_sim::guiding::mission::{
    campaign, drive_mission, welaser_mission, PathClass, Shape, WorldObstacle, BOUNDS,
};

const SEEDS: std::ops::RangeInclusive<u64> = 1..=5;
const LATERAL_LINE_M: f64 = BOUNDS.lateral_line_m;
const LATERAL_SPIRAL_M: f64 = BOUNDS.lateral_spiral_m;
const REACH_M: f64 = BOUNDS.reach_m;

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
//= spec/emmi2024.md#em-sim-mission-safe-closed-loop-safety-of-a-mission
//= type=test
//# On every tick of a detour on a road, the distance of the
//# footprint's corners outside the road's edge MUST be measured.
//= spec/emmi2024.md#em-sim-mission-the-supervisor-drives-the-farm
//= type=test
//# On a road's Approximation task the hazard MUST be assessed with the road's
//# corridor (its centreline and half its width less an allowance for the
//# tracking error), so that a detour keeps the footprint on the road or the
//# robot stops.
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
        // Each detour planned once (EM-MISSION-OBSTACLE).
        assert_eq!(o.detour_plans, o.replans.len(), "seed {seed}");
        // The detour keeps the footprint on the road (EM-OBST-ROAD).
        assert!(o.detour_off_road_m.is_finite(), "seed {seed}");
        assert!(
            o.detour_off_road_m <= 0.0,
            "seed {seed}: {}",
            o.detour_off_road_m
        );
        eprintln!(
            "seed {seed}: footprint outside the road on the detour {:.3} m",
            o.detour_off_road_m
        );
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
        // Every detour on the road (EM-OBST-ROAD): -inf without one.
        assert!(r.detour_off_road_m <= 0.0, "{r:?}");
    }
    // Obstacles left in the middle of a 4 m road stop some missions for
    // good (NoDetourOnRoad, or a box held in the critical area).
    assert!(rows.iter().filter(|r| r.complete).count() >= 3);
    assert!(rows.iter().any(|r| r.detour_plans > 0));
}

//= spec/emmi2024.md#em-sim-mission-file-missions-with-obstacles-as-files
//= type=test
//# A scenario file with `[guiding]`, `[farm]` and `[[obstacle]]` tables MUST be
//# driven by the core's mission supervisor with those obstacles, and the
//# built-in `welaser-mission` MUST be such a file.
#[test]
fn the_built_in_mission_is_a_file_with_its_obstacles() {
    let run = builtin_mission("welaser-mission")
        .expect("listed")
        .expect("valid");
    assert_eq!(run.guiding.name, "welaser-mission");
    assert_eq!(run.obstacles.len(), 3);
    let walker = &run.obstacles[1];
    // 7 m at 1 m/s from 16 s.
    assert_eq!(walker.walk, Some(((9.0, 0.5), 16.0, 23.0)));
    assert_eq!(walker.centre(19.5), Some((9.0, -3.0)));
    assert!(
        matches!(run.obstacles[0].shape, Shape::Box { heading, .. } if (heading - 0.3).abs() < 1e-12)
    );
    assert_eq!(run.obstacles[2].present_s, (0.0, 400.0));
    // The guided missions without obstacles are not missions of the supervisor.
    for (name, _) in BUILTIN.iter().filter(|(n, _)| *n != "welaser-mission") {
        assert!(builtin_mission(name).is_none(), "{name}");
    }
}

//= spec/emmi2024.md#em-sim-mission-file-missions-with-obstacles-as-files
//= type=test
//# A scenario file's `[[obstacle]]` tables MUST be refused, naming the file
//# and the field, for an unknown kind, a size or radius out of range, a
//# non-finite place, a walk that is not a person's or has no positive
//# duration, or a presence that ends before it starts.
#[test]
fn bad_obstacle_tables_name_their_file_and_field() {
    let good = BUILTIN
        .iter()
        .find(|(n, _)| *n == "welaser-mission")
        .expect("listed")
        .1;
    let refused = |text: &str| {
        let e = GuidingFile::parse(text, "my-mission.toml")
            .and_then(|f| f.mission("my-mission.toml"))
            .expect_err("refused");
        assert!(e.to_string().contains("my-mission.toml"), "{e}");
        e.field().map(str::to_owned)
    };
    let cases = [
        (good.replace("kind = \"box\"", "kind = \"tree\""), "obstacle[0].kind"),
        (good.replace("size_m = [0.6, 0.6]", "size_m = [0.6, 30.0]"), "obstacle[0].size_m"),
        (good.replace("size_m = [0.6, 0.6]", "radius_m = 0.3"), "obstacle[0].radius_m"),
        (good.replace("at = [50.0, -3.2]", "at = [nan, -3.2]"), "obstacle[0].at"),
        (good.replace("radius_m = 0.25\n\n[obstacle.walk]", "radius_m = 3.0\n\n[obstacle.walk]"), "obstacle[1].radius_m"),
        (good.replace("kind = \"person\"\nat = [9.0", "kind = \"post\"\nat = [9.0"), "obstacle[1].walk"),
        (good.replace("speed_mps = 1.0", "speed_mps = 0.0"), "obstacle[1].walk.speed_mps"),
        (good.replace("to = [9.0, 0.5]", "to = [9.0, -6.5]"), "obstacle[1].walk.to"),
        (good.replace("start_s = 16.0", "start_s = -1.0"), "obstacle[1].walk.start_s"),
        (good.replace("present_s = [0.0, 400.0]", "present_s = [400.0, 100.0]"), "obstacle[2].present_s"),
        (good.replace("name = \"person in the field\"", "name = \" \""), "obstacle[2].name"),
        (format!("{good}\n[[obstacle]]\nname = \"x\"\nkind = \"post\"\nat = [1.0, 1.0]\n"), "obstacle[3].radius_m"),
        (format!("{good}\n[[obstacle]]\nname = \"x\"\nkind = \"post\"\nat = [1.0, 1.0]\nradius_m = 0.1\nheight_m = 2.0\n"), "obstacle[3].height_m"),
    ];
    for (text, field) in &cases {
        assert_ne!(text.as_str(), good, "{field}: the case changed nothing");
        assert_eq!(refused(text).as_deref(), Some(*field), "{field}");
    }
    // Obstacles need a farm.
    let start = good.find("[farm]").expect("farm");
    let end = good.find("# The mission's obstacles").expect("obstacles");
    let no_farm = format!("{}{}", &good[..start], &good[end..]);
    assert_eq!(refused(&no_farm).as_deref(), Some("obstacle"));
    // `obstacle = []`: a supervised mission with no obstacle.
    let none = good[..end].replacen("seed = 1\n", "seed = 1\nobstacle = []\n", 1);
    let run = GuidingFile::parse(&none, "t")
        .and_then(|f| f.mission("t"))
        .expect("valid")
        .expect("a mission");
    assert!(run.obstacles.is_empty());
}

/// A box `length` × `width` m, square to the x axis, at `at`, there all run.
fn standing_box(name: &str, at: (f64, f64), length: f64, width: f64) -> WorldObstacle {
    WorldObstacle {
        name: name.to_owned(),
        shape: Shape::Box {
            length,
            width,
            heading: 0.0,
        },
        at,
        walk: None,
        present_s: (0.0, f64::INFINITY),
    }
}

//= spec/emmi2024.md#em-sim-mission-safe-closed-loop-safety-of-a-mission
//= type=test
//# A campaign of missions with obstacles placed at random along the roads
//# and in the fields MUST end each mission complete or stopped with a reason,
//# with no collision and no crop plant run over.
/// Bad scenes end to end: a box on the first road's first goal (the goal
/// covered), a box under the robot's front at the start: a stop with its
/// reason, held, no collision, no later task started.
#[test]
fn blocked_roads_stop_with_a_reason_and_skip_nothing() {
    let wall = |at, length, width| standing_box("blocking", at, length, width);
    for (obstacle, reasons) in [
        // The road's first goal: 0.5 m before the corner's tangent point.
        (
            wall((11.5, -3.0), 0.6, 0.6),
            &[StopReason::NoDetour, StopReason::Obstacle][..],
        ),
        // Under the front of the footprint at the start.
        (wall((0.75, -3.0), 0.4, 0.4), &[StopReason::Obstacle][..]),
    ] {
        for seed in 1..=3 {
            let mut run = welaser_mission(seed).expect("built-in");
            run.guiding.duration_s = 120.0;
            run.obstacles = vec![obstacle.clone()];
            let o = drive_mission(&run);
            let last = o
                .stops
                .last()
                .unwrap_or_else(|| panic!("{obstacle:?}: no stop"));
            assert!(
                reasons.contains(&last.reason),
                "{obstacle:?}: {:?}",
                o.stops
            );
            assert!(last.to_s >= 119.0, "{obstacle:?}: not held: {:?}", o.stops);
            assert!(o.stops.iter().all(|s| s.justified), "{:?}", o.stops);
            if obstacle.at.0 < 1.0 {
                // Under the robot from the start: it never moves.
                assert!(o.drive.ticks.iter().all(|t| t.command.0 == 0.0));
            } else {
                assert!(o.collisions.is_empty(), "{obstacle:?}: {:?}", o.collisions);
            }
            assert!(!o.complete());
            assert_eq!(o.tasks[0].result, "running", "{:?}", o.tasks);
            assert!(
                o.tasks[1..].iter().all(|t| t.result == "not started"),
                "{:?}",
                o.tasks
            );
        }
    }
}

/// More bad scenes end to end: the robot boxed in on the first road (a box
/// across it ahead, walls along both edges, a box behind) stops with a
/// named reason and stays stopped, hitting nothing and starting no later
/// task; a burst of spurious returns (200 specks of 5 mm over 2 s ahead on
/// the road) neither panics nor hits anything, and the mission completes.
#[test]
fn boxed_in_and_a_burst_of_specks_end_to_end() {
    let boxed = |at, length, width| standing_box("boxing in", at, length, width);
    for seed in 1..=3 {
        let mut run = welaser_mission(seed).expect("built-in");
        run.guiding.duration_s = 120.0;
        run.obstacles = vec![
            boxed((6.0, -3.0), 0.6, 3.6),
            boxed((3.0, -1.1), 8.0, 0.3),
            boxed((3.0, -4.9), 8.0, 0.3),
            boxed((-2.0, -3.0), 0.6, 3.6),
        ];
        let o = drive_mission(&run);
        let last = o
            .stops
            .last()
            .unwrap_or_else(|| panic!("seed {seed}: no stop"));
        assert!(
            [
                StopReason::NoDetour,
                StopReason::NoDetourOnRoad,
                StopReason::Obstacle
            ]
            .contains(&last.reason),
            "seed {seed}: {:?}",
            o.stops
        );
        assert!(last.to_s >= 119.0, "seed {seed}: not held: {:?}", o.stops);
        assert!(o.stops.iter().all(|s| s.justified), "{:?}", o.stops);
        assert!(o.collisions.is_empty(), "seed {seed}: {:?}", o.collisions);
        assert!(o.replans.is_empty(), "seed {seed}: a detour out of the box");
        assert!(!o.complete());
        assert!(
            o.tasks[1..].iter().all(|t| t.result == "not started"),
            "{:?}",
            o.tasks
        );
    }
    for seed in 1..=2_u64 {
        let mut run = welaser_mission(seed).expect("built-in");
        let mut x = seed;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1_u64 << 53) as f64
        };
        for k in 0..200 {
            let at = (3.0 + 8.0 * next(), -4.5 + 3.0 * next());
            run.obstacles.push(WorldObstacle {
                name: format!("speck {k}"),
                shape: Shape::Circle { radius: 0.005 },
                at,
                walk: None,
                present_s: (4.0, 6.0),
            });
        }
        let o = drive_mission(&run);
        eprintln!(
            "specks, seed {seed}: {:?}, stops {:?}",
            o.phase,
            o.stops_by_reason()
        );
        assert!(o.complete(), "seed {seed}: {:?} {:?}", o.phase, o.stops);
        assert!(o.collisions.is_empty(), "seed {seed}: {:?}", o.collisions);
        assert!(o.stops.iter().all(|s| s.justified), "{:?}", o.stops);
    }
}

//= spec/emmi2024.md#em-sim-mission-safe-closed-loop-safety-of-a-mission
//= type=test
//# The arcs' angular error MUST be reported per kind of arc (the fields'
//# U-turns, the roads' corners, detours and the legs re-planned after
//# them); over seeds 1 to 5, its mean over each mission's arcs MUST be at
//# most 0.0103 rad, and so MUST its mean over the fields' U-turns of those
//# missions pooled, as the paper pools every spiral followed.
/// The arcs' angular error split by kind, against ground truth: each seed
/// of 1-10 reported; each mission's and the U-turns' pooled means of seeds
/// 1-5 held.
#[test]
fn arcs_angular_error_by_kind() {
    let bound = 0.0103;
    let mut pooled: Vec<(PathClass, f64)> = Vec::new();
    for seed in 1..=10_u64 {
        let run = welaser_mission(seed).expect("built-in");
        let o = drive_mission(&run);
        let k = |c| o.angular_spiral_of(c);
        let (f, r, d) = (
            k(PathClass::Field),
            k(PathClass::Road),
            k(PathClass::Detour),
        );
        eprintln!(
            "seed {seed}: arcs' angular error, mrad: all {:.1} ({} arcs), field U-turns {:.1} ({}), road corners {:.1} ({}), detours {:.1} ({})",
            1e3 * o.drive.angular_spiral().mean_abs,
            o.drive.angular_spiral().count,
            1e3 * f.mean_abs,
            f.count,
            1e3 * r.mean_abs,
            r.count,
            1e3 * d.mean_abs,
            d.count
        );
        assert!(f.count >= 4 && r.count >= 4, "seed {seed}");
        if seed <= 5 {
            assert!(o.drive.angular_spiral().mean_abs <= bound, "seed {seed}");
        }
        if seed <= 5 {
            pooled.extend(
                o.classified
                    .iter()
                    .filter(|(c, m)| {
                        *c != PathClass::Detour
                            && matches!(m.kind, fieldguide_sim::guiding::Kind::Spiral(_))
                    })
                    .map(|(c, m)| (*c, m.angular_rad)),
            );
        }
    }
    let mean = |keep: &dyn Fn(PathClass) -> bool| {
        let v: Vec<f64> = pooled
            .iter()
            .filter(|(c, _)| keep(*c))
            .map(|p| p.1)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (all, field, road) = (
        mean(&|_| true),
        mean(&|c| c == PathClass::Field),
        mean(&|c| c == PathClass::Road),
    );
    eprintln!(
        "seeds 1-5 pooled, mrad: all arcs {:.2}, field U-turns {:.2}, road corners {:.2}",
        1e3 * all,
        1e3 * field,
        1e3 * road
    );
    assert!(all <= bound, "{all}");
    assert!(field <= bound, "{field}");
}
