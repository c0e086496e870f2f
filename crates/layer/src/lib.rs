//! The oedometric viscoelastic layer model of van Emden et al. (Tribology International 111
//! (2017) 197–210): a dry contact (elastic half-space, gap ≥ 0, pressure ≥ 0, force balance)
//! with a transported Kelvin–Voigt layer `l = l0 (1 − ε)` in the gap,
//! `η(p) Dε/Dt + E(p, ε) ε = p`. The contact is the shared core's [`ehl_core::DrySolver`].

pub mod laws;
pub mod model;
pub mod run;
pub mod steady;
pub mod stepper;
pub mod transport;

pub use laws::{DamperReading, LawParameters, LawSet, ModulusLaw};
pub use model::{LayerModel, LayerSpec, LayerState, Monitor, SEED_LAYER, SEED_SUPPLY_THICKNESS_M};
pub use run::{Snapshot, SqueezeReport, squeeze_steady, uniform_state};
pub use steady::{
    CYCLE_BOUND, SteadyCycle, SteadyReport, SteadySettings, rolling_steady, strain_residual,
};
pub use stepper::{LayerError, Scheme, SteadyFailure, Stepper, stability_estimate};
