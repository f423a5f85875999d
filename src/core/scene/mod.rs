//! Scenes (DESIGN.md §1.1, docs/semantics.md "Scenes"): several obstacles on several lanes,
//! static and moving, lane changes and a destination.
//!
//! A [`Scene`] is what a scene file states, after validation. A single-obstacle
//! [`Problem`] is the scene with one moving obstacle in lane 0 ([`Scene::from_problem`]),
//! and a scene that is exactly that gives it back ([`Scene::as_problem`]), so old files
//! keep their answers and certificates.
//!
//! # Scene files
//!
//! [`Scene::load`], [`Scene::load_with_overrides`] and [`Scene::from_toml_str`] read a scene
//! as strictly as [`Problem::load`] reads a problem (same machinery, same [`ProblemError`]s):
//!
//! ```toml
//! name = "seed-lanes"
//! [robot]                      # a problem's robot keys, plus:
//! goal = 30.0                  # optional: destination x (m), > 0
//! sensing_range = 3.0          # optional: R >= controller.reaction_radius (m); default unlimited
//! [controller]                 # a problem's controller keys, plus:
//! lane_change = true           # optional, default false
//! lane_change_periods = 10     # whole periods, >= 1; required when lane_change = true
//! lane_change_rear_gap = 0.5   # m, >= 0; required when lane_change = true
//! [scene]                      # optional
//! lanes = [-1, 0, 1]           # lanes that exist, each once, including 0; default [0]
//! [[obstacle]]                 # at least one
//! name = "oncoming"            # optional, unique; default "obstacle-<index>"
//! lane = 0                     # one of scene.lanes
//! position = 10.0              # initial x (m) > robot.clearance, or a range [min, max]
//! max_speed = 0.15             # W_i (m/s), >= 0
//! static = false               # optional, default false; true requires max_speed = 0
//! ```
//!
//! - A file with `[environment]` (a problem file) reads as [`Scene::from_problem`] of its
//!   problem, after all of the problem's checks with the problem's messages; it may carry
//!   the scene's `[robot]` and `[controller]` keys, which then apply to that scene (a lane
//!   change is refused there: it has one lane). `[environment]` beside `[scene]` or
//!   `[[obstacle]]` is an error.
//! - `lane_change_periods` and `lane_change_rear_gap` without `lane_change = true` are
//!   checked and ignored, so that `--set controller.lane_change=false` switches lane changes
//!   off in a file that sets them.
//! - The lanes are stored ascending (the file may list them in any order).
//! - Errors name the file (with the line) or the `--set` flag, the key — an obstacle's by
//!   index and name, `obstacle[1] ("parked").max_speed` — and the reason.
//! - `--set` takes a problem's keys, the scene's (`robot.goal=30`, `scene.lanes=[0,1]`,
//!   `controller.lane_change=true`) and an obstacle's by its 0-based index
//!   (`obstacle.1.max_speed=0.2`; an index past the last obstacle is an error naming the
//!   flag). Overridden values pass the same checks.
//! - [`Scene::to_toml_string`] writes the scene form, which reads back as an equal scene.

//!
//! # Running a scene
//!
//! [`Scene::params`] gives its numbers ([`SceneParams`]), [`SceneWorld`] is its step
//! function (guards in [`guards`], lanes in [`lateral`], per-obstacle safety in
//! [`safety`]), and [`simulate`] runs, replays and traces it.

pub(crate) mod fields;
pub(crate) mod keys;
pub(crate) mod origin;
mod read;
pub(crate) mod shape;
pub(crate) mod validate;
mod write;

use serde::{Deserialize, Serialize};

pub use crate::core::model::Position;
#[cfg(doc)]
use crate::core::model::ProblemError;
use crate::core::model::{Controller, Environment, Params, Problem, Robot, Sensing};
use crate::core::num::Scalar;

pub mod guards;
pub mod lateral;
pub mod observe;
mod params;
#[cfg(test)]
mod run_tests;
pub mod safety;
pub mod simulate;
mod world;

pub use lateral::{LaneChangeEvent, Lateral};
pub use observe::ObservationPlan;
pub use params::{LaneChangeParams, ObstacleParams, SceneParams};
pub use world::{ObstacleStep, SceneStepRecord, SceneWorld};

/// A scene: one robot, its controller, the lanes and every obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name shown in reports.
    pub name: String,
    /// The robot's dynamics and timing (as in a single-obstacle problem).
    pub robot: Robot,
    /// The controller's braking rule (as in a single-obstacle problem).
    pub controller: Controller,
    /// Destination x (m): the robot brakes to stop at it (`nearDestination`); None: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub goal: Option<f64>,
    /// Sensing range R ≥ ρ (m); None: unlimited.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensing_range: Option<f64>,
    /// Lane changes, when the controller may make them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lane_change: Option<LaneChange>,
    /// Observation noise and occlusion (`[sensing]`), the same for every obstacle; None:
    /// exact observations of obstacles visible from the start.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensing: Option<Sensing>,
    /// Lanes that exist, ascending, without repeats; the robot starts in lane 0.
    pub lanes: Vec<i32>,
    /// The obstacles, in file order (their index is their number in `--set obstacle.N.…`).
    pub obstacles: Vec<Obstacle>,
}

/// How the controller changes lanes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct LaneChange {
    /// P: whole control periods a lane change lasts, ≥ 1.
    pub periods: u32,
    /// A lane is free when no seen obstacle in it is observed at a gap in [−rear_gap, ρ] (m).
    pub rear_gap: f64,
}

/// One obstacle of a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Obstacle {
    /// Unique name (default `obstacle-<index>`); trace obstacle ids are matched to it.
    pub name: String,
    /// The lane it moves in.
    pub lane: i32,
    /// Its x at t = 0 (m), ahead of the robot.
    pub position: Position,
    /// W_i: bound on its speed towards −x (m/s), ≥ 0.
    pub max_speed: f64,
    /// Known to the robot as static (requires `max_speed = 0`): the danger rule counts only
    /// the robot's own braking (d_static = d_coll with V_a = 0).
    #[serde(rename = "static")]
    pub is_static: bool,
}

impl Scene {
    /// The scene a single-obstacle problem stands for: one moving obstacle in lane 0.
    pub fn from_problem(problem: &Problem) -> Scene {
        Scene {
            name: problem.name.clone(),
            robot: problem.robot.clone(),
            controller: problem.controller.clone(),
            goal: None,
            sensing_range: None,
            lane_change: None,
            sensing: problem.sensing.clone(),
            lanes: vec![0],
            obstacles: vec![Obstacle {
                name: "obstacle-0".into(),
                lane: 0,
                position: problem.environment.initial_gap,
                max_speed: problem.environment.obstacle_speed,
                is_static: false,
            }],
        }
    }

    /// The single-obstacle problem this scene is, if it is one: one moving obstacle, in
    /// lane 0, at a fixed position, no goal, no lane changes. (Lanes and sensing range do
    /// not change the answer then: see docs/semantics.md.)
    pub fn as_problem(&self) -> Option<Problem> {
        let [o] = self.obstacles.as_slice() else {
            return None;
        };
        // A range stays with the scene engines, which have always answered it.
        let x = o.position;
        if x.is_range() {
            return None;
        }
        if o.lane != 0 || o.is_static || self.goal.is_some() || self.lane_change.is_some() {
            return None;
        }
        Some(Problem {
            name: self.name.clone(),
            robot: self.robot.clone(),
            controller: self.controller.clone(),
            environment: Environment {
                obstacle_speed: o.max_speed,
                initial_gap: x,
            },
            sensing: self.sensing.clone(),
        })
    }

    /// The single-obstacle parameters of obstacle `i`, as the controller and the environment
    /// see it: W = W_i, g0 = its nearest initial x, and for a static obstacle V_a = 0 (the
    /// danger rule counts only the robot's own braking; no observed speed exceeds it).
    pub fn obstacle_params<N: Scalar>(&self, i: usize) -> Params<N> {
        let o = &self.obstacles[i];
        let mut problem = Problem {
            name: self.name.clone(),
            robot: self.robot.clone(),
            controller: self.controller.clone(),
            environment: Environment {
                obstacle_speed: o.max_speed,
                initial_gap: Position::At(o.position.min()),
            },
            sensing: self.sensing.clone(),
        };
        if o.is_static {
            problem.controller.assumed_obstacle_speed = 0.0;
        }
        problem.params()
    }

    /// The robot's and controller's numbers (the obstacle fields W and g0 are 0: no
    /// obstacle is meant).
    pub fn robot_params<N: Scalar>(&self) -> Params<N> {
        Problem {
            name: self.name.clone(),
            robot: self.robot.clone(),
            controller: self.controller.clone(),
            environment: Environment {
                obstacle_speed: 0.0,
                initial_gap: Position::At(0.0),
            },
            sensing: self.sensing.clone(),
        }
        .params()
    }

    /// Indices of the obstacles in `lane`.
    pub fn in_lane(&self, lane: i32) -> impl Iterator<Item = usize> + '_ {
        (0..self.obstacles.len()).filter(move |&i| self.obstacles[i].lane == lane)
    }

    /// The largest speed bound of the scene's moving obstacles (0 if none move).
    pub fn largest_moving_bound(&self) -> f64 {
        self.obstacles
            .iter()
            .filter(|o| !o.is_static)
            .map(|o| o.max_speed)
            .fold(0.0, f64::max)
    }
}
