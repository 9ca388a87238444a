//! Re-planning round an obstacle with one intermediate waypoint (Emmi 2024,
//! section 3.2, Fig. 8; `spec/emmi2024.md`, EM-OBST-DETOUR, EM-OBST-CLEAR
//! and EM-OBST-NO-DETOUR).
//!
//! A circle is passed beside it, a segment round one of its ends; the two
//! Dubins legs start → waypoint → goal (GoToGoal, section 3.1) must keep the
//! footprint clear of every obstacle by the safety margin, as a check
//! stepping no farther than the clearance allows shows (EM-OBST-CLEAR).

use heapless::Vec;

use super::areas::{above, at_least, ObstacleConfig, Shape, Xy};
use super::corridor::Corridor;
use super::Obstacle;
use crate::error::Precondition;
use crate::geometry::frame::{Pose2, World};
use crate::geometry::units::Meters;
use crate::planning::dubins::{shortest, DubinsPath};

/// Extra lateral offsets of the waypoint tried in turn, in units of half the
/// width plus the margin (EM-OBST-DETOUR).
const EXTRA: [f64; 7] = [0.0, 0.125, 0.25, 0.375, 0.5, 1.0, 2.0];

/// Most samples of one clearance check; a path needing more is not clear
/// (EM-OBST-CLEAR).
const MAX_SAMPLES: usize = 200_000;

/// Most samples of the search for the path's heading beside the obstacle.
const HEADING_SAMPLES: u32 = 1024;

/// The outcome of re-planning round one obstacle (EM-OBST-DETOUR,
/// EM-OBST-NO-DETOUR).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DetourPlan {
    /// Go through this waypoint, then on to the goal.
    Waypoint(Pose2<World>),
    /// The footprint at the goal is not clear of the obstacles: no detour
    /// reaches it.
    GoalBlocked,
    /// No waypoint on either side gives two clear legs.
    NoClearSide,
    /// Waypoints give two clear legs, but none keeps the footprint inside
    /// the road's corridor by the margin (EM-OBST-ROAD).
    NoDetourOnRoad,
}

/// `(x, y, θ)` of a pose.
fn raw(p: &Pose2<World>) -> (f64, f64, f64) {
    (p.position.x(), p.position.y(), p.heading.get())
}

/// The obstacles of the robot frame at `seen_from`, as seen in the world,
/// and the road's corridor when one bounds the footprint.
struct Scene<'o> {
    obstacles: &'o [Obstacle],
    cos: f64,
    sin: f64,
    origin: Xy,
    corridor: Option<&'o Corridor>,
}

impl<'o> Scene<'o> {
    fn new(obstacles: &'o [Obstacle], seen_from: &Pose2<World>) -> Self {
        let (x, y, h) = raw(seen_from);
        Self {
            obstacles,
            cos: libm::cos(h),
            sin: libm::sin(h),
            origin: (x, y),
            corridor: None,
        }
    }

    /// The same scene, the footprint also bounded by `corridor`.
    const fn within(self, corridor: Option<&'o Corridor>) -> Self {
        Self { corridor, ..self }
    }

    /// An obstacle in the world frame.
    fn world(&self, o: &Obstacle) -> Shape {
        Shape::of(o).moved(self.cos, self.sin, self.origin)
    }

    /// The least distance between the footprint at `pose` and an obstacle,
    /// or the corridor's edge plus the margin, metres (infinite without
    /// obstacles and corridor, NaN only from non-finite input).
    //= spec/emmi2024.md#em-obst-road-detours-inside-the-road
    //# With a corridor, the clearance of EM-OBST-CLEAR MUST be the lesser of
    //# the clearance to the obstacles and the room of the pose plus the
    //# margin, so that a clear path keeps the whole footprint inside the
    //# corridor.
    fn clearance(&self, pose: (f64, f64, f64), config: &ObstacleConfig) -> f64 {
        let body = config.footprint().body_box();
        let room = self.corridor.map_or(f64::INFINITY, |c| {
            c.room(pose, &config.footprint()) + config.margin().get()
        });
        self.obstacles
            .iter()
            .map(|o| {
                self.world(o)
                    .into_body(pose.0, pose.1, pose.2)
                    .box_distance(&body)
            })
            .fold(room, |m, d| {
                if m.is_nan() || !(d.is_nan() || d < m) {
                    m
                } else {
                    d
                }
            })
    }
}

/// How fast a clearance can shrink per metre of arc length: 1 + ρ/r with ρ
/// the footprint's radius.
fn shrink_rate(config: &ObstacleConfig) -> f64 {
    1.0 + config.footprint().radius() / config.radius().get().get()
}

/// Whether the footprint moving along `path` from arc length 0 to
/// `min(upto, L)` keeps at least the margin from every obstacle.
///
/// The clearance c(s) shrinks by at most k = 1 + ρ/r per metre (a footprint
/// point at distance ρ from the origin moves at most (1 + ρ/r) ds), so after
/// a sample of clearance c the next one is taken (c − margin)/k further on,
/// and each sample must show c ≥ margin + k · step.
//= spec/emmi2024.md#em-obst-clear-clear-legs
//# A path MUST be clear only when, at samples s_0 = 0 < s_1 < … ending at
//# the checked length, the footprint's clearance c_i to every obstacle
//# satisfies c_i ≥ margin + k · step and s_{i+1} − s_i ≤ (c_i − margin) / k,
//# with k = 1 + ρ/r, ρ the footprint's largest distance from its origin and
//# r the turning radius.
fn clear_along(path: &DubinsPath, upto: f64, scene: &Scene<'_>, config: &ObstacleConfig) -> bool {
    let k = shrink_rate(config);
    let margin = config.margin().get();
    let need = margin + k * config.step();
    let end = path.length().get().min(upto);
    let mut s = 0.0_f64;
    for _ in 0..MAX_SAMPLES {
        let Ok(pose) = path.pose_at(Meters(s)) else {
            return false;
        };
        let c = scene.clearance(raw(&pose), config);
        if !at_least(c, need) {
            return false;
        }
        if s >= end {
            return true;
        }
        s = (s + (c - margin) / k).min(end);
    }
    false
}

/// Whether the obstacle `target` of the robot frame at `pose` lies on the
/// path from `pose` to `goal` within `upto` metres of arc length: the
/// footprint moving along it would come nearer than the margin.
pub(super) fn on_path(
    target: &Obstacle,
    pose: &Pose2<World>,
    nominal: &DubinsPath,
    upto: f64,
    config: &ObstacleConfig,
) -> bool {
    let scene = Scene::new(core::slice::from_ref(target), pose);
    !clear_along(nominal, upto, &scene, config)
}

/// The heading of the planned path where it passes nearest to `point`.
fn heading_beside(nominal: &DubinsPath, from: Xy, point: Xy, r: f64) -> Option<f64> {
    let span = nominal
        .length()
        .get()
        .min(libm::hypot(point.0 - from.0, point.1 - from.1) + 2.0 * core::f64::consts::TAU * r);
    let ds = span / f64::from(HEADING_SAMPLES);
    (0..=HEADING_SAMPLES)
        .filter_map(|i| {
            let p = nominal.pose_at(Meters(ds * f64::from(i))).ok()?;
            let (x, y, h) = raw(&p);
            Some((libm::hypot(x - point.0, y - point.1), h))
        })
        .fold(None, |best: Option<(f64, f64)>, (d, h)| match best {
            Some((bd, _)) if !above(bd, d) => best,
            _ => Some((d, h)),
        })
        .map(|(_, h)| h)
}

/// The intermediate waypoint going round `target`, one of `obstacles` (all
/// in the robot frame at `pose`), on the way to `goal` (Emmi 2024, section
/// 3.2, Fig. 8). Waypoints whose second leg meets another obstacle only
/// beyond `horizon` metres are taken when no other is clear: that obstacle
/// is met again, in the warning area, later on.
///
/// # Errors
/// The errors of [`shortest`] for the planned path `pose` → `goal`
/// (`EM-DUBINS-RANGE` beyond 1e7 m).
pub fn detour(
    target: &Obstacle,
    obstacles: &[Obstacle],
    pose: &Pose2<World>,
    goal: &Pose2<World>,
    horizon: Meters,
    config: &ObstacleConfig,
) -> Result<DetourPlan, Precondition> {
    detour_within(target, obstacles, pose, goal, horizon, None, config)
}

/// [`detour`] on a road whose `corridor` (when known) bounds the footprint
/// along both legs by the margin (EM-OBST-ROAD); without one, the paper's
/// behaviour.
///
/// # Errors
/// As [`detour`].
//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//# The waypoint of a circle of radius ρ MUST lie beside its centre, at
//# ρ + width/2 + margin + k · step (plus, in turn, 0, 0.125, 0.25, 0.375,
//# 0.5, 1 and 2 times width/2 + margin) to the left or the right of the
//# planned path's heading
//# where the path passes nearest to the centre, with that heading.
//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//# The waypoint of a segment MUST lie beyond one of its ends, along the
//# segment, or beside one of its ends, to the left or the right of the
//# planned path's heading, at width/2 + margin + k · step (plus the same
//# extra offsets) from that end, with the planned path's heading where it
//# passes nearest to the segment's midpoint.
//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//# Among the candidate waypoints whose two legs are clear, the one of least
//# total length start → waypoint → goal MUST be chosen.
//= spec/emmi2024.md#em-obst-detour-the-intermediate-waypoint
//# When no candidate has two clear legs, the candidate of least total length
//# whose first leg is clear and whose second leg is clear of the obstacle
//# gone round, and of every obstacle over its first `horizon` metres, MUST
//# be chosen.
pub fn detour_within(
    target: &Obstacle,
    obstacles: &[Obstacle],
    pose: &Pose2<World>,
    goal: &Pose2<World>,
    horizon: Meters,
    corridor: Option<&Corridor>,
    config: &ObstacleConfig,
) -> Result<DetourPlan, Precondition> {
    let radius = config.radius();
    let nominal = shortest(pose, goal, radius)?;
    let scene = Scene::new(obstacles, pose);
    let k = shrink_rate(config);
    let margin = config.margin().get();
    //= spec/emmi2024.md#em-obst-no-detour-no-way-round
    //# When the footprint at the goal is less than margin + k · step from an
    //# obstacle, re-planning MUST report that the goal is blocked.
    if !at_least(
        scene.clearance(raw(goal), config),
        margin + k * config.step(),
    ) {
        return Ok(DetourPlan::GoalBlocked);
    }
    let half = 0.5 * config.footprint().width().get();
    let base = half + margin + k * config.step();
    let unit = half + margin;
    let from = (pose.position.x(), pose.position.y());
    let r = radius.get().get();
    let shape = scene.world(target);
    let reference = match shape {
        Shape::Circle(c, _) => c,
        Shape::Segment(a, b) => (0.5 * (a.0 + b.0), 0.5 * (a.1 + b.1)),
    };
    let Some(heading) = heading_beside(&nominal, from, reference, r) else {
        return Ok(DetourPlan::NoClearSide);
    };
    let left = (-libm::sin(heading), libm::cos(heading));
    let right = (-left.0, -left.1);
    // Each anchor and the direction its waypoints lie in; the obstacle's
    // own extent beyond the anchor.
    let (anchors, count, own): ([(Xy, Xy); 6], usize, f64) = match shape {
        Shape::Circle(c, rho) => (
            [
                (c, left),
                (c, right),
                (c, left),
                (c, left),
                (c, left),
                (c, left),
            ],
            2,
            rho,
        ),
        Shape::Segment(a, b) => {
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len = libm::hypot(dx, dy);
            if len > 0.0 {
                let u = (dx / len, dy / len);
                let back = (-u.0, -u.1);
                (
                    [
                        (b, u),
                        (a, back),
                        (b, left),
                        (b, right),
                        (a, left),
                        (a, right),
                    ],
                    6,
                    0.0,
                )
            } else {
                (
                    [
                        (a, left),
                        (a, right),
                        (a, left),
                        (a, left),
                        (a, left),
                        (a, left),
                    ],
                    2,
                    0.0,
                )
            }
        }
    };
    let mut candidates: Vec<Candidate, 42> = Vec::new();
    for (anchor, dir) in anchors.into_iter().take(count) {
        for extra in EXTRA {
            let offset = own + base + extra * unit;
            let Ok(waypoint) = Pose2::new(
                anchor.0 + offset * dir.0,
                anchor.1 + offset * dir.1,
                heading,
            ) else {
                continue;
            };
            let (Ok(first), Ok(second)) = (
                shortest(pose, &waypoint, radius),
                shortest(&waypoint, goal, radius),
            ) else {
                continue;
            };
            let total = first.length().get() + second.length().get();
            let _ = candidates.push((total, candidates.len(), waypoint, first, second));
        }
    }
    candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let alone = Scene::new(core::slice::from_ref(target), pose);
    let on_road = |corridor| {
        choose(
            &candidates,
            &Scene::new(obstacles, pose).within(corridor),
            &Scene::new(core::slice::from_ref(target), pose).within(corridor),
            horizon,
            config,
        )
    };
    if let Some(waypoint) = on_road(corridor) {
        return Ok(DetourPlan::Waypoint(waypoint));
    }
    //= spec/emmi2024.md#em-obst-road-detours-inside-the-road
    //# When no candidate qualifies inside the corridor but one would without
    //# it, re-planning MUST report that no detour fits on the road.
    if corridor.is_some() && choose(&candidates, &scene, &alone, horizon, config).is_some() {
        return Ok(DetourPlan::NoDetourOnRoad);
    }
    //= spec/emmi2024.md#em-obst-no-detour-no-way-round
    //# When no candidate waypoint qualifies, re-planning MUST report that no
    //# side is clear.
    Ok(DetourPlan::NoClearSide)
}

/// A candidate `(total, order, waypoint, first leg, second leg)`.
type Candidate = (f64, usize, Pose2<World>, DubinsPath, DubinsPath);

/// The first of the sorted `candidates` whose two legs are clear in
/// `scene`, or else the first whose first leg is and whose second leg is
/// clear over `horizon` and of the obstacle gone round (`alone`).
fn choose(
    candidates: &[Candidate],
    scene: &Scene<'_>,
    alone: &Scene<'_>,
    horizon: Meters,
    config: &ObstacleConfig,
) -> Option<Pose2<World>> {
    for strict in [true, false] {
        for (_, _, waypoint, first, second) in candidates {
            let second_clear = if strict {
                clear_along(second, f64::INFINITY, scene, config)
            } else {
                clear_along(second, horizon.get(), scene, config)
                    && clear_along(second, f64::INFINITY, alone, config)
            };
            if second_clear && clear_along(first, f64::INFINITY, scene, config) {
                return Some(*waypoint);
            }
        }
    }
    None
}
