//! The shape of a planar problem file: a `[plane]` table that marks it, only known tables and
//! keys outside the obstacles, and at least one `[[obstacle]]`.

use toml::de::{DeTable, DeValue};

use crate::core::model::ProblemError;
use crate::core::model::error::with_article;
use crate::core::planar::keys::{TABLES, keys_of};
use crate::core::scene::keys::SceneKey;
use crate::core::scene::origin::Source;
use crate::core::scene::shape::has_obstacles;

/// The keys a planar file has at its top level, as listed in messages.
const TOP: &str = "name, [plane], [robot], [controller], [sensing], [[obstacle]]";

/// Checks that `root` (the document with the overrides applied) is shaped like a planar
/// problem outside its obstacles.
pub(crate) fn check(source: &Source<'_>, root: &DeTable<'_>) -> Result<(), ProblemError> {
    for (k, v) in root.iter() {
        let name = k.get_ref().as_ref();
        if name == "name" || name == "obstacle" {
            continue;
        }
        let unknown = |key: String, span, reason: String| ProblemError::Shape {
            origin: source.origin.to_string(),
            key,
            reason,
            location: source.location(span),
        };
        if !TABLES.contains(&name) {
            let hint = match name {
                "environment" => {
                    "; a planar file gives its obstacles as [[obstacle]] tables, not [environment]"
                }
                _ => "",
            };
            return Err(unknown(
                name.to_string(),
                k.span(),
                format!("unknown key; a planar problem file has {TOP}{hint}"),
            ));
        }
        let DeValue::Table(table) = v.get_ref() else {
            return Err(source.shape(
                SceneKey::Plain(table_name(name)),
                name.to_string(),
                format!(
                    "must be a table ([{name}]), not {}",
                    with_article(v.get_ref().type_str())
                ),
            ));
        };
        let known = keys_of(name);
        if let Some((key, _)) = table
            .iter()
            .find(|(key, _)| !known.contains(&key.get_ref().as_ref()))
        {
            let has = if known.is_empty() {
                "no keys".to_string()
            } else {
                known.join(", ")
            };
            return Err(unknown(
                format!("{name}.{}", key.get_ref()),
                key.span(),
                format!("unknown key; [{name}] has {has}"),
            ));
        }
    }
    if !root.contains_key("plane") {
        return Err(ProblemError::Shape {
            origin: source.origin.to_string(),
            key: "plane".into(),
            reason: "missing: a planar problem file is marked by a [plane] table (it may be \
                     empty)"
                .into(),
            location: None,
        });
    }
    if !has_obstacles(root) {
        return Err(ProblemError::Shape {
            origin: source.origin.to_string(),
            key: "obstacle".into(),
            reason: "a planar problem needs at least one [[obstacle]]".into(),
            location: None,
        });
    }
    Ok(())
}

/// The table's name as a `'static` key (it is one of [`TABLES`]).
fn table_name(name: &str) -> &'static str {
    TABLES
        .iter()
        .find(|t| **t == name)
        .copied()
        .unwrap_or("plane")
}
