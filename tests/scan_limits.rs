//! The sensor's valid range interval of a planar LiDAR scan
//! (`spec/library.md`, LIB-SCAN): which limits are accepted, and which
//! ranges count as returns.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp
)]

use fieldguide::perception::{RangeLimits, MAX_RANGE};
use fieldguide::Meters;

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

//= spec/library.md#lib-scan-one-planar-lidar-scan
//= type=test
//# Range limits MUST be refused, with an error naming the requirement,
//# unless 0 ≤ min < max ≤ 1e6 m.
#[test]
fn limits_are_checked() {
    assert!(RangeLimits::new(m(0.0), m(MAX_RANGE)).is_ok());
    for (lo, hi) in [(1.0, 1.0), (2.0, 1.0), (-0.1, 1.0), (0.0, 1.0e6 + 1.0)] {
        let err = RangeLimits::new(m(lo), m(hi)).unwrap_err();
        assert_eq!(err.requirement, "LIB-SCAN");
    }
}

//= spec/library.md#lib-scan-one-planar-lidar-scan
//= type=test
//# A range MUST be used only when it is finite and lies in the sensor's
//# valid interval [min, max); any other range, `max` itself included,
//# MUST be treated as no return.
#[test]
fn accepted_ranges_are_finite_and_in_the_half_open_interval() {
    let l = RangeLimits::new(m(0.1), m(20.0)).unwrap();
    assert!((l.min() - 0.1).abs() < 1e-15 && (l.max() - 20.0).abs() < 1e-15);
    for r in [0.1, 5.0, 19.999_999] {
        assert!(l.accepts(r), "{r}");
    }
    for r in [
        0.099_999,
        20.0,
        20.1,
        -1.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        assert!(!l.accepts(r), "{r}");
    }
}
