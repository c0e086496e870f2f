//! `cargo xtask waves`: the amplitude-reduction study. Runs the built-in sweep
//! `waviness-reduction` (a transverse wave through the seed's contact, flooded, two wavelengths
//! over speed, both models), sets each point's deformed amplitude `A_d/A_i`
//! against Venner's parameter `∇ = (λ/a) M^(3/4) / L^(1/2)` (reference/amplitude-reduction.json),
//! checks the collapse (the two wavelengths' curves at the same `∇`), charts it and writes
//! `docs/measured/waviness-reduction.md`.

use crate::measured::{self, Table};
use anyhow::{Context, Result};
use ehl_workbench::plot::{self, Mark, Panel, Series};
use ehl_workbench::{compare, sweep};
use std::collections::BTreeMap;
use std::path::Path;

/// One model's answer at one point: speed [m/s], `λ/a`, `M`, `L`, `∇`, `A_d/A_i`.
#[derive(Clone, Copy)]
struct Row {
    speed: f64,
    wave_a: f64,
    m: f64,
    l: f64,
    nabla: f64,
    ratio: Option<f64>,
}

/// The ratio of the curve `curve` (points `(∇, A_d/A_i)` of one wavelength, sorted by `∇`) at `x`,
/// linear in `log ∇` and `log A_d/A_i` between its points; `None` outside it.
fn on_curve(curve: &[(f64, f64)], x: f64) -> Option<f64> {
    curve.windows(2).find(|w| w[0].0 <= x && x <= w[1].0).map(|w| {
        let t = (x.ln() - w[0].0.ln()) / (w[1].0.ln() - w[0].0.ln());
        (w[0].1.ln() + t * (w[1].1.ln() - w[0].1.ln())).exp()
    })
}

pub fn run(out: &Path) -> Result<()> {
    let (mut s, dir_of) = ehl_scene::load_sweep("waviness-reduction")?;
    if crate::quick() {
        // The code path on 65² (both waves, 6.4 and 12.8 cells each), two speeds whose
        // curves meet at one ∇.
        s.parameters[0].values = Some(vec![0.1, 0.3]);
    }
    let (plan, ran, recs) = crate::sweep_page::run_afresh(&s, dir_of.as_deref(), out)?;
    let mut rows: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    for (p, r) in plan.points.iter().zip(&recs) {
        let sc = &p.scene;
        let u = sc.conditions.rolling_velocity_m_s.context("the sweep's scene rolls")?;
        let lub = sc.lubricant.context("the sweep's scene has a lubricant")?.lubricant();
        let contact = sc.conditions.contact();
        let moes = ehl_core::Moes::from_si(&contact, &lub, 2.0 * u);
        let a = ehl_core::HertzScales::new(&contact).a;
        let wave_m = r.values[1];
        let wave_a = wave_m / a;
        let nabla = wave_a * moes.m.powf(0.75) / moes.l.sqrt();
        for m in &r.models {
            let ratio = m.passage.and_then(|q| q.amplitude_ratio);
            // An answer without its wave's amplitude is a broken study, not a point to skip.
            if m.observables.is_some() && ratio.is_none() {
                anyhow::bail!(
                    "{} at point {}: answered without a deformed amplitude",
                    compare::model_name(m.model),
                    r.index
                );
            }
            let row = Row { speed: u, wave_a, m: moes.m, l: moes.l, nabla, ratio };
            rows.entry(compare::model_name(m.model)).or_default().push(row);
        }
    }
    let mut t = Table::new(&["model", "u [m/s]", "λ / a", "M", "L", "∇", "A_d / A_i"]);
    let mut collapse = Table::new(&[
        "model",
        "u [m/s]",
        "λ / a",
        "∇",
        "A_d / A_i",
        "the other wavelength's curve at this ∇",
        "difference",
    ]);
    let mut series = vec![];
    for (model, rs) in &rows {
        for r in rs {
            t.rows.push(vec![
                model.clone(),
                format!("{}", r.speed),
                format!("{:.3}", r.wave_a),
                format!("{:.0}", r.m),
                format!("{:.2}", r.l),
                format!("{:.2}", r.nabla),
                r.ratio.map_or("—".into(), |v| format!("{v:.4}")),
            ]);
        }
        // One curve a wavelength, over the speeds; λ/a is the same to rounding at every speed
        // (one contact), so the curves are keyed by it to three places.
        let key = |r: &Row| (r.wave_a * 1e3).round() as i64;
        let mut waves: Vec<i64> = rs.iter().map(key).collect();
        waves.sort();
        waves.dedup();
        let curve = |w: i64| {
            let mut c: Vec<(f64, f64)> = rs
                .iter()
                .filter(|r| key(r) == w)
                .filter_map(|r| r.ratio.map(|v| (r.nabla, v)))
                .collect();
            c.sort_by(|x, y| x.0.total_cmp(&y.0));
            c
        };
        for &w in &waves {
            let label = format!("{model}, λ = {:.2} a", w as f64 / 1e3);
            series.push(Series::new(label, curve(w), Mark::LinePoints));
        }
        // The collapse: each point of one wavelength against the other wavelength's curve
        // where it reaches the same ∇ (at another speed: other M and L).
        for &w in &waves {
            for &v in waves.iter().filter(|&&v| v != w) {
                let other = curve(v);
                for r in rs.iter().filter(|r| key(r) == w) {
                    let (Some(here), Some(there)) = (r.ratio, on_curve(&other, r.nabla)) else {
                        continue;
                    };
                    collapse.rows.push(vec![
                        model.clone(),
                        format!("{}", r.speed),
                        format!("{:.3}", r.wave_a),
                        format!("{:.2}", r.nabla),
                        format!("{here:.4}"),
                        format!("{there:.4} (λ = {:.2} a)", v as f64 / 1e3),
                        format!("{:+.0} %", 100.0 * (here / there - 1.0)),
                    ]);
                }
            }
        }
    }
    std::fs::create_dir_all(out)?;
    let png = out.join("waviness-reduction.png");
    plot::charts(
        &png,
        &[Panel::new(
            "A wave's deformed amplitude at the contact's centre",
            "∇ = (λ/a) M^(3/4) / L^(1/2)",
            "A_d / A_i",
            series,
        )
        .log_log()],
        "the sweep waviness-reduction: the seed's contact flooded (Reynolds) or fed 25 nm (layer)",
    )?;
    println!("wrote {}", png.display());
    let g = plan.points[0].scene.grid();
    measured::write(
        "waviness-reduction",
        "The amplitude reduction of a wave through the contact",
        "cargo xtask waves",
        &format!(
            "`ehl sweep waviness-reduction`: {}\n\n{} points on {}² in {:.0} s on {} cores. \
             `A_d/A_i`: the amplitude of the film's oscillation at the contact's centre over \
             the last passage (a passage that repeats, or the time limit), per the surfaces' \
             amplitude; `∇` with the point's Moes `M` and `L` and the Hertz radius `a`. The \
             collapse table sets each point against the other wavelength's curve at the same \
             `∇` (interpolated in `log ∇`, `log A_d/A_i`), reached there at other `M` and `L`; \
             the principle says the difference is nil. The chart: `waviness-reduction.png` in \
             the study's folder (`--out`).",
            s.description,
            plan.points.len(),
            g.nx,
            ran.wall_time_s,
            sweep::default_jobs(),
        ),
        &[("Every point", &t), ("The collapse", &collapse)],
    )?;
    Ok(())
}
