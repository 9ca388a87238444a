//! Validates the sensor sections: `[noise]` (GNSS, sideslip observer and
//! odometry errors) and `[gnss]` (the outages of the RTK fix).

use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::schema::ScenarioFile;
use crate::sensors::SensorNoise;

/// Spans of simulated time `[from, to)` without a GNSS fix, seconds, in
/// increasing order without overlap.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GnssOutages(Vec<(f64, f64)>);

impl GnssOutages {
    /// Whether the GNSS has a fix at time `t_s`.
    #[must_use]
    pub fn has_fix(&self, t_s: f64) -> bool {
        !self.0.iter().any(|(from, to)| t_s >= *from && t_s < *to)
    }

    /// The spans, seconds.
    #[must_use]
    pub fn spans(&self) -> &[(f64, f64)] {
        &self.0
    }
}

/// The sensor noise of `[noise]`.
pub(super) fn noise(
    file: &ScenarioFile,
    check: &Checker<'_>,
) -> Result<SensorNoise, ScenarioError> {
    let n = &file.noise;
    Ok(SensorNoise {
        gnss_position_m: check.range("noise.gnss_position_m", n.gnss_position_m, 0.0, 10.0)?,
        gnss_heading_rad: check
            .range("noise.gnss_heading_deg", n.gnss_heading_deg, 0.0, 45.0)?
            .to_radians(),
        sideslip_rad: check
            .range("noise.sideslip_deg", n.sideslip_deg, 0.0, 45.0)?
            .to_radians(),
        sideslip_observer_settling_s: check.range(
            "noise.sideslip_observer_settling_s",
            n.sideslip_observer_settling_s,
            0.0,
            60.0,
        )?,
        odometry_scale_error: check.range(
            "noise.odometry_scale_error",
            n.odometry_scale_error,
            -0.5,
            0.5,
        )?,
        odometry_yaw_bias_rad_s: check
            .range(
                "noise.odometry_yaw_bias_deg_s",
                n.odometry_yaw_bias_deg_s,
                -90.0,
                90.0,
            )?
            .to_radians(),
        odometry_yaw_noise_rad: check
            .range(
                "noise.odometry_yaw_noise_deg",
                n.odometry_yaw_noise_deg,
                0.0,
                45.0,
            )?
            .to_radians(),
    })
}

/// The outages of `[gnss]`, none when the section is absent.
pub(super) fn gnss_outages(
    file: &ScenarioFile,
    check: &Checker<'_>,
) -> Result<GnssOutages, ScenarioError> {
    let mut spans: Vec<(f64, f64)> = Vec::new();
    for (i, [from, to]) in file
        .gnss
        .as_ref()
        .map_or(&[][..], |g| g.outages_s.as_slice())
        .iter()
        .copied()
        .enumerate()
    {
        let field = format!("gnss.outages_s[{i}]");
        let earliest = spans.last().map_or(0.0, |(_, end)| *end);
        let from = check.non_negative(&field, from)?;
        let to = check.finite(&field, to)?;
        if from < earliest {
            return Err(check.error(&field, "must start after the previous outage ends"));
        }
        if to <= from {
            return Err(check.error(&field, "must end after it starts"));
        }
        spans.push((from, to));
    }
    Ok(GnssOutages(spans))
}
