//! Errors as the command line reports them (message, kind, position, exit code) and
//! the one way to print on stdout.
use certmesh::error::{Error, Result};
use std::io::Write;

// ---------------------------------------------------------------------------------
// Errors and exit codes

/// An error as the command line reports it: the message, a kind, a position (formula
/// column or file line) and the exit code.
pub(crate) struct CliError {
    pub(crate) message: String,
    pub(crate) kind: &'static str,
    pub(crate) position: Option<usize>,
    pub(crate) code: i32,
}

/// Exit code of usage and input errors.
pub(crate) const EXIT_INPUT: i32 = 2;
/// Exit code of a failure while doing the work.
pub(crate) const EXIT_RUNTIME: i32 = 1;

impl From<Error> for CliError {
    fn from(e: Error) -> Self {
        let (kind, position) = match &e {
            Error::Parse { column, .. } | Error::NeedsFeature { column, .. } => {
                ("formula", Some(*column))
            }
            Error::Format { line, .. } => ("file", (*line > 0).then_some(*line)),
            Error::Param(_) => ("parameter", None),
            Error::Domain(_) => ("domain", None),
            Error::TooLarge(_) => ("too-large", None),
            Error::NotFinite(_) => ("not-finite", None),
            Error::Unknown { .. } => ("unknown-name", None),
            Error::Io { .. } => ("io", None),
        };
        CliError {
            message: e.to_string(),
            kind,
            position,
            code: EXIT_INPUT,
        }
    }
}

impl CliError {
    /// The same error, as a failure during the work (exit 1).
    pub(crate) fn runtime(mut self) -> Self {
        self.code = EXIT_RUNTIME;
        self
    }
    pub(crate) fn with_prefix(mut self, p: &str) -> Self {
        self.message = format!("{p}: {}", self.message);
        self
    }
}

pub(crate) type CliResult<T> = std::result::Result<T, CliError>;

/// `result.runtime()`: a library error met while doing the work (exit 1).
pub(crate) trait Runtime<T> {
    fn runtime(self) -> CliResult<T>;
}
impl<T> Runtime<T> for Result<T> {
    fn runtime(self) -> CliResult<T> {
        self.map_err(|e| CliError::from(e).runtime())
    }
}

/// Print a line on stdout; a closed pipe (`certmesh ... | head`) is not an error.
macro_rules! out {
    ($($t:tt)*) => {{
        let _ = writeln!(std::io::stdout().lock(), $($t)*);
    }};
}

pub(crate) fn print_json(v: &impl serde::Serialize) {
    out!(
        "{}",
        serde_json::to_string_pretty(v).expect("reports serialize")
    );
}

/// Does the command line ask for JSON output? (Used for errors clap reports before the
/// arguments are parsed.)
pub(crate) fn wants_json(args: &[std::ffi::OsString]) -> bool {
    args.iter().skip(1).any(|a| a == "--json")
}

pub(crate) fn report_error(e: &CliError, json: bool) -> ! {
    if json {
        print_json(&serde_json::json!({
            "error": e.message,
            "kind": e.kind,
            "position": e.position,
        }));
    } else {
        eprintln!("certmesh: error: {}", e.message);
    }
    std::process::exit(e.code);
}
