//! Simulated proprioceptive sensors: RTK-GNSS pose, the sideslip observer and
//! odometry (distance from the wheels, heading from the wheels or from a yaw
//! gyro). Each tick draws the same number of random values whatever the noise
//! levels, from the run's one generator (see [`crate::rng`]); a gyro draws
//! from its own generator, seeded from the run's seed, so that a run with a
//! gyro sees the same world, path and other noise as the run with wheels.

use fieldguide::guidance::{FixKind, FixQuality};
use fieldguide::model::bicycle::Sideslip;
use fieldguide::{Odom, Pose2, Precondition, World};

use crate::plant::VehicleState;
use crate::rng::{gauss_markov, SimRng};

/// Mixed into the run's seed to seed the gyro's own generator.
pub const GYRO_STREAM: u64 = 0x6779_7230_0d0e_a000;

/// Where the odometry's heading increments come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HeadingSource {
    /// The wheels: each tick's true heading change plus
    /// `odometry_yaw_bias_rad_s · Δt` and a white noise of σ
    /// `odometry_yaw_noise_rad` per tick, so that the heading's random walk
    /// after t seconds, σ √(t / Δt), grows with the tick rate; nothing while
    /// no wheel turns (the encoders count nothing at rest).
    Wheels,
    /// A yaw-rate gyro integrated over each tick ([`GyroErrors`]).
    Gyro(GyroErrors),
}

/// The errors of a yaw-rate gyro in its datasheet's terms (the Allan
/// variance's angle random walk and bias instability, IEEE Std 952).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroErrors {
    /// Angle random walk, rad/√s: the rate's white noise integrates to a
    /// heading error of σ = ARW √t whatever the tick rate (σ ARW √Δt per tick).
    pub random_walk_rad_sqrt_s: f64,
    /// Constant bias left on the rate after its calibration at standstill,
    /// rad/s: the heading drifts by bias · t.
    pub bias_rad_s: f64,
    /// Bias instability: stationary σ of a slow wander of the bias, a
    /// first-order Gauss-Markov process starting at zero, rad/s (0: none).
    pub bias_instability_rad_s: f64,
    /// Correlation time of that wander, s.
    pub bias_time_constant_s: f64,
}

/// A gyro through a run: its errors, its own generator and its bias wander.
#[derive(Debug, Clone)]
struct Gyro {
    errors: GyroErrors,
    rng: SimRng,
    /// The bias wander's value, rad/s.
    wander_rad_s: f64,
}

impl Gyro {
    /// The gyro's error on the heading change over the last `dt` seconds,
    /// rad. Draws two values from its own generator (random walk, then the
    /// bias wander), at each reading but the first (which has no increment).
    fn error(&mut self, dt: f64) -> f64 {
        let e = self.errors;
        let walk = self
            .rng
            .gaussian(e.random_walk_rad_sqrt_s * dt.max(0.0).sqrt());
        let error = (e.bias_rad_s + self.wander_rad_s) * dt + walk;
        self.wander_rad_s = gauss_markov(
            self.wander_rad_s,
            e.bias_instability_rad_s,
            e.bias_time_constant_s,
            dt,
            self.rng.gaussian(1.0),
        );
        error
    }
}

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
    /// Where the odometry's heading comes from (the two fields above are
    /// the wheels' errors, unused with a gyro).
    pub heading: HeadingSource,
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

/// The sensors' state: the observer's filtered estimate, the odometry pose
/// and the gyro.
#[derive(Debug, Clone)]
pub struct Sensors {
    noise: SensorNoise,
    /// Filtered (front, rear) sideslip before noise, radians.
    observer: (f64, f64),
    /// Odometry pose (x, y, heading) in the odometry frame.
    odometry: (f64, f64, f64),
    /// The true state at the previous reading, for the odometry increments.
    last_truth: Option<VehicleState>,
    /// The gyro, when it gives the heading.
    gyro: Option<Gyro>,
}

impl Sensors {
    /// Sensors with `noise`, the observer starting at the true sideslip of
    /// `initial`; a gyro's generator is seeded from the run's `seed`.
    #[must_use]
    pub fn new(noise: SensorNoise, initial: &VehicleState, seed: u64) -> Self {
        Self {
            noise,
            observer: (initial.sideslip.front.get(), initial.sideslip.rear.get()),
            odometry: (0.0, 0.0, 0.0),
            last_truth: None,
            gyro: match noise.heading {
                HeadingSource::Wheels => None,
                HeadingSource::Gyro(errors) => Some(Gyro {
                    errors,
                    rng: SimRng::from_seed(seed ^ GYRO_STREAM),
                    wander_rad_s: 0.0,
                }),
            },
        }
    }

    /// The readings at the true state `truth`, `dt` seconds after the previous
    /// reading, with a GNSS pose when `fix`. Draws 7 values from `rng`, with
    /// or without a fix: GNSS x, y, heading; observer front, rear; the
    /// wheels' heading noise (drawn, unused, with a gyro); and one reserved
    /// for an odometry distance noise (so adding it later keeps streams
    /// aligned). A gyro draws from its own generator.
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
        // error, and the heading source's errors, integrated along the
        // odometry heading (it does not know the sideslip, so a slipping
        // vehicle drifts too).
        let heading_noise = rng.gaussian(n.odometry_yaw_noise_rad);
        let _reserved = rng.gaussian(0.0);
        if let Some(last) = self.last_truth {
            let ds = (truth.distance_m - last.distance_m) * (1.0 + n.odometry_scale_error);
            let turn = fieldguide::Radians::new(truth.pose.heading.get() - last.pose.heading.get())
                .map_or(f64::NAN, |a| {
                    fieldguide::geometry::units::wrap_angle(a).get()
                });
            // The wheels' heading comes from their encoders: while no wheel
            // turns it stays still, errors included; a gyro drifts at rest too.
            let wheels_still = ds == 0.0 && turn == 0.0;
            let dth = match self.gyro.as_mut() {
                None if wheels_still => 0.0,
                None => turn + n.odometry_yaw_bias_rad_s * dt + heading_noise,
                Some(gyro) => turn + gyro.error(dt),
            };
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
            heading: HeadingSource::Wheels,
        }
    }

    fn state(x: f64, y: f64, th: f64, d: f64) -> VehicleState {
        let mut s = VehicleState::at(Pose2::new(x, y, th).unwrap(), &Terrain::default());
        s.distance_m = d;
        s
    }

    /// The last readings of `sensors` along `states`, one every `dt`.
    fn last_reading(
        sensors: &mut Sensors,
        states: impl Iterator<Item = VehicleState>,
        dt: f64,
        rng: &mut SimRng,
    ) -> Readings {
        let mut last = None;
        for s in states {
            last = Some(sensors.read(&s, dt, true, rng).unwrap());
        }
        last.unwrap()
    }

    #[test]
    fn noiseless_sensors_report_the_truth() {
        let s0 = state(3.0, 4.0, 0.5, 0.0);
        let mut sensors = Sensors::new(quiet(), &s0, 1);
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
        let (mut a, mut b) = (Sensors::new(noise, &s0, 3), Sensors::new(noise, &s0, 3));
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
        let mut sensors = Sensors::new(noise, &s0, 1);
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
        let mut sensors = Sensors::new(noise, &state(0.0, 0.0, 0.0, 0.0), 1);
        let mut rng = SimRng::from_seed(2);
        let odo = last_reading(
            &mut sensors,
            (0..=100).map(|k| {
                let d = f64::from(k) * 0.1;
                state(d, 0.0, 0.0, d)
            }),
            0.1,
            &mut rng,
        )
        .odometry;
        // 10 m driven, 10.2 m counted; 10 s of 0.01 rad/s bias: 0.1 rad of heading.
        assert!((odo.heading.get() - 0.1).abs() < 1e-9);
        let counted = odo.position.x().hypot(odo.position.y());
        assert!((counted - 10.2).abs() < 0.01, "{counted}");
        assert!(
            odo.position.y() > 0.4,
            "the biased heading bends the track left"
        );
    }

    fn gyro(errors: GyroErrors) -> SensorNoise {
        SensorNoise {
            heading: HeadingSource::Gyro(errors),
            ..quiet()
        }
    }

    const EXACT_GYRO: GyroErrors = GyroErrors {
        random_walk_rad_sqrt_s: 0.0,
        bias_rad_s: 0.0,
        bias_instability_rad_s: 0.0,
        bias_time_constant_s: 1.0,
    };

    /// The odometry heading after `duration_s` at `speed` m/s straight
    /// ahead (0: standing still), read every `dt`.
    fn heading_at(noise: SensorNoise, seed: u64, dt: f64, duration_s: f64, speed: f64) -> f64 {
        let s0 = state(0.0, 0.0, 0.0, 0.0);
        let mut sensors = Sensors::new(noise, &s0, seed);
        let mut rng = SimRng::from_seed(seed);
        let ticks = (duration_s / dt).round() as u32;
        let states = (0..=ticks).map(|k| {
            let d = speed * dt * f64::from(k);
            state(d, 0.0, 0.0, d)
        });
        last_reading(&mut sensors, states, dt, &mut rng)
            .odometry
            .heading
            .get()
    }

    /// The odometry heading after `duration_s` standing still, read every `dt`.
    fn heading_after(noise: SensorNoise, seed: u64, dt: f64, duration_s: f64) -> f64 {
        heading_at(noise, seed, dt, duration_s, 0.0)
    }

    /// The variance of the heading error after `duration_s` at `speed` over
    /// seeds 1..=`seeds`.
    fn heading_variance(
        noise: SensorNoise,
        dt: f64,
        duration_s: f64,
        speed: f64,
        seeds: u64,
    ) -> f64 {
        let sq: f64 = (1..=seeds)
            .map(|seed| heading_at(noise, seed, dt, duration_s, speed).powi(2))
            .sum();
        sq / seeds as f64
    }

    #[test]
    fn the_wheels_heading_stands_still_with_the_wheels_and_a_gyro_drifts() {
        let mut wheels = quiet();
        wheels.odometry_yaw_bias_rad_s = 0.001;
        wheels.odometry_yaw_noise_rad = 0.001;
        assert_eq!(heading_after(wheels, 5, 0.01, 20.0), 0.0);
        assert!(heading_at(wheels, 5, 0.01, 20.0, 1.0).abs() > 0.005);
        let drifting = gyro(GyroErrors {
            bias_rad_s: 0.001,
            ..EXACT_GYRO
        });
        assert!((heading_after(drifting, 5, 0.01, 20.0) - 0.02).abs() < 1e-9);
    }

    #[test]
    fn the_gyro_random_walk_grows_as_its_datasheet_says_whatever_the_tick_rate() {
        // ARW 0.01 rad/√s: after 40 s the heading error's variance is
        // ARW² · 40 = 0.004 rad², at 100 Hz and at 20 Hz alike. Over 800
        // seeds the variance's estimate has a relative σ of √(2/800) = 5 %.
        let noise = gyro(GyroErrors {
            random_walk_rad_sqrt_s: 0.01,
            ..EXACT_GYRO
        });
        let expected = 0.01_f64.powi(2) * 40.0;
        let fast = heading_variance(noise, 0.01, 40.0, 0.0, 800);
        let slow = heading_variance(noise, 0.05, 40.0, 0.0, 800);
        for v in [fast, slow] {
            assert!((v / expected - 1.0).abs() < 0.16, "{v} vs {expected}");
        }
        assert!((fast / slow - 1.0).abs() < 0.25, "{fast} vs {slow}");
        // The wheels' noise is per tick: five times the ticks, five times the variance.
        let mut wheels = quiet();
        wheels.odometry_yaw_noise_rad = 0.001;
        let ratio = heading_variance(wheels, 0.01, 40.0, 1.0, 400)
            / heading_variance(wheels, 0.05, 40.0, 1.0, 400);
        assert!((ratio / 5.0 - 1.0).abs() < 0.3, "{ratio}");
    }

    #[test]
    fn the_gyro_bias_integrates_to_bias_times_time_and_turns_are_kept() {
        let noise = gyro(GyroErrors {
            bias_rad_s: 0.001,
            ..EXACT_GYRO
        });
        for dt in [0.01, 0.05] {
            assert!((heading_after(noise, 4, dt, 100.0) - 0.1).abs() < 1e-9);
        }
        // Turning: the true turn plus the bias, integrated along the heading.
        let mut sensors = Sensors::new(noise, &state(0.0, 0.0, 0.0, 0.0), 4);
        let mut rng = SimRng::from_seed(4);
        let turning = (0..=100).map(|k| {
            let t = f64::from(k) * 0.1;
            state(0.0, 0.0, 0.05 * t, t)
        });
        let heading = last_reading(&mut sensors, turning, 0.1, &mut rng)
            .odometry
            .heading
            .get();
        assert!((heading - (0.5 + 0.01)).abs() < 1e-9, "{heading}");
    }

    #[test]
    fn the_gyro_bias_wanders_with_its_instability_and_correlation_time() {
        // Standing still, each tick's heading error is the bias times dt: the
        // bias starts at zero, and after five correlation times its spread
        // over seeds is the instability.
        let sigma = 0.002;
        let noise = gyro(GyroErrors {
            bias_instability_rad_s: sigma,
            bias_time_constant_s: 2.0,
            ..EXACT_GYRO
        });
        let dt = 0.05;
        let s0 = state(0.0, 0.0, 0.0, 0.0);
        let (mut first, mut late) = (0.0_f64, 0.0);
        let seeds = 2000;
        for seed in 1..=seeds {
            let mut sensors = Sensors::new(noise, &s0, seed);
            let mut rng = SimRng::from_seed(seed);
            let mut headings = Vec::new();
            for _ in 0..=201 {
                let r = sensors.read(&s0, dt, true, &mut rng).unwrap();
                headings.push(r.odometry.heading.get());
            }
            first = first.max(headings[1].abs());
            late += ((headings[201] - headings[200]) / dt).powi(2);
        }
        assert!(first < 1e-15, "the wander starts at zero: {first}");
        let spread = (late / seeds as f64).sqrt();
        assert!((spread / sigma - 1.0).abs() < 0.08, "{spread}");
    }

    #[test]
    fn an_exact_gyro_is_exact_wheels_and_the_gyro_leaves_the_other_draws_alone() {
        let s0 = state(0.0, 0.0, 0.0, 0.0);
        let base = SensorNoise {
            gnss_position_m: 0.015,
            odometry_scale_error: 0.01,
            ..quiet()
        };
        let noisy_gyro = SensorNoise {
            heading: HeadingSource::Gyro(GyroErrors {
                random_walk_rad_sqrt_s: 0.01,
                bias_rad_s: 0.001,
                ..EXACT_GYRO
            }),
            ..base
        };
        let exact_gyro = SensorNoise {
            heading: HeadingSource::Gyro(EXACT_GYRO),
            ..base
        };
        let mut wheels = Sensors::new(base, &s0, 5);
        let mut exact = Sensors::new(exact_gyro, &s0, 5);
        let mut noisy = Sensors::new(noisy_gyro, &s0, 5);
        let (mut ra, mut rb, mut rc) = (
            SimRng::from_seed(5),
            SimRng::from_seed(5),
            SimRng::from_seed(5),
        );
        for k in 0..200 {
            let t = f64::from(k) * 0.02;
            let truth = state(t, 0.1 * t * t, 0.2 * t, t);
            let a = wheels.read(&truth, 0.02, true, &mut ra).unwrap();
            let b = exact.read(&truth, 0.02, true, &mut rb).unwrap();
            let c = noisy.read(&truth, 0.02, true, &mut rc).unwrap();
            assert_eq!(a, b);
            assert_eq!(a.gnss, c.gnss);
            if k > 10 {
                assert_ne!(a.odometry, c.odometry);
            }
        }
    }

    #[test]
    fn observer_converges_with_its_settling_time() {
        let mut noise = quiet();
        noise.sideslip_observer_settling_s = 1.0;
        let s0 = state(0.0, 0.0, 0.0, 0.0);
        let mut sensors = Sensors::new(noise, &s0, 1);
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
