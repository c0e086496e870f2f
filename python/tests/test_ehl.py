"""The Python API against the command line it wraps: the same scenes refused the same way, the
same comparison to the last digit, the same sweep table; arrays in SI with the grid's shape.

`EHL_BIN` names the command-line binary to compare with (default: the workspace's release
build, `target/release/ehl`)."""

import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ehl

ROOT = Path(__file__).resolve().parents[2]
EHL = os.environ.get("EHL_BIN", str(ROOT / "target" / "release" / "ehl"))


def cli(*args):
    return subprocess.run([EHL, *map(str, args)], capture_output=True, text=True)


def seed_dict():
    return ehl.scene("seed").to_dict()


def test_a_refused_scene_names_its_field_and_the_allowed_range():
    d = seed_dict()
    d["conditions"]["load_n"] = -20.0
    with pytest.raises(ehl.SceneError) as e:
        ehl.scene(d)
    assert e.value.field == "conditions.load_n", str(e.value)
    assert e.value.value == "-20" and "> 0" in e.value.allowed, str(e.value)
    # An unknown field is named by its path too.
    d = seed_dict()
    d["conditions"]["load"] = 20.0
    with pytest.raises(ehl.SceneError) as e:
        ehl.scene(d)
    assert "conditions" in e.value.field and "load" in str(e.value)
    # Nothing of a refused name.
    with pytest.raises(ehl.SceneError):
        ehl.scene("no-such-scene")


def test_compare_on_a_coarse_seed_equals_the_command_lines_table_to_the_last_digit(tmp_path):
    # 65²: the layer and dry models converge; the films of both Reynolds models close on cells
    # of 0.039 a, the fed one's solids touch there and it answers (flagged, its error bar
    # larger than its film); the flooded one's clamp fails there, and it answers through the
    # mass-conserving solver with the inflow filled (flagged too).
    out = cli("compare", "seed", "--grid", 65, "--out", tmp_path / "cli")
    assert (tmp_path / "cli" / "comparison.json").is_file(), out.stderr
    c = ehl.compare("seed", grid=65, out=tmp_path / "py")
    by_cli = json.loads((tmp_path / "cli" / "comparison.json").read_text())
    by_py = json.loads((tmp_path / "py" / "comparison.json").read_text())

    def strip(rows):
        return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in rows]

    assert strip(by_py["models"]) == strip(by_cli["models"])
    assert strip(c.table()) == strip(by_cli["models"])

    def rest(d):
        return {k: v for k, v in d.items() if k not in ("models", "total_wall_time_s")}

    assert rest(by_py) == rest(by_cli)
    assert by_py["schedule"] == "side-by-side"
    # Every model answers; the thin Reynolds films say they miss the accuracy.
    assert not c.errors
    assert c["reynolds"].solid_contact["load_share"] > 0.0 and c["reynolds"].flagged
    assert c["reynolds-flooded"].flagged
    # A pandas DataFrame takes the rows as they are (when pandas is there).
    pd = pytest.importorskip("pandas")
    df = pd.DataFrame(c.table())
    assert list(df["model"]) == ["layer", "reynolds", "reynolds-flooded", "dry"]


def test_models_run_one_at_a_time_give_the_same_rows_and_say_so():
    # 65²: every model answers (the thin Reynolds films flagged); sharing the cores or not,
    # every number and diagnosis is the same (each model's sums do not depend on its thread).
    together = ehl.compare("seed", grid=65)
    alone = ehl.compare("seed", grid=65, one_at_a_time=True)
    assert together.comparison["schedule"] == "side-by-side"
    assert alone.comparison["schedule"] == "one-at-a-time"
    for a, b in zip(together.table(), alone.table(), strict=True):
        assert a["model"] == b["model"] and a["converged"] == b["converged"]
        for k, v in a.items():
            if k == "wall_time_s":
                continue
            if isinstance(v, float):
                assert v == pytest.approx(b[k], rel=1e-12, abs=0.0), (a["model"], k)
            else:
                assert v == b[k], (a["model"], k)
    assert alone.comparison["total_wall_time_s"] >= sum(r["wall_time_s"] for r in alone.table())


def test_compare_of_a_seed_layer_scene_runs_its_comparison_like_the_command_line():
    # squeeze-after-stop names stop-compare: the same stop through the layer, Reynolds and dry
    # models; grid applies to the comparison (33²: the Reynolds film closes, listed).
    c = ehl.compare("squeeze-after-stop", grid=33)
    assert c.comparison["scene"] == "stop-compare"
    assert [r["model"] for r in c.table()] == ["layer", "reynolds", "dry"]
    assert c.comparison["grid"]["nx"] == 33
    # As a scene it stays the layer model's own.
    assert ehl.scene("squeeze-after-stop").models == ["layer"]


def test_fields_are_si_arrays_of_the_grids_shape_on_its_axes():
    r = ehl.run("hertz", grid=33)
    s = r.summary
    a, p_h = s["scales"]["a"]["value"], s["scales"]["p_h"]["value"]
    p = r.fields["pressure_pa"]
    assert p.shape == (33, 33) == (r.y.size, r.x.size) and p.dtype == np.float64
    # The axes in metres: the scene's domain ([-1.25, 1.25] a for `hertz`) and its spacing.
    scene = ehl.scene("hertz").to_dict()["domain"]
    assert math.isclose(r.x[0], scene["x_a"][0] * a, rel_tol=1e-12)
    assert math.isclose(r.y[-1], scene["y_a"][1] * a, rel_tol=1e-12)
    assert math.isclose(r.x[1] - r.x[0], s["grid"]["dx"]["value"], rel_tol=1e-9)
    # Pressure in Pa: Hertz's p_h at the centre (33² resolves it to 1 %).
    assert abs(p.max() / p_h - 1.0) < 0.01
    assert r.observables["max_pressure_pa"] == (r["max_pressure_pa"], "Pa")
    # The standard pair: the dry contact's film is its gap, 0 where the solids touch.
    assert np.array_equal(r.pressure, p) and r.film.shape == p.shape and r.film.min() == 0.0
    assert r.observables["central_film_m"][1] == "m"
    # The dry contact's solids carry the whole load, over Hertz's circle (33² cells: 5 %).
    c = r.solid_contact
    assert math.isclose(c["load_share"], 1.0, rel_tol=1e-12) and c["max_pressure_pa"] == p.max()
    assert abs(c["area_m2"] / (math.pi * a * a) - 1.0) < 0.05


def test_an_answer_returned_unconverged_says_why():
    # The seed's Reynolds case on 129² stalls at a force balance of 1.1e-6 against 1e-6 with its
    # answer settled: returned, with the caveat the command line prints (settled in the summary).
    r = ehl.run("reynolds-seed", grid=129)
    assert r.caveat is not None and "settled" in r.caveat, r.caveat
    assert r.summary["caveat"] == r.caveat and r["central_film_m"] > 0.0
    assert ehl.run("hertz", grid=33).caveat is None


def test_an_answer_carries_its_estimated_error_and_a_flagged_one_warns():
    # The seed's Reynolds case on 129², where its film barely exists: the films' error from the
    # solver's grid law, beyond 5 %: flagged, with a warning, the flags and the errors as
    # attributes; the dry contact on 33² within 5 %: no warning, no flag.
    with pytest.warns(ehl.AccuracyWarning, match="h_c"):
        r = ehl.run("reynolds-seed", grid=129)
    assert r.flagged and any(f.startswith("h_c ±") for f in r.flags), r.flags
    value, error, unit = r.errors["h_c"]
    assert unit == "m" and error > 0.05 * value, r.errors
    import warnings as w

    with w.catch_warnings():
        w.simplefilter("error", ehl.AccuracyWarning)
        d = ehl.run("hertz", grid=33, accuracy=0.2)
    assert not d.flagged and d.summary["accuracy"]["limit"] == 0.2
    assert d.errors["p_max"][1] > 0.0 and d.errors["h_c"][1] is None
    # Asked not to estimate: said, and flagged as such.
    with pytest.warns(ehl.AccuracyWarning, match="not estimated"):
        ehl.run("hertz", grid=33, estimate=False)


def test_the_readme_one_liner_prints_a_table_with_error_bars_and_no_flag():
    # The README's `ehl.compare('seed', accuracy=0.05).table()`: every answer within 5 % on the
    # grid the accuracy needs, the table printing as the command line's, rows for pandas.
    import warnings as w

    with w.catch_warnings():
        w.simplefilter("error", ehl.AccuracyWarning)
        c = ehl.compare("seed", accuracy=0.05)
    t = c.table()
    assert not c.flagged and "±" in str(t) and "FLAGGED" not in str(t)
    assert [r["model"] for r in t] == ["layer", "reynolds", "reynolds-flooded", "dry"]


def test_a_marching_run_gives_its_history_as_arrays():
    r = ehl.run("rolling-from-uniform", grid=33)
    h = r.history
    assert h is not None and h["t_s"].ndim == 1 and h["t_s"].size > 10
    assert np.all(np.diff(h["t_s"]) > 0)
    assert h["central_film_m"].shape == h["t_s"].shape
    assert ehl.run("hertz", grid=33).history is None


def test_a_sweeps_table_equals_the_command_lines_results_csv(tmp_path):
    d = seed_dict()
    d["name"] = "seed-33"
    d["models"] = ["layer", "dry"]
    d["grid"] = {"nx": 33, "ny": 33}
    (tmp_path / "seed-33.json").write_text(json.dumps(d))
    spec = {
        "name": "loads",
        "scene": "seed-33.json",
        "parameters": [{"parameter": "conditions.load_n", "values": [10.0, 20.0]}],
        "adapt": False,
    }
    path = tmp_path / "loads.json"
    path.write_text(json.dumps(spec))
    out = cli("sweep", path, "--out", tmp_path / "cli")
    assert out.returncode == 0, out.stdout + out.stderr
    res = ehl.sweep(path, out=tmp_path / "py")
    text = (tmp_path / "cli" / "results.csv").read_text()
    assert res.csv == text
    rows = res.table()
    assert len(rows) == 2 * 2 and rows[0]["model"] == "layer" and rows[0]["converged"] is True
    assert rows[1]["conditions.load_n"] == 10.0 and isinstance(rows[0]["central_film_m"], float)


def test_a_model_that_does_not_converge_raises_its_diagnosis():
    d = ehl.scene("reynolds-m20-l10").to_dict()
    d["reynolds"]["solver"]["max_cycles"] = 2
    d["reynolds"]["solver"]["advanced"] = {"fallback_lag": 0.0}
    with pytest.raises(ehl.ModelError) as e:
        ehl.run(d, grid=33)
    assert "did not converge" in str(e.value)


def test_a_march_that_fails_keeps_its_record_beside_the_output_folder(tmp_path):
    # The shallow dent's Reynolds march on 65² allowed 4 cycles a step fails as the dent
    # crosses the inlet, as on the command line: the record goes beside `out`.
    d = ehl.scene("dent-shallow-compare").to_dict()
    d.pop("models")
    d["model"] = "reynolds"
    d["reynolds"]["solver"]["advanced"] = {"step_max_cycles": 4}
    with pytest.raises(ehl.ModelError) as e:
        ehl.run(d, grid=65, out=tmp_path / "dent", estimate=False)
    assert "dent-failed" in str(e.value)
    failure = json.loads((tmp_path / "dent-failed" / "failure.json").read_text())
    assert failure["failed"] is True and failure["steps_taken"] >= 1
    assert not (tmp_path / "dent").exists()


def test_ctrl_c_stops_the_solve_and_frees_the_cores():
    # The seed comparison on 1025² takes minutes: however early or late the interrupt comes,
    # the solve is under way or about to be. KeyboardInterrupt must come once the solve has
    # stopped (the solvers check between cycles: well within 10 s), and afterwards the process
    # must use no more CPU than an idle one (an abandoned solve kept both cores busy).
    import signal
    import sys
    import time

    child = (
        # Python's own Ctrl-C handler, whatever the child inherited: a shell that runs the
        # tests in the background (`cmd &`) hands it SIGINT ignored.
        "import ehl, resource, signal, time\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        # 'start' inside the try: a signal that lands as soon as it is read is caught too.
        "try:\n"
        "    print('start', flush=True)\n"
        "    ehl.compare('seed', grid=1025, estimate=False)\n"
        "except KeyboardInterrupt:\n"
        "    c0 = resource.getrusage(resource.RUSAGE_SELF)\n"
        "    raised = time.monotonic()\n"
        "    time.sleep(1.0)\n"
        "    c1 = resource.getrusage(resource.RUSAGE_SELF)\n"
        "    cpu = (c1.ru_utime + c1.ru_stime) - (c0.ru_utime + c0.ru_stime)\n"
        "    print('interrupted', raised, cpu, flush=True)\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", child],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert p.stdout.readline().strip() == "start"
    # Two seconds in, the 1025² solves are under way: the stop is asked of a running solver.
    time.sleep(2.0)
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=120)
    words = out.split()
    assert words[:1] == ["interrupted"], out + err
    raised, cpu = float(words[1]), float(words[2])
    assert raised - t0 < 10.0, f"raised {raised - t0:.1f} s after the interrupt"
    # An idle second costs ~0 s of CPU; a solve left running costs ~2 (two cores).
    assert cpu < 0.3, f"{cpu:.2f} s of CPU in the second after the interrupt"


def test_a_wave_rolled_through_the_contact_gives_its_last_passage():
    # 65²: the wave of a/4 on 6.5 cells; the layer model answers and reports its last passage,
    # λ its mean central film over the wave's RMS height A/√2, and the wave it carries (above
    # the surfaces' own on this coarse grid: its grid convergence is in docs/findings.md, "A
    # wave through the contact", so only its sign and its SI form are held here).
    # The layer model alone, no error bars read: the Reynolds march and the coarser grids'
    # passages are not run.
    d = ehl.scene("waviness-compare").to_dict()
    d["models"] = ["layer"]
    c = ehl.compare(d, grid=65, estimate=False)
    p = c["layer"].passage
    assert p is not None and p["central_film_min_m"] <= p["central_film_mean_m"]
    assert p["lambda"] == pytest.approx(p["central_film_mean_m"] / (5e-9 / np.sqrt(2)), rel=1e-12)
    assert p["amplitude_ratio"] > 0.0
    assert p["deformed_amplitude_m"] == pytest.approx(p["amplitude_ratio"] * 5e-9, rel=1e-12)
    assert c.comparison["models"][0]["passage"]["lambda"] == pytest.approx(p["lambda"], rel=1e-12)
    # The layer model says where its solids touch (no layer left) over the passage too.
    assert 0.0 <= p["contact_load_share_mean"] <= p["contact_load_share_max"] < 1.0
    # Not estimated, so no passage statistic has an error bar.
    assert set(c["layer"].passage_errors.values()) == {None}
    assert ehl.compare("seed", grid=33, estimate=False)["layer"].passage is None
