//! Crop plots: plants with position, radius and height.
