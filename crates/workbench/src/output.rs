//! Writes an outcome: `summary.json` (every scalar with its unit), `centreline.csv`, fields as
//! `.npy` and PNG figures, all in SI. Files are staged and moved into place only when all of
//! them were written, so a failed run leaves nothing half-written.

use crate::error::{Error, Result, create_dir, interruption, io, output, write_file};
use crate::model::Outcome;
pub use crate::model::{Centreline, q};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Writes everything the scene asks for into `dir`, replacing it as a whole (see
/// [`replace_dir`]); returns the files written.
pub fn write(outcome: &dyn Outcome, dir: &Path) -> Result<Vec<PathBuf>> {
    replace_dir(dir, |stage| write_into(outcome, stage))
}

/// The file the writer leaves in every folder it fills: what marks a folder as an `ehl`
/// output, which a later run may replace. A folder without it is the user's, and is never
/// removed.
pub const MARKER: &str = ".ehl-output";

/// Whether `dir` may take a run's output, asked before any work: it does not exist yet (and
/// nothing on its path is a file), is an empty folder, or is an earlier `ehl` output (it holds
/// [`MARKER`]). Anything else is refused, naming it: a file, a folder of other files, the
/// working folder or one holding it.
pub fn check_out_dir(dir: &Path) -> Result<()> {
    let refuse =
        |why: String| Err(Error::Refused(format!("output folder {}: {why}", dir.display())));
    for up in dir.ancestors().skip(1).filter(|p| !p.as_os_str().is_empty()) {
        if up.exists() && !up.is_dir() {
            return refuse(format!(
                "{} is a file, so no folder can be made under it",
                up.display()
            ));
        }
    }
    // One look at the path: another run may move an earlier output aside and its own into
    // place at any moment, and a folder seen to exist and then gone is no file.
    let gone = |e: &std::io::Error| e.kind() == std::io::ErrorKind::NotFound;
    match std::fs::metadata(dir) {
        Err(e) if gone(&e) => return Ok(()),
        Err(e) => return Err(io(format!("reading {}", dir.display()))(e)),
        Ok(m) if !m.is_dir() => {
            return refuse(
                "is a file: refusing to replace it (give a new folder, or an earlier ehl output)"
                    .into(),
            );
        }
        Ok(_) => {}
    }
    if let (Ok(here), Ok(there)) = (std::env::current_dir(), dir.canonicalize())
        && here.starts_with(&there)
    {
        return refuse(
            "is the working folder or holds it: refusing to replace it (give a folder inside it)"
                .into(),
        );
    }
    if dir.join(MARKER).is_file() {
        return Ok(());
    }
    let entries: Vec<String> = match std::fs::read_dir(dir) {
        Err(e) if gone(&e) => return Ok(()),
        listing => listing
            .map_err(io(format!("reading {}", dir.display())))?
            .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
            .collect(),
    };
    // Between the look for the marker and the listing another run may have put its own output
    // in place: a listing that holds the marker is an ehl output too (two runs racing into one
    // folder refused each other about once in fifty).
    if entries.is_empty() || entries.iter().any(|e| e == MARKER) {
        return Ok(());
    }
    let shown: Vec<&str> = entries.iter().take(3).map(String::as_str).collect();
    refuse(format!(
        "holds {} entries that are not an ehl output ({}{}): refusing to replace it (give a new or empty folder)",
        entries.len(),
        shown.join(", "),
        if entries.len() > 3 { ", …" } else { "" }
    ))
}

/// The longest part of an output folder's name that goes into its staging folders' names: with
/// the dot and a `.partial-<pid>` tail they stay within the 255 bytes a file name may have.
const STAGE_NAME_BYTES: usize = 200;

/// The names of the staging and set-aside folders of runs into `dir`: `(prefix, parent)`; a
/// run's own are `<prefix>partial-<pid>` and `<prefix>old-<pid>[-k]` in `parent`.
fn stage_names(dir: &Path) -> Result<(String, PathBuf)> {
    let name = dir
        .file_name()
        .ok_or_else(|| Error::Refused(format!("output folder {} has no name", dir.display())))?
        .to_string_lossy()
        .to_string();
    let mut cut = name.len().min(STAGE_NAME_BYTES);
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((format!(".{}.", &name[..cut]), parent))
}

/// Whether process `pid` is running (on a system without `/proc`: assumed so, and its folders
/// are left alone).
fn alive(pid: u32) -> bool {
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// What killed runs into `dir` left beside it (their staging and set-aside folders, each an ehl
/// output by its marker, its run no longer alive): removed, but for a set-aside output where
/// `dir` itself is missing (a run killed between its two renames), which is put back first.
fn tidy_leftovers(dir: &Path, prefix: &str, parent: &Path) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(parent) else { return Ok(()) };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(prefix) else { continue };
        let (kind, tail) = match rest.split_once('-') {
            Some((k @ ("partial" | "old"), t)) => (k, t),
            _ => continue,
        };
        let pid = tail.split('-').next().and_then(|p| p.parse::<u32>().ok());
        let path = e.path();
        let ours = path.join(MARKER).is_file()
            || std::fs::read_dir(&path).is_ok_and(|mut d| d.next().is_none());
        if pid.is_none_or(alive) || !ours {
            continue;
        }
        if kind == "old" && !dir.exists() {
            std::fs::rename(&path, dir).map_err(io(format!(
                "putting {} back as {}",
                path.display(),
                dir.display()
            )))?;
        } else {
            std::fs::remove_dir_all(&path).map_err(io(format!(
                "removing {}, left by a run that was killed",
                path.display()
            )))?;
        }
    }
    Ok(())
}

/// Fills a fresh staging folder beside `dir` with `fill`, and only when that succeeded puts it
/// in place of `dir`: an old run's files never mix with the new one's, and a failed or
/// interrupted run leaves `dir` as it was. `dir` must pass [`check_out_dir`] (checked again
/// here); what killed runs left beside it is tidied first. A stop asked for
/// ([`ehl_core::cancel`]) before the new output is in place abandons it, the staging folder
/// removed once `fill` has returned (never under a writer still filling it); once in place,
/// the output stays, complete. Returns the files at their final paths.
pub fn replace_dir(
    dir: &Path,
    fill: impl FnOnce(&Path) -> Result<Vec<PathBuf>>,
) -> Result<Vec<PathBuf>> {
    check_out_dir(dir)?;
    let (prefix, parent) = stage_names(dir)?;
    create_dir(&parent)?;
    tidy_leftovers(dir, &prefix, &parent)?;
    let pid = std::process::id();
    let stage = parent.join(format!("{prefix}partial-{pid}"));
    if stage.exists() {
        std::fs::remove_dir_all(&stage).map_err(io(format!("removing {}", stage.display())))?;
    }
    create_dir(&stage)?;
    let interrupted =
        || Error::Interrupted(format!("no output written; {} is as it was", dir.display()));
    let filled = write_file(&stage.join(MARKER), MARKER_TEXT)
        .and_then(|_| ehl_core::cancel::check().map_err(|_| interrupted()))
        .and_then(|_| fill(&stage))
        .and_then(|f| ehl_core::cancel::check().map(|_| f).map_err(|_| interrupted()));
    let files = match filled {
        Ok(f) => f,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&stage);
            // A writer stopped by the request says only that it stopped: say what stands.
            return Err(if ehl_core::cancel::requested() { interrupted() } else { e });
        }
    };
    // Another run may put its output in place between our two renames: set that aside too,
    // a few times, before giving up.
    let mut old = vec![];
    let mut k = 0;
    loop {
        if dir.exists() {
            if let Err(e) = check_out_dir(dir) {
                let _ = std::fs::remove_dir_all(&stage);
                return Err(e);
            }
            let aside = parent.join(format!("{prefix}old-{pid}-{k}"));
            match std::fs::rename(dir, &aside) {
                Ok(()) => old.push(aside),
                // Another run moved it first.
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => {
                    let _ = std::fs::remove_dir_all(&stage);
                    return Err(io(format!("moving the old {} aside", dir.display()))(e));
                }
            }
        }
        match std::fs::rename(&stage, dir) {
            Ok(()) => break,
            // Another run's output landed between the two renames: set it aside too.
            Err(_) if k < 8 => k += 1,
            Err(e) => {
                let _ = std::fs::remove_dir_all(&stage);
                return Err(io(format!("moving the results into {}", dir.display()))(e));
            }
        }
    }
    for o in old {
        std::fs::remove_dir_all(&o).map_err(io(format!("removing {}", o.display())))?;
    }
    Ok(files.into_iter().map(|f| dir.join(f.strip_prefix(&stage).unwrap_or(&f))).collect())
}

/// What the marker file says, for a reader who finds it.
const MARKER_TEXT: &str =
    "This folder is an output of the ehl workbench: a later run into it replaces it whole.\n";

/// Writes an outcome's files into `dir` (no staging: [`write`] stages).
pub fn write_into(outcome: &dyn Outcome, dir: &Path) -> Result<Vec<PathBuf>> {
    let outputs = outcome.scene().outputs;
    // A field with a non-finite value is no answer: refused here, before any file says otherwise.
    for (name, field) in [("pressure", outcome.pressure().clone()), ("film", outcome.film())] {
        if let Some(((j, i), v)) = field.indexed_iter().find(|(_, v)| !v.is_finite()) {
            return Err(Error::Output {
                context: format!("scene `{}`", outcome.scene().name),
                message: format!(
                    "the answer's {name} is {v} at grid point (i={i}, j={j}): nothing written"
                ),
            });
        }
    }
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
            interruption()?;
            let f = dir.join(format!("{stem}.npy"));
            ndarray_npy::write_npy(&f, &field)
                .map_err(output(format!("writing {}", f.display())))?;
            files.push(f);
        }
    }
    if outputs.figures {
        files.extend(outcome.figures(dir, "", "")?);
    }
    Ok(files)
}

/// The folder a failed `ehl run` into `dir` writes what its march kept ([`write_failure`]):
/// beside `dir`, never in its place, so that a failure never replaces an earlier answer.
pub fn failed_dir(dir: &Path) -> PathBuf {
    let name = dir.file_name().map_or("out".into(), |n| n.to_string_lossy().into_owned());
    dir.with_file_name(format!("{name}-failed"))
}

/// Keeps what the march of a one-model `scene` had done when it failed with `e`, in
/// [`failed_dir`]`(out)`, replaced as a whole ([`replace_dir`]): the folder, or `None` when `e`
/// carries no record (a failure that is not a march's).
pub fn keep_failure(scene: &ehl_scene::Scene, e: &Error, out: &Path) -> Result<Option<PathBuf>> {
    if e.partial().is_none() {
        return Ok(None);
    }
    let kept = failed_dir(out);
    replace_dir(&kept, |stage| write_failure(scene, &scene.model_names(), e, stage))?;
    Ok(Some(kept))
}

/// Writes what a failed march kept into `dir` (no staging): `failure.json` (the diagnosis, its
/// kind, the steps taken and the time reached, the grid), the record up to the last step taken
/// as `timeseries.csv`, and that state's fields as `.npy` (SI; arrays of `ny` rows by `nx`).
/// No `summary.json`: it is no answer. Nothing when `e` carries no record.
pub fn write_failure(
    scene: &ehl_scene::Scene,
    model: &str,
    e: &Error,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let Some(p) = e.partial() else { return Ok(vec![]) };
    let mut files = vec![];
    let (mut written, mut refused) = (vec![], vec![]);
    for (stem, field) in &p.fields {
        interruption()?;
        // A non-finite value is no state to look at: named, not written.
        if field.iter().any(|v| !v.is_finite()) {
            refused.push(stem.clone());
            continue;
        }
        let f = dir.join(format!("{stem}.npy"));
        ndarray_npy::write_npy(&f, field).map_err(output(format!("writing {}", f.display())))?;
        files.push(f);
        written.push(format!("{stem}.npy"));
    }
    let f = dir.join("timeseries.csv");
    write_file(&f, csv(&p.rows))?;
    files.push(f);
    let g = scene.grid();
    let text = serde_json::json!({
        "scene": scene.name,
        "model": model,
        "failed": true,
        "what_this_is": "the record of a march that failed, up to the last step it took: no answer",
        "diagnosis": e.to_string(),
        "kind": e.class(),
        "steps_taken": p.steps,
        "time_reached": q(p.t_s, "s"),
        "timeseries": "timeseries.csv",
        "fields_of_the_last_state": written,
        "fields_not_written_non_finite": refused,
        "grid": {"nx": g.nx, "ny": g.ny, "x_a": [g.x_min, g.x_max], "y_a": [g.y_min, g.y_max]},
    });
    let f = dir.join("failure.json");
    let text = serde_json::to_string_pretty(&text).map_err(output("failure.json"))?;
    write_file(&f, text + "\n")?;
    files.push(f);
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
pub const SHARED_KEYS: [&str; 15] = [
    "schema",
    "scene",
    "model",
    "description",
    "conditions",
    "scales",
    "grid",
    "observables",
    "solid_contact",
    "passage",
    "accuracy",
    "indicators",
    "caveat",
    "timings",
    "details",
];

/// `summary.json`'s `accuracy`: each standard observable with its value, unit, estimated error
/// (absolute and relative) and the order the grids showed; how it was estimated, the limit and
/// what is flagged. `null` fields where no error was estimated.
fn accuracy(outcome: &dyn Outcome) -> Value {
    let ob = outcome.observables();
    let v = ob.standard();
    let Some((e, limit)) = outcome.estimate() else {
        return serde_json::json!({ "estimated": false });
    };
    let observables: serde_json::Map<String, Value> = ehl_core::observe::OBSERVED
        .iter()
        .enumerate()
        .map(|(k, (name, unit))| {
            let b = e.errors[k];
            (
                name.to_string(),
                serde_json::json!({
                    "value": v[k], "unit": unit,
                    "error": b.map(|b| b.absolute), "relative_error": b.map(|b| b.relative),
                    "observed_order": b.and_then(|b| b.order),
                }),
            )
        })
        .collect();
    serde_json::json!({
        "estimated": true,
        "observables": observables,
        "film_overlap": q(ob.film_overlap_m, "m"),
        "grids": e.grids,
        "method": e.method,
        "limit": limit,
        "within_limit": e.worst().is_some_and(|w| w <= limit),
        "passage": passage_errors(&e.passage),
        "wall_time": q(e.wall_time_s, "s"),
    })
}

/// `accuracy.passage`: the last passage's statistics' errors, each `null` where none was
/// estimated (no passage, or no coarser grid carried the pattern through one).
fn passage_errors(e: &ehl_core::observe::PassageErrors) -> Value {
    let bar = |b: Option<ehl_core::observe::ErrorBar>, unit: &str| {
        b.map(|b| {
            serde_json::json!({
                "error": b.absolute, "unit": unit, "relative_error": b.relative,
                "observed_order": b.order,
            })
        })
    };
    serde_json::json!({
        "central_film_mean": bar(e.central_film_mean, "m"),
        "contact_load_share_mean": bar(e.contact_load_share_mean, "1"),
        "contact_area_mean": bar(e.contact_area_mean, "m^2"),
        "amplitude_ratio": bar(e.amplitude_ratio, "1"),
    })
}

/// `summary.json`'s `passage`: the last passage's statistics, units beside the numbers.
pub fn passage(p: ehl_core::Passage) -> Value {
    serde_json::json!({
        "travel": q(p.travel_m, "m"),
        "duration": q(p.duration_s, "s"),
        "records": p.records,
        "central_film": {
            "mean": p.central_film_mean_m, "min": p.central_film_min_m,
            "max": p.central_film_max_m, "unit": "m",
        },
        "minimum_film": q(p.minimum_film_m, "m"),
        "max_pressure": q(p.max_pressure_pa, "Pa"),
        "lambda": p.lambda,
        "deformed_amplitude": p.deformed_amplitude_m.map(|v| q(v, "m")),
        "amplitude_ratio": p.amplitude_ratio,
        "contact_load_share": p.contact_load_share_mean.map(|m| serde_json::json!({
            "mean": m, "max": p.contact_load_share_max, "unit": "1",
        })),
        "contact_area_mean": p.contact_area_mean_m2.map(|v| q(v, "m^2")),
    })
}

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
        // Where the solids touch, apart from the fluid (`null`: the model does not say).
        "solid_contact": outcome.solid_contact().map(|c| serde_json::json!({
            "load_share": c.load_share,
            "area": q(c.area_m2, "m^2"),
            "max_pressure": q(c.max_pressure_pa, "Pa"),
        })),
        // A march through a patterned relief: its last passage (`null`: none).
        "passage": outcome.passage().map(passage),
        "accuracy": accuracy(outcome),
        "indicators": indicators,
        // Why the answer needs a caveat: not converged, or flagged by its accuracy (`null`: none).
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
