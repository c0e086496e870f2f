//! Centreline snapshots of every built-in scene on a coarse grid.
//!
//! Values are Hertz-normalised (`x/a`, `p/p_h`, `h/(a²/R)`) and printed to 5 decimals after a
//! solve to 1e-11: the solver's own spread (~1e-11) and cross-machine FFT rounding (~1e-15) sit
//! six orders below the printed digit, so the snapshot changes only when the numbers do.

use ehl_cli::{Outcome, run_scene};

fn fmt(v: f64) -> String {
    let s = format!("{v:.5}");
    if s == "-0.00000" { "0.00000".into() } else { s }
}

#[test]
fn builtin_scene_centrelines() {
    for scene in ehl_scene::builtins() {
        let mut scene = scene.with_points(33).unwrap();
        scene.solver.tolerance = 1e-11;
        let outcome = run_scene(&scene).unwrap();
        let text = match &outcome {
            Outcome::Dry(o) => {
                let j = o.grid.row_nearest(0.0);
                let mut s = String::from("x/a, p/p_h, h/(a^2/R)\n");
                for i in 0..o.grid.nx {
                    s += &format!(
                        "{}, {}, {}\n",
                        fmt(o.grid.x(i)),
                        fmt(o.p[[j, i]]),
                        fmt(o.gap[[j, i]])
                    );
                }
                s
            }
        };
        insta::assert_snapshot!(format!("centreline_{}", scene.name), text);
    }
}
