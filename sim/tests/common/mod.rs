//! Helpers shared by the closed-loop tests of the specialised behaviours.
#![allow(dead_code, clippy::unwrap_used, clippy::indexing_slicing)]

use fieldguide::geometry::path::PathConfig;
use fieldguide::guidance::Mode;
use fieldguide::{Meters, Point2, Verdict, World};
use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, TickRecord};
use fieldguide_sim::scenario::setup::Reference;
use fieldguide_sim::scenario::{Setup, Source};

/// The built-in scenario `name` with `seed` in place of its own (another
/// field, other noise; `runner::prepare_with_seed`).
pub fn prepare_seed(name: &str, seed: u64) -> (Setup, SimRng) {
    prepare_edited(name, seed, |t| t)
}

/// The built-in scenario `name`, its text edited by `edit` (other
/// parameters), with `seed` in place of its own.
pub fn prepare_edited(
    name: &str,
    seed: u64,
    edit: impl FnOnce(String) -> String,
) -> (Setup, SimRng) {
    let mut source = Source::builtin(name).unwrap();
    source.text = edit(source.text);
    runner::prepare_with_seed(&source, seed).unwrap()
}

/// The stress field `name` (`sim/scenarios/stress/<name>.toml`) as written.
pub fn stress_source(name: &str) -> Source {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios/stress")
        .join(format!("{name}.toml"));
    Source::file(&path).unwrap()
}

/// A scenario's `text` without the lines that start with `key` (an optional
/// rule switched off: `handover_`, `entry_`, `bridge_m`).
pub fn without_key(text: &str, key: &str) -> String {
    text.lines()
        .filter(|l| !l.starts_with(key))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The stress field `name` with its lines starting with `off` removed when
/// given (an optional rule switched off).
pub fn stress_source_without(name: &str, off: Option<&str>) -> Source {
    let mut source = stress_source(name);
    if let Some(key) = off {
        source.text = without_key(&source.text, key);
    }
    source
}

/// Per seed of `seeds`, of the stress field `name` without its lines
/// starting with `off` ([`stress_source_without`]): the largest
/// and the mean |error to the followed line| and the largest error towards
/// the hedge from the envelope's line (`stress::envelope::face_errors`).
/// Every run must reach the path's end and follow the edge.
pub fn followed_figures(
    name: &str,
    off: Option<&str>,
    seeds: std::ops::RangeInclusive<u64>,
) -> Vec<(f64, f64, f64)> {
    seeds
        .map(|seed| {
            let source = stress_source_without(name, off);
            let (setup, mut rng) = runner::prepare_with_seed(&source, seed).unwrap();
            let out = runner::run(&setup, &mut rng);
            assert_eq!(out.end, runner::RunEnd::PathEnd, "{name}, seed {seed}");
            let errors = fieldguide_sim::stress::envelope::face_errors(&setup, &out.trace);
            assert!(!errors.is_empty(), "{name}, seed {seed}: no edge following");
            let max = errors.iter().map(|e| e.followed.abs()).fold(0.0, f64::max);
            let mean = errors.iter().map(|e| e.followed.abs()).sum::<f64>() / errors.len() as f64;
            let towards = errors.iter().map(|e| -e.envelope).fold(0.0, f64::max);
            (max, mean, towards)
        })
        .collect()
}

/// The worst of `values` over a sweep: the largest, with the seed it came from.
pub fn worst_of(values: impl IntoIterator<Item = (u64, f64)>) -> (u64, f64) {
    values.into_iter().fold(
        (0, f64::NEG_INFINITY),
        |w, (seed, v)| if v > w.1 { (seed, v) } else { w },
    )
}

/// Moves the recorded path `dy` metres to the north (a GNSS offset), so a test
/// can tell whether the rows or hedge steer, or the path does.
pub fn shift_recorded_path(setup: &mut Setup, dy: f64) {
    let shifted: Vec<Point2<World>> = setup
        .path
        .vertices()
        .iter()
        .map(|v| Point2::new(v.position.x(), v.position.y() + dy).unwrap())
        .collect();
    *setup.path = Reference::from_waypoints(
        &shifted,
        PathConfig::new(Meters::new(1.0).unwrap()).unwrap(),
    )
    .unwrap();
}

/// The ticks that have been steered by `mode` for more than `settled_m` metres
/// of travel since that mode last took over.
pub fn settled_in(trace: &[TickRecord], mode: Mode, settled_m: f64) -> Vec<&TickRecord> {
    let mut since_switch = 0.0;
    let mut settled = Vec::new();
    for w in trace.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        since_switch = if a.mode() == mode {
            since_switch + (b.distance_m - a.distance_m)
        } else {
            0.0
        };
        if since_switch > settled_m {
            settled.push(a);
        }
    }
    settled
}

/// How one specialised behaviour runs in a closed-loop scenario: its mode,
/// how many consecutive Enter ticks its entry takes, and the desired speeds
/// of it and of path tracking, m/s.
pub struct Behaviour {
    pub mode: Mode,
    pub enter_ticks: usize,
    pub speed: f64,
    pub path_speed: f64,
}

/// Checks that no command of `trace` comes from a stale or invalid estimate,
/// and returns the count of each verdict over the scans ([enter, hold, exit,
/// absent]): every tick carries its latest scan's verdict (younger than
/// `scan_period` seconds); the behaviour steers only with Enter or Hold, on
/// the detector's own error in a scan tick, a straight line, at its speed;
/// path tracking steers at its speed while at most `enter_ticks` Enter
/// verdicts run; no other mode appears.
pub fn assert_commands_from_fresh_valid_estimates(
    trace: &[TickRecord],
    scan_period: f64,
    behaviour: &Behaviour,
) -> [usize; 4] {
    let first = trace[0].command.detector.unwrap();
    assert!(first.scanned && first.verdict == Verdict::Absent);
    let mut verdicts = [0_usize; 4];
    let mut enters = 0_usize;
    for r in trace {
        let d = r.command.detector.unwrap();
        assert!(
            d.age_s >= 0.0 && d.age_s < scan_period - 1e-9,
            "t = {}: age {}",
            r.t_s,
            d.age_s
        );
        if d.scanned {
            verdicts[Verdict::ALL.iter().position(|v| *v == d.verdict).unwrap()] += 1;
        }
        let speed = r.command.speed().get();
        if r.mode() == behaviour.mode {
            enters = 0;
            assert!(
                d.verdict.estimate_is_valid(),
                "t = {}: {:?}",
                r.t_s,
                d.verdict
            );
            // The law's error is the detector's, moved by odometry between scans.
            let used = r.command.estimated_error.unwrap();
            if d.scanned {
                let own = d.error.unwrap();
                assert!((used.y.get() - own.y.get()).abs() < 1e-9);
                assert!((used.angular_deviation.get() - own.angular_deviation.get()).abs() < 1e-9);
            }
            assert!(used.curvature.get().abs() < 1e-15, "a straight line");
            assert!((speed - behaviour.speed).abs() < 1e-12, "t = {}", r.t_s);
        } else if r.mode() == Mode::PathTracking {
            // Path tracking steers while the machine counts Enter verdicts:
            // at most the transit delay's ticks in a row (SW-DELAYS).
            enters = if d.verdict == Verdict::Enter {
                enters + 1
            } else {
                0
            };
            assert!(
                enters <= behaviour.enter_ticks,
                "t = {}: {enters} Enter ticks",
                r.t_s
            );
            assert!(
                (speed - behaviour.path_speed).abs() < 1e-12,
                "t = {}",
                r.t_s
            );
        } else {
            panic!(
                "t = {}: {:?} in a run of {:?}",
                r.t_s,
                r.mode(),
                behaviour.mode
            );
        }
    }
    verdicts
}

/// An open-loop furrow rig: plants on flat ground, the simulated inclined
/// LiDAR, drifting wheel odometry (`OdometryErrors::FIELD`) and a furrow
/// detector, for tests that drive the robot along known poses and compare
/// what the detector reports with the true rows.
pub struct FurrowRig {
    index: fieldguide_sim::world::crops::PlantIndex,
    ground: fieldguide_sim::world::terrain::Ground,
    lidar: fieldguide_sim::lidar::inclined::InclinedLidar,
    odometry: fieldguide_sim::odometry::WheelOdometry,
    /// The detector under test.
    pub detector: fieldguide::perception::furrow::FurrowDetector<256, 32>,
}

impl FurrowRig {
    /// `plants` seen by the default inclined LiDAR, detected with `params`.
    pub fn new(
        plants: Vec<fieldguide_sim::world::Plant>,
        params: &fieldguide::perception::furrow::FurrowParams,
    ) -> Self {
        Self::with_odometry(
            plants,
            params,
            fieldguide_sim::odometry::OdometryErrors::FIELD,
        )
    }

    /// As [`Self::new`], with the odometry's error model `errors`.
    pub fn with_odometry(
        plants: Vec<fieldguide_sim::world::Plant>,
        params: &fieldguide::perception::furrow::FurrowParams,
        errors: fieldguide_sim::odometry::OdometryErrors,
    ) -> Self {
        use fieldguide::perception::furrow::{FurrowConfig, FurrowDetector};
        use fieldguide_sim::odometry::WheelOdometry;
        Self {
            index: fieldguide_sim::world::crops::PlantIndex::new(plants, 0.5),
            ground: fieldguide_sim::world::terrain::Ground::default(),
            lidar: fieldguide_sim::lidar::inclined::InclinedLidar::furrow_default(),
            odometry: WheelOdometry::new(fieldguide::Pose2::new(10.0, -3.0, 1.0).unwrap(), errors),
            detector: FurrowDetector::new(FurrowConfig::new(params).unwrap()).unwrap(),
        }
    }

    /// What the detector makes of a scan cast from the true pose `pose`.
    pub fn detect(
        &mut self,
        pose: &fieldguide::Pose2<World>,
        rng: &mut impl rand::Rng,
    ) -> fieldguide::perception::furrow::FurrowDetection {
        let world = fieldguide_sim::world::scene::Scene {
            ground: &self.ground,
            plants: &self.index,
            obstacles: None,
            obstacle_height: 2.0,
        };
        let scan = self.lidar.scan(pose, &world, rng);
        self.detector
            .detect(&scan.as_scan().unwrap(), &self.odometry.pose())
            .unwrap()
    }

    /// The odometry's reading of the true motion from `from` to `to`.
    pub fn drive(
        &mut self,
        from: &fieldguide::Pose2<World>,
        to: &fieldguide::Pose2<World>,
        rng: &mut impl rand::Rng,
    ) {
        self.odometry.update_between(from, to, rng);
    }
}
