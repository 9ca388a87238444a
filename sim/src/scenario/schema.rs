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
    /// Crop plots and grass (`[world]`, optional: no plants without it).
    pub world: Option<WorldSection>,
    /// An inclined 2D LiDAR looking at the ground (`[lidar]`, optional).
    pub lidar: Option<LidarSection>,
    /// Furrow pursuing (`[furrow]`, optional; needs `[world]` and `[lidar]`).
    pub furrow: Option<FurrowSection>,
    /// A horizontal 2D LiDAR looking at hedges (`[horizontal_lidar]`, optional).
    pub horizontal_lidar: Option<HorizontalLidarSection>,
    /// Edge following (`[edge]`, optional; needs `[horizontal_lidar]`).
    pub edge: Option<EdgeSection>,
    /// The switching machine's delays and the plan check (`[switching]`,
    /// optional: Tables 1-2 and the library's defaults without it).
    pub switching: Option<SwitchingSection>,
    /// Localisation outages and errors; absent: a fix in every tick, white noise only.
    pub gnss: Option<GnssSection>,
}

/// `[gnss]`: when the RTK-GNSS has no fix, and its errors beyond the white
/// noise of `[noise]`. Every field is optional; the defaults add nothing.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GnssSection {
    /// Spans of simulated time `[from, to)` without a fix, seconds, each
    /// `0 <= from < to`, in increasing order without overlap (default none).
    #[serde(default)]
    pub outages_s: Vec<[f64; 2]>,
    /// Spans `[from, to)` of the abscissa of the true pose's projection on
    /// the path without a fix, metres, increasing, not overlapping (default none).
    #[serde(default)]
    pub outages_m: Vec<[f64; 2]>,
    /// Outages placed from a plot's end (`[[gnss.plot_end_outages]]`).
    #[serde(default)]
    pub plot_end_outages: Vec<PlotEndOutage>,
    /// Constant offset `[east, north]` of every reported position, metres (default none).
    pub bias_m: Option<[f64; 2]>,
    /// `"random_walk"` or `"sinusoid"`: a slow drift of the reported position (default none).
    pub drift: Option<DriftName>,
    /// Standard deviation per axis (random walk) or amplitude (sinusoid) of the drift, metres.
    pub drift_m: Option<f64>,
    /// Correlation time (random walk) or period (sinusoid) of the drift, seconds.
    pub drift_time_constant_s: Option<f64>,
    /// Direction of a sinusoidal drift, degrees from east (default 90: north).
    pub drift_heading_deg: Option<f64>,
    /// Spans of simulated time `[from, to)` with a float fix, seconds.
    #[serde(default)]
    pub float_s: Vec<[f64; 2]>,
    /// Spans of abscissa `[from, to)` with a float fix, metres.
    #[serde(default)]
    pub float_m: Vec<[f64; 2]>,
    /// White noise per axis added while the fix is float, metres (default 0.1).
    pub float_noise_m: Option<f64>,
    /// Standard deviation per axis of the offset drawn when a float span starts, metres (default 0.3).
    pub float_jump_m: Option<f64>,
}

/// `[[gnss.plot_end_outages]]`: an outage starting `before_m` ahead of the
/// end of plot `plot` along the path, lasting `length_m` of path.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotEndOutage {
    /// Index of the plot in `[[world.plots]]` (from 0).
    pub plot: usize,
    /// How far before the plot's end (along the path) the outage starts, metres (negative: after it).
    pub before_m: f64,
    /// Length of path the outage covers, metres.
    pub length_m: f64,
}

/// The kind of the GNSS drift.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DriftName {
    /// A first-order Gauss-Markov process per axis (a random walk pulled back
    /// to zero with the time constant), starting at zero.
    RandomWalk,
    /// `drift_m · sin(2π t / T)` along `drift_heading_deg`.
    Sinusoid,
}

/// `[switching]`: transit delays (Pierre 2022, Tables 1-2), Stop delay,
/// held-scan age and plan consistency (SW-PLAN-CONSISTENCY, beyond the paper).
/// Every field is optional; a missing one takes the value in brackets.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwitchingSection {
    /// The behaviours from highest to lowest priority, by section name
    /// (`"furrow"`, `"edge"`): every configured behaviour exactly once
    /// [`["furrow", "edge"]`: crop rows beat a hedge beside the plot].
    pub priority: Option<Vec<String>>,
    /// Time to transit to edge following, s [0.4, Table 1].
    pub edge_enter_s: Option<f64>,
    /// Time to transit back to path tracking from edge following, s [0.26, Table 1].
    pub edge_exit_s: Option<f64>,
    /// Time to transit to furrow pursuing, s [0.5, Table 2].
    pub furrow_enter_s: Option<f64>,
    /// Time to transit back to path tracking from furrow pursuing, s [0.3, Table 2].
    pub furrow_exit_s: Option<f64>,
    /// Stop after this long without a command source, s (default 0.5).
    pub stop_delay_s: Option<f64>,
    /// How long a detection is carried by odometry between scans, s (default 0.1).
    pub max_scan_age_s: Option<f64>,
    /// Plan consistency on: a line further than this from the path leaves
    /// its behaviour, m [off when absent].
    pub plan_max_offset_m: Option<f64>,
    /// Plan consistency: largest heading difference to the path, degrees (default 20).
    pub plan_max_heading_deg: Option<f64>,
    /// Plan consistency of a line whose behaviour is not entered: largest
    /// heading difference to the path, degrees, in [0, plan_max_heading_deg]
    /// (default: plan_max_heading_deg; GD-PLAN-ENTRY).
    pub plan_entry_heading_deg: Option<f64>,
    /// Plan consistency: how long a line may disagree, s (default 0.3).
    pub plan_delay_s: Option<f64>,
    /// Plan consistency: how far ahead along the path the line's offset is
    /// also checked, m (default 0: only at the robot; SW-PLAN-AHEAD).
    pub plan_lookahead_m: Option<f64>,
    /// Plan consistency through a GNSS outage: how far odometry carries the
    /// last fix for the check, m, in (0, 1000] (default: not carried;
    /// GD-PLAN-DEAD-RECKONING).
    pub plan_dead_reckoning_m: Option<f64>,
    /// How far odometry carries the active behaviour's last valid line
    /// across scans that find nothing, m, in (0, 100] (default: not
    /// carried; GD-BRIDGE).
    pub bridge_m: Option<f64>,
    /// After a Stop, steer the wheels to the first command at standstill
    /// before moving (default false; GD-RESUME).
    pub steer_before_resuming: Option<bool>,
    /// Hand-over to path tracking (GD-HANDOVER): the reference stays on the
    /// behaviour's last line for this odometry distance, m, in [0, 1000]
    /// [off when absent].
    pub handover_hold_m: Option<f64>,
    /// Hand-over: the reference's shift then shrinks by this many metres per
    /// metre, in (0, 1] (default 0.1).
    pub handover_slope: Option<f64>,
    /// Hand-over: the line's offset is averaged over this odometry length,
    /// m, > 0 (default 1).
    pub handover_averaging_m: Option<f64>,
    /// Hand-over: for this odometry distance path tracking follows the
    /// behaviour's last line carried by odometry, whatever the fix, m, in
    /// (0, 1000] (GD-HANDOVER-LINE) [off when absent].
    pub handover_line_m: Option<f64>,
    /// Entry into a behaviour (GD-ENTRY): the lateral reference starts at
    /// the robot's error to the line and the point `entry_lead_m` ahead of
    /// the rear axle closes on the line over this length, m, in (0, 1000]
    /// [off when absent].
    pub entry_closing_m: Option<f64>,
    /// Entry: the lead, m, in (0, 1000] [the vehicle's wheelbase].
    pub entry_lead_m: Option<f64>,
    /// Fix rule (GD-FIX-QUALITY): a fix whose claimed horizontal σ is
    /// above this, m, in (0, 1000], or of a kind worse than
    /// `fix_worst_kind`, counts as no fix [off when absent].
    pub fix_max_accuracy_m: Option<f64>,
    /// Fix rule: the worst kind taken, `"rtk_fixed"`, `"rtk_float"`,
    /// `"single"` or `"dead_reckoned"` (default `"rtk_fixed"`).
    pub fix_worst_kind: Option<FixKindName>,
    /// Fix rule: how far path tracking steers on the last good fix carried
    /// by odometry, m, in [0, 1000] [0: it stops commanding at once].
    pub fix_dead_reckoning_m: Option<f64>,
    /// Fix rule: how fast the step to a returning good fix is taken up,
    /// metres per metre, in (0, 1] [0.1].
    pub fix_rejoin_slope: Option<f64>,
    /// Fix rule: the largest curvature of that take-up's shift, 1/m, in
    /// (0, 1000] [0.05].
    pub fix_rejoin_curvature: Option<f64>,
    /// Fix rule: a refused RTK float fix's offset from the carried pose is
    /// averaged over this odometry distance, m, in (0, 1000], and its
    /// changes then correct the carried pose (GD-FIX-FLOAT) [off when absent].
    pub fix_float_averaging_m: Option<f64>,
    /// Odometry aid (GD-ODOMETRY-AID): the odometry's heading is pulled to
    /// each good fix's heading with this time constant, s, in (0, 1000]
    /// [off when absent].
    pub odometry_aid_time_constant_s: Option<f64>,
    /// Odometry aid: the largest rate of its correction, degrees per
    /// second, in (0, 180] [0.5].
    pub odometry_aid_max_rate_deg_s: Option<f64>,
}

/// A fix kind in `switching.fix_worst_kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FixKindName {
    /// RTK fixed.
    RtkFixed,
    /// RTK float.
    RtkFloat,
    /// Single point or code differential.
    Single,
    /// The receiver's own dead reckoning.
    DeadReckoned,
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
    /// The path recorded down the centre lines of the world's plots.
    pub along_plots: Option<AlongPlots>,
    /// Spacing of the waypoints sampled along segments, metres.
    pub sample_step_m: f64,
    /// Standard deviation of the Gaussian noise added to each sampled waypoint
    /// (a path recorded by driving with RTK-GNSS), metres.
    pub recording_noise_m: f64,
    /// Smoothing window of the reference path (core `PathConfig`), metres.
    pub smoothing_window_m: f64,
}

/// `[path.along_plots]`: a path recorded by driving down the true centre line
/// of every plot of `[world]`, in order, joined by straight lines.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlongPlots {
    /// Straight lead-in before the first plot, along its heading, metres.
    pub lead_in_m: f64,
    /// Straight run-out after the last plot, along its heading, metres.
    pub run_out_m: f64,
    /// How one plot's end is joined to the next plot's start (default `"straight"`).
    #[serde(default)]
    pub join: JoinName,
    /// Turning radius of a `"dubins"` join, metres (default: the vehicle's
    /// least, wheelbase / tan(max steering)).
    pub turning_radius_m: Option<f64>,
}

/// How `[path.along_plots]` joins consecutive plots.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JoinName {
    /// A straight line: a kink where the headings differ.
    #[default]
    Straight,
    /// The shortest arc-line-arc path of the turning radius (Dubins):
    /// the heading is continuous.
    Dubins,
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
    /// Down the true centre line of `[[world.plots]]` number this (from 0),
    /// joined to the previous point by a straight: a path recorded by
    /// driving down a (curved) plot.
    pub along_plot: Option<usize>,
    /// Desired speed of path tracking along this segment, m/s (default `control.speed_m_s`).
    pub speed_m_s: Option<f64>,
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
    /// Control period, seconds (default 0.01 s, 100 Hz: the core pipeline's).
    #[serde(default = "default_period_s")]
    pub period_s: f64,
    /// Lateral gain g_y as the papers' tables give it (positive); the law uses k_y = −g_y, 1/m.
    pub lateral_gain: f64,
    /// Heading gain g_θ (positive); the law uses k_θ = −g_θ, 1/m.
    pub heading_gain: f64,
    /// Minimum ratio g_θ / g_y the core accepts (|k_θ| ≫ |k_y|).
    pub min_gain_ratio: f64,
    /// Prediction horizon T, seconds: the curvature is fed forward at s + v (T + τ).
    pub horizon_s: f64,
    /// The steering's time constant τ the law is told, seconds (default 0):
    /// added to the horizon (PT-FEEDFORWARD-LAG) and, without a bandwidth,
    /// to the schedule's derivation (PT-SCHEDULE).
    #[serde(default)]
    pub steering_lag_s: f64,
    /// The speed schedule of the gains (`[control.schedule]`, optional: the
    /// gains per metre at every speed without it).
    #[serde(default)]
    pub schedule: Option<ScheduleSection>,
    /// Whether the law uses the sideslip observer's estimate (false: β = 0 in the law).
    pub sideslip_compensation: bool,
    /// `"exact"` or `"printed"` reading of eq. 6.
    pub inversion: InversionName,
}

/// `[control.schedule]`: the range of speeds the gains are scheduled for.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduleSection {
    /// Lowest speed the law accepts, m/s.
    pub min_speed_m_s: f64,
    /// Highest speed the law accepts, m/s.
    pub max_speed_m_s: f64,
    /// Largest time-domain heading gain v g_θ, 1/s; default derived from
    /// the steering's rate limit, saturation and `control.steering_lag_s`.
    #[serde(default)]
    pub bandwidth_per_s: Option<f64>,
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
    /// Slope of the ground along x (east), percent (default 0).
    #[serde(default)]
    pub slope_x_percent: f64,
    /// Slope of the ground along y (north), percent (default 0).
    #[serde(default)]
    pub slope_y_percent: f64,
    /// Half the crest-to-trough height of the ground's undulation, metres (default 0: none).
    #[serde(default)]
    pub undulation_amplitude_m: f64,
    /// Distance between the undulation's crests, metres (needed with an amplitude).
    pub undulation_wavelength_m: Option<f64>,
    /// Direction in which the undulation's height varies, degrees from east (default 0).
    #[serde(default)]
    pub undulation_heading_deg: f64,
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
    /// Where the odometry's heading comes from (default: the wheels).
    #[serde(default)]
    pub odometry_heading: HeadingName,
    /// The gyro's angle random walk, degrees per √hour (gyro only, needed).
    pub gyro_random_walk_deg_sqrt_h: Option<f64>,
    /// The gyro's constant residual bias, degrees per hour (gyro only, needed).
    pub gyro_bias_deg_h: Option<f64>,
    /// The gyro's bias instability: stationary σ of the bias wander,
    /// degrees per hour (gyro only, default 0).
    pub gyro_bias_instability_deg_h: Option<f64>,
    /// The correlation time of the bias wander, s (needed with an instability).
    pub gyro_bias_time_constant_s: Option<f64>,
}

/// The source of the odometry's heading.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeadingName {
    /// The wheels, with `odometry_yaw_bias_deg_s` and `odometry_yaw_noise_deg`.
    #[default]
    Wheels,
    /// A yaw-rate gyro, with the `gyro_*` fields.
    Gyro,
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
    /// When set, success also needs the mean |lateral error to the true
    /// centre line| inside the plots at most this, metres.
    pub in_plot_mean_abs_m: Option<f64>,
    /// When set, success also needs the largest |lateral error to the true
    /// centre line| inside the plots at most this, metres.
    pub in_plot_max_abs_m: Option<f64>,
    /// |error to a hedge's true offset line| band that counts as converged
    /// (default 0.05 m).
    #[serde(default = "default_band_m")]
    pub along_hedge_band_m: f64,
    /// When set, success also needs the mean |lateral error to the true
    /// offset line| along the hedges, after convergence, at most this, metres.
    pub along_hedge_mean_abs_m: Option<f64>,
    /// When set, success also needs the largest |lateral error to the true
    /// offset line| along the hedges, after convergence, at most this, metres.
    pub along_hedge_max_abs_m: Option<f64>,
    /// |curvature| of the path from which a tick counts as in a turn, 1/m (default 0.1).
    pub turn_curvature_per_m: Option<f64>,
}

/// `[world]`: crop plots and grass.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSection {
    /// Crop plots (`[[world.plots]]`), in the order the robot meets them.
    #[serde(default)]
    pub plots: Vec<PlotSection>,
    /// Rectangles of grass (`[[world.grass]]`).
    #[serde(default)]
    pub grass: Vec<GrassSection>,
    /// Hedges (`[[world.hedges]]`), in the order the robot meets them.
    #[serde(default)]
    pub hedges: Vec<HedgeSection>,
    /// Height of the hedges and walls above the ground, metres (default 2.0).
    pub obstacle_height_m: Option<f64>,
    /// Rows of posts or trunks (`[[world.posts]]`).
    #[serde(default)]
    pub posts: Vec<PostsSection>,
    /// Fences (`[[world.fences]]`).
    #[serde(default)]
    pub fences: Vec<FenceSection>,
    /// Plants read from a CSV file (columns `x_m,y_m,radius_m,height_m`
    /// and optionally `kind`), relative to the scenario file.
    pub plants_csv: Option<String>,
}

/// `[[world.posts]]`: posts or trunks, cylinders along a polyline or read
/// from a CSV file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PostsSection {
    /// Name, for messages.
    pub name: String,
    /// The line the posts stand on, vertices `[x_m, y_m]` (with `spacing_m`).
    pub line: Option<Vec<[f64; 2]>>,
    /// Distance between posts along the line, metres.
    pub spacing_m: Option<f64>,
    /// Post radius, metres (default for the CSV's rows without `radius_m`).
    pub radius_m: Option<f64>,
    /// Posts missing along the line, by number from 0.
    #[serde(default)]
    pub missing: Vec<usize>,
    /// Probability that each other post is missing (default 0).
    pub missing_fraction: Option<f64>,
    /// The posts as a CSV file (columns `x_m,y_m` and optionally `radius_m`),
    /// relative to the scenario file; instead of `line`.
    pub csv: Option<String>,
}

/// What a LiDAR sees of a fence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FenceKind {
    /// A thin wall (boards, mesh) between the posts: every ray hits it.
    Wall,
    /// Wires between the posts: a ray hits only the posts.
    Wire,
}

/// `[[world.fences]]`: posts along a polyline, with a wall or wires between them.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FenceSection {
    /// Name, for messages.
    pub name: String,
    /// `"wall"` or `"wire"`.
    pub kind: FenceKind,
    /// The fence line, vertices `[x_m, y_m]`, at least two.
    pub line: Vec<[f64; 2]>,
    /// Distance between posts along the line, metres.
    pub post_spacing_m: f64,
    /// Post radius, metres.
    pub post_radius_m: f64,
}

/// `[[world.hedges]]`: a straight hedge with ragged faces and gaps.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HedgeSection {
    /// Name, for the summary.
    pub name: String,
    /// Start of the hedge's centre line and its heading, world frame
    /// (a straight hedge; instead of `centre` and `centre_csv`).
    pub start: Option<StartPose>,
    /// Length along the centre line, metres (with `start`).
    pub length_m: Option<f64>,
    /// The centre line as a polyline `[[x_m, y_m], ...]`, corners rounded by
    /// `corner_radius_m`.
    pub centre: Option<Vec<[f64; 2]>>,
    /// The centre line's vertices as a CSV file (columns `x_m,y_m`),
    /// relative to the scenario file.
    pub centre_csv: Option<String>,
    /// Radius of the arcs rounding the centre line's corners, metres (default 0).
    pub corner_radius_m: Option<f64>,
    /// Distance between the two nominal faces, metres.
    pub thickness_m: f64,
    /// Largest displacement of a face vertex across the hedge, metres.
    pub raggedness_m: f64,
    /// Along-hedge distance between face vertices, metres.
    pub vertex_spacing_m: f64,
    /// Stretches `[from_m, to_m]` along the hedge without hedge.
    #[serde(default)]
    pub gaps_m: Vec<[f64; 2]>,
}

/// The crop of a plot, with its layout (Pierre 2022, section 4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CropName {
    /// Two rows 0.75 m apart, plants about 0.5 m high.
    Maize,
    /// Three rows 0.375 m apart, plants about 0.3 m high.
    Beans,
}

/// `[[world.plots]]`: one crop plot.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSection {
    /// Name, for plots and the summary.
    pub name: String,
    /// `"maize"` or `"beans"`.
    pub crop: CropName,
    /// Start of the plot's centre line and its heading, world frame
    /// (straight rows with the bend; instead of `centre` and `centre_csv`).
    pub start: Option<StartPose>,
    /// Length of the rows, metres (with `start`).
    pub length_m: Option<f64>,
    /// The centre line as a polyline `[[x_m, y_m], ...]`, corners rounded by
    /// `corner_radius_m`.
    pub centre: Option<Vec<[f64; 2]>>,
    /// The centre line's vertices as a CSV file (columns `x_m,y_m`),
    /// relative to the scenario file.
    pub centre_csv: Option<String>,
    /// Radius of the arcs rounding the centre line's corners, metres (default 0).
    pub corner_radius_m: Option<f64>,
    /// Lateral amplitude of the rows' sinusoidal bend, metres (default: the crop's, 0.05).
    pub bend_amplitude_m: Option<f64>,
    /// Wavelength of the bend, metres (default: the crop's, 40).
    pub bend_wavelength_m: Option<f64>,
    /// Probability that a plant is missing (default: the crop's, 0.05).
    pub missing_fraction: Option<f64>,
    /// Number of rows (default: the crop's, 2 for maize, 3 for beans).
    pub rows: Option<u32>,
    /// Lateral distance between neighbouring rows, metres (default: the crop's).
    pub row_spacing_m: Option<f64>,
    /// Mean distance between neighbouring plants along a row, metres (default: the crop's).
    pub plant_spacing_m: Option<f64>,
    /// Standard deviation of the plant spacing, metres (default: the crop's).
    pub plant_spacing_std_m: Option<f64>,
    /// Mean plant height, metres (default: the crop's).
    pub plant_height_m: Option<f64>,
    /// Standard deviation of the plant height, metres (default: the crop's).
    pub plant_height_std_m: Option<f64>,
    /// Mean radius of a plant's opaque stem core, metres (default: the crop's).
    pub stem_radius_m: Option<f64>,
    /// Standard deviation of the stem radius, metres (default: the crop's).
    pub stem_radius_std_m: Option<f64>,
    /// Stretches `[from_m, to_m]` along the plot where no plant grew.
    #[serde(default)]
    pub bare_m: Vec<[f64; 2]>,
    /// The rows continue past the plot's end for this many metres as
    /// volunteer plants (weeds: seen by the LiDAR, not crop, not part of the
    /// plot): the cause of the excursion of Pierre 2022, Exp. 2 (default 0).
    pub volunteers_m: Option<f64>,
}

/// `[[world.grass]]`: grass tufts scattered uniformly over a rectangle.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrassSection {
    /// Two opposite corners `[[x0_m, y0_m], [x1_m, y1_m]]`, world frame.
    pub corners: [[f64; 2]; 2],
    /// Tufts per square metre.
    pub density_per_m2: f64,
    /// Mean tuft radius, metres.
    pub radius_m: f64,
    /// Standard deviation of the radius, metres.
    pub radius_std_m: f64,
    /// Mean tuft height, metres.
    pub height_m: f64,
    /// Standard deviation of the height, metres.
    pub height_std_m: f64,
}

/// `[lidar]`: an inclined 2D LiDAR on the robot.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LidarSection {
    /// Sensor position forward of O, metres.
    pub mount_x_m: f64,
    /// Sensor position left of O, metres.
    pub mount_y_m: f64,
    /// Sensor height above the ground, metres.
    pub height_m: f64,
    /// Pitch, degrees, positive nose down.
    pub pitch_deg: f64,
    /// Field of view, centred on the forward axis, degrees.
    pub field_of_view_deg: f64,
    /// Number of rays.
    pub rays: u32,
    /// Shortest range reported, metres.
    pub range_min_m: f64,
    /// Longest range; beyond it no return, metres.
    pub range_max_m: f64,
    /// Standard deviation of the range noise, metres.
    pub range_noise_m: f64,
    /// Scans per second; the control period must divide the scan period.
    pub rate_hz: f64,
}

/// `[furrow]`: the furrow detector (Pierre 2022, section 2.3, Table 2) and
/// the backstepping law it drives.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FurrowSection {
    /// Forward speed while pursuing the furrow, m/s (Table 2: 0.7).
    pub speed_m_s: f64,
    /// Lateral gain g_y (positive); the law uses k_y = −g_y (Table 2: 0.8).
    pub lateral_gain: f64,
    /// Heading gain g_θ (positive); the law uses k_θ = −g_θ.
    pub heading_gain: f64,
    /// Minimum ratio g_θ / g_y accepted.
    pub min_gain_ratio: f64,
    /// Half width of the angular window around the forward axis, degrees.
    pub window_half_angle_deg: f64,
    /// w_ref, width of the plant model in rays, odd (Table 2: 15).
    pub template_width_rays: u32,
    /// Zero rays framing the plant model on each side.
    pub template_margin_rays: u32,
    /// h_ref, height of the plant model, metres (Table 2: 0.3).
    pub template_height_m: f64,
    /// Heights at or below this count as ground, metres.
    pub height_floor_m: f64,
    /// c_t, the correlation a local maximum must exceed.
    pub peak_threshold: f64,
    /// Rows followed: 1 or 2.
    pub rows: u32,
    /// d_min, least lateral distance between the two rows, metres (rows = 2 only; Table 2: 0.66).
    pub min_row_spacing_m: Option<f64>,
    /// d_max, largest lateral distance between the two rows, metres (rows = 2 only; Table 2: 0.9).
    pub max_row_spacing_m: Option<f64>,
    /// n, the last selections the lines are fitted to (Table 2: 25 averaged scans).
    pub averaged_scans: u32,
    /// Selections farther than this from the robot are dropped, metres.
    pub keep_distance_m: f64,
    /// The least travel the kept selections span, metres (FUR-SPAN; default
    /// 0: the count alone, as Table 2).
    pub min_span_m: Option<f64>,
    /// Fewest points of a row before its line is fitted.
    pub min_points: u32,
    /// Shortest extent along x of a row's points before its line is fitted, metres.
    pub min_extent_m: f64,
    /// Correlation above which the detection may enter furrow pursuing (Table 2: 0.4).
    pub enter_correlation: f64,
    /// Correlation below which it must leave it (Table 2: 0.2).
    pub exit_correlation: f64,
}

/// `[horizontal_lidar]`: a horizontal 2D LiDAR on the robot.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HorizontalLidarSection {
    /// Sensor position forward of O, metres.
    pub mount_x_m: f64,
    /// Sensor position left of O, metres.
    pub mount_y_m: f64,
    /// Sensor heading on the robot, degrees, counter-clockwise (0: forward).
    pub mount_heading_deg: f64,
    /// Sensor height above the ground, metres (default 1.0: above the crops).
    pub mount_height_m: Option<f64>,
    /// Field of view centred on the sensor's x axis, degrees (360: all round).
    pub field_of_view_deg: f64,
    /// Number of rays.
    pub rays: u32,
    /// Shortest range reported, metres.
    pub range_min_m: f64,
    /// Longest range; beyond it no return, metres.
    pub range_max_m: f64,
    /// Standard deviation of the range noise, metres.
    pub range_noise_m: f64,
    /// Scans per second; the control period must divide the scan period.
    pub rate_hz: f64,
}

/// The side of the robot where the edge is followed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SideName {
    /// The edge is on the robot's left.
    Left,
    /// The edge is on the robot's right.
    Right,
}

/// `[edge]`: the edge detector (Pierre 2022, section 2.2, Table 1) and the
/// backstepping law it drives.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdgeSection {
    /// Forward speed while following the edge, m/s (Table 1: 0.4).
    pub speed_m_s: f64,
    /// Lateral gain g_y (positive); the law uses k_y = −g_y.
    pub lateral_gain: f64,
    /// Heading gain g_θ (positive); the law uses k_θ = −g_θ.
    pub heading_gain: f64,
    /// Minimum ratio g_θ / g_y accepted.
    pub min_gain_ratio: f64,
    /// `"left"` or `"right"`: where the edge is.
    pub side: SideName,
    /// D, desired lateral distance to the edge, metres (Table 1: 1.4).
    pub desired_distance_m: f64,
    /// r, radius of the rolling circle, metres (Table 1: 1).
    pub circle_radius_m: f64,
    /// θ_max, largest rotation about one pivot, degrees.
    pub max_rotation_deg: f64,
    /// l_max, chain length at which the chain stops, metres (Table 1: 3).
    pub max_chain_length_m: f64,
    /// Largest translation of the circle searching the first point, metres (Table 1: 3).
    pub search_distance_m: f64,
    /// l_min, length the chain must exceed to be followed, metres.
    pub min_chain_length_m: f64,
    /// w_max, spread of the chain along y it must stay below, metres.
    pub max_width_m: f64,
    /// Fewest chain points of a detection.
    pub min_points: u32,
    /// Longest link between consecutive chain points; a longer one is a gap
    /// in the edge, where the chain stops (EDGE-GAP), metres.
    pub max_link_m: f64,
    /// Largest turn of a link from the chain's direction; a sharper turn is a
    /// corner or the end of the edge, where the chain stops (EDGE-CORNER), degrees.
    pub max_turn_deg: f64,
    /// σ_edge, residual standard deviation below which the detection may enter, metres (Table 1: 0.15).
    pub enter_residual_m: f64,
    /// σ_path, residual standard deviation above which it must leave, metres (Table 1: 0.5).
    pub exit_residual_m: f64,
    /// l_end: a chain stopped by a gap, a corner or the rotation limit must
    /// be longer than this to be followed (EDGE-PIECE-END), metres; absent: 0, never.
    #[serde(default)]
    pub end_chain_length_m: f64,
    /// x_ahead: a chain whose first point lies farther ahead of the robot
    /// is not followed (EDGE-PIECE-END), metres; absent: never.
    #[serde(default)]
    pub max_start_ahead_m: Option<f64>,
    /// Whether the detector looks for the next piece's line ahead when its
    /// chain gives no valid estimate (EDGE-LOOK-AHEAD); absent: false.
    #[serde(default)]
    pub look_ahead: bool,
    /// l_cap: the length along x dropped from the start of the chain found
    /// ahead (EDGE-LOOK-AHEAD), metres; absent: 0.5.
    pub look_ahead_end_cap_m: Option<f64>,
    /// Δx: the step between the search's starts ahead (EDGE-LOOK-AHEAD),
    /// metres; absent: 0.5.
    pub look_ahead_step_m: Option<f64>,
    /// x_far: the farthest start of the search ahead (EDGE-LOOK-AHEAD),
    /// metres; absent: 4.
    pub look_ahead_farthest_m: Option<f64>,
    /// l_fit: the shortest extent along x of the part fitted ahead
    /// (EDGE-LOOK-AHEAD), metres; absent: 1.
    pub look_ahead_min_span_m: Option<f64>,
    /// Whether the chain is read as its least-squares straight line
    /// instead of the paper's parabola (EDGE-STRAIGHT); absent: false.
    #[serde(default)]
    pub straight: bool,
}

fn default_period_s() -> f64 {
    0.01
}

fn default_band_m() -> f64 {
    0.05
}
