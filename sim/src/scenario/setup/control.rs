//! Validates `[control]`, the path-tracking law, and holds what the laws of
//! `[edge]` and `[furrow]` share with it: forward speed and table gains.

use fieldguide::control::backstepping::{BacksteppingConfig, Gains, Inversion, SpeedSchedule};
use fieldguide::control::ControlLaw;
use fieldguide::{Meters, MetersPerSecond, RadiansPerSecond, Seconds};

use crate::error::ScenarioError;
use crate::plant::VehicleParams;
use crate::scenario::check::Checker;
use crate::scenario::schema::{InversionName, ScenarioFile};

/// The guidance settings, typed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlSetup {
    /// The backstepping law's configuration (gains in equation form, k = −g).
    pub backstepping: BacksteppingConfig,
    /// Forward speed v.
    pub speed: MetersPerSecond,
    /// Control period, seconds.
    pub period_s: f64,
    /// Prediction horizon T, seconds.
    pub horizon_s: f64,
    /// The steering's time constant τ the law is told, seconds.
    pub steering_lag_s: f64,
    /// Curvature look-ahead distance v (T + τ).
    pub lookahead: Meters,
    /// Whether the law uses the observer's sideslip estimate.
    pub sideslip_compensation: bool,
}

/// The path-tracking law of `[control]` on `vehicle`.
pub(super) fn control(
    file: &ScenarioFile,
    check: &Checker<'_>,
    vehicle: VehicleParams,
) -> Result<ControlSetup, ScenarioError> {
    let c = &file.control;
    let speed = forward_speed(check, "control", c.speed_m_s)?;
    // At most 10 kHz: every delay of the switching machine, counted in
    // ticks, stays far inside its 16-bit counter.
    let period_s = check.range("control.period_s", c.period_s, 1e-4, 1.0)?;
    let gains = gains(
        check,
        "control",
        c.lateral_gain,
        c.heading_gain,
        c.min_gain_ratio,
    )?;
    let horizon_s = check.range("control.horizon_s", c.horizon_s, 0.0, 10.0)?;
    let steering_lag_s = check.range("control.steering_lag_s", c.steering_lag_s, 0.0, 20.0)?;
    let lookahead = Meters::new(speed.get() * (horizon_s + steering_lag_s))
        .map_err(|e| check.error("control.horizon_s", &e.to_string()))?;
    let schedule = match &c.schedule {
        Some(section) => Some(schedule(check, section, &vehicle, steering_lag_s)?),
        None => None,
    };
    let inversion = match c.inversion {
        InversionName::Exact => Inversion::Exact,
        InversionName::Printed => Inversion::Printed,
    };
    let backstepping = BacksteppingConfig {
        gains,
        vehicle: vehicle.bicycle(),
        inversion,
        schedule,
    };
    within_schedule(check, "control", &backstepping, speed)?;
    Ok(ControlSetup {
        backstepping,
        speed,
        period_s,
        horizon_s,
        steering_lag_s,
        lookahead,
        sideslip_compensation: c.sideslip_compensation,
    })
}

/// The speed schedule of `[control.schedule]` on `vehicle`.
fn schedule(
    check: &Checker<'_>,
    section: &crate::scenario::schema::ScheduleSection,
    vehicle: &VehicleParams,
    steering_lag_s: f64,
) -> Result<SpeedSchedule, ScenarioError> {
    let min_field = "control.schedule.min_speed_m_s";
    let max_field = "control.schedule.max_speed_m_s";
    let min = check.open_range(min_field, section.min_speed_m_s, 0.0, 20.0)?;
    let max = check.open_range(max_field, section.max_speed_m_s, 0.0, 20.0)?;
    if max < min {
        return Err(check.error(max_field, &format!("must be >= {min_field} = {min}")));
    }
    let to_speed = |field: &str, v: f64| {
        MetersPerSecond::new(v).map_err(|e| check.error(field, &e.to_string()))
    };
    let (min, max) = (to_speed(min_field, min)?, to_speed(max_field, max)?);
    let built = match section.bandwidth_per_s {
        Some(b) => {
            let field = "control.schedule.bandwidth_per_s";
            let b = check.open_range(field, b, 0.0, 1e3)?;
            let b = RadiansPerSecond::new(b).map_err(|e| check.error(field, &e.to_string()))?;
            SpeedSchedule::new(min, max, b)
        }
        None => Seconds::new(steering_lag_s)
            .and_then(|tau| SpeedSchedule::for_actuator(min, max, &vehicle.bicycle(), tau)),
    }
    .map_err(|e| check.error("control.schedule", &e.to_string()))?;
    Ok(built)
}

/// Refuses `section.speed_m_s` when `law` does not accept `speed` (outside
/// its speed schedule: PT-SCHEDULE-RANGE).
pub(super) fn within_schedule(
    check: &Checker<'_>,
    section: &str,
    law: &BacksteppingConfig,
    speed: MetersPerSecond,
) -> Result<(), ScenarioError> {
    law.check_speed(speed).map_err(|e| {
        let range = law.schedule.map_or(String::new(), |s| {
            format!(
                " [{}, {}] m/s of control.schedule",
                s.min_speed().get(),
                s.max_speed().get()
            )
        });
        check.error(
            &format!("{section}.speed_m_s"),
            &format!("{} m/s is outside the range{range} ({e})", speed.get()),
        )
    })
}

/// The forward speed `section.speed_m_s` of a behaviour: within (0, 20) m/s.
pub(super) fn forward_speed(
    check: &Checker<'_>,
    section: &str,
    speed_m_s: f64,
) -> Result<MetersPerSecond, ScenarioError> {
    let field = format!("{section}.speed_m_s");
    let speed = check.open_range(&field, speed_m_s, 0.0, 20.0)?;
    MetersPerSecond::new(speed).map_err(|e| check.error(&field, &e.to_string()))
}

/// The law's gains from the table gains `section.lateral_gain` and
/// `section.heading_gain` (positive, as printed; the law's equation-form
/// gains are k = −g) and their least ratio `section.min_gain_ratio`.
pub(super) fn gains(
    check: &Checker<'_>,
    section: &str,
    lateral_gain: f64,
    heading_gain: f64,
    min_gain_ratio: f64,
) -> Result<Gains, ScenarioError> {
    let g_y = check.positive(&format!("{section}.lateral_gain"), lateral_gain)?;
    let g_theta = check.positive(&format!("{section}.heading_gain"), heading_gain)?;
    let ratio = check.range(
        &format!("{section}.min_gain_ratio"),
        min_gain_ratio,
        1.0,
        1e6,
    )?;
    Gains::new(-g_y, -g_theta, ratio).map_err(|e| {
        check.error(
            &format!("{section}.heading_gain"),
            &format!(
                "heading_gain / lateral_gain = {} is below {section}.min_gain_ratio = {ratio} ({e})",
                g_theta / g_y
            ),
        )
    })
}
