//! Metrics of a run, all against ground truth (the true pose projected on the
//! reference path), never against the robot's estimate.
//!
//! Definitions (also in `sim/scenarios/README.md`):
//! - `converged_after_m`: distance travelled until |y| stays below the band for
//!   the rest of the run (the distance of the first tick of the final run of
//!   ticks inside the band); 0 if |y| never left it; null if the last tick is
//!   outside it.
//! - `first_within_band_m`: distance travelled when |y| first enters the band.
//! - `success`: the run reached its end (path end, or the full duration when it
//!   does not stop at the path end) without a core error, and
//!   `converged_after_m` is at most `metrics.converge_within_m`: |y| came
//!   into the band within that distance and stayed in it to the end. In a
//!   world with crop plants, also no crop plant crushed; and when the
//!   scenario sets `metrics.in_plot_mean_abs_m` / `in_plot_max_abs_m`, the
//!   in-plot error within them.
//! - `in_plot_lateral_error_m`: |error of O to the true centre line of the
//!   plot's followed rows| over the ticks where O is inside a plot (its
//!   projection on the centre line within the plot's length); per plot in
//!   `plots`.
//! - `along_hedge_lateral_error_m`: |error of O to a hedge's true offset line
//!   (its nominal face moved by the desired distance)| over the ticks where
//!   the hedge is present abeam of O (not in a gap); per hedge in `hedges`.
//!   `along_hedge_converged_after_m` is the distance travelled at the first of
//!   these ticks within `metrics.along_hedge_band_m`, and
//!   `along_hedge_after_convergence_m` the statistics from there on. With
//!   `metrics.along_hedge_mean_abs_m` / `along_hedge_max_abs_m`, success also
//!   needs that convergence and those statistics within them.
//! - Turns: a tick is in a turn when the path's |curvature| at the true
//!   projection is at least `metrics.turn_curvature_per_m`. `turn_s` is the
//!   time in turns, `turn_mode_s` that time per mode, `turn_specialised_s`
//!   the part of it in a specialised behaviour (not path tracking, not Stop);
//!   `lateral_error_straight_m` and `lateral_error_curve_m` split the true
//!   |y| between the ticks off and in turns.
//! - `crushed_plants`: each crop plant crushed, located (x, y, plot, wheel,
//!   time of the first overlap).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::runner::{CrushedPlant, LineTruth, RunEnd, RunOutput, TickRecord};
use crate::scenario::Setup;
use fieldguide::guidance::Mode;

/// Statistics of |error| over ticks.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorStats {
    /// Mean of |e|.
    pub mean_abs: f64,
    /// Root mean square of e.
    pub rms: f64,
    /// Largest |e|.
    pub max_abs: f64,
    /// 95th percentile of |e| (nearest rank).
    pub p95_abs: f64,
}

/// Statistics of `values` (any sign); `None` when there are none.
#[must_use]
pub fn error_stats(values: impl IntoIterator<Item = f64>) -> Option<ErrorStats> {
    let mut abs: Vec<f64> = values.into_iter().map(f64::abs).collect();
    if abs.is_empty() {
        return None;
    }
    abs.sort_by(f64::total_cmp);
    let n = abs.len() as f64;
    let rank = ((0.95 * n).ceil() as usize).clamp(1, abs.len());
    Some(ErrorStats {
        mean_abs: abs.iter().sum::<f64>() / n,
        rms: (abs.iter().map(|a| a * a).sum::<f64>() / n).sqrt(),
        max_abs: abs.last().copied().unwrap_or(0.0),
        p95_abs: abs.get(rank - 1).copied().unwrap_or(0.0),
    })
}

/// Index of the first error of the final stretch with |y| < `band` (0 when
/// |y| never left the band); `None` if the last one is outside it or there are none.
#[must_use]
pub fn converged_index(errors: &[f64], band: f64) -> Option<usize> {
    match errors.iter().rposition(|y| outside_band(*y, band)) {
        None => (!errors.is_empty()).then_some(0),
        Some(last_out) => (last_out + 1 < errors.len()).then_some(last_out + 1),
    }
}

/// Whether `y` is outside the band: |y| ≥ `band`, or not a number.
fn outside_band(y: f64, band: f64) -> bool {
    y.abs() >= band || y.is_nan()
}

/// Index of the first error with |y| < `band`.
#[must_use]
pub fn first_within_index(errors: &[f64], band: f64) -> Option<usize> {
    errors.iter().position(|y| y.abs() < band)
}

/// The true lateral errors of a trace, metres.
#[must_use]
pub fn lateral_errors(trace: &[TickRecord]) -> Vec<f64> {
    trace.iter().map(|r| r.lateral_error_m).collect()
}

/// The summary written to `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Scenario name.
    pub scenario: String,
    /// Seed of the run.
    pub seed: u64,
    /// Distance travelled by O, metres.
    pub distance_m: f64,
    /// Simulated time, seconds.
    pub duration_s: f64,
    /// Length of the reference path, metres.
    pub path_length_m: f64,
    /// |y| statistics over the whole run, metres.
    pub lateral_error_m: ErrorStats,
    /// |y| statistics from `converged_after_m` on (null if never converged), metres.
    pub lateral_error_after_convergence_m: Option<ErrorStats>,
    /// |y| statistics while O is on a slip patch (null if never), metres.
    pub lateral_error_on_slip_m: Option<ErrorStats>,
    /// |θ̃| statistics over the whole run, degrees.
    pub angular_error_deg: ErrorStats,
    /// Convergence band, metres.
    pub band_m: f64,
    /// Distance until |y| stays below the band (null if never), metres.
    pub converged_after_m: Option<f64>,
    /// Distance when |y| first enters the band (null if never), metres.
    pub first_within_band_m: Option<f64>,
    /// Distance travelled in each mode, metres.
    pub mode_distance_m: BTreeMap<&'static str, f64>,
    /// Number of mode changes.
    pub mode_switches: usize,
    /// Simulated time without a GNSS fix, seconds.
    pub gnss_lost_s: f64,
    /// Simulated time the switching machine spent in Stop, seconds.
    pub stop_s: f64,
    /// Crop plants run over by a wheel (grass never counts).
    pub plants_crushed: usize,
    /// Crop plants in the world.
    pub crop_plants: usize,
    /// The crushed crop plants, located, in the order they were crushed.
    pub crushed_plants: Vec<CrushedPlant>,
    /// Simulated time with a float GNSS fix, seconds.
    pub gnss_float_s: f64,
    /// |curvature| from which a tick is in a turn, 1/m.
    pub turn_curvature_per_m: f64,
    /// Simulated time in turns, seconds.
    pub turn_s: f64,
    /// Simulated time in turns in each mode, seconds.
    pub turn_mode_s: BTreeMap<&'static str, f64>,
    /// Simulated time in turns in a specialised behaviour, seconds.
    pub turn_specialised_s: f64,
    /// |y| statistics over the ticks off turns (null if none), metres.
    pub lateral_error_straight_m: Option<ErrorStats>,
    /// |y| statistics over the ticks in turns (null if none), metres.
    pub lateral_error_curve_m: Option<ErrorStats>,
    /// |error to the true centre line of the followed rows| over the ticks
    /// with O inside a plot (null without plots), metres.
    pub in_plot_lateral_error_m: Option<ErrorStats>,
    /// The same per plot, with the distance driven inside it in each mode.
    pub plots: Vec<StretchSummary>,
    /// |error to a hedge's true offset line| over the ticks with a hedge
    /// present abeam of O (null without hedges or without `[edge]`), metres.
    pub along_hedge_lateral_error_m: Option<ErrorStats>,
    /// Distance travelled at the first along-hedge tick within
    /// `metrics.along_hedge_band_m` (null if none), metres.
    pub along_hedge_converged_after_m: Option<f64>,
    /// |error to the true offset line| over the along-hedge ticks from
    /// `along_hedge_converged_after_m` on (null if never converged), metres.
    pub along_hedge_after_convergence_m: Option<ErrorStats>,
    /// The along-hedge errors per hedge, with the distance driven beside it in each mode.
    pub hedges: Vec<StretchSummary>,
    /// How many scans the row detector graded with each verdict (empty without one).
    pub verdicts: BTreeMap<&'static str, usize>,
    /// Fraction of ticks whose steering command saturated.
    pub steering_saturated_fraction: f64,
    /// Whether the run reached its end (path end or full duration).
    pub reached_end: bool,
    /// The core error that stopped the run, if any.
    pub aborted: Option<String>,
    /// See the module documentation.
    pub success: bool,
    /// Why the run failed: each bound it broke, in words (empty on success).
    pub failures: Vec<String>,
}

/// The metrics of one crop plot or one hedge: the stretch where a
/// specialised behaviour has a true line to follow.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StretchSummary {
    /// The plot's or hedge's name.
    pub name: String,
    /// Length of its rows or of the hedge, metres.
    pub length_m: f64,
    /// |error to the true line| while O is inside the plot or beside the
    /// hedge (null if never), metres.
    pub lateral_error_m: Option<ErrorStats>,
    /// Distance driven with O inside the plot or beside the hedge, in each mode, metres.
    pub mode_distance_m: BTreeMap<&'static str, f64>,
}

/// The label of a verdict in summaries and traces.
#[must_use]
pub const fn verdict_label(v: fieldguide::Verdict) -> &'static str {
    match v {
        fieldguide::Verdict::Enter => "enter",
        fieldguide::Verdict::Hold => "hold",
        fieldguide::Verdict::Exit => "exit",
        fieldguide::Verdict::Absent => "absent",
    }
}

/// The true lateral errors to the plots' centre lines over the ticks inside
/// plot `plot` (every plot when `None`), metres.
#[must_use]
pub fn in_plot_errors(trace: &[TickRecord], plot: Option<usize>) -> Vec<f64> {
    truth_errors(trace, |r| r.plot, plot)
}

/// The true lateral errors to the hedges' offset lines over the ticks with
/// hedge `hedge` (every hedge when `None`) present abeam of O, metres.
#[must_use]
pub fn along_hedge_errors(trace: &[TickRecord], hedge: Option<usize>) -> Vec<f64> {
    truth_errors(trace, |r| r.hedge, hedge)
}

/// The errors of the truths `truth` picks, of item `index` (every item when `None`).
fn truth_errors(
    trace: &[TickRecord],
    truth: impl Fn(&TickRecord) -> Option<LineTruth>,
    index: Option<usize>,
) -> Vec<f64> {
    trace
        .iter()
        .filter_map(truth)
        .filter(|p| index.is_none_or(|i| p.index == i))
        .map(|p| p.lateral_error_m)
        .collect()
}

/// The along-hedge ticks from the first one within `band` of the true offset
/// line on: the distance travelled at that tick and the errors from there.
#[must_use]
pub fn along_hedge_after_convergence(trace: &[TickRecord], band: f64) -> Option<(f64, Vec<f64>)> {
    let along: Vec<(f64, f64)> = trace
        .iter()
        .filter_map(|r| r.hedge.map(|h| (r.distance_m, h.lateral_error_m)))
        .collect();
    let first = along.iter().position(|(_, e)| e.abs() < band)?;
    let distance = along.get(first).map(|(d, _)| *d)?;
    Some((
        distance,
        along.get(first..)?.iter().map(|(_, e)| *e).collect(),
    ))
}

/// The summaries of the stretches `truth` picks, one per `(name, length)` item.
fn stretch_summaries(
    trace: &[TickRecord],
    items: impl Iterator<Item = (String, f64)>,
    truth: impl Fn(&TickRecord) -> Option<LineTruth> + Copy,
) -> Vec<StretchSummary> {
    items
        .enumerate()
        .map(|(i, (name, length_m))| StretchSummary {
            name,
            length_m,
            lateral_error_m: error_stats(truth_errors(trace, truth, Some(i))),
            mode_distance_m: mode_distances(trace, |r| truth(r).is_some_and(|q| q.index == i)),
        })
        .collect()
}

/// Distance driven in each mode over the consecutive pairs of ticks whose
/// first tick satisfies `keep`.
fn mode_distances(
    trace: &[TickRecord],
    keep: impl Fn(&TickRecord) -> bool,
) -> BTreeMap<&'static str, f64> {
    let mut out = BTreeMap::new();
    for pair in trace.windows(2) {
        let [a, b] = pair else { continue };
        if keep(a) {
            *out.entry(a.label()).or_insert(0.0) += b.distance_m - a.distance_m;
        }
    }
    out
}

/// The turn metrics of a trace (module documentation, "Turns").
#[derive(Debug, Clone, PartialEq)]
pub struct Turns {
    /// |curvature| from which a tick is in a turn, 1/m.
    pub threshold: f64,
    /// Time in turns, seconds.
    pub time_s: f64,
    /// Time in turns per mode label, seconds.
    pub mode_s: BTreeMap<&'static str, f64>,
    /// Time in turns in a specialised behaviour, seconds.
    pub specialised_s: f64,
    /// |y| off turns.
    pub straight: Option<ErrorStats>,
    /// |y| in turns.
    pub curve: Option<ErrorStats>,
}

/// Whether `record` is in a turn: |curvature| at least `threshold`.
#[must_use]
pub fn in_turn(record: &TickRecord, threshold: f64) -> bool {
    record.curvature.abs() >= threshold
}

/// The turn metrics of `trace` at curvature `threshold`, each tick counting
/// `period_s`.
#[must_use]
pub fn turns(trace: &[TickRecord], threshold: f64, period_s: f64) -> Turns {
    let mut mode_s = BTreeMap::new();
    let mut specialised_s = 0.0;
    for r in trace.iter().filter(|r| in_turn(r, threshold)) {
        *mode_s.entry(r.label()).or_insert(0.0) += period_s;
        if matches!(r.mode(), Mode::Behaviour(_)) {
            specialised_s += period_s;
        }
    }
    let split = |turning: bool| {
        error_stats(
            trace
                .iter()
                .filter(|r| in_turn(r, threshold) == turning)
                .map(|r| r.lateral_error_m),
        )
    };
    Turns {
        threshold,
        time_s: mode_s.values().sum(),
        mode_s,
        specialised_s,
        straight: split(false),
        curve: split(true),
    }
}

/// The summary of `output`, a run of `setup`.
#[must_use]
pub fn summarize(setup: &Setup, output: &RunOutput) -> Summary {
    let trace = &output.trace;
    let band = setup.metrics.band_m;
    let distance_at = |i: usize| trace.get(i).map(|r| r.distance_m);
    let ys = lateral_errors(trace);
    let first = first_within_index(&ys, band);
    let converged = converged_index(&ys, band);
    let after = converged
        .and_then(|i| ys.get(i..))
        .and_then(|t| error_stats(t.iter().copied()));
    let mut mode_distance = mode_distances(trace, |_| true);
    let switches = trace
        .windows(2)
        .filter(|w| matches!(w, [a, b] if a.mode() != b.mode()))
        .count();
    if let Some(last) = trace.last() {
        mode_distance.entry(last.label()).or_insert(0.0);
    }
    let in_plot = error_stats(in_plot_errors(trace, None));
    let plots = stretch_summaries(
        trace,
        setup
            .world
            .plots
            .iter()
            .map(|p| (p.name.clone(), p.spec.length)),
        |r| r.plot,
    );
    let along_hedge = error_stats(along_hedge_errors(trace, None));
    let hedge_convergence = along_hedge_after_convergence(trace, setup.metrics.along_hedge_band_m);
    let hedge_converged_m = hedge_convergence.as_ref().map(|(d, _)| *d);
    let hedge_after = hedge_convergence.and_then(|(_, e)| error_stats(e));
    let hedges = stretch_summaries(
        trace,
        setup
            .world
            .hedges
            .iter()
            .map(|h| (h.name.clone(), h.spec.length)),
        |r| r.hedge,
    );
    let mut verdicts = BTreeMap::new();
    for d in trace.iter().filter_map(|r| r.command.detector) {
        if d.scanned {
            *verdicts.entry(verdict_label(d.verdict)).or_insert(0) += 1;
        }
    }
    let crop_plants = setup.world.crop_count();
    let turn = turns(
        trace,
        setup.metrics.turn_curvature_per_m,
        setup.control.period_s,
    );
    let reached_end = match output.end {
        RunEnd::PathEnd => true,
        RunEnd::Duration => !setup.run.stop_at_path_end,
        RunEnd::Aborted(_) => false,
    };
    let first_m = first.and_then(distance_at);
    let converged_m = converged.and_then(distance_at);
    let failures = failures(&Verdicts {
        setup,
        end: &output.end,
        reached_end,
        converged_m,
        band,
        crushed: output.plants_crushed,
        in_plot,
        hedge_after,
    });
    let success = failures.is_empty();
    let zero = ErrorStats {
        mean_abs: 0.0,
        rms: 0.0,
        max_abs: 0.0,
        p95_abs: 0.0,
    };
    Summary {
        scenario: setup.name.clone(),
        seed: setup.seed,
        distance_m: trace.last().map_or(0.0, |r| r.distance_m),
        duration_s: trace.last().map_or(0.0, |r| r.t_s),
        path_length_m: setup.path.length().get(),
        lateral_error_m: error_stats(trace.iter().map(|r| r.lateral_error_m)).unwrap_or(zero),
        lateral_error_after_convergence_m: after,
        lateral_error_on_slip_m: error_stats(
            trace
                .iter()
                .filter(|r| r.patch.is_some())
                .map(|r| r.lateral_error_m),
        ),
        angular_error_deg: error_stats(trace.iter().map(|r| r.angular_error_rad.to_degrees()))
            .unwrap_or(zero),
        band_m: band,
        converged_after_m: converged_m,
        first_within_band_m: first_m,
        mode_distance_m: mode_distance,
        mode_switches: switches,
        gnss_lost_s: trace.iter().filter(|r| r.readings.gnss.is_none()).count() as f64
            * setup.control.period_s,
        stop_s: trace
            .iter()
            .filter(|r| r.command.switching_mode == Mode::Stop)
            .count() as f64
            * setup.control.period_s,
        plants_crushed: output.plants_crushed,
        crop_plants,
        crushed_plants: output.crushed.clone(),
        gnss_float_s: trace.iter().filter(|r| r.gnss_float).count() as f64 * setup.control.period_s,
        turn_curvature_per_m: turn.threshold,
        turn_s: turn.time_s,
        turn_mode_s: turn.mode_s,
        turn_specialised_s: turn.specialised_s,
        lateral_error_straight_m: turn.straight,
        lateral_error_curve_m: turn.curve,
        in_plot_lateral_error_m: in_plot,
        plots,
        along_hedge_lateral_error_m: along_hedge,
        along_hedge_converged_after_m: hedge_converged_m,
        along_hedge_after_convergence_m: hedge_after,
        hedges,
        verdicts,
        steering_saturated_fraction: if trace.is_empty() {
            0.0
        } else {
            trace.iter().filter(|r| r.command.saturated).count() as f64 / trace.len() as f64
        },
        reached_end,
        aborted: match &output.end {
            RunEnd::Aborted(why) => Some(why.clone()),
            _ => None,
        },
        success,
        failures,
    }
}

/// What `success` is judged from.
struct Verdicts<'a> {
    setup: &'a Setup,
    end: &'a RunEnd,
    reached_end: bool,
    converged_m: Option<f64>,
    band: f64,
    crushed: usize,
    in_plot: Option<ErrorStats>,
    hedge_after: Option<ErrorStats>,
}

/// The bounds a run broke, each in words naming the scenario field that set
/// it (module documentation, `success`).
fn failures(v: &Verdicts<'_>) -> Vec<String> {
    let mut broken = Vec::new();
    if !v.reached_end {
        broken.push(match v.end {
            RunEnd::Aborted(why) => format!("stopped early: {why}"),
            RunEnd::PathEnd | RunEnd::Duration => "did not reach the path's end".to_owned(),
        });
    }
    let within = v.setup.metrics.converge_within_m;
    match v.converged_m {
        None => broken.push(format!(
            "|y| outside the {} m band (metrics.band_m) at the end",
            v.band
        )),
        Some(d) if d > within => broken.push(format!(
            "converged after {d:.2} m > metrics.converge_within_m = {within} m"
        )),
        Some(_) => {}
    }
    if v.crushed > 0 {
        broken.push(format!("{} crop plants crushed", v.crushed));
    }
    let m = &v.setup.metrics;
    let bounds = [
        (
            "in_plot_mean_abs_m",
            m.in_plot_mean_abs_m,
            v.in_plot.map(|e| e.mean_abs),
            "in-plot mean |error|",
        ),
        (
            "in_plot_max_abs_m",
            m.in_plot_max_abs_m,
            v.in_plot.map(|e| e.max_abs),
            "in-plot max |error|",
        ),
        (
            "along_hedge_mean_abs_m",
            m.along_hedge_mean_abs_m,
            v.hedge_after.map(|e| e.mean_abs),
            "along-hedge mean |error| after convergence",
        ),
        (
            "along_hedge_max_abs_m",
            m.along_hedge_max_abs_m,
            v.hedge_after.map(|e| e.max_abs),
            "along-hedge max |error| after convergence",
        ),
    ];
    for (field, bound, value, what) in bounds {
        match (bound, value) {
            (Some(b), Some(x)) if x > b => {
                broken.push(format!("{what} {x:.4} m > metrics.{field} = {b} m"));
            }
            (Some(_), None) => broken.push(format!("no {what} (metrics.{field} is set)")),
            _ => {}
        }
    }
    broken
}

/// A convergence requirement on a run: from some distance travelled at most
/// `within_m` on, |y| stays below the band up to `within_m`, and afterwards
/// stays below it on the given abscissa intervals (for example the straights;
/// curves may leave it briefly).
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergenceCheck {
    /// Band on |y|, metres.
    pub band_m: f64,
    /// Distance travelled by which |y| must have settled in the band, metres.
    pub within_m: f64,
    /// Abscissa intervals `(s_start, s_end)` where |y| must stay in the band after `within_m`.
    pub hold_on: Vec<(f64, f64)>,
}

/// Why a run fails a [`ConvergenceCheck`].
#[derive(Debug, Clone, PartialEq)]
pub enum ConvergenceFailure {
    /// The run did not reach the end of the path (a core error, or the duration ran out).
    Incomplete(String),
    /// |y| was never below the band.
    NeverWithinBand {
        /// Smallest |y| seen, metres.
        min_abs_m: f64,
    },
    /// |y| settled in the band only after `within_m`.
    TooLate {
        /// Distance from which |y| stayed in the band up to `within_m`, metres.
        distance_m: f64,
    },
    /// After `within_m`, |y| left the band on a hold interval.
    LeftBand {
        /// Abscissa where it happened, metres.
        s_m: f64,
        /// Lateral error there, metres.
        y_m: f64,
    },
}

/// Checks `output` against `check`; on success returns the distance from
/// which |y| stayed in the band (up to `within_m`, and on the hold intervals
/// after). The band is checked first, then that the run reached the path's end.
pub fn check_convergence(
    output: &RunOutput,
    check: &ConvergenceCheck,
) -> Result<f64, ConvergenceFailure> {
    let trace = &output.trace;
    if first_within_index(&lateral_errors(trace), check.band_m).is_none() {
        let min_abs_m = trace
            .iter()
            .map(|r| r.lateral_error_m.abs())
            .fold(f64::INFINITY, f64::min);
        return Err(ConvergenceFailure::NeverWithinBand { min_abs_m });
    }
    let held = |r: &TickRecord| {
        check
            .hold_on
            .iter()
            .any(|(a, b)| r.s_m >= *a && r.s_m <= *b)
    };
    let outside = |r: &TickRecord| outside_band(r.lateral_error_m, check.band_m);
    // Ticks that break the requirement if they come after the settling point.
    let mut violations = trace
        .iter()
        .enumerate()
        .filter(|(_, r)| outside(r) && (r.distance_m <= check.within_m || held(r)));
    if let Some((_, r)) = violations
        .clone()
        .find(|(_, r)| r.distance_m > check.within_m)
    {
        return Err(ConvergenceFailure::LeftBand {
            s_m: r.s_m,
            y_m: r.lateral_error_m,
        });
    }
    let settled_m = match violations.next_back() {
        None => trace.first().map_or(0.0, |r| r.distance_m),
        Some((i, _)) => trace.get(i + 1).map_or(f64::INFINITY, |r| r.distance_m),
    };
    if settled_m > check.within_m {
        return Err(ConvergenceFailure::TooLate {
            distance_m: settled_m,
        });
    }
    // Checked last, so that a diverging run reports how it diverged.
    if output.end != RunEnd::PathEnd {
        return Err(ConvergenceFailure::Incomplete(format!("{:?}", output.end)));
    }
    Ok(settled_m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_by_hand() {
        let s = error_stats([3.0, -4.0, 0.0, 1.0]).unwrap();
        assert!((s.mean_abs - 2.0).abs() < 1e-12);
        assert!((s.rms - (26.0_f64 / 4.0).sqrt()).abs() < 1e-12);
        assert!((s.max_abs - 4.0).abs() < 1e-12);
        // Nearest rank: ceil(0.95 * 4) = 4th smallest of |e| = 4.
        assert!((s.p95_abs - 4.0).abs() < 1e-12);
        let many = error_stats((1..=100).map(f64::from)).unwrap();
        assert!((many.p95_abs - 95.0).abs() < 1e-12);
        assert!(error_stats(std::iter::empty()).is_none());
    }

    #[test]
    fn convergence_indices() {
        let band = 0.05;
        assert_eq!(
            converged_index(&[0.8, 0.1, 0.01, 0.06, 0.02, 0.01], band),
            Some(4)
        );
        assert_eq!(converged_index(&[0.01, 0.02], band), Some(0));
        assert_eq!(converged_index(&[0.01, 0.2], band), None);
        assert_eq!(converged_index(&[0.01, f64::NAN], band), None);
        assert_eq!(converged_index(&[], band), None);
        assert_eq!(first_within_index(&[0.8, -0.04, 0.3], band), Some(1));
        assert_eq!(first_within_index(&[0.8, -0.05], band), None);
    }
}
