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
