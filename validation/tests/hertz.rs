//! The dry contact core against Hertz, end to end through the scene runner, and the scene's
//! derived scales against the reference values stored in `reference/hertz.json`.

use ehl_cli::{Outcome, run_scene};
use serde_json::Value;

fn reference() -> Value {
    let text = include_str!("../../reference/hertz.json");
    serde_json::from_str(text).unwrap()
}

fn hertz_at(n: usize) -> ehl_cli::DryOutcome {
    let scene = ehl_scene::builtin("hertz").unwrap().with_points(n).unwrap();
    match run_scene(&scene).unwrap() {
        Outcome::Dry(o) => o,
        _ => unreachable!("the hertz scene is dry"),
    }
}

#[test]
fn scales_match_the_published_values() {
    let r = reference();
    let o = hertz_at(33);
    for (key, value) in [
        ("contact_radius_a_m", o.scales.a),
        ("max_pressure_p_h_pa", o.scales.p_h),
        ("approach_m", o.scales.delta),
    ] {
        let v = &r["values"][key];
        let expected = v["value"].as_f64().unwrap();
        let digits = v["digits"].as_i64().unwrap() as i32;
        // The reference prints `digits` significant figures: agree to half a unit in the last.
        let tol = 0.5 * 10f64.powi(expected.abs().log10().floor() as i32 - digits + 1);
        assert!((value - expected).abs() <= tol, "{key}: {value} vs {expected} ± {tol}");
    }
}

#[test]
fn central_pressure_at_129_within_1e_4() {
    let o = hertz_at(129);
    // Measured discretisation error on 129² is 1.5e-5 (xtask convergence dry); the bound the
    // issue sets, 1e-4, leaves room for other machines' rounding but not for a wrong kernel.
    assert!(o.hertz.p_max_error.abs() < 1e-4, "p_max/p_h - 1 = {}", o.hertz.p_max_error);
    assert!(o.hertz.approach_error.abs() < 1e-4, "approach error {}", o.hertz.approach_error);
}

#[test]
fn errors_fall_with_refinement() {
    let (c, f) = (hertz_at(65).hertz, hertz_at(129).hertz);
    // Observed orders are ~2 (max pressure, approach) and ~1 (L2, contact radius): halving the
    // spacing must cut each error by at least 1.5x (order > 0.58). The area-counted contact
    // radius jumps as rings of cells enter the contact and is not monotone below 65².
    for (what, ec, ef) in [
        ("max pressure", c.p_max_error, f.p_max_error),
        ("approach", c.approach_error, f.approach_error),
        ("pressure L2", c.pressure_l2_error, f.pressure_l2_error),
        ("contact radius", c.contact_radius_error, f.contact_radius_error),
    ] {
        assert!(ef.abs() * 1.5 < ec.abs(), "{what}: {ec:e} on 65^2 -> {ef:e} on 129^2");
    }
}

#[test]
fn load_is_carried() {
    let o = hertz_at(65);
    let load = o.p.sum() * o.grid.cell_area();
    assert!((load / (2.0 * std::f64::consts::PI / 3.0) - 1.0).abs() < 1e-12);
}
