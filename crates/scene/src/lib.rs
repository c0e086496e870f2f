//! Scenes as data: what to run (model, conditions in SI, domain, grid, solver settings,
//! outputs), read from JSON, checked before anything is computed or written.
//!
//! Built-in scenes are the JSON files in `validation/scenes/`, compiled in by name.

use ehl_core::{
    Contact, Dent, DrySettings, Grid, Hole, Kinematics, KinematicsError, Lubricant, Passing, Supply,
};
use ehl_layer::{LayerSpec, Scheme, SteadySettings};
use ehl_reynolds::{DensityLaw, ReynoldsSettings, ViscosityLaw};
use serde::{Deserialize, Serialize};
use std::path::Path;

pub mod sweep;
pub mod views;
pub use sweep::{Axis, Parameter, Sweep, builtin_sweep_names, load_sweep};
pub use views::{LayerView, ReynoldsView};

/// A scene. Unknown fields are refused, so a typo never silently falls back to a default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name, used for output folders.
    pub name: String,
    /// One line on what the scene shows.
    #[serde(default)]
    pub description: String,
    /// Which model runs it (a one-model scene) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    model: Option<Model>,
    /// … or which models run it, each on the same conditions, domain and grid (a comparison
    /// scene, for `ehl compare`). Exactly one of `model` and `models` is given: both are
    /// private, read through [`Scene::model`] and [`Scene::models`] and set only by parsing
    /// (checked) or by [`Scene::for_model`] and [`Scene::comparing`], so no value holds both.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    models: Vec<Model>,
    /// Ball, load, modulus and rolling speed (SI).
    pub conditions: Conditions,
    /// Lubricant (the layer's damper, the Reynolds fluid); required by those models.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lubricant: Option<LubricantSpec>,
    /// The oil supplied to the contact (its thickness, holes in it), one for every model: the
    /// layer model's layer. Required by the layer model; the Reynolds model runs fully flooded
    /// (and says so in its summary) until it reads it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub supply: Option<Supply>,
    /// The viscoelastic layer; required by the layer model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<LayerSpec>,
    /// What happens in time: start, motion, features, steps, stop rule, snapshots (layer model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<RunSpec>,
    /// The Reynolds model's laws, optional Moes input and solver settings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reynolds: Option<ReynoldsSpec>,
    /// The computational rectangle [a].
    pub domain: Domain,
    /// Points per side.
    pub grid: GridSpec,
    #[serde(default)]
    /// The dry contact solver's settings (every model's contact).
    pub solver: DrySettings,
    #[serde(default)]
    /// Which files a run writes.
    pub outputs: Outputs,
    /// A one-model scene's case through every model: the comparison scene (a built-in name or
    /// a path) that `ehl compare` of this scene runs ([`Scene::as_comparison`]). The seed's
    /// layer scenes name theirs (`squeeze-after-stop`: `stop-compare`), whose plan both models
    /// can march on a common grid; `ehl run` ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub comparison: Option<String>,
    /// The relative accuracy asked of the answer (`0.02`: 2 %) instead of a grid: the domain and
    /// grid then follow the accuracy rule for it (the sweeps' rule, each model's own need, the
    /// finest any listed model asks for; never coarser than `grid`), the answer's estimated
    /// error is checked against it, and a miss is flagged with the grid that would meet it.
    /// Absent: the scene's own grid, its answers flagged beyond 5 %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<f64>,
}

/// The model a scene runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Model {
    /// Dry elastic contact of the ball on a flat (the contact core alone).
    Dry,
    /// The oedometric viscoelastic layer model.
    Layer,
    /// The conventional Reynolds EHL model: mass conserving, fed the scene's `supply` (fully
    /// flooded when the scene has none).
    Reynolds,
    /// The same solver fully flooded whatever the scene supplies (it does not read `supply`):
    /// the reference a starved contact is measured against (`R = h_c / h_c,flooded`).
    ReynoldsFlooded,
}

/// A block of a scene beyond the conditions, domain, grid, contact solver and outputs that
/// every model reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Block {
    /// `lubricant`.
    Lubricant,
    /// `supply`.
    Supply,
    /// `layer`.
    Layer,
    /// `run`.
    Run,
    /// `reynolds`.
    Reynolds,
}

impl Model {
    /// The name a scene gives it (`reynolds-flooded`).
    pub fn name(self) -> &'static str {
        match self {
            Model::Dry => "dry",
            Model::Layer => "layer",
            Model::Reynolds => "reynolds",
            Model::ReynoldsFlooded => "reynolds-flooded",
        }
    }

    /// The blocks this model reads: a comparison hands each model these and no others (one
    /// line per model, not a rule per pair).
    pub fn blocks(self) -> &'static [Block] {
        match self {
            Model::Dry => &[],
            Model::Layer => &[Block::Lubricant, Block::Supply, Block::Layer, Block::Run],
            Model::Reynolds => &[Block::Lubricant, Block::Supply, Block::Run, Block::Reynolds],
            Model::ReynoldsFlooded => &[Block::Lubricant, Block::Run, Block::Reynolds],
        }
    }
}

/// The Reynolds model's block.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReynoldsSpec {
    #[serde(default)]
    /// The viscosity law.
    pub viscosity: ViscosityLaw,
    #[serde(default)]
    /// The density law.
    pub density: DensityLaw,
    /// Moes' `M`, `L`: when given, they set the load and the (pure-rolling) velocity, with `R`,
    /// `E'`, `η0` and `α` kept; `conditions.load_n` and `rolling_velocity_m_s` are then ignored.
    #[serde(default)]
    pub moes: Option<ehl_core::Moes>,
    #[serde(default)]
    /// The multigrid solver's settings.
    pub solver: ReynoldsSettings,
}

impl Scene {
    /// The models this scene runs: the one of a one-model scene, or the comparison's list.
    pub fn models(&self) -> Vec<Model> {
        match self.model {
            Some(m) => vec![m],
            None => self.models.clone(),
        }
    }

    /// The models as a scene names them: `layer, reynolds, dry`.
    pub fn model_names(&self) -> String {
        self.models().iter().map(|m| m.name()).collect::<Vec<_>>().join(", ")
    }

    /// The one model of a one-model scene; `None` for a comparison (take [`Scene::for_model`]
    /// first).
    pub fn model(&self) -> Option<Model> {
        self.model
    }

    /// Whether the scene is a comparison (several models).
    pub fn is_comparison(&self) -> bool {
        self.model.is_none()
    }

    /// What `ehl compare` of this scene runs: `None` for a comparison scene (itself), or the
    /// comparison a one-model scene names (`comparison`), loaded and checked: it must be a
    /// comparison of the same contact (conditions). A one-model scene without one runs as a
    /// comparison of its one model (`None`).
    pub fn as_comparison(&self) -> Result<Option<Scene>, SceneError> {
        let Some(name) = self.comparison.as_deref().filter(|_| !self.is_comparison()) else {
            return Ok(None);
        };
        let c = load(name)?;
        let ck = Check { origin: &format!("`{}`", self.name) };
        if !c.is_comparison() {
            return Err(ck.err(
                "comparison",
                name.into(),
                "a comparison scene (one listing `models`)",
            ));
        }
        if c.conditions != self.conditions {
            return Err(ck.err(
                "comparison",
                name.into(),
                "a comparison of the same contact (its `conditions` equal this scene's)",
            ));
        }
        Ok(Some(c))
    }

    /// This scene as a comparison of `models` (each once), checked.
    pub fn comparing(&self, models: &[Model]) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        s.model = None;
        s.models = models.to_vec();
        s.comparison = None;
        s.validate(&format!("`{}` as a comparison", self.name))?;
        Ok(s)
    }

    /// This scene as `m` alone runs it: the same conditions, domain and grid, `m`'s blocks.
    /// What `ehl compare` runs per model, and what `ehl run` of that model would run.
    pub fn for_model(&self, m: Model) -> Scene {
        let mut s = self.clone();
        s.model = Some(m);
        s.models.clear();
        let keeps = |b: Block| m.blocks().contains(&b);
        if !keeps(Block::Lubricant) {
            s.lubricant = None;
        }
        if !keeps(Block::Supply) {
            s.supply = None;
        }
        if !keeps(Block::Layer) {
            s.layer = None;
        }
        if !keeps(Block::Run) {
            s.run = None;
        }
        if !keeps(Block::Reynolds) {
            s.reynolds = None;
        }
        s
    }

    /// Contact and sum velocity [m/s] a Reynolds scene runs with (Moes input resolved).
    pub fn reynolds_conditions(&self) -> (Contact, f64) {
        let mut c = self.conditions.contact();
        let mut u_sum = 2.0 * self.conditions.rolling_velocity_m_s.unwrap_or(0.0);
        if let (Some(r), Some(l)) = (&self.reynolds, &self.lubricant)
            && let Some(m) = &r.moes
        {
            let (load, u) = m.to_load_and_velocity(
                c.ball_radius,
                c.reduced_modulus,
                l.eta0_pa_s,
                l.alpha_per_pa,
            );
            c.load = load;
            u_sum = u;
        }
        (c, u_sum)
    }
}

impl Scene {
    /// The dents of the run in the ball, their depths in metres (an `amplitude` in units of the
    /// supply's thickness resolved with it).
    pub fn dents(&self) -> Result<Vec<Dent>, SceneError> {
        let Some(r) = &self.run else { return Ok(vec![]) };
        let l0 = self.supply.as_ref().map(|s| s.thickness_m);
        let mut out = vec![];
        for (k, f) in r.features.iter().enumerate() {
            match f {
                Feature::Dent(d) => out.push(d.resolved(l0).ok_or_else(|| SceneError::Range {
                    origin: self.name.clone(),
                    field: format!("run.features[{k}].dent.amplitude"),
                    value: format!("{:?}", d.amplitude),
                    allowed: "a depth in units of supply.thickness_m needs a supply: give `supply`, or `depth_m`".into(),
                })?),
                Feature::Hole(_) => {}
            }
        }
        Ok(out)
    }

    /// The holes in the supply.
    pub fn holes(&self) -> Vec<Hole> {
        self.supply.as_ref().map_or(vec![], |s| s.holes.clone())
    }

    /// What passes through the contact, in order: the run's dents, then the supply's holes.
    /// "The first feature" of the stop rules and `run.snapshots_a` is the first of these.
    pub fn passing(&self) -> Vec<Passing> {
        let dents = self.run.iter().flat_map(|r| &r.features).filter_map(|f| match f {
            Feature::Dent(d) => Some(Passing { x_start_a: d.x_start_a, reach_a: d.reach_a() }),
            Feature::Hole(_) => None,
        });
        dents.chain(self.holes().iter().map(Passing::from)).collect()
    }
}

/// A feature of the run. Only dents (in the ball's surface) belong here; a hole is in the oil
/// supply (`supply.holes`) and is refused here with that said.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Feature {
    /// A dent (or bump) in the ball.
    Dent(DentSpec),
    /// Refused: holes are in `supply.holes`.
    Hole(Hole),
}

/// A dent as a scene gives it: the depth in metres, or as the seed's factor `A` in units of the
/// supply's thickness (exactly one of the two).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DentSpec {
    /// Height factor `A` [-]: depth in units of `supply.thickness_m` …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// … or the depth at the centre [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_m: Option<f64>,
    /// Width factor `W` [a].
    pub width_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Centre across the rolling direction [a].
    #[serde(default)]
    pub y_a: f64,
}

impl DentSpec {
    /// The dent with its depth in metres, an amplitude resolved with the supply's thickness
    /// `l0_m` [m]; `None` when an amplitude has no supply to refer to.
    pub fn resolved(&self, l0_m: Option<f64>) -> Option<Dent> {
        let depth_m = match (self.depth_m, self.amplitude, l0_m) {
            (Some(d), _, _) => d,
            (None, Some(a), Some(l0)) => a * l0,
            _ => return None,
        };
        Some(Dent { depth_m, width_a: self.width_a, x_start_a: self.x_start_a, y_a: self.y_a })
    }
    /// Radius beyond which the dent is below 1e-6 of its depth [a].
    pub fn reach_a(&self) -> f64 {
        Dent { depth_m: 0.0, width_a: self.width_a, x_start_a: 0.0, y_a: 0.0 }.reach_a()
    }
}

/// The fastest rolling speed a scene may ask for [m/s]. The models are isothermal, which a
/// point contact stops being long before this (shear heating); and a march steps a cell's
/// travel at a time, so a speed far above the reference speed costs as many more steps (a
/// table knot at 4097 m/s in `stop-start-compare`, 0.01 m/s reference, ran for 365 s on 17²).
pub const MAX_SPEED_M_S: f64 = 100.0;

pub use ehl_core::check::num;

/// The plausible range of each physical input, SI: `(field, least, most, unit, why)`. Beyond
/// them no ball-on-disc contact the models describe exists (a ball of a kilometre, a modulus of
/// a gas), and the arithmetic would overflow or lose every digit before a model could say so.
pub const PLAUSIBLE: &[(&str, f64, f64, &str, &str)] = &[
    ("conditions.ball_radius_m", 1e-6, 10.0, "m", "from a micro-sphere to a large bearing ball"),
    ("conditions.load_n", 1e-6, 1e7, "N", "from a micro-newton probe to a heavy bearing"),
    ("conditions.reduced_modulus_pa", 1e5, 1e13, "Pa", "from a soft elastomer to diamond"),
    ("lubricant.eta0_pa_s", 1e-6, 1e6, "Pa s", "from a gas to a bitumen"),
    ("lubricant.alpha_per_pa", 0.0, 1e-6, "1/Pa", "oils are 1e-8 to 4e-8"),
    ("lubricant.p0_roelands_pa", 1e6, 1e10, "Pa", "Roelands' constant is 1.96e8"),
    ("supply.thickness_m", 1e-12, 1e-3, "m", "from a molecular layer to a millimetre of oil"),
];

/// The largest distance of any place in a scene from the contact's centre, in units of `a`:
/// a feature or a hole further out never reaches a domain the checks allow.
pub const MAX_PLACE_A: f64 = 1e4;

/// The most snapshots a run may take (times and positions together): each holds two whole
/// fields in memory until the run is written (1000 on 1025² is 16 GB).
pub const MAX_SNAPSHOTS: usize = 1000;

/// The farthest a domain may reach from the contact's centre, in units of `a` (an inlet 50 `a`
/// long is already far beyond any starvation study's).
pub const MAX_DOMAIN_A: f64 = 1000.0;

/// The largest `a / R` a scene may reach: Hertz's half-space and the small-slope gap hold for
/// a contact small against the ball (`a/R` ≤ 0.2 keeps the parabolic gap within 1 % of the
/// sphere's at the contact's edge).
pub const MAX_A_OVER_R: f64 = 0.2;

/// The longest time a scene may ask for [s]: a stop, a ramp, a table's knot, a snapshot, a time
/// limit. Steps are held to a budget too; this keeps the plan's arithmetic finite.
pub const MAX_TIME_S: f64 = 1e4;

/// The range checks' vocabulary: each refusal names the scene, the field, the value and what is
/// allowed.
struct Check<'a> {
    origin: &'a str,
}

impl Check<'_> {
    fn err(&self, field: &str, value: String, allowed: &str) -> SceneError {
        SceneError::Range {
            origin: self.origin.into(),
            field: field.into(),
            value,
            allowed: allowed.into(),
        }
    }
    fn positive(&self, field: &str, v: f64, unit: &str) -> Result<(), SceneError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.err(field, num(v), &format!("must be finite and > 0 ({unit})")))
        }
    }
    /// A name used for folders: letters, digits, `-`, `_`.
    fn name(&self, name: &str) -> Result<(), SceneError> {
        if name.trim().is_empty()
            || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(self.err(
                "name",
                format!("{name:?}"),
                "must be non-empty ASCII letters, digits, '-' or '_'",
            ));
        }
        Ok(())
    }
    /// The first of `(refused, field, value, allowed)` that is refused, its `allowed` worded by
    /// `say`.
    fn first_refusal(
        &self,
        checks: &[(bool, &str, String, &str)],
        say: impl Fn(&str) -> String,
    ) -> Result<(), SceneError> {
        match checks.iter().find(|c| c.0) {
            Some((_, field, value, allowed)) => Err(self.err(field, value.clone(), &say(allowed))),
            None => Ok(()),
        }
    }
    /// A rolling speed [m/s]: from 0 to [`MAX_SPEED_M_S`].
    fn speed(&self, field: &str, u: f64) -> Result<(), SceneError> {
        if u.is_finite() && (0.0..=MAX_SPEED_M_S).contains(&u) {
            Ok(())
        } else {
            Err(self.err(field, num(u), &format!("must be in [0, {MAX_SPEED_M_S}] (m/s)")))
        }
    }
    /// A time [s]: from 0 to [`MAX_TIME_S`].
    fn time(&self, field: &str, t: f64) -> Result<(), SceneError> {
        self.own("", ehl_core::check::within(field, t, 0.0, MAX_TIME_S, "s"))
    }
    /// A solver's own check ([`ehl_core::FieldError`]), its field put under `prefix`.
    fn own(&self, prefix: &str, r: Result<(), ehl_core::FieldError>) -> Result<(), SceneError> {
        r.map_err(|e| {
            let e = e.under(prefix);
            self.err(&e.field, e.value, &e.allowed)
        })
    }
    /// A physical input within its plausible range ([`PLAUSIBLE`]).
    fn plausible(&self, field: &str, v: f64) -> Result<(), SceneError> {
        let Some(&(_, lo, hi, unit, why)) = PLAUSIBLE.iter().find(|p| p.0 == field) else {
            return Ok(());
        };
        if v.is_finite() && v >= lo && v <= hi {
            return Ok(());
        }
        Err(self.err(
            field,
            num(v),
            &format!("must be in [{}, {}] ({unit}): {why}", num(lo), num(hi)),
        ))
    }
    fn nonneg(&self, field: &str, v: f64, unit: &str) -> Result<(), SceneError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(self.err(field, num(v), &format!("must be finite and >= 0 ({unit})")))
        }
    }
}

/// Conditions in SI; each field's unit is in its name.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conditions {
    /// Ball radius `R` [m].
    pub ball_radius_m: f64,
    /// Normal load `F` [N].
    pub load_n: f64,
    /// Reduced modulus `E'` [Pa].
    pub reduced_modulus_pa: f64,
    /// Rolling velocity `u1` [m/s] of both surfaces (pure rolling); 0 or absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_velocity_m_s: Option<f64>,
}

/// Lubricant in SI.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricantSpec {
    /// Viscosity at ambient pressure `η0` [Pa s].
    pub eta0_pa_s: f64,
    /// Pressure–viscosity coefficient `α` [1/Pa].
    pub alpha_per_pa: f64,
    /// Roelands pressure constant `p0` [Pa].
    pub p0_roelands_pa: f64,
}

impl LubricantSpec {
    /// The lubricant in the core's terms.
    pub fn lubricant(&self) -> Lubricant {
        Lubricant {
            eta0: self.eta0_pa_s,
            alpha: self.alpha_per_pa,
            p0_roelands: self.p0_roelands_pa,
        }
    }
}

/// How time advances.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSettings {
    /// The layer model's scheme (the Reynolds solver steps by second-order backward differences).
    #[serde(default)]
    pub scheme: Scheme,
    /// Rolling: time steps per spatial interval `n_t`, `Δt = ΔX a / (n_t u1)` (every model).
    #[serde(default = "default_nt")]
    pub steps_per_cell: f64,
    /// Squeeze (layer model): a fixed step [s]; when absent, error control sets it.
    #[serde(default)]
    pub dt_s: Option<f64>,
    /// Error control: RMS local strain error per step to aim for.
    #[serde(default = "default_err")]
    pub error_tolerance: f64,
    /// Extra Picard passes of the implicit scheme (0: coefficients extrapolated, still 2nd order).
    #[serde(default)]
    pub picard: usize,
}

fn default_nt() -> f64 {
    10.0
}
fn default_err() -> f64 {
    1e-4
}

impl Default for TimeSettings {
    fn default() -> Self {
        Self {
            scheme: Scheme::Implicit,
            steps_per_cell: default_nt(),
            dt_s: None,
            error_tolerance: default_err(),
            picard: 0,
        }
    }
}

/// When a march stops (every model reads it: the workbench's one driver applies it).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSettings {
    /// Steady when central and minimum layer thickness (per `l0`), maximum pressure (per `p_h`)
    /// and contact diameter (per `2a`) all change less than this over the window.
    #[serde(default = "default_steady_tol")]
    pub steady_tolerance: f64,
    /// Window: travel [a] when rolling.
    #[serde(default = "default_window_a")]
    pub window_travel_a: f64,
    /// Window: time [s] in squeeze.
    #[serde(default = "default_window_s")]
    pub window_time_s: f64,
    /// Stop once every feature has left the domain (its centre a reach beyond `x` max), rather
    /// than at steady state …
    #[serde(default)]
    pub until_features_passed: bool,
    /// … or once the first feature's centre reaches this `x` [a].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_feature_at_a: Option<f64>,
    /// Time limit [s]: a run that is not steady by then stops and says so. Required unless a
    /// feature ends the run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_time_s: Option<f64>,
}

impl Default for StopSettings {
    fn default() -> Self {
        Self {
            steady_tolerance: default_steady_tol(),
            window_travel_a: default_window_a(),
            window_time_s: default_window_s(),
            until_features_passed: false,
            until_feature_at_a: None,
            max_time_s: Some(10.0),
        }
    }
}

fn default_steady_tol() -> f64 {
    1e-3
}
fn default_window_a() -> f64 {
    0.5
}
fn default_window_s() -> f64 {
    0.5
}

/// Initial state of a layer run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartState {
    /// Unstrained layer of the supply thickness (`ε = 0`).
    Uniform,
    /// The fully squeezed state `ε = min(p/Eo, 1)`.
    Squeezed,
    /// Steady rolling at the scene's velocity, solved directly.
    SteadyRolling,
}

/// How a layer run is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Steady rolling solved directly (`∂ε/∂t = 0`): no history, no snapshots in time.
    Steady,
    /// Time stepping from a start state: histories, snapshots, features passing, squeeze.
    March,
}

/// What the surfaces do, stated once for every model: pure rolling (both surfaces at one
/// speed), at `conditions.rolling_velocity_m_s` unless a table gives the speeds. The core's
/// [`Kinematics`] is what the models read ([`RunSpec::kinematics`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Motion {
    /// Pure rolling at `conditions.rolling_velocity_m_s`.
    Rolling,
    /// Squeeze: the rolling stops (suddenly) at the start, the load stays (a stop at 0 s).
    Squeeze,
    /// No time stepping: the start state is the result (e.g. the steady squeeze).
    None,
    /// Rolling at the scene's speed, then a sudden stop at `at_s` [s] (`{"stop": {"at_s": 0.05}}`).
    #[serde(rename = "stop")]
    StopAt {
        /// When the surfaces stop [s].
        at_s: f64,
    },
    /// From rest to the scene's speed in a linear ramp over `ramp_s` [s] (0: at once).
    StartUp {
        /// How long the ramp takes [s].
        ramp_s: f64,
    },
    /// The speed as a piecewise-linear table of `[t [s], u [m/s]]` knots (two at one time: a
    /// jump); after the last knot its speed holds.
    Table {
        /// The knots `[t, u]`, times non-decreasing from 0.
        knots: Vec<[f64; 2]>,
    },
}

impl Motion {
    /// Whether anything marches in time (all but `none`).
    pub fn marches(&self) -> bool {
        *self != Motion::None
    }
    /// The name used in reports (`rolling`, `squeeze`, `stop`, `start-up`, `table`, `none`).
    pub fn label(&self) -> &'static str {
        match self {
            Motion::Rolling => "rolling",
            Motion::Squeeze => "squeeze",
            Motion::None => "none",
            Motion::StopAt { .. } => "stop",
            Motion::StartUp { .. } => "start-up",
            Motion::Table { .. } => "table",
        }
    }
}

/// A layer run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// `steady` or `march`; absent: `steady` when the scene asks only for the steady rolling
    /// state (rolling, no start, no features, no snapshots in time), else `march`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<Method>,
    /// Where the march starts (required by `march`; `steady` has no start).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<StartState>,
    /// How the surfaces move (docs/scenes.md, Motion).
    pub motion: Motion,
    #[serde(default)]
    /// Dents in the ball passing.
    pub features: Vec<Feature>,
    #[serde(default)]
    /// Steps: scheme, steps per cell, fixed step or error control.
    pub time: TimeSettings,
    #[serde(default)]
    /// When the march stops.
    pub stop: StopSettings,
    /// Times [s, from the start of the motion] at which fields are written …
    #[serde(default)]
    pub snapshots_s: Vec<f64>,
    /// … and positions [a] of the first feature's centre at which fields are written (a
    /// feature travels with the surfaces: the time is when the motion has carried it there).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub snapshots_a: Vec<f64>,
    /// The direct steady solve (method `steady`, and a `steady-rolling` start).
    #[serde(default)]
    pub steady: SteadySettings,
}

impl RunSpec {
    /// The motion as the models read it, built on the reference speed `u_ref` [m/s] (the
    /// scene's rolling speed; for a table without one, its largest speed).
    pub fn kinematics(&self, u_ref: f64) -> Result<Kinematics, KinematicsError> {
        match &self.motion {
            Motion::Rolling => Kinematics::constant(u_ref),
            Motion::None => Kinematics::constant(0.0),
            Motion::Squeeze => Kinematics::stop_at(u_ref, 0.0),
            Motion::StopAt { at_s } => Kinematics::stop_at(u_ref, *at_s),
            Motion::StartUp { ramp_s } => Kinematics::start_up(u_ref, *ramp_s),
            Motion::Table { knots } => {
                let k: Vec<(f64, f64)> = knots.iter().map(|k| (k[0], k[1])).collect();
                let reference =
                    if u_ref > 0.0 { u_ref } else { k.iter().map(|k| k.1).fold(0.0, f64::max) };
                Kinematics::table(&k, reference)
            }
        }
    }

    /// The method this run uses, the default resolved.
    pub fn method(&self) -> Method {
        self.method.unwrap_or(
            if self.motion == Motion::Rolling
                && self.start.is_none()
                && self.features.is_empty()
                && self.snapshots_s.is_empty()
                && self.snapshots_a.is_empty()
            {
                Method::Steady
            } else {
                Method::March
            },
        )
    }
    /// Every snapshot time [s]: `snapshots_s` and the times `snapshots_a` give for the `first`
    /// feature carried by `motion` on the Hertz radius `a` [m], in order; a
    /// position the motion never carries the feature to has no time (the scene's checks refuse
    /// it).
    pub fn snapshot_times(&self, a: f64, motion: &Kinematics, first: Option<&Passing>) -> Vec<f64> {
        let x0 = first.map_or(0.0, |f| f.x_start_a);
        let mut t: Vec<f64> = self.snapshots_s.clone();
        t.extend(self.snapshots_a.iter().filter_map(|&x| motion.time_at_travel((x - x0) * a)));
        t.sort_by(f64::total_cmp);
        t
    }
    /// The start state of a march (validated present).
    pub fn start(&self) -> StartState {
        self.start.unwrap_or(StartState::Uniform)
    }
}
impl Conditions {
    /// The contact in the core's terms.
    pub fn contact(&self) -> Contact {
        Contact {
            ball_radius: self.ball_radius_m,
            load: self.load_n,
            reduced_modulus: self.reduced_modulus_pa,
        }
    }
}

/// The computational rectangle in units of the Hertz radius `a`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// `[x_min, x_max]` [a], `x` the rolling direction.
    pub x_a: [f64; 2],
    /// `[y_min, y_max]` [a].
    pub y_a: [f64; 2],
}

/// Points per side.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Points along `x`.
    pub nx: usize,
    /// Points along `y`.
    pub ny: usize,
}

/// Which files a run writes (`summary.json` always).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Outputs {
    /// `centreline.csv`: the fields along `y = 0`.
    pub centreline: bool,
    /// Full fields as `.npy`.
    pub fields: bool,
    /// PNG figures.
    pub figures: bool,
}

impl Default for Outputs {
    fn default() -> Self {
        Self { centreline: true, fields: true, figures: true }
    }
}

/// Refused input: which field, what it holds, what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    #[error("scene {origin}: {}{message}", if path.is_empty() { String::new() } else { format!("field `{path}`: ") })]
    /// The JSON does not parse, or a field is missing or unknown.
    Parse {
        /// Which scene.
        origin: String,
        /// The field's path (`conditions.load_n`); empty at the top level, where the message
        /// names the field when there is one.
        path: String,
        /// The parser's words.
        message: String,
    },
    #[error("scene {origin}: field `{field}` = {value} is out of range: {allowed}")]
    /// A value out of its range.
    Range {
        /// Which scene.
        origin: String,
        /// The field's path.
        field: String,
        /// What it holds.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    #[error("no built-in scene or file named `{0}` (built-ins: {list})", list = builtin_names().join(", "))]
    /// No built-in scene or file of that name.
    Unknown(String),
    #[error(
        "`{name}` is both a built-in {kind} and a file here: write `./{name}` for the file, or rename it"
    )]
    /// A name that is a built-in and a file in the working folder.
    Ambiguous {
        /// The name given.
        name: String,
        /// `scene` or `sweep`.
        kind: &'static str,
    },
    #[error("scene file {path}: {message}")]
    /// The scene file cannot be read.
    Io {
        /// The file.
        path: String,
        /// The system's words.
        message: String,
    },
}

macro_rules! builtin_scenes {
    ($($name:literal),*) => {
        &[$(($name, include_str!(concat!("../../../validation/scenes/", $name, ".json")))),*]
    };
}

const BUILTINS: &[(&str, &str)] = builtin_scenes!(
    "seed",
    "hertz",
    "squeeze-steady",
    "rolling-from-squeezed",
    "rolling-from-uniform",
    "rolling-steady",
    "squeeze-after-stop",
    "dent-deep",
    "dent-shallow",
    "dent-shallow-compare",
    "hole",
    "hole-compare",
    "hole-starved-compare",
    "stop-compare",
    "stop-start-compare",
    "rolling-from-squeezed-compare",
    "startup-ramp-compare",
    "reynolds-m20-l10",
    "reynolds-m20-l10-dent",
    "reynolds-seed"
);

/// Names of the built-in scenes.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTINS.iter().map(|(n, _)| *n).collect()
}

/// All built-in scenes, parsed and checked.
pub fn builtins() -> Vec<Scene> {
    BUILTINS.iter().map(|(n, _)| builtin(n).expect("built-in scenes are valid")).collect()
}

/// A built-in scene by name.
pub fn builtin(name: &str) -> Result<Scene, SceneError> {
    let (_, text) = BUILTINS
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| SceneError::Unknown(name.into()))?;
    Scene::from_json(text, &format!("`{name}` (built-in)"))
}

/// A built-in name, or else a path to a JSON file. A name that is both (a file `hertz` in the
/// working folder) is refused as ambiguous rather than guessed. A file's relative
/// `comparison` path is read from the file's own folder.
///
/// ```
/// let s = ehl_scene::load("hertz").unwrap();
/// assert_eq!(s.grid.nx, 129);
/// // A field out of its range is refused, naming it and what it allows.
/// let e = s.with_points(3).unwrap_err().to_string();
/// assert!(e.contains("grid.nx") && e.contains("5 ..= 4097"));
/// ```
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    let path = Path::new(name_or_path);
    let named = BUILTINS.iter().any(|(n, _)| *n == name_or_path);
    // A folder named like a built-in (an output folder `seed`) is no scene file: no clash.
    match (named, path.is_file()) {
        (true, false) => return builtin(name_or_path),
        (true, true) => {
            return Err(SceneError::Ambiguous { name: name_or_path.into(), kind: "scene" });
        }
        (false, false) => return Err(SceneError::Unknown(name_or_path.into())),
        (false, true) => {}
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::Io { path: name_or_path.into(), message: e.to_string() })?;
    let mut scene = Scene::from_json(&text, &format!("file {name_or_path}"))?;
    if let Some(c) = &scene.comparison
        && !BUILTINS.iter().any(|(n, _)| n == c)
        && Path::new(c).is_relative()
        && let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
    {
        scene.comparison = Some(dir.join(c).to_string_lossy().into_owned());
    }
    Ok(scene)
}

/// Deserialises scene-crate JSON (scenes, sweeps), a refusal naming the field's path. The text
/// must be one JSON object and nothing after it: a second scene pasted below the first, or a
/// merge's leftover, is refused rather than ignored.
fn parse<T: serde::de::DeserializeOwned>(text: &str, origin: &str) -> Result<T, SceneError> {
    let refuse =
        |message: String| SceneError::Parse { origin: origin.into(), path: String::new(), message };
    match text.trim_start().chars().next() {
        Some('{') => {}
        Some(c) => {
            return Err(refuse(format!(
                "expected a JSON object `{{ … }}`, found text starting with `{c}`"
            )));
        }
        None => return Err(refuse("the text is empty: expected a JSON object".into())),
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let path = e.path().to_string();
        SceneError::Parse {
            origin: origin.into(),
            path: if path == "." { String::new() } else { path },
            message: e.into_inner().to_string(),
        }
    })?;
    de.end().map_err(|e| {
        refuse(format!(
            "more text after the JSON object ends (line {}, column {}): one object per file",
            e.line(),
            e.column()
        ))
    })?;
    Ok(value)
}

impl Scene {
    /// Parses and checks; `origin` names the source in error messages.
    pub fn from_json(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let scene: Scene = parse(text, origin)?;
        scene.validate(origin)?;
        Ok(scene)
    }

    /// The scene as JSON, every default filled in.
    pub fn to_json(&self) -> String {
        let mut filled = self.clone();
        if let Some(r) = filled.run.as_mut() {
            r.method = Some(r.method());
        }
        serde_json::to_string_pretty(&filled).unwrap_or_default()
    }

    /// The same scene asking for the relative `accuracy` (the `--accuracy` override), checked.
    pub fn with_accuracy(&self, accuracy: f64) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        s.accuracy = Some(accuracy);
        s.validate(&format!("`{}` with the accuracy {accuracy}", self.name))?;
        Ok(s)
    }

    /// The same scene with `n` points per side (the `--grid` override).
    pub fn with_points(&self, n: usize) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        s.grid = GridSpec { nx: n, ny: n };
        s.validate(&format!("`{}` with the grid {n}²", self.name))?;
        Ok(s)
    }

    /// The scene's grid [a].
    pub fn grid(&self) -> Grid {
        Grid::new(
            self.grid.nx,
            self.grid.ny,
            (self.domain.x_a[0], self.domain.x_a[1]),
            (self.domain.y_a[0], self.domain.y_a[1]),
        )
    }

    /// Range checks, each naming the field and what it allows.
    pub fn validate(&self, origin: &str) -> Result<(), SceneError> {
        let ck = Check { origin };
        ck.name(&self.name)?;
        match (self.model, self.models.is_empty()) {
            (Some(_), false) => {
                return Err(ck.err(
                    "models",
                    format!("{:?}", self.models),
                    "give either `model` (one model) or `models` (a comparison), not both",
                ));
            }
            (None, true) => {
                return Err(ck.err(
                    "model",
                    "(missing)".into(),
                    "one of \"dry\", \"layer\", \"reynolds\"; or `models`, a list of them",
                ));
            }
            (None, false) => {
                if let Some(c) = &self.comparison {
                    return Err(ck.err(
                        "comparison",
                        c.clone(),
                        "only on a one-model scene (a comparison is its own)",
                    ));
                }
                for (k, m) in self.models.iter().enumerate() {
                    if self.models[..k].contains(m) {
                        return Err(ck.err(
                            &format!("models[{k}]"),
                            format!("{m:?}"),
                            "each model once",
                        ));
                    }
                }
                if self.reynolds.as_ref().is_some_and(|r| r.moes.is_some()) {
                    return Err(ck.err(
                        "reynolds.moes",
                        "(given)".into(),
                        "not in a comparison: every model must run the same load and velocity (give conditions.load_n and rolling_velocity_m_s)",
                    ));
                }
                // Each model checks the scene as it would run it alone: the field names are the
                // scene's own.
                for &m in &self.models {
                    self.for_model(m).validate(origin)?;
                }
                return Ok(());
            }
            (Some(_), true) => {}
        }
        let c = &self.conditions;
        ck.positive("conditions.ball_radius_m", c.ball_radius_m, "m")?;
        ck.positive("conditions.load_n", c.load_n, "N")?;
        ck.positive("conditions.reduced_modulus_pa", c.reduced_modulus_pa, "Pa")?;
        ck.plausible("conditions.ball_radius_m", c.ball_radius_m)?;
        ck.plausible("conditions.load_n", c.load_n)?;
        ck.plausible("conditions.reduced_modulus_pa", c.reduced_modulus_pa)?;
        self.validate_contact_size(&ck, &self.conditions.contact(), "conditions.load_n")?;
        if let Some(a) = self.accuracy {
            ck.own(
                "",
                ehl_core::check::within(
                    "accuracy",
                    a,
                    1e-3,
                    0.5,
                    "relative error of the answer, 0.02: 2 %",
                ),
            )?;
        }
        self.validate_domain(&ck)?;
        ck.own("solver", self.solver.check())?;
        if let Some(u) = c.rolling_velocity_m_s {
            ck.speed("conditions.rolling_velocity_m_s", u)?;
        }
        if let Some(l) = &self.lubricant {
            ck.positive("lubricant.eta0_pa_s", l.eta0_pa_s, "Pa s")?;
            ck.nonneg("lubricant.alpha_per_pa", l.alpha_per_pa, "1/Pa")?;
            ck.positive("lubricant.p0_roelands_pa", l.p0_roelands_pa, "Pa")?;
            ck.plausible("lubricant.eta0_pa_s", l.eta0_pa_s)?;
            ck.plausible("lubricant.alpha_per_pa", l.alpha_per_pa)?;
            ck.plausible("lubricant.p0_roelands_pa", l.p0_roelands_pa)?;
        }
        if let Some(sup) = &self.supply {
            ck.positive("supply.thickness_m", sup.thickness_m, "m")?;
            ck.plausible("supply.thickness_m", sup.thickness_m)?;
            for (k, h) in sup.holes.iter().enumerate() {
                let f = |n: &str| format!("supply.holes[{k}].{n}");
                ck.own(
                    "",
                    ehl_core::check::above(&f("radius_a"), h.radius_a, 0.0, 100.0, "units of a"),
                )?;
                for (n, v) in [("x_start_a", h.x_start_a), ("y_a", h.y_a)] {
                    ck.own(
                        "",
                        ehl_core::check::within(&f(n), v, -MAX_PLACE_A, MAX_PLACE_A, "units of a"),
                    )?;
                }
            }
        }
        if let Some(l) = &self.layer {
            ck.own("layer", l.check())?;
        }
        match self.model {
            Some(Model::Reynolds | Model::ReynoldsFlooded) => self.validate_reynolds(&ck),
            Some(Model::Layer) => self.validate_layer(&ck),
            _ => Ok(()),
        }
    }

    /// The contact small against the ball ([`MAX_A_OVER_R`]), `field` named as the cause.
    fn validate_contact_size(
        &self,
        ck: &Check,
        c: &Contact,
        field: &str,
    ) -> Result<(), SceneError> {
        let a = ehl_core::HertzScales::new(c).a;
        let ratio = a / c.ball_radius;
        if ratio.is_finite() && ratio <= MAX_A_OVER_R {
            return Ok(());
        }
        Err(ck.err(
            field,
            num(if field == "conditions.load_n" { c.load } else { ratio }),
            &format!(
                "gives a Hertz radius a = {} m, {} of the ball's radius: the half-space contact needs a/R <= {MAX_A_OVER_R} (a lighter load, a stiffer pair or a larger ball)",
                num(a),
                num(ratio)
            ),
        ))
    }

    /// The domain holds the Hertz contact (±1 `a` either way) and lies within [`MAX_DOMAIN_A`];
    /// the grid has 5 to 4097 points a side and at least two cells across the contact.
    fn validate_domain(&self, ck: &Check) -> Result<(), SceneError> {
        for (field, r) in [("domain.x_a", self.domain.x_a), ("domain.y_a", self.domain.y_a)] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]) {
                return Err(ck.err(
                    field,
                    format!("[{}, {}]", num(r[0]), num(r[1])),
                    "must be [min, max] with finite min < max (units of a)",
                ));
            }
            if !(r[0] <= -1.0 && r[1] >= 1.0 && r[0] >= -MAX_DOMAIN_A && r[1] <= MAX_DOMAIN_A) {
                return Err(ck.err(
                    field,
                    format!("[{}, {}]", num(r[0]), num(r[1])),
                    &format!("must hold the Hertz contact and stay within ±{MAX_DOMAIN_A}: min in [-{MAX_DOMAIN_A}, -1], max in [1, {MAX_DOMAIN_A}] (units of a)"),
                ));
            }
        }
        // 5 points is the least that resolves anything; 4097² fields are 128 MiB each.
        for (field, n, r) in
            [("grid.nx", self.grid.nx, self.domain.x_a), ("grid.ny", self.grid.ny, self.domain.y_a)]
        {
            if !(5..=4097).contains(&n) {
                return Err(ck.err(field, n.to_string(), "must be 5 ..= 4097 points"));
            }
            let cell = (r[1] - r[0]) / (n - 1) as f64;
            if cell > 1.0 {
                return Err(ck.err(
                    field,
                    n.to_string(),
                    &format!(
                        "gives cells of {} a: at least two cells across the Hertz contact's diameter need cells <= 1 a (more points, or a shorter domain)",
                        num(cell)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The Reynolds model's block and grid.
    fn validate_reynolds(&self, ck: &Check) -> Result<(), SceneError> {
        let c = &self.conditions;
        let missing = |f: &str| ck.err(f, "(missing)".into(), "required by the Reynolds model");
        let l = self.lubricant.ok_or_else(|| missing("lubricant"))?;
        let r = self.reynolds.as_ref().ok_or_else(|| missing("reynolds"))?;
        match r.moes {
            Some(m) => {
                if let Some(u) = c.rolling_velocity_m_s {
                    return Err(ck.err(
                        "conditions.rolling_velocity_m_s",
                        num(u),
                        "must be absent with reynolds.moes (M and L set the load and the velocity; conditions.load_n is replaced too, and the run says so)",
                    ));
                }
                ck.own(
                    "reynolds.moes",
                    ehl_core::check::above("m", m.m, 0.0, 1e5, "Moes' load parameter"),
                )?;
                ck.own(
                    "reynolds.moes",
                    ehl_core::check::above("l", m.l, 0.0, 1e3, "Moes' material parameter"),
                )?;
                ck.positive(
                    "lubricant.alpha_per_pa",
                    l.alpha_per_pa,
                    "1/Pa (Moes input derives U from L)",
                )?;
                let (contact, u_sum) = self.reynolds_conditions();
                self.validate_contact_size(ck, &contact, "reynolds.moes.m")?;
                ck.speed("reynolds.moes.l", 0.5 * u_sum)?;
            }
            None => {
                let u = c.rolling_velocity_m_s.unwrap_or(0.0);
                ck.positive(
                    "conditions.rolling_velocity_m_s",
                    u,
                    "m/s (a Reynolds film needs motion)",
                )?;
            }
        }
        if let Some(run) = &self.run {
            self.validate_reynolds_run(ck, run)?;
        }
        ck.own("reynolds.solver", r.solver.check())?;
        if self.grid.nx != self.grid.ny
            || ((self.domain.x_a[1] - self.domain.x_a[0]) / (self.grid.nx - 1) as f64
                - (self.domain.y_a[1] - self.domain.y_a[0]) / (self.grid.ny - 1) as f64)
                .abs()
                > 1e-12
        {
            return Err(ck.err(
                "grid",
                format!("{}x{}", self.grid.nx, self.grid.ny),
                "the Reynolds solver needs square cells (equal spacing in x and y)",
            ));
        }

        Ok(())
    }

    /// The scenario as the Reynolds model runs it: the steady solve, then (method `march`) time
    /// steps from it while dents in the ball pass at the mean velocity.
    fn validate_reynolds_run(&self, ck: &Check, r: &RunSpec) -> Result<(), SceneError> {
        if r.method() == Method::March {
            ck.first_refusal(
                &[
                    (!matches!(r.start, Some(StartState::SteadyRolling | StartState::Squeezed)), "run.start", format!("{:?}", r.start), "steady-rolling or squeezed"),
                ],
                |allowed| format!("must be {allowed} for the Reynolds model (its march starts from its steady solve at the speed the motion starts with; squeezed: then stopped and left at rest until the squeeze is steady)"),
            )?;
        }
        let marching = self.run.as_ref().is_some_and(|r| r.method == Some(Method::March));
        if let Some(k) = self.supply.as_ref().and_then(|s| (!s.holes.is_empty()).then_some(0))
            && !marching
        {
            return Err(ck.err(
                &format!("supply.holes[{k}]"),
                "(given)".into(),
                "only in a march for the Reynolds model (run.method \"march\"): a hole passes the contact; a steady solve has none",
            ));
        }
        let (_, u_sum) = self.reynolds_conditions();
        self.validate_run(ck, r, 0.5 * u_sum)
    }

    /// The layer model's blocks: the layer and the run.
    fn validate_layer(&self, ck: &Check) -> Result<(), SceneError> {
        let missing = |f: &str| ck.err(f, "(missing)".into(), "required by the layer model");
        if self.lubricant.is_none() {
            return Err(missing("lubricant"));
        }
        if self.supply.is_none() {
            return Err(ck.err(
                "supply",
                "(missing)".into(),
                "required by the layer model: its layer is the supplied oil (supply.thickness_m, m)",
            ));
        }
        if self.layer.is_none() {
            return Err(missing("layer"));
        }
        let r = self.run.as_ref().ok_or_else(|| missing("run"))?;
        self.validate_run(ck, r, self.conditions.rolling_velocity_m_s.unwrap_or(0.0))
    }

    /// The scenario every marching model reads (method, start, motion, features, steps, stop
    /// rule, snapshots), the motion built on the rolling velocity `u` [m/s].
    fn validate_run(&self, ck: &Check, r: &RunSpec, u: f64) -> Result<(), SceneError> {
        Self::validate_motion(ck, r, u)?;
        let kin = r
            .kinematics(u)
            .map_err(|e| ck.err("run.motion", format!("{:?}", r.motion), &e.what))?;
        let a = ehl_core::HertzScales::new(&self.conditions.contact()).a;
        let passing = self.passing();
        self.validate_features(ck, r)?;
        Self::validate_method(ck, r, &kin, !passing.is_empty())?;
        Self::validate_steps(ck, r)?;
        Self::validate_stop(ck, r, &kin, a, passing.first())?;
        Self::validate_snapshots(ck, r, &kin, a, passing.first())
    }

    /// A stop's time, a ramp's length, a table's knots; the scene's speed where the motion
    /// rolls at it.
    fn validate_motion(ck: &Check, r: &RunSpec, u: f64) -> Result<(), SceneError> {
        match &r.motion {
            Motion::StopAt { at_s } => ck.time("run.motion.stop.at_s", *at_s)?,
            Motion::StartUp { ramp_s } => ck.time("run.motion.start-up.ramp_s", *ramp_s)?,
            Motion::Table { knots } if knots.is_empty() => {
                return Err(ck.err(
                    "run.motion.table.knots",
                    "[]".into(),
                    "at least one [t (s), u (m/s)] knot",
                ));
            }
            Motion::Table { knots } => {
                for (k, knot) in knots.iter().enumerate() {
                    ck.time(&format!("run.motion.table.knots[{k}][0]"), knot[0])?;
                    ck.speed(&format!("run.motion.table.knots[{k}][1]"), knot[1])?;
                }
            }
            _ => {}
        }
        let uses_scene_speed =
            matches!(r.motion, Motion::Rolling | Motion::StopAt { .. } | Motion::StartUp { .. });
        if uses_scene_speed && !(u > 0.0) {
            return Err(ck.err(
                "conditions.rolling_velocity_m_s",
                num(u),
                &format!("must be > 0 (m/s): run.motion `{}` rolls at it", r.motion.label()),
            ));
        }
        Ok(())
    }

    /// Method and start, the direct steady solve's settings, and the velocity rolling needs.
    fn validate_method(
        ck: &Check,
        r: &RunSpec,
        kin: &Kinematics,
        anything_passes: bool,
    ) -> Result<(), SceneError> {
        match (r.method(), r.start) {
            (Method::March, None) => {
                return Err(ck.err(
                    "run.start",
                    "(missing)".into(),
                    "required by the march method (uniform, squeezed or steady-rolling); a rolling scene with no start, features or snapshots is solved steady",
                ));
            }
            (Method::Steady, Some(s)) => {
                return Err(ck.err(
                    "run.start",
                    format!("{s:?}"),
                    "the steady method solves the steady state directly and has no start: remove run.start, or set run.method to \"march\"",
                ));
            }
            _ => {}
        }
        if r.method() == Method::Steady {
            ck.first_refusal(
                &[
                    (
                        r.motion != Motion::Rolling,
                        "run.motion",
                        format!("{:?}", r.motion),
                        "must be rolling",
                    ),
                    (
                        anything_passes,
                        "run.features",
                        format!("{} dent(s) and the supply's holes", r.features.len()),
                        "a dent or a hole passing is not steady: none allowed",
                    ),
                    (
                        !r.snapshots_s.is_empty(),
                        "run.snapshots_s",
                        format!("{:?}", r.snapshots_s),
                        "snapshots in time need a history: none allowed",
                    ),
                ],
                |allowed| format!("{allowed} with run.method \"steady\" (use \"march\")"),
            )?;
        }
        ck.own("run.steady", r.steady.check())?;
        let u = kin.speed_before();
        if r.start == Some(StartState::SteadyRolling) && !(u > 0.0) {
            return Err(ck.err(
                "run.start",
                "steady-rolling".into(),
                &format!(
                    "a steady-rolling start needs the motion to roll before it starts; run.motion `{}` starts at rest (use a uniform or squeezed start)",
                    r.motion.label()
                ),
            ));
        }
        Ok(())
    }

    /// Steps: per cell (rolling), a fixed step or error control (squeeze).
    fn validate_steps(ck: &Check, r: &RunSpec) -> Result<(), SceneError> {
        let t = &r.time;
        if !(t.steps_per_cell.is_finite() && t.steps_per_cell >= 0.5 && t.steps_per_cell <= 1000.0)
        {
            return Err(ck.err(
                "run.time.steps_per_cell",
                format!("{}", t.steps_per_cell),
                "must be in [0.5, 1000] (time steps per grid interval)",
            ));
        }
        if let Some(dt) = t.dt_s {
            ck.positive("run.time.dt_s", dt, "s")?;
            ck.time("run.time.dt_s", dt)?;
        }
        if !(t.error_tolerance.is_finite() && t.error_tolerance > 0.0 && t.error_tolerance < 1.0) {
            return Err(ck.err(
                "run.time.error_tolerance",
                format!("{}", t.error_tolerance),
                "must be in (0, 1)",
            ));
        }
        if t.picard > 10 {
            return Err(ck.err("run.time.picard", t.picard.to_string(), "must be 0 ..= 10"));
        }
        Ok(())
    }

    /// Stop rules: steady tolerance and windows, a feature's end, the time limit.
    fn validate_stop(
        ck: &Check,
        r: &RunSpec,
        kin: &Kinematics,
        a: f64,
        first: Option<&Passing>,
    ) -> Result<(), SceneError> {
        let st = &r.stop;
        if !(st.steady_tolerance.is_finite()
            && st.steady_tolerance > 0.0
            && st.steady_tolerance < 1.0)
        {
            return Err(ck.err(
                "run.stop.steady_tolerance",
                format!("{}", st.steady_tolerance),
                "must be in (0, 1)",
            ));
        }
        ck.positive("run.stop.window_travel_a", st.window_travel_a, "units of a")?;
        ck.positive("run.stop.window_time_s", st.window_time_s, "s")?;
        ck.time("run.stop.window_time_s", st.window_time_s)?;
        ck.own(
            "",
            ehl_core::check::within(
                "run.stop.window_travel_a",
                st.window_travel_a,
                0.0,
                1e6,
                "units of a",
            ),
        )?;
        let feature_ends = st.until_features_passed || st.until_feature_at_a.is_some();
        match st.max_time_s {
            Some(t) => {
                ck.positive("run.stop.max_time_s", t, "s")?;
                ck.time("run.stop.max_time_s", t)?;
            }
            None if !feature_ends && r.method() == Method::March && r.motion.marches() => {
                return Err(ck.err(
                    "run.stop.max_time_s",
                    "(missing)".into(),
                    "required unless a feature ends the run (until_features_passed or until_feature_at_a) (s)",
                ));
            }
            None => {}
        }
        if feature_ends && first.is_none() {
            return Err(ck.err(
                if st.until_features_passed {
                    "run.stop.until_features_passed"
                } else {
                    "run.stop.until_feature_at_a"
                },
                "(given)".into(),
                "needs a feature passing: a dent in run.features or a hole in supply.holes",
            ));
        }
        if st.until_features_passed && !(kin.final_speed() > 0.0) {
            return Err(ck.err(
                "run.motion",
                r.motion.label().into(),
                "must keep rolling (a final speed > 0) for every feature to leave the domain",
            ));
        }
        if let Some(x) = st.until_feature_at_a {
            let x0 = first.map_or(f64::NAN, |f| f.x_start_a);
            if !(x.is_finite() && x > x0) {
                return Err(ck.err(
                    "run.stop.until_feature_at_a",
                    num(x),
                    &format!("finite and > the first feature's start {x0} (a)"),
                ));
            }
            if kin.time_at_travel((x - x0) * a).is_none() {
                return Err(ck.err(
                    "run.stop.until_feature_at_a",
                    num(x),
                    &format!(
                        "a position run.motion `{}` carries the first feature to: it stops after {:.4} a",
                        r.motion.label(),
                        x0 + kin.travel_limit().unwrap_or(f64::INFINITY) / a
                    ),
                ));
            }
            if let Some((k, &xs)) = r.snapshots_a.iter().enumerate().find(|(_, xs)| **xs > x) {
                return Err(ck.err(
                    &format!("run.snapshots_a[{k}]"),
                    num(xs),
                    &format!("<= run.stop.until_feature_at_a = {x} (a): the run ends there"),
                ));
            }
        }
        Ok(())
    }

    /// Features: dents (depth in one unit, an amplitude with a supply to refer to), each with a
    /// finite place; a hole is refused here (it is in the supply).
    fn validate_features(&self, ck: &Check, r: &RunSpec) -> Result<(), SceneError> {
        for (k, f) in r.features.iter().enumerate() {
            match f {
                Feature::Dent(d) => {
                    let f = |n: &str| format!("run.features[{k}].dent.{n}");
                    match (d.amplitude, d.depth_m) {
                        (Some(_), Some(_)) | (None, None) => {
                            return Err(ck.err(
                                &f("depth_m"),
                                format!("amplitude {:?}, depth_m {:?}", d.amplitude, d.depth_m),
                                "give exactly one of `depth_m` (m) and `amplitude` (units of the supply thickness l0)",
                            ));
                        }
                        (Some(a), None) if !a.is_finite() => {
                            return Err(ck.err(&f("amplitude"), num(a), "must be finite"));
                        }
                        (Some(_), None) if self.supply.is_none() => {
                            return Err(ck.err(
                                &f("amplitude"),
                                "(given)".into(),
                                "in units of supply.thickness_m: give `supply`, or the depth in metres (`depth_m`)",
                            ));
                        }
                        (None, Some(m)) if !m.is_finite() => {
                            return Err(ck.err(&f("depth_m"), num(m), "must be finite (m)"));
                        }
                        _ => {}
                    }
                    use ehl_core::check::{above, within};
                    if let Some(m) = d.depth_m {
                        ck.own("", within(&f("depth_m"), m, -1e-3, 1e-3, "m, negative a bump"))?;
                    }
                    if let Some(a) = d.amplitude {
                        ck.own(
                            "",
                            within(
                                &f("amplitude"),
                                a,
                                -1e6,
                                1e6,
                                "units of supply.thickness_m, negative a bump",
                            ),
                        )?;
                    }
                    ck.own("", above(&f("width_a"), d.width_a, 0.0, 100.0, "units of a"))?;
                    for (n, v) in [("x_start_a", d.x_start_a), ("y_a", d.y_a)] {
                        ck.own("", within(&f(n), v, -MAX_PLACE_A, MAX_PLACE_A, "units of a"))?;
                    }
                }
                Feature::Hole(_) => {
                    return Err(ck.err(
                        &format!("run.features[{k}]"),
                        "hole".into(),
                        "a dent: a hole is in the oil supply, not the ball (move it to supply.holes)",
                    ));
                }
            }
        }
        Ok(())
    }

    /// Snapshots by time, or by the first feature's position while it rolls.
    fn validate_snapshots(
        ck: &Check,
        r: &RunSpec,
        kin: &Kinematics,
        a: f64,
        first: Option<&Passing>,
    ) -> Result<(), SceneError> {
        let n = r.snapshots_s.len() + r.snapshots_a.len();
        if n > MAX_SNAPSHOTS {
            return Err(ck.err(
                "run.snapshots_s",
                format!("{n} snapshots (with run.snapshots_a)"),
                &format!("at most {MAX_SNAPSHOTS}: each holds whole fields"),
            ));
        }
        for (k, &ts) in r.snapshots_s.iter().enumerate() {
            ck.time(&format!("run.snapshots_s[{k}]"), ts)?;
        }
        if !r.snapshots_a.is_empty() {
            let Some(x0) = first.map(|f| f.x_start_a) else {
                return Err(ck.err(
                    "run.snapshots_a",
                    format!("{:?}", r.snapshots_a),
                    "positions of the first feature's centre: needs a dent in run.features or a hole in supply.holes",
                ));
            };
            for (k, &x) in r.snapshots_a.iter().enumerate() {
                if !(x.is_finite() && x >= x0) {
                    return Err(ck.err(
                        &format!("run.snapshots_a[{k}]"),
                        num(x),
                        &format!("finite and >= the first feature's start {x0} (a)"),
                    ));
                }
                if kin.time_at_travel((x - x0) * a).is_none() {
                    return Err(ck.err(
                        &format!("run.snapshots_a[{k}]"),
                        num(x),
                        &format!(
                            "a position run.motion `{}` carries the first feature to (features travel with the surfaces; it stops at {:.4} a): give run.snapshots_s instead",
                            r.motion.label(),
                            x0 + kin.travel_limit().unwrap_or(f64::INFINITY) / a
                        ),
                    ));
                }
            }
        }

        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hertz_text() -> String {
        BUILTINS.iter().find(|(n, _)| *n == "hertz").unwrap().1.to_string()
    }

    fn refused(text: &str) -> String {
        Scene::from_json(text, "test").unwrap_err().to_string()
    }

    #[test]
    fn builtins_parse_and_round_trip() {
        // The JSON spells out every default (the run's method resolved): reading it back gives
        // the same scene, whose JSON is the same again.
        for s in builtins() {
            let again = Scene::from_json(&s.to_json(), "round trip").unwrap();
            assert_eq!(
                s.run.as_ref().map(RunSpec::method),
                again.run.as_ref().map(|r| r.method.unwrap())
            );
            assert_eq!(s.to_json(), again.to_json());
            assert_eq!(Scene::from_json(&again.to_json(), "again").unwrap(), again);
        }
        assert_eq!(load("hertz").unwrap().name, "hertz");
    }

    #[test]
    fn missing_and_unknown_fields_are_named() {
        let t = hertz_text().replace("\"load_n\": 20.0,", "");
        let m = refused(&t);
        assert!(m.contains("conditions") && m.contains("load_n"), "{m}");
        let t = hertz_text().replace("\"load_n\"", "\"lod_n\"");
        let m = refused(&t);
        assert!(m.contains("unknown field `lod_n`"), "{m}");
    }

    #[test]
    fn out_of_range_values_are_named_with_their_range() {
        let m = refused(&hertz_text().replace("9.525e-3", "-9.525e-3"));
        assert!(m.contains("conditions.ball_radius_m") && m.contains("> 0"), "{m}");
        let m = refused(&hertz_text().replace("\"nx\": 129", "\"nx\": 4"));
        assert!(m.contains("grid.nx") && m.contains("5 ..= 4097"), "{m}");
        let m = refused(&hertz_text().replace("[-1.25, 1.25], \"y_a\"", "[1.25, -1.25], \"y_a\""));
        assert!(m.contains("domain.x_a"), "{m}");
        let m = refused(&hertz_text().replace("\"tolerance\": 1e-8", "\"tolerance\": 0"));
        assert!(m.contains("solver.tolerance"), "{m}");
    }

    #[test]
    fn nan_and_overflow_are_refused() {
        // JSON has no NaN: the parser refuses it, naming the field.
        let m = refused(&hertz_text().replace("20.0", "NaN"));
        assert!(m.contains("load_n"), "{m}");
        let m = refused(&hertz_text().replace("20.0", "1e999"));
        assert!(m.contains("load_n"), "{m}");
    }

    #[test]
    fn reynolds_march_reads_the_shared_run_block() {
        let text = BUILTINS.iter().find(|b| b.0 == "reynolds-m20-l10-dent").unwrap().1;
        let m =
            refused(&text.replace("\"until_feature_at_a\": 1.0", "\"until_feature_at_a\": -3.0"));
        assert!(
            m.contains("run.stop.until_feature_at_a") && m.contains("first feature's start"),
            "{m}"
        );
        let m = refused(&text.replace("\"steps_per_cell\": 1.0", "\"steps_per_cell\": 0.0"));
        assert!(m.contains("run.time.steps_per_cell"), "{m}");
        let m = refused(&text.replace("[-1.0, -0.5, 0.0, 0.5]", "[-1.0, 4.0]"));
        assert!(m.contains("run.snapshots_a[1]") && m.contains("the run ends there"), "{m}");
        // What the Reynolds model cannot march: a hole (in the ball: refused for every model),
        // a dent in units of a supply the scene has not, another start or motion; and a run
        // with no end.
        let hole = text.replace(
            "{ \"dent\": { \"depth_m\": 2.5e-7, \"width_a\": 0.5, \"x_start_a\": -2.0, \"y_a\": 0.0 } }",
            "{ \"hole\": { \"radius_a\": 0.2, \"x_start_a\": -2.0 } }",
        );
        let m = refused(&hole);
        assert!(m.contains("run.features[0]") && m.contains("supply.holes"), "{m}");
        let amp = text.replace("\"depth_m\": 2.5e-7", "\"amplitude\": 10.0");
        let m = refused(&amp);
        assert!(m.contains("run.features[0].dent.amplitude") && m.contains("supply"), "{m}");
        let m = refused(&text.replace("\"steady-rolling\"", "\"uniform\""));
        assert!(m.contains("run.start") && m.contains("steady-rolling"), "{m}");
        let m = refused(&text.replace("\"stop\": { \"until_feature_at_a\": 1.0 }", "\"stop\": {}"));
        assert!(m.contains("run.stop.max_time_s") && m.contains("required"), "{m}");
    }

    #[test]
    fn the_seed_s_layer_scenes_name_their_case_through_both_models() {
        // `ehl compare squeeze-after-stop` runs the stop through both models, on the
        // comparison's own plan: the same contact, both models, the same start.
        for (one, both) in [
            ("squeeze-after-stop", "stop-compare"),
            ("rolling-from-squeezed", "rolling-from-squeezed-compare"),
        ] {
            let s = builtin(one).unwrap();
            assert!(!s.is_comparison());
            let c = s.as_comparison().unwrap().expect("it names its comparison");
            assert_eq!(c.name, both);
            assert!(c.models().contains(&Model::Layer) && c.models().contains(&Model::Reynolds));
            assert_eq!(c.conditions, s.conditions);
            let (r1, r2) = (s.run.as_ref().unwrap(), c.run.as_ref().unwrap());
            assert_eq!(r1.start, r2.start, "{one}");
        }
        // A comparison is its own, and a scene that names none runs as itself.
        assert!(builtin("stop-compare").unwrap().as_comparison().unwrap().is_none());
        assert!(builtin("squeeze-steady").unwrap().as_comparison().unwrap().is_none());
        // Refused: the field on a comparison scene, a name that is not a comparison, and a
        // comparison of another contact, each naming the field.
        let text = |n: &str| BUILTINS.iter().find(|b| b.0 == n).unwrap().1.to_string();
        let m = refused(&text("stop-compare").replacen('{', "{\"comparison\": \"seed\",", 1));
        assert!(m.contains("comparison") && m.contains("one-model"), "{m}");
        let named = |c: &str| {
            Scene::from_json(
                &text("squeeze-after-stop").replace("\"stop-compare\"", &format!("\"{c}\"")),
                "t",
            )
            .unwrap()
            .as_comparison()
            .unwrap_err()
            .to_string()
        };
        let m = named("hole");
        assert!(m.contains("comparison") && m.contains("listing `models`"), "{m}");
        let m = named(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../validation/tests/data/user-10n.json"
        ));
        assert!(m.contains("comparison") && m.contains("same contact"), "{m}");
    }

    #[test]
    fn a_comparison_runs_one_dent_and_one_supply_through_every_model() {
        // A dent in units of the supply's thickness is the same dent in metres for every model;
        // the supply stays for the Reynolds model (to read) and leaves the dry one.
        let text = BUILTINS.iter().find(|b| b.0 == "dent-shallow").unwrap().1.to_string();
        let mut s = Scene::from_json(&text, "test").unwrap();
        s.reynolds = Some(ReynoldsSpec {
            viscosity: ViscosityLaw::default(),
            density: DensityLaw::default(),
            moes: None,
            solver: ReynoldsSettings::default(),
        });
        let s = s.comparing(&[Model::Layer, Model::Reynolds]).unwrap();
        assert!(s.is_comparison() && s.comparing(&[Model::Layer, Model::Layer]).is_err());
        let r = s.for_model(Model::Reynolds);
        let l = s.for_model(Model::Layer);
        assert_eq!(r.dents().unwrap(), l.dents().unwrap());
        assert_eq!(r.dents().unwrap()[0].depth_m, 1.25 * 2.5e-8);
        assert!(r.layer.is_none() && r.supply == s.supply && l.run == s.run);
        assert!(s.for_model(Model::Dry).supply.is_none());
        // A hole in the ball is refused (it belongs to the supply); one in the supply passes a
        // march of both models (the Reynolds model sees it enter at its inflow edge), and is
        // refused in a steady Reynolds solve (a steady contact has none).
        let m = refused(&text.replace("{\n        \"dent\"", "{\n        \"hole\": { \"radius_a\": 0.2, \"x_start_a\": -1.0 } }, {\n        \"dent\""));
        assert!(m.contains("run.features[0]") && m.contains("supply.holes"), "{m}");
        let mut holed = s.clone();
        holed.supply.as_mut().unwrap().holes =
            vec![Hole { radius_a: 0.2, x_start_a: -1.0, y_a: 0.0 }];
        holed.validate("test").unwrap();
        let mut steady = holed.for_model(Model::Reynolds);
        steady.run.as_mut().unwrap().method = Some(Method::Steady);
        let m = steady.validate("test").unwrap_err().to_string();
        assert!(m.contains("supply.holes[0]") && m.contains("only in a march"), "{m}");
        // The layer needs its supply; a dent in units of a supply that is not there is refused.
        let m = refused(&text.replace("\"supply\": { \"thickness_m\": 2.5e-08 },", ""));
        assert!(m.contains("`supply`") && m.contains("required by the layer model"), "{m}");
    }

    #[test]
    fn dent_depth_and_snapshots_in_either_unit() {
        let text = BUILTINS.iter().find(|b| b.0 == "dent-shallow").unwrap().1.to_string();
        // The depth in metres is the factor times l0 (25 nm): 1.25 l0 = 31.25 nm.
        let metres = text.replace("\"amplitude\": 1.25", "\"depth_m\": 3.125e-8");
        let s = Scene::from_json(&metres, "test").unwrap();
        let Feature::Dent(d) = s.run.as_ref().unwrap().features[0] else { panic!() };
        assert_eq!(d.resolved(None).unwrap().depth_m, 3.125e-8);
        let Feature::Dent(a) = builtin("dent-shallow").unwrap().run.unwrap().features[0] else {
            panic!()
        };
        assert!(a.resolved(None).is_none(), "an amplitude needs the supply");
        assert!((a.resolved(Some(2.5e-8)).unwrap().depth_m - 3.125e-8).abs() < 1e-22);
        let both = text.replace("\"amplitude\": 1.25", "\"amplitude\": 1.25, \"depth_m\": 3.1e-8");
        let m = refused(&both);
        assert!(m.contains("run.features[0].dent.depth_m") && m.contains("exactly one"), "{m}");
        let none = text.replace("\"amplitude\": 1.25,", "");
        assert!(refused(&none).contains("exactly one"));
        // Snapshots by dent position are the times the dent takes to get there: from -1.25 a
        // at 0.01 m/s on a = 0.13466 mm, -0.75 a is reached at 6.733e-3 s.
        let s = Scene::from_json(&text, "test").unwrap();
        let first = s.passing().first().copied();
        let t = s.run.unwrap().snapshot_times(
            1.3466e-4,
            &Kinematics::constant(0.01).unwrap(),
            first.as_ref(),
        );
        assert_eq!(t.len(), 5);
        assert!((t[0] - 6.733e-3).abs() < 1e-7 && (t[2] - 1.6833e-2).abs() < 1e-6, "{t:?}");
        let before = text.replace("[-0.75, -0.25, 0.0, 0.25, 0.75]", "[-2.0]");
        assert!(refused(&before).contains("run.snapshots_a[0]"));
        // The Reynolds dent takes times as well as positions (`run.snapshot_times` for both).
        let rt = BUILTINS.iter().find(|b| b.0 == "reynolds-m20-l10-dent").unwrap().1.to_string();
        let ok = rt.replace("\"snapshots_a\": [-1.0, -0.5, 0.0, 0.5]", "\"snapshots_s\": [0.0]");
        let s = Scene::from_json(&ok, "test").unwrap();
        assert_eq!(
            s.run.unwrap().snapshot_times(1e-4, &Kinematics::constant(0.5).unwrap(), None),
            vec![0.0]
        );
    }

    #[test]
    fn layer_method_defaults_and_conflicts() {
        let text = |n: &str| BUILTINS.iter().find(|b| b.0 == n).unwrap().1.to_string();
        // Asked only for the steady state: solved steady; any start, feature or snapshot: march.
        assert_eq!(builtin("rolling-steady").unwrap().run.unwrap().method(), Method::Steady);
        for n in ["rolling-from-uniform", "rolling-from-squeezed", "hole", "squeeze-steady"] {
            assert_eq!(builtin(n).unwrap().run.unwrap().method(), Method::March, "{n}");
        }
        let steady = text("rolling-steady");
        let m =
            refused(&steady.replace(
                "\"method\": \"steady\",",
                "\"method\": \"steady\", \"start\": \"uniform\",",
            ));
        assert!(m.contains("run.start") && m.contains("no start"), "{m}");
        let m = refused(&steady.replace("\"motion\": \"rolling\"", "\"motion\": \"squeeze\""));
        assert!(m.contains("run.motion") && m.contains("march"), "{m}");
        let m = refused(&steady.replace(
            "\"motion\": \"rolling\",",
            "\"motion\": \"rolling\", \"snapshots_s\": [0.01],",
        ));
        assert!(m.contains("run.snapshots_s"), "{m}");
        let m = refused(&steady.replace("\"substeps\": 4", "\"substeps\": 0"));
        assert!(m.contains("run.steady.substeps") && m.contains("1 ..= 64"), "{m}");
        // A march needs its start.
        let m = refused(&text("hole").replace("\"start\": \"steady-rolling\",", ""));
        assert!(m.contains("run.start") && m.contains("required"), "{m}");
    }

    #[test]
    fn discretisation_stop_needs_the_multigrid_start() {
        let text = BUILTINS.iter().find(|b| b.0 == "reynolds-m20-l10").unwrap().1;
        let with = |solver: &str| {
            text.replace(
                "\"viscosity\": \"roelands\",",
                &format!("\"solver\": {solver}, \"viscosity\": \"roelands\","),
            )
        };
        Scene::from_json(&with("{\"stop\": \"discretisation\"}"), "test").unwrap();
        let m = refused(&with("{\"stop\": \"discretisation\", \"fmg_cycles\": 0}"));
        assert!(m.contains("reynolds.solver.stop") && m.contains("fmg_cycles"), "{m}");
    }

    #[test]
    fn step_sweeps_slow_mode_jumps_and_relaxation_thresholds_are_range_checked() {
        let text = BUILTINS.iter().find(|b| b.0 == "reynolds-m20-l10").unwrap().1;
        let with = |solver: &str| {
            text.replace(
                "\"viscosity\": \"roelands\",",
                &format!("\"solver\": {solver}, \"viscosity\": \"roelands\","),
            )
        };
        Scene::from_json(&with("{\"step_pre_sweeps\": 1, \"mode_extrapolation\": 0}"), "t")
            .unwrap();
        let m = refused(&with("{\"step_pre_sweeps\": 0}"));
        assert!(m.contains("reynolds.solver.step_pre_sweeps") && m.contains("1 ..= 4"), "{m}");
        let m = refused(&with("{\"fallback_omega_gs\": 1.5}"));
        assert!(
            m.contains("reynolds.solver.fallback_omega_gs") && m.contains("0: no third"),
            "{m}"
        );
        let m = refused(&with("{\"mode_extrapolation\": -1}"));
        assert!(
            m.contains("reynolds.solver.mode_extrapolation") && m.contains("0: no jumps"),
            "{m}"
        );
        let m = refused(&with("{\"relax\": {\"transient_threshold_at_rest\": 0}}"));
        assert!(
            m.contains("reynolds.solver.relax.transient_threshold_at_rest") && m.contains("1000"),
            "{m}"
        );
    }

    #[test]
    fn law_sets_and_their_conflicts() {
        let text = |n: &str| BUILTINS.iter().find(|b| b.0 == n).unwrap().1.to_string();
        let steady = text("rolling-steady");
        // The reconstruction needs its damper constant; the seed-fit laws fix it and refuse it.
        let m = refused(&steady.replace("\"damper_constant\": 550000.0,", ""));
        assert!(m.contains("layer.damper_constant") && m.contains("required"), "{m}");
        let fit = steady.replace("\"damper_constant\": 550000.0,", "\"laws\": \"seed-fit\",");
        let s = Scene::from_json(&fit, "test").unwrap();
        assert_eq!(s.layer.unwrap().laws, ehl_layer::LawSet::SeedFit);
        let m = refused(&steady.replace(
            "\"damper_constant\": 550000.0,",
            "\"damper_constant\": 550000.0, \"laws\": \"seed-fit\",",
        ));
        assert!(m.contains("layer.damper_constant") && m.contains("seed-fit"), "{m}");
        let m = refused(&fit.replace(
            "\"laws\": \"seed-fit\",",
            "\"laws\": \"seed-fit\", \"damper_pressure_scale\": 0.5,",
        ));
        assert!(m.contains("layer.damper_pressure_scale"), "{m}");
        let m = refused(&steady.replace(
            "\"damper_constant\": 550000.0,",
            "\"damper_constant\": 550000.0, \"damper_pressure_scale\": 7.0,",
        ));
        assert!(m.contains("layer.damper_pressure_scale") && m.contains("[0, 5]"), "{m}");
    }

    #[test]
    fn motions_that_change_are_read_once_and_refused_where_they_cannot_run() {
        let text = |n: &str| BUILTINS.iter().find(|b| b.0 == n).unwrap().1.to_string();
        let sq = text("squeeze-after-stop");
        let with =
            |motion: &str| sq.replace("\"motion\": \"squeeze\"", &format!("\"motion\": {motion}"));
        // A stop later on, a ramp, a table: parsed into the core's kinematics.
        let s = Scene::from_json(&with("{ \"stop\": { \"at_s\": 0.02 } }"), "test").unwrap();
        let k = s.run.as_ref().unwrap().kinematics(0.01).unwrap();
        assert_eq!((k.speed(0.01), k.speed(0.03), k.reference_speed()), (0.01, 0.0, 0.01));
        let t = with("{ \"table\": { \"knots\": [[0, 0.01], [0.1, 0.0]] } }");
        let s = Scene::from_json(&t, "test").unwrap();
        let k = s.run.as_ref().unwrap().kinematics(0.01).unwrap();
        assert!((k.travel(1.0) - 5e-4).abs() < 1e-18);
        // Refusals name the field: a stop before 0, a table running backwards, a steady-rolling
        // start for a motion that starts at rest.
        let m = refused(&with("{ \"stop\": { \"at_s\": -1.0 } }"));
        assert!(m.contains("run.motion.stop.at_s") && m.contains("[0, 10000]"), "{m}");
        let m = refused(&with("{ \"table\": { \"knots\": [[1.0, 0.01], [0.5, 0.0]] } }"));
        assert!(m.contains("run.motion") && m.contains("must not decrease"), "{m}");
        let m = refused(&with("{ \"table\": { \"knots\": [[0, 0.01], [0.1, 4097.0]] } }"));
        assert!(m.contains("run.motion.table.knots[1][1]") && m.contains("[0, 100]"), "{m}");
        let m = refused(&with("{ \"start-up\": { \"ramp_s\": 0.01 } }"));
        assert!(m.contains("run.start") && m.contains("starts at rest"), "{m}");
        // A feature snapshot the motion never carries the feature to.
        let dent = text("dent-shallow");
        let stopped = dent
            .replace("\"motion\": \"rolling\"", "\"motion\": { \"stop\": { \"at_s\": 0.005 } }");
        let m = refused(&stopped);
        assert!(m.contains("run.motion") && m.contains("leave the domain"), "{m}");
        // 0.005 s at 0.01 m/s carries the dent 0.37 a: from -1.25 a to -0.88 a, short of -0.75 a.
        let m = refused(&stopped.replace("\"until_features_passed\": true,", ""));
        assert!(m.contains("run.snapshots_a[0]") && m.contains("stops at -0.8787 a"), "{m}");
        // The Reynolds march starts from its steady solve: a motion from rest is refused by
        // name (the start), a stop after rolling is read.
        let r = text("reynolds-m20-l10-dent");
        let up = r.replace(
            "\"motion\": \"rolling\"",
            "\"motion\": { \"start-up\": { \"ramp_s\": 0.01 } }",
        );
        assert!(refused(&up).contains("run.start"));
        let sq = text("squeeze-after-stop")
            .replace("\"model\": \"layer\"", "\"model\": \"reynolds\", \"reynolds\": {}");
        let read = Scene::from_json(&sq, "test");
        assert!(read.is_ok(), "{:?}", read.err());
    }

    #[test]
    fn unknown_name_lists_builtins() {
        let m = load("no-such-scene").unwrap_err().to_string();
        assert!(m.contains("hertz"), "{m}");
    }

    #[test]
    fn grid_override_is_checked() {
        let s = builtin("hertz").unwrap();
        assert_eq!(s.with_points(65).unwrap().grid().nx, 65);
        assert!(s.with_points(3).is_err());
    }
}
