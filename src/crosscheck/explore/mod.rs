//! The exhaustive explorer: every behaviour of the *finite* model, breadth first.
//!
//! The seed paper verified its robot with UPPAAL: every behaviour of a finite model and a
//! safety query. This module is that check in Rust, as a second engine that holds the
//! analyser ([`crate::analysis`]) honest: it shares nothing with the analyser but the step
//! function [`World::step`], run in exact rationals ([`Exact`]), so no float ever decides a
//! guard, a collision or whether two states are the same.
//!
//! # The model (a model checker's vocabulary)
//!
//! - **Init states**: one per start, [`World::with_gap`] — the robot at its initial speed
//!   about to accelerate (or drive), the obstacle at the problem's initial gap; for a range
//!   `initial_gap = [g_min, g_max]`, at each of a finite set of starts (`--starts 5`, the
//!   default, is five evenly spaced gaps from g_min to g_max, both ends included): the
//!   environment's first choice, finite like its speeds.
//! - **Actions** ([`Choice`]): the obstacle's speed for the next control period, chosen
//!   from a finite [`SpeedSet`] ⊆ [0, W] (`--speeds 5` is {0, W/4, W/2, 3W/4, W}); with
//!   sensing noise, where this period's observation can both keep the guard quiet and make
//!   it fire, the error's aim (quiet or fire); with occlusion, while the obstacle is
//!   hidden and this period's observation shows a true gap ≥ d_det, whether it is first
//!   seen now or stays hidden. The actions of a state are listed in a fixed order
//!   (ascending speed, hidden before seen, quiet before fire): the search is deterministic,
//!   and so are its state count and its counterexample.
//! - **Next state**: [`World::step_with`] with that speed and aim, the obstacle hidden until
//!   it is first seen ([`World::hide_until`]) — the simulator's step function.
//! - **Property** (`always`): no step has its `collision` flag set, i.e. the robot is never
//!   moving with gap ≤ clearance (a robot that comes to rest inside a step is judged by its
//!   gap at the instant of rest, < clearance; DESIGN.md §1).
//! - **Counterexample**: the *shortest* path (fewest control periods) from the init state to
//!   a colliding step. Breadth-first search reaches every state first along a shortest path
//!   and every state keeps a parent pointer, so the path is read back from the pointers and
//!   replayed through [`simulate::run_choosing`] into the simulator's trace format.
//!
//! # Noise and occlusion as finite choices, exactly
//!
//! *Noise.* An observation's error enters nothing but its own step's guard
//! (docs/semantics.md §12): the observed gap and speed are read once, by the guard at the
//! step they are observed, and never again. Fix the obstacle's speeds. Then a run is
//! determined by the step T at which the robot brakes (or by its never braking), and T is
//! the first step whose guard fires. Given the guard outcomes before step k (all quiet),
//! the robot's speed at k is fixed, and the set of outcomes the errors of step k can give
//! is {quiet, fire} ∩ (what some error in [−σ_g, σ_g] × [−σ_w, σ_w] gives) — it depends on
//! the true gap and speed observed and that robot speed only. So the runs of all error
//! sequences are exactly the runs of all outcome sequences that pick, step by step, an
//! outcome some error allows: choosing "quiet" or "fire" per observation, where both are
//! possible, loses no behaviour and adds none. [`World::seen`] realises each choice with
//! one concrete error, and every step checks that the outcome it gives is the one chosen.
//!
//! *Occlusion.* A behaviour hides the obstacle for a prefix of the observations and first
//! shows it at a step K whose true observed gap is ≥ d_det. The explorer chooses, at each
//! step while hidden, to stay hidden or (where that gap is ≥ d_det) to show it; a hidden
//! state in which no observation to come can show a gap ≥ d_det (the first one that exists
//! already shows less; gaps never grow) has no admissible continuation, so it is *lost*:
//! neither it nor the step into it belongs to a behaviour, and neither is watched. (A step
//! into a state that is not lost belongs to the behaviour that shows the obstacle at the
//! next admissible step.) Each behaviour is one path, and each path one behaviour.
//!
//! *Starts.* A range is explored at its listed starts only, as the speeds are: the answer
//! covers exactly the behaviours of the finite model, never the range's points between.
//!
//! Besides the verdict, the search reports the minimum separation over all explored
//! behaviours, with the analyser's meaning: the gap at the instant the robot comes to rest,
//! minimised over every behaviour, and −∞ if some behaviour never brakes. The search goes on
//! past a collision (the semantics lets the obstacle pass through the robot) so that this
//! minimum covers colliding behaviours too.
//!
//! # States: what is stored, and why it is exact
//!
//! Visited states are stored in full in a hash map keyed by a [`StateKey`]; equality is
//! decided on the whole key, never on a hash. The key leaves out what cannot change any
//! future guard, collision or separation — each omission below is exact (two states with the
//! same key have the same futures, step for step), so the abstraction merges states without
//! losing or inventing a behaviour:
//!
//! 1. **The robot's absolute position.** [`World::step`] uses the position only through the
//!    distance travelled in the step, `end.position − start.position`, which in exact
//!    rationals is the same number from every start ([`crate::core::semantics::robot_motion`]
//!    adds the travelled distance to the start; in floats it would not be). Guards read
//!    gaps, never positions. The robot's speed and mode and the current gap stay, exactly:
//!    they determine every later gap.
//! 2. **The step index k.** It matters only for "no observation before L" and "observed
//!    speed 0 before the first step"; both are encoded in the pending observations (3).
//! 3. **The observation history, reduced to what the robot will still act on.** At step k
//!    the robot acts on the gap L periods ago and the speed of the period before that. The
//!    key holds, for each of the next L steps, the *verdict* that observation will give:
//!    which outcomes some error allows, (fire-able, quiet-able). For a true gap g, a
//!    measured speed that some error shows above V_a (*fast*, wrong-assumption guard on)
//!    or at or below it (*slow*), and θ(v) = min(ρ, d_coll(v)): fire-able iff some
//!    observed gap in [g − σ_g, g + σ_g] lies in (0, ρ] if fast, in (0, θ(v)] if not;
//!    quiet-able iff g − σ_g ≤ 0 (seen as passed) or g + σ_g exceeds θ(v) if slow, ρ if not.
//!    The robot's speed v only grows until it brakes and never passes v_max, and θ is
//!    nondecreasing in v, so fire-ability only appears and quiet-ability only disappears
//!    on the way from the current speed to v_max. Hence:
//!    - *quiet*, *fires*, *either*: the same pair at the current speed and at v_max, so at
//!      every speed the robot can have when it acts (quiet also stands for "no observation
//!      yet"; *either* occurs only with noise);
//!    - *near(gap, fast, slow)*: otherwise; the pair depends on the robot's speed at that
//!      step, so the exact gap and the speed's two bits are kept.
//!
//!    Without noise these are the classes of the noise-free explorer (fast and slow
//!    exclude each other, *either* never occurs), so its state counts are unchanged. The
//!    brake *reason* is dropped: after Brake both reasons have the same future. Plus the
//!    last period's two bits (fast, slow), kept only while the current gap can be seen in
//!    the area, −σ_g < g ≤ ρ + σ_g (it is observed together with the current gap, L periods
//!    from now; outside that band neither bit changes its verdict). The speed observed
//!    before the first period has ended is exactly 0: slow, never fast.
//!
//!    With occlusion, while the obstacle is hidden, the key also holds a *hidden* mark and,
//!    for each pending observation, whether it exists and whether its true gap is ≥ d_det
//!    (where it may first show the obstacle); once seen, these are dropped (a seen obstacle
//!    stays seen). Without occlusion nothing is hidden and the key is the noise-free one.
//! 4. **Everything but gap and speed once the robot brakes** (Brake latches, guards are no
//!    longer evaluated), and **everything once it rests** (Stop is final: one state).
//!
//! Every step checks the abstraction against the real thing: the guard the key predicts for
//! the step must be the guard [`World::step`] evaluated, or the search stops with
//! [`ExploreError::Inconsistent`].
//!
//! A state whose robot still accelerates or drives, whose obstacle is seen, whose gap is
//! ≤ −σ_g and whose pending observations are all quiet is *terminal*: no later observation
//! can be seen in the area (gaps never grow), so the robot never brakes and the minimum
//! separation is −∞. Such a state is only reached through a colliding step. A hidden
//! obstacle's paths end where it is lost. With these cuts every path is finite, so the
//! search ends.
//!
//! A state budget ([`Options::max_states`]) bounds memory: when it is reached the search
//! stops with the verdict `inconclusive` (or `collision`, if one was already found).
//!
//! # Where things are
//!
//! - `speeds`: the finite speed set (the actions) and how `--speeds` is read;
//! - `starts`: the finite set of starts in a range of initial gaps (`--starts`);
//! - `observe`: what an observation still to come allows the guard to do (noise), and
//!   whether it may first show a hidden obstacle (occlusion);
//! - `model`: the states, their exact keys and the finite model's transitions;
//! - `search`: the breadth-first search over the model (one search for this layer,
//!   `crosscheck::bfs`), what it watches, and the paths it replays;
//! - [`scene`]: the same for scenes (several obstacles, lanes, lane changes, a goal).
//!
//! [`World::step`]: crate::core::semantics::World::step
//! [`World::with_gap`]: crate::core::semantics::World::with_gap
//! [`World::step_with`]: crate::core::semantics::World::step_with
//! [`World::seen`]: crate::core::semantics::World::seen
//! [`World::hide_until`]: crate::core::semantics::World::hide_until
//! [`Exact`]: crate::core::num::Exact
//! [`simulate::run_choosing`]: crate::core::simulate::run_choosing

use serde::{Deserialize, Serialize};

mod model;
mod observe;
pub mod scene;
mod search;
mod speeds;
mod starts;
mod window;

pub use model::{Choice, FiniteModel, State, StateKey, Status, Transition};
pub use search::{Exploration, Path, explore, explore_model};
pub use speeds::{SpeedSet, show_exact};
pub use starts::{DEFAULT_STARTS, MAX_STARTS};

use crate::core::budget::Work;

/// Default state budget: under 1 GB of memory at the measured 320–450 bytes per state (and
/// [`Options::max_memory`] lowers it for larger states).
pub const DEFAULT_MAX_STATES: usize = 2_000_000;

/// Largest `--speeds N` accepted (the number of actions per state).
pub const MAX_SPEEDS: usize = 1000;

/// Errors of the explorer that are not verdicts.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExploreError {
    /// The speed set is empty, malformed or outside [0, W].
    #[error("--speeds {spec}: {reason}")]
    Speeds {
        /// The set as given.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The options are unusable (a zero state budget).
    #[error("{0}")]
    Options(String),
    /// The state abstraction disagreed with the step function, or a path failed to replay.
    /// A bug, reported rather than hidden.
    #[error("internal inconsistency: {0}")]
    Inconsistent(String),
}

/// Search options.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// Stop with `inconclusive` once this many distinct states are stored.
    pub max_states: usize,
    /// Memory budget of the stored states (bytes): the state limit is lowered to what fits
    /// at [`PROBLEM_STATE_BYTES`] or, for a scene, [`bytes_per_state`] each (a long latency
    /// makes every scene state large).
    pub max_memory: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_states: DEFAULT_MAX_STATES,
            max_memory: Work::ExploreMemory.default_limit(),
        }
    }
}

impl Options {
    /// The most states stored: `max_states`, or fewer when that many states of
    /// `bytes_per_state` bytes would pass `max_memory` (at least 1).
    pub fn state_limit(&self, bytes_per_state: u64) -> usize {
        let fit = self.max_memory / bytes_per_state.max(1);
        self.max_states
            .min(usize::try_from(fit).unwrap_or(usize::MAX))
            .max(1)
    }
}

/// Why a search stopped short, and what raises it: the state budget, or the memory budget
/// when that held fewer states (`state_limit` < `options.max_states`).
pub fn budget_reached(states: usize, state_limit: usize, options: &Options) -> String {
    if state_limit < options.max_states {
        format!(
            "memory budget reached ({states} states; {} MiB holds {state_limit} states of \
             this model's size); raise --max-memory, or use fewer --speeds",
            options.max_memory >> 20
        )
    } else {
        format!("state budget reached ({states} states); raise --max-states or use fewer --speeds")
    }
}

/// Bytes a stored state of a problem's model takes, over-estimated, whatever the latency:
/// its pending observations and the world's history are shared with the states along its
/// path, so each state adds one node of each (~600 bytes a state measured, peak RSS over
/// states, at latency 1 and at latency 999 alike).
pub const PROBLEM_STATE_BYTES: u64 = 1024;

/// Bytes a stored scene state takes, over-estimated: ~450 measured for the seed's small
/// latencies, plus ~57 per pending observation (latency 999 measured 57 KB per state; 72
/// counted, for the search's own overhead), each kept in the state and in its key, per
/// moving obstacle.
pub fn bytes_per_state(latency: usize, obstacles: usize) -> u64 {
    let obstacles = obstacles.max(1) as u64;
    obstacles.saturating_mul(512u64.saturating_add((latency as u64).saturating_mul(72)))
}

/// The explorer's three-valued answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "lowercase")]
pub enum ExploreVerdict {
    /// Every behaviour of the finite model was explored; none collides.
    Safe,
    /// Some behaviour collides (a counterexample path is given).
    Collision,
    /// The state budget ran out before either was established.
    Inconclusive,
}

impl ExploreVerdict {
    /// The word used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            ExploreVerdict::Safe => "safe",
            ExploreVerdict::Collision => "collision",
            ExploreVerdict::Inconclusive => "inconclusive",
        }
    }
}
