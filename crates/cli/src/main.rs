//! `ehl`: run a scene and write its results.

use anyhow::{Result, bail};
use clap::{Parser, Subcommand};
use ehl_workbench::{compare, output, run_scene};
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
    /// Output folder (default: out/<scene name>); replaced as a whole when the run is done.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Points per side, overriding the scene's grid.
    #[arg(long)]
    grid: Option<usize>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a one-model scene (a built-in name or a JSON file) and write its results.
    Run(RunArgs),
    /// Run every model a comparison scene lists on the same grid and put them side by side.
    Compare(RunArgs),
    /// List the built-in scenes.
    Scenes,
    /// Check a scene file without running it; prints it with all defaults filled in.
    Check { scene: String },
}

fn main() {
    // An interrupted run leaves no partial output: the staging folder goes with it.
    let _ = ctrlc::set_handler(|| {
        output::abandon_stage();
        eprintln!("interrupted: no output written");
        std::process::exit(130);
    });
    if let Err(e) = real_main() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn real_main() -> Result<()> {
    match Cli::parse().command {
        Command::Scenes => {
            for s in ehl_scene::builtins() {
                println!("{:<24} {}", s.name, s.description);
            }
        }
        Command::Check { scene } => {
            let s = ehl_scene::load(&scene)?;
            println!("{}", s.to_json());
        }
        Command::Run(RunArgs { scene, out, grid, threads }) => {
            let s = prepare(&scene, grid, threads)?;
            if s.model.is_none() {
                bail!(
                    "scene `{}` lists several models ({:?}): run it with `ehl compare`",
                    s.name,
                    s.models
                );
            }
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&s.name));
            let outcome = run_scene(&s)?;
            let files = output::write(outcome.as_ref(), &dir)?;
            print!("{}", outcome.report());
            println!("wrote {} files to {}:", files.len(), dir.display());
            for f in files {
                println!("  {}", f.display());
            }
        }
        Command::Compare(RunArgs { scene, out, grid, threads }) => {
            let s = prepare(&scene, grid, threads)?;
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&s.name));
            let c = compare::run(&s);
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

/// The scene to run: loaded, validated, the grid and thread count set.
fn prepare(scene: &str, grid: Option<usize>, threads: Option<usize>) -> Result<ehl_scene::Scene> {
    let mut s = ehl_scene::load(scene)?;
    if let Some(n) = grid {
        s = s.with_points(n)?;
    }
    if let Some(t) = threads {
        anyhow::ensure!(t >= 1, "--threads must be >= 1");
        rayon::ThreadPoolBuilder::new().num_threads(t).build_global()?;
    }
    Ok(s)
}
