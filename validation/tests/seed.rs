//! The layer model against the values the seed reports (`reference/seed.json`), in
//! Hertz-normalised form, on grids coarse enough for CI. Each tolerance is the grid's own
//! discretisation error (measured by `cargo xtask convergence layer`) plus the seed's rounding.

use ehl_workbench::{Outcome, layer::LayerOutcome, run_scene};
use serde_json::Value;

fn seed(id: &str) -> f64 {
    let r: Value = serde_json::from_str(include_str!("../../reference/seed.json")).unwrap();
    r["values"].as_array().unwrap().iter().find(|v| v["id"] == id).unwrap()["normalised"]
        .as_f64()
        .unwrap()
}

fn layer(scene: &str, n: usize, edit: impl Fn(&mut ehl_scene::Scene)) -> LayerOutcome {
    let mut s = ehl_scene::builtin(scene).unwrap().with_points(n).unwrap();
    s.run.as_mut().unwrap().snapshots_s.clear();
    s.run.as_mut().unwrap().snapshots_a.clear();
    edit(&mut s);
    *run_scene(&s).unwrap().downcast::<LayerOutcome>().expect("a layer scene")
}

#[test]
fn steady_squeeze_matches_the_seed() {
    let o = layer("squeeze-steady", 65, |_| {});
    let (f, s, ob) = (&o.final_monitor, &o.scales, o.observables());
    // Maximum pressure: the seed's 0.5083 GPa / 0.509 GPa = 0.9986 p_h; ours is 0.9983 on
    // 257² and within 0.3% on 65². 0.5% covers the grid and the seed's 4-digit rounding.
    let p = ob.max_pressure_pa / s.p_h;
    assert!((p / seed("squeeze_max_pressure") - 1.0).abs() < 5e-3, "p_max/p_h = {p}");
    // The dry zone is counted in cells along y = 0, the contact extent interpolated at 1 % of
    // p_h: ±1 cell per edge is ΔX/a = 0.039 of 2a.
    let d = ob.contact_extent_x_m / (2.0 * s.a);
    assert!((d - seed("squeeze_contact_diameter")).abs() < 0.04, "contact diameter/2a = {d}");
    let dd = f.dry_diameter / (2.0 * s.a);
    assert!((dd - seed("squeeze_dry_diameter")).abs() < 0.04, "dry diameter/2a = {dd}");
}

#[test]
fn steady_rolling_central_thickness_matches_the_seed() {
    // 129², n_t = 5 (time error < 0.05 nm). Our converged value sits 4.3% below the seed's
    // 11.6 nm (11.10 nm on 257²; the lost laws and the coefficient smoothing, see docs/layer.md); the
    // grid adds +1.2% at 129² (11.23 nm). 6% bounds that deviation, not more.
    let o = layer("rolling-from-uniform", 129, |s| {
        s.run.as_mut().unwrap().time.steps_per_cell = 5.0;
    });
    assert!(o.record.as_ref().unwrap().finished);
    let hc = o.final_monitor.central_thickness / o.supply_thickness_m();
    let want = seed("rolling_central_thickness");
    assert!((hc / want - 1.0).abs() < 0.06, "h_c/l0 = {hc} against the seed's {want}");
}

#[test]
fn rolling_from_squeezed_and_from_uniform_reach_the_same_steady_state() {
    let edit = |s: &mut ehl_scene::Scene| s.run.as_mut().unwrap().time.steps_per_cell = 5.0;
    let a = layer("rolling-from-uniform", 65, edit);
    let b = layer("rolling-from-squeezed", 65, edit);
    let (fa, fb) = (&a.final_monitor, &b.final_monitor);
    // Both stop when nothing changes by more than 1e-3 l0 over 0.5 a of travel; they must agree
    // to a few times that.
    let l0 = a.supply_thickness_m();
    assert!((fa.central_thickness - fb.central_thickness).abs() < 5e-3 * l0);
    assert!((fa.minimum_thickness - fb.minimum_thickness).abs() < 5e-3 * l0);
}

#[test]
fn squeeze_after_stop_ends_in_the_direct_steady_squeeze() {
    // The time-dependent squeeze (error-controlled BDF2) must end where the direct solve of
    // eps = min(p/Eo, 1) is: the steady squeeze is independent of the damper and of history.
    let dynamic = layer("squeeze-after-stop", 33, |_| {});
    let direct = layer("squeeze-steady", 33, |_| {});
    assert!(dynamic.record.as_ref().unwrap().finished);
    let (a, b) = (&dynamic.final_monitor, &direct.final_monitor);
    let (oa, ob) = (dynamic.observables(), direct.observables());
    // The run stops when nothing changes by 1e-3 (per p_h) over 0.5 s; the remaining relaxation
    // is below that, so 2e-3 p_h bounds the difference of maximum pressures, and 1e-3 of 2a
    // that of the contact extents (the same stop rule watches it).
    assert!((oa.max_pressure_pa - ob.max_pressure_pa).abs() < 2e-3 * dynamic.scales.p_h);
    let two_a = 2.0 * dynamic.scales.a;
    assert!((oa.contact_extent_x_m - ob.contact_extent_x_m).abs() < 1e-3 * two_a);
    assert!(
        (a.dry_diameter - b.dry_diameter).abs() <= dynamic.grid.dx() * dynamic.scales.a + 1e-12
    );
}

#[test]
fn a_stop_mid_run_rolls_to_it_then_ends_in_the_same_steady_squeeze() {
    // Steady rolling, 20 ms more of it (19 cells of travel on 33², 190 steps), then a sudden
    // stop: the squeeze after it forgets the history and ends where the direct steady squeeze
    // is, as the stop at t = 0 does (the test above; same bounds, same reasons).
    let stop = 0.02;
    let o = layer("squeeze-after-stop", 33, |s| {
        s.run.as_mut().unwrap().motion = ehl_scene::Motion::StopAt { at_s: stop };
    });
    let direct = layer("squeeze-steady", 33, |_| {});
    let rec = o.record.as_ref().unwrap();
    assert!(rec.finished, "{}", rec.stop_reason);
    let (a, b) = (&o.final_monitor, &direct.final_monitor);
    let (oa, ob) = (o.observables(), direct.observables());
    assert!((oa.max_pressure_pa - ob.max_pressure_pa).abs() < 2e-3 * o.scales.p_h);
    let two_a = 2.0 * o.scales.a;
    assert!((oa.contact_extent_x_m - ob.contact_extent_x_m).abs() < 1e-3 * two_a);
    assert!((a.dry_diameter - b.dry_diameter).abs() <= o.grid.dx() * o.scales.a + 1e-12);
    // While it rolled, the steps were the rolling ones (10 a cell at 0.01 m/s, about 0.1 ms,
    // equal steps landing on the stop); the steady rule waited a window after the stop. A
    // stop read as one at t = 0 rolls no step; one never reached never becomes steady.
    let rolled = rec.observed.iter().filter(|(t, _)| *t <= stop * (1.0 + 1e-12)).count() - 1;
    let cells = 0.01 * stop / (o.grid.dx() * o.scales.a);
    assert_eq!(rolled as f64, (10.0 * cells - 1e-9).ceil(), "steps while rolling");
    assert!(o.final_state.t > stop + 0.5, "steady only a window after the stop");
}

#[test]
fn hole_central_pressure_drop_matches_the_seed() {
    // The hole (radius 0.2 a) centred at x = 0 at t = 1.45 a / u1; its drop of the central
    // pressure against the steady rolling state it passes through (the run's start).
    let o = layer("hole", 129, |s| {
        let r = s.run.as_mut().unwrap();
        r.stop.until_features_passed = false;
        r.stop.until_feature_at_a = Some(0.0);
    });
    let steady = layer("rolling-steady", 129, |_| {});
    let drop = 1.0 - o.final_monitor.central_pressure / steady.final_monitor.central_pressure;
    let want = seed("hole_central_pressure_drop");
    // Measured: 2.26 % on 129², 2.28 % on 257² (the grid moves it by 0.02 points); the seed
    // prints "≈ 2.3 %" (±0.05 points). 0.1 points holds both; no hole, or a hole the transport
    // smeared or lost, drops by 0 or by several points.
    assert!((drop - want).abs() < 1e-3, "drop {drop} against the seed's {want}");
}

#[test]
fn seed_fit_laws_reproduce_the_recorded_fit() {
    // The `seed-fit` law set (reference/seed-fit.json's `laws`, written by `cargo xtask
    // identify`) run through a scene must give the steady-rolling h_c the fit recorded on its
    // own grid: the same solve (direct steady, strain tolerance 1e-5, h_c converged to ~2e-5
    // l0) on the same grid, so 1e-4 relative bounds run-to-run rounding and nothing else; a law
    // set not wired through (κ or σ ignored) moves h_c by percents.
    let r: Value = serde_json::from_str(include_str!("../../reference/seed-fit.json")).unwrap();
    let n = r["grids"]["rolling"].as_u64().unwrap() as usize;
    let want = r["targets"][0]["seed_fit_fit_grid"].as_f64().unwrap();
    let o = layer("rolling-steady", n, |s| {
        let l = s.layer.as_mut().unwrap();
        l.laws = ehl_layer::LawSet::SeedFit;
        l.damper_constant = None;
    });
    let hc = o.final_monitor.central_thickness / o.supply_thickness_m();
    assert!((hc / want - 1.0).abs() < 1e-4, "h_c/l0 = {hc}, recorded {want}");
    let recon = layer("rolling-steady", n, |_| {});
    let h0 = recon.final_monitor.central_thickness / recon.supply_thickness_m();
    assert!((hc / h0 - 1.0).abs() > 0.01, "seed-fit {hc} against reconstruction {h0}");
}
