//! Writes an outcome: `summary.json` (every scalar with its unit), `centreline.csv`, fields as
//! `.npy` and PNG figures, all in SI. Files are staged and moved into place only when all of
//! them were written, so a failed run leaves nothing half-written.

use crate::plot::{self, Mark, Panel, Series};
use crate::run::{DryOutcome, Outcome};
use anyhow::{Context, Result};
use ehl_core::hertz;
use ndarray::Array2;
use serde_json::{Map, Value, json};
use std::path::{Path, PathBuf};

/// A scalar with its unit.
pub fn q(value: f64, unit: &str) -> Value {
    json!({ "value": value, "unit": unit })
}

/// Columns of the centreline table: header (with unit) and values.
pub struct Centreline {
    pub columns: Vec<(String, Vec<f64>)>,
}

impl Centreline {
    pub fn to_csv(&self) -> String {
        let mut s = self.columns.iter().map(|c| c.0.as_str()).collect::<Vec<_>>().join(",");
        s.push('\n');
        for k in 0..self.columns[0].1.len() {
            let row: Vec<String> = self.columns.iter().map(|c| format!("{:e}", c.1[k])).collect();
            s.push_str(&row.join(","));
            s.push('\n');
        }
        s
    }
}

impl Outcome {
    /// Every scalar result with its unit, the conditions, the grid and the solver's record.
    pub fn summary(&self) -> Value {
        match self {
            Outcome::Dry(o) => dry_summary(o),
            Outcome::Layer(o) => o.summary(),
            Outcome::Reynolds(o) => o.summary(),
        }
    }
    /// The fields along the grid row nearest to `y = 0`.
    pub fn centreline(&self) -> Centreline {
        match self {
            Outcome::Dry(o) => dry_centreline(o),
            Outcome::Layer(o) => o.centreline(),
            Outcome::Reynolds(o) => o.centreline(),
        }
    }
    /// Full fields in SI, with file stems.
    pub fn fields(&self) -> Vec<(String, Array2<f64>)> {
        match self {
            Outcome::Dry(o) => {
                let s = &o.scales;
                vec![
                    ("pressure_pa".into(), o.p.mapv(|v| s.p_si(v))),
                    ("gap_m".into(), o.gap.mapv(|v| s.h_si(v))),
                    ("deformation_m".into(), o.w.mapv(|v| s.h_si(v))),
                ]
            }
            Outcome::Layer(o) => o.fields(),
            Outcome::Reynolds(o) => o.fields(),
        }
    }
    /// Time series as CSV (SI), for models that step in time.
    pub fn time_series_csv(&self) -> Option<String> {
        match self {
            Outcome::Layer(o) => o.time_series_csv(),
            Outcome::Reynolds(o) => o.time_series_csv(),
            Outcome::Dry(_) => None,
        }
    }

    /// Grid coordinates `x`, `y` [m] of the field columns and rows.
    pub fn axes(&self) -> (ndarray::Array1<f64>, ndarray::Array1<f64>) {
        let (grid, a) = match self {
            Outcome::Dry(o) => (&o.grid, o.scales.a),
            Outcome::Layer(o) => (&o.grid, o.scales.a),
            Outcome::Reynolds(o) => (&o.grid, o.prm.scales.a),
        };
        let to_si = |v: Vec<f64>| ndarray::Array1::from(v).mapv(|v| v * a);
        (to_si(grid.xs()), to_si(grid.ys()))
    }
    /// Draws the figures into `dir`, file names starting with `prefix`.
    pub fn figures(&self, dir: &Path, prefix: &str) -> Result<Vec<PathBuf>> {
        match self {
            Outcome::Dry(o) => dry_figures(o, dir, prefix),
            Outcome::Layer(o) => o.figures(dir, prefix),
            Outcome::Reynolds(o) => o.figures(dir, prefix),
        }
    }
}

fn grid_json(o: &DryOutcome) -> Value {
    let (g, a) = (&o.grid, o.scales.a);
    json!({
        "nx": g.nx, "ny": g.ny,
        "x_range": q_pair(g.x_min * a, g.x_max * a),
        "y_range": q_pair(g.y_min * a, g.y_max * a),
        "dx": q(g.dx() * a, "m"), "dy": q(g.dy() * a, "m"),
    })
}

fn q_pair(lo: f64, hi: f64) -> Value {
    json!({ "value": [lo, hi], "unit": "m" })
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
        "scene": o.scene.name,
        "model": "dry",
        "description": o.scene.description,
        "conditions": o.scene.conditions,
        "grid": grid_json(o),
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
            "threads": rayon::current_num_threads(),
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

fn dry_figures(o: &DryOutcome, dir: &Path, prefix: &str) -> Result<Vec<PathBuf>> {
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
        &conditions_note(o),
    )?;
    let map = dir.join(format!("{prefix}pressure_map.png"));
    let g = &o.grid;
    plot::heat_maps(
        &map,
        &[plot::MapPanel {
            field: &o.p,
            title: "Pressure p / p_h".into(),
            bar_label: "p / p_h".into(),
        }],
        g,
        &conditions_note(o),
    )?;
    Ok(vec![centre, map])
}

/// Writes everything the scene asks for into `dir`; returns the files written.
pub fn write(outcome: &Outcome, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let stage = dir.join(".partial");
    if stage.exists() {
        std::fs::remove_dir_all(&stage)?;
    }
    std::fs::create_dir_all(&stage)?;
    let staged = write_into(outcome, &stage);
    let staged = match staged {
        Ok(files) => files,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&stage);
            return Err(e);
        }
    };
    let mut written = vec![];
    for f in staged {
        let target = dir.join(f.file_name().unwrap());
        std::fs::rename(&f, &target)?;
        written.push(target);
    }
    std::fs::remove_dir_all(&stage)?;
    Ok(written)
}

fn write_into(outcome: &Outcome, dir: &Path) -> Result<Vec<PathBuf>> {
    let outputs = outcome.scene().outputs;
    let mut files = vec![];
    let summary = dir.join("summary.json");
    std::fs::write(&summary, serde_json::to_string_pretty(&outcome.summary())? + "\n")?;
    files.push(summary);
    if let Some(csv) = outcome.time_series_csv() {
        let f = dir.join("timeseries.csv");
        std::fs::write(&f, csv)?;
        files.push(f);
    }
    if outputs.centreline {
        let f = dir.join("centreline.csv");
        std::fs::write(&f, outcome.centreline().to_csv())?;
        files.push(f);
    }
    if outputs.fields {
        let (x, y) = outcome.axes();
        for (stem, arr) in [("x_m", x), ("y_m", y)] {
            let f = dir.join(format!("{stem}.npy"));
            ndarray_npy::write_npy(&f, &arr).with_context(|| format!("writing {}", f.display()))?;
            files.push(f);
        }
        for (stem, field) in outcome.fields() {
            let f = dir.join(format!("{stem}.npy"));
            ndarray_npy::write_npy(&f, &field)
                .with_context(|| format!("writing {}", f.display()))?;
            files.push(f);
        }
    }
    if outputs.figures {
        files.extend(outcome.figures(dir, "")?);
    }
    Ok(files)
}
