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
            pre_sweeps: envu("PRE", d.pre_sweeps),
            post_sweeps: envu("POST", d.post_sweeps),
            gamma: envu("GAMMA", d.gamma),
            film_tolerance: std::env::var("FTOL")
                .map(|v| v.parse().unwrap())
                .unwrap_or(d.film_tolerance),
            stall_cycles: envu("STALL", d.stall_cycles),
            relax: RelaxSettings {
                omega_gs: std::env::var("OMEGA")
                    .map(|v| v.parse().unwrap())
                    .unwrap_or(d.relax.omega_gs),
                meniscus_passes: envu("MPASS", d.relax.meniscus_passes),
                ..d.relax
            },
            h00_gain: std::env::var("H00GAIN").map(|v| v.parse().unwrap()).unwrap_or(d.h00_gain),
            fallback_lag: if std::env::var("NOLAG").is_ok() { 0.0 } else { d.fallback_lag },
            ..d
        };
        let mut s = ReynoldsSolver::new(grid, prm, st);
        if let Some(h) = h_oil_nm {
            let hd = h * 1e-9 / delta;
            s.set_supply(Some(&move |_y| hd));
        }
        let t = std::time::Instant::now();
        let r = s.solve(&mut |c| {
            if std::env::var("LOG").is_ok() {
                println!(
                    "  cycle {} n {} res {:.3e} load {:.2e} hc {:.5e} mass {:.2e}",
                    c.cycle, c.points, c.residual, c.load_error, c.central_film, c.mass_defect
                )
            }
        });
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
        let mut s = ReynoldsSolver::new(
            grid,
            prm,
            ReynoldsSettings { fmg_cycles: 0, ..Default::default() },
        );
        s.set_supply(Some(&move |_y| hd));
        let h00 = s.h00;
        sweeps(&mut s, &prm, h00, nsw.parse().unwrap());
        return;
    }
    if let Ok(k) = std::env::var("DIFF") {
        let k: usize = k.parse().unwrap();
        let hd = supplies[0] * 1e-9 / delta;
        let run = |c: usize| {
            let st = ReynoldsSettings {
                fmg_cycles: 0,
                max_cycles: c,
                fallback_lag: 0.0,
                stall_cycles: 0,
                film_tolerance: 1e-14,
                ..Default::default()
            };
            let mut s = ReynoldsSolver::new(grid, prm, st);
            s.set_supply(Some(&move |_y| hd));
            let _ = s.solve(&mut |_| {});
            (s.pressure().clone(), s.theta().clone(), s.film().clone())
        };
        let (p0, t0, h0) = run(k);
        let (p1, t1, _) = run(k + 1);
        let dp = &p1 - &p0;
        let dt = &t1 - &t0;
        let mut v: Vec<((usize, usize), f64, f64)> =
            dp.indexed_iter().map(|(ix, d)| (ix, *d, dt[ix])).collect();
        v.sort_by(|a, b| b.1.abs().partial_cmp(&a.1.abs()).unwrap());
        for (ix, d, e) in v.iter().take(8) {
            println!(
                "dP {d:+.2e} dθ {e:+.2e} at x {:.3} y {:.3} P {:.3e} θ {:.3} H {:.3e}",
                grid.x(ix.1),
                grid.y(ix.0),
                p0[*ix],
                t0[*ix],
                h0[*ix]
            );
        }
        v.sort_by(|a, b| b.2.abs().partial_cmp(&a.2.abs()).unwrap());
        for (ix, d, e) in v.iter().take(8) {
            println!(
                "dθ {e:+.2e} dP {d:+.2e} at x {:.3} y {:.3} P {:.3e} θ {:.3} H {:.3e}",
                grid.x(ix.1),
                grid.y(ix.0),
                p0[*ix],
                t0[*ix],
                h0[*ix]
            );
        }
        println!("sum dP {:.3e} sum|dθ| {:.3e}", dp.sum(), dt.iter().map(|v| v.abs()).sum::<f64>());
        return;
    }
    let hf = if std::env::var("SKIPF").is_ok() { 1.0 } else { solve(None) };
    for h in supplies {
        let hc = solve(Some(h));
        if std::env::var("CENTRE").is_ok() {
            let hd = h * 1e-9 / delta;
            let mut s = ReynoldsSolver::new(
                grid,
                prm,
                ReynoldsSettings {
                    max_cycles: std::env::var("MAXC").map(|v| v.parse().unwrap()).unwrap_or(5),
                    fallback_lag: 0.0,
                    ..Default::default()
                },
            );
            s.set_supply(Some(&move |_y| hd));
            let _ = s.solve(&mut |_| {});
            if std::env::var("ACROSS").is_ok() {
                across(&s, -0.5)
            } else {
                centre(&s)
            };
            flows(&s, &prm);
            worst(&s, &prm);
            if std::env::var("SWEEPS").is_ok() {
                worst(&s, &prm);
                let h00 = s.h00;
                sweeps(&mut s, &prm, h00, 10);
            }
        }
        println!("   R = {:.4}", hc / hf);
    }
}

#[allow(dead_code)]
fn centre(s: &ReynoldsSolver) {
    let g = s.grid();
    let j = g.row_nearest(0.0);
    for i in (0..g.nx).filter(|&i| i < 30 || i % 8 == 0) {
        println!(
            "x {:.3} P {:.4} H {:.4e} theta {:.4}",
            g.x(i),
            s.pressure()[[j, i]],
            s.film()[[j, i]],
            s.theta()[[j, i]]
        );
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
        let blobs: Vec<(usize, usize)> =
            f.p.indexed_iter()
                .filter(|(ix, v)| **v > 0.0 && gg.x(ix.1) < -2.5)
                .map(|(ix, _)| ix)
                .take(6)
                .collect();
        let nb = f.p.indexed_iter().filter(|(ix, v)| **v > 0.0 && gg.x(ix.1) < -2.5).count();
        let rr = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
        if k % 25 == 0 {
            println!(
                "sweep {k}: blobs {nb} {blobs:?} rms {rr:.3e} load {:.4e} hc {:.5e}",
                f.load(),
                f.film[[f.grid.row_nearest(0.0), f.grid.col_nearest(0.0)]]
            );
        }
        println!(
            "sweep {k}: P1..5 {:?} th {:?} r {:?}",
            (col0()..col0() + 6).map(|i| format!("{:.2e}", f.p[[j, i]])).collect::<Vec<_>>(),
            (col0()..col0() + 6).map(|i| format!("{:.3}", f.theta[[j, i]])).collect::<Vec<_>>(),
            (col0()..col0() + 6).map(|i| format!("{:.2e}", r[[j, i]])).collect::<Vec<_>>()
        );
        let rs = RelaxSettings {
            omega_gs: std::env::var("OMEGA").map(|v| v.parse().unwrap()).unwrap_or(0.4),
            ..Default::default()
        };
        s.finest_mut().relax(prm, h00, &rs);
    }
}

#[allow(dead_code)]
/// Worst.
pub fn worst(s: &ReynoldsSolver, prm: &ReynoldsParams) {
    let g = s.grid();
    let r = s.finest().residual(prm);
    println!("net source sum(r) h^2 = {:.4e}", r.sum() * g.dx() * g.dx());
    let f = s.finest();
    let mut cat = [0.0f64; 6];
    for ((j, i), &v) in r.indexed_iter() {
        let (p, t, x) = (f.p[[j, i]], f.theta[[j, i]], g.x(i));
        let k = if p > 0.0 {
            if x < 0.0 { 0 } else { 1 }
        } else if t < 1.0 {
            if x < 0.0 { 2 } else { 3 }
        } else if x < 0.0 {
            4
        } else {
            5
        };
        cat[k] += v * v;
    }
    println!(
        "rms share: full in {:.2e} full out {:.2e} partial in {:.2e} partial out {:.2e} P0θ1 in {:.2e} P0θ1 out {:.2e}",
        cat[0].sqrt(),
        cat[1].sqrt(),
        cat[2].sqrt(),
        cat[3].sqrt(),
        cat[4].sqrt(),
        cat[5].sqrt()
    );
    let mut v: Vec<((usize, usize), f64)> = r.indexed_iter().map(|(ix, v)| (ix, *v)).collect();
    v.sort_by(|a, b| b.1.abs().partial_cmp(&a.1.abs()).unwrap());
    for ((j, i), m) in v.iter().take(12) {
        println!(
            "r {m:+.2e} at i {i} j {j} x={:.3} y={:.3} P={:.3e} H={:.4e} th={:.3}",
            g.x(*i),
            g.y(*j),
            s.pressure()[[*j, *i]],
            s.film()[[*j, *i]],
            s.theta()[[*j, *i]]
        );
    }
}

fn col0() -> usize {
    std::env::var("COL").map(|v| v.parse().unwrap()).unwrap_or(25)
}

/// The discrete mass flow through each cross-section `x_{i+1/2}` (Couette by the scheme's
/// upwind flux, Poiseuille by the half-point `ε̄`), summed over the rows.
pub fn flows(s: &ReynoldsSolver, prm: &ReynoldsParams) {
    let f = s.finest();
    let (eps, rt) = f.coefficients(prm);
    let g = s.grid();
    let h = g.dx();
    for i in (1..g.nx - 1).step_by(g.nx / 16) {
        let mut couette = 0.0;
        let mut pois = 0.0;
        for j in 1..g.ny - 1 {
            let q = |k: usize| rt[[j, k]] * f.film[[j, k]];
            couette += (1.5 * q(i) - 0.5 * q(i - 1)) * h;
            pois +=
                -0.5 * (eps[[j, i]] + eps[[j, i + 1]]) * (f.p[[j, i + 1]] - f.p[[j, i]]) / h * h;
        }
        println!(
            "x {:.3}: couette {couette:.4e} poiseuille {pois:.4e} total {:.4e}",
            g.x(i) + 0.5 * h,
            couette + pois
        );
    }
}

/// A profile across at `x`.
pub fn across(s: &ReynoldsSolver, x: f64) {
    let g = s.grid();
    let i = g.col_nearest(x);
    for j in (g.ny / 2..g.ny).step_by(4) {
        println!(
            "y {:.3} P {:.3e} H {:.4e} theta {:.4}",
            g.y(j),
            s.pressure()[[j, i]],
            s.film()[[j, i]],
            s.theta()[[j, i]]
        );
    }
}
