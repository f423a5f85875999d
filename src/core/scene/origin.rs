//! Where a scene's value came from — the file, at a line, or a `--set` flag — so that every
//! error names it.

use std::ops::Range;

use toml::de::DeTable;

use crate::core::model::document::span_at;
use crate::core::model::{Location, ProblemError};
use crate::core::scene::keys::SceneKey;

/// The text of a scene file, its parsed document and the overrides applied to it.
pub(crate) struct Source<'a> {
    /// The file's text.
    pub(crate) text: &'a str,
    /// The file's name in errors (usually its path).
    pub(crate) origin: &'a str,
    /// The document as the file has it, without overrides.
    pub(crate) doc: &'a DeTable<'a>,
    /// The overrides, in order: dotted key and the `--set key=value` that set it.
    pub(crate) sets: &'a [(String, String)],
}

impl Source<'_> {
    /// The last `--set` of the dotted `key`, if any.
    pub(crate) fn set_of(&self, key: &str) -> Option<&str> {
        self.sets
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, set)| set.as_str())
    }

    /// The last `--set` of a key in `table` (`scene`, `obstacle`), if any.
    pub(crate) fn set_in(&self, table: &str) -> Option<&str> {
        self.sets
            .iter()
            .rev()
            .find(|(k, _)| k.split('.').next() == Some(table))
            .map(|(_, set)| set.as_str())
    }

    /// Where the byte range `span` of the file is.
    pub(crate) fn location(&self, span: Range<usize>) -> Option<Box<Location>> {
        Location::of_span(self.text, span).map(Box::new)
    }

    /// The origin and location of the value at `key`: the `--set` that set it, or the file
    /// with the value's place in it (or, for an obstacle key the file leaves out, the
    /// obstacle's `[[obstacle]]` header).
    pub(crate) fn place(&self, key: SceneKey) -> (String, Option<Box<Location>>) {
        if let Some(set) = self.set_of(&key.dotted()) {
            return (set.to_string(), None);
        }
        let path = key.path();
        let span = span_at(self.doc, &path).or_else(|| match key {
            SceneKey::Obstacle(..) => span_at(self.doc, &path[..2]),
            SceneKey::Plain(_) => None,
        });
        (self.origin.to_string(), span.and_then(|s| self.location(s)))
    }

    /// A value of `key` (named `shown` in the message) that is not allowed.
    pub(crate) fn invalid(
        &self,
        key: SceneKey,
        shown: String,
        value: String,
        reason: String,
    ) -> ProblemError {
        let (origin, location) = self.place(key);
        ProblemError::Invalid {
            origin,
            key: shown,
            value,
            reason,
            location,
        }
    }

    /// A key (named `shown`) the file's shape does not allow, or lacks.
    pub(crate) fn shape(&self, key: SceneKey, shown: String, reason: String) -> ProblemError {
        let (origin, location) = self.place(key);
        ProblemError::Shape {
            origin,
            key: shown,
            reason,
            location,
        }
    }

    /// The file's text at `span` (a value as written), or `?` if the span is not in it.
    pub(crate) fn written(&self, span: Range<usize>) -> String {
        self.text.get(span).unwrap_or("?").to_string()
    }
}
