//! Hertz's analytic solution for a sphere on a flat, in Hertz units (`X` in `a`, `P` in `p_h`,
//! deflections and gaps in `a²/R`). The approach is exactly `1` (i.e. `δ = a²/R`).

use std::f64::consts::PI;

/// `P(X, Y) = sqrt(1 − X² − Y²)` inside the contact, 0 outside.
pub fn pressure(x: f64, y: f64) -> f64 {
    (1.0 - x * x - y * y).max(0.0).sqrt()
}

/// Surface deflection of the half-space under the Hertz pressure at radius `r`:
/// `1 − r²/2` inside, `((2 − r²) asin(1/r) + sqrt(r² − 1)) / π` outside.
pub fn deflection(r: f64) -> f64 {
    if r <= 1.0 {
        1.0 - 0.5 * r * r
    } else {
        ((2.0 - r * r) * (1.0 / r).asin() + (r * r - 1.0).sqrt()) / PI
    }
}

/// Gap `H = −1 + r²/2 + W(r)`: zero inside the contact, positive outside.
pub fn gap(r: f64) -> f64 {
    (-1.0 + 0.5 * r * r + deflection(r)).max(0.0)
}

/// Where the gap outside the contact reaches `h` [a²/R]: the radius [a] (bisection on [1, 100]).
pub fn separation_radius(h: f64) -> f64 {
    let (mut lo, mut hi) = (1.0, 100.0);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) < h { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

/// The Hertz approach `H0 = −1` (the rigid-body term of the gap).
pub const APPROACH: f64 = -1.0;

#[cfg(test)]
mod tests {
    #[test]
    fn deflection_is_continuous_and_gap_opens_outside() {
        let (i, o) = (super::deflection(1.0 - 1e-12), super::deflection(1.0 + 1e-12));
        assert!((i - o).abs() < 1e-5);
        assert!(super::gap(0.5) == 0.0 && super::gap(1.2) > 0.0);
    }
}

/// A numerical dry solution compared with Hertz (all relative errors are signed where a sign
/// means something: positive = numerical above Hertz).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Comparison {
    /// Largest pressure `P_max` [p_h].
    pub p_max: f64,
    /// `P_max − 1`.
    pub p_max_error: f64,
    /// Area-equivalent contact radius `sqrt(A_c / π)` [a], `A_c` the area of the cells carrying
    /// pressure (an O(ΔX) estimate: the edge is only known to within a cell).
    pub contact_radius: f64,
    /// `contact_radius − 1`.
    pub contact_radius_error: f64,
    /// Approach `−H0` [a²/R].
    pub approach: f64,
    /// `approach − 1`.
    pub approach_error: f64,
    /// `‖P − P_Hertz‖₂ / ‖P_Hertz‖₂` over the grid.
    pub pressure_l2_error: f64,
}

/// Compares the pressure `p` [p_h] and approach term `h0` [a²/R] on `grid` with Hertz.
pub fn compare(grid: &crate::Grid, p: &ndarray::Array2<f64>, h0: f64) -> Comparison {
    let exact = grid.field(pressure);
    let p_max = p.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let area = p.iter().filter(|&&v| v > 0.0).count() as f64 * grid.cell_area();
    let contact_radius = (area / PI).sqrt();
    let num: f64 = p.iter().zip(&exact).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = exact.iter().map(|b| b * b).sum();
    Comparison {
        p_max,
        p_max_error: p_max - 1.0,
        contact_radius,
        contact_radius_error: contact_radius - 1.0,
        approach: -h0,
        approach_error: -h0 - 1.0,
        pressure_l2_error: (num / den).sqrt(),
    }
}

/// Observed order of convergence between two grids whose spacing differs by `ratio`, from known
/// errors: `log(|e_coarse| / |e_fine|) / log(ratio)`.
pub fn observed_order(e_coarse: f64, e_fine: f64, ratio: f64) -> f64 {
    (e_coarse.abs() / e_fine.abs()).ln() / ratio.ln()
}

/// Observed order from a quantity on three grids refined by `ratio` each time (no exact value
/// needed): `log(|q1 − q2| / |q2 − q3|) / log(ratio)`. Every convergence study uses this one.
pub fn observed_order_of_three(q_coarse: f64, q_medium: f64, q_fine: f64, ratio: f64) -> f64 {
    observed_order(q_coarse - q_medium, q_medium - q_fine, ratio)
}

#[cfg(test)]
mod comparison_tests {
    use super::*;

    #[test]
    fn separation_radius_inverts_the_hertz_gap() {
        // Hertz separation at r = 1.25 by hand: 0.78125 − 1 + (0.4375 asin 0.8 + 0.75)/π = 0.149118.
        assert!((separation_radius(0.149118) - 1.25).abs() < 1e-5);
    }
    use crate::Grid;

    #[test]
    fn comparison_of_the_exact_field_and_of_known_errors() {
        let g = Grid::square(201, 1.25);
        let exact = g.field(pressure);
        let c = compare(&g, &exact, APPROACH);
        assert_eq!((c.p_max, c.p_max_error, c.approach, c.approach_error), (1.0, 0.0, 1.0, 0.0));
        assert_eq!(c.pressure_l2_error, 0.0);
        // Cells with p > 0 cover the disc to within the ring of edge cells (ΔX = 0.0125).
        assert!(c.contact_radius_error.abs() < 0.0125, "{}", c.contact_radius_error);
        // Known errors: 1 % too much pressure everywhere, an approach 0.1 too deep.
        let c = compare(&g, &exact.mapv(|v| 1.01 * v), -1.1);
        assert!((c.p_max_error - 0.01).abs() < 1e-14 && (c.pressure_l2_error - 0.01).abs() < 1e-14);
        assert!((c.approach - 1.1).abs() < 1e-14 && (c.approach_error - 0.1).abs() < 1e-14);
        // A contact of radius 0.5: the area-equivalent radius halves.
        let half = g.field(|x, y| pressure(2.0 * x, 2.0 * y));
        let c = compare(&g, &half, APPROACH);
        assert!(
            (c.contact_radius - 0.5).abs() < 0.0125
                && (c.contact_radius_error + 0.5).abs() < 0.0125
        );
    }

    #[test]
    fn observed_orders() {
        // e = h²: halving h quarters the error.
        assert!((observed_order(4e-4, 1e-4, 2.0) - 2.0).abs() < 1e-12);
        assert!((observed_order(-3e-3, 1e-3, 3.0) - 1.0).abs() < 1e-12);
        // q = 1 + h: 1.4, 1.2, 1.1 -> first order.
        assert!((observed_order_of_three(1.4, 1.2, 1.1, 2.0) - 1.0).abs() < 1e-12);
        assert!(
            (observed_order_of_three(1.0 + 0.16, 1.0 + 0.04, 1.0 + 0.01, 2.0) - 2.0).abs() < 1e-12
        );
    }
}
