//! The plane's lower bounds, solver-free (docs/reductions.md §11; issue 36): the robot's
//! motion under a brake step, the convex covers of a guard's outside, one leaf's
//! second-order cone program, whose exact Neumaier–Shcherbina bound `check` recomputes, and
//! the planar certificate with its exact check.

pub mod certificate;
pub mod check;
pub mod cover;
pub mod domain;
pub mod exact_text;
pub mod leaf;
pub mod region;
pub mod tiling;
pub mod trajectory;
pub mod witness_record;
