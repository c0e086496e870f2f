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

/// Backward differences for `∂(ρ̄H)/∂T`.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimeScheme {
    /// First order (implicit Euler): robust. The default, because second order amplifies
    /// what each step's iteration leaves: on 257² (`M = 20, L = 10`, one step per cell) a
    /// steady state drifted by a factor ~2 per step at the usual per-step tolerances, and in
    /// the seed's regime the cycles diverged on the second step.
    #[default]
    Bdf1,
    /// Second order (first step first order): needs per-step tolerances far below the time
    /// error (tested with `1e-8` on 33²: observed order 1.95).
    Bdf2,
}

/// Solver controls.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ReynoldsSettings {
    /// Cycle limit; past it the solve fails with its history.
    pub max_cycles: usize,
    /// Sweeps before and after the coarse-grid correction.
    pub pre_sweeps: usize,
    /// Relaxation sweeps after each coarse-grid correction.
    pub post_sweeps: usize,
    /// Sweeps on the coarsest grid.
    pub coarse_sweeps: usize,
    /// Coarse-grid visits per level: 2 = W-cycle, 1 = V-cycle.
    pub gamma: usize,
    /// The same in a time step. V-cycles: with the time derivative's term W-cycles diverged
    /// within a step on the seed's conditions over `[−1.25, 1.25]²` (257², one step a cell:
    /// the residual grew 2.8× a cycle from the fifth cycle on, with `H00` held or not), where
    /// V-cycles converge at 0.5 a cycle and held the steady state through 100 steps.
    pub step_gamma: usize,
    /// `h00_gain` in a time step. Lower: the time derivative's term makes the pressure answer
    /// a change of `H00` more strongly than in a steady solve. Measured on the seed's shallow
    /// dent over `[−1.25, 1.25]²` (257², one step a cell, V-cycles): at 0.3 the force balance
    /// stopped at 1.1e-6 (tolerance 1e-6) as the dent crossed `x = 0.87–0.92 a`, with 30
    /// coarsest-grid sweeps too; at 0.1 all 224 steps converge.
    pub step_h00_gain: f64,
    /// Sweeps before the coarse-grid correction in a rolling time step (1 by default); steps at
    /// rest take at least 2, as a steady solve: with 1 the rigid isoviscous squeeze
    /// (`tests/squeeze.rs`, 129²) cycles at its first step (the load error changing sign
    /// every cycle, residual 5e3). Measured on the seed's contact, 257²,
    /// `cargo xtask bench --only steps`, 2 → 1: the shallow dent's passage fed 25 nm 0.046 →
    /// 0.034 s a step (1.14 → 1.16 cycles), its largest deviations from the tight march 0.60 →
    /// 0.95 % (central film), 0.08 → 0.19 % (minimum film), 0.23 → 0.43 % (pressure maximum);
    /// rolling 0.032 → 0.025 s; at rest after a stop 0.121 → 0.076 s (3.65 → 3.25 cycles).
    pub step_pre_sweeps: usize,
    /// The cycle limit of a time step. A step that has not converged by then fails, and error
    /// control tries it shorter. Accepted steps take at most 14 cycles in every march measured
    /// (the seed's stop on 257²: 844 steps, 2.1 a step; the dent passage: 9 at most). With the
    /// steady limit (`max_cycles`) a failing step ran until the stall watch could judge it (81
    /// cycles, mass conserving): on 257² the stop's 0.5 s at rest took 294 s, 0.34 s a step;
    /// at 30, 152 s with the same steps and answer. (The rigid squeeze check, whose force
    /// balance has a deliberately weak gain, sets its own.)
    pub step_max_cycles: usize,
    /// Coarsest grid (points per side, at least).
    pub coarsest_points: usize,
    /// Converged when the central film changes by less than this (relative) per cycle …
    pub film_tolerance: f64,
    /// … and the force balance is met to this (relative).
    pub load_tolerance: f64,
    /// Mass conserving, also: the oil the equations leave unaccounted for, over the supply
    /// ([`CycleLog::mass_defect`]), below this. The central film's change per cycle alone
    /// stopped where a meniscus still crept: on the seed's contact with 25 nm supplied (257²)
    /// 0.4 % short of its converged value at a change of 1e-4 a cycle, where the oil
    /// unaccounted for was 10 % of the supply; at 1 % the film is within 0.05 %.
    pub mass_tolerance: f64,
    /// Stop, not converged, when the finest residual has not halved over this many cycles
    /// (a stall or a limit cycle; 0: run to `max_cycles`).
    pub stall_cycles: usize,
    /// Gain of the `H00` update per coarsest-grid sweep (times the Hertz compliance `1/π`).
    pub h00_gain: f64,
    /// Full-multigrid start: cycles on each coarser grid, coarsest first, each grid started from
    /// the one below; 0 starts the finest grid from Hertz.
    pub fmg_cycles: usize,
    /// Lagged laws for a second attempt: when a steady solve with the laws following the
    /// pressures at once diverges, stalls or cycles, it starts again with
    /// `relax.coefficient_lag` set to this (and keeps it for the time steps that follow);
    /// 0: no second attempt. Lagged laws cost cycles (`M = 20, L = 10` on 257²: 17 against 13
    /// at 0.2) but converge where the high-`L` light-load cases diverged (every `L = 20` case of
    /// the map up to `M = 2223` on 257²).
    pub fallback_lag: f64,
    /// Smaller Gauss–Seidel changes for a third attempt (`relax.omega_gs` set to this, the
    /// laws still lagged), when the lagged attempt also diverges, stalls or cycles; 0, or not
    /// below `relax.omega_gs`: no third attempt. Measured (`seed-speed-load`, fed
    /// 25 nm): at 0.3 m/s and 20 N on 385², and at 1 m/s under 5 and 10 N on 641² and 577², the
    /// heavily starved contacts (films of 21–22 nm, `h_oil/ρ̄`) ended both attempts in a limit
    /// cycle of the force balance or a stall at × 0.4, and converge at × 0.25; a smaller `H00`
    /// gain diverged instead.
    pub fallback_omega_gs: f64,
    /// Mass conserving, steady: when the attempts above end with the film closed, diverged,
    /// stalled or cycling, a last attempt solves the contact fully flooded (the clamp), then
    /// switches the supply on and cycles from that answer, descending only to grids that hold
    /// the film (cells at most twice [`crate::formulas::cell_needed`]). Kept when it converges.
    /// Measured on `seed-speed-load` fed 25 nm: at 2 mm/s, 40 N and 5 mm/s, 80 N (769², the
    /// grid rule's) every earlier attempt diverged in the start on 193² or closed the film at
    /// the outlet (`x` = 0.92–0.99 a), where the flooded solve converges on the same grid; from
    /// the flooded answer they converge (3.668 and 6.294 nm against 3.67 and 6.32 nm flooded),
    /// and so does 2 mm/s, 80 N on 1153² (3.376 against 3.380 nm), whose start diverged on
    /// every start grid tried.
    pub flooded_start_fallback: bool,
    /// Time discretisation of transient runs.
    pub time_scheme: TimeScheme,
    /// A time step starts from the last state plus the last step's change (pressure and
    /// `H00`), the pressure's carried downstream by the surfaces' travel over the step (at rest,
    /// the linear extrapolation in time), rather than from the last state. Measured with the
    /// extrapolation in place: at rest after a stop (the seed's contact fed 25 nm, 129², steps
    /// of a cell's transit) 3.9 cycles a step against 5.4; a dent passing `M = 20, L = 10`
    /// (129², one step a cell) 3.70 against 3.92, the answers within the step's tolerances (the
    /// dent's peak pressure by 2e-4). Carried with the surfaces, the seed's shallow dent (257²,
    /// fed 25 nm) 4.02 → 1.14 cycles a step.
    pub extrapolated_start: bool,
    /// Mass conserving, in a time step: the steady solve's extra passes of the relaxation, along
    /// the columns and around the menisci ([`RelaxSettings::column_pass`],
    /// [`RelaxSettings::meniscus_passes`]). A steady solve needs them to move its menisci from
    /// the start to where they settle, many cells; a step starts one step from its answer, and
    /// without them (the default) it costs half as much and ends no further from the fully
    /// converged march (measured in `docs/reynolds.md`, "Time steps without the extra passes").
    pub step_extra_passes: bool,
    /// In time steps, where the film closes the solids touch (`H = 0`, the pressure there the
    /// contact's, `≥ 0`; the point lets go when holding the gap shut would take a negative
    /// pressure) instead of the film going negative: the side lobes and the exit constriction
    /// after a stop, squeezed shut, and the dry band they leave when rolling starts again. A
    /// rolling step decides its contact anew from its closed films (the set of the last step
    /// is let go, its points full: `θ = 1`, which carries no oil while `H = 0`); holding the
    /// set from step to step instead, the first rolling steps after a stop failed to converge
    /// (`stop-start-compare`, `rolling-from-squeezed-compare`). Steady solves never touch: in
    /// steady rolling a positive film exists on a grid fine enough (2 mm/s, 80 N: closed on
    /// 257², +0.50 nm on 1025²), so a film that closes there is the grid's (the sweeps' grid
    /// rule), and contact rows in the steady full-multigrid start turned the seed's flooded
    /// contact into a dry one (98 % of the load on contact on 129²).
    pub contact: bool,
    /// Mass conserving, steady: the largest factor of a jump along the solve's slow mode when
    /// one mode governs its cycles (the meniscus ring and the pressure inside it; the module
    /// [`crate::extrapolate`] says how it is found and what it gained); 0: no jumps. Time steps
    /// never jump (they start a step from their answer and stop within a few cycles).
    pub mode_extrapolation: f64,
    /// Mass conserving, steady: the first attempt's cycles descend only to grids whose cells are
    /// at most [`COARSE_FILM_CELLS`] times the grid rule's ([`formulas::cell_needed`]), and
    /// those coarser grids solve for the film content too where the gap is partly filled (they
    /// move the menisci; otherwise they hold the finer grid's `θ` and correct pressures only).
    /// When that attempt fails, the next ones hold `θ` on the coarser grids, every grid down to
    /// the coarsest. [`ReynoldsSolver::solve`] says what it gained. A time step never moves
    /// the menisci on its coarser grids, and the workbench turns this off for the steady start
    /// of a march (its first step failed from the first attempt's answer once).
    pub coarse_film_content: bool,
    /// The line relaxation's settings.
    pub relax: RelaxSettings,
    /// When a steady solve stops.
    pub stop: StopRule,
}

/// When a steady solve stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum StopRule {
    /// The central film settled to `film_tolerance` per cycle and the load to `load_tolerance`.
    #[default]
    Strict,
    /// Algebraic error a tenth of the grid's discretisation error: the central film's change
    /// per cycle (the algebraic error estimate) and its load error's share (relative) both
    /// below a tenth of `|H_c − H_c,2h| / 3` (Richardson at order 2 against the film of the
    /// full-multigrid start's grid below). Needs `fmg_cycles > 0`; stops no later than `Strict`.
    Discretisation,
}

impl Default for ReynoldsSettings {
    fn default() -> Self {
        Self {
            max_cycles: 200,
            pre_sweeps: 2,
            post_sweeps: 1,
            coarse_sweeps: 10,
            gamma: 2,
            step_gamma: 1,
            step_h00_gain: 0.1,
            step_max_cycles: 30,
            step_pre_sweeps: 1,
            coarsest_points: 17,
            film_tolerance: 1e-4,
            load_tolerance: 1e-6,
            mass_tolerance: 1e-2,
            stall_cycles: 20,
            h00_gain: 0.3,
            fmg_cycles: 2,
            fallback_lag: 0.2,
            fallback_omega_gs: 0.25,
            flooded_start_fallback: true,
            time_scheme: TimeScheme::Bdf1,
            extrapolated_start: true,
            step_extra_passes: false,
            contact: true,
            mode_extrapolation: 10.0,
            coarse_film_content: true,
            relax: RelaxSettings::default(),
            stop: StopRule::Strict,
        }
    }
}

impl ReynoldsSettings {
    /// Range checks, each naming its field (its path inside these settings): counts that end
    /// (a cycle on 4097² takes seconds: 10⁴ of them is hours), gains and factors where the
    /// iteration they steer can converge, tolerances a double can meet, and the coarsest grid
    /// no smaller than the least grid a scene may have.
    pub fn check(&self) -> Result<(), FieldError> {
        use ehl_core::check::{above, count, within};
        count("max_cycles", self.max_cycles, 1, 10_000, "cycles")?;
        count("pre_sweeps", self.pre_sweeps, 1, 20, "sweeps")?;
        count("post_sweeps", self.post_sweeps, 0, 20, "sweeps")?;
        count("coarse_sweeps", self.coarse_sweeps, 1, 1000, "sweeps")?;
        count("gamma", self.gamma, 1, 2, "1: V-cycles, 2: W-cycles")?;
        count("step_gamma", self.step_gamma, 1, 2, "1: V-cycles, 2: W-cycles")?;
        above("h00_gain", self.h00_gain, 0.0, 10.0, "times the Hertz compliance 1/pi")?;
        above("step_h00_gain", self.step_h00_gain, 0.0, 10.0, "times the Hertz compliance 1/pi")?;
        count(
            "step_pre_sweeps",
            self.step_pre_sweeps,
            1,
            4,
            "sweeps before a time step's coarse-grid correction",
        )?;
        count("step_max_cycles", self.step_max_cycles, 1, 10_000, "cycles")?;
        count("coarsest_points", self.coarsest_points, 5, 4097, "points per side")?;
        within("film_tolerance", self.film_tolerance, 1e-12, 0.1, "relative change a cycle")?;
        within("load_tolerance", self.load_tolerance, 1e-14, 0.1, "relative")?;
        within(
            "mass_tolerance",
            self.mass_tolerance,
            1e-8,
            1.0,
            "oil unaccounted for, over the supply",
        )?;
        count("stall_cycles", self.stall_cycles, 0, 10_000, "cycles; 0: no stall watch")?;
        count(
            "fmg_cycles",
            self.fmg_cycles,
            0,
            100,
            "cycles a coarser grid; 0: no full-multigrid start",
        )?;
        within("fallback_lag", self.fallback_lag, 0.0, 1.0, "0: no second attempt")?;
        within("fallback_omega_gs", self.fallback_omega_gs, 0.0, 1.0, "0: no third attempt")?;
        within(
            "mode_extrapolation",
            self.mode_extrapolation,
            0.0,
            100.0,
            "0: no jumps; the largest factor of a jump along the slow mode",
        )?;
        if self.stop == StopRule::Discretisation && self.fmg_cycles == 0 {
            return Err(FieldError {
                field: "stop".into(),
                value: "\"discretisation\"".into(),
                allowed: "needs the full-multigrid start (fmg_cycles >= 1): its grid below gives the discretisation error estimate".into(),
            });
        }
        self.relax.check().map_err(|e| e.under("relax"))
    }
}

/// One cycle's record.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CycleLog {
    /// The cycle (1 the first).
    pub cycle: usize,
    /// Points per side of the grid cycled (coarser than the finest during the full-multigrid
    /// start).
    pub points: usize,
    /// RMS residual of the Reynolds equation on the finest grid.
    pub residual: f64,
    /// `∬P / (2π/3) − 1`.
    pub load_error: f64,
    /// `H00` after the cycle [a²/R].
    pub h00: f64,
    /// Central film `H(0, 0)` [a²/R].
    pub central_film: f64,
    /// Minimum film [a²/R].
    pub minimum_film: f64,
    /// Wall time since the solve began [s]: what this cycle's answer cost.
    pub wall_s: f64,
    /// Mass conserving: the oil the discrete equations leave unaccounted for, `|Σ r| h²` (the
    /// equations in flux form: what flows out of the domain's edges less what the supply
    /// brings), over the supply's flux `Σ H_oil h` (0 with the clamp).
    pub mass_defect: f64,
}

/// Why a solve that ran to its end did not converge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FailureKind {
    /// The film went negative: the lubricated solution broke down.
    FilmClosed,
    /// The load error changes sign every cycle.
    LimitCycle,
    /// The residual has not halved over the stall window.
    Stalled,
    /// Still converging when the cycle limit came.
    CycleLimit,
}

/// What kept a solve from converging: the kind, where (for a closed film) and when, with the
/// sentence a user reads.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Diagnosis {
    /// What kind of failure.
    pub kind: FailureKind,
    /// The cycle it was given up at.
    pub cycle: usize,
    /// `(x, y)` [a] of the closed film.
    pub at: Option<(f64, f64)>,
    /// The diagnosis in words.
    pub text: String,
}

impl std::fmt::Display for Diagnosis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

/// A solve's outcome.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReynoldsReport {
    /// Whether the stop rule was met.
    pub converged: bool,
    /// Why not converged: what, where, at which cycle.
    pub diagnosis: Option<Diagnosis>,
    /// Cycles run (both attempts).
    pub cycles: usize,
    /// Every cycle's record.
    pub history: Vec<CycleLog>,
    /// Wall time [s].
    pub wall_time_s: f64,
    /// The laws' lag this answer was relaxed with (`relax.coefficient_lag`; 0: none).
    pub lagged_laws: f64,
    /// Why the attempt before this answer's was given up (when the solve started again: with
    /// lagged laws, [`ReynoldsSettings::fallback_lag`], and then with smaller Gauss–Seidel
    /// changes, [`ReynoldsSettings::fallback_omega_gs`]; a third attempt's quotes both; then
    /// from the flooded answer, [`ReynoldsSettings::flooded_start_fallback`]). Their cycles and
    /// time are counted in `cycles` and `wall_time_s`.
    pub first_attempt: Option<String>,
    /// The Gauss–Seidel changes' factor this answer was relaxed with (`relax.omega_gs`).
    pub omega_gs: f64,
    /// A steady solve that stalled (or cycled) with its answer settled: returned, not converged
    /// (`converged` false, `diagnosis` says why), with how little the answer still moved.
    pub settled: Option<Settled>,
    /// Jumps along the slow mode that the answer's cycles took and kept (mass conserving,
    /// steady: [`ReynoldsSettings::mode_extrapolation`]).
    pub mode_jumps: usize,
    /// Mass conserving: the answer's cycles started from the flooded answer
    /// ([`ReynoldsSettings::flooded_start_fallback`]), not from a start of their own.
    pub from_flooded: bool,
}

/// How a stalled steady solve's answer settled over its last cycles ([`SETTLED_BOUND`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Settled {
    /// Finest-grid cycles it was measured over (the stall window).
    pub window: usize,
    /// Spread (largest − smallest) of the central film over them, relative to it [-].
    pub central_film_spread: f64,
    /// Spread of the minimum film, relative to it [-].
    pub minimum_film_spread: f64,
    /// Largest force-balance error over them [-].
    pub load_error: f64,
    /// Largest unaccounted oil over them, relative to the supply's flux [-] (0 with the clamp).
    pub mass_defect: f64,
}

/// Largest relative spread of the central film, and largest force-balance error, over a stalled
/// steady solve's window for it to return its answer as settled: a tenth of the 1 % change at
/// which a sweep's grid check flags a point (the same bound the layer model's steady solve
/// returns its cycles under), so what is left is never what decides a comparison. The minimum
/// film, in the side lobes' constriction, wobbles more (the seed on 129²: 5.9e-3 while the
/// central film moves 5.1e-4) and its grid error is larger still (a sweep's grid check moves it
/// by 3–120 % at these points): it is held to ten times this, the flag limit itself.
pub const SETTLED_BOUND: f64 = 1e-3;

/// The settling of a stalled solve over its last `window` finest-grid cycles, if within
/// [`SETTLED_BOUND`] (and the oil unaccounted for within 3× `mass_tolerance`); `None`
/// otherwise, or with too few cycles to judge.
fn settled(history: &[CycleLog], window: usize, mass_tolerance: f64) -> Option<Settled> {
    let finest = history.last()?.points;
    let fine: Vec<&CycleLog> = history.iter().filter(|c| c.points == finest).collect();
    if window == 0 || fine.len() < window {
        return None;
    }
    let w = &fine[fine.len() - window..];
    let spread = |f: fn(&CycleLog) -> f64| {
        let (lo, hi) = w
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| (lo.min(f(c)), hi.max(f(c))));
        (hi - lo) / hi.abs()
    };
    let largest = |f: fn(&CycleLog) -> f64| w.iter().map(|c| f(c).abs()).fold(0.0, f64::max);
    let s = Settled {
        window,
        central_film_spread: spread(|c| c.central_film),
        minimum_film_spread: spread(|c| c.minimum_film),
        load_error: largest(|c| c.load_error),
        mass_defect: largest(|c| c.mass_defect),
    };
    let within = s.central_film_spread < SETTLED_BOUND
        && s.minimum_film_spread < 10.0 * SETTLED_BOUND
        && s.load_error < SETTLED_BOUND
        && s.mass_defect <= 3.0 * mass_tolerance;
    within.then_some(s)
}

/// Which quantity ran away in a divergence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Divergence {
    /// The pressure.
    NonFinitePressure,
    /// The film.
    NonFiniteFilm,
    /// The residual.
    NonFiniteResidual,
    /// The load error past 1e3: growth by orders of magnitude before it reaches infinity.
    Runaway,
}

/// Why a solve stopped short.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum ReynoldsError {
    #[error(
        "Reynolds solve diverged at cycle {cycle}: {what} (last central film {film:e}, load error {load:e})"
    )]
    /// The solve ran away: a non-finite value, or the load error past 1e3.
    Diverged {
        /// The cycle.
        cycle: usize,
        /// Which quantity.
        kind: Divergence,
        /// `(x, y)` [a] of the first non-finite value, or of the pressure peak.
        at: (f64, f64),
        /// What happened, in words.
        what: String,
        /// The last central film [a²/R].
        film: f64,
        /// The last load error.
        load: f64,
    },
    /// A time step asked of a solver with no steady state to step from.
    #[error("a time step needs a steady solve to start from: call solve() first")]
    NoSteadyStart,
    /// The solve ran to its end without meeting its stop rule (it stalled, cycled, the film
    /// closed, or the cycle limit came): the report, with its diagnosis (what, where, when).
    #[error("the Reynolds solve did not converge: {}", diagnosis_text(.0))]
    NotConverged(Box<ReynoldsReport>),
    /// Stopped on request ([`ehl_core::cancel`]) between two cycles.
    #[error(transparent)]
    Cancelled(#[from] ehl_core::cancel::Cancelled),
}

/// The diagnosis of a report in words (empty when it has none).
fn diagnosis_text(r: &ReynoldsReport) -> &str {
    r.diagnosis.as_ref().map_or("", |d| d.text.as_str())
}

/// A solve's or step's one failure channel: a report that did not converge becomes an error.
fn converged(r: Result<ReynoldsReport, ReynoldsError>) -> Result<ReynoldsReport, ReynoldsError> {
    match r {
        Ok(rep) if !rep.converged && rep.settled.is_none() => {
            Err(ReynoldsError::NotConverged(Box::new(rep)))
        }
        other => other,
    }
}

impl ReynoldsError {
    /// The cycle the solve stopped at (0: before any).
    pub fn cycle(&self) -> usize {
        match self {
            ReynoldsError::Diverged { cycle, .. } => *cycle,
            ReynoldsError::NoSteadyStart | ReynoldsError::Cancelled(_) => 0,
            ReynoldsError::NotConverged(r) => r.cycles,
        }
    }
}

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

/// Mass conserving, the full-multigrid start begins on the coarsest grid with at least this
/// many points per side ([`ReynoldsSolver::fmg_top`]) …
const STARVED_FMG_POINTS: usize = 129;
/// … and gives each grid of the start at most this many cycles to settle.
const STARVED_FMG_MAX_CYCLES: usize = 40;

/// How far each grid of a mass-conserving full-multigrid start settles before the next finer
/// grid takes over: the central film's change a cycle (relative) and the oil the equations
/// leave unaccounted for, in units of [`ReynoldsSettings::mass_tolerance`] (the load to 1e-4
/// either way). Loosely: the finer grid's cycles move the menisci as well as the coarser grid's
/// do, and a tight settle spent its cycles on a meniscus the finer grid then moved anyway (the
/// measurements: `docs/decisions.md`, "A tight settle of the fed full-multigrid start").
const STARVED_FMG_SETTLE: (f64, f64) = (1e-2, 30.0);

fn restrict_full_weighting(r: &Array2<f64>) -> Array2<f64> {
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

impl ReynoldsSolver {
    /// Builds the hierarchy and starts from the Hertz pressure with `H00` from the
    /// Nijenbanning–Venner–Moes central film (on the coarsest grid when the start is full
    /// multigrid).
    pub fn new(grid: Grid, prm: ReynoldsParams, settings: ReynoldsSettings) -> Self {
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
    /// Mass conserving, the coarsest with at least [`STARVED_FMG_POINTS`] per side: on coarser
    /// grids the seed's films are thinner than the grid resolves (negative central films on
    /// 17² and 33², 65² wandering with 5 nm supplied), and the meniscus they gave led the finer
    /// grids into a flooded-like state the supply could not sustain, drained one sweep at a
    /// time (5 nm on 257² from 17²: the central film 2.5× too thick after 150 cycles; started
    /// on 129² it converges in 13).
    fn fmg_top(&self) -> usize {
        if self.active.fmg_cycles == 0 {
            return 0;
        }
        if !self.levels[0].mass_conserving() {
            return self.levels.len() - 1;
        }
        (0..self.levels.len())
            .rev()
            .find(|&l| self.levels[l].grid.nx >= STARVED_FMG_POINTS)
            .unwrap_or(0)
    }

    /// Whether the coarser grids of the cycles solve for the film content, and with it whether
    /// their Couette faces are first order where the gap is partly filled
    /// ([`Level::first_order_partial`]; the finest grid's equations, the answer's, never are).
    /// Without, the coarser grids are as they were before either existed: a time step's cycles
    /// with the first-order faces on its coarser grids failed to converge in the first step of
    /// `rolling-from-squeezed-compare` (30 cycles, force balance 2.2e-6 against 1e-6).
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
    /// supplied. Starting from the flooded film instead, the relaxation drained the excess oil
    /// as slowly as time would (seed conditions, 5 nm on 257²: the central film still 2.5×
    /// too thick after 150 cycles).
    fn starved_film_estimate(&self, hc: f64) -> f64 {
        let Some(s) = self.levels[0].supply() else { return hc };
        let h_oil = s.iter().cloned().fold(f64::INFINITY, f64::min);
        let r = h_oil / (self.prm.density.rho(1.0) * hc);
        hc * r / (1.0 + r * r).sqrt()
    }

    /// Adds `extra(X, Y)` [a²/R] to the rigid film on every level (a dent where positive).
    pub fn set_extra_gap(&mut self, extra: impl Fn(f64, f64) -> f64 + Copy) {
        for l in &mut self.levels {
            l.set_extra_gap(extra);
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
    /// finest grid, `H00` [a²/R]. Solve with `fmg_cycles` 0: a full-multigrid start would begin
    /// again from Hertz.
    pub fn start_from_answer(
        &mut self,
        p: &dyn Fn(usize, usize) -> f64,
        theta: &dyn Fn(usize, usize) -> f64,
        h00: f64,
    ) {
        let f = &mut self.levels[0];
        f.p = Array2::from_shape_fn(f.p.dim(), |(j, i)| p(j, i));
        f.theta = Array2::from_shape_fn(f.theta.dim(), |(j, i)| theta(j, i));
        self.h00 = h00;
        f.update_film(h00);
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

    /// One time step of `dt` [a/u_ref] (the dent, if any, already moved by the caller): the
    /// time derivative by backward differences ([`TimeScheme`]), solved from the last state by
    /// cycles of `step_gamma` (1, V-cycles, by default). The steady solve before the first step
    /// is `T = 0`; steps may differ in size (second order: the variable-step formula, ratio
    /// `ω = dt / dt_prev`, which is the equal-step one at `ω = 1`).
    pub fn step(
        &mut self,
        dt: f64,
        log: &mut dyn FnMut(&CycleLog),
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
            // time. Measured on the seed's shallow dent passing the contact fed 25 nm (257², one
            // step a cell): 4.02 cycles a step with the change extrapolated in place (the
            // moving dent's pressure extrapolated where it was), 1.14 with it carried.
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
            gamma: s.step_gamma,
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
        // Rolling, the first cycle's film change is judged against the start, so that a step
        // whose start was already its answer takes one cycle, not two. Measured on the seed's
        // contact over [−1.25, 1.25]² (257², one step a cell, `cargo xtask bench --only
        // steps`): rolling steadily, fed 25 nm or flooded, 2.0 → 1.0 cycles a step (0.064 →
        // 0.031 s); the shallow dent's passage 4.22 → 4.02 cycles, and its largest deviations
        // from the tightly converged march 1.88 → 1.56 % (central film), 0.16 → 0.13 %
        // (minimum film), 0.85 → 0.81 % (pressure maximum): no less accurate. At rest the
        // trapped film drains by less than the stop rule's 1e-4 a step, and one-cycle steps
        // let it drift: `stop-compare`'s film after 5 s at rest was 9.636 nm against 9.591 nm
        // converged tightly (film 1e-6, load 1e-8) and 9.606 nm with two cycles at least, so
        // at rest the first cycle is never the last.
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

    /// One FAS cycle with level `l` on top, whose force balance asks for `∬P = target`.
    ///
    /// `H00` is the extra unknown of the force balance. As in Venner & Lubrecht it is updated
    /// on the coarsest grid, between sweeps, against the FAS-corrected load target
    /// (`target + load_c(Î P) − load(P)`), so that the load converges at the multigrid rate
    /// instead of at the rate of a per-cycle update.
    fn cycle(&mut self, l: usize, target: f64) {
        let (prm, s) = (self.prm, self.active);
        let last = self.levels.len() - 1;
        if l >= last.min(self.coarsest) {
            // Where the solids touch, twice the gain. Measured on `stop-compare` (129², the
            // seed's stop, the side lobes closed): with the gain of the film alone the force
            // balance held a period-2 cycle of ±1.5e-6 (tolerance 1e-6) with the contact set
            // unchanged, 14 solves failed and were retried shorter (305 steps, 17 s); with
            // twice the gain 218 steps, 12 s; half the gain: 5503 steps.
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
            // loaded point beside one, moves that boundary every cycle (on 257² this kept a
            // period-2 limit cycle in the load at ±1.2e-4, with residuals of order one at
            // near-zero pressures on the outlet boundary). Relaxation fixes those points. The
            // same for a point where the solids touch or beside one: the coarse grid holds the
            // gap's equation only at its own injected points, and its correction there kept a
            // period-2 cycle in the central film (5.0670/5.0686e-3 a²/R) with the contact set
            // unchanged over 30 cycles (`stop-compare`, 129², 0.04 s after the stop; 910 steps
            // and 50 s with the correction, 305 and 17 s without).
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
    /// still moves lowers the residual slowly but steadily (the seed's contact with 25 nm
    /// supplied: ~0.97 a cycle over 120 cycles on 257²): a window twice as long tells that from
    /// a stall.
    fn stall_window(&self) -> usize {
        self.active.stall_cycles * if self.levels[0].mass_conserving() { 2 } else { 1 }
    }

    /// What keeps the solve from converging, in words: a closed film (where), or which criterion
    /// is missed and by how much.
    fn diagnose(&self, history: &[CycleLog], stalled: bool) -> Diagnosis {
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
            (FailureKind::Stalled, "stalled: the residual has not halved over the last cycles")
        } else {
            (FailureKind::CycleLimit, "still converging at the cycle limit")
        };
        let text = format!(
            "after {} cycles: force balance off by {:.2e} (tolerance {:.0e}), residual {:.2e}, central film {:.5e} a²/R; {how}",
            last.cycle,
            last.load_error,
            self.active.load_tolerance,
            last.residual,
            last.central_film
        );
        Diagnosis { kind, cycle: last.cycle, at: None, text }
    }

    /// Central and minimum film of the finest grid.
    pub fn films(&self) -> (f64, f64) {
        self.films_on(0)
    }

    fn films_on(&self, l: usize) -> (f64, f64) {
        let f = &self.levels[l];
        let g = &f.grid;
        let hc = f.film[[g.row_nearest(0.0), g.col_nearest(0.0)]];
        let hmin = f.film.iter().cloned().fold(f64::INFINITY, f64::min);
        (hc, hmin)
    }

    /// One cycle with level `l` on top, recorded; fails on non-finite or runaway values.
    fn logged_cycle(
        &mut self,
        l: usize,
        cycle: usize,
        t0: Instant,
    ) -> Result<CycleLog, ReynoldsError> {
        ehl_core::cancel::check()?;
        let target = 2.0 * PI / 3.0;
        self.levels[l].theta_free = true;
        self.cycle(l, target);
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

    /// Steady solve: full-multigrid start (when set), then cycles on the finest grid until the
    /// central film and the load settle; `log` sees every cycle. The result is time `T = 0` of
    /// any transient run that follows. `Ok` only when converged: a divergence, and a solve that
    /// ran to its end without converging ([`ReynoldsError::NotConverged`], with its report and
    /// diagnosis), are errors.
    ///
    /// Mass conserving, the first attempt's coarser grids solve for the film content
    /// ([`ReynoldsSettings::coarse_film_content`]): the ring of full film round the contact,
    /// which the finest grid's relaxation moved a little each cycle, moves with the coarse-grid
    /// correction. Measured (2 cores, the same tolerances, against the coarser grids holding
    /// `θ` with the jumps along the slow mode): the seed's contact fed 25 nm on 257², 33 → 20
    /// cycles (2.3 → 1.2 s); 15 nm 31 → 24, 100 nm 21 → 13, 5 nm 13 → 13, 10 nm 10 → 14,
    /// 50 nm 16 → 18; 5 mm/s, 40 N on 641², 104 → 52 cycles (35 → 19 s); 10 mm/s, 80 N (257²)
    /// 71 → 26; 1 m/s, 80 N 24 → 19; 20 mm/s, 40 N (385²) 40 → 26 cycles, and the film it
    /// stops at 2e-5 from the one converged 10× tighter, against 1.8e-3. Slower: 2 mm/s, 20 N
    /// (257²), 53 → 73 cycles; 1 m/s, 5 N, 213 → 260. The depth ([`COARSE_FILM_CELLS`]):
    /// down to cells of 8× the grid rule's, the seed's 5–100 nm take 10–23 cycles; to 4×,
    /// 11–20, but 10 mm/s, 80 N 65 cycles against 25 and 5 mm/s, 40 N on 641² 76 against 30;
    /// to 16×, 14–23; to 2×, 24–54; every grid down to 17² closed the film. It needs the
    /// coarser grids' Couette faces first order where the gap is partly filled
    /// ([`Level::first_order_partial`]; the depths above were measured with them on every grid).
    /// Since then every attempt's full-multigrid start hands over from its coarser grid loosely
    /// (`STARVED_FMG_SETTLE` in this file: the seed's 25 nm 20 → 9 cycles, 5 mm/s, 40 N on
    /// 641² 52 → 17, on 1281² 796 → 145).
    pub fn solve(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
    ) -> Result<ReynoldsReport, ReynoldsError> {
        let t0 = Instant::now();
        self.steady_setup();
        let coarse_theta = self.active.coarse_film_content && self.levels[0].mass_conserving();
        if coarse_theta {
            // Never finer than the grid the full-multigrid start begins on (its cycles descend
            // at least that far).
            self.coarsest = self.film_holding_depth(COARSE_FILM_CELLS).max(self.fmg_top());
            self.set_coarse_theta(true);
        }
        let mut rep = self.cycles(log, 0, 0.0, f64::NAN);
        if coarse_theta {
            self.coarsest = usize::MAX;
            self.set_coarse_theta(false);
            // Failed: once more with the coarser grids holding the film content, every grid
            // down to the coarsest.
            if let Some(failed) = given_up(&rep).or_else(|| film_closed(&rep)) {
                let said =
                    format!("first attempt, the coarser grids moving the menisci: {}", failed.0);
                rep = self.attempt(
                    log,
                    "with the coarser grids holding the film content",
                    failed,
                    said,
                    t0,
                );
            }
        }
        let theta = self.active.fallback_lag;
        if theta > 0.0 && self.active.relax.coefficient_lag == 0.0 {
            // The relaxation failed with the laws following at once: start again with them
            // lagged (they stay lagged for any time steps that follow).
            if let Some(failed) = given_up(&rep) {
                self.active.relax.coefficient_lag = theta;
                let said = format!("first attempt, laws following at once: {}", failed.0);
                rep =
                    self.attempt(log, &format!("with lagged laws (θ = {theta})"), failed, said, t0);
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
                rep = self.attempt(log, &what, failed, said, t0);
            }
        }
        if self.active.flooded_start_fallback && self.levels[0].mass_conserving() {
            // The film closed (or the attempts above gave up): once more from the clamp's
            // answer, the supply then switched on. Kept only when it converges; else the
            // attempts before stand, their state back, with what this one gave.
            if let Some(failed) = film_closed(&rep).or_else(|| given_up(&rep)) {
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
        // A stall or a limit cycle whose answer has settled is returned, saying so.
        let window = self.stall_window();
        let rep = rep.map(|mut r| {
            let stuck = r
                .diagnosis
                .as_ref()
                .is_some_and(|d| matches!(d.kind, FailureKind::Stalled | FailureKind::LimitCycle));
            if !r.converged && stuck {
                r.settled = settled(&r.history, window, self.active.mass_tolerance);
            }
            r
        });
        self.rho_h = vec![self.levels[0].rho_film(&self.prm)];
        // Stopped inside a later attempt: the stop is the answer, not the attempts before it.
        ehl_core::cancel::check()?;
        converged(rep)
    }

    /// Before a steady solve: no time history, the settings as given, and no contact
    /// ([`ReynoldsSettings::contact`]: steady solves never touch).
    fn steady_setup(&mut self) {
        self.active = ReynoldsSettings { contact: false, ..self.settings };
        for l in &mut self.levels {
            l.time_a0 = 0.0;
            l.history.fill(0.0);
            l.touch = false;
            l.contact.fill(false);
        }
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

    /// One more attempt of a steady solve, from the start, with the settings now in force
    /// (`self.active`): `what` names them, `failed` is the attempt before's failure (its text
    /// and its cycles, counted on) and `said` what the attempts before were and how they ended.
    /// Its report, or its divergence, says which attempt it is and quotes `said`.
    fn attempt(
        &mut self,
        log: &mut dyn FnMut(&CycleLog),
        what: &str,
        failed: (String, usize),
        said: String,
        t0: Instant,
    ) -> Result<ReynoldsReport, ReynoldsError> {
        self.start();
        let spent = t0.elapsed().as_secs_f64();
        match self.cycles(log, failed.1, spent, f64::NAN) {
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

    /// The last attempt of a mass-conserving steady solve: the same contact fully flooded
    /// first (the clamp, its own full-multigrid start), then the supply switched on and cycles
    /// from that answer (`θ` from [`Level::start_theta_from_flooded`]), cycle numbers and time
    /// counted on from `cycles_before` and `t0`: the fed cycles' outcome, or the flooded
    /// solve's when that did not converge.
    fn attempt_from_flooded(
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
        // ([`formulas::cell_needed`]). Measured at 5 mm/s, 80 N (fed 25 nm, 769², the rule's
        // grid): cycles down to 17² diverged in their first cycle (the coarse grids' films
        // closed, and their corrections wrecked the fine film: `H_c` × 20 in one cycle); down to
        // 385², converged in 93 cycles (90 s, 6.294 nm against 6.32 nm flooded); on 769² alone
        // (ten sweeps a cycle) the oil balance still missed by 11 % after as many cycles.
        self.coarsest = self.film_holding_depth(2.0);
        // The ring of full film round the contact (its meniscus and the pressure inside it,
        // [`crate::extrapolate`]) moves a little each sweep, and on these fine grids that is
        // little a cycle: measured at 2 mm/s, 80 N (1153²), the residual fell 5.7× and the oil
        // unaccounted for from 0.70 to 0.13 over 104 cycles, steadily, when the stall watch's
        // window (40 cycles) stopped it. Twice the window and twice the cycles.
        let kept = self.active;
        self.active.fmg_cycles = 0;
        self.active.stall_cycles *= 2;
        self.active.max_cycles *= 2;
        let fed = self.cycles(log, flooded.cycles, t0.elapsed().as_secs_f64(), f64::NAN);
        self.active = kept;
        self.coarsest = usize::MAX;
        FromFlooded::Fed(fed)
    }

    /// Cycles until converged or given up; cycle numbers and wall times continue from
    /// `cycles_before` and `spent_s` (a second attempt's count both); `start_hc` is the central
    /// film the first cycle's change is measured from (NaN: the first cycle is never the last).
    fn cycles(
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
                let p = prolong(&self.levels[l].p);
                let theta = prolong(&self.levels[l].theta);
                let h00 = self.h00;
                let f = &mut self.levels[l - 1];
                f.p = p;
                f.theta = theta;
                f.rhs.fill(0.0);
                f.update_film(h00);
            }
        }
        for lv in &mut self.levels {
            lv.touch = self.active.contact;
        }
        // The central film of the grid below, where the full-multigrid start left it.
        let coarse_hc = history.last().map(|c: &CycleLog| c.central_film);
        let mut prev_hc = start_hc;
        let film_floor = 1e-2 * self.starved_film_estimate(self.nvm_film());
        let mut stalled = false;
        let mut jumps = ModeExtrapolation::new(self.active.mode_extrapolation);
        for _ in 0..self.active.max_cycles {
            cycle += 1;
            let rec = self.logged_cycle(0, cycle, t0)?;
            let (h00, moved) = jumps.after_cycle(&mut self.levels[0], self.h00, rec.residual);
            self.h00 = h00;
            log(&rec);
            history.push(rec);
            if moved {
                // The record is not the state's after a jump: the next cycle judges it.
                prev_hc = f64::NAN;
                continue;
            }
            let hc = rec.central_film;
            // Relative to the central film, or to a hundredth of the supplied contact's film
            // where the centre has closed (a dry band passing after a stop: `H_c` 1e-10 a²/R,
            // whose relative change no cycle settles).
            let settled =
                ((hc - prev_hc) / hc.abs().max(film_floor)).abs() < self.active.film_tolerance;
            let mass = rec.mass_defect <= self.active.mass_tolerance;
            let strict = settled && rec.load_error.abs() < self.active.load_tolerance && mass;
            let discretisation = match (self.active.stop, coarse_hc) {
                (StopRule::Discretisation, Some(h2)) => {
                    let e_d = (hc - h2).abs() / 3.0;
                    (hc - prev_hc).abs() < 0.1 * e_d
                        && rec.load_error.abs() < 0.1 * e_d / hc
                        && mass
                }
                _ => false,
            };
            if strict || discretisation {
                return Ok(ReynoldsReport {
                    converged: true,
                    diagnosis: None,
                    cycles: cycle,
                    history,
                    wall_time_s: t0.elapsed().as_secs_f64(),
                    lagged_laws: self.active.relax.coefficient_lag,
                    first_attempt: None,
                    omega_gs: self.active.relax.omega_gs,
                    settled: None,
                    mode_jumps: mode_jumps + jumps.jumps,
                    from_flooded: false,
                });
            }
            prev_hc = hc;
            // A stall or a limit cycle: the residual not even halved over the last window.
            let fine: Vec<f64> =
                history.iter().filter(|c| c.points == rec.points).map(|c| c.residual).collect();
            let w = self.stall_window();
            if w > 0 && fine.len() > 2 * w {
                let (before, last) = fine.split_at(fine.len() - w);
                let best = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min);
                if best(last) > 0.5 * best(before) {
                    stalled = true;
                    break;
                }
            }
        }
        Ok(ReynoldsReport {
            converged: false,
            diagnosis: Some(self.diagnose(&history, stalled)),
            cycles: cycle,
            history,
            wall_time_s: t0.elapsed().as_secs_f64(),
            lagged_laws: self.active.relax.coefficient_lag,
            first_attempt: None,
            omega_gs: self.active.relax.omega_gs,
            settled: None,
            mode_jumps: mode_jumps + jumps.jumps,
            from_flooded: false,
        })
    }
}

/// Why a steady attempt was given up, and after how many cycles: a divergence, a stall or a
/// limit cycle. Not a cycle limit (more of the same would converge), nor a closed film: the
/// lagged and smaller-change attempts did not open one where tried (the fed contact at 10 mm/s,
/// 80 N on 769²: closed again with lagged laws, then stalled with smaller changes, 236 s for no
/// answer); a fed film that closed goes to the start from the flooded answer
/// ([`ReynoldsSettings::flooded_start_fallback`]).
fn given_up(rep: &Result<ReynoldsReport, ReynoldsError>) -> Option<(String, usize)> {
    match rep {
        // A stop asked for ends the solve: no attempt follows.
        Err(ReynoldsError::Cancelled(_)) => None,
        Err(e) => Some((e.to_string(), e.cycle())),
        Ok(r) => r
            .diagnosis
            .as_ref()
            .filter(|d| matches!(d.kind, FailureKind::Stalled | FailureKind::LimitCycle))
            .map(|d| (d.text.clone(), r.cycles)),
    }
}

/// Where the attempt from the flooded answer ended
/// ([`ReynoldsSettings::flooded_start_fallback`]).
enum FromFlooded {
    /// The flooded solve did not converge: its outcome.
    Flooded(Result<ReynoldsReport, ReynoldsError>),
    /// The fed cycles from the flooded answer: their outcome.
    Fed(Result<ReynoldsReport, ReynoldsError>),
}

/// What a steady attempt that did not converge says: its diagnosis, or its error.
fn what_it_said(rep: &Result<ReynoldsReport, ReynoldsError>) -> String {
    match rep {
        Ok(r) => r.diagnosis.as_ref().map(|d| d.text.clone()).unwrap_or_default(),
        Err(e) => e.to_string(),
    }
}

/// A failed steady solve's report or divergence with `note` added to what it says.
fn with_note(
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
fn film_closed(rep: &Result<ReynoldsReport, ReynoldsError>) -> Option<(String, usize)> {
    match rep {
        Err(_) => None,
        Ok(r) => r
            .diagnosis
            .as_ref()
            .filter(|d| matches!(d.kind, FailureKind::FilmClosed))
            .map(|d| (d.text.clone(), r.cycles)),
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
}
