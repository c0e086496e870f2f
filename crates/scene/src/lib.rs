//! Scenes as data: what to run (model, conditions in SI, domain, grid, solver settings,
//! outputs), read from JSON, checked before anything is computed or written.
//!
//! Built-in scenes are the JSON files in `validation/scenes/`, compiled in by name.

use ehl_core::{
    Contact, DrySettings, Grid, Hole, Kinematics, KinematicsError, Lubricant, Passing, Relief,
    Supply,
};
use ehl_layer::{LayerSpec, Scheme, SteadySettings};
use ehl_reynolds::{DensityLaw, ReynoldsSettings, ViscosityLaw};
use serde::{Deserialize, Serialize};
use std::path::Path;

mod builtins;
mod error;
mod limits;
mod relief;
mod spec;
pub mod sweep;
mod tiers;
mod validate;
pub mod views;
use builtins::parse;
pub use builtins::{builtin, builtin_names, builtins, load};
pub use error::SceneError;
pub use limits::{
    MAX_A_OVER_R, MAX_DOMAIN_A, MAX_PLACE_A, MAX_SNAPSHOTS, MAX_SPEED_M_S, MAX_TIME_S,
    MIN_CELLS_PER_WAVELENGTH, PLAUSIBLE,
};
pub use relief::{DentSpec, Feature, HeightMapSpec, RoughnessSpec, WavinessSpec};
pub use spec::{
    Conditions, Domain, GridSpec, LubricantSpec, Method, Motion, Outputs, RunSpec, StartState,
    StopSettings, TimeSettings,
};
pub use sweep::{Axis, Parameter, Sweep, builtin_sweep_names, load_sweep};
pub use tiers::{Tiered, Tiers};
use validate::Check;
pub use views::{LayerView, MarchCase, ReynoldsView};

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
    pub solver: Tiered<DrySettings>,
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
    pub solver: Tiered<ReynoldsSettings>,
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
    /// The supplied oil's thickness `l0` [m], when there is oil (a supply thicker than zero):
    /// the unit of a dent's `amplitude` and of the layer model's thicknesses.
    pub fn oil_m(&self) -> Option<f64> {
        self.supply.as_ref().map(|s| s.thickness_m).filter(|&t| t > 0.0)
    }

    /// The surfaces' relief in the run, resolved for a contact of half-width `a_m` [m]: dents
    /// with their depths in metres (an `amplitude` in units of the supply's thickness resolved
    /// with it), waviness and roughness with their lengths in units of `a`.
    pub fn relief(&self, a_m: f64) -> Result<Relief, SceneError> {
        let Some(r) = &self.run else { return Ok(Relief::default()) };
        let l0 = self.oil_m();
        let mut out = Relief::default();
        for (k, f) in r.features.iter().enumerate() {
            match f {
                Feature::Dent(d) => out.dents.push(d.resolved(l0).ok_or_else(|| SceneError::Range {
                    origin: self.name.clone(),
                    field: format!("run.features[{k}].dent.amplitude"),
                    value: format!("{:?}", d.amplitude),
                    allowed: "a depth in units of supply.thickness_m needs oil: give a supply thicker than zero, or `depth_m`".into(),
                })?),
                Feature::Waviness(w) => out.waves.push(w.resolved(a_m)),
                Feature::Roughness(r) => out.roughness.push(r.resolved(a_m)),
                Feature::HeightMap(m) => {
                    out.maps.push(m.resolved(a_m).map_err(|why| SceneError::Range {
                        origin: self.name.clone(),
                        field: format!("run.features[{k}].height-map.path"),
                        value: m.path.clone(),
                        allowed: why,
                    })?)
                }
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
            Feature::Waviness(_)
            | Feature::Roughness(_)
            | Feature::HeightMap(_)
            | Feature::Hole(_) => None,
        });
        dents.chain(self.holes().iter().map(Passing::from)).collect()
    }
}

pub use ehl_core::check::num;

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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtins::BUILTINS;

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
    fn moes_input_that_sets_an_impossible_speed_or_contact_names_its_own_value() {
        // L sets the speed through the lubricant: a tenth of an oil's α asks for 1e4 times the
        // speed, and the error shows L's value beside the speed it set (not one as the other).
        let m20 = BUILTINS.iter().find(|(n, _)| *n == "reynolds-m20-l10").unwrap().1;
        let m = refused(&m20.replace("\"alpha_per_pa\": 2.2e-8", "\"alpha_per_pa\": 2.2e-9"));
        assert!(m.contains("`reynolds.moes.l` = 10 ") && m.contains("rolling velocity"), "{m}");
        let m = refused(&m20.replace("117000000000.0", "1e9"));
        assert!(m.contains("`reynolds.moes.m` = 20 ") && m.contains("Hertz radius"), "{m}");
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
            solver: Tiered::default(),
        });
        let s = s.comparing(&[Model::Layer, Model::Reynolds]).unwrap();
        assert!(s.is_comparison() && s.comparing(&[Model::Layer, Model::Layer]).is_err());
        let r = s.for_model(Model::Reynolds);
        let l = s.for_model(Model::Layer);
        let a = 1.3e-4;
        assert_eq!(r.relief(a).unwrap(), l.relief(a).unwrap());
        assert_eq!(r.relief(a).unwrap().dents[0].depth_m, 1.25 * 2.5e-8);
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
    fn no_oil_is_the_reynolds_model_s_dry_limit_and_no_layer() {
        let builtin = |name: &str| BUILTINS.iter().find(|b| b.0 == name).unwrap().1.to_string();
        // A Reynolds contact with no oil supplied is a scene (its answer is the dry contact).
        let dry = builtin("reynolds-seed").replace(
            "\"model\": \"reynolds\",",
            "\"model\": \"reynolds\", \"supply\": { \"thickness_m\": 0.0 },",
        );
        let s = Scene::from_json(&dry, "test").unwrap();
        assert_eq!(s.supply.as_ref().map(|s| s.thickness_m), Some(0.0));
        // Less than none is refused, naming the field; so is a supply thinner than a molecule.
        let m = refused(&dry.replace("\"thickness_m\": 0.0", "\"thickness_m\": -1e-9"));
        assert!(m.contains("supply.thickness_m") && m.contains(">= 0"), "{m}");
        let m = refused(&dry.replace("\"thickness_m\": 0.0", "\"thickness_m\": 1e-15"));
        assert!(m.contains("supply.thickness_m") && m.contains("molecular"), "{m}");
        // The layer model's layer is the oil: it refuses none.
        let layer =
            builtin("dent-shallow").replace("\"thickness_m\": 2.5e-08", "\"thickness_m\": 0.0");
        let m = refused(&layer);
        assert!(m.contains("supply.thickness_m") && m.contains("layer model"), "{m}");
        // A Reynolds march with no oil is the dry contact's, stepped: refused, saying so.
        let dent = builtin("reynolds-m20-l10-dent").replace(
            "\"model\": \"reynolds\",",
            "\"model\": \"reynolds\", \"supply\": { \"thickness_m\": 0.0 },",
        );
        let m = refused(&dent);
        assert!(m.contains("supply.thickness_m") && m.contains("`dry` model"), "{m}");
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
        let m = refused(&steady.replace(
            "\"strain_tolerance\": 1e-05",
            "\"strain_tolerance\": 1e-05, \"advanced\": { \"substeps\": 0 }",
        ));
        assert!(m.contains("run.steady.advanced.substeps") && m.contains("1 ..= 64"), "{m}");
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
        let m = refused(&with("{\"stop\": \"discretisation\", \"advanced\": {\"fmg_cycles\": 0}}"));
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
        let adv = |knobs: &str| with(&format!("{{\"advanced\": {knobs}}}"));
        Scene::from_json(&adv("{\"step_pre_sweeps\": 1, \"mode_extrapolation\": 0}"), "t").unwrap();
        let m = refused(&adv("{\"step_pre_sweeps\": 0}"));
        assert!(
            m.contains("reynolds.solver.advanced.step_pre_sweeps") && m.contains("1 ..= 4"),
            "{m}"
        );
        let m = refused(&adv("{\"fallback_omega_gs\": 1.5}"));
        assert!(
            m.contains("reynolds.solver.advanced.fallback_omega_gs") && m.contains("0: no third"),
            "{m}"
        );
        let m = refused(&adv("{\"mode_extrapolation\": -1}"));
        assert!(
            m.contains("reynolds.solver.advanced.mode_extrapolation") && m.contains("0: no jumps"),
            "{m}"
        );
        let m = refused(&adv("{\"relax\": {\"transient_threshold_at_rest\": 0}}"));
        assert!(
            m.contains("reynolds.solver.advanced.relax.transient_threshold_at_rest")
                && m.contains("1000"),
            "{m}"
        );
        // A knob written beside the user settings is refused with where it goes.
        let m = refused(&with("{\"step_pre_sweeps\": 1}"));
        assert!(m.contains("reynolds.solver") && m.contains("under `advanced`"), "{m}");
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

    /// The wavy built-in with its first feature replaced by `feature` and `edit` applied.
    fn wavy(feature: serde_json::Value, edit: impl Fn(&mut serde_json::Value)) -> String {
        let mut v: serde_json::Value =
            serde_json::from_str(&builtin("waviness-compare").unwrap().to_json()).unwrap();
        v["run"]["features"][0] = feature;
        edit(&mut v);
        v.to_string()
    }

    #[test]
    fn waviness_and_roughness_are_read_in_si_and_resolved_on_the_contact() {
        let s = builtin("waviness-compare").unwrap();
        let a = ehl_core::HertzScales::new(&s.conditions.contact()).a;
        let relief = s.relief(a).unwrap();
        let w = relief.waves[0];
        assert_eq!((w.amplitude_m, w.wavelength_a * a), (5e-9, 3.4e-5));
        assert_eq!(relief.period_a(), Some(w.wavelength_a));
        assert!(s.passing().is_empty(), "a pattern covers the track: it never passes");
        let rough = serde_json::json!({"roughness": {"rq_m": 2e-9, "correlation_length_m": 2e-5, "seed": 3}});
        let t = Scene::from_json(&wavy(rough, |_| {}), "test").unwrap().relief(a).unwrap();
        assert_eq!(t.roughness[0], ehl_core::Roughness::new(2e-9, 2e-5 / a, 2e-5 / a, 3));
        assert_eq!(t.period_a(), None, "roughness never repeats");
        // A wave rolling in: its edge in m, resolved in a; out of range, named.
        let entering = serde_json::json!({"waviness": {"amplitude_m": 5e-9, "wavelength_m": 3.4e-5, "enters_at_x_m": -1.7e-4}});
        let t = Scene::from_json(&wavy(entering, |_| {}), "test").unwrap().relief(a).unwrap();
        assert_eq!(t.waves[0].edge_a, Some(-1.7e-4 / a));
        assert_eq!(t.period_a(), Some(3.4e-5 / a), "it repeats once it fills the contact");
        let far = serde_json::json!({"waviness": {"amplitude_m": 5e-9, "wavelength_m": 3.4e-5, "enters_at_x_m": -2.0}});
        let m = refused(&wavy(far, |_| {}));
        assert!(m.contains("features[0].waviness.enters_at_x_m"), "{m}");
    }

    #[test]
    fn a_pattern_the_grid_cannot_carry_is_refused_with_its_cells_and_the_grid_that_would() {
        use serde_json::json;
        let wave = |amp: f64, len: f64, angle: f64| json!({"waviness": {"amplitude_m": amp, "wavelength_m": len, "angle_deg": angle}});
        // 129² over 2.5 a: cells of 2.63 µm; an 8 µm wave spans about 3 of them.
        let m = refused(&wavy(wave(5e-9, 8e-6, 0.0), |_| {}));
        assert!(m.contains("features[0].waviness.wavelength_m"), "{m}");
        assert!(
            m.contains("3.04 cells") && m.contains("at least 4") && m.contains("170 points"),
            "{m}"
        );
        let m = refused(&wavy(wave(-1e-9, 3.4e-5, 0.0), |_| {}));
        assert!(m.contains("waviness.amplitude_m"), "{m}");
        let m = refused(&wavy(wave(5e-9, 3.4e-5, 400.0), |_| {}));
        assert!(m.contains("waviness.angle_deg"), "{m}");
        let rough = json!({"roughness": {"rq_m": 2e-9, "correlation_length_m": 2e-5, "correlation_length_y_m": 4e-6}});
        let m = refused(&wavy(rough, |_| {}));
        assert!(m.contains("roughness.correlation_length_y_m") && m.contains("1.52 cells"), "{m}");
        // A pattern passing is not steady.
        let steady = |v: &mut serde_json::Value| {
            v["run"]["method"] = "steady".into();
            v["run"].as_object_mut().unwrap().remove("start");
            v["run"].as_object_mut().unwrap().remove("snapshots_s");
        };
        let m = refused(&wavy(wave(5e-9, 3.4e-5, 0.0), steady));
        assert!(m.contains("run.") && m.contains("not steady"), "{m}");
    }
}
