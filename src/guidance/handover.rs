//! Hand-overs without a jolt (`spec/guidance.md`, GD-HANDOVER): when the
//! machine moves from a behaviour to path tracking, path tracking follows the
//! planned path shifted sideways onto the behaviour's last line, holds that
//! shift for a configured distance (the wheels pass the last plant or the end
//! of the hedge the sensor saw), then brings it to zero at a bounded lateral
//! slope. Pierre 2022 (section 3) switches straight back to the path; where
//! the rows or the hedge lie off the path, that steers across them.
//!
//! The shift o(d) after d metres of odometry since the hand-over is o₀ while
//! d ≤ D (the hold distance) and sign(o₀) max(0, |o₀| − k (d − D)) after, k
//! the slope; the error path tracking gets is the error to the path shifted
//! by o: (y − o, θ̃ − atan(do/dd), c / (1 − o c)).

use super::{BehaviourStatus, Guidance};
use crate::control::ControlLaw;
use crate::error::{finite, Precondition};
use crate::geometry::carry::{moved_line_error, pose_in_scan_frame};
use crate::geometry::frame::{Odom, Pose2};
use crate::geometry::path::FrenetError;
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_raw, Curvature, Meters, Radians};
use crate::perception::Detector;
use crate::supervisor::switching::{
    line_relative_to_path, CommandSource, Mode as MachineMode, Output,
};

/// The hand-over rule as a user writes it; [`Handover::new`] validates it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandoverParams {
    /// D: odometry distance after the hand-over during which the shift is
    /// held, m, ≥ 0; at least how far ahead of the rear axle the behaviour's
    /// sensor sees, so that every wheel is past the last plant seen.
    pub hold: Meters,
    /// k: how fast the shift then goes to zero, metres of lateral change per
    /// metre travelled, in (0, 1].
    pub slope: f64,
    /// λ: the line's offset is averaged over the odometry distance with
    /// this length, m, > 0 (the weight of a new offset after Δd metres is
    /// 1 − exp(−Δd / λ)): a single noisy line does not move the reference.
    pub averaging: Meters,
    /// With a length, m, > 0: for that odometry distance after the
    /// hand-over path tracking follows the behaviour's last line carried by
    /// odometry, whatever the fix does, and the shift then starts from that
    /// line's offset (GD-HANDOVER-LINE); `None`: the shifted path at once.
    pub line_hold: Option<Meters>,
}

/// A validated hand-over rule (GD-HANDOVER).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Handover {
    params: HandoverParams,
}

impl Handover {
    /// Validates `params` once.
    ///
    /// # Errors
    /// `GD-HANDOVER` when the hold distance is negative, the averaging
    /// length not positive or the slope not in (0, 1] (NaN included).
    //= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
    //# A hand-over rule whose hold distance is negative, whose averaging length is
    //# not positive or whose slope is not in (0, 1] MUST be refused with
    //# `GD-HANDOVER`.
    pub fn new(params: &HandoverParams) -> Result<Self, Precondition> {
        if params.hold.get() < 0.0 {
            return Err(Precondition::new(
                "GD-HANDOVER",
                "handover hold distance must not be negative",
            ));
        }
        if params.averaging.get() <= 0.0 {
            return Err(Precondition::new(
                "GD-HANDOVER",
                "handover averaging length must be > 0",
            ));
        }
        if !(params.slope > 0.0 && params.slope <= 1.0) {
            return Err(Precondition::new(
                "GD-HANDOVER",
                "handover slope must lie in (0, 1]",
            ));
        }
        //= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
        //# A hand-over rule whose line hold is given and not positive MUST be refused
        //# with `GD-HANDOVER-LINE`.
        if params.line_hold.is_some_and(|l| l.get() <= 0.0) {
            return Err(Precondition::new(
                "GD-HANDOVER-LINE",
                "handover line hold must be > 0",
            ));
        }
        Ok(Self { params: *params })
    }

    /// The validated parameters.
    #[must_use]
    pub const fn params(&self) -> &HandoverParams {
        &self.params
    }

    /// The shift o(d) of the reference from the path, `travelled` metres
    /// after a hand-over that started with shift `start` (a negative
    /// distance counts as 0): `start` during the hold, then its magnitude
    /// less the slope times the distance past the hold, never past zero.
    //= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
    //# The shift MUST equal the line's offset from the path while the odometry
    //# distance since the hand-over is at most the hold distance, and MUST then
    //# shrink toward zero by the slope times the distance past the hold, never
    //# changing sign.
    #[must_use]
    pub fn offset(&self, start: Meters, travelled: Meters) -> Meters {
        shrunk(start, self.params.slope, travelled.get() - self.held())
    }

    /// How far the shift is held: the hold distance, or the line hold when
    /// it is longer (GD-HANDOVER-LINE).
    //= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
    //# With a line hold, the shift MUST be held while the odometry distance since
    //# the hand-over is at most the longer of the hold distance and the line hold.
    fn held(&self) -> f64 {
        self.params.line_hold.map_or(self.params.hold.get(), |l| {
            l.get().max(self.params.hold.get())
        })
    }

    /// The line's averaged offset after a tick that measured `measured`
    /// having travelled `travelled` metres: `previous` moved toward
    /// `measured` by the weight 1 − exp(−Δd / λ), or `measured` without a
    /// previous one (a negative distance counts as 0).
    //= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
    //# The offset MUST be averaged over the odometry distance: each tick the
    //# behaviour commands moves it toward that tick's offset by the weight
    //# 1 − exp(−Δd / λ), Δd the tick's odometry distance and λ the averaging
    //# length; the first such tick after the behaviour was entered sets it.
    #[must_use]
    pub fn averaged(
        &self,
        previous: Option<Meters>,
        measured: Meters,
        travelled: Meters,
    ) -> Meters {
        let Some(previous) = previous else {
            return measured;
        };
        let weight = averaging_weight(travelled.get(), self.params.averaging.get());
        // Both finite; a weight in [0, 1] keeps the result between them.
        let moved = previous.get() + weight * (measured.get() - previous.get());
        Meters::new(moved).unwrap_or(measured)
    }

    /// Whether the shift started at `start` has reached zero after
    /// `travelled` metres: the hand-over is over.
    #[must_use]
    pub fn is_over(&self, start: Meters, travelled: Meters) -> bool {
        self.offset(start, travelled).get() == 0.0
    }

    /// The error to the path shifted by o(d) (the hand-over's reference),
    /// from the error `path` to the path: y − o, θ̃ − atan(do/dd) with
    /// do/dd = −k sign(o₀) while the shift shrinks, the curvatures c / (1 − o c).
    ///
    /// # Errors
    /// `GD-HANDOVER` when 1 − o c ≤ 0 at the projection or ahead (the shift
    /// reaches the path's centre of curvature); `LIB-FINITE` on overflow.
    //= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
    //# During a hand-over, path tracking's error MUST be the error to the path
    //# shifted sideways by the hand-over's shift: the lateral error less the
    //# shift, the angular deviation less the angle of the shift's change per metre
    //# travelled, and the curvatures c / (1 − o c) of the shifted path.
    pub fn reference_error(
        &self,
        path: &TrackingError,
        start: Meters,
        travelled: Meters,
    ) -> Result<TrackingError, Precondition> {
        let o = self.offset(start, travelled).get();
        let shrinking = o != 0.0 && travelled.get() > self.held();
        let rate = if shrinking {
            -libm::copysign(self.params.slope, o)
        } else {
            0.0
        };
        shifted_error(path, o, rate)
    }
}

/// The weight 1 − exp(−Δd / λ) of a new value after `travelled` = Δd metres
/// (none for a negative distance) in an average over the odometry length
/// `length` = λ > 0: GD-HANDOVER's line offset, GD-FIX-FLOAT's correction.
pub(super) fn averaging_weight(travelled: f64, length: f64) -> f64 {
    1.0 - libm::exp(-travelled.max(0.0) / length)
}

/// `start` shrunk toward zero by `slope` times `past` metres (none for a
/// negative distance), never past zero: the shared ramp of GD-HANDOVER and
/// GD-ENTRY. `slope` is a validated one, in (0, 1].
pub(super) fn shrunk(start: Meters, slope: f64, past: f64) -> Meters {
    if past <= 0.0 {
        return start;
    }
    // Both finite, slope ≤ 1: the product is finite.
    let left = start.get().abs() - slope * past;
    if left <= 0.0 {
        Meters::ZERO
    } else {
        Meters::new(libm::copysign(left, start.get())).unwrap_or(Meters::ZERO)
    }
}

/// The error `path` seen from that path shifted sideways by `o` whose shift
/// changes by `rate` metres per metre: (y − o, θ̃ − atan(rate), c / (1 − o c)).
///
/// # Errors
/// `GD-HANDOVER` when 1 − o c ≤ 0 at the projection or ahead; `LIB-FINITE`
/// on overflow.
pub(super) fn shifted_error(
    path: &TrackingError,
    o: f64,
    rate: f64,
) -> Result<TrackingError, Precondition> {
    let y = finite(path.y.get() - o, "handover lateral error overflows")?;
    let theta = wrap_raw(path.angular_deviation.get() - libm::atan(rate));
    let shifted = |c: Curvature| -> Result<Curvature, Precondition> {
        let denominator = finite(1.0 - o * c.get(), "handover curvature overflows")?;
        if denominator <= 0.0 {
            return Err(Precondition::new(
                "GD-HANDOVER",
                "the shifted path passes the path's centre of curvature",
            ));
        }
        Curvature::new(c.get() / denominator)
    };
    Ok(TrackingError {
        y: Meters::new(y)?,
        angular_deviation: Radians::new(theta)?,
        curvature: shifted(path.curvature)?,
        curvature_ahead: shifted(path.curvature_ahead)?,
    })
}

/// A behaviour's line as its last commanding tick saw it: the error to it
/// and the odometry pose of that tick (GD-HANDOVER-LINE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct CarriedLine {
    error: TrackingError,
    odom: Pose2<Odom>,
}

/// A hand-over in progress: the shift it started with and the odometry
/// distance since.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Active {
    pub(super) start: Meters,
    pub(super) travelled: f64,
}

impl Active {
    /// The odometry distance since the hand-over, saturated to a finite value.
    pub(super) fn travelled(&self) -> Meters {
        Meters::new(self.travelled.min(f64::MAX)).unwrap_or(Meters::ZERO)
    }
}

impl<const PATH: usize, D, L, const K: usize> Guidance<'_, PATH, D, L, K>
where
    D: Detector,
    L: ControlLaw + Copy,
    D::Config: Copy,
{
    /// The shift path tracking's reference starts from and the odometry
    /// distance since, in this tick, before the machine steps: in a
    /// behaviour, its line's latest offset (a hand-over in this tick starts
    /// there); after one, the hand-over in progress; `None` without a rule.
    pub(super) fn reference_offset(&self) -> Option<(Meters, Meters)> {
        self.config.handover()?;
        match self.machine.mode() {
            MachineMode::Behaviour(_) => self.line_offset.map(|o| (o, Meters::ZERO)),
            MachineMode::PathTracking | MachineMode::Stop => {
                self.handing_over.map(|a| (a.start, a.travelled()))
            }
        }
    }

    /// Path tracking's error in a tick of a hand-over's line hold
    /// (GD-HANDOVER-LINE): to the behaviour's last line carried by odometry
    /// to `odometry`; the hand-over's start becomes that line's offset from
    /// the path (`frenet`, when there is one). `None` outside a line hold, or
    /// when the line cannot be carried; a line hold past its length ends.
    //= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
    //# While the odometry distance since a hand-over that started on leaving a
    //# behaviour is at most the line hold, path tracking's error MUST be the error
    //# to that behaviour's line in the last tick it commanded, moved to the current
    //# pose through odometry as GD-ODOMETRY moves a straight line, whatever the
    //# fix, unless an entry (GD-ENTRY) shifts the reference.
    //= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
    //# In each such tick in which the path has a projection, the hand-over's shift
    //# MUST be re-evaluated as that carried line's offset from the path.
    pub(super) fn line_hold(
        &mut self,
        frenet: Option<&FrenetError>,
        odometry: &Pose2<Odom>,
    ) -> Option<TrackingError> {
        let length = self.config.handover()?.params().line_hold?;
        if matches!(self.machine.mode(), MachineMode::Behaviour(_)) {
            return None;
        }
        let line = self.held_line?;
        let active = self.handing_over.as_mut()?;
        if active.travelled > length.get() {
            self.held_line = None;
            return None;
        }
        let error = pose_in_scan_frame(&line.odom, odometry)
            .and_then(|pose| moved_line_error(&line.error, &pose))
            .ok()?;
        if let Some(relative) =
            frenet.and_then(|f| line_relative_to_path(&error, &f.tracking_error()).ok())
        {
            active.start = relative.offset;
        }
        Some(error)
    }

    /// The shift o(d) of `reference` (GD-HANDOVER).
    pub(super) fn shift(&self, reference: Option<(Meters, Meters)>) -> Option<Meters> {
        let rule = self.config.handover()?;
        reference.map(|(start, travelled)| rule.offset(start, travelled))
    }

    /// Path tracking's error in this tick: to the path, to the path shifted
    /// by an entry's approach (GD-ENTRY) or by the hand-over (GD-HANDOVER).
    pub(super) fn path_error(
        &self,
        frenet: &FrenetError,
        reference: Option<(Meters, Meters)>,
        approach: Option<(Meters, f64)>,
    ) -> Result<TrackingError, Precondition> {
        if let Some((o, rate)) = approach {
            return shifted_error(&frenet.tracking_error(), o.get(), rate);
        }
        match (self.config.handover(), reference) {
            (Some(rule), Some((start, travelled))) => {
                rule.reference_error(&frenet.tracking_error(), start, travelled)
            }
            _ => Ok(frenet.tracking_error()),
        }
    }

    /// After the machine's step: a behaviour in charge records its line's
    /// offset from the path and ends any hand-over; leaving a behaviour
    /// starts a hand-over from the last offset recorded; a hand-over whose
    /// shift reached zero ends (GD-HANDOVER).
    //= spec/guidance.md#gd-handover-hand-over-to-path-tracking-without-a-jolt
    //# When a hand-over rule is configured and the machine leaves a behaviour, a
    //# hand-over MUST start from the offset from the path of that behaviour's line
    //# in the last tick the behaviour commanded; it MUST end when the shift reaches
    //# zero, when a behaviour is entered or when the path is replaced.
    pub(super) fn track_handover(
        &mut self,
        before: MachineMode,
        switching: &Output,
        behaviours: &[BehaviourStatus],
        travelled: f64,
        odometry: &Pose2<Odom>,
    ) {
        let Some(rule) = self.config.handover().copied() else {
            return;
        };
        match switching.mode {
            MachineMode::Behaviour(i) => {
                self.handing_over = None;
                self.held_line = None;
                let commanding = switching.source == CommandSource::Behaviour(i);
                let status = behaviours.get(i);
                let offset = status.and_then(|b| b.plan).map(|p| p.offset);
                if before != switching.mode {
                    // Another behaviour's line, or none: start afresh.
                    self.line_offset = None;
                    self.last_line = None;
                }
                if let (true, Some(offset)) = (commanding, offset) {
                    let travelled = Meters::new(travelled.min(f64::MAX)).unwrap_or(Meters::ZERO);
                    self.line_offset = Some(rule.averaged(self.line_offset, offset, travelled));
                }
                if let (true, Some(error)) = (commanding, status.and_then(|b| b.error)) {
                    self.last_line = Some(CarriedLine {
                        error,
                        odom: *odometry,
                    });
                }
            }
            MachineMode::PathTracking | MachineMode::Stop => {
                if matches!(before, MachineMode::Behaviour(_)) {
                    self.handing_over = self.line_offset.take().map(|start| Active {
                        start,
                        travelled: 0.0,
                    });
                    self.held_line = self
                        .last_line
                        .take()
                        .filter(|_| self.handing_over.is_some());
                } else if self
                    .handing_over
                    .is_some_and(|a| rule.is_over(a.start, a.travelled()))
                {
                    self.handing_over = None;
                }
            }
        }
    }
}
