//! Reference paths built from waypoints and the Frénet projection of a pose.
