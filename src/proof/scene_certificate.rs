//! Scene certificates: a scene's answer in a form `check` re-verifies without the solver.
//!
//! Like a single-obstacle [`Certificate`](crate::proof::certificate::Certificate), with the
//! proofs grouped per obstacle of the robot's lane: its own pieces, then its bystander
//! pieces. [`check_scene`](crate::proof::scene_check::check_scene) rebuilds both lists from
//! the scene alone — the bystander steps from which firing pieces of other obstacles the
//! certificate proves empty — and recomputes every bound exactly.

use serde::{Deserialize, Serialize};

use crate::core::model::{Environment, Problem};
use crate::core::scene::Scene;
use crate::core::scene::simulate::SceneTraceRow;
pub use crate::proof::certificate::Proof;
use crate::proof::premise::{Premise, premises};
use crate::proof::schedule::Piece;
use crate::proof::verdict::Verdict;
use crate::proof::witness_runs::Speeds;

/// The format tag written into every scene certificate.
pub const SCENE_FORMAT: &str = "safereach-scene-certificate/5";

/// The proofs for one obstacle of the robot's lane.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ObstacleProofs {
    /// Its index in the scene.
    pub obstacle: usize,
    /// Its name (for readers; checked against the scene).
    pub name: String,
    /// Rigorous lower bound on its separation, rounded down (null: not proved).
    pub lower_bound: Option<f64>,
    /// One proof per own piece, in decomposition order.
    pub own: Vec<Proof>,
    /// One proof per bystander piece, ascending by step.
    pub bystanders: Vec<Proof>,
}

/// What made the robot brake in a bystander witness.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Trigger {
    /// The destination.
    Goal,
    /// Another obstacle (scene index) through one of its own pieces.
    Obstacle {
        /// Scene index of the obstacle that fired.
        obstacle: usize,
        /// Its piece.
        piece: Piece,
    },
}

/// A concrete worst-case behaviour of a scene, replayed exactly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SceneWitness {
    /// Scene index of the obstacle whose separation is the worst case.
    pub obstacle: usize,
    /// Its lane.
    pub lane: i32,
    /// The piece of that obstacle.
    pub piece: Piece,
    /// For a bystander piece: what made the robot brake.
    pub trigger: Option<Trigger>,
    /// Strict rows were kept this far inside.
    pub margin: f64,
    /// Speeds per obstacle (scene order) as constant-speed segments from period 0, the
    /// same form as a single-obstacle witness's; W_i after the last.
    pub obstacle_speeds: Vec<Speeds>,
    /// The replay collides.
    pub collides: bool,
    /// The obstacle's replayed separation, rounded down (null: it never stopped).
    pub separation: Option<f64>,
    /// The replayed trace, one row per obstacle per instant: only with `certify --steps`
    /// (it grows with the horizon; `check` replays the speeds either way and compares the
    /// rows when they are present).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<SceneTraceRow>,
}

/// The scene certificate file (and `certify --json` output for scenes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SceneCertificate {
    /// Always [`SCENE_FORMAT`].
    pub format: String,
    /// The verdict.
    pub verdict: Verdict,
    /// s* over every obstacle (m), inside its bracket [`lower_bound`, `witness.separation`]
    /// ([`crate::proof::separation`]); null when the robot may pass an obstacle unbraked or
    /// nothing pins it.
    ///
    /// [`lower_bound`]: SceneCertificate::lower_bound
    pub min_separation: Option<f64>,
    /// How wide the s* bracket may be (m): 1e-6, or for an inconclusive certificate the
    /// bracket's width rounded up when it is wider.
    pub separation_tolerance: f64,
    /// The worst case is an obstacle passing while the robot never brakes (s* = −∞).
    pub never_stops: bool,
    /// Rigorous lower bound on s*, rounded down (null: no finite bound is proved).
    pub lower_bound: Option<f64>,
    /// The clearance (m).
    pub clearance: f64,
    /// Premises of the verdict.
    pub premises: Vec<Premise>,
    /// The worst-case behaviour.
    pub witness: Option<SceneWitness>,
    /// The scene answered.
    pub scene: Scene,
    /// Proofs per obstacle of the robot's lane, in scene order.
    pub obstacles: Vec<ObstacleProofs>,
    /// Linear programs handed to the solver.
    pub programs_solved: usize,
    /// SHA-256 (hex) of this certificate serialised with an empty digest.
    pub digest: String,
}

impl SceneCertificate {
    /// SHA-256 of the certificate with an empty digest field.
    pub fn compute_digest(&self) -> String {
        let mut copy = self.clone();
        copy.digest.clear();
        crate::proof::digest::json_sha256(&copy)
    }

    /// Pieces proved, over every obstacle.
    pub fn pieces(&self) -> usize {
        self.obstacles
            .iter()
            .map(|o| o.own.len() + o.bystanders.len())
            .sum()
    }
}

/// The premises of a scene's verdict: the single-obstacle list with the scene's largest
/// moving speed bound (each obstacle's own bound is in the scene) and, for first detection,
/// the nearer of ρ and the nearest obstacle start.
pub fn scene_premises(scene: &Scene) -> Vec<Premise> {
    let nearest = scene
        .obstacles
        .iter()
        .map(|o| o.position.min())
        .fold(f64::INFINITY, f64::min);
    let problem = Problem {
        name: scene.name.clone(),
        robot: scene.robot.clone(),
        controller: scene.controller.clone(),
        environment: Environment {
            obstacle_speed: scene.largest_moving_bound(),
            initial_gap: crate::core::model::Position::At(if nearest.is_finite() {
                nearest
            } else {
                scene.controller.reaction_radius
            }),
        },
        sensing: scene.sensing.clone(),
    };
    premises(&problem)
}
