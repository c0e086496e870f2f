//! Seed Fig. 7 and its table: the built-in `seed` comparison scene (the layer model, the
//! Reynolds solver and the dry contact under Table 1 on one grid), through the same path as
//! `ehl compare seed`; Fig. 12 (the shallow dent) through both models the same way.

use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// Runs the `seed` comparison into `out/seed-comparison` and prints its table.
pub fn fig7(out: &Path) -> Result<Vec<PathBuf>> {
    comparison(out, "seed", "seed-comparison")
}

/// The seed's Fig. 12 with its Reynolds side: the shallow dent passing both models from the
/// built-in `dent-shallow-compare` scene (histories overlaid, each model's snapshots at the
/// seed's dent positions), into `out/dent-shallow-comparison`.
pub fn fig12(out: &Path) -> Result<Vec<PathBuf>> {
    comparison(out, "dent-shallow-compare", "dent-shallow-comparison")
}

/// Runs a built-in comparison scene into `out/dir` and prints its table; every model must run.
fn comparison(out: &Path, scene: &str, dir: &str) -> Result<Vec<PathBuf>> {
    let scene = ehl_scene::builtin(scene)?;
    let scene = scene.with_points(crate::scene_points(&scene))?;
    let c = ehl_workbench::compare::run(&scene);
    print!("{}", c.table());
    if !c.all_converged() {
        bail!("the {} comparison did not converge for every model", scene.name);
    }
    Ok(c.write(&out.join(dir))?)
}

/// The seed's Fig. 1: the flow in the Reynolds film under Table 1 on 1025² (the seed's grid for
/// it), velocity profiles and vectors and the flux-ratio map (`fig1_*`).
pub fn fig1(out: &Path) -> Result<Vec<PathBuf>> {
    let scene = ehl_scene::builtin("reynolds-seed")?.with_points(crate::points(1025))?;
    let o = ehl_workbench::reynolds::run_reynolds(&scene)?;
    println!(
        "Fig. 1 (reynolds-seed, 1025²): mean |pressure-driven / boundary-driven flux| over the loaded zone {:.4}",
        o.flux_ratio_contact_mean()
    );
    Ok(o.flow_figures(out, "fig1_")?)
}
