//! Simulated proprioceptive sensors: RTK-GNSS pose, the sideslip observer and
//! wheel odometry. Each tick draws the same number of random values whatever
//! the noise levels, from the run's one generator (see [`crate::rng`]).

use fieldguide::guidance::{FixKind, FixQuality};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::{Odom, Pose2, Precondition, World};

use crate::plant::VehicleState;
use crate::rng::SimRng;

/// Noise levels and drifts of the sensors (radians and metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise {
    /// RTK-GNSS position noise, per axis, metres (white, one draw per tick).
    pub gnss_position_m: f64,
    /// Heading noise of the localisation, radians (white).
    pub gnss_heading_rad: f64,
    /// Sideslip observer noise on each angle, radians (white).
    pub sideslip_rad: f64,
    /// 5 % settling time of the sideslip observer, seconds.
    pub sideslip_observer_settling_s: f64,
    /// Relative error of the odometry distance (0.01: 1 % too long).
    pub odometry_scale_error: f64,
    /// Bias of the odometry yaw rate, rad/s.
    pub odometry_yaw_bias_rad_s: f64,
    /// Noise on each odometry heading increment, radians.
    pub odometry_yaw_noise_rad: f64,
}

/// What the robot's sensors report at one tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Readings {
    /// Estimated pose of O from RTK-GNSS (and IMU), world frame; `None`
    /// without a fix.
    pub gnss: Option<Pose2<World>>,
    /// What the receiver says of that fix: RTK fixed with σ the white
    /// noise `gnss_position_m`, unless the runner's GNSS errors say float
    /// (`crate::gnss::GnssError::quality`).
    pub gnss_quality: FixQuality,
    /// Pose of O from wheel odometry, odometry frame (the robot's start pose is its origin).
    pub odometry: Pose2<Odom>,
    /// The sideslip observer's estimate of β_F and β_R.
    pub sideslip: Sideslip,
}

/// The sensors' state: the observer's filtered estimate and the odometry pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensors {
    noise: SensorNoise,
    /// Filtered (front, rear) sideslip before noise, radians.
    observer: (f64, f64),
    /// Odometry pose (x, y, heading) in the odometry frame.
    odometry: (f64, f64, f64),
    /// The true state at the previous reading, for the odometry increments.
    last_truth: Option<VehicleState>,
}

impl Sensors {
    /// Sensors with `noise`, the observer starting at the true sideslip of `initial`.
    #[must_use]
    pub fn new(noise: SensorNoise, initial: &VehicleState) -> Self {
        Self {
            noise,
            observer: (initial.sideslip.front.get(), initial.sideslip.rear.get()),
            odometry: (0.0, 0.0, 0.0),
            last_truth: None,
        }
    }

    /// The readings at the true state `truth`, `dt` seconds after the previous
    /// reading, with a GNSS pose when `fix`. Draws 7 values from `rng`, with
    /// or without a fix: GNSS x, y, heading; observer front, rear; odometry
    /// heading noise; and one reserved for an odometry distance noise (so
    /// adding it later keeps streams aligned).
    ///
    /// Errors only on non-finite values (`LIB-FINITE`).
    pub fn read(
        &mut self,
        truth: &VehicleState,
        dt: f64,
        fix: bool,
        rng: &mut SimRng,
    ) -> Result<Readings, Precondition> {
        let n = self.noise;
        let p = truth.pose;
        let gnss = Pose2::new(
            p.position.x() + rng.gaussian(n.gnss_position_m),
            p.position.y() + rng.gaussian(n.gnss_position_m),
            p.heading.get() + rng.gaussian(n.gnss_heading_rad),
        )?;

        // Observer: first-order convergence to the true sideslip (τ = T_s / 3), plus noise.
        let tau = n.sideslip_observer_settling_s / 3.0;
        let gain = if tau > 0.0 {
            1.0 - (-dt / tau).exp()
        } else {
            1.0
        };
        let (front, rear) = (truth.sideslip.front.get(), truth.sideslip.rear.get());
        self.observer.0 += gain * (front - self.observer.0);
        self.observer.1 += gain * (rear - self.observer.1);
        let sideslip = Sideslip::new(
            self.observer.0 + rng.gaussian(n.sideslip_rad),
            self.observer.1 + rng.gaussian(n.sideslip_rad),
        )?;

        // Odometry: distance and heading increments of the truth, with scale
        // error, yaw bias and noise, integrated along the odometry heading (it
        // does not know the sideslip, so a slipping vehicle drifts too).
        let heading_noise = rng.gaussian(n.odometry_yaw_noise_rad);
        let _reserved = rng.gaussian(0.0);
        if let Some(last) = self.last_truth {
            let ds = (truth.distance_m - last.distance_m) * (1.0 + n.odometry_scale_error);
            let dth = fieldguide::Radians::new(truth.pose.heading.get() - last.pose.heading.get())
                .map_or(f64::NAN, |a| {
                    fieldguide::geometry::units::wrap_angle(a).get()
                })
                + n.odometry_yaw_bias_rad_s * dt
                + heading_noise;
            let (x, y, th) = self.odometry;
            let mid = th + dth / 2.0;
            self.odometry = (x + ds * mid.cos(), y + ds * mid.sin(), th + dth);
        }
        self.last_truth = Some(*truth);
        let (x, y, th) = self.odometry;
        Ok(Readings {
            gnss: fix.then_some(gnss),
            gnss_quality: FixQuality {
                kind: FixKind::RtkFixed,
                accuracy: fieldguide::Meters::new(n.gnss_position_m).ok(),
            },
            odometry: Pose2::new(x, y, th)?,
            sideslip,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::terrain::Terrain;

    fn quiet() -> SensorNoise {
        SensorNoise {
            gnss_position_m: 0.0,
            gnss_heading_rad: 0.0,
            sideslip_rad: 0.0,
            sideslip_observer_settling_s: 0.0,
            odometry_scale_error: 0.0,
            odometry_yaw_bias_rad_s: 0.0,
            odometry_yaw_noise_rad: 0.0,
        }
    }

    fn state(x: f64, y: f64, th: f64, d: f64) -> VehicleState {
        let mut s = VehicleState::at(Pose2::new(x, y, th).unwrap(), &Terrain::default());
        s.distance_m = d;
        s
    }

    #[test]
    fn noiseless_sensors_report_the_truth() {
        let s0 = state(3.0, 4.0, 0.5, 0.0);
        let mut sensors = Sensors::new(quiet(), &s0);
        let mut rng = SimRng::from_seed(1);
        let r = sensors.read(&s0, 0.02, true, &mut rng).unwrap();
        assert_eq!(r.gnss, Some(s0.pose));
        assert_eq!(r.odometry, Pose2::new(0.0, 0.0, 0.0).unwrap());
        // Straight ahead 1 m: odometry moves 1 m along its own x axis.
        let s1 = state(3.0 + 0.5_f64.cos(), 4.0 + 0.5_f64.sin(), 0.5, 1.0);
        let r = sensors.read(&s1, 0.02, true, &mut rng).unwrap();
        assert!((r.odometry.position.x() - 1.0).abs() < 1e-12);
        assert!(r.odometry.position.y().abs() < 1e-12);
    }

    #[test]
    fn without_a_fix_there_is_no_pose_and_the_streams_stay_aligned() {
        let s0 = state(3.0, 4.0, 0.5, 0.0);
        let mut noise = quiet();
        noise.gnss_position_m = 0.015;
        noise.sideslip_rad = 0.01;
        let (mut a, mut b) = (Sensors::new(noise, &s0), Sensors::new(noise, &s0));
        let (mut ra, mut rb) = (SimRng::from_seed(3), SimRng::from_seed(3));
        let lost = a.read(&s0, 0.02, false, &mut ra).unwrap();
        let fixed = b.read(&s0, 0.02, true, &mut rb).unwrap();
        assert_eq!(lost.gnss, None);
        assert!(fixed.gnss.is_some());
        assert_eq!(lost.sideslip, fixed.sideslip);
        // The next draws are the same: the outage consumed the same values.
        let next_a = a.read(&s0, 0.02, true, &mut ra).unwrap();
        let next_b = b.read(&s0, 0.02, true, &mut rb).unwrap();
        assert_eq!(next_a, next_b);
    }

    #[test]
    fn gnss_noise_has_the_configured_spread() {
        let mut noise = quiet();
        noise.gnss_position_m = 0.015;
        let s0 = state(0.0, 0.0, 0.0, 0.0);
        let mut sensors = Sensors::new(noise, &s0);
        let mut rng = SimRng::from_seed(9);
        let n = 5000;
        let sq: f64 = (0..n)
            .map(|_| {
                sensors
                    .read(&s0, 0.02, true, &mut rng)
                    .unwrap()
                    .gnss
                    .unwrap()
                    .position
                    .x()
                    .powi(2)
            })
            .sum();
        let sigma = (sq / f64::from(n)).sqrt();
        assert!((sigma - 0.015).abs() < 0.001, "sigma {sigma}");
    }

    #[test]
    fn odometry_scale_error_and_bias_drift() {
        let mut noise = quiet();
        noise.odometry_scale_error = 0.02;
        noise.odometry_yaw_bias_rad_s = 0.01;
        let mut sensors = Sensors::new(noise, &state(0.0, 0.0, 0.0, 0.0));
        let mut rng = SimRng::from_seed(2);
        let mut last = None;
        for k in 0..=100 {
            let d = f64::from(k) * 0.1;
            last = Some(
                sensors
                    .read(&state(d, 0.0, 0.0, d), 0.1, true, &mut rng)
                    .unwrap(),
            );
        }
        let odo = last.unwrap().odometry;
        // 10 m driven, 10.2 m counted; 10 s of 0.01 rad/s bias: 0.1 rad of heading.
        assert!((odo.heading.get() - 0.1).abs() < 1e-9);
        let counted = odo.position.x().hypot(odo.position.y());
        assert!((counted - 10.2).abs() < 0.01, "{counted}");
        assert!(
            odo.position.y() > 0.4,
            "the biased heading bends the track left"
        );
    }

    #[test]
    fn observer_converges_with_its_settling_time() {
        let mut noise = quiet();
        noise.sideslip_observer_settling_s = 1.0;
        let s0 = state(0.0, 0.0, 0.0, 0.0);
        let mut sensors = Sensors::new(noise, &s0);
        let mut slipping = s0;
        slipping.sideslip = Sideslip::new(-0.03, -0.05).unwrap();
        let mut rng = SimRng::from_seed(3);
        let mut r = None;
        for _ in 0..50 {
            r = Some(sensors.read(&slipping, 0.02, true, &mut rng).unwrap());
        }
        let rear = r.unwrap().sideslip.rear.get();
        assert!((rear - (-0.05) * 0.95).abs() < 0.05 * 0.002, "{rear}");
    }
}
