//! The relaxation: the line sweeps, the column pass and the meniscus windows of the
//! cavitation, and the banded solve of a line.

use super::*;

/// A column-pass point's kind: its pressure the unknown …
const FULL: u8 = 0;
/// … its film content (`P = 0`, the gap partly filled) …
const PARTIAL: u8 = 1;
/// … or neither (touching, or loaded where its change distributes: left to the row pass).
const HELD: u8 = 2;

/// `film[ii] += d K(|ii − i|)` for the points within `NEAR` cells of `i` on a row, `krow` the
/// kernel's row at the change's distance across the rows: the near-field film change of a
/// pressure change `d` at `i` that the lines relaxed after it see at once (the full film is
/// recomputed by FFT after a sweep). Within 8 cells the kernel carries what the line
/// Jacobian needs; beyond, the change is smooth and small.
fn add_near_field(film: &mut [f64], krow: &[f64], i: usize, d: f64) {
    const NEAR: usize = 8;
    let (lo, hi) = (i.saturating_sub(NEAR), (i + NEAR).min(film.len() - 1));
    // Two slices (upstream, the kernel read backwards; from `i` on, forwards): the same sums,
    // bit for bit, vectorised and without an index check per point. Measured over the seed's
    // dent passage (257²): this loop held ~30 % of the line relaxation's samples, and the
    // relaxation's share of the run fell from 44 % to 40 % (steps ~3 % faster).
    for (f, &k) in film[lo..i].iter_mut().zip(krow[1..=i - lo].iter().rev()) {
        *f += d * k;
    }
    for (f, &k) in film[i..=hi].iter_mut().zip(&krow[..=hi - i]) {
        *f += d * k;
    }
}

/// Forward elimination (no pivoting) of the pentadiagonal system `band · x = r` (row q holds
/// columns q−2 … q+2), in place, for rows `from` on: rows before `from` must hold their
/// eliminated state already, rows from `from` on their original one.
pub(super) fn eliminate_banded(band: &mut [[f64; 5]], r: &mut [f64], from: usize) {
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
pub(super) fn back_substitute_banded(band: &[[f64; 5]], r: &[f64], x: &mut [f64]) {
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

impl Level {
    /// One sweep of line relaxation over all lines, then the film recomputed.
    ///
    /// Order: the centre line first, then outward in both directions at once (the sweep is
    /// symmetric, as the contact is, and the two halves run on two threads; the result does not
    /// depend on the number of threads). Each line sees at once the pressure changes of the
    /// lines relaxed before it in its own half and their near-field film change.
    pub fn relax(&mut self, prm: &ReynoldsParams, h00: f64, s: &RelaxSettings) {
        self.update_contact();
        self.laws_for(prm);
        self.lagged = s.coefficient_lag > 0.0;
        self.sweep_halves(|this, rows, j, next, w| {
            this.relax_line(prm, s, rows, Line::whole(j, next), w);
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

    /// Relaxes every interior row through `row(level, rows, j, next, work)`: the centre row
    /// first, then outward in both directions at once (rows above the centre upward, rows below
    /// downward, on two threads; `next` is the row relaxed after `j` in its half). The first row
    /// below the centre reads the centre row as it was when the halves began (the ghost); the
    /// pressure changes it makes there are added when both halves are done. The result does not
    /// depend on the number of threads.
    pub(super) fn sweep_halves(
        &mut self,
        row: impl Fn(&Self, &mut Rows, usize, &[usize], &mut LineWork) + Sync,
    ) {
        let (ny, nx) = self.p_dim();
        self.lend(|this, lent| {
            let Lent { p, film, laws, theta, work } = lent;
            let mut whole = Rows::whole(p, film, laws, theta);
            let mid = ny / 2;
            row(this, &mut whole, mid, &[mid - 1, mid + 1], &mut work[0]);
            // The lower half keeps a frozen copy of the centre row; its changes there wait.
            let ghost = Ghost {
                j: mid,
                p: whole.p_row(mid).to_vec(),
                film: whole.film_row(mid).to_vec(),
                laws: whole.laws[mid * nx..(mid + 1) * nx].to_vec(),
                theta: whole.theta_row(mid).to_vec(),
                deferred: Vec::new(),
            };
            let (p_lo, p_hi) = split_rows(p, mid);
            let (f_lo, f_hi) = split_rows(film, mid);
            let (l_lo, l_hi) = split_rows(laws, mid);
            let (t_lo, t_hi) = split_rows(theta, mid);
            let mut below =
                Rows { ghost: Some(ghost), ..Rows::from_slices(0, nx, p_lo, f_lo, l_lo, t_lo) };
            let mut above = Rows::from_slices(mid, nx, p_hi, f_hi, l_hi, t_hi);
            let [w_lo, w_hi] = work;
            let row = &row;
            let upper = || {
                for j in mid + 1..ny - 1 {
                    row(this, &mut above, j, &[j + 1], w_hi);
                }
            };
            let lower = || {
                for j in (1..mid).rev() {
                    row(this, &mut below, j, &[j - 1], w_lo);
                }
            };
            // Even on the coarsest grids the halves gain from two threads: its many sweeps a
            // visit are a noticeable share of a solve when run on one.
            rayon::join(upper, lower);
            let deferred = below.ghost.take().map(|g| g.deferred).unwrap_or_default();
            for (i, d) in deferred {
                above.add_p(i, mid, d);
            }
        });
    }

    /// Lends the pressure, film, laws, film content and line buffers to `f`, with the level
    /// read-only, and takes them back.
    pub(super) fn lend<R>(&mut self, f: impl FnOnce(&Self, &mut Lent) -> R) -> R {
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
    /// the passes in turn from one edge to the other and outward from the centre on two
    /// threads ([`Self::sweep_halves`]). A meniscus moves by the oil its neighbours' pressures
    /// push into it, a little each sweep, and where the supply fills part of the inlet that
    /// was the slow part of the whole solve, a relaxation-bound mode (docs/decisions.md,
    /// "Passes around the menisci"). Windows cost a few cells a row.
    pub(super) fn relax_menisci(&mut self, prm: &ReynoldsParams, h00: f64, s: &RelaxSettings) {
        for pass in 0..s.meniscus_passes {
            let windows = |this: &Self, rows: &mut Rows, j, next: &[usize], w: &mut LineWork| {
                this.relax_windows(prm, s, rows, j, next, w)
            };
            // The rows in turn from one edge to the other on one thread, then outward from the
            // centre on two: outward alone, a meniscus's change never reached the rows between
            // it and the centre within a sweep (docs/decisions.md, "The fed solve's cost on the
            // finest grids").
            if pass % 2 == 1 {
                self.sweep_halves(windows);
            } else {
                let ny = self.p_dim().0;
                self.lend(|this, lent| {
                    let Lent { p, film, laws, theta, work } = lent;
                    let mut rows = Rows::whole(p, film, laws, theta);
                    for j in 1..ny - 1 {
                        windows(this, &mut rows, j, &[j - 1, j + 1], &mut work[0]);
                    }
                });
            }
        }
        if s.meniscus_passes > 0 {
            self.update_film(h00);
        }
    }

    /// Relaxes the windows of row `j` around its boundaries between full and partly filled
    /// gap ([`Self::relax_menisci`]); `next` as for a whole line.
    fn relax_windows(
        &self,
        prm: &ReynoldsParams,
        s: &RelaxSettings,
        rows: &mut Rows,
        j: usize,
        next: &[usize],
        w: &mut LineWork,
    ) {
        let nx = self.p_dim().1;
        let mut windows = std::mem::take(&mut w.windows);
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
        // A window stops short of the points where the solids touch: their gap's changes,
        // relaxed again in each pass, overshot (the line solve sees a part of the contact's
        // elastic response) and a start from the dry contact ran away.
        let touching = |i: usize| self.touch && self.contact[[j, i]];
        for &(lo, hi) in &windows {
            let mut from = lo;
            for i in lo..=hi + 1 {
                if i <= hi && !touching(i) {
                    continue;
                }
                if from < i {
                    let line = Line { j, next, span: Some((from, i - 1)) };
                    self.relax_line(prm, s, rows, line, w);
                }
                from = i + 1;
            }
        }
        w.windows = windows;
    }

    /// A point's own wedge coefficient through its elastic self-influence, and in a time step
    /// the transient term's (`a0 ρ̄ K(0, 0)`), per `ρ̄`: what the Poiseuille diagonal is
    /// compared with to choose a point's relaxation ([`Self::relax_line`] says why).
    /// What the Poiseuille diagonal is compared with to choose distributive relaxation: the
    /// wedge diagonal's parts, each times its threshold (per unit `ρ̄`).
    pub(super) fn switch_diag(&self, s: &RelaxSettings) -> f64 {
        let (wedge, transient) = self.diag_parts();
        // A solver resolves the threshold for its finest grid; a level relaxed alone is its own.
        let t = if self.speed == 0.0 {
            s.transient_threshold_at_rest
        } else {
            s.transient_threshold_for(self.grid.nx.max(self.grid.ny))
        };
        s.distributive_threshold * wedge + t * transient
    }

    /// The wedge's and the time term's self-coefficients through the elastic self-influence,
    /// per `ρ̄`.
    pub(super) fn diag_parts(&self) -> (f64, f64) {
        let wedge = self.speed
            * (1.5 * self.k(0, 0) - 2.0 * self.k(1, 0) + 0.5 * self.k(2, 0)).abs()
            / self.h;
        (wedge, self.time_a0 * self.k(0, 0))
    }

    pub(super) fn wedge_diag(&self) -> f64 {
        let (wedge, transient) = self.diag_parts();
        wedge + transient
    }

    /// Mass conserving: a second pass of line relaxation with the lines across the rolling
    /// direction (columns, from the inflow on, so that each sees its upstream neighbours' new
    /// film content), over the points where the Poiseuille term governs (the distributive
    /// ones are left to the row pass). Beside the contact the boundary between full and partly
    /// filled gap runs along `x`, between rows: a row pass holds one side of it while solving
    /// the other, and the side meniscus crept a little each sweep, for tens of cycles. The
    /// column Jacobian keeps the Poiseuille stencil, the film-content columns and
    /// the elastic coupling along the column; the film is recomputed after the pass.
    ///
    /// The columns are solved in two halves at once, the rows below the centre and the rest,
    /// each holding the other's row beside it as the pass found it: on one thread the column
    /// pass took a fifth of a fed solve's time (the seed's contact fed 10 nm on 513²), and the
    /// halves solve their own columns as the whole did, one row of coupling less.
    pub(super) fn relax_columns(&mut self, prm: &ReynoldsParams, h00: f64, s: &RelaxSettings) {
        let (ny, nx) = self.p_dim();
        let (eps, mut rt) = self.coefficients(prm);
        let mid = ny / 2;
        let mut p = std::mem::take(&mut self.p);
        let mut theta = std::mem::take(&mut self.theta);
        let mut film = std::mem::take(&mut self.film);
        // Each half reads the other's row beside its own as it was when the pass began: the
        // result does not depend on the number of threads.
        let seam = [row_of(&p, mid).to_vec(), row_of(&p, mid - 1).to_vec()];
        {
            let (p_lo, p_hi) = split_rows(&mut p, mid);
            let (t_lo, t_hi) = split_rows(&mut theta, mid);
            let (f_lo, f_hi) = split_rows(&mut film, mid);
            let (r_lo, r_hi) = split_rows(&mut rt, mid);
            let lower = ColumnHalf {
                first: 0,
                nx,
                rows: (1, mid - 1),
                p: p_lo,
                theta: t_lo,
                film: f_lo,
                rt: r_lo,
                seam: (mid, &seam[0]),
            };
            let upper = ColumnHalf {
                first: mid,
                nx,
                rows: (mid, ny - 2),
                p: p_hi,
                theta: t_hi,
                film: f_hi,
                rt: r_hi,
                seam: (mid - 1, &seam[1]),
            };
            let this = &*self;
            rayon::join(
                || this.relax_column_half(prm, s, &eps, lower),
                || this.relax_column_half(prm, s, &eps, upper),
            );
        }
        (self.p, self.theta, self.film) = (p, theta, film);
        self.update_film(h00);
    }

    /// [`Self::relax_columns`] over one half's rows: each column from the inflow on, solved
    /// over the half's rows with the other half's row beside them held.
    fn relax_column_half(
        &self,
        prm: &ReynoldsParams,
        s: &RelaxSettings,
        eps: &Array2<f64>,
        c: ColumnHalf,
    ) {
        let nx = self.p_dim().1;
        let (j0, j1) = c.rows;
        let m = j1 + 1 - j0;
        let mut band = vec![[0.0; 5]; m];
        let mut solve = vec![[0.0; 5]; m];
        let (mut r, mut rhs, mut delta) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        let (mut kind, mut fixed, mut known) = (vec![0u8; m], vec![false; m], vec![0.0; m]);
        let switch_diag = self.switch_diag(s);
        for i in 1..nx - 1 {
            self.column_system(prm, eps, &c, (i, switch_diag), (&mut kind, &mut r, &mut band));
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
                    let at = c.at(q + j0, i);
                    let k = if kind[q] == PARTIAL {
                        let t = c.theta[at] + delta[q];
                        (!(0.0..=1.0).contains(&t)).then(|| t.clamp(0.0, 1.0) - c.theta[at])
                    } else {
                        let pq = c.p[at];
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
                let j = q + j0;
                let d = delta[q] * omega(kind[q]);
                if !d.is_finite() || kind[q] == HELD {
                    continue;
                }
                let at = c.at(j, i);
                if kind[q] == PARTIAL {
                    let t = (c.theta[at] + d).clamp(0.0, 1.0);
                    c.theta[at] = t;
                    c.rt[at] = prm.density.rho(c.p[at]) * t;
                } else {
                    let old = c.p[at];
                    let new = if old + d > CAVITATION_FLOOR { old + d } else { 0.0 };
                    c.p[at] = new;
                    // The film nearby follows at once (the kernel's nearest field, what the
                    // column Jacobian reads), on this half's rows.
                    for jj in j.saturating_sub(2).max(j0)..=(j + 2).min(j1) {
                        for ii in i.saturating_sub(2)..=(i + 2).min(nx - 1) {
                            let k = self.k(ii as i64 - i as i64, jj as i64 - j as i64);
                            c.film[c.at(jj, ii)] += (new - old) * k;
                        }
                    }
                }
            }
        }
    }

    /// Column `i` of a [`ColumnHalf`]: each point's kind, its residual and its row of the
    /// column Jacobian (none for a held point: its row is the identity in the solve).
    fn column_system(
        &self,
        prm: &ReynoldsParams,
        eps: &Array2<f64>,
        c: &ColumnHalf,
        (i, switch_diag): (usize, f64),
        (kind, r, band): (&mut [u8], &mut [f64], &mut [[f64; 5]]),
    ) {
        let h = self.h;
        let (j0, m) = (c.rows.0, kind.len());
        for q in 0..m {
            let j = q + j0;
            let e = [row_of(eps, j - 1), row_of(eps, j), row_of(eps, j + 1)];
            let pj = c.p[c.at(j, i)];
            let dens = prm.density.rho(pj);
            let distributive = 4.0 * e[1][i] / (h * h) < dens * switch_diag;
            // A touching point, and a loaded one whose change distributes, is held whatever
            // its residual: neither the residual nor its Jacobian row is read (inside the
            // contact that is most of a column).
            if self.contact[[j, i]] || pj > 0.0 && distributive {
                kind[q] = HELD;
                continue;
            }
            let rows = [c.p_row(j - 1), c.p_row(j), c.p_row(j + 1)];
            let oil = (c.row(&*c.rt, j), c.row(&*c.theta, j));
            r[q] = self.rhs[[j, i]] - self.op_line(e, oil, rows, c.row(&*c.film, j), i, j);
            kind[q] = if pj <= 0.0 && (c.theta[c.at(j, i)] < 1.0 || r[q] > 0.0) {
                PARTIAL
            } else if distributive {
                HELD
            } else {
                FULL
            };
        }
        for q in 0..m {
            if kind[q] == HELD {
                // Its row is the identity in the solve.
                continue;
            }
            let j = q + j0;
            let e = [row_of(eps, j - 1), row_of(eps, j), row_of(eps, j + 1)];
            let (ee, ew, en, es) = self.half_points(e, j, i);
            let rt_row = c.row(&*c.rt, j);
            let [w0, w1, w2] = self.upwind(c.row(&*c.theta, j), j, i);
            let (r0, r1, r2) =
                (w0 * rt_row[i] / h, w1 * rt_row[i - 1] / h, w2 * rt_row[i.max(2) - 2] / h);
            let mut row = [0.0; 5];
            for dj in -1i64..=1 {
                let qc = q as i64 + dj;
                if qc < 0 || qc >= m as i64 {
                    continue;
                }
                let col = (dj + 2) as usize;
                row[col] = match kind[qc as usize] {
                    PARTIAL if dj == 0 => {
                        -(self.speed * w0 / h + self.time_a0)
                            * prm.density.rho(c.p[c.at(j, i)])
                            * c.film[c.at(j, i)]
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
                            + self.time_a0 * rt_row[i] * self.k(0, dj);
                        pois - elastic
                    }
                };
            }
            band[q] = row;
        }
    }

    /// Makes column `q` of the line Jacobian `band` (row `j`, the line's first point `lo`) a
    /// film content's: `∂L_i/∂θ_q` for the rows `i = q, q+1, q+2` the upwind stencil reaches
    /// (first order at the first point), none upstream; `mass` is the point's `ρ̄H`.
    ///
    /// A partly filled point's column from the start of a line solve; a loaded point's from the
    /// pass after the solve drove its pressure below zero, where the Poiseuille term governs
    /// (the open gap), the pressure given up. The complementarity `P ≥ 0`, `θ ≤ 1` is so decided
    /// within the line, not a sweep later: held at `P = 0` with its gap full, such a point
    /// stood for the sweep against its neighbour's film content, and beside the contact a front
    /// of excess oil (a loaded point at 1e-6 `p_h`, the gap full behind it) moved a few cells a
    /// sweep and took tens of cycles to leave by the outlet (docs/decisions.md, "A loaded
    /// point's release within the line"). Not in contact nor beside a distributive change
    /// (which would spread onto it), and not where the laws are lagged.
    fn theta_column(
        &self,
        band: &mut [[f64; 5]],
        (j, lo): (usize, usize),
        q: usize,
        theta: &[f64],
        mass: f64,
    ) {
        let m = band.len();
        // The rows upstream of the point do not see its film content.
        for ahead in 1..=2 {
            if q >= ahead {
                band[q - ahead][2 + ahead] = 0.0;
            }
        }
        for back in 0..3 {
            let row = q + back;
            if row >= m {
                break;
            }
            if self.contact[[j, row + lo]] {
                continue;
            }
            let weight = self.upwind(theta, j, row + lo)[back];
            let own = if back == 0 { self.time_a0 * mass } else { 0.0 };
            band[row][2 - back] = -self.speed * weight * mass / self.h - own;
        }
    }

    /// Relaxes line `j` of `rows`, then adds the near-field film change of its pressure changes
    /// to the rows `next` (the lines relaxed after it in this half).
    pub(super) fn relax_line(
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
        // weight of `ρ̄H`). Solving both kinds in one line system matters: a tiny pressure change
        // moves a neighbour's film-content equation by order one, and updating `θ` point by
        // point between the pressure solves moved the meniscus one cell in several sweeps.
        // A coarser grid of a cycle holds `θ` (its partly filled points keep `P = 0`), unless it
        // solves for it too ([`Self::coarse_theta`]).
        if mass_conserving {
            // A loaded point's gap is full (a prolonged start, a correction, may leave less).
            // The row itself takes it when the line is done: until then the row still holds
            // the point partly filled, and [`Rows::add_p`] drops the change the solve makes
            // there. That holds back a correction that loaded a point past the meniscus for a
            // sweep, and is kept: filling the row first cost the fed solves more cycles
            // (docs/decisions.md, "The fed solve's cost on the finest grids").
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
                self.jacobian_row(eps, rho, &w.theta, (j, q + lo), lo, &w.dist)
            };
        }
        for q in (0..m).filter(|&q| w.partial[q]) {
            self.theta_column(&mut w.band, (j, lo), q, &w.theta, w.dens[q + lo] * film[q + lo]);
        }
        // Complementarity on the line: points whose pressure the solve would drive negative
        // release it (below), or where they cannot (in contact, beside a distributive change,
        // on a grid that holds `θ`) are fixed at P = 0 (their row becomes δ = −P), and the
        // line is solved again, so that
        // the others' changes account for it; clamping afterwards instead makes the
        // cavitation boundary flip from cycle to cycle. Film contents the solve would take
        // above 1 or below 0 are fixed there the same way (a full gap becomes a pressure
        // unknown at the next sweep).
        let dist = &w.dist;
        // Mass conserving, where the Poiseuille term outweighs the wedge's elastic coupling many
        // times (the open inlet and the sides) a full Gauss–Seidel step is stable, and the
        // pressures there (carrying the oil the menisci trade) settle twice as fast
        // (docs/decisions.md, "Full Gauss–Seidel steps where the Poiseuille term dominates").
        let big = s.poiseuille_full_step;
        let poiseuille = |q: usize| {
            big > 0.0 && mass_conserving && {
                let i = q + lo;
                4.0 * eps[1][i] / (h * h) > big * w.dens[i] * wedge_diag
            }
        };
        let omega = |q: usize, partial: &[bool]| {
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
        w.released.clear();
        w.released.resize(m, 0.0);
        w.known.clear();
        w.known.resize(m, 0.0);
        w.solve.resize(m, [0.0; 5]);
        w.rhs.resize(m, 0.0);
        let theta_solved = self.theta_free || self.coarse_theta;
        if !theta_solved {
            for q in (0..m).filter(|&q| w.partial[q]) {
                w.fixed[q] = true;
            }
        }
        // A full point of the open gap that the solve drives below `P = 0` releases it: its
        // film content is the unknown from the next pass on ([`Self::theta_column`] says why).
        let switchable = |q: usize, dist: &[bool]| {
            mass_conserving
                && theta_solved
                && poiseuille(q)
                && s.coefficient_lag == 0.0
                && !touching(q + lo)
                && !(q.saturating_sub(1)..(q + 2).min(m)).any(|k| dist[k])
        };
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
                let known = if w.partial[q] {
                    let t = w.theta[q + lo] + w.delta[q];
                    (!(0.0..=1.0).contains(&t)).then(|| t.clamp(0.0, 1.0) - w.theta[q + lo])
                } else {
                    let pq = p_line[q + lo];
                    let om = omega(q, &w.partial);
                    (pq + om * w.delta[q] < 0.0).then(|| -pq / om)
                };
                let Some(k) = known else { continue };
                if !w.partial[q] && switchable(q, dist) {
                    // The known change `−P` moves to the right-hand side of the rows it reaches.
                    let pq = p_line[q + lo];
                    for row in q.saturating_sub(2)..(q + 3).min(m) {
                        w.r[row] += w.band[row][2 + q - row] * pq;
                    }
                    (w.released[q], w.partial[q]) = (pq, true);
                    let mass = w.dens[q + lo] * film[q + lo];
                    self.theta_column(&mut w.band, (j, lo), q, &w.theta, mass);
                    let c = q.saturating_sub(2);
                    first = Some(first.map_or(c, |f: usize| f.min(c)));
                    continue;
                }
                w.fixed[q] = true;
                w.known[q] = k;
                first = Some(first.map_or(q, |f: usize| f.min(q)));
            }
        }
        let partial = &w.partial;
        // Apply changes (cavitation: no negative pressures, film contents in [0, 1]).
        w.applied.clear();
        for q in 0..m {
            let i = q + lo;
            let d = w.delta[q] * omega(q, partial);
            if !d.is_finite() {
                continue;
            }
            if partial[q] {
                let t = (w.theta[i] + d).clamp(0.0, 1.0);
                w.theta[i] = t;
                w.rho[i] = w.dens[i] * t;
                if w.released[q] != 0.0 {
                    w.applied.extend(rows.add_p(i, j, -w.released[q]));
                }
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
        // film is recomputed by FFT after the sweep).
        for &jn in next.iter().filter(|&&jn| jn >= 1 && jn < ny - 1) {
            let film = rows.film_row_mut(jn);
            for &(i, jj, d) in &w.applied {
                add_near_field(film, &self.kernel[jn.abs_diff(jj)], i, d);
            }
        }
    }
}
