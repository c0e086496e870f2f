//! Shared contact core of the EHL workbench.
//!
//! Both solvers (the oedometric layer model and the Reynolds EHL model) stand on this crate:
//! the conditions and their Hertzian scales ([`params`]), the uniform grid ([`grid`]), the elastic
//! half-space deformation as an FFT convolution ([`deformation`]), the dry contact solver
//! ([`dry`]), the motion of the surfaces over time ([`kinematics`]) and Hertz's analytic solution
//! to check them against ([`hertz`]).
//!
//! Units: SI at the boundary (the `params` types), Hertzian dimensionless form inside:
//! `X = x/a`, `P = p/p_h`, gaps and deformations in units of the Hertz approach `a²/R`.

pub mod cancel;
pub mod check;
pub mod deformation;
pub mod dry;
pub mod features;
pub mod grid;
pub mod hertz;
pub mod kinematics;
pub mod laws;
pub mod observe;
pub mod params;
pub mod passage;

/// The least work (values computed) worth a parallel task of its own: smaller loops run as
/// one task on the calling thread. The coarse multigrid grids (17², 33²) otherwise paid more
/// for waking threads than for the work (on 17² the film update by FFT cost 26 µs, most of it
/// thread hand-over).
pub const PAR_MIN_WORK: usize = 16_384;

/// Items per parallel task when each item carries `work` values: at least [`PAR_MIN_WORK`].
pub fn par_min_len(work: usize) -> usize {
    PAR_MIN_WORK.div_ceil(work.max(1))
}

pub use check::FieldError;
pub use deformation::Deformation;
pub use dry::{DryProblem, DryReport, DrySettings, DrySolver, Start};
pub use features::{
    Dent, HeightMap, Hole, Passing, ROUGHNESS_MODES, Relief, Roughness, Supply, Waviness,
};
pub use grid::Grid;
pub use kinematics::{Kinematics, KinematicsError};
pub use observe::{Observables, SolidContact};
pub use params::{Contact, HertzScales, Lubricant, Moes, SEED_CONTACT, SEED_LUBRICANT};
pub use passage::Passage;

/// A numerical failure, with enough context to find it: which quantity, where, when.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum NumericError {
    #[error(
        "{quantity} became non-finite ({value}) at grid point (i={i}, j={j}) in iteration {iteration}"
    )]
    /// A field became NaN or infinite.
    NonFinite {
        /// Which field (pressure, gap, deformation, strain).
        quantity: &'static str,
        /// The value found.
        value: f64,
        /// Column.
        i: usize,
        /// Row.
        j: usize,
        /// The iteration (or step) it was found in.
        iteration: usize,
    },
    #[error(
        "dry contact solve did not converge: residual {residual:.3e} > tolerance {tolerance:.1e} after {iterations} iterations on {nx}x{ny}"
    )]
    /// The iteration limit came before the tolerance.
    NotConverged {
        /// The last residual [a²/R].
        residual: f64,
        /// The tolerance asked for [a²/R].
        tolerance: f64,
        /// Iterations run.
        iterations: usize,
        /// Grid points along `x`.
        nx: usize,
        /// Grid points along `y`.
        ny: usize,
    },
    #[error("{0}")]
    /// Input refused before any work, with what was wrong.
    Invalid(String),
    /// Stopped on request ([`cancel`]) before it converged.
    #[error(transparent)]
    Cancelled(#[from] cancel::Cancelled),
}

/// Returns the first non-finite entry of `a` as an error naming `quantity` and `iteration`.
pub fn check_finite<'a>(
    quantity: &'static str,
    a: impl Into<ndarray::ArrayView2<'a, f64>>,
    iteration: usize,
) -> Result<(), NumericError> {
    if let Some(((j, i), &value)) = a.into().indexed_iter().find(|(_, v)| !v.is_finite()) {
        return Err(NumericError::NonFinite { quantity, value, i, j, iteration });
    }
    Ok(())
}
