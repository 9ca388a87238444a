//! Turns that stay inside the field (`spec/emmi2024.md`, EM-SIM-BOUNDARY):
//! GoToGoal with a field boundary polygon checks the robot's footprint at
//! every sampled pose of a Dubins path, takes the shortest word that stays
//! inside, or refuses with a named reason.

use fieldguide::planning::dubins::{path_with_word, DubinsPath, TurningRadius, Word};
use fieldguide::{Meters, Pose2, Precondition, World};

use super::RobotSpec;

/// The spacing of the poses checked along a path, m.
pub const CHECK_SPACING_M: f64 = 0.02;

/// A simple polygon, its vertices in order (either orientation), m.
#[derive(Debug, Clone, PartialEq)]
pub struct Boundary {
    /// The vertices `(x, y)`.
    pub vertices: Vec<(f64, f64)>,
}

impl Boundary {
    /// The rectangle [x0, x1] × [y0, y1].
    #[must_use]
    pub fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Self {
            vertices: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)],
        }
    }

    /// Whether `(x, y)` lies inside (crossing count of a ray towards +x).
    #[must_use]
    pub fn contains(&self, (x, y): (f64, f64)) -> bool {
        let n = self.vertices.len();
        let mut inside = false;
        for k in 0..n {
            let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
            if (a.1 > y) != (b.1 > y) {
                let cross = a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1);
                if x < cross {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Whether the segment from `p` to `q` crosses an edge.
    fn crosses(&self, p: (f64, f64), q: (f64, f64)) -> bool {
        let n = self.vertices.len();
        let side = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
            (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
        };
        (0..n).any(|k| {
            let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
            side(p, q, a) * side(p, q, b) < 0.0 && side(a, b, p) * side(a, b, q) < 0.0
        })
    }

    /// Whether the footprint of the robot at `pose` lies inside: its four
    /// corners inside and none of its sides crossing an edge.
    #[must_use]
    pub fn holds(&self, robot: &RobotSpec, pose: &Pose2<World>) -> bool {
        let c = footprint(robot, pose);
        c.iter().all(|&p| self.contains(p)) && (0..4).all(|k| !self.crosses(c[k], c[(k + 1) % 4]))
    }
}

/// The corners of the robot's footprint at `pose`: its tracks' length by
/// the width over the tracks' outer edges, centred on O.
#[must_use]
pub fn footprint(robot: &RobotSpec, pose: &Pose2<World>) -> [(f64, f64); 4] {
    let (s, c) = pose.heading.get().sin_cos();
    let (x, y) = (pose.position.x(), pose.position.y());
    let (hl, hw) = (
        robot.length_m / 2.0,
        (robot.track_m + robot.track_width_m) / 2.0,
    );
    let at = |f: f64, l: f64| (x + f * c - l * s, y + f * s + l * c);
    [at(hl, hw), at(-hl, hw), at(-hl, -hw), at(hl, -hw)]
}

/// Whether every pose of `path`, [`CHECK_SPACING_M`] apart and both ends,
/// keeps the footprint inside `boundary`.
#[must_use]
pub fn stays_inside(path: &DubinsPath, boundary: &Boundary, robot: &RobotSpec) -> bool {
    let l = path.length().get();
    let steps = (l / CHECK_SPACING_M).ceil().clamp(1.0, 1e6);
    let mut k = 0.0;
    while k <= steps {
        let s = (l * k / steps).min(l);
        let pose = Meters::new(s).and_then(|s| path.pose_at(s));
        match pose {
            Ok(p) if boundary.holds(robot, &p) => {}
            _ => return false,
        }
        k += 1.0;
    }
    true
}

/// GoToGoal inside `boundary`: the shortest of the six words from `start` to
/// `goal` with `radius` whose footprint stays inside at every sampled pose.
///
/// # Errors
/// `EM-SIM-BOUNDARY` when no word stays inside (no turn fits this headland
/// with this radius); `EM-DUBINS-RANGE` for coordinates beyond range.
//= spec/emmi2024.md#em-sim-boundary-turns-inside-the-field
//# With a field boundary, GoToGoal MUST check the robot's footprint at every
//# pose sampled at most 0.02 m apart along a word, and return the shortest word
//# whose footprint stays inside.
//= spec/emmi2024.md#em-sim-boundary-turns-inside-the-field
//# When no word stays inside, GoToGoal MUST refuse with the `EM-SIM-BOUNDARY`
//# error, naming the reason: no turn fits this headland with this radius.
pub fn shortest_inside(
    start: &Pose2<World>,
    goal: &Pose2<World>,
    radius: TurningRadius,
    boundary: &Boundary,
    robot: &RobotSpec,
) -> Result<DubinsPath, Precondition> {
    let mut words: Vec<DubinsPath> = Word::ALL
        .iter()
        .filter_map(|&w| path_with_word(start, goal, radius, w).ok())
        .collect();
    words.sort_by(|a, b| a.length().get().total_cmp(&b.length().get()));
    words
        .into_iter()
        .find(|p| stays_inside(p, boundary, robot))
        .ok_or(Precondition::new(
            "EM-SIM-BOUNDARY",
            "no turn fits this headland with this radius",
        ))
}
