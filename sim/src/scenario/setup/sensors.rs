//! Validates the sensor sections: `[noise]` (GNSS, sideslip observer and
//! odometry errors) and `[gnss]` (the outages of the RTK fix).

use fieldguide::{Meters, Pose2, World};

use crate::capacity::Reference;
use crate::error::ScenarioError;
use crate::gnss::{AbscissaSpan, Drift, FloatFix, GnssErrors, GnssOutages, Spans};
use crate::scenario::check::Checker;
use crate::scenario::schema::{DriftName, GnssSection, HeadingName, NoiseSection, ScenarioFile};
use crate::sensors::{GyroErrors, HeadingSource, SensorNoise};
use crate::world::crops::PlotSpec;

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
        heading: heading(n, check)?,
    })
}

/// The odometry's heading source of `[noise]`: with a gyro, its random walk
/// and bias are needed and the wheels' yaw errors must be 0; with the wheels,
/// the `gyro_*` fields are refused.
fn heading(n: &NoiseSection, check: &Checker<'_>) -> Result<HeadingSource, ScenarioError> {
    if n.odometry_heading == HeadingName::Wheels {
        for (field, given) in [
            (
                "noise.gyro_random_walk_deg_sqrt_h",
                n.gyro_random_walk_deg_sqrt_h,
            ),
            ("noise.gyro_bias_deg_h", n.gyro_bias_deg_h),
            (
                "noise.gyro_bias_instability_deg_h",
                n.gyro_bias_instability_deg_h,
            ),
            (
                "noise.gyro_bias_time_constant_s",
                n.gyro_bias_time_constant_s,
            ),
        ] {
            if given.is_some() {
                return Err(check.error(field, "needs `noise.odometry_heading = \"gyro\"`"));
            }
        }
        return Ok(HeadingSource::Wheels);
    }
    for (field, value) in [
        ("noise.odometry_yaw_bias_deg_s", n.odometry_yaw_bias_deg_s),
        ("noise.odometry_yaw_noise_deg", n.odometry_yaw_noise_deg),
    ] {
        if value != 0.0 {
            return Err(check.error(
                field,
                "must be 0 with `odometry_heading = \"gyro\"` (the gyro gives the heading)",
            ));
        }
    }
    let needed = |field: &str, value: Option<f64>| {
        value.ok_or_else(|| check.error(field, "needed with `odometry_heading = \"gyro\"`"))
    };
    // Datasheet units to SI: °/√h to rad/√s, °/h to rad/s.
    let per_root_hour = |deg: f64| deg.to_radians() / 60.0;
    let per_hour = |deg: f64| deg.to_radians() / 3600.0;
    let (instability, time_constant) =
        match (n.gyro_bias_instability_deg_h, n.gyro_bias_time_constant_s) {
            (None, None) => (0.0, 1.0),
            (None, Some(_)) => {
                return Err(check.error(
                    "noise.gyro_bias_time_constant_s",
                    "needs `noise.gyro_bias_instability_deg_h`",
                ))
            }
            (Some(_), None) => {
                return Err(check.error(
                    "noise.gyro_bias_time_constant_s",
                    "needed with `noise.gyro_bias_instability_deg_h`",
                ))
            }
            (Some(sigma), Some(tau)) => (
                check.range("noise.gyro_bias_instability_deg_h", sigma, 0.0, 3600.0)?,
                check.open_range("noise.gyro_bias_time_constant_s", tau, 0.0, 1e6)?,
            ),
        };
    Ok(HeadingSource::Gyro(GyroErrors {
        random_walk_rad_sqrt_s: per_root_hour(check.range(
            "noise.gyro_random_walk_deg_sqrt_h",
            needed(
                "noise.gyro_random_walk_deg_sqrt_h",
                n.gyro_random_walk_deg_sqrt_h,
            )?,
            0.0,
            60.0,
        )?),
        bias_rad_s: per_hour(check.range(
            "noise.gyro_bias_deg_h",
            needed("noise.gyro_bias_deg_h", n.gyro_bias_deg_h)?,
            -3600.0,
            3600.0,
        )?),
        bias_instability_rad_s: per_hour(instability),
        bias_time_constant_s: time_constant,
    }))
}

/// Spans of time `[from, to)` of `field` (`gnss.outages_s`), seconds: each
/// `0 <= from < to`, increasing, not overlapping; with `until_s`, each ending
/// by then (an outage the run cannot outlast is refused).
fn time_spans(
    check: &Checker<'_>,
    field: &str,
    spans: &[[f64; 2]],
    until_s: Option<f64>,
) -> Result<Vec<(f64, f64)>, ScenarioError> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (i, [from, to]) in spans.iter().copied().enumerate() {
        let field = format!("{field}[{i}]");
        let earliest = out.last().map_or(0.0, |(_, end)| *end);
        let from = check.non_negative(&field, from)?;
        let to = check.finite(&field, to)?;
        if from < earliest {
            return Err(check.error(&field, "must start after the previous outage ends"));
        }
        if to <= from {
            return Err(check.error(&field, "must end after it starts"));
        }
        if let Some(until) = until_s.filter(|u| to > *u) {
            return Err(check.error(
                &field,
                &format!(
                    "ends at {to} s, after run.duration_s = {until} s: the fix would not return before the run ends"
                ),
            ));
        }
        out.push((from, to));
    }
    Ok(out)
}

/// Spans of abscissa of `field` (`gnss.outages_m`) on `path`, metres: each
/// `0 <= from < to <= ` the path's length.
fn abscissa_spans(
    check: &Checker<'_>,
    field: &str,
    spans: &[[f64; 2]],
    path: &Reference,
) -> Result<Vec<AbscissaSpan>, ScenarioError> {
    spans
        .iter()
        .enumerate()
        .map(|(i, [from, to])| {
            let field = format!("{field}[{i}]");
            let from = check.non_negative(&field, *from)?;
            let to = check.finite(&field, *to)?;
            abscissa_span(check, &field, from, to, path)
        })
        .collect()
}

/// The span `[from, to)` of `field`, checked against `path`.
fn abscissa_span(
    check: &Checker<'_>,
    field: &str,
    from: f64,
    to: f64,
    path: &Reference,
) -> Result<AbscissaSpan, ScenarioError> {
    let length = path.length().get();
    if to <= from {
        return Err(check.error(field, "must end after it starts"));
    }
    if from < 0.0 || to > length {
        return Err(check.error(
            field,
            &format!(
                "[{from}, {to}) m leaves the path [0, {length:.2}] m: the fix would not return before the path ends"
            ),
        ));
    }
    Ok(AbscissaSpan {
        from_m: from,
        to_m: to,
        field: field.to_owned(),
    })
}

/// `spans` sorted, refused when two overlap (naming the later one).
fn ordered(
    check: &Checker<'_>,
    mut spans: Vec<AbscissaSpan>,
) -> Result<Vec<AbscissaSpan>, ScenarioError> {
    spans.sort_by(|a, b| a.from_m.total_cmp(&b.from_m));
    for pair in spans.windows(2) {
        if let [a, b] = pair {
            if b.from_m < a.to_m {
                return Err(check.error(
                    &b.field,
                    &format!("overlaps {} [{}, {}) m", a.field, a.from_m, a.to_m),
                ));
            }
        }
    }
    Ok(spans)
}

/// The abscissa on `path` of the end of `plot`'s centre line.
fn plot_end_abscissa(plot: &PlotSpec, path: &Reference) -> Result<f64, fieldguide::Precondition> {
    let (x, y, heading) = plot.centre_line(plot.length);
    let pose = Pose2::<World>::new(x, y, heading)?;
    Ok(path.project(&pose, Meters::ZERO)?.s.get())
}

/// The outages of `[gnss]` on `path` (`plots`: the world's, for outages
/// placed from a plot's end), none when the section is absent. An outage
/// the run cannot outlast (ending after `run.duration_s` or beyond the
/// path's end) is refused.
pub(super) fn gnss_outages(
    file: &ScenarioFile,
    check: &Checker<'_>,
    path: &Reference,
    plots: &[PlotSpec],
) -> Result<GnssOutages, ScenarioError> {
    let Some(g) = file.gnss.as_ref() else {
        return Ok(GnssOutages::default());
    };
    let time = time_spans(
        check,
        "gnss.outages_s",
        &g.outages_s,
        Some(file.run.duration_s),
    )?;
    let mut abscissa = abscissa_spans(check, "gnss.outages_m", &g.outages_m, path)?;
    for (i, o) in g.plot_end_outages.iter().enumerate() {
        let field = format!("gnss.plot_end_outages[{i}]");
        let Some(plot) = plots.get(o.plot) else {
            return Err(check.error(
                &format!("{field}.plot"),
                &format!("no plot {} in `[[world.plots]]`", o.plot),
            ));
        };
        let before = check.finite(&format!("{field}.before_m"), o.before_m)?;
        let length = check.positive(&format!("{field}.length_m"), o.length_m)?;
        let end = plot_end_abscissa(plot, path).map_err(|e| check.error(&field, &e.to_string()))?;
        abscissa.push(abscissa_span(
            check,
            &field,
            end - before,
            end - before + length,
            path,
        )?);
    }
    Ok(GnssOutages(Spans::new(time, ordered(check, abscissa)?)))
}

/// The errors of `[gnss]` on `path`: bias, drift and float spans; none when
/// the section is absent or gives none.
pub(super) fn gnss_errors(
    file: &ScenarioFile,
    check: &Checker<'_>,
    path: &Reference,
) -> Result<GnssErrors, ScenarioError> {
    let Some(g) = file.gnss.as_ref() else {
        return Ok(GnssErrors::default());
    };
    let bias_m = match g.bias_m {
        Some([x, y]) => (
            check.range("gnss.bias_m", x, -100.0, 100.0)?,
            check.range("gnss.bias_m", y, -100.0, 100.0)?,
        ),
        None => (0.0, 0.0),
    };
    Ok(GnssErrors {
        bias_m,
        drift: drift(g, check)?,
        float: float(g, check, path)?,
    })
}

/// The drift of `[gnss]`: `drift_m` and `drift_time_constant_s` are needed
/// with `drift` and refused without it.
fn drift(g: &GnssSection, check: &Checker<'_>) -> Result<Option<Drift>, ScenarioError> {
    let Some(kind) = g.drift else {
        for (field, given) in [
            ("gnss.drift_m", g.drift_m.is_some()),
            (
                "gnss.drift_time_constant_s",
                g.drift_time_constant_s.is_some(),
            ),
            ("gnss.drift_heading_deg", g.drift_heading_deg.is_some()),
        ] {
            if given {
                return Err(check.error(
                    field,
                    "needs `gnss.drift` (\"random_walk\" or \"sinusoid\")",
                ));
            }
        }
        return Ok(None);
    };
    let needed = |field: &str, value: Option<f64>| {
        value.ok_or_else(|| check.error(field, "needed with `gnss.drift`"))
    };
    let size = check.range(
        "gnss.drift_m",
        needed("gnss.drift_m", g.drift_m)?,
        0.0,
        100.0,
    )?;
    let time = check.open_range(
        "gnss.drift_time_constant_s",
        needed("gnss.drift_time_constant_s", g.drift_time_constant_s)?,
        0.0,
        1e6,
    )?;
    Ok(Some(match kind {
        DriftName::RandomWalk => {
            if g.drift_heading_deg.is_some() {
                return Err(check.error(
                    "gnss.drift_heading_deg",
                    "only with `drift = \"sinusoid\"` (a random walk drifts on both axes)",
                ));
            }
            Drift::RandomWalk {
                sigma_m: size,
                time_constant_s: time,
            }
        }
        DriftName::Sinusoid => Drift::Sinusoid {
            amplitude_m: size,
            period_s: time,
            heading_rad: check
                .range(
                    "gnss.drift_heading_deg",
                    g.drift_heading_deg.unwrap_or(90.0),
                    -360.0,
                    360.0,
                )?
                .to_radians(),
        },
    }))
}

/// Default white noise per axis while the fix is float, metres.
pub const FLOAT_NOISE_M: f64 = 0.1;

/// Default standard deviation of the offset drawn when the fix turns float, metres.
pub const FLOAT_JUMP_M: f64 = 0.3;

/// The float-fix spans of `[gnss]`, if any (their noise and jump refused without spans).
fn float(
    g: &GnssSection,
    check: &Checker<'_>,
    path: &Reference,
) -> Result<Option<FloatFix>, ScenarioError> {
    let time = time_spans(check, "gnss.float_s", &g.float_s, None)?;
    let abscissa = ordered(
        check,
        abscissa_spans(check, "gnss.float_m", &g.float_m, path)?,
    )?;
    let spans = Spans::new(time, abscissa);
    if spans.is_empty() {
        for (field, given) in [
            ("gnss.float_noise_m", g.float_noise_m.is_some()),
            ("gnss.float_jump_m", g.float_jump_m.is_some()),
        ] {
            if given {
                return Err(check.error(
                    field,
                    "needs float spans (`gnss.float_s` or `gnss.float_m`)",
                ));
            }
        }
        return Ok(None);
    }
    Ok(Some(FloatFix {
        spans,
        noise_m: check.range(
            "gnss.float_noise_m",
            g.float_noise_m.unwrap_or(FLOAT_NOISE_M),
            0.0,
            100.0,
        )?,
        jump_m: check.range(
            "gnss.float_jump_m",
            g.float_jump_m.unwrap_or(FLOAT_JUMP_M),
            0.0,
            100.0,
        )?,
    }))
}
