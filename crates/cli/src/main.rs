//! `ehl`: run a scene and write its results.

use anyhow::{Result, bail};
use clap::{Parser, Subcommand};
use ehl_workbench::{Outcome, compare, output};
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "ehl", version, about = "EHL point-contact validation workbench")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What `run` and `compare` take.
#[derive(clap::Args)]
struct RunArgs {
    /// Built-in scene name (see `ehl scenes`) or path to a scene JSON file.
    scene: String,
    /// Output folder (default: out/SCENE, the scene's name); replaced as a whole when the run is done.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Points per side, overriding the scene's grid.
    #[arg(long)]
    grid: Option<usize>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// The accuracy asked of the answer (`2%` or `0.02`): the grid and domain then follow the
    /// accuracy rule (never coarser than the scene's or `--grid`), and an answer whose
    /// estimated error misses it is flagged with the grid that would meet it.
    #[arg(long, value_parser = parse_accuracy)]
    accuracy: Option<f64>,
    /// Skip the error estimate (the answer on half and a quarter of the points per side):
    /// faster, and the answer says it was not checked.
    #[arg(long)]
    no_estimate: bool,
}

/// `2%` or `0.02`: a relative accuracy.
fn parse_accuracy(s: &str) -> Result<f64, String> {
    let (text, scale) = match s.trim().strip_suffix('%') {
        Some(t) => (t.trim(), 0.01),
        None => (s.trim(), 1.0),
    };
    text.parse::<f64>().map(|v| v * scale).map_err(|_| {
        format!("`{s}` is not an accuracy: give a percentage (`2%`) or a fraction (`0.02`)")
    })
}

/// What `compare` takes: `run`'s arguments and the schedule.
#[derive(clap::Args)]
struct CompareArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Run the models one after the other, so that each wall time is that model's own cost
    /// (default: all at once, sharing the cores).
    #[arg(long)]
    one_at_a_time: bool,
}

/// `ehl sweep SWEEP [--out DIR] [--jobs N]` plans, runs and merges locally (rerun to resume);
/// the subcommands split that for a cluster.
#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
struct SweepArgs {
    #[command(subcommand)]
    step: Option<SweepStep>,
    /// Built-in sweep name (see `ehl scenes`) or path to a sweep JSON file.
    sweep: Option<String>,
    /// Sweep folder (default: out/sweep-NAME, the sweep's name); a rerun into it skips finished points.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Points run at once, each on one thread (default: all cores).
    #[arg(long)]
    jobs: Option<usize>,
}

#[derive(Subcommand)]
enum SweepStep {
    /// Write the point list (`plan.json`) and a SLURM array script (`sweep.sbatch`).
    Plan {
        sweep: String,
        /// Array tasks; task I runs the points k with k % N = I.
        #[arg(long, default_value_t = 1)]
        shards: usize,
        /// Cores each task asks SLURM for (points it runs at once).
        #[arg(long, default_value_t = 1)]
        cpus_per_task: usize,
        #[arg(long)]
        out: PathBuf,
    },
    /// Run the unfinished points of a planned sweep, or of one shard of it (`--shard I/N`).
    Run {
        dir: PathBuf,
        #[arg(long)]
        shard: Option<ehl_workbench::sweep::Shard>,
        #[arg(long)]
        jobs: Option<usize>,
    },
    /// Write the results and charts of a sweep whose points have all finished.
    Merge { dir: PathBuf },
}

#[derive(Subcommand)]
enum Command {
    /// Run a one-model scene (a built-in name or a JSON file) and write its results.
    Run(RunArgs),
    /// Run every model a comparison scene lists on the same grid and put them side by side.
    Compare(CompareArgs),
    /// Run one scene over one or two parameters (`ehl sweep SWEEP`), or the cluster steps
    /// (`ehl sweep plan|run|merge`).
    Sweep(SweepArgs),
    /// List the built-in scenes and sweeps.
    Scenes,
    /// Check a scene file without running it; prints it with all defaults filled in.
    Check { scene: String },
}

fn main() {
    // A signal asks the solvers and the writer to stop: they return within about a second, and
    // the output folder is left as it was (or, if the new output was already in place, whole).
    // A second signal stops at once; the next run into the folder tidies what that leaves.
    let _ = ctrlc::set_handler(|| {
        if ehl_workbench::cancel::requested() {
            eprintln!("interrupted again: stopping at once");
            std::process::exit(130);
        }
        ehl_workbench::cancel::request();
    });
    let result = real_main();
    let interrupted = ehl_workbench::cancel::requested();
    match result {
        Err(e) if interrupted => {
            eprintln!("{}", interruption_text(&e));
            std::process::exit(130);
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::exit(1);
        }
        Ok(()) if interrupted => {
            eprintln!("interrupted after the results were complete: they are in place, whole");
            std::process::exit(130);
        }
        Ok(()) => {}
    }
}

/// What an interrupted run says: the writer's account of the output folder when it has one.
fn interruption_text(e: &anyhow::Error) -> String {
    match e.downcast_ref::<ehl_workbench::Error>() {
        Some(w @ ehl_workbench::Error::Interrupted(_)) => w.to_string(),
        _ => "interrupted: no output written".into(),
    }
}

fn real_main() -> Result<()> {
    match Cli::parse().command {
        Command::Scenes => scenes()?,
        Command::Sweep(args) => sweep(args)?,
        Command::Check { scene } => {
            let s = ehl_scene::load(&scene)?;
            println!("{}", s.to_json());
        }
        Command::Run(RunArgs { scene, out, grid, threads, accuracy, no_estimate }) => {
            let s = prepare(ehl_scene::load(&scene)?, grid, threads, accuracy)?;
            if s.is_comparison() {
                bail!(
                    "scene `{}` is a comparison of several models ({}): run it with `ehl compare`",
                    s.name,
                    s.model_names()
                );
            }
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&s.name));
            output::check_out_dir(&dir)?;
            let s = announce(&s, &dir);
            let outcome = match ehl_workbench::accuracy::run(&s, !no_estimate) {
                Ok(o) => o,
                Err(ehl_workbench::Error::Interrupted(m)) => {
                    return Err(ehl_workbench::Error::Interrupted(format!(
                        "{m}; no output written, {} is as it was",
                        dir.display()
                    ))
                    .into());
                }
                // A march that failed keeps what it had done, beside the output folder (an
                // earlier answer in it stays).
                Err(e) => match (output::keep_failure(&s, &e, &dir), e.partial()) {
                    (Ok(Some(kept)), Some(p)) => bail!(
                        "{e}\nthe march's record up to its failure ({} steps, t = {:.6e} s) and that state's fields are in {} (failure.json); {} is as it was",
                        p.steps,
                        p.t_s,
                        kept.display(),
                        dir.display()
                    ),
                    (Err(w), _) => bail!("{e}\nits record up to the failure was not written: {w}"),
                    _ => return Err(e.into()),
                },
            };
            eprintln!("writing the results into {}", dir.display());
            let files = output::write(&outcome, &dir)?;
            print!("{}", outcome.report());
            println!("wrote {} files to {}:", files.len(), dir.display());
            for f in files {
                println!("  {}", f.display());
            }
        }
        Command::Compare(CompareArgs {
            run: RunArgs { scene, out, grid, threads, accuracy, no_estimate },
            one_at_a_time,
        }) => {
            let s = prepare(comparison(&scene)?, grid, threads, accuracy)?;
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&s.name));
            output::check_out_dir(&dir)?;
            let s = announce(&s, &dir);
            let c = compare::run_checked(
                &s,
                compare::Schedule::one_at_a_time(one_at_a_time),
                !no_estimate,
            );
            eprintln!("writing the results into {}", dir.display());
            let files = c.write(&dir)?;
            print!("{}", c.table());
            println!(
                "wrote {} files to {} (each model's own outputs in a subfolder)",
                files.len(),
                dir.display()
            );
            if !c.all_converged() {
                bail!("not every model converged (see the table)");
            }
        }
    }
    Ok(())
}

fn sweep(args: SweepArgs) -> Result<()> {
    use ehl_workbench::sweep::{self, Plan, Shard};
    let report = |dir: &std::path::Path, s: &sweep::RunSummary| {
        println!(
            "ran {} points in {:.1} s ({} already finished) in {}",
            s.ran,
            s.wall_time_s,
            s.skipped,
            dir.display()
        );
    };
    match (args.step, args.sweep) {
        (Some(SweepStep::Plan { sweep: name, shards, cpus_per_task, out }), _) => {
            let (sw, base) = ehl_scene::load_sweep(&name)?;
            let plan = Plan::new(&sw, base.as_deref())?;
            plan.write(&out)?;
            let script = sweep::write_sbatch(&out, shards, cpus_per_task)?;
            println!(
                "planned {} points of sweep {} in {}; submit with `sbatch {}`, then `ehl sweep merge {}`",
                plan.points.len(),
                sw.name,
                out.display(),
                script.display(),
                out.display()
            );
        }
        (Some(SweepStep::Run { dir, shard, jobs }), _) => {
            let s = sweep::run(
                &dir,
                shard.unwrap_or(Shard::all()),
                jobs.unwrap_or_else(sweep::default_jobs),
            )?;
            report(&dir, &s);
        }
        (Some(SweepStep::Merge { dir }), _) => {
            let files = sweep::merge::merge(&dir)?;
            print_table(&dir)?;
            println!("wrote {} files to {}", files.len(), dir.display());
        }
        (None, Some(name)) => {
            let (sw, base) = ehl_scene::load_sweep(&name)?;
            let dir =
                args.out.unwrap_or_else(|| PathBuf::from("out").join(format!("sweep-{}", sw.name)));
            let (s, files) = sweep::run_local(
                &sw,
                base.as_deref(),
                &dir,
                args.jobs.unwrap_or_else(sweep::default_jobs),
            )?;
            report(&dir, &s);
            print_table(&dir)?;
            println!("wrote {} result files to {}", files.len(), dir.display());
        }
        (None, None) => {
            bail!("give a sweep (a built-in name or a file), or a step: plan, run, merge")
        }
    }
    Ok(())
}

/// `ehl scenes`: the built-in scenes (what runs them, which models) and sweeps, aligned.
fn scenes() -> Result<()> {
    let scenes = ehl_scene::builtins();
    let sweeps: Vec<ehl_scene::Sweep> = ehl_scene::builtin_sweep_names()
        .into_iter()
        .map(|n| ehl_scene::load_sweep(n).map(|(s, _)| s))
        .collect::<Result<_, _>>()?;
    let rows: Vec<(String, String, String)> = scenes
        .iter()
        .map(|s| {
            let how = if s.is_comparison() {
                format!("compare: {}", s.model_names())
            } else {
                match &s.comparison {
                    Some(c) => format!("run: {} (compare: {c})", s.model_names()),
                    None => format!("run: {}", s.model_names()),
                }
            };
            (s.name.clone(), how, s.description.clone())
        })
        .collect();
    let w0 = rows.iter().map(|r| r.0.len()).chain(sweeps.iter().map(|s| s.name.len())).max();
    let w1 = rows.iter().map(|r| r.1.chars().count()).max().unwrap_or(0);
    let w0 = w0.unwrap_or(0);
    println!("{:<w0$}  {:<w1$}  what it shows", "scene", "how it runs");
    for (name, how, what) in rows {
        println!("{name:<w0$}  {how:<w1$}  {what}");
    }
    println!("\nbuilt-in sweeps (ehl sweep NAME):");
    for s in sweeps {
        println!("{:<w0$}  {}", s.name, s.description);
    }
    Ok(())
}

/// The scene on the grid its accuracy asks for, said on the terminal before it runs (the tests
/// wait for this line: the run has started).
fn announce(s: &ehl_scene::Scene, dir: &std::path::Path) -> ehl_scene::Scene {
    let (s, grown) = ehl_workbench::accuracy::resolved(s);
    eprintln!(
        "running `{}` ({}) on {}{}, into {}",
        s.name,
        s.model_names(),
        grid_words(&s),
        grown.map_or(String::new(), |_| " (the grid the accuracy asked needs)".into()),
        dir.display()
    );
    s
}

/// The grid in words: `129² over x [-1.5, 1.5] a, y [-1.5, 1.5] a`.
fn grid_words(s: &ehl_scene::Scene) -> String {
    let (g, d) = (&s.grid, &s.domain);
    let side = if g.nx == g.ny { format!("{}²", g.nx) } else { format!("{}x{}", g.nx, g.ny) };
    let b = |v: f64| {
        let t = format!("{v:.4}");
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    format!(
        "{side} over x [{}, {}] a, y [{}, {}] a",
        b(d.x_a[0]),
        b(d.x_a[1]),
        b(d.y_a[0]),
        b(d.y_a[1])
    )
}

/// The merged sweep's terminal table.
fn print_table(dir: &std::path::Path) -> Result<()> {
    use ehl_workbench::sweep;
    let plan = sweep::Plan::load(dir)?;
    let recs = sweep::records(dir, &plan)?;
    print!("{}", sweep::merge::table(&plan, &recs));
    Ok(())
}

/// The scene to run: loaded, validated, the grid and thread count set.
/// The scene `ehl compare NAME` runs: `NAME` itself, or the comparison a one-model scene
/// names (the seed's layer scenes name theirs), said on the terminal.
fn comparison(scene: &str) -> Result<ehl_scene::Scene> {
    let s = ehl_scene::load(scene)?;
    let names = |s: &ehl_scene::Scene| {
        s.models().iter().map(|&m| compare::model_name(m)).collect::<Vec<_>>().join(", ")
    };
    Ok(match s.as_comparison()? {
        Some(c) => {
            println!(
                "scene `{}` is the {} model's own; its case through every model is `{}` ({}): running that",
                s.name,
                names(&s),
                c.name,
                names(&c)
            );
            c
        }
        None => {
            if !s.is_comparison() {
                println!(
                    "scene `{}` names no comparison: running its one model ({})",
                    s.name,
                    names(&s)
                );
            }
            s
        }
    })
}

/// A loaded scene with the command line's grid, accuracy and thread count applied.
fn prepare(
    mut s: ehl_scene::Scene,
    grid: Option<usize>,
    threads: Option<usize>,
    accuracy: Option<f64>,
) -> Result<ehl_scene::Scene> {
    if let Some(n) = grid {
        s = s.with_points(n)?;
    }
    if let Some(a) = accuracy {
        s = s.with_accuracy(a)?;
    }
    if let Some(t) = threads {
        anyhow::ensure!(t >= 1, "--threads must be >= 1");
        rayon::ThreadPoolBuilder::new().num_threads(t).build_global()?;
    }
    Ok(s)
}
