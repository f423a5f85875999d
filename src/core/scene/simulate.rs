//! Running a scene forward: runs, exact replay (in [`Exact`] and in `Rational`), traces and
//! the horizon, as [`crate::core::simulate`] does for one obstacle, through the one scene
//! step function [`SceneWorld::step`].

use serde::{Deserialize, Serialize};

use crate::core::num::{Exact, Scalar, exact_float};
use crate::core::rational::Rational;
use crate::core::semantics::{BrakeReason, Mode, Observation};
use crate::core::simulate::TraceRow;

use super::lateral::{LaneChangeEvent, Lateral};
use super::observe::ObservationPlan;
use super::params::SceneParams;
use super::world::{SceneStepRecord, SceneWorld};

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum RunEnd {
    /// The robot came to rest.
    Rest,
    /// Nothing could happen any more ([`SceneWorld::settled`]): the robot drives on for ever.
    Settled,
    /// Stopped at the first collision, as asked.
    Collision,
    /// `max_steps` periods passed.
    MaxSteps,
}

/// One obstacle's safety over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleSafety<N> {
    /// sep_i: infimum of its separation measure over the instants at which the robot moved
    /// in its lane (None: the robot never did).
    pub sep: Option<N>,
    /// The robot moved in its lane with separation ≤ clearance at some instant.
    pub collided: bool,
}

/// How a scene run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOutcome<N> {
    /// The robot collided with some obstacle.
    pub collided: bool,
    /// Each obstacle's safety, in the scene's order.
    pub obstacles: Vec<ObstacleSafety<N>>,
    /// Step at whose start the robot braked, and why.
    pub brake: Option<(usize, BrakeReason)>,
    /// The lane changes, in order.
    pub lane_changes: Vec<LaneChangeEvent>,
    /// Each obstacle's gap when the robot came to rest (None: it never did within the run).
    pub rest_gaps: Option<Vec<N>>,
    /// Why the run ended.
    pub end: RunEnd,
}

impl<N: Scalar> SceneOutcome<N> {
    /// The obstacle with the least separation (a colliding one first on ties, then the
    /// lowest index); None when the robot never moved in any obstacle's lane.
    pub fn worst(&self) -> Option<usize> {
        let mut best: Option<(usize, &N, bool)> = None;
        for (i, o) in self.obstacles.iter().enumerate() {
            let Some(sep) = &o.sep else { continue };
            let better = match best {
                None => true,
                Some((_, s, c)) => *sep < *s || (*sep == *s && o.collided && !c),
            };
            if better {
                best = Some((i, sep, o.collided));
            }
        }
        best.map(|(i, _, _)| i)
    }

    /// The least separation of any obstacle, and which obstacle it is.
    pub fn min_separation(&self) -> Option<(usize, N)> {
        let i = self.worst()?;
        self.obstacles[i].sep.clone().map(|s| (i, s))
    }
}

/// A scene run's records and outcome.
#[derive(Clone, Debug)]
pub struct SceneRun<N> {
    /// One record per simulated period.
    pub records: Vec<SceneStepRecord<N>>,
    /// How it ended.
    pub outcome: SceneOutcome<N>,
}

/// Runs the scene from `starts` (one x per obstacle) with `speed(i, k)` as obstacle i's
/// speed in period k, until the robot rests, nothing can happen any more (after at least
/// one period; see [`SceneWorld::settled`]), or `max_steps` periods pass; with
/// `stop_at_collision`, also at the first collision. (Past a collision obstacles move
/// through the robot, so a replay can go on to the instant it rests.)
pub fn run<N: Scalar>(
    params: SceneParams<N>,
    speed: impl FnMut(usize, usize) -> N,
    starts: Vec<N>,
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneRun<N> {
    run_observing(
        params,
        speed,
        |_, _, truth| Some(truth),
        starts,
        max_steps,
        stop_at_collision,
    )
}

/// [`run`] with the robot's observations chosen by the environment: `shown(i, k, truth)` is
/// what it is shown of obstacle i at step k's start ([`SceneWorld::step_seeing`]).
pub fn run_observing<N: Scalar>(
    params: SceneParams<N>,
    mut speed: impl FnMut(usize, usize) -> N,
    mut shown: impl FnMut(usize, usize, Observation<N>) -> Option<Observation<N>>,
    starts: Vec<N>,
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneRun<N> {
    let n = params.obstacles.len();
    let mut world = SceneWorld::new(params, starts);
    let mut records = Vec::new();
    let mut outcome = SceneOutcome {
        collided: false,
        obstacles: vec![
            ObstacleSafety {
                sep: None,
                collided: false
            };
            n
        ],
        brake: None,
        lane_changes: Vec::new(),
        rest_gaps: None,
        end: RunEnd::MaxSteps,
    };
    let mut speeds = Vec::with_capacity(n);
    loop {
        if world.stopped() {
            outcome.end = RunEnd::Rest;
            break;
        }
        if world.k() >= max_steps {
            break;
        }
        if world.k() > 0 && world.settled() {
            outcome.end = RunEnd::Settled;
            break;
        }
        let k = world.k();
        speeds.clear();
        speeds.extend((0..n).map(|i| speed(i, k)));
        let rec = world.step_seeing(&speeds, |i, truth| shown(i, k, truth));
        if let Some(reason) = rec.brake {
            outcome.brake = Some((rec.k, reason));
        }
        outcome.lane_changes.extend(rec.lane_change);
        for (total, step) in outcome.obstacles.iter_mut().zip(&rec.obstacles) {
            if let Some(s) = &step.safety {
                total.sep = Some(match total.sep.take() {
                    Some(m) => N::min_of(m, s.sep.clone()),
                    None => s.sep.clone(),
                });
                total.collided |= s.collision;
            }
        }
        if rec.motion.came_to_rest() {
            outcome.rest_gaps = rec.obstacles.iter().map(|o| o.rest_gap.clone()).collect();
        }
        let hit = rec.collision();
        records.push(rec);
        if hit {
            outcome.collided = true;
            if stop_at_collision {
                outcome.end = if world.stopped() {
                    RunEnd::Rest
                } else {
                    RunEnd::Collision
                };
                break;
            }
        }
    }
    SceneRun { records, outcome }
}

/// Obstacle i's exact speed in period k: `speeds[i][k]` read as the exact rational the float
/// is, W_i after the last one.
fn exact_speed(params: &SceneParams<Exact>, speeds: &[Vec<f64>], i: usize, k: usize) -> Exact {
    speeds
        .get(i)
        .and_then(|s| s.get(k))
        .map(|&w| exact_float(w))
        .unwrap_or_else(|| params.obstacles[i].max_speed.clone())
}

/// Replays per-obstacle speeds exactly (`speeds[i][k]` for obstacle i in period k, W_i after
/// the last one) from `starts`, as [`run`] does.
pub fn replay_exact(
    params: &SceneParams<Exact>,
    speeds: &[Vec<f64>],
    starts: &[Exact],
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneRun<Exact> {
    run(
        params.clone(),
        |i, k| exact_speed(params, speeds, i, k),
        starts.to_vec(),
        max_steps,
        stop_at_collision,
    )
}

/// A scene witness replay: exact like [`replay_exact`], computed with `Rational` (machine
/// words while the numbers fit).
#[derive(Clone, Debug)]
pub struct SceneReplay {
    /// The run, in fast exact numbers.
    pub run: SceneRun<Rational>,
    /// The parameters it ran with.
    pub params: SceneParams<Rational>,
}

impl SceneReplay {
    /// Whether the robot collided with some obstacle.
    pub fn collided(&self) -> bool {
        self.run.outcome.collided
    }

    /// Each obstacle's sep_i, exactly (None: the robot never moved in its lane).
    pub fn separations(&self) -> Vec<Option<Exact>> {
        self.run
            .outcome
            .obstacles
            .iter()
            .map(|o| o.sep.as_ref().map(Rational::to_exact))
            .collect()
    }

    /// Each obstacle's gap when the robot came to rest.
    pub fn rest_gaps(&self) -> Option<Vec<Exact>> {
        self.run
            .outcome
            .rest_gaps
            .as_ref()
            .map(|g| g.iter().map(Rational::to_exact).collect())
    }

    /// The obstacle with the least separation and its lane.
    pub fn worst(&self) -> Option<(usize, i32)> {
        let i = self.run.outcome.worst()?;
        Some((i, self.params.obstacles[i].lane))
    }

    /// Periods run.
    pub fn periods(&self) -> usize {
        self.run.records.len()
    }

    /// The trace rows.
    pub fn trace(&self) -> Vec<SceneTraceRow> {
        trace(&self.params, &self.run)
    }
}

/// Replays per-obstacle speeds exactly, as [`replay_exact`] does, in `Rational` numbers.
pub fn replay(
    params: &SceneParams<Exact>,
    speeds: &[Vec<f64>],
    starts: &[Exact],
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneReplay {
    replay_with(
        params,
        |i, k| exact_speed(params, speeds, i, k),
        &ObservationPlan::exact(params.obstacles.len()),
        starts,
        max_steps,
        stop_at_collision,
    )
}

/// As [`replay`], for speeds given as exact numbers (`speeds[i][k]`, W_i after the last):
/// speeds that no float is, such as an explorer's W/3.
pub fn replay_exact_speeds(
    params: &SceneParams<Exact>,
    speeds: &[Vec<Exact>],
    starts: &[Exact],
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneReplay {
    let exact = ObservationPlan::exact(params.obstacles.len());
    replay_observing(params, speeds, &exact, starts, max_steps, stop_at_collision)
}

/// As [`replay_exact_speeds`], with the robot's observations as `plan` shows them (noise
/// and occlusion).
pub fn replay_observing(
    params: &SceneParams<Exact>,
    speeds: &[Vec<Exact>],
    plan: &ObservationPlan<Exact>,
    starts: &[Exact],
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneReplay {
    let speed = |i: usize, k: usize| {
        speeds
            .get(i)
            .and_then(|s| s.get(k))
            .cloned()
            .unwrap_or_else(|| params.obstacles[i].max_speed.clone())
    };
    replay_with(params, speed, plan, starts, max_steps, stop_at_collision)
}

/// A replay in `Rational` numbers with obstacle i's speed in period k from `speed(i, k)`
/// and the observations `plan` shows.
fn replay_with(
    params: &SceneParams<Exact>,
    speed: impl Fn(usize, usize) -> Exact,
    plan: &ObservationPlan<Exact>,
    starts: &[Exact],
    max_steps: usize,
    stop_at_collision: bool,
) -> SceneReplay {
    let fast: SceneParams<Rational> = params.map(Rational::from_exact);
    let plan: ObservationPlan<Rational> = plan.map(Rational::from_exact);
    let run = run_observing(
        fast.clone(),
        |i, k| Rational::from_exact(&speed(i, k)),
        |i, k, truth| plan.shown(i, k, truth),
        starts.iter().map(Rational::from_exact).collect(),
        max_steps,
        stop_at_collision,
    );
    SceneReplay { run, params: fast }
}

/// One row of a scene trace: one obstacle at one instant, with the robot's lanes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(from = "FlatSceneTraceRow")]
pub struct SceneTraceRow {
    /// The single-obstacle row's columns, for this obstacle.
    #[serde(flatten)]
    pub row: TraceRow,
    /// The obstacle's name.
    pub obstacle: String,
    /// The lane the robot occupies from this instant on; during a lane change, the lane it
    /// moves into.
    pub robot_lane: i32,
    /// During a lane change, the lane the robot is leaving (it occupies both).
    pub leaving_lane: Option<i32>,
    /// The obstacle's lane.
    pub obstacle_lane: i32,
}

/// A [`SceneTraceRow`] as it is read: every column named, so that an unknown one is refused
/// (serde cannot refuse unknown fields beside a flattened struct).
#[derive(Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
struct FlatSceneTraceRow {
    t: f64,
    robot_position: f64,
    robot_speed: f64,
    robot_mode: Mode,
    obstacle_position: f64,
    obstacle_speed: f64,
    gap: f64,
    obstacle: String,
    robot_lane: i32,
    leaving_lane: Option<i32>,
    obstacle_lane: i32,
}

impl From<FlatSceneTraceRow> for SceneTraceRow {
    fn from(f: FlatSceneTraceRow) -> Self {
        SceneTraceRow {
            row: TraceRow {
                t: f.t,
                robot_position: f.robot_position,
                robot_speed: f.robot_speed,
                robot_mode: f.robot_mode,
                obstacle_position: f.obstacle_position,
                obstacle_speed: f.obstacle_speed,
                gap: f.gap,
            },
            obstacle: f.obstacle,
            robot_lane: f.robot_lane,
            leaving_lane: f.leaving_lane,
            obstacle_lane: f.obstacle_lane,
        }
    }
}

/// The trace of a scene run: for each obstacle, a row at every period start and one at the
/// instant the robot came to rest (or, when the run ended on a collision or because nothing
/// could happen any more, at the end of its last period). Rows are ordered by time, then
/// by obstacle.
pub fn trace<N: Scalar>(params: &SceneParams<N>, run: &SceneRun<N>) -> Vec<SceneTraceRow> {
    let dt = &params.robot.dt;
    let mut rows = Vec::new();
    let last = run.records.len().saturating_sub(1);
    let end_row = matches!(run.outcome.end, RunEnd::Collision | RunEnd::Settled)
        || (run.outcome.end == RunEnd::MaxSteps
            && run.records.last().is_some_and(SceneStepRecord::collision));
    for (index, rec) in run.records.iter().enumerate() {
        let t = N::int(rec.k as i64) * dt.clone();
        let end = &rec.motion.end;
        push_rows(&mut rows, params, rec, rec.lateral, |o| {
            (
                t.clone(),
                rec.robot.position.clone(),
                rec.robot.speed.clone(),
                rec.robot.mode,
                o.gap.clone(),
            )
        });
        if rec.motion.came_to_rest() {
            let at = t.clone() + rec.motion.moving_for.clone();
            push_rows(&mut rows, params, rec, rec.lateral, |o| {
                let gap = o.rest_gap.clone().expect("a resting period has rest gaps");
                (at.clone(), end.position.clone(), N::zero(), Mode::Stop, gap)
            });
        } else if index == last && end_row {
            let at = t.clone() + dt.clone();
            let lateral = rec.lateral.at_step(rec.k + 1, params.lane_change_periods());
            push_rows(&mut rows, params, rec, lateral, |o| {
                (
                    at.clone(),
                    end.position.clone(),
                    end.speed.clone(),
                    end.mode,
                    o.end_gap.clone(),
                )
            });
        }
    }
    rows
}

/// One row per obstacle of `rec` at one instant: `state(o)` gives the instant, the robot's
/// position, speed and mode, and the obstacle's gap then.
fn push_rows<N: Scalar>(
    rows: &mut Vec<SceneTraceRow>,
    params: &SceneParams<N>,
    rec: &SceneStepRecord<N>,
    lateral: Lateral,
    state: impl Fn(&super::world::ObstacleStep<N>) -> (N, N, N, Mode, N),
) {
    for (o, step) in params.obstacles.iter().zip(&rec.obstacles) {
        let (t, x, v, mode, gap) = state(step);
        rows.push(SceneTraceRow {
            row: TraceRow {
                t: t.shown_f64(),
                robot_position: x.as_f64(),
                robot_speed: v.as_f64(),
                robot_mode: mode,
                obstacle_position: (x + gap.clone()).as_f64(),
                obstacle_speed: step.speed.as_f64(),
                gap: gap.as_f64(),
            },
            obstacle: o.name.clone(),
            robot_lane: lateral.lane,
            leaving_lane: lateral.leaving(),
            obstacle_lane: o.lane,
        });
    }
}

/// The number of periods after which a scene run certainly has ended or nothing can happen
/// any more, unless the robot has passed through an obstacle in its lane: it reaches the
/// farthest obstacle start (plus the clearance and the rear gap) or its goal even if no
/// obstacle moves, sees that with latency L, finishes a lane change, then stops within
/// v_max/(b_min·dt) more (the plant's braking).
pub fn horizon(params: &SceneParams<f64>) -> usize {
    let p = &params.robot;
    let rear = params.lane_change.as_ref().map_or(0.0, |lc| lc.rear_gap);
    let farthest = params
        .obstacles
        .iter()
        .map(|o| o.start_max + p.clearance + rear)
        .fold(0.0, f64::max);
    let distance = farthest.max(params.goal.unwrap_or(0.0));
    let reach = p.v_max / p.a + distance / p.v_max;
    let stop = p.v_max / p.b_min;
    ((reach + stop) / p.dt).ceil() as usize + p.L + params.lane_change_periods() + 4
}
