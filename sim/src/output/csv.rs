//! The per-tick CSV trace (`trace.csv`).
//!
//! One line per control tick. Angles in radians, distances in metres, world
//! frame unless the column says `odom_`. `y_true_m` and the other `_true`
//! columns are ground truth; `est_` columns are what the robot's sensors said
//! (`est_x_m`, `est_y_m`, `est_heading_rad` are empty without a GNSS fix).
//! The last columns are empty without a row detector or outside the plots:
//! the latest scan's verdict, whether it arrived at this tick, its age and
//! quality (the weaker correlation of its selection, or the residual standard
//! deviation of an edge chain), the plot O is in with O's abscissa and true
//! lateral error to that plot's centre line, and the hedge present abeam of O
//! with O's abscissa along it and true lateral and angular errors to its
//! offset line.

use std::fmt::Write as _;

use fieldguide::guidance::PlanPose;

use crate::metrics::verdict_label;
use crate::runner::TickRecord;

/// The header line of the trace.
pub const HEADER: &str = "t_s,x_true_m,y_true_m,heading_true_rad,\
est_x_m,est_y_m,est_heading_rad,odom_x_m,odom_y_m,odom_heading_rad,\
distance_m,s_m,lateral_error_true_m,angular_error_true_rad,curvature_1_m,\
lateral_error_est_m,angular_error_est_rad,\
steering_cmd_rad,steering_rad,saturated,\
beta_front_true_rad,beta_rear_true_rad,beta_front_used_rad,beta_rear_used_rad,\
slip_patch,mode,switching_mode,\
verdict,scanned,scan_age_s,scan_quality,plot,plot_s_m,plot_lateral_error_true_m,\
hedge,hedge_s_m,hedge_lateral_error_true_m,hedge_angular_error_true_rad,plan_pose,gnss_valid";

/// The whole trace as CSV text, header first.
#[must_use]
pub fn trace_csv(
    trace: &[TickRecord],
    patch_names: &[String],
    plot_names: &[String],
    hedge_names: &[String],
) -> String {
    let mut out = String::with_capacity(trace.len().saturating_mul(260));
    out.push_str(HEADER);
    out.push('\n');
    for r in trace {
        let est = r.readings.gnss.map_or_else(
            || ",,".to_owned(),
            |g| {
                format!(
                    "{:.4},{:.4},{:.5}",
                    g.position.x(),
                    g.position.y(),
                    g.heading.get()
                )
            },
        );
        let o = &r.readings.odometry;
        let (ey, eth) = r.command.estimated_error.map_or((f64::NAN, f64::NAN), |e| {
            (e.y.get(), e.angular_deviation.get())
        });
        let patch = r
            .patch
            .and_then(|i| patch_names.get(i))
            .map_or(String::new(), |n| n.replace(',', ";"));
        let detector = r.command.detector.map_or_else(
            || ",,,".to_owned(),
            |d| {
                format!(
                    "{},{},{:.2},{}",
                    verdict_label(d.verdict),
                    u8::from(d.scanned),
                    d.age_s,
                    optional(d.quality.unwrap_or(f64::NAN)),
                )
            },
        );
        let plot = r.plot.map_or_else(
            || ",,".to_owned(),
            |p| {
                let name = plot_names
                    .get(p.index)
                    .map_or(String::new(), |n| n.replace(',', ";"));
                format!("{name},{:.4},{:.5}", p.s_m, p.lateral_error_m)
            },
        );
        let hedge = r.hedge.map_or_else(
            || ",,,".to_owned(),
            |h| {
                let name = hedge_names
                    .get(h.index)
                    .map_or(String::new(), |n| n.replace(',', ";"));
                format!(
                    "{name},{:.4},{:.5},{:.5}",
                    h.s_m, h.lateral_error_m, h.angular_error_rad
                )
            },
        );
        // Writing into a String cannot fail.
        let _ = writeln!(
            out,
            "{:.2},{:.4},{:.4},{:.5},{},{:.4},{:.4},{:.5},{:.4},{:.4},{:.5},{:.5},{:.5},{},{},{:.5},{:.5},{},{:.5},{:.5},{:.5},{:.5},{},{},{},{},{},{},{},{}",
            r.t_s,
            r.truth.position.x(),
            r.truth.position.y(),
            r.truth.heading.get(),
            est,
            o.position.x(),
            o.position.y(),
            o.heading.get(),
            r.distance_m,
            r.s_m,
            r.lateral_error_m,
            r.angular_error_rad,
            r.curvature,
            optional(ey),
            optional(eth),
            r.command.steering(),
            r.steering_rad,
            u8::from(r.command.saturated),
            r.sideslip_rad.0,
            r.sideslip_rad.1,
            r.command.sideslip_used.front.get(),
            r.command.sideslip_used.rear.get(),
            patch,
            r.label(),
            r.command.switching_label,
            detector,
            plot,
            hedge,
            plan_pose_label(&r.command.plan_pose),
            u8::from(r.readings.gnss.is_some()),
        );
    }
    out
}

/// The `plan_pose` column: what the plan check judged the lines from.
fn plan_pose_label(pose: &PlanPose) -> &'static str {
    match pose {
        PlanPose::Gnss => "gnss",
        PlanPose::DeadReckoned { .. } => "dead_reckoned",
        PlanPose::Unjudged => "unjudged",
    }
}

/// A number with 5 decimals, or an empty cell for "none".
fn optional(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.5}")
    } else {
        String::new()
    }
}
