//! Vine-row runs as TOML files (`sim/scenarios/README.md`, "Vine rows"): a
//! file with a `[vineyard]` table names the season and the law, and may
//! change the vineyard (`[field]`), the robot (`[robot]`) and its odometry
//! (`[odometry]`); the built-in `vineyard-*` runs are such files. Every
//! table refuses unknown keys, and a value out of range is an error naming
//! its field.

use serde::Deserialize;

use super::field::Season;
use super::{Strategy, VineyardRun};
use crate::error::ScenarioError;
use crate::odometry::OdometryErrors;
use crate::scenario::check::Checker;

/// The built-in vine-row runs: `(name, TOML text)`.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "vineyard-summer-s1",
        include_str!("../../scenarios/vineyard-summer-s1.toml"),
    ),
    (
        "vineyard-summer-s2",
        include_str!("../../scenarios/vineyard-summer-s2.toml"),
    ),
    (
        "vineyard-winter-s1",
        include_str!("../../scenarios/vineyard-winter-s1.toml"),
    ),
    (
        "vineyard-winter-s2",
        include_str!("../../scenarios/vineyard-winter-s2.toml"),
    ),
    (
        "vineyard-summer-2ws",
        include_str!("../../scenarios/vineyard-summer-2ws.toml"),
    ),
    (
        "vineyard-rows-and-turns",
        include_str!("../../scenarios/vineyard-rows-and-turns.toml"),
    ),
];

/// A vine-row file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VineyardFile {
    /// The run's name: the output folder.
    pub name: String,
    /// One line saying what it shows.
    pub description: String,
    /// The seed of the vineyard's generation and of every noise.
    pub seed: u64,
    /// The season and the law.
    pub vineyard: VineyardSection,
    /// Changes to the vineyard (`[field]`, optional).
    #[serde(default)]
    pub field: FieldSection,
    /// Changes to the robot (`[robot]`, optional).
    #[serde(default)]
    pub robot: RobotSection,
    /// The odometry's errors (`[odometry]`, optional).
    pub odometry: Option<OdometrySection>,
}

/// `[vineyard]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VineyardSection {
    /// `summer` or `winter`.
    pub season: String,
    /// `s1`, `s2` or `2ws` (strategy 1 with the rear steering held at 0).
    pub strategy: String,
    /// Follow row 0, turn in the headland, follow row 2 back, switched by
    /// the core pipeline (strategy 1 only).
    #[serde(default)]
    pub turns: bool,
}

/// `[field]`: each key replaces the season's own.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSection {
    /// Rows.
    pub rows: Option<u32>,
    /// Distance between rows, m.
    pub spacing_m: Option<f64>,
    /// Row length, m.
    pub length_m: Option<f64>,
    /// Distance between vines, m.
    pub vine_gap_m: Option<f64>,
    /// Canopy width, m.
    pub canopy_width_m: Option<f64>,
    /// Canopy top above the ground, m.
    pub canopy_height_m: Option<f64>,
    /// Probability that a canopy cylinder is there.
    pub density: Option<f64>,
    /// Probability that a vine is missing.
    pub missing: Option<f64>,
    /// The first vines of every row, all missing.
    pub missing_at_entry: Option<u32>,
    /// Distance between posts, m.
    pub post_gap_m: Option<f64>,
    /// Along-row slope dz/dx.
    pub slope_along: Option<f64>,
    /// Cross slope dz/dy.
    pub slope_across: Option<f64>,
    /// Bumps' amplitude, m (0: none).
    pub bump_amplitude_m: Option<f64>,
    /// Bumps' wavelength, m.
    pub bump_wavelength_m: Option<f64>,
}

/// `[robot]`: each key replaces the paper run's.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    /// Forward speed, m/s.
    pub speed_mps: Option<f64>,
    /// How far before the row's first vine the front axle starts, m.
    pub start_before_m: Option<f64>,
    /// How far left of the row centre line R starts, m.
    pub start_offset_m: Option<f64>,
    /// Strategy 1's gains [k_y, k_θ, k_r], equation form (negative).
    pub gains_s1: Option<[f64; 3]>,
    /// Strategy 2's gains [K_F, K_R] (positive).
    pub gains_s2: Option<[f64; 2]>,
    /// The actuators' 5 % settling time, s.
    pub steering_settling_s: Option<f64>,
    /// The actuators' rate limit, rad/s.
    pub steering_rate_rad_s: Option<f64>,
    /// The steering saturation, rad.
    pub steering_limit_rad: Option<f64>,
    /// The ground's sideslip [front, rear], rad.
    pub sideslip_rad: Option<[f64; 2]>,
    /// A stretch of low grip [from x, to x, sideslip rad].
    pub low_grip: Option<[f64; 3]>,
    /// Whether the law is given the true sideslip.
    pub sideslip_known: Option<bool>,
    /// The LiDAR's angular resolution, degrees.
    pub lidar_resolution_deg: Option<f64>,
    /// The LiDAR's range noise σ, m.
    pub lidar_noise_m: Option<f64>,
    /// The detector's model margin, rays.
    pub model_margin: Option<u32>,
    /// Errors are summarised from this distance along the row, m.
    pub settle_m: Option<f64>,
}

/// `[odometry]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OdometrySection {
    /// Relative distance error.
    pub scale: f64,
    /// Heading drift, rad/m.
    pub yaw_drift_rad_m: f64,
    /// Distance noise, m/√m.
    pub distance_noise: f64,
    /// Heading noise, rad/√m.
    pub yaw_noise: f64,
}

/// Whether the TOML `text` is a vine-row run (it has a `[vineyard]` table).
#[must_use]
pub fn is_vineyard(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("vineyard"))
}

impl VineyardFile {
    /// Parses `text` (`origin` names it in messages).
    pub fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        crate::scenario::parse_as(text, origin)
    }

    /// The validated run.
    pub fn run(&self, origin: &str) -> Result<VineyardRun, ScenarioError> {
        let check = Checker::new(origin);
        let season = match self.vineyard.season.as_str() {
            "summer" => Season::Summer,
            "winter" => Season::Winter,
            _ => return Err(check.error("vineyard.season", "must be summer or winter")),
        };
        let strategy = match self.vineyard.strategy.as_str() {
            "s1" => Strategy::One,
            "s2" => Strategy::Two,
            "2ws" => Strategy::TwoWheel,
            _ => return Err(check.error("vineyard.strategy", "must be s1, s2 or 2ws")),
        };
        let mut run = VineyardRun::paper(season, strategy, self.seed);
        if self.vineyard.turns {
            if strategy != Strategy::One {
                return Err(check.error(
                    "vineyard.turns",
                    "the headland turn runs with strategy s1 only",
                ));
            }
            run.turns = true;
            run.low_grip = None;
        }
        crate::scenario::setup::check_name(&check, &self.name)?;
        run.name.clone_from(&self.name);
        let f = &self.field;
        let c = &mut run.field;
        if let Some(r) = f.rows {
            c.rows = check.count("field.rows", r, 1, 20)?;
        }
        check.replace(&mut c.spacing, f.spacing_m, "field.spacing_m", 1.5, 4.0)?;
        check.replace(&mut c.length, f.length_m, "field.length_m", 15.0, 300.0)?;
        check.replace(&mut c.vine_gap, f.vine_gap_m, "field.vine_gap_m", 0.5, 3.0)?;
        check.replace(
            &mut c.canopy_width,
            f.canopy_width_m,
            "field.canopy_width_m",
            0.05,
            0.8,
        )?;
        check.replace(
            &mut c.canopy_height,
            f.canopy_height_m,
            "field.canopy_height_m",
            0.3,
            1.6,
        )?;
        check.replace(&mut c.density, f.density, "field.density", 0.0, 1.0)?;
        check.replace(&mut c.missing, f.missing, "field.missing", 0.0, 1.0)?;
        if let Some(n) = f.missing_at_entry {
            c.missing_at_entry = check.count("field.missing_at_entry", n, 0, 10)?;
        }
        check.replace(
            &mut c.post_gap,
            f.post_gap_m,
            "field.post_gap_m",
            1.0,
            100.0,
        )?;
        check.replace(
            &mut c.slope[0],
            f.slope_along,
            "field.slope_along",
            -0.3,
            0.3,
        )?;
        check.replace(
            &mut c.slope[1],
            f.slope_across,
            "field.slope_across",
            -0.3,
            0.3,
        )?;
        let (mut amp, mut wave, heading) = c.bumps.unwrap_or((0.0, 3.0, 0.6));
        check.replace(
            &mut amp,
            f.bump_amplitude_m,
            "field.bump_amplitude_m",
            0.0,
            0.2,
        )?;
        check.replace(
            &mut wave,
            f.bump_wavelength_m,
            "field.bump_wavelength_m",
            0.5,
            50.0,
        )?;
        c.bumps = (amp > 0.0).then_some((amp, wave, heading));
        let r = &self.robot;
        check.replace(&mut run.speed_mps, r.speed_mps, "robot.speed_mps", 0.1, 3.0)?;
        check.replace(
            &mut run.start.0,
            r.start_before_m,
            "robot.start_before_m",
            0.0,
            20.0,
        )?;
        check.replace(
            &mut run.start.1,
            r.start_offset_m,
            "robot.start_offset_m",
            -1.0,
            1.0,
        )?;
        if let Some([k_y, k_t, k_r]) = r.gains_s1 {
            for (k, field) in [(k_y, "k_y"), (k_t, "k_theta"), (k_r, "k_r")] {
                check.range(&format!("robot.gains_s1.{field}"), k, -20.0, -1e-3)?;
            }
            run.gains1 = (k_y, k_t, k_r);
        }
        if let Some([k_f, k_r]) = r.gains_s2 {
            check.range("robot.gains_s2.K_F", k_f, 1e-3, 20.0)?;
            check.range("robot.gains_s2.K_R", k_r, 1e-3, 20.0)?;
            run.gains2 = (k_f, k_r);
        }
        check.replace(
            &mut run.steering.0,
            r.steering_settling_s,
            "robot.steering_settling_s",
            0.0,
            5.0,
        )?;
        check.replace(
            &mut run.steering.1,
            r.steering_rate_rad_s,
            "robot.steering_rate_rad_s",
            0.01,
            10.0,
        )?;
        check.replace(
            &mut run.steering.2,
            r.steering_limit_rad,
            "robot.steering_limit_rad",
            0.05,
            1.2,
        )?;
        if let Some([front, rear]) = r.sideslip_rad {
            run.sideslip = (
                check.range("robot.sideslip_rad", front, -0.5, 0.5)?,
                check.range("robot.sideslip_rad", rear, -0.5, 0.5)?,
            );
        }
        if let Some([from, to, beta]) = r.low_grip {
            let from = check.finite("robot.low_grip", from)?;
            if !(to.is_finite() && to > from) {
                return Err(
                    check.error("robot.low_grip", "must be [from, to, beta] with to > from")
                );
            }
            run.low_grip = Some((from, to, check.range("robot.low_grip", beta, -0.5, 0.5)?));
        }
        if let Some(k) = r.sideslip_known {
            run.sideslip_known = k;
        }
        check.replace(
            &mut run.lidar_resolution_deg,
            r.lidar_resolution_deg,
            "robot.lidar_resolution_deg",
            0.25,
            3.0,
        )?;
        check.replace(
            &mut run.lidar_noise_m,
            r.lidar_noise_m,
            "robot.lidar_noise_m",
            0.0,
            0.2,
        )?;
        if let Some(m) = r.model_margin {
            run.model_margin = check.count("robot.model_margin", m, 1, 20)?;
        }
        check.replace(&mut run.settle_m, r.settle_m, "robot.settle_m", 0.0, 300.0)?;
        if let Some(o) = &self.odometry {
            run.odometry = OdometryErrors {
                scale: check.range("odometry.scale", o.scale, -0.5, 0.5)?,
                yaw_drift: check.range("odometry.yaw_drift_rad_m", o.yaw_drift_rad_m, -1.0, 1.0)?,
                distance_noise: check.range(
                    "odometry.distance_noise",
                    o.distance_noise,
                    0.0,
                    1.0,
                )?,
                yaw_noise: check.range("odometry.yaw_noise", o.yaw_noise, 0.0, 1.0)?,
            };
        }
        if run.settle_m >= run.field.length - run.stop_before_end_m {
            return Err(check.error(
                "robot.settle_m",
                "must be shorter than the row less its last 3 m",
            ));
        }
        Ok(run)
    }
}
