//! Layer-model scenes: the run (start state, motion, stop rule) and what it writes.

use crate::drive::{self, Plan, Step, Transient};
use crate::error::{Result, Within};
use crate::model::{Centreline, ContactModel, Outcome, q};
use crate::plot::{self, MapPanel, Mark, Panel, Series};
use ehl_core::observe::Observables;
use ehl_core::{Grid, HertzScales, hertz};
use ehl_layer::{
    LayerModel, LayerState, Monitor, Scheme, Snapshot, SqueezeReport, SteadyReport, SteadySettings,
    Stepper, rolling_steady, squeeze_steady, stability_estimate, uniform_state,
};
use ehl_scene::{LayerView, Method, Motion, Scene, StartState};
use ndarray::Array2;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a layer scene produced.
pub struct LayerOutcome {
    /// The scene run.
    pub scene: Scene,
    /// Hertz scales.
    pub scales: HertzScales,
    /// The grid [a].
    pub grid: Grid,
    /// `l0 / (a²/R)`, `Eo / p_h`, for normalising.
    pub l0: f64,
    /// What the model read of the scene.
    pub view: LayerView,
    /// `Eo / p_h`.
    pub eo: f64,
    /// The state at the end (steady, or where the march stopped).
    pub final_state: LayerState,
    /// Final layer thickness `L` [a²/R] and gap `H` [a²/R].
    pub l: Array2<f64>,
    /// Final gap above the layer [a²/R].
    pub gap: Array2<f64>,
    /// The scene's own motion (absent for `motion: none`).
    pub record: Option<LayerRecord>,
    /// The direct steady-rolling solve (method `steady`, or a `steady-rolling` start).
    pub steady: Option<SteadyReport>,
    /// The direct steady-squeeze solve (a `squeezed` start).
    pub squeeze: Option<SqueezeReport>,
    /// The monitor of the final state (SI).
    pub final_monitor: Monitor,
    /// Explicit stability estimate [s] at the scene's grid.
    pub stability_estimate_s: f64,
    /// Building the model [s].
    pub setup_time_s: f64,
    /// The whole run [s].
    pub total_time_s: f64,
}

/// A layer march: a row per step, strain, pressure and thickness at the snapshots.
pub type LayerRecord = drive::Record<LayerRow, Snapshot>;

/// What is recorded after each step of a layer march: the standard observables (the driver
/// computes them once for every model) and the layer's own quantities beside them. Its
/// `Serialize` form is the time series' columns.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LayerRow {
    /// Time [s] from the start of the motion.
    #[serde(rename = "t_s")]
    pub t: f64,
    /// The standard observables, one definition for every model.
    #[serde(flatten)]
    pub observed: Observables,
    /// The layer's own: its thickness, the dry zone, the approach, the wiggle.
    #[serde(flatten)]
    pub layer: Monitor,
}

/// The layer model as the driver marches it.
struct LayerMarch<'a> {
    m: &'a LayerModel,
    state: LayerState,
    stepper: Stepper,
}

impl Transient for LayerMarch<'_> {
    type Row = LayerRow;
    type Snapshot = Snapshot;
    type Saved = (LayerState, Stepper);
    fn time(&self) -> f64 {
        self.state.t
    }
    fn step(&mut self, dt: f64, estimate_error: bool) -> Result<Step> {
        self.stepper.estimate_error = estimate_error;
        let i = self.stepper.step(self.m, &mut self.state, dt)?;
        Ok(Step { solves: i.solves, iterations: i.iterations, error_estimate: i.error_estimate })
    }
    fn row(&self, step: &Step, observed: &Observables) -> LayerRow {
        LayerRow {
            t: self.state.t,
            observed: *observed,
            layer: Monitor::of(self.m, &self.state, step.iterations),
        }
    }
    /// The standard observables the steady rule watches: central and minimum film per `l0`,
    /// maximum pressure per `p_h`, contact extent along `x` per `2a` (interpolated at 1 % of
    /// `p_h`, so it moves smoothly rather than by whole cells).
    fn monitors(&self, r: &LayerRow) -> Vec<f64> {
        let (sc, l0, o) = (&self.m.scales, self.m.supply_thickness_m(), &r.observed);
        vec![
            o.central_film_m / l0,
            o.minimum_film_m / l0,
            o.max_pressure_pa / sc.p_h,
            o.contact_extent_x_m / (2.0 * sc.a),
        ]
    }
    fn snapshot(&self) -> Snapshot {
        Snapshot::of(self.m, &self.state)
    }
    fn fields(&self) -> Vec<(String, Array2<f64>)> {
        let (sn, s) = (Snapshot::of(self.m, &self.state), &self.m.scales);
        vec![
            ("pressure_pa".into(), sn.p.mapv(|v| s.p_si(v))),
            ("layer_thickness_m".into(), sn.l.mapv(|v| s.h_si(v))),
            ("strain".into(), sn.eps),
            ("gap_m".into(), (&sn.film - &sn.l).mapv(|v| s.h_si(v))),
        ]
    }
    fn observables(&self) -> Observables {
        let (m, s) = (self.m, &self.state);
        let film = s.thickness(m) + s.gap(m);
        Observables::from_fields(&m.grid, &m.scales, &s.p, &film)
    }
    fn save(&self) -> Option<Self::Saved> {
        Some((self.state.clone(), self.stepper.clone()))
    }
    fn restore(&mut self, (state, stepper): Self::Saved) {
        self.state = state;
        self.stepper = stepper;
    }
}

/// The registered layer model.
pub struct Layer;

impl ContactModel for Layer {
    fn kind(&self) -> ehl_scene::Model {
        ehl_scene::Model::Layer
    }
    fn run(&self, scene: &Scene) -> Result<Box<dyn Outcome>> {
        Ok(Box::new(run_layer(scene)?))
    }
    /// Nothing happens before the layer touches the ball, where the Hertz separation equals the
    /// supply thickness `l0`: the inlet goes where it is `2 l0`.
    fn inlet_distance(&self, scene: &Scene) -> f64 {
        scene.supply.as_ref().map_or(0.0, |sup| {
            let s = ehl_core::HertzScales::new(&scene.conditions.contact());
            ehl_core::hertz::separation_radius(2.0 * s.h_dimless(sup.thickness_m))
        })
    }
}

impl Outcome for LayerOutcome {
    fn caveat(&self) -> Option<String> {
        self.steady.as_ref().and_then(|r| r.cycle).map(|c| {
            format!(
                "steady solve settled on a cycle (strain mismatch up to {:.1e}, at x = {:.3} a, y = {:.3} a): over its last {} iterations the central film moved by {:.1e} and the maximum pressure by {:.1e} (relative)",
                c.mismatch, c.at_a[0], c.at_a[1], c.window, c.central_film_spread, c.max_pressure_spread
            )
        })
    }
    fn scene(&self) -> &Scene {
        &self.scene
    }
    fn scales(&self) -> HertzScales {
        self.scales
    }
    fn grid(&self) -> &Grid {
        &self.grid
    }
    fn pressure(&self) -> &Array2<f64> {
        &self.final_state.p
    }
    fn film(&self) -> Array2<f64> {
        &self.l + &self.gap
    }
    fn wall_time_s(&self) -> f64 {
        self.total_time_s
    }
    fn summary(&self) -> Value {
        LayerOutcome::summary(self)
    }
    fn centreline(&self) -> Centreline {
        LayerOutcome::centreline(self)
    }
    fn fields(&self) -> Vec<(String, Array2<f64>)> {
        LayerOutcome::fields(self)
    }
    fn time_series(&self) -> Result<Option<Vec<Value>>> {
        self.record.as_ref().map(|rec| crate::model::json_rows(&rec.rows)).transpose()
    }
    fn history(&self) -> Option<&[(f64, Observables)]> {
        self.record.as_ref().map(|r| r.observed.as_slice())
    }
    fn contact_history(&self) -> Option<Vec<(f64, f64)>> {
        let r = self.record.as_ref()?;
        Some(
            r.rows
                .iter()
                .map(|row| (row.layer.contact_load_share, row.layer.contact_area))
                .collect(),
        )
    }
    fn solid_contact(&self) -> Option<ehl_core::SolidContact> {
        let p = &self.final_state.p;
        Some(ehl_layer::model::solid_contact(&self.grid, &self.scales, p, &self.l, self.l0))
    }
    fn approach_history(&self) -> Option<Vec<(f64, f64)>> {
        self.record.as_ref().map(|r| r.rows.iter().map(|row| (row.t, row.layer.approach)).collect())
    }
    fn snapshots(&self) -> Vec<(f64, &Array2<f64>, Array2<f64>)> {
        let Some(rec) = &self.record else { return vec![] };
        rec.snapshots.iter().map(|(t, sn)| (*t, &sn.p, sn.film.clone())).collect()
    }
    fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
        LayerOutcome::figures(self, dir, prefix, footnote)
    }
    fn report(&self) -> String {
        layer_report(self)
    }
}

/// Runs a layer scene: its start state, then the march or the steady solve it asks for.
pub fn run_layer(scene: &Scene) -> Result<LayerOutcome> {
    let t_all = Instant::now();
    // The scene resolved once: everything below reads the view.
    let view = scene.layer_view()?;
    let (r, spec, supply_m) = (&view.march.run, view.layer, view.supply.thickness_m);
    let motion = view.march.motion.clone();
    let grid = view.grid;
    let t0 = Instant::now();
    let mut m =
        LayerModel::new(&view.contact, &view.lubricant, &spec, supply_m, motion, grid, view.dry)
            .within(|| format!("scene `{}`", view.name))?;
    let setup_time_s = t0.elapsed().as_secs_f64();
    let fail = |what: &str| format!("scene `{}`: {what}", view.name);

    let spin = crate::progress::spinner("layer");
    let mut squeeze = None;
    let mut steady = None;
    let stepper = Stepper::new(r.time.scheme, r.time.picard);
    let mut solve_steady = |what: &str, settings: &SteadySettings| -> Result<LayerState> {
        spin.set_message(format!("layer {what}: steady rolling, solved directly"));
        let (s, rep) = rolling_steady(&m, settings).within(|| fail(what))?;
        steady = Some(rep);
        Ok(s)
    };
    let method = r.method();
    let mut state = match (method, r.start()) {
        (Method::Steady, _) => solve_steady("steady solve", &r.steady)?,
        (Method::March, StartState::Uniform) => {
            uniform_state(&m).within(|| fail("uniform start"))?
        }
        (Method::March, StartState::SteadyRolling) => {
            // A march starts in its own steady state: at one implicit step a cell that is the
            // direct solve at one sub-step a cell, term for term (`ehl_layer::steady`). From the
            // scene's finer steady solve (4 sub-steps, 4.7 % more central film on 129²) the march
            // drifted to its own as the layer renewed: after a stop and a start the seed's
            // contact settled 4.7 % above where it began, an artefact read as physics. Other
            // steps keep the scene's sub-steps.
            let own = r.time.scheme == Scheme::Implicit && r.time.steps_per_cell == 1.0;
            let settings =
                SteadySettings { substeps: if own { 1 } else { r.steady.substeps }, ..*r.steady };
            solve_steady("steady-rolling start", &settings)?
        }
        (Method::March, StartState::Squeezed) => {
            let (s, rep) = squeeze_steady(&m).within(|| fail("steady squeeze"))?;
            squeeze = Some(rep);
            s
        }
    };
    // The scene's own motion starts at t = 0.
    state.t = 0.0;
    m.set_passing(view.march.relief.clone(), view.supply.holes.clone());
    let record = match (method, &r.motion) {
        (Method::Steady, _) | (_, Motion::None) => None,
        (Method::March, motion) => {
            let label = motion.label();
            // Error control from a step the layer resolves at the inlet, η(0)/Eo / 100; BDF2's
            // error estimate is third order, Heun's second.
            let order = if stepper.scheme == Scheme::Implicit { 3.0 } else { 2.0 };
            let controlled = Some((m.eta(0.0) / m.eo * 1e-2, order));
            let plan =
                Plan::from_run(r, &view.march.passing, &grid, m.scales.a, m.motion(), controlled)
                    .within(|| fail("run"))?
                    .per_passage(&view.march.relief, &grid, m.scales.a, m.motion());
            let mut march = LayerMarch { m: &m, state, stepper };
            let mut rec = drive::drive(&mut march, &plan, &mut |t| {
                spin.set_message(format!("layer {label}: t = {t:.4} s"))
            })
            .within(|| fail(&format!("{label} run")))?;
            state = march.state;
            // The final state closes the snapshot series.
            if rec.snapshots.last().is_none_or(|s| s.0 < state.t) {
                rec.snapshots.push((state.t, Snapshot::of(&m, &state)));
            }
            Some(rec)
        }
    };
    spin.finish_and_clear();
    let final_monitor = Monitor::of(&m, &state, 0);
    let l = state.thickness(&m);
    let gap = state.gap(&m);
    Ok(LayerOutcome {
        scene: scene.clone(),
        scales: m.scales,
        grid,
        l0: m.l0,
        view: view.clone(),
        eo: m.eo,
        l,
        gap,
        record,
        steady,
        squeeze,
        final_monitor,
        stability_estimate_s: stability_estimate(&m),
        setup_time_s,
        total_time_s: t_all.elapsed().as_secs_f64(),
        final_state: state,
    })
}

impl LayerOutcome {
    /// The supply's thickness `l0` [m].
    pub fn supply_thickness_m(&self) -> f64 {
        self.view.supply.thickness_m
    }

    /// What only the layer model reports (`summary.json`'s `details`).
    pub fn summary(&self) -> Value {
        let (s, f) = (&self.scales, &self.final_monitor);
        let (spec, r) = (&self.view.layer, &self.view.march.run);
        let mut run_json = json!({
            "start": r.start, "motion": r.motion, "features": r.features,
            "scheme": r.time.scheme, "time": r.time, "stop": r.stop,
        });
        if let Some(rec) = &self.record {
            let n = rec.steps.max(1) as f64;
            run_json["steps"] = json!(rec.steps);
            run_json["rejected_steps"] = json!(rec.rejected_steps);
            run_json["contact_solves"] = json!(rec.solves);
            run_json["contact_iterations"] = json!(rec.iterations);
            run_json["iterations_per_step"] = json!(rec.iterations as f64 / n);
            run_json["time_step_range"] =
                json!({"value": [rec.dt_range.0, rec.dt_range.1], "unit": "s"});
            run_json["simulated_time"] = q(self.final_state.t, "s");
            run_json["wall_time"] = q(rec.wall_time_s, "s");
            run_json["wall_time_per_step"] = q(rec.wall_time_s / n, "s");
            run_json["finished"] = json!(rec.finished);
            run_json["stop_reason"] = json!(rec.stop_reason);
        }
        json!({
            "lubricant": self.scene.lubricant,
            "supply": self.view.supply,
            "layer": spec,
            "laws": {
                "modulus": spec.modulus_law,
                "damper_reading": spec.damper_reading,
                "coefficient_smoothing": q(spec.coefficient_smoothing_a * s.a, "m"),
                "oedometric_modulus": q(self.eo * s.p_h, "Pa"),
            },
            // The layer's own; films, maximum pressure and contact extents are the shared
            // observables beside these.
            "results": {
                "central_layer_thickness": q(f.central_thickness, "m"),
                "minimum_layer_thickness_loaded": q(f.minimum_thickness, "m"),
                "central_pressure": q(f.central_pressure, "Pa"),
                "dry_diameter": q(f.dry_diameter, "m"),
                "approach": q(f.approach, "m"),
                "lateral_wiggle": q(f.lateral_wiggle, "Pa"),
            },
            "normalised": {
                "central_layer_thickness_over_l0": f.central_thickness / self.supply_thickness_m(),
                "minimum_layer_thickness_loaded_over_l0": f.minimum_thickness / self.supply_thickness_m(),
                "dry_diameter_over_2a": f.dry_diameter / (2.0 * s.a),
            },
            "run": run_json,
            "method": format!("{:?}", r.method()).to_lowercase(),
            "steady_solve": self.steady,
            "steady_squeeze_solve": self.squeeze,
            "explicit_stability_estimate": q(self.stability_estimate_s, "s"),
            "setup_time": q(self.setup_time_s, "s"),
        })
    }

    fn row(&self, field: &Array2<f64>) -> Vec<f64> {
        field.row(self.grid.row_nearest(0.0)).to_vec()
    }

    /// Pressure, layer, strain and gap along `y = 0`, with Hertz's pressure (SI).
    pub fn centreline(&self) -> Centreline {
        let (g, s) = (&self.grid, &self.scales);
        let xs = g.xs();
        let y = g.y(g.row_nearest(0.0));
        Centreline {
            columns: vec![
                ("x_m".into(), xs.iter().map(|&x| s.x_si(x)).collect()),
                (
                    "pressure_pa".into(),
                    self.row(&self.final_state.p).iter().map(|&v| s.p_si(v)).collect(),
                ),
                (
                    "layer_thickness_m".into(),
                    self.row(&self.l).iter().map(|&v| s.h_si(v)).collect(),
                ),
                ("strain".into(), self.row(&self.final_state.eps)),
                ("gap_m".into(), self.row(&self.gap).iter().map(|&v| s.h_si(v)).collect()),
                (
                    "pressure_dry_hertz_pa".into(),
                    xs.iter().map(|&x| s.p_si(hertz::pressure(x, y))).collect(),
                ),
            ],
        }
    }

    /// The final fields (SI).
    pub fn fields(&self) -> Vec<(String, Array2<f64>)> {
        let s = &self.scales;
        let mut v = vec![
            ("pressure_pa".to_string(), self.final_state.p.mapv(|v| s.p_si(v))),
            ("layer_thickness_m".to_string(), self.l.mapv(|v| s.h_si(v))),
            ("strain".to_string(), self.final_state.eps.clone()),
            ("gap_m".to_string(), self.gap.mapv(|v| s.h_si(v))),
        ];
        if let Some(rec) = &self.record {
            for (k, (t, snap)) in rec.snapshots.iter().enumerate() {
                let tag = format!("snapshot{k:02}_t{t:.5}s");
                v.push((format!("{tag}_pressure_pa"), snap.p.mapv(|v| s.p_si(v))));
                v.push((format!("{tag}_layer_thickness_m"), snap.l.mapv(|v| s.h_si(v))));
            }
        }
        v
    }

    /// Conditions and laws, for figure footnotes.
    pub fn note(&self) -> String {
        let (spec, r) = (&self.view.layer, &self.view.march.run);
        format!(
            "{}: R = {} mm, F = {} N, u1 = {} m/s, l0 = {} nm, E law {}, damper {} (κ = {:e}, {} laws){}, {} n_t = {}; grid {}x{}; a = {:.4} mm",
            self.scene.name,
            self.scene.conditions.ball_radius_m * 1e3,
            self.scene.conditions.load_n,
            self.scene.conditions.rolling_velocity_m_s.unwrap_or(0.0),
            self.supply_thickness_m() * 1e9,
            crate::model::word(&spec.modulus_law),
            crate::model::word(&spec.damper_reading),
            spec.law_parameters(self.scales.p_h).map_or(f64::NAN, |l| l.damper_constant),
            crate::model::word(&spec.laws),
            if spec.coefficient_smoothing_a > 0.0 {
                format!(", smoothing {} a", spec.coefficient_smoothing_a)
            } else {
                String::new()
            },
            crate::model::word(&r.time.scheme),
            r.time.steps_per_cell,
            self.grid.nx,
            self.grid.ny,
            self.scales.a * 1e3
        )
    }

    /// Pressure [p_h] and layer thickness [nm] maps side by side (pressure first, as every
    /// model's maps).
    fn maps(
        &self,
        f: &Path,
        l: &Array2<f64>,
        p: &Array2<f64>,
        when: &str,
        note: &str,
    ) -> Result<()> {
        let g = &self.grid;
        let lnm = l.mapv(|v| v * self.scales.delta * 1e9);
        plot::heat_maps(
            f,
            &[
                MapPanel {
                    field: p,
                    title: format!("Pressure p / p_h {when}"),
                    bar_label: "p / p_h".into(),
                    diverging: false,
                },
                MapPanel {
                    field: &lnm,
                    title: format!("Layer l [nm] {when}"),
                    bar_label: "l [nm]".into(),
                    diverging: false,
                },
            ],
            g,
            note,
        )
    }

    /// The maps, the centrelines, the history and the snapshots as PNG.
    pub fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>> {
        let note = self.note() + footnote;
        let note = note.as_str();
        let mut out = vec![];
        let (s, g) = (&self.scales, &self.grid);
        let l0_nm = self.supply_thickness_m() * 1e9;
        let x: Vec<f64> = g.xs();
        let line = |field: &Array2<f64>, scale: f64| -> Vec<(f64, f64)> {
            x.iter().cloned().zip(self.row(field).iter().map(|v| v * scale)).collect()
        };
        // Final centrelines: layer thickness and pressure, with dry Hertz for reference.
        let f = dir.join(format!("{prefix}centreline.png"));
        let hertz_p: Vec<(f64, f64)> = x.iter().map(|&xx| (xx, hertz::pressure(xx, 0.0))).collect();
        plot::charts(
            &f,
            &[
                Panel::new(
                    "Layer thickness along y = 0",
                    "x / a",
                    "l [nm]",
                    vec![Series::new("layer model", line(&self.l, s.delta * 1e9), Mark::Line)],
                )
                .legend(plotters::prelude::SeriesLabelPosition::LowerRight),
                Panel::new(
                    "Pressure along y = 0",
                    "x / a",
                    "p / p_h",
                    vec![
                        Series::new("layer model", line(&self.final_state.p, 1.0), Mark::Line),
                        Series::new("dry contact (Hertz)", hertz_p, Mark::Line),
                    ],
                ),
            ],
            note,
        )?;
        out.push(f);
        let f = dir.join(format!("{prefix}maps.png"));
        self.maps(&f, &self.l, &self.final_state.p, &format!("(final, l0 = {l0_nm} nm)"), note)?;
        out.push(f);
        if let Some(rec) = &self.record {
            let ser = |k: fn(&LayerRow) -> f64, scale: f64| -> Vec<(f64, f64)> {
                rec.rows.iter().map(|r| (r.t, k(r) * scale)).collect()
            };
            let f = dir.join(format!("{prefix}history.png"));
            plot::history_chart(
                &f,
                "t [s]",
                "Layer thickness",
                [
                    ("central", ser(|r| r.layer.central_thickness, 1e9)),
                    ("minimum", ser(|r| r.layer.minimum_thickness, 1e9)),
                ],
                "Pressure",
                [
                    ("maximum", ser(|r| r.observed.max_pressure_pa, 1.0 / s.p_h)),
                    ("central", ser(|r| r.layer.central_pressure, 1.0 / s.p_h)),
                ],
                note,
            )?;
            out.push(f);
            if !rec.snapshots.is_empty() {
                // Centrelines at every snapshot time.
                let f = dir.join(format!("{prefix}snapshots_centreline.png"));
                let series_of = |sel: fn(&ehl_layer::Snapshot) -> &Array2<f64>,
                                 scale: f64|
                 -> Vec<Series> {
                    rec.snapshots
                        .iter()
                        .map(|(t, sn)| {
                            Series::new(format!("t = {t:.4} s"), line(sel(sn), scale), Mark::Line)
                        })
                        .collect()
                };
                plot::charts(
                    &f,
                    &[
                        Panel::new(
                            "Layer thickness along y = 0",
                            "x / a",
                            "l [nm]",
                            series_of(|s| &s.l, s.delta * 1e9),
                        )
                        .legend(plotters::prelude::SeriesLabelPosition::LowerRight),
                        Panel::new(
                            "Pressure along y = 0",
                            "x / a",
                            "p / p_h",
                            series_of(|s| &s.p, 1.0),
                        ),
                    ],
                    note,
                )?;
                out.push(f);
                for (k, (t, sn)) in rec.snapshots.iter().enumerate() {
                    crate::error::interruption()?;
                    let f = dir.join(format!("{prefix}snapshot{k:02}_maps.png"));
                    self.maps(&f, &sn.l, &sn.p, &format!("at t = {t:.4} s"), note)?;
                    out.push(f);
                }
            }
        }
        Ok(out)
    }
}

/// The terminal report.
fn layer_report(o: &LayerOutcome) -> String {
    use std::fmt::Write;
    let mut out = String::new();

    let f = &o.final_monitor;
    let s = &o.scales;
    let l0 = o.supply_thickness_m();
    let _ = writeln!(
        out,
        "scene {} ({}x{}): {:.1} s wall",
        o.scene.name, o.grid.nx, o.grid.ny, o.total_time_s
    );
    if let Some(p) = &o.steady {
        let its: Vec<String> = p.iterations.iter().map(|(n, k)| format!("{k} on {n}²")).collect();
        let _ = writeln!(
            out,
            "  steady rolling solved directly: {} iterations, strain residual {:.1e}, {:.2} s wall",
            its.join(", "),
            p.strain_residual,
            p.wall_time_s
        );
    }
    if let Some(c) = Outcome::caveat(o) {
        let _ = writeln!(out, "  caveat: {c}");
    }
    if let Some(r) = &o.record {
        let _ = writeln!(
            out,
            "  run: {} steps ({} rejected), {:.4} s simulated, {:.1} s wall, {:.2} ms/step, {:.2} contact iterations/step; {}",
            r.steps,
            r.rejected_steps,
            o.final_state.t,
            r.wall_time_s,
            r.wall_time_s / r.steps.max(1) as f64 * 1e3,
            r.iterations as f64 / r.steps.max(1) as f64,
            r.stop_reason
        );
        if !r.finished {
            let _ = writeln!(out, "  warning: the run did not reach its stop condition");
        }
    }
    let _ = writeln!(
        out,
        "  central layer {:.4e} m ({:.4} l0)   minimum where loaded {:.4e} m ({:.4} l0)",
        f.central_thickness,
        f.central_thickness / l0,
        f.minimum_thickness,
        f.minimum_thickness / l0
    );
    let ob = o.observables();
    let _ = writeln!(
        out,
        "  max pressure {:.5e} Pa ({:.4} p_h)   contact extent {:.4e} m ({:.4} x 2a)   dry diameter {:.4e} m",
        ob.max_pressure_pa,
        ob.max_pressure_pa / s.p_h,
        ob.contact_extent_x_m,
        ob.contact_extent_x_m / (2.0 * s.a),
        f.dry_diameter
    );
    if f.lateral_wiggle > 0.05 * s.p_h {
        let _ = writeln!(
            out,
            "  note: row-to-row pressure wiggle {:.3} p_h: the lateral short-wave instability of the layer model (see docs/layer.md)",
            f.lateral_wiggle / s.p_h
        );
    }

    out
}
