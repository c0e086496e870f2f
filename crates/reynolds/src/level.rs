//! One grid of the multigrid hierarchy: pressure, film, the FAS right-hand side, the discrete
//! Reynolds operator and its line relaxation.
//!
//! Discretisation (Venner & Lubrecht): the Poiseuille term central with `ε̄` averaged to the
//! half points, the wedge term `∂(ρ̄H)/∂X` second-order upwind (first order next to the inflow
//! boundary), the time derivative `∂(ρ̄H)/∂T` by backward differences (transient runs),
//! `P = 0` on the boundary, cavitation as `P ≥ 0`.
//!
//! Two cavitation conditions. Without a supply (fully flooded) the pressure is clamped at 0 and
//! a cavitated point's equation is dropped (Reynolds' condition: the oil pushed out is lost).
//! With a supply the solver is mass conserving (Jakobsson–Floberg–Olsson in Elrod's film
//! content): the wedge and time terms act on `ρ̄ θ H`, `θ` the share of the gap filled with oil,
//! with `P ≥ 0, θ ≤ 1, P (1 − θ) = 0`; where `P = 0` the equation holds with `θ` as its unknown
//! (the oil transported, conserved), and the supply enters as `ρ̄θH = H_oil` on the inflow
//! boundary. The flooded clamp stays the default: it is the same answer for a flooded contact
//! (tested against a thick supply) and its digits are the textbook's.
//!
//! Relaxation: for every line along `X`, changes `δ` of all its interior points are solved
//! together from a banded (pentadiagonal) system. Where the Poiseuille coefficients are large a
//! point's change is its own (Gauss–Seidel); where they are small compared with the wedge term's
//! elastic coupling (the stiff Hertzian zone) the change is distributed (Jacobi distributive):
//! `+δ` at the point and `−δ/4` at its four neighbours, so that the film change it causes is
//! local. The wedge term's dependence on `P` enters through the (distributed) influence kernel.

use crate::laws::{Density, Viscosity};
use crate::params::ReynoldsParams;
use ehl_core::deformation::influence_coefficient;
use ehl_core::{Deformation, Grid};
use ndarray::{Array2, Zip};
use rayon::prelude::*;

/// Pressure [p_h] below which a point counts as cavitated.
pub const CAVITATION_FLOOR: f64 = 1e-10;

/// Relaxation controls.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RelaxSettings {
    /// Points where (Poiseuille diagonal) / (wedge diagonal) falls below this relax
    /// distributively …
    pub distributive_threshold: f64,
    /// … and the time term's part of that diagonal (its elastic self-coupling `a0 ρ̄ K(0, 0)`,
    /// zero in a steady solve) counts with this threshold instead. Measured on the seed's
    /// contact over `[−1.25, 1.25]²` on 257², steps of one cell: at 0.3, Gauss–Seidel steps
    /// where the time term rivals the Poiseuille one made the V-cycle amplify the residual ~7× a
    /// cycle (fed 25 nm, rolling; steps of two cells held) and the first step at rest after a
    /// stop diverged (flooded and fed); at 1 every case converges (2–4 cycles a step); 0.5 and
    /// 0.7 fail some. The cost: on 33² at a twentieth of a cell a step (`M = 20, L = 10`, a
    /// dent, BDF2) the switch at 1 cycles with the load error at ~1e-6 (0.3 converges there).
    pub transient_threshold: f64,
    /// … and at rest (no wedge term: the time term's coupling is the whole of it) with this
    /// one. At rest the coupling falls as the step grows (`a0 = 1/ΔT`), and points where it
    /// was still a fifth of the Poiseuille term took Gauss–Seidel steps at the threshold of 1:
    /// the seed's stop on 257² (fed 25 nm) cycled with period 2, growing 1.2× a cycle, in
    /// steps over 2.5e-4 s, so error control, held back by those failures, kept the steps near
    /// 1.2 ms (the squeeze to its steady end: 1676 steps, 192 rejected, 227.5 s). Over its first
    /// 0.1 s: at 1, 374 steps and 32 failed solves; 3, 169 and 6; 10, 129 and 1; 30, 133 and 1;
    /// 100, 145 and 4. The whole squeeze at 3: 675 steps, 105.5 s (`cargo xtask bench --only
    /// squeeze`); at 10: 558 steps, 91 s. The price is a slower contraction per cycle, which a
    /// step's stop rule (the film's change per cycle) reads as converged earlier: against the
    /// same march converged tightly (first 0.5 s), the central film is within 0.16 % at 3
    /// (0.02 % at 1, 0.12 % at 10) and the minimum film 0.4 % (1.3 % at 1, 0.02 % at 10); the
    /// oil balance of a squeeze that closes the lobes on 129² (`tests/squeeze.rs`) misses by
    /// 1.1e-2 of the oil moved at 3 (6.6e-3 at 1, 5.3e-2 at 10, past that test's bound). The
    /// default stays 1 for now: at 3
    /// `rolling-from-squeezed-compare`'s first rolling step after its rest (up to 5 s, the
    /// lobes shut) fails at any step length (docs/reynolds.md, "Steps at rest");
    /// `stop-compare`, which never rolls again, sets 3.
    pub transient_threshold_at_rest: f64,
    /// Under-relaxation of Gauss–Seidel changes. At 0.7 the outlet pressure spike on 513²
    /// (M = 20, L = 10) keeps a period-2 limit cycle (load ±1.5e-5); 0.5 converges in 18
    /// cycles, 0.4 in 15.
    pub omega_gs: f64,
    /// Under-relaxation of distributive changes.
    pub omega_jd: f64,
    /// Lagged laws: 0 (the default), the viscosity and density follow each pressure at once,
    /// also within a sweep; `θ` in (0, 1], they are held through a sweep and then follow `θ`
    /// of each point's pressure change (at convergence both are the same). The line Jacobian
    /// holds `ε̄` fixed, and where `η̄` rises steeply with `P` (high `L`, light loads) a
    /// checkerboard of a few tenths of `p_h` changes `ε̄` by orders of magnitude: on 257²
    /// (`M = 10, L = 20`) the relaxation alone diverged from the converged 129² solution and
    /// converged with `ε̄` held. Measured (257², `L = 20`): θ = 1 and 0.7 diverge, 0.5 leaves
    /// `M = 20` stalled, 0.3 leaves `M = 500` and `2223` stalled, 0.2 converges `M = 10 … 2223`,
    /// 0.1 diverges again at `M = 2223`. Slower where not needed (`M = 20, L = 10`: 17 cycles at 0.2
    /// against 13), hence a second attempt's setting ([`crate::ReynoldsSettings::fallback_lag`]).
    pub coefficient_lag: f64,
    /// Mass conserving: passes of line relaxation, after each sweep, over windows of each row
    /// around the boundaries between full and partly filled gap (the menisci). 4 halved the
    /// cycles with 10 nm supplied on the seed's contact (257²: 47 → 21); 8 diverged with 5 nm.
    pub meniscus_passes: usize,
    /// Mass conserving: after each sweep, a pass of line relaxation along the columns
    /// (the column pass, `relax_columns`, says why).
    pub column_pass: bool,
    /// Under-relaxation of the gap's changes where the solids touch. The line solve sees the
    /// elastic response of the line's nearest five points only, less than the whole line's.
    pub omega_contact: f64,
    /// Mass conserving: points whose Poiseuille diagonal exceeds this many times the wedge's
    /// take full Gauss–Seidel steps (0: none).
    pub poiseuille_full_step: f64,
}

impl RelaxSettings {
    /// Range checks, each naming its field: thresholds and factors where the relaxation they
    /// steer can converge, pass counts that end.
    pub fn check(&self) -> Result<(), ehl_core::FieldError> {
        use ehl_core::check::{above, count, within};
        within(
            "distributive_threshold",
            self.distributive_threshold,
            0.0,
            1000.0,
            "Poiseuille over wedge diagonal",
        )?;
        above(
            "transient_threshold",
            self.transient_threshold,
            0.0,
            1000.0,
            "times the time term's elastic self-coupling",
        )?;
        above(
            "transient_threshold_at_rest",
            self.transient_threshold_at_rest,
            0.0,
            1000.0,
            "times the time term's elastic self-coupling",
        )?;
        above("omega_gs", self.omega_gs, 0.0, 1.5, "Gauss-Seidel under-relaxation")?;
        above("omega_jd", self.omega_jd, 0.0, 1.5, "distributive under-relaxation")?;
        within("coefficient_lag", self.coefficient_lag, 0.0, 1.0, "0: laws follow at once")?;
        count("meniscus_passes", self.meniscus_passes, 0, 32, "passes")?;
        above(
            "omega_contact",
            self.omega_contact,
            0.0,
            1.5,
            "under-relaxation where the solids touch",
        )?;
        within("poiseuille_full_step", self.poiseuille_full_step, 0.0, 1e6, "0: none")
    }
}

impl Default for RelaxSettings {
    fn default() -> Self {
        Self {
            distributive_threshold: 0.3,
            transient_threshold: 1.0,
            transient_threshold_at_rest: 1.0,
            omega_gs: 0.4,
            omega_jd: 0.3,
            coefficient_lag: 0.0,
            meniscus_passes: 4,
            column_pass: true,
            omega_contact: 0.7,
            poiseuille_full_step: 30.0,
        }
    }
}

/// One grid of the hierarchy: pressure, film, right-hand side, the kernel and the laws' cache; the discrete operator and its relaxation.
pub struct Level {
    /// The grid [a].
    pub grid: Grid,
    /// The deformation operator of this grid.
    pub op: Deformation,
    /// Spacing (equal in X and Y) [a].
    pub h: f64,
    /// Pressure `P` [p_h].
    pub p: Array2<f64>,
    /// Film `H` [a²/R].
    pub film: Array2<f64>,
    /// Film content `θ` (the share of the gap filled with oil, 1 wherever `P > 0`); all ones
    /// without a supply. Column 0 (the inflow boundary) holds the supply's `H_oil / H`.
    pub theta: Array2<f64>,
    /// The supplied layer per row at the inflow boundary [a²/R] (`ρ̄θH` there, the oil at
    /// ambient density): `None` is fully flooded with the clamp.
    supply: Option<Vec<f64>>,
    /// Whether relaxation solves for `θ` where `P = 0` (the top grid of a cycle, with its extra
    /// passes round the menisci); coarser grids of a cycle hold the finer grid's `θ`, injected,
    /// and correct pressures only, unless [`Self::coarse_theta`].
    pub theta_free: bool,
    /// On a coarser grid of a cycle (`theta_free` false): its line relaxation solves for `θ`
    /// where the gap is partly filled too, so that the grid moves the menisci (the steady
    /// solve's first attempt, [`crate::ReynoldsSettings::coarse_film_content`]); without, it
    /// holds the finer grid's `θ`.
    pub coarse_theta: bool,
    /// Whether the Couette term's faces that read a partly filled point are first order (the
    /// coarser grids when they solve for the film content; the Couette weights, `upwind`, say
    /// why).
    pub first_order_partial: bool,
    /// FAS right-hand side (zero on the finest grid).
    pub rhs: Array2<f64>,
    /// Influence kernel rows `K(|di|, dj)` for `dj = 0, 1, 2`, `di = 0 … nx+2`.
    kernel: [Vec<f64>; 3],
    /// Rigid film `X²/2 + Y²/2`, plus any extra gap (a dent).
    shape: Array2<f64>,
    /// Transient term `∂(ρ̄H)/∂T ≈ time_a0 · ρ̄H + history` (second-order backward
    /// differences): `time_a0` [1/ΔT] is 0 for a steady problem …
    pub time_a0: f64,
    /// The wedge term's speed factor `u(t)/u_ref`: the scales (`λ̄`, the time unit `a/u_ref`)
    /// are built on a fixed reference speed, and the surfaces' speed at the time solved for
    /// enters here (1 at the reference speed, 0 at rest: a pure squeeze).
    pub speed: f64,
    /// … and `history` the known part from earlier steps (finest grid only: on coarse grids a
    /// constant term cancels in the FAS equations, so they keep zeros).
    pub history: Array2<f64>,
    /// The laws at each point as last evaluated: `[P_c, η̄ λ̄, ρ̄]` at the coefficient pressure
    /// `P_c` (the point's pressure, or where lagged laws have got to: see
    /// [`RelaxSettings::coefficient_lag`]). The line relaxation reads three rows per line and
    /// a sweep changes few pressures between reads, so `η̄` (a `pow` and an `exp`) is evaluated
    /// again only where `P` changed (bitwise).
    laws: Array2<[f64; 3]>,
    /// Whether the laws lag the pressures (held through a sweep, then following part way).
    lagged: bool,
    /// The laws the cache holds values of (a level solved with other parameters starts afresh).
    laws_for: Option<(f64, Viscosity, Density)>,
    /// `K(di, 0)` as a distributed change sees it ([`Self::kd`]), `di = 0 … 4`: what the line
    /// Jacobian reads, tabulated once.
    kd_line: [f64; 5],
    /// `K(di, 0)`, `di = 0 … 4`, likewise.
    k_line: [f64; 5],
    /// Each half-sweep's line buffers, reused from line to line.
    work: [LineWork; 2],
    /// Rigid solids: no deformation (`W[P] = 0`, the kernel zero). Not a model of a real
    /// contact: the check against the rigid isoviscous squeeze's analytic answer.
    rigid: bool,
    /// Where the solids touch: the film closed (`H = 0`), the point's equation the gap's
    /// (`H = 0`, its pressure the contact's) instead of Reynolds'. Decided before each sweep
    /// (`update_contact`) and held through it.
    pub contact: Array2<bool>,
    /// Whether closed films become contact (off: the film may go negative, as before).
    pub touch: bool,
}

/// A level's pressure, film and law cache from row `first` on, lent to one half of a sweep,
/// with a frozen copy of one row beyond them (the ghost) whose pressure changes wait.
struct Rows<'a> {
    first: usize,
    nx: usize,
    p: &'a mut [f64],
    film: &'a mut [f64],
    laws: &'a mut [[f64; 3]],
    theta: &'a mut [f64],
    ghost: Option<Ghost>,
}

/// A row another half owns, as it was when this half began; the law cache is this half's own.
struct Ghost {
    j: usize,
    p: Vec<f64>,
    film: Vec<f64>,
    laws: Vec<[f64; 3]>,
    theta: Vec<f64>,
    /// Pressure changes `(i, ΔP)` for the owner to add afterwards.
    deferred: Vec<(usize, f64)>,
}

impl<'a> Rows<'a> {
    /// All rows of a level's arrays.
    fn whole(
        p: &'a mut Array2<f64>,
        film: &'a mut Array2<f64>,
        laws: &'a mut Array2<[f64; 3]>,
        theta: &'a mut Array2<f64>,
    ) -> Self {
        let layout = "grid arrays are in standard layout";
        let nx = p.ncols();
        Self::from_slices(
            0,
            nx,
            p.as_slice_mut().expect(layout),
            film.as_slice_mut().expect(layout),
            laws.as_slice_mut().expect(layout),
            theta.as_slice_mut().expect(layout),
        )
    }

    fn from_slices(
        first: usize,
        nx: usize,
        p: &'a mut [f64],
        film: &'a mut [f64],
        laws: &'a mut [[f64; 3]],
        theta: &'a mut [f64],
    ) -> Self {
        Self { first, nx, p, film, laws, theta, ghost: None }
    }

    fn span(&self, j: usize) -> std::ops::Range<usize> {
        let k = j - self.first;
        k * self.nx..(k + 1) * self.nx
    }

    fn ghost(&self, j: usize) -> Option<&Ghost> {
        self.ghost.as_ref().filter(|g| g.j == j)
    }

    fn p_row(&self, j: usize) -> &[f64] {
        match self.ghost(j) {
            Some(g) => &g.p,
            None => &self.p[self.span(j)],
        }
    }

    fn film_row(&self, j: usize) -> &[f64] {
        match self.ghost(j) {
            Some(g) => &g.film,
            None => &self.film[self.span(j)],
        }
    }

    fn theta_row(&self, j: usize) -> &[f64] {
        match self.ghost(j) {
            Some(g) => &g.theta,
            None => &self.theta[self.span(j)],
        }
    }

    /// A row's film content to write (never the ghost).
    fn theta_row_mut(&mut self, j: usize) -> &mut [f64] {
        assert!(self.ghost(j).is_none(), "the ghost row is not relaxed by this half");
        let r = self.span(j);
        &mut self.theta[r]
    }

    /// A row's film to add near-field changes to (never the ghost: it lies behind the sweep).
    fn film_row_mut(&mut self, j: usize) -> &mut [f64] {
        assert!(self.ghost(j).is_none(), "the ghost row is not relaxed by this half");
        let r = self.span(j);
        &mut self.film[r]
    }

    fn laws_p_film(&mut self, j: usize) -> (&mut [[f64; 3]], &[f64], &[f64]) {
        if self.ghost(j).is_none() {
            let r = self.span(j);
            return (&mut self.laws[r.clone()], &self.p[r.clone()], &self.film[r]);
        }
        let g = self.ghost.as_mut().expect("checked");
        (&mut g.laws, &g.p, &g.film)
    }

    /// Adds `d` to `P(i, j)`, a pressure below the cavitation floor becoming 0; returns the
    /// change made `(i, j, ΔP)` if any (none yet on the ghost row: it waits for its owner).
    fn add_p(&mut self, i: usize, j: usize, d: f64) -> Option<(usize, usize, f64)> {
        if let Some(g) = self.ghost.as_mut().filter(|g| g.j == j) {
            g.deferred.push((i, d));
            return None;
        }
        let k = self.span(j).start + i;
        if self.theta[k] < 1.0 {
            // A partly filled point keeps `P = 0` (a distributed change reaching it).
            return None;
        }
        let old = self.p[k];
        // Pressures below 1e-10 p_h are cavitation, not load: left positive they carry
        // equations they cannot satisfy and keep the free boundary moving.
        let new = if old + d > CAVITATION_FLOOR { old + d } else { 0.0 };
        self.p[k] = new;
        (new != old).then_some((i, j, new - old))
    }
}

/// A level's arrays lent out while its rows are relaxed (the level itself read-only meanwhile).
struct Lent {
    p: Array2<f64>,
    film: Array2<f64>,
    laws: Array2<[f64; 3]>,
    theta: Array2<f64>,
    work: [LineWork; 2],
}

/// A line to relax: row `j`, the rows relaxed after it in its half (they see its near-field
/// film change at once), and the points `lo ..= hi` that are its unknowns (`None`: the whole
/// interior; a window around a meniscus otherwise).
struct Line<'a> {
    j: usize,
    next: &'a [usize],
    span: Option<(usize, usize)>,
}

impl<'a> Line<'a> {
    fn whole(j: usize, next: &'a [usize]) -> Self {
        Self { j, next, span: None }
    }
}

/// Buffers of one line's relaxation (kept so that a sweep allocates nothing).
#[derive(Clone, Default)]
struct LineWork {
    /// `ε̄` on rows `j−1, j, j+1`.
    eps: [Vec<f64>; 3],
    /// `ρ̄θ` on row `j` (what the wedge and time terms carry).
    rho: Vec<f64>,
    /// `ρ̄` on row `j`, and `θ` as the line's relaxation leaves it.
    dens: Vec<f64>,
    theta: Vec<f64>,
    /// Which unknowns change distributively.
    dist: Vec<bool>,
    /// Residuals of the line's equations.
    r: Vec<f64>,
    /// Line Jacobian (row q: columns q−2 … q+2) and a copy the elimination may destroy.
    band: Vec<[f64; 5]>,
    solve: Vec<[f64; 5]>,
    /// The right-hand side as elimination leaves it, and the changes `δ`.
    rhs: Vec<f64>,
    delta: Vec<f64>,
    /// Unknowns held by the complementarity passes (`P = 0`; `θ` at 1 or 0) …
    fixed: Vec<bool>,
    /// … and the change their row fixes.
    known: Vec<f64>,
    /// Which unknowns are film contents (`P = 0`, the gap partly filled).
    partial: Vec<bool>,
    /// Pressure changes made `(i, j, ΔP)`.
    applied: Vec<(usize, usize, f64)>,
}

impl Level {
    /// A level on `grid` (square cells), empty.
    pub fn new(grid: Grid) -> Self {
        assert!((grid.dx() - grid.dy()).abs() < 1e-12 * grid.dx(), "square cells required");
        let kernel: [Vec<f64>; 3] = [0, 1, 2].map(|dj| {
            (0..grid.nx as i64 + 3).map(|di| influence_coefficient(&grid, di, dj)).collect()
        });
        let mut l = Self {
            op: Deformation::new(grid),
            h: grid.dx(),
            p: grid.zeros(),
            film: grid.zeros(),
            theta: Array2::ones(grid.shape()),
            supply: None,
            theta_free: true,
            coarse_theta: false,
            first_order_partial: false,
            rhs: grid.zeros(),
            kernel,
            shape: grid.paraboloid(),
            time_a0: 0.0,
            speed: 1.0,
            history: grid.zeros(),
            laws: Array2::from_elem(grid.shape(), [f64::NAN; 3]),
            laws_for: None,
            lagged: false,
            kd_line: [0.0; 5],
            k_line: [0.0; 5],
            work: Default::default(),
            rigid: false,
            contact: Array2::from_elem(grid.shape(), false),
            touch: false,
            grid,
        };
        l.kd_line = std::array::from_fn(|di| l.kd(di as i64, 0));
        l.k_line = std::array::from_fn(|di| l.k(di as i64, 0));
        l
    }

    #[inline]
    fn k(&self, di: i64, dj: i64) -> f64 {
        self.kernel[dj.unsigned_abs() as usize][di.unsigned_abs() as usize]
    }

    /// Kernel seen by a distributed change (+1 at the origin, −1/4 at the four neighbours).
    #[inline]
    fn kd(&self, di: i64, dj: i64) -> f64 {
        self.k(di, dj)
            - 0.25
                * (self.k(di - 1, dj)
                    + self.k(di + 1, dj)
                    + self.k(di, dj - 1)
                    + self.k(di, dj + 1))
    }

    /// Makes the solids rigid: the film is `H00 + X²/2 + Y²/2 + extra` with no deformation, and
    /// the relaxation sees no elastic coupling (the kernel zero). For the analytic squeeze.
    pub fn set_rigid(&mut self) {
        self.rigid = true;
        for row in &mut self.kernel {
            row.fill(0.0);
        }
        self.kd_line = [0.0; 5];
        self.k_line = [0.0; 5];
    }

    /// Rigid film `X²/2 + Y²/2 + extra(X, Y)` [a²/R]: a dent, a bump, or nothing.
    pub fn set_extra_gap(&mut self, extra: impl Fn(f64, f64) -> f64) {
        self.shape = self.grid.field(|x, y| 0.5 * (x * x + y * y) + extra(x, y));
    }

    /// `ρ̄θH` on the grid: the oil's mass per area (`θ = 1` without a supply).
    pub fn rho_film(&self, prm: &ReynoldsParams) -> Array2<f64> {
        Zip::from(&self.p)
            .and(&self.film)
            .and(&self.theta)
            .par_map_collect(|&p, &h, &t| prm.density.rho(p) * t * h)
    }

    /// The supplied layer per row at the inflow boundary [a²/R] (`None`: fully flooded, the
    /// clamp); `θ` starts full and the boundary's follows the film.
    pub fn set_supply(&mut self, supply: Option<Vec<f64>>) {
        if let Some(s) = &supply {
            assert_eq!(s.len(), self.grid.ny, "one supply value per row");
        }
        self.supply = supply;
        self.set_inflow_theta();
    }

    /// The supplied layer per row at the inflow boundary [a²/R] (`None`: flooded, the clamp).
    pub fn supply(&self) -> Option<&[f64]> {
        self.supply.as_deref()
    }

    /// Whether the level conserves mass (has a supply) rather than clamping.
    pub fn mass_conserving(&self) -> bool {
        self.supply.is_some()
    }

    /// A start for `θ`: where `P = 0`, the supplied layer as it arrives, `min(1, H_oil / H)`
    /// (the oil is carried, nothing pushes it back; behind the contact, about what a starved
    /// contact lets through); 1 where loaded. Starting full there instead left the inlet holding oil no supply brought,
    /// and the relaxation carried it away one cell in several sweeps.
    pub fn start_theta(&mut self) {
        self.theta.fill(1.0);
        let Some(s) = &self.supply else { return };
        for ((j, i), t) in self.theta.indexed_iter_mut() {
            let h = self.film[[j, i]];
            if self.p[[j, i]] <= 0.0 && h > s[j] {
                *t = s[j] / h;
            }
        }
    }

    /// A start for `θ` from a flooded answer (the clamp's pressure): along each row, upstream
    /// of where the gap first narrows to the supplied layer, the oil is not there to carry a
    /// pressure, so `P = 0` there; then [`Self::start_theta`]. Kept full, the inlet held a
    /// hundred times the supply where the gap is wide, and the first cycle diverged at the
    /// inflow corner (5 mm/s, 80 N, 769²).
    pub fn start_theta_from_flooded(&mut self) {
        if let Some(s) = &self.supply {
            for (j, &sj) in s.iter().enumerate() {
                for i in 0..self.grid.nx {
                    if self.film[[j, i]] <= sj {
                        break;
                    }
                    self.p[[j, i]] = 0.0;
                }
            }
        }
        self.start_theta();
    }

    /// The wedge's weight at the first point, `(ρ̄θH)_1 − (ρ̄θH)_0` over `h`. In flux form the
    /// second-order upwind stencil has the face flux `1.5 q_i − 0.5 q_(i−1)`; at the first
    /// point the flooded scheme's weight 1 makes the inflow face's flux `(q_0 + q_1)/2`, half
    /// of it the first cell's own content: harmless when the gap is full there, but with a
    /// thin supply (`q_0 = H_oil ≪ q_1`) a source of oil (the seed's contact with 5 nm
    /// supplied carried 7× the supply through the contact). Mass conserving, the inflow face
    /// carries exactly the supply (`q_0`, the layer as it arrives: weight 1.5); the flooded
    /// clamp keeps its weight and its digits.
    #[inline]
    fn first_weight(&self) -> f64 {
        if self.supply.is_some() { 1.5 } else { 1.0 }
    }

    /// The Couette term's weights of `ρ̄θH` at `i, i−1, i−2` (times `1/h`) in point `i`'s
    /// equation, given the row's film contents: the difference of two face fluxes, so that the
    /// oil is conserved whichever each face takes. A face carries the second-order upwind flux
    /// `(3q_i − q_(i−1))/2`; on a coarser grid that solves for the film content
    /// ([`Self::first_order_partial`]) a face that reads a partly filled point carries the
    /// first-order `q_i`. The finest grid's equations, the answer's, are the same everywhere.
    ///
    /// Why first order there: `θ` where the gap is partly filled is carried by the surfaces,
    /// and the second-order flux over a jump in `θ` (the edges of the side bands behind the
    /// contact, a meniscus) over- and undershoots, so that the relaxation clamps `θ` at 0 and 1
    /// in turn. On a coarse grid that solves for `θ`
    /// ([`crate::ReynoldsSettings::coarse_film_content`]) its corrections then wrecked the fine
    /// film: the seed's 10 nm supply closed its film at the outlet within a few cycles (257²),
    /// and converges in 14 cycles with these faces. On every grid, first order where either
    /// point is partly filled moved the seed's central films by up to 0.4 % (10 nm, 257²) and
    /// dried less of a passing hole (`hole-starved-compare`: the contact's share of the load
    /// 5.5 % → 0.06 %, the hole's edges smeared): not the answer's discretisation. Faces that
    /// go first order only where both points are partly filled, or only where the upwind point
    /// is, stalled or closed the film with every supply of the seed's contact tried (5–100 nm).
    ///
    /// A limited flux on every grid was measured against these faces and set aside (first order
    /// at the menisci): `docs/decisions.md`, "Limited Couette faces".
    #[inline]
    fn upwind(&self, theta: &[f64], i: usize) -> [f64; 3] {
        if i < 2 {
            let w = self.first_weight();
            return [w, -w, 0.0];
        }
        if !self.first_order_partial {
            return [1.5, -2.0, 0.5];
        }
        // Face fluxes `F(i+½)`: second order, `(3q_i − q_(i−1))/2`, where the gap is full on
        // both points the face reads; first order, `q_i`, where either is partly filled.
        let partly = |k: usize| theta[k] < 1.0;
        let east = partly(i) || partly(i - 1);
        let west = partly(i - 1) || partly(i - 2);
        let w0 = if east { 1.0 } else { 1.5 };
        let w1 = (if east { 0.0 } else { -0.5 }) - (if west { 1.0 } else { 1.5 });
        let w2 = if west { 0.0 } else { 0.5 };
        [w0, w1, w2]
    }

    /// `θ` on the inflow column from the supply and the film there (`P = 0`, `ρ̄ = 1`):
    /// `min(1, H_oil / H)`.
    fn set_inflow_theta(&mut self) {
        let Some(s) = &self.supply else { return };
        for (j, &h_oil) in s.iter().enumerate() {
            let h = self.film[[j, 0]];
            self.theta[[j, 0]] = if h > h_oil { (h_oil / h).max(0.0) } else { 1.0 };
        }
    }

    /// `∬ P dX dY` (trapezoidal; `P = 0` on the boundary).
    pub fn load(&self) -> f64 {
        self.p.sum() * self.h * self.h
    }

    /// `H = H00 + X²/2 + Y²/2 + W[P]`.
    pub fn update_film(&mut self, h00: f64) {
        // Partly filled points keep their oil (`θH`, `P = 0`) as the gap moves: the oil is
        // carried, not made by opening the gap. Keeping `θ` instead, a coarse grid's `H00`
        // update saw oil appear in the inlet as the gap opened and answered with pressure the
        // fine grid then removed (M = 20, L = 10, 129², 1 µm supplied: the residual stalled at
        // ~0.3 with the force balance on, converged at 0.5 a cycle with `H00` held).
        let before = self.mass_conserving().then(|| self.film.clone());
        if self.rigid {
            self.film.fill(0.0);
        } else {
            self.op.apply(self.p.view(), self.film.view_mut());
        }
        Zip::from(&mut self.film).and(&self.shape).for_each(|f, &s| *f += s + h00);
        if let Some(old) = before {
            Zip::from(&mut self.theta)
                .and(&self.p)
                .and(&old)
                .and(&self.film)
                .for_each(|t, &p, &h0, &h| keep_oil(t, p, h0, h));
        }
        self.set_inflow_theta();
    }

    /// `H += dh` everywhere (a change of `H00`), partly filled points keeping their oil.
    pub fn shift_film(&mut self, dh: f64) {
        if self.mass_conserving() {
            Zip::from(&mut self.theta)
                .and(&self.p)
                .and(&self.film)
                .for_each(|t, &p, &h| keep_oil(t, p, h, h + dh));
        }
        self.film += dh;
        self.set_inflow_theta();
    }

    /// `(ε̄, ρ̄)` at pressure `p` and film `h`: `ε̄ = ρ̄ H³ / (η̄ λ̄)` with `H ≥ 0`.
    #[inline]
    fn eps_rho(prm: &ReynoldsParams, p: f64, h: f64) -> (f64, f64) {
        let rho = prm.density.rho(p);
        (Self::eps_of(rho, h, prm.viscosity.eta(p) * prm.lambda_bar), rho)
    }

    /// `ε̄ = ρ̄ H³ / (η̄ λ̄)` with `H ≥ 0`, from `ρ̄` and the product `η̄ λ̄`.
    #[inline]
    fn eps_of(rho: f64, h: f64, eta_lambda: f64) -> f64 {
        rho * h.max(0.0).powi(3) / eta_lambda
    }

    /// `ε̄` and `ρ̄θ` on the whole grid (the laws from the relaxation's cache where it holds
    /// the point's pressure, the same values bit for bit; lagged laws where they lag).
    pub fn coefficients(&self, prm: &ReynoldsParams) -> (Array2<f64>, Array2<f64>) {
        let cached = self.laws_for == Some((prm.lambda_bar, prm.viscosity, prm.density));
        let held = cached && self.lagged;
        let at = |&p: &f64, &h: &f64, c: &[f64; 3], &t: &f64| {
            let (e, r) = if cached && (c[0].to_bits() == p.to_bits() || held && c[0].is_finite()) {
                (Self::eps_of(c[2], h, c[1]), c[2])
            } else {
                Self::eps_rho(prm, p, h)
            };
            (e, r * t)
        };
        let zip = Zip::from(&self.p).and(&self.film).and(&self.laws).and(&self.theta);
        let both = if self.p.len() >= ehl_core::PAR_MIN_WORK {
            zip.par_map_collect(at)
        } else {
            zip.map_collect(at)
        };
        (both.mapv(|v| v.0), both.mapv(|v| v.1))
    }

    /// `g(j, i, L(P))` at every interior point (0 on the boundary), rows in parallel.
    fn map_operator(
        &self,
        prm: &ReynoldsParams,
        g: impl Fn(usize, usize, f64) -> f64 + Sync,
    ) -> Array2<f64> {
        let (eps, rho) = self.coefficients(prm);
        let (ny, nx) = self.p.dim();
        let mut out = self.grid.zeros();
        let rows = out.axis_iter_mut(ndarray::Axis(0)).into_par_iter();
        rows.with_min_len(ehl_core::par_min_len(nx)).enumerate().for_each(|(j, mut row)| {
            if j == 0 || j == ny - 1 {
                return;
            }
            let e = [row_of(&eps, j - 1), row_of(&eps, j), row_of(&eps, j + 1)];
            let r = row_of(&rho, j);
            let t = row_of(&self.theta, j);
            let (p, film) = self.rows(j);
            for i in 1..nx - 1 {
                row[i] = g(j, i, self.op_line(e, (r, t), p, film, i, j));
            }
        });
        out
    }

    /// Residual `f − L(P)` (zero on the boundary; with the clamp also at cavitated points of
    /// the finest grid, whose equation is dropped; mass conserving, every point's equation
    /// holds, with `θ` its unknown where `P = 0`).
    /// Where the solids touch, the gap's equation is not Reynolds' and is not counted: the
    /// residual there is 0 (what the cycle's record, the oil balance and the stall watch read).
    pub fn residual(&self, prm: &ReynoldsParams) -> Array2<f64> {
        let mut r = self.residual_with_contact(prm);
        if self.touch {
            Zip::from(&mut r).and(&self.contact).for_each(|r, &c| {
                if c {
                    *r = 0.0
                }
            });
        }
        r
    }

    /// [`Self::residual`] with the gap's residual `f − H` where the solids touch.
    fn residual_with_contact(&self, prm: &ReynoldsParams) -> Array2<f64> {
        let all = self.mass_conserving();
        self.map_operator(prm, |j, i, l| {
            if all || self.p[[j, i]] > 0.0 || self.rhs[[j, i]] != 0.0 || self.contact[[j, i]] {
                self.rhs[[j, i]] - l
            } else {
                0.0
            }
        })
    }

    /// The points where the solids touch, decided before a sweep: a point whose film has
    /// closed (`H ≤ 0`) joins; a point in contact stays while it carries pressure (the line
    /// solve lets go of it, `P = 0`, when holding the gap closed would take a negative
    /// pressure: the gap opens there).
    ///
    /// Only the top grid of a cycle decides: a coarser grid holds the finer grid's points
    /// (injected), whose equations its right-hand side was built with; a coarse point that
    /// joined on its own would take the Reynolds right-hand side for a gap.
    fn update_contact(&mut self) {
        if !self.touch || !self.theta_free {
            return;
        }
        let (ny, nx) = self.p.dim();
        for j in 1..ny - 1 {
            for i in 1..nx - 1 {
                let c = &mut self.contact[[j, i]];
                *c = self.film[[j, i]] <= 0.0 || (*c && self.p[[j, i]] > 0.0);
            }
        }
    }

    /// The load the contact carries (`∬ P` over the points where the solids touch) and the
    /// area it covers [a²].
    pub fn contact_load_and_area(&self) -> (f64, f64) {
        let h2 = self.h * self.h;
        let (mut load, mut n) = (0.0, 0usize);
        Zip::from(&self.p).and(&self.contact).for_each(|&p, &c| {
            if c {
                load += p;
                n += 1;
            }
        });
        (load * h2, n as f64 * h2)
    }

    /// The residual a coarser grid is given: [`Self::residual`], but mass conserving only where
    /// the gap is loaded. Where `P = 0` the equation is the film content's, which the coarse
    /// grid holds (it corrects pressures only); restricted, those residuals asked loaded coarse
    /// points for pressure corrections that the fine relaxation then undid (M = 20, L = 10 on
    /// 129², 1 µm supplied: the residual stalled at 0.2, while relaxation alone converged at
    /// 0.99 a sweep). The flooded clamp drops cavitated points' residuals the same way.
    pub fn residual_to_restrict(&self, prm: &ReynoldsParams) -> Array2<f64> {
        let mut r = self.residual_with_contact(prm);
        if self.mass_conserving() {
            Zip::from(&mut r).and(&self.p).and(&self.contact).for_each(|r, &p, &c| {
                if p <= 0.0 && !c {
                    *r = 0.0
                }
            });
        }
        r
    }

    /// `L(P)` on the whole grid (interior), for the FAS coarse right-hand side.
    pub fn operator(&self, prm: &ReynoldsParams) -> Array2<f64> {
        self.map_operator(prm, |_, _, l| l)
    }

    /// One sweep of line relaxation over all lines, then the film recomputed.
    ///
    /// Order: the centre line first, then outward in both directions at once (lines above the
    /// centre upward, lines below downward: the sweep is symmetric, as the contact is, and the
    /// two halves run on two threads). Each line sees at once the pressure changes of the lines
    /// relaxed before it in its own half and their near-field film change. The first line below
    /// the centre reads the centre row as the centre line left it; the distributive changes it
    /// makes on the centre row are added when both halves are done. The result does not depend
    /// on the number of threads.
    pub fn relax(&mut self, prm: &ReynoldsParams, h00: f64, s: &RelaxSettings) {
        let (ny, nx) = self.p.dim();
        self.update_contact();
        self.laws_for(prm);
        self.lagged = s.coefficient_lag > 0.0;
        self.lend(|this, lent| {
            let Lent { p, film, laws, theta, work } = lent;
            let mut whole = Rows::whole(p, film, laws, theta);
            let mid = ny / 2;
            this.relax_line(
                prm,
                s,
                &mut whole,
                Line::whole(mid, &[mid - 1, mid + 1]),
                &mut work[0],
            );
            // The lower half keeps a frozen copy of the centre row; its changes there wait.
            let ghost = Ghost {
                j: mid,
                p: whole.p_row(mid).to_vec(),
                film: whole.film_row(mid).to_vec(),
                laws: whole.laws[mid * nx..(mid + 1) * nx].to_vec(),
                theta: whole.theta_row(mid).to_vec(),
                deferred: Vec::new(),
            };
            let (p_lo, p_hi) = p.as_slice_mut().expect("standard layout").split_at_mut(mid * nx);
            let (f_lo, f_hi) = film.as_slice_mut().expect("standard layout").split_at_mut(mid * nx);
            let (l_lo, l_hi) = laws.as_slice_mut().expect("standard layout").split_at_mut(mid * nx);
            let (t_lo, t_hi) =
                theta.as_slice_mut().expect("standard layout").split_at_mut(mid * nx);
            let mut below =
                Rows { ghost: Some(ghost), ..Rows::from_slices(0, nx, p_lo, f_lo, l_lo, t_lo) };
            let mut above = Rows::from_slices(mid, nx, p_hi, f_hi, l_hi, t_hi);
            let [w_lo, w_hi] = work;
            let upper = || {
                for j in mid + 1..ny - 1 {
                    this.relax_line(prm, s, &mut above, Line::whole(j, &[j + 1]), w_hi);
                }
            };
            let lower = || {
                for j in (1..mid).rev() {
                    this.relax_line(prm, s, &mut below, Line::whole(j, &[j - 1]), w_lo);
                }
            };
            // Even on 17² the halves gain from two threads (measured: a sweep's halves stay
            // in the pool's hands, and the coarsest grid's 10 sweeps a visit were 12 % of a
            // 257² solve on 2 threads when run on one).
            rayon::join(upper, lower);
            let deferred = below.ghost.take().map(|g| g.deferred).unwrap_or_default();
            for (i, d) in deferred {
                above.add_p(i, mid, d);
            }
        });
        self.update_film(h00);
        if self.mass_conserving() && self.theta_free {
            if s.column_pass {
                self.relax_columns(prm, h00, s);
            }
            self.relax_menisci(prm, h00, s);
        }
        if self.lagged {
            self.follow_laws(prm, s.coefficient_lag);
        }
    }

    /// Lends the pressure, film, laws, film content and line buffers to `f`, with the level
    /// read-only, and takes them back.
    fn lend<R>(&mut self, f: impl FnOnce(&Self, &mut Lent) -> R) -> R {
        let mut lent = Lent {
            p: std::mem::take(&mut self.p),
            film: std::mem::take(&mut self.film),
            laws: std::mem::take(&mut self.laws),
            theta: std::mem::take(&mut self.theta),
            work: std::mem::take(&mut self.work),
        };
        let r = f(self, &mut lent);
        let Lent { p, film, laws, theta, work } = lent;
        (self.p, self.film, self.laws, self.theta, self.work) = (p, film, laws, theta, work);
        r
    }

    /// Mass conserving: `meniscus_passes` passes of line relaxation over windows of each row
    /// around the boundaries between full and partly filled gap (7 cells, the neighbours held),
    /// the rows in turn. A meniscus moves by the oil its neighbours' pressures push into it,
    /// a little each sweep, and where the supply fills part of the inlet that was the slow
    /// part of the whole solve: the seed's contact with 25 nm supplied needed ~4× the cycles
    /// at 3 sweeps a cycle as at 12 (129²), a relaxation-bound mode. Windows cost a few cells
    /// a row.
    fn relax_menisci(&mut self, prm: &ReynoldsParams, h00: f64, s: &RelaxSettings) {
        if s.meniscus_passes == 0 {
            return;
        }
        let (ny, nx) = self.p_dim();
        let mut windows: Vec<(usize, usize)> = Vec::new();
        self.lend(|this, lent| {
            let Lent { p, film, laws, theta, work } = lent;
            let mut rows = Rows::whole(p, film, laws, theta);
            for _ in 0..s.meniscus_passes {
                for j in 1..ny - 1 {
                    windows.clear();
                    let (pr, tr) = (rows.p_row(j), rows.theta_row(j));
                    let full = |i: usize| pr[i] > 0.0 || tr[i] >= 1.0;
                    for i in 1..nx - 2 {
                        if full(i) != full(i + 1) {
                            let (lo, hi) = (i.saturating_sub(3).max(1), (i + 4).min(nx - 2));
                            match windows.last_mut() {
                                Some(w) if w.1 + 1 >= lo => w.1 = hi,
                                _ => windows.push((lo, hi)),
                            }
                        }
                    }
                    for &span in &windows {
                        let line = Line { j, next: &[j - 1, j + 1], span: Some(span) };
                        this.relax_line(prm, s, &mut rows, line, &mut work[0]);
                    }
                }
            }
        });
        self.update_film(h00);
    }

    /// A point's own wedge coefficient through its elastic self-influence, and in a time step
    /// the transient term's (`a0 ρ̄ K(0, 0)`), per `ρ̄`: what the Poiseuille diagonal is
    /// compared with to choose a point's relaxation ([`Self::relax_line`] says why).
    /// What the Poiseuille diagonal is compared with to choose distributive relaxation: the
    /// wedge diagonal's parts, each times its threshold (per unit `ρ̄`).
    fn switch_diag(&self, s: &RelaxSettings) -> f64 {
        let (wedge, transient) = self.diag_parts();
        let t =
            if self.speed == 0.0 { s.transient_threshold_at_rest } else { s.transient_threshold };
        s.distributive_threshold * wedge + t * transient
    }

    /// The wedge's and the time term's self-coefficients through the elastic self-influence,
    /// per `ρ̄`.
    fn diag_parts(&self) -> (f64, f64) {
        let wedge = self.speed
            * (1.5 * self.k(0, 0) - 2.0 * self.k(1, 0) + 0.5 * self.k(2, 0)).abs()
            / self.h;
        (wedge, self.time_a0 * self.k(0, 0))
    }

    fn wedge_diag(&self) -> f64 {
        let (wedge, transient) = self.diag_parts();
        wedge + transient
    }

    /// Mass conserving: a second pass of line relaxation with the lines across the rolling
    /// direction (columns, from the inflow on, so that each sees its upstream neighbours' new
    /// film content), over the points where the Poiseuille term governs (the distributive
    /// ones are left to the row pass). Beside the contact the boundary between full and partly
    /// filled gap runs along `x`, between rows: a row pass holds one side of it while solving
    /// the other, and the side meniscus crept a little each sweep (the seed's contact with
    /// 25 nm supplied: film contents beside the contact changing by 0.07 a cycle after 40
    /// cycles). The column Jacobian keeps the Poiseuille stencil, the film-content columns and
    /// the elastic coupling along the column; the film is recomputed after the pass.
    fn relax_columns(&mut self, prm: &ReynoldsParams, h00: f64, s: &RelaxSettings) {
        let (ny, nx) = self.p_dim();
        let h = self.h;
        let (eps, mut rt) = self.coefficients(prm);
        let m = ny - 2;
        let mut band = vec![[0.0; 5]; m];
        let mut solve = vec![[0.0; 5]; m];
        let (mut r, mut rhs, mut delta) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        let (mut kind, mut fixed, mut known) = (vec![0u8; m], vec![false; m], vec![0.0; m]);
        let switch_diag = self.switch_diag(s);
        const FULL: u8 = 0;
        const PARTIAL: u8 = 1;
        const HELD: u8 = 2;
        for i in 1..nx - 1 {
            for q in 0..m {
                let j = q + 1;
                let e = [row_of(&eps, j - 1), row_of(&eps, j), row_of(&eps, j + 1)];
                let (p, film) = self.rows(j);
                let t = row_of(&self.theta, j);
                r[q] = self.rhs[[j, i]] - self.op_line(e, (row_of(&rt, j), t), p, film, i, j);
                let dens = prm.density.rho(self.p[[j, i]]);
                kind[q] = if self.contact[[j, i]] {
                    HELD
                } else if self.p[[j, i]] <= 0.0 && (self.theta[[j, i]] < 1.0 || r[q] > 0.0) {
                    PARTIAL
                } else if 4.0 * e[1][i] / (h * h) < dens * switch_diag {
                    HELD
                } else {
                    FULL
                };
            }
            for q in 0..m {
                let j = q + 1;
                let e = [row_of(&eps, j - 1), row_of(&eps, j), row_of(&eps, j + 1)];
                let (ee, ew, en, es) = self.half_points(e, i);
                let rtj = |ii: usize| rt[[j, ii]];
                let [w0, w1, w2] = self.upwind(row_of(&self.theta, j), i);
                let (r0, r1, r2) =
                    (w0 * rtj(i) / h, w1 * rtj(i - 1) / h, w2 * rtj(i.max(2) - 2) / h);
                let mut row = [0.0; 5];
                for dj in -1i64..=1 {
                    let qc = q as i64 + dj;
                    if qc < 0 || qc >= m as i64 {
                        continue;
                    }
                    let c = (dj + 2) as usize;
                    row[c] = match kind[qc as usize] {
                        PARTIAL if dj == 0 => {
                            -(self.speed * w0 / h + self.time_a0)
                                * prm.density.rho(self.p[[j, i]])
                                * self.film[[j, i]]
                        }
                        PARTIAL => 0.0,
                        _ => {
                            let pois = match dj {
                                0 => -(ee + ew + en + es) / (h * h),
                                1 => en / (h * h),
                                _ => es / (h * h),
                            };
                            let elastic = self.speed
                                * (r0 * self.k(0, dj) + r1 * self.k(1, dj) + r2 * self.k(2, dj))
                                + self.time_a0 * rtj(i) * self.k(0, dj);
                            pois - elastic
                        }
                    };
                }
                band[q] = row;
            }
            let omega = |k: u8| if k == PARTIAL { 1.0 } else { s.omega_gs };
            fixed.iter_mut().zip(&kind).for_each(|(f, &k)| *f = k == HELD);
            known.fill(0.0);
            let mut first = Some(0);
            for _pass in 0..5 {
                let Some(from) = first else { break };
                solve[from..].copy_from_slice(&band[from..]);
                rhs[from..].copy_from_slice(&r[from..]);
                for q in from..m {
                    if fixed[q] {
                        solve[q] = [0.0, 0.0, 1.0, 0.0, 0.0];
                        rhs[q] = known[q];
                    }
                }
                eliminate_banded(&mut solve, &mut rhs, from);
                back_substitute_banded(&solve, &rhs, &mut delta);
                first = None;
                for q in 0..m {
                    if fixed[q] {
                        continue;
                    }
                    let j = q + 1;
                    let k = if kind[q] == PARTIAL {
                        let t = self.theta[[j, i]] + delta[q];
                        (!(0.0..=1.0).contains(&t)).then(|| t.clamp(0.0, 1.0) - self.theta[[j, i]])
                    } else {
                        let pq = self.p[[j, i]];
                        (pq + omega(kind[q]) * delta[q] < 0.0).then(|| -pq / omega(kind[q]))
                    };
                    if let Some(k) = k {
                        fixed[q] = true;
                        known[q] = k;
                        first.get_or_insert(q);
                    }
                }
            }
            for q in 0..m {
                let j = q + 1;
                let d = delta[q] * omega(kind[q]);
                if !d.is_finite() || kind[q] == HELD {
                    continue;
                }
                if kind[q] == PARTIAL {
                    let t = (self.theta[[j, i]] + d).clamp(0.0, 1.0);
                    self.theta[[j, i]] = t;
                    rt[[j, i]] = prm.density.rho(self.p[[j, i]]) * t;
                } else {
                    let old = self.p[[j, i]];
                    let new = if old + d > CAVITATION_FLOOR { old + d } else { 0.0 };
                    self.p[[j, i]] = new;
                    // The film nearby follows at once (the kernel's nearest field, what the
                    // column Jacobian reads).
                    for jj in j.saturating_sub(2).max(1)..(j + 3).min(ny - 1) {
                        for ii in i.saturating_sub(2)..=(i + 2).min(nx - 1) {
                            self.film[[jj, ii]] +=
                                (new - old) * self.k(ii as i64 - i as i64, jj as i64 - j as i64);
                        }
                    }
                }
            }
        }
        self.update_film(h00);
    }

    /// Lagged laws follow `theta` of each point's pressure change since they were evaluated
    /// (all of it once within rounding of the pressure, so that a converged state's laws are
    /// its own, bit for bit).
    fn follow_laws(&mut self, prm: &ReynoldsParams, theta: f64) {
        let at = |c: &mut [f64; 3], &p: &f64| {
            let pc = if !c[0].is_finite() || (p - c[0]).abs() <= 1e-12 * p.abs().max(1e-3) {
                p
            } else {
                c[0] + theta * (p - c[0])
            };
            if pc.to_bits() != c[0].to_bits() {
                *c = laws_at(prm, pc);
            }
        };
        let zip = Zip::from(&mut self.laws).and(&self.p);
        if self.p.len() >= ehl_core::PAR_MIN_WORK { zip.par_for_each(at) } else { zip.for_each(at) }
    }

    /// Whether the laws lag the pressures.
    pub fn lagged(&self) -> bool {
        self.lagged
    }

    /// The pressure each point's laws are evaluated at: what a coarser grid's lagged laws
    /// start from.
    pub fn coefficient_pressures(&self) -> Array2<f64> {
        Zip::from(&self.p)
            .and(&self.laws)
            .map_collect(|&p, c| if self.lagged && c[0].is_finite() { c[0] } else { p })
    }

    /// Evaluates the laws at the coefficient pressures `pc` (a finer grid's, injected), to be
    /// held while they lag.
    pub fn set_coefficient_pressures(&mut self, prm: &ReynoldsParams, pc: &Array2<f64>) {
        self.laws_for(prm);
        self.lagged = true;
        Zip::from(&mut self.laws).and(pc).for_each(|c, &pc| *c = laws_at(prm, pc));
    }

    /// Back to an empty state (no pressure, film, right-hand side, history or laws), the rigid
    /// film kept.
    pub fn reset(&mut self) {
        for a in [&mut self.p, &mut self.film, &mut self.rhs, &mut self.history] {
            a.fill(0.0);
        }
        self.theta.fill(1.0);
        self.contact.fill(false);
        self.set_inflow_theta();
        self.time_a0 = 0.0;
        self.laws.fill([f64::NAN; 3]);
        self.laws_for = None;
        self.lagged = false;
    }

    /// Makes the law cache hold values of `prm`'s laws (emptied when they differ).
    fn laws_for(&mut self, prm: &ReynoldsParams) {
        let key = Some((prm.lambda_bar, prm.viscosity, prm.density));
        if self.laws_for != key {
            self.laws.fill([f64::NAN; 3]);
            self.laws_for = key;
        }
    }

    /// Relaxes line `j` of `rows`, then adds the near-field film change of its pressure changes
    /// to the rows `next` (the lines relaxed after it in this half).
    fn relax_line(
        &self,
        prm: &ReynoldsParams,
        s: &RelaxSettings,
        rows: &mut Rows,
        line: Line,
        w: &mut LineWork,
    ) {
        let Line { j, next, span } = line;
        let (ny, nx) = self.p_dim();
        let h = self.h;
        // The line's unknowns: points `lo ..= hi` (the whole interior, or a window whose
        // neighbours are held).
        let (lo, hi) = span.unwrap_or((1, nx - 2));
        let m = hi + 1 - lo;
        // Wedge coefficients of a point's own change on its own equation, and in a time step the
        // transient term's (`a0 ρ̄ K(0, 0)`, the same elastic self-influence): compare with the
        // Poiseuille diagonal to choose the relaxation. Without the transient term, points in
        // the outlet constriction whose elastic coupling a time step doubles stayed Gauss–Seidel
        // and the smoother amplified an error there from step to step (seed conditions, 257²,
        // one step a cell: the residual grew 1.37× a step and diverged after ~50 steps; more
        // sweeps diverged sooner).
        let (wedge_diag, switch_diag) = (self.wedge_diag(), self.switch_diag(s));
        w.band.resize(m, [0.0; 5]);
        w.delta.resize(m, 0.0);
        // The coefficients the line's equations and Jacobian read: `ε̄` at a point's neighbours
        // and `ρ̄H` two points upstream (three cells each way, to spare).
        let reach = lo.saturating_sub(3)..=(hi + 3).min(nx - 1);
        Self::line_coefficients(prm, s.coefficient_lag > 0.0, rows, j, reach, w);
        let eps = w.eps.each_ref().map(|r| r.as_slice());
        let p = [rows.p_row(j - 1), rows.p_row(j), rows.p_row(j + 1)];
        let film = rows.film_row(j);
        let rhs = row_of(&self.rhs, j);
        let mass_conserving = self.mass_conserving();
        // Where the gap is full `P` is a line unknown; mass conserving, where `P = 0` and the
        // equation asks for less oil than a full gap holds (`r > 0`), or the gap is partly
        // filled, `θ` is (its column in the line Jacobian the wedge's and the time term's
        // weight of `ρ̄H`). Solving both kinds in one line system matters: with the seed's
        // `ε̄` a pressure change of 1e-5 moves a neighbour's film-content equation by ~0.4,
        // and updating `θ` point by point between the pressure solves moved the meniscus
        // one cell in several sweeps (129², a 5 nm supply: the force balance stalled at 2e-4).
        // A coarser grid of a cycle holds `θ` (its partly filled points keep `P = 0`), unless it
        // solves for it too ([`Self::coarse_theta`]).
        if mass_conserving {
            // A loaded point's gap is full (a prolonged start, a correction, may leave less).
            for i in 1..nx - 1 {
                if p[1][i] > 0.0 && w.theta[i] != 1.0 {
                    w.theta[i] = 1.0;
                    w.rho[i] = w.dens[i];
                }
            }
        }
        let rho = w.rho.as_slice();
        w.r.clear();
        let theta_row = w.theta.as_slice();
        w.r.extend((lo..=hi).map(|i| rhs[i] - self.op_line(eps, (rho, theta_row), p, film, i, j)));
        w.partial.clear();
        let touching = |i: usize| self.contact[[j, i]];
        w.partial.extend((lo..=hi).map(|i| {
            mass_conserving
                && !touching(i)
                && p[1][i] <= 0.0
                && (w.theta[i] < 1.0 || w.r[i - lo] > 0.0)
        }));
        // Which points distribute (by the density: not a partly filled point, nor a point
        // beside one on the line, whose change the distribution would spread onto it).
        let part = |q: usize| w.partial[q];
        w.dist.clear();
        // Where the solids touch the change distributes always: the gap's equation is the
        // limit `ε̄ → 0` of Reynolds', the elastic response to a point change reaches across
        // the whole contact, and with the far field a sweep late (the film is recomputed after
        // it) point changes that close each gap overshoot by the kernel's sum over the contact
        // (17², the seed's start: the load doubled in one sweep). A distributed change's
        // response is local.
        w.dist.extend((lo..=hi).map(|i| {
            let q = i - lo;
            !(part(q) || q > 0 && part(q - 1) || q + 1 < m && part(q + 1))
                && (touching(i) || 4.0 * eps[1][i] / (h * h) < w.dens[i] * switch_diag)
        }));
        for q in 0..m {
            w.band[q] = if touching(q + lo) {
                // The gap's row: its change through the elastic response to the line's
                // pressure changes (a film-content unknown moves no gap).
                std::array::from_fn(|c| {
                    let qc = q as i64 + c as i64 - 2;
                    if qc < 0 || qc >= m as i64 || w.partial[qc as usize] {
                        return 0.0;
                    }
                    let k = if w.dist[qc as usize] { &self.kd_line } else { &self.k_line };
                    k[(c as i64 - 2).unsigned_abs() as usize]
                })
            } else {
                self.jacobian_row(eps, rho, &w.theta, q + lo, lo, &w.dist)
            };
        }
        for q in (0..m).filter(|&q| w.partial[q]) {
            // ∂L_i/∂θ_q for the rows i = q, q+1, q+2 the upwind stencil reaches (first order
            // at the first point).
            let mass = w.dens[q + lo] * film[q + lo];
            // The rows upstream of the point do not see its film content.
            for ahead in 1..=2 {
                if q >= ahead {
                    w.band[q - ahead][2 + ahead] = 0.0;
                }
            }
            for back in 0..3 {
                let row = q + back;
                if row >= m {
                    break;
                }
                if touching(row + lo) {
                    continue;
                }
                let weight = self.upwind(&w.theta, row + lo)[back];
                let own = if back == 0 { self.time_a0 * mass } else { 0.0 };
                w.band[row][2 - back] = -self.speed * weight * mass / h - own;
            }
        }
        // Complementarity on the line: points whose pressure the solve would drive negative
        // are fixed at P = 0 (their row becomes δ = −P) and the line solved again, so that
        // the others' changes account for it; clamping afterwards instead makes the
        // cavitation boundary flip from cycle to cycle. Film contents the solve would take
        // above 1 or below 0 are fixed there the same way (a full gap becomes a pressure
        // unknown at the next sweep).
        let dist = &w.dist;
        let partial = &w.partial;
        // (A larger step beside the meniscus, 0.7, halved the cycles with 25 nm supplied on the
        // seed's contact and diverged with 5 and 10 nm.)
        // Mass conserving, where the Poiseuille term outweighs the wedge's elastic coupling many
        // times (the open inlet and the sides) a full Gauss–Seidel step is stable, and the
        // pressures there (a few 1e-5 p_h, carrying the oil the menisci trade) settle twice as
        // fast: the seed's contact with 25 nm supplied, 257², 112 → 60 cycles; 100 nm 45 → 21;
        // M = 20, L = 10 with 3 µm 112 → 57, and 25 nm on 513² converged (119 cycles) where it had
        // stalled. The ratio: at 10 the seed's 5 nm on 513² kept a limit cycle, at 3 the 100 nm
        // case of M = 20 stalled, at 1 the seed's 5 nm diverged on 257²; 30 and 100 gave the
        // same cycles as 10 on 257² and converged on 513².
        let big = s.poiseuille_full_step;
        let poiseuille = |q: usize| {
            big > 0.0 && mass_conserving && {
                let i = q + lo;
                4.0 * eps[1][i] / (h * h) > big * w.dens[i] * wedge_diag
            }
        };
        let omega = |q: usize| {
            if partial[q] {
                1.0
            } else if touching(q + lo) {
                s.omega_contact
            } else if dist[q] {
                s.omega_jd
            } else if poiseuille(q) {
                1.0
            } else {
                s.omega_gs
            }
        };
        let p_line = p[1];
        w.fixed.clear();
        w.fixed.resize(m, false);
        w.known.clear();
        w.known.resize(m, 0.0);
        w.solve.resize(m, [0.0; 5]);
        w.rhs.resize(m, 0.0);
        if !self.theta_free && !self.coarse_theta {
            for q in (0..m).filter(|&q| partial[q]) {
                w.fixed[q] = true;
            }
        }
        let mut first = Some(0);
        for _pass in 0..5 {
            // The rows before the first newly fixed one eliminate as they did in the last
            // pass: the elimination resumes there (the same operations, the same numbers).
            let Some(from) = first else { break };
            w.solve[from..].copy_from_slice(&w.band[from..]);
            w.rhs[from..].copy_from_slice(&w.r[from..]);
            for q in from..m {
                if w.fixed[q] {
                    w.solve[q] = [0.0, 0.0, 1.0, 0.0, 0.0];
                    w.rhs[q] = w.known[q];
                }
            }
            eliminate_banded(&mut w.solve, &mut w.rhs, from);
            back_substitute_banded(&w.solve, &w.rhs, &mut w.delta);
            first = None;
            for q in 0..m {
                if w.fixed[q] {
                    continue;
                }
                let known = if partial[q] {
                    let t = w.theta[q + lo] + w.delta[q];
                    (!(0.0..=1.0).contains(&t)).then(|| t.clamp(0.0, 1.0) - w.theta[q + lo])
                } else {
                    let pq = p_line[q + lo];
                    (pq + omega(q) * w.delta[q] < 0.0).then(|| -pq / omega(q))
                };
                if let Some(k) = known {
                    w.fixed[q] = true;
                    w.known[q] = k;
                    first.get_or_insert(q);
                }
            }
        }
        // Apply changes (cavitation: no negative pressures, film contents in [0, 1]).
        w.applied.clear();
        for q in 0..m {
            let i = q + lo;
            let d = w.delta[q] * omega(q);
            if !d.is_finite() {
                continue;
            }
            if partial[q] {
                let t = (w.theta[i] + d).clamp(0.0, 1.0);
                w.theta[i] = t;
                w.rho[i] = w.dens[i] * t;
            } else if dist[q] {
                w.applied.extend(rows.add_p(i, j, d));
                for (ii, jj) in [(i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1)] {
                    if ii >= 1 && ii < nx - 1 && jj >= 1 && jj < ny - 1 {
                        w.applied.extend(rows.add_p(ii, jj, -0.25 * d));
                    }
                }
            } else {
                w.applied.extend(rows.add_p(i, j, d));
            }
        }
        if mass_conserving {
            rows.theta_row_mut(j).copy_from_slice(&w.theta);
        }
        // The next lines see the near-field film change of these changes at once (the full
        // film is recomputed by FFT after the sweep): within NEAR cells the kernel carries
        // what the line Jacobian needs; beyond, the change is smooth and small.
        const NEAR: usize = 8;
        for &jn in next.iter().filter(|&&jn| jn >= 1 && jn < ny - 1) {
            let film = rows.film_row_mut(jn);
            for &(i, jj, d) in &w.applied {
                let krow = &self.kernel[jn.abs_diff(jj)];
                let (lo, hi) = (i.saturating_sub(NEAR), (i + NEAR).min(nx - 1));
                // `film[ii] += d K(|ii − i|)` for `ii` in `lo ..= hi`, as two slices (upstream,
                // the kernel read backwards; from `i` on, forwards): the same sums, bit for bit,
                // vectorised and without an index check per point. Measured over the seed's dent
                // passage (257²): this loop held ~30 % of the line relaxation's samples, and the
                // relaxation's share of the run fell from 44 % to 40 % (steps ~3 % faster).
                for (f, &k) in film[lo..i].iter_mut().zip(krow[1..=i - lo].iter().rev()) {
                    *f += d * k;
                }
                for (f, &k) in film[i..=hi].iter_mut().zip(&krow[..=hi - i]) {
                    *f += d * k;
                }
            }
        }
    }

    /// Points per side `(ny, nx)` (the pressure array may be lent out during a sweep).
    fn p_dim(&self) -> (usize, usize) {
        (self.grid.ny, self.grid.nx)
    }

    /// `ε̄` on lines `j−1, j, j+1` and `ρ̄` on line `j`, from the current pressure and film,
    /// into `w` (the laws from the cache, re-evaluated where the pressure changed: the same
    /// values [`Self::eps_rho`] gives, bit for bit; `held`: lagged laws, not re-evaluated), at
    /// the points `reach` of the row; NaN elsewhere (the film content: the whole row).
    ///
    /// Why a reach: a meniscus window relaxes a few cells of a row, and each window computed
    /// three whole rows of coefficients, serially. Over the reach only, the seed's contact fed
    /// 25 nm (257², the whole `ehl compare` of the fed model, medians of 5 alternated runs)
    /// took 3.00 s of wall against 3.17 s (CPU 3.77 against 3.82 s), the same answer bit for bit.
    fn line_coefficients(
        prm: &ReynoldsParams,
        held: bool,
        rows: &mut Rows,
        j: usize,
        reach: std::ops::RangeInclusive<usize>,
        w: &mut LineWork,
    ) {
        for (slot, jj) in (j - 1..=j + 1).enumerate() {
            let (laws, p, film) = rows.laws_p_film(jj);
            let eps = &mut w.eps[slot];
            eps.clear();
            eps.resize(p.len(), f64::NAN);
            for i in reach.clone() {
                let c = &mut laws[i];
                if c[0].to_bits() != p[i].to_bits() && !(held && c[0].is_finite()) {
                    *c = laws_at(prm, p[i]);
                }
                eps[i] = Self::eps_of(c[2], film[i], c[1]);
            }
            if jj == j {
                w.dens.clear();
                w.dens.resize(p.len(), f64::NAN);
                for i in reach.clone() {
                    w.dens[i] = laws[i][2];
                }
            }
        }
        w.theta.clear();
        w.theta.extend_from_slice(rows.theta_row(j));
        w.rho.clear();
        w.rho.extend(w.dens.iter().zip(&w.theta).map(|(r, t)| r * t));
    }

    /// `ε̄` averaged to the half points east, west, north, south of `i` (rows `j−1, j, j+1`).
    #[inline]
    fn half_points(&self, eps: [&[f64]; 3], i: usize) -> (f64, f64, f64, f64) {
        let e = eps[1][i];
        // With contact (time steps), a closed gap (`ε̄ = 0`, `H ≤ 0`) passes no oil through its
        // faces: where the solids touch, the pressure is the contact's, and the mean with an
        // open neighbour's `ε̄` would drive a flow out of a closed gap. Open on both sides, or
        // without contact (steady solves, unchanged), the mean.
        let touch = self.touch;
        let half = |n: f64| if touch && (e == 0.0 || n == 0.0) { 0.0 } else { 0.5 * (e + n) };
        (half(eps[1][i + 1]), half(eps[1][i - 1]), half(eps[2][i]), half(eps[0][i]))
    }

    /// The discrete operator `L(P)` at `(i, j)`, given `ε̄` on rows `j−1, j, j+1`, `ρ̄θ` and `θ`
    /// on row `j` (`oil`), and the rows `j−1, j, j+1` of `P` and `j` of `H`: the one place the
    /// discretisation is written.
    #[inline]
    fn op_line(
        &self,
        eps: [&[f64]; 3],
        oil: (&[f64], &[f64]),
        p: [&[f64]; 3],
        film: &[f64],
        i: usize,
        j: usize,
    ) -> f64 {
        if self.contact[[j, i]] {
            // Where the solids touch the equation is the gap's: `H = 0` on the finest grid.
            return film[i];
        }
        let h = self.h;
        let (rho, theta) = oil;
        let (ee, ew, en, es) = self.half_points(eps, i);
        let pc = p[1][i];
        let a = (ee * (p[1][i + 1] - pc) - ew * (pc - p[1][i - 1]) + en * (p[2][i] - pc)
            - es * (pc - p[0][i]))
            / (h * h);
        let rh = |ii: usize| rho[ii] * film[ii];
        let [w0, w1, w2] = self.upwind(theta, i);
        let b = if i >= 2 {
            (w0 * rh(i) + w1 * rh(i - 1) + w2 * rh(i - 2)) / h
        } else {
            (w0 * rh(i) + w1 * rh(i - 1)) / h
        };
        a - self.speed * b - self.time_a0 * rho[i] * film[i] - self.history[[j, i]]
    }

    /// Rows `j−1, j, j+1` of `P` and row `j` of `H`, as [`Self::op_line`] reads them.
    fn rows(&self, j: usize) -> ([&[f64]; 3], &[f64]) {
        (
            [row_of(&self.p, j - 1), row_of(&self.p, j), row_of(&self.p, j + 1)],
            row_of(&self.film, j),
        )
    }

    /// Row `i` of the line Jacobian: `∂L_i/∂δ_ic` for `ic = i−2 … i+2` on the line (zero
    /// outside it), where the change at `ic` is `+δ` there, and `−δ/4` at its neighbours when
    /// `dist[ic − 1]`.
    fn jacobian_row(
        &self,
        eps: [&[f64]; 3],
        rho: &[f64],
        theta: &[f64],
        i: usize,
        lo: usize,
        dist: &[bool],
    ) -> [f64; 5] {
        // The smoother's approximation only (the equations are `op_line`'s): reciprocals of the
        // spacing instead of divisions change its last digits, not the solution.
        let (inv_h, inv_h2) = (1.0 / self.h, 1.0 / (self.h * self.h));
        let m = dist.len();
        let (ee, ew, en, es) = self.half_points(eps, i);
        // Poiseuille stencil coefficients of P at i − 3 … i + 3 (same line) in L_i.
        let pois = [0.0, 0.0, ew * inv_h2, -(ee + ew + en + es) * inv_h2, ee * inv_h2, 0.0, 0.0];
        // Wedge: −∂(ρH)_x/∂δ; the film at the point `back` cells upstream of i changes by
        // K(i − back − ic, 0) (or the distributed kernel).
        let [w0, w1, w2] = self.upwind(theta, i);
        let (r0, r1, r2) = if i >= 2 {
            (w0 * rho[i] * inv_h, w1 * rho[i - 1] * inv_h, w2 * rho[i - 2] * inv_h)
        } else {
            (w0 * rho[i] * inv_h, w1 * rho[i - 1] * inv_h, 0.0)
        };
        let transient = self.time_a0 * rho[i];
        let mut row = [0.0; 5];
        for d in -2i64..=2 {
            let ic = i as i64 + d;
            if ic < lo as i64 || ic >= (lo + m) as i64 {
                continue;
            }
            let dist = dist[ic as usize - lo];
            let c = (d + 3) as usize;
            let (mut a, k) = (pois[c], if dist { &self.kd_line } else { &self.k_line });
            if dist {
                // Neighbours on the line at ic ± 1 each get −1/4; those off the line (ic, j ± 1)
                // enter L_i only when ic = i, through en, es.
                a -= 0.25 * (pois[c - 1] + pois[c + 1]);
                if d == 0 {
                    a -= 0.25 * (en + es) * inv_h2;
                }
            }
            let kk = |back: i64| k[(d + back).unsigned_abs() as usize];
            let w = self.speed * (r0 * kk(0) + r1 * kk(1) + r2 * kk(2));
            row[(d + 2) as usize] = a - w - transient * kk(0);
        }
        row
    }
}

/// A partly filled point's film content `t` when its gap moves from `h0` to `h` [a²/R]: the
/// oil `t h` it holds is kept (where `P = 0`; a full or loaded point, or a closed gap, keeps `t`).
#[inline]
fn keep_oil(t: &mut f64, p: f64, h0: f64, h: f64) {
    if p <= 0.0 && *t < 1.0 && h > 0.0 && h0 > 0.0 {
        *t = (*t * h0 / h).min(1.0);
    }
}

/// The laws' entry at pressure `p` [p_h]: `[P, η̄ λ̄, ρ̄]`.
#[inline]
fn laws_at(prm: &ReynoldsParams, p: f64) -> [f64; 3] {
    [p, prm.viscosity.eta(p) * prm.lambda_bar, prm.density.rho(p)]
}

/// Row `j` of a grid array (standard layout) as a slice.
fn row_of(a: &Array2<f64>, j: usize) -> &[f64] {
    let n = a.ncols();
    &a.as_slice().expect("grid arrays are in standard layout")[j * n..(j + 1) * n]
}

/// Forward elimination (no pivoting) of the pentadiagonal system `band · x = r` (row q holds
/// columns q−2 … q+2), in place, for rows `from` on: rows before `from` must hold their
/// eliminated state already, rows from `from` on their original one.
fn eliminate_banded(band: &mut [[f64; 5]], r: &mut [f64], from: usize) {
    let m = band.len();
    // Lower bandwidth 2, upper bandwidth 2: fill-in stays inside the band. Pivots `from − 2`
    // and `from − 1` still act on rows `from`, `from + 1`.
    for q in from.saturating_sub(2)..m {
        let piv = band[q][2];
        if piv == 0.0 || !piv.is_finite() {
            continue;
        }
        for below in 1..=2 {
            let row = q + below;
            if row >= m {
                break;
            }
            if row < from {
                continue;
            }
            let f = band[row][2 - below] / piv;
            if f == 0.0 {
                continue;
            }
            for col in 0..=2 {
                // column q + col in row q sits at index 2 + col; in row `row` at 2 + col − below.
                let idx = 2 + col - below;
                band[row][idx] -= f * band[q][2 + col];
            }
            r[row] -= f * r[q];
        }
    }
}

/// Back substitution of an eliminated pentadiagonal system into `x`.
fn back_substitute_banded(band: &[[f64; 5]], r: &[f64], x: &mut [f64]) {
    let m = band.len();
    for q in (0..m).rev() {
        let mut s = r[q];
        for col in 1..=2 {
            if q + col < m {
                s -= band[q][2 + col] * x[q + col];
            }
        }
        x[q] = if band[q][2] != 0.0 { s / band[q][2] } else { 0.0 };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{DensityLaw, ViscosityLaw};

    /// The column of `L_i` (row `j`) for a change `+1` at `(ic, j)` (distributed: `−1/4` at its
    /// four neighbours), by finite differences of [`Level::op_line`] with `ε̄`, `ρ̄` frozen (the
    /// line Jacobian's own approximation): the pressures changed and the film of row `j` moved
    /// by the full kernel `K(di, dj)` of every changed point. Central differences of an operator
    /// that is affine in `(P, H)` once the coefficients are frozen: exact to rounding.
    fn fd_column(
        l: &Level,
        prm: &ReynoldsParams,
        i: usize,
        j: usize,
        ic: usize,
        dist: bool,
    ) -> f64 {
        let (eps, rho) = l.coefficients(prm);
        let e = [row_of(&eps, j - 1), row_of(&eps, j), row_of(&eps, j + 1)];
        let r = row_of(&rho, j);
        let mut changes = vec![(ic, j, 1.0)];
        if dist {
            changes.extend([(ic - 1, j, -0.25), (ic + 1, j, -0.25)]);
            changes.extend([(ic, j - 1, -0.25), (ic, j + 1, -0.25)]);
        }
        let nx = l.grid.nx;
        let op_at = |delta: f64| {
            let mut p = l.p.clone();
            let mut film = row_of(&l.film, j).to_vec();
            for &(ii, jj, d) in &changes {
                p[[jj, ii]] += delta * d;
                for (x, f) in film.iter_mut().enumerate() {
                    *f += delta * d * l.k(x as i64 - ii as i64, j as i64 - jj as i64);
                }
            }
            let rows = [row_of(&p, j - 1), row_of(&p, j), row_of(&p, j + 1)];
            assert!(nx > i + 1);
            l.op_line(e, (r, row_of(&l.theta, j)), rows, &film, i, j)
        };
        let delta = 1e-4;
        (op_at(delta) - op_at(-delta)) / (2.0 * delta)
    }

    /// A level of 33² at the M = 20, L = 10 conditions with Hertz's pressure and its film: a
    /// pressurised contact, cavitated beyond it, the wedge strong at the inlet.
    fn hertzian_level() -> (Level, ReynoldsParams) {
        let lub = ehl_core::SEED_LUBRICANT;
        let prm = ReynoldsParams::from_moes(
            &ehl_core::Moes { m: 20.0, l: 10.0 },
            &ehl_core::SEED_CONTACT,
            lub.eta0,
            lub.p0_roelands,
            ViscosityLaw::Roelands,
            DensityLaw::DowsonHigginson,
        );
        let mut l = Level::new(Grid::new(33, 33, (-2.5, 1.5), (-2.0, 2.0)));
        l.p = l.grid.field(|x, y| (1.0 - x * x - y * y).max(0.0).sqrt());
        l.update_film(0.3);
        (l, prm)
    }

    #[test]
    fn the_line_jacobian_is_the_residuals_derivative_on_loaded_cavitated_and_transient_lines() {
        // Every entry of `jacobian_row`, against central differences of `op_line` (what the
        // residual is): on the centre line (loaded, cavitated at the outlet, the inlet where
        // the wedge dominates), for Gauss–Seidel and distributed changes side by side, steady
        // and with a BDF2 time term. Measured agreement: 1.3e-11 of the row's largest entry
        // (rounding: the operator is affine in the changes once ε̄, ρ̄ are frozen); bound 1e-7.
        // Caught (each run by hand): the wedge's upwind weight −2 → −1.9 in `jacobian_row`
        // (7e-6 off at the inlet), the time term 10 % short, a distributed change's off-line
        // neighbours at −0.2 instead of −1/4 (2e-2 off).
        let (mut l, prm) = hertzian_level();
        let j = 16;
        let m = l.grid.nx - 2;
        // Steady at the reference speed; a time step at the reference speed, at half of it,
        // and at rest (a pure squeeze: no wedge term at all).
        for (time_a0, speed) in [(0.0, 1.0), (1.5 / 0.05, 1.0), (1.5 / 0.05, 0.5), (30.0, 0.0)] {
            l.time_a0 = time_a0;
            l.speed = speed;
            let (eps, rho) = l.coefficients(&prm);
            let e = [row_of(&eps, j - 1), row_of(&eps, j), row_of(&eps, j + 1)];
            let r = row_of(&rho, j);
            // Alternate the relaxation kinds so each entry meets both.
            let dist: Vec<bool> = (0..m).map(|q| q % 3 == 1).collect();
            // Inlet (x ≈ −2.4, −1.5), loaded (x ≈ −0.5, 0, 0.5), cavitated (x ≈ 1.2).
            for i in [2, 9, 16, 20, 24, 29] {
                let row = l.jacobian_row(e, r, row_of(&l.theta, j), i, 1, &dist);
                let scale = row.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                for d in -2i64..=2 {
                    let ic = i as i64 + d;
                    if ic < 1 || ic > m as i64 {
                        continue;
                    }
                    let ic = ic as usize;
                    let fd = fd_column(&l, &prm, i, j, ic, dist[ic - 1]);
                    let got = row[(d + 2) as usize];
                    assert!(
                        (got - fd).abs() <= 1e-7 * scale,
                        "a0 = {time_a0}, speed {speed}, i = {i}, column {ic} (dist {}): Jacobian {got:.9e}, finite difference {fd:.9e}",
                        dist[ic - 1]
                    );
                }
            }
        }
        // The lines checked hold each kind of point.
        assert!(l.p[[j, 29]] == 0.0 && l.p[[j, 16]] > 0.5 && l.p[[j, 2]] == 0.0);
    }

    #[test]
    fn held_laws_reach_the_points_own_once_the_pressure_stops() {
        // Lagged laws follow θ of the remaining change each sweep: from laws held at P = 0.5,
        // with the pressure fixed at Hertz's, they close the gap geometrically (0.8^k) and snap
        // to the point's own laws bit for bit once within 1e-12 (after ~125 sweeps), so that a
        // converged state's laws are its own. Without the snap they stall an ulp or so away.
        let prm = ReynoldsParams::from_si(
            &ehl_core::SEED_CONTACT,
            &ehl_core::SEED_LUBRICANT,
            0.02,
            ViscosityLaw::Roelands,
            DensityLaw::DowsonHigginson,
        );
        let mut l = Level::new(Grid::square(9, 1.5));
        l.p = l.grid.field(ehl_core::hertz::pressure);
        l.set_coefficient_pressures(&prm, &l.grid.field(|_, _| 0.5));
        l.follow_laws(&prm, 0.2);
        let off = Zip::from(&l.laws).and(&l.p).fold(0usize, |n, c, &p| n + (c[0] != p) as usize);
        assert!(off > 0, "one sweep must leave the laws lagging");
        for _ in 0..200 {
            l.follow_laws(&prm, 0.2);
        }
        for (c, &p) in l.laws.iter().zip(&l.p) {
            assert_eq!(c, &laws_at(&prm, p), "laws held at {} for P = {p}", c[0]);
        }
    }

    #[test]
    fn cached_laws_equal_fresh_ones_after_changes_and_under_new_laws() {
        // The cache must give Self::eps_rho's values bit for bit: after pressures change, and
        // when the same level is used with other laws (no stale η̄ from the first).
        let c = ehl_core::SEED_CONTACT;
        let lub = ehl_core::SEED_LUBRICANT;
        let roelands = ReynoldsParams::from_si(
            &c,
            &lub,
            0.02,
            ViscosityLaw::Roelands,
            DensityLaw::DowsonHigginson,
        );
        let barus = ReynoldsParams::from_si(
            &c,
            &lub,
            0.02,
            ViscosityLaw::Barus,
            DensityLaw::Incompressible,
        );
        let mut l = Level::new(Grid::square(17, 1.5));
        l.p = l.grid.field(ehl_core::hertz::pressure);
        l.film = l.grid.field(|x, y| 0.3 + 0.1 * x * x + 0.05 * y);
        let fresh = |l: &Level, prm: &ReynoldsParams, j: usize| -> (Vec<f64>, Vec<f64>) {
            (0..17).map(|i| Level::eps_rho(prm, l.p[[j, i]], l.film[[j, i]])).unzip()
        };
        let mut w = LineWork::default();
        let coefficients = |l: &mut Level, prm: &ReynoldsParams, j: usize, w: &mut LineWork| {
            l.laws_for(prm);
            let mut rows = Rows::whole(&mut l.p, &mut l.film, &mut l.laws, &mut l.theta);
            Level::line_coefficients(prm, false, &mut rows, j, 0..=16, w);
        };
        coefficients(&mut l, &roelands, 8, &mut w);
        assert_eq!((w.eps[1].clone(), w.rho.clone()), fresh(&l, &roelands, 8));
        l.p[[8, 5]] *= 1.5;
        l.p[[9, 6]] = 0.0;
        coefficients(&mut l, &roelands, 8, &mut w);
        assert_eq!((w.eps[1].clone(), w.rho.clone()), fresh(&l, &roelands, 8));
        assert_eq!(w.eps[2], fresh(&l, &roelands, 9).0);
        coefficients(&mut l, &barus, 8, &mut w);
        assert_eq!((w.eps[1].clone(), w.rho.clone()), fresh(&l, &barus, 8));
        // A window's reach: the same values there, bit for bit, after a change inside it, and
        // NaN outside it, so that an equation or Jacobian reading past the reach shows.
        l.p[[8, 6]] *= 0.5;
        l.p[[7, 5]] *= 1.2;
        l.laws_for(&barus);
        let mut rows = Rows::whole(&mut l.p, &mut l.film, &mut l.laws, &mut l.theta);
        Level::line_coefficients(&barus, false, &mut rows, 8, 4..=9, &mut w);
        let (eps, rho) = fresh(&l, &barus, 8);
        let eps_below = fresh(&l, &barus, 7).0;
        for i in 0..17 {
            if (4..=9).contains(&i) {
                assert_eq!((w.eps[1][i], w.rho[i], w.eps[0][i]), (eps[i], rho[i], eps_below[i]));
            } else {
                assert!(w.eps[1][i].is_nan() && w.rho[i].is_nan() && w.eps[2][i].is_nan(), "{i}");
            }
        }
    }

    #[test]
    fn a_sweep_gives_the_same_pressures_on_one_thread_and_two() {
        // The two halves of a sweep read only their own rows and a frozen copy of the centre
        // row, so running them on one thread or two must give the same numbers, bit for bit.
        let prm = ReynoldsParams::from_si(
            &ehl_core::SEED_CONTACT,
            &ehl_core::SEED_LUBRICANT,
            0.05,
            ViscosityLaw::Roelands,
            DensityLaw::DowsonHigginson,
        );
        let sweep = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut l = Level::new(Grid::new(33, 33, (-2.5, 1.5), (-2.0, 2.0)));
                l.p = l.grid.field(ehl_core::hertz::pressure);
                l.update_film(-0.4);
                let before = l.p.clone();
                for _ in 0..3 {
                    l.relax(&prm, -0.4, &RelaxSettings::default());
                }
                (before, l.p)
            })
        };
        let ((start, one), (_, two)) = (sweep(1), sweep(2));
        assert!(one != start, "the sweeps changed nothing");
        assert_eq!(one, two);
    }

    #[test]
    fn the_couette_faces_conserve_the_oil_whichever_order_each_takes() {
        // A row of film contents alternating full and partly filled runs, and a flux `q` that
        // varies: the Couette terms of points 2 … n−2 must sum to the last face's flux less the
        // first's (the interior faces cancel), with each face first order (`q_i`) where it reads
        // a partly filled point and second order (`(3q_i − q_(i−1))/2`) elsewhere, on a coarser
        // grid; second order everywhere on one that holds `θ`. A point-by-point switch of the
        // stencil (the first version tried) leaves the interior faces uncancelled: measured
        // 0.14 here, against a flux of about 1; the bound is rounding.
        let mut l = Level::new(Grid::new(33, 33, (-1.25, 1.25), (-1.25, 1.25)));
        let n = 33;
        let theta: Vec<f64> =
            (0..n).map(|i| if (i / 4) % 2 == 0 { 1.0 } else { 0.3 + 0.01 * i as f64 }).collect();
        let q: Vec<f64> = (0..n).map(|i| 1.0 + 0.5 * (0.7 * i as f64).sin()).collect();
        for first_order in [true, false] {
            l.first_order_partial = first_order;
            let face = |i: usize| {
                let partly = theta[i] < 1.0 || theta[i - 1] < 1.0;
                if first_order && partly { q[i] } else { 0.5 * (3.0 * q[i] - q[i - 1]) }
            };
            let sum: f64 = (2..n - 1)
                .map(|i| {
                    let w = l.upwind(&theta, i);
                    w[0] * q[i] + w[1] * q[i - 1] + w[2] * q[i - 2]
                })
                .sum();
            let ends = face(n - 2) - face(1);
            assert!((sum - ends).abs() < 1e-12, "{first_order}: {sum} against {ends}");
        }
    }

    #[test]
    fn banded_solver_matches_dense() {
        let m = 7;
        let mut band = vec![[0.0; 5]; m];
        let mut dense = vec![vec![0.0; m]; m];
        for q in 0..m {
            for d in -2i64..=2 {
                let c = q as i64 + d;
                if c >= 0 && c < m as i64 {
                    let v = if d == 0 {
                        6.0 + q as f64
                    } else {
                        1.0 / (1.0 + (d * d) as f64 + q as f64)
                    };
                    band[q][(d + 2) as usize] = v;
                    dense[q][c as usize] = v;
                }
            }
        }
        let x_true: Vec<f64> = (0..m).map(|k| (k as f64).sin() + 1.0).collect();
        let r: Vec<f64> = (0..m).map(|q| (0..m).map(|c| dense[q][c] * x_true[c]).sum()).collect();
        let original = band.clone();
        let (mut r, mut x) = (r, vec![0.0; m]);
        eliminate_banded(&mut band, &mut r, 0);
        back_substitute_banded(&band, &r, &mut x);
        // Rows from 4 on replaced (row 4 by the identity, as a fixed point's) and the
        // elimination resumed there: the same numbers as eliminating the new system afresh.
        let mut changed = original.clone();
        changed[4] = [0.0, 0.0, 1.0, 0.0, 0.0];
        let r2: Vec<f64> = (0..m).map(|q| if q == 4 { -0.5 } else { q as f64 + 1.0 }).collect();
        let (mut fresh, mut fresh_r) = (changed.clone(), r2.clone());
        eliminate_banded(&mut fresh, &mut fresh_r, 0);
        let mut resumed = original.clone();
        let mut resumed_r: Vec<f64> = (0..m).map(|q| q as f64 + 1.0).collect();
        eliminate_banded(&mut resumed, &mut resumed_r, 0);
        resumed[4..].copy_from_slice(&changed[4..]);
        resumed_r[4..].copy_from_slice(&r2[4..]);
        eliminate_banded(&mut resumed, &mut resumed_r, 4);
        assert_eq!((resumed, resumed_r), (fresh, fresh_r));
        for k in 0..m {
            assert!((x[k] - x_true[k]).abs() < 1e-12);
        }
    }

    #[test]
    fn a_flooded_answer_loses_its_pressure_where_the_gap_is_wider_than_the_supply() {
        // A flooded inlet carries pressure from the inflow boundary on; fed a layer `s`, the
        // oil is only where the gap has narrowed to it. Catches a start that keeps the flooded
        // inlet full (the first fed cycle diverged at the inflow corner) or that empties the
        // loaded zone as well.
        let mut l = Level::new(Grid::square(33, 1.5));
        let s = 0.05;
        l.set_supply(Some(vec![s; 33]));
        l.p = l.grid.field(|x, y| ehl_core::hertz::pressure(x, y) + 1e-3 * (1.5 - x.abs()));
        l.film = l.grid.field(|x, y| 0.01 + 0.5 * (x * x + y * y - 1.0).max(0.0));
        let (p0, film) = (l.p.clone(), l.film.clone());
        l.start_theta_from_flooded();
        for j in 0..33 {
            let meniscus = (0..33).find(|&i| film[[j, i]] <= s).unwrap_or(33);
            for i in 0..33 {
                let (p, t, h) = (l.p[[j, i]], l.theta[[j, i]], film[[j, i]]);
                if i < meniscus {
                    assert_eq!(p, 0.0, "row {j}, point {i} upstream of the meniscus keeps P");
                    // The layer arrives as supplied: θ H = s.
                    assert!((t * h - s).abs() < 1e-12 * s, "row {j}, point {i}: θ H = {}", t * h);
                } else {
                    assert_eq!(p, p0[[j, i]], "row {j}, point {i} downstream changed P");
                }
            }
        }
        // The centre row's meniscus is inside the inlet, not at its boundary nor the contact.
        let m = (0..33).find(|&i| film[[16, i]] <= s).unwrap();
        assert!(l.grid.x(m) > -1.5 && l.grid.x(m) < -1.0, "meniscus at x = {}", l.grid.x(m));
    }
}
