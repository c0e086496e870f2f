//! Reynolds-model scenes: the steady EHL solve and what it writes.

use crate::output::{Centreline, q};
use crate::plot::{self, MapPanel, Mark, Panel, Series};
use anyhow::{Result, bail};
use ehl_core::{Grid, hertz};
use ehl_reynolds::formulas::{hamrock_dowson_central, nvm_central};
use ehl_reynolds::{ReynoldsParams, ReynoldsReport, ReynoldsSolver};
use ehl_scene::Scene;
use ndarray::Array2;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub struct ReynoldsOutcome {
    pub scene: Scene,
    pub prm: ReynoldsParams,
    pub grid: Grid,
    /// Pressure `P` [p_h] and film `H` [a²/R].
    pub p: Array2<f64>,
    pub film: Array2<f64>,
    pub h00: f64,
    pub report: ReynoldsReport,
    /// Central film from the formulas [m]: Hamrock–Dowson, NVM.
    pub formulas: (f64, f64),
    pub setup_time_s: f64,
}

/// The dimensionless parameters and a solver (hierarchy built, Hertz start) for a Reynolds
/// scene.
pub fn build_solver(scene: &Scene) -> (ReynoldsParams, ReynoldsSolver) {
    let spec = scene.reynolds.expect("validated");
    let lub = scene.lubricant.expect("validated").lubricant();
    let (contact, u_sum) = scene.reynolds_conditions();
    let prm = ReynoldsParams::from_si(&contact, &lub, u_sum, spec.viscosity, spec.density);
    (prm, ReynoldsSolver::new(scene.grid(), prm, spec.solver))
}

pub fn run_reynolds(scene: &Scene) -> Result<ReynoldsOutcome> {
    let lub = scene.lubricant.expect("validated").lubricant();
    let (contact, u_sum) = scene.reynolds_conditions();
    let grid = scene.grid();
    let t0 = Instant::now();
    let (prm, mut solver) = build_solver(scene);
    let setup_time_s = t0.elapsed().as_secs_f64();
    let spin = crate::progress::spinner("reynolds");
    let report = solver.solve(&mut |c| {
        spin.set_message(format!(
            "cycle {}: H_c {:.5}, load error {:+.1e}",
            c.cycle, c.central_film, c.load_error
        ))
    })?;
    spin.finish_and_clear();
    if !report.converged {
        // Nothing is written for a solve that did not converge: say what happened instead.
        bail!(
            "scene `{}`: the Reynolds solve did not converge: {}",
            scene.name,
            report.diagnosis.clone().unwrap_or_default()
        );
    }
    let formulas =
        (hamrock_dowson_central(&contact, &lub, 0.5 * u_sum), nvm_central(&contact, &lub, u_sum));
    let f = &solver.levels[0];
    Ok(ReynoldsOutcome {
        scene: scene.clone(),
        prm,
        grid,
        p: f.p.clone(),
        film: f.film.clone(),
        h00: solver.h00,
        report,
        formulas,
        setup_time_s,
    })
}

impl ReynoldsOutcome {
    /// Central and minimum film [a²/R], maximum pressure [p_h].
    pub fn films(&self) -> (f64, f64, f64) {
        let g = &self.grid;
        let hc = self.film[[g.row_nearest(0.0), g.col_nearest(0.0)]];
        let hmin = self.film.iter().cloned().fold(f64::INFINITY, f64::min);
        let pmax = self.p.iter().cloned().fold(0.0, f64::max);
        (hc, hmin, pmax)
    }

    /// A film in Hertz units to Moes' `h/R · U^(−1/2)` (U with the sum velocity).
    fn moes_film(&self, h: f64) -> f64 {
        h * (1.5 * self.prm.moes.m).powf(2.0 / 3.0)
    }

    pub fn summary(&self) -> Value {
        let s = &self.prm.scales;
        let (hc, hmin, pmax) = self.films();
        let (contact, u_sum) = self.scene.reynolds_conditions();
        let last = self.report.history.last().unwrap();
        json!({
            "scene": self.scene.name,
            "model": "reynolds",
            "description": self.scene.description,
            "conditions_used": {
                "ball_radius": q(contact.ball_radius, "m"), "load": q(contact.load, "N"),
                "reduced_modulus": q(contact.reduced_modulus, "Pa"), "sum_velocity": q(u_sum, "m/s"),
                "moes_m": self.prm.moes.m, "moes_l": self.prm.moes.l, "lambda_bar": self.prm.lambda_bar,
            },
            "lubricant": self.scene.lubricant,
            "laws": { "viscosity": self.scene.reynolds.unwrap().viscosity, "density": self.scene.reynolds.unwrap().density },
            "scales": { "a": q(s.a, "m"), "p_h": q(s.p_h, "Pa"), "a2_over_r": q(s.delta, "m") },
            "grid": { "nx": self.grid.nx, "ny": self.grid.ny, "dx": q(self.grid.dx() * s.a, "m") },
            "results": {
                "central_film": q(s.h_si(hc), "m"),
                "minimum_film": q(s.h_si(hmin), "m"),
                "max_pressure": q(s.p_si(pmax), "Pa"),
                "h00": q(s.h_si(self.h00), "m"),
            },
            "dimensionless": {
                "central_film_hertz": hc, "minimum_film_hertz": hmin, "h00_hertz": self.h00,
                "central_film_moes": self.moes_film(hc), "minimum_film_moes": self.moes_film(hmin),
                "max_pressure_over_p_h": pmax,
            },
            "formulas_central_film": {
                "hamrock_dowson_1977": q(self.formulas.0, "m"),
                "nijenbanning_venner_moes_1994": q(self.formulas.1, "m"),
            },
            "solver": {
                "settings": self.scene.reynolds.unwrap().solver,
                "cycles": self.report.cycles,
                "final_residual": last.residual,
                "final_load_error": last.load_error,
                "history": self.report.history,
                "setup_time": q(self.setup_time_s, "s"),
                "solve_time": q(self.report.wall_time_s, "s"),
            },
        })
    }

    fn row(&self, f: &Array2<f64>) -> Vec<f64> {
        f.row(self.grid.row_nearest(0.0)).to_vec()
    }

    pub fn centreline(&self) -> Centreline {
        let s = &self.prm.scales;
        let xs = self.grid.xs();
        Centreline {
            columns: vec![
                ("x_m".into(), xs.iter().map(|&x| s.x_si(x)).collect()),
                ("pressure_pa".into(), self.row(&self.p).iter().map(|&v| s.p_si(v)).collect()),
                ("film_m".into(), self.row(&self.film).iter().map(|&v| s.h_si(v)).collect()),
                (
                    "pressure_dry_hertz_pa".into(),
                    xs.iter().map(|&x| s.p_si(hertz::pressure(x, 0.0))).collect(),
                ),
            ],
        }
    }

    pub fn fields(&self) -> Vec<(String, Array2<f64>)> {
        let s = &self.prm.scales;
        vec![
            ("pressure_pa".into(), self.p.mapv(|v| s.p_si(v))),
            ("film_m".into(), self.film.mapv(|v| s.h_si(v))),
        ]
    }

    fn note(&self) -> String {
        let (c, u) = self.scene.reynolds_conditions();
        format!(
            "{}: M = {:.1}, L = {:.2} (F = {:.3} N, u_s = {:.4} m/s), {:?} viscosity, {:?} density; grid {}x{}",
            self.scene.name,
            self.prm.moes.m,
            self.prm.moes.l,
            c.load,
            u,
            self.scene.reynolds.unwrap().viscosity,
            self.scene.reynolds.unwrap().density,
            self.grid.nx,
            self.grid.ny
        )
    }

    pub fn figures(&self, dir: &Path, prefix: &str) -> Result<Vec<PathBuf>> {
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
                },
                MapPanel {
                    field: &film_nm,
                    title: "Film h [nm] (scale capped at 3 h_c)".into(),
                    bar_label: "h [nm]".into(),
                },
            ],
            (g.x_min, g.x_max),
            (g.y_min, g.y_max),
            "x / a",
            "y / a",
            &self.note(),
        )?;
        out.push(f);
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
            &self.note(),
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
            &self.note(),
        )?;
        out.push(f);
        Ok(out)
    }
}
