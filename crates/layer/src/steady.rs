//! Steady rolling solved directly, without marching in time.
//!
//! At steady state `∂ε/∂t = 0` and the strain law is a transport equation along `x` for a given
//! pressure: `(u1/a) ∂ε/∂X = (p − E(p_c, ε) ε) / η(p_c)`, `ε = 0` upstream of the inlet,
//! `0 ≤ ε ≤ 1` (`p_c` is the coefficient pressure: `p`, or its smoothing when regularised).
//! It is discretised by BDF2 along `x` in `m` sub-steps a cell (`h = ΔX / m`; A-stable, so no
//! limit on the cell size), with the pressure, the coefficient pressure and `ln η` linear between
//! nodes and `E` taken at the strain extrapolated from the two previous sub-steps:
//!
//! `3 ε_s − 4 ε_{s−1} + ε_{s−2} = 2 k_s (p_s − E_s ε_s)`, `k_s = h a / (u1 η_s)`.
//!
//! With `m = 1` this is term for term the steady state of the implicit time stepper at one step
//! per cell (`n_t = 1`, whole-cell shifts, `E` at the extrapolated state): the marched and the
//! direct steady states answer the same discrete equations (tested). More sub-steps resolve the
//! inlet, where the strain relaxes over about a cell on 257².
//!
//! The coupled problem (contact + strain along every row) is solved by a fixed-point iteration:
//! 1. with the upstream strains and the coefficients of the current iterate, the strain of every
//!    point is affine in its own pressure, `ε_i = A_i + B_i p_i`, and the contact is solved with
//!    that layer ([`LayerModel::contact_with_affine_layer`], as in the implicit step);
//! 2. a Gauss–Seidel sweep along every row re-solves each point's strain and pressure with the
//!    elastic response taken local (`local_march`), which gives the next iterate.
//!
//! Converged when the sweep changes the strain the contact carried by less than
//! `strain_tolerance` at every point (max norm), the contact being held to its own tolerance.
//! Before that, each contact solve stops at a tenth of the gap the last mismatch stands for
//! (`l0` times it; an inexact fixed point: solving it tighter than the outer error buys nothing),
//! and a mismatch measured on such a loose solve never counts as converged.
//! Coarser grids are solved first and interpolated up (nested iteration).
//!
//! At low speed the iteration can settle on a cycle instead: the mismatch wanders at a few
//! points where the layer is squeezed out (`ε` at its bound 1) or the contact's lateral edge
//! grazes a row, points that switch in and out of those sets from one iteration to the next. It
//! is the equations', not the iteration's: the time march at the same point settles with a
//! mismatch of the same size, and the cycle's answer is the marched one (tested); mixing,
//! tighter contact solves and damping did not remove it (docs/decisions.md, "The direct steady
//! solve at low speed"). The cycle moves the answer little, so when the solve stalls with the central film and
//! the maximum pressure steady over the stall window to [`CYCLE_BOUND`], it returns the last
//! iterate with the cycle reported ([`SteadyCycle`]): an answer with its bound, which a sweep
//! flags, instead of a hole in the map.

use crate::model::{LayerModel, LayerState};
use crate::stepper::{LayerError, SteadyFailure};
use ehl_core::grid::prolong;
use ehl_core::{Start, check_finite};
use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Settings of the direct steady-rolling solve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteadySettings {
    /// Converged when the strain the contact was solved with and the strain marched from the
    /// solved pressure differ by less than this at every point [-].
    #[serde(default = "default_strain_tolerance")]
    pub strain_tolerance: f64,
    /// Iterations on the finest grid before the solve gives up with a diagnosis.
    #[serde(default = "default_max_iterations")]
    pub max_iterations: usize,
    /// BDF2 sub-steps per cell along `x` (pressure linear between nodes). 1: exactly the
    /// implicit stepper's steady state at one step per cell.
    #[serde(default = "default_substeps")]
    pub substeps: usize,
    /// Solve on coarser grids first (down to 33 points a side) and interpolate up.
    #[serde(default = "default_true")]
    pub nested: bool,
}

fn default_strain_tolerance() -> f64 {
    1e-6
}
fn default_max_iterations() -> usize {
    300
}
fn default_substeps() -> usize {
    4
}
fn default_true() -> bool {
    true
}

impl SteadySettings {
    /// Range checks, each naming its field.
    pub fn check(&self) -> Result<(), ehl_core::FieldError> {
        use ehl_core::check::{count, within};
        within("strain_tolerance", self.strain_tolerance, 1e-12, 1e-2, "")?;
        count("max_iterations", self.max_iterations, 1, 100_000, "iterations")?;
        count("substeps", self.substeps, 1, 64, "sub-steps a cell")
    }
}

impl Default for SteadySettings {
    fn default() -> Self {
        Self {
            strain_tolerance: default_strain_tolerance(),
            max_iterations: default_max_iterations(),
            substeps: default_substeps(),
            nested: true,
        }
    }
}

/// What the steady solve did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SteadyReport {
    /// Fixed-point iterations per grid, coarsest first: `(points a side, iterations)`.
    pub iterations: Vec<(usize, usize)>,
    /// Contact solves (each warm-started), all grids.
    pub solves: usize,
    /// Contact-solver iterations, all grids.
    pub contact_iterations: usize,
    /// Largest strain mismatch at the end (see [`SteadySettings::strain_tolerance`]).
    pub strain_residual: f64,
    /// Largest strain mismatch after each finest-grid iteration.
    pub history: Vec<f64>,
    /// Wall time of the solve [s].
    pub wall_time_s: f64,
    /// The solve stalled on a cycle that moves the answer by less than [`CYCLE_BOUND`]: it
    /// returned the last iterate, not a converged one (`None` when it converged).
    pub cycle: Option<SteadyCycle>,
}

/// A steady solve that settled on a cycle: how far from converged its answer is.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SteadyCycle {
    /// Iterations over which the cycle was measured (the stall window).
    pub window: usize,
    /// Largest strain mismatch over the window [-] (the tolerance was not met).
    pub mismatch: f64,
    /// Where it was largest at the last iteration: `x`, `y` [a].
    pub at_a: [f64; 2],
    /// Spread (largest − smallest) over the window of the central film, relative to it [-].
    pub central_film_spread: f64,
    /// Spread of the maximum pressure, relative to it [-].
    pub max_pressure_spread: f64,
    /// Spread of the approach `h0`, relative to the central film [-]: reported, not judged
    /// (the films and the pressure are the answer; where the layer is squeezed thin the
    /// approach's wobble is a larger share of the film than the film's own).
    pub approach_spread: f64,
}

impl SteadyCycle {
    /// The larger of the central film's and the maximum pressure's relative spreads: how much
    /// the answer moves.
    pub fn spread(&self) -> f64 {
        self.central_film_spread.max(self.max_pressure_spread)
    }
}

/// Largest relative spread of the answer over a stall window for the solve to return it as a
/// cycle-bounded answer: a tenth of the 1 % change at which a sweep's grid check flags a point,
/// so the cycle is never what decides a comparison (and the point is flagged all the same).
pub const CYCLE_BOUND: f64 = 1e-3;

/// Coarsest grid of the nested iteration: the inlet zone needs a few cells.
const MIN_NESTED_POINTS: usize = 33;

/// The steady rolling state of `m` (rolling at [`LayerModel::rolling_speed`] `> 0`, no
/// features), solved directly.
pub fn rolling_steady(
    m: &LayerModel,
    settings: &SteadySettings,
) -> Result<(LayerState, SteadyReport), LayerError> {
    solve(m, settings, false)
}

/// [`rolling_steady`] on one grid of the nested iteration; `start_only`: a coarser grid's solve,
/// whose answer is only the next grid's start, so a stall returns its last iterate whatever the
/// cycle (the finest grid's solve is the one judged).
fn solve(
    m: &LayerModel,
    settings: &SteadySettings,
    start_only: bool,
) -> Result<(LayerState, SteadyReport), LayerError> {
    let t0 = Instant::now();
    if !(m.rolling_speed() > 0.0) {
        return Err(LayerError::Setup(format!(
            "steady rolling needs a rolling velocity > 0 (got {} m/s)",
            m.rolling_speed()
        )));
    }
    if m.has_passing() {
        return Err(LayerError::Setup(
            "steady rolling: a feature passing is not steady; march it in time".into(),
        ));
    }
    let mut report = SteadyReport {
        iterations: vec![],
        solves: 0,
        contact_iterations: 0,
        strain_residual: f64::NAN,
        history: vec![],
        wall_time_s: 0.0,
        cycle: None,
    };
    // Nested iteration: the coarse solution, interpolated, is the start.
    let start = match m.grid.coarser(MIN_NESTED_POINTS).filter(|_| settings.nested) {
        Some(cg) => {
            let coarse = m.on_grid(cg);
            let mut loose = *settings;
            // A coarse grid gives a start only: its discretisation error is far above any tight
            // tolerance, so 1e-4 of strain is enough there.
            loose.strain_tolerance = settings.strain_tolerance.max(1e-4);
            let (s, r) = solve(&coarse, &loose, true)?;
            report.iterations = r.iterations;
            report.solves = r.solves;
            report.contact_iterations = r.contact_iterations;
            Some((prolong(&s.p), prolong(&s.eps)))
        }
        None => None,
    };
    let substeps = settings.substeps;
    let cell = Cell::new(m, substeps);
    let (mut p, mut w, mut eps, mut sub) = match start {
        Some((p, eps)) => {
            // One sub-step before each node, by linear interpolation of the start.
            let mut sub = eps.clone();
            for mut row in sub.rows_mut() {
                let e = row.to_vec();
                for i in 0..e.len() {
                    let up = if i >= 1 { e[i - 1] } else { 0.0 };
                    row[i] = e[i] - (e[i] - up) / substeps as f64;
                }
            }
            (p, m.grid.zeros(), eps, sub)
        }
        None => {
            let s = crate::run::uniform_state(m)?;
            let (eps, sub) = march(m, &s.p, substeps);
            (s.p, s.w, eps, sub)
        }
    };
    let mut start_kind = Start::Warm;
    let supply = m.supply(0.0);
    let ball = m.ball(0.0);
    let mut h0;
    let mut it = 0;
    let tight = m.solver.settings.tolerance;
    let l0_max = supply.iter().cloned().fold(0.0, f64::max);
    // Per finest-grid iteration: the central layer, the maximum pressure and the approach, what
    // a stall's cycle is judged by.
    let mut answers: Vec<[f64; 3]> = vec![];
    // The mismatches that count (measured on contact solves as tight as the gap they stand
    // for, below), and where the last of them was largest.
    let mut honest: Vec<f64> = vec![];
    let mut honest_at = (0, 0);
    let centre = (m.grid.ny / 2, m.grid.nx / 2);
    let residual = loop {
        it += 1;
        // Inexact fixed point: the contact is solved only as tightly as the outer iteration's
        // own error needs, a tenth of the gap the last strain mismatch stands for (the layer's
        // thickness times it), and never looser than 1e-5 nor tighter than its settings.
        // After a mismatch below the tolerance measured on a looser solve, the next solve is
        // held to the tolerance that lets it count.
        let accept = tight.max(INNER_FORCING * l0_max * settings.strain_tolerance);
        let tol = report.history.last().map_or(tight, |&d| {
            if d < settings.strain_tolerance {
                accept
            } else {
                (INNER_FORCING * l0_max * d).clamp(tight, tight.max(1e-5))
            }
        });
        let coef = Coefficients::of(m, &p);
        let [a, b] = linearise(&cell, &coef, &p, &eps, &sub);
        let r = m
            .contact_with_affine_layer(
                &ball,
                &supply,
                &a,
                &b,
                &mut p,
                &mut w,
                start_kind,
                Some(tol),
            )
            .map_err(|e| LayerError::Contact { step: it, t: 0.0, source: e })?;
        start_kind = Start::Warm;
        report.solves += r.solves;
        report.contact_iterations += r.iterations;
        h0 = r.h0;
        let eps_c = r.eps;
        // The contact's gap with its layer, then the local march along every row.
        // Loaded points count as closed: the contact solve holds them closed to its own
        // tolerance, and its residual gap is not the transport's to correct.
        let gap = Zip::from(&ball).and(&w).and(&supply).and(&eps_c).and(&p).par_map_collect(
            |&g, &w, &l0, &e, &p| if p > 0.0 { 0.0 } else { h0 + g + w - l0 * (1.0 - e) },
        );
        // The sweep takes its coefficients at the contact's pressure, not the iterate's: sharing
        // the iterate's set saves an evaluation but stalled the 257² solve at a mismatch of 3.5e-2.
        let [p_loc, eps_loc, sub_loc] =
            local_march(&cell, &Coefficients::of(m, &p), &p, &eps_c, &gap, &supply);
        check_finite("strain", &eps_loc, it)
            .and_then(|_| check_finite("pressure", &p, it))
            .map_err(|e| LayerError::Contact { step: it, t: 0.0, source: e })?;
        // Largest change the march makes to the strain the contact carried.
        let (mut worst, mut at) = (0.0f64, (0, 0));
        for ((j, i), (&x, &y)) in
            eps_loc.indexed_iter().zip(eps_c.iter()).map(|((ji, x), y)| (ji, (x, y)))
        {
            let d = (x - y).abs();
            if d > worst {
                worst = d;
                at = (j, i);
            }
        }
        report.history.push(worst);
        // A mismatch says where the iteration stands only if the contact was solved at least
        // as tightly as the gap it stands for (`l0` times it), or to `accept`: on a looser
        // solve the contact barely moves and the march agrees with it (5 mm/s, 20 N, 385²:
        // 1e-6 on each solve left at the 7e-7 the mismatch before asked for, 2e-4–5e-4 on the
        // tight solve after it), and counting those hid a cycle from the stall watch for 300
        // iterations. A converging solve's mismatches all count (each solve is held to a tenth
        // of the last mismatch's gap, and the next mismatch is of its order).
        if tol <= accept.max(l0_max * worst) {
            honest.push(worst);
            honest_at = at;
        }
        answers.push([
            supply[centre] * (1.0 - eps_c[centre]),
            p.iter().cloned().fold(0.0, f64::max),
            h0,
        ]);
        // A mismatch measured on a contact solved looser than a tenth of the gap the strain
        // tolerance stands for does not count as converged.
        if worst < settings.strain_tolerance && tol <= accept {
            eps = eps_c;
            break worst;
        }
        let stall = stalled(&honest);
        let place = if honest.is_empty() { at } else { honest_at };
        let at_a = [m.grid.x(place.1), m.grid.y(place.0)];
        let cyc = stall.then(|| cycle(&honest, &answers, supply[centre], at_a));
        if let Some(c) = cyc.filter(|c| start_only || c.spread() < CYCLE_BOUND) {
            // A coarser grid's start is not reported: the finest grid's solve is judged.
            report.cycle = (!start_only).then_some(c);
            eps = eps_c;
            break c.mismatch;
        }
        (p, eps, sub) = (p_loc, eps_loc, sub_loc);
        if it >= settings.max_iterations || stall {
            let (kind, trend) = if it < settings.max_iterations {
                (
                    SteadyFailure::Stalled,
                    format!(
                        "stalled: no mismatch below the best so far ({:.2e}) in the last {STALL_WINDOW} iterations, over which the answer moved by {:.1e} (relative; a cycle is returned below {CYCLE_BOUND:.0e})",
                        honest.iter().cloned().fold(f64::INFINITY, f64::min),
                        cyc.map_or(f64::NAN, |c| c.spread())
                    ),
                )
            } else {
                trend(&honest)
            };
            return Err(LayerError::Steady {
                iteration: it,
                residual: honest.last().copied().unwrap_or(worst),
                tolerance: settings.strain_tolerance,
                x: at_a[0],
                y: at_a[1],
                trend,
                kind,
            });
        }
    };
    report.iterations.push((m.grid.nx, it));
    report.strain_residual = residual;
    report.wall_time_s = t0.elapsed().as_secs_f64();
    Ok((LayerState { t: 0.0, eps, p, w, h0 }, report))
}

/// The steady solver's residual at a state: the largest difference between its strain and the
/// strain marched (with `substeps` per cell) from its pressure [-]. Zero for a steady state of
/// the discrete equations; the state's contact is assumed solved (it is, for any state a run
/// or the steady solve produced).
pub fn strain_residual(m: &LayerModel, state: &LayerState, substeps: usize) -> f64 {
    let (eps, _) = march(m, &state.p, substeps);
    (&eps - &state.eps).iter().fold(0.0f64, |a, d| a.max(d.abs()))
}

/// The inner (contact) tolerance as a fraction of the gap the outer mismatch stands for.
const INNER_FORCING: f64 = 0.1;

/// Iterations without a new best mismatch after which the solve is called stalled.
const STALL_WINDOW: usize = 30;

/// Whether the last [`STALL_WINDOW`] iterations failed to beat the best mismatch before them:
/// the iteration has settled on a cycle or a fixed point above the tolerance, and more
/// iterations only cost time (at the seed's lowest speeds the same mismatch repeats for
/// hundreds of iterations). Converging solves set a new best every few iterations. A new best
/// must beat the old by 1 %: a cycle repeats its values to rounding, and "new bests" in the
/// last digits would keep it from being called stalled (docs/decisions.md, "The direct steady
/// solve at low speed").
fn stalled(history: &[f64]) -> bool {
    let n = history.len();
    n > STALL_WINDOW + 10 && {
        let best = |h: &[f64]| h.iter().cloned().fold(f64::INFINITY, f64::min);
        best(&history[n - STALL_WINDOW..]) >= 0.99 * best(&history[..n - STALL_WINDOW])
    }
}

/// The cycle a stalled solve settled on: how much it moves the answer (central layer, maximum
/// pressure, approach; per iteration in `answers`) over the stall window; `at_a` where the
/// mismatch is largest at the last iteration [a].
fn cycle(history: &[f64], answers: &[[f64; 3]], l0_centre: f64, at_a: [f64; 2]) -> SteadyCycle {
    let n = answers.len();
    debug_assert!(n >= STALL_WINDOW, "a stall is judged over a full window");
    let recent = &history[history.len().saturating_sub(STALL_WINDOW)..];
    let w = &answers[n - STALL_WINDOW..];
    let spread = |k: usize| {
        let (lo, hi) = w
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), a| (lo.min(a[k]), hi.max(a[k])));
        hi - lo
    };
    // Relative to the central layer, or where the layer is squeezed out there, to a thousandth
    // of the supplied one.
    let film = answers[n - 1][0].max(1e-3 * l0_centre);
    SteadyCycle {
        window: STALL_WINDOW,
        mismatch: recent.iter().cloned().fold(0.0, f64::max),
        at_a,
        central_film_spread: spread(0) / film,
        max_pressure_spread: spread(1) / answers[n - 1][1],
        approach_spread: spread(2) / film,
    }
}

/// How the strain mismatch behaved over the last iterations, for a diagnosis: the kind and
/// the words.
fn trend(history: &[f64]) -> (SteadyFailure, String) {
    let n = history.len();
    if n < 10 {
        return (SteadyFailure::IterationLimit, "too few iterations to judge".into());
    }
    let (old, new) = (history[n - 10], history[n - 1]);
    if new > old {
        (
            SteadyFailure::Diverging,
            format!(
                "growing over the last 10 iterations ({old:.2e} -> {new:.2e}): the iteration diverges"
            ),
        )
    } else if new > 0.5 * old {
        (
            SteadyFailure::Stalled,
            format!("stalled over the last 10 iterations ({old:.2e} -> {new:.2e})"),
        )
    } else {
        (
            SteadyFailure::IterationLimit,
            format!(
                "still falling ({old:.2e} -> {new:.2e} over the last 10 iterations): allow more iterations"
            ),
        )
    }
}

/// The strain law across one cell, from node `i − 1` to node `i`, in `m` BDF2 sub-steps of
/// `h = ΔX / m`, with the pressure, the coefficient pressure and `ln η` linear between the nodes.
/// Inputs: the strains at the two points before the cell (`e1` at node `i − 1`, `e2` one
/// sub-step before it), the pressures `p0` (node `i − 1`, known) and `p1` (node `i`, the unknown),
/// `p1_guess` (where `E` is evaluated: `E` takes the strain extrapolated from the two previous
/// sub-steps, as the time stepper takes it from the two previous levels), and the coefficients
/// at both nodes ([`Node`]; `ln η` linear between them). Returns the strain at
/// node `i` and one sub-step before it, each as `(α, β)` with `ε = α + β p1`.
///
/// With `m = 1` this is term for term the implicit stepper's steady state at one step per cell.
struct Cell<'a> {
    m: &'a LayerModel,
    substeps: usize,
    /// `ΔX a / (u1 m)` [s]: the time a material point takes for one sub-step.
    dt: f64,
}

impl Cell<'_> {
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn across(
        &self,
        e1: f64,
        e2: f64,
        p0: f64,
        p1_guess: f64,
        n0: Node,
        n1: Node,
    ) -> ((f64, f64), (f64, f64)) {
        let m = self.m;
        // (α, β) of the last two sub-steps, and their values at the guess.
        let (mut c1, mut c2) = ((e1, 0.0), (e2, 0.0));
        let (mut v1, mut v2) = (e1, e2);
        let n = self.substeps as f64;
        // `ln η` linear between the nodes: `1/η` geometric, one `exp` a cell for its ratio.
        let ratio = ((n0.ln_eta - n1.ln_eta) / n).exp();
        let mut k = self.dt * n0.inv_eta;
        for s in 1..=self.substeps {
            let th = s as f64 / n;
            let pc = (1.0 - th) * n0.pc + th * n1.pc;
            k *= ratio;
            let e_coef = (2.0 * v1 - v2).clamp(0.0, 1.0);
            let d = 3.0 + 2.0 * k * m.modulus(pc, e_coef);
            let mut c = (
                (4.0 * c1.0 - c2.0 + 2.0 * k * (1.0 - th) * p0) / d,
                (4.0 * c1.1 - c2.1 + 2.0 * k * th) / d,
            );
            let v = c.0 + c.1 * p1_guess;
            // Between nodes the strain is held in [0, 1] where the guess puts it outside.
            if s < self.substeps && !(0.0..=1.0).contains(&v) {
                c = (v.clamp(0.0, 1.0), 0.0);
            }
            (c2, c1) = (c1, c);
            (v2, v1) = (v1, c.0 + c.1 * p1_guess);
        }
        (c1, c2)
    }
}

/// Per point, `ε_i = A_i + B_i p_i`, with the upstream strains of the iterate (`eps`, `sub`)
/// and the coefficients at the iterate's pressure.
fn linearise(
    cell: &Cell,
    coef: &Coefficients,
    p: &Array2<f64>,
    eps: &Array2<f64>,
    sub: &Array2<f64>,
) -> [Array2<f64>; 2] {
    let rows = by_rows(p.nrows(), |j| {
        let (e, s, p) = (eps.row(j), sub.row(j), p.row(j));
        (0..e.len())
            .map(|i| {
                let (e1, e2, p0) =
                    if i >= 1 { (e[i - 1], s[i - 1], p[i - 1]) } else { (0.0, 0.0, 0.0) };
                let (n, _) = cell.across(e1, e2, p0, p[i], coef.up(j, i), coef.at(j, i));
                [n.0, n.1]
            })
            .collect()
    });
    assemble(p.dim(), &rows)
}

/// Runs `f` for every row index in parallel; each returns its row's values, `K` per point.
fn by_rows<const K: usize>(
    ny: usize,
    f: impl Fn(usize) -> Vec<[f64; K]> + Sync + Send,
) -> Vec<Vec<[f64; K]>> {
    use rayon::prelude::*;
    (0..ny).into_par_iter().map(f).collect()
}

/// The `K` fields of per-row, per-point values.
fn assemble<const K: usize>(dim: (usize, usize), rows: &[Vec<[f64; K]>]) -> [Array2<f64>; K] {
    std::array::from_fn(|k| Array2::from_shape_fn(dim, |(j, i)| rows[j][i][k]))
}

/// The strain along every row from the pressure `p`: at the nodes and one sub-step before.
pub fn march(m: &LayerModel, p: &Array2<f64>, substeps: usize) -> (Array2<f64>, Array2<f64>) {
    let cell = Cell::new(m, substeps);
    let coef = Coefficients::of(m, p);
    let rows = by_rows(p.nrows(), |j| {
        let p = p.row(j);
        let mut out: Vec<[f64; 2]> = Vec::with_capacity(p.len());
        for i in 0..p.len() {
            let (e1, e2, p0) = match i {
                0 => (0.0, 0.0, 0.0),
                _ => (out[i - 1][0], out[i - 1][1], p[i - 1]),
            };
            let (n, q) = cell.across(e1, e2, p0, p[i], coef.up(j, i), coef.at(j, i));
            out.push([(n.0 + n.1 * p[i]).clamp(0.0, 1.0), (q.0 + q.1 * p[i]).clamp(0.0, 1.0)]);
        }
        out
    });
    let [eps, sub] = assemble(p.dim(), &rows);
    (eps, sub)
}

/// The material coefficients' arguments at one node.
#[derive(Clone, Copy)]
struct Node {
    /// Coefficient pressure [p_h].
    pc: f64,
    /// `ln(η / p_h)` [ln s].
    ln_eta: f64,
    /// `p_h / η` [1/s].
    inv_eta: f64,
}

/// The material coefficients' arguments at the nodes, evaluated once per iteration (the
/// sub-steps interpolate them).
struct Coefficients {
    nodes: Array2<Node>,
}

impl Coefficients {
    fn of(m: &LayerModel, p: &Array2<f64>) -> Self {
        let pc = m.coefficient_pressure(p);
        // Elementwise, so the parallel map gives the serial map's values exactly.
        let nodes = Zip::from(&pc).par_map_collect(|&pc| {
            let ln_eta = m.damper.ln_eta(pc);
            Node { pc, ln_eta, inv_eta: (-ln_eta).exp() }
        });
        Self { nodes }
    }
    #[inline]
    fn at(&self, j: usize, i: usize) -> Node {
        self.nodes[[j, i]]
    }
    /// Upstream of node `i`; upstream of the inlet the layer is unloaded.
    #[inline]
    fn up(&self, j: usize, i: usize) -> Node {
        if i >= 1 { self.at(j, i - 1) } else { Node { pc: 0.0, ..self.at(j, 0) } }
    }
}

impl<'a> Cell<'a> {
    fn new(m: &'a LayerModel, substeps: usize) -> Self {
        Self { m, substeps, dt: m.grid.dx() * m.scales.a / (m.rolling_speed() * substeps as f64) }
    }
}

/// Upstream neighbours whose pressure changes the local march adds to a point's deflection: a
/// sweep along `x` sees the upstream changes only, and a longer one-sided near field does
/// worse (docs/decisions.md, "The direct steady solve: grids, speed, and what was tried").
const NEAR_UPSTREAM: usize = 2;

/// One Gauss–Seidel sweep along every row of the coupled problem with the elastic response
/// taken local (one cell's self-influence `K00`, and the deflection of the changes just made
/// [`NEAR_UPSTREAM`] cells upstream): from the contact solution `(p, ε_c)` with gap `gap` (0
/// where loaded), each point in turn gets the strain of its new upstream strains and the
/// pressure that keeps its gap, `gap + near + K00 δp + l0 (ε − ε_c) = 0` where loaded, `p ≥ 0`,
/// `ε ∈ [0, 1]`. Returns the new pressure, strain, and strain a sub-step before.
///
/// Why local: where the layer is more compliant than the half-space at the grid scale, marching
/// the contact's pressure alone over-corrects the strain (the contact already answered the
/// lagged upstream strain with pressure): that iteration diverges on fine grids. With the
/// cell's own stiffness in the sweep, a change of upstream strain is shared between pressure and
/// strain as the contact would share it.
fn local_march(
    cell: &Cell,
    coef: &Coefficients,
    p: &Array2<f64>,
    eps_c: &Array2<f64>,
    gap: &Array2<f64>,
    supply: &Array2<f64>,
) -> [Array2<f64>; 3] {
    let k00 = cell.m.solver.operator().self_influence();
    // Deflection at a point per unit pressure change 1 and 2 cells upstream on its row.
    let k_up: [f64; NEAR_UPSTREAM] = std::array::from_fn(|d| {
        ehl_core::deformation::influence_coefficient(&cell.m.grid, d as i64 + 1, 0)
    });
    let rows = by_rows(p.nrows(), |j| {
        let (p, ec, g, l0) = (p.row(j), eps_c.row(j), gap.row(j), supply.row(j));
        let mut out: Vec<[f64; 3]> = Vec::with_capacity(p.len());
        for i in 0..p.len() {
            let (e1, e2, p0) = match i {
                0 => (0.0, 0.0, 0.0),
                _ => (out[i - 1][1], out[i - 1][2], out[i - 1][0]),
            };
            let p_old = p[i];
            let (n, q) = cell.across(e1, e2, p0, p_old, coef.up(j, i), coef.at(j, i));
            // The gap, with the deflection the pressure changes just made upstream on this row
            // add here.
            let near: f64 = (0..NEAR_UPSTREAM.min(i))
                .map(|d| k_up[d] * (out[i - 1 - d][0] - p[i - 1 - d]))
                .sum();
            let gi = g[i] + near;
            let dp = -(gi + l0[i] * (n.0 + n.1 * p_old - ec[i])) / (k00 + l0[i] * n.1);
            let mut pi = (p_old + dp).max(0.0);
            let mut ei = (n.0 + n.1 * pi).max(0.0);
            if ei > 1.0 && l0[i] > 0.0 {
                // No layer left: the gap closes on the ball alone.
                ei = 1.0;
                pi = (p_old - (gi + l0[i] * (1.0 - ec[i])) / k00).max(0.0);
            }
            out.push([pi, ei.min(1.0), (q.0 + q.1 * pi).clamp(0.0, 1.0)]);
        }
        out
    });
    assemble(p.dim(), &rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stall_is_a_window_without_a_new_best() {
        // Falling with setbacks (the seed's 257² history shape): not stalled.
        let falling: Vec<f64> =
            (0..60).map(|k| 1e-2 * 0.9f64.powi(k) * if k % 5 == 0 { 3.0 } else { 1.0 }).collect();
        assert!(!stalled(&falling));
        // One value repeated after 20 falling iterations: stalled once a window has passed.
        let mut flat: Vec<f64> = (0..20).map(|k| 1e-3 * 0.8f64.powi(k)).collect();
        let last = *flat.last().unwrap();
        flat.extend(std::iter::repeat_n(last * 1.5, 29));
        assert!(!stalled(&flat), "29 iterations are inside the window");
        flat.push(last * 1.5);
        assert!(stalled(&flat));
        // The first 10 iterations only settle the start: 35 are too few to judge.
        let mut short = vec![1e-6; 5];
        short.extend(std::iter::repeat_n(1e-3, 30));
        assert!(!stalled(&short));
    }

    #[test]
    fn the_trend_reads_the_last_ten_iterations() {
        let ramp = |from: f64, to: f64| -> Vec<f64> {
            (0..12).map(|k| from * (to / from).powf(k as f64 / 11.0)).collect()
        };
        let trend = |h: &[f64]| trend(h).1;
        assert!(trend(&[1e-3; 9]).contains("too few"));
        assert!(trend(&ramp(1e-4, 1e-3)).contains("diverges"), "{}", trend(&ramp(1e-4, 1e-3)));
        assert!(trend(&ramp(1e-3, 8e-4)).contains("stalled"), "{}", trend(&ramp(1e-3, 8e-4)));
        let falling = trend(&ramp(1e-3, 1e-5));
        assert!(
            falling.contains("still falling") && falling.contains("more iterations"),
            "{falling}"
        );
    }
}
