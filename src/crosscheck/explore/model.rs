//! The finite model the explorer searches: its states, the exact keys that merge states with
//! the same future (the module docs of `explore` say what a key leaves out and why that is
//! exact), its choices (the obstacle's speed, and where sensing leaves it open, the
//! observation error's aim and the first sighting of a hidden obstacle), and its
//! transitions through the step function, checked against the key's prediction at every
//! step.

use std::hash::{Hash, Hasher};

use super::observe::{Pending, Seen, Sight, SpeedSeen, classify, may_be_in_area, resolve};
use super::starts::{DEFAULT_STARTS, starts};
use super::window::Window;
use super::{ExploreError, SpeedSet};
use crate::core::model::{Params, Problem};
use crate::core::num::Exact;
use crate::core::semantics::{Mode, StepRecord, World, danger_distance};

/// A state of the finite model: the world as [`World::step`] runs it, plus the explorer's
/// own account of the observations still to come (kept in step with the world's history
/// from the step records, and checked against the world's guard at every step). Both
/// histories — the world's and the pending observations — are shared with the states along
/// its path, so a state's size does not grow with the latency.
#[derive(Clone, Debug)]
pub struct State {
    /// The world, its history taken out into `history`.
    world: World<Exact>,
    /// The world's history: the gap at each of the last L+1 periods' starts and the
    /// obstacle's speed over it.
    history: Window<(Exact, Exact)>,
    /// The observations at steps k+L−1, …, k+1, k, newest first (while accelerating or
    /// driving).
    pending: Window<Pending>,
    /// What the last period's speed can be made to look like (the speed observed together
    /// with the current gap).
    last: SpeedSeen,
    /// Occlusion: the obstacle has not been seen yet.
    hidden: bool,
}

impl State {
    /// The world in this state, without the history its observations are read from
    /// (shared between states; [`FiniteModel::next_state`] restores it to step).
    pub fn world(&self) -> &World<Exact> {
        &self.world
    }

    /// Whether the obstacle is still hidden (occlusion).
    pub fn hidden(&self) -> bool {
        self.hidden
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
        last: SpeedSeen,
        /// The pending observations' verdicts and, while the obstacle is hidden, which
        /// of them may first show it.
        pending: PendingKey,
    },
    /// Braking: only gap and speed matter.
    Braking { speed: Exact, gap: Exact },
    /// At rest for good.
    Stopped,
}

/// The pending observations as a key sees them: each one's verdict and, while the obstacle
/// is hidden (`hidden`), whether it may first show it. Shares the state's nodes.
#[derive(Clone, Debug)]
struct PendingKey {
    pending: Window<Pending>,
    hidden: bool,
}

impl PartialEq for PendingKey {
    fn eq(&self, other: &Self) -> bool {
        self.hidden == other.hidden
            && self.pending.same_by(&other.pending, |a, b| {
                a.seen == b.seen && (!self.hidden || a.sight == b.sight)
            })
    }
}

impl Eq for PendingKey {}

impl Hash for PendingKey {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.hidden.hash(state);
        let hidden = self.hidden;
        self.pending.hash_by(state, |p, h| {
            p.seen.hash(h);
            if hidden {
                p.sight.hash(h);
            }
        });
    }
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
    /// The obstacle is still hidden and no observation to come shows a true gap ≥ d_det:
    /// no behaviour goes through this state (its first sighting came too late), so it and
    /// the step into it are left out.
    Lost,
}

/// One choice of the environment for one control period.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Choice {
    /// Index of the obstacle's speed in the speed set.
    pub speed: u16,
    /// Occlusion: the hidden obstacle is first seen at this period's start.
    pub show: bool,
    /// The observation error lets the guard fire (else it keeps it quiet); where only one
    /// is possible, that one. True exactly when the guard fires in this period.
    pub react: bool,
}

/// One step of the model: the step function's record and the state it leads to.
#[derive(Clone, Debug)]
pub struct Transition {
    /// What [`World::step`] reported.
    pub record: StepRecord<Exact>,
    /// The next state.
    pub next: State,
}

/// The finite model: a problem, the obstacle's speed set and the starts explored.
#[derive(Clone, Debug)]
pub struct FiniteModel {
    params: Params<Exact>,
    speeds: SpeedSet,
    /// The initial gaps explored: the problem's, or points of its range.
    starts: Vec<Exact>,
    /// d_coll(v_max), the largest danger distance (None: infinite, the `area` rule).
    top_danger: Option<Exact>,
}

impl FiniteModel {
    /// The model of a (validated) problem with the obstacle's speeds from `speeds` (and for
    /// a range of initial gaps, [`DEFAULT_STARTS`] starts).
    pub fn new(problem: &Problem, speeds: SpeedSet) -> Self {
        Self::from_params(problem.params(), speeds)
    }

    /// As [`FiniteModel::new`], from exact parameters.
    pub fn from_params(params: Params<Exact>, speeds: SpeedSet) -> Self {
        let top_danger = danger_distance(&params, &params.v_max);
        let starts = starts(&params, DEFAULT_STARTS).expect("the default count is valid");
        FiniteModel {
            params,
            speeds,
            starts,
            top_danger,
        }
    }

    /// The same model with `n` evenly spaced starts over the range of initial gaps, both
    /// ends included (n ≥ 2; a single initial gap is its only start whatever n).
    pub fn with_starts(mut self, n: usize) -> Result<Self, ExploreError> {
        self.starts = starts(&self.params, n)?;
        Ok(self)
    }

    /// The problem's exact numbers.
    pub fn params(&self) -> &Params<Exact> {
        &self.params
    }

    /// The obstacle's speed set.
    pub fn speeds(&self) -> &SpeedSet {
        &self.speeds
    }

    /// The initial gaps explored, ascending.
    pub fn starts(&self) -> &[Exact] {
        &self.starts
    }

    /// The init states, one per start (in [`FiniteModel::starts`] order): the world at
    /// t = 0, the obstacle hidden if it may be (occlusion). A start from which a hidden
    /// obstacle can never be seen has no behaviour and is left out.
    pub fn init_states(&self) -> Vec<State> {
        self.starts
            .iter()
            .map(|g| State {
                world: World::with_gap(self.params.clone(), g.clone()),
                history: Window::empty(),
                pending: (0..self.params.L).fold(Window::empty(), |w, _| {
                    let quiet = Pending {
                        seen: Seen::Quiet,
                        sight: Sight::Nothing,
                    };
                    w.pushed(quiet, self.params.L)
                }),
                last: SpeedSeen::NONE_YET,
                hidden: self.params.d_det.is_some(),
            })
            .filter(|s| self.status(s) != Status::Lost)
            .collect()
    }

    /// Whether `state` has successors.
    pub fn status(&self, state: &State) -> Status {
        let w = &state.world;
        match w.robot().mode {
            Mode::Stop => Status::Stopped,
            Mode::Accelerate | Mode::Drive if state.hidden => {
                if self.sighting_left(state) {
                    Status::Running
                } else {
                    Status::Lost
                }
            }
            Mode::Accelerate | Mode::Drive
                if *w.gap() <= -self.params.sigma_g.clone()
                    && state.pending.newest_first().all(|s| s.seen == Seen::Quiet) =>
            {
                Status::NeverBrakes
            }
            _ => Status::Running,
        }
    }

    /// Whether some observation to come may be a hidden obstacle's first sighting: the
    /// first one that exists (pending, or else the current gap) shows a true gap ≥ d_det.
    fn sighting_left(&self, state: &State) -> bool {
        match state
            .pending
            .oldest_first()
            .find(|s| s.sight != Sight::Nothing)
        {
            Some(s) => s.sight == Sight::Far,
            None => Sight::of(&self.params, state.world.gap()) == Sight::Far,
        }
    }

    /// `(fire, quiet)` for the observation at this step, if the obstacle is seen in it
    /// (`show`: first seen now): what some error makes the guard do.
    fn now(&self, state: &State, show: bool) -> (bool, bool) {
        if state.hidden && !show {
            return (false, true);
        }
        let v = &state.world.robot().speed;
        match state.pending.oldest() {
            Some(s) => resolve(&self.params, &s.seen, v),
            // L = 0: the robot sees the current gap with the last period's speed.
            None => {
                let seen = classify(
                    &self.params,
                    state.world.gap(),
                    state.last,
                    v,
                    self.top_danger.as_ref(),
                );
                resolve(&self.params, &seen, v)
            }
        }
    }

    /// Whether the hidden obstacle may be first seen at this step: an observation exists
    /// and shows a true gap ≥ d_det.
    fn may_show(&self, state: &State) -> bool {
        state.hidden
            && match state.pending.oldest() {
                Some(s) => s.sight == Sight::Far,
                None => Sight::of(&self.params, state.world.gap()) == Sight::Far,
            }
    }

    /// The choices of `state`, in their fixed order: ascending speed, then hidden before
    /// seen, then the error keeping the guard quiet before letting it fire; none for a
    /// terminal state.
    pub fn actions(&self, state: &State) -> Vec<Choice> {
        if self.status(state) != Status::Running {
            return Vec::new();
        }
        let moving = matches!(state.world.robot().mode, Mode::Accelerate | Mode::Drive);
        let shows: &[bool] = if self.may_show(state) {
            &[false, true]
        } else {
            &[false]
        };
        let mut aims = Vec::with_capacity(shows.len() * 2);
        for &show in shows {
            let (fire, quiet) = if moving {
                self.now(state, show)
            } else {
                (false, true)
            };
            if quiet {
                aims.push((show, false));
            }
            if fire {
                aims.push((show, true));
            }
        }
        (0..self.speeds.len() as u16)
            .flat_map(|speed| {
                aims.iter()
                    .map(move |&(show, react)| Choice { speed, show, react })
            })
            .collect()
    }

    /// The state `choice` leads to from `state`, through [`World::step_with`].
    ///
    /// [`World::step_with`]: crate::core::semantics::World::step_with
    pub fn next_state(&self, state: &State, choice: Choice) -> Result<Transition, ExploreError> {
        let p = &self.params;
        let w = self
            .speeds
            .speeds()
            .get(usize::from(choice.speed))
            .ok_or_else(|| ExploreError::Inconsistent("a speed outside the set".into()))?
            .clone();
        if choice.show && !self.may_show(state) {
            return Err(ExploreError::Inconsistent(format!(
                "at step {} the obstacle cannot be first seen",
                state.world.k()
            )));
        }
        let moving_before = matches!(state.world.robot().mode, Mode::Accelerate | Mode::Drive);
        let predicted = moving_before.then(|| {
            let (fire, quiet) = self.now(state, choice.show);
            if choice.react { fire } else { !quiet }
        });
        let mut world = state.world.clone();
        let (gaps, speeds) = state
            .history
            .oldest_first()
            .map(|(g, w)| (g.clone(), w.clone()))
            .unzip();
        world.restore_history(gaps, speeds);
        if state.hidden {
            world.hide_until(if choice.show { world.k() } else { usize::MAX });
        }
        let record = world.step_with(w.clone(), choice.react);
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
        let history = self.shared_history(state, &mut world)?;
        let next = match world.robot().mode {
            Mode::Accelerate | Mode::Drive => {
                let mut pending = state.pending.clone();
                if pending.len() > 0 {
                    // The gap at this step's start, with the previous period's speed, is
                    // what the robot sees L periods from now.
                    pending = pending.pushed(
                        Pending {
                            seen: classify(
                                p,
                                &record.gap,
                                state.last,
                                &world.robot().speed,
                                self.top_danger.as_ref(),
                            ),
                            sight: Sight::of(p, &record.gap),
                        },
                        p.L,
                    );
                }
                State {
                    world,
                    history,
                    pending,
                    last: SpeedSeen::of(p, &w),
                    hidden: state.hidden && !choice.show,
                }
            }
            Mode::Brake | Mode::Stop | Mode::Idle => State {
                world,
                history,
                pending: Window::empty(),
                last: SpeedSeen::NONE_YET,
                hidden: false,
            },
        };
        Ok(Transition { record, next })
    }

    /// The history `world` holds after a step from `state`, taken out of it: the state's
    /// shared history with the one entry the step added (checked against the world's).
    fn shared_history(
        &self,
        state: &State,
        world: &mut World<Exact>,
    ) -> Result<Window<(Exact, Exact)>, ExploreError> {
        let (gaps, speeds) = world.take_history();
        let (Some(gap), Some(speed)) = (gaps.back(), speeds.back()) else {
            return Err(ExploreError::Inconsistent("a step left no history".into()));
        };
        let history = state
            .history
            .pushed((gap.clone(), speed.clone()), self.params.L + 1);
        let same = history.len() == gaps.len()
            && history.len() == speeds.len()
            && history
                .oldest_first()
                .zip(gaps.iter().zip(&speeds))
                .all(|((g, w), (g2, w2))| g == g2 && w == w2);
        if !same {
            return Err(ExploreError::Inconsistent(format!(
                "at step {} the shared history is not the world's",
                world.k()
            )));
        }
        Ok(history)
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
                // The last speed is observed only with the current gap.
                let last = if may_be_in_area(&self.params, &gap) {
                    state.last
                } else {
                    SpeedSeen::NONE_YET
                };
                KeyRepr::Moving {
                    mode,
                    speed: robot.speed.clone(),
                    last,
                    gap,
                    pending: PendingKey {
                        pending: state.pending.clone(),
                        hidden: state.hidden,
                    },
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crosscheck::explore::SpeedSet;

    /// The seed problem's model at latency `l`, its speeds {0, W}.
    fn seed_model(l: usize) -> FiniteModel {
        let text = include_str!("../../../problems/seed.toml");
        let set = format!("robot.latency={l}");
        let problem = Problem::from_toml_str_with_overrides(text, "seed.toml", &[set])
            .expect("a valid problem");
        let speeds = SpeedSet::evenly_spaced(&problem.params::<Exact>().W, 2).expect("two speeds");
        FiniteModel::new(&problem, speeds)
    }

    #[test]
    fn a_step_adds_one_node_of_history_whatever_the_latency() {
        for l in [1, 20, 999] {
            let model = seed_model(l);
            let mut state = model.init_states().remove(0);
            for step in 0..40 {
                let choice = model.actions(&state)[usize::from(step % 3 == 0)];
                let next = model.next_state(&state, choice).expect("a step").next;
                assert_eq!(next.pending.len(), l, "latency {l}, step {step}");
                assert_eq!(next.history.len(), (step + 1).min(l + 1));
                // What storing the successor costs beyond its parent: one node each.
                assert_eq!(next.pending.nodes_not_in(&state.pending), 1);
                assert_eq!(next.history.nodes_not_in(&state.history), 1);
                let (gaps, _) = next.world.clone().take_history();
                assert!(gaps.is_empty(), "the world keeps no copy of the history");
                state = next;
            }
        }
    }
}
