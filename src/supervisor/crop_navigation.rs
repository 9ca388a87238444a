//! Driving a whole crop on LiDAR alone with a symmetric differential robot
//! (Guyonneau 2022, sections 3-4, Fig. 5; `spec/guyonneau2022.md`, NAV-*).
//!
//! The robot knows only that it starts between two rows, parallel to them,
//! how many inter-rows it must drive and on which side the next one is. Each
//! tick, [`CropNavigator::step`] takes the scans of its front and back
//! LiDARs and its odometry pose and returns a differential command:
//!
//! 1. **Measuring**: standing still while the rows detector measures the row
//!    distance d (ROWS-INIT-STILL);
//! 2. **Driving** an inter-row, forward or backward: the rows either side,
//!    seen in the frame of the direction of travel, through the fuzzy
//!    controller (NAV-TRAVEL-FRAME); the row ends when no point remains
//!    beside the robot for some scans in a row (NAV-ROW-END);
//! 3. **Changing** row without turning round (NAV-ROW-CHANGE): a quarter
//!    turn in place towards the next row, d straight on, a quarter turn
//!    back, all on odometry; the next inter-row is driven the other way;
//! 4. **Done** after the last inter-row, or **Stopped** with a reason.
//!
//! A robot that cannot command stands still and says why ([`Waiting`]).

use heapless::Vec;

use crate::control::fuzzy::Defuzzifier;
use crate::control::fuzzy_rows::{FuzzyRowController, Orientation};
use crate::error::Precondition;
use crate::geometry::frame::{Odom, Pose2};
use crate::geometry::units::{Meters, MetersPerSecond, Radians, RadiansPerSecond};
use crate::model::differential::Differential;
use crate::model::Command;
use crate::perception::furrow::lines::RowLine;
use crate::perception::furrow::selection::Pair;
use crate::perception::furrow::RowLines;
use crate::perception::rows::filter::MAX_ROWS;
use crate::perception::rows::points::RowPoint;
use crate::perception::rows::{RowsConfig, RowsDetection, RowsDetector};
use crate::perception::Scan;

/// A quarter turn is complete within this much heading, rad (about 0.6°).
pub const TURN_TOLERANCE: f64 = 0.01;
/// The crossing is complete within this much distance, m.
pub const CROSS_TOLERANCE: f64 = 0.005;
/// Yaw rate per radian of heading left to turn, 1/s (NAV-ROW-CHANGE).
pub const TURN_GAIN: f64 = 2.0;
/// Speed per metre left to cross, 1/s (NAV-ROW-CHANGE).
pub const CROSS_GAIN: f64 = 1.0;
/// Yaw rate per radian of heading error while crossing, 1/s.
pub const HEADING_GAIN: f64 = 2.0;
/// The slowest a manoeuvre moves, as a share of its top wheel speed, so
/// that it always ends.
pub const CREEP_SHARE: f64 = 0.1;

/// Which side of the robot the next inter-row is on, in its body frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// y > 0.
    Left,
    /// y < 0.
    Right,
}

/// The navigator's parameters as a user writes them; [`NavParams::authors`]
/// gives the paper's robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavParams {
    /// The rows detector, with the front LiDAR's mount first and the back
    /// LiDAR's second.
    pub rows: RowsConfig,
    /// The robot's wheels and their limit.
    pub vehicle: Differential,
    /// The wheel speed of the fuzzy controller's full output, m/s, at most
    /// the vehicle's limit.
    pub top_speed: MetersPerSecond,
    /// How the controller reads the orientation (ROWS-FUZZY-INPUTS).
    pub orientation: Orientation,
    /// How it defuzzifies.
    pub defuzzifier: Defuzzifier,
    /// Inter-rows to drive, ≥ 1 (the paper: five).
    pub inter_rows: u8,
    /// The side of the first new inter-row (the paper: left); every change
    /// goes the same way, since the robot never turns round.
    pub next_side: Side,
    /// The robot's length, m, > 0 (the paper's robot: about 1.1 m).
    pub body_length: Meters,
    /// How far behind the robot's end the nearest point must be for the row
    /// to have ended, m, ≥ 0 (authors' implementation: 0.9 m).
    pub end_margin: Meters,
    /// Scans in a row that must see the end, ≥ 1 (authors': 3).
    pub end_scans: u8,
    /// The top wheel speed of a row change, m/s, in (0, the vehicle's limit].
    pub manoeuvre_speed: MetersPerSecond,
    /// Ticks without a usable scan (none given, or no point in it) after
    /// which the robot stops, ≥ 1; until then it keeps its last command.
    pub blind_ticks: u16,
}

impl NavParams {
    /// The paper's robot with `rows`: 1.1 m long, wheels 0.1 m wide 0.5 m
    /// apart at most 1 m/s, a top speed of 0.5 m/s, five inter-rows, the
    /// first new one to the left, the authors' row end (0.9 m, three scans),
    /// row changes at 0.3 m/s, and 0.25 s without scans at 40 Hz (10 ticks).
    ///
    /// # Errors
    /// As [`Differential::new`].
    pub fn authors(rows: RowsConfig) -> Result<Self, Precondition> {
        Ok(Self {
            rows,
            vehicle: Differential::new(Meters(0.5), MetersPerSecond(1.0))?,
            top_speed: MetersPerSecond(0.5),
            orientation: Orientation::SidesMeanSlope,
            defuzzifier: Defuzzifier::Exact,
            inter_rows: 5,
            next_side: Side::Left,
            body_length: Meters(1.1),
            end_margin: Meters(0.9),
            end_scans: 3,
            manoeuvre_speed: MetersPerSecond(0.3),
            blind_ticks: 10,
        })
    }
}

/// A step of a row change (NAV-ROW-CHANGE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Manoeuvre {
    /// A quarter turn in place towards the next inter-row.
    TurnTowards,
    /// Straight on by the row distance.
    Cross,
    /// A quarter turn in place back to the rows' direction.
    TurnBack,
}

/// Why a navigator stopped for good.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Halt {
    /// No usable scan for `blind_ticks` ticks.
    Blind,
    /// A command the vehicle could not take (a law out of its limits).
    Refused(Precondition),
}

/// Where the navigator is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Standing still while the row distance is measured.
    Measuring,
    /// Driving inter-row `row` (1-based), backward when `backward`.
    Driving {
        /// The inter-row, from 1.
        row: u8,
        /// Whether the robot drives it backward.
        backward: bool,
    },
    /// Changing from inter-row `row` to the next.
    Changing {
        /// The inter-row just finished, from 1.
        row: u8,
        /// Which step of the change.
        step: Manoeuvre,
    },
    /// Every inter-row driven: standing still.
    Done,
    /// Standing still for good.
    Stopped(Halt),
}

/// Why the robot stands still in a tick where it would drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Waiting {
    /// The row distance is being measured (no pair of rows seen yet, or the
    /// robot moved).
    MeasuringRows,
    /// The detector has no rows either side of the robot.
    RowsNotSeen,
}

/// One tick's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavTick {
    /// The command, within the vehicle's limits.
    pub command: Command,
    /// The phase after this tick.
    pub phase: Phase,
    /// Why the robot stands still, when it would drive but cannot.
    pub waiting: Option<Waiting>,
    /// The rows detector's result, when it ran in this tick.
    pub detection: Option<RowsDetection>,
    /// Scans in a row that saw the end of the inter-row.
    pub end_count: u8,
}

/// The manoeuvre's reference: the odometry pose where the change started
/// and where the current step started.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Change {
    heading: f64,
    step_start: Pose2<Odom>,
}

/// The symmetric robot's navigator over a whole crop.
#[derive(Debug, Clone)]
pub struct CropNavigator<const POINTS: usize = 1024> {
    params: NavParams,
    detector: RowsDetector<POINTS>,
    controller: FuzzyRowController,
    phase: Phase,
    change: Option<Change>,
    end_count: u8,
    blind: u16,
    last: Command,
}

impl<const POINTS: usize> CropNavigator<POINTS> {
    /// A navigator of `params`, measuring the rows first.
    ///
    /// # Errors
    /// `NAV-PARAMS` when a parameter is out of its range; the controller's
    /// own (`ROWS-FUZZY-SPEED`).
    //= spec/guyonneau2022.md#nav-params-the-navigator-s-parameters
    //# A navigator MUST be refused with an error naming NAV-PARAMS unless it
    //# drives at least one inter-row, its top speed and its manoeuvre speed are
    //# > 0 and within the vehicle's wheel-speed limit, its body length is > 0,
    //# its end margin ≥ 0, and it counts at least one end scan and one blind
    //# tick.
    pub fn new(params: NavParams) -> Result<Self, Precondition> {
        let max = params.vehicle.max_wheel_speed().get();
        let speed_ok = |v: MetersPerSecond| v.get() > 0.0 && v.get() <= max;
        let fail = |violated| Err(Precondition::new("NAV-PARAMS", violated));
        if params.inter_rows == 0 {
            return fail("at least one inter-row");
        }
        if !(speed_ok(params.top_speed) && speed_ok(params.manoeuvre_speed)) {
            return fail("speeds must be > 0 and within the wheel-speed limit");
        }
        if params.body_length.get() <= 0.0 || params.end_margin.get() < 0.0 {
            return fail("body length > 0 and end margin >= 0");
        }
        if params.end_scans == 0 || params.blind_ticks == 0 {
            return fail("at least one end scan and one blind tick");
        }
        Ok(Self {
            detector: RowsDetector::new(params.rows),
            controller: FuzzyRowController::authors(
                params.orientation,
                params.defuzzifier,
                params.top_speed,
            )?,
            params,
            phase: Phase::Measuring,
            change: None,
            end_count: 0,
            blind: 0,
            last: Command::Differential {
                left: MetersPerSecond::ZERO,
                right: MetersPerSecond::ZERO,
            },
        })
    }

    /// The phase.
    #[must_use]
    pub const fn phase(&self) -> Phase {
        self.phase
    }

    /// The rows detector.
    #[must_use]
    pub const fn detector(&self) -> &RowsDetector<POINTS> {
        &self.detector
    }

    /// One control tick: the scans that arrived (front LiDAR's first, back
    /// LiDAR's second; none in a tick without scans) and the odometry pose.
    ///
    /// # Errors
    /// The detector's refusal of malformed scans (`ROWS-MOUNTS`,
    /// `LIB-FINITE`); the command a law could not make (`LIB-FINITE`).
    //= spec/guyonneau2022.md#nav-phases-measure-drive-change-done
    //# The navigator MUST stand still while it measures the row distance,
    //# then drive the first inter-row forward, change row at each inter-row's
    //# end, drive each next inter-row in the direction opposite to the last,
    //# and stand still once the configured number of inter-rows is driven.
    pub fn step(
        &mut self,
        scans: &[Scan<'_>],
        odometry: &Pose2<Odom>,
    ) -> Result<NavTick, Precondition> {
        let stop = Command::Differential {
            left: MetersPerSecond::ZERO,
            right: MetersPerSecond::ZERO,
        };
        let mut tick = NavTick {
            command: stop,
            phase: self.phase,
            waiting: None,
            detection: None,
            end_count: self.end_count,
        };
        match self.phase {
            Phase::Done | Phase::Stopped(_) => return Ok(tick),
            Phase::Changing { row, step } => {
                let command = self.manoeuvre(row, step, odometry)?;
                tick.command = self.checked(command);
            }
            Phase::Measuring | Phase::Driving { .. } => {
                if scans.is_empty() {
                    tick.command = self.blind_tick(stop);
                } else {
                    let detection = self.detector.observe_scans(scans, odometry)?;
                    tick.detection = Some(detection);
                    let (command, waiting) = self.drive(&detection, stop)?;
                    tick.command = self.checked(command);
                    tick.waiting = waiting;
                }
            }
        }
        self.last = tick.command;
        tick.phase = self.phase;
        tick.end_count = self.end_count;
        Ok(tick)
    }

    /// `command` when the vehicle takes it, else the stop and the halt
    /// (GD-VEHICLE).
    fn checked(&mut self, command: Command) -> Command {
        let within = match command {
            Command::Differential { left, right } => self.params.vehicle.within(left, right),
            _ => false,
        };
        if within {
            command
        } else {
            self.phase = Phase::Stopped(Halt::Refused(Precondition::new(
                "GD-VEHICLE",
                "wheel speed beyond the vehicle's limit",
            )));
            command.stopped()
        }
    }

    /// A tick without a usable scan: the last command for `blind_ticks`
    /// ticks, then Stop for good (NAV-BLIND).
    //= spec/guyonneau2022.md#nav-blind-a-lidar-that-stops-sending
    //# A tick without a scan, or whose scans hold no point, MUST keep the last
    //# command for at most the configured number of blind ticks in a row; the
    //# next such tick MUST stop the robot for good with the reason Blind.
    fn blind_tick(&mut self, stop: Command) -> Command {
        self.blind = self.blind.saturating_add(1);
        if self.blind > self.params.blind_ticks {
            self.phase = Phase::Stopped(Halt::Blind);
            stop
        } else {
            self.last
        }
    }

    /// Measuring or driving on one tick's detection.
    fn drive(
        &mut self,
        detection: &RowsDetection,
        stop: Command,
    ) -> Result<(Command, Option<Waiting>), Precondition> {
        if self.detector.points().is_empty() {
            return Ok((self.blind_tick(stop), None));
        }
        self.blind = 0;
        if self.detector.row_distance().is_none() {
            // Measuring, or measuring again after the rows were lost.
            return Ok((stop, Some(Waiting::MeasuringRows)));
        }
        let (row, backward) = match self.phase {
            Phase::Driving { row, backward } => (row, backward),
            _ => (1, false),
        };
        self.phase = Phase::Driving { row, backward };
        if self.row_ended(backward) {
            self.end_count = 0;
            //= spec/guyonneau2022.md#nav-phases-measure-drive-change-done
            //# The last inter-row's end MUST give Done, with the robot standing
            //# still.
            self.phase = if row >= self.params.inter_rows {
                Phase::Done
            } else {
                Phase::Changing {
                    row,
                    step: Manoeuvre::TurnTowards,
                }
            };
            return Ok((stop, None));
        }
        let pair = match detection.detection.line {
            Some(RowLines::Two(pair)) => pair,
            _ => return Ok((stop, Some(Waiting::RowsNotSeen))),
        };
        let rows = self.detector.rows().unwrap_or(&[]);
        let (sides, travel_rows) = in_travel_frame(&pair, rows, backward)?;
        let wheels = self.controller.command(&sides, &travel_rows)?;
        Ok((to_body(&wheels.command, backward), None))
    }

    /// Whether this scan saw the inter-row's end, and the count of such scans
    /// in a row reached.
    fn row_ended(&mut self, backward: bool) -> bool {
        let reach = self.params.end_margin.get() + 0.5 * self.params.body_length.get();
        if nearest_point_behind(self.detector.points(), backward, reach) {
            self.end_count = self.end_count.saturating_add(1);
        } else {
            self.end_count = 0;
        }
        self.end_count >= self.params.end_scans
    }

    /// The command of one step of a row change, on odometry.
    fn manoeuvre(
        &mut self,
        row: u8,
        step: Manoeuvre,
        odometry: &Pose2<Odom>,
    ) -> Result<Command, Precondition> {
        let change = *self.change.get_or_insert(Change {
            heading: odometry.heading.get(),
            step_start: *odometry,
        });
        let distance = self.detector.row_distance().map_or(0.0, Meters::get);
        let side = match self.params.next_side {
            Side::Left => 1.0,
            Side::Right => -1.0,
        };
        let quarter = side * core::f64::consts::FRAC_PI_2;
        let across = change.heading + quarter;
        let p = &self.params;
        let (command, done) = match step {
            Manoeuvre::TurnTowards => turn_to(p, across, odometry)?,
            Manoeuvre::Cross => cross(p, &change.step_start, across, distance, odometry)?,
            Manoeuvre::TurnBack => turn_to(p, change.heading, odometry)?,
        };
        if done {
            let next = match step {
                Manoeuvre::TurnTowards => Some(Manoeuvre::Cross),
                Manoeuvre::Cross => Some(Manoeuvre::TurnBack),
                Manoeuvre::TurnBack => None,
            };
            self.change = next.map(|_| Change {
                step_start: *odometry,
                ..change
            });
            self.phase = match next {
                Some(step) => Phase::Changing { row, step },
                None => {
                    let backward = row & 1 == 1;
                    Phase::Driving {
                        row: row.saturating_add(1),
                        backward,
                    }
                }
            };
            return Ok(command.stopped());
        }
        Ok(command)
    }
}

/// Whether the point nearest the robot O lies more than `reach` m behind it
/// along the direction of travel; `false` without points.
//= spec/guyonneau2022.md#nav-row-end-no-plant-beside-the-robot
//# A scan MUST see the inter-row's end when the point of the scans nearest to
//# O lies more than the end margin plus half the body length behind O along
//# the direction of travel, and the inter-row MUST end after the configured
//# number of such scans in a row.
#[must_use]
pub fn nearest_point_behind(points: &[RowPoint], backward: bool, reach: f64) -> bool {
    let nearest = points.iter().map(|p| p.position).min_by(|a, b| {
        let (da, db) = (a.x() * a.x() + a.y() * a.y(), b.x() * b.x() + b.y() * b.y());
        da.total_cmp(&db)
    });
    nearest.is_some_and(|p| {
        let along = if backward { -p.x() } else { p.x() };
        along < -reach
    })
}

/// The rows either side, and every row left to right, as seen in the frame
/// of the direction of travel: unchanged forward; backward, each line
/// y = a x + b becomes y = a x − b and left and right swap.
///
/// # Errors
/// `LIB-FINITE` never in practice (negating a finite intercept).
//= spec/guyonneau2022.md#nav-travel-frame-the-rows-seen-in-the-direction-of-travel
//# Driving backward, the controller MUST read the rows in the frame turned by
//# π: each row y = a x + b as y = a x − b, left and right swapped; its left
//# and right wheel speeds (v_l′, v_r′) MUST be applied as the body's
//# (−v_r′, −v_l′).
pub fn in_travel_frame(
    sides: &Pair<RowLine>,
    rows: &[RowLine],
    backward: bool,
) -> Result<(Pair<RowLine>, Vec<RowLine, MAX_ROWS>), Precondition> {
    let mut all: Vec<RowLine, MAX_ROWS> = Vec::new();
    if !backward {
        for row in rows {
            let _ = all.push(*row);
        }
        return Ok((*sides, all));
    }
    let turned = |l: &RowLine| RowLine::new(l.slope(), l.intercept().negated());
    for row in rows.iter().rev() {
        let _ = all.push(turned(row)?);
    }
    Ok((
        Pair {
            left: turned(&sides.right)?,
            right: turned(&sides.left)?,
        },
        all,
    ))
}

/// A command of the direction of travel as the body's (NAV-TRAVEL-FRAME).
#[must_use]
pub fn to_body(command: &Command, backward: bool) -> Command {
    match (*command, backward) {
        (Command::Differential { left, right }, true) => Command::Differential {
            left: right.negated(),
            right: left.negated(),
        },
        (command, _) => command,
    }
}

/// A turn in place to odometry heading `target`: a yaw rate of
/// `TURN_GAIN` per radian left, within the manoeuvre speed and at least
/// `CREEP_SHARE` of it; done within `TURN_TOLERANCE`.
//= spec/guyonneau2022.md#nav-row-change-a-row-change-without-turning-round
//# A row change MUST turn in place by a quarter turn towards the next
//# inter-row, drive straight on by the row distance d, and turn in place back
//# to the heading it started from, each step on odometry alone; each turn
//# MUST end within 0.01 rad of its heading and the crossing within 0.005 m of
//# its length.
fn turn_to(
    params: &NavParams,
    target: f64,
    odometry: &Pose2<Odom>,
) -> Result<(Command, bool), Precondition> {
    let left = Radians::new(target - odometry.heading.get())?
        .wrapped()
        .get();
    let w = params.vehicle.track().get();
    let top = 2.0 * params.manoeuvre_speed.get() / w;
    let rate = (TURN_GAIN * libm::fabs(left)).clamp(CREEP_SHARE * top, top);
    let yaw = RadiansPerSecond::new(libm::copysign(rate, left))?;
    let (command, _) = params.vehicle.wheels(MetersPerSecond::ZERO, yaw)?;
    Ok((command, libm::fabs(left) < TURN_TOLERANCE))
}

/// Straight on from `start` along odometry heading `heading` by `length` m:
/// a speed of `CROSS_GAIN` per metre left, within the manoeuvre speed and
/// at least `CREEP_SHARE` of it, the heading held by `HEADING_GAIN`; done
/// within `CROSS_TOLERANCE`.
fn cross(
    params: &NavParams,
    start: &Pose2<Odom>,
    heading: f64,
    length: f64,
    odometry: &Pose2<Odom>,
) -> Result<(Command, bool), Precondition> {
    let (s, c) = libm::sincos(heading);
    let along = (odometry.position.x() - start.position.x()) * c
        + (odometry.position.y() - start.position.y()) * s;
    let left = length - along;
    let top = params.manoeuvre_speed.get();
    let speed = libm::copysign(
        (CROSS_GAIN * libm::fabs(left)).clamp(CREEP_SHARE * top, top),
        left,
    );
    let error = Radians::new(heading - odometry.heading.get())?
        .wrapped()
        .get();
    let (command, _) = params.vehicle.wheels(
        MetersPerSecond::new(speed)?,
        RadiansPerSecond::new(HEADING_GAIN * error)?,
    )?;
    Ok((command, libm::fabs(left) < CROSS_TOLERANCE))
}
