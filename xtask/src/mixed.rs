//! `cargo xtask mixed`: the mixed-lubrication map. Runs the built-in sweep `mixed-lubrication`
//! (a rough surface rolling in over the seed's contact, over speed, both models), and sets each
//! model's share of the load its solids carry, and their area, against the film over the
//! roughness `λ` of the same passage; charts both and writes `docs/measured/mixed-lubrication.md`.

use crate::measured::{self, Table};
use anyhow::{Context, Result};
use ehl_workbench::plot::{self, Mark, Panel, Series};
use ehl_workbench::{compare, sweep};
use std::collections::BTreeMap;
use std::path::Path;

/// The bounds of the `λ` regimes the bearing and gear standards read (Tallian: below 1 the
/// asperities carry much of the load, above 3 the film separates the surfaces).
const REGIMES: [(f64, &str); 2] = [(1.0, "λ = 1"), (3.0, "λ = 3")];

pub fn run(out: &Path) -> Result<()> {
    let (mut s, dir_of) = ehl_scene::load_sweep("mixed-lubrication")?;
    if crate::quick() {
        // The code path on 65², in seconds: one speed whose film the roughness does not close,
        // the roughness' correlation length on the cells 65² carries (20 µm on 3.8 of them).
        s.parameters[0].values = Some(vec![0.1]);
    }
    let (plan, ran, recs) = if crate::quick() {
        let mut plan = sweep::Plan::new(&s, dir_of.as_deref())?;
        for p in &mut plan.points {
            let mut sc = p.scene.clone();
            if let Some(ehl_scene::Feature::Roughness(r)) =
                sc.run.as_mut().map(|r| &mut r.features[0])
            {
                r.correlation_length_m = 2e-5;
            }
            p.scene = sc.with_points(65)?;
        }
        crate::sweep_page::run_plan(plan, out)?
    } else {
        crate::sweep_page::run_afresh(&s, dir_of.as_deref(), out)?
    };
    let mut t = Table::new(&[
        "model",
        "u [m/s]",
        "λ",
        "h_c mean [nm]",
        "h_min [nm]",
        "the solids' share of the load, mean (largest)",
        "their area / πa², mean",
        "wall [s]",
    ]);
    let mut share: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut area: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    for (p, r) in plan.points.iter().zip(&recs) {
        let u = p.scene.conditions.rolling_velocity_m_s.context("the sweep's scene rolls")?;
        let a = ehl_core::HertzScales::new(&p.scene.conditions.contact()).a;
        let hertz_area = std::f64::consts::PI * a * a;
        for m in &r.models {
            let name = compare::model_name(m.model);
            let Some(q) = m.passage.filter(|_| m.observables.is_some()) else {
                let why = m.failure.clone().unwrap_or_else(|| "no passage".into());
                t.rows.push(vec![
                    name,
                    format!("{u}"),
                    format!("failed: {why}"),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    "—".into(),
                    format!("{:.0}", m.wall_time_s),
                ]);
                continue;
            };
            let lambda = q.lambda.context("a rough passage has its λ")?;
            let (mean, max) = (q.contact_load_share_mean, q.contact_load_share_max);
            let (Some(mean), Some(max), Some(ar)) = (mean, max, q.contact_area_mean_m2) else {
                anyhow::bail!("{name} at point {}: a passage without its contact", r.index);
            };
            t.rows.push(vec![
                name.clone(),
                format!("{u}"),
                format!("{lambda:.2}"),
                format!("{:.2}", q.central_film_mean_m * 1e9),
                format!("{:.2}", q.minimum_film_m * 1e9),
                format!("{:.3} % ({:.3} %)", 100.0 * mean, 100.0 * max),
                format!("{:.3} %", 100.0 * ar / hertz_area),
                format!("{:.0}", m.wall_time_s),
            ]);
            share.entry(name.clone()).or_default().push((lambda, 100.0 * mean));
            area.entry(name).or_default().push((lambda, 100.0 * ar / hertz_area));
        }
    }
    let series = |m: &BTreeMap<String, Vec<(f64, f64)>>| -> Vec<Series> {
        m.iter()
            .map(|(name, pts)| {
                let mut pts = pts.clone();
                pts.sort_by(|x, y| x.0.total_cmp(&y.0));
                Series::new(name.clone(), pts, Mark::LinePoints)
            })
            .collect()
    };
    let with_regimes = |p: Panel| REGIMES.iter().fold(p, |p, (x, l)| p.mark_x(*x, *l));
    std::fs::create_dir_all(out)?;
    let png = out.join("mixed-lubrication.png");
    plot::charts(
        &png,
        &[
            with_regimes(
                Panel::new(
                    "The share of the load the solids carry, mean over the last transit",
                    "λ = the passage's mean central film / Rq",
                    "load share [%]",
                    series(&share),
                )
                .log_x(),
            ),
            with_regimes(
                Panel::new(
                    "The area where the solids touch, mean over the last transit",
                    "λ = the passage's mean central film / Rq",
                    "contact area / πa² [%]",
                    series(&area),
                )
                .log_x(),
            ),
        ],
        "the sweep mixed-lubrication: 20 nm roughness over the seed's contact fed 200 nm, over speed",
    )?;
    println!("wrote {}", png.display());
    let g = plan.points[0].scene.grid();
    measured::write(
        "mixed-lubrication",
        "The mixed-lubrication map",
        "cargo xtask mixed",
        &format!(
            "`ehl sweep mixed-lubrication`: {}\n\n{} points on {}² in {:.0} s on {} cores. Over \
             the last transit of the domain (the rough surface fills it after the first): `λ` \
             the mean central film over `Rq`, the least film, the share of the load the solids \
             carry where they touch (the Reynolds solver: where its film closed in a step; the \
             layer model: where no layer is left) with its largest value, and their area over \
             the Hertz area `πa²`. The chart: `mixed-lubrication.png` in the study's folder \
             (`--out`), with the standards' regime bounds `λ` = 1 and 3. What it shows: \
             docs/findings.md, \"Mixed lubrication over a rough surface\".",
            s.description,
            plan.points.len(),
            g.nx,
            ran.wall_time_s,
            sweep::default_jobs(),
        ),
        &[("Every point", &t)],
    )?;
    Ok(())
}
