//! GoToGoal: the shortest forward path between two poses with a minimum
//! turning radius, made of arcs and straights (Dubins 1957; Emmi 2024,
//! section 3.1, Fig. 4; `spec/emmi2024.md`, EM-DUBINS-*).
//!
//! The six candidate words are LSL, LSR, RSL, RSR, RLR and LRL (L a left arc
//! of radius r, R a right arc, S a straight). Each is solved in closed form
//! in the frame where the start lies at the origin and the goal on the x
//! axis, distances divided by r; [`shortest`] keeps the shortest word that
//! exists. The path converts into a [`ReferencePath`] whose vertices carry
//! the exact heading and curvature (±1/r on arcs, 0 on straights), so a path
//! tracker's curvature feed-forward sees the arcs
//! ([`DubinsPath::to_reference_path`]).

use core::f64::consts::{PI, TAU};

use crate::error::{finite, Precondition};
use crate::geometry::frame::{Point2, Pose2, World};
use crate::geometry::path::{ReferencePath, MAX_PATH_COORDINATE};
use crate::geometry::units::{wrap_raw, Curvature, Meters, Radians};
use crate::model::skid_steer::SkidSteer;

/// The smallest accepted turning radius, metres (EM-DUBINS-RADIUS).
pub const MIN_RADIUS: f64 = 1e-3;

/// The largest accepted turning radius, metres (EM-DUBINS-RADIUS).
pub const MAX_RADIUS: f64 = 1e4;

/// The smallest sample spacing of [`DubinsPath::to_reference_path`], metres
/// (EM-DUBINS-PATH): twice the reference path's duplicate distance, so that
/// samples on an arc never fall within it.
pub const MIN_SPACING: f64 = 2e-3;

/// A normalised segment length this close below 2π is a full turn that ends
/// where it starts, and is taken as 0 (EM-DUBINS-DEGENERATE).
const FULL_TURN_SNAP: f64 = 1e-12;

/// Turning circles of the start and the goal whose squared centre distance
/// (over r²) is below this are one circle: LSL and RSR are then one arc,
/// whose tangent direction, the direction between the centres, is rounding
/// noise (EM-DUBINS-DEGENERATE). The rounding of that squared distance is
/// about 3e−15 where circles can coincide (d ≤ 2).
const SAME_CIRCLE_SQ: f64 = 1e-12;

/// The direction of one segment of a Dubins path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Turn {
    /// A left (counter-clockwise) arc of the turning radius, curvature +1/r.
    Left,
    /// A straight, curvature 0.
    Straight,
    /// A right (clockwise) arc of the turning radius, curvature −1/r.
    Right,
}

impl Turn {
    /// +1 for a left arc, 0 for a straight, −1 for a right arc.
    const fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Straight => 0.0,
            Self::Right => -1.0,
        }
    }
}

/// The six Dubins words (Dubins 1957).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Word {
    /// Left, straight, left.
    Lsl,
    /// Left, straight, right.
    Lsr,
    /// Right, straight, left.
    Rsl,
    /// Right, straight, right.
    Rsr,
    /// Right, left, right.
    Rlr,
    /// Left, right, left.
    Lrl,
}

impl Word {
    /// The six words in the order [`shortest`] tries them (ties go to the
    /// first one).
    pub const ALL: [Self; 6] = [
        Self::Lsl,
        Self::Lsr,
        Self::Rsl,
        Self::Rsr,
        Self::Rlr,
        Self::Lrl,
    ];

    /// The three segment directions of this word.
    #[must_use]
    pub const fn turns(self) -> [Turn; 3] {
        use Turn::{Left as L, Right as R, Straight as S};
        match self {
            Self::Lsl => [L, S, L],
            Self::Lsr => [L, S, R],
            Self::Rsl => [R, S, L],
            Self::Rsr => [R, S, R],
            Self::Rlr => [R, L, R],
            Self::Lrl => [L, R, L],
        }
    }

    /// The word of the mirror image about the x axis: left and right swapped.
    #[must_use]
    pub const fn mirrored(self) -> Self {
        match self {
            Self::Lsl => Self::Rsr,
            Self::Lsr => Self::Rsl,
            Self::Rsl => Self::Lsr,
            Self::Rsr => Self::Lsl,
            Self::Rlr => Self::Lrl,
            Self::Lrl => Self::Rlr,
        }
    }

    /// The word of the same path driven backwards from the goal with both
    /// headings turned by π: the segments in reverse order, each arc of the
    /// other hand.
    #[must_use]
    pub const fn reversed(self) -> Self {
        match self {
            Self::Lsl => Self::Rsr,
            Self::Lsr => Self::Lsr,
            Self::Rsl => Self::Rsl,
            Self::Rsr => Self::Lsl,
            Self::Rlr => Self::Lrl,
            Self::Lrl => Self::Rlr,
        }
    }
}

/// A minimum turning radius r, metres, in [`MIN_RADIUS`, `MAX_RADIUS`].
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct TurningRadius(f64);

impl TurningRadius {
    /// A turning radius of `radius` metres.
    ///
    /// # Errors
    /// `EM-DUBINS-RADIUS` outside [`MIN_RADIUS`, `MAX_RADIUS`].
    //= spec/emmi2024.md#em-dubins-radius-turning-radius
    //# The turning radius r MUST lie in [1e−3 m, 1e4 m]; another radius, zero
    //# included, MUST be refused with the `EM-DUBINS-RADIUS` error.
    pub fn new(radius: Meters) -> Result<Self, Precondition> {
        let r = radius.get();
        if (MIN_RADIUS..=MAX_RADIUS).contains(&r) {
            Ok(Self(r))
        } else {
            Err(Precondition::new(
                "EM-DUBINS-RADIUS",
                "turning radius outside [1e-3, 1e4] m",
            ))
        }
    }

    /// A turning radius for a tracked robot: as [`TurningRadius::new`], and
    /// at least the track distance so that both tracks move forward
    /// (Emmi 2024, section 3.3.2).
    ///
    /// # Errors
    /// `EM-DUBINS-RADIUS` as [`TurningRadius::new`]; `EM-SKID-FORWARD` below
    /// the track distance.
    //= spec/emmi2024.md#em-skid-forward-both-tracks-forward-in-turns
    //# A planner option MUST refuse a turning radius below the track distance b
    //# with the `EM-SKID-FORWARD` error.
    pub fn for_vehicle(radius: Meters, vehicle: &SkidSteer) -> Result<Self, Precondition> {
        let r = Self::new(radius)?;
        vehicle.check_turn_radius(radius)?;
        Ok(r)
    }

    /// The radius in metres.
    #[must_use]
    pub const fn get(self) -> Meters {
        Meters(self.0)
    }
}

/// One segment of a Dubins path, in the `World` frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Its direction.
    pub turn: Turn,
    /// The pose where it starts.
    pub start: Pose2<World>,
    /// Its length, metres (≥ 0).
    pub length: Meters,
    /// Its curvature: +1/r (left), −1/r (right) or 0 (straight), 1/m.
    pub curvature: Curvature,
    /// The centre of its arc; `None` for a straight.
    pub centre: Option<Point2<World>>,
}

/// A Dubins path: a start pose, a radius, a word and the three segment
/// lengths divided by the radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DubinsPath {
    start: Pose2<World>,
    radius: f64,
    word: Word,
    params: [f64; 3],
}

/// The problem in the normalised frame: start at the origin, goal at (d, 0),
/// headings α and β, both in [0, 2π).
struct Normalised {
    d: f64,
    alpha: f64,
    beta: f64,
    sa: f64,
    sb: f64,
    ca: f64,
    cb: f64,
    c_ab: f64,
}

/// `x` modulo 2π in [0, 2π), a value within [`FULL_TURN_SNAP`] of 2π being 0.
fn mod_tau(x: f64) -> f64 {
    // The arguments here lie within a few turns of [0, 2π): one addition or
    // subtraction usually suffices.
    let m = if (0.0..TAU).contains(&x) {
        x
    } else if (-TAU..0.0).contains(&x) {
        x + TAU
    } else if (TAU..2.0 * TAU).contains(&x) {
        x - TAU
    } else {
        x - TAU * libm::floor(x / TAU)
    };
    if !(0.0..TAU - FULL_TURN_SNAP).contains(&m) {
        0.0
    } else {
        m
    }
}

//= spec/emmi2024.md#em-dubins-range-coordinates-within-range
//# Poses with a coordinate of magnitude above 1e7 m MUST be refused with the
//# `EM-DUBINS-RANGE` error.
fn normalise(
    start: &Pose2<World>,
    goal: &Pose2<World>,
    radius: TurningRadius,
) -> Result<Normalised, Precondition> {
    let far = |p: &Pose2<World>| {
        libm::fabs(p.position.x()) > MAX_PATH_COORDINATE
            || libm::fabs(p.position.y()) > MAX_PATH_COORDINATE
    };
    if far(start) || far(goal) {
        return Err(Precondition::new(
            "EM-DUBINS-RANGE",
            "pose coordinate beyond 1e7 m",
        ));
    }
    let dx = goal.position.x() - start.position.x();
    let dy = goal.position.y() - start.position.y();
    // Within the range, dx² + dy² ≤ 1.6e15: no overflow, no need of hypot.
    let d = libm::sqrt(dx * dx + dy * dy) / radius.0;
    let theta = if d > 0.0 { libm::atan2(dy, dx) } else { 0.0 };
    let alpha = mod_tau(start.heading.get() - theta);
    let beta = mod_tau(goal.heading.get() - theta);
    let (sa, ca) = libm::sincos(alpha);
    let (sb, cb) = libm::sincos(beta);
    Ok(Normalised {
        d,
        alpha,
        beta,
        sa,
        sb,
        ca,
        cb,
        // cos(α − β), without a third cosine.
        c_ab: ca * cb + sa * sb,
    })
}

/// The normalised segment lengths of `word`, `None` when it does not exist
/// or when its straight or middle arc alone is at least `bound` (a normalised
/// total it cannot beat; `f64::INFINITY` to compute every word).
//= spec/emmi2024.md#em-dubins-words-the-six-words
//# For each of the six words LSL, LSR, RSL, RSR, RLR and LRL the planner MUST
//# compute the segment lengths of the path of that word from the start pose to
//# the goal pose, or report that the word does not exist.
fn word_params(n: &Normalised, word: Word, bound: f64) -> Option<[f64; 3]> {
    let Normalised {
        d,
        alpha,
        beta,
        sa,
        sb,
        ca,
        cb,
        c_ab,
    } = *n;
    let d_sq = d * d;
    match word {
        // The squared distance between the two circles' centres (over r²): it
        // is never negative but for rounding.
        Word::Lsl => {
            let p_sq = (2.0 + d_sq - 2.0 * c_ab + 2.0 * d * (sa - sb)).max(0.0);
            let p = libm::sqrt(p_sq);
            if p_sq < SAME_CIRCLE_SQ {
                return Some([mod_tau(beta - alpha), 0.0, 0.0]);
            }
            if p >= bound {
                return None;
            }
            let phi = libm::atan2(cb - ca, d + sa - sb);
            Some([mod_tau(phi - alpha), p, mod_tau(beta - phi)])
        }
        Word::Rsr => {
            let p_sq = (2.0 + d_sq - 2.0 * c_ab + 2.0 * d * (sb - sa)).max(0.0);
            let p = libm::sqrt(p_sq);
            if p_sq < SAME_CIRCLE_SQ {
                return Some([mod_tau(alpha - beta), 0.0, 0.0]);
            }
            if p >= bound {
                return None;
            }
            let phi = libm::atan2(ca - cb, d - sa + sb);
            Some([mod_tau(alpha - phi), p, mod_tau(phi - beta)])
        }
        Word::Lsr => {
            let p_sq = -2.0 + d_sq + 2.0 * c_ab + 2.0 * d * (sa + sb);
            if p_sq < 0.0 {
                return None;
            }
            let p = libm::sqrt(p_sq);
            if p >= bound {
                return None;
            }
            let phi = libm::atan2(-ca - cb, d + sa + sb) - libm::atan2(-2.0, p);
            Some([mod_tau(phi - alpha), p, mod_tau(phi - beta)])
        }
        Word::Rsl => {
            let p_sq = -2.0 + d_sq + 2.0 * c_ab - 2.0 * d * (sa + sb);
            if p_sq < 0.0 {
                return None;
            }
            let p = libm::sqrt(p_sq);
            if p >= bound {
                return None;
            }
            let phi = libm::atan2(ca + cb, d - sa - sb) - libm::atan2(2.0, p);
            Some([mod_tau(alpha - phi), p, mod_tau(beta - phi)])
        }
        Word::Rlr => {
            let c = (6.0 - d_sq + 2.0 * c_ab + 2.0 * d * (sa - sb)) / 8.0;
            // The middle arc is at least π: no shorter than the bound.
            if !(-1.0..=1.0).contains(&c) || PI >= bound {
                return None;
            }
            let phi = libm::atan2(ca - cb, d - sa + sb);
            let p = mod_tau(TAU - libm::acos(c));
            let t = mod_tau(alpha - phi + mod_tau(0.5 * p));
            Some([t, p, mod_tau(alpha - beta - t + mod_tau(p))])
        }
        Word::Lrl => {
            let c = (6.0 - d_sq + 2.0 * c_ab + 2.0 * d * (sb - sa)) / 8.0;
            // The middle arc is at least π: no shorter than the bound.
            if !(-1.0..=1.0).contains(&c) || PI >= bound {
                return None;
            }
            let phi = libm::atan2(ca - cb, d + sa - sb);
            let p = mod_tau(TAU - libm::acos(c));
            let t = mod_tau(-alpha - phi + 0.5 * p);
            Some([t, p, mod_tau(beta - alpha - t + mod_tau(p))])
        }
    }
}

/// The Dubins path of `word` from `start` to `goal` with turning radius
/// `radius`.
///
/// # Errors
/// `EM-DUBINS-WORDS` when no path of that word joins the poses;
/// `EM-DUBINS-RANGE` for coordinates beyond 1e7 m.
//= spec/emmi2024.md#em-dubins-words-the-six-words
//# A word that does not exist between the two poses MUST be reported with the
//# `EM-DUBINS-WORDS` error.
pub fn path_with_word(
    start: &Pose2<World>,
    goal: &Pose2<World>,
    radius: TurningRadius,
    word: Word,
) -> Result<DubinsPath, Precondition> {
    let n = normalise(start, goal, radius)?;
    let params = word_params(&n, word, f64::INFINITY).ok_or(Precondition::new(
        "EM-DUBINS-WORDS",
        "no path of this word joins the poses",
    ))?;
    DubinsPath::checked(*start, radius, word, params)
}

/// The shortest Dubins path from `start` to `goal` with turning radius
/// `radius` (Emmi 2024, section 3.1, GoToGoal). The same pose gives the
/// path of length 0 (word LSL).
///
/// # Errors
/// `EM-DUBINS-RANGE` for coordinates beyond 1e7 m.
//= spec/emmi2024.md#em-dubins-shortest-the-shortest-word
//# GoToGoal MUST return the path of least length among the words that exist;
//# among words of equal computed length it MUST return the first in the order
//# LSL, LSR, RSL, RSR, RLR, LRL.
//= spec/emmi2024.md#em-dubins-degenerate-degenerate-problems
//# When the goal pose equals the start pose, GoToGoal MUST return a path of
//# length 0.
pub fn shortest(
    start: &Pose2<World>,
    goal: &Pose2<World>,
    radius: TurningRadius,
) -> Result<DubinsPath, Precondition> {
    let n = normalise(start, goal, radius)?;
    if start == goal {
        // α and β are measured from the direction to the goal, which does not
        // exist here; the path of length 0 is the answer.
        return DubinsPath::checked(*start, radius, Word::Lsl, [0.0; 3]);
    }
    let mut best: Option<(Word, [f64; 3], f64)> = None;
    for word in Word::ALL {
        // A word whose straight or middle arc alone is no shorter than the
        // best total cannot win (ties go to the earlier word): skip its
        // remaining trigonometry.
        let bound = best.map_or(f64::INFINITY, |(_, _, t)| t);
        if let Some(p) = word_params(&n, word, bound) {
            let [a, b, c] = p;
            let total = a + b + c;
            if best.is_none_or(|(_, _, t)| total < t) {
                best = Some((word, p, total));
            }
        }
    }
    // LSL always exists (its squared centre distance is clamped at 0).
    let (word, params, _) = best.unwrap_or((Word::Lsl, [0.0; 3], 0.0));
    DubinsPath::checked(*start, radius, word, params)
}

/// The pose reached from `pose` after a normalised length `t` (radians on an
/// arc, metres over r on a straight) of direction `turn` with radius `r`.
fn advance(pose: (f64, f64, f64), turn: Turn, t: f64, r: f64) -> (f64, f64, f64) {
    let (x, y, h) = pose;
    let k = turn.sign();
    if k == 0.0 {
        let l = r * t;
        (x + l * libm::cos(h), y + l * libm::sin(h), h)
    } else {
        // The chord of the arc: length 2 r sin(t/2), direction h ± t/2.
        let chord = 2.0 * r * libm::sin(0.5 * t);
        let mid = h + k * 0.5 * t;
        (
            x + chord * libm::cos(mid),
            y + chord * libm::sin(mid),
            h + k * t,
        )
    }
}

impl DubinsPath {
    /// A path whose total length is finite.
    fn checked(
        start: Pose2<World>,
        radius: TurningRadius,
        word: Word,
        params: [f64; 3],
    ) -> Result<Self, Precondition> {
        let [a, b, c] = params;
        finite((a + b + c) * radius.0, "Dubins path length")?;
        Ok(Self {
            start,
            radius: radius.0,
            word,
            params,
        })
    }

    /// The word of the path.
    #[must_use]
    pub const fn word(&self) -> Word {
        self.word
    }

    /// The start pose.
    #[must_use]
    pub const fn start(&self) -> Pose2<World> {
        self.start
    }

    /// The turning radius, metres.
    #[must_use]
    pub const fn radius(&self) -> Meters {
        Meters(self.radius)
    }

    /// The total length, metres.
    //= spec/emmi2024.md#em-dubins-shortest-the-shortest-word
    //# The length of a path MUST be r times the sum of its three normalised
    //# segment lengths.
    #[must_use]
    pub fn length(&self) -> Meters {
        let [a, b, c] = self.params;
        Meters((a + b + c) * self.radius)
    }

    /// The three segments, in order, in the `World` frame.
    #[must_use]
    pub fn segments(&self) -> [Segment; 3] {
        let mut pose = (
            self.start.position.x(),
            self.start.position.y(),
            self.start.heading.get(),
        );
        let turns = self.word.turns();
        let r = self.radius;
        let mut out = [Segment {
            turn: Turn::Straight,
            start: self.start,
            length: Meters::ZERO,
            curvature: Curvature::ZERO,
            centre: None,
        }; 3];
        for ((slot, turn), t) in out.iter_mut().zip(turns).zip(self.params) {
            let (x, y, h) = pose;
            let k = turn.sign();
            *slot = Segment {
                turn,
                start: Pose2 {
                    position: Point2::new(x, y).unwrap_or(self.start.position),
                    heading: Radians(wrap_raw(h)),
                },
                length: Meters(r * t),
                curvature: Curvature(k / r),
                centre: if k == 0.0 {
                    None
                } else {
                    Point2::new(x - k * r * libm::sin(h), y + k * r * libm::cos(h)).ok()
                },
            };
            pose = advance(pose, turn, t, r);
        }
        out
    }

    /// The pose at arc length `s` along the path, `s` limited to [0, L].
    ///
    /// # Errors
    /// `LIB-FINITE` if a coordinate overflows (not for poses within range).
    //= spec/emmi2024.md#em-dubins-sample-poses-along-the-path
    //# The pose at arc length s MUST be the start pose moved along the segments of
    //# the word, each arc of radius r turning by its length over r; the pose at
    //# s = L MUST be the goal pose.
    pub fn pose_at(&self, s: Meters) -> Result<Pose2<World>, Precondition> {
        let mut left = s.get().max(0.0) / self.radius;
        let mut pose = (
            self.start.position.x(),
            self.start.position.y(),
            self.start.heading.get(),
        );
        for (turn, t) in self.word.turns().into_iter().zip(self.params) {
            let step = left.min(t);
            pose = advance(pose, turn, step, self.radius);
            left -= step;
        }
        let (x, y, h) = pose;
        Pose2::new(x, y, wrap_raw(h))
    }

    /// The end pose (the goal, to rounding).
    ///
    /// # Errors
    /// `LIB-FINITE` as [`DubinsPath::pose_at`].
    pub fn end(&self) -> Result<Pose2<World>, Precondition> {
        self.pose_at(self.length())
    }

    /// The path as a [`ReferencePath`] of at most `N` vertices, sampled at
    /// most `spacing` apart along each segment (segment ends included), each
    /// vertex with its exact heading and the curvature of the segment that
    /// starts there (the last one: of the last segment).
    ///
    /// # Errors
    /// `EM-DUBINS-PATH` for a spacing below 2 mm; the errors of
    /// [`ReferencePath::from_exact`] (`PATH-WAYPOINTS` for a path shorter
    /// than 1 mm, `PATH-CAPACITY` beyond `N` vertices).
    //= spec/emmi2024.md#em-dubins-path-the-path-as-a-reference-path
    //# The reference path of a Dubins path MUST have vertices on the path,
    //# segment ends included, at most the requested spacing apart along each
    //# segment (1 mm more where a sample within 1 mm of the previous one was
    //# merged), each carrying the exact heading of the path there and the
    //# curvature of the segment that starts there (+1/r, −1/r or 0).
    pub fn to_reference_path<const N: usize>(
        &self,
        spacing: Meters,
    ) -> Result<ReferencePath<N>, Precondition> {
        if spacing.get() < MIN_SPACING {
            return Err(Precondition::new(
                "EM-DUBINS-PATH",
                "sample spacing below 2 mm",
            ));
        }
        // On an arc, at most a quarter turn between samples: the chord of a
        // step h ≤ π r / 2 is at least 2h/π, so consecutive samples stay more
        // than 1 mm apart and none collapse (a full turn's chord is 0).
        let arc_step = spacing.get().min(0.5 * PI * self.radius);
        let segments = self.segments();
        let last_curvature = segments
            .iter()
            .rev()
            .find(|g| g.length.get() > 0.0)
            .map_or(Curvature::ZERO, |g| g.curvature);
        let mut index = 0_usize;
        let mut k = 0.0_f64;
        let mut done = false;
        let samples = core::iter::from_fn(|| loop {
            if done {
                return None;
            }
            let Some(g) = segments.get(index) else {
                done = true;
                return self.end().ok().map(|p| (p, last_curvature));
            };
            let step = if g.turn == Turn::Straight {
                spacing.get()
            } else {
                arc_step
            };
            let pieces = libm::ceil(g.length.get() / step);
            if k >= pieces {
                index = index.saturating_add(1);
                k = 0.0;
                continue;
            }
            let along = g.length.get() * (k / pieces);
            k += 1.0;
            let t = along / self.radius;
            let (x, y, h) = advance(
                (
                    g.start.position.x(),
                    g.start.position.y(),
                    g.start.heading.get(),
                ),
                g.turn,
                t,
                self.radius,
            );
            let pose = Pose2::new(x, y, wrap_raw(h)).ok()?;
            return Some((pose, g.curvature));
        });
        ReferencePath::from_exact(samples)
    }
}
