//! The checks a planar certificate adds to its premises ([`PlaneCheck`]): what the planar
//! problem states of the robot's path and of each obstacle beyond its speed bound (where it
//! starts, the region it keeps to, that it is one the certificate speaks of). Only a planar
//! certificate's monitor runs them (`monitor::planar`).

use super::{Carried, PremiseCheck};

/// A check a planar certificate adds (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PlaneCheck {
    /// The robot's centre is farther from its certified path than the path's drift D.
    RobotPath,
    /// An obstacle is first seen farther from its start (point or box) than its speed bound
    /// lets it come since t = 0, beyond observation noise.
    ObstacleStart,
    /// An obstacle is seen outside the convex region it is certified to keep to, beyond
    /// observation noise.
    ObstacleRegion,
    /// A tracked object the certificate has no obstacle for.
    UncertifiedObstacle,
}

impl PlaneCheck {
    /// Every planar check, in output order.
    pub const ALL: [PlaneCheck; 4] = [
        PlaneCheck::RobotPath,
        PlaneCheck::ObstacleStart,
        PlaneCheck::ObstacleRegion,
        PlaneCheck::UncertifiedObstacle,
    ];

    /// The stable name.
    pub const fn name(self) -> &'static str {
        match self {
            PlaneCheck::RobotPath => "robot_path",
            PlaneCheck::ObstacleStart => "obstacle_start",
            PlaneCheck::ObstacleRegion => "obstacle_region",
            PlaneCheck::UncertifiedObstacle => "uncertified_obstacle",
        }
    }

    /// Its row: unit, relation and reasons.
    pub(crate) fn row(self) -> &'static PremiseCheck {
        match self {
            PlaneCheck::RobotPath => &ROBOT_PATH,
            PlaneCheck::ObstacleStart => &OBSTACLE_START,
            PlaneCheck::ObstacleRegion => &OBSTACLE_REGION,
            PlaneCheck::UncertifiedObstacle => &UNCERTIFIED_OBSTACLE,
        }
    }
}

/// `robot_path`: the centre's distance from the path (m) above the drift D.
const ROBOT_PATH: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: ">",
    positive: false,
    not_checked: "no instant",
    not_monitored: super::always_monitored,
};

/// `obstacle_start`: the first seen centre's distance from its start (m) above W_i·t + σ_p.
const OBSTACLE_START: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: ">",
    positive: false,
    not_checked: "no obstacle of the certificate was seen",
    not_monitored: super::always_monitored,
};

/// `obstacle_region`: the seen centre's distance outside its region (m) above σ_p.
const OBSTACLE_REGION: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: ">",
    positive: false,
    not_checked: "no obstacle with a region was seen",
    not_monitored: super::always_monitored,
};

/// `uncertified_obstacle`: an object whose id names no obstacle of the certificate.
const UNCERTIFIED_OBSTACLE: PremiseCheck = PremiseCheck {
    unit: "",
    relation: "",
    positive: false,
    not_checked: "no object was seen",
    not_monitored: plane_always,
};

fn plane_always(_: Carried) -> Option<&'static str> {
    None
}
