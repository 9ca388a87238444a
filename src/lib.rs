//! # fieldguide
//!
//! Verification-first guidance for agricultural field robots: path tracking with
//! sideslip (Pierre et al. 2022), edge following and furrow pursuing on 2D
//! LiDAR scans, and the switching between them, in one pipeline open to any
//! detector, control law and vehicle.
//!
//! The core is `no_std`, allocates nothing, never panics and never returns a
//! NaN: functions with a restricted domain return `Result<_, Precondition>`
//! naming the requirement of `spec/` they protect.
//!
//! ## One tick, as data flows through the core
//!
//! 1. Each LiDAR scan goes to the detector of the behaviour it is routed to,
//!    behind [`perception::Detector`], which returns a verdict, the error to
//!    its line at the robot and the line, held and moved by odometry until the
//!    next scan.
//! 2. The GNSS pose goes to [`geometry::path::ReferencePath::project`], which
//!    returns the Frénet error (s, y, θ̃, c(s), c(s + vT)).
//! 3. Every source with a valid estimate (path tracking, each behaviour) runs
//!    its law behind [`control::ControlLaw`], which returns a command of the
//!    vehicle's actuation ([`model::Command`]) within its limits, or refuses
//!    its error.
//! 4. The verdicts, and whether each law could command, go to the switching
//!    machine in [`supervisor`], which selects the source whose command is
//!    applied, or Stop.
//!
//! [`guidance::Guidance`] runs these steps once per control tick, for any
//! number of behaviour slots, routed scans, poses and odometry in, the
//! selected source's command at its speed out (`spec/guidance.md`);
//! [`presets`] configures it as in Pierre 2022's experiments.
//!
//! ## Conventions
//!
//! Frames are x forward, y left, z up; angles counter-clockwise positive,
//! wrapped to (−π, π]; lateral error positive when the robot is left of the
//! path; curvature positive for a left turn; steering positive to the left
//! (`spec/library.md`). Units are types ([`geometry::units`]); points carry
//! their frame in their type ([`geometry::frame`]).
//= spec/library.md#lib-no-alloc-no-allocation
//# The core MUST be `no_std` and MUST NOT allocate on the heap: buffers have a
//# fixed capacity, and a full buffer is a returned value, not a panic.
#![no_std]
#![forbid(unsafe_code)]

//= spec/library.md#lib-no-panic-no-panic
//# The core MUST NOT panic for any input: a function whose domain is restricted
//# MUST return `Result<_, Precondition>` naming the requirement it protects.
//
// Enforced by the lint table of `Cargo.toml` (unwrap, expect, panic, indexing,
// integer arithmetic and `as` casts denied) and by `panic = "abort"`.

//= spec/library.md#lib-determinism-no-hidden-inputs
//# Core functions MUST be deterministic functions of their arguments and state:
//# no clocks, no global randomness; time MUST be counted in control ticks of a
//# fixed period.
//
// `no_std` leaves the core no clock and no random source to reach for.

pub mod control;
pub mod error;
pub mod geometry;
pub mod guidance;
pub mod model;
pub mod perception;
pub mod planning;
pub mod presets;
pub mod supervisor;

pub use error::Precondition;
pub use geometry::frame::{Frame, Odom, Point2, Pose2, Robot, Sensor, Transform2, World};
pub use geometry::tracking::TrackingError;
pub use geometry::units::{Curvature, Meters, MetersPerSecond, Radians, RadiansPerSecond, Seconds};
pub use perception::Verdict;

/// The README's examples, compiled and run as doctests so they cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
