//! Probe for the starved, mass-conserving solver: `starved N H_OIL_NM...` solves the seed's
//! conditions (Table 1, u = 0.01 m/s, [-1.25, 1.25]²) on N², flooded (the clamp) and fed each
//! supply, and prints the central film, `ρ̄(p_c) h_c` against the supply, `R` and the inlet
//! meniscus on the centre line. `M20=1`: Moes' M = 20, L = 10 on [-4.5, 1.5] × [-3, 3] instead.
//! Each solve prints its cycles and the attempts its cascade ran. `LOG=1` prints every cycle
//! (residual, load error, central film, the oil unaccounted for);
//! `POIS=ratio` sets `relax.poiseuille_full_step`; `OMEGA`, `LAG` the Gauss–Seidel changes'
//! under-relaxation (`FEDOMEGA` the fed solve's) and the laws' lag; `U=m/s` the rolling speed `u1` of the seed's
//! contact (`LOAD=N` its load); `MAXC`, `GAIN`, `WC`, `JUMPS`, `MENP` the cycle limit, the `H00`
//! gain, the gap's under-relaxation, the slow mode's jump cap (0: none) and the meniscus passes (`COLS=0`: no column pass); `GAMMA`
//! the fed solves' cycle (1: V-cycles, 2: W-cycles; the flooded solve keeps the default), `PRE` their
//! pre-sweeps; `MASS`,
//! `FILMTOL` the stop rule's oil and film tolerances; `DOMAIN=x0,x1,y0,y1` the domain [a]
//! (square cells); `ROW=y,x0,x1` a row's state after the solve, `MINAT=1` where the film is thinnest, `DUMP=path` every finest-grid
//! point's `j i P θ H residual` as text; a failure prints the largest
//! residuals and where. `DRY=1`: the attempt from the dry contact alone; `FED=1`: no flooded
//! solve first.
#[path = "../tests/common/mod.rs"]
mod common;

use ehl_core::Grid;
use ehl_reynolds::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().expect("N")).unwrap_or(129);
    let supplies: Vec<f64> = args.iter().skip(2).map(|s| s.parse().expect("nm")).collect();
    let m20 = std::env::var("M20").is_ok();
    let u1: Option<f64> = std::env::var("U").ok().map(|v| v.parse().expect("U: m/s"));
    let prm = match (m20, u1) {
        (true, _) => common::m20(),
        (false, Some(u)) => common::seed_loaded(
            u,
            std::env::var("LOAD").map_or(20.0, |v| v.parse().expect("LOAD: N")),
        ),
        (false, None) => common::seed(),
    };
    let domain: Option<Vec<f64>> = std::env::var("DOMAIN")
        .ok()
        .map(|v| v.split(',').map(|t| t.parse().expect("DOMAIN: x0,x1,y0,y1 [a]")).collect());
    let grid = if let Some(d) = domain {
        Grid::new(n, n, (d[0], d[1]), (d[2], d[3]))
    } else if m20 {
        Grid::new(n, n, (-4.5, 1.5), (-3.0, 3.0))
    } else {
        Grid::new(n, n, (-1.25, 1.25), (-1.25, 1.25))
    };
    let delta = prm.scales.delta;
    {
        // The flooded film the grid rule reads, against the cells this grid has.
        let hc = formulas::moes_to_hertz_film(formulas::nvm_central_moes(&prm.moes), &prm.moes);
        println!(
            "NVM central film {:.3e} a²/R ({:.3} nm): cell {:.4} a, the rule's {:.4} a, dry gap error {:.3e} a²/R",
            hc,
            hc * delta * 1e9,
            grid.dx(),
            formulas::cell_needed(hc),
            formulas::dry_gap_error(grid.dx())
        );
    }
    let log = std::env::var("LOG").is_ok();
    let solve = |h_oil_nm: Option<f64>| {
        let mut settings = ReynoldsSettings::default();
        if let Ok(v) = std::env::var("POIS") {
            settings.relax.poiseuille_full_step = v.parse().expect("POIS: a ratio");
        }
        if let Ok(v) = std::env::var("MAXC") {
            settings.max_cycles = v.parse().expect("MAXC: cycles");
        }
        if let Ok(v) = std::env::var("GAIN") {
            settings.h00_gain = v.parse().expect("GAIN");
        }
        if let Ok(v) = std::env::var("OMEGA") {
            settings.relax.omega_gs = v.parse().expect("OMEGA: Gauss-Seidel under-relaxation");
        }
        if let Ok(v) = std::env::var("FEDOMEGA") {
            settings.fed_omega_gs = v.parse().expect("FEDOMEGA: the fed solve's under-relaxation");
        }
        if let Ok(v) = std::env::var("LAG") {
            settings.relax.coefficient_lag = v.parse().expect("LAG: the laws' lag");
        }
        if let Ok(v) = std::env::var("WC") {
            settings.relax.omega_contact = v.parse().expect("WC");
        }
        if let Ok(v) = std::env::var("GAMMA")
            && h_oil_nm.is_some()
        {
            settings.gamma = v.parse().expect("GAMMA");
        }
        if let Ok(v) = std::env::var("PRE")
            && h_oil_nm.is_some()
        {
            settings.pre_sweeps = v.parse().expect("PRE: the fed solves' pre-sweeps");
        }
        if let Ok(v) = std::env::var("COLS") {
            settings.relax.column_pass = v != "0";
        }
        if let Ok(v) = std::env::var("MENP") {
            settings.relax.meniscus_passes = v.parse().expect("MENP");
        }
        if let Ok(v) = std::env::var("MASS") {
            settings.mass_tolerance = v.parse().expect("MASS: a share");
        }
        if let Ok(v) = std::env::var("FILMTOL") {
            settings.film_tolerance = v.parse().expect("FILMTOL: relative");
        }
        if let Ok(v) = std::env::var("CFC") {
            settings.coarse_film_content = v == "1";
        }
        if let Ok(v) = std::env::var("COARSEST") {
            settings.coarsest_points = v.parse().expect("COARSEST: points");
        }
        if let Ok(v) = std::env::var("JUMPS") {
            settings.mode_extrapolation = v.parse().expect("JUMPS: a cap");
        }
        let mut s = ReynoldsSolver::new(grid, prm, settings);
        if let Some(h) = h_oil_nm {
            let hd = h * 1e-9 / delta;
            s.set_supply(Some(&move |_y| hd));
        }
        let t = std::time::Instant::now();
        let mut logf = |c: &CycleLog| {
            if log {
                println!(
                    "  cycle {} on {}²: residual {:.3e}, load {:.2e}, h_c {:.5e}, h_min {:.4e}, oil {:.2e}",
                    c.cycle,
                    c.points,
                    c.residual,
                    c.load_error,
                    c.central_film,
                    c.minimum_film,
                    c.mass_defect
                )
            }
        };
        let r = if std::env::var("DRY").is_ok() {
            s.solve_from_dry(&mut logf)
        } else {
            s.solve(&mut logf)
        };
        // A point's place and state on the finest grid, in one line.
        let point = |j: usize, i: usize| {
            let f = s.finest();
            format!(
                "x = {:.3} a, y = {:.3} a: P {:.4e}, θ {:.3e}, H {:+.3e}, contact {}",
                grid.x(i),
                grid.y(j),
                f.p[[j, i]],
                f.theta[[j, i]],
                f.film[[j, i]],
                f.contact[[j, i]]
            )
        };
        if let Ok(at) = std::env::var("ROW") {
            // `ROW=y,x0,x1`: the row nearest y [a] from x0 to x1 [a].
            let v: Vec<f64> = at.split(',').map(|t| t.parse().expect("ROW: y,x0,x1")).collect();
            let (j, r) = (grid.row_nearest(v[0]), s.finest().residual(&prm));
            for i in grid.col_nearest(v[1])..=grid.col_nearest(v[2]) {
                println!("  {}, residual {:+.2e}", point(j, i), r[[j, i]]);
            }
        }
        if let Ok(path) = std::env::var("DUMP") {
            use std::io::Write;
            let f = s.finest();
            let r = f.residual(&prm);
            let mut out = std::io::BufWriter::new(std::fs::File::create(&path).expect("DUMP"));
            for ((j, i), v) in r.indexed_iter() {
                writeln!(
                    out,
                    "{j} {i} {:.6e} {:.6e} {:.6e} {:.6e}",
                    f.p[[j, i]],
                    f.theta[[j, i]],
                    f.film[[j, i]],
                    v
                )
                .unwrap();
            }
        }
        if std::env::var("MINAT").is_ok() {
            let f = s.finest();
            let ((j, i), m) = f
                .film
                .indexed_iter()
                .fold(((0, 0), f64::INFINITY), |a, (ix, &v)| if v < a.1 { (ix, v) } else { a });
            println!("  minimum film {m:.3e} a²/R at {}", point(j, i));
        }
        let (hc, _) = s.films();
        let (j, i) = (grid.row_nearest(0.0), grid.col_nearest(0.0));
        let rho = prm.density.rho(s.pressure()[[j, i]]);
        let th = s.theta();
        let meniscus =
            (0..=i).rev().find(|&k| th[[j, k]] < 1.0).map_or(grid.x(0), |k| grid.x(k + 1));
        if let Some(b) = s.oil_balance() {
            let q = b.supplied;
            println!(
                "  oil (of the supply): carried out {:.4e}, pressed out {:.2e}, into the contact {:.4e}, stored {:.2e}, unaccounted {:.2e}; balance {:.2e}",
                b.carried_out / q,
                b.pressed_out / q,
                b.into_contact / q,
                b.stored / q,
                b.unaccounted / q,
                (q - b.carried_out - b.pressed_out - b.into_contact - b.stored - b.unaccounted) / q
            );
        }
        match &r {
            Ok(r) => println!(
                "supply {h_oil_nm:?} nm: {} cycles ({} attempts{}{}), {:.2} s; h_c {:.3} nm, ρ̄ h_c {:.3} nm, meniscus {meniscus:.3} a",
                r.cycles,
                r.attempts,
                if r.inflow_filled { ", the inflow filled" } else { "" },
                if r.converged { "" } else { ", not converged" },
                t.elapsed().as_secs_f64(),
                hc * delta * 1e9,
                rho * hc * delta * 1e9
            ),
            Err(e) => {
                println!("supply {h_oil_nm:?} nm: {e}");
                for ((j, i), m) in common::largest_residuals(&prm, &s, 4) {
                    println!("  residual {m:+.2e} at {}", point(j, i));
                }
            }
        }
        hc
    };
    // `FED=1`: the fed solves alone (a profile of their cycles without the flooded one's).
    let flooded = if std::env::var("FED").is_ok() { f64::NAN } else { solve(None) };
    for h in supplies {
        println!("  R = {:.4}", solve(Some(h)) / flooded);
    }
}
