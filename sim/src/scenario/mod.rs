//! Scenarios: TOML files with a documented schema (`sim/scenarios/README.md`),
//! built-in ones embedded in the binary, and their validation into a [`Setup`].
//!
//! A missing, unknown, mistyped or out-of-range field is a
//! [`ScenarioError::Field`] naming it as `section.field`.

pub mod check;
pub mod reference;
pub mod schema;
pub mod setup;
pub mod table;

use std::path::{Path, PathBuf};

pub use schema::ScenarioFile;
pub use setup::{build, Setup};

use crate::error::ScenarioError;
use crate::rng::SimRng;

/// The built-in scenarios: `(name, TOML text)`, embedded at compile time.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "path-tracking",
        include_str!("../../scenarios/path-tracking.toml"),
    ),
    (
        "path-tracking-no-compensation",
        include_str!("../../scenarios/path-tracking-no-compensation.toml"),
    ),
    (
        "furrow-pursuing",
        include_str!("../../scenarios/furrow-pursuing.toml"),
    ),
    (
        "hedge-following",
        include_str!("../../scenarios/hedge-following.toml"),
    ),
    (
        "exp1-hedge",
        include_str!("../../scenarios/exp1-hedge.toml"),
    ),
    (
        "exp1-hedge-maize",
        include_str!("../../scenarios/exp1-hedge-maize.toml"),
    ),
    ("exp2-acre", include_str!("../../scenarios/exp2-acre.toml")),
    (
        "exp2-acre-no-plan",
        include_str!("../../scenarios/exp2-acre-no-plan.toml"),
    ),
    (
        "exp3-acre-curved",
        include_str!("../../scenarios/exp3-acre-curved.toml"),
    ),
    (
        "gnss-outage",
        include_str!("../../scenarios/gnss-outage.toml"),
    ),
    (
        "tracking-v0_3-offset",
        include_str!("../../scenarios/tracking-v0_3-offset.toml"),
    ),
    (
        "tracking-v1-offset",
        include_str!("../../scenarios/tracking-v1-offset.toml"),
    ),
    (
        "tracking-v2-offset",
        include_str!("../../scenarios/tracking-v2-offset.toml"),
    ),
    (
        "tracking-v3-offset",
        include_str!("../../scenarios/tracking-v3-offset.toml"),
    ),
    (
        "tracking-v0_3-heading",
        include_str!("../../scenarios/tracking-v0_3-heading.toml"),
    ),
    (
        "tracking-v1-heading",
        include_str!("../../scenarios/tracking-v1-heading.toml"),
    ),
    (
        "tracking-v2-heading",
        include_str!("../../scenarios/tracking-v2-heading.toml"),
    ),
    (
        "tracking-v3-heading",
        include_str!("../../scenarios/tracking-v3-heading.toml"),
    ),
    (
        "tracking-sbend-v1_5",
        include_str!("../../scenarios/tracking-sbend-v1_5.toml"),
    ),
    (
        "tracking-sbend-v3",
        include_str!("../../scenarios/tracking-sbend-v3.toml"),
    ),
    (
        "tracking-uturn",
        include_str!("../../scenarios/tracking-uturn.toml"),
    ),
    (
        "tracking-slip",
        include_str!("../../scenarios/tracking-slip.toml"),
    ),
    (
        "tracking-lag-2s",
        include_str!("../../scenarios/tracking-lag-2s.toml"),
    ),
];

/// The names of the built-in scenarios.
#[must_use]
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN.iter().map(|(name, _)| *name).collect()
}

/// The text of a scenario and where it came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Source {
    /// Built-in name or file path, for messages.
    pub origin: String,
    /// The TOML text.
    pub text: String,
    /// Folder of the file (to resolve a waypoint CSV); `None` for a built-in.
    pub base_dir: Option<PathBuf>,
}

impl Source {
    /// The built-in scenario `name`, if there is one.
    #[must_use]
    pub fn builtin(name: &str) -> Option<Self> {
        BUILTIN
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(n, text)| Self {
                origin: format!("built-in scenario `{n}`"),
                text: (*text).to_owned(),
                base_dir: None,
            })
    }

    /// The scenario file at `path`.
    pub fn file(path: &Path) -> Result<Self, ScenarioError> {
        let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Read {
            file: path.to_path_buf(),
            source,
        })?;
        Ok(Self {
            origin: path.display().to_string(),
            text,
            base_dir: Some(
                path.parent()
                    .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
            ),
        })
    }

    /// A built-in name, else a file path. Something that exists but cannot be
    /// read (a folder, no permission) or that is written as a path
    /// (`dir/x.toml`) gives the operating system's reason; otherwise the
    /// error lists the built-ins and suggests the closest one.
    pub fn resolve(name_or_path: &str) -> Result<Self, ScenarioError> {
        if let Some(s) = Self::builtin(name_or_path) {
            return Ok(s);
        }
        let path = Path::new(name_or_path);
        let looks_like_a_path = path.extension().is_some() || path.components().count() > 1;
        if path.exists() || looks_like_a_path {
            Self::file(path)
        } else {
            Err(ScenarioError::NotFound {
                requested: name_or_path.to_owned(),
                builtins: builtin_names(),
                suggestion: closest_builtin(name_or_path),
            })
        }
    }

    /// Parses the text; errors name the field (`vehicle.wheelbase_m`).
    pub fn parse(&self) -> Result<ScenarioFile, ScenarioError> {
        parse(&self.text, &self.origin)
    }

    /// Parses and validates, drawing the path's recording noise from `rng`.
    pub fn setup(&self, rng: &mut SimRng) -> Result<Setup, ScenarioError> {
        let file = self.parse()?;
        build(&file, &self.origin, self.base_dir.as_deref(), rng)
    }
}

/// The built-in name nearest to `requested` in edits (insertions, deletions,
/// substitutions of one character), when at most a third of its length.
fn closest_builtin(requested: &str) -> Option<&'static str> {
    BUILTIN
        .iter()
        .map(|(name, _)| (strsim::levenshtein(requested, name), *name))
        .filter(|(d, name)| *d <= (name.len() / 3).max(1))
        .min_by_key(|(d, _)| *d)
        .map(|(_, name)| name)
}

/// Parses scenario TOML `text` (`origin` names it in messages).
pub fn parse(text: &str, origin: &str) -> Result<ScenarioFile, ScenarioError> {
    parse_as(text, origin)
}

/// Parses TOML `text` as a `T` (`origin` names it in messages); errors name
/// the field (`vehicle.wheelbase_m`), its line and column.
pub fn parse_as<T: serde::de::DeserializeOwned>(
    text: &str,
    origin: &str,
) -> Result<T, ScenarioError> {
    let de = toml::Deserializer::parse(text).map_err(|e| ScenarioError::Syntax {
        origin: origin.to_owned(),
        message: e.to_string(),
    })?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let at = e.path().to_string();
        let inner = e.inner();
        let message = inner.message().trim();
        let place = inner.span().map_or_else(String::new, |span| {
            format!(" ({})", line_column(text, span.start))
        });
        ScenarioError::Field {
            origin: origin.to_owned(),
            field: field_of(&at, message),
            reason: format!("{message}{place}"),
        }
    })
}

/// "line L, column C" (1-based) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> String {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    format!("line {line}, column {column}")
}

/// The dotted field an error is about: serde names a missing field in the
/// message, relative to the table at `at`. An empty key (`"" = 1`) is
/// spelled `""`, as TOML writes it, so that the field named is never blank.
fn field_of(at: &str, message: &str) -> String {
    let missing = message
        .split("missing field `")
        .nth(1)
        .and_then(|rest| rest.split('`').next());
    match (missing, at) {
        (Some(name), "." | "") => name.to_owned(),
        (Some(name), table) => format!("{table}.{name}"),
        (None, ".") => ".".to_owned(),
        (None, field) => field
            .split('.')
            .map(|key| if key.is_empty() { "\"\"" } else { key })
            .collect::<Vec<_>>()
            .join("."),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_parse_and_carry_their_own_name() {
        for (name, _) in BUILTIN {
            let src = Source::builtin(name).unwrap();
            let file = src.parse().unwrap();
            assert_eq!(file.name, *name);
            let mut rng = SimRng::from_seed(file.seed);
            let setup = src.setup(&mut rng).unwrap();
            assert!(setup.path.length().get() > 10.0);
        }
    }

    #[test]
    fn field_names_for_missing_fields() {
        assert_eq!(
            field_of("vehicle", "missing field `track_m`"),
            "vehicle.track_m"
        );
        assert_eq!(field_of(".", "missing field `seed`"), "seed");
        assert_eq!(
            field_of("vehicle.wheelbase_m", "invalid type"),
            "vehicle.wheelbase_m"
        );
        assert_eq!(field_of("", "unknown field ``"), "\"\"");
        assert_eq!(field_of("vehicle.", "unknown field ``"), "vehicle.\"\"");
    }

    #[test]
    fn positions_are_one_based() {
        assert_eq!(line_column("a = 1\nbb = x", 11), "line 2, column 6");
        assert_eq!(line_column("a", 0), "line 1, column 1");
    }

    #[test]
    fn unknown_names_list_the_builtins() {
        let e = Source::resolve("no-such-scenario").unwrap_err();
        assert!(e.to_string().contains("path-tracking"));
    }
}
