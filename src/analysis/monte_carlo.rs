//! Monte Carlo over random obstacle behaviours: the seed paper's measure of safety, kept as
//! a cross-check beside the proofs (a certified problem must never collide here). With
//! sensing noise every error keeps the robot from reacting as far as it can
//! ([`crate::core::semantics::World::step`]); with occlusion every other run (the odd ones)
//! keeps the obstacle hidden as late as the premise allows
//! ([`crate::core::simulate::run_hiding_late`]), the even ones show it from the start.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::core::model::Params;
use crate::core::simulate::{Run, horizon, run, run_hiding_late};

/// Monte Carlo summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct MonteCarlo {
    /// Runs simulated.
    pub runs: usize,
    /// Runs that collided.
    pub collisions: usize,
    /// Lowest gap seen while the robot moved, over all runs (m).
    pub min_separation: f64,
    /// Seed of the first run; run i uses seed + i.
    pub seed: u64,
    /// Index of the run that came closest.
    pub closest_run: usize,
}

/// The obstacle speeds of Monte Carlo run `i`: uniform in (0, W] each period, from a
/// ChaCha8 stream seeded with `seed + i` (reproducible across platforms and releases).
pub fn random_speeds(w: f64, seed: u64, i: usize) -> impl FnMut(usize) -> f64 {
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(i as u64));
    move |_| w * (1.0 - rng.random::<f64>())
}

/// Monte Carlo run `i`: [`random_speeds`], and with occlusion, for odd `i`, the obstacle
/// hidden as late as the premise allows. `simulate --trace` replays the closest run so.
pub fn monte_carlo_run(
    params: &Params<f64>,
    seed: u64,
    i: usize,
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<f64> {
    let speeds = random_speeds(params.W, seed, i);
    if params.d_det.is_some() && i % 2 == 1 {
        run_hiding_late(params.clone(), speeds, max_steps, stop_at_collision)
    } else {
        run(params.clone(), speeds, max_steps, stop_at_collision)
    }
}

/// Simulates `runs` random obstacle behaviours.
pub fn monte_carlo(params: &Params<f64>, runs: usize, seed: u64) -> MonteCarlo {
    let max = horizon(params);
    let mut summary = MonteCarlo {
        runs,
        collisions: 0,
        min_separation: params.g0,
        seed,
        closest_run: 0,
    };
    for i in 0..runs {
        let run = monte_carlo_run(params, seed, i, max, true);
        if run.outcome.collided {
            summary.collisions += 1;
        }
        if let Some(g) = run.outcome.min_moving_gap
            && g < summary.min_separation
        {
            summary.min_separation = g;
            summary.closest_run = i;
        }
    }
    summary
}
