//! A scene's worst case in words: which obstacle, in which lane, and why the robot braked
//! (or did not), as `certify` prints it and sweeps and reports record it per cell.

use serde::{Deserialize, Serialize};

use crate::analysis::scene::SceneAnalysis;
use crate::core::scene::Scene;
use crate::core::semantics::BrakeReason;
use crate::proof::scene_certificate::{SceneWitness, Trigger};
use crate::proof::schedule::{Ending, Piece};
use crate::proof::search_certificate::SearchCertificate;

/// Why the robot braked in a scene's worst case.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum BrakeCause {
    /// On collision danger from the worst-case obstacle itself.
    CollisionDanger,
    /// On seeing the worst-case obstacle faster than V_a.
    WrongAssumption,
    /// It never braked: the obstacle passed through the reaction area (s* = −∞).
    NeverBraked,
    /// For another obstacle (named), which fired first.
    AnotherObstacle(String),
    /// For its destination.
    Destination,
    /// For another obstacle or its destination; no replayed witness says which.
    ElseUnknown,
    /// A run of the exact search (lane changes, position ranges): its lane changes, then
    /// how it ended (None: it never braked).
    Run {
        /// Lane changes before the end.
        lane_changes: usize,
        /// Why the robot braked, if it did.
        brake: Option<BrakeReason>,
    },
}

impl BrakeCause {
    /// The cause of a piece's ending, refined by the witness's trigger when there is one.
    fn of(scene: &Scene, piece: &Piece, trigger: Option<&Trigger>) -> BrakeCause {
        match (piece.ending, trigger) {
            (Ending::Danger, _) => BrakeCause::CollisionDanger,
            (Ending::WrongAssumption, _) => BrakeCause::WrongAssumption,
            (Ending::PassThrough, _) => BrakeCause::NeverBraked,
            (Ending::Bystander, Some(Trigger::Goal)) => BrakeCause::Destination,
            (Ending::Bystander, Some(Trigger::Obstacle { obstacle, .. })) => {
                BrakeCause::AnotherObstacle(scene.obstacles[*obstacle].name.clone())
            }
            (Ending::Bystander, None) => BrakeCause::ElseUnknown,
        }
    }

    /// A short machine-readable tag: `collision_danger`, `another_obstacle:NAME`, ….
    pub fn tag(&self) -> String {
        match self {
            BrakeCause::CollisionDanger => "collision_danger".into(),
            BrakeCause::WrongAssumption => "wrong_assumption".into(),
            BrakeCause::NeverBraked => "never_braked".into(),
            BrakeCause::AnotherObstacle(name) => format!("another_obstacle:{name}"),
            BrakeCause::Destination => "destination".into(),
            BrakeCause::ElseUnknown => "another_obstacle_or_destination".into(),
            BrakeCause::Run {
                lane_changes,
                brake,
            } => format!("lane_changes:{lane_changes}:{}", brake_tag(*brake)),
        }
    }

    /// The cause in a few words, for a table: `collision danger`, `for "first"`.
    pub fn short(&self) -> String {
        match self {
            BrakeCause::CollisionDanger => "collision danger".into(),
            BrakeCause::WrongAssumption => "faster than V_a".into(),
            BrakeCause::NeverBraked => "never braked".into(),
            BrakeCause::AnotherObstacle(name) => format!("for \"{name}\""),
            BrakeCause::Destination => "for the destination".into(),
            BrakeCause::ElseUnknown => "for another obstacle or the destination".into(),
            BrakeCause::Run {
                lane_changes,
                brake,
            } => format!(
                "{lane_changes} lane change(s), {}",
                brake_tag(*brake).replace('_', " ")
            ),
        }
    }

    /// The cause in words, as `certify` prints it (another obstacle's name in quotes after).
    pub fn describe(&self) -> String {
        match self {
            BrakeCause::CollisionDanger => "the robot brakes on collision danger".into(),
            BrakeCause::WrongAssumption => "the robot brakes on seeing it faster than V_a".into(),
            BrakeCause::NeverBraked => "it passes through the reaction area unbraked".into(),
            BrakeCause::AnotherObstacle(name) => {
                format!("the robot brakes for another obstacle (\"{name}\")")
            }
            BrakeCause::Destination => "the robot brakes for its destination".into(),
            BrakeCause::ElseUnknown => {
                "the robot brakes for another obstacle or its destination".into()
            }
            BrakeCause::Run {
                lane_changes,
                brake,
            } => format!(
                "after {lane_changes} lane change(s) the robot {}",
                match brake {
                    Some(BrakeReason::CollisionDanger) => "brakes on collision danger",
                    Some(BrakeReason::WrongAssumption) => "brakes on an obstacle faster than V_a",
                    Some(BrakeReason::Destination) => "brakes for its destination",
                    None => "never brakes",
                }
            ),
        }
    }
}

/// The tag of a brake reason (`never_braked` for none).
fn brake_tag(brake: Option<BrakeReason>) -> &'static str {
    match brake {
        Some(BrakeReason::CollisionDanger) => "collision_danger",
        Some(BrakeReason::WrongAssumption) => "wrong_assumption",
        Some(BrakeReason::Destination) => "destination",
        None => "never_braked",
    }
}

/// A scene's worst case: the obstacle whose separation is s*, its lane, and why the robot
/// braked.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SceneWorstCase {
    /// The obstacle's index in the scene.
    pub obstacle: usize,
    /// Its name.
    pub name: String,
    /// Its lane.
    pub lane: i32,
    /// Why the robot braked.
    pub cause: BrakeCause,
}

impl SceneWorstCase {
    /// The worst case a replayed witness shows.
    pub fn from_witness(scene: &Scene, w: &SceneWitness) -> SceneWorstCase {
        SceneWorstCase {
            obstacle: w.obstacle,
            name: scene.obstacles[w.obstacle].name.clone(),
            lane: w.lane,
            cause: BrakeCause::of(scene, &w.piece, w.trigger.as_ref()),
        }
    }

    /// The analysis's worst case: its witness's when it has one, else the piece with the
    /// least optimum (or the feasible pass-through); None when there is neither.
    pub fn of_analysis(a: &SceneAnalysis) -> Option<SceneWorstCase> {
        if let Some(w) = &a.witness {
            return Some(SceneWorstCase::from_witness(&a.scene, w));
        }
        let (k, piece) = a.worst.as_ref()?;
        let obstacle = a.obstacles[*k].obstacle;
        let o = &a.scene.obstacles[obstacle];
        Some(SceneWorstCase {
            obstacle,
            name: o.name.clone(),
            lane: o.lane,
            cause: BrakeCause::of(&a.scene, piece, None),
        })
    }

    /// The worst case of a search certificate's witness.
    pub fn of_search(c: &SearchCertificate) -> Option<SceneWorstCase> {
        let w = c.witness.as_ref()?;
        Some(SceneWorstCase {
            obstacle: w.obstacle,
            name: c.scene.obstacles[w.obstacle].name.clone(),
            lane: w.lane,
            cause: BrakeCause::Run {
                lane_changes: w.lane_changes.len(),
                brake: w.brake.map(|(_, r)| r),
            },
        })
    }

    /// `obstacle "second" in lane 0: the robot brakes on collision danger`.
    pub fn describe(&self) -> String {
        format!(
            "obstacle \"{}\" in lane {}: {}",
            self.name,
            self.lane,
            self.cause.describe()
        )
    }
}
