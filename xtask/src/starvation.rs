//! The starvation study: the seed's contact fed supplies of 5 nm … 200 nm, the layer model and
//! the mass-conserving Reynolds solver against the flooded Reynolds film; the starvation curve
//! `R = h_c / h_c,flooded` against `r = h_oil / (ρ̄_c h_c,flooded)` with the Chevalier/Damiens
//! form `R = r / (1 + r^γ)^(1/γ)` fitted for each model; and the grid convergence of the
//! starved film and its inlet meniscus.

use crate::measured::{self, Table};
use anyhow::{Context, Result};
use ehl_scene::{Model, Parameter, Scene};
use ehl_workbench::compare;
use ehl_workbench::plot::{self, Mark, Panel, Series};
use std::path::{Path, PathBuf};

/// The supplies of the built-in sweep `seed-supply` [m].
fn supplies() -> Result<Vec<f64>> {
    let (sweep, _) = ehl_scene::sweep::load_sweep("seed-supply")?;
    let all = sweep.parameters[0].values();
    // Quickly: every third, the thinnest and the seed's among them.
    Ok(if crate::quick() { all.into_iter().step_by(3).collect() } else { all })
}

/// `R(r) = r / (1 + r^γ)^(1/γ)`.
fn curve(r: f64, gamma: f64) -> f64 {
    r / (1.0 + r.powf(gamma)).powf(1.0 / gamma)
}

/// The `γ` in [0.5, 10] that fits `(r, R)` best in least squares on `log R` (golden section on
/// a unimodal error), and its RMS misfit.
fn fit_gamma(points: &[(f64, f64)]) -> (f64, f64) {
    let err = |g: f64| {
        let s: f64 = points.iter().map(|&(r, big_r)| (curve(r, g).ln() - big_r.ln()).powi(2)).sum();
        (s / points.len() as f64).sqrt()
    };
    let (mut a, mut b) = (0.5f64, 10.0f64);
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (c, d) = (b - phi * (b - a), a + phi * (b - a));
        if err(c) < err(d) { b = d } else { a = c }
    }
    let g = 0.5 * (a + b);
    (g, err(g))
}

/// One supply through the comparison's models: the central films [m] of the layer model, the
/// starved and the flooded Reynolds solver, `ρ̄` at the flooded centre, the inlet meniscus [a].
struct Point {
    h_oil: f64,
    layer: Option<f64>,
    starved: Option<f64>,
    flooded: f64,
    rho_c: f64,
    meniscus_a: Option<f64>,
    starved_s: f64,
    flooded_s: f64,
}

fn run_point(seed: &Scene, h_oil: f64) -> Result<Point> {
    let mut scene =
        seed.with_parameter(Parameter::SupplyThickness, h_oil).map_err(anyhow::Error::msg)?;
    scene.outputs.figures = false;
    // One at a time: the starved and flooded walls are set against each other as costs.
    let c = compare::run_with(&scene, compare::Schedule::OneAtATime);
    let film = |m: Model| {
        c.entries
            .iter()
            .find(|e| e.model == m)
            .and_then(|e| e.outcome.as_ref().ok())
            .map(|o| o.observables().central_film_m)
    };
    let wall =
        |m: Model| c.entries.iter().find(|e| e.model == m).map_or(f64::NAN, |e| e.wall_time_s);
    let flooded_entry =
        c.entries.iter().find(|e| e.model == Model::ReynoldsFlooded).context("flooded entry")?;
    let flooded = flooded_entry
        .outcome
        .as_ref()
        .map_err(|e| anyhow::anyhow!("flooded Reynolds failed: {e}"))?;
    let s = flooded.scales();
    let g = flooded.grid();
    let pc = flooded.pressure()[[g.row_nearest(0.0), g.col_nearest(0.0)]];
    // ρ̄ at the flooded centre (Dowson–Higginson, the seed's density law).
    let rho_c = ehl_core::laws::Density::DowsonHigginson { p_h: s.p_h }.rho(pc);
    let meniscus_a = c
        .entries
        .iter()
        .find(|e| e.model == Model::Reynolds)
        .and_then(|e| e.outcome.as_ref().ok())
        .and_then(|o| o.summary()["supply"]["inlet_meniscus"]["value"].as_f64())
        .map(|x| x / s.a);
    Ok(Point {
        h_oil,
        layer: film(Model::Layer),
        starved: film(Model::Reynolds),
        flooded: film(Model::ReynoldsFlooded).context("flooded film")?,
        rho_c,
        meniscus_a,
        starved_s: wall(Model::Reynolds),
        flooded_s: wall(Model::ReynoldsFlooded),
    })
}

/// Runs the study: the supply sweep on `points`², the grid study of the starved film on
/// `grids`, the figure and `docs/measured/starvation.md`.
pub fn run(out: &Path, points: usize, grids: &[usize]) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    let mut seed = ehl_scene::builtin("seed").map_err(anyhow::Error::msg)?;
    seed.grid.nx = points;
    seed.grid.ny = points;
    let pts: Vec<Point> =
        supplies()?.into_iter().map(|h| run_point(&seed, h)).collect::<Result<_>>()?;
    let mut table = Table::new(&[
        "h_oil [nm]",
        "r",
        "R layer",
        "R Reynolds",
        "rho_c h_c / h_oil",
        "inlet meniscus [a]",
        "starved / flooded solve time",
    ]);
    let (mut layer_rr, mut rey_rr) = (vec![], vec![]);
    let mut data = vec![];
    for p in &pts {
        let r = p.h_oil / (p.rho_c * p.flooded);
        let rl = p.layer.map(|h| h / p.flooded);
        let rs = p.starved.map(|h| h / p.flooded);
        data.push(serde_json::json!({
            "h_oil_m": p.h_oil, "r": r, "rho_c": p.rho_c,
            "central_film_m": {"layer": p.layer, "reynolds": p.starved, "reynolds_flooded": p.flooded},
            "inlet_meniscus_a": p.meniscus_a,
            "solve_s": {"reynolds": p.starved_s, "reynolds_flooded": p.flooded_s},
        }));
        if let Some(v) = rl {
            layer_rr.push((r, v));
        }
        if let Some(v) = rs {
            rey_rr.push((r, v));
        }
        let f = |v: Option<f64>| v.map_or("failed".into(), |v| format!("{v:.4}"));
        table.rows.push(vec![
            format!("{:.0}", p.h_oil * 1e9),
            format!("{r:.3}"),
            f(rl),
            f(rs),
            f(p.starved.map(|h| p.rho_c * h / p.h_oil)),
            p.meniscus_a.map_or("-".into(), |x| format!("{x:.3}")),
            format!(
                "{:.1} s / {:.2} s = {:.0}×",
                p.starved_s,
                p.flooded_s,
                p.starved_s / p.flooded_s
            ),
        ]);
    }
    let (g_rey, e_rey) = fit_gamma(&rey_rr);
    let (g_layer, e_layer) = fit_gamma(&layer_rr);
    let mut fits = Table::new(&["model", "gamma", "RMS misfit of ln R"]);
    fits.rows.push(vec![
        "Reynolds (mass conserving)".into(),
        format!("{g_rey:.2}"),
        format!("{e_rey:.3}"),
    ]);
    fits.rows.push(vec!["layer".into(), format!("{g_layer:.2}"), format!("{e_layer:.3}")]);

    // Grid convergence of the starved film and the meniscus (5 nm: fully starved; 25 nm: the
    // seed's supply, nearly flooded).
    let mut conv = Table::new(&[
        "h_oil [nm]",
        "grid",
        "h_c [nm]",
        "inlet meniscus [a]",
        "cycles",
        "solve [s]",
    ]);
    for h_oil in [5e-9, 25e-9] {
        for &n in grids {
            let mut s = seed
                .for_model(Model::Reynolds)
                .with_parameter(Parameter::SupplyThickness, h_oil)
                .map_err(anyhow::Error::msg)?;
            s.grid.nx = n;
            s.grid.ny = n;
            let row = match ehl_workbench::reynolds::run_reynolds(&s) {
                Ok(o) => {
                    let hc = ehl_workbench::model::Outcome::observables(&o).central_film_m;
                    vec![
                        format!("{:.0}", h_oil * 1e9),
                        format!("{n}²"),
                        format!("{:.4}", hc * 1e9),
                        o.meniscus_a().map_or("-".into(), |x| format!("{x:.4}")),
                        o.report.cycles.to_string(),
                        format!("{:.2}", o.report.wall_time_s),
                    ]
                }
                Err(e) => vec![
                    format!("{:.0}", h_oil * 1e9),
                    format!("{n}²"),
                    format!("failed: {e}"),
                    "".into(),
                    "".into(),
                    "".into(),
                ],
            };
            conv.rows.push(row);
        }
    }

    // The figure: R against r, both models, the fitted curves, the seed's 25 nm marked.
    let line = |g: f64| -> Vec<(f64, f64)> {
        (0..=60)
            .map(|k| 10f64.powf(-1.0 + 2.5 * k as f64 / 60.0))
            .map(|r| (r, curve(r, g)))
            .collect()
    };
    let fig = out.join("starvation.png");
    plot::charts(
        &fig,
        &[Panel::new(
            "Starvation: the seed's contact fed 5-200 nm (R = h_c / h_c,flooded Reynolds)",
            "r = h_oil / (rho_c h_c,flooded)",
            "R",
            vec![
                Series::new("Reynolds, mass conserving", rey_rr.clone(), Mark::Points),
                Series::new(format!("fit, gamma = {g_rey:.2}"), line(g_rey), Mark::Line),
                Series::new("layer model", layer_rr.clone(), Mark::Points),
                Series::new(format!("fit, gamma = {g_layer:.2}"), line(g_layer), Mark::Line),
            ],
        )
        .log_log()],
        &format!("{points}² over [-1.25, 1.25]² a; Table 1 conditions, u1 = 0.01 m/s"),
    )?;
    let csv = out.join("starvation.csv");
    // The numbers behind the table as data, through the workbench's one CSV writer.
    std::fs::write(&csv, ehl_workbench::output::csv(&data))?;
    let page = measured::write(
        "starvation",
        "Starvation: the seed's contact fed a finite supply",
        &format!("cargo xtask starvation --points {points}"),
        "Both models fed the same supply (the built-in sweep `seed-supply`); `R` is each model's \
         central film over the flooded Reynolds film, `r` the supply over the flooded central \
         film's oil (`rho_c` the density at the flooded centre). The thin-supply limit is \
         `rho_c h_c = h_oil` (mass conservation through the contact). The fitted form is \
         Chevalier et al. (1998) / Damiens et al. (2004): `R = r / (1 + r^gamma)^(1/gamma)`.",
        &[
            ("The supply sweep", &table),
            ("Fits of the starvation curve", &fits),
            ("Grid convergence of the starved Reynolds film", &conv),
        ],
    )?;
    Ok(vec![fig, csv, page])
}

/// The operating points of the starved bench: the seed's (Table 1) and the low-speed, loaded
/// one whose fed solve grew most with the grid: `(u1 [m/s], load [N])`.
const STARVED_POINTS: [(f64, f64); 2] = [(0.01, 20.0), (0.005, 40.0)];

/// The supplies of the starved bench [m].
const STARVED_SUPPLIES: [f64; 3] = [5e-9, 10e-9, 25e-9];

/// The target of the starved bench: a fed solve's cycles and wall time within this factor of
/// the flooded solve's on the same grid.
const STARVED_TARGET: f64 = 1.5;

/// What one steady Reynolds solve cost and gave.
#[derive(Clone, Copy)]
struct Cost {
    /// Wall time [s].
    wall: f64,
    cycles: usize,
    /// The cycles' work in finest-grid cycles (`ReynoldsReport::work_cycles`).
    work: f64,
    /// Central film [m].
    hc: f64,
    /// Slow-mode jumps taken.
    jumps: usize,
    /// Attempts the cascade ran.
    attempts: usize,
}

/// One steady Reynolds solve's cost, the median of `reps` by wall time, or what stopped it.
fn timed(scene: &Scene, reps: usize) -> std::result::Result<Cost, String> {
    let mut runs = vec![];
    for _ in 0..reps {
        let o = ehl_workbench::reynolds::run_reynolds(scene).map_err(|e| e.to_string())?;
        let hc = ehl_workbench::model::Outcome::observables(&o).central_film_m;
        let r = &o.report;
        runs.push(Cost {
            wall: r.wall_time_s,
            cycles: r.cycles,
            work: r.work_cycles,
            hc,
            jumps: r.mode_jumps,
            attempts: r.attempts,
        });
    }
    runs.sort_by(|a, b| a.wall.total_cmp(&b.wall));
    Ok(runs[runs.len() / 2])
}

/// The starved steady solve's cost against the flooded one (cycles, wall time, the attempts
/// its cascade ran) on the seed's contact and at 5 mm/s, 40 N, fed 5, 10 and 25 nm, on 257²,
/// 513², … up to `max` points per side (quickly: 129², the seed's point), the median of `reps`
/// solves each on 257² and one above: `docs/measured/bench-starved.md`.
pub fn bench(max: usize, reps: usize) -> Result<PathBuf> {
    let grids: Vec<usize> = if crate::quick() {
        vec![129]
    } else {
        [257, 513, 1025, 2049].into_iter().filter(|&n| n <= max.max(257)).collect()
    };
    let points: &[(f64, f64)] = if crate::quick() { &STARVED_POINTS[..1] } else { &STARVED_POINTS };
    let mut t = Table::new(&[
        "u1 [m/s]",
        "load [N]",
        "grid",
        "supply",
        "solve [s]",
        "cycles",
        "work [finest-grid cycles]",
        "attempts",
        "slow-mode jumps",
        "h_c [nm]",
        "time against flooded",
        "cycles against flooded",
        "work against flooded",
        "time a unit of work against flooded",
    ]);
    let (mut fed, mut within_time, mut within_cycles, mut cascades) = (0, 0, 0, 0);
    let mut within_work = 0;
    for &(u1, load) in points {
        for &n in &grids {
            let mut seed = ehl_scene::builtin("seed").map_err(anyhow::Error::msg)?;
            seed.grid.nx = n;
            seed.grid.ny = n;
            seed.outputs.figures = false;
            seed.conditions.rolling_velocity_m_s = Some(u1);
            seed.conditions.load_n = load;
            let reps = if n <= 257 { reps } else { 1 };
            println!("{u1} m/s, {load} N on {n}²: flooded");
            let head =
                |supply: String| vec![format!("{u1}"), format!("{load}"), format!("{n}²"), supply];
            let flooded = match timed(&seed.for_model(Model::ReynoldsFlooded), reps) {
                Ok(f) => f,
                Err(e) => {
                    let mut row = head("none (flooded)".into());
                    row.push(format!("failed: {}", e.chars().take(80).collect::<String>()));
                    row.extend(std::iter::repeat_n(String::new(), 9));
                    t.rows.push(row);
                    continue;
                }
            };
            let mut row = head("none (flooded)".into());
            row.extend([
                format!("{:.2}", flooded.wall),
                flooded.cycles.to_string(),
                format!("{:.1}", flooded.work),
                flooded.attempts.to_string(),
                String::new(),
                format!("{:.3}", flooded.hc * 1e9),
                "1.0×".into(),
                "1.0×".into(),
                "1.0×".into(),
                "1.0×".into(),
            ]);
            t.rows.push(row);
            for h_oil in STARVED_SUPPLIES {
                println!("{u1} m/s, {load} N on {n}²: fed {:.0} nm", h_oil * 1e9);
                let s = seed
                    .for_model(Model::Reynolds)
                    .with_parameter(Parameter::SupplyThickness, h_oil)
                    .map_err(anyhow::Error::msg)?;
                let mut row = head(format!("{:.0} nm", h_oil * 1e9));
                fed += 1;
                match timed(&s, reps) {
                    Ok(Cost { wall: w, cycles: c, work, hc, jumps, attempts }) => {
                        let (rt, rc) = (w / flooded.wall, c as f64 / flooded.cycles as f64);
                        let rw = work / flooded.work;
                        within_time += usize::from(rt <= STARVED_TARGET);
                        within_cycles += usize::from(rc <= STARVED_TARGET);
                        within_work += usize::from(rw <= STARVED_TARGET);
                        cascades += usize::from(attempts > 1);
                        row.extend([
                            format!("{w:.2}"),
                            c.to_string(),
                            format!("{work:.1}"),
                            attempts.to_string(),
                            jumps.to_string(),
                            format!("{:.3}", hc * 1e9),
                            format!("{rt:.1}×"),
                            format!("{rc:.1}×"),
                            format!("{rw:.1}×"),
                            format!("{:.1}×", rt / rw),
                        ]);
                    }
                    Err(e) => {
                        row.push(format!("failed: {}", e.chars().take(80).collect::<String>()));
                        row.extend(std::iter::repeat_n(String::new(), 9));
                    }
                }
                t.rows.push(row);
            }
        }
    }
    let max_n = grids.last().copied().unwrap_or(257);
    measured::write(
        "bench-starved",
        "The starved Reynolds solve against the flooded one",
        &format!("cargo xtask bench --only starved --max-points {max_n}"),
        &format!(
            "The seed's contact (Table 1) at its own 10 mm/s, 20 N and at 5 mm/s, 40 N, on its \
             domain [-1.25, 1.25]² a, {} points per side, steady, flooded and fed 5, 10 and 25 nm; \
             the median of {reps} solves on 257², one above. The target: a fed solve's cycles \
             and wall time within {STARVED_TARGET}× the flooded solve's on the same grid. \
             Attempts: those the steady solve's cascade ran (1: the first answered). Slow-mode \
             jumps: the mass-conserving solve's extrapolations along its slow mode \
             (`mode_extrapolation`, `crates/reynolds/src/extrapolate.rs`). Cycles are counted \
             on every grid alike, a full-multigrid start's on its coarse grids included; work \
             counts each cycle at its top grid's share of the finest grid's points (one on \
             half the points per side a quarter, `ReynoldsReport::work_cycles`), every \
             attempt's, so that it compares solves whose starts begin on different grids (the \
             fed start begins on the coarsest grid that holds its film, the flooded one on \
             17²); the time a unit of work is the price of a fed cycle against a flooded one. \
             Of the {fed} fed solves, {within_time} within the target in time, {within_work} \
             in work and {within_cycles} in cycles; {cascades} needed more than one attempt.",
            grids.iter().map(|n| format!("{n}")).collect::<Vec<_>>().join(", ")
        ),
        &[("Steady solves", &t)],
    )
}
