//! Reference paths built from waypoints and the Frénet projection of a pose.
//!
//! Pierre 2022, section 2.1: the robot is modelled in a Frénet frame at the
//! point of the reference trajectory Γ closest to the controlled point O, where
//! the curvilinear abscissa s, the lateral error y, the angular deviation θ̃ and
//! the curvature c(s) are defined. This module builds Γ from recorded
//! waypoints (`spec/geometry.md`, PATH-*) and computes those quantities
//! (FRENET-*).
//!
//! Geometry of a path:
//! - positions and s are those of the polyline through the waypoints;
//! - heading and curvature are smoothed over a window `w` (default 1 m) so that
//!   c(s) stays meaningful when waypoints carry centimetre GNSS noise;
//! - before s = 0 and after s = L the path continues straight along its end
//!   tangents, with zero curvature; the curvature ahead of the robot,
//!   c(s + v T), holds the curvature of the nearer end there, so that it does
//!   not jump when s + v T crosses an end (FRENET-CURVATURE).

use heapless::Vec;

use super::frame::{Point2, Pose2, World};
use super::tracking::TrackingError;
use super::units::{wrap_raw, Curvature, Meters, Radians};
use crate::error::Precondition;

/// Consecutive waypoints closer than this (metres) are duplicates and dropped
/// (`spec/geometry.md`, PATH-WAYPOINTS). One millimetre is well below the
/// precision of RTK GNSS (about 1.5 cm), so dropping such points loses nothing.
pub const MIN_WAYPOINT_SPACING: f64 = 1e-3;

/// The largest magnitude of a waypoint coordinate, metres (`spec/geometry.md`,
/// PATH-RANGE): a local tangent plane 20 000 km across. Differences of such
/// coordinates are exact to 2e−9 m, far below [`MIN_WAYPOINT_SPACING`].
pub const MAX_PATH_COORDINATE: f64 = 1e7;

/// The longest path, metres (PATH-RANGE). Below it the spacing of `f64` is at
/// most 1.2e−7 m, so each kept waypoint, at least [`MIN_WAYPOINT_SPACING`]
/// from the last one, adds to s and s increases strictly along the path.
pub const MAX_PATH_LENGTH: f64 = 1e9;

/// A chord shorter than this (metres) has no usable direction; the heading
/// then falls back to the direction of the polyline segment at s.
const MIN_CHORD: f64 = 1e-9;

/// Configuration of a [`ReferencePath`], validated by
/// [`ReferencePath::from_waypoints`] (`spec/geometry.md`, PATH-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathConfig {
    /// Length w of the smoothing window for heading and curvature, metres, > 0
    /// (`spec/geometry.md`, PATH-HEADING and PATH-CURVATURE).
    ///
    /// The default, 1 m, keeps the heading noise near √2·σ/w ≈ 0.02 rad and the
    /// curvature noise near √6·σ/w² ≈ 0.04 1/m for σ = 1.5 cm GNSS noise, while
    /// blurring curvature changes over only about 2w = 2 m, short against the
    /// ≈ 9 m of a 3 m-radius U-turn.
    pub smoothing_window: Meters,
}

impl PathConfig {
    /// The default smoothing window, metres.
    pub const DEFAULT_SMOOTHING_WINDOW: f64 = 1.0;

    /// A configuration with the given smoothing window; a window ≤ 0 is the
    /// `PATH-CONFIG` error.
    //= spec/geometry.md#path-config-path-configuration
    //# The smoothing window w MUST be strictly positive; a path configuration
    //# where it is not MUST be refused with the `PATH-CONFIG` error.
    pub fn new(smoothing_window: Meters) -> Result<Self, Precondition> {
        if smoothing_window.get() > 0.0 {
            Ok(Self { smoothing_window })
        } else {
            Err(Precondition::new(
                "PATH-CONFIG",
                "smoothing window must be > 0",
            ))
        }
    }
}

impl Default for PathConfig {
    fn default() -> Self {
        Self {
            smoothing_window: Meters(Self::DEFAULT_SMOOTHING_WINDOW),
        }
    }
}

/// One stored vertex of a [`ReferencePath`], in the `World` frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathVertex {
    /// Position of the waypoint, metres, `World` frame.
    pub position: Point2<World>,
    /// Curvilinear abscissa s of the vertex: polyline length from the first
    /// waypoint, metres.
    pub s: Meters,
    /// Smoothed heading of the path at the vertex, radians in (−π, π].
    pub heading: Radians,
    /// Smoothed curvature c(s) at the vertex, 1/m, positive for a left turn.
    pub curvature: Curvature,
}

/// Where the closest point lies relative to the recorded path
/// (`spec/geometry.md`, FRENET-ENDS).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PathPosition {
    /// Before the first waypoint: s < 0, on the backward extension of the start tangent.
    BeforeStart,
    /// On the recorded path: 0 ≤ s ≤ L.
    Within,
    /// After the last waypoint: s > L, on the forward extension of the end tangent.
    PastEnd,
}

/// The Frénet error of a pose relative to a [`ReferencePath`] (Pierre 2022,
/// section 2.1; `spec/geometry.md`, FRENET-*).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrenetError {
    /// Curvilinear abscissa of the closest point, metres (< 0 or > L past the ends).
    pub s: Meters,
    /// Signed lateral error, metres, > 0 when the robot is left of the path.
    pub y: Meters,
    /// θ̃ = robot heading − path heading at s, radians, wrapped to (−π, π].
    pub angular_deviation: Radians,
    /// c(s), 1/m, positive for a left turn.
    pub curvature: Curvature,
    /// c(s + lookahead), 1/m (lookahead = v T, chosen by the caller; Pierre 2022 eq. 7).
    pub curvature_ahead: Curvature,
    /// Whether the closest point is before, on or after the recorded path.
    pub position: PathPosition,
}

impl FrenetError {
    /// The error as the control laws take it ([`TrackingError`]).
    #[must_use]
    pub const fn tracking_error(&self) -> TrackingError {
        TrackingError {
            y: self.y,
            angular_deviation: self.angular_deviation,
            curvature: self.curvature,
            curvature_ahead: self.curvature_ahead,
        }
    }
}

impl From<FrenetError> for TrackingError {
    fn from(e: FrenetError) -> Self {
        e.tracking_error()
    }
}

/// A reference path Γ of at most `N` vertices in the `World` frame, built from
/// waypoints (Pierre 2022, section 2.1; `spec/geometry.md`).
///
/// Invariants: at least 2 vertices, consecutive vertices at least
/// [`MIN_WAYPOINT_SPACING`] apart, coordinates within
/// [`MAX_PATH_COORDINATE`], L at most [`MAX_PATH_LENGTH`], s strictly
/// increasing from 0 to L.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferencePath<const N: usize> {
    vertices: Vec<PathVertex, N>,
    config: PathConfig,
    length: f64,
    /// Built by [`ReferencePath::from_exact`]: heading and curvature are the
    /// vertices' own, not smoothed from positions.
    exact: bool,
}

/// `x` limited to `[lo, hi]` (`lo ≤ hi`); never panics, unlike `f64::clamp`.
fn clamp(x: f64, lo: f64, hi: f64) -> f64 {
    x.max(lo).min(hi)
}

/// The closest point found so far during a projection.
#[derive(Clone, Copy)]
struct Candidate {
    distance_sq: f64,
    s: f64,
    x: f64,
    y: f64,
    /// Direction used for the side of the robot (FRENET-LATERAL).
    side: Side,
}

/// The path direction that decides the side of the robot: a vector (segment or
/// extension; only the sign of the cross product matters) or, at a vertex, the
/// smoothed heading there, turned into a vector only for the winning candidate.
#[derive(Clone, Copy)]
enum Side {
    Vector(f64, f64),
    Heading(f64),
}

impl<const N: usize> ReferencePath<N> {
    /// Builds a path from waypoints in the `World` frame.
    ///
    /// Consecutive waypoints closer than [`MIN_WAYPOINT_SPACING`] to the last
    /// kept one are dropped. Errors: a smoothing window ≤ 0 (`PATH-CONFIG`),
    /// a waypoint coordinate beyond ±[`MAX_PATH_COORDINATE`] or a length
    /// beyond [`MAX_PATH_LENGTH`] (`PATH-RANGE`), fewer than 2 distinct
    /// waypoints (`PATH-WAYPOINTS`), more than `N` distinct waypoints
    /// (`PATH-CAPACITY`).
    //= spec/geometry.md#path-waypoints-distinct-waypoints
    //# A waypoint closer than `MIN_WAYPOINT_SPACING` (1 mm) to the last kept
    //# waypoint MUST be dropped, not reported as an error.
    //= spec/geometry.md#path-waypoints-distinct-waypoints
    //# A path MUST be refused with the `PATH-WAYPOINTS` error when fewer than 2
    //# distinct waypoints remain.
    //= spec/geometry.md#path-capacity-fixed-capacity
    //# A path of capacity N MUST be refused with the `PATH-CAPACITY` error when
    //# more than N distinct waypoints are given.
    //= spec/geometry.md#path-arc-length-curvilinear-abscissa
    //# The curvilinear abscissa s of a vertex MUST be the length of the polyline
    //# through the kept waypoints from the first one to that vertex.
    //= spec/geometry.md#path-range-coordinates-and-length-within-range
    //# A path MUST be refused with the `PATH-RANGE` error when a waypoint has a
    //# coordinate of magnitude above `MAX_PATH_COORDINATE` (1e7 m) or when its
    //# length L exceeds `MAX_PATH_LENGTH` (1e9 m).
    //= spec/geometry.md#path-range-coordinates-and-length-within-range
    //# The abscissae of consecutive vertices of a path MUST increase strictly.
    pub fn from_waypoints(
        points: &[Point2<World>],
        config: PathConfig,
    ) -> Result<Self, Precondition> {
        let config = PathConfig::new(config.smoothing_window)?;
        let mut vertices: Vec<PathVertex, N> = Vec::new();
        let mut last: Option<(Point2<World>, f64)> = None;
        for &p in points {
            if libm::fabs(p.x()) > MAX_PATH_COORDINATE || libm::fabs(p.y()) > MAX_PATH_COORDINATE {
                return Err(Precondition::new(
                    "PATH-RANGE",
                    "waypoint coordinate beyond 1e7 m",
                ));
            }
            let s = match last {
                None => 0.0,
                Some((q, s_q)) => {
                    // Within the coordinate range: at most 2.9e7 m, never overflows.
                    let d = q.distance_to(p)?.get();
                    if d < MIN_WAYPOINT_SPACING {
                        continue;
                    }
                    let s = s_q + d;
                    if s > MAX_PATH_LENGTH {
                        return Err(Precondition::new("PATH-RANGE", "path length beyond 1e9 m"));
                    }
                    s
                }
            };
            let vertex = PathVertex {
                position: p,
                s: Meters(s),
                heading: Radians::ZERO,
                curvature: Curvature::ZERO,
            };
            if vertices.push(vertex).is_err() {
                return Err(Precondition::new(
                    "PATH-CAPACITY",
                    "more distinct waypoints than the path capacity N",
                ));
            }
            last = Some((p, s));
        }
        let length = match last {
            Some((_, s)) if vertices.len() >= 2 => s,
            _ => {
                return Err(Precondition::new(
                    "PATH-WAYPOINTS",
                    "fewer than 2 distinct waypoints",
                ))
            }
        };
        let mut path = Self {
            vertices,
            config,
            length,
            exact: false,
        };
        let mut i = 0_usize;
        while let Some(v) = path.vertices.get(i) {
            let s = v.s.get();
            let heading = path.smoothed_heading(s);
            let curvature = path.smoothed_curvature(s);
            if let Some(v) = path.vertices.get_mut(i) {
                v.heading = heading;
                v.curvature = curvature;
            }
            i = i.saturating_add(1);
        }
        Ok(path)
    }

    /// Builds a path from samples that carry their exact heading and the
    /// curvature of the piece of path that starts at them (the last sample:
    /// of the piece that ends there), as a planner knows them
    /// (`spec/emmi2024.md`, EM-DUBINS-PATH).
    ///
    /// [`ReferencePath::from_waypoints`] smooths heading and curvature over a
    /// window, which suits noisy recorded waypoints but blurs a planned path's
    /// arcs (a Dubins arc's curvature jumps from 0 to ±1/r). Here the heading
    /// between two vertices is interpolated linearly (exact on arcs sampled
    /// densely) and c(s) is the curvature of the vertex that starts the
    /// segment holding s; positions, s and the projection are those of
    /// [`ReferencePath::from_waypoints`]. A sample closer than
    /// [`MIN_WAYPOINT_SPACING`] to the last kept one replaces it (the first
    /// one is kept), so the last sample always ends the path. The path's
    /// configuration is the default one and unused.
    ///
    /// # Errors
    /// `PATH-RANGE`, `PATH-WAYPOINTS` and `PATH-CAPACITY` as
    /// [`ReferencePath::from_waypoints`].
    //= spec/emmi2024.md#em-dubins-path-the-path-as-a-reference-path
    //# A reference path built from exact samples MUST return, at a vertex, the
    //# vertex's heading and, for s in [0, L], the curvature of the vertex that
    //# starts the segment holding s, instead of smoothed values.
    pub fn from_exact<I>(samples: I) -> Result<Self, Precondition>
    where
        I: IntoIterator<Item = (Pose2<World>, Curvature)>,
    {
        let mut vertices: Vec<PathVertex, N> = Vec::new();
        for (pose, curvature) in samples {
            let p = pose.position;
            if libm::fabs(p.x()) > MAX_PATH_COORDINATE || libm::fabs(p.y()) > MAX_PATH_COORDINATE {
                return Err(Precondition::new(
                    "PATH-RANGE",
                    "waypoint coordinate beyond 1e7 m",
                ));
            }
            let mut vertex = PathVertex {
                position: p,
                s: Meters::ZERO,
                heading: pose.heading,
                curvature,
            };
            if let Some(last) = vertices.last().copied() {
                if last.position.distance_to(p)?.get() < MIN_WAYPOINT_SPACING {
                    // Too close: replace the last vertex unless it is the first.
                    let before = vertices.len().checked_sub(2).and_then(|i| vertices.get(i));
                    let Some(before) = before.copied() else {
                        continue;
                    };
                    let d = before.position.distance_to(p)?.get();
                    if d < MIN_WAYPOINT_SPACING {
                        continue;
                    }
                    vertices.pop();
                    vertex.s = Meters(before.s.get() + d);
                } else {
                    vertex.s = Meters(last.s.get() + last.position.distance_to(p)?.get());
                }
            }
            if vertex.s.get() > MAX_PATH_LENGTH {
                return Err(Precondition::new("PATH-RANGE", "path length beyond 1e9 m"));
            }
            if vertices.push(vertex).is_err() {
                return Err(Precondition::new(
                    "PATH-CAPACITY",
                    "more distinct waypoints than the path capacity N",
                ));
            }
        }
        let length = match vertices.last() {
            Some(v) if vertices.len() >= 2 => v.s.get(),
            _ => {
                return Err(Precondition::new(
                    "PATH-WAYPOINTS",
                    "fewer than 2 distinct waypoints",
                ))
            }
        };
        Ok(Self {
            vertices,
            config: PathConfig::default(),
            length,
            exact: true,
        })
    }

    /// Total length L of the recorded path, metres.
    #[must_use]
    pub fn length(&self) -> Meters {
        Meters(self.length)
    }

    /// The configuration the path was built with.
    #[must_use]
    pub const fn config(&self) -> PathConfig {
        self.config
    }

    /// The stored vertices (position, s, smoothed heading, smoothed curvature), for plotting.
    #[must_use]
    pub fn vertices(&self) -> &[PathVertex] {
        &self.vertices
    }

    /// The point of the path at abscissa `s`, `World` frame. Outside [0, L] the
    /// point lies on the straight extension along the end tangent
    /// (PATH-EXTENSION). Errors with `LIB-FINITE` only if the point overflows.
    //= spec/geometry.md#path-extension-straight-extensions
    //# Before s = 0 and after s = L the path MUST continue as straight half-lines
    //# along the smoothed headings at s = 0 and s = L, with zero curvature.
    pub fn point_at(&self, s: Meters) -> Result<Point2<World>, Precondition> {
        let s = s.get();
        let (anchor, offset) = if s < 0.0 {
            (0.0, s)
        } else if s > self.length {
            (self.length, s - self.length)
        } else {
            return Ok(self.polyline_point(s));
        };
        let p = self.polyline_point(anchor);
        let h = self.smoothed_heading(anchor).get();
        Point2::new(p.x() + offset * libm::cos(h), p.y() + offset * libm::sin(h))
    }

    /// The smoothed heading of the path at `s`, radians in (−π, π]
    /// (PATH-HEADING); outside [0, L] the heading of the nearer end.
    #[must_use]
    pub fn heading_at(&self, s: Meters) -> Radians {
        self.smoothed_heading(clamp(s.get(), 0.0, self.length))
    }

    /// The smoothed curvature c(s), 1/m, positive for a left turn
    /// (PATH-CURVATURE); zero outside [0, L] (PATH-EXTENSION).
    #[must_use]
    pub fn curvature_at(&self, s: Meters) -> Curvature {
        self.smoothed_curvature(s.get())
    }

    /// The Frénet error of `pose` at the globally closest point of the path
    /// (Pierre 2022, section 2.1; FRENET-CLOSEST). `lookahead` (metres, any
    /// sign, usually v T) gives `curvature_ahead = c(s + lookahead)`, held at
    /// the curvature of the nearer end when s + lookahead lies beyond it
    /// (FRENET-CURVATURE). O(N). Errors with `LIB-FINITE` when a distance or
    /// abscissa overflows.
    //= spec/geometry.md#frenet-closest-closest-point
    //# `project` MUST return the abscissa s of a point of the extended path
    //# (the polyline and its two end extensions) closest to the robot position.
    pub fn project(
        &self,
        pose: &Pose2<World>,
        lookahead: Meters,
    ) -> Result<FrenetError, Precondition> {
        self.project_between(pose, lookahead, f64::NEG_INFINITY, f64::INFINITY)
    }

    /// The Frénet error of `pose` at the closest point among the points of the
    /// extended path whose abscissa lies in `[s_hint − window, s_hint + window]`
    /// (FRENET-LOCAL), so that another leg of the path (a U-turn's return) cannot
    /// capture the robot. Errors: `window < 0` (`FRENET-LOCAL`), overflow
    /// (`LIB-FINITE`).
    //= spec/geometry.md#frenet-local-local-search
    //# `project_near` MUST return the abscissa of a point closest to the robot
    //# among the points of the extended path whose abscissa lies in
    //# [s_hint − window, s_hint + window].
    //= spec/geometry.md#frenet-local-local-search
    //# A negative window MUST be refused with the `FRENET-LOCAL` error.
    pub fn project_near(
        &self,
        pose: &Pose2<World>,
        lookahead: Meters,
        s_hint: Meters,
        window: Meters,
    ) -> Result<FrenetError, Precondition> {
        if window.get() < 0.0 {
            return Err(Precondition::new(
                "FRENET-LOCAL",
                "search window must be >= 0",
            ));
        }
        let lo = s_hint.get() - window.get();
        let hi = s_hint.get() + window.get();
        self.project_between(pose, lookahead, lo, hi)
    }

    /// The Frénet error at the closest point with abscissa in `[lo, hi]` (`lo ≤ hi`,
    /// infinities allowed).
    fn project_between(
        &self,
        pose: &Pose2<World>,
        lookahead: Meters,
        lo: f64,
        hi: f64,
    ) -> Result<FrenetError, Precondition> {
        let qx = pose.position.x();
        let qy = pose.position.y();
        let mut best: Option<Candidate> = None;
        let mut offer = |c: Candidate| {
            let better = match best {
                None => c.distance_sq.is_finite(),
                Some(b) => c.distance_sq < b.distance_sq,
            };
            if better {
                best = Some(c);
            }
        };

        // Polyline segments, clipped to the abscissa window.
        for pair in self.vertices.windows(2) {
            let (Some(a), Some(b)) = (pair.first(), pair.get(1)) else {
                continue;
            };
            let (s_a, s_b) = (a.s.get(), b.s.get());
            if s_b < lo || s_a > hi {
                continue;
            }
            let len = s_b - s_a;
            let dx = b.position.x() - a.position.x();
            let dy = b.position.y() - a.position.y();
            let t_lo = if lo <= s_a { 0.0 } else { (lo - s_a) / len };
            let t_hi = if hi >= s_b { 1.0 } else { (hi - s_a) / len };
            // Foot of the perpendicular, limited to the segment; the division is
            // only needed when the foot falls inside (rarely, over a long path).
            let dot = (qx - a.position.x()) * dx + (qy - a.position.y()) * dy;
            let len_sq = len * len;
            let t_free = if dot <= 0.0 {
                0.0
            } else if dot >= len_sq {
                1.0
            } else {
                dot / len_sq
            };
            let t = clamp(t_free, t_lo, t_hi);
            let x = a.position.x() + t * dx;
            let y = a.position.y() + t * dy;
            let ex = qx - x;
            let ey = qy - y;
            // At a vertex (outside of a corner) the side is taken from the
            // smoothed tangent; inside a segment from the segment itself.
            //= spec/geometry.md#frenet-corner-corners
            //# Where the closest point is a vertex on the outside of a corner, y MUST be
            //# the signed distance to that vertex with its side taken from the smoothed
            //# heading at the vertex, and θ̃ MUST use the smoothed heading at the vertex.
            let side = if t <= 0.0 {
                Side::Heading(a.heading.get())
            } else if t >= 1.0 {
                Side::Heading(b.heading.get())
            } else {
                Side::Vector(dx, dy)
            };
            offer(Candidate {
                distance_sq: ex * ex + ey * ey,
                s: s_a + t * len,
                x,
                y,
                side,
            });
        }

        // The straight extensions before the start and after the end.
        if let (Some(first), Some(last)) = (self.vertices.first(), self.vertices.last()) {
            if lo <= 0.0 {
                let (tx, ty) = unit(first.heading.get());
                let (px, py) = (first.position.x(), first.position.y());
                let u = clamp((qx - px) * tx + (qy - py) * ty, lo, hi.min(0.0));
                offer(ray_candidate(qx, qy, px, py, tx, ty, u, 0.0));
            }
            if hi >= self.length {
                let (tx, ty) = unit(last.heading.get());
                let (px, py) = (last.position.x(), last.position.y());
                let u = clamp(
                    (qx - px) * tx + (qy - py) * ty,
                    lo.max(self.length) - self.length,
                    hi - self.length,
                );
                offer(ray_candidate(qx, qy, px, py, tx, ty, u, self.length));
            }
        }

        let Some(c) = best else {
            return Err(Precondition::new(
                "LIB-FINITE",
                "distance from the pose to the path overflows",
            ));
        };
        self.frenet_at(pose, lookahead, &c)
    }

    /// Builds the Frénet error from the chosen closest point.
    //= spec/geometry.md#frenet-lateral-signed-lateral-error
    //# The lateral error y MUST be the distance from the robot position to the
    //# closest point, positive when the robot is left of the path direction at
    //# that point and negative when it is right.
    //= spec/geometry.md#frenet-angular-angular-deviation
    //# The angular deviation MUST be θ̃ = θ − θ_Γ(s), the robot heading minus
    //# the smoothed path heading at s, wrapped to (−π, π].
    //= spec/geometry.md#frenet-curvature-curvature-at-and-ahead-of-s
    //# The Frénet error MUST carry c(s), the path's smoothed curvature at s, zero
    //# beyond the ends.
    //= spec/geometry.md#frenet-curvature-curvature-at-and-ahead-of-s
    //# The Frénet error MUST carry the curvature ahead c(min(max(s + lookahead,
    //# 0), L)): the smoothed curvature at s + lookahead, held at the curvature of
    //# the nearer end when s + lookahead lies beyond an end.
    //= spec/geometry.md#frenet-ends-before-the-start-and-past-the-end
    //# The position MUST be `BeforeStart` when s < 0, `PastEnd` when s > L and
    //# `Within` otherwise.
    fn frenet_at(
        &self,
        pose: &Pose2<World>,
        lookahead: Meters,
        c: &Candidate,
    ) -> Result<FrenetError, Precondition> {
        let ex = pose.position.x() - c.x;
        let ey = pose.position.y() - c.y;
        let distance = libm::hypot(ex, ey);
        let (tx, ty) = match c.side {
            Side::Vector(tx, ty) => (tx, ty),
            Side::Heading(h) => unit(h),
        };
        let cross = tx * ey - ty * ex;
        let y = if cross < 0.0 { -distance } else { distance };
        let s = Meters::new(c.s)?;
        let y = Meters::new(y)?;
        let path_heading = self.heading_at(s);
        let angular_deviation = Radians::new(wrap_raw(pose.heading.get() - path_heading.get()))?;
        let curvature = self.curvature_at(s);
        // An abscissa that overflows lies beyond an end: the clamp takes it there.
        let ahead = clamp(s.get() + lookahead.get(), 0.0, self.length);
        let curvature_ahead = self.curvature_at(Meters(ahead));
        let position = if s.get() < 0.0 {
            PathPosition::BeforeStart
        } else if s.get() > self.length {
            PathPosition::PastEnd
        } else {
            PathPosition::Within
        };
        Ok(FrenetError {
            s,
            y,
            angular_deviation,
            curvature,
            curvature_ahead,
            position,
        })
    }

    /// The polyline point at `s`, clamped to [0, L]. Always finite: it lies
    /// on a segment between two finite vertices.
    fn polyline_point(&self, s: f64) -> Point2<World> {
        let (a, b, t) = self.locate(s);
        let x = a.position.x() + t * (b.position.x() - a.position.x());
        let y = a.position.y() + t * (b.position.y() - a.position.y());
        Point2::new(x, y).unwrap_or(a.position)
    }

    /// The segment containing `s` (clamped to [0, L]) and the fraction along it.
    fn locate(&self, s: f64) -> (PathVertex, PathVertex, f64) {
        let s = clamp(s, 0.0, self.length);
        let after = self.vertices.partition_point(|v| v.s.get() <= s);
        let last_segment = self.vertices.len().saturating_sub(2);
        let i = after.saturating_sub(1).min(last_segment);
        let a = self.vertices.get(i).copied();
        let b = self.vertices.get(i.saturating_add(1)).copied();
        match (a, b) {
            (Some(a), Some(b)) => {
                let len = b.s.get() - a.s.get();
                let t = clamp((s - a.s.get()) / len, 0.0, 1.0);
                (a, b, if t.is_finite() { t } else { 0.0 })
            }
            // Unreachable: a path has at least 2 vertices. Degrade gracefully.
            (Some(a), None) => (a, a, 0.0),
            _ => {
                let o = PathVertex {
                    position: Point2::origin(),
                    s: Meters::ZERO,
                    heading: Radians::ZERO,
                    curvature: Curvature::ZERO,
                };
                (o, o, 0.0)
            }
        }
    }

    /// Bounds of the smoothing window around `s`, clipped to [0, L].
    fn window(&self, s: f64) -> (f64, f64) {
        let half = 0.5 * self.config.smoothing_window.get();
        ((s - half).max(0.0), (s + half).min(self.length))
    }

    /// Smoothed heading at `s ∈ [0, L]`: direction of the chord p(b) − p(a) over
    /// the clipped window [a, b] around s.
    //= spec/geometry.md#path-heading-smoothed-heading
    //# The heading at s MUST be the direction of the chord p(b) − p(a) of the
    //# polyline, where [a, b] = [s − w/2, s + w/2] ∩ [0, L].
    //= spec/geometry.md#path-heading-smoothed-heading
    //# When that chord is shorter than 1e−9 m, the heading MUST be the direction
    //# of the polyline segment containing s.
    fn smoothed_heading(&self, s: f64) -> Radians {
        if self.exact {
            let (a, b, t) = self.locate(s);
            let turn = wrap_raw(b.heading.get() - a.heading.get());
            return Radians::new(wrap_raw(a.heading.get() + t * turn)).unwrap_or(a.heading);
        }
        let (a, b) = self.window(s);
        let pa = self.polyline_point(a);
        let pb = self.polyline_point(b);
        let (dx, dy) = (pb.x() - pa.x(), pb.y() - pa.y());
        let angle = if libm::hypot(dx, dy) >= MIN_CHORD {
            libm::atan2(dy, dx)
        } else {
            let (sa, sb, _) = self.locate(s);
            libm::atan2(
                sb.position.y() - sa.position.y(),
                sb.position.x() - sa.position.x(),
            )
        };
        Radians::new(wrap_raw(angle)).unwrap_or(Radians::ZERO)
    }

    /// Midpoint of the clipped window around `x`: the abscissa whose tangent the
    /// chord heading at `x` represents (exactly, on a circular arc).
    fn window_centre(&self, x: f64) -> f64 {
        let (a, b) = self.window(x);
        0.5 * (a + b)
    }

    /// Smoothed curvature at `s`: zero outside [0, L], else the wrapped heading
    /// difference between the ends of the clipped window over the arc length
    /// between the centres of their chords.
    //= spec/geometry.md#path-curvature-smoothed-curvature
    //# For s in [0, L] the curvature MUST be c(s) = wrap(θ_Γ(b) − θ_Γ(a)) / (m(b) − m(a)),
    //# where [a, b] = [s − w/2, s + w/2] ∩ [0, L], θ_Γ is the smoothed heading and
    //# m(x) is the centre of the clipped window around x.
    //= spec/geometry.md#path-curvature-smoothed-curvature
    //# When m(b) − m(a) is below 1e−9 m, the curvature MUST be 0.
    fn smoothed_curvature(&self, s: f64) -> Curvature {
        if s < 0.0 || s > self.length {
            return Curvature::ZERO;
        }
        if self.exact {
            return self.locate(s).0.curvature;
        }
        let (a, b) = self.window(s);
        let arc = self.window_centre(b) - self.window_centre(a);
        if arc < MIN_CHORD {
            return Curvature::ZERO;
        }
        let turn = wrap_raw(self.smoothed_heading(b).get() - self.smoothed_heading(a).get());
        Curvature::new(turn / arc).unwrap_or(Curvature::ZERO)
    }
}

/// The unit vector of heading `h`.
fn unit(h: f64) -> (f64, f64) {
    (libm::cos(h), libm::sin(h))
}

/// The candidate at abscissa `origin_s + u` on the ray from `(px, py)` along `(tx, ty)`.
#[allow(clippy::too_many_arguments)]
fn ray_candidate(
    qx: f64,
    qy: f64,
    px: f64,
    py: f64,
    tx: f64,
    ty: f64,
    u: f64,
    origin_s: f64,
) -> Candidate {
    let x = px + u * tx;
    let y = py + u * ty;
    let ex = qx - x;
    let ey = qy - y;
    Candidate {
        distance_sq: ex * ex + ey * ey,
        s: origin_s + u,
        x,
        y,
        side: Side::Vector(tx, ty),
    }
}
