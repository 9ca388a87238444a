//! Centre lines that follow a real field: a polyline whose corners are
//! rounded by circular arcs of one radius (a line-arc-line chain, so the
//! heading is continuous along it), for plots, hedges, post rows and fences.
//!
//! A curve is checked when built: at least two distinct vertices, no corner
//! turning by more than 90° (the line would fold back on itself), and room on
//! every side for the arcs of its two ends. [`Curve::check_band`] then checks
//! that a band of rows or a hedge of a given half width along it neither folds
//! at a corner (an arc no wider than the half width) nor overlaps another
//! stretch of itself: rows that would cross each other are refused.

use core::f64::consts::{FRAC_PI_2, PI};
use std::collections::HashMap;

/// Why a polyline cannot be a centre line; vertices are numbered from 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CurveError {
    /// Fewer than two vertices.
    TooFewVertices,
    /// A coordinate is NaN or infinite.
    NotFinite {
        /// The vertex.
        vertex: usize,
    },
    /// The vertex repeats the one before it (a segment of length 0).
    RepeatedVertex {
        /// The vertex.
        vertex: usize,
    },
    /// The line turns by more than 90° at the vertex: it folds back.
    FoldsBack {
        /// The vertex.
        vertex: usize,
        /// The turn, degrees.
        turn_deg: f64,
    },
    /// The arcs rounding the corners at both ends of the segment that ends
    /// at this vertex do not fit on it: the corner radius is too large.
    NoRoom {
        /// The vertex ending the segment.
        vertex: usize,
    },
    /// The corner at the vertex is rounded by an arc no wider than the
    /// band's half width: the rows on its inside would fold and cross.
    TooTight {
        /// The vertex.
        vertex: usize,
        /// The corner radius, m.
        radius: f64,
        /// The band's half width, m.
        half_width: f64,
    },
    /// Two stretches of the line come closer than the band's width: the
    /// rows (or the hedge) beside them would cross each other.
    Crosses {
        /// The vertex starting the first stretch.
        vertex: usize,
        /// The vertex starting the other stretch.
        other: usize,
    },
}

impl core::fmt::Display for CurveError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            Self::TooFewVertices => write!(f, "needs at least two vertices"),
            Self::NotFinite { vertex } => write!(f, "vertex {vertex} is not finite"),
            Self::RepeatedVertex { vertex } => {
                write!(f, "vertex {vertex} repeats the vertex before it")
            }
            Self::FoldsBack { vertex, turn_deg } => write!(
                f,
                "the line folds back at vertex {vertex} (it turns by {turn_deg:.1}°, more than 90°)"
            ),
            Self::NoRoom { vertex } => write!(
                f,
                "the corner arcs do not fit on the segment ending at vertex {vertex}: use a smaller corner radius or longer segments"
            ),
            Self::TooTight {
                vertex,
                radius,
                half_width,
            } => write!(
                f,
                "the corner at vertex {vertex} (radius {radius} m) is no wider than the half width {half_width} m: the inner rows would fold and cross each other"
            ),
            Self::Crosses { vertex, other } => write!(
                f,
                "the stretches after vertices {vertex} and {other} come closer than the width of the rows: the rows would cross each other"
            ),
        }
    }
}

impl std::error::Error for CurveError {}

/// One piece of a curve: a straight (curvature 0) or a circular arc.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    /// Abscissa of its start along the curve, m.
    s0: f64,
    /// Start point, world frame, m.
    start: [f64; 2],
    /// Heading at its start, rad.
    heading: f64,
    /// Signed curvature, 1/m (positive to the left).
    curvature: f64,
    /// Length, m (≥ 0).
    length: f64,
    /// The polyline vertex this piece belongs to (a straight: the vertex
    /// starting its segment; an arc: its corner).
    vertex: usize,
}

impl Piece {
    /// Position and heading `d` m from the start (beyond its ends too).
    fn pose(&self, d: f64) -> (f64, f64, f64) {
        let (x, y, h, k) = (self.start[0], self.start[1], self.heading, self.curvature);
        if k == 0.0 {
            (x + d * h.cos(), y + d * h.sin(), h)
        } else {
            let e = h + k * d;
            (x + (e.sin() - h.sin()) / k, y - (e.cos() - h.cos()) / k, e)
        }
    }

    /// The distance along the piece (clamped to it) of the point nearest `(x, y)`.
    fn nearest(&self, x: f64, y: f64) -> f64 {
        let (sx, sy) = (self.start[0], self.start[1]);
        if self.curvature == 0.0 {
            let d = (x - sx) * self.heading.cos() + (y - sy) * self.heading.sin();
            return d.clamp(0.0, self.length);
        }
        let r = 1.0 / self.curvature;
        // Centre of the arc, left of the start for a left turn.
        let (cx, cy) = (sx - r * self.heading.sin(), sy + r * self.heading.cos());
        let start_angle = (sy - cy).atan2(sx - cx);
        let angle = (y - cy).atan2(x - cx);
        // Angle swept from the start in the direction of travel, in [0, 2π).
        let swept = (self.curvature.signum() * (angle - start_angle)).rem_euclid(2.0 * PI);
        let d = swept * r.abs();
        if d <= self.length {
            d
        } else {
            // Past the end: the nearer of the two ends.
            let over = d - self.length;
            let under = 2.0 * PI * r.abs() - d;
            if over < under {
                self.length
            } else {
                0.0
            }
        }
    }
}

/// A polyline with corners rounded by arcs of one radius (radius 0: sharp
/// corners, for post rows and fences only).
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pieces: Vec<Piece>,
    length: f64,
    radius: f64,
}

/// The angle wrapped to (−π, π].
fn wrap(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w == -PI {
        PI
    } else {
        w
    }
}

impl Curve {
    /// The curve through `vertices` (world frame, m) with every corner
    /// rounded by an arc of `radius` m (≥ 0): straight from the first vertex,
    /// along each segment, round each corner, straight to the last vertex.
    ///
    /// # Errors
    /// Fewer than two vertices, a non-finite or repeated vertex, a negative
    /// radius (as [`CurveError::NoRoom`] at vertex 0), a corner turning by
    /// more than 90° or arcs that do not fit on their segment.
    pub fn new(vertices: &[[f64; 2]], radius: f64) -> Result<Self, CurveError> {
        if vertices.len() < 2 {
            return Err(CurveError::TooFewVertices);
        }
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(CurveError::NoRoom { vertex: 0 });
        }
        if let Some(vertex) = vertices
            .iter()
            .position(|v| !(v[0].is_finite() && v[1].is_finite()))
        {
            return Err(CurveError::NotFinite { vertex });
        }
        // Segment k runs from vertex k to vertex k + 1.
        let mut headings = Vec::with_capacity(vertices.len() - 1);
        let mut lengths = Vec::with_capacity(vertices.len() - 1);
        for (k, w) in vertices.windows(2).enumerate() {
            let (Some(a), Some(b)) = (w.first(), w.get(1)) else {
                continue;
            };
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let length = dx.hypot(dy);
            if length <= 1e-9 {
                return Err(CurveError::RepeatedVertex { vertex: k + 1 });
            }
            headings.push(dy.atan2(dx));
            lengths.push(length);
        }
        // The turn at each corner (vertex 1 .. n − 2) and the arc's tangent length.
        let mut turns = vec![0.0; vertices.len()];
        let mut tangents = vec![0.0; vertices.len()];
        for i in 1..vertices.len() - 1 {
            let (Some(&h0), Some(&h1)) = (headings.get(i - 1), headings.get(i)) else {
                continue;
            };
            let turn = wrap(h1 - h0);
            if turn.abs() > FRAC_PI_2 + 1e-9 {
                return Err(CurveError::FoldsBack {
                    vertex: i,
                    turn_deg: turn.to_degrees(),
                });
            }
            if let (Some(t), Some(tan)) = (turns.get_mut(i), tangents.get_mut(i)) {
                *t = turn;
                *tan = radius * (0.5 * turn.abs()).tan();
            }
        }
        let mut pieces = Vec::with_capacity(2 * vertices.len());
        let mut s = 0.0;
        for (k, (&h, &length)) in headings.iter().zip(&lengths).enumerate() {
            let t0 = tangents.get(k).copied().unwrap_or(0.0);
            let t1 = tangents.get(k + 1).copied().unwrap_or(0.0);
            let straight = length - t0 - t1;
            if straight < -1e-9 {
                return Err(CurveError::NoRoom { vertex: k + 1 });
            }
            let straight = straight.max(0.0);
            let Some(a) = vertices.get(k) else { continue };
            let start = [a[0] + t0 * h.cos(), a[1] + t0 * h.sin()];
            if straight > 0.0 {
                pieces.push(Piece {
                    s0: s,
                    start,
                    heading: h,
                    curvature: 0.0,
                    length: straight,
                    vertex: k,
                });
                s += straight;
            }
            let turn = turns.get(k + 1).copied().unwrap_or(0.0);
            if radius > 0.0 && turn != 0.0 {
                let corner = [start[0] + straight * h.cos(), start[1] + straight * h.sin()];
                let arc = radius * turn.abs();
                pieces.push(Piece {
                    s0: s,
                    start: corner,
                    heading: h,
                    curvature: turn.signum() / radius,
                    length: arc,
                    vertex: k + 1,
                });
                s += arc;
            } else if turn != 0.0 {
                // A sharp corner: a piece of length 0 carrying the new heading.
                let Some(&next) = headings.get(k + 1) else {
                    continue;
                };
                let Some(v) = vertices.get(k + 1) else {
                    continue;
                };
                pieces.push(Piece {
                    s0: s,
                    start: *v,
                    heading: next,
                    curvature: 0.0,
                    length: 0.0,
                    vertex: k + 1,
                });
            }
        }
        Ok(Self {
            pieces,
            length: s,
            radius,
        })
    }

    /// The length along the curve, m.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The corner radius, m.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The piece holding abscissa `s` (the first before 0, the last past the end).
    fn piece_at(&self, s: f64) -> Option<&Piece> {
        let i = self.pieces.partition_point(|p| p.s0 <= s);
        self.pieces.get(i.saturating_sub(1))
    }

    /// Position and heading `(x, y, heading)` at abscissa `s`; before the
    /// start and past the end, along the straight continuing the end's heading.
    #[must_use]
    pub fn pose_at(&self, s: f64) -> (f64, f64, f64) {
        self.piece_at(s)
            .map_or((f64::NAN, f64::NAN, f64::NAN), |p| p.pose(s - p.s0))
    }

    /// The point `across` m left of the curve (negative: right) at abscissa `s`.
    #[must_use]
    pub fn offset(&self, s: f64, across: f64) -> [f64; 2] {
        let (x, y, h) = self.pose_at(s);
        [x - across * h.sin(), y + across * h.cos()]
    }

    /// The polyline vertex the stretch at abscissa `s` belongs to.
    #[must_use]
    pub fn vertex_at(&self, s: f64) -> usize {
        self.piece_at(s).map_or(0, |p| p.vertex)
    }

    /// The projection of `(x, y)` on the curve: its abscissa and its signed
    /// distance to the curve, positive to the left. `None` before the start
    /// or past the end (the point is not beside the curve).
    #[must_use]
    pub fn project(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let mut best: Option<(f64, f64)> = None;
        for p in &self.pieces {
            let d = p.nearest(x, y);
            let (px, py, _) = p.pose(d);
            let dist = (x - px).hypot(y - py);
            if best.is_none_or(|(_, b)| dist < b) {
                best = Some((p.s0 + d, dist));
            }
        }
        let (s, _) = best?;
        let (px, py, h) = self.pose_at(s);
        let along = (x - px) * h.cos() + (y - py) * h.sin();
        let outside = (s <= 0.0 && along < -1e-12) || (s >= self.length && along > 1e-12);
        let lateral = -(x - px) * h.sin() + (y - py) * h.cos();
        (!outside && lateral.is_finite()).then_some((s, lateral))
    }

    /// Checks that a band `half_width` m to each side of the curve (rows,
    /// a hedge) neither folds at a corner nor overlaps another stretch of
    /// itself.
    ///
    /// # Errors
    /// [`CurveError::TooTight`] at the first corner whose arc (or a sharp
    /// corner) is no wider than `half_width`; [`CurveError::Crosses`] when
    /// two stretches more than π·`half_width` apart along the curve come
    /// closer than 2·`half_width`.
    pub fn check_band(&self, half_width: f64) -> Result<(), CurveError> {
        for p in &self.pieces {
            let corner = p.curvature != 0.0 || (p.length == 0.0 && p.s0 > 0.0);
            if corner && half_width > 0.0 && self.radius <= half_width {
                return Err(CurveError::TooTight {
                    vertex: p.vertex,
                    radius: self.radius,
                    half_width,
                });
            }
        }
        if half_width <= 0.0 || half_width.is_nan() {
            return Ok(());
        }
        // Samples a fraction of the half width apart, hashed in cells of the
        // band's width: only neighbouring cells can hold a point too close.
        let step = (0.25 * half_width).clamp(0.02, 0.5);
        let count = (self.length / step).ceil().min(1e6) as usize;
        let width = 2.0 * half_width;
        let samples: Vec<(f64, [f64; 2])> = (0..=count)
            .map(|i| {
                let s = self.length * i as f64 / count.max(1) as f64;
                let (x, y, _) = self.pose_at(s);
                (s, [x, y])
            })
            .collect();
        let cell_of = |p: [f64; 2]| ((p[0] / width).floor() as i64, (p[1] / width).floor() as i64);
        let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (i, (_, p)) in samples.iter().enumerate() {
            cells.entry(cell_of(*p)).or_default().push(i);
        }
        let apart = PI * half_width + 2.0 * step;
        for (s, p) in &samples {
            let (cx, cy) = cell_of(*p);
            for nx in cx - 1..=cx + 1 {
                for ny in cy - 1..=cy + 1 {
                    let Some(list) = cells.get(&(nx, ny)) else {
                        continue;
                    };
                    for &j in list {
                        let Some((t, q)) = samples.get(j) else {
                            continue;
                        };
                        if t - s > apart && (p[0] - q[0]).hypot(p[1] - q[1]) < width {
                            return Err(CurveError::Crosses {
                                vertex: self.vertex_at(*s),
                                other: self.vertex_at(*t),
                            });
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::FRAC_PI_4;

    #[test]
    fn a_right_angle_rounded_by_an_arc_keeps_its_heading_continuous() {
        // East 10 m, then north 10 m, corner radius 2.
        let c = Curve::new(&[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]], 2.0).unwrap();
        let expected = 8.0 + PI + 8.0;
        assert!((c.length() - expected).abs() < 1e-9, "{}", c.length());
        let (x, y, h) = c.pose_at(8.0 + 0.5 * PI);
        // Half way round the arc centred at (8, 2): 45°.
        assert!((x - (8.0 + 2.0 * (PI / 4.0).sin())).abs() < 1e-9);
        assert!((y - (2.0 - 2.0 * (PI / 4.0).cos())).abs() < 1e-9);
        assert!((h - PI / 4.0).abs() < 1e-9);
        let (x, y, h) = c.pose_at(c.length());
        assert!((x - 10.0).abs() < 1e-9 && (y - 10.0).abs() < 1e-9);
        assert!((h - FRAC_PI_2).abs() < 1e-9);
        // Heading continuous: no step between samples 1 cm apart.
        let mut previous = c.pose_at(0.0).2;
        let mut s = 0.0;
        while s < c.length() {
            s += 0.01;
            let h = c.pose_at(s).2;
            assert!((h - previous).abs() <= 0.01 / 2.0 + 1e-9, "at {s}");
            previous = h;
        }
        // Projection: a point 1 m right of the first straight, one inside the corner.
        let (s, lateral) = c.project(4.0, -1.0).unwrap();
        assert!((s - 4.0).abs() < 1e-9 && (lateral + 1.0).abs() < 1e-9);
        let q = FRAC_PI_4.sin();
        let (s, lateral) = c.project(8.0 + 1.5 * q, 2.0 - 1.5 * q).unwrap();
        assert!((s - 8.0 - FRAC_PI_2).abs() < 1e-9, "{s}");
        assert!((lateral - 0.5).abs() < 1e-9, "{lateral}");
        assert!(c.project(-1.0, 0.0).is_none());
        assert!(c.project(10.0, 11.0).is_none());
        assert_eq!(c.vertex_at(3.0), 0);
        assert_eq!(c.vertex_at(9.0), 1);
    }

    #[test]
    fn bad_polylines_are_refused_with_their_vertex() {
        assert_eq!(
            Curve::new(&[[0.0, 0.0]], 1.0),
            Err(CurveError::TooFewVertices)
        );
        assert_eq!(
            Curve::new(&[[0.0, 0.0], [0.0, 0.0]], 1.0),
            Err(CurveError::RepeatedVertex { vertex: 1 })
        );
        assert!(matches!(
            Curve::new(&[[0.0, 0.0], [10.0, 0.0], [0.0, 1.0]], 1.0),
            Err(CurveError::FoldsBack { vertex: 1, .. })
        ));
        // Two right angles 3 m apart cannot both take 2 m arcs.
        assert_eq!(
            Curve::new(&[[0.0, 0.0], [10.0, 0.0], [10.0, 3.0], [20.0, 3.0]], 2.0),
            Err(CurveError::NoRoom { vertex: 2 })
        );
        assert_eq!(
            Curve::new(&[[0.0, f64::NAN], [1.0, 0.0]], 1.0),
            Err(CurveError::NotFinite { vertex: 0 })
        );
    }

    #[test]
    fn bands_that_fold_or_overlap_are_refused() {
        let corner = Curve::new(&[[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]], 2.0).unwrap();
        assert!(corner.check_band(1.5).is_ok());
        assert!(matches!(
            corner.check_band(2.0),
            Err(CurveError::TooTight { vertex: 1, .. })
        ));
        // A hairpin in two right angles 3 m apart: each corner is wide enough
        // for a 1 m band, but the two legs are 3 m apart, less than 2 × 1.6.
        let hairpin = Curve::new(&[[0.0, 0.0], [20.0, 0.0], [20.0, 3.0], [0.0, 3.0]], 1.5).unwrap();
        assert!(hairpin.check_band(1.0).is_ok());
        assert!(matches!(
            hairpin.check_band(1.6),
            Err(CurveError::TooTight { .. }) | Err(CurveError::Crosses { .. })
        ));
        // Round a field and back along the first side, 1.5 m from it: the
        // corners are wide enough for a 1 m band, but the last stretch comes
        // back within 2 m of the first.
        let round = Curve::new(
            &[
                [0.0, 0.0],
                [20.0, 0.0],
                [20.0, 10.0],
                [0.0, 10.0],
                [0.0, 1.5],
            ],
            2.0,
        )
        .unwrap();
        assert!(round.check_band(0.7).is_ok());
        assert_eq!(
            round.check_band(1.0),
            Err(CurveError::Crosses {
                vertex: 0,
                other: 3
            })
        );
        // Sharp corners are fine for posts (no band) but not for rows.
        let sharp = Curve::new(&[[0.0, 0.0], [5.0, 0.0], [5.0, 5.0]], 0.0).unwrap();
        assert!(sharp.check_band(0.0).is_ok());
        assert!(sharp.check_band(0.1).is_err());
        assert!((sharp.length() - 10.0).abs() < 1e-12);
        let (x, y, h) = sharp.pose_at(7.0);
        assert!((x - 5.0).abs() < 1e-12 && (y - 2.0).abs() < 1e-12);
        assert!((h - FRAC_PI_2).abs() < 1e-12);
    }
}
