//! The odometry's heading aided by the good fix's (`spec/guidance.md`,
//! GD-ODOMETRY-AID): a complementary filter that keeps the odometry's
//! increments and pulls its heading's drift out with the heading of each
//! good fix, at a bounded rate, so that the odometry frame keeps its
//! rotation against the world. The pipeline applies it once, at the top of
//! its tick; a vehicle stack may also run it on its own.

use crate::error::{finite, Precondition};
use crate::geometry::carry::pose_in_scan_frame;
use crate::geometry::frame::{Odom, Pose2, World};
use crate::geometry::units::{wrap_raw, Radians, RadiansPerSecond, Seconds};

/// The aid as a user writes it; [`OdometryAid::new`] validates it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdometryAidParams {
    /// τ, the filter's time constant, s, > 0 (about 1-3 s for a
    /// dual-antenna heading: GD-ODOMETRY-AID's reading).
    pub time_constant: Seconds,
    /// The largest rate the correction turns the odometry frame at, in
    /// rad/s and positive: above the odometry's drift rate, low enough that
    /// what the frame holds never jumps.
    pub max_rate: RadiansPerSecond,
}

/// A validated aid at a control period: the gain α = 1 − exp(−Δt / τ) and
/// the largest correction of a tick (GD-ODOMETRY-AID).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdometryAid {
    params: OdometryAidParams,
    gain: f64,
    max_step: f64,
}

impl OdometryAid {
    /// Validates `params` at the control period `period` (> 0, as the
    /// configuration has checked).
    ///
    /// # Errors
    /// `GD-ODOMETRY-AID` when the time constant or the largest rate is not
    /// positive, or when the period is not (`LIB-FINITE` should the
    /// largest step overflow).
    //= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
    //# An odometry aid whose time constant or largest rate is not positive MUST be
    //# refused with `GD-ODOMETRY-AID`.
    pub fn new(params: &OdometryAidParams, period: Seconds) -> Result<Self, Precondition> {
        let (tau, rate) = (params.time_constant.get(), params.max_rate.get());
        let refused = [
            (tau, "odometry aid time_constant must be > 0"),
            (rate, "odometry aid max_rate must be > 0"),
            (period.get(), "the control period must be > 0"),
        ]
        .into_iter()
        .find(|(value, _)| *value <= 0.0);
        if let Some((_, violated)) = refused {
            return Err(Precondition::new("GD-ODOMETRY-AID", violated));
        }
        // Δt / τ is positive and may be +∞ (τ tiny): α is then 1.
        let gain = 1.0 - libm::exp(-(period.get() / tau));
        let max_step = finite(rate * period.get(), "odometry aid largest step overflows")?;
        Ok(Self {
            params: *params,
            gain,
            max_step,
        })
    }

    /// The parameters it was built from.
    #[must_use]
    pub const fn params(&self) -> &OdometryAidParams {
        &self.params
    }

    /// α = 1 − exp(−Δt / τ), in [0, 1].
    #[must_use]
    pub const fn gain(&self) -> f64 {
        self.gain
    }

    /// The largest correction of one tick, the largest rate times the period.
    #[must_use]
    pub fn max_step(&self) -> Radians {
        Radians(self.max_step)
    }
}

/// The aided odometry's state: the previous tick's odometry and aided poses
/// and the reference offset of the first good fix.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AidedOdometry {
    /// The previous tick's odometry pose and aided pose.
    last: Option<(Pose2<Odom>, Pose2<Odom>)>,
    /// The aided heading less the fix's at the first good fix, rad.
    reference: Option<f64>,
}

impl AidedOdometry {
    /// No tick yet.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            last: None,
            reference: None,
        }
    }

    /// The reference offset, once a good fix fixed it: the aided heading
    /// less the fix's, wrapped.
    #[must_use]
    pub fn reference(&self) -> Option<Radians> {
        self.reference.map(Radians)
    }

    /// The aided pose of a tick whose odometry pose is `odometry` and whose
    /// good fix, if any, is `fix` (GD-ODOMETRY-AID).
    //= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
    //# When an odometry aid is configured, every step of a tick MUST use, in place
    //# of the tick's odometry pose, the aided pose: in the first tick the odometry
    //# pose itself, in every later tick the previous aided pose moved by the
    //# odometry's increment since the previous tick (the tick's odometry pose in
    //# the robot frame of the previous tick's), its heading then turned by the
    //# tick's correction.
    //= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
    //# A tick whose aided pose overflows MUST take the tick's odometry pose as its
    //# aided pose and forget the reference offset, so that the next good fix fixes
    //# a new one.
    pub fn step(
        &mut self,
        aid: &OdometryAid,
        odometry: Pose2<Odom>,
        fix: Option<&Pose2<World>>,
    ) -> Pose2<Odom> {
        let moved = match self.last {
            None => Ok(odometry),
            Some((last, aided)) => pose_in_scan_frame(&last, &odometry)
                .and_then(|increment| aided.body_to_frame().apply_pose(increment)),
        };
        let aided = match moved {
            Ok(pose) => self.corrected(aid, pose, fix),
            Err(_) => {
                self.reference = None;
                odometry
            }
        };
        self.last = Some((odometry, aided));
        aided
    }

    /// `pose` turned by the tick's correction.
    //= spec/guidance.md#gd-odometry-aid-the-odometry-s-heading-aided-by-the-good-fix-s
    //# The correction MUST be zero in a tick without a good fix (GD-FIX-QUALITY)
    //# and in the tick of the first good fix, which fixes the reference offset: the
    //# aided heading less the fix's heading. In a tick with a later good fix it
    //# MUST be α e with α = 1 − exp(−Δt / τ), Δt the period, τ the aid's time
    //# constant and e the reference offset less the tick's offset, wrapped to
    //# (−π, π], limited in magnitude to the aid's largest rate times the period.
    fn corrected(
        &mut self,
        aid: &OdometryAid,
        pose: Pose2<Odom>,
        fix: Option<&Pose2<World>>,
    ) -> Pose2<Odom> {
        let Some(fix) = fix else {
            return pose;
        };
        // Finite headings, wrapped before they are subtracted: every
        // difference below is finite.
        let offset = wrap_raw(wrap_raw(pose.heading.get()) - wrap_raw(fix.heading.get()));
        let Some(reference) = self.reference else {
            self.reference = Some(offset);
            return pose;
        };
        let error = wrap_raw(reference - offset);
        let correction = (aid.gain * error).max(-aid.max_step).min(aid.max_step);
        Pose2 {
            heading: Radians(wrap_raw(pose.heading.get() + correction)),
            ..pose
        }
    }
}
