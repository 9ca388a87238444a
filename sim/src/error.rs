//! Errors of the simulator and the `fieldguide` program.
//!
//! A scenario error always names what is wrong: the file, and for a bad value
//! the dotted field (`vehicle.wheelbase_m`, `path.segments[2].arc_radius_m`).

use std::fmt;
use std::path::PathBuf;

use fieldguide::Precondition;

/// Why a scenario could not be loaded or turned into a simulation setup.
#[derive(Debug)]
pub enum ScenarioError {
    /// The scenario name is neither a built-in scenario nor a readable file.
    NotFound {
        /// What the user asked for.
        requested: String,
        /// The built-in names, for the message.
        builtins: Vec<&'static str>,
        /// The built-in name closest to `requested`, when one is close.
        suggestion: Option<&'static str>,
    },
    /// A file (scenario or waypoint CSV) could not be read.
    Read {
        /// The file.
        file: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The TOML text does not parse (syntax error).
    Syntax {
        /// The scenario file or built-in name.
        origin: String,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A field is missing, unknown, of the wrong type, or out of its range.
    Field {
        /// The scenario file or built-in name.
        origin: String,
        /// The dotted path of the field (`vehicle.wheelbase_m`).
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A cell (or a line) of a CSV file a field refers to is wrong.
    Table(Box<TableError>),
}

/// Where a CSV file a scenario field refers to is wrong, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableError {
    /// The scenario file or built-in name.
    pub origin: String,
    /// The dotted path of the field naming the CSV file.
    pub field: String,
    /// The CSV file, as the scenario names it.
    pub file: String,
    /// The line, from 1.
    pub line: usize,
    /// The column, from 1, and its header name.
    pub column: (usize, String),
    /// What is wrong with it.
    pub reason: String,
}

impl ScenarioError {
    /// The dotted field name when the error is about one field.
    #[must_use]
    pub fn field(&self) -> Option<&str> {
        match self {
            Self::Field { field, .. } => Some(field),
            Self::Table(t) => Some(&t.field),
            _ => None,
        }
    }

    /// The CSV file, line and column (from 1) when the error is about a cell.
    #[must_use]
    pub fn cell(&self) -> Option<(&str, usize, usize)> {
        match self {
            Self::Table(t) => Some((&t.file, t.line, t.column.0)),
            _ => None,
        }
    }
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFound {
                requested,
                builtins,
                suggestion,
            } => {
                write!(
                    f,
                    "scenario `{requested}` is neither a built-in scenario ({}) nor a file",
                    builtins.join(", ")
                )?;
                match suggestion {
                    Some(name) => write!(f, "; did you mean `{name}`?"),
                    None => Ok(()),
                }
            }
            Self::Read { file, source } => {
                write!(f, "cannot read `{}`: {source}", file.display())
            }
            Self::Syntax { origin, message } => {
                write!(f, "{origin}: not valid TOML: {message}")
            }
            Self::Field {
                origin,
                field,
                reason,
            } => write!(f, "{origin}: field `{field}`: {reason}"),
            Self::Table(t) => write!(
                f,
                "{}: field `{}`: {}:{}:{} (column `{}`): {}",
                t.origin, t.field, t.file, t.line, t.column.0, t.column.1, t.reason
            ),
        }
    }
}

impl std::error::Error for ScenarioError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Read { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Any error of the simulator program.
#[derive(Debug)]
pub enum SimError {
    /// The scenario is not usable.
    Scenario(ScenarioError),
    /// The core refused a value while setting up a run (what was being built, and why).
    Setup {
        /// What was being built.
        what: String,
        /// The core's precondition error.
        source: Precondition,
    },
    /// The scenario is not usable with one seed of a sweep (its world or
    /// path cannot be built from that seed).
    AtSeed {
        /// The seed.
        seed: u64,
        /// Why.
        source: ScenarioError,
    },
    /// Writing an output file failed.
    Write {
        /// The file.
        file: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Scenario(e) => e.fmt(f),
            Self::Setup { what, source } => write!(f, "cannot set up {what}: {source}"),
            Self::AtSeed { seed, source } => write!(f, "seed {seed}: {source}"),
            Self::Write { file, source } => {
                write!(f, "cannot write `{}`: {source}", file.display())
            }
        }
    }
}

impl std::error::Error for SimError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Scenario(e) => Some(e),
            Self::Setup { source, .. } => Some(source),
            Self::AtSeed { source, .. } => Some(source),
            Self::Write { source, .. } => Some(source),
        }
    }
}

impl From<ScenarioError> for SimError {
    fn from(e: ScenarioError) -> Self {
        Self::Scenario(e)
    }
}
