//! The checks a scene certificate adds to its premises ([`SceneCheck`]): what the scene
//! states of each obstacle beyond the speed bound (static obstacles stay put, named obstacles
//! keep their lane). A single-obstacle certificate has none of them. (Safety itself,
//! `collision`, is a [`BehaviourCheck`](super::BehaviourCheck) every monitor runs.)
//!
//! Their rows (unit, relation, reasons) are [`PremiseCheck`]s like the premises'; the checks
//! themselves are in `obstacle.rs` (`static_obstacle`) and `lanes.rs` (`obstacle_lane`).

use super::{Carried, PremiseCheck};

/// A check a scene certificate adds (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SceneCheck {
    /// A static obstacle moved: its stated speed, or the speed its successive positions
    /// imply, exceeds what observation noise allows (0 without noise), either way.
    StaticObstacle,
    /// An obstacle the certificate names was seen in a lane other than its own.
    ObstacleLane,
}

impl SceneCheck {
    /// Every scene check, in output order.
    pub const ALL: [SceneCheck; 2] = [SceneCheck::StaticObstacle, SceneCheck::ObstacleLane];

    /// The stable name.
    pub const fn name(self) -> &'static str {
        match self {
            SceneCheck::StaticObstacle => "static_obstacle",
            SceneCheck::ObstacleLane => "obstacle_lane",
        }
    }

    /// Its row: unit, relation and reasons.
    pub(crate) fn row(self) -> &'static PremiseCheck {
        match self {
            SceneCheck::StaticObstacle => &STATIC_OBSTACLE,
            SceneCheck::ObstacleLane => &OBSTACLE_LANE,
        }
    }
}

/// `static_obstacle`: |speed| ≤ 2σ/Δt (observed and bound in m/s).
const STATIC_OBSTACLE: PremiseCheck = PremiseCheck {
    unit: "m/s",
    relation: ">",
    positive: false,
    not_checked: "no static obstacle of the certificate was seen with obstacle_v or twice",
    not_monitored: super::always_monitored,
};

/// `obstacle_lane`: observed lane ≠ certified lane (both lane numbers, no unit).
const OBSTACLE_LANE: PremiseCheck = PremiseCheck {
    unit: "",
    relation: "!=",
    positive: false,
    not_checked: "no obstacle of the certificate was seen",
    not_monitored: lane_not_monitored,
};

fn lane_not_monitored(carried: Carried) -> Option<&'static str> {
    (!carried.obstacle_lane).then_some(
        "no sample carried obstacle_lane; add the lane columns (robot_lane, obstacle_lane, \
         leaving_lane) to check lanes",
    )
}
