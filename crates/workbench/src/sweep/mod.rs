//! Sweeps: one scene over one or two parameters, every model it lists at every point.
//!
//! A sweep runs in three steps that share one folder, so the same sweep runs on a laptop or as a
//! SLURM array:
//! 1. **plan** ([`Plan::new`], `plan.json`): every point's scene, built from the sweep file and
//!    given the domain and grid its physics needs ([`adapt`]), validated before anything runs;
//! 2. **run** ([`run`]): the points of a shard (all of them locally), in parallel over the cores,
//!    each in a single-threaded pool so its numbers do not depend on where or beside what it ran;
//!    each finished point is one file `points/NNNNN.json` written atomically, and points whose
//!    file exists are skipped: a killed run loses only the points in flight, and shards never
//!    write the same file;
//! 3. **merge** ([`merge::merge`]): `results.csv`, `results.json`, `cost.csv` and the charts.
//!
//! A model that fails at a point is recorded with its diagnosis; the sweep goes on.

pub mod merge;

/// The observables a check judges, in the order of every change and error triple.
pub const OBSERVED: [&str; 3] = ["h_c", "h_min", "p_max"];

use crate::accuracy::{self, gci as convergence, rule as adapt};
use crate::error::{Error, Result, io, output};
use crate::model::Outcome;
use crate::progress;
use ehl_core::Observables;
use ehl_scene::{Model, Scene, Sweep};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Every point of a sweep, ready to run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The sweep as given.
    pub sweep: Sweep,
    /// Every point, in order.
    pub points: Vec<PlannedPoint>,
}

/// One point: the parameters' values and the scene that runs them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlannedPoint {
    /// Its place in the plan.
    pub index: usize,
    /// The parameters' values, in the sweep's order.
    pub values: Vec<f64>,
    /// The scene that runs it (domain and grid adapted: the finest grid any of its models
    /// needs).
    pub scene: Scene,
    /// What the domain-and-grid rule changed from the base scene, if anything.
    pub adapted: Option<String>,
    /// Each model's own grid over the point's domain, where the rule gives it a coarser one
    /// than the point's ([`adapt::adapt_model`]); a model not listed runs on the point's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grids: Vec<(Model, ehl_scene::GridSpec)>,
}

impl PlannedPoint {
    /// The one-model scene model `m` runs this point on: the point's domain, `m`'s grid.
    pub fn scene_for(&self, m: Model) -> Scene {
        let mut one = self.scene.for_model(m);
        if let Some((_, g)) = self.grids.iter().find(|(k, _)| *k == m) {
            one.grid = *g;
        }
        one
    }
}

/// One model's answer at a point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelRecord {
    /// Which model.
    pub model: Model,
    /// The grid it ran on (the point's, or a coarser one its own rule allows); `None` in
    /// records that predate per-model grids, which ran on the point's.
    #[serde(default)]
    pub grid: Option<ehl_scene::GridSpec>,
    /// Whether a film separates the surfaces, as the outcome says (false for the dry contact,
    /// and for a model that failed: there is no outcome to say).
    pub lubricated: bool,
    /// The standard observables (SI); `None` when the model failed.
    pub observables: Option<Observables>,
    /// Why it failed, when it did …
    pub diagnosis: Option<String>,
    /// … and the kind of failure ([`crate::error::Diagnosis::class`]: `film closed`,
    /// `stalled`, …), what a map counts.
    #[serde(default)]
    pub failure: Option<String>,
    /// The model's premise indicators ([`crate::model::Outcome::indicators`]).
    #[serde(default)]
    pub indicators: std::collections::BTreeMap<String, crate::model::Indicator>,
    /// The statistics of the last passage of a pattern rolled through the contact
    /// ([`crate::model::Outcome::passage`]: its films, `λ`, a wave's `A_d/A_i`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passage: Option<ehl_core::Passage>,
    /// Wall time of the model's run at this point [s], single thread.
    pub wall_time_s: f64,
    /// The same point at half the points per side, when the sweep asks for it.
    pub grid_check: Option<CheckRecord>,
    /// … and at a quarter: with the half, the order the answer converges at.
    #[serde(default)]
    pub grid_check_quarter: Option<CheckRecord>,
    /// The estimated discretisation error of `h_c`, `h_min`, `p_max` from the three grids
    /// ([`convergence::grid_error`]); `None` where undefined (a check failed, the dry
    /// contact's films).
    #[serde(default)]
    pub grid_error: Option<[Option<convergence::GridError>; 3]>,
    /// The same point with a longer inlet, when the sweep asks for it.
    pub domain_check: Option<CheckRecord>,
    /// Wall time of the checks [s].
    pub check_wall_time_s: f64,
    /// Why the point's answer is not to be trusted as it stands (the solver's caveat, an
    /// estimated grid error or a domain check's change beyond the sweep's limit, or a check
    /// that failed); `None` when the solver converged and the checks pass (or were not asked
    /// for).
    pub flag: Option<String>,
}

/// A check run: its grid and domain, its observables, and the relative changes it measures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckRecord {
    /// Points along `x`.
    pub nx: usize,
    /// Points along `y`.
    pub ny: usize,
    /// Domain along `x` [a].
    pub x_a: [f64; 2],
    /// Domain along `y` [a].
    pub y_a: [f64; 2],
    /// Its observables, `None` when it failed.
    pub observables: Option<Observables>,
    /// Why it failed, when it did.
    pub diagnosis: Option<String>,
    /// Relative changes of `h_c`, `h_min`, `p_max` (grid: point − coarse over point; domain:
    /// larger − coarse over coarse); films only for lubricated models, `None` where undefined.
    pub change: Option<[Option<f64>; 3]>,
}

/// A finished point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointRecord {
    /// Its place in the plan.
    pub index: usize,
    /// The parameters' values.
    pub values: Vec<f64>,
    /// Points along `x`.
    pub nx: usize,
    /// Points along `y`.
    pub ny: usize,
    /// Domain along `x` [a].
    pub x_a: [f64; 2],
    /// Domain along `y` [a].
    pub y_a: [f64; 2],
    /// Every model's answer.
    pub models: Vec<ModelRecord>,
}

impl PointRecord {
    /// The grid model `m` ran on at this point (the point's, in records without one).
    pub fn grid_of(&self, m: &ModelRecord) -> ehl_scene::GridSpec {
        m.grid.unwrap_or(ehl_scene::GridSpec { nx: self.nx, ny: self.ny })
    }
}

impl Plan {
    /// Builds every point's scene (adapted when the sweep says so) and checks it.
    pub fn new(sweep: &Sweep, sweep_dir: Option<&Path>) -> Result<Plan> {
        let base = sweep.base_scene(sweep_dir)?;
        let points = sweep
            .points(&base)?
            .into_iter()
            .enumerate()
            .map(|(index, (values, scene))| {
                let (mut adapted_scene, adapted) = if sweep.adapt {
                    adapt::adapt(&scene, sweep.resolve, sweep.flag_change_above)
                } else {
                    (scene.clone(), None)
                };
                let what = format!("of sweep {} point {index} (adapted)", sweep.name);
                adapted_scene.validate(&what)?;
                adapted_scene.name = format!("{}-{index:05}", sweep.name);
                let mut grids = vec![];
                if sweep.adapt {
                    for m in scene.models() {
                        let one =
                            adapt::adapt_model(&scene, m, sweep.resolve, sweep.flag_change_above);
                        if one.grid != adapted_scene.grid {
                            one.validate(&format!("{what} for {}", m.name()))?;
                            grids.push((m, one.grid));
                        }
                    }
                }
                Ok(PlannedPoint { index, values, scene: adapted_scene, adapted, grids })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Plan { sweep: sweep.clone(), points })
    }

    /// Writes `plan.json` into `dir` (created), or, when `dir` already holds a plan, checks that
    /// it is this one (so a rerun resumes) and refuses otherwise.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let f = dir.join("plan.json");
        if f.exists() {
            let old = Plan::load(dir)?;
            if old != *self {
                return Err(Error::Refused(format!(
                    "{} holds the plan of another sweep (or of this one before it was edited): choose another --out, or remove the folder to start again",
                    dir.display()
                )));
            }
            return Ok(());
        }
        // No plan: the folder must be new or empty, never a folder of the user's files (its
        // `results.csv` would be overwritten).
        if dir.is_file() {
            return Err(Error::Refused(format!(
                "sweep folder {}: is a file (give a new folder, or an earlier sweep's)",
                dir.display()
            )));
        }
        if std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_some()) {
            return Err(Error::Refused(format!(
                "sweep folder {}: holds files but no sweep's plan.json: refusing to write into it (give a new or empty folder, or an earlier sweep's)",
                dir.display()
            )));
        }
        std::fs::create_dir_all(dir.join("points"))
            .map_err(io(format!("creating {}", dir.display())))?;
        let text = serde_json::to_string_pretty(self).map_err(output("plan.json"))?;
        write_atomic(&f, &(text + "\n"))
    }

    /// Reads the plan a sweep folder holds (`plan.json`).
    pub fn load(dir: &Path) -> Result<Plan> {
        let f = dir.join("plan.json");
        let text = std::fs::read_to_string(&f).map_err(io(format!(
            "reading {} (is this a sweep folder? `ehl sweep plan` writes it)",
            f.display()
        )))?;
        serde_json::from_str(&text).map_err(output(format!("parsing {}", f.display())))
    }

    /// The record of point `index` if it finished (a file that does not parse, or belongs to
    /// another point, counts as not finished).
    pub fn finished(&self, dir: &Path, index: usize) -> Option<PointRecord> {
        let text = std::fs::read_to_string(point_file(dir, index)).ok()?;
        let r: PointRecord = serde_json::from_str(&text).ok()?;
        (r.index == index && r.values == self.points[index].values).then_some(r)
    }
}

/// Where point `index`'s record goes.
pub fn point_file(dir: &Path, index: usize) -> PathBuf {
    dir.join("points").join(format!("{index:05}.json"))
}

/// Writes `text` to `path` through a temporary file in the same folder and a rename, so a reader
/// (or a killed writer) never sees half a file.
pub fn write_atomic(path: &Path, text: &str) -> Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::Refused(format!("{} is not a file name", path.display())))?
        .to_string_lossy();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, text).map_err(io(format!("writing {}", tmp.display())))?;
    std::fs::rename(&tmp, path).map_err(io(format!("moving {} into place", path.display())))
}

/// Shard `index` of `count`: the points `k` with `k % count == index` (neighbouring points,
/// which cost alike, go to different shards).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which shard (from 0).
    pub index: usize,
    /// Of how many.
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}`: a shard is I/N with 0 <= I < N (e.g. 0/4)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) =
            (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl Shard {
    /// Every point in one shard.
    pub fn all() -> Shard {
        Shard { index: 0, count: 1 }
    }
    /// Whether point `point` is this shard's.
    pub fn holds(&self, point: usize) -> bool {
        point % self.count == self.index
    }
}

/// Points run at once by default: one per core.
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}

/// What a run did.
pub struct RunSummary {
    /// Points run now.
    pub ran: usize,
    /// Points found finished and skipped.
    pub skipped: usize,
    /// Wall time [s].
    pub wall_time_s: f64,
}

/// Runs the points of `shard` that have no record yet, `jobs` at a time.
pub fn run(dir: &Path, shard: Shard, jobs: usize) -> Result<RunSummary> {
    if jobs < 1 {
        return Err(Error::Refused("--jobs must be >= 1".into()));
    }
    let plan = Plan::load(dir)?;
    std::fs::create_dir_all(dir.join("points"))
        .map_err(io(format!("creating {}/points", dir.display())))?;
    let mine: Vec<&PlannedPoint> = plan.points.iter().filter(|p| shard.holds(p.index)).collect();
    let mut todo: Vec<&PlannedPoint> =
        mine.iter().copied().filter(|p| plan.finished(dir, p.index).is_none()).collect();
    // The finest grids first: a sweep's time is the longest worker's, and the points on the
    // grids a thin film asks for cost a hundred times the others.
    todo.sort_by_key(|p| std::cmp::Reverse(p.scene.grid.nx * p.scene.grid.ny));
    let skipped = mine.len() - todo.len();
    let t0 = Instant::now();
    let bar = progress::bar(todo.len() as u64, &format!("sweep {}", plan.sweep.name));
    let next = AtomicUsize::new(0);
    let error: std::sync::Mutex<Option<Error>> = std::sync::Mutex::new(None);
    std::thread::scope(|s| {
        for _ in 0..jobs.min(todo.len().max(1)) {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    if k >= todo.len() || error.lock().unwrap().is_some() {
                        break;
                    }
                    let p = todo[k];
                    let rec = run_point(&plan.sweep, p);
                    let line = point_line(&plan.sweep, &rec);
                    let written = serde_json::to_string_pretty(&rec)
                        .map_err(output(format!("point {}", p.index)))
                        .and_then(|t| write_atomic(&point_file(dir, p.index), &(t + "\n")));
                    // A record that does not read back would be rerun forever: stop instead.
                    let written = written.and_then(|()| match plan.finished(dir, p.index) {
                        Some(_) => Ok(()),
                        None => Err(Error::Refused(format!(
                            "point {}: its record {} does not read back",
                            p.index,
                            point_file(dir, p.index).display()
                        ))),
                    });
                    if let Err(e) = written {
                        *error.lock().unwrap() = Some(e);
                        break;
                    }
                    bar.suspend(|| eprintln!("{line}"));
                    bar.inc(1);
                }
            });
        }
    });
    bar.finish_and_clear();
    if let Some(e) = error.into_inner().unwrap() {
        return Err(e);
    }
    Ok(RunSummary { ran: todo.len(), skipped, wall_time_s: t0.elapsed().as_secs_f64() })
}

/// The one-line report of a finished point.
fn point_line(sweep: &Sweep, r: &PointRecord) -> String {
    let vals: Vec<String> = sweep
        .parameters
        .iter()
        .zip(&r.values)
        .map(|(a, v)| format!("{} = {v}", a.parameter.name()))
        .collect();
    let models: Vec<String> = r
        .models
        .iter()
        .map(|m| {
            let name = crate::compare::model_name(m.model);
            // A model on a grid of its own says which.
            let time = match Some(r.grid_of(m)).filter(|g| (g.nx, g.ny) != (r.nx, r.ny)) {
                Some(g) => format!("{:.1} s on {}x{}", m.wall_time_s, g.nx, g.ny),
                None => format!("{:.1} s", m.wall_time_s),
            };
            match (&m.observables, &m.flag) {
                (Some(o), None) => format!("{name} h_c {:.3} nm ({time})", o.central_film_m * 1e9),
                (Some(o), Some(f)) => {
                    format!("{name} h_c {:.3} nm ({time}) FLAGGED: {f}", o.central_film_m * 1e9)
                }
                (None, _) => format!("{name} FAILED ({time})"),
            }
        })
        .collect();
    format!("point {} ({}; {}x{}): {}", r.index, vals.join(", "), r.nx, r.ny, models.join("; "))
}

/// What a point keeps of a model's answer.
#[derive(Clone)]
struct Answer {
    observables: Observables,
    /// Whether a film separates the surfaces.
    lubricated: bool,
    indicators: std::collections::BTreeMap<String, crate::model::Indicator>,
    /// [`crate::model::Outcome::caveat`].
    caveat: Option<String>,
    /// [`crate::model::Outcome::passage`].
    passage: Option<ehl_core::Passage>,
}
/// A model's failure: its diagnosis and the kind ([`crate::Error::class`]).
type Failed = (String, &'static str);

/// Runs one model on one scene in the current (single-thread) pool; a failure is its
/// diagnosis (the models report failures as errors: nothing on their paths panics).
fn run_model(scene: &Scene) -> (Result<Answer, Failed>, f64, Option<Box<dyn Outcome>>) {
    timed(|| crate::run::run_scene(scene))
}

/// A check of `answer` (`check`: its scene on coarser cells, over its domain or a grown one), run
/// as an estimate's coarser grids are ([`accuracy::run_check`]: from the answer, within the
/// estimate's bounds).
fn run_check(check: &Scene, answer: &dyn Outcome) -> (Result<Answer, Failed>, f64) {
    let (a, t, _) = timed(|| accuracy::run_check(check, answer));
    (a, t)
}

/// A run's answer (and the outcome it came from) or its failure, and its wall time [s].
fn timed(
    run: impl FnOnce() -> crate::error::Result<Box<dyn Outcome>>,
) -> (Result<Answer, Failed>, f64, Option<Box<dyn Outcome>>) {
    let t0 = Instant::now();
    let (out, outcome) = match run() {
        Ok(o) => (
            Ok(Answer {
                observables: o.observables(),
                lubricated: o.lubricated(),
                indicators: o.indicators().into_iter().collect(),
                caveat: o.caveat(),
                passage: o.passage(),
            }),
            Some(o),
        ),
        Err(e) => (Err((format!("{e:#}"), e.class())), None),
    };
    (out, t0.elapsed().as_secs_f64(), outcome)
}

/// The first three of the accuracy module's observables (`h_c`, `h_min`, `p_max`): what a
/// sweep's records keep.
fn three<T: Copy>(a: [T; 5]) -> [T; 3] {
    [a[0], a[1], a[2]]
}

/// The estimated grid errors of `h_c`, `h_min`, `p_max` ([`accuracy::grid_errors`]).
fn grid_errors(
    point: &Observables,
    half: &Observables,
    quarter: Option<&Observables>,
    lubricated: bool,
) -> [Option<convergence::GridError>; 3] {
    three(accuracy::grid_errors(point, half, quarter, lubricated))
}

/// The relative changes of `h_c`, `h_min`, `p_max` ([`accuracy::changes`]).
fn changes(a: &Observables, b: &Observables, lubricated: bool) -> [Option<f64>; 3] {
    three(accuracy::changes(a, b, lubricated))
}

fn check_record(scene: &Scene, run: &Result<Answer, Failed>) -> CheckRecord {
    CheckRecord {
        nx: scene.grid.nx,
        ny: scene.grid.ny,
        x_a: scene.domain.x_a,
        y_a: scene.domain.y_a,
        observables: run.as_ref().ok().map(|r| r.observables),
        diagnosis: run.as_ref().err().map(|e| e.0.clone()),
        change: None,
    }
}

/// Runs every model of a point, and its checks, in a single-thread pool: the numbers are then
/// the same whichever worker, shard or machine ran it (rayon's parallel sums would otherwise
/// vary in the last digits with the thread count and scheduling).
pub fn run_point(sweep: &Sweep, p: &PlannedPoint) -> PointRecord {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a one-thread pool");
    pool.install(|| {
        let scene = &p.scene;
        let models = scene
            .models()
            .into_iter()
            .map(|m| {
                let one = p.scene_for(m);
                let (main, wall_time_s, outcome) = run_model(&one);
                let mut rec = ModelRecord {
                    model: m,
                    grid: Some(one.grid),
                    lubricated: main.as_ref().is_ok_and(|r| r.lubricated),
                    observables: main.as_ref().ok().map(|r| r.observables),
                    diagnosis: main.as_ref().err().map(|e| e.0.clone()),
                    failure: main.as_ref().err().map(|e| e.1.to_string()),
                    indicators: main.as_ref().map(|r| r.indicators.clone()).unwrap_or_default(),
                    passage: main.as_ref().ok().and_then(|r| r.passage),
                    wall_time_s,
                    grid_check: None,
                    grid_check_quarter: None,
                    grid_error: None,
                    domain_check: None,
                    check_wall_time_s: 0.0,
                    flag: None,
                };
                let caveat = main.as_ref().ok().and_then(|r| r.caveat.clone());
                if let (Ok(Answer { observables: ob, lubricated: lub, .. }), Some(outcome)) =
                    (&main, &outcome)
                    && sweep.checks
                {
                    let (gs, ds) = (adapt::grid_check(&one), adapt::domain_check(&one));
                    let qs = adapt::grid_check(&gs);
                    let outcome = outcome.as_ref();
                    let (g, tg) = run_check(&gs, outcome);
                    // The quarter grid only matters when the half one answered.
                    let (q, tq) =
                        if g.is_ok() { run_check(&qs, outcome) } else { (g.clone(), 0.0) };
                    let (d, td) = run_check(&ds, outcome);
                    rec.check_wall_time_s = tg + tq + td;
                    let mut gc = check_record(&gs, &g);
                    let mut qc = check_record(&qs, &q);
                    let mut dc = check_record(&ds, &d);
                    let ob_of = |r: &Result<Answer, Failed>| r.as_ref().ok().map(|a| a.observables);
                    let (half, quarter, big) = (ob_of(&g), ob_of(&q), ob_of(&d));
                    gc.change = half.map(|c| changes(ob, &c, *lub));
                    if let (Some(c), Some(big)) = (half, big) {
                        dc.change = Some(changes(&big, &c, *lub));
                    }
                    if let (Some(half), Some(quarter)) = (half, quarter) {
                        qc.change = Some(changes(&half, &quarter, *lub));
                    }
                    rec.grid_error =
                        half.map(|half| grid_errors(ob, &half, quarter.as_ref(), *lub));
                    rec.flag = flag(sweep.flag_change_above, &gc, rec.grid_error.as_ref(), &dc);
                    rec.grid_check = Some(gc);
                    rec.grid_check_quarter = Some(qc);
                    rec.domain_check = Some(dc);
                }
                // The solver's own caveat flags the point first, checks or none.
                rec.flag = match (caveat, rec.flag.take()) {
                    (Some(c), Some(f)) => Some(format!("{c}; {f}")),
                    (c, f) => c.or(f),
                };
                rec
            })
            .collect();
        PointRecord {
            index: p.index,
            values: p.values.clone(),
            nx: scene.grid.nx,
            ny: scene.grid.ny,
            x_a: scene.domain.x_a,
            y_a: scene.domain.y_a,
            models,
        }
    })
}

/// The flag of a model at a point: each estimated grid error
/// ([`convergence::grid_error`]) and each domain check's change beyond `limit`, by how much,
/// and each check that failed. An undefined change (the dry contact's films) is not checked.
fn flag(
    limit: f64,
    grid: &CheckRecord,
    errors: Option<&[Option<convergence::GridError>; 3]>,
    domain: &CheckRecord,
) -> Option<String> {
    let mut parts = vec![];
    // The grid's share: each estimate beyond the limit, with its order when observed.
    let grid_over = errors.map(|es| {
        beyond(limit, es.map(|e| e.map(|e| (e.error, e.order))), |n, (e, order)| match order {
            Some(p) => format!("{n} ±{:.1} % (order {p:.2})", 100.0 * e),
            None => format!("{n} ±{:.1} %", 100.0 * e),
        })
    });
    // The domain's share: each change beyond the limit, signed.
    let domain_over = domain.change.map(|ch| {
        beyond(limit, ch.map(|v| v.map(|v| (v, ()))), |n, (v, ())| {
            format!("{n} {:+.1} %", 100.0 * v)
        })
    });
    for (what, check, over, c) in
        [("grid error", "grid", grid_over, grid), ("domain", "domain", domain_over, domain)]
    {
        match (over, &c.diagnosis) {
            (Some(over), _) if over.is_empty() => {}
            (Some(over), _) => parts.push(format!("{what} {}", over.join(", "))),
            (None, Some(_)) => parts.push(format!("{check} check failed")),
            (None, None) => {
                parts.push(format!("{check} check not compared (its reference failed)"))
            }
        }
    }
    (!parts.is_empty()).then(|| parts.join("; "))
}

/// The observables whose value (first of each pair) is beyond `limit` in size, each written by
/// `say` with its name ([`OBSERVED`]); undefined ones (the dry contact's films) are not judged.
fn beyond<T: Copy>(
    limit: f64,
    values: [Option<(f64, T)>; 3],
    say: impl Fn(&str, (f64, T)) -> String,
) -> Vec<String> {
    values
        .iter()
        .zip(OBSERVED)
        .filter_map(|(v, n)| v.filter(|(v, _)| v.abs() > limit).map(|v| say(n, v)))
        .collect()
}

/// Writes the SLURM array script for `shards` shards of the sweep in `dir`: one task per shard,
/// each `ehl sweep run DIR --shard $SLURM_ARRAY_TASK_ID/N` on the cores SLURM gives it.
pub fn write_sbatch(dir: &Path, shards: usize, cpus_per_task: usize) -> Result<PathBuf> {
    let refuse = |m: String| Err(Error::Refused(m));
    if shards < 1 {
        return refuse("--shards must be >= 1".into());
    }
    if cpus_per_task < 1 {
        return refuse("--cpus-per-task must be >= 1".into());
    }
    let plan = Plan::load(dir)?;
    if shards > plan.points.len() {
        return refuse(format!(
            "--shards {shards} is more than the sweep's {} points",
            plan.points.len()
        ));
    }
    let dir_abs = std::fs::canonicalize(dir).map_err(io(format!("finding {}", dir.display())))?;
    let exe = std::env::current_exe().map_err(io("locating the ehl binary"))?;
    let q = |p: &Path| format!("'{}'", p.display().to_string().replace('\'', "'\\''"));
    let text = format!(
        "#!/bin/bash\n\
         # SLURM array job for sweep `{name}` ({n} points in {shards} shards), written by `ehl sweep plan`.\n\
         # Submit with `sbatch {script}`; when every task has finished, `ehl sweep merge {dir}`.\n\
         # The ehl binary and this folder must be on a file system the compute nodes share.\n\
         #SBATCH --job-name=ehl-{name}\n\
         #SBATCH --array=0-{last}\n\
         #SBATCH --cpus-per-task={cpus_per_task}\n\
         #SBATCH --output={dir}/slurm-%A_%a.out\n\
         set -euo pipefail\n\
         exec {exe} sweep run {dir} --shard \"$SLURM_ARRAY_TASK_ID/{shards}\" --jobs \"${{SLURM_CPUS_PER_TASK:-1}}\"\n",
        name = plan.sweep.name,
        n = plan.points.len(),
        script = q(&dir_abs.join("sweep.sbatch")),
        dir = q(&dir_abs),
        last = shards - 1,
        exe = q(&exe),
    );
    let f = dir.join("sweep.sbatch");
    write_atomic(&f, &text)?;
    Ok(f)
}

/// Plans, runs every point not yet finished, and merges: the local sweep.
pub fn run_local(
    sweep: &Sweep,
    sweep_dir: Option<&Path>,
    dir: &Path,
    jobs: usize,
) -> Result<(RunSummary, Vec<PathBuf>)> {
    let plan = Plan::new(sweep, sweep_dir)?;
    plan.write(dir)?;
    let summary = run(dir, Shard::all(), jobs)?;
    let files = merge::merge(dir)?;
    Ok((summary, files))
}

/// The records of every point, in order; the missing ones named.
pub fn records(dir: &Path, plan: &Plan) -> Result<Vec<PointRecord>> {
    let mut out = vec![];
    let mut missing = vec![];
    for p in &plan.points {
        match plan.finished(dir, p.index) {
            Some(r) => out.push(r),
            None => missing.push(p.index),
        }
    }
    if !missing.is_empty() {
        let list: Vec<String> = missing.iter().take(12).map(|k| k.to_string()).collect();
        return Err(Error::Refused(format!(
            "{} of {} points have no result yet (points {}{}): run `ehl sweep run {}` (or the shards that hold them) first",
            missing.len(),
            plan.points.len(),
            list.join(", "),
            if missing.len() > 12 { ", …" } else { "" },
            dir.display()
        )));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obs(hc: f64, hmin: f64, p: f64) -> Observables {
        Observables {
            central_film_m: hc,
            minimum_film_m: hmin,
            max_pressure_pa: p,
            ..Default::default()
        }
    }

    fn record(o: Option<Observables>) -> CheckRecord {
        CheckRecord {
            nx: 0,
            ny: 0,
            x_a: [0.0; 2],
            y_a: [0.0; 2],
            diagnosis: o.is_none().then(|| "failed".to_string()),
            observables: o,
            change: None,
        }
    }

    /// The measured series of the seed's contact at 2 mm/s, 20 N, flooded, on 1153², 577²,
    /// 289² (h_c 4.1554, 4.0315, 3.5229 nm; h_min 1.0027, 0.9296, 0.5313 nm): the half grid
    /// moves h_c by 3.0 %, beyond a 2 % limit, but at the observed order 2.04 the point's own
    /// error is 1.25 · 3.0 % / 3 = 1.24 %: not flagged. Without the quarter grid the change
    /// itself is the estimate, and it is.
    #[test]
    fn a_point_is_flagged_on_its_estimated_error_not_on_the_half_grid_s_change() {
        let point = obs(4.1554e-9, 1.0027e-9, 5.2668e8);
        let half = obs(4.0315e-9, 0.9296e-9, 5.2666e8);
        let quarter = obs(3.5229e-9, 0.5313e-9, 5.2665e8);
        let domain = CheckRecord {
            change: Some([Some(0.001), Some(0.001), Some(0.0)]),
            ..record(Some(half))
        };
        let es = grid_errors(&point, &half, Some(&quarter), true);
        let hc = es[0].unwrap();
        assert!(
            (hc.order.unwrap() - 2.04).abs() < 0.01 && (hc.error - 0.0124).abs() < 2e-4,
            "{hc:?}"
        );
        // h_min on the film's scale: 0.0731 nm of 4.16 nm, at order 2 (2.45 observed): 0.73 %.
        let hmin = es[1].unwrap();
        assert!((hmin.error - 0.0073).abs() < 2e-4, "{hmin:?}");
        assert_eq!(flag(0.02, &record(Some(half)), Some(&es), &domain), None);
        let two = grid_errors(&point, &half, None, true);
        let f = flag(0.02, &record(Some(half)), Some(&two), &domain).unwrap();
        assert!(f.contains("grid error h_c ±3.0 %"), "{f}");
        // A failed half grid is a failed check; a domain change beyond the limit is named.
        let far = CheckRecord { change: Some([Some(0.03), None, None]), ..domain.clone() };
        let f = flag(0.02, &record(None), None, &far).unwrap();
        assert_eq!(f, "grid check failed; domain h_c +3.0 %");
    }

    /// The layer squeezed out at 2 mm/s, 40 N (measured on 1793², 897², 449²: h_c 0.21436,
    /// 0.21436, 0.21378 nm; h_min −2.3, −0.46, −0.40 pm, the solids touching): judged on the
    /// 0.21 nm film, 1.8 pm read as `h_min` ±2.6 %, a flag. On the nanometre floor it is
    /// 0.55 %, and no flag. The floor must not blunt the check where films are films: the
    /// 2 mm/s, 20 N Reynolds series above keeps its 1.24 % (the floor is a quarter of that
    /// film), and a sub-nanometre film that moves by a fifth of a nanometre is still flagged.
    #[test]
    fn picometre_changes_of_a_squeezed_out_film_are_judged_on_a_nanometre_not_flagged() {
        let point = obs(0.214362e-9, -2.3e-12, 5.2e8);
        let half = obs(0.214359e-9, -0.46e-12, 5.2e8);
        let quarter = obs(0.213779e-9, -0.40e-12, 5.2e8);
        let domain = CheckRecord { change: Some([Some(0.0); 3]), ..record(Some(half)) };
        let es = grid_errors(&point, &half, Some(&quarter), true);
        // The changes grow as the grid refines (order −4.85, credited 0.5):
        // 1.25 / (√2 − 1) ≈ 3.0 × 1.84 pm / 1 nm.
        let hmin = es[1].unwrap();
        assert!((hmin.error - 3.0 * 1.84e-3).abs() < 1e-4, "{hmin:?}");
        assert_eq!(flag(0.02, &record(Some(half)), Some(&es), &domain), None);
        // Judged on the film itself, it was flagged (the bug this floor removes).
        let on_film = convergence::grid_error(-2.3e-12, -0.46e-12, Some(-0.40e-12), 0.214e-9);
        assert!(on_film.unwrap().error > 0.02);
        // A sub-nanometre film that moves by 0.2 nm is flagged on the floor.
        let moved = obs(0.414e-9, -2.3e-12, 5.2e8);
        let es = grid_errors(&moved, &half, None, true);
        let f = flag(0.02, &record(Some(half)), Some(&es), &domain).unwrap();
        assert!(f.contains("grid error h_c ±20.0 %"), "{f}");
        // A film above the floor keeps its own scale.
        let four = obs(4.1554e-9, 1.0027e-9, 5.2668e8);
        assert_eq!(accuracy::film_scale(four.central_film_m), four.central_film_m);
    }

    /// The seed's contact at 2 mm/s, 80 N: its Reynolds film (NVM 1.8 nm) asks for cells of
    /// 0.0024 a, over 1025 points per side; the layer and the dry contact ask for no finer
    /// cells than the scene's. They run on the scene's 257² over the same rectangle (the
    /// thin film's inlet lies within the scene's), where a 2561² layer solve cost 480 s
    /// against 2 s for the same film within 0.8 %. A plan that ran every model on the point's
    /// grid, or gave a model its own domain, fails here.
    #[test]
    fn a_model_that_needs_no_finer_cells_runs_on_the_scene_s_cells_over_the_point_s_domain() {
        let sweep = Sweep::from_json(
            r#"{"name": "t", "scene": "seed", "parameters": [
                {"parameter": "conditions.rolling_velocity_m_s", "values": [0.002]},
                {"parameter": "conditions.load_n", "values": [80]}]}"#,
            "test",
        )
        .unwrap();
        let plan = Plan::new(&sweep, None).unwrap();
        let p = &plan.points[0];
        assert!(p.scene.grid.nx >= 1025, "{:?}", p.scene.grid);
        for m in p.scene.models() {
            let one = p.scene_for(m);
            assert_eq!(one.domain, p.scene.domain, "{m:?}");
            let own = matches!(m, Model::Layer | Model::Dry);
            let want = if own { 257 } else { p.scene.grid.nx };
            assert_eq!((one.grid.nx, one.grid.ny), (want, want), "{m:?}");
        }
        // Without the grid rule every model runs on the point's (scene's) cells.
        let coarse = Sweep { resolve: false, ..sweep };
        let plan = Plan::new(&coarse, None).unwrap();
        assert!(plan.points[0].grids.is_empty() && plan.points[0].scene.grid.nx == 257);
    }
}
