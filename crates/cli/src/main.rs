//! `ehl`: run a scene and write its results.

use anyhow::Result;
use clap::{Parser, Subcommand};
use ehl_cli::{output, run_scene};
use std::path::PathBuf;

#[derive(Parser)]
#[command(name = "ehl", version, about = "EHL point-contact validation workbench")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene (a built-in name or a JSON file) and write its results.
    Run {
        /// Built-in scene name (see `ehl scenes`) or path to a scene JSON file.
        scene: String,
        /// Output folder (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Points per side, overriding the scene's grid.
        #[arg(long)]
        grid: Option<usize>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// List the built-in scenes.
    Scenes,
    /// Check a scene file without running it; prints it with all defaults filled in.
    Check { scene: String },
}

fn main() {
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
        Command::Run { scene, out, grid, threads } => {
            let mut s = ehl_scene::load(&scene)?;
            if let Some(n) = grid {
                s = s.with_points(n)?;
            }
            if let Some(t) = threads {
                anyhow::ensure!(t >= 1, "--threads must be >= 1");
                rayon::ThreadPoolBuilder::new().num_threads(t).build_global()?;
            }
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&s.name));
            let outcome = run_scene(&s)?;
            let files = output::write(&outcome, &dir)?;
            print_result(&outcome);
            println!("wrote {} files to {}:", files.len(), dir.display());
            for f in files {
                println!("  {}", f.display());
            }
        }
    }
    Ok(())
}

fn print_result(outcome: &ehl_cli::Outcome) {
    match outcome {
        ehl_cli::Outcome::Dry(o) => {
            let (h, s) = (&o.hertz, &o.scales);
            println!(
                "scene {} ({}x{}): solved in {:.3} s ({} iterations, residual {:.1e}; setup {:.3} s)",
                o.scene.name,
                o.grid.nx,
                o.grid.ny,
                o.solve_time_s,
                o.report.iterations,
                o.report.residual,
                o.setup_time_s
            );
            println!(
                "  max pressure   {:.6e} Pa   Hertz {:.6e} Pa   rel. error {:+.2e}",
                s.p_si(h.p_max),
                s.p_h,
                h.p_max_error
            );
            println!(
                "  contact radius {:.6e} m    Hertz {:.6e} m    rel. error {:+.2e} (area-equivalent)",
                s.x_si(h.contact_radius),
                s.a,
                h.contact_radius_error
            );
            println!(
                "  approach       {:.6e} m    Hertz {:.6e} m    rel. error {:+.2e}",
                s.h_si(h.approach),
                s.delta,
                h.approach_error
            );
            println!("  pressure L2 error vs Hertz {:.2e}", h.pressure_l2_error);
        }
        ehl_cli::Outcome::Reynolds(o) => {
            let (hc, hmin, pmax) = o.films();
            let s = &o.prm.scales;
            println!(
                "scene {} ({}x{}): converged in {} cycles, {:.2} s (setup {:.2} s); M = {:.2}, L = {:.3}",
                o.scene.name,
                o.grid.nx,
                o.grid.ny,
                o.report.cycles,
                o.report.wall_time_s,
                o.setup_time_s,
                o.prm.moes.m,
                o.prm.moes.l
            );
            println!(
                "  central film {:.4e} m (H = {:.5}), minimum film {:.4e} m (H = {:.5}), max pressure {:.4e} Pa ({:.4} p_h)",
                s.h_si(hc),
                hc,
                s.h_si(hmin),
                hmin,
                s.p_si(pmax),
                pmax
            );
            println!(
                "  formulas: Hamrock-Dowson {:.4e} m, Nijenbanning-Venner-Moes {:.4e} m",
                o.formulas.0, o.formulas.1
            );
        }
        ehl_cli::Outcome::Layer(o) => {
            let f = &o.final_monitor;
            let s = &o.scales;
            let l0 = o.scene.layer.unwrap().supply_thickness_m;
            println!(
                "scene {} ({}x{}): {:.1} s wall",
                o.scene.name, o.grid.nx, o.grid.ny, o.total_time_s
            );
            if let Some(p) = &o.steady {
                let its: Vec<String> =
                    p.iterations.iter().map(|(n, k)| format!("{k} on {n}²")).collect();
                println!(
                    "  steady rolling solved directly: {} iterations, strain residual {:.1e}, {:.2} s wall",
                    its.join(", "),
                    p.strain_residual,
                    p.wall_time_s
                );
            }
            if let Some(r) = &o.record {
                println!(
                    "  run: {} steps ({} rejected), {:.4} s simulated, {:.1} s wall, {:.2} ms/step, {:.2} contact iterations/step; {}",
                    r.steps,
                    r.rejected_steps,
                    o.final_state.t,
                    r.wall_time_s,
                    r.wall_time_s / r.steps.max(1) as f64 * 1e3,
                    r.iterations as f64 / r.steps.max(1) as f64,
                    r.stop_reason
                );
                if !r.steady {
                    println!("  warning: the run did not reach its stop condition");
                }
            }
            println!(
                "  central thickness {:.4e} m ({:.4} l0)   minimum {:.4e} m ({:.4} l0)",
                f.central_thickness,
                f.central_thickness / l0,
                f.minimum_thickness,
                f.minimum_thickness / l0
            );
            println!(
                "  max pressure {:.5e} Pa ({:.4} p_h)   contact diameter {:.4e} m ({:.4} x 2a)   dry diameter {:.4e} m",
                f.max_pressure,
                f.max_pressure / s.p_h,
                f.contact_diameter,
                f.contact_diameter / (2.0 * s.a),
                f.dry_diameter
            );
            if f.lateral_wiggle > 0.05 * s.p_h {
                println!(
                    "  note: row-to-row pressure wiggle {:.3} p_h: the lateral short-wave instability of the layer model (see README)",
                    f.lateral_wiggle / s.p_h
                );
            }
        }
    }
}
