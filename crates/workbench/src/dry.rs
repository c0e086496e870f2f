//! The dry contact as a workbench model: the contact core alone, checked against Hertz.

use crate::error::{Result, Within};
use crate::model::{Centreline, ContactModel, Outcome, q};
use crate::plot::{self, Mark, Panel, Series};
use ehl_core::hertz::{self, Comparison};
use ehl_core::{DryProblem, DryReport, DrySolver, Grid, HertzScales, Start};
use ehl_scene::Scene;
use ndarray::Array2;
use serde_json::{Map, Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The registered dry model.
pub struct Dry;

impl ContactModel for Dry {
    fn kind(&self) -> ehl_scene::Model {
        ehl_scene::Model::Dry
    }
    fn run(&self, scene: &Scene) -> Result<Box<dyn Outcome>> {
        Ok(Box::new(run_dry(scene)?))
    }
}

/// A dry contact solution, in Hertz units, with its comparison against Hertz.
pub struct DryOutcome {
    /// The scene run.
    pub scene: Scene,
    /// Hertz scales.
    pub scales: HertzScales,
    /// The grid [a].
    pub grid: Grid,
    /// Pressure `P` [p_h].
    pub p: Array2<f64>,
    /// Elastic deformation `W` [a²/R].
    pub w: Array2<f64>,
    /// Gap `H` [a²/R].
    pub gap: Array2<f64>,
    /// The solver's report.
    pub report: DryReport,
    /// The answer against Hertz's.
    pub hertz: Comparison,
    /// Building the operators (kernel spectra, FFT plans) [s].
    pub setup_time_s: f64,
    /// The solve itself [s].
    pub solve_time_s: f64,
}

impl Outcome for DryOutcome {
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn scales(&self) -> HertzScales {
        self.scales
    }
    fn grid(&self) -> &Grid {
        &self.grid
    }
    fn pressure(&self) -> &Array2<f64> {
        &self.p
    }
    fn film(&self) -> Array2<f64> {
        // Inside the contact the gap is zero to the solver's tolerance (±1e-7 a²/R): an overlap
        // of that size is not a film.
        self.gap.mapv(|h| h.max(0.0))
    }
    fn wall_time_s(&self) -> f64 {
        self.setup_time_s + self.solve_time_s
    }
    fn lubricated(&self) -> bool {
        false
    }
    /// The whole load on the solids, over the points that carry pressure.
    fn solid_contact(&self) -> Option<ehl_core::SolidContact> {
        let touching = self.p.mapv(|v| v > 0.0);
        Some(ehl_core::SolidContact::from_mask(&self.grid, &self.scales, &self.p, &touching))
    }
    fn summary(&self) -> Value {
        dry_summary(self)
    }
    fn centreline(&self) -> Centreline {
        dry_centreline(self)
    }
    fn fields(&self) -> Vec<(String, Array2<f64>)> {
        let s = &self.scales;
        vec![
            ("pressure_pa".into(), self.p.mapv(|v| s.p_si(v))),
            ("gap_m".into(), self.gap.mapv(|v| s.h_si(v))),
            ("deformation_m".into(), self.w.mapv(|v| s.h_si(v))),
        ]
    }
    fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
        dry_figures(self, dir, prefix, footnote)
    }
    fn report(&self) -> String {
        dry_report(self)
    }
}

fn run_dry(scene: &Scene) -> Result<DryOutcome> {
    let scales = HertzScales::new(&scene.conditions.contact());
    let grid = scene.grid();
    let spin = crate::progress::spinner(&format!("dry contact {}x{}", grid.nx, grid.ny));
    let t0 = Instant::now();
    let solver = DrySolver::new(grid, *scene.solver);
    let setup_time_s = t0.elapsed().as_secs_f64();
    let shape = grid.paraboloid();
    let problem =
        DryProblem { rigid_gap: shape.view(), compliance: None, load: scales.load_dimensionless() };
    let (mut p, mut w) = (grid.zeros(), grid.zeros());
    let t1 = Instant::now();
    let report = solver
        .solve(&problem, &mut p, &mut w, Start::Flat)
        .within(|| format!("scene `{}`: dry contact solve failed", scene.name))?;
    let solve_time_s = t1.elapsed().as_secs_f64();
    spin.finish_and_clear();
    let gap = DrySolver::gap(&problem, report.h0, &p, &w);
    let hertz = hertz::compare(&grid, &p, report.h0);
    Ok(DryOutcome {
        scene: scene.clone(),
        scales,
        grid,
        p,
        w,
        gap,
        report,
        hertz,
        setup_time_s,
        solve_time_s,
    })
}

fn dry_summary(o: &DryOutcome) -> Value {
    let s = &o.scales;
    let h = &o.hertz;
    let mut results = Map::new();
    let mut put = |k: &str, v: Value| {
        results.insert(k.into(), v);
    };
    put("max_pressure", q(s.p_si(h.p_max), "Pa"));
    put("contact_radius", q(s.x_si(h.contact_radius), "m"));
    put("approach", q(s.h_si(h.approach), "m"));
    put("load", q(o.p.sum() * o.grid.cell_area() * s.p_h * s.a * s.a, "N"));
    let mut hertz_ref = Map::new();
    hertz_ref.insert("contact_radius_a".into(), q(s.a, "m"));
    hertz_ref.insert("max_pressure_p_h".into(), q(s.p_h, "Pa"));
    hertz_ref.insert("approach_a2_over_r".into(), q(s.delta, "m"));
    let errors = json!({
        "max_pressure": q(h.p_max_error, "1 (relative to p_h)"),
        "contact_radius": q(h.contact_radius_error, "1 (relative to a)"),
        "approach": q(h.approach_error, "1 (relative to a^2/R)"),
        "pressure_l2": q(h.pressure_l2_error, "1 (relative L2 over the grid)"),
    });
    json!({
        "results": results,
        "hertz": hertz_ref,
        "relative_error_vs_hertz": errors,
        "solver": {
            "method": if o.scene.solver.preconditioned { "Polonsky-Keer CG, spectral preconditioner" } else { "Polonsky-Keer CG" },
            "nested_start": o.scene.solver.nested,
            "tolerance": q(o.scene.solver.tolerance, "1 (RMS gap on the contact / (a^2/R))"),
            "iterations": o.report.iterations,
            "coarse_iterations": o.report.coarse_iterations,
            "fft_convolutions_fine": o.report.fine_applies,
            "residual": q(o.report.residual, "1 (RMS gap on the contact / (a^2/R))"),
            "contact_points": o.report.contact_points,
            "setup_time": q(o.setup_time_s, "s"),
            "solve_time": q(o.solve_time_s, "s"),
        },
    })
}

fn dry_centreline(o: &DryOutcome) -> Centreline {
    let (g, s) = (&o.grid, &o.scales);
    let j = g.row_nearest(0.0);
    let y = g.y(j);
    let xs = g.xs();
    Centreline {
        columns: vec![
            ("x_m".into(), xs.iter().map(|&x| s.x_si(x)).collect()),
            ("pressure_pa".into(), o.p.row(j).iter().map(|&v| s.p_si(v)).collect()),
            ("gap_m".into(), o.gap.row(j).iter().map(|&v| s.h_si(v)).collect()),
            (
                "pressure_hertz_pa".into(),
                xs.iter().map(|&x| s.p_si(hertz::pressure(x, y))).collect(),
            ),
            (
                "gap_hertz_m".into(),
                xs.iter().map(|&x| s.h_si(hertz::gap((x * x + y * y).sqrt()))).collect(),
            ),
        ],
    }
}

/// Conditions line for figure footnotes.
pub fn conditions_note(o: &DryOutcome) -> String {
    let c = &o.scene.conditions;
    format!(
        "scene {}: R = {} mm, F = {} N, E' = {} GPa; a = {:.4} mm, p_h = {:.4} GPa; grid {}x{}",
        o.scene.name,
        c.ball_radius_m * 1e3,
        c.load_n,
        c.reduced_modulus_pa / 1e9,
        o.scales.a * 1e3,
        o.scales.p_h / 1e9,
        o.grid.nx,
        o.grid.ny
    )
}

fn dry_figures(o: &DryOutcome, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
    let line = dry_centreline(o);
    let x: Vec<f64> = line.columns[0].1.iter().map(|&v| v / o.scales.a).collect();
    let col = |k: usize, scale: f64| -> Vec<(f64, f64)> {
        x.iter().cloned().zip(line.columns[k].1.iter().map(|v| v / scale)).collect()
    };
    let fine_x: Vec<f64> = (0..=400)
        .map(|k| o.grid.x_min + (o.grid.x_max - o.grid.x_min) * k as f64 / 400.0)
        .collect();
    let hertz_p: Vec<(f64, f64)> = fine_x.iter().map(|&x| (x, hertz::pressure(x, 0.0))).collect();
    let hertz_h: Vec<(f64, f64)> = fine_x.iter().map(|&x| (x, hertz::gap(x.abs()))).collect();
    let centre = dir.join(format!("{prefix}centreline.png"));
    plot::charts(
        &centre,
        &[
            Panel::new(
                "Pressure along y = 0",
                "x / a",
                "p / p_h",
                vec![
                    Series::new("Hertz (analytic)", hertz_p, Mark::Line),
                    Series::new("numerical", col(1, o.scales.p_h), Mark::Points),
                ],
            ),
            Panel::new(
                "Gap along y = 0",
                "x / a",
                "h / (a²/R)",
                vec![
                    Series::new("Hertz (analytic)", hertz_h, Mark::Line),
                    Series::new("numerical", col(2, o.scales.delta), Mark::Points),
                ],
            )
            .legend(plotters::prelude::SeriesLabelPosition::UpperMiddle),
        ],
        &(conditions_note(o) + footnote),
    )?;
    let map = dir.join(format!("{prefix}pressure_map.png"));
    let g = &o.grid;
    plot::heat_maps(
        &map,
        &[plot::MapPanel {
            field: &o.p,
            title: "Pressure p / p_h".into(),
            bar_label: "p / p_h".into(),
            diverging: false,
        }],
        g,
        &(conditions_note(o) + footnote),
    )?;
    Ok(vec![centre, map])
}

/// The terminal report.
fn dry_report(o: &DryOutcome) -> String {
    use std::fmt::Write;
    let mut out = String::new();

    let (h, s) = (&o.hertz, &o.scales);
    let _ = writeln!(
        out,
        "scene {} ({}x{}): solved in {:.3} s ({} iterations, residual {:.1e}; setup {:.3} s)",
        o.scene.name,
        o.grid.nx,
        o.grid.ny,
        o.solve_time_s,
        o.report.iterations,
        o.report.residual,
        o.setup_time_s
    );
    let _ = writeln!(
        out,
        "  max pressure   {:.6e} Pa   Hertz {:.6e} Pa   rel. error {:+.2e}",
        s.p_si(h.p_max),
        s.p_h,
        h.p_max_error
    );
    let _ = writeln!(
        out,
        "  contact radius {:.6e} m    Hertz {:.6e} m    rel. error {:+.2e} (area-equivalent)",
        s.x_si(h.contact_radius),
        s.a,
        h.contact_radius_error
    );
    let _ = writeln!(
        out,
        "  approach       {:.6e} m    Hertz {:.6e} m    rel. error {:+.2e}",
        s.h_si(h.approach),
        s.delta,
        h.approach_error
    );
    let _ = writeln!(out, "  pressure L2 error vs Hertz {:.2e}", h.pressure_l2_error);

    out
}
