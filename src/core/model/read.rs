//! Reading problem files strictly (TOML, unknown keys refused, types checked key by key),
//! `--set` overrides applied to the parsed document, and writing problems back.

use std::path::Path;

use serde::Deserialize;
use toml::de::DeTable;

use crate::core::model::Problem;
use crate::core::model::document::{parse_error, value_at, value_span};
use crate::core::model::error::{Location, ProblemError};
use crate::core::model::keys::{KEYS, TABLES, key_spec};
use crate::core::model::overrides::{Override, Target};

/// Where a `--set` of a problem's `key` goes, or the error for a key no problem has.
fn resolve(key: &str, origin: &str) -> Result<Target, ProblemError> {
    key_spec(key)
        .map(Target::plain)
        .ok_or_else(|| unknown_key(origin.to_string(), key))
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

/// The text of the problem, scene or planar file at `path`, and its name in errors.
pub(crate) fn read_file(path: &Path) -> Result<(String, String), ProblemError> {
    let origin = path.display().to_string();
    let text = crate::core::text_file::read_text(path, crate::core::text_file::MAX_PROBLEM_BYTES)
        .map_err(|source| ProblemError::Read {
        origin: origin.clone(),
        source,
    })?;
    Ok((text, origin))
}

/// Parsed `--set` overrides, and each one's dotted key with its `--set` origin.
pub(crate) type Overrides<'s> = (Vec<Override<'s>>, Vec<(String, String)>);

/// `sets` (each `dotted.key=value`) parsed against `resolve`, and each one's dotted key
/// with its `--set` origin, for errors in the values they set.
pub(crate) fn parse_overrides<'s>(
    sets: &'s [String],
    resolve: impl Fn(&str, &str) -> Result<Target, ProblemError> + Copy,
) -> Result<Overrides<'s>, ProblemError> {
    let overrides = sets
        .iter()
        .map(|s| Override::parse(s, resolve))
        .collect::<Result<Vec<_>, _>>()?;
    let origins = overrides
        .iter()
        .map(|o| (o.target.dotted.clone(), o.origin.clone()))
        .collect();
    Ok((overrides, origins))
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
        let (text, origin) = read_file(path)?;
        Self::from_toml_str_with_overrides(&text, &origin, sets)
    }

    /// [`Problem::from_toml_str`] with `--set` overrides, as [`Problem::load_with_overrides`].
    pub fn from_toml_str_with_overrides(
        text: &str,
        origin: &str,
        sets: &[String],
    ) -> Result<Problem, ProblemError> {
        let (overrides, overridden) = parse_overrides(sets, resolve)?;
        let doc = DeTable::parse(text).map_err(|e| parse_error(origin, text, None, e))?;
        let mut root = doc.clone();
        for o in overrides {
            o.apply(root.get_mut())?;
        }
        problem_from_document(text, origin, doc.get_ref(), root.into_inner(), &overridden)
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

/// Checks the type of every problem key the document `doc` (parsed from `text`) has, so that
/// a wrong one is named by its dotted key in the user's words, with the line (serde would say
/// "invalid type: string, expected f64"). Scene files share the problem's keys.
pub(crate) fn check_key_types(
    text: &str,
    origin: &str,
    doc: &DeTable<'_>,
) -> Result<(), ProblemError> {
    for spec in KEYS {
        let Some(value) = value_at(doc, spec.key) else {
            continue;
        };
        if let Err(reason) = spec.check(value.clone()) {
            let span = value.span();
            return Err(ProblemError::Invalid {
                origin: origin.to_string(),
                key: spec.key.to_string(),
                value: text.get(span.clone()).unwrap_or("?").to_string(),
                reason,
                location: Location::of_span(text, span).map(Box::new),
            });
        }
    }
    Ok(())
}

/// The problem in `root` (the document `doc` parsed from `text`, with the overrides
/// `overridden` — pairs of dotted key and `--set` origin — applied), deserialised and
/// validated. An error in a value an override set names the override; else the file, with the
/// line.
pub(crate) fn problem_from_document(
    text: &str,
    origin: &str,
    doc: &DeTable<'_>,
    root: DeTable<'_>,
    overridden: &[(String, String)],
) -> Result<Problem, ProblemError> {
    check_key_types(text, origin, doc)?;
    let problem =
        Problem::deserialize(toml::de::Deserializer::from(toml::Spanned::new(0..0, root)))
            .map_err(|mut e| {
                e.set_input(Some(text));
                parse_error(origin, text, Some(doc), e)
            })?;
    let Some(v) = problem.violation() else {
        return Ok(problem);
    };
    let from_set = overridden.iter().rev().find(|(k, _)| k == v.key);
    Err(match from_set {
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
            location: value_span(doc, v.key)
                .and_then(|s| Location::of_span(text, s))
                .map(Box::new),
        },
    })
}
