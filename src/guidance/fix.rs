//! A GNSS fix with its quality (`spec/guidance.md`, GD-FIX-QUALITY): the
//! kind a receiver reports (NMEA GGA quality 4 / 5 / 1 / 6, UBX `carrSoln`)
//! and its horizontal accuracy σ (UBX `hAcc`, GST), judged against a
//! configured rule. A fix the rule refuses counts as no fix: the plan check
//! carries the last good fix by odometry (GD-PLAN-DEAD-RECKONING) and path
//! tracking, with a carry distance configured, steers on that carried pose,
//! then stops with the reason named; when a good fix returns, the step
//! between the carried pose and it is taken up at a bounded slope. With a
//! float averaging length, a refused RTK float fix corrects the carried
//! pose: its offset from it is averaged over the first metres of float, and
//! path tracking then steers on the float fix less that offset
//! (GD-FIX-FLOAT).
//!
//! Pierre 2022 assumes an RTK-fixed pose; a float fix 0.3-1 m off or a
//! single-point one would steer path tracking beside the path by that much.

use super::handover::{averaging_weight, shifted_error, Active};
use super::Guidance;
use crate::control::ControlLaw;
use crate::error::Precondition;
use crate::geometry::frame::{Odom, Pose2, World};
use crate::geometry::path::FrenetError;
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::{wrap_raw, Meters};
use crate::perception::Detector;

/// The kind of a fix, from best to worst.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FixKind {
    /// RTK with the carrier ambiguities fixed (GGA quality 4): centimetres.
    RtkFixed,
    /// RTK float (GGA quality 5): decimetres, jumps when the ambiguities move.
    RtkFloat,
    /// Single point or differential code (GGA quality 1 or 2): metres.
    Single,
    /// The receiver's own dead reckoning (GGA quality 6): no satellite fix.
    DeadReckoned,
}

/// What a receiver says of one fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixQuality {
    /// The fix's kind.
    pub kind: FixKind,
    /// The horizontal accuracy σ the receiver claims, m; `None` when it
    /// gives none (only the kind is judged). A negative σ is no accuracy
    /// the rule can accept.
    pub accuracy: Option<Meters>,
}

impl FixQuality {
    /// An RTK-fixed fix without an accuracy figure: the quality
    /// [`super::Guidance::step`] assumes (the behaviour before qualities).
    pub const RTK_FIXED: Self = Self {
        kind: FixKind::RtkFixed,
        accuracy: None,
    };
}

/// The rule a fix is judged by, as a user writes it; [`FixRule::new`]
/// validates it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixRuleParams {
    /// The worst kind accepted (`RtkFixed` between crop rows).
    pub worst_kind: FixKind,
    /// The largest horizontal σ accepted, m, > 0.
    pub max_accuracy: Meters,
    /// How far path tracking goes on the last good fix carried by odometry,
    /// m, ≥ 0 (0: path tracking stops commanding at once without a good
    /// fix); beyond it localisation is lost and the machine stops (SW-STOP).
    pub path_dead_reckoning: Meters,
    /// How fast the step between the carried pose and a returning good fix
    /// is taken up, metres of lateral change per metre travelled, in (0, 1].
    pub rejoin_slope: f64,
    /// The largest curvature of that take-up's shift, 1/m, > 0 (+∞: the
    /// slope alone bounds it): a small step taken up at the slope alone
    /// would bend the reference more sharply than the steering can follow.
    pub rejoin_curvature: f64,
    /// λ: with a length, a refused RTK float fix corrects the carried pose
    /// (GD-FIX-FLOAT): its offset from the carried pose is averaged over the
    /// first λ metres of float, m, > 0, and its changes thereafter, smoothed
    /// twice over λ metres, move the carried pose; `None`: the carried pose
    /// alone.
    pub float_averaging: Option<Meters>,
}

/// A validated fix rule (GD-FIX-QUALITY).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixRule {
    params: FixRuleParams,
}

impl FixRule {
    /// Validates `params` once.
    ///
    /// # Errors
    /// `GD-FIX-QUALITY` when the largest σ is not positive, the carry
    /// distance negative, the rejoin slope outside (0, 1] or the rejoin
    /// curvature not positive (NaN included).
    //= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
    //# A fix rule whose largest accuracy is not positive, whose path
    //# dead-reckoning distance is negative, whose rejoin slope is not in (0, 1]
    //# or whose rejoin curvature is not positive MUST be refused with
    //# `GD-FIX-QUALITY`.
    pub fn new(params: &FixRuleParams) -> Result<Self, Precondition> {
        if params.max_accuracy.get() <= 0.0 {
            return Err(Precondition::new(
                "GD-FIX-QUALITY",
                "fix max_accuracy must be > 0",
            ));
        }
        if params.path_dead_reckoning.get() < 0.0 {
            return Err(Precondition::new(
                "GD-FIX-QUALITY",
                "fix path_dead_reckoning must not be negative",
            ));
        }
        if !(params.rejoin_slope > 0.0 && params.rejoin_slope <= 1.0) {
            return Err(Precondition::new(
                "GD-FIX-QUALITY",
                "fix rejoin_slope must lie in (0, 1]",
            ));
        }
        if params.rejoin_curvature.is_nan() || params.rejoin_curvature <= 0.0 {
            return Err(Precondition::new(
                "GD-FIX-QUALITY",
                "fix rejoin_curvature must be > 0",
            ));
        }
        //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
        //# A fix rule whose float averaging length is given and not positive MUST be
        //# refused with `GD-FIX-FLOAT`.
        if params.float_averaging.is_some_and(|l| l.get() <= 0.0) {
            return Err(Precondition::new(
                "GD-FIX-FLOAT",
                "fix float_averaging must be > 0",
            ));
        }
        Ok(Self { params: *params })
    }

    /// The validated parameters.
    #[must_use]
    pub const fn params(&self) -> &FixRuleParams {
        &self.params
    }

    /// Whether a fix of `quality` is good enough: its kind at most the worst
    /// accepted and its σ, when given, in [0, largest σ].
    //= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
    //# A fix MUST be good exactly when its kind is at most the rule's worst kind
    //# (RTK fixed, then float, single, dead-reckoned) and its horizontal accuracy,
    //# when the receiver gives one, is at least zero and at most the rule's largest
    //# accuracy.
    #[must_use]
    pub fn accepts(&self, quality: &FixQuality) -> bool {
        quality.kind <= self.params.worst_kind
            && quality
                .accuracy
                .is_none_or(|s| s.get() >= 0.0 && s.get() <= self.params.max_accuracy.get())
    }

    /// The pose a tick's GNSS pose `gnss` of `quality` gives the core: the
    /// pose when the fix is good, `None` otherwise.
    #[must_use]
    pub fn filter(&self, gnss: Option<Pose2<World>>, quality: &FixQuality) -> Option<Pose2<World>> {
        gnss.filter(|_| self.accepts(quality))
    }

    /// The shift o(d) of path tracking's reference `travelled` metres after
    /// a good fix returned with the step `start` (the fix's lateral error
    /// less the carried pose's): o₀ (1 − S(d / D)), S(u) = 3u² − 2u³ the
    /// smoothstep, D = max(1.5 |o₀| / k, √(6 |o₀| / κ)), so that its rate
    /// starts and ends at zero and never exceeds the rejoin slope k, and its
    /// curvature (at most 6 |o₀| / D²) never exceeds the rejoin curvature κ;
    /// zero from D on (a negative distance counts as 0).
    #[must_use]
    pub fn rejoin_offset(&self, start: Meters, travelled: Meters) -> Meters {
        let (o, _) = self.rejoin_shape(start, travelled);
        o
    }

    /// The shift o(d) of [`FixRule::rejoin_offset`] and its rate do/dd.
    fn rejoin_shape(&self, start: Meters, travelled: Meters) -> (Meters, f64) {
        let o0 = start.get();
        // 1.5 |o0| / k: finite (k ≥ a positive f64, |o0| finite) unless o0
        // is beyond f64::MAX / 1.5 · k; an overflow ends the rejoin. The
        // curvature's bound √(6 |o0| / κ) is finite for κ > 0 but tiny, 0
        // for κ = +∞.
        let length = (1.5 * libm::fabs(o0) / self.params.rejoin_slope).max(libm::sqrt(
            6.0 * libm::fabs(o0) / self.params.rejoin_curvature,
        ));
        let d = travelled.get().max(0.0);
        if !(length.is_finite() && length > 0.0) || d >= length {
            return (Meters::ZERO, 0.0);
        }
        let u = d / length;
        let o = o0 * (1.0 - u * u * (3.0 - 2.0 * u));
        let rate = -o0 * 6.0 * u * (1.0 - u) / length;
        (Meters::new(o).unwrap_or(Meters::ZERO), rate)
    }

    /// Path tracking's error `path` (to the path, from the good fix) seen
    /// from the path shifted by the rejoin's shift o(d) of
    /// [`FixRule::rejoin_offset`]: y − o, θ̃ − atan(do/dd), c / (1 − o c).
    ///
    /// # Errors
    /// `GD-HANDOVER` when the shifted path passes the path's centre of
    /// curvature, `LIB-FINITE` on overflow.
    //= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
    //# When a good fix returns after ticks in which path tracking steered on the
    //# carried pose, path tracking's error MUST be the error to the path shifted
    //# sideways by o₀ (1 − S(d / D)), o₀ the fix's lateral error less the lateral
    //# error of the last carried pose, d the odometry distance since, S(u) = 3u² −
    //# 2u³ and D = max(1.5 |o₀| / k, √(6 |o₀| / κ)) with k the rejoin slope and κ
    //# the rejoin curvature (zero from D on), the angular deviation less atan of
    //# that shift's rate, in every tick in which no entry (GD-ENTRY) or hand-over
    //# (GD-HANDOVER) shifts the reference.
    pub fn rejoin_error(
        &self,
        path: &TrackingError,
        start: Meters,
        travelled: Meters,
    ) -> Result<TrackingError, Precondition> {
        let (o, rate) = self.rejoin_shape(start, travelled);
        shifted_error(path, o.get(), rate)
    }
}

/// What path tracking steered on in a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FixUse {
    /// The tick's fix (a good one, or any without a rule configured).
    Fix,
    /// No fix in the tick and no rule configured: nothing to steer on
    /// (GD-LOCALISATION).
    NoFix,
    /// No good fix: the last good fix carried `travelled` metres by odometry.
    Carried {
        /// Odometry distance since the last good fix.
        travelled: Meters,
    },
    /// No good fix: the last good fix carried `travelled` metres by
    /// odometry and moved by the float fix's correction (GD-FIX-FLOAT).
    Float {
        /// Odometry distance since the last good fix.
        travelled: Meters,
    },
    /// No good fix and none to carry: no good fix yet, or farther than the
    /// path dead-reckoning distance; the reason names GD-FIX-QUALITY.
    Lost(Precondition),
}

/// A rejoin in progress: the shift it started with and the odometry
/// distance since (the hand-over's record, GD-HANDOVER).
pub(super) type Rejoin = Active;

/// A pose less another, world frame: east, north and heading (wrapped).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Offset {
    x: f64,
    y: f64,
    heading: f64,
}

impl Offset {
    /// `a` less `b`; `None` on overflow.
    fn between(a: &Pose2<World>, b: &Pose2<World>) -> Option<Self> {
        let o = Self {
            x: a.position.x() - b.position.x(),
            y: a.position.y() - b.position.y(),
            heading: wrap_raw(a.heading.get() - b.heading.get()),
        };
        (o.x.is_finite() && o.y.is_finite()).then_some(o)
    }

    /// `pose` moved by this offset.
    ///
    /// # Errors
    /// `LIB-FINITE` on overflow.
    pub(super) fn applied(&self, pose: &Pose2<World>) -> Result<Pose2<World>, Precondition> {
        Pose2::new(
            pose.position.x() + self.x,
            pose.position.y() + self.y,
            pose.heading.get() + self.heading,
        )
    }

    /// `self + k (other − self)` per component, the heading's difference wrapped.
    fn toward(&self, other: &Self, k: f64) -> Self {
        Self {
            x: self.x + k * (other.x - self.x),
            y: self.y + k * (other.y - self.y),
            heading: wrap_raw(self.heading + k * wrap_raw(other.heading - self.heading)),
        }
    }
}

/// The float span since the last good fix (GD-FIX-FLOAT): the float fix's
/// offset from the carried pose averaged over the span's first λ metres
/// (r), then the correction m − r smoothed twice over the odometry distance
/// λ, 2a − b (Brown's linear exponential smoothing): it follows a drift
/// growing steadily with distance without the lag λ of one average.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct FloatSpan {
    /// Odometry distance of the float ticks averaged so far, m.
    averaged: f64,
    /// The mean offset of those ticks, weighted by their distance.
    mean: Offset,
    /// r, once the float ticks have covered λ metres.
    bias: Option<Offset>,
    /// a: m − r averaged over λ metres of float ticks; zero until r is set.
    level: Offset,
    /// b: a averaged over λ metres of float ticks; zero until r is set.
    smoothed: Offset,
}

impl FloatSpan {
    /// The span after a float tick that measured the offset `m` having
    /// travelled `travelled` metres, with the averaging length `length`.
    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //# The offset r MUST be the mean of the float fix's offset from the carried
    //# pose (east, north and heading) over the span's float ticks, each weighted
    //# by its odometry distance, until those ticks cover the averaging length λ;
    //# from then on r MUST stay.
    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //# The averages a and b MUST be zero when r is set, and each later float tick
    //# MUST move a toward m − r, then b toward that moved a, both by the weight 1 −
    //# exp(−Δd / λ), m the tick's float fix offset from the carried pose and Δd
    //# the tick's odometry distance, unless m − r, a, b or 2a − b would then
    //# overflow: such a tick MUST leave a and b as they are.
    fn record(&mut self, m: &Offset, travelled: f64, length: f64) {
        let d = travelled.max(0.0);
        match self.bias {
            Some(r) => {
                let target = Offset {
                    x: m.x - r.x,
                    y: m.y - r.y,
                    heading: wrap_raw(m.heading - r.heading),
                };
                let weight = averaging_weight(d, length);
                let level = self.level.toward(&target, weight);
                let smoothed = self.smoothed.toward(&level, weight);
                let correction = level.toward(&smoothed, -1.0);
                if [target, level, smoothed, correction]
                    .iter()
                    .all(|o| o.x.is_finite() && o.y.is_finite())
                {
                    self.level = level;
                    self.smoothed = smoothed;
                }
            }
            None => {
                self.averaged += d;
                // The first tick sets the mean; later ones weigh d / total.
                let weight = if self.averaged > 0.0 {
                    d / self.averaged
                } else {
                    1.0
                };
                self.mean = self.mean.toward(m, weight);
                if self.averaged >= length {
                    self.bias = Some(self.mean);
                }
            }
        }
    }

    /// The correction 2a − b, once r is set: a extrapolated by its lag
    /// behind b, which is a's lag behind m − r on a steady drift.
    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //# The span's correction MUST be 2a − b (the heading's difference wrapped),
    //# and its east and north MUST each be at most three times the largest
    //# magnitude of that component of m − r over the span's float ticks.
    fn correction(&self) -> Option<Offset> {
        self.bias.map(|_| self.level.toward(&self.smoothed, -1.0))
    }
}

impl<const PATH: usize, D, L, const K: usize> Guidance<'_, PATH, D, L, K>
where
    D: Detector,
    L: ControlLaw + Copy,
    D::Config: Copy,
{
    /// What path tracking steers on in a tick whose good fix (if
    /// `good_fix`) projected as `frenet`: that projection; without a good
    /// fix and with a rule, the last good fix carried by odometry within the
    /// path dead-reckoning distance, moved by the float correction
    /// (GD-FIX-FLOAT) once there is one, or nothing and why.
    //= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
    //# With a fix rule, in a tick without a good fix, path tracking MUST steer on
    //# the pose of the last good fix moved by odometry, as GD-PLAN-DEAD-RECKONING
    //# moves it, while the odometry distance since that fix is at most the rule's
    //# path dead-reckoning distance; beyond it, and before the first good fix,
    //# localisation MUST be invalid, with the reason named (`GD-FIX-QUALITY`).
    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //# From the tick r is set until the span ends, in every tick in which
    //# GD-FIX-QUALITY has path tracking steer on the carried pose, path tracking
    //# MUST steer on the carried pose moved by the span's correction instead (east,
    //# north and heading added).
    pub(super) fn path_pose(
        &self,
        frenet: Option<FrenetError>,
        good_fix: bool,
        odometry: &Pose2<Odom>,
    ) -> (Option<FrenetError>, FixUse) {
        let Some(rule) = self.config.fix() else {
            let used = if good_fix { FixUse::Fix } else { FixUse::NoFix };
            return (frenet, used);
        };
        if good_fix {
            return (frenet, FixUse::Fix);
        }
        let correction = self.floating.and_then(|f| f.correction());
        let limit = rule.params().path_dead_reckoning;
        match self.carried(odometry, limit, correction) {
            Ok((travelled, carried)) => {
                let used = if correction.is_some() {
                    FixUse::Float { travelled }
                } else {
                    FixUse::Carried { travelled }
                };
                (Some(carried), used)
            }
            Err(reason) => (None, FixUse::Lost(reason)),
        }
    }

    /// Records the tick's fix `gnss` of `quality` in the float span
    /// (GD-FIX-FLOAT), `travelled` metres after the previous tick: a good
    /// fix ends the span; a refused RTK float fix, with the carried pose
    /// within the path dead-reckoning distance, adds its offset from that
    /// pose; any other tick leaves the span as it is.
    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //# With a float averaging length configured, a float span MUST start at the
    //# first tick after a good fix whose fix the rule refuses and whose kind is RTK
    //# float, and MUST end at the next good fix; only ticks with such a fix and a
    //# carried pose (GD-FIX-QUALITY) are its float ticks.
    pub(super) fn track_float(
        &mut self,
        gnss: Option<&Pose2<World>>,
        quality: &FixQuality,
        good_fix: bool,
        odometry: &Pose2<Odom>,
        travelled: f64,
    ) {
        let Some(rule) = self.config.fix() else {
            return;
        };
        let Some(length) = rule.params().float_averaging else {
            return;
        };
        if good_fix {
            self.floating = None;
            return;
        }
        let Some(fix) = gnss.filter(|_| quality.kind == FixKind::RtkFloat) else {
            return;
        };
        let limit = rule.params().path_dead_reckoning;
        let offset = self
            .carried_pose(odometry, limit)
            .ok()
            .and_then(|(_, carried)| Offset::between(fix, &carried));
        if let Some(m) = offset {
            self.floating
                .get_or_insert_default()
                .record(&m, travelled, length.get());
        }
    }

    /// The rejoin of this tick, after `travelled` metres of odometry: a
    /// carried tick records its lateral error; the first good fix after
    /// one starts a rejoin from the step between them; a rejoin whose shift
    /// reached zero ends.
    pub(super) fn rejoin(
        &mut self,
        frenet: Option<&FrenetError>,
        used: &FixUse,
        travelled: f64,
    ) -> Option<Rejoin> {
        let rule = *self.config.fix()?;
        if let Some(r) = self.rejoining.as_mut() {
            r.travelled += travelled;
        }
        match (used, frenet) {
            (FixUse::Carried { .. } | FixUse::Float { .. }, Some(f)) => {
                self.carried_y = Some(f.y);
                self.rejoining = None;
            }
            (FixUse::Fix, Some(f)) => {
                if let Some(before) = self.carried_y.take() {
                    // Both finite lateral errors; a step that overflows starts nothing.
                    self.rejoining =
                        Meters::new(f.y.get() - before.get())
                            .ok()
                            .map(|start| Rejoin {
                                start,
                                travelled: 0.0,
                            });
                }
            }
            _ => {}
        }
        if self
            .rejoining
            .is_some_and(|r| rule.rejoin_offset(r.start, r.travelled()).get() == 0.0)
        {
            self.rejoining = None;
        }
        self.rejoining
    }

    /// Path tracking's error on `frenet`: to the path shifted by the rejoin
    /// in progress, else as GD-ENTRY and GD-HANDOVER give it.
    pub(super) fn rejoined_error(
        &self,
        frenet: &FrenetError,
        rejoin: Option<Rejoin>,
        reference: Option<(Meters, Meters)>,
        approach: Option<(Meters, f64)>,
    ) -> Result<TrackingError, Precondition> {
        match (self.config.fix(), rejoin) {
            (Some(rule), Some(r)) => {
                rule.rejoin_error(&frenet.tracking_error(), r.start, r.travelled())
            }
            _ => self.path_error(frenet, reference, approach),
        }
    }

    /// The shift of the rejoin `rejoin`, if one is in progress.
    pub(super) fn rejoin_shift(&self, rejoin: Option<Rejoin>) -> Option<Meters> {
        let rule = self.config.fix()?;
        rejoin.map(|r| rule.rejoin_offset(r.start, r.travelled()))
    }
}

#[cfg(test)]
mod tests {
    //! The rejoin's smoothstep (GD-FIX-QUALITY): it starts at the step with
    //! a zero rate, ends at zero with a zero rate at D = 1.5 |o₀| / k, and
    //! its rate peaks at the slope k halfway.

    use super::*;

    fn rule(slope: f64) -> Result<FixRule, Precondition> {
        FixRule::new(&FixRuleParams {
            worst_kind: FixKind::RtkFixed,
            max_accuracy: Meters::new(0.05)?,
            path_dead_reckoning: Meters::new(10.0)?,
            rejoin_slope: slope,
            rejoin_curvature: f64::INFINITY,
            float_averaging: None,
        })
    }

    fn offset(x: f64, y: f64, heading: f64) -> Offset {
        Offset { x, y, heading }
    }

    fn close(a: &Offset, b: &Offset) -> bool {
        libm::fabs(a.x - b.x) < 1e-12
            && libm::fabs(a.y - b.y) < 1e-12
            && libm::fabs(wrap_raw(a.heading - b.heading)) < 1e-12
    }

    /// The span's correction, zero before r is set.
    fn corrected(span: &FloatSpan) -> Offset {
        span.correction().unwrap_or_default()
    }

    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //= type=test
    //# The offset r MUST be the mean of the float fix's offset from the carried
    //# pose (east, north and heading) over the span's float ticks, each weighted
    //# by its odometry distance, until those ticks cover the averaging length λ;
    //# from then on r MUST stay.
    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //= type=test
    //# The averages a and b MUST be zero when r is set, and each later float tick
    //# MUST move a toward m − r, then b toward that moved a, both by the weight 1 −
    //# exp(−Δd / λ), m the tick's float fix offset from the carried pose and Δd
    //# the tick's odometry distance, unless m − r, a, b or 2a − b would then
    //# overflow: such a tick MUST leave a and b as they are.
    #[test]
    fn the_float_offset_is_a_distance_weighted_mean_then_the_correction_smoothed_twice() {
        let mut span = FloatSpan::default();
        // A tick at standstill weighs nothing; the others by their distance.
        span.record(&offset(9.0, 9.0, 0.5), 0.0, 2.0);
        span.record(&offset(0.4, -0.2, 0.01), 0.5, 2.0);
        span.record(&offset(0.6, 0.2, 0.03), 1.0, 2.0);
        assert!(span.bias.is_none() && span.correction().is_none());
        // Covering λ = 2 m sets r: (0.5·m₁ + 1·m₂ + 0.5·m₃) / 2.
        span.record(&offset(0.2, 0.0, -0.01), 0.5, 2.0);
        let r = offset(0.45, 0.05, 0.015);
        assert!(span.bias.is_some_and(|b| close(&b, &r)), "{span:?}");
        assert!(close(&span.level, &Offset::default()));
        assert!(close(&span.smoothed, &Offset::default()));
        assert!(span
            .correction()
            .is_some_and(|c| close(&c, &Offset::default())));
        // Then a moves toward m − r by w = 1 − exp(−Δd / λ), b toward the
        // moved a by w, the correction is 2a − b; r stays.
        let m = offset(0.55, 0.15, 0.025);
        span.record(&m, 1.0, 2.0);
        let w = 1.0 - libm::exp(-0.5);
        let step = |k: f64| offset(0.1 * k, 0.1 * k, 0.01 * k);
        assert!(close(&span.level, &step(w)));
        assert!(close(&span.smoothed, &step(w * w)));
        assert!(close(&corrected(&span), &step(2.0 * w - w * w)));
        span.record(&m, 1000.0, 2.0);
        assert!(close(&corrected(&span), &step(1.0)));
        assert!(span.bias.is_some_and(|b| close(&b, &r)));
        // Headings across ±π average on the circle.
        let mut span = FloatSpan::default();
        span.record(&offset(0.0, 0.0, 3.1), 1.0, 2.0);
        span.record(&offset(0.0, 0.0, -3.1), 1.0, 2.0);
        let heading = span.bias.map_or(0.0, |b| b.heading);
        assert!(libm::fabs(libm::fabs(heading) - core::f64::consts::PI) < 1e-9);
        // A tick whose m − r overflows, or whose a would, leaves a and b.
        let mut span = FloatSpan::default();
        span.record(&offset(-1e308, 0.0, 0.0), 2.0, 2.0);
        let before = span;
        span.record(&offset(f64::MAX, 0.0, 0.1), 1.0, 2.0);
        assert_eq!(span, before);
        let mut span = FloatSpan::default();
        span.record(&Offset::default(), 2.0, 2.0);
        span.record(&offset(f64::MAX, -f64::MAX, 0.1), 1000.0, 2.0);
        let before = span;
        assert!(close(&corrected(&span), &offset(f64::MAX, -f64::MAX, 0.1)));
        span.record(&offset(-f64::MAX, f64::MAX, 0.2), 1000.0, 2.0);
        assert_eq!(span, before);
    }

    //= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
    //= type=test
    //# The span's correction MUST be 2a − b (the heading's difference wrapped),
    //# and its east and north MUST each be at most three times the largest
    //# magnitude of that component of m − r over the span's float ticks.
    #[test]
    fn a_drift_growing_with_distance_is_followed_without_the_lag_of_one_average() {
        // λ = 2 m, a tick every 0.01 m; r = (0.5, −0.3, 0.02) over the first
        // 2 m, then m − r grows 0.015 m, −0.01 m and 0.0011 rad per metre.
        let (length, tick) = (2.0, 0.01);
        let r = offset(0.5, -0.3, 0.02);
        let rate = offset(0.015, -0.01, 0.0011);
        let mut span = FloatSpan::default();
        for _ in 0..200 {
            span.record(&r, tick, length);
        }
        assert!(span.bias.is_some_and(|b| close(&b, &r)));
        let drift = |d: f64| offset(rate.x * d, rate.y * d, rate.heading * d);
        for k in 1..=4000_u32 {
            let d = f64::from(k) * tick;
            let m = drift(d);
            span.record(
                &offset(r.x + m.x, r.y + m.y, r.heading + m.heading),
                tick,
                length,
            );
            let c = corrected(&span);
            // Bounded by three times the largest |m − r| so far (m − r grows).
            assert!(libm::fabs(c.x) <= 3.0 * libm::fabs(m.x) + 1e-12);
            assert!(libm::fabs(c.y) <= 3.0 * libm::fabs(m.y) + 1e-12);
            if d >= 20.0 * length {
                // One average a lags by about λ times the drift rate: 0.03 m
                // east; 2a − b has no steady lag.
                let lag = |a: &Offset| offset(m.x - a.x, m.y - a.y, m.heading - a.heading);
                let one = lag(&span.level);
                assert!(
                    libm::fabs(one.x / (length * rate.x) - 1.0) < 0.01,
                    "{one:?}"
                );
                assert!(
                    libm::fabs(one.y / (length * rate.y) - 1.0) < 0.01,
                    "{one:?}"
                );
                assert!(libm::fabs(one.heading / (length * rate.heading) - 1.0) < 0.01);
                let two = lag(&c);
                assert!(
                    libm::fabs(two.x) < 1e-6 && libm::fabs(two.y) < 1e-6,
                    "{two:?}"
                );
                assert!(libm::fabs(two.heading) < 1e-7, "{two:?}");
            }
        }
        // A step in m − r: 2a − b overshoots it by e⁻² (13.5 %) at 2λ and
        // stays within three times it, the heading's difference wrapped.
        let mut span = FloatSpan::default();
        span.record(&offset(0.0, 0.0, 3.0), length, length);
        let step = offset(0.2, -0.1, -3.0);
        let mut largest = 0.0_f64;
        for _ in 0..4000 {
            span.record(&step, tick, length);
            let c = corrected(&span);
            assert!(libm::fabs(c.x) <= 3.0 * 0.2 && libm::fabs(c.y) <= 3.0 * 0.1);
            assert!(libm::fabs(c.heading) <= core::f64::consts::PI);
            largest = largest.max(c.x);
        }
        assert!(
            libm::fabs(largest / 0.2 - (1.0 + libm::exp(-2.0))) < 1e-3,
            "{largest}"
        );
        let c = corrected(&span);
        assert!(libm::fabs(c.x - 0.2) < 1e-4);
        // −3 − 3 wraps to 2π − 6 ≈ 0.283 rad.
        assert!(libm::fabs(c.heading - (2.0 * core::f64::consts::PI - 6.0)) < 1e-4);
    }

    #[test]
    fn the_rejoin_starts_and_ends_flat_and_never_outruns_its_slope() -> Result<(), Precondition> {
        for (o0, k) in [(0.3, 0.1), (-0.5, 0.2), (0.05, 1.0), (-1.2, 0.05)] {
            let r = rule(k)?;
            let start = Meters::new(o0)?;
            let length = 1.5 * libm::fabs(o0) / k;
            let (o, rate) = r.rejoin_shape(start, Meters::ZERO);
            assert!(o == start && rate == 0.0);
            let (_, rate) = r.rejoin_shape(start, Meters::new(length / 2.0)?);
            assert!(libm::fabs(libm::fabs(rate) - k) < 1e-12, "peak {rate}");
            let (o, rate) = r.rejoin_shape(start, Meters::new(length)?);
            assert!(o == Meters::ZERO && rate == 0.0);
            // Monotone toward zero, never past it, rate within k.
            let mut previous = o0;
            for i in 1..=100_u32 {
                let d = length * f64::from(i) / 100.0;
                let (o, rate) = r.rejoin_shape(start, Meters::new(d)?);
                assert!(libm::fabs(o.get()) <= libm::fabs(previous) && o.get() * o0 >= 0.0);
                assert!(libm::fabs(rate) <= k + 1e-12);
                previous = o.get();
            }
            // A negative distance counts as none.
            assert!(r.rejoin_offset(start, Meters::new(-1.0)?) == start);
        }
        Ok(())
    }

    #[test]
    fn a_small_step_is_taken_up_within_the_rejoin_curvature() -> Result<(), Precondition> {
        for (o0, k, kappa) in [
            (0.08, 0.1, 0.05),
            (-0.01, 0.1, 0.05),
            (0.3, 0.1, 0.2),
            (1.0, 0.1, 0.05),
        ] {
            let r = FixRule::new(&FixRuleParams {
                rejoin_curvature: kappa,
                ..*rule(k)?.params()
            })?;
            let start = Meters::new(o0)?;
            let length = (1.5 * libm::fabs(o0) / k).max(libm::sqrt(6.0 * libm::fabs(o0) / kappa));
            let (o, _) = r.rejoin_shape(start, Meters::new(length * 0.999)?);
            assert!(o != Meters::ZERO);
            let (o, rate) = r.rejoin_shape(start, Meters::new(length)?);
            assert!(o == Meters::ZERO && rate == 0.0);
            // The rate within k, its change per metre within κ.
            let h = length / 1000.0;
            for i in 0..1000_u32 {
                let d = h * f64::from(i);
                let (_, a) = r.rejoin_shape(start, Meters::new(d)?);
                let (_, b) = r.rejoin_shape(start, Meters::new(d + h)?);
                assert!(libm::fabs(a) <= k + 1e-12);
                assert!(
                    libm::fabs(b - a) / h <= kappa * (1.0 + 1e-6),
                    "{o0}: {}",
                    (b - a) / h
                );
            }
        }
        Ok(())
    }
}
