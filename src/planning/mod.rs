//! Local planners of Emmi 2024 (section 3.1): GoToGoal, a Dubins path between
//! two poses ([`dubins`]), and LineFollowing, a straight line to a point ahead
//! ([`line_following`]); and which planner and which tracking controller run
//! ([`manager`]); `spec/emmi2024.md`, EM-DUBINS-*, EM-LINE, EM-PLANNER and
//! EM-TRACKER.
//!
//! Both planners give a [`crate::geometry::path::ReferencePath`] whose
//! vertices carry exact headings and curvatures, so the pipeline follows a
//! planned path like a recorded one.

pub mod dubins;
pub mod line_following;
pub mod manager;
