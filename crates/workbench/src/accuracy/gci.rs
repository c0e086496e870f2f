//! The discretisation error of a sweep point's answer, estimated from three grids.
//!
//! A point runs on its grid (`h`), and its grid check on half the points per side (`2h`) and a
//! quarter (`4h`). With `f₁, f₂, f₃` an observable on the three, the change `e₂₁ = f₂ − f₁`
//! alone is the coarse answer's error more than the point's: at second order the point's own
//! error is a third of it. The three grids give the order the answer actually converges at,
//! `p = log₂((f₃ − f₂)/(f₂ − f₁))`, and with it the point's error, Roache's grid convergence
//! index (P. J. Roache, *Perspective: a method for uniform reporting of grid refinement
//! studies*, J. Fluids Eng. 116 (1994) 405–413; the procedure of I. B. Celik et al., J. Fluids
//! Eng. 130 (2008) 078001): `GCI = F_s |e₂₁/f₁| / (2^p − 1)`, `F_s = 1.25` with three grids.
//!
//! Guarded where the three grids do not show a converging answer:
//! - `p` is used at most 2, the schemes' formal order (a higher observed order is a lucky
//!   cancellation, not a rate to bank on), and at least 0.5 (below, the grids are far from the
//!   asymptotic range: the estimate is then `3.0 |e₂₁/f₁|`, larger than the change itself);
//! - when the changes alternate in sign or the quarter grid has no answer (a film that does
//!   not exist on it), the two-grid estimate with `F_s = 3` at order 2 is used:
//!   `3 |e₂₁/f₁| / 3 = |e₂₁/f₁|`, the change itself (what the sweeps flagged on before).

use serde::{Deserialize, Serialize};

/// Roache's safety factor with three grids and an observed order.
pub const SAFETY_THREE_GRIDS: f64 = 1.25;
/// The schemes' formal order: the most an observed order is credited with.
const FORMAL_ORDER: f64 = 2.0;
/// The least observed order credited (below it the estimate grows as if at this order).
const LEAST_ORDER: f64 = 0.5;

/// An observable's estimated discretisation error at a point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridError {
    /// The order observed on the three grids; `None` when they do not show one (the changes
    /// alternate in sign, or the quarter grid had no answer).
    pub order: Option<f64>,
    /// The estimated relative error of the point's answer (the grid convergence index).
    pub error: f64,
}

/// The half-grid change whose estimated error at the schemes' order is `error`: the inverse of
/// the grid convergence index, `error (2^2 − 1) / 1.25` (4.8 % for 2 %). What the grid rule asks
/// the central film's change to stay within ([`ehl_reynolds::formulas::cell_for_change`]).
pub fn change_allowed(error: f64) -> f64 {
    error * (FORMAL_ORDER.exp2() - 1.0) / SAFETY_THREE_GRIDS
}

/// The estimated error of `f1` (the point's answer) relative to `scale` (its own value, or the
/// film's scale for a minimum film) from `f2` (half the points per side) and `f3` (a quarter,
/// when it answered); `None` when the change is not a number (a zero scale).
pub fn grid_error(f1: f64, f2: f64, f3: Option<f64>, scale: f64) -> Option<GridError> {
    let e21 = f2 - f1;
    let change = (e21 / scale).abs();
    if !change.is_finite() {
        return None;
    }
    // Only changes of one sign converge to a limit the order describes.
    let order = f3
        .filter(|f3| ((f3 - f2) / e21).is_finite() && (f3 - f2) / e21 > 0.0)
        .map(|f3| ehl_core::hertz::observed_order_of_three(f3, f2, f1, 2.0));
    let error = match order {
        Some(p) => {
            let p = p.clamp(LEAST_ORDER, FORMAL_ORDER);
            SAFETY_THREE_GRIDS * change / (p.exp2() - 1.0)
        }
        None => change,
    };
    Some(GridError { order, error })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f(h) = f₀ + C hᵖ` on `h`, `2h`, `4h`.
    fn series(f0: f64, c: f64, p: f64) -> (f64, f64, f64) {
        let f = |h: f64| f0 + c * h.powf(p);
        (f(0.01), f(0.02), f(0.04))
    }

    #[test]
    fn a_second_order_answer_has_its_order_observed_and_its_error_bounded_by_1_25_times_the_truth()
    {
        let (f1, f2, f3) = series(4.2, -1000.0, 2.0);
        let g = grid_error(f1, f2, Some(f3), f1).unwrap();
        // Exact series: the order to rounding.
        assert!((g.order.unwrap() - 2.0).abs() < 1e-9, "{g:?}");
        let truth = ((f1 - 4.2) / f1).abs();
        assert!((g.error / truth - 1.25).abs() < 1e-9, "{g:?} against {truth}");
    }

    #[test]
    fn a_higher_observed_order_is_credited_only_the_formal_second() {
        let (f1, f2, f3) = series(4.2, -1e5, 3.0);
        let g = grid_error(f1, f2, Some(f3), f1).unwrap();
        assert!((g.order.unwrap() - 3.0).abs() < 1e-9);
        // At order 2 the error is a third of the change, times 1.25: more than the truth (a
        // seventh of the change at order 3).
        let change = ((f2 - f1) / f1).abs();
        assert!((g.error - 1.25 * change / 3.0).abs() < 1e-12);
        assert!(g.error > ((f1 - 4.2) / f1).abs());
    }

    #[test]
    fn changes_that_hardly_shrink_give_an_error_larger_than_the_change() {
        let (f1, f2, f3) = series(4.2, -10.0, 0.2);
        let g = grid_error(f1, f2, Some(f3), f1).unwrap();
        let change = ((f2 - f1) / f1).abs();
        assert!((g.order.unwrap() - 0.2).abs() < 1e-9);
        assert!((g.error - 1.25 * change / (0.5f64.exp2() - 1.0)).abs() < 1e-12);
        assert!(g.error > 3.0 * change);
    }

    #[test]
    fn alternating_changes_or_no_quarter_grid_fall_back_to_the_change_itself() {
        let g = grid_error(4.0, 3.5, Some(3.8), 4.0).unwrap();
        assert_eq!(g.order, None);
        assert!((g.error - 0.125).abs() < 1e-12);
        let g = grid_error(4.0, 3.5, None, 4.0).unwrap();
        assert_eq!(g.order, None);
        assert!((g.error - 0.125).abs() < 1e-12);
    }

    #[test]
    fn a_zero_scale_has_no_relative_error_and_a_film_scale_judges_a_minimum_near_zero() {
        assert_eq!(grid_error(0.0, 1e-9, Some(2e-9), 0.0), None);
        // A minimum film of -0.0005 nm against -0.0001 nm on the half grid (the layer squeezed
        // out, the solids touching) is 4e-4 nm of a 1.25 nm film, not a 300 % change.
        let g = grid_error(-5e-13, -1e-13, None, 1.25e-9).unwrap();
        assert!((g.error - 3.2e-4).abs() < 1e-12, "{g:?}");
    }
}
