//! Validates `[switching]`: the transit delays of the switching machine and
//! its plan consistency check.

use fieldguide::guidance::{
    BehaviourId, Entry, EntryParams, FixKind, FixRule, FixRuleParams, Handover, HandoverParams,
    OdometryAid, OdometryAidParams, MAX_SCAN_AGE_TICKS,
};
use fieldguide::supervisor::switching::{PlanTolerance, MAX_DELAY_TICKS};
use fieldguide::{Meters, Radians, RadiansPerSecond, Seconds};

use crate::error::ScenarioError;
use crate::scenario::check::Checker;
use crate::scenario::schema::{FixKindName, ScenarioFile, SwitchingSection};

/// The id of furrow pursuing, the `[furrow]` section (`"furrow"` in
/// `switching.priority`).
pub const FURROW: BehaviourId = fieldguide::presets::FURROW;

/// The id of edge following, the `[edge]` section (`"edge"` in
/// `switching.priority`).
pub const EDGE: BehaviourId = fieldguide::presets::EDGE;

/// Plan consistency (SW-PLAN-CONSISTENCY) as configured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanSetup {
    /// Largest offset and heading difference of a consistent line.
    pub tolerance: PlanTolerance,
    /// How long a line may disagree before its behaviour is left.
    pub delay: Seconds,
    /// How far odometry carries the last fix for the check through an
    /// outage (GD-PLAN-DEAD-RECKONING); `None`: not carried.
    pub dead_reckoning: Option<Meters>,
}

/// `[switching]`, typed (defaults: Tables 1-2 and the library's GD-CONFIG).
#[derive(Debug, Clone, PartialEq)]
pub struct SwitchingSetup {
    /// The configured behaviours from highest to lowest priority (GD-BEHAVIOURS).
    pub priority: Vec<BehaviourId>,
    /// Time to transit to edge following, s.
    pub edge_enter_s: f64,
    /// Time to transit back from edge following, s.
    pub edge_exit_s: f64,
    /// Time to transit to furrow pursuing, s.
    pub furrow_enter_s: f64,
    /// Time to transit back from furrow pursuing, s.
    pub furrow_exit_s: f64,
    /// Stop after this long without a source, s.
    pub stop_delay_s: f64,
    /// Largest age of a held detection, s.
    pub max_scan_age_s: f64,
    /// Plan consistency, when on.
    pub plan: Option<PlanSetup>,
    /// The bridge length (GD-BRIDGE); `None`: no bridge.
    pub bridge: Option<Meters>,
    /// Whether the wheels are steered at standstill after a Stop (GD-RESUME).
    pub steer_before_resuming: bool,
    /// The hand-over rule, when on (GD-HANDOVER).
    pub handover: Option<HandoverParams>,
    /// The entry rule, when on (GD-ENTRY).
    pub entry: Option<EntryParams>,
    /// The fix rule, when on (GD-FIX-QUALITY).
    pub fix: Option<FixRuleParams>,
    /// The odometry aid, when on (GD-ODOMETRY-AID).
    pub odometry_aid: Option<OdometryAidParams>,
}

/// The switching settings of `[switching]`, each default taken when a field is absent.
pub(super) fn switching(
    file: &ScenarioFile,
    configured: &[BehaviourId],
    period_s: f64,
    check: &Checker<'_>,
) -> Result<SwitchingSetup, ScenarioError> {
    let s = file.switching.clone().unwrap_or_default();
    // A positive delay that its tick counter can hold at `period_s`
    // (SW-DELAYS), named here rather than at the run's first tick.
    let pos = |field: &str, v: Option<f64>, default: f64| -> Result<f64, ScenarioError> {
        let name = format!("switching.{field}");
        let v = check.positive(&name, v.unwrap_or(default))?;
        let longest = if field == "max_scan_age_s" {
            f64::from(MAX_SCAN_AGE_TICKS)
        } else {
            f64::from(MAX_DELAY_TICKS)
        };
        if v / period_s > longest {
            return Err(check.error(
                &name,
                &format!("longer than {longest} control ticks of control.period_s = {period_s} s"),
            ));
        }
        Ok(v)
    };
    let plan = match s.plan_max_offset_m {
        None => {
            if s.plan_max_heading_deg.is_some()
                || s.plan_entry_heading_deg.is_some()
                || s.plan_delay_s.is_some()
                || s.plan_lookahead_m.is_some()
                || s.plan_dead_reckoning_m.is_some()
            {
                return Err(check.error(
                    "switching.plan_max_offset_m",
                    "plan consistency needs its offset when its heading, entry heading, delay, look-ahead or dead reckoning is set",
                ));
            }
            None
        }
        Some(offset) => {
            let offset = check.positive("switching.plan_max_offset_m", offset)?;
            let heading = check.range(
                "switching.plan_max_heading_deg",
                s.plan_max_heading_deg.unwrap_or(20.0),
                0.0,
                180.0,
            )?;
            let delay = pos("plan_delay_s", s.plan_delay_s, 0.3)?;
            let lookahead = check.non_negative(
                "switching.plan_lookahead_m",
                s.plan_lookahead_m.unwrap_or(0.0),
            )?;
            let err =
                |f: &'static str| move |e: fieldguide::Precondition| check.error(f, &e.to_string());
            let dead_reckoning = positive_length(
                check,
                "switching.plan_dead_reckoning_m",
                s.plan_dead_reckoning_m,
                1000.0,
            )?;
            let tolerance = PlanTolerance::new(
                Meters::new(offset).map_err(err("switching.plan_max_offset_m"))?,
                Radians::new(heading.to_radians())
                    .map_err(err("switching.plan_max_heading_deg"))?,
            )
            .map_err(err("switching.plan_max_offset_m"))?
            .with_lookahead(Meters::new(lookahead).map_err(err("switching.plan_lookahead_m"))?)
            .map_err(err("switching.plan_lookahead_m"))?;
            let tolerance = match s.plan_entry_heading_deg {
                None => tolerance,
                Some(h) => {
                    let h = check.range("switching.plan_entry_heading_deg", h, 0.0, heading)?;
                    tolerance
                        .with_entry_heading(
                            Radians::new(h.to_radians())
                                .map_err(err("switching.plan_entry_heading_deg"))?,
                        )
                        .map_err(err("switching.plan_entry_heading_deg"))?
                }
            };
            Some(PlanSetup {
                tolerance,
                delay: Seconds::new(delay).map_err(err("switching.plan_delay_s"))?,
                dead_reckoning,
            })
        }
    };
    if s.entry_lead_m.is_some() && s.entry_closing_m.is_none() {
        return Err(check.error(
            "switching.entry_closing_m",
            "the entry needs its closing length when its lead is set",
        ));
    }
    let handover = match s.handover_hold_m {
        None => {
            if s.handover_slope.is_some()
                || s.handover_averaging_m.is_some()
                || s.handover_line_m.is_some()
            {
                return Err(check.error(
                    "switching.handover_hold_m",
                    "the hand-over needs its hold distance when its slope, averaging or line hold is set",
                ));
            }
            None
        }
        Some(hold) => {
            let field = "switching.handover_hold_m";
            let hold = check.range(field, hold, 0.0, 1000.0)?;
            let slope = s.handover_slope.unwrap_or(0.1);
            let averaging = check.range(
                "switching.handover_averaging_m",
                s.handover_averaging_m.unwrap_or(1.0),
                0.0,
                1000.0,
            )?;
            let line_hold = positive_length(
                check,
                "switching.handover_line_m",
                s.handover_line_m,
                1000.0,
            )?;
            let params = HandoverParams {
                hold: Meters::new(hold).map_err(|e| check.error(field, &e.to_string()))?,
                slope,
                averaging: Meters::new(averaging)
                    .map_err(|e| check.error("switching.handover_averaging_m", &e.to_string()))?,
                line_hold,
            };
            Handover::new(&params).map_err(|e| {
                let field = if averaging <= 0.0 {
                    "switching.handover_averaging_m"
                } else {
                    "switching.handover_slope"
                };
                check.error(field, &e.to_string())
            })?;
            Some(params)
        }
    };
    let fix = fix_rule(&s, check)?;
    Ok(SwitchingSetup {
        fix,
        odometry_aid: odometry_aid(&s, period_s, check)?,
        priority: priority(s.priority.as_deref(), configured, check)?,
        edge_enter_s: pos("edge_enter_s", s.edge_enter_s, 0.4)?,
        edge_exit_s: pos("edge_exit_s", s.edge_exit_s, 0.26)?,
        furrow_enter_s: pos("furrow_enter_s", s.furrow_enter_s, 0.5)?,
        furrow_exit_s: pos("furrow_exit_s", s.furrow_exit_s, 0.3)?,
        stop_delay_s: pos("stop_delay_s", s.stop_delay_s, 0.5)?,
        max_scan_age_s: pos("max_scan_age_s", s.max_scan_age_s, 0.1)?,
        plan,
        bridge: positive_length(check, "switching.bridge_m", s.bridge_m, 100.0)?,
        steer_before_resuming: s.steer_before_resuming.unwrap_or(false),
        handover,
        entry: s
            .entry_closing_m
            .map(|closing| {
                let field = "switching.entry_closing_m";
                let closing = check.range(field, closing, 0.0, 1000.0)?;
                let lead_field = "switching.entry_lead_m";
                let lead = check.range(
                    lead_field,
                    s.entry_lead_m.unwrap_or(file.vehicle.wheelbase_m),
                    0.0,
                    1000.0,
                )?;
                let params = EntryParams {
                    closing: Meters::new(closing)
                        .map_err(|e| check.error(field, &e.to_string()))?,
                    lead: Meters::new(lead).map_err(|e| check.error(lead_field, &e.to_string()))?,
                };
                Entry::new(&params)
                    .map(|_| params)
                    .map_err(|e| check.error(field, &e.to_string()))
            })
            .transpose()?,
    })
}

/// The fix rule of `switching.fix_*` (GD-FIX-QUALITY), on when its largest
/// accuracy is set.
fn fix_rule(
    s: &SwitchingSection,
    check: &Checker<'_>,
) -> Result<Option<FixRuleParams>, ScenarioError> {
    let Some(accuracy) = s.fix_max_accuracy_m else {
        if s.fix_worst_kind.is_some()
            || s.fix_dead_reckoning_m.is_some()
            || s.fix_rejoin_slope.is_some()
            || s.fix_rejoin_curvature.is_some()
            || s.fix_float_averaging_m.is_some()
        {
            return Err(check.error(
                "switching.fix_max_accuracy_m",
                "the fix rule needs its largest accuracy when its kind, dead reckoning, rejoin slope or curvature or float averaging is set",
            ));
        }
        return Ok(None);
    };
    let field = "switching.fix_max_accuracy_m";
    let accuracy = check.range(field, accuracy, 0.0, 1000.0)?;
    let carry_field = "switching.fix_dead_reckoning_m";
    let carry = check.range(
        carry_field,
        s.fix_dead_reckoning_m.unwrap_or(0.0),
        0.0,
        1000.0,
    )?;
    let curvature_field = "switching.fix_rejoin_curvature";
    let curvature = s
        .fix_rejoin_curvature
        .map_or(Ok(0.05), |c| check.range(curvature_field, c, 0.0, 1000.0))?;
    let params = FixRuleParams {
        worst_kind: match s.fix_worst_kind.unwrap_or(FixKindName::RtkFixed) {
            FixKindName::RtkFixed => FixKind::RtkFixed,
            FixKindName::RtkFloat => FixKind::RtkFloat,
            FixKindName::Single => FixKind::Single,
            FixKindName::DeadReckoned => FixKind::DeadReckoned,
        },
        max_accuracy: Meters::new(accuracy).map_err(|e| check.error(field, &e.to_string()))?,
        path_dead_reckoning: Meters::new(carry)
            .map_err(|e| check.error(carry_field, &e.to_string()))?,
        rejoin_slope: s.fix_rejoin_slope.unwrap_or(0.1),
        rejoin_curvature: curvature,
        float_averaging: positive_length(
            check,
            "switching.fix_float_averaging_m",
            s.fix_float_averaging_m,
            1000.0,
        )?,
    };
    FixRule::new(&params).map_err(|e| {
        let field = if accuracy <= 0.0 {
            field
        } else if curvature <= 0.0 {
            curvature_field
        } else {
            "switching.fix_rejoin_slope"
        };
        check.error(field, &e.to_string())
    })?;
    Ok(Some(params))
}

/// The odometry aid of `switching.odometry_aid_*` (GD-ODOMETRY-AID), on
/// when its time constant is set.
fn odometry_aid(
    s: &SwitchingSection,
    period_s: f64,
    check: &Checker<'_>,
) -> Result<Option<OdometryAidParams>, ScenarioError> {
    let field = "switching.odometry_aid_time_constant_s";
    let rate_field = "switching.odometry_aid_max_rate_deg_s";
    let Some(tau) = s.odometry_aid_time_constant_s else {
        if s.odometry_aid_max_rate_deg_s.is_some() {
            return Err(check.error(
                field,
                "the odometry aid needs its time constant when its largest rate is set",
            ));
        }
        return Ok(None);
    };
    let tau = check.range(field, tau, 0.0, 1000.0)?;
    let rate = s.odometry_aid_max_rate_deg_s.unwrap_or(0.5);
    let rate = check.range(rate_field, rate, 0.0, 180.0)?;
    let params = OdometryAidParams {
        time_constant: Seconds::new(tau).map_err(|e| check.error(field, &e.to_string()))?,
        max_rate: RadiansPerSecond::new(rate.to_radians())
            .map_err(|e| check.error(rate_field, &e.to_string()))?,
    };
    let period = Seconds::new(period_s).map_err(|e| check.error(field, &e.to_string()))?;
    OdometryAid::new(&params, period).map_err(|e| {
        let field = if tau <= 0.0 { field } else { rate_field };
        check.error(field, &e.to_string())
    })?;
    Ok(Some(params))
}

/// An optional length of `field`, in (0, `max`] m when given.
fn positive_length(
    check: &Checker<'_>,
    field: &str,
    value: Option<f64>,
    max: f64,
) -> Result<Option<Meters>, ScenarioError> {
    value
        .map(|d| {
            let d = check.range(field, d, 0.0, max)?;
            if d <= 0.0 {
                return Err(check.error(field, &format!("must be > 0, got {d}")));
            }
            Meters::new(d).map_err(|e| check.error(field, &e.to_string()))
        })
        .transpose()
}

/// `switching.priority`: the ids of the named behaviours in order, each a
/// configured one, each once, all of them; absent, `configured` as it is
/// (furrow first).
fn priority(
    names: Option<&[String]>,
    configured: &[BehaviourId],
    check: &Checker<'_>,
) -> Result<Vec<BehaviourId>, ScenarioError> {
    let Some(names) = names else {
        return Ok(configured.to_vec());
    };
    let field = "switching.priority";
    let mut ids = Vec::new();
    for name in names {
        let id = match name.as_str() {
            "furrow" => FURROW,
            "edge" => EDGE,
            other => {
                return Err(check.error(
                    field,
                    &format!("unknown behaviour `{other}`: expected `furrow` or `edge`"),
                ))
            }
        };
        if !configured.contains(&id) {
            return Err(check.error(
                field,
                &format!("`{name}` is not configured: its section is missing"),
            ));
        }
        if ids.contains(&id) {
            return Err(check.error(field, &format!("`{name}` is named twice")));
        }
        ids.push(id);
    }
    if ids.len() != configured.len() {
        return Err(check.error(
            field,
            "must name every configured behaviour (`furrow` and `edge`)",
        ));
    }
    Ok(ids)
}
