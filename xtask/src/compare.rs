//! Seed Fig. 7 and its table: the built-in `seed` comparison scene (the layer model, the
//! Reynolds solver and the dry contact under Table 1 on one grid), through the same path as
//! `ehl compare seed`.

use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// Runs the `seed` comparison into `out/seed-comparison` and prints its table.
pub fn fig7(out: &Path) -> Result<Vec<PathBuf>> {
    let scene = ehl_scene::builtin("seed")?;
    let c = ehl_workbench::compare::run(&scene);
    print!("{}", c.table());
    if !c.all_converged() {
        bail!("the seed comparison did not converge for every model");
    }
    c.write(&out.join("seed-comparison"))
}

/// The seed's Fig. 1: the flow in the Reynolds film under Table 1 on 1025² (the seed's grid for
/// it), velocity profiles and vectors and the flux-ratio map (`fig1_*`).
pub fn fig1(out: &Path) -> Result<Vec<PathBuf>> {
    let scene = ehl_scene::builtin("reynolds-seed")?.with_points(1025)?;
    let o = ehl_workbench::reynolds::run_reynolds(&scene)?;
    println!(
        "Fig. 1 (reynolds-seed, 1025²): mean |pressure-driven / boundary-driven flux| over the loaded zone {:.4}",
        o.flux_ratio_contact_mean()
    );
    o.flow_figures(out, "fig1_")
}
