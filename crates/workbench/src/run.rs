//! The registry of models and the runner: a scene goes in, the outcome of its model comes out.

use crate::error::{Error, Result};
use crate::model::{ContactModel, Outcome};
use ehl_scene::Scene;

/// Every model the workbench runs. A new model is its module (or crate) implementing
/// [`ContactModel`], its name in the scene's `Model` enum, and one line here.
pub static MODELS: &[&dyn ContactModel] = &[
    &crate::dry::Dry,
    &crate::layer::Layer,
    &crate::reynolds::Reynolds,
    &crate::reynolds::ReynoldsFlooded,
];

/// The registered model of a scene's kind.
pub fn model(kind: ehl_scene::Model) -> Result<&'static dyn ContactModel> {
    match MODELS.iter().find(|m| m.kind() == kind) {
        Some(m) => Ok(*m),
        None => Err(Error::Refused(format!("no model registered for {kind:?}"))),
    }
}

/// Runs a one-model `scene` (already validated) and returns its outcome; fails with a diagnosis
/// if the solver diverges or does not converge. [`crate::accuracy::run`] adds the answer's
/// estimated error.
///
/// ```
/// use ehl_workbench::Outcome;
/// let scene = ehl_scene::load("hertz").unwrap().with_points(33).unwrap();
/// let answer = ehl_workbench::run_scene(&scene).unwrap();
/// // The dry contact's peak pressure is Hertz's p_h (33² resolves it to 1e-3).
/// let p_max = answer.observables().max_pressure_pa;
/// assert!((p_max / answer.scales().p_h - 1.0).abs() < 1e-3);
/// ```
pub fn run_scene(scene: &Scene) -> Result<Box<dyn Outcome>> {
    let Some(kind) = scene.model() else {
        return Err(Error::Refused(format!(
            "scene `{}` is a comparison of {:?}: run it with `ehl compare`, or one model of it (Scene::for_model)",
            scene.name,
            scene.models()
        )));
    };
    stopped(scene, model(kind)?.run(scene))
}

/// Runs `coarse`, the scene of `finer` on fewer points, with the model of `finer`'s scene, for
/// an error estimate ([`ContactModel::run_coarser`]).
pub fn run_coarser(coarse: &Scene, finer: &dyn Outcome) -> Result<Box<dyn Outcome>> {
    let Some(kind) = coarse.model() else {
        return Err(Error::Refused(format!("scene `{}` is a comparison", coarse.name)));
    };
    stopped(coarse, model(kind)?.run_coarser(coarse, finer))
}

/// A model's outcome, or the stop that ended it.
fn stopped(scene: &Scene, outcome: Result<Box<dyn Outcome>>) -> Result<Box<dyn Outcome>> {
    if ehl_core::cancel::requested() {
        // Whatever the model ended with, it ended because a stop was asked for.
        return Err(Error::Interrupted(format!(
            "scene `{}`: stopped before it finished",
            scene.name
        )));
    }
    outcome
}
