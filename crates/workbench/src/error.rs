//! The workbench's errors, typed: a scene refused, a model's failure with its solver's own
//! diagnosis, a file that could not be read or written, a figure or table that could not be
//! drawn, a request that cannot run. Each says what, where and when in its text, and keeps the
//! solver's diagnosis as a value a caller can match (`Error::Model { diagnosis, .. }`).
//! The binary and xtask wrap these in `anyhow` for their reports; the library does not.

use std::fmt;

/// Why the workbench gave no answer.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene (or a sweep over it) was refused, naming the field.
    #[error(transparent)]
    Scene(#[from] ehl_scene::SceneError),
    /// A model failed: where and when (`context`, e.g. "scene `seed`: time step 3 (t = …)"),
    /// and its solver's diagnosis.
    #[error("{context}: {diagnosis}")]
    Model {
        /// Where and when, outermost first.
        context: String,
        /// The solver's own diagnosis.
        diagnosis: Diagnosis,
        /// What a march had done before it failed, when it failed marching.
        partial: Option<Box<Partial>>,
    },
    /// A file or folder could not be read or written. The system's error is part of the
    /// message, not a separate cause: a report that prints causes says it once.
    #[error("{context}: {error}")]
    Io {
        /// What was being done, and to which path.
        context: String,
        /// The system's error.
        error: std::io::Error,
    },
    /// An output (a figure, JSON, an `.npy` file) could not be produced.
    #[error("{context}: {message}")]
    Output {
        /// Which output.
        context: String,
        /// What went wrong.
        message: String,
    },
    /// A request the workbench cannot run as asked (a comparison run as one model, an empty
    /// plan, a sweep folder from another sweep).
    #[error("{0}")]
    Refused(String),
    /// Stopped on request ([`ehl_core::cancel`]: a signal, Python's Ctrl-C): what was done and
    /// what is in place.
    #[error("interrupted: {0}")]
    Interrupted(String),
}

/// A solver's diagnosis, by the solver it comes from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Diagnosis {
    /// The dry contact solver (every model's contact).
    #[error(transparent)]
    Contact(#[from] ehl_core::NumericError),
    /// The layer model's stepper or steady solve.
    #[error(transparent)]
    Layer(#[from] ehl_layer::LayerError),
    /// The Reynolds solver: a divergence, or a solve that ended unconverged.
    #[error(transparent)]
    Reynolds(#[from] ehl_reynolds::ReynoldsError),
    /// A motion that cannot be built.
    #[error(transparent)]
    Motion(#[from] ehl_core::KinematicsError),
    /// A march that cannot be planned or driven as the scene asks (what to change is named).
    #[error("{0}")]
    Plan(String),
}

impl Diagnosis {
    /// The kind of failure in a word or two, what a map of many runs counts: `interrupted`
    /// (stopped on request), `film closed`
    /// (the lubricated solution broke down where the film went negative), `stalled`, `limit
    /// cycle`, `diverged`, `cycle limit` (still converging when the iterations ran out),
    /// `unstable` (explicit steps past their limit), `contact solve` (the dry contact solver's
    /// own failure) or `refused` (a run that cannot be set up as asked).
    pub fn class(&self) -> &'static str {
        use ehl_core::NumericError as N;
        use ehl_layer::LayerError as L;
        use ehl_reynolds::{FailureKind as K, ReynoldsError as R};
        match self {
            Diagnosis::Contact(N::Cancelled(_))
            | Diagnosis::Layer(L::Contact { source: N::Cancelled(_), .. })
            | Diagnosis::Reynolds(R::Cancelled(_)) => "interrupted",
            Diagnosis::Contact(_) | Diagnosis::Layer(L::Contact { .. }) => "contact solve",
            Diagnosis::Layer(L::Unstable { .. }) => "unstable",
            Diagnosis::Layer(L::Steady { kind, .. }) => match kind {
                ehl_layer::SteadyFailure::Stalled => "stalled",
                ehl_layer::SteadyFailure::Diverging => "diverged",
                ehl_layer::SteadyFailure::IterationLimit => "cycle limit",
            },
            Diagnosis::Reynolds(R::Diverged { .. }) => "diverged",
            Diagnosis::Reynolds(R::DryStart(_)) => "contact solve",
            Diagnosis::Reynolds(R::NotConverged(r)) => match r.diagnosis.as_ref().map(|d| d.kind) {
                Some(K::FilmClosed) => "film closed",
                Some(K::LimitCycle) => "limit cycle",
                Some(K::Stalled) => "stalled",
                Some(K::CycleLimit) | None => "cycle limit",
            },
            Diagnosis::Layer(L::Setup(_))
            | Diagnosis::Reynolds(R::NoSteadyStart)
            | Diagnosis::Motion(_)
            | Diagnosis::Plan(_) => "refused",
        }
    }
}

/// The workbench's result.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The same error with `what` (a place or a time) put in front of its context.
    pub fn within(self, what: impl fmt::Display) -> Error {
        let join = |c: String| if c.is_empty() { what.to_string() } else { format!("{what}: {c}") };
        match self {
            Error::Model { context, diagnosis, partial } => {
                Error::Model { context: join(context), diagnosis, partial }
            }
            Error::Io { context, error } => Error::Io { context: join(context), error },
            Error::Output { context, message } => Error::Output { context: join(context), message },
            Error::Refused(m) => Error::Refused(join(m)),
            Error::Interrupted(m) => Error::Interrupted(m),
            Error::Scene(e) => Error::Scene(e),
        }
    }

    /// The solver's diagnosis, when a model failed.
    pub fn diagnosis(&self) -> Option<&Diagnosis> {
        match self {
            Error::Model { diagnosis, .. } => Some(diagnosis),
            _ => None,
        }
    }

    /// The kind of failure ([`Diagnosis::class`]); `other` for an error that is not a model's
    /// (a file, a figure).
    pub fn class(&self) -> &'static str {
        self.diagnosis().map_or("other", Diagnosis::class)
    }

    /// What the failed march had done, when a model failed marching.
    pub fn partial(&self) -> Option<&Partial> {
        match self {
            Error::Model { partial, .. } => partial.as_deref(),
            _ => None,
        }
    }

    /// The same error carrying what the march had done (a model's failure only: any other
    /// error is no march's, and is returned as it was).
    pub fn with_partial(self, p: Partial) -> Error {
        match self {
            Error::Model { context, diagnosis, .. } => {
                Error::Model { context, diagnosis, partial: Some(Box::new(p)) }
            }
            e => e,
        }
    }
}

/// What a march that failed had done: its record up to the last step it took and that
/// state's fields. Not an answer (the run failed), but where and how it went wrong, and what
/// an hour's march keeps of its work: the writers put it beside the diagnosis
/// ([`crate::output::write_failure`]).
#[derive(Clone, Debug)]
pub struct Partial {
    /// The start, then one row per step taken (SI): the columns of an answer's
    /// `timeseries.csv`.
    pub rows: Vec<serde_json::Value>,
    /// Steps taken.
    pub steps: usize,
    /// Time [s] from the start of the motion to the last state taken.
    pub t_s: f64,
    /// That state's fields (SI), by file stem.
    pub fields: Vec<(String, ndarray::Array2<f64>)>,
}

impl From<Diagnosis> for Error {
    fn from(diagnosis: Diagnosis) -> Self {
        Error::Model { context: String::new(), diagnosis, partial: None }
    }
}

/// Each solver's error is a model failure with that diagnosis.
macro_rules! diagnosis_from {
    ($($t:ty),*) => {$(
        impl From<$t> for Error {
            fn from(e: $t) -> Self {
                Diagnosis::from(e).into()
            }
        }
    )*};
}
diagnosis_from!(
    ehl_core::NumericError,
    ehl_layer::LayerError,
    ehl_reynolds::ReynoldsError,
    ehl_core::KinematicsError
);

/// A figure the drawing backend could not draw.
impl<E: std::error::Error + Send + Sync> From<plotters::drawing::DrawingAreaErrorKind<E>>
    for Error
{
    fn from(e: plotters::drawing::DrawingAreaErrorKind<E>) -> Self {
        Error::Output { context: "drawing a figure".into(), message: e.to_string() }
    }
}

/// Puts a place or a time in front of an error, as it passes up.
pub trait Within<T> {
    /// `what` in front of the error's context.
    fn within(self, what: impl FnOnce() -> String) -> Result<T>;
}

impl<T, E: Into<Error>> Within<T> for std::result::Result<T, E> {
    fn within(self, what: impl FnOnce() -> String) -> Result<T> {
        self.map_err(|e| e.into().within(what()))
    }
}

/// Writes `contents` to `path`, a failure naming the path; stops first when a stop was asked
/// for ([`interruption`]).
pub fn write_file(path: &std::path::Path, contents: impl AsRef<[u8]>) -> Result<()> {
    interruption()?;
    std::fs::write(path, contents).map_err(io(format!("writing {}", path.display())))
}

/// `Err(Interrupted)` once a stop was asked for ([`ehl_core::cancel`]): the check a writer makes
/// between files, so that it stops within a file's time of a signal.
pub fn interruption() -> Result<()> {
    ehl_core::cancel::check().map_err(|_| Error::Interrupted("the writing stopped".into()))
}

/// Creates the folder `path` and its parents, a failure naming the path.
pub fn create_dir(path: &std::path::Path) -> Result<()> {
    std::fs::create_dir_all(path).map_err(io(format!("creating {}", path.display())))
}

/// An I/O failure, saying what was being done.
pub fn io(context: impl fmt::Display) -> impl FnOnce(std::io::Error) -> Error {
    let context = context.to_string();
    move |error| Error::Io { context, error }
}

/// An output failure (a drawing backend, a serialiser), saying which output.
pub fn output<E: fmt::Display>(context: impl fmt::Display) -> impl FnOnce(E) -> Error {
    let context = context.to_string();
    move |e| Error::Output { context, message: e.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn context_reads_outermost_first_and_the_diagnosis_stays_a_value() {
        let e: Error = ehl_core::NumericError::Invalid("load 0".into()).into();
        let e = e.within("time step 3 (t = 1e-3 s)").within("scene `seed`");
        assert_eq!(e.to_string(), "scene `seed`: time step 3 (t = 1e-3 s): load 0");
        assert!(matches!(
            e.diagnosis(),
            Some(Diagnosis::Contact(ehl_core::NumericError::Invalid(_)))
        ));
        let r: Result<()> =
            Err(Diagnosis::Plan("run.time.dt_s: required".into())).within(|| "run".into());
        assert_eq!(r.unwrap_err().to_string(), "run: run.time.dt_s: required");
    }
}
