//! Planar problems (docs/semantics.md §13, issue 36): a robot disc on a path, obstacle discs
//! from any direction, Euclidean separation.
//!
//! The exact geometry they are decided with is [`crate::core::plane`]; this module holds the
//! problem: the file as read ([`PlanarProblem`], §13.10) and its exact numbers
//! ([`PlanarParams`], [`PlanarProblem::params`]); one concrete adversary choice
//! ([`PlanarBehaviour`]) and its exact replay ([`run`], [`PlanarReplay`], §13.11): guards,
//! motion along the path, and each obstacle's least separation inside steps as an exact
//! bracket.
//!
//! # Planar problem files
//!
//! A file with a top-level `[plane]` table is a planar problem. [`PlanarProblem::load`],
//! [`PlanarProblem::load_with_overrides`] and [`PlanarProblem::from_toml_str`] read it as
//! strictly as a problem is read (the same machinery, the same [`ProblemError`]s naming the
//! file or `--set`, the key, the reason and the line): its `[robot]` and `[controller]` are a
//! problem's, validated by the same rules, plus the planar keys; an obstacle's key is named
//! by index and name, `obstacle[1] ("car").region`, and set by index,
//! `--set obstacle.1.max_speed=12`.
//!
//! [`ProblemError`]: crate::core::model::ProblemError

mod behaviour;
mod exact;
mod fields;
mod file;
pub(crate) mod keys;
mod observe;
mod params;
mod phases;
mod pieces;
mod read;
mod replay;
mod separation;
mod shape;
mod validate;

pub use behaviour::{BehaviourError, ObstacleBehaviour, PlanarBehaviour};
pub use exact::{AXIS_LENGTH, DEFAULT_DIRECTION_TOLERANCE};
pub use file::{
    PlanarObstacleFile, PlanarProblem, PlanarRobot, PlanarSensingFile, StartFile, Zone,
};
pub use params::{DangerZone, PlanarObstacle, PlanarParams, PlanarSensing, Start};
pub use phases::{Phase, motion_phases};
pub use pieces::{PathPiece, path_pieces};
pub use replay::{BrakeEvent, PlanarGuard, PlanarReplay, PlanarRun, StepChoice, run, run_observed};
pub use separation::Separation;
