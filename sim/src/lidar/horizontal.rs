//! A horizontal 2D LiDAR ray-cast in the one world of every sensor
//! ([`Scene`]: hedges, walls and posts through the obstacle grid, plants
//! taller than the sensor, rising ground) (Pierre 2022, section 2.2, Fig. 3):
//! mount pose and height on the robot, field of view, ray count, range limits
//! and Gaussian range noise.
//!
//! Its scans are what `fieldguide::perception::edge` consumes: the ranges
//! here, the `fieldguide::perception::Scan` over them by
//! [`HorizontalLidar::scan_view`], the mount by [`HorizontalLidar::mount`].

use core::f64::consts::TAU;

use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Pose2, Precondition, Radians, Robot, Sensor, Transform2, World};
use rand::Rng;
use rand_distr::{Distribution, Normal};

use crate::world::hedge::InvalidSpec;
use crate::world::scene::Scene;

/// The parameters of a horizontal LiDAR.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HorizontalLidarSpec {
    /// Mount position on the robot (robot frame: x forward, y left), metres.
    pub mount_xy: [f64; 2],
    /// Mount heading on the robot, radians (0: facing forward).
    pub mount_heading: f64,
    /// Sensor height above the ground under the robot, metres, ≥ 0.
    pub mount_height: f64,
    /// Field of view, radians, in (0, 2π], centred on the sensor's x axis.
    pub field_of_view: f64,
    /// Number of rays, ≥ 2.
    pub rays: usize,
    /// Smallest valid range, metres, ≥ 0.
    pub range_min: f64,
    /// Largest valid range, metres, > `range_min`.
    pub range_max: f64,
    /// Standard deviation of the Gaussian range noise, metres, ≥ 0.
    pub noise_sigma: f64,
}

impl HorizontalLidarSpec {
    /// A 360-ray, 360° LiDAR 1.2 m ahead of the rear axle, 0.05-30 m,
    /// σ = 0.01 m: the simulator's default for edge following.
    pub const DEFAULT: Self = Self {
        mount_xy: [1.2, 0.0],
        mount_heading: 0.0,
        mount_height: 1.0,
        field_of_view: TAU,
        rays: 360,
        range_min: 0.05,
        range_max: 30.0,
        noise_sigma: 0.01,
    };
}

/// A validated horizontal LiDAR.
#[derive(Debug, Clone, Copy)]
pub struct HorizontalLidar {
    spec: HorizontalLidarSpec,
    mount: Transform2<Sensor, Robot>,
    limits: RangeLimits,
    start: f64,
    increment: f64,
    noise: Option<Normal<f64>>,
}

fn invalid(field: &'static str, reason: &'static str) -> InvalidSpec {
    InvalidSpec { field, reason }
}

impl HorizontalLidar {
    /// Checks `spec` and prepares the ray geometry. A full circle of view
    /// spaces the rays by `fov / rays` (no ray twice); a partial one by
    /// `fov / (rays − 1)` (both edges of the view included).
    pub fn new(spec: HorizontalLidarSpec) -> Result<Self, InvalidSpec> {
        let mount = Transform2::new(spec.mount_xy[0], spec.mount_xy[1], spec.mount_heading)
            .map_err(|_| invalid("mount", "must be finite"))?;
        if !(spec.mount_height.is_finite() && spec.mount_height >= 0.0) {
            return Err(invalid("mount_height", "must be finite and >= 0"));
        }
        if !(spec.field_of_view > 0.0 && spec.field_of_view <= TAU) {
            return Err(invalid("field_of_view", "must be in (0, 2 pi]"));
        }
        if spec.rays < 2 {
            return Err(invalid("rays", "must be at least 2"));
        }
        let limits = match (Meters::new(spec.range_min), Meters::new(spec.range_max)) {
            (Ok(lo), Ok(hi)) => RangeLimits::new(lo, hi)
                .map_err(|_| invalid("range_max", "need 0 <= range_min < range_max <= 1e6 m"))?,
            _ => return Err(invalid("range_min", "range limits must be finite")),
        };
        let noise = if spec.noise_sigma == 0.0 {
            None
        } else if spec.noise_sigma > 0.0 && spec.noise_sigma.is_finite() {
            Normal::new(0.0, spec.noise_sigma).ok()
        } else {
            return Err(invalid("noise_sigma", "must be finite and >= 0"));
        };
        let full_circle = spec.field_of_view >= TAU - 1e-12;
        let gaps = if full_circle {
            spec.rays as f64
        } else {
            (spec.rays - 1) as f64
        };
        Ok(Self {
            spec,
            mount,
            limits,
            start: -0.5 * spec.field_of_view,
            increment: spec.field_of_view / gaps,
            noise,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn spec(&self) -> &HorizontalLidarSpec {
        &self.spec
    }

    /// The mount pose as the core takes it (sensor → robot).
    #[must_use]
    pub fn mount(&self) -> Transform2<Sensor, Robot> {
        self.mount
    }

    /// The angle of ray `k` in the sensor frame, radians.
    #[must_use]
    pub fn ray_angle(&self, k: usize) -> f64 {
        self.start + k as f64 * self.increment
    }

    /// Ray-casts one scan from a robot at `pose` in `scene` into `out`
    /// (cleared first, one range per ray, metres): the true distance to the
    /// nearest hit plus Gaussian noise, or +∞ when nothing is hit within
    /// `range_max`. The rays are level, `mount_height` above the ground
    /// under the robot.
    pub fn scan(
        &self,
        pose: &Pose2<World>,
        scene: &Scene<'_>,
        rng: &mut impl Rng,
        out: &mut Vec<f64>,
    ) -> Result<(), Precondition> {
        out.clear();
        let to_world = pose.body_to_frame::<Robot>();
        let sensor_pose = to_world.apply_pose(Pose2::<Robot> {
            position: self.mount.apply(fieldguide::Point2::origin())?,
            heading: self.mount.angle(),
        })?;
        let ground = if scene.ground.is_flat() {
            0.0
        } else {
            scene.ground.height(pose.position.x(), pose.position.y())
        };
        let origin = [
            sensor_pose.position.x(),
            sensor_pose.position.y(),
            ground + self.spec.mount_height,
        ];
        let heading = sensor_pose.heading.get();
        // The plants near the scan, only when one is tall enough to be seen.
        let mut near = Vec::new();
        if scene.plants_reach(origin[2]) {
            let reach = self.spec.range_max + scene.plants.max_radius();
            scene.plants.query(
                (origin[0] - reach, origin[1] - reach),
                (origin[0] + reach, origin[1] + reach),
                &mut near,
            );
        }
        // Each plant can only be hit by the rays within its angular width
        // as seen from the sensor (the rays are level): the (ray, plant)
        // pairs, by ray.
        let mut pairs = self.rays_near(origin, heading, scene, &near);
        pairs.sort_unstable();
        let mut ray_plants = Vec::new();
        let mut next = 0;
        for k in 0..self.spec.rays {
            ray_plants.clear();
            while let Some(&(ray, i)) = pairs.get(next) {
                if ray > k {
                    break;
                }
                if ray == k {
                    ray_plants.push(i);
                }
                next += 1;
            }
            let a = heading + self.ray_angle(k);
            let dir = [a.cos(), a.sin(), 0.0];
            let range = match scene.cast(origin, dir, self.spec.range_max, &ray_plants) {
                Some(t) => t + self.noise.map_or(0.0, |n| n.sample(rng)),
                None => f64::INFINITY,
            };
            out.push(range);
        }
        Ok(())
    }

    /// The (ray, plant) pairs of `near` (indices into the scene's plants)
    /// such that the plant's circle lies within the ray's reach in angle,
    /// seen from the sensor at `origin` facing `heading`: a ray outside a
    /// plant's angular width cannot meet it. One ray of margin each side.
    fn rays_near(
        &self,
        origin: [f64; 3],
        heading: f64,
        scene: &Scene<'_>,
        near: &[usize],
    ) -> Vec<(usize, usize)> {
        let rays = self.spec.rays;
        let mut pairs = Vec::with_capacity(near.len() * 4);
        let all = scene.plants.plants();
        for &i in near {
            let Some(p) = all.get(i) else { continue };
            let (dx, dy) = (p.position.x() - origin[0], p.position.y() - origin[1]);
            let dist = dx.hypot(dy);
            if dist <= p.radius {
                pairs.extend((0..rays).map(|k| (k, i)));
                continue;
            }
            let half = (p.radius / dist).asin();
            let bearing = dy.atan2(dx) - heading;
            // The bearing and its turns either side, for a view that wraps.
            for turn in [-TAU, 0.0, TAU] {
                let lo = ((bearing + turn - half - self.start) / self.increment).ceil() - 1.0;
                let hi = ((bearing + turn + half - self.start) / self.increment).floor() + 1.0;
                let (lo, hi) = (lo.max(0.0), hi.min((rays - 1) as f64));
                if lo <= hi {
                    pairs.extend((lo as usize..=hi as usize).map(|k| (k, i)));
                }
            }
        }
        pairs.dedup();
        pairs
    }

    /// The scan geometry for the core's edge detector, over `ranges`.
    pub fn scan_view<'a>(&self, ranges: &'a [f64]) -> Result<Scan<'a>, Precondition> {
        Ok(Scan {
            start: Radians::new(self.start)?,
            increment: Radians::new(self.increment)?,
            ranges,
            limits: self.limits,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::crops::PlantIndex;
    use crate::world::grid::Grid;
    use crate::world::hedge::{HedgeSpec, Obstacles};
    use crate::world::terrain::Ground;
    use fieldguide::perception::edge::{detect, EdgeConfig, Side};
    use fieldguide::Verdict;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    const FLAT: Ground = Ground {
        slope: [0.0, 0.0],
        undulation: None,
    };

    /// No plants.
    fn none() -> PlantIndex {
        PlantIndex::new(Vec::new(), 0.5)
    }

    /// The flat world of `grid`'s obstacles and `plants`.
    fn scene<'a>(grid: &'a Grid, plants: &'a PlantIndex) -> Scene<'a> {
        Scene {
            ground: &FLAT,
            plants,
            obstacles: Some(grid),
            obstacle_height: 2.0,
        }
    }

    fn wall_world(y: f64) -> Grid {
        let mut o = Obstacles::default();
        o.add_wall([-50.0, y], [50.0, y]).unwrap();
        Grid::new(o, 0.5).unwrap()
    }

    #[test]
    fn a_ray_hits_a_wall_at_its_known_distance() {
        let lidar = HorizontalLidar::new(HorizontalLidarSpec {
            noise_sigma: 0.0,
            ..HorizontalLidarSpec::DEFAULT
        })
        .unwrap();
        // Robot at (3, 0) heading north; wall 5 m north: the ray straight
        // ahead (k = 180, angle 0) sees it 5 − 1.2 m away.
        let pose = Pose2::<World>::new(3.0, 0.0, core::f64::consts::FRAC_PI_2).unwrap();
        let mut ranges = Vec::new();
        lidar
            .scan(
                &pose,
                &scene(&wall_world(5.0), &none()),
                &mut StdRng::seed_from_u64(0),
                &mut ranges,
            )
            .unwrap();
        assert_eq!(ranges.len(), 360);
        assert!(lidar.ray_angle(180).abs() < 1e-12);
        assert!((ranges[180] - 3.8).abs() < 1e-9);
        // Rays pointing away from the wall see nothing.
        assert!(ranges[0].is_infinite());
        // A 45° ray to the left: 3.8 / cos 45°.
        let k45 = 180 + 45;
        assert!((ranges[k45] - 3.8 * std::f64::consts::SQRT_2).abs() < 1e-9);
    }

    #[test]
    fn noise_has_the_requested_spread_and_limits_are_checked() {
        let lidar = HorizontalLidar::new(HorizontalLidarSpec::DEFAULT).unwrap();
        let pose = Pose2::<World>::new(0.0, 0.0, core::f64::consts::FRAC_PI_2).unwrap();
        let grid = wall_world(5.0);
        let mut rng = StdRng::seed_from_u64(3);
        let mut ranges = Vec::new();
        let (mut n, mut sum, mut sum2) = (0.0, 0.0, 0.0);
        for _ in 0..400 {
            lidar
                .scan(&pose, &scene(&grid, &none()), &mut rng, &mut ranges)
                .unwrap();
            let e = ranges[180] - 3.8;
            n += 1.0;
            sum += e;
            sum2 += e * e;
        }
        let mean = sum / n;
        let sd = (sum2 / n - mean * mean).sqrt();
        assert!(mean.abs() < 0.003, "mean {mean}");
        assert!((sd - 0.01).abs() < 0.002, "sd {sd}");
        for (spec, field) in [
            (
                HorizontalLidarSpec {
                    rays: 1,
                    ..HorizontalLidarSpec::DEFAULT
                },
                "rays",
            ),
            (
                HorizontalLidarSpec {
                    field_of_view: 7.0,
                    ..HorizontalLidarSpec::DEFAULT
                },
                "field_of_view",
            ),
            (
                HorizontalLidarSpec {
                    range_max: 0.01,
                    ..HorizontalLidarSpec::DEFAULT
                },
                "range_max",
            ),
            (
                HorizontalLidarSpec {
                    noise_sigma: -1.0,
                    ..HorizontalLidarSpec::DEFAULT
                },
                "noise_sigma",
            ),
            (
                HorizontalLidarSpec {
                    mount_heading: f64::NAN,
                    ..HorizontalLidarSpec::DEFAULT
                },
                "mount",
            ),
        ] {
            assert_eq!(HorizontalLidar::new(spec).unwrap_err().field, field);
        }
        // A partial view includes both edges.
        let half = HorizontalLidar::new(HorizontalLidarSpec {
            field_of_view: core::f64::consts::PI,
            rays: 181,
            ..HorizontalLidarSpec::DEFAULT
        })
        .unwrap();
        assert!((half.ray_angle(0) + core::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((half.ray_angle(180) - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn the_core_detects_a_simulated_hedge_at_its_distance() {
        // A ragged hedge whose near face is 1.4 m to the left of the robot,
        // parallel to it: the detected lateral error is about D − 1.4 = 0.
        let mut rng = StdRng::seed_from_u64(11);
        let mut o = Obstacles::default();
        o.add_hedge(
            &HedgeSpec {
                start: [-10.0, 1.4 + 0.5],
                heading: 0.0,
                length: 30.0,
                thickness: 1.0,
                raggedness: 0.03,
                vertex_spacing: 0.25,
                gaps: vec![],
                centre: None,
            },
            &mut rng,
        )
        .unwrap();
        let grid = Grid::new(o, 0.5).unwrap();
        let lidar = HorizontalLidar::new(HorizontalLidarSpec::DEFAULT).unwrap();
        let pose = Pose2::<World>::new(0.0, 0.0, 0.0).unwrap();
        let mut ranges = Vec::new();
        lidar
            .scan(&pose, &scene(&grid, &none()), &mut rng, &mut ranges)
            .unwrap();
        let config = EdgeConfig::pierre2022().unwrap();
        let det = detect::<512, 256>(
            &lidar.scan_view(&ranges).unwrap(),
            &lidar.mount(),
            Side::Left,
            &config,
        )
        .unwrap();
        assert_eq!(det.verdict, Verdict::Enter);
        let e = det.usable_error().unwrap();
        assert!(e.y.get().abs() < 0.05, "{e:?}");
        assert!(e.angular_deviation.get().abs() < 0.05, "{e:?}");
        // Asked on the right, where there is nothing: Absent.
        let right = detect::<512, 256>(
            &lidar.scan_view(&ranges).unwrap(),
            &lidar.mount(),
            Side::Right,
            &config,
        )
        .unwrap();
        assert_eq!(right.verdict, Verdict::Absent);
    }
}
