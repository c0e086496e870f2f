//! Seed Fig. 7 and its table: the layer model, the Reynolds solver and the dry contact under
//! the same conditions (Table 1, the layer model's domain and grid), along the centreline.

use anyhow::{Result, bail};
use ehl_cli::layer::LayerOutcome;
use ehl_cli::plot::{self, Mark, Panel, Series};
use ehl_cli::reynolds::ReynoldsOutcome;
use ehl_cli::{Outcome, run_scene};
use ehl_core::Grid;
use ehl_scene::Model;
use ndarray::Array2;
use plotters::prelude::SeriesLabelPosition;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Pressure below which a point counts as outside the contact [p_h]: Reynolds pressure has an
/// inlet tail that never reaches zero, so the contact size needs a threshold; 1 % of `p_h`.
const CONTACT_THRESHOLD: f64 = 0.01;

/// Length of the stretch where `p > CONTACT_THRESHOLD` along a line, linearly interpolated at
/// the two crossings [in units of the spacing's unit].
fn extent(v: &[f64], h: f64) -> f64 {
    let above: Vec<usize> = (0..v.len()).filter(|&i| v[i] > CONTACT_THRESHOLD).collect();
    let (Some(&i0), Some(&i1)) = (above.first(), above.last()) else { return 0.0 };
    let cross = |a: usize, b: usize| -> f64 {
        // Fraction of the cell from a (outside) to b (inside) where the threshold is crossed.
        (CONTACT_THRESHOLD - v[a]) / (v[b] - v[a])
    };
    let left = if i0 > 0 { i0 as f64 - 1.0 + cross(i0 - 1, i0) } else { 0.0 };
    let right =
        if i1 + 1 < v.len() { i1 as f64 + 1.0 - cross(i1 + 1, i1) } else { (v.len() - 1) as f64 };
    (right - left) * h
}

struct Row {
    model: &'static str,
    central_nm: f64,
    minimum_nm: f64,
    p_max_ph: f64,
    diameter_x_a: f64,
    diameter_y_a: f64,
}

fn row(model: &'static str, g: &Grid, p: &Array2<f64>, film_nm: &Array2<f64>) -> Row {
    let (j0, i0) = (g.row_nearest(0.0), g.col_nearest(0.0));
    let along_x: Vec<f64> = p.row(j0).to_vec();
    let along_y: Vec<f64> = p.column(i0).to_vec();
    // Minimum film over the contact (where the pressure is above the threshold): outside it the
    // dry gap and the layer model's film are undefined or open.
    let minimum = film_nm
        .iter()
        .zip(p.iter())
        .filter(|(_, p)| **p > CONTACT_THRESHOLD)
        .map(|(f, _)| *f)
        .fold(f64::INFINITY, f64::min);
    Row {
        model,
        central_nm: film_nm[[j0, i0]],
        minimum_nm: minimum,
        p_max_ph: p.iter().cloned().fold(0.0, f64::max),
        diameter_x_a: extent(&along_x, g.dx()),
        diameter_y_a: extent(&along_y, g.dy()),
    }
}

/// Fig. 7 analogue and the table, into `out`.
pub fn fig7(layer: &LayerOutcome, rey: &ReynoldsOutcome, out: &Path) -> Result<Vec<PathBuf>> {
    let g = layer.grid;
    if rey.grid != g {
        bail!("Fig. 7 needs the layer and Reynolds scenes on one grid and domain");
    }
    // The dry contact of the same scene: the layer scene with its layer taken away.
    let mut dry = layer.scene.clone();
    dry.model = Model::Dry;
    dry.layer = None;
    dry.run = None;
    dry.lubricant = None;
    dry.conditions.rolling_velocity_m_s = None;
    dry.name = format!("{}-dry", layer.scene.name);
    let Outcome::Dry(dry) = run_scene(&dry)? else { unreachable!("dry scene") };
    let nm_layer = layer.scales.delta * 1e9;
    let nm_rey = rey.prm.scales.delta * 1e9;
    let nm_dry = dry.scales.delta * 1e9;
    let p_layer = &layer.final_state.p;
    let rows = [
        row("layer model", &g, p_layer, &layer.l.mapv(|v| v * nm_layer)),
        row("Reynolds", &g, &rey.p, &rey.film.mapv(|v| v * nm_rey)),
        row("dry contact", &g, &dry.p, &dry.gap.mapv(|v| v * nm_dry)),
    ];
    println!(
        "Side by side (Table 1, {}x{} over [{}, {}] a): film = layer thickness (layer model), oil film (Reynolds), gap (dry)",
        g.nx, g.ny, g.x_min, g.x_max
    );
    println!(
        "  {:<12} {:>14} {:>14} {:>12} {:>12} {:>12}",
        "model", "central [nm]", "minimum [nm]", "p_max [p_h]", "2a_x [a]", "2a_y [a]"
    );
    for r in &rows {
        println!(
            "  {:<12} {:>14.3} {:>14.3} {:>12.4} {:>12.4} {:>12.4}",
            r.model, r.central_nm, r.minimum_nm, r.p_max_ph, r.diameter_x_a, r.diameter_y_a
        );
    }
    let j0 = g.row_nearest(0.0);
    let xs = g.xs();
    let line = |a: &Array2<f64>, k: f64, cap: f64| -> Vec<(f64, f64)> {
        xs.iter().zip(a.row(j0).iter()).map(|(&x, &v)| (x, v * k)).filter(|v| v.1 <= cap).collect()
    };
    // Films beyond 60 nm (the open gap outside the contact) are left off the film panel.
    let cap = 60.0;
    let png = out.join("fig7_centreline_layer_reynolds_dry.png");
    plot::charts(
        &png,
        &[
            Panel::new(
                "Pressure along y = 0",
                "x / a",
                "p / p_h",
                vec![
                    Series::new("layer model", line(p_layer, 1.0, f64::MAX), Mark::Line),
                    Series::new("Reynolds", line(&rey.p, 1.0, f64::MAX), Mark::Line),
                    Series::new("dry contact", line(&dry.p, 1.0, f64::MAX), Mark::Line),
                ],
            )
            .legend(SeriesLabelPosition::UpperLeft),
            Panel::new(
                "Layer thickness / film along y = 0 (up to 60 nm)",
                "x / a",
                "[nm]",
                vec![
                    Series::new("layer thickness l", line(&layer.l, nm_layer, cap), Mark::Line),
                    Series::new("Reynolds film h", line(&rey.film, nm_rey, cap), Mark::Line),
                    Series::new("dry gap", line(&dry.gap, nm_dry, cap), Mark::Line),
                ],
            )
            .legend(SeriesLabelPosition::UpperRight),
        ],
        &format!(
            "seed Fig. 7 analogue: {} (steady) against {} and the dry contact; Table 1, {}x{}",
            layer.scene.name, rey.scene.name, g.nx, g.ny
        ),
    )?;
    let table = out.join("fig7_table.json");
    let v: Vec<_> = rows
        .iter()
        .map(|r| {
            json!({"model": r.model, "central_film_nm": r.central_nm, "minimum_film_nm": r.minimum_nm,
                "max_pressure_ph": r.p_max_ph, "contact_diameter_x_a": r.diameter_x_a,
                "contact_diameter_y_a": r.diameter_y_a})
        })
        .collect();
    std::fs::write(
        &table,
        serde_json::to_string_pretty(&json!({
            "what": "Seed Fig. 7 table: central and minimum film (layer thickness for the layer model), maximum pressure and contact size, same conditions and grid",
            "contact_size": format!("extent along the centre lines where p > {CONTACT_THRESHOLD} p_h"),
            "minimum_film": format!("over the points where p > {CONTACT_THRESHOLD} p_h"),
            "grid": [g.nx, g.ny], "rows": v,
            "seed_reported_nm": {"reynolds_central": 12.3, "layer_central": 11.6},
        }))? + "\n",
    )?;
    Ok(vec![png, table])
}

#[cfg(test)]
mod tests {
    #[test]
    fn extent_interpolates_the_crossings() {
        // Linear ramps crossing 0.01 at x = 0.5 and x = 3.5 (spacing 1).
        let v = [0.0, 0.02, 0.5, 0.02, 0.0];
        assert!((super::extent(&v, 1.0) - 3.0).abs() < 1e-12);
        assert_eq!(super::extent(&[0.0; 4], 1.0), 0.0);
    }
}
