//! The workbench's library, behind the `ehl` command-line tool and the xtask harness: a
//! [`Scene`](ehl_scene::Scene) goes in, each model in the registry ([`run::MODELS`]) that the
//! scene lists runs it through the one [`model::Outcome`] interface, and [`output::write`] turns
//! an outcome into `summary.json`, `centreline.csv`, `.npy` fields and PNG figures;
//! [`compare`] puts several models' outcomes side by side.

pub mod accuracy;
pub mod compare;
pub mod drive;
pub mod dry;
pub mod error;
pub mod layer;
pub mod model;
pub mod output;
pub mod plot;
pub mod progress;
pub mod reynolds;
pub mod run;
pub mod sweep;

pub use dry::DryOutcome;
/// Stopping a run under way (a signal, Python's Ctrl-C): the core's one request, read by every solver.
pub use ehl_core::cancel;
pub use error::{Diagnosis, Error};
pub use model::{ContactModel, Outcome};
pub use run::{MODELS, run_scene};
