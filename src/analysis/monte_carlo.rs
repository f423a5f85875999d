//! Monte Carlo over random obstacle behaviours: the seed paper's measure of safety, kept as
//! a cross-check beside the proofs (a certified problem must never collide here). With
//! sensing noise every error keeps the robot from reacting as far as it can
//! ([`crate::core::semantics::World::step`]); with occlusion every other run (the odd ones)
//! keeps the obstacle hidden as late as the premise allows
//! ([`crate::core::simulate::run_hiding_late`]), the even ones show it from the start.
//!
//! The runs step the semantics in the number type of the parameters they are given. In
//! exact numbers ([`crate::core::rational::Rational`], what `simulate` uses) each drawn speed
//! is the decimal its float prints as, and every guard decides exactly as a replay does: in
//! floats a robot position that lies exactly on a danger threshold (a static obstacle, a
//! decimal start) can round past it, fire a period late and come closer than the certified
//! s*. Floats remain for speed where only collisions are counted.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::core::model::Params;
use crate::core::num::Scalar;
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

/// [`random_speeds`] as numbers of type `N`: each float read as the decimal it prints as
/// ([`Scalar::decimal`]), which lies in (0, W] as the float does.
fn random_speeds_as<N: Scalar>(w: f64, seed: u64, i: usize) -> impl FnMut(usize) -> N {
    let mut speeds = random_speeds(w, seed, i);
    move |k| N::decimal(speeds(k))
}

/// The parameters as floats, for the horizon and the speed bound the draws scale.
fn floats<N: Scalar>(params: &Params<N>) -> Params<f64> {
    params.map(Scalar::as_f64)
}

/// Monte Carlo run `i`: [`random_speeds`], and with occlusion, for odd `i`, the obstacle
/// hidden as late as the premise allows. `simulate --trace` replays the closest run so.
pub fn monte_carlo_run<N: Scalar>(
    params: &Params<N>,
    seed: u64,
    i: usize,
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    let speeds = random_speeds_as(floats(params).W, seed, i);
    if params.d_det.is_some() && i % 2 == 1 {
        run_hiding_late(params.clone(), speeds, max_steps, stop_at_collision)
    } else {
        run(params.clone(), speeds, max_steps, stop_at_collision)
    }
}

/// Simulates `runs` random obstacle behaviours, in the number type of `params` (exact ones
/// decide every guard as a replay does).
pub fn monte_carlo<N: Scalar>(params: &Params<N>, runs: usize, seed: u64) -> MonteCarlo {
    let max = horizon(&floats(params));
    let mut least = params.g0.clone();
    let mut summary = MonteCarlo {
        runs,
        collisions: 0,
        min_separation: least.as_f64(),
        seed,
        closest_run: 0,
    };
    for i in 0..runs {
        let run = monte_carlo_run(params, seed, i, max, true);
        if run.outcome.collided {
            summary.collisions += 1;
        }
        if let Some(g) = run.outcome.min_moving_gap
            && g < least
        {
            summary.min_separation = g.as_f64();
            least = g;
            summary.closest_run = i;
        }
    }
    summary
}
