//! Detectors: one module per detector, each turning a LiDAR scan into a line or
//! parabola in the robot frame and a quality verdict for the switching machine.

pub mod edge;
pub mod furrow;

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
