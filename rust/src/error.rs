//! What the engine can refuse, one variant per kind of failure. Every message names the place
//! (body, contact, node, element, key, by the case's names where the model carries them) and
//! the fix, so that the front ends can show it as one line; the kind lets them map it to an
//! exception class without reading the text.

use std::fmt;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Malformed or unsupported input: NaN, out-of-range values, bad indices, degenerate mesh,
    /// initial penetration.
    Input,
    /// A body (or part of one) is free to move: a mechanism the supports and closed contacts
    /// leave unresisted.
    FreeBody,
    /// The tangential load exceeds what friction can hold: a body slides as a whole.
    GrossSliding,
    /// A linear system is singular: redundant constraints or a stiffness with a mechanism.
    Singular,
    /// Equilibrium is lost beyond `Options::equilibrium_tol` (ill-conditioning).
    Equilibrium,
    /// The last-resort anti-cycling rule froze a status and a contact condition is violated:
    /// the scene may be ill-posed for its friction coefficient.
    IllPosed,
    /// A broken invariant of the engine itself: a bug.
    Internal,
    /// A stop was requested from outside (`interrupt`): not a failure, the run ends there.
    Interrupted,
}

impl ErrorKind {
    pub fn name(self) -> &'static str {
        match self {
            ErrorKind::Input => "input",
            ErrorKind::FreeBody => "free_body",
            ErrorKind::GrossSliding => "gross_sliding",
            ErrorKind::Singular => "singular",
            ErrorKind::Equilibrium => "equilibrium",
            ErrorKind::IllPosed => "ill_posed",
            ErrorKind::Internal => "internal",
            ErrorKind::Interrupted => "interrupted",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    pub kind: ErrorKind,
    pub message: String,
}

impl Error {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Error { kind, message: message.into() }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

pub type Result<T> = std::result::Result<T, Error>;

/// `bail!(Kind, "...", args)` returns an `Error` of `ErrorKind::Kind` built with `format!`.
#[macro_export]
macro_rules! bail {
    ($kind:ident, $($arg:tt)*) => {
        return Err($crate::error::Error::new($crate::error::ErrorKind::$kind, format!($($arg)*)))
    };
}

/// `fail!(Kind, "...", args)`: the same `Error` as a value (for `map_err`, `ok_or_else`).
#[macro_export]
macro_rules! fail {
    ($kind:ident, $($arg:tt)*) => {
        $crate::error::Error::new($crate::error::ErrorKind::$kind, format!($($arg)*))
    };
}

/// Whether `SLIPSTEP_TRACE` is set: the engine then writes what it decides at its rare, costly
/// steps (rate problems, last resorts) to stderr, one line each, for diagnosis.
pub fn tracing() -> bool {
    static ON: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("SLIPSTEP_TRACE").is_some())
}

/// `trace!("...", args)`: one diagnostic line on stderr when `SLIPSTEP_TRACE` is set.
#[macro_export]
macro_rules! trace {
    ($($arg:tt)*) => {
        if $crate::error::tracing() {
            eprintln!("slipstep-trace: {}", format!($($arg)*));
        }
    };
}
