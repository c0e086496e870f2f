//! Probe for a dent through the fed seed contact: `deepdent N STEPS_PER_CELL STEPS [A]` marches
//! the seed's conditions (Table 1, 25 nm supplied, [-1.25, 1.25]² on N²) with a dent of
//! `A l0` (default 1000: the seed's deep dent, `W` = 0.1 a) entering at −1.25 a, and prints each
//! step's cycles and films; on a failure, the centre line round the dent and the largest
//! residuals. Environment: FLOODED=1 no supply; LOG=1 every cycle; DUMP=1 the centre line round
//! the dent after each step; COARSEST (points: 129 on 129² is relaxation alone), PRE, MAXC,
//! GAMMA, OMEGA (Gauss–Seidel), THR and TTHR (the relaxation switch's thresholds), EXTRA=1 (the steps' extra passes) override the settings.
//! `WAVE=A_nm,λ_a[,edge_a]`: a transverse wave instead of the dent, rolling in over the smooth
//! contact from `edge_a` when given (`STEPS_PER_CELL` and `STEPS` as for the dent; 0 steps: the
//! steady solve alone); `FILMTOL` the steps' film tolerance (`STEPFILM` the whole film's); `ONE=1` the first attempt alone,
//! `NOCONTACT=1` the lubricated cycles alone; `BDF2=1` second-order steps; `NEG=1` lists the
//! closed and touching points; `AROUND=1`, on a failure, the points round the largest residuals; `AHEAD` the points
//! the centre line's dumps show downstream of the dent's centre (8); `DENTY` the dent's `y` (a);
//! `NOCARRY=1` each step started from the last state; `LASTMAXC` the last step's cycle limit.
#[path = "../tests/common/mod.rs"]
mod common;

use ehl_core::{Dent, Grid};
use ehl_reynolds::*;

fn main() {
    let arg =
        |k: usize, d: f64| std::env::args().nth(k).map_or(d, |s| s.parse().expect("a number"));
    let (n, per_cell, steps, amplitude) =
        (arg(1, 129.0) as usize, arg(2, 1.0), arg(3, 10.0) as usize, arg(4, 1000.0));
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<usize>().ok());
    let prm = common::seed();
    let grid = Grid::new(n, n, (-1.25, 1.25), (-1.25, 1.25));
    let delta = prm.scales.delta;
    let mut settings = ReynoldsSettings::default();
    settings.coarsest_points = env("COARSEST").unwrap_or(settings.coarsest_points);
    settings.step_pre_sweeps = env("PRE").unwrap_or(settings.step_pre_sweeps);
    settings.step_max_cycles = env("MAXC").unwrap_or(settings.step_max_cycles);
    settings.step_extra_passes = std::env::var("EXTRA").is_ok();
    settings.extrapolated_start = std::env::var("NOCARRY").is_err();
    if let Some(w) = std::env::var("OMEGA").ok().and_then(|v| v.parse().ok()) {
        settings.relax.omega_gs = w;
    }
    if let Some(t) = std::env::var("TTHR").ok().and_then(|v| v.parse().ok()) {
        settings.relax.transient_threshold = Some(t);
    }
    if let Some(t) = std::env::var("THR").ok().and_then(|v| v.parse().ok()) {
        settings.relax.distributive_threshold = t;
    }
    if let Some(g) = env("GAMMA") {
        settings.step_gamma = g;
    }
    if std::env::var("BDF2").is_ok() {
        settings.time_scheme = TimeScheme::Bdf2;
    }
    let mut s = ReynoldsSolver::new(grid, prm, settings);
    let y_a = std::env::var("DENTY").ok().map_or(0.0, |v| v.parse().expect("DENTY: a"));
    let dent = Dent { depth_m: amplitude * 25e-9, width_a: 0.1, x_start_a: -1.25, y_a };
    // WAVE=A_nm,λ_a: transverse waviness instead of the dent (the march's start, as scenes
    // solve it: the coarser grids holding the film content).
    let wave: Option<ehl_core::Waviness> = std::env::var("WAVE").ok().map(|v| {
        let mut it = v.split(',').map(|x| x.parse::<f64>().expect("WAVE: A_nm,λ_a[,edge_a]"));
        let (amplitude_m, wavelength_a) = (it.next().expect("A") * 1e-9, it.next().expect("λ"));
        let w = ehl_core::Waviness {
            amplitude_m,
            wavelength_a,
            angle_rad: 0.0,
            phase_rad: 0.0,
            edge_a: None,
        };
        it.next().map_or(w, |e| w.entering_at(e))
    });
    let wave_gap = move |x: f64, travel: f64| wave.map_or(0.0, |w| w.gap(x, 0.0, travel, delta));
    if let Some(t) = std::env::var("FILMTOL").ok().and_then(|v| v.parse().ok()) {
        s.settings.film_tolerance = t;
    }
    if let Some(t) = std::env::var("STEPFILM").ok().and_then(|v| v.parse().ok()) {
        s.settings.step_film_tolerance = t;
    }
    if wave.is_some() {
        s.settings.coarse_film_content = false;
        s.set_extra_gap(move |x, _| wave_gap(x, 0.0));
    }
    if std::env::var("FLOODED").is_err() {
        let h_oil = 25e-9 / delta;
        s.set_supply(Some(&move |_y| h_oil));
    }
    if std::env::var("ONE").is_ok() {
        s.settings.fallback_lag = 0.0;
        s.settings.flooded_start_fallback = false;
        s.settings.filled_inflow_fallback = false;
        s.settings.max_cycles = env("MAXC").unwrap_or(200);
    }
    if std::env::var("NOCONTACT").is_ok() {
        s.settings.contact = false;
        s.settings.max_cycles = env("MAXC").unwrap_or(60);
    }
    let (log, dump) = (std::env::var("LOG").is_ok(), std::env::var("DUMP").is_ok());
    // One line a cycle, the steady solve's and the steps' alike.
    let show = |c: &CycleLog| {
        if log {
            println!(
                "   {:>3} on {}²: residual {:.3e}, load {:+.3e}, h_c {:.6}, oil {:.2e}, h00 {:.6}",
                c.cycle, c.points, c.residual, c.load_error, c.central_film, c.mass_defect, c.h00
            )
        }
    };
    let r = s.solve(&mut |c| show(c));
    println!("steady: {:?}, films {:?} a²/R", r.as_ref().map(|r| r.cycles), s.films());
    if std::env::var("NEG").is_ok() {
        let l = s.finest();
        for ((j, i), &h) in l.film.indexed_iter() {
            if h < 0.0 || l.contact[[j, i]] {
                println!(
                    "  closed at x {:.3} y {:.3}: H {:.3e} P {:.3e} θ {:.3} contact {}",
                    grid.x(i),
                    grid.y(j),
                    h,
                    l.p[[j, i]],
                    l.theta[[j, i]],
                    l.contact[[j, i]]
                );
            }
        }
    }
    let dt = grid.dx() / per_cell;
    let jc = grid.row_nearest(0.0);
    let line = |s: &ReynoldsSolver, xc: f64, r: Option<&ndarray::Array2<f64>>| {
        let (l, ic) = (s.finest(), grid.col_nearest(xc));
        let ahead = std::env::var("AHEAD").ok().and_then(|v| v.parse::<usize>().ok()).unwrap_or(8);
        for i in ic.saturating_sub(8)..(ic + ahead).min(n) {
            let res = r.map_or(String::new(), |r| format!(" res {:+.2e}", r[[jc, i]]));
            println!(
                "  x {:.3} P {:.3e} θ {:.3e} H {:.3e}{res}",
                grid.x(i),
                l.p[[jc, i]],
                l.theta[[jc, i]],
                l.film[[jc, i]]
            );
        }
    };
    for k in 1..=steps {
        let xc = -1.25 + k as f64 * dt;
        if wave.is_some() {
            s.set_extra_gap(move |x, _| wave_gap(x, xc + 1.25));
        } else {
            s.set_extra_gap(move |x, y| dent.gap(x, y, xc, delta));
        }
        if k == steps {
            s.settings.step_max_cycles = env("LASTMAXC").unwrap_or(s.settings.step_max_cycles);
        }
        let t = std::time::Instant::now();
        let r = s.step(dt, &mut |c| show(c));
        let (hc, hm) = s.films();
        match r {
            Ok(r) => {
                println!(
                    "step {k}, dent at {xc:.3} a: {} cycles, {:.2} s; h_c {:.3} nm, h_min {:.3} nm, P_max {:.3}",
                    r.cycles,
                    t.elapsed().as_secs_f64(),
                    hc * delta * 1e9,
                    hm * delta * 1e9,
                    s.pressure().iter().cloned().fold(0.0, f64::max)
                );
                if dump {
                    line(&s, xc, None);
                }
            }
            Err(e) => {
                println!("step {k}, dent at {xc:.3} a: {e}");
                let r = s.finest().residual(&prm);
                line(&s, xc, Some(&r));
                for ((j, i), m) in common::largest_residuals(&prm, &s, 3) {
                    println!(
                        "  largest residual {m:+.2e} at x = {:.3} a, y = {:.3} a",
                        grid.x(i),
                        grid.y(j)
                    );
                    if std::env::var("AROUND").is_ok() {
                        let l = s.finest();
                        for jj in j - 1..=j + 1 {
                            for ii in i - 2..=i + 2 {
                                println!(
                                    "    ({:.3},{:.3}) P {:.2e} θ {:.3} H {:+.2e} c {} res {:+.2e}",
                                    grid.x(ii),
                                    grid.y(jj),
                                    l.p[[jj, ii]],
                                    l.theta[[jj, ii]],
                                    l.film[[jj, ii]],
                                    u8::from(l.contact[[jj, ii]]),
                                    r[[jj, ii]]
                                );
                            }
                        }
                    }
                }
                break;
            }
        }
    }
}
