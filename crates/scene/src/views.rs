//! Parse, don't validate: what each model reads of a scene, resolved once into a value with
//! every block it needs present, the motion built and the features in metres. A model's
//! adapter asks for its view once and runs from it, never returning to the scene; a missing
//! block is refused naming the field.

use crate::{Check, Model, ReynoldsSpec, RunSpec, Scene, SceneError};
use ehl_core::{Contact, DrySettings, Grid, Kinematics, Lubricant, Passing, Relief, Supply};
use ehl_layer::LayerSpec;

/// A march resolved: its run block, the motion built, what passes through the contact.
#[derive(Clone, Debug, PartialEq)]
pub struct MarchCase {
    /// The run block (steps, stop rules, snapshots).
    pub run: RunSpec,
    /// The motion, on the model's reference speed.
    pub motion: Kinematics,
    /// What passes through the contact, in order: the dents, then the supply's holes
    /// ([`Scene::passing`]).
    pub passing: Vec<Passing>,
    /// The surfaces' relief (dents' depths in metres, lengths in units of the model's `a`).
    pub relief: Relief,
}

impl MarchCase {
    /// The run's block and motion resolved on the reference speed `u_ref` [m/s], its relief on
    /// the model's contact half-width `a_m` [m].
    fn of(scene: &Scene, run: &RunSpec, u_ref: f64, a_m: f64) -> Result<MarchCase, SceneError> {
        let motion = run.kinematics(u_ref).map_err(|e| {
            Check { origin: &scene.name }.err(
                "run.motion",
                run.motion.label().into(),
                &e.to_string(),
            )
        })?;
        let relief = scene.relief(a_m)?;
        Ok(MarchCase { run: run.clone(), motion, passing: scene.passing(), relief })
    }

    /// The rest a squeezed start takes before this march: the same contact, supply and steps,
    /// a sudden stop from the reference speed and rest under the load until steady by the
    /// run's own rule or `max_time_s`; smooth surfaces (the supply's holes still pass).
    pub fn at_rest(&self, max_time_s: f64) -> Result<MarchCase, SceneError> {
        let run = RunSpec {
            start: Some(crate::StartState::SteadyRolling),
            motion: crate::Motion::Squeeze,
            features: vec![],
            snapshots_s: vec![],
            snapshots_a: vec![],
            stop: crate::StopSettings {
                until_features_passed: false,
                until_feature_at_a: None,
                max_time_s: Some(max_time_s),
                ..self.run.stop
            },
            ..self.run.clone()
        };
        let motion = run.kinematics(self.motion.reference_speed()).map_err(|e| {
            Check { origin: "(the squeezed start)" }.err(
                "run.motion",
                "squeeze".into(),
                &e.to_string(),
            )
        })?;
        let passing = self.passing[self.relief.dents.len()..].to_vec();
        Ok(MarchCase { run, motion, passing, relief: Relief::default() })
    }
}

/// The layer model's view of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerView {
    /// The scene's name (for the diagnoses).
    pub name: String,
    /// The grid over the scene's domain.
    pub grid: Grid,
    /// The contact solver's settings.
    pub dry: DrySettings,
    /// What happens in time, resolved (its motion on the rolling speed; a steady run's too).
    pub march: MarchCase,
    /// Ball, load, modulus.
    pub contact: Contact,
    /// The damper's lubricant.
    pub lubricant: Lubricant,
    /// The oil supplied: the layer.
    pub supply: Supply,
    /// The layer's laws.
    pub layer: LayerSpec,
    /// The scene's rolling speed [m/s] (0 when the scene gives none): the motion's reference.
    pub rolling_velocity_m_s: f64,
}

/// The Reynolds model's view of a scene (Moes input resolved).
#[derive(Clone, Debug, PartialEq)]
pub struct ReynoldsView {
    /// The scene's name (for the diagnoses).
    pub name: String,
    /// The grid over the scene's domain.
    pub grid: Grid,
    /// Ball, load (from Moes' `M` where given), modulus.
    pub contact: Contact,
    /// The sum velocity `u1 + u2` [m/s] (pure rolling: twice the rolling speed).
    pub sum_velocity_m_s: f64,
    /// The fluid.
    pub lubricant: Lubricant,
    /// Laws and solver settings.
    pub spec: ReynoldsSpec,
    /// The march after the steady solve, if the scene asks for one, its motion on the mean
    /// velocity (under pure rolling a dent on the ball moves at it).
    pub march: Option<MarchCase>,
    /// The oil supplied (read by the starved solver; the flooded one says it did not).
    pub supply: Option<Supply>,
}

impl Scene {
    /// A refusal naming a block `model` needs and the scene lacks.
    fn missing(&self, field: &str, model: Model) -> SceneError {
        Check { origin: &self.name }.err(
            field,
            "(missing)".into(),
            &format!("required by the {} model", format!("{model:?}").to_lowercase()),
        )
    }

    /// What the layer model reads.
    pub fn layer_view(&self) -> Result<LayerView, SceneError> {
        let m = Model::Layer;
        let lubricant = self.lubricant.ok_or_else(|| self.missing("lubricant", m))?.lubricant();
        let supply = self.supply.clone().ok_or_else(|| self.missing("supply", m))?;
        let layer = self.layer.ok_or_else(|| self.missing("layer", m))?;
        let run = self.run.clone().ok_or_else(|| self.missing("run", m))?;
        let rolling_velocity_m_s = self.conditions.rolling_velocity_m_s.unwrap_or(0.0);
        Ok(LayerView {
            name: self.name.clone(),
            grid: self.grid(),
            dry: *self.solver,
            march: MarchCase::of(
                self,
                &run,
                rolling_velocity_m_s,
                ehl_core::HertzScales::new(&self.conditions.contact()).a,
            )?,
            contact: self.conditions.contact(),
            lubricant,
            supply,
            layer,
            rolling_velocity_m_s,
        })
    }

    /// What the Reynolds model reads.
    pub fn reynolds_view(&self) -> Result<ReynoldsView, SceneError> {
        let m = Model::Reynolds;
        let lubricant = self.lubricant.ok_or_else(|| self.missing("lubricant", m))?.lubricant();
        let spec = self.reynolds.clone().ok_or_else(|| self.missing("reynolds", m))?;
        let (contact, sum_velocity_m_s) = self.reynolds_conditions();
        let march = match self.run.as_ref().filter(|r| r.method() == crate::Method::March) {
            Some(r) => {
                let a = ehl_core::HertzScales::new(&contact).a;
                Some(MarchCase::of(self, r, 0.5 * sum_velocity_m_s, a)?)
            }
            None => None,
        };
        Ok(ReynoldsView {
            name: self.name.clone(),
            grid: self.grid(),
            contact,
            sum_velocity_m_s,
            lubricant,
            spec,
            march,
            supply: self.supply.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_model_gets_its_view_or_the_missing_block_named() {
        let seed = crate::builtin("seed").unwrap();
        let l = seed.for_model(Model::Layer).layer_view().unwrap();
        assert_eq!((l.supply.thickness_m, l.rolling_velocity_m_s), (2.5e-8, 0.01));
        let r = seed.for_model(Model::Reynolds).reynolds_view().unwrap();
        assert_eq!(r.sum_velocity_m_s, 0.02);
        assert!(r.march.is_none(), "the seed's Reynolds solve is steady");
        // The dry model's scene holds none of their blocks: asking is refused by name.
        let dry = seed.for_model(Model::Dry);
        let e = dry.layer_view().unwrap_err().to_string();
        assert!(e.contains("lubricant") && e.contains("layer model"), "{e}");
        let e = dry.reynolds_view().unwrap_err().to_string();
        assert!(e.contains("lubricant") && e.contains("reynolds model"), "{e}");
    }
}
