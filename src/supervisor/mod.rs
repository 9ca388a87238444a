//! Supervision: the switching between behaviours (Pierre 2022, section 3),
//! a whole crop driven on LiDAR alone (Guyonneau 2022, sections 3-4), and
//! missions of tasks (Emmi 2024, sections 3.1-3.2).

pub mod crop_navigation;
pub mod mission;
pub mod switching;
