//! Validates `[furrow]`: the furrow detector and the law of furrow pursuing,
//! on the inclined LiDAR of `[lidar]`.

use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::perception::furrow::{FurrowConfig, FurrowParams, Rows};
use fieldguide::{Meters, MetersPerSecond, Radians};

use super::control::{forward_speed, gains, within_schedule};
use super::lidar::LidarSetup;
use crate::capacity::{FURROW_RAYS, FURROW_SCANS};
use crate::error::ScenarioError;
use crate::lidar::inclined::InclinedLidar;
use crate::scenario::check::Checker;
use crate::scenario::schema::FurrowSection;

/// Furrow pursuing: the detector's validated configuration and the law it drives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FurrowSetup {
    /// The detector (Table 2 with the library's choices), mount taken from `[lidar]`.
    pub detector: FurrowConfig,
    /// The backstepping law of furrow pursuing: no sideslip, no prediction
    /// (Pierre 2022, section 2.3.1: "this version of the control law does not
    /// include an estimation of sideslip angles or the predictive layer").
    pub backstepping: BacksteppingConfig,
    /// Forward speed while pursuing the furrow.
    pub speed: MetersPerSecond,
}

/// The furrow detector and law of `[furrow]`, the mount taken from `[lidar]`,
/// the vehicle and inversion from the path-tracking law `path_law`.
pub(super) fn furrow(
    f: &FurrowSection,
    lidar: &LidarSetup,
    path_law: &BacksteppingConfig,
    check: &Checker<'_>,
) -> Result<FurrowSetup, ScenarioError> {
    let speed = forward_speed(check, "furrow", f.speed_m_s)?;
    within_schedule(check, "furrow", path_law, speed)?;
    let gains = gains(
        check,
        "furrow",
        f.lateral_gain,
        f.heading_gain,
        f.min_gain_ratio,
    )?;
    let half = check
        .open_range(
            "furrow.window_half_angle_deg",
            f.window_half_angle_deg,
            0.0,
            90.0,
        )?
        .to_radians();
    let in_window = window_rays(&lidar.lidar, half);
    if in_window > FURROW_RAYS {
        return Err(check.error(
            "furrow.window_half_angle_deg",
            &format!(
                "the window holds {in_window} rays of the LiDAR, more than the detector's {FURROW_RAYS}"
            ),
        ));
    }
    let width = f.template_width_rays;
    if width % 2 == 0 || width > 999 {
        return Err(check.error(
            "furrow.template_width_rays",
            &format!("must be odd and at most 999 (the model is centred on a ray), got {width}"),
        ));
    }
    if f.template_margin_rays > 999 {
        return Err(check.error(
            "furrow.template_margin_rays",
            &format!("must be at most 999, got {}", f.template_margin_rays),
        ));
    }
    let h_ref = check.open_range("furrow.template_height_m", f.template_height_m, 0.0, 10.0)?;
    let floor = check.range("furrow.height_floor_m", f.height_floor_m, 0.0, h_ref)?;
    check.below(
        "furrow.height_floor_m",
        floor,
        "furrow.template_height_m",
        h_ref,
    )?;
    let c_t = check.open_range("furrow.peak_threshold", f.peak_threshold, 0.0, 1.0)?;
    let rows = match (f.rows, f.min_row_spacing_m, f.max_row_spacing_m) {
        (1, None, None) => Rows::One,
        (1, _, _) => {
            return Err(check.error(
                "furrow.rows",
                "one row takes no `min_row_spacing_m` / `max_row_spacing_m`",
            ))
        }
        (2, Some(lo), Some(hi)) => {
            let lo = check.open_range("furrow.min_row_spacing_m", lo, 0.0, 100.0)?;
            let hi = check.open_range("furrow.max_row_spacing_m", hi, 0.0, 100.0)?;
            check.above(
                "furrow.max_row_spacing_m",
                hi,
                "furrow.min_row_spacing_m",
                lo,
            )?;
            Rows::Two {
                min_spacing: meters(check, "furrow.min_row_spacing_m", lo)?,
                max_spacing: meters(check, "furrow.max_row_spacing_m", hi)?,
            }
        }
        (2, None, _) => {
            return Err(check.error("furrow.min_row_spacing_m", "required with rows = 2"))
        }
        (2, _, None) => {
            return Err(check.error("furrow.max_row_spacing_m", "required with rows = 2"))
        }
        (n, _, _) => return Err(check.error("furrow.rows", &format!("must be 1 or 2, got {n}"))),
    };
    let scans = check.count("furrow.averaged_scans", f.averaged_scans, 1, FURROW_SCANS)?;
    let min_points = check.count("furrow.min_points", f.min_points, 2, 1000)?;
    let enter = check.range("furrow.enter_correlation", f.enter_correlation, 0.0, 1.0)?;
    let exit = check.range("furrow.exit_correlation", f.exit_correlation, 0.0, 1.0)?;
    check.above(
        "furrow.enter_correlation",
        enter,
        "furrow.exit_correlation",
        exit,
    )?;
    let l = &lidar.lidar;
    let keep = check.open_range("furrow.keep_distance_m", f.keep_distance_m, 0.0, 1000.0)?;
    let extent = check.range("furrow.min_extent_m", f.min_extent_m, 0.0, 100.0)?;
    let span = check.range("furrow.min_span_m", f.min_span_m.unwrap_or(0.0), 0.0, 100.0)?;
    let params = FurrowParams {
        mount_x: meters(check, "lidar.mount_x_m", l.mount_x)?,
        mount_y: meters(check, "lidar.mount_y_m", l.mount_y)?,
        mount_height: meters(check, "lidar.height_m", l.height)?,
        mount_pitch: Radians::new(l.pitch)
            .map_err(|e| check.error("lidar.pitch_deg", &e.to_string()))?,
        window_half_angle: Radians::new(half)
            .map_err(|e| check.error("furrow.window_half_angle_deg", &e.to_string()))?,
        template_width: usize::try_from(width).unwrap_or(1),
        template_margin: usize::try_from(f.template_margin_rays).unwrap_or(0),
        template_height: meters(check, "furrow.template_height_m", h_ref)?,
        height_floor: meters(check, "furrow.height_floor_m", floor)?,
        peak_threshold: c_t,
        rows,
        averaged_scans: scans,
        keep_distance: meters(check, "furrow.keep_distance_m", keep)?,
        min_span: meters(check, "furrow.min_span_m", span)?,
        min_points,
        min_extent: meters(check, "furrow.min_extent_m", extent)?,
        enter,
        exit,
    };
    // Every value was range-checked above; what the core still refuses is
    // reported against the section, with the requirement it names.
    let detector =
        FurrowConfig::new(&params).map_err(|e| check.refused("furrow", "configuration", &e))?;
    Ok(FurrowSetup {
        detector,
        backstepping: BacksteppingConfig { gains, ..*path_law },
        speed,
    })
}

/// Number of rays of `lidar` whose angle lies within ±`half` rad (the
/// detector's window), counted as the core counts them.
fn window_rays(lidar: &InclinedLidar, half: f64) -> usize {
    (0..lidar.rays)
        .map(|j| lidar.angle_min() + j as f64 * lidar.angle_increment())
        .filter(|a| (-half..=half).contains(a))
        .count()
}

/// `value` as core `Meters` (already range-checked, so only a non-finite
/// value could fail), the error naming `field`.
fn meters(check: &Checker<'_>, field: &str, value: f64) -> Result<Meters, ScenarioError> {
    Meters::new(value).map_err(|e| check.error(field, &e.to_string()))
}
