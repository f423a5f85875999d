//! The model's semantics (DESIGN.md §1): the one step function every engine runs.
//!
//! A [`World`] holds the robot, the obstacle's gap and the observation history; its
//! [`World::step`] advances one control period given the obstacle's speed for that period.
//! The simulator, witness replay, the certificate checker and the explorer call it; the
//! analyser builds its robot trajectories from [`robot_motion`] and its guards from
//! [`danger_distance`], the same functions `step` uses.
//!
//! Facts the analyser relies on, each a property of this code and pinned by tests:
//! - the gap never increases (robot speed ≥ 0 forward, obstacle speed ≥ 0 towards it);
//! - while the robot accelerates or drives its speed never decreases, and `danger_distance`
//!   is nondecreasing in the speed, so guard thresholds only grow until the robot brakes;
//! - braking latches: once in Brake the robot slows at b until it rests (Stop), for good.
//!
//! The pieces, one idea a file: the robot's state ([`Mode`], [`RobotState`]), its motion
//! over one period ([`robot_motion`]), the controller's guard ([`guard`],
//! [`danger_distance`]), the world and its one step ([`World`]), and the multi-period step
//! that crosses many uniform periods at once ([`World::leap`]).

mod controller;
mod leap;
mod motion;
mod state;
#[cfg(test)]
pub(crate) mod tests;
mod within;
mod world;

pub use controller::{BrakeReason, Observation, danger_distance, guard};
pub use leap::{Leap, Watch};
pub use motion::{Motion, robot_motion};
pub use state::{Mode, RobotState};
pub use within::state_within;
pub use world::{StepRecord, World};
