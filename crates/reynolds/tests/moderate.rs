//! The FAS solver on the classic moderate case M = 20, L = 10 (Roelands, Dowson–Higginson) on
//! a coarse grid: it must converge (central film settled to 1e-4 per cycle, force balance to
//! 1e-6) and land near the Nijenbanning–Venner–Moes fit; and the seed's high-load regime.

mod common;

use ehl_core::Grid;
use ehl_reynolds::formulas::{moes_to_hertz_film, nvm_central_moes};
use ehl_reynolds::*;

#[test]
fn m20_l10_converges_on_65_and_is_near_nvm() {
    let prm = common::m20();
    let grid = Grid::new(65, 65, (-4.5, 1.5), (-3.0, 3.0));
    let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
    let rep = s.solve(&mut |_| {}).unwrap();
    assert!(rep.converged, "not converged in {} cycles", rep.cycles);
    let (hc, hmin) = s.films();
    let nvm = moes_to_hertz_film(nvm_central_moes(&prm.moes), &prm.moes);
    // NVM is a curve fit good to several percent; 65² over 6 a has ΔX = 0.094 a, whose
    // discretisation error in H_c is a few percent more (0.409 on 65², 0.419 on 129²).
    assert!((hc / nvm - 1.0).abs() < 0.2, "H_c {hc} vs NVM {nvm}");
    assert!(hmin < hc && hmin > 0.5 * hc, "H_min {hmin} against H_c {hc}");
}

#[test]
fn seed_regime_converges_on_257_near_the_seed_film() {
    // The seed's regime, on the layer model's domain [-1.25, 1.25]² (ΔX = 0.0098 a: the inlet
    // zone where the film forms is ~0.03 a wide here, so coarser grids cannot hold this film).
    let prm = common::seed();
    assert!((prm.moes.m - 2223.0).abs() < 1.0 && (prm.moes.l - 2.49).abs() < 0.01);
    let grid = Grid::new(257, 257, (-1.25, 1.25), (-1.25, 1.25));
    let mut s = ReynoldsSolver::new(grid, prm, ReynoldsSettings::default());
    let rep = s.solve(&mut |_| {}).unwrap();
    assert!(rep.converged, "{:?}", rep.diagnosis);
    let (hc, hmin) = s.films();
    let hc_m = hc * prm.scales.delta;
    // The seed reports 12.3 nm on 257 points. Ours: 11.79 nm on 257², 12.30 nm on 513²; the
    // 257² discretisation error is ~5 % by Richardson extrapolation (observed order ~2), and the
    // seed's domain is not stated: 7 % holds the first and leaves the second little room.
    assert!((hc_m / 12.3e-9 - 1.0).abs() < 0.07, "h_c = {hc_m:e} m against the seed's 12.3 nm");
    // Side lobes: the minimum film sits well below the central one (horseshoe).
    assert!(hmin > 0.0 && hmin < 0.5 * hc, "H_min {hmin} against H_c {hc}");
}

#[test]
fn seed_regime_failure_on_a_coarse_grid_is_diagnosed() {
    // On the usual wide domain, 33² cannot hold the seed's 12 nm film (a cell is 0.19 a, the
    // inlet zone 0.03 a): the film closes, and the solver must say so, with what and where.
    let prm = common::seed();
    let grid = Grid::new(33, 33, (-4.5, 1.5), (-3.0, 3.0));
    let settings = ReynoldsSettings { max_cycles: 40, ..ReynoldsSettings::default() };
    let mut s = ReynoldsSolver::new(grid, prm, settings);
    let rep = s.solve(&mut |_| {}).unwrap();
    assert!(!rep.converged);
    let d = rep.diagnosis.expect("a non-converged solve says why");
    assert!(d.contains("cycle"), "{d}");
    assert!(d.contains("film closed") || d.contains("force balance"), "{d}");
}
