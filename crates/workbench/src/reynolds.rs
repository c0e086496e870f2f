//! Reynolds-model scenes: the steady EHL solve and what it writes.

pub mod flow;
use crate::drive::{self, Step, Transient};
use crate::error::{Result, Within};
use crate::model::{Centreline, ContactModel, Indicator, Outcome, q};
use crate::plot::{self, MapPanel, Mark, Panel, Series};
use ehl_core::observe::Observables;
use ehl_core::{Dent, Grid, HertzScales, Kinematics, hertz};
use ehl_reynolds::formulas::{hamrock_dowson_central, nvm_central};
use ehl_reynolds::{ReynoldsParams, ReynoldsReport, ReynoldsSolver};
use ehl_scene::{ReynoldsView, Scene, StartState};
use ndarray::{Array2, Zip};
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
    /// the film is still ~3 % short (measured: the sweep's domain check moved `h_c` by +3.0 % at
    /// every speed of `seed-speed`), so `1 + 2 (m* − 1)` (0.5 % short at 1 + 1.8 (m* − 1), 0.2 m/s).
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
    /// film's existence limit stalls and hands over to attempt after attempt (the seed flooded on
    /// 129²: 144 cycles, 3.8 s, four times the 257² answer's own 15 cycles), and an answer that
    /// takes that is no error estimate to wait for.
    /// The grid error law of the central film ([`ehl_reynolds::formulas::GRID_CHANGE_PER_CELL2`]:
    /// the half grid moves it by `K ρ²`), read as the grid convergence index of that change at
    /// order 2, `1.25 K ρ² / 3`. Measured for `ρ` up to 0.25; beyond it (a grid coarser than
    /// the film's existence asks for) it overstates: the steel ball of the README on 129²
    /// (`ρ` = 0.6) reads 65 % where the film is 33 % off.
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
        }
        coarse
    }
}

/// The most cycles a coarser grid of an error estimate is given ([`ContactModel::for_estimate`]):
/// above the flooded solve's 15–17 on any grid where it converges and the fed seed's 9–24.
const ESTIMATE_CYCLES: usize = 25;

/// The central film's change a cycle at which a coarser grid of an error estimate stops: a
/// sixth of the least error an estimate gives a film ([`crate::accuracy::FILM_FLOOR`]). The
/// seed's flooded 129², started from its finer answer, settles within 1e-4 by its sixth cycle
/// and then alternates by 3e-4 a cycle, which the solve's own 1e-4 never accepts.
const ESTIMATE_FILM_TOLERANCE: f64 = 5e-4;

/// The force balance a coarser grid of an error estimate is held to: a load off by 1e-5 moves
/// the film by about 1e-6 (`h ∝ W^-0.07`), far below the least error an estimate gives a film
/// ([`crate::accuracy::FILM_FLOOR`]), where the solve's own 1e-6 took the seed's flooded 129²
/// from its finer answer 25 cycles and more.
const ESTIMATE_LOAD_TOLERANCE: f64 = 1e-5;

/// The Nijenbanning–Venner–Moes central film of the scene's rolling contact in Hertz units
/// [a²/R]; `None` without a lubricant or rolling.
fn nvm_film(scene: &Scene) -> Option<f64> {
    let (Some(l), (c, u_sum)) = (&scene.lubricant, scene.reynolds_conditions()) else {
        return None;
    };
    (u_sum > 0.0).then(|| HertzScales::new(&c).h_dimless(nvm_central(&c, &l.lubricant(), u_sum)))
}

impl Outcome for ReynoldsOutcome {
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
        // the grid does not resolve the thinnest film (2 mm/s, 80 N on 513²: -0.14 nm at the
        // side lobe; +0.50 nm on the 1025² the grid rule asks for).
        // A march whose steps had contact (`reynolds.solver.contact`, on by default) holds a
        // closed film at `H = 0` where the solids touch; the points beside the contact, decided
        // before each sweep, can end a hundredth of the central film below 0 (`stop-compare`,
        // 129²: -0.009 nm beside the closed lobes against 9.65 nm central), the contact edge's
        // discretisation, not a missing contact: below that it counts. Without contact the
        // film closes at rest where the solids would touch (-2.8 nm in `stop-compare`).
        let ob = self.observables();
        let rows = self.transient.as_ref().map(|t| t.rows.as_slice()).unwrap_or_default();
        let at_rest = rows.last().is_some_and(|r| r.speed_m_s == 0.0);
        let touched = rows.iter().any(|r| r.contact_area_m2 > 0.0);
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
        match (settled, negative) {
            (Some(a), Some(b)) => Some(format!("{a}; {b}")),
            (a, b) => a.or(b),
        }
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
        self.film.clone()
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
                "contact_load_share".into(),
                Indicator::new(
                    self.transient.as_ref().map_or(0.0, |t| {
                        t.rows.iter().map(|r| r.contact_load_share).fold(0.0, f64::max)
                    }),
                    "1",
                    "the largest share of the load where the solids touched in a march (0: none; steady solves never touch)",
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
    let v = scene.reynolds_view()?;
    let (spec, lub) = (&v.spec, &v.lubricant);
    let prm =
        ReynoldsParams::from_si(&v.contact, lub, v.sum_velocity_m_s, spec.viscosity, spec.density);
    Ok((prm, ReynoldsSolver::new(scene.grid(), prm, spec.solver)))
}

/// Solves a Reynolds scene: steady, then the march it asks for.
pub fn run_reynolds(scene: &Scene) -> Result<ReynoldsOutcome> {
    run_reynolds_from(scene, None)
}

/// A finer answer over the same domain that a coarser grid's steady solve starts from (an
/// error estimate's coarser grids): its fields taken at every `stride`-th point.
struct FinerStart<'a> {
    answer: &'a ReynoldsOutcome,
    stride: usize,
}

impl<'a> FinerStart<'a> {
    /// The start for `coarse` (the finer answer's scene on fewer points) from `finer`'s answer:
    /// only a steady answer on a grid whose points include the coarse grid's (the same domain,
    /// `n - 1` a multiple).
    fn new(coarse: &Scene, finer: &'a dyn Outcome) -> Option<Self> {
        let answer = finer.inner().unwrap_or(finer).as_any().downcast_ref::<ReynoldsOutcome>()?;
        let (f, c) = (&answer.grid, coarse.grid());
        let stride = (f.nx - 1) / (c.nx - 1).max(1);
        let nested = stride >= 2
            && (c.nx - 1) * stride == f.nx - 1
            && (c.ny - 1) * stride == f.ny - 1
            && (f.x(0) - c.x(0)).abs() < 1e-9
            && (f.y(0) - c.y(0)).abs() < 1e-9;
        let steady = answer.transient.is_none() && coarse.reynolds_view().ok()?.march.is_none();
        (nested && steady).then_some(Self { answer, stride })
    }
}

/// Solves a Reynolds scene, its steady solve started from a finer answer when one is given
/// (else from Hertz, full multigrid).
fn run_reynolds_from(scene: &Scene, finer: Option<&FinerStart>) -> Result<ReynoldsOutcome> {
    let view = scene.reynolds_view()?;
    let (contact, u_sum, lub) = (view.contact, view.sum_velocity_m_s, view.lubricant);
    let grid = scene.grid();
    let t0 = Instant::now();
    let (prm, mut solver) = build_solver(scene)?;
    let run = view.march.as_ref();
    if run.is_some() {
        // A march starts from a steady answer whose coarser grids held the film content: from
        // the first attempt's answer with them moving the menisci (converged to the same
        // tolerances), the first step of `rolling-from-squeezed-compare` stopped unconverged at
        // its 30 cycles (force balance 2.2e-6 against 1e-6); from it after 10 more cycles to a
        // film tolerance of 1e-5, or from the holding answer, every step converges. Still so
        // with the start handing over loosely (`STARVED_FMG_SETTLE`): 30 cycles, 2.16e-6.
        solver.settings.coarse_film_content = false;
    }
    let dents = if run.is_some() { scene.dents()? } else { vec![] };
    // The march starts from the steady solution with the dents at their start.
    if !dents.is_empty() {
        set_dents(&mut solver, &dents, 0.0);
    }
    // The supply: the layer arriving at the inflow boundary (holes there at the start left
    // out of the steady solve: a steady contact has none; they enter as the march carries them).
    if let Some(sup) = &view.supply {
        let h_oil = sup.thickness_m / prm.scales.delta;
        solver.set_supply(Some(&|_| h_oil));
    }
    // A march's motion, on the mean velocity (under pure rolling a dent on the ball moves at
    // it: the reference speed of the solver's scales, `λ̄` and the time unit `a/u_m`); it
    // starts from the steady state at the speed before its motion starts.
    let motion = match run {
        Some(r) => {
            let m = r.kinematics(0.5 * u_sum).within(|| format!("scene `{}`", scene.name))?;
            // A squeezed start rolled at the scene's speed before it stopped; a steady-rolling
            // one rolls at the speed before its motion starts.
            let before = if r.start == Some(StartState::Squeezed) {
                1.0
            } else {
                m.speed_before() / m.reference_speed()
            };
            solver.set_speed(before);
            Some(m)
        }
        None => None,
    };
    if let Some(f) = finer.filter(|_| run.is_none()) {
        // Near its own answer already: cycles from there, no full-multigrid start.
        solver.settings.fmg_cycles = 0;
        let (a, k) = (f.answer, f.stride);
        solver.start_from_answer(
            &|j, i| a.p[[k * j, k * i]],
            &|j, i| a.theta[[k * j, k * i]],
            a.h00,
        );
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
        .within(|| format!("scene `{}`", scene.name))?;
    spin.finish_and_clear();
    let formulas =
        (hamrock_dowson_central(&contact, &lub, 0.5 * u_sum), nvm_central(&contact, &lub, u_sum));
    let transient = match run {
        Some(r) => {
            let motion = motion.expect("built with the run");
            // The march's plan, made before a squeezed start's rest (which may take long), so
            // that a plan the driver refuses is refused at once.
            let plan = march_plan(scene, r, &motion, &prm, &solver.grid())?;
            let rest = (r.start == Some(StartState::Squeezed))
                .then(|| squeeze_start(scene, r, u_sum, &prm, &mut solver, &dents, &view.supply))
                .transpose()?;
            let mut t =
                run_transient(scene, plan, motion, &prm, &mut solver, dents, view.supply.clone())?;
            t.squeezed_rest = rest;
            Some(t)
        }
        None => None,
    };
    let (fp, ff) = (solver.pressure(), solver.film());
    let theta = solver.theta().clone();
    Ok(ReynoldsOutcome {
        scene: scene.clone(),
        view: view.clone(),
        prm,
        grid,
        p: fp.clone(),
        film: ff.clone(),
        theta,
        h00: solver.h00,
        report,
        formulas,
        setup_time_s,
        transient,
    })
}

/// The squeezed start: the steady solve at the scene's speed (the surfaces rolled before they
/// were squeezed; the caller solved it), a sudden stop, and rest under the load until the squeeze
/// is steady by the scene's own rule (its tolerance, its window in time), at most
/// [`SQUEEZE_START_MAX_S`]: the Reynolds film's counterpart of the layer model's steady squeeze.
/// The trapped film drains for as long as one waits (its lobes closed, the centre sealed), so
/// "steady" is the scene's tolerance over its window, not a limit reached.
fn squeeze_start(
    scene: &Scene,
    r: &ehl_scene::RunSpec,
    u_sum: f64,
    prm: &ReynoldsParams,
    solver: &mut ReynoldsSolver,
    dents: &[Dent],
    supply: &Option<ehl_core::Supply>,
) -> Result<SqueezedRest> {
    let rest = ehl_scene::RunSpec {
        start: Some(StartState::SteadyRolling),
        motion: ehl_scene::Motion::Squeeze,
        features: vec![],
        snapshots_s: vec![],
        snapshots_a: vec![],
        stop: ehl_scene::StopSettings {
            until_features_passed: false,
            until_feature_at_a: None,
            max_time_s: Some(SQUEEZE_START_MAX_S),
            ..r.stop
        },
        ..r.clone()
    };
    let mut at_rest = scene.clone();
    at_rest.run = Some(rest.clone());
    let motion = rest.kinematics(0.5 * u_sum).within(|| format!("scene `{}`", scene.name))?;
    let plan = march_plan(&at_rest, &rest, &motion, prm, &solver.grid())?;
    let t = run_transient(&at_rest, plan, motion, prm, solver, dents.to_vec(), supply.clone())
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

/// Puts the dents (depths in m) into the solver's rigid film with their centres moved by
/// `travel` [a] from their start, in units of `a²/R`: the core's dent, the layer model's too.
fn set_dents(solver: &mut ReynoldsSolver, dents: &[Dent], travel: f64) {
    let delta = solver.prm.scales.delta;
    solver.set_extra_gap(move |x: f64, y: f64| {
        dents.iter().map(|d| d.gap(x, y, d.x_start_a + travel, delta)).sum()
    });
}

/// The Reynolds solver as the driver marches it: each step moves the dents by the travel of
/// the surfaces, sets the wedge term's speed, and solves to the scene's tolerances from the
/// last state.
struct ReynoldsMarch<'a> {
    solver: &'a mut ReynoldsSolver,
    dents: Vec<Dent>,
    /// The supply when it has holes: the inflow boundary's layer follows them.
    holes: Option<ehl_core::Supply>,
    /// Time since the motion started [s] and the time unit `a/u_ref` [s].
    t_s: f64,
    time_unit: f64,
    /// How the surfaces move (the dents travel with the ball).
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
    /// step to step, which are no error of the time step. On `stop-compare` (129², lobes closed
    /// from 10 ms after the stop): 240 steps and 13 s (measured), against 543 steps and 35 s
    /// watching the edge (as measured when it was found). (At one step a cell the
    /// restart after a stop moved with this watch's variants, `stop-start-compare`'s dip at
    /// 0.62–0.98 transits: the rolling steps' own error at Courant 1; at two steps a cell and
    /// finer it is 0.96–0.97 whatever the steps at rest, docs/reynolds.md, "Steps at rest".)
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
        if !self.dents.is_empty() {
            set_dents(self.solver, &self.dents, travel);
        }
        if let Some(sup) = &self.holes {
            let (x_in, delta) = (self.solver.grid().x(0), self.solver.prm.scales.delta);
            self.solver.set_inflow(Some(&|y| sup.thickness_at(x_in, y, travel) / delta));
        }
        // The wedge term at the speed of the time solved for (the scales stay at u_ref).
        self.solver.set_speed(self.motion.speed(t_new) / self.motion.reference_speed());
        let where_ = || match self.dents.is_empty() {
            false => format!("dent at x = {:.3} a", self.x0 + travel),
            true => format!("u = {:.4e} m/s", self.motion.speed(t_new)),
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
fn march_plan(
    scene: &Scene,
    run: &ehl_scene::RunSpec,
    motion: &Kinematics,
    prm: &ReynoldsParams,
    g: &Grid,
) -> Result<drive::Plan> {
    let a = prm.scales.a;
    let controlled = Some((g.dx() * a / motion.reference_speed(), 2.0));
    drive::Plan::from_run(run, &scene.passing(), g, a, motion, controlled)
        .within(|| format!("scene `{}`: run", scene.name))
}

/// Marches the scene's run from the steady solution on `plan` ([`march_plan`]: steps per cell,
/// the stop rule, snapshots); a step that does not converge ends the run with its diagnosis,
/// step and time.
fn run_transient(
    scene: &Scene,
    mut plan: drive::Plan,
    motion: Kinematics,
    prm: &ReynoldsParams,
    solver: &mut ReynoldsSolver,
    dents: Vec<Dent>,
    supply: Option<ehl_core::Supply>,
) -> Result<TransientRecord> {
    let s = prm.scales;
    let g = solver.grid();
    // An error estimate below the solve's own algebraic error (the central film settles to
    // `film_tolerance` per cycle) is that error's noise: error control asks no less than ten
    // times it. At the scene's 1e-4 against a film tolerance of 1e-4 the seed's stop on 129²
    // rejected a third of its steps (202 of 621) and never took a step past 0.011 s.
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
    let x0 = scene.passing().first().map_or(0.0, |p| p.x_start_a);
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
        dents,
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
        .within(|| format!("scene `{}`: Reynolds march", scene.name))?;
    spin.finish_and_clear();
    let at = |t: f64| x0 + march.motion.travel(t) / s.a;
    Ok(TransientRecord {
        snapshots: rec.snapshots.into_iter().map(|(t, (p, h))| (t, at(t), p, h)).collect(),
        passing: !scene.passing().is_empty(),
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

impl ReynoldsOutcome {
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
                "lagged_laws": self.report.lagged_laws,
                "first_attempt": self.report.first_attempt,
                "omega_gs": self.report.omega_gs,
                "from_flooded": self.report.from_flooded,
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

    fn note(&self) -> String {
        let (c, u) = self.scene.reynolds_conditions();
        format!(
            "{}: R = {} mm, F = {:.4} N, u1 = {:.4} m/s (M = {:.1}, L = {:.2}), {} viscosity, {} density; grid {}x{}",
            self.scene.name,
            c.ball_radius * 1e3,
            c.load,
            0.5 * u,
            self.prm.moes.m,
            self.prm.moes.l,
            crate::model::word(&self.view.spec.viscosity),
            crate::model::word(&self.view.spec.density),
            self.grid.nx,
            self.grid.ny
        )
    }

    /// The maps, the centreline and, for a march, the history and snapshots as PNG.
    pub fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
        let note = self.note() + footnote;
        let note = note.as_str();
        let g = &self.grid;
        let nm = self.prm.scales.delta * 1e9;
        let mut out = vec![];
        // Seed Fig. 4 analogue: pressure and film maps.
        let f = dir.join(format!("{prefix}maps.png"));
        // The colour scale stops at 3 h_c: the open gap outside the contact is two orders
        // thicker and would hide the horseshoe.
        let cap = 3.0 * self.films().0 * nm;
        let film_nm = self.film.mapv(|v| (v * nm).min(cap));
        plot::heat_maps(
            &f,
            &[
                MapPanel {
                    field: &self.p,
                    title: "Pressure p / p_h".into(),
                    bar_label: "p / p_h".into(),
                    diverging: false,
                },
                MapPanel {
                    field: &film_nm,
                    title: "Film h [nm] (scale capped at 3 h_c)".into(),
                    bar_label: "h [nm]".into(),
                    diverging: false,
                },
            ],
            g,
            note,
        )?;
        out.push(f);
        if let Some(xm) = self.meniscus_a() {
            // The oil where the gap is not full: the film content, and the oil layer it holds
            // (θ h), with the inlet meniscus on the centre line in the title.
            let f = dir.join(format!("{prefix}film_content.png"));
            let oil_nm = Zip::from(&self.theta).and(&self.film).map_collect(|&t, &h| t * h * nm);
            let cap = 3.0 * self.films().0 * nm;
            let oil_nm = oil_nm.mapv(|v| v.min(cap));
            plot::heat_maps(
                &f,
                &[
                    MapPanel {
                        field: &self.theta,
                        title: format!("Film content θ (1: full; inlet meniscus at x = {xm:.3} a)"),
                        bar_label: "θ".into(),
                        diverging: false,
                    },
                    MapPanel {
                        field: &oil_nm,
                        title: "Oil θ h [nm] (scale capped at 3 h_c)".into(),
                        bar_label: "θ h [nm]".into(),
                        diverging: false,
                    },
                ],
                g,
                note,
            )?;
            out.push(f);
        }
        let x = g.xs();
        let line = |v: Vec<f64>, k: f64| -> Vec<(f64, f64)> {
            x.iter().cloned().zip(v.into_iter().map(|y| y * k)).collect()
        };
        let f = dir.join(format!("{prefix}centreline.png"));
        plot::charts(
            &f,
            &[
                Panel::new(
                    "Pressure along y = 0",
                    "x / a",
                    "p / p_h",
                    vec![
                        Series::new("Reynolds", line(self.row(&self.p), 1.0), Mark::Line),
                        Series::new(
                            "dry contact (Hertz)",
                            x.iter().map(|&xx| (xx, hertz::pressure(xx, 0.0))).collect(),
                            Mark::Line,
                        ),
                    ],
                ),
                Panel::new(
                    "Film along y = 0",
                    "x / a",
                    "h [nm]",
                    vec![Series::new("Reynolds", line(self.row(&self.film), nm), Mark::Line)],
                ),
            ],
            note,
        )?;
        out.push(f);
        let f = dir.join(format!("{prefix}convergence.png"));
        let hist = &self.report.history;
        plot::charts(
            &f,
            &[Panel::new(
                "Cycle history",
                "W-cycle",
                "value",
                vec![
                    Series::new(
                        "RMS residual",
                        hist.iter().map(|c| (c.cycle as f64, c.residual)).collect(),
                        Mark::LinePoints,
                    ),
                    Series::new(
                        "|load error|",
                        hist.iter().map(|c| (c.cycle as f64, c.load_error.abs())).collect(),
                        Mark::LinePoints,
                    ),
                ],
            )
            .log_log()],
            note,
        )?;
        out.push(f);
        if let Some(t) = &self.transient {
            out.extend(self.transient_figures(t, dir, prefix, note)?);
        } else {
            // The seed's Fig. 1: the flow in the film (steady solutions only).
            out.extend(self.flow_figures(dir, prefix)?);
        }
        Ok(out)
    }

    fn transient_figures(
        &self,
        t: &TransientRecord,
        dir: &Path,
        prefix: &str,
        note: &str,
    ) -> Result<Vec<PathBuf>> {
        let s = &self.prm.scales;
        // Told by the first feature's position while features pass, else by time.
        let (axis, what) = if t.passing {
            ("dent centre x / a", "while the dent passes")
        } else {
            ("t [s]", "against time")
        };
        let abscissa =
            |r: &TransientRow| if t.passing { r.dent_x_m / self.prm.scales.a } else { r.t_s };
        let xs = |f: fn(&TransientRow) -> f64, k: f64| -> Vec<(f64, f64)> {
            t.rows.iter().map(|r| (abscissa(r), f(r) * k)).collect()
        };
        let f_hist = dir.join(format!("{prefix}history.png"));
        plot::history_chart(
            &f_hist,
            axis,
            &format!("Film {what}"),
            [
                ("central film", xs(|r| r.central_film_m, 1e9)),
                ("minimum film", xs(|r| r.minimum_film_m, 1e9)),
            ],
            &format!("Pressure {what}"),
            [
                ("maximum", xs(|r| r.max_pressure_pa, 1.0 / s.p_h)),
                ("central", xs(|r| r.central_pressure_pa, 1.0 / s.p_h)),
            ],
            note,
        )?;
        let label = |ts: f64, xd: f64| {
            if t.passing { format!("dent at {xd:.3} a") } else { format!("t = {ts:.4} s") }
        };
        let nm = s.delta * 1e9;
        let x = self.grid.xs();
        let j = self.grid.row_nearest(0.0);
        let line = |a: &Array2<f64>, k: f64| -> Vec<(f64, f64)> {
            x.iter().zip(a.row(j).iter()).map(|(&x, &v)| (x, v * k)).collect()
        };
        // Films above 3 central films of the steady start are the open gap: left off.
        let cap = 3.0 * self.report.history.last().map_or(f64::MAX, |c| c.central_film) * nm;
        let f_snap = dir.join(format!("{prefix}snapshots_centreline.png"));
        plot::charts(
            &f_snap,
            &[
                Panel::new(
                    "Pressure along y = 0",
                    "x / a",
                    "p / p_h",
                    t.snapshots
                        .iter()
                        .map(|(ts, xd, p, _)| {
                            Series::new(label(*ts, *xd), line(p, 1.0), Mark::Line)
                        })
                        .collect(),
                ),
                Panel::new(
                    "Film along y = 0",
                    "x / a",
                    "h [nm]",
                    t.snapshots
                        .iter()
                        .map(|(ts, xd, _, h)| {
                            let pts = line(h, nm).into_iter().filter(|v| v.1 <= cap).collect();
                            Series::new(label(*ts, *xd), pts, Mark::Line)
                        })
                        .collect(),
                ),
            ],
            note,
        )?;
        Ok(vec![f_hist, f_snap])
    }
}

/// The terminal report.
fn reynolds_report(o: &ReynoldsOutcome) -> String {
    use std::fmt::Write;
    let mut out = String::new();

    let (hc, hmin, pmax) = o.films();
    let s = &o.prm.scales;
    let _ = writeln!(
        out,
        "scene {} ({}x{}): {} in {} cycles, {:.2} s (setup {:.2} s); M = {:.2}, L = {:.3}",
        o.scene.name,
        o.grid.nx,
        o.grid.ny,
        if o.report.converged { "converged" } else { "settled" },
        o.report.cycles,
        o.report.wall_time_s,
        o.setup_time_s,
        o.prm.moes.m,
        o.prm.moes.l
    );
    if let Some(c) = Outcome::caveat(o) {
        let _ = writeln!(out, "  caveat: {c}");
    }
    if o.scene.reynolds.as_ref().is_some_and(|r| r.moes.is_some()) {
        let (c, u_sum) = o.scene.reynolds_conditions();
        let _ = writeln!(
            out,
            "  load and velocity from Moes M, L: F = {:.4} N, u1 = u2 = {:.4e} m/s (conditions.load_n = {} N not used)",
            c.load,
            0.5 * u_sum,
            o.scene.conditions.load_n
        );
    }
    let _ = writeln!(
        out,
        "  central film {:.4e} m (H = {:.5}), minimum film {:.4e} m (H = {:.5}), max pressure {:.4e} Pa ({:.4} p_h)",
        s.h_si(hc),
        hc,
        s.h_si(hmin),
        hmin,
        s.p_si(pmax),
        pmax
    );
    let _ = writeln!(
        out,
        "  formulas: Hamrock-Dowson {:.4e} m, Nijenbanning-Venner-Moes {:.4e} m",
        o.formulas.0, o.formulas.1
    );
    // Where the solids touched during a march: the most of the load the contact carried.
    if let Some(t) = &o.transient
        && let Some(r) =
            t.rows.iter().max_by(|a, b| a.contact_load_share.total_cmp(&b.contact_load_share))
        && r.contact_area_m2 > 0.0
    {
        let last = t.rows.last().expect("a march has its start row");
        let _ = writeln!(
            out,
            "  contact (the film closed, the solids touching): at most {:.2e} of the load on {:.3e} m² at t = {:.4} s; at the end {:.2e} on {:.3e} m²",
            r.contact_load_share,
            r.contact_area_m2,
            r.t_s,
            last.contact_load_share,
            last.contact_area_m2
        );
    }

    out
}
