//! The one error type of the core: a violated precondition.
//!
//! Every function whose domain is restricted returns `Result<_, Precondition>`.
//! The error names the requirement of `spec/` that the check protects, so a
//! log line leads straight to the requirement, its reading of the paper and
//! its tests.

use core::fmt;

/// A precondition that did not hold: the requirement it protects and what was wrong.
///
/// `requirement` is the stable identifier of a requirement in `spec/`
/// (for example `"PT-DENOM"`, see `spec/README.md`), `violated` says in a few
/// words which condition failed (for example `"1 - y c(s) <= 0"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Precondition {
    /// Stable requirement identifier in `spec/`.
    pub requirement: &'static str,
    /// The condition that failed, in words.
    pub violated: &'static str,
}

impl Precondition {
    /// A precondition error for `requirement`, saying which condition was `violated`.
    #[must_use]
    pub const fn new(requirement: &'static str, violated: &'static str) -> Self {
        Self {
            requirement,
            violated,
        }
    }
}

impl fmt::Display for Precondition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "precondition {} violated: {}",
            self.requirement, self.violated
        )
    }
}

impl core::error::Error for Precondition {}

/// Returns `value` when it is finite, otherwise the `LIB-FINITE` error naming `what`.
///
/// This is the single gate through which computed floating-point values leave
/// the core (`spec/library.md`, LIB-FINITE).
//= spec/library.md#lib-finite-no-nan-or-infinity
//# A value returned by the core MUST be finite: a computation whose result
//# would be NaN or infinite MUST return a `Precondition` error instead.
pub fn finite(value: f64, what: &'static str) -> Result<f64, Precondition> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Precondition::new("LIB-FINITE", what))
    }
}
