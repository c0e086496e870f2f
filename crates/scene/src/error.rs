//! Refused input: which field, what it holds, what is allowed.

use super::*;

/// Refused input: which field, what it holds, what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    #[error("scene {origin}: {}{message}", if path.is_empty() { String::new() } else { format!("field `{path}`: ") })]
    /// The JSON does not parse, or a field is missing or unknown.
    Parse {
        /// Which scene.
        origin: String,
        /// The field's path (`conditions.load_n`); empty at the top level, where the message
        /// names the field when there is one.
        path: String,
        /// The parser's words.
        message: String,
    },
    #[error("scene {origin}: field `{field}` = {value} is out of range: {allowed}")]
    /// A value out of its range.
    Range {
        /// Which scene.
        origin: String,
        /// The field's path.
        field: String,
        /// What it holds.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    #[error("no built-in scene or file named `{0}` (built-ins: {list})", list = builtin_names().join(", "))]
    /// No built-in scene or file of that name.
    Unknown(String),
    #[error(
        "`{name}` is both a built-in {kind} and a file here: write `./{name}` for the file, or rename it"
    )]
    /// A name that is a built-in and a file in the working folder.
    Ambiguous {
        /// The name given.
        name: String,
        /// `scene` or `sweep`.
        kind: &'static str,
    },
    #[error("scene file {path}: {message}")]
    /// The scene file cannot be read.
    Io {
        /// The file.
        path: String,
        /// The system's words.
        message: String,
    },
}
