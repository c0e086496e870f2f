//! Uniform vertex-centred grid over a rectangle given in units of the Hertz radius `a`.

use ndarray::Array2;
use serde::{Deserialize, Serialize};

/// A uniform grid of `nx × ny` points over `[x_min, x_max] × [y_min, y_max]` (units of `a`),
/// points on the boundary. Fields on it are `Array2` of shape `(ny, nx)`, indexed `[[j, i]]`,
/// so that lines along `x` (the rolling direction) are contiguous.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// Points along `x`.
    pub nx: usize,
    /// Points along `y`.
    pub ny: usize,
    /// Smallest `x` [a].
    pub x_min: f64,
    /// Largest `x` [a].
    pub x_max: f64,
    /// Smallest `y` [a].
    pub y_min: f64,
    /// Largest `y` [a].
    pub y_max: f64,
}

impl Grid {
    /// A grid of `nx × ny` points over `x = (min, max)`, `y = (min, max)` [a].
    pub fn new(nx: usize, ny: usize, x: (f64, f64), y: (f64, f64)) -> Self {
        assert!(nx >= 2 && ny >= 2 && x.1 > x.0 && y.1 > y.0, "degenerate grid");
        Self { nx, ny, x_min: x.0, x_max: x.1, y_min: y.0, y_max: y.1 }
    }
    /// Square `n × n` grid over `[-half, half]²`.
    pub fn square(n: usize, half: f64) -> Self {
        Self::new(n, n, (-half, half), (-half, half))
    }
    /// Spacing `ΔX` [a].
    pub fn dx(&self) -> f64 {
        (self.x_max - self.x_min) / (self.nx - 1) as f64
    }
    /// Spacing `ΔY` [a].
    pub fn dy(&self) -> f64 {
        (self.y_max - self.y_min) / (self.ny - 1) as f64
    }
    /// Area of one cell `ΔX ΔY` [a²].
    pub fn cell_area(&self) -> f64 {
        self.dx() * self.dy()
    }
    /// `x` of column `i` [a].
    pub fn x(&self, i: usize) -> f64 {
        self.x_min + i as f64 * self.dx()
    }
    /// `y` of row `j` [a].
    pub fn y(&self, j: usize) -> f64 {
        self.y_min + j as f64 * self.dy()
    }
    /// Every column's `x` [a].
    pub fn xs(&self) -> Vec<f64> {
        (0..self.nx).map(|i| self.x(i)).collect()
    }
    /// Every row's `y` [a].
    pub fn ys(&self) -> Vec<f64> {
        (0..self.ny).map(|j| self.y(j)).collect()
    }
    /// `(ny, nx)`: the shape of a field on this grid.
    pub fn shape(&self) -> (usize, usize) {
        (self.ny, self.nx)
    }
    /// A field of zeros on this grid.
    pub fn zeros(&self) -> Array2<f64> {
        Array2::zeros(self.shape())
    }
    /// A field from a function of `(X, Y)`.
    pub fn field(&self, f: impl Fn(f64, f64) -> f64) -> Array2<f64> {
        Array2::from_shape_fn(self.shape(), |(j, i)| f(self.x(i), self.y(j)))
    }
    /// The undeformed ball, `(X² + Y²)/2` in units of `a²/R`.
    pub fn paraboloid(&self) -> Array2<f64> {
        self.field(|x, y| 0.5 * (x * x + y * y))
    }
    /// Index of the grid line nearest to `y`: the centreline row for `y = 0`.
    pub fn row_nearest(&self, y: f64) -> usize {
        (((y - self.y_min) / self.dy()).round().max(0.0) as usize).min(self.ny - 1)
    }
    /// Index of the grid column nearest to `x`.
    pub fn col_nearest(&self, x: f64) -> usize {
        (((x - self.x_min) / self.dx()).round().max(0.0) as usize).min(self.nx - 1)
    }
    /// The grid with every other point (same rectangle), if both sides have an odd count of
    /// at least `min_points`.
    pub fn coarser(&self, min_points: usize) -> Option<Grid> {
        let ok = |n: usize| n % 2 == 1 && (n - 1) / 2 + 1 >= min_points;
        (ok(self.nx) && ok(self.ny)).then(|| Grid {
            nx: (self.nx - 1) / 2 + 1,
            ny: (self.ny - 1) / 2 + 1,
            ..*self
        })
    }
}

/// The seed's dent shape (its Eq. 14, reconstructed): `10^(−10 r² / W²)` at squared distance
/// `r2` from the centre, width factor `W`; both models scale it by their depth.
#[inline]
pub fn dent_profile(r2: f64, width: f64) -> f64 {
    10f64.powf(-10.0 * r2 / (width * width))
}

/// Injection of a fine field onto the grid with every other point.
pub fn inject(fine: &Array2<f64>) -> Array2<f64> {
    let (ny, nx) = fine.dim();
    Array2::from_shape_fn(((ny - 1) / 2 + 1, (nx - 1) / 2 + 1), |(j, i)| fine[[2 * j, 2 * i]])
}

/// Bilinear interpolation of a coarse field onto the grid with twice the points per side.
pub fn prolong(coarse: &Array2<f64>) -> Array2<f64> {
    let (ny, nx) = coarse.dim();
    Array2::from_shape_fn((2 * ny - 1, 2 * nx - 1), |(j, i)| {
        let (j0, i0) = (j / 2, i / 2);
        let (j1, i1) = (j.div_ceil(2), i.div_ceil(2));
        0.25 * (coarse[[j0, i0]] + coarse[[j0, i1]] + coarse[[j1, i0]] + coarse[[j1, i1]])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_coarsening_and_transfer() {
        let g = Grid::new(9, 5, (-2.0, 2.0), (-1.0, 1.0));
        assert_eq!(g.dx(), 0.5);
        assert_eq!(g.row_nearest(0.0), 2);
        let c = g.coarser(3).unwrap();
        assert_eq!((c.nx, c.ny), (5, 3));
        assert!(c.coarser(3).is_none());
        // Bilinear transfer reproduces a bilinear function exactly.
        let fc = c.field(|x, y| 1.0 + 2.0 * x - 3.0 * y + 0.5 * x * y);
        let ff = prolong(&fc);
        let exact = g.field(|x, y| 1.0 + 2.0 * x - 3.0 * y + 0.5 * x * y);
        assert!((&ff - &exact).iter().all(|d| d.abs() < 1e-13));
        assert_eq!(inject(&exact), fc);
    }
}
