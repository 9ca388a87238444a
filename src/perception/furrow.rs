//! Furrow detection on an inclined 2D LiDAR (Pierre 2022, section 2.3, eqs. 12-20, 22).
