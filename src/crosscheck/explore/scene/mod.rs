//! The exhaustive explorer over scenes: every joint behaviour of a scene's *finite* model,
//! breadth first — the single-obstacle explorer ([`super`]) for several obstacles, lanes,
//! lane changes and a destination (DESIGN.md §1.1).
//!
//! Like the single-obstacle explorer it shares nothing with the analyser but the step
//! function, here the scene's [`SceneWorld::step`], run in exact numbers ([`Rational`]):
//! no float decides a guard, a lane change, a collision or whether two states are the same.
//!
//! # The model
//!
//! - **Init states**: the scene at t = 0 ([`SceneWorld::new`]) from every combination of
//!   obstacle starts: an obstacle's position, or both ends of its range (a range is sampled
//!   at its ends, as speeds are sampled by a finite set).
//! - **Actions**: one speed per obstacle for the next period, obstacle i's from its own
//!   finite set ⊆ [0, W_i] ([`SceneSpeeds`]; by default {0, W_i}). The joint actions of a
//!   state are listed in a fixed order (obstacle 0's choice varying slowest, each set
//!   ascending), so the search, its state count and its counterexample are deterministic.
//! - **Next state**: [`SceneWorld::step`] with those speeds (with noise or occlusion,
//!   [`SceneWorld::step_seeing`] with the chosen looks: "Noise and occlusion" below).
//! - **Property** (`always`): no period has an obstacle's collision flag set (the robot
//!   moving in its lane with separation ≤ clearance, §1.1 "Safety").
//! - **Counterexample**: a shortest path (fewest periods) to a colliding period, replayed
//!   from scratch through [`simulate::replay_exact_speeds`] (the exact-speed twin of
//!   `simulate::replay`); it must collide in its last period.
//!
//! Besides the verdict it reports, per obstacle, the least separation sep_i over every
//! explored behaviour, exactly. A behaviour's sep_i is the infimum of its periods' shares
//! ([`ObstacleStep::safety`]), so the least over behaviours is the least share over every
//! transition computed; the search goes on past collisions (obstacles pass through the
//! robot) so that colliding behaviours count too. Every obstacle's least separation comes
//! with the path that realises it, replayed from scratch to that very number.
//!
//! # When a branch ends
//!
//! A branch ends at a state that is
//! - **stopped**: the robot rests for good;
//! - **settled** ([`SceneWorld::settled`], after the first period, as `simulate::run`):
//!   nothing can happen any more;
//! - **never braking**: no goal, the robot accelerating or driving, no lane change under
//!   way, and every obstacle of its lane observed at a gap ≤ 0. Observed gaps never grow,
//!   so no obstacle becomes relevant again, no guard fires again, the robot stays in its
//!   lane and drives on for ever; an obstacle of its lane whose occupancy interval began
//!   with it ahead then has a gap that falls without bound: sep_i = −∞ (`unbounded`). (It
//!   is not settled, so there is such an obstacle, and the robot has already passed
//!   through it: a collision.)
//!
//! Every other branch goes on. Every branch ends within [`simulate::horizon`] periods
//! (the robot passes every obstacle or reaches its goal and stops; what remains after that
//! is a pass-through, cut as never braking). As a guard, a state still running at the
//! horizon is not expanded and the search reports itself incomplete (`inconclusive`,
//! never `safe`). So does a state budget ([`Options::max_states`]), as in the
//! single-obstacle explorer; a collision found before either is still a collision.
//!
//! # States: what is stored, and why it is exact
//!
//! Visited states are keyed by a [`SceneKey`], stored and compared in full (exact rationals
//! in canonical form, never only hashes). The key is read from the world itself, and leaves
//! out only what no later guard, lane change, collision or separation reads:
//!
//! 1. **The robot's position**, unless the scene has a goal (the destination guard reads
//!    it). The step function uses it otherwise only through the distance travelled, which
//!    in exact numbers is the same from every start.
//! 2. **The step index k**, beyond min(k, L+1): it decides only whether observations have
//!    begun and whether the observed speed is still the initial 0; a lane change under way
//!    is keyed by the periods it still lasts.
//! 3. **Observation history, beyond how it will be read**: the oldest remembered gap is
//!    never observed again (the newest L are). A remembered gap beyond ρ is kept as
//!    "far": it is never relevant, a lane with it is free, seen or beyond the sensing range
//!    R ≥ ρ alike, and it is not ≤ 0. Without lane changes a remembered gap ≤ 0 is kept as
//!    "passed" (never relevant, and only "≤ 0" is asked of it). A remembered speed is read
//!    only by the wrong-assumption guard, only as "faster than V_a", only for a moving
//!    obstacle, and only when the gap observed with it (the gap at the start of the next
//!    period) is relevant, in (0, ρ]: that one bit is kept.
//! 4. **Once the robot brakes**: guards are never evaluated again (Brake latches), so only
//!    its speed, the lane change still under way, and the gap and occupancy side of the
//!    obstacles in the lanes it still occupies matter.
//! 5. **Ended states**: one key per kind (their futures are not explored).
//!
//! # Obstacles that cannot matter
//!
//! Without lane changes the robot stays in lane 0 for ever: an obstacle of another lane is
//! never in an occupied lane, never relevant to a guard, and (no lane change) never looked
//! at by the free-lane test. Its speeds and start change nothing but its own record, so it
//! is given one speed (the least of its set) and one start (its nearest), and left out of
//! the keys; its separation is None (the robot never moves in its lane). With lane changes
//! on every obstacle matters.
//!
//! # Noise and occlusion
//!
//! With `[sensing]` the environment also chooses what the robot is shown (docs/semantics.md
//! §12, per obstacle and per observation), as finite choices:
//!
//! - **Errors**: each observation of an obstacle that matters is shown with a gap error in
//!   {0, −σ_g, +σ_g} and a speed error in {0, −σ_w, +σ_w} (none on the speed read before any
//!   period has ended, which is the initial 0). These are a finite subset of the errors the
//!   semantics allows, as the speed sets are of the speeds: what the explorer finds is a
//!   real behaviour, and it may miss behaviours that need an error strictly inside ±σ.
//! - **Occlusion**: every obstacle starts hidden; at each observation while the robot
//!   accelerates or drives, a hidden obstacle stays hidden or, where the true observed gap
//!   is ≥ d_det, is first shown. A hidden state whose next observation already shows a true
//!   gap below d_det can never show it (gaps never grow): it is *lost*, and neither it nor
//!   the step into it is watched. Once the robot brakes no guard reads an observation
//!   again, so the hidden marks are dropped (the behaviour shows the obstacle at its next
//!   observation, which is ≥ d_det since the state is not lost).
//! - **Grouping**: an observation is read by its own step's guard only, so the combinations
//!   of looks of a state are grouped by the command they make the guard give and by which
//!   obstacles stay hidden; one combination per group is explored (the exact observation
//!   first, so reported paths err only where an error changed the guard).
//! - **Far observations**: an observation that every error shows beyond ρ is read by no
//!   guard and no free-lane test, so it is shown exactly, and a hidden obstacle stays hidden
//!   through it when the following observation (known for L ≥ 1) still shows a true gap
//!   ≥ d_det — showing it then instead changes no step — and is shown when it does not
//!   (with L = 0, where the following one is not known yet, both are explored).
//!
//! The keys then keep what the choices read: remembered gaps beyond max(ρ + σ_g, d_det) as
//! "far" (every shown value is beyond ρ, and a hidden obstacle may still be shown there),
//! ≤ −σ_g as "passed" without lane changes, others exactly; for each remembered speed
//! whether some error shows it above V_a and whether some shows it at or below; and the
//! hidden mark. Every reported path carries its observations ([`ScenePath::plan`]: first
//! sightings and errors) and is replayed from scratch with them.
//!
//! # Where things are
//!
//! - `speeds`: each obstacle's finite speed set and how `--speeds` is read for a scene;
//! - `key`: the exact state keys;
//! - `model`: init states, joint actions, transitions, when a branch ends;
//! - `search`: the breadth-first search, what it watches, the replayed paths.
//!
//! [`SceneWorld::step`]: crate::core::scene::SceneWorld::step
//! [`SceneWorld::new`]: crate::core::scene::SceneWorld::new
//! [`SceneWorld::step_seeing`]: crate::core::scene::SceneWorld::step_seeing
//! [`SceneWorld::settled`]: crate::core::scene::SceneWorld::settled
//! [`ObstacleStep::safety`]: crate::core::scene::ObstacleStep::safety
//! [`Rational`]: crate::core::rational::Rational
//! [`simulate::replay_exact_speeds`]: crate::core::scene::simulate::replay_exact_speeds
//! [`simulate::horizon`]: crate::core::scene::simulate::horizon
//! [`Options::max_states`]: super::Options::max_states

mod key;
mod model;
mod search;
mod speeds;

pub use key::SceneKey;
pub use model::{
    Look, MAX_JOINT_ACTIONS, MAX_LOOK_COMBINATIONS, SceneModel, SceneMoves, SceneState,
    SceneStatus, SceneTransition,
};
pub use search::{
    ObstacleExploration, SceneExploration, ScenePath, explore_scene, explore_scene_model,
};
pub use speeds::SceneSpeeds;

/// Default state budget for scenes: under 1 GB of memory at the measured 1.15 KB per state
/// (problems/scene-oncoming.toml: keys, and the worlds still to expand).
pub const DEFAULT_SCENE_MAX_STATES: usize = 600_000;
