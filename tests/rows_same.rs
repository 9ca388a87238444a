//! The line finder (`ruby::Ruby`) against a straightforward reference of
//! the same algorithm (`rows_reference`, Guyonneau 2022, Alg. 1 and its
//! refinements; `spec/guyonneau2022.md`, RUBY-*): on drives along the
//! paper's four crops and on random fields, every variant gives the same
//! lines, point counts and energies, bit for bit, call after call.
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::cast_precision_loss
)]

#[path = "crop_scans/mod.rs"]
mod crop_scans;
#[path = "rows_reference/mod.rs"]
mod rows_reference;

use crop_scans::{crop, Lidar, Mount, Pose};
use fieldguide::perception::rows::points::{
    merge_runs, scan_points, scan_points_with, Points, Rays, RowPoint,
};
use fieldguide::perception::rows::ruby::{Found, Ruby, RubyConfig, RubyParams, Variant};
use fieldguide::{Point2, Robot};
use proptest::prelude::*;
use rows_reference::{RefFound, Reference};

const N: usize = 512;

/// The points each variant works on (Z, or Z* for the one-point variants)
/// along `scans` scans of a drive between two rows of crop `n`.
fn drive(n: usize, seed: u64, variant: Variant, scans: usize) -> Vec<Vec<RowPoint>> {
    let mut spec = crop(n, seed, 0.75);
    spec.weeds *= 4;
    spec.length = 40.0;
    let field = spec.build();
    let mount = Mount::front(0.3);
    let transform = mount.transform();
    let lidar = Lidar::paper();
    let merge = RubyParams::authors(variant).merge_distance;
    (0..scans)
        .map(|k| {
            let along = 1.0 + 0.1 * k as f64;
            let robot = field.between(1, 2, along).compose(&Pose::new(
                0.0,
                0.05 * (along * 1.5).sin(),
                0.02 * (along * 0.7).cos(),
            ));
            let raw = field.cast(&robot, &mount, &lidar, seed ^ k as u64);
            let mut points = Points::<N>::new();
            scan_points(&raw.scan(), &transform, &mut points).unwrap();
            if variant.one_point() {
                merge_runs(&mut points, merge);
            }
            points.to_vec()
        })
        .collect()
}

fn params(variant: Variant, seed: u64) -> RubyParams {
    let mut p = RubyParams::authors(variant);
    p.seed = seed;
    p
}

/// Runs both finders over `scans` in order and says where they first
/// differ.
fn compare(p: RubyParams, scans: &[Vec<RowPoint>]) -> Result<usize, String> {
    let mut fast = Ruby::<N>::new(RubyConfig::new(p).unwrap());
    let mut reference = Reference::new(p);
    let mut models = 0;
    for (k, points) in scans.iter().enumerate() {
        let f = fast.find(points);
        let r = reference.find(points);
        if !same_found(&f, &r) {
            return Err(format!("scan {k}: {f:?} against {r:?}"));
        }
        let (fm, rm) = (fast.models(), reference.models());
        let same_models = fm.len() == rm.len()
            && fm.iter().zip(rm).all(|(f, r)| {
                f.line.slope().to_bits() == r.a.to_bits()
                    && f.line.intercept().get().to_bits() == r.b.to_bits()
                    && f.points == r.points
                    && f.energy.to_bits() == r.energy.to_bits()
            });
        if !same_models {
            return Err(format!("scan {k}: models {fm:?} against {rm:?}"));
        }
        models += fm.len();
    }
    Ok(models)
}

fn same_found(f: &Found, r: &RefFound) -> bool {
    f.energy.to_bits() == r.energy.to_bits()
        && f.start_energy.to_bits() == r.start_energy.to_bits()
        && f.points == r.points
        && f.accepted == r.accepted
}

//= spec/guyonneau2022.md#ruby-iteration-alg-1-iterations
//= type=test
//# Each call MUST start from the previous call's set of lines (the empty
//# set on the first call), refitted to the points they attach on this scan,
//# and
//# MUST run the configured number of iterations, unless it ends early
//# (below), each of which seeds new models, merges, re-attaches, deletes and
//# re-attaches again, and is kept only when its energy is not above the
//# energy of the set kept before it.
#[test]
fn every_variant_matches_the_reference_bit_for_bit_on_the_crops() {
    for variant in Variant::ALL {
        for n in 1..=4 {
            for seed in [1, 2] {
                let scans = drive(n, seed, variant, 60);
                let models = compare(params(variant, seed * 7 + n as u64), &scans)
                    .unwrap_or_else(|e| panic!("{} crop {n} seed {seed}: {e}", variant.name()));
                // Lines were found: the comparison is not of empty sets.
                assert!(models >= 60 * 2, "{} crop {n}: {models}", variant.name());
            }
        }
    }
}

/// One ray table against the rays computed afresh: the same points, bit for
/// bit, when the LiDAR's geometry changes between scans and for rays beyond
/// the table.
//= spec/guyonneau2022.md#rows-points-scan-points-in-the-robot-frame
//= type=test
//# Every ray whose range the scan's limits accept MUST become the point
//# (r cos φ, r sin φ) of the sensor frame, φ = start + k · increment, moved into
//# the robot frame through the sensor's mount; rays are kept in ray order.
#[test]
fn a_table_of_the_rays_gives_the_same_points() {
    let field = crop(4, 3, 0.75).build();
    let mount = Mount::front(0.3);
    let transform = mount.transform();
    let mut wide = Lidar::paper();
    wide.rays = 541;
    wide.start = -2.35;
    wide.increment = 4.7 / 540.0;
    let mut short: Rays<100> = Rays::new();
    let mut long: Rays<N> = Rays::new();
    let mut compared = 0;
    for k in 0_u32..12 {
        let lidar = if k % 3 == 2 { wide } else { Lidar::paper() };
        let robot = field.between(1, 2, 1.0 + 0.3 * f64::from(k));
        let raw = field.cast(&robot, &mount, &lidar, u64::from(k));
        let scan = raw.scan();
        let mut plain = Points::<N>::new();
        let g = scan_points(&scan, &transform, &mut plain).unwrap();
        for tabled in [
            {
                let mut out = Points::<N>::new();
                let h = scan_points_with(&scan, &transform, &mut short, &mut out).unwrap();
                assert_eq!(h, g);
                out
            },
            {
                let mut out = Points::<N>::new();
                let h = scan_points_with(&scan, &transform, &mut long, &mut out).unwrap();
                assert_eq!(h, g);
                out
            },
        ] {
            assert_eq!(tabled.len(), plain.len());
            for (t, p) in tabled.iter().zip(&plain) {
                assert_eq!(t.position.x().to_bits(), p.position.x().to_bits());
                assert_eq!(t.position.y().to_bits(), p.position.y().to_bits());
                assert_eq!(t.returns, p.returns);
            }
            compared += plain.len();
        }
    }
    assert!(compared > 12 * 100, "{compared}");
}

fn variant() -> impl Strategy<Value = Variant> {
    prop::sample::select(Variant::ALL.to_vec())
}

/// Three to six noisy rows, weeds, and a few scans of it moved a little.
fn field() -> impl Strategy<Value = Vec<Vec<RowPoint>>> {
    (
        3_usize..=6,
        0.4_f64..1.6,
        -0.3_f64..0.3,
        prop::collection::vec((0.1_f64..4.0, -3.0_f64..3.0), 0..80),
        any::<u64>(),
    )
        .prop_map(|(rows, spacing, slope, weeds, seed)| {
            let mut noise = crop_scans::SplitMix64::new(seed);
            (0..3)
                .map(|scan| {
                    let shift = 0.03 * scan as f64;
                    let mut points = Vec::new();
                    for r in 0..rows {
                        let b = (r as f64 - (rows as f64 - 1.0) / 2.0) * spacing + shift;
                        for i in 0..40 {
                            let x = 0.2 + 0.1 * i as f64;
                            let y = slope * x + b + 0.01 * noise.gaussian();
                            points.push((x, y));
                        }
                    }
                    points.extend(weeds.iter().copied());
                    // In angle order, as a scan gives them.
                    points.sort_by(|p, q| p.1.atan2(p.0).total_cmp(&q.1.atan2(q.0)));
                    points
                        .into_iter()
                        .map(|(x, y)| RowPoint {
                            position: Point2::<Robot>::new(x, y).unwrap(),
                            returns: 1,
                        })
                        .collect()
                })
                .collect()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    //= spec/guyonneau2022.md#ruby-reattach-points-re-attached
    //= type=test
    //# Every point MUST be attached to the model closest to it, or to several
    //# models (every model within the outlier distance) when points are shared,
    //# and MUST be an outlier when no model lies within the outlier distance;
    //# a model left with fewer than three points MUST then be removed and its
    //# points re-attached to the models left.
    #[test]
    fn random_fields_match_the_reference_bit_for_bit(
        scans in field(), v in variant(), seed in any::<u64>()
    ) {
        let result = compare(params(v, seed), &scans);
        prop_assert!(result.is_ok(), "{}: {:?}", v.name(), result);
    }
}
