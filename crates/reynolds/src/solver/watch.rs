//! How a steady solve's cycles are watched on the finest grid: whether they have stalled, and
//! whether they swing with period two.

use super::CycleLog;

/// Finest-grid cycles in a row over which a swing with period two is judged ([`swings`]): four
/// changes of the central film.
const SWING_CYCLES: usize = 5;

/// The change of the central film, relative to it, above which a swing is judged in every
/// cycle, growing or not: a hundred times the stop rule's film tolerance (1e-4 a cycle). The
/// swing at 0.3 m/s, 20 N on 385² moves it by 5–18 % a cycle from its third cycle on the finest
/// grid; the meniscus that rocks by a cell at 5 mm/s, 80 N on 1793² by 1e-4, and there smaller
/// changes stall the cycles where 0.4 converges in 20.
const SWING_SIZE: f64 = 1e-2;

/// Whether the last [`SWING_CYCLES`] cycles of `history` on the grid of `points` swing with
/// period two: the central film's change changes sign every cycle, and the changes are each at
/// least [`SWING_SIZE`] of the film, or grow every cycle from above the stop rule's
/// `film_tolerance` (0.3 m/s, 5 N on 257²: from 2e-4 of the film, 1.1× a cycle, to 1 % twenty
/// cycles later). The Gauss–Seidel changes overshoot; smaller ones end it (docs/decisions.md,
/// "Smaller Gauss–Seidel changes for the fed solve").
pub(super) fn swings(history: &[CycleLog], points: usize, film_tolerance: f64) -> bool {
    let films: Vec<f64> = history
        .iter()
        .rev()
        .filter(|c| c.points == points)
        .take(SWING_CYCLES)
        .map(|c| c.central_film)
        .collect();
    if films.len() < SWING_CYCLES {
        return false;
    }
    // Newest first: `changes[0]` is the last cycle's.
    let changes: Vec<f64> = films.windows(2).map(|w| w[0] - w[1]).collect();
    let relative: Vec<f64> = changes.iter().zip(&films).map(|(d, h)| (d / h).abs()).collect();
    let large = relative.iter().all(|&r| r >= SWING_SIZE);
    let growing =
        relative.windows(2).all(|r| r[0] > r[1]) && relative[SWING_CYCLES - 2] > film_tolerance;
    changes.windows(2).all(|c| c[0] * c[1] < 0.0) && (large || growing)
}

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

    /// Finest-grid cycles on 257² whose central films are `films`, oldest first.
    fn films(films: &[f64]) -> Vec<CycleLog> {
        let mut h = history(films.len(), |_| 0.0);
        h.iter_mut().zip(films).for_each(|(c, &f)| c.central_film = f);
        h
    }

    #[test]
    fn a_swing_with_period_two_is_told_from_a_film_that_converges_or_rocks() {
        let tol = 1e-4;
        // The swing at 0.3 m/s, 20 N on 385² (its cycles 5 to 9 on the finest grid, ×1e-2):
        // changes of 5–18 % alternating in sign.
        let swing = films(&[1.10930, 0.99603, 1.12174, 1.07361, 1.13209]);
        assert!(swings(&swing, 257, tol));
        // A coarser grid's cycles are not the finest grid's, nor are four cycles five.
        assert!(!swings(&swing, 513, tol));
        assert!(!swings(&swing[1..], 257, tol));
        // The swing growing from small at 0.3 m/s, 5 N on 257² (cycles 7 to 11): alternating
        // changes of 2e-4 to 4e-4 of the film, each larger than the one before.
        let growing = films(&[2.94146, 2.94088, 2.94184, 2.94074, 2.94200]);
        assert!(swings(&growing, 257, tol));
        // The same alternation dying away converges: not a swing.
        let dying = films(&[2.94200, 2.94074, 2.94184, 2.94088, 2.94146]);
        assert!(!swings(&dying, 257, tol));
        // The meniscus rocking by a cell at 5 mm/s, 80 N on 1793² (central film moving by 1e-4
        // with no pattern), and a film settling from one side: neither.
        assert!(!swings(&films(&[1.36453, 1.36452, 1.36441, 1.36440, 1.36444]), 257, tol));
        assert!(!swings(&films(&[1.30, 1.34, 1.35, 1.355, 1.3552]), 257, tol));
        // Alternating but below the stop rule's tolerance, growing or not: the cycles'
        // rounding, left to the stop rule.
        assert!(!swings(&films(&[1.0, 1.00001, 0.99998, 1.00002, 0.99997]), 257, tol));
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
