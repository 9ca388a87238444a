//! The C interface called as a C program calls it: a pipeline made, stepped
//! and freed; refusals named by requirement; null pointers caught; scans
//! routed; the closed loop of the C example converging; no allocation per
//! tick (a counting allocator watches the ticks).
#![allow(
    unsafe_code,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::result_large_err
)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::ffi::CStr;

use fieldguide_ffi::{
    fg_pipeline_free, fg_pipeline_new, fg_pipeline_new_with_fix_rule, fg_pipeline_new_with_rules,
    fg_pipeline_step, fg_pipeline_step_with_fix, FgConfig, FgError, FgFix, FgFixRule,
    FgHandoverRule, FgMode, FgPipeline, FgPoint, FgPose, FgPreset, FgScan, FgStatus, FgTickInput,
    FgTickOutput, FG_BEHAVIOUR_EDGE, FG_BEHAVIOUR_FURROW, FG_FIX_RTK_FIXED, FG_FIX_RTK_FLOAT,
};

struct Counting;

thread_local! {
    static WATCHING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: every call is forwarded unchanged to the system allocator; the
// wrapper only counts, in const-initialised thread-locals that do not allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if WATCHING.with(Cell::get) {
            ALLOCATIONS.with(|n| n.set(n.get() + 1));
        }
        // SAFETY: the caller's contract is the system allocator's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is the system allocator's.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn straight() -> Vec<FgPoint> {
    (0..=60)
        .map(|i| FgPoint {
            x: f64::from(i),
            y: 0.0,
        })
        .collect()
}

fn config(preset: FgPreset) -> FgConfig {
    FgConfig {
        preset,
        edge_on_left: false,
        edge_lidar: FgPose {
            x: 1.2,
            y: 0.0,
            heading: 0.0,
        },
        smoothing_window_m: 1.0,
    }
}

fn no_error() -> FgError {
    FgError {
        requirement: [0; 32],
        message: [0; 128],
    }
}

fn requirement(e: &FgError) -> String {
    // SAFETY: the library NUL-terminates within the array.
    unsafe { CStr::from_ptr(e.requirement.as_ptr()) }
        .to_str()
        .unwrap()
        .to_owned()
}

fn new(preset: FgPreset, waypoints: &[FgPoint]) -> Result<*mut FgPipeline, FgError> {
    let mut p: *mut FgPipeline = core::ptr::null_mut();
    let mut e = no_error();
    let c = config(preset);
    // SAFETY: live locals of the right types; `waypoints.len()` points.
    let s = unsafe { fg_pipeline_new(&c, waypoints.as_ptr(), waypoints.len(), &mut p, &mut e) };
    match s {
        FgStatus::Ok => Ok(p),
        _ => Err(e),
    }
}

fn input(pose: FgPose, scans: &[FgScan]) -> FgTickInput {
    FgTickInput {
        scans: if scans.is_empty() {
            core::ptr::null()
        } else {
            scans.as_ptr()
        },
        scan_count: scans.len(),
        gnss_valid: true,
        gnss: pose,
        odometry: pose,
        sideslip_front_rad: 0.0,
        sideslip_rear_rad: 0.0,
    }
}

fn blank() -> FgTickOutput {
    FgTickOutput {
        has_command: false,
        speed_m_s: 0.0,
        steering_rad: 0.0,
        mode: FgMode::Stop,
        behaviour: 0,
        has_path_error: false,
        lateral_error_m: 0.0,
    }
}

fn step(p: *mut FgPipeline, i: &FgTickInput) -> Result<FgTickOutput, (FgStatus, FgError)> {
    let mut out = blank();
    let mut e = no_error();
    // SAFETY: `p` is a live pipeline of this test; the rest are live locals.
    let s = unsafe { fg_pipeline_step(p, i, &mut out, &mut e) };
    match s {
        FgStatus::Ok => Ok(out),
        s => Err((s, e)),
    }
}

fn free(p: *mut FgPipeline) {
    // SAFETY: made by `new` and freed once.
    unsafe { fg_pipeline_free(p) };
}

#[test]
fn the_c_examples_loop_converges_and_its_ticks_allocate_nothing() {
    let p = new(FgPreset::PathTracking, &straight()).unwrap();
    let (mut x, mut y, mut heading) = (0.0_f64, 0.5_f64, 0.0_f64);
    let mut first = None;
    let mut last = blank();
    // Under Miri, which interprets every instruction, the first two seconds.
    let ticks = if cfg!(miri) { 200 } else { 2000 };
    WATCHING.with(|w| w.set(true));
    for _ in 0..=ticks {
        let out = step(p, &input(FgPose { x, y, heading }, &[])).unwrap();
        first.get_or_insert(out);
        last = out;
        x += 0.01 * out.speed_m_s * heading.cos();
        y += 0.01 * out.speed_m_s * heading.sin();
        heading += 0.01 * out.speed_m_s * out.steering_rad.tan() / 2.0;
    }
    WATCHING.with(|w| w.set(false));
    assert_eq!(ALLOCATIONS.with(Cell::get), 0, "a tick allocated");
    let first = first.unwrap();
    // Table 2's speed; 0.5 m left: full right lock (30°).
    assert!((first.speed_m_s - 0.8).abs() < 1e-12);
    assert!((first.steering_rad + core::f64::consts::FRAC_PI_6).abs() < 1e-12);
    assert_eq!(first.mode, FgMode::PathTracking);
    assert!((first.lateral_error_m - 0.5).abs() < 1e-12);
    // Converged after 16 m; under Miri, on its way after 1.6 m.
    let bound = if cfg!(miri) { 0.3 } else { 1e-4 };
    assert!(last.lateral_error_m.abs() < bound, "{last:?}");
    free(p);
}

#[test]
fn refusals_name_their_requirement() {
    // One waypoint is no path.
    let e = new(FgPreset::PathTracking, &straight()[..1]).unwrap_err();
    assert!(requirement(&e).starts_with("PATH-"), "{}", requirement(&e));
    // A non-finite waypoint.
    let mut bad = straight();
    bad[3].y = f64::NAN;
    assert_eq!(
        requirement(&new(FgPreset::Furrow, &bad).unwrap_err()),
        "LIB-FINITE"
    );
    // A bad smoothing window.
    let mut p: *mut FgPipeline = core::ptr::null_mut();
    let mut e = no_error();
    let mut c = config(FgPreset::PathTracking);
    c.smoothing_window_m = 0.0;
    let w = straight();
    // SAFETY: live locals.
    let s = unsafe { fg_pipeline_new(&c, w.as_ptr(), w.len(), &mut p, &mut e) };
    assert_eq!(s, FgStatus::Refused);
    assert!(p.is_null());
    assert!(!requirement(&e).is_empty());
    // A non-finite pose in a tick: refused, and the pipeline goes on.
    let p = new(FgPreset::Furrow, &straight()).unwrap();
    let (status, e) = step(
        p,
        &input(
            FgPose {
                x: f64::INFINITY,
                y: 0.0,
                heading: 0.0,
            },
            &[],
        ),
    )
    .unwrap_err();
    assert_eq!(status, FgStatus::Refused);
    assert_eq!(requirement(&e), "LIB-FINITE");
    assert!(step(
        p,
        &input(
            FgPose {
                x: 1.0,
                y: 0.0,
                heading: 0.0
            },
            &[]
        )
    )
    .is_ok());
    free(p);
}

#[test]
fn scans_are_routed_to_configured_behaviours_only() {
    let ranges = vec![2.0_f64; 360];
    let scan = |behaviour| FgScan {
        behaviour,
        start_rad: -core::f64::consts::PI,
        increment_rad: core::f64::consts::TAU / 360.0,
        ranges: ranges.as_ptr(),
        count: ranges.len(),
        range_min_m: 0.05,
        range_max_m: 30.0,
    };
    let pose = FgPose {
        x: 1.0,
        y: 0.0,
        heading: 0.0,
    };
    // Furrow pursuing alone: an edge scan is refused, a furrow scan taken.
    let p = new(FgPreset::Furrow, &straight()).unwrap();
    let (status, e) = step(p, &input(pose, &[scan(FG_BEHAVIOUR_EDGE)])).unwrap_err();
    assert_eq!(status, FgStatus::Refused);
    assert_eq!(requirement(&e), "GD-INPUT");
    assert!(step(p, &input(pose, &[scan(FG_BEHAVIOUR_FURROW)])).is_ok());
    // Three scans for two behaviours.
    let three = [
        scan(FG_BEHAVIOUR_FURROW),
        scan(FG_BEHAVIOUR_EDGE),
        scan(FG_BEHAVIOUR_FURROW),
    ];
    let (_, e) = step(p, &input(pose, &three)).unwrap_err();
    assert_eq!(requirement(&e), "GD-INPUT");
    free(p);
    // Both behaviours: one scan each.
    let p = new(FgPreset::Both, &straight()).unwrap();
    let out = step(
        p,
        &input(pose, &[scan(FG_BEHAVIOUR_FURROW), scan(FG_BEHAVIOUR_EDGE)]),
    );
    assert!(out.is_ok());
    free(p);
}

#[test]
fn null_pointers_are_caught() {
    let w = straight();
    let c = config(FgPreset::PathTracking);
    let mut p: *mut FgPipeline = core::ptr::null_mut();
    // SAFETY: each call has a null where a pointer is required, which the
    // library checks before reading anything.
    unsafe {
        assert_eq!(
            fg_pipeline_new(
                core::ptr::null(),
                w.as_ptr(),
                w.len(),
                &mut p,
                core::ptr::null_mut()
            ),
            FgStatus::NullPointer
        );
        assert_eq!(
            fg_pipeline_new(&c, core::ptr::null(), 0, &mut p, core::ptr::null_mut()),
            FgStatus::NullPointer
        );
        assert_eq!(
            fg_pipeline_new(
                &c,
                w.as_ptr(),
                w.len(),
                core::ptr::null_mut(),
                core::ptr::null_mut()
            ),
            FgStatus::NullPointer
        );
    }
    let p = new(FgPreset::Furrow, &straight()).unwrap();
    let pose = FgPose {
        x: 0.0,
        y: 0.0,
        heading: 0.0,
    };
    let mut i = input(pose, &[]);
    i.scan_count = 1; // scans: null
    assert_eq!(step(p, &i).unwrap_err().0, FgStatus::NullPointer);
    let mut out = blank();
    // SAFETY: null pipeline and null output, checked before use; a null
    // error pointer is allowed.
    unsafe {
        assert_eq!(
            fg_pipeline_step(
                core::ptr::null_mut(),
                &input(pose, &[]),
                &mut out,
                core::ptr::null_mut()
            ),
            FgStatus::NullPointer
        );
        assert_eq!(
            fg_pipeline_step(
                p,
                &input(pose, &[]),
                core::ptr::null_mut(),
                core::ptr::null_mut()
            ),
            FgStatus::NullPointer
        );
        fg_pipeline_free(core::ptr::null_mut());
    }
    free(p);
}

#[test]
fn the_behaviour_ids_are_the_cores() {
    assert_eq!(FG_BEHAVIOUR_EDGE, fieldguide::presets::EDGE.0);
    assert_eq!(FG_BEHAVIOUR_FURROW, fieldguide::presets::FURROW.0);
}

/// Path tracking with a fix rule (RTK fixed only, σ ≤ 0.05 m, 1 m carried
/// by odometry): a float fix 0.5 m off is refused, the pose carried from the
/// last good fix steers, and past 1 m of travel localisation is lost and
/// the machine stops. Without a rule the same fix is taken and the error
/// jumps by 0.5 m.
//= spec/guidance.md#gd-fix-quality-a-fix-judged-by-its-kind-and-accuracy
//= type=test
//# A fix rule whose largest accuracy is not positive, whose path
//# dead-reckoning distance is negative, whose rejoin slope is not in (0, 1]
//# or whose rejoin curvature is not positive MUST be refused with
//# `GD-FIX-QUALITY`.
#[test]
fn a_float_fix_is_judged_by_the_fix_rule() {
    let rule = FgFixRule {
        worst_kind: FG_FIX_RTK_FIXED,
        max_accuracy_m: 0.05,
        path_dead_reckoning_m: 1.0,
        rejoin_slope: 0.1,
        rejoin_curvature: 0.05,
        has_float_averaging: false,
        float_averaging_m: 0.0,
    };
    let make = |rule: Option<&FgFixRule>| -> Result<*mut FgPipeline, FgError> {
        let mut p: *mut FgPipeline = core::ptr::null_mut();
        let mut e = no_error();
        let c = config(FgPreset::PathTracking);
        let w = straight();
        let r = rule.map_or(core::ptr::null(), |r| r as *const FgFixRule);
        // SAFETY: live locals of the right types; `w.len()` points.
        let s =
            unsafe { fg_pipeline_new_with_fix_rule(&c, w.as_ptr(), w.len(), r, &mut p, &mut e) };
        match s {
            FgStatus::Ok => Ok(p),
            _ => Err(e),
        }
    };
    let tick = |p: *mut FgPipeline, x: f64, fix: &FgFix| -> Result<FgTickOutput, FgError> {
        let mut i = input(
            FgPose {
                x,
                y: 0.0,
                heading: 0.0,
            },
            &[],
        );
        if fix.kind == FG_FIX_RTK_FLOAT {
            i.gnss.y = 0.5;
        }
        let mut out = blank();
        let mut e = no_error();
        // SAFETY: `p` is a live pipeline of this test; the rest are live locals.
        match unsafe { fg_pipeline_step_with_fix(p, &i, fix, &mut out, &mut e) } {
            FgStatus::Ok => Ok(out),
            _ => Err(e),
        }
    };
    let fixed = FgFix {
        kind: FG_FIX_RTK_FIXED,
        has_accuracy: true,
        accuracy_m: 0.02,
    };
    let float = FgFix {
        kind: FG_FIX_RTK_FLOAT,
        has_accuracy: true,
        accuracy_m: 0.3,
    };
    for with_rule in [true, false] {
        let p = make(with_rule.then_some(&rule)).unwrap();
        // On the path at 0.01 m a tick, 1 m with RTK fixed then 2 m float.
        let mut stopped_at = None;
        for k in 0..300 {
            let x = 0.01 * f64::from(k);
            let out = tick(p, x, if k < 100 { &fixed } else { &float }).unwrap();
            if k == 101 {
                let expected = if with_rule { 0.0 } else { 0.5 };
                assert!(
                    out.has_path_error && (out.lateral_error_m - expected).abs() < 1e-6,
                    "{out:?}"
                );
            }
            if out.mode == FgMode::Stop {
                stopped_at.get_or_insert(x);
            }
        }
        // With the rule: carried 1 m, then lost, then Stop; never without.
        match stopped_at {
            Some(x) => assert!(with_rule && x > 2.0 && x < 3.0, "stopped at {x}"),
            None => assert!(!with_rule),
        }
        free(p);
    }
    // Refusals: a rule with σ ≤ 0, an unknown kind or a rejoin curvature
    // ≤ 0, in the rule or a fix.
    for bad in [
        FgFixRule {
            max_accuracy_m: 0.0,
            ..rule
        },
        FgFixRule {
            worst_kind: 9,
            ..rule
        },
        FgFixRule {
            rejoin_curvature: 0.0,
            ..rule
        },
    ] {
        assert_eq!(
            requirement(&make(Some(&bad)).unwrap_err()),
            "GD-FIX-QUALITY"
        );
    }
    let p = make(Some(&rule)).unwrap();
    let odd = FgFix { kind: 4, ..fixed };
    assert_eq!(
        requirement(&tick(p, 0.0, &odd).unwrap_err()),
        "GD-FIX-QUALITY"
    );
    let nan = FgFix {
        accuracy_m: f64::NAN,
        ..fixed
    };
    assert_eq!(requirement(&tick(p, 0.0, &nan).unwrap_err()), "LIB-FINITE");
    // A null fix is a null pointer; the pipeline still steps afterwards.
    let mut out = blank();
    let i = input(
        FgPose {
            x: 0.0,
            y: 0.0,
            heading: 0.0,
        },
        &[],
    );
    // SAFETY: a live pipeline and locals, and a null fix the call must catch.
    let s = unsafe {
        fg_pipeline_step_with_fix(p, &i, core::ptr::null(), &mut out, core::ptr::null_mut())
    };
    assert_eq!(s, FgStatus::NullPointer);
    assert!(tick(p, 0.0, &fixed).unwrap().has_command);
    free(p);
}

/// The float averaging and the hand-over's line hold reach the core: a
/// length given is validated (GD-FIX-FLOAT, GD-HANDOVER-LINE), one not
/// given is ignored whatever its value.
//= spec/guidance.md#gd-fix-float-a-float-fix-corrects-the-carried-pose
//= type=test
//# A fix rule whose float averaging length is given and not positive MUST be
//# refused with `GD-FIX-FLOAT`.
//= spec/guidance.md#gd-handover-line-the-last-line-of-a-behaviour-held-after-a-hand-over
//= type=test
//# A hand-over rule whose line hold is given and not positive MUST be refused
//# with `GD-HANDOVER-LINE`.
#[test]
fn the_float_averaging_and_the_line_hold_are_validated() {
    let rule = FgFixRule {
        worst_kind: FG_FIX_RTK_FIXED,
        max_accuracy_m: 0.05,
        path_dead_reckoning_m: 10.0,
        rejoin_slope: 0.1,
        rejoin_curvature: 0.05,
        has_float_averaging: true,
        float_averaging_m: 2.0,
    };
    let handover = FgHandoverRule {
        hold_m: 4.0,
        slope: 0.1,
        averaging_m: 1.0,
        has_line_hold: true,
        line_hold_m: 3.0,
    };
    let make = |rule: &FgFixRule, handover: &FgHandoverRule| -> Result<(), FgError> {
        let mut p: *mut FgPipeline = core::ptr::null_mut();
        let mut e = no_error();
        let c = config(FgPreset::Furrow);
        let w = straight();
        // SAFETY: live locals of the right types; `w.len()` points.
        let s = unsafe {
            fg_pipeline_new_with_rules(&c, w.as_ptr(), w.len(), rule, handover, &mut p, &mut e)
        };
        match s {
            FgStatus::Ok => {
                free(p);
                Ok(())
            }
            _ => Err(e),
        }
    };
    assert!(make(&rule, &handover).is_ok());
    for length in [0.0, -1.0] {
        let bad = FgFixRule {
            float_averaging_m: length,
            ..rule
        };
        assert_eq!(
            requirement(&make(&bad, &handover).unwrap_err()),
            "GD-FIX-FLOAT"
        );
        let off = FgFixRule {
            has_float_averaging: false,
            ..bad
        };
        assert!(make(&off, &handover).is_ok());
        let bad = FgHandoverRule {
            line_hold_m: length,
            ..handover
        };
        assert_eq!(
            requirement(&make(&rule, &bad).unwrap_err()),
            "GD-HANDOVER-LINE"
        );
        let off = FgHandoverRule {
            has_line_hold: false,
            ..bad
        };
        assert!(make(&rule, &off).is_ok());
    }
    let nan = FgHandoverRule {
        line_hold_m: f64::NAN,
        ..handover
    };
    assert_eq!(requirement(&make(&rule, &nan).unwrap_err()), "LIB-FINITE");
}
