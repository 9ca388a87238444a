//! The bounds a stress run is held to, and the physical limits they are
//! derived from (`spec/pierre2022.md`, PT-SPEED-RANGE): what a steering of
//! rate R on a wheelbase L allows, so that a bound says what the actuator
//! permits rather than what one tuning happened to reach.
//!
//! Every figure is measured against ground truth: the true pose projected on
//! the reference path ([`TickRecord::lateral_error_m`]).

use serde::Serialize;

use crate::metrics::Summary;
use crate::runner::{RunOutput, TickRecord};
use crate::scenario::Setup;

/// The convergence band of PT-SPEED-RANGE, metres.
pub const BAND_M: f64 = 0.05;

/// What the feedback may add to the drift a step allows (PT-SPEED-RANGE).
pub const MARGIN: f64 = 1.25;

/// The time the linearised scheduled loop (a critically damped pair at
/// Ω / 2, PT-SPEED-RANGE) needs to bring (y0, ẏ0) within the band for good,
/// seconds (searched back from 60 s in steps of 1 ms).
#[must_use]
pub fn linear_time_s(y0: f64, y_dot0: f64, bandwidth: f64) -> f64 {
    let p = bandwidth / 2.0;
    let y = |t: f64| (y0 + (y_dot0 + p * y0) * t).abs() * (-p * t).exp();
    let mut t = 60.0;
    while t > 0.0 && y(t) < BAND_M {
        t -= 1e-3;
    }
    t
}

/// The convergence distance PT-SPEED-RANGE allows from (y0, θ0) at `v`:
/// 10 m or 5 s of travel, or 1.3 times the linearised loop's time at the
/// schedule's bandwidth, whichever is longest, metres.
#[must_use]
pub fn allowed_convergence_m(v: f64, y0: f64, theta0: f64, bandwidth: f64) -> f64 {
    let linear = linear_time_s(y0.abs(), v * theta0.sin() * y0.signum(), bandwidth);
    10.0_f64.max(5.0 * v).max(1.3 * v * linear)
}

/// The lateral offset a curvature step Δκ leaves when the steering follows
/// it at its rate limit R in a ramp centred on the step (PT-SPEED-RANGE):
/// Δκ d² / 24 over the ramp's length d = Δκ L v / R, metres.
#[must_use]
pub fn ramp_offset_m(delta_kappa: f64, v: f64, wheelbase_m: f64, rate_rad_s: f64) -> f64 {
    let d = delta_kappa * wheelbase_m * v / rate_rad_s;
    delta_kappa * d * d / 24.0
}

/// The lateral drift of a step Δβ of the rear sideslip at speed v
/// (PT-SPEED-RANGE): the heading must turn by Δβ, which at the rate limit R
/// takes t = 2 √(Δβ L / (R v)), drifting v Δβ t / 2 meanwhile; the
/// observer's lag τ_o adds v Δβ τ_o, metres.
#[must_use]
pub fn slip_drift_m(delta_beta: f64, v: f64, wheelbase_m: f64, rate_rad_s: f64, tau_o: f64) -> f64 {
    let turn_s = 2.0 * (delta_beta * wheelbase_m / (rate_rad_s * v)).sqrt();
    v * delta_beta * (turn_s / 2.0 + tau_o)
}

/// One bound of a stress class, judged on every run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// The scenario file's own checks (`[metrics]`, reaching the end, no
    /// plant crushed): the run's `success`.
    ScenarioChecks,
    /// No crop plant under a wheel.
    NoPlantCrushed,
    /// PT-SPEED-RANGE: |y| within the band for good after the distance
    /// [`allowed_convergence_m`] gives from the run's first true error.
    ConvergesInTime,
    /// PT-SPEED-RANGE: the largest error on the far side of the path below
    /// this fraction of the first |y|.
    Overshoot(f64),
    /// |y| below the band from convergence on.
    SettledInBand,
    /// PT-SPEED-RANGE: |y| over the whole run below the larger of the band
    /// and [`MARGIN`] × [`ramp_offset_m`] of this curvature step (1/m).
    CurvatureStep(f64),
    /// PT-SPEED-RANGE: |y| over the whole run below the larger of the band
    /// and [`MARGIN`] × [`slip_drift_m`] of this rear-sideslip step
    /// (degrees), with the observer's settling time (seconds, 5 %).
    SlipStep(f64, f64),
    /// |y| from this abscissa of the path on below this, metres (a bound
    /// measured, not derived: the README says so).
    MaxFrom(f64, f64),
    /// |y| before this abscissa, from the convergence allowed by
    /// [`Bound::ConvergesInTime`] on, below the band.
    SettledBefore(f64),
    /// Largest |error to the true centre line| inside the plots below this, metres.
    InPlotMax(f64),
    /// Largest |error to the true offset line| along the hedges after
    /// convergence below this, metres.
    AlongHedgeMax(f64),
    /// At most this many mode changes in the run.
    SwitchesAtMost(usize),
    /// Largest |error to the offset line of hedge 0's followed line| in
    /// edge following, settled, below this, metres ([`super::envelope`]:
    /// the face's envelope straightened over the detector's l_max).
    FollowedMax(f64),
    /// Mean |error to that line| below this, metres.
    FollowedMean(f64),
    /// Largest error towards the hedge from the offset line of its face's
    /// envelope itself (the clearance lost inside the offset), below this,
    /// metres: the side the robot must keep clear of, judged against the
    /// vegetation's outermost line, not the straightened one.
    EnvelopeTowards(f64),
}

/// What [`Bound::FollowedMax`] measures, in words.
pub const FOLLOWED_MAX: &str = "max |y| to the followed line (m)";
/// What [`Bound::FollowedMean`] measures, in words.
pub const FOLLOWED_MEAN: &str = "mean |y| to the followed line (m)";
/// What [`Bound::EnvelopeTowards`] measures, in words.
pub const TOWARDS: &str = "max towards the hedge from the envelope's line (m)";

/// A bound's figure on one run: the value measured and the limit it must
/// not exceed (a count or a metre figure; `pass` when value ≤ limit).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Judged {
    /// What was measured, in words.
    pub what: String,
    /// The measured value.
    pub value: f64,
    /// The largest allowed value.
    pub limit: f64,
    /// The run's own words on what broke, when it says (a scenario's checks).
    pub detail: Vec<String>,
}

impl Judged {
    /// Whether the value is within the limit (a NaN never is).
    #[must_use]
    pub fn pass(&self) -> bool {
        self.value <= self.limit
    }
}

/// The run's speed, steering rate, wheelbase and schedule bandwidth.
struct Physics {
    v: f64,
    rate: f64,
    wheelbase: f64,
    bandwidth: Option<f64>,
}

impl Physics {
    fn of(setup: &Setup) -> Self {
        Self {
            v: setup.control.speed.get(),
            rate: setup.vehicle.actuator.rate_limit_rad_s,
            wheelbase: setup.vehicle.wheelbase.get().get(),
            bandwidth: setup
                .control
                .backstepping
                .schedule
                .map(|s| s.bandwidth().get()),
        }
    }
}

fn max_abs<'a>(records: impl Iterator<Item = &'a TickRecord>) -> f64 {
    records.map(|r| r.lateral_error_m.abs()).fold(0.0, f64::max)
}

impl Bound {
    /// The bound's figure on one run.
    #[must_use]
    pub fn judge(&self, setup: &Setup, run: &RunOutput, summary: &Summary) -> Judged {
        let trace = &run.trace;
        let p = Physics::of(setup);
        let first = trace.first();
        let y0 = first.map_or(0.0, |r| r.lateral_error_m);
        let theta0 = first.map_or(0.0, |r| r.angular_error_rad);
        let judged = |what: String, value: f64, limit: f64| Judged {
            what,
            value,
            limit,
            detail: Vec::new(),
        };
        let allowed = || {
            p.bandwidth
                .map_or(f64::INFINITY, |b| allowed_convergence_m(p.v, y0, theta0, b))
        };
        match *self {
            Self::ScenarioChecks => Judged {
                what: "scenario checks broken".to_owned(),
                value: summary.failures.len() as f64,
                limit: 0.0,
                detail: summary.failures.clone(),
            },
            Self::NoPlantCrushed => judged(
                "crop plants crushed".to_owned(),
                summary.plants_crushed as f64,
                0.0,
            ),
            Self::ConvergesInTime => judged(
                "converged after (m)".to_owned(),
                summary.converged_after_m.unwrap_or(f64::INFINITY),
                allowed(),
            ),
            Self::Overshoot(fraction) => {
                let side = if y0 < 0.0 { -1.0 } else { 1.0 };
                let far = trace
                    .iter()
                    .map(|r| -side * r.lateral_error_m)
                    .fold(0.0, f64::max);
                judged("overshoot (m)".to_owned(), far, fraction * y0.abs())
            }
            Self::SettledInBand => judged(
                "max |y| after convergence (m)".to_owned(),
                summary
                    .lateral_error_after_convergence_m
                    .map_or(f64::INFINITY, |e| e.max_abs),
                BAND_M,
            ),
            Self::CurvatureStep(delta_kappa) => judged(
                "max |y| (m)".to_owned(),
                summary.lateral_error_m.max_abs,
                BAND_M.max(MARGIN * ramp_offset_m(delta_kappa, p.v, p.wheelbase, p.rate)),
            ),
            Self::SlipStep(delta_beta_deg, settling_s) => judged(
                "max |y| (m)".to_owned(),
                summary.lateral_error_m.max_abs,
                BAND_M.max(
                    MARGIN
                        * slip_drift_m(
                            delta_beta_deg.to_radians(),
                            p.v,
                            p.wheelbase,
                            p.rate,
                            settling_s / 3.0,
                        ),
                ),
            ),
            Self::MaxFrom(s, limit) => judged(
                format!("max |y| from s = {s} m (m)"),
                max_abs(trace.iter().filter(|r| r.s_m >= s)),
                limit,
            ),
            Self::SettledBefore(s) => {
                let within = allowed();
                let settled = trace
                    .iter()
                    .filter(|r| r.s_m < s && r.lateral_error_m.abs() >= BAND_M)
                    .map(|r| r.distance_m)
                    .fold(0.0, f64::max);
                judged(
                    format!("in the band before s = {s} m after (m)"),
                    settled,
                    within,
                )
            }
            Self::InPlotMax(limit) => judged(
                "max |y| to the rows in the plots (m)".to_owned(),
                summary
                    .in_plot_lateral_error_m
                    .map_or(f64::INFINITY, |e| e.max_abs),
                limit,
            ),
            Self::AlongHedgeMax(limit) => judged(
                "max |y| along the hedges after convergence (m)".to_owned(),
                summary
                    .along_hedge_after_convergence_m
                    .map_or(f64::INFINITY, |e| e.max_abs),
                limit,
            ),
            Self::FollowedMax(limit) | Self::FollowedMean(limit) => {
                let errors = super::envelope::face_errors(setup, trace);
                let max = matches!(self, Self::FollowedMax(_));
                let value = if errors.is_empty() {
                    f64::INFINITY
                } else if max {
                    errors.iter().map(|e| e.followed.abs()).fold(0.0, f64::max)
                } else {
                    errors.iter().map(|e| e.followed.abs()).sum::<f64>() / errors.len() as f64
                };
                let what = if max { FOLLOWED_MAX } else { FOLLOWED_MEAN };
                judged(what.to_owned(), value, limit)
            }
            Self::EnvelopeTowards(limit) => {
                let errors = super::envelope::face_errors(setup, trace);
                let value = if errors.is_empty() {
                    f64::INFINITY
                } else {
                    errors.iter().map(|e| -e.envelope).fold(0.0, f64::max)
                };
                judged(TOWARDS.to_owned(), value, limit)
            }
            Self::SwitchesAtMost(n) => judged(
                "mode changes".to_owned(),
                summary.mode_switches as f64,
                n as f64,
            ),
        }
    }
}
