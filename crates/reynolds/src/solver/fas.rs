//! The full-approximation-scheme cycle: one cycle, its record, its diagnosis.

use super::*;

pub(super) fn restrict_full_weighting(r: &Array2<f64>) -> Array2<f64> {
    let (ny, nx) = r.dim();
    let (cy, cx) = ((ny - 1) / 2 + 1, (nx - 1) / 2 + 1);
    Array2::from_shape_fn((cy, cx), |(j, i)| {
        if j == 0 || i == 0 || j == cy - 1 || i == cx - 1 {
            return 0.0;
        }
        let (fj, fi) = (2 * j, 2 * i);
        (4.0 * r[[fj, fi]]
            + 2.0 * (r[[fj, fi - 1]] + r[[fj, fi + 1]] + r[[fj - 1, fi]] + r[[fj + 1, fi]])
            + r[[fj - 1, fi - 1]]
            + r[[fj - 1, fi + 1]]
            + r[[fj + 1, fi - 1]]
            + r[[fj + 1, fi + 1]])
            / 16.0
    })
}

/// How far above the best residual of an attempt's finest-grid cycles its last one may stand
/// for the attempt to be still converging at the cycle limit: a slow one ends at or near its
/// best (a fed meniscus still moving: its residual stands while its oil falls); touching
/// cycles that wander (the seed's contact at 2 mm/s, 80 N on 65²: residuals 0.03 … 1.6
/// over the last 40 cycles, 20× the best) are not converging, and the cascade goes on.
const STILL_CONVERGING: f64 = 4.0;

/// Whether the last finest-grid cycle of `history` stands within [`STILL_CONVERGING`] of the
/// best residual those cycles reached.
pub(super) fn near_best(history: &[CycleLog]) -> bool {
    let Some(last) = history.last() else { return true };
    let best = history
        .iter()
        .filter(|c| c.points == last.points)
        .map(|c| c.residual)
        .fold(f64::INFINITY, f64::min);
    last.residual <= STILL_CONVERGING * best
}

impl ReynoldsSolver {
    /// One FAS cycle with level `l` on top, whose force balance asks for `∬P = target`.
    ///
    /// `H00` is the extra unknown of the force balance. As in Venner & Lubrecht it is updated
    /// on the coarsest grid, between sweeps, against the FAS-corrected load target
    /// (`target + load_c(Î P) − load(P)`), so that the load converges at the multigrid rate
    /// instead of at the rate of a per-cycle update.
    pub(super) fn cycle(&mut self, l: usize, target: f64) {
        let (prm, s) = (self.prm, self.active);
        let last = self.levels.len() - 1;
        if l >= last.min(self.coarsest) {
            // Where the solids touch, twice the gain: with the film's alone the force balance
            // held a period-2 cycle with the contact set unchanged (docs/decisions.md, "Contact
            // in time steps").
            let touching = self.levels[l].touch && self.levels[l].contact.iter().any(|&c| c);
            let gain = if touching { 2.0 * s.h00_gain } else { s.h00_gain };
            for _ in 0..s.coarse_sweeps {
                self.levels[l].relax(&prm, self.h00, &s.relax);
                let dh = gain * (self.levels[l].load() - target) / PI;
                self.h00 += dh;
                self.levels[l].shift_film(dh);
            }
            return;
        }
        for _ in 0..s.pre_sweeps {
            self.levels[l].relax(&prm, self.h00, &s.relax);
        }
        let r = self.levels[l].residual_to_restrict(&prm);
        let p_hat = inject(&self.levels[l].p);
        let load_f = self.levels[l].load();
        if s.relax.coefficient_lag > 0.0 {
            // Lagged laws: the coarse grid's start where the fine grid's are.
            let pc = inject(&self.levels[l].coefficient_pressures());
            self.levels[l + 1].set_coefficient_pressures(&prm, &pc);
        }
        let theta_hat = inject(&self.levels[l].theta);
        let fluid = Zip::from(&r)
            .and(&self.levels[l].contact)
            .map_collect(|&r, &t| if t { 0.0 } else { r });
        // The coarse grid starts touching where the fine grid touches (its own closed films
        // join at its sweeps).
        let contact_hat = {
            let c = &self.levels[l].contact;
            let (ny, nx) = c.dim();
            Array2::from_shape_fn(((ny - 1) / 2 + 1, (nx - 1) / 2 + 1), |(j, i)| c[[2 * j, 2 * i]])
        };
        let target_c = {
            let c = &mut self.levels[l + 1];
            c.p = p_hat.clone();
            // The coarse grid holds the fine grid's film content and corrects pressures only:
            // where the gap is partly filled it keeps `P = 0`.
            c.theta = theta_hat.clone();
            c.contact = contact_hat;
            c.theta_free = false;
            c.coarse_theta = self.coarse_theta;
            c.rhs.fill(0.0);
            c.update_film(self.h00);
            let lc = c.operator(&prm);
            // Where the solids touch the residual is a gap's, elsewhere Reynolds': the two
            // are not mixed. A coarse point in contact takes the fine gap's residual at its
            // own place; the others the full weighting of the fine Reynolds residuals (a fine
            // gap's residual of 1e-3 a²/R beside Reynolds' of 1e2 gave a coarse gap a
            // pressure change of thousands of p_h: the start on 33² exploded).
            let mut rr = restrict_full_weighting(&fluid);
            Zip::indexed(&mut rr).and(&c.contact).for_each(|(j, i), v, &t| {
                if t {
                    *v = r[[2 * j, 2 * i]];
                }
            });
            c.rhs = lc + rr;
            target + c.load() - load_f
        };
        for _ in 0..s.gamma {
            self.cycle(l + 1, target_c);
        }
        let corr = prolong(&(&self.levels[l + 1].p - &p_hat));
        let theta_corr = self.levels[l + 1]
            .coarse_theta
            .then(|| prolong(&(&self.levels[l + 1].theta - &theta_hat)));
        {
            let f = &mut self.levels[l];
            if let Some(tc) = &theta_corr {
                // The film content where the fine gap is partly filled.
                for ((t, &p), &d) in f.theta.iter_mut().zip(&f.p).zip(tc) {
                    if p <= 0.0 && *t < 1.0 {
                        *t = (*t + d).clamp(0.0, 1.0);
                    }
                }
            }
            // Only points inside the pressurised region are corrected: the coarse grid cannot
            // resolve the cavitation boundary, and a correction at a cavitated point, or at a
            // loaded point beside one, moves that boundary every cycle (a period-2 limit cycle
            // in the load). Relaxation fixes those points. The same for a point where the
            // solids touch or beside one: the coarse grid holds the gap's equation only at its
            // own injected points, and its correction there kept a period-2 cycle in the central
            // film (docs/decisions.md, "Three changes that made the steady cycles converge",
            // "Contact in time steps").
            let p0 = f.p.clone();
            let (ny, nx) = p0.dim();
            for j in 1..ny - 1 {
                for i in 1..nx - 1 {
                    let p = p0[[j, i]];
                    let c = &f.contact;
                    let touching = c[[j, i]]
                        || c[[j, i - 1]]
                        || c[[j, i + 1]]
                        || c[[j - 1, i]]
                        || c[[j + 1, i]];
                    let inside = p > 0.0
                        && !touching
                        && p0[[j, i - 1]] > 0.0
                        && p0[[j, i + 1]] > 0.0
                        && p0[[j - 1, i]] > 0.0
                        && p0[[j + 1, i]] > 0.0;
                    if inside {
                        let q = p + corr[[j, i]];
                        f.p[[j, i]] = if q > crate::level::CAVITATION_FLOOR { q } else { 0.0 };
                    }
                }
            }
            f.update_film(self.h00);
        }
        for _ in 0..s.post_sweeps {
            self.levels[l].relax(&prm, self.h00, &s.relax);
        }
    }

    /// The finest-grid cycles over which a stall is judged. Mass conserving, a meniscus that
    /// still moves lowers the residual slowly but steadily, by a few per cent a cycle: a window
    /// twice as long tells that from a stall.
    pub(super) fn stall_window(&self) -> usize {
        self.active.stall_cycles * if self.levels[0].mass_conserving() { 2 } else { 1 }
    }

    /// The window a steady solve's lubricated cycles are judged over for a stall
    /// ([`Self::stall_window`]), a quarter of it (half `stall_cycles`) in a fed solve's
    /// attempts whose coarser grids move the menisci, on a grid that holds the film, while the
    /// film is open and the solids apart. Where the first attempt does not converge it ends in
    /// a cycle of a few periods short of the answer (5 mm/s, 40 N fed 10 nm on 1025²: its film
    /// 1.5 % thick, 2 % of the supply unaccounted for) that the next attempt leaves in about 20
    /// cycles; judged over the whole window it ran 80 cycles first (docs/decisions.md, "The
    /// full-multigrid start on a grid that holds the film"). On a coarser grid the first
    /// attempt's film closes late, and the solids touch.
    pub(super) fn judged_stall_window(&self, touching: bool, closed: bool) -> usize {
        if self.menisci_moving_open(touching, closed) {
            self.active.stall_cycles / 2
        } else {
            self.stall_window()
        }
    }

    /// An attempt whose coarser grids move the menisci, on a grid that holds the film, with the
    /// film open and the solids apart: the cycles [`Self::judged_stall_window`] judges over a
    /// shorter window and [`Self::judged_early`] judges early.
    fn menisci_moving_open(&self, touching: bool, closed: bool) -> bool {
        self.coarse_theta && self.finest_holds_film() && !touching && !closed
    }

    /// How much of the supply an attempt may leave unaccounted for and still be near the
    /// answer: a stall within it is continued ([`CONTINUE_WITHIN`] times the oil's tolerance),
    /// beyond it started again or judged early.
    pub(super) fn oil_near(&self) -> f64 {
        self.active.mass_tolerance * CONTINUE_WITHIN
    }

    /// Whether this attempt's lubricated cycles are judged early too ([`stalled_early`]): a fed
    /// steady solve's first attempt, in W-cycles whose coarser grids move the menisci, on a grid
    /// that holds the film, the film open and the solids apart. Its stall then starts the
    /// V-cycle attempt ([`stalled_far`]).
    pub(super) fn judged_early(&self, touching: bool, closed: bool) -> bool {
        self.attempts == 1
            && self.active.gamma >= 2
            && self.fed_steady()
            && self.menisci_moving_open(touching, closed)
    }

    /// What keeps the solve from converging, in words: a closed film (where), or which criterion
    /// is missed and by how much.
    pub(super) fn diagnose(&self, history: &[CycleLog], stalled: bool) -> Diagnosis {
        let last = history.last().expect("at least one cycle");
        let f = &self.levels[0];
        let ((j, i), hmin) = f
            .film
            .indexed_iter()
            .fold(((0, 0), f64::INFINITY), |a, (ix, &v)| if v < a.1 { (ix, v) } else { a });
        if hmin < 0.0 && !f.touch {
            let text = format!(
                "the film closed at cycle {}: H = {hmin:.3e} a²/R at (x = {:.3} a, y = {:.3} a) where P = {:.3} p_h; the lubricated solution broke down: the film is too thin for cells of {:.4} a (a finer grid or a narrower domain resolves thinner films)",
                last.cycle,
                f.grid.x(i),
                f.grid.y(j),
                f.p[[j, i]],
                f.grid.dx()
            );
            let at = Some((f.grid.x(i), f.grid.y(j)));
            return Diagnosis { kind: FailureKind::FilmClosed, cycle: last.cycle, at, text };
        }
        // A limit cycle shows as the load error changing sign from cycle to cycle.
        let tail = &history[history.len().saturating_sub(8)..];
        let flips = tail.windows(2).filter(|w| w[0].load_error * w[1].load_error < 0.0).count();
        let (kind, how) = if tail.len() >= 4 && flips + 1 >= tail.len() {
            (
                FailureKind::LimitCycle,
                "the load error changes sign every cycle: a limit cycle, not slow convergence",
            )
        } else if stalled {
            (
                FailureKind::Stalled,
                if f.mass_conserving() {
                    "stalled: neither the residual nor the oil unaccounted for has halved over the last cycles"
                } else {
                    "stalled: the residual has not halved over the last cycles"
                },
            )
        } else if !near_best(history) {
            (
                FailureKind::Stalled,
                "not converging: at the cycle limit the residual is many times the best it reached",
            )
        } else {
            (FailureKind::CycleLimit, "still converging at the cycle limit")
        };
        let oil = if f.supply().is_some() {
            format!(", {:.1} % of the supply's oil unaccounted for", 100.0 * last.mass_defect)
        } else {
            String::new()
        };
        let mut text = format!(
            "after {} cycles: force balance off by {:.2e} (tolerance {:.0e}), residual {:.2e}{oil}, central film {:.5e} a²/R; {how}",
            last.cycle,
            last.load_error,
            self.active.load_tolerance,
            last.residual,
            last.central_film
        );
        // Touching, the solids overlapping deeper than the grid tells a closed gap from a film:
        // the equations between the touching points are the grid's, not the film's (a wave's
        // crests closing the film at the side lobes stalled so on 65² and 129²).
        let resolved = crate::formulas::dry_gap_error(f.grid.dx());
        let mut at = None;
        if f.touch && hmin < -resolved {
            at = Some((f.grid.x(i), f.grid.y(j)));
            text += &format!(
                "; the solids overlap by {:.3e} a²/R at (x = {:.3} a, y = {:.3} a), deeper than cells of {:.4} a tell a closed gap from a film ({resolved:.1e} a²/R): a finer grid resolves the film between the touching points",
                -hmin,
                f.grid.x(i),
                f.grid.y(j),
                f.grid.dx()
            );
        }
        Diagnosis { kind, cycle: last.cycle, at, text }
    }

    /// Central and minimum film of the finest grid.
    pub fn films(&self) -> (f64, f64) {
        self.films_on(0)
    }

    pub(super) fn films_on(&self, l: usize) -> (f64, f64) {
        let f = &self.levels[l];
        let g = &f.grid;
        let hc = f.film[[g.row_nearest(0.0), g.col_nearest(0.0)]];
        let hmin = f.film.iter().cloned().fold(f64::INFINITY, f64::min);
        (hc, hmin)
    }

    /// One cycle with level `l` on top, recorded; fails on non-finite or runaway values.
    pub(super) fn logged_cycle(
        &mut self,
        l: usize,
        cycle: usize,
        t0: Instant,
    ) -> Result<CycleLog, ReynoldsError> {
        ehl_core::cancel::check()?;
        let target = 2.0 * PI / 3.0;
        self.levels[l].theta_free = true;
        // The whole cycle, its coarser grids' sweeps included, relaxes with the factor of the
        // grid on top (a fed steady solve's finest grid takes its own: `cycle_omega_gs`).
        let kept = self.active.relax.omega_gs;
        self.active.relax.omega_gs = self.cycle_omega_gs(l);
        self.cycle(l, target);
        self.active.relax.omega_gs = kept;
        let f = &self.levels[l];
        let load = f.load();
        let load_error = load / target - 1.0;
        let (hc, hmin) = self.films_on(l);
        let res = f.residual(&self.prm);
        let residual = (res.iter().map(|v| v * v).sum::<f64>() / res.len() as f64).sqrt();
        let mass_defect = match f.supply() {
            Some(sup) => {
                let h = f.h;
                let q_in: f64 = sup.iter().sum::<f64>() * h;
                res.sum().abs() * h * h / q_in.max(f64::MIN_POSITIVE)
            }
            None => 0.0,
        };
        let rec = CycleLog {
            mass_defect,
            cycle,
            points: f.grid.nx,
            residual,
            load_error,
            h00: self.h00,
            central_film: hc,
            minimum_film: hmin,
            wall_s: t0.elapsed().as_secs_f64(),
        };
        let at =
            |j: usize, i: usize| format!("(x = {:.3} a, y = {:.3} a)", f.grid.x(i), f.grid.y(j));
        if !(hc.is_finite() && residual.is_finite() && load.is_finite()) {
            let bad =
                |a: &Array2<f64>| a.indexed_iter().find(|(_, v)| !v.is_finite()).map(|(ix, _)| ix);
            let xy = |j: usize, i: usize| (f.grid.x(i), f.grid.y(j));
            let (kind, place, what) = match (bad(&f.p), bad(&f.film)) {
                (Some((j, i)), _) => (
                    Divergence::NonFinitePressure,
                    xy(j, i),
                    format!("pressure non-finite at {}", at(j, i)),
                ),
                (None, Some((j, i))) => (
                    Divergence::NonFiniteFilm,
                    xy(j, i),
                    format!("film non-finite at {}", at(j, i)),
                ),
                _ => {
                    let ((j, i), pm) = f
                        .p
                        .indexed_iter()
                        .fold(((0, 0), 0.0f64), |a, (ix, &v)| if v > a.1 { (ix, v) } else { a });
                    let what = format!(
                        "residual non-finite on the {}² grid; pressure peaks at P = {pm:.3e} p_h at {}",
                        f.grid.nx,
                        at(j, i)
                    );
                    (Divergence::NonFiniteResidual, xy(j, i), what)
                }
            };
            return Err(ReynoldsError::Diverged {
                cycle,
                kind,
                at: place,
                what,
                film: hc,
                load: load_error,
            });
        }
        // Growth by orders of magnitude is divergence too, before it reaches infinity.
        if load_error.abs() > 1e3 {
            let ((j, i), pm) =
                f.p.indexed_iter()
                    .fold(((0, 0), 0.0f64), |a, (ix, &v)| if v > a.1 { (ix, v) } else { a });
            return Err(ReynoldsError::Diverged {
                cycle,
                kind: Divergence::Runaway,
                at: (f.grid.x(i), f.grid.y(j)),
                what: format!("pressure grows without bound: P = {pm:.3e} p_h at {}", at(j, i)),
                film: hc,
                load: load_error,
            });
        }
        Ok(rec)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finest-grid cycles on 65² with these residuals.
    fn history(residuals: &[f64]) -> Vec<CycleLog> {
        let cycle = |(k, &residual): (usize, &f64)| CycleLog {
            cycle: k + 1,
            points: 65,
            residual,
            load_error: 0.0,
            h00: 0.0,
            central_film: 1e-3,
            minimum_film: 5e-4,
            wall_s: 0.0,
            mass_defect: 0.0,
        };
        residuals.iter().enumerate().map(cycle).collect()
    }

    #[test]
    fn an_attempt_whose_residual_wanders_far_above_its_best_is_not_still_converging() {
        // Touching cycles at 2 mm/s, 80 N on 65²: from 0.025 to between 0.03 and 1.6.
        assert!(!near_best(&history(&[0.14, 0.025, 0.55, 1.6, 0.03, 0.51])));
        // A slow one ends at its best, or near it (a fed meniscus still moving).
        assert!(near_best(&history(&[0.14, 0.05, 0.03, 0.02])));
        assert!(near_best(&history(&[0.14, 0.02, 0.03, 0.025])));
        // A coarser grid's cycles (the full-multigrid start) do not count.
        let mut h = history(&[0.5, 0.4]);
        h[0].points = 33;
        h[0].residual = 1e-3;
        assert!(near_best(&h));
    }
}
