//! The rules a planar problem's numbers keep, in the file's terms: the motion exactly as a
//! problem's (the same checks), then every planar number finite and in its key's range,
//! unique obstacle names, start boxes the right way round, a field of view of at most 360°.
//! The geometry (paths, polygons, directions, where obstacles start) is checked exactly
//! where the problem becomes exact numbers (`exact.rs`).

use crate::core::model::error::show_number;
use crate::core::model::keys::KeySpec;
use crate::core::model::validate::{motion_violation, number_violation};
use crate::core::planar::file::{PlanarProblem, StartFile, Zone};
use crate::core::planar::keys::{
    DIRECTION, DIRECTION_TOLERANCE, FIELD_OF_VIEW, FIRST_DETECTION, MAX_SPEED, PATH,
    PATH_TOLERANCE, POSITION_NOISE, RADIUS, RANGE, REGION, ROBOT_RADIUS, START, START_MAX,
    START_MIN, STOP_POLYGON, VELOCITY_NOISE,
};
use crate::core::scene::keys::SceneKey;
use crate::core::scene::validate::{SceneViolation, obstacle_name_violation};

/// A point as messages show it: `[1.5, -2]`.
pub(crate) fn show_point(p: &[f64; 2]) -> String {
    format!("[{}, {}]", show_number(p[0]), show_number(p[1]))
}

/// A list of points as messages show it.
pub(crate) fn show_points(points: &[[f64; 2]]) -> String {
    let shown: Vec<String> = points.iter().map(show_point).collect();
    format!("[{}]", shown.join(", "))
}

/// The violation at `key` of `x` outside `spec`'s range.
fn number(key: SceneKey, spec: &'static KeySpec, x: f64) -> Option<SceneViolation> {
    number_violation(spec, x).map(|v| SceneViolation {
        key,
        value: v.value,
        reason: v.reason,
    })
}

/// A coordinate of `points` (the value at `key`) that is not finite or too large.
fn coordinates(
    key: SceneKey,
    spec: &'static KeySpec,
    points: &[[f64; 2]],
    shown: impl Fn() -> String,
) -> Option<SceneViolation> {
    let v = points
        .iter()
        .flatten()
        .find_map(|&x| number_violation(spec, x))?;
    Some(SceneViolation {
        key,
        value: shown(),
        reason: format!("every coordinate {}", v.reason),
    })
}

impl PlanarProblem {
    /// The first rule of the model the problem breaks: the numbers' own ranges in file
    /// order, then the geometry.
    pub(crate) fn violation(&self) -> Option<SceneViolation> {
        self.number_violation()
            .or_else(|| (0..self.obstacles.len()).find_map(|i| self.obstacle_violation(i)))
            .or_else(|| self.exact().err())
    }

    /// `key` as messages name it (with the obstacle's name for an obstacle's key).
    pub(crate) fn show_key(&self, key: SceneKey) -> String {
        key.show_in(|i| self.obstacles.get(i).map(|o| o.name.clone()))
    }

    /// The name, the motion (as a problem's), and the planar numbers outside the obstacles.
    fn number_violation(&self) -> Option<SceneViolation> {
        let plain = |spec: &'static KeySpec, x: Option<f64>| {
            x.and_then(|x| number(SceneKey::Plain(spec.key), spec, x))
        };
        if self.name.trim().is_empty() {
            return Some(SceneViolation {
                key: SceneKey::Plain("name"),
                value: format!("{:?}", self.name),
                reason: "must not be empty".into(),
            });
        }
        let s = &self.sensing;
        motion_violation(&self.robot, &self.controller)
            .map(|v| SceneViolation {
                key: SceneKey::Plain(v.key),
                value: v.value,
                reason: v.reason,
            })
            .or_else(|| plain(&DIRECTION_TOLERANCE, self.direction_tolerance))
            .or_else(|| {
                let tolerance = self.direction_tolerance.filter(|&d| d > 1.0)?;
                Some(SceneViolation {
                    key: SceneKey::Plain(DIRECTION_TOLERANCE.key),
                    value: show_number(tolerance),
                    reason: "must be <= 1: a chord distance between unit vectors (1e-9 is \
                             about 1e-9 rad)"
                        .into(),
                })
            })
            .or_else(|| plain(&ROBOT_RADIUS, Some(self.body.radius)))
            .or_else(|| plain(&PATH_TOLERANCE, Some(self.body.path_tolerance)))
            .or_else(|| {
                let path = self.body.path.as_ref()?;
                coordinates(SceneKey::Plain(PATH.key), &PATH, path, || show_points(path))
            })
            .or_else(|| match &self.zone {
                Zone::Polygon(p) => {
                    coordinates(SceneKey::Plain(STOP_POLYGON.key), &STOP_POLYGON, p, || {
                        show_points(p)
                    })
                }
                Zone::Disc => None,
            })
            .or_else(|| plain(&POSITION_NOISE, s.position_noise))
            .or_else(|| plain(&VELOCITY_NOISE, s.velocity_noise))
            .or_else(|| plain(&FIRST_DETECTION, s.first_detection))
            .or_else(|| plain(&RANGE, s.range))
            .or_else(|| plain(&FIELD_OF_VIEW, s.field_of_view))
            .or_else(|| {
                let theta = s.field_of_view.filter(|&t| t > 360.0)?;
                Some(SceneViolation {
                    key: SceneKey::Plain(FIELD_OF_VIEW.key),
                    value: show_number(theta),
                    reason: "must be in (0, 360] (degrees): the view's full angle, centred on \
                             the heading"
                        .into(),
                })
            })
    }

    /// Obstacle `i`'s own numbers: a name (unique), a radius and speed in range, finite
    /// coordinates, a start box the right way round.
    fn obstacle_violation(&self, i: usize) -> Option<SceneViolation> {
        let o = &self.obstacles[i];
        let key = |field: &'static str| SceneKey::Obstacle(i, field);
        let at = |field: &'static str, value: String, reason: String| {
            Some(SceneViolation {
                key: key(field),
                value,
                reason,
            })
        };
        let earlier = self.obstacles[..i].iter().map(|p| p.name.as_str());
        if let Some(v) = obstacle_name_violation(i, &o.name, earlier) {
            return Some(v);
        }
        let point = |spec: &'static KeySpec, p: &[f64; 2]| {
            coordinates(key(spec.key), spec, std::slice::from_ref(p), || {
                show_point(p)
            })
        };
        let start = match &o.start {
            StartFile::At(p) => point(&START, p),
            StartFile::Box { min, max } => point(&START_MIN, min)
                .or_else(|| point(&START_MAX, max))
                .or_else(|| {
                    let axis = (0..2).find(|&a| min[a] > max[a])?;
                    at(
                        START_MIN.key,
                        show_point(min),
                        format!(
                            "a box needs start_min <= start_max in x and in y; here {} {} > {}",
                            ["x", "y"][axis],
                            show_number(min[axis]),
                            show_number(max[axis])
                        ),
                    )
                }),
        };
        number(key(RADIUS.key), &RADIUS, o.radius)
            .or(start)
            .or_else(|| number(key(MAX_SPEED.key), &MAX_SPEED, o.max_speed))
            .or_else(|| point(&DIRECTION, o.direction.as_ref()?))
            .or_else(|| {
                let region = o.region.as_ref()?;
                coordinates(key(REGION.key), &REGION, region, || show_points(region))
            })
    }
}
