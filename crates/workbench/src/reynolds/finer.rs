//! Where a finer answer lies in a coarser grid, so that a check or an error estimate's coarser
//! grid starts from it (`run_reynolds_from`).

use super::ReynoldsOutcome;
use crate::model::Outcome;
use ehl_core::Grid;
use ehl_scene::Scene;

/// A finer answer that a coarser grid's steady solve starts from (an error estimate's coarser
/// grids, over the same domain; a domain check's, over a domain grown beyond it): its fields
/// taken at every `stride`-th point, the coarse grid's point `(j, i)` the finer answer's
/// `(stride (j − offset.0), stride (i − offset.1))` where that lies on it.
pub(super) struct FinerStart<'a> {
    pub(super) answer: &'a ReynoldsOutcome,
    stride: usize,
    offset: (usize, usize),
}

impl<'a> FinerStart<'a> {
    /// The start for `coarse` (the finer answer's scene on coarser cells) from `finer`'s
    /// answer: only a steady answer whose points, every `stride`-th, are points of the coarse
    /// grid, and whose domain the coarse one holds.
    pub(super) fn new(coarse: &Scene, finer: &'a dyn Outcome) -> Option<Self> {
        let answer = finer.inner().unwrap_or(finer).as_any().downcast_ref::<ReynoldsOutcome>()?;
        // The coarse scene is the finer answer's on coarser cells: a steady answer's is steady.
        if answer.transient.is_some() {
            return None;
        }
        let (stride, offset) = nested_in(&answer.grid, &coarse.grid())?;
        Some(Self { answer, stride, offset })
    }

    /// The finer answer's `P` [p_h] and `θ` at the coarse grid's point `(j, i)`, where it has one.
    pub(super) fn at(&self, j: usize, i: usize) -> Option<(f64, f64)> {
        let (k, a) = (self.stride, self.answer);
        let (fj, fi) = (k * j.checked_sub(self.offset.0)?, k * i.checked_sub(self.offset.1)?);
        (fj < a.grid.ny && fi < a.grid.nx).then(|| (a.p[[fj, fi]], a.theta[[fj, fi]]))
    }
}

/// Where the finer grid `f` lies in the coarser `c`: every `stride`-th point of `f` a point of
/// `c`, `f`'s first at `c`'s `offset` (rows, columns), all of `f` inside `c`; `None` otherwise.
fn nested_in(f: &Grid, c: &Grid) -> Option<(usize, (usize, usize))> {
    let stride = (c.dx() / f.dx()).round() as usize;
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9 * c.dx().max(c.dy());
    let cells = |from: f64, step: f64| {
        let k = (from / step).round();
        (k >= 0.0).then_some(k as usize)
    };
    let offset = (cells(f.y(0) - c.y(0), c.dy())?, cells(f.x(0) - c.x(0), c.dx())?);
    let nested = stride >= 1
        && near(c.dx(), stride as f64 * f.dx())
        && near(c.dy(), stride as f64 * f.dy())
        && near(f.y(0), c.y(offset.0))
        && near(f.x(0), c.x(offset.1))
        && (f.ny - 1).is_multiple_of(stride)
        && (f.nx - 1).is_multiple_of(stride)
        && offset.0 + (f.ny - 1) / stride < c.ny
        && offset.1 + (f.nx - 1) / stride < c.nx;
    nested.then_some((stride, offset))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finer_answer_is_placed_in_its_checks_grids_point_on_point() {
        let seed = ehl_scene::builtin("seed").unwrap().with_points(257).unwrap();
        let f = seed.grid();
        // The half grid over the same domain: every second point, from the corner.
        let half = crate::accuracy::rule::grid_check(&seed).grid();
        assert_eq!(nested_in(&f, &half), Some((2, (0, 0))));
        // The domain check: the half's cells over an inlet 1.5× as long and `y` grown alike,
        // the answer's last column on the grown grid's last, its rows in the middle.
        let grown = crate::accuracy::rule::domain_check(&seed).grid();
        let (stride, (oj, oi)) = nested_in(&f, &grown).unwrap();
        assert_eq!((stride, oi + 128, 2 * oj + 128), (2, grown.nx - 1, grown.ny - 1));
        for (i, j) in [(0, 0), (64, 40), (128, 128)] {
            assert!((grown.x(oi + i) - f.x(2 * i)).abs() < 1e-12);
            assert!((grown.y(oj + j) - f.y(2 * j)).abs() < 1e-12);
        }
        // Off the coarse grid's points by half a cell, starting inside the answer's domain, or
        // ending inside it: no placement.
        let shifted =
            Grid::new(129, 129, (-1.25 + 0.5 * half.dx(), 1.25 + 0.5 * half.dx()), (-1.25, 1.25));
        assert_eq!(nested_in(&f, &shifted), None);
        let smaller = Grid::new(65, 65, (-0.625, 0.625), (-0.625, 0.625));
        assert_eq!(nested_in(&f, &smaller), None);
        let short = Grid::new(65, 65, (-1.25, 0.0), (-1.25, 0.0));
        assert_eq!(nested_in(&f, &short), None);
    }
}
