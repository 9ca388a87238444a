//! An inclined 2D LiDAR hitting the ground and plants (Pierre 2022, section
//! 2.3: "the Lidar is inclined to look at the ground").
//!
//! The scan plane is the sensor's x-y plane pitched down by `pitch` about the
//! robot's y axis, as the core's `perception::furrow::scan::MountPose`
//! describes it: ray `j` at in-plane angle `a_j` has the robot-frame
//! direction `(cos a cos p, sin a, −cos a sin p)`. Rays are cast in the one
//! world of every sensor ([`Scene`]): the ground (flat, sloping or
//! undulating), plants modelled as vertical cylinders (side wall or top
//! disk), hedges and walls. The sensor stands `height` above the ground
//! under the robot. A scan first takes from the plant index the plants
//! inside the bounding box of its footprint (the sensor and every ray's
//! end), so a ray is only tested against the plants near the scan.

use fieldguide::perception::{RangeLimits, Scan};
use fieldguide::{Meters, Pose2, Precondition, Radians, World};
use rand::Rng;
use rand_distr::{Distribution, Normal};

use crate::world::scene::Scene;

/// An inclined 2D LiDAR and its mount on the robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InclinedLidar {
    /// Sensor position forward of the robot origin O, m.
    pub mount_x: f64,
    /// Sensor position left of O, m.
    pub mount_y: f64,
    /// Sensor height above the ground, m.
    pub height: f64,
    /// Pitch, rad, positive nose down.
    pub pitch: f64,
    /// Angular field of view, centred on the forward axis, rad.
    pub field_of_view: f64,
    /// Number of rays (≥ 2).
    pub rays: usize,
    /// Shortest range the sensor reports, m.
    pub range_min: f64,
    /// Longest range the sensor reports, m; beyond it the ray has no return.
    pub range_max: f64,
    /// Standard deviation of the range noise, m.
    pub range_noise: f64,
}

impl InclinedLidar {
    /// The LiDAR of the library's furrow defaults (`FurrowParams::table2`):
    /// 1.5 m ahead of O, 1.0 m high, pitched 0.38 rad, 360 rays over 90°,
    /// ranges 0.1-20 m, 1 cm of range noise.
    #[must_use]
    pub const fn furrow_default() -> Self {
        Self {
            mount_x: 1.5,
            mount_y: 0.0,
            height: 1.0,
            pitch: 0.38,
            field_of_view: core::f64::consts::FRAC_PI_2,
            rays: 360,
            range_min: 0.1,
            range_max: 20.0,
            range_noise: 0.01,
        }
    }

    /// Angle of ray 0, rad.
    #[must_use]
    pub fn angle_min(&self) -> f64 {
        -self.field_of_view / 2.0
    }

    /// Angle between consecutive rays, rad.
    #[must_use]
    pub fn angle_increment(&self) -> f64 {
        self.field_of_view / (self.rays.max(2) as f64 - 1.0)
    }

    /// The sensor origin and the world direction of ray angle `a` from
    /// `pose`, the sensor `height` above the ground at `ground_z`.
    fn ray(&self, pose: &Pose2<World>, ground_z: f64, a: f64) -> ([f64; 3], [f64; 3]) {
        let psi = pose.heading.get();
        let (c, s) = (psi.cos(), psi.sin());
        let (px, py) = (pose.position.x(), pose.position.y());
        let origin = [
            px + c * self.mount_x - s * self.mount_y,
            py + s * self.mount_x + c * self.mount_y,
            ground_z + self.height,
        ];
        let (dx, dy, dz) = (
            a.cos() * self.pitch.cos(),
            a.sin(),
            -a.cos() * self.pitch.sin(),
        );
        (origin, [c * dx - s * dy, s * dx + c * dy, dz])
    }

    /// The height of the ground under the robot at `pose`, m.
    fn ground_z(pose: &Pose2<World>, scene: &Scene<'_>) -> f64 {
        if scene.ground.is_flat() {
            0.0
        } else {
            scene.ground.height(pose.position.x(), pose.position.y())
        }
    }

    /// The noiseless range of ray angle `a` from `pose` in `scene`, among
    /// the plants `near`: the first hit, or infinity when nothing lies
    /// within `range_max`.
    fn cast(&self, pose: &Pose2<World>, a: f64, scene: &Scene<'_>, near: &[usize]) -> f64 {
        let (o, d) = self.ray(pose, Self::ground_z(pose, scene), a);
        scene
            .cast(o, d, self.range_max, near)
            .unwrap_or(f64::INFINITY)
    }

    /// The world bounding box of the scan's footprint from `pose`: the
    /// sensor and the end of every ray (its ground hit, or its end at
    /// `range_max`), widened by `margin`.
    fn footprint(
        &self,
        pose: &Pose2<World>,
        scene: &Scene<'_>,
        margin: f64,
    ) -> ((f64, f64), (f64, f64)) {
        let (mut x0, mut y0, mut x1, mut y1) = (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        );
        let mut grow = |x: f64, y: f64| {
            x0 = x0.min(x);
            y0 = y0.min(y);
            x1 = x1.max(x);
            y1 = y1.max(y);
        };
        for j in 0..self.rays {
            let a = self.angle_min() + j as f64 * self.angle_increment();
            let (o, d) = self.ray(pose, Self::ground_z(pose, scene), a);
            grow(o[0], o[1]);
            // On uneven ground a ray may reach past the plane's hit: its end
            // at `range_max` bounds it.
            let end = if d[2] < 0.0 && scene.ground.is_flat() {
                (o[2] / -d[2]).min(self.range_max)
            } else {
                self.range_max
            };
            grow(o[0] + end * d[0], o[1] + end * d[1]);
        }
        ((x0 - margin, y0 - margin), (x1 + margin, y1 + margin))
    }

    /// One scan from `pose` in `scene`, with Gaussian range noise drawn
    /// from `rng`. Rays with no return read `f64::INFINITY`; noisy ranges are
    /// clamped to `[range_min, range_max]`.
    pub fn scan(&self, pose: &Pose2<World>, scene: &Scene<'_>, rng: &mut impl Rng) -> InclinedScan {
        let (lo, hi) = self.footprint(pose, scene, scene.plants.max_radius());
        let mut near = Vec::new();
        scene.plants.query(lo, hi, &mut near);
        let noise = Normal::new(0.0, self.range_noise).ok();
        let ranges = (0..self.rays)
            .map(|j| {
                let a = self.angle_min() + j as f64 * self.angle_increment();
                let r = self.cast(pose, a, scene, &near);
                match (&noise, r.is_finite()) {
                    (Some(n), true) => (r + n.sample(rng)).clamp(self.range_min, self.range_max),
                    _ => r,
                }
            })
            .collect();
        InclinedScan {
            ranges,
            angle_min: self.angle_min(),
            angle_increment: self.angle_increment(),
            range_min: self.range_min,
            range_max: self.range_max,
        }
    }

    /// The same scan without the index's prefilter: every plant tested, no
    /// noise (the reference the prefiltered scan is tested against).
    #[must_use]
    pub fn scan_exhaustive(&self, pose: &Pose2<World>, scene: &Scene<'_>) -> Vec<f64> {
        let all: Vec<usize> = (0..scene.plants.plants().len()).collect();
        (0..self.rays)
            .map(|j| {
                self.cast(
                    pose,
                    self.angle_min() + j as f64 * self.angle_increment(),
                    scene,
                    &all,
                )
            })
            .collect()
    }
}

/// A simulated inclined scan: ranges in metres (infinity for no return),
/// ray `j` at `angle_min + j · angle_increment`, valid in `[range_min, range_max)`.
#[derive(Debug, Clone, PartialEq)]
pub struct InclinedScan {
    /// Ranges, m.
    pub ranges: Vec<f64>,
    /// Angle of ray 0, rad.
    pub angle_min: f64,
    /// Angle between rays, rad.
    pub angle_increment: f64,
    /// The LiDAR's shortest reported range, m.
    pub range_min: f64,
    /// The LiDAR's longest range, m; ranges at or beyond it are no return.
    pub range_max: f64,
}

impl InclinedScan {
    /// The scan as the core's furrow detector reads it. Errors on non-finite
    /// angles (`LIB-FINITE`) or range limits the core refuses (`LIB-SCAN`).
    pub fn as_scan(&self) -> Result<Scan<'_>, Precondition> {
        Ok(Scan {
            start: Radians::new(self.angle_min)?,
            increment: Radians::new(self.angle_increment)?,
            ranges: &self.ranges,
            limits: RangeLimits::new(Meters::new(self.range_min)?, Meters::new(self.range_max)?)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::crops::PlantIndex;
    use crate::world::terrain::Ground;
    use crate::world::{Plant, PlantKind};

    const FLAT: Ground = Ground {
        slope: [0.0, 0.0],
        undulation: None,
    };

    /// The flat world of `index`, without obstacles.
    fn flat(index: &PlantIndex) -> Scene<'_> {
        Scene {
            ground: &FLAT,
            plants: index,
            obstacles: None,
            obstacle_height: 2.0,
        }
    }
    use fieldguide::perception::furrow::scan::{scan_to_points, MountPose, ScanWindow};
    use fieldguide::Point2;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    fn quiet() -> InclinedLidar {
        InclinedLidar {
            range_noise: 0.0,
            ..InclinedLidar::furrow_default()
        }
    }

    fn plant(x: f64, y: f64, radius: f64, height: f64) -> Plant {
        Plant {
            position: Point2::new(x, y).unwrap(),
            radius,
            height,
            kind: PlantKind::Crop,
        }
    }

    #[test]
    fn a_ray_at_known_pitch_hits_the_ground_at_the_right_distance() {
        let lidar = InclinedLidar {
            rays: 3,
            field_of_view: 1.0,
            ..quiet()
        };
        let pose = Pose2::<World>::new(2.0, -1.0, 0.7).unwrap();
        let index = PlantIndex::new(Vec::new(), 0.5);
        let scan = lidar.scan(&pose, &flat(&index), &mut StdRng::seed_from_u64(1));
        // Centre ray: h / sin p. Side rays at ±0.5 rad: h / (cos 0.5 sin p).
        let p: f64 = 0.38;
        assert!((scan.ranges[1] - 1.0 / p.sin()).abs() < 1e-12);
        assert!((scan.ranges[0] - 1.0 / (0.5_f64.cos() * p.sin())).abs() < 1e-12);
        assert!((scan.ranges[2] - scan.ranges[0]).abs() < 1e-12);
        // A pitch up never meets the ground: no return.
        let up = InclinedLidar {
            pitch: -0.1,
            ..lidar
        };
        assert!(up
            .scan_exhaustive(&pose, &flat(&PlantIndex::new(Vec::new(), 0.5)))
            .iter()
            .all(|r| r.is_infinite()));
    }

    #[test]
    fn a_plant_in_front_returns_a_bump_of_its_height() {
        let lidar = quiet();
        // The centre ray reaches z = 0.3 at forward distance (1.0 − 0.3) / tan p from the sensor.
        let p: f64 = 0.38;
        let x_top = 1.5 + 0.7 / p.tan();
        let plants = vec![plant(x_top + 0.05, 0.0, 0.1, 0.3)];
        let index = PlantIndex::new(plants.clone(), 0.5);
        let pose = Pose2::<World>::new(0.0, 0.0, 0.0).unwrap();
        let scan = lidar.scan(&pose, &flat(&index), &mut StdRng::seed_from_u64(1));
        assert_eq!(scan.ranges, lidar.scan_exhaustive(&pose, &flat(&index)));
        let mount = MountPose::new(
            Meters::new(1.5).unwrap(),
            Meters::ZERO,
            Meters::new(1.0).unwrap(),
            Radians::new(p).unwrap(),
        )
        .unwrap();
        let window = ScanWindow::new(Radians::new(0.7).unwrap()).unwrap();
        let mut points = vec![None; 400];
        let w = scan_to_points(&scan.as_scan().unwrap(), &mount, &window, &mut points).unwrap();
        let heights: Vec<f64> = points[..w.count]
            .iter()
            .flatten()
            .map(|q| q.height.get())
            .collect();
        let top = heights.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        // The rays through the top disk read the plant's height; the rest is ground.
        assert!((top - 0.3).abs() < 1e-9, "{top}");
        let bump = heights.iter().filter(|&&z| z > 0.05).count();
        // The disk is 0.2 m wide, at about 2.6 m: some 17 rays of 0.25°.
        assert!((10..=25).contains(&bump), "{bump}");
        assert!(heights.iter().all(|&z| z.abs() < 1e-9 || z > 0.05));
    }

    #[test]
    fn the_prefilter_changes_nothing() {
        let mut rng = StdRng::seed_from_u64(9);
        let mut plants =
            crate::world::crops::PlotSpec::maize(Point2::new(0.0, 0.0).unwrap(), 0.0, 15.0)
                .generate(&mut rng);
        plants.extend(
            crate::world::crops::PlotSpec::beans(Point2::new(0.0, 3.0).unwrap(), 0.0, 15.0)
                .generate(&mut rng),
        );
        let index = PlantIndex::new(plants.clone(), 0.5);
        let lidar = quiet();
        for pose in [
            (0.0, 0.0, 0.0),
            (5.0, 0.1, 0.05),
            (9.0, 2.8, -0.2),
            (3.0, 1.5, 1.57),
        ] {
            let pose = Pose2::<World>::new(pose.0, pose.1, pose.2).unwrap();
            let fast = lidar.scan(&pose, &flat(&index), &mut rng);
            assert_eq!(fast.ranges, lidar.scan_exhaustive(&pose, &flat(&index)));
        }
    }

    #[test]
    fn noise_has_the_configured_spread() {
        let lidar = InclinedLidar {
            range_noise: 0.02,
            ..InclinedLidar::furrow_default()
        };
        let pose = Pose2::<World>::new(0.0, 0.0, 0.0).unwrap();
        let index = PlantIndex::new(Vec::new(), 0.5);
        let clean = lidar.scan_exhaustive(&pose, &flat(&index));
        let mut rng = StdRng::seed_from_u64(4);
        let mut sq = 0.0;
        let mut n = 0.0;
        for _ in 0..20 {
            let s = lidar.scan(&pose, &flat(&index), &mut rng);
            for (a, b) in s.ranges.iter().zip(&clean) {
                sq += (a - b) * (a - b);
                n += 1.0;
            }
        }
        let sigma = (sq / n).sqrt();
        assert!((sigma - 0.02).abs() < 0.002, "{sigma}");
    }
}
