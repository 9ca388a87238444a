//! A GNSS fix with its quality (`spec/guidance.md`, GD-FIX-QUALITY): the
//! rule alone, then path tracking on a straight path in a kinematic
//! closed loop, the receiver's fix turning float (a jump of 0.3-1 m) or
//! vanishing, with odometry that drifts.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::as_conversions,
    clippy::arithmetic_side_effects,
    clippy::float_cmp,
    clippy::cast_precision_loss
)]

mod common;

use common::{fix_rule as rule, m, straight_path, PATH_N};
use fieldguide::guidance::{
    FixKind, FixQuality, FixRule, FixRuleParams, FixUse, Guidance, GuidanceConfig, Mode, PlanPose,
    TickInput, TickOutput,
};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::presets::{pierre2022_path, Pierre2022, Pierre2022Params};
use fieldguide::{Meters, Odom, Pose2, World};

const PERIOD: f64 = 0.01;
const WHEELBASE: f64 = 2.0;

const FIXED: FixQuality = FixQuality {
    kind: FixKind::RtkFixed,
    accuracy: Some(Meters::ZERO),
};

fn float(sigma: f64) -> FixQuality {
    FixQuality {
        kind: FixKind::RtkFloat,
        accuracy: Some(m(sigma)),
    }
}

fn params(fix: Option<FixRuleParams>) -> Pierre2022Params {
    let mut p = pierre2022_path().unwrap();
    p.plan_dead_reckoning = Some(m(20.0));
    p.fix = fix;
    p
}

/// The receiver's fix of one tick and its quality.
type Reported = Option<(Pose2<World>, FixQuality)>;

/// What the receiver gives in one tick, from the true pose (x, y, ψ).
type Receiver<'r> = dyn Fn(f64, (f64, f64, f64)) -> Reported + 'r;

/// One tick's record: time, true pose, the core's output.
struct Tick {
    pose: (f64, f64, f64),
    steering: f64,
    out: TickOutput<Sideslip, 2>,
}

/// Drives path tracking in a kinematic bicycle loop (the command's speed
/// and steering applied for one period, the steering at once) from
/// (0, `y0`, 0) for `duration` seconds; the odometry is the true pose with
/// its heading drifting by `yaw_drift` rad per metre travelled.
fn drive(
    g: &mut Pierre2022<'_, PATH_N>,
    y0: f64,
    duration: f64,
    yaw_drift: f64,
    receiver: &Receiver<'_>,
) -> Vec<Tick> {
    let (mut x, mut y, mut psi) = (0.0, y0, 0.0_f64);
    let (mut ox, mut oy, mut opsi) = (0.0, y0, 0.0_f64);
    let mut ticks = Vec::new();
    let steps = (duration / PERIOD).round() as u32;
    for k in 0..steps {
        let t = f64::from(k) * PERIOD;
        let gnss = receiver(t, (x, y, psi));
        let input = TickInput {
            scans: &[],
            gnss: gnss.map(|(p, _)| p),
            odometry: Pose2::<Odom>::new(ox, oy, opsi).unwrap(),
            extra: Sideslip::ZERO,
        };
        let out = match gnss {
            Some((_, quality)) => g.step_with_fix(&input, &quality).unwrap(),
            None => g.step(&input).unwrap(),
        };
        let (v, delta) = out.command.map_or((0.0, 0.0), |c| {
            (
                c.command.speed().get(),
                c.command.steering().map_or(0.0, |s| s.get()),
            )
        });
        ticks.push(Tick {
            pose: (x, y, psi),
            steering: delta,
            out,
        });
        let ds = v * PERIOD;
        let dpsi = ds * delta.tan() / WHEELBASE;
        x += ds * (psi + dpsi / 2.0).cos();
        y += ds * (psi + dpsi / 2.0).sin();
        psi += dpsi;
        let odpsi = dpsi + yaw_drift * ds;
        ox += ds * (opsi + odpsi / 2.0).cos();
        oy += ds * (opsi + odpsi / 2.0).sin();
        opsi += odpsi;
    }
    ticks
}

fn pose(p: (f64, f64, f64)) -> Pose2<World> {
    Pose2::new(p.0, p.1, p.2).unwrap()
}

//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# A fix rule whose largest accuracy is not positive, whose path
//# dead-reckoning distance is negative, whose rejoin slope is not in (0, 1]
//# or whose rejoin curvature is not positive MUST be refused with
//# `GD-FIX-QUALITY`.
#[test]
fn a_fix_rule_out_of_its_ranges_is_refused() {
    let bad = [
        FixRuleParams {
            max_accuracy: Meters::ZERO,
            ..rule()
        },
        FixRuleParams {
            max_accuracy: m(-0.1),
            ..rule()
        },
        FixRuleParams {
            path_dead_reckoning: m(-1.0),
            ..rule()
        },
        FixRuleParams {
            rejoin_slope: 0.0,
            ..rule()
        },
        FixRuleParams {
            rejoin_slope: 1.5,
            ..rule()
        },
        FixRuleParams {
            rejoin_slope: f64::NAN,
            ..rule()
        },
        FixRuleParams {
            rejoin_curvature: 0.0,
            ..rule()
        },
        FixRuleParams {
            rejoin_curvature: -0.05,
            ..rule()
        },
        FixRuleParams {
            rejoin_curvature: f64::NAN,
            ..rule()
        },
    ];
    for p in bad {
        assert_eq!(FixRule::new(&p).unwrap_err().requirement, "GD-FIX-QUALITY");
        let config = GuidanceConfig::new(&params(Some(p)));
        assert_eq!(config.unwrap_err().requirement, "GD-FIX-QUALITY");
    }
    let edge = FixRuleParams {
        path_dead_reckoning: Meters::ZERO,
        rejoin_slope: 1.0,
        rejoin_curvature: f64::INFINITY,
        ..rule()
    };
    assert!(FixRule::new(&edge).is_ok());
    let config = GuidanceConfig::new(&params(Some(rule()))).unwrap();
    assert_eq!(config.fix().unwrap().params(), &rule());
}

//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# A fix MUST be good exactly when its kind is at most the rule's worst kind
//# (RTK fixed, then float, single, dead-reckoned) and its horizontal accuracy,
//# when the receiver gives one, is at least zero and at most the rule's largest
//# accuracy.
#[test]
fn a_fix_is_good_by_its_kind_and_its_accuracy() {
    let kinds = [
        FixKind::RtkFixed,
        FixKind::RtkFloat,
        FixKind::Single,
        FixKind::DeadReckoned,
    ];
    for (w, worst) in kinds.iter().enumerate() {
        let r = FixRule::new(&FixRuleParams {
            worst_kind: *worst,
            ..rule()
        })
        .unwrap();
        for (k, kind) in kinds.iter().enumerate() {
            for (sigma, within) in [
                (None, true),
                (Some(0.0), true),
                (Some(0.05), true),
                (Some(0.0501), false),
                (Some(-0.01), false),
                (Some(3.0), false),
            ] {
                let q = FixQuality {
                    kind: *kind,
                    accuracy: sigma.map(m),
                };
                assert_eq!(
                    r.accepts(&q),
                    k <= w && within,
                    "{kind:?} {sigma:?} {worst:?}"
                );
                let p = Some(pose((1.0, 2.0, 0.0)));
                assert_eq!(r.filter(p, &q).is_some(), k <= w && within);
                assert_eq!(r.filter(None, &q), None);
            }
        }
    }
    // What `step` assumes is good under any rule.
    assert!(FixRule::new(&rule())
        .unwrap()
        .accepts(&FixQuality::RTK_FIXED));
}

/// The receiver of the closed loops: fixed with the true pose, float
/// (σ 0.3 m) with an offset `jump` over [t0, t1).
fn float_span(jump: (f64, f64), t0: f64, t1: f64) -> impl Fn(f64, (f64, f64, f64)) -> Reported {
    move |t, p| {
        if t >= t0 && t < t1 {
            Some((pose((p.0 + jump.0, p.1 + jump.1, p.2)), float(0.3)))
        } else {
            Some((pose(p), FIXED))
        }
    }
}

/// Offsets of 0.3-1 m in eight directions: the jumps of a float fix.
fn jumps() -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for (i, r) in [0.3, 0.5, 0.8, 1.0].iter().enumerate() {
        for k in 0..8 {
            let a = f64::from(k) * core::f64::consts::FRAC_PI_4 + 0.3 * i as f64;
            v.push((r * a.cos(), r * a.sin()));
        }
    }
    v
}

//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# When a fix rule is configured, a tick whose fix is not good MUST be
//# processed as a tick without a fix: it MUST NOT be projected for path
//# tracking or for the plan check, nor become the last fix of
//# GD-PLAN-DEAD-RECKONING; without a rule every fix MUST be taken.
//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# With a fix rule, in a tick without a good fix, path tracking MUST steer on
//# the pose of the last good fix moved by odometry, as GD-PLAN-DEAD-RECKONING
//# moves it, while the odometry distance since that fix is at most the rule's
//# path dead-reckoning distance; beyond it, and before the first good fix,
//# localisation MUST be invalid, with the reason named (`GD-FIX-QUALITY`).
#[test]
fn a_float_fix_does_not_steer_path_tracking_off_the_path() {
    let path = straight_path(-10.0, 190.0);
    let mut worst_with = 0.0_f64;
    let mut least_without = f64::INFINITY;
    for jump in jumps() {
        // 10 s on the path (8 m), 12 s float (9.6 m), then fixed again.
        let receiver = float_span(jump, 10.0, 22.0);
        let mut with: Pierre2022<'_, PATH_N> =
            Guidance::new(GuidanceConfig::new(&params(Some(rule()))).unwrap(), &path).unwrap();
        let ticks = drive(&mut with, 0.0, 30.0, 0.0, &receiver);
        for t in &ticks {
            worst_with = worst_with.max(t.pose.1.abs());
        }
        // Every float tick: carried, judged from the carried pose, commanding.
        for (k, t) in ticks.iter().enumerate() {
            let time = k as f64 * PERIOD;
            if (10.0..22.0).contains(&time) {
                assert!(
                    matches!(t.out.path.fix, FixUse::Carried { .. }),
                    "{:?}",
                    t.out.path.fix
                );
                assert!(matches!(
                    t.out.path.plan_pose,
                    PlanPose::DeadReckoned { .. }
                ));
                let y = t.out.path.frenet.unwrap().y.get();
                assert!(
                    (y - t.pose.1).abs() < 1e-6,
                    "carried y {y} true {}",
                    t.pose.1
                );
                assert!(t.out.path.localisation_valid);
                assert_eq!(t.out.mode, Mode::PathTracking);
            } else {
                assert_eq!(t.out.path.fix, FixUse::Fix);
                assert_eq!(t.out.path.plan_pose, PlanPose::Gnss);
            }
        }
        // Without a rule the float fix is taken: the robot follows the jump.
        let mut without: Pierre2022<'_, PATH_N> =
            Guidance::new(GuidanceConfig::new(&params(None)).unwrap(), &path).unwrap();
        let ticks = drive(&mut without, 0.0, 30.0, 0.0, &receiver);
        let off = ticks.iter().map(|t| t.pose.1.abs()).fold(0.0, f64::max);
        if jump.1.abs() > 0.25 {
            least_without = least_without.min(off);
        }
    }
    // Odometry exact here: the carried pose is the true one.
    assert!(
        worst_with < 1e-6,
        "with the rule, {worst_with} m off the path"
    );
    assert!(
        least_without > 0.2,
        "without it, only {least_without} m off"
    );
}

#[test]
fn beyond_the_dead_reckoning_distance_localisation_is_lost_and_the_robot_stops() {
    let path = straight_path(-10.0, 190.0);
    for carry in [0.0, 2.0, 5.0] {
        let p = params(Some(FixRuleParams {
            path_dead_reckoning: m(carry),
            ..rule()
        }));
        let mut g: Pierre2022<'_, PATH_N> =
            Guidance::new(GuidanceConfig::new(&p).unwrap(), &path).unwrap();
        // A single-point fix from the start: no good fix yet.
        let first = g
            .step_with_fix(
                &TickInput {
                    scans: &[],
                    gnss: Some(pose((0.0, 0.0, 0.0))),
                    odometry: Pose2::<Odom>::new(0.0, 0.0, 0.0).unwrap(),
                    extra: Sideslip::ZERO,
                },
                &FixQuality {
                    kind: FixKind::Single,
                    accuracy: None,
                },
            )
            .unwrap();
        match first.path.fix {
            FixUse::Lost(reason) => assert_eq!(reason.requirement, "GD-FIX-QUALITY"),
            other => panic!("{other:?}"),
        }
        assert!(!first.path.localisation_valid);
        let mut g: Pierre2022<'_, PATH_N> =
            Guidance::new(GuidanceConfig::new(&p).unwrap(), &path).unwrap();
        // Fixed for 2 s, then no fix at all.
        let receiver = |t: f64, q: (f64, f64, f64)| (t < 2.0).then(|| (pose(q), FIXED));
        let ticks = drive(&mut g, 0.0, 20.0, 0.0, &receiver);
        let x_fix = ticks[199].pose.0;
        let mut stopped_at = None;
        for t in &ticks[200..] {
            let beyond = t.pose.0 - x_fix;
            match t.out.path.fix {
                FixUse::Carried { travelled } => {
                    assert!(travelled.get() <= carry + 1e-9);
                    assert!(t.out.path.localisation_valid);
                }
                FixUse::Lost(reason) => {
                    assert_eq!(reason.requirement, "GD-FIX-QUALITY");
                    assert!(beyond > carry - 0.02, "lost after {beyond} m");
                    assert!(!t.out.path.localisation_valid);
                }
                other => panic!("{other:?}"),
            }
            if t.out.mode == Mode::Stop && stopped_at.is_none() {
                stopped_at = Some(t.pose.0);
            }
        }
        // Stopped, within the carry distance and the Stop delay's travel.
        let stopped_at = stopped_at.expect("the robot stops");
        assert!(stopped_at - x_fix <= carry + 0.8 * 0.5 + 0.05);
        assert!(stopped_at - x_fix >= carry);
        let last = ticks.last().unwrap();
        assert_eq!(last.out.command.unwrap().command.speed().get(), 0.0);
    }
}

//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# When a good fix returns after ticks in which path tracking steered on the
//# carried pose, path tracking's error MUST be the error to the path shifted
//# sideways by o₀ (1 − S(d / D)), o₀ the fix's lateral error less the lateral
//# error of the last carried pose, d the odometry distance since, S(u) = 3u² −
//# 2u³ and D = max(1.5 |o₀| / k, √(6 |o₀| / κ)) with k the rejoin slope and κ
//# the rejoin curvature (zero from D on), the angular deviation less atan of
//# that shift's rate, in every tick in which no entry (GD-ENTRY) or hand-over
//# (GD-HANDOVER) shifts the reference.
#[test]
fn a_returning_fix_is_rejoined_at_the_slope_without_a_swing() {
    let path = straight_path(-10.0, 190.0);
    // The fix comes back with a bias (a drift that moved during the float
    // span) and odometry's heading drifts by 0.0011 rad per metre (0.05°/s
    // at 0.8 m/s) or not: the carried pose and the returning fix differ by
    // the bias and the odometry's error.
    // With κ = 0.05 /m the curvature's bound sets D for these steps (the
    // slope's would be 1.5 |o₀| / 0.1 = 15 |o₀|, under √(120 |o₀|) below
    // 0.53 m); with κ = +∞ the slope alone does.
    let cases = [
        (0.15, 0.0, 0.05),
        (-0.3, 0.0, 0.05),
        (0.3, 0.0011, 0.05),
        (-0.15, -0.0011, 0.05),
        (0.08, 0.0, 0.05),
        (0.15, 0.0, f64::INFINITY),
        (-0.3, 0.0011, f64::INFINITY),
    ];
    for (bias, drift, curvature) in cases {
        let rule = FixRuleParams {
            rejoin_curvature: curvature,
            ..rule()
        };
        let receiver = move |t: f64, p: (f64, f64, f64)| {
            if (10.0..22.0).contains(&t) {
                Some((pose((p.0, p.1 + 0.6, p.2)), float(0.3)))
            } else if t >= 22.0 {
                Some((pose((p.0, p.1 + bias, p.2)), FIXED))
            } else {
                Some((pose(p), FIXED))
            }
        };
        let mut g: Pierre2022<'_, PATH_N> =
            Guidance::new(GuidanceConfig::new(&params(Some(rule))).unwrap(), &path).unwrap();
        let ticks = drive(&mut g, 0.0, 60.0, drift, &receiver);
        let back = 2200;
        let carried = ticks[back - 1].out.path.frenet.unwrap().y.get();
        let fix = ticks[back].out.path.frenet.unwrap().y.get();
        let step = fix - carried;
        assert!(step.abs() > 0.05, "step {step}");
        let start = ticks[back].out.path.reference_offset.unwrap().get();
        assert!((start - step).abs() < 1e-9, "shift {start} step {step}");
        // The shift follows the smoothstep over D, never changing sign, its
        // rate never above the slope, its curvature never above κ.
        let x0 = ticks[back].pose.0;
        let length = (1.5 * step.abs() / 0.1).max((6.0 * step.abs() / curvature).sqrt());
        assert!(curvature.is_infinite() || length > 1.5 * step.abs() / 0.1 + 0.5);
        let mut previous = (0.0, step);
        let mut samples = Vec::new();
        for t in &ticks[back..] {
            let d = t.pose.0 - x0;
            let u = (d / length).min(1.0);
            let expected = step * (1.0 - u * u * (3.0 - 2.0 * u));
            let shift = t.out.path.reference_offset.map_or(0.0, Meters::get);
            assert!(
                (shift - expected).abs() < 0.01,
                "d {d}: {shift} vs {expected}"
            );
            assert!(shift * step >= 0.0);
            if d > previous.0 {
                let rate = (shift - previous.1).abs() / (d - previous.0);
                assert!(rate <= 0.1 + 1e-3, "rate {rate}");
            }
            previous = (d, shift);
            samples.push((d, shift));
        }
        // Second differences over 0.25 m (a finite one against the shape's
        // 6 |o0| / D²).
        let peak = 6.0 * step.abs() / (length * length);
        let mut most: f64 = 0.0;
        for w in samples.windows(2 * 25 + 1).step_by(5) {
            let (a, b, c) = (w[0], w[25], w[50]);
            let h = (c.0 - a.0) / 2.0;
            if h > 0.15 && c.0 < length {
                most = most.max(((c.1 - 2.0 * b.1 + a.1) / (h * h)).abs());
            }
        }
        assert!(most <= peak * 1.05 + 1e-3, "curvature {most} vs {peak}");
        assert!(
            most <= curvature * 1.05,
            "curvature {most} above {curvature}"
        );
        assert!(most > 0.5 * peak, "curvature {most} vs {peak}");
        // No swing: the steering at the return moves by at most the law's
        // heading term on the odometry's heading error (k_θ = 2.8 on a 2 m
        // wheelbase); with exact odometry, under a third of what the lateral
        // step at once would give (k_y L |o0|, k_y = 0.7).
        let heading_step = (ticks[back].out.path.frenet.unwrap().angular_deviation.get()
            - ticks[back - 1]
                .out
                .path
                .frenet
                .unwrap()
                .angular_deviation
                .get())
        .abs();
        let before = ticks[back - 1].steering;
        let jolt = (ticks[back].steering - before).abs();
        eprintln!("bias {bias} m, odometry drift {drift} rad/m: step {step:.3} m, heading step {heading_step:.4} rad, steering moves {jolt:.4} rad");
        assert!(
            jolt < 2.8 * WHEELBASE * heading_step + 0.01,
            "steering jumps by {jolt} rad"
        );
        if drift == 0.0 {
            assert!(
                jolt < 0.7 * WHEELBASE * step.abs() / 3.0,
                "jolt {jolt} step {step}"
            );
        }
        // Path tracking ends on the path as the fix places it.
        let end = ticks.last().unwrap().out.path.frenet.unwrap().y.get();
        assert!(end.abs() < 0.05, "ends {end} m off");
    }
}

/// A deterministic noise in [−a, a] for tick `k` and axis `axis`.
fn noise(k: u64, axis: u64, a: f64) -> f64 {
    let h = (k * 2 + axis)
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    a * (2.0 * ((h >> 11) as f64 / (1_u64 << 53) as f64) - 1.0)
}

/// The float receiver of GD-FIX-FLOAT's closed loop: fixed with the true
/// pose, float over [10 s, 40 s) with the offset `jump` and a white noise of
/// ±`white` m per axis.
fn noisy_float(jump: (f64, f64), white: f64) -> impl Fn(f64, (f64, f64, f64)) -> Reported {
    move |t, p| {
        let k = (t / PERIOD).round() as u64;
        if (10.0..40.0).contains(&t) {
            let (x, y) = (
                p.0 + jump.0 + noise(k, 0, white),
                p.1 + jump.1 + noise(k, 1, white),
            );
            Some((pose((x, y, p.2)), float(0.3)))
        } else {
            Some((pose(p), FIXED))
        }
    }
}

//= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
//= type=test
//# With a float averaging length configured, a float span MUST start at the
//# first tick after a good fix whose fix the rule refuses and whose kind is RTK
//# float, and MUST end at the next good fix; only ticks with such a fix and a
//# carried pose (GD-FIX-QUALITY) are its float ticks.
//= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
//= type=test
//# From the tick r is set until the span ends, in every tick in which
//# GD-FIX-QUALITY has path tracking steer on the carried pose, path tracking
//# MUST steer on the carried pose moved by the span's correction instead (east,
//# north and heading added).
//= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
//= type=test
//# The offset r MUST be the mean of the float fix's offset from the carried
//# pose (east, north and heading) over the span's float ticks, each weighted
//# by its odometry distance, until those ticks cover the averaging length λ;
//# from then on r MUST stay.
//= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
//= type=test
//# The span's correction MUST be 2a − b (the heading's difference wrapped),
//# and its east and north MUST each be at most three times the largest
//# magnitude of that component of m − r over the span's float ticks.
#[test]
fn a_float_fix_less_its_offset_corrects_the_odometry_drift() {
    let path = straight_path(-10.0, 190.0);
    // Odometry's heading drifts by 0.0011 rad per metre (0.05°/s at
    // 0.8 m/s): over the 24 m of float the carried pose drifts 0.3 m sideways.
    let drift = 0.0011;
    for (i, jump) in jumps().into_iter().enumerate() {
        let receiver = noisy_float(jump, if i % 2 == 0 { 0.0 } else { 0.05 });
        let carried = FixRuleParams {
            path_dead_reckoning: m(30.0),
            ..rule()
        };
        let corrected = FixRuleParams {
            float_averaging: Some(m(2.0)),
            ..carried
        };
        let mut g: Pierre2022<'_, PATH_N> = Guidance::new(
            GuidanceConfig::new(&params(Some(corrected))).unwrap(),
            &path,
        )
        .unwrap();
        let ticks = drive(&mut g, 0.0, 45.0, drift, &receiver);
        let start = ticks[1000].pose.0;
        let mut worst = 0.0_f64;
        let mut largest = (0.0_f64, 0.0_f64);
        for (k, t) in ticks.iter().enumerate() {
            let time = k as f64 * PERIOD;
            worst = worst.max(t.pose.1.abs());
            if !(10.0..40.0).contains(&time) {
                assert_eq!(t.out.path.fix, FixUse::Fix);
                continue;
            }
            // Carried alone over the first 2 m of float, corrected after.
            let float_travelled = t.pose.0 - start;
            match t.out.path.fix {
                FixUse::Carried { .. } => assert!(float_travelled < 2.0 + 0.01),
                FixUse::Float { .. } => {
                    assert!(float_travelled > 2.0 - 0.01);
                    // The float fix less its offset: the true pose within
                    // the odometry's drift over the averaging and the noise.
                    let f = t.out.path.frenet.unwrap();
                    largest = (
                        largest.0.max((f.y.get() - t.pose.1).abs()),
                        largest.1.max((f.angular_deviation.get() - t.pose.2).abs()),
                    );
                }
                other => panic!("{other:?}"),
            }
        }
        // One average of m − r would lag the drift by about λ (2 m × 0.0011
        // × 24 m = 0.05 m at the end); 2a − b follows it (0.007 m at worst).
        assert!(
            worst < 0.015 && largest.0 < 0.015 && largest.1 < 0.005,
            "jump {jump:?}: {worst} m off with the correction"
        );
        // Without the averaging: the carried pose alone drifts off.
        let mut plain: Pierre2022<'_, PATH_N> =
            Guidance::new(GuidanceConfig::new(&params(Some(carried))).unwrap(), &path).unwrap();
        let ticks = drive(&mut plain, 0.0, 45.0, drift, &receiver);
        let off = ticks.iter().map(|t| t.pose.1.abs()).fold(0.0, f64::max);
        assert!(
            off > 0.2 && off > 20.0 * worst,
            "jump {jump:?}: only {off} m off without it"
        );
    }
}

//= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
//= type=test
//# A fix rule whose float averaging length is given and not positive MUST be
//# refused with `GD-FIX-FLOAT`.
#[test]
fn a_float_averaging_length_not_positive_is_refused() {
    for length in [0.0, -2.0] {
        let p = FixRuleParams {
            float_averaging: Some(m(length)),
            ..rule()
        };
        assert_eq!(FixRule::new(&p).unwrap_err().requirement, "GD-FIX-FLOAT");
        let config = GuidanceConfig::new(&params(Some(p)));
        assert_eq!(config.unwrap_err().requirement, "GD-FIX-FLOAT");
    }
    let p = FixRuleParams {
        float_averaging: Some(m(1e-9)),
        ..rule()
    };
    assert!(FixRule::new(&p).is_ok());
}
