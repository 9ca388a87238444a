//! The closed loop: truth, sensors, guidance, plant, once per control period.
//!
//! One tick at time t = k·period:
//! 1. the true pose is projected on the reference path, and placed relative
//!    to the crop plots' true centre lines and to the hedges' true offset
//!    lines (ground truth: the errors recorded and scored are these, never
//!    the robot's estimate);
//! 2. the sensors read the true state (with noise, from the run's generator),
//!    and on its scan ticks each mounted LiDAR scans the one world (ground,
//!    plants, hedges) from the true pose, its scan routed to its behaviour;
//! 3. the guidance turns the readings into a command;
//! 4. the tick is recorded, crop plants under the wheels are counted (and
//!    located), and the run stops at the end of the path, at the duration, on
//!    a core error, or when the robot stands in Stop inside a GNSS outage
//!    placed by distance (which then can never end);
//! 5. the plant integrates the command over one period.

use fieldguide::geometry::path::PathPosition;
use fieldguide::{Meters, Pose2, Precondition, World};

use crate::error::ScenarioError;
use crate::gnss::GnssErrorState;
use crate::guidance::pipeline::Pipeline;
use crate::guidance::{Command, Guidance, TickInput, SEARCH_WINDOW_M};
use crate::lidar::inclined::InclinedScan;
use crate::lidar::{Mounted, MountedLidar};
use crate::plant::{Plant, VehicleState};
use crate::rng::SimRng;
use crate::scenario::{Setup, Source};
use crate::sensors::{Readings, Sensors};
use crate::world::crops::PlantIndex;
use crate::world::grid::Grid;
use crate::world::scene::Scene;
use crate::world::PlantKind;
use fieldguide::guidance::Mode;

/// Cell size of the plant index, metres (a few plants per cell in a row).
pub const PLANT_INDEX_CELL_M: f64 = 0.5;

/// How far from a plot's centre line (or a hedge's offset line) the robot
/// still counts as inside the plot (beside the hedge) for the in-plot
/// (along-hedge) metrics, metres: beyond the rows and the wheels.
pub const PLOT_REACH_M: f64 = 2.0;

/// Cell size of the obstacle grid the horizontal LiDAR casts through, metres.
pub const OBSTACLE_GRID_CELL_M: f64 = 0.5;

/// How long the robot may stand in Stop inside a GNSS outage placed by
/// distance before the run is stopped: the outage ends only when the robot
/// moves past it, and nothing else moves it, seconds.
pub const OUTAGE_STALL_S: f64 = 5.0;

/// The names of the wheels, in the order of
/// [`crate::plant::VehicleParams::wheel_centres`].
pub const WHEELS: [&str; 4] = ["rear_left", "rear_right", "front_left", "front_right"];

/// A crop plant a wheel went over: where, in which plot, under which wheel, when.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CrushedPlant {
    /// Index of the plant in `setup.world.plants`.
    pub index: usize,
    /// East coordinate of the plant, metres.
    pub x_m: f64,
    /// North coordinate of the plant, metres.
    pub y_m: f64,
    /// The plot it grew in (null for a plant outside every plot).
    pub plot: Option<String>,
    /// The wheel that went over it first (`rear_left`, `rear_right`, `front_left`, `front_right`).
    pub wheel: &'static str,
    /// Time of the first tick a wheel's contact patch overlapped it, seconds.
    pub t_s: f64,
}

/// Where the true pose of O lies relative to the true line a specialised
/// behaviour should follow (ground truth): a crop plot's centre line, or the
/// line at the desired distance from a hedge's nominal face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineTruth {
    /// Index of the plot in `setup.world.plots`, or of the hedge in `setup.world.hedges`.
    pub index: usize,
    /// Abscissa along the plot's centre line or the hedge, metres.
    pub s_m: f64,
    /// Signed distance of O to the true line (the middle of the rows
    /// followed; the hedge's offset line), metres, positive to the left.
    pub lateral_error_m: f64,
    /// Heading of O minus the true line's heading, radians.
    pub angular_error_rad: f64,
}

/// Everything recorded at one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickRecord {
    /// Time, seconds.
    pub t_s: f64,
    /// True pose of O, world frame.
    pub truth: Pose2<World>,
    /// Sensor readings (estimated pose, odometry, observed sideslip).
    pub readings: Readings,
    /// Abscissa of the true pose's projection on the path, metres.
    pub s_m: f64,
    /// True lateral error, metres, positive left of the path.
    pub lateral_error_m: f64,
    /// True angular deviation θ̃, radians.
    pub angular_error_rad: f64,
    /// Path curvature at the true projection, 1/m.
    pub curvature: f64,
    /// The command of this tick.
    pub command: Command,
    /// Actual steering angle at this tick, radians.
    pub steering_rad: f64,
    /// True sideslip (front, rear), radians.
    pub sideslip_rad: (f64, f64),
    /// Index of the slip patch under O, if any.
    pub patch: Option<usize>,
    /// Distance travelled by O, metres.
    pub distance_m: f64,
    /// Whether the GNSS fix is float at this tick (`[gnss] float_s`, `float_m`).
    pub gnss_float: bool,
    /// Where O is relative to a crop plot it is inside, if any.
    pub plot: Option<LineTruth>,
    /// Where O is relative to the offset line of a hedge present abeam of
    /// it, if any (only with `[edge]`, whose desired distance places the line).
    pub hedge: Option<LineTruth>,
}

impl TickRecord {
    /// The behaviour in charge at this tick.
    #[must_use]
    pub const fn mode(&self) -> Mode {
        self.command.mode
    }

    /// The label of the behaviour in charge at this tick.
    #[must_use]
    pub const fn label(&self) -> &'static str {
        self.command.label
    }
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RunEnd {
    /// The true projection reached the end of the path.
    PathEnd,
    /// The scenario's duration elapsed.
    Duration,
    /// The core refused a value (the message names the requirement): the run stops there.
    Aborted(String),
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// One record per control tick.
    pub trace: Vec<TickRecord>,
    /// Why it ended.
    pub end: RunEnd,
    /// Number of distinct crop plants a wheel went over (grass never counts).
    pub plants_crushed: usize,
    /// Those plants, in the order they were crushed.
    pub crushed: Vec<CrushedPlant>,
}

/// Parses and validates `source`, and makes the run's generator from its seed
/// (the path's recording noise is its first draws).
pub fn prepare(source: &Source) -> Result<(Setup, SimRng), ScenarioError> {
    let file = source.parse()?;
    prepare_file(source, file)
}

/// [`prepare`] with `seed` in place of the scenario's own `seed`: the whole
/// run follows from it (the world's generation, the path's recording noise,
/// the sensors' noise), and `Setup::seed` and the summary report it. The
/// text is not edited, so every other field is the file's.
pub fn prepare_with_seed(source: &Source, seed: u64) -> Result<(Setup, SimRng), ScenarioError> {
    prepare_edited(source, seed, |_| {})
}

/// [`prepare_with_seed`] with the parsed file changed by `edit` before it
/// is validated and built (the stress campaign's odometry override).
///
/// # Errors
/// As [`prepare_with_seed`], for the edited file.
pub fn prepare_edited(
    source: &Source,
    seed: u64,
    edit: impl FnOnce(&mut crate::scenario::ScenarioFile),
) -> Result<(Setup, SimRng), ScenarioError> {
    let mut file = source.parse()?;
    file.seed = seed;
    edit(&mut file);
    prepare_file(source, file)
}

/// Builds the setup of the parsed `file` of `source`, drawing from a
/// generator seeded with `file.seed`, and hands that generator on.
fn prepare_file(
    source: &Source,
    file: crate::scenario::ScenarioFile,
) -> Result<(Setup, SimRng), ScenarioError> {
    let mut rng = SimRng::from_seed(file.seed);
    let setup =
        crate::scenario::build(&file, &source.origin, source.base_dir.as_deref(), &mut rng)?;
    Ok((setup, rng))
}

/// Runs `setup` with its own guidance: the core pipeline
/// (`fieldguide::guidance::Guidance`: path tracking, and edge following or
/// furrow pursuing when the scenario has an `[edge]` or a `[furrow]` section,
/// switched by the core's machine with the `[switching]` delays).
#[must_use]
pub fn run(setup: &Setup, rng: &mut SimRng) -> RunOutput {
    match Pipeline::new(setup) {
        Ok(mut guidance) => run_with(setup, &mut guidance, rng),
        Err(e) => RunOutput {
            trace: Vec::new(),
            end: RunEnd::Aborted(format!("guidance pipeline: {e}")),
            plants_crushed: 0,
            crushed: Vec::new(),
        },
    }
}

/// Runs `setup` with any `guidance`.
#[must_use]
pub fn run_with(setup: &Setup, guidance: &mut dyn Guidance, rng: &mut SimRng) -> RunOutput {
    let period = setup.control.period_s;
    let max_ticks = (setup.run.duration_s / period).ceil() as u64;
    let terrain = &setup.world.terrain;
    let mut state = VehicleState::at(setup.initial, terrain);
    let mut sensors = Sensors::new(setup.noise, &state, setup.seed);
    let index = PlantIndex::new(setup.world.plants.clone(), PLANT_INDEX_CELL_M);
    let obstacles = &setup.world.obstacles;
    let grid = if obstacles.segments.is_empty() && obstacles.circles.is_empty() {
        None
    } else {
        match Grid::new(obstacles.clone(), OBSTACLE_GRID_CELL_M) {
            Ok(grid) => Some(grid),
            Err(e) => {
                return RunOutput {
                    trace: Vec::new(),
                    end: RunEnd::Aborted(format!("obstacle grid: {e}")),
                    plants_crushed: 0,
                    crushed: Vec::new(),
                }
            }
        }
    };
    let scene = Scene {
        ground: &terrain.ground,
        plants: &index,
        obstacles: grid.as_ref(),
        obstacle_height: setup.world.obstacle_height,
    };
    let lidars = setup.lidars();
    let mut buffers: Vec<Option<Reading>> = vec![None; lidars.len()];
    let mut crushed = vec![false; setup.world.plants.len()];
    let mut located = Vec::new();
    let mut near = Vec::new();
    let mut gnss = GnssErrorState::new(&setup.gnss_errors, setup.seed);
    let mut stalled_s = 0.0;
    let mut trace = Vec::with_capacity(usize::try_from(max_ticks.min(1 << 20)).unwrap_or(0));
    let mut truth_hint: Option<Meters> = None;
    let mut end = RunEnd::Duration;
    for k in 0..=max_ticks {
        let t_s = k as f64 * period;
        match tick(
            setup,
            guidance,
            &state,
            &mut sensors,
            &mut truth_hint,
            (t_s, &mut gnss),
            (&scene, &lidars, k, &mut buffers),
            rng,
        ) {
            Ok((record, past_end)) => {
                count_crushed(
                    setup,
                    &index,
                    &record,
                    &mut crushed,
                    &mut near,
                    &mut located,
                );
                trace.push(record);
                if past_end && setup.run.stop_at_path_end {
                    end = RunEnd::PathEnd;
                    break;
                }
                if let Some(why) = stalled_in_outage(setup, &record, &mut stalled_s) {
                    end = RunEnd::Aborted(why);
                    break;
                }
                match setup.vehicle.advance(
                    &state,
                    &record.command.drive,
                    terrain,
                    period,
                    setup.run.substeps,
                ) {
                    Ok(next) => state = next,
                    Err(e) => {
                        end = RunEnd::Aborted(format!("plant at t = {t_s:.2} s: {e}"));
                        break;
                    }
                }
            }
            Err(e) => {
                end = RunEnd::Aborted(format!("t = {t_s:.2} s: {e}"));
                break;
            }
        }
    }
    RunOutput {
        trace,
        end,
        plants_crushed: crushed.iter().filter(|c| **c).count(),
        crushed: located,
    }
}

/// Counts the time the robot of `record` stands in Stop inside a GNSS outage
/// placed by distance (`stalled_s`, reset outside); past
/// [`OUTAGE_STALL_S`], the reason to stop the run, naming the outage's field.
fn stalled_in_outage(setup: &Setup, record: &TickRecord, stalled_s: &mut f64) -> Option<String> {
    let span =
        setup.gnss_outages.0.at_abscissa(record.s_m).filter(|_| {
            record.readings.gnss.is_none() && record.command.switching_mode == Mode::Stop
        });
    let Some(span) = span else {
        *stalled_s = 0.0;
        return None;
    };
    *stalled_s += setup.control.period_s;
    (*stalled_s >= OUTAGE_STALL_S).then(|| {
        format!(
            "GNSS outage {} [{:.2}, {:.2}) m never ends: the robot stood in Stop for {OUTAGE_STALL_S} s \
             at s = {:.2} m without a fix or another source (an outage placed by distance ends \
             only when the robot moves past it)",
            span.field, span.from_m, span.to_m, record.s_m
        )
    })
}

/// One LiDAR's latest scan, kept between ticks (the horizontal LiDAR's
/// buffer is reused).
#[derive(Debug, Clone)]
enum Reading {
    /// An inclined LiDAR's scan.
    Inclined(InclinedScan),
    /// A horizontal LiDAR's ranges.
    Horizontal(Vec<f64>),
}

/// The world, the mounted LiDARs, the tick's index and each LiDAR's reading.
type Scanning<'a, 'w> = (
    &'a Scene<'w>,
    &'a [MountedLidar],
    u64,
    &'a mut [Option<Reading>],
);

/// Steps 1-3 of a tick (`lidars`: the world, the mounted LiDARs, each
/// scanning on its scan ticks, and their buffers); returns the record and
/// whether the true projection is past the end.
#[allow(
    clippy::too_many_arguments,
    reason = "one tick reads the whole loop state; a struct would only rename it"
)]
fn tick(
    setup: &Setup,
    guidance: &mut dyn Guidance,
    state: &VehicleState,
    sensors: &mut Sensors,
    truth_hint: &mut Option<Meters>,
    (t_s, gnss): (f64, &mut GnssErrorState),
    lidars: Scanning<'_, '_>,
    rng: &mut SimRng,
) -> Result<(TickRecord, bool), Precondition> {
    let (scene, mounted, k, buffers) = lidars;
    let path = &setup.path;
    let truth = match *truth_hint {
        None => path.project(&state.pose, Meters::ZERO)?,
        Some(hint) => path.project_near(
            &state.pose,
            Meters::ZERO,
            hint,
            Meters::new(SEARCH_WINDOW_M)?,
        )?,
    };
    *truth_hint = Some(truth.s);
    let fix = setup.gnss_outages.has_fix_at(t_s, truth.s.get());
    let mut readings = sensors.read(state, setup.control.period_s, fix, rng)?;
    // The receiver's errors beyond its white noise (their own generator).
    let error = gnss.step(t_s, truth.s.get(), setup.control.period_s);
    readings.gnss_quality = error.quality(setup.noise.gnss_position_m);
    if let (Some(p), true) = (readings.gnss, error.offset_m != (0.0, 0.0)) {
        readings.gnss = Some(Pose2::new(
            p.position.x() + error.offset_m.0,
            p.position.y() + error.offset_m.1,
            p.heading.get(),
        )?);
    }
    // Each LiDAR in turn, on its scan ticks (the generator's draws in the
    // order of the list).
    let mut fresh = vec![false; mounted.len()];
    for ((lidar, reading), new) in mounted.iter().zip(buffers.iter_mut()).zip(&mut fresh) {
        if k % lidar.scan_every != 0 {
            continue;
        }
        *new = true;
        match &lidar.sensor {
            Mounted::Inclined(l) => {
                *reading = Some(Reading::Inclined(l.scan(&state.pose, scene, rng)))
            }
            Mounted::Horizontal(l) => {
                let mut ranges = match reading.take() {
                    Some(Reading::Horizontal(r)) => r,
                    _ => Vec::new(),
                };
                l.scan(&state.pose, scene, rng, &mut ranges)?;
                *reading = Some(Reading::Horizontal(ranges));
            }
        }
    }
    let mut scans = Vec::with_capacity(mounted.len());
    for ((lidar, reading), new) in mounted.iter().zip(buffers.iter()).zip(&fresh) {
        let scan = match (&lidar.sensor, reading, new) {
            (_, _, false) | (_, None, _) => continue,
            (Mounted::Inclined(_), Some(Reading::Inclined(s)), true) => s.as_scan()?,
            (Mounted::Horizontal(l), Some(Reading::Horizontal(r)), true) => l.scan_view(r)?,
            _ => continue,
        };
        scans.push(fieldguide::guidance::RoutedScan {
            behaviour: lidar.route,
            scan,
        });
    }
    let command = guidance.step(&TickInput {
        time_s: t_s,
        readings: &readings,
        scans: &scans,
    })?;
    let (x, y) = (state.pose.position.x(), state.pose.position.y());
    let heading = state.pose.heading.get();
    let plot = setup
        .world
        .plot_at(x, y, PLOT_REACH_M)
        .map(|(index, p)| LineTruth {
            index,
            s_m: p.s,
            lateral_error_m: p.lateral,
            angular_error_rad: fieldguide::Radians::new(
                heading
                    - setup
                        .world
                        .plots
                        .get(index)
                        .map_or(0.0, |q| q.spec.centre_line(p.s).2),
            )
            .map_or(f64::NAN, |a| {
                fieldguide::geometry::units::wrap_angle(a).get()
            }),
        });
    let hedge = setup.edge.and_then(|e| {
        setup
            .world
            .hedge_at((x, y, heading), e.detector.offset().get(), PLOT_REACH_M)
            .map(|(index, h)| LineTruth {
                index,
                s_m: h.along,
                lateral_error_m: h.lateral,
                angular_error_rad: h.angular,
            })
    });
    let past_end = truth.position == PathPosition::PastEnd || truth.s.get() >= path.length().get();
    Ok((
        TickRecord {
            t_s,
            truth: state.pose,
            readings,
            s_m: truth.s.get(),
            lateral_error_m: truth.y.get(),
            angular_error_rad: truth.angular_deviation.get(),
            curvature: truth.curvature.get(),
            command,
            steering_rad: state.steering,
            sideslip_rad: (state.sideslip.front.get(), state.sideslip.rear.get()),
            patch: setup
                .world
                .terrain
                .patches
                .iter()
                .position(|p| p.contains(x, y)),
            distance_m: state.distance_m,
            gnss_float: error.float,
            plot,
            hedge,
        },
        past_end,
    ))
}

/// Marks the crop plants a wheel's contact patch (a disc of the tyre width)
/// overlaps at `record`'s true pose, and locates each newly marked one in
/// `located`; grass is never marked. `index` holds `setup.world.plants` in
/// order; `near` is scratch space.
fn count_crushed(
    setup: &Setup,
    index: &PlantIndex,
    record: &TickRecord,
    crushed: &mut [bool],
    near: &mut Vec<usize>,
    located: &mut Vec<CrushedPlant>,
) {
    if crushed.is_empty() {
        return;
    }
    let half_tyre = setup.vehicle.tyre_width_m / 2.0;
    let reach = half_tyre + index.max_radius();
    for (w, wheel) in setup
        .vehicle
        .wheel_centres(&record.truth)
        .iter()
        .zip(WHEELS)
    {
        index.query(
            (w[0] - reach, w[1] - reach),
            (w[0] + reach, w[1] + reach),
            near,
        );
        for &i in near.iter() {
            let (Some(plant), Some(hit)) = (index.plants().get(i), crushed.get_mut(i)) else {
                continue;
            };
            let (px, py) = (plant.position.x(), plant.position.y());
            if !*hit
                && plant.kind == PlantKind::Crop
                && (w[0] - px).hypot(w[1] - py) < plant.radius + half_tyre
            {
                *hit = true;
                located.push(CrushedPlant {
                    index: i,
                    x_m: px,
                    y_m: py,
                    plot: setup
                        .world
                        .plot_at(px, py, PLOT_REACH_M)
                        .and_then(|(p, _)| setup.world.plots.get(p))
                        .map(|p| p.name.clone()),
                    wheel,
                    t_s: record.t_s,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Plant;
    use fieldguide::Point2;

    #[test]
    fn plants_on_the_track_are_crushed_once_and_others_spared() {
        let source = Source::builtin("path-tracking").unwrap();
        let (mut setup, mut rng) = prepare(&source).unwrap();
        setup.run.duration_s = 10.0;
        // The robot starts 0.8 m right of the path heading east, its rear axle at
        // x = 0 and its front axle at x = 2 m: a plant just ahead of the right
        // rear wheel and one just ahead of the left front wheel are run over
        // within a fraction of a second; one between the wheels and one far
        // away are spared.
        let y0 = setup.initial.position.y();
        let plant = |x: f64, y: f64, kind: PlantKind| Plant {
            position: Point2::new(x, y).unwrap(),
            radius: 0.05,
            height: 0.3,
            kind,
        };
        setup.world.plants = vec![
            plant(0.3, y0 - 0.75, PlantKind::Crop),
            plant(2.2, y0 + 0.75, PlantKind::Crop),
            plant(0.3, y0, PlantKind::Crop),
            plant(4.0, y0 + 5.0, PlantKind::Crop),
            // Grass under a wheel is seen but never counted.
            plant(0.5, y0 - 0.75, PlantKind::Grass),
            plant(2.4, y0 + 0.75, PlantKind::Grass),
        ];
        let out = run(&setup, &mut rng);
        assert_eq!(out.plants_crushed, 2);
    }

    #[test]
    fn same_seed_same_trace() {
        let source = Source::builtin("path-tracking").unwrap();
        let (mut a, mut ra) = prepare(&source).unwrap();
        let (mut b, mut rb) = prepare(&source).unwrap();
        a.run.duration_s = 5.0;
        b.run.duration_s = 5.0;
        assert_eq!(run(&a, &mut ra), run(&b, &mut rb));
    }

    #[test]
    fn a_seed_override_replaces_the_files_seed_and_nothing_else() {
        let source = Source::builtin("furrow-pursuing").unwrap();
        let own = source.parse().unwrap().seed;
        // The file's own seed given explicitly: the same setup and run as `prepare`.
        let (mut a, mut ra) = prepare(&source).unwrap();
        let (mut b, mut rb) = prepare_with_seed(&source, own).unwrap();
        assert_eq!(b.seed, own);
        assert_eq!(a.world.plants, b.world.plants);
        a.run.duration_s = 5.0;
        b.run.duration_s = 5.0;
        let trace_a = run(&a, &mut ra);
        assert_eq!(trace_a, run(&b, &mut rb));
        // The same other seed twice: identical fields and traces.
        let other = own.wrapping_add(1);
        let (mut c, mut rc) = prepare_with_seed(&source, other).unwrap();
        let (mut d, mut rd) = prepare_with_seed(&source, other).unwrap();
        assert_eq!(c.seed, other);
        assert_eq!(c.world.plants, d.world.plants);
        c.run.duration_s = 5.0;
        d.run.duration_s = 5.0;
        let trace_c = run(&c, &mut rc);
        assert_eq!(trace_c, run(&d, &mut rd));
        // Another seed: another field (the plants moved), other noise
        // (another trace), the same scenario otherwise.
        assert_ne!(a.world.plants, c.world.plants);
        assert_ne!(trace_a.trace, trace_c.trace);
        assert_eq!(a.name, c.name);
        assert_eq!(a.world.plots.len(), c.world.plots.len());
        assert_eq!(a.furrow, c.furrow);
        // The text is untouched: the source still parses with its own seed.
        assert_eq!(source.parse().unwrap().seed, own);
    }
}
