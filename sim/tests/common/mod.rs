//! Helpers shared by the closed-loop tests of the specialised behaviours.
#![allow(dead_code, clippy::unwrap_used, clippy::indexing_slicing)]

use fieldguide::geometry::path::PathConfig;
use fieldguide::{Meters, Point2, World};
use fieldguide_sim::guidance::Mode;
use fieldguide_sim::rng::SimRng;
use fieldguide_sim::runner::{self, TickRecord};
use fieldguide_sim::scenario::setup::Reference;
use fieldguide_sim::scenario::{Setup, Source};

/// The built-in scenario `name` with `seed` in place of its own (another
/// field, other noise; `runner::prepare_with_seed`).
pub fn prepare_seed(name: &str, seed: u64) -> (Setup, SimRng) {
    prepare_edited(name, seed, |t| t)
}

/// The built-in scenario `name`, its text edited by `edit` (other
/// parameters), with `seed` in place of its own.
pub fn prepare_edited(
    name: &str,
    seed: u64,
    edit: impl FnOnce(String) -> String,
) -> (Setup, SimRng) {
    let mut source = Source::builtin(name).unwrap();
    source.text = edit(source.text);
    runner::prepare_with_seed(&source, seed).unwrap()
}

/// The worst of `values` over a sweep: the largest, with the seed it came from.
pub fn worst_of(values: impl IntoIterator<Item = (u64, f64)>) -> (u64, f64) {
    values.into_iter().fold(
        (0, f64::NEG_INFINITY),
        |w, (seed, v)| if v > w.1 { (seed, v) } else { w },
    )
}

/// Moves the recorded path `dy` metres to the north (a GNSS offset), so a test
/// can tell whether the rows or hedge steer, or the path does.
pub fn shift_recorded_path(setup: &mut Setup, dy: f64) {
    let shifted: Vec<Point2<World>> = setup
        .path
        .vertices()
        .iter()
        .map(|v| Point2::new(v.position.x(), v.position.y() + dy).unwrap())
        .collect();
    *setup.path = Reference::from_waypoints(
        &shifted,
        PathConfig::new(Meters::new(1.0).unwrap()).unwrap(),
    )
    .unwrap();
}

/// The ticks that have been steered by `mode` for more than `settled_m` metres
/// of travel since that mode last took over.
pub fn settled_in(trace: &[TickRecord], mode: Mode, settled_m: f64) -> Vec<&TickRecord> {
    let mut since_switch = 0.0;
    let mut settled = Vec::new();
    for w in trace.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        since_switch = if a.mode() == mode {
            since_switch + (b.distance_m - a.distance_m)
        } else {
            0.0
        };
        if since_switch > settled_m {
            settled.push(a);
        }
    }
    settled
}
