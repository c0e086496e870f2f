//! Runs a scene through its model.

use anyhow::{Context, Result};
use ehl_core::hertz::{self, Comparison};
use ehl_core::{DryProblem, DryReport, DrySolver, Grid, HertzScales, Start};
use ehl_scene::{Model, Scene};
use ndarray::Array2;
use std::time::Instant;

/// What a run produced, per model.
pub enum Outcome {
    Dry(DryOutcome),
    Layer(Box<crate::layer::LayerOutcome>),
    Reynolds(Box<crate::reynolds::ReynoldsOutcome>),
}

impl Outcome {
    pub fn scene(&self) -> &Scene {
        match self {
            Outcome::Dry(o) => &o.scene,
            Outcome::Layer(o) => &o.scene,
            Outcome::Reynolds(o) => &o.scene,
        }
    }
}

/// A dry contact solution, in Hertz units, with its comparison against Hertz.
pub struct DryOutcome {
    pub scene: Scene,
    pub scales: HertzScales,
    pub grid: Grid,
    /// Pressure `P` [p_h].
    pub p: Array2<f64>,
    /// Elastic deformation `W` [a²/R].
    pub w: Array2<f64>,
    /// Gap `H` [a²/R].
    pub gap: Array2<f64>,
    pub report: DryReport,
    pub hertz: Comparison,
    /// Building the operators (kernel spectra, FFT plans) [s].
    pub setup_time_s: f64,
    /// The solve itself [s].
    pub solve_time_s: f64,
}

/// Runs `scene` (already validated) and returns its outcome; fails with a diagnosis if the
/// solver diverges or does not converge.
pub fn run_scene(scene: &Scene) -> Result<Outcome> {
    match scene.model {
        Model::Dry => Ok(Outcome::Dry(run_dry(scene)?)),
        Model::Layer => Ok(Outcome::Layer(Box::new(crate::layer::run_layer(scene)?))),
        Model::Reynolds => Ok(Outcome::Reynolds(Box::new(crate::reynolds::run_reynolds(scene)?))),
    }
}

fn run_dry(scene: &Scene) -> Result<DryOutcome> {
    let scales = HertzScales::new(&scene.conditions.contact());
    let grid = scene.grid();
    let spin = crate::progress::spinner(&format!("dry contact {}x{}", grid.nx, grid.ny));
    let t0 = Instant::now();
    let solver = DrySolver::new(grid, scene.solver);
    let setup_time_s = t0.elapsed().as_secs_f64();
    let shape = grid.paraboloid();
    let problem =
        DryProblem { rigid_gap: shape.view(), compliance: None, load: scales.load_dimensionless() };
    let (mut p, mut w) = (grid.zeros(), grid.zeros());
    let t1 = Instant::now();
    let report = solver
        .solve(&problem, &mut p, &mut w, Start::Flat)
        .with_context(|| format!("scene `{}`: dry contact solve failed", scene.name))?;
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
