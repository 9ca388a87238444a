//! The vineyard: straight rows of vines along x from x = 0 to the row
//! length, headlands of bare ground before and after them, on ground that
//! slopes across and along the rows and has bumps.
//!
//! Row 0, the leftmost, runs along y = 0 (the true row centre line the
//! robot follows, straddling it); the others lie `spacing` apart to its
//! right. A vine is a trunk (a thin cylinder) and its canopy: overlapping
//! cylinders every [`SEGMENT_M`] along the row, as wide as the season's
//! canopy, each present with the season's density, so that winter wood has
//! gaps. Posts stand in the row every `post_gap`; whole vines may be missing,
//! and so may the first vines of every row.

use rand::Rng;

use fieldguide::Point2;

use crate::world::terrain::{Ground, Undulation};
use crate::world::{Plant, PlantKind};

/// The distance between two canopy cylinders along a row, m.
pub const SEGMENT_M: f64 = 0.1;
/// A trunk's radius, m.
pub const TRUNK_RADIUS_M: f64 = 0.05;
/// A post's radius, m.
pub const POST_RADIUS_M: f64 = 0.05;

/// The season: what the canopy looks like (section 3 of Iberraken 2022).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Season {
    /// Dense foliage, about 0.4-0.6 m wide.
    Summer,
    /// Sparse wood, about 0.1-0.2 m wide, with gaps.
    Winter,
}

impl Season {
    /// Its name in files and reports.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Summer => "summer",
            Self::Winter => "winter",
        }
    }
}

/// A vineyard's shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineyardSpec {
    /// The season.
    pub season: Season,
    /// Rows.
    pub rows: usize,
    /// Distance between rows, m.
    pub spacing: f64,
    /// Row length, m.
    pub length: f64,
    /// Distance between vines along a row, m.
    pub vine_gap: f64,
    /// Canopy width, m.
    pub canopy_width: f64,
    /// Canopy top above the ground, m.
    pub canopy_height: f64,
    /// Probability that a canopy cylinder is there (1 for a dense canopy).
    pub density: f64,
    /// Probability that a whole vine is missing.
    pub missing: f64,
    /// The first vines of every row, all missing (young replants at the
    /// entry: the row starts with posts and bare wire).
    pub missing_at_entry: usize,
    /// Distance between posts along a row, m.
    pub post_gap: f64,
    /// Post top above the ground, m.
    pub post_height: f64,
    /// Ground slope (dz/dx along the rows, dz/dy across).
    pub slope: [f64; 2],
    /// Bumps: amplitude, wavelength, m, and direction of the crests' normal, rad.
    pub bumps: Option<(f64, f64, f64)>,
}

impl VineyardSpec {
    /// The season's vineyard: 3 rows 2.0 m apart, 40 m long, a vine every
    /// 1.0 m, canopies 0.45 m wide and dense in summer, 0.15 m wide and 70 %
    /// present in winter, 1.0 m high; 3 % of the vines missing; a post every
    /// 6 m, 1.3 m high; a 3 % cross slope, a 1 % along-row slope and bumps
    /// 4 cm high every 3 m.
    #[must_use]
    pub const fn paper(season: Season) -> Self {
        let (canopy_width, density) = match season {
            Season::Summer => (0.45, 1.0),
            Season::Winter => (0.15, 0.7),
        };
        Self {
            season,
            rows: 3,
            spacing: 2.0,
            length: 40.0,
            vine_gap: 1.0,
            canopy_width,
            canopy_height: 1.0,
            density,
            missing: 0.03,
            missing_at_entry: 0,
            post_gap: 6.0,
            post_height: 1.3,
            slope: [0.01, 0.03],
            bumps: Some((0.04, 3.0, 0.6)),
        }
    }

    /// The centre line of row `i`, y, m.
    #[must_use]
    pub fn row_y(&self, i: usize) -> f64 {
        -(i as f64) * self.spacing
    }

    /// The ground.
    #[must_use]
    pub fn ground(&self) -> Ground {
        Ground {
            slope: self.slope,
            undulation: self
                .bumps
                .map(|(amplitude, wavelength, heading)| Undulation {
                    amplitude,
                    wavelength,
                    heading,
                }),
        }
    }

    /// The vineyard's vines and posts, drawn from `rng`: `(canopies and
    /// posts as the LiDAR sees them, trunks and posts as the wheels meet them)`.
    pub fn generate(&self, rng: &mut impl Rng) -> (Vec<Plant>, Vec<Plant>) {
        let mut seen = Vec::new();
        let mut solid = Vec::new();
        let stand = |x: f64, y: f64, radius: f64, height: f64| {
            Point2::new(x, y).ok().map(|position| Plant {
                position,
                radius,
                height,
                kind: PlantKind::Crop,
            })
        };
        let vines = (self.length / self.vine_gap).floor() as usize;
        for row in 0..self.rows {
            let y = self.row_y(row);
            for v in 0..=vines {
                let x = v as f64 * self.vine_gap;
                if v < self.missing_at_entry || rng.random::<f64>() < self.missing {
                    continue;
                }
                solid.extend(stand(x, y, TRUNK_RADIUS_M, self.canopy_height));
                seen.extend(stand(x, y, TRUNK_RADIUS_M, self.canopy_height));
                // The canopy along the wire, half a vine gap each side.
                let n = (self.vine_gap / SEGMENT_M).round() as usize;
                for k in 0..n {
                    let cx = x - 0.5 * self.vine_gap + (k as f64 + 0.5) * SEGMENT_M;
                    if (0.0..=self.length).contains(&cx) && rng.random::<f64>() < self.density {
                        let top = self.canopy_height * (0.95 + 0.1 * rng.random::<f64>());
                        seen.extend(stand(cx, y, 0.5 * self.canopy_width, top));
                    }
                }
            }
            let posts = (self.length / self.post_gap).floor() as usize;
            for p in 0..=posts {
                let x = p as f64 * self.post_gap + 0.5 * self.vine_gap;
                if x <= self.length {
                    solid.extend(stand(x, y, POST_RADIUS_M, self.post_height));
                    seen.extend(stand(x, y, POST_RADIUS_M, self.post_height));
                }
            }
        }
        (seen, solid)
    }
}
