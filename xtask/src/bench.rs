//! Timings of the contact core: deformation apply, dry solve from a flat start, warm-started
//! solves after a small change of the gap (what the layer model does every time step).

use anyhow::{Context, Result};
use ehl_core::dry::extrapolate;
use ehl_core::{DryProblem, DrySettings, DrySolver, Grid, Start};
use ndarray::Array2;
use std::path::Path;
use std::time::Instant;

/// Median wall time of `reps` runs of `f` [s].
fn median_time(reps: usize, mut f: impl FnMut()) -> f64 {
    let ts: Vec<f64> = (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    median(&ts)
}

struct Row {
    n: usize,
    threads: usize,
    /// Building the solver: every level's influence kernel and its spectrum [s].
    setup_s: f64,
    apply_ms: f64,
    apply_per_nlogn_ns: f64,
    flat_s: f64,
    flat_its: usize,
    coarse_its: Vec<(usize, usize)>,
    warm_ms: f64,
    warm_its: f64,
    extrap_ms: f64,
    extrap_its: f64,
}

fn bench_grid(n: usize, threads: usize) -> Result<Row> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    pool.install(|| {
        let g = Grid::square(n, 1.25);
        let setup_s = median_time(if n <= 257 { 7 } else { 3 }, || {
            std::hint::black_box(DrySolver::new(g, DrySettings::default()));
        });
        let solver = DrySolver::new(g, DrySettings::default());
        let nn = (n * n) as f64;
        let reps = if n <= 257 { 21 } else { 7 };
        let p0 = g.field(ehl_core::hertz::pressure);
        let mut w = g.zeros();
        let apply = median_time(reps, || solver.operator().apply(p0.view(), w.view_mut()));

        let load = 2.0 * std::f64::consts::PI / 3.0;
        let f = g.paraboloid();
        let prob = DryProblem { rigid_gap: f.view(), compliance: None, load };
        let mut p = g.zeros();
        let mut rep = None;
        let flat = median_time(if n <= 257 { 7 } else { 3 }, || {
            rep = Some(solver.solve(&prob, &mut p, &mut w, Start::Flat).unwrap());
        });
        let rep = rep.unwrap();

        // A layer-model-like sequence: a bump of the layer's relative height (l0/(a²/R) ≈ 0.013
        // for the seed) moving by a tenth of a cell per step, re-solved from the last pressure
        // (plain warm start) or from the linear extrapolation of the last two.
        let steps = 12;
        let bump = |s: usize| -> Array2<f64> {
            let shift = -0.5 + 0.1 * g.dx() * s as f64;
            &f + &g.field(|x, y| 0.013 * (-((x - shift).powi(2) + y * y) / 0.02).exp())
        };
        let gaps: Vec<Array2<f64>> = (0..=steps).map(bump).collect();
        let (warm, warm_its) = sequence(&solver, &gaps, load, false);
        let (ex, ex_its) = sequence(&solver, &gaps, load, true);
        Ok(Row {
            n,
            threads,
            setup_s,
            apply_ms: apply * 1e3,
            apply_per_nlogn_ns: apply / (nn * nn.log2()) * 1e9,
            flat_s: flat,
            flat_its: rep.iterations,
            coarse_its: rep.coarse_iterations,
            warm_ms: warm * 1e3,
            warm_its,
            extrap_ms: ex * 1e3,
            extrap_its: ex_its,
        })
    })
}

/// Solves `gaps[0]` from flat, then each following gap warm-started from the last pressure
/// (or its linear extrapolation); returns the mean time [s] and iterations per warm solve.
fn sequence(solver: &DrySolver, gaps: &[Array2<f64>], load: f64, extrap: bool) -> (f64, f64) {
    let g = *solver.grid();
    let (mut p, mut w) = (g.zeros(), g.zeros());
    let prob0 = DryProblem { rigid_gap: gaps[0].view(), compliance: None, load };
    solver.solve(&prob0, &mut p, &mut w, Start::Flat).unwrap();
    let mut prev = p.clone();
    let (mut time, mut its) = (0.0, 0usize);
    for gap in &gaps[1..] {
        let prob = DryProblem { rigid_gap: gap.view(), compliance: None, load };
        let t = Instant::now();
        let mut start = if extrap { extrapolate(&p, &prev) } else { p.clone() };
        let r = solver.solve(&prob, &mut start, &mut w, Start::Warm).unwrap();
        time += t.elapsed().as_secs_f64();
        its += r.iterations;
        prev = std::mem::replace(&mut p, start);
    }
    let steps = (gaps.len() - 1) as f64;
    (time / steps, its as f64 / steps)
}

/// One part of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Part {
    Contact,
    Layer,
    Reynolds,
    /// The starved Reynolds solve against the flooded one (`docs/measured/bench-starved.md`).
    Starved,
    /// Reynolds time steps on the seed's contact, rolling and at rest after a stop
    /// (`docs/measured/bench-steps.md`).
    Steps,
    /// The seed's stop on 257², the Reynolds side to its steady squeeze
    /// (`docs/measured/bench-squeeze.md`).
    Squeeze,
    /// Comparison scenes with their models at once and one at a time
    /// (`docs/measured/bench-compare.md`).
    Compare,
    /// One transit of a random rough surface through the seed's contact, both models
    /// (`docs/measured/bench-rough.md`).
    Rough,
    /// The error estimate's cost against the solve alone, every model on the seed's 257²
    /// (`docs/measured/bench-estimate.md`).
    Estimate,
    /// The Reynolds solver's dry limits on the seed's 257²: vanishing speed, almost no oil
    /// (`docs/measured/bench-dry-limit.md`).
    DryLimit,
}

pub fn run(out: &Path, max: usize, only: Option<Part>) -> Result<()> {
    std::fs::create_dir_all(out)?;
    let wanted = |p: Part| only.is_none_or(|o| o == p);
    if wanted(Part::Contact) {
        contact(out, max)?;
    }
    if wanted(Part::Layer) {
        let layer = crate::layer::bench(max)?;
        let f = out.join("bench_layer.json");
        std::fs::write(&f, serde_json::to_string_pretty(&layer)? + "\n")?;
        println!("wrote {}", f.display());
        let steady = crate::layer::bench_steady(max)?;
        let f = out.join("bench_layer_steady.json");
        std::fs::write(&f, serde_json::to_string_pretty(&steady)? + "\n")?;
        println!("wrote {}", f.display());
    }
    if wanted(Part::Reynolds) {
        let reynolds = crate::reynolds::bench(max)?;
        let f = out.join("bench_reynolds.json");
        std::fs::write(&f, serde_json::to_string_pretty(&reynolds)? + "\n")?;
        println!("wrote {}", f.display());
    }
    if wanted(Part::Starved) {
        println!(
            "wrote {}",
            crate::starvation::bench(max, if crate::quick() { 1 } else { 3 })?.display()
        );
    }
    // The seed's grid, quickly 65² (the steps 129²: the smallest of their table): the code
    // paths of the parts on the seed's contact.
    let seed_n = if crate::quick() { 65 } else { crate::seed_grid(max) };
    if wanted(Part::Steps) {
        steps(crate::seed_grid(max))?;
    }
    if wanted(Part::Squeeze) {
        squeeze(seed_n)?;
    }
    if wanted(Part::Compare) {
        compare(if crate::quick() { 1 } else { 3 })?;
    }
    if wanted(Part::Rough) {
        rough(seed_n, if crate::quick() { 1 } else { 3 })?;
    }
    if wanted(Part::Estimate) {
        estimate(seed_n, if crate::quick() { 1 } else { 3 })?;
    }
    if wanted(Part::DryLimit) {
        println!("wrote {}", crate::contact::bench(seed_n)?.display());
    }
    Ok(())
}

/// The error estimate ([`ehl_workbench::accuracy::estimate`]: the same model on half and a
/// quarter of the points per side) against the solve alone, each model of the seed's comparison
/// and the textbook `M = 20, L = 10` contact on `n`², the median of `runs` each; what the
/// estimate found.
fn estimate(n: usize, runs: usize) -> Result<std::path::PathBuf> {
    use ehl_workbench::{accuracy, run_scene};
    let mut t = crate::measured::Table::new(&[
        "scene",
        "model",
        "grid",
        "solve [s]",
        "estimate [s]",
        "estimate / solve",
        "grids answering",
        "h_c error",
    ]);
    let seed = ehl_scene::builtin("seed")?.with_points(n)?;
    let mut cases: Vec<(String, ehl_scene::Scene)> =
        seed.models().into_iter().map(|m| ("seed".to_string(), seed.for_model(m))).collect();
    cases
        .push(("reynolds-m20-l10".into(), ehl_scene::builtin("reynolds-m20-l10")?.with_points(n)?));
    for (name, scene) in cases {
        let (mut solve, mut est) = (vec![], vec![]);
        let mut last = None;
        for _ in 0..runs {
            let clock = Instant::now();
            let o = run_scene(&scene)?;
            solve.push(clock.elapsed().as_secs_f64());
            let clock = Instant::now();
            let e = accuracy::estimate(&scene, o.as_ref());
            est.push(clock.elapsed().as_secs_f64());
            last = Some(e);
        }
        let e = last.context("at least one run")?;
        let (s, x) = (median(&solve), median(&est));
        let model = scene.model().map_or("", |m| m.name());
        println!("{name} {model} {n}²: solve {s:.2} s, estimate {x:.2} s ({:.0} %)", 100.0 * x / s);
        t.rows.push(vec![
            name,
            model.into(),
            format!("{n}²"),
            format!("{s:.2}"),
            format!("{x:.2}"),
            format!("{:.0} %", 100.0 * x / s),
            e.grids.iter().map(|g| format!("{g}²")).collect::<Vec<_>>().join(", "),
            e.errors[0].map_or("—".into(), |b| format!("{:.2} %", 100.0 * b.relative)),
        ]);
    }
    crate::measured::write(
        "bench-estimate",
        "The error estimate's cost",
        &format!("cargo xtask bench --only estimate --max-points {n}"),
        "Each model's answer on the scene's grid, then its error estimate: the same model on half \
         and a quarter of the points per side over the same domain, the two at once, a coarser \
         grid wider than the model's answer can exist on not run; a Reynolds coarse grid of a \
         steady answer starts from that answer (its points a subset of the finer grid's), held \
         to a film settled within 5e-4 a cycle and a load within 1e-5, its first attempt and 25 \
         cycles at most. Wall times on 2 cores, the median of the runs; \
         the grids that answered and the central film's estimated error (relative).",
        &[("Solve and estimate", &t)],
    )
}

/// The deformation operator and the dry solver.
fn contact(out: &Path, max: usize) -> Result<()> {
    println!("Contact core benchmark (median wall times; N = n^2 points; tolerance 1e-8)");
    println!(
        "{:>5} {:>3} {:>9} {:>10} {:>14} {:>10} {:>5} {:>10} {:>6} {:>11} {:>6}  nested start (n, its)",
        "n",
        "thr",
        "setup[s]",
        "apply[ms]",
        "apply/NlogN[ns]",
        "flat[s]",
        "its",
        "warm[ms]",
        "its",
        "extrap[ms]",
        "its"
    );
    let mut rows = vec![];
    for threads in [1, 2] {
        for n in crate::grid_sizes(max) {
            let r = bench_grid(n, threads)?;
            println!(
                "{:>5} {:>3} {:>9.4} {:>10.3} {:>14.3} {:>10.4} {:>5} {:>10.2} {:>6.1} {:>11.2} {:>6.1}  {:?}",
                r.n,
                r.threads,
                r.setup_s,
                r.apply_ms,
                r.apply_per_nlogn_ns,
                r.flat_s,
                r.flat_its,
                r.warm_ms,
                r.warm_its,
                r.extrap_ms,
                r.extrap_its,
                r.coarse_its
            );
            rows.push(r);
        }
    }
    println!(
        "Targets (single thread): apply 257^2 <= 3 ms; flat solve 257^2 <= 0.06 s, 513^2 <= 0.3 s"
    );
    let json: Vec<_> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "n": r.n, "threads": r.threads, "setup_s": r.setup_s, "apply_ms": r.apply_ms,
                "apply_per_nlogn_ns": r.apply_per_nlogn_ns, "flat_solve_s": r.flat_s,
                "flat_iterations": r.flat_its, "nested_iterations": r.coarse_its,
                "warm_solve_ms": r.warm_ms, "warm_iterations": r.warm_its,
                "extrapolated_solve_ms": r.extrap_ms, "extrapolated_iterations": r.extrap_its,
            })
        })
        .collect();
    let f = out.join("bench_contact.json");
    std::fs::write(&f, serde_json::to_string_pretty(&json)? + "\n")?;
    println!("wrote {}", f.display());
    let mut t = crate::measured::Table::new(&[
        "n",
        "threads",
        "setup [s]",
        "apply [ms]",
        "apply / N log N [ns]",
        "flat solve [s]",
        "iterations",
        "warm solve [ms]",
        "iterations",
        "extrapolated [ms]",
        "iterations",
    ]);
    for r in &rows {
        t.rows.push(vec![
            r.n.to_string(),
            r.threads.to_string(),
            format!("{:.4}", r.setup_s),
            format!("{:.3}", r.apply_ms),
            format!("{:.3}", r.apply_per_nlogn_ns),
            format!("{:.4}", r.flat_s),
            r.flat_its.to_string(),
            format!("{:.2}", r.warm_ms),
            format!("{:.1}", r.warm_its),
            format!("{:.2}", r.extrap_ms),
            format!("{:.1}", r.extrap_its),
        ]);
    }
    crate::measured::write(
        "bench-contact",
        "The contact core's speed",
        &format!("cargo xtask bench --only contact --max-points {max}"),
        "Median wall times of the deformation operator (one FFT convolution) and the dry contact \
         solver on `n²` grids over `[-1.25, 1.25]²` a, tolerance 1e-8: from a flat start, warm \
         from the last answer after a small change of the gap, and from the extrapolation of the \
         last two answers (what the layer model does every time step). Targets, single thread: \
         apply on 257² ≤ 3 ms; a flat solve on 257² ≤ 0.06 s, on 513² ≤ 0.3 s.",
        &[("Median wall times (`N = n²` points)", &t)],
    )?;
    Ok(())
}

/// Reynolds time steps in the seed's regime: the contact of Table 1 on its own domain
/// `[−1.25, 1.25]²`, flooded and fed 25 nm, from the steady solve: 20 steps rolling at one step
/// a cell, then 20 at rest (a sudden stop; steps of one cell's transit at the rolling speed,
/// 0.26 ms, as error control starts them). Wall time and cycles per step, on 129² up to `max`.
fn steps(max: usize) -> Result<std::path::PathBuf> {
    use ehl_reynolds::{ReynoldsSettings, ReynoldsSolver};
    let mut t = crate::measured::Table::new(&[
        "n",
        "supply",
        "motion",
        "step [s]",
        "cycles a step",
        "steady solve [s]",
    ]);
    let prm = ehl_reynolds::ReynoldsParams::from_si(
        &ehl_core::SEED_CONTACT,
        &ehl_core::SEED_LUBRICANT,
        0.02,
        ehl_reynolds::ViscosityLaw::Roelands,
        ehl_reynolds::DensityLaw::DowsonHigginson,
    );
    for n in [129, 257].into_iter().filter(|&n| n <= max) {
        for fed in [false, true] {
            let grid = ehl_core::Grid::new(n, n, (-1.25, 1.25), (-1.25, 1.25));
            let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
            if fed {
                let h_oil = 25e-9 / prm.scales.delta;
                s.set_supply(Some(&move |_y| h_oil));
            }
            let supply = if fed { "25 nm" } else { "flooded" };
            let failed = |t: &mut crate::measured::Table, what: String| {
                println!("{n}² {supply}: {what}");
                t.rows.push(vec![
                    n.to_string(),
                    supply.into(),
                    what,
                    "".into(),
                    "".into(),
                    "".into(),
                ]);
            };
            let steady = match s.solve(&mut |_| {}) {
                Ok(r) => r,
                Err(e) => {
                    failed(&mut t, format!("steady solve failed: {e}"));
                    continue;
                }
            };
            let dt = grid.dx();
            for (motion, speed) in [("rolling", 1.0), ("at rest", 0.0)] {
                s.set_speed(speed);
                let (clock, mut cycles) = (Instant::now(), 0);
                let mut ok = true;
                for k in 0..20 {
                    match s.step(dt, &mut |_| {}) {
                        Ok(r) => cycles += r.cycles,
                        Err(e) => {
                            failed(&mut t, format!("{motion}: step {} failed: {e}", k + 1));
                            ok = false;
                            break;
                        }
                    }
                }
                if !ok {
                    break;
                }
                let per = clock.elapsed().as_secs_f64() / 20.0;
                println!(
                    "{n}² {} {motion}: {per:.3} s a step, {:.1} cycles",
                    if fed { "25 nm" } else { "flooded" },
                    cycles as f64 / 20.0
                );
                t.rows.push(vec![
                    n.to_string(),
                    if fed { "25 nm".into() } else { "flooded".into() },
                    motion.into(),
                    format!("{per:.3}"),
                    format!("{:.1}", cycles as f64 / 20.0),
                    format!("{:.2}", steady.wall_time_s),
                ]);
            }
        }
    }
    let passage = dent_passage(max.min(257), prm)?;
    crate::measured::write(
        "bench-steps",
        "Reynolds time steps in the seed's regime",
        &format!("cargo xtask bench --only steps --max-points {max}"),
        "The seed's contact (Table 1, u1 = 0.01 m/s) on its own domain [-1.25, 1.25]² a, from \
         the steady solve: 20 steps rolling at one step a cell, then 20 at rest after a sudden \
         stop (steps of one cell's transit at the rolling speed, 0.26 ms on 129², as error \
         control starts them); mean wall time and cycles a step. The target: a step on \
         257² in the seed's regime at 0.04 s. Second table: the seed's shallow dent (31 nm, \
         W = 0.1 a) passing the contact fed 25 nm, at one step a cell from x = −1.25 a to 1.25 a, \
         with each variant's largest deviation from the same march converged tightly (film \
         1e-6 a cycle, load 1e-8, oil 1e-4) over the passage, relative to each \
         quantity's largest value: what a step's stopping rule leaves, accumulated. The last \
         row is the time discretisation's error for scale (two steps a cell against one, both \
         tight).",
        &[("Time steps", &t), ("A dent passage: speed against accuracy", &passage)],
    )
}

/// The seed's stop (`stop-compare`, fed 25 nm: steady rolling, a sudden stop at 5 ms, rest
/// under the load until the scene's steady rule or 5 s), the Reynolds side alone on `n`²,
/// with the relaxation's threshold at rest as it was (1) and as the scene sets it: wall time
/// of the whole run (steady solve and march), steps, rejected steps, and where the squeeze
/// ends. The target: the full squeeze on 257² in 2 min.
fn squeeze(n: usize) -> Result<std::path::PathBuf> {
    use ehl_workbench::reynolds::run_reynolds;
    let mut t = crate::measured::Table::new(&[
        "n",
        "threshold at rest",
        "wall [s]",
        "steps",
        "rejected",
        "cycles a step",
        "end [s]",
        "lobes closed at [s]",
        "central film at the end [nm]",
        "contact's share of the load",
    ]);
    let base = ehl_scene::load("stop-compare")?.for_model(ehl_scene::Model::Reynolds);
    let own = base.reynolds.as_ref().map_or(1.0, |r| r.solver.relax.transient_threshold_at_rest);
    for threshold in [1.0, own] {
        let mut scene = base.clone();
        scene.grid = ehl_scene::GridSpec { nx: n, ny: n };
        if crate::quick() {
            // Quickly: the stop and 15 ms at rest.
            if let Some(r) = scene.run.as_mut() {
                r.stop.max_time_s = Some(0.02);
            }
        }
        if let Some(r) = scene.reynolds.as_mut() {
            r.solver.relax.transient_threshold_at_rest = threshold;
        }
        let clock = Instant::now();
        let o = run_reynolds(&scene)?;
        let wall = clock.elapsed().as_secs_f64();
        let Some(tr) = &o.transient else { anyhow::bail!("stop-compare did not march") };
        let steps = tr.rows.len().saturating_sub(1);
        let cycles: usize = tr.rows.iter().map(|r| r.cycles).sum();
        let closed = tr.rows.iter().find(|r| r.minimum_film_m <= 0.0).map(|r| r.t_s);
        let end = tr.rows.last().map_or(0.0, |r| r.t_s);
        let last = tr.rows.last();
        println!(
            "{n}² stop, threshold at rest {threshold}: {wall:.1} s, {steps} steps ({} rejected)",
            tr.rejected_steps
        );
        t.rows.push(vec![
            n.to_string(),
            format!("{threshold}"),
            format!("{wall:.1}"),
            steps.to_string(),
            tr.rejected_steps.to_string(),
            format!("{:.2}", cycles as f64 / steps.max(1) as f64),
            format!("{end:.3}"),
            closed.map_or("open".into(), |t| format!("{t:.3}")),
            last.map_or(String::new(), |r| format!("{:.3}", r.central_film_m * 1e9)),
            last.map_or(String::new(), |r| format!("{:.1e}", r.contact_load_share)),
        ]);
    }
    crate::measured::write(
        "bench-squeeze",
        "The seed's stop on 257²: the Reynolds squeeze to its end",
        &format!("cargo xtask bench --only squeeze --max-points {n}"),
        "stop-compare's Reynolds side alone (Table 1, fed 25 nm, [-1.25, 1.25]² a): the steady \
         solve, 5 ms rolling at two steps a cell, a sudden stop, then error-controlled steps \
         (tolerance 1e-3) at rest until the scene's steady rule (1e-3 over 0.5 s) or 5 s. The \
         relaxation's threshold for the time term at rest \
         (`reynolds.solver.advanced.relax.transient_threshold_at_rest`) as it was (1) and as the scene \
         sets it. The target: the full squeeze on 257² within 2 min.",
        &[("The full squeeze", &t)],
    )
}

/// Whole comparisons on their own grids, `runs` times each way, the two schedules alternating so
/// that a change in the cores' load falls on both: the wall of the whole comparison with the
/// models at once (the default) and one at a time, with each model's own wall one at a time
/// (from the last run).
/// The target: `dent-shallow-compare` within 15 s on 2 cores.
fn compare(runs: usize) -> Result<std::path::PathBuf> {
    use ehl_workbench::compare::{self, Schedule};
    let mut t = crate::measured::Table::new(&[
        "scene",
        "grid",
        "at once: median [s]",
        "at once: range [s]",
        "one at a time: median [s]",
        "one at a time: range [s]",
        "ratio",
        "each model alone [s]",
    ]);
    let names: &[&str] = if crate::quick() { &["seed"] } else { &["dent-shallow-compare", "seed"] };
    for &name in names {
        let mut scene = ehl_scene::builtin(name)?;
        scene = scene.with_points(crate::scene_points(&scene))?;
        scene.outputs.figures = false;
        let (mut together, mut apart) = (vec![], vec![]);
        let mut own = String::new();
        for run in 0..runs {
            for schedule in [Schedule::SideBySide, Schedule::OneAtATime] {
                let c = compare::run_with(&scene, schedule);
                if !c.all_converged() {
                    anyhow::bail!("{name}: not every model answered\n{}", c.table());
                }
                println!("{name} run {run}, {}: {:.2} s", schedule.name(), c.total_wall_time_s);
                match schedule {
                    Schedule::SideBySide => together.push(c.total_wall_time_s),
                    Schedule::OneAtATime => {
                        apart.push(c.total_wall_time_s);
                        own = c
                            .entries
                            .iter()
                            .map(|e| format!("{} {:.2}", e.name(), e.wall_time_s))
                            .collect::<Vec<_>>()
                            .join(", ");
                    }
                }
            }
        }
        let range = |v: &[f64]| {
            let (lo, hi) = v.iter().fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
            format!("{lo:.2}–{hi:.2}")
        };
        let (m1, m2) = (median(&together), median(&apart));
        let g = scene.grid();
        t.rows.push(vec![
            name.into(),
            format!("{}²", g.nx),
            format!("{m1:.2}"),
            range(&together),
            format!("{m2:.2}"),
            range(&apart),
            format!("{:.2}", m1 / m2),
            own,
        ]);
    }
    crate::measured::write(
        "bench-compare",
        "Comparisons: the models at once and one at a time",
        "cargo xtask bench --only compare",
        &format!(
            "`ehl compare`'s run of every model of a built-in comparison scene (no figures, \
             nothing written), {runs} times with the models at once (the default, each a task \
             on the one rayon pool) and {runs} times one after the other, alternating. Each \
             model alone keeps fewer than the two cores busy (serial line relaxation and march \
             bookkeeping), so at once the comparison takes about its slowest model's time. \
             The target: dent-shallow-compare within 15 s on 2 cores."
        ),
        &[("Whole comparisons", &t)],
    )
}

/// One transit of `roughness-compare`'s random surface through the seed's contact on `n`²
/// (the surfaces travel the domain's length once, one step a cell, from the steady start),
/// both models, `runs` times at once and one at a time, alternating. The target: within 60 s
/// on 2 cores on 257².
fn rough(n: usize, runs: usize) -> Result<std::path::PathBuf> {
    use ehl_workbench::compare::{self, Schedule};
    let mut scene = ehl_scene::builtin("roughness-compare")?.with_points(n)?;
    scene.outputs.figures = false;
    let g = scene.grid();
    let a = ehl_core::HertzScales::new(&scene.conditions.contact()).a;
    let u = scene.conditions.rolling_velocity_m_s.context("roughness-compare rolls")?;
    let transit_s = (g.x_max - g.x_min) * a / u;
    let run = scene.run.as_mut().context("roughness-compare marches")?;
    run.stop.max_time_s = Some(transit_s);
    run.snapshots_s = vec![transit_s];
    // One step a cell: the transit's steps.
    let steps = g.nx - 1;
    let mut t = crate::measured::Table::new(&[
        "grid",
        "steps",
        "at once: median [s]",
        "one at a time: median [s]",
        "each model alone [s]",
        "per step, each model [ms]",
    ]);
    let (mut together, mut apart, mut own, mut per_step) =
        (vec![], vec![], "—".to_string(), "—".to_string());
    // Quickly, the models at once only (the default; CI's check that the bench runs).
    let schedules: &[Schedule] = if crate::quick() {
        &[Schedule::SideBySide]
    } else {
        &[Schedule::SideBySide, Schedule::OneAtATime]
    };
    for run in 0..runs {
        for &schedule in schedules {
            let c = compare::run_with(&scene, schedule);
            if !c.all_converged() {
                anyhow::bail!("roughness-compare on {n}²: not every model answered\n{}", c.table());
            }
            println!("rough {n}² run {run}, {}: {:.2} s", schedule.name(), c.total_wall_time_s);
            match schedule {
                Schedule::SideBySide => together.push(c.total_wall_time_s),
                Schedule::OneAtATime => {
                    apart.push(c.total_wall_time_s);
                    let each = |f: &dyn Fn(&compare::Entry) -> String| {
                        c.entries
                            .iter()
                            .map(|e| format!("{} {}", e.name(), f(e)))
                            .collect::<Vec<_>>()
                            .join(", ")
                    };
                    own = each(&|e| format!("{:.2}", e.wall_time_s));
                    per_step = each(&|e| format!("{:.0}", 1e3 * e.wall_time_s / steps as f64));
                }
            }
        }
    }
    t.rows.push(vec![
        format!("{n}²"),
        steps.to_string(),
        format!("{:.2}", median(&together)),
        if apart.is_empty() { "—".into() } else { format!("{:.2}", median(&apart)) },
        own,
        per_step,
    ]);
    crate::measured::write(
        "bench-rough",
        "A rough surface through the contact",
        &format!("cargo xtask bench --only rough --max-points {n}"),
        &format!(
            "`roughness-compare` (isotropic random roughness, Rq 3 nm, correlation length 20 µm, \
             through the seed's contact fed 25 nm) on {n}², stopped after one transit of the \
             domain ({:.4} s: the surfaces travel its 2.5 a once, one step a cell), no error \
             estimate, no figures; {runs} runs with both models at once and one at a time, \
             alternating; wall times on 2 cores, medians. The target: within 60 s on 257².",
            transit_s
        ),
        &[("One transit", &t)],
    )
}

/// The median of `v` (at least one value).
fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The seed's shallow dent passing the seed's contact fed 25 nm on `n`², one step a cell:
/// the default steps, the steps with the steady solve's extra mass-conserving passes, and
/// looser or tighter V-cycles, each against the tightly converged march. The dent and the
/// supply are `dent-shallow-compare`'s.
fn dent_passage(n: usize, prm: ehl_reynolds::ReynoldsParams) -> Result<crate::measured::Table> {
    use ehl_reynolds::{ReynoldsSettings, ReynoldsSolver};
    let grid = ehl_core::Grid::new(n, n, (-1.25, 1.25), (-1.25, 1.25));
    let scene = ehl_scene::builtin("dent-shallow-compare")?;
    let dent = scene.relief(prm.scales.a)?.dents[0];
    let supply = scene.supply.as_ref().context("dent-shallow-compare has a supply")?;
    let h_oil = supply.thickness_m / prm.scales.delta;
    // One march, its steady start solved with `steady` and its steps with `steps`: the central
    // and minimum film and the pressure maximum after every cell's travel, the wall time and
    // cycles a step.
    let march = |steady: ReynoldsSettings,
                 steps: ReynoldsSettings,
                 per_cell: usize|
     -> Result<(Vec<[f64; 3]>, f64, f64)> {
        let mut s = ReynoldsSolver::new(grid, prm, steady);
        s.set_supply(Some(&move |_y| h_oil));
        s.solve(&mut |_| {}).map_err(|e| anyhow::anyhow!("steady solve: {e}"))?;
        s.settings = steps;
        let dt = grid.dx() / per_cell as f64;
        // Quickly: the dent's first eight cells of travel.
        let cells = if crate::quick() { 8 } else { (2.5 / grid.dx()).round() as usize };
        let (clock, mut cycles, mut out) = (Instant::now(), 0, vec![]);
        for k in 1..=cells * per_cell {
            let xc = dent.x_start_a + k as f64 * dt;
            let delta = prm.scales.delta;
            s.set_extra_gap(move |x, y| dent.gap(x, y, xc, delta));
            cycles += s
                .step(dt, &mut |_| {})
                .map_err(|e| anyhow::anyhow!("step {k} (dent at {xc:.3} a): {e}"))?
                .cycles;
            if k % per_cell == 0 {
                let (hc, hmin) = s.films();
                let pmax = s.pressure().iter().cloned().fold(0.0, f64::max);
                out.push([hc, hmin, pmax]);
            }
        }
        let steps = (cells * per_cell) as f64;
        Ok((out, clock.elapsed().as_secs_f64() / steps, cycles as f64 / steps))
    };
    let tight = ReynoldsSettings {
        film_tolerance: 1e-6,
        load_tolerance: 1e-8,
        mass_tolerance: 1e-4,
        ..ReynoldsSettings::default()
    };
    let (reference, _, _) = march(tight, tight, 1)?;
    let deviation = |run: &[[f64; 3]], q: usize| {
        let top = reference.iter().map(|r| r[q].abs()).fold(0.0, f64::max);
        let d = run.iter().zip(&reference).map(|(a, b)| (a[q] - b[q]).abs()).fold(0.0, f64::max);
        format!("{:.2} %", 100.0 * d / top)
    };
    let mut t = crate::measured::Table::new(&[
        "steps",
        "step [s]",
        "cycles a step",
        "central film",
        "minimum film",
        "pressure maximum",
    ]);
    let d = ReynoldsSettings::default();
    let variants: [(&str, ReynoldsSettings, usize); 5] = [
        ("default: V(1,1) rolling (V(2,1) at rest), no extra passes", d, 1),
        (
            "with the steady solve's extra passes",
            ReynoldsSettings { step_extra_passes: true, ..d },
            1,
        ),
        (
            "V(2,1) (`step_pre_sweeps: 2`, the default before)",
            ReynoldsSettings { step_pre_sweeps: 2, ..d },
            1,
        ),
        ("V(2,2)", ReynoldsSettings { step_pre_sweeps: 2, post_sweeps: 2, ..d }, 1),
        ("tight, two steps a cell: the time error", tight, 2),
    ];
    for (name, settings, per_cell) in variants {
        let steady = if per_cell > 1 { tight } else { d };
        let row = match march(steady, settings, per_cell) {
            Ok((run, step, cycles)) => {
                println!("{n}² dent passage, {name}: {step:.3} s a step, {cycles:.2} cycles");
                vec![
                    name.to_string(),
                    format!("{step:.3}"),
                    format!("{cycles:.2}"),
                    deviation(&run, 0),
                    deviation(&run, 1),
                    deviation(&run, 2),
                ]
            }
            Err(e) => vec![
                name.to_string(),
                format!("failed: {e}"),
                "".into(),
                "".into(),
                "".into(),
                "".into(),
            ],
        };
        t.rows.push(row);
    }
    Ok(t)
}
