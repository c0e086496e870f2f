//! One case, every model: runs each model a comparison scene lists on the identical grid and
//! domain, and puts their standard observables side by side (`comparison.json`, `.csv`, a
//! terminal table), with overlaid centrelines and the film difference map. A model that fails is
//! listed with its diagnosis; the others still write their results.

use crate::accuracy;
use crate::error::{Result, create_dir, output, write_file};
use crate::model::Outcome;
use crate::output::{self, q};
use crate::plot::{self, MapPanel, Mark, Panel, Series};
use ehl_core::HertzScales;
use ehl_scene::{Model, Scene};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

mod notes;

/// One model's part of a comparison.
pub struct Entry {
    /// Which model.
    pub model: Model,
    /// The outcome, or the diagnosis of why there is none.
    pub outcome: Result<Box<dyn Outcome>, crate::Error>,
    /// Wall time of its run [s].
    pub wall_time_s: f64,
}

impl Entry {
    /// The model's name as scenes spell it.
    pub fn name(&self) -> String {
        model_name(self.model)
    }
}

/// The scene's spelling of a model.
pub fn model_name(m: Model) -> String {
    m.name().into()
}

/// Every model's run of one scene.
pub struct Comparison {
    /// The comparison scene.
    pub scene: Scene,
    /// One entry per listed model, in the scene's order.
    pub entries: Vec<Entry>,
    /// How the models shared the cores.
    pub schedule: Schedule,
    /// Wall time of the whole comparison, every model's run [s].
    pub total_wall_time_s: f64,
}

/// How a comparison's models share the cores.
///
/// Why at once by default: neither model keeps two cores busy on its own. Its line relaxation
/// (Reynolds) and its march's bookkeeping and transport (layer) are serial, so each keeps
/// well under two cores busy. The models are independent work, so the one that waits fills the
/// other's idle core (`cargo xtask bench --only compare`: docs/measured/bench-compare.md). Every
/// number each model returns is the same either way: the suite holds each model's observables
/// in a comparison to its run alone (`validation/tests/compare.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Schedule {
    /// Every model at once, each a task on the one rayon pool with its parallel parts in it:
    /// the comparison takes about its slowest model's time, and each model's wall time includes
    /// the others' share of the cores.
    #[default]
    SideBySide,
    /// One model after the other, each with every core: each wall time is that model's own cost.
    OneAtATime,
}

impl Schedule {
    /// The schedule a caller asks for with a `one at a time` switch (the binary's
    /// `--one-at-a-time`, Python's `one_at_a_time=True`).
    pub fn one_at_a_time(yes: bool) -> Self {
        if yes { Schedule::OneAtATime } else { Schedule::SideBySide }
    }

    /// The name written to `comparison.json` and the table.
    pub fn name(self) -> &'static str {
        match self {
            Schedule::SideBySide => "side-by-side",
            Schedule::OneAtATime => "one-at-a-time",
        }
    }
}

/// Runs every model of `scene` (validated) at once ([`Schedule::SideBySide`]), each on
/// `scene.for_model(m)`: the same conditions, domain and grid.
///
/// ```
/// use ehl_workbench::Outcome;
/// let scene = ehl_scene::load("seed").unwrap().with_points(65).unwrap();
/// let c = ehl_workbench::compare::run(&scene);
/// // One entry per model of the scene, in its order; a model that fails has its diagnosis.
/// let names: Vec<String> = c.entries.iter().map(|e| e.name()).collect();
/// assert_eq!(names, ["layer", "reynolds", "reynolds-flooded", "dry"]);
/// let dry = c.entries[3].outcome.as_ref().unwrap();
/// // The same contact in every entry: the dry one's peak is Hertz's p_h within 1 %.
/// assert!((dry.observables().max_pressure_pa / dry.scales().p_h - 1.0).abs() < 1e-2);
/// ```
pub fn run(scene: &Scene) -> Comparison {
    run_with(scene, Schedule::default())
}

/// Runs every model of `scene` (validated) on the given schedule, each on
/// `scene.for_model(m)`: the same conditions, domain and grid.
pub fn run_with(scene: &Scene, schedule: Schedule) -> Comparison {
    run_models(scene, schedule, None)
}

/// Runs every model of `scene` (validated) on the grid its accuracy asks for
/// ([`accuracy::resolved`]) on the given schedule, each answer checked: its error estimated
/// unless `estimate` is false, and flagged beyond the scene's accuracy (or the default
/// limit). What `ehl compare` and Python run.
pub fn run_checked(scene: &Scene, schedule: Schedule, estimate: bool) -> Comparison {
    let (scene, _) = accuracy::resolved(scene);
    run_models(&scene, schedule, Some(accuracy::Checking::of(&scene, estimate)))
}

/// Runs every model of `scene` on `schedule`, each answer checked as `checking` asks (when
/// given; the check's coarser runs belong to the model's wall time).
fn run_models(
    scene: &Scene,
    schedule: Schedule,
    checking: Option<accuracy::Checking>,
) -> Comparison {
    let t0 = Instant::now();
    let one = |m: Model| {
        let t = Instant::now();
        let own = scene.for_model(m);
        let outcome = crate::run::run_scene(&own).map(|o| match checking {
            Some(how) => Box::new(accuracy::Checked::new(&own, o, how)) as Box<dyn Outcome>,
            None => o,
        });
        Entry { model: m, outcome, wall_time_s: t.elapsed().as_secs_f64() }
    };
    let models = scene.models();
    let entries = match schedule {
        Schedule::OneAtATime => models.into_iter().map(one).collect(),
        // The models are tasks on the one rayon pool, their own parallel parts nested in them:
        // a model on its own plain thread would enter the pool from outside at every line
        // relaxation's join, a hand-over that costs more than the idle core gives.
        Schedule::SideBySide => {
            use rayon::prelude::*;
            models.into_par_iter().map(one).collect()
        }
    };
    Comparison {
        scene: scene.clone(),
        entries,
        schedule,
        total_wall_time_s: t0.elapsed().as_secs_f64(),
    }
}

impl Comparison {
    /// Whether every model gave an answer.
    pub fn all_converged(&self) -> bool {
        self.entries.iter().all(|e| e.outcome.is_ok())
    }

    /// The Hertz scales of the scene's contact.
    pub fn scales(&self) -> HertzScales {
        HertzScales::new(&self.scene.conditions.contact())
    }

    /// The table as JSON: per model the observables (SI), wall time, converged (answered) or the
    /// diagnosis, and the caveat of an answer returned unconverged (`null` otherwise); the
    /// conditions and the Hertz scales.
    pub fn to_json(&self) -> Value {
        let s = self.scales();
        let g = self.scene.grid();
        let rows: Vec<Value> = self
            .entries
            .iter()
            .map(|e| match &e.outcome {
                Ok(o) => {
                    let ob = o.observables();
                    json!({
                        "model": e.name(), "converged": true,
                        "central_film_m": ob.central_film_m, "minimum_film_m": ob.minimum_film_m,
                        "minimum_film_at_m": [ob.minimum_film_at_m.0, ob.minimum_film_at_m.1],
                        "film_overlap_m": ob.film_overlap_m,
                        "max_pressure_pa": ob.max_pressure_pa,
                        "max_pressure_at_m": [ob.max_pressure_at_m.0, ob.max_pressure_at_m.1],
                        "contact_extent_x_m": ob.contact_extent_x_m,
                        "contact_extent_y_m": ob.contact_extent_y_m,
                        "load_error": ob.load_error, "wall_time_s": e.wall_time_s,
                        "errors": errors_json(Some(o.as_ref())),
                        "solid_contact": o.solid_contact(),
                        "passage": o.passage().map(crate::output::passage),
                        "caveat": o.caveat(),
                    })
                }
                Err(d) => json!({
                    "model": e.name(), "converged": false, "diagnosis": d.to_string(),
                    "wall_time_s": e.wall_time_s,
                    // A march that failed: how far it got, and where its record is.
                    "failed_march": d.partial().map(|p| json!({
                        "steps_taken": p.steps,
                        "time_reached": q(p.t_s, "s"),
                        "record": format!("{}/failure.json", e.name()),
                    })),
                }),
            })
            .collect();
        json!({
            "scene": self.scene.name,
            "description": self.scene.description,
            "conditions": self.scene.conditions,
            "lubricant": self.scene.lubricant,
            "layer": self.scene.layer,
            "scales": {
                "a": q(s.a, "m"), "p_h": q(s.p_h, "Pa"), "a2_over_r": q(s.delta, "m"),
            },
            "grid": {"nx": g.nx, "ny": g.ny, "x_a": [g.x_min, g.x_max], "y_a": [g.y_min, g.y_max]},
            "definitions": {
                "film": "separation of the solid surfaces: Reynolds film, layer thickness plus any gap above it, dry gap",
                "minimum_film": "smallest film over the domain",
                "contact_extent": format!("length along y = 0 (x) and x = 0 (y) where p >= {} p_h, crossings interpolated", ehl_core::observe::EXTENT_THRESHOLD),
            },
            "models": rows,
            "schedule": self.schedule.name(),
            "total_wall_time_s": self.total_wall_time_s,
        })
    }

    /// The same table as CSV; a failed model has empty numbers and its diagnosis.
    pub fn to_csv(&self) -> String {
        let rows: Vec<serde_json::Value> = self
            .entries
            .iter()
            .map(|e| {
                let ob = e.outcome.as_ref().ok().map(|o| o.observables());
                let contact = e.outcome.as_ref().ok().and_then(|o| o.solid_contact());
                let passage = e.outcome.as_ref().ok().and_then(|o| o.passage());
                let bars = e.outcome.as_ref().ok().and_then(|o| o.estimate())
                    .map(|(est, _)| est.passage).unwrap_or_default();
                serde_json::json!({
                    "model": e.name(),
                    "converged": ob.is_some(),
                    "central_film_m": ob.map(|o| o.central_film_m),
                    "minimum_film_m": ob.map(|o| o.minimum_film_m),
                    "max_pressure_pa": ob.map(|o| o.max_pressure_pa),
                    "contact_extent_x_m": ob.map(|o| o.contact_extent_x_m),
                    "contact_extent_y_m": ob.map(|o| o.contact_extent_y_m),
                    "load_error": ob.map(|o| o.load_error),
                    "film_overlap_m": ob.map(|o| o.film_overlap_m),
                    "contact_load_share": contact.map(|c| c.load_share),
                    "contact_area_m2": contact.map(|c| c.area_m2),
                    "contact_max_pressure_pa": contact.map(|c| c.max_pressure_pa),
                    "passage_central_film_mean_m": passage.map(|p| p.central_film_mean_m),
                    "passage_minimum_film_m": passage.map(|p| p.minimum_film_m),
                    "passage_lambda": passage.and_then(|p| p.lambda),
                    "passage_amplitude_ratio": passage.and_then(|p| p.amplitude_ratio),
                    "passage_amplitude_ratio_error": bars.amplitude_ratio.map(|b| b.absolute),
                    "passage_central_film_mean_error_m": bars.central_film_mean.map(|b| b.absolute),
                    "passage_contact_load_share_mean": passage.and_then(|p| p.contact_load_share_mean),
                    "passage_contact_load_share_mean_error": bars.contact_load_share_mean.map(|b| b.absolute),
                    "passage_contact_load_share_max": passage.and_then(|p| p.contact_load_share_max),
                    "passage_contact_area_mean_m2": passage.and_then(|p| p.contact_area_mean_m2),
                    "passage_contact_area_mean_error_m2": bars.contact_area_mean.map(|b| b.absolute),
                    "error": errors_json(e.outcome.as_ref().ok().map(|o| o.as_ref())),
                    "wall_time_s": e.wall_time_s,
                    "diagnosis": e.outcome.as_ref().err().map(|d| d.to_string()),
                    "caveat": e.outcome.as_ref().ok().and_then(|o| o.caveat()),
                })
            })
            .collect();
        crate::output::csv(&rows)
    }

    /// The side-by-side table for the terminal: each observable with its estimated error
    /// (`11.790 ± 0.310`) where one was estimated, then each model's caveats and flags.
    pub fn table(&self) -> String {
        let s = self.scales();
        let g = self.scene.grid();
        // Bounds as a reader reads them: at most four decimals (a grown inlet is -1.3670236… a).
        let b = |v: f64| {
            let t = format!("{v:.4}");
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        let mut t = format!(
            "scene {} ({}x{} over [{}, {}] x [{}, {}] a; a = {:.4} mm, p_h = {:.4} GPa)\n",
            self.scene.name,
            g.nx,
            g.ny,
            b(g.x_min),
            b(g.x_max),
            b(g.y_min),
            b(g.y_max),
            s.a * 1e3,
            s.p_h * 1e-9
        );
        // Each cell: the value, with its error bar where there is one.
        let cell = |o: &dyn Outcome, k: usize, v: f64| {
            let bar = o.estimate().and_then(|(e, _)| e.errors[k]);
            let (scale, digits) = match k {
                0 | 1 => (1e9, 3),
                2 => (1e-9, 4),
                _ => (1e3, 4),
            };
            accuracy::with_bar(v, bar.as_ref(), scale, digits)
        };
        let rows: Vec<(String, Result<[String; 7], String>)> = self
            .entries
            .iter()
            .map(|e| {
                let row = match &e.outcome {
                    Ok(o) => {
                        let ob = o.observables();
                        Ok([
                            cell(o.as_ref(), 0, ob.central_film_m),
                            cell(o.as_ref(), 1, ob.minimum_film_m),
                            cell(o.as_ref(), 2, ob.max_pressure_pa),
                            cell(o.as_ref(), 3, ob.contact_extent_x_m),
                            cell(o.as_ref(), 4, ob.contact_extent_y_m),
                            format!("{:.1e}", ob.load_error),
                            format!("{:.2}", e.wall_time_s),
                        ])
                    }
                    Err(d) => Err(format!("FAILED after {:.2} s: {d}", e.wall_time_s)),
                };
                (e.name(), row)
            })
            .collect();
        let heads = [
            "h_c [nm]",
            "h_min [nm]",
            "p_max [GPa]",
            "2a_x [mm]",
            "2a_y [mm]",
            "load err",
            "wall [s]",
        ];
        let widths: Vec<usize> = (0..7)
            .map(|k| {
                rows.iter()
                    .filter_map(|r| r.1.as_ref().ok().map(|c| c[k].chars().count()))
                    .chain([heads[k].chars().count()])
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        t += &format!("  {:<16}", "model");
        for (h, w) in heads.iter().zip(&widths) {
            t += &format!(" {h:>w$}");
        }
        t += "\n";
        for (name, row) in &rows {
            t += &format!("  {name:<16}");
            match row {
                Ok(cells) => {
                    for (c, w) in cells.iter().zip(&widths) {
                        t += &format!(" {c:>w$}");
                    }
                }
                Err(m) => t += &format!(" {m}"),
            }
            t += "\n";
        }
        t += &self.notes();
        t += &format!(
            "  all models: {:.2} s of wall, {} ({})\n",
            self.total_wall_time_s,
            self.schedule.name(),
            match self.schedule {
                Schedule::SideBySide => "each wall shares the cores with the others",
                Schedule::OneAtATime => "each wall is that model's own cost",
            }
        );
        t
    }

    /// Writes the comparison into `dir` (replaced as a whole once everything is written):
    /// the table (JSON, CSV), the overlaid centrelines, the film difference map (layer − Reynolds,
    /// when both converged), and each model's own outputs in a subfolder.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        output::replace_dir(dir, |stage| self.write_into(stage))
    }

    fn write_into(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let mut files = vec![];
        let f = dir.join("comparison.json");
        let text =
            serde_json::to_string_pretty(&self.to_json()).map_err(output("comparison.json"))?;
        write_file(&f, text + "\n")?;
        files.push(f);
        let f = dir.join("comparison.csv");
        write_file(&f, self.to_csv())?;
        files.push(f);
        if let Some(csv) = self.history_csv() {
            let f = dir.join("comparison_history.csv");
            write_file(&f, csv)?;
            files.push(f);
        }
        if self.scene.outputs.figures {
            files.extend(self.figures(dir)?);
        }
        for e in &self.entries {
            let sub = dir.join(e.name());
            match &e.outcome {
                Ok(o) => {
                    create_dir(&sub)?;
                    files.extend(output::write_into(o.as_ref(), &sub)?);
                }
                // A march that failed: what it had done, beside its diagnosis.
                Err(err) if err.partial().is_some() => {
                    create_dir(&sub)?;
                    files.extend(output::write_failure(&self.scene, &e.name(), err, &sub)?);
                }
                Err(_) => {}
            }
        }
        Ok(files)
    }

    /// The models' histories (runs in time) in one table, SI: every step's standard observables,
    /// the solids' approach and the share of the load they carry where they touch (empty for a
    /// model that reports none).
    pub fn history_csv(&self) -> Option<String> {
        let mut s = String::from(
            "model,t_s,central_film_m,minimum_film_m,film_overlap_m,max_pressure_pa,approach_m,contact_load_share\n",
        );
        let mut any = false;
        for e in &self.entries {
            let Ok(o) = e.outcome.as_ref() else { continue };
            let Some(h) = o.history() else { continue };
            any = true;
            let approach = aligned_approach(o.as_ref(), h);
            let contact = o.contact_history().filter(|c| c.len() == h.len());
            for (k, (t, ob)) in h.iter().enumerate() {
                let d = approach.as_ref().map_or(String::new(), |a| format!("{:e}", a[k]));
                let c = contact.as_ref().map_or(String::new(), |c| format!("{:e}", c[k].0));
                s += &format!(
                    "{},{t:e},{:e},{:e},{:e},{:e},{d},{c}\n",
                    e.name(),
                    ob.central_film_m,
                    ob.minimum_film_m,
                    ob.film_overlap_m,
                    ob.max_pressure_pa
                );
            }
        }
        any.then_some(s)
    }

    /// Every model that ran in time, by name, with its history (time [s], observables).
    fn histories(&self) -> Vec<(String, &[(f64, ehl_core::Observables)])> {
        self.entries
            .iter()
            .filter_map(|e| Some((e.name(), e.outcome.as_ref().ok()?.history()?)))
            .collect()
    }

    /// Central and minimum film and maximum pressure against time, every model that ran in time.
    fn history_figure(&self, dir: &Path, note: &str) -> Result<Option<PathBuf>> {
        let p_h = self.scales().p_h;
        let runs = self.histories();
        if runs.is_empty() {
            return Ok(None);
        }
        let series = |f: fn(&ehl_core::Observables) -> f64, k: f64| -> Vec<Series> {
            runs.iter()
                .map(|(name, h)| {
                    Series::new(
                        name.clone(),
                        h.iter().map(|(t, o)| (t * 1e3, f(o) * k)).collect(),
                        Mark::Line,
                    )
                })
                .collect()
        };
        // The approach's change: the squeeze's drain (its value, ~a²/R, hides nanometres).
        let approach: Vec<Series> = self
            .entries
            .iter()
            .filter_map(|e| {
                let o = e.outcome.as_ref().ok()?;
                let h = o.history()?;
                let a = aligned_approach(o.as_ref(), h)?;
                let d0 = *a.first()?;
                let pts = h.iter().zip(&a).map(|((t, _), d)| (t * 1e3, (d - d0) * 1e9)).collect();
                Some(Series::new(e.name(), pts, Mark::Line))
            })
            .collect();
        // The share of the load the solids carry where they touch, when any model's did.
        let contact: Vec<Series> = self
            .entries
            .iter()
            .filter_map(|e| {
                let o = e.outcome.as_ref().ok()?;
                let (h, c) = (o.history()?, o.contact_history()?);
                (c.len() == h.len()).then_some(())?;
                let pts = h.iter().zip(&c).map(|((t, _), c)| (t * 1e3, 100.0 * c.0)).collect();
                Some(Series::new(e.name(), pts, Mark::Line))
            })
            .collect();
        let touched = contact.iter().any(|s| s.points.iter().any(|p| p.1 > 0.0));
        let f = dir.join("comparison_history.png");
        // The motion's stops and starts, marked on every panel.
        let events = self.motion_events();
        let panel = |title: &str, y: &str, s: Vec<Series>| {
            events.iter().fold(Panel::new(title, "t [ms]", y, styled(s)), |p, (t, what)| {
                p.mark_x(t * 1e3, *what)
            })
        };
        let panels: Vec<Panel> = [
            panel("Central film", "h_c [nm]", series(|o| o.central_film_m, 1e9)),
            panel("Minimum film", "h_min [nm]", series(|o| o.minimum_film_m, 1e9)),
            panel("Maximum pressure", "p_max / p_h", series(|o| o.max_pressure_pa, 1.0 / p_h)),
            panel("Approach since the start", "δ − δ(0) [nm]", approach),
        ]
        .into_iter()
        .chain(touched.then(|| panel("The solids' share of the load", "share [%]", contact)))
        .filter(Panel::has_data)
        .collect();
        plot::charts(&f, &panels, note)?;
        Ok(Some(f))
    }

    /// When the scene's motion stops and starts [s] (none for a scene that does not march).
    fn motion_events(&self) -> Vec<(f64, &'static str)> {
        let u = self.scene.conditions.rolling_velocity_m_s.unwrap_or(0.0);
        self.scene.run.as_ref().and_then(|r| r.kinematics(u).ok()).map_or(vec![], |k| k.events())
    }

    /// Every model's snapshots at the plan's snapshot times, pressure and film along `y = 0`
    /// overlaid (the seed's Figs. 6 and 10 with every model); `None` without snapshots. Films
    /// above three times the largest central film of any snapshot are the open gap: left off.
    fn snapshot_figure(&self, dir: &Path, note: &str) -> Result<Option<PathBuf>> {
        // Each model's snapshots, taken once (they copy their films).
        let models: Vec<(String, &dyn Outcome, Vec<_>)> = self
            .entries
            .iter()
            .filter_map(|e| e.outcome.as_ref().ok().map(|o| (e.name(), o.as_ref())))
            .map(|(name, o)| (name, o, o.snapshots()))
            .filter(|m| !m.2.is_empty())
            .collect();
        let Some((_, first, _)) = models.first() else { return Ok(None) };
        let (g, sc) = (*first.grid(), first.scales());
        let (j, jc) = (g.row_nearest(0.0), g.col_nearest(0.0));
        let nm = sc.delta * 1e9;
        let cap = 3.0
            * models.iter().flat_map(|m| m.2.iter().map(|s| s.2[[j, jc]])).fold(0.0, f64::max)
            * nm;
        let xs = g.xs();
        let line = |a: &ndarray::Array2<f64>, k: f64| -> Vec<(f64, f64)> {
            xs.iter().zip(a.row(j).iter()).map(|(&x, &v)| (x, v * k)).collect()
        };
        // A pair of panels per model (pressure, film), one series per snapshot time.
        let mut panels = vec![];
        for (name, _, snaps) in &models {
            let (mut pressures, mut films) = (vec![], vec![]);
            for (t, p, h) in snaps {
                let label = format!("t = {t:.4} s");
                pressures.push(Series::new(label.clone(), line(p, 1.0), Mark::Line));
                let film = line(h, nm).into_iter().filter(|v| v.1 <= cap).collect();
                films.push(Series::new(label, film, Mark::Line));
            }
            panels.push(Panel::new(
                &format!("{name}: pressure along y = 0"),
                "x / a",
                "p / p_h",
                pressures,
            ));
            panels.push(Panel::new(&format!("{name}: film along y = 0"), "x / a", "h [nm]", films));
        }
        let f = dir.join("comparison_snapshots.png");
        plot::charts(&f, &panels, note)?;
        Ok(Some(f))
    }

    /// After a stop: central and minimum film against the time since the surfaces stopped, on
    /// log axes (the seed's Fig. 9 read as a decay), while they rest; `None` when the motion
    /// never rests after rolling.
    fn squeeze_figure(&self, dir: &Path, note: &str) -> Result<Option<PathBuf>> {
        let Some(run) = &self.scene.run else { return Ok(None) };
        let u = self.scene.conditions.rolling_velocity_m_s.unwrap_or(0.0);
        let Ok(motion) = run.kinematics(u) else { return Ok(None) };
        let runs = self.histories();
        // The stop: the first recorded time at rest (the state just as the surfaces stop).
        let Some(t_stop) =
            runs.first().and_then(|(_, h)| h.iter().map(|p| p.0).find(|&t| motion.speed(t) == 0.0))
        else {
            return Ok(None);
        };
        let series = |f: fn(&ehl_core::Observables) -> f64| -> Vec<Series> {
            runs.iter()
                .map(|(name, h)| {
                    let pts = h
                        .iter()
                        .skip_while(|(t, _)| *t <= t_stop)
                        .take_while(|(t, _)| motion.speed(*t) == 0.0)
                        .filter(|(_, o)| f(o) > CONTACT_FILM_M)
                        .map(|(t, o)| ((t - t_stop) * 1e3, f(o) * 1e9))
                        .collect();
                    Series::new(name.clone(), pts, Mark::Line)
                })
                .collect()
        };
        let f = dir.join("comparison_squeeze.png");
        plot::charts(
            &f,
            &[
                Panel::new(
                    "Central film after the stop",
                    "time since the stop [ms]",
                    "h_c [nm]",
                    styled(series(|o| o.central_film_m)),
                )
                .log_log(),
                Panel::new(
                    "Minimum film after the stop (above 0.01 nm: below, the solids touch)",
                    "time since the stop [ms]",
                    "h_min [nm]",
                    styled(series(|o| o.minimum_film_m)),
                )
                .log_log(),
            ],
            note,
        )?;
        Ok(Some(f))
    }

    fn figures(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let ok: Vec<(String, &dyn Outcome)> = self
            .entries
            .iter()
            .filter_map(|e| e.outcome.as_ref().ok().map(|o| (e.name(), o.as_ref())))
            .collect();
        if ok.is_empty() {
            return Ok(vec![]);
        }
        let s = self.scales();
        let g = self.scene.grid();
        let j0 = g.row_nearest(0.0);
        let xs = g.xs();
        // Films beyond 5x the largest central film (the open gap outside the contact) are left
        // off the film panel so the contact's films are readable.
        let hc_max =
            ok.iter().map(|(_, o)| o.observables().central_film_m).fold(0.0, f64::max).max(1e-9);
        let cap_nm = 5.0 * hc_max * 1e9;
        let mut p_series = vec![];
        let mut h_series = vec![];
        for (name, o) in &ok {
            let p = o.pressure();
            p_series.push(Series::new(
                name.clone(),
                xs.iter().zip(p.row(j0)).map(|(&x, &v)| (x, v)).collect(),
                Mark::Line,
            ));
            let film = o.film();
            h_series.push(Series::new(
                name.clone(),
                xs.iter()
                    .zip(film.row(j0))
                    .map(|(&x, &v)| (x, s.h_si(v) * 1e9))
                    .filter(|v| v.1 <= cap_nm)
                    .collect(),
                Mark::Line,
            ));
        }
        // Each model's central film with its estimated error, where there is one.
        let bars: Vec<String> = ok
            .iter()
            .filter(|(_, o)| o.lubricated())
            .filter_map(|(name, o)| {
                let (e, _) = o.estimate()?;
                let hc = o.observables().central_film_m;
                Some(format!("{name} {}", accuracy::with_bar(hc, e.errors[0].as_ref(), 1e9, 3)))
            })
            .collect();
        // A march through a pattern: each model's solids' mean share over the last passage.
        let shares: Vec<String> = ok
            .iter()
            .filter_map(|(name, o)| {
                let s = o.passage()?.contact_load_share_mean?;
                let bar = o.estimate().and_then(|(e, _)| e.passage.contact_load_share_mean);
                Some(format!("{name} {}", accuracy::with_bar(s, bar.as_ref(), 100.0, 2)))
            })
            .collect();
        let note = format!(
            "{}: R = {} mm, F = {} N, u1 = {} m/s; {}x{}{}{}",
            self.scene.name,
            self.scene.conditions.ball_radius_m * 1e3,
            self.scene.conditions.load_n,
            self.scene.conditions.rolling_velocity_m_s.unwrap_or(0.0),
            g.nx,
            g.ny,
            if bars.is_empty() {
                String::new()
            } else {
                format!("; h_c [nm]: {}", bars.join(", "))
            },
            if shares.is_empty() {
                String::new()
            } else {
                format!("; the solids' mean share over the last passage [%]: {}", shares.join(", "))
            }
        );
        let centre = dir.join("comparison_centreline.png");
        plot::charts(
            &centre,
            &[
                Panel::new("Pressure along y = 0", "x / a", "p / p_h", styled(p_series)),
                Panel::new(
                    &format!("Film along y = 0 (up to {cap_nm:.0} nm)"),
                    "x / a",
                    "h [nm]",
                    styled(h_series),
                ),
            ],
            &note,
        )?;
        let mut files = vec![centre];
        files.extend(self.history_figure(dir, &note)?);
        files.extend(self.squeeze_figure(dir, &note)?);
        files.extend(self.snapshot_figure(dir, &note)?);
        // The first two lubricated models in the scene's order (the seed's: layer − Reynolds).
        let wet: Vec<&(String, &dyn Outcome)> = ok.iter().filter(|(_, o)| o.lubricated()).collect();
        if let [a, b, ..] = wet.as_slice() {
            files.extend(self.map_figures(dir, &note, [*a, *b], cap_nm)?);
        }
        Ok(files)
    }

    /// The maps of two lubricated models `[(name, outcome); 2]`: their film difference, clipped
    /// to `±cap_nm` [nm] (outside the contact both films open to micrometres), and their films
    /// and pressures side by side (a pattern inside the contact, a dent's print).
    fn map_figures(
        &self,
        dir: &Path,
        note: &str,
        pair: [&(String, &dyn Outcome); 2],
        cap_nm: f64,
    ) -> Result<Vec<PathBuf>> {
        let [(name_a, a), (name_b, b)] = pair;
        let (s, g) = (self.scales(), self.scene.grid());
        let diff = (a.film() - b.film()).mapv(|v| (s.h_si(v) * 1e9).clamp(-cap_nm, cap_nm));
        let map = dir.join("comparison_film_difference.png");
        let title = format!("Film difference {name_a} − {name_b}");
        let bar_label = "Δh [nm]".into();
        let panel = MapPanel { field: &diff, title, bar_label, diverging: true };
        plot::heat_maps(&map, &[panel], &g, note)?;
        // The films up to twice the largest central film, so that the contact's own variations
        // take the colours rather than the open gap around it.
        let top = 0.4 * cap_nm;
        let film = |o: &dyn Outcome| o.film().mapv(|v| (s.h_si(v) * 1e9).clamp(0.0, top));
        let (fa, fb) = (film(*a), film(*b));
        let gpa = |o: &dyn Outcome| o.pressure().mapv(|v| s.p_si(v) * 1e-9);
        let (pa, pb) = (gpa(*a), gpa(*b));
        let panel = |field, title: String, bar: &str| MapPanel {
            field,
            title,
            bar_label: bar.into(),
            diverging: false,
        };
        let maps = dir.join("comparison_maps.png");
        plot::heat_maps(
            &maps,
            &[
                panel(&fa, format!("Film, {name_a}"), "h [nm]"),
                panel(&fb, format!("Film, {name_b}"), "h [nm]"),
                panel(&pa, format!("Pressure, {name_a}"), "p [GPa]"),
                panel(&pb, format!("Pressure, {name_b}"), "p [GPa]"),
            ],
            &g,
            note,
        )?;
        Ok(vec![map, maps])
    }
}

/// The film below which the squeeze figure counts the solids as touching [m]: 0.01 nm, a
/// twentieth of a molecular diameter of any oil; what a solver reports below it is its own
/// noise about `H = 0`.
const CONTACT_FILM_M: f64 = 1e-11;

/// A comparison's curves styled: the first two models (what the comparison is about) solid,
/// the references listed after them (the flooded solve, the dry contact) dashed, so that a
/// reference drawn over a curve it nearly equals leaves that curve showing between its dashes.
fn styled(mut series: Vec<Series>) -> Vec<Series> {
    for s in series.iter_mut().skip(2) {
        s.dashed = true;
    }
    series
}

/// An answer's estimated errors for the comparison's JSON and CSV: per observable its error
/// (absolute, SI) and relative error, and the grids; nulls where none was estimated (the same
/// keys every row, so the CSV's columns line up).
fn errors_json(o: Option<&dyn Outcome>) -> Value {
    let est = o.and_then(|o| o.estimate());
    let mut m = serde_json::Map::new();
    for (k, (name, unit)) in ehl_core::observe::OBSERVED.iter().enumerate() {
        let b = est.and_then(|(e, _)| e.errors[k]);
        m.insert(
            format!("{name}_{unit}"),
            json!({"error": b.map(|b| b.absolute), "relative": b.map(|b| b.relative)}),
        );
    }
    m.insert("limit".into(), json!(est.map(|e| e.1)));
    m.insert(
        "grids".into(),
        json!(
            est.map(|(e, _)| e.grids.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(" "))
        ),
    );
    Value::Object(m)
}

/// A model's approach [m] on the times of its history, or `None` when it reports none or its
/// times are not the history's.
fn aligned_approach(o: &dyn Outcome, h: &[(f64, ehl_core::Observables)]) -> Option<Vec<f64>> {
    let a = o.approach_history()?;
    let same = a.len() == h.len()
        && a.iter().zip(h).all(|((ta, _), (th, _))| (ta - th).abs() <= 1e-12 * th.abs().max(1e-30));
    same.then(|| a.into_iter().map(|(_, d)| d).collect())
}
