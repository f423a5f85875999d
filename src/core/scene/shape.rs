//! The shape of a scene file: which tables and keys it may have, and its two forms — a
//! single-obstacle problem (`[environment]`) or a scene (`[scene]`, `[[obstacle]]`), never
//! both, and a scene with at least one obstacle.

use toml::de::{DeTable, DeValue};

use crate::core::model::ProblemError;
use crate::core::scene::keys::{SCENE_TABLES, SceneKey, keys_of};
use crate::core::scene::origin::Source;

/// Which form a file has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Form {
    /// `[environment]`: one moving obstacle in lane 0, read as a problem.
    Problem,
    /// `[scene]` and `[[obstacle]]`.
    Scene,
}

/// The keys a scene file has at its top level, as listed in messages.
const TOP: &str = "name, [robot], [controller], [sensing], [scene], [[obstacle]] \
                   (or [environment] for a single obstacle)";

/// Checks that `root` (the document with the overrides applied) has only known keys outside
/// its obstacles, and tells its form.
pub(crate) fn check(source: &Source<'_>, root: &DeTable<'_>) -> Result<Form, ProblemError> {
    unknown_keys(source, root)?;
    let has = |k: &str| root.contains_key(k);
    let environment = has("environment");
    let scene = has("scene") || has("obstacle");
    if environment && scene {
        let scene_part = if has("obstacle") {
            "[[obstacle]]"
        } else {
            "[scene]"
        };
        // Blame the part an override added, if one did; else the file's [environment].
        let from_set = [
            ("environment", source.set_in("environment")),
            ("scene", source.set_in("scene")),
            ("obstacle", source.set_in("obstacle")),
        ]
        .into_iter()
        .find_map(|(table, set)| set.filter(|_| !source.doc.contains_key(table)));
        let reason = format!(
            "a file is either a single-obstacle problem ([environment]) or a scene ([scene] and \
             [[obstacle]]), not both; this one has [environment] and {scene_part}"
        );
        return Err(match from_set {
            Some(set) => ProblemError::Shape {
                origin: set.to_string(),
                key: "environment".into(),
                reason,
                location: None,
            },
            None => source.shape(SceneKey::Plain("environment"), "environment".into(), reason),
        });
    }
    if environment {
        return Ok(Form::Problem);
    }
    if !has_obstacles(root) {
        return Err(ProblemError::Shape {
            origin: source.origin.to_string(),
            key: "obstacle".into(),
            reason: "a scene needs at least one [[obstacle]] (or, for a single obstacle, an \
                     [environment] table)"
                .into(),
            location: None,
        });
    }
    Ok(Form::Scene)
}

/// Whether `root` has an `obstacle` value other than an empty array (a value that is not an
/// array of tables is the obstacle reader's error).
pub(crate) fn has_obstacles(root: &DeTable<'_>) -> bool {
    match root.get("obstacle").map(|v| v.get_ref()) {
        None => false,
        Some(DeValue::Array(items)) => !items.is_empty(),
        Some(_) => true,
    }
}

/// The first key outside the obstacles that a scene file does not have.
fn unknown_keys(source: &Source<'_>, root: &DeTable<'_>) -> Result<(), ProblemError> {
    let unknown = |key: String, span, reason: String| ProblemError::Shape {
        origin: source.origin.to_string(),
        key,
        reason,
        location: source.location(span),
    };
    for (k, v) in root.iter() {
        let name = k.get_ref().as_ref();
        if name == "name" || name == "obstacle" {
            continue;
        }
        if !SCENE_TABLES.contains(&name) {
            return Err(unknown(
                name.to_string(),
                k.span(),
                format!("unknown key; a scene file has {TOP}"),
            ));
        }
        // A table that is not a table is the reader's error, in its own words.
        let DeValue::Table(table) = v.get_ref() else {
            continue;
        };
        let known = keys_of(name);
        if let Some((key, _)) = table
            .iter()
            .find(|(key, _)| !known.contains(&key.get_ref().as_ref()))
        {
            return Err(unknown(
                format!("{name}.{}", key.get_ref()),
                key.span(),
                format!("unknown key; [{name}] has {}", known.join(", ")),
            ));
        }
    }
    Ok(())
}
