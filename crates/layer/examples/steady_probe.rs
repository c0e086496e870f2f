//! Probe of the direct steady-rolling solve on the seed's conditions: iterations, time, films.
//! `cargo run --release -p ehl-layer --example steady_probe -- 257 [smoothing] [nested 0|1]`
use ehl_core::{DrySettings, Grid};
use ehl_layer::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(129);
    let sm: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.02);
    let nested = args.get(3).map(|s| s != "0").unwrap_or(true);
    let substeps: usize = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(4);
    let spec = LayerSpec { coefficient_smoothing_a: sm, ..SEED_LAYER };
    let dry_tol: f64 = std::env::var("DRYTOL").map(|v| v.parse().unwrap()).unwrap_or(1e-7);
    let settings = DrySettings { tolerance: dry_tol, ..DrySettings::default() };
    let m = LayerModel::new(
        &ehl_core::SEED_CONTACT,
        &ehl_core::SEED_LUBRICANT,
        &spec,
        ehl_layer::SEED_SUPPLY_THICKNESS_M,
        ehl_core::Kinematics::constant(0.01).unwrap(),
        Grid::square(n, 1.25),
        settings,
    )
    .unwrap();
    let tol: f64 = std::env::var("TOL").map(|v| v.parse().unwrap()).unwrap_or(1e-6);
    let st =
        SteadySettings { nested, substeps, strain_tolerance: tol, ..SteadySettings::default() };
    match rolling_steady(&m, &st) {
        Ok((s, r)) => {
            let mon = Monitor::of(&m, &s, 0);
            println!(
                "n={n} its={:?} solves={} cg={} res={:.2e} time={:.3}s h_c={:.4} nm h_min={:.4} nm p_max={:.5} wiggle={:.3}",
                r.iterations,
                r.solves,
                r.contact_iterations,
                r.strain_residual,
                r.wall_time_s,
                mon.central_thickness * 1e9,
                mon.minimum_thickness * 1e9,
                s.p.iter().cloned().fold(0.0, f64::max),
                mon.lateral_wiggle / m.scales.p_h
            );
            let h: Vec<String> = r.history.iter().map(|v| format!("{v:.1e}")).collect();
            println!("history: {}", h.join(" "));
        }
        Err(e) => println!("n={n}: {e}"),
    }
}
