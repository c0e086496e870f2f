//! The workbench's harness: `cargo xtask figures | convergence dry|layer|reynolds |
//! stability reynolds | bench | slurm-check | mutants`.
//!
//! Fine grids live here, not in the tests: these commands take seconds to minutes.

mod accuracy;
mod bench;
mod compare;
mod contact;
mod convergence;
mod example;
mod findings;
mod identify;
mod layer;
mod measured;
mod mixed;
mod mutants;
mod reynolds;
mod scene_study;
mod seed_page;
mod slurm;
mod starvation;
mod sweep_page;
mod waves;

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "cargo xtask")]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Run the study on coarse grids, in seconds: the code paths of the real study, not its
    /// numbers (CI runs every study so). Measured pages go to `target/quick-measured/`, never
    /// to `docs/measured/`.
    #[arg(long, global = true)]
    quick: bool,
}

/// Whether this run is a quick one (`--quick`).
static QUICK: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether the study runs quickly, on coarse grids (`--quick`).
pub fn quick() -> bool {
    QUICK.load(std::sync::atomic::Ordering::Relaxed)
}

/// The points per side a study runs `n` at: `n` itself, or quickly a grid of the same rank
/// eight times coarser per side (129 → 17, 257 → 33, 1025 → 129), at least 17.
pub fn points(n: usize) -> usize {
    if quick() { ((n.saturating_sub(1)) / 8 + 1).max(17) } else { n }
}

#[derive(Subcommand)]
enum Command {
    /// Regenerate every figure of the project into one folder.
    Figures {
        #[arg(long, default_value = "out/figures")]
        out: PathBuf,
    },
    /// Grid (and, for time-dependent models, time-step) convergence studies.
    Convergence {
        /// Which study: `dry` (Hertz grid study), `layer` (steady rolling: grids, time steps,
        /// explicit stability, speed against accuracy), `layer-steady` (the direct steady solve),
        /// `reynolds` (grid studies of the built-in Reynolds scenes); or any scene, built-in or a
        /// file (one model or a comparison): every model's grid study on `--grids`, observed
        /// orders, one speed-against-accuracy chart.
        study: String,
        /// Grids of a scene study, points per side.
        #[arg(long, value_delimiter = ',', default_value = "65,129,257,513")]
        grids: Vec<usize>,
        /// A scene study of these of the scene's models only (`layer,reynolds`): a model too
        /// slow on the finest grid left out.
        #[arg(long, value_delimiter = ',')]
        models: Vec<String>,
        /// A scene study at this rolling speed [m/s] instead of the scene's.
        #[arg(long)]
        speed: Option<f64>,
        #[arg(long, default_value = "out/convergence")]
        out: PathBuf,
        /// Finest grid, points per side.
        #[arg(long, default_value_t = 513)]
        max_points: usize,
        /// Grid of the layer time-step study.
        #[arg(long, default_value_t = 129)]
        nt_points: usize,
    },
    /// The starvation study: the seed's contact fed 5-200 nm (the built-in sweep
    /// `seed-supply`), both models' starvation curves with the fitted `γ`, the grid
    /// convergence of the starved film; writes `docs/measured/starvation.md`.
    Starvation {
        #[arg(long, default_value = "out/starvation")]
        out: PathBuf,
        /// Points per side of the supply sweep.
        #[arg(long, default_value_t = 257)]
        points: usize,
        /// Grids of the convergence study (points per side).
        #[arg(long, value_delimiter = ',', default_value = "129,257,513")]
        grids: Vec<usize>,
    },
    /// Stability studies: `reynolds` (converged or not, and cycles, over Moes' M and L).
    Stability {
        /// Which: `reynolds`.
        which: Which,
        #[arg(long, default_value = "out/stability")]
        out: PathBuf,
        /// Points per side.
        #[arg(long, default_value_t = 257)]
        points: usize,
        /// From this load parameter M on, the layer model's narrow domain.
        #[arg(long, default_value_t = 500.0)]
        narrow_from_m: f64,
    },
    /// Identify the seed's lost laws (damper prefactor, its pressure scale, the modulus law's
    /// reference pressure) from its reported numbers; writes `reference/seed-fit.json` (what the
    /// `seed-fit` law set uses) and the report and chart into `--out`.
    Identify {
        #[arg(long, default_value = "out/identify")]
        out: PathBuf,
        /// Grid of the steady solve and the rolling march, points per side.
        #[arg(long, default_value_t = 65)]
        points: usize,
        /// Grid of the squeeze after a stop (its times need the loaded zone resolved).
        #[arg(long, default_value_t = 129)]
        squeeze_points: usize,
        /// Grid the fit is checked on.
        #[arg(long, default_value_t = 129)]
        check_points: usize,
    },
    /// Time the deformation operator, the dry solver, the layer model and the Reynolds solver,
    /// 65² … 513².
    Bench {
        #[arg(long, default_value = "out/bench")]
        out: PathBuf,
        /// Finest grid, points per side.
        #[arg(long, default_value_t = 513)]
        max_points: usize,
        /// Time only this part (all when absent).
        #[arg(long, value_enum)]
        only: Option<bench::Part>,
    },
    /// Whether every answer's error estimate holds: the Reynolds stability map and `seed-speed`
    /// on `--points`², each estimate against the Richardson limit of grids 2× and 4× finer;
    /// writes `docs/measured/accuracy.md`.
    Accuracy {
        #[arg(long, default_value = "out/accuracy")]
        out: PathBuf,
        /// The answers' grid, points per side.
        #[arg(long, default_value_t = 257)]
        points: usize,
    },
    /// The seed's reported values against the built-in scenes that reproduce them, on the
    /// seed's grid: writes `docs/measured/seed-against-ours.md`.
    Seed {
        /// Points per side.
        #[arg(long, default_value_t = 257)]
        points: usize,
        /// Where the comparison's rows go as JSON.
        #[arg(long, default_value = "out/seed-against-ours")]
        out: PathBuf,
    },
    /// The solids touching in a steady Reynolds solve: the seed's contact fed 0.1–2 nm with
    /// contact and without, on 129² and 257²; writes `docs/measured/steady-contact.md`. With
    /// `--grids`, instead: 2 mm/s, 80 N fed 25 nm on 257², 513², 1025² (the contact's share
    /// and area as the grid refines), `docs/measured/contact-grids.md`.
    Contact {
        #[arg(long, default_value = "out/steady-contact")]
        out: PathBuf,
        /// The touching contact over grids instead.
        #[arg(long)]
        grids: bool,
    },
    /// The seed's comparisons that move (a hole, a dent, a stop, a start) through every model:
    /// writes `docs/measured/findings.md`, and each comparison's outputs (histories, figures)
    /// into `--out`.
    Findings {
        #[arg(long, default_value = "out/findings")]
        out: PathBuf,
    },
    /// A built-in sweep run as `ehl sweep NAME` runs it, merged: writes
    /// `docs/measured/sweep-NAME.md` (its table and robustness counts).
    Sweep {
        /// The built-in sweep (`ehl sweep --list`).
        name: String,
        /// The map alone: every point on the grid its inlet rule grows it to, without the grid
        /// rule's refinement and the checks (minutes where the full sweep takes hours); writes
        /// `docs/measured/sweep-NAME-map.md`.
        #[arg(long)]
        map: bool,
        /// Write the page from the sweep already run and merged in this folder (as on a
        /// cluster: `ehl sweep plan`, the array, `ehl sweep merge`) instead of running it.
        #[arg(long)]
        from: Option<PathBuf>,
        #[arg(long, default_value = "out/sweeps")]
        out: PathBuf,
    },
    /// The mixed-lubrication map: the sweep `mixed-lubrication` (a rough surface rolling in over
    /// the seed's contact, over speed, both models), the share of the load the solids carry and
    /// their area against `λ`; writes `docs/measured/mixed-lubrication.md` and the chart into
    /// `--out`.
    Mixed {
        #[arg(long, default_value = "out/mixed")]
        out: PathBuf,
    },
    /// The amplitude-reduction study: the sweep `waviness-reduction` (two waves through the
    /// seed's contact over speed, both models), `A_d/A_i` against Venner's `∇` and the collapse
    /// of the two wavelengths' curves; writes `docs/measured/waviness-reduction.md` and the
    /// chart into `--out`.
    Waves {
        #[arg(long, default_value = "out/waves")]
        out: PathBuf,
    },
    /// The README's example (`ehl compare seed --accuracy 5%`): writes
    /// `docs/measured/example-compare.md` and the README's table from one run, and the
    /// comparison's outputs into `--out`, as the command does.
    Example {
        #[arg(long, default_value = "out/seed")]
        out: PathBuf,
    },
    /// The sweep's cluster path against a real SLURM: a one-node cluster on localhost (installed
    /// with apt-get when missing; root), a 4-point sweep as an array of 2, merged, compared with
    /// a local run byte for byte; the daemons stopped.
    SlurmCheck {
        /// Keep the temporary folder (configuration, logs, both runs).
        #[arg(long)]
        keep: bool,
        /// The `ehl` binary to run, already built (by default the check builds `ehl-cli`, which
        /// relinks `target/release/ehl` under anything running it).
        #[arg(long)]
        ehl: Option<PathBuf>,
    },
    /// Mutation testing (cargo-mutants) of the numerical files, each by its own crate's tests;
    /// hours for all files on 2 cores: pick with `--file`, sample with `--shard k/n`.
    Mutants {
        /// A file under crates/{core,layer,reynolds}/src (repeatable); default: the target list.
        #[arg(long)]
        file: Vec<String>,
        /// Run one shard of each file's mutants, e.g. `0/4` for a quarter.
        #[arg(long)]
        shard: Option<String>,
        /// Per-mutant test timeout [s] (the crates' suites take 3–25 s unmutated).
        #[arg(long, default_value_t = 120)]
        timeout: u64,
        #[arg(long, default_value = "out/mutants")]
        out: PathBuf,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Which {
    Reynolds,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum Study {
    Dry,
    Layer,
    /// The layer's direct steady solve: grids to `--max-points` (1025 recommended), against the
    /// marched state on 257², and the model as published.
    LayerSteady,
    Reynolds,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    QUICK.store(cli.quick, std::sync::atomic::Ordering::Relaxed);
    match cli.command {
        Command::Figures { out } => figures(&out),
        Command::Convergence { study, grids, models, speed, out, max_points, nt_points } => {
            let (max_points, nt_points) = (points(max_points), points(nt_points));
            let mut grids: Vec<usize> = grids.into_iter().map(points).collect();
            grids.dedup();
            match <Study as clap::ValueEnum>::from_str(&study, false) {
                Ok(Study::Dry) => convergence::dry(&out, max_points).map(|_| ()),
                Ok(Study::Layer) => layer::convergence(&out, max_points, nt_points).map(|_| ()),
                Ok(Study::LayerSteady) => layer::steady_study(&out, max_points, true).map(|_| ()),
                Ok(Study::Reynolds) => reynolds::convergence(&out, max_points).map(|_| ()),
                Err(_) => {
                    let variant = scene_study::Variant { models, speed_m_s: speed };
                    scene_study::run(&study, &grids, &variant, &out).map(|_| ())
                }
            }
        }
        Command::Bench { out, max_points, only } => bench::run(&out, points(max_points), only),
        Command::Identify { out, points: n, squeeze_points, check_points } => {
            identify::run(&out, points(n), points(squeeze_points), points(check_points))
        }
        Command::Starvation { out, points: n, grids } => {
            // Quickly: the seed's contact on the least grids its films exist on.
            let (n, grids) = if quick() { (129, vec![129, 193]) } else { (n, grids) };
            for f in starvation::run(&out, n, &grids)? {
                println!("  {}", f.display());
            }
            Ok(())
        }
        Command::SlurmCheck { keep, ehl } => slurm::check(keep, ehl),
        Command::Example { out } => example::run(&out),
        Command::Findings { out } => findings::run(&out),
        Command::Contact { out, grids: false } => contact::run(&out),
        Command::Contact { out, grids: true } => contact::over_grids(&out),
        Command::Sweep { name, map, from, out } => {
            sweep_page::run(&name, map, from.as_deref(), &out)
        }
        Command::Waves { out } => waves::run(&out),
        Command::Mixed { out } => mixed::run(&out),
        Command::Seed { points: n, out } => seed_page::run(points(n), &out),
        Command::Accuracy { out, points: n } => accuracy::run(&out, points(n)),
        Command::Mutants { file, shard, timeout, out } => {
            mutants::run(&file, shard.as_deref(), timeout, &out)
        }
        Command::Stability { which: Which::Reynolds, out, points: n, narrow_from_m } => {
            reynolds::stability(&out, points(n), narrow_from_m).map(|_| ())
        }
    }
}

/// The points per side a scene runs at in a study: [`points`] of its own, but never below 129
/// quickly for a scene that runs the Reynolds solver: the seed's thin films close on coarser
/// grids (the film needs cells of 0.02 a there), and a study of a failure is not the study.
pub fn scene_points(scene: &ehl_scene::Scene) -> usize {
    use ehl_scene::Model::{Reynolds, ReynoldsFlooded};
    let lubricated = scene.models().iter().any(|m| matches!(m, Reynolds | ReynoldsFlooded));
    let n = scene.grid.nx;
    if quick() && lubricated { n.min(129) } else { points(n) }
}

/// The grid of a study of the seed's contact through the Reynolds solver, at most `max`: 257
/// points per side, quickly 129 (the least its films exist on).
pub fn seed_grid(max: usize) -> usize {
    if quick() { 129 } else { max.min(257) }
}

/// Grid sizes 65, 129, … up to `max` points per side (quickly: 17, 33, 65 up to `max`).
pub fn grid_sizes(max: usize) -> Vec<usize> {
    let from = if quick() { 4 } else { 6 };
    (from..=12).map(|k| (1usize << k) + 1).filter(|&n| n <= max).collect()
}

fn figures(out: &std::path::Path) -> Result<()> {
    std::fs::create_dir_all(out)?;
    let mut written = vec![];
    for scene in ehl_scene::builtins() {
        if scene.is_comparison() {
            continue; // comparison scenes: Figs. 7 and 12 below
        }
        let scene = scene.with_points(scene_points(&scene))?;
        let outcome = ehl_workbench::run_scene(&scene)?;
        written.extend(outcome.figures(out, &format!("{}_", scene.name), "")?);
        // The numbers behind the figures, for the validation table.
        let f = out.join(format!("{}_summary.json", scene.name));
        let summary = ehl_workbench::output::summary(outcome.as_ref());
        std::fs::write(&f, serde_json::to_string_pretty(&summary)? + "\n")?;
        written.push(f);
        if let Some(rows) = outcome.time_series()? {
            let f = out.join(format!("{}_timeseries.csv", scene.name));
            std::fs::write(&f, ehl_workbench::output::csv(&rows))?;
            written.push(f);
        }
    }
    // Fig. 7: the seed comparison (layer, Reynolds, dry on one grid).
    written.extend(compare::fig7(out)?);
    written.extend(compare::fig12(out)?);
    written.extend(compare::fig1(out)?);
    written.extend(convergence::dry(out, points(513))?);
    written.push(layer::modulus_figure(out)?);
    written.extend(identify::figures(out)?);
    println!("figures written to {}:", out.display());
    for f in written {
        println!("  {}", f.display());
    }
    Ok(())
}
