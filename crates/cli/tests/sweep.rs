//! `ehl sweep` end to end: a killed sweep resumes to the results of an uninterrupted one, a
//! sharded run merges to the same bytes, failed points are rows with their diagnosis, and bad
//! sweeps are refused before anything is written.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

fn ehl() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ehl"))
}

/// The seed comparison on 65² (coarse: a test, not a study; no grid rule) over 4 speeds from
/// 0.01 to 1 m/s (at the lowest a Reynolds film fails on 65²: a failed point), in `dir`.
fn fixture(dir: &Path) -> PathBuf {
    let mut scene: serde_json::Value =
        serde_json::from_str(&ehl_scene::builtin("seed").unwrap().to_json()).unwrap();
    scene["name"] = "seed-65".into();
    scene["grid"] = serde_json::json!({"nx": 65, "ny": 65});
    // The clamp alone, so that the flooded film closes and a point fails (with the inflow
    // filled it answers).
    scene["reynolds"]["solver"]["advanced"] = serde_json::json!({"filled_inflow_fallback": false});
    std::fs::write(dir.join("seed-65.json"), scene.to_string()).unwrap();
    let sweep = dir.join("speed.json");
    std::fs::write(
        &sweep,
        r#"{"name": "speed", "scene": "seed-65.json", "resolve": false,
            "parameters": [{"parameter": "conditions.rolling_velocity_m_s", "log": [0.01, 1.0], "points": 4}]}"#,
    )
    .unwrap();
    sweep
}

fn ok(o: std::process::Output) -> String {
    assert!(
        o.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn finished(dir: &Path) -> usize {
    std::fs::read_dir(dir.join("points"))
        .map(|r| {
            r.filter_map(|e| e.ok())
                .filter(|e| e.file_name().to_string_lossy().ends_with(".json"))
                .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
                .count()
        })
        .unwrap_or(0)
}

#[test]
fn killed_and_sharded_sweeps_give_the_uninterrupted_results_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let sweep = fixture(tmp.path());
    let reference = tmp.path().join("reference");
    let out = ok(ehl().arg("sweep").arg(&sweep).arg("--out").arg(&reference).output().unwrap());
    assert!(out.contains("ran 4 points"), "{out}");
    // The terminal table: a row per point, each model's h_c or `failed`.
    assert!(out.contains("layer h_c [nm]") && out.contains("failed"), "{out}");
    assert_eq!(out.lines().filter(|l| l.trim_start().starts_with(char::is_numeric)).count(), 4);
    let csv = std::fs::read_to_string(reference.join("results.csv")).unwrap();
    for f in ["results.json", "cost.csv", "plan.json", "sweep_films.png", "sweep_cost.png"] {
        assert!(reference.join(f).is_file(), "{f} missing");
    }

    // Every point has a row per model; a model that failed has its diagnosis and no numbers,
    // and did not stop the sweep. (On 65² the Reynolds film closes at 2 mm/s.)
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 4 * 4, "layer, reynolds (fed the supply), reynolds-flooded, dry");
    let failed: Vec<&&str> = rows.iter().filter(|r| r.contains(",false,")).collect();
    assert!(!failed.is_empty(), "the fixture has a failing point");
    for r in &failed {
        assert!(r.contains(",,,") && r.ends_with('"') && r.contains("did not converge"), "{r}");
    }
    assert!(rows.iter().filter(|r| r.contains(",layer,true,")).count() >= 3, "{csv}");

    // A real SIGKILL mid-sweep: nothing can tidy up, yet the rerun finishes only the rest.
    let killed = tmp.path().join("killed");
    let mut child = ehl()
        .arg("sweep")
        .arg(&sweep)
        .arg("--out")
        .arg(&killed)
        .args(["--jobs", "1"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while finished(&killed) < 1 {
        assert!(t0.elapsed() < Duration::from_secs(120), "no point finished");
        std::thread::sleep(Duration::from_millis(5));
    }
    let kill = Command::new("kill").args(["-KILL", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    assert!(!child.wait().unwrap().success());
    let done = finished(&killed);
    assert!((1..4).contains(&done), "{done} points finished before the kill");
    assert!(!killed.join("results.csv").exists());
    let out = ok(ehl().arg("sweep").arg(&sweep).arg("--out").arg(&killed).output().unwrap());
    assert!(out.contains(&format!("({done} already finished)")), "{out}");
    assert_eq!(std::fs::read_to_string(killed.join("results.csv")).unwrap(), csv);

    // The cluster path: plan 2 shards, run each alone, merge.
    let sharded = tmp.path().join("sharded");
    ok(ehl()
        .args(["sweep", "plan"])
        .arg(&sweep)
        .args(["--shards", "2", "--out"])
        .arg(&sharded)
        .output()
        .unwrap());
    let sbatch = std::fs::read_to_string(sharded.join("sweep.sbatch")).unwrap();
    assert!(sbatch.contains("#SBATCH --array=0-1"), "{sbatch}");
    assert!(sbatch.contains("--shard \"$SLURM_ARRAY_TASK_ID/2\""), "{sbatch}");
    ok(ehl().args(["sweep", "run"]).arg(&sharded).args(["--shard", "0/2"]).output().unwrap());
    // Shard 0 holds the even points only: merging now names the missing odd ones.
    assert_eq!(finished(&sharded), 2);
    let o = ehl().args(["sweep", "merge"]).arg(&sharded).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("2 of 4 points have no result yet (points 1, 3)"), "{err}");
    ok(ehl().args(["sweep", "run"]).arg(&sharded).args(["--shard", "1/2"]).output().unwrap());
    ok(ehl().args(["sweep", "merge"]).arg(&sharded).output().unwrap());
    assert_eq!(std::fs::read_to_string(sharded.join("results.csv")).unwrap(), csv);

    // The same folder with another sweep is refused, not mixed.
    let other = tmp.path().join("other.json");
    std::fs::write(
        &other,
        std::fs::read_to_string(&sweep).unwrap().replace("\"points\": 4", "\"points\": 3"),
    )
    .unwrap();
    let o = ehl().arg("sweep").arg(&other).arg("--out").arg(&reference).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds the plan of another sweep"));
}

#[test]
fn bad_sweeps_are_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let sweep = fixture(tmp.path());
    let out = tmp.path().join("out");
    let text = std::fs::read_to_string(&sweep).unwrap();
    for (bad, says) in [
        (text.replace("[0.01, 1.0]", "[0.0, 1.0]"), "parameters[0].log"),
        (text.replace("rolling_velocity_m_s", "speed"), "parameters[0].parameter"),
        (text.replace("seed-65.json", "missing.json"), "missing.json"),
        (
            text.replace("conditions.rolling_velocity_m_s", "supply.thickness_m")
                .replace("seed-65.json", "hertz"),
            "no supply",
        ),
    ] {
        std::fs::write(&sweep, &bad).unwrap();
        let o = ehl().arg("sweep").arg(&sweep).arg("--out").arg(&out).output().unwrap();
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{says}: {err}");
        assert!(!out.exists(), "{says}: output written for a refused sweep");
    }
    let o = ehl().args(["sweep", "run"]).arg(tmp.path().join("nowhere")).output().unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("is this a sweep folder"));
    let o = ehl().args(["sweep", "run"]).arg(&out).args(["--shard", "2/2"]).output().unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("0 <= I < N"));
}
