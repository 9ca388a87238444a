//! Control laws, and the gain sign convention they all share.
//!
//! # Gain sign convention (`spec/pierre2022.md`, PT-GAINS)
//!
//! Gains are written in the *equation form* of the papers: the law imposes
//! y' = k_y y (Pierre 2022, eq. 2) and e' = k_θ e (eq. 4), where ' is the
//! derivative with respect to the distance travelled along the path. An error
//! decays only for a **negative** gain, so convergent gains are negative, and
//! 1/|k| is the distance over which the error falls by a factor e.
//!
//! The papers' tables list positive "proportional gains" g (Table 1: 0.7): a
//! configuration that takes table values maps them once as k = −g (the
//! simulator's scenario schema does this). [`Gains::new`] refuses positive or
//! zero gains, and requires |k_θ| ≥ r |k_y| for a configured minimum ratio r ≥ 1,
//! which is how the library reads the paper's "k_θ ≫ k_y".

pub mod backstepping;

use crate::error::Precondition;

/// The two convergence gains of the backstepping law, per metre, in equation
/// form (negative = convergent), validated once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    k_y: f64,
    k_theta: f64,
}

impl Gains {
    /// Gains `k_y` (lateral, eq. 2) and `k_theta` (angular, eq. 4), per metre,
    /// with `min_ratio` the least accepted |k_θ| / |k_y|.
    ///
    /// Errors: `PT-GAINS-SIGN` unless both gains are finite and strictly
    /// negative; `PT-GAINS-RATIO` unless `min_ratio` is finite and ≥ 1 and
    /// |k_θ| ≥ `min_ratio` |k_y|.
    //= spec/pierre2022.md#pt-gains-gain-sign-and-ratio
    //# Both gains MUST be finite and strictly negative (convergent in equation
    //# form), and |k_θ| MUST be at least a configured ratio r ≥ 1 times |k_y|;
    //# other gains MUST be refused at construction.
    pub fn new(k_y: f64, k_theta: f64, min_ratio: f64) -> Result<Self, Precondition> {
        let finite_negative = |k: f64| k.is_finite() && k < 0.0;
        if !(finite_negative(k_y) && finite_negative(k_theta)) {
            return Err(Precondition::new(
                "PT-GAINS-SIGN",
                "gains must be finite and < 0 (equation form: y' = k_y y)",
            ));
        }
        Self::with_ratio(k_y, k_theta, min_ratio)
    }

    /// Like [`Gains::new`] but without the sign check, so a test can show that
    /// a wrong sign makes the closed loop diverge. Only with the
    /// `fault-injection` feature; never in a vehicle.
    #[cfg(feature = "fault-injection")]
    pub fn with_unchecked_sign(
        k_y: f64,
        k_theta: f64,
        min_ratio: f64,
    ) -> Result<Self, Precondition> {
        if !(k_y.is_finite() && k_theta.is_finite() && k_y != 0.0 && k_theta != 0.0) {
            return Err(Precondition::new(
                "PT-GAINS-SIGN",
                "gains must be finite and non-zero",
            ));
        }
        Self::with_ratio(k_y, k_theta, min_ratio)
    }

    fn with_ratio(k_y: f64, k_theta: f64, min_ratio: f64) -> Result<Self, Precondition> {
        let ratio_ok = min_ratio.is_finite()
            && min_ratio >= 1.0
            && libm::fabs(k_theta) >= min_ratio * libm::fabs(k_y);
        if ratio_ok {
            Ok(Self { k_y, k_theta })
        } else {
            Err(Precondition::new(
                "PT-GAINS-RATIO",
                "need min_ratio >= 1 and |k_theta| >= min_ratio |k_y|",
            ))
        }
    }

    /// k_y, per metre (negative).
    #[must_use]
    pub const fn k_y(&self) -> f64 {
        self.k_y
    }

    /// k_θ, per metre (negative).
    #[must_use]
    pub const fn k_theta(&self) -> f64 {
        self.k_theta
    }
}
