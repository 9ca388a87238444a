//! Unit newtypes: one type per physical meaning, every value finite.
//!
//! Constructors reject NaN and infinities (`spec/library.md`, LIB-UNITS), so a
//! value of these types that exists is finite. Arithmetic is done on the inner
//! `f64` by the functions that own an equation; their results come back through
//! these constructors, which is where a NaN or an overflow would be caught.

use core::f64::consts::{PI, TAU};

use crate::error::{finite, Precondition};

//= spec/library.md#lib-units-typed-quantities
//# Quantities that mean different things MUST have different types (`Meters`,
//# `Radians`, `Curvature`, `MetersPerSecond`, `RadiansPerSecond`, `Seconds`).
macro_rules! finite_unit {
    ($(#[$doc:meta])* $name:ident, $unit:literal) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
        pub struct $name(pub(crate) f64);

        impl $name {
            /// Zero in this unit.
            pub const ZERO: Self = Self(0.0);

            #[doc = concat!("A value in ", $unit, "; a NaN or infinite `value` is the `LIB-FINITE` error.")]
            //= spec/library.md#lib-units-typed-quantities
            //# Constructors of unit types MUST reject NaN and infinite values with a
            //# `Precondition` error.
            pub fn new(value: f64) -> Result<Self, Precondition> {
                finite(value, concat!(stringify!($name), " must be finite")).map(Self)
            }

            #[doc = concat!("The value in ", $unit, ".")]
            #[must_use]
            pub const fn get(self) -> f64 {
                self.0
            }

            /// The absolute value.
            #[must_use]
            pub fn abs(self) -> Self {
                Self(libm::fabs(self.0))
            }

            /// The negated value (mirror image about the path, `spec/library.md` LIB-FRAMES).
            #[must_use]
            pub fn negated(self) -> Self {
                Self(-self.0)
            }
        }
    };
}

finite_unit!(
    /// A length or a signed distance, in metres.
    Meters,
    "metres (m)"
);
finite_unit!(
    /// An angle, in radians, counter-clockwise positive. Not necessarily wrapped;
    /// [`Radians::wrapped`] brings it to (−π, π].
    Radians,
    "radians (rad)"
);
finite_unit!(
    /// A path curvature, in 1/m, positive for a left turn.
    Curvature,
    "reciprocal metres (1/m)"
);
finite_unit!(
    /// A signed speed along the vehicle's forward axis, in m/s.
    MetersPerSecond,
    "metres per second (m/s)"
);
finite_unit!(
    /// An angular rate (yaw rate), in rad/s, counter-clockwise positive.
    RadiansPerSecond,
    "radians per second (rad/s)"
);
finite_unit!(
    /// A duration, in seconds.
    Seconds,
    "seconds (s)"
);

/// `angle` (radians) wrapped to (−π, π]; NaN for NaN or infinite input. The
/// raw form used inside the core, where every result goes through a unit
/// constructor or is finite by construction.
pub(crate) fn wrap_raw(angle: f64) -> f64 {
    let r = libm::remainder(angle, TAU);
    // `remainder` gives [−π, π]; −π is mapped to π so the interval is (−π, π].
    if r <= -PI {
        PI
    } else {
        r
    }
}

/// The same direction as `angle`, wrapped to (−π, π].
///
/// An angle is finite by its type, so the result always is: there is no
/// angle to wrap in a NaN or an infinity (`spec/library.md`, LIB-FINITE).
//= spec/library.md#lib-frames-frames-and-sign-conventions
//# Angles MUST be counter-clockwise positive and, where the core returns an
//# orientation, wrapped to (−π, π].
#[must_use]
pub fn wrap_angle(angle: Radians) -> Radians {
    Radians(wrap_raw(angle.0))
}

impl Radians {
    /// The same direction, wrapped to (−π, π] ([`wrap_angle`]).
    #[must_use]
    pub fn wrapped(self) -> Self {
        wrap_angle(self)
    }
}

/// Distinct meanings are distinct types: none of these compiles.
///
/// ```compile_fail
/// let _: fieldguide::Meters = fieldguide::Radians::ZERO;
/// ```
///
/// ```compile_fail
/// let _: fieldguide::Curvature = fieldguide::Meters::ZERO;
/// ```
///
/// ```compile_fail
/// let _: fieldguide::MetersPerSecond = fieldguide::RadiansPerSecond::ZERO;
/// ```
//= spec/library.md#lib-units-typed-quantities
//= type=test
//# Quantities that mean different things MUST have different types (`Meters`,
//# `Radians`, `Curvature`, `MetersPerSecond`, `RadiansPerSecond`, `Seconds`).
#[cfg(doctest)]
pub struct DistinctUnitTypes;

#[cfg(test)]
#[allow(clippy::float_cmp)] // exact values are the point of these checks
mod tests {
    use super::*;

    //= spec/library.md#lib-units-typed-quantities
    //= type=test
    //# Constructors of unit types MUST reject NaN and infinite values with a
    //# `Precondition` error.
    #[test]
    fn constructors_reject_non_finite_values() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(Meters::new(bad).unwrap_err().requirement, "LIB-FINITE");
            assert!(Radians::new(bad).is_err());
            assert!(Curvature::new(bad).is_err());
            assert!(MetersPerSecond::new(bad).is_err());
            assert!(RadiansPerSecond::new(bad).is_err());
            assert!(Seconds::new(bad).is_err());
        }
        assert_eq!(Meters::new(-2.5).unwrap().get(), -2.5);
    }

    //= spec/library.md#lib-frames-frames-and-sign-conventions
    //= type=test
    //# Angles MUST be counter-clockwise positive and, where the core returns an
    //# orientation, wrapped to (−π, π].
    #[test]
    fn wrapping_lands_in_the_half_open_interval() {
        let w = |a: f64| wrap_angle(Radians::new(a).unwrap()).get();
        assert_eq!(w(PI), PI);
        assert_eq!(w(-PI), PI);
        assert!((w(3.0 * PI) - PI).abs() < 1e-12);
        assert!((w(-0.5 - TAU) + 0.5).abs() < 1e-12);
        assert!((w(1e6) - libm::remainder(1e6, TAU)).abs() < 1e-9);
        // The largest angles wrap to a finite angle too.
        for a in [f64::MAX, -f64::MAX, 1e300, f64::MIN_POSITIVE, 5e-324, -0.0] {
            let r = w(a);
            assert!(r.is_finite() && r > -PI && r <= PI, "{a}: {r}");
        }
    }
}
