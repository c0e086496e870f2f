//! The flow inside a Reynolds film (the seed's Fig. 1): why a layer can stand in for the oil.
//!
//! In the film the velocity is Couette plus Poiseuille. With both surfaces at the mean velocity
//! `u_m` (pure rolling) and `ζ = z / h`: `u / u_m = 1 + 6 r_x (ζ² − ζ)`, where
//! `r = h² ∇p / (12 η u_m)` is the pressure-driven flux over the boundary-driven flux
//! (`q = u_m h (1 − r_x)` along `x`). In the Reynolds solver's Hertz units this is
//! `r = H² ∇P / (η̄ λ̄)`, the same ratio as `ε̄ |∇P| / (ρ̄ H)` of its equation. Where `|r| ≪ 1`
//! the oil moves as a solid layer with the surfaces: the layer model's premise.

use super::ReynoldsOutcome;
use crate::error::Result;
use crate::plot::{self, MapPanel, Mark, Panel, Series};
use ndarray::Array2;
use std::path::{Path, PathBuf};

/// The indicator's name in `Outcome::indicators` (and in sweep results).
pub const FLUX_INDICATOR: &str = "flux_ratio_contact_mean";

/// Where the flux ratio is averaged: the loaded zone, `p ≥` this [p_h] (the observables'
/// contact-extent threshold).
pub const LOADED: f64 = ehl_core::observe::EXTENT_THRESHOLD;

impl ReynoldsOutcome {
    /// `(r_x, r_y)`: pressure-driven over boundary-driven flux, signed, per node (central
    /// differences; 0 on the boundary and where the film is closed).
    pub fn flux_ratio_components(&self) -> (Array2<f64>, Array2<f64>) {
        let (ny, nx) = self.p.dim();
        let (dx, dy) = (self.grid.dx(), self.grid.dy());
        let (mut rx, mut ry) = (Array2::zeros((ny, nx)), Array2::zeros((ny, nx)));
        for j in 1..ny - 1 {
            for i in 1..nx - 1 {
                let film = self.film[[j, i]].max(0.0);
                let k =
                    film * film / (self.prm.viscosity.eta(self.p[[j, i]]) * self.prm.lambda_bar);
                rx[[j, i]] = k * (self.p[[j, i + 1]] - self.p[[j, i - 1]]) / (2.0 * dx);
                ry[[j, i]] = k * (self.p[[j + 1, i]] - self.p[[j - 1, i]]) / (2.0 * dy);
            }
        }
        (rx, ry)
    }

    /// `|r|`: the magnitude of the pressure-driven flux over the boundary-driven flux.
    pub fn flux_ratio(&self) -> Array2<f64> {
        let (rx, ry) = self.flux_ratio_components();
        ndarray::Zip::from(&rx).and(&ry).map_collect(|a, b| a.hypot(*b))
    }

    /// Mean `|r|` over the loaded zone (`p ≥ 0.01 p_h`): one number for how far the flow in
    /// the contact is from a solid layer's (0: pure rolling of a solid layer).
    pub fn flux_ratio_contact_mean(&self) -> f64 {
        let r = self.flux_ratio();
        let (sum, n) = r
            .iter()
            .zip(self.p.iter())
            .filter(|(_, p)| **p >= LOADED)
            .fold((0.0, 0usize), |(s, n), (r, _)| (s + r, n + 1));
        if n == 0 { 0.0 } else { sum / n as f64 }
    }

    /// The velocity profile `u / u_m` at `ζ = z/h` for the signed ratio `r_x` (pure rolling).
    pub fn velocity(r_x: f64, zeta: f64) -> f64 {
        1.0 + 6.0 * r_x * (zeta * zeta - zeta)
    }

    /// The seed's Fig. 1 from this solution: velocity profiles across the film and velocity
    /// vectors along the centreline, and the map of `|r|`.
    pub fn flow_figures(&self, dir: &Path, prefix: &str) -> Result<Vec<PathBuf>> {
        let g = &self.grid;
        let j0 = g.row_nearest(0.0);
        let (rx, _) = self.flux_ratio_components();
        let nm = self.prm.scales.delta * 1e9;
        let stations: Vec<f64> = [-1.2, -1.05, -0.9, 0.0, 0.9, 1.05]
            .into_iter()
            .filter(|&x| x > g.x_min + 2.0 * g.dx() && x < g.x_max - 2.0 * g.dx())
            .collect();
        let zetas: Vec<f64> = (0..=20).map(|k| k as f64 / 20.0).collect();
        let profiles: Vec<Series> = stations
            .iter()
            .map(|&x| {
                let i = g.col_nearest(x);
                let r = rx[[j0, i]];
                Series::new(
                    format!("x = {x} a (r_x = {r:+.3})"),
                    zetas.iter().map(|&z| (Self::velocity(r, z), z)).collect(),
                    Mark::Line,
                )
            })
            .collect();
        // Vectors: horizontal arrows at five heights across the film at each station, length
        // u / u_m × 0.15 a; the film's upper surface drawn through them.
        let arrows_x: Vec<f64> = (0..=16)
            .map(|k| -1.4 + 2.8 * k as f64 / 16.0)
            .filter(|&x| x > g.x_min && x < g.x_max)
            .collect();
        let film_row: Vec<(f64, f64)> = (0..g.nx)
            .map(|i| (g.x(i), self.film[[j0, i]] * nm))
            .filter(|(x, _)| (-1.5..=1.5).contains(x))
            .collect();
        let h_cap = 4.0 * self.film[[j0, g.col_nearest(0.0)]] * nm;
        let mut vectors = vec![Series::new(
            "film surface h(x)",
            film_row.into_iter().map(|(x, h)| (x, h.min(h_cap))).collect(),
            Mark::Line,
        )];
        let mut shafts = vec![];
        for &x in &arrows_x {
            let i = g.col_nearest(x);
            let h = (self.film[[j0, i]] * nm).min(h_cap);
            for k in 1..=5 {
                let z = k as f64 / 6.0;
                let len = 0.15 * Self::velocity(rx[[j0, i]], z);
                let y = z * h;
                shafts.push((x, y, len, h_cap));
            }
        }
        // Each arrow: the shaft and two head strokes, as segments.
        let mut arrow_pts = vec![];
        for (x, y, len, cap) in shafts {
            let head = 0.03 * cap;
            let tip = x + len;
            let back = tip - 0.03 * len.signum();
            arrow_pts.extend([
                (x, y),
                (tip, y),
                (back, y + head),
                (tip, y),
                (back, y - head),
                (tip, y),
            ]);
        }
        vectors.push(Series::new("u(z): length 0.15 a per u_m", arrow_pts, Mark::Segments));
        let f = dir.join(format!("{prefix}flow.png"));
        let note = format!(
            "{}; r = pressure-driven / boundary-driven flux, mean |r| over p >= 0.01 p_h: {:.4}",
            self.scene.name,
            self.flux_ratio_contact_mean()
        );
        plot::charts(
            &f,
            &[
                Panel::new("Velocity across the film, y = 0", "u / u_m", "z / h", profiles)
                    .legend(plotters::prelude::SeriesLabelPosition::UpperLeft),
                Panel::new(
                    &format!("Velocity vectors along y = 0 (film capped at {h_cap:.0} nm)"),
                    "x / a",
                    "z [nm]",
                    vectors,
                ),
            ],
            &note,
        )?;
        let map = dir.join(format!("{prefix}flux_ratio_map.png"));
        let log_r = self.flux_ratio().mapv(|r| r.max(1e-4).log10());
        plot::heat_maps(
            &map,
            &[MapPanel {
                field: &log_r,
                title: "log10 |pressure-driven / boundary-driven flux|".into(),
                bar_label: "log10 |r|".into(),
                diverging: false,
            }],
            g,
            &note,
        )?;
        Ok(vec![f, map])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_carries_the_flux_the_ratio_says() {
        // ∫₀¹ u/u_m dζ = 1 − r_x (trapezoid on 2000 intervals: error ~1e-7 for this quadratic).
        for r in [-0.7, 0.0, 0.3, 2.0] {
            let n = 2000;
            let q: f64 = (0..n)
                .map(|k| {
                    let (a, b) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
                    0.5 * (ReynoldsOutcome::velocity(r, a) + ReynoldsOutcome::velocity(r, b))
                        / n as f64
                })
                .sum();
            assert!((q - (1.0 - r)).abs() < 1e-6, "r {r}: flux {q}");
            // No slip: both surfaces move at u_m.
            assert_eq!(
                (ReynoldsOutcome::velocity(r, 0.0), ReynoldsOutcome::velocity(r, 1.0)),
                (1.0, 1.0)
            );
        }
    }
}
