//! Example and property tests of the switching machine's configuration and of
//! plan consistency (`spec/pierre2022.md`, SW-DELAYS, SW-PLAN-CONSISTENCY).
//! The machine's properties are proven in `fieldguide-proofs`.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use approx::assert_abs_diff_eq;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::supervisor::switching::{
    delay_ticks, line_relative_to_path, line_relative_to_path_ahead, BehaviourConfig, PathAhead,
    PlanTolerance, MAX_DELAY_TICKS,
};
use fieldguide::{Curvature, Meters, Point2, Radians, Seconds, TrackingError, World};
use proptest::prelude::*;

fn s(v: f64) -> Seconds {
    Seconds::new(v).unwrap()
}

const HERE: &PathAhead = &PathAhead::HERE;

fn error(y: f64, angular_deviation: f64) -> TrackingError {
    TrackingError {
        y: Meters::new(y).unwrap(),
        angular_deviation: Radians::new(angular_deviation).unwrap(),
        curvature: Curvature::ZERO,
        curvature_ahead: Curvature::ZERO,
    }
}

//= spec/pierre2022.md#sw-delays-transit-delays-in-control-ticks
//= type=test
//# Each specialised behaviour MUST have a positive delay to enter its mode and
//# a positive delay to leave it, and every delay MUST be converted once, at
//# construction, to a whole number of control ticks n = ⌈delay / period⌉.
#[test]
fn the_tables_in_ticks() {
    // Tables 1-2 at 100 Hz: the quotients are integers.
    for (delay, ticks) in [(0.4, 40), (0.26, 26), (0.5, 50), (0.3, 30)] {
        assert_eq!(delay_ticks(s(delay), s(0.01), "SW-DELAYS").unwrap(), ticks);
    }
    // At 10 Hz: 0.26 s is 2.6 periods, rounded up to 3.
    for (delay, ticks) in [(0.4, 4), (0.26, 3), (0.5, 5), (0.3, 3)] {
        assert_eq!(delay_ticks(s(delay), s(0.1), "SW-DELAYS").unwrap(), ticks);
    }
    // Representation error on both sides of an integer quotient: 0.07 s / 0.01 s
    // is 7.000000000000001 in f64 and must not become 8 ticks.
    assert_eq!(0.07 / 0.01, 7.000_000_000_000_001);
    assert_eq!(0.3 / 0.1, 2.999_999_999_999_999_6);
    assert_eq!(delay_ticks(s(0.07), s(0.01), "SW-DELAYS").unwrap(), 7);
    assert_eq!(delay_ticks(s(0.3), s(0.1), "SW-DELAYS").unwrap(), 3);
    // Rounding up, never down: 0.305 s is 30.5 periods.
    assert_eq!(delay_ticks(s(0.305), s(0.01), "SW-DELAYS").unwrap(), 31);
    assert_eq!(delay_ticks(s(0.4), s(0.3), "SW-DELAYS").unwrap(), 2);
    // A positive delay is at least one tick.
    assert_eq!(delay_ticks(s(1e-12), s(0.01), "SW-DELAYS").unwrap(), 1);
    assert_eq!(delay_ticks(s(5e-324), s(2.0), "SW-DELAYS").unwrap(), 1);
    // The longest delay, and one tick more.
    assert_eq!(
        delay_ticks(s(655.35), s(0.01), "SW-DELAYS").unwrap(),
        MAX_DELAY_TICKS
    );
    let error = delay_ticks(s(655.36), s(0.01), "SW-STOP").unwrap_err();
    assert_eq!(error.requirement, "SW-STOP");
    assert_eq!(
        delay_ticks(s(0.4), s(0.0), "SW-STOP")
            .unwrap_err()
            .requirement,
        "SW-DELAYS"
    );
    assert_eq!(
        delay_ticks(s(-0.4), s(0.01), "SW-PLAN-CONSISTENCY")
            .unwrap_err()
            .requirement,
        "SW-PLAN-CONSISTENCY"
    );
}

#[test]
fn every_millisecond_delay_converts_as_integer_arithmetic_says() {
    // Exhaustive over delays of 1 ms to 2 s and periods of 1 ms to 100 ms:
    // the f64 conversion agrees with ⌈d / p⌉ computed on integers.
    for period_ms in 1u32..=100 {
        let period = s(f64::from(period_ms) / 1000.0);
        for delay_ms in 1u32..=2000 {
            let expected = delay_ms.div_ceil(period_ms);
            let ticks = delay_ticks(s(f64::from(delay_ms) / 1000.0), period, "SW-DELAYS").unwrap();
            assert_eq!(u32::from(ticks), expected, "{delay_ms} ms / {period_ms} ms");
        }
    }
}

#[test]
fn the_paper_presets() {
    let edge = BehaviourConfig::edge_following().unwrap();
    assert_eq!(
        (edge.enter_delay().get(), edge.exit_delay().get()),
        (0.4, 0.26)
    );
    let furrow = BehaviourConfig::furrow_pursuing().unwrap();
    assert_eq!(
        (furrow.enter_delay().get(), furrow.exit_delay().get()),
        (0.5, 0.3)
    );
}

//= spec/pierre2022.md#sw-plan-consistency-line-consistent-with-the-planned-path
//= type=test
//# A behaviour's line MUST be consistent with the planned path when both the
//# lateral offset of the line's point closest to the robot, y_path −
//# y_line cos(θ̃_path − θ̃_line), and the heading difference, wrapped
//# θ̃_path − θ̃_line, are within the configured tolerances in absolute value.
#[test]
fn plan_consistency_by_hand() {
    let tolerance =
        PlanTolerance::new(Meters::new(0.25).unwrap(), Radians::new(0.2).unwrap()).unwrap();
    // Parallel line 0.2 m left of the path: the robot is 0.3 m left of the
    // path and 0.1 m left of the line.
    let parallel = line_relative_to_path(&error(0.1, 0.05), &error(0.3, 0.05)).unwrap();
    assert_abs_diff_eq!(parallel.offset.get(), 0.2, epsilon = 1e-12);
    assert_abs_diff_eq!(parallel.heading.get(), 0.0, epsilon = 1e-12);
    assert!(tolerance.is_consistent(&error(0.1, 0.05), &error(0.3, 0.05), HERE));
    assert!(!tolerance.is_consistent(&error(0.0, 0.05), &error(0.3, 0.05), HERE));

    // A line turned 0.3 rad left of the path (robot heading along the path):
    // offset 1 − cos 0.3 = 0.044 663 511 m, heading 0.3 rad > 0.2 rad.
    let turned = line_relative_to_path(&error(1.0, -0.3), &error(1.0, 0.0)).unwrap();
    assert_abs_diff_eq!(turned.offset.get(), 0.044_663_511, epsilon = 1e-9);
    assert_abs_diff_eq!(turned.heading.get(), 0.3, epsilon = 1e-12);
    assert!(!tolerance.is_consistent(&error(1.0, -0.3), &error(1.0, 0.0), HERE));

    // Headings wrap: 3.0 − (−3.0) = 6.0 rad is −0.283 rad.
    let wrapped = line_relative_to_path(&error(0.0, -3.0), &error(0.0, 3.0)).unwrap();
    assert_abs_diff_eq!(
        wrapped.heading.get(),
        6.0 - 2.0 * core::f64::consts::PI,
        epsilon = 1e-12
    );

    // Exp. 2, end of the third plot: the false rows run straight on while the
    // path turns left: 0.8 m off and 0.4 rad apart is inconsistent.
    assert!(!tolerance.is_consistent(&error(0.0, 0.0), &error(-0.8, -0.4), HERE));
    // An offset that overflows is inconsistent, not a panic.
    assert!(!tolerance.is_consistent(&error(-1e308, 0.0), &error(1e308, 0.0), HERE));
    assert!(line_relative_to_path(&error(-1e308, 0.0), &error(1e308, 0.0)).is_err());
}

/// A path along the x axis for `straight` metres, then a left arc of radius
/// `radius` over `arc` metres, sampled every 2 cm, with a 0.1 m smoothing
/// window (so its headings are those of the arc within 1e-2 rad).
fn straight_then_arc(straight: f64, radius: f64, arc: f64) -> ReferencePath<2048> {
    let step = 0.02;
    let mut points: Vec<Point2<World>> = (0..)
        .map(|i| f64::from(i) * step)
        .take_while(|x| *x < straight)
        .map(|x| Point2::new(x, 0.0).unwrap())
        .collect();
    for a in (0..)
        .map(|i| f64::from(i) * step)
        .take_while(|l| *l <= arc + step)
        .map(|l| l / radius)
    {
        points.push(Point2::new(straight + radius * a.sin(), radius * (1.0 - a.cos())).unwrap());
    }
    ReferencePath::from_waypoints(&points, PathConfig::new(Meters::new(0.1).unwrap()).unwrap())
        .unwrap()
}

//= spec/pierre2022.md#sw-plan-ahead-the-line-against-the-path-ahead
//= type=test
//# When a look-ahead distance d > 0 is configured, a line consistent at the
//# robot MUST still be inconsistent with the planned path when the offset of
//# its point d ahead of its point closest to the robot, measured from the
//# tangent of the path at s + d, exceeds the offset tolerance in absolute value.
#[test]
fn a_straight_line_where_the_path_turns_is_caught_ahead() {
    // Exp. 2's U-turn: radius 6 m, starting 10 m along the path. The robot is
    // on the path at its start, heading along it, and so is a line running
    // straight on (the volunteer plants).
    let path = straight_then_arc(10.0, 6.0, 8.0);
    let on = error(0.0, 0.0);
    let tolerance = PlanTolerance::new(Meters::new(0.25).unwrap(), Radians::new(0.05).unwrap())
        .unwrap()
        .with_lookahead(Meters::new(2.0).unwrap())
        .unwrap();
    let d = tolerance.lookahead();
    // At the robot the line agrees with the path, whatever the look-ahead.
    assert!(tolerance.is_consistent(&on, &on, HERE));
    // By hand, 0.2 m before the arc (where the smoothed tangent is the x
    // axis): the line's point 2 m on is (11.8, 0); the path 2 m on is 1.8 m
    // into the arc, at φ = 0.3 rad, P = (10 + R sin φ, R (1 − cos φ)); the
    // offset is (Q − P)·(−sin φ, cos φ) ≈ −0.274 m.
    let at = |s: f64| PathAhead::on_path(&path, Meters::new(s).unwrap(), d).unwrap();
    let phi: f64 = 1.8 / 6.0;
    let (px, py) = (10.0 + 6.0 * phi.sin(), 6.0 * (1.0 - phi.cos()));
    let expected = -(11.8 - px) * phi.sin() + (0.0 - py) * phi.cos();
    let relative = line_relative_to_path_ahead(&on, &on, &at(9.8)).unwrap();
    assert_abs_diff_eq!(relative.offset.get(), expected, epsilon = 1e-3);
    assert_abs_diff_eq!(relative.heading.get(), -phi, epsilon = 1e-3);
    assert!(!tolerance.is_consistent(&on, &on, &at(9.8)));
    // Walking up to the turn: consistent until the path 2 m ahead is about
    // sqrt(2 R 0.25) = 1.73 m into the arc, i.e. from 0.27 m before it.
    let first_caught = (0..200)
        .map(|i| 8.5 + f64::from(i) * 0.01)
        .find(|s| !tolerance.is_consistent(&on, &on, &at(*s)))
        .unwrap();
    assert!((first_caught - 9.73).abs() < 0.03, "{first_caught}");
    // A row curving gently (radius 400 m, Exp. 3) is followed by a line along
    // its tangent: 5 mm off 2 m ahead, consistent.
    let gentle = straight_then_arc(1.0, 400.0, 6.0);
    let ahead = PathAhead::on_path(&gentle, Meters::new(1.0).unwrap(), d).unwrap();
    let relative = line_relative_to_path_ahead(&on, &on, &ahead).unwrap();
    assert_abs_diff_eq!(relative.offset.get(), -0.005, epsilon = 1e-3);
    assert!(tolerance.is_consistent(&on, &on, &ahead));
    // Past the path's end the straight extension is used: a line along it is
    // consistent there.
    let end = PathAhead::on_path(&gentle, gentle.length(), d).unwrap();
    assert_abs_diff_eq!(end.distance().get(), 2.0);
    let relative = line_relative_to_path_ahead(&on, &on, &end).unwrap();
    assert_abs_diff_eq!(relative.offset.get(), 0.0, epsilon = 1e-9);
    // Negative look-aheads are refused, by name.
    let e = PathAhead::on_path(&path, Meters::new(1.0).unwrap(), Meters::new(-0.1).unwrap());
    assert_eq!(e.unwrap_err().requirement, "SW-PLAN-AHEAD");
    let e = tolerance.with_lookahead(Meters::new(-0.1).unwrap());
    assert_eq!(e.unwrap_err().requirement, "SW-PLAN-AHEAD");
}

//= spec/guidance.md#gd-plan-entry-a-line-entered-only-near-the-path-s-heading
//= type=test
//# An entry heading that is negative or larger than the tolerance's largest
//# heading MUST be refused with `GD-PLAN-ENTRY`.
#[test]
fn an_entry_heading_beyond_the_largest_heading_is_refused() {
    let tolerance =
        PlanTolerance::new(Meters::new(0.3).unwrap(), Radians::new(0.2).unwrap()).unwrap();
    assert_eq!(tolerance.entry_heading(), None);
    for bad in [-1e-9, -0.1, 0.2 + 1e-9, 3.0] {
        let e = tolerance.with_entry_heading(Radians::new(bad).unwrap());
        assert_eq!(e.unwrap_err().requirement, "GD-PLAN-ENTRY", "{bad}");
    }
    for good in [0.0, 0.1, 0.2] {
        let t = tolerance
            .with_entry_heading(Radians::new(good).unwrap())
            .unwrap();
        assert_eq!(t.entry_heading(), Some(Radians::new(good).unwrap()));
        // The other tolerances are kept.
        assert_eq!(
            (t.max_offset(), t.max_heading()),
            (tolerance.max_offset(), tolerance.max_heading())
        );
    }
}

/// An angle wrapped to (−π, π].
fn wrap(angle: f64) -> f64 {
    fieldguide::geometry::units::wrap_angle(Radians::new(angle).unwrap()).get()
}

fn angle() -> impl Strategy<Value = f64> {
    -3.0..3.0f64
}

proptest! {
    /// Independent geometry: the path is the x axis, the line passes through
    /// (x0, d) with heading φ, the robot is at (rx, ry) with heading ψ. The
    /// line's point closest to the robot has lateral coordinate
    /// ry − y_line cos φ, and the line's heading relative to the path is φ.
    #[test]
    fn the_offset_is_the_line_point_closest_to_the_robot(
        rx in -5.0..5.0f64, ry in -5.0..5.0f64, psi in angle(),
        x0 in -5.0..5.0f64, d in -5.0..5.0f64, phi in -1.5..1.5f64,
    ) {
        // Signed distance of the robot from the line, positive to its left.
        let y_line = -phi.sin() * (rx - x0) + phi.cos() * (ry - d);
        let closest = (rx + y_line * phi.sin(), ry - y_line * phi.cos());
        // The closest point lies on the line.
        let on_line = -phi.sin() * (closest.0 - x0) + phi.cos() * (closest.1 - d);
        prop_assert!(on_line.abs() < 1e-9);
        let path = error(ry, wrap(psi));
        let line = error(y_line, wrap(psi - phi));
        let relative = line_relative_to_path(&line, &path).unwrap();
        prop_assert!((relative.offset.get() - closest.1).abs() < 1e-9);
        prop_assert!((relative.heading.get() - phi).abs() < 1e-9);
    }

    //= spec/pierre2022.md#sw-plan-ahead-the-line-against-the-path-ahead
    //= type=test
    //# With d = 0 the offset at the robot MUST equal that of SW-PLAN-CONSISTENCY.
    /// The same geometry, looked at `ahead` metres further along the straight
    /// path: the line's point that far along it from the closest one has
    /// lateral coordinate closest.y + ahead sin φ (SW-PLAN-AHEAD); with
    /// ahead = 0 this is [`line_relative_to_path`] exactly.
    #[test]
    fn ahead_on_a_straight_path_moves_along_the_line(
        ry in -5.0..5.0f64, psi in angle(), y_line in -5.0..5.0f64,
        phi in -1.5..1.5f64, s in -5.0..15.0f64, ahead in 0.0..5.0f64,
    ) {
        let path_geometry: ReferencePath<4> = ReferencePath::from_waypoints(
            &[Point2::new(0.0, 0.0).unwrap(), Point2::new(10.0, 0.0).unwrap()],
            PathConfig::default(),
        ).unwrap();
        let path = error(ry, wrap(psi));
        let line = error(y_line, wrap(psi - phi));
        let here = line_relative_to_path(&line, &path).unwrap();
        let at = |d: f64| PathAhead::on_path(&path_geometry, Meters::new(s).unwrap(),
            Meters::new(d).unwrap()).unwrap();
        let there = line_relative_to_path_ahead(&line, &path, &at(ahead)).unwrap();
        prop_assert!((there.offset.get() - (here.offset.get() + ahead * phi.sin())).abs() < 1e-9);
        prop_assert!((there.heading.get() - phi).abs() < 1e-9);
        prop_assert_eq!(line_relative_to_path_ahead(&line, &path, &at(0.0)).unwrap(), here);
    }

    /// Mirroring left and right keeps consistency; a line equal to the path
    /// is always consistent; any finite input gives an answer.
    #[test]
    fn consistency_is_mirror_symmetric_and_total(
        y_line in prop::num::f64::NORMAL | prop::num::f64::ZERO,
        y_path in -10.0..10.0f64,
        a_line in angle(), a_path in angle(),
        max_offset in 0.0..2.0f64, max_heading in 0.0..3.1f64,
    ) {
        let tolerance = PlanTolerance::new(Meters::new(max_offset).unwrap(),
            Radians::new(max_heading).unwrap()).unwrap();
        let line = error(y_line, a_line);
        let path = error(y_path, a_path);
        prop_assert_eq!(
            tolerance.is_consistent(&line, &path, HERE),
            tolerance.is_consistent(&line.mirrored(), &path.mirrored(), HERE)
        );
        prop_assert!(tolerance.is_consistent(&path, &path, HERE));
    }
}
