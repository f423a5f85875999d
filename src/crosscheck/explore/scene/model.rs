//! The finite model of a scene: its init states (one per combination of obstacle starts),
//! its joint actions (one speed per obstacle from each obstacle's set), its transitions
//! through [`SceneWorld::step`], when a state ends, and its exact keys.

use super::key::{Ending, SceneKey};
use super::speeds::SceneSpeeds;
use crate::core::num::{Exact, Scalar};
use crate::core::rational::Rational;
use crate::core::scene::safety::Side;
use crate::core::scene::simulate::horizon;
use crate::core::scene::{SceneParams, SceneStepRecord, SceneWorld};
use crate::core::semantics::Mode;
use crate::crosscheck::explore::ExploreError;

/// Most joint actions (combinations of one speed per obstacle) a state may have.
pub const MAX_JOINT_ACTIONS: usize = 1 << 16;

/// A state of a scene's finite model: the world as [`SceneWorld::step`] runs it.
#[derive(Clone, Debug)]
pub struct SceneState {
    world: SceneWorld<Rational>,
}

impl SceneState {
    /// The world in this state.
    pub fn world(&self) -> &SceneWorld<Rational> {
        &self.world
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
}

impl SceneModel {
    /// The model of a scene's exact numbers with each obstacle's speeds from `speeds`.
    pub fn new(params: SceneParams<Exact>, speeds: SceneSpeeds) -> Result<Self, ExploreError> {
        if params.robot.noisy() || params.robot.d_det.is_some() {
            return Err(ExploreError::Options(
                "the scene explorer shows the robot every obstacle exactly from the start; \
                 [sensing] settings are explored for single-obstacle problems only so far \
                 (the run search decides scenes with them)"
                    .into(),
            ));
        }
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
        if joint.is_none() {
            return Err(ExploreError::Options(format!(
                "the obstacles' speed sets combine to more than {MAX_JOINT_ACTIONS} joint \
                 choices per period; use fewer --speeds"
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
        })
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

    /// The world at t = 0 from `starts` (one x per obstacle).
    pub fn init_state(&self, starts: &[Exact]) -> SceneState {
        SceneState {
            world: SceneWorld::new(
                self.params.clone(),
                starts.iter().map(Rational::from_exact).collect(),
            ),
        }
    }

    /// Number of joint actions of a running state.
    pub fn joint_actions(&self) -> usize {
        self.radix.iter().product()
    }

    /// The speed index of each obstacle in joint action `action`: mixed radix, obstacle 0
    /// most significant, so ascending actions list the choices in lexicographic order.
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
        let passed = lane
            .iter()
            .all(|&i| w.seen(i).is_some_and(|o| o.gap <= Rational::zero()));
        if !passed {
            return Vec::new();
        }
        lane.into_iter()
            .filter(|&i| w.side(i).unwrap_or_else(|| Side::of(w.gap(i))) == Side::Ahead)
            .collect()
    }

    /// The state `action` leads to from `state`, through [`SceneWorld::step`].
    pub fn next_state(&self, state: &SceneState, action: usize) -> SceneTransition {
        let speeds: Vec<Rational> = self
            .choices(action)
            .into_iter()
            .enumerate()
            .map(|(i, c)| self.levels[i][c].clone())
            .collect();
        let mut world = state.world.clone();
        let record = world.step(&speeds);
        SceneTransition {
            record,
            next: SceneState { world },
        }
    }

    /// The exact key of `state`, whose status is `status`.
    pub fn key(&self, state: &SceneState, status: SceneStatus) -> SceneKey {
        match status {
            SceneStatus::Running => SceneKey::running(&state.world, &self.matters),
            SceneStatus::Stopped => SceneKey::ended(Ending::Stopped),
            SceneStatus::Settled => SceneKey::ended(Ending::Settled),
            SceneStatus::NeverBrakes => SceneKey::ended(Ending::NeverBrakes),
        }
    }
}
