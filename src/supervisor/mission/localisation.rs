//! The localisation choice (Emmi 2024, section 3.1; EM-LOC-CHOICE).

use crate::geometry::frame::{Pose2, Robot, World};
use crate::geometry::units::Meters;

use super::LocalisationStatus;

/// The pose of one tick and where it comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fix {
    /// The valid GNSS fix.
    Gnss(Pose2<World>),
    /// The last fix moved by odometry; `driven` metres since that fix.
    Odometry {
        /// The dead-reckoned pose.
        pose: Pose2<World>,
        /// The distance driven since the last fix.
        driven: Meters,
    },
    /// No usable pose.
    Lost,
}

impl Fix {
    /// The pose, when there is one.
    #[must_use]
    pub const fn pose(&self) -> Option<Pose2<World>> {
        match self {
            Self::Gnss(pose) | Self::Odometry { pose, .. } => Some(*pose),
            Self::Lost => None,
        }
    }

    /// The abstract status the machine reads.
    #[must_use]
    pub const fn status(&self) -> LocalisationStatus {
        match self {
            Self::Gnss(_) => LocalisationStatus::Gnss,
            Self::Odometry { .. } => LocalisationStatus::Odometry,
            Self::Lost => LocalisationStatus::Lost,
        }
    }
}

/// GNSS while it is valid, odometry from the last valid fix for at most a
/// distance, then Lost (EM-LOC-CHOICE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Localiser {
    limit: f64,
    last: Option<Pose2<World>>,
    driven: f64,
}

impl Localiser {
    /// A localiser allowing odometry for `distance` metres since a fix
    /// (negative distances count as 0); Lost until the first fix.
    #[must_use]
    pub fn new(distance: Meters) -> Self {
        Self {
            limit: distance.get().max(0.0),
            last: None,
            driven: 0.0,
        }
    }

    /// One tick: the GNSS fix if it is valid, and the odometry increment (the
    /// robot's motion since the previous tick, in the robot frame of the
    /// previous tick).
    //= spec/emmi2024.md#em-loc-choice-gnss-or-odometry
    //# The pose MUST be the GNSS fix while it is valid; without a valid fix, the
    //# last valid fix moved by the odometry increments since, as long as the
    //# distance driven since that fix is at most the configured odometry
    //# distance; beyond it, or before any valid fix, the localisation MUST be
    //# Lost.
    pub fn update(&mut self, gnss: Option<Pose2<World>>, increment: &Pose2<Robot>) -> Fix {
        if let Some(pose) = gnss {
            self.last = Some(pose);
            self.driven = 0.0;
            return Fix::Gnss(pose);
        }
        let step = libm::hypot(increment.position.x(), increment.position.y());
        // `driven` only grows (an overflow to +inf stays beyond the limit).
        self.driven += step;
        let moved = self
            .last
            .and_then(|last| last.body_to_frame::<Robot>().apply_pose(*increment).ok());
        self.last = moved;
        match (moved, Meters::new(self.driven)) {
            (Some(pose), Ok(driven)) if self.driven <= self.limit => Fix::Odometry { pose, driven },
            _ => {
                // Beyond the limit the dead-reckoned pose is never used again.
                self.last = None;
                Fix::Lost
            }
        }
    }
}
