//! Elastic half-space deformation of a pressure field, as a non-periodic linear convolution.
//!
//! `W(X) = (2/π²) ∬ P(X') / |X − X'| dX'` (Hertz units: `W` in `a²/R`, `P` in `p_h`, `X` in `a`),
//! with `P` piecewise constant on the grid cells. The influence coefficients are the exact
//! integrals of `1/r` over a rectangular cell (Love's rectangle solution). The convolution is done
//! with zero-padded real FFTs: the kernel is even in both directions, so a padded period of
//! `M ≥ 2(n − 1)` is exact (offsets `±(n − 1)` alias onto the same, equal, coefficient). The
//! kernel spectrum and FFT plans are built once per grid and reused by every apply.

use crate::grid::Grid;
use ndarray::{Array2, ArrayView2, ArrayViewMut2};
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner, num_complex::Complex};
use std::f64::consts::PI;
use std::sync::{Arc, Mutex};

/// Columns (rows) gathered at once in the transposes of [`Deformation::convolve`].
const TILE: usize = 16;

/// `∬ 1/r` over the rectangle `[−hx, hx] × [−hy, hy]`, seen from `(x, y)`.
///
/// Antiderivative `u asinh(v/|u|) + v asinh(u/|v|)`: the `u ln|u|` parts of the textbook form
/// `u ln(v + r) + v ln(u + r)` cancel between corners and are dropped, which avoids the
/// cancellation in `v + r` for negative `v`.
pub fn rectangle_influence(x: f64, y: f64, hx: f64, hy: f64) -> f64 {
    let g = corner;
    g(x + hx, y + hy) - g(x + hx, y - hy) - g(x - hx, y + hy) + g(x - hx, y - hy)
}

/// The rectangle formula's corner function `u asinh(v/|u|) + v asinh(u/|v|)` (odd in both).
#[inline]
fn corner(u: f64, v: f64) -> f64 {
    let a = if u == 0.0 { 0.0 } else { u * (v / u.abs()).asinh() };
    let b = if v == 0.0 { 0.0 } else { v * (u / v.abs()).asinh() };
    a + b
}

/// Influence coefficient in Hertz units: `W` at offset `(di ΔX, dj ΔY)` from a cell of unit `P`.
pub fn influence_coefficient(grid: &Grid, di: i64, dj: i64) -> f64 {
    let (dx, dy) = (grid.dx(), grid.dy());
    2.0 / (PI * PI) * rectangle_influence(di as f64 * dx, dj as f64 * dy, 0.5 * dx, 0.5 * dy)
}

/// [`influence_coefficient`] for every offset `0 ≤ di < nx`, `0 ≤ dj < ny` (row-major in `dj`),
/// from a table of the rectangle formula's corner function at the cell corners `(k − ½) ΔX`.
fn influence_quarter(grid: &Grid) -> Vec<f64> {
    let g = corner;
    let (nx, ny, dx, dy) = (grid.nx, grid.ny, grid.dx(), grid.dy());
    let c: Vec<f64> = (0..=nx).map(|k| (k as f64 - 0.5) * dx).collect();
    let r: Vec<f64> = (0..=ny).map(|k| (k as f64 - 0.5) * dy).collect();
    let t: Vec<f64> = r.iter().flat_map(|&v| c.iter().map(move |&u| g(u, v))).collect();
    let at = |i: usize, j: usize| t[j * (nx + 1) + i];
    let scale = 2.0 / (PI * PI);
    let mut q = vec![0.0; nx * ny];
    for dj in 0..ny {
        for di in 0..nx {
            q[dj * nx + di] =
                scale * (at(di + 1, dj + 1) - at(di + 1, dj) - at(di, dj + 1) + at(di, dj));
        }
    }
    q
}

/// Smallest `2^a 3^b 5^c 7^d ≥ n`: padded lengths rustfft transforms fast.
fn fast_length(n: usize) -> usize {
    (n..)
        .find(|&m| {
            let mut m = m;
            for p in [2, 3, 5, 7] {
                while m % p == 0 {
                    m /= p;
                }
            }
            m == 1
        })
        .unwrap()
}

/// What multiplies the spectrum between the forward and inverse transforms.
#[derive(Clone, Copy, Debug)]
pub enum Symbol {
    /// The influence kernel: the deformation itself.
    Kernel,
    /// `1 / (K̂ + shift)`: an approximate inverse of `A + shift·I`, used as a preconditioner.
    InverseShifted(f64),
}

/// The deformation operator of one grid. Cheap to share: `apply` takes `&self` and is
/// thread-safe; the FFT work inside is split over rayon's pool.
pub struct Deformation {
    grid: Grid,
    /// Padded lengths along x (real transform) and y (complex transform).
    mx: usize,
    my: usize,
    /// `mx / 2 + 1`: complex columns after the real transform along x.
    kx: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    fft_y: Arc<dyn Fft<f64>>,
    ifft_y: Arc<dyn Fft<f64>>,
    /// Kernel spectrum `K̂[k][j]` (real: the kernel is even), not normalised.
    symbol: Vec<f64>,
    /// Spare work buffers: (row spectra ny×kx, column spectra kx×my).
    buffers: Mutex<Vec<SpectraPair>>,
    /// Self-influence `K(0, 0)`: the local stiffness of one cell.
    k00: f64,
}

/// One convolution's work buffers: row spectra (ny × kx) and column spectra (kx × my).
type SpectraPair = (Vec<Complex<f64>>, Vec<Complex<f64>>);

impl Deformation {
    /// The operator of `grid`: influence coefficients, their spectrum and the FFT plans, built once.
    pub fn new(grid: Grid) -> Self {
        let mx = fast_length(2 * (grid.nx - 1)).max(2);
        let my = fast_length(2 * (grid.ny - 1)).max(2);
        let kx = mx / 2 + 1;
        let mut rplanner = RealFftPlanner::<f64>::new();
        let r2c = rplanner.plan_fft_forward(mx);
        let c2r = rplanner.plan_fft_inverse(mx);
        let mut planner = FftPlanner::<f64>::new();
        let fft_y = planner.plan_fft_forward(my);
        let ifft_y = planner.plan_fft_inverse(my);
        let mut op = Self {
            grid,
            mx,
            my,
            kx,
            r2c,
            c2r,
            fft_y,
            ifft_y,
            symbol: Vec::new(),
            buffers: Mutex::new(Vec::new()),
            k00: influence_coefficient(&grid, 0, 0),
        };
        op.symbol = op.kernel_spectrum();
        op
    }

    /// The grid the operator is built on.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }
    /// Self-influence of a cell, `K(0,0)` [a²/R per p_h].
    pub fn self_influence(&self) -> f64 {
        self.k00
    }
    /// Padded transform size `(my, mx)`.
    pub fn padded_shape(&self) -> (usize, usize) {
        (self.my, self.mx)
    }
    /// Smallest value of the kernel spectrum (positive: the operator is positive definite).
    pub fn min_symbol(&self) -> f64 {
        self.symbol.iter().cloned().fold(f64::INFINITY, f64::min)
    }

    /// Kernel laid out on the padded period, wrapped, then transformed once.
    fn kernel_spectrum(&self) -> Vec<f64> {
        let (nx, ny, mx, my, kx) = (self.grid.nx, self.grid.ny, self.mx, self.my, self.kx);
        let offset = |m: usize, n: usize, period: usize| -> Option<i64> {
            if m < n {
                Some(m as i64)
            } else if m + n > period {
                Some(m as i64 - period as i64)
            } else {
                None
            }
        };
        // The kernel is even in both offsets, and each coefficient combines the corner function
        // at four cell corners shared with its neighbours: one table of the corner function
        // over the quarter's corners gives every coefficient from (n + 1)² evaluations instead
        // of 16 n² (docs/decisions.md, "The influence coefficients from one table").
        let quarter = influence_quarter(&self.grid);
        let mut rows = vec![Complex::new(0.0, 0.0); my * kx];
        let mut line = vec![0.0; mx];
        for j in 0..my {
            line.iter_mut().for_each(|v| *v = 0.0);
            if let Some(dj) = offset(j, ny, my) {
                let q = &quarter[dj.unsigned_abs() as usize * nx..][..nx];
                for (i, v) in line.iter_mut().enumerate() {
                    if let Some(di) = offset(i, nx, mx) {
                        *v = q[di.unsigned_abs() as usize];
                    }
                }
            }
            self.r2c.process(&mut line, &mut rows[j * kx..(j + 1) * kx]).unwrap();
        }
        let mut symbol = vec![0.0; kx * my];
        let mut col = vec![Complex::new(0.0, 0.0); my];
        for k in 0..kx {
            for j in 0..my {
                col[j] = rows[j * kx + k];
            }
            self.fft_y.process(&mut col);
            for j in 0..my {
                symbol[k * my + j] = col[j].re;
            }
        }
        symbol
    }

    /// `out = K p`: the deformation `W` [a²/R] of the pressure `P` [p_h].
    pub fn apply(&self, p: ArrayView2<f64>, out: ArrayViewMut2<f64>) {
        self.convolve(p, out, Symbol::Kernel);
    }

    /// Convenience: returns `K p` as a new array.
    pub fn deform(&self, p: &Array2<f64>) -> Array2<f64> {
        let mut w = self.grid.zeros();
        self.apply(p.view(), w.view_mut());
        w
    }

    /// `out = F⁻¹[s(K̂) F[input]]` restricted to the grid, with `s` given by `symbol`.
    pub fn convolve(&self, input: ArrayView2<f64>, mut out: ArrayViewMut2<f64>, symbol: Symbol) {
        let (nx, ny, mx, my, kx) = (self.grid.nx, self.grid.ny, self.mx, self.my, self.kx);
        assert_eq!(input.dim(), (ny, nx), "input field does not match the grid");
        assert_eq!(out.dim(), (ny, nx), "output field does not match the grid");
        let (mut rows, mut cols) = self.buffers.lock().unwrap().pop().unwrap_or_else(|| {
            (vec![Complex::new(0.0, 0.0); ny * kx], vec![Complex::new(0.0, 0.0); kx * my])
        });
        let norm = 1.0 / (mx * my) as f64;

        // A: real FFT of each (zero-padded) row of the input.
        rows.par_chunks_mut(kx).with_min_len(crate::par_min_len(mx)).enumerate().for_each_init(
            || (vec![0.0; mx], self.r2c.make_scratch_vec()),
            |(line, scratch), (j, spec)| {
                line[..nx].iter_mut().zip(input.row(j)).for_each(|(l, &v)| *l = v);
                line[nx..].iter_mut().for_each(|l| *l = 0.0);
                self.r2c.process_with_scratch(line, spec, scratch).unwrap();
            },
        );
        // B: per column k: gather, FFT along y, multiply by the symbol, inverse FFT along y.
        // Columns go in blocks of `TILE`: the gather then reads `TILE` neighbouring values of
        // each row (whole cache lines) instead of one value a row: the strided gathers were a
        // large share of a fine steady layer solve (docs/decisions.md, "The direct steady
        // solve: grids, speed, and what was tried").
        let rows_ref = &rows;
        let min_blocks = crate::par_min_len(my * TILE);
        cols.par_chunks_mut(my * TILE).with_min_len(min_blocks).enumerate().for_each_init(
            || vec![Complex::new(0.0, 0.0); self.fft_y.get_inplace_scratch_len()],
            |scratch, (b, block)| {
                let k0 = b * TILE;
                let width = block.len() / my;
                for j in 0..ny {
                    let src = &rows_ref[j * kx + k0..j * kx + k0 + width];
                    for (t, &v) in src.iter().enumerate() {
                        block[t * my + j] = v;
                    }
                }
                for (t, col) in block.chunks_mut(my).enumerate() {
                    col[ny..].iter_mut().for_each(|c| *c = Complex::new(0.0, 0.0));
                    self.fft_y.process_with_scratch(col, scratch);
                    let k = k0 + t;
                    let s = &self.symbol[k * my..(k + 1) * my];
                    match symbol {
                        Symbol::Kernel => {
                            col.iter_mut().zip(s).for_each(|(c, &s)| *c *= s * norm);
                        }
                        Symbol::InverseShifted(shift) => {
                            col.iter_mut().zip(s).for_each(|(c, &s)| *c *= norm / (s + shift));
                        }
                    }
                    self.ifft_y.process_with_scratch(col, scratch);
                }
            },
        );
        // C: per output row: gather the spectrum, inverse real FFT, keep the first nx values;
        // rows in blocks of `TILE` for the same reason.
        let cols_ref = &cols;
        let min_blocks = crate::par_min_len(mx * TILE);
        out.axis_chunks_iter_mut(ndarray::Axis(0), TILE)
            .into_par_iter()
            .with_min_len(min_blocks)
            .enumerate()
            .for_each_init(
                || {
                    (
                        vec![Complex::new(0.0, 0.0); kx * TILE],
                        vec![0.0; mx],
                        self.c2r.make_scratch_vec(),
                    )
                },
                |(spec, line, scratch), (b, mut out_rows)| {
                    let j0 = b * TILE;
                    let height = out_rows.nrows();
                    for k in 0..kx {
                        let src = &cols_ref[k * my + j0..k * my + j0 + height];
                        for (t, &v) in src.iter().enumerate() {
                            spec[t * kx + k] = v;
                        }
                    }
                    for (t, mut out_row) in out_rows.axis_iter_mut(ndarray::Axis(0)).enumerate() {
                        let spec = &mut spec[t * kx..(t + 1) * kx];
                        // The result is real: the imaginary parts at 0 and Nyquist are rounding noise.
                        spec[0].im = 0.0;
                        if mx % 2 == 0 {
                            spec[kx - 1].im = 0.0;
                        }
                        self.c2r.process_with_scratch(spec, line, scratch).unwrap();
                        out_row.iter_mut().zip(&line[..nx]).for_each(|(o, &l)| *o = l);
                    }
                },
            );
        self.buffers.lock().unwrap().push((rows, cols));
    }

    /// Direct O(N²) summation, the reference the FFT path is tested against.
    pub fn apply_direct(&self, p: &Array2<f64>) -> Array2<f64> {
        let g = &self.grid;
        Array2::from_shape_fn(g.shape(), |(j, i)| {
            let mut s = 0.0;
            for ((jj, ii), &pv) in p.indexed_iter() {
                if pv != 0.0 {
                    s += pv * influence_coefficient(g, i as i64 - ii as i64, j as i64 - jj as i64);
                }
            }
            s
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hertz;

    /// Midpoint-rule reference for `∬ 1/r` over a far cell: smooth there, so 200² points give
    /// ~1e-6 relative accuracy.
    fn quadrature(x: f64, y: f64, hx: f64, hy: f64) -> f64 {
        let n = 200;
        let (sx, sy) = (2.0 * hx / n as f64, 2.0 * hy / n as f64);
        let mut s = 0.0;
        for a in 0..n {
            for b in 0..n {
                let xx = -hx + (a as f64 + 0.5) * sx;
                let yy = -hy + (b as f64 + 0.5) * sy;
                s += 1.0 / ((x - xx).powi(2) + (y - yy).powi(2)).sqrt();
            }
        }
        s * sx * sy
    }

    #[test]
    fn rectangle_influence_matches_closed_form_and_quadrature() {
        // Centre of a square of side h: 4 h asinh(1).
        let h = 0.3;
        let centre = rectangle_influence(0.0, 0.0, h / 2.0, h / 2.0);
        assert!((centre - 4.0 * h * 1f64.asinh()).abs() < 1e-14);
        for &(x, y) in &[(1.0, 0.0), (-0.7, 0.4), (0.0, -2.0), (-1.5, -1.5)] {
            let exact = rectangle_influence(x, y, 0.1, 0.05);
            let q = quadrature(x, y, 0.1, 0.05);
            assert!((exact / q - 1.0).abs() < 1e-5, "({x},{y}): {exact} vs {q}");
        }
    }

    #[test]
    fn corner_table_gives_every_influence_coefficient() {
        // The table-built quarter against the formula evaluated offset by offset, on a
        // rectangular grid with unequal spacings. Only rounding separates them: the four-corner
        // difference cancels the corner values' leading digits, ~(r/ΔX)² of them, so the bound
        // is a few ulps of K(0,0) times that (1e-15 K00 (1 + di² + dj²)); a wrong corner index
        // is off by a whole coefficient.
        let g = Grid::new(13, 9, (-1.3, 0.9), (-0.8, 1.1));
        let q = influence_quarter(&g);
        let k00 = influence_coefficient(&g, 0, 0);
        for dj in 0..9 {
            for di in 0..13 {
                let k = influence_coefficient(&g, di as i64, dj as i64);
                let k_neg = influence_coefficient(&g, -(di as i64), -(dj as i64));
                let bound = 1e-15 * k00 * (1 + di * di + dj * dj) as f64;
                let qk = q[dj * 13 + di];
                assert!((qk - k).abs() < bound, "({di}, {dj}): {qk} against {k}");
                assert!((k_neg - k).abs() < bound, "even kernel at ({di}, {dj})");
            }
        }
    }

    #[test]
    fn fft_matches_direct_summation() {
        // Rectangular, non-square spacing, odd/even counts and a padded length that is not a
        // power of two: every path of the padding logic.
        for &(nx, ny) in &[(17, 13), (12, 9), (5, 5)] {
            let g = Grid::new(nx, ny, (-1.3, 0.9), (-0.8, 1.1));
            let op = Deformation::new(g);
            let p = g.field(|x, y| (3.0 * x).sin() * (2.0 * y).cos() + 1.5 + 0.3 * x * y);
            let fft = op.deform(&p);
            let direct = op.apply_direct(&p);
            let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff = (&fft - &direct).iter().fold(0.0f64, |m, v| m.max(v.abs()));
            // Round-off of two 2-D FFTs: ~1e-15 relative; 1e-12 leaves room, not slack for bugs.
            assert!(diff / scale < 1e-12, "{nx}x{ny}: rel diff {}", diff / scale);
        }
    }

    #[test]
    fn self_influence_is_the_response_of_a_loaded_cell() {
        // The FFT path's response at a cell under unit pressure there alone: the kernel's
        // centre value, which the layer's local march and the preconditioner take from
        // `self_influence` (mutants returning ±1 went unseen before).
        let g = Grid::new(17, 13, (-1.0, 1.0), (-0.7, 0.8));
        let op = Deformation::new(g);
        let mut p = g.zeros();
        p[[6, 8]] = 1.0;
        let w = op.deform(&p);
        let k00 = op.self_influence();
        assert!((w[[6, 8]] / k00 - 1.0).abs() < 1e-12, "{} vs {k00}", w[[6, 8]]);
        // Closed form for a square cell of side h at its centre, W = (2/π²) ∬ P / r:
        // ∬ 1/r = 4 h ln(1 + √2), so K00 = (8/π²) h ln(1 + √2) = 0.08930 for h = 0.125 a.
        let exact = 8.0 / (PI * PI) * 0.125 * (1.0 + 2f64.sqrt()).ln();
        assert!((k00 / exact - 1.0).abs() < 1e-12, "{k00} vs {exact}");
    }

    #[test]
    fn padding_takes_the_next_fast_length_of_twice_the_grid() {
        // Linear (not circular) convolution needs 2 (n − 1) points; the next length of factors
        // 2, 3, 5, 7 transforms fast: 2·33 = 66 = 2·3·11 → 70, 2·11 = 22 → 24.
        let op = Deformation::new(Grid::new(34, 12, (-1.0, 1.0), (-0.3, 0.3)));
        assert_eq!(op.padded_shape(), (24, 70));
        assert_eq!(Deformation::new(Grid::square(33, 1.0)).padded_shape(), (64, 64));
    }

    #[test]
    fn symbol_is_positive_and_its_minimum_that_of_a_direct_transform() {
        let op = Deformation::new(Grid::square(65, 1.25));
        assert!(op.min_symbol() > 0.0, "min symbol {}", op.min_symbol());
        // On 9² (period 16²) the spectrum by a direct cosine sum over the wrapped coefficients
        // (each from the rectangle formula, not the corner table or an FFT): its smallest value
        // is the operator's, to the sums' rounding (~1e-15 of the largest term).
        let g = Grid::square(9, 1.0);
        let op = Deformation::new(g);
        let (my, mx) = op.padded_shape();
        let wrap = |m: usize, n: usize, period: usize| {
            if m < n { Some(m as i64) } else { (m + n > period).then(|| m as i64 - period as i64) }
        };
        let mut direct = f64::INFINITY;
        for l in 0..my {
            for k in 0..mx {
                let mut s = 0.0;
                for n in 0..my {
                    for m in 0..mx {
                        if let (Some(di), Some(dj)) = (wrap(m, g.nx, mx), wrap(n, g.ny, my)) {
                            let phase = 2.0 * PI * (k * m) as f64 / mx as f64
                                + 2.0 * PI * (l * n) as f64 / my as f64;
                            s += influence_coefficient(&g, di, dj) * phase.cos();
                        }
                    }
                }
                direct = direct.min(s);
            }
        }
        assert!((op.min_symbol() / direct - 1.0).abs() < 1e-12, "{} vs {direct}", op.min_symbol());
    }

    #[test]
    fn hertz_pressure_gives_hertz_deflection() {
        // Piecewise-constant sampling of sqrt(1 − r²) misrepresents the square-root edge: the
        // deflection error is O(ΔX^1.5) there; on 129² (ΔX ≈ 0.02) that is ~3e-3 of the centre
        // value. We assert 4e-3 here and that halving ΔX reduces it.
        let mut errs = vec![];
        for n in [65, 129] {
            let g = Grid::square(n, 1.5);
            let op = Deformation::new(g);
            let p = g.field(hertz::pressure);
            let w = op.deform(&p);
            let exact = g.field(|x, y| hertz::deflection((x * x + y * y).sqrt()));
            let err = (&w - &exact).iter().fold(0.0f64, |m, v| m.max(v.abs()));
            errs.push(err);
        }
        assert!(errs[1] < 4e-3, "max deflection error on 129²: {}", errs[1]);
        assert!(errs[1] < 0.6 * errs[0], "no convergence: {errs:?}");
    }
}
