//! Simulated 2D LiDARs, of either kind, mounted in any number on the robot:
//! each scans the one world ([`crate::world::scene::Scene`]) on its own
//! scan ticks and its scans are routed to one behaviour's detector.

pub mod horizontal;
pub mod inclined;

use fieldguide::guidance::BehaviourId;

use horizontal::HorizontalLidar;
use inclined::InclinedLidar;

/// A LiDAR of either kind.
#[derive(Debug, Clone, Copy)]
pub enum Mounted {
    /// Pitched towards the ground (furrow pursuing, Pierre 2022 section 2.3).
    Inclined(InclinedLidar),
    /// Level (edge following, Pierre 2022 section 2.2).
    Horizontal(HorizontalLidar),
}

/// A LiDAR on the robot: the sensor, the behaviour its scans go to and how
/// often it scans.
#[derive(Debug, Clone, Copy)]
pub struct MountedLidar {
    /// The sensor and its mount.
    pub sensor: Mounted,
    /// The behaviour whose detector reads its scans.
    pub route: BehaviourId,
    /// A scan every this many control ticks.
    pub scan_every: u64,
}
