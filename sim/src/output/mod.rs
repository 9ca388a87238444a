//! Output: CSV traces, JSON summaries, SVG plots, written to `out/<scenario>/`.

pub mod csv;
pub mod json;
pub mod plots;
pub mod svg;

use std::path::{Path, PathBuf};

use crate::error::SimError;
use crate::metrics::Summary;
use crate::runner::RunOutput;
use crate::scenario::Setup;
use crate::sweep::Sweep;

/// The files of one run.
pub const FILES: [&str; 4] = [
    "trace.csv",
    "summary.json",
    "trajectory.svg",
    "lateral_error.svg",
];

/// The file of a seed sweep (`fieldguide sweep`).
pub const SWEEP_FILE: &str = "sweep.csv";

/// The extra figure of a world with plants.
pub const ROWS_FILE: &str = "rows.svg";

/// Writes `trace.csv`, `summary.json`, `trajectory.svg` and `lateral_error.svg`
/// (and `rows.svg` in a world with plants) into `out_root/<scenario name>/`,
/// creating it; returns that folder.
pub fn write_run(
    out_root: &Path,
    setup: &Setup,
    output: &RunOutput,
    summary: &Summary,
) -> Result<PathBuf, SimError> {
    let dir = out_root.join(&setup.name);
    write_run_to(&dir, setup, output, summary)?;
    Ok(dir)
}

/// [`write_run`]'s files written into `dir` itself, creating it.
pub fn write_run_to(
    dir: &Path,
    setup: &Setup,
    output: &RunOutput,
    summary: &Summary,
) -> Result<(), SimError> {
    let dir = dir.to_path_buf();
    std::fs::create_dir_all(&dir).map_err(|source| SimError::Write {
        file: dir.clone(),
        source,
    })?;
    let names: Vec<String> = setup
        .world
        .terrain
        .patches
        .iter()
        .map(|p| p.name.clone())
        .collect();
    let plot_names: Vec<String> = setup.world.plots.iter().map(|p| p.name.clone()).collect();
    let hedge_names: Vec<String> = setup.world.hedges.iter().map(|h| h.name.clone()).collect();
    let json = json::summary_json(summary).map_err(|e| SimError::Write {
        file: dir.join("summary.json"),
        source: std::io::Error::other(e),
    })?;
    let contents = [
        csv::trace_csv(&output.trace, &names, &plot_names, &hedge_names),
        json,
        plots::trajectory_svg_marked(setup, &output.trace, &output.crushed),
        plots::lateral_error_svg(setup, &output.trace),
    ];
    for (name, text) in FILES.iter().zip(contents) {
        let file = dir.join(name);
        std::fs::write(&file, text).map_err(|source| SimError::Write { file, source })?;
    }
    if !setup.world.plants.is_empty() {
        let file = dir.join(ROWS_FILE);
        std::fs::write(
            &file,
            plots::rows_svg_marked(setup, &output.trace, &output.crushed),
        )
        .map_err(|source| SimError::Write { file, source })?;
    }
    Ok(())
}

/// Writes `sweep.csv` (one line per seed, [`crate::sweep::sweep_csv`]) into
/// `out_root/<scenario>/`, creating it; returns the file.
pub fn write_sweep<R: crate::sweep::Row>(
    out_root: &Path,
    sweep: &Sweep<R>,
) -> Result<PathBuf, SimError> {
    let dir = out_root.join(&sweep.scenario);
    std::fs::create_dir_all(&dir).map_err(|source| SimError::Write {
        file: dir.clone(),
        source,
    })?;
    let file = dir.join(SWEEP_FILE);
    std::fs::write(&file, crate::sweep::sweep_csv(&sweep.rows)).map_err(|source| {
        SimError::Write {
            file: file.clone(),
            source,
        }
    })?;
    Ok(file)
}

/// Writes each `(name, text)` into `dir`, creating it.
pub fn write_files(dir: &Path, files: &[(&str, String)]) -> Result<(), SimError> {
    std::fs::create_dir_all(dir).map_err(|source| SimError::Write {
        file: dir.to_path_buf(),
        source,
    })?;
    for (name, text) in files {
        let file = dir.join(name);
        std::fs::write(&file, text).map_err(|source| SimError::Write { file, source })?;
    }
    Ok(())
}
