//! Terrain: the ground's height (flat, sloping or undulating) and its
//! sideslip angles, everywhere and on patches.
//!
//! The height z = g(x, y) is what every LiDAR ray meets when it hits the
//! ground and what plants stand on; a plane of slope `(dz/dx, dz/dy)` plus a
//! sinusoidal undulation across a heading. The vehicle itself is driven in
//! the plane (its kinematics ignore its attitude); the ground's shape acts
//! through what the sensors see.
//!
//! A patch is a polygon in the world frame (metres) carrying its own front and
//! rear sideslip angles β_F, β_R (Pierre 2022, section 2.1: the angle from each
//! wheel's orientation to its actual velocity). The sideslip acting on the
//! vehicle is that of the first patch containing the middle of the rear axle
//! (the controlled point O), or the base sideslip outside every patch. The
//! change at a patch boundary is a step: real ground changes over a wheel's
//! length, which at 0.8 m/s is a few control periods, shorter than the
//! steering actuator's settling time.

use fieldguide::model::bicycle::Sideslip;

/// A polygon of ground with its own sideslip.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipPatch {
    /// Name, for plots and messages.
    pub name: String,
    /// Vertices `[x, y]`, world frame, metres, at least 3, in order (either orientation).
    pub polygon: Vec<[f64; 2]>,
    /// The sideslip on the patch.
    pub sideslip: Sideslip,
}

impl SlipPatch {
    /// Whether `(x, y)` lies inside the polygon (even-odd rule; points on an
    /// edge may fall either side).
    #[must_use]
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let mut inside = false;
        let n = self.polygon.len();
        for (i, a) in self.polygon.iter().enumerate() {
            let Some(b) = self.polygon.get((i + n - 1) % n) else {
                continue;
            };
            let crosses = (a[1] > y) != (b[1] > y);
            if crosses {
                let x_cross = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                if x < x_cross {
                    inside = !inside;
                }
            }
        }
        inside
    }
}

/// A sinusoidal undulation of the ground: crests `wavelength` m apart,
/// running across `heading` (the direction in which the height varies).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Undulation {
    /// Half the crest-to-trough height, m.
    pub amplitude: f64,
    /// Distance between crests, m, > 0.
    pub wavelength: f64,
    /// Direction in which the height varies, rad from east.
    pub heading: f64,
}

/// The shape of the ground: z = slope · (x, y) + amplitude sin(2π u / wavelength),
/// u the position along the undulation's heading.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ground {
    /// (dz/dx, dz/dy), dimensionless.
    pub slope: [f64; 2],
    /// The undulation, if any.
    pub undulation: Option<Undulation>,
}

impl Ground {
    /// Whether the ground is the plane z = 0.
    #[must_use]
    pub fn is_flat(&self) -> bool {
        self.slope == [0.0, 0.0] && self.undulation.is_none()
    }

    /// An upper bound of the ground's height over a field of ±1 km, m (the
    /// slope's rise over 1 km plus the undulation's amplitude).
    #[must_use]
    pub fn highest(&self) -> f64 {
        let rise = 1000.0 * (self.slope[0].abs() + self.slope[1].abs());
        rise + self.undulation.map_or(0.0, |u| u.amplitude.abs())
    }

    /// The ground's height at `(x, y)`, m.
    #[must_use]
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let plane = self.slope[0] * x + self.slope[1] * y;
        match self.undulation {
            None => plane,
            Some(u) => {
                let along = x * u.heading.cos() + y * u.heading.sin();
                plane + u.amplitude * (core::f64::consts::TAU * along / u.wavelength).sin()
            }
        }
    }

    /// The range at which the ray from `o` along the unit direction `d`
    /// meets the ground within `max`, if it does: exact on the flat plane,
    /// else by marching in steps of at most `STEP_M` of height change and
    /// bisecting the first crossing to 0.1 mm.
    #[must_use]
    pub fn hit(&self, o: [f64; 3], d: [f64; 3], max: f64) -> Option<f64> {
        if self.is_flat() {
            return (d[2] < 0.0).then(|| o[2] / -d[2]);
        }
        /// Largest ray step, m: far below an undulation's wavelength.
        const STEP_M: f64 = 0.05;
        let above = |r: f64| o[2] + r * d[2] - self.height(o[0] + r * d[0], o[1] + r * d[1]);
        if above(0.0) <= 0.0 {
            return Some(0.0);
        }
        let mut r0 = 0.0;
        while r0 < max {
            let r1 = (r0 + STEP_M).min(max);
            if above(r1) <= 0.0 {
                let (mut lo, mut hi) = (r0, r1);
                while hi - lo > 1e-4 {
                    let mid = 0.5 * (lo + hi);
                    if above(mid) <= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(hi);
            }
            r0 = r1;
        }
        None
    }
}

/// The ground of a world: its shape, base sideslip and patches.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Terrain {
    /// Sideslip outside every patch.
    pub base: Sideslip,
    /// Patches, the first containing a point wins.
    pub patches: Vec<SlipPatch>,
    /// The ground's height.
    pub ground: Ground,
}

impl Terrain {
    /// The patch containing `(x, y)`, if any.
    #[must_use]
    pub fn patch_at(&self, x: f64, y: f64) -> Option<&SlipPatch> {
        self.patches.iter().find(|p| p.contains(x, y))
    }

    /// The sideslip at `(x, y)`, world frame, metres.
    #[must_use]
    pub fn sideslip_at(&self, x: f64, y: f64) -> Sideslip {
        self.patch_at(x, y).map_or(self.base, |p| p.sideslip)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(name: &str, x0: f64, y0: f64, side: f64, beta: f64) -> SlipPatch {
        SlipPatch {
            name: name.to_owned(),
            polygon: vec![
                [x0, y0],
                [x0 + side, y0],
                [x0 + side, y0 + side],
                [x0, y0 + side],
            ],
            sideslip: Sideslip::new(beta, beta).unwrap(),
        }
    }

    #[test]
    fn point_in_polygon_square_and_concave() {
        let sq = square("a", 0.0, 0.0, 2.0, 0.0);
        assert!(sq.contains(1.0, 1.0));
        assert!(!sq.contains(3.0, 1.0));
        assert!(!sq.contains(1.0, -0.1));
        // An L shape (concave): the notch is outside.
        let l = SlipPatch {
            name: "l".into(),
            polygon: vec![
                [0.0, 0.0],
                [2.0, 0.0],
                [2.0, 1.0],
                [1.0, 1.0],
                [1.0, 2.0],
                [0.0, 2.0],
            ],
            sideslip: Sideslip::ZERO,
        };
        assert!(l.contains(0.5, 1.5));
        assert!(l.contains(1.5, 0.5));
        assert!(!l.contains(1.5, 1.5));
        // Clockwise order gives the same answer.
        let mut cw = sq.clone();
        cw.polygon.reverse();
        assert!(cw.contains(1.0, 1.0) && !cw.contains(-1.0, 1.0));
    }

    #[test]
    fn first_patch_wins_and_base_elsewhere() {
        let terrain = Terrain {
            base: Sideslip::new(0.01, 0.02).unwrap(),
            patches: vec![
                square("a", 0.0, 0.0, 2.0, -0.05),
                square("b", 1.0, 1.0, 2.0, 0.07),
            ],
            ..Terrain::default()
        };
        assert_eq!(terrain.sideslip_at(1.5, 1.5).rear.get(), -0.05);
        assert_eq!(terrain.sideslip_at(2.5, 2.5).rear.get(), 0.07);
        assert_eq!(terrain.sideslip_at(10.0, 0.0), terrain.base);
        assert_eq!(
            terrain.patch_at(2.5, 2.5).map(|p| p.name.as_str()),
            Some("b")
        );
    }
}
