//! The one error type of the library: every failure names the problem and, where
//! there is one, its position (column of a formula, line of a file).
use thiserror::Error;

/// Errors reported by certmesh. Bad input is never a panic.
#[derive(Debug, Error)]
pub enum Error {
    /// A formula did not parse. `column` is 1-based.
    #[error("formula error: {message} at column {column}")]
    Parse { message: String, column: usize },
    /// A formula uses a function that needs an optional cargo feature.
    #[error("'{function}' at column {column} needs rigorous interval enclosures from MPFR: rebuild with `--features mpfr` (needs the m4 program)")]
    NeedsFeature { function: String, column: usize },
    /// A mesh file is malformed. `line` is 1-based (0 for binary data: `message` then
    /// gives the byte offset, and the text names no line).
    #[error("{format} file{}: {message}", at_line(*.line))]
    Format {
        format: &'static str,
        line: usize,
        message: String,
    },
    /// A parameter is out of range or inconsistent.
    #[error("invalid parameter: {0}")]
    Param(String),
    /// The domain is empty, unbounded or not finite.
    #[error("invalid domain: {0}")]
    Domain(String),
    /// The requested work would not fit in memory.
    #[error("too large: {0}")]
    TooLarge(String),
    /// f is NaN or infinite somewhere it must be evaluated.
    #[error("f is not finite: {0}")]
    NotFinite(String),
    /// An unknown catalog entry, algorithm or format.
    #[error("unknown {kind} '{name}'; known: {known}")]
    Unknown {
        kind: &'static str,
        name: String,
        known: String,
    },
    #[error("i/o error on {path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

/// ", line N" for a line of a text file, nothing for binary data (line 0).
fn at_line(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(", line {line}")
    }
}

impl Error {
    pub fn io(path: impl AsRef<std::path::Path>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().display().to_string(),
            source,
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;
