//! Reynolds studies: the stability map over Moes' (M, L) and the central film against the
//! published formulas (`reference/reynolds_cases.json`).

use anyhow::Result;
use ehl_cli::plot::{self, Mark, Panel, Series};
use ehl_core::{Contact, Grid, Lubricant, Moes};
use ehl_reynolds::formulas::{hamrock_dowson_central, nvm_central};
use ehl_reynolds::{DensityLaw, ReynoldsParams, ReynoldsSettings, ReynoldsSolver, ViscosityLaw};
use plotters::prelude::SeriesLabelPosition;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

pub fn stability(out: &Path, n: usize) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    let cases: Value = serde_json::from_str(include_str!("../../reference/reynolds_cases.json"))?;
    let ms: Vec<f64> = cases["m"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let ls: Vec<f64> = cases["l"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let (r, e, eta0, alpha, p0) = (9.525e-3, 1.17e11, 40e-3, 2.2e-8, 1.96e8);
    let grid = Grid::new(n, n, (-4.5, 1.5), (-3.0, 3.0));
    println!(
        "Reynolds stability map on {n}^2 over [-4.5, 1.5] x [-3, 3] (Roelands, Dowson-Higginson; R, E', eta0, alpha fixed)"
    );
    println!(
        "{:>7} {:>5} {:>10} {:>7} {:>12} {:>12} {:>12} {:>9} {:>9}",
        "M", "L", "converged", "cycles", "h_c [m]", "HD [m]", "NVM [m]", "vs HD", "vs NVM"
    );
    let mut rows = vec![];
    for &l in &ls {
        for &m in &ms {
            let moes = Moes { m, l };
            let (load, u_sum) = moes.to_load_and_velocity(r, e, eta0, alpha);
            let c = Contact { ball_radius: r, load, reduced_modulus: e };
            let lub = Lubricant { eta0, alpha, p0_roelands: p0 };
            let prm = ReynoldsParams::from_si(
                &c,
                &lub,
                u_sum,
                ViscosityLaw::Roelands,
                DensityLaw::DowsonHigginson,
            );
            let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
            let (converged, cycles, diagnosis) = match s.solve(&mut |_| {}) {
                Ok(rep) => (rep.converged, rep.cycles, rep.diagnosis),
                Err(e) => (false, 0, Some(e.to_string())),
            };
            let (hc, hmin) = s.films();
            let ok = converged && hmin > 0.0;
            let hc_m = prm.scales.h_si(hc);
            let (hd, nvm) =
                (hamrock_dowson_central(&c, &lub, 0.5 * u_sum), nvm_central(&c, &lub, u_sum));
            if ok {
                println!(
                    "{m:>7} {l:>5} {:>10} {:>7} {:>12.4e} {:>12.4e} {:>12.4e} {:>+8.1}% {:>+8.1}%",
                    ok,
                    cycles,
                    hc_m,
                    hd,
                    nvm,
                    (hc_m / hd - 1.0) * 100.0,
                    (hc_m / nvm - 1.0) * 100.0
                );
            } else {
                let why: String = diagnosis.clone().unwrap_or_default().chars().take(90).collect();
                println!(
                    "{m:>7} {l:>5} {:>10} {:>7} {:>12} {:>12.4e} {:>12.4e}  {why}",
                    ok, cycles, "-", hd, nvm
                );
            }
            rows.push(json!({
                "m": m, "l": l, "converged": ok, "cycles": cycles, "diagnosis": diagnosis,
                "central_film_m": if ok { Some(hc_m) } else { None }, "hamrock_dowson_m": hd, "nvm_m": nvm,
            }));
        }
    }
    let pick = |ok: bool| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r["converged"].as_bool() == Some(ok))
            .map(|r| (r["m"].as_f64().unwrap(), r["l"].as_f64().unwrap()))
            .collect()
    };
    let map = out.join("reynolds_stability.png");
    plot::charts(
        &map,
        &[Panel::new(
            &format!("Reynolds FAS solver on {n}^2: converged or not"),
            "M (load)",
            "L (lubricant)",
            vec![
                Series::new("converged", pick(true), Mark::Points),
                Series::new("not converged (see JSON for why)", pick(false), Mark::Points),
            ],
        )
        .log_log()
        .legend(SeriesLabelPosition::UpperLeft)],
        "up to 200 W-cycles; converged: central film settled to 1e-4 per cycle, force balance to 1e-6, film > 0",
    )?;
    let dev = |key: &str, l: f64| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r["converged"].as_bool() == Some(true) && r["l"].as_f64() == Some(l))
            .map(|r| {
                (
                    r["m"].as_f64().unwrap(),
                    (r["central_film_m"].as_f64().unwrap() / r[key].as_f64().unwrap() - 1.0)
                        * 100.0,
                )
            })
            .collect()
    };
    let chart = out.join("reynolds_formulas.png");
    let mk = |key: &str, name: &str| {
        Panel::new(
            &format!("Central film against {name}"),
            "M",
            "deviation [%]",
            ls.iter()
                .map(|&l| Series::new(format!("L = {l}"), dev(key, l), Mark::LinePoints))
                .collect(),
        )
    };
    let mut p1 = mk("hamrock_dowson_m", "Hamrock-Dowson (1977)");
    p1.log_x = true;
    let mut p2 = mk("nvm_m", "Nijenbanning-Venner-Moes (1994)");
    p2.log_x = true;
    plot::charts(
        &chart,
        &[p1, p2],
        &format!(
            "converged cases only, {n}^2 over [-4.5, 1.5] x [-3, 3]; the formulas are fits good to several percent"
        ),
    )?;
    let json_path = out.join("reynolds_stability.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&json!({"grid": n, "cases": rows}))? + "\n",
    )?;
    Ok(vec![map, chart, json_path])
}
