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
//! - **Init states**: one, [`World::new`] — the robot at rest about to accelerate, the
//!   obstacle at the problem's initial gap.
//! - **Actions**: the obstacle's speed for the next control period, chosen from a finite
//!   [`SpeedSet`] ⊆ [0, W] (`--speeds 5` is {0, W/4, W/2, 3W/4, W}). The actions of a state
//!   are listed in ascending speed order, always the same: the search is deterministic, and
//!   so are its state count and its counterexample.
//! - **Next state**: [`World::step`] with that speed — the simulator's step function.
//! - **Property** (`always`): no step has its `collision` flag set, i.e. the robot is never
//!   moving with gap ≤ clearance (a robot that comes to rest inside a step is judged by its
//!   gap at the instant of rest, < clearance; DESIGN.md §1).
//! - **Counterexample**: the *shortest* path (fewest control periods) from the init state to
//!   a colliding step. Breadth-first search reaches every state first along a shortest path
//!   and every state keeps a parent pointer, so the path is read back from the pointers and
//!   replayed through [`simulate::run`] into the simulator's trace format.
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
//!    - *quiet*: no observation yet, a gap outside the area (≤ 0 or > ρ), or a gap beyond
//!      the danger distance at top speed (d_coll is nondecreasing in the speed and the robot
//!      never exceeds v_max) with no wrong-assumption speed — no guard can fire;
//!    - *fires*: a gap in the area seen with a speed above V_a (wrong-assumption guard on),
//!      any gap in the area under the `area` rule, or a gap already within the danger
//!      distance at the robot's current speed (its speed, hence d_coll, only grows until it
//!      brakes) — the guard fires if the robot is still accelerating or driving by then;
//!    - *near(gap)*: otherwise; whether it fires depends on the robot's speed at that step,
//!      so the exact gap is kept.
//!
//!    The brake *reason* is dropped: after Brake both reasons have the same future. Plus one
//!    bit, whether the last period's speed exceeded V_a, kept only while the current gap is
//!    in the area (it is observed together with the current gap, L periods from now).
//! 4. **Everything but gap and speed once the robot brakes** (Brake latches, guards are no
//!    longer evaluated), and **everything once it rests** (Stop is final: one state).
//!
//! Every step checks the abstraction against the real thing: the guard the key predicts for
//! the step must be the guard [`World::step`] evaluated, or the search stops with
//! [`ExploreError::Inconsistent`].
//!
//! A state whose robot still accelerates or drives, whose gap is ≤ 0 and whose pending
//! observations are all quiet is *terminal*: no later observation can be in the area (gaps
//! never grow), so the robot never brakes and the minimum separation is −∞. Such a state is
//! only reached through a colliding step. With these cuts every path is finite, so the
//! search ends.
//!
//! A state budget ([`Options::max_states`]) bounds memory: when it is reached the search
//! stops with the verdict `inconclusive` (or `collision`, if one was already found).

use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::hash::{BuildHasherDefault, Hasher};

use serde::{Deserialize, Serialize};

use crate::core::model::{Params, Problem};
use crate::core::num::{Exact, exact_decimal};
use crate::core::semantics::{Mode, StepRecord, World, danger_distance};
use crate::core::simulate::{self, Run, TraceRow};

/// Default state budget: under 1 GB of memory at the measured 320–450 bytes per state.
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

// ---------------------------------------------------------------------------------------------
// Speed sets
// ---------------------------------------------------------------------------------------------

/// The finite set of obstacle speeds the explorer chooses from each period: distinct, exact,
/// within [0, W], in ascending order (the fixed action order).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpeedSet {
    speeds: Vec<Exact>,
}

impl SpeedSet {
    /// `n` evenly spaced speeds from 0 to W, both included: {0, W/(n−1), …, W} (n ≥ 2;
    /// with W = 0 the set is {0}).
    pub fn evenly_spaced(w: &Exact, n: usize) -> Result<SpeedSet, ExploreError> {
        let spec = n.to_string();
        if n < 2 {
            return Err(ExploreError::Speeds {
                spec,
                reason: "a count must be at least 2 (0 and W); for one explicit speed write \
                         it with a decimal point, e.g. --speeds 0.0"
                    .into(),
            });
        }
        if n > MAX_SPEEDS {
            return Err(ExploreError::Speeds {
                spec,
                reason: format!("at most {MAX_SPEEDS} speeds"),
            });
        }
        let step = w.clone() / Exact::from(n - 1);
        let speeds = (0..n).map(|i| step.clone() * Exact::from(i)).collect();
        Self::from_list(w, speeds, &spec)
    }

    /// An explicit set (sorted and deduplicated here); every speed must lie in [0, W].
    pub fn from_list(
        w: &Exact,
        mut speeds: Vec<Exact>,
        spec: &str,
    ) -> Result<SpeedSet, ExploreError> {
        if speeds.is_empty() {
            return Err(ExploreError::Speeds {
                spec: spec.into(),
                reason: "no speeds given".into(),
            });
        }
        if let Some(bad) = speeds.iter().find(|s| **s < Exact::ZERO || *s > w) {
            return Err(ExploreError::Speeds {
                spec: spec.into(),
                reason: format!(
                    "speed {} m/s is outside [0, W] = [0, {}] m/s (environment.obstacle_speed)",
                    show_exact(bad),
                    show_exact(w)
                ),
            });
        }
        speeds.sort();
        speeds.dedup();
        if speeds.len() > MAX_SPEEDS {
            return Err(ExploreError::Speeds {
                spec: spec.into(),
                reason: format!("at most {MAX_SPEEDS} speeds"),
            });
        }
        Ok(SpeedSet { speeds })
    }

    /// Reads `--speeds`: a bare whole number N is a count (N evenly spaced speeds from 0 to
    /// W); anything else is a comma-separated list of speeds in m/s, each a decimal (`0.05`,
    /// read as the decimal it is, like problem files) or a fraction (`3/80`).
    pub fn parse(spec: &str, w: &Exact) -> Result<SpeedSet, ExploreError> {
        let text = spec.trim();
        let bad = |reason: String| ExploreError::Speeds {
            spec: spec.to_string(),
            reason,
        };
        if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) {
            let n: usize = text
                .parse()
                .map_err(|_| bad(format!("count too large (at most {MAX_SPEEDS})")))?;
            return Self::evenly_spaced(w, n).map_err(|e| match e {
                ExploreError::Speeds { reason, .. } => bad(reason),
                other => other,
            });
        }
        let mut speeds = Vec::new();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            speeds.push(parse_speed(item).map_err(|reason| bad(format!("`{item}`: {reason}")))?);
        }
        Self::from_list(w, speeds, spec)
    }

    /// The speeds, ascending.
    pub fn speeds(&self) -> &[Exact] {
        &self.speeds
    }

    /// Number of speeds (actions per state).
    pub fn len(&self) -> usize {
        self.speeds.len()
    }

    /// Always false: a speed set has at least one speed.
    pub fn is_empty(&self) -> bool {
        self.speeds.is_empty()
    }
}

impl fmt::Display for SpeedSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let items: Vec<String> = self.speeds.iter().map(show_exact).collect();
        write!(f, "{{{}}}", items.join(", "))
    }
}

fn parse_speed(item: &str) -> Result<Exact, String> {
    if let Some((num, den)) = item.split_once('/') {
        let n: Exact = num
            .trim()
            .parse()
            .map_err(|_| "not a number (write a decimal like 0.05 or a fraction like 3/80)")?;
        let d: Exact = den
            .trim()
            .parse()
            .map_err(|_| "not a number (write a decimal like 0.05 or a fraction like 3/80)")?;
        if d == Exact::ZERO {
            return Err("division by zero".into());
        }
        return Ok(n / d);
    }
    let x: f64 = item
        .parse()
        .map_err(|_| "not a number (write a decimal like 0.05 or a fraction like 3/80)")?;
    if !x.is_finite() {
        return Err("must be finite".into());
    }
    Ok(exact_decimal(x))
}

/// An exact number as text: a terminating decimal when it is one (`0.0375`), else the
/// reduced fraction (`1/30`).
pub fn show_exact(x: &Exact) -> String {
    let den = x.denominator().clone();
    let mut d = den.clone();
    let (two, five) = (dashu_int::UBig::from(2u8), dashu_int::UBig::from(5u8));
    let mut digits = 0usize;
    let mut twos = 0usize;
    let mut fives = 0usize;
    while (&d % &two) == dashu_int::UBig::ZERO {
        d /= &two;
        twos += 1;
    }
    while (&d % &five) == dashu_int::UBig::ZERO {
        d /= &five;
        fives += 1;
    }
    if d != dashu_int::UBig::ONE || twos.max(fives) > 30 {
        return x.to_string();
    }
    digits += twos.max(fives);
    let scaled = x.numerator().clone() * dashu_int::IBig::from(10u8).pow(digits)
        / dashu_int::IBig::from(den);
    let negative = scaled < dashu_int::IBig::ZERO;
    let mut s = if negative {
        (-scaled).to_string()
    } else {
        scaled.to_string()
    };
    if digits > 0 {
        if s.len() <= digits {
            s = format!("{}{s}", "0".repeat(digits + 1 - s.len()));
        }
        s.insert(s.len() - digits, '.');
    }
    if negative {
        s.insert(0, '-');
    }
    s
}

// ---------------------------------------------------------------------------------------------
// States
// ---------------------------------------------------------------------------------------------

/// What the robot's guard will make of one future observation (see the module docs, 3).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Seen {
    /// No guard can fire on it.
    Quiet,
    /// The guard fires on it (if the robot still accelerates or drives then).
    Fires,
    /// An observed gap in the area: fires iff gap ≤ d_coll(speed at that step).
    Near(Exact),
}

/// A state of the finite model: the world as [`World::step`] runs it, plus the explorer's
/// own account of the observations still to come (kept in step with the world's history
/// from the step records, and checked against the world's guard at every step).
#[derive(Clone, Debug)]
pub struct State {
    world: World<Exact>,
    /// Verdicts of the observations at steps k, k+1, …, k+L−1 (while accelerating or driving).
    pending: VecDeque<Seen>,
    /// The last period's speed exceeded V_a (with the wrong-assumption guard on).
    last_fast: bool,
}

impl State {
    /// The world in this state.
    pub fn world(&self) -> &World<Exact> {
        &self.world
    }
}

/// The part of a [`State`] that determines its future: equal keys, equal futures. Stored in
/// full in the visited set (module docs list what it leaves out and why that is exact).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct StateKey(KeyRepr);

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum KeyRepr {
    /// Accelerating or driving.
    Moving {
        mode: Mode,
        speed: Exact,
        gap: Exact,
        last_fast: bool,
        pending: Box<[Seen]>,
    },
    /// Braking: only gap and speed matter.
    Braking { speed: Exact, gap: Exact },
    /// At rest for good.
    Stopped,
}

/// Whether a state has successors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// The robot can still act: every action has a next state.
    Running,
    /// The robot rests for good (Stop).
    Stopped,
    /// The robot accelerates or drives and no guard can ever fire again: it never brakes.
    NeverBrakes,
}

/// One step of the model: the step function's record and the state it leads to.
#[derive(Clone, Debug)]
pub struct Transition {
    /// What [`World::step`] reported.
    pub record: StepRecord<Exact>,
    /// The next state.
    pub next: State,
}

/// The finite model: a problem and the obstacle's speed set.
#[derive(Clone, Debug)]
pub struct FiniteModel {
    params: Params<Exact>,
    speeds: SpeedSet,
    /// d_coll(v_max), the largest danger distance (None: infinite, the `area` rule).
    top_danger: Option<Exact>,
}

impl FiniteModel {
    /// The model of a (validated) problem with the obstacle's speeds from `speeds`.
    pub fn new(problem: &Problem, speeds: SpeedSet) -> Self {
        Self::from_params(problem.params(), speeds)
    }

    /// As [`FiniteModel::new`], from exact parameters.
    pub fn from_params(params: Params<Exact>, speeds: SpeedSet) -> Self {
        let top_danger = danger_distance(&params, &params.v_max);
        FiniteModel {
            params,
            speeds,
            top_danger,
        }
    }

    /// The problem's exact numbers.
    pub fn params(&self) -> &Params<Exact> {
        &self.params
    }

    /// The obstacle's speed set.
    pub fn speeds(&self) -> &SpeedSet {
        &self.speeds
    }

    /// The init states: one, the world at t = 0.
    pub fn init_states(&self) -> Vec<State> {
        vec![State {
            world: World::new(self.params.clone()),
            pending: std::iter::repeat_n(Seen::Quiet, self.params.L).collect(),
            last_fast: false,
        }]
    }

    /// Whether `state` has successors.
    pub fn status(&self, state: &State) -> Status {
        let w = &state.world;
        match w.robot().mode {
            Mode::Stop => Status::Stopped,
            Mode::Accelerate | Mode::Drive
                if *w.gap() <= Exact::ZERO && state.pending.iter().all(|s| *s == Seen::Quiet) =>
            {
                Status::NeverBrakes
            }
            _ => Status::Running,
        }
    }

    /// The actions of `state`, in their fixed order: indices into the speed set, ascending
    /// speed; none for a terminal state.
    pub fn actions(&self, state: &State) -> std::ops::Range<usize> {
        match self.status(state) {
            Status::Running => 0..self.speeds.len(),
            _ => 0..0,
        }
    }

    /// The state `action` leads to from `state`, through [`World::step`].
    pub fn next_state(&self, state: &State, action: usize) -> Result<Transition, ExploreError> {
        let p = &self.params;
        let w = self.speeds.speeds[action].clone();
        let moving_before = matches!(state.world.robot().mode, Mode::Accelerate | Mode::Drive);
        let predicted = if moving_before {
            let v = &state.world.robot().speed;
            Some(match state.pending.front() {
                // L = 0: the robot sees the current gap with the last period's speed.
                None => self.classify(state.world.gap(), state.last_fast, v) == Seen::Fires,
                Some(Seen::Quiet) => false,
                Some(Seen::Fires) => true,
                Some(Seen::Near(gap)) => danger_distance(p, v).is_none_or(|d| *gap <= d),
            })
        } else {
            None
        };
        let mut world = state.world.clone();
        let record = world.step(w.clone());
        if let Some(fires) = predicted
            && fires != record.brake.is_some()
        {
            return Err(ExploreError::Inconsistent(format!(
                "at step {} the state key predicted the guard {} but the step function {}",
                record.k,
                if fires { "fires" } else { "stays quiet" },
                if fires { "did not brake" } else { "braked" },
            )));
        }
        let fast = p.wrong_assumption_brake && w > p.V_a;
        let next = match world.robot().mode {
            Mode::Accelerate | Mode::Drive => {
                let mut pending = state.pending.clone();
                if pending.pop_front().is_some() {
                    // The gap at this step's start, with the previous period's speed, is
                    // what the robot sees L periods from now.
                    let seen = self.classify(&record.gap, state.last_fast, &world.robot().speed);
                    pending.push_back(seen);
                }
                State {
                    world,
                    pending,
                    last_fast: fast,
                }
            }
            Mode::Brake | Mode::Stop | Mode::Idle => State {
                world,
                pending: VecDeque::new(),
                last_fast: false,
            },
        };
        Ok(Transition { record, next })
    }

    /// The verdict of observing `gap` with a speed that was above V_a iff `fast`, by a robot
    /// whose speed is `v` now and will not fall before the observation is acted on.
    fn classify(&self, gap: &Exact, fast: bool, v: &Exact) -> Seen {
        let p = &self.params;
        if *gap <= Exact::ZERO || *gap > p.rho {
            return Seen::Quiet;
        }
        if fast {
            return Seen::Fires;
        }
        match (danger_distance(p, v), &self.top_danger) {
            (None, _) => Seen::Fires,
            (Some(d), _) if *gap <= d => Seen::Fires,
            (_, Some(top)) if gap > top => Seen::Quiet,
            _ => Seen::Near(gap.clone()),
        }
    }

    /// The key of `state` (see the module docs for why it is exact).
    pub fn key(&self, state: &State) -> StateKey {
        let w = &state.world;
        let robot = w.robot();
        StateKey(match robot.mode {
            Mode::Stop => KeyRepr::Stopped,
            Mode::Brake => KeyRepr::Braking {
                speed: robot.speed.clone(),
                gap: w.gap().clone(),
            },
            mode => {
                let gap = w.gap().clone();
                let in_area = gap > Exact::ZERO && gap <= self.params.rho;
                KeyRepr::Moving {
                    mode,
                    speed: robot.speed.clone(),
                    last_fast: state.last_fast && in_area,
                    gap,
                    pending: state.pending.iter().cloned().collect(),
                }
            }
        })
    }
}

// ---------------------------------------------------------------------------------------------
// The search
// ---------------------------------------------------------------------------------------------

/// Search options.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// Stop with `inconclusive` once this many distinct states are stored.
    pub max_states: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_states: DEFAULT_MAX_STATES,
        }
    }
}

/// The explorer's three-valued answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
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

/// A path of the model, replayed through the simulator.
#[derive(Clone, Debug)]
pub struct Path {
    /// The actions: the obstacle's speed in each control period, exactly.
    pub speeds: Vec<Exact>,
    /// The replay through [`simulate::run`] in exact numbers.
    pub run: Run<Exact>,
    /// The replay as the simulator's trace.
    pub trace: Vec<TraceRow>,
}

impl Path {
    /// Number of control periods (actions).
    pub fn periods(&self) -> usize {
        self.speeds.len()
    }
}

/// The result of a search.
#[derive(Clone, Debug)]
pub struct Exploration {
    /// The verdict.
    pub verdict: ExploreVerdict,
    /// Every behaviour was explored (false: the state budget was reached).
    pub complete: bool,
    /// Distinct states stored (init state included).
    pub states: usize,
    /// Transitions computed (calls of the step function).
    pub transitions: usize,
    /// Length of the longest path explored, in control periods.
    pub depth: usize,
    /// Least gap at rest over all explored behaviours that come to rest (None: none came to
    /// rest after moving). With `never_stops` the minimum separation is −∞ regardless.
    pub min_separation: Option<Exact>,
    /// Some explored behaviour never brakes: the minimum separation is −∞.
    pub never_stops: bool,
    /// On collision: the shortest path to a colliding step.
    pub counterexample: Option<Path>,
    /// The path realising the minimum separation (to the rest, or to the point where the
    /// robot can no longer brake).
    pub closest: Option<Path>,
    /// The speed set explored.
    pub speeds: SpeedSet,
}

impl Exploration {
    /// The minimum separation as a float: −∞ when some behaviour never brakes, None when
    /// no explored behaviour moved and came to rest.
    pub fn min_separation_f64(&self) -> Option<f64> {
        if self.never_stops {
            Some(f64::NEG_INFINITY)
        } else {
            self.min_separation.as_ref().map(|s| s.to_f64().value())
        }
    }
}

/// A fast, deterministic hasher for the visited set (multiply–rotate, as rustc's FxHasher).
/// Only bucket placement depends on it: keys are compared in full.
#[derive(Default)]
struct FxHasher(u64);

impl Hasher for FxHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
    fn write_u8(&mut self, i: u8) {
        self.write_u64(u64::from(i));
    }
    fn write_u32(&mut self, i: u32) {
        self.write_u64(u64::from(i));
    }
}

/// How a stored state was first reached: its parent and the action taken there.
#[derive(Clone, Copy)]
struct Node {
    parent: u32,
    action: u16,
}

const ROOT: u32 = u32::MAX;

/// The end of a path: the state `node`, then `action`.
#[derive(Clone, Copy)]
struct PathEnd {
    node: u32,
    action: u16,
}

/// Explores every behaviour of a (validated) problem's finite model with the obstacle's
/// speeds from `speeds`, breadth first.
pub fn explore(
    problem: &Problem,
    speeds: SpeedSet,
    options: &Options,
) -> Result<Exploration, ExploreError> {
    explore_model(&FiniteModel::new(problem, speeds), options)
}

/// Explores a model breadth first (see the module docs).
pub fn explore_model(model: &FiniteModel, options: &Options) -> Result<Exploration, ExploreError> {
    if options.max_states == 0 {
        return Err(ExploreError::Options(
            "--max-states must be at least 1".into(),
        ));
    }
    if options.max_states >= ROOT as usize {
        return Err(ExploreError::Options(format!(
            "--max-states must be below {ROOT}"
        )));
    }
    let mut visited: HashMap<StateKey, u32, BuildHasherDefault<FxHasher>> = HashMap::default();
    let mut nodes: Vec<Node> = Vec::new();
    let mut frontier: Vec<(u32, State)> = Vec::new();
    for state in model.init_states() {
        let id = nodes.len() as u32;
        if visited.insert(model.key(&state), id).is_none() {
            nodes.push(Node {
                parent: ROOT,
                action: 0,
            });
            frontier.push((id, state));
        }
    }
    let mut transitions = 0usize;
    let mut depth = 0usize;
    let mut complete = true;
    let mut counterexample: Option<PathEnd> = None;
    let mut min_separation: Option<Exact> = None;
    let mut closest: Option<PathEnd> = None;
    let mut never_stops = false;
    'search: while !frontier.is_empty() {
        let mut next_frontier = Vec::new();
        for (id, state) in frontier.drain(..) {
            for action in model.actions(&state) {
                let t = model.next_state(&state, action)?;
                transitions += 1;
                depth = depth.max(t.record.k + 1);
                let end = PathEnd {
                    node: id,
                    action: action as u16,
                };
                if t.record.collision && counterexample.is_none() {
                    counterexample = Some(end);
                }
                if let Some(g) = &t.record.rest_gap
                    && min_separation.as_ref().is_none_or(|m| g < m)
                {
                    min_separation = Some(g.clone());
                    if !never_stops {
                        closest = Some(end);
                    }
                }
                let status = model.status(&t.next);
                if status == Status::NeverBrakes && !never_stops {
                    never_stops = true;
                    closest = Some(end);
                }
                let key = model.key(&t.next);
                if visited.contains_key(&key) {
                    continue;
                }
                if visited.len() >= options.max_states {
                    complete = false;
                    break 'search;
                }
                let child = nodes.len() as u32;
                visited.insert(key, child);
                nodes.push(Node {
                    parent: id,
                    action: action as u16,
                });
                if status == Status::Running {
                    next_frontier.push((child, t.next));
                }
            }
        }
        frontier = next_frontier;
    }
    let states = visited.len();
    drop(visited);
    let path_of = |end: PathEnd, stop_at_collision: bool| -> Result<Path, ExploreError> {
        let mut actions = vec![end.action];
        let mut id = end.node;
        while nodes[id as usize].parent != ROOT {
            actions.push(nodes[id as usize].action);
            id = nodes[id as usize].parent;
        }
        actions.reverse();
        let speeds: Vec<Exact> = actions
            .iter()
            .map(|&a| model.speeds.speeds[a as usize].clone())
            .collect();
        let run = simulate::run(
            model.params.clone(),
            |k| speeds[k].clone(),
            speeds.len(),
            stop_at_collision,
        );
        if run.records.len() != speeds.len() {
            return Err(ExploreError::Inconsistent(format!(
                "a path of {} periods replays for only {}",
                speeds.len(),
                run.records.len()
            )));
        }
        let trace = simulate::trace(&model.params, &run);
        Ok(Path { speeds, run, trace })
    };
    let counterexample = counterexample.map(|end| path_of(end, true)).transpose()?;
    if let Some(c) = &counterexample
        && !c.run.records.last().is_some_and(|r| r.collision)
    {
        return Err(ExploreError::Inconsistent(
            "the counterexample does not collide when replayed".into(),
        ));
    }
    let closest = closest.map(|end| path_of(end, false)).transpose()?;
    let verdict = if counterexample.is_some() {
        ExploreVerdict::Collision
    } else if complete {
        ExploreVerdict::Safe
    } else {
        ExploreVerdict::Inconclusive
    };
    Ok(Exploration {
        verdict,
        complete,
        states,
        transitions,
        depth,
        min_separation,
        never_stops,
        counterexample,
        closest,
        speeds: model.speeds.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_numbers_show_as_decimals_when_they_terminate() {
        let q = |n: i64, d: i64| Exact::from(n) / Exact::from(d);
        assert_eq!(show_exact(&q(3, 80)), "0.0375");
        assert_eq!(show_exact(&q(-58, 100)), "-0.58");
        assert_eq!(show_exact(&q(1, 30)), "1/30");
        assert_eq!(show_exact(&q(7, 1)), "7");
        assert_eq!(show_exact(&Exact::ZERO), "0");
        assert_eq!(show_exact(&q(-1, 200)), "-0.005");
    }
}
