//! A vine row followed by a straddling four-wheel-steering robot (Iberraken
//! 2022, section 3): the inclined 2D LiDAR at Table 1's mount, the core's
//! `perception::vine::VineDetector`, strategy 1 or 2 of
//! `control::four_ws`, and the [`crate::plant::FourWsPlant`].
//!
//! One tick at 20 Hz: the LiDAR ray-casts the vineyard ([`field`]) from the
//! true pose over the sloping, bumpy ground; the detector reads the scan and
//! the wheel odometry (with drift); the law's angles drive the plant, which
//! slides with the terrain's sideslip. The robot enters the row as a real
//! one would (the paper's conclusion: the row's surveyed ends and GNSS for
//! the transition, the LiDAR inside the row): the core's switching machine
//! (Pierre 2022, section 3) starts in path tracking on the surveyed row
//! line, the same law fed by the GNSS pose, and enters vine following once
//! the detector's verdict has been Enter, its line consistent with the
//! surveyed one, for [`ENTER_DELAY_S`]. Errors are measured against the
//! true row centre line (y = 0, along x), never the robot's estimate: the lateral deviation of R
//! and the heading. A vine is touched when a wheel's contact patch meets a
//! trunk or a post. [`turns`] runs the same robot and vineyard through the
//! core's switching pipeline, with a headland turn.

pub mod field;
pub mod file;
pub mod plot;
pub mod turns;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use fieldguide::control::four_ws::{
    strategy1_command, strategy2_command, Objectives, RearSteering, Strategy1, Strategy1Gains,
    Strategy2, Strategy2Gains,
};
use fieldguide::model::bicycle::{Sideslip, SteeringLimit, Wheelbase};
use fieldguide::model::four_ws::FourWheelSteering;
use fieldguide::model::Command;
use fieldguide::perception::vine::{VineConfig, VineDetector, VineParams};
use fieldguide::supervisor::switching::{
    BehaviourConfig, CommandSource, Input, PathAhead, PlanTolerance, Report, Switching,
    SwitchingConfig,
};
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Odom, Pose2, Radians, Seconds, TrackingError, World,
};

use crate::error::SimError;
use crate::lidar::inclined::InclinedLidar;
use crate::odometry::OdometryErrors;
use crate::plant::{FourWsPlant, Plant, SteeringActuator, VehicleState};
use crate::rng::SimRng;
use crate::world::crops::PlantIndex;
use crate::world::scene::Scene;
use crate::world::terrain::{SlipPatch, Terrain};
use crate::world::Plant as Stem;
use field::{Season, VineyardSpec};

/// The control period, s (20 Hz).
pub const PERIOD_S: f64 = 0.05;
/// The wheelbase L, m.
pub const WHEELBASE_M: f64 = 1.2;
/// The track (between the left and right wheels), m: with the right wheel
/// over the row, the robot's centre is 0.7 m from it (section 3).
pub const TRACK_M: f64 = 1.4;
/// A tyre's width and contact length, m.
pub const TYRE_M: (f64, f64) = (0.25, 0.4);
/// Rays the detector may see in its field of view.
pub const RAYS: usize = 128;
/// The detector's set-point capacity.
pub const POINTS: usize = 128;

/// The row's entry, m: the vines and posts before it are counted apart
/// ([`VineOutcome::touched_in_row`] leaves them out).
pub const ENTRY_M: f64 = 3.0;
/// How long the detector's verdict must be Enter, its line consistent with
/// the surveyed row, before the robot follows the vines, s.
pub const ENTER_DELAY_S: f64 = 1.0;
/// How long an Exit or Absent verdict lasts before the robot goes back to
/// path tracking on the surveyed row, s.
pub const EXIT_DELAY_S: f64 = 0.5;
/// The vine line's largest offset (m) and heading difference (rad) to the
/// surveyed row line for them to agree.
pub const PLAN_TOLERANCE: (f64, f64) = (0.5, 0.3);

/// The control law of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Strategy 1, backstepping position/orientation (eqs. 9-16).
    One,
    /// Strategy 2, front and rear lateral errors (eqs. 17-23).
    Two,
    /// Strategy 1 with the rear steering held at 0: two-wheel steering.
    TwoWheel,
}

impl Strategy {
    /// Its name in files and reports.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::One => "s1",
            Self::Two => "s2",
            Self::TwoWheel => "2ws",
        }
    }
}

/// A fault put into the loop to show that the checks bite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The law reads the lateral deviation negated: the sign of its lateral
    /// gain (k_y, or K_R and K_F on the lateral part) flipped. In the run
    /// with turns, where the law is inside the core pipeline, its angles are
    /// negated: every gain's sign flipped.
    FlippedLateralGain,
}

/// One run: the vineyard, the law, the robot and its imperfections.
#[derive(Debug, Clone, PartialEq)]
pub struct VineyardRun {
    /// The run's name (output folder).
    pub name: String,
    /// The vineyard.
    pub field: VineyardSpec,
    /// The law.
    pub strategy: Strategy,
    /// Strategy 1's gains (k_y, k_θ, k_r), equation form.
    pub gains1: (f64, f64, f64),
    /// Strategy 2's gains (K_F, K_R).
    pub gains2: (f64, f64),
    /// The seed of the vineyard's generation and of every noise.
    pub seed: u64,
    /// The forward speed, m/s.
    pub speed_mps: f64,
    /// Both steering actuators: 5 % settling time, s, rate limit, rad/s,
    /// saturation, rad.
    pub steering: (f64, f64, f64),
    /// The sideslip of the ground (front, rear), rad, everywhere.
    pub sideslip: (f64, f64),
    /// A stretch of low grip: from x, to x, m, and its sideslip (both axles), rad.
    pub low_grip: Option<(f64, f64, f64)>,
    /// Whether the law is given the true sideslip (an observer's estimate,
    /// section 2.2.1) or none.
    pub sideslip_known: bool,
    /// The wheel odometry's errors.
    pub odometry: OdometryErrors,
    /// The LiDAR's angular resolution, degrees.
    pub lidar_resolution_deg: f64,
    /// The LiDAR's range noise σ, m.
    pub lidar_noise_m: f64,
    /// The detector's model margin, rays each side.
    pub model_margin: usize,
    /// The start: the front axle this far before the row's first vine, m,
    /// and R this far left of the row centre line, m.
    pub start: (f64, f64),
    /// Errors are summarised once R is this far along the row, m.
    pub settle_m: f64,
    /// The run ends when R is this far before the row's end, m.
    pub stop_before_end_m: f64,
    /// The GNSS pose's noise σ: position (m), heading (rad).
    pub gnss_noise: (f64, f64),
    /// A fault, for the tests that show the checks bite.
    pub fault: Option<Fault>,
    /// Whether the run follows row 0, turns in the headland and follows
    /// row 2 back, switched by the core pipeline ([`turns`]).
    pub turns: bool,
}

impl VineyardRun {
    /// The paper's run in `season` with `strategy` and `seed` (section 3):
    /// 1 m/s; Table 1's gains with k_r = 3 k_θ for strategy 1 (k_r = k_θ
    /// only cancels β_R: the rear axle would not act on the orientation);
    /// actuators settling in 0.3 s, 1 rad/s, ±0.5 rad; a 0.03 rad sideslip
    /// on both axles (a cross slope), given to the law; odometry 0.5 % long
    /// drifting 0.002 rad/m; a 1.5° LiDAR with 1 cm of noise and model
    /// margins of 3 rays; the front axle 1.5 m before the row, R 0.7 m left
    /// of it; an RTK GNSS pose within 2 cm and 0.01 rad (σ) for the entry;
    /// errors after 10 m; the run ends 3 m before the row's end.
    #[must_use]
    pub fn paper(season: Season, strategy: Strategy, seed: u64) -> Self {
        Self {
            name: format!("vineyard-{}-{}", season.name(), strategy.name()),
            field: VineyardSpec::paper(season),
            strategy,
            gains1: (-0.9, -1.0, -3.0),
            gains2: (0.35, 0.35),
            seed,
            speed_mps: 1.0,
            steering: (0.3, 1.0, 0.5),
            sideslip: (0.03, 0.03),
            low_grip: Some((25.0, 32.0, 0.08)),
            sideslip_known: true,
            odometry: OdometryErrors {
                scale: 0.005,
                yaw_drift: 0.002,
                distance_noise: 0.002,
                yaw_noise: 0.002,
            },
            lidar_resolution_deg: 1.5,
            lidar_noise_m: 0.01,
            model_margin: 3,
            start: (1.5, 0.7),
            settle_m: 10.0,
            stop_before_end_m: 3.0,
            gnss_noise: (0.02, 0.01),
            fault: None,
            turns: false,
        }
    }

    /// The inclined LiDAR at Table 1's mount (x = 1.0 m, y = 0, z = 2.0 m,
    /// pitched 45°), rays `lidar_resolution_deg` apart over ±45° (the
    /// sensor covers more; the detector reads ±30° of it), 20 m.
    #[must_use]
    pub fn lidar(&self) -> InclinedLidar {
        let step = self.lidar_resolution_deg.to_radians();
        let rays = 2 * (45.0 / self.lidar_resolution_deg).round() as usize + 1;
        InclinedLidar {
            mount_x: 1.0,
            mount_y: 0.0,
            height: 2.0,
            pitch: core::f64::consts::FRAC_PI_4,
            field_of_view: step * (rays as f64 - 1.0),
            rays,
            range_min: 0.05,
            range_max: 20.0,
            range_noise: self.lidar_noise_m,
        }
    }

    /// The detector's parameters: Table 1 of the season, margins of
    /// `model_margin` rays.
    #[must_use]
    pub fn vine_params(&self) -> VineParams {
        let mut p = match self.field.season {
            Season::Summer => VineParams::summer(),
            Season::Winter => VineParams::winter(),
        };
        p.model_margin = self.model_margin;
        p.seed = self.seed;
        p
    }
}

/// One tick of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineTick {
    /// Time, s.
    pub t_s: f64,
    /// The true pose of R.
    pub truth: Pose2<World>,
    /// The lateral deviation of R from the true row centre line, m, left positive.
    pub lateral_m: f64,
    /// The heading relative to the row, rad.
    pub angular_rad: f64,
    /// How far R is along the row it drives, from the row's start in its
    /// direction of travel, m; negative outside the rows.
    pub along_m: f64,
    /// Whether the switching pipeline followed the vines (runs with turns).
    pub following: Option<bool>,
    /// The actual front and rear steering angles, rad.
    pub steering: (f64, f64),
    /// The detector's estimate (lateral, angular), when it had a line.
    pub estimate: Option<(f64, f64)>,
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum VineEnd {
    /// R reached the end of the row.
    Done,
    /// The core refused a value.
    Aborted(String),
}

/// A run's trace and figures.
#[derive(Debug, Clone, PartialEq)]
pub struct VineOutcome {
    /// One record per tick.
    pub ticks: Vec<VineTick>,
    /// Why it ended.
    pub end: VineEnd,
    /// Trunks and posts a wheel met.
    pub touched: usize,
    /// Those of them at least [`ENTRY_M`] into the row.
    pub touched_in_row: usize,
    /// The canopies and posts (as the LiDAR sees them).
    pub plants: Vec<Stem>,
    /// Ticks with a row line.
    pub detected: usize,
}

/// Summary figures after stabilisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settled {
    /// Largest |lateral deviation|, m.
    pub lateral_max_abs: f64,
    /// Mean |lateral deviation|, m.
    pub lateral_mean_abs: f64,
    /// Largest |angular deviation|, rad.
    pub angular_max_abs: f64,
    /// Mean |angular deviation|, rad.
    pub angular_mean_abs: f64,
}

impl VineOutcome {
    /// The outcome of a loop that recorded `ticks` and ended with `end`:
    /// `touched` marks the trunks and posts of `solid` a wheel met, `seen`
    /// is what the LiDAR saw, `detected` the ticks with a row line.
    pub(crate) fn of(
        ticks: Vec<VineTick>,
        end: VineEnd,
        touched: &[bool],
        solid: &[Stem],
        seen: &[Stem],
        detected: usize,
    ) -> Self {
        Self {
            ticks,
            end,
            touched: touched.iter().filter(|t| **t).count(),
            touched_in_row: touched
                .iter()
                .zip(solid)
                .filter(|(t, p)| **t && p.position.x() >= ENTRY_M)
                .count(),
            plants: seen.to_vec(),
            detected,
        }
    }

    /// The errors once R is `settle_m` along the row.
    #[must_use]
    pub fn settled(&self, settle_m: f64) -> Option<Settled> {
        let after: Vec<&VineTick> = self
            .ticks
            .iter()
            .filter(|t| t.along_m >= settle_m)
            .collect();
        if after.is_empty() {
            return None;
        }
        let n = after.len() as f64;
        let max = |f: fn(&VineTick) -> f64| after.iter().map(|t| f(t).abs()).fold(0.0, f64::max);
        let mean = |f: fn(&VineTick) -> f64| after.iter().map(|t| f(t).abs()).sum::<f64>() / n;
        Some(Settled {
            lateral_max_abs: max(|t| t.lateral_m),
            lateral_mean_abs: mean(|t| t.lateral_m),
            angular_max_abs: max(|t| t.angular_rad),
            angular_mean_abs: mean(|t| t.angular_rad),
        })
    }

    /// The largest |rear steering angle| of the run, rad.
    #[must_use]
    pub fn rear_max_abs(&self) -> f64 {
        self.ticks
            .iter()
            .map(|t| t.steering.1.abs())
            .fold(0.0, f64::max)
    }

    /// Whether R reached the end of the row touching no vine from the start.
    #[must_use]
    pub fn success(&self) -> bool {
        self.end == VineEnd::Done && self.touched == 0
    }
}

/// Runs `run`.
//= spec/iberraken2022.md#fws-closed-loop-vine-row-held-against-the-true-row
//# Once R is 10 m into the row, a robot following a vine row with four-wheel
//# steering MUST stay within 0.03 m of the true row centre line, in summer and
//# in winter, with either strategy.
//= spec/iberraken2022.md#fws-closed-loop-vine-row-held-against-the-true-row
//# Its angular deviation to the true row
//# MUST stay within 0.03 rad with strategy 1 and within 0.06 rad with
//# strategy 2.
//= spec/iberraken2022.md#fws-2ws-comparison-two-wheel-steering-turns-the-robot-more
//# With the rear steering held at 0, the robot's angular deviation to the true
//# row after stabilisation MUST be larger than with strategy 1 on the same
//# field and seed.
#[must_use]
pub fn drive(run: &VineyardRun) -> VineOutcome {
    let mut rng = SimRng::from_seed(run.seed);
    let (seen, solid) = run.field.generate(&mut rng);
    let result = if run.turns {
        turns::drive_in(run, &seen, &solid, &mut rng)
    } else {
        drive_in(run, &seen, &solid, &mut rng)
    };
    match result {
        Ok(outcome) => outcome,
        Err(e) => VineOutcome {
            ticks: Vec::new(),
            end: VineEnd::Aborted(e),
            touched: 0,
            touched_in_row: 0,
            plants: seen,
            detected: 0,
        },
    }
}

/// The law of a run, either strategy.
enum Law {
    One(Strategy1),
    Two(Strategy2),
}

fn law(run: &VineyardRun, vehicle: FourWheelSteering) -> Result<Law, String> {
    let (k_y, k_t, k_r) = run.gains1;
    Ok(match run.strategy {
        Strategy::One | Strategy::TwoWheel => Law::One(Strategy1 {
            gains: Strategy1Gains::new(k_y, k_t, k_r, 1.0).map_err(|e| e.to_string())?,
            vehicle,
            rear: if run.strategy == Strategy::One {
                RearSteering::Backstepping
            } else {
                RearSteering::Held
            },
        }),
        Strategy::Two => Law::Two(Strategy2 {
            gains: Strategy2Gains::new(run.gains2.0, run.gains2.1).map_err(|e| e.to_string())?,
            vehicle,
        }),
    })
}

fn drive_in(
    run: &VineyardRun,
    seen: &[Stem],
    solid: &[Stem],
    rng: &mut SimRng,
) -> Result<VineOutcome, String> {
    let s = |e: fieldguide::Precondition| e.to_string();
    let limit = SteeringLimit::new(run.steering.2).map_err(s)?;
    let actuator = SteeringActuator::from_settling(run.steering.0, run.steering.1, limit);
    let wheelbase = Wheelbase::new(WHEELBASE_M).map_err(s)?;
    let plant = FourWsPlant {
        wheelbase,
        front: actuator,
        rear: actuator,
    };
    let vehicle = FourWheelSteering::new(wheelbase, limit, limit, None, None).map_err(s)?;
    let law = law(run, vehicle)?;
    let config = VineConfig::new(&run.vine_params()).map_err(s)?;
    let mut detector = VineDetector::<RAYS, POINTS>::new(config).map_err(s)?;
    let lidar = run.lidar();
    let index = PlantIndex::new(seen.to_vec(), crate::runner::PLANT_INDEX_CELL_M);
    let base = Sideslip::new(run.sideslip.0, run.sideslip.1).map_err(s)?;
    let mut terrain = Terrain {
        base,
        patches: Vec::new(),
        ground: run.field.ground(),
    };
    if let Some((x0, x1, beta)) = run.low_grip {
        terrain.patches.push(SlipPatch {
            name: "low grip".to_owned(),
            polygon: vec![[x0, -100.0], [x1, -100.0], [x1, 100.0], [x0, 100.0]],
            sideslip: Sideslip::new(beta, beta).map_err(s)?,
        });
    }
    let scene = Scene {
        ground: &terrain.ground,
        plants: &index,
        obstacles: None,
        obstacle_height: 0.0,
    };
    let start = Pose2::<World>::new(-run.start.0 - WHEELBASE_M, run.start.1, 0.0).map_err(s)?;
    let mut state = VehicleState::at(start, &terrain);
    let mut odometry = FourWsOdometry::new(run.odometry).map_err(s)?;
    let speed = MetersPerSecond::new(run.speed_mps).map_err(s)?;
    let mut switching = entry_switching().map_err(s)?;
    let tolerance = PlanTolerance::new(
        Meters::new(PLAN_TOLERANCE.0).map_err(s)?,
        Radians::new(PLAN_TOLERANCE.1).map_err(s)?,
    )
    .map_err(s)?;
    let mut touched = vec![false; solid.len()];
    let mut ticks = Vec::new();
    let mut detected = 0;
    let end_x = run.field.length - run.stop_before_end_m;
    let steps =
        ((end_x + run.start.0 + WHEELBASE_M + 20.0) / run.speed_mps / PERIOD_S).ceil() as u64;
    let mut end = VineEnd::Aborted("the row's end was not reached".to_owned());
    for k in 0..=steps {
        let t_s = k as f64 * PERIOD_S;
        let scan = lidar.scan(&state.pose, &scene, rng);
        let view = scan.as_scan().map_err(s)?;
        let d = detector
            .detect(&view, &odometry.pose())
            .map_err(|e| format!("t = {t_s:.2} s: {e}"))?;
        let slip = if run.sideslip_known {
            state.sideslip
        } else {
            Sideslip::ZERO
        };
        //= spec/iberraken2022.md#fws-entry-entering-the-row-on-the-surveyed-row-line
        //# From its start until the vine detector locks, the robot MUST track the
        //# surveyed centre line of the row from its GNSS pose, with the law it follows
        //# the vines with.
        //= spec/iberraken2022.md#fws-entry-entering-the-row-on-the-surveyed-row-line
        //# It MUST follow the vines once the detector's verdict has been
        //# Enter, with a row line within 0.5 m and 0.3 rad of the surveyed one, for 1 s,
        //# and from 3 m into the row on.
        let gnss = surveyed_row_error(run, &state.pose, rng).map_err(s)?;
        let plan_consistent = d
            .error
            .is_some_and(|e| tolerance.is_consistent(&e, &gnss, &PathAhead::HERE));
        let mode = switching.step(&Input {
            behaviours: [Report {
                verdict: d.verdict,
                plan_consistent,
            }],
            localisation_valid: true,
        });
        let following = mode.source == CommandSource::Behaviour(0);
        let error = match mode.source {
            CommandSource::Behaviour(_) => d.error,
            CommandSource::PathTracking => Some(gnss),
            CommandSource::None => None,
        };
        if d.error.is_some() {
            detected += 1;
        }
        let command = match error {
            Some(e) => {
                let e = match run.fault {
                    Some(Fault::FlippedLateralGain) => TrackingError {
                        y: Meters::new(-e.y.get()).map_err(s)?,
                        ..e
                    },
                    None => e,
                };
                let c = match &law {
                    Law::One(l) => {
                        let objectives = Objectives {
                            sideslip: slip,
                            ..Objectives::NEUTRAL
                        };
                        strategy1_command(l, &e, &objectives, speed)
                    }
                    Law::Two(l) => strategy2_command(l, &e, slip, speed),
                }
                .map_err(|e| format!("t = {t_s:.2} s: {e}"))?;
                Command::FourWheelSteering {
                    speed,
                    front: c.front,
                    rear: c.rear,
                }
            }
            None => Command::FourWheelSteering {
                speed: MetersPerSecond::new(0.0).map_err(s)?,
                front: Radians::ZERO,
                rear: Radians::ZERO,
            },
        };
        let truth = state.pose;
        mark_touched(&truth, solid, &mut touched);
        ticks.push(VineTick {
            t_s,
            truth,
            lateral_m: truth.position.y() - run.field.row_y(0),
            angular_rad: truth.heading.get(),
            along_m: truth.position.x(),
            following: Some(following),
            steering: (state.steering, state.rear_steering),
            estimate: d.error.map(|e| (e.y.get(), e.angular_deviation.get())),
        });
        if truth.position.x() >= end_x {
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

/// The switching machine of a row's entry: vine following, the one
/// behaviour, entered after [`ENTER_DELAY_S`] of Enter verdicts consistent
/// with the surveyed row, left after [`EXIT_DELAY_S`] of Exit or Absent ones
/// or 0.5 s of disagreement; a stop after 1 s without a command.
fn entry_switching() -> Result<Switching<1>, fieldguide::Precondition> {
    let behaviour =
        BehaviourConfig::new(Seconds::new(ENTER_DELAY_S)?, Seconds::new(EXIT_DELAY_S)?)?;
    let config = SwitchingConfig::new(
        Seconds::new(PERIOD_S)?,
        [behaviour],
        Seconds::new(1.0)?,
        Some(Seconds::new(0.5)?),
    )?;
    Ok(Switching::new(config))
}

/// The robot's error to the surveyed centre line of row 0 (along +x), from
/// a GNSS pose: the true pose with the run's [`VineyardRun::gnss_noise`].
fn surveyed_row_error(
    run: &VineyardRun,
    pose: &Pose2<World>,
    rng: &mut SimRng,
) -> Result<TrackingError, fieldguide::Precondition> {
    let (sigma_p, sigma_h) = run.gnss_noise;
    let y = pose.position.y() - run.field.row_y(0) + rng.gaussian(sigma_p);
    let heading = wrap(pose.heading.get() + rng.gaussian(sigma_h));
    Ok(TrackingError {
        y: Meters::new(y)?,
        angular_deviation: Radians::new(heading)?,
        curvature: Curvature::new(0.0)?,
        curvature_ahead: Curvature::new(0.0)?,
    })
}

/// The odometry of a four-wheel-steering robot: the distance the wheels
/// roll (with the scale error and noise of [`OdometryErrors`]) along the
/// body's heading turned by the measured rear steering angle and the
/// sideslip estimate the law is given, and the heading change (with drift
/// and noise), integrated by the midpoint rule. A robot that crabs moves
/// sideways in its odometry too, as its rear wheels' angle says.
#[derive(Debug, Clone, PartialEq)]
pub struct FourWsOdometry {
    pose: Pose2<Odom>,
    errors: OdometryErrors,
}

impl FourWsOdometry {
    /// Odometry at the origin with the error model `errors`.
    ///
    /// # Errors
    /// None in practice (the origin is finite).
    pub fn new(errors: OdometryErrors) -> Result<Self, fieldguide::Precondition> {
        Ok(Self {
            pose: Pose2::new(0.0, 0.0, 0.0)?,
            errors,
        })
    }

    /// The current pose.
    #[must_use]
    pub const fn pose(&self) -> Pose2<Odom> {
        self.pose
    }

    /// Integrates the true motion from `from` to `to`, the rear sideslip
    /// estimate being `slip_estimate`; a non-finite result leaves the pose.
    pub fn update(
        &mut self,
        from: &VehicleState,
        to: &VehicleState,
        slip_estimate: f64,
        rng: &mut SimRng,
    ) {
        let (dx, dy) = (
            to.pose.position.x() - from.pose.position.x(),
            to.pose.position.y() - from.pose.position.y(),
        );
        let turn = wrap(to.pose.heading.get() - from.pose.heading.get());
        let distance = dx.hypot(dy);
        let e = &self.errors;
        let root = distance.sqrt();
        let ds = distance * (1.0 + e.scale) + rng.gaussian(e.distance_noise * root);
        let dpsi = turn + e.yaw_drift * distance + rng.gaussian(e.yaw_noise * root);
        let (x, y, psi) = (
            self.pose.position.x(),
            self.pose.position.y(),
            self.pose.heading.get(),
        );
        let course = psi + dpsi / 2.0 + to.rear_steering + slip_estimate;
        if let Ok(p) = Pose2::new(x + ds * course.cos(), y + ds * course.sin(), psi + dpsi) {
            self.pose = p;
        }
    }
}

/// `a` wrapped to (−π, π].
pub(crate) fn wrap(a: f64) -> f64 {
    Radians::new(a).map_or(0.0, |r| fieldguide::geometry::units::wrap_angle(r).get())
}

/// The contact patches' centres (rear left, rear right, front left, front
/// right) of a robot at `pose`, world frame.
#[must_use]
pub fn wheels(pose: &Pose2<World>) -> [(f64, f64); 4] {
    let (s, c) = pose.heading.get().sin_cos();
    let (x, y) = (pose.position.x(), pose.position.y());
    let at = |along: f64, across: f64| (x + along * c - across * s, y + along * s + across * c);
    let h = TRACK_M / 2.0;
    [
        at(0.0, h),
        at(0.0, -h),
        at(WHEELBASE_M, h),
        at(WHEELBASE_M, -h),
    ]
}

/// Marks the trunks and posts a wheel's contact patch (a rectangle
/// [`TYRE_M`] aligned with the body) meets.
//= spec/iberraken2022.md#fws-closed-loop-vine-row-held-against-the-true-row
//# From the paper's start, no wheel MUST touch a trunk or a post.
pub(crate) fn mark_touched(pose: &Pose2<World>, solid: &[Stem], touched: &mut [bool]) {
    let (s, c) = pose.heading.get().sin_cos();
    for (w, wy) in wheels(pose) {
        for (p, hit) in solid.iter().zip(touched.iter_mut()) {
            let (dx, dy) = (p.position.x() - w, p.position.y() - wy);
            if dx.abs() > 2.0 || dy.abs() > 2.0 {
                continue;
            }
            let (along, across) = (dx * c + dy * s, -dx * s + dy * c);
            if along.abs() <= TYRE_M.1 / 2.0 + p.radius && across.abs() <= TYRE_M.0 / 2.0 + p.radius
            {
                *hit = true;
            }
        }
    }
}

/// The trace of a run: one line per tick.
#[must_use]
pub fn trace_csv(outcome: &VineOutcome) -> String {
    let mut csv = String::from(
        "t_s,x_m,y_m,heading_rad,lateral_m,angular_rad,front_rad,rear_rad,est_lateral_m,est_angular_rad,mode\n",
    );
    for t in &outcome.ticks {
        let (ey, et) = t
            .estimate
            .map_or((String::new(), String::new()), |(y, th)| {
                (format!("{y:.6}"), format!("{th:.6}"))
            });
        let _ = writeln!(
            csv,
            "{:.3},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{ey},{et},{}",
            t.t_s,
            t.truth.position.x(),
            t.truth.position.y(),
            t.truth.heading.get(),
            t.lateral_m,
            t.angular_rad,
            t.steering.0,
            t.steering.1,
            match t.following {
                None => "",
                Some(true) => "vine_following",
                Some(false) => "path_tracking",
            },
        );
    }
    csv
}

/// A run's figures as JSON, errors against the true row after stabilisation.
#[must_use]
pub fn summary_json(run: &VineyardRun, outcome: &VineOutcome) -> serde_json::Value {
    let settled = outcome.settled(run.settle_m);
    serde_json::json!({
        "scenario": run.name,
        "season": run.field.season.name(),
        "strategy": run.strategy.name(),
        "seed": run.seed,
        "success": outcome.success(),
        "end": match &outcome.end { VineEnd::Done => "done".to_owned(), VineEnd::Aborted(e) => format!("aborted: {e}") },
        "vines_touched": outcome.touched,
        "vines_touched_past_entry": outcome.touched_in_row,
        "settle_m": run.settle_m,
        "lateral_error_m": settled.map(|s| serde_json::json!({
            "mean_abs": s.lateral_mean_abs, "max_abs": s.lateral_max_abs })),
        "angular_error_rad": settled.map(|s| serde_json::json!({
            "mean_abs": s.angular_mean_abs, "max_abs": s.angular_max_abs })),
        "steering_rear_rad": { "max_abs": outcome.rear_max_abs() },
        "ticks_with_row_line": outcome.detected,
        "duration_s": outcome.ticks.last().map_or(0.0, |t| t.t_s),
    })
}

/// Writes `trace.csv`, `summary.json`, `deviations.svg`, `steering.svg` and
/// `trajectory.svg`
/// of a run into `out/<run name>/`; returns the folder.
pub fn write_drive(
    out: &Path,
    run: &VineyardRun,
    outcome: &VineOutcome,
) -> Result<PathBuf, SimError> {
    let dir = out.join(&run.name);
    let files = [
        ("trace.csv", trace_csv(outcome)),
        (
            "summary.json",
            serde_json::to_string_pretty(&summary_json(run, outcome)).unwrap_or_default(),
        ),
        ("deviations.svg", plot::deviations_svg(run, outcome)),
        ("steering.svg", plot::steering_svg(run, outcome)),
        ("trajectory.svg", plot::trajectory_svg(run, outcome)),
    ];
    crate::output::write_files(&dir, &files)?;
    Ok(dir)
}
