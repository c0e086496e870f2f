//! What a solve says: each cycle's record, the report, the diagnosis of a failure, the errors.

use super::*;

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
    /// The residual has not halved over the stall window (nor, mass conserving, the oil
    /// unaccounted for).
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
    /// The cycles' work in finest-grid cycles, every attempt's: a cycle whose top grid has
    /// half the finest grid's points per side counts a quarter (its relaxations, coarse-grid
    /// visits and film updates cost in proportion to its points), so that solves whose
    /// full-multigrid starts begin on different grids compare by what they cost, not by
    /// how many cycles they logged.
    pub work_cycles: f64,
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
    /// A flooded steady solve whose attempts with the clamp all failed: its answer is the
    /// mass-conserving solver's, fed a layer that fills the gap along the inflow boundary (the
    /// inlet flooded as the clamp's), the solids touching where its film closes
    /// ([`ReynoldsSolver::solve`]).
    pub inflow_filled: bool,
    /// A steady solve whose lubricated cycles stalled with the film closed: the cycle from
    /// which the solids touched where it had closed ([`ReynoldsSettings::contact`]); the
    /// contact's share of the load and its area are [`ReynoldsSolver::contact`]'s.
    pub touched_from: Option<usize>,
    /// A steady solve whose attempts all failed with a film thinner than the grid tells from a
    /// closed gap:
    /// its answer's cycles started from the dry contact, the solids touching from the first
    /// ([`ReynoldsSolver::solve`]).
    pub from_dry: bool,
    /// The attempts the steady solve ran, the first included (the answer is the last that
    /// converged or settled, or the first's where a later one failed): the cascade's cost.
    pub attempts: usize,
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
pub(super) fn settled(history: &[CycleLog], window: usize, mass_tolerance: f64) -> Option<Settled> {
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
    // The last film and load error come before `what`: a later attempt's `what` quotes the
    // attempts before it, and at its end they read as the first attempt's.
    #[error(
        "Reynolds solve diverged at cycle {cycle} (last central film {film:.4e} a²/R, load error {load:.2e}): {what}"
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
    /// The dry contact a steady solve starts from where no film can be told (or no oil is
    /// supplied) failed: the core's dry solver's own failure.
    #[error("the dry contact the solve starts from failed: {0}")]
    DryStart(String),
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
pub(super) fn diagnosis_text(r: &ReynoldsReport) -> &str {
    r.diagnosis.as_ref().map_or("", |d| d.text.as_str())
}

/// A solve's or step's one failure channel: a report that did not converge becomes an error.
pub(super) fn converged(
    r: Result<ReynoldsReport, ReynoldsError>,
) -> Result<ReynoldsReport, ReynoldsError> {
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
            ReynoldsError::NoSteadyStart
            | ReynoldsError::DryStart(_)
            | ReynoldsError::Cancelled(_) => 0,
            ReynoldsError::NotConverged(r) => r.cycles,
        }
    }
}

/// A cycle's work in finest-grid cycles ([`ReynoldsReport::work_cycles`]): its top grid's
/// points over the finest grid's, `points` and `finest` per side.
pub(super) fn cycle_work(points: usize, finest: usize) -> f64 {
    (points as f64 / finest as f64).powi(2)
}
