//! The four simulated crops of Guyonneau 2022 (section 4.1.2), generated
//! from a seed: six straight rows of stems (five inter-rows) along the world
//! x axis, from x = 0 to the row length, row i at y = i · spacing.
//!
//! - crop 1: equal rows, plants regularly spaced, no weed;
//! - crop 2: plants randomly spaced along each row;
//! - crop 3: crop 2 with 50 weeds;
//! - crop 4: uneven rows (each plant off its row's line by up to 2 cm) with
//!   10 % of the plants missing, one 0.6 m hole per row and 100 weeds.
//!
//! The spacing differs between crops but is constant within one; weeds are
//! seen by the LiDARs and may be run over, crop plants may not.

use fieldguide::{Point2, World};
use rand::Rng;

use crate::world::{Plant, PlantKind};

/// Rows of every crop: six (five inter-rows).
pub const ROWS: usize = 6;
/// A stem's radius, m.
pub const STEM_RADIUS: f64 = 0.02;
/// A crop plant's height, m (above both LiDARs).
pub const PLANT_HEIGHT: f64 = 0.5;
/// A weed's height, m.
pub const WEED_HEIGHT: f64 = 0.3;

/// How one crop is laid out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CropSpec {
    /// The paper's crop number, 1 to 4 (0 for a field of the user's).
    pub crop: u8,
    /// Distance between neighbouring rows, m.
    pub spacing: f64,
    /// Length of the rows, m.
    pub length: f64,
    /// Nominal distance between consecutive plants of a row, m.
    pub plant_gap: f64,
    /// Each plant moves along its row by a uniform draw in ±this share of
    /// the gap.
    pub jitter_share: f64,
    /// Each plant moves across its row by a uniform draw in ±this, m.
    pub lateral_jitter: f64,
    /// Probability that a plant is missing.
    pub missing: f64,
    /// Length of the one hole of each row, m (0: none).
    pub hole: f64,
    /// Weeds, uniform over the field's rectangle.
    pub weeds: usize,
    /// Each row ends up to this much before the row length, uniformly (rows
    /// drilled to a headland that is not square), m.
    pub ragged_ends: f64,
}

impl CropSpec {
    /// Crop `n` of the paper (1 to 4), `None` for another number. Rows
    /// 1.2, 1.4, 1.0 and 1.3 m apart, 10 m long, plants every 0.2 m.
    #[must_use]
    pub fn paper(n: u8) -> Option<Self> {
        let crop1 = Self {
            crop: 1,
            spacing: 1.2,
            length: 10.0,
            plant_gap: 0.2,
            jitter_share: 0.0,
            lateral_jitter: 0.0,
            missing: 0.0,
            hole: 0.0,
            weeds: 0,
            ragged_ends: 0.0,
        };
        let crop2 = Self {
            crop: 2,
            spacing: 1.4,
            jitter_share: 0.4,
            ..crop1
        };
        match n {
            1 => Some(crop1),
            2 => Some(crop2),
            3 => Some(Self {
                crop: 3,
                spacing: 1.0,
                weeds: 50,
                ..crop2
            }),
            4 => Some(Self {
                crop: 4,
                spacing: 1.3,
                lateral_jitter: 0.02,
                missing: 0.1,
                hole: 0.6,
                weeds: 100,
                ..crop2
            }),
            _ => None,
        }
    }

    /// The lateral position of row `i`, m.
    #[must_use]
    pub fn row_y(&self, i: usize) -> f64 {
        i as f64 * self.spacing
    }

    /// The plants: the rows' crop plants row by row, then the weeds.
    pub fn generate(&self, rng: &mut impl Rng) -> Vec<Plant> {
        let mut plants = Vec::new();
        let count = (self.length / self.plant_gap).floor() as usize;
        for i in 0..ROWS {
            let end = self.length - symmetric(rng, self.ragged_ends).abs();
            let hole_start = if self.hole > 0.0 {
                rng.random_range(0.0..(self.length - self.hole).max(0.0))
            } else {
                f64::INFINITY
            };
            for k in 0..=count {
                let jitter = self.jitter_share * self.plant_gap;
                let x = k as f64 * self.plant_gap + symmetric(rng, jitter);
                let y = self.row_y(i) + symmetric(rng, self.lateral_jitter);
                let gone = rng.random::<f64>() < self.missing;
                let in_hole = (hole_start..hole_start + self.hole).contains(&x);
                if gone || in_hole || !(0.0..=end).contains(&x) {
                    continue;
                }
                if let Ok(position) = Point2::<World>::new(x, y) {
                    plants.push(Plant {
                        position,
                        radius: STEM_RADIUS,
                        height: PLANT_HEIGHT,
                        kind: PlantKind::Crop,
                    });
                }
            }
        }
        let (y0, y1) = (
            -0.5 * self.spacing,
            self.row_y(ROWS - 1) + 0.5 * self.spacing,
        );
        for _ in 0..self.weeds {
            let x = rng.random_range(0.0..self.length);
            let y = rng.random_range(y0..y1);
            let radius = rng.random_range(0.01..0.03);
            if let Ok(position) = Point2::<World>::new(x, y) {
                plants.push(Plant {
                    position,
                    radius,
                    height: WEED_HEIGHT,
                    kind: PlantKind::Grass,
                });
            }
        }
        plants
    }

    /// The signed distance of `y` from the middle of the inter-row it lies
    /// in (0-based, between rows i and i + 1), m, and that inter-row; `None`
    /// outside the outer rows.
    #[must_use]
    pub fn offset_from_middle(&self, y: f64) -> Option<(usize, f64)> {
        let i = (y / self.spacing).floor();
        if !(0.0..(ROWS - 1) as f64).contains(&i) {
            return None;
        }
        Some((i as usize, y - (i + 0.5) * self.spacing))
    }
}

/// A uniform draw in ±`half` (0 without a draw when `half` is 0).
fn symmetric(rng: &mut impl Rng, half: f64) -> f64 {
    if half > 0.0 {
        rng.random_range(-half..half)
    } else {
        0.0
    }
}
