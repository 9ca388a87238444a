//! The points of the last selections, kept across scans and moved by
//! odometry (Pierre 2022, section 2.3.1: "the previously selected points are
//! grouped in a set P_t that is updated at each instant"; `spec/pierre2022.md`
//! FUR-ACCUMULATE).
//!
//! Reading: a selection is stored once, in the odometry frame, through the
//! odometry pose of the tick that saw it; each tick the stored points are
//! read back through the inverse of the current odometry pose. Moving them by
//! the per-tick increment instead would compound one rounding per tick; this
//! way each point is transformed twice whatever its age.

use heapless::Deque;

use super::selection::Pair;
use crate::error::Precondition;
use crate::geometry::frame::{Frame, Odom, Point2, Pose2, Robot, Transform2};
use crate::geometry::units::{wrap_angle, Meters, Radians};

/// One scan's selection: one row's point, or a pair of rows' points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Selected<F: Frame> {
    /// One row (eq. 14).
    One(Point2<F>),
    /// Two rows (eq. 19): left has the larger y in the frame it was selected in.
    Two(Pair<Point2<F>>),
}

impl<F: Frame> Selected<F> {
    /// The point that stands for the selection: the row's point, or the pair's middle (eq. 18).
    #[must_use]
    pub fn reference(&self) -> Point2<F> {
        match self {
            Self::One(p) => *p,
            Self::Two(pair) => pair.mid(),
        }
    }

    /// The same selection through `transform`; an error only on overflow.
    pub fn moved<G: Frame>(
        &self,
        transform: &Transform2<F, G>,
    ) -> Result<Selected<G>, Precondition> {
        Ok(match self {
            Self::One(p) => Selected::One(transform.apply(*p)?),
            Self::Two(pair) => Selected::Two(Pair {
                left: transform.apply(pair.left)?,
                right: transform.apply(pair.right)?,
            }),
        })
    }
}

/// One kept selection: its points in the odometry frame, and the odometry
/// position (FUR-SPAN) and heading (FUR-FIRST-LINE) of the scan that saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Kept {
    selection: Selected<Odom>,
    at: Point2<Odom>,
    heading: Radians,
}

/// The last `limit` selections, more while they span less than `span` of
/// travel, at most `N`; stored in the odometry frame (FUR-ACCUMULATE,
/// FUR-SPAN).
#[derive(Debug, Clone)]
pub struct Accumulator<const N: usize> {
    entries: Deque<Kept, N>,
    limit: usize,
    keep_distance: Meters,
    span: Meters,
}

impl<const N: usize> Accumulator<N> {
    /// Keeps the last `limit` selections whose reference point lies within
    /// `keep_distance` m of the robot.
    ///
    /// Errors with `FUR-ACCUMULATE` unless `1 ≤ limit ≤ N` and `keep_distance > 0`.
    //= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
    //# A capacity of zero, a capacity above the storage N, or a non-positive
    //# keep distance MUST be refused with an error naming FUR-ACCUMULATE.
    pub fn new(limit: usize, keep_distance: Meters) -> Result<Self, Precondition> {
        if limit == 0 || limit > N {
            return Err(Precondition::new(
                "FUR-ACCUMULATE",
                "the number of kept selections must lie in 1..=N",
            ));
        }
        if keep_distance.get() <= 0.0 {
            return Err(Precondition::new(
                "FUR-ACCUMULATE",
                "the keep distance must be > 0",
            ));
        }
        Ok(Self {
            entries: Deque::new(),
            limit,
            keep_distance,
            span: Meters::ZERO,
        })
    }

    /// The same buffer, keeping more than its `limit` selections (up to `N`)
    /// while they span less than `span` of the robot's travel (FUR-SPAN); 0
    /// keeps the count alone.
    ///
    /// Errors with `FUR-SPAN` when `span` is negative.
    //= spec/pierre2022.md#fur-span-the-kept-selections-span-a-distance-of-travel
    //# A negative span MUST be refused with an error naming FUR-SPAN.
    pub fn with_span(self, span: Meters) -> Result<Self, Precondition> {
        if span.get() < 0.0 {
            return Err(Precondition::new("FUR-SPAN", "the span must be >= 0"));
        }
        Ok(Self { span, ..self })
    }

    /// How many selections are kept.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether no selection is kept.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Forgets every selection.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// The transform from the odometry frame into the robot frame at pose `odom`.
    pub fn odom_to_robot(odom: &Pose2<Odom>) -> Result<Transform2<Odom, Robot>, Precondition> {
        odom.body_to_frame::<Robot>().inverse()
    }

    /// Stores `selection`, seen in the robot frame at odometry pose `odom`.
    /// When `limit` selections are already kept, the oldest is dropped first
    /// and returned. Errors only when a point overflows.
    //= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
    //# Each selection MUST be stored in the odometry frame through the
    //# odometry pose of its scan, and read back in the current robot frame
    //# through the inverse of the current odometry pose.
    //= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
    //# When the buffer already holds its capacity of selections, storing a new
    //# one MUST drop the oldest.
    pub fn push(
        &mut self,
        selection: &Selected<Robot>,
        odom: &Pose2<Odom>,
    ) -> Result<Option<Selected<Odom>>, Precondition> {
        let stored = Kept {
            selection: selection.moved(&odom.body_to_frame::<Robot>())?,
            at: odom.position,
            heading: odom.heading,
        };
        let mut dropped = None;
        while self.entries.len() >= self.limit
            && (self.entries.is_full() || self.spans_without_oldest(stored.at))
        {
            dropped = self.entries.pop_front().map(|k| k.selection);
            if dropped.is_none() {
                break;
            }
        }
        // The deque is not full here, so it has room; a refusal would leave the buffer as it is.
        let _ = self.entries.push_back(stored);
        Ok(dropped)
    }

    /// Whether the kept selections but the oldest, with one seen at `at`,
    /// still span the configured span of travel (FUR-SPAN). With fewer than
    /// two kept, or a distance that overflows, they do.
    //= spec/pierre2022.md#fur-span-the-kept-selections-span-a-distance-of-travel
    //# When the buffer holds its n selections and has room for more, storing a
    //# new one MUST drop the oldest only if the robot's odometry positions at the
    //# scans of the second oldest and of the new selection are at least the
    //# configured span apart.
    fn spans_without_oldest(&self, at: Point2<Odom>) -> bool {
        self.entries.iter().nth(1).is_none_or(|second| {
            second
                .at
                .distance_to(at)
                .map_or(true, |d| d.get() >= self.span.get())
        })
    }

    /// Drops the selections whose reference point is farther than the keep
    /// distance from the robot at odometry pose `odom`, or behind its rear
    /// axle; returns how many.
    //= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
    //# A selection whose reference point lies farther than the keep distance
    //# from the robot MUST be dropped.
    //= spec/pierre2022.md#fur-accumulate-selections-kept-across-scans-through-odometry
    //# A selection whose reference point lies behind the robot (x < 0 in the
    //# current robot frame) MUST be dropped.
    pub fn forget_far(&mut self, odom: &Pose2<Odom>) -> usize {
        let mut kept = Deque::<Kept, N>::new();
        let mut dropped = 0_usize;
        let to_robot = Self::odom_to_robot(odom).ok();
        while let Some(entry) = self.entries.pop_front() {
            let reference = entry.selection.reference();
            // A distance or transform that overflows is farther than any keep distance.
            let near = reference
                .distance_to(odom.position)
                .is_ok_and(|d| d.get() <= self.keep_distance.get());
            let ahead = to_robot
                .as_ref()
                .and_then(|t| t.apply(reference).ok())
                .is_some_and(|p| p.x() >= 0.0);
            if near && ahead {
                let _ = kept.push_back(entry);
            } else {
                dropped = dropped.saturating_add(1);
            }
        }
        self.entries = kept;
        dropped
    }

    /// The kept selections in the robot frame at odometry pose `odom`, oldest
    /// first. A selection whose transform overflows is skipped.
    pub fn in_robot_frame(&self, odom: &Pose2<Odom>) -> impl Iterator<Item = Selected<Robot>> + '_ {
        let transform = Self::odom_to_robot(odom).ok();
        self.entries
            .iter()
            .filter_map(move |e| transform.as_ref().and_then(|t| e.selection.moved(t).ok()))
    }

    /// The odometry heading of the scan that took the newest kept selection
    /// (FUR-FIRST-LINE). `None` when nothing is kept.
    #[must_use]
    pub fn newest_heading(&self) -> Option<Radians> {
        self.entries.back().map(|k| k.heading)
    }

    /// How far the robot turned over its last `count` kept selections: the
    /// odometry heading of the newest minus that of the `count`-th newest,
    /// wrapped to (−π, π] (FUR-FIRST-LINE). `None` when fewer than `count`
    /// selections are kept or `count` is 0.
    #[must_use]
    pub fn recent_turn(&self, count: usize) -> Option<Radians> {
        let newest = self.entries.back()?;
        let earlier = self.entries.iter().rev().nth(count.checked_sub(1)?)?;
        Radians::new(newest.heading.get() - earlier.heading.get())
            .ok()
            .map(wrap_angle)
    }

    /// The newest selection in the robot frame at odometry pose `odom`: the
    /// previous selection of eqs. 14 and 19. `None` when nothing is kept.
    #[must_use]
    pub fn newest(&self, odom: &Pose2<Odom>) -> Option<Selected<Robot>> {
        let t = Self::odom_to_robot(odom).ok()?;
        self.entries.back()?.selection.moved(&t).ok()
    }
}
