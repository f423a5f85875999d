//! The keys a planar problem file has beyond a problem's robot and controller: the `[plane]`
//! table that marks it, the robot's disc and path, the danger zone, `[sensing]` and each
//! obstacle's keys; and where `--set` puts them (`obstacle.1.max_speed`). Errors name an
//! obstacle's key as scenes do: `obstacle[1] ("car").region`.

use crate::core::model::ProblemError;
use crate::core::model::keys::{Bound, KEYS, KeySpec, Kind, spec};
use crate::core::model::overrides::Target;
use crate::core::scene::keys::resolve_in;

/// The chord tolerance of every direction (dimensionless, in (0, 1]).
pub(crate) const DIRECTION_TOLERANCE: KeySpec = spec(
    "plane.direction_tolerance",
    Kind::Number,
    "",
    Bound::Positive,
);
/// r_R: the robot disc's radius (m).
pub(crate) const ROBOT_RADIUS: KeySpec =
    spec("robot.radius", Kind::Number, "m", Bound::NonNegative);
/// The robot's path: a polyline from (0, 0).
pub(crate) const PATH: KeySpec = spec("robot.path", Kind::Points, "m", Bound::Free);
/// How far the robot's centre may be off its path (m): a tracking tolerance, added to the
/// path's drift D.
pub(crate) const PATH_TOLERANCE: KeySpec = spec(
    "robot.path_tolerance",
    Kind::Number,
    "m",
    Bound::NonNegative,
);
/// What the robot does at the path's end: `stop` or `continue`.
pub(crate) const PATH_END: KeySpec = spec("robot.path_end", Kind::Text, "", Bound::Free);
/// The danger zone: `disc` or `polygon`.
pub(crate) const DANGER_ZONE: KeySpec = spec("controller.danger_zone", Kind::Text, "", Bound::Free);
/// The stop polygon, in the robot's frame (m).
pub(crate) const STOP_POLYGON: KeySpec =
    spec("controller.stop_polygon", Kind::Points, "m", Bound::Free);
/// σ_p (m).
pub(crate) const POSITION_NOISE: KeySpec = spec(
    "sensing.position_noise",
    Kind::Number,
    "m",
    Bound::NonNegative,
);
/// σ_w (m/s).
pub(crate) const VELOCITY_NOISE: KeySpec = spec(
    "sensing.velocity_noise",
    Kind::Number,
    "m/s",
    Bound::NonNegative,
);
/// d_det (m).
pub(crate) const FIRST_DETECTION: KeySpec = spec(
    "sensing.first_detection",
    Kind::Number,
    "m",
    Bound::Positive,
);
/// R (m).
pub(crate) const RANGE: KeySpec = spec("sensing.range", Kind::Number, "m", Bound::Positive);
/// θ (degrees).
pub(crate) const FIELD_OF_VIEW: KeySpec = spec(
    "sensing.field_of_view",
    Kind::Number,
    "degrees",
    Bound::Positive,
);

/// The planar keys outside the obstacles, in file order.
pub(crate) const PLANAR_KEYS: &[&KeySpec] = &[
    &DIRECTION_TOLERANCE,
    &ROBOT_RADIUS,
    &PATH,
    &PATH_TOLERANCE,
    &PATH_END,
    &DANGER_ZONE,
    &STOP_POLYGON,
    &POSITION_NOISE,
    &VELOCITY_NOISE,
    &FIRST_DETECTION,
    &RANGE,
    &FIELD_OF_VIEW,
];

/// An obstacle's name.
pub(crate) const NAME: KeySpec = spec("name", Kind::Text, "", Bound::Free);
/// r_i (m).
pub(crate) const RADIUS: KeySpec = spec("radius", Kind::Number, "m", Bound::NonNegative);
/// Its start centre (m).
pub(crate) const START: KeySpec = spec("start", Kind::Point, "m", Bound::Free);
/// The least corner of its start box (m).
pub(crate) const START_MIN: KeySpec = spec("start_min", Kind::Point, "m", Bound::Free);
/// The greatest corner of its start box (m).
pub(crate) const START_MAX: KeySpec = spec("start_max", Kind::Point, "m", Bound::Free);
/// W_i (m/s).
pub(crate) const MAX_SPEED: KeySpec = spec("max_speed", Kind::Number, "m/s", Bound::NonNegative);
/// Its fixed direction (any nonzero vector).
pub(crate) const DIRECTION: KeySpec = spec("direction", Kind::Point, "", Bound::Free);
/// The convex polygon it never leaves (m).
pub(crate) const REGION: KeySpec = spec("region", Kind::Points, "m", Bound::Free);

/// The keys of one `[[obstacle]]`, in file order.
pub(crate) const OBSTACLE_KEYS: &[&KeySpec] = &[
    &NAME, &RADIUS, &START, &START_MIN, &START_MAX, &MAX_SPEED, &DIRECTION, &REGION,
];

/// The tables of a planar file (besides the `[[obstacle]]` array).
pub(crate) const TABLES: &[&str] = &["plane", "robot", "controller", "sensing"];

/// The keys of the 1-D problem a planar file shares: name, `[robot]` and `[controller]`.
fn shared_keys() -> impl Iterator<Item = &'static KeySpec> {
    KEYS.iter().filter(|s| {
        !s.key.contains('.') || s.key.starts_with("robot.") || s.key.starts_with("controller.")
    })
}

/// Every key outside the obstacles, the shared ones first.
pub(crate) fn plain_keys() -> Vec<&'static KeySpec> {
    shared_keys().chain(PLANAR_KEYS.iter().copied()).collect()
}

/// The keys of `table` (`robot`), without the table's name.
pub(crate) fn keys_of(table: &str) -> Vec<&'static str> {
    let prefix = format!("{table}.");
    plain_keys()
        .into_iter()
        .filter_map(|s| s.key.strip_prefix(prefix.as_str()))
        .collect()
}

/// Where a `--set` of a planar problem's `key` goes (`obstacle.<index>.<key>` for an
/// obstacle's), or the error for a key no planar problem has.
pub(crate) fn resolve(key: &str, origin: &str) -> Result<Target, ProblemError> {
    resolve_in(key, origin, &plain_keys(), TABLES, OBSTACLE_KEYS)
}
