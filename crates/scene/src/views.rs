//! Parse, don't validate: what each model reads of a scene, as a value with every block it
//! needs present. A model's adapter asks for its view and gets it or a refusal naming the
//! missing field; no adapter unwraps an optional block.

use crate::{Check, Model, ReynoldsSpec, RunSpec, Scene, SceneError};
use ehl_core::{Contact, Lubricant, Supply};
use ehl_layer::LayerSpec;

/// The layer model's view of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerView {
    /// Ball, load, modulus.
    pub contact: Contact,
    /// The damper's lubricant.
    pub lubricant: Lubricant,
    /// The oil supplied: the layer.
    pub supply: Supply,
    /// The layer's laws.
    pub layer: LayerSpec,
    /// What happens in time.
    pub run: RunSpec,
    /// The scene's rolling speed [m/s] (0 when the scene gives none): the motion's reference.
    pub rolling_velocity_m_s: f64,
}

/// The Reynolds model's view of a scene (Moes input resolved).
#[derive(Clone, Debug, PartialEq)]
pub struct ReynoldsView {
    /// Ball, load (from Moes' `M` where given), modulus.
    pub contact: Contact,
    /// The sum velocity `u1 + u2` [m/s] (pure rolling: twice the rolling speed).
    pub sum_velocity_m_s: f64,
    /// The fluid.
    pub lubricant: Lubricant,
    /// Laws and solver settings.
    pub spec: ReynoldsSpec,
    /// The march after the steady solve, if the scene asks for one.
    pub march: Option<RunSpec>,
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
        Ok(LayerView {
            contact: self.conditions.contact(),
            lubricant: self.lubricant.ok_or_else(|| self.missing("lubricant", m))?.lubricant(),
            supply: self.supply.clone().ok_or_else(|| self.missing("supply", m))?,
            layer: self.layer.ok_or_else(|| self.missing("layer", m))?,
            run: self.run.clone().ok_or_else(|| self.missing("run", m))?,
            rolling_velocity_m_s: self.conditions.rolling_velocity_m_s.unwrap_or(0.0),
        })
    }

    /// What the Reynolds model reads.
    pub fn reynolds_view(&self) -> Result<ReynoldsView, SceneError> {
        let m = Model::Reynolds;
        let lubricant = self.lubricant.ok_or_else(|| self.missing("lubricant", m))?.lubricant();
        let spec = self.reynolds.clone().ok_or_else(|| self.missing("reynolds", m))?;
        let (contact, sum_velocity_m_s) = self.reynolds_conditions();
        Ok(ReynoldsView {
            contact,
            sum_velocity_m_s,
            lubricant,
            spec,
            march: self.run.clone().filter(|r| r.method() == crate::Method::March),
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
