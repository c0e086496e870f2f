//! The Reynolds march: the solver as the driver steps it, the plan of its steps, a squeezed
//! start's rest, and the dents it carries.

use super::{SqueezedRest, TransientRecord, TransientRow};
use crate::drive::{self, Step, Transient};
use crate::error::{Result, Within};
use ehl_core::observe::Observables;
use ehl_core::{Grid, Kinematics, Relief};
use ehl_reynolds::{ReynoldsParams, ReynoldsSolver};
use ehl_scene::{MarchCase, ReynoldsView};
use ndarray::Array2;

/// The squeezed start: the steady solve at the scene's speed (the surfaces rolled before they
/// were squeezed; the caller solved it), a sudden stop, and rest under the load until the squeeze
/// is steady by the scene's own rule (its tolerance, its window in time), at most
/// [`SQUEEZE_START_MAX_S`]: the Reynolds film's counterpart of the layer model's steady squeeze.
/// The trapped film drains for as long as one waits (its lobes closed, the centre sealed), so
/// "steady" is the scene's tolerance over its window, not a limit reached.
pub(super) fn squeeze_start(
    view: &ReynoldsView,
    march: &MarchCase,
    prm: &ReynoldsParams,
    solver: &mut ReynoldsSolver,
) -> Result<SqueezedRest> {
    let rest = march.at_rest(SQUEEZE_START_MAX_S)?;
    let plan = march_plan(&view.name, &rest, prm, &solver.grid())?;
    let t = run_transient(&view.name, plan, &rest, prm, solver, view.supply.clone())
        .within(|| "the squeezed start (at rest after steady rolling)".to_string())?;
    Ok(SqueezedRest {
        rest_s: t.observed.last().map_or(0.0, |o| o.0),
        steps: t.rows.len().saturating_sub(1),
        ended: t.stop_reason,
    })
}

/// The longest rest a squeezed start takes [s]: the seed's time to its steady squeeze (Sect.
/// 4.2, about 5 s).
const SQUEEZE_START_MAX_S: f64 = 5.0;

/// Puts the surfaces' relief into the solver's rigid film, moved by `travel` [a] from its
/// start, in units of `a²/R`: the core's relief, the layer model's too.
pub(super) fn set_relief(solver: &mut ReynoldsSolver, relief: &Relief, travel: f64) {
    let delta = solver.prm.scales.delta;
    solver.set_extra_gap_on(|g| relief.gap_on(g, travel, delta));
}

/// The Reynolds solver as the driver marches it: each step moves the relief by the travel of
/// the surfaces, sets the wedge term's speed, and solves to the scene's tolerances from the
/// last state.
struct ReynoldsMarch<'a> {
    solver: &'a mut ReynoldsSolver,
    relief: Relief,
    /// The supply when it has holes: the inflow boundary's layer follows them.
    holes: Option<ehl_core::Supply>,
    /// Time since the motion started [s] and the time unit `a/u_ref` [s].
    t_s: f64,
    time_unit: f64,
    /// How the surfaces move (the relief travels with them).
    motion: Kinematics,
    /// Where the first dent starts [a] (0 without dents: the travel).
    x0: f64,
    centre: (usize, usize),
    /// The steady start's central film [m]: the films' scale for the steady rule.
    h_ref: f64,
    /// The error estimate's watched quantities `(t [s], [H_c, H_min, H00])` of the last two
    /// accepted states, newest first: the predictor extrapolates them.
    watched: Vec<(f64, [f64; 3])>,
}

impl ReynoldsMarch<'_> {
    /// What error control watches: the central film, the minimum film and `H00`. Where the
    /// solids touch the minimum film is the contact's 0 (its step from the last open film to
    /// 0 counts, as the closing it is), not the contact edge's hundredths of a nanometre from
    /// step to step, which are no error of the time step and would double the steps of a
    /// squeeze (docs/decisions.md, "Steps at rest").
    fn watched_now(&self) -> [f64; 3] {
        let (hc, hmin) = self.solver.films();
        let touching = self.solver.contact().1 > 0.0;
        [hc, if touching { 0.0 } else { hmin }, self.solver.h00]
    }
}

impl Transient for ReynoldsMarch<'_> {
    type Row = TransientRow;
    type Snapshot = (Array2<f64>, Array2<f64>);
    type Saved = (ehl_reynolds::SolverState, f64, Vec<(f64, [f64; 3])>);
    fn time(&self) -> f64 {
        self.t_s
    }
    /// The local error estimate of a step (backward Euler, error `O(dt²)`): the gap between
    /// the solution and the linear extrapolation of the last two states, times
    /// `dt / (dt + dt_prev)` (the standard estimate of the first-order scheme's local error),
    /// largest over the central film, the minimum film (0 where the solids touch) and `H00`,
    /// over the central film.
    fn step(&mut self, dt: f64, estimate_error: bool) -> Result<Step> {
        let t_new = self.t_s + dt;
        let travel = self.motion.travel(t_new) / self.solver.prm.scales.a;
        if !self.relief.is_empty() {
            set_relief(self.solver, &self.relief, travel);
        }
        if let Some(sup) = &self.holes {
            let (x_in, delta) = (self.solver.grid().x(0), self.solver.prm.scales.delta);
            self.solver.set_inflow(Some(&|y| sup.thickness_at(x_in, y, travel) / delta));
        }
        // The wedge term at the speed of the time solved for (the scales stay at u_ref).
        self.solver.set_speed(self.motion.speed(t_new) / self.motion.reference_speed());
        // How steep the dents' walls are on these cells over the steady film: a gap that jumps
        // tenfold from one cell to the next is no thin film, and a failure at a dent says so.
        let cell = self.solver.grid().dx().max(self.solver.grid().dy());
        let where_ = || match (self.relief.dents.is_empty(), self.relief.is_empty()) {
            (false, _) => {
                let walls = self.relief.dents.iter();
                let steepest =
                    walls.map(|d| d.steepest_cell_ratio(cell, self.h_ref)).fold(1.0, f64::max);
                format!(
                    "dent at x = {:.3} a, its walls changing the gap up to {steepest:.3}× from one cell to the next on this grid over the steady central film ({:.2} nm)",
                    self.x0 + travel,
                    self.h_ref * 1e9
                )
            }
            (true, false) => format!("surfaces moved {travel:.3} a"),
            (true, true) => format!("u = {:.4e} m/s", self.motion.speed(t_new)),
        };
        let rep = self.solver.step(dt / self.time_unit, &mut |_| {}).within(where_)?;
        let now = self.watched_now();
        let error_estimate = match (estimate_error, self.watched.as_slice()) {
            (true, [(t1, y1), (t0, y0), ..]) => {
                let dt_prev = t1 - t0;
                let k = dt / (dt + dt_prev);
                let scale = now[0].abs().max(f64::MIN_POSITIVE);
                let worst = (0..3)
                    .map(|q| {
                        let pred = y1[q] + dt * (y1[q] - y0[q]) / dt_prev;
                        k * (now[q] - pred).abs() / scale
                    })
                    .fold(0.0, f64::max);
                Some(worst)
            }
            _ => None,
        };
        self.t_s = t_new;
        self.watched.insert(0, (t_new, now));
        self.watched.truncate(2);
        Ok(Step { solves: 1, iterations: rep.cycles, error_estimate })
    }
    fn row(&self, step: &Step, ob: &Observables) -> TransientRow {
        let (p, s) = (self.solver.pressure(), self.solver.prm.scales);
        let (jc, ic) = self.centre;
        let t_s = self.time();
        let (share, area) = self.solver.contact();
        TransientRow {
            t_s,
            speed_m_s: self.motion.speed(t_s),
            dent_x_m: self.x0 * self.solver.prm.scales.a + self.motion.travel(t_s),
            central_film_m: ob.central_film_m,
            minimum_film_m: ob.minimum_film_m,
            film_overlap_m: ob.film_overlap_m,
            max_pressure_pa: ob.max_pressure_pa,
            central_pressure_pa: s.p_si(p[[jc, ic]]),
            contact_load_share: share,
            contact_area_m2: area * s.a * s.a,
            oil_into_contact: self
                .solver
                .oil_balance()
                .map(|b| b.into_contact / b.reference_supply),
            h00_m: s.h_si(self.solver.h00),
            cycles: step.iterations,
        }
    }
    /// Central and minimum film per the steady start's central film, maximum pressure per `p_h`.
    fn monitors(&self, r: &TransientRow) -> Vec<f64> {
        let (h, p_h) = (self.h_ref, self.solver.prm.scales.p_h);
        vec![r.central_film_m / h, r.minimum_film_m / h, r.max_pressure_pa / p_h]
    }
    fn snapshot(&self) -> Self::Snapshot {
        (self.solver.pressure().clone(), self.solver.film().clone())
    }
    fn fields(&self) -> Vec<(String, Array2<f64>)> {
        let (s, sc) = (&*self.solver, self.solver.prm.scales);
        vec![
            ("pressure_pa".into(), s.pressure().mapv(|v| sc.p_si(v))),
            ("film_m".into(), s.film().mapv(|v| sc.h_si(v))),
            ("film_content".into(), s.theta().clone()),
        ]
    }
    fn observables(&self) -> Observables {
        let s = &self.solver;
        Observables::from_fields(&s.grid(), &s.prm.scales, s.pressure(), s.film())
    }
    fn save(&self) -> Option<Self::Saved> {
        Some((self.solver.save(), self.t_s, self.watched.clone()))
    }
    fn restore(&mut self, saved: Self::Saved) {
        let (state, t, watched) = saved;
        self.solver.restore(state);
        self.t_s = t;
        self.watched = watched;
    }
}

/// The driver's plan of a march on `g`: while the surfaces roll, steps per cell at the speed;
/// at rest, error control from a first step of one cell's transit at the reference speed
/// (backward Euler: local error of order 2 in the step).
pub(super) fn march_plan(
    name: &str,
    march: &MarchCase,
    prm: &ReynoldsParams,
    g: &Grid,
) -> Result<drive::Plan> {
    let (a, motion) = (prm.scales.a, &march.motion);
    let controlled = Some((g.dx() * a / motion.reference_speed(), 2.0));
    let plan = drive::Plan::from_run(&march.run, &march.passing, g, a, motion, controlled)
        .within(|| format!("scene `{name}`: run"))?;
    Ok(plan.per_passage(&march.relief, g, a, motion))
}

/// Marches the scene's run from the steady solution on `plan` ([`march_plan`]: steps per cell,
/// the stop rule, snapshots); a step that does not converge ends the run with its diagnosis,
/// step and time.
pub(super) fn run_transient(
    name: &str,
    mut plan: drive::Plan,
    case: &MarchCase,
    prm: &ReynoldsParams,
    solver: &mut ReynoldsSolver,
    supply: Option<ehl_core::Supply>,
) -> Result<TransientRecord> {
    let (motion, relief) = (case.motion.clone(), case.relief.clone());
    let s = prm.scales;
    let g = solver.grid();
    // An error estimate below the solve's own algebraic error (the central film settles to
    // `film_tolerance` per cycle) is that error's noise: error control asks no less than ten
    // times it: asked as tightly as the solve converges, a squeeze rejects its steps on the
    // solve's noise and never grows them.
    let floor = 10.0 * solver.settings.film_tolerance;
    for ph in &mut plan.phases {
        if let drive::Steps::Controlled { tolerance, .. } = &mut ph.steps {
            *tolerance = tolerance.max(floor);
        }
    }
    // The time step reported: the first phase's (fixed steps), or the first step tried.
    let dt_s = match plan.phases.first().map(|p| p.steps) {
        Some(drive::Steps::Fixed { dt_s }) => dt_s,
        Some(drive::Steps::Controlled { dt0_s, .. }) => dt0_s,
        None => 0.0,
    };
    // The first feature's start (the first dent, else the first hole; 0 without any).
    let x0 = case.passing.first().map_or(0.0, |p| p.x_start_a);
    let centre = (g.row_nearest(0.0), g.col_nearest(0.0));
    let time_unit = s.a / motion.reference_speed();
    let h_ref = s.h_si(solver.films().0);
    // Holes already inside the domain at the start: no oil there where the gap is not full.
    let holes = supply.filter(|s| !s.holes.is_empty());
    if let Some(sup) = &holes {
        solver.set_theta(|x, y, t| if sup.thickness_at(x, y, 0.0) > 0.0 { t } else { 0.0 });
    }
    let watched = {
        let (hc, hmin) = solver.films();
        vec![(0.0, [hc, hmin, solver.h00])]
    };
    let mut march = ReynoldsMarch {
        solver,
        relief,
        holes,
        t_s: 0.0,
        time_unit,
        motion,
        x0,
        centre,
        h_ref,
        watched,
    };
    let expected = plan.end.as_ref().map_or(0, |e| (e.0 / dt_s).round() as u64);
    let spin = crate::progress::bar(expected, "reynolds march");
    let rec = drive::drive(&mut march, &plan, &mut |_| spin.inc(1))
        .within(|| format!("scene `{name}`: Reynolds march"))?;
    spin.finish_and_clear();
    let at = |t: f64| x0 + march.motion.travel(t) / s.a;
    Ok(TransientRecord {
        snapshots: rec.snapshots.into_iter().map(|(t, (p, h))| (t, at(t), p, h)).collect(),
        passing: !case.passing.is_empty(),
        rows: rec.rows,
        observed: rec.observed,
        dt_s,
        dt_a: dt_s / time_unit,
        wall_time_s: rec.wall_time_s,
        rejected_steps: rec.rejected_steps,
        dt_range: rec.dt_range,
        finished: rec.finished,
        stop_reason: rec.stop_reason,
        squeezed_rest: None,
    })
}
