//! The breadth-first search over a scene's finite model (the layer's one search,
//! `crosscheck::bfs`), what it watches on every transition (collisions, each obstacle's
//! least separation, behaviours that drive through an obstacle for ever), and the paths
//! read back from the search's parent links and replayed from scratch through
//! [`simulate::replay_exact_speeds`].

use super::model::{Look, SceneModel, SceneState, SceneStatus, SceneTransition};
use super::speeds::SceneSpeeds;
use crate::core::num::{Exact, Scalar};
use crate::core::rational::Rational;
use crate::core::scene::simulate::{self, SceneReplay};
use crate::core::scene::{ObservationPlan, Scene};
use crate::crosscheck::bfs::{self, MAX_NODES, NodeId, Reached, Successors};
use crate::crosscheck::explore::{ExploreError, ExploreVerdict, Options};

use super::key::SceneKey;

/// A path of the model: the starts, every obstacle's speed in every period, and its replay.
#[derive(Clone, Debug)]
pub struct ScenePath {
    /// Each obstacle's x at t = 0.
    pub starts: Vec<Exact>,
    /// `speeds[i][k]`: obstacle i's speed in period k, exactly.
    pub speeds: Vec<Vec<Exact>>,
    /// What the robot was shown (exact observations, every obstacle visible from the
    /// start, unless the scene has noise or occlusion).
    pub plan: ObservationPlan<Exact>,
    /// The path replayed from scratch through [`simulate::replay_observing`] (for a
    /// counterexample, stopping at its collision).
    pub replay: SceneReplay,
}

impl ScenePath {
    /// Number of control periods (joint actions).
    pub fn periods(&self) -> usize {
        self.speeds.first().map_or(0, Vec::len)
    }
}

/// What the search found about one obstacle.
#[derive(Clone, Debug)]
pub struct ObstacleExploration {
    /// Least separation sep_i over every explored behaviour in which the robot moved in its
    /// lane, exactly (None: in none). With `unbounded` it is −∞ regardless.
    pub min_separation: Option<Exact>,
    /// Some explored behaviour drives through it for ever: sep_i = −∞.
    pub unbounded: bool,
    /// Some explored behaviour collides with it.
    pub collides: bool,
    /// The path to the period realising `min_separation` (with `unbounded`: to the first
    /// state from which its separation falls without bound).
    pub closest: Option<ScenePath>,
}

impl ObstacleExploration {
    /// The least separation as a float: −∞ when unbounded, None when the robot never moved
    /// in its lane.
    pub fn min_separation_f64(&self) -> Option<f64> {
        if self.unbounded {
            Some(f64::NEG_INFINITY)
        } else {
            self.min_separation.as_ref().map(|s| s.to_f64().value())
        }
    }
}

/// The result of a scene search.
#[derive(Clone, Debug)]
pub struct SceneExploration {
    /// The verdict: `collision` as soon as one is found (its path replays to it), `safe`
    /// only when every branch ended, `inconclusive` otherwise.
    pub verdict: ExploreVerdict,
    /// Every branch ended (false: the state budget or the horizon was reached).
    pub complete: bool,
    /// The state budget ran out.
    pub budget_exhausted: bool,
    /// The state limit the search ran with: [`Options::max_states`], or fewer when
    /// [`Options::max_memory`] holds fewer states of this model's size.
    pub state_limit: usize,
    /// Some branch was still running at the horizon.
    pub horizon_reached: bool,
    /// The horizon, in periods.
    pub horizon: usize,
    /// Distinct states stored (init states included).
    pub states: usize,
    /// Transitions computed (calls of the step function).
    pub transitions: usize,
    /// Length of the longest path explored, in control periods.
    pub depth: usize,
    /// Per obstacle, in the scene's order.
    pub obstacles: Vec<ObstacleExploration>,
    /// On collision: a shortest path to a colliding period.
    pub counterexample: Option<ScenePath>,
    /// The speed sets explored.
    pub speeds: SceneSpeeds,
    /// Each obstacle's starts explored.
    pub starts: Vec<Vec<Exact>>,
}

impl SceneExploration {
    /// Some explored behaviour drives through an obstacle for ever (s = −∞).
    pub fn never_stops(&self) -> bool {
        self.obstacles.iter().any(|o| o.unbounded)
    }

    /// The least finite separation over every obstacle (None: the robot never moved in any
    /// obstacle's lane). With [`Self::never_stops`] the least separation is −∞ regardless.
    pub fn min_separation(&self) -> Option<Exact> {
        self.obstacles
            .iter()
            .filter_map(|o| o.min_separation.clone())
            .min()
    }

    /// The least separation as a float: −∞ when some behaviour never stops.
    pub fn min_separation_f64(&self) -> Option<f64> {
        if self.never_stops() {
            Some(f64::NEG_INFINITY)
        } else {
            self.min_separation().map(|s| s.to_f64().value())
        }
    }

    /// The obstacle of the least separation (an unbounded one first, then the least, the
    /// lowest index on ties).
    pub fn worst(&self) -> Option<usize> {
        if let Some(i) = self.obstacles.iter().position(|o| o.unbounded) {
            return Some(i);
        }
        let least = self.min_separation()?;
        self.obstacles
            .iter()
            .position(|o| o.min_separation.as_ref() == Some(&least))
    }

    /// The path of the least separation.
    pub fn closest(&self) -> Option<&ScenePath> {
        self.obstacles[self.worst()?].closest.as_ref()
    }
}

/// The end of a path: the state `node`, then joint action `action`.
#[derive(Clone, Copy)]
struct PathEnd {
    node: NodeId,
    action: u32,
}

#[derive(Default)]
struct ObstacleWatch {
    min: Option<Rational>,
    closest: Option<PathEnd>,
    unbounded: Option<PathEnd>,
    collides: bool,
}

/// What the search watches on the transitions it computes, in the order it computes them.
struct Watch {
    transitions: usize,
    depth: usize,
    counterexample: Option<PathEnd>,
    obstacles: Vec<ObstacleWatch>,
    horizon_reached: bool,
}

impl Watch {
    fn note(&mut self, model: &SceneModel, t: &SceneTransition, status: SceneStatus, end: PathEnd) {
        self.transitions += 1;
        self.depth = self.depth.max(t.record.k + 1);
        for (watch, step) in self.obstacles.iter_mut().zip(&t.record.obstacles) {
            let Some(safety) = &step.safety else { continue };
            if safety.collision {
                watch.collides = true;
                self.counterexample.get_or_insert(end);
            }
            if watch.min.as_ref().is_none_or(|m| safety.sep < *m) {
                watch.min = Some(safety.sep.clone());
                watch.closest = Some(end);
            }
        }
        if status == SceneStatus::NeverBrakes {
            for i in model.unbounded(&t.next) {
                self.obstacles[i].unbounded.get_or_insert(end);
            }
        }
    }
}

/// Explores every joint behaviour of a (validated) scene's finite model, with each
/// obstacle's speeds from `speeds`, breadth first.
pub fn explore_scene(
    scene: &Scene,
    speeds: SceneSpeeds,
    options: &Options,
) -> Result<SceneExploration, ExploreError> {
    explore_scene_model(&SceneModel::new(scene.params(), speeds)?, options)
}

/// Explores a scene model breadth first (see the module docs).
pub fn explore_scene_model(
    model: &SceneModel,
    options: &Options,
) -> Result<SceneExploration, ExploreError> {
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
    // Init states with distinct keys, so that the search's root ids index `roots`.
    let mut roots: Vec<Vec<Exact>> = Vec::new();
    let mut init: Vec<(SceneKey, SceneState)> = Vec::new();
    for starts in model.start_combinations() {
        let Some(state) = model.init_state(&starts) else {
            continue;
        };
        let key = model.key(&state, SceneStatus::Running);
        if !init.iter().any(|(k, _)| *k == key) {
            init.push((key, state));
            roots.push(starts);
        }
    }
    let mut watch = Watch {
        transitions: 0,
        depth: 0,
        counterexample: None,
        obstacles: (0..model.params().obstacles.len())
            .map(|_| ObstacleWatch::default())
            .collect(),
        horizon_reached: false,
    };
    let params = model.params();
    let state_limit = options.state_limit(crate::crosscheck::explore::bytes_per_state(
        params.robot.L,
        params.obstacles.len(),
    ));
    let reached = bfs::search(init, state_limit, |id, state, next| {
        expand(model, &mut watch, id, state, next);
        Ok::<(), ExploreError>(())
    })?;
    let replay = |end: PathEnd, stop: bool| replay(model, &reached, &roots, end, stop);
    let counterexample = watch.counterexample.map(|e| replay(e, true)).transpose()?;
    if let Some(c) = &counterexample
        && !c.replay.run.records.last().is_some_and(|r| r.collision())
    {
        return Err(ExploreError::Inconsistent(
            "the counterexample does not collide when replayed".into(),
        ));
    }
    let mut obstacles = Vec::with_capacity(watch.obstacles.len());
    for (i, w) in watch.obstacles.iter().enumerate() {
        let min = w.min.as_ref().map(Rational::to_exact);
        let closest = match (w.unbounded, w.closest) {
            (Some(end), _) | (None, Some(end)) => Some(replay(end, false)?),
            (None, None) => None,
        };
        if w.unbounded.is_none()
            && let Some(path) = &closest
            && path.replay.separations()[i] != min
        {
            return Err(ExploreError::Inconsistent(format!(
                "obstacle {i}: the closest path replays to another separation"
            )));
        }
        obstacles.push(ObstacleExploration {
            min_separation: min,
            unbounded: w.unbounded.is_some(),
            collides: w.collides,
            closest,
        });
    }
    let complete = reached.complete && !watch.horizon_reached;
    let verdict = if counterexample.is_some() {
        ExploreVerdict::Collision
    } else if complete {
        ExploreVerdict::Safe
    } else {
        ExploreVerdict::Inconclusive
    };
    Ok(SceneExploration {
        verdict,
        complete,
        budget_exhausted: !reached.complete,
        state_limit,
        horizon_reached: watch.horizon_reached,
        horizon: model.horizon(),
        states: reached.states,
        transitions: watch.transitions,
        depth: watch.depth,
        obstacles,
        counterexample,
        speeds: model.speeds().clone(),
        starts: model.starts().to_vec(),
    })
}

/// The successors of `state` (stored as `id`), in the fixed joint-action order, each
/// transition watched before its next state is offered to the search. A state still running
/// at the horizon is not expanded (the search is then incomplete).
fn expand(
    model: &SceneModel,
    watch: &mut Watch,
    id: NodeId,
    state: &SceneState,
    next: &mut Successors<'_, SceneState, SceneKey, u32>,
) {
    if state.world().k() >= model.horizon() {
        watch.horizon_reached = true;
        return;
    }
    let moves = model.moves(state);
    for action in 0..moves.len() {
        // A lost next state belongs to no behaviour: its step is not watched either.
        let Some(t) = model.next_state(state, &moves, action) else {
            continue;
        };
        let end = PathEnd {
            node: id,
            action: action as u32,
        };
        let status = model.status(&t.next);
        watch.note(model, &t, status, end);
        let key = model.key(&t.next, status);
        let flow = if status == SceneStatus::Running {
            next.offer(end.action, key, |_| t.next)
        } else {
            next.offer_leaf(end.action, key)
        };
        if flow.is_break() {
            break;
        }
    }
}

/// The path to the state `end.node` then `end.action`, replayed from scratch (stopping at
/// the first collision if `stop_at_collision`).
fn replay(
    model: &SceneModel,
    reached: &Reached<u32>,
    roots: &[Vec<Exact>],
    end: PathEnd,
    stop_at_collision: bool,
) -> Result<ScenePath, ExploreError> {
    let (root, mut actions) = reached.rooted_path_to(end.node);
    actions.push(end.action);
    let n = model.params().obstacles.len();
    let starts = roots[root as usize].clone();
    let inconsistent = || ExploreError::Inconsistent("a stored path is not a path".into());
    // The actions' looks depend on the state they are taken in: walk the model again.
    let mut state = model.init_state(&starts).ok_or_else(inconsistent)?;
    let mut speeds: Vec<Vec<Exact>> = vec![Vec::with_capacity(actions.len()); n];
    let mut plan = ObservationPlan::exact(n);
    plan.hidden_until = vec![actions.len(); n];
    for (k, &a) in actions.iter().enumerate() {
        let moves = model.moves(&state);
        let a = a as usize;
        for (i, c) in model.choices(moves.speed_action(a)).into_iter().enumerate() {
            speeds[i].push(model.speed(i, c).clone());
        }
        for (i, look) in moves.looks(a).iter().enumerate() {
            let Look::Shown {
                gap_error,
                speed_error,
            } = look
            else {
                continue;
            };
            plan.hidden_until[i] = plan.hidden_until[i].min(k);
            if *gap_error != Rational::zero() || *speed_error != Rational::zero() {
                plan.errors
                    .insert((i, k), (gap_error.to_exact(), speed_error.to_exact()));
            }
        }
        if k + 1 < actions.len() {
            state = model
                .next_state(&state, &moves, a)
                .ok_or_else(inconsistent)?
                .next;
        }
    }
    let replay = simulate::replay_observing(
        model.params(),
        &speeds,
        &plan,
        &starts,
        actions.len(),
        stop_at_collision,
    );
    if replay.periods() != actions.len() {
        return Err(ExploreError::Inconsistent(format!(
            "a path of {} periods replays for only {}",
            actions.len(),
            replay.periods()
        )));
    }
    Ok(ScenePath {
        starts,
        speeds,
        plan,
        replay,
    })
}
