//! A built-in sweep run as `ehl sweep NAME` runs it (its accuracy rule, its checks), merged, and
//! its table written to `docs/measured/sweep-NAME.md`: the sweeps' results as a measured page.

use anyhow::{Context, Result};
use ehl_workbench::sweep;
use std::path::Path;

/// Runs the built-in sweep `name` into `out/NAME` and writes its page; with `map`, every point
/// on the grid its inlet rule grows it to, without the grid rule's refinement or the checks (the
/// page `sweep-NAME-map`). Quickly: every point on 65² without either (the code path, not the
/// results). From a folder already run and merged, the page alone (its time the points' own,
/// summed: a cluster's wall is not known here).
pub fn run(name: &str, map: bool, from: Option<&Path>, out: &Path) -> Result<()> {
    let (mut s, dir_of) = ehl_scene::load_sweep(name)?;
    if crate::quick() || map {
        s.resolve = false;
        s.checks = false;
    }
    let (plan, time, recs) = match from {
        Some(dir) => {
            let plan = sweep::Plan::load(dir)?;
            anyhow::ensure!(
                plan.sweep.name == s.name && plan.sweep.resolve == s.resolve,
                "{} holds the sweep `{}` (grid rule {}), not `{name}`{}",
                dir.display(),
                plan.sweep.name,
                if plan.sweep.resolve { "on" } else { "off" },
                if map { " --map" } else { "" }
            );
            let recs = sweep::records(dir, &plan)?;
            let own: f64 = recs.iter().flat_map(|r| &r.models).map(|m| m.wall_time_s).sum();
            (plan, format!("{own:.0} s of the points' own time (read from a finished run)"), recs)
        }
        None => {
            let (plan, run, recs) = run_afresh(&s, dir_of.as_deref(), out)?;
            let time = format!("on {} cores in {:.0} s", sweep::default_jobs(), run.wall_time_s);
            (plan, time, recs)
        }
    };
    let table = sweep::merge::table(&plan, &recs);
    let how = if crate::quick() {
        "Quickly: every point on 65², without the rule's grids or the checks (the code path, not \
         the results)"
    } else if map {
        "Every point on the scene's cells, its domain grown by the inlet rule, without the grid \
         rule's refinement or the checks: the map, not each answer's error (a film thinner than \
         the cells resolve fails as closed)"
    } else {
        "Every point on the domain its rule gives it, each model on the cells it needs there, each \
         answer checked against half and a quarter of its points per side and a longer inlet"
    };
    let mut intro = format!(
        "`ehl sweep {name}`: {}\n\n{how}, {} points {time}. The table is the sweep's own \
         summary; `results.csv`, `results.json` and the charts are in the sweep's folder.\n\n\
         ```\n{table}```\n",
        s.description,
        plan.points.len(),
    );
    intro += &ratio_maps(&plan, &recs);
    let (page, command) = if map {
        (format!("sweep-{name}-map"), format!("cargo xtask sweep {name} --map"))
    } else {
        (format!("sweep-{name}"), format!("cargo xtask sweep {name}"))
    };
    crate::measured::write(&page, &format!("The sweep `{name}`"), &command, &intro, &[])?;
    Ok(())
}

/// For a sweep over two parameters with the layer model and a Reynolds model: the layer's `h_c`
/// over each Reynolds model's at every point, laid out as a map (the first parameter across),
/// within 10 % in bold, a failure named by its model and kind, and in brackets the Reynolds
/// flux indicator (the mean of `|r|` over the loaded zone) where it was reported. Empty
/// otherwise.
fn ratio_maps(plan: &sweep::Plan, recs: &[sweep::PointRecord]) -> String {
    use ehl_scene::Model;
    let models = plan.points.first().map(|p| p.scene.models()).unwrap_or_default();
    let axes = &plan.sweep.parameters;
    let Some(layer) = models.iter().position(|&m| m == Model::Layer) else {
        return String::new();
    };
    if axes.len() != 2 {
        return String::new();
    }
    let (v0, v1) = (axes[0].values(), axes[1].values());
    let at = |i0: usize, i1: usize| &recs[i0 * v1.len() + i1];
    let mut out = String::new();
    for (k, &m) in models.iter().enumerate() {
        if !matches!(m, Model::Reynolds | Model::ReynoldsFlooded) {
            continue;
        }
        out += &format!(
            "\nLayer `h_c` / {} `h_c` (rows: {}, columns: {}; within 10 % in bold):\n\n| |",
            m.name(),
            axes[1].parameter.name(),
            axes[0].parameter.name()
        );
        for v in &v0 {
            out += &format!(" {v} |");
        }
        out += "\n|---|";
        out += &"---|".repeat(v0.len());
        out.push('\n');
        for (i1, w) in v1.iter().enumerate() {
            out += &format!("| {w} |");
            for i0 in 0..v0.len() {
                let r = at(i0, i1);
                let (l, re) = (&r.models[layer], &r.models[k]);
                let cell = match (&l.observables, &re.observables) {
                    (Some(a), Some(b)) => {
                        let q = a.central_film_m / b.central_film_m;
                        if (q - 1.0).abs() <= 0.1 {
                            format!("**{q:.2}**")
                        } else {
                            format!("{q:.2}")
                        }
                    }
                    _ => [l, re]
                        .iter()
                        .filter(|x| x.observables.is_none())
                        .map(|x| {
                            format!(
                                "{} {}",
                                x.model.name(),
                                x.failure.as_deref().unwrap_or("failed")
                            )
                        })
                        .collect::<Vec<_>>()
                        .join(", "),
                };
                let flux = re.indicators.get(ehl_workbench::reynolds::flow::FLUX_INDICATOR);
                match flux {
                    Some(f) => out += &format!(" {cell} ({:.3}) |", f.value),
                    None => out += &format!(" {cell} |"),
                }
            }
            out.push('\n');
        }
    }
    out
}

/// Runs sweep `s` (its scene found from `dir_of`) afresh into `out/NAME` (a page says what one
/// run measured: an earlier run's points are cleared), quickly with every point on 65², and
/// merges it: its plan, the run's summary and the points' records.
pub fn run_afresh(
    s: &ehl_scene::Sweep,
    dir_of: Option<&Path>,
    out: &Path,
) -> Result<(sweep::Plan, sweep::RunSummary, Vec<sweep::PointRecord>)> {
    let mut plan = sweep::Plan::new(s, dir_of)?;
    if crate::quick() {
        for p in &mut plan.points {
            p.scene = p.scene.with_points(65)?;
        }
    }
    run_plan(plan, out)
}

/// Runs `plan` afresh into `out/NAME` and merges it (a study that changed its points' scenes
/// after planning: [`run_afresh`] otherwise).
pub fn run_plan(
    plan: sweep::Plan,
    out: &Path,
) -> Result<(sweep::Plan, sweep::RunSummary, Vec<sweep::PointRecord>)> {
    let dir = out.join(&plan.sweep.name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).with_context(|| format!("clearing {}", dir.display()))?;
    }
    plan.write(&dir)?;
    let run = sweep::run(&dir, sweep::Shard::all(), sweep::default_jobs())?;
    sweep::merge::merge(&dir)?;
    let recs = sweep::records(&dir, &plan)?;
    Ok((plan, run, recs))
}
