//! Scenes with lane changes: an exact search over the runs the controller can tell apart.
//!
//! The schedule decomposition ([`crate::proof::scene_schedule`]) composes single-obstacle
//! pieces; a lane change couples the obstacles more tightly (danger in one lane, a free
//! neighbour, the time test, the lanes the robot then occupies), so scenes with lane
//! changes (and obstacles whose start is a range) are decided here instead, without a
//! solver:
//!
//! - **Runs** ([`tree`]): until it brakes the robot follows the drive profile, and at each
//!   step the controller distinguishes only finitely many *cells* of each observation
//!   ([`cells`]). Branching on the reachable cells enumerates every run: its lane changes,
//!   its brake step and reason, or that it drives on for ever.
//! - **Obstacles** ([`chain`]): a run constrains each obstacle only through intervals of its
//!   position at single steps and of single speeds, and its speeds are independent, so
//!   what a run leaves possible of its position at any step is an interval, computed
//!   exactly forwards and backwards.
//! - **Separation** ([`leaf`]): per obstacle and occupancy interval of its lane, the worst
//!   gap (ahead) or −gap (behind) is an end of such an interval.
//!
//! Every number is an exact rational and every choice is a case split that covers all
//! behaviours, so s* is exact. The proof is in docs/reductions.md §7.

pub mod cells;
pub mod chain;
mod dominance;
pub mod interval;
pub mod leaf;
pub mod sense;
pub mod tree;

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::Scene;
use crate::core::scene::SceneParams;
use crate::core::scene::simulate;

use chain::Extra;
use leaf::{BrakeCurves, Motion, Objective, Worst, WorstMemo};
pub use tree::SearchOptions;
use tree::{Leaf, Profile, TreeError, TreeStats, walk};

/// At most this many step starts are expanded.
pub const NODE_BUDGET: usize = 2_000_000;

/// One obstacle's worst-case separation over the whole scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Separation {
    /// The robot never moves in its lane: nothing to measure (+∞).
    Unmeasured,
    /// The exact infimum.
    Finite(Rational),
    /// −∞: the robot can keep moving in its lane with it ahead for ever.
    Unbounded,
}

/// The run and obstacle of the worst case.
#[derive(Clone, Debug)]
pub struct WorstRun {
    /// The obstacle (scene index).
    pub obstacle: usize,
    /// Its worst case in the run.
    pub worst: Worst,
    /// The run.
    pub leaf: Leaf,
    /// The robot's motion in it.
    pub motion: Motion,
}

/// The search's answer.
#[derive(Clone, Debug)]
pub struct SceneSearch {
    /// Per obstacle (scene order).
    pub obstacles: Vec<Separation>,
    /// The overall worst case (None: the robot never moves in an obstacle's lane).
    pub worst: Option<WorstRun>,
    /// What the search did.
    pub stats: TreeStats,
}

impl SceneSearch {
    /// s* (None: −∞ or nothing measured; see [`Self::unbounded`]).
    pub fn min_separation(&self) -> Option<&Rational> {
        self.worst.as_ref().and_then(|w| w.worst.value.as_ref())
    }

    /// Whether s* = −∞.
    pub fn unbounded(&self) -> bool {
        self.worst.as_ref().is_some_and(|w| w.worst.value.is_none())
    }
}

/// Searches every run of a (validated) scene.
pub fn search_scene(scene: &Scene) -> Result<SceneSearch, TreeError> {
    search_scene_with(scene, SearchOptions::default())
}

/// [`search_scene`] searching as `how` asks: the same answers whatever it asks, slower
/// without the shortcuts. For tests of the lemmas behind them.
pub fn search_scene_with(scene: &Scene, how: SearchOptions) -> Result<SceneSearch, TreeError> {
    let p: SceneParams<Rational> = scene
        .params::<crate::core::num::Exact>()
        .map(Rational::from_exact);
    let horizon = simulate::horizon(&p.map(|x| x.as_f64()));
    let mut profile = Profile::new(&p);
    let mut per: Vec<Option<Worst>> = vec![None; p.obstacles.len()];
    let mut overall: Option<WorstRun> = None;
    let mut curves = BrakeCurves::new();
    let mut worsts = WorstMemo::for_scene(&p);
    let stats = walk(
        &p,
        &mut profile,
        horizon,
        NODE_BUDGET,
        how,
        |leaf, profile| {
            let motion = &Motion::of_with(&p, profile, &leaf.ending, &mut curves);
            let of_leaf = worsts.of_leaf(&p, profile, leaf, motion);
            for (i, (slot, w)) in per.iter_mut().zip(of_leaf).enumerate() {
                let Some(w) = w else {
                    continue;
                };
                if overall.as_ref().is_none_or(|o| w.below(&o.worst)) {
                    overall = Some(WorstRun {
                        obstacle: i,
                        worst: w.clone(),
                        leaf: leaf.clone(),
                        motion: motion.clone(),
                    });
                }
                if slot.as_ref().is_none_or(|s| w.below(s)) {
                    *slot = Some(w);
                }
            }
        },
    )?;
    let obstacles = per
        .into_iter()
        .map(|w| match w {
            None => Separation::Unmeasured,
            Some(Worst { value: None, .. }) => Separation::Unbounded,
            Some(Worst { value: Some(v), .. }) => Separation::Finite(v),
        })
        .collect();
    Ok(SceneSearch {
        obstacles,
        worst: overall,
        stats,
    })
}

/// A behaviour of the worst run: each obstacle's start and its speeds (W_i after the
/// last). The worst obstacle is placed within `slack` of its infimum (at it when that is
/// attained); every other obstacle is chosen away from the run's boundaries.
pub fn worst_behaviour(
    scene: &Scene,
    run: &WorstRun,
    slack: &Rational,
) -> Option<(Vec<Rational>, Vec<Vec<Rational>>)> {
    let p: SceneParams<Rational> = scene
        .params::<crate::core::num::Exact>()
        .map(Rational::from_exact);
    let mut profile = Profile::new(&p);
    let mut starts = Vec::new();
    let mut speeds = Vec::new();
    for (i, chain) in run.leaf.chains.iter().enumerate() {
        let mut extra: Vec<Extra> = Vec::new();
        if i == run.obstacle {
            let start = match &run.worst.objective {
                Objective::Ahead { interval, .. }
                | Objective::Unbounded { interval }
                | Objective::Behind { interval } => interval.start,
            };
            let at_start = run.motion.position(&p, &mut profile, start);
            extra.push(run.worst.side(&at_start));
            match &run.worst.objective {
                Objective::Ahead { step, .. } => {
                    let x = chain.marginal(*step, &extra);
                    extra.push(Extra {
                        step: *step,
                        position: interval::Interval::point(x.near_lower(slack)?),
                    });
                }
                Objective::Behind { .. } => {
                    let x = chain.marginal(start, &extra);
                    extra.push(Extra {
                        step: start,
                        position: interval::Interval::point(x.near_upper(slack)?),
                    });
                }
                Objective::Unbounded { .. } => {}
            }
        }
        let (x0, ws) = chain.sample(&extra)?;
        starts.push(x0);
        speeds.push(ws);
    }
    Some((starts, speeds))
}
