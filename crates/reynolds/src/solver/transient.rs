//! One time step of the Reynolds equation from the last state.

use super::*;

impl ReynoldsSolver {
    /// One time step of `dt` [a/u_ref] (the dent, if any, already moved by the caller): the
    /// time derivative by backward differences ([`TimeScheme`]), solved from the last state by
    /// cycles of `step_gamma` (1, V-cycles, by default). The steady solve before the first step
    /// is `T = 0`; steps may differ in size (second order: the variable-step formula, ratio
    /// `ω = dt / dt_prev`, which is the equal-step one at `ω = 1`).
    ///
    /// A step whose cycles fail (stalled, cycling or diverged) is solved again from the state
    /// before it with the other cycle (V-cycles after W-cycles, W after V), and once that has
    /// answered, the steps after it start with it. Where V-cycles amplify a mode of the state,
    /// they fail step after step, each time after their whole stall window (the rough contact
    /// at 5 mm/s on 513²: from the fifth step every fourth, 81 cycles and 11–27 s each, then
    /// every step, and its 223rd past any shorter sub-step), and W-cycles answer in one cycle;
    /// elsewhere W-cycles diverge where V-cycles converge (docs/decisions.md, "V-cycles in a
    /// time step", "The other cycle where a step's cycles fail"). The report's `cycles` count
    /// both attempts; `first_attempt` says why the first was given up.
    pub fn step(
        &mut self,
        dt: f64,
        log: &mut dyn FnMut(&CycleLog),
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let gamma = self.step_gamma.unwrap_or(self.settings.step_gamma);
        let saved = self.save();
        let first = match self.step_with(dt, log, gamma) {
            Err(e @ (ReynoldsError::NotConverged(_) | ReynoldsError::Diverged { .. })) => e,
            other => return other,
        };
        self.restore(saved);
        let (tried, other) = if gamma >= 2 { ("W", 1) } else { ("V", 2) };
        let (cycles, said) = match &first {
            ReynoldsError::NotConverged(r) => (r.cycles, report::diagnosis_text(r).to_string()),
            ReynoldsError::Diverged { cycle, .. } => (*cycle, first.to_string()),
            e => (0, e.to_string()),
        };
        let why = format!("with {tried}-cycles: {said}");
        match self.step_with(dt, log, other) {
            Ok(mut r) => {
                self.step_gamma = Some(other);
                r.cycles += cycles;
                r.first_attempt = Some(why);
                Ok(r)
            }
            Err(e) => Err(noted(e, &format!("; before that, {why}"))),
        }
    }

    /// [`Self::step`] with cycles of `gamma` (1: V, 2: W).
    fn step_with(
        &mut self,
        dt: f64,
        log: &mut dyn FnMut(&CycleLog),
        gamma: usize,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let (a0, history) = match self.rho_h.as_slice() {
            [n] => (1.0 / dt, n.mapv(|v| -v / dt)),
            [n, nm1, ..] => {
                // ∂q/∂T ≈ [(1+2ω) q_(n+1) − (1+ω)² q_n + ω² q_(n−1)] / ((1+ω) dt).
                let w = dt / self.last_dt;
                let c = 1.0 / ((1.0 + w) * dt);
                ((1.0 + 2.0 * w) * c, (n * -((1.0 + w) * (1.0 + w)) + nm1 * (w * w)) * c)
            }
            [] => return Err(ReynoldsError::NoSteadyStart),
        };
        // Contact ([`ReynoldsSettings::contact`]): at rest the set is held from the last step;
        // rolling (or without contact) it is let go, and the step's sweeps decide it anew.
        let renew = !self.settings.contact || self.levels[0].speed != 0.0;
        for l in &mut self.levels {
            l.time_a0 = a0;
            l.touch = self.settings.contact;
            // A step's faces into the contact are second order, whatever start it has.
            l.first_order_into_contact = false;
            if renew {
                // A point let go keeps its pressure, full of oil (`θ = 1`: loaded).
                Zip::from(&mut l.theta).and(&l.contact).for_each(|t, &c| {
                    if c {
                        *t = 1.0
                    }
                });
                l.contact.fill(false);
            }
        }
        self.levels[0].history = history;
        let now = (self.levels[0].p.clone(), self.h00);
        if let (true, Some((p_before, h00_before))) =
            (self.settings.extrapolated_start, self.before.as_ref())
        {
            // The start: the last step's change of pressure added again, carried downstream by
            // the surfaces' travel over this step (`speed · dt` [a], linear between cells), and
            // scaled to this step's length (pressures kept non-negative, partly filled points
            // left at `P = 0`). What a dent or a film front does to the pressure travels with
            // the surfaces; at rest the travel is 0 and this is the linear extrapolation in
            // time. Extrapolated in place, a moving dent's pressure was extrapolated where it
            // had been (docs/decisions.md, "A step's start carried with the surfaces").
            let w = dt / self.last_dt;
            let f = &mut self.levels[0];
            let change = &f.p - p_before;
            let travel = f.speed * dt / f.h;
            let (whole, frac) = (travel.floor(), travel - travel.floor());
            let nx = f.p.ncols() as isize;
            for ((j, i), p) in f.p.indexed_iter_mut() {
                if f.theta[[j, i]] < 1.0 {
                    continue;
                }
                let from = i as isize - whole as isize;
                let at =
                    |ii: isize| if (0..nx).contains(&ii) { change[[j, ii as usize]] } else { 0.0 };
                let d = (1.0 - frac) * at(from) + frac * at(from - 1);
                *p = (*p + w * d).max(0.0);
            }
            let dh = w * (self.h00 - h00_before);
            self.h00 += dh;
            let h00 = self.h00;
            self.levels[0].update_film(h00);
        }
        // A step's cycles: from the last state (no full-multigrid start), the step's cycle
        // and force-balance gain; the laws as the steady solve left them (lagged or not).
        // The settings as they are now (a caller may change them between steps), with the
        // relaxation (the laws' lag) as the steady solve left it.
        let (s, mut relax) = (self.settings, self.active.relax);
        if !s.step_extra_passes {
            relax.meniscus_passes = 0;
            relax.column_pass = false;
        }
        self.active = ReynoldsSettings {
            fmg_cycles: 0,
            max_cycles: s.step_max_cycles,
            gamma,
            h00_gain: s.step_h00_gain,
            pre_sweeps: if self.levels[0].speed == 0.0 {
                s.step_pre_sweeps.max(2)
            } else {
                s.step_pre_sweeps
            },
            mode_extrapolation: 0.0,
            relax,
            ..s
        };
        // Rolling, the first cycle's film change is judged against the start (the whole film's
        // too, [`ReynoldsSettings::step_film_tolerance`]), so that a step whose start was
        // already its answer takes one cycle, not two, no less accurate. At
        // rest the trapped film drains by less than the stop rule's tolerance a step, and
        // one-cycle steps let it drift, so at rest the first cycle is never the last
        // (docs/decisions.md, "A step's start carried with the surfaces").
        let start_hc = if self.levels[0].speed != 0.0 { self.films().0 } else { f64::NAN };
        let rep = converged(self.cycles(log, 0, 0.0, start_hc));
        let rho_h = self.levels[0].rho_film(&self.prm);
        self.rho_h.insert(0, rho_h);
        self.before = Some(now);
        self.rho_h.truncate(match self.active.time_scheme {
            TimeScheme::Bdf1 => 1,
            TimeScheme::Bdf2 => 2,
        });
        self.last_dt = dt;
        rep
    }
}

/// `e` with `note` added to what it says (a failure's diagnosis, a divergence's account).
fn noted(e: ReynoldsError, note: &str) -> ReynoldsError {
    match e {
        ReynoldsError::NotConverged(mut r) => {
            if let Some(d) = r.diagnosis.as_mut() {
                d.text.push_str(note);
            }
            ReynoldsError::NotConverged(r)
        }
        ReynoldsError::Diverged { cycle, kind, at, what, film, load } => {
            ReynoldsError::Diverged { cycle, kind, at, what: format!("{what}{note}"), film, load }
        }
        e => e,
    }
}
