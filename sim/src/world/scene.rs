//! The one world every sensor ray-casts: the ground (flat, sloping or
//! undulating), the plants standing on it and the obstacles (hedges, walls,
//! posts) rising from it to the world's obstacle height.
//!
//! A LiDAR of either kind asks [`Scene::cast`] for the first hit of a 3D ray:
//! an inclined LiDAR sees a hedge beside the plot and a horizontal one sees
//! plants taller than its mount, as they would in a field.

use super::crops::PlantIndex;
use super::grid::Grid;
use super::terrain::Ground;
use super::Plant;

/// What a ray can hit, and the indexes that keep casting cheap.
#[derive(Debug, Clone, Copy)]
pub struct Scene<'a> {
    /// The ground's shape.
    pub ground: &'a Ground,
    /// The plants, indexed by position.
    pub plants: &'a PlantIndex,
    /// The obstacles' outlines, indexed by cell; `None` without obstacles.
    pub obstacles: Option<&'a Grid>,
    /// The obstacles' height above the ground, m.
    pub obstacle_height: f64,
}

impl Scene<'_> {
    /// The range at which the ray from `o` along the unit direction `d`
    /// first meets the ground, a plant of `near` (indices into the plant
    /// index; the caller picks those near the ray) or an obstacle, if within
    /// `max`; `None` when nothing is hit.
    #[must_use]
    pub fn cast(&self, o: [f64; 3], d: [f64; 3], max: f64, near: &[usize]) -> Option<f64> {
        let mut best = self.ground.hit(o, d, max).unwrap_or(f64::INFINITY);
        let all = self.plants.plants();
        for p in near.iter().filter_map(|&i| all.get(i)) {
            if let Some(r) = self.hit_plant(o, d, p) {
                best = best.min(r);
            }
        }
        if let Some(r) = self.hit_obstacle(o, d, max.min(best)) {
            best = best.min(r);
        }
        (best <= max).then_some(best)
    }

    /// Whether a ray at height `z` pointing level can hit a plant (one at
    /// least that tall stands somewhere), so a level scan above every plant
    /// skips the plant index.
    #[must_use]
    pub fn plants_reach(&self, z: f64) -> bool {
        self.plants.max_height() + self.ground.highest() >= z
    }

    /// A plant's cylinder, standing on the ground under its stem.
    fn hit_plant(&self, o: [f64; 3], d: [f64; 3], plant: &Plant) -> Option<f64> {
        let base = if self.ground.is_flat() {
            0.0
        } else {
            self.ground.height(plant.position.x(), plant.position.y())
        };
        hit_cylinder([o[0], o[1], o[2] - base], d, plant)
    }

    /// The first obstacle outline along the ray's horizontal projection,
    /// when the ray is between the ground and the obstacle height there.
    fn hit_obstacle(&self, o: [f64; 3], d: [f64; 3], max: f64) -> Option<f64> {
        let grid = self.obstacles?;
        let level = d[2] == 0.0;
        // A level ray's horizontal direction is its own (unit) direction.
        let horizontal = if level { 1.0 } else { d[0].hypot(d[1]) };
        if horizontal <= 1e-12 {
            return None;
        }
        let dir = [d[0] / horizontal, d[1] / horizontal];
        let t = grid.cast([o[0], o[1]], dir, max * horizontal)?;
        let r = t / horizontal;
        let z = o[2] + r * d[2];
        let (x, y) = (o[0] + r * d[0], o[1] + r * d[1]);
        let ground = if self.ground.is_flat() {
            0.0
        } else {
            self.ground.height(x, y)
        };
        (z >= ground && z <= ground + self.obstacle_height).then_some(r)
    }
}

/// The range at which the ray from `o` along the unit direction `d` first
/// meets the cylinder of `plant` standing on z = 0 (its side wall between
/// the ground and its top, or its top disk), if it does at `r ≥ 0` above the
/// ground.
#[must_use]
pub fn hit_cylinder(o: [f64; 3], d: [f64; 3], plant: &Plant) -> Option<f64> {
    let (cx, cy) = (plant.position.x(), plant.position.y());
    let (ox, oy) = (o[0] - cx, o[1] - cy);
    // |(ox, oy) + r (dx, dy)|² = R²  ⇒  A r² + 2 B r + C = 0.
    let a = d[0] * d[0] + d[1] * d[1];
    let b = ox * d[0] + oy * d[1];
    let c = ox * ox + oy * oy - plant.radius * plant.radius;
    if a <= 0.0 {
        return None;
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let (r_in, r_out) = ((-b - root) / a, (-b + root) / a);
    if r_out < 0.0 {
        return None;
    }
    let r_in = r_in.max(0.0);
    let z = |r: f64| o[2] + r * d[2];
    let z_in = z(r_in);
    if (0.0..=plant.height).contains(&z_in) {
        return Some(r_in);
    }
    if z_in > plant.height && d[2] < 0.0 {
        // Above the top when it enters the wall: it may come down through the top disk.
        let r_top = (o[2] - plant.height) / -d[2];
        if r_top >= r_in && r_top <= r_out {
            return Some(r_top);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::hedge::Obstacles;
    use crate::world::terrain::Undulation;
    use crate::world::PlantKind;
    use fieldguide::Point2;

    fn plant(x: f64, y: f64, height: f64) -> Plant {
        Plant {
            position: Point2::new(x, y).unwrap(),
            radius: 0.05,
            height,
            kind: PlantKind::Crop,
        }
    }

    fn wall_grid() -> Grid {
        let mut o = Obstacles::default();
        o.add_wall([0.0, 1.0], [20.0, 1.0]).unwrap();
        Grid::new(o, 0.5).unwrap()
    }

    #[test]
    fn a_ray_pitched_down_sees_a_wall_below_its_top_and_passes_over_a_low_one() {
        let ground = Ground::default();
        let plants = PlantIndex::new(Vec::new(), 0.5);
        let grid = wall_grid();
        // From 1 m up, 45° to the left and 10° down: the wall y = 1 is 1 m
        // away across, √2 m along the horizontal, at z = 1 − √2 tan 10°.
        let (yaw, pitch) = (45_f64.to_radians(), 10_f64.to_radians());
        let d = [
            yaw.cos() * pitch.cos(),
            yaw.sin() * pitch.cos(),
            -pitch.sin(),
        ];
        let o = [5.0, 0.0, 1.0];
        let scene = |height| Scene {
            ground: &ground,
            plants: &plants,
            obstacles: Some(&grid),
            obstacle_height: height,
        };
        let r = scene(2.0).cast(o, d, 30.0, &[]).unwrap();
        assert!((r - 2_f64.sqrt() / pitch.cos()).abs() < 1e-9, "{r}");
        // A wall lower than the ray where it crosses: the ray goes on to the ground.
        let z_at_wall = 1.0 - 2_f64.sqrt() * pitch.tan();
        let over = scene(z_at_wall - 0.01).cast(o, d, 30.0, &[]).unwrap();
        assert!((over - 1.0 / pitch.sin()).abs() < 1e-9, "{over}");
    }

    #[test]
    fn a_level_ray_passes_over_short_plants_and_meets_tall_ones() {
        let ground = Ground::default();
        let plants = PlantIndex::new(vec![plant(3.0, 0.0, 0.5), plant(6.0, 0.0, 1.5)], 0.5);
        let scene = Scene {
            ground: &ground,
            plants: &plants,
            obstacles: None,
            obstacle_height: 2.0,
        };
        let near = [0, 1];
        let r = scene
            .cast([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], 30.0, &near)
            .unwrap();
        assert!((r - 5.95).abs() < 1e-12, "{r}");
        assert!(scene.plants_reach(1.0) && !scene.plants_reach(1.6));
        // Without the tall one, nothing within range (level over flat ground).
        assert_eq!(
            scene.cast([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], 30.0, &[0]),
            None
        );
    }

    #[test]
    fn sloping_and_undulating_ground_is_met_where_the_ray_reaches_it() {
        let plants = PlantIndex::new(Vec::new(), 0.5);
        let pitch: f64 = 0.38;
        let d = [pitch.cos(), 0.0, -pitch.sin()];
        // Rising 10 % ahead: 1 − r sin p = 0.1 r cos p.
        let rising = Ground {
            slope: [0.1, 0.0],
            undulation: None,
        };
        let scene = |ground| Scene {
            ground,
            plants: &plants,
            obstacles: None,
            obstacle_height: 2.0,
        };
        let r = scene(&rising).cast([0.0, 0.0, 1.0], d, 20.0, &[]).unwrap();
        let exact = 1.0 / (pitch.sin() + 0.1 * pitch.cos());
        assert!((r - exact).abs() < 2e-4, "{r} vs {exact}");
        let level_ground = Ground::default();
        let flat = scene(&level_ground)
            .cast([0.0, 0.0, 1.0], d, 20.0, &[])
            .unwrap();
        assert!(r < flat - 0.1);
        // Waves of 0.2 m every 3 m: the hit lies on the ground, within the
        // bisection's 0.1 mm.
        let waves = Ground {
            slope: [0.0, 0.0],
            undulation: Some(Undulation {
                amplitude: 0.2,
                wavelength: 3.0,
                heading: 0.0,
            }),
        };
        for x0 in [0.0, 0.7, 1.9] {
            let o = [x0, 0.0, waves.height(x0, 0.0) + 1.0];
            let r = scene(&waves).cast(o, d, 20.0, &[]).unwrap();
            let (x, z) = (o[0] + r * d[0], o[2] + r * d[2]);
            assert!((z - waves.height(x, 0.0)).abs() < 1e-4, "{x0}: {z}");
        }
        // A plant stands on the ground under it.
        let tall = PlantIndex::new(vec![plant(4.0, 0.0, 0.3)], 0.5);
        let on_slope = Scene {
            ground: &rising,
            plants: &tall,
            obstacles: None,
            obstacle_height: 2.0,
        };
        let level = [1.0, 0.0, 0.0];
        // At 0.65 m: above the ground (0.4 m at x = 4) and below the top (0.7 m).
        let hit = on_slope.cast([0.0, 0.0, 0.65], level, 20.0, &[0]).unwrap();
        assert!((hit - 3.95).abs() < 1e-9, "{hit}");
    }
}
