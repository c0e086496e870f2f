//! The steady solve: its cycles and the cascade of attempts after a failure.

use super::*;

impl ReynoldsSolver {
    /// Steady solve: full-multigrid start (when set), then cycles on the finest grid until the
    /// central film and the load settle; `log` sees every cycle. The result is time `T = 0` of
    /// any transient run that follows. `Ok` only when converged: a divergence, and a solve that
    /// ran to its end without converging ([`ReynoldsError::NotConverged`], with its report and
    /// diagnosis), are errors.
    ///
    /// Mass conserving, the first attempt's coarser grids solve for the film content
    /// ([`ReynoldsSettings::coarse_film_content`]): the ring of full film round the contact,
    /// which the finest grid's relaxation moves a little each cycle, moves with the coarse-grid
    /// correction (docs/decisions.md, "The coarser grids solving for the film content").
    ///
    /// When every attempt fails with a film thinner than the grid tells from a closed gap, a
    /// last one starts from the dry contact, the solids touching from its first cycle: its
    /// answer is the closed film ([`ReynoldsReport::from_dry`]; docs/decisions.md, "The start from the dry contact,
    /// where the grid cannot tell the film from a closed gap").
    pub fn solve(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let t0 = Instant::now();
        // Every cycle's work, whichever attempt ran it (the reports count their own only).
        let finest = self.grid().nx;
        let mut work = 0.0;
        let log = &mut |c: &CycleLog| {
            work += cycle_work(c.points, finest);
            log(c)
        };
        let rep = self.solve_counted(log, t0);
        rep.map(|r| ReynoldsReport { work_cycles: work, ..r })
    }

    /// [`Self::solve`] with every cycle logged through `log`.
    fn solve_counted(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        self.steady_setup();
        if self.settings.contact
            && self.levels[0].supply().is_some_and(|s| s.iter().all(|&h| h <= 0.0))
        {
            // No oil supplied: no film can form, and the lubricated attempts only fail their
            // way to the dry contact (the seed's contact on 65² took 167 cycles to get there).
            let rep = self.attempt_from_dry(log, 0, t0);
            self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
            ehl_core::cancel::check()?;
            return converged(rep);
        }
        let fed = self.levels[0].mass_conserving();
        self.attempts = 1;
        let mut rep = self.first_attempt(log, 0, t0);
        let theta = self.active.fallback_lag;
        if theta > 0.0 && self.active.relax.coefficient_lag == 0.0 {
            // The relaxation failed with the laws following at once: start again with them
            // lagged (they stay lagged for any time steps that follow).
            if let Some(failed) = given_up(&rep) {
                self.active.relax.coefficient_lag = theta;
                let said = format!("first attempt, laws following at once: {}", failed.0);
                rep = self.attempt(
                    log,
                    Begin::Afresh,
                    &format!("with lagged laws (θ = {theta})"),
                    failed,
                    said,
                    t0,
                );
            }
        }
        let omega = self.active.fallback_omega_gs;
        if self.active.relax.coefficient_lag > 0.0
            && omega > 0.0
            && omega < self.active.relax.omega_gs
        {
            // Lagged laws failed too: once more with smaller Gauss–Seidel changes.
            if let Some(failed) = given_up(&rep) {
                let was = self.active.relax.omega_gs;
                self.active.relax.omega_gs = omega;
                let said = format!("before that, Gauss–Seidel changes × {was}, {}", failed.0);
                let what = format!(
                    "with lagged laws (θ = {}) and Gauss–Seidel changes × {omega}",
                    self.active.relax.coefficient_lag
                );
                rep = self.attempt(log, Begin::Afresh, &what, failed, said, t0);
            }
        }
        if self.active.flooded_start_fallback && self.levels[0].mass_conserving() {
            // The film closed (or the attempts above gave up): once more from the clamp's
            // answer, the supply then switched on. Kept only when it converges; else the
            // attempts before stand, their state back, with what this one gave.
            if let Some(failed) = failure(&rep) {
                let kept = self.save();
                let (note, answer) = match self.attempt_from_flooded(log, failed.1, t0) {
                    FromFlooded::Fed(Ok(r)) if r.converged => (String::new(), Some(r)),
                    FromFlooded::Fed(fed) => (what_it_said(&fed), None),
                    FromFlooded::Flooded(flooded) => {
                        (format!("its flooded solve: {}", what_it_said(&flooded)), None)
                    }
                };
                rep = match (answer, rep) {
                    (Some(mut r), _) => {
                        r.first_attempt = Some(failed.0);
                        r.from_flooded = true;
                        Ok(r)
                    }
                    (None, before) => {
                        self.restore(kept);
                        with_note(before, &format!("; then from the flooded answer: {note}"))
                    }
                };
            }
        }
        if self.active.filled_inflow_fallback
            && self.settings.contact
            && !fed
            && self.film_held()
            && !self.film_resolved()
        {
            rep = self.flooded_through_film_content(rep, log, t0);
        }
        if self.settings.contact && !self.film_held() {
            rep = self.dry_start_fallback(rep, log, t0);
        }
        if fed && self.active.relax.coefficient_lag == self.settings.relax.coefficient_lag {
            // The steps relax as the settings say, unless the solve needed its lagged attempt.
            self.active.relax.omega_gs = self.settings.relax.omega_gs;
        }
        // A stall or a limit cycle whose answer has settled is returned, saying so.
        let attempts = self.attempts;
        let rep = rep.map(|mut r| {
            r.attempts = attempts;
            if !r.converged {
                r.settled = self.settled_stall(&r);
            }
            r
        });
        self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
        // Stopped inside a later attempt: the stop is the answer, not the attempts before it.
        ehl_core::cancel::check()?;
        converged(rep)
    }

    /// A steady solve's first attempt from its start, cycle numbers counted on from
    /// `cycles_before`: mass conserving, its coarser grids solving for the film content
    /// ([`ReynoldsSettings::coarse_film_content`]), never finer than the grid the full-multigrid
    /// start begins on (its cycles descend at least that far), and what follows their stall.
    pub(super) fn first_attempt(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        cycles_before: usize,
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let coarse_theta = self.active.coarse_film_content && self.levels[0].mass_conserving();
        if coarse_theta {
            self.coarsest = self.film_holding_depth(COARSE_FILM_CELLS).max(self.fmg_top());
            self.set_coarse_theta(true);
        }
        let rep = self.cycles(log, cycles_before, t0.elapsed().as_secs_f64(), f64::NAN);
        if coarse_theta { self.after_coarse_film_content(rep, log, t0) } else { rep }
    }

    /// Before a steady solve: no time history, the settings as given, and no contact until
    /// the cycles stall with the film closed ([`ReynoldsSettings::contact`]).
    pub(super) fn steady_setup(&mut self) {
        self.active = ReynoldsSettings { contact: false, ..self.settings };
        self.attempts = 0;
        for l in &mut self.levels {
            l.time_a0 = 0.0;
            l.history.fill(0.0);
            l.touch = false;
            l.first_order_into_contact = false;
            l.contact.fill(false);
        }
    }

    /// A steady solve that is only the cascade's last attempt: from the dry contact, the solids
    /// touching from the first cycle (`attempt_from_dry`), where the film is known to be
    /// thinner than the grid tells from a closed gap (the probes trace that attempt alone).
    pub fn solve_from_dry(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let t0 = Instant::now();
        self.steady_setup();
        let rep = self.attempt_from_dry(log, 0, t0);
        self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
        converged(rep)
    }

    /// Mass conserving, a steady solve that starts from the flooded answer: the same contact
    /// solved fully flooded first, then the supply switched on and cycles from that answer
    /// (what [`ReynoldsSettings::flooded_start_fallback`] does after failed attempts, here the
    /// only attempt). `Ok` only when converged; a flooded solve that fails ends it with its own
    /// outcome, said to be the flooded solve's. Without a supply: [`Self::solve`].
    pub fn solve_from_flooded(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
    ) -> Result<ReynoldsReport, ReynoldsError> {
        if !self.levels[0].mass_conserving() {
            return self.solve(log);
        }
        self.steady_setup();
        let rep = match self.attempt_from_flooded(log, 0, Instant::now()) {
            FromFlooded::Fed(fed) => fed.map(|mut r| {
                r.from_flooded = true;
                r
            }),
            FromFlooded::Flooded(flooded) => {
                with_note(flooded, " (the flooded solve the fed one starts from)")
            }
        };
        self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
        ehl_core::cancel::check()?;
        converged(rep.map(|mut r| {
            // Only a converged answer is the fed one: the flooded solve's settled answer is not.
            r.settled = None;
            r
        }))
    }

    /// After a first attempt whose coarser grids solved for the film content: one whose residual
    /// swung far above its best is left to the lagged laws that follow in [`Self::solve`]; one
    /// that stalled far from the answer starts again with V-cycles, the coarser grids still
    /// solving for it; from there they hold it, and an attempt that stalled is continued or
    /// started again.
    pub(super) fn after_coarse_film_content(
        &mut self,
        mut rep: Result<ReynoldsReport, ReynoldsError>,
        log: &mut dyn FnMut(&CycleLog),
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        // What the attempts so far said: a later attempt's failure quotes the ones before it
        // already; the first attempt's is named.
        let said = |attempts: usize, text: &str| {
            if attempts > 1 {
                text.to_string()
            } else {
                format!("first attempt, the coarser grids moving the menisci: {text}")
            }
        };
        // A swing grown from near the answer: straight on to the lagged laws, which end it
        // where every other attempt of this cascade swung the same.
        let lag_next = self.active.fallback_lag > 0.0 && self.active.relax.coefficient_lag == 0.0;
        if lag_next && swung_away(&rep) {
            self.set_coarse_theta(false);
            self.coarsest = usize::MAX;
            return rep;
        }
        // Stalled with its film open, further from the answer than a continuation reaches:
        // once more from the start with V-cycles (the grid below visited once a cycle, not
        // twice), the coarser grids still moving the menisci to the same depth. Where the
        // W-cycles end in a cycle of the menisci (5 mm/s, 40 N fed 10 nm on 1025² and 2049²)
        // V-cycles from the start converge in 18 cycles; as the first attempt they took
        // 1.2–2× the W-cycles' on the bench's other cases (docs/decisions.md, "V-cycles where
        // the W-cycles stall").
        let near = self.oil_near();
        if let Some(failed) = stalled_far(&rep, near, self.active.gamma) {
            let said = said(self.attempts, &failed.0);
            // Its start relaxes as the settings say until a film there closes: with the
            // first attempt's smaller changes it took 30 cycles, not 18 (1025²).
            let kept = (self.active.gamma, self.active.relax.omega_gs);
            self.active.gamma = 1;
            self.active.relax.omega_gs = self.settings.relax.omega_gs;
            rep = self.attempt(log, Begin::Afresh, "again with V-cycles", failed, said, t0);
            (self.active.gamma, self.active.relax.omega_gs) = kept;
        }
        self.set_coarse_theta(false);
        // Stalled with its film open and its oil nearly accounted for: a cycle of the
        // menisci a few tenths of a per cent from the answer. On from there with the
        // coarser grids holding the film content, which ends that cycle (the seed's
        // contact at 10 mm/s, 40 N on 897² over its rule's domain, 0.9 % of the oil
        // unaccounted for: 2 more cycles, where a restart took 84). Further from it the
        // finest grid alone moves the menisci too slowly, and the restart's coarser grids
        // are faster (5 mm/s, 40 N fed 10 nm on 1025², 2.9 %: 67 cycles against 25).
        if let Some(failed) = stalled_open(&rep, near) {
            let said = said(self.attempts, &failed.0);
            let what = "continued with the coarser grids holding the film content";
            // To the depth of the attempt it continues: on a grid coarser than the grid rule's
            // (5 mm/s, 80 N fed 5 nm on 385², the rule asking for 1793²) every grid down to the
            // coarsest closed its film and wrecked the fine one's (the residual 3e-5 → 2e-2 in
            // one cycle, and every later attempt failed); to that depth, 5 more cycles.
            rep = self.attempt(log, Begin::WhereLeft, what, failed, said, t0);
        }
        self.coarsest = usize::MAX;
        // Failed: once more with the coarser grids holding the film content, every grid
        // down to the coarsest.
        if let Some(failed) = given_up(&rep).or_else(|| film_closed(&rep)) {
            let said = said(self.attempts, &failed.0);
            rep = self.attempt(
                log,
                Begin::Afresh,
                "with the coarser grids holding the film content",
                failed,
                said,
                t0,
            );
        }
        rep
    }

    /// One more attempt of a steady solve, with the settings now in force (`self.active`),
    /// from the start or from where the attempt before stopped (`begin`): `what` names them,
    /// `failed` is the attempt before's failure (its text and its cycles, counted on) and
    /// `said` what the attempts before were and how they ended. Its report, or its divergence,
    /// says which attempt it is and quotes `said`.
    pub(super) fn attempt(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        begin: Begin,
        what: &str,
        failed: (String, usize),
        said: String,
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let fmg = self.active.fmg_cycles;
        match begin {
            Begin::Afresh => self.start(),
            // No full-multigrid start: the cycles go on from the state as it stands.
            Begin::WhereLeft => self.active.fmg_cycles = 0,
        }
        self.attempts += 1;
        let spent = t0.elapsed().as_secs_f64();
        let rep = self.cycles(log, failed.1, spent, f64::NAN);
        self.active.fmg_cycles = fmg;
        match rep {
            Ok(mut r) => {
                if let Some(d) = r.diagnosis.as_mut() {
                    d.text = format!("{what}: {}; {said}", d.text);
                }
                r.first_attempt = Some(failed.0);
                Ok(r)
            }
            Err(ReynoldsError::Diverged { cycle, kind, at, what: w, film, load }) => {
                let w = format!("{what}: {w}; {said}");
                Err(ReynoldsError::Diverged { cycle, kind, at, what: w, film, load })
            }
            Err(e) => Err(e),
        }
    }

    /// Whether a steady cycle's answer has settled against the cycle's before, each `(H_c,
    /// the contact's share of the load where the solids touch at the centre)`: the central
    /// film's change relative to it, or to `film_floor` where the centre has closed (a dry band
    /// passing after a stop: `H_c` 1e-10 a²/R, whose relative change no cycle settles). Where
    /// the solids touch at the centre its film is the gap equation's residual, not an answer:
    /// the share settles instead (from the dry contact on 129², the central gap moved by 1e-9
    /// a²/R a cycle while the load and the share had settled, and it stalled).
    fn settles(
        &self,
        now: (f64, Option<f64>),
        before: (f64, Option<f64>),
        film_floor: f64,
    ) -> bool {
        let tol = self.active.film_tolerance;
        match (now.1, before.1) {
            (Some(s), Some(b)) => (s - b).abs() < tol,
            _ => ((now.0 - before.0) / now.0.abs().max(film_floor)).abs() < tol,
        }
    }

    /// Whether the solids touch at the contact's centre on the finest grid.
    fn centre_touching(&self) -> bool {
        let f = &self.levels[0];
        f.touch && f.contact[[f.grid.row_nearest(0.0), f.grid.col_nearest(0.0)]]
    }

    /// Cycles until converged or given up; cycle numbers and wall times continue from
    /// `cycles_before` and `spent_s` (a second attempt's count both); `start_hc` is the central
    /// film the first cycle's change is measured from (NaN: the first cycle is never the last).
    pub(super) fn cycles(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        cycles_before: usize,
        spent_s: f64,
        start_hc: f64,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let t0 = Instant::now()
            .checked_sub(std::time::Duration::from_secs_f64(spent_s))
            .unwrap_or_else(Instant::now);
        let mut history = vec![];
        let mut cycle = cycles_before;
        let mut mode_jumps = 0;
        if self.active.fmg_cycles > 0 {
            let mass_conserving = self.levels[0].mass_conserving();
            for l in (1..=self.fmg_top()).rev() {
                self.levels[l].rhs.fill(0.0);
                // Mass conserving, each grid of the start settles (the load to 1e-4, the film
                // and the oil as `STARVED_FMG_SETTLE` says): a meniscus moves a few cells a
                // cycle, cheaper on the coarser grid.
                let most =
                    if mass_conserving { STARVED_FMG_MAX_CYCLES } else { self.active.fmg_cycles };
                let (film, oil) = STARVED_FMG_SETTLE;
                let mut prev = f64::NAN;
                let mut jumps = ModeExtrapolation::new(self.active.mode_extrapolation);
                for k in 0..most {
                    cycle += 1;
                    let rec = self.logged_cycle(l, cycle, t0)?;
                    self.watch_fed_start(&rec);
                    let (h00, moved) =
                        jumps.after_cycle(&mut self.levels[l], self.h00, rec.residual);
                    self.h00 = h00;
                    log(&rec);
                    history.push(rec);
                    let settled = ((rec.central_film - prev) / rec.central_film).abs() < film
                        && rec.load_error.abs() < 1e-4
                        && rec.mass_defect < oil * self.active.mass_tolerance;
                    // After a jump the record is not the state's: judge the next cycle.
                    prev = if moved { f64::NAN } else { rec.central_film };
                    if mass_conserving && k + 1 >= self.active.fmg_cycles && settled && !moved {
                        break;
                    }
                }
                mode_jumps += jumps.jumps;
                self.start_finer(l);
            }
        }
        for lv in &mut self.levels {
            lv.touch = self.active.contact;
            if !lv.touch {
                lv.contact.fill(false);
            }
        }
        // The solids touch only where the lubricated cycles end with the film closed
        // ([`ReynoldsSettings::contact`]).
        let may_touch = self.settings.contact && !self.active.contact;
        let mut touching = Touching::default();
        // The central film of the grid below, where the full-multigrid start left it.
        let coarse_hc = history.last().map(|c: &CycleLog| c.central_film);
        // The central film and, where the solids touch at the centre, the contact's share of
        // the load, as the cycle before left them.
        let mut prev: (f64, Option<f64>) = (start_hc, None);
        let film_floor = 1e-2 * self.starved_film_estimate(self.nvm_film());
        let mut stalled = false;
        let near = self.oil_near();
        let mut jumps = ModeExtrapolation::new(self.active.mode_extrapolation);
        let mut whole = FilmBefore::in_step(&self.levels[0], film_floor, &self.active);
        for _ in 0..self.active.max_cycles {
            cycle += 1;
            let rec = match self.logged_cycle(0, cycle, t0) {
                Ok(rec) => rec,
                Err(e) if matches!(e, ReynoldsError::Cancelled(_)) => return Err(e),
                Err(e) => {
                    let jumps = mode_jumps + jumps.jumps;
                    return self.lubricated_report(&mut touching, &mut history, t0, jumps).ok_or(e);
                }
            };
            let (h00, moved) = jumps.after_cycle(&mut self.levels[0], self.h00, rec.residual);
            self.h00 = h00;
            log(&rec);
            history.push(rec);
            let settled_all = whole.as_mut().is_none_or(|w| w.settled(&self.levels[0], &rec));
            if moved {
                // The record is not the state's after a jump: the next cycle judges it.
                prev = (f64::NAN, None);
                continue;
            }
            let hc = rec.central_film;
            let now = (hc, self.centre_touching().then(|| self.contact().0));
            let settled = self.settles(now, prev, film_floor) && settled_all;
            let mass = rec.mass_defect <= self.active.mass_tolerance;
            let closed = may_touch && touching.at.is_none() && rec.minimum_film < 0.0;
            let strict = settled && rec.load_error.abs() < self.active.load_tolerance && mass;
            let discretisation = match (self.active.stop, coarse_hc) {
                (StopRule::Discretisation, Some(h2)) => {
                    let e_d = (hc - h2).abs() / 3.0;
                    (hc - prev.0).abs() < 0.1 * e_d && rec.load_error.abs() < 0.1 * e_d / hc && mass
                }
                _ => false,
            };
            if (strict || discretisation) && closed {
                // Converged with the film closed: touching from here, this answer kept.
                self.let_touch(&mut touching, cycle, history.len(), true);
                prev = (f64::NAN, None);
                continue;
            }
            if strict || discretisation {
                let jumps = mode_jumps + jumps.jumps;
                return Ok(self.attempt_report(None, cycle, history, t0, jumps, touching.at));
            }
            prev = now;
            let w = self.judged_stall_window(touching.at.is_some(), closed);
            let judged = &history[touching.judged_from..];
            let early = self.judged_early(touching.at.is_some(), closed)
                && stalled_early(judged, rec.points, near);
            if early || stalled_over(judged, rec.points, w) {
                if closed && settled_round_closure(&history[history.len() - w..]) {
                    self.let_touch(&mut touching, cycle, history.len(), false);
                    prev = (f64::NAN, None);
                    continue;
                }
                stalled = true;
                break;
            }
        }
        let jumps = mode_jumps + jumps.jumps;
        if let Some(r) = self.lubricated_report(&mut touching, &mut history, t0, jumps) {
            return Ok(r);
        }
        let diagnosis = Some(self.diagnose(&history, stalled));
        Ok(self.attempt_report(diagnosis, cycle, history, t0, jumps, touching.at))
    }

    /// From cycle `cycle` on the solids touch where the film has closed, on every grid; the
    /// stall is judged on the cycles from `history_len` on. `keep`: the state now is a
    /// converged lubricated answer, kept to return to should the touching cycles not converge.
    fn let_touch(&mut self, t: &mut Touching, cycle: usize, history_len: usize, keep: bool) {
        if keep {
            t.lubricated = Some((self.save(), history_len, cycle));
        }
        self.levels.iter_mut().for_each(|lv| lv.touch = true);
        (t.at, t.judged_from) = (Some(cycle), history_len);
    }

    /// The full-multigrid start: level `l`'s pressure and film content prolonged to the next
    /// finer level, which starts from them with no right-hand side, its film recomputed.
    fn start_finer(&mut self, l: usize) {
        let p = prolong(&self.levels[l].p);
        let theta = prolong(&self.levels[l].theta);
        let h00 = self.h00;
        let f = &mut self.levels[l - 1];
        f.p = p;
        f.theta = theta;
        f.rhs.fill(0.0);
        f.update_film(h00);
    }

    /// A mass-conserving steady solve (not a time step's cycles).
    pub(super) fn fed_steady(&self) -> bool {
        self.levels[0].mass_conserving() && self.levels[0].time_a0 == 0.0
    }

    /// A fed steady solve after the full-multigrid start's cycle `rec`: where its film closes
    /// the start's coarser grids relax with [`ReynoldsSettings::fed_omega_gs`] too, for this
    /// attempt and the solve's later ones (fed 25 nm at 2 mm/s, 80 N on 257², whose cycles
    /// with larger changes stalled settled once the solids touched).
    pub(super) fn watch_fed_start(&mut self, rec: &CycleLog) {
        if self.fed_steady() && rec.minimum_film < 0.0 {
            let w = &mut self.active.relax.omega_gs;
            *w = w.min(self.active.fed_omega_gs);
        }
    }

    /// The Gauss–Seidel changes' factor of a cycle with level `l` on top: a fed steady solve's
    /// finest-grid cycles take [`ReynoldsSettings::fed_omega_gs`] where it is smaller, its
    /// full-multigrid start the settings' own.
    pub(super) fn cycle_omega_gs(&self, l: usize) -> f64 {
        let w = self.active.relax.omega_gs;
        if l == 0 && self.fed_steady() { w.min(self.active.fed_omega_gs) } else { w }
    }

    /// Back to the converged lubricated answer the solids were let touch from, when one was
    /// kept and the touching cycles neither converged nor settled: its state and record, no
    /// contact, and its report. A closure that touching does not resolve keeps the answer it
    /// had, flagged for its film below zero. Touching cycles that stalled settled
    /// ([`Self::touching_settled`]) keep theirs (returned as settled, the contact reported).
    fn lubricated_report(
        &mut self,
        t: &mut Touching,
        history: &mut Vec<CycleLog>,
        t0: Instant,
        mode_jumps: usize,
    ) -> Option<ReynoldsReport> {
        let since = &history[t.judged_from.min(history.len())..];
        if t.at.is_some() && self.touching_settled(since).is_some() {
            return None;
        }
        let (state, len, cycle) = t.lubricated.take()?;
        self.restore(state);
        for lv in &mut self.levels {
            lv.touch = false;
            lv.contact.fill(false);
        }
        let h00 = self.h00;
        self.levels[0].update_film(h00);
        history.truncate(len);
        *t = Touching::default();
        Some(self.attempt_report(None, cycle, std::mem::take(history), t0, mode_jumps, None))
    }

    /// How touching cycles that stalled settled over the last stall window of `history`
    /// ([`settled`]): `None` when they did not.
    fn touching_settled(&self, history: &[CycleLog]) -> Option<Settled> {
        settled(history, self.stall_window(), self.active.mass_tolerance)
    }

    /// The report of an attempt's cycles: converged without a diagnosis, else with it.
    pub(super) fn attempt_report(
        &self,
        diagnosis: Option<Diagnosis>,
        cycles: usize,
        history: Vec<CycleLog>,
        t0: Instant,
        mode_jumps: usize,
        touched_from: Option<usize>,
    ) -> ReynoldsReport {
        // Touching cycles that stalled settled are an answer (the solids touching where the
        // film closed): no later attempt starts over from a lubricated start that closes again.
        let stuck = diagnosis
            .as_ref()
            .is_some_and(|d| matches!(d.kind, FailureKind::Stalled | FailureKind::LimitCycle));
        let settled =
            (touched_from.is_some() && stuck).then(|| self.touching_settled(&history)).flatten();
        let nx = self.grid().nx;
        ReynoldsReport {
            converged: diagnosis.is_none(),
            diagnosis,
            cycles,
            work_cycles: history.iter().map(|c| cycle_work(c.points, nx)).sum(),
            history,
            wall_time_s: t0.elapsed().as_secs_f64(),
            lagged_laws: self.active.relax.coefficient_lag,
            first_attempt: None,
            omega_gs: self.cycle_omega_gs(0),
            settled,
            mode_jumps,
            from_flooded: false,
            inflow_filled: false,
            touched_from,
            from_dry: false,
            attempts: self.attempts,
        }
    }
}

/// Why a steady attempt was given up, and after how many cycles: a divergence, a stall or a
/// limit cycle (not one whose touching cycles settled: that is an answer). Not a cycle limit
/// (more of the same would converge), nor a closed film, which
/// the lagged and smaller-change attempts did not open where tried; a fed film that closed goes
/// to the start from the flooded answer ([`ReynoldsSettings::flooded_start_fallback`]).
pub(super) fn given_up(rep: &Result<ReynoldsReport, ReynoldsError>) -> Option<(String, usize)> {
    match rep {
        // A stop asked for ends the solve: no attempt follows.
        Err(ReynoldsError::Cancelled(_)) => None,
        Err(e) => Some((e.to_string(), e.cycle())),
        Ok(r) => r
            .diagnosis
            .as_ref()
            .filter(|d| matches!(d.kind, FailureKind::Stalled | FailureKind::LimitCycle))
            .filter(|_| r.settled.is_none())
            .map(|d| (d.text.clone(), r.cycles)),
    }
}

/// A failed attempt's diagnosis and cycles, whether its film closed or it gave up.
pub(super) fn failure(rep: &Result<ReynoldsReport, ReynoldsError>) -> Option<(String, usize)> {
    film_closed(rep).or_else(|| given_up(rep))
}

/// Where one more attempt of a steady solve begins ([`ReynoldsSolver::attempt`]).
#[derive(Clone, Copy, Debug)]
pub(super) enum Begin {
    /// From the start: the Hertz pressure and the full-multigrid start.
    Afresh,
    /// From the state the attempt before left, no full-multigrid start.
    WhereLeft,
}

/// Where the attempt from the flooded answer ended
/// ([`ReynoldsSettings::flooded_start_fallback`]).
pub(super) enum FromFlooded {
    /// The flooded solve did not converge: its outcome.
    Flooded(Result<ReynoldsReport, ReynoldsError>),
    /// The fed cycles from the flooded answer: their outcome.
    Fed(Result<ReynoldsReport, ReynoldsError>),
}

/// What a steady attempt that did not converge says: its diagnosis, or its error.
pub(super) fn what_it_said(rep: &Result<ReynoldsReport, ReynoldsError>) -> String {
    match rep {
        Ok(r) => r.diagnosis.as_ref().map(|d| d.text.clone()).unwrap_or_default(),
        Err(e) => e.to_string(),
    }
}

/// A failed steady solve's report or divergence with `note` added to what it says.
pub(super) fn with_note(
    rep: Result<ReynoldsReport, ReynoldsError>,
    note: &str,
) -> Result<ReynoldsReport, ReynoldsError> {
    match rep {
        Ok(mut r) => {
            if let Some(d) = r.diagnosis.as_mut() {
                d.text.push_str(note);
            }
            Ok(r)
        }
        Err(ReynoldsError::Diverged { cycle, kind, at, what, film, load }) => {
            let what = format!("{what}{note}");
            Err(ReynoldsError::Diverged { cycle, kind, at, what, film, load })
        }
        Err(e) => Err(e),
    }
}

/// A steady attempt that ended with its film closed, and after how many cycles.
pub(super) fn film_closed(rep: &Result<ReynoldsReport, ReynoldsError>) -> Option<(String, usize)> {
    match rep {
        Err(_) => None,
        Ok(r) => r
            .diagnosis
            .as_ref()
            .filter(|d| matches!(d.kind, FailureKind::FilmClosed))
            .map(|d| (d.text.clone(), r.cycles)),
    }
}

/// How far a stalled answer's central film may still move over the stall window, relative to
/// it, for its closed film to become contact: the closure's own rows keep the lubricated
/// answer moving by a percent or two (the seed's contact fed 0.2 nm: 1.2 % on 257²); an answer
/// that moves by tens of percent (the same on 513²: ±60 %) passes through its closures, and
/// touching there turned into a contact over the whole Hertz zone.
pub const CLOSURE_SETTLED: f64 = 3e-2;

/// Whether a stalled answer has settled round its closed film: its central film within
/// [`CLOSURE_SETTLED`] and its force balance within [`SETTLED_BOUND`] over the `window`'s
/// cycles.
fn settled_round_closure(window: &[CycleLog]) -> bool {
    let (lo, hi) = window.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| {
        (l.min(c.central_film), h.max(c.central_film))
    });
    let load = window.iter().fold(0.0f64, |m, c| m.max(c.load_error.abs()));
    hi - lo < CLOSURE_SETTLED * hi.abs() && load < SETTLED_BOUND
}

/// The solids' contact in a steady solve's cycles: the cycle from which they touch, the
/// cycles the stall is judged on from, and the converged lubricated answer (its state, the
/// length of its record, its cycle) to return to should touching not converge.
#[derive(Default)]
struct Touching {
    at: Option<usize>,
    judged_from: usize,
    lubricated: Option<(SolverState, usize, usize)>,
}

/// In a time step the whole film settles, not the centre alone
/// ([`ReynoldsSettings::step_film_tolerance`]).
struct FilmBefore {
    /// The film as the cycle before left it (the step's start before the first cycle) …
    film: Array2<f64>,
    /// … the stop rule's floor, where the centre has closed …
    floor: f64,
    /// … and the largest change a cycle that is settled.
    tolerance: f64,
}

impl FilmBefore {
    /// In a time step (the time term on), from the film as it stands.
    fn in_step(finest: &Level, floor: f64, s: &ReynoldsSettings) -> Option<Self> {
        (finest.time_a0 > 0.0).then(|| Self {
            film: finest.film.clone(),
            floor,
            tolerance: s.step_film_tolerance,
        })
    }

    /// Whether no film changed since the last call by more than the tolerance, relative to
    /// the larger of its own and the central film (the floor where the centre has closed);
    /// the film is remembered for the next.
    fn settled(&mut self, finest: &Level, rec: &CycleLog) -> bool {
        let floor = rec.central_film.abs().max(self.floor);
        let change = Zip::from(&finest.film)
            .and(&self.film)
            .fold(0.0, |m: f64, &a, &b| m.max((a - b).abs() / a.abs().max(floor)));
        self.film.assign(&finest.film);
        change < self.tolerance
    }
}
