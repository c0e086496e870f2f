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

/// The Hertz approach `H0 = −1` (the rigid-body term of the gap).
pub const APPROACH: f64 = -1.0;

#[cfg(test)]
mod tests {
    #[test]
    fn deflection_is_continuous_and_gap_opens_outside() {
        let (i, o) = (
            super::deflection(1.0 - 1e-12),
            super::deflection(1.0 + 1e-12),
        );
        assert!((i - o).abs() < 1e-5);
        assert!(super::gap(0.5) == 0.0 && super::gap(1.2) > 0.0);
    }
}
