//! Reynolds studies: the stability map over Moes' (M, L) and the central film against the
//! published formulas (`reference/reynolds_cases.json`).

use anyhow::Result;
use ehl_reynolds::params::{DensityLaw, ViscosityLaw};
use ehl_workbench::plot::{self, Mark, Panel, Series};
use ehl_workbench::sweep;
use plotters::prelude::SeriesLabelPosition;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// `cargo xtask stability reynolds`: converged or not, and cycles, over (M, L); at
/// `M ≥ narrow_from_m` on the layer model's domain `[-1.25, 1.25]²`, where the film is so thin
/// that the inlet zone is a few hundredths of `a` wide and the wide domain's cells cannot hold it.
/// Moes' `M` and `L` of `reference/reynolds_cases.json`.
fn cases() -> Result<(Vec<f64>, Vec<f64>)> {
    let cases: Value = serde_json::from_str(include_str!("../../reference/reynolds_cases.json"))?;
    let list = |k: &str| -> Vec<f64> {
        cases[k].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect()
    };
    let (m, l) = (list("m"), list("l"));
    // Quickly: the lightest and heaviest loads at the lowest and highest L.
    let ends = |v: Vec<f64>| if crate::quick() { vec![v[0], v[v.len() - 1]] } else { v };
    Ok((ends(m), ends(l)))
}

/// The stability map's sweep (every case of `reference/reynolds_cases.json` on `n`²) with the
/// scene's laws or `laws`, run and merged in `out/folder`; one row per case.
fn map_sweep(
    out: &Path,
    folder: &str,
    n: usize,
    narrow_from_m: f64,
    laws: Option<(ViscosityLaw, DensityLaw)>,
) -> Result<Vec<Value>> {
    let (ms, ls) = cases()?;
    // The map is a sweep of `reynolds-m20-l10` (R, E', η0, α of the classic case) over Moes' L
    // (slowest) and M, each point on its fixed domain (no adaptation, no checks: the map shows
    // where the solver itself fails), run in parallel, one thread per point.
    let sweep: ehl_scene::Sweep = serde_json::from_value(json!({
        "name": "reynolds-stability",
        "scene": "reynolds-m20-l10",
        "parameters": [{"parameter": "moes.l", "values": ls}, {"parameter": "moes.m", "values": ms}],
        "adapt": false,
        "checks": false,
    }))?;
    sweep.validate("stability map")?;
    let mut plan = sweep::Plan::new(&sweep, None)?;
    let wide = ehl_scene::Domain { x_a: [-4.5, 1.5], y_a: [-3.0, 3.0] };
    let narrow = ehl_scene::Domain { x_a: [-1.25, 1.25], y_a: [-1.25, 1.25] };
    for p in &mut plan.points {
        p.scene.domain = if p.values[1] >= narrow_from_m { narrow } else { wide };
        p.scene.grid = ehl_scene::GridSpec { nx: n, ny: n };
        p.scene.outputs.figures = false;
        if let Some((v, d)) = laws {
            let r = p.scene.reynolds.as_mut().expect("a Reynolds scene");
            r.viscosity = v;
            r.density = d;
        }
        p.scene.validate("stability map point")?;
    }
    let dir = out.join(folder);
    if dir.exists() {
        std::fs::remove_dir_all(&dir)?; // the map's cycles and times are measured afresh
    }
    plan.write(&dir)?;
    sweep::run(&dir, sweep::Shard::all(), sweep::default_jobs())?;
    sweep::merge::merge(&dir)?;
    let mut rows = vec![];
    for rec in sweep::records(&dir, &plan)? {
        let (l, m) = (rec.values[0], rec.values[1]);
        let point = &plan.points[rec.index];
        let mr = &rec.models[0];
        let [hd, _, nvm] = sweep::merge::formulas_at(point).expect("a rolling Reynolds scene");
        let ok = mr.observables.is_some_and(|o| o.minimum_film_m > 0.0);
        let cycles = mr.indicators.get("cycles").map(|c| c.value as u64).unwrap_or(0);
        let lagged = mr.indicators.get("lagged_laws").is_some_and(|t| t.value > 0.0);
        let hc_m = mr.observables.map(|o| o.central_film_m);
        match (ok, hc_m) {
            (true, Some(hc_m)) => println!(
                "{m:>7} {l:>5} {:>10} {:>7} {:>12.4e} {:>12.4e} {:>12.4e} {:>+8.1}% {:>+8.1}%",
                ok,
                cycles,
                hc_m,
                hd,
                nvm,
                (hc_m / hd - 1.0) * 100.0,
                (hc_m / nvm - 1.0) * 100.0
            ),
            _ => {
                let why: String =
                    mr.diagnosis.clone().unwrap_or_default().chars().take(90).collect();
                println!(
                    "{m:>7} {l:>5} {:>10} {:>7} {:>12} {:>12.4e} {:>12.4e}  {why}",
                    ok, cycles, "-", hd, nvm
                )
            }
        }
        let rule = if ok { Value::Null } else { on_the_rules_grid(&point.scene) };
        rows.push(json!({
            "m": m, "l": l, "converged": ok, "cycles": cycles, "lagged_laws": lagged,
            "diagnosis": mr.diagnosis,
            "domain_a": [rec.x_a, rec.y_a],
            "central_film_m": if ok { hc_m } else { None }, "hamrock_dowson_m": hd, "nvm_m": nvm,
            "wall_time_s": mr.wall_time_s,
            "on_the_rules_grid": rule,
        }));
    }
    Ok(rows)
}

/// A map point that failed, run again on the grid the sweeps' existence rule gives it (its
/// cells at most `CELLS_PER_FILM · H_c^{2/3}` a, its domain kept unless its inlet is short):
/// whether the failure was the grid's. `null` when the rule asks for no finer grid than the map's.
fn on_the_rules_grid(scene: &ehl_scene::Scene) -> Value {
    let (fine, what) = ehl_workbench::accuracy::rule::adapt(scene, true, f64::INFINITY);
    let Some(what) = what else { return Value::Null };
    let t = std::time::Instant::now();
    let run = ehl_workbench::run_scene(&fine);
    let wall = t.elapsed().as_secs_f64();
    let g = fine.grid();
    let (ok, hc, hmin, why) = match &run {
        Ok(o) => {
            let ob = o.observables();
            let ok = ob.minimum_film_m > 0.0 && o.caveat().is_none();
            (ok, Some(ob.central_film_m), Some(ob.minimum_film_m), o.caveat())
        }
        Err(e) => (false, None, None, Some(e.to_string())),
    };
    println!(
        "          on the rule's grid ({what}): {} in {wall:.1} s{}",
        if ok { "converged" } else { "FAILED" },
        match (hc, hmin, &why) {
            (Some(hc), Some(hm), None) => format!(", h_c {:.4e} m, h_min {:.4e} m", hc, hm),
            (_, _, Some(w)) => format!(": {}", w.chars().take(120).collect::<String>()),
            _ => String::new(),
        }
    );
    json!({
        "grid": g.nx, "domain_a": [[g.x_min, g.x_max], [g.y_min, g.y_max]], "converged": ok,
        "central_film_m": hc, "minimum_film_m": hmin, "diagnosis": why, "wall_time_s": wall,
    })
}

pub fn stability(out: &Path, n: usize, narrow_from_m: f64) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    let (_, ls) = cases()?;
    println!("Roelands viscosity, Dowson-Higginson density (the map):");
    let rows = map_sweep(out, "reynolds-stability-sweep", n, narrow_from_m, None)?;
    // Like for like: Hamrock-Dowson and NVM were fitted to Barus, incompressible solutions.
    println!("Barus viscosity, incompressible (the formulas' own laws):");
    let rows_barus = map_sweep(
        out,
        "reynolds-barus-sweep",
        n,
        narrow_from_m,
        Some((ViscosityLaw::Barus, DensityLaw::Incompressible)),
    )?;
    // Converged points by cycles, those the second attempt (lagged laws) converged apart.
    let pick_lagged = |lagged: bool, ok: bool, cycles: (u64, u64)| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r["converged"].as_bool() == Some(ok))
            .filter(|r| !ok || r["lagged_laws"].as_bool() == Some(lagged))
            .filter(|r| (cycles.0..=cycles.1).contains(&r["cycles"].as_u64().unwrap()))
            .map(|r| (r["m"].as_f64().unwrap(), r["l"].as_f64().unwrap()))
            .collect()
    };
    let pick = |ok: bool, cycles: (u64, u64)| pick_lagged(false, ok, cycles);
    let map = out.join("reynolds_stability.png");
    plot::charts(
        &map,
        &[Panel::new(
            &format!("Reynolds FAS solver on {n}^2: converged or not"),
            "M (load)",
            "L (lubricant)",
            vec![
                Series::new("converged in <= 15 cycles", pick(true, (0, 15)), Mark::Points),
                Series::new("converged in 16-30 cycles", pick(true, (16, 30)), Mark::Points),
                Series::new("converged in > 30 cycles", pick(true, (31, u64::MAX)), Mark::Points),
                Series::new(
                    "converged with lagged laws (second attempt)",
                    pick_lagged(true, true, (0, u64::MAX)),
                    Mark::Points,
                ),
                Series::new(
                    "not converged (see JSON for why)",
                    pick(false, (0, u64::MAX)),
                    Mark::Points,
                ),
            ],
        )
        .log_log()
        // Room above L = 20 for the legend.
        .y_range(0.7, 150.0)
        .legend(SeriesLabelPosition::UpperLeft)],
        &format!(
            "converged: h_c settled to 1e-4/cycle, load to 1e-6; [-1.25, 1.25]^2 from M = {narrow_from_m}"
        ),
    )?;
    let dev = |rows: &[Value], key: &str, l: f64| -> Vec<(f64, f64)> {
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
    let mk = |rows: &[Value], key: &str, name: &str| {
        let mut p = Panel::new(
            name,
            "M",
            "deviation [%]",
            ls.iter()
                .map(|&l| Series::new(format!("L = {l}"), dev(rows, key, l), Mark::LinePoints))
                .collect(),
        );
        p.log_x = true;
        p
    };
    plot::charts(
        &chart,
        &[
            mk(&rows_barus, "hamrock_dowson_m", "Barus, incompressible vs Hamrock-Dowson (1977)"),
            mk(&rows_barus, "nvm_m", "Barus, incompressible vs NVM (1994)"),
            mk(&rows, "hamrock_dowson_m", "Roelands, D-H vs Hamrock-Dowson"),
            mk(&rows, "nvm_m", "Roelands, D-H vs NVM"),
        ],
        &format!(
            "central film, converged cases only, {n}^2 over [-4.5, 1.5] x [-3, 3] ([-1.25, 1.25]^2 from M = {narrow_from_m}); left: the laws the formulas were fitted to (like for like), right: the map's Roelands + Dowson-Higginson"
        ),
    )?;
    let json_path = out.join("reynolds_stability.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(
            &json!({"grid": n, "cases": rows, "barus_incompressible": rows_barus}),
        )? + "\n",
    )?;
    let page = stability_page(n, narrow_from_m, &rows, &rows_barus)?;
    Ok(vec![map, chart, json_path, page])
}

/// The stability map's rows as a measured page (`docs/measured/reynolds-stability.md`).
fn stability_page(
    n: usize,
    narrow_from_m: f64,
    rows: &[Value],
    barus: &[Value],
) -> Result<PathBuf> {
    let table = |rows: &[Value]| {
        let mut t = crate::measured::Table::new(&[
            "M",
            "L",
            "answer",
            "cycles",
            "h_c [nm]",
            "vs Hamrock-Dowson",
            "vs NVM",
            "wall [s]",
            "on the rule's grid",
        ]);
        for r in rows {
            let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
            let ok = r["converged"].as_bool() == Some(true);
            let hc = f("central_film_m");
            let rule = &r["on_the_rules_grid"];
            let on_rule = if rule.is_null() {
                "-".to_string()
            } else if rule["converged"].as_bool() == Some(true) {
                format!(
                    "{}²: h_c {:.4} nm, {:.1} s",
                    rule["grid"],
                    rule["central_film_m"].as_f64().unwrap_or(f64::NAN) * 1e9,
                    rule["wall_time_s"].as_f64().unwrap_or(f64::NAN)
                )
            } else {
                format!("{}²: failed", rule["grid"])
            };
            let answer = match (ok, r["lagged_laws"].as_bool() == Some(true)) {
                (true, false) => "converged".to_string(),
                (true, true) => "converged, lagged laws".to_string(),
                _ => {
                    let d = r["diagnosis"].as_str().unwrap_or("failed");
                    format!("failed: {}", d.chars().take(60).collect::<String>())
                }
            };
            let pct = |k: &str| {
                if ok { format!("{:+.1} %", (hc / f(k) - 1.0) * 100.0) } else { "-".into() }
            };
            t.rows.push(vec![
                format!("{}", f("m")),
                format!("{}", f("l")),
                answer,
                format!("{}", r["cycles"]),
                if ok { format!("{:.4}", hc * 1e9) } else { "-".into() },
                pct("hamrock_dowson_m"),
                pct("nvm_m"),
                format!("{:.2}", f("wall_time_s")),
                on_rule,
            ]);
        }
        t
    };
    let count = |rows: &[Value]| {
        let ok = rows.iter().filter(|r| r["converged"].as_bool() == Some(true)).count();
        format!("{ok} of {}", rows.len())
    };
    let intro = format!(
        "The Reynolds solver over Moes' `M` and `L` (`reference/reynolds_cases.json`: `R`, `E'`, \
         `η0`, `α` of `reynolds-m20-l10`, load and velocity from `M`, `L`), each case from Hertz on \
         {n}² over `[-4.5, 1.5] × [-3, 3]`, from `M = {narrow_from_m}` on `[-1.25, 1.25]²`, one \
         thread a case. A case that fails is run again on the grid the sweeps' rule gives it. \
         The central film is set against Hamrock–Dowson (1977) and NVM (1994), which were fitted \
         to Barus, incompressible solutions. Converged: Roelands and Dowson–Higginson {}, Barus \
         and incompressible {}.",
        count(rows),
        count(barus)
    );
    crate::measured::write(
        "reynolds-stability",
        "The Reynolds stability map and the film formulas",
        &format!("cargo xtask stability reynolds --points {n}"),
        &intro,
        &[
            ("Roelands viscosity, Dowson–Higginson density (the map)", &table(rows)),
            ("Barus viscosity, incompressible (the formulas' own laws)", &table(barus)),
        ],
    )
}

/// One Reynolds solve of the grid study.
#[derive(Clone, Debug, serde::Serialize)]
struct Solve {
    scene: String,
    n: usize,
    converged: bool,
    cycles: usize,
    wall_s: f64,
    central_nm: f64,
    minimum_nm: f64,
    max_pressure_ph: f64,
    /// Finest-grid cycles: (wall time [s], central [nm], minimum [nm]).
    per_cycle: Vec<(f64, f64, f64)>,
}

fn solve_scene(name: &str, n: usize) -> Result<Solve> {
    solve_scene_with(name, n, ehl_reynolds::StopRule::Strict)
}

fn solve_scene_with(name: &str, n: usize, stop: ehl_reynolds::StopRule) -> Result<Solve> {
    let (r, diagnosis) = solve_scene_report(name, n, stop)?;
    print_solve(&r, diagnosis);
    Ok(r)
}

/// [`solve_scene`] without the line it prints.
fn solve_scene_quiet(name: &str, n: usize) -> Result<Solve> {
    Ok(solve_scene_report(name, n, ehl_reynolds::StopRule::Strict)?.0)
}

fn solve_scene_report(
    name: &str,
    n: usize,
    stop: ehl_reynolds::StopRule,
) -> Result<(Solve, Option<ehl_reynolds::Diagnosis>)> {
    let mut scene = ehl_scene::builtin(name)?.with_points(n)?;
    scene.reynolds.as_mut().expect("a Reynolds scene").solver.stop = stop;
    let (prm, mut s) = ehl_workbench::reynolds::build_solver(&scene)?;
    let nm = prm.scales.delta * 1e9;
    // A solve that ran to its end unconverged is still a row of the table (marked NOT).
    let rep = match s.solve(&mut |_| {}) {
        Err(ehl_reynolds::ReynoldsError::NotConverged(rep)) => *rep,
        other => other?,
    };
    let (hc, hmin) = s.films();
    let pmax = s.pressure().iter().cloned().fold(0.0, f64::max);
    let per_cycle = rep
        .history
        .iter()
        .filter(|c| c.points == n)
        .map(|c| (c.wall_s, c.central_film * nm, c.minimum_film * nm))
        .collect();
    let r = Solve {
        scene: name.into(),
        n,
        converged: rep.converged && hmin > 0.0,
        cycles: rep.cycles,
        wall_s: rep.wall_time_s,
        central_nm: hc * nm,
        minimum_nm: hmin * nm,
        max_pressure_ph: pmax,
        per_cycle,
    };
    Ok((r, rep.diagnosis))
}

fn print_solve(r: &Solve, diagnosis: Option<ehl_reynolds::Diagnosis>) {
    println!(
        "  {:<18} {:>5} {:>6} {:>4} cycles {:>8.3} s  h_c {:>10.4} nm  h_min {:>10.4} nm  p_max {:.4} p_h{}",
        r.scene,
        r.n,
        if r.converged { "" } else { "NOT" },
        r.cycles,
        r.wall_s,
        r.central_nm,
        r.minimum_nm,
        r.max_pressure_ph,
        diagnosis.map(|d| format!("  ({d})")).unwrap_or_default()
    );
}

/// `cargo xtask convergence reynolds`: grid studies of the two built-in Reynolds scenes with
/// observed orders, speed against accuracy (grids and cycles), and, when the layer study's
/// JSON sits in `out`, both models' cost against accuracy on one chart.
pub fn convergence(out: &Path, max_points: usize) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    let mut all: Vec<Vec<Solve>> = vec![];
    let mut orders = vec![];
    for name in ["reynolds-m20-l10", "reynolds-seed"] {
        println!("Grid study, scene {name} (each solve from Hertz, full-multigrid start):");
        let pts: Vec<Solve> = crate::grid_sizes(max_points)
            .into_iter()
            .map(|n| solve_scene(name, n))
            .collect::<Result<_>>()?;
        let ok: Vec<&Solve> = pts.iter().filter(|p| p.converged).collect();
        for w in ok.windows(3) {
            let o = |f: fn(&Solve) -> f64| {
                ehl_core::hertz::observed_order_of_three(f(w[0]), f(w[1]), f(w[2]), 2.0)
            };
            let (oc, om) = (o(|p| p.central_nm), o(|p| p.minimum_nm));
            // Richardson with the observed order of the central film.
            let extra =
                w[2].central_nm + (w[2].central_nm - w[1].central_nm) / (2f64.powf(oc) - 1.0);
            println!(
                "  observed order {} -> {} -> {}: central {oc:.2}, minimum {om:.2}; extrapolated h_c {extra:.4} nm",
                w[0].n, w[1].n, w[2].n
            );
            orders.push(json!({"scene": name, "grids": [w[0].n, w[1].n, w[2].n],
                "central": oc, "minimum": om, "extrapolated_central_nm": extra}));
        }
        all.push(pts);
    }
    // Speed against accuracy, against the Richardson-extrapolated films (the grid limit), not
    // the finest grid: measured against the finest grid, a coarse grid's early cycles can sit
    // closer than its converged answer (algebraic and discretisation errors of opposite sign
    // cancel), so the curve rose as the solve converged. Grids: the total error of each
    // converged solve (its discretisation error). Cycles on the grid below the finest: the
    // algebraic error (against that grid's converged film) apart from the total.
    let mut series_c = vec![];
    let mut series_m = vec![];
    let mut references = vec![];
    let mut stop_rules = vec![];
    for pts in &all {
        let ok: Vec<&Solve> = pts.iter().filter(|p| p.converged).collect();
        if ok.len() < 2 {
            println!("  {}: fewer than two converged grids, no chart", pts[0].scene);
            continue;
        }
        let name = ok[0].scene.trim_start_matches("reynolds-").to_string();
        // Richardson from the finest two with the observed order of the finest three when it
        // is credible (1 … 3), else the scheme's 2.
        let extrapolate = |f: fn(&Solve) -> f64| -> (f64, f64) {
            let k = ok.len();
            let order = if k >= 3 {
                ehl_core::hertz::observed_order_of_three(
                    f(ok[k - 3]),
                    f(ok[k - 2]),
                    f(ok[k - 1]),
                    2.0,
                )
            } else {
                2.0
            };
            let order = if (1.0..=3.0).contains(&order) { order } else { 2.0 };
            (f(ok[k - 1]) + (f(ok[k - 1]) - f(ok[k - 2])) / (2f64.powf(order) - 1.0), order)
        };
        let (ref_c, order_c) = extrapolate(|p| p.central_nm);
        let (ref_m, order_m) = extrapolate(|p| p.minimum_nm);
        println!(
            "  {name}: Richardson h_c {ref_c:.4} nm (order {order_c:.2}), h_min {ref_m:.4} nm (order {order_m:.2})"
        );
        references
            .push(json!({"scene": ok[0].scene, "central_nm": ref_c, "central_order": order_c,
            "minimum_nm": ref_m, "minimum_order": order_m}));
        let grids = |pick: fn(&Solve) -> f64, r: f64| -> Vec<(f64, f64)> {
            ok.iter().map(|p| (p.wall_s, (pick(p) - r).abs())).collect()
        };
        // A curve on both charts: central film against its reference, minimum against its own.
        type Points<'a> = &'a dyn Fn(fn(&Solve) -> f64, f64) -> Vec<(f64, f64)>;
        let mut both = |label: String, pts: Points| {
            series_c.push(Series::new(
                label.clone(),
                pts(|p| p.central_nm, ref_c),
                Mark::LinePoints,
            ));
            series_m.push(Series::new(label, pts(|p| p.minimum_nm, ref_m), Mark::LinePoints));
        };
        both(format!("{name}: grids (discretisation)"), &grids);
        // The same grids under the discretisation-error stop rule.
        let loose: Vec<Solve> = ok
            .iter()
            .map(|p| solve_scene_with(&p.scene, p.n, ehl_reynolds::StopRule::Discretisation))
            .collect::<Result<_>>()?;
        for (p, q) in ok.iter().zip(&loose) {
            println!(
                "  {name} {}^2: discretisation stop {} cycles {:.3} s (strict {} cycles {:.3} s), h_c {:.4} nm against {:.4}",
                p.n, q.cycles, q.wall_s, p.cycles, p.wall_s, q.central_nm, p.central_nm
            );
        }
        let pick_loose = |f: fn(&Solve) -> f64, r: f64| -> Vec<(f64, f64)> {
            loose.iter().filter(|q| q.converged).map(|q| (q.wall_s, (f(q) - r).abs())).collect()
        };
        both(format!("{name}: grids, discretisation-error stop"), &pick_loose);
        stop_rules.push(json!({"scene": ok[0].scene, "strict": ok.iter().map(|p| json!({"n": p.n, "cycles": p.cycles, "wall_s": p.wall_s, "central_nm": p.central_nm, "minimum_nm": p.minimum_nm})).collect::<Vec<_>>(),
            "discretisation": loose.iter().map(|p| json!({"n": p.n, "converged": p.converged, "cycles": p.cycles, "wall_s": p.wall_s, "central_nm": p.central_nm, "minimum_nm": p.minimum_nm})).collect::<Vec<_>>()}));
        let below = ok[ok.len() - 2];
        let cyc = |k: usize, reference: f64| -> Vec<(f64, f64)> {
            below
                .per_cycle
                .iter()
                .map(|c| (c.0, ([c.1, c.2][k] - reference).abs()))
                .filter(|v| v.1 > 0.0)
                .collect()
        };
        let (conv_c, conv_m) = (below.central_nm, below.minimum_nm);
        for (k, series, r, conv) in
            [(0, &mut series_c, ref_c, conv_c), (1, &mut series_m, ref_m, conv_m)]
        {
            for (what, against) in [("total", r), ("algebraic", conv)] {
                series.push(Series::new(
                    format!("{name}: cycles on {}^2, {what}", below.n),
                    cyc(k, against),
                    Mark::LinePoints,
                ));
            }
        }
    }
    let png = out.join("reynolds_speed_accuracy.png");
    let panel = |title: &str, s: Vec<Series>| {
        Panel::new(title, "wall time [s]", "|error| [nm] vs Richardson", s)
            .log_log()
            .legend(SeriesLabelPosition::UpperRight)
    };
    plot::charts(
        &png,
        &[panel("Central film", series_c.clone()), panel("Minimum film", series_m.clone())],
        "Reynolds, errors against the Richardson-extrapolated film of each scene; cycles: after each W-cycle on the grid below the finest, total (vs Richardson) and algebraic (vs that grid's converged film)",
    )?;
    let mut written = vec![png];
    // Both models on one chart, seed conditions, when the layer study has been run.
    let layer_json = out.join("layer_convergence.json");
    if let Ok(text) = std::fs::read_to_string(&layer_json) {
        let v: Value = serde_json::from_str(&text)?;
        let layer_pts: Vec<&Value> = v["grid_study"]
            .as_array()
            .map(|a| a.iter().filter(|p| p["scheme"] == "implicit").collect())
            .unwrap_or_default();
        if let Some(fin) = layer_pts.last() {
            let curve = |key: &str| -> Vec<(f64, f64)> {
                layer_pts[..layer_pts.len() - 1]
                    .iter()
                    .map(|p| {
                        let e = (p[key].as_f64().unwrap() - fin[key].as_f64().unwrap()).abs();
                        (p["wall_s"].as_f64().unwrap(), e)
                    })
                    .collect()
            };
            let seed: Vec<&Series> =
                series_c.iter().filter(|s| s.label.starts_with("seed")).collect();
            let seed_m: Vec<&Series> =
                series_m.iter().filter(|s| s.label.starts_with("seed")).collect();
            let mk = |title: &str, key: &str, rey: Vec<&Series>| {
                let mut s = vec![Series::new(
                    "layer model (implicit, n_t = 10): grids",
                    curve(key),
                    Mark::LinePoints,
                )];
                s.extend(rey.into_iter().map(|r| {
                    let mut r = r.clone();
                    r.label = format!("Reynolds {}", r.label);
                    r
                }));
                panel(title, s)
            };
            let both = out.join("speed_accuracy_layer_vs_reynolds.png");
            plot::charts(
                &both,
                &[
                    mk("Central thickness / film", "central_nm", seed),
                    mk("Minimum thickness / film", "minimum_nm", seed_m),
                ],
                "seed Table 1 conditions; layer: steady rolling to steady state (xtask convergence layer); Reynolds: steady solve; each against its own finest grid",
            )?;
            written.push(both);
        }
    } else {
        println!(
            "(no {} yet: run `cargo xtask convergence layer` for the side-by-side chart)",
            layer_json.display()
        );
    }
    let json_path = out.join("reynolds_convergence.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(
            &json!({"grid_studies": all, "observed_orders": orders, "richardson": references}),
        )? + "\n",
    )?;
    written.push(json_path);
    written.push(convergence_page(max_points, &all, &orders, &references, &stop_rules)?);
    for f in &written {
        println!("  wrote {}", f.display());
    }
    Ok(written)
}

/// The grid studies as a measured page (`docs/measured/reynolds-convergence.md`).
fn convergence_page(
    max_points: usize,
    all: &[Vec<Solve>],
    orders: &[Value],
    references: &[Value],
    stop_rules: &[Value],
) -> Result<PathBuf> {
    use crate::measured::Table;
    let mut grids = Table::new(&[
        "scene",
        "grid",
        "answer",
        "cycles",
        "wall [s]",
        "h_c [nm]",
        "h_min [nm]",
        "p_max / p_h",
    ]);
    for p in all.iter().flatten() {
        grids.rows.push(vec![
            p.scene.clone(),
            format!("{}²", p.n),
            if p.converged { "converged".into() } else { "not converged".into() },
            p.cycles.to_string(),
            format!("{:.3}", p.wall_s),
            format!("{:.4}", p.central_nm),
            format!("{:.4}", p.minimum_nm),
            format!("{:.4}", p.max_pressure_ph),
        ]);
    }
    let mut ord = Table::new(&["scene", "grids", "order of h_c", "order of h_min"]);
    for o in orders {
        ord.rows.push(vec![
            o["scene"].as_str().unwrap_or_default().to_string(),
            o["grids"].as_array().map_or(String::new(), |g| {
                g.iter().map(|n| format!("{n}²")).collect::<Vec<_>>().join(", ")
            }),
            format!("{:.2}", o["central"].as_f64().unwrap_or(f64::NAN)),
            format!("{:.2}", o["minimum"].as_f64().unwrap_or(f64::NAN)),
        ]);
    }
    let mut rich = Table::new(&["scene", "h_c [nm]", "its order", "h_min [nm]", "its order"]);
    for r in references {
        let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
        rich.rows.push(vec![
            r["scene"].as_str().unwrap_or_default().to_string(),
            format!("{:.4}", f("central_nm")),
            format!("{:.2}", f("central_order")),
            format!("{:.4}", f("minimum_nm")),
            format!("{:.2}", f("minimum_order")),
        ]);
    }
    let mut stops = Table::new(&[
        "scene",
        "grid",
        "strict: cycles, wall [s], h_c [nm]",
        "discretisation stop: cycles, wall [s], h_c [nm]",
    ]);
    for s in stop_rules {
        let scene = s["scene"].as_str().unwrap_or_default();
        let (Some(a), Some(b)) = (s["strict"].as_array(), s["discretisation"].as_array()) else {
            continue;
        };
        for (p, q) in a.iter().zip(b) {
            let cell = |v: &Value| {
                format!(
                    "{}, {:.3}, {:.4}",
                    v["cycles"],
                    v["wall_s"].as_f64().unwrap_or(f64::NAN),
                    v["central_nm"].as_f64().unwrap_or(f64::NAN)
                )
            };
            stops.rows.push(vec![scene.to_string(), format!("{}²", p["n"]), cell(p), cell(q)]);
        }
    }
    crate::measured::write(
        "reynolds-convergence",
        "The Reynolds solver's grid convergence",
        &format!("cargo xtask convergence reynolds --max-points {max_points}"),
        "The built-in Reynolds scenes `reynolds-m20-l10` (`M = 20, L = 10` over `[-4.5, 1.5] × \
         [-3, 3]`) and `reynolds-seed` (the seed's Table 1 over `[-1.25, 1.25]²`), each grid \
         solved from Hertz with the full-multigrid start to the strict stop rule (the central film \
         settled to 1e-4 a cycle, the load to 1e-6), on the machine's cores; then the observed \
         orders of three successive grids, the Richardson limits (the finest two at the finest \
         three's order when it lies in 1 … 3, else 2), and the same grids under the \
         discretisation-error stop rule.",
        &[
            ("Each grid", &grids),
            ("Observed orders", &ord),
            ("Richardson limits", &rich),
            ("The strict stop rule and the discretisation-error stop", &stops),
        ],
    )
}

/// `cargo xtask bench`, Reynolds part: each built-in steady scene from Hertz to converged,
/// 65² … `max` (the seed's from 257²: coarser grids cannot hold its film), with the time per
/// finest-grid W-cycle, on one thread and on two (the speed-up printed; the answers must agree
/// to the last digit: the sweep order does not depend on the thread count).
pub fn bench(max: usize) -> Result<Value> {
    println!("Reynolds solves (from Hertz, full-multigrid start, to the strict stop rule):");
    let mut rows = vec![];
    for name in ["reynolds-m20-l10", "reynolds-seed"] {
        for n in crate::grid_sizes(max).into_iter().filter(|&n| name != "reynolds-seed" || n >= 257)
        {
            // Wall times on this shared machine vary by ±30 % from run to run: each solve
            // three times, one and two threads interleaved, the fastest of each kept.
            let pools = [1, 2].map(|t| rayon::ThreadPoolBuilder::new().num_threads(t).build());
            let mut by_threads: Vec<Solve> = vec![];
            let mut walls = [vec![], vec![]];
            for _rep in 0..3 {
                for (k, pool) in pools.iter().enumerate() {
                    let pool = pool.as_ref().map_err(|e| anyhow::anyhow!("{e}"))?;
                    let r = pool.install(|| solve_scene_quiet(name, n))?;
                    walls[k].push(r.wall_s);
                    match by_threads.get_mut(k) {
                        Some(best) if best.wall_s <= r.wall_s => {}
                        Some(best) => *best = r,
                        None => by_threads.push(r),
                    }
                }
            }
            for (k, r) in by_threads.iter().enumerate() {
                let threads = k + 1;
                let fine = r.per_cycle.len().max(1);
                let first_fine = r.per_cycle.first().map_or(0.0, |c| c.0);
                let per_cycle = (r.wall_s - first_fine) / (fine.saturating_sub(1).max(1)) as f64;
                let mut w = walls[k].clone();
                w.sort_by(f64::total_cmp);
                print!("  {threads} thread{}", if threads > 1 { "s" } else { " " });
                print_solve(r, None);
                println!(
                    "        fastest of 3 (median {:.3} s); per finest W-cycle {:.3} s ({} of {} cycles on {}^2)",
                    w[1], per_cycle, fine, r.cycles, n
                );
                rows.push(json!({"scene": name, "n": n, "threads": threads,
                    "converged": r.converged, "cycles": r.cycles, "finest_cycles": fine,
                    "wall_s": r.wall_s, "median_wall_s": w[1], "per_finest_cycle_s": per_cycle,
                    "central_nm": r.central_nm, "minimum_nm": r.minimum_nm}));
            }
            let (one, two) = (&by_threads[0], &by_threads[1]);
            anyhow::ensure!(
                one.central_nm == two.central_nm && one.minimum_nm == two.minimum_nm,
                "{name} on {n}^2: the thread count changed the answer ({} / {} nm)",
                one.central_nm,
                two.central_nm
            );
            println!("        2 threads: {:.2}x faster, same answer", one.wall_s / two.wall_s);
        }
    }
    println!(
        "Targets: M = 20, L = 10 single thread 257^2 <= 0.4 s, 513^2 <= 1.5 s; 2 threads >= 1.5x"
    );
    Ok(json!(rows))
}
