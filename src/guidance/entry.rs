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
use crate::geometry::units::{Meters, Radians};
use crate::perception::Detector;
use crate::supervisor::switching::LineRelativeToPath;
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

/// The largest |tan| of a line's heading from the path the reference turns
/// through (a line across the path is refused by the plan check long before).
const MAX_TILT: f64 = 1e6;

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

    /// The closing shape s(d) and its change per metre s'(d), `travelled`
    /// metres after the entry (a negative distance counts as 0), with μ the
    /// closing length and ℓ the lead: (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ),
    /// (1 + d/ℓ) e^(−d/ℓ) when μ = ℓ, up to [`ENTRY_SPAN`] times the longer
    /// of the two, then 0. s(0) = 1, s'(0) = 0, s in [0, 1].
    fn shape(&self, travelled: Meters) -> (f64, f64) {
        let mu = self.params.closing.get();
        let lead = self.params.lead.get();
        let d = travelled.get().max(0.0);
        if d >= ENTRY_SPAN * mu.max(lead) {
            return (0.0, 0.0);
        }
        // d / μ and d / ℓ lie in [0, 20]: every term is finite.
        let (front, rear) = (libm::exp(-d / mu), libm::exp(-d / lead));
        if (mu - lead).abs() <= COINCIDENT * mu.max(lead) {
            ((1.0 + d / lead) * rear, -d / (lead * lead) * rear)
        } else {
            (
                (mu * front - lead * rear) / (mu - lead),
                (rear - front) / (mu - lead),
            )
        }
    }

    /// The reference r(d) and its change per metre dr/dd, `travelled`
    /// metres after an entry whose lateral error to the line is `start`
    /// (a negative distance counts as 0): r₀ s(d), s the closing shape
    /// (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ), (1 + d/ℓ) e^(−d/ℓ) when μ = ℓ,
    /// up to [`ENTRY_SPAN`] times the longer of μ and ℓ, then 0.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# The reference MUST equal r₀ s(d), r₀ the start's lateral error to the
    //# line and s(d) = (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ), or (1 + d/ℓ) e^(−d/ℓ)
    //# when μ = ℓ, d the odometry distance since the entry started, μ the closing
    //# length and ℓ the lead, and MUST be zero once d reaches twenty times the
    //# longer of μ and ℓ.
    #[must_use]
    pub fn reference(&self, start: Meters, travelled: Meters) -> (Meters, f64) {
        let (shape, slope) = self.shape(travelled);
        let r0 = start.get();
        // shape lies in [0, 1]; the rate saturates for an absurd r₀.
        (
            Meters::new(r0 * shape).unwrap_or(Meters::ZERO),
            (r0 * slope).clamp(-f64::MAX, f64::MAX),
        )
    }

    /// The reference's change per metre seen from the line and from the
    /// path, when the line's heading minus the path's is `heading` (zero
    /// without a path): the reference is the blend s(d) of the start's track,
    /// parallel to the path, and (1 − s(d)) of the line, so it turns from
    /// the path's heading to the line's as it closes.
    fn rates(&self, start: Meters, travelled: Meters, heading: Radians) -> (f64, f64) {
        let (shape, _) = self.shape(travelled);
        let (_, rate) = self.reference(start, travelled);
        // |tan| saturates where the line stands across the path.
        let tilt = libm::tan(heading.get()).clamp(-MAX_TILT, MAX_TILT);
        (rate - shape * tilt, rate + (1.0 - shape) * tilt)
    }

    /// The error the behaviour's law gets on its straight line `line`
    /// during an entry: the error to the line shifted by r(d), (y − r,
    /// θ̃ − atan(dr/dd)), dr/dd = r₀ s'(d) − s(d) tan h with h = `heading`,
    /// the line's heading minus the path's (zero without a path).
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# During an entry, the behaviour's law MUST get the error to its line
    //# shifted sideways by the reference: the lateral error less the reference,
    //# the angular deviation less the angle of the reference's change per metre
    //# travelled seen from the line, r₀ s'(d) − s(d) tan h, h the line's heading
    //# minus the path's (zero when the path has no projection).
    pub fn reference_error(
        &self,
        line: &TrackingError,
        start: Meters,
        travelled: Meters,
        heading: Radians,
    ) -> Result<TrackingError, Precondition> {
        let (r, _) = self.reference(start, travelled);
        let (rate, _) = self.rates(start, travelled, heading);
        shifted_error(line, r.get(), rate)
    }

    /// Whether the entry from `start` is over after `travelled`: its
    /// closing shape has reached zero (an entry from zero is over at once).
    #[must_use]
    pub fn is_over(&self, start: Meters, travelled: Meters) -> bool {
        start.get() == 0.0 || self.shape(travelled).0 == 0.0
    }
}

/// An entry in progress: the behaviour it closes on (its priority index),
/// the reference's start (the start's lateral error to the line, as last
/// re-evaluated) and the odometry distance since, and the robot's lateral
/// error to the path when it started, when the path had a projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Entering {
    pub(super) behaviour: usize,
    pub(super) ramp: Active,
    pub(super) anchor: Option<Meters>,
}

/// An entry's reference in one tick, before the line is placed on the path:
/// the rule, the start as last evaluated, the anchor and the distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct EntryReference {
    rule: Entry,
    start: Meters,
    anchor: Option<Meters>,
    travelled: Meters,
}

impl EntryReference {
    /// The start's lateral error to the line where the line lies now,
    /// `plan`: the anchor (the robot's error to the path at the start) less
    /// the line's offset from the path, or the start as last evaluated
    /// without both.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# While the path has a projection, r₀ MUST be re-evaluated in every tick
    //# as the robot's lateral error to the path when the entry started less the
    //# line's current offset from the path, so that the reference follows the
    //# line as it is detected again; without a projection r₀ MUST keep its last
    //# value.
    pub(super) fn start(&self, plan: Option<&LineRelativeToPath>) -> Meters {
        match (self.anchor, plan) {
            (Some(anchor), Some(plan)) => {
                Meters::new(anchor.get() - plan.offset.get()).unwrap_or(self.start)
            }
            _ => self.start,
        }
    }

    /// The behaviour law's error on its straight line `line` with the line
    /// placed on the path as `plan` (GD-ENTRY).
    pub(super) fn line_error(
        &self,
        line: &TrackingError,
        plan: Option<&LineRelativeToPath>,
    ) -> Result<TrackingError, Precondition> {
        let heading = plan.map_or(Radians::ZERO, |p| p.heading);
        self.rule
            .reference_error(line, self.start(plan), self.travelled, heading)
    }

    /// Path tracking's shift from the path and its change per metre while
    /// the entry closes on the line placed as `plan`: the line's offset plus
    /// r(d), changing by r₀ s'(d) + (1 − s(d)) tan h.
    fn path_shift(&self, plan: &LineRelativeToPath) -> Option<(Meters, f64)> {
        let start = self.start(Some(plan));
        let (r, _) = self.rule.reference(start, self.travelled);
        let (_, rate) = self.rule.rates(start, self.travelled, plan.heading);
        Some((Meters::new(plan.offset.get() + r.get()).ok()?, rate))
    }
}

/// Whether a behaviour's line may be closed on in this tick: a valid
/// estimate, reported so, consistent with the plan.
fn usable(status: &BehaviourStatus) -> bool {
    status.reported.estimate_is_valid() && status.plan_consistent && status.error.is_some()
}

/// A new entry into behaviour `index` from its status: from its lateral
/// error to the line, anchored at the robot's error to the path when the
/// line has an offset from it.
fn started(index: usize, status: &BehaviourStatus) -> Option<Entering> {
    let e = status.error?;
    Some(Entering {
        behaviour: index,
        ramp: Active {
            start: e.y,
            travelled: 0.0,
        },
        anchor: status
            .plan
            .and_then(|p| Meters::new(p.offset.get() + e.y.get()).ok()),
    })
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
    ) -> Option<EntryReference> {
        let rule = *self.config.entry()?;
        match self.entering {
            Some(e) if e.behaviour == index => Some(EntryReference {
                rule,
                start: e.ramp.start,
                anchor: e.anchor,
                travelled: e.ramp.travelled(),
            }),
            _ if self.machine.mode() == MachineMode::Behaviour(index) => None,
            _ => line.map(|e| EntryReference {
                rule,
                start: e.y,
                anchor: None,
                travelled: Meters::ZERO,
            }),
        }
    }

    /// The approach in path tracking (GD-ENTRY): while an entry closes on a
    /// behaviour the machine has not entered yet, path tracking's reference
    /// is the path shifted by that line's offset from the path plus r(d);
    /// `None` otherwise.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# While an entry closes on a behaviour the machine has not entered,
    //# path tracking's error MUST be the error to the path shifted sideways by
    //# that behaviour's line offset from the path plus the reference, changing by
    //# the reference's change per metre seen from the path,
    //# r₀ s'(d) + (1 − s(d)) tan h.
    pub(super) fn approach(&self, behaviours: &[BehaviourStatus]) -> Option<(Meters, f64)> {
        if self.machine.mode() != MachineMode::PathTracking {
            return None;
        }
        let entering = self.entering?;
        let status = behaviours.get(entering.behaviour)?;
        let plan = status.plan.filter(|_| usable(status))?;
        self.entry_reference(entering.behaviour, None)?
            .path_shift(&plan)
    }

    /// After the machine's step: starts, carries on or ends the entry
    /// (GD-ENTRY); `shift` is path tracking's shift in this tick.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# When an entry rule is configured, an entry MUST start from the robot's
    //# lateral error to a behaviour's line in the first tick that line is usable
    //# (a valid estimate consistent with the plan, with an offset from the path)
    //# while path tracking commands, the first usable behaviour in priority order,
    //# ending any hand-over in progress, or in the tick the machine enters a
    //# behaviour no entry closes on; it MUST end when its closing shape reaches
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
        // The start as evaluated in this tick, kept for ticks without a path.
        if let Some(e) = self.entering.as_mut() {
            if let (Some(anchor), Some(plan)) =
                (e.anchor, behaviours.get(e.behaviour).and_then(|b| b.plan))
            {
                e.ramp.start =
                    Meters::new(anchor.get() - plan.offset.get()).unwrap_or(e.ramp.start);
            }
        }
        match switching.mode {
            MachineMode::Behaviour(i) => match self.entering {
                Some(e) if e.behaviour == i => {
                    if rule.is_over(e.ramp.start, e.ramp.travelled()) {
                        self.entering = None;
                    }
                }
                _ if before == switching.mode => {}
                _ => {
                    self.entering = behaviours.get(i).and_then(|b| started(i, b));
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
                            // No behaviour was left: no line to hold.
                            self.held_line = None;
                        }
                    }
                } else {
                    self.entering = behaviours
                        .iter()
                        .enumerate()
                        .find(|(_, b)| usable(b) && b.plan.is_some())
                        .and_then(|(i, b)| started(i, b));
                    if self.entering.is_some() {
                        self.handing_over = None;
                    }
                }
            }
            MachineMode::Stop => self.entering = None,
        }
    }
}

#[cfg(test)]
mod tests {
    //! The start re-evaluated from the line's offset (GD-ENTRY): the
    //! reference is the blend of the start's track and the line, wherever
    //! the line is detected again.

    use super::*;

    fn m(v: f64) -> Meters {
        Meters::new(v).unwrap_or(Meters::ZERO)
    }

    fn plan(offset: f64, heading: f64) -> LineRelativeToPath {
        LineRelativeToPath {
            offset: m(offset),
            heading: Radians::new(heading).unwrap_or(Radians::ZERO),
        }
    }

    /// The robot 0.05 m right of the path when the entry started, the line
    /// first 0.45 m left of the path, then found 0.3 m left.
    fn reference(travelled: f64) -> Result<EntryReference, Precondition> {
        Ok(EntryReference {
            rule: Entry::new(&EntryParams {
                closing: m(0.5),
                lead: m(2.0),
            })?,
            start: m(-0.5),
            anchor: Some(m(-0.05)),
            travelled: m(travelled),
        })
    }

    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //= type=test
    //# While the path has a projection, r₀ MUST be re-evaluated in every tick
    //# as the robot's lateral error to the path when the entry started less the
    //# line's current offset from the path, so that the reference follows the
    //# line as it is detected again; without a projection r₀ MUST keep its last
    //# value.
    #[test]
    fn the_start_follows_the_line_detected_again() -> Result<(), Precondition> {
        for d in [0.0, 0.7, 2.3, 6.0] {
            let e = reference(d)?;
            assert!((e.start(Some(&plan(0.45, 0.0))).get() + 0.5).abs() < 1e-12);
            assert!((e.start(Some(&plan(0.3, 0.0))).get() + 0.35).abs() < 1e-12);
            // No projection: the last value.
            assert!((e.start(None).get() + 0.5).abs() < 1e-12);
            // Path tracking's reference lies between the start's track
            // (−0.05) and the line, s(d) of the way from the line: the same
            // place wherever the line was first seen.
            let (shape, _) = e.rule.shape(m(d));
            for line in [0.45, 0.3] {
                let (shift, _) = e
                    .path_shift(&plan(line, 0.0))
                    .ok_or(Precondition::new("T", "none"))?;
                let expected = shape * -0.05 + (1.0 - shape) * line;
                assert!((shift.get() - expected).abs() < 1e-12, "{d} {line}");
            }
        }
        Ok(())
    }

    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //= type=test
    //# While an entry closes on a behaviour the machine has not entered,
    //# path tracking's error MUST be the error to the path shifted sideways by
    //# that behaviour's line offset from the path plus the reference, changing by
    //# the reference's change per metre seen from the path,
    //# r₀ s'(d) + (1 − s(d)) tan h.
    #[test]
    fn the_shift_turns_from_the_path_to_the_line() -> Result<(), Precondition> {
        let h = 0.04;
        for d in [0.0, 0.7, 2.3, 6.0, 45.0] {
            let e = reference(d)?;
            let (shape, slope) = e.rule.shape(m(d));
            let (_, rate) = e
                .path_shift(&plan(0.3, h))
                .ok_or(Precondition::new("T", "none"))?;
            let expected = -0.35 * slope + (1.0 - shape) * libm::tan(h);
            assert!((rate - expected).abs() < 1e-12, "{d}");
        }
        // At the start: the path's heading; at the end: the line's.
        let (_, start) = reference(0.0)?
            .path_shift(&plan(0.3, h))
            .ok_or(Precondition::new("T", "none"))?;
        let (_, end) = reference(45.0)?
            .path_shift(&plan(0.3, h))
            .ok_or(Precondition::new("T", "none"))?;
        assert!(start.abs() < 1e-12 && (end - libm::tan(h)).abs() < 1e-12);
        Ok(())
    }
}
