//! A tracked robot guided on RTK-GNSS through a crop field (Emmi 2024,
//! sections 3-5): the core's planners (`planning::dubins` GoToGoal,
//! LineFollowing), the controller each segment gets
//! (`planning::manager::tracker_for`: lateral PD on straights, spiral on
//! arcs) and the linear speed controller, driving the skid-steer plant
//! ([`crate::plant::SkidSteerPlant`]) along a mission of goals.
//!
//! One tick at 10 Hz (the GNSS's and the controller's rate): a GNSS fix of
//! the true pose with Gaussian noise feeds the controllers; when the robot
//! has no path it plans to the next goal from the fix (GoToGoal from a 45°
//! change of direction, else the mission's line from the previous goal);
//! the speed profile stops it at the goal, where it rests a second. The
//! paper's indicators (section 5) are measured against ground truth: the
//! true pose against the planned path, the goal against the true pose, and
//! every crop plant under a track.

pub mod boundary;
pub mod farm;
pub mod field;
pub mod file;
pub mod mission;
pub mod plot;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use fieldguide::control::lateral_pd::{LateralGains, LateralPd, LateralRate};
use fieldguide::control::speed_profile::{
    Braking, SpeedCommand, SpeedProfile, SpeedState, REACH_DISTANCE,
};
use fieldguide::control::spiral::{spiral_command, spiral_state, Spiral};
use fieldguide::control::ControlLaw;
use fieldguide::geometry::path::ReferencePath;
use fieldguide::model::skid_steer::SkidSteer;
use fieldguide::model::Command;
use fieldguide::planning::dubins::{shortest, TurningRadius};
use fieldguide::planning::manager::{
    choose_planner, tracker_for, Planner, PlannerThreshold, Tracker,
};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Pose2, Precondition, Radians, RadiansPerSecond, Seconds,
    World,
};

use crate::error::SimError;
use crate::plant::{Plant, SkidSteerPlant, VehicleState};
use crate::rng::SimRng;
use crate::world::crops::PlantIndex;
use crate::world::terrain::Terrain;
use crate::world::{Plant as Stem, PlantKind};
use farm::{Farm, RouteGoal, Task};
use field::FieldSpec;

/// The control period: one tick per GNSS fix at 10 Hz (section 5.1), s.
pub const PERIOD_S: f64 = 0.1;
/// Sub-steps of the plant per tick.
pub const SUBSTEPS: u32 = 5;
/// How long the robot rests at each goal before planning the next, s.
pub const REST_S: f64 = 1.0;
/// The reference paths' vertex spacing, m.
pub const PATH_SPACING_M: f64 = 0.02;
/// Vertices a planned path may hold.
pub const PATH_CAPACITY: usize = 4096;
/// A segment shorter than this is not counted as a manoeuvre of its own, m.
pub const MIN_MANOEUVRE_M: f64 = 0.2;

/// A fault put into the loop to show that the checks bite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The lateral controller's distance gains KP_d and KD_d with the wrong
    /// sign (the lateral error fed to it negated).
    FlippedLateralGain,
    /// The spiral controller's gain λ with the wrong sign (its angle error
    /// negated).
    FlippedSpiralGain,
}

/// The tracked robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotSpec {
    /// Distance between the tracks' centres, m.
    pub track_m: f64,
    /// Width of each track, m.
    pub track_width_m: f64,
    /// Length of the tracks on the ground, m.
    pub length_m: f64,
    /// Largest track speed, m/s (Table 1: about 6 km/h).
    pub max_track_speed: f64,
    /// Time constant of the tracks' speed, s.
    pub lag_s: f64,
    /// Slip of the left and right tracks, share of their speed.
    pub slip: (f64, f64),
    /// Effective over geometric track, χ ≥ 1.
    pub icr_factor: f64,
}

impl RobotSpec {
    /// The default robot: tracks 0.75 m apart (set to the crop's rows),
    /// 0.2 m wide, 1.2 m long, 1.67 m/s at most, a lag of 0.15 s, slips of
    /// 2 % and 3 %, an effective track 5 % wider.
    pub const DEFAULT: Self = Self {
        track_m: 0.75,
        track_width_m: 0.2,
        length_m: 1.2,
        max_track_speed: 1.67,
        lag_s: 0.15,
        slip: (0.02, 0.03),
        icr_factor: 1.05,
    };

    /// The plant of this robot.
    #[must_use]
    pub fn plant(&self) -> SkidSteerPlant {
        SkidSteerPlant {
            track_m: self.track_m,
            time_constant_s: self.lag_s,
            max_track_speed: self.max_track_speed,
            slip: self.slip,
            icr_factor: self.icr_factor,
        }
    }
}

/// The controllers' settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlSpec {
    /// K_φ, KP_d, KD_d, K_v, K_w of eqs. 1-2.
    pub lateral_gains: [f64; 5],
    /// The control point's distance ahead, m.
    pub control_point_m: f64,
    /// The spiral gain λ, 1/s.
    pub spiral_lambda: f64,
    /// The threshold speed v_th, m/s.
    pub threshold_speed: f64,
    /// The nominal speed on lines, m/s.
    pub line_speed: f64,
    /// The nominal speed in turns (GoToGoal paths), m/s.
    pub turn_speed: f64,
}

impl ControlSpec {
    /// The settings of the built-in scenarios.
    pub const DEFAULT: Self = Self {
        lateral_gains: [1.2, 1.5, 0.3, 1.0, 0.5],
        control_point_m: 0.5,
        spiral_lambda: 2.0,
        threshold_speed: 0.1,
        line_speed: 0.5,
        turn_speed: 0.2,
    };
}

/// One run: the field and its mission, the robot, the GNSS, the seed.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidingRun {
    /// The run's name (output folder).
    pub name: String,
    /// The seed of the field's plants and of every noise.
    pub seed: u64,
    /// The field and the passes the robot drives.
    pub field: FieldSpec,
    /// The robot.
    pub robot: RobotSpec,
    /// The controllers.
    pub control: ControlSpec,
    /// The GNSS position noise σ per axis, m (section 5.1: 0.015).
    pub gnss_sigma_m: f64,
    /// The GNSS heading noise σ, rad (the paper's angular accuracy, 0.009).
    pub gnss_heading_sigma_rad: f64,
    /// No fix from the first time to the second, s: the robot stands still
    /// until the fix returns (EM-SIM-GNSS-LOST).
    pub gnss_outage_s: Option<(f64, f64)>,
    /// O's start this far left of the first pass, m.
    pub start_offset_m: f64,
    /// The longest the mission may take, s.
    pub duration_s: f64,
    /// A fault, for the tests that show the checks bite.
    pub fault: Option<Fault>,
    /// Every U-turn's footprint stays inside the field's outline
    /// ([`boundary::shortest_inside`]).
    pub stay_inside: bool,
    /// A farm of fields joined by roads, driven from its yard; `None`: the
    /// one field `field`, from the start of its first pass.
    pub farm: Option<Farm>,
}

impl GuidingRun {
    /// The mission's goals, each with its task (the one field's goals are
    /// all `Task::Field(0)`).
    ///
    /// # Errors
    /// As [`Farm::route`].
    pub fn route(&self) -> Result<Vec<RouteGoal>, Precondition> {
        match &self.farm {
            Some(farm) => farm.route(),
            None => Ok(self
                .field
                .goals()
                .into_iter()
                .map(|goal| RouteGoal {
                    goal,
                    task: Task::Field(0),
                })
                .collect()),
        }
    }

    /// Every crop plant of the mission's field or farm.
    pub fn plants(&self, rng: &mut SimRng) -> Vec<Stem> {
        match &self.farm {
            Some(farm) => farm.plants(rng),
            None => self.field.plants(rng),
        }
    }

    /// The fields of the mission, placed in the world (the one field at
    /// the origin, its rows along x).
    #[must_use]
    pub fn placed_fields(&self) -> Vec<farm::PlacedField> {
        match &self.farm {
            Some(farm) => farm.fields.clone(),
            None => vec![farm::PlacedField {
                corner: (0.0, 0.0),
                heading_rad: 0.0,
                field: self.field.clone(),
                passes: self.field.passes().len(),
            }],
        }
    }

    /// The robot's start, and the start of the first LineFollowing line.
    fn starts(&self) -> Result<(Pose2<World>, Pose2<World>), Precondition> {
        match &self.farm {
            Some(farm) => Ok((farm.yard, farm.yard)),
            None => Ok((
                self.field.start(self.start_offset_m)?,
                self.field.first_line_start()?,
            )),
        }
    }

    /// The outline GoToGoal's turns stay inside during `task`, if any (on
    /// a road, none).
    #[must_use]
    pub fn outline(&self, task: Task) -> Option<boundary::Boundary> {
        let Task::Field(k) = task else {
            return None;
        };
        self.placed_fields().get(k).map(farm::PlacedField::outline)
    }
}

/// What a manoeuvre followed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A straight, by the lateral controller.
    Line,
    /// An arc of this radius, by the spiral controller.
    Spiral(f64),
}

/// One line or spiral followed: its errors against ground truth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Manoeuvre {
    /// Line or spiral.
    pub kind: Kind,
    /// Mean |lateral error| over its ticks, m.
    pub lateral_m: f64,
    /// Mean |angular error| over its ticks, rad (θ̃ on a line, α − α_d on
    /// a spiral).
    pub angular_rad: f64,
    /// Largest |lateral error|, m.
    pub max_lateral_m: f64,
    /// Ticks measured.
    pub ticks: usize,
}

/// One goal reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    /// The goal.
    pub goal: Pose2<World>,
    /// The planner that led there.
    pub planner: Planner,
    /// Distance from the goal to the robot's longitudinal axis at rest
    /// (section 5.1), m.
    pub axis_m: f64,
    /// Distance from the goal to O at rest, m.
    pub distance_m: f64,
}

/// How a mission ended.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    /// Every goal reached.
    Done,
    /// Out of time.
    Timeout,
    /// A planner or controller refused (its reason).
    Refused(String),
}

/// One tick of the trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tick {
    /// Time, s.
    pub t_s: f64,
    /// True pose.
    pub truth: Pose2<World>,
    /// GNSS fix (drawn every tick; used only when `gnss_valid`).
    pub fix: Pose2<World>,
    /// Whether the fix was valid in this tick.
    pub gnss_valid: bool,
    /// Commanded linear and angular speed.
    pub command: (f64, f64),
    /// The goal being driven to (index), if any.
    pub goal: Option<usize>,
    /// True lateral error to the planned path, m, while moving on it.
    pub lateral_m: Option<f64>,
}

/// The result of a mission.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// How it ended.
    pub end: End,
    /// Every tick.
    pub ticks: Vec<Tick>,
    /// Each line or spiral followed.
    pub manoeuvres: Vec<Manoeuvre>,
    /// Each goal reached.
    pub reaches: Vec<Reach>,
    /// The planned paths, sampled.
    pub paths: Vec<Vec<(f64, f64)>>,
    /// The field's plants.
    pub plants: Vec<Stem>,
    /// Indices of the crop plants a track ran over.
    pub crushed: Vec<usize>,
    /// The mission's goals, each with its task.
    pub goals: Vec<RouteGoal>,
}

/// Mean and largest absolute value and count of a set of per-manoeuvre figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kpi {
    /// Mean of |x|.
    pub mean_abs: f64,
    /// Largest |x|.
    pub max_abs: f64,
    /// How many.
    pub count: usize,
}

impl Kpi {
    /// The indicator of `values` (mean and max 0 when empty).
    //= spec/emmi2024.md#em-sim-kpi-reach-lateral-and-angular-errors
    //# Each indicator MUST be summarised by the mean and the largest of the
    //# absolute per-manoeuvre values and their count.
    #[must_use]
    pub fn of(values: &[f64]) -> Self {
        let count = values.len();
        let sum: f64 = values.iter().map(|v| v.abs()).sum();
        let mean_abs = if count == 0 {
            0.0
        } else {
            sum / f64::from(u32::try_from(count).unwrap_or(u32::MAX))
        };
        let max_abs = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        Self {
            mean_abs,
            max_abs,
            count,
        }
    }

    /// As JSON.
    #[must_use]
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({"mean_abs": self.mean_abs, "max_abs": self.max_abs, "count": self.count})
    }
}

impl Outcome {
    /// Per-manoeuvre values of lines (`line`) or spirals, lateral or angular.
    #[must_use]
    pub fn values(&self, line: bool, lateral: bool) -> Vec<f64> {
        self.manoeuvres
            .iter()
            .filter(|m| matches!(m.kind, Kind::Line) == line)
            .map(|m| if lateral { m.lateral_m } else { m.angular_rad })
            .collect()
    }

    /// The reach errors (distance to the robot's axis), m.
    #[must_use]
    pub fn reach_values(&self) -> Vec<f64> {
        self.reaches.iter().map(|r| r.axis_m).collect()
    }

    /// `reach_error_m`.
    #[must_use]
    pub fn reach_error(&self) -> Kpi {
        Kpi::of(&self.reach_values())
    }

    /// `lateral_error_line_m`.
    #[must_use]
    pub fn lateral_line(&self) -> Kpi {
        Kpi::of(&self.values(true, true))
    }

    /// `lateral_error_spiral_m`.
    #[must_use]
    pub fn lateral_spiral(&self) -> Kpi {
        Kpi::of(&self.values(false, true))
    }

    /// `angular_error_line_rad`.
    #[must_use]
    pub fn angular_line(&self) -> Kpi {
        Kpi::of(&self.values(true, false))
    }

    /// `angular_error_spiral_rad`.
    #[must_use]
    pub fn angular_spiral(&self) -> Kpi {
        Kpi::of(&self.values(false, false))
    }
}

/// A planned path being driven.
struct Active {
    goal: usize,
    planner: Planner,
    path: ReferencePath<PATH_CAPACITY>,
    /// Each segment: its end along the path and its tracker.
    segments: Vec<(f64, f64, Tracker)>,
    profile: SpeedProfile,
    speed: SpeedState,
    s_fix: f64,
    s_true: f64,
    previous_y: Option<(usize, f64)>,
    /// The turning radius of the arcs, m.
    radius: f64,
    /// Per segment: (Σ|y|, Σ|angle|, max |y|, ticks).
    sums: Vec<(f64, f64, f64, usize)>,
}

/// Accumulates the ground-truth errors of segment `k`.
fn add(sums: &mut [(f64, f64, f64, usize)], k: usize, y: f64, a: f64) {
    if let Some(e) = sums.get_mut(k) {
        e.0 += y.abs();
        e.1 += a.abs();
        e.2 = e.2.max(y.abs());
        e.3 += 1;
    }
}

fn sample_path(path: &ReferencePath<PATH_CAPACITY>) -> Vec<(f64, f64)> {
    let n = 200_u32;
    let l = path.length().get();
    (0..=n)
        .filter_map(|k| {
            let s = l * f64::from(k) / f64::from(n);
            let p = path.point_at(Meters::new(s).ok()?).ok()?;
            Some((p.x(), p.y()))
        })
        .collect()
}

/// The speed profile of a path of `planner`: the turn speed with 0.3 m of
/// acceleration and braking on GoToGoal paths, the line speed with 1 m on
/// lines.
fn profile(c: &ControlSpec, planner: Planner) -> Result<SpeedProfile, Precondition> {
    let (v, ramp) = match planner {
        Planner::GoToGoal => (c.turn_speed, 0.3),
        Planner::LineFollowing => (c.line_speed, 1.0),
    };
    SpeedProfile::new(
        MetersPerSecond::new(c.threshold_speed.min(v))?,
        MetersPerSecond::new(v)?,
        Meters::new(ramp)?,
        Braking::Fixed(Meters::new(ramp)?),
        Meters::new(REACH_DISTANCE)?,
    )
}

/// Plans the path to goal `g` from the fix `fix` (the previous goal `from`
/// is the start of a LineFollowing line).
fn plan(
    run: &GuidingRun,
    vehicle: &SkidSteer,
    fix: &Pose2<World>,
    from: &Pose2<World>,
    goals: &[RouteGoal],
    g: usize,
) -> Result<Active, Precondition> {
    let RouteGoal { goal, task } = goals
        .get(g)
        .ok_or_else(|| Precondition::new("EM-PLANNER", "no such goal"))?;
    let planner = choose_planner(fix, &goal.pose, PlannerThreshold::DEFAULT);
    let c = &run.control;
    let (path, segments, profile, radius) = match planner {
        Planner::GoToGoal => {
            let radius = TurningRadius::for_vehicle(Meters::new(goal.radius_m)?, vehicle)?;
            let turn = match run.outline(*task).filter(|_| run.stay_inside) {
                Some(outline) => {
                    boundary::shortest_inside(fix, &goal.pose, radius, &outline, &run.robot)?
                }
                None => shortest(fix, &goal.pose, radius)?,
            };
            let path: ReferencePath<PATH_CAPACITY> =
                turn.to_reference_path(Meters::new(PATH_SPACING_M)?)?;
            let segments = tracked_segments(&turn);
            let profile = profile(c, Planner::GoToGoal)?;
            (path, segments, profile, goal.radius_m)
        }
        Planner::LineFollowing => {
            let path: ReferencePath<PATH_CAPACITY> = ReferencePath::from_exact([
                (*from, Curvature::ZERO),
                (goal.pose, Curvature::ZERO),
            ])?;
            let l = path.length().get();
            let profile = profile(c, Planner::LineFollowing)?;
            (path, vec![(0.0, l, Tracker::Lateral)], profile, 0.0)
        }
    };
    let n = segments.len();
    Ok(Active {
        goal: g,
        planner,
        path,
        segments,
        profile,
        speed: SpeedState::Moving,
        s_fix: 0.0,
        s_true: 0.0,
        previous_y: None,
        radius,
        sums: vec![(0.0, 0.0, 0.0, 0); n],
    })
}

/// Each segment of a Dubins path: where it starts and ends along the path,
/// and the controller that tracks it (`tracker_for`, EM-TRACKER).
pub(crate) fn tracked_segments(
    path: &fieldguide::planning::dubins::DubinsPath,
) -> Vec<(f64, f64, Tracker)> {
    let mut end = 0.0;
    path.segments()
        .iter()
        .map(|seg| {
            end += seg.length.get();
            (end - seg.length.get(), end, tracker_for(seg))
        })
        .collect()
}

/// The segment index at abscissa `s`.
fn segment_at(segments: &[(f64, f64, Tracker)], s: f64) -> usize {
    segments
        .iter()
        .position(|&(_, end, _)| s < end)
        .unwrap_or(segments.len().saturating_sub(1))
}

fn wrap(a: f64) -> f64 {
    Radians::new(a).map_or(0.0, |r| r.wrapped().get())
}

/// Marks the crop plants under either track at `pose`.
fn mark_crushed(
    index: &PlantIndex,
    robot: &RobotSpec,
    pose: &Pose2<World>,
    crushed: &mut [bool],
    near: &mut Vec<usize>,
) {
    let half_l = robot.length_m / 2.0;
    let half_w = robot.track_width_m / 2.0;
    let reach = half_l.hypot(robot.track_m / 2.0 + half_w) + index.max_radius();
    let (x, y) = (pose.position.x(), pose.position.y());
    index.query((x - reach, y - reach), (x + reach, y + reach), near);
    let (s, c) = pose.heading.get().sin_cos();
    for &i in near.iter() {
        let (Some(p), Some(hit)) = (index.plants().get(i), crushed.get_mut(i)) else {
            continue;
        };
        let (dx, dy) = (p.position.x() - x, p.position.y() - y);
        let (along, across) = (dx * c + dy * s, -dx * s + dy * c);
        let under = |centre: f64| (across - centre).abs() <= half_w + p.radius;
        if p.kind == PlantKind::Crop
            && along.abs() <= half_l + p.radius
            && (under(robot.track_m / 2.0) || under(-robot.track_m / 2.0))
        {
            *hit = true;
        }
    }
}

/// The command (m/s, rad/s), the true lateral error, whether stopped.
type Steer = ((f64, f64), Option<f64>, bool);

/// The controllers of a run: the vehicle, the lateral PD and the spiral.
struct Controllers {
    vehicle: SkidSteer,
    lateral: LateralPd,
    spiral: Spiral,
}

impl Controllers {
    /// The controllers of `run`'s robot and settings.
    fn of(run: &GuidingRun) -> Result<Self, Precondition> {
        let r = &run.robot;
        let vehicle = SkidSteer::new(
            Meters::new(r.track_m)?,
            MetersPerSecond::new(r.max_track_speed)?,
        )?;
        let g = run.control.lateral_gains;
        let lateral = LateralPd {
            gains: LateralGains::new(g[0], g[1], g[2], g[3], g[4])?,
            control_point: Meters::new(run.control.control_point_m)?,
            vehicle,
        };
        let spiral = Spiral::new(run.control.spiral_lambda, Radians::ZERO, vehicle)?;
        Ok(Self {
            vehicle,
            lateral,
            spiral,
        })
    }
}

/// One tick along the active path `a` from the fix: the command (m/s,
/// rad/s), the true lateral error, and whether the speed profile stopped
/// at the path's end.
fn steer(
    run: &GuidingRun,
    ctl: &Controllers,
    a: &mut Active,
    fix: &Pose2<World>,
    truth: &Pose2<World>,
) -> Result<Steer, Precondition> {
    let (lateral, spiral) = (&ctl.lateral, &ctl.spiral);
    let mut command = (0.0, 0.0);
    let mut lateral_now = None;
    let mut finished = false;
    let window = Meters::new(0.5)?;
    let f = a
        .path
        .project_near(fix, Meters::ZERO, Meters::new(a.s_fix)?, window)?;
    a.s_fix = f.s.get();
    let length = a.path.length().get();
    let (next, speed) = a.profile.step(
        a.speed,
        Meters::new(a.s_fix.max(0.0))?,
        Meters::new(length - a.s_fix)?,
    );
    a.speed = next;
    match speed {
        SpeedCommand::Stop => finished = true,
        SpeedCommand::Go(v) => {
            let k = segment_at(&a.segments, a.s_fix);
            let tracker = a.segments.get(k).map_or(Tracker::Lateral, |s| s.2);
            let saturated = match tracker {
                Tracker::Lateral => {
                    let mut e = f.tracking_error();
                    if run.fault == Some(Fault::FlippedLateralGain) {
                        e.y = Meters::new(-e.y.get())?;
                    }
                    let y_cp = lateral.control_point_error(&e)?;
                    let rate = match a.previous_y {
                        Some((pk, py)) if pk == k => LateralRate::between_ticks(
                            Meters::new(py)?,
                            y_cp,
                            Seconds::new(PERIOD_S)?,
                        )?,
                        _ => LateralRate::ZERO,
                    };
                    a.previous_y = Some((k, y_cp.get()));
                    lateral.command(&e, &rate, v)?
                }
                Tracker::Spiral {
                    centre,
                    desired_angle,
                } => {
                    a.previous_y = None;
                    let law = if run.fault == Some(Fault::FlippedSpiralGain) {
                        // α_d reflected about α: e changes sign.
                        let alpha = spiral_state(fix, centre)?.angle.get();
                        spiral.towards(Radians::new(2.0 * alpha - desired_angle.get())?)
                    } else {
                        spiral.towards(desired_angle)
                    };
                    spiral_command(&law, fix, centre, v)?
                }
            };
            if let Command::SkidSteer { speed, yaw_rate } = saturated.command {
                command = (speed.get(), yaw_rate.get());
            }
            // Ground truth: the true pose against the planned path.
            //= spec/emmi2024.md#em-sim-kpi-reach-lateral-and-angular-errors
            //# The lateral error of a line MUST be the signed distance of the true pose to
            //# the planned straight, and of a spiral |d − r|, d the true distance to the
            //# arc's centre and r its radius; the angular error of a line MUST be the true
            //# heading minus the path's, and of a spiral wrap(α − α_d) from the true pose.
            let tf = a
                .path
                .project_near(truth, Meters::ZERO, Meters::new(a.s_true)?, window)?;
            a.s_true = tf.s.get();
            let kt = segment_at(&a.segments, a.s_true);
            match a.segments.get(kt).map(|s| s.2) {
                Some(Tracker::Spiral {
                    centre,
                    desired_angle,
                }) => {
                    let st = spiral_state(truth, centre)?;
                    let radius = a.radius;
                    let y = st.distance.get() - radius;
                    let e = wrap(st.angle.get() - desired_angle.get());
                    add(&mut a.sums, kt, y, e);
                    lateral_now = Some(y);
                }
                _ => {
                    let y = tf.y.get();
                    add(&mut a.sums, kt, y, tf.angular_deviation.get());
                    lateral_now = Some(y);
                }
            }
        }
    }
    Ok((command, lateral_now, finished))
}

/// Ends the path `a`: the figures of each of its segments long enough to
/// count as a manoeuvre.
fn close_manoeuvres(a: &Active, manoeuvres: &mut Vec<Manoeuvre>) {
    for (k, &(s0, s1, tracker)) in a.segments.iter().enumerate() {
        let Some(&(sy, sa, my, n)) = a.sums.get(k) else {
            continue;
        };
        if s1 - s0 < MIN_MANOEUVRE_M || n == 0 {
            continue;
        }
        let nf = f64::from(u32::try_from(n).unwrap_or(u32::MAX));
        manoeuvres.push(Manoeuvre {
            kind: match tracker {
                Tracker::Lateral => Kind::Line,
                Tracker::Spiral { .. } => Kind::Spiral(a.radius),
            },
            lateral_m: sy / nf,
            angular_rad: sa / nf,
            max_lateral_m: my,
            ticks: n,
        });
    }
}

/// Drives the mission of `run`.
//= spec/emmi2024.md#em-sim-figures-closed-loop-figures
//# Over every seed of a sweep of at least five, a built-in mission MUST reach
//# every goal without a track running over a crop plant, with a mean lateral
//# error on lines of at most 0.038 m and on spirals of at most 0.06 m, a mean
//# reach error of at most 0.045 m and a mean absolute angular error on
//# spirals of at most 0.0103 rad.
//= spec/emmi2024.md#em-sim-figures-closed-loop-figures
//# Fields of our own MUST meet the same figures: other row spacing and row
//# length, a faster robot, a noisier GNSS.
#[must_use]
pub fn drive(run: &GuidingRun) -> Outcome {
    let mut rng = SimRng::from_seed(run.seed);
    let plants = run.plants(&mut rng);
    let goals = run.route();
    let mut outcome = Outcome {
        end: End::Done,
        ticks: Vec::new(),
        manoeuvres: Vec::new(),
        reaches: Vec::new(),
        paths: Vec::new(),
        plants: plants.clone(),
        crushed: Vec::new(),
        goals: Vec::new(),
    };
    match goals {
        Ok(goals) => {
            outcome.goals.clone_from(&goals);
            if let Err(e) = drive_in(run, &plants, &goals, &mut rng, &mut outcome) {
                outcome.end = End::Refused(e.to_string());
            }
        }
        Err(e) => outcome.end = End::Refused(e.to_string()),
    }
    outcome
}

#[allow(clippy::too_many_lines)]
fn drive_in(
    run: &GuidingRun,
    plants: &[Stem],
    goals: &[RouteGoal],
    rng: &mut SimRng,
    out: &mut Outcome,
) -> Result<(), Precondition> {
    let ctl = Controllers::of(run)?;
    let r = &run.robot;
    let vehicle = ctl.vehicle;
    let plant = r.plant();
    let terrain = Terrain::default();
    let index = PlantIndex::new(plants.to_vec(), 0.5);
    let mut crushed = vec![false; plants.len()];
    let mut near = Vec::new();
    let (start, mut from) = run.starts()?;
    let mut state = VehicleState::at(start, &terrain);
    let mut next_goal = 0_usize;
    let mut active: Option<Active> = None;
    let mut rest_until = 0.0_f64;
    let mut pending: Option<(usize, Planner)> = None;
    let max_ticks = (run.duration_s / PERIOD_S).ceil().clamp(0.0, 1e7);
    let mut tick = 0.0_f64;
    loop {
        let t = tick * PERIOD_S;
        if tick > max_ticks {
            out.end = End::Timeout;
            break;
        }
        tick += 1.0;
        let truth = state.pose;
        let fix = Pose2::<World>::new(
            truth.position.x() + rng.gaussian(run.gnss_sigma_m),
            truth.position.y() + rng.gaussian(run.gnss_sigma_m),
            truth.heading.get() + rng.gaussian(run.gnss_heading_sigma_rad),
        )?;
        mark_crushed(&index, r, &truth, &mut crushed, &mut near);
        //= spec/emmi2024.md#em-sim-gnss-lost-no-fix-no-motion
        //# While the GNSS has no fix the robot MUST be commanded to stand still,
        //# and the mission MUST go on from the next fix.
        if run.gnss_outage_s.is_some_and(|(a, b)| (a..b).contains(&t)) {
            out.ticks.push(Tick {
                t_s: t,
                truth,
                fix,
                gnss_valid: false,
                command: (0.0, 0.0),
                goal: active.as_ref().map(|a| a.goal),
                lateral_m: None,
            });
            let stop = Command::SkidSteer {
                speed: MetersPerSecond::ZERO,
                yaw_rate: RadiansPerSecond::ZERO,
            };
            state = plant.advance(&state, &stop, &terrain, PERIOD_S, SUBSTEPS)?;
            // The rest at a goal lasts a second of valid fixes.
            rest_until += PERIOD_S;
            continue;
        }
        // At rest after a goal: measure the reach error once the rest is over.
        //= spec/emmi2024.md#em-sim-kpi-reach-lateral-and-angular-errors
        //# Each goal's reach error MUST be the distance from the goal to the robot's
        //# longitudinal axis, from the true pose once the robot has rested at the goal.
        if let Some((gi, planner)) = pending {
            if t + 1e-9 >= rest_until {
                if let Some(RouteGoal { goal, .. }) = goals.get(gi) {
                    let (dx, dy) = (
                        goal.pose.position.x() - truth.position.x(),
                        goal.pose.position.y() - truth.position.y(),
                    );
                    let (s, c) = truth.heading.get().sin_cos();
                    out.reaches.push(Reach {
                        goal: goal.pose,
                        planner,
                        axis_m: (-dx * s + dy * c).abs(),
                        distance_m: dx.hypot(dy),
                    });
                    from = goal.pose;
                }
                pending = None;
            }
        }
        let command = (0.0, 0.0);
        if pending.is_none() && active.is_none() {
            if next_goal >= goals.len() {
                out.end = End::Done;
                out.ticks.push(Tick {
                    t_s: t,
                    truth,
                    fix,
                    gnss_valid: true,
                    command,
                    goal: None,
                    lateral_m: None,
                });
                break;
            }
            let a = plan(run, &vehicle, &fix, &from, goals, next_goal)?;
            out.paths.push(sample_path(&a.path));
            active = Some(a);
            next_goal += 1;
        }
        let (command, lateral_now, finished) = match active.as_mut() {
            Some(a) => steer(run, &ctl, a, &fix, &truth)?,
            None => ((0.0, 0.0), None, false),
        };
        if finished {
            if let Some(a) = active.take() {
                close_manoeuvres(&a, &mut out.manoeuvres);
                pending = Some((a.goal, a.planner));
                rest_until = t + REST_S;
            }
        }
        out.ticks.push(Tick {
            t_s: t,
            truth,
            fix,
            gnss_valid: true,
            command,
            goal: active.as_ref().map(|a| a.goal),
            lateral_m: lateral_now,
        });
        let cmd = Command::SkidSteer {
            speed: MetersPerSecond::new(command.0)?,
            yaw_rate: RadiansPerSecond::new(command.1)?,
        };
        state = plant.advance(&state, &cmd, &terrain, PERIOD_S, SUBSTEPS)?;
    }
    out.crushed = crushed
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.then_some(i))
        .collect();
    Ok(())
}

/// The trace of a mission: one line per tick.
#[must_use]
pub fn trace_csv(outcome: &Outcome) -> String {
    let mut csv = String::from(
        "t_s,x_m,y_m,heading_rad,gnss_valid,fix_x_m,fix_y_m,fix_heading_rad,v_mps,w_radps,goal,lateral_m\n",
    );
    for t in &outcome.ticks {
        let _ = writeln!(
            csv,
            "{:.2},{:.5},{:.5},{:.5},{},{:.5},{:.5},{:.5},{:.4},{:.4},{},{}",
            t.t_s,
            t.truth.position.x(),
            t.truth.position.y(),
            t.truth.heading.get(),
            t.gnss_valid,
            t.fix.position.x(),
            t.fix.position.y(),
            t.fix.heading.get(),
            t.command.0,
            t.command.1,
            t.goal.map_or(String::new(), |g| g.to_string()),
            t.lateral_m.map_or(String::new(), |y| format!("{y:.5}")),
        );
    }
    csv
}

/// The end's label.
#[must_use]
pub fn end_label(end: &End) -> String {
    match end {
        End::Done => "done".to_owned(),
        End::Timeout => "out of time".to_owned(),
        End::Refused(why) => format!("refused: {why}"),
    }
}

/// One task of a mission as driven: its goals, time and distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskRecord {
    /// The road or field.
    pub task: Task,
    /// Its goals reached.
    pub goals_reached: usize,
    /// From planning its first goal to planning the next task's, s.
    pub duration_s: f64,
    /// The true distance travelled, m.
    pub distance_m: f64,
}

impl Outcome {
    /// The task each tick belongs to: that of the goal being driven to, or
    /// of the last one while resting.
    #[must_use]
    pub fn tick_tasks(&self) -> Vec<Option<Task>> {
        let mut last = None;
        self.ticks
            .iter()
            .map(|t| {
                if let Some(g) = t.goal.and_then(|g| self.goals.get(g)) {
                    last = Some(g.task);
                }
                last
            })
            .collect()
    }

    /// Each task in the order driven.
    #[must_use]
    pub fn tasks(&self) -> Vec<TaskRecord> {
        let mut out: Vec<TaskRecord> = Vec::new();
        let tasks = self.tick_tasks();
        for (w, task) in self.ticks.windows(2).zip(&tasks) {
            let Some(task) = *task else { continue };
            let step = (w[1].truth.position.x() - w[0].truth.position.x())
                .hypot(w[1].truth.position.y() - w[0].truth.position.y());
            match out.last_mut() {
                Some(r) if r.task == task => {
                    r.duration_s += w[1].t_s - w[0].t_s;
                    r.distance_m += step;
                }
                _ => out.push(TaskRecord {
                    task,
                    goals_reached: 0,
                    duration_s: w[1].t_s - w[0].t_s,
                    distance_m: step,
                }),
            }
        }
        let mut reached = self.reaches.len();
        let mut g = 0;
        for r in &mut out {
            while reached > 0 && self.goals.get(g).is_some_and(|x| x.task == r.task) {
                r.goals_reached += 1;
                reached -= 1;
                g += 1;
            }
        }
        out
    }

    /// Per tick on a road, the true distance of O to the road's centreline,
    /// m (empty without a farm).
    #[must_use]
    pub fn road_offsets(&self, run: &GuidingRun) -> Vec<f64> {
        let Some(lines) = run.farm.as_ref().and_then(|f| f.road_polylines().ok()) else {
            return Vec::new();
        };
        self.ticks
            .iter()
            .zip(self.tick_tasks())
            .filter_map(|(t, task)| match task {
                Some(Task::Road(k)) => lines.get(k).map(|line| {
                    Farm::distance_to_road(line, (t.truth.position.x(), t.truth.position.y()))
                }),
                _ => None,
            })
            .collect()
    }
}

/// A mission's figures as JSON.
#[must_use]
pub fn summary_json(run: &GuidingRun, outcome: &Outcome) -> serde_json::Value {
    serde_json::json!({
        "scenario": run.name,
        "seed": run.seed,
        "end": end_label(&outcome.end),
        "goals": outcome.goals.len(),
        "goals_reached": outcome.reaches.len(),
        "plants_crushed": outcome.crushed.len(),
        "reach_error_m": outcome.reach_error().json(),
        "reach_distance_m": Kpi::of(&outcome.reaches.iter().map(|r| r.distance_m).collect::<Vec<_>>()).json(),
        "lateral_error_line_m": outcome.lateral_line().json(),
        "lateral_error_spiral_m": outcome.lateral_spiral().json(),
        "angular_error_line_rad": outcome.angular_line().json(),
        "angular_error_spiral_rad": outcome.angular_spiral().json(),
        "duration_s": outcome.ticks.last().map_or(0.0, |t| t.t_s),
        "road_offset_m": Kpi::of(&outcome.road_offsets(run)).json(),
        "tasks": outcome.tasks().iter().map(|r| {
            let (kind, index) = match r.task {
                Task::Road(k) => ("approximation", k),
                Task::Field(k) => ("treatment", k),
            };
            serde_json::json!({
                "kind": kind,
                "index": index,
                "goals_reached": r.goals_reached,
                "duration_s": r.duration_s,
                "distance_m": r.distance_m,
            })
        }).collect::<Vec<_>>(),
    })
}

/// Writes `trace.csv`, `summary.json`, `trajectory.svg` and the histograms
/// of a mission into `out/<run name>/`; returns the folder.
pub fn write_mission(out: &Path, run: &GuidingRun, outcome: &Outcome) -> Result<PathBuf, SimError> {
    let dir = out.join(&run.name);
    let mut files = vec![
        ("trace.csv", trace_csv(outcome)),
        (
            "summary.json",
            serde_json::to_string_pretty(&summary_json(run, outcome)).unwrap_or_default(),
        ),
        ("trajectory.svg", plot::trajectory_svg(run, outcome)),
    ];
    files.extend(plot::histograms(outcome));
    crate::output::write_files(&dir, &files)?;
    Ok(dir)
}
