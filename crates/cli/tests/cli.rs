//! The `ehl` binary end to end: what it writes, and what it refuses.

use std::process::Command;

fn ehl() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ehl"))
}

#[test]
fn run_writes_every_output_in_si() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("hertz");
    let o = ehl().args(["run", "hertz", "--grid", "33", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("wrote") && stdout.contains(out.to_str().unwrap()), "{stdout}");
    for f in [
        "summary.json",
        "centreline.csv",
        "x_m.npy",
        "y_m.npy",
        "pressure_pa.npy",
        "gap_m.npy",
        "deformation_m.npy",
        "centreline.png",
        "pressure_map.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    assert!(!out.join(".partial").exists());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let p_max = &summary["results"]["max_pressure"];
    assert_eq!(p_max["unit"], "Pa");
    // 33² is coarse: Hertz's 0.5265 GPa to within 1e-3 (measured error 2e-4 there).
    assert!((p_max["value"].as_f64().unwrap() / 0.5265e9 - 1.0).abs() < 1e-3);
    assert_eq!(summary["results"]["load"]["unit"], "N");
    let csv = std::fs::read_to_string(out.join("centreline.csv")).unwrap();
    assert!(csv.starts_with("x_m,pressure_pa,gap_m,"));
    assert_eq!(csv.lines().count(), 34);
    let p: ndarray::Array2<f64> = ndarray_npy::read_npy(out.join("pressure_pa.npy")).unwrap();
    assert_eq!(p.dim(), (33, 33));
}

#[test]
fn bad_scene_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bad.json");
    let text = ehl_scene::builtin("hertz").unwrap().to_json().replace("0.009525", "-0.009525");
    std::fs::write(&scene, text).unwrap();
    let out = dir.path().join("out");
    let o = ehl().arg("run").arg(&scene).arg("--out").arg(&out).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("conditions.ball_radius_m") && err.contains("> 0"), "{err}");
    assert!(!out.exists(), "output folder created for a refused scene");

    let o = ehl().args(["run", "hertz", "--grid", "4", "--out"]).arg(&out).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("grid.nx"));
    assert!(!out.exists());
}

#[test]
fn scenes_lists_builtins() {
    let o = ehl().arg("scenes").output().unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains("hertz"));
}
