//! Unit types and frames (`spec/library.md`, LIB-UNITS, LIB-FRAMES,
//! LIB-FINITE): constructors refuse non-finite values, angles wrap to
//! (−π, π], transforms round-trip and follow the frames' conventions, and
//! a computation that overflows is an error.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp // exact values are the point of these checks
)]

use core::f64::consts::{PI, TAU};

use fieldguide::geometry::units::wrap_angle;
use fieldguide::{
    Curvature, Meters, MetersPerSecond, Point2, Pose2, Radians, RadiansPerSecond, Robot, Seconds,
    Transform2, World,
};

//= spec/library.md#lib-units-typed-quantities
//= type=test
//# Constructors of unit types MUST reject NaN and infinite values with a
//# `Precondition` error.
#[test]
fn constructors_reject_non_finite_values() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(Meters::new(bad).unwrap_err().requirement, "LIB-FINITE");
        assert!(Radians::new(bad).is_err());
        assert!(Curvature::new(bad).is_err());
        assert!(MetersPerSecond::new(bad).is_err());
        assert!(RadiansPerSecond::new(bad).is_err());
        assert!(Seconds::new(bad).is_err());
    }
    assert_eq!(Meters::new(-2.5).unwrap().get(), -2.5);
}

//= spec/library.md#lib-frames-frames-and-sign-conventions
//= type=test
//# Angles MUST be counter-clockwise positive and, where the core returns an
//# orientation, wrapped to (−π, π].
#[test]
fn wrapping_lands_in_the_half_open_interval() {
    let w = |a: f64| wrap_angle(Radians::new(a).unwrap()).get();
    assert_eq!(w(PI), PI);
    assert_eq!(w(-PI), PI);
    assert!((w(3.0 * PI) - PI).abs() < 1e-12);
    assert!((w(-0.5 - TAU) + 0.5).abs() < 1e-12);
    assert!((w(1e6) - libm::remainder(1e6, TAU)).abs() < 1e-9);
    // The largest angles wrap to a finite angle too.
    for a in [f64::MAX, -f64::MAX, 1e300, f64::MIN_POSITIVE, 5e-324, -0.0] {
        let r = w(a);
        assert!(r.is_finite() && r > -PI && r <= PI, "{a}: {r}");
    }
}

//= spec/library.md#lib-frames-frames-and-sign-conventions
//= type=test
//# Frames MUST be right-handed with x forward, y left and z up; world frames are
//# x east and y north.
#[test]
fn transform_round_trip_and_composition() {
    let robot = Pose2::<World>::new(3.0, -1.0, 0.7).unwrap();
    let to_world: Transform2<Robot, World> = robot.body_to_frame();
    let p = Point2::<Robot>::new(1.5, 0.25).unwrap();
    let w = to_world.apply(p).unwrap();
    let back = to_world.inverse().unwrap().apply(w).unwrap();
    assert!((back.x() - p.x()).abs() < 1e-12 && (back.y() - p.y()).abs() < 1e-12);
    // The robot origin lands on the pose's position.
    let o = to_world.apply(Point2::origin()).unwrap();
    assert!((o.x() - 3.0).abs() < 1e-12 && (o.y() + 1.0).abs() < 1e-12);
    // Forward is along the heading, and left is a quarter turn counter-clockwise.
    let l = to_world.apply(Point2::new(0.0, 1.0).unwrap()).unwrap();
    assert!((l.x() - 3.0 + libm::sin(0.7)).abs() < 1e-12);
    assert!((l.y() + 1.0 - libm::cos(0.7)).abs() < 1e-12);
    let f = to_world.apply(Point2::new(1.0, 0.0).unwrap()).unwrap();
    assert!((f.x() - 3.0 - libm::cos(0.7)).abs() < 1e-12);
    assert!((f.y() + 1.0 - libm::sin(0.7)).abs() < 1e-12);
    let id = to_world.then(&to_world.inverse().unwrap()).unwrap();
    assert!(id.angle().get().abs() < 1e-12);
}

#[test]
fn non_finite_points_are_refused() {
    assert!(Point2::<World>::new(f64::NAN, 0.0).is_err());
    assert!(Pose2::<World>::new(0.0, 0.0, f64::INFINITY).is_err());
    let huge = Transform2::<Robot, World>::new(f64::MAX, 0.0, 0.0).unwrap();
    assert!(huge.apply(Point2::new(f64::MAX, 0.0).unwrap()).is_err());
}

//= spec/library.md#lib-finite-no-nan-or-infinity
//= type=test
//# A value returned by the core MUST be finite: a computation whose result
//# would be NaN or infinite MUST return a `Precondition` error instead.
#[test]
fn a_distance_that_overflows_is_an_error() {
    let far = Point2::<World>::new(f64::MAX, 1e308).unwrap();
    let e = far.distance_to(Point2::origin()).unwrap_err();
    assert_eq!(e.requirement, "LIB-FINITE");
    let near = Point2::<World>::new(3.0, 4.0).unwrap();
    assert!((near.distance_to(Point2::origin()).unwrap().get() - 5.0).abs() < 1e-15);
    // The largest finite distance is still a distance.
    let edge = Point2::<World>::new(f64::MAX, 0.0).unwrap();
    assert!(edge.distance_to(Point2::origin()).unwrap().get() >= f64::MAX);
}
