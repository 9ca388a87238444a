//! Vine structure reconstruction (Iberraken 2022, section 2.1.4, eq. 2):
//! set-points kept in the odometry frame, a candidate joining them when its
//! lateral deviation from the newest one is small, dropped beyond a distance
//! from the robot (`spec/iberraken2022.md`, VINE-AGGREGATE).

use heapless::Deque;

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Odom, Point2, Pose2, Robot};
use crate::geometry::units::{Meters, Radians};

/// One aggregated set-point: where, in the odometry frame, and the
/// correlation score of the maximum it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetPoint {
    /// Position, odometry frame, m.
    pub point: Point2<Odom>,
    /// The score r(k) of its maximum.
    pub score: f64,
}

/// The lateral deviation of a retrieved point r from the previous set-point
/// p, in the robot's frame of yaw θ (Iberraken 2022, eq. 2):
/// l = |−sin θ (x_r − x_p) + cos θ (y_r − y_p)|, metres.
///
/// # Errors
/// `LIB-FINITE` on overflow.
//= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
//# The lateral deviation of a candidate r from the newest set-point p MUST be
//# l = |−sin θ (x_r − x_p) + cos θ (y_r − y_p)|, both points in the odometry
//# frame and θ the robot's odometry yaw.
pub fn lateral_deviation(
    candidate: Point2<Odom>,
    previous: Point2<Odom>,
    yaw: Radians,
) -> Result<Meters, Precondition> {
    let (s, c) = (libm::sin(yaw.get()), libm::cos(yaw.get()));
    let l = -s * (candidate.x() - previous.x()) + c * (candidate.y() - previous.y());
    Meters::new(finite(libm::fabs(l), "lateral deviation overflows")?)
}

/// The set-points, at most `N`, oldest first, in the odometry frame.
#[derive(Debug, Clone)]
pub struct SetPoints<const N: usize> {
    points: Deque<SetPoint, N>,
    keep_distance: Meters,
}

impl<const N: usize> SetPoints<N> {
    /// Set-points dropped farther than `keep_distance` m from the robot; `N`
    /// must be at least 1 (a capacity of 0 does not compile).
    ///
    /// # Errors
    /// `VINE-AGGREGATE` when the distance is not positive.
    pub fn new(keep_distance: Meters) -> Result<Self, Precondition> {
        if keep_distance.get() <= 0.0 {
            return Err(Precondition::new(
                "VINE-AGGREGATE",
                "the keep distance must be > 0",
            ));
        }
        Ok(Self {
            points: Deque::new(),
            keep_distance,
        })
    }

    /// How many set-points are kept.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether none is kept.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Forgets every set-point.
    pub fn clear(&mut self) {
        self.points.clear();
    }

    /// The newest set-point.
    #[must_use]
    pub fn newest(&self) -> Option<SetPoint> {
        self.points.back().copied()
    }

    /// The kept set-points, oldest first.
    pub fn iter(&self) -> impl Iterator<Item = &SetPoint> + Clone {
        let (front, back) = self.points.as_slices();
        front.iter().chain(back)
    }

    /// The mean score of the kept set-points, `None` when none is kept.
    #[must_use]
    pub fn mean_score(&self) -> Option<f64> {
        let (n, sum) = self
            .points
            .iter()
            .fold((0.0_f64, 0.0_f64), |(n, s), p| (n + 1.0, s + p.score));
        (n > 0.0).then(|| sum / n)
    }

    /// Drops the set-points farther than the keep distance from the robot at
    /// `odom`; returns how many.
    //= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
    //# A set-point farther than the keep distance from the robot MUST be
    //# dropped.
    pub fn forget_far(&mut self, odom: &Pose2<Odom>) -> usize {
        let mut kept = Deque::<SetPoint, N>::new();
        let mut dropped = 0_usize;
        while let Some(p) = self.points.pop_front() {
            let near = p
                .point
                .distance_to(odom.position)
                .is_ok_and(|d| d.get() <= self.keep_distance.get());
            if near {
                let _ = kept.push_back(p);
            } else {
                dropped = dropped.saturating_add(1);
            }
        }
        self.points = kept;
        dropped
    }

    /// Adds `point`; when `N` are kept, the oldest is dropped first and
    /// returned.
    //= spec/iberraken2022.md#vine-aggregate-set-points-aggregated-through-odometry
    //# When the store holds its capacity, adding a set-point MUST drop the
    //# oldest.
    pub fn push(&mut self, point: SetPoint) -> Option<SetPoint> {
        let dropped = if self.points.is_full() {
            self.points.pop_front()
        } else {
            None
        };
        // Room was made above.
        let _ = self.points.push_back(point);
        dropped
    }

    /// The kept set-points in the robot frame at odometry pose `odom`,
    /// oldest first; a point whose transform overflows is skipped.
    pub fn in_robot_frame(
        &self,
        odom: &Pose2<Odom>,
    ) -> impl Iterator<Item = Point2<Robot>> + Clone + '_ {
        let to_robot = odom.body_to_frame::<Robot>().inverse().ok();
        self.iter()
            .filter_map(move |p| to_robot.as_ref().and_then(|t| t.apply(p.point).ok()))
    }
}
