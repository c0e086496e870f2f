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
    let p_max = &summary["details"]["results"]["max_pressure"];
    assert_eq!(p_max["unit"], "Pa");
    // 33² is coarse: Hertz's 0.5265 GPa to within 1e-3 (measured error 2e-4 there).
    assert!((p_max["value"].as_f64().unwrap() / 0.5265e9 - 1.0).abs() < 1e-3);
    assert_eq!(summary["details"]["results"]["load"]["unit"], "N");
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

fn read_json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_reused_output_folder_holds_only_the_new_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x");
    let o = ehl().args(["run", "hertz", "--grid", "17", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success());
    assert!(out.join("deformation_m.npy").is_file());
    let o =
        ehl().args(["run", "squeeze-steady", "--grid", "17", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The Hertz run's files are gone with it; the folder is the squeeze run's alone.
    assert!(!out.join("deformation_m.npy").exists() && !out.join("pressure_map.png").exists());
    assert_eq!(read_json(&out.join("summary.json"))["scene"], "squeeze-steady");
    let leftovers: Vec<_> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers, vec![std::ffi::OsString::from("x")], "staging folders left behind");
}

/// Starts `ehl` with `args`, waits until its standard error has a line containing `event` (the
/// run says when it starts solving and when it starts writing) and `after` seconds more, then
/// sends `signal`; returns the output and how long the process took to end after the signal.
fn signal_at(args: &[&str], event: &str, after: f64, signal: &str) -> (std::process::Output, f64) {
    use std::io::BufRead;
    let mut child = ehl()
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut said = String::new();
    loop {
        let mut line = String::new();
        assert!(err.read_line(&mut line).unwrap() > 0, "ended before `{event}`: {said}");
        said += &line;
        if line.contains(event) {
            break;
        }
    }
    std::thread::sleep(std::time::Duration::from_secs_f64(after));
    let sent = std::time::Instant::now();
    let kill = Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut err, &mut rest).unwrap();
    let status = child.wait().unwrap();
    let waited = sent.elapsed().as_secs_f64();
    (std::process::Output { status, stdout: vec![], stderr: (said + &rest).into_bytes() }, waited)
}

fn interrupted(signal: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    // An earlier run in the folder: an interrupted run must leave it as it was.
    assert!(
        ehl().args(["run", "hertz", "--grid", "17", "--out"]).arg(&out).status().unwrap().success()
    );
    // rolling-from-uniform on 129² marches ~1600 steps (seconds): interrupted as it starts.
    let (o, _) = signal_at(
        &["run", "rolling-from-uniform", "--grid", "129", "--out", out.to_str().unwrap()],
        "running",
        0.0,
        signal,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{signal}: {err}");
    assert!(err.contains("interrupted") && err.contains("as it was"), "{signal}: {err}");
    assert_eq!(
        read_json(&out.join("summary.json"))["scene"],
        "hertz",
        "{signal}: old output changed"
    );
    let names: Vec<_> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, vec![std::ffi::OsString::from("run")], "{signal}: partial output left");
}

#[test]
fn sigint_while_solving_leaves_the_old_output_as_it_was() {
    interrupted("-INT");
}

#[test]
fn sigterm_while_solving_leaves_the_old_output_as_it_was() {
    interrupted("-TERM");
}

#[test]
fn a_signal_while_the_output_is_written_leaves_the_old_output_whole() {
    // 300 snapshots, each a map figure: seconds of writing, interrupted as it starts. The writer
    // stops between files, and its stage is removed once it has stopped.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    assert!(
        ehl().args(["run", "hertz", "--grid", "17", "--out"]).arg(&out).status().unwrap().success()
    );
    let mut v: serde_json::Value =
        serde_json::from_str(&ehl_scene::builtin("rolling-from-uniform").unwrap().to_json())
            .unwrap();
    let times: Vec<f64> = (0..300).map(|k| k as f64 * 1e-4).collect();
    v["run"]["snapshots_s"] = serde_json::json!(times);
    let scene = dir.path().join("many.json");
    std::fs::write(&scene, v.to_string()).unwrap();
    for signal in ["-TERM", "-HUP", "-INT"] {
        let (o, _) = signal_at(
            &["run", scene.to_str().unwrap(), "--grid", "33", "--out", out.to_str().unwrap()],
            "writing",
            0.0,
            signal,
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(130), "{signal}: {err}");
        assert_eq!(read_json(&out.join("summary.json"))["scene"], "hertz", "{signal}: {err}");
        let mut names: Vec<_> =
            std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        names.sort();
        assert_eq!(names, ["many.json", "run"], "{signal}: a stage left behind");
    }
}

#[test]
fn a_signal_stops_a_long_solve_within_seconds() {
    // The seed's fed Reynolds contact on 1025² takes a minute; signalled 3 s in, in its cycles,
    // it checks for a stop between them (a cycle there is ~0.3 s), so it ends well within 10 s
    // of the signal (the bound leaves room for shared, slow cores; a solve that ignored the
    // stop runs on for the rest of its minute).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("seed");
    let (o, waited) = signal_at(
        &["run", "reynolds-seed", "--grid", "1025", "--out", out.to_str().unwrap()],
        "running",
        3.0,
        "-TERM",
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(waited < 10.0, "ended {waited:.1} s after the signal: {err}");
    assert!(!out.exists());
}

#[test]
fn an_output_folder_that_is_not_ours_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let thesis = dir.path().join("mythesis");
    std::fs::create_dir_all(thesis.join("chapters")).unwrap();
    std::fs::write(thesis.join("chapters/ch1.tex"), "x").unwrap();
    let file = dir.path().join("afile");
    std::fs::write(&file, "mine").unwrap();
    for (target, says) in [
        (thesis.clone(), "not an ehl output"),
        (file.clone(), "is a file"),
        (file.join("sub"), "is a file"),
        (dir.path().to_path_buf(), "working folder"),
    ] {
        let o = ehl()
            .current_dir(dir.path())
            .args(["run", "hertz", "--grid", "17", "--out"])
            .arg(&target)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{}: {err}", target.display());
        assert!(!err.contains("running"), "refused only after starting: {err}");
    }
    assert_eq!(std::fs::read_to_string(thesis.join("chapters/ch1.tex")).unwrap(), "x");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
}

#[test]
fn runs_racing_into_one_folder_each_leave_a_whole_output() {
    // Two runs at once into one folder, twenty times: each succeeds, the folder holds one run's
    // files whole, and nothing is left beside it.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("race");
    for _ in 0..20 {
        let kids: Vec<_> = (0..2)
            .map(|_| {
                ehl()
                    .args(["run", "hertz", "--grid", "17", "--out"])
                    .arg(&out)
                    .stdout(std::process::Stdio::null())
                    .stderr(std::process::Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        for k in kids {
            let o = k.wait_with_output().unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
        assert_eq!(read_json(&out.join("summary.json"))["scene"], "hertz");
        let names: Vec<_> =
            std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, vec![std::ffi::OsString::from("race")], "left beside it");
    }
}

#[test]
fn compare_writes_the_table_and_each_model_and_lists_a_failure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cmp");
    let given = concat!(env!("CARGO_MANIFEST_DIR"), "/../../validation/tests/data/user-10n.json");
    // The Reynolds solve given 3 cycles cannot converge: the layer and dry models still write,
    // the table names the failure, the exit status is non-zero.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(given).unwrap()).unwrap();
    v["reynolds"] =
        serde_json::json!({"solver": {"max_cycles": 3, "advanced": {"fallback_lag": 0.0}}});
    let scene = dir.path().join("user-10n-3-cycles.json");
    std::fs::write(&scene, v.to_string()).unwrap();
    let o = ehl()
        .arg("compare")
        .arg(&scene)
        .args(["--grid", "65", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(!o.status.success(), "{stdout}");
    assert!(stdout.contains("reynolds") && stdout.contains("FAILED"), "{stdout}");
    let table = read_json(&out.join("comparison.json"));
    let models = table["models"].as_array().unwrap();
    assert_eq!(models.len(), 3);
    for m in models {
        let name = m["model"].as_str().unwrap();
        if name == "reynolds" {
            assert_eq!(m["converged"], false);
            assert!(m["diagnosis"].as_str().unwrap().contains("did not converge"), "{m}");
            assert!(!out.join(name).exists());
        } else {
            assert_eq!(m["converged"], true);
            assert!(
                m["central_film_m"].as_f64().unwrap() >= 0.0
                    && m["wall_time_s"].as_f64().unwrap() > 0.0
            );
            assert!(out.join(name).join("summary.json").is_file(), "{name}'s own outputs");
        }
    }
    assert_eq!(table["scales"]["a"]["unit"], "m");
    let csv = std::fs::read_to_string(out.join("comparison.csv")).unwrap();
    assert!(
        csv.starts_with("model,converged,central_film_m,") && csv.lines().count() == 4,
        "{csv}"
    );
    assert!(out.join("comparison_centreline.png").is_file());
    // `ehl run` refuses a comparison scene, pointing to `compare`.
    let o = ehl().arg("run").arg(&scene).arg("--out").arg(dir.path().join("r")).output().unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("ehl compare"));
}

#[test]
fn compare_of_a_seed_layer_scene_runs_its_case_through_every_model() {
    // `ehl compare squeeze-after-stop` (the layer's own stop scene) runs `stop-compare`, the
    // same stop through the layer, Reynolds and dry models on one plan, and says so. On 33² the
    // Reynolds film closes (cells of 0.078 a): the table lists it, the others answer.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("stop");
    let o = ehl()
        .args(["compare", "squeeze-after-stop", "--grid", "33", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("scene `squeeze-after-stop` is the layer model's own")
            && stdout.contains("`stop-compare` (layer, reynolds, dry)"),
        "{stdout}"
    );
    let table = read_json(&out.join("comparison.json"));
    assert_eq!(table["scene"], "stop-compare");
    let models: Vec<&str> =
        table["models"].as_array().unwrap().iter().map(|m| m["model"].as_str().unwrap()).collect();
    assert_eq!(models, ["layer", "reynolds", "dry"]);
    assert_eq!(table["grid"]["nx"], 33, "--grid applies to the comparison");
    // `ehl run` of the same scene is still the layer model's own run.
    let o = ehl()
        .args(["run", "squeeze-after-stop", "--grid", "17", "--out"])
        .arg(dir.path().join("layer"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("layer/summary.json").is_file());
}

#[test]
fn thread_count_does_not_change_results() {
    // Rayon's summation order differs with the thread count: the results may differ in the last
    // digits only (measured: identical to 1e-15 relative on the dry contact).
    let dir = tempfile::tempdir().unwrap();
    let mut p = vec![];
    for t in ["1", "2"] {
        let out = dir.path().join(t);
        let o = ehl()
            .args(["run", "hertz", "--grid", "65", "--threads", t, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success());
        let s = read_json(&out.join("summary.json"));
        assert_eq!(s["timings"]["threads"].as_u64().unwrap().to_string(), t);
        p.push(s["details"]["results"]["max_pressure"]["value"].as_f64().unwrap());
    }
    assert!((p[0] / p[1] - 1.0).abs() < 1e-12, "{p:?}");
    let o = ehl().args(["run", "hertz", "--threads", "0"]).output().unwrap();
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--threads"));
}

#[test]
fn check_fills_defaults_and_names_bad_fields() {
    let o = ehl().args(["check", "rolling-steady"]).output().unwrap();
    assert!(o.status.success());
    let filled: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // User settings spelled out with their defaults; the solvers' internal knobs only where a
    // scene changes them (under `advanced`).
    assert!(filled["solver"]["max_iterations"].as_u64().unwrap() > 0);
    assert!(filled["run"]["steady"]["strain_tolerance"].as_f64().unwrap() > 0.0);
    assert!(filled["run"]["steady"].get("advanced").is_none(), "{filled}");
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.json");
    let mut wrong = filled.clone();
    wrong["run"]["steady"]["advanced"] = serde_json::json!({ "substeps": 0 });
    let text = serde_json::to_string_pretty(&wrong).unwrap();
    std::fs::write(&bad, text).unwrap();
    let o = ehl().arg("check").arg(&bad).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("run.steady.advanced.substeps"));
}

#[test]
fn a_run_that_does_not_converge_writes_nothing_and_says_why() {
    // The seed's Reynolds case on 65², the clamp alone (measured: the film closes at
    // x = 0.16 a, y = 0.98 a; with the inflow filled it answers).
    let dir = tempfile::tempdir().unwrap();
    let mut scene: serde_json::Value =
        serde_json::from_str(&ehl_scene::builtin("reynolds-seed").unwrap().to_json()).unwrap();
    scene["reynolds"]["solver"]["advanced"] = serde_json::json!({"filled_inflow_fallback": false});
    let scenes = tempfile::tempdir().unwrap();
    let file = scenes.path().join("reynolds-seed.json");
    std::fs::write(&file, scene.to_string()).unwrap();
    let out = dir.path().join("seed65");
    let o = ehl().arg("run").arg(&file).args(["--grid", "65", "--out"]).arg(&out).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("did not converge") && err.contains("film closed") && err.contains("x ="),
        "{err}"
    );
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none(), "something was written");
}

#[test]
fn a_march_that_fails_keeps_its_record_beside_the_output_and_the_answer_there_stays() {
    // The shallow dent's Reynolds march on 65² allowed 4 cycles a step: a step as the dent
    // crosses the inlet needs more (measured: the 14th fails, its V-cycles and then W-cycles out of cycles). The answer already in the
    // output folder stays; the march's rows up to its last step and that state's fields go
    // beside it, to `<out>-failed`, with the diagnosis.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dent");
    let o = ehl().args(["run", "hertz", "--grid", "17", "--out"]).arg(&out).output().unwrap();
    assert!(o.status.success());
    let mut scene: serde_json::Value =
        serde_json::from_str(&ehl_scene::builtin("dent-shallow-compare").unwrap().to_json())
            .unwrap();
    let v = scene.as_object_mut().unwrap();
    v.remove("models");
    v.insert("model".into(), "reynolds".into());
    scene["reynolds"]["solver"]["advanced"] = serde_json::json!({"step_max_cycles": 4});
    let file = dir.path().join("dent-4-cycles.json");
    std::fs::write(&file, scene.to_string()).unwrap();
    let o = ehl()
        .arg("run")
        .arg(&file)
        .args(["--grid", "65", "--no-estimate", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("dent-failed"), "{err}");
    assert_eq!(read_json(&out.join("summary.json"))["scene"], "hertz", "the answer replaced");
    let kept = dir.path().join("dent-failed");
    let failure = read_json(&kept.join("failure.json"));
    assert_eq!((&failure["failed"], &failure["kind"]), (&true.into(), &"cycle limit".into()));
    let steps = failure["steps_taken"].as_u64().unwrap() as usize;
    assert!(steps >= 1, "{failure}");
    // The header, the start and a row a step taken; the time reached is the last row's.
    let csv = std::fs::read_to_string(kept.join("timeseries.csv")).unwrap();
    assert_eq!(csv.lines().count(), steps + 2, "{csv}");
    let last_t: f64 = csv.lines().last().unwrap().split(',').next().unwrap().parse().unwrap();
    assert_eq!(last_t, failure["time_reached"]["value"].as_f64().unwrap());
    // That state's fields: the grid's, finite, the pressure Hertzian in size.
    let p: ndarray::Array2<f64> = ndarray_npy::read_npy(kept.join("pressure_pa.npy")).unwrap();
    assert_eq!(p.dim(), (65, 65));
    let p_max = p.iter().cloned().fold(0.0, f64::max);
    assert!(p.iter().all(|v| v.is_finite()) && p_max > 3e8 && p_max < 1e9, "{p_max}");
    assert!(kept.join("film_m.npy").is_file() && !kept.join("summary.json").exists());
    // In a comparison the record goes to the model's own folder, the table says where.
    let mut scene: serde_json::Value =
        serde_json::from_str(&ehl_scene::builtin("dent-shallow-compare").unwrap().to_json())
            .unwrap();
    scene["reynolds"]["solver"]["advanced"] = serde_json::json!({"step_max_cycles": 4});
    std::fs::write(&file, scene.to_string()).unwrap();
    let cmp = dir.path().join("cmp");
    let o = ehl()
        .arg("compare")
        .arg(&file)
        .args(["--grid", "65", "--no-estimate", "--out"])
        .arg(&cmp)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(!o.status.success() && stdout.contains("its march failed after"), "{stdout}");
    let table = read_json(&cmp.join("comparison.json"));
    let rey = &table["models"].as_array().unwrap()[1];
    assert_eq!(rey["failed_march"]["steps_taken"].as_u64().unwrap() as usize, steps, "{rey}");
    assert_eq!(rey["failed_march"]["record"], "reynolds/failure.json");
    assert_eq!(read_json(&cmp.join("reynolds/failure.json"))["steps_taken"], steps);
    assert!(
        cmp.join("layer/summary.json").is_file() && !cmp.join("reynolds/summary.json").exists()
    );
}
