//! Validates `[run]` (duration and integration) and `[metrics]` (the bounds
//! of convergence and success).

use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::schema::ScenarioFile;

/// How long a run lasts and how finely the plant is integrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunLimits {
    /// Longest simulated time, seconds.
    pub duration_s: f64,
    /// Stop when the robot's projection reaches the end of the path.
    pub stop_at_path_end: bool,
    /// Plant sub-steps per control period.
    pub substeps: u32,
}

/// Bounds of the summary's convergence and success (`sim/scenarios/README.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricsSpec {
    /// Convergence band on |y|, metres.
    pub band_m: f64,
    /// Largest `converged_after_m` of a successful run, metres.
    pub converge_within_m: f64,
    /// Largest in-plot mean |error to the true centre line| of a successful run, metres.
    pub in_plot_mean_abs_m: Option<f64>,
    /// Largest in-plot max |error to the true centre line| of a successful run, metres.
    pub in_plot_max_abs_m: Option<f64>,
    /// Band on |error to a hedge's true offset line| that counts as converged, metres.
    pub along_hedge_band_m: f64,
    /// Largest mean |error to the true offset line| along the hedges after
    /// convergence of a successful run, metres.
    pub along_hedge_mean_abs_m: Option<f64>,
    /// Largest max |error to the true offset line| along the hedges after
    /// convergence of a successful run, metres.
    pub along_hedge_max_abs_m: Option<f64>,
    /// |curvature| of the path at the true projection from which a tick is
    /// in a turn, 1/m (the turn and straight/curve metrics).
    pub turn_curvature_per_m: f64,
}

/// Default |curvature| from which the path turns, 1/m (a radius of 10 m:
/// well above the curvature the recording noise leaves on a straight).
pub const TURN_CURVATURE_PER_M: f64 = 0.1;

/// The most control ticks of a run: the trace holds one record per tick
/// (about 3 h at 100 Hz).
pub const MAX_TICKS: f64 = 1_000_000.0;

/// The run limits of `[run]` at a control period of `period_s`.
pub(super) fn run(
    file: &ScenarioFile,
    period_s: f64,
    check: &Checker<'_>,
) -> Result<RunLimits, ScenarioError> {
    let duration_s = check.open_range("run.duration_s", file.run.duration_s, 0.0, 1e6)?;
    if duration_s / period_s > MAX_TICKS {
        return Err(check.error(
            "run.duration_s",
            &format!(
                "more than {MAX_TICKS} control ticks (run.duration_s / control.period_s = {:.0})",
                duration_s / period_s
            ),
        ));
    }
    check.count("run.substeps", file.run.substeps, 1, 1000)?;
    Ok(RunLimits {
        duration_s,
        stop_at_path_end: file.run.stop_at_path_end,
        substeps: file.run.substeps,
    })
}

/// The bounds of `[metrics]`.
pub(super) fn metrics(
    file: &ScenarioFile,
    check: &Checker<'_>,
) -> Result<MetricsSpec, ScenarioError> {
    let optional_positive = |field: &str, v: Option<f64>| -> Result<Option<f64>, ScenarioError> {
        v.map(|v| check.positive(field, v)).transpose()
    };
    Ok(MetricsSpec {
        band_m: check.positive("metrics.band_m", file.metrics.band_m)?,
        converge_within_m: check
            .positive("metrics.converge_within_m", file.metrics.converge_within_m)?,
        in_plot_mean_abs_m: optional_positive(
            "metrics.in_plot_mean_abs_m",
            file.metrics.in_plot_mean_abs_m,
        )?,
        in_plot_max_abs_m: optional_positive(
            "metrics.in_plot_max_abs_m",
            file.metrics.in_plot_max_abs_m,
        )?,
        along_hedge_band_m: check.positive(
            "metrics.along_hedge_band_m",
            file.metrics.along_hedge_band_m,
        )?,
        along_hedge_mean_abs_m: optional_positive(
            "metrics.along_hedge_mean_abs_m",
            file.metrics.along_hedge_mean_abs_m,
        )?,
        along_hedge_max_abs_m: optional_positive(
            "metrics.along_hedge_max_abs_m",
            file.metrics.along_hedge_max_abs_m,
        )?,
        turn_curvature_per_m: check.positive(
            "metrics.turn_curvature_per_m",
            file.metrics
                .turn_curvature_per_m
                .unwrap_or(TURN_CURVATURE_PER_M),
        )?,
    })
}
