//! Semi-Lagrangian transport along `x` at the uniform surface velocity: the value a material
//! point carries to grid point `x_i` at the new time is read at its departure point
//! `x_i − s ΔX` (`s = u1 Δt / ΔX` cells) by cubic Lagrange interpolation on the upwind-biased
//! stencil `j−2 … j+1`. Exact for whole-cell shifts (`n_t = 1`), O(ΔX⁴) per step otherwise.
//! Upstream of the inlet the supply value (`inflow`) enters; past the outlet the last column is
//! held (the stencil reaches one point downstream only with a small weight).

use ndarray::{Array2, Axis, Zip};

/// Returns `field` carried `s ≥ 0` cells downstream (towards `+x`).
pub fn shift(field: &Array2<f64>, s: f64, inflow: f64) -> Array2<f64> {
    assert!(s >= 0.0 && s.is_finite());
    let k = s.floor() as isize;
    let theta = s - k as f64;
    let u = -theta;
    let w = [
        -(u + 1.0) * u * (u - 1.0) / 6.0,
        (u + 2.0) * u * (u - 1.0) / 2.0,
        -(u + 2.0) * (u + 1.0) * (u - 1.0) / 2.0,
        (u + 2.0) * (u + 1.0) * u / 6.0,
    ];
    let mut out = Array2::zeros(field.dim());
    let nx = field.ncols() as isize;
    Zip::from(out.axis_iter_mut(Axis(0))).and(field.axis_iter(Axis(0))).par_for_each(|mut o, f| {
        let at = |m: isize| -> f64 {
            if m < 0 {
                inflow
            } else if m >= nx {
                f[(nx - 1) as usize]
            } else {
                f[m as usize]
            }
        };
        for i in 0..nx {
            let j = i - k;
            o[i as usize] = if theta == 0.0 {
                at(j)
            } else {
                w[0] * at(j - 2) + w[1] * at(j - 1) + w[2] * at(j) + w[3] * at(j + 1)
            };
        }
    });
    out
}

/// `shift` for many rows at once is what the steppers need; this helper keeps the strain in
/// `[0, 1]` after interpolation, where the cubic may overshoot at sharp edges.
pub fn shift_strain(eps: &Array2<f64>, s: f64) -> Array2<f64> {
    let mut out = shift(eps, s, 0.0);
    out.par_mapv_inplace(|v| v.clamp(0.0, 1.0));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_cell_shift_is_exact_and_inflow_enters() {
        let f = Array2::from_shape_fn((2, 6), |(j, i)| (i + 10 * j) as f64);
        let g = shift(&f, 2.0, -1.0);
        assert_eq!(g.row(1).to_vec(), vec![-1.0, -1.0, 10.0, 11.0, 12.0, 13.0]);
    }

    #[test]
    fn cubic_is_exact_for_cubics_and_fourth_order() {
        let n = 41;
        let dx = 0.05;
        let cubic = |x: f64| 1.0 + x - 2.0 * x * x + 0.5 * x * x * x;
        let f = Array2::from_shape_fn((1, n), |(_, i)| cubic(i as f64 * dx));
        let g = shift(&f, 0.3, 0.0);
        for i in 3..n - 1 {
            let x = (i as f64 - 0.3) * dx;
            assert!((g[[0, i]] - cubic(x)).abs() < 1e-12);
        }
        // Interpolation error of a smooth non-polynomial: O(ΔX⁴).
        let err = |dx: f64| {
            let n = (2.0 / dx) as usize + 1;
            let f = Array2::from_shape_fn((1, n), |(_, i)| (3.0 * i as f64 * dx).sin());
            let g = shift(&f, 0.4, 0.0);
            (3..n - 1)
                .map(|i| (g[[0, i]] - (3.0 * (i as f64 - 0.4) * dx).sin()).abs())
                .fold(0.0, f64::max)
        };
        let order = (err(0.02) / err(0.01)).log2();
        assert!(order > 3.8, "observed order {order}");
    }
}
