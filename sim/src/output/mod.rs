//! Output: CSV traces, JSON summaries, SVG plots.

pub mod csv;
pub mod json;
pub mod svg;
