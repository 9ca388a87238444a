//! Detection quality of an edge chain (Pierre 2022, eq. 21 as corrected,
//! Table 1; EDGE-QUALITY): chain length, spread along y, and the residual
//! standard deviation of the parabola, graded into a [`Verdict`].

use super::config::EdgeConfig;
use crate::error::Precondition;
use crate::geometry::fit::ParabolaFit;
use crate::geometry::frame::{Point2, Robot};
use crate::geometry::units::Meters;
use crate::perception::Verdict;

/// The three measures of eq. 21 for one chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeQuality {
    /// Polyline length of the chain, metres (compared with l_min).
    pub length: Meters,
    /// Spread of the chain along the robot's y axis, `max p_y − min p_y`,
    /// metres (compared with w_max).
    pub width: Meters,
    /// Residual standard deviation `sqrt(mean((p_y − (a p_x² + b p_x + c))²))`,
    /// metres (compared with σ_edge and σ_path).
    pub residual_std: Meters,
}

impl EdgeQuality {
    /// The measures of `chain_points` (of polyline length `length`) against `parabola`.
    ///
    /// Errors with `EDGE-QUALITY` for an empty chain and `LIB-FINITE` on overflow.
    //= spec/pierre2022.md#edge-quality-detection-quality-and-verdict
    //# The residual standard deviation MUST be the square root of the mean of
    //# the squared residuals (p_y − (a p_x² + b p_x + c))² over the chain, and
    //# the width MUST be the largest difference p_{y,1} − p_{y,2} over pairs of
    //# chain points.
    pub fn measure(
        chain_points: &[Point2<Robot>],
        length: Meters,
        parabola: &ParabolaFit,
    ) -> Result<Self, Precondition> {
        let mut n = 0.0_f64;
        let mut sum_sq = 0.0_f64;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in chain_points {
            let residual = parabola.residual(*p)?;
            sum_sq += residual * residual;
            n += 1.0;
            lo = lo.min(p.y());
            hi = hi.max(p.y());
        }
        if chain_points.is_empty() {
            return Err(Precondition::new("EDGE-QUALITY", "empty chain"));
        }
        Ok(Self {
            length,
            width: Meters::new(hi - lo)?,
            residual_std: Meters::new(libm::sqrt(sum_sq / n))?,
        })
    }

    /// The verdict of eq. 21 with Table 1's hysteresis: `Exit` when the chain
    /// is not longer than l_min or not narrower than w_max; otherwise the
    /// residual standard deviation graded by `SW-CLASSIFY` (`Enter` below
    /// σ_edge, `Exit` above σ_path, `Hold` between).
    //= spec/pierre2022.md#edge-quality-detection-quality-and-verdict
    //# The verdict of a fitted chain MUST be Exit when its length is not greater
    //# than l_min or its width is not less than w_max, and otherwise the
    //# classification of its residual standard deviation against σ_edge (enter)
    //# and σ_path (exit), smaller being better.
    #[must_use]
    pub fn grade(&self, config: &EdgeConfig) -> Verdict {
        // Meters are finite, so these comparisons are total.
        if self.length.get() <= config.min_chain_length().get()
            || self.width.get() >= config.max_width().get()
        {
            Verdict::Exit
        } else {
            config.thresholds().classify(self.residual_std.get())
        }
    }
}
