//! The vehicles: their kinematics, their actuator limits and the one command
//! type a control law asks of them (`spec/guidance.md`, GD-VEHICLE).
//!
//! A vehicle is described once, here, by what it can do: the kinematic model
//! of its actuation and the limits of its actuators. A control law
//! ([`crate::control::ControlLaw`]) is written for one [`Actuation`] and
//! returns a [`Command`] of that actuation; the pipeline refuses a law made
//! for another vehicle than the one it drives.
//!
//! | Actuation | Command | Stop |
//! |---|---|---|
//! | [`Actuation::Bicycle`] (front steering, Pierre 2022) | speed, steering angle | 0 m/s, steering held |
//! | [`Actuation::FourWheelSteering`] | speed, front and rear steering angles | 0 m/s, both angles held |
//! | [`Actuation::Differential`] | left and right wheel speeds | both wheels at 0 m/s |
//! | [`Actuation::SkidSteer`] | speed, yaw rate | 0 m/s, 0 rad/s |

pub mod bicycle;
pub mod differential;
pub mod four_ws;
pub mod skid_steer;

use crate::error::Precondition;
use crate::geometry::units::{MetersPerSecond, Radians, RadiansPerSecond};

/// How a vehicle is actuated: which [`Command`] variant it takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Actuation {
    /// Front-wheel steering, the extended kinematic bicycle (Pierre 2022, eq. 1).
    Bicycle,
    /// Front and rear steering.
    FourWheelSteering,
    /// Two driven wheels on one axle, steering by their speed difference.
    Differential,
    /// Tracks or skid-steered wheels, commanded in speed and yaw rate.
    SkidSteer,
}

impl Actuation {
    /// A label for logs and errors.
    #[must_use]
    pub const fn label(self) -> &'static str {
        match self {
            Self::Bicycle => "bicycle",
            Self::FourWheelSteering => "four_wheel_steering",
            Self::Differential => "differential",
            Self::SkidSteer => "skid_steer",
        }
    }

    /// The command that holds this vehicle at rest before any command was
    /// made: every speed zero, every steering angle zero (GD-STOP).
    #[must_use]
    pub const fn at_rest(self) -> Command {
        match self {
            Self::Bicycle => Command::Bicycle {
                speed: MetersPerSecond::ZERO,
                steering: Radians::ZERO,
            },
            Self::FourWheelSteering => Command::FourWheelSteering {
                speed: MetersPerSecond::ZERO,
                front: Radians::ZERO,
                rear: Radians::ZERO,
            },
            Self::Differential => Command::Differential {
                left: MetersPerSecond::ZERO,
                right: MetersPerSecond::ZERO,
            },
            Self::SkidSteer => Command::SkidSteer {
                speed: MetersPerSecond::ZERO,
                yaw_rate: RadiansPerSecond::ZERO,
            },
        }
    }
}

/// What a vehicle is asked to do in one tick, one variant per actuation.
/// Angles are positive to the left, speeds positive forward.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Forward speed of the controlled point and front steering angle δ.
    Bicycle {
        /// Forward speed, m/s.
        speed: MetersPerSecond,
        /// Steering angle δ, rad.
        steering: Radians,
    },
    /// Forward speed and the front and rear steering angles.
    FourWheelSteering {
        /// Forward speed, m/s.
        speed: MetersPerSecond,
        /// Front steering angle, rad.
        front: Radians,
        /// Rear steering angle, rad.
        rear: Radians,
    },
    /// Left and right wheel speeds.
    Differential {
        /// Left wheel speed, m/s.
        left: MetersPerSecond,
        /// Right wheel speed, m/s.
        right: MetersPerSecond,
    },
    /// Forward speed and yaw rate.
    SkidSteer {
        /// Forward speed, m/s.
        speed: MetersPerSecond,
        /// Yaw rate, rad/s, positive to the left.
        yaw_rate: RadiansPerSecond,
    },
}

impl Command {
    /// The actuation this command is for.
    #[must_use]
    pub const fn actuation(&self) -> Actuation {
        match self {
            Self::Bicycle { .. } => Actuation::Bicycle,
            Self::FourWheelSteering { .. } => Actuation::FourWheelSteering,
            Self::Differential { .. } => Actuation::Differential,
            Self::SkidSteer { .. } => Actuation::SkidSteer,
        }
    }

    /// The forward speed of the controlled point, m/s (the mean of the wheel
    /// speeds for a differential vehicle).
    #[must_use]
    pub fn speed(&self) -> MetersPerSecond {
        match *self {
            Self::Bicycle { speed, .. }
            | Self::FourWheelSteering { speed, .. }
            | Self::SkidSteer { speed, .. } => speed,
            // The mean of two finite values is finite: no overflow halving first.
            Self::Differential { left, right } => {
                MetersPerSecond(0.5 * left.get() + 0.5 * right.get())
            }
        }
    }

    /// The stop this command becomes in Stop (GD-STOP): every speed zero,
    /// steering angles held where the vehicle steers with angles, the yaw
    /// rate zero where it steers with a rate.
    #[must_use]
    pub const fn stopped(&self) -> Self {
        match *self {
            Self::Bicycle { steering, .. } => Self::Bicycle {
                speed: MetersPerSecond::ZERO,
                steering,
            },
            Self::FourWheelSteering { front, rear, .. } => Self::FourWheelSteering {
                speed: MetersPerSecond::ZERO,
                front,
                rear,
            },
            Self::Differential { .. } | Self::SkidSteer { .. } => self.actuation().at_rest(),
        }
    }

    /// The steering angle of a bicycle command, `None` for other actuations.
    #[must_use]
    pub const fn steering(&self) -> Option<Radians> {
        match self {
            Self::Bicycle { steering, .. } => Some(*steering),
            Self::FourWheelSteering { .. } | Self::Differential { .. } | Self::SkidSteer { .. } => {
                None
            }
        }
    }
}

/// A command as a law made it: within the vehicle's limits, and whether it
/// had to be clamped to get there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Saturated {
    /// The command, within the vehicle's limits.
    pub command: Command,
    /// Whether the law's raw output was beyond a limit and clamped.
    pub saturated: bool,
}

/// A vehicle as the pipeline drives it: its actuation and the limits of its
/// actuators (GD-VEHICLE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Vehicle {
    /// A front-steered bicycle (Pierre 2022, eq. 1).
    Bicycle(bicycle::Bicycle),
    /// A differential robot (Guyonneau 2022, section 4.1.1).
    Differential(differential::Differential),
    /// A four-wheel-steering robot (Iberraken 2022, eqs. 5-8).
    FourWheelSteering(four_ws::FourWheelSteering),
    /// A tracked (skid-steer) robot (Emmi 2024, section 2.1).
    SkidSteer(skid_steer::SkidSteer),
}

impl Vehicle {
    /// The actuation of this vehicle.
    #[must_use]
    pub const fn actuation(&self) -> Actuation {
        match self {
            Self::Bicycle(_) => Actuation::Bicycle,
            Self::Differential(_) => Actuation::Differential,
            Self::FourWheelSteering(_) => Actuation::FourWheelSteering,
            Self::SkidSteer(_) => Actuation::SkidSteer,
        }
    }

    /// Checks that `command` is for this vehicle and within its limits.
    ///
    /// # Errors
    /// `GD-VEHICLE` for a command of another actuation or beyond a limit.
    //= spec/guidance.md#gd-vehicle-one-vehicle-one-command-type
    //# A command MUST be of the actuation of the vehicle it is sent to and
    //# within that vehicle's actuator limits.
    pub fn check(&self, command: &Command) -> Result<(), Precondition> {
        match (self, command) {
            (Self::Bicycle(b), Command::Bicycle { steering, .. }) => {
                if steering.get().abs() <= b.max_steering.get().get() {
                    Ok(())
                } else {
                    Err(Precondition::new(
                        "GD-VEHICLE",
                        "steering beyond the vehicle's limit",
                    ))
                }
            }
            (Self::Differential(d), Command::Differential { left, right }) => {
                if d.within(*left, *right) {
                    Ok(())
                } else {
                    Err(Precondition::new(
                        "GD-VEHICLE",
                        "wheel speed beyond the vehicle's limit",
                    ))
                }
            }
            (Self::FourWheelSteering(f), Command::FourWheelSteering { front, rear, .. }) => {
                if f.within_limits(*front, *rear) {
                    Ok(())
                } else {
                    Err(Precondition::new(
                        "GD-VEHICLE",
                        "front or rear steering beyond the vehicle's limit",
                    ))
                }
            }
            //= spec/emmi2024.md#em-skid-limits-track-distance-and-speed-limit
            //# A skid-steer command MUST be within the vehicle's limits when both
            //# track speeds satisfy |v_l| ≤ v_max and |v_r| ≤ v_max.
            (Self::SkidSteer(k), Command::SkidSteer { speed, yaw_rate }) => {
                if k.within_limits(speed.get(), yaw_rate.get()) {
                    Ok(())
                } else {
                    Err(Precondition::new(
                        "GD-VEHICLE",
                        "track speed beyond the vehicle's limit",
                    ))
                }
            }
            (
                Self::Bicycle(_)
                | Self::Differential(_)
                | Self::FourWheelSteering(_)
                | Self::SkidSteer(_),
                _,
            ) => Err(Precondition::new(
                "GD-VEHICLE",
                "command of another actuation than the vehicle's",
            )),
        }
    }
}
