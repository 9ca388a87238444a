//! Worlds: terrain, hedges and walls, crop plots.
//!
//! A [`World`] is everything around the vehicle that the simulator measures
//! against: the ground's sideslip, the plants the LiDAR sees and a wheel may
//! run over, the plots whose true centre lines score furrow pursuing, and the
//! hedges whose nominal faces score edge following.

pub mod crops;
pub mod curve;
pub mod grid;
pub mod hedge;
pub mod scene;
pub mod terrain;

use fieldguide::{Point2, World as WorldFrame};

use crops::{PlotPosition, PlotSpec};
use hedge::{HedgeSpec, Obstacles, OffsetLinePosition};
use terrain::Terrain;

/// What a plant is: a crop plant (must not be run over) or a grass tuft.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlantKind {
    /// A crop plant of a row: counted in `plants_crushed` when a wheel runs over it.
    Crop,
    /// Grass or a weed, in the headlands or between rows: seen by the LiDAR,
    /// never counted as crushed.
    Grass,
}

/// A plant modelled as a vertical cylinder standing on the ground z = 0: the
/// LiDAR hits its side wall or its top, a wheel crushes it when the wheel's
/// contact patch overlaps its footprint disc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plant {
    /// Centre of the stem, world frame, m.
    pub position: Point2<WorldFrame>,
    /// Radius of the cylinder (the footprint disc), m (> 0).
    pub radius: f64,
    /// Height of the cylinder's top, m (> 0).
    pub height: f64,
    /// Crop or grass.
    pub kind: PlantKind,
}

/// The simulated world of one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct World {
    /// Ground sideslip.
    pub terrain: Terrain,
    /// Every plant: the crop plots' plants, then the grass.
    pub plants: Vec<Plant>,
    /// The crop plots the plants were drawn from (their true centre lines are
    /// the ground truth of furrow pursuing), in the order the robot meets them.
    pub plots: Vec<Plot>,
    /// The hedges (their nominal faces are the ground truth of edge
    /// following), in the order the robot meets them.
    pub hedges: Vec<Hedge>,
    /// What a LiDAR can hit besides the ground and the plants: the hedges'
    /// generated outlines.
    pub obstacles: Obstacles,
    /// The obstacles' height above the ground, m (`[world] obstacle_height_m`).
    pub obstacle_height: f64,
}

/// A named hedge.
#[derive(Debug, Clone, PartialEq)]
pub struct Hedge {
    /// Name, for the summary.
    pub name: String,
    /// Layout and nominal faces.
    pub spec: HedgeSpec,
}

/// A named crop plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// Name, for plots and the summary.
    pub name: String,
    /// Layout and true centre line.
    pub spec: PlotSpec,
}

impl World {
    /// The plot beside which the world point `(x, y)` lies, with its
    /// position relative to that plot's true centre line: the first plot
    /// whose projection ([`PlotSpec::project`]) falls within its length and
    /// lies within `reach` m of its centre line.
    #[must_use]
    pub fn plot_at(&self, x: f64, y: f64, reach: f64) -> Option<(usize, PlotPosition)> {
        self.plots.iter().enumerate().find_map(|(i, p)| {
            p.spec
                .project(x, y)
                .filter(|q| q.lateral.abs() <= reach)
                .map(|q| (i, q))
        })
    }

    /// The hedge beside which a robot at world pose `(x, y, heading)`
    /// keeping `offset` metres from it lies, with its position relative to
    /// that hedge's offset line ([`HedgeSpec::offset_line_position`]): the
    /// first hedge present abeam of it within `reach` m of the offset line.
    #[must_use]
    pub fn hedge_at(
        &self,
        (x, y, heading): (f64, f64, f64),
        offset: f64,
        reach: f64,
    ) -> Option<(usize, OffsetLinePosition)> {
        self.hedges.iter().enumerate().find_map(|(i, h)| {
            h.spec
                .offset_line_position(x, y, heading, offset)
                .filter(|q| q.lateral.abs() <= reach)
                .map(|q| (i, q))
        })
    }

    /// How many of the plants are crop plants.
    #[must_use]
    pub fn crop_count(&self) -> usize {
        self.plants
            .iter()
            .filter(|p| p.kind == PlantKind::Crop)
            .count()
    }
}
