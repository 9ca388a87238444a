//! Tasks and their legs (Emmi 2024, sections 3.1 and 4; EM-MISSION-TASKS).

use heapless::Vec;

use crate::error::Precondition;
use crate::geometry::frame::{Pose2, World};
use crate::geometry::path::MIN_WAYPOINT_SPACING;
use crate::geometry::units::Meters;

/// The most tasks of a mission.
pub const MAX_TASKS: usize = 8;
/// The most waypoints of an Approximation.
pub const MAX_WAYPOINTS: usize = 16;
/// The most rows of a Treatment.
pub const MAX_ROWS: usize = 16;
/// The most legs of a task: two per row of a Treatment.
pub const MAX_LEGS: usize = 2 * MAX_ROWS;

/// The kind of a task.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TaskKind {
    /// Reach a field along roads.
    Approximation,
    /// Work a field, row by row.
    Treatment,
}

/// One crop row: the pose where its pass starts (heading along the pass) and
/// its length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// The start of the pass, heading along the row.
    pub start: Pose2<World>,
    /// The length of the pass, metres, at least 1 mm.
    pub length: Meters,
}

/// One task of a mission.
#[derive(Debug, Clone, PartialEq)]
pub enum Task {
    /// One leg per waypoint, on roads.
    Approximation(Vec<Pose2<World>, MAX_WAYPOINTS>),
    /// Per row, a turn to its start then its pass, inside the field.
    Treatment(Vec<Row, MAX_ROWS>),
}

impl Task {
    /// An Approximation through `waypoints`, in order.
    ///
    /// # Errors
    /// `EM-MISSION-TASKS` for no waypoint or more than [`MAX_WAYPOINTS`].
    //= spec/emmi2024.md#em-mission-tasks-tasks-and-legs
    //# A mission MUST be a list of at most 8 tasks, each an Approximation (at most
    //# 16 waypoints, one leg per waypoint, on roads) or a Treatment (at most 16
    //# rows, two legs per row: a turn to the row's start, then the pass along it,
    //# inside the field); a task with no waypoint or no row MUST be refused with
    //# the `EM-MISSION-TASKS` error.
    pub fn approximation(waypoints: &[Pose2<World>]) -> Result<Self, Precondition> {
        if waypoints.is_empty() {
            return Err(Precondition::new("EM-MISSION-TASKS", "no waypoint"));
        }
        Vec::from_slice(waypoints)
            .map(Self::Approximation)
            .map_err(|_| Precondition::new("EM-MISSION-TASKS", "more than 16 waypoints"))
    }

    /// A Treatment of `rows`, in order.
    ///
    /// # Errors
    /// `EM-MISSION-TASKS` for no row, more than [`MAX_ROWS`], or a row
    /// shorter than 1 mm.
    pub fn treatment(rows: &[Row]) -> Result<Self, Precondition> {
        if rows.is_empty() {
            return Err(Precondition::new("EM-MISSION-TASKS", "no row"));
        }
        if rows.iter().any(|r| r.length.get() < MIN_WAYPOINT_SPACING) {
            return Err(Precondition::new(
                "EM-MISSION-TASKS",
                "row shorter than 1 mm",
            ));
        }
        Vec::from_slice(rows)
            .map(Self::Treatment)
            .map_err(|_| Precondition::new("EM-MISSION-TASKS", "more than 16 rows"))
    }

    /// The kind of this task.
    #[must_use]
    pub const fn kind(&self) -> TaskKind {
        match self {
            Self::Approximation(_) => TaskKind::Approximation,
            Self::Treatment(_) => TaskKind::Treatment,
        }
    }

    /// The number of legs: one per waypoint, two per row.
    #[must_use]
    pub fn legs(&self) -> u8 {
        let n = match self {
            Self::Approximation(w) => w.len(),
            Self::Treatment(r) => r.len().saturating_mul(2),
        };
        u8::try_from(n).unwrap_or(u8::MAX)
    }
}

/// What the machine knows of a mission: each task's kind and number of legs.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct Shape {
    tasks: Vec<(TaskKind, u8), MAX_TASKS>,
}

impl Shape {
    /// The shape of `tasks` (the first [`MAX_TASKS`]).
    #[must_use]
    pub fn of(tasks: &[Task]) -> Self {
        let mut shape = Self::default();
        for task in tasks.iter().take(MAX_TASKS) {
            // Capacity is MAX_TASKS and at most MAX_TASKS are pushed.
            let _ = shape.tasks.push((task.kind(), task.legs()));
        }
        shape
    }

    /// The shape of tasks given as (kind, legs), the first [`MAX_TASKS`]; a
    /// task of 0 legs is kept (the machine aborts on it).
    #[must_use]
    pub fn from_legs(tasks: &[(TaskKind, u8)]) -> Self {
        let mut shape = Self::default();
        for task in tasks.iter().take(MAX_TASKS) {
            let _ = shape.tasks.push(*task);
        }
        shape
    }

    /// The number of tasks.
    #[must_use]
    pub fn len(&self) -> u8 {
        u8::try_from(self.tasks.len()).unwrap_or(u8::MAX)
    }

    /// Whether there is no task.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tasks.is_empty()
    }

    /// Task `index`'s kind and number of legs.
    #[must_use]
    pub fn task(&self, index: u8) -> Option<(TaskKind, u8)> {
        self.tasks.get(usize::from(index)).copied()
    }
}
