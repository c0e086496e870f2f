//! `cargo xtask waves`: the amplitude-reduction study. Runs the built-in sweep
//! `waviness-reduction` (a transverse wave through the seed's contact, flooded, two wavelengths
//! over speed, both models), sets each point's deformed amplitude `A_d/A_i`
//! against Venner's parameter `∇ = (λ/a) M^(3/4) / L^(1/2)` (reference/amplitude-reduction.json),
//! checks the collapse (the two wavelengths' curves at the same `∇`, and in a second form of the
//! parameter the points collapse in), charts it and writes `docs/measured/waviness-reduction.md`.

use crate::measured::{self, Table};
use anyhow::{Context, Result};
use ehl_workbench::plot::{self, Mark, Panel, Series};
use ehl_workbench::{compare, sweep};
use std::collections::BTreeMap;
use std::path::Path;

/// One model's answer at one point: speed [m/s], `λ/a`, `M`, `L`, `A_d/A_i`, on a grid of
/// `n` points a side, with the estimated error of the ratio where a grid twice coarser ran the
/// same point.
#[derive(Clone, Copy)]
struct Row {
    speed: f64,
    wave_a: f64,
    m: f64,
    l: f64,
    n: usize,
    ratio: Option<f64>,
    error: Option<f64>,
}

impl Row {
    /// The wavelength to three places: the same at every speed (one contact).
    fn wave_key(&self) -> i64 {
        (self.wave_a * 1e3).round() as i64
    }
}

/// The order the error estimate assumes: the steps and the faces are second order (the fed
/// wave's three-grid study observed 1.3 from a 65² film closed at the crests,
/// docs/measured/convergence-waviness-compare.md; the flooded wave's has no 65² answer with its
/// steps converged to 1e-6). An answer's own estimate with two
/// grids takes the change itself (`ehl_workbench::accuracy`: it knows no order for the scene);
/// the study knows the wave's.
const ORDER: f64 = 2.0;

/// The ratio of the curve `curve` (points `(∇, A_d/A_i, error)` of one wavelength, sorted by `∇`) at
/// `x`, linear in `log ∇` and `log A_d/A_i` between its points, with the larger error of the two
/// points it lies between; `None` outside it.
fn on_curve(curve: &[(f64, f64, f64)], x: f64) -> Option<(f64, f64)> {
    curve.windows(2).find(|w| w[0].0 <= x && x <= w[1].0).map(|w| {
        let t = (x.ln() - w[0].0.ln()) / (w[1].0.ln() - w[0].0.ln());
        ((w[0].1.ln() + t * (w[1].1.ln() - w[0].1.ln())).exp(), w[0].2.max(w[1].2))
    })
}

/// A form of the amplitude reduction's parameter, from a point's `λ/a`, `M` and `L`.
struct Form {
    /// Its symbol and formula, for the tables and the chart's axis.
    label: &'static str,
    of: fn(&Row) -> f64,
}

/// The published (line contact's) form, and the one the points collapse in.
const FORMS: [Form; 2] = [
    Form {
        label: "∇ = (λ/a) M^(3/4) / L^(1/2)", of: |r| r.wave_a * r.m.powf(0.75) / r.l.sqrt()
    },
    Form {
        label: "∇₂ = (λ/a) (M / L^(1/2))^(1/2)", of: |r| r.wave_a * (r.m / r.l.sqrt()).sqrt()
    },
];

/// Each model's finest-grid curves in `form` (one a wavelength, over the speeds) and the
/// collapse: each point of one wavelength against the other wavelength's curve where it reaches
/// the same value of the parameter (at another speed: other `M` and `L`), judged against the
/// two points' estimated errors.
fn collapse(rows: &BTreeMap<String, Vec<Row>>, finest: usize, form: &Form) -> (Table, Panel) {
    let mut table = Table::new(&[
        "model",
        "u [m/s]",
        "λ / a",
        "parameter",
        "A_d / A_i",
        "the other wavelength's curve there",
        "difference",
        "within the estimated errors",
    ]);
    let mut series = vec![];
    for (model, rs) in rows {
        let fine: Vec<&Row> = rs.iter().filter(|r| r.n == finest).collect();
        let mut waves: Vec<i64> = fine.iter().map(|r| r.wave_key()).collect();
        waves.sort();
        waves.dedup();
        let curve = |w: i64| {
            let mut c: Vec<(f64, f64, f64)> = fine
                .iter()
                .filter(|r| r.wave_key() == w)
                .filter_map(|r| r.ratio.map(|v| ((form.of)(r), v, r.error.unwrap_or(0.0))))
                .collect();
            c.sort_by(|x, y| x.0.total_cmp(&y.0));
            c
        };
        for &w in &waves {
            let label = format!("{model}, λ = {:.2} a", w as f64 / 1e3);
            let c = curve(w).iter().map(|p| (p.0, p.1)).collect();
            series.push(Series::new(label, c, Mark::LinePoints));
        }
        for &w in &waves {
            for &v in waves.iter().filter(|&&v| v != w) {
                let other = curve(v);
                for r in fine.iter().filter(|r| r.wave_key() == w) {
                    let x = (form.of)(r);
                    let (Some(here), Some((there, e_there))) = (r.ratio, on_curve(&other, x))
                    else {
                        continue;
                    };
                    let within = match r.error {
                        Some(e) => {
                            let yes = (here - there).abs() <= e + e_there;
                            format!("{} (±{:.4})", if yes { "yes" } else { "no" }, e + e_there)
                        }
                        None => "— (one grid)".into(),
                    };
                    table.rows.push(vec![
                        model.clone(),
                        format!("{}", r.speed),
                        format!("{:.3}", r.wave_a),
                        format!("{x:.2}"),
                        format!("{here:.4}"),
                        format!("{there:.4} (λ = {:.2} a)", v as f64 / 1e3),
                        format!("{:+.0} %", 100.0 * (here / there - 1.0)),
                        within,
                    ]);
                }
            }
        }
    }
    let panel = Panel::new(
        "A wave's deformed amplitude at the contact's centre",
        form.label,
        "A_d / A_i",
        series,
    )
    .log_log();
    (table, panel)
}

pub fn run(out: &Path) -> Result<()> {
    let (mut s, dir_of) = ehl_scene::load_sweep("waviness-reduction")?;
    if crate::quick() {
        // The code path on 65² alone (both waves, 6.4 and 12.8 cells each), two speeds whose
        // curves meet at one ∇.
        s.parameters[0].values = Some(vec![0.1, 0.3]);
    }
    let planned = sweep::Plan::new(&s, dir_of.as_deref())?;
    let n = planned.points.first().context("the sweep has points")?.scene.grid().nx;
    // The sweep's own grid and the one twice finer, each point's error estimated from the two.
    let grids = if crate::quick() { vec![65] } else { vec![n, 2 * n - 1] };
    let wave_axis = s
        .parameters
        .iter()
        .position(|p| p.parameter == ehl_scene::sweep::Parameter::Wavelength)
        .context("the sweep varies the wavelength")?;
    let (mut points, mut recs, mut wall_time_s) = (vec![], vec![], 0.0);
    for &n in &grids {
        let mut plan = planned.clone();
        plan.sweep.name = format!("{}-{n}", s.name);
        for p in &mut plan.points {
            p.scene = p.scene.with_points(n)?;
        }
        let (plan, ran, r) = crate::sweep_page::run_plan(plan, out)?;
        points.extend(plan.points);
        recs.extend(r);
        wall_time_s += ran.wall_time_s;
    }
    let mut rows: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    for (p, r) in points.iter().zip(&recs) {
        let sc = &p.scene;
        let u = sc.conditions.rolling_velocity_m_s.context("the sweep's scene rolls")?;
        let lub = sc.lubricant.context("the sweep's scene has a lubricant")?.lubricant();
        let contact = sc.conditions.contact();
        let moes = ehl_core::Moes::from_si(&contact, &lub, 2.0 * u);
        let a = ehl_core::HertzScales::new(&contact).a;
        let wave_a = r.values[wave_axis] / a;
        let n = sc.grid().nx;
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
            let row = Row { speed: u, wave_a, m: moes.m, l: moes.l, n, ratio, error: None };
            rows.entry(compare::model_name(m.model)).or_default().push(row);
        }
    }
    // Each point's error from its twin on the grid twice coarser (Richardson at ORDER).
    for rs in rows.values_mut() {
        let twins: Vec<(f64, i64, usize, Option<f64>)> =
            rs.iter().map(|r| (r.speed, r.wave_key(), r.n, r.ratio)).collect();
        for r in rs.iter_mut() {
            let coarse = twins
                .iter()
                .find(|t| t.0 == r.speed && t.1 == r.wave_key() && 2 * (t.2 - 1) == r.n - 1);
            if let (Some(&(_, _, _, Some(c))), Some(f)) = (coarse, r.ratio) {
                r.error = Some((f - c).abs() / (2f64.powf(ORDER) - 1.0));
            }
        }
    }
    let finest = rows.values().flatten().map(|r| r.n).max().unwrap_or(0);
    let mut t = Table::new(&[
        "model",
        "grid",
        "u [m/s]",
        "λ / a",
        "M",
        "L",
        "∇",
        "∇₂",
        "A_d / A_i",
        "± (est.)",
    ]);
    for (model, rs) in &rows {
        for r in rs {
            t.rows.push(vec![
                model.clone(),
                format!("{}²", r.n),
                format!("{}", r.speed),
                format!("{:.3}", r.wave_a),
                format!("{:.0}", r.m),
                format!("{:.2}", r.l),
                format!("{:.2}", (FORMS[0].of)(r)),
                format!("{:.2}", (FORMS[1].of)(r)),
                r.ratio.map_or("—".into(), |v| format!("{v:.4}")),
                r.error.map_or("—".into(), |e| format!("{e:.4}")),
            ]);
        }
    }
    let (collapses, panels): (Vec<Table>, Vec<Panel>) =
        FORMS.iter().map(|f| collapse(&rows, finest, f)).unzip();
    std::fs::create_dir_all(out)?;
    let png = out.join("waviness-reduction.png");
    plot::charts(
        &png,
        &panels,
        "the sweep waviness-reduction: the seed's contact flooded (Reynolds) or fed 25 nm (layer)",
    )?;
    println!("wrote {}", png.display());
    measured::write(
        "waviness-reduction",
        "The amplitude reduction of a wave through the contact",
        "cargo xtask waves",
        &format!(
            "`ehl sweep waviness-reduction`: {}\n\n{} points on {} in {:.0} s on {} cores. \
             `A_d/A_i`: the amplitude of the film's oscillation at the contact's centre over \
             the last passage (a passage that repeats, or the time limit), per the surfaces' \
             amplitude; `∇` with the point's Moes `M` and `L` and the Hertz radius `a`; `±` the \
             estimated error of a point from its twin on the grid twice coarser (Richardson at \
             order {ORDER}). The curves and the collapse are the finest grid's ({finest}²): \
             each point against the other wavelength's curve at the same `∇` (interpolated in \
             `log ∇`, `log A_d/A_i`), reached there at other `M` and `L`; the principle says the \
             difference is nil, and the last column says whether it is within the two points' \
             estimated errors. Twice: in the published (line contact's) `∇`, and in \
             `∇₂ = (λ/a) (M / L^(1/2))^(1/2)`, a form with a weaker dependence on `M` that the \
             points themselves collapse in (not a published form in the stored sources). The \
             chart: `waviness-reduction.png` in the study's folder (`--out`), one panel a form.",
            s.description,
            points.len(),
            grids.iter().map(|n| format!("{n}²")).collect::<Vec<_>>().join(" and "),
            wall_time_s,
            sweep::default_jobs(),
        ),
        &[
            ("Every point", &t),
            ("The collapse in ∇ (the line contact's published form)", &collapses[0]),
            ("The collapse in ∇₂ (the form these points collapse in)", &collapses[1]),
        ],
    )?;
    Ok(())
}
