//! Horizontal 2D LiDAR ray-cast against hedges, walls and posts.
