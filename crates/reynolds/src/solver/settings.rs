//! What a solve is asked: the settings, their defaults and their checks.

use super::*;

/// Backward differences for `∂(ρ̄H)/∂T`.
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimeScheme {
    /// First order (implicit Euler): robust. The default, because second order amplifies
    /// what each step's iteration leaves (docs/decisions.md, "Time steps").
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
    /// The same in a time step: V-cycles, which converge where W-cycles diverged with the time
    /// derivative's term (docs/decisions.md, "Time steps").
    pub step_gamma: usize,
    /// `h00_gain` in a time step. Lower: the time derivative's term makes the pressure answer
    /// a change of `H00` more strongly than in a steady solve (docs/decisions.md, "Time steps").
    pub step_h00_gain: f64,
    /// Sweeps before the coarse-grid correction in a rolling time step (1 by default); steps at
    /// rest take at least 2, as a steady solve, or the rigid squeeze cycles at its first step
    /// (`tests/squeeze.rs`; the cost: docs/measured/bench-steps.md, docs/decisions.md).
    pub step_pre_sweeps: usize,
    /// The cycle limit of a time step. A step that has not converged by then fails, and error
    /// control tries it shorter: well above what accepted steps take, well below the steady
    /// limit a failing step would otherwise run to (docs/decisions.md, "Time steps").
    pub step_max_cycles: usize,
    /// Coarsest grid (points per side, at least).
    pub coarsest_points: usize,
    /// Converged when the central film changes by less than this (relative) per cycle …
    pub film_tolerance: f64,
    /// In a time step, also: no film anywhere changes by more than this a cycle, relative to
    /// the larger of its own and the central film. A step starts close to its answer and may
    /// end after one cycle, and the central film alone does not see a dent or a front away
    /// from the centre: the seed's shallow dent on 257² left its film up to 7.9 % from the
    /// tightly converged march's with the central film alone, 1.1 % with this at 3e-3, for
    /// 1.5 times the wall time; at 1e-3 a flooded march on 129² stopped at the side lobes' limit
    /// cycle (docs/decisions.md, "Time steps judged by the whole film").
    pub step_film_tolerance: f64,
    /// … and the force balance is met to this (relative).
    pub load_tolerance: f64,
    /// Mass conserving, also: the oil the equations leave unaccounted for, over the supply
    /// ([`CycleLog::mass_defect`]), below this: the central film's change per cycle alone stops
    /// where a meniscus still creeps (docs/decisions.md, "The oil's own stop criterion").
    pub mass_tolerance: f64,
    /// Stop, not converged, when the finest residual has not halved over this many cycles,
    /// nor, mass conserving, the oil unaccounted for (a stall or a limit cycle; 0: run to
    /// `max_cycles`).
    pub stall_cycles: usize,
    /// Gain of the `H00` update per coarsest-grid sweep (times the Hertz compliance `1/π`).
    pub h00_gain: f64,
    /// Full-multigrid start: cycles on each coarser grid, coarsest first, each grid started from
    /// the one below; 0 starts the finest grid from Hertz.
    pub fmg_cycles: usize,
    /// Lagged laws for a second attempt: when a steady solve with the laws following the
    /// pressures at once diverges, stalls or cycles, it starts again with
    /// `relax.coefficient_lag` set to this (and keeps it for the time steps that follow);
    /// 0: no second attempt. Lagged laws cost cycles but converge where the high-`L`
    /// light-load cases diverge (docs/measured/reynolds-stability.md).
    pub fallback_lag: f64,
    /// Smaller Gauss–Seidel changes for a third attempt (`relax.omega_gs` set to this, the
    /// laws still lagged), when the lagged attempt also diverges, stalls or cycles; 0, or not
    /// below `relax.omega_gs`: no third attempt. For heavily starved contacts whose first two
    /// attempts end in a limit cycle of the force balance (docs/reynolds.md, "The attempts
    /// after a failure").
    pub fallback_omega_gs: f64,
    /// Mass conserving, steady: the Gauss–Seidel changes' under-relaxation of the finest
    /// grid's cycles (where smaller than `relax.omega_gs`); the full-multigrid start's coarser
    /// grids relax at `relax.omega_gs` unless a film closes there. At high speed and light load
    /// the fed cycles at 0.4 swing (0.3 m/s, 20 N on 385² over the rule's domain: 197 cycles
    /// over four attempts, 11 with this); with 0.25 in the start as well, the first attempt
    /// stalled at 5 mm/s, 80 N on 1793² (170 cycles over two attempts, 20 with this)
    /// (docs/decisions.md, "Smaller Gauss–Seidel changes for the fed solve"). The time steps
    /// after the solve relax at `relax.omega_gs` unless it needed its lagged attempt.
    pub fed_omega_gs: f64,
    /// Mass conserving, steady: when the attempts above end with the film closed, diverged,
    /// stalled or cycling, a last attempt solves the contact fully flooded (the clamp), then
    /// switches the supply on and cycles from that answer, descending only to grids that hold
    /// the film (cells at most twice [`crate::formulas::cell_needed`]). Kept when it converges:
    /// for fine fed grids whose coarser start grids cannot hold the film (docs/reynolds.md,
    /// "The attempts after a failure").
    pub flooded_start_fallback: bool,
    /// Flooded, steady: when every attempt with the clamp fails on a grid coarser than the grid
    /// rule asks for (its film closing there), a last attempt solves the contact mass
    /// conserving, fed a layer that fills the gap along the inflow boundary, the solids
    /// touching where the film closes (docs/reynolds.md, "The attempts after a failure").
    pub filled_inflow_fallback: bool,
    /// Time discretisation of transient runs.
    pub time_scheme: TimeScheme,
    /// A time step starts from the last state plus the last step's change (pressure and
    /// `H00`), the pressure's carried downstream by the surfaces' travel over the step (at rest,
    /// the linear extrapolation in time), rather than from the last state: fewer cycles a step,
    /// the same answers (docs/decisions.md, "A step's start carried with the surfaces").
    pub extrapolated_start: bool,
    /// Mass conserving, in a time step: the steady solve's extra passes of the relaxation, along
    /// the columns and around the menisci ([`RelaxSettings::column_pass`],
    /// [`RelaxSettings::meniscus_passes`]). A steady solve needs them to move its menisci from
    /// the start to where they settle, many cells; a step starts one step from its answer, and
    /// without them (the default) it costs less and ends no further from the fully converged
    /// march (docs/decisions.md, "Time steps without the extra passes").
    pub step_extra_passes: bool,
    /// In time steps, where the film closes the solids touch (`H = 0`, the pressure there the
    /// contact's, `≥ 0`; the point lets go when holding the gap shut would take a negative
    /// pressure) instead of the film going negative: the side lobes and the exit constriction
    /// after a stop, squeezed shut, and the dry band they leave when rolling starts again. A
    /// rolling step decides its contact anew from its closed films (the set of the last step
    /// is let go, its points full: `θ = 1`, which carries no oil while `H = 0`; a set held from
    /// step to step kept the first rolling steps after a stop from converging). A steady solve
    /// lets the solids touch only when its lubricated cycles end with the film closed (a supply
    /// thinner than the discrete dry gap's error at the contact's edge, a grid too coarse for
    /// the film): converged on the closure, or stalled in an answer settled round it. From that
    /// state the closed points become contact and the cycles go on
    /// ([`ReynoldsReport::touched_from`]); a converged lubricated answer whose touching cycles
    /// fail is returned as it was. Touching from the first cycle, a start's passing closures
    /// became a contact set the cycles never let go of (docs/decisions.md, "The solids touching
    /// in the steady cycles"). Where every attempt fails with a film thinner than the grid
    /// tells from a closed gap, a last attempt starts from the dry contact, touching from its first cycle
    /// ([`ReynoldsReport::from_dry`]).
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
            step_film_tolerance: 3e-3,
            load_tolerance: 1e-6,
            mass_tolerance: 1e-2,
            stall_cycles: 20,
            h00_gain: 0.3,
            fmg_cycles: 2,
            fallback_lag: 0.2,
            fallback_omega_gs: 0.25,
            fed_omega_gs: 0.25,
            flooded_start_fallback: true,
            filled_inflow_fallback: true,
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
    /// These settings with the coarsest grid raised so that every grid of the hierarchy over
    /// `grid` carries a wave `shortest_a` [a] long (a surface pattern's shortest) with two
    /// cells a wavelength at least, Nyquist's limit.
    ///
    /// Why: a grid coarser than that samples the pattern into a longer wave of the same
    /// amplitude that is not there, and where the pattern's crests touch, the coarsest grid's
    /// force balance ran away on it (a 20 nm, 34 µm wave through the seed's contact on 129²:
    /// on 17², 1.6 cells a wavelength, `H00` fell by 1.5e-3 a²/R in one visit, the whole
    /// contact closed, and every attempt failed; stopping at 33², it answered, settled).
    pub fn carrying(mut self, grid: &Grid, shortest_a: f64) -> Self {
        let mut g = *grid;
        while let Some(c) = g.coarser(self.coarsest_points) {
            if c.dx().max(c.dy()) > 0.5 * shortest_a {
                break;
            }
            g = c;
        }
        self.coarsest_points = self.coarsest_points.max(g.nx.min(g.ny));
        self
    }

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
        within(
            "step_film_tolerance",
            self.step_film_tolerance,
            1e-12,
            1.0,
            "relative change a cycle",
        )?;
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
        above("fed_omega_gs", self.fed_omega_gs, 0.0, 1.5, "Gauss-Seidel under-relaxation")?;
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
