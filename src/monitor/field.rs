//! The columns of a trace: the names a sample's fields have in CSV headers and JSON keys,
//! shared by the trace reader (which looks them up) and the monitor's input checks (which
//! name the field that is wrong).
//!
//! The lane columns (`robot_lane`, `obstacle_lane`, `leaving_lane`) are those of scene
//! traces, and the planar columns (`robot_y`, `obstacle_y`, `obstacle_vx`, `obstacle_vy`)
//! those of planar traces; a trace without them reads as before.

use std::fmt;

/// A column of a trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Field {
    /// `t`
    T,
    /// `robot_x`
    RobotX,
    /// `robot_v`
    RobotV,
    /// `robot_mode`
    RobotMode,
    /// `obstacle_id`
    ObstacleId,
    /// `obstacle_x`
    ObstacleX,
    /// `obstacle_v`
    ObstacleV,
    /// `obstacle_t`
    ObstacleT,
    /// `robot_lane` (scene traces)
    RobotLane,
    /// `obstacle_lane` (scene traces)
    ObstacleLane,
    /// `leaving_lane` (scene traces)
    LeavingLane,
    /// `robot_y` (planar traces: the robot's centre is (`robot_x`, `robot_y`))
    RobotY,
    /// `obstacle_y` (planar traces: the obstacle's centre is (`obstacle_x`, `obstacle_y`))
    ObstacleY,
    /// `obstacle_vx` (planar traces: the obstacle's velocity over the period that ends at `t`)
    ObstacleVx,
    /// `obstacle_vy` (planar traces)
    ObstacleVy,
}

impl Field {
    /// Every column, required ones first.
    pub const ALL: [Field; 15] = [
        Field::T,
        Field::RobotX,
        Field::RobotV,
        Field::ObstacleId,
        Field::ObstacleX,
        Field::ObstacleV,
        Field::RobotMode,
        Field::ObstacleT,
        Field::RobotLane,
        Field::ObstacleLane,
        Field::LeavingLane,
        Field::RobotY,
        Field::ObstacleY,
        Field::ObstacleVx,
        Field::ObstacleVy,
    ];

    /// The column's name in traces.
    pub fn as_str(self) -> &'static str {
        match self {
            Field::T => "t",
            Field::RobotX => "robot_x",
            Field::RobotV => "robot_v",
            Field::RobotMode => "robot_mode",
            Field::ObstacleId => "obstacle_id",
            Field::ObstacleX => "obstacle_x",
            Field::ObstacleV => "obstacle_v",
            Field::ObstacleT => "obstacle_t",
            Field::RobotLane => "robot_lane",
            Field::ObstacleLane => "obstacle_lane",
            Field::LeavingLane => "leaving_lane",
            Field::RobotY => "robot_y",
            Field::ObstacleY => "obstacle_y",
            Field::ObstacleVx => "obstacle_vx",
            Field::ObstacleVy => "obstacle_vy",
        }
    }

    /// The column named `name`.
    pub fn from_name(name: &[u8]) -> Option<Field> {
        Field::ALL
            .into_iter()
            .find(|f| f.as_str().as_bytes() == name)
    }

    /// Whether every sample must have it.
    pub fn required(self) -> bool {
        matches!(
            self,
            Field::T | Field::RobotX | Field::RobotV | Field::ObstacleId | Field::ObstacleX
        )
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}
