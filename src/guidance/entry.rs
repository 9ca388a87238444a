//! Entries without a swing (`spec/guidance.md`, GD-ENTRY), the mirror of
//! GD-HANDOVER: when the machine enters a behaviour, the behaviour's law
//! does not steer onto its line at once; its lateral reference starts at the
//! robot's error to the line in the tick of the entry, with the robot's
//! heading, and closes on the line smoothly over a closing length λ.
//! Pierre 2022 (section 3) hands the whole error to the furrow law at once:
//! entering rows 0.3 m off the path, the law turns the rear axle onto them
//! within about 1/k_y = 1.25 m, and the front axle, 2 m ahead, swings past
//! the rows' centre over the near row.
//!
//! The reference r(d) after d metres of odometry since the entry is
//! r₀ (1 + d/λ) e^(−d/λ), r₀ the entry's lateral error (the critically damped
//! approach: r'(0) = 0, no overshoot); the law gets the error to that
//! reference, (y − r, θ̃ − atan(dr/dd)). A rear axle that follows it puts the
//! front axle, L ahead, at r + L r' = r₀ e^(−d/λ) (1 + d (λ − L)/λ²): on the
//! entry's side of the line whenever λ ≥ L.

use super::handover::{shifted_error, Active};
use super::{BehaviourStatus, Guidance};
use crate::control::ControlLaw;
use crate::error::Precondition;
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::Meters;
use crate::perception::Detector;
use crate::supervisor::switching::{Mode as MachineMode, Output};

/// How many times the longer of the closing length and the lead after which
/// the entry's reference is zero: there it is at most 21 e^(−20) < 10⁻⁷ of
/// its start.
pub const ENTRY_SPAN: f64 = 20.0;

/// Relative difference below which the closing length and the lead count as
/// equal and the reference takes its limit form (no cancellation).
const COINCIDENT: f64 = 1e-6;

/// The longest closing length or lead, m.
const MAX_LENGTH_M: f64 = 1000.0;

/// The entry rule as a user writes it; [`Entry::new`] validates it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EntryParams {
    /// μ: the closing length of the point `lead` ahead of the rear axle, m,
    /// in (0, 1000]: that point closes on the line as e^(−d/μ).
    pub closing: Meters,
    /// ℓ: how far ahead of the rear axle the point that closes without
    /// overshoot lies, m, in (0, 1000]: the wheelbase, so that the front
    /// axle never swings past the line.
    pub lead: Meters,
}

/// A validated entry rule (GD-ENTRY).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    params: EntryParams,
}

impl Entry {
    /// Validates `params` once.
    ///
    /// # Errors
    /// `GD-ENTRY` when the closing length or the lead is not in (0, 1000] m.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# An entry rule whose closing length or lead is not in (0, 1000] m MUST be
    //# refused with `GD-ENTRY`.
    pub fn new(params: &EntryParams) -> Result<Self, Precondition> {
        let within = |m: Meters| m.get() > 0.0 && m.get() <= MAX_LENGTH_M;
        if !within(params.closing) || !within(params.lead) {
            return Err(Precondition::new(
                "GD-ENTRY",
                "entry closing length and lead must lie in (0, 1000] m",
            ));
        }
        Ok(Self { params: *params })
    }

    /// The validated parameters.
    #[must_use]
    pub const fn params(&self) -> &EntryParams {
        &self.params
    }

    /// The reference r(d) and its change per metre dr/dd, `travelled`
    /// metres after an entry whose lateral error to the line was `start` (a
    /// negative distance counts as 0), with μ the closing length and ℓ the
    /// lead: r₀ (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ), r₀ (1 + d/ℓ) e^(−d/ℓ)
    /// when μ = ℓ, up to [`ENTRY_SPAN`] times the longer of the two, then 0.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# The reference MUST equal the robot's lateral error r₀ to the line when the
    //# entry starts and MUST then close on the line as
    //# r₀ (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ), or r₀ (1 + d/ℓ) e^(−d/ℓ) when μ = ℓ,
    //# d the odometry distance since the entry started, μ the closing length and ℓ
    //# the lead, and MUST be zero once d reaches twenty times the longer of μ and
    //# ℓ.
    #[must_use]
    pub fn reference(&self, start: Meters, travelled: Meters) -> (Meters, f64) {
        let mu = self.params.closing.get();
        let lead = self.params.lead.get();
        let d = travelled.get().max(0.0);
        if d >= ENTRY_SPAN * mu.max(lead) {
            return (Meters::ZERO, 0.0);
        }
        let r0 = start.get();
        // d / μ and d / ℓ lie in [0, 20]: every term is finite.
        let (front, rear) = (libm::exp(-d / mu), libm::exp(-d / lead));
        let (shape, slope) = if (mu - lead).abs() <= COINCIDENT * mu.max(lead) {
            ((1.0 + d / lead) * rear, -d / (lead * lead) * rear)
        } else {
            (
                (mu * front - lead * rear) / (mu - lead),
                (rear - front) / (mu - lead),
            )
        };
        // shape lies in [0, 1]; the rate saturates for an absurd r₀.
        (
            Meters::new(r0 * shape).unwrap_or(Meters::ZERO),
            (r0 * slope).clamp(-f64::MAX, f64::MAX),
        )
    }

    /// The error the behaviour's law gets on its straight line `line`
    /// during an entry: the error to the line shifted by r(d), (y − r,
    /// θ̃ − atan(dr/dd)).
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# During an entry, the behaviour's law MUST get the error to its line
    //# shifted sideways by the reference: the lateral error less the reference,
    //# the angular deviation less the angle of the reference's change per metre
    //# travelled.
    pub fn reference_error(
        &self,
        line: &TrackingError,
        start: Meters,
        travelled: Meters,
    ) -> Result<TrackingError, Precondition> {
        let (r, rate) = self.reference(start, travelled);
        shifted_error(line, r.get(), rate)
    }

    /// Whether the entry that started at `start` is over after `travelled`.
    #[must_use]
    pub fn is_over(&self, start: Meters, travelled: Meters) -> bool {
        self.reference(start, travelled).0.get() == 0.0
    }
}

/// An entry in progress: the behaviour it closes on (its priority index),
/// the reference's start and the odometry distance since.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Entering {
    pub(super) behaviour: usize,
    pub(super) ramp: Active,
}

/// Whether a behaviour's line may be closed on in this tick: a valid
/// estimate, reported so, consistent with the plan.
fn usable(status: &BehaviourStatus) -> bool {
    status.reported.estimate_is_valid() && status.plan_consistent && status.error.is_some()
}

impl<const PATH: usize, D, L, const K: usize> Guidance<'_, PATH, D, L, K>
where
    D: Detector,
    L: ControlLaw + Copy,
    D::Config: Copy,
{
    /// The entry reference of behaviour `index` in this tick, before the
    /// machine steps: the entry in progress when it closes on this
    /// behaviour, none for the active behaviour once its entry is over, and
    /// for any other one starting at the current error `line` (a switch in
    /// this tick commands from it); `None` without a rule.
    pub(super) fn entry_reference(
        &self,
        index: usize,
        line: Option<&TrackingError>,
    ) -> Option<(Entry, Meters, Meters)> {
        let rule = *self.config.entry()?;
        match self.entering {
            Some(e) if e.behaviour == index => Some((rule, e.ramp.start, e.ramp.travelled())),
            _ if self.machine.mode() == MachineMode::Behaviour(index) => None,
            _ => line.map(|e| (rule, e.y, Meters::ZERO)),
        }
    }

    /// The approach in path tracking (GD-ENTRY): while an entry closes on a
    /// behaviour the machine has not entered yet, path tracking's reference
    /// is the path shifted by that line's offset from the path plus r(d),
    /// changing by dr/dd per metre; `None` otherwise.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# While an entry closes on a behaviour the machine has not entered,
    //# path tracking's error MUST be the error to the path shifted sideways by
    //# that behaviour's line offset from the path plus the reference, changing by
    //# the reference's change per metre.
    pub(super) fn approach(&self, behaviours: &[BehaviourStatus]) -> Option<(Meters, f64)> {
        let rule = self.config.entry()?;
        if self.machine.mode() != MachineMode::PathTracking {
            return None;
        }
        let entering = self.entering?;
        let status = behaviours.get(entering.behaviour)?;
        let plan = status.plan.filter(|_| usable(status))?;
        let (r, rate) = rule.reference(entering.ramp.start, entering.ramp.travelled());
        let offset = Meters::new(plan.offset.get() + r.get()).ok()?;
        Some((offset, rate))
    }

    /// After the machine's step: starts, carries on or ends the entry
    /// (GD-ENTRY); `shift` is path tracking's shift in this tick.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# When an entry rule is configured, an entry MUST start from the robot's
    //# lateral error to a behaviour's line in the first tick that line is usable
    //# (a valid estimate consistent with the plan, with an offset from the path)
    //# while path tracking commands, the first usable behaviour in priority order,
    //# ending any hand-over in progress, or in the tick the machine enters a
    //# behaviour no entry closes on; it MUST end when its reference reaches
    //# zero in the behaviour, when the machine leaves the behaviour or stops, when
    //# the line stops being usable before the machine entered (a hand-over then
    //# starts from the shift, when a hand-over rule is configured) or when the
    //# path is replaced.
    pub(super) fn track_entry(
        &mut self,
        before: MachineMode,
        switching: &Output,
        behaviours: &[BehaviourStatus],
        shift: Option<Meters>,
    ) {
        let Some(rule) = self.config.entry().copied() else {
            return;
        };
        match switching.mode {
            MachineMode::Behaviour(i) => match self.entering {
                Some(e) if e.behaviour == i => {
                    if rule.is_over(e.ramp.start, e.ramp.travelled()) {
                        self.entering = None;
                    }
                }
                _ if before == switching.mode => {}
                _ => {
                    self.entering = behaviours.get(i).and_then(|b| b.error).map(|e| Entering {
                        behaviour: i,
                        ramp: Active {
                            start: e.y,
                            travelled: 0.0,
                        },
                    });
                }
            },
            MachineMode::PathTracking => {
                if matches!(before, MachineMode::Behaviour(_)) {
                    self.entering = None;
                } else if let Some(e) = self.entering {
                    if !behaviours.get(e.behaviour).is_some_and(usable) {
                        self.entering = None;
                        if self.config.handover().is_some() {
                            self.handing_over = shift.map(|start| Active {
                                start,
                                travelled: 0.0,
                            });
                        }
                    }
                } else {
                    self.entering = behaviours
                        .iter()
                        .enumerate()
                        .find(|(_, b)| usable(b) && b.plan.is_some())
                        .and_then(|(i, b)| {
                            b.error.map(|e| Entering {
                                behaviour: i,
                                ramp: Active {
                                    start: e.y,
                                    travelled: 0.0,
                                },
                            })
                        });
                    if self.entering.is_some() {
                        self.handing_over = None;
                    }
                }
            }
            MachineMode::Stop => self.entering = None,
        }
    }
}
