//! The two-half sweep's machinery: rows lent to each half, the ghost rows at the seam,
//! a line's own slices and the line solve's work arrays.

use super::*;

/// A level's pressure, film and law cache from row `first` on, lent to one half of a sweep,
/// with a frozen copy of one row beyond them (the ghost) whose pressure changes wait.
pub(super) struct Rows<'a> {
    pub(super) first: usize,
    pub(super) nx: usize,
    pub(super) p: &'a mut [f64],
    pub(super) film: &'a mut [f64],
    pub(super) laws: &'a mut [[f64; 3]],
    pub(super) theta: &'a mut [f64],
    pub(super) ghost: Option<Ghost>,
}

/// A row another half owns, as it was when this half began; the law cache is this half's own.
pub(super) struct Ghost {
    pub(super) j: usize,
    pub(super) p: Vec<f64>,
    pub(super) film: Vec<f64>,
    pub(super) laws: Vec<[f64; 3]>,
    pub(super) theta: Vec<f64>,
    /// Pressure changes `(i, ΔP)` for the owner to add afterwards.
    pub(super) deferred: Vec<(usize, f64)>,
}

impl<'a> Rows<'a> {
    /// All rows of a level's arrays.
    pub(super) fn whole(
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

    pub(super) fn from_slices(
        first: usize,
        nx: usize,
        p: &'a mut [f64],
        film: &'a mut [f64],
        laws: &'a mut [[f64; 3]],
        theta: &'a mut [f64],
    ) -> Self {
        Self { first, nx, p, film, laws, theta, ghost: None }
    }

    pub(super) fn span(&self, j: usize) -> std::ops::Range<usize> {
        let k = j - self.first;
        k * self.nx..(k + 1) * self.nx
    }

    pub(super) fn ghost(&self, j: usize) -> Option<&Ghost> {
        self.ghost.as_ref().filter(|g| g.j == j)
    }

    pub(super) fn p_row(&self, j: usize) -> &[f64] {
        match self.ghost(j) {
            Some(g) => &g.p,
            None => &self.p[self.span(j)],
        }
    }

    pub(super) fn film_row(&self, j: usize) -> &[f64] {
        match self.ghost(j) {
            Some(g) => &g.film,
            None => &self.film[self.span(j)],
        }
    }

    pub(super) fn theta_row(&self, j: usize) -> &[f64] {
        match self.ghost(j) {
            Some(g) => &g.theta,
            None => &self.theta[self.span(j)],
        }
    }

    /// A row's film content to write (never the ghost).
    pub(super) fn theta_row_mut(&mut self, j: usize) -> &mut [f64] {
        assert!(self.ghost(j).is_none(), "the ghost row is not relaxed by this half");
        let r = self.span(j);
        &mut self.theta[r]
    }

    /// A row's film to add near-field changes to (never the ghost: it lies behind the sweep).
    pub(super) fn film_row_mut(&mut self, j: usize) -> &mut [f64] {
        assert!(self.ghost(j).is_none(), "the ghost row is not relaxed by this half");
        let r = self.span(j);
        &mut self.film[r]
    }

    pub(super) fn laws_p_film(&mut self, j: usize) -> (&mut [[f64; 3]], &[f64], &[f64]) {
        if self.ghost(j).is_none() {
            let r = self.span(j);
            return (&mut self.laws[r.clone()], &self.p[r.clone()], &self.film[r]);
        }
        let g = self.ghost.as_mut().expect("checked");
        (&mut g.laws, &g.p, &g.film)
    }

    /// Adds `d` to `P(i, j)`, a pressure below the cavitation floor becoming 0; returns the
    /// change made `(i, j, ΔP)` if any (none yet on the ghost row: it waits for its owner).
    pub(super) fn add_p(&mut self, i: usize, j: usize, d: f64) -> Option<(usize, usize, f64)> {
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

/// A grid array's rows before `row` and from `row` on, as two slices (the halves of a sweep).
pub(super) fn split_rows<T>(a: &mut Array2<T>, row: usize) -> (&mut [T], &mut [T]) {
    let nx = a.ncols();
    a.as_slice_mut().expect("grid arrays are in standard layout").split_at_mut(row * nx)
}

/// A level's arrays lent out while its rows are relaxed (the level itself read-only meanwhile).
pub(super) struct Lent {
    pub(super) p: Array2<f64>,
    pub(super) film: Array2<f64>,
    pub(super) laws: Array2<[f64; 3]>,
    pub(super) theta: Array2<f64>,
    pub(super) work: [LineWork; 2],
}

/// A line to relax: row `j`, the rows relaxed after it in its half (they see its near-field
/// film change at once), and the points `lo ..= hi` that are its unknowns (`None`: the whole
/// interior; a window around a meniscus otherwise).
pub(super) struct Line<'a> {
    pub(super) j: usize,
    pub(super) next: &'a [usize],
    pub(super) span: Option<(usize, usize)>,
}

impl<'a> Line<'a> {
    pub(super) fn whole(j: usize, next: &'a [usize]) -> Self {
        Self { j, next, span: None }
    }
}

/// Buffers of one line's relaxation (kept so that a sweep allocates nothing).
#[derive(Clone, Default)]
pub(super) struct LineWork {
    /// `ε̄` on rows `j−1, j, j+1`.
    pub(super) eps: [Vec<f64>; 3],
    /// `ρ̄θ` on row `j` (what the wedge and time terms carry).
    pub(super) rho: Vec<f64>,
    /// `ρ̄` on row `j`, and `θ` as the line's relaxation leaves it.
    pub(super) dens: Vec<f64>,
    pub(super) theta: Vec<f64>,
    /// Which unknowns change distributively.
    pub(super) dist: Vec<bool>,
    /// Residuals of the line's equations.
    pub(super) r: Vec<f64>,
    /// Line Jacobian (row q: columns q−2 … q+2) and a copy the elimination may destroy.
    pub(super) band: Vec<[f64; 5]>,
    pub(super) solve: Vec<[f64; 5]>,
    /// The right-hand side as elimination leaves it, and the changes `δ`.
    pub(super) rhs: Vec<f64>,
    pub(super) delta: Vec<f64>,
    /// Unknowns held by the complementarity passes (`P = 0`; `θ` at 1 or 0) …
    pub(super) fixed: Vec<bool>,
    /// … and the change their row fixes.
    pub(super) known: Vec<f64>,
    /// Which unknowns are film contents (`P = 0`, the gap partly filled).
    pub(super) partial: Vec<bool>,
    /// The pressure a loaded point gives up where the solve made its film content the
    /// unknown (`P` set to 0).
    pub(super) released: Vec<f64>,
    /// Pressure changes made `(i, j, ΔP)`.
    pub(super) applied: Vec<(usize, usize, f64)>,
    /// A row's windows `(lo, hi)` around its menisci ([`Level::relax_menisci`]).
    pub(super) windows: Vec<(usize, usize)>,
}

/// One half of the column pass's rows ([`Level::relax_columns`]): the level's pressure, film
/// content, film and `ρ̄θ` from row `first` on, the rows `rows` (inclusive) it solves, and the
/// other half's pressure row beside them as it was when the pass began.
pub(super) struct ColumnHalf<'a> {
    pub(super) first: usize,
    pub(super) nx: usize,
    pub(super) rows: (usize, usize),
    pub(super) p: &'a mut [f64],
    pub(super) theta: &'a mut [f64],
    pub(super) film: &'a mut [f64],
    pub(super) rt: &'a mut [f64],
    pub(super) seam: (usize, &'a [f64]),
}

impl ColumnHalf<'_> {
    /// The index of point `(j, i)` in this half's slices.
    pub(super) fn at(&self, j: usize, i: usize) -> usize {
        (j - self.first) * self.nx + i
    }

    /// Row `j` of one of this half's slices.
    pub(super) fn row<'b>(&self, v: &'b [f64], j: usize) -> &'b [f64] {
        &v[self.at(j, 0)..self.at(j, 0) + self.nx]
    }

    /// Row `j` of the pressure: the seam's where it is the other half's.
    pub(super) fn p_row(&self, j: usize) -> &[f64] {
        if j == self.seam.0 { self.seam.1 } else { self.row(self.p, j) }
    }
}
