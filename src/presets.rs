//! The configurations of Pierre 2022's experiments (Tables 1 and 2), as
//! ready-made pipeline parameters (`spec/guidance.md`, GD-CONFIG, Presets).
//!
//! Path tracking and the two behaviours of the paper, edge following
//! ([`EDGE`]) and furrow pursuing ([`FURROW`]), with the backstepping law on a
//! 2 m bicycle steering at most 30°.

use core::f64::consts::FRAC_PI_6;

use heapless::Vec;

use crate::control::backstepping::{BacksteppingConfig, Gains, Inversion};
use crate::error::Precondition;
use crate::geometry::frame::{Robot, Sensor, Transform2};
use crate::geometry::units::{Meters, MetersPerSecond, Seconds};
use crate::guidance::{BehaviourId, BehaviourParams, Guidance, GuidanceParams, PathTrackingParams};
use crate::model::bicycle::{Bicycle, SteeringLimit, Wheelbase};
use crate::model::Vehicle;
use crate::perception::edge::{EdgeConfig, EdgeDetectorConfig, Side};
use crate::perception::furrow::{FurrowConfig, FurrowParams};
use crate::perception::{AnyDetector, AnyDetectorConfig};

/// The id of edge following in the presets.
pub const EDGE: BehaviourId = BehaviourId(1);

/// The id of furrow pursuing in the presets.
pub const FURROW: BehaviourId = BehaviourId(2);

/// The parameters of a pipeline of the paper's kind: any of the library's
/// detectors, backstepping, up to two behaviours.
pub type Pierre2022Params = GuidanceParams<AnyDetectorConfig, BacksteppingConfig, 2>;

/// A pipeline of the paper's kind on a path of `PATH` points, with the
/// detectors' default capacities.
pub type Pierre2022<'p, const PATH: usize> = Guidance<'p, PATH, AnyDetector, BacksteppingConfig, 2>;

/// The vehicle of the presets: wheelbase 2 m (section 4), steering limit 30°,
/// no rate limit known.
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn vehicle() -> Result<Bicycle, Precondition> {
    Bicycle::new(Wheelbase::new(2.0)?, SteeringLimit::new(FRAC_PI_6)?, None)
}

/// The backstepping law of a table's positive "proportional gain" `g`:
/// k_y = −g, k_θ = `ratio` k_y (ratio at least 2), on [`vehicle`], exact
/// inversion (GD-CONFIG, Presets).
fn table_law(g: f64, ratio: f64) -> Result<BacksteppingConfig, Precondition> {
    Ok(BacksteppingConfig {
        gains: Gains::new(-g, -ratio * g, 2.0)?,
        vehicle: vehicle()?,
        inversion: Inversion::Exact,
        schedule: None,
    })
}

/// Path tracking, Tables 1-2: 0.8 m/s, gain 0.7 (k_y = −0.7, k_θ = −2.8),
/// horizon 1 s, sideslip compensated; search window 3 m (the library's choice).
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn path_tracking() -> Result<PathTrackingParams<BacksteppingConfig>, Precondition> {
    Ok(PathTrackingParams {
        law: table_law(0.7, 4.0)?,
        speed: MetersPerSecond::new(0.8)?,
        horizon: Seconds::new(1.0)?,
        steering_lag: Seconds::ZERO,
        compensation: true,
        search_window: Meters::new(3.0)?,
    })
}

/// Edge following, Table 1: 0.4 m/s, the detector of
/// [`EdgeConfig::pierre2022`] (D = 1.4 m, r = 1 m, chain 3 m, search 3 m,
/// σ 0.15 / 0.5 m), gain 0.75 (k_y = −0.75, k_θ = 2 k_y = −1.5: the detected
/// heading is noisier than GNSS's, so the heading gain is the smallest ratio
/// accepted, as the simulator measured; the table's derivative gain has no
/// counterpart in eqs. 2-7), 0.4 s to enter, 0.26 s to leave; the edge on
/// `side`, seen by a LiDAR mounted at `mount`.
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn edge_following(
    side: Side,
    mount: Transform2<Sensor, Robot>,
) -> Result<BehaviourParams<AnyDetectorConfig, BacksteppingConfig>, Precondition> {
    Ok(BehaviourParams {
        id: EDGE,
        label: "edge_following",
        detector: AnyDetectorConfig::Edge(EdgeDetectorConfig {
            edge: EdgeConfig::pierre2022()?,
            mount,
            side,
        }),
        law: table_law(0.75, 2.0)?,
        speed: MetersPerSecond::new(0.4)?,
        enter_delay: Seconds::new(0.4)?,
        exit_delay: Seconds::new(0.26)?,
        plan: None,
    })
}

/// Furrow pursuing, Table 2: 0.7 m/s, the detector of
/// [`FurrowParams::table2`], gain 0.8 (k_y = −0.8, k_θ = −3.2), 0.5 s to
/// enter, 0.3 s to leave.
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn furrow_pursuing(
) -> Result<BehaviourParams<AnyDetectorConfig, BacksteppingConfig>, Precondition> {
    Ok(BehaviourParams {
        id: FURROW,
        label: "furrow_pursuing",
        detector: AnyDetectorConfig::Furrow(FurrowConfig::new(&FurrowParams::table2())?),
        law: table_law(0.8, 4.0)?,
        speed: MetersPerSecond::new(0.7)?,
        enter_delay: Seconds::new(0.5)?,
        exit_delay: Seconds::new(0.3)?,
        plan: None,
    })
}

/// Path tracking alone, as in Tables 1-2, with the library's defaults of
/// GD-CONFIG (100 Hz, Stop after 0.5 s, scans held 0.1 s, no plan check).
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn pierre2022_path() -> Result<Pierre2022Params, Precondition> {
    Ok(GuidanceParams {
        period: Seconds::new(0.01)?,
        vehicle: Vehicle::Bicycle(vehicle()?),
        path: path_tracking()?,
        behaviours: Vec::new(),
        priority: Vec::new(),
        stop_delay: Seconds::new(0.5)?,
        plan_delay: None,
        max_scan_age: Seconds::new(0.1)?,
        plan_dead_reckoning: None,
        bridge: None,
        steer_before_resuming: false,
        handover: None,
        entry: None,
        fix: None,
        odometry_aid: None,
    })
}

/// `params` with `behaviour` added.
fn with(
    mut params: Pierre2022Params,
    behaviour: BehaviourParams<AnyDetectorConfig, BacksteppingConfig>,
) -> Result<Pierre2022Params, Precondition> {
    params
        .behaviours
        .push(behaviour)
        .map_err(|_| Precondition::new("GD-BEHAVIOURS", "more than K behaviours"))?;
    Ok(params)
}

/// Experiment 1 of Pierre 2022 (Table 1): path tracking and edge following
/// of an edge on `side`, seen by a LiDAR mounted at `mount`.
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn pierre2022_edge(
    side: Side,
    mount: Transform2<Sensor, Robot>,
) -> Result<Pierre2022Params, Precondition> {
    with(pierre2022_path()?, edge_following(side, mount)?)
}

/// Experiments 2 and 3 of Pierre 2022 (Table 2): path tracking and furrow
/// pursuing of two rows.
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn pierre2022_furrow() -> Result<Pierre2022Params, Precondition> {
    with(pierre2022_path()?, furrow_pursuing()?)
}

/// Both behaviours, furrow pursuing first (crop rows beat a hedge beside the
/// plot), edge following of an edge on `side` seen by a LiDAR at `mount`.
///
/// # Errors
/// None in practice: the values satisfy every precondition.
pub fn pierre2022_both(
    side: Side,
    mount: Transform2<Sensor, Robot>,
) -> Result<Pierre2022Params, Precondition> {
    let mut params = with(pierre2022_furrow()?, edge_following(side, mount)?)?;
    params.priority = Vec::from_slice(&[FURROW, EDGE])
        .map_err(|_| Precondition::new("GD-BEHAVIOURS", "more than K behaviours"))?;
    Ok(params)
}
