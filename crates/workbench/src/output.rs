//! Writes an outcome: `summary.json` (every scalar with its unit), `centreline.csv`, fields as
//! `.npy` and PNG figures, all in SI. Files are staged and moved into place only when all of
//! them were written, so a failed run leaves nothing half-written.

use crate::error::{Error, Result, create_dir, io, output, write_file};
use crate::model::Outcome;
pub use crate::model::{Centreline, q};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Writes everything the scene asks for into `dir`, replacing it as a whole (see
/// [`replace_dir`]); returns the files written.
pub fn write(outcome: &dyn Outcome, dir: &Path) -> Result<Vec<PathBuf>> {
    replace_dir(dir, |stage| write_into(outcome, stage))
}

/// The staging folder of the run in progress, removed by the signal handler on SIGINT/SIGTERM.
static STAGE: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

/// Removes the staging folder of the write in progress, if any: what an interrupted run must do
/// so it leaves no partial output (the binary calls it from its SIGINT/SIGTERM handler).
pub fn abandon_stage() {
    if let Ok(mut g) = STAGE.lock()
        && let Some(p) = g.take()
    {
        let _ = std::fs::remove_dir_all(p);
    }
}

/// Fills a fresh staging folder beside `dir` with `fill`, and only when that succeeded puts it in
/// place of `dir`: an old run's files never mix with the new one's, and a failed or interrupted
/// run leaves `dir` as it was. Returns the files at their final paths.
pub fn replace_dir(
    dir: &Path,
    fill: impl FnOnce(&Path) -> Result<Vec<PathBuf>>,
) -> Result<Vec<PathBuf>> {
    let name = dir
        .file_name()
        .ok_or_else(|| Error::Refused(format!("output folder {} has no name", dir.display())))?
        .to_string_lossy()
        .to_string();
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    create_dir(&parent)?;
    let pid = std::process::id();
    let stage = parent.join(format!(".{name}.partial-{pid}"));
    let old = parent.join(format!(".{name}.old-{pid}"));
    for p in [&stage, &old] {
        if p.exists() {
            std::fs::remove_dir_all(p).map_err(io(format!("removing {}", p.display())))?;
        }
    }
    create_dir(&stage)?;
    *STAGE.lock().unwrap() = Some(stage.clone());
    let files = match fill(&stage) {
        Ok(f) => f,
        Err(e) => {
            abandon_stage();
            return Err(e);
        }
    };
    if dir.exists() {
        std::fs::rename(dir, &old)
            .map_err(io(format!("moving the old {} aside", dir.display())))?;
    }
    std::fs::rename(&stage, dir)
        .map_err(io(format!("moving the results into {}", dir.display())))?;
    *STAGE.lock().unwrap() = None;
    if old.exists() {
        std::fs::remove_dir_all(&old).map_err(io(format!("removing {}", old.display())))?;
    }
    Ok(files.into_iter().map(|f| dir.join(f.strip_prefix(&stage).unwrap_or(&f))).collect())
}

/// Writes an outcome's files into `dir` (no staging: [`write`] stages).
pub fn write_into(outcome: &dyn Outcome, dir: &Path) -> Result<Vec<PathBuf>> {
    let outputs = outcome.scene().outputs;
    let mut files = vec![];
    let file = dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary(outcome)).map_err(output("summary.json"))?;
    write_file(&file, text + "\n")?;
    files.push(file);
    if let Some(rows) = outcome.time_series()? {
        let csv = csv(&rows);

        let f = dir.join("timeseries.csv");
        write_file(&f, csv)?;
        files.push(f);
    }
    if outputs.centreline {
        let f = dir.join("centreline.csv");
        write_file(&f, outcome.centreline().to_csv())?;
        files.push(f);
    }
    if outputs.fields {
        let (x, y) = outcome.axes();
        for (stem, arr) in [("x_m", x), ("y_m", y)] {
            let f = dir.join(format!("{stem}.npy"));
            ndarray_npy::write_npy(&f, &arr).map_err(output(format!("writing {}", f.display())))?;
            files.push(f);
        }
        for (stem, field) in outcome.fields() {
            let f = dir.join(format!("{stem}.npy"));
            ndarray_npy::write_npy(&f, &field)
                .map_err(output(format!("writing {}", f.display())))?;
            files.push(f);
        }
    }
    if outputs.figures {
        files.extend(outcome.figures(dir, "")?);
    }
    Ok(files)
}

/// A text cell: bare when it is a plain word, else quoted (with its own quotes made single and
/// its line breaks spaces, so a row stays one line).
fn cell_text(s: &str) -> String {
    if s.chars().all(|c| c.is_alphanumeric() || "-_.".contains(c)) {
        s.to_string()
    } else {
        format!("\"{}\"", s.replace('"', "'").replace('\n', " "))
    }
}

/// CSV of `rows` (each the JSON form of a `Serialize` row, or an object built in column order):
/// a column per leaf of a row (nested names joined by `.`, array items by `[k]`, in order),
/// numbers in `e` notation (counts as integers), text bare when it is a plain word and quoted
/// otherwise, `null` empty. The header is the first row's; every row has the same leaves.
pub fn csv(rows: &[Value]) -> String {
    fn leaves(v: &Value, name: String, out: &mut Vec<(String, String)>) {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    let n = if name.is_empty() { k.clone() } else { format!("{name}.{k}") };
                    leaves(x, n, out);
                }
            }
            Value::Array(a) => {
                for (k, x) in a.iter().enumerate() {
                    leaves(x, format!("{name}[{k}]"), out);
                }
            }
            Value::Number(n) => out.push((
                name,
                match (n.as_u64(), n.as_i64(), n.as_f64()) {
                    (Some(u), _, _) => u.to_string(),
                    (_, Some(i), _) => i.to_string(),
                    (_, _, Some(f)) => format!("{f:e}"),
                    _ => n.to_string(),
                },
            )),
            Value::String(s) => out.push((name, cell_text(s))),
            Value::Bool(b) => out.push((name, b.to_string())),
            Value::Null => out.push((name, String::new())),
        }
    }
    let mut text = String::new();
    for (k, v) in rows.iter().enumerate() {
        let mut cells = vec![];
        leaves(v, String::new(), &mut cells);
        if k == 0 {
            text += &cells.iter().map(|c| c.0.as_str()).collect::<Vec<_>>().join(",");
            text.push('\n');
        }
        text += &cells.iter().map(|c| c.1.as_str()).collect::<Vec<_>>().join(",");
        text.push('\n');
    }
    text
}

/// The version of the shared part of `summary.json`: a reader checks it before reading.
pub const SUMMARY_SCHEMA: &str = "ehl-summary/1";

/// The keys of `summary.json` every model writes, in the same shape: what a reader can take
/// from any model's summary without knowing which model wrote it.
pub const SHARED_KEYS: [&str; 12] = [
    "schema",
    "scene",
    "model",
    "description",
    "conditions",
    "scales",
    "grid",
    "observables",
    "indicators",
    "caveat",
    "timings",
    "details",
];

/// `summary.json`: the shared part (SI, units beside every number), then the model's own
/// summary under `details`.
pub fn summary(outcome: &dyn Outcome) -> Value {
    let (scene, sc, g) = (outcome.scene(), outcome.scales(), outcome.grid());
    let (c, u) = outcome.conditions_used();
    let a = sc.a;
    let indicators: serde_json::Map<String, Value> = outcome
        .indicators()
        .into_iter()
        .map(|(k, i)| (k, serde_json::to_value(i).unwrap_or(Value::Null)))
        .collect();
    serde_json::json!({
        "schema": SUMMARY_SCHEMA,
        "scene": scene.name,
        "model": scene.model(),
        "description": scene.description,
        "conditions": {
            "ball_radius": q(c.ball_radius, "m"),
            "load": q(c.load, "N"),
            "reduced_modulus": q(c.reduced_modulus, "Pa"),
            "rolling_velocity": q(u, "m/s"),
        },
        "scales": { "a": q(a, "m"), "p_h": q(sc.p_h, "Pa"), "a2_over_r": q(sc.delta, "m") },
        "grid": {
            "nx": g.nx, "ny": g.ny,
            "x_range": { "value": [g.x_min * a, g.x_max * a], "unit": "m" },
            "y_range": { "value": [g.y_min * a, g.y_max * a], "unit": "m" },
            "dx": q(g.dx() * a, "m"), "dy": q(g.dy() * a, "m"),
        },
        "observables": serde_json::to_value(outcome.observables()).unwrap_or(Value::Null),
        "indicators": indicators,
        // Why the answer is returned though not converged (`null` when converged).
        "caveat": outcome.caveat(),
        "timings": {
            "total_wall_time": q(outcome.wall_time_s(), "s"),
            "threads": rayon::current_num_threads(),
        },
        "details": outcome.summary(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_has_a_column_per_leaf_in_declared_order() {
        #[derive(serde::Serialize)]
        struct Inner {
            at_m: (f64, f64),
            n: usize,
        }
        #[derive(serde::Serialize)]
        struct Row {
            t_s: f64,
            inner: Inner,
            #[serde(flatten)]
            flat: Inner,
            note: &'static str,
        }
        let r = |t: f64| Row {
            t_s: t,
            inner: Inner { at_m: (1.5, -2.0), n: 3 },
            flat: Inner { at_m: (0.0, 1e-9), n: 7 },
            note: "a \"b\"",
        };
        let rows = [r(0.0), r(0.25)].map(|r| serde_json::to_value(r).unwrap());
        let text = csv(&rows);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "t_s,inner.at_m[0],inner.at_m[1],inner.n,at_m[0],at_m[1],n,note");
        assert_eq!(lines[2], "2.5e-1,1.5e0,-2e0,3,0e0,1e-9,7,\"a 'b'\"");
        assert_eq!(lines.len(), 3);
    }
}
