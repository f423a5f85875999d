//! The finite model of a scene: its init states (one per combination of obstacle starts),
//! its joint actions (what the robot is shown of each obstacle, then one speed per obstacle
//! from each obstacle's set), its transitions through [`SceneWorld::step_seeing`], when a
//! state ends, and its exact keys.

use super::key::{Ending, SceneKey};
use super::speeds::SceneSpeeds;
use crate::core::num::{Exact, Scalar};
use crate::core::rational::Rational;
use crate::core::scene::guards::Command;
use crate::core::scene::safety::Side;
use crate::core::scene::simulate::horizon;
use crate::core::scene::{SceneParams, SceneStepRecord, SceneWorld};
use crate::core::semantics::{Mode, Observation};
use crate::crosscheck::explore::ExploreError;

/// Most joint actions (combinations of one speed per obstacle) a state may have.
pub const MAX_JOINT_ACTIONS: usize = 1 << 16;

/// Most combinations of observation choices (one look per obstacle) a state may have.
pub const MAX_LOOK_COMBINATIONS: usize = 1 << 16;

/// Most combinations of looks and speeds a state may have.
const MAX_MOVES: usize = 1 << 20;

/// A state of a scene's finite model: the world as [`SceneWorld::step_seeing`] runs it,
/// and which obstacles are still hidden (occlusion).
#[derive(Clone, Debug)]
pub struct SceneState {
    world: SceneWorld<Rational>,
    /// `hidden[i]`: obstacle i has not been shown yet (always false without occlusion, and
    /// once the robot no longer accelerates or drives: no guard reads it any more).
    hidden: Vec<bool>,
}

impl SceneState {
    /// The world in this state.
    pub fn world(&self) -> &SceneWorld<Rational> {
        &self.world
    }

    /// Whether obstacle i is still hidden.
    pub fn hidden(&self, i: usize) -> bool {
        self.hidden[i]
    }
}

/// What the environment shows the robot of one obstacle at one step start.
#[derive(Clone, Debug, PartialEq)]
pub enum Look {
    /// Nothing: the obstacle is still hidden (occlusion).
    Hidden,
    /// Its observation, with these errors added to the true gap and speed.
    Shown {
        /// Added to the true gap (within ±σ_g).
        gap_error: Rational,
        /// Added to the true speed (within ±σ_w).
        speed_error: Rational,
    },
}

impl Look {
    /// The exact observation.
    fn exact() -> Look {
        Look::Shown {
            gap_error: Rational::zero(),
            speed_error: Rational::zero(),
        }
    }

    /// What the robot is shown of a true observation `truth`.
    fn show(&self, truth: Observation<Rational>) -> Option<Observation<Rational>> {
        match self {
            Look::Hidden => None,
            Look::Shown {
                gap_error,
                speed_error,
            } => Some(Observation {
                gap: truth.gap + gap_error.clone(),
                speed: truth.speed + speed_error.clone(),
            }),
        }
    }
}

/// The joint actions of one state: the distinct outcomes of the environment's observation
/// choices (each with one combination of looks that realises it), times the speed
/// combinations. Action a is outcome a / speeds, speed combination a % speeds.
#[derive(Clone, Debug)]
pub struct SceneMoves {
    /// One combination of looks (one per obstacle) per distinct outcome, in a fixed order.
    outcomes: Vec<Vec<Look>>,
    speeds: usize,
}

impl SceneMoves {
    /// Number of joint actions.
    pub fn len(&self) -> usize {
        self.outcomes.len() * self.speeds
    }

    /// Whether there is none (never: every state has at least one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The looks of joint action `action`.
    pub fn looks(&self, action: usize) -> &[Look] {
        &self.outcomes[action / self.speeds]
    }

    /// The speed combination of joint action `action` (see [`SceneModel::choices`]).
    pub fn speed_action(&self, action: usize) -> usize {
        action % self.speeds
    }
}

/// Whether a state has successors, and if not, why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneStatus {
    /// The robot can still act: every joint action has a next state.
    Running,
    /// The robot rests for good (Stop).
    Stopped,
    /// Nothing can happen any more ([`SceneWorld::settled`]): the robot drives on for ever
    /// and no separation falls further.
    Settled,
    /// The robot drives on for ever (no guard can fire again) through an obstacle that was
    /// ahead when it entered that obstacle's lane: that separation falls without bound.
    NeverBrakes,
}

/// One step of the model: the step function's record and the state it leads to.
#[derive(Clone, Debug)]
pub struct SceneTransition {
    /// What [`SceneWorld::step`] reported.
    pub record: SceneStepRecord<Rational>,
    /// The next state.
    pub next: SceneState,
}

/// The finite model of a scene: its numbers, every obstacle's speed set and starts.
#[derive(Clone, Debug)]
pub struct SceneModel {
    exact: SceneParams<Exact>,
    params: SceneParams<Rational>,
    speeds: SceneSpeeds,
    /// Obstacle i's speeds as fast exact numbers.
    levels: Vec<Vec<Rational>>,
    /// Obstacle i's choices per period: its set's size, or 1 when it cannot matter.
    radix: Vec<usize>,
    /// Obstacle i can matter (module docs, "Obstacles that cannot matter").
    matters: Vec<bool>,
    /// Obstacle i's starts: its position, or both ends of its range.
    starts: Vec<Vec<Exact>>,
    horizon: usize,
    /// The gap errors the environment chooses among: {0, −σ_g, σ_g} ({0} without noise).
    gap_errors: Vec<Rational>,
    /// The speed errors: {0, −σ_w, σ_w}.
    speed_errors: Vec<Rational>,
}

/// {0, −σ, σ}, or {0} when σ = 0: the exact observation first, so that an outcome's
/// representative errs only where an error changes what the guard does.
fn errors(sigma: &Rational) -> Vec<Rational> {
    if *sigma > Rational::zero() {
        vec![Rational::zero(), -sigma.clone(), sigma.clone()]
    } else {
        vec![Rational::zero()]
    }
}

impl SceneModel {
    /// The model of a scene's exact numbers with each obstacle's speeds from `speeds`.
    pub fn new(params: SceneParams<Exact>, speeds: SceneSpeeds) -> Result<Self, ExploreError> {
        if speeds.sets().len() != params.obstacles.len() {
            return Err(ExploreError::Options(format!(
                "{} speed sets for {} obstacles",
                speeds.sets().len(),
                params.obstacles.len()
            )));
        }
        // Without lane changes the robot stays in lane 0: obstacles of other lanes are never
        // occupied and never seen by a guard.
        let matters: Vec<bool> = params
            .obstacles
            .iter()
            .map(|o| params.lane_change.is_some() || o.lane == 0)
            .collect();
        let radix: Vec<usize> = (0..params.obstacles.len())
            .map(|i| if matters[i] { speeds.of(i).len() } else { 1 })
            .collect();
        let joint = radix
            .iter()
            .try_fold(1usize, |n, r| n.checked_mul(*r))
            .filter(|n| *n <= MAX_JOINT_ACTIONS);
        let Some(joint) = joint else {
            return Err(ExploreError::Options(format!(
                "the obstacles' speed sets combine to more than {MAX_JOINT_ACTIONS} joint \
                 choices per period; use fewer --speeds"
            )));
        };
        let robot = params.robot.map(Rational::from_exact);
        let gap_errors = errors(&robot.sigma_g);
        let speed_errors = errors(&robot.sigma_w);
        // Per obstacle at most: hidden, or shown with one error of each kind.
        let looks = gap_errors.len() * speed_errors.len() + usize::from(robot.d_det.is_some());
        let combinations = matters
            .iter()
            .filter(|&&m| m)
            .try_fold(1usize, |n, _| n.checked_mul(looks))
            .filter(|n| *n <= MAX_LOOK_COMBINATIONS && n * joint <= MAX_MOVES);
        if combinations.is_none() {
            return Err(ExploreError::Options(format!(
                "the observation choices (hidden or shown, errors −σ, 0, +σ) of {} obstacles \
                 and their speed sets combine to too many joint choices per period; use fewer \
                 obstacles or --speeds",
                matters.iter().filter(|&&m| m).count()
            )));
        }
        let levels = speeds
            .sets()
            .iter()
            .map(|s| s.speeds().iter().map(Rational::from_exact).collect())
            .collect();
        let starts = params
            .obstacles
            .iter()
            .zip(&matters)
            .map(|(o, &m)| {
                if m && o.start_max != o.start_min {
                    vec![o.start_min.clone(), o.start_max.clone()]
                } else {
                    vec![o.start_min.clone()]
                }
            })
            .collect();
        let horizon = horizon(&params.map(|x| x.to_f64().value()));
        Ok(SceneModel {
            params: params.map(Rational::from_exact),
            exact: params,
            speeds,
            levels,
            radix,
            matters,
            starts,
            horizon,
            gap_errors,
            speed_errors,
        })
    }

    /// Whether the robot's observations are the environment's choice (noise or occlusion).
    pub fn sensing(&self) -> bool {
        self.params.robot.noisy() || self.params.robot.d_det.is_some()
    }

    /// The scene's exact numbers.
    pub fn params(&self) -> &SceneParams<Exact> {
        &self.exact
    }

    /// The obstacles' speed sets.
    pub fn speeds(&self) -> &SceneSpeeds {
        &self.speeds
    }

    /// Each obstacle's starts explored: its position, or both ends of its range (one start
    /// for an obstacle that cannot matter).
    pub fn starts(&self) -> &[Vec<Exact>] {
        &self.starts
    }

    /// Whether obstacle i can matter at all (else it has one speed and one start).
    pub fn matters(&self, i: usize) -> bool {
        self.matters[i]
    }

    /// Periods after which every branch has ended unless the robot passed through an
    /// obstacle ([`horizon`]); a branch still running there ends the search incomplete.
    pub fn horizon(&self) -> usize {
        self.horizon
    }

    /// Replaces the horizon (a test's lever to see the search stop incomplete).
    pub fn with_horizon(mut self, horizon: usize) -> Self {
        self.horizon = horizon;
        self
    }

    /// The combinations of starts, in a fixed order (obstacle 0's varying slowest): the
    /// init states are the worlds at t = 0 from each.
    pub fn start_combinations(&self) -> Vec<Vec<Exact>> {
        let mut all: Vec<Vec<Exact>> = vec![Vec::new()];
        for choices in &self.starts {
            all = all
                .into_iter()
                .flat_map(|prefix| {
                    choices.iter().map(move |x| {
                        let mut v = prefix.clone();
                        v.push(x.clone());
                        v
                    })
                })
                .collect();
        }
        all
    }

    /// The world at t = 0 from `starts` (one x per obstacle), every obstacle hidden with
    /// occlusion (it is first shown by a later choice). None when no behaviour starts there
    /// (an obstacle can never be first seen: its first observation already shows a true
    /// gap below d_det).
    pub fn init_state(&self, starts: &[Exact]) -> Option<SceneState> {
        let world = SceneWorld::new(
            self.params.clone(),
            starts.iter().map(Rational::from_exact).collect(),
        );
        let hidden = vec![self.params.robot.d_det.is_some(); starts.len()];
        self.admissible(SceneState { world, hidden })
    }

    /// Number of speed combinations of a running state.
    pub fn speed_actions(&self) -> usize {
        self.radix.iter().product()
    }

    /// The true gap of obstacle i's next observation (the gap at t = 0 before the first
    /// one, at step L).
    fn next_observed_gap(&self, world: &SceneWorld<Rational>, i: usize) -> Rational {
        match world.observation_if_shown(i) {
            Some(obs) => obs.gap,
            None => world.history(i).0.front().unwrap_or(world.gap(i)).clone(),
        }
    }

    /// The true gap the observation after the next one will show, when it is already
    /// known (latency ≥ 1, and the next observation exists): the gap at (k + 1 − L)·dt.
    fn following_observed_gap(&self, world: &SceneWorld<Rational>, i: usize) -> Option<Rational> {
        let l = self.params.robot.L;
        world.observation_if_shown(i)?;
        match l {
            0 => None,
            1 => Some(world.gap(i).clone()),
            _ => {
                let (gaps, _) = world.history(i);
                gaps.get(gaps.len().checked_sub(l - 1)?).cloned()
            }
        }
    }

    /// `state`, unless it is *lost*: an obstacle still hidden whose next observation
    /// already shows a true gap below d_det can never be first seen (gaps never grow), so
    /// no behaviour passes through it. Once the robot no longer accelerates or drives no
    /// guard reads an observation again, so the hidden marks are dropped there (the
    /// behaviour shows each such obstacle at its next observation).
    fn admissible(&self, mut state: SceneState) -> Option<SceneState> {
        if let Some(d_det) = &self.params.robot.d_det {
            for i in 0..state.hidden.len() {
                if state.hidden[i] && self.next_observed_gap(&state.world, i) < *d_det {
                    return None;
                }
            }
        }
        if !matches!(state.world.robot().mode, Mode::Accelerate | Mode::Drive) {
            state.hidden.iter_mut().for_each(|h| *h = false);
        }
        Some(state)
    }

    /// The looks the environment may choose for obstacle i in `state`: while a guard reads
    /// observations, a hidden obstacle stays hidden or (when its true observed gap is
    /// ≥ d_det) is first shown; a shown one is shown with each error in {−σ_g, 0, σ_g} ×
    /// {−σ_w, 0, σ_w}. An obstacle that cannot matter is shown exactly as soon as it may be.
    fn looks(&self, state: &SceneState, i: usize) -> Vec<Look> {
        let w = &state.world;
        let reads = matches!(w.robot().mode, Mode::Accelerate | Mode::Drive);
        let Some(truth) = w.observation_if_shown(i).filter(|_| reads) else {
            return vec![if state.hidden[i] {
                Look::Hidden
            } else {
                Look::exact()
            }];
        };
        let showable = !state.hidden[i]
            || self
                .params
                .robot
                .d_det
                .as_ref()
                .is_none_or(|d| truth.gap >= *d);
        if !self.matters[i] {
            return vec![if showable {
                Look::exact()
            } else {
                Look::Hidden
            }];
        }
        // Every shown value beyond ρ: no guard and no free-lane test reads it, so errors
        // change nothing, and a hidden obstacle may as well be first shown at the next
        // observation, when that one still shows a true gap ≥ d_det (module docs,
        // "Noise and occlusion").
        let robot = &self.params.robot;
        if truth.gap.clone() - robot.sigma_g.clone() > robot.rho {
            if !state.hidden[i] {
                return vec![Look::exact()];
            }
            return match self.following_observed_gap(w, i) {
                Some(g) if robot.d_det.as_ref().is_some_and(|d| g >= *d) => vec![Look::Hidden],
                _ if !showable => vec![Look::Hidden],
                Some(_) => vec![Look::exact()],
                // Latency 0: the following observation is not known yet, so both.
                None => vec![Look::Hidden, Look::exact()],
            };
        }
        let mut out = Vec::new();
        if state.hidden[i] {
            out.push(Look::Hidden);
        }
        // The speed read before any period has ended is the initial 0, with no error.
        let zero = [Rational::zero()];
        let speed_errors = if w.k() == robot.L {
            &zero[..]
        } else {
            &self.speed_errors[..]
        };
        if showable {
            for g in &self.gap_errors {
                for e in speed_errors {
                    out.push(Look::Shown {
                        gap_error: g.clone(),
                        speed_error: e.clone(),
                    });
                }
            }
        }
        out
    }

    /// The joint actions of a running state. Without noise or occlusion there is one
    /// outcome (every obstacle shown exactly) and the actions are the speed combinations.
    /// Otherwise every combination of looks is tried and grouped by what it changes: the
    /// command it makes the guard give and which obstacles stay hidden (an observation is
    /// read by that guard only, so two combinations that agree on both lead to the same
    /// next state for every speed combination).
    pub fn moves(&self, state: &SceneState) -> SceneMoves {
        let speeds = self.speed_actions();
        if !self.sensing() {
            let exact = vec![Look::exact(); state.hidden.len()];
            return SceneMoves {
                outcomes: vec![exact],
                speeds,
            };
        }
        let options: Vec<Vec<Look>> = (0..state.hidden.len())
            .map(|i| self.looks(state, i))
            .collect();
        let mut seen: Vec<(Option<Command>, Vec<bool>)> = Vec::new();
        let mut outcomes = Vec::new();
        let mut index = vec![0usize; options.len()];
        loop {
            let looks: Vec<Look> = index
                .iter()
                .zip(&options)
                .map(|(&j, o)| o[j].clone())
                .collect();
            let command = state.world.command_seeing(|i, truth| looks[i].show(truth));
            let hidden: Vec<bool> = looks.iter().map(|l| *l == Look::Hidden).collect();
            let outcome = (command, hidden);
            if !seen.contains(&outcome) {
                seen.push(outcome);
                outcomes.push(looks);
            }
            // Next combination: the last obstacle's choice varies fastest.
            let mut i = options.len();
            loop {
                if i == 0 {
                    return SceneMoves { outcomes, speeds };
                }
                i -= 1;
                index[i] += 1;
                if index[i] < options[i].len() {
                    break;
                }
                index[i] = 0;
            }
        }
    }

    /// The speed index of each obstacle in speed combination `action`: mixed radix,
    /// obstacle 0 most significant, so ascending combinations list the choices in
    /// lexicographic order.
    pub fn choices(&self, action: usize) -> Vec<usize> {
        let mut rest = action;
        let mut out = vec![0; self.radix.len()];
        for (i, r) in self.radix.iter().enumerate().rev() {
            out[i] = rest % r;
            rest /= r;
        }
        out
    }

    /// Obstacle i's exact speed for speed index `index` of its set.
    pub fn speed(&self, i: usize, index: usize) -> &Exact {
        &self.speeds.of(i).speeds()[index]
    }

    /// Whether `state` has successors, and if not, why.
    pub fn status(&self, state: &SceneState) -> SceneStatus {
        let w = &state.world;
        if w.stopped() {
            SceneStatus::Stopped
        } else if w.k() > 0 && w.settled() {
            SceneStatus::Settled
        } else if !self.unbounded(state).is_empty() {
            SceneStatus::NeverBrakes
        } else {
            SceneStatus::Running
        }
    }

    /// The obstacles whose separation falls without bound from `state` on: none unless no
    /// guard can fire again — no goal, the robot accelerating or driving, no lane change
    /// under way, and every obstacle of its lane already observed at a gap ≤ 0 (observed gaps
    /// never grow, so none becomes relevant again) — and then those of its lane whose
    /// occupancy interval began with them ahead (their gap falls for ever while the robot
    /// drives on).
    pub fn unbounded(&self, state: &SceneState) -> Vec<usize> {
        let w = &state.world;
        let p = &self.params;
        let lateral = w.lateral();
        let driving = matches!(w.robot().mode, Mode::Accelerate | Mode::Drive);
        if p.goal.is_some() || !driving || lateral.change.is_some() {
            return Vec::new();
        }
        let lane: Vec<usize> = (0..p.obstacles.len())
            .filter(|&i| p.obstacles[i].lane == lateral.lane)
            .collect();
        // Observed ≤ 0 whatever the error (a hidden obstacle is first shown at a gap
        // ≥ d_det > 0).
        let past = -p.robot.sigma_g.clone();
        let passed = lane
            .iter()
            .all(|&i| !state.hidden[i] && w.seen(i).is_some_and(|o| o.gap <= past));
        if !passed {
            return Vec::new();
        }
        lane.into_iter()
            .filter(|&i| w.side(i).unwrap_or_else(|| Side::of(w.gap(i))) == Side::Ahead)
            .collect()
    }

    /// The state joint action `action` (of `moves`, the state's [`SceneModel::moves`])
    /// leads to from `state`, through [`SceneWorld::step_seeing`]; None when it is lost (no
    /// behaviour passes through it, see [`SceneModel::init_state`]).
    pub fn next_state(
        &self,
        state: &SceneState,
        moves: &SceneMoves,
        action: usize,
    ) -> Option<SceneTransition> {
        let speeds: Vec<Rational> = self
            .choices(moves.speed_action(action))
            .into_iter()
            .enumerate()
            .map(|(i, c)| self.levels[i][c].clone())
            .collect();
        let looks = moves.looks(action);
        let mut world = state.world.clone();
        let record = world.step_seeing(&speeds, |i, truth| looks[i].show(truth));
        let hidden = state
            .hidden
            .iter()
            .zip(looks)
            .map(|(&h, l)| h && *l == Look::Hidden)
            .collect();
        let next = self.admissible(SceneState { world, hidden })?;
        Some(SceneTransition { record, next })
    }

    /// The exact key of `state`, whose status is `status`.
    pub fn key(&self, state: &SceneState, status: SceneStatus) -> SceneKey {
        let hidden = self.sensing().then_some(state.hidden.as_slice());
        match status {
            SceneStatus::Running => SceneKey::running(&state.world, &self.matters, hidden),
            SceneStatus::Stopped => SceneKey::ended(Ending::Stopped),
            SceneStatus::Settled => SceneKey::ended(Ending::Settled),
            SceneStatus::NeverBrakes => SceneKey::ended(Ending::NeverBrakes),
        }
    }
}
