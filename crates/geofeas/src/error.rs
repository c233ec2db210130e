//! Errors of the geofeas core.
//!
//! Every fallible public function returns [`Result<T>`]. Each variant carries the offending row
//! and field so that a caller (the Python bindings, a native service) can tell the user exactly
//! which input was wrong.

/// Result alias used throughout the crate.
pub type Result<T> = std::result::Result<T, Error>;

/// What went wrong, with the row (0-based) and field that caused it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A value that must be finite was NaN or infinite.
    #[error("{what} row {row}: field '{field}' is not finite ({value})")]
    NonFinite {
        what: &'static str,
        row: usize,
        field: &'static str,
        value: f64,
    },
    /// A semi-axis or variance that must be strictly positive was not.
    #[error("{what} row {row}: field '{field}' must be > 0, got {value}")]
    NonPositive {
        what: &'static str,
        row: usize,
        field: &'static str,
        value: f64,
    },
    /// A covariance matrix is not symmetric positive definite.
    #[error("covariance row {row}: not symmetric positive definite ({reason})")]
    NotPositiveDefinite { row: usize, reason: String },
    /// Two inputs that must have the same length do not.
    #[error("length mismatch: {left} rows in a, {right} rows in b")]
    LengthMismatch { left: usize, right: usize },
    /// An array has the wrong shape.
    #[error("{what}: expected shape {expected}, got {got}")]
    Shape {
        what: &'static str,
        expected: String,
        got: String,
    },
    /// An option is out of its valid range.
    #[error("invalid option '{name}': {reason}")]
    InvalidOption { name: &'static str, reason: String },
    /// The requested output would not fit in memory.
    #[error("output of {rows} x {cols} values ({bytes} bytes) exceeds the limit of {limit} bytes")]
    TooLarge {
        rows: usize,
        cols: usize,
        bytes: u128,
        limit: u128,
    },
    /// A long computation was interrupted by the caller (for example Ctrl-C in Python).
    #[error("interrupted")]
    Interrupted,
    /// A finite value outside the documented input domain (magnitudes whose scores could not
    /// be computed to full accuracy in double precision).
    #[error("{what} row {row}: field '{field}' = {value} is outside the input domain ({reason})")]
    OutOfDomain {
        what: &'static str,
        row: usize,
        field: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// Operator decisions that contradict each other or the feasibility rules; `rows` are the
    /// decisions involved (0-based rows of the caller's table).
    #[error("decisions rows {}: {reason}", join_rows(.rows))]
    Decisions { rows: Vec<usize>, reason: String },
    /// Anything about input data that does not fit the variants above.
    #[error("{0}")]
    Invalid(String),
    /// An error in the named argument of a call (`a`, `b`, `reports`, ...).
    #[error("argument '{argument}': {source}")]
    InArgument {
        argument: &'static str,
        source: Box<Error>,
    },
}

fn join_rows(rows: &[usize]) -> String {
    rows.iter()
        .map(|r| r.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

impl Error {
    /// This error, attributed to the argument `argument` (kept if one is already named).
    pub fn in_argument(self, argument: &'static str) -> Self {
        match self {
            Self::InArgument { .. } | Self::Interrupted => self,
            other => Self::InArgument {
                argument,
                source: Box::new(other),
            },
        }
    }

    /// The argument at fault, when known (an option's name for [`Error::InvalidOption`]).
    pub fn argument(&self) -> Option<&'static str> {
        match self {
            Self::InArgument { argument, .. } => Some(argument),
            Self::InvalidOption { name, .. } => Some(name),
            _ => None,
        }
    }

    /// The row (0-based) at fault, when the error concerns one row.
    pub fn row(&self) -> Option<usize> {
        match self {
            Self::NonFinite { row, .. }
            | Self::NonPositive { row, .. }
            | Self::OutOfDomain { row, .. }
            | Self::NotPositiveDefinite { row, .. } => Some(*row),
            Self::InArgument { source, .. } => source.row(),
            _ => None,
        }
    }

    /// The rows at fault (0-based) and what is wrong with them together, for an error about
    /// several rows of one table ([`Error::Decisions`]).
    pub fn rows(&self) -> Option<(&[usize], &str)> {
        match self {
            Self::Decisions { rows, reason } => Some((rows, reason)),
            Self::InArgument { source, .. } => source.rows(),
            _ => None,
        }
    }

    /// The field at fault, when the error concerns one field.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            Self::NonFinite { field, .. }
            | Self::NonPositive { field, .. }
            | Self::OutOfDomain { field, .. } => Some(field),
            Self::InArgument { source, .. } => source.field(),
            _ => None,
        }
    }
}
