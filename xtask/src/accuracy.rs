//! Whether the error estimate every answer carries can be trusted: on the Reynolds stability
//! map (Moes' `M`, `L`, the flooded solver) and on `seed-speed` (the seed's contact over speed,
//! every lubricated model), each answer on its default grid with its estimate
//! ([`ehl_workbench::accuracy::estimate`]) against its actual error: the same point on grids 2×
//! and 4× finer per side, their Richardson limit with the three grids' observed order (the
//! finest grid's answer where the three show none). Writes `docs/measured/accuracy.md`.

use crate::measured::{self, Table};
use anyhow::Result;
use ehl_scene::{Model, Scene};
use ehl_workbench::{accuracy, run_scene};
use rayon::prelude::*;
use serde_json::Value;
use std::path::Path;

/// One case: its name, the model's scene on the default grid.
struct Case {
    name: String,
    scene: Scene,
}

/// What a case gave: per film (central, minimum) the estimated and the actual error (relative to
/// the film's scale), or why there is no comparison.
struct Row {
    name: String,
    model: String,
    outcome: Result<[(f64, f64); 2], String>,
}

/// The reference of an observable from the answers on `n`, `2n`, `4n` (per side): their
/// Richardson limit at the observed order when they converge monotonically at an order in
/// [0.5, 4], else the finest answer.
fn reference(f1: f64, f2: f64, f4: f64) -> f64 {
    let (e21, e42) = (f2 - f1, f4 - f2);
    if e21 != 0.0 && e42 / e21 > 0.0 {
        let p = (e21 / e42).log2();
        if (0.5..=4.0).contains(&p) {
            return f4 + e42 / (p.exp2() - 1.0);
        }
    }
    f4
}

/// The scene on `k`-fold refined grids (points `(n − 1) k + 1` per side).
fn refined(s: &Scene, k: usize) -> Scene {
    let mut r = s.clone();
    r.grid.nx = (s.grid.nx - 1) * k + 1;
    r.grid.ny = (s.grid.ny - 1) * k + 1;
    r
}

fn run_case(c: &Case) -> Row {
    let model = c.scene.model().map_or("", |m| m.name()).to_string();
    let go = || -> Result<[(f64, f64); 2], String> {
        let o = run_scene(&c.scene)
            .map_err(|e| format!("no answer on the default grid: {}", e.class()))?;
        let e = accuracy::estimate(&c.scene, o.as_ref());
        let ob = o.observables();
        let fine = |k: usize| {
            run_scene(&refined(&c.scene, k))
                .map(|o| o.observables())
                .map_err(|e| format!("no answer on the {k}× grid: {}", e.class()))
        };
        let (o2, o4) = (fine(2)?, fine(4)?);
        let scale = accuracy::film_scale(ob.central_film_m);
        let films = |o: &ehl_core::Observables| [o.central_film_m, o.minimum_film_m];
        let (f1, f2, f4) = (films(&ob), films(&o2), films(&o4));
        let mut out = [(f64::NAN, f64::NAN); 2];
        for k in 0..2 {
            let actual = (f1[k] - reference(f1[k], f2[k], f4[k])).abs() / scale;
            let est = e.errors[k].map_or(f64::NAN, |b| b.relative);
            out[k] = (est, actual);
        }
        if out.iter().all(|(est, _)| est.is_nan()) {
            return Err(format!("no estimate: {}", e.method));
        }
        Ok(out)
    };
    Row { name: c.name.clone(), model, outcome: go() }
}

/// The cases: the stability map's points on `n`² and `seed-speed`'s, each lubricated model.
fn cases(n: usize) -> Result<Vec<Case>> {
    let rc: Value = serde_json::from_str(include_str!("../../reference/reynolds_cases.json"))?;
    let list = |k: &str| -> Vec<f64> {
        rc[k].as_array().map_or(vec![], |a| a.iter().filter_map(Value::as_f64).collect())
    };
    let (mut ms, mut ls) = (list("m"), list("l"));
    if crate::quick() {
        ms.truncate(2);
        ls.truncate(2);
    }
    let base = ehl_scene::builtin("reynolds-m20-l10")?;
    let mut out = vec![];
    for &l in &ls {
        for &m in &ms {
            let mut s = base.clone();
            if let Some(r) = s.reynolds.as_mut()
                && let Some(moes) = r.moes.as_mut()
            {
                moes.m = m;
                moes.l = l;
            }
            // The map's own domains: the standard one, the narrow one from M = 500.
            s.domain = if m >= 500.0 {
                ehl_scene::Domain { x_a: [-1.25, 1.25], y_a: [-1.25, 1.25] }
            } else {
                ehl_scene::Domain { x_a: [-4.5, 1.5], y_a: [-3.0, 3.0] }
            };
            s.grid = ehl_scene::GridSpec { nx: n, ny: n };
            s.outputs.figures = false;
            s.validate("accuracy study")?;
            out.push(Case { name: format!("map M = {m}, L = {l}"), scene: s });
        }
    }
    let (sweep, _) = ehl_scene::load_sweep("seed-speed")?;
    let mut speeds = sweep.parameters[0].values();
    if crate::quick() {
        speeds = vec![speeds[speeds.len() - 1]];
    }
    let seed = ehl_scene::builtin("seed")?.with_points(n)?;
    for u in speeds {
        let s = seed
            .with_parameter(ehl_scene::Parameter::RollingVelocity, u)
            .map_err(anyhow::Error::msg)?;
        for m in [Model::Layer, Model::Reynolds, Model::ReynoldsFlooded] {
            let mut one = s.for_model(m);
            one.outputs.figures = false;
            out.push(Case { name: format!("seed-speed u1 = {u} m/s"), scene: one });
        }
    }
    Ok(out)
}

/// Runs the study on `n`² (its answers' grid; the reference grids 2× and 4× finer per side).
pub fn run(out: &Path, n: usize) -> Result<()> {
    std::fs::create_dir_all(out)?;
    let cases = cases(n)?;
    println!("{} cases on {n}², references on {}² and {}²", cases.len(), 2 * n - 1, 4 * n - 3);
    // The cases in parallel, each on one thread (its numbers then do not depend on the others).
    let rows: Vec<Row> = cases
        .par_iter()
        .map(|c| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool");
            let r = pool.install(|| run_case(c));
            match &r.outcome {
                Ok(v) => println!(
                    "{} {}: h_c est {:.2} % actual {:.2} %, h_min est {:.2} % actual {:.2} %",
                    r.name,
                    r.model,
                    100.0 * v[0].0,
                    100.0 * v[0].1,
                    100.0 * v[1].0,
                    100.0 * v[1].1
                ),
                Err(why) => println!("{} {}: {why}", r.name, r.model),
            }
            r
        })
        .collect();
    let mut t = Table::new(&[
        "case",
        "model",
        "h_c estimated",
        "h_c actual",
        "bracketed",
        "h_min estimated",
        "h_min actual",
        "bracketed",
    ]);
    let (mut compared, mut bracketed, mut worst) = (0usize, 0usize, 0.0f64);
    let pct = |v: f64| if v.is_nan() { "—".to_string() } else { format!("{:.2} %", 100.0 * v) };
    for r in &rows {
        match &r.outcome {
            Ok(v) => {
                let mut cells = vec![r.name.clone(), r.model.clone()];
                for (est, actual) in v {
                    let ok = est.is_finite() && *est >= *actual;
                    if est.is_finite() {
                        compared += 1;
                        bracketed += ok as usize;
                        worst = worst.max(actual / est);
                    }
                    cells.extend([
                        pct(*est),
                        pct(*actual),
                        if ok { "yes".into() } else { "no".into() },
                    ]);
                }
                t.rows.push(cells);
            }
            Err(why) => {
                let mut cells = vec![r.name.clone(), r.model.clone(), why.clone()];
                cells.extend(std::iter::repeat_n(String::new(), 5));
                t.rows.push(cells);
            }
        }
    }
    let share = bracketed as f64 / compared.max(1) as f64;
    println!(
        "bracketed {bracketed} of {compared} ({:.0} %); the most an estimate understates: {worst:.2}×",
        100.0 * share
    );
    measured::write(
        "accuracy",
        "Does the error estimate hold?",
        &format!("cargo xtask accuracy --points {n}"),
        &format!(
            "Every answer's estimated error (the same model on half and a quarter of the points \
             per side: `ehl_workbench::accuracy::estimate`) against its actual error: the \
             Richardson limit of the same point on {n}², {}² and {}² (the finest where the three \
             show no order), both relative to the film's scale (the central film, at least 1 nm). \
             Cases: the Reynolds stability map (flooded, Moes' M and L, the map's domains) and \
             `seed-speed` (the seed's contact over rolling speed; the layer model, the fed and the \
             flooded Reynolds solver), each on {n}². An answer is bracketed when its estimate is at \
             least its actual error. **{bracketed} of {compared} estimates bracket the actual \
             error ({:.0} %); the most an estimate understates it is {worst:.2}×.** Cases without \
             an answer or without an estimate on {n}² are listed with why: they are flagged, not \
             estimated.",
            2 * n - 1,
            4 * n - 3,
            100.0 * share
        ),
        &[("Estimated against actual errors", &t)],
    )?;
    Ok(())
}
