//! Wheel odometry with drift: the robot's own estimate of its motion, in the
//! odometry frame, integrated from wheel increments that carry a scale error,
//! a heading drift and random noise.

use fieldguide::{Odom, Pose2, World};
use rand::Rng;
use rand_distr::{Distribution, Normal};

/// The error model of the wheel odometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OdometryErrors {
    /// Relative error on the distance travelled (0.01 = reads 1 % long).
    pub scale: f64,
    /// Heading drift per metre travelled, rad/m (a steady bias, e.g. unequal wheel radii).
    pub yaw_drift: f64,
    /// Standard deviation of the distance noise per √m travelled, m/√m.
    pub distance_noise: f64,
    /// Standard deviation of the heading noise per √m travelled, rad/√m.
    pub yaw_noise: f64,
}

impl OdometryErrors {
    /// No error at all: the odometry follows the true motion exactly.
    pub const EXACT: Self = Self {
        scale: 0.0,
        yaw_drift: 0.0,
        distance_noise: 0.0,
        yaw_noise: 0.0,
    };

    /// A typical tractor on soil: 1 % scale error, 0.005 rad/m drift, a few mm of noise.
    pub const FIELD: Self = Self {
        scale: 0.01,
        yaw_drift: 0.005,
        distance_noise: 0.003,
        yaw_noise: 0.002,
    };
}

/// The motion between two true poses as wheel odometry measures it: the
/// distance along the mean heading (negative backwards) and the heading
/// change, wrapped to (−π, π].
#[must_use]
pub fn increment(from: &Pose2<World>, to: &Pose2<World>) -> (f64, f64) {
    let dx = to.position.x() - from.position.x();
    let dy = to.position.y() - from.position.y();
    let dpsi = fieldguide::Radians::new(to.heading.get() - from.heading.get())
        .map_or(f64::NAN, |a| {
            fieldguide::geometry::units::wrap_angle(a).get()
        });
    let mid = from.heading.get() + dpsi / 2.0;
    (dx * mid.cos() + dy * mid.sin(), dpsi)
}

/// Wheel odometry: integrates measured increments into a pose of the odometry frame.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelOdometry {
    pose: Pose2<Odom>,
    errors: OdometryErrors,
    travelled: f64,
}

impl WheelOdometry {
    /// Odometry starting at `start` with the error model `errors`.
    #[must_use]
    pub const fn new(start: Pose2<Odom>, errors: OdometryErrors) -> Self {
        Self {
            pose: start,
            errors,
            travelled: 0.0,
        }
    }

    /// The current odometry pose.
    #[must_use]
    pub const fn pose(&self) -> Pose2<Odom> {
        self.pose
    }

    /// Distance travelled so far (true, unsigned), m.
    #[must_use]
    pub const fn travelled(&self) -> f64 {
        self.travelled
    }

    /// Integrates a true motion of `distance` m along the mean heading and a
    /// heading change of `turn` rad, as the wheels measure it (with the
    /// model's errors, noise drawn from `rng`), by the midpoint rule.
    /// Returns the new pose; a non-finite result leaves the pose unchanged.
    pub fn update(&mut self, distance: f64, turn: f64, rng: &mut impl Rng) -> Pose2<Odom> {
        let e = &self.errors;
        let root = distance.abs().sqrt();
        let draw = |std: f64, rng: &mut dyn rand::RngCore| {
            Normal::new(0.0, std * root)
                .map(|n| n.sample(rng))
                .unwrap_or(0.0)
        };
        let ds = distance * (1.0 + e.scale) + draw(e.distance_noise, rng);
        let dpsi = turn + e.yaw_drift * distance.abs() + draw(e.yaw_noise, rng);
        let psi = self.pose.heading.get();
        let mid = psi + dpsi / 2.0;
        let next = Pose2::new(
            self.pose.position.x() + ds * mid.cos(),
            self.pose.position.y() + ds * mid.sin(),
            psi + dpsi,
        );
        if let Ok(p) = next {
            self.pose = p;
            self.travelled += distance.abs();
        }
        self.pose
    }

    /// Integrates the true motion from `from` to `to` (see [`increment`]).
    pub fn update_between(
        &mut self,
        from: &Pose2<World>,
        to: &Pose2<World>,
        rng: &mut impl Rng,
    ) -> Pose2<Odom> {
        let (ds, dpsi) = increment(from, to);
        self.update(ds, dpsi, rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    fn arc(t: f64) -> Pose2<World> {
        // A circle of radius 10 m, counter-clockwise from (0, 0) heading east.
        let psi = t / 10.0;
        Pose2::new(10.0 * psi.sin(), 10.0 * (1.0 - psi.cos()), psi).unwrap()
    }

    #[test]
    fn exact_odometry_follows_the_true_motion() {
        let mut odo = WheelOdometry::new(Pose2::new(0.0, 0.0, 0.0).unwrap(), OdometryErrors::EXACT);
        let mut rng = StdRng::seed_from_u64(1);
        for i in 0..400 {
            odo.update_between(
                &arc(f64::from(i) * 0.05),
                &arc(f64::from(i + 1) * 0.05),
                &mut rng,
            );
        }
        let truth = arc(20.0);
        let p = odo.pose();
        assert!((p.position.x() - truth.position.x()).abs() < 1e-6);
        assert!((p.position.y() - truth.position.y()).abs() < 1e-6);
        assert!((p.heading.get() - truth.heading.get()).abs() < 1e-9);
        // The chords of 0.05 m arcs: 20 m less about 1e-5 m.
        assert!((odo.travelled() - 20.0).abs() < 1e-4);
    }

    #[test]
    fn drift_grows_with_distance() {
        let errors = OdometryErrors {
            scale: 0.02,
            yaw_drift: 0.01,
            distance_noise: 0.0,
            yaw_noise: 0.0,
        };
        let mut odo = WheelOdometry::new(Pose2::new(0.0, 0.0, 0.0).unwrap(), errors);
        let mut rng = StdRng::seed_from_u64(1);
        for _ in 0..100 {
            odo.update(0.1, 0.0, &mut rng);
        }
        // 10 m straight reads 10.2 m, and the heading drifted by 0.1 rad.
        let p = odo.pose();
        assert!((p.heading.get() - 0.1).abs() < 1e-9);
        let read = p.position.x().hypot(p.position.y());
        assert!((read - 10.2).abs() < 0.01, "{read}");
        assert!(p.position.y() > 0.4);
    }

    #[test]
    fn noise_is_seeded() {
        let run = |seed| {
            let mut odo =
                WheelOdometry::new(Pose2::new(0.0, 0.0, 0.0).unwrap(), OdometryErrors::FIELD);
            let mut rng = StdRng::seed_from_u64(seed);
            for _ in 0..50 {
                odo.update(0.05, 0.001, &mut rng);
            }
            odo.pose()
        };
        assert_eq!(run(3), run(3));
        assert_ne!(run(3), run(4));
    }
}
