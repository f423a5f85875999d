//! Reading a scene's own values out of the document, key by key and typed: the robot's goal
//! and sensing range, the controller's lane-change settings, the lanes and the obstacles. A
//! value of the wrong type, an unknown or a missing key is an error naming the key (with the
//! obstacle's index and name) and the line.

use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeTable, DeValue, ValueDeserializer};

use crate::core::model::ProblemError;
use crate::core::model::error::with_article;
use crate::core::model::keys::KeySpec;
use crate::core::scene::keys::{
    GOAL, LANE, LANE_CHANGE, LANE_CHANGE_PERIODS, LANE_CHANGE_REAR_GAP, LANES, MAX_SPEED, NAME,
    OBSTACLE_KEYS, POSITION, SENSING_RANGE, STATIC, SceneKey, default_name, obstacle_label,
};
use crate::core::scene::origin::Source;
use crate::core::scene::validate::lane_change_key_violation;
use crate::core::scene::{LaneChange, Obstacle, Position};

/// The scene's keys in `[robot]` and `[controller]`, as read.
pub(crate) struct Extras {
    /// `robot.goal`.
    pub(crate) goal: Option<f64>,
    /// `robot.sensing_range`.
    pub(crate) sensing_range: Option<f64>,
    /// The lane change, when `controller.lane_change = true`.
    pub(crate) lane_change: Option<LaneChange>,
}

/// The value at `key` (described by `spec`) read as a `T`; `shown` names it in errors.
pub(crate) fn typed<T: DeserializeOwned>(
    source: &Source<'_>,
    spec: &KeySpec,
    key: SceneKey,
    shown: &str,
    value: &Spanned<DeValue<'_>>,
) -> Result<T, ProblemError> {
    let wrong = |reason: String| {
        let (origin, location) = source.place(key);
        ProblemError::Invalid {
            origin,
            key: shown.to_string(),
            value: source.written(value.span()),
            reason,
            location,
        }
    };
    spec.check(value.clone()).map_err(wrong)?;
    T::deserialize(ValueDeserializer::from(value.clone()))
        .map_err(|e| wrong(e.message().trim_end().to_string()))
}

/// Takes the scene's keys out of the `[robot]` and `[controller]` tables of `root` (so that
/// what is left reads as a problem's robot and controller) and reads them.
///
/// `lane_change_periods` and `lane_change_rear_gap` are required when `lane_change = true`;
/// without it they are still checked (type and range) and then ignored, so a lane change can
/// be switched off with one `--set controller.lane_change=false`.
pub(crate) fn take_extras(
    source: &Source<'_>,
    root: &mut DeTable<'_>,
) -> Result<Extras, ProblemError> {
    let mut take = |spec: &'static KeySpec| -> Option<Spanned<DeValue<'_>>> {
        let (table, field) = spec.key.split_once('.')?;
        match root.get_mut(table)?.get_mut() {
            DeValue::Table(t) => t.remove(field),
            _ => None,
        }
    };
    let goal = take(&GOAL);
    let sensing_range = take(&SENSING_RANGE);
    let lane_change = take(&LANE_CHANGE);
    let periods = take(&LANE_CHANGE_PERIODS);
    let rear_gap = take(&LANE_CHANGE_REAR_GAP);
    let read = |spec: &'static KeySpec, value: Option<Spanned<DeValue<'_>>>| {
        value
            .map(|v| typed::<f64>(source, spec, SceneKey::Plain(spec.key), spec.key, &v))
            .transpose()
    };
    let goal = read(&GOAL, goal)?;
    let sensing_range = read(&SENSING_RANGE, sensing_range)?;
    let on = lane_change
        .map(|v| {
            typed::<bool>(
                source,
                &LANE_CHANGE,
                SceneKey::Plain(LANE_CHANGE.key),
                LANE_CHANGE.key,
                &v,
            )
        })
        .transpose()?
        .unwrap_or(false);
    let periods = periods
        .map(|v| {
            let key = SceneKey::Plain(LANE_CHANGE_PERIODS.key);
            typed::<u32>(
                source,
                &LANE_CHANGE_PERIODS,
                key,
                LANE_CHANGE_PERIODS.key,
                &v,
            )
        })
        .transpose()?;
    let rear_gap = read(&LANE_CHANGE_REAR_GAP, rear_gap)?;
    if !on {
        let partial = LaneChange {
            periods: periods.unwrap_or(1),
            rear_gap: rear_gap.unwrap_or(0.0),
        };
        if let Some(v) = lane_change_key_violation(&partial) {
            return Err(source.invalid(v.key, v.key.show(""), v.value, v.reason));
        }
        return Ok(Extras {
            goal,
            sensing_range,
            lane_change: None,
        });
    }
    let missing = |spec: &KeySpec, what: &str| {
        source.shape(
            SceneKey::Plain(LANE_CHANGE.key),
            spec.key.to_string(),
            format!("missing: required when controller.lane_change = true ({what})"),
        )
    };
    let periods = periods.ok_or_else(|| {
        missing(
            &LANE_CHANGE_PERIODS,
            "how many whole control periods a lane change lasts, >= 1",
        )
    })?;
    let rear_gap = rear_gap.ok_or_else(|| {
        missing(
            &LANE_CHANGE_REAR_GAP,
            "how far behind the robot (m) an obstacle still keeps a lane occupied, >= 0",
        )
    })?;
    Ok(Extras {
        goal,
        sensing_range,
        lane_change: Some(LaneChange { periods, rear_gap }),
    })
}

/// The lanes of the `[scene]` table `scene` (default `[0]`), in the file's order.
pub(crate) fn lanes(
    source: &Source<'_>,
    scene: Option<&Spanned<DeValue<'_>>>,
) -> Result<Vec<i32>, ProblemError> {
    let Some(scene) = scene else {
        return Ok(vec![0]);
    };
    let DeValue::Table(table) = scene.get_ref() else {
        return Err(source.shape(
            SceneKey::Plain("scene"),
            "scene".into(),
            format!(
                "must be a table ([scene] with lanes = [...]), not {}",
                with_article(scene.get_ref().type_str())
            ),
        ));
    };
    match table.get("lanes") {
        None => Ok(vec![0]),
        Some(v) => typed(source, &LANES, SceneKey::Plain(LANES.key), LANES.key, v),
    }
}

/// The obstacles in the `obstacle` value (an array of tables), in the file's order.
pub(crate) fn obstacles(
    source: &Source<'_>,
    value: &Spanned<DeValue<'_>>,
) -> Result<Vec<Obstacle>, ProblemError> {
    obstacle_tables(source, value, OBSTACLE_KEYS, |index, table, name| {
        obstacle(source, index, table, name)
    })
}

/// Each `[[obstacle]]` table of the `obstacle` value read by `read` (given its index, its
/// table and its name), in the file's order: a table each, its name read first (every
/// other error names the obstacle by it; default `obstacle-<index>`), then no key outside
/// `keys`. Scenes and planar problems share it.
pub(crate) fn obstacle_tables<T>(
    source: &Source<'_>,
    value: &Spanned<DeValue<'_>>,
    keys: &[&'static KeySpec],
    read: impl Fn(usize, &DeTable<'_>, String) -> Result<T, ProblemError>,
) -> Result<Vec<T>, ProblemError> {
    let DeValue::Array(items) = value.get_ref() else {
        return Err(source.shape(
            SceneKey::Plain("obstacle"),
            "obstacle".into(),
            format!(
                "must be [[obstacle]] tables, not {}",
                with_article(value.get_ref().type_str())
            ),
        ));
    };
    let known: Vec<&str> = keys.iter().map(|s| s.key).collect();
    let mut out = Vec::with_capacity(items.len());
    for (index, item) in items.iter().enumerate() {
        let DeValue::Table(table) = item.get_ref() else {
            return Err(ProblemError::Shape {
                origin: source.origin.to_string(),
                key: format!("obstacle[{index}]"),
                reason: format!(
                    "must be a table ([[obstacle]]), not {}",
                    with_article(item.get_ref().type_str())
                ),
                location: source.location(item.span()),
            });
        };
        let mut name = default_name(index);
        if let Some(v) = table.get(NAME.key) {
            let key = SceneKey::Obstacle(index, NAME.key);
            name = typed(source, &NAME, key, &key.show(&name), v)?;
        }
        if let Some((key, _)) = table
            .iter()
            .find(|(k, _)| !known.contains(&k.get_ref().as_ref()))
        {
            return Err(ProblemError::Shape {
                origin: source.origin.to_string(),
                key: format!("{}.{}", obstacle_label(index, &name), key.get_ref()),
                reason: format!("unknown key; an obstacle has {}", known.join(", ")),
                location: source.location(key.span()),
            });
        }
        out.push(read(index, table, name)?);
    }
    Ok(out)
}

/// The scene obstacle at `index`, from its table (its name already read).
fn obstacle(
    source: &Source<'_>,
    index: usize,
    table: &DeTable<'_>,
    name: String,
) -> Result<Obstacle, ProblemError> {
    let shown = |field: &'static str| SceneKey::Obstacle(index, field).show(&name);
    let required = |spec: &'static KeySpec, what: &str| match table.get(spec.key) {
        Some(v) => Ok(v),
        None => Err(source.shape(
            SceneKey::Obstacle(index, spec.key),
            shown(spec.key),
            format!("missing: every obstacle needs {what}"),
        )),
    };
    let field = |spec: &'static KeySpec| SceneKey::Obstacle(index, spec.key);
    let lane = required(&LANE, "its lane (a whole number listed in scene.lanes)")?;
    let lane: i32 = typed(source, &LANE, field(&LANE), &shown(LANE.key), lane)?;
    let position = required(
        &POSITION,
        "its initial x (m): a number, or a range [min, max]",
    )?;
    let position: Position = typed(
        source,
        &POSITION,
        field(&POSITION),
        &shown(POSITION.key),
        position,
    )?;
    let max_speed = required(&MAX_SPEED, "its speed bound (m/s), >= 0")?;
    let max_speed: f64 = typed(
        source,
        &MAX_SPEED,
        field(&MAX_SPEED),
        &shown(MAX_SPEED.key),
        max_speed,
    )?;
    let is_static = match table.get(STATIC.key) {
        Some(v) => typed(source, &STATIC, field(&STATIC), &shown(STATIC.key), v)?,
        None => false,
    };
    Ok(Obstacle {
        name,
        lane,
        position,
        max_speed,
        is_static,
    })
}
