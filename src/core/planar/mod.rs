//! Planar problems (docs/semantics.md §13, issue 36): a robot disc on a path, obstacle discs
//! from any direction, Euclidean separation.
//!
//! The exact geometry they are decided with is [`crate::core::plane`]; this module holds the
//! problem: its exact numbers ([`PlanarParams`]).

mod params;

pub use params::{DangerZone, PlanarObstacle, PlanarParams, PlanarSensing, Start};
