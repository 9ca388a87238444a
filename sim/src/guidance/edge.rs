//! Edge following (Pierre 2022, section 2.2): the core's edge detector on the
//! horizontal LiDAR's scans, the line kept at the desired distance from the
//! edge fed to the backstepping law, with path tracking standing in while the
//! verdict is Exit or Absent ([`super::specialised`]: the stand-in for
//! switching, the line carried between scans by odometry, the law).
//!
//! # The line to follow
//!
//! The detector fits the parabola y = a x² + b x + c to the chain (eqs. 8-10)
//! and gives the robot's error to the tangent at x_r = 0 moved by D towards
//! the robot (eq. 11, EDGE-ERRORS, EDGE-OFFSET): y = s·D − c cos φ,
//! θ̃ = −φ, φ = arctan b. That line is `y = b x + c − s·D·sqrt(1 + b²)` in
//! the scan's robot frame (a perpendicular shift of D is a shift of
//! D / cos φ along y), whose error by FUR-ERRORS, −(c − s·D/cos φ) cos φ and
//! −arctan b, is the detector's; between scans it is moved by odometry.
//!
//! # The law
//!
//! Backstepping with the edge's gains and speed (Table 1: 0.4 m/s; the gains
//! are mapped in `sim/scenarios/README.md`, "Edge following"), no sideslip
//! ("this version of the control law does not include an estimation of
//! sideslip angles") and no curvature, the line being straight.

use fieldguide::perception::edge::{EdgeDetector, EdgeFit, Side};
use fieldguide::perception::furrow::lines::RowLine;
use fieldguide::perception::furrow::RowLines;
use fieldguide::{Meters, Precondition, Robot, Sensor, Transform2};

use super::specialised::{Detection, Sensing, Specialised};
use super::{Mode, PathTracking, TickInput};
use crate::scenario::setup::EdgeSetup;

/// Most valid rays of a horizontal scan (a LiDAR with more rays is refused,
/// naming `horizontal_lidar.rays`).
pub const EDGE_RAYS: usize = 2048;

/// Most chain points (`edge.min_points` at most this; a longer chain stops
/// with `ChainEnd::Capacity`).
pub const EDGE_CHAIN: usize = 256;

/// The simulator's edge detector.
pub type Detector = EdgeDetector<EDGE_RAYS, EDGE_CHAIN>;

/// The edge detector run on the horizontal LiDAR's scans, on one side.
#[derive(Debug, Clone)]
pub struct EdgeSensing {
    detector: Box<Detector>,
    side: Side,
}

impl EdgeSensing {
    /// The detector's state (its points and chain are those of the latest scan).
    #[must_use]
    pub fn detector(&self) -> &Detector {
        &self.detector
    }
}

/// The line the robot follows, `y = b x + c − s·D·sqrt(1 + b²)` in the
/// robot frame of the scan (see the module documentation).
pub fn offset_line(fit: &EdgeFit, side: Side, offset: Meters) -> Result<RowLine, Precondition> {
    let slope = fit.parabola.slope_at(0.0)?;
    let value = fit.parabola.value_at(0.0)?;
    let shift = side.sign() * offset.get() * (1.0 + slope * slope).sqrt();
    RowLine::new(slope, Meters::new(value - shift)?)
}

impl Sensing for EdgeSensing {
    const MODE: Mode = Mode::EdgeFollowing;

    fn sense(&mut self, input: &TickInput<'_>) -> Result<Option<Detection>, Precondition> {
        let Some(scan) = input.horizontal else {
            return Ok(None);
        };
        let outcome = self.detector.detect(&scan, self.side)?;
        let offset = self.detector.config().offset();
        let lines = match &outcome.fit {
            Some(fit) => Some(RowLines::One(offset_line(fit, self.side, offset)?)),
            None => None,
        };
        Ok(Some(Detection {
            verdict: outcome.verdict,
            quality: outcome.fit.map(|f| f.quality.residual_std.get()),
            error: outcome.fit.map(|f| f.error),
            lines,
        }))
    }
}

/// Edge following with path tracking standing in while the detector has no
/// usable line.
pub type EdgeFollowing<'p> = Specialised<'p, EdgeSensing>;

impl<'p> Specialised<'p, EdgeSensing> {
    /// Edge following as `setup` configures it, seen by a LiDAR mounted at
    /// `mount`, with `fallback` in charge while the verdict is Exit or Absent.
    #[must_use]
    pub fn new(
        setup: &EdgeSetup,
        mount: Transform2<Sensor, Robot>,
        fallback: PathTracking<'p>,
    ) -> Self {
        let sensing = EdgeSensing {
            detector: Box::new(Detector::new(setup.detector, mount)),
            side: setup.side,
        };
        Self::with_sensing(sensing, setup.backstepping, setup.speed, fallback)
    }

    /// The detector's state.
    #[must_use]
    pub fn detector(&self) -> &Detector {
        self.sensing().detector()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fieldguide::perception::edge::{EdgeQuality, ParabolaFit};
    use fieldguide::perception::furrow::lines::tracking_error;

    #[test]
    fn the_offset_line_gives_the_detectors_error() {
        for (side, a, b, c) in [
            (Side::Left, 0.02, 0.1, 1.3),
            (Side::Right, -0.05, -0.3, -1.6),
            (Side::Left, 0.0, 0.0, 1.4),
        ] {
            let parabola = ParabolaFit { a, b, c };
            let offset = Meters::new(1.4).unwrap();
            let error =
                fieldguide::perception::edge::tracking_error(&parabola, side, offset, 0.0).unwrap();
            let fit = EdgeFit {
                parabola,
                quality: EdgeQuality {
                    length: Meters::new(3.0).unwrap(),
                    width: Meters::new(0.2).unwrap(),
                    residual_std: Meters::new(0.01).unwrap(),
                },
                error,
            };
            let line = offset_line(&fit, side, offset).unwrap();
            let e = tracking_error(&line).unwrap();
            assert!((e.y.get() - error.y.get()).abs() < 1e-12, "{e:?} {error:?}");
            assert!((e.angular_deviation.get() - error.angular_deviation.get()).abs() < 1e-12);
        }
    }
}
