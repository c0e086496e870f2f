//! Diagnostic probe for M = 20, L = 10 (Roelands, Dowson-Higginson): `m20 N` solves on N²,
//! `m20 N relax` watches single-grid relaxation (`fmgrelax`: from the full-multigrid start,
//! FMG cycles on each coarser grid), `m20 N freeze` runs cycles with H00 frozen and
//! prints where the largest residuals sit, `m20 N diff` where the pressure changes between
//! cycles, `m20 N steps` takes time steps from the steady state (a fixed point, or a drift?).
//! Extra arguments: omega_jd, threshold, omega_gs. Environment: GAMMA, PRE, POST, COARSEST, FMG,
//! MAXC, FTOL (film and load tolerance) override the settings; M, L the case; SEED=1 the seed's
//! Table 1 conditions; NARROW=1 the domain [-HALF, HALF]² (HALF = 1.25); COURANT the step;
//! STEPS how many (6); LAG the laws' lag (`coefficient_lag`); H00GAIN the `H00` update's gain; PROFILE=1 (with `steps`) where the residuals are largest.
#[path = "../tests/common/mod.rs"]
mod common;

use ehl_core::Grid;
use ehl_reynolds::*;
/// The `n` points where `|f|` is largest on the finest grid: value, place, `P` and `H` there.
fn largest(s: &ReynoldsSolver, f: &ndarray::Array2<f64>, n: usize) -> Vec<String> {
    let (l, g) = (s.finest(), s.grid());
    let mut v: Vec<((usize, usize), f64)> = f.indexed_iter().map(|(ix, v)| (ix, *v)).collect();
    v.sort_by(|a, b| b.1.abs().partial_cmp(&a.1.abs()).unwrap());
    v.iter()
        .take(n)
        .map(|((j, i), m)| {
            format!(
                "{m:+.2e} at x={:.3} y={:.3} P={:.3e} H={:.4e}",
                g.x(*i),
                g.y(*j),
                l.p[[*j, *i]],
                l.film[[*j, *i]]
            )
        })
        .collect()
}

fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(65);
    let envf = |k: &str, d: f64| std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d);
    // SEED=1: the seed's Table 1 conditions (M ≈ 2223, L ≈ 2.49) instead of M, L.
    let prm = if std::env::var("SEED").is_ok() {
        common::seed()
    } else {
        common::moes(envf("M", 20.0), envf("L", 10.0))
    };
    println!("M {:.2} L {:.2} lambda {:.4e}", prm.moes.m, prm.moes.l, prm.lambda_bar);
    // NARROW=1: the layer model's domain [-1.25, 1.25]² instead.
    let grid = if std::env::var("NARROW").is_ok() {
        let hw: f64 = std::env::var("HALF").ok().and_then(|v| v.parse().ok()).unwrap_or(1.25);
        Grid::new(n, n, (-hw, hw), (-hw, hw))
    } else {
        Grid::new(n, n, (-4.5, 1.5), (-3.0, 3.0))
    };
    let mut settings = ReynoldsSettings::default();
    if let Some(v) = std::env::args().nth(3) {
        settings.relax.omega_jd = v.parse().unwrap();
    }
    if let Some(v) = std::env::args().nth(4) {
        settings.relax.distributive_threshold = v.parse().unwrap();
    }
    if let Some(v) = std::env::args().nth(5) {
        settings.relax.omega_gs = v.parse().unwrap();
    }
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<usize>().ok());
    if let Some(v) = env("GAMMA") {
        settings.gamma = v;
    }
    if let Some(v) = env("PRE") {
        settings.pre_sweeps = v;
    }
    if let Some(v) = env("POST") {
        settings.post_sweeps = v;
    }
    if let Ok(v) = std::env::var("FTOL") {
        settings.film_tolerance = v.parse().unwrap();
        settings.load_tolerance = v.parse().unwrap();
    }
    if let Some(v) = env("MAXC") {
        settings.max_cycles = v;
    }
    if let Some(v) = env("FMG") {
        settings.fmg_cycles = v;
    }
    if let Ok(v) = std::env::var("H00GAIN") {
        settings.h00_gain = v.parse().unwrap();
    }
    if let Ok(v) = std::env::var("LAG") {
        settings.relax.coefficient_lag = v.parse().unwrap();
    }
    if let Some(v) = env("COARSEST") {
        settings.coarsest_points = v;
    }
    let mut s = ReynoldsSolver::new(grid, prm, settings);
    println!("levels {}", s.depth());
    if std::env::args().nth(2).as_deref() == Some("freeze") {
        s.settings.max_cycles = 30;
        let _ = s.solve(&mut |_| {});
        s.settings.h00_gain = 0.0;
        s.settings.max_cycles = 1;
        s.settings.fmg_cycles = 0;
        for _ in 0..4 {
            let _ = s.solve(&mut |c| {
                print!(
                    "frozen res {:.3e} load {:+.4e} Hc {:.6} Hmin {:.6}",
                    c.residual, c.load_error, c.central_film, c.minimum_film
                )
            });
            let r = s.finest().residual(&prm);
            for line in largest(&s, &r, 3) {
                print!(" | {line}");
            }
            println!();
        }
        return;
    }
    if std::env::args().nth(2).as_deref() == Some("steps") {
        let _ = s.solve(&mut |_| {});
        println!("steady {:?}", s.films());
        if std::env::var("PROFILE").is_ok() {
            let l = s.finest();
            let g = l.grid;
            let r = l.residual(&s.prm);
            for line in largest(&s, &r, 5) {
                println!("  steady res {line} (H00 {:.6e})", s.h00);
            }
            for xq in [0.0, 0.3, 0.6, 0.9] {
                let i = g.col_nearest(xq);
                for j in (g.ny - 12)..g.ny {
                    println!(
                        "x {:.3} y {:.4} P {:.3e} H {:.4e} res {:.2e}",
                        g.x(i),
                        g.y(j),
                        l.p[[j, i]],
                        l.film[[j, i]],
                        r[[j, i]]
                    );
                }
            }
        }
        let dt = s.finest().h
            * std::env::var("COURANT").ok().and_then(|v| v.parse().ok()).unwrap_or(1.0);
        for k in 1..=std::env::var("STEPS").ok().and_then(|v| v.parse().ok()).unwrap_or(6) {
            let r = s.step(dt, &mut |c| {
                println!(
                    "     {:>3} res {:.3e} load {:+.3e} Hc {:.6} Hmin {:.6}",
                    c.cycle, c.residual, c.load_error, c.central_film, c.minimum_film
                )
            });
            println!("step {k}: {:?} films {:?}", r.map(|r| (r.converged, r.cycles)), s.films());
            if std::env::var("PROFILE").is_ok() {
                let l = s.finest();
                for line in largest(&s, &l.residual(&s.prm), 5) {
                    println!("   res {line}");
                }
            }
        }
        return;
    }
    if std::env::args().nth(2).as_deref() == Some("diff") {
        s.settings.max_cycles = 40;
        let _ = s.solve(&mut |_| {});
        s.settings.max_cycles = 1;
        s.settings.fmg_cycles = 0;
        for _ in 0..3 {
            let before = s.finest().p.clone();
            let _ = s.solve(&mut |c| print!("load {:+.4e}", c.load_error));
            let d = &s.finest().p - &before;
            println!(" sum dP h^2 {:.3e}", d.sum() * s.finest().h * s.finest().h);
            for line in largest(&s, &d, 6) {
                println!("   dP {line}");
            }
        }
        return;
    }
    let mode = std::env::args().nth(2);
    if matches!(mode.as_deref(), Some("relax" | "fmgrelax")) {
        if mode.as_deref() == Some("fmgrelax") {
            // The start only: the coarser grids' cycles, prolonged to the finest grid.
            s.settings.max_cycles = 0;
            let _ = s.solve(&mut |_| {});
        }
        let h00 = s.h00;
        let rs = s.settings.relax;
        for k in 0..=400 {
            if k % 40 == 0 {
                let r = s.finest().residual(&prm);
                let pos: Vec<f64> = r
                    .iter()
                    .zip(s.finest().p.iter())
                    .filter(|(_, p)| **p > 0.0)
                    .map(|(r, _)| *r)
                    .collect();
                let rms = (pos.iter().map(|v| v * v).sum::<f64>() / pos.len() as f64).sqrt();
                let ((j, i), mx) = r.indexed_iter().fold(((0, 0), 0.0f64), |a, (ix, v)| {
                    if v.abs() > a.1 { (ix, v.abs()) } else { a }
                });
                println!(
                    "sweep {k:>4} rms(P>0) {rms:.3e} max {mx:.3e} at x={:.3} y={:.3} P={:.4}",
                    s.finest().grid.x(i),
                    s.finest().grid.y(j),
                    s.finest().p[[j, i]]
                );
            }
            let prm = s.prm;
            s.finest_mut().relax(&prm, h00, &rs);
        }
        return;
    }
    let rep = s.solve(&mut |c| {
        println!(
            "{:>4} {:>4}² res {:.3e} load {:+.3e} H00 {:.5} Hc {:.5} Hmin {:.5}",
            c.cycle, c.points, c.residual, c.load_error, c.h00, c.central_film, c.minimum_film
        )
    });
    println!("{:?}", rep.map(|r| (r.converged, r.cycles, r.wall_time_s)));
    let (hc, hmin) = s.films();
    println!("films {hc:.17e} {hmin:.17e} p_sum {:.17e}", s.finest().p.sum());
}
