//! The dry contact core against Hertz, end to end through the scene runner, and the scene's
//! derived scales against the reference values stored in `reference/hertz.json`.

use ehl_workbench::run_scene;
use serde_json::Value;

fn reference() -> Value {
    let text = include_str!("../../reference/hertz.json");
    serde_json::from_str(text).unwrap()
}

fn hertz_at(n: usize) -> ehl_workbench::DryOutcome {
    let scene = ehl_scene::builtin("hertz").unwrap().with_points(n).unwrap();
    *run_scene(&scene)
        .unwrap()
        .downcast::<ehl_workbench::DryOutcome>()
        .expect("the hertz scene is dry")
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
fn central_pressure_and_approach_at_129_within_their_discretisation_error() {
    let o = hertz_at(129);
    // Measured discretisation errors on 129²: 1.47e-5 (p_max) and -1.75e-5 (approach), second
    // order (xtask convergence dry). 2e-5 holds them (rounding is ~1e-12) and fails a kernel
    // scaled by 1 + 1e-4 or a first-order error (~4x larger here).
    assert!(o.hertz.p_max_error.abs() < 2e-5, "p_max/p_h - 1 = {}", o.hertz.p_max_error);
    assert!(o.hertz.approach_error.abs() < 2e-5, "approach error {}", o.hertz.approach_error);
}

#[test]
fn errors_fall_with_refinement() {
    let (c, f) = (hertz_at(65).hertz, hertz_at(129).hertz);
    // Measured ratios 65² -> 129²: max pressure 3.61, approach 4.37 (second order: 4), pressure
    // L2 1.93, contact radius 2.51 (first order: the contact edge is located to a cell, 2). Each
    // bound sits below its measured ratio and above what one order less would give, so a
    // first-order bug in a second-order quantity fails (ratio 2 < 3), and a zeroth-order one in
    // the others (ratio 1 < 1.6).
    for (what, ec, ef, min_ratio) in [
        ("max pressure", c.p_max_error, f.p_max_error, 3.0),
        ("approach", c.approach_error, f.approach_error, 3.0),
        ("pressure L2", c.pressure_l2_error, f.pressure_l2_error, 1.6),
        ("contact radius", c.contact_radius_error, f.contact_radius_error, 1.6),
    ] {
        assert!(
            ef.abs() * min_ratio < ec.abs(),
            "{what}: {ec:e} on 65^2 -> {ef:e} on 129^2 (ratio {} < {min_ratio})",
            ec / ef
        );
    }
}

#[test]
fn pressure_is_hertzian_and_centred() {
    let o = hertz_at(65);
    // L2 distance to sqrt(1 - r²), measured 6.2e-3 on 65² (first order: the edge cells); 7e-3.
    assert!(o.hertz.pressure_l2_error.abs() < 7e-3, "{}", o.hertz.pressure_l2_error);
    // The centre of pressure: an off-by-one in the kernel's offsets shifts it by ~a cell (0.04 a);
    // symmetric rounding leaves ~1e-15.
    let (mut mx, mut my, mut m) = (0.0, 0.0, 0.0);
    for ((j, i), &p) in o.p.indexed_iter() {
        mx += p * o.grid.x(i);
        my += p * o.grid.y(j);
        m += p;
    }
    assert!((mx / m).abs() < 1e-10 && (my / m).abs() < 1e-10, "centre ({}, {})", mx / m, my / m);
}
