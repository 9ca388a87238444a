//! The simulator's buffer capacities: the const generics of the core types it
//! instantiates (the guidance pipeline and its [`Reference`] path), which the
//! scenario setup also checks a file against, so that every scenario it
//! accepts fits them.

use fieldguide::geometry::path::ReferencePath;

/// Most waypoints a reference path may hold (409.6 m at the usual 0.1 m spacing).
pub const PATH_CAPACITY: usize = 4096;

/// The reference path type of the simulator.
pub type Reference = ReferencePath<PATH_CAPACITY>;

/// Most valid rays of a horizontal scan (a LiDAR with more rays is refused,
/// naming `horizontal_lidar.rays`).
pub const EDGE_RAYS: usize = 2048;

/// Most chain points (`edge.min_points` at most this).
pub const EDGE_CHAIN: usize = 256;

/// Most rays of the furrow detector's angular window (a scenario whose window
/// holds more is refused, naming `furrow.window_half_angle_deg`).
pub const FURROW_RAYS: usize = 1024;

/// Most selections the furrow detector keeps (`furrow.averaged_scans` at most this).
pub const FURROW_SCANS: usize = 64;
