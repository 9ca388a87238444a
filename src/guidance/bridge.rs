//! Regular gaps bridged by the held line (`spec/guidance.md`, GD-BRIDGE):
//! across trunks, posts and short gaps, the active behaviour keeps steering
//! on its last valid line carried by odometry instead of handing the
//! command to path tracking and flipping modes.

use crate::geometry::carry::moved_line_error;
use crate::geometry::carry::pose_in_scan_frame;
use crate::geometry::frame::{Odom, Pose2};
use crate::geometry::tracking::TrackingError;
use crate::geometry::units::Meters;
use crate::perception::Detection;

/// A behaviour's latest detection with a valid estimate (Enter or Hold):
/// its tracking error at its scan's pose, where the robot was then, and the
/// odometry distance since.
#[derive(Debug, Clone, Copy)]
pub(super) struct LastValid {
    error: TrackingError,
    odom: Pose2<Odom>,
    travelled: f64,
}

/// What the tick's scan did to a behaviour's last valid line.
#[derive(Debug, Clone, Copy)]
pub(super) enum ScanOutcome<'a, L> {
    /// No scan in this tick.
    None,
    /// The detector read the scan.
    Read(&'a Detection<L>),
    /// The detector refused the scan.
    Refused,
}

/// Updates `last` after a tick whose odometry pose is `odometry`, the robot
/// having moved `travelled` metres since the previous tick: a valid
/// detection replaces it, a refused scan ends it (a failing sensor is not a
/// gap), otherwise the distance grows.
pub(super) fn record<L>(
    last: &mut Option<LastValid>,
    scan: ScanOutcome<'_, L>,
    odometry: &Pose2<Odom>,
    travelled: f64,
) {
    match scan {
        ScanOutcome::Read(d) if d.verdict.estimate_is_valid() => {
            *last = d.error.map(|error| LastValid {
                error,
                odom: *odometry,
                travelled: 0.0,
            });
        }
        ScanOutcome::Refused => *last = None,
        ScanOutcome::Read(_) | ScanOutcome::None => {
            if let Some(l) = last.as_mut() {
                l.travelled += travelled;
            }
        }
    }
}

/// The error to the last valid line, carried straight to `odometry`, and the
/// distance it has been carried, while that distance is at most `bridge`
/// (GD-BRIDGE); `None` beyond it, without a line, or when moving it
/// overflows.
//= spec/guidance.md#gd-bridge-regular-gaps-bridged-by-the-held-line
//# When a bridge length is configured, a tick in which the behaviour of the
//# active specialised mode has no valid estimate MUST report Hold with the
//# tracking error of that behaviour's latest scan with an Enter or Hold verdict,
//# moved to the current pose through odometry as the error to a straight line
//# (GD-ODOMETRY), as long as the odometry distance summed over the ticks since
//# that scan is at most the bridge length and no scan of that behaviour was
//# refused since; otherwise, and for a behaviour that is not active, the
//# estimate MUST be that of GD-SCAN-AGE.
pub(super) fn carried(
    last: Option<&LastValid>,
    odometry: &Pose2<Odom>,
    bridge: Meters,
) -> Option<(TrackingError, Meters)> {
    let last = last?;
    if last.travelled > bridge.get() {
        return None;
    }
    let pose = pose_in_scan_frame(&last.odom, odometry).ok()?;
    let error = moved_line_error(&last.error, &pose).ok()?;
    Some((error, Meters::new(last.travelled).ok()?))
}
