//! Edge detection on a horizontal 2D LiDAR (Pierre 2022, section 2.2, Algorithm 1, eqs. 8-11, 21).
