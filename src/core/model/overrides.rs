//! `--set dotted.key=value` overrides: parsed and type-checked against a key table, then put
//! into the parsed document before it is deserialised, so they pass the same checks as the
//! file. Problems and scenes share this; each says which keys it has ([`Target`]).

use std::borrow::Cow;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::core::model::error::ProblemError;
use crate::core::model::keys::{KeySpec, Kind};

/// One step of a key's path in the document: a table's key or an array's index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum PathStep {
    /// A key of a table.
    Key(&'static str),
    /// An element of an array (of tables: `[[obstacle]]`).
    Index(usize),
}

/// Where an override goes and what its value must be.
#[derive(Clone, Debug)]
pub(crate) struct Target {
    /// The key as the user wrote it, normalised (`obstacle.1.max_speed`).
    pub(crate) dotted: String,
    /// The key's description (type, unit, bound).
    pub(crate) spec: &'static KeySpec,
    /// The path to the value in the document.
    pub(crate) path: Vec<PathStep>,
}

impl Target {
    /// A key of the table `KEYS`-style dotted name `spec.key` (`robot.braking`, `name`).
    pub(crate) fn plain(spec: &'static KeySpec) -> Target {
        Target {
            dotted: spec.key.to_string(),
            spec,
            path: spec.key.split('.').map(PathStep::Key).collect(),
        }
    }
}

/// What `spec`'s key takes, with its unit: "a number in m/s".
fn expected(spec: &KeySpec) -> String {
    match spec.unit {
        "" => spec.kind.expected().to_string(),
        unit if spec.kind == Kind::Count => format!("{} of {unit}", spec.kind.expected()),
        unit => format!("{} in {unit}", spec.kind.expected()),
    }
}

/// One `--set dotted.key=value`, parsed and type-checked.
pub(crate) struct Override<'s> {
    /// `--set dotted.key=value`, the origin of its errors.
    pub(crate) origin: String,
    /// Where it goes.
    pub(crate) target: Target,
    /// The value to put in the document.
    pub(crate) value: Spanned<DeValue<'s>>,
}

impl<'s> Override<'s> {
    /// Parses `set`; `resolve` maps the key (and the override's origin, for its error) to
    /// where it goes, or to the error for a key the document does not have.
    pub(crate) fn parse(
        set: &'s str,
        resolve: impl Fn(&str, &str) -> Result<Target, ProblemError>,
    ) -> Result<Override<'s>, ProblemError> {
        let origin = format!("--set {set}");
        let Some((key, text)) = set.split_once('=') else {
            return Err(ProblemError::BadOverride {
                origin,
                key: None,
                reason: "expected dotted.key=value, e.g. environment.obstacle_speed=0.25".into(),
            });
        };
        let (key, text) = (key.trim(), text.trim());
        let target = resolve(key, &origin)?;
        // Strings may be given bare (`danger_rule=kinematic`, `name=foo`).
        let value = if matches!(target.spec.kind, Kind::Text | Kind::Rule)
            && !text.starts_with(['"', '\''])
        {
            Spanned::new(0..text.len(), DeValue::String(Cow::Borrowed(text)))
        } else {
            // Not a TOML value at all (`fast`, `yes`, a number too large for a float): said
            // as what the key takes.
            DeValue::parse(text).map_err(|_| ProblemError::Invalid {
                origin: origin.clone(),
                key: key.to_string(),
                value: text.to_string(),
                reason: format!("expected {}, got `{text}`", expected(target.spec)),
                location: None,
            })?
        };
        target
            .spec
            .check(value.clone())
            .map_err(|reason| ProblemError::Invalid {
                origin: origin.clone(),
                key: key.to_string(),
                value: text.to_string(),
                reason,
                location: None,
            })?;
        Ok(Override {
            origin,
            target,
            value,
        })
    }

    /// Puts the value into the document, creating the tables on its path that the document
    /// lacks. An index past the end of an array is an error naming the override; a step
    /// through a value of the wrong shape is left alone for the file's own error to surface.
    pub(crate) fn apply(self, root: &mut DeTable<'s>) -> Result<(), ProblemError> {
        let key = |k: &'static str| Spanned::new(0..0, Cow::Borrowed(k));
        let Some((last, steps)) = self.target.path.split_last() else {
            return Ok(());
        };
        let PathStep::Key(field) = *last else {
            return Ok(());
        };
        let mut table = root;
        let mut walked = String::new();
        let mut steps = steps.iter().peekable();
        while let Some(step) = steps.next() {
            let PathStep::Key(name) = *step else {
                return Ok(());
            };
            walked = if walked.is_empty() {
                name.to_string()
            } else {
                format!("{walked}.{name}")
            };
            if let Some(&&PathStep::Index(i)) = steps.peek() {
                steps.next();
                let Some(DeValue::Array(items)) = table.get_mut(name).map(Spanned::get_mut) else {
                    return Err(self.no_such_element(&walked, i, 0));
                };
                let len = items.len();
                match items.get_mut(i).map(Spanned::get_mut) {
                    Some(DeValue::Table(t)) => table = t,
                    Some(_) => return Ok(()),
                    None => return Err(self.no_such_element(&walked, i, len)),
                }
                continue;
            }
            if table.get(name).is_none() {
                table.insert(
                    key(name),
                    Spanned::new(0..0, DeValue::Table(DeTable::new())),
                );
            }
            // A `name` that is not a table is the file's error; leave it to surface.
            match table.get_mut(name).map(Spanned::get_mut) {
                Some(DeValue::Table(t)) => table = t,
                _ => return Ok(()),
            }
        }
        table.insert(key(field), self.value);
        Ok(())
    }

    /// The error for an index past the end of the array at `array` (of `len` elements).
    fn no_such_element(&self, array: &str, index: usize, len: usize) -> ProblemError {
        let has = match len {
            0 => format!("the file has no [[{array}]]"),
            1 => format!("the file has one [[{array}]], index 0"),
            n => format!(
                "the file has {n} [[{array}]] tables, indices 0 to {}",
                n - 1
            ),
        };
        ProblemError::BadOverride {
            origin: self.origin.clone(),
            key: Some(self.target.dotted.clone()),
            reason: format!("there is no {array} {index}: {has}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::model::keys::key_spec;

    fn obstacle_target(index: usize) -> Target {
        Target {
            dotted: format!("obstacle.{index}.lane"),
            spec: key_spec("robot.latency").unwrap(),
            path: vec![
                PathStep::Key("obstacle"),
                PathStep::Index(index),
                PathStep::Key("lane"),
            ],
        }
    }

    fn resolve_obstacle(key: &str, _origin: &str) -> Result<Target, ProblemError> {
        let index = key.split('.').nth(1).unwrap().parse().unwrap();
        Ok(obstacle_target(index))
    }

    #[test]
    fn an_indexed_override_sets_that_element() {
        let text = "[[obstacle]]\nlane = 0\n[[obstacle]]\nlane = 1\n";
        let mut doc = DeTable::parse(text).unwrap().into_inner();
        Override::parse("obstacle.1.lane=7", resolve_obstacle)
            .unwrap()
            .apply(&mut doc)
            .unwrap();
        let lanes: Vec<String> = match doc["obstacle"].get_ref() {
            DeValue::Array(items) => items
                .iter()
                .map(|t| match t.get_ref() {
                    DeValue::Table(t) => t["lane"].get_ref().as_integer().unwrap().to_string(),
                    _ => unreachable!(),
                })
                .collect(),
            _ => unreachable!(),
        };
        assert_eq!(lanes, ["0", "7"]);

        let err = Override::parse("obstacle.2.lane=7", resolve_obstacle)
            .unwrap()
            .apply(&mut doc)
            .unwrap_err();
        assert_eq!(err.origin(), "--set obstacle.2.lane=7");
        assert!(
            err.to_string().ends_with(
                "there is no obstacle 2: the file has 2 [[obstacle]] tables, indices 0 to 1"
            ),
            "{err}"
        );
        let mut empty = DeTable::new();
        let err = Override::parse("obstacle.0.lane=7", resolve_obstacle)
            .unwrap()
            .apply(&mut empty)
            .unwrap_err();
        assert!(
            err.to_string().ends_with("the file has no [[obstacle]]"),
            "{err}"
        );
    }

    #[test]
    fn a_plain_override_creates_its_table() {
        let mut doc = DeTable::new();
        Override::parse("robot.latency=3", |k, _| {
            Ok(Target::plain(key_spec(k).unwrap()))
        })
        .unwrap()
        .apply(&mut doc)
        .unwrap();
        match doc["robot"].get_ref() {
            DeValue::Table(t) => {
                assert_eq!(t["latency"].get_ref().as_integer().unwrap().as_str(), "3")
            }
            _ => panic!("no [robot]"),
        }
    }
}
