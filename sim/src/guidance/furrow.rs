//! Furrow pursuing (Pierre 2022, section 2.3): the core's furrow detector on
//! the inclined LiDAR's scans, its row lines fed to the backstepping law, with
//! path tracking standing in while the verdict is Exit or Absent
//! ([`super::specialised`]: the stand-in for switching, the lines carried
//! between scans by odometry, the law).
//!
//! The law uses the furrow's gains (Table 2: 0.8, mapped as k = −g like path
//! tracking) and no predictive layer ("this version of the control law does
//! not include an estimation of sideslip angles or the predictive layer").

use fieldguide::perception::furrow::FurrowDetector;
use fieldguide::Precondition;

use super::specialised::{Detection, Sensing, Specialised};
use super::{Mode, PathTracking, TickInput};
use crate::scenario::setup::FurrowSetup;

/// Most rays of the detector's angular window (a scenario whose window holds
/// more is refused, naming `furrow.window_half_angle_deg`).
pub const FURROW_RAYS: usize = 1024;

/// Most selections the detector keeps (`furrow.averaged_scans` at most this).
pub const FURROW_SCANS: usize = 64;

/// The simulator's furrow detector.
pub type Detector = FurrowDetector<FURROW_RAYS, FURROW_SCANS>;

/// The furrow detector stepped on the inclined LiDAR's scans.
#[derive(Debug, Clone)]
pub struct FurrowSensing {
    detector: Box<Detector>,
}

impl FurrowSensing {
    /// The detector's state.
    #[must_use]
    pub fn detector(&self) -> &Detector {
        &self.detector
    }
}

impl Sensing for FurrowSensing {
    const MODE: Mode = Mode::FurrowPursuing;

    fn sense(&mut self, input: &TickInput<'_>) -> Result<Option<Detection>, Precondition> {
        let Some(scan) = input.scan else {
            return Ok(None);
        };
        let d = self
            .detector
            .step(&scan.as_scan()?, &input.readings.odometry)?;
        Ok(Some(Detection {
            verdict: d.verdict,
            quality: d.quality,
            error: d.error,
            lines: d.lines,
        }))
    }
}

/// Furrow pursuing with path tracking standing in while the detector has no
/// usable line.
pub type FurrowPursuing<'p> = Specialised<'p, FurrowSensing>;

impl<'p> Specialised<'p, FurrowSensing> {
    /// Furrow pursuing as `setup` configures it, with `fallback` in charge
    /// while the verdict is Exit or Absent. Errors with the core's
    /// `FUR-ACCUMULATE` when the configured averaged scans exceed [`FURROW_SCANS`].
    pub fn new(setup: &FurrowSetup, fallback: PathTracking<'p>) -> Result<Self, Precondition> {
        let sensing = FurrowSensing {
            detector: Box::new(Detector::new(setup.detector)?),
        };
        Ok(Self::with_sensing(
            sensing,
            setup.backstepping,
            setup.speed,
            fallback,
        ))
    }

    /// The detector's state.
    #[must_use]
    pub fn detector(&self) -> &Detector {
        self.sensing().detector()
    }
}
