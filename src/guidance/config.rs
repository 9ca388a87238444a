//! The pipeline's configuration, validated once (`spec/guidance.md`,
//! GD-CONFIG): path tracking, a list of behaviour slots, their priority and
//! the vehicle, for any detector and law.

use heapless::Vec;

use super::entry::{Entry, EntryParams};
use super::fix::{FixRule, FixRuleParams};
use super::handover::{Handover, HandoverParams};
use super::odometry::{OdometryAid, OdometryAidParams};
use crate::control::ControlLaw;
use crate::error::{finite, Precondition};
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};
use crate::model::Vehicle;
use crate::supervisor::switching::{delay_ticks, BehaviourConfig, PlanTolerance, SwitchingConfig};

/// Relative slack of the scan-age conversion, as in SW-DELAYS: a quotient
/// that is mathematically an integer keeps its value despite rounding.
const AGE_SLACK: f64 = 1e-9;

/// The longest maximal scan age, in ticks: one less than the age counter
/// can hold, so that an age beyond it is always counted (GD-SCAN-AGE).
pub const MAX_SCAN_AGE_TICKS: u16 = u16::MAX - 1;

/// A behaviour's identifier, chosen by the user, unique in a pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BehaviourId(pub u16);

/// Path tracking's part of the configuration (Pierre 2022, section 2.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathTrackingParams<L> {
    /// The control law.
    pub law: L,
    /// Desired speed v, m/s, > 0 (GD-SPEED).
    pub speed: MetersPerSecond,
    /// Prediction horizon T, s, ≥ 0: the curvature is fed forward at
    /// s + v (T + τ) (eq. 7; GD-PREDICTION, PT-FEEDFORWARD-LAG).
    pub horizon: Seconds,
    /// Time constant τ of the steering's first-order lag, s, ≥ 0 (a 5 %
    /// settling time T_s gives τ = T_s / 3), added to the horizon: the
    /// steering reaches a command τ late on average (PT-FEEDFORWARD-LAG).
    /// 0: the horizon alone, as the paper writes it.
    pub steering_lag: Seconds,
    /// Whether the law reads the tick's extra input (for backstepping the
    /// sideslip estimate, eq. 6); without it the law gets its neutral input
    /// (GD-PREDICTION).
    pub compensation: bool,
    /// Half-width of the local search around the last projection, m, > 0
    /// (GD-LOCALISATION).
    pub search_window: Meters,
}

/// One behaviour slot: a detector, its law and its place in the switching.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BehaviourParams<C, L> {
    /// The identifier scans are routed with and the priority names.
    pub id: BehaviourId,
    /// A label for logs, traces and plots (for example `"edge_following"`).
    pub label: &'static str,
    /// The detector's configuration, with the thresholds that grade its
    /// verdicts.
    pub detector: C,
    /// The control law of this behaviour, on its straight line.
    pub law: L,
    /// Desired speed, m/s, > 0 (GD-SPEED).
    pub speed: MetersPerSecond,
    /// Time to transit to this behaviour (SW-DELAYS).
    pub enter_delay: Seconds,
    /// Time to transit back to path tracking (SW-DELAYS).
    pub exit_delay: Seconds,
    /// The largest disagreement of this behaviour's line with the planned
    /// path (SW-PLAN-CONSISTENCY); `None`: never checked.
    pub plan: Option<PlanTolerance>,
}

/// Everything the pipeline needs, as a user writes it; [`GuidanceConfig::new`]
/// validates it once (GD-CONFIG). `C` is the detectors' configuration, `L`
/// the law, `K` the most behaviour slots.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidanceParams<C, L, const K: usize> {
    /// The control period: `step` is called once per period, s, > 0.
    pub period: Seconds,
    /// The vehicle every law must command (GD-VEHICLE).
    pub vehicle: Vehicle,
    /// Path tracking, always present: the default mode.
    pub path: PathTrackingParams<L>,
    /// The behaviour slots, in any order.
    pub behaviours: Vec<BehaviourParams<C, L>, K>,
    /// The behaviours' ids from highest to lowest priority: every configured
    /// id exactly once, or empty for the order of `behaviours`.
    pub priority: Vec<BehaviourId, K>,
    /// Stop after this long without a command source, s, > 0 (SW-STOP).
    pub stop_delay: Seconds,
    /// How long a line may disagree with the plan before its behaviour is
    /// left, s, > 0; needed when a behaviour has a plan tolerance.
    pub plan_delay: Option<Seconds>,
    /// How long a detection is carried by odometry between scans, s, ≥ 0
    /// (GD-SCAN-AGE).
    pub max_scan_age: Seconds,
    /// How far odometry carries the last GNSS fix for the plan check while
    /// the fix is lost, m, > 0 (GD-PLAN-DEAD-RECKONING); `None`: the plan is
    /// checked only in ticks with a fix.
    pub plan_dead_reckoning: Option<Meters>,
    /// How far odometry carries the active behaviour's last valid line
    /// across scans that find nothing, m, > 0 (GD-BRIDGE); `None`: such a
    /// scan is Absent at once.
    pub bridge: Option<Meters>,
    /// Whether, after a Stop, the wheels are steered to the first command
    /// at standstill before the vehicle moves (GD-RESUME).
    pub steer_before_resuming: bool,
    /// How path tracking takes over from a behaviour (GD-HANDOVER); `None`:
    /// straight back to the path, as Pierre 2022 does.
    pub handover: Option<HandoverParams>,
    /// How a behaviour takes over from path tracking (GD-ENTRY); `None`:
    /// the behaviour's law gets its whole error at once, as Pierre 2022 does.
    pub entry: Option<EntryParams>,
    /// Which GNSS fixes are good enough, and how far path tracking carries
    /// the last good one (GD-FIX-QUALITY); `None`: every fix is taken.
    pub fix: Option<FixRuleParams>,
    /// The odometry's heading aided by the good fix's (GD-ODOMETRY-AID);
    /// `None`: the odometry as it comes.
    pub odometry_aid: Option<OdometryAidParams>,
}

/// A validated pipeline configuration (GD-CONFIG): the behaviours in
/// priority order.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidanceConfig<C, L, const K: usize> {
    params: GuidanceParams<C, L, K>,
    switching: SwitchingConfig<K>,
    lookahead: Meters,
    max_scan_age_ticks: u16,
    settle_ticks: u16,
    handover: Option<Handover>,
    entry: Option<Entry>,
    fix: Option<FixRule>,
    odometry_aid: Option<OdometryAid>,
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
    let ticks = if f64::from(up) > quotient * (1.0 + AGE_SLACK) {
        up.saturating_sub(1)
    } else {
        up
    };
    if ticks > MAX_SCAN_AGE_TICKS {
        return Err(Precondition::new(
            "GD-SCAN-AGE",
            "max_scan_age longer than 65 534 control ticks",
        ));
    }
    Ok(ticks)
}

/// ⌈3 τ / period⌉ ticks, 0 without a lag (GD-RESUME); `period` is already
/// known to be positive and τ not negative.
//= spec/guidance.md#gd-resume-steering-before-moving-after-a-stop
//# A configuration whose 3 τ is longer than 65 535 ticks MUST be refused with
//# `GD-RESUME`.
fn settle_ticks(lag: Seconds, period: Seconds) -> Result<u16, Precondition> {
    if lag.get() <= 0.0 {
        return Ok(0);
    }
    let settle = Seconds::new(finite(3.0 * lag.get(), "3 tau overflows")?)?;
    delay_ticks(settle, period, "GD-RESUME")
}

/// The behaviours of `params` in priority order (GD-BEHAVIOURS).
//= spec/guidance.md#gd-behaviours-behaviour-slots-in-a-priority-order
//# A configuration with two behaviours of one id, or a priority that names an
//# unknown behaviour, names one twice or leaves one out, MUST be refused with
//# `GD-BEHAVIOURS`.
fn in_priority_order<C: Copy, L: Copy, const K: usize>(
    params: &GuidanceParams<C, L, K>,
) -> Result<Vec<BehaviourParams<C, L>, K>, Precondition> {
    for (i, b) in params.behaviours.iter().enumerate() {
        if params
            .behaviours
            .iter()
            .skip(i.saturating_add(1))
            .any(|o| o.id == b.id)
        {
            return Err(Precondition::new(
                "GD-BEHAVIOURS",
                "two behaviours have the same id",
            ));
        }
    }
    if params.priority.is_empty() {
        return Ok(params.behaviours.clone());
    }
    let mut ordered = Vec::new();
    for (i, id) in params.priority.iter().enumerate() {
        if params
            .priority
            .iter()
            .skip(i.saturating_add(1))
            .any(|o| o == id)
        {
            return Err(Precondition::new(
                "GD-BEHAVIOURS",
                "priority names a behaviour twice",
            ));
        }
        let Some(b) = params.behaviours.iter().find(|b| b.id == *id) else {
            return Err(Precondition::new(
                "GD-BEHAVIOURS",
                "priority names a behaviour that is not configured",
            ));
        };
        // At most K ids and each found once: the push cannot overflow.
        ordered
            .push(*b)
            .map_err(|_| Precondition::new("GD-BEHAVIOURS", "more than K behaviours"))?;
    }
    if ordered.len() != params.behaviours.len() {
        return Err(Precondition::new(
            "GD-BEHAVIOURS",
            "priority must name every configured behaviour",
        ));
    }
    Ok(ordered)
}

impl<C: Copy, L: ControlLaw + Copy, const K: usize> GuidanceConfig<C, L, K> {
    /// Validates `params` once.
    ///
    /// # Errors
    /// - `SW-MODES` when `K` is 0 (no behaviour slot) or more than 8;
    /// - `GD-BEHAVIOURS` for two behaviours with one id, or a priority that
    ///   names an unknown behaviour, one twice or not every one;
    /// - `GD-VEHICLE` when a law commands another actuation than the vehicle's;
    /// - `SW-DELAYS` when the period or a behaviour's delay is not positive
    ///   or longer than 65 535 ticks; `SW-STOP`, `SW-PLAN-CONSISTENCY` for the
    ///   Stop and plan delays (a plan tolerance without a plan delay is the
    ///   latter);
    /// - `GD-SPEED` when a desired speed is not positive, or the law's
    ///   error when it refuses that speed (`PT-SCHEDULE-RANGE` outside a
    ///   backstepping law's speed schedule);
    /// - `GD-PREDICTION` when the horizon or the steering lag is negative
    ///   (`LIB-FINITE` if v (T + τ) overflows);
    /// - `GD-LOCALISATION` when the search window is not positive;
    /// - `GD-SCAN-AGE` when the maximal scan age is negative or longer than
    ///   65 534 ticks;
    /// - `GD-PLAN-DEAD-RECKONING` when the dead-reckoning distance is not
    ///   positive;
    /// - `GD-BRIDGE` when the bridge length is not positive;
    /// - `GD-RESUME` when 3 τ is longer than 65 535 ticks.
    /// - `GD-HANDOVER` when the hand-over's hold distance is negative or its
    ///   slope outside (0, 1].
    /// - `GD-ENTRY` when the entry's slope is outside (0, 1].
    /// - `GD-FIX-QUALITY` when the fix rule's largest accuracy is not
    ///   positive, its carry distance negative or its rejoin slope outside
    ///   (0, 1].
    /// - `GD-ODOMETRY-AID` when the odometry aid's time constant or largest
    ///   rate is not positive.
    //= spec/guidance.md#gd-config-configuration-validated-once
    //# A guidance configuration MUST be validated once, at construction, and refused
    //# with an error naming the requirement that fails: a speed that is not positive
    //# (`GD-SPEED`), a negative prediction horizon (`GD-PREDICTION`), a search window
    //# that is not positive (`GD-LOCALISATION`), a maximal scan age that is negative
    //# or longer than 65 534 ticks (`GD-SCAN-AGE`), or a delay of the switching
    //# machine (`SW-DELAYS`, `SW-STOP`, `SW-PLAN-CONSISTENCY`).
    pub fn new(params: &GuidanceParams<C, L, K>) -> Result<Self, Precondition> {
        let ordered = in_priority_order(params)?;
        //= spec/guidance.md#gd-vehicle-one-vehicle-one-command-type
        //# A configuration whose path-tracking law or any behaviour's law commands
        //# another actuation than the configured vehicle's MUST be refused with
        //# `GD-VEHICLE`.
        let actuation = params.vehicle.actuation();
        if params.path.law.actuation() != actuation
            || ordered.iter().any(|b| b.law.actuation() != actuation)
        {
            return Err(Precondition::new(
                "GD-VEHICLE",
                "a law commands another actuation than the vehicle's",
            ));
        }
        if params.plan_delay.is_none() && ordered.iter().any(|b| b.plan.is_some()) {
            return Err(Precondition::new(
                "SW-PLAN-CONSISTENCY",
                "a plan tolerance needs a plan delay",
            ));
        }
        // Slots beyond the configured behaviours report Absent every tick;
        // they take the delays of the highest-priority behaviour (or the Stop
        // delay), which they never use.
        let filler = match ordered.first() {
            Some(b) => BehaviourConfig::new(b.enter_delay, b.exit_delay)?,
            None => BehaviourConfig::new(params.stop_delay, params.stop_delay)
                .map_err(|_| Precondition::new("SW-STOP", "stop_delay must be positive"))?,
        };
        let mut behaviours = [filler; K];
        for (slot, b) in behaviours.iter_mut().zip(ordered.iter()) {
            *slot = BehaviourConfig::new(b.enter_delay, b.exit_delay)?;
        }
        let switching = SwitchingConfig::new(
            params.period,
            behaviours,
            params.stop_delay,
            params.plan_delay,
        )?;
        positive_speed(params.path.speed, "path.speed must be > 0")?;
        params.path.law.check_speed(params.path.speed)?;
        for b in &ordered {
            positive_speed(b.speed, "a behaviour's speed must be > 0")?;
            b.law.check_speed(b.speed)?;
        }
        if params.path.horizon.get() < 0.0 || params.path.steering_lag.get() < 0.0 {
            return Err(Precondition::new(
                "GD-PREDICTION",
                "path.horizon and path.steering_lag must not be negative",
            ));
        }
        //= spec/pierre2022.md#pt-speed-range-path-tracking-over-the-speed-range
        //# Started on the path, |y| MUST stay below the larger of 0.05 m and 1.25
        //# times the offset Δκ d² / 24 of a rate-limited ramp through each curvature
        //# step Δκ, and below the larger of 0.05 m and 1.25 times the drift of a
        //# sideslip step.
        //= spec/pierre2022.md#pt-feedforward-lag-feed-forward-timed-for-the-steering-lag
        //# The curvature MUST be fed forward at s + v (T + τ), with T the
        //# prediction horizon and τ ≥ 0 the steering's configured time constant.
        let lookahead = path_lookahead(&params.path, params.path.speed)?;
        if params.path.search_window.get() <= 0.0 {
            return Err(Precondition::new(
                "GD-LOCALISATION",
                "path.search_window must be > 0",
            ));
        }
        let max_scan_age_ticks = scan_age_ticks(params.max_scan_age, params.period)?;
        //= spec/guidance.md#gd-plan-dead-reckoning-the-plan-checked-through-a-gnss-outage
        //# A dead-reckoning distance that is not positive MUST be refused with
        //# `GD-PLAN-DEAD-RECKONING`.
        if params.plan_dead_reckoning.is_some_and(|d| d.get() <= 0.0) {
            return Err(Precondition::new(
                "GD-PLAN-DEAD-RECKONING",
                "plan_dead_reckoning must be > 0",
            ));
        }
        //= spec/guidance.md#gd-bridge-regular-gaps-bridged-by-the-held-line
        //# A bridge length that is not positive MUST be refused with `GD-BRIDGE`.
        if params.bridge.is_some_and(|d| d.get() <= 0.0) {
            return Err(Precondition::new("GD-BRIDGE", "bridge must be > 0"));
        }
        let settle_ticks = settle_ticks(params.path.steering_lag, params.period)?;
        let handover = params.handover.as_ref().map(Handover::new).transpose()?;
        let entry = params.entry.as_ref().map(Entry::new).transpose()?;
        let fix = params.fix.as_ref().map(FixRule::new).transpose()?;
        let odometry_aid = params
            .odometry_aid
            .as_ref()
            .map(|aid| OdometryAid::new(aid, params.period))
            .transpose()?;
        Ok(Self {
            params: GuidanceParams {
                behaviours: ordered,
                priority: Vec::new(),
                ..params.clone()
            },
            switching,
            lookahead,
            max_scan_age_ticks,
            settle_ticks,
            handover,
            entry,
            fix,
            odometry_aid,
        })
    }
}

/// The look-ahead v (T + τ) of path tracking's feed-forward at `speed`
/// (GD-PREDICTION, PT-FEEDFORWARD-LAG); `LIB-FINITE` when it overflows.
fn path_lookahead<L>(
    path: &PathTrackingParams<L>,
    speed: MetersPerSecond,
) -> Result<Meters, Precondition> {
    let lead = finite(
        path.horizon.get() + path.steering_lag.get(),
        "path look-ahead time T + tau overflows",
    )?;
    Meters::new(finite(
        speed.get() * lead,
        "path look-ahead v (T + tau) overflows",
    )?)
}

impl<C, L: ControlLaw, const K: usize> GuidanceConfig<C, L, K> {
    /// Replaces the desired speed of path tracking and its look-ahead
    /// v (T + τ) (GD-SPEED-CHANGE); on an error nothing changes.
    ///
    /// # Errors
    /// `GD-SPEED` when `speed` is not positive, the law's error when it
    /// refuses it (`PT-SCHEDULE-RANGE`), `LIB-FINITE` when the look-ahead
    /// overflows.
    pub(crate) fn set_path_speed(&mut self, speed: MetersPerSecond) -> Result<(), Precondition> {
        positive_speed(speed, "path.speed must be > 0")?;
        self.params.path.law.check_speed(speed)?;
        let lookahead = path_lookahead(&self.params.path, speed)?;
        self.params.path.speed = speed;
        self.lookahead = lookahead;
        Ok(())
    }
}

impl<C, L, const K: usize> GuidanceConfig<C, L, K> {
    /// The parameters, with the behaviours in priority order (index `i` is
    /// the switching machine's `Mode::Behaviour(i)`) and the priority list
    /// emptied.
    #[must_use]
    pub const fn params(&self) -> &GuidanceParams<C, L, K> {
        &self.params
    }

    /// The behaviours in priority order.
    #[must_use]
    pub fn behaviours(&self) -> &[BehaviourParams<C, L>] {
        &self.params.behaviours
    }

    /// The switching machine's configuration: the behaviours in priority
    /// order, their delays in ticks, Stop and plan delays.
    #[must_use]
    pub const fn switching(&self) -> &SwitchingConfig<K> {
        &self.switching
    }

    /// The look-ahead v (T + τ) of path tracking's feed-forward, m
    /// (GD-PREDICTION, PT-FEEDFORWARD-LAG).
    #[must_use]
    pub const fn lookahead(&self) -> Meters {
        self.lookahead
    }

    /// The largest age of a held detection, in ticks (GD-SCAN-AGE).
    #[must_use]
    pub const fn max_scan_age_ticks(&self) -> u16 {
        self.max_scan_age_ticks
    }

    /// The ticks the steering settles for, ⌈3 τ / period⌉, after its
    /// rate-limited turn at standstill (GD-RESUME).
    #[must_use]
    pub const fn settle_ticks(&self) -> u16 {
        self.settle_ticks
    }

    /// The validated hand-over rule, if one is configured (GD-HANDOVER).
    #[must_use]
    pub const fn handover(&self) -> Option<&Handover> {
        self.handover.as_ref()
    }

    /// The validated entry rule, if one is configured (GD-ENTRY).
    #[must_use]
    pub const fn entry(&self) -> Option<&Entry> {
        self.entry.as_ref()
    }

    /// The validated fix rule, if one is configured (GD-FIX-QUALITY).
    #[must_use]
    pub const fn fix(&self) -> Option<&FixRule> {
        self.fix.as_ref()
    }

    /// The validated odometry aid, if one is configured (GD-ODOMETRY-AID).
    #[must_use]
    pub const fn odometry_aid(&self) -> Option<&OdometryAid> {
        self.odometry_aid.as_ref()
    }
}
