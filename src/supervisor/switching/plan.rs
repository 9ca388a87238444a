//! Plan consistency: does a behaviour's line agree with the planned path?
//! (`spec/pierre2022.md`, SW-PLAN-CONSISTENCY; beyond the paper, whose
//! conclusion names it as future work.)

use crate::error::{finite, Precondition};
use crate::geometry::path::ReferencePath;
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_raw, Meters, Radians};

/// Where a behaviour's line lies relative to the planned path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineRelativeToPath {
    /// Lateral offset of the line's point closest to the robot, measured from
    /// the planned path, metres, positive left of the path.
    pub offset: Meters,
    /// The line's heading minus the path's, radians, wrapped to (−π, π].
    pub heading: Radians,
}

/// The planned path a distance d ahead of the robot's projection, seen from
/// the path's frame at the projection: x along the tangent at s, y to its
/// left (SW-PLAN-AHEAD).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathAhead {
    distance: Meters,
    along: Meters,
    left: Meters,
    turn: Radians,
}

impl PathAhead {
    /// The path at the projection itself (d = 0).
    pub const HERE: Self = Self {
        distance: Meters(0.0),
        along: Meters(0.0),
        left: Meters(0.0),
        turn: Radians(0.0),
    };

    /// The point of `path` at abscissa s + `distance` and its tangent, seen
    /// from the tangent at `s` (metres along and to the left, and the heading
    /// change, wrapped). Past the path's end the straight extension is used
    /// (PATH-EXTENSION).
    ///
    /// # Errors
    /// `SW-PLAN-AHEAD` when `distance` is negative; `LIB-FINITE` when a
    /// coordinate overflows.
    pub fn on_path<const N: usize>(
        path: &ReferencePath<N>,
        s: Meters,
        distance: Meters,
    ) -> Result<Self, Precondition> {
        if distance.get() < 0.0 {
            return Err(Precondition::new(
                "SW-PLAN-AHEAD",
                "look-ahead distance must not be negative",
            ));
        }
        let ahead = Meters::new(s.get() + distance.get())?;
        let here = path.point_at(s)?;
        let there = path.point_at(ahead)?;
        let heading = path.heading_at(s).get();
        let (sin, cos) = (libm::sin(heading), libm::cos(heading));
        let (dx, dy) = (there.x() - here.x(), there.y() - here.y());
        Ok(Self {
            distance,
            along: Meters(finite(cos * dx + sin * dy, "path look-ahead overflows")?),
            left: Meters(finite(cos * dy - sin * dx, "path look-ahead overflows")?),
            turn: Radians(wrap_raw(path.heading_at(ahead).get() - heading)),
        })
    }

    /// The look-ahead distance d along the path, metres.
    #[must_use]
    pub const fn distance(&self) -> Meters {
        self.distance
    }
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
//= spec/pierre2022.md#sw-plan-ahead-the-line-against-the-path-ahead
//# With d = 0 the offset at the robot MUST equal that of SW-PLAN-CONSISTENCY.
pub fn line_relative_to_path(
    line: &TrackingError,
    path: &TrackingError,
) -> Result<LineRelativeToPath, Precondition> {
    line_relative_to_path_ahead(line, path, &PathAhead::HERE)
}

/// The position of a behaviour's line relative to the planned path at
/// `ahead` (SW-PLAN-AHEAD): the line's point d ahead of its point closest to
/// the robot, offset from the path's tangent at s + d, and the line's heading
/// minus the path's there. With [`PathAhead::HERE`] this is
/// [`line_relative_to_path`].
///
/// # Errors
/// `LIB-FINITE` when the offset overflows.
pub fn line_relative_to_path_ahead(
    line: &TrackingError,
    path: &TrackingError,
    ahead: &PathAhead,
) -> Result<LineRelativeToPath, Precondition> {
    // The line's heading in the path frame at s; the robot is at (0, y_path).
    let delta = wrap_raw(path.angular_deviation.get() - line.angular_deviation.get());
    let (sin_d, cos_d) = (libm::sin(delta), libm::cos(delta));
    let (y_line, y_path, d) = (line.y.get(), path.y.get(), ahead.distance.get());
    // The line's point closest to the robot, moved d along the line.
    let x = y_line * sin_d + d * cos_d;
    let y = y_path - y_line * cos_d + d * sin_d;
    // Its offset from the path's tangent at s + d.
    let turn = ahead.turn.get();
    let offset = finite(
        (y - ahead.left.get()) * libm::cos(turn) - (x - ahead.along.get()) * libm::sin(turn),
        "line offset from the planned path overflows",
    )?;
    Ok(LineRelativeToPath {
        offset: Meters(offset),
        heading: Radians(wrap_raw(delta - turn)),
    })
}

/// Tolerances within which a behaviour's line agrees with the planned path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanTolerance {
    max_offset: Meters,
    max_heading: Radians,
    lookahead: Meters,
    entry_heading: Option<Radians>,
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
            lookahead: Meters(0.0),
            entry_heading: None,
        })
    }

    /// The same tolerances, with a tighter heading `entry_heading` for the
    /// line of a behaviour in a tick that starts outside its mode, so that
    /// a line turned from the path is not entered (GD-PLAN-ENTRY).
    ///
    /// # Errors
    /// `GD-PLAN-ENTRY` when `entry_heading` is outside [0, max_heading].
    //= spec/guidance.md#gd-plan-entry-a-line-entered-only-near-the-path-s-heading
    //# An entry heading that is negative or larger than the tolerance's largest
    //# heading MUST be refused with `GD-PLAN-ENTRY`.
    pub fn with_entry_heading(self, entry_heading: Radians) -> Result<Self, Precondition> {
        if entry_heading.get() < 0.0 || entry_heading.get() > self.max_heading.get() {
            return Err(Precondition::new(
                "GD-PLAN-ENTRY",
                "the entry heading must be within [0, max_heading]",
            ));
        }
        Ok(Self {
            entry_heading: Some(entry_heading),
            ..self
        })
    }

    /// The heading within which a line of a behaviour not entered is
    /// consistent, radians (`None`: [`Self::max_heading`]).
    #[must_use]
    pub const fn entry_heading(&self) -> Option<Radians> {
        self.entry_heading
    }

    /// The same tolerances, also checking the line's offset `lookahead`
    /// metres ahead along the path (SW-PLAN-AHEAD), so that a line going
    /// straight on where the plan turns is left before the turn.
    ///
    /// # Errors
    /// `SW-PLAN-AHEAD` when `lookahead` is negative.
    pub fn with_lookahead(self, lookahead: Meters) -> Result<Self, Precondition> {
        if lookahead.get() < 0.0 {
            return Err(Precondition::new(
                "SW-PLAN-AHEAD",
                "look-ahead distance must not be negative",
            ));
        }
        Ok(Self { lookahead, ..self })
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

    /// How far ahead along the path the line's offset is also checked,
    /// metres (0: only at the robot).
    #[must_use]
    pub const fn lookahead(&self) -> Meters {
        self.lookahead
    }

    /// Whether the line of `line` agrees with the planned path of `path`: the
    /// per-tick flag the switching machine consumes. `ahead` is the path at
    /// [`Self::lookahead`] (`PathAhead::on_path(path, s, self.lookahead())`);
    /// with a zero look-ahead, [`PathAhead::HERE`]. An offset that overflows is
    /// inconsistent.
    //= spec/pierre2022.md#sw-plan-consistency-line-consistent-with-the-planned-path
    //# A behaviour's line MUST be consistent with the planned path when both the
    //# lateral offset of the line's point closest to the robot, y_path −
    //# y_line cos(θ̃_path − θ̃_line), and the heading difference, wrapped
    //# θ̃_path − θ̃_line, are within the configured tolerances in absolute value.
    //= spec/pierre2022.md#sw-plan-ahead-the-line-against-the-path-ahead
    //# When a look-ahead distance d > 0 is configured, a line consistent at the
    //# robot MUST still be inconsistent with the planned path when the offset of
    //# its point d ahead of its point closest to the robot, measured from the
    //# tangent of the path at s + d, exceeds the offset tolerance in absolute value.
    #[must_use]
    pub fn is_consistent(
        &self,
        line: &TrackingError,
        path: &TrackingError,
        ahead: &PathAhead,
    ) -> bool {
        let within = |relative: Result<LineRelativeToPath, Precondition>, heading: bool| {
            relative.is_ok_and(|r| {
                r.offset.abs().get() <= self.max_offset.get()
                    && (!heading || r.heading.abs().get() <= self.max_heading.get())
            })
        };
        within(line_relative_to_path(line, path), true)
            && (ahead.distance.get() <= 0.0
                || within(line_relative_to_path_ahead(line, path, ahead), false))
    }
}
