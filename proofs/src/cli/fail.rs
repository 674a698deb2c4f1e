//! Errors of the `proofs` command line and the exit-code convention: 0 success (the
//! certificate was written or accepted, whatever its verdicts), 1 a certificate
//! rejected by `check` or a run stopped by its budget (nothing proven, no certificate
//! written), 2 a usage or input error (as clap). With `--json` an error is the object
//! `{"error": ..., "kind": ..., "position": ...}` on stdout.
use proofs::bnb::Budget;
use std::process::ExitCode;

/// Exit codes: 0 success (the certificate was written or accepted, whatever its
/// verdicts), 1 a certificate rejected by `check` or a run stopped by its budget
/// (nothing proven, no certificate written), 2 a usage or input error (as clap).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Kind {
    Usage,
    Input,
    Check,
    Budget,
}

pub(crate) struct Fail {
    pub(crate) kind: Kind,
    pub(crate) msg: String,
    /// Byte offset into the input file, when known.
    pub(crate) position: Option<usize>,
}

impl Fail {
    pub(crate) fn input(msg: impl Into<String>) -> Fail {
        Fail {
            kind: Kind::Input,
            msg: msg.into(),
            position: None,
        }
    }
    pub(crate) fn check(msg: impl Into<String>) -> Fail {
        Fail {
            kind: Kind::Check,
            msg: msg.into(),
            position: None,
        }
    }
    /// The error of a run: a budget stop, or an input the run refused.
    pub(crate) fn run(msg: String, budget: &Budget) -> Fail {
        Fail {
            kind: if budget.is_exhausted() {
                Kind::Budget
            } else {
                Kind::Input
            },
            msg,
            position: None,
        }
    }
    pub(crate) fn code(&self) -> u8 {
        match self.kind {
            Kind::Usage | Kind::Input => 2,
            Kind::Check | Kind::Budget => 1,
        }
    }
    pub(crate) fn kind_name(&self) -> &'static str {
        match self.kind {
            Kind::Usage => "usage",
            Kind::Input => "input",
            Kind::Check => "check",
            Kind::Budget => "budget",
        }
    }
}

impl From<String> for Fail {
    fn from(msg: String) -> Fail {
        Fail::input(msg)
    }
}

impl From<&str> for Fail {
    fn from(msg: &str) -> Fail {
        Fail::input(msg)
    }
}

pub(crate) fn report(f: &Fail, json: bool) -> ExitCode {
    if json {
        let v = serde_json::json!({
            "error": f.msg,
            "kind": f.kind_name(),
            "position": f.position,
        });
        println!("{v}");
    } else {
        eprintln!("error: {}", f.msg);
    }
    ExitCode::from(f.code())
}
