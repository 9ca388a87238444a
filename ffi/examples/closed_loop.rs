//! The reference of the C and C++ examples (`closed_loop.c`,
//! `closed_loop.cpp`): the same closed loop through the C interface, the
//! same lines printed. `.ci/run` compares the three outputs.
//!
//! A straight 60 m path recorded every metre; a bicycle with a 2 m
//! wheelbase starts 0.5 m left of it; path tracking at 100 Hz for 20 s, the
//! pose integrated by Euler steps of the control period; one line a second.

use fieldguide_ffi::{
    fg_pipeline_free, fg_pipeline_new, fg_pipeline_step, FgConfig, FgError, FgPipeline, FgPoint,
    FgPose, FgPreset, FgStatus, FgTickInput, FgTickOutput,
};

fn main() -> std::process::ExitCode {
    let waypoints: Vec<FgPoint> = (0..=60)
        .map(|i| FgPoint {
            x: f64::from(i),
            y: 0.0,
        })
        .collect();
    let config = FgConfig {
        preset: FgPreset::PathTracking,
        edge_on_left: false,
        edge_lidar: FgPose {
            x: 1.2,
            y: 0.0,
            heading: 0.0,
        },
        smoothing_window_m: 1.0,
    };
    let mut pipeline: *mut FgPipeline = core::ptr::null_mut();
    let mut error = FgError {
        requirement: [0; 32],
        message: [0; 128],
    };
    // SAFETY: every pointer is to a live local of the right type; the
    // waypoints are `waypoints.len()` readable points.
    let status = unsafe {
        fg_pipeline_new(
            &config,
            waypoints.as_ptr(),
            waypoints.len(),
            &mut pipeline,
            &mut error,
        )
    };
    if status != FgStatus::Ok {
        eprintln!("refused: {status:?}");
        return std::process::ExitCode::FAILURE;
    }
    let (mut x, mut y, mut heading) = (0.0_f64, 0.5_f64, 0.0_f64);
    let (dt, wheelbase) = (0.01_f64, 2.0_f64);
    for k in 0..=2000 {
        let input = FgTickInput {
            scans: core::ptr::null(),
            scan_count: 0,
            gnss_valid: true,
            gnss: FgPose { x, y, heading },
            odometry: FgPose { x, y, heading },
            sideslip_front_rad: 0.0,
            sideslip_rear_rad: 0.0,
        };
        let mut out = FgTickOutput {
            has_command: false,
            speed_m_s: 0.0,
            steering_rad: 0.0,
            mode: fieldguide_ffi::FgMode::Stop,
            behaviour: 0,
            has_path_error: false,
            lateral_error_m: 0.0,
        };
        // SAFETY: `pipeline` was made above and is used by this thread
        // alone; the input holds no scan; `out` and `error` are live locals.
        let status = unsafe { fg_pipeline_step(pipeline, &input, &mut out, &mut error) };
        if status != FgStatus::Ok {
            eprintln!("tick {k} refused: {status:?}");
            break;
        }
        if k % 100 == 0 {
            println!(
                "t={:.2} mode={} command={} speed={:.6} steering={:.6} y={:.6}",
                f64::from(k) * dt,
                out.mode as i32,
                i32::from(out.has_command),
                out.speed_m_s,
                out.steering_rad,
                out.lateral_error_m
            );
        }
        let v = out.speed_m_s;
        x += dt * v * heading.cos();
        y += dt * v * heading.sin();
        heading += dt * v * out.steering_rad.tan() / wheelbase;
    }
    // SAFETY: made by `fg_pipeline_new` above, freed once, not used after.
    unsafe { fg_pipeline_free(pipeline) };
    std::process::ExitCode::SUCCESS
}
