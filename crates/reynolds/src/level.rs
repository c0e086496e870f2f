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
use serde::Serialize;

mod laws;
mod operator;
mod relax;
mod rows;
mod smoother;
use laws::laws_at;
pub use relax::{RelaxSettings, TRANSIENT_THRESHOLDS};
use rows::{ColumnHalf, Ghost, Lent, Line, LineWork, Rows, split_rows};

/// Pressure [p_h] below which a point counts as cavitated.
pub const CAVITATION_FLOOR: f64 = 1e-10;

/// Where a mass-conserving answer's oil goes, per unit time, in the equations' flux units
/// ([`Level::oil_balance`]): `supplied = carried_out + pressed_out + into_contact + stored +
/// unaccounted`, to rounding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OilBalance {
    /// The supply's flux through the inflow face.
    pub supplied: f64,
    /// The supply's flux at the reference speed (`speed` 1): what a step's flows are shares
    /// of, at rest too.
    pub reference_supply: f64,
    /// What the surfaces carry out across the outlet column.
    pub carried_out: f64,
    /// What the pressure pushes out through the domain's edges (0 where it is 0 beside them).
    pub pressed_out: f64,
    /// What the touching points take: the oil arriving at the closed gap, and in a step what
    /// it held before it closed (the discrete equations destroy it).
    pub into_contact: f64,
    /// The growth of the oil held in the open gap (0 in a steady answer).
    pub stored: f64,
    /// What the equations leave unmet (`−Σ r h²`: 0 at convergence).
    pub unaccounted: f64,
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
    /// Whether the Couette face *into* a point where the solids touch is first order as well
    /// (the face behind one always is): set by the start from the dry contact, where the oil
    /// that reaches the contact's rim is a film thinner than the grid resolves (`upwind` says
    /// why).
    pub first_order_into_contact: bool,
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
            first_order_into_contact: false,
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

    /// Rigid film `X²/2 + Y²/2 + extra` [a²/R] (a dent, a bump, a relief, or nothing), the
    /// extra gap given on this level's points.
    pub fn set_extra_gap_field(&mut self, extra: &Array2<f64>) {
        self.shape = self.grid.paraboloid() + extra;
    }

    /// The rigid film `X²/2 + Y²/2 + extra` [a²/R] (the gap at `H00 = 0` without deformation).
    pub fn rigid_film(&self) -> &Array2<f64> {
        &self.shape
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
        self.start_theta_where(&|_| true);
    }

    /// [`Self::start_theta`] at the points `fresh` selects only, the others kept.
    pub fn start_theta_where(&mut self, fresh: &dyn Fn((usize, usize)) -> bool) {
        let supply = self.supply.as_ref();
        for (ji, t) in self.theta.indexed_iter_mut().filter(|(ji, _)| fresh(*ji)) {
            let h = self.film[ji];
            *t = match supply {
                Some(s) if self.p[ji] <= 0.0 && h > s[ji.0] => s[ji.0] / h,
                _ => 1.0,
            };
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
    /// thin supply (`q_0 = H_oil ≪ q_1`) a source of oil, several times the supply carried
    /// through a starved contact. Mass conserving, the inflow face
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
    /// and the second-order flux over a jump in `θ` (a meniscus, the edges of the side bands)
    /// over- and undershoots, so that the relaxation clamps `θ` at 0 and 1 in turn and a coarse
    /// grid's corrections wreck the fine film. A face that reads a point where the solids touch
    /// is first order on every grid: the shut gap passes no oil, and the second-order face
    /// behind it (`−q/2` of the point before) would draw oil out of it. From the dry contact
    /// ([`Self::first_order_into_contact`]) the face into a touching point is first order too:
    /// its `−q/2` of the point two before draws oil back out of the contact's rim, the rim's full
    /// point at `P = 0` takes more oil than it passes on, and the cycles stall at vanishing
    /// speed. What each choice
    /// measured, and the faces set aside: `docs/decisions.md`, "First-order faces on the finest
    /// grid", "Limited Couette faces" and "Passes around the menisci".
    #[inline]
    fn upwind(&self, theta: &[f64], j: usize, i: usize) -> [f64; 3] {
        if i < 2 {
            let w = self.first_weight();
            return [w, -w, 0.0];
        }
        let near_contact = self.shut(j, i)
            || self.shut(j, i - 1)
            || self.shut(j, i - 2)
            || self.face_into_contact(j, i + 1);
        if !self.first_order_partial && !near_contact {
            return [1.5, -2.0, 0.5];
        }
        let (east, west) =
            (self.first_order_face(theta, j, i), self.first_order_face(theta, j, i - 1));
        let w0 = if east { 1.0 } else { 1.5 };
        let w1 = (if east { 0.0 } else { -0.5 }) - (if west { 1.0 } else { 1.5 });
        let w2 = if west { 0.0 } else { 0.5 };
        [w0, w1, w2]
    }

    /// Whether the Couette face `F(i+½)` (between points `i` and `i + 1`, read from `i` and
    /// `i − 1`) is first order, `q_i`, rather than second order, `(3q_i − q_(i−1))/2`: where
    /// either point it reads is shut, or partly filled on a grid that solves for the film content
    /// with first-order faces ([`Self::upwind`] says why).
    #[inline]
    fn first_order_face(&self, theta: &[f64], j: usize, i: usize) -> bool {
        let partly = |k: usize| (self.first_order_partial && theta[k] < 1.0) || self.shut(j, k);
        partly(i) || partly(i - 1) || self.face_into_contact(j, i + 1)
    }

    /// Whether a face into point `(i, j)` is first order because the solids touch there
    /// ([`Self::first_order_into_contact`]).
    #[inline]
    fn face_into_contact(&self, j: usize, i: usize) -> bool {
        self.first_order_into_contact && i < self.contact.ncols() && self.shut(j, i)
    }

    /// The Couette face flux `F(i+½)` on row `j` of the film contents `q` (the face
    /// [`Self::upwind`]'s weights difference), `i ≥ 1`.
    pub(super) fn face_flux(&self, q: impl Fn(usize) -> f64, j: usize, i: usize) -> f64 {
        let theta = row_of(&self.theta, j);
        if self.first_order_face(theta, j, i) { q(i) } else { 1.5 * q(i) - 0.5 * q(i - 1) }
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
}

/// A partly filled point's film content `t` when its gap moves from `h0` to `h` [a²/R]: the
/// oil `t h` it holds is kept (where `P = 0`; a full or loaded point, or a closed gap, keeps `t`).
#[inline]
fn keep_oil(t: &mut f64, p: f64, h0: f64, h: f64) {
    if p <= 0.0 && *t < 1.0 && h > 0.0 && h0 > 0.0 {
        *t = (*t * h0 / h).min(1.0);
    }
}

/// Row `j` of a grid array (standard layout) as a slice.
fn row_of(a: &Array2<f64>, j: usize) -> &[f64] {
    let n = a.ncols();
    &a.as_slice().expect("grid arrays are in standard layout")[j * n..(j + 1) * n]
}

#[cfg(test)]
mod tests {
    use super::smoother::{back_substitute_banded, eliminate_banded};
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
                let row = l.jacobian_row(e, r, row_of(&l.theta, j), (j, i), 1, &dist);
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
        let theta_full = vec![1.0; n];
        // The same with the solids touching at a few points of the row: the faces that read
        // one are first order too, on every grid.
        let j = 16;
        let shut = |i: usize| (9..12).contains(&i) || i == 20;
        // From the dry contact the faces into a touching point are first order as well.
        let cases = [
            (true, false, false),
            (false, false, false),
            (false, true, false),
            (false, true, true),
        ];
        for (first_order, touching, into) in cases {
            l.first_order_partial = first_order;
            l.touch = touching;
            l.first_order_into_contact = into;
            for i in 0..n {
                l.contact[[j, i]] = touching && shut(i);
            }
            let face = |i: usize| {
                let partly = theta[i] < 1.0 || theta[i - 1] < 1.0;
                let closed = touching && (shut(i) || shut(i - 1) || into && shut(i + 1));
                if first_order && partly || closed { q[i] } else { 0.5 * (3.0 * q[i] - q[i - 1]) }
            };
            let sum: f64 = (2..n - 1)
                .map(|i| {
                    let w = l.upwind(&theta, j, i);
                    w[0] * q[i] + w[1] * q[i - 1] + w[2] * q[i - 2]
                })
                .sum();
            let ends = face(n - 2) - face(1);
            assert!((sum - ends).abs() < 1e-12, "{first_order}: {sum} against {ends}");
            // The point before a touching one (8, before 9): its east face is the one into the
            // contact, its west face second order.
            let w = l.upwind(&theta_full, j, 8);
            let east = if into { [1.0, 0.0, 0.0] } else { [1.5, -0.5, 0.0] };
            assert_eq!(w, [east[0], east[1] - 1.5, 0.5], "into the contact: {into}");
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
