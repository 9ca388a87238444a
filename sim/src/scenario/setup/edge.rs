//! Validates `[edge]`: the edge detector and the law of edge following, on
//! the horizontal LiDAR of `[horizontal_lidar]`.

use fieldguide::control::backstepping::BacksteppingConfig;
use fieldguide::perception::edge::{
    EdgeConfig, EdgeParameters, LookAhead, Side, MAX_LOOK_AHEAD_STEPS,
};
use fieldguide::MetersPerSecond;

use super::control::{forward_speed, gains, within_schedule};
use super::lidar::HorizontalLidarSetup;
use crate::capacity::{EDGE_CHAIN, EDGE_RAYS};
use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::schema::{EdgeSection, SideName};

/// Edge following: the detector's validated configuration, the side, and the law it drives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeSetup {
    /// The detector (Table 1 with the library's choices), mount taken from `[horizontal_lidar]`.
    pub detector: EdgeConfig,
    /// Where the edge is.
    pub side: Side,
    /// The backstepping law of edge following, without sideslip (Pierre 2022,
    /// section 2.2: "this version of the control law does not include an
    /// estimation of sideslip angles").
    pub backstepping: BacksteppingConfig,
    /// Forward speed while following the edge.
    pub speed: MetersPerSecond,
}

/// The edge detector and law of `[edge]`, the mount taken from
/// `[horizontal_lidar]`, the vehicle and inversion from the path-tracking law `path_law`.
pub(super) fn edge(
    e: &EdgeSection,
    lidar: &HorizontalLidarSetup,
    path_law: &BacksteppingConfig,
    check: &Checker<'_>,
) -> Result<EdgeSetup, ScenarioError> {
    let rays = lidar.lidar.spec().rays;
    if rays > EDGE_RAYS {
        return Err(check.error(
            "horizontal_lidar.rays",
            &format!("edge following takes at most {EDGE_RAYS} rays, got {rays}"),
        ));
    }
    let speed = forward_speed(check, "edge", e.speed_m_s)?;
    within_schedule(check, "edge", path_law, speed)?;
    let gains = gains(
        check,
        "edge",
        e.lateral_gain,
        e.heading_gain,
        e.min_gain_ratio,
    )?;
    let radius = check.open_range("edge.circle_radius_m", e.circle_radius_m, 0.0, 100.0)?;
    let rotation = check.open_range("edge.max_rotation_deg", e.max_rotation_deg, 0.0, 360.0)?;
    let l_max = check.open_range("edge.max_chain_length_m", e.max_chain_length_m, 0.0, 1000.0)?;
    let l_min = check.range("edge.min_chain_length_m", e.min_chain_length_m, 0.0, l_max)?;
    check.below(
        "edge.min_chain_length_m",
        l_min,
        "edge.max_chain_length_m",
        l_max,
    )?;
    let min_points = check.count("edge.min_points", e.min_points, 4, EDGE_CHAIN)?;
    let enter = check.open_range("edge.enter_residual_m", e.enter_residual_m, 0.0, 100.0)?;
    let exit = check.open_range("edge.exit_residual_m", e.exit_residual_m, 0.0, 100.0)?;
    check.above("edge.exit_residual_m", exit, "edge.enter_residual_m", enter)?;
    let params = EdgeParameters {
        radius,
        max_rotation: rotation.to_radians(),
        max_chain_length: l_max,
        search_distance: check.open_range(
            "edge.search_distance_m",
            e.search_distance_m,
            0.0,
            1000.0,
        )?,
        offset: check.range("edge.desired_distance_m", e.desired_distance_m, 0.0, 1000.0)?,
        min_chain_length: l_min,
        max_link: check.open_range("edge.max_link_m", e.max_link_m, 0.0, 1000.0)?,
        max_turn: check
            .range("edge.max_turn_deg", e.max_turn_deg, 0.0, 180.0)
            .and_then(|v| {
                if v > 0.0 {
                    Ok(v)
                } else {
                    Err(check.error("edge.max_turn_deg", "must be within (0, 180], got 0"))
                }
            })?
            .to_radians(),
        max_width: check.open_range("edge.max_width_m", e.max_width_m, 0.0, 1000.0)?,
        min_points,
        sigma_enter: enter,
        sigma_exit: exit,
        min_end_chain_length: check.range(
            "edge.end_chain_length_m",
            e.end_chain_length_m,
            0.0,
            1000.0,
        )?,
        max_start_ahead: match e.max_start_ahead_m {
            Some(v) => check.open_range("edge.max_start_ahead_m", v, 0.0, 1000.0)?,
            None => f64::MAX,
        },
        look_ahead: look_ahead(e, check)?,
        straight: e.straight,
    };
    // Every value was range-checked above; what the core still refuses is
    // reported against the section, with the requirement it names.
    let detector =
        EdgeConfig::new(&params).map_err(|err| check.refused("edge", "configuration", &err))?;
    Ok(EdgeSetup {
        detector,
        side: match e.side {
            SideName::Left => Side::Left,
            SideName::Right => Side::Right,
        },
        backstepping: BacksteppingConfig { gains, ..*path_law },
        speed,
    })
}

/// The look-ahead of `[edge]` (EDGE-LOOK-AHEAD), `None` when off; an
/// absent key takes [`LookAhead::HEDGE`]'s value, and the keys given are
/// checked even when it is off.
fn look_ahead(e: &EdgeSection, check: &Checker<'_>) -> Result<Option<LookAhead>, ScenarioError> {
    let d = LookAhead::HEDGE;
    let step = check.open_range(
        "edge.look_ahead_step_m",
        e.look_ahead_step_m.unwrap_or(d.step),
        0.0,
        1000.0,
    )?;
    let look = LookAhead {
        end_cap: check.range(
            "edge.look_ahead_end_cap_m",
            e.look_ahead_end_cap_m.unwrap_or(d.end_cap),
            0.0,
            1000.0,
        )?,
        step,
        farthest: check.range(
            "edge.look_ahead_farthest_m",
            e.look_ahead_farthest_m.unwrap_or(d.farthest),
            step,
            f64::from(MAX_LOOK_AHEAD_STEPS) * step,
        )?,
        min_span: check.open_range(
            "edge.look_ahead_min_span_m",
            e.look_ahead_min_span_m.unwrap_or(d.min_span),
            0.0,
            1000.0,
        )?,
    };
    Ok(e.look_ahead.then_some(look))
}
