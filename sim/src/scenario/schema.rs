//! The scenario file as written in TOML (`sim/scenarios/README.md` documents
//! every field). Units are in the field names: `_m` metres, `_s` seconds,
//! `_deg` degrees, `_deg_s` degrees per second, `_m_s` metres per second.
//!
//! Every table refuses unknown keys, so a misspelt field is an error naming it
//! rather than a silently ignored line. Ranges are checked in
//! [`super::setup`], which names the field of any value out of range.

use serde::Deserialize;

/// A whole scenario file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// Name of the scenario: the output folder `out/<name>/`. Letters, digits, `-`, `_`.
    pub name: String,
    /// One line saying what the scenario shows.
    pub description: String,
    /// Seed of the run's only random generator.
    pub seed: u64,
    /// The reference path.
    pub path: PathSection,
    /// Where the robot starts, relative to the start of the path.
    pub initial: InitialSection,
    /// The vehicle plant.
    pub vehicle: VehicleSection,
    /// The guidance: speed, gains, prediction horizon, compensation.
    pub control: ControlSection,
    /// Sideslip of the ground, everywhere and per patch.
    pub terrain: TerrainSection,
    /// Sensor noise.
    pub noise: NoiseSection,
    /// How long the run lasts.
    pub run: RunSection,
    /// Bounds for the summary's convergence and success.
    pub metrics: MetricsSection,
}

/// `[path]`: the reference path, from segments or from a CSV of waypoints.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PathSection {
    /// Pose where the first segment starts (required with `segments`, refused with `csv`).
    pub start: Option<StartPose>,
    /// The path as straight and arc segments, sampled every `sample_step_m`.
    pub segments: Option<Vec<Segment>>,
    /// The path as a CSV file of waypoints `x_m,y_m` (header line), relative to the scenario file.
    pub csv: Option<String>,
    /// Spacing of the waypoints sampled along segments, metres.
    pub sample_step_m: f64,
    /// Standard deviation of the Gaussian noise added to each sampled waypoint
    /// (a path recorded by driving with RTK-GNSS), metres.
    pub recording_noise_m: f64,
    /// Smoothing window of the reference path (core `PathConfig`), metres.
    pub smoothing_window_m: f64,
}

/// `[path.start]`: the pose where the first segment starts, world frame.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartPose {
    /// East coordinate, metres.
    pub x_m: f64,
    /// North coordinate, metres.
    pub y_m: f64,
    /// Heading, degrees counter-clockwise from east.
    pub heading_deg: f64,
}

/// One segment: either `{ straight_m = L }` or `{ arc_radius_m = R, arc_angle_deg = A }`
/// (A > 0 turns left, A < 0 turns right).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Segment {
    /// Length of a straight segment, metres.
    pub straight_m: Option<f64>,
    /// Radius of an arc, metres.
    pub arc_radius_m: Option<f64>,
    /// Signed turning angle of an arc, degrees, positive to the left.
    pub arc_angle_deg: Option<f64>,
}

/// `[initial]`: the robot's start pose, in the Frénet frame of the path's first point.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// Offset along the path's initial tangent, metres (negative: behind the start).
    pub longitudinal_m: f64,
    /// Lateral offset, metres, positive to the left of the path.
    pub lateral_m: f64,
    /// Heading relative to the path's initial tangent, degrees, positive to the left.
    pub heading_deg: f64,
}

/// `[vehicle]`: the bicycle plant and its steering actuator.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSection {
    /// Wheelbase L, metres.
    pub wheelbase_m: f64,
    /// Track (distance between the left and right wheels), metres.
    pub track_m: f64,
    /// Tyre width, metres (for counting plants under the wheels).
    pub tyre_width_m: f64,
    /// Steering saturation |δ| ≤ δ_max, degrees (also the law's saturation).
    pub max_steering_deg: f64,
    /// 5 % settling time of the first-order steering actuator, seconds (τ = T_s / 3; 0: no lag).
    pub steering_settling_s: f64,
    /// Steering rate limit, degrees per second.
    pub steering_rate_deg_s: f64,
}

/// How the steering law inverts the yaw rate (`fieldguide::control::backstepping::Inversion`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InversionName {
    /// Exact inversion (keeps cos θ̃₂ / cos β_R).
    Exact,
    /// Eq. 6 as printed.
    Printed,
}

/// `[control]`: the path-tracking guidance.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSection {
    /// Forward speed v, m/s (held constant by the plant).
    pub speed_m_s: f64,
    /// Control period, seconds (default 0.02 s, 50 Hz).
    #[serde(default = "default_period_s")]
    pub period_s: f64,
    /// Lateral gain g_y as the papers' tables give it (positive); the law uses k_y = −g_y, 1/m.
    pub lateral_gain: f64,
    /// Heading gain g_θ (positive); the law uses k_θ = −g_θ, 1/m.
    pub heading_gain: f64,
    /// Minimum ratio g_θ / g_y the core accepts (|k_θ| ≫ |k_y|).
    pub min_gain_ratio: f64,
    /// Prediction horizon T, seconds: the curvature is fed forward at s + v T.
    pub horizon_s: f64,
    /// Whether the law uses the sideslip observer's estimate (false: β = 0 in the law).
    pub sideslip_compensation: bool,
    /// `"exact"` or `"printed"` reading of eq. 6.
    pub inversion: InversionName,
}

/// `[terrain]`: sideslip everywhere, and patches where it differs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainSection {
    /// Front sideslip β_F outside every patch, degrees.
    pub front_sideslip_deg: f64,
    /// Rear sideslip β_R outside every patch, degrees.
    pub rear_sideslip_deg: f64,
    /// Patches of ground with their own sideslip (`[[terrain.patches]]`); the first that contains the rear-axle midpoint applies.
    #[serde(default)]
    pub patches: Vec<PatchSection>,
}

/// `[[terrain.patches]]`: a polygon of ground with its own sideslip angles.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatchSection {
    /// Name, for plots and messages.
    pub name: String,
    /// Vertices `[x_m, y_m]` in the world frame, at least 3, in order.
    pub polygon: Vec<[f64; 2]>,
    /// Front sideslip β_F on the patch, degrees.
    pub front_sideslip_deg: f64,
    /// Rear sideslip β_R on the patch, degrees.
    pub rear_sideslip_deg: f64,
}

/// `[noise]`: standard deviations and drifts of the simulated sensors.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseSection {
    /// RTK-GNSS position noise, per axis, metres.
    pub gnss_position_m: f64,
    /// GNSS/IMU heading noise, degrees.
    pub gnss_heading_deg: f64,
    /// Sideslip observer noise on each angle, degrees.
    pub sideslip_deg: f64,
    /// 5 % settling time of the sideslip observer, seconds (0: follows the true value at once).
    pub sideslip_observer_settling_s: f64,
    /// Relative scale error of the wheel odometry distance (0.01 = 1 % too long).
    pub odometry_scale_error: f64,
    /// Bias of the odometry yaw rate, degrees per second.
    pub odometry_yaw_bias_deg_s: f64,
    /// Noise on each odometry heading increment, degrees.
    pub odometry_yaw_noise_deg: f64,
}

/// `[run]`: duration and integration.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    /// Longest simulated time, seconds.
    pub duration_s: f64,
    /// Stop as soon as the robot's projection reaches the end of the path.
    pub stop_at_path_end: bool,
    /// RK4 sub-steps of the plant per control period.
    pub substeps: u32,
}

/// `[metrics]`: convergence band and success bounds.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MetricsSection {
    /// |y| band for convergence, metres (default 0.05 m).
    #[serde(default = "default_band_m")]
    pub band_m: f64,
    /// Success needs `converged_after_m` (|y| stays in the band from there to the end) at most this, metres.
    pub converge_within_m: f64,
}

fn default_period_s() -> f64 {
    0.02
}

fn default_band_m() -> f64 {
    0.05
}
