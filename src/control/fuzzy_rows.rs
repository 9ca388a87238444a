//! Guyonneau 2022's fuzzy wheel-speed controller (section 3.3, eqs. 18-19,
//! Table 1; `spec/guyonneau2022.md`, ROWS-FUZZY-*): the robot's orientation
//! and position between the rows either side of it, through the
//! [`super::fuzzy`] engine, to the left and right wheel speeds of a
//! differential robot.

use super::fuzzy::{Defuzzifier, Engine, Rule, Term, Variable, MAX_VARIABLES};
use crate::error::Precondition;
use crate::geometry::units::MetersPerSecond;
use crate::model::Command;
use crate::perception::furrow::lines::RowLine;
use crate::perception::furrow::selection::Pair;

/// How the orientation is read from the rows (ROWS-FUZZY-INPUTS).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Orientation {
    /// atan of the mean slope of the rows either side of the robot (the
    /// authors' implementation; the default).
    SidesMeanSlope,
    /// The mean of atan of every filtered row's slope (eq. 18 as printed).
    AllRowsMeanAngle,
}

/// θ_r of eq. 18, rad: negative when the robot heads left of the rows.
///
/// # Errors
/// `ROWS-FUZZY-INPUTS` when there is no row.
//= spec/guyonneau2022.md#rows-fuzzy-inputs-orientation-and-position-eqs-18-19
//# The orientation MUST be atan((a_left + a_right)/2) of the rows either side
//# (the default), or (1/n) Σ atan(a_i) over the n filtered rows; with the
//# library's slopes it is negative when the robot heads left of the rows.
pub fn orientation(
    sides: &Pair<RowLine>,
    rows: &[RowLine],
    how: Orientation,
) -> Result<f64, Precondition> {
    match how {
        Orientation::SidesMeanSlope => Ok(libm::atan(
            0.5 * sides.left.slope() + 0.5 * sides.right.slope(),
        )),
        Orientation::AllRowsMeanAngle => {
            let n = rows.iter().map(|_| 1.0).sum::<f64>();
            if n < 1.0 {
                return Err(Precondition::new("ROWS-FUZZY-INPUTS", "no filtered row"));
            }
            Ok(rows.iter().map(|r| libm::atan(r.slope()) / n).sum())
        }
    }
}

/// x_r of eq. 19 as the authors compute it: |b_l|/|b_r| − 1 when the left
/// row is nearer, 1 − |b_r|/|b_l| otherwise; in [−1, 1], negative when the
/// robot is nearer the left row.
///
/// # Errors
/// `ROWS-FUZZY-INPUTS` when a row passes through the robot (b = 0) or a
/// value is not finite.
//= spec/guyonneau2022.md#rows-fuzzy-inputs-orientation-and-position-eqs-18-19
//# The position MUST be x_r = |b_l|/|b_r| − 1 when |b_l| < |b_r| and
//# x_r = 1 − |b_r|/|b_l| otherwise, and MUST be refused with an error naming
//# ROWS-FUZZY-INPUTS when a row passes through the robot (b = 0).
pub fn position(sides: &Pair<RowLine>) -> Result<f64, Precondition> {
    let (l, r) = (
        libm::fabs(sides.left.intercept().get()),
        libm::fabs(sides.right.intercept().get()),
    );
    if !(l > 0.0 && r > 0.0 && l.is_finite() && r.is_finite()) {
        return Err(Precondition::new(
            "ROWS-FUZZY-INPUTS",
            "a row passes through the robot",
        ));
    }
    Ok(if l < r { l / r - 1.0 } else { 1.0 - r / l })
}

/// Five terms over a range: very left (a ramp), left, centre, right (triangles)
/// and very right (a ramp), the triangles' vertices at −h, 0, h and their
/// feet at ∓2h.
fn five(h: f64, range: f64) -> Variable {
    let terms = [
        Term::Ramp {
            start: -h,
            end: -2.0 * h,
        },
        Term::Triangle {
            left: -2.0 * h,
            peak: -h,
            right: 0.0,
        },
        Term::Triangle {
            left: -h,
            peak: 0.0,
            right: h,
        },
        Term::Triangle {
            left: 0.0,
            peak: h,
            right: 2.0 * h,
        },
        Term::Ramp {
            start: h,
            end: 2.0 * h,
        },
    ];
    Variable {
        min: -range,
        max: range,
        terms: terms.into_iter().collect(),
    }
}

/// A wheel's seven terms over [−1, 1] (a fraction of the top speed): normal,
/// middle and slow backward, stop, slow, middle and normal forward.
fn wheel() -> Variable {
    let (m, s) = (0.666, 0.333);
    let terms = [
        Term::Ramp {
            start: -m,
            end: -1.0,
        },
        Term::Triangle {
            left: -1.0,
            peak: -m,
            right: -s,
        },
        Term::Triangle {
            left: -m,
            peak: -s,
            right: 0.0,
        },
        Term::Triangle {
            left: -s,
            peak: 0.0,
            right: s,
        },
        Term::Triangle {
            left: 0.0,
            peak: s,
            right: m,
        },
        Term::Triangle {
            left: s,
            peak: m,
            right: 1.0,
        },
        Term::Ramp { start: m, end: 1.0 },
    ];
    Variable {
        min: -1.0,
        max: 1.0,
        terms: terms.into_iter().collect(),
    }
}

/// Table 1 as output terms: [orientation][position] → (left, right), the
/// wheel terms 0..6 from normal backward to normal forward (1F = 4, 2F = 5,
/// 3F = 6, 1B = 2, 2B = 1).
pub const TABLE_1: [[(u8, u8); 5]; 5] = [
    [(5, 1), (5, 1), (4, 2), (6, 4), (6, 5)],
    [(4, 2), (4, 2), (5, 4), (4, 4), (5, 5)],
    [(6, 4), (6, 5), (6, 6), (5, 6), (4, 6)],
    [(5, 5), (4, 4), (4, 5), (2, 4), (2, 4)],
    [(5, 6), (4, 6), (2, 4), (1, 5), (1, 5)],
];

/// The paper's controller: its engine, how it reads the orientation, its
/// defuzzifier and the wheels' top speed.
#[derive(Debug, Clone, PartialEq)]
pub struct FuzzyRowController {
    engine: Engine,
    orientation: Orientation,
    defuzzifier: Defuzzifier,
    top_speed: MetersPerSecond,
}

/// The wheel speeds of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelSpeeds {
    /// The differential command (left, right), m/s.
    pub command: Command,
    /// The wheels' speeds as fractions of the top speed, in [−1, 1].
    pub fractions: (f64, f64),
    /// Whether a rule fired for both wheels (otherwise that wheel stops).
    pub fired: bool,
}

impl FuzzyRowController {
    /// The engine of the authors' membership functions (orientation over
    /// ±π/4 with vertices at ±π/12, position over ±1 with vertices at ±0.5,
    /// wheels over ±1) and Table 1's 25 rules, wheels stopping when no rule
    /// fires.
    ///
    /// # Errors
    /// `ROWS-FUZZY-SPEED` unless the top speed is > 0.
    //= spec/guyonneau2022.md#rows-fuzzy-command-wheel-speeds
    //# A top speed that is not > 0 MUST be refused with an error naming
    //# ROWS-FUZZY-SPEED.
    //= spec/guyonneau2022.md#rows-fuzzy-rules-membership-functions-and-table-1
    //# The controller MUST use, for the orientation over ±π/4, a falling ramp
    //# from −π/12 to −π/6 (very left), triangles (−π/6, −π/12, 0), (−π/12, 0,
    //# π/12), (0, π/12, π/6) and a rising ramp from π/12 to π/6 (very right);
    //# the same shapes at ±0.5 and ±1 for the position over ±1; seven wheel
    //# terms over ±1 with vertices at ±1 (ramps from ±0.666), ±0.666, ±0.333
    //# and 0; and the 25 rules of Table 1.
    pub fn authors(
        orientation: Orientation,
        defuzzifier: Defuzzifier,
        top_speed: MetersPerSecond,
    ) -> Result<Self, Precondition> {
        if top_speed.get() <= 0.0 {
            return Err(Precondition::new(
                "ROWS-FUZZY-SPEED",
                "the top wheel speed must be > 0",
            ));
        }
        let quarter = core::f64::consts::FRAC_PI_4;
        let inputs = [five(quarter / 3.0, quarter), five(0.5, 1.0)];
        let outputs = [wheel(), wheel()];
        let mut rules: heapless::Vec<Rule, 25> = heapless::Vec::new();
        for (o, row) in (0_u8..).zip(TABLE_1.iter()) {
            for (p, &(left, right)) in (0_u8..).zip(row.iter()) {
                let mut when = [None; MAX_VARIABLES];
                let mut then = [None; MAX_VARIABLES];
                (when[0], when[1]) = (Some(o), Some(p));
                (then[0], then[1]) = (Some(left), Some(right));
                let _ = rules.push(Rule { when, then });
            }
        }
        Ok(Self {
            engine: Engine::new(&inputs, &outputs, &rules, &[0.0, 0.0])?,
            orientation,
            defuzzifier,
            top_speed,
        })
    }

    /// The engine.
    #[must_use]
    pub const fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The wheel speeds for orientation θ_r and position x_r.
    ///
    /// # Errors
    /// `FUZZY-INPUT` on a non-finite input; `LIB-FINITE` on overflow.
    pub fn wheels(&self, theta: f64, x: f64) -> Result<WheelSpeeds, Precondition> {
        let out = self.engine.evaluate(&[theta, x], self.defuzzifier)?;
        let (l, r) = match out.as_slice() {
            [l, r] => (*l, *r),
            _ => return Err(Precondition::new("FUZZY-ENGINE", "two outputs expected")),
        };
        let v = self.top_speed.get();
        //= spec/guyonneau2022.md#rows-fuzzy-command-wheel-speeds
        //# The command MUST be the differential command whose wheel speeds are
        //# the two outputs times the top speed.
        Ok(WheelSpeeds {
            command: Command::Differential {
                left: MetersPerSecond::new(l.value * v)?,
                right: MetersPerSecond::new(r.value * v)?,
            },
            fractions: (l.value, r.value),
            fired: l.fired && r.fired,
        })
    }

    /// The wheel speeds for the filtered rows, the pair either side of the
    /// robot among them (eqs. 18-19).
    ///
    /// # Errors
    /// As [`orientation`], [`position`] and [`FuzzyRowController::wheels`].
    pub fn command(
        &self,
        sides: &Pair<RowLine>,
        rows: &[RowLine],
    ) -> Result<WheelSpeeds, Precondition> {
        let theta = orientation(sides, rows, self.orientation)?;
        self.wheels(theta, position(sides)?)
    }
}
