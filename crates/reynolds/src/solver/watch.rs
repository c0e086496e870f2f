//! How a steady solve's cycles are watched on the finest grid: whether they have stalled, and
//! where a fed solve's stalled attempt goes on from.

use super::fas::near_best;
use super::steady::given_up;
use super::{CycleLog, ReynoldsError, ReynoldsReport};

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
        let (before, last) = bests(&fine, window);
        before > 0.0 && last <= 0.5 * before
    };
    !halved(|c| c.residual) && !halved(|c| c.mass_defect)
}

/// The least of `values` before their last `window`, and the least over it: what a stall is
/// judged on. `window` must not exceed `values.len()`.
fn bests(values: &[f64], window: usize) -> (f64, f64) {
    let (before, last) = values.split_at(values.len() - window);
    let best = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min);
    (best(before), best(last))
}

/// Finest-grid cycles over which a W-cycle first attempt is judged once, early: at its
/// `2 · EARLY_WINDOW + 1`-th, the last `EARLY_WINDOW` against the best before them
/// ([`stalled_early`]).
pub(super) const EARLY_WINDOW: usize = 4;

/// Whether a fed first attempt's W-cycles have stalled far from the answer by its
/// `2 · EARLY_WINDOW + 1`-th finest-grid cycle of `history` on `points`: neither the residual
/// nor the oil halved over the last [`EARLY_WINDOW`] ([`stalled_over`]), the oil not even
/// lowered below its best before them, and more than `oil_near` of the supply still
/// unaccounted for. Cycles at the multigrid rate halve the residual every cycle or two (the
/// bench's converging cases, 257² to 2049²), and one near the answer is left to the full
/// window. A meniscus that creeps to its place lowers the oil at a few per cent a cycle
/// without halving it: left to the full window too (2 mm/s, 80 N fed 25 nm on 1025², started
/// on the finest grid with 64 % of the oil unaccounted for: 37 cycles, where the V-cycle
/// attempt this rule would start from the same place ended diverged after 17 minutes).
/// Where the W-cycles keep a cycle of the menisci going after the coarser grids' start (5
/// mm/s, 40 N fed 10 nm on 1025²: the residual about 1e-2 from the first finest cycle on,
/// 4–5 % of the oil unaccounted for, none of it gained back) the full window judged it 12
/// cycles later (docs/decisions.md, "V-cycles where the W-cycles stall").
pub(super) fn stalled_early(history: &[CycleLog], points: usize, oil_near: f64) -> bool {
    let oil: Vec<f64> =
        history.iter().filter(|c| c.points == points).map(|c| c.mass_defect.abs()).collect();
    let lowered = || {
        let (before, last) = bests(&oil, EARLY_WINDOW);
        last < before
    };
    oil.len() == 2 * EARLY_WINDOW + 1
        && oil[oil.len() - 1] > oil_near
        && !lowered()
        && stalled_over(history, points, EARLY_WINDOW)
}

/// How many times the oil's tolerance a fed solve's attempt whose coarser grids move the menisci
/// may leave unaccounted for and be continued from where it stalled, rather than started again
/// ([`super::ReynoldsSolver::solve`]): measured 1.2 % of the oil at 10 mm/s, 20 N on 641² (23 more
/// cycles against a restart's 49), 2.9 % at 5 mm/s, 40 N fed 10 nm on 1025² (67 against 25).
pub(super) const CONTINUE_WITHIN: f64 = 2.0;

/// The failure of an attempt that stalled (or settled into a limit cycle) unconverged, with
/// its film open, the solids apart and at most `oil` of its supply unaccounted for at its last
/// cycle: a state to go on from.
pub(super) fn stalled_open(
    rep: &Result<ReynoldsReport, ReynoldsError>,
    oil: f64,
) -> Option<(String, usize)> {
    match rep {
        Ok(r)
            if r.touched_from.is_none()
                && r.history.last().is_some_and(|c| c.mass_defect.abs() <= oil) =>
        {
            given_up(rep)
        }
        _ => None,
    }
}

/// The failure of a W-cycle attempt (`gamma` > 1) that stalled with its film open and the
/// solids apart, but with more than `near` of its supply unaccounted for (too far from the answer
/// to be continued): one to start again from with V-cycles, where the W-cycles' second visit
/// of the grid below kept a cycle of the menisci going (docs/decisions.md, "V-cycles where the
/// W-cycles stall").
pub(super) fn stalled_far(
    rep: &Result<ReynoldsReport, ReynoldsError>,
    near: f64,
    gamma: usize,
) -> Option<(String, usize)> {
    if gamma < 2 || stalled_open(rep, near).is_some() {
        return None;
    }
    stalled_open(rep, f64::INFINITY)
}

/// Whether an attempt that stalled with its film open and the solids apart ([`stalled_open`])
/// ended far above the best residual its finest-grid cycles reached ([`near_best`]): a swing
/// that grew from near the answer, which neither a continuation nor other cycles end. At 1 m/s,
/// 10 N fed 25 nm on 577² (`seed-speed-load` over its rule's domain) the residual rose from 5e-4
/// to 8e-3 in twenty cycles, the force balance swinging ±7e-4 with period two; continued, then
/// started again with the coarser grids holding the film content (or with V-cycles), it swung
/// the same for 80 cycles each, and the laws lagged converged it in 11 (docs/decisions.md,
/// "A swing that grew from near the answer").
pub(super) fn swung_away(rep: &Result<ReynoldsReport, ReynoldsError>) -> bool {
    stalled_open(rep, f64::INFINITY).is_some() && rep.as_ref().is_ok_and(|r| !near_best(&r.history))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::solver::{Diagnosis, FailureKind, Settled};

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

    /// A first attempt's report: stalled (or `kind`) after 30 cycles with `oil` of the supply
    /// unaccounted for at its last, the solids touching from `touched` if given.
    fn stalled(kind: FailureKind, oil: f64, touched: Option<usize>) -> ReynoldsReport {
        let diagnosis = Diagnosis { kind, cycle: 30, at: None, text: "stalled".into() };
        ReynoldsReport {
            converged: false,
            diagnosis: Some(diagnosis),
            cycles: 30,
            work_cycles: 30.0,
            history: history(30, |_| oil),
            wall_time_s: 0.0,
            lagged_laws: 0.0,
            first_attempt: None,
            omega_gs: 0.4,
            settled: None,
            mode_jumps: 0,
            from_flooded: false,
            inflow_filled: false,
            touched_from: touched,
            from_dry: false,
            attempts: 1,
        }
    }

    #[test]
    fn a_first_attempt_stalled_with_its_oil_nearly_accounted_for_is_continued_not_restarted() {
        let near = 0.01 * CONTINUE_WITHIN;
        // 0.9 % and 1.2 % of the oil (10 mm/s, 40 N on 897² and 20 N on 641², the rule's
        // domains): continued, a limit cycle as well as a stall, oil gained or lost alike.
        for (kind, oil) in [
            (FailureKind::Stalled, 0.009),
            (FailureKind::LimitCycle, 0.012),
            (FailureKind::Stalled, -0.009),
        ] {
            assert!(stalled_open(&Ok(stalled(kind, oil, None)), near).is_some(), "{oil}");
        }
        // 2.9 % (5 mm/s, 40 N fed 10 nm on 1025²): a restart's coarser grids drain it faster.
        assert!(stalled_open(&Ok(stalled(FailureKind::Stalled, 0.029, None)), near).is_none());
        // The solids touching, or a closed film: not a state to go on from.
        assert!(stalled_open(&Ok(stalled(FailureKind::Stalled, 0.009, Some(12))), near).is_none());
        assert!(stalled_open(&Ok(stalled(FailureKind::FilmClosed, 0.009, None)), near).is_none());
        // A settled answer is returned as it is.
        let mut settled = stalled(FailureKind::Stalled, 0.009, None);
        settled.settled = Some(Settled {
            window: 40,
            central_film_spread: 0.0,
            minimum_film_spread: 0.0,
            load_error: 0.0,
            mass_defect: 0.009,
        });
        assert!(stalled_open(&Ok(settled), near).is_none());
    }

    #[test]
    fn a_first_attempt_stalled_far_from_the_answer_starts_again_with_v_cycles_only_from_w_cycles() {
        let near = 0.01 * CONTINUE_WITHIN;
        // 2.8 % (5 mm/s, 40 N fed 10 nm on 1025², its W-cycles rocking): again with V-cycles,
        // a limit cycle as well as a stall.
        for kind in [FailureKind::Stalled, FailureKind::LimitCycle] {
            assert!(stalled_far(&Ok(stalled(kind, 0.028, None)), near, 2).is_some());
        }
        // Already V-cycles: not again.
        assert!(stalled_far(&Ok(stalled(FailureKind::Stalled, 0.028, None)), near, 1).is_none());
        // Near the answer: continued instead.
        assert!(stalled_far(&Ok(stalled(FailureKind::Stalled, 0.009, None)), near, 2).is_none());
        // The solids touching, or a closed film: the attempts for those follow instead.
        assert!(
            stalled_far(&Ok(stalled(FailureKind::Stalled, 0.028, Some(12))), near, 2).is_none()
        );
        assert!(stalled_far(&Ok(stalled(FailureKind::FilmClosed, 0.028, None)), near, 2).is_none());
    }

    #[test]
    fn w_cycles_that_neither_halve_the_residual_nor_lower_the_oil_over_their_first_finest_cycles_are_judged_early()
     {
        let near = 0.01 * CONTINUE_WITHIN;
        let judged = 2 * EARLY_WINDOW + 1;
        // The residual standing at 1e-2 and the oil rocking about 4–5 % (5 mm/s, 40 N fed
        // 10 nm on 1025², its first attempt's first finest-grid cycles): judged at once.
        let rocking = |k: usize| 0.045 + 0.005 * (k % 2) as f64;
        assert!(stalled_early(&history(judged, rocking), 257, near));
        // Judged once only: before, too few cycles; after, the full window's business.
        assert!(!stalled_early(&history(judged - 1, rocking), 257, near));
        assert!(!stalled_early(&history(judged + 1, rocking), 257, near));
        // Cycles on the coarser grids do not count towards it.
        let mut start = history(3, rocking);
        start.iter_mut().for_each(|c| c.points = 129);
        start.extend(history(judged - 1, rocking));
        assert!(!stalled_early(&start, 257, near));
        // Within twice the tolerance (10 mm/s, 20 N fed 25 nm on 2049²: the residual 4e-2 to
        // 1e-1 while the oil stayed under 1 %, converged at its eleventh finest cycle): left to
        // the full window.
        assert!(!stalled_early(&history(judged, |_| 0.009), 257, near));
        // The oil halved, or the residual: converging.
        assert!(!stalled_early(&history(judged, |k| 0.2 * 0.8f64.powi(k as i32)), 257, near));
        // A meniscus creeping to its place, the oil lowered a few per cent a cycle without
        // halving while the residual grows (2 mm/s, 80 N fed 25 nm on 1025², its first nine
        // cycles): left to the full window, which it passes at its 37th cycle.
        let creeping = [0.642, 0.640, 0.644, 0.652, 0.647, 0.637, 0.622, 0.610, 0.597];
        let mut creep = history(judged, |k| creeping[k]);
        creep.iter_mut().enumerate().for_each(|(k, c)| c.residual = 0.09 + 0.035 * k as f64);
        assert!(stalled_over(&creep, 257, EARLY_WINDOW));
        assert!(!stalled_early(&creep, 257, near));
        // The same oil, none of it gained back after the start: judged.
        let mut stuck = creep.clone();
        stuck.iter_mut().skip(EARLY_WINDOW + 1).for_each(|c| c.mass_defect = 0.645);
        assert!(stalled_early(&stuck, 257, near));
        let mut halving = history(judged, rocking);
        halving.iter_mut().enumerate().for_each(|(k, c)| c.residual = 1e-2 * 0.6f64.powi(k as i32));
        assert!(!stalled_early(&halving, 257, near));
    }

    #[test]
    fn a_stall_whose_residual_swung_far_above_its_best_is_not_gone_on_from() {
        // The residual from 5e-4 up to 8e-3 (1 m/s, 10 N fed 25 nm on 577²), the oil near the
        // answer: swung away, whatever the oil.
        let swinging = |oil: f64| {
            let mut r = stalled(FailureKind::LimitCycle, oil, None);
            let n = r.history.len();
            r.history.iter_mut().enumerate().for_each(|(k, c)| {
                c.residual = 5e-4 * 16f64.powf(k as f64 / (n - 1) as f64);
            });
            r
        };
        assert!(swung_away(&Ok(swinging(0.003))));
        assert!(swung_away(&Ok(swinging(0.03))));
        // A cycle of the menisci stands at its best: gone on from as before.
        assert!(!swung_away(&Ok(stalled(FailureKind::Stalled, 0.028, None))));
        // The solids touching, or a closed film: the attempts for those follow.
        let mut touching = swinging(0.003);
        touching.touched_from = Some(12);
        assert!(!swung_away(&Ok(touching)));
        let mut closed = swinging(0.003);
        closed.diagnosis.as_mut().unwrap().kind = FailureKind::FilmClosed;
        assert!(!swung_away(&Ok(closed)));
    }
}
