//! The native half of the `ehl` Python package: the workbench's library calls (the same ones the
//! `ehl` command makes) behind four functions, their answers as JSON text and numpy arrays. The
//! Python half (`ehl/__init__.py`) turns them into objects.
//!
//! Every solve runs on a worker thread with the GIL released; the calling thread waits in short
//! slices and checks for signals between them. Ctrl-C asks the solve to stop (it does so at its
//! next cycle or step, writing nothing) and raises `KeyboardInterrupt` once it has.

use ehl_scene::{Scene, SceneError as RustSceneError, Sweep};
use ehl_workbench::{accuracy, compare, output, sweep};
use ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Duration;

pyo3::create_exception!(
    _ehl,
    SceneError,
    pyo3::exceptions::PyValueError,
    "A scene or sweep refused: `field` names the field (its path), `allowed` what it may hold."
);
pyo3::create_exception!(
    _ehl,
    ModelError,
    pyo3::exceptions::PyRuntimeError,
    "A model that did not converge or could not run: the message is its diagnosis."
);

/// A refused scene as `SceneError(message)` with `.field` (the field's path, bare:
/// `conditions.load_n`), `.value` and `.allowed` set when the scene names them. A parse error's
/// place in the JSON text ("at line 1 column 211") is left out: that text is the one this
/// package made from a dict or a loaded scene, never the user's.
fn scene_error(py: Python<'_>, e: &RustSceneError) -> PyErr {
    let unplaced = |m: &str| match m.rfind(" at line ") {
        Some(k) if m[k + 9..].split(" column ").all(|n| n.parse::<u64>().is_ok()) => {
            m[..k].to_string()
        }
        _ => m.to_string(),
    };
    let (text, field, value, allowed) = match e {
        RustSceneError::Range { field, value, allowed, .. } => {
            (e.to_string(), Some(field.clone()), Some(value.clone()), Some(allowed.clone()))
        }
        RustSceneError::Parse { path, message, .. } => {
            let message = unplaced(message);
            let field = (!path.is_empty()).then(|| path.clone());
            (unplaced(&e.to_string()), field, None, Some(message))
        }
        _ => (e.to_string(), None, None, None),
    };
    let err = SceneError::new_err(text);
    let v = err.value(py);
    let _ = v.setattr("field", field);
    let _ = v.setattr("value", value);
    let _ = v.setattr("allowed", allowed);
    err
}

/// How long an interrupted call waits for its solve to stop before it raises anyway: the
/// solvers check for a stop between cycles and steps, well within this.
const STOP_WAIT: Duration = Duration::from_secs(10);

/// Runs `work` on a worker thread with the GIL released, checking for signals every 50 ms.
/// On an interrupt the work is asked to stop ([`ehl_workbench::cancel`]: the solve returns at
/// its next cycle or step, and writes nothing), the call waits for it to end (at most
/// [`STOP_WAIT`]), and the signal's exception is raised: nothing keeps the cores busy after.
fn off_thread<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    ehl_workbench::cancel::clear();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(work());
    });
    let mut rx = rx;
    loop {
        // The receiver is moved through the GIL-free section (it may be sent, not shared).
        let (got, back) = py.detach(move || (rx.recv_timeout(Duration::from_millis(50)), rx));
        rx = back;
        match got {
            Ok(v) => return Ok(v),
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    ehl_workbench::cancel::request();
                    let _ = py.detach(move || rx.recv_timeout(STOP_WAIT));
                    ehl_workbench::cancel::clear();
                    return Err(e);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the solve's thread ended without an answer"));
            }
        }
    }
}

/// A scene from a built-in name or a path (`is_json` false), or from JSON text; checked. Returns
/// the scene as JSON text (every default written out).
/// With `for_compare`, a one-model scene that names its comparison (`comparison`) is that
/// comparison, before `grid` applies (what `ehl compare NAME` runs).
#[pyfunction]
#[pyo3(signature = (spec, is_json, grid=None, for_compare=false))]
fn load_scene(
    py: Python<'_>,
    spec: &str,
    is_json: bool,
    grid: Option<usize>,
    for_compare: bool,
) -> PyResult<String> {
    let scene = if is_json { Scene::from_json(spec, "(dict)") } else { ehl_scene::load(spec) };
    let mut scene = scene.map_err(|e| scene_error(py, &e))?;
    if for_compare && let Some(c) = scene.as_comparison().map_err(|e| scene_error(py, &e))? {
        scene = c;
    }
    if let Some(n) = grid {
        scene = scene.with_points(n).map_err(|e| scene_error(py, &e))?;
    }
    Ok(scene.to_json())
}

/// What Python receives of one model's answer, computed off the GIL.
struct Answer {
    summary: String,
    report: String,
    fields: Vec<(String, Array2<f64>)>,
    film: Array2<f64>,
    pressure: Array2<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    time_series: Option<String>,
    flags: Vec<String>,
}

fn answer(o: &dyn ehl_workbench::Outcome) -> Result<Answer, String> {
    let s = o.scales();
    let g = o.grid();
    let rows = o.time_series().map_err(|e| e.to_string())?;
    Ok(Answer {
        summary: output::summary(o).to_string(),
        report: o.report(),
        fields: o.fields(),
        film: o.film().mapv(|h| s.h_si(h)),
        pressure: o.pressure().mapv(|p| s.p_si(p)),
        x: g.xs().iter().map(|&v| s.x_si(v)).collect(),
        y: g.ys().iter().map(|&v| s.x_si(v)).collect(),
        time_series: rows.map(|r| serde_json::Value::Array(r).to_string()),
        flags: o
            .as_any()
            .downcast_ref::<accuracy::Checked>()
            .map(|c| c.flags.clone())
            .unwrap_or_default(),
    })
}

/// `{"summary", "report", "fields": {name: (ny, nx) array}, "film", "pressure" (every model's
/// standard two, SI), "x", "y", "time_series"}`.
fn to_py<'py>(py: Python<'py>, a: Answer) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("summary", a.summary)?;
    d.set_item("report", a.report)?;
    let fields = PyDict::new(py);
    for (name, f) in a.fields {
        fields.set_item(name, f.into_pyarray(py))?;
    }
    d.set_item("fields", fields)?;
    d.set_item("film", a.film.into_pyarray(py))?;
    d.set_item("pressure", a.pressure.into_pyarray(py))?;
    d.set_item("x", PyArray1::from_vec(py, a.x))?;
    d.set_item("y", PyArray1::from_vec(py, a.y))?;
    d.set_item("time_series", a.time_series)?;
    d.set_item("flags", a.flags)?;
    Ok(d)
}

/// Runs a one-model scene (JSON text); writes the command line's files to `out` when given.
#[pyfunction]
#[pyo3(signature = (scene_json, out=None, estimate=true))]
fn run<'py>(
    py: Python<'py>,
    scene_json: &str,
    out: Option<PathBuf>,
    estimate: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = Scene::from_json(scene_json, "(scene)").map_err(|e| scene_error(py, &e))?;
    if let Some(dir) = &out {
        output::check_out_dir(dir).map_err(|e| ModelError::new_err(e.to_string()))?;
    }
    let got = off_thread(py, move || -> Result<Answer, String> {
        let outcome = accuracy::run(&scene, estimate).map_err(|e| {
            // A march that failed keeps what it had done beside `out`, as the command line's.
            match out.as_deref().map(|dir| output::keep_failure(&scene, &e, dir)) {
                Some(Ok(Some(kept))) => format!(
                    "{e}\nthe march's record up to its failure is in {} (failure.json)",
                    kept.display()
                ),
                Some(Err(w)) => format!("{e}\nits record up to the failure was not written: {w}"),
                _ => e.to_string(),
            }
        })?;
        if let Some(dir) = out {
            output::write(&outcome, &dir).map_err(|e| e.to_string())?;
        }
        answer(&outcome)
    })?;
    to_py(py, got.map_err(ModelError::new_err)?)
}

/// A comparison as Python receives it: `comparison.json`'s text, the printed table, and each
/// model's answer or diagnosis by name.
type Compared = (String, String, Vec<(String, Result<Answer, String>)>);

/// Runs every model of a comparison scene (JSON text): `{"table": comparison.json's text,
/// "text": the printed table, "results": {model: answer}, "errors": {model: diagnosis}}`; writes
/// the command line's files to `out` when given. The models run at once unless `one_at_a_time`.
#[pyfunction]
#[pyo3(signature = (scene_json, out=None, one_at_a_time=false, estimate=true))]
fn compare_scene<'py>(
    py: Python<'py>,
    scene_json: &str,
    out: Option<PathBuf>,
    one_at_a_time: bool,
    estimate: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = Scene::from_json(scene_json, "(scene)").map_err(|e| scene_error(py, &e))?;
    if let Some(dir) = &out {
        output::check_out_dir(dir).map_err(|e| ModelError::new_err(e.to_string()))?;
    }
    let got = off_thread(py, move || -> Result<Compared, String> {
        let c =
            compare::run_checked(&scene, compare::Schedule::one_at_a_time(one_at_a_time), estimate);
        if let Some(dir) = out {
            c.write(&dir).map_err(|e| e.to_string())?;
        }
        let entries = c
            .entries
            .iter()
            .map(|e| {
                let a = match &e.outcome {
                    Ok(o) => answer(o.as_ref()),
                    Err(d) => Err(d.to_string()),
                };
                (e.name().to_string(), a)
            })
            .collect();
        Ok((c.to_json().to_string(), c.table(), entries))
    })?;
    let (table, text, entries) = got.map_err(ModelError::new_err)?;
    let d = PyDict::new(py);
    d.set_item("table", table)?;
    d.set_item("text", text)?;
    let (results, errors) = (PyDict::new(py), PyDict::new(py));
    for (name, a) in entries {
        match a {
            Ok(a) => results.set_item(name, to_py(py, a)?)?,
            Err(e) => errors.set_item(name, e)?,
        }
    }
    d.set_item("results", results)?;
    d.set_item("errors", errors)?;
    Ok(d)
}

/// Runs a sweep (a built-in name or a path, or JSON text) locally into `out` (plan, points,
/// results: the command line's files); returns the folder and `results.csv`'s text.
#[pyfunction]
#[pyo3(signature = (spec, is_json, out, jobs=None))]
fn run_sweep<'py>(
    py: Python<'py>,
    spec: &str,
    is_json: bool,
    out: PathBuf,
    jobs: Option<usize>,
) -> PyResult<Bound<'py, PyList>> {
    let (sw, base): (Sweep, Option<PathBuf>) = if is_json {
        (Sweep::from_json(spec, "(dict)").map_err(|e| scene_error(py, &e))?, None)
    } else {
        ehl_scene::load_sweep(spec).map_err(|e| scene_error(py, &e))?
    };
    let dir = out.clone();
    let got = off_thread(py, move || -> Result<String, String> {
        let jobs = jobs.unwrap_or_else(sweep::default_jobs);
        sweep::run_local(&sw, base.as_deref(), &dir, jobs).map_err(|e| e.to_string())?;
        std::fs::read_to_string(dir.join("results.csv")).map_err(|e| e.to_string())
    })?;
    let csv = got.map_err(ModelError::new_err)?;
    PyList::new(py, [out.display().to_string(), csv])
}

/// The names of the built-in scenes and sweeps.
#[pyfunction]
fn builtins() -> (Vec<&'static str>, Vec<&'static str>) {
    (ehl_scene::builtin_names(), ehl_scene::builtin_sweep_names())
}

/// A scratch folder that outlives this call (for a sweep without `out`): its path.
#[pyfunction]
fn scratch_dir() -> PyResult<String> {
    let d = tempfile::Builder::new()
        .prefix("ehl-sweep-")
        .tempdir()
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok(d.keep().display().to_string())
}

#[pymodule]
fn _ehl(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add_function(wrap_pyfunction!(load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(compare_scene, m)?)?;
    m.add_function(wrap_pyfunction!(run_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(builtins, m)?)?;
    m.add_function(wrap_pyfunction!(scratch_dir, m)?)?;
    Ok(())
}
