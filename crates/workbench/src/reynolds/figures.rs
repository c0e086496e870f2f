//! The Reynolds answer's figures: the pressure and film maps, the centreline, the flow and,
//! for a march, its history and snapshots.

use super::{ReynoldsOutcome, TransientRecord, TransientRow};
use crate::error::Result;
use crate::plot::{self, MapPanel, Mark, Panel, Series};
use ehl_core::hertz;
use ndarray::{Array2, Zip};
use std::path::{Path, PathBuf};

impl ReynoldsOutcome {
    fn note(&self) -> String {
        let (c, u) = self.scene.reynolds_conditions();
        // Where the solids touch at the end, the contact apart from the fluid.
        let touching = crate::model::Outcome::solid_contact(self)
            .filter(|c| c.area_m2 > 0.0)
            .map(|c| {
                format!(
                    "; the solids touch: {:.2e} of the load on {:.3e} m², contact pressure up to {:.4} GPa",
                    c.load_share,
                    c.area_m2,
                    c.max_pressure_pa * 1e-9
                )
            })
            .unwrap_or_default();
        format!(
            "{}: R = {} mm, F = {:.4} N, u1 = {:.4} m/s (M = {:.1}, L = {:.2}), {} viscosity, {} density; grid {}x{}{touching}",
            self.scene.name,
            c.ball_radius * 1e3,
            c.load,
            0.5 * u,
            self.prm.moes.m,
            self.prm.moes.l,
            crate::model::word(&self.view.spec.viscosity),
            crate::model::word(&self.view.spec.density),
            self.grid.nx,
            self.grid.ny
        )
    }

    /// The maps, the centreline and, for a march, the history and snapshots as PNG.
    pub fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
        let note = self.note() + footnote;
        let note = note.as_str();
        let g = &self.grid;
        let nm = self.prm.scales.delta * 1e9;
        let mut out = vec![];
        // Seed Fig. 4 analogue: pressure and film maps.
        let f = dir.join(format!("{prefix}maps.png"));
        // The colour scale stops at 3 h_c: the open gap outside the contact is two orders
        // thicker and would hide the horseshoe.
        let cap = 3.0 * self.films().0 * nm;
        let film_nm = self.film.mapv(|v| (v * nm).min(cap));
        plot::heat_maps(
            &f,
            &[
                MapPanel {
                    field: &self.p,
                    title: "Pressure p / p_h".into(),
                    bar_label: "p / p_h".into(),
                    diverging: false,
                },
                MapPanel {
                    field: &film_nm,
                    title: "Film h [nm] (scale capped at 3 h_c)".into(),
                    bar_label: "h [nm]".into(),
                    diverging: false,
                },
            ],
            g,
            note,
        )?;
        out.push(f);
        if let Some(xm) = self.meniscus_a() {
            // The oil where the gap is not full: the film content, and the oil layer it holds
            // (θ h), with the inlet meniscus on the centre line in the title.
            let f = dir.join(format!("{prefix}film_content.png"));
            let oil_nm = Zip::from(&self.theta).and(&self.film).map_collect(|&t, &h| t * h * nm);
            let cap = 3.0 * self.films().0 * nm;
            let oil_nm = oil_nm.mapv(|v| v.min(cap));
            plot::heat_maps(
                &f,
                &[
                    MapPanel {
                        field: &self.theta,
                        title: format!("Film content θ (1: full; inlet meniscus at x = {xm:.3} a)"),
                        bar_label: "θ".into(),
                        diverging: false,
                    },
                    MapPanel {
                        field: &oil_nm,
                        title: "Oil θ h [nm] (scale capped at 3 h_c)".into(),
                        bar_label: "θ h [nm]".into(),
                        diverging: false,
                    },
                ],
                g,
                note,
            )?;
            out.push(f);
        }
        let x = g.xs();
        let line = |v: Vec<f64>, k: f64| -> Vec<(f64, f64)> {
            x.iter().cloned().zip(v.into_iter().map(|y| y * k)).collect()
        };
        let f = dir.join(format!("{prefix}centreline.png"));
        plot::charts(
            &f,
            &[
                Panel::new(
                    "Pressure along y = 0",
                    "x / a",
                    "p / p_h",
                    vec![
                        Series::new("Reynolds", line(self.row(&self.p), 1.0), Mark::Line),
                        Series::new(
                            "dry contact (Hertz)",
                            x.iter().map(|&xx| (xx, hertz::pressure(xx, 0.0))).collect(),
                            Mark::Line,
                        ),
                    ],
                ),
                Panel::new(
                    "Film along y = 0",
                    "x / a",
                    "h [nm]",
                    vec![Series::new("Reynolds", line(self.row(&self.film), nm), Mark::Line)],
                ),
            ],
            note,
        )?;
        out.push(f);
        let f = dir.join(format!("{prefix}convergence.png"));
        let hist = &self.report.history;
        plot::charts(
            &f,
            &[Panel::new(
                "Cycle history",
                "W-cycle",
                "value",
                vec![
                    Series::new(
                        "RMS residual",
                        hist.iter().map(|c| (c.cycle as f64, c.residual)).collect(),
                        Mark::LinePoints,
                    ),
                    Series::new(
                        "|load error|",
                        hist.iter().map(|c| (c.cycle as f64, c.load_error.abs())).collect(),
                        Mark::LinePoints,
                    ),
                ],
            )
            .log_log()],
            note,
        )?;
        out.push(f);
        if let Some(t) = &self.transient {
            out.extend(self.transient_figures(t, dir, prefix, note)?);
        } else {
            // The seed's Fig. 1: the flow in the film (steady solutions only).
            out.extend(self.flow_figures(dir, prefix)?);
        }
        Ok(out)
    }

    fn transient_figures(
        &self,
        t: &TransientRecord,
        dir: &Path,
        prefix: &str,
        note: &str,
    ) -> Result<Vec<PathBuf>> {
        let s = &self.prm.scales;
        // Told by the first feature's position while features pass, else by time.
        let (axis, what) = if t.passing {
            ("dent centre x / a", "while the dent passes")
        } else {
            ("t [s]", "against time")
        };
        let abscissa =
            |r: &TransientRow| if t.passing { r.dent_x_m / self.prm.scales.a } else { r.t_s };
        let xs = |f: fn(&TransientRow) -> f64, k: f64| -> Vec<(f64, f64)> {
            t.rows.iter().map(|r| (abscissa(r), f(r) * k)).collect()
        };
        let f_hist = dir.join(format!("{prefix}history.png"));
        plot::history_chart(
            &f_hist,
            axis,
            &format!("Film {what}"),
            [
                ("central film", xs(|r| r.central_film_m, 1e9)),
                ("minimum film", xs(|r| r.minimum_film_m, 1e9)),
            ],
            &format!("Pressure {what}"),
            [
                ("maximum", xs(|r| r.max_pressure_pa, 1.0 / s.p_h)),
                ("central", xs(|r| r.central_pressure_pa, 1.0 / s.p_h)),
            ],
            note,
        )?;
        let label = |ts: f64, xd: f64| {
            if t.passing { format!("dent at {xd:.3} a") } else { format!("t = {ts:.4} s") }
        };
        let nm = s.delta * 1e9;
        let x = self.grid.xs();
        let j = self.grid.row_nearest(0.0);
        let line = |a: &Array2<f64>, k: f64| -> Vec<(f64, f64)> {
            x.iter().zip(a.row(j).iter()).map(|(&x, &v)| (x, v * k)).collect()
        };
        // Films above 3 central films of the steady start are the open gap: left off.
        let cap = 3.0 * self.report.history.last().map_or(f64::MAX, |c| c.central_film) * nm;
        let f_snap = dir.join(format!("{prefix}snapshots_centreline.png"));
        plot::charts(
            &f_snap,
            &[
                Panel::new(
                    "Pressure along y = 0",
                    "x / a",
                    "p / p_h",
                    t.snapshots
                        .iter()
                        .map(|(ts, xd, p, _)| {
                            Series::new(label(*ts, *xd), line(p, 1.0), Mark::Line)
                        })
                        .collect(),
                ),
                Panel::new(
                    "Film along y = 0",
                    "x / a",
                    "h [nm]",
                    t.snapshots
                        .iter()
                        .map(|(ts, xd, _, h)| {
                            let pts = line(h, nm).into_iter().filter(|v| v.1 <= cap).collect();
                            Series::new(label(*ts, *xd), pts, Mark::Line)
                        })
                        .collect(),
                ),
            ],
            note,
        )?;
        Ok(vec![f_hist, f_snap])
    }
}
