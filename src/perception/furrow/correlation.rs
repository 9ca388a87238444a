//! The plant model of eq. 12 and the normalised correlation of eq. 13
//! (Pierre 2022, section 2.3; `spec/pierre2022.md` FUR-SIGNAL, FUR-TEMPLATE,
//! FUR-CORRELATION).

use crate::error::Precondition;
use crate::geometry::units::Meters;

/// Samples whose magnitude exceeds this many metres are not heights a LiDAR
/// measures; they count as 0 so that squared sums stay finite (FUR-CORRELATION).
pub const MAX_SAMPLE: f64 = 1.0e6;

/// The grid the correlation reads samples on, metres: 2⁻²⁴ m ≈ 6e−8 m, far
/// below any LiDAR's resolution (FUR-CORRELATION). Each sample is rounded to
/// the nearest multiple of it, so a height below half of it counts as 0, and
/// the sums of eq. 13 are sums of integers, exact whatever the heights.
pub const SAMPLE_QUANTUM: f64 = 1.0 / 16_777_216.0;

/// 1 / [`SAMPLE_QUANTUM`], exactly.
const PER_QUANTUM: f64 = 16_777_216.0;

/// The rectangular plant model of eq. 12, with zero margins (FUR-TEMPLATE).
///
/// Template index `i` runs over `[−half, half]` with `half = (width − 1)/2 +
/// margin`; `z_r[i] = height` when `|i| ≤ (width − 1)/2` (the support, `width`
/// rays) and `0` on the `margin` rays on each side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Template {
    width: usize,
    margin: usize,
    height: Meters,
    energy: f64,
}

impl Template {
    /// A rectangle `width` rays wide and `height` m high, framed by `margin`
    /// rays of zeros on each side.
    ///
    /// Errors with `FUR-TEMPLATE` unless `width` is odd (so the rectangle has
    /// a centre ray, `[−w/2, w/2]` of eq. 12 holding exactly `w` integers),
    /// `height > 0`, the total length `width + 2 margin` fits in `u32` and
    /// `R = width · height²` is finite.
    //= spec/pierre2022.md#fur-template-rectangular-plant-model-with-zero-margins
    //# A template whose width is even or zero, whose height is not positive,
    //# or whose length overflows MUST be refused with an error naming
    //# FUR-TEMPLATE.
    pub fn new(width: usize, margin: usize, height: Meters) -> Result<Self, Precondition> {
        if width % 2 == 0 {
            return Err(Precondition::new(
                "FUR-TEMPLATE",
                "template width must be an odd number of rays (>= 1)",
            ));
        }
        if height.get() <= 0.0 {
            return Err(Precondition::new(
                "FUR-TEMPLATE",
                "template height must be > 0",
            ));
        }
        let overflow = Precondition::new("FUR-TEMPLATE", "template length overflows");
        let length = margin
            .checked_mul(2)
            .and_then(|m2| m2.checked_add(width))
            .ok_or(overflow)?;
        u32::try_from(length).map_err(|_| overflow)?;
        let support = u32::try_from(width).map_err(|_| overflow)?;
        let energy = f64::from(support) * height.get() * height.get();
        if !energy.is_finite() {
            return Err(Precondition::new(
                "FUR-TEMPLATE",
                "template energy w h^2 overflows",
            ));
        }
        Ok(Self {
            width,
            margin,
            height,
            energy,
        })
    }

    /// Width of the rectangle, in rays (odd).
    #[must_use]
    pub const fn width(&self) -> usize {
        self.width
    }

    /// Zero rays on each side of the rectangle.
    #[must_use]
    pub const fn margin(&self) -> usize {
        self.margin
    }

    /// Height of the rectangle, m.
    #[must_use]
    pub const fn height(&self) -> Meters {
        self.height
    }

    /// Half the support: `(width − 1)/2`.
    #[must_use]
    pub const fn half_width(&self) -> usize {
        self.width / 2
    }

    /// Half the whole template: `(width − 1)/2 + margin` (validated not to overflow).
    #[must_use]
    pub const fn half_length(&self) -> usize {
        self.half_width().saturating_add(self.margin)
    }

    /// The template's length in rays, `width + 2 margin`.
    #[must_use]
    pub const fn length(&self) -> usize {
        self.margin.saturating_mul(2).saturating_add(self.width)
    }

    /// `z_r` at offset `i` from the centre (eq. 12): `height` on the support, else 0.
    //= spec/pierre2022.md#fur-template-rectangular-plant-model-with-zero-margins
    //# The template MUST be z_r[i] = h_ref for |i| ≤ (w_ref − 1)/2 and z_r[i] = 0
    //# for the m zero rays on each side, with i ∈ [−L/2, L/2] and L = w_ref + 2m.
    #[must_use]
    pub fn value(&self, offset: isize) -> f64 {
        if offset.unsigned_abs() <= self.half_width() {
            self.height.get()
        } else {
            0.0
        }
    }

    /// `R = Σ_i z_r[i]² = width · height²` (eq. 13).
    #[must_use]
    pub const fn energy(&self) -> f64 {
        self.energy
    }
}

/// The correlation input `z_a` of one ray (FUR-SIGNAL): its height when it is
/// above the noise floor, and 0 for ground, noise and dropped rays.
//= spec/pierre2022.md#fur-signal-height-signal-with-a-noise-floor
//# The signal z_a of a window ray MUST be its height z when z > z_floor and
//# 0 otherwise; a dropped ray MUST count as 0.
#[must_use]
pub fn height_signal(height: Option<Meters>, floor: Meters) -> f64 {
    match height {
        Some(z) if z.get() > floor.get() => z.get(),
        _ => 0.0,
    }
}

/// 1.5 · 2⁵²: added to a number of magnitude below 2⁵¹, it rounds that
/// number to the nearest whole one (ties to even) and leaves it in the low
/// bits of the sum, which lies in [2⁵², 2⁵³).
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// The bits of [`ROUNDER`].
const ROUNDER_BITS: u64 = ROUNDER.to_bits();

/// A sample as the correlation reads it, in multiples of [`SAMPLE_QUANTUM`]:
/// the value rounded to the nearest multiple (ties to even); non-finite or
/// absurd values count as 0. |result| ≤ 10⁶ · 2²⁴ < 2⁴⁴.
fn sample(value: f64) -> i64 {
    if value.is_finite() && libm::fabs(value) <= MAX_SAMPLE {
        // An exact scaling by a power of two (|scaled| < 2⁴⁴), rounded by the
        // addition; the difference of the bits is the whole number, in two's
        // complement.
        let sum = value * PER_QUANTUM + ROUNDER;
        i64::from_ne_bytes(sum.to_bits().wrapping_sub(ROUNDER_BITS).to_ne_bytes())
    } else {
        0
    }
}

/// An exact integer sum as an `f64`: one rounding when it fits an `i64`
/// (as every window of real heights does), else at most four (relative
/// error below 4 · 2⁻⁵³), from its 32-bit limbs.
pub(crate) fn to_f64(v: i128) -> f64 {
    if let Ok(small) = i64::try_from(v) {
        // small = high · 2³² + low, high in i32, low in u32.
        let high = i32::try_from(small.wrapping_shr(32)).unwrap_or(0);
        let low = u32::try_from(small & 0xffff_ffff).unwrap_or(0);
        return f64::from(high) * 4_294_967_296.0 + f64::from(low);
    }
    let magnitude = v.unsigned_abs();
    let mut x = 0.0_f64;
    for shift in [96_u32, 64, 32, 0] {
        let limb = u32::try_from(magnitude.wrapping_shr(shift) & 0xffff_ffff).unwrap_or(0);
        x = x * 4_294_967_296.0 + f64::from(limb);
    }
    if v < 0 {
        -x
    } else {
        x
    }
}

/// The exact sums of one window: `S` over the support, `T` and `A` over
/// the whole window, in quanta and squared quanta. With |sample| < 2⁴⁴ and
/// at most 2³² samples (the template length fits `u32`), |S|, |T| < 2⁷⁶ and
/// A < 2¹²⁰ (a square below 2⁸⁸): no integer operation wraps, so the
/// wrapping ones are exact. Shared with the vine detector's Pearson score
/// (VINE-CORRELATION), which reads `T` as well.
#[derive(Default)]
pub(crate) struct Sums {
    /// S = Σ z over the support.
    pub(crate) support: i128,
    /// T = Σ z over the whole window.
    pub(crate) total: i128,
    /// A = Σ z² over the whole window.
    pub(crate) energy: i128,
}

impl Sums {
    fn add_window(&mut self, z: i64) {
        self.total = self.total.wrapping_add(i128::from(z));
        self.energy = self
            .energy
            .wrapping_add(i128::from(z).wrapping_mul(i128::from(z)));
    }

    fn remove_window(&mut self, z: i64) {
        self.total = self.total.wrapping_sub(i128::from(z));
        self.energy = self
            .energy
            .wrapping_sub(i128::from(z).wrapping_mul(i128::from(z)));
    }

    fn add_support(&mut self, z: i64) {
        self.support = self.support.wrapping_add(i128::from(z));
    }

    fn remove_support(&mut self, z: i64) {
        self.support = self.support.wrapping_sub(i128::from(z));
    }

    /// c = h S / sqrt(A R), back in metres (exact scalings by powers of two).
    fn score(&self, template: &Template) -> f64 {
        let s = to_f64(self.support) * SAMPLE_QUANTUM;
        let a = to_f64(self.energy) * (SAMPLE_QUANTUM * SAMPLE_QUANTUM);
        score(template.height().get() * s, a, template.energy())
    }
}

/// The score from the sums of eq. 13: `c = N / sqrt(A R)`, 0 where `A = 0`
/// (an all-zero window: nothing to correlate), clamped to [−1, 1] against
/// rounding (Cauchy–Schwarz bounds the exact value).
fn score(numerator: f64, a: f64, r: f64) -> f64 {
    if a.is_nan() || a <= 0.0 {
        return 0.0;
    }
    let c = numerator / libm::sqrt(a * r);
    if c.is_finite() {
        c.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

/// The normalised correlation of eq. 13 by its definition, `O(N · L)`: the
/// reference against which [`correlate`] is tested.
///
/// `out[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)` with `A = Σ_i z_a[k+i]²`,
/// `R = Σ_i z_r[i]²`, `i ∈ [−half, half]`, for every centre `k` where the whole
/// template fits (`half ≤ k < n − half`); `out[k] = 0` elsewhere and where
/// `A = 0`. Samples are read on the grid of [`SAMPLE_QUANTUM`] (rounded to
/// the nearest multiple) and the sums are exact; samples that are not finite
/// or exceed [`MAX_SAMPLE`] count as 0. Since `z_r` is `h_ref` on the support and
/// 0 elsewhere, `Σ_i z_r[i] z_a[k+i] = h_ref · Σ_support z_a[k+i]`.
///
/// Errors with `FUR-CORRELATION` when `out` is shorter than `signal`.
//= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
//# The score at centre ray k MUST be c[k] = Σ_i z_r[i] z_a[k+i] / sqrt(A R)
//# with A = Σ_i z_a[k+i]² and R = Σ_i z_r[i]², both sums over the template
//# index i ∈ [−L/2, L/2], for every k where the whole template lies in the
//# window; elsewhere, and where A = 0, c[k] MUST be 0.
pub fn correlate_direct(
    signal: &[f64],
    template: &Template,
    out: &mut [f64],
) -> Result<(), Precondition> {
    let out = prepare(signal, out)?;
    let half = template.half_length();
    for (k, slot) in out.iter_mut().enumerate() {
        let Some(start) = k.checked_sub(half) else {
            continue;
        };
        let Some(window) = start
            .checked_add(template.length())
            .and_then(|end| signal.get(start..end))
        else {
            continue;
        };
        let mut sums = Sums::default();
        let mut offset = 0_isize.saturating_sub_unsigned(half);
        for &z in window {
            let z = sample(z);
            if template.value(offset) > 0.0 {
                sums.add_support(z);
            }
            sums.add_window(z);
            offset = offset.saturating_add(1);
        }
        *slot = sums.score(template);
    }
    Ok(())
}

/// Checks `out` against `signal` and zeroes the part that will be written.
fn prepare<'o>(signal: &[f64], out: &'o mut [f64]) -> Result<&'o mut [f64], Precondition> {
    let out = out.get_mut(..signal.len()).ok_or(Precondition::new(
        "FUR-CORRELATION",
        "the output is shorter than the signal",
    ))?;
    out.fill(0.0);
    Ok(out)
}

/// The normalised correlation of eq. 13, `O(N)` whatever the template length:
/// the support sum `S` and the window energy `A` slide by one ray per centre
/// (one sample enters, one leaves), and `c[k] = height · S / sqrt(A R)`.
///
/// The sums are integers in quanta of [`SAMPLE_QUANTUM`], so sliding them is
/// exact: the result is [`correlate_direct`]'s, bit for bit, whatever the
/// heights (a tall sample that left the window leaves no rounding behind),
/// with the same outputs where the template does not fit and the same errors.
//= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
//# The scores of a window of N rays MUST be computed with running sums, in
//# O(N) operations whatever the template length.
//= spec/pierre2022.md#fur-correlation-normalised-correlation-by-running-sums
//# Each sample z_a MUST be read as the nearest multiple of `SAMPLE_QUANTUM`
//# (2⁻²⁴ m), and the running sums MUST equal the sums of the definition
//# exactly, whatever the heights.
pub fn correlate(signal: &[f64], template: &Template, out: &mut [f64]) -> Result<(), Precondition> {
    let out = prepare(signal, out)?;
    let half = template.half_length();
    slide(
        signal,
        template.length(),
        template.margin(),
        template.width(),
        |start, sums| {
            if let Some(slot) = out.get_mut(start.saturating_add(half)) {
                *slot = sums.score(template);
            }
        },
    );
    Ok(())
}

/// Slides a window of `length` samples over `signal`, one sample in and
/// one out per step, its support the `width` samples from `offset` within
/// it, and calls `visit(start, sums)` with the exact [`Sums`] of the window
/// starting at each `start` where it fits: `O(N)` whatever the length.
/// Samples are read by [`SAMPLE_QUANTUM`] as in [`correlate_direct`].
pub(crate) fn slide(
    signal: &[f64],
    length: usize,
    offset: usize,
    width: usize,
    mut visit: impl FnMut(usize, &Sums),
) {
    let n = signal.len();
    if length == 0 || n < length {
        return;
    }
    let z = |i: usize| signal.get(i).copied().map_or(0, sample);
    let support_end = offset.saturating_add(width);
    let mut sums = Sums::default();
    for i in 0..length {
        let v = z(i);
        sums.add_window(v);
        if i >= offset && i < support_end {
            sums.add_support(v);
        }
    }
    let last = n.saturating_sub(length);
    for start in 0..=last {
        visit(start, &sums);
        if start < last {
            // The window loses `start` and gains `start + length`; the
            // support loses `start + offset` and gains `start + support_end`.
            sums.remove_window(z(start));
            sums.add_window(z(start.saturating_add(length)));
            sums.remove_support(z(start.saturating_add(offset)));
            sums.add_support(z(start.saturating_add(support_end)));
        }
    }
}
