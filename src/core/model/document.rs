//! The parsed TOML document behind an error: where a key's value sits (for the line and the
//! pointer under a message), which key covers a position, and toml's own errors in those
//! terms.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::core::model::error::{Location, ProblemError};
use crate::core::model::keys::TABLES;
use crate::core::model::overrides::PathStep;

/// The span of the value at dotted `key` in `doc`.
pub(crate) fn value_span(doc: &DeTable<'_>, key: &str) -> Option<Range<usize>> {
    value_at(doc, key).map(Spanned::span)
}

/// The value at dotted `key` in `doc`, if the document has it.
pub(crate) fn value_at<'d, 's>(
    doc: &'d DeTable<'s>,
    key: &str,
) -> Option<&'d Spanned<DeValue<'s>>> {
    let mut table = doc;
    let mut parts = key.split('.').peekable();
    while let Some(part) = parts.next() {
        let value = table.get(part)?;
        if parts.peek().is_none() {
            return Some(value);
        }
        match value.get_ref() {
            DeValue::Table(t) => table = t,
            _ => return None,
        }
    }
    None
}

/// The span of the value at `path` in `doc` (through tables and arrays).
pub(crate) fn span_at(doc: &DeTable<'_>, path: &[PathStep]) -> Option<Range<usize>> {
    let (first, rest) = path.split_first()?;
    let PathStep::Key(first) = *first else {
        return None;
    };
    let mut value = doc.get(first)?;
    for step in rest {
        value = match (step, value.get_ref()) {
            (PathStep::Key(k), DeValue::Table(t)) => t.get(*k)?,
            (PathStep::Index(i), DeValue::Array(items)) => items.get(*i)?,
            _ => return None,
        };
    }
    Some(value.span())
}

/// The dotted key whose key or value covers byte `pos` of the document, innermost first.
pub(crate) fn key_at(table: &DeTable<'_>, pos: usize, prefix: &str) -> Option<String> {
    for (k, v) in table.iter() {
        let path = if prefix.is_empty() {
            k.get_ref().to_string()
        } else {
            format!("{prefix}.{}", k.get_ref())
        };
        if let DeValue::Table(t) = v.get_ref()
            && let Some(inner) = key_at(t, pos, &path)
        {
            return Some(inner);
        }
        if k.span().contains(&pos) || v.span().contains(&pos) {
            return Some(path);
        }
    }
    None
}

/// A toml error as a [`ProblemError::Parse`], with the key it is at when `doc` can tell.
pub(crate) fn parse_error(
    origin: &str,
    text: &str,
    doc: Option<&DeTable<'_>>,
    error: toml::de::Error,
) -> ProblemError {
    let span = error.span();
    let line = span
        .clone()
        .and_then(|s| Location::of_span(text, s))
        .map(|l| l.line);
    let mut key = match (doc, span) {
        (Some(doc), Some(span)) => key_at(doc, span.start, ""),
        _ => None,
    };
    if let Some(missing) = error
        .message()
        .strip_prefix("missing field `")
        .and_then(|m| m.split('`').next())
    {
        key = Some(match key {
            Some(table) if TABLES.contains(&table.as_str()) => format!("{table}.{missing}"),
            _ => missing.to_string(),
        });
    }
    let mut message = error.to_string().trim_end().to_string();
    let mut line = line;
    if error.span().is_none() && error.message().contains("recursion limit") {
        // toml says neither where nor why: name the most deeply nested line.
        let deepest = text
            .lines()
            .enumerate()
            .max_by_key(|(_, l)| l.matches(['.', '[', '{']).count())
            .map_or(1, |(i, _)| i + 1);
        line = Some(deepest);
        message = format!(
            "line {deepest}: nested too deeply for the TOML reader (a key or value with too \
             many parts)"
        );
    }
    ProblemError::Parse {
        origin: origin.to_string(),
        key,
        line,
        message,
    }
}
