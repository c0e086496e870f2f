//! The standard observables every model reports, defined once: what `ehl compare` puts side by
//! side, so a difference between models is a difference of physics, not of bookkeeping.

use crate::{Grid, HertzScales};
use ndarray::Array2;
use serde::{Deserialize, Serialize};

/// Pressure threshold of the contact extent, as a fraction of `p_h`. A Reynolds pressure is
/// positive far into the inlet (0.001 `p_h` at 1.5 `a` for the seed), a dry or layer pressure is
/// zero outside the contact: 1 % of `p_h` marks the loaded zone for all alike.
pub const EXTENT_THRESHOLD: f64 = 0.01;

/// The standard observables an error is estimated for, as tables name them, with their unit.
pub const OBSERVED: [(&str, &str); 5] =
    [("h_c", "m"), ("h_min", "m"), ("p_max", "Pa"), ("2a_x", "m"), ("2a_y", "m")];

/// A model's answer in SI.
///
/// A film is the separation of the two solid surfaces (the layer model's layer plus any gap
/// above it; the Reynolds film; the dry gap), so it is never below zero: where the solids
/// touch it is zero, and the contact carries the load there. A model whose field goes below
/// zero somewhere (a film too thin for its grid, a contact solved to its tolerance) reports
/// the film there as zero and the depth it went below as [`Observables::film_overlap_m`]: the
/// solids' overlap, a discretisation error of the answer, not a film.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Observables {
    /// Film at the contact centre `(0, 0)` [m], at least 0.
    pub central_film_m: f64,
    /// Smallest film over the domain [m], at least 0 (0: the solids touch somewhere).
    pub minimum_film_m: f64,
    /// Where the minimum film is: `(x, y)` [m] (the deepest overlap's place when there is one).
    pub minimum_film_at_m: (f64, f64),
    /// How far the model's film field went below zero [m] (the solids' overlap, at the place
    /// of the minimum film): 0 for a film that exists everywhere. A discretisation error (a
    /// grid too coarse for the thinnest film, or a contact's tolerance), reported with the
    /// answer's error rather than as a negative film.
    #[serde(default)]
    pub film_overlap_m: f64,
    /// Largest pressure [Pa] and where, `(x, y)` [m].
    pub max_pressure_pa: f64,
    /// Where the maximum pressure is: `(x, y)` [m].
    pub max_pressure_at_m: (f64, f64),
    /// Extent of `p ≥ 0.01 p_h` along `y = 0` and along `x = 0` [m], the crossings linearly
    /// interpolated between nodes.
    pub contact_extent_x_m: f64,
    /// Contact extent along `x = 0` [m] (where `p ≥ 1 %` of `p_h`).
    pub contact_extent_y_m: f64,
    /// `∬p / F − 1`.
    pub load_error: f64,
}

/// One observable's estimated error.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorBar {
    /// The estimated error relative to the observable's scale (its value; a film's over the
    /// film's scale).
    pub relative: f64,
    /// The same in the observable's unit (m, Pa): the answer's `±`.
    pub absolute: f64,
    /// The order the three grids converge at, when they show one.
    pub order: Option<f64>,
}

/// An answer's estimated discretisation errors, and how they were found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Points per side of the answer's grid and of the coarser grids that answered.
    pub grids: Vec<usize>,
    /// Per observable of [`OBSERVED`] (`h_c`, `h_min`, `p_max`, `2a_x`, `2a_y`): its error bar, `None` where undefined (the dry
    /// contact's films) or where no coarser grid answered.
    pub errors: [Option<ErrorBar>; 5],
    /// How the errors were estimated, in words (three grids; two with the order assumed; or
    /// why none could be).
    pub method: String,
    /// The coarser runs' wall time [s].
    pub wall_time_s: f64,
    /// A march through a patterned relief: the errors of its last passage's statistics, from
    /// the same passage on the coarser grids (all `None` without a passage, or where no
    /// coarser grid carried the pattern through one).
    #[serde(default)]
    pub passage: PassageErrors,
}

/// The estimated errors of a march's last passage ([`crate::Passage`]), each `None` where the
/// answer or no coarser grid has the statistic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PassageErrors {
    /// The mean central film (and with it `λ`, the same relative error), relative to the
    /// film's scale; `absolute` in m.
    pub central_film_mean: Option<ErrorBar>,
    /// The solids' mean share of the load, relative to the share's scale (the share, at least
    /// a thousandth of the load); `absolute` as a fraction of the load.
    pub contact_load_share_mean: Option<ErrorBar>,
    /// Their mean area, relative to the area's scale (the area, at least a thousandth of the
    /// Hertz area); `absolute` in m².
    pub contact_area_mean: Option<ErrorBar>,
    /// A single wave's `A_d/A_i`, relative to it; `absolute` in the ratio's unit, 1.
    pub amplitude_ratio: Option<ErrorBar>,
}

impl PassageErrors {
    /// No statistic of the passage carries an error: no coarser grid carried it through.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// The statistics an accuracy is asked of, with their names: the mean central film, the
    /// solids' mean share of the load, a wave's `A_d/A_i` (the area follows the share).
    pub fn judged(&self) -> [(&'static str, Option<ErrorBar>); 3] {
        [
            ("the last passage's mean h_c", self.central_film_mean),
            (
                "the solids' mean share of the load over the last passage",
                self.contact_load_share_mean,
            ),
            ("A_d/A_i of the last passage", self.amplitude_ratio),
        ]
    }
}

impl Estimate {
    /// The largest relative error of the central film, minimum film and maximum pressure (the
    /// observables an accuracy is asked of); `None` when none was estimated.
    pub fn worst(&self) -> Option<f64> {
        self.errors[..3].iter().flatten().map(|e| e.relative).reduce(f64::max)
    }
}

/// Length of the zone where `v ≥ thr` along a line of samples at spacing `h` [same unit as h]:
/// from the first crossing to the last, each interpolated linearly; 0 when `v < thr` everywhere.
pub fn extent(v: &[f64], h: f64, thr: f64) -> f64 {
    let (Some(first), Some(last)) =
        (v.iter().position(|&p| p >= thr), v.iter().rposition(|&p| p >= thr))
    else {
        return 0.0;
    };
    // Fraction of the cell before `first` (after `last`) that lies above the threshold.
    let lead = if first > 0 { (v[first] - thr) / (v[first] - v[first - 1]) } else { 0.0 };
    let trail = if last + 1 < v.len() { (v[last] - thr) / (v[last] - v[last + 1]) } else { 0.0 };
    ((last - first) as f64 + lead + trail) * h
}

impl Observables {
    /// The observables of [`OBSERVED`], in its order (SI).
    pub fn standard(&self) -> [f64; 5] {
        [
            self.central_film_m,
            self.minimum_film_m,
            self.max_pressure_pa,
            self.contact_extent_x_m,
            self.contact_extent_y_m,
        ]
    }

    /// From the pressure `P` [p_h] and film `H` [a²/R] on `grid` (units of `a`).
    pub fn from_fields(
        grid: &Grid,
        scales: &HertzScales,
        p: &Array2<f64>,
        film: &Array2<f64>,
    ) -> Self {
        let (jc, ic) = (grid.row_nearest(0.0), grid.col_nearest(0.0));
        let mut hmin = (f64::INFINITY, 0, 0);
        for ((j, i), &h) in film.indexed_iter() {
            if h < hmin.0 {
                hmin = (h, j, i);
            }
        }
        let mut pmax = (f64::NEG_INFINITY, 0, 0);
        for ((j, i), &v) in p.indexed_iter() {
            if v > pmax.0 {
                pmax = (v, j, i);
            }
        }
        let row: Vec<f64> = p.row(jc).to_vec();
        let col: Vec<f64> = p.column(ic).to_vec();
        let load = p.sum() * grid.cell_area() / scales.load_dimensionless();
        let at = |j: usize, i: usize| (scales.x_si(grid.x(i)), scales.x_si(grid.y(j)));
        Self {
            central_film_m: scales.h_si(film[[jc, ic]]).max(0.0),
            minimum_film_m: scales.h_si(hmin.0).max(0.0),
            minimum_film_at_m: at(hmin.1, hmin.2),
            film_overlap_m: scales.h_si(-hmin.0).max(0.0),
            max_pressure_pa: scales.p_si(pmax.0),
            max_pressure_at_m: at(pmax.1, pmax.2),
            contact_extent_x_m: scales.x_si(extent(&row, grid.dx(), EXTENT_THRESHOLD)),
            contact_extent_y_m: scales.x_si(extent(&col, grid.dy(), EXTENT_THRESHOLD)),
            load_error: load - 1.0,
        }
    }
}

/// Where the solids touch in an answer (the film closed, the load carried by the solids
/// there rather than by a fluid): the contact's own load, area and pressure, reported apart
/// from the fluid's. Zero everywhere for a film that separates the surfaces everywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SolidContact {
    /// The share of the load the contact carries `∬_contact p / ∬ p` [-].
    pub load_share: f64,
    /// The area where the solids touch [m²].
    pub area_m2: f64,
    /// The largest contact pressure [Pa] (0 without contact).
    pub max_pressure_pa: f64,
}

impl SolidContact {
    /// From the pressure `P` [p_h] on `grid` and the points where the solids touch: those that
    /// carry pressure (a point whose gap closed at `P = 0` is the contact's edge, carrying
    /// nothing).
    pub fn from_mask(
        grid: &Grid,
        scales: &HertzScales,
        p: &Array2<f64>,
        touching: &Array2<bool>,
    ) -> Self {
        let (mut on, mut n, mut peak) = (0.0, 0usize, 0.0f64);
        for (&v, &t) in p.iter().zip(touching) {
            if t && v > 0.0 {
                on += v;
                n += 1;
                peak = peak.max(v);
            }
        }
        let all = p.sum();
        Self {
            load_share: if all > 0.0 { on / all } else { 0.0 },
            area_m2: n as f64 * grid.cell_area() * scales.a * scales.a,
            max_pressure_pa: scales.p_si(peak),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_film_below_zero_is_reported_as_zero_with_its_overlap() {
        // A Hertz-like pressure and a film that dips to -0.02 a²/R off centre: the minimum film
        // is 0 (the solids touch) and the overlap is the dip, in metres; the centre keeps its
        // positive film.
        let grid = Grid::new(33, 33, (-1.5, 1.5), (-1.5, 1.5));
        let scales = HertzScales::new(&crate::SEED_CONTACT);
        let p = grid.field(|x, y| (1.0 - x * x - y * y).max(0.0).sqrt());
        let mut film = grid.field(|_, _| 0.1);
        film[[16, 30]] = -0.02;
        let o = Observables::from_fields(&grid, &scales, &p, &film);
        assert_eq!(o.minimum_film_m, 0.0);
        assert!((o.film_overlap_m - scales.h_si(0.02)).abs() < 1e-20, "{o:?}");
        assert!((o.central_film_m - scales.h_si(0.1)).abs() < 1e-20);
        assert!((o.minimum_film_at_m.0 - scales.x_si(grid.x(30))).abs() < 1e-15);
        // A film that exists everywhere has no overlap.
        let o = Observables::from_fields(&grid, &scales, &p, &grid.field(|_, _| 0.1));
        assert_eq!(o.film_overlap_m, 0.0);
        assert!(o.minimum_film_m > 0.0);
    }

    #[test]
    fn extent_interpolates_the_crossings() {
        // sqrt(1 - x²) sampled at 0.1: the extent of >= 0.01 is 2 sqrt(1 - 1e-4) = 1.9999,
        // the linear interpolation in the last cell before the edge errs by < a cell's fraction.
        let h = 0.1;
        let v: Vec<f64> =
            (0..31).map(|k| (1.0 - (-1.5 + k as f64 * h).powi(2)).max(0.0).sqrt()).collect();
        let e = extent(&v, h, 0.01);
        assert!((e - 2.0).abs() < 0.05, "{e}");
        // A step exactly at nodes: from node 2 to node 5 is 3 cells, plus the interpolated
        // fractions (v = 1 at the nodes, 0 beside: (1 - 0.5)/1 = 0.5 each side).
        let v = [0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0];
        assert!((extent(&v, 1.0, 0.5) - 4.0).abs() < 1e-12);
        assert_eq!(extent(&[0.0; 5], 1.0, 0.5), 0.0);
        assert_eq!(extent(&[1.0; 5], 1.0, 0.5), 4.0);
    }
}
