//! Entries without a swing (`spec/guidance.md`, GD-ENTRY): the rule's
//! reference against its closed form, the lead point that closes without
//! overshoot, the error the laws get and the refused rules. The closed loop
//! is in `sim/tests/entry.rs`.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    clippy::cast_precision_loss,
    clippy::as_conversions
)]

use fieldguide::guidance::entry::ENTRY_SPAN;
use fieldguide::guidance::{Entry, EntryParams};
use fieldguide::{Meters, Radians, TrackingError};

fn m(v: f64) -> Meters {
    Meters::new(v).unwrap()
}

fn rule(closing: f64, lead: f64) -> Entry {
    Entry::new(&EntryParams {
        closing: m(closing),
        lead: m(lead),
    })
    .unwrap()
}

/// Closing lengths, leads and starts swept by the tests (μ = ℓ included).
const CLOSINGS: [f64; 5] = [0.3, 1.0, 2.0, 2.000_000_000_1, 5.0];
const LEADS: [f64; 3] = [0.5, 2.0, 3.0];
const STARTS: [f64; 4] = [-0.45, -0.05, 0.2, 0.3];
/// Tangents of the robot's heading from the path's at the start.
const SLOPES: [f64; 4] = [0.0, -0.1, 0.05, 0.15];

//= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
//= type=test
//# An entry rule whose closing length or lead is not in (0, 1000] m MUST be
//# refused with `GD-ENTRY`.
#[test]
fn rules_outside_the_lengths_are_refused() {
    for bad in [0.0, -1.0, 1000.5, 1e300] {
        for params in [
            EntryParams {
                closing: m(bad),
                lead: m(2.0),
            },
            EntryParams {
                closing: m(1.0),
                lead: m(bad),
            },
        ] {
            assert_eq!(
                Entry::new(&params).unwrap_err().requirement,
                "GD-ENTRY",
                "{bad}"
            );
        }
    }
    assert_eq!(rule(1000.0, 1e-9).params().closing, m(1000.0));
}

//= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
//= type=test
//# The reference MUST equal r₀ s(d) + ℓ t₀ p(d), r₀ the start's lateral
//# error to the line, t₀ the tangent of the robot's heading from the path's
//# when the entry started (from the line's when the path had no projection),
//# s(d) = (μ e^(−d/μ) − ℓ e^(−d/ℓ)) / (μ − ℓ) and
//# p(d) = μ (e^(−d/μ) − e^(−d/ℓ)) / (μ − ℓ), or (1 + d/ℓ) e^(−d/ℓ) and
//# (d/ℓ) e^(−d/ℓ) when μ = ℓ, d the odometry distance since the entry
//# started, μ the closing length and ℓ the lead, and MUST be zero once d
//# reaches twenty times the longer of μ and ℓ.
#[test]
fn the_reference_starts_at_the_error_and_closes_on_the_line() {
    for mu in CLOSINGS {
        for lead in LEADS {
            let entry = rule(mu, lead);
            let end = ENTRY_SPAN * mu.max(lead);
            for r0 in STARTS {
                let (r, rate) = entry.reference(m(r0), m(0.0));
                assert!((r.get() - r0).abs() < 1e-12, "{mu} {lead} {r0}");
                assert!(rate.abs() < 1e-9, "starts with the robot's heading");
                // A negative distance counts as none.
                assert_eq!(
                    entry.reference(m(r0), m(-3.0)),
                    entry.reference(m(r0), m(0.0))
                );
                let mut previous = r0.abs();
                for k in 1..=400 {
                    let d = end * f64::from(k) / 400.0;
                    let (r, rate) = entry.reference(m(r0), m(d));
                    // μ within 10⁻¹⁰ of ℓ: the closed form cancels in floating
                    // point, its limit is within 10⁻⁹ of it.
                    let expected = if (mu - lead).abs() < 1e-9 {
                        r0 * (1.0 + d / lead) * (-d / lead).exp()
                    } else {
                        r0 * (mu * (-d / mu).exp() - lead * (-d / lead).exp()) / (mu - lead)
                    };
                    if d < end {
                        assert!(
                            (r.get() - expected).abs() < 1e-6 * r0.abs(),
                            "{mu} {lead} {d}"
                        );
                    } else {
                        assert_eq!(r.get(), 0.0);
                        assert_eq!(rate, 0.0);
                        assert!(entry.is_over(m(r0), m(d)));
                    }
                    // Never past the line, never away from it.
                    assert!(r.get() * r0 >= 0.0 && r.get().abs() <= previous + 1e-15);
                    previous = r.get().abs();
                    // The rate is the derivative of the reference.
                    if d + 1e-4 < end && d > 1e-4 {
                        let ahead = entry.reference(m(r0), m(d + 1e-4)).0.get();
                        let behind = entry.reference(m(r0), m(d - 1e-4)).0.get();
                        let numeric = (ahead - behind) / 2e-4;
                        assert!(
                            (rate - numeric).abs() < 1e-5,
                            "{mu} {lead} {d}: {rate} {numeric}"
                        );
                    }
                }
                assert!(!entry.is_over(m(r0), m(0.5 * end)));
            }
        }
    }
}

/// The property the rule is built for: the point ℓ ahead of the rear axle of
/// a vehicle on the reference, r + ℓ r', nears the line as (r₀ + ℓ t₀) e^(−d/μ),
/// from where the robot's heading t₀ puts it: it never passes the line, so
/// with ℓ the wheelbase neither axle swings across. The reference starts at
/// the robot, along its heading: r(0) = r₀, r'(0) = t₀.
//= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
//= type=test
//# The reference MUST equal r₀ s(d) + ℓ t₀ p(d), r₀ the start's lateral
//# error to the line, t₀ the tangent of the robot's heading from the path's
#[test]
fn the_lead_point_closes_without_overshoot() {
    for mu in CLOSINGS {
        for lead in LEADS {
            let entry = rule(mu, lead);
            for (r0, t0) in STARTS.iter().flat_map(|&r0| SLOPES.map(|t0| (r0, t0))) {
                let (r, rate) = entry.reference_with_heading(m(r0), t0, m(0.0));
                assert!((r.get() - r0).abs() < 1e-12 && (rate - t0).abs() < 1e-12);
                let front = r0 + lead * t0;
                for k in 0..200 {
                    let d = 0.05 * f64::from(k);
                    let (r, rate) = entry.reference_with_heading(m(r0), t0, m(d));
                    let point = r.get() + lead * rate;
                    if d < ENTRY_SPAN * mu.max(lead) {
                        let expected = front * (-d / mu).exp();
                        assert!(
                            (point - expected).abs() < 1e-6 * (r0.abs() + lead * t0.abs()),
                            "{mu} {lead} {r0} {t0} {d}"
                        );
                    }
                    assert!(point * front >= -1e-15, "{mu} {lead} {d}: {point}");
                }
                // Parallel to the path, the reference of before.
                if t0 == 0.0 {
                    let d = m(1.3);
                    assert_eq!(
                        entry.reference_with_heading(m(r0), t0, d),
                        entry.reference(m(r0), d)
                    );
                }
            }
        }
    }
}

//= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
//= type=test
//# During an entry, the behaviour's law MUST get the error to its line
//# shifted sideways by the reference: the lateral error less the reference,
//# the angular deviation less the angle of the reference's change per metre
//# travelled seen from the line, r'(d) − s(d) tan h, h the line's heading
//# minus the path's (zero when the path has no projection).
#[test]
fn the_law_gets_the_error_to_the_reference() {
    let entry = rule(1.0, 2.0);
    let line = TrackingError::to_straight_line(m(-0.28), Radians::new(0.02).unwrap());
    for h in [0.0, 0.06, -0.3] {
        let heading = Radians::new(h).unwrap();
        for d in [0.0, 0.4, 1.5, 3.0, 45.0] {
            let (r, rate) = entry.reference(m(-0.3), m(d));
            let shape = r.get() / -0.3;
            let error = entry
                .reference_error(&line, m(-0.3), m(d), heading)
                .unwrap();
            assert!((error.y.get() - (-0.28 - r.get())).abs() < 1e-12);
            let turned = (rate - shape * h.tan()).atan();
            assert!(
                (error.angular_deviation.get() - (0.02 - turned)).abs() < 1e-12,
                "{h} {d}"
            );
            assert_eq!(error.curvature.get(), 0.0);
        }
        // At the start the law sees the robot on its reference, heading
        // along the path: the line's heading plus h.
        let start = entry
            .reference_error(&line, m(-0.28), m(0.0), heading)
            .unwrap();
        assert!(start.y.get().abs() < 1e-12);
        assert!(
            (start.angular_deviation.get() - (0.02 + h)).abs() < 1e-12,
            "{h}"
        );
    }
}

proptest::proptest! {
    /// For any rule, start and distance: the reference stays between the
    /// start and the line (it never passes the line), and its offset changes
    /// by at most |r₀| / (e min(μ, ℓ)) per metre.
    //= spec/guidance.md#gd-entry-entry-into-a-behaviour-without-a-swing
    //= type=test
    //# The reference MUST equal r₀ s(d) + ℓ t₀ p(d), r₀ the start's lateral
    //# error to the line, t₀ the tangent of the robot's heading from the path's
    #[test]
    fn the_reference_never_passes_the_line_and_turns_gently(
        mu in 0.05_f64..20.0,
        lead in 0.05_f64..20.0,
        r0 in -2.0_f64..2.0,
        d in 0.0_f64..400.0,
    ) {
        let entry = rule(mu, lead);
        let (r, rate) = entry.reference(m(r0), m(d));
        proptest::prop_assert!(r.get() * r0 >= 0.0 && r.get().abs() <= r0.abs() * (1.0 + 1e-12));
        let bound = r0.abs() / (core::f64::consts::E * mu.min(lead));
        proptest::prop_assert!(rate.abs() <= bound * (1.0 + 1e-9) + 1e-15, "{rate} {bound}");
    }
}
