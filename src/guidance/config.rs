//! The pipeline's configuration, validated once (`spec/guidance.md`,
//! GD-CONFIG), and the presets of Pierre 2022, Tables 1 and 2.

use core::f64::consts::FRAC_PI_6;

use crate::control::backstepping::{BacksteppingConfig, Inversion, SteeringLimit};
use crate::control::Gains;
use crate::error::{finite, Precondition};
use crate::geometry::frame::{Robot, Sensor, Transform2};
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};
use crate::model::bicycle::Wheelbase;
use crate::perception::edge::{EdgeConfig, Side};
use crate::perception::furrow::{FurrowConfig, FurrowParams};
use crate::supervisor::switching::{delay_ticks, BehaviourConfig, PlanTolerance, SwitchingConfig};

/// Relative slack of the scan-age conversion, as in SW-DELAYS: a quotient
/// that is mathematically an integer keeps its value despite rounding.
const AGE_SLACK: f64 = 1e-9;

/// The two specialised behaviours of the pipeline (GD-BEHAVIOURS).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Behaviour {
    /// Edge following on the horizontal LiDAR (Pierre 2022, section 2.2).
    EdgeFollowing,
    /// Furrow pursuing on the inclined LiDAR (Pierre 2022, section 2.3).
    FurrowPursuing,
}

/// Which specialised behaviour wins when both can be entered (GD-BEHAVIOURS).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Priority {
    /// Furrow pursuing first: crop rows beat a hedge beside the plot (default).
    #[default]
    FurrowFirst,
    /// Edge following first: for orchards, where the structure is the work.
    EdgeFirst,
}

impl Priority {
    /// The behaviours in priority order: index `i` is the switching
    /// machine's `Mode::Behaviour(i)`.
    #[must_use]
    pub const fn order(self) -> [Behaviour; 2] {
        match self {
            Self::FurrowFirst => [Behaviour::FurrowPursuing, Behaviour::EdgeFollowing],
            Self::EdgeFirst => [Behaviour::EdgeFollowing, Behaviour::FurrowPursuing],
        }
    }
}

/// Path tracking's part of the configuration (Pierre 2022, section 2.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathTrackingParams {
    /// The backstepping law (gains, wheelbase, saturation, reading of eq. 6).
    pub law: BacksteppingConfig,
    /// Desired speed v, m/s, > 0 (Tables 1-2: 0.8 m/s; GD-SPEED).
    pub speed: MetersPerSecond,
    /// Prediction horizon T, s, ≥ 0: the curvature is fed forward at s + v T
    /// (eq. 7; Tables 1-2: 1 s; GD-PREDICTION).
    pub horizon: Seconds,
    /// Whether the law compensates the estimated sideslip (eq. 6; GD-PREDICTION).
    pub sideslip_compensation: bool,
    /// Half-width of the local search around the last projection, m, > 0
    /// (GD-LOCALISATION).
    pub search_window: Meters,
}

/// Edge following's part of the configuration (Pierre 2022, section 2.2, Table 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeFollowingParams {
    /// The detector (Algorithm 1, eqs. 8-11, eq. 21); its σ thresholds are
    /// the switching machine's for this behaviour.
    pub detector: EdgeConfig,
    /// The horizontal LiDAR's mount pose, sensor → robot.
    pub mount: Transform2<Sensor, Robot>,
    /// The side of the robot where the edge is followed.
    pub side: Side,
    /// The backstepping law of this behaviour.
    pub law: BacksteppingConfig,
    /// Desired speed, m/s, > 0 (Table 1: 0.4 m/s; GD-SPEED).
    pub speed: MetersPerSecond,
    /// Time to transit to edge following (Table 1: 0.4 s; SW-DELAYS).
    pub enter_delay: Seconds,
    /// Time to transit back to path tracking (Table 1: 0.26 s; SW-DELAYS).
    pub exit_delay: Seconds,
}

/// Furrow pursuing's part of the configuration (Pierre 2022, section 2.3, Table 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FurrowPursuingParams {
    /// The detector (eqs. 12-20, eq. 22); its correlation thresholds are the
    /// switching machine's for this behaviour.
    pub detector: FurrowConfig,
    /// The backstepping law of this behaviour.
    pub law: BacksteppingConfig,
    /// Desired speed, m/s, > 0 (Table 2: 0.7 m/s; GD-SPEED).
    pub speed: MetersPerSecond,
    /// Time to transit to furrow pursuing (Table 2: 0.5 s; SW-DELAYS).
    pub enter_delay: Seconds,
    /// Time to transit back to path tracking (Table 2: 0.3 s; SW-DELAYS).
    pub exit_delay: Seconds,
}

/// Plan consistency (SW-PLAN-CONSISTENCY): a behaviour whose line disagrees
/// with the planned path for `delay` is left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanCheck {
    /// Largest offset and heading difference of a consistent line.
    pub tolerance: PlanTolerance,
    /// How long a line may disagree before its behaviour is left, s, > 0.
    pub delay: Seconds,
}

/// Everything the pipeline needs, as a user writes it; [`GuidanceConfig::new`]
/// validates it once (GD-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceParams {
    /// The control period: `step` is called once per period, s, > 0.
    pub period: Seconds,
    /// Path tracking, always present: the default mode.
    pub path: PathTrackingParams,
    /// Edge following, when the vehicle has a horizontal LiDAR for it.
    pub edge: Option<EdgeFollowingParams>,
    /// Furrow pursuing, when the vehicle has an inclined LiDAR for it.
    pub furrow: Option<FurrowPursuingParams>,
    /// Which behaviour wins when both can be entered.
    pub priority: Priority,
    /// Stop after this long without a command source, s, > 0 (SW-STOP).
    pub stop_delay: Seconds,
    /// Plan consistency, beyond the paper; `None` turns it off.
    pub plan: Option<PlanCheck>,
    /// How long a detection is carried by odometry between scans, s, ≥ 0
    /// (GD-SCAN-AGE).
    pub max_scan_age: Seconds,
}

/// The backstepping law of a table's positive "proportional gain" `g`:
/// k_y = −g, k_θ = `ratio` k_y (ratio at least 2), wheelbase 2 m, steering
/// limit 30°, exact inversion (GD-CONFIG, Presets).
fn table_law(g: f64, ratio: f64) -> Result<BacksteppingConfig, Precondition> {
    Ok(BacksteppingConfig {
        gains: Gains::new(-g, -ratio * g, 2.0)?,
        wheelbase: Wheelbase::new(2.0)?,
        max_steering: SteeringLimit::new(FRAC_PI_6)?,
        inversion: Inversion::Exact,
    })
}

impl PathTrackingParams {
    /// Tables 1-2: 0.8 m/s, gain 0.7 (k_y = −0.7, k_θ = −2.8), horizon 1 s,
    /// sideslip compensated; search window 3 m (the library's choice).
    ///
    /// # Errors
    /// None in practice: the values satisfy every precondition.
    pub fn pierre2022() -> Result<Self, Precondition> {
        Ok(Self {
            law: table_law(0.7, 4.0)?,
            speed: MetersPerSecond::new(0.8)?,
            horizon: Seconds::new(1.0)?,
            sideslip_compensation: true,
            search_window: Meters::new(3.0)?,
        })
    }
}

impl EdgeFollowingParams {
    /// Table 1: 0.4 m/s, the detector of [`EdgeConfig::pierre2022`]
    /// (D = 1.4 m, r = 1 m, chain 3 m, search 3 m, σ 0.15 / 0.5 m), gain 0.75
    /// (k_y = −0.75, k_θ = 2 k_y = −1.5: the detected heading is noisier than
    /// GNSS's, so the heading gain is the smallest ratio accepted, as the
    /// simulator measured in `sim/scenarios/README.md`, "Edge following"; the
    /// table's derivative gain has no counterpart in eqs. 2-7), 0.4 s to enter, 0.26 s to leave; the edge on `side`, seen
    /// by a LiDAR mounted at `mount`.
    ///
    /// # Errors
    /// None in practice: the values satisfy every precondition.
    pub fn pierre2022(side: Side, mount: Transform2<Sensor, Robot>) -> Result<Self, Precondition> {
        Ok(Self {
            detector: EdgeConfig::pierre2022()?,
            mount,
            side,
            law: table_law(0.75, 2.0)?,
            speed: MetersPerSecond::new(0.4)?,
            enter_delay: Seconds::new(0.4)?,
            exit_delay: Seconds::new(0.26)?,
        })
    }
}

impl FurrowPursuingParams {
    /// Table 2: 0.7 m/s, the detector of [`FurrowParams::table2`], gain 0.8
    /// (k_y = −0.8, k_θ = −3.2), 0.5 s to enter, 0.3 s to leave.
    ///
    /// # Errors
    /// None in practice: the values satisfy every precondition.
    pub fn pierre2022() -> Result<Self, Precondition> {
        Ok(Self {
            detector: FurrowConfig::new(&FurrowParams::table2())?,
            law: table_law(0.8, 4.0)?,
            speed: MetersPerSecond::new(0.7)?,
            enter_delay: Seconds::new(0.5)?,
            exit_delay: Seconds::new(0.3)?,
        })
    }
}

impl GuidanceParams {
    /// Path tracking alone, as in Tables 1-2, with the library's defaults of
    /// GD-CONFIG (100 Hz, Stop after 0.5 s, scans held 0.1 s, furrow first,
    /// no plan check).
    ///
    /// # Errors
    /// None in practice: the values satisfy every precondition.
    pub fn pierre2022_path() -> Result<Self, Precondition> {
        Ok(Self {
            period: Seconds::new(0.01)?,
            path: PathTrackingParams::pierre2022()?,
            edge: None,
            furrow: None,
            priority: Priority::FurrowFirst,
            stop_delay: Seconds::new(0.5)?,
            plan: None,
            max_scan_age: Seconds::new(0.1)?,
        })
    }

    /// Experiment 1 of Pierre 2022 (Table 1): path tracking and edge
    /// following of an edge on `side`, seen by a LiDAR mounted at `mount`.
    ///
    /// # Errors
    /// None in practice: the values satisfy every precondition.
    pub fn pierre2022_edge(
        side: Side,
        mount: Transform2<Sensor, Robot>,
    ) -> Result<Self, Precondition> {
        Ok(Self {
            edge: Some(EdgeFollowingParams::pierre2022(side, mount)?),
            ..Self::pierre2022_path()?
        })
    }

    /// Experiments 2 and 3 of Pierre 2022 (Table 2): path tracking and furrow
    /// pursuing of two rows.
    ///
    /// # Errors
    /// None in practice: the values satisfy every precondition.
    pub fn pierre2022_furrow() -> Result<Self, Precondition> {
        Ok(Self {
            furrow: Some(FurrowPursuingParams::pierre2022()?),
            ..Self::pierre2022_path()?
        })
    }
}

/// A validated pipeline configuration (GD-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceConfig {
    params: GuidanceParams,
    switching: SwitchingConfig<2>,
    lookahead: Meters,
    max_scan_age_ticks: u16,
}

fn positive_speed(speed: MetersPerSecond, violated: &'static str) -> Result<(), Precondition> {
    if speed.get() > 0.0 {
        Ok(())
    } else {
        Err(Precondition::new("GD-SPEED", violated))
    }
}

/// n = ⌊max_age / period⌋ ticks with a relative slack of 10⁻⁹ (GD-SCAN-AGE);
/// `period` is already known to be positive.
fn scan_age_ticks(max_age: Seconds, period: Seconds) -> Result<u16, Precondition> {
    let age = max_age.get();
    if age < 0.0 {
        return Err(Precondition::new(
            "GD-SCAN-AGE",
            "max_scan_age must not be negative",
        ));
    }
    if age <= 0.0 {
        return Ok(0);
    }
    // ⌈q (1 − ε)⌉, refused beyond 65 535 ticks; one less unless q reaches it.
    let up = delay_ticks(max_age, period, "GD-SCAN-AGE")?;
    let quotient = age / period.get();
    if f64::from(up) > quotient * (1.0 + AGE_SLACK) {
        Ok(up.saturating_sub(1))
    } else {
        Ok(up)
    }
}

impl GuidanceConfig {
    /// Validates `params` once.
    ///
    /// # Errors
    /// - `SW-DELAYS` when the period or a behaviour's delay is not positive
    ///   or longer than 65 535 ticks; `SW-STOP`, `SW-PLAN-CONSISTENCY` for the
    ///   Stop and plan delays;
    /// - `GD-SPEED` when a desired speed is not positive;
    /// - `GD-PREDICTION` when the horizon is negative (`LIB-FINITE` if v T
    ///   overflows);
    /// - `GD-LOCALISATION` when the search window is not positive;
    /// - `GD-SCAN-AGE` when the maximal scan age is negative or longer than
    ///   65 535 ticks.
    //= spec/guidance.md#gd-config-configuration-validated-once
    //# A guidance configuration MUST be validated once, at construction, and refused
    //# with an error naming the requirement that fails: a speed that is not positive
    //# (`GD-SPEED`), a negative prediction horizon (`GD-PREDICTION`), a search window
    //# that is not positive (`GD-LOCALISATION`), a maximal scan age that is negative
    //# or longer than 65 535 ticks (`GD-SCAN-AGE`), or a delay of the switching
    //# machine (`SW-DELAYS`, `SW-STOP`, `SW-PLAN-CONSISTENCY`).
    pub fn new(params: &GuidanceParams) -> Result<Self, Precondition> {
        let behaviour = |b: Behaviour| -> Result<BehaviourConfig, Precondition> {
            match b {
                Behaviour::EdgeFollowing => match &params.edge {
                    Some(e) => {
                        BehaviourConfig::new(e.detector.thresholds(), e.enter_delay, e.exit_delay)
                    }
                    None => BehaviourConfig::edge_following(),
                },
                Behaviour::FurrowPursuing => match &params.furrow {
                    Some(f) => {
                        BehaviourConfig::new(*f.detector.thresholds(), f.enter_delay, f.exit_delay)
                    }
                    None => BehaviourConfig::furrow_pursuing(),
                },
            }
        };
        let [first, second] = params.priority.order();
        let switching = SwitchingConfig::new(
            params.period,
            [behaviour(first)?, behaviour(second)?],
            params.stop_delay,
            params.plan.map(|p| p.delay),
        )?;
        positive_speed(params.path.speed, "path.speed must be > 0")?;
        if let Some(e) = &params.edge {
            positive_speed(e.speed, "edge.speed must be > 0")?;
        }
        if let Some(f) = &params.furrow {
            positive_speed(f.speed, "furrow.speed must be > 0")?;
        }
        if params.path.horizon.get() < 0.0 {
            return Err(Precondition::new(
                "GD-PREDICTION",
                "path.horizon must not be negative",
            ));
        }
        let lookahead = Meters::new(finite(
            params.path.speed.get() * params.path.horizon.get(),
            "path look-ahead v T overflows",
        )?)?;
        if params.path.search_window.get() <= 0.0 {
            return Err(Precondition::new(
                "GD-LOCALISATION",
                "path.search_window must be > 0",
            ));
        }
        let max_scan_age_ticks = scan_age_ticks(params.max_scan_age, params.period)?;
        Ok(Self {
            params: *params,
            switching,
            lookahead,
            max_scan_age_ticks,
        })
    }

    /// The parameters this configuration was built from.
    #[must_use]
    pub const fn params(&self) -> &GuidanceParams {
        &self.params
    }

    /// The switching machine's configuration: the behaviours in priority
    /// order, their delays in ticks, Stop and plan delays.
    #[must_use]
    pub const fn switching(&self) -> &SwitchingConfig<2> {
        &self.switching
    }

    /// The look-ahead v T of path tracking's feed-forward, m (GD-PREDICTION).
    #[must_use]
    pub const fn lookahead(&self) -> Meters {
        self.lookahead
    }

    /// The largest age of a held detection, in ticks (GD-SCAN-AGE).
    #[must_use]
    pub const fn max_scan_age_ticks(&self) -> u16 {
        self.max_scan_age_ticks
    }
}
