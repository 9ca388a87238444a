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
//! The reference r(d) after d metres of odometry since the entry starts at
//! the robot, r(0) = r₀ its lateral error, along its heading, r'(0) = t₀ the
//! tangent of its heading from the path's; the law gets the error to that
//! reference, (y − r, θ̃ − atan(dr/dd)). A rear axle that follows it puts the
//! point ℓ ahead (the lead: the wheelbase) at r + ℓ r' = (r₀ + ℓ t₀) e^(−d/μ),
//! μ the closing length: that point never passes the line.

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

    /// The closing shapes s(d) and p(d) and their changes per metre,
    /// `travelled` metres after the entry (a negative distance counts as 0),
    /// with μ the closing length and ℓ the lead: s(d) =
    /// (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ) and p(d) =
    /// μ (e^(−d/μ) − e^(−d/ℓ)) / (μ − ℓ), or (1 + d/ℓ) e^(−d/ℓ) and
    /// (d/ℓ) e^(−d/ℓ) when μ = ℓ, up to [`ENTRY_SPAN`] times the longer of the
    /// two, then 0. s(0) = 1, s'(0) = 0, p(0) = 0, p'(0) = 1/ℓ: s + ℓ s' and
    /// p + ℓ p' are e^(−d/μ) and its multiple, so the point ℓ ahead closes as
    /// e^(−d/μ) from wherever the robot's heading puts it.
    fn shape(&self, travelled: Meters) -> Shape {
        let mu = self.params.closing.get();
        let lead = self.params.lead.get();
        let d = travelled.get().max(0.0);
        if d >= ENTRY_SPAN * mu.max(lead) {
            return Shape::default();
        }
        // d / μ and d / ℓ lie in [0, 20]: every term is finite.
        let (front, rear) = (libm::exp(-d / mu), libm::exp(-d / lead));
        if (mu - lead).abs() <= COINCIDENT * mu.max(lead) {
            Shape {
                offset: (1.0 + d / lead) * rear,
                offset_rate: -d / (lead * lead) * rear,
                turn: d * rear,
                turn_rate: (1.0 - d / lead) * rear,
            }
        } else {
            Shape {
                offset: (mu * front - lead * rear) / (mu - lead),
                offset_rate: (rear - front) / (mu - lead),
                turn: lead * mu * (front - rear) / (mu - lead),
                turn_rate: (mu * rear - lead * front) / (mu - lead),
            }
        }
    }

    /// The reference r(d) and its change per metre dr/dd, `travelled`
    /// metres after an entry whose lateral error to the line is `start`,
    /// the robot then parallel to the path (t₀ = 0):
    /// [`Self::reference_with_heading`] with a zero slope.
    #[must_use]
    pub fn reference(&self, start: Meters, travelled: Meters) -> (Meters, f64) {
        self.reference_with_heading(start, 0.0, travelled)
    }

    /// The reference r(d) and its change per metre dr/dd, `travelled`
    /// metres after an entry whose lateral error to the line is `start` (r₀)
    /// and whose heading from the path's had the tangent `slope` (t₀; a
    /// negative distance counts as 0): r₀ s(d) + ℓ t₀ p(d), s and p the
    /// closing shapes, up to [`ENTRY_SPAN`] times the longer of μ and ℓ,
    /// then 0. r(0) = r₀ and r'(0) = t₀: the reference starts at the robot,
    /// along its heading.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# The reference MUST equal r₀ s(d) + ℓ t₀ p(d), r₀ the start's lateral
    //# error to the line, t₀ the tangent of the robot's heading from the path's
    //# when the entry started (from the line's when the path had no projection),
    //# s(d) = (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ) and
    //# p(d) = μ (e^(−d/μ) − e^(−d/ℓ)) / (μ − ℓ), or (1 + d/ℓ) e^(−d/ℓ) and
    //# (d/ℓ) e^(−d/ℓ) when μ = ℓ, d the odometry distance since the entry
    //# started, μ the closing length and ℓ the lead, and MUST be zero once d
    //# reaches twenty times the longer of μ and ℓ.
    #[must_use]
    pub fn reference_with_heading(
        &self,
        start: Meters,
        slope: f64,
        travelled: Meters,
    ) -> (Meters, f64) {
        let shape = self.shape(travelled);
        let r0 = start.get();
        // The shapes are finite; the values saturate for an absurd start.
        let saturated = |v: f64| v.clamp(-f64::MAX, f64::MAX);
        (
            Meters::new(saturated(r0 * shape.offset + slope * shape.turn)).unwrap_or(Meters::ZERO),
            saturated(r0 * shape.offset_rate + slope * shape.turn_rate),
        )
    }

    /// The reference's change per metre seen from the line and from the
    /// path, when the line's heading minus the path's is `heading` (zero
    /// without a path): the reference is the blend s(d) of the start's track
    /// and (1 − s(d)) of the line, so it turns to the line's heading as it
    /// closes.
    fn rates(&self, start: &Start, travelled: Meters, heading: Radians) -> (f64, f64) {
        let shape = self.shape(travelled).offset;
        let (_, rate) = self.reference_with_heading(start.offset, start.slope, travelled);
        // |tan| saturates where the line stands across the path.
        let tilt = slope_of(heading.get());
        (rate - shape * tilt, rate + (1.0 - shape) * tilt)
    }

    /// The error the behaviour's law gets on its straight line `line`
    /// during an entry that started parallel to the path (t₀ = 0): the error
    /// to the line shifted by r(d), (y − r, θ̃ − atan(dr/dd)),
    /// dr/dd = r'(d) − s(d) tan h with h = `heading`, the line's heading
    /// minus the path's (zero without a path).
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    pub fn reference_error(
        &self,
        line: &TrackingError,
        start: Meters,
        travelled: Meters,
        heading: Radians,
    ) -> Result<TrackingError, Precondition> {
        self.error_from(
            line,
            &Start {
                offset: start,
                slope: 0.0,
            },
            travelled,
            heading,
        )
    }

    /// The error to the line shifted by the reference from `start`.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //# During an entry, the behaviour's law MUST get the error to its line
    //# shifted sideways by the reference: the lateral error less the reference,
    //# the angular deviation less the angle of the reference's change per metre
    //# travelled seen from the line, r'(d) − s(d) tan h, h the line's heading
    //# minus the path's (zero when the path has no projection).
    fn error_from(
        &self,
        line: &TrackingError,
        start: &Start,
        travelled: Meters,
        heading: Radians,
    ) -> Result<TrackingError, Precondition> {
        let (r, _) = self.reference_with_heading(start.offset, start.slope, travelled);
        let (rate, _) = self.rates(start, travelled, heading);
        shifted_error(line, r.get(), rate)
    }

    /// Whether the entry from `start` is over after `travelled`: its
    /// closing shape has reached zero (an entry from zero is over at once).
    #[must_use]
    pub fn is_over(&self, start: Meters, travelled: Meters) -> bool {
        self.is_over_from(
            &Start {
                offset: start,
                slope: 0.0,
            },
            travelled,
        )
    }

    /// [`Self::is_over`] for an entry that may start turning.
    fn is_over_from(&self, start: &Start, travelled: Meters) -> bool {
        (start.offset.get() == 0.0 && start.slope == 0.0) || self.shape(travelled).offset == 0.0
    }
}

/// The closing shapes s(d) and s'(d), and ℓ p(d) and ℓ p'(d) (ℓ p'(0) = 1
/// whatever ℓ, where p'(0) alone is 1/ℓ).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Shape {
    offset: f64,
    offset_rate: f64,
    turn: f64,
    turn_rate: f64,
}

/// Where an entry's reference starts: r₀, the lateral error to the line,
/// and t₀, the tangent of the robot's heading from the path's.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Start {
    offset: Meters,
    slope: f64,
}

/// The tangent of a heading from the path's, `deviation` radians (the
/// robot's, or the line's), saturated where it stands across the path.
fn slope_of(deviation: f64) -> f64 {
    libm::tan(deviation).clamp(-MAX_TILT, MAX_TILT)
}

/// An entry in progress: the behaviour it closes on (its priority index),
/// the reference's start (the start's lateral error to the line, as last
/// re-evaluated) and the odometry distance since, the robot's lateral
/// error to the path when it started, when the path had a projection, and
/// the tangent t₀ of its heading from the path's then.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Entering {
    pub(super) behaviour: usize,
    pub(super) ramp: Active,
    pub(super) anchor: Option<Meters>,
    pub(super) slope: f64,
}

/// An entry's reference in one tick, before the line is placed on the path:
/// the rule, the start as last evaluated, the anchor, the distance, and t₀
/// (`None` for an entry starting in this tick: from the line's error).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct EntryReference {
    rule: Entry,
    start: Meters,
    anchor: Option<Meters>,
    travelled: Meters,
    slope: Option<f64>,
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

    /// The whole start where the line lies now: r₀ as [`Self::start`], and
    /// t₀ as kept, or for an entry starting in this tick from the robot's
    /// heading from the path, the line's angular deviation plus h.
    fn whole_start(
        &self,
        line: Option<&TrackingError>,
        plan: Option<&LineRelativeToPath>,
    ) -> Start {
        let slope = self
            .slope
            .unwrap_or_else(|| line.map_or(0.0, |l| slope_of(deviation_from_path(l, plan))));
        Start {
            offset: self.start(plan),
            slope,
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
        self.rule.error_from(
            line,
            &self.whole_start(Some(line), plan),
            self.travelled,
            heading,
        )
    }

    /// Path tracking's shift from the path and its change per metre while
    /// the entry closes on the line placed as `plan`: the line's offset plus
    /// r(d), changing by r'(d) + (1 − s(d)) tan h.
    fn path_shift(&self, plan: &LineRelativeToPath) -> Option<(Meters, f64)> {
        let start = self.whole_start(None, Some(plan));
        let (r, _) = self
            .rule
            .reference_with_heading(start.offset, start.slope, self.travelled);
        let (_, rate) = self.rule.rates(&start, self.travelled, plan.heading);
        Some((Meters::new(plan.offset.get() + r.get()).ok()?, rate))
    }
}

/// Whether a behaviour's line may be closed on in this tick: a valid
/// estimate, reported so, consistent with the plan.
fn usable(status: &BehaviourStatus) -> bool {
    status.reported.estimate_is_valid() && status.plan_consistent && status.error.is_some()
}

/// The robot's heading from the path's, radians: the angular deviation
/// from the line plus the line's heading from the path's, or the deviation
/// from the line alone without a projection.
fn deviation_from_path(line: &TrackingError, plan: Option<&LineRelativeToPath>) -> f64 {
    line.angular_deviation.get() + plan.map_or(0.0, |p| p.heading.get())
}

/// A new entry into behaviour `index` from its status: from its lateral
/// error to the line, anchored at the robot's error to the path when the
/// line has an offset from it, along the robot's heading.
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
        slope: slope_of(deviation_from_path(&e, status.plan.as_ref())),
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
                slope: Some(e.slope),
            }),
            _ if self.machine.mode() == MachineMode::Behaviour(index) => None,
            _ => line.map(|e| EntryReference {
                rule,
                start: e.y,
                anchor: None,
                travelled: Meters::ZERO,
                slope: None,
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
    //# r'(d) + (1 − s(d)) tan h.
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
                    let start = Start {
                        offset: e.ramp.start,
                        slope: e.slope,
                    };
                    if rule.is_over_from(&start, e.ramp.travelled()) {
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
            slope: Some(0.0),
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
            let shape = e.rule.shape(m(d)).offset;
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
    //# r'(d) + (1 − s(d)) tan h.
    #[test]
    fn the_shift_turns_from_the_path_to_the_line() -> Result<(), Precondition> {
        let h = 0.04;
        for d in [0.0, 0.7, 2.3, 6.0, 45.0] {
            let e = reference(d)?;
            let Shape {
                offset: shape,
                offset_rate: slope,
                ..
            } = e.rule.shape(m(d));
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

    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //= type=test
    //# The reference MUST equal r₀ s(d) + ℓ t₀ p(d), r₀ the start's lateral
    //# error to the line, t₀ the tangent of the robot's heading from the path's
    //# when the entry started (from the line's when the path had no projection),
    #[test]
    fn an_entry_starts_along_the_robots_heading() -> Result<(), Precondition> {
        // The robot 0.02 rad off the line, the line 0.04 rad off the path:
        // 0.06 rad off the path, turning back to it.
        let line = TrackingError::to_straight_line(m(-0.5), Radians::new(0.02)?);
        let fresh = EntryReference {
            slope: None,
            ..reference(0.0)?
        };
        let with_path = fresh.whole_start(Some(&line), Some(&plan(0.45, 0.04)));
        assert!((with_path.slope - libm::tan(0.06)).abs() < 1e-12);
        let without = fresh.whole_start(Some(&line), None);
        assert!((without.slope - libm::tan(0.02)).abs() < 1e-12);
        // The law sees the robot on its reference, along it: no jump.
        let error = fresh.line_error(&line, Some(&plan(0.45, 0.04)))?;
        assert!(error.y.get().abs() < 1e-12);
        assert!(error.angular_deviation.get().abs() < 1e-3);
        // Once started, t₀ is kept whatever the line's deviation now.
        let kept = EntryReference {
            slope: Some(0.1),
            ..reference(0.0)?
        };
        assert!((kept.whole_start(Some(&line), None).slope - 0.1).abs() < 1e-12);
        Ok(())
    }
}
