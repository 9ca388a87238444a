//! Validates the two LiDAR sections: `[lidar]`, the inclined LiDAR that sees
//! the rows, and `[horizontal_lidar]`, the one that sees the edge.

use crate::error::ScenarioError;
use crate::lidar::horizontal::{HorizontalLidar, HorizontalLidarSpec};
use crate::lidar::inclined::InclinedLidar;
use crate::scenario::check::Checker;
use crate::scenario::schema::{HorizontalLidarSection, LidarSection};

/// The inclined LiDAR and how often it scans.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LidarSetup {
    /// The sensor and its mount.
    pub lidar: InclinedLidar,
    /// A scan every this many control ticks (the scan period over the control period).
    pub scan_every: u64,
}

/// The horizontal LiDAR and how often it scans.
#[derive(Debug, Clone, Copy)]
pub struct HorizontalLidarSetup {
    /// The sensor and its mount.
    pub lidar: HorizontalLidar,
    /// A scan every this many control ticks.
    pub scan_every: u64,
}

/// The inclined LiDAR of `[lidar]`; its scan period must be a whole number of
/// control periods `period_s`.
pub(super) fn lidar(
    l: &LidarSection,
    period_s: f64,
    check: &Checker<'_>,
) -> Result<LidarSetup, ScenarioError> {
    let height = check.open_range("lidar.height_m", l.height_m, 0.0, 10.0)?;
    let pitch = check.open_range("lidar.pitch_deg", l.pitch_deg, 0.0, 90.0)?;
    let fov = check.open_range("lidar.field_of_view_deg", l.field_of_view_deg, 0.0, 360.0)?;
    let (rays, range_min, range_max) =
        rays_and_ranges(check, "lidar", l.rays, l.range_min_m, l.range_max_m)?;
    let scan_every = scan_every(check, "lidar.rate_hz", l.rate_hz, period_s)?;
    Ok(LidarSetup {
        lidar: InclinedLidar {
            mount_x: check.range("lidar.mount_x_m", l.mount_x_m, -20.0, 20.0)?,
            mount_y: check.range("lidar.mount_y_m", l.mount_y_m, -20.0, 20.0)?,
            height,
            pitch: pitch.to_radians(),
            field_of_view: fov.to_radians(),
            rays,
            range_min,
            range_max,
            range_noise: check.range("lidar.range_noise_m", l.range_noise_m, 0.0, 1.0)?,
        },
        scan_every,
    })
}

/// The horizontal LiDAR of `[horizontal_lidar]`; its scan period must be a
/// whole number of control periods `period_s`.
pub(super) fn horizontal_lidar(
    l: &HorizontalLidarSection,
    period_s: f64,
    check: &Checker<'_>,
) -> Result<HorizontalLidarSetup, ScenarioError> {
    let fov = check.range(
        "horizontal_lidar.field_of_view_deg",
        l.field_of_view_deg,
        0.0,
        360.0,
    )?;
    if fov <= 0.0 {
        return Err(check.error(
            "horizontal_lidar.field_of_view_deg",
            &format!("must be within (0, 360], got {fov}"),
        ));
    }
    let (rays, range_min, range_max) = rays_and_ranges(
        check,
        "horizontal_lidar",
        l.rays,
        l.range_min_m,
        l.range_max_m,
    )?;
    let spec = HorizontalLidarSpec {
        mount_xy: [
            check.range("horizontal_lidar.mount_x_m", l.mount_x_m, -20.0, 20.0)?,
            check.range("horizontal_lidar.mount_y_m", l.mount_y_m, -20.0, 20.0)?,
        ],
        mount_heading: check
            .range(
                "horizontal_lidar.mount_heading_deg",
                l.mount_heading_deg,
                -180.0,
                180.0,
            )?
            .to_radians(),
        mount_height: check.range(
            "horizontal_lidar.mount_height_m",
            l.mount_height_m.unwrap_or(1.0),
            0.0,
            20.0,
        )?,
        field_of_view: fov.to_radians(),
        rays,
        range_min,
        range_max,
        noise_sigma: check.range("horizontal_lidar.range_noise_m", l.range_noise_m, 0.0, 1.0)?,
    };
    let lidar = HorizontalLidar::new(spec)
        .map_err(|e| check.error(&format!("horizontal_lidar.{}", e.field), e.reason))?;
    Ok(HorizontalLidarSetup {
        lidar,
        scan_every: scan_every(check, "horizontal_lidar.rate_hz", l.rate_hz, period_s)?,
    })
}

/// The scan period of a LiDAR scanning at `rate_hz` (field `field`) in
/// control periods of `period_s`: it must be a whole number, at least 1.
fn scan_every(
    check: &Checker<'_>,
    field: &str,
    rate_hz: f64,
    period_s: f64,
) -> Result<u64, ScenarioError> {
    let rate = check.open_range(field, rate_hz, 0.0, 1000.0)?;
    let ticks = 1.0 / (rate * period_s);
    let every = ticks.round();
    if every < 1.0 || (ticks - every).abs() > 1e-6 * ticks {
        return Err(check.error(
            field,
            &format!(
                "the scan period 1/{rate} s must be a whole number of control periods ({period_s} s)"
            ),
        ));
    }
    // A whole number in [1, 1e6 / period]: the conversion is exact.
    Ok(every as u64)
}

/// The ray count and valid range interval shared by both LiDAR sections
/// (`section` names them in errors): 2 to 10 000 rays, 0 ≤ min < max ≤ 1000 m.
fn rays_and_ranges(
    check: &Checker<'_>,
    section: &str,
    rays: u32,
    range_min: f64,
    range_max: f64,
) -> Result<(usize, f64, f64), ScenarioError> {
    let rays = check.count(&format!("{section}.rays"), rays, 2, 10_000)?;
    let min_field = format!("{section}.range_min_m");
    let max_field = format!("{section}.range_max_m");
    let range_min = check.range(&min_field, range_min, 0.0, 1000.0)?;
    let range_max = check.range(&max_field, range_max, 0.0, 1000.0)?;
    check.above(&max_field, range_max, &min_field, range_min)?;
    Ok((rays, range_min, range_max))
}
