//! The explorer's search: the finite model handed to the layer's one breadth-first search
//! ([`crate::crosscheck::bfs`]), what is watched on every transition it computes (collisions,
//! the gap at rest, behaviours that never brake), and the paths read back from the search's
//! parent links and replayed through the simulator.

use super::model::{Choice, FiniteModel, State, StateKey, Status, Transition};
use super::{ExploreError, ExploreVerdict, Options, SpeedSet};
use crate::core::model::Problem;
use crate::core::num::Exact;
use crate::core::simulate::{self, Run, TraceRow};
use crate::crosscheck::bfs::{self, MAX_NODES, NodeId, Reached, Successors};

/// A path of the model, replayed through the simulator.
#[derive(Clone, Debug)]
pub struct Path {
    /// The initial gap it starts from.
    pub start: Exact,
    /// The actions: the obstacle's speed in each control period, exactly.
    pub speeds: Vec<Exact>,
    /// The aim of each period's observation error: true where it let the guard fire (the
    /// guard fired there), false where it kept it quiet or nothing was observed.
    pub reacts: Vec<bool>,
    /// Occlusion: the period at whose start the obstacle was first seen (None: hidden
    /// throughout the path, or no occlusion).
    pub first_seen: Option<usize>,
    /// The replay through [`simulate::run_choosing`] in exact numbers.
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
    /// The state limit the search ran with: [`Options::max_states`], or fewer when
    /// [`Options::max_memory`] holds fewer states of this model's size.
    pub state_limit: usize,
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
    /// The initial gaps explored.
    pub starts: Vec<Exact>,
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

/// The end of a path: the state `node`, then `action`.
#[derive(Clone, Copy)]
struct PathEnd {
    node: NodeId,
    action: Choice,
}

/// What the search watches on the transitions it computes, in the order it computes them.
#[derive(Default)]
struct Watch {
    transitions: usize,
    depth: usize,
    counterexample: Option<PathEnd>,
    min_separation: Option<Exact>,
    closest: Option<PathEnd>,
    never_stops: bool,
}

impl Watch {
    /// Takes note of the transition `t` at the end of a path `end`, leading to a state of
    /// status `status`.
    fn note(&mut self, t: &Transition, status: Status, end: PathEnd) {
        self.transitions += 1;
        self.depth = self.depth.max(t.record.k + 1);
        if t.record.collision && self.counterexample.is_none() {
            self.counterexample = Some(end);
        }
        if let Some(g) = &t.record.rest_gap
            && self.min_separation.as_ref().is_none_or(|m| g < m)
        {
            self.min_separation = Some(g.clone());
            if !self.never_stops {
                self.closest = Some(end);
            }
        }
        if status == Status::NeverBrakes && !self.never_stops {
            self.never_stops = true;
            self.closest = Some(end);
        }
    }
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
    if options.max_states >= MAX_NODES {
        return Err(ExploreError::Options(format!(
            "--max-states must be below {MAX_NODES}"
        )));
    }
    let mut watch = Watch::default();
    // Init states are kept in start order; the starts whose hidden obstacle can never be
    // seen are left out (no behaviour), so each root remembers its start.
    let init_states = model.init_states();
    let roots: Vec<Exact> = init_states
        .iter()
        .map(|s| s.world().gap().clone())
        .collect();
    let init = init_states.into_iter().map(|s| (model.key(&s), s));
    let state_limit = options.state_limit(super::PROBLEM_STATE_BYTES);
    let reached = bfs::search(init, state_limit, |id, state, next| {
        expand(model, &mut watch, id, state, next)
    })?;
    let counterexample = watch
        .counterexample
        .map(|end| replay(model, &roots, &reached, end, true))
        .transpose()?;
    if let Some(c) = &counterexample
        && !c.run.records.last().is_some_and(|r| r.collision)
    {
        return Err(ExploreError::Inconsistent(
            "the counterexample does not collide when replayed".into(),
        ));
    }
    let closest = watch
        .closest
        .map(|end| replay(model, &roots, &reached, end, false))
        .transpose()?;
    let verdict = if counterexample.is_some() {
        ExploreVerdict::Collision
    } else if reached.complete {
        ExploreVerdict::Safe
    } else {
        ExploreVerdict::Inconclusive
    };
    Ok(Exploration {
        verdict,
        complete: reached.complete,
        states: reached.states,
        state_limit,
        transitions: watch.transitions,
        depth: watch.depth,
        min_separation: watch.min_separation,
        never_stops: watch.never_stops,
        counterexample,
        closest,
        speeds: model.speeds().clone(),
        starts: model.starts().to_vec(),
    })
}

/// The successors of `state` (stored as `id`), in the fixed action order, each transition
/// watched before its next state is offered to the search. Terminal states are stored but
/// not expanded.
fn expand(
    model: &FiniteModel,
    watch: &mut Watch,
    id: NodeId,
    state: &State,
    next: &mut Successors<'_, State, StateKey, Choice>,
) -> Result<(), ExploreError> {
    for action in model.actions(state) {
        let t = model.next_state(state, action)?;
        let end = PathEnd { node: id, action };
        let status = model.status(&t.next);
        if status == Status::Lost {
            // Not a behaviour: the hidden obstacle is never seen at a gap ≥ d_det.
            watch.transitions += 1;
            continue;
        }
        watch.note(&t, status, end);
        let key = model.key(&t.next);
        let flow = if status == Status::Running {
            next.offer(end.action, key, |_| t.next)
        } else {
            next.offer_leaf(end.action, key)
        };
        if flow.is_break() {
            break;
        }
    }
    Ok(())
}

/// The path to the state `end.node` then `end.action`, replayed through the simulator
/// from its start with its choices (stopping at the first collision if
/// `stop_at_collision`).
fn replay(
    model: &FiniteModel,
    roots: &[Exact],
    reached: &Reached<Choice>,
    end: PathEnd,
    stop_at_collision: bool,
) -> Result<Path, ExploreError> {
    let (root, mut actions) = reached.rooted_path_to(end.node);
    actions.push(end.action);
    let start = roots[root as usize].clone();
    let speeds: Vec<Exact> = actions
        .iter()
        .map(|a| model.speeds().speeds()[usize::from(a.speed)].clone())
        .collect();
    let reacts: Vec<bool> = actions.iter().map(|a| a.react).collect();
    let first_seen = actions.iter().position(|a| a.show);
    let hidden_until = match (&model.params().d_det, first_seen) {
        (None, _) => 0,
        (Some(_), Some(k)) => k,
        (Some(_), None) => usize::MAX,
    };
    let run = simulate::run_choosing(
        model.params().clone(),
        start.clone(),
        |k| (speeds[k].clone(), reacts[k]),
        hidden_until,
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
    let trace = simulate::trace(model.params(), &run);
    Ok(Path {
        start,
        speeds,
        reacts,
        first_seen,
        run,
        trace,
    })
}
