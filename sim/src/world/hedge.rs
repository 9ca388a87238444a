//! Hedges, walls and post rows: the structures a horizontal LiDAR sees and
//! edge following follows (Pierre 2022, section 2.2 and experiment 1).
//!
//! A hedge is a strip of vegetation with ragged faces, cut by gaps; a wall is
//! a segment; a post row is a line of circles. Everything is generated in the
//! world frame (x east, y north, metres) from a spec and a caller's random
//! number generator, so a seed reproduces a world.

use rand::Rng;

use super::curve::Curve;

/// A straight obstacle boundary from `a` to `b`, world frame, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// One end.
    pub a: [f64; 2],
    /// The other end.
    pub b: [f64; 2],
}

/// A round obstacle (a post, a trunk), world frame, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    /// Centre.
    pub center: [f64; 2],
    /// Radius, > 0.
    pub radius: f64,
}

/// A spec that cannot be built: the field and the reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InvalidSpec {
    /// The offending field.
    pub field: &'static str,
    /// Why it is refused.
    pub reason: &'static str,
}

impl core::fmt::Display for InvalidSpec {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "invalid `{}`: {}", self.field, self.reason)
    }
}

impl std::error::Error for InvalidSpec {}

fn check(ok: bool, field: &'static str, reason: &'static str) -> Result<(), InvalidSpec> {
    if ok {
        Ok(())
    } else {
        Err(InvalidSpec { field, reason })
    }
}

/// A straight hedge: a strip of `thickness` metres along a centre line from
/// `start`, heading `heading`, `length` metres long, whose two faces are
/// polylines with a vertex every `vertex_spacing` metres, each vertex moved
/// across the hedge by a uniform draw in ±`raggedness`. `gaps` are
/// intervals `[from, to]` of along-hedge distance with no hedge.
#[derive(Debug, Clone, PartialEq)]
pub struct HedgeSpec {
    /// Start of the centre line, world frame, metres.
    pub start: [f64; 2],
    /// Direction of the centre line, radians, counter-clockwise from east.
    pub heading: f64,
    /// Length along the centre line, metres, > 0.
    pub length: f64,
    /// Distance between the two nominal faces, metres, > 0.
    pub thickness: f64,
    /// Largest displacement of a face vertex across the hedge, metres,
    /// in [0, thickness / 2).
    pub raggedness: f64,
    /// Along-hedge distance between face vertices, metres, > 0.
    pub vertex_spacing: f64,
    /// Along-hedge intervals `[from, to]` without hedge, metres.
    pub gaps: Vec<[f64; 2]>,
    /// The centre line as a rounded polyline (`None`: straight from `start`
    /// along `heading`). With it, `start`, `heading` and `length` are its
    /// start, initial heading and length.
    pub centre: Option<Curve>,
}

/// Which face of a hedge, looking along its heading.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Face {
    /// The face on the left of the heading.
    Left,
    /// The face on the right of the heading.
    Right,
}

impl HedgeSpec {
    /// Checks the spec: finite values, positive length, thickness and vertex
    /// spacing, raggedness in [0, thickness/2), gaps ordered within the hedge.
    pub fn validate(&self) -> Result<(), InvalidSpec> {
        check(
            self.start.iter().all(|v| v.is_finite()),
            "start",
            "must be finite",
        )?;
        check(self.heading.is_finite(), "heading", "must be finite")?;
        check(
            self.length.is_finite() && self.length > 0.0,
            "length",
            "must be finite and > 0",
        )?;
        check(
            self.thickness.is_finite() && self.thickness > 0.0,
            "thickness",
            "must be finite and > 0",
        )?;
        check(
            self.raggedness >= 0.0 && self.raggedness < 0.5 * self.thickness,
            "raggedness",
            "must be in [0, thickness / 2)",
        )?;
        check(
            self.vertex_spacing.is_finite() && self.vertex_spacing > 0.0,
            "vertex_spacing",
            "must be finite and > 0",
        )?;
        check(
            self.gaps
                .iter()
                .all(|g| g[0].is_finite() && g[1].is_finite() && g[0] < g[1]),
            "gaps",
            "each gap must be [from, to] with from < to",
        )
    }

    /// The world point at along-hedge distance `along` and signed offset
    /// `across` (positive to the left of the heading) from the centre line.
    #[must_use]
    pub fn point(&self, along: f64, across: f64) -> [f64; 2] {
        if let Some(curve) = &self.centre {
            return curve.offset(along, across);
        }
        let (c, s) = (self.heading.cos(), self.heading.sin());
        [
            self.start[0] + along * c - across * s,
            self.start[1] + along * s + across * c,
        ]
    }

    /// The nominal (not ragged) line of a face: its two ends, gaps ignored.
    /// This is the ground truth an edge follower's offset is measured from.
    #[must_use]
    pub fn nominal_face(&self, face: Face) -> Segment {
        let across = match face {
            Face::Left => 0.5 * self.thickness,
            Face::Right => -0.5 * self.thickness,
        };
        Segment {
            a: self.point(0.0, across),
            b: self.point(self.length, across),
        }
    }

    /// The along-hedge intervals that carry hedge: `[0, length]` minus the gaps.
    #[must_use]
    pub fn pieces(&self) -> Vec<[f64; 2]> {
        let mut gaps: Vec<[f64; 2]> = self.gaps.clone();
        gaps.sort_by(|a, b| a[0].total_cmp(&b[0]));
        let mut pieces = Vec::new();
        let mut from = 0.0;
        for g in gaps {
            let to = g[0].min(self.length);
            if to > from {
                pieces.push([from, to]);
            }
            from = from.max(g[1]);
        }
        if self.length > from {
            pieces.push([from, self.length]);
        }
        pieces
    }

    /// The outline segments of the hedge: for each piece between gaps, its
    /// two ragged faces and its two end caps (a closed polygon).
    pub fn generate(&self, rng: &mut impl Rng) -> Result<Vec<Segment>, InvalidSpec> {
        self.validate()?;
        let half = 0.5 * self.thickness;
        let mut out = Vec::new();
        for [a0, a1] in self.pieces() {
            let mut left = Vec::new();
            let mut right = Vec::new();
            let mut along = a0;
            loop {
                let jitter_l = self.jitter(rng);
                let jitter_r = self.jitter(rng);
                left.push(self.point(along, half + jitter_l));
                right.push(self.point(along, -half + jitter_r));
                if along >= a1 {
                    break;
                }
                along = (along + self.vertex_spacing).min(a1);
            }
            for face in [&left, &right] {
                out.extend(face.windows(2).filter_map(|w| match w {
                    [a, b] => Some(Segment { a: *a, b: *b }),
                    _ => None,
                }));
            }
            if let (Some(l0), Some(r0), Some(l1), Some(r1)) =
                (left.first(), right.first(), left.last(), right.last())
            {
                out.push(Segment { a: *l0, b: *r0 });
                out.push(Segment { a: *l1, b: *r1 });
            }
        }
        Ok(out)
    }

    fn jitter(&self, rng: &mut impl Rng) -> f64 {
        if self.raggedness > 0.0 {
            rng.random_range(-self.raggedness..=self.raggedness)
        } else {
            0.0
        }
    }
}

/// Where a pose lies relative to the line an edge follower keeps at a
/// desired distance from a hedge's nominal face (ground truth of edge
/// following; [`HedgeSpec::offset_line_position`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffsetLinePosition {
    /// Along-hedge distance of the pose's projection on the centre line, metres.
    pub along: f64,
    /// Signed distance of the pose to the offset line, metres, positive to
    /// the left of the direction of travel (the library's lateral error).
    pub lateral: f64,
    /// Heading of the pose minus the offset line's heading in the direction
    /// of travel, radians, in (−π, π].
    pub angular: f64,
}

impl HedgeSpec {
    /// Whether the along-hedge distance `along` lies on the hedge: within
    /// `[0, length]` and strictly inside no gap.
    #[must_use]
    pub fn is_present(&self, along: f64) -> bool {
        (0.0..=self.length).contains(&along)
            && !self.gaps.iter().any(|g| along > g[0] && along < g[1])
    }

    /// The ground truth of edge following for a robot at world pose
    /// `(x, y, heading)` keeping `offset` metres from this hedge: its
    /// position relative to the nominal face on its side
    /// ([`HedgeSpec::nominal_face`]) moved `offset` metres away from the
    /// hedge, measured in the direction of travel (the along-hedge direction
    /// that makes less than 90° with `heading`). `None` where the hedge is
    /// absent (before its start, past its end, in a gap).
    #[must_use]
    pub fn offset_line_position(
        &self,
        x: f64,
        y: f64,
        heading: f64,
        offset: f64,
    ) -> Option<OffsetLinePosition> {
        if let Some(curve) = &self.centre {
            return self.curved_offset_line_position(curve, (x, y, heading), offset);
        }
        let (c, s) = (self.heading.cos(), self.heading.sin());
        let (dx, dy) = (x - self.start[0], y - self.start[1]);
        let along = dx * c + dy * s;
        let across = -dx * s + dy * c;
        if !self.is_present(along) {
            return None;
        }
        // The face on the robot's side, and the offset line beyond it.
        let (face, away) = if across >= 0.0 {
            (Face::Left, 1.0)
        } else {
            (Face::Right, -1.0)
        };
        let f = self.nominal_face(face);
        let (ux, uy) = (f.b[0] - f.a[0], f.b[1] - f.a[1]);
        let norm = ux.hypot(uy);
        // Signed distance to the face line, positive left of the hedge's heading.
        let to_face = (-(x - f.a[0]) * uy + (y - f.a[1]) * ux) / norm;
        let lateral = to_face - away * offset;
        let relative = wrap(heading - self.heading);
        let (lateral, angular) = if relative.abs() <= core::f64::consts::FRAC_PI_2 {
            (lateral, relative)
        } else {
            (-lateral, wrap(relative - core::f64::consts::PI))
        };
        (lateral.is_finite() && angular.is_finite()).then_some(OffsetLinePosition {
            along,
            lateral,
            angular,
        })
    }
}

impl HedgeSpec {
    /// [`Self::offset_line_position`] for a hedge along a curve: the pose's
    /// projection on the centre line gives the along-hedge distance, the
    /// side and the line's heading there.
    fn curved_offset_line_position(
        &self,
        curve: &Curve,
        (x, y, heading): (f64, f64, f64),
        offset: f64,
    ) -> Option<OffsetLinePosition> {
        let (along, across) = curve.project(x, y)?;
        if !self.is_present(along) {
            return None;
        }
        let away = if across >= 0.0 { 1.0 } else { -1.0 };
        let lateral = across - away * (0.5 * self.thickness + offset);
        let line_heading = curve.pose_at(along).2;
        let relative = wrap(heading - line_heading);
        let (lateral, angular) = if relative.abs() <= core::f64::consts::FRAC_PI_2 {
            (lateral, relative)
        } else {
            (-lateral, wrap(relative - core::f64::consts::PI))
        };
        (lateral.is_finite() && angular.is_finite()).then_some(OffsetLinePosition {
            along,
            lateral,
            angular,
        })
    }

    /// Signed distance of `(x, y)` from the centre line, metres, positive
    /// to the left of the heading (for a curve: of the nearest point's).
    #[must_use]
    pub fn across(&self, x: f64, y: f64) -> f64 {
        match &self.centre {
            Some(curve) => curve.project(x, y).map_or_else(
                || {
                    // Beyond an end: the side of the nearer end's tangent.
                    let (px, py, h) = curve.pose_at(0.0);
                    -(x - px) * h.sin() + (y - py) * h.cos()
                },
                |(_, lateral)| lateral,
            ),
            None => {
                let (c, sn) = (self.heading.cos(), self.heading.sin());
                -(x - self.start[0]) * sn + (y - self.start[1]) * c
            }
        }
    }

    /// The line `across` m from the centre line between the along-hedge
    /// distances `a` and `b`: its two ends for a straight hedge, a point
    /// every 0.5 m for a curved one.
    #[must_use]
    pub fn line(&self, a: f64, b: f64, across: f64) -> Vec<[f64; 2]> {
        let n = if self.centre.is_some() {
            ((b - a) / 0.5).ceil().clamp(1.0, 1e5) as usize
        } else {
            1
        };
        (0..=n)
            .map(|k| self.point(a + (b - a) * k as f64 / n as f64, across))
            .collect()
    }
}

/// `angle` wrapped to (−π, π].
fn wrap(angle: f64) -> f64 {
    fieldguide::Radians::new(angle).map_or(f64::NAN, |a| {
        fieldguide::geometry::units::wrap_angle(a).get()
    })
}

/// A row of posts: `count` circles of `radius` along a line from `start`
/// heading `heading`, `spacing` metres apart, each moved along the row by a
/// uniform draw in ±`spacing_noise`, and each missing with probability
/// `missing`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PostRowSpec {
    /// Centre of the first post, world frame, metres.
    pub start: [f64; 2],
    /// Direction of the row, radians.
    pub heading: f64,
    /// Number of post positions.
    pub count: usize,
    /// Distance between post positions, metres, > 0.
    pub spacing: f64,
    /// Post radius, metres, > 0.
    pub radius: f64,
    /// Largest displacement of a post along the row, metres, in [0, spacing / 2).
    pub spacing_noise: f64,
    /// Probability that a post is missing, in [0, 1].
    pub missing: f64,
}

impl PostRowSpec {
    /// The posts, after checking the spec.
    pub fn generate(&self, rng: &mut impl Rng) -> Result<Vec<Circle>, InvalidSpec> {
        check(
            self.start.iter().all(|v| v.is_finite()) && self.heading.is_finite(),
            "start",
            "start and heading must be finite",
        )?;
        check(
            self.spacing.is_finite() && self.spacing > 0.0,
            "spacing",
            "must be finite and > 0",
        )?;
        check(
            self.radius.is_finite() && self.radius > 0.0,
            "radius",
            "must be finite and > 0",
        )?;
        check(
            self.spacing_noise >= 0.0 && self.spacing_noise < 0.5 * self.spacing,
            "spacing_noise",
            "must be in [0, spacing / 2)",
        )?;
        check(
            (0.0..=1.0).contains(&self.missing),
            "missing",
            "must be a probability in [0, 1]",
        )?;
        let (c, s) = (self.heading.cos(), self.heading.sin());
        let mut out = Vec::with_capacity(self.count);
        let mut along = 0.0;
        for _ in 0..self.count {
            let shift = if self.spacing_noise > 0.0 {
                rng.random_range(-self.spacing_noise..=self.spacing_noise)
            } else {
                0.0
            };
            let present = self.missing <= 0.0 || !rng.random_bool(self.missing);
            if present {
                let a = along + shift;
                out.push(Circle {
                    center: [self.start[0] + a * c, self.start[1] + a * s],
                    radius: self.radius,
                });
            }
            along += self.spacing;
        }
        Ok(out)
    }
}

/// Posts of `radius` m every `spacing` m along `curve`, from its start
/// (a row of trunks or posts): post `k` at abscissa `k · spacing`.
#[must_use]
pub fn posts_along(curve: &Curve, spacing: f64, radius: f64) -> Vec<Circle> {
    if !(spacing > 0.0 && spacing.is_finite()) {
        return Vec::new();
    }
    let count = (curve.length() / spacing + 1e-9).floor().min(1e6) as usize;
    (0..=count)
        .map(|k| {
            let (x, y, _) = curve.pose_at(k as f64 * spacing);
            Circle {
                center: [x, y],
                radius,
            }
        })
        .collect()
}

/// A fence along the polyline `vertices`: a post of `radius` m at every
/// vertex and evenly between them, at most `spacing` m apart; with `wall`,
/// also the segments between the vertices (a thin wall a LiDAR always hits;
/// without it, wires a LiDAR misses: only the posts are seen).
#[must_use]
pub fn fence(vertices: &[[f64; 2]], spacing: f64, radius: f64, wall: bool) -> Obstacles {
    let mut out = Obstacles::default();
    if let Some(first) = vertices.first() {
        out.circles.push(Circle {
            center: *first,
            radius,
        });
    }
    for w in vertices.windows(2) {
        let (Some(a), Some(b)) = (w.first(), w.get(1)) else {
            continue;
        };
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = (length / spacing).ceil().clamp(1.0, 1e6) as usize;
        for k in 1..=n {
            let t = k as f64 / n as f64;
            out.circles.push(Circle {
                center: [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
                radius,
            });
        }
        if wall {
            out.segments.push(Segment { a: *a, b: *b });
        } else {
            out.wires.push(Segment { a: *a, b: *b });
        }
    }
    out
}

/// Everything a horizontal LiDAR can hit.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Obstacles {
    /// Straight boundaries: hedge outlines and walls.
    pub segments: Vec<Segment>,
    /// Posts and trunks.
    pub circles: Vec<Circle>,
    /// Fence wires between posts: drawn in the plots, never hit by a LiDAR.
    pub wires: Vec<Segment>,
}

impl Obstacles {
    /// Adds a wall from `a` to `b`.
    pub fn add_wall(&mut self, a: [f64; 2], b: [f64; 2]) -> Result<(), InvalidSpec> {
        check(
            a.iter().chain(&b).all(|v| v.is_finite()),
            "wall",
            "ends must be finite",
        )?;
        self.segments.push(Segment { a, b });
        Ok(())
    }

    /// Adds a generated hedge.
    pub fn add_hedge(&mut self, spec: &HedgeSpec, rng: &mut impl Rng) -> Result<(), InvalidSpec> {
        let segments = spec.generate(rng)?;
        self.segments.extend(segments);
        Ok(())
    }

    /// Adds the obstacles of `other`.
    pub fn extend(&mut self, other: Obstacles) {
        self.segments.extend(other.segments);
        self.circles.extend(other.circles);
        self.wires.extend(other.wires);
    }

    /// Adds a generated post row.
    pub fn add_post_row(
        &mut self,
        spec: &PostRowSpec,
        rng: &mut impl Rng,
    ) -> Result<(), InvalidSpec> {
        let posts = spec.generate(rng)?;
        self.circles.extend(posts);
        Ok(())
    }

    /// The distance along the ray from `origin` in the unit direction `dir`
    /// to the nearest obstacle, if one is hit within `max_range`: every
    /// obstacle is tested (the reference the spatial index is checked against).
    #[must_use]
    pub fn cast_brute(&self, origin: [f64; 2], dir: [f64; 2], max_range: f64) -> Option<f64> {
        let seg = self
            .segments
            .iter()
            .filter_map(|s| ray_segment(origin, dir, s));
        let circ = self
            .circles
            .iter()
            .filter_map(|c| ray_circle(origin, dir, c));
        seg.chain(circ)
            .filter(|t| *t <= max_range)
            .min_by(f64::total_cmp)
    }
}

/// Distance `t ≥ 0` along the ray `origin + t dir` (unit `dir`) to segment
/// `s`, if the ray crosses it. A ray along a segment (parallel) misses it.
#[must_use]
pub fn ray_segment(origin: [f64; 2], dir: [f64; 2], s: &Segment) -> Option<f64> {
    let e = [s.b[0] - s.a[0], s.b[1] - s.a[1]];
    let denom = dir[0] * e[1] - dir[1] * e[0];
    if denom.abs() < 1e-15 {
        return None;
    }
    let w = [s.a[0] - origin[0], s.a[1] - origin[1]];
    let t = (w[0] * e[1] - w[1] * e[0]) / denom;
    let u = (w[0] * dir[1] - w[1] * dir[0]) / denom;
    (t >= 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
}

/// Distance `t ≥ 0` along the ray (unit `dir`) to the first crossing of
/// circle `c`'s boundary, if any.
#[must_use]
pub fn ray_circle(origin: [f64; 2], dir: [f64; 2], c: &Circle) -> Option<f64> {
    let m = [origin[0] - c.center[0], origin[1] - c.center[1]];
    let b = m[0] * dir[0] + m[1] * dir[1];
    let cc = m[0] * m[0] + m[1] * m[1] - c.radius * c.radius;
    let disc = b * b - cc;
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let (t0, t1) = (-b - root, -b + root);
    if t0 >= 0.0 {
        Some(t0)
    } else if t1 >= 0.0 {
        Some(t1)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    fn hedge() -> HedgeSpec {
        HedgeSpec {
            start: [0.0, 2.0],
            heading: 0.0,
            length: 20.0,
            thickness: 1.0,
            raggedness: 0.1,
            vertex_spacing: 0.2,
            gaps: vec![[8.0, 10.0]],
            centre: None,
        }
    }

    #[test]
    fn a_gap_gives_no_return() {
        let mut obstacles = Obstacles::default();
        obstacles
            .add_hedge(&hedge(), &mut StdRng::seed_from_u64(1))
            .unwrap();
        // Looking north (across the hedge) from the robot's side.
        let through_gap = obstacles.cast_brute([9.0, 0.0], [0.0, 1.0], 30.0);
        assert_eq!(through_gap, None);
        let at_hedge = obstacles.cast_brute([5.0, 0.0], [0.0, 1.0], 30.0).unwrap();
        // The near face is at y = 1.5 ± 0.1.
        assert!((at_hedge - 1.5).abs() <= 0.1 + 1e-12);
        // Two pieces, each a closed outline.
        assert_eq!(hedge().pieces(), vec![[0.0, 8.0], [10.0, 20.0]]);
    }

    #[test]
    fn same_seed_same_hedge_and_bad_specs_name_their_field() {
        let a = hedge().generate(&mut StdRng::seed_from_u64(7)).unwrap();
        let b = hedge().generate(&mut StdRng::seed_from_u64(7)).unwrap();
        let c = hedge().generate(&mut StdRng::seed_from_u64(8)).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
        let bad = HedgeSpec {
            raggedness: 0.6,
            ..hedge()
        };
        assert_eq!(
            bad.generate(&mut StdRng::seed_from_u64(1))
                .unwrap_err()
                .field,
            "raggedness"
        );
        let posts = PostRowSpec {
            start: [0.0, 0.0],
            heading: 0.0,
            count: 10,
            spacing: 1.0,
            radius: 0.05,
            spacing_noise: 0.0,
            missing: 2.0,
        };
        assert_eq!(
            posts
                .generate(&mut StdRng::seed_from_u64(1))
                .unwrap_err()
                .field,
            "missing"
        );
    }

    #[test]
    fn the_offset_line_is_the_nominal_face_moved_away_from_the_hedge() {
        // Near (right) face at y = 1.5, the offset line 1.4 m south at y = 0.1.
        let h = hedge();
        let p = h.offset_line_position(5.0, 0.0, 0.1, 1.4).unwrap();
        assert!((p.along - 5.0).abs() < 1e-12);
        assert!((p.lateral + 0.1).abs() < 1e-12, "{p:?}");
        assert!((p.angular - 0.1).abs() < 1e-12);
        // Driving west on the north side (face y = 2.5, line y = 3.9): 0.2 m
        // north of the line is 0.2 m to the right of the travel direction.
        let q = h.offset_line_position(4.0, 4.1, 3.0, 1.4).unwrap();
        assert!((q.lateral + 0.2).abs() < 1e-12, "{q:?}");
        assert!((q.angular - (3.0 - core::f64::consts::PI)).abs() < 1e-12);
        // Nothing in the gap, before the start or past the end.
        assert!(h.offset_line_position(9.0, 0.0, 0.0, 1.4).is_none());
        assert!(h.offset_line_position(-0.1, 0.0, 0.0, 1.4).is_none());
        assert!(h.offset_line_position(20.1, 0.0, 0.0, 1.4).is_none());
        assert!(h.is_present(8.0) && !h.is_present(8.01) && h.is_present(10.01));
    }

    #[test]
    fn rays_hit_walls_and_posts_at_known_distances() {
        let mut obstacles = Obstacles::default();
        obstacles.add_wall([5.0, -10.0], [5.0, 10.0]).unwrap();
        obstacles
            .add_post_row(
                &PostRowSpec {
                    start: [2.0, 3.0],
                    heading: 0.0,
                    count: 3,
                    spacing: 1.0,
                    radius: 0.1,
                    spacing_noise: 0.0,
                    missing: 0.0,
                },
                &mut StdRng::seed_from_u64(0),
            )
            .unwrap();
        let t = obstacles.cast_brute([0.0, 0.0], [1.0, 0.0], 30.0).unwrap();
        assert!((t - 5.0).abs() < 1e-12);
        let t = obstacles.cast_brute([3.0, 0.0], [0.0, 1.0], 30.0).unwrap();
        assert!((t - 2.9).abs() < 1e-12);
        // Beyond the range: nothing.
        assert_eq!(obstacles.cast_brute([0.0, 0.0], [1.0, 0.0], 4.0), None);
    }
}
