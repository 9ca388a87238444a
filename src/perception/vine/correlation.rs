//! The vine model (Iberraken 2022, section 2.1.2) and the correlation score
//! of eq. 1 with Pearson's normalisation (section 2.1.3;
//! `spec/iberraken2022.md`, VINE-MODEL and VINE-CORRELATION).
//!
//! The running sums are those of furrow pursuing's correlation
//! ([`crate::perception::furrow::correlation`]): exact integer sums of the
//! samples read on the grid of
//! [`SAMPLE_QUANTUM`](crate::perception::furrow::correlation::SAMPLE_QUANTUM),
//! slid one ray per offset, with the window's total added for the means.

use crate::error::Precondition;
use crate::geometry::units::Meters;
use crate::perception::furrow::correlation::{slide, to_f64, Sums};

/// The longest model accepted, in rays (it keeps every integer sum exact).
pub const MAX_MODEL_LENGTH: usize = 4096;

/// The vine model: a square signal `width` rays wide and `height` m high
/// whose base is the ground, framed by `margin` rays of ground on each side
/// (VINE-MODEL).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VineModel {
    width: usize,
    margin: usize,
    height: Meters,
}

impl VineModel {
    /// A square `width` rays wide, `height` m high, with `margin` rays of
    /// ground on each side.
    ///
    /// # Errors
    /// `VINE-MODEL` unless width ≥ 1, margin ≥ 1, height > 0 and the length
    /// width + 2 margin is at most [`MAX_MODEL_LENGTH`].
    //= spec/iberraken2022.md#vine-model-square-vine-model
    //# A model whose width or margin is zero, whose height is not positive, or
    //# whose length exceeds 4096 rays MUST be refused with an error naming
    //# VINE-MODEL.
    pub fn new(width: usize, margin: usize, height: Meters) -> Result<Self, Precondition> {
        let length = margin.checked_mul(2).and_then(|m| m.checked_add(width));
        let ok = width >= 1
            && margin >= 1
            && height.get() > 0.0
            && length.is_some_and(|l| l <= MAX_MODEL_LENGTH);
        if ok {
            Ok(Self {
                width,
                margin,
                height,
            })
        } else {
            Err(Precondition::new(
                "VINE-MODEL",
                "need width >= 1, margin >= 1, height > 0, length <= 4096 rays",
            ))
        }
    }

    /// Width of the square, rays.
    #[must_use]
    pub const fn width(&self) -> usize {
        self.width
    }

    /// Rays of ground on each side.
    #[must_use]
    pub const fn margin(&self) -> usize {
        self.margin
    }

    /// Height of the square, m.
    #[must_use]
    pub const fn height(&self) -> Meters {
        self.height
    }

    /// The model's length, width + 2 margin rays (validated ≤ 4096).
    #[must_use]
    pub const fn length(&self) -> usize {
        self.width
            .saturating_add(self.margin)
            .saturating_add(self.margin)
    }

    /// m_i, i from 0 to length − 1: `height` on the square, 0 on the ground.
    //= spec/iberraken2022.md#vine-model-square-vine-model
    //# The model MUST be m_i = h for the w rays margin ≤ i < margin + w and
    //# m_i = 0 (the ground) for the margin rays on each side.
    #[must_use]
    pub fn value(&self, i: usize) -> f64 {
        if i >= self.margin && i < self.margin.saturating_add(self.width) {
            self.height.get()
        } else {
            0.0
        }
    }
}

/// Pearson's r from the exact sums of one window of `length` samples whose
/// support holds `width`: r = (L S − w T) / sqrt((L A − T²) w (L − w)), 0
/// when the window is flat (L A = T²) or a product leaves `i128`. The
/// model's height cancels: r does not depend on it.
fn pearson(sums: &Sums, length: i128, width: i128) -> f64 {
    let products = (
        length.checked_mul(sums.support),
        width.checked_mul(sums.total),
        length.checked_mul(sums.energy),
        sums.total.checked_mul(sums.total),
    );
    let (Some(ls), Some(wt), Some(la), Some(tt)) = products else {
        return 0.0;
    };
    let spread = la.wrapping_sub(tt);
    if spread <= 0 {
        return 0.0;
    }
    let numerator = ls.wrapping_sub(wt);
    let model = width.wrapping_mul(length.wrapping_sub(width));
    // A perfect match (z = a m + b, a > 0) makes the numerator's square the
    // product exactly: it scores 1 exactly, not 1 within a rounding.
    let product = spread.checked_mul(model);
    if numerator > 0
        && numerator
            .checked_mul(numerator)
            .is_some_and(|n2| Some(n2) == product)
    {
        return 1.0;
    }
    let r = to_f64(numerator) / (libm::sqrt(to_f64(spread)) * libm::sqrt(to_f64(model)));
    if r.is_finite() {
        r.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

/// The correlation score of eq. 1 with Pearson's normalisation at every
/// offset k where the model lies in the signal (k from 0 to N − length),
/// written to `out[k]` (the rest of `out` up to N is 0), in O(N):
/// r(k) = Σ_j (z_{k+j} − z̄_k)(m_j − m̄) / (sqrt(Σ_j (z_{k+j} − z̄_k)²)
/// sqrt(Σ_j (m_j − m̄)²)), z̄_k the mean of the window. A flat window
/// scores 0.
///
/// # Errors
/// `VINE-CORRELATION` when `out` is shorter than `signal`.
//= spec/iberraken2022.md#vine-correlation-pearson-correlation-by-running-sums
//# The score at offset k MUST be
//# r(k) = Σ_j (z_{k+j} − z̄_k)(m_j − m̄) / (sqrt(Σ_j (z_{k+j} − z̄_k)²) ·
//# sqrt(Σ_j (m_j − m̄)²)), the sums over the model's rays j, z̄_k the mean of
//# the window and m̄ the model's, for every offset k where the model lies in
//# the window of rays; a window of equal samples MUST score 0.
//= spec/iberraken2022.md#vine-correlation-pearson-correlation-by-running-sums
//# The scores MUST be computed with running sums, in O(N) operations
//# whatever the model's length.
pub fn correlate(signal: &[f64], model: &VineModel, out: &mut [f64]) -> Result<(), Precondition> {
    let out = out.get_mut(..signal.len()).ok_or(Precondition::new(
        "VINE-CORRELATION",
        "the output is shorter than the signal",
    ))?;
    out.fill(0.0);
    // Both fit i128 (validated length ≤ 4096).
    let length = i128::try_from(model.length()).unwrap_or(0);
    let width = i128::try_from(model.width).unwrap_or(0);
    slide(
        signal,
        model.length(),
        model.margin,
        model.width,
        |k, sums| {
            if let Some(slot) = out.get_mut(k) {
                *slot = pearson(sums, length, width);
            }
        },
    );
    Ok(())
}
