//! Writing a scene back as a scene file that reads back as an equal scene.

use serde::Serialize;

use crate::core::model::{Controller, Robot, Sensing};
use crate::core::scene::{Obstacle, Scene};

/// A scene in the file's shape: the scene's settings in `[robot]` and `[controller]`, the
/// lanes in `[scene]`, the obstacles as `[[obstacle]]`.
#[derive(Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
struct File<'a> {
    name: &'a str,
    robot: RobotTable<'a>,
    controller: ControllerTable<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sensing: Option<&'a Sensing>,
    scene: SceneTable<'a>,
    obstacle: &'a [Obstacle],
}

#[derive(Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
struct RobotTable<'a> {
    #[serde(flatten)]
    robot: &'a Robot,
    #[serde(skip_serializing_if = "Option::is_none")]
    goal: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sensing_range: Option<f64>,
}

#[derive(Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
struct ControllerTable<'a> {
    #[serde(flatten)]
    controller: &'a Controller,
    lane_change: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    lane_change_periods: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    lane_change_rear_gap: Option<f64>,
}

#[derive(Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
struct SceneTable<'a> {
    lanes: &'a [i32],
}

impl Scene {
    /// The scene as a scene file (always the scene form, also for a single-obstacle
    /// problem's scene) that reads back as an equal scene.
    pub fn to_toml_string(&self) -> String {
        let file = File {
            name: &self.name,
            robot: RobotTable {
                robot: &self.robot,
                goal: self.goal,
                sensing_range: self.sensing_range,
            },
            controller: ControllerTable {
                controller: &self.controller,
                lane_change: self.lane_change.is_some(),
                lane_change_periods: self.lane_change.map(|l| l.periods),
                lane_change_rear_gap: self.lane_change.map(|l| l.rear_gap),
            },
            sensing: self.sensing.as_ref(),
            scene: SceneTable { lanes: &self.lanes },
            obstacle: &self.obstacles,
        };
        toml::to_string(&file).expect("a scene always serialises to TOML")
    }
}
