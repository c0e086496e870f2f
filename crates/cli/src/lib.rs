//! The workbench's runner and writers, behind the `ehl` command-line tool and the xtask harness:
//! a [`Scene`](ehl_scene::Scene) goes in, an [`Outcome`] comes out, and [`output::write`] turns it
//! into `summary.json`, `centreline.csv`, `.npy` fields and PNG figures.

pub mod layer;
pub mod output;
pub mod plot;
pub mod progress;
pub mod reynolds;
pub mod run;

pub use run::{DryOutcome, Outcome, run_scene};
