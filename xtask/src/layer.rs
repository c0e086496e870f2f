//! Layer-model studies: grid and time-step convergence of steady rolling (seed Fig. 15), explicit
//! against implicit, the explicit stability limit by experiment, speed against accuracy, and the
//! per-step bench.

use anyhow::{Context, Result};
use ehl_layer::{LayerModel, ModulusLaw, Scheme, Stepper, squeeze_steady};
use ehl_scene::Scene;
use ehl_scene::TimeSettings;
use ehl_workbench::layer::LayerOutcome;
use ehl_workbench::plot::{self, Mark, Panel, Series};
use ehl_workbench::{Outcome, run_scene};
use plotters::prelude::SeriesLabelPosition;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The steady-rolling scene with another grid, scheme and steps per cell.
pub fn rolling(n: usize, scheme: Scheme, nt: f64) -> Scene {
    let mut s = ehl_scene::builtin("rolling-from-uniform").unwrap().with_points(n).unwrap();
    let r = s.run.as_mut().unwrap();
    r.method = Some(ehl_scene::Method::March);
    r.time = TimeSettings { scheme, steps_per_cell: nt, ..r.time };
    r.snapshots_s.clear();
    r.snapshots_a.clear();
    s.outputs.figures = false;
    s
}

/// The same with the coefficient smoothing set to `sigma` [a] (0: the model as published).
pub fn rolling_smoothed(n: usize, sigma: f64) -> Scene {
    let mut s = rolling(n, Scheme::Implicit, 10.0);
    s.layer.as_mut().unwrap().coefficient_smoothing_a = sigma;
    s
}

fn layer(o: Box<dyn Outcome>) -> LayerOutcome {
    *o.downcast::<LayerOutcome>().expect("a layer scene")
}

/// One steady-rolling result.
#[derive(Clone, Debug, serde::Serialize)]
struct Point {
    n: usize,
    scheme: Scheme,
    nt: f64,
    dt_s: f64,
    central_nm: f64,
    minimum_nm: f64,
    max_pressure_ph: f64,
    wiggle_ph: f64,
    steps: usize,
    wall_s: f64,
    steady: bool,
}

fn measure(n: usize, scheme: Scheme, nt: f64) -> Result<Point> {
    measure_scene(&rolling(n, scheme, nt))
}

fn measure_scene(scene: &Scene) -> Result<Point> {
    let (n, scheme, nt) = {
        let t = &scene.run.as_ref().unwrap().time;
        (scene.grid.nx, t.scheme, t.steps_per_cell)
    };
    let o = layer(run_scene(scene)?);
    let rec = o.record.as_ref().unwrap();
    let f = &o.final_monitor;
    let p = Point {
        n,
        scheme,
        nt,
        dt_s: o.grid.dx() * o.scales.a / (nt * 0.01),
        central_nm: f.central_thickness * 1e9,
        minimum_nm: f.minimum_thickness * 1e9,
        max_pressure_ph: o.observables().max_pressure_pa / o.scales.p_h,
        wiggle_ph: f.lateral_wiggle / o.scales.p_h,
        steps: rec.steps,
        wall_s: rec.wall_time_s,
        steady: rec.finished,
    };
    println!(
        "  {:>4} {:>9} n_t={:>5} dt={:.3e}s  h_c={:8.4} nm  h_min={:7.4} nm  p_max={:.4} p_h  wiggle={:.3} p_h  {:>6} steps {:7.1} s{}",
        p.n,
        format!("{:?}", p.scheme),
        p.nt,
        p.dt_s,
        p.central_nm,
        p.minimum_nm,
        p.max_pressure_ph,
        p.wiggle_ph,
        p.steps,
        p.wall_s,
        if p.steady { "" } else { "  NOT STEADY" }
    );
    Ok(p)
}

/// Observed order of three results with refinement ratio 2 (the core's one definition).
fn order3(q1: f64, q2: f64, q3: f64) -> f64 {
    ehl_core::hertz::observed_order_of_three(q1, q2, q3, 2.0)
}

fn print_orders(label: &str, pts: &[&Point]) -> Vec<serde_json::Value> {
    let mut v = vec![];
    for w in pts.windows(3) {
        let (a, b, c) = (w[0], w[1], w[2]);
        let oc = order3(a.central_nm, b.central_nm, c.central_nm);
        let om = order3(a.minimum_nm, b.minimum_nm, c.minimum_nm);
        println!(
            "  observed order ({label} {} -> {} -> {}): central {:.2}, minimum {:.2}",
            if label == "grid" { a.n as f64 } else { a.nt },
            if label == "grid" { b.n as f64 } else { b.nt },
            if label == "grid" { c.n as f64 } else { c.nt },
            oc,
            om
        );
        v.push(json!({"from": [a.n, a.nt], "to": [c.n, c.nt], "central": oc, "minimum": om}));
    }
    v
}

/// `cargo xtask convergence layer`.
pub fn convergence(out: &Path, max_points: usize, nt_points: usize) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    println!(
        "Layer model, steady rolling from a uniform layer (Table 1, u1 = 0.01 m/s), to steady"
    );
    println!("Grid study (n_t = 10):");
    let mut grid_pts = vec![];
    for n in crate::grid_sizes(max_points) {
        grid_pts.push(measure(n, Scheme::Implicit, 10.0)?);
        // The explicit scheme costs two solves a step: up to 257² here.
        if n <= 257 {
            grid_pts.push(measure(n, Scheme::Explicit, 10.0)?);
        }
    }
    let imp: Vec<&Point> = grid_pts.iter().filter(|p| p.scheme == Scheme::Implicit).collect();
    let exp: Vec<&Point> = grid_pts.iter().filter(|p| p.scheme == Scheme::Explicit).collect();
    let mut orders = json!({});
    orders["grid_implicit"] = json!(print_orders("grid", &imp));
    orders["grid_explicit"] = json!(print_orders("grid", &exp));

    println!("Time-step study on {nt_points}^2:");
    let nts = [2.5, 5.0, 10.0, 20.0, 40.0, 80.0];
    // Time-step differences at n_t >= 10 are ~1e-3 nm: stop on a 10x tighter steady rule than
    // the scenes' (1e-3 l0 = 0.025 nm), or the stop itself decides the differences.
    let tight = |scheme, nt| {
        let mut s = rolling(nt_points, scheme, nt);
        s.run.as_mut().unwrap().stop.steady_tolerance = 1e-4;
        s
    };
    let mut nt_pts = vec![];
    // n_t = 1 (exact whole-cell transport) for the implicit scheme only: the explicit one is
    // unstable there on 129² (see the stability limit below).
    for &nt in [1.0].iter().chain(&nts) {
        nt_pts.push(measure_scene(&tight(Scheme::Implicit, nt))?);
    }
    for &nt in &nts[1..] {
        nt_pts.push(measure_scene(&tight(Scheme::Explicit, nt))?);
    }
    let imp_t: Vec<&Point> = nt_pts.iter().filter(|p| p.scheme == Scheme::Implicit).collect();
    let exp_t: Vec<&Point> = nt_pts.iter().filter(|p| p.scheme == Scheme::Explicit).collect();
    orders["time_implicit"] = json!(print_orders("n_t", &imp_t));
    orders["time_explicit"] = json!(print_orders("n_t", &exp_t));
    let (a, b) = (imp_t.last().unwrap(), exp_t.last().unwrap());
    println!(
        "Explicit against implicit at n_t = {} on {}^2: central {:+.2e} nm, minimum {:+.2e} nm, p_max {:+.2e} p_h (implicit's own change over its last refinement: central {:.2e}, minimum {:.2e})",
        a.nt,
        nt_points,
        b.central_nm - a.central_nm,
        b.minimum_nm - a.minimum_nm,
        b.max_pressure_ph - a.max_pressure_ph,
        (imp_t[imp_t.len() - 2].central_nm - a.central_nm).abs(),
        (imp_t[imp_t.len() - 2].minimum_nm - a.minimum_nm).abs(),
    );

    let mut limit_grids: Vec<usize> =
        [65, 129, 257].into_iter().map(crate::points).map(|n| n.min(max_points)).collect();
    limit_grids.dedup();
    let stability = stability_limit(&limit_grids)?;

    println!("Lateral instability: the model as published (smoothing 0), implicit, n_t = 10:");
    let default_sigma = rolling(65, Scheme::Implicit, 10.0).layer.unwrap().coefficient_smoothing_a;
    let mut raw = vec![];
    for n in crate::grid_sizes(max_points.min(257)) {
        raw.push(measure_scene(&rolling_smoothed(n, 0.0))?);
    }

    println!("Direct steady solve (rolling-steady), same grids:");
    let steady: Vec<SteadyPoint> = crate::grid_sizes(max_points)
        .into_iter()
        .map(|n| measure_steady(&steady_scene(n, None)))
        .collect();
    // Speed against accuracy: error against the finest implicit result of each study.
    let finest_grid = *imp.last().unwrap();
    let finest_t = *imp_t.last().unwrap();
    let curve = |pts: &[&Point], reference: &Point, label: &str, pick: fn(&Point) -> f64| {
        Series::new(
            label,
            pts.iter()
                .filter(|p| !std::ptr::eq(**p, reference))
                .map(|p| (p.wall_s, (pick(p) - pick(reference)).abs()))
                .collect(),
            Mark::LinePoints,
        )
    };
    let chart = |title: &str, pick: fn(&Point) -> f64| {
        Panel::new(
            title,
            "wall time [s]",
            "|error| [nm] vs finest implicit",
            vec![
                curve(&imp, finest_grid, "implicit, grids (n_t = 10)", pick),
                curve(&exp, finest_grid, "explicit, grids (n_t = 10)", pick),
                curve(&imp_t, finest_t, &format!("implicit, n_t ({nt_points}^2)"), pick),
                curve(&exp_t, finest_t, &format!("explicit, n_t ({nt_points}^2)"), pick),
                Series::new(
                    "steady solve, grids",
                    steady
                        .iter()
                        .filter(|p| p.converged)
                        .map(|p| {
                            let q = Point {
                                central_nm: p.central_nm,
                                minimum_nm: p.minimum_nm,
                                ..finest_grid.clone()
                            };
                            (p.wall_s, (pick(&q) - pick(finest_grid)).abs())
                        })
                        .collect(),
                    Mark::LinePoints,
                ),
            ],
        )
        .log_log()
        .legend(SeriesLabelPosition::UpperRight)
    };
    let png = out.join("layer_speed_accuracy.png");
    plot::charts(
        &png,
        &[
            chart("Central layer thickness", |p| p.central_nm),
            chart("Minimum layer thickness", |p| p.minimum_nm),
        ],
        &format!(
            "steady rolling from uniform, Table 1; grid errors against {}^2 implicit, time-step errors against n_t = 40 on {}^2",
            finest_grid.n, nt_points
        ),
    )?;
    let conv_png = out.join("layer_convergence.png");
    let vs_n = |pts: &[&Point], pick: fn(&Point) -> f64, label: &str| {
        Series::new(label, pts.iter().map(|p| (p.n as f64, pick(p))).collect(), Mark::LinePoints)
    };
    let vs_t = |pts: &[&Point], pick: fn(&Point) -> f64, label: &str| {
        Series::new(label, pts.iter().map(|p| (p.nt, pick(p))).collect(), Mark::LinePoints)
    };
    plot::charts(
        &conv_png,
        &[
            Panel::new(
                "Grid convergence (n_t = 10)",
                "points per side",
                "layer thickness [nm]",
                vec![
                    vs_n(&imp, |p| p.central_nm, "central, implicit"),
                    vs_n(&exp, |p| p.central_nm, "central, explicit"),
                    vs_n(&imp, |p| p.minimum_nm, "minimum, implicit"),
                    vs_n(&exp, |p| p.minimum_nm, "minimum, explicit"),
                ],
            )
            .legend(SeriesLabelPosition::MiddleRight),
            Panel::new(
                &format!("Time-step convergence ({nt_points}^2)"),
                "time steps per cell n_t",
                "layer thickness [nm]",
                vec![
                    vs_t(&imp_t, |p| p.central_nm, "central, implicit"),
                    vs_t(&exp_t, |p| p.central_nm, "central, explicit"),
                    vs_t(&imp_t, |p| p.minimum_nm, "minimum, implicit"),
                    vs_t(&exp_t, |p| p.minimum_nm, "minimum, explicit"),
                ],
            )
            .legend(SeriesLabelPosition::MiddleRight),
        ],
        "seed Fig. 15 analogue: steady rolling from a uniform 25 nm layer, Table 1",
    )?;
    let wig = out.join("layer_lateral_instability.png");
    plot::charts(
        &wig,
        &[Panel::new(
            "Lateral short-wave instability against grid",
            "points per side",
            "row-to-row pressure wiggle / p_h",
            vec![
                vs_n(
                    &raw.iter().collect::<Vec<_>>(),
                    |p| p.wiggle_ph,
                    "as published (no smoothing)",
                ),
                vs_n(&imp, |p| p.wiggle_ph, &format!("smoothing {default_sigma} a (default)")),
            ],
        )
        .legend(SeriesLabelPosition::UpperLeft)],
        "steady rolling, implicit, n_t = 10; streaks grow where alpha_eff (p - E eps) > 1 - eps dE/dp",
    )?;
    let json_path = out.join("layer_convergence.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&json!({
            "grid_study": grid_pts, "time_step_study": nt_pts, "observed_orders": orders,
            "as_published_grid_study": raw, "default_smoothing_a": default_sigma,
            "explicit_stability": stability, "steady_grid_study": steady,
        }))? + "\n",
    )?;
    let page = convergence_page(max_points, nt_points, &grid_pts, &nt_pts, &orders, &stability)?;
    Ok(vec![png, conv_png, wig, json_path, page])
}

/// The layer study as a measured page (`docs/measured/layer-convergence.md`).
fn convergence_page(
    max_points: usize,
    nt_points: usize,
    grid_pts: &[Point],
    nt_pts: &[Point],
    orders: &serde_json::Value,
    stability: &[serde_json::Value],
) -> Result<PathBuf> {
    use crate::measured::Table;
    let points = |pts: &[Point]| {
        let mut t = Table::new(&[
            "grid",
            "scheme",
            "n_t",
            "h_c [nm]",
            "h_min [nm]",
            "p_max / p_h",
            "row-to-row wiggle / p_h",
            "steps",
            "wall [s]",
            "per step [ms]",
            "steady",
        ]);
        for p in pts {
            t.rows.push(vec![
                format!("{}²", p.n),
                format!("{:?}", p.scheme).to_lowercase(),
                format!("{}", p.nt),
                format!("{:.4}", p.central_nm),
                format!("{:.4}", p.minimum_nm),
                format!("{:.4}", p.max_pressure_ph),
                format!("{:.3}", p.wiggle_ph),
                p.steps.to_string(),
                format!("{:.1}", p.wall_s),
                format!("{:.1}", 1e3 * p.wall_s / p.steps.max(1) as f64),
                if p.steady { "yes".into() } else { "no".into() },
            ]);
        }
        t
    };
    let mut ord = Table::new(&["study", "from", "to", "order of h_c", "order of h_min"]);
    for key in ["grid_implicit", "grid_explicit", "time_implicit", "time_explicit"] {
        for o in orders[key].as_array().into_iter().flatten() {
            let f = |k: &str| format!("{:.2}", o[k].as_f64().unwrap_or(f64::NAN));
            ord.rows.push(vec![
                key.replace('_', ", "),
                format!("{}² n_t {}", o["from"][0], o["from"][1]),
                format!("{}² n_t {}", o["to"][0], o["to"][1]),
                f("central"),
                f("minimum"),
            ]);
        }
    }
    let mut stab = Table::new(&[
        "grid",
        "largest stable Δt [s]",
        "first failing Δt [s]",
        "estimate 2η/(E + k l0) [s]",
    ]);
    for r in stability {
        let f = |k: &str| format!("{:.3e}", r[k].as_f64().unwrap_or(f64::NAN));
        stab.rows.push(vec![
            format!("{}²", r["n"]),
            f("largest_stable_dt_s"),
            f("first_failing_dt_s"),
            f("estimate_s"),
        ]);
    }
    crate::measured::write(
        "layer-convergence",
        "The layer model's grid and time-step convergence",
        &format!("cargo xtask convergence layer --max-points {max_points} --nt-points {nt_points}"),
        "Steady rolling from a uniform layer (Table 1, `u1` = 0.01 m/s, the built-in defaults) \
         until the run's steady rule, on grids at `n_t` = 10 steps a cell (the explicit scheme up \
         to 257²: two solves a step), then on one grid over `n_t` (the runs stopped on a rule ten \
         times tighter than the scenes', so the stop does not decide the differences); the \
         observed orders of three successive grids or step counts; and the explicit scheme's \
         stability limit found by experiment (the step raised until 0.5 a of rolling from the \
         steady state fails) against the model notes' estimate.",
        &[
            ("The grid study", &points(grid_pts)),
            ("The time-step study", &points(nt_pts)),
            ("Observed orders", &ord),
            ("The explicit scheme's stability limit", &stab),
        ],
    )
}

/// Raises the explicit step until the run fails; from the implicit steady state, 0.5 a of travel.
fn stability_limit(grids: &[usize]) -> Result<Vec<serde_json::Value>> {
    println!(
        "Explicit stability limit by experiment (0.5 a of rolling from the implicit steady state):"
    );
    let mut rows = vec![];
    for &n in grids {
        let scene = rolling(n, Scheme::Implicit, 10.0);
        let start = layer(run_scene(&scene)?);
        let (model, estimate) = model_of(&scene)?;
        let mut last_ok = None;
        let mut first_fail = None;
        for nt in [10.0, 5.0, 3.0, 2.0, 1.5, 1.0, 0.75, 0.5] {
            let mut s = start.final_state.clone();
            let dt = model.grid.dx() * model.scales.a / (nt * model.rolling_speed());
            let mut st = Stepper::new(Scheme::Explicit, 0);
            let steps = (0.5 * nt / model.grid.dx()).ceil() as usize;
            let mut failure = None;
            for _ in 0..steps {
                if let Err(e) = st.step(&model, &mut s, dt) {
                    failure = Some(e.to_string());
                    break;
                }
            }
            match failure {
                None => {
                    println!("  {n:>4}^2  n_t = {nt:>5}  dt = {dt:.3e} s  stable");
                    last_ok = Some(dt);
                }
                Some(e) => {
                    println!("  {n:>4}^2  n_t = {nt:>5}  dt = {dt:.3e} s  FAILS: {e}");
                    first_fail = Some(dt);
                    break;
                }
            }
        }
        println!(
            "  {n:>4}^2: largest stable dt {:.3e} s, first failing {:.3e} s; estimate 2 eta/(E + k l0) = {estimate:.3e} s",
            last_ok.unwrap_or(f64::NAN),
            first_fail.unwrap_or(f64::NAN)
        );
        rows.push(json!({"n": n, "largest_stable_dt_s": last_ok, "first_failing_dt_s": first_fail, "estimate_s": estimate}));
    }
    Ok(rows)
}

fn model_of(scene: &Scene) -> Result<(LayerModel, f64)> {
    let m = LayerModel::new(
        &scene.conditions.contact(),
        &scene.lubricant.unwrap().lubricant(),
        &scene.layer.unwrap(),
        scene.supply.as_ref().context("a layer scene has a supply")?.thickness_m,
        ehl_core::Kinematics::constant(scene.conditions.rolling_velocity_m_s.unwrap()).unwrap(),
        scene.grid(),
        *scene.solver,
    )
    .unwrap();
    let e = ehl_layer::stability_estimate(&m);
    Ok((m, e))
}

/// Seed Fig. 3 analogue: the modulus laws against strain and pressure.
pub fn modulus_figure(out: &Path) -> Result<PathBuf> {
    let scene = ehl_scene::builtin("rolling-from-uniform").unwrap();
    let (m, _) = model_of(&scene.with_points(17)?)?;
    let laws = [ModulusLaw::Power, ModulusLaw::PowerLinear, ModulusLaw::Geometric];
    let mut panels = vec![];
    let style = |k: usize| if k == 0 { Mark::Line } else { Mark::LinePoints };
    let mut s1 = vec![];
    let mut s2 = vec![];
    for (k, law) in laws.iter().enumerate() {
        for &p in &[0.5, 1.0, 1.5] {
            s1.push(Series::new(
                format!("{law:?}, p = {p} p_h"),
                (0..=50)
                    .map(|i| {
                        let e = i as f64 / 50.0;
                        (e, law.modulus(p, e, m.eo, m.p_ref))
                    })
                    .collect(),
                style(k),
            ));
        }
        for &e in &[0.25, 0.5, 0.9] {
            s2.push(Series::new(
                format!("{law:?}, eps = {e}"),
                (0..=50)
                    .map(|i| {
                        let p = 1.5 * i as f64 / 50.0;
                        (p, law.modulus(p, e, m.eo, m.p_ref))
                    })
                    .collect(),
                style(k),
            ));
        }
    }
    panels.push(
        Panel::new("E against strain", "strain eps", "E / p_h", s1)
            .legend(SeriesLabelPosition::UpperLeft),
    );
    panels.push(
        Panel::new("E against pressure", "p / p_h", "E / p_h", s2)
            .legend(SeriesLabelPosition::UpperLeft),
    );
    let f = out.join("layer_fig03_modulus.png");
    plot::charts(
        &f,
        &panels,
        &format!(
            "modulus laws (reconstructions of the seed's lost Eq. 10): Eo = {:.4} p_h, p_ref = p_h; Power (default): E = Eo + max(p - Eo, 0) eps^(p_ref/Eo)",
            m.eo
        ),
    )?;
    Ok(f)
}

/// `cargo xtask bench` (layer part): time and contact iterations per step, and the direct
/// steady-squeeze solve, on 65² … max².
pub fn bench(max: usize) -> Result<Vec<serde_json::Value>> {
    println!(
        "Layer model benchmark: 40 rolling steps (n_t = 10) right after a restart from the squeezed layer (the hardest phase), and the direct steady squeeze"
    );
    println!(
        "{:>5} {:>12} {:>10} {:>12} {:>10} {:>14} {:>8}",
        "n", "impl ms/step", "its/step", "expl ms/step", "its/step", "squeeze-dir s", "passes"
    );
    let mut rows = vec![];
    for n in crate::grid_sizes(max) {
        let scene = rolling(n, Scheme::Implicit, 10.0);
        let (m, _) = model_of(&scene)?;
        let t = Instant::now();
        let (sq, rep) = squeeze_steady(&m)?;
        let sq_time = t.elapsed().as_secs_f64();
        let _ = rep;
        let dt = m.grid.dx() * m.scales.a / (10.0 * m.rolling_speed());
        let mut per = vec![];
        for scheme in [Scheme::Implicit, Scheme::Explicit] {
            let mut s = sq.clone();
            let mut st = Stepper::new(scheme, 0);
            // Warm up past the restart transient's first steps, then time.
            for _ in 0..5 {
                st.step(&m, &mut s, dt)?;
            }
            let steps = 40;
            let t = Instant::now();
            let mut its = 0;
            for _ in 0..steps {
                its += st.step(&m, &mut s, dt)?.iterations;
            }
            per.push((t.elapsed().as_secs_f64() / steps as f64 * 1e3, its as f64 / steps as f64));
        }
        println!(
            "{:>5} {:>12.2} {:>10.2} {:>12.2} {:>10.2} {:>14.3} {:>8}",
            n, per[0].0, per[0].1, per[1].0, per[1].1, sq_time, rep.passes
        );
        rows.push(json!({
            "n": n, "implicit_ms_per_step": per[0].0, "implicit_iterations_per_step": per[0].1,
            "explicit_ms_per_step": per[1].0, "explicit_iterations_per_step": per[1].1,
            "steady_squeeze_s": sq_time, "steady_squeeze_passes": rep.passes,
        }));
    }
    println!(
        "Targets: steady squeeze at 513^2 <= 5 s; steady rolling 257^2 n_t = 10 <= 60 s (see `ehl run rolling-from-uniform`)"
    );
    Ok(rows)
}

/// The built-in `rolling-steady` scene (direct steady solve) on an `n²` grid, no figures.
pub fn steady_scene(n: usize, smoothing: Option<f64>) -> Scene {
    let mut s = ehl_scene::builtin("rolling-steady").unwrap().with_points(n).unwrap();
    if let Some(sigma) = smoothing {
        s.layer.as_mut().unwrap().coefficient_smoothing_a = sigma;
    }
    s.outputs.figures = false;
    s
}

/// One direct steady solve: its films, cost, or why it failed.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SteadyPoint {
    pub n: usize,
    pub converged: bool,
    pub diagnosis: Option<String>,
    pub central_nm: f64,
    pub minimum_nm: f64,
    pub max_pressure_ph: f64,
    pub wiggle_ph: f64,
    /// `(points a side, iterations)`, coarsest first.
    pub iterations: Vec<(usize, usize)>,
    pub wall_s: f64,
}

pub fn measure_steady(scene: &Scene) -> SteadyPoint {
    let n = scene.grid.nx;
    let t = Instant::now();
    let p = match run_scene(scene) {
        Ok(o) => {
            let o = layer(o);
            let f = &o.final_monitor;
            let rep = o.steady.as_ref().expect("a steady scene");
            SteadyPoint {
                n,
                converged: true,
                diagnosis: None,
                central_nm: f.central_thickness * 1e9,
                minimum_nm: f.minimum_thickness * 1e9,
                max_pressure_ph: o.observables().max_pressure_pa / o.scales.p_h,
                wiggle_ph: f.lateral_wiggle / o.scales.p_h,
                iterations: rep.iterations.clone(),
                wall_s: rep.wall_time_s,
            }
        }
        Err(e) => SteadyPoint {
            n,
            converged: false,
            diagnosis: Some(format!("{e:#}")),
            central_nm: f64::NAN,
            minimum_nm: f64::NAN,
            max_pressure_ph: f64::NAN,
            wiggle_ph: f64::NAN,
            iterations: vec![],
            wall_s: t.elapsed().as_secs_f64(),
        },
    };
    match &p.diagnosis {
        None => println!(
            "  {:>5}  h_c={:9.5} nm  h_min={:8.5} nm  p_max={:.5} p_h  wiggle={:.3} p_h  iterations {:?}  {:6.2} s",
            p.n, p.central_nm, p.minimum_nm, p.max_pressure_ph, p.wiggle_ph, p.iterations, p.wall_s
        ),
        Some(d) => println!("  {:>5}  FAILED after {:.1} s: {d}", p.n, p.wall_s),
    }
    p
}

/// `cargo xtask convergence layer-steady`: grid study of the direct steady solve, its agreement
/// with the marched steady state on 257², and what it does with the model as published.
pub fn steady_study(out: &Path, max_points: usize, compare_march: bool) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(out)?;
    println!("Steady rolling solved directly (rolling-steady: Table 1, 4 sub-steps a cell):");
    let pts: Vec<SteadyPoint> = crate::grid_sizes(max_points)
        .into_iter()
        .map(|n| measure_steady(&steady_scene(n, None)))
        .collect();
    let ok: Vec<&SteadyPoint> = pts.iter().filter(|p| p.converged).collect();
    let mut orders = vec![];
    for w in ok.windows(3) {
        let oc = order3(w[0].central_nm, w[1].central_nm, w[2].central_nm);
        let om = order3(w[0].minimum_nm, w[1].minimum_nm, w[2].minimum_nm);
        println!(
            "  observed order ({} -> {} -> {}): central {oc:.2}, minimum {om:.2}",
            w[0].n, w[1].n, w[2].n
        );
        orders.push(json!({"grids": [w[0].n, w[1].n, w[2].n], "central": oc, "minimum": om}));
    }
    if let [.., a, b] = ok.as_slice() {
        // Richardson with the observed second order of the discretisation (BDF2, sub-steps).
        let rich = |f: fn(&SteadyPoint) -> f64| f(b) + (f(b) - f(a)) / 3.0;
        println!(
            "  Richardson (order 2) from {} and {}: central {:.4} nm, minimum {:.4} nm",
            a.n,
            b.n,
            rich(|p| p.central_nm),
            rich(|p| p.minimum_nm)
        );
    }

    println!("The model as published (coefficient smoothing 0):");
    let raw: Vec<SteadyPoint> = crate::grid_sizes(max_points.min(513))
        .into_iter()
        .map(|n| measure_steady(&steady_scene(n, Some(0.0))))
        .collect();

    let mut comparison = serde_json::Value::Null;
    if compare_march {
        let n = 257.min(max_points);
        println!(
            "Against the marched steady state on {n}² (implicit, n_t = 10, rolling-from-uniform):"
        );
        let m = measure(n, Scheme::Implicit, 10.0)?;
        let d = ok.iter().find(|p| p.n == n).expect("the steady grid study covers it");
        // The marched run stops when h_c, h_min change < 1e-3 l0 over 0.5 a of travel: its
        // films are known to ~1e-3 l0 = 0.025 nm, which bounds any comparison with it.
        let bound_nm = 1e-3 * 25.0;
        let rel = |a: f64, b: f64| (a - b) / b;
        println!(
            "  h_c: steady {:.4} nm, marched {:.4} nm ({:+.3}%); h_min: {:.4} vs {:.4} nm ({:+.2}%); p_max: {:.5} vs {:.5} p_h; marched steady tolerance {bound_nm} nm; wall {:.2} s vs {:.1} s",
            d.central_nm,
            m.central_nm,
            100.0 * rel(d.central_nm, m.central_nm),
            d.minimum_nm,
            m.minimum_nm,
            100.0 * rel(d.minimum_nm, m.minimum_nm),
            d.max_pressure_ph,
            m.max_pressure_ph,
            d.wall_s,
            m.wall_s
        );
        comparison =
            json!({"grid": n, "steady": d, "marched": m, "marched_tolerance_nm": bound_nm});
    }
    let png = out.join("layer_steady_convergence.png");
    let vs_n = |pts: &[&SteadyPoint], pick: fn(&SteadyPoint) -> f64, label: &str| {
        Series::new(label, pts.iter().map(|p| (p.n as f64, pick(p))).collect(), Mark::LinePoints)
    };
    let raw_ok: Vec<&SteadyPoint> = raw.iter().filter(|p| p.converged).collect();
    plot::charts(
        &png,
        &[
            Panel::new(
                "Direct steady solve: grid convergence",
                "points per side",
                "layer thickness [nm]",
                vec![
                    vs_n(&ok, |p| p.central_nm, "central"),
                    vs_n(&ok, |p| p.minimum_nm, "minimum"),
                    vs_n(&raw_ok, |p| p.central_nm, "central, as published"),
                    vs_n(&raw_ok, |p| p.minimum_nm, "minimum, as published"),
                ],
            )
            .legend(SeriesLabelPosition::MiddleRight),
            Panel::new(
                "Cost and lateral wiggle",
                "points per side",
                "wall time [s] / wiggle [p_h]",
                vec![
                    vs_n(&ok, |p| p.wall_s, "wall time [s]"),
                    vs_n(&ok, |p| p.wiggle_ph, "wiggle, smoothing 0.02 a"),
                    vs_n(&raw_ok, |p| p.wiggle_ph, "wiggle, as published"),
                ],
            )
            .log_log()
            .legend(SeriesLabelPosition::UpperLeft),
        ],
        "rolling-steady (Table 1, u1 = 0.01 m/s), steady solve: BDF2 along x, 4 sub-steps a cell, strain tolerance 1e-5",
    )?;
    let json_path = out.join("layer_steady_convergence.json");
    std::fs::write(
        &json_path,
        serde_json::to_string_pretty(&json!({
            "grid_study": pts, "observed_orders": orders, "as_published": raw,
            "against_march": comparison,
        }))? + "\n",
    )?;
    let page = steady_page(max_points, &pts, &raw, &orders, &comparison)?;
    Ok(vec![png, json_path, page])
}

/// The direct steady solve's study as a measured page (`docs/measured/layer-steady.md`).
fn steady_page(
    max_points: usize,
    pts: &[SteadyPoint],
    raw: &[SteadyPoint],
    orders: &[serde_json::Value],
    against: &serde_json::Value,
) -> Result<PathBuf> {
    use crate::measured::Table;
    let table = |pts: &[SteadyPoint]| {
        let mut t = Table::new(&[
            "grid",
            "answer",
            "h_c [nm]",
            "h_min [nm]",
            "p_max / p_h",
            "row-to-row wiggle / p_h",
            "iterations (finest)",
            "wall [s]",
        ]);
        for p in pts {
            t.rows.push(vec![
                format!("{}²", p.n),
                if p.converged {
                    "converged".to_string()
                } else {
                    format!(
                        "failed: {}",
                        p.diagnosis.as_deref().unwrap_or("").chars().take(80).collect::<String>()
                    )
                },
                format!("{:.4}", p.central_nm),
                format!("{:.4}", p.minimum_nm),
                format!("{:.4}", p.max_pressure_ph),
                format!("{:.3}", p.wiggle_ph),
                p.iterations.last().map_or(String::new(), |i| i.1.to_string()),
                format!("{:.2}", p.wall_s),
            ]);
        }
        t
    };
    let mut ord = Table::new(&["grids", "order of h_c", "order of h_min"]);
    for o in orders {
        let f = |k: &str| format!("{:.2}", o[k].as_f64().unwrap_or(f64::NAN));
        let g = o["grids"].as_array().map_or(String::new(), |g| {
            g.iter().map(|n| format!("{n}²")).collect::<Vec<_>>().join(", ")
        });
        ord.rows.push(vec![g, f("central"), f("minimum")]);
    }
    let mut vs = Table::new(&["grid", "", "h_c [nm]", "h_min [nm]", "p_max / p_h", "wall [s]"]);
    for (label, key) in [("steady solve", "steady"), ("march (implicit, n_t = 10)", "marched")] {
        let v = &against[key];
        if v.is_null() {
            continue;
        }
        let f = |k: &str, d: usize| format!("{:.*}", d, v[k].as_f64().unwrap_or(f64::NAN));
        vs.rows.push(vec![
            format!("{}²", against["grid"]),
            label.to_string(),
            f("central_nm", 4),
            f("minimum_nm", 4),
            f("max_pressure_ph", 5),
            f("wall_s", 2),
        ]);
    }
    crate::measured::write(
        "layer-steady",
        "The layer model's steady rolling, solved directly",
        &format!("cargo xtask convergence layer-steady --max-points {max_points}"),
        "`rolling-steady` (Table 1, `u1` = 0.01 m/s, coefficient smoothing 0.02 a, 4 sub-steps a \
         cell, strain tolerance 1e-5) solved directly on each grid, its nested grids included; \
         the model as published (smoothing 0); and the marched steady state on 257² beside it \
         (the march stops when its films change by less than 1e-3 `l0` = 0.025 nm over 0.5 a, \
         which bounds the comparison).",
        &[
            ("The grid study", &table(pts)),
            ("Observed orders", &ord),
            ("The model as published (smoothing 0)", &table(raw)),
            ("Against the march", &vs),
        ],
    )
}

/// `cargo xtask bench` (steady part): the direct steady solve per grid on 1 and 2 threads.
pub fn bench_steady(max: usize) -> Result<Vec<serde_json::Value>> {
    println!("Direct steady rolling (rolling-steady), whole solve including its nested grids:");
    println!(
        "{:>5} {:>8} {:>10} {:>10}  iterations (n, its)",
        "n", "threads", "wall [s]", "per point [us]"
    );
    let mut rows = vec![];
    for n in crate::grid_sizes(max) {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
            let p = pool.install(|| measure_steady(&steady_scene(n, None)));
            println!(
                "{:>5} {:>8} {:>10.3} {:>10.2}  {:?}",
                n,
                threads,
                p.wall_s,
                p.wall_s / (n * n) as f64 * 1e6,
                p.iterations
            );
            rows.push(json!({"n": n, "threads": threads, "wall_s": p.wall_s, "iterations": p.iterations, "converged": p.converged}));
        }
    }
    println!(
        "Targets (single thread): 257^2 <= 2 s, 513^2 <= 8 s, 1025^2 <= 40 s (--max-points 1025)"
    );
    Ok(rows)
}
