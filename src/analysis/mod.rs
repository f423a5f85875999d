//! The analyser: schedule pieces -> programs -> Clarabel -> bounds, witnesses and verdicts;
//! and what is built on it: safe radius and largest safe speed, sweeps and reports.

mod analyse;
mod certify;
pub mod lp;
mod monte_carlo;
pub mod planar;
pub mod radius;
pub mod region;
pub mod region_lift;
pub mod region_search;
pub mod region_statement;
pub mod region_subject;
pub mod report;
pub mod scene;
pub mod scene_answer;
mod scene_monte_carlo;
pub mod scene_radius;
pub mod scene_region;
mod scene_witness;
pub mod scene_worst;
pub mod simplex;
pub mod sweep;
pub mod sweep_file;
pub mod sweep_planar;

pub use analyse::*;
pub use monte_carlo::{MonteCarlo, monte_carlo, monte_carlo_run, random_speeds};
pub use scene_monte_carlo::{
    LateObserver, ObstacleMonteCarlo, RandomBehaviour, SceneMonteCarlo, SpeedPattern,
    scene_monte_carlo, scene_monte_carlo_run,
};
