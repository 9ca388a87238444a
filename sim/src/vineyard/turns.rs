//! Vine following as a behaviour of the core's switching pipeline, with a
//! headland turn on the recorded path (beyond the paper: its switching as in
//! Pierre 2022, section 3).
//!
//! The recorded path runs along row 0 from the robot's start, turns right
//! in the headland on a half circle of radius `spacing` into row 2 (a
//! straddling robot skips a row to turn wide enough) and runs back along it.
//! The core's `guidance::Guidance` holds path tracking (strategy 1 on the
//! path, GNSS pose) and one behaviour, vine following (the vine detector on
//! the inclined LiDAR, strategy 1 on its row line), with transit delays and
//! plan consistency: inside a row the pipeline follows the vines; at the row's
//! end, the detection lost, it goes back to path tracking for the turn.

use fieldguide::control::four_ws::{Objectives, RearSteering, Strategy1, Strategy1Gains};
use fieldguide::geometry::path::ReferencePath;
use fieldguide::guidance::{
    BehaviourId, BehaviourParams, Guidance, GuidanceConfig, GuidanceParams, Mode,
    PathTrackingParams, RoutedScan, TickInput,
};
use fieldguide::model::bicycle::{Sideslip, SteeringLimit, Wheelbase};
use fieldguide::model::four_ws::FourWheelSteering;
use fieldguide::model::{Command, Vehicle};
use fieldguide::perception::vine::{VineConfig, VineDetector};
use fieldguide::supervisor::switching::PlanTolerance;
use fieldguide::{Curvature, Meters, MetersPerSecond, Pose2, Radians, Seconds, World};

use super::{
    mark_touched, FourWsOdometry, VineEnd, VineOutcome, VineTick, VineyardRun, PERIOD_S, POINTS,
    RAYS, WHEELBASE_M,
};
use crate::plant::{FourWsPlant, Plant, SteeringActuator, VehicleState};
use crate::rng::SimRng;
use crate::world::crops::PlantIndex;
use crate::world::scene::Scene;
use crate::world::terrain::Terrain;
use crate::world::Plant as Stem;

/// The vine-following behaviour's id.
pub const VINES: BehaviourId = BehaviourId(1);
/// The recorded path's capacity, vertices.
pub const PATH_VERTICES: usize = 4096;
/// The path's sampling step, m.
const STEP_M: f64 = 0.05;
/// How far ahead along the path the plan check looks, m: the line is left
/// before the turn starts.
const LOOKAHEAD_M: f64 = 2.0;
/// How far past the row's end the turn starts, m.
const HEADLAND_M: f64 = 1.5;

/// The recorded path: along row 0 from `x0`, a half circle to the right into
/// row 2, back along row 2 to `x0`.
fn recorded_path(run: &VineyardRun, x0: f64) -> Result<ReferencePath<PATH_VERTICES>, String> {
    let s = |e: fieldguide::Precondition| e.to_string();
    let end = run.field.length + HEADLAND_M;
    let r = run.field.spacing;
    let (y0, y2) = (run.field.row_y(0), run.field.row_y(2));
    let mut samples = Vec::new();
    let straight = (end - x0) / STEP_M;
    for k in 0..=straight.ceil() as usize {
        let x = (x0 + k as f64 * STEP_M).min(end);
        samples.push((
            Pose2::new(x, y0, 0.0).map_err(s)?,
            Curvature::new(0.0).map_err(s)?,
        ));
    }
    let turn = core::f64::consts::PI * r / STEP_M;
    let n = turn.ceil() as usize;
    for k in 1..=n {
        let a = core::f64::consts::PI * k as f64 / n as f64;
        let (x, y) = (end + r * a.sin(), y0 - r + r * a.cos());
        samples.push((
            Pose2::new(x, y, -a).map_err(s)?,
            Curvature::new(-1.0 / r).map_err(s)?,
        ));
    }
    for k in 1..=straight.ceil() as usize {
        let x = (end - k as f64 * STEP_M).max(x0);
        samples.push((
            Pose2::new(x, y2, core::f64::consts::PI).map_err(s)?,
            Curvature::new(0.0).map_err(s)?,
        ));
    }
    ReferencePath::from_exact(samples).map_err(s)
}

/// Runs `run` with the headland turn through the core pipeline.
#[allow(clippy::too_many_lines)]
pub fn drive_in(
    run: &VineyardRun,
    seen: &[Stem],
    solid: &[Stem],
    rng: &mut SimRng,
) -> Result<VineOutcome, String> {
    let s = |e: fieldguide::Precondition| e.to_string();
    if run.field.rows < 3 {
        return Err("the headland turn needs 3 rows".to_owned());
    }
    let limit = SteeringLimit::new(run.steering.2).map_err(s)?;
    let actuator = SteeringActuator::from_settling(run.steering.0, run.steering.1, limit);
    let wheelbase = Wheelbase::new(WHEELBASE_M).map_err(s)?;
    let plant = FourWsPlant {
        wheelbase,
        front: actuator,
        rear: actuator,
    };
    let vehicle = FourWheelSteering::new(wheelbase, limit, limit, None, None).map_err(s)?;
    let (k_y, k_t, k_r) = run.gains1;
    let law = Strategy1 {
        gains: Strategy1Gains::new(k_y, k_t, k_r, 1.0).map_err(s)?,
        vehicle,
        rear: RearSteering::Backstepping,
    };
    let speed = MetersPerSecond::new(run.speed_mps).map_err(s)?;
    let start_x = -run.start.0 - WHEELBASE_M;
    let path = recorded_path(run, start_x)?;
    let mut behaviours = heapless::Vec::new();
    behaviours
        .push(BehaviourParams {
            id: VINES,
            label: "vine_following",
            detector: VineConfig::new(&run.vine_params()).map_err(s)?,
            law,
            speed,
            enter_delay: Seconds::new(1.0).map_err(s)?,
            exit_delay: Seconds::new(0.5).map_err(s)?,
            plan: Some(
                PlanTolerance::new(Meters::new(0.5).map_err(s)?, Radians::new(0.3).map_err(s)?)
                    .and_then(|p| p.with_lookahead(Meters::new(LOOKAHEAD_M)?))
                    .map_err(s)?,
            ),
        })
        .map_err(|_| "one behaviour".to_owned())?;
    let params = GuidanceParams {
        period: Seconds::new(PERIOD_S).map_err(s)?,
        vehicle: Vehicle::FourWheelSteering(vehicle),
        path: PathTrackingParams {
            law,
            speed,
            horizon: Seconds::new(0.0).map_err(s)?,
            steering_lag: Seconds::new(run.steering.0 / 3.0).map_err(s)?,
            compensation: true,
            search_window: Meters::new(3.0).map_err(s)?,
        },
        behaviours,
        priority: heapless::Vec::new(),
        stop_delay: Seconds::new(1.0).map_err(s)?,
        plan_delay: Some(Seconds::new(0.5).map_err(s)?),
        max_scan_age: Seconds::new(0.2).map_err(s)?,
        plan_dead_reckoning: None,
        bridge: None,
        steer_before_resuming: false,
        handover: None,
        entry: None,
        fix: None,
        odometry_aid: None,
    };
    let config = GuidanceConfig::new(&params).map_err(s)?;
    let mut core: Box<Guidance<'_, PATH_VERTICES, VineDetector<RAYS, POINTS>, Strategy1, 1>> =
        Box::new(Guidance::new(config, &path).map_err(s)?);
    let lidar = run.lidar();
    let index = PlantIndex::new(seen.to_vec(), crate::runner::PLANT_INDEX_CELL_M);
    let terrain = Terrain {
        base: Sideslip::new(run.sideslip.0, run.sideslip.1).map_err(s)?,
        patches: Vec::new(),
        ground: run.field.ground(),
    };
    let scene = Scene {
        ground: &terrain.ground,
        plants: &index,
        obstacles: None,
        obstacle_height: 0.0,
    };
    let start = Pose2::<World>::new(start_x, run.start.1, 0.0).map_err(s)?;
    let mut state = VehicleState::at(start, &terrain);
    let mut odometry = FourWsOdometry::new(run.odometry).map_err(s)?;
    let mut touched = vec![false; solid.len()];
    let mut ticks = Vec::new();
    let mut detected = 0;
    let (y0, y2) = (run.field.row_y(0), run.field.row_y(2));
    let length = run.field.length;
    let total = path.length().get();
    let steps = ((total + 10.0) / run.speed_mps / PERIOD_S).ceil() as u64;
    let mut end = VineEnd::Aborted("the path's end was not reached".to_owned());
    for k in 0..=steps {
        let t_s = k as f64 * PERIOD_S;
        let scan = lidar.scan(&state.pose, &scene, rng);
        let routed = [RoutedScan {
            behaviour: VINES,
            scan: scan.as_scan().map_err(s)?,
        }];
        let slip = state.sideslip;
        let out = core
            .step(&TickInput {
                scans: &routed,
                gnss: Some(state.pose),
                odometry: odometry.pose(),
                extra: Objectives {
                    sideslip: slip,
                    ..Objectives::NEUTRAL
                },
            })
            .map_err(|e| format!("t = {t_s:.2} s: {e}"))?;
        let following = out.mode == Mode::Behaviour(VINES);
        if following {
            detected += 1;
        }
        let mut command = out.command.map_or(
            Command::FourWheelSteering {
                speed: MetersPerSecond::new(0.0).map_err(s)?,
                front: Radians::ZERO,
                rear: Radians::ZERO,
            },
            |c| c.command,
        );
        // The law inside the pipeline: its gains' signs flipped is its
        // angles negated.
        if let (
            Some(super::Fault::FlippedLateralGain),
            Command::FourWheelSteering { speed, front, rear },
        ) = (run.fault, command)
        {
            command = Command::FourWheelSteering {
                speed,
                front: Radians::new(-front.get()).map_err(s)?,
                rear: Radians::new(-rear.get()).map_err(s)?,
            };
        }
        let truth = state.pose;
        mark_touched(&truth, solid, &mut touched);
        let (x, y, th) = (truth.position.x(), truth.position.y(), truth.heading.get());
        // The row being driven: row 0 heading +x, row 2 heading −x.
        let back = th.cos() < 0.0 && y < 0.5 * (y0 + y2);
        let (lateral, angular, along) = if back {
            (y2 - y, super::wrap(th - core::f64::consts::PI), length - x)
        } else {
            (y - y0, th, x)
        };
        let in_row = (0.0..=length).contains(&x);
        ticks.push(VineTick {
            t_s,
            truth,
            lateral_m: lateral,
            angular_rad: angular,
            along_m: if in_row { along } else { -1.0 },
            steering: (state.steering, state.rear_steering),
            estimate: out
                .behaviour(VINES)
                .and_then(|b| b.error)
                .map(|e| (e.y.get(), e.angular_deviation.get())),
            following: Some(following),
        });
        if back && x <= 0.0 {
            end = VineEnd::Done;
            break;
        }
        let before = state;
        state = plant
            .advance(&state, &command, &terrain, PERIOD_S, 4)
            .map_err(|e| format!("t = {t_s:.2} s: {e}"))?;
        odometry.update(&before, &state, slip.rear.get(), rng);
    }
    Ok(VineOutcome::of(ticks, end, &touched, solid, seen, detected))
}
