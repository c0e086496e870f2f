//! A built-in sweep run as `ehl sweep NAME` runs it (its accuracy rule, its checks), merged, and
//! its table written to `docs/measured/sweep-NAME.md`: the sweeps' results as a measured page.

use anyhow::{Context, Result};
use ehl_workbench::sweep;
use std::path::Path;

/// Runs the built-in sweep `name` into `out/NAME` and writes its page. Quickly: every point on
/// 65² without the rule's grids or the checks (the code path, not the results).
pub fn run(name: &str, out: &Path) -> Result<()> {
    let (mut s, dir_of) = ehl_scene::load_sweep(name)?;
    if crate::quick() {
        s.resolve = false;
        s.checks = false;
    }
    let (plan, run, recs) = run_afresh(&s, dir_of.as_deref(), out)?;
    let table = sweep::merge::table(&plan, &recs);
    let how = if crate::quick() {
        "Quickly: every point on 65², without the rule's grids or the checks (the code path, not \
         the results)"
    } else {
        "Every point on the grid and domain its rule gives it, each answer checked against half \
         and a quarter of its points per side and a longer inlet"
    };
    let intro = format!(
        "`ehl sweep {name}`: {}\n\n{how}, {} points on {} cores in {:.0} s. The table is the \
         sweep's own summary; `results.csv`, `results.json` and the charts are in the sweep's \
         folder.\n\n```\n{table}```\n",
        s.description,
        plan.points.len(),
        sweep::default_jobs(),
        run.wall_time_s,
    );
    crate::measured::write(
        &format!("sweep-{name}"),
        &format!("The sweep `{name}`"),
        &format!("cargo xtask sweep {name}"),
        &intro,
        &[],
    )?;
    Ok(())
}

/// Runs sweep `s` (its scene found from `dir_of`) afresh into `out/NAME` (a page says what one
/// run measured: an earlier run's points are cleared), quickly with every point on 65², and
/// merges it: its plan, the run's summary and the points' records.
pub fn run_afresh(
    s: &ehl_scene::Sweep,
    dir_of: Option<&Path>,
    out: &Path,
) -> Result<(sweep::Plan, sweep::RunSummary, Vec<sweep::PointRecord>)> {
    let dir = out.join(&s.name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).with_context(|| format!("clearing {}", dir.display()))?;
    }
    let mut plan = sweep::Plan::new(s, dir_of)?;
    if crate::quick() {
        for p in &mut plan.points {
            p.scene = p.scene.with_points(65)?;
        }
    }
    plan.write(&dir)?;
    let run = sweep::run(&dir, sweep::Shard::all(), sweep::default_jobs())?;
    sweep::merge::merge(&dir)?;
    let recs = sweep::records(&dir, &plan)?;
    Ok((plan, run, recs))
}
