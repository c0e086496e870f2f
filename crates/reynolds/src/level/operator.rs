//! The discrete operator, written once: the coefficients, the residual, the line's
//! equations and their Jacobian.

use super::*;

impl Level {
    /// `(ε̄, ρ̄)` at pressure `p` and film `h`: `ε̄ = ρ̄ H³ / (η̄ λ̄)` with `H ≥ 0`.
    #[inline]
    pub(super) fn eps_rho(prm: &ReynoldsParams, p: f64, h: f64) -> (f64, f64) {
        let rho = prm.density.rho(p);
        (Self::eps_of(rho, h, prm.viscosity.eta(p) * prm.lambda_bar), rho)
    }

    /// `ε̄ = ρ̄ H³ / (η̄ λ̄)` with `H ≥ 0`, from `ρ̄` and the product `η̄ λ̄`.
    #[inline]
    pub(super) fn eps_of(rho: f64, h: f64, eta_lambda: f64) -> f64 {
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
    pub(super) fn map_operator(
        &self,
        prm: &ReynoldsParams,
        g: impl Fn(usize, usize, f64) -> f64 + Sync,
    ) -> Array2<f64> {
        self.map_equations(prm, false, g)
    }

    /// [`Self::map_operator`]; `open`: Reynolds' operator at touching points too
    /// ([`Self::op_reynolds`]), not the gap's equation.
    fn map_equations(
        &self,
        prm: &ReynoldsParams,
        open: bool,
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
                let l = if open {
                    self.op_reynolds(e, (r, t), p, film, i, j)
                } else {
                    self.op_line(e, (r, t), p, film, i, j)
                };
                row[i] = g(j, i, l);
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
    pub(super) fn residual_with_contact(&self, prm: &ReynoldsParams) -> Array2<f64> {
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
    pub(super) fn update_contact(&mut self) {
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

    /// Where the supplied oil goes, per unit time [a²/R · a · u_ref/a, in flux units of the
    /// equations: the supply's flux is `speed Σ H_oil h`]; `None` without a supply (the flooded
    /// clamp makes and destroys oil where it cavitates) or with none to share out (a supply of
    /// no oil).
    ///
    /// The contact's intake is Reynolds' operator at the touching points
    /// (`op_reynolds`): their faces are shut, so it is the oil the faces bring to the
    /// closed gap and, in a step, what the gap held before it closed. The discrete equations
    /// destroy that oil (a point in contact has the gap's equation, not the oil's), so it is the
    /// contact edge's discretisation error on the oil, falling as the grid resolves the gap
    /// closing (docs/reynolds.md, "Where the oil goes").
    pub fn oil_balance(&self, prm: &ReynoldsParams) -> Option<OilBalance> {
        let supply = self.supply.as_ref()?;
        let (ny, nx) = self.p.dim();
        let (h, h2) = (self.h, self.h * self.h);
        let rows = 1..ny - 1;
        let reference_supply = supply[rows.clone()].iter().sum::<f64>() * h;
        if reference_supply <= 0.0 {
            return None;
        }
        let supplied = self.speed * reference_supply;
        let (eps, rho_theta) = self.coefficients(prm);
        // The surfaces carry out what the last interior face passes, the face its point's
        // equation has.
        let q = |j: usize, i: usize| {
            if self.shut(j, i) { 0.0 } else { rho_theta[[j, i]] * self.film[[j, i]] }
        };
        let last = nx - 2;
        let carried_out = self.speed
            * rows.clone().map(|j| self.face_flux(|i| q(j, i), j, last)).sum::<f64>()
            * h;
        // The pressure pushes oil out through the edges' faces, `ε̄ (P − 0)/h` over a face `h`
        // long (none where the pressure beside the edge is 0).
        let mut pressed_out = 0.0;
        for j in rows.clone() {
            let e = [row_of(&eps, j - 1), row_of(&eps, j), row_of(&eps, j + 1)];
            for i in 1..nx - 1 {
                if !(j == 1 || j == ny - 2 || i == 1 || i == last) {
                    continue;
                }
                let (ee, ew, en, es) = self.half_points(e, j, i);
                let pc = self.p[[j, i]];
                let face = |c: f64, edge: bool| if edge { c * pc } else { 0.0 };
                pressed_out += face(ee, i == last)
                    + face(ew, i == 1)
                    + face(en, j == ny - 2)
                    + face(es, j == 1);
            }
        }
        // Reynolds' operator everywhere, touching points included, in one pass: at a touching
        // point what it takes, elsewhere the residual (`f − L`) the equations leave.
        let l = self.map_equations(prm, true, |_, _, l| l);
        let (mut into_contact, mut unaccounted, mut stored) = (0.0, 0.0, 0.0);
        for j in rows {
            for i in 1..nx - 1 {
                if self.shut(j, i) {
                    into_contact += l[[j, i]];
                } else {
                    unaccounted -= self.rhs[[j, i]] - l[[j, i]];
                    // The oil stored in the open gap grows at `∂(ρ̄θH)/∂T` there.
                    stored +=
                        self.time_a0 * rho_theta[[j, i]] * self.film[[j, i]] + self.history[[j, i]];
                }
            }
        }
        let (into_contact, unaccounted, stored) =
            (into_contact * h2, unaccounted * h2, stored * h2);
        Some(OilBalance {
            supplied,
            reference_supply,
            carried_out,
            pressed_out,
            into_contact,
            stored,
            unaccounted,
        })
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

    /// Points per side `(ny, nx)` (the pressure array may be lent out during a sweep).
    pub(super) fn p_dim(&self) -> (usize, usize) {
        (self.grid.ny, self.grid.nx)
    }

    /// `ε̄` on lines `j−1, j, j+1` and `ρ̄` on line `j`, from the current pressure and film,
    /// into `w` (the laws from the cache, re-evaluated where the pressure changed: the same
    /// values [`Self::eps_rho`] gives, bit for bit; `held`: lagged laws, not re-evaluated), at
    /// the points `reach` of the row; NaN elsewhere (the film content: the whole row).
    ///
    /// Why a reach: a meniscus window relaxes a few cells of a row, and computing three whole
    /// rows of coefficients for each window, serially, cost a few per cent of a fed solve.
    pub(super) fn line_coefficients(
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

    /// Whether the solids touch at `(i, j)` (with contact on).
    #[inline]
    pub(super) fn shut(&self, j: usize, i: usize) -> bool {
        self.touch && self.contact[[j, i]]
    }

    /// `ε̄` averaged to the half points east, west, north, south of `(i, j)` (rows `j−1, j,
    /// j+1`).
    #[inline]
    pub(super) fn half_points(&self, eps: [&[f64]; 3], j: usize, i: usize) -> (f64, f64, f64, f64) {
        let e = eps[1][i];
        // With contact, a closed gap (`ε̄ = 0`, `H ≤ 0`) or a point where the solids touch
        // passes no oil through its faces: the pressure there is the contact's, and the mean
        // with an open neighbour's `ε̄` would drive a flow through a shut gap (a gap held at
        // `H = 0` from above has a tiny `ε̄`, not none, and lost oil: docs/decisions.md, "The
        // solids touching in the steady cycles"). Open on both sides, or without contact, the
        // mean.
        let touch = self.touch;
        let shut = |jj: usize, ii: usize| touch && self.contact[[jj, ii]];
        let here = shut(j, i);
        let half = |n: f64, jj: usize, ii: usize| {
            if touch && (e == 0.0 || n == 0.0 || here || shut(jj, ii)) {
                0.0
            } else {
                0.5 * (e + n)
            }
        };
        (
            half(eps[1][i + 1], j, i + 1),
            half(eps[1][i - 1], j, i - 1),
            half(eps[2][i], j + 1, i),
            half(eps[0][i], j - 1, i),
        )
    }

    /// The discrete operator `L(P)` at `(i, j)`, given `ε̄` on rows `j−1, j, j+1`, `ρ̄θ` and `θ`
    /// on row `j` (`oil`), and the rows `j−1, j, j+1` of `P` and `j` of `H`: the one place the
    /// discretisation is written.
    #[inline]
    pub(super) fn op_line(
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
        self.op_reynolds(eps, oil, p, film, i, j)
    }

    /// Reynolds' operator at `(i, j)` whether or not the solids touch there ([`Self::op_line`]
    /// away from the contact). At a touching point its faces are shut and its own film content
    /// sends nothing on, so what is left is the oil the faces bring in from upstream and, in a
    /// step, what the gap held before it closed: the oil the contact takes
    /// ([`Self::oil_balance`]).
    #[inline]
    pub(super) fn op_reynolds(
        &self,
        eps: [&[f64]; 3],
        oil: (&[f64], &[f64]),
        p: [&[f64]; 3],
        film: &[f64],
        i: usize,
        j: usize,
    ) -> f64 {
        let h = self.h;
        let (rho, theta) = oil;
        let (ee, ew, en, es) = self.half_points(eps, j, i);
        let pc = p[1][i];
        let a = (ee * (p[1][i + 1] - pc) - ew * (pc - p[1][i - 1]) + en * (p[2][i] - pc)
            - es * (pc - p[0][i]))
            / (h * h);
        // A shut gap sends no oil downstream: its film is the gap equation's residual, not a
        // film, and read as one it made oil at the contact's trailing edge.
        let rh = |ii: usize| if self.shut(j, ii) { 0.0 } else { rho[ii] * film[ii] };
        let [w0, w1, w2] = self.upwind(theta, j, i);
        let b = if i >= 2 {
            (w0 * rh(i) + w1 * rh(i - 1) + w2 * rh(i - 2)) / h
        } else {
            (w0 * rh(i) + w1 * rh(i - 1)) / h
        };
        a - self.speed * b - self.time_a0 * rho[i] * film[i] - self.history[[j, i]]
    }

    /// Rows `j−1, j, j+1` of `P` and row `j` of `H`, as [`Self::op_line`] reads them.
    pub(super) fn rows(&self, j: usize) -> ([&[f64]; 3], &[f64]) {
        (
            [row_of(&self.p, j - 1), row_of(&self.p, j), row_of(&self.p, j + 1)],
            row_of(&self.film, j),
        )
    }

    /// Row `i` of line `j`'s Jacobian: `∂L_i/∂δ_ic` for `ic = i−2 … i+2` on the line (zero
    /// outside it), where the change at `ic` is `+δ` there, and `−δ/4` at its neighbours when
    /// `dist[ic − 1]`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn jacobian_row(
        &self,
        eps: [&[f64]; 3],
        rho: &[f64],
        theta: &[f64],
        (j, i): (usize, usize),
        lo: usize,
        dist: &[bool],
    ) -> [f64; 5] {
        // The smoother's approximation only (the equations are `op_line`'s): reciprocals of the
        // spacing instead of divisions change its last digits, not the solution.
        let (inv_h, inv_h2) = (1.0 / self.h, 1.0 / (self.h * self.h));
        let m = dist.len();
        let (ee, ew, en, es) = self.half_points(eps, j, i);
        // Poiseuille stencil coefficients of P at i − 3 … i + 3 (same line) in L_i.
        let pois = [0.0, 0.0, ew * inv_h2, -(ee + ew + en + es) * inv_h2, ee * inv_h2, 0.0, 0.0];
        // Wedge: −∂(ρH)_x/∂δ; the film at the point `back` cells upstream of i changes by
        // K(i − back − ic, 0) (or the distributed kernel).
        let [w0, w1, w2] = self.upwind(theta, j, i);
        let sent = |k: usize| if self.shut(j, k) { 0.0 } else { rho[k] * inv_h };
        let (r0, r1, r2) = if i >= 2 {
            (w0 * sent(i), w1 * sent(i - 1), w2 * sent(i - 2))
        } else {
            (w0 * sent(i), w1 * sent(i - 1), 0.0)
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
