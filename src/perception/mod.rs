//! Detectors: one module per detector, each turning a LiDAR scan into a line or
//! parabola in the robot frame and a quality verdict for the switching machine.
//!
//! Every detector implements [`Detector`] (GD-DETECTOR) and reads the same
//! message, [`Scan`] (LIB-SCAN): a horizontal LiDAR's for [`edge`], an
//! inclined one's for [`furrow`] and [`vine`]; [`AnyDetector`] holds any of
//! them in one slot.

pub mod detector;
pub mod edge;
pub mod furrow;
pub mod obstacles;
pub mod rows;
pub mod scan;
pub mod vine;

pub use detector::{AnyDetector, AnyDetectorConfig, AnyLine, Detection, Detector, HeldLine};
pub use scan::{RangeLimits, Scan, MAX_RANGE};

/// A detector's judgement of its own estimate in one tick, as the switching
/// machine consumes it (Pierre 2022, section 3; `spec/pierre2022.md`).
///
/// The thresholds of each detector's quality criteria (eqs. 21 and 22 with
/// Tables 1 and 2) map its continuous quality onto these four values with
/// hysteresis: a quality good enough to *enter* the specialised behaviour,
/// one good enough to *stay* in it, and one bad enough to *leave* it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Verdict {
    /// An estimate exists and meets the entry thresholds.
    Enter,
    /// An estimate exists and is usable, but only meets the thresholds to stay:
    /// between the entry and the exit thresholds.
    Hold,
    /// An estimate exists but fails the exit thresholds: it must not be used.
    Exit,
    /// No estimate at all (nothing detected, or too little data yet).
    Absent,
}

impl Verdict {
    /// Every verdict, for exhaustive checks.
    pub const ALL: [Self; 4] = [Self::Enter, Self::Hold, Self::Exit, Self::Absent];

    /// Whether a command may be made from the estimate this tick (Enter or Hold).
    #[must_use]
    pub const fn estimate_is_valid(self) -> bool {
        matches!(self, Self::Enter | Self::Hold)
    }
}

use crate::error::Precondition;

/// Which way a detector's quality measure improves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Better {
    /// Smaller is better (a residual standard deviation, Pierre 2022 eq. 21).
    Lower,
    /// Larger is better (a correlation score, Pierre 2022 eq. 22).
    Higher,
}

/// Hysteresis thresholds on one continuous quality measure: a stricter one to
/// enter a specialised behaviour and a looser one to leave it (Pierre 2022,
/// section 3 and Tables 1-2: σ_edge = 0.15 m / σ_path = 0.5 m; correlation
/// 0.4 / 0.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QualityThresholds {
    enter: f64,
    exit: f64,
    better: Better,
}

impl QualityThresholds {
    /// Thresholds `enter` and `exit` for a quality that improves as `better` says.
    ///
    /// Errors with `SW-THRESHOLDS` when a threshold is not finite or when the
    /// entry threshold is not strictly stricter than the exit one (for
    /// [`Better::Lower`], `enter < exit`; for [`Better::Higher`], `enter > exit`).
    //= spec/pierre2022.md#sw-thresholds-hysteresis-thresholds-ordered
    //# A detector's entry threshold MUST be strictly stricter than its exit
    //# threshold; a configuration where it is not MUST be refused at construction
    //# with an error naming the requirement.
    pub fn new(enter: f64, exit: f64, better: Better) -> Result<Self, Precondition> {
        let ordered = match better {
            Better::Lower => enter < exit,
            Better::Higher => enter > exit,
        };
        if !enter.is_finite() || !exit.is_finite() {
            Err(Precondition::new(
                "SW-THRESHOLDS",
                "thresholds must be finite",
            ))
        } else if ordered {
            Ok(Self {
                enter,
                exit,
                better,
            })
        } else {
            Err(Precondition::new(
                "SW-THRESHOLDS",
                "entry threshold must be strictly stricter than exit threshold",
            ))
        }
    }

    /// The entry threshold.
    #[must_use]
    pub const fn enter(&self) -> f64 {
        self.enter
    }

    /// The exit threshold.
    #[must_use]
    pub const fn exit(&self) -> f64 {
        self.exit
    }

    /// The verdict for a quality measured on an existing estimate: `Enter` when
    /// strictly better than the entry threshold, `Exit` when strictly worse than
    /// the exit threshold or not a number, `Hold` in between (bounds included).
    /// `Absent` is never returned here: only a detector knows it has no estimate.
    //= spec/pierre2022.md#sw-classify-quality-to-verdict
    //# The verdict of an existing estimate MUST be Enter when its quality is
    //# strictly better than the entry threshold, Exit when it is strictly worse
    //# than the exit threshold or is not a number, and Hold otherwise.
    #[must_use]
    pub fn classify(&self, quality: f64) -> Verdict {
        let (better_than_enter, worse_than_exit) = match self.better {
            Better::Lower => (quality < self.enter, quality > self.exit),
            Better::Higher => (quality > self.enter, quality < self.exit),
        };
        if quality.is_nan() || worse_than_exit {
            Verdict::Exit
        } else if better_than_enter {
            Verdict::Enter
        } else {
            Verdict::Hold
        }
    }
}
