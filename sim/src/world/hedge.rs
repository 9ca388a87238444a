//! Hedges, walls and post rows.
