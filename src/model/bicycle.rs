//! The extended kinematic bicycle model with sideslip (Pierre 2022, eq. 1).
