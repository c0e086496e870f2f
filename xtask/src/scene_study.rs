//! `cargo xtask convergence <scene> [--grids 65,129,257,513]`: a grid study of any scene, one-model
//! or comparison, through the same path as `ehl compare`: each model's observables per grid, the
//! observed orders of its central and minimum film (and of a wave's `A_d/A_i` where a pattern
//! rolled), a Richardson reference, and one
//! speed-against-accuracy chart with every model on the same axes (wall times on one thread).

use anyhow::{Result, bail};
use ehl_core::Passage;
use ehl_core::hertz::observed_order_of_three;
use ehl_workbench::plot::{self, Mark, Panel, Series};
use ehl_workbench::{compare, sweep};
use serde_json::json;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, serde::Serialize)]
struct Point {
    n: usize,
    converged: bool,
    diagnosis: Option<String>,
    central_film_nm: f64,
    minimum_film_nm: f64,
    max_pressure_gpa: f64,
    /// The last passage of a pattern (its films, `λ`, a wave's `A_d/A_i`), when one rolled.
    passage: Option<ehl_core::Passage>,
    wall_time_s: f64,
}

/// The grid study as a sweep over `grid.n` (no domain adaptation, no checks: the study is the
/// check), run in parallel through `ehl_workbench::sweep`, one thread per grid; its folder
/// (`<out>/<scene>-grids`) holds the sweep's own results too.
pub fn run(scene: &str, grids: &[usize], variant: &Variant, out: &Path) -> Result<Vec<PathBuf>> {
    // What the study prints is also its page's body (for a built-in scene).
    let mut log = String::new();
    macro_rules! say {
        ($($t:tt)*) => {{
            let line = format!($($t)*);
            println!("{line}");
            log += &line;
            log.push('\n');
        }};
    }
    if grids.len() < 2 {
        bail!("--grids: at least two grids (three for observed orders)");
    }
    std::fs::create_dir_all(out)?;
    let (base, source) = variant.apply(ehl_scene::load(scene)?, out)?;
    // A pattern that repeats or a rough surface is measured over a passage; a run that ends
    // before one is complete has no statistics, which the page must say rather than omit.
    let patterned = base.run.as_ref().is_some_and(|r| {
        r.features.iter().any(|f| {
            use ehl_scene::Feature::*;
            matches!(f, Waviness(_) | Roughness(_) | HeightMap(_))
        })
    });
    let sweep: ehl_scene::Sweep = serde_json::from_value(json!({
        "name": format!("{}-grids", base.name),
        "scene": source.as_deref().unwrap_or(scene),
        "parameters": [{"parameter": "grid.n", "values": grids}],
        "adapt": false,
        "checks": false,
    }))?;
    sweep.validate("convergence study")?;
    let dir = out.join(&sweep.name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir)?; // a study measures time: never resume an old one
    }
    let plan = sweep::Plan::new(&sweep, None)?;
    plan.write(&dir)?;
    sweep::run(&dir, sweep::Shard::all(), sweep::default_jobs())?;
    sweep::merge::merge(&dir)?;
    let recs = sweep::records(&dir, &plan)?;
    let mut by_model: BTreeMap<String, Vec<Point>> = BTreeMap::new();
    for r in &recs {
        let n = r.nx;
        say!("{} on {n}²:", base.name);
        for m in &r.models {
            let name = compare::model_name(m.model);
            let p = match &m.observables {
                Some(ob) => Point {
                    n,
                    converged: true,
                    diagnosis: None,
                    central_film_nm: ob.central_film_m * 1e9,
                    minimum_film_nm: ob.minimum_film_m * 1e9,
                    max_pressure_gpa: ob.max_pressure_pa * 1e-9,
                    passage: m.passage,
                    wall_time_s: m.wall_time_s,
                },
                None => Point {
                    n,
                    converged: false,
                    diagnosis: m.diagnosis.clone(),
                    central_film_nm: f64::NAN,
                    minimum_film_nm: f64::NAN,
                    max_pressure_gpa: f64::NAN,
                    passage: None,
                    wall_time_s: m.wall_time_s,
                },
            };
            match &p.diagnosis {
                None => say!(
                    "  {:<9} h_c {:>10.4} nm  h_min {:>9.4} nm  p_max {:.5} GPa  {:>7.2} s",
                    name,
                    p.central_film_nm,
                    p.minimum_film_nm,
                    p.max_pressure_gpa,
                    p.wall_time_s
                ),
                Some(d) => say!("  {:<9} FAILED ({:.2} s): {d}", name, p.wall_time_s),
            }
            if let Some(q) = &p.passage {
                say!(
                    "  {:<9} last passage: h_c mean {:.4} nm ({:.4}–{:.4}){}",
                    "",
                    q.central_film_mean_m * 1e9,
                    q.central_film_min_m * 1e9,
                    q.central_film_max_m * 1e9,
                    q.amplitude_ratio.map_or(String::new(), |r| format!(", A_d/A_i {r:.4}"))
                        + &q.contact_load_share_mean.map_or(String::new(), |c| format!(
                            ", the solids' share {:.3} % (mean; {:.3} % at most)",
                            100.0 * c,
                            100.0 * q.contact_load_share_max.unwrap_or(c)
                        ))
                );
            } else if patterned && p.converged {
                say!(
                    "  {:<9} no passage: the pattern did not fill the domain before the run's time limit",
                    ""
                );
            }
            by_model.entry(name).or_default().push(p);
        }
    }
    let mut summary = serde_json::Map::new();
    let mut series = vec![];
    for (model, pts) in &by_model {
        let ok: Vec<&Point> = pts.iter().filter(|p| p.converged).collect();
        let mut orders = vec![];
        for w in ok.windows(3) {
            if w[1].n != 2 * w[0].n - 1 || w[2].n != 2 * w[1].n - 1 {
                continue; // orders need grids refined by 2
            }
            let oc = observed_order_of_three(
                w[0].central_film_nm,
                w[1].central_film_nm,
                w[2].central_film_nm,
                2.0,
            );
            let om = observed_order_of_three(
                w[0].minimum_film_nm,
                w[1].minimum_film_nm,
                w[2].minimum_film_nm,
                2.0,
            );
            say!(
                "  {model}: observed order {}→{}→{}: h_c {oc:.2}, h_min {om:.2}",
                w[0].n,
                w[1].n,
                w[2].n
            );
            // The last passage's statistics where each grid has them: a wave's deformed
            // amplitude, the solids' mean share of the load (where they touched), the mean
            // central film (and `λ` with it).
            let mut passage =
                |what: &str, unit: &str, scale: f64, get: fn(&Passage) -> Option<f64>| {
                    let line = passage_orders(w, what, unit, scale, get)?;
                    say!("  {model}: {}", line.0);
                    Some(line.1)
                };
            let amplitude = passage("A_d/A_i", "", 1.0, |q| q.amplitude_ratio);
            let share = passage("the solids' share", "", 1.0, |q| q.contact_load_share_mean);
            let mean_film =
                passage("the passage's mean h_c", " nm", 1e9, |q| Some(q.central_film_mean_m));
            orders.push(json!({
                "passage_central_film_mean": mean_film,
                "contact_load_share": share,
                "grids": [w[0].n, w[1].n, w[2].n],
                "central_film": oc,
                "minimum_film": om,
                "amplitude_ratio": amplitude,
            }));
        }
        // Reference: Richardson from the finest three at their observed order when it is
        // sensible (0.5 … 4), else the finest grid's value.
        let reference = match ok.len() {
            k if k >= 3 => {
                let c = ok[k - 1].central_film_nm;
                richardson(ok[k - 3].central_film_nm, ok[k - 2].central_film_nm, c).1.unwrap_or(c)
            }
            k if k >= 1 => ok[k - 1].central_film_nm,
            _ => f64::NAN,
        };
        let pts_xy: Vec<(f64, f64)> = ok
            .iter()
            .map(|p| (p.wall_time_s, (p.central_film_nm - reference).abs()))
            .filter(|(t, e)| *t > 0.0 && *e > 0.0)
            .collect();
        series.push(Series::new(
            format!("{model} (h_c against {reference:.4} nm)"),
            pts_xy,
            Mark::LinePoints,
        ));
        summary.insert(
            model.clone(),
            json!({"points": pts, "observed_orders": orders, "reference_central_film_nm": reference}),
        );
    }
    let stem = base.name.clone();
    let png = out.join(format!("{stem}_speed_accuracy.png"));
    plot::charts(
        &png,
        &[Panel::new(
            &format!("{stem}: error in h_c against wall time, grids {grids:?}"),
            "wall time [s], one thread",
            "|h_c − reference| [nm]",
            series,
        )
        .log_log()],
        "reference: Richardson from each model's finest 3 grids (its finest grid if the order is off 0.5-4)",
    )?;
    let js = out.join(format!("{stem}_convergence.json"));
    std::fs::write(
        &js,
        serde_json::to_string_pretty(&json!({"scene": stem, "grids": grids, "models": summary}))?
            + "\n",
    )?;
    println!("wrote {} and {}", png.display(), js.display());
    let mut files = vec![png, js];
    if ehl_scene::builtin_names().contains(&scene) {
        let list: Vec<String> = grids.iter().map(|n| n.to_string()).collect();
        let intro = format!(
            "The grid study of the built-in scene `{scene}`{}: every model on {} points per side \
             (the scene's domain, no adaptation, no checks), run in parallel, one thread per \
             grid; observed orders from grids refined by 2, and a wave's `A_d/A_i` and the \
             solids' share of the load with their orders and Richardson limits where a pattern \
             rolled.\n\n```\n{log}```\n",
            variant.words(),
            list.join(", ")
        );
        files.push(crate::measured::write(
            &format!("convergence-{stem}"),
            &format!("Grid convergence of `{scene}`{}", variant.words()),
            &format!(
                "cargo xtask convergence {scene} --grids {}{}",
                list.join(","),
                variant.args()
            ),
            &intro,
            &[],
        )?);
    }
    Ok(files)
}

/// A passage statistic (`get`, times `scale` in `unit`) of the three grids `w`: the page's line
/// (`{what} a, b, c{unit}: observed order …, limit …`) and its JSON; `None` unless every grid
/// has it and it is not zero on all three (the solids never touched: no order to observe).
fn passage_orders(
    w: &[&Point],
    what: &str,
    unit: &str,
    scale: f64,
    get: fn(&Passage) -> Option<f64>,
) -> Option<(String, serde_json::Value)> {
    let v: Vec<f64> = w.iter().filter_map(|p| p.passage.as_ref().and_then(get)).collect();
    if v.len() != 3 || v.iter().all(|&x| x == 0.0) {
        return None;
    }
    let v: Vec<f64> = v.iter().map(|x| x * scale).collect();
    let (o, limit) = richardson(v[0], v[1], v[2]);
    let line = format!(
        "{what} {:.4}, {:.4}, {:.4}{unit}: observed order {o:.2}, limit {}",
        v[0],
        v[1],
        v[2],
        limit.map_or("— (order off 0.5–4)".into(), |l| format!("{l:.4}{unit}"))
    );
    Some((line, json!({"values": v, "unit": unit.trim(), "order": o, "limit": limit})))
}

/// The observed order of three values on grids refined by 2 (coarsest first), and the
/// Richardson limit at that order when the order is sensible (0.5 … 4).
fn richardson(coarse: f64, medium: f64, fine: f64) -> (f64, Option<f64>) {
    let o = observed_order_of_three(coarse, medium, fine, 2.0);
    (o, (0.5..=4.0).contains(&o).then(|| fine + (fine - medium) / (2f64.powf(o) - 1.0)))
}

/// A scene study of a variant of its scene: some of its models, another rolling speed.
#[derive(Clone, Debug, Default)]
pub struct Variant {
    /// The models kept, by name (empty: all the scene's).
    pub models: Vec<String>,
    /// The rolling speed [m/s] instead of the scene's.
    pub speed_m_s: Option<f64>,
}

impl Variant {
    /// The scene as the variant runs it, named for it, and the file it was written to (in
    /// `out`) when it differs from the scene; checked as every scene is.
    fn apply(
        &self,
        base: ehl_scene::Scene,
        out: &Path,
    ) -> Result<(ehl_scene::Scene, Option<String>)> {
        if self.models.is_empty() && self.speed_m_s.is_none() {
            return Ok((base, None));
        }
        let mut s = base.clone();
        if !self.models.is_empty() {
            let models = self
                .models
                .iter()
                .map(|m| {
                    let found = serde_json::from_value::<ehl_scene::Model>(json!(m));
                    match found {
                        Ok(model) if base.models().contains(&model) => Ok(model),
                        _ => Err(anyhow::anyhow!(
                            "--models: `{m}` is not one of the scene's models ({})",
                            base.model_names()
                        )),
                    }
                })
                .collect::<Result<Vec<_>>>()?;
            s = s.comparing(&models)?;
        }
        if let Some(u) = self.speed_m_s {
            // As a speed sweep sets it: a rolling march keeps its travel (its time limit and
            // snapshots scaled with the speed), so a pattern still fills the contact.
            s = s
                .with_parameter(ehl_scene::Parameter::RollingVelocity, u)
                .map_err(|e| anyhow::anyhow!("--speed {u}: {e}"))?;
        }
        s.name = format!("{}{}", base.name, self.suffix());
        let text = serde_json::to_string_pretty(&s)?;
        // Checked as a file is, before any point runs.
        ehl_scene::Scene::from_json(&text, "convergence --models/--speed")?;
        let path = out.join(format!("{}.json", s.name));
        std::fs::write(&path, text + "\n")?;
        Ok((s, Some(path.display().to_string())))
    }

    /// The variant in a name (a scene's name takes letters, digits, `-` and `_`):
    /// `-layer-u0_005`.
    fn suffix(&self) -> String {
        let models = self.models.iter().map(|m| format!("-{m}")).collect::<String>();
        let speed = self.speed_m_s.map_or(String::new(), |u| format!("-u{u}").replace('.', "_"));
        models + &speed
    }

    /// The variant in words, for the page: ` (the layer model alone, at 0.005 m/s)`.
    fn words(&self) -> String {
        let mut parts = vec![];
        if !self.models.is_empty() {
            parts.push(format!("{} alone", self.models.join(" and ")));
        }
        if let Some(u) = self.speed_m_s {
            parts.push(format!("at {u} m/s"));
        }
        if parts.is_empty() { String::new() } else { format!(" ({})", parts.join(", ")) }
    }

    /// The variant as the command's options.
    fn args(&self) -> String {
        let models = if self.models.is_empty() {
            String::new()
        } else {
            format!(" --models {}", self.models.join(","))
        };
        models + &self.speed_m_s.map_or(String::new(), |u| format!(" --speed {u}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_variant_at_half_the_speed_rolls_the_same_travel_in_twice_the_time() {
        // A march stopped at the scene's time at half its speed rolls half the travel: the
        // roughness that rolls in over the domain would not fill it, and the study would
        // have no passage to measure.
        let base = ehl_scene::builtin("roughness-mixed-compare").unwrap();
        let t0 = base.run.as_ref().unwrap().stop.max_time_s.unwrap();
        let u0 = base.conditions.rolling_velocity_m_s.unwrap();
        let dir = std::env::temp_dir().join(format!("ehl-variant-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let v = Variant { models: vec!["layer".into()], speed_m_s: Some(0.5 * u0) };
        let (s, file) = v.apply(base, &dir).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let t = s.run.as_ref().unwrap().stop.max_time_s.unwrap();
        assert!((t / t0 - 2.0).abs() < 1e-12, "{t} s against {t0} s");
        assert_eq!(s.conditions.rolling_velocity_m_s, Some(0.5 * u0));
        assert!(file.is_some_and(|f| f.ends_with("-layer-u0_005.json")));
    }
}
