//! FAS multigrid for the Reynolds problem: W-cycles (or V) over the grid hierarchy, line
//! relaxation on every level, the elastic film through each level's own FFT deformation
//! operator, and the force balance driving `H00` between cycles.

use crate::extrapolate::ModeExtrapolation;
use crate::formulas::{self, moes_to_hertz_film, nvm_central_moes};
use crate::level::{Level, RelaxSettings};
use crate::params::ReynoldsParams;
use ehl_core::FieldError;
use ehl_core::grid::{inject, prolong};
use ehl_core::{Grid, hertz};
use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::time::Instant;

mod attempts;
mod fas;
mod report;
mod settings;
mod steady;
mod transient;
mod watch;
pub use report::{
    CycleLog, Diagnosis, Divergence, FailureKind, ReynoldsError, ReynoldsReport, SETTLED_BOUND,
    Settled,
};
use report::{converged, cycle_work, settled};
pub use settings::{ReynoldsSettings, StopRule, TimeScheme};
use watch::{CONTINUE_WITHIN, stalled_early, stalled_far, stalled_open, stalled_over, swung_away};

/// The Reynolds EHL solver: FAS multigrid over a hierarchy of levels, steady solves and time steps.
///
/// ```
/// use ehl_reynolds::{DensityLaw, ReynoldsParams, ReynoldsSettings, ReynoldsSolver, ViscosityLaw};
/// let prm = ReynoldsParams::from_si(
///     &ehl_core::SEED_CONTACT,
///     &ehl_core::SEED_LUBRICANT,
///     0.2, // sum velocity [m/s]
///     ViscosityLaw::Roelands,
///     DensityLaw::DowsonHigginson,
/// );
/// let grid = ehl_core::Grid::new(65, 65, (-2.5, 1.5), (-2.0, 2.0));
/// let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
/// let report = s.solve(&mut |_| {}).unwrap();
/// let (hc, hmin) = s.films(); // central and minimum film [a²/R]
/// assert!(report.converged && hc > hmin && hmin > 0.0);
/// ```
pub struct ReynoldsSolver {
    /// Finest first. Callers read the answer through [`ReynoldsSolver::pressure`],
    /// [`ReynoldsSolver::film`] and [`ReynoldsSolver::grid`].
    pub(crate) levels: Vec<Level>,
    /// The dimensionless parameters.
    pub prm: ReynoldsParams,
    /// The film constant `H00` [a²/R] the force balance sets.
    pub h00: f64,
    /// The settings as given: each solve starts from them.
    pub settings: ReynoldsSettings,
    /// The settings in force for the solve or step under way: `settings`, with the laws lagged
    /// after a failed first attempt, or the time step's cycle and gain. Never written back.
    active: ReynoldsSettings,
    /// `ρ̄H` of the last two time levels, newest first (transient runs) …
    rho_h: Vec<Array2<f64>>,
    /// … and the step that led to the newest [a/u_ref] (the backward differences of unequal
    /// steps need the step before) …
    last_dt: f64,
    /// … and the pressure and `H00` before the newest step: a step starts from the last state
    /// plus the last step's change, the pressure's carried with the surfaces
    /// ([`ReynoldsSettings::extrapolated_start`]).
    before: Option<(Array2<f64>, f64)>,
    /// The coarsest level the cycles descend to: the last, but in the mass-conserving cycles
    /// of [`ReynoldsSolver::attempt_from_flooded`] the coarsest whose cells hold the film.
    coarsest: usize,
    /// Whether the coarser grids of a cycle solve for the film content too
    /// ([`ReynoldsSettings::coarse_film_content`]; only in a steady solve's first attempt).
    coarse_theta: bool,
    /// Attempts the steady solve under way has run ([`ReynoldsReport::attempts`]).
    attempts: usize,
    /// The cycle (1: V, 2: W) that answered a time step after the other failed it: the steps
    /// after it start with it ([`ReynoldsSolver::step`]); `None`, `step_gamma`'s.
    step_gamma: Option<usize>,
}

/// What a time step changes, kept to return to when an error-controlled step is rejected
/// ([`ReynoldsSolver::save`], [`ReynoldsSolver::restore`]).
#[derive(Clone, Debug)]
pub struct SolverState {
    p: Array2<f64>,
    film: Array2<f64>,
    theta: Array2<f64>,
    contact: Array2<bool>,
    coefficient_pressures: Option<Array2<f64>>,
    h00: f64,
    rho_h: Vec<Array2<f64>>,
    last_dt: f64,
    before: Option<(Array2<f64>, f64)>,
}

/// The coarsest grid of a steady mass-conserving solve's first attempt, in cells of the grid
/// rule ([`ReynoldsSettings::coarse_film_content`]).
pub const COARSE_FILM_CELLS: f64 = 8.0;

/// The under-relaxation of the gap's changes where the solids touch in the start from the dry
/// contact, at most ([`ReynoldsSolver::attempt_from_dry`]; the lubricated solve's is
/// [`RelaxSettings::omega_contact`]).
const DRY_START_OMEGA_CONTACT: f64 = 0.4;

/// Mass conserving, the full-multigrid start begins on the coarsest grid with at least this
/// many points per side ([`ReynoldsSolver::fmg_top`]) …
const STARVED_FMG_POINTS: usize = 129;
/// … whose cells are at most this many times the grid rule's ([`formulas::cell_needed`]): the
/// film's existence was measured to end at twice the rule's cell ([`formulas::CELLS_PER_FILM`]).
/// A start on a grid that closes the film hands the next grid a meniscus far from its own and a
/// third of the supply unaccounted for, drained about a cell a cycle (5 mm/s, 40 N fed 10 nm:
/// 43 cycles on 513² from 129², 17 from 257²; docs/decisions.md, "The full-multigrid start on
/// a grid that holds the film") …
const STARVED_FMG_CELLS: f64 = 2.0;
/// … and gives each grid of the start at most this many cycles to settle.
const STARVED_FMG_MAX_CYCLES: usize = 40;

/// How far each grid of a mass-conserving full-multigrid start settles before the next finer
/// grid takes over: the central film's change a cycle (relative) and the oil the equations
/// leave unaccounted for, in units of [`ReynoldsSettings::mass_tolerance`] (the load to 1e-4
/// either way). Loosely: the finer grid's cycles move the menisci as well as the coarser grid's
/// do, and a tight settle spent its cycles on a meniscus the finer grid then moved anyway (the
/// measurements: `docs/decisions.md`, "A tight settle of the fed full-multigrid start").
const STARVED_FMG_SETTLE: (f64, f64) = (1e-2, 30.0);

impl ReynoldsSolver {
    /// Builds the hierarchy and starts from the Hertz pressure with `H00` from the
    /// Nijenbanning–Venner–Moes central film (on the coarsest grid when the start is full
    /// multigrid).
    pub fn new(grid: Grid, prm: ReynoldsParams, mut settings: ReynoldsSettings) -> Self {
        // The time term's threshold is the finest grid's on every grid of the hierarchy.
        let relax = &mut settings.relax;
        relax.transient_threshold = Some(relax.transient_threshold_for(grid.nx.max(grid.ny)));
        let mut grids = vec![grid];
        while let Some(c) = grids.last().unwrap().coarser(settings.coarsest_points) {
            grids.push(c);
        }
        let levels: Vec<Level> = grids.into_iter().map(Level::new).collect();
        let mut s = Self {
            levels,
            prm,
            h00: 0.0,
            settings,
            active: settings,
            rho_h: vec![],
            last_dt: 0.0,
            before: None,
            coarsest: usize::MAX,
            coarse_theta: false,
            attempts: 0,
            step_gamma: None,
        };
        s.start();
        s
    }

    /// The start: the Hertz pressure (on the coarsest grid for a full-multigrid start, else on
    /// the finest), `H00` from the NVM central film, every other field empty. The rigid films
    /// (any extra gap) are kept.
    fn start(&mut self) {
        for l in &mut self.levels {
            l.reset();
            l.touch = false;
        }
        self.h00 = self.starved_film_estimate(self.nvm_film()) - 1.0;
        let top = self.fmg_top();
        let g = self.levels[top].grid;
        self.levels[top].p = g.field(hertz::pressure);
        let h00 = self.h00;
        self.levels[top].update_film(h00);
        self.levels[top].start_theta();
        self.rho_h.clear();
        self.before = None;
    }

    /// The grid a solve starts on: the coarsest for a full-multigrid start, the finest without.
    /// Mass conserving, the coarsest with at least [`STARVED_FMG_POINTS`] per side and, where
    /// the finest grid holds the film, whose cells hold it too ([`STARVED_FMG_CELLS`]): coarser
    /// grids do not resolve a starved film, and the meniscus they give leads the finer grids
    /// into a flooded-like state the supply cannot sustain, drained one sweep at a time.
    fn fmg_top(&self) -> usize {
        if self.active.fmg_cycles == 0 {
            return 0;
        }
        if !self.levels[0].mass_conserving() {
            return self.levels.len() - 1;
        }
        let by_points = (0..self.levels.len())
            .rev()
            .find(|&l| self.levels[l].grid.nx >= STARVED_FMG_POINTS)
            .unwrap_or(0);
        // On a grid too coarse for the film itself (the solids may touch) the start keeps the
        // coarser grids: the finest alone, from the Hertz pressure, diverged there.
        if self.finest_holds_film() {
            by_points.min(self.film_holding_depth(STARVED_FMG_CELLS))
        } else {
            by_points
        }
    }

    /// Whether the finest grid's cells hold the contact's film: at most [`STARVED_FMG_CELLS`]
    /// times the grid rule's, the cell at which the film's existence was measured to end.
    pub(super) fn finest_holds_film(&self) -> bool {
        self.levels[0].grid.dx() <= STARVED_FMG_CELLS * formulas::cell_needed(self.nvm_film())
    }

    /// Whether the coarser grids of the cycles solve for the film content, and with it whether
    /// their Couette faces are first order where the gap is partly filled
    /// ([`Level::first_order_partial`]; the finest grid's equations, the answer's, never are).
    /// Without, the coarser grids hold the film content with second-order faces: a time step's
    /// cycles with the first-order faces on its coarser grids failed to converge in a squeezed
    /// restart's first step (docs/decisions.md, "The start of a march").
    fn set_coarse_theta(&mut self, on: bool) {
        self.coarse_theta = on;
        for l in self.levels.iter_mut().skip(1) {
            l.first_order_partial = on;
        }
    }

    /// The contact's flooded central film after Nijenbanning–Venner–Moes [a²/R].
    fn nvm_film(&self) -> f64 {
        moes_to_hertz_film(nvm_central_moes(&self.prm.moes), &self.prm.moes)
    }

    /// The coarsest level whose cells are at most `cells` times the grid rule's for the
    /// contact's flooded film ([`formulas::cell_needed`]); the finest when none is.
    fn film_holding_depth(&self, cells: f64) -> usize {
        let cell = formulas::cell_needed(self.nvm_film());
        (0..self.levels.len())
            .take_while(|&l| self.levels[l].grid.dx() <= cells * cell)
            .last()
            .unwrap_or(0)
    }

    /// The central film to start from [a²/R]: the flooded estimate `hc` without a supply; with
    /// one, `hc · R(r)` by the starvation curve's form (Chevalier et al. 1998) with `γ = 2`,
    /// `r = H_oil / (ρ̄(p_h) hc)` (the thinnest row's supply): a start that holds about the oil
    /// supplied. From the flooded film instead, the relaxation drains the excess oil as slowly
    /// as time would (hundreds of cycles on the seed's contact fed 5 nm).
    fn starved_film_estimate(&self, hc: f64) -> f64 {
        let Some(s) = self.levels[0].supply() else { return hc };
        let h_oil = s.iter().cloned().fold(f64::INFINITY, f64::min);
        let r = h_oil / (self.prm.density.rho(1.0) * hc);
        hc * r / (1.0 + r * r).sqrt()
    }

    /// Whether this grid can tell the contact's film from a closed gap: the film (the flooded
    /// estimate, or fed the film the supply makes) at least the discrete dry gap's error at the
    /// contact's edge ([`formulas::dry_gap_error`]). Thinner, a film
    /// that closes is the answer, not a failure of the cycles.
    fn film_held(&self) -> bool {
        let film = self.starved_film_estimate(self.nvm_film());
        film >= formulas::dry_gap_error(self.levels[0].grid.dx())
    }

    /// Whether this grid's cells are at most the grid rule's for the contact's flooded film
    /// ([`formulas::cell_needed`]): coarser, its film may close where the contact's does not.
    fn film_resolved(&self) -> bool {
        self.levels[0].grid.dx() <= formulas::cell_needed(self.nvm_film())
    }

    /// Adds `extra(X, Y)` [a²/R] to the rigid film on every level (a dent where positive).
    pub fn set_extra_gap(&mut self, extra: impl Fn(f64, f64) -> f64) {
        self.set_extra_gap_on(|g| g.field(&extra));
    }

    /// Adds the field `extra(grid)` [a²/R] to the rigid film on every level, each level's
    /// given on its own grid: for a relief summed over a whole grid at once
    /// ([`ehl_core::Relief::gap_on`]).
    pub fn set_extra_gap_on(&mut self, extra: impl Fn(&Grid) -> Array2<f64>) {
        for l in &mut self.levels {
            l.set_extra_gap_field(&extra(&l.grid));
        }
        let h00 = self.h00;
        self.levels[0].update_film(h00);
    }

    /// The oil supplied at the inflow boundary `X = x_min`, per `Y` [a²/R] (the layer `h_oil`
    /// at ambient density; 0 in a hole crossing the boundary): the solver becomes mass
    /// conserving (film content `θ`, [`Level`]). `None`: fully flooded, the clamp. Called again
    /// before a solve: the solver starts again ([`Self::set_inflow`] between time steps).
    pub fn set_supply(&mut self, h_oil: Option<&dyn Fn(f64) -> f64>) {
        self.set_inflow(h_oil);
        self.start();
    }

    /// The supply at the inflow boundary changed (a hole crossing it) [a²/R]: the state is
    /// kept, only the boundary's film content follows.
    pub fn set_inflow(&mut self, h_oil: Option<&dyn Fn(f64) -> f64>) {
        for l in &mut self.levels {
            let g = l.grid;
            l.set_supply(h_oil.map(|f| (0..g.ny).map(|j| f(g.y(j))).collect()));
        }
    }

    /// Makes the solids rigid on every level (no elastic deformation): not a model of a real
    /// contact, but the rigid isoviscous squeeze has an analytic answer to check against.
    /// Call before solving.
    pub fn set_rigid(&mut self) {
        for l in &mut self.levels {
            l.set_rigid();
        }
        let h00 = self.h00;
        self.levels[0].update_film(h00);
    }

    /// A start at rest: the surfaces at `H00 = h00` [a²/R] with no pressure yet (a ball put down
    /// on an oil film), the time history from that gap. Time steps follow, the load applied
    /// from the first: the rigid squeeze's start, or a drop.
    pub fn start_from_gap(&mut self, h00: f64) {
        for l in &mut self.levels {
            l.reset();
        }
        self.h00 = h00;
        self.levels[0].update_film(h00);
        self.levels[0].start_theta();
        self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
        self.last_dt = 0.0;
        self.before = None;
    }

    /// A start from an answer known at this grid's points (another grid's answer carried over:
    /// an error estimate's coarser grids start from the finer answer, which differs from their
    /// own by the discretisation error only): `P` [p_h] and `θ` at each point `(j, i)` of the
    /// finest grid where the answer has one, `H00` [a²/R]. Where it has none (a domain grown
    /// beyond the answer's), `P = 0` and `θ` as a fresh start has it ([`Level::start_theta`]).
    /// Solve with `fmg_cycles` 0: a full-multigrid start would begin again from Hertz.
    pub fn start_from_answer(&mut self, at: &dyn Fn(usize, usize) -> Option<(f64, f64)>, h00: f64) {
        let f = &mut self.levels[0];
        let known = Array2::from_shape_fn(f.p.dim(), |(j, i)| at(j, i));
        f.p = known.map(|k| k.map_or(0.0, |(p, _)| p));
        // Where the answer has no point, `θ` needs the film, which needs the pressure first.
        f.theta = known.map(|k| k.map_or(1.0, |(_, t)| t));
        self.h00 = h00;
        f.update_film(h00);
        f.start_theta_where(&|ji| known[ji].is_none());
    }

    /// The state a time step changes (finest grid, `H00`, the time history).
    pub fn save(&self) -> SolverState {
        let f = &self.levels[0];
        SolverState {
            p: f.p.clone(),
            film: f.film.clone(),
            theta: f.theta.clone(),
            contact: f.contact.clone(),
            coefficient_pressures: f.lagged().then(|| f.coefficient_pressures()),
            h00: self.h00,
            rho_h: self.rho_h.clone(),
            last_dt: self.last_dt,
            before: self.before.clone(),
        }
    }

    /// Back to a state [`Self::save`] took.
    pub fn restore(&mut self, s: SolverState) {
        let prm = self.prm;
        let f = &mut self.levels[0];
        f.p = s.p;
        f.film = s.film;
        f.theta = s.theta;
        f.contact = s.contact;
        if let Some(pc) = &s.coefficient_pressures {
            f.set_coefficient_pressures(&prm, pc);
        }
        self.h00 = s.h00;
        self.rho_h = s.rho_h;
        self.last_dt = s.last_dt;
        self.before = s.before;
    }

    /// Where the solids touch on the finest grid: the share of the load the contact carries
    /// and the area it covers [a²] (0 and 0 where the film is open everywhere).
    pub fn contact(&self) -> (f64, f64) {
        let f = &self.levels[0];
        let (load, area) = f.contact_load_and_area();
        (load / f.load().max(f64::MIN_POSITIVE), area)
    }

    /// Where the finest grid's oil goes ([`Level::oil_balance`]); `None` fully flooded.
    pub fn oil_balance(&self) -> Option<crate::OilBalance> {
        self.levels[0].oil_balance(&self.prm)
    }

    /// The points of the finest grid where the solids touch.
    pub fn contact_points(&self) -> &Array2<bool> {
        &self.levels[0].contact
    }

    /// Whether the solver conserves mass (has a supply).
    pub fn mass_conserving(&self) -> bool {
        self.levels[0].mass_conserving()
    }

    /// Film content `θ` on the finest grid (1 where the gap is full).
    pub fn theta(&self) -> &Array2<f64> {
        &self.levels[0].theta
    }

    /// Sets the finest grid's film content where `P = 0` (the oil present where the gap is not
    /// full: a hole cut into the inlet layer at the start of a march), `ρ̄θH` kept by the time
    /// history that follows.
    pub fn set_theta(&mut self, theta: impl Fn(f64, f64, f64) -> f64) {
        let f = &mut self.levels[0];
        let g = f.grid;
        for ((j, i), t) in f.theta.indexed_iter_mut() {
            if f.p[[j, i]] <= 0.0 {
                *t = theta(g.x(i), g.y(j), *t);
            }
        }
        if !self.rho_h.is_empty() {
            self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
        }
    }

    /// The finest grid.
    pub fn grid(&self) -> Grid {
        self.levels[0].grid
    }

    /// Pressure `P` [p_h] on the finest grid.
    pub fn pressure(&self) -> &Array2<f64> {
        &self.levels[0].p
    }

    /// Film `H` [a²/R] on the finest grid.
    pub fn film(&self) -> &Array2<f64> {
        &self.levels[0].film
    }

    /// How many grids the hierarchy has.
    pub fn depth(&self) -> usize {
        self.levels.len()
    }

    /// The finest level itself, for probes that inspect it sweep by sweep (`examples/m20.rs`);
    /// a solve needs none of this.
    pub fn finest(&self) -> &Level {
        &self.levels[0]
    }

    /// The finest level to relax by hand, for the same probes.
    pub fn finest_mut(&mut self) -> &mut Level {
        &mut self.levels[0]
    }

    /// Sets the surfaces' speed as a factor of the reference speed the scales are built on
    /// (`u(t)/u_ref`; 1 at the reference, 0 at rest) on every level: the wedge term's weight.
    /// Dimensionless time stays in units of `a/u_ref`, so a speed that falls to 0 leaves the
    /// time step finite.
    pub fn set_speed(&mut self, factor: f64) {
        for l in &mut self.levels {
            l.speed = factor;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{DensityLaw, ViscosityLaw};
    use ehl_core::{Grid, Moes, SEED_CONTACT};

    fn history(load_errors: &[f64]) -> Vec<CycleLog> {
        let rec = |k: usize, e: f64| CycleLog {
            cycle: k + 1,
            points: 33,
            residual: 1e-3,
            load_error: e,
            h00: -0.5,
            central_film: 0.4,
            minimum_film: 0.3,
            wall_s: 0.0,
            mass_defect: 0.0,
        };
        load_errors.iter().enumerate().map(|(k, &e)| rec(k, e)).collect()
    }

    #[test]
    fn diagnosis_tells_a_limit_cycle_from_a_stall_and_the_cycle_limit() {
        let prm = ReynoldsParams::from_moes(
            &Moes { m: 20.0, l: 10.0 },
            &SEED_CONTACT,
            40e-3,
            1.96e8,
            ViscosityLaw::Roelands,
            DensityLaw::DowsonHigginson,
        );
        let mut s = ReynoldsSolver::new(
            Grid::new(33, 33, (-4.5, 1.5), (-3.0, 3.0)),
            prm,
            ReynoldsSettings::default(),
        );
        s.levels[0].film.fill(0.4); // an open film: the history decides
        let flipping = history(&[1e-4, -1e-4, 1e-4, -1e-4, 1e-4, -1e-4, 1e-4, -1e-4]);
        let d = s.diagnose(&flipping, true);
        assert_eq!((d.kind, d.cycle), (FailureKind::LimitCycle, 8), "{d}");
        // One sign change short of every cycle is no limit cycle.
        let mostly = history(&[1e-4, -1e-4, 1e-4, -1e-4, -1e-4, 1e-4, -1e-4, 1e-4]);
        assert_eq!(s.diagnose(&mostly, true).kind, FailureKind::Stalled);
        let falling = history(&[1e-2, 5e-3, 2e-3, 1e-3]);
        assert_eq!(s.diagnose(&falling, false).kind, FailureKind::CycleLimit);
        s.levels[0].film[[5, 7]] = -1e-3;
        let d = s.diagnose(&falling, false);
        let g = s.levels[0].grid;
        assert_eq!((d.kind, d.at), (FailureKind::FilmClosed, Some((g.x(7), g.y(5)))), "{d}");
    }

    /// The seed's contact at `u1` [m/s] under `load` [N] on `n`² over its ±1.25 a, fed 10 nm.
    fn fed_seed(u1: f64, load: f64, n: usize) -> ReynoldsSolver {
        let contact = ehl_core::Contact { load, ..SEED_CONTACT };
        let lub = &ehl_core::SEED_LUBRICANT;
        let (visc, dens) = (ViscosityLaw::Roelands, DensityLaw::DowsonHigginson);
        let prm = ReynoldsParams::from_si(&contact, lub, 2.0 * u1, visc, dens);
        let grid = Grid::new(n, n, (-1.25, 1.25), (-1.25, 1.25));
        let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
        let hd = 10e-9 / prm.scales.delta;
        s.set_supply(Some(&move |_y| hd));
        s
    }

    #[test]
    fn a_fed_steady_solve_makes_smaller_changes_on_its_finest_grid_and_in_a_start_that_closes() {
        let mut s = fed_seed(0.01, 20.0, 65);
        let (flooded, fed) = (s.settings.relax.omega_gs, s.settings.fed_omega_gs);
        assert!(fed < flooded, "{fed} against {flooded}");
        // The finest grid's cycles at the fed changes; the start's coarser grids at the flooded
        // (with 0.25 there too, 5 mm/s, 80 N on 1793² stalled: docs/decisions.md).
        assert_eq!((s.cycle_omega_gs(0), s.cycle_omega_gs(1)), (fed, flooded));
        // A flooded solve, and a time step's cycles, keep the flooded changes on every grid.
        let mut flooding = fed_seed(0.01, 20.0, 65);
        flooding.set_supply(None);
        assert_eq!(flooding.cycle_omega_gs(0), flooded);
        let mut step = fed_seed(0.01, 20.0, 65);
        step.levels[0].time_a0 = 1.0;
        assert_eq!(step.cycle_omega_gs(0), flooded);
        // A start whose film stays open keeps its changes; one whose film closes takes the fed
        // ones on its coarser grids too, for the rest of the solve.
        let mut rec = super::watch::tests::history(1, |_| 0.0)[0];
        s.watch_fed_start(&rec);
        assert_eq!(s.cycle_omega_gs(1), flooded);
        rec.minimum_film = -1e-4;
        s.watch_fed_start(&rec);
        assert_eq!(s.cycle_omega_gs(1), fed);
        step.watch_fed_start(&rec);
        assert_eq!(step.cycle_omega_gs(1), flooded, "a time step's cycles are not the start's");
    }

    #[test]
    fn a_fed_start_begins_on_the_coarsest_grid_that_holds_the_film() {
        let top = |s: &ReynoldsSolver| s.levels[s.fmg_top()].grid.nx;
        // 5 mm/s, 40 N: 129² closes the film (cells 3.8× the grid rule's), 257² holds it (1.9×).
        assert_eq!(top(&fed_seed(0.005, 40.0, 513)), 257);
        assert_eq!(top(&fed_seed(0.005, 40.0, 257)), 257);
        // The seed's 10 mm/s, 20 N: 129² holds it (2.0×).
        assert_eq!(top(&fed_seed(0.01, 20.0, 513)), 129);
        // 2 mm/s, 80 N on 257² (the rule asks for 1153²): the finest does not hold the film, and
        // the start keeps the coarser grids, down to 129 points.
        assert_eq!(top(&fed_seed(0.002, 80.0, 257)), 129);
    }

    #[test]
    fn a_first_attempt_on_a_grid_that_holds_the_film_is_judged_over_a_quarter_of_its_window() {
        let mut s = fed_seed(0.005, 40.0, 257);
        let (full, half) = (s.stall_window(), s.active.stall_cycles / 2);
        assert!(half > 0 && half < full);
        s.set_coarse_theta(true);
        assert_eq!(s.judged_stall_window(false, false), half);
        // Touching, or closed, the whole window, as in every later attempt.
        assert_eq!(s.judged_stall_window(true, false), full);
        assert_eq!(s.judged_stall_window(false, true), full);
        s.set_coarse_theta(false);
        assert_eq!(s.judged_stall_window(false, false), full);
        // On a grid too coarse for the film the first attempt's film closes late: whole window.
        let mut coarse = fed_seed(0.002, 80.0, 257);
        coarse.set_coarse_theta(true);
        assert_eq!(coarse.judged_stall_window(false, false), full);
    }
}
