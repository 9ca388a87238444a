//! Inclined 2D LiDAR hitting ground and plants.
