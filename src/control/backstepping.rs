//! Backstepping path tracking with sideslip compensation (Pierre 2022, eqs. 2-7).
