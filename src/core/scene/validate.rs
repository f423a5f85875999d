//! The rules a scene keeps: the problem's rules for the robot and the controller, and the
//! scene's own — lanes that include lane 0 once each, obstacles in existing lanes with unique
//! names, static obstacles that do not move, positions ahead of the robot, a sensing range
//! that covers the reaction radius, a lane change with a lane to change into, and horizons
//! of at most a million control periods.

use crate::core::model::error::{Violation, show_number};
use crate::core::model::keys::{KEYS, Kind, MAX_PERIODS};
use crate::core::model::validate::{
    distance_horizon_violation, latency_violation, motion_horizon_violation, number_violation,
    occluded_too_close, robot_controller_numbers, robot_violation, sensing_numbers,
};
use crate::core::model::{ProblemError, error::show_count};
use crate::core::scene::keys::{
    GOAL, LANE_CHANGE, LANE_CHANGE_PERIODS, LANE_CHANGE_REAR_GAP, LANES, MAX_LANE, MAX_SPEED,
    POSITION, SENSING_RANGE, SceneKey,
};
use crate::core::scene::{LaneChange, Position, Scene};

/// A rule of the model a scene breaks: the key, its value as shown, and why.
pub(crate) struct SceneViolation {
    /// The key whose value breaks the rule.
    pub(crate) key: SceneKey,
    /// The value as shown in messages.
    pub(crate) value: String,
    /// The rule, in the user's terms.
    pub(crate) reason: String,
}

impl SceneViolation {
    /// A problem rule's violation at a key outside the obstacles.
    fn plain(v: Violation) -> SceneViolation {
        SceneViolation {
            key: SceneKey::Plain(v.key),
            value: v.value,
            reason: v.reason,
        }
    }

    /// A problem rule's violation at key `v.key` of obstacle `index`.
    fn of_obstacle(index: usize, v: Violation) -> SceneViolation {
        SceneViolation {
            key: SceneKey::Obstacle(index, v.key),
            value: v.value,
            reason: v.reason,
        }
    }
}

/// Obstacle `index`'s name `name` when it is empty or the same as one of the `earlier`
/// obstacles' (in file order). Scenes and planar problems share it.
pub(crate) fn obstacle_name_violation<'a>(
    index: usize,
    name: &str,
    mut earlier: impl Iterator<Item = &'a str>,
) -> Option<SceneViolation> {
    let reason = if name.trim().is_empty() {
        "must not be empty".to_string()
    } else {
        let j = earlier.position(|p| p == name)?;
        format!(
            "obstacle[{j}] has the same name; names must be unique (trace obstacle ids are \
             matched to them)"
        )
    };
    Some(SceneViolation {
        key: SceneKey::Obstacle(index, "name"),
        value: format!("{name:?}"),
        reason,
    })
}

/// An initial position as shown in messages: `10` or `[8, 12]`.
pub(crate) fn show_position(p: &Position) -> String {
    match *p {
        Position::At(x) => show_number(x),
        Position::Range(lo, hi) => format!("[{}, {}]", show_number(lo), show_number(hi)),
    }
}

/// Lanes as shown in messages: `[-1, 0, 1]`.
pub(crate) fn show_lanes(lanes: &[i32]) -> String {
    let lanes: Vec<String> = lanes.iter().map(i32::to_string).collect();
    format!("[{}]", lanes.join(", "))
}

/// A lane change's own settings out of range: fewer than one period (or absurdly many), a
/// negative or non-finite rear gap.
pub(crate) fn lane_change_key_violation(lc: &LaneChange) -> Option<SceneViolation> {
    let key = SceneKey::Plain(LANE_CHANGE_PERIODS.key);
    if lc.periods < 1 {
        return Some(SceneViolation {
            key,
            value: lc.periods.to_string(),
            reason: "must be >= 1 (control periods)".into(),
        });
    }
    if f64::from(lc.periods) > MAX_PERIODS {
        return Some(SceneViolation {
            key,
            value: lc.periods.to_string(),
            reason: format!("must be <= {} (control periods)", show_count(MAX_PERIODS)),
        });
    }
    number_violation(&LANE_CHANGE_REAR_GAP, lc.rear_gap).map(SceneViolation::plain)
}

impl Scene {
    /// Checks the scene against the model's conditions (the problem's rules for the robot
    /// and the controller, and the scene's own; see the module docs of
    /// [`crate::core::scene`]); `origin` names the scene in the error. Errors name an
    /// obstacle's key by its index and name: `obstacle[1] ("parked").max_speed`.
    pub fn validate(&self, origin: &str) -> Result<(), ProblemError> {
        match self.violation() {
            None => Ok(()),
            Some(v) => Err(ProblemError::Invalid {
                origin: origin.to_string(),
                key: self.show_key(v.key),
                value: v.value,
                reason: v.reason,
                location: None,
            }),
        }
    }

    /// `key` as messages name it (with the obstacle's name for an obstacle's key).
    pub(crate) fn show_key(&self, key: SceneKey) -> String {
        key.show_in(|i| self.obstacles.get(i).map(|o| o.name.clone()))
    }

    /// The first rule of the model the scene breaks: each key's own range in file order,
    /// then the rules that tie keys together.
    pub(crate) fn violation(&self) -> Option<SceneViolation> {
        self.name_violation()
            .or_else(|| self.robot_controller_violation())
            .or_else(|| self.setting_violation())
            .or_else(|| self.lanes_violation())
            .or_else(|| {
                self.obstacles.is_empty().then(|| SceneViolation {
                    key: SceneKey::Plain("obstacle"),
                    value: "[]".into(),
                    reason: "a scene needs at least one obstacle".into(),
                })
            })
            .or_else(|| (0..self.obstacles.len()).find_map(|i| self.obstacle_violation(i)))
            .or_else(|| self.cross_violation())
    }

    fn name_violation(&self) -> Option<SceneViolation> {
        self.name.trim().is_empty().then(|| SceneViolation {
            key: SceneKey::Plain("name"),
            value: format!("{:?}", self.name),
            reason: "must not be empty".into(),
        })
    }

    /// The robot's and the controller's numbers, checked as in a problem.
    fn robot_controller_violation(&self) -> Option<SceneViolation> {
        let mut numbers = robot_controller_numbers(&self.robot, &self.controller);
        numbers.extend(sensing_numbers(self.sensing.as_ref()));
        KEYS.iter()
            .find_map(|spec| match spec.kind {
                Kind::Count => latency_violation(spec, self.robot.latency),
                Kind::Number => {
                    let &(_, x) = numbers.iter().find(|(k, _)| *k == spec.key)?;
                    number_violation(spec, x)
                }
                _ => None,
            })
            .or_else(|| robot_violation(&self.robot))
            .map(SceneViolation::plain)
    }

    /// The goal, the sensing range and the lane change's settings, each in its own range.
    fn setting_violation(&self) -> Option<SceneViolation> {
        let optional = [(&GOAL, self.goal), (&SENSING_RANGE, self.sensing_range)];
        optional
            .into_iter()
            .find_map(|(spec, x)| number_violation(spec, x?))
            .map(SceneViolation::plain)
            .or_else(|| {
                self.lane_change
                    .as_ref()
                    .and_then(lane_change_key_violation)
            })
    }

    fn lanes_violation(&self) -> Option<SceneViolation> {
        let lanes = &self.lanes;
        let bad = |reason: String| {
            Some(SceneViolation {
                key: SceneKey::Plain(LANES.key),
                value: show_lanes(lanes),
                reason,
            })
        };
        if let Some(l) = lanes.iter().find(|l| l.abs() > MAX_LANE) {
            return bad(format!(
                "lane {l} is out of range: lanes lie between -{MAX_LANE} and {MAX_LANE}"
            ));
        }
        if !lanes.contains(&0) {
            return bad("must contain lane 0, the lane the robot starts in".into());
        }
        for (i, l) in lanes.iter().enumerate() {
            if lanes[..i].contains(l) {
                return bad(format!("lane {l} is listed twice; each lane once"));
            }
        }
        if !lanes.is_sorted() {
            return bad("must be in ascending order".into());
        }
        None
    }

    /// Obstacle `i`'s own keys: a name (unique), an existing lane, finite positions in order,
    /// a speed bound in range and, for a static obstacle, zero.
    fn obstacle_violation(&self, i: usize) -> Option<SceneViolation> {
        let o = &self.obstacles[i];
        let at = |field: &'static str, value: String, reason: String| {
            Some(SceneViolation {
                key: SceneKey::Obstacle(i, field),
                value,
                reason,
            })
        };
        let earlier = self.obstacles[..i].iter().map(|p| p.name.as_str());
        if let Some(v) = obstacle_name_violation(i, &o.name, earlier) {
            return Some(v);
        }
        if !self.lanes.contains(&o.lane) {
            return at(
                "lane",
                o.lane.to_string(),
                format!(
                    "not a lane of the scene: scene.lanes = {}",
                    show_lanes(&self.lanes)
                ),
            );
        }
        let ends = [o.position.min(), o.position.max()];
        if let Some(v) = ends.iter().find_map(|&x| number_violation(&POSITION, x)) {
            return at("position", show_position(&o.position), v.reason);
        }
        if let Position::Range(lo, hi) = o.position
            && lo > hi
        {
            return at(
                "position",
                show_position(&o.position),
                format!(
                    "a range [min, max] needs min <= max; here min {} > max {}",
                    show_number(lo),
                    show_number(hi)
                ),
            );
        }
        if let Some(v) = number_violation(&MAX_SPEED, o.max_speed) {
            return Some(SceneViolation::of_obstacle(i, v));
        }
        if o.is_static && o.max_speed != 0.0 {
            return at(
                "max_speed",
                show_number(o.max_speed),
                "a static obstacle must have max_speed = 0".into(),
            );
        }
        None
    }

    /// Rules that tie keys together: obstacles ahead of the clearance, a sensing range that
    /// covers the reaction radius, a lane to change into, and the horizons.
    fn cross_violation(&self) -> Option<SceneViolation> {
        let r = &self.robot;
        for (i, o) in self.obstacles.iter().enumerate() {
            let which = match o.position {
                Position::At(_) => "must be",
                Position::Range(..) => "its min must be",
            };
            if o.position.min() <= r.clearance {
                return Some(SceneViolation {
                    key: SceneKey::Obstacle(i, POSITION.key),
                    value: show_position(&o.position),
                    reason: format!(
                        "{which} > robot.clearance = {} (m): obstacles start ahead of the robot, \
                         beyond its clearance",
                        show_number(r.clearance)
                    ),
                });
            }
            let d_det = self.sensing.as_ref().and_then(|s| s.first_detection_gap);
            if let Some(d) = d_det.filter(|&d| o.position.min() < d) {
                return Some(SceneViolation {
                    key: SceneKey::Obstacle(i, POSITION.key),
                    value: show_position(&o.position),
                    reason: occluded_too_close(which, d),
                });
            }
        }
        let rho = self.controller.reaction_radius;
        if let Some(range) = self.sensing_range
            && range < rho
        {
            return Some(SceneViolation {
                key: SceneKey::Plain(SENSING_RANGE.key),
                value: show_number(range),
                reason: format!(
                    "must be >= controller.reaction_radius = {} (m): the robot must see as far \
                     as it reacts",
                    show_number(rho)
                ),
            });
        }
        if self.lane_change.is_some() && !self.lanes.iter().any(|l| l.abs() == 1) {
            let reason = if self.lanes.len() < 2 {
                format!(
                    "a lane change with one lane: scene.lanes = {}; add lane 1 or -1 to change \
                     into",
                    show_lanes(&self.lanes)
                )
            } else {
                format!(
                    "no lane to change into: scene.lanes = {} has neither lane 1 nor lane -1 \
                     next to lane 0",
                    show_lanes(&self.lanes)
                )
            };
            return Some(SceneViolation {
                key: SceneKey::Plain(LANE_CHANGE.key),
                value: "true".into(),
                reason,
            });
        }
        self.horizon_violation()
    }

    /// A distance the robot would need more than a million control periods to cover at top
    /// speed (the farthest start of each obstacle, the goal), or a robot too slow to speed
    /// up or stop within them.
    fn horizon_violation(&self) -> Option<SceneViolation> {
        let r = &self.robot;
        self.obstacles
            .iter()
            .enumerate()
            .find_map(|(i, o)| {
                distance_horizon_violation(
                    r,
                    POSITION.key,
                    o.position.max(),
                    "position / (robot.max_speed * robot.control_period)",
                    "to reach the obstacle's start at the robot's top speed",
                )
                .map(|v| SceneViolation {
                    value: show_position(&o.position),
                    ..SceneViolation::of_obstacle(i, v)
                })
            })
            .or_else(|| {
                let goal = self.goal?;
                distance_horizon_violation(
                    r,
                    GOAL.key,
                    goal,
                    "goal / (max_speed * control_period)",
                    "to reach the goal at top speed",
                )
                .map(SceneViolation::plain)
            })
            .or_else(|| motion_horizon_violation(r).map(SceneViolation::plain))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::model::Problem;
    use crate::core::scene::Obstacle;

    /// The seed's scene with two more obstacles in two more lanes, and a lane change.
    fn scene() -> Scene {
        let mut s = Scene::from_problem(&Problem::shipped_seed());
        s.lanes = vec![-1, 0, 1];
        s.lane_change = Some(LaneChange {
            periods: 5,
            rear_gap: 0.5,
        });
        s.obstacles.push(Obstacle {
            name: "left".into(),
            lane: 1,
            position: Position::Range(3.0, 4.0),
            max_speed: 0.0,
            is_static: true,
        });
        s.obstacles.push(Obstacle {
            name: "right".into(),
            lane: -1,
            position: Position::At(2.0),
            max_speed: 0.1,
            is_static: false,
        });
        s
    }

    fn reason(s: &Scene) -> Option<(String, String)> {
        s.violation().map(|v| (s.show_key(v.key), v.reason))
    }

    #[test]
    fn the_example_scene_is_valid() {
        assert!(reason(&scene()).is_none());
    }

    #[test]
    fn lanes_are_stored_ascending() {
        let mut s = scene();
        s.lanes = vec![1, 0, -1];
        let (key, why) = reason(&s).unwrap();
        assert_eq!(
            (key.as_str(), why.as_str()),
            ("scene.lanes", "must be in ascending order")
        );
    }

    #[test]
    fn a_scene_has_an_obstacle() {
        let mut s = scene();
        s.obstacles.clear();
        assert_eq!(reason(&s).unwrap().0, "obstacle");
    }

    #[test]
    fn obstacle_keys_are_named_by_index_and_name() {
        let mut s = scene();
        s.obstacles[2].max_speed = -1.0;
        let (key, why) = reason(&s).unwrap();
        assert_eq!(key, "obstacle[2] (\"right\").max_speed");
        assert_eq!(why, "must be >= 0 (m/s)");
    }

    #[test]
    fn a_range_may_be_a_point() {
        let mut s = scene();
        s.obstacles[1].position = Position::Range(3.0, 3.0);
        assert!(reason(&s).is_none());
    }

    #[test]
    fn a_lane_change_needs_a_lane_next_to_lane_0() {
        let mut s = scene();
        s.lanes = vec![-1, 0];
        s.obstacles[1].lane = -1;
        assert!(reason(&s).is_none(), "lane -1 alone is enough");
        s.lanes = vec![0, 2];
        s.obstacles[1].lane = 2;
        s.obstacles[2].lane = 2;
        let (key, why) = reason(&s).unwrap();
        assert_eq!(key, "controller.lane_change");
        assert!(why.starts_with("no lane to change into"), "{why}");
        // Without lane changes, lanes need not touch lane 0.
        s.lane_change = None;
        assert!(reason(&s).is_none());
    }

    #[test]
    fn lane_change_settings_have_their_ranges() {
        let v = |periods, rear_gap| {
            lane_change_key_violation(&LaneChange { periods, rear_gap }).map(|v| v.key)
        };
        assert_eq!(v(1, 0.0), None);
        assert_eq!(
            v(0, 0.0),
            Some(SceneKey::Plain("controller.lane_change_periods"))
        );
        assert_eq!(
            v(2_000_000, 0.0),
            Some(SceneKey::Plain("controller.lane_change_periods"))
        );
        assert_eq!(
            v(1, -0.1),
            Some(SceneKey::Plain("controller.lane_change_rear_gap"))
        );
        assert_eq!(
            v(1, f64::NAN),
            Some(SceneKey::Plain("controller.lane_change_rear_gap"))
        );
    }

    #[test]
    fn the_sensing_range_may_equal_the_reaction_radius() {
        let mut s = scene();
        s.sensing_range = Some(s.controller.reaction_radius);
        assert!(reason(&s).is_none());
        s.sensing_range = Some(s.controller.reaction_radius * 0.999);
        assert_eq!(reason(&s).unwrap().0, "robot.sensing_range");
    }
}
