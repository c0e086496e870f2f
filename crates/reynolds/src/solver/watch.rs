//! How a steady solve's cycles are watched on the finest grid: whether they have stalled.

use super::CycleLog;

/// Whether the finest-grid cycles of `history` on `points` have stalled: neither the residual
/// nor the oil unaccounted for (mass conserving; zero otherwise) even halved over the last
/// `window` against the best before it. A fed solve whose meniscus still creeps towards its
/// place lowers the oil steadily while the residual stands (docs/decisions.md, "A loaded
/// point's release within the line").
pub(super) fn stalled_over(history: &[CycleLog], points: usize, window: usize) -> bool {
    // Too few cycles to judge count as halved: no stall yet.
    let halved = |of: fn(&CycleLog) -> f64| {
        let fine: Vec<f64> = history.iter().filter(|c| c.points == points).map(of).collect();
        if window == 0 || fine.len() <= 2 * window {
            return true;
        }
        let (before, last) = fine.split_at(fine.len() - window);
        let best = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min);
        best(before) > 0.0 && best(last) <= 0.5 * best(before)
    };
    !halved(|c| c.residual) && !halved(|c| c.mass_defect)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// `n` finest-grid cycles on 257², the residual standing at 1e-2 and the oil unaccounted
    /// for `oil(k)` at cycle `k`.
    pub(in crate::solver) fn history(n: usize, oil: impl Fn(usize) -> f64) -> Vec<CycleLog> {
        (0..n)
            .map(|k| CycleLog {
                cycle: k + 1,
                points: 257,
                residual: 1e-2,
                load_error: 0.0,
                h00: 0.0,
                central_film: 1e-3,
                minimum_film: 5e-4,
                wall_s: 0.0,
                mass_defect: oil(k),
            })
            .collect()
    }

    #[test]
    fn a_fed_attempt_whose_oil_still_halves_is_not_stalled_though_its_residual_stands() {
        // 3 % less oil unaccounted for a cycle (the rate measured on 1025², 5 mm/s, 40 N, fed
        // 10 nm): over a 40-cycle window it falls to 0.3 of the best before, not stalled.
        assert!(!stalled_over(&history(100, |k| 0.3 * 0.97f64.powi(k as i32)), 257, 40));
        // The oil rocking about 2 % (that case's first attempt from cycle 110 on): stalled.
        assert!(stalled_over(&history(100, |k| 0.02 + 0.002 * (k % 3) as f64), 257, 40));
        // Flooded, no oil measured (zero): the residual alone decides, and it stands.
        assert!(stalled_over(&history(100, |_| 0.0), 257, 40));
        // Too few cycles to judge.
        assert!(!stalled_over(&history(60, |_| 0.02), 257, 40));
    }
}
