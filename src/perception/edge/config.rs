//! The edge detector's configuration, validated once (requirement EDGE-CONFIG),
//! and the side of the robot on which an edge is searched.

use core::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

use crate::error::Precondition;
use crate::geometry::units::{Meters, Radians};
use crate::perception::{Better, QualityThresholds};

/// The side of the robot where the chain is built (Pierre 2022, Algorithm 1, `s`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// The edge is on the robot's left (y > 0); the circle rolls on its right.
    Left,
    /// The edge is on the robot's right (y < 0); the circle rolls on its left.
    Right,
}

impl Side {
    /// `+1` for the left, `−1` for the right: the direction of the translation
    /// along the robot's y axis and the sense of the rotation (counter-clockwise
    /// for the left).
    #[must_use]
    pub const fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Right => -1.0,
        }
    }

    /// The other side.
    #[must_use]
    pub const fn mirrored(self) -> Self {
        match self {
            Self::Left => Self::Right,
            Self::Right => Self::Left,
        }
    }
}

/// The raw parameters of the edge detector, before validation
/// (Pierre 2022, Table 1 and section 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeParameters {
    /// Radius r of the rolling circle, metres (Table 1: 1 m).
    pub radius: f64,
    /// Largest rotation θ_max about one pivot, radians, in (0, 2π) (not in Table 1).
    pub max_rotation: f64,
    /// Chain length l_max at which the chain stops, metres (Table 1: 3 m).
    pub max_chain_length: f64,
    /// Largest translation of the circle when searching the first point,
    /// metres (Table 1: "maximal distance to search an edge", 3 m).
    pub search_distance: f64,
    /// Desired lateral distance D between the robot and the edge, metres (Table 1: 1.4 m).
    pub offset: f64,
    /// Chain length l_min the chain must exceed to be followed, metres (eq. 21; not in Table 1).
    pub min_chain_length: f64,
    /// Longest link l_link between consecutive chain points, metres, > 0: a
    /// contact farther from the pivot is a gap in the edge and the chain stops
    /// before it (EDGE-GAP; not in the paper). Contacts are always closer
    /// than 2r, so a value of 2r or more never stops a chain.
    pub max_link: f64,
    /// Largest turn φ_turn, radians, in (0, π], of a link from the chain's
    /// direction so far (its first point to the pivot): a sharper turn is a
    /// corner or the end of the edge and the chain stops before it
    /// (EDGE-CORNER; not in the paper). π never stops a chain.
    pub max_turn: f64,
    /// Spread w_max of the chain along the robot's y axis that it must stay
    /// below, metres (eq. 21; not in Table 1).
    pub max_width: f64,
    /// Fewest chain points for a detection, ≥ 4: a parabola has 3
    /// coefficients, so the residual of eq. 21 needs more points to mean
    /// anything (not in the paper).
    pub min_points: usize,
    /// σ_edge: residual standard deviation below which edge following may be
    /// entered, metres (Table 1: 0.15 m).
    pub sigma_enter: f64,
    /// σ_path: residual standard deviation above which edge following is
    /// left, metres (Table 1: 0.5 m).
    pub sigma_exit: f64,
    /// l_end, metres, ≥ 0: a chain stopped by a break of the edge (a gap, a
    /// corner, the rotation limit) must be longer than l_end to be followed
    /// (EDGE-PIECE-END; not in the paper). 0 never acts.
    pub min_end_chain_length: f64,
    /// x_ahead, metres, > 0: a chain whose first point lies farther ahead
    /// of the robot than x_ahead starts at a piece's end face and is not
    /// followed (EDGE-PIECE-END; not in the paper). `f64::MAX` never acts.
    pub max_start_ahead: f64,
    /// The search for the next piece's line ahead when the chain gives no
    /// valid estimate (EDGE-LOOK-AHEAD; not in the paper); `None`: off.
    pub look_ahead: Option<LookAhead>,
    /// Whether the chain is read as its least-squares straight line
    /// instead of eq. 10's parabola (EDGE-STRAIGHT; not in the paper);
    /// `false`: the paper's parabola.
    pub straight: bool,
}

/// The most starts the look-ahead search tries: `x_far / Δx` is at most
/// this (EDGE-LOOK-AHEAD), which bounds its work to that many chains.
pub const MAX_LOOK_AHEAD_STEPS: u16 = 64;

/// The parameters of the look-ahead search (EDGE-LOOK-AHEAD): chains are
/// built with the circle's translation starting at x = Δx, 2Δx, … up to
/// x_far ahead of the robot; the first chain found, its first `end_cap`
/// metres dropped, gives the next piece's line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LookAhead {
    /// l_cap, metres, ≥ 0: the length along x dropped from the start of
    /// the chain found ahead (the next piece's end cap).
    pub end_cap: f64,
    /// Δx, metres, > 0: the step between the abscissae the search starts from.
    pub step: f64,
    /// x_far, metres, ≥ Δx and at most [`MAX_LOOK_AHEAD_STEPS`] steps: the
    /// farthest abscissa the search starts from.
    pub farthest: f64,
    /// l_fit, metres, > 0: the shortest extent along x of the part fitted.
    pub min_span: f64,
}

impl LookAhead {
    /// The values measured on ragged hedges with gaps: l_cap = 0.5 m,
    /// Δx = 0.5 m, x_far = 4 m, l_fit = 1 m (EDGE-LOOK-AHEAD).
    pub const HEDGE: Self = Self {
        end_cap: 0.5,
        step: 0.5,
        farthest: 4.0,
        min_span: 1.0,
    };
}

impl EdgeParameters {
    /// Table 1 of Pierre 2022 for edge following, completed with the library's
    /// choices for the values the paper does not give: θ_max = π/2,
    /// l_min = 1.5 m, w_max = 1 m, 5 points at least (`spec/pierre2022.md`,
    /// EDGE-CONFIG), and the rules beyond the paper: l_link = 1 m (EDGE-GAP)
    /// and φ_turn = π/4 (EDGE-CORNER); the piece-end rule is off
    /// (EDGE-PIECE-END: l_end = 0, x_ahead = `f64::MAX`) and so are the
    /// look-ahead (EDGE-LOOK-AHEAD) and the straight reading (EDGE-STRAIGHT).
    pub const PIERRE2022: Self = Self {
        radius: 1.0,
        max_rotation: FRAC_PI_2,
        max_chain_length: 3.0,
        search_distance: 3.0,
        offset: 1.4,
        min_chain_length: 1.5,
        max_link: 1.0,
        max_turn: FRAC_PI_4,
        max_width: 1.0,
        min_points: 5,
        sigma_enter: 0.15,
        sigma_exit: 0.5,
        min_end_chain_length: 0.0,
        max_start_ahead: f64::MAX,
        look_ahead: None,
        straight: false,
    };
}

/// A validated edge-detector configuration (EDGE-CONFIG).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeConfig {
    radius: f64,
    max_rotation: f64,
    max_chain_length: f64,
    search_distance: f64,
    offset: f64,
    min_chain_length: f64,
    max_link: f64,
    cos_max_turn: f64,
    max_turn: f64,
    max_width: f64,
    min_points: usize,
    thresholds: QualityThresholds,
    min_end_chain_length: f64,
    max_start_ahead: f64,
    look_ahead: Option<LookAhead>,
    straight: bool,
}

fn require(ok: bool, violated: &'static str) -> Result<(), Precondition> {
    if ok {
        Ok(())
    } else {
        Err(Precondition::new("EDGE-CONFIG", violated))
    }
}

impl EdgeConfig {
    /// Validates `p` once, so that detection never re-checks it.
    ///
    /// Errors with `EDGE-CONFIG` naming the failed condition (every value
    /// finite; `r > 0`; `0 < θ_max < 2π`; `l_max > 0`; search distance > 0;
    /// `D ≥ 0`; `0 ≤ l_min < l_max`; `l_link > 0`; `0 < φ_turn ≤ π`;
    /// `w_max > 0`; at least 4 points; `σ_edge > 0`; `l_end ≥ 0`;
    /// `x_ahead > 0`), and with
    /// `SW-THRESHOLDS` when `σ_edge < σ_path` does not hold.
    //= spec/pierre2022.md#edge-config-detector-configuration
    //# A configuration MUST be refused at construction, with an error naming
    //# the requirement, unless r > 0, 0 < θ_max < 2π, l_max > 0, the search
    //# distance is > 0, D ≥ 0, 0 ≤ l_min < l_max, l_link > 0,
    //# 0 < φ_turn ≤ π, w_max > 0, the fewest chain points is at least 4 and
    //# 0 < σ_edge < σ_path, every value being finite.
    //= spec/pierre2022.md#edge-piece-end-a-chain-at-a-piece-s-end-is-not-followed
    //# A configuration MUST be refused with `EDGE-CONFIG` unless l_end ≥ 0 and
    //# x_ahead > 0, both finite.
    pub fn new(p: &EdgeParameters) -> Result<Self, Precondition> {
        let values = [
            p.radius,
            p.max_rotation,
            p.max_chain_length,
            p.search_distance,
            p.offset,
            p.min_chain_length,
            p.max_link,
            p.max_turn,
            p.max_width,
            p.sigma_enter,
            p.sigma_exit,
            p.min_end_chain_length,
            p.max_start_ahead,
        ];
        require(
            values.iter().all(|v| v.is_finite()),
            "every parameter must be finite",
        )?;
        require(p.radius > 0.0, "radius r must be > 0")?;
        require(
            p.max_rotation > 0.0 && p.max_rotation < TAU,
            "theta_max must be in (0, 2 pi)",
        )?;
        require(p.max_chain_length > 0.0, "l_max must be > 0")?;
        require(p.search_distance > 0.0, "search distance must be > 0")?;
        require(p.offset >= 0.0, "desired lateral distance D must be >= 0")?;
        require(
            p.min_chain_length >= 0.0 && p.min_chain_length < p.max_chain_length,
            "l_min must be in [0, l_max)",
        )?;
        require(p.max_link > 0.0, "the longest link l_link must be > 0")?;
        require(
            p.max_turn > 0.0 && p.max_turn <= PI,
            "the largest turn phi_turn must be in (0, pi]",
        )?;
        require(p.max_width > 0.0, "w_max must be > 0")?;
        require(p.min_points >= 4, "the fewest chain points must be >= 4")?;
        require(p.sigma_enter > 0.0, "sigma_edge must be > 0")?;
        require(
            p.min_end_chain_length >= 0.0,
            "the piece-end chain length l_end must be >= 0",
        )?;
        require(
            p.max_start_ahead > 0.0,
            "the farthest chain start ahead x_ahead must be > 0",
        )?;
        let thresholds = QualityThresholds::new(p.sigma_enter, p.sigma_exit, Better::Lower)?;
        if let Some(a) = &p.look_ahead {
            check_look_ahead(a)?;
        }
        Ok(Self {
            radius: p.radius,
            max_rotation: p.max_rotation,
            max_chain_length: p.max_chain_length,
            search_distance: p.search_distance,
            offset: p.offset,
            min_chain_length: p.min_chain_length,
            max_link: p.max_link,
            // A turn of π or more never stops a chain, rounding included.
            cos_max_turn: if p.max_turn >= PI {
                -2.0
            } else {
                libm::cos(p.max_turn)
            },
            max_turn: p.max_turn,
            max_width: p.max_width,
            min_points: p.min_points,
            thresholds,
            min_end_chain_length: p.min_end_chain_length,
            max_start_ahead: p.max_start_ahead,
            look_ahead: p.look_ahead,
            straight: p.straight,
        })
    }

    /// The configuration of [`EdgeParameters::PIERRE2022`].
    pub fn pierre2022() -> Result<Self, Precondition> {
        Self::new(&EdgeParameters::PIERRE2022)
    }

    /// Radius r of the rolling circle.
    #[must_use]
    pub const fn radius(&self) -> Meters {
        Meters(self.radius)
    }

    /// Largest rotation θ_max about one pivot.
    #[must_use]
    pub const fn max_rotation(&self) -> Radians {
        Radians(self.max_rotation)
    }

    /// Chain length l_max.
    #[must_use]
    pub const fn max_chain_length(&self) -> Meters {
        Meters(self.max_chain_length)
    }

    /// Largest translation of the circle when searching the first point.
    #[must_use]
    pub const fn search_distance(&self) -> Meters {
        Meters(self.search_distance)
    }

    /// Desired lateral distance D to the edge.
    #[must_use]
    pub const fn offset(&self) -> Meters {
        Meters(self.offset)
    }

    /// Chain length l_min to exceed.
    #[must_use]
    pub const fn min_chain_length(&self) -> Meters {
        Meters(self.min_chain_length)
    }

    /// Longest link l_link between consecutive chain points (EDGE-GAP).
    #[must_use]
    pub const fn max_link(&self) -> Meters {
        Meters(self.max_link)
    }

    /// Largest turn φ_turn of a link from the chain's direction (EDGE-CORNER).
    #[must_use]
    pub const fn max_turn(&self) -> Radians {
        Radians(self.max_turn)
    }

    /// cos φ_turn, computed once.
    pub(super) const fn cos_max_turn(&self) -> f64 {
        self.cos_max_turn
    }

    /// Chain spread w_max along y to stay below.
    #[must_use]
    pub const fn max_width(&self) -> Meters {
        Meters(self.max_width)
    }

    /// Fewest chain points for a detection.
    #[must_use]
    pub const fn min_points(&self) -> usize {
        self.min_points
    }

    /// l_end, the length a chain stopped by a break must exceed (EDGE-PIECE-END).
    #[must_use]
    pub const fn min_end_chain_length(&self) -> Meters {
        Meters(self.min_end_chain_length)
    }

    /// x_ahead, the farthest a chain's first point may lie ahead of the
    /// robot (EDGE-PIECE-END).
    #[must_use]
    pub const fn max_start_ahead(&self) -> Meters {
        Meters(self.max_start_ahead)
    }

    /// The look-ahead search, when on (EDGE-LOOK-AHEAD).
    #[must_use]
    pub const fn look_ahead(&self) -> Option<&LookAhead> {
        self.look_ahead.as_ref()
    }

    /// Whether the chain is read as a straight line (EDGE-STRAIGHT).
    #[must_use]
    pub const fn straight(&self) -> bool {
        self.straight
    }

    /// σ_edge / σ_path hysteresis on the residual standard deviation.
    #[must_use]
    pub const fn thresholds(&self) -> QualityThresholds {
        self.thresholds
    }
}

/// Refuses look-ahead parameters out of their domain (EDGE-LOOK-AHEAD).
//= spec/pierre2022.md#edge-look-ahead-the-next-piece-s-line-seen-ahead
//# A configuration with the look-ahead on MUST be refused with
//# `EDGE-LOOK-AHEAD` unless l_cap ≥ 0, Δx > 0, Δx ≤ x_far ≤ 64 Δx and
//# l_fit > 0, every value finite.
fn check_look_ahead(a: &LookAhead) -> Result<(), Precondition> {
    let ok = |ok: bool, violated: &'static str| {
        if ok {
            Ok(())
        } else {
            Err(Precondition::new("EDGE-LOOK-AHEAD", violated))
        }
    };
    ok(
        [a.end_cap, a.step, a.farthest, a.min_span]
            .iter()
            .all(|v| v.is_finite()),
        "every look-ahead parameter must be finite",
    )?;
    ok(a.end_cap >= 0.0, "the end cap l_cap must be >= 0")?;
    ok(a.step > 0.0, "the step dx must be > 0")?;
    ok(
        a.farthest >= a.step && a.farthest <= f64::from(MAX_LOOK_AHEAD_STEPS) * a.step,
        "the farthest start x_far must be within [dx, 64 dx]",
    )?;
    ok(a.min_span > 0.0, "the fitted extent l_fit must be > 0")
}
