//! Reading problem files strictly (TOML, unknown keys refused, types checked key by key),
//! `--set` overrides applied to the parsed document, and writing problems back.

use std::borrow::Cow;
use std::ops::Range;
use std::path::Path;

use serde::Deserialize;
use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

use crate::core::model::error::{Location, ProblemError};
use crate::core::model::keys::{KEYS, KeySpec, Kind, TABLES, key_spec};
use crate::core::model::{DangerRule, Problem};

/// One `--set dotted.key=value`, parsed and type-checked.
struct Override<'s> {
    /// `--set dotted.key=value`, the origin of its errors.
    origin: String,
    /// The key's description.
    spec: &'static KeySpec,
    /// The value to put in the document.
    value: Spanned<DeValue<'s>>,
}

impl<'s> Override<'s> {
    fn parse(set: &'s str) -> Result<Override<'s>, ProblemError> {
        let origin = format!("--set {set}");
        let Some((key, text)) = set.split_once('=') else {
            return Err(ProblemError::BadOverride {
                origin,
                key: None,
                reason: "expected dotted.key=value, e.g. environment.obstacle_speed=0.25".into(),
            });
        };
        let (key, text) = (key.trim(), text.trim());
        let Some(spec) = key_spec(key) else {
            return Err(unknown_key(origin, key));
        };
        // Strings may be given bare (`danger_rule=kinematic`, `name=foo`).
        let value =
            if matches!(spec.kind, Kind::Text | Kind::Rule) && !text.starts_with(['"', '\'']) {
                Spanned::new(0..text.len(), DeValue::String(Cow::Borrowed(text)))
            } else {
                DeValue::parse(text).map_err(|e| ProblemError::Invalid {
                    origin: origin.clone(),
                    key: key.to_string(),
                    value: text.to_string(),
                    reason: format!("not a TOML value: {}", e.message().trim_end()),
                    location: None,
                })?
            };
        type_check(spec.kind, value.clone()).map_err(|e| ProblemError::Invalid {
            origin: origin.clone(),
            key: key.to_string(),
            value: text.to_string(),
            reason: e.message().trim_end().to_string(),
            location: None,
        })?;
        Ok(Override {
            origin,
            spec,
            value,
        })
    }

    /// Puts the value into the document, creating its table if the document lacks it.
    fn apply(self, root: &mut DeTable<'s>) {
        let key = |k: &'s str| Spanned::new(0..0, Cow::Borrowed(k));
        match self.spec.key.split_once('.') {
            None => {
                root.insert(key(self.spec.key), self.value);
            }
            Some((table, field)) => match root.get_mut(table) {
                Some(v) => {
                    // A `table` that is not a table is the file's error; leave it to surface.
                    if let DeValue::Table(t) = v.get_mut() {
                        t.insert(key(field), self.value);
                    }
                }
                None => {
                    let mut t = DeTable::new();
                    t.insert(key(field), self.value);
                    root.insert(key(table), Spanned::new(0..0, DeValue::Table(t)));
                }
            },
        }
    }
}

/// Whether `value` deserialises as a value of `kind`, with serde's message if not.
fn type_check(kind: Kind, value: Spanned<DeValue<'_>>) -> Result<(), toml::de::Error> {
    fn check<T: DeserializeOwned>(value: Spanned<DeValue<'_>>) -> Result<(), toml::de::Error> {
        T::deserialize(ValueDeserializer::from(value)).map(drop)
    }
    match kind {
        Kind::Text => check::<String>(value),
        Kind::Number => check::<f64>(value),
        Kind::Count => check::<u32>(value),
        Kind::Rule => check::<DangerRule>(value),
        Kind::Flag => check::<bool>(value),
    }
}

/// The error for a `--set` of a key no problem has (or of a whole table).
fn unknown_key(origin: String, key: &str) -> ProblemError {
    if TABLES.contains(&key) {
        let keys: Vec<&str> = KEYS
            .iter()
            .map(|s| s.key)
            .filter(|k| k.starts_with(&format!("{key}.")))
            .collect();
        return ProblemError::BadOverride {
            origin,
            key: Some(key.to_string()),
            reason: format!(
                "`{key}` is a table; set one of its keys: {}",
                keys.join(", ")
            ),
        };
    }
    let (table, known) = match key.split_once('.') {
        Some((table, _)) if TABLES.contains(&table) => (
            Some(table.to_string()),
            KEYS.iter()
                .filter_map(|s| s.key.strip_prefix(&format!("{table}.")[..]))
                .map(str::to_string)
                .collect(),
        ),
        _ => (
            None,
            KEYS.iter()
                .filter(|s| !s.key.contains('.'))
                .map(|s| s.key.to_string())
                .chain(TABLES.iter().map(|t| format!("{t}.*")))
                .collect(),
        ),
    };
    ProblemError::UnknownKey {
        origin,
        key: key.to_string(),
        table,
        known,
    }
}

/// The span of the value at dotted `key` in `doc`.
fn value_span(doc: &DeTable<'_>, key: &str) -> Option<Range<usize>> {
    let mut table = doc;
    let mut parts = key.split('.').peekable();
    while let Some(part) = parts.next() {
        let value = table.get(part)?;
        if parts.peek().is_none() {
            return Some(value.span());
        }
        match value.get_ref() {
            DeValue::Table(t) => table = t,
            _ => return None,
        }
    }
    None
}

/// The dotted key whose key or value covers byte `pos` of the document, innermost first.
fn key_at(table: &DeTable<'_>, pos: usize, prefix: &str) -> Option<String> {
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
fn parse_error(
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
    ProblemError::Parse {
        origin: origin.to_string(),
        key,
        line,
        message: error.to_string().trim_end().to_string(),
    }
}

impl Problem {
    /// Every key a problem file has, dotted (`robot.braking`), in file order.
    pub fn known_keys() -> impl Iterator<Item = &'static str> {
        KEYS.iter().map(|s| s.key)
    }

    /// Reads and validates a problem from TOML `text`; `origin` (usually the path) names the
    /// text in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Problem, ProblemError> {
        Self::from_toml_str_with_overrides(text, origin, &[])
    }

    /// Reads and validates the problem file at `path`.
    pub fn load(path: &Path) -> Result<Problem, ProblemError> {
        Self::load_with_overrides(path, &[])
    }

    /// Reads the problem file at `path`, applies `sets` (each `dotted.key=value`, the value a
    /// TOML value; strings may be bare: `controller.danger_rule=kinematic`) in order, then
    /// validates the result. Errors in an override name the override as their origin.
    pub fn load_with_overrides(path: &Path, sets: &[String]) -> Result<Problem, ProblemError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| ProblemError::Read {
            origin: origin.clone(),
            source,
        })?;
        Self::from_toml_str_with_overrides(&text, &origin, sets)
    }

    /// [`Problem::from_toml_str`] with `--set` overrides, as [`Problem::load_with_overrides`].
    pub fn from_toml_str_with_overrides(
        text: &str,
        origin: &str,
        sets: &[String],
    ) -> Result<Problem, ProblemError> {
        let overrides = sets
            .iter()
            .map(|s| Override::parse(s))
            .collect::<Result<Vec<_>, _>>()?;
        let doc = DeTable::parse(text).map_err(|e| parse_error(origin, text, None, e))?;
        let mut root = doc.clone();
        let overridden: Vec<(&'static str, String)> = overrides
            .iter()
            .map(|o| (o.spec.key, o.origin.clone()))
            .collect();
        for o in overrides {
            o.apply(root.get_mut());
        }
        let problem =
            Problem::deserialize(toml::de::Deserializer::from(root)).map_err(|mut e| {
                e.set_input(Some(text));
                parse_error(origin, text, Some(doc.get_ref()), e)
            })?;
        if let Some(v) = problem.violation() {
            let from_set = overridden.iter().rev().find(|(k, _)| *k == v.key);
            return Err(match from_set {
                Some((_, set)) => ProblemError::Invalid {
                    origin: set.clone(),
                    key: v.key.to_string(),
                    value: v.value,
                    reason: v.reason,
                    location: None,
                },
                None => ProblemError::Invalid {
                    origin: origin.to_string(),
                    key: v.key.to_string(),
                    value: v.value,
                    reason: v.reason,
                    location: value_span(doc.get_ref(), v.key)
                        .and_then(|s| Location::of_span(text, s))
                        .map(Box::new),
                },
            });
        }
        Ok(problem)
    }

    /// Checks the problem against the model's conditions (finite, in range, positive where
    /// required, a gap larger than the clearance, a horizon of at most a million control
    /// periods); `origin` names the problem in the error.
    pub fn validate(&self, origin: &str) -> Result<(), ProblemError> {
        match self.violation() {
            None => Ok(()),
            Some(v) => Err(ProblemError::Invalid {
                origin: origin.to_string(),
                key: v.key.to_string(),
                value: v.value,
                reason: v.reason,
                location: None,
            }),
        }
    }

    /// The problem as a TOML document that reads back as an equal problem.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(self).expect("a problem always serialises to TOML")
    }

    /// The shipped seed problem (`problems/seed.toml`), for unit tests.
    #[cfg(test)]
    pub(crate) fn shipped_seed() -> Problem {
        Problem::load(Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed.toml"
        )))
        .expect("the shipped seed problem loads")
    }
}
