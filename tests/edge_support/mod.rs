//! Helpers shared by the edge tests: point generators, an analytic ray caster
//! for walls, and the paper's stepped Algorithm 1 as a reference.
#![allow(
    clippy::arithmetic_side_effects,
    dead_code,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::float_cmp
)]

use fieldguide::perception::edge::{EdgeConfig, Side};
use fieldguide::{Point2, Robot};

/// Robot-frame point.
pub fn pt(x: f64, y: f64) -> Point2<Robot> {
    Point2::new(x, y).unwrap()
}

/// Points of a straight wall on `side` at perpendicular distance `dist` from
/// the robot's origin, heading `angle` relative to the robot, sampled every
/// `spacing` metres of wall from along-wall abscissa `from` to `to`.
pub fn wall(
    side: Side,
    dist: f64,
    angle: f64,
    spacing: f64,
    from: f64,
    to: f64,
) -> Vec<Point2<Robot>> {
    let s = side.sign();
    // Foot of the perpendicular from the origin, on the requested side.
    let (nx, ny) = (-s * angle.sin(), s * angle.cos());
    let (dx, dy) = (angle.cos(), angle.sin());
    let mut out = Vec::new();
    let mut a = from;
    while a <= to {
        out.push(pt(dist * nx + a * dx, dist * ny + a * dy));
        a += spacing;
    }
    out
}

/// Hedge-like points on `side`: along-hedge abscissae `xs` (any order) with
/// lateral jitter `jitter[k]` around a line at distance `dist` and heading `angle`.
pub fn hedge(side: Side, dist: f64, angle: f64, xs: &[f64], jitter: &[f64]) -> Vec<Point2<Robot>> {
    let s = side.sign();
    let (nx, ny) = (-s * angle.sin(), s * angle.cos());
    let (dx, dy) = (angle.cos(), angle.sin());
    xs.iter()
        .zip(jitter)
        .map(|(&a, &j)| pt((dist + j) * nx + a * dx, (dist + j) * ny + a * dy))
        .collect()
}

/// The paper's Algorithm 1 with small steps, as the library reads it
/// (`spec/pierre2022.md`, EDGE-CHAIN-*): only points strictly on `side`; the
/// circle's front semicircle sweeps from the robot's x axis (t = −r) by steps
/// `t_step`; then rotations by `theta_step` about the pivot. A chain point is
/// never taken twice; the chain stops before a link longer than l_link
/// (EDGE-GAP) or turning from the chord by more than φ_turn (EDGE-CORNER).
/// Returns the indices of the chain.
pub fn stepped_chain(
    points: &[Point2<Robot>],
    side: Side,
    config: &EdgeConfig,
    t_step: f64,
    theta_step: f64,
    capacity: usize,
) -> Vec<usize> {
    let s = side.sign();
    let r = config.radius().get();
    let on_side: Vec<usize> = (0..points.len())
        .filter(|&i| s * points[i].y() > 0.0)
        .collect();
    let dist = |c: (f64, f64), i: usize| {
        ((points[i].x() - c.0).powi(2) + (points[i].y() - c.1).powi(2)).sqrt()
    };
    let in_disk = |c: (f64, f64), chain: &[usize]| -> Option<usize> {
        on_side
            .iter()
            .copied()
            .filter(|i| !chain.contains(i) && dist(c, *i) <= r)
            .min_by(|a, b| dist(c, *a).total_cmp(&dist(c, *b)))
    };
    // Translation.
    let mut t = -r;
    let mut c = (0.0, s * t);
    let first = loop {
        if let Some(i) = in_disk(c, &[]) {
            break i;
        }
        t += t_step;
        if t > config.search_distance().get() {
            return Vec::new();
        }
        c = (0.0, s * t);
    };
    let mut chain = vec![first];
    let mut length = 0.0;
    let (theta_max, l_max) = (config.max_rotation().get(), config.max_chain_length().get());
    let (cs, sn) = (theta_step.cos(), (s * theta_step).sin());
    while length < l_max && chain.len() < capacity {
        let p = *chain.last().unwrap();
        let (px, py) = (points[p].x(), points[p].y());
        let mut theta = 0.0;
        let mut found = in_disk(c, &chain);
        while found.is_none() && theta < theta_max {
            theta += theta_step;
            let (ux, uy) = (c.0 - px, c.1 - py);
            c = (px + cs * ux - sn * uy, py + sn * ux + cs * uy);
            found = in_disk(c, &chain);
        }
        match found {
            Some(q) if theta < theta_max => {
                let link = dist((px, py), q);
                // EDGE-GAP: a link longer than l_link is a gap.
                if link > config.max_link().get() {
                    break;
                }
                // EDGE-CORNER: a link turning from the chord p0 → p by more than φ_turn.
                let p0 = chain[0];
                let (cx, cy) = (px - points[p0].x(), py - points[p0].y());
                let (lx, ly) = (points[q].x() - px, points[q].y() - py);
                let chord = cx.hypot(cy);
                if chord > 0.0
                    && (cx * lx + cy * ly) / (chord * link) < config.max_turn().get().cos()
                {
                    break;
                }
                length += link;
                chain.push(q);
            }
            _ => break,
        }
    }
    chain
}

/// Ranges of a scan of the infinite line `{p : n·p = k}` (robot frame, `n` a
/// unit normal) seen from a LiDAR at `mount = (x, y, heading)`, rays from
/// `start` by `increment`; rays that miss, or hit beyond `max`, give +inf.
pub fn cast_line(
    mount: (f64, f64, f64),
    n: (f64, f64),
    k: f64,
    start: f64,
    increment: f64,
    rays: usize,
    max: f64,
) -> Vec<f64> {
    (0..rays)
        .map(|i| {
            let a = mount.2 + start + increment * f64::from(u32::try_from(i).unwrap());
            let (dx, dy) = (a.cos(), a.sin());
            let denom = n.0 * dx + n.1 * dy;
            let num = k - (n.0 * mount.0 + n.1 * mount.1);
            let range = num / denom;
            if denom.abs() > 1e-12 && range > 0.0 && range <= max {
                range
            } else {
                f64::INFINITY
            }
        })
        .collect()
}
