//! Conventional Reynolds EHL point-contact solver in Hertz units (Venner & Lubrecht's
//! formulation): `∂/∂X(ε̄ ∂P/∂X) + ∂/∂Y(ε̄ ∂P/∂Y) − ∂(ρ̄H)/∂X = 0`, `ε̄ = ρ̄H³/(η̄λ̄)`,
//! `H = H00 + X²/2 + Y²/2 + W[P]` (the shared core's deformation operator on every level),
//! `∬ P = 2π/3`, `P ≥ 0`.

pub mod extrapolate;
pub mod formulas;
/// The lubricant laws, written once in the core.
pub use ehl_core::laws;
pub mod level;
pub mod params;
pub mod solver;

pub use level::{Level, OilBalance, RelaxSettings};
pub use params::{DensityLaw, ReynoldsParams, ViscosityLaw};
pub use solver::{
    CycleLog, Diagnosis, Divergence, FailureKind, ReynoldsError, ReynoldsReport, ReynoldsSettings,
    ReynoldsSolver, SETTLED_BOUND, Settled, SolverState, StopRule, TimeScheme,
};
