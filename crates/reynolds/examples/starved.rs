//! Probe for the starved, mass-conserving solver: `starved N H_OIL_NM...` solves the seed's
//! conditions (Table 1, u = 0.01 m/s, [-1.25, 1.25]²) on N² flooded (the clamp) and with each
//! supply, and prints the central film, `ρ̄(p_c) H_c` against `H_oil`, `R` and the meniscus.
#[path = "../tests/common/mod.rs"]
mod common;

use ehl_core::Grid;
use ehl_reynolds::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(65);
    let supplies: Vec<f64> = args[2..].iter().map(|s| s.parse().unwrap()).collect();
    let prm = if std::env::var("M20").is_ok() { common::m20() } else { common::seed() };
    let grid = if std::env::var("M20").is_ok() {
        Grid::new(n, n, (-4.5, 1.5), (-3.0, 3.0))
    } else {
        Grid::new(n, n, (-1.25, 1.25), (-1.25, 1.25))
    };
    let delta = prm.scales.delta;
    let solve = |h_oil_nm: Option<f64>| {
        let envu = |k: &str, d: usize| std::env::var(k).map(|v| v.parse().unwrap()).unwrap_or(d);
        let d = ReynoldsSettings::default();
        let st = ReynoldsSettings {
            coarsest_points: envu("COARSEST", d.coarsest_points),
            coarse_sweeps: envu("CSWEEPS", d.coarse_sweeps),
            max_cycles: envu("MAXCYC", d.max_cycles),
            fmg_cycles: envu("FMG", d.fmg_cycles),
            fallback_lag: if std::env::var("NOLAG").is_ok() { 0.0 } else { d.fallback_lag },
            ..d
        };
        let mut s = ReynoldsSolver::new(grid, prm, st);
        if let Some(h) = h_oil_nm {
            let hd = h * 1e-9 / delta;
            s.set_supply(Some(&move |_y| hd));
        }
        let t = std::time::Instant::now();
        let r = s.solve(&mut |_| {});
        let dt = t.elapsed().as_secs_f64();
        let (hc, hmin) = s.films();
        let (j, i) = (grid.row_nearest(0.0), grid.col_nearest(0.0));
        let pc = s.pressure()[[j, i]];
        let rho = prm.density.rho(pc);
        // Meniscus: first x on the centre line where theta reaches 1.
        let th = s.theta();
        let men = (0..n).find(|&k| th[[j, k]] >= 1.0 && k > 0).map(|k| grid.x(k));
        println!(
            "h_oil {:>8?} nm: ok {} cycles {:>3} {:.2}s  hc {:.3} nm hmin {:.3} nm  rho_c*hc {:.3} nm  meniscus {:?}",
            h_oil_nm,
            r.as_ref().is_ok(),
            r.as_ref().map(|r| r.cycles).unwrap_or(0),
            dt,
            hc * delta * 1e9,
            hmin * delta * 1e9,
            rho * hc * delta * 1e9,
            men
        );
        if let Err(e) = &r {
            println!("  {e}");
        }
        hc
    };
    if let Ok(nsw) = std::env::var("RELAX") {
        let hd = supplies[0] * 1e-9 / delta;
        let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings { fmg_cycles: 0, ..Default::default() });
        s.set_supply(Some(&move |_y| hd));
        let h00 = s.h00;
        sweeps(&mut s, &prm, h00, nsw.parse().unwrap());
        return;
    }
    let hf = solve(None);
    for h in supplies {
        let hc = solve(Some(h));
        if std::env::var("CENTRE").is_ok() { let hd = h * 1e-9 / delta; let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings { max_cycles: std::env::var("MAXC").map(|v| v.parse().unwrap()).unwrap_or(5), fallback_lag: 0.0, ..Default::default() }); s.set_supply(Some(&move |_y| hd)); let _ = s.solve(&mut |_| {}); centre(&s); if std::env::var("SWEEPS").is_ok() { worst(&s, &prm); let h00 = s.h00; sweeps(&mut s, &prm, h00, 10); } }
        println!("   R = {:.4}", hc / hf);
    }
}

#[allow(dead_code)]
fn centre(s: &ReynoldsSolver) {
    let g = s.grid();
    let j = g.row_nearest(0.0);
    for i in (0..g.nx).filter(|&i| i < 30 || i % 8 == 0) {
        println!("x {:.3} P {:.4} H {:.4e} theta {:.4}", g.x(i), s.pressure()[[j, i]], s.film()[[j, i]], s.theta()[[j, i]]);
    }
}

#[allow(dead_code)]
/// Sweeps.
pub fn sweeps(s: &mut ReynoldsSolver, prm: &ReynoldsParams, h00: f64, n: usize) {
    let g = s.grid();
    let j: usize = std::env::var("ROW").map(|v| v.parse().unwrap()).unwrap_or(g.row_nearest(0.0));
    let _ = g;
    for k in 0..n {
        let r = s.finest().residual(prm);
        let f = s.finest();
        let gg = s.grid();
        let blobs: Vec<(usize, usize)> = f.p.indexed_iter().filter(|(ix, v)| **v > 0.0 && gg.x(ix.1) < -2.5).map(|(ix, _)| ix).take(6).collect();
        let nb = f.p.indexed_iter().filter(|(ix, v)| **v > 0.0 && gg.x(ix.1) < -2.5).count();
        let rr = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
        println!("sweep {k}: blobs {nb} {blobs:?} rms {rr:.3e}");
        println!(
            "sweep {k}: P1..5 {:?} th {:?} r {:?}",
            (col0()..col0() + 6).map(|i| format!("{:.2e}", f.p[[j, i]])).collect::<Vec<_>>(),
            (col0()..col0() + 6).map(|i| format!("{:.3}", f.theta[[j, i]])).collect::<Vec<_>>(),
            (col0()..col0() + 6).map(|i| format!("{:.2e}", r[[j, i]])).collect::<Vec<_>>()
        );
        s.finest_mut().relax(prm, h00, &RelaxSettings::default());
    }
}

#[allow(dead_code)]
/// Worst.
pub fn worst(s: &ReynoldsSolver, prm: &ReynoldsParams) {
    let g = s.grid();
    let r = s.finest().residual(prm);
    let mut v: Vec<((usize, usize), f64)> = r.indexed_iter().map(|(ix, v)| (ix, *v)).collect();
    v.sort_by(|a, b| b.1.abs().partial_cmp(&a.1.abs()).unwrap());
    for ((j, i), m) in v.iter().take(12) {
        println!("r {m:+.2e} at i {i} j {j} x={:.3} y={:.3} P={:.3e} H={:.4e} th={:.3}", g.x(*i), g.y(*j), s.pressure()[[*j, *i]], s.film()[[*j, *i]], s.theta()[[*j, *i]]);
    }
}

fn col0() -> usize {
    std::env::var("COL").map(|v| v.parse().unwrap()).unwrap_or(25)
}
