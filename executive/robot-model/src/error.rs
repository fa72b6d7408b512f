//! What can be wrong with a robot description, and where.

use std::path::PathBuf;

/// A robot description could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("{}: cannot read the robot description: {source}", path.display())]
    Io {
        /// The file that was asked for.
        path: PathBuf,
        /// Why reading failed.
        #[source]
        source: std::io::Error,
    },
    /// The text is not a valid robot description; boxed to keep `Result<RobotModel, _>` small.
    #[error(transparent)]
    Invalid(Box<InvalidModel>),
}

/// A fault in a robot description with its place: `origin:line:column: field: message`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{origin}:{line}:{column}: {}{message}", field_prefix(.field))]
pub struct InvalidModel {
    /// Where the text came from: a file path or a name.
    pub origin: String,
    /// 1-based line of the offending key or value.
    pub line: usize,
    /// 1-based column (in characters) of the offending key or value.
    pub column: usize,
    /// Path of the offending field, e.g. `arm.reach_x[1]`; empty for faults of the whole text.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

fn field_prefix(field: &str) -> String {
    if field.is_empty() {
        String::new()
    } else {
        format!("{field}: ")
    }
}
