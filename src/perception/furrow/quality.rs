//! The furrow detector's verdict (eq. 22 as corrected, Table 2; Pierre 2022,
//! section 3; `spec/pierre2022.md` FUR-QUALITY).

use crate::perception::{QualityThresholds, Verdict};

/// The verdict of one tick.
///
/// - `Absent` when no line could be fitted (fewer accumulated points than
///   the minimum, FUR-LINE and FUR-FIRST-LINE);
/// - otherwise `Exit` when this scan selected nothing (`P = ∅`, first line of
///   eq. 22), and else the hysteresis classification of the selection's
///   weakest score: for two rows `min(c[k_l], c[k_r])`, for one row the
///   selected maximum's score. With Table 2 (enter 0.4, exit 0.2,
///   [`crate::perception::Better::Higher`]): `Enter` when both maxima exceed
///   0.4, `Exit` when one is below 0.2, `Hold` in between.
//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//# The verdict MUST be Absent when no row line could be fitted from the
//# accumulated points.
//= spec/pierre2022.md#fur-quality-verdict-from-the-weaker-maximum
//# Otherwise the verdict MUST be Exit when the scan yielded no selection,
//# and else the classification (SW-CLASSIFY, larger is better) of the
//# weaker score of the selection: min(c[k_l], c[k_r]) for a pair, c[k] for
//# one row.
#[must_use]
pub fn furrow_verdict(
    thresholds: &QualityThresholds,
    line_fitted: bool,
    weakest_score: Option<f64>,
) -> Verdict {
    if !line_fitted {
        return Verdict::Absent;
    }
    weakest_score.map_or(Verdict::Exit, |q| thresholds.classify(q))
}
