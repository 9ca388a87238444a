//! A uniform grid over the obstacles of a world, so that a LiDAR ray tests
//! only the obstacles of the cells it crosses (campaigns of
//! hundreds of runs must take seconds).
//!
//! Cells are squares of a chosen size over the obstacles' bounding box; each
//! lists the segments and circles that may overlap it (a conservative
//! superset). A ray walks the cells in order (Amanatides and Woo's traversal)
//! and stops once the nearest hit found lies before the next cell.

use super::hedge::{ray_circle, ray_segment, InvalidSpec, Obstacles};

/// Largest number of cells; a finer request is coarsened to this.
const MAX_CELLS: f64 = 4.0e6;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Item {
    Segment(usize),
    Circle(usize),
}

/// Obstacles indexed by a uniform grid.
#[derive(Debug, Clone)]
pub struct Grid {
    obstacles: Obstacles,
    origin: [f64; 2],
    cell: f64,
    nx: usize,
    ny: usize,
    /// Cell `k`'s items are `items[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    items: Vec<Item>,
}

impl Grid {
    /// Indexes `obstacles` with square cells of `cell` metres (coarsened if
    /// that would make more than four million cells).
    pub fn new(obstacles: Obstacles, cell: f64) -> Result<Self, InvalidSpec> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(InvalidSpec {
                field: "cell",
                reason: "must be finite and > 0",
            });
        }
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut grow = |p: [f64; 2], pad: f64| {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k] - pad);
                hi[k] = hi[k].max(p[k] + pad);
            }
        };
        for s in &obstacles.segments {
            grow(s.a, 0.0);
            grow(s.b, 0.0);
        }
        for c in &obstacles.circles {
            grow(c.center, c.radius);
        }
        if !(lo[0].is_finite() && lo[1].is_finite() && hi[0].is_finite() && hi[1].is_finite()) {
            // No obstacle: an empty grid.
            return Ok(Self {
                obstacles,
                origin: [0.0, 0.0],
                cell,
                nx: 0,
                ny: 0,
                offsets: vec![0],
                items: Vec::new(),
            });
        }
        let origin = [lo[0] - 0.5 * cell, lo[1] - 0.5 * cell];
        let (w, h) = (
            hi[0] - origin[0] + 0.5 * cell,
            hi[1] - origin[1] + 0.5 * cell,
        );
        let cell = cell.max((w * h / MAX_CELLS).sqrt());
        let nx = (w / cell).ceil().max(1.0) as usize;
        let ny = (h / cell).ceil().max(1.0) as usize;
        let mut grid = Self {
            obstacles,
            origin,
            cell,
            nx,
            ny,
            offsets: Vec::new(),
            items: Vec::new(),
        };
        // Two passes: count per cell, then fill (compressed rows).
        let mut counts = vec![0_usize; nx * ny];
        grid.for_each_overlap(|k, _| counts[k] += 1);
        let mut offsets = Vec::with_capacity(nx * ny + 1);
        let mut total = 0;
        offsets.push(0);
        for c in &counts {
            total += c;
            offsets.push(total);
        }
        let mut items = vec![Item::Segment(0); total];
        let mut fill: Vec<usize> = offsets[..nx * ny].to_vec();
        grid.for_each_overlap(|k, item| {
            items[fill[k]] = item;
            fill[k] += 1;
        });
        grid.offsets = offsets;
        grid.items = items;
        Ok(grid)
    }

    /// The indexed obstacles.
    #[must_use]
    pub fn obstacles(&self) -> &Obstacles {
        &self.obstacles
    }

    /// The cell size actually used, metres.
    #[must_use]
    pub fn cell(&self) -> f64 {
        self.cell
    }

    fn cell_range(&self, lo: f64, hi: f64, axis: usize) -> (usize, usize) {
        let n = if axis == 0 { self.nx } else { self.ny };
        let to_cell =
            |v: f64| (((v - self.origin[axis]) / self.cell).floor().max(0.0) as usize).min(n - 1);
        (to_cell(lo), to_cell(hi))
    }

    /// Calls `f(cell, item)` for every cell each obstacle may overlap: the
    /// cells of its bounding box whose centre is within half a diagonal of a
    /// segment (all of them for a circle).
    fn for_each_overlap(&self, mut f: impl FnMut(usize, Item)) {
        let half_diag = 0.5 * self.cell * std::f64::consts::SQRT_2 * (1.0 + 1e-9);
        for (i, s) in self.obstacles.segments.iter().enumerate() {
            let (x0, x1) = self.cell_range(s.a[0].min(s.b[0]), s.a[0].max(s.b[0]), 0);
            let (y0, y1) = self.cell_range(s.a[1].min(s.b[1]), s.a[1].max(s.b[1]), 1);
            for iy in y0..=y1 {
                for ix in x0..=x1 {
                    let c = [
                        self.origin[0] + (ix as f64 + 0.5) * self.cell,
                        self.origin[1] + (iy as f64 + 0.5) * self.cell,
                    ];
                    if point_segment_distance(c, s.a, s.b) <= half_diag {
                        f(iy * self.nx + ix, Item::Segment(i));
                    }
                }
            }
        }
        for (i, c) in self.obstacles.circles.iter().enumerate() {
            let (x0, x1) = self.cell_range(c.center[0] - c.radius, c.center[0] + c.radius, 0);
            let (y0, y1) = self.cell_range(c.center[1] - c.radius, c.center[1] + c.radius, 1);
            for iy in y0..=y1 {
                for ix in x0..=x1 {
                    f(iy * self.nx + ix, Item::Circle(i));
                }
            }
        }
    }

    fn hit(&self, item: Item, origin: [f64; 2], dir: [f64; 2]) -> Option<f64> {
        match item {
            Item::Segment(i) => self
                .obstacles
                .segments
                .get(i)
                .and_then(|s| ray_segment(origin, dir, s)),
            Item::Circle(i) => self
                .obstacles
                .circles
                .get(i)
                .and_then(|c| ray_circle(origin, dir, c)),
        }
    }

    /// The distance along the ray from `origin` in the unit direction `dir`
    /// to the nearest obstacle within `max_range`, walking the grid: the same
    /// answer as [`Obstacles::cast_brute`].
    #[must_use]
    pub fn cast(&self, origin: [f64; 2], dir: [f64; 2], max_range: f64) -> Option<f64> {
        if self.nx == 0 || self.ny == 0 {
            return None;
        }
        // Clip the ray to the grid's box.
        let size = [self.nx as f64 * self.cell, self.ny as f64 * self.cell];
        let (mut t0, mut t1) = (0.0_f64, max_range);
        for k in 0..2 {
            let (lo, hi) = (self.origin[k], self.origin[k] + size[k]);
            if dir[k].abs() < 1e-300 {
                if origin[k] < lo || origin[k] > hi {
                    return None;
                }
            } else {
                let (ta, tb) = ((lo - origin[k]) / dir[k], (hi - origin[k]) / dir[k]);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
            }
        }
        if t0 > t1 {
            return None;
        }
        let start = [origin[0] + t0 * dir[0], origin[1] + t0 * dir[1]];
        let n = [self.nx, self.ny];
        let mut cell = [0_usize; 2];
        let mut step = [0_isize; 2];
        let mut t_next = [f64::INFINITY; 2];
        let mut t_delta = [f64::INFINITY; 2];
        for k in 0..2 {
            let c =
                (((start[k] - self.origin[k]) / self.cell).floor().max(0.0) as usize).min(n[k] - 1);
            cell[k] = c;
            if dir[k] > 0.0 {
                step[k] = 1;
                let boundary = self.origin[k] + (c as f64 + 1.0) * self.cell;
                t_next[k] = (boundary - origin[k]) / dir[k];
                t_delta[k] = self.cell / dir[k];
            } else if dir[k] < 0.0 {
                step[k] = -1;
                let boundary = self.origin[k] + c as f64 * self.cell;
                t_next[k] = (boundary - origin[k]) / dir[k];
                t_delta[k] = -self.cell / dir[k];
            }
        }
        let mut best: Option<f64> = None;
        loop {
            let k = cell[1] * self.nx + cell[0];
            if let (Some(&a), Some(&b)) = (self.offsets.get(k), self.offsets.get(k + 1)) {
                for &item in self.items.get(a..b).unwrap_or(&[]) {
                    if let Some(t) = self.hit(item, origin, dir) {
                        if t <= max_range && best.is_none_or(|b| t < b) {
                            best = Some(t);
                        }
                    }
                }
            }
            let axis = if t_next[0] < t_next[1] { 0 } else { 1 };
            let t_exit = t_next[axis];
            if best.is_some_and(|b| b <= t_exit) || t_exit > t1 {
                return best;
            }
            match cell[axis].checked_add_signed(step[axis]) {
                Some(c) if c < n[axis] => cell[axis] = c,
                _ => return best,
            }
            t_next[axis] += t_delta[axis];
        }
    }
}

/// Distance from point `p` to the segment `[a, b]`.
fn point_segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let len2 = e[0] * e[0] + e[1] * e[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * e[0], a[1] + t * e[1]];
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::hedge::{HedgeSpec, PostRowSpec};
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    fn world(seed: u64) -> Obstacles {
        let mut rng = StdRng::seed_from_u64(seed);
        let mut o = Obstacles::default();
        o.add_hedge(
            &HedgeSpec {
                start: [-5.0, 1.5],
                heading: 0.1,
                length: 30.0,
                thickness: 0.8,
                raggedness: 0.15,
                vertex_spacing: 0.15,
                gaps: vec![[10.0, 12.0]],
                centre: None,
            },
            &mut rng,
        )
        .unwrap();
        o.add_wall([-5.0, -3.0], [25.0, -2.0]).unwrap();
        o.add_post_row(
            &PostRowSpec {
                start: [0.0, 6.0],
                heading: -0.05,
                count: 20,
                spacing: 1.5,
                radius: 0.08,
                spacing_noise: 0.2,
                missing: 0.2,
            },
            &mut rng,
        )
        .unwrap();
        o
    }

    #[test]
    fn grid_agrees_with_brute_force() {
        for (seed, cell) in [(1, 0.5), (2, 0.2), (3, 2.0), (4, 0.05)] {
            let obstacles = world(seed);
            let grid = Grid::new(obstacles.clone(), cell).unwrap();
            let mut rng = StdRng::seed_from_u64(seed + 100);
            let mut hits = 0;
            for _ in 0..3000 {
                // Origins inside and outside the grid; any direction.
                let o = [rng.random_range(-10.0..30.0), rng.random_range(-6.0..9.0)];
                let a: f64 = rng.random_range(-3.2..3.2);
                let d = [a.cos(), a.sin()];
                let max = rng.random_range(0.5..40.0);
                let fast = grid.cast(o, d, max);
                let slow = obstacles.cast_brute(o, d, max);
                match (fast, slow) {
                    (Some(f), Some(s)) => {
                        hits += 1;
                        assert!((f - s).abs() < 1e-9, "{o:?} {d:?}: {f} vs {s}");
                    }
                    (None, None) => {}
                    other => panic!("{o:?} {d:?} {max}: {other:?}"),
                }
            }
            assert!(hits > 500, "too few hits to mean anything: {hits}");
        }
    }

    #[test]
    fn empty_world_and_bad_cell() {
        let grid = Grid::new(Obstacles::default(), 1.0).unwrap();
        assert_eq!(grid.cast([0.0, 0.0], [1.0, 0.0], 10.0), None);
        assert_eq!(
            Grid::new(Obstacles::default(), 0.0).unwrap_err().field,
            "cell"
        );
        // A huge world with a tiny cell is coarsened, not exhausted.
        let mut o = Obstacles::default();
        o.add_wall([0.0, 0.0], [1.0e4, 1.0e4]).unwrap();
        let grid = Grid::new(o, 0.01).unwrap();
        assert!(grid.cell() > 1.0);
        let t = grid.cast([0.0, 10.0], [1.0, 0.0], 100.0).unwrap();
        assert!((t - 10.0).abs() < 1e-9);
    }
}
