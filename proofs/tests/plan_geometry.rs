//! A bolero harness over the plan-consistency geometry (SW-PLAN-CONSISTENCY,
//! SW-PLAN-AHEAD, LIB-FINITE): for any `f64` inputs, NaN and infinities
//! included, the path ahead and the line's offset are either finite values or
//! named errors, never a panic or a NaN, and checking the line ahead only
//! ever adds a condition to the check at the robot.
//!
//! Random search here (`cargo test`); with `cargo bolero test` it is a
//! coverage-guided fuzz target. It is not a Kani proof: the geometry goes
//! through `sin`, `cos` and `atan2` of libm, which bounded model checking of
//! floating point does not finish on.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::sync::atomic::{AtomicU64, Ordering};

use bolero::check;
use fieldguide::geometry::path::{PathConfig, ReferencePath};
use fieldguide::supervisor::switching::{
    line_relative_to_path, line_relative_to_path_ahead, PathAhead, PlanTolerance,
};
use fieldguide::{Curvature, Meters, Point2, Radians, TrackingError, World};
use fieldguide_proofs::evidence::{self, Kind};

/// One case: two tracking errors, a two-segment path, where the robot
/// projects on it, the look-ahead and the tolerances.
type Case = ([f64; 4], [f64; 6], f64, f64, [f64; 2]);

fn error(y: f64, angular_deviation: f64) -> Option<TrackingError> {
    Some(TrackingError {
        y: Meters::new(y).ok()?,
        angular_deviation: Radians::new(angular_deviation).ok()?,
        curvature: Curvature::ZERO,
        curvature_ahead: Curvature::ZERO,
    })
}

#[test]
fn plan_geometry_is_total_and_the_look_ahead_only_adds_a_condition() {
    let record = evidence::start("plan geometry, random f64 cases", Kind::Harness);
    let count = AtomicU64::new(0);
    check!().with_type::<Case>().for_each(
        |&([yl, al, yp, ap], corners, s, d, [max_offset, max_heading])| {
            count.fetch_add(1, Ordering::Relaxed);
            let (Some(line), Some(path)) = (error(yl, al), error(yp, ap)) else {
                return;
            };
            let points: Option<Vec<Point2<World>>> = corners
                .chunks_exact(2)
                .map(|c| Point2::new(c[0], c[1]).ok())
                .collect();
            let Some(points) = points else { return };
            // Any waypoints: a path, or a named refusal.
            let Ok(reference) = ReferencePath::<4>::from_waypoints(&points, PathConfig::default())
            else {
                return;
            };
            let (Ok(s), Ok(d)) = (Meters::new(s), Meters::new(d)) else {
                return;
            };
            let ahead = match PathAhead::on_path(&reference, s, d) {
                Ok(ahead) => ahead,
                Err(e) => {
                    assert!(
                        ["SW-PLAN-AHEAD", "LIB-FINITE"].contains(&e.requirement),
                        "{e}"
                    );
                    return;
                }
            };
            for relative in [
                line_relative_to_path(&line, &path),
                line_relative_to_path_ahead(&line, &path, &ahead),
            ] {
                match relative {
                    Ok(r) => {
                        assert!(r.offset.get().is_finite(), "{r:?}");
                        assert!(r.heading.get().abs() <= core::f64::consts::PI, "{r:?}");
                    }
                    Err(e) => assert_eq!(e.requirement, "LIB-FINITE"),
                }
            }
            let (Ok(max_offset), Ok(max_heading)) =
                (Meters::new(max_offset), Radians::new(max_heading))
            else {
                return;
            };
            let Ok(here) = PlanTolerance::new(max_offset, max_heading) else {
                return;
            };
            let there = here.with_lookahead(d).unwrap();
            // Consistent with the path ahead implies consistent at the robot.
            if there.is_consistent(&line, &path, &ahead) {
                assert!(here.is_consistent(&line, &path, &PathAhead::HERE));
            }
        },
    );
    record.finish(&evidence::harness(
        &["SW-PLAN-AHEAD", "LIB-FINITE"],
        count.into_inner(),
        None,
    ));
}
