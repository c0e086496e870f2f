//! The steady solve's later attempts, each from its own start: from the flooded answer (a fed
//! solve), with the inflow filled (a flooded solve on cells wider than the grid rule's), and
//! from the dry contact (a film thinner than the grid tells from a closed gap).

use super::steady::{FromFlooded, failure, what_it_said, with_note};
use super::*;

impl ReynoldsSolver {
    /// The last attempt of a mass-conserving steady solve: the same contact fully flooded
    /// first (the clamp, its own full-multigrid start), then the supply switched on and cycles
    /// from that answer (`θ` from [`Level::start_theta_from_flooded`]), cycle numbers and time
    /// counted on from `cycles_before` and `t0`: the fed cycles' outcome, or the flooded
    /// solve's when that did not converge.
    pub(super) fn attempt_from_flooded(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        cycles_before: usize,
        t0: Instant,
    ) -> FromFlooded {
        let kept: Vec<Option<Vec<f64>>> =
            self.levels.iter().map(|l| l.supply().map(<[f64]>::to_vec)).collect();
        for l in &mut self.levels {
            l.set_supply(None);
        }
        self.start();
        self.attempts += 1;
        let flooded = self.cycles(log, cycles_before, t0.elapsed().as_secs_f64(), f64::NAN);
        for (l, s) in self.levels.iter_mut().zip(kept) {
            l.set_supply(s);
        }
        let flooded = match flooded {
            Ok(r) if r.converged => r,
            other => return FromFlooded::Flooded(other),
        };
        self.levels[0].start_theta_from_flooded();
        let h00 = self.h00;
        self.levels[0].update_film(h00);
        // The cycles descend only to grids whose cells are at most twice the grid rule's
        // ([`formulas::cell_needed`]): deeper, the coarse grids' closed films wreck the fine one
        // (docs/reynolds.md, "The attempts after a failure").
        self.coarsest = self.film_holding_depth(2.0);
        // The ring of full film round the contact (its meniscus and the pressure inside it,
        // [`crate::extrapolate`]) moves a little each sweep, and on these fine grids that is
        // little a cycle, but steadily: twice the stall window and twice the cycles.
        let kept = self.active;
        self.active.fmg_cycles = 0;
        self.active.stall_cycles *= 2;
        self.active.max_cycles *= 2;
        let fed = self.cycles(log, flooded.cycles, t0.elapsed().as_secs_f64(), f64::NAN);
        self.active = kept;
        self.coarsest = usize::MAX;
        FromFlooded::Fed(fed)
    }

    /// How a stalled or cycling report's answer settled over the stall window, if it did.
    pub(super) fn settled_stall(&self, r: &ReynoldsReport) -> Option<Settled> {
        let stuck = r
            .diagnosis
            .as_ref()
            .is_some_and(|d| matches!(d.kind, FailureKind::Stalled | FailureKind::LimitCycle));
        stuck
            .then(|| settled(&r.history, self.stall_window(), self.active.mass_tolerance))
            .flatten()
    }

    /// After every attempt of a flooded solve failed on a grid that tells the film from a
    /// closed gap but is coarser than the grid rule asks for (where the film closes on it):
    /// once more mass conserving, fed a layer that fills the gap along the whole
    /// inflow boundary, so that the inlet is flooded as the clamp's is, and the solids may touch
    /// where the film closes (the answer's [`ReynoldsReport::inflow_filled`]). The clamp makes
    /// oil wherever its pressure is held at zero, and a point in contact carries none: with
    /// the solids touching its cycles diverged (the seed's contact at 1 mm/s on 257², its
    /// film closed at the side of the contact), where the film content's answer it touches
    /// with. Kept when it converges; else the attempts before stand, their state back, with
    /// what this one gave. The supply is gone again after it: the model stays the clamp's for
    /// what follows.
    pub(super) fn flooded_through_film_content(
        &mut self,
        rep: Result<ReynoldsReport, ReynoldsError>,
        log: &mut dyn FnMut(&CycleLog),
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let Some(failed) = failure(&rep) else { return rep };
        if rep.as_ref().is_ok_and(|r| self.settled_stall(r).is_some()) {
            // A stall whose answer has settled is an answer, returned as such.
            return rep;
        }
        let kept = (self.save(), self.attempts, self.active);
        // Four times the widest rigid gap along the inflow boundary (at least 1 a²/R): the gap
        // there stays full whatever `H00` and deformation the cycles settle on.
        let inflow = self.levels[0].rigid_film().column(0).iter().fold(1.0f64, |m, &h| m.max(h));
        let fill = 4.0 * inflow;
        for l in &mut self.levels {
            let ny = l.grid.ny;
            l.set_supply(Some(vec![fill; ny]));
        }
        self.steady_setup();
        self.attempts = kept.1 + 1;
        self.start();
        let fed = self.first_attempt(log, failed.1, t0);
        self.set_coarse_theta(false);
        self.coarsest = usize::MAX;
        for l in &mut self.levels {
            l.set_supply(None);
        }
        match fed {
            Ok(mut r) if r.converged => {
                r.first_attempt = Some(failed.0);
                r.inflow_filled = true;
                Ok(r)
            }
            other => {
                let note = what_it_said(&other);
                self.restore(kept.0);
                (self.attempts, self.active) = (kept.1 + 1, kept.2);
                with_note(rep, &format!("; then mass conserving, the inflow filled: {note}"))
            }
        }
    }

    /// After every attempt failed on a grid that cannot tell the film from a closed gap: once
    /// more from the dry contact ([`Self::attempt_from_dry`]), kept when it converges; else the
    /// attempts before stand, their state back, with what this one gave.
    pub(super) fn dry_start_fallback(
        &mut self,
        rep: Result<ReynoldsReport, ReynoldsError>,
        log: &mut dyn FnMut(&CycleLog),
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let Some(failed) = failure(&rep) else { return rep };
        let kept = (self.save(), self.levels.iter().map(|l| l.touch).collect::<Vec<_>>());
        let note = match self.attempt_from_dry(log, failed.1, t0) {
            Ok(mut r) if r.converged => {
                r.first_attempt = Some(failed.0);
                return Ok(r);
            }
            other => what_it_said(&other),
        };
        self.restore(kept.0);
        for (l, touch) in self.levels.iter_mut().zip(kept.1) {
            l.touch = touch;
        }
        with_note(rep, &format!("; then from the dry contact: {note}"))
    }

    /// The last attempt of a steady solve on a grid that cannot tell the film from a closed
    /// gap ([`Self::film_held`]): from the dry contact (the core's dry solver over the same
    /// rigid film and load), the solids touching where it carries pressure from the first
    /// cycle, no full-multigrid start; cycle numbers and time counted on from `cycles_before`
    /// and `t0`.
    ///
    /// Its limit is the dry contact itself: at vanishing speed, or without oil, the pressure
    /// is the dry solver's and the solids carry the load. It does not find a film the grid
    /// could hold: from the dry contact a rolling contact stays dry (a point in contact lets
    /// go only where holding it shut would take a negative pressure), so it is tried only
    /// where the grid cannot tell the film from a closed gap ([`Self::film_held`]).
    pub(super) fn attempt_from_dry(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        cycles_before: usize,
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        use ehl_core::{DryProblem, DrySettings, DrySolver, Start};
        self.start();
        self.attempts += 1;
        let f = &self.levels[0];
        let problem =
            DryProblem { rigid_gap: f.rigid_film().view(), compliance: None, load: 2.0 * PI / 3.0 };
        let solver = DrySolver::new(f.grid, DrySettings::default());
        let (mut p, mut w) = (f.grid.zeros(), f.grid.zeros());
        let dry = solver
            .solve(&problem, &mut p, &mut w, Start::Flat)
            .map_err(|e| ReynoldsError::DryStart(e.to_string()))?;
        self.h00 = dry.h0;
        let h00 = self.h00;
        let f = &mut self.levels[0];
        f.p = p;
        f.update_film(h00);
        f.contact = f.p.mapv(|v| v > 0.0);
        f.start_theta();
        for lv in &mut self.levels {
            lv.touch = true;
        }
        // The finest grid alone: no coarser grid holds the film, and their corrections ran
        // away in the open film beside the contact where `ε̄` is vast at vanishing speed (257²,
        // 1e-6 m/s: diverged in the first cycle). The start is the dry answer already; what is
        // left is near the contact's edge, which relaxation reaches.
        self.coarsest = 0;
        let kept = self.active;
        self.active.fmg_cycles = 0;
        self.active.contact = true;
        // The gap's changes under-relaxed more than in a lubricated solve: with the whole load
        // on the solids the line solve's near response misses the contact's far field by more,
        // and at 0.7 the force balance ran away from the dry answer (129² and 257², no oil:
        // the load error grew from 2e-7 to 3e-3 in four cycles; 0.6 held on 129² only, 0.5 on
        // 65² to 513²).
        let w = &mut self.active.relax.omega_contact;
        *w = w.min(DRY_START_OMEGA_CONTACT);
        // The oil that reaches the rim enters the contact through first-order faces (kept for
        // the answer's oil balance; the next solve or step resets them).
        self.levels[0].first_order_into_contact = true;
        let rep = self.cycles(log, cycles_before, t0.elapsed().as_secs_f64(), f64::NAN);
        if !rep.as_ref().is_ok_and(|r| r.converged) {
            self.levels[0].first_order_into_contact = false;
        }
        self.active = kept;
        self.coarsest = usize::MAX;
        rep.map(|mut r| {
            r.touched_from = Some(cycles_before + 1);
            r.from_dry = true;
            r
        })
    }
}
