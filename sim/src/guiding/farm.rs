//! A farm of several fields joined by roads (Emmi 2024, section 4: "a set of
//! roads connecting the farm's diverse elements, including buildings and crop
//! fields"; the robot follows "a set of geographical waypoints" to reach each
//! field, then treats it).
//!
//! The mission starts in the yard, drives road 0 to field 0, treats its
//! first passes, drives road 1 to field 1, and so on; the last road leads
//! back to the yard. Each road is a polyline of waypoints from where the
//! robot stands (the yard, or the end of the last pass treated) to the next
//! field's first pass, or to the yard. Its goals follow the paper's rule
//! (section 4, EM-PLANNER): a waypoint where the road bends by less than 45°
//! is a LineFollowing goal; at a bend of 45° or more the robot follows the
//! road to the bend's first tangent point, and GoToGoal turns it onto the
//! next stretch with the road's corner radius (EM-SIM-FARM).

use core::f64::consts::{FRAC_PI_4, PI};

use fieldguide::{Pose2, Precondition, World};

use super::boundary::Boundary;
use super::field::{FieldSpec, Goal};
use crate::rng::SimRng;
use crate::world::Plant;

/// How far before a bend's first tangent point the LineFollowing goal
/// lies, m: the robot may stop a little past its goal, and GoToGoal's
/// word then still begins with the straight that leads into the arc.
pub const BEND_SLACK_M: f64 = 0.5;

/// What a goal of a farm mission belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Task {
    /// Driving road `k` (Approximation).
    Road(usize),
    /// Treating field `k` (Treatment).
    Field(usize),
}

/// A field placed on the farm: its `FieldSpec` (rows along its own x) with
/// its corner and the direction of its rows in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedField {
    /// The field's corner (its own (0, 0)) in the world, m.
    pub corner: (f64, f64),
    /// The direction of its rows (its own x axis) in the world, rad.
    pub heading_rad: f64,
    /// The field.
    pub field: FieldSpec,
    /// How many of its passes the robot treats, from the first.
    pub passes: usize,
}

impl PlacedField {
    /// A point of the field's own frame in the world.
    #[must_use]
    pub fn to_world(&self, (x, y): (f64, f64)) -> (f64, f64) {
        let (s, c) = self.heading_rad.sin_cos();
        (self.corner.0 + x * c - y * s, self.corner.1 + x * s + y * c)
    }

    /// A pose of the field's own frame in the world.
    ///
    /// # Errors
    /// `LIB-FINITE` for a non-finite placement.
    pub fn pose_to_world(&self, pose: &Pose2<World>) -> Result<Pose2<World>, Precondition> {
        let (x, y) = self.to_world((pose.position.x(), pose.position.y()));
        Pose2::new(x, y, pose.heading.get() + self.heading_rad)
    }

    /// The field's outline in the world.
    #[must_use]
    pub fn outline(&self) -> Boundary {
        let f = &self.field;
        Boundary {
            vertices: [
                (0.0, 0.0),
                (f.length_m, 0.0),
                (f.length_m, f.width_m),
                (0.0, f.width_m),
            ]
            .into_iter()
            .map(|p| self.to_world(p))
            .collect(),
        }
    }

    /// The goals of its treatment: the first `passes` passes and the U-turns
    /// between them, in the world (the first pass's start is reached by the
    /// road).
    ///
    /// # Errors
    /// `LIB-FINITE` for a non-finite placement.
    pub fn treatment(&self) -> Result<Vec<Goal>, Precondition> {
        let keep = (2 * self.passes).saturating_sub(1);
        self.field
            .goals()
            .into_iter()
            .take(keep)
            .map(|g| {
                Ok(Goal {
                    pose: self.pose_to_world(&g.pose)?,
                    radius_m: g.radius_m,
                })
            })
            .collect()
    }

    /// The start of its first pass, in the world.
    ///
    /// # Errors
    /// `LIB-FINITE` for a non-finite placement.
    pub fn entry(&self) -> Result<Pose2<World>, Precondition> {
        self.pose_to_world(&self.field.first_line_start()?)
    }
}

/// A road: the waypoints between where the robot stands and where the road
/// ends (both left out), m.
#[derive(Debug, Clone, PartialEq)]
pub struct Road {
    /// The waypoints in order.
    pub waypoints: Vec<(f64, f64)>,
}

/// A farm: the yard, the fields in the order they are treated, and the
/// roads (one more than the fields: the last leads back to the yard).
#[derive(Debug, Clone, PartialEq)]
pub struct Farm {
    /// Where the robot starts and ends.
    pub yard: Pose2<World>,
    /// The fields.
    pub fields: Vec<PlacedField>,
    /// The roads.
    pub roads: Vec<Road>,
    /// The turning radius of GoToGoal at the roads' bends, m.
    pub corner_radius_m: f64,
    /// The roads' width, m.
    pub road_width_m: f64,
}

/// A farm mission's goal: where, with which radius, and in which task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RouteGoal {
    /// The goal.
    pub goal: Goal,
    /// The task it belongs to.
    pub task: Task,
}

/// Where a road starts and where it ends.
pub type RoadEnds = (Pose2<World>, Pose2<World>);

/// The direction from `a` to `b`, rad.
fn direction(a: (f64, f64), b: (f64, f64)) -> f64 {
    (b.1 - a.1).atan2(b.0 - a.0)
}

/// `a` wrapped into (−π, π].
fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(2.0 * PI);
    if r > PI {
        r - 2.0 * PI
    } else {
        r
    }
}

impl Farm {
    /// The built-in farm of `welaser-farm`: the yard west of two 20 m ×
    /// 20 m fields 20 m apart along a farm road; three passes in each.
    ///
    /// # Errors
    /// Never for these constants (`LIB-FINITE` otherwise).
    pub fn builtin() -> Result<Self, Precondition> {
        let field = FieldSpec::lines();
        Ok(Self {
            yard: Pose2::new(0.0, -3.0, 0.0)?,
            fields: vec![
                PlacedField {
                    corner: (20.0, 4.0),
                    heading_rad: 0.0,
                    field: field.clone(),
                    passes: 3,
                },
                PlacedField {
                    corner: (60.0, 4.0),
                    heading_rad: 0.0,
                    field,
                    passes: 3,
                },
            ],
            roads: vec![
                Road {
                    waypoints: vec![(14.0, -3.0), (14.0, 5.0)],
                },
                Road {
                    waypoints: vec![(50.0, 8.0), (57.0, 5.0)],
                },
                Road {
                    waypoints: vec![(84.0, 8.0), (84.0, -3.0)],
                },
            ],
            corner_radius_m: 2.0,
            road_width_m: 4.0,
        })
    }

    /// Every crop plant of every field, in the world.
    pub fn plants(&self, rng: &mut SimRng) -> Vec<Plant> {
        let mut out = Vec::new();
        for f in &self.fields {
            for mut p in f.field.plants(rng) {
                let (x, y) = f.to_world((p.position.x(), p.position.y()));
                if let Ok(position) = fieldguide::Point2::new(x, y) {
                    p.position = position;
                    out.push(p);
                }
            }
        }
        out
    }

    /// The road `k` as a polyline from `from` to `to`, waypoints between.
    fn polyline(&self, k: usize, from: (f64, f64), to: (f64, f64)) -> Vec<(f64, f64)> {
        let mut points = vec![from];
        if let Some(road) = self.roads.get(k) {
            points.extend(road.waypoints.iter().copied());
        }
        points.push(to);
        points
    }

    /// The poses each road runs between: (start pose, end pose), in order.
    ///
    /// # Errors
    /// `LIB-FINITE` for a non-finite placement.
    pub fn road_ends(&self) -> Result<Vec<RoadEnds>, Precondition> {
        let mut out = Vec::new();
        let mut at = self.yard;
        for f in &self.fields {
            let entry = f.entry()?;
            out.push((at, entry));
            at = f.treatment()?.last().map_or(entry, |g| g.pose);
        }
        // Back in the yard, facing along the road's last stretch.
        let last_from = self
            .roads
            .last()
            .and_then(|r| r.waypoints.last().copied())
            .unwrap_or((at.position.x(), at.position.y()));
        let (x, y) = (self.yard.position.x(), self.yard.position.y());
        out.push((at, Pose2::new(x, y, direction(last_from, (x, y)))?));
        Ok(out)
    }

    /// Each road as a polyline in the world, from its start to its end.
    ///
    /// # Errors
    /// As [`Farm::road_ends`].
    pub fn road_polylines(&self) -> Result<Vec<Vec<(f64, f64)>>, Precondition> {
        Ok(self
            .road_ends()?
            .iter()
            .enumerate()
            .map(|(k, (a, b))| {
                let xy = |p: &Pose2<World>| (p.position.x(), p.position.y());
                self.polyline(k, xy(a), xy(b))
            })
            .collect())
    }

    /// The mission's goals: each road's, then each field's treatment, the
    /// last road's to the yard.
    //= spec/emmi2024.md#em-sim-farm-roads-joining-fields
    //# A farm mission MUST drive from the yard along each road to its field,
    //# treat the field's passes, and return to the yard along the last road,
    //# keeping the tracks on the roads and meeting the closed-loop figures.
    ///
    /// # Errors
    /// `EM-SIM-FARM` for a road whose bends do not fit its corner radius or
    /// that meets its end more than 45° off the end's heading; `LIB-FINITE`
    /// for a non-finite placement.
    pub fn route(&self) -> Result<Vec<RouteGoal>, Precondition> {
        if self.roads.len() != self.fields.len() + 1 {
            return Err(Precondition::new(
                "EM-SIM-FARM",
                "a farm needs one road more than fields (the last leads back to the yard)",
            ));
        }
        let mut out = Vec::new();
        for (k, (points, (start, end))) in self
            .road_polylines()?
            .iter()
            .zip(self.road_ends()?)
            .enumerate()
        {
            for goal in self.road_goals(points, &start, &end)? {
                out.push(RouteGoal {
                    goal,
                    task: Task::Road(k),
                });
            }
            if let Some(f) = self.fields.get(k) {
                for goal in f.treatment()? {
                    out.push(RouteGoal {
                        goal,
                        task: Task::Field(k),
                    });
                }
            }
        }
        Ok(out)
    }

    /// The goals along one road's polyline from `start` to `end`.
    //= spec/emmi2024.md#em-sim-farm-roads-joining-fields
    //# A waypoint where the road bends by less than 45° MUST be a
    //# LineFollowing goal on the road; at a bend of 45° or more the robot MUST
    //# follow the road to 0.5 m before the bend's first tangent point and turn
    //# by GoToGoal to its second, the tangent points at the corner radius.
    fn road_goals(
        &self,
        points: &[(f64, f64)],
        start: &Pose2<World>,
        end: &Pose2<World>,
    ) -> Result<Vec<Goal>, Precondition> {
        let r = self.corner_radius_m;
        let refuse = |why: &'static str| Err(Precondition::new("EM-SIM-FARM", why));
        let legs: Vec<f64> = points.windows(2).map(|w| direction(w[0], w[1])).collect();
        let length = |i: usize| {
            points
                .get(i)
                .zip(points.get(i + 1))
                .map_or(0.0, |(a, b)| (b.0 - a.0).hypot(b.1 - a.1))
        };
        // The first and last legs meet the start's and the end's heading.
        let (Some(&first), Some(&last)) = (legs.first(), legs.last()) else {
            return refuse("a road needs a start and an end");
        };
        if wrap(first - start.heading.get()).abs() >= FRAC_PI_4
            || wrap(end.heading.get() - last).abs() >= FRAC_PI_4
        {
            return refuse(
                "a road must leave its start and meet its end within 45 degrees of their headings",
            );
        }
        // The tangent length at each interior waypoint (0 for a gentle bend).
        let mut tangent = vec![0.0; points.len()];
        for i in 1..points.len().saturating_sub(1) {
            let bend =
                wrap(legs.get(i).copied().unwrap_or(0.0) - legs.get(i - 1).copied().unwrap_or(0.0));
            if bend.abs() >= FRAC_PI_4 {
                if bend.abs() > 0.8 * PI {
                    return refuse("a road bends by more than 144 degrees at a waypoint");
                }
                if let Some(t) = tangent.get_mut(i) {
                    *t = r * (bend.abs() / 2.0).tan();
                }
            }
        }
        for i in 0..legs.len() {
            let room =
                tangent.get(i).copied().unwrap_or(0.0) + tangent.get(i + 1).copied().unwrap_or(0.0);
            if length(i) < room + 2.0 * BEND_SLACK_M {
                return refuse("a stretch of road is too short for the bends at its ends");
            }
        }
        let mut goals = Vec::new();
        for i in 1..points.len() {
            let (Some(&p), Some(&incoming)) = (points.get(i), legs.get(i - 1)) else {
                continue;
            };
            let t = tangent.get(i).copied().unwrap_or(0.0);
            if i + 1 == points.len() {
                goals.push(Goal {
                    pose: Pose2::new(p.0, p.1, end.heading.get())?,
                    radius_m: r,
                });
            } else if t > 0.0 {
                let outgoing = legs.get(i).copied().unwrap_or(incoming);
                let (si, ci) = incoming.sin_cos();
                let (so, co) = outgoing.sin_cos();
                let back = t + BEND_SLACK_M;
                goals.push(Goal {
                    pose: Pose2::new(p.0 - back * ci, p.1 - back * si, incoming)?,
                    radius_m: r,
                });
                goals.push(Goal {
                    pose: Pose2::new(p.0 + t * co, p.1 + t * so, outgoing)?,
                    radius_m: r,
                });
            } else {
                goals.push(Goal {
                    pose: Pose2::new(p.0, p.1, incoming)?,
                    radius_m: r,
                });
            }
        }
        Ok(goals)
    }

    /// The first road whose centreline runs between a field's headlands
    /// across its crop rows: `(road, field)`.
    #[must_use]
    pub fn road_across_rows(&self) -> Option<(usize, usize)> {
        let polylines = self.road_polylines().ok()?;
        for (k, line) in polylines.iter().enumerate() {
            for w in line.windows(2) {
                let (a, b) = (w[0], w[1]);
                let steps = ((b.0 - a.0).hypot(b.1 - a.1) / 0.1).ceil().clamp(1.0, 1e5);
                for i in 0..=(steps as u32) {
                    let u = f64::from(i) / steps;
                    let p = (a.0 + u * (b.0 - a.0), a.1 + u * (b.1 - a.1));
                    for (j, f) in self.fields.iter().enumerate() {
                        let (s, c) = f.heading_rad.sin_cos();
                        let (dx, dy) = (p.0 - f.corner.0, p.1 - f.corner.1);
                        let (x, y) = (dx * c + dy * s, -dx * s + dy * c);
                        let g = &f.field;
                        if x > g.headland_m
                            && x < g.length_m - g.headland_m
                            && y > 0.0
                            && y < g.width_m
                        {
                            return Some((k, j));
                        }
                    }
                }
            }
        }
        None
    }

    /// The distance of `point` to a road's `polyline`, m (the road-keeping
    /// check).
    #[must_use]
    pub fn distance_to_road(polyline: &[(f64, f64)], point: (f64, f64)) -> f64 {
        polyline
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0], w[1]);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let l2 = dx * dx + dy * dy;
                let u = if l2 > 0.0 {
                    (((point.0 - a.0) * dx + (point.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (point.0 - a.0 - u * dx).hypot(point.1 - a.1 - u * dy)
            })
            .fold(f64::INFINITY, f64::min)
    }
}
