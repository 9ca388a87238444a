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
