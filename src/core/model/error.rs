//! Errors in problem files, in the user's terms: the file or flag, the key, the value, the
//! reason and, where the file has one, the line.

use std::ops::Range;

/// Where a value sits in a problem file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// The whole source line (without its line break).
    pub source_line: String,
    /// How many characters of the line the value covers (at least 1).
    pub width: usize,
}

impl Location {
    /// The location of the byte range `span` of `text`, if it lies inside `text`.
    pub(crate) fn of_span(text: &str, span: Range<usize>) -> Option<Location> {
        let before = text.get(..span.start)?;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[span.start..]
            .find('\n')
            .map_or(text.len(), |i| span.start + i);
        let source_line = text[line_start..line_end]
            .trim_end_matches('\r')
            .to_string();
        let width = text
            .get(span.start..span.end.min(line_end))
            .map_or(1, |s| s.chars().count().max(1));
        Some(Location {
            line: before.matches('\n').count() + 1,
            column: text[line_start..span.start].chars().count() + 1,
            source_line,
            width,
        })
    }
}

/// Renders `location` as a rustc-style pointer under the one-line message.
pub(crate) fn show_location(origin: &str, location: &Option<Box<Location>>) -> String {
    let Some(l) = location else {
        return String::new();
    };
    let gutter = " ".repeat(l.line.to_string().len());
    format!(
        "\n{gutter}--> {origin}:{}:{}\n{gutter} |\n{} | {}\n{gutter} | {}{}",
        l.line,
        l.column,
        l.line,
        l.source_line,
        " ".repeat(l.column - 1),
        "^".repeat(l.width),
    )
}

/// Renders the known keys of an unknown `--set` key's table.
pub(crate) fn show_known(known: &[String]) -> String {
    known.join(", ")
}

/// Why a problem (or a scene) could not be read or is not a valid problem (or scene).
///
/// Every variant names its origin: the file's path, the text's origin given to
/// [`Problem::from_toml_str`](crate::core::model::Problem::from_toml_str), or the offending `--set key=value`. The first line of the
/// message is self-contained; some messages add a pointer into the file below it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProblemError {
    /// The file could not be read (missing, unreadable, not UTF-8).
    #[error("{origin}: cannot read the problem file")]
    Read {
        /// The path.
        origin: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The text is not TOML, or not shaped like a problem (an unknown, missing or mistyped
    /// key). The message is the toml crate's, with line, column and a snippet when it has them.
    #[error("{origin}: {message}")]
    Parse {
        /// The file (or other origin of the text).
        origin: String,
        /// The dotted key the error is at, when known (e.g. `robot.braking` for a missing key).
        key: Option<String>,
        /// 1-based line of the error, when known.
        line: Option<usize>,
        /// The toml crate's message.
        message: String,
    },
    /// A value of the right type that is not allowed: non-finite, out of range, or violating a
    /// condition of the model.
    #[error("{origin}: {key} = {value}: {reason}{}", show_location(.origin, .location))]
    Invalid {
        /// The file, or the `--set key=value` the value came from.
        origin: String,
        /// The dotted key.
        key: String,
        /// The value as read.
        value: String,
        /// Why it is rejected.
        reason: String,
        /// Where the value sits in the file, when it comes from one.
        location: Option<Box<Location>>,
    },
    /// A key where the file's shape has none, or a key or table it lacks or cannot combine
    /// (scene files: an unknown key in an obstacle, a missing lane-change setting, an
    /// `[environment]` beside `[[obstacle]]`).
    #[error("{origin}: {key}: {reason}{}", show_location(.origin, .location))]
    Shape {
        /// The file, or the `--set key=value` that made the shape.
        origin: String,
        /// The key, in the user's terms (`obstacle[1] ("parked").colour`).
        key: String,
        /// What is wrong, and what would be right.
        reason: String,
        /// Where the key sits in the file, when it comes from one.
        location: Option<Box<Location>>,
    },
    /// A `--set` key that no problem has.
    #[error("{origin}: unknown key `{key}`; known keys{}: {}",
        .table.as_ref().map(|t| format!(" of [{t}]")).unwrap_or_default(), show_known(.known))]
    UnknownKey {
        /// The `--set key=value`.
        origin: String,
        /// The key as given.
        key: String,
        /// The table the key was looked up in (`None`: the top level).
        table: Option<String>,
        /// The keys that table does have.
        known: Vec<String>,
    },
    /// A `--set` that is not `dotted.key=value`, or that sets a whole table.
    #[error("{origin}: {reason}")]
    BadOverride {
        /// The `--set` argument.
        origin: String,
        /// The key, if one could be read.
        key: Option<String>,
        /// What is wrong with it.
        reason: String,
    },
}

impl ProblemError {
    /// Where the error comes from: a path, an origin given to [`Problem::from_toml_str`](crate::core::model::Problem::from_toml_str),
    /// or `--set key=value`.
    pub fn origin(&self) -> &str {
        match self {
            ProblemError::Read { origin, .. }
            | ProblemError::Parse { origin, .. }
            | ProblemError::Invalid { origin, .. }
            | ProblemError::Shape { origin, .. }
            | ProblemError::UnknownKey { origin, .. }
            | ProblemError::BadOverride { origin, .. } => origin,
        }
    }

    /// The dotted key the error is about, when known.
    pub fn key(&self) -> Option<&str> {
        match self {
            ProblemError::Read { .. } => None,
            ProblemError::Parse { key, .. } | ProblemError::BadOverride { key, .. } => {
                key.as_deref()
            }
            ProblemError::Invalid { key, .. }
            | ProblemError::Shape { key, .. }
            | ProblemError::UnknownKey { key, .. } => Some(key),
        }
    }

    /// The 1-based line in the file, when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            ProblemError::Parse { line, .. } => *line,
            ProblemError::Invalid { location, .. } | ProblemError::Shape { location, .. } => {
                location.as_ref().map(|l| l.line)
            }
            _ => None,
        }
    }
}

/// A rule of the model a problem breaks.
pub(crate) struct Violation {
    pub(crate) key: &'static str,
    pub(crate) value: String,
    pub(crate) reason: String,
}

/// A number as shown in messages: plain when moderate, in exponent form when huge or tiny.
pub(crate) fn show_number(x: f64) -> String {
    let a = x.abs();
    if a.is_finite() && a != 0.0 && !(1e-6..1e9).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A large count of control periods as shown in messages.
pub(crate) fn show_count(x: f64) -> String {
    if x < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}

pub(crate) fn with_unit(text: String, unit: &str) -> String {
    if unit.is_empty() {
        text
    } else {
        format!("{text} ({unit})")
    }
}

/// `word` with its indefinite article: `a string`, `an integer`.
pub(crate) fn with_article(word: &str) -> String {
    let vowel = word.starts_with(['a', 'e', 'i', 'o', 'u']);
    format!("{} {word}", if vowel { "an" } else { "a" })
}
