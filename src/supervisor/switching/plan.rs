//! Plan consistency: does a behaviour's line agree with the planned path?
//! (`spec/pierre2022.md`, SW-PLAN-CONSISTENCY; beyond the paper, whose
//! conclusion names it as future work.)

use crate::error::{finite, Precondition};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_angle, Meters, Radians};

/// Where a behaviour's line lies relative to the planned path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineRelativeToPath {
    /// Lateral offset of the line's point closest to the robot, measured from
    /// the planned path, metres, positive left of the path.
    pub offset: Meters,
    /// The line's heading minus the path's, radians, wrapped to (−π, π].
    pub heading: Radians,
}

/// The position of a behaviour's line relative to the planned path, from the
/// two tracking errors of the same robot point (SW-PLAN-CONSISTENCY):
/// Δ = wrap(θ̃_path − θ̃_line), offset = y_path − y_line cos Δ.
///
/// `line` is the error to the behaviour's line to follow, `path` the Frénet
/// error to the planned path; both in metres and radians (LIB-FRAMES).
///
/// # Errors
/// `LIB-FINITE` when the offset overflows (lateral errors near `f64::MAX`).
pub fn line_relative_to_path(
    line: &TrackingError,
    path: &TrackingError,
) -> Result<LineRelativeToPath, Precondition> {
    let heading = wrap_angle(path.angular_deviation.get() - line.angular_deviation.get());
    let offset = finite(
        path.y.get() - line.y.get() * libm::cos(heading),
        "line offset from the planned path overflows",
    )?;
    Ok(LineRelativeToPath {
        offset: Meters(offset),
        heading: Radians(heading),
    })
}

/// Tolerances within which a behaviour's line agrees with the planned path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanTolerance {
    max_offset: Meters,
    max_heading: Radians,
}

impl PlanTolerance {
    /// Lines within `max_offset` of the path and `max_heading` of its heading
    /// are consistent with it.
    ///
    /// # Errors
    /// `SW-PLAN-CONSISTENCY` when `max_offset` is negative or `max_heading` is
    /// outside [0, π].
    pub fn new(max_offset: Meters, max_heading: Radians) -> Result<Self, Precondition> {
        if max_offset.get() < 0.0 {
            return Err(Precondition::new(
                "SW-PLAN-CONSISTENCY",
                "max_offset must not be negative",
            ));
        }
        if max_heading.get() < 0.0 || max_heading.get() > core::f64::consts::PI {
            return Err(Precondition::new(
                "SW-PLAN-CONSISTENCY",
                "max_heading must be within [0, pi]",
            ));
        }
        Ok(Self {
            max_offset,
            max_heading,
        })
    }

    /// The largest lateral offset of a consistent line, metres.
    #[must_use]
    pub const fn max_offset(&self) -> Meters {
        self.max_offset
    }

    /// The largest heading difference of a consistent line, radians.
    #[must_use]
    pub const fn max_heading(&self) -> Radians {
        self.max_heading
    }

    /// Whether the line of `line` agrees with the planned path of `path`: the
    /// per-tick flag the switching machine consumes. An offset that overflows
    /// is inconsistent.
    //= spec/pierre2022.md#sw-plan-consistency-line-consistent-with-the-planned-path
    //# A behaviour's line MUST be consistent with the planned path when both the
    //# lateral offset of the line's point closest to the robot, y_path −
    //# y_line cos(θ̃_path − θ̃_line), and the heading difference, wrapped
    //# θ̃_path − θ̃_line, are within the configured tolerances in absolute value.
    #[must_use]
    pub fn is_consistent(&self, line: &TrackingError, path: &TrackingError) -> bool {
        match line_relative_to_path(line, path) {
            Ok(relative) => {
                relative.offset.abs().get() <= self.max_offset.get()
                    && relative.heading.abs().get() <= self.max_heading.get()
            }
            Err(_) => false,
        }
    }
}
