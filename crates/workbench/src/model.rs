//! The one model interface: every model (dry contact, layer, Reynolds) builds from a scene, runs
//! it, and answers in the same terms: the standard observables, the fields, its own outputs.
//! Nothing outside a model's own module matches on which model it is; the registry in
//! [`crate::run`] is the one place that lists them.

use crate::error::Result;
use ehl_core::{Grid, HertzScales, Observables};
use ehl_scene::Scene;
use ndarray::Array2;
use serde_json::{Value, json};
use std::any::Any;
use std::path::{Path, PathBuf};

/// A model the workbench can run: one registration line in [`crate::run::MODELS`].
pub trait ContactModel: Sync {
    /// The scene's name for it (`"dry"`, `"layer"`, `"reynolds"`).
    fn kind(&self) -> ehl_scene::Model;
    /// Runs a one-model scene (validated) for this model; fails with a diagnosis (what, where,
    /// when) if the model diverges or does not converge.
    fn run(&self, scene: &Scene) -> Result<Box<dyn Outcome>>;
    /// The inlet distance [a] upstream of the contact centre this model needs for the scene's
    /// conditions (sweeps grow a point's domain to it); 0: the scene's own domain will do.
    fn inlet_distance(&self, _scene: &Scene) -> f64 {
        0.0
    }
    /// The largest cell [a] on which this model's answer exists for the scene's conditions
    /// and, where the model knows how its answer moves with the grid, moves by at most `change`
    /// (relative) from half the points per side (sweeps refine a point's grid to it, `change`
    /// from their flag limit); infinite: any grid will do.
    fn cell_needed(&self, _scene: &Scene, _change: f64) -> f64 {
        f64::INFINITY
    }
    /// The scene a coarser grid of an error estimate or a sweep's check runs (the answer's
    /// scene on coarser cells): a model may bound its cost there, where an answer that is slow
    /// to come is no estimate worth waiting for ([`crate::accuracy::run_check`]); by default the
    /// scene itself.
    fn for_estimate(&self, coarse: Scene) -> Scene {
        coarse
    }
    /// Runs `coarse`, the scene of this model's answer `finer` on coarser cells, for an error
    /// estimate ([`crate::accuracy::estimate`]) or a sweep's check (over the same domain, or
    /// one grown beyond it): a model may start it from the finer answer, which differs from
    /// the coarse grid's own by the discretisation error (and the domain's change) only; by
    /// default it runs from its usual start.
    fn run_coarser(&self, coarse: &Scene, _finer: &dyn Outcome) -> Result<Box<dyn Outcome>> {
        self.run(coarse)
    }
    /// The films' relative error this model's answer is expected to have on the scene's grid,
    /// from the model's measured grid-error law, with the law in words: the estimate's fallback
    /// when no coarser grid can answer ([`crate::accuracy::estimate`]). `None`: no law known.
    fn film_error_law(&self, _scene: &Scene) -> Option<(f64, String)> {
        None
    }
    /// The order this model's films converge at, measured over many answers, with where it
    /// was measured: with it, an estimate from two grids credits that order (Roache's safety
    /// factor 1.25) rather than taking the change itself. `None`: not measured.
    fn verified_order(&self) -> Option<(f64, &'static str)> {
        None
    }
}

/// Any outcome as `Any`, so a caller that needs one model's own fields can downcast.
pub trait AsAny {
    /// As `&dyn Any`.
    fn as_any(&self) -> &dyn Any;
    /// As `Box<dyn Any>`.
    fn into_any(self: Box<Self>) -> Box<dyn Any>;
}

impl<T: Any> AsAny for T {
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn into_any(self: Box<Self>) -> Box<dyn Any> {
        self
    }
}

/// What a run produced. Hertz units inside (`P` in `p_h`, films in `a²/R`, lengths in `a`); the
/// writers turn them into SI.
pub trait Outcome: AsAny + Send + Sync + 'static {
    /// The scene it ran.
    fn scene(&self) -> &Scene;
    /// Hertz scales of its contact.
    fn scales(&self) -> HertzScales;
    /// Its grid [a].
    fn grid(&self) -> &Grid;
    /// Pressure `P` [p_h].
    fn pressure(&self) -> &Array2<f64>;
    /// Separation of the two solid surfaces [a²/R]: the Reynolds film, the layer plus any gap
    /// above it, the dry gap.
    fn film(&self) -> Array2<f64>;
    /// Whether a film separates the surfaces (false for the dry contact): the comparison's film
    /// difference map is between the first two lubricated models.
    fn lubricated(&self) -> bool {
        true
    }
    /// The standard observables, one definition for all models.
    fn observables(&self) -> Observables {
        Observables::from_fields(self.grid(), &self.scales(), self.pressure(), &self.film())
    }
    /// Scalars that say how far the model's own premises hold at this answer, or what the
    /// answer cost the solver (e.g. the Reynolds film's pressure-driven share of the flux, the
    /// layer model's premise), by name, each saying what it is: sweeps tabulate and chart every
    /// one without knowing any.
    fn indicators(&self) -> Vec<(String, Indicator)> {
        vec![]
    }
    /// Why the answer, though returned, is not converged to the solver's tolerance (a solve that
    /// settled on a cycle, with how much the cycle moves the answer), for a sweep to flag and a
    /// report to state; `None` when it converged.
    fn caveat(&self) -> Option<String> {
        None
    }
    /// Where the solids touch in the answer, with the contact's own share of the load, area
    /// and pressure (the layer model's: where its layer vanished); `None` for a model that
    /// does not tell contact from a film.
    fn solid_contact(&self) -> Option<ehl_core::SolidContact> {
        None
    }
    /// An answer that is the closed film because its grid cannot tell a thinner film from a
    /// closed gap: that film [m], its films' error whatever coarser grids or a grid law say
    /// (they resolve the film no better). `None` for an answer with a film of its own.
    fn film_resolution_m(&self) -> Option<f64> {
        None
    }
    /// Statistics over the last passage of a march rolling through a patterned relief
    /// (waviness, roughness): the films over it, `λ`, a single wave's deformed amplitude at the
    /// contact's centre ([`ehl_core::Passage`]); `None` for anything else.
    fn passage(&self) -> Option<ehl_core::Passage> {
        passage_of(self)
    }
    /// The contact and the rolling speed [m/s] the model ran (the scene's; the Reynolds
    /// model's Moes input resolves them).
    fn conditions_used(&self) -> (ehl_core::Contact, f64) {
        let c = &self.scene().conditions;
        (c.contact(), c.rolling_velocity_m_s.unwrap_or(0.0))
    }
    /// Wall time of the whole run [s].
    fn wall_time_s(&self) -> f64;
    /// What only this model reports, with units: the writer puts it after the part of
    /// `summary.json` every model shares ([`crate::output::summary`]: scene, model,
    /// conditions, scales, grid, observables, indicators, timings), whose keys it must not use.
    fn summary(&self) -> Value;
    /// Its fields along `y = 0` (SI), as CSV columns.
    fn centreline(&self) -> Centreline;
    /// Fields to write as `.npy`, SI, with their file stems.
    fn fields(&self) -> Vec<(String, Array2<f64>)>;
    /// A run in time's record, one row per step (SI, each row a JSON object whose leaves are
    /// the columns): the writer renders it as `timeseries.csv` ([`crate::output::csv`]).
    fn time_series(&self) -> Result<Option<Vec<Value>>> {
        Ok(None)
    }
    /// The standard observables after every step of a run in time (time [s] from the start of
    /// the motion), as the driver recorded them: what a comparison overlays.
    fn history(&self) -> Option<&[(f64, Observables)]> {
        None
    }
    /// The share of the load the solids carry and their area [m²] after every step, on the
    /// times of [`Outcome::history`] (one entry a record); `None` for a model that does not
    /// march or does not tell contact from a film.
    fn contact_history(&self) -> Option<Vec<(f64, f64)>> {
        None
    }
    /// The solids' mutual approach [m] after every step of a run in time, on the times of
    /// [`Outcome::history`]: `−h0`, where the film is `h = h0 + x²/2R + y²/2R +` the
    /// deformation (the Reynolds `H00`, the layer model's `h0`), so that a squeeze that drains
    /// the film raises it. `None` for a model that does not march or has no approach.
    fn approach_history(&self) -> Option<Vec<(f64, f64)>> {
        None
    }
    /// A run in time's snapshots: the time [s], pressure `P` [p_h] and film [a²/R] at each
    /// (what a comparison overlays at the same times).
    fn snapshots(&self) -> Vec<(f64, &Array2<f64>, Array2<f64>)> {
        vec![]
    }
    /// Its own figures, written into `dir` with `prefix`, `footnote` added to each figure's own
    /// footnote (the answer's estimated errors); the files written.
    fn figures(&self, dir: &Path, prefix: &str, footnote: &str) -> Result<Vec<PathBuf>>;
    /// The terminal report.
    fn report(&self) -> String;
    /// The answer's estimated discretisation error and the limit it was judged against, when
    /// one was estimated (the workbench's `accuracy` module).
    fn estimate(&self) -> Option<(&ehl_core::observe::Estimate, f64)> {
        None
    }
    /// The model's own outcome inside a wrapper that adds to it (an estimate of its error);
    /// `None` for a model's own outcome.
    fn inner(&self) -> Option<&dyn Outcome> {
        None
    }
}

/// [`Outcome::passage`]: the passage a periodic pattern's period long (else the domain's
/// length), at the rolling speed. A single wave's deformed amplitude is its film's at the
/// contact's centre: the centre's oscillation over the passage where the wave moves through
/// the contact (the amplitude-reduction literature's `A_d`, free of any window), else (a
/// longitudinal wave, which stands) the harmonic fitted across the centre over the whole
/// wavelengths within `|y| ≤ a/2`.
fn passage_of<O: Outcome + ?Sized>(o: &O) -> Option<ehl_core::Passage> {
    let (scene, a, g) = (o.scene(), o.scales().a, *o.grid());
    scene.run.as_ref().filter(|r| r.motion == ehl_scene::Motion::Rolling)?;
    let relief = scene.relief(a).ok()?;
    // A pattern (waviness, roughness) has an RMS height; dents alone pass and are gone.
    let rms = relief.rms_m()?;
    let u = o.conditions_used().1;
    let period_a = relief.period_a();
    let travel_a = period_a.unwrap_or(g.x_max - g.x_min);
    let duration = travel_a * a / u;
    let history = o.history()?;
    let p = ehl_core::Passage::over(history, duration, travel_a * a, Some(rms))?;
    let p = match o.contact_history() {
        Some(c) => p.with_contact(history, &c, duration),
        None => p,
    };
    let Some(w) = relief.single_wave() else { return Some(p) };
    let a_d = match period_a {
        Some(period_a) => {
            let omega = std::f64::consts::TAU * u / (period_a * a);
            ehl_core::passage::centre_amplitude(history, duration, omega)
        }
        None => standing_amplitude(o, w.wavelength_a),
    };
    Some(match a_d {
        Some(a_d) => p.with_amplitude(a_d, w.amplitude_m),
        None => p,
    })
}

/// A standing (longitudinal) wave's amplitude in the film across the centre: the harmonic
/// of wavelength `wavelength_a` [a] along `y` through the centre, fitted over a quartic trend
/// on the whole wavelengths within `|y| ≤ a/2`; `None` for a wave longer than that.
fn standing_amplitude<O: Outcome + ?Sized>(o: &O, wavelength_a: f64) -> Option<f64> {
    let whole = (1.0 / wavelength_a).floor();
    if whole < 1.0 {
        return None;
    }
    let (g, film, delta) = (o.grid(), o.film(), o.scales().delta);
    let reach = 0.5 * whole * wavelength_a + 1e-9;
    let i = g.col_nearest(0.0);
    let (ys, h): (Vec<f64>, Vec<f64>) = (0..g.ny)
        .filter(|&j| g.y(j).abs() <= reach)
        .map(|j| (g.y(j), film[[j, i]] * delta))
        .unzip();
    ehl_core::passage::harmonic_amplitude(&ys, &h, std::f64::consts::TAU / wavelength_a)
}

impl dyn Outcome {
    /// The model's own outcome type, for what only that model has (through any wrapper).
    pub fn downcast_ref<T: Outcome>(&self) -> Option<&T> {
        match self.inner() {
            Some(inner) => inner.downcast_ref(),
            None => self.as_any().downcast_ref(),
        }
    }
    /// The model's own outcome type, owned (a wrapper's is not: use [`Self::downcast_ref`]).
    pub fn downcast<T: Outcome>(self: Box<Self>) -> Option<Box<T>> {
        self.into_any().downcast().ok()
    }
    /// Grid axes [m].
    pub fn axes(&self) -> (ndarray::Array1<f64>, ndarray::Array1<f64>) {
        let (g, a) = (self.grid(), self.scales().a);
        (
            ndarray::Array1::from_shape_fn(g.nx, |i| g.x(i) * a),
            ndarray::Array1::from_shape_fn(g.ny, |j| g.y(j) * a),
        )
    }
}

/// Rows in their JSON form: what [`Outcome::time_series`] returns (the writer renders them as
/// CSV, [`crate::output::csv`]).
pub fn json_rows<T: serde::Serialize>(rows: &[T]) -> Result<Vec<Value>> {
    rows.iter()
        .map(serde_json::to_value)
        .collect::<std::result::Result<_, _>>()
        .map_err(crate::error::output("a time series"))
}

/// A scalar a model reports about its own answer, describing itself for the tables and charts
/// that show it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Indicator {
    /// The value.
    pub value: f64,
    /// Its unit (`"1"` for a ratio or a count).
    pub unit: String,
    /// What it says, as a chart title.
    pub description: String,
    /// Whether it spans decades (charted on a log scale).
    pub log_scale: bool,
}

impl Indicator {
    /// An indicator of `value` in `unit`, described by `description`.
    pub fn new(value: f64, unit: &str, description: &str, log_scale: bool) -> Self {
        Self { value, unit: unit.into(), description: description.into(), log_scale }
    }
}

/// A scalar with its unit.
pub fn q(value: f64, unit: &str) -> Value {
    json!({ "value": value, "unit": unit })
}

/// A setting's value as the scene spells it (`dowson-higginson`, `implicit`): what figure
/// footnotes and reports print, never the code's own type names.
pub fn word<T: serde::Serialize>(v: &T) -> String {
    match serde_json::to_value(v) {
        Ok(Value::String(s)) => s,
        Ok(other) => other.to_string(),
        Err(_) => String::new(),
    }
}

/// Columns of the centreline table: header (with unit) and values.
pub struct Centreline {
    /// `(header with unit, values)` per column.
    pub columns: Vec<(String, Vec<f64>)>,
}

impl Centreline {
    /// The table as CSV.
    pub fn to_csv(&self) -> String {
        let mut s = self.columns.iter().map(|c| c.0.as_str()).collect::<Vec<_>>().join(",");
        s.push('\n');
        for k in 0..self.columns[0].1.len() {
            let row: Vec<String> = self.columns.iter().map(|c| format!("{:e}", c.1[k])).collect();
            s.push_str(&row.join(","));
            s.push('\n');
        }
        s
    }
}
