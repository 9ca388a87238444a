//! A Mamdani fuzzy inference engine of fixed size (Guyonneau 2022, section
//! 3.3; `spec/guyonneau2022.md`, FUZZY-*): triangle and ramp terms; AND =
//! minimum, implication = algebraic product, aggregation = maximum;
//! defuzzification by the centroid, exact or sampled as FuzzyLite samples it.
//!
//! Rules are conjunctions of input terms (one per input, or none for an
//! input the rule ignores) giving one term per output. Because the
//! implication is a product and the aggregation a maximum, the aggregate of
//! an output is `A(y) = max_t s_t μ_t(y)`, s_t the strongest firing of the
//! rules concluding term t: piecewise linear, so its centroid has a closed
//! form (FUZZY-CENTROID).

use heapless::Vec;

use crate::error::{finite, Precondition};

/// Terms a variable holds at most.
pub const MAX_TERMS: usize = 8;
/// Inputs and outputs an engine holds at most.
pub const MAX_VARIABLES: usize = 4;
/// Rules an engine holds at most.
pub const MAX_RULES: usize = 64;

/// A membership function (FUZZY-TERMS).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Term {
    /// 0 at `left` and `right`, 1 at `peak`, linear between
    /// (`left ≤ peak ≤ right`, `left < right`).
    Triangle {
        /// Left foot.
        left: f64,
        /// Vertex.
        peak: f64,
        /// Right foot.
        right: f64,
    },
    /// 0 at `start`, 1 at `end` and beyond, linear between (`start ≠ end`;
    /// rising when `start < end`, falling otherwise), as FuzzyLite's Ramp.
    Ramp {
        /// Where the membership is 0.
        start: f64,
        /// Where it reaches 1.
        end: f64,
    },
}

impl Term {
    /// Whether the parameters are finite and ordered.
    fn is_valid(&self) -> bool {
        match *self {
            Self::Triangle { left, peak, right } => {
                left.is_finite()
                    && peak.is_finite()
                    && right.is_finite()
                    && left <= peak
                    && peak <= right
                    && left < right
            }
            Self::Ramp { start, end } => {
                start.is_finite() && end.is_finite() && libm::fabs(end - start) > 0.0
            }
        }
    }

    /// μ(x), in [0, 1] (0 for a NaN x).
    //= spec/guyonneau2022.md#fuzzy-terms-triangles-and-ramps
    //# A triangle (l, p, r) MUST have membership (x − l)/(p − l) on [l, p],
    //# (r − x)/(r − p) on [p, r] and 0 elsewhere (1 at x = p); a ramp (s, e)
    //# MUST have membership 0 on the side of s away from e, 1 on the side of e
    //# away from s, and (x − s)/(e − s) between.
    #[must_use]
    pub fn membership(&self, x: f64) -> f64 {
        let mu = match *self {
            Self::Triangle { left, peak, right } => {
                if x < left || x > right {
                    0.0
                } else if x < peak {
                    (x - left) / (peak - left)
                } else if x > peak {
                    (right - x) / (right - peak)
                } else {
                    1.0
                }
            }
            Self::Ramp { start, end } => {
                let t = (x - start) / (end - start);
                t.clamp(0.0, 1.0)
            }
        };
        if mu.is_nan() {
            0.0
        } else {
            mu
        }
    }

    /// The abscissae where the membership bends.
    fn vertices(&self) -> [f64; 3] {
        match *self {
            Self::Triangle { left, peak, right } => [left, peak, right],
            Self::Ramp { start, end } => [start, end, end],
        }
    }
}

/// A linguistic variable: a range and its terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// The lower end of the range.
    pub min: f64,
    /// The upper end of the range.
    pub max: f64,
    /// The terms, by index.
    pub terms: Vec<Term, MAX_TERMS>,
}

/// One rule: the term each input must be (`None`: any), and the term each
/// output is then.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rule {
    /// The antecedent's term per input.
    pub when: [Option<u8>; MAX_VARIABLES],
    /// The consequent's term per output.
    pub then: [Option<u8>; MAX_VARIABLES],
}

/// How an output's aggregate becomes a number (FUZZY-CENTROID).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Defuzzifier {
    /// The centroid of the aggregate, integrated exactly.
    Exact,
    /// FuzzyLite's centroid: the mean of the aggregate's samples at the
    /// middles of `resolution` equal steps of the range, weighted by value.
    Sampled {
        /// Steps, ≥ 1 (FuzzyLite's default is 100).
        resolution: u16,
    },
}

/// One output's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Output {
    /// The defuzzified value, in the output's range; the `stop` value when no
    /// rule fired.
    pub value: f64,
    /// Whether any rule gave this output a non-zero aggregate.
    pub fired: bool,
}

/// A validated engine.
#[derive(Debug, Clone, PartialEq)]
pub struct Engine {
    inputs: Vec<Variable, MAX_VARIABLES>,
    outputs: Vec<Variable, MAX_VARIABLES>,
    rules: Vec<Rule, MAX_RULES>,
    /// The value an output takes when no rule fires, per output.
    stop: Vec<f64, MAX_VARIABLES>,
}

impl Engine {
    /// An engine of `inputs`, `outputs`, `rules`, each output taking the
    /// matching `stop` value (clamped to its range) when no rule fires.
    ///
    /// # Errors
    /// `FUZZY-ENGINE` when a variable's range is not finite and increasing,
    /// a term is not valid (FUZZY-TERMS), a rule names a term a variable
    /// does not have or a variable the engine does not have, or the stop
    /// values do not match the outputs.
    //= spec/guyonneau2022.md#fuzzy-engine-an-engine-checked-once
    //# An engine MUST be refused at construction, with an error naming
    //# FUZZY-ENGINE, when a range is not finite and increasing, a term's
    //# parameters are not finite and ordered, a rule names a term or a
    //# variable that does not exist, or an output has no stop value.
    pub fn new(
        inputs: &[Variable],
        outputs: &[Variable],
        rules: &[Rule],
        stop: &[f64],
    ) -> Result<Self, Precondition> {
        let bad = |why| Err(Precondition::new("FUZZY-ENGINE", why));
        let variable_ok = |v: &Variable| {
            v.min.is_finite()
                && v.max.is_finite()
                && v.min < v.max
                && v.terms.iter().all(Term::is_valid)
        };
        if !inputs.iter().chain(outputs).all(variable_ok) {
            return bad("a range is not finite and increasing, or a term is invalid");
        }
        let names = |side: &[Option<u8>; MAX_VARIABLES], vars: &[Variable]| {
            side.iter()
                .enumerate()
                .all(|(i, t)| match (t, vars.get(i)) {
                    (None, _) => true,
                    (Some(t), Some(v)) => usize::from(*t) < v.terms.len(),
                    (Some(_), None) => false,
                })
        };
        if !rules
            .iter()
            .all(|r| names(&r.when, inputs) && names(&r.then, outputs))
        {
            return bad("a rule names a term or a variable that does not exist");
        }
        if stop.len() != outputs.len() || !stop.iter().all(|s| s.is_finite()) {
            return bad("one finite stop value per output");
        }
        let full =
            || Precondition::new("FUZZY-ENGINE", "more variables or rules than the capacity");
        let mut stops: Vec<f64, MAX_VARIABLES> = Vec::new();
        for (s, v) in stop.iter().zip(outputs) {
            stops.push(s.clamp(v.min, v.max)).map_err(|_| full())?;
        }
        Ok(Self {
            inputs: Vec::from_slice(inputs).map_err(|_| full())?,
            outputs: Vec::from_slice(outputs).map_err(|_| full())?,
            rules: Vec::from_slice(rules).map_err(|_| full())?,
            stop: stops,
        })
    }

    /// The outputs for `inputs` (one value per input variable).
    ///
    /// # Errors
    /// `FUZZY-INPUT` when the number of values is not the number of inputs
    /// or a value is not finite; `LIB-FINITE` on overflow.
    //= spec/guyonneau2022.md#fuzzy-inference-min-product-max
    //# A rule's firing MUST be the minimum of its antecedent terms'
    //# memberships; an output's aggregate MUST be, at each y, the maximum over
    //# the rules concluding on it of the firing times the consequent term's
    //# membership.
    pub fn evaluate(
        &self,
        inputs: &[f64],
        defuzzifier: Defuzzifier,
    ) -> Result<Vec<Output, MAX_VARIABLES>, Precondition> {
        //= spec/guyonneau2022.md#fuzzy-input-inputs-checked-each-evaluation
        //# An evaluation MUST be refused with an error naming FUZZY-INPUT unless it
        //# is given one finite value per input variable.
        if inputs.len() != self.inputs.len() || !inputs.iter().all(|x| x.is_finite()) {
            return Err(Precondition::new(
                "FUZZY-INPUT",
                "one finite value per input variable",
            ));
        }
        // m[i][t]: the membership of input i in its term t, once per term.
        let mut membership = [[0.0_f64; MAX_TERMS]; MAX_VARIABLES];
        for ((m, variable), &x) in membership.iter_mut().zip(&self.inputs).zip(inputs) {
            for (slot, term) in m.iter_mut().zip(&variable.terms) {
                *slot = term.membership(x);
            }
        }
        // s[o][t]: the strongest firing concluding term t of output o.
        let mut strength = [[0.0_f64; MAX_TERMS]; MAX_VARIABLES];
        for rule in &self.rules {
            let mut firing = 1.0_f64;
            for (term, m) in rule.when.iter().zip(&membership).take(inputs.len()) {
                if let Some(&mu) = term.and_then(|t| m.get(usize::from(t))) {
                    firing = firing.min(mu);
                }
            }
            if firing <= 0.0 {
                // A rule that does not fire raises no strength.
                continue;
            }
            for (term, s) in rule
                .then
                .iter()
                .zip(strength.iter_mut())
                .take(self.outputs.len())
            {
                if let Some(slot) = term.and_then(|t| s.get_mut(usize::from(t))) {
                    *slot = slot.max(firing);
                }
            }
        }
        let mut out = Vec::new();
        for ((variable, s), &stop) in self.outputs.iter().zip(&strength).zip(&self.stop) {
            let (area, moment) = match defuzzifier {
                Defuzzifier::Exact => exact(variable, s),
                Defuzzifier::Sampled { resolution } => sampled(variable, s, resolution),
            };
            //= spec/guyonneau2022.md#fuzzy-centroid-exact-and-sampled-centroids
            //# When no rule gives an output a non-zero aggregate, the output MUST be
            //# its stop value, flagged as not fired, never a NaN.
            let fired = area > 0.0;
            let value = if fired {
                finite(moment / area, "fuzzy centroid overflows")?.clamp(variable.min, variable.max)
            } else {
                stop
            };
            let _ = out.push(Output { value, fired });
        }
        Ok(out)
    }
}

/// The aggregate `A(y) = max_t s_t μ_t(y)` of one output.
fn aggregate(variable: &Variable, strength: &[f64; MAX_TERMS], y: f64) -> f64 {
    variable.terms.iter().zip(strength).fold(0.0, |a, (t, &s)| {
        if s > 0.0 {
            a.max(s * t.membership(y))
        } else {
            a
        }
    })
}

/// (∫ A, ∫ y A) over the range by FuzzyLite's sampling.
//= spec/guyonneau2022.md#fuzzy-centroid-exact-and-sampled-centroids
//# The sampled centroid MUST be Σ y_i A(y_i) / Σ A(y_i) over the middles
//# y_i = min + (i + 1/2)(max − min)/N, i = 0, …, N − 1, of N equal steps.
fn sampled(variable: &Variable, strength: &[f64; MAX_TERMS], resolution: u16) -> (f64, f64) {
    let n = f64::from(resolution.max(1));
    let dx = (variable.max - variable.min) / n;
    let (mut area, mut moment) = (0.0, 0.0);
    let mut i = 0.0;
    while i < n {
        let y = variable.min + (i + 0.5) * dx;
        let a = aggregate(variable, strength, y);
        area += a;
        moment += a * y;
        i += 1.0;
    }
    (area, moment)
}

/// (∫ A, ∫ y A) over the range, exactly: A is linear between consecutive
/// breakpoints (the terms' vertices and the crossings of their pieces).
//= spec/guyonneau2022.md#fuzzy-centroid-exact-and-sampled-centroids
//# The exact centroid MUST be ∫ y A(y) dy / ∫ A(y) dy over the output's range,
//# integrated piece by piece between the terms' vertices and the points where
//# two scaled terms cross, where A is linear.
fn exact(variable: &Variable, strength: &[f64; MAX_TERMS]) -> (f64, f64) {
    let (lo, hi) = (variable.min, variable.max);
    // The scaled terms that take part, s_t μ_t.
    let active: Vec<(Term, f64), MAX_TERMS> = variable
        .terms
        .iter()
        .zip(strength)
        .filter(|(_, &s)| s > 0.0)
        .map(|(t, &s)| (*t, s))
        .collect();
    let mut cuts: Vec<f64, { 3 * MAX_TERMS + 2 }> = Vec::new();
    let _ = cuts.push(lo);
    let _ = cuts.push(hi);
    for (t, _) in &active {
        for v in t.vertices() {
            if v > lo && v < hi && !cuts.contains(&v) {
                let _ = cuts.push(v);
            }
        }
    }
    cuts.sort_unstable_by(f64::total_cmp);
    // Each scaled term's value at a cut, computed once: [x0] then [x1].
    let at = |x: f64| -> [f64; MAX_TERMS] {
        let mut v = [0.0; MAX_TERMS];
        for (slot, (t, s)) in v.iter_mut().zip(&active) {
            *slot = s * t.membership(x);
        }
        v
    };
    let n = active.len();
    let (mut area, mut moment) = (0.0, 0.0);
    let mut x0 = lo;
    let mut v0 = at(lo);
    for &x1 in cuts.iter().skip(1) {
        let v1 = at(x1);
        // Every scaled term is one line on [x0, x1]; a line zero at both
        // ends is zero throughout and never above the others.
        let mut lines: [(f64, f64); MAX_TERMS] = [(0.0, 0.0); MAX_TERMS];
        let mut count = 0_usize;
        for (&a, &b) in v0.iter().zip(&v1).take(n) {
            if a > 0.0 || b > 0.0 {
                if let Some(slot) = lines.get_mut(count) {
                    *slot = (a, b);
                    count = count.saturating_add(1);
                }
            }
        }
        let lines = lines.get(..count).unwrap_or_default();
        if !lines.is_empty() {
            let (a, m) = segment(x0, x1, lines);
            area += a;
            moment += m;
        }
        (x0, v0) = (x1, v1);
    }
    (area, moment)
}

/// (∫ A, ∫ y A) over [x0, x1] for A the upper envelope of `lines`, each
/// given by its values at x0 and x1: exact between the lines' crossings,
/// where A is linear.
fn segment(x0: f64, x1: f64, lines: &[(f64, f64)]) -> (f64, f64) {
    // Where two lines cross inside, the maximum may change line (as a share
    // of the segment).
    let mut inner: Vec<f64, { MAX_TERMS * MAX_TERMS }> = Vec::new();
    for (i, &(a0, a1)) in lines.iter().enumerate() {
        for &(b0, b1) in lines.iter().skip(i.saturating_add(1)) {
            let (d0, d1) = (a0 - b0, a1 - b1);
            if (d0 < 0.0 && d1 > 0.0) || (d0 > 0.0 && d1 < 0.0) {
                let _ = inner.push(d0 / (d0 - d1));
            }
        }
    }
    inner.sort_unstable_by(f64::total_cmp);
    let upper = |t: f64| {
        lines
            .iter()
            .fold(0.0_f64, |a, &(l0, l1)| a.max(l0 + t * (l1 - l0)))
    };
    let span = x1 - x0;
    let (mut area, mut moment) = (0.0, 0.0);
    let (mut left, mut a_left) = (x0, lines.iter().fold(0.0_f64, |a, l| a.max(l.0)));
    let ends = inner.iter().map(|&t| (x0 + t * span, upper(t)));
    let last = (x1, lines.iter().fold(0.0_f64, |a, l| a.max(l.1)));
    for (right, a_right) in ends.chain(core::iter::once(last)) {
        let h = right - left;
        area += 0.5 * h * (a_left + a_right);
        moment += h * (left * (2.0 * a_left + a_right) + right * (a_left + 2.0 * a_right)) / 6.0;
        (left, a_left) = (right, a_right);
    }
    (area, moment)
}
