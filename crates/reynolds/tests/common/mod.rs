//! The reference cases of the Reynolds tests (and of the `m20` probe).
#![allow(dead_code)] // each test file uses what it needs

use ehl_core::{Moes, SEED_CONTACT, SEED_LUBRICANT};
use ehl_reynolds::*;

/// The classic moderate case `M = 20, L = 10`.
pub fn m20() -> ReynoldsParams {
    moes(20.0, 10.0)
}

/// Roelands `η0 = 40 mPa s`, `p0 = 1.96e8 Pa`, Dowson–Higginson on the seed's ball and load:
/// velocity and `α` follow from `M`, `L`.
pub fn moes(m: f64, l: f64) -> ReynoldsParams {
    ReynoldsParams::from_moes(
        &Moes { m, l },
        &SEED_CONTACT,
        40e-3,
        1.96e8,
        ViscosityLaw::Roelands,
        DensityLaw::DowsonHigginson,
    )
}

/// Seed Table 1: `M ≈ 2223, L ≈ 2.49`, pure rolling at `u1 = 0.01 m/s` (sum velocity 0.02 m/s).
pub fn seed() -> ReynoldsParams {
    seed_at(0.01)
}

/// The seed's contact (Table 1) in pure rolling at `u1` [m/s].
pub fn seed_at(u1: f64) -> ReynoldsParams {
    seed_loaded(u1, SEED_CONTACT.load)
}

/// The seed's contact (Table 1) under `load` [N] in pure rolling at `u1` [m/s].
pub fn seed_loaded(u1: f64, load: f64) -> ReynoldsParams {
    ReynoldsParams::from_si(
        &ehl_core::Contact { load, ..SEED_CONTACT },
        &SEED_LUBRICANT,
        2.0 * u1,
        ViscosityLaw::Roelands,
        DensityLaw::DowsonHigginson,
    )
}

/// The oil through the domain's edges per unit time (Hertz units): what the supply brings in at
/// the inflow face, and what leaves through the four faces, each from the discrete fluxes
/// (Couette by the scheme's upwind face values at the surfaces' speed, Poiseuille by the
/// half-point `ε̄`).
pub fn edge_flows(prm: &ReynoldsParams, s: &ReynoldsSolver) -> (f64, f64) {
    let f = s.finest();
    let (eps, rt) = f.coefficients(prm);
    let (p, film) = (&f.p, &f.film);
    let (ny, nx) = p.dim();
    let (h, u) = (f.h, f.speed);
    let q = |j: usize, i: usize| rt[[j, i]] * film[[j, i]];
    // Poiseuille flux from point a to its neighbour b, through their shared face.
    let pois = |a: (usize, usize), b: (usize, usize)| -0.5 * (eps[a] + eps[b]) * (p[b] - p[a]) / h;
    let supplied: f64 = (1..ny - 1).map(|j| u * q(j, 0) * h).sum();
    let (o, b) = (nx - 2, nx - 1);
    let out_x: f64 = (1..ny - 1)
        .map(|j| {
            let couette = u * (1.5 * q(j, o) - 0.5 * q(j, o - 1));
            (couette + pois((j, o), (j, b)) + pois((j, 1), (j, 0))) * h
        })
        .sum();
    let sides: f64 =
        (1..nx - 1).map(|i| (pois((1, i), (0, i)) + pois((ny - 2, i), (ny - 1, i))) * h).sum();
    (supplied, out_x + sides)
}

/// The oil in the domain, `Σ ρ̄θH h²` over the points the equations hold at (Hertz units).
pub fn oil_held(prm: &ReynoldsParams, s: &ReynoldsSolver) -> f64 {
    let f = s.finest();
    let (ny, nx) = f.p.dim();
    let m = f.rho_film(prm);
    let mut sum = 0.0;
    for j in 1..ny - 1 {
        for i in 1..nx - 1 {
            sum += m[[j, i]];
        }
    }
    sum * f.h * f.h
}

/// The `k` largest residuals of the finest grid by size, each with its `(j, i)` (the probes'
/// diagnosis of a failed solve or step).
pub fn largest_residuals(
    prm: &ReynoldsParams,
    s: &ReynoldsSolver,
    k: usize,
) -> Vec<((usize, usize), f64)> {
    let r = s.finest().residual(prm);
    let mut v: Vec<_> = r.indexed_iter().map(|(ix, v)| (ix, *v)).collect();
    v.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    v.truncate(k);
    v
}
