//! Proofs without a solver: the schedule decomposition into exact programs, the bounds that
//! dual multipliers prove, and the certificate format with its exact check.
//!
//! This layer compiles without Clarabel: a certificate is checked by rebuilding every piece
//! from the problem alone and recomputing every bound in exact rationals.

pub mod approach_closed_form;
pub mod certificate;
pub mod certificate_file;
pub mod check;
pub mod digest;
pub mod exact_speed_runs;
pub mod json_read;
pub mod occlusion_schedule;
pub mod planar;
pub mod premise;
pub mod program;
pub mod region_check;
pub mod region_map;
pub mod region_schedule;
pub mod scene_certificate;
pub mod scene_check;
pub mod scene_region_check;
pub mod scene_region_schedule;
pub mod scene_schedule;
pub mod scene_search;
pub mod schedule;
pub mod search_certificate;
pub mod search_check;
pub mod search_observations;
pub mod separation;
pub mod verdict;
pub mod witness_runs;
pub mod witness_schedule;
