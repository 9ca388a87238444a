//! A whole crop driven on LiDAR alone (Guyonneau 2022, section 4): the
//! symmetric differential robot with a LiDAR at the front and one at the
//! back, the core's `supervisor::crop_navigation::CropNavigator`, one of the
//! paper's four crops, and the paper's test plan ([`campaign`]).
//!
//! One tick at 40 Hz (the LiDARs' rate): both LiDARs ray-cast the crop from
//! the true pose ([`crate::world::scene::Scene`]), their ranges rounded to
//! the 0.01 m resolution; the wheel odometry (with drift) gives the pose the
//! navigator reads; the navigator's wheel speeds drive the plant
//! ([`crate::plant::DifferentialPlant`]). Errors are measured against the
//! true rows, never the robot's estimate: the offset from the middle of the
//! inter-row the robot is in while it drives an inter-row inside the field,
//! and every crop plant under the robot's body.

pub mod campaign;
pub mod field;
pub mod file;
pub mod plot;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use fieldguide::model::Command;
use fieldguide::perception::rows::ruby::Variant;
use fieldguide::perception::rows::{RowsConfig, RowsParams};
use fieldguide::supervisor::crop_navigation::{CropNavigator, Halt, NavParams, Phase, Waiting};
use fieldguide::{Odom, Pose2, World};

use crate::error::SimError;
use crate::lidar::horizontal::{HorizontalLidar, HorizontalLidarSpec};
use crate::odometry::{OdometryErrors, WheelOdometry};
use crate::plant::{DifferentialPlant, Plant, VehicleState};
use crate::rng::SimRng;
use crate::world::crops::PlantIndex;
use crate::world::scene::Scene;
use crate::world::terrain::{Ground, Terrain};
use crate::world::{Plant as Stem, PlantKind};
use field::CropSpec;

/// The control period: one tick per scan of the 40 Hz LiDARs, s.
pub const PERIOD_S: f64 = 0.025;
/// The robot's length and width, m (the paper: about 1.1 m long).
pub const BODY: (f64, f64) = (1.1, 0.6);
/// How far ahead of and behind O the LiDARs sit, m (at the body's ends).
pub const LIDAR_OFFSET_M: f64 = 0.55;
/// How high the LiDARs are, m (below the plants' tops).
pub const LIDAR_HEIGHT_M: f64 = 0.2;
/// The LiDARs' range resolution, m (section 4.1.1).
pub const RANGE_RESOLUTION_M: f64 = 0.01;
/// The correlation time of the wheels' slip, s.
pub const SLIP_TIME_S: f64 = 1.0;
/// Ticks whose detector time and points the paper's Tables 4-6 average.
pub const TIMED_TICKS: usize = 500;

/// A fault put into the loop to show that the checks bite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The controller's left and right outputs swapped while it drives an
    /// inter-row (Table 1's rules for the other wheel).
    SwappedWheels,
}

/// Where a LiDAR sits on the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LidarMount {
    /// Position along the robot's axis, m, forward positive.
    pub x_m: f64,
    /// Position across, m, left positive.
    pub y_m: f64,
    /// Facing, rad (0 forward, π backward).
    pub heading_rad: f64,
}

impl LidarMount {
    /// The paper's LiDARs: at the front facing forward, at the back facing
    /// backward, [`LIDAR_OFFSET_M`] from O.
    pub const PAPER: [Self; 2] = [
        Self {
            x_m: LIDAR_OFFSET_M,
            y_m: 0.0,
            heading_rad: 0.0,
        },
        Self {
            x_m: -LIDAR_OFFSET_M,
            y_m: 0.0,
            heading_rad: core::f64::consts::PI,
        },
    ];
}

/// One run: the crop, the line finder, the seed of everything random, and
/// the robot's imperfections.
#[derive(Debug, Clone, PartialEq)]
pub struct CropRun {
    /// The run's name (output folder).
    pub name: String,
    /// The crop.
    pub crop: CropSpec,
    /// The line finder's variant.
    pub variant: Variant,
    /// The seed of the crop's generation and of every noise.
    pub seed: u64,
    /// The wheel odometry's errors.
    pub odometry: OdometryErrors,
    /// The wheel speed of the fuzzy controller's full output, m/s (the
    /// wheels' limit is 1 m/s).
    pub top_speed_m_s: f64,
    /// The wheels' time constant, s.
    pub wheel_lag_s: f64,
    /// Wheel slip on soil: each wheel delivers its command times 1 + s, s a
    /// stationary first-order random process (Ornstein-Uhlenbeck) of this
    /// standard deviation and a correlation time of [`SLIP_TIME_S`]; the
    /// odometry does not see it.
    pub wheel_slip: f64,
    /// The LiDARs, one or two, in the order the rows detector reads them
    /// (the paper: one at each end of the body, facing out).
    pub lidars: Vec<LidarMount>,
    /// The LiDARs' range noise σ, m (section 4.1.1: 0.01 m).
    pub lidar_noise_m: f64,
    /// The start: O this far into the first inter-row, m, and this far off
    /// its middle (positive left), m.
    pub start: (f64, f64),
    /// The longest the run may take, s.
    pub duration_s: f64,
    /// A fault, for the tests that show the checks bite.
    pub fault: Option<Fault>,
    /// The LiDARs send nothing from the first time to the second, s.
    pub outage_s: Option<(f64, f64)>,
}

impl CropRun {
    /// The paper's run of crop `crop` (1-4) with `variant` and `seed`: odometry
    /// reading 0.5 % long and drifting 0.002 rad/m, wheels settling in 0.3 s
    /// and slipping by 2 % (σ),
    /// the LiDARs' σ = 0.01 m, the robot 0.5 m into the first inter-row on
    /// its middle, at most 600 s.
    #[must_use]
    pub fn paper(crop: u8, variant: Variant, seed: u64) -> Option<Self> {
        Some(Self {
            name: format!("guyonneau-crop{crop}"),
            crop: CropSpec::paper(crop)?,
            variant,
            seed,
            odometry: OdometryErrors {
                scale: 0.005,
                yaw_drift: 0.002,
                distance_noise: 0.002,
                yaw_noise: 0.002,
            },
            top_speed_m_s: 0.5,
            wheel_lag_s: 0.1,
            wheel_slip: 0.02,
            lidars: LidarMount::PAPER.to_vec(),
            lidar_noise_m: 0.01,
            start: (0.5, 0.0),
            duration_s: 600.0,
            fault: None,
            outage_s: None,
        })
    }
}

/// One tick of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CropTick {
    /// Time, s.
    pub t_s: f64,
    /// The true pose of O.
    pub truth: Pose2<World>,
    /// The navigator's phase after the tick.
    pub phase: Phase,
    /// Why it stood still, if it did.
    pub waiting: Option<Waiting>,
    /// The commanded wheel speeds (left, right), m/s.
    pub command: (f64, f64),
    /// The offset of O from the middle of its inter-row, m, positive left,
    /// while it drives an inter-row with O inside the field.
    pub offset_m: Option<f64>,
    /// The navigator's time on the tick, µs, when the detector ran.
    pub detector_us: Option<f64>,
    /// The points the line finder worked on, when the detector ran.
    pub points: Option<usize>,
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CropEnd {
    /// Every inter-row driven.
    Done,
    /// The navigator stopped for good.
    Stopped(String),
    /// The run's duration elapsed.
    Timeout,
    /// The core refused a value.
    Aborted(String),
}

/// A run's trace and figures.
#[derive(Debug, Clone, PartialEq)]
pub struct CropOutcome {
    /// One record per tick.
    pub ticks: Vec<CropTick>,
    /// Why it ended.
    pub end: CropEnd,
    /// Crop plants under the body at some tick.
    pub crushed: usize,
    /// The crop's plants (crop plants, then weeds).
    pub plants: Vec<Stem>,
    /// The row distance the robot measured, m.
    pub row_distance_m: Option<f64>,
}

impl CropOutcome {
    /// The paper's success: the end of the last inter-row reached without
    /// running over a crop plant.
    #[must_use]
    pub fn success(&self) -> bool {
        self.end == CropEnd::Done && self.crushed == 0
    }

    /// The mean squared offset from the middle of the rows while driving
    /// inter-rows inside the field (row changes excluded), mm² (Table 3).
    #[must_use]
    pub fn mse_mm2(&self) -> Option<f64> {
        mean(
            self.ticks
                .iter()
                .filter_map(|t| t.offset_m)
                .map(|o| (o * 1000.0).powi(2)),
        )
    }

    /// The largest |offset|, m.
    #[must_use]
    pub fn max_offset_m(&self) -> Option<f64> {
        self.ticks
            .iter()
            .filter_map(|t| t.offset_m)
            .map(f64::abs)
            .reduce(f64::max)
    }

    /// The mean navigator time per detector tick and points per tick over the
    /// first [`TIMED_TICKS`] detector ticks (Tables 4-5).
    #[must_use]
    pub fn timing(&self) -> (Option<f64>, Option<f64>) {
        let first: Vec<(f64, usize)> = self
            .ticks
            .iter()
            .filter_map(|t| t.detector_us.zip(t.points))
            .take(TIMED_TICKS)
            .collect();
        (
            mean(first.iter().map(|f| f.0)),
            mean(first.iter().map(|f| f.1 as f64)),
        )
    }
}

/// The mean of `values`, `None` without any.
fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0_u32), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / f64::from(n))
}

/// The paper's LiDAR (section 4.1.1) at `mount`: 360 rays over 180°,
/// 0.1-4 m, range noise σ = `noise` m.
fn lidar(mount: &LidarMount, noise: f64) -> Result<HorizontalLidar, String> {
    HorizontalLidar::new(HorizontalLidarSpec {
        mount_xy: [mount.x_m, mount.y_m],
        mount_heading: mount.heading_rad,
        mount_height: LIDAR_HEIGHT_M,
        field_of_view: core::f64::consts::PI,
        rays: 360,
        range_min: 0.1,
        range_max: 4.0,
        noise_sigma: noise,
    })
    .map_err(|e| format!("LiDAR: {e:?}"))
}

/// Runs `run`.
#[must_use]
pub fn drive(run: &CropRun) -> CropOutcome {
    let mut rng = SimRng::from_seed(run.seed);
    let mut plants = run.crop.generate(&mut rng);
    // The robot is put down at its start: nothing stands under its body.
    let (x, y) = (run.start.0, 0.5 * run.crop.spacing + run.start.1);
    plants.retain(|p| {
        (p.position.x() - x).abs() > BODY.0 / 2.0 + p.radius
            || (p.position.y() - y).abs() > BODY.1 / 2.0 + p.radius
    });
    match drive_in(run, &plants, &mut rng) {
        Ok(outcome) => outcome,
        Err(e) => CropOutcome {
            ticks: Vec::new(),
            end: CropEnd::Aborted(e),
            crushed: 0,
            plants,
            row_distance_m: None,
        },
    }
}

fn drive_in(run: &CropRun, plants: &[Stem], rng: &mut SimRng) -> Result<CropOutcome, String> {
    let lidars = run
        .lidars
        .iter()
        .map(|m| lidar(m, run.lidar_noise_m))
        .collect::<Result<Vec<_>, _>>()?;
    let (first, second) = match lidars.as_slice() {
        [a] => (a, None),
        [a, b] => (a, Some(b)),
        _ => return Err("one or two LiDARs".to_owned()),
    };
    let mut rows = RowsParams::authors(run.variant, first.mount());
    if let Some(b) = second {
        rows = rows.with_second(b.mount());
    }
    let config = RowsConfig::new(rows).map_err(|e| e.to_string())?;
    let params = NavParams {
        top_speed: fieldguide::MetersPerSecond::new(run.top_speed_m_s)
            .map_err(|e| e.to_string())?,
        ..NavParams::authors(config).map_err(|e| e.to_string())?
    };
    let mut nav = CropNavigator::<1024>::new(params).map_err(|e| e.to_string())?;
    let plant = DifferentialPlant {
        track_m: params.vehicle.track().get(),
        time_constant_s: run.wheel_lag_s,
        max_wheel_speed: params.vehicle.max_wheel_speed().get(),
    };
    let index = PlantIndex::new(plants.to_vec(), crate::runner::PLANT_INDEX_CELL_M);
    let ground = Ground::default();
    let scene = Scene {
        ground: &ground,
        plants: &index,
        obstacles: None,
        obstacle_height: 0.0,
    };
    let terrain = Terrain::default();
    let start = Pose2::<World>::new(run.start.0, 0.5 * run.crop.spacing + run.start.1, 0.0)
        .map_err(|e| e.to_string())?;
    let mut state = VehicleState::at(start, &terrain);
    let mut odometry = WheelOdometry::new(
        Pose2::<Odom>::new(0.0, 0.0, 0.0).map_err(|e| e.to_string())?,
        run.odometry,
    );
    let mut ranges: Vec<Vec<f64>> = vec![Vec::new(); lidars.len()];
    let mut crushed = vec![false; plants.len()];
    let mut near = Vec::new();
    let mut ticks = Vec::new();
    let mut end = CropEnd::Timeout;
    let mut slip = (rng.gaussian(run.wheel_slip), rng.gaussian(run.wheel_slip));
    let steps = (run.duration_s / PERIOD_S).ceil() as u64;
    for k in 0..=steps {
        let t_s = k as f64 * PERIOD_S;
        for (l, r) in lidars.iter().zip(ranges.iter_mut()) {
            l.scan(&state.pose, &scene, rng, r)
                .map_err(|e| e.to_string())?;
            for range in r.iter_mut() {
                *range = (*range / RANGE_RESOLUTION_M).round() * RANGE_RESOLUTION_M;
            }
        }
        let scans = lidars
            .iter()
            .zip(&ranges)
            .map(|(l, r)| l.scan_view(r))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| e.to_string())?;
        let silent = run.outage_s.is_some_and(|(a, b)| (a..b).contains(&t_s));
        let scans: &[_] = if silent { &[] } else { &scans };
        let began = Instant::now();
        let tick = nav
            .step(scans, &odometry.pose())
            .map_err(|e| format!("t = {t_s:.2} s: {e}"))?;
        let spent = began.elapsed().as_secs_f64() * 1e6;
        let mut command = tick.command;
        if let (Some(Fault::SwappedWheels), Phase::Driving { .. }) = (run.fault, tick.phase) {
            if let Command::Differential { left, right } = command {
                command = Command::Differential {
                    left: right,
                    right: left,
                };
            }
        }
        let (x, y) = (state.pose.position.x(), state.pose.position.y());
        let inside = (0.0..=run.crop.length).contains(&x);
        let offset = match tick.phase {
            Phase::Driving { .. } if inside => run.crop.offset_from_middle(y).map(|o| o.1),
            _ => None,
        };
        mark_crushed(&index, &state.pose, &mut crushed, &mut near);
        let wheels = match command {
            Command::Differential { left, right } => (left.get(), right.get()),
            _ => (0.0, 0.0),
        };
        ticks.push(CropTick {
            t_s,
            truth: state.pose,
            phase: tick.phase,
            waiting: tick.waiting,
            command: wheels,
            offset_m: offset,
            detector_us: tick.detection.map(|_| spent),
            points: tick.detection.map(|d| d.gathered.kept),
        });
        match tick.phase {
            Phase::Done => {
                end = CropEnd::Done;
                break;
            }
            Phase::Stopped(halt) => {
                end = CropEnd::Stopped(match halt {
                    Halt::Blind => "blind: no usable scan".to_owned(),
                    Halt::Refused(e) => e.to_string(),
                });
                break;
            }
            _ => {}
        }
        // The slip's exact discretisation over one period.
        let keep = (-PERIOD_S / SLIP_TIME_S).exp();
        let kick = run.wheel_slip * (1.0 - keep * keep).sqrt();
        slip = (
            slip.0 * keep + rng.gaussian(kick),
            slip.1 * keep + rng.gaussian(kick),
        );
        let delivered = match command {
            Command::Differential { left, right } => Command::Differential {
                left: fieldguide::MetersPerSecond::new(left.get() * (1.0 + slip.0))
                    .map_err(|e| e.to_string())?,
                right: fieldguide::MetersPerSecond::new(right.get() * (1.0 + slip.1))
                    .map_err(|e| e.to_string())?,
            },
            other => other,
        };
        let before = state.pose;
        state = plant
            .advance(&state, &delivered, &terrain, PERIOD_S, 2)
            .map_err(|e| e.to_string())?;
        odometry.update_between(&before, &state.pose, rng);
    }
    Ok(CropOutcome {
        ticks,
        end,
        crushed: crushed.iter().filter(|c| **c).count(),
        plants: plants.to_vec(),
        row_distance_m: nav.detector().row_distance().map(fieldguide::Meters::get),
    })
}

/// Marks the crop plants whose stem overlaps the robot's body (a rectangle
/// of [`BODY`] centred on O): the robot runs over them.
fn mark_crushed(
    index: &PlantIndex,
    pose: &Pose2<World>,
    crushed: &mut [bool],
    near: &mut Vec<usize>,
) {
    let (half_l, half_w) = (BODY.0 / 2.0, BODY.1 / 2.0);
    let reach = half_l.hypot(half_w) + index.max_radius();
    let (x, y) = (pose.position.x(), pose.position.y());
    index.query((x - reach, y - reach), (x + reach, y + reach), near);
    let (s, c) = pose.heading.get().sin_cos();
    for &i in near.iter() {
        let (Some(p), Some(hit)) = (index.plants().get(i), crushed.get_mut(i)) else {
            continue;
        };
        let (dx, dy) = (p.position.x() - x, p.position.y() - y);
        let (along, across) = (dx * c + dy * s, -dx * s + dy * c);
        if p.kind == PlantKind::Crop
            && along.abs() <= half_l + p.radius
            && across.abs() <= half_w + p.radius
        {
            *hit = true;
        }
    }
}

/// The trace of a drive: one line per tick.
#[must_use]
pub fn trace_csv(outcome: &CropOutcome) -> String {
    let mut csv = String::from(
        "t_s,x_m,y_m,heading_rad,phase,waiting,left_mps,right_mps,offset_m,detector_us,points\n",
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.6}"));
    for t in &outcome.ticks {
        let phase = match t.phase {
            Phase::Measuring => "measuring".to_owned(),
            Phase::Driving { row, backward } => {
                format!(
                    "row {row} {}",
                    if backward { "backward" } else { "forward" }
                )
            }
            Phase::Changing { row, step } => format!("change after row {row}: {step:?}"),
            Phase::Done => "done".to_owned(),
            Phase::Stopped(h) => format!("stopped: {h:?}").replace(',', ";"),
        };
        let _ = writeln!(
            csv,
            "{:.3},{:.6},{:.6},{:.6},{phase},{},{:.6},{:.6},{},{},{}",
            t.t_s,
            t.truth.position.x(),
            t.truth.position.y(),
            t.truth.heading.get(),
            t.waiting.map_or(String::new(), |w| format!("{w:?}")),
            t.command.0,
            t.command.1,
            opt(t.offset_m),
            opt(t.detector_us),
            t.points.map_or(String::new(), |p| p.to_string()),
        );
    }
    csv
}

/// A drive's figures as JSON.
#[must_use]
pub fn summary_json(run: &CropRun, outcome: &CropOutcome) -> serde_json::Value {
    let (detector_us, points) = outcome.timing();
    serde_json::json!({
        "scenario": run.name,
        "crop": run.crop.crop,
        "variant": campaign::variant_name(run.variant),
        "seed": run.seed,
        "success": outcome.success(),
        "end": campaign::end_label(&outcome.end),
        "plants_crushed": outcome.crushed,
        "mse_mm2": outcome.mse_mm2(),
        "max_offset_m": outcome.max_offset_m(),
        "row_distance_m": outcome.row_distance_m,
        "true_row_distance_m": run.crop.spacing,
        "time_per_tick_us_first_500": detector_us,
        "points_per_tick_first_500": points,
        "duration_s": outcome.ticks.last().map_or(0.0, |t| t.t_s),
    })
}

/// Writes `trace.csv`, `summary.json` and `trajectory.svg` of a drive into
/// `out/<run name>/`; returns the folder.
pub fn write_drive(out: &Path, run: &CropRun, outcome: &CropOutcome) -> Result<PathBuf, SimError> {
    let dir = out.join(&run.name);
    let files = [
        ("trace.csv", trace_csv(outcome)),
        (
            "summary.json",
            serde_json::to_string_pretty(&summary_json(run, outcome)).unwrap_or_default(),
        ),
        ("trajectory.svg", plot::trajectory_svg(run, outcome)),
    ];
    crate::output::write_files(&dir, &files)?;
    Ok(dir)
}
