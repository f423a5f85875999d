//! Reading planar problem files strictly (docs/semantics.md §13.10): the TOML document is
//! parsed once, the `--set` overrides are put into it, its shape is checked, the planar keys
//! are taken out of `[robot]` and `[controller]` so that what is left reads as a problem's
//! robot and controller (the same types, the same messages), and the whole is validated.

use std::path::Path;

use serde::Deserialize;
use toml::de::{DeTable, DeValue};

use crate::core::model::document::parse_error;
use crate::core::model::read::{check_key_types, parse_overrides, read_file};
use crate::core::model::{Controller, ProblemError, Robot};
use crate::core::planar::fields::{Planar, obstacles, planar_keys};
use crate::core::planar::file::PlanarProblem;
use crate::core::planar::keys::resolve;
use crate::core::planar::shape::check;
use crate::core::scene::origin::Source;

/// What a planar file shares with a problem, once the planar keys are taken out.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Head {
    name: String,
    robot: Robot,
    controller: Controller,
}

impl PlanarProblem {
    /// Whether `text` is a planar problem file: TOML with a top-level `[plane]` table.
    pub fn is_planar(text: &str) -> bool {
        text.parse::<toml::Table>()
            .is_ok_and(|t| t.contains_key("plane"))
    }

    /// Reads and validates a planar problem from TOML `text`; `origin` (usually the path)
    /// names the text in errors.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<PlanarProblem, ProblemError> {
        Self::from_toml_str_with_overrides(text, origin, &[])
    }

    /// Reads and validates the planar problem file at `path`.
    pub fn load(path: &Path) -> Result<PlanarProblem, ProblemError> {
        Self::load_with_overrides(path, &[])
    }

    /// Reads the planar problem file at `path`, applies `sets` in order, then validates the
    /// result. Each set is `dotted.key=value` with a TOML value (strings may be bare), as for
    /// problems: a `[robot]`, `[controller]`, `[plane]` or `[sensing]` key, or an obstacle's
    /// by its 0-based index (`obstacle.1.max_speed=1.2`, `robot.path=[[0,0],[5,0]]`). Errors
    /// in an override name the override as their origin.
    pub fn load_with_overrides(
        path: &Path,
        sets: &[String],
    ) -> Result<PlanarProblem, ProblemError> {
        let (text, origin) = read_file(path)?;
        Self::from_toml_str_with_overrides(&text, &origin, sets)
    }

    /// The file's `text` as a TOML table with the overrides `sets` applied in place, as
    /// the reader applies them (an obstacle's key by its index): what a problem with
    /// overrides states, for writing it back (the Python package's `to_json`). Only the
    /// overrides are checked here, not the problem; errors are the reader's.
    pub fn stated_table(
        text: &str,
        origin: &str,
        sets: &[String],
    ) -> Result<toml::Table, ProblemError> {
        let (overrides, _) = parse_overrides(sets, resolve)?;
        let doc = DeTable::parse(text).map_err(|e| parse_error(origin, text, None, e))?;
        let doc = doc.get_ref();
        let mut root = doc.clone();
        for o in overrides {
            o.apply(&mut root)?;
        }
        toml::Table::deserialize(toml::de::Deserializer::from(toml::Spanned::new(0..0, root)))
            .map_err(|mut e| {
                e.set_input(Some(text));
                parse_error(origin, text, Some(doc), e)
            })
    }

    /// [`PlanarProblem::from_toml_str`] with `--set` overrides, as
    /// [`PlanarProblem::load_with_overrides`].
    pub fn from_toml_str_with_overrides(
        text: &str,
        origin: &str,
        sets: &[String],
    ) -> Result<PlanarProblem, ProblemError> {
        let (overrides, sets) = parse_overrides(sets, resolve)?;
        let doc = DeTable::parse(text).map_err(|e| parse_error(origin, text, None, e))?;
        let doc = doc.get_ref();
        let source = Source {
            text,
            origin,
            doc,
            sets: &sets,
        };
        let mut root = doc.clone();
        for o in overrides {
            o.apply(&mut root)?;
        }
        check(&source, &root)?;
        check_key_types(text, origin, doc)?;
        let Planar {
            direction_tolerance,
            body,
            zone,
            sensing,
        } = planar_keys(&source, &mut root)?;
        let obstacle = root.remove("obstacle").expect("the shape has obstacles");
        let obstacles = obstacles(&source, &obstacle)?;
        let head = Head::deserialize(toml::de::Deserializer::from(toml::Spanned::new(0..0, root)))
            .map_err(|mut e| {
                e.set_input(Some(text));
                parse_error(origin, text, Some(doc), e)
            })?;
        let problem = PlanarProblem {
            name: head.name,
            direction_tolerance,
            robot: head.robot,
            body,
            controller: head.controller,
            zone,
            sensing,
            obstacles,
        };
        if let Some(v) = problem.violation() {
            let shown = problem.show_key(v.key);
            return Err(source.invalid(v.key, shown, v.value, v.reason));
        }
        Ok(problem)
    }
}

/// Removes table `table`'s key `field` from `root`, if both are there.
pub(crate) fn take<'s>(
    root: &mut DeTable<'s>,
    table: &str,
    field: &str,
) -> Option<toml::Spanned<DeValue<'s>>> {
    match root.get_mut(table)?.get_mut() {
        DeValue::Table(t) => t.remove(field),
        _ => None,
    }
}
