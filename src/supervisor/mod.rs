//! Supervision: the switching between behaviours (Pierre 2022, section 3),
//! and a whole crop driven on LiDAR alone (Guyonneau 2022, sections 3-4).

pub mod crop_navigation;
pub mod switching;
