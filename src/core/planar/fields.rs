//! Reading a planar file's own values out of the document, key by key and typed: `[plane]`,
//! the robot's disc and path, the danger zone, `[sensing]` and the obstacles. A value of the
//! wrong type, an unknown or a missing key is an error naming the key (with the obstacle's
//! index and name) and the line.

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::core::model::ProblemError;
use crate::core::model::keys::KeySpec;
use crate::core::planar::file::{
    PlanarObstacleFile, PlanarRobot, PlanarSensingFile, StartFile, Zone,
};
use crate::core::planar::keys::{
    DANGER_ZONE, DIRECTION, DIRECTION_TOLERANCE, FIELD_OF_VIEW, FIRST_DETECTION, MAX_SPEED,
    OBSTACLE_KEYS, PATH, PATH_END, PATH_TOLERANCE, POSITION_NOISE, RADIUS, RANGE, REGION,
    ROBOT_RADIUS, START, START_MAX, START_MIN, STOP_POLYGON, VELOCITY_NOISE,
};
use crate::core::planar::read::take;
use crate::core::scene::fields::{obstacle_tables, typed};
use crate::core::scene::keys::SceneKey;
use crate::core::scene::origin::Source;

/// The planar keys outside the obstacles, as read.
pub(crate) struct Planar {
    /// `plane.direction_tolerance`.
    pub(crate) direction_tolerance: Option<f64>,
    /// The robot's disc and path.
    pub(crate) body: PlanarRobot,
    /// The danger zone.
    pub(crate) zone: Zone,
    /// `[sensing]`.
    pub(crate) sensing: PlanarSensingFile,
}

/// The value of the plain key `spec` read as a `T`.
fn plain<T: serde::de::DeserializeOwned>(
    source: &Source<'_>,
    spec: &'static KeySpec,
    value: Option<Spanned<DeValue<'_>>>,
) -> Result<Option<T>, ProblemError> {
    value
        .map(|v| typed(source, spec, SceneKey::Plain(spec.key), spec.key, &v))
        .transpose()
}

/// One of `choices` for the text key `spec` (None when absent).
fn choice(
    source: &Source<'_>,
    spec: &'static KeySpec,
    value: Option<Spanned<DeValue<'_>>>,
    choices: &[&str],
) -> Result<Option<String>, ProblemError> {
    let Some(text) = plain::<String>(source, spec, value)? else {
        return Ok(None);
    };
    if choices.contains(&text.as_str()) {
        return Ok(Some(text));
    }
    let shown: Vec<String> = choices.iter().map(|c| format!("{c:?}")).collect();
    Err(source.invalid(
        SceneKey::Plain(spec.key),
        spec.key.to_string(),
        format!("{text:?}"),
        format!("must be one of {}", shown.join(", ")),
    ))
}

/// Takes `[plane]`, `[sensing]` and the planar keys of `[robot]` and `[controller]` out of
/// `root` (so that what is left reads as a problem's name, robot and controller) and reads
/// them.
pub(crate) fn planar_keys(
    source: &Source<'_>,
    root: &mut DeTable<'_>,
) -> Result<Planar, ProblemError> {
    let tolerance = take(root, "plane", "direction_tolerance");
    root.remove("plane");
    let direction_tolerance = plain(source, &DIRECTION_TOLERANCE, tolerance)?;
    let radius = take(root, "robot", "radius");
    let path = take(root, "robot", "path");
    let path_end = take(root, "robot", "path_end");
    let path_tolerance = take(root, "robot", "path_tolerance");
    let radius = plain(source, &ROBOT_RADIUS, radius)?.unwrap_or(0.0);
    let path: Option<Vec<[f64; 2]>> = plain(source, &PATH, path)?;
    let path_tolerance = plain(source, &PATH_TOLERANCE, path_tolerance)?.unwrap_or(0.0);
    let end = choice(source, &PATH_END, path_end, &["stop", "continue"])?;
    if end.is_some() && path.is_none() {
        return Err(source.shape(
            SceneKey::Plain(PATH_END.key),
            PATH_END.key.into(),
            "given without robot.path: the default path (the x axis) has no end".into(),
        ));
    }
    let body = PlanarRobot {
        radius,
        stops_at_end: path.is_some() && end.as_deref() != Some("continue"),
        path,
        path_tolerance,
    };
    let zone = take(root, "controller", "danger_zone");
    let polygon = take(root, "controller", "stop_polygon");
    let zone = choice(source, &DANGER_ZONE, zone, &["disc", "polygon"])?;
    let polygon: Option<Vec<[f64; 2]>> = plain(source, &STOP_POLYGON, polygon)?;
    let zone = match (zone.as_deref(), polygon) {
        (Some("polygon"), Some(p)) => Zone::Polygon(p),
        (Some("polygon"), None) => {
            return Err(source.shape(
                SceneKey::Plain(DANGER_ZONE.key),
                STOP_POLYGON.key.into(),
                "missing: required when controller.danger_zone = \"polygon\" (the convex stop \
                 polygon in the robot's frame, [[x, y], ...] in m)"
                    .into(),
            ));
        }
        (_, Some(_)) => {
            return Err(source.shape(
                SceneKey::Plain(STOP_POLYGON.key),
                STOP_POLYGON.key.into(),
                "given without controller.danger_zone = \"polygon\": the disc zone has no \
                 polygon"
                    .into(),
            ));
        }
        (_, None) => Zone::Disc,
    };
    let mut sense = |spec: &'static KeySpec| {
        let field = spec.key.split_once('.').expect("a sensing key").1;
        plain::<f64>(source, spec, take(root, "sensing", field))
    };
    let sensing = PlanarSensingFile {
        position_noise: sense(&POSITION_NOISE)?,
        velocity_noise: sense(&VELOCITY_NOISE)?,
        first_detection: sense(&FIRST_DETECTION)?,
        range: sense(&RANGE)?,
        field_of_view: sense(&FIELD_OF_VIEW)?,
    };
    root.remove("sensing");
    Ok(Planar {
        direction_tolerance,
        body,
        zone,
        sensing,
    })
}

/// The obstacles in the `obstacle` value (an array of tables), in the file's order.
pub(crate) fn obstacles(
    source: &Source<'_>,
    value: &Spanned<DeValue<'_>>,
) -> Result<Vec<PlanarObstacleFile>, ProblemError> {
    obstacle_tables(source, value, OBSTACLE_KEYS, |index, table, name| {
        obstacle(source, index, table, name)
    })
}

/// The planar obstacle at `index`, from its table (its name already read).
fn obstacle(
    source: &Source<'_>,
    index: usize,
    table: &DeTable<'_>,
    name: String,
) -> Result<PlanarObstacleFile, ProblemError> {
    let shown = |field: &'static str| SceneKey::Obstacle(index, field).show(&name);
    fn read<T: serde::de::DeserializeOwned>(
        source: &Source<'_>,
        table: &DeTable<'_>,
        index: usize,
        name: &str,
        spec: &'static KeySpec,
    ) -> Result<Option<T>, ProblemError> {
        let key = SceneKey::Obstacle(index, spec.key);
        table
            .get(spec.key)
            .map(|v| typed(source, spec, key, &key.show(name), v))
            .transpose()
    }
    let shape = |field: &'static str, reason: &str| {
        source.shape(
            SceneKey::Obstacle(index, field),
            shown(field),
            reason.to_string(),
        )
    };
    let radius: Option<f64> = read(source, table, index, &name, &RADIUS)?;
    let at: Option<[f64; 2]> = read(source, table, index, &name, &START)?;
    let min: Option<[f64; 2]> = read(source, table, index, &name, &START_MIN)?;
    let max: Option<[f64; 2]> = read(source, table, index, &name, &START_MAX)?;
    let start = match (at, min, max) {
        (Some(p), None, None) => StartFile::At(p),
        (None, Some(min), Some(max)) => StartFile::Box { min, max },
        (Some(_), _, _) => {
            return Err(shape(
                START.key,
                "give either start = [x, y] or start_min and start_max (a box), not both",
            ));
        }
        (None, None, None) => {
            return Err(shape(
                START.key,
                "missing: every obstacle needs start = [x, y] (m), or start_min and start_max \
                 (a box of starts)",
            ));
        }
        (None, Some(_), None) => {
            return Err(shape(START_MAX.key, "missing: start_min needs start_max"));
        }
        (None, None, Some(_)) => {
            return Err(shape(START_MIN.key, "missing: start_max needs start_min"));
        }
    };
    let Some(max_speed) = read(source, table, index, &name, &MAX_SPEED)? else {
        return Err(shape(
            MAX_SPEED.key,
            "missing: every obstacle needs its speed bound max_speed (m/s), >= 0",
        ));
    };
    Ok(PlanarObstacleFile {
        radius: radius.unwrap_or(0.0),
        start,
        max_speed,
        direction: read(source, table, index, &name, &DIRECTION)?,
        region: read(source, table, index, &name, &REGION)?,
        name,
    })
}
