//! The keys a scene file has beyond a problem's: the robot's goal and sensing range, the
//! controller's lane changes, the lanes, and each obstacle's keys; how errors name them
//! (`obstacle[1] ("parked").max_speed`) and where `--set` puts them
//! (`obstacle.1.max_speed`).

use crate::core::model::ProblemError;
use crate::core::model::keys::{Bound, KEYS, KeySpec, Kind, spec};
use crate::core::model::overrides::{PathStep, Target};

/// Largest lane index magnitude accepted: lanes are small integers, and engines add ±1.
pub(crate) const MAX_LANE: i32 = 1_000_000;

/// The destination x (m).
pub(crate) const GOAL: KeySpec = spec("robot.goal", Kind::Number, "m", Bound::Positive);
/// The sensing range R (m).
pub(crate) const SENSING_RANGE: KeySpec =
    spec("robot.sensing_range", Kind::Number, "m", Bound::Positive);
/// Whether the controller may change lanes.
pub(crate) const LANE_CHANGE: KeySpec = spec("controller.lane_change", Kind::Flag, "", Bound::Free);
/// How many whole control periods a lane change lasts (≥ 1).
pub(crate) const LANE_CHANGE_PERIODS: KeySpec = spec(
    "controller.lane_change_periods",
    Kind::Count,
    "control periods",
    Bound::Positive,
);
/// How far behind the robot an obstacle still makes a lane occupied (m).
pub(crate) const LANE_CHANGE_REAR_GAP: KeySpec = spec(
    "controller.lane_change_rear_gap",
    Kind::Number,
    "m",
    Bound::NonNegative,
);
/// The lanes that exist.
pub(crate) const LANES: KeySpec = spec("scene.lanes", Kind::Lanes, "", Bound::Free);

/// The keys a scene adds outside its obstacles, in file order.
pub(crate) const SCENE_KEYS: &[&KeySpec] = &[
    &GOAL,
    &SENSING_RANGE,
    &LANE_CHANGE,
    &LANE_CHANGE_PERIODS,
    &LANE_CHANGE_REAR_GAP,
    &LANES,
];

/// An obstacle's name.
pub(crate) const NAME: KeySpec = spec("name", Kind::Text, "", Bound::Free);
/// An obstacle's lane.
pub(crate) const LANE: KeySpec = spec("lane", Kind::Lane, "", Bound::Free);
/// An obstacle's initial x (m): a number or a range.
pub(crate) const POSITION: KeySpec = spec("position", Kind::Position, "m", Bound::Free);
/// An obstacle's speed bound W_i (m/s).
pub(crate) const MAX_SPEED: KeySpec = spec("max_speed", Kind::Number, "m/s", Bound::NonNegative);
/// Whether an obstacle is known to be static.
pub(crate) const STATIC: KeySpec = spec("static", Kind::Flag, "", Bound::Free);

/// The keys of one `[[obstacle]]`, in file order.
pub(crate) const OBSTACLE_KEYS: &[&KeySpec] = &[&NAME, &LANE, &POSITION, &MAX_SPEED, &STATIC];

/// The tables a scene file may have, and the array of obstacle tables.
pub(crate) const SCENE_TABLES: &[&str] =
    &["robot", "controller", "environment", "sensing", "scene"];

/// A key of a scene: where its value sits and how messages name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SceneKey {
    /// A key outside the obstacles, dotted (`robot.goal`, `scene.lanes`, `name`).
    Plain(&'static str),
    /// Key `field` of the obstacle at `index`.
    Obstacle(usize, &'static str),
}

impl SceneKey {
    /// The key as `--set` writes it: `robot.goal`, `obstacle.1.max_speed`.
    pub(crate) fn dotted(self) -> String {
        match self {
            SceneKey::Plain(key) => key.to_string(),
            SceneKey::Obstacle(i, field) => format!("obstacle.{i}.{field}"),
        }
    }

    /// The path to its value in the document.
    pub(crate) fn path(self) -> Vec<PathStep> {
        match self {
            SceneKey::Plain(key) => key.split('.').map(PathStep::Key).collect(),
            SceneKey::Obstacle(i, field) => vec![
                PathStep::Key("obstacle"),
                PathStep::Index(i),
                PathStep::Key(field),
            ],
        }
    }

    /// The key as messages name it, `name_of` giving obstacle `i`'s name (None: past the
    /// last obstacle, named by its default name).
    pub(crate) fn show_in(self, name_of: impl Fn(usize) -> Option<String>) -> String {
        match self {
            SceneKey::Obstacle(i, _) => self.show(&name_of(i).unwrap_or_else(|| default_name(i))),
            SceneKey::Plain(_) => self.show(""),
        }
    }

    /// The key as messages name it; `name` is the obstacle's name, for an obstacle's key.
    pub(crate) fn show(self, name: &str) -> String {
        match self {
            SceneKey::Plain(key) => key.to_string(),
            SceneKey::Obstacle(i, field) => format!("{}.{field}", obstacle_label(i, name)),
        }
    }
}

/// How messages name the obstacle at `index` called `name`: `obstacle[1] ("parked")`.
pub(crate) fn obstacle_label(index: usize, name: &str) -> String {
    format!("obstacle[{index}] ({name:?})")
}

/// The name of the obstacle at `index` when its table gives none.
pub(crate) fn default_name(index: usize) -> String {
    format!("obstacle-{index}")
}

/// The keys of table `table` (`robot`) of a scene file, without the table's name.
pub(crate) fn keys_of(table: &str) -> Vec<&'static str> {
    let prefix = format!("{table}.");
    KEYS.iter()
        .map(|s| s.key)
        .chain(SCENE_KEYS.iter().map(|s| s.key))
        .filter_map(|k| k.strip_prefix(prefix.as_str()))
        .collect()
}

/// The keys of an obstacle table.
#[cfg(test)]
pub(crate) fn obstacle_keys() -> Vec<&'static str> {
    OBSTACLE_KEYS.iter().map(|s| s.key).collect()
}

/// Where a `--set` of a scene's `key` goes (`obstacle.<index>.<key>` for an obstacle's), or
/// the error for a key no scene has.
pub(crate) fn resolve(key: &str, origin: &str) -> Result<Target, ProblemError> {
    let plain: Vec<&'static KeySpec> = KEYS.iter().chain(SCENE_KEYS.iter().copied()).collect();
    resolve_in(key, origin, &plain, SCENE_TABLES, OBSTACLE_KEYS)
}

/// Where a `--set` of `key` goes in a file whose keys outside the obstacles are `plain`, in
/// the tables `tables`, and whose `[[obstacle]]` tables have the keys `obstacle`; or the
/// error naming the keys the file does have. Scenes and planar problems share it.
pub(crate) fn resolve_in(
    key: &str,
    origin: &str,
    plain: &[&'static KeySpec],
    tables: &[&str],
    obstacle: &[&'static KeySpec],
) -> Result<Target, ProblemError> {
    if let Some(spec) = plain.iter().find(|s| s.key == key) {
        return Ok(Target::plain(spec));
    }
    let keys_of = |table: &str| -> Vec<&'static str> {
        let prefix = format!("{table}.");
        plain
            .iter()
            .filter_map(|s| s.key.strip_prefix(prefix.as_str()))
            .collect()
    };
    let obstacle_keys: Vec<&str> = obstacle.iter().map(|s| s.key).collect();
    let bad = |reason: String| ProblemError::BadOverride {
        origin: origin.to_string(),
        key: Some(key.to_string()),
        reason,
    };
    let one_key = || {
        format!(
            "set one key of one obstacle: obstacle.<index>.<key>, the index counting [[obstacle]] \
             tables from 0 and the key one of {}",
            obstacle_keys.join(", ")
        )
    };
    if key == "obstacle" || key.starts_with("obstacle.") {
        let rest = key.strip_prefix("obstacle.").unwrap_or("");
        let Some((index, field)) = rest.split_once('.') else {
            return Err(bad(one_key()));
        };
        let Ok(index) = index.parse::<usize>() else {
            return Err(bad(format!(
                "`{index}` is not an obstacle index (0, 1, ...); {}",
                one_key()
            )));
        };
        let Some(spec) = obstacle.iter().find(|s| s.key == field) else {
            return Err(ProblemError::UnknownKey {
                origin: origin.to_string(),
                key: key.to_string(),
                table: Some("[obstacle]".into()),
                known: obstacle_keys.iter().map(|k| k.to_string()).collect(),
            });
        };
        return Ok(Target {
            dotted: format!("obstacle.{index}.{field}"),
            spec,
            path: SceneKey::Obstacle(index, spec.key).path(),
        });
    }
    if tables.contains(&key) {
        return Err(bad(format!(
            "`{key}` is a table; set one of its keys: {}",
            keys_of(key)
                .iter()
                .map(|k| format!("{key}.{k}"))
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let (table, known) = match key.split_once('.') {
        Some((table, _)) if tables.contains(&table) => (
            Some(table.to_string()),
            keys_of(table).iter().map(|k| k.to_string()).collect(),
        ),
        _ => (
            None,
            plain
                .iter()
                .filter(|s| !s.key.contains('.'))
                .map(|s| s.key.to_string())
                .chain(tables.iter().map(|t| format!("{t}.*")))
                .chain(["obstacle.<index>.*".to_string()])
                .collect(),
        ),
    };
    Err(ProblemError::UnknownKey {
        origin: origin.to_string(),
        key: key.to_string(),
        table,
        known,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::model::Problem;
    use crate::core::scene::{LaneChange, Scene};

    /// A scene that sets every optional key, so that its file has them all.
    fn full_scene() -> Scene {
        let mut s = Scene::from_problem(&Problem::shipped_seed());
        s.goal = Some(20.0);
        s.sensing_range = Some(3.0);
        s.lane_change = Some(LaneChange {
            periods: 3,
            rear_gap: 0.2,
        });
        s.lanes = vec![0, 1];
        s.robot.braking_min = Some(0.04);
        s.robot.initial_speed = Some(0.1);
        s.sensing = Some(crate::core::model::Sensing {
            gap_noise: Some(0.01),
            speed_noise: Some(0.02),
            first_detection_gap: Some(0.5),
        });
        s
    }

    #[test]
    fn key_tables_match_what_a_scene_file_has() {
        let table: toml::Table = toml::from_str(&full_scene().to_toml_string()).unwrap();
        let mut keys = Vec::new();
        let mut obstacle = Vec::new();
        for (k, v) in &table {
            match v {
                toml::Value::Table(t) => keys.extend(t.keys().map(|f| format!("{k}.{f}"))),
                toml::Value::Array(items) => {
                    obstacle.extend(items[0].as_table().unwrap().keys().cloned())
                }
                _ => keys.push(k.clone()),
            }
        }
        let mut known: Vec<String> = KEYS
            .iter()
            .chain(SCENE_KEYS.iter().copied())
            .map(|s| s.key.to_string())
            .filter(|k| !k.starts_with("environment."))
            .collect();
        keys.sort();
        known.sort();
        assert_eq!(keys, known);
        assert_eq!(obstacle, obstacle_keys());
    }

    #[test]
    fn overrides_resolve_to_their_place() {
        let t = resolve("obstacle.12.max_speed", "--set x").unwrap();
        assert_eq!(t.dotted, "obstacle.12.max_speed");
        assert_eq!(
            t.path,
            [
                PathStep::Key("obstacle"),
                PathStep::Index(12),
                PathStep::Key("max_speed")
            ]
        );
        assert_eq!(t.spec.kind, Kind::Number);
        let t = resolve("scene.lanes", "--set x").unwrap();
        assert_eq!(t.path, [PathStep::Key("scene"), PathStep::Key("lanes")]);
        assert_eq!(
            resolve("robot.braking", "o").unwrap().dotted,
            "robot.braking"
        );
        assert_eq!(
            resolve("environment.initial_gap", "o").unwrap().dotted,
            "environment.initial_gap"
        );
        for bad in [
            "obstacle",
            "obstacle.0",
            "obstacle.-1.lane",
            "obstacle.0.colour",
            "scene",
            "scene.width",
            "colour",
        ] {
            let err = resolve(bad, "--set flag").unwrap_err();
            assert_eq!(err.origin(), "--set flag", "{bad}");
            assert_eq!(err.key(), Some(bad), "{bad}");
        }
    }

    #[test]
    fn keys_are_shown_and_set_by_index_and_name() {
        let k = SceneKey::Obstacle(1, "max_speed");
        assert_eq!(k.show("parked"), "obstacle[1] (\"parked\").max_speed");
        assert_eq!(k.dotted(), "obstacle.1.max_speed");
        let k = SceneKey::Plain("robot.goal");
        assert_eq!(
            (k.show("x"), k.dotted()),
            ("robot.goal".into(), "robot.goal".into())
        );
    }
}
