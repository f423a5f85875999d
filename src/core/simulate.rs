//! Running the semantics forward: witness replay (exact or in floats) and Monte Carlo.
//!
//! Both go through [`World::step`], the one step function. Replay in [`Exact`] numbers is
//! what makes a refutation a theorem: the witness's obstacle speeds are floats, read as the
//! exact rationals they are, and the collision is decided without rounding.

use serde::{Deserialize, Serialize};

use crate::core::model::Params;
use crate::core::num::{Exact, Scalar, exact_float};
use crate::core::rational::Rational;
use crate::core::semantics::{BrakeReason, Mode, StepRecord, World};

/// One row of a trace: the state at a control-period start, or at the instant the robot
/// came to rest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct TraceRow {
    /// Time (s).
    pub t: f64,
    /// Robot position along its lane (m).
    pub robot_position: f64,
    /// Robot speed (m/s).
    pub robot_speed: f64,
    /// Robot mode from this instant on.
    pub robot_mode: Mode,
    /// Obstacle position along the robot's lane (m).
    pub obstacle_position: f64,
    /// Obstacle speed held from this instant to the next row (m/s).
    pub obstacle_speed: f64,
    /// Gap = obstacle position − robot position (m).
    pub gap: f64,
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutcome<N> {
    /// The robot was moving with gap ≤ clearance at some instant.
    pub collided: bool,
    /// Gap when the robot came to rest (None: it never did within the run).
    pub rest_gap: Option<N>,
    /// Step at whose start the robot braked, and why.
    pub brake: Option<(usize, BrakeReason)>,
    /// Lowest gap seen while the robot moved.
    pub min_moving_gap: Option<N>,
}

/// A run's records and outcome.
#[derive(Clone, Debug)]
pub struct Run<N> {
    /// One record per simulated period.
    pub records: Vec<StepRecord<N>>,
    /// How it ended.
    pub outcome: RunOutcome<N>,
}

/// Runs the world with `speed(k)` as the obstacle's speed in period k until the robot rests
/// or `max_steps` periods pass; with `stop_at_collision`, also at the first collision.
/// (Past a collision the semantics lets the obstacle move through the robot, so a replay
/// can go on to the instant the robot rests.)
pub fn run<N: Scalar>(
    params: Params<N>,
    speed: impl FnMut(usize) -> N,
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    run_reacting_at(params, speed, Aim::default(), max_steps, stop_at_collision)
}

/// What the environment aims at beyond the obstacle's speeds: the period from which it
/// lets the robot react (None: never), and the period before which it keeps the obstacle
/// hidden (0: seen from the start).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Aim {
    /// Errors keep the guard quiet before this period and let it fire from it on.
    pub react_at: Option<usize>,
    /// Nothing is seen at the starts of earlier periods.
    pub hidden_until: usize,
}

/// [`run`] with the environment's [`Aim`]: with noisy sensing it keeps the robot from
/// reacting before period `react_at` and lets it react from then on, as far as the noise
/// allows ([`World::step_with`]); with occlusion it hides the obstacle before
/// `hidden_until`. A worst case is replayed so: its schedule names both.
pub fn run_reacting_at<N: Scalar>(
    params: Params<N>,
    mut speed: impl FnMut(usize) -> N,
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    let react_at = aim.react_at;
    let mut world = World::new(params);
    world.hide_until(aim.hidden_until);
    run_world(
        world,
        |k| (speed(k), react_at.is_some_and(|t| k >= t)),
        max_steps,
        stop_at_collision,
    )
}

/// [`run`] from the initial gap `start` with the environment's choices period by period:
/// `choose(k)` is the obstacle's speed in period k and the aim of that period's observation
/// error (let the guard fire, else keep it quiet, as far as the noise allows:
/// [`World::step_with`]); the obstacle is hidden before period `hidden_until`. The
/// explorer's paths replay so, one choice per period.
pub fn run_choosing<N: Scalar>(
    params: Params<N>,
    start: N,
    choose: impl FnMut(usize) -> (N, bool),
    hidden_until: usize,
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    let mut world = World::with_gap(params, start);
    world.hide_until(hidden_until);
    run_world(world, choose, max_steps, stop_at_collision)
}

/// [`run`] with occlusion played late: the obstacle stays hidden for as long as a later
/// observation could still show a true gap ≥ d_det, and is seen from the last observation
/// that surely does (the observed gap falls by at most (v_max + W)·dt per period) — a
/// pedestrian stepping out as late as the premise allows. Without d_det it is [`run`].
pub fn run_hiding_late<N: Scalar>(
    params: Params<N>,
    mut speed: impl FnMut(usize) -> N,
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    let mut world = World::new(params);
    if world.params().d_det.is_some() {
        world.hide_until(usize::MAX);
    }
    run_world_with(
        world,
        |k| (speed(k), false),
        reveal_if_last_chance,
        max_steps,
        stop_at_collision,
    )
}

/// Shows a hidden obstacle now if its next observation might fall below d_det (or no
/// admissible sighting is left: then it is seen, as an obstacle visible from the start is).
fn reveal_if_last_chance<N: Scalar>(world: &mut World<N>) {
    let Some(d_det) = world.params().d_det.clone() else {
        return;
    };
    if world.observation().is_some() {
        return;
    }
    if let Some(obs) = world.observation_if_shown() {
        let p = world.params();
        let fall = (p.v_max.clone() + p.W.clone()) * p.dt.clone();
        if obs.gap - fall < d_det {
            world.hide_until(world.k());
        }
    }
}

/// Runs `world` with `choose(k)` = (speed, error aim) in period k (see [`run_choosing`]).
fn run_world<N: Scalar>(
    world: World<N>,
    choose: impl FnMut(usize) -> (N, bool),
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    run_world_with(world, choose, |_| {}, max_steps, stop_at_collision)
}

/// [`run_world`] with `before(world)` called at each period's start (the environment's
/// choices that need the world, such as when to show a hidden obstacle).
fn run_world_with<N: Scalar>(
    mut world: World<N>,
    mut choose: impl FnMut(usize) -> (N, bool),
    mut before: impl FnMut(&mut World<N>),
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<N> {
    let mut records = Vec::new();
    let mut outcome = RunOutcome {
        collided: false,
        rest_gap: None,
        brake: None,
        min_moving_gap: None,
    };
    while world.k() < max_steps && !world.stopped() {
        before(&mut world);
        let (w, react) = choose(world.k());
        let rec = world.step_with(w, react);
        if let Some(reason) = rec.brake {
            outcome.brake = Some((rec.k, reason));
        }
        if rec.motion.moving_for > N::zero() {
            let low = rec.rest_gap.clone().unwrap_or_else(|| rec.end_gap.clone());
            outcome.min_moving_gap = Some(match outcome.min_moving_gap.take() {
                Some(m) => N::min_of(m, low),
                None => low,
            });
        }
        if rec.rest_gap.is_some() {
            outcome.rest_gap = rec.rest_gap.clone();
        }
        let hit = rec.collision;
        records.push(rec);
        if hit {
            outcome.collided = true;
            if stop_at_collision {
                break;
            }
        }
    }
    Run { records, outcome }
}

/// Replays obstacle speeds exactly (`speeds[k]` in period k; W after the last one) for at
/// most `max_steps` periods, until the robot rests (or, with `stop_at_collision`, collides).
pub fn replay_exact(
    params: &Params<Exact>,
    speeds: &[f64],
    max_steps: usize,
    stop_at_collision: bool,
) -> Run<Exact> {
    let tail = params.W.clone();
    run(
        params.clone(),
        |k| {
            speeds
                .get(k)
                .map(|&w| exact_float(w))
                .unwrap_or_else(|| tail.clone())
        },
        max_steps,
        stop_at_collision,
    )
}

/// A witness replay: exact like [`replay_exact`], computed with `Rational` (machine words
/// while the numbers fit, several times faster on long runs).
#[derive(Clone, Debug)]
pub struct Replay {
    /// The run, in fast exact numbers.
    pub run: Run<Rational>,
    /// The parameters it ran with.
    pub params: Params<Rational>,
}

impl Replay {
    /// Whether the robot was moving with gap ≤ clearance at some instant.
    pub fn collided(&self) -> bool {
        self.run.outcome.collided
    }

    /// Gap when the robot came to rest.
    pub fn rest_gap(&self) -> Option<Exact> {
        self.run.outcome.rest_gap.as_ref().map(Rational::to_exact)
    }

    /// Periods run.
    pub fn periods(&self) -> usize {
        self.run.records.len()
    }

    /// The trace rows.
    pub fn trace(&self) -> Vec<TraceRow> {
        trace(&self.params, &self.run)
    }
}

/// Replays obstacle speeds exactly, as [`replay_exact`] does, in `Rational` numbers.
pub fn replay(
    params: &Params<Exact>,
    speeds: &[f64],
    max_steps: usize,
    stop_at_collision: bool,
) -> Replay {
    replay_reacting_at(params, speeds, Aim::default(), max_steps, stop_at_collision)
}

/// [`replay`] with the observation errors of [`run_reacting_at`].
pub fn replay_reacting_at(
    params: &Params<Exact>,
    speeds: &[f64],
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
) -> Replay {
    let params: Params<Rational> = params.map(Rational::from_exact);
    let tail = params.W.clone();
    let run = run_reacting_at(
        params.clone(),
        |k| {
            speeds
                .get(k)
                .map(|&w| Rational::from_exact(&exact_float(w)))
                .unwrap_or_else(|| tail.clone())
        },
        aim,
        max_steps,
        stop_at_collision,
    );
    Replay { run, params }
}

/// The trace of a run: a row at every period start, and one at the instant the robot came
/// to rest (or, after a collision, at the end of the colliding period). Times are written
/// without the noise of float arithmetic (k·dt is 2.3, not 2.3000000000000003).
pub fn trace<N: Scalar>(params: &Params<N>, run: &Run<N>) -> Vec<TraceRow> {
    let mut rows = Vec::new();
    let last = run.records.len().saturating_sub(1);
    for (i, rec) in run.records.iter().enumerate() {
        let t = N::int(rec.k as i64) * params.dt.clone();
        rows.push(TraceRow {
            t: t.shown_f64(),
            robot_position: rec.robot.position.as_f64(),
            robot_speed: rec.robot.speed.as_f64(),
            robot_mode: rec.robot.mode,
            obstacle_position: (rec.robot.position.clone() + rec.gap.clone()).as_f64(),
            obstacle_speed: rec.obstacle_speed.as_f64(),
            gap: rec.gap.as_f64(),
        });
        let end = &rec.motion.end;
        if let Some(g) = &rec.rest_gap {
            rows.push(TraceRow {
                t: (t.clone() + rec.motion.moving_for.clone()).shown_f64(),
                robot_position: end.position.as_f64(),
                robot_speed: 0.0,
                robot_mode: Mode::Stop,
                obstacle_position: (end.position.clone() + g.clone()).as_f64(),
                obstacle_speed: rec.obstacle_speed.as_f64(),
                gap: g.as_f64(),
            });
        } else if i == last && rec.collision && !rec.motion.came_to_rest() {
            rows.push(TraceRow {
                t: (t + params.dt.clone()).shown_f64(),
                robot_position: end.position.as_f64(),
                robot_speed: end.speed.as_f64(),
                robot_mode: end.mode,
                obstacle_position: (end.position.clone() + rec.end_gap.clone()).as_f64(),
                obstacle_speed: rec.obstacle_speed.as_f64(),
                gap: rec.end_gap.as_f64(),
            });
        }
    }
    rows
}

/// `runs` random runs of up to `horizon` periods each (see [`horizon`]), if within `budget`
/// (of [`Work::SimulatedPeriods`](crate::core::budget::Work::SimulatedPeriods)).
pub fn runs_within(
    budget: &crate::core::budget::Budget,
    runs: usize,
    horizon: usize,
) -> Result<(), crate::core::budget::OverBudget> {
    let needed = (runs as u64).checked_mul(horizon as u64);
    budget.allow(
        format!(
            "{} runs of up to {} control periods each",
            crate::core::budget::grouped(runs as u64),
            crate::core::budget::grouped(horizon as u64)
        ),
        needed,
    )
}

/// The number of periods after which a run certainly has ended: the robot reaches the
/// obstacle's (farthest) start within this many periods even if the obstacle stands still,
/// then stops within v_max/(b_min·dt) more (the plant's braking).
pub fn horizon(params: &Params<f64>) -> usize {
    let p = params;
    let reach = p.v_max / p.a + (p.g0_max + p.clearance) / p.v_max;
    let stop = p.v_max / p.b_min;
    ((reach + stop) / p.dt).ceil() as usize + p.L + 4
}
