//! Range checks that name the field they refuse (`section.field`).

use std::fmt::Display;

use crate::error::ScenarioError;

/// Checks values of one scenario (`origin`: its file or built-in name).
#[derive(Debug, Clone, Copy)]
pub struct Checker<'a> {
    origin: &'a str,
}

impl<'a> Checker<'a> {
    /// A checker for the scenario called `origin` in messages.
    #[must_use]
    pub const fn new(origin: &'a str) -> Self {
        Self { origin }
    }

    /// The scenario's name in messages (its file or built-in name).
    #[must_use]
    pub const fn origin(&self) -> &'a str {
        self.origin
    }

    /// The error "`field`: `reason`".
    #[must_use]
    pub fn error(&self, field: &str, reason: &str) -> ScenarioError {
        ScenarioError::Field {
            origin: self.origin.to_owned(),
            field: field.to_owned(),
            reason: reason.to_owned(),
        }
    }

    /// `value` if finite.
    pub fn finite(&self, field: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.error(field, &format!("must be a finite number, got {value}")))
        }
    }

    /// `value` if finite and > 0.
    pub fn positive(&self, field: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(self.error(field, &format!("must be > 0, got {value}")))
        }
    }

    /// `value` if finite and ≥ 0.
    pub fn non_negative(&self, field: &str, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(self.error(field, &format!("must be >= 0, got {value}")))
        }
    }

    /// `value` if finite and within `[lo, hi]`.
    pub fn range(&self, field: &str, value: f64, lo: f64, hi: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() && value >= lo && value <= hi {
            Ok(value)
        } else {
            Err(self.error(field, &format!("must be within [{lo}, {hi}], got {value}")))
        }
    }

    /// Replaces `*dst` by `value` when a file gives one, if finite and within
    /// `[lo, hi]`; leaves it otherwise.
    pub fn replace(
        &self,
        dst: &mut f64,
        value: Option<f64>,
        field: &str,
        lo: f64,
        hi: f64,
    ) -> Result<(), ScenarioError> {
        if let Some(x) = value {
            *dst = self.range(field, x, lo, hi)?;
        }
        Ok(())
    }

    /// `value` as a count if within `[lo, hi]`.
    pub fn count(
        &self,
        field: &str,
        value: u32,
        lo: usize,
        hi: usize,
    ) -> Result<usize, ScenarioError> {
        usize::try_from(value)
            .ok()
            .filter(|v| (lo..=hi).contains(v))
            .ok_or_else(|| self.error(field, &format!("must be within [{lo}, {hi}], got {value}")))
    }

    /// The error of a value (`what`) that passed the range checks but that
    /// the core refuses, with the requirement the core names (`reason`).
    #[must_use]
    pub fn refused(&self, field: &str, what: &str, reason: &impl Display) -> ScenarioError {
        self.error(field, &format!("the core refuses the {what}: {reason}"))
    }

    /// `value` if finite and strictly within `(lo, hi)`.
    pub fn open_range(
        &self,
        field: &str,
        value: f64,
        lo: f64,
        hi: f64,
    ) -> Result<f64, ScenarioError> {
        if value.is_finite() && value > lo && value < hi {
            Ok(value)
        } else {
            Err(self.error(
                field,
                &format!("must be strictly between {lo} and {hi}, got {value}"),
            ))
        }
    }

    /// `Ok` if `value` (of `field`) is strictly above `other` (of `other_field`):
    /// the check of an ordered pair such as a minimum and a maximum.
    pub fn above(
        &self,
        field: &str,
        value: f64,
        other_field: &str,
        other: f64,
    ) -> Result<(), ScenarioError> {
        if value > other {
            Ok(())
        } else {
            Err(self.error(
                field,
                &format!("must be above {other_field} = {other}, got {value}"),
            ))
        }
    }

    /// `Ok` if `value` (of `field`) is strictly below `other` (of `other_field`).
    pub fn below(
        &self,
        field: &str,
        value: f64,
        other_field: &str,
        other: f64,
    ) -> Result<(), ScenarioError> {
        if value < other {
            Ok(())
        } else {
            Err(self.error(
                field,
                &format!("must be below {other_field} = {other}, got {value}"),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordered_pairs_name_both_fields() {
        let c = Checker::new("demo.toml");
        assert!(c
            .above("lidar.range_max_m", 30.0, "lidar.range_min_m", 0.1)
            .is_ok());
        assert!(c
            .below(
                "edge.min_chain_length_m",
                1.5,
                "edge.max_chain_length_m",
                3.0
            )
            .is_ok());
        for bad in [
            c.above("lidar.range_max_m", 0.1, "lidar.range_min_m", 0.1),
            c.below(
                "edge.min_chain_length_m",
                3.0,
                "edge.max_chain_length_m",
                3.0,
            ),
        ] {
            let text = bad.unwrap_err().to_string();
            assert!(text.contains("lidar.range_max_m") || text.contains("edge.min_chain_length_m"));
            assert!(
                text.contains("lidar.range_min_m = 0.1")
                    || text.contains("edge.max_chain_length_m = 3")
            );
        }
    }

    #[test]
    fn each_check_names_the_field_and_the_value() {
        let c = Checker::new("demo.toml");
        assert!(c.positive("vehicle.wheelbase_m", 2.0).is_ok());
        let e = c.positive("vehicle.wheelbase_m", 0.0).unwrap_err();
        assert_eq!(e.field(), Some("vehicle.wheelbase_m"));
        assert_eq!(
            e.to_string(),
            "demo.toml: field `vehicle.wheelbase_m`: must be > 0, got 0"
        );
        assert!(c.non_negative("a.b", 0.0).is_ok());
        assert!(c.non_negative("a.b", -1e-9).is_err());
        assert!(c.range("a.b", 5.0, 0.0, 5.0).is_ok());
        assert!(c.range("a.b", f64::NAN, 0.0, 5.0).is_err());
        assert!(c.open_range("a.b", 5.0, 0.0, 5.0).is_err());
        assert!(c.finite("a.b", f64::INFINITY).is_err());
        assert_eq!(c.count("a.n", 4, 4, 256).ok(), Some(4));
        assert_eq!(
            c.count("a.n", 3, 4, 256).unwrap_err().to_string(),
            "demo.toml: field `a.n`: must be within [4, 256], got 3"
        );
    }
}
