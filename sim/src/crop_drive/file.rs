//! Crop drives as TOML files (`sim/scenarios/README.md`, "Crop drives"): a
//! file with a `[crop_drive]` table names one of the paper's crops and a
//! line-finding variant, and may change the crop, the robot, its odometry
//! and its LiDARs; the built-in `guyonneau-crop1` to `guyonneau-crop4` are
//! such files. Every table refuses unknown keys, and a value out of range is
//! an error naming its field.

use serde::Deserialize;

use fieldguide::perception::rows::ruby::Variant;

use super::{CropRun, LidarMount};
use crate::error::ScenarioError;
use crate::odometry::OdometryErrors;
use crate::scenario::check::Checker;

/// The built-in crop drives: `(name, TOML text)`.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "guyonneau-crop1",
        include_str!("../../scenarios/guyonneau-crop1.toml"),
    ),
    (
        "guyonneau-crop2",
        include_str!("../../scenarios/guyonneau-crop2.toml"),
    ),
    (
        "guyonneau-crop3",
        include_str!("../../scenarios/guyonneau-crop3.toml"),
    ),
    (
        "guyonneau-crop4",
        include_str!("../../scenarios/guyonneau-crop4.toml"),
    ),
];

/// A crop-drive file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CropDriveFile {
    /// The drive's name: the output folder.
    pub name: String,
    /// One line saying what it shows.
    pub description: String,
    /// The seed of the crop's generation and of every noise.
    pub seed: u64,
    /// The crop and the line finder.
    pub crop_drive: CropDriveSection,
    /// Changes to the crop (`[field]`, optional).
    #[serde(default)]
    pub field: FieldSection,
    /// Changes to the robot (`[robot]`, optional).
    #[serde(default)]
    pub robot: RobotSection,
    /// The odometry's errors (`[odometry]`, optional).
    pub odometry: Option<OdometrySection>,
    /// The LiDARs (`[[lidar]]`, one or two; the paper's two without).
    #[serde(default)]
    pub lidar: Vec<LidarSection>,
}

/// `[crop_drive]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CropDriveSection {
    /// The paper's crop, 1 to 4, as a start.
    pub crop: u8,
    /// `Ruby`, `RG`, `RGOP`, `RGOPPN` or `RGOPPNI`.
    pub variant: String,
}

/// `[field]`: each key replaces the crop's own.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSection {
    /// Distance between rows, m.
    pub spacing_m: Option<f64>,
    /// Row length, m.
    pub length_m: Option<f64>,
    /// Nominal distance between plants, m.
    pub plant_gap_m: Option<f64>,
    /// Along-row jitter, share of the gap.
    pub jitter_share: Option<f64>,
    /// Across-row jitter, m.
    pub lateral_jitter_m: Option<f64>,
    /// Probability that a plant is missing.
    pub missing: Option<f64>,
    /// Length of each row's hole, m.
    pub hole_m: Option<f64>,
    /// Weeds.
    pub weeds: Option<u32>,
    /// Each row ends up to this much short of the row length, m.
    pub ragged_ends_m: Option<f64>,
}

/// `[robot]`: each key replaces the paper run's.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    /// How far into the first inter-row O starts, m.
    pub start_along_m: Option<f64>,
    /// How far left of the inter-row's middle O starts, m.
    pub start_offset_m: Option<f64>,
    /// The fuzzy controller's top wheel speed, m/s.
    pub top_speed_m_s: Option<f64>,
    /// The wheels' time constant, s.
    pub wheel_lag_s: Option<f64>,
    /// The wheels' slip σ, share of the command.
    pub wheel_slip: Option<f64>,
    /// The LiDARs' range noise σ, m.
    pub lidar_noise_m: Option<f64>,
    /// The LiDARs send nothing from the first time to the second, s.
    pub lidar_outage_s: Option<[f64; 2]>,
    /// The longest the drive may take, s.
    pub duration_s: Option<f64>,
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

/// `[[lidar]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LidarSection {
    /// Position along the robot, m, forward positive.
    pub mount_x_m: f64,
    /// Position across, m, left positive.
    #[serde(default)]
    pub mount_y_m: f64,
    /// Facing, degrees (0 forward, 180 backward).
    pub heading_deg: f64,
}

/// Whether the TOML `text` is a crop drive (it has a `[crop_drive]` table).
#[must_use]
pub fn is_crop_drive(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("crop_drive"))
}

/// The variant of its paper name.
fn variant(name: &str) -> Option<Variant> {
    super::campaign::VARIANTS
        .into_iter()
        .find(|v| super::campaign::variant_name(*v) == name)
}

impl CropDriveFile {
    /// Parses `text` (`origin` names it in messages).
    pub fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        crate::scenario::parse_as(text, origin)
    }

    /// The validated run.
    pub fn run(&self, origin: &str) -> Result<CropRun, ScenarioError> {
        let check = Checker::new(origin);
        let v = variant(&self.crop_drive.variant).ok_or_else(|| {
            check.error(
                "crop_drive.variant",
                "must be one of Ruby, RG, RGOP, RGOPPN, RGOPPNI",
            )
        })?;
        let mut run = CropRun::paper(self.crop_drive.crop, v, self.seed)
            .ok_or_else(|| check.error("crop_drive.crop", "must be 1, 2, 3 or 4"))?;
        crate::scenario::setup::check_name(&check, &self.name)?;
        run.name.clone_from(&self.name);
        let f = &self.field;
        let c = &mut run.crop;
        check.replace(&mut c.spacing, f.spacing_m, "field.spacing_m", 0.3, 3.0)?;
        check.replace(&mut c.length, f.length_m, "field.length_m", 0.0, 500.0)?;
        check.replace(
            &mut c.plant_gap,
            f.plant_gap_m,
            "field.plant_gap_m",
            0.02,
            5.0,
        )?;
        check.replace(
            &mut c.jitter_share,
            f.jitter_share,
            "field.jitter_share",
            0.0,
            0.5,
        )?;
        check.replace(
            &mut c.lateral_jitter,
            f.lateral_jitter_m,
            "field.lateral_jitter_m",
            0.0,
            0.2,
        )?;
        check.replace(&mut c.missing, f.missing, "field.missing", 0.0, 1.0)?;
        check.replace(&mut c.hole, f.hole_m, "field.hole_m", 0.0, 100.0)?;
        check.replace(
            &mut c.ragged_ends,
            f.ragged_ends_m,
            "field.ragged_ends_m",
            0.0,
            100.0,
        )?;
        if let Some(w) = f.weeds {
            c.weeds = check.count("field.weeds", w, 0, 100_000)?;
        }
        let r = &self.robot;
        check.replace(
            &mut run.start.0,
            r.start_along_m,
            "robot.start_along_m",
            0.0,
            100.0,
        )?;
        check.replace(
            &mut run.start.1,
            r.start_offset_m,
            "robot.start_offset_m",
            -1.0,
            1.0,
        )?;
        check.replace(
            &mut run.top_speed_m_s,
            r.top_speed_m_s,
            "robot.top_speed_m_s",
            0.01,
            1.0,
        )?;
        check.replace(
            &mut run.wheel_lag_s,
            r.wheel_lag_s,
            "robot.wheel_lag_s",
            0.0,
            5.0,
        )?;
        check.replace(
            &mut run.wheel_slip,
            r.wheel_slip,
            "robot.wheel_slip",
            0.0,
            0.5,
        )?;
        check.replace(
            &mut run.lidar_noise_m,
            r.lidar_noise_m,
            "robot.lidar_noise_m",
            0.0,
            0.5,
        )?;
        check.replace(
            &mut run.duration_s,
            r.duration_s,
            "robot.duration_s",
            0.0,
            86_400.0,
        )?;
        if let Some([from, to]) = r.lidar_outage_s {
            let from = check.non_negative("robot.lidar_outage_s", from)?;
            if !(to.is_finite() && to > from) {
                return Err(
                    check.error("robot.lidar_outage_s", "must be [from, to] with to > from")
                );
            }
            run.outage_s = Some((from, to));
        }
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
        if !self.lidar.is_empty() {
            if self.lidar.len() > 2 {
                return Err(check.error(
                    "lidar",
                    "one or two LiDARs (the rows detector reads at most two)",
                ));
            }
            run.lidars = self
                .lidar
                .iter()
                .enumerate()
                .map(|(k, l)| {
                    let at = |key: &str| format!("lidar[{k}].{key}");
                    Ok(LidarMount {
                        x_m: check.range(&at("mount_x_m"), l.mount_x_m, -5.0, 5.0)?,
                        y_m: check.range(&at("mount_y_m"), l.mount_y_m, -5.0, 5.0)?,
                        heading_rad: check
                            .range(&at("heading_deg"), l.heading_deg, -360.0, 360.0)?
                            .to_radians(),
                    })
                })
                .collect::<Result<_, ScenarioError>>()?;
        }
        Ok(run)
    }
}
