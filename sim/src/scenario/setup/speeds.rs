//! Validates the desired speeds of path tracking per segment (`speed_m_s`
//! on a `[path] segments` entry) into speeds by abscissa on the path.

use fieldguide::MetersPerSecond;

use super::control::{forward_speed, within_schedule, ControlSetup};
use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::reference::Piece;
use crate::scenario::schema::ScenarioFile;
use crate::world::crops::PlotSpec;

/// The desired speed of path tracking along the path: each stretch from the
/// abscissa where it starts, in increasing order; empty when no segment sets
/// a speed (`control.speed_m_s` everywhere).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathSpeeds(Vec<(f64, MetersPerSecond)>);

impl PathSpeeds {
    /// Speeds from the abscissas where they start (metres), increasing.
    #[must_use]
    pub const fn new(stretches: Vec<(f64, MetersPerSecond)>) -> Self {
        Self(stretches)
    }

    /// The stretches: (abscissa where each starts, metres; its speed).
    #[must_use]
    pub fn stretches(&self) -> &[(f64, MetersPerSecond)] {
        &self.0
    }

    /// The speed at abscissa `s_m`: that of the last stretch starting at or
    /// before it (the first one before the first start); `None` when empty.
    #[must_use]
    pub fn at(&self, s_m: f64) -> Option<MetersPerSecond> {
        self.0
            .iter()
            .rev()
            .find(|(from, _)| *from <= s_m)
            .or(self.0.first())
            .map(|(_, v)| *v)
    }
}

/// The speeds of `[path] segments` (their nominal `pieces` projected on the
/// path; `plots` for segments along a plot, which make one or two pieces),
/// each checked as `control.speed_m_s` is: within (0, 20) m/s and accepted
/// by the path-tracking law of `control` (PT-SCHEDULE-RANGE outside
/// `[control.schedule]`). A segment without a speed takes `control.speed_m_s`.
pub(super) fn path_speeds(
    file: &ScenarioFile,
    check: &Checker<'_>,
    control: &ControlSetup,
    pieces: &[Piece],
    plots: &[PlotSpec],
) -> Result<PathSpeeds, ScenarioError> {
    let Some(segments) = &file.path.segments else {
        return Ok(PathSpeeds::default());
    };
    if segments.iter().all(|s| s.speed_m_s.is_none()) {
        return Ok(PathSpeeds::default());
    }
    let mut stretches = Vec::with_capacity(segments.len());
    let mut cursor = 0_usize;
    for (i, segment) in segments.iter().enumerate() {
        let section = format!("path.segments[{i}]");
        let speed = match segment.speed_m_s {
            Some(v) => {
                let speed = forward_speed(check, &section, v)?;
                within_schedule(check, &section, &control.backstepping, speed)?;
                speed
            }
            None => control.speed,
        };
        let Some(piece) = pieces.get(cursor) else {
            return Err(check.error(&section, "has no piece of path"));
        };
        // A segment along a plot away from the previous end starts with a
        // straight join to the plot's start, a piece of its own.
        let pieces_of_segment = match segment.along_plot.and_then(|p| plots.get(p)) {
            Some(plot) => {
                let (x0, y0, _) = plot.centre_line(0.0);
                if piece.start == [x0, y0] {
                    1
                } else {
                    2
                }
            }
            None => 1,
        };
        stretches.push((piece.s_start, speed));
        cursor += pieces_of_segment;
    }
    Ok(PathSpeeds(stretches))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_speed_is_that_of_the_stretch_reached() {
        let v = |x: f64| MetersPerSecond::new(x).unwrap();
        let speeds = PathSpeeds::new(vec![(0.1, v(1.0)), (10.0, v(0.5)), (20.0, v(2.0))]);
        assert_eq!(speeds.at(0.0), Some(v(1.0)));
        assert_eq!(speeds.at(9.99), Some(v(1.0)));
        assert_eq!(speeds.at(10.0), Some(v(0.5)));
        assert_eq!(speeds.at(25.0), Some(v(2.0)));
        assert_eq!(PathSpeeds::default().at(3.0), None);
    }
}
