//! Guided missions as TOML files (`sim/scenarios/README.md`, "Guided
//! missions on a tracked robot"): a file with a `[guiding]` table names the
//! layout of the field and the speeds and turning radii, and may change the
//! field, the robot and the GNSS; the built-in `welaser-lines` and
//! `welaser-turns` are such files. Every table refuses unknown keys, and a
//! value out of range is an error naming its field.

use serde::Deserialize;

use fieldguide::model::skid_steer::SkidSteer;
use fieldguide::planning::dubins::TurningRadius;
use fieldguide::{Meters, MetersPerSecond, Pose2};

use super::farm::{Farm, PlacedField, Road};
use super::field::{FieldSpec, Layout};
use super::mission::{MissionRun, Shape, WorldObstacle};
use super::{ControlSpec, GuidingRun, RobotSpec};
use crate::error::ScenarioError;
use crate::scenario::check::Checker;

/// The built-in guided missions: `(name, TOML text)`.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "welaser-lines",
        include_str!("../../scenarios/welaser-lines.toml"),
    ),
    (
        "welaser-turns",
        include_str!("../../scenarios/welaser-turns.toml"),
    ),
    (
        "welaser-farm",
        include_str!("../../scenarios/welaser-farm.toml"),
    ),
    (
        "welaser-mission",
        include_str!("../../scenarios/welaser-mission.toml"),
    ),
];

/// A guided-mission file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuidingFile {
    /// The mission's name: the output folder.
    pub name: String,
    /// One line saying what it shows.
    pub description: String,
    /// The seed of the plants and of every noise.
    pub seed: u64,
    /// The layout, speeds and radii.
    pub guiding: GuidingSection,
    /// Changes to the field (`[field]`, optional).
    #[serde(default)]
    pub field: FieldSection,
    /// Changes to the robot (`[robot]`, optional).
    #[serde(default)]
    pub robot: RobotSection,
    /// Changes to the GNSS (`[gnss]`, optional).
    #[serde(default)]
    pub gnss: GnssSection,
    /// A farm of such fields joined by roads (`[farm]`, optional).
    pub farm: Option<FarmSection>,
    /// The obstacles of a mission driven by the core's supervisor
    /// (`[[obstacle]]`, optional; with it the file is a mission with
    /// obstacles, `obstacle = []` one with none).
    pub obstacle: Option<Vec<ObstacleSection>>,
}

/// `[[obstacle]]`: a post, a box or a person on the farm.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSection {
    /// A name for the reports.
    pub name: String,
    /// `post`, `box` or `person`.
    pub kind: String,
    /// Where it stands (a person: where it starts walking), m.
    pub at: [f64; 2],
    /// A post's or a person's radius, m.
    pub radius_m: Option<f64>,
    /// A box's length and width, m.
    pub size_m: Option<[f64; 2]>,
    /// The direction of a box's length, degrees.
    pub heading_deg: Option<f64>,
    /// A person walks in a straight line (`[obstacle.walk]`).
    pub walk: Option<WalkSection>,
    /// Present from the first time to the second, s (default: always).
    pub present_s: Option<[f64; 2]>,
}

/// `[obstacle.walk]`: a person walking at a set time and speed.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WalkSection {
    /// Where the walk ends, m.
    pub to: [f64; 2],
    /// When it starts, s.
    pub start_s: f64,
    /// Its speed, m/s.
    pub speed_mps: f64,
}

/// `[farm]`: the yard, the fields (each the layout of `[guiding]` and
/// `[field]`, placed) and the roads between them.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FarmSection {
    /// The yard: x, y (m) and heading (degrees) where the robot starts.
    pub yard: [f64; 3],
    /// GoToGoal's turning radius at the roads' bends, m.
    pub corner_radius_m: f64,
    /// The roads' width, m.
    pub road_width_m: f64,
    /// The fields in the order they are treated (`[[farm.field]]`).
    pub field: Vec<PlacedFieldSection>,
    /// The roads (`[[farm.road]]`): to each field, then back to the yard.
    pub road: Vec<RoadSection>,
}

/// `[[farm.field]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlacedFieldSection {
    /// The field's corner, m.
    pub corner: [f64; 2],
    /// The direction of its rows, degrees.
    pub heading_deg: f64,
    /// How many passes the robot treats.
    pub passes: u32,
}

/// `[[farm.road]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoadSection {
    /// The waypoints between the road's start and its end, m.
    pub waypoints: Vec<[f64; 2]>,
}

/// `[guiding]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuidingSection {
    /// `rows` (row following, one radius) or `turns` (passes 2 r apart).
    pub layout: String,
    /// Nominal speed on lines, m/s.
    pub line_speed_mps: f64,
    /// Nominal speed in turns, m/s.
    pub turn_speed_mps: f64,
    /// Turning radii of the U-turns, used in turn, m.
    pub turn_radii_m: Vec<f64>,
    /// Every U-turn's footprint stays inside the field's outline.
    #[serde(default)]
    pub stay_inside: bool,
}

/// `[field]`: each key replaces the layout's own.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSection {
    /// Along the rows, m.
    pub length_m: Option<f64>,
    /// Across the rows, m.
    pub width_m: Option<f64>,
    /// Depth of each headland, m.
    pub headland_m: Option<f64>,
    /// Distance between crop rows, m (`rows` only).
    pub row_spacing_m: Option<f64>,
    /// Rows from one pass to the next (`rows` only).
    pub pass_rows: Option<u32>,
    /// Distance between plants, m.
    pub plant_gap_m: Option<f64>,
}

/// `[robot]`: each key replaces the default robot's.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    /// Distance between the tracks, m.
    pub track_m: Option<f64>,
    /// Time constant of the tracks, s.
    pub lag_s: Option<f64>,
    /// Slip of the left track, share.
    pub slip_left: Option<f64>,
    /// Slip of the right track, share.
    pub slip_right: Option<f64>,
    /// Effective over geometric track, ≥ 1.
    pub icr_factor: Option<f64>,
    /// O starts this far left of the first pass, m.
    pub start_offset_m: Option<f64>,
    /// The longest the mission may take, s.
    pub duration_s: Option<f64>,
}

/// `[gnss]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GnssSection {
    /// Position noise σ per axis, m.
    pub sigma_m: Option<f64>,
    /// Heading noise σ, rad.
    pub heading_sigma_rad: Option<f64>,
    /// No fix from the first time to the second, s.
    pub outage_s: Option<[f64; 2]>,
}

/// Whether the TOML `text` is a guided mission (it has a `[guiding]` table).
#[must_use]
pub fn is_guiding(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("guiding"))
}

impl GuidingFile {
    /// Parses `text` (`origin` names it in messages).
    ///
    /// # Errors
    /// A syntax error, an unknown key or a mistyped value, naming the field.
    pub fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        crate::scenario::parse_as(text, origin)
    }

    /// The validated run.
    ///
    /// # Errors
    /// A value out of range, naming its field.
    #[allow(clippy::too_many_lines)]
    pub fn run(&self, origin: &str) -> Result<GuidingRun, ScenarioError> {
        let check = Checker::new(origin);
        crate::scenario::setup::check_name(&check, &self.name)?;
        let g = &self.guiding;
        let mut field = match g.layout.as_str() {
            "rows" => FieldSpec::lines(),
            "turns" => FieldSpec::turns(),
            _ => return Err(check.error("guiding.layout", "must be `rows` or `turns`")),
        };
        let f = &self.field;
        check.replace(
            &mut field.length_m,
            f.length_m,
            "field.length_m",
            6.0,
            500.0,
        )?;
        check.replace(&mut field.width_m, f.width_m, "field.width_m", 2.0, 500.0)?;
        check.replace(
            &mut field.headland_m,
            f.headland_m,
            "field.headland_m",
            1.0,
            50.0,
        )?;
        if 2.0 * field.headland_m >= field.length_m - 1.0 {
            return Err(check.error(
                "field.headland_m",
                "the headlands leave no room for rows (need 2 headlands + 1 m <= length)",
            ));
        }
        check.replace(
            &mut field.plant_gap_m,
            f.plant_gap_m,
            "field.plant_gap_m",
            0.05,
            5.0,
        )?;
        if let Layout::Rows {
            row_spacing_m,
            pass_rows,
        } = &mut field.layout
        {
            check.replace(
                row_spacing_m,
                f.row_spacing_m,
                "field.row_spacing_m",
                0.3,
                5.0,
            )?;
            if let Some(p) = f.pass_rows {
                *pass_rows = u32::try_from(check.count("field.pass_rows", p, 1, 20)?).unwrap_or(1);
            }
        } else if f.row_spacing_m.is_some() || f.pass_rows.is_some() {
            return Err(check.error(
                "field.row_spacing_m",
                "only for layout `rows` (layout `turns` puts a row under each pass)",
            ));
        }
        let mut robot = RobotSpec::DEFAULT;
        let r = &self.robot;
        check.replace(&mut robot.track_m, r.track_m, "robot.track_m", 0.3, 3.0)?;
        check.replace(&mut robot.lag_s, r.lag_s, "robot.lag_s", 0.0, 2.0)?;
        check.replace(&mut robot.slip.0, r.slip_left, "robot.slip_left", 0.0, 0.3)?;
        check.replace(
            &mut robot.slip.1,
            r.slip_right,
            "robot.slip_right",
            0.0,
            0.3,
        )?;
        check.replace(
            &mut robot.icr_factor,
            r.icr_factor,
            "robot.icr_factor",
            1.0,
            2.0,
        )?;
        let mut control = ControlSpec::DEFAULT;
        control.line_speed = check.range(
            "guiding.line_speed_mps",
            g.line_speed_mps,
            0.1,
            robot.max_track_speed,
        )?;
        control.turn_speed = check.range(
            "guiding.turn_speed_mps",
            g.turn_speed_mps,
            0.1,
            robot.max_track_speed,
        )?;
        if g.turn_radii_m.is_empty() || g.turn_radii_m.len() > 20 {
            return Err(check.error("guiding.turn_radii_m", "one to twenty radii"));
        }
        let vehicle = SkidSteer::new(
            Meters::new(robot.track_m).map_err(|e| check.refused("robot.track_m", "track", &e))?,
            MetersPerSecond::new(robot.max_track_speed)
                .map_err(|e| check.refused("robot.track_m", "track speed", &e))?,
        )
        .map_err(|e| check.refused("robot.track_m", "robot", &e))?;
        for (k, &radius) in g.turn_radii_m.iter().enumerate() {
            let at = format!("guiding.turn_radii_m[{k}]");
            let radius = check.range(&at, radius, 0.1, 20.0)?;
            let m = Meters::new(radius).map_err(|e| check.refused(&at, "radius", &e))?;
            TurningRadius::for_vehicle(m, &vehicle)
                .map_err(|e| check.refused(&at, "turning radius", &e))?;
            if 2.0 * radius + robot.length_m / 2.0 + field.overhang_m > field.headland_m + 2.0 {
                return Err(check.error(&at, "the U-turn does not fit the headland"));
            }
        }
        field.turn_radii_m.clone_from(&g.turn_radii_m);
        let mut run = GuidingRun {
            name: self.name.clone(),
            seed: self.seed,
            field,
            robot,
            control,
            gnss_sigma_m: 0.015,
            gnss_heading_sigma_rad: 0.009,
            start_offset_m: 0.05,
            duration_s: 3600.0,
            fault: None,
            stay_inside: g.stay_inside,
            farm: None,
            gnss_outage_s: None,
        };
        check.replace(
            &mut run.start_offset_m,
            r.start_offset_m,
            "robot.start_offset_m",
            -0.5,
            0.5,
        )?;
        check.replace(
            &mut run.duration_s,
            r.duration_s,
            "robot.duration_s",
            1.0,
            86_400.0,
        )?;
        check.replace(
            &mut run.gnss_sigma_m,
            self.gnss.sigma_m,
            "gnss.sigma_m",
            0.0,
            0.5,
        )?;
        check.replace(
            &mut run.gnss_heading_sigma_rad,
            self.gnss.heading_sigma_rad,
            "gnss.heading_sigma_rad",
            0.0,
            0.2,
        )?;
        if let Some([from, to]) = self.gnss.outage_s {
            let from = check.non_negative("gnss.outage_s", from)?;
            if !(to.is_finite() && to > from) {
                return Err(check.error("gnss.outage_s", "must be [from, to] with to > from"));
            }
            run.gnss_outage_s = Some((from, to));
        }
        if run.field.passes().len() < 2 {
            return Err(check.error("field.width_m", "the field holds fewer than two passes"));
        }
        if let Some(farm) = &self.farm {
            run.farm = Some(farm.farm(&check, &run, &vehicle)?);
        }
        Ok(run)
    }
}

impl GuidingFile {
    /// The mission with obstacles of a file with `[[obstacle]]` tables
    /// (`None` without them), validated: the farm's run and its obstacles.
    ///
    /// # Errors
    /// Those of [`GuidingFile::run`]; an obstacle without a `[farm]`, or a
    /// value out of range, naming `obstacle[k].<field>`.
    //= spec/emmi2024.md#em-sim-mission-file-missions-with-obstacles-as-files
    //# A scenario file's `[[obstacle]]` tables MUST be refused, naming the file
    //# and the field, for an unknown kind, a size or radius out of range, a
    //# non-finite place, a walk that is not a person's or has no positive
    //# duration, or a presence that ends before it starts.
    pub fn mission(&self, origin: &str) -> Result<Option<MissionRun>, ScenarioError> {
        let Some(sections) = &self.obstacle else {
            return Ok(None);
        };
        let guiding = self.run(origin)?;
        let check = Checker::new(origin);
        if guiding.farm.is_none() {
            return Err(check.error("obstacle", "obstacles need a [farm]"));
        }
        if sections.len() > 64 {
            return Err(check.error("obstacle", "at most 64 obstacles"));
        }
        let obstacles = sections
            .iter()
            .enumerate()
            .map(|(k, o)| o.obstacle(&check, k))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Some(MissionRun { guiding, obstacles }))
    }
}

impl ObstacleSection {
    /// The validated obstacle `k` of the file.
    fn obstacle(&self, check: &Checker, k: usize) -> Result<WorldObstacle, ScenarioError> {
        let at = |f: &str| format!("obstacle[{k}].{f}");
        if self.name.trim().is_empty() {
            return Err(check.error(&at("name"), "must not be empty"));
        }
        let place = |f: &str, p: [f64; 2]| -> Result<(f64, f64), ScenarioError> {
            Ok((check.finite(&at(f), p[0])?, check.finite(&at(f), p[1])?))
        };
        let circle = |what: &str| -> Result<Shape, ScenarioError> {
            if self.size_m.is_some() || self.heading_deg.is_some() {
                return Err(check.error(
                    &at("size_m"),
                    &format!("a {what} has a radius_m, not a size_m or heading_deg"),
                ));
            }
            let r = self
                .radius_m
                .ok_or_else(|| check.error(&at("radius_m"), &format!("a {what} needs one")))?;
            Ok(Shape::Circle {
                radius: check.range(&at("radius_m"), r, 0.02, 2.0)?,
            })
        };
        let shape = match self.kind.as_str() {
            "post" => circle("post")?,
            "person" => circle("person")?,
            "box" => {
                if self.radius_m.is_some() {
                    return Err(check.error(&at("radius_m"), "a box has a size_m, not a radius_m"));
                }
                let [l, w] = self
                    .size_m
                    .ok_or_else(|| check.error(&at("size_m"), "a box needs [length, width]"))?;
                Shape::Box {
                    length: check.range(&at("size_m"), l, 0.05, 20.0)?,
                    width: check.range(&at("size_m"), w, 0.05, 20.0)?,
                    heading: check
                        .finite(&at("heading_deg"), self.heading_deg.unwrap_or(0.0))?
                        .to_radians(),
                }
            }
            _ => {
                return Err(check.error(&at("kind"), "must be `post`, `box` or `person`"));
            }
        };
        let from = place("at", self.at)?;
        let walk = match &self.walk {
            None => None,
            Some(_) if self.kind != "person" => {
                return Err(check.error(&at("walk"), "only a person walks"));
            }
            Some(w) => {
                let to = place("walk.to", w.to)?;
                let start = check.non_negative(&at("walk.start_s"), w.start_s)?;
                let speed = check.range(&at("walk.speed_mps"), w.speed_mps, 0.05, 5.0)?;
                let length = (to.0 - from.0).hypot(to.1 - from.1);
                if length <= 0.0 {
                    return Err(check.error(&at("walk.to"), "must differ from `at`"));
                }
                Some((to, start, start + length / speed))
            }
        };
        let present_s = match self.present_s {
            None => (0.0, f64::INFINITY),
            Some([a, b]) => {
                let a = check.non_negative(&at("present_s"), a)?;
                if !(b.is_finite() && b > a) {
                    return Err(check.error(&at("present_s"), "must be [from, to] with to > from"));
                }
                (a, b)
            }
        };
        Ok(WorldObstacle {
            name: self.name.clone(),
            shape,
            at: from,
            walk,
            present_s,
        })
    }
}

/// The built-in mission with obstacles `name` (`None` for an unknown name or
/// a built-in without `[[obstacle]]` tables), validated.
///
/// # Errors
/// When the built-in file is not valid (a bug).
//= spec/emmi2024.md#em-sim-mission-file-missions-with-obstacles-as-files
//# A scenario file with `[guiding]`, `[farm]` and `[[obstacle]]` tables MUST be
//# driven by the core's mission supervisor with those obstacles, and the
//# built-in `welaser-mission` MUST be such a file.
pub fn builtin_mission(name: &str) -> Option<Result<MissionRun, ScenarioError>> {
    let (n, text) = BUILTIN.iter().find(|(n, _)| *n == name)?;
    let origin = format!("built-in scenario `{n}`");
    GuidingFile::parse(text, &origin)
        .and_then(|f| f.mission(&origin))
        .transpose()
}

/// The built-in mission `name`, validated.
///
/// # Errors
/// When the built-in file is not valid (a bug).
pub fn builtin(name: &str) -> Option<Result<GuidingRun, ScenarioError>> {
    BUILTIN.iter().find(|(n, _)| *n == name).map(|(n, text)| {
        let origin = format!("built-in scenario `{n}`");
        GuidingFile::parse(text, &origin)?.run(&origin)
    })
}

impl FarmSection {
    /// The validated farm of fields like `run.field`.
    //= spec/emmi2024.md#em-sim-farm-roads-joining-fields
    //# A farm whose roads do not match its fields, bend too tightly for their
    //# stretches, leave or meet a field more than 45° off its passes, or run
    //# across a field's crop rows MUST be refused, naming the road.
    fn farm(
        &self,
        check: &Checker,
        run: &GuidingRun,
        vehicle: &SkidSteer,
    ) -> Result<Farm, ScenarioError> {
        let [x, y, heading_deg] = self.yard;
        let yard = Pose2::new(x, y, heading_deg.to_radians())
            .map_err(|e| check.refused("farm.yard", "yard", &e))?;
        let radius = Meters::new(self.corner_radius_m)
            .map_err(|e| check.refused("farm.corner_radius_m", "radius", &e))?;
        TurningRadius::for_vehicle(radius, vehicle)
            .map_err(|e| check.refused("farm.corner_radius_m", "turning radius", &e))?;
        let mut road_width_m = 4.0;
        check.replace(
            &mut road_width_m,
            Some(self.road_width_m),
            "farm.road_width_m",
            1.0,
            50.0,
        )?;
        if self.field.is_empty() || self.field.len() > 20 {
            return Err(check.error("farm.field", "one to twenty fields"));
        }
        let passes = run.field.passes().len();
        let mut fields = Vec::new();
        for (k, f) in self.field.iter().enumerate() {
            let at = format!("farm.field[{k}].passes");
            let p = usize::try_from(f.passes).unwrap_or(0);
            if p == 0 || p > passes {
                return Err(check.error(
                    &at,
                    &format!("must be 1 to {passes}, the passes the field holds"),
                ));
            }
            if !(f.corner.iter().all(|v| v.is_finite()) && f.heading_deg.is_finite()) {
                return Err(check.error(
                    &format!("farm.field[{k}]"),
                    "corner and heading must be finite",
                ));
            }
            fields.push(PlacedField {
                corner: (f.corner[0], f.corner[1]),
                heading_rad: f.heading_deg.to_radians(),
                field: run.field.clone(),
                passes: p,
            });
        }
        if self.road.len() != fields.len() + 1 {
            return Err(check.error(
                "farm.road",
                "one road to each field and one back to the yard (one more than the fields)",
            ));
        }
        let roads = self
            .road
            .iter()
            .map(|r| Road {
                waypoints: r.waypoints.iter().map(|w| (w[0], w[1])).collect(),
            })
            .collect();
        let farm = Farm {
            yard,
            fields,
            roads,
            corner_radius_m: self.corner_radius_m,
            road_width_m,
        };
        farm.route()
            .map_err(|e| check.refused("farm.road", "route", &e))?;
        if let Some((road, field)) = farm.road_across_rows() {
            return Err(check.error(
                &format!("farm.road[{road}]"),
                &format!("crosses the crop rows of field {field}"),
            ));
        }
        Ok(farm)
    }
}
