//! The finite model the explorer searches: its states, the exact keys that merge states with
//! the same future (the module docs of `explore` say what a key leaves out and why that is
//! exact), and its transitions through the step function, checked against the key's
//! prediction at every step.

use std::collections::VecDeque;

use super::{ExploreError, SpeedSet};
use crate::core::model::{Params, Problem};
use crate::core::num::Exact;
use crate::core::semantics::{Mode, StepRecord, World, danger_distance};

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
        let w = self.speeds.speeds()[action].clone();
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
