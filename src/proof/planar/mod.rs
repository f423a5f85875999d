//! The plane's lower bounds, solver-free (docs/reductions.md §11; issue 36): the robot's
//! motion under a brake step, the convex covers of a guard's outside, and one leaf's
//! second-order cone program, whose exact Neumaier–Shcherbina bound `check` can recompute.

pub mod cover;
pub mod domain;
pub mod leaf;
pub mod trajectory;
