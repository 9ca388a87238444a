//! Detectors: one module per detector, each turning a LiDAR scan into a line or
//! parabola in the robot frame and a quality verdict.

pub mod edge;
pub mod furrow;
