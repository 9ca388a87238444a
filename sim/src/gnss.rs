//! The RTK-GNSS beyond its white noise: when it has no fix (outages by time
//! or by the abscissa the robot has reached on its path), and the errors of
//! a real receiver, a constant bias, a slow drift and float-fix spans
//! (`[gnss]`, `sim/scenarios/README.md`).
//!
//! The errors draw from their own generator, seeded from the run's seed, so
//! that a scenario with them sees the same world, path and sensor noise as
//! the one without them, and a scenario without them draws nothing more: its
//! runs are those of before.

use fieldguide::guidance::{FixKind, FixQuality};
use fieldguide::Meters;

use crate::rng::{gauss_markov, SimRng};

/// Mixed into the run's seed to seed the GNSS errors' own generator.
pub const GNSS_STREAM: u64 = 0x6e55_e440_0f1e_1d00;

/// A span `[from, to)` of the abscissa of the true pose's projection on the
/// path, metres, and the scenario field that placed it.
#[derive(Debug, Clone, PartialEq)]
pub struct AbscissaSpan {
    /// Where it starts, metres.
    pub from_m: f64,
    /// Where it ends, metres.
    pub to_m: f64,
    /// The field that placed it (`gnss.outages_m[0]`), for messages.
    pub field: String,
}

/// Spans of simulated time and spans of abscissa, each list increasing and
/// without overlap; a tick is inside when it is inside one of either.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Spans {
    time: Vec<(f64, f64)>,
    abscissa: Vec<AbscissaSpan>,
}

impl Spans {
    /// The spans `time` (seconds) and `abscissa` (metres), each increasing
    /// and without overlap (checked by the scenario's setup).
    #[must_use]
    pub const fn new(time: Vec<(f64, f64)>, abscissa: Vec<AbscissaSpan>) -> Self {
        Self { time, abscissa }
    }

    /// The spans of time `[from, to)`, seconds.
    #[must_use]
    pub fn spans(&self) -> &[(f64, f64)] {
        &self.time
    }

    /// The spans of abscissa, metres.
    #[must_use]
    pub fn abscissa_spans(&self) -> &[AbscissaSpan] {
        &self.abscissa
    }

    /// Whether there is no span at all.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.time.is_empty() && self.abscissa.is_empty()
    }

    /// Whether time `t_s` is inside a span of time.
    #[must_use]
    pub fn in_time(&self, t_s: f64) -> bool {
        self.time.iter().any(|(from, to)| t_s >= *from && t_s < *to)
    }

    /// The span of abscissa containing `s_m`, if any.
    #[must_use]
    pub fn at_abscissa(&self, s_m: f64) -> Option<&AbscissaSpan> {
        self.abscissa
            .iter()
            .find(|a| s_m >= a.from_m && s_m < a.to_m)
    }

    /// Whether a tick at time `t_s` with the true projection at `s_m` is
    /// inside a span.
    #[must_use]
    pub fn contains(&self, t_s: f64, s_m: f64) -> bool {
        self.in_time(t_s) || self.at_abscissa(s_m).is_some()
    }
}

/// When the RTK-GNSS has no fix.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GnssOutages(pub Spans);

impl GnssOutages {
    /// Whether the GNSS has a fix at time `t_s` (spans of time only).
    #[must_use]
    pub fn has_fix(&self, t_s: f64) -> bool {
        !self.0.in_time(t_s)
    }

    /// Whether the GNSS has a fix at time `t_s` with the true projection at
    /// abscissa `s_m`: outside every span of time and of abscissa.
    #[must_use]
    pub fn has_fix_at(&self, t_s: f64, s_m: f64) -> bool {
        !self.0.contains(t_s, s_m)
    }

    /// The spans of time, seconds.
    #[must_use]
    pub fn spans(&self) -> &[(f64, f64)] {
        self.0.spans()
    }

    /// The spans of abscissa, metres.
    #[must_use]
    pub fn abscissa_spans(&self) -> &[AbscissaSpan] {
        self.0.abscissa_spans()
    }
}

/// A slow drift of the reported position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drift {
    /// A first-order Gauss-Markov process on each axis, starting at zero:
    /// d ← a d + σ √(1 − a²) w with a = exp(−Δt / τ), w standard normal; its
    /// stationary standard deviation is σ, its correlation time τ.
    RandomWalk {
        /// σ, metres.
        sigma_m: f64,
        /// τ, seconds.
        time_constant_s: f64,
    },
    /// A · sin(2π t / T) along the direction `heading_rad` (from east).
    Sinusoid {
        /// A, metres.
        amplitude_m: f64,
        /// T, seconds.
        period_s: f64,
        /// Direction of the offset, radians from east.
        heading_rad: f64,
    },
}

/// Spans where the fix is float rather than fixed: more noise, and an offset
/// drawn each time the fix turns float, kept until it is fixed again.
#[derive(Debug, Clone, PartialEq)]
pub struct FloatFix {
    /// Where the fix is float.
    pub spans: Spans,
    /// White noise per axis added while float, metres.
    pub noise_m: f64,
    /// Standard deviation per axis of the offset drawn when the fix turns float, metres.
    pub jump_m: f64,
}

/// The errors of the reported position beyond the white noise of `[noise]`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GnssErrors {
    /// Constant offset (east, north), metres.
    pub bias_m: (f64, f64),
    /// The drift, if any.
    pub drift: Option<Drift>,
    /// The float-fix spans, if any.
    pub float: Option<FloatFix>,
}

impl GnssErrors {
    /// Whether there is no error to add (the default).
    #[must_use]
    pub fn is_none(&self) -> bool {
        self.bias_m == (0.0, 0.0) && self.drift.is_none() && self.float.is_none()
    }
}

/// The error of the reported position at one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GnssError {
    /// Offset added to the reported position (east, north), metres.
    pub offset_m: (f64, f64),
    /// Whether the fix is float at this tick.
    pub float: bool,
    /// The spread per axis the float span adds, metres: √(noise² + jump²)
    /// of `[gnss]` float_noise_m and float_jump_m; 0 while fixed.
    pub float_sigma_m: f64,
}

impl GnssError {
    /// What the receiver reports of this tick's fix, its white noise per
    /// axis being `white_m` (`[noise] gnss_position_m`): RTK fixed with σ =
    /// `white_m`, or RTK float with σ = √(white_m² + float_sigma_m²). A
    /// receiver's σ is its own solution's spread: a slow drift or a bias
    /// (a base station misplaced, multipath) is common to its measurements
    /// and not in it, so neither raises σ.
    #[must_use]
    pub fn quality(&self, white_m: f64) -> FixQuality {
        let (kind, sigma) = if self.float {
            (FixKind::RtkFloat, white_m.hypot(self.float_sigma_m))
        } else {
            (FixKind::RtkFixed, white_m)
        };
        FixQuality {
            kind,
            accuracy: Meters::new(sigma).ok(),
        }
    }
}

/// The errors' state through a run.
#[derive(Debug, Clone)]
pub struct GnssErrorState {
    errors: GnssErrors,
    /// The errors' own generator; `None` when there are no errors.
    rng: Option<SimRng>,
    /// The random walk's value, metres.
    walk: (f64, f64),
    /// The offset of the current float span, if the fix is float.
    jump: Option<(f64, f64)>,
}

impl GnssErrorState {
    /// The state at the start of a run of seed `seed`.
    #[must_use]
    pub fn new(errors: &GnssErrors, seed: u64) -> Self {
        Self {
            rng: (!errors.is_none()).then(|| SimRng::from_seed(seed ^ GNSS_STREAM)),
            errors: errors.clone(),
            walk: (0.0, 0.0),
            jump: None,
        }
    }

    /// The error of the tick at time `t_s` with the true projection at `s_m`,
    /// `dt_s` before the next. Draws six values per tick from the errors'
    /// own generator whatever the spans (random walk, float noise, float
    /// jump; two axes each), none without errors.
    pub fn step(&mut self, t_s: f64, s_m: f64, dt_s: f64) -> GnssError {
        let Some(rng) = self.rng.as_mut() else {
            return GnssError {
                offset_m: (0.0, 0.0),
                float: false,
                float_sigma_m: 0.0,
            };
        };
        let draws = [
            rng.gaussian(1.0),
            rng.gaussian(1.0),
            rng.gaussian(1.0),
            rng.gaussian(1.0),
            rng.gaussian(1.0),
            rng.gaussian(1.0),
        ];
        let (mut dx, mut dy) = self.errors.bias_m;
        match self.errors.drift {
            Some(Drift::RandomWalk {
                sigma_m,
                time_constant_s,
            }) => {
                dx += self.walk.0;
                dy += self.walk.1;
                self.walk = (
                    gauss_markov(self.walk.0, sigma_m, time_constant_s, dt_s, draws[0]),
                    gauss_markov(self.walk.1, sigma_m, time_constant_s, dt_s, draws[1]),
                );
            }
            Some(Drift::Sinusoid {
                amplitude_m,
                period_s,
                heading_rad,
            }) => {
                let d = amplitude_m * (std::f64::consts::TAU * t_s / period_s).sin();
                dx += d * heading_rad.cos();
                dy += d * heading_rad.sin();
            }
            None => {}
        }
        let float = self
            .errors
            .float
            .as_ref()
            .is_some_and(|f| f.spans.contains(t_s, s_m));
        let mut float_sigma_m = 0.0;
        if let (true, Some(f)) = (float, &self.errors.float) {
            let jump = *self
                .jump
                .get_or_insert((f.jump_m * draws[4], f.jump_m * draws[5]));
            dx += jump.0 + f.noise_m * draws[2];
            dy += jump.1 + f.noise_m * draws[3];
            float_sigma_m = f.noise_m.hypot(f.jump_m);
        } else {
            self.jump = None;
        }
        GnssError {
            offset_m: (dx, dy),
            float,
            float_sigma_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_errors_nothing_is_added() {
        let mut s = GnssErrorState::new(&GnssErrors::default(), 1);
        for k in 0..10 {
            let e = s.step(f64::from(k) * 0.01, 0.0, 0.01);
            assert_eq!(e.offset_m, (0.0, 0.0));
            assert!(!e.float);
        }
    }

    #[test]
    fn a_random_walk_has_its_stationary_spread_and_correlation_time() {
        let errors = GnssErrors {
            drift: Some(Drift::RandomWalk {
                sigma_m: 0.1,
                time_constant_s: 1.0,
            }),
            ..GnssErrors::default()
        };
        let mut s = GnssErrorState::new(&errors, 3);
        let dt = 0.1;
        let xs: Vec<f64> = (0..200_000)
            .map(|k| s.step(f64::from(k) * dt, 0.0, dt).offset_m.0)
            .collect();
        assert_eq!(xs[0], 0.0, "the walk starts at zero");
        let tail = &xs[1000..];
        let n = tail.len() as f64;
        let var = tail.iter().map(|x| x * x).sum::<f64>() / n;
        assert!((var.sqrt() - 0.1).abs() < 0.005, "sigma {}", var.sqrt());
        // Lag-10 autocorrelation exp(-1) at one time constant.
        let lag = 10;
        let cov = tail.windows(lag + 1).map(|w| w[0] * w[lag]).sum::<f64>() / (n - 10.0);
        let rho = cov / var;
        assert!((rho - (-1.0_f64).exp()).abs() < 0.03, "rho {rho}");
    }

    #[test]
    fn the_receiver_reports_float_with_its_spread_and_fixed_with_its_noise() {
        let errors = GnssErrors {
            drift: Some(Drift::RandomWalk {
                sigma_m: 0.1,
                time_constant_s: 20.0,
            }),
            float: Some(FloatFix {
                spans: Spans::new(vec![(1.0, 2.0)], Vec::new()),
                noise_m: 0.1,
                jump_m: 0.3,
            }),
            ..GnssErrors::default()
        };
        let mut s = GnssErrorState::new(&errors, 7);
        let fixed = s.step(0.5, 0.0, 0.1).quality(0.015);
        assert_eq!(fixed.kind, FixKind::RtkFixed);
        // The drift is not in a receiver's sigma: the white noise alone.
        assert_eq!(fixed.accuracy.map(Meters::get), Some(0.015));
        let float = s.step(1.5, 0.0, 0.1).quality(0.015);
        assert_eq!(float.kind, FixKind::RtkFloat);
        let sigma = (0.015_f64.powi(2) + 0.1_f64.powi(2) + 0.3_f64.powi(2)).sqrt();
        assert!((float.accuracy.map_or(0.0, Meters::get) - sigma).abs() < 1e-12);
        assert_eq!(s.step(2.5, 0.0, 0.1).quality(0.015).kind, FixKind::RtkFixed);
    }

    #[test]
    fn a_float_span_jumps_once_and_adds_noise() {
        let errors = GnssErrors {
            float: Some(FloatFix {
                spans: Spans::new(vec![(1.0, 2.0)], Vec::new()),
                noise_m: 0.0,
                jump_m: 0.5,
            }),
            ..GnssErrors::default()
        };
        let mut s = GnssErrorState::new(&errors, 5);
        let at = |s: &mut GnssErrorState, t: f64| s.step(t, 0.0, 0.1);
        assert_eq!(at(&mut s, 0.9).offset_m, (0.0, 0.0));
        let first = at(&mut s, 1.0);
        assert!(first.float && first.offset_m != (0.0, 0.0));
        // Held through the span (no noise here), dropped after it.
        assert_eq!(at(&mut s, 1.5).offset_m, first.offset_m);
        let after = at(&mut s, 2.0);
        assert!(!after.float);
        assert_eq!(after.offset_m, (0.0, 0.0));
    }
}
