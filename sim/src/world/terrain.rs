//! Terrain: sideslip patches.
