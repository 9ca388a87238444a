//! The field of a guided mission (Emmi 2024, section 5: fields of about
//! 20 m × 20 m): crop rows along x between two headlands, and the passes
//! the robot drives, each straddling a crop row, joined by U-turns in the
//! headlands.
//!
//! Two layouts: `Rows`, crop rows every `row_spacing_m` and a pass every
//! `pass_rows` rows (row following with U-turns of one radius); `Turns`, a
//! pass 2 r apart for each radius r of the list in turn, a crop row under
//! each pass (U-turns of several radii).

use core::f64::consts::PI;

use fieldguide::{Point2, Pose2, Precondition, World};
use rand::Rng;

use crate::rng::SimRng;
use crate::world::{Plant, PlantKind};

/// How the passes are laid out.
#[derive(Debug, Clone, PartialEq)]
pub enum Layout {
    /// Crop rows every `row_spacing_m`, a pass over every `pass_rows`-th row.
    Rows {
        /// Distance between crop rows, m.
        row_spacing_m: f64,
        /// Rows from one pass to the next.
        pass_rows: u32,
    },
    /// Passes 2 r apart for each radius r of `FieldSpec::turn_radii_m` in
    /// turn, a crop row under each.
    Turns,
}

/// A goal of the mission: a pose, and the turning radius GoToGoal uses to
/// reach it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Goal {
    /// The goal pose.
    pub pose: Pose2<World>,
    /// The Dubins radius towards it, m.
    pub radius_m: f64,
}

/// A field and its passes.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldSpec {
    /// Along the rows, m.
    pub length_m: f64,
    /// Across the rows, m.
    pub width_m: f64,
    /// Depth of each headland, m (the rows run between them).
    pub headland_m: f64,
    /// Distance from the field's side to the first pass, m.
    pub side_m: f64,
    /// The layout of rows and passes.
    pub layout: Layout,
    /// Turning radii of the U-turns, used in turn, m.
    pub turn_radii_m: Vec<f64>,
    /// Distance between plants of a row, m.
    pub plant_gap_m: f64,
    /// Radius of a plant's stem disc, m.
    pub plant_radius_m: f64,
    /// How far each pass runs past the rows' ends, m (the tracks clear the
    /// rows before the robot turns).
    pub overhang_m: f64,
}

impl FieldSpec {
    /// The field of `welaser-lines`: 20 m × 20 m, headlands of 5 m, crop
    /// rows 0.75 m apart, a pass over every second row, U-turns of 0.75 m.
    #[must_use]
    pub fn lines() -> Self {
        Self {
            length_m: 20.0,
            width_m: 20.0,
            headland_m: 5.0,
            side_m: 1.0,
            layout: Layout::Rows {
                row_spacing_m: 0.75,
                pass_rows: 2,
            },
            turn_radii_m: vec![0.75],
            plant_gap_m: 0.15,
            plant_radius_m: 0.03,
            overhang_m: 1.0,
        }
    }

    /// The field of `welaser-turns`: passes for U-turns of 0.75, 1, 1.25,
    /// 1.5 and 2 m.
    #[must_use]
    pub fn turns() -> Self {
        Self {
            layout: Layout::Turns,
            turn_radii_m: vec![0.75, 1.0, 1.25, 1.5, 2.0],
            ..Self::lines()
        }
    }

    /// The radius of the `k`-th U-turn.
    #[must_use]
    pub fn radius(&self, k: usize) -> f64 {
        let n = self.turn_radii_m.len().max(1);
        self.turn_radii_m.get(k % n).copied().unwrap_or(1.0)
    }

    /// The passes' lateral positions y, m.
    #[must_use]
    pub fn passes(&self) -> Vec<f64> {
        let mut y = self.side_m;
        let mut out = Vec::new();
        let mut k = 0;
        while y <= self.width_m - self.side_m + 1e-9 && out.len() < 1000 {
            out.push(y);
            y += match self.layout {
                Layout::Rows {
                    row_spacing_m,
                    pass_rows,
                } => row_spacing_m * f64::from(pass_rows.max(1)),
                Layout::Turns => 2.0 * self.radius(k),
            };
            k += 1;
        }
        out
    }

    /// The crop rows' lateral positions y, m.
    #[must_use]
    pub fn rows(&self) -> Vec<f64> {
        match self.layout {
            Layout::Rows { row_spacing_m, .. } => {
                let mut out = Vec::new();
                let mut y = self.side_m;
                while y <= self.width_m - self.side_m + 1e-9 && out.len() < 10_000 {
                    out.push(y);
                    y += row_spacing_m;
                }
                out
            }
            Layout::Turns => self.passes(),
        }
    }

    /// The crop plants: each row from one headland to the other, a plant
    /// every `plant_gap_m` with ±20 % jitter along the row.
    pub fn plants(&self, rng: &mut SimRng) -> Vec<Plant> {
        let (x0, x1) = (self.headland_m, self.length_m - self.headland_m);
        let mut out = Vec::new();
        for y in self.rows() {
            let mut x = x0;
            while x <= x1 && out.len() < 1_000_000 {
                let jitter = rng.random_range(-0.2..=0.2) * self.plant_gap_m;
                let px = (x + jitter).clamp(x0, x1);
                if let Ok(position) = Point2::new(px, y) {
                    out.push(Plant {
                        position,
                        radius: self.plant_radius_m,
                        height: 0.3,
                        kind: PlantKind::Crop,
                    });
                }
                x += self.plant_gap_m;
            }
        }
        out
    }

    /// Where the passes start and end along x.
    fn pass_ends(&self) -> (f64, f64) {
        (
            self.headland_m - self.overhang_m,
            self.length_m - self.headland_m + self.overhang_m,
        )
    }

    /// The mission: for each pass, the start of the pass (reached by a
    /// U-turn, except the first) and its end.
    #[must_use]
    pub fn goals(&self) -> Vec<Goal> {
        let (a, b) = self.pass_ends();
        let mut out = Vec::new();
        for (k, y) in self.passes().into_iter().enumerate() {
            let forward = k % 2 == 0;
            let (from, to, heading) = if forward { (a, b, 0.0) } else { (b, a, PI) };
            let radius = self.radius(k.saturating_sub(1));
            if k > 0 {
                if let Ok(pose) = Pose2::new(from, y, heading) {
                    out.push(Goal {
                        pose,
                        radius_m: radius,
                    });
                }
            }
            if let Ok(pose) = Pose2::new(to, y, heading) {
                out.push(Goal {
                    pose,
                    radius_m: self.radius(k),
                });
            }
        }
        out
    }

    /// The start of the first pass.
    ///
    /// # Errors
    /// `LIB-FINITE` for a field of non-finite size.
    pub fn first_line_start(&self) -> Result<Pose2<World>, Precondition> {
        Pose2::new(self.pass_ends().0, self.side_m, 0.0)
    }

    /// The robot's start: the first pass's start, `offset` m to the left.
    ///
    /// # Errors
    /// As [`FieldSpec::first_line_start`].
    pub fn start(&self, offset: f64) -> Result<Pose2<World>, Precondition> {
        Pose2::new(self.pass_ends().0, self.side_m + offset, 0.0)
    }
}
