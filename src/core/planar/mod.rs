//! Planar problems (docs/semantics.md §13, issue 36): a robot disc on a path, obstacle discs
//! from any direction, Euclidean separation.
//!
//! The exact geometry they are decided with is [`crate::core::plane`]; this module holds the
//! problem (its exact numbers, [`PlanarParams`]), one concrete adversary choice
//! ([`PlanarBehaviour`]) and its exact replay ([`run`], [`PlanarReplay`]): guards, motion
//! along the path, and each obstacle's least separation inside steps as an exact bracket.

mod behaviour;
mod observe;
mod params;
mod phases;
mod pieces;
mod replay;
mod separation;

pub use behaviour::{BehaviourError, ObstacleBehaviour, PlanarBehaviour};
pub use params::{DangerZone, PlanarObstacle, PlanarParams, PlanarSensing, Start};
pub use phases::{Phase, motion_phases};
pub use pieces::{PathPiece, path_pieces};
pub use replay::{BrakeEvent, PlanarGuard, PlanarReplay, PlanarRun, StepChoice, run};
pub use separation::Separation;
