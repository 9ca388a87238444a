//! Validates `[vehicle]`: wheelbase, track, tyres and the steering actuator.

use fieldguide::model::bicycle::{SteeringLimit, Wheelbase};

use crate::error::ScenarioError;
use crate::plant::{SteeringActuator, VehicleParams};
use crate::scenario::check::Checker;
use crate::scenario::schema::ScenarioFile;

/// The vehicle of `[vehicle]`.
pub(super) fn vehicle(
    file: &ScenarioFile,
    check: &Checker<'_>,
) -> Result<VehicleParams, ScenarioError> {
    let v = &file.vehicle;
    let wheelbase = Wheelbase::new(check.positive("vehicle.wheelbase_m", v.wheelbase_m)?)
        .map_err(|e| check.error("vehicle.wheelbase_m", &e.to_string()))?;
    let max = check.open_range("vehicle.max_steering_deg", v.max_steering_deg, 0.0, 90.0)?;
    let limit = SteeringLimit::new(max.to_radians())
        .map_err(|e| check.error("vehicle.max_steering_deg", &e.to_string()))?;
    let settling = check.range(
        "vehicle.steering_settling_s",
        v.steering_settling_s,
        0.0,
        60.0,
    )?;
    let rate = check.positive("vehicle.steering_rate_deg_s", v.steering_rate_deg_s)?;
    Ok(VehicleParams {
        wheelbase,
        track_m: check.positive("vehicle.track_m", v.track_m)?,
        tyre_width_m: check.non_negative("vehicle.tyre_width_m", v.tyre_width_m)?,
        actuator: SteeringActuator::from_settling(settling, rate.to_radians(), limit),
    })
}
