//! The layer model (and the Reynolds reference) against the values the seed reports
//! (`reference/seed.json`), on the seed's grid: each built-in scene that reproduces one of its
//! numbers, run and set against it in Hertz-normalised form. Writes
//! `docs/measured/seed-against-ours.md`. The tests (`validation/tests/seed.rs`) hold the same
//! comparisons on coarse grids.

use crate::measured::{self, Table};
use anyhow::{Context, Result};
use ehl_workbench::{Outcome, layer::LayerOutcome, run_scene};
use serde_json::Value;

/// The seed's value of `id` (`reference/seed.json`): as it reports it, and normalised.
fn seed(id: &str) -> Result<(f64, Option<f64>, String)> {
    let r: Value = serde_json::from_str(include_str!("../../reference/seed.json"))?;
    let v = r["values"]
        .as_array()
        .and_then(|a| a.iter().find(|v| v["id"] == id))
        .with_context(|| format!("{id} in reference/seed.json"))?;
    Ok((
        v["value"].as_f64().unwrap_or(f64::NAN),
        v["normalised"].as_f64(),
        v["section"].as_str().unwrap_or_default().to_string(),
    ))
}

/// A built-in layer scene on `n`² without its snapshots, edited, run.
fn layer(scene: &str, n: usize, edit: impl Fn(&mut ehl_scene::Scene)) -> Result<LayerOutcome> {
    let mut s = ehl_scene::builtin(scene)?.with_points(n)?;
    if let Some(r) = s.run.as_mut() {
        r.snapshots_s.clear();
        r.snapshots_a.clear();
    }
    s.outputs.figures = false;
    edit(&mut s);
    Ok(*run_scene(&s)?.downcast::<LayerOutcome>().context("a layer scene")?)
}

/// Runs the comparisons on `n`² and writes the page.
pub fn run(n: usize, out: &std::path::Path) -> Result<()> {
    let mut t = Table::new(&["quantity", "seed (its section)", "ours", "deviation", "scene"]);
    let mut row = |what: &str, id: &str, ours: f64, unit: &str, scene: &str| -> Result<()> {
        let (value, normalised, section) = seed(id)?;
        let want = normalised.unwrap_or(value);
        t.rows.push(vec![
            what.to_string(),
            format!("{want:.4}{unit} (§{section})"),
            format!("{ours:.4}{unit}"),
            format!("{:+.1} %", (ours / want - 1.0) * 100.0),
            format!("`{scene}`"),
        ]);
        Ok(())
    };
    // The steady squeeze, solved directly.
    let sq = layer("squeeze-steady", n, |_| {})?;
    let (s, ob) = (sq.scales, sq.observables());
    row(
        "steady squeeze: p_max / p_h",
        "squeeze_max_pressure",
        ob.max_pressure_pa / s.p_h,
        "",
        "squeeze-steady",
    )?;
    row(
        "steady squeeze: contact diameter / 2a",
        "squeeze_contact_diameter",
        ob.contact_extent_x_m / (2.0 * s.a),
        "",
        "squeeze-steady",
    )?;
    row(
        "steady squeeze: dry diameter / 2a",
        "squeeze_dry_diameter",
        sq.final_monitor.dry_diameter / (2.0 * s.a),
        "",
        "squeeze-steady",
    )?;
    // Steady rolling, solved directly.
    let roll = layer("rolling-steady", n, |_| {})?;
    let hc = roll.final_monitor.central_thickness / roll.supply_thickness_m();
    row("steady rolling: h_c / l0", "rolling_central_thickness", hc, "", "rolling-steady")?;
    // The squeeze after a stop: when the maximum pressure peaks, when the run's rule finds it
    // steady.
    let stop = layer("squeeze-after-stop", n, |_| {})?;
    if let Some(rec) = stop.record.as_ref() {
        let peak = rec
            .observed
            .iter()
            .max_by(|a, b| a.1.max_pressure_pa.total_cmp(&b.1.max_pressure_pa))
            .map_or(f64::NAN, |o| o.0);
        row(
            "squeeze: the maximum pressure's peak [s]",
            "squeeze_peak_time",
            peak,
            " s",
            "squeeze-after-stop",
        )?;
        row(
            "squeeze: steady by the run's rule [s]",
            "squeeze_time_to_steady",
            stop.final_state.t,
            " s",
            "squeeze-after-stop",
        )?;
    }
    // The hole centred: its drop of the central pressure against steady rolling.
    let hole = layer("hole", n, |s| {
        if let Some(r) = s.run.as_mut() {
            r.stop.until_features_passed = false;
            r.stop.until_feature_at_a = Some(0.0);
        }
    })?;
    let drop = 1.0 - hole.final_monitor.central_pressure / roll.final_monitor.central_pressure;
    row("hole centred: central pressure drop", "hole_central_pressure_drop", drop, "", "hole")?;
    // The Reynolds reference the seed drew its Fig. 4 from.
    // Quickly, the least grid its film exists on.
    let rey = run_scene(&ehl_scene::builtin("reynolds-seed")?.with_points(crate::seed_grid(n))?)?;
    let l0 = ehl_layer::SEED_SUPPLY_THICKNESS_M;
    row(
        "Reynolds: h_c / l0",
        "reynolds_central_film",
        rey.observables().central_film_m / l0,
        "",
        "reynolds-seed",
    )?;
    let intro = format!(
        "The values the seed reports (`reference/seed.json`, with the section each comes from) \
         against the built-in scenes that reproduce them, on {n}² (the seed's grid), in \
         Hertz-normalised form: the seed's with the contact its time step implies (`a` = 0.13697 \
         mm, `p_h` = 0.509 GPa), ours with Table 1's. Times in seconds are the damper's, not \
         normalised. Why each differs: docs/layer.md. The tests in `validation/tests/seed.rs` \
         hold the same comparisons on coarse grids."
    );
    std::fs::create_dir_all(out)?;
    let rows: Vec<serde_json::Value> = t
        .rows
        .iter()
        .map(|r| serde_json::json!({"quantity": r[0], "seed": r[1], "ours": r[2], "deviation": r[3], "scene": r[4]}))
        .collect();
    std::fs::write(
        out.join("seed-against-ours.json"),
        serde_json::to_string_pretty(&rows)? + "\n",
    )?;
    measured::write(
        "seed-against-ours",
        "The seed's reported values against the workbench",
        &format!("cargo xtask seed --points {n}"),
        &intro,
        &[("Each value", &t)],
    )?;
    Ok(())
}
