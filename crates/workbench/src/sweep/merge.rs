//! The merged results of a sweep: `results.csv` (a row per point and model; only numbers that
//! do not depend on the machine, so a sharded run and a local run give the same file byte for
//! byte), `results.json` (the same with wall times and the checks in full), `cost.csv` (wall
//! times), and the charts.

use super::{ModelRecord, Plan, PointRecord, records, write_atomic};
use crate::compare::model_name;
use crate::error::{Result, io, output};
use crate::plot::{self, Category, CellPanel, Mark, Panel, Series};
use ehl_core::Observables;
use ehl_reynolds::formulas;
use ehl_scene::Model;
use plotters::prelude::SeriesLabelPosition;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// The published film formulas at a point [m]: Hamrock–Dowson central and minimum, NVM central
/// (pure rolling, the point's own conditions). `None` without lubricant or motion.
pub fn formulas_at(p: &super::PlannedPoint) -> Option<[f64; 3]> {
    let l = p.scene.lubricant?.lubricant();
    let (c, u_sum) = p.scene.reynolds_conditions();
    (u_sum > 0.0).then(|| {
        [
            formulas::hamrock_dowson_central(&c, &l, 0.5 * u_sum),
            formulas::hamrock_dowson_minimum(&c, &l, 0.5 * u_sum),
            formulas::nvm_central(&c, &l, u_sum),
        ]
    })
}

/// `results.csv`.
pub fn results_csv(plan: &Plan, recs: &[PointRecord]) -> String {
    // Every premise indicator any model reported, a column each (empty for the others).
    let names: std::collections::BTreeSet<&String> =
        recs.iter().flat_map(|r| r.models.iter().flat_map(|m| m.indicators.keys())).collect();
    let mut rows = vec![];
    for r in recs {
        let f = formulas_at(&plan.points[r.index]);
        for m in &r.models {
            // A row as data, its columns in order; the one writer renders it.
            let mut row = serde_json::Map::new();
            let mut put = |k: &str, v: Value| {
                row.insert(k.to_string(), v);
            };
            put("point", json!(r.index));
            for (a, v) in plan.sweep.parameters.iter().zip(&r.values) {
                put(&a.parameter.name(), json!(v));
            }
            let o = m.observables.as_ref();
            let g = m.grid_check.as_ref().and_then(|c| c.change).unwrap_or_default();
            let d = m.domain_check.as_ref().and_then(|c| c.change).unwrap_or_default();
            put("model", json!(model_name(m.model)));
            put("converged", json!(o.is_some()));
            put("central_film_m", json!(o.map(|o| o.central_film_m)));
            put("minimum_film_m", json!(o.map(|o| o.minimum_film_m)));
            put("max_pressure_pa", json!(o.map(|o| o.max_pressure_pa)));
            put("contact_extent_x_m", json!(o.map(|o| o.contact_extent_x_m)));
            put("contact_extent_y_m", json!(o.map(|o| o.contact_extent_y_m)));
            put("load_error", json!(o.map(|o| o.load_error)));
            put("hamrock_dowson_central_m", json!(f.map(|f| f[0])));
            put("hamrock_dowson_minimum_m", json!(f.map(|f| f[1])));
            put("nvm_central_m", json!(f.map(|f| f[2])));
            let grid = r.grid_of(m);
            put("nx", json!(grid.nx));
            put("ny", json!(grid.ny));
            put("x_min_a", json!(r.x_a[0]));
            put("x_max_a", json!(r.x_a[1]));
            put("y_min_a", json!(r.y_a[0]));
            put("y_max_a", json!(r.y_a[1]));
            for (k, v) in super::OBSERVED.iter().zip(g) {
                put(&format!("grid_change_{k}"), json!(v));
            }
            let e = m.grid_error.unwrap_or_default();
            for (k, v) in super::OBSERVED.iter().zip(e) {
                put(&format!("grid_order_{k}"), json!(v.and_then(|v| v.order)));
                put(&format!("grid_error_{k}"), json!(v.map(|v| v.error)));
            }
            for (k, v) in super::OBSERVED.iter().zip(d) {
                put(&format!("domain_change_{k}"), json!(v));
            }
            for n in &names {
                put(n, json!(m.indicators.get(*n).map(|i| i.value)));
            }
            put("flag", json!(m.flag));
            put("diagnosis", json!(m.diagnosis));
            rows.push(Value::Object(row));
        }
    }
    crate::output::csv(&rows)
}

/// `cost.csv`: wall time of each model's run and of its checks at each point.
pub fn cost_csv(plan: &Plan, recs: &[PointRecord]) -> String {
    let mut rows = vec![];
    for r in recs {
        for m in &r.models {
            let mut row = serde_json::Map::new();
            row.insert("point".into(), json!(r.index));
            for (a, v) in plan.sweep.parameters.iter().zip(&r.values) {
                row.insert(a.parameter.name(), json!(v));
            }
            row.insert("model".into(), json!(model_name(m.model)));
            let g = r.grid_of(m);
            row.insert("nx".into(), json!(g.nx));
            row.insert("ny".into(), json!(g.ny));
            row.insert("wall_time_s".into(), json!(m.wall_time_s));
            row.insert("check_wall_time_s".into(), json!(m.check_wall_time_s));
            rows.push(Value::Object(row));
        }
    }
    crate::output::csv(&rows)
}

/// `results.json`: the sweep, its parameters, and every point's record in full.
pub fn results_json(plan: &Plan, recs: &[PointRecord]) -> Value {
    let points: Vec<Value> = recs
        .iter()
        .map(|r| {
            let p = &plan.points[r.index];
            let f = formulas_at(p);
            json!({
                "point": r.index,
                "values": r.values,
                "adapted": p.adapted,
                "formulas_m": f.map(|f| json!({
                    "hamrock_dowson_central": f[0], "hamrock_dowson_minimum": f[1], "nvm_central": f[2],
                })),
                "record": r,
            })
        })
        .collect();
    json!({
        "sweep": plan.sweep,
        "parameters": plan.sweep.parameters.iter().map(|a| json!({
            "name": a.parameter.name(), "unit": a.parameter.unit(), "values": a.values(), "log": a.is_log(),
        })).collect::<Vec<_>>(),
        "definitions": {
            "film": "separation of the solid surfaces (see comparison.json of `ehl compare`)",
            "grid_change": "(this point - the same domain at half the points per side) / the half-points run (h_min: over its central film)",
            "grid_order": "the order of convergence observed on the model's grid at the point, half and a quarter of its points per side (empty: the changes alternate, or the quarter grid failed)",
            "grid_error": "the point's estimated relative discretisation error, Roache's grid convergence index: 1.25 |f_half - f| / (2^p - 1) over f (h_min: over h_c), p the observed order held to [0.5, 2]; without an observed order, |f_half - f| over the same",
            "domain_change": "(larger domain - the half-points run) / the half-points run, same cells (h_min: over its central film)",
            "flag": format!("an estimated grid error or a domain change beyond {} (relative), or a check that failed", plan.sweep.flag_change_above),
            "wall_time_s": "one thread per point",
        },
        "robustness": robustness(plan, recs),
        "points": points,
    })
}

/// The terminal summary: per point its parameters and each model's `h_c` [nm] with its
/// estimated grid error (`failed`, or `*` for a flagged point), then where the details are.
pub fn table(plan: &Plan, recs: &[PointRecord]) -> String {
    let models = plan.points.first().map(|p| p.scene.models()).unwrap_or_default();
    let mut heads: Vec<String> =
        plan.sweep.parameters.iter().map(|a| short_name(&a.parameter.name())).collect();
    heads.extend(models.iter().map(|&m| format!("{} h_c [nm]", model_name(m))));
    let widths: Vec<usize> = heads.iter().map(|h| h.len().max(12)).collect();
    let mut t = String::from("  point");
    for (h, w) in heads.iter().zip(&widths) {
        t += &format!(" {h:>w$}");
    }
    t.push('\n');
    for r in recs {
        t += &format!("  {:>5}", r.index);
        let mut cells: Vec<String> = r.values.iter().map(|v| format!("{v:.4e}")).collect();
        cells.extend(r.models.iter().map(|m| match &m.observables {
            Some(o) => {
                // The estimated grid error of h_c, where the checks gave one.
                let err = m.grid_error.and_then(|e| e[0]).map(|e| e.error);
                format!(
                    "{:.3}{}{}",
                    o.central_film_m * 1e9,
                    err.map(|e| format!(" ±{:.1}%", 100.0 * e)).unwrap_or_default(),
                    if m.flag.is_some() { "*" } else { "" }
                )
            }
            None => "failed".into(),
        }));
        for (c, w) in cells.iter().zip(&widths) {
            t += &format!(" {c:>w$}");
        }
        t.push('\n');
    }
    t += "  (±: h_c's estimated grid error, from each model's grid, half and a quarter of its points per side)\n";
    t += "  (* flagged: the solver returned an unconverged answer that had settled, or its estimated grid error or the domain check's change exceeds the limit; failures and flags in results.csv)\n";
    for r in robustness(plan, recs) {
        t += &format!("  {r}\n");
    }
    t
}

/// How one model fared over a sweep: points converged with their checks passed, converged but
/// flagged, and failed, by the kind of failure.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Robustness {
    /// Which model.
    pub model: Model,
    /// Converged, checks passed (or not run).
    pub converged: usize,
    /// Converged, flagged by a check.
    pub flagged: usize,
    /// Failed, by kind (`film closed`, `stalled`, …).
    pub failed: std::collections::BTreeMap<String, usize>,
}

impl std::fmt::Display for Robustness {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let failed: usize = self.failed.values().sum();
        write!(
            f,
            "{}: {} converged, {} flagged, {failed} failed",
            model_name(self.model),
            self.converged,
            self.flagged
        )?;
        if failed > 0 {
            let kinds: Vec<String> = self.failed.iter().map(|(k, n)| format!("{n} {k}")).collect();
            write!(f, " ({})", kinds.join(", "))?;
        }
        Ok(())
    }
}

/// Each model's [`Robustness`] over the sweep's points, in the scene's model order.
pub fn robustness(plan: &Plan, recs: &[PointRecord]) -> Vec<Robustness> {
    let models = plan.points.first().map(|p| p.scene.models()).unwrap_or_default();
    models
        .iter()
        .enumerate()
        .map(|(k, &model)| {
            let mut r = Robustness { model, converged: 0, flagged: 0, failed: Default::default() };
            for m in recs.iter().map(|p| &p.models[k]) {
                match (&m.observables, &m.flag) {
                    (Some(_), None) => r.converged += 1,
                    (Some(_), Some(_)) => r.flagged += 1,
                    (None, _) => {
                        *r.failed.entry(m.failure.clone().unwrap_or("other".into())).or_default() +=
                            1
                    }
                }
            }
            r
        })
        .collect()
}

/// A point's outcome for one model, as a map of outcomes shows it.
fn outcome_cell(m: &ModelRecord) -> (String, Category) {
    match (&m.observables, &m.flag) {
        (Some(_), None) => ("converged".into(), Category::Good),
        (Some(_), Some(_)) => ("flagged".into(), Category::Doubtful),
        (None, _) => (m.failure.clone().unwrap_or("failed".into()), Category::Bad),
    }
}

/// The map of outcomes (`sweep_robustness.png`): per model, each point converged, flagged or
/// failed (the kind written in the cell), with the counts in the panel's title.
fn robustness_chart(ctx: &Ctx, files: &mut Vec<PathBuf>) -> Result<()> {
    let axes = &ctx.plan.sweep.parameters;
    let n0 = axes[0].values().len();
    let n1 = axes.get(1).map_or(1, |a| a.values().len());
    let ticks = |a: Option<&ehl_scene::Axis>| -> Vec<String> {
        a.map_or(vec![String::new()], |a| a.values().iter().map(|v| format!("{v}")).collect())
    };
    let counts = robustness(ctx.plan, ctx.recs);
    let panels: Vec<CellPanel> = counts
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let mut labels = vec![vec![None; n0]; n1];
            for (i, r) in ctx.recs.iter().enumerate() {
                labels[i % n1][i / n1] = Some(outcome_cell(&r.models[k]));
            }
            CellPanel {
                title: c.to_string(),
                values: vec![],
                outline: vec![],
                log_colour: false,
                digits: 0,
                labels,
            }
        })
        .collect();
    let label = |a: &ehl_scene::Axis| format!("{} [{}]", a.parameter.name(), a.parameter.unit());
    let yl = axes.get(1).map(label).unwrap_or_default();
    put(files, ctx.dir, "sweep_robustness.png", &|f| {
        plot::cell_maps(
            f,
            &panels,
            &ticks(axes.first()),
            &ticks(axes.get(1)),
            &label(&axes[0]),
            &yl,
            &ctx.note,
        )
    })
}

/// The last part of a parameter's field name, for narrow columns.
fn short_name(name: &str) -> String {
    name.rsplit('.').next().unwrap_or(name).to_string()
}

/// Reads every point's record and writes the results and charts into `dir`.
pub fn merge(dir: &Path) -> Result<Vec<PathBuf>> {
    let plan = Plan::load(dir)?;
    let recs = records(dir, &plan)?;
    let mut files = vec![];
    for (name, body) in [
        ("results.csv", results_csv(&plan, &recs)),
        ("cost.csv", cost_csv(&plan, &recs)),
        (
            "results.json",
            serde_json::to_string_pretty(&results_json(&plan, &recs))
                .map_err(output("results.json"))?
                + "\n",
        ),
    ] {
        let f = dir.join(name);
        write_atomic(&f, &body)?;
        files.push(f);
    }
    files.extend(charts(dir, &plan, &recs)?);
    Ok(files)
}

fn obs(m: &ModelRecord) -> Option<&Observables> {
    m.observables.as_ref()
}

/// The short reason of a failure, for legends: the diagnosis's last clause (its verdict),
/// without the scene's name.
fn short(d: &str) -> String {
    let d = match d.split_once("`: ") {
        Some((head, rest)) if head.starts_with("scene `") => rest,
        _ => d,
    };
    let last = d.rsplit("; ").next().unwrap_or(d).trim();
    if last.chars().count() > 55 {
        last.chars().take(52).collect::<String>() + "..."
    } else {
        last.to_string()
    }
}

/// What every chart needs: the sweep, its records, the models, the footnote.
struct Ctx<'a> {
    dir: &'a Path,
    plan: &'a Plan,
    recs: &'a [PointRecord],
    models: Vec<Model>,
    note: String,
}

/// Draws a chart through a temporary name (a reader never sees half a PNG) and lists it.
fn put(
    files: &mut Vec<PathBuf>,
    dir: &Path,
    name: &str,
    draw: &dyn Fn(&Path) -> Result<()>,
) -> Result<()> {
    let t = dir.join(format!(".{name}.tmp-{}.png", std::process::id()));
    draw(&t)?;
    let f = dir.join(name);
    std::fs::rename(&t, &f).map_err(io(format!("moving {} into place", f.display())))?;
    files.push(f);
    Ok(())
}

/// The first two lubricated models (by the scene's order; a model is lubricated where any of
/// its points says so), as record indices with their names: the pair a comparison's film ratio
/// is taken between (`compare`'s difference map takes the same pair), the seed's layer and
/// Reynolds.
fn film_pair(models: &[Model], recs: &[PointRecord]) -> Option<((usize, String), (usize, String))> {
    let wet: Vec<usize> =
        (0..models.len()).filter(|&k| recs.iter().any(|r| r.models[k].lubricated)).collect();
    match wet.as_slice() {
        [a, b, ..] => Some(((*a, model_name(models[*a])), (*b, model_name(models[*b])))),
        _ => None,
    }
}

/// An indicator some model reported: its name, what it says (from the first record that has
/// it), and which models (by column) report it.
struct IndicatorColumn {
    name: String,
    description: String,
    unit: String,
    log_scale: bool,
    models: Vec<usize>,
}

/// Every indicator reported at any point, in name order.
fn indicators(models: &[Model], recs: &[PointRecord]) -> Vec<IndicatorColumn> {
    let mut out: Vec<IndicatorColumn> = vec![];
    for k in 0..models.len() {
        for r in recs {
            for (name, i) in &r.models[k].indicators {
                match out.iter_mut().find(|c| &c.name == name) {
                    Some(c) if !c.models.contains(&k) => c.models.push(k),
                    Some(_) => {}
                    None => out.push(IndicatorColumn {
                        name: name.clone(),
                        description: i.description.clone(),
                        unit: i.unit.clone(),
                        log_scale: i.log_scale,
                        models: vec![k],
                    }),
                }
            }
        }
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// A model's name as a chart title starts it.
fn title_case(name: &str) -> String {
    let mut c = name.chars();
    c.next().map(|f| f.to_uppercase().chain(c).collect()).unwrap_or_default()
}

fn charts(dir: &Path, plan: &Plan, recs: &[PointRecord]) -> Result<Vec<PathBuf>> {
    let ctx = Ctx {
        dir,
        plan,
        recs,
        models: plan.points[0].scene.models(),
        note: format!(
            "sweep {} of scene {}: {} points; wall times on one thread per point",
            plan.sweep.name,
            plan.sweep.scene,
            recs.len()
        ),
    };
    let mut files = vec![];
    if plan.sweep.parameters.len() == 1 {
        one_parameter(&ctx, &mut files)?;
    } else {
        two_parameters(&ctx, &mut files)?;
    }
    robustness_chart(&ctx, &mut files)?;
    Ok(files)
}

/// Films (with the formulas), agreement beside the flux indicator, and cost, against the one
/// parameter.
fn one_parameter(ctx: &Ctx, files: &mut Vec<PathBuf>) -> Result<()> {
    let (plan, recs, models, note) = (ctx.plan, ctx.recs, &ctx.models, &ctx.note);
    let axes = &plan.sweep.parameters;
    let a = &axes[0];
    let x_label = format!("{} [{}]", a.parameter.name(), a.parameter.unit());
    let mut hc = vec![];
    let mut hmin = vec![];
    let mut fails = vec![];
    let mut cost = vec![];
    for (k, &m) in models.iter().enumerate() {
        let name = model_name(m);
        let rows: Vec<(&PointRecord, &ModelRecord)> =
            recs.iter().map(|r| (r, &r.models[k])).collect();
        if rows.iter().any(|(_, mr)| mr.lubricated) {
            let pts = |f: &dyn Fn(&Observables) -> f64| -> Vec<(f64, f64)> {
                rows.iter()
                    .filter_map(|(r, mr)| obs(mr).map(|o| (r.values[0], f(o) * 1e9)))
                    .collect()
            };
            hc.push(Series::new(name.clone(), pts(&|o| o.central_film_m), Mark::LinePoints));
            hmin.push(Series::new(name.clone(), pts(&|o| o.minimum_film_m), Mark::LinePoints));
            let flagged: Vec<(f64, f64)> = rows
                .iter()
                .filter(|(_, mr)| mr.flag.is_some())
                .filter_map(|(r, mr)| obs(mr).map(|o| (r.values[0], o.central_film_m * 1e9)))
                .collect();
            if !flagged.is_empty() {
                hc.push(Series::new(format!("{name}: flagged"), flagged, Mark::Points));
            }
        }
        let failed: Vec<&(&PointRecord, &ModelRecord)> =
            rows.iter().filter(|(_, mr)| mr.observables.is_none()).collect();
        if let Some((_, first)) = failed.first() {
            fails.push((
                format!(
                    "{name} failed at {} point(s): {}",
                    failed.len(),
                    short(first.diagnosis.as_deref().unwrap_or(""))
                ),
                failed.iter().map(|(r, _)| r.values[0]).collect::<Vec<f64>>(),
            ));
        }
        cost.push(Series::new(
            name.clone(),
            rows.iter().map(|(r, mr)| (r.values[0], mr.wall_time_s.max(1e-3))).collect(),
            Mark::LinePoints,
        ));
    }
    let formula = |k: usize| -> Vec<(f64, f64)> {
        recs.iter()
            .filter_map(|r| formulas_at(&plan.points[r.index]).map(|f| (r.values[0], f[k] * 1e9)))
            .collect()
    };
    if plan.points.iter().any(|p| formulas_at(p).is_some()) {
        hc.push(Series::new("Hamrock-Dowson", formula(0), Mark::Line));
        hc.push(Series::new("NVM", formula(2), Mark::Line));
        hmin.push(Series::new("Hamrock-Dowson", formula(1), Mark::Line));
    }
    // Failed points sit on the lower edge of the film charts, one row per model.
    let floor = hc
        .iter()
        .chain(&hmin)
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|v| *v > 0.0)
        .fold(f64::INFINITY, f64::min);
    let floor = if floor.is_finite() { floor / 1.3 } else { 1.0 };
    for (k, (label, xs)) in fails.into_iter().enumerate() {
        let y = floor / 1.25f64.powi(k as i32);
        let s = Series::new(label, xs.iter().map(|&x| (x, y)).collect(), Mark::Points);
        hc.push(s.clone());
        hmin.push(s);
    }
    let log = a.is_log();
    // Room above the data for the legend: the films rise to the right, so it goes on top.
    let top = hc
        .iter()
        .chain(&hmin)
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    let panel = |title: &str, y: &str, series: Vec<Series>| {
        let mut p = Panel::new(title, &x_label, y, series).legend(SeriesLabelPosition::UpperLeft);
        p.log_x = log;
        p.log_y = log;
        if log && top > 0.0 {
            p = p.y_range(floor / 2.0, top * 60.0);
        }
        p
    };
    put(files, ctx.dir, "sweep_films.png", &|f| {
        plot::charts(
            f,
            &[
                panel("Central film h_c", "h_c [nm]", hc.clone()),
                panel("Minimum film h_min", "h_min [nm]", hmin.clone()),
            ],
            note,
        )
    })?;
    // The layer/Reynolds agreement, then every indicator any model reported: a panel each, a
    // series per model that reports it (named and described by the models, not here).
    let mut panels = vec![];
    if let Some(((kl, name_l), (kr, name_r))) = film_pair(models, recs) {
        let ratio: Vec<(f64, f64)> = recs
            .iter()
            .filter_map(|r| match (obs(&r.models[kl]), obs(&r.models[kr])) {
                (Some(l), Some(re)) => Some((r.values[0], l.central_film_m / re.central_film_m)),
                _ => None,
            })
            .collect();
        let xs: Vec<f64> = recs.iter().map(|r| r.values[0]).collect();
        let band = |v: f64| xs.iter().map(|&x| (x, v)).collect::<Vec<_>>();
        let mut a = Panel::new(
            &format!("{} h_c / {} h_c", title_case(&name_l), title_case(&name_r)),
            &x_label,
            "ratio",
            vec![
                Series::new(format!("{name_l} / {name_r}"), ratio, Mark::LinePoints),
                Series::new("+10 %", band(1.1), Mark::Line),
                Series::new("-10 %", band(0.9), Mark::Line),
            ],
        );
        a.log_x = log;
        panels.push(a);
    }
    // An indicator with one value at every point gets no panel of its own: it is named in the
    // footnote with its value.
    let mut constant = vec![];
    for ind in indicators(models, recs) {
        let name = ind.name.as_str();
        let values: Vec<f64> = ind
            .models
            .iter()
            .flat_map(|&k| recs.iter().filter_map(move |r| r.models[k].indicators.get(name)))
            .map(|i| i.value)
            .collect();
        if let Some(&v) = values.first()
            && values.iter().all(|&x| x == v)
        {
            constant.push(format!("{} = {} {} at every point", ind.name, v, ind.unit));
            continue;
        }
        let series = ind
            .models
            .iter()
            .map(|&k| {
                let pts = recs
                    .iter()
                    .filter_map(|r| {
                        r.models[k].indicators.get(&ind.name).map(|i| (r.values[0], i.value))
                    })
                    .collect();
                Series::new(model_name(models[k]), pts, Mark::LinePoints)
            })
            .collect();
        let mut p =
            Panel::new(&ind.description, &x_label, &format!("{} [{}]", ind.name, ind.unit), series);
        p.log_x = log;
        p.log_y = ind.log_scale;
        panels.push(p);
    }
    if !panels.is_empty() {
        let note = if constant.is_empty() {
            note.to_string()
        } else {
            format!("{note}; {}", constant.join(", "))
        };
        put(files, ctx.dir, "sweep_agreement.png", &|f| plot::charts(f, &panels, &note))?;
    }
    put(files, ctx.dir, "sweep_cost.png", &|f| {
        let mut p =
            Panel::new("Wall time per point (one thread)", &x_label, "wall time [s]", cost.clone())
                .legend(SeriesLabelPosition::UpperLeft);
        p.log_x = log;
        p.log_y = true;
        plot::charts(f, &[p], note)
    })?;
    Ok(())
}

/// Maps over the two parameters: layer/Reynolds film ratio beside the flux indicator, and each
/// model's wall time.
fn two_parameters(ctx: &Ctx, files: &mut Vec<PathBuf>) -> Result<()> {
    let (plan, recs, models, note) = (ctx.plan, ctx.recs, &ctx.models, &ctx.note);
    let axes = &plan.sweep.parameters;
    let (a0, a1) = (&axes[0], &axes[1]);
    let (n0, n1) = (a0.values().len(), a1.values().len());
    let ticks = |a: &ehl_scene::Axis| -> Vec<String> {
        a.values().iter().map(|v| format!("{v}")).collect()
    };
    let at = |i0: usize, i1: usize| &recs[i0 * n1 + i1];
    let mut panels = vec![];
    let mut agree = vec![vec![false; n0]; n1];
    if let Some(((kl, name_l), (kr, name_r))) = film_pair(models, recs) {
        let mut ratio = vec![vec![None; n0]; n1];
        for i0 in 0..n0 {
            for i1 in 0..n1 {
                let r = at(i0, i1);
                if let (Some(l), Some(re)) = (obs(&r.models[kl]), obs(&r.models[kr])) {
                    let q = l.central_film_m / re.central_film_m;
                    ratio[i1][i0] = Some(q);
                    agree[i1][i0] = (q - 1.0).abs() <= 0.1;
                }
            }
        }
        panels.push(CellPanel {
            title: format!(
                "{} h_c / {} h_c (outlined: within 10 %)",
                title_case(&name_l),
                title_case(&name_r)
            ),
            values: ratio,
            outline: agree.clone(),
            log_colour: false,
            digits: 3,
            labels: vec![],
        });
    }
    // Every indicator of every model beside it, with the same outline.
    for ind in indicators(models, recs) {
        for &k in &ind.models {
            let mut v = vec![vec![None; n0]; n1];
            for i0 in 0..n0 {
                for i1 in 0..n1 {
                    v[i1][i0] = at(i0, i1).models[k].indicators.get(&ind.name).map(|i| i.value);
                }
            }
            panels.push(CellPanel {
                title: format!("{}: {}", title_case(&model_name(models[k])), ind.description),
                values: v,
                outline: agree.clone(),
                log_colour: ind.log_scale,
                digits: 3,
                labels: vec![],
            });
        }
    }
    let mut cost_panels = vec![];
    for (k, &m) in models.iter().enumerate() {
        let mut t = vec![vec![None; n0]; n1];
        for i0 in 0..n0 {
            for i1 in 0..n1 {
                let mr = &at(i0, i1).models[k];
                t[i1][i0] = mr.observables.is_some().then_some(mr.wall_time_s);
            }
        }
        cost_panels.push(CellPanel {
            title: format!("{} wall time [s] (blank: failed)", model_name(m)),
            values: t,
            outline: vec![vec![false; n0]; n1],
            log_colour: true,
            digits: 2,
            labels: vec![],
        });
    }
    let xl = format!("{} [{}]", a0.parameter.name(), a0.parameter.unit());
    let yl = format!("{} [{}]", a1.parameter.name(), a1.parameter.unit());
    if !panels.is_empty() {
        put(files, ctx.dir, "sweep_film_ratio.png", &|f| {
            plot::cell_maps(f, &panels, &ticks(a0), &ticks(a1), &xl, &yl, note)
        })?;
    }
    put(files, ctx.dir, "sweep_cost.png", &|f| {
        plot::cell_maps(f, &cost_panels, &ticks(a0), &ticks(a1), &xl, &yl, note)
    })?;
    Ok(())
}
