//! Reynolds-model scenes: the steady EHL solve and what it writes.

mod figures;
mod finer;
use finer::FinerStart;
mod march;
use march::{march_plan, run_transient, set_relief, squeeze_start};
pub mod flow;
mod report;
use crate::error::{Result, Within};
use crate::model::{Centreline, ContactModel, Indicator, Outcome, q};
use ehl_core::observe::Observables;
use ehl_core::{Grid, HertzScales, hertz};
use ehl_reynolds::formulas::{hamrock_dowson_central, nvm_central};
use ehl_reynolds::{ReynoldsParams, ReynoldsReport, ReynoldsSolver};
use ehl_scene::{ReynoldsView, Scene, StartState};
use ndarray::{Array2, Zip};
use report::reynolds_report;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A Reynolds solution: steady, or the final state of a march, with the march's record.
pub struct ReynoldsOutcome {
    /// The scene run.
    pub scene: Scene,
    /// What the model read of the scene.
    pub view: ReynoldsView,
    /// The dimensionless parameters.
    pub prm: ReynoldsParams,
    /// The finest grid [a].
    pub grid: Grid,
    /// Pressure `P` [p_h] and film `H` [a²/R].
    pub p: Array2<f64>,
    /// Film `H` [a²/R].
    pub film: Array2<f64>,
    /// Film content `θ` (1 where the gap is full; all ones fully flooded).
    pub theta: Array2<f64>,
    /// Where the solids touch (the film closed: `H = 0`, the pressure there the contact's).
    pub contact: Array2<bool>,
    /// `H00` [a²/R].
    pub h00: f64,
    /// The steady solve's report.
    pub report: ReynoldsReport,
    /// Central film from the formulas [m]: Hamrock–Dowson, NVM.
    pub formulas: (f64, f64),
    /// Building the solver [s].
    pub setup_time_s: f64,
    /// The dent's passage, for a transient scene (`p`, `film` are then its final state).
    pub transient: Option<TransientRecord>,
    /// Where the answer's oil goes (mass conserving; `None` fully flooded).
    pub oil: Option<ehl_reynolds::OilBalance>,
}

/// One time step of a transient run, SI.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TransientRow {
    /// Time from the start of the march [s].
    pub t_s: f64,
    /// The surfaces' speed [m/s].
    pub speed_m_s: f64,
    /// Dent centre [m] (without dents: the travel from the start).
    pub dent_x_m: f64,
    /// Central film [m].
    pub central_film_m: f64,
    /// Minimum film [m] (at least 0: a film is a separation).
    pub minimum_film_m: f64,
    /// How far the film field went below zero [m] (the solids' overlap: a discretisation error).
    pub film_overlap_m: f64,
    /// Maximum pressure [Pa].
    pub max_pressure_pa: f64,
    /// Central pressure [Pa].
    pub central_pressure_pa: f64,
    /// The share of the load carried where the solids touch (the film closed: `H = 0`) [-].
    pub contact_load_share: f64,
    /// The area where the solids touch [m²].
    pub contact_area_m2: f64,
    /// The oil the touching points took in the step (arriving at the closed gap, and what the
    /// gap held before it closed), over the supply's flux at the reference speed [-]; `None`
    /// fully flooded ([`ehl_reynolds::OilBalance`]).
    pub oil_into_contact: Option<f64>,
    /// `H00` [m].
    pub h00_m: f64,
    /// Multigrid cycles of the step.
    pub cycles: usize,
}

/// A transient run: rows per step, fields at the requested dent positions, cost.
pub struct TransientRecord {
    /// The start, then one row per step.
    pub rows: Vec<TransientRow>,
    /// Time [s], first feature's position [a] (the travel without features), pressure
    /// [p_h], film [a²/R].
    pub snapshots: Vec<(f64, f64, Array2<f64>, Array2<f64>)>,
    /// Whether features pass (the histories and snapshots are then told by position, else by
    /// time).
    pub passing: bool,
    /// The standard observables after every step (time [s]).
    pub observed: Vec<(f64, Observables)>,
    /// The first phase's step [s] (equal steps), or the first step error control tries.
    pub dt_s: f64,
    /// The step in the time unit `a/u_ref`.
    pub dt_a: f64,
    /// Wall time of the march [s].
    pub wall_time_s: f64,
    /// Steps error control rejected (or retried after a failed solve).
    pub rejected_steps: usize,
    /// `(smallest, largest)` step [s].
    pub dt_range: (f64, f64),
    /// Ended by its rule, not the time limit; and why it stopped.
    pub finished: bool,
    /// Why it stopped, in words.
    pub stop_reason: String,
    /// A squeezed start's rest, before the scene's motion.
    pub squeezed_rest: Option<SqueezedRest>,
}

/// The rest of a squeezed start: steady rolling, a sudden stop, and rest under the load.
#[derive(Clone, Debug)]
pub struct SqueezedRest {
    /// How long the contact rested [s] …
    pub rest_s: f64,
    /// … in how many steps …
    pub steps: usize,
    /// … and why the rest ended (steady, or the time limit).
    pub ended: String,
}

/// The registered Reynolds model.
pub struct Reynolds;

/// The Reynolds model fully flooded whatever the scene supplies (a comparison's reference for
/// the starved one): the same solver, given a scene without its `supply` block.
pub struct ReynoldsFlooded;

impl ContactModel for ReynoldsFlooded {
    fn kind(&self) -> ehl_scene::Model {
        ehl_scene::Model::ReynoldsFlooded
    }
    fn run(&self, scene: &Scene) -> Result<Box<dyn Outcome>> {
        Ok(Box::new(run_reynolds(scene)?))
    }
    /// A steady answer's coarser grids start from it ([`ReynoldsSolver::start_from_answer`]):
    /// the cycles a full-multigrid start spends finding the contact are not spent again.
    fn run_coarser(&self, coarse: &Scene, finer: &dyn Outcome) -> Result<Box<dyn Outcome>> {
        Ok(Box::new(run_reynolds_from(coarse, FinerStart::new(coarse, finer).as_ref())?))
    }
    fn inlet_distance(&self, scene: &Scene) -> f64 {
        Reynolds.inlet_distance(scene)
    }
    fn cell_needed(&self, scene: &Scene, change: f64) -> f64 {
        Reynolds.cell_needed(scene, change)
    }
    fn for_estimate(&self, coarse: Scene) -> Scene {
        Reynolds.for_estimate(coarse)
    }
    fn film_error_law(&self, scene: &Scene) -> Option<(f64, String)> {
        Reynolds.film_error_law(scene)
    }
    fn verified_order(&self) -> Option<(f64, &'static str)> {
        Reynolds.verified_order()
    }
}

pub use ehl_reynolds::formulas::CELLS_PER_FILM;

impl ContactModel for Reynolds {
    fn kind(&self) -> ehl_scene::Model {
        ehl_scene::Model::Reynolds
    }
    fn run(&self, scene: &Scene) -> Result<Box<dyn Outcome>> {
        Ok(Box::new(run_reynolds(scene)?))
    }
    /// A steady answer's coarser grids start from it ([`ReynoldsSolver::start_from_answer`]):
    /// the cycles a full-multigrid start spends finding the contact are not spent again.
    fn run_coarser(&self, coarse: &Scene, finer: &dyn Outcome) -> Result<Box<dyn Outcome>> {
        Ok(Box::new(run_reynolds_from(coarse, FinerStart::new(coarse, finer).as_ref())?))
    }
    /// Beyond Hamrock–Dowson's starvation boundary `m*` for the NVM central film: at `m*` itself
    /// the film is still a few per cent short, so `1 + 2 (m* − 1)` (docs/decisions.md, "The
    /// accuracy rule's constants").
    fn inlet_distance(&self, scene: &Scene) -> f64 {
        nvm_film(scene)
            .map_or(0.0, |h| 1.0 + 2.0 * (ehl_reynolds::formulas::starvation_boundary(h) - 1.0))
    }
    /// The accuracy rule ([`ehl_reynolds::formulas::cell_for_change`], never coarser than the
    /// film's existence needs) for the scene's NVM central film.
    fn cell_needed(&self, scene: &Scene, change: f64) -> f64 {
        nvm_film(scene)
            .map_or(f64::INFINITY, |h| ehl_reynolds::formulas::cell_for_change(h, change))
    }
    /// The first attempt alone, and at most `ESTIMATE_CYCLES` cycles: a coarse grid near the
    /// film's existence limit stalls and hands over to attempt after attempt, many times the
    /// finer answer's own cycles, and an answer that takes that is no error estimate to wait
    /// for (docs/decisions.md, "An error estimate's coarser grids").
    /// The grid error law of the central film ([`ehl_reynolds::formulas::GRID_CHANGE_PER_CELL2`]:
    /// the half grid moves it by `K ρ²`), read as the grid convergence index of that change at
    /// order 2, `1.25 K ρ² / 3`. Measured for `ρ` up to 0.25; beyond it (a grid coarser than
    /// the film's existence asks for) it overstates the error, which errs on the safe side.
    fn film_error_law(&self, scene: &Scene) -> Option<(f64, String)> {
        let h = nvm_film(scene)?;
        let g = scene.grid();
        let rho = g.dx().max(g.dy()) / h.powf(2.0 / 3.0);
        let k = ehl_reynolds::formulas::GRID_CHANGE_PER_CELL2;
        let error = 1.25 * k * rho * rho / 3.0;
        Some((
            error,
            format!(
                "the solver's measured grid law (the half grid moves h_c by {k} ρ², ρ = {rho:.3} the cell over H_c^(2/3)), at order 2"
            ),
        ))
    }
    /// Every film of `seed-speed-load` (35 points, 2 mm/s … 1 m/s, 5 … 80 N) converged at
    /// 1.92–2.09 on its three grids (`docs/sweeps.md`).
    fn verified_order(&self) -> Option<(f64, &'static str)> {
        Some((2.0, "measured 1.92-2.09 on the speed-load map"))
    }
    fn for_estimate(&self, mut coarse: Scene) -> Scene {
        if let Some(r) = coarse.reynolds.as_mut() {
            let s = &mut r.solver;
            s.max_cycles = s.max_cycles.min(ESTIMATE_CYCLES);
            s.load_tolerance = s.load_tolerance.max(ESTIMATE_LOAD_TOLERANCE);
            s.film_tolerance = s.film_tolerance.max(ESTIMATE_FILM_TOLERANCE);
            s.fallback_lag = 0.0;
            s.fallback_omega_gs = 0.0;
            s.flooded_start_fallback = false;
            s.filled_inflow_fallback = false;
        }
        coarse
    }
}

/// The most cycles a coarser grid of an error estimate is given ([`ContactModel::for_estimate`]):
/// above the flooded solve's 15–17 on any grid where it converges and the fed seed's 9–24.
const ESTIMATE_CYCLES: usize = 25;

/// The central film's change a cycle at which a coarser grid of an error estimate stops: a
/// sixth of the least error an estimate gives a film ([`crate::accuracy::FILM_FLOOR`]): a coarse
/// grid started from its finer answer settles quickly and then alternates by more than the
/// solve's own tolerance, which it never accepts (docs/decisions.md, "An error estimate's
/// coarser grids").
const ESTIMATE_FILM_TOLERANCE: f64 = 5e-4;

/// The force balance a coarser grid of an error estimate is held to: a load off by 1e-5 moves
/// the film by about 1e-6 (`h ∝ W^-0.07`), far below the least error an estimate gives a film
/// ([`crate::accuracy::FILM_FLOOR`]), where the solve's own tolerance costs a coarse grid many
/// cycles more.
const ESTIMATE_LOAD_TOLERANCE: f64 = 1e-5;

/// The Nijenbanning–Venner–Moes central film of the scene's rolling contact in Hertz units
/// [a²/R]; `None` without a lubricant, rolling or oil (a film the grid rule sizes cells for).
fn nvm_film(scene: &Scene) -> Option<f64> {
    let (Some(l), (c, u_sum)) = (&scene.lubricant, scene.reynolds_conditions()) else {
        return None;
    };
    if no_oil(scene) {
        return None;
    }
    (u_sum > 0.0).then(|| HertzScales::new(&c).h_dimless(nvm_central(&c, &l.lubricant(), u_sum)))
}

/// Whether the scene supplies no oil at all (`supply.thickness_m` = 0): its steady answer is
/// the dry contact ([`ehl_reynolds::ReynoldsSolver::solve`]).
fn no_oil(scene: &Scene) -> bool {
    scene.supply.is_some() && scene.oil_m().is_none()
}

impl Outcome for ReynoldsOutcome {
    fn solid_contact(&self) -> Option<ehl_core::SolidContact> {
        let s = &self.prm.scales;
        Some(ehl_core::SolidContact::from_mask(&self.grid, s, &self.p, &self.contact))
    }
    /// The discrete dry gap's error at the contact's edge, for a steady answer that started
    /// from the dry contact ([`ehl_reynolds::ReynoldsReport::from_dry`]); none without oil
    /// (no film on any grid).
    fn film_resolution_m(&self) -> Option<f64> {
        let gap = if no_oil(&self.scene) {
            0.0
        } else {
            ehl_reynolds::formulas::dry_gap_error(self.grid.dx())
        };
        (self.report.from_dry && self.transient.is_none()).then(|| self.prm.scales.h_si(gap))
    }
    fn caveat(&self) -> Option<String> {
        let r = &self.report;
        let settled = r.settled.map(|st| {
            format!(
                "steady solve {} with its answer settled: over its last {} cycles the central film moved by {:.1e} and the minimum film by {:.1e} (relative), force balance within {:.1e}",
                match r.diagnosis.as_ref().map(|d| d.kind) {
                    Some(ehl_reynolds::FailureKind::LimitCycle) => "in a limit cycle",
                    _ => "stalled",
                },
                st.window,
                st.central_film_spread,
                st.minimum_film_spread,
                st.load_error
            )
        });
        // A converged answer whose film went below zero somewhere (the solids overlap there):
        // the grid does not resolve the thinnest film. A march whose steps had contact
        // (`reynolds.solver.contact`, on by default) holds a closed film at `H = 0` where the
        // solids touch; the points beside the contact, decided before each sweep, can end
        // up to a hundredth of the central film below 0, the contact edge's discretisation,
        // not a missing contact: only below that it counts.
        let ob = self.observables();
        let rows = self.transient.as_ref().map(|t| t.rows.as_slice()).unwrap_or_default();
        let at_rest = rows.last().is_some_and(|r| r.speed_m_s == 0.0);
        let touched =
            rows.iter().any(|r| r.contact_area_m2 > 0.0) || self.contact.iter().any(|&c| c);
        let allowed = if touched { 1e-2 * ob.central_film_m.abs() } else { 0.0 };
        let negative = (ob.film_overlap_m > allowed).then(|| {
            let why = if at_rest {
                "the solids touch there at rest, and the steps had no contact between them (reynolds.solver.contact off): the film goes negative where they would".to_string()
            } else {
                format!(
                    "the grid does not resolve the thinnest film (the film exists on cells <= {:.4} a here: the sweeps' grid rule)",
                    Reynolds.cell_needed(&self.scene, f64::INFINITY)
                )
            };
            format!(
                "the film went {:.3e} m below zero (reported as 0: the solids overlap) at x = {:.3e} m, y = {:.3e} m: {why}",
                ob.film_overlap_m, ob.minimum_film_at_m.0, ob.minimum_film_at_m.1,
            )
        });
        // A pattern rolled through in first-order steps: they damp what the film carries of it
        // (docs/findings.md, "A wave through the contact"), which nothing else would show.
        let first_order = self
            .scene
            .reynolds
            .as_ref()
            .is_none_or(|r| r.solver.time_scheme == ehl_reynolds::TimeScheme::Bdf1);
        let patterned = self.scene.relief(self.prm.scales.a).is_ok_and(|r| r.has_pattern());
        let damped = (self.transient.is_some() && first_order && patterned).then(|| {
            "the surfaces' pattern rolled through in implicit Euler steps, which damp what the film carries of it (a wave on 12.8 steps kept 0.04 of its amplitude where second-order steps keep 0.65): its passage's swings and contact are understated; reynolds.solver.time_scheme \"bdf2\" where its steps converge".to_string()
        });
        // A pattern's amplitude in the film is a difference of films a few per cent apart:
        // steps that stop at a larger change a cycle leave it an iteration error of that order.
        let film_tolerance = self.view.spec.solver.film_tolerance;
        let loose = (self.transient.is_some()
            && patterned
            && film_tolerance > PATTERN_FILM_TOLERANCE)
            .then(|| {
                format!(
                    "its steps stopped at a change of {film_tolerance:.0e} a cycle in the central film: the pattern's amplitude in the film and the solids' share carry an iteration error (a 0.25 a wave on 129²: A_d/A_i 9-17 % off at 1e-4, 1-3 % at 1e-5, 0.2 % at 1e-6); reynolds.solver.film_tolerance {PATTERN_FILM_TOLERANCE:.0e}"
                )
            });
        [settled, negative, damped, loose, self.oil_lost()]
            .into_iter()
            .flatten()
            .reduce(|a, b| format!("{a}; {b}"))
    }
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn scales(&self) -> HertzScales {
        self.prm.scales
    }
    fn grid(&self) -> &Grid {
        &self.grid
    }
    fn pressure(&self) -> &Array2<f64> {
        &self.p
    }
    fn film(&self) -> Array2<f64> {
        // Where the solids touch the gap's equation holds it at `H = 0`: a closed gap, not an
        // overlap, to within what the grid tells from a closed gap at all. Deeper, the gap
        // equation is not met there (an answer returned settled, not converged: 2 mm/s, 80 N
        // on 257² held a touching point 2 nm deep at `P = 0`), and the overlap is reported.
        let closed = ehl_reynolds::formulas::dry_gap_error(self.grid.dx());
        let mut f = self.film.clone();
        Zip::from(&mut f).and(&self.contact).for_each(|h, &c| {
            if c && *h > -closed {
                *h = h.max(0.0)
            }
        });
        f
    }
    fn indicators(&self) -> Vec<(String, Indicator)> {
        vec![
            (
                flow::FLUX_INDICATOR.into(),
                Indicator::new(
                    self.flux_ratio_contact_mean(),
                    "1",
                    "pressure- / boundary-driven flux, contact mean (0: a solid layer)",
                    true,
                ),
            ),
            (
                "cycles".into(),
                Indicator::new(
                    self.report.cycles as f64,
                    "1",
                    "multigrid cycles of the steady solve",
                    false,
                ),
            ),
            (
                "lagged_laws".into(),
                Indicator::new(
                    self.report.lagged_laws,
                    "1",
                    "the laws' lag of the answer (0: none; > 0: a second attempt)",
                    false,
                ),
            ),
            (
                "from_flooded".into(),
                Indicator::new(
                    f64::from(u8::from(self.report.from_flooded)),
                    "1",
                    "1: the fed solve started from the flooded answer (its last attempt)",
                    false,
                ),
            ),
            (
                "inflow_filled".into(),
                Indicator::new(
                    f64::from(u8::from(self.report.inflow_filled)),
                    "1",
                    "1: flooded, the clamp's attempts failed on cells wider than the grid rule's; the answer is the mass-conserving solver's with the inflow filled",
                    false,
                ),
            ),
            (
                "from_dry".into(),
                Indicator::new(
                    f64::from(u8::from(self.report.from_dry)),
                    "1",
                    "1: the film is thinner than this grid tells from a closed gap; the answer started from the dry contact",
                    false,
                ),
            ),
            (
                "oil_into_contact".into(),
                Indicator::new(
                    self.oil_into_contact().unwrap_or(0.0),
                    "1",
                    "the oil the touching points took, of the oil supplied (a march: over its steps; 0: none, or flooded)",
                    false,
                ),
            ),
            (
                "contact_load_share".into(),
                Indicator::new(
                    self.transient.as_ref().map_or_else(
                        || Outcome::solid_contact(self).map_or(0.0, |c| c.load_share),
                        |t| t.rows.iter().map(|r| r.contact_load_share).fold(0.0, f64::max),
                    ),
                    "1",
                    "the largest share of the load the solids carried where they touched (a march: over its steps; a steady solve: its answer; 0: none)",
                    false,
                ),
            ),
        ]
    }
    fn conditions_used(&self) -> (ehl_core::Contact, f64) {
        (self.view.contact, 0.5 * self.view.sum_velocity_m_s)
    }
    fn wall_time_s(&self) -> f64 {
        self.setup_time_s
            + self.report.wall_time_s
            + self.transient.as_ref().map_or(0.0, |t| t.wall_time_s)
    }
    fn summary(&self) -> Value {
        ReynoldsOutcome::summary(self)
    }
    fn centreline(&self) -> Centreline {
        ReynoldsOutcome::centreline(self)
    }
    fn fields(&self) -> Vec<(String, Array2<f64>)> {
        ReynoldsOutcome::fields(self)
    }
    fn time_series(&self) -> Result<Option<Vec<Value>>> {
        self.transient.as_ref().map(|t| crate::model::json_rows(&t.rows)).transpose()
    }
    fn history(&self) -> Option<&[(f64, Observables)]> {
        self.transient.as_ref().map(|t| t.observed.as_slice())
    }
    fn contact_history(&self) -> Option<Vec<(f64, f64)>> {
        let t = self.transient.as_ref()?;
        Some(t.rows.iter().map(|r| (r.contact_load_share, r.contact_area_m2)).collect())
    }
    fn approach_history(&self) -> Option<Vec<(f64, f64)>> {
        self.transient.as_ref().map(|t| t.rows.iter().map(|r| (r.t_s, -r.h00_m)).collect())
    }
    fn snapshots(&self) -> Vec<(f64, &Array2<f64>, Array2<f64>)> {
        let Some(t) = &self.transient else { return vec![] };
        t.snapshots.iter().map(|(ts, _, p, h)| (*ts, p, h.clone())).collect()
    }
    fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
        ReynoldsOutcome::figures(self, dir, prefix, footnote)
    }
    fn report(&self) -> String {
        reynolds_report(self)
    }
}

/// The dimensionless parameters and a solver (hierarchy built, Hertz start) for a Reynolds
/// scene.
pub fn build_solver(scene: &Scene) -> Result<(ReynoldsParams, ReynoldsSolver)> {
    Ok(solver_for(&scene.reynolds_view()?))
}

/// The steps' film tolerance a pattern's march needs for its amplitude in the film and the
/// solids' share to carry no more than a few tenths of a per cent of iteration error: measured
/// on a 0.25 a wave through the seed's contact on 129² (flooded, 0.1 m/s), `A_d/A_i` 0.596 at
/// the default 1e-4, 0.556 at 1e-5, 0.549 at 1e-6; with the hierarchy to 17² instead of 33²,
/// 0.643, 0.566, 0.551 (docs/decisions.md, "The steps' film tolerance under a pattern").
pub const PATTERN_FILM_TOLERANCE: f64 = 1e-6;

/// The dimensionless parameters and a solver for a resolved Reynolds case.
fn solver_for(v: &ReynoldsView) -> (ReynoldsParams, ReynoldsSolver) {
    let (spec, lub) = (&v.spec, &v.lubricant);
    let prm =
        ReynoldsParams::from_si(&v.contact, lub, v.sum_velocity_m_s, spec.viscosity, spec.density);
    // Every grid of the hierarchy carries the surfaces' pattern (`ReynoldsSettings::carrying`).
    let shortest = v.march.as_ref().and_then(|m| m.relief.shortest_wave_a());
    let settings = match shortest {
        Some(l) => spec.solver.carrying(&v.grid, l),
        None => *spec.solver,
    };
    (prm, ReynoldsSolver::new(v.grid, prm, settings))
}

/// Solves a Reynolds scene: steady, then the march it asks for.
pub fn run_reynolds(scene: &Scene) -> Result<ReynoldsOutcome> {
    run_reynolds_from(scene, None)
}

/// Solves a Reynolds scene, its steady solve started from a finer answer when one is given
/// (else from Hertz, full multigrid).
fn run_reynolds_from(scene: &Scene, finer: Option<&FinerStart>) -> Result<ReynoldsOutcome> {
    // The scene resolved once: everything below reads the view.
    let view = scene.reynolds_view()?;
    let (contact, u_sum, lub) = (view.contact, view.sum_velocity_m_s, view.lubricant);
    let grid = view.grid;
    let t0 = Instant::now();
    let (prm, mut solver) = solver_for(&view);
    let run = view.march.as_ref();
    if run.is_some() {
        // A march starts from a steady answer whose coarser grids held the film content: from
        // the first attempt's answer, with them moving the menisci, a squeezed restart's first
        // step stopped unconverged (docs/decisions.md, "The start of a march").
        solver.settings.coarse_film_content = false;
    }
    // The march starts from the steady solution with the relief at its start.
    if let Some(m) = run.filter(|m| !m.relief.is_empty()) {
        set_relief(&mut solver, &m.relief, 0.0);
    }
    // The supply: the layer arriving at the inflow boundary (holes there at the start left
    // out of the steady solve: a steady contact has none; they enter as the march carries them).
    if let Some(sup) = &view.supply {
        let h_oil = sup.thickness_m / prm.scales.delta;
        solver.set_supply(Some(&|_| h_oil));
    }
    // A march starts from the steady state at the speed before its motion starts; a squeezed
    // start rolled at the scene's speed before it stopped.
    if let Some(m) = run {
        let before = if m.run.start == Some(StartState::Squeezed) {
            1.0
        } else {
            m.motion.speed_before() / m.motion.reference_speed()
        };
        solver.set_speed(before);
    }
    if let Some(f) = finer.filter(|_| run.is_none()) {
        // Near its own answer already: cycles from there, no full-multigrid start.
        solver.settings.fmg_cycles = 0;
        solver.start_from_answer(&|j, i| f.at(j, i), f.answer.h00);
    }
    let setup_time_s = t0.elapsed().as_secs_f64();
    let spin = crate::progress::spinner("reynolds");
    // Nothing is written for a solve that did not converge: its error says what happened.
    let report = solver
        .solve(&mut |c| {
            spin.set_message(format!(
                "reynolds cycle {}: H_c {:.5}, load error {:+.1e}",
                c.cycle, c.central_film, c.load_error
            ))
        })
        .within(|| format!("scene `{}`", view.name))?;
    spin.finish_and_clear();
    let formulas =
        (hamrock_dowson_central(&contact, &lub, 0.5 * u_sum), nvm_central(&contact, &lub, u_sum));
    let transient = match run {
        Some(m) => {
            // The march's plan, made before a squeezed start's rest (which may take long), so
            // that a plan the driver refuses is refused at once.
            let plan = march_plan(&view.name, m, &prm, &solver.grid())?;
            let rest = (m.run.start == Some(StartState::Squeezed))
                .then(|| squeeze_start(&view, m, &prm, &mut solver))
                .transpose()?;
            let mut t = run_transient(&view.name, plan, m, &prm, &mut solver, view.supply.clone())?;
            t.squeezed_rest = rest;
            Some(t)
        }
        None => None,
    };
    let (fp, ff) = (solver.pressure(), solver.film());
    let theta = solver.theta().clone();
    let touching = solver.contact_points().clone();
    Ok(ReynoldsOutcome {
        scene: scene.clone(),
        view: view.clone(),
        prm,
        grid,
        p: fp.clone(),
        film: ff.clone(),
        theta,
        contact: touching,
        h00: solver.h00,
        report,
        formulas,
        setup_time_s,
        transient,
        oil: solver.oil_balance(),
    })
}

impl ReynoldsOutcome {
    /// The oil the touching points took, as a share of the oil supplied: a steady answer's
    /// flows, or over a march the oil its steps took (each step's rate over its duration)
    /// against the oil the supply brought in over them; `None` fully flooded, or a march that
    /// brought none in (at rest throughout).
    pub fn oil_into_contact(&self) -> Option<f64> {
        let Some(t) = &self.transient else {
            return self.oil.map(|b| b.into_contact / b.reference_supply);
        };
        // A step's rates are its end's (implicit steps); the supply's flux goes with the
        // surfaces' speed, as a share of the flux at the reference speed.
        let u_ref = 0.5 * self.view.sum_velocity_m_s;
        let (mut taken, mut supplied) = (0.0, 0.0);
        for w in t.rows.windows(2) {
            let dt = w[1].t_s - w[0].t_s;
            taken += dt * w[1].oil_into_contact?;
            supplied += dt * w[1].speed_m_s / u_ref;
        }
        (supplied > 0.0).then(|| taken / supplied)
    }

    /// A march's largest share of the supply's flux the touching points took in one step.
    pub(crate) fn oil_into_contact_in_a_step(&self) -> Option<f64> {
        let rows = &self.transient.as_ref()?.rows;
        rows.iter().filter_map(|r| r.oil_into_contact).max_by(|a, b| a.abs().total_cmp(&b.abs()))
    }

    /// Where the touching points took more of the supplied oil than the solver's oil
    /// tolerance: the discrete equations destroy it (a point in contact has the gap's equation),
    /// so the film around the contact carries that much less: the contact edge's
    /// discretisation error, falling as the grid resolves the gap's closing.
    fn oil_lost(&self) -> Option<String> {
        let share = self.oil_into_contact()?;
        let tolerance = self.view.spec.solver.mass_tolerance;
        (share.abs() > tolerance).then(|| {
            format!(
                "the solids took {:.2} % of the supplied oil where they touch{} (the oil tolerance is {:.1} %): the closed gap's edge on cells of {:.4} a, where the discrete gap cannot close more sharply; a finer grid loses less",
                100.0 * share,
                if self.transient.is_some() { " over the march" } else { "" },
                100.0 * tolerance,
                self.grid.dx()
            )
        })
    }

    /// Central and minimum film [a²/R], maximum pressure [p_h]: the standard observables in
    /// Hertz units (one definition, `ehl_core::observe`).
    pub fn films(&self) -> (f64, f64, f64) {
        let (ob, sc) = (self.observables(), self.prm.scales);
        (ob.central_film_m / sc.delta, ob.minimum_film_m / sc.delta, ob.max_pressure_pa / sc.p_h)
    }

    /// A film in Hertz units to Moes' `h/R · U^(−1/2)` (U with the sum velocity).
    fn moes_film(&self, h: f64) -> f64 {
        h * (1.5 * self.prm.moes.m).powf(2.0 / 3.0)
    }

    /// What only the Reynolds model reports (`summary.json`'s `details`).
    pub fn summary(&self) -> Value {
        let s = &self.prm.scales;
        let (hc, hmin, pmax) = self.films();
        let u_sum = self.view.sum_velocity_m_s;
        let last = self.report.history.last().unwrap();
        json!({
            "moes": {
                "sum_velocity": q(u_sum, "m/s"),
                "m": self.prm.moes.m, "l": self.prm.moes.l, "lambda_bar": self.prm.lambda_bar,
            },
            "lubricant": self.scene.lubricant,
            "supply": match self.view.supply.as_ref() {
                Some(sup) => json!({
                    "thickness": q(sup.thickness_m, "m"),
                    "applied": true,
                    "cavitation": "mass conserving (film content θ, Elrod/JFO)",
                    "inlet_meniscus": self.meniscus_a().map(|x| q(s.x_si(x), "m")),
                    "oil": self.oil.map(|b| {
                        let share = |v: f64| v / b.reference_supply;
                        json!({
                            "what": "where the supplied oil goes, each a share of the supply's flux at the scene's speed (a march: its last step)",
                            "carried_out": share(b.carried_out),
                            "pressed_out_at_edges": share(b.pressed_out),
                            "into_contact": share(b.into_contact),
                            "stored": share(b.stored),
                            "unaccounted": share(b.unaccounted),
                        })
                    }),
                }),
                None => json!({ "applied": false, "cavitation": "fully flooded, Reynolds' condition (P ≥ 0)" }),
            },
            "laws": { "viscosity": self.view.spec.viscosity, "density": self.view.spec.density },
            "results": {
                "central_film": q(s.h_si(hc), "m"),
                "minimum_film": q(s.h_si(hmin), "m"),
                "max_pressure": q(s.p_si(pmax), "Pa"),
                "h00": q(s.h_si(self.h00), "m"),
            },
            "dimensionless": {
                "central_film_hertz": hc, "minimum_film_hertz": hmin, "h00_hertz": self.h00,
                "central_film_moes": self.moes_film(hc), "minimum_film_moes": self.moes_film(hmin),
                "max_pressure_over_p_h": pmax,
            },
            "formulas_central_film": {
                "hamrock_dowson_1977": q(self.formulas.0, "m"),
                "nijenbanning_venner_moes_1994": q(self.formulas.1, "m"),
            },
            "solver": {
                "settings": self.view.spec.solver,
                "cycles": self.report.cycles,
                "work_cycles": self.report.work_cycles,
                "lagged_laws": self.report.lagged_laws,
                "first_attempt": self.report.first_attempt,
                "omega_gs": self.report.omega_gs,
                "from_flooded": self.report.from_flooded,
                "inflow_filled": self.report.inflow_filled,
                "touched_from_cycle": self.report.touched_from,
                "from_dry": self.report.from_dry,
                "attempts": self.report.attempts,
                "settled": self.report.settled,
                "final_residual": last.residual,
                "final_load_error": last.load_error,
                "history": self.report.history,
                "setup_time": q(self.setup_time_s, "s"),
                "solve_time": q(self.report.wall_time_s, "s"),
            },
            "transient": self.transient.as_ref().map(|t| {
                let cycles: usize = t.rows.iter().map(|r| r.cycles).sum();
                let steps = t.rows.len() - 1;
                json!({
                    "what": "results above are the final state; the steady solve is the start",
                    "steps": steps, "dt": q(t.dt_s, "s"), "dt_over_a_per_u_m": t.dt_a,
                    "courant_number": t.dt_a / self.grid.dx(),
                    "cycles_per_step": cycles as f64 / steps as f64,
                    "wall_time": q(t.wall_time_s, "s"),
                    "wall_time_per_step": q(t.wall_time_s / steps as f64, "s"),
                    "snapshots_at_s": t.snapshots.iter().map(|s| s.0).collect::<Vec<_>>(),
                    "snapshots_at_dent_x_a": t.passing.then(|| t.snapshots.iter().map(|s| s.1).collect::<Vec<_>>()),
                    "rejected_steps": t.rejected_steps,
                    "dt_range": [q(t.dt_range.0, "s"), q(t.dt_range.1, "s")],
                    "finished": t.finished, "stop_reason": t.stop_reason,
                    "squeezed_start": t.squeezed_rest.as_ref().map(|r| json!({
                        "what": "steady rolling, a sudden stop, and rest under the load before the scene's motion",
                        "rest": q(r.rest_s, "s"), "steps": r.steps, "ended": r.ended,
                    })),
                })
            }),
        })
    }

    fn row(&self, f: &Array2<f64>) -> Vec<f64> {
        f.row(self.grid.row_nearest(0.0)).to_vec()
    }

    /// Pressure and film along `y = 0` (SI).
    pub fn centreline(&self) -> Centreline {
        let s = &self.prm.scales;
        let xs = self.grid.xs();
        Centreline {
            columns: vec![
                ("x_m".into(), xs.iter().map(|&x| s.x_si(x)).collect()),
                ("pressure_pa".into(), self.row(&self.p).iter().map(|&v| s.p_si(v)).collect()),
                ("film_m".into(), self.row(&self.film).iter().map(|&v| s.h_si(v)).collect()),
                (
                    "pressure_dry_hertz_pa".into(),
                    xs.iter().map(|&x| s.p_si(hertz::pressure(x, 0.0))).collect(),
                ),
            ],
        }
    }

    /// The final fields (SI), and the flux ratio.
    pub fn fields(&self) -> Vec<(String, Array2<f64>)> {
        let s = &self.prm.scales;
        let mut f = vec![
            ("pressure_pa".into(), self.p.mapv(|v| s.p_si(v))),
            ("film_m".into(), self.film.mapv(|v| s.h_si(v))),
        ];
        if self.view.supply.is_some() {
            f.push(("film_content".into(), self.theta.clone()));
        }
        if let Some(t) = &self.transient {
            for (k, (ts, _, p, h)) in t.snapshots.iter().enumerate() {
                let tag = format!("snapshot{k:02}_t{ts:.5}s");
                f.push((format!("{tag}_pressure_pa"), p.mapv(|v| s.p_si(v))));
                f.push((format!("{tag}_film_m"), h.mapv(|v| s.h_si(v))));
            }
        }
        f
    }

    /// Where the gap first fills on the centre line, upstream of the centre [a] (the inlet
    /// meniscus; the domain's inflow edge when full there): mass conserving only.
    pub fn meniscus_a(&self) -> Option<f64> {
        self.view.supply.as_ref()?;
        let g = &self.grid;
        let j = g.row_nearest(0.0);
        let centre = g.col_nearest(0.0);
        let first_full =
            (0..=centre).rev().find(|&i| self.theta[[j, i]] < 1.0).map_or(0, |i| i + 1);
        Some(g.x(first_full))
    }
}
