//! Running the semantics forward: witness replay (exact or in floats) and Monte Carlo.
//!
//! Both go through [`World::step`], the one step function. Replay in [`Exact`] numbers is
//! what makes a refutation a theorem: the witness's obstacle speeds are floats, read as the
//! exact rationals they are, and the collision is decided without rounding.

use serde::{Deserialize, Serialize};

use crate::core::model::Params;
use crate::core::num::{Exact, Scalar, exact_float};
use crate::core::rational::Rational;
use crate::core::semantics::{BrakeReason, Leap, Mode, Observation, StepRecord, Watch, World};

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
    let mut summary = RunSummary::default();
    while world.k() < max_steps && !world.stopped() {
        before(&mut world);
        let (w, react) = choose(world.k());
        let truth = summary.truth(&world);
        let rec = world.step_with(w, react);
        summary.record(world.params(), &rec, truth);
        let hit = rec.collision;
        records.push(rec);
        if hit && stop_at_collision {
            break;
        }
    }
    Run {
        records,
        outcome: summary.outcome,
    }
}

/// The obstacle's speed held over `length` control periods from period `start`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SpeedSegment {
    /// First period (from 0).
    pub start: usize,
    /// Number of periods (at least 1).
    pub length: usize,
    /// Speed towards the robot (m/s).
    pub speed: f64,
}

/// The robot's mode over `length` control periods from period `start` (the mode at each
/// period's start, as the replay's rows give it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ModeSegment {
    /// First period (from 0).
    pub start: usize,
    /// Number of periods (at least 1).
    pub length: usize,
    /// The mode.
    pub mode: Mode,
}

/// What a run showed of the obstacle at its periods' starts (steps are step indices).
#[derive(Clone, Debug, PartialEq)]
pub struct Sightings<N> {
    /// The first step at whose start the robot saw the obstacle at all.
    pub first_seen: Option<usize>,
    /// The true gap that first sighting shows (the gap at (first_seen − L)·dt).
    pub first_seen_gap: Option<N>,
    /// The first step at whose start the robot saw it within ρ (passed included).
    pub within_radius: Option<usize>,
    /// The first step at whose start the robot saw it passed (observed gap ≤ 0).
    pub passed: Option<usize>,
    /// At the brake step the robot saw the obstacle faster than V_a.
    pub seen_fast_at_brake: bool,
}

impl<N> Default for Sightings<N> {
    fn default() -> Self {
        Sightings {
            first_seen: None,
            first_seen_gap: None,
            within_radius: None,
            passed: None,
            seen_fast_at_brake: false,
        }
    }
}

/// A run as what its checks read of it, without a record per period: its outcome, length,
/// mode segments, sightings and the end of its trace. Built period by period from records
/// ([`RunSummary::record`]) or from whole leaps ([`RunSummary::leap`]), alike.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary<N> {
    /// How it ended.
    pub outcome: RunOutcome<N>,
    /// Periods run.
    pub periods: usize,
    /// The robot's mode at each period's start, as maximal segments.
    pub modes: Vec<ModeSegment>,
    /// What the robot saw.
    pub sightings: Sightings<N>,
    /// The last period run, and how far past its start the trace's last row is: the
    /// instant of rest, or the end of a colliding period (None: the start itself).
    last: Option<(usize, Option<N>)>,
}

impl<N> Default for RunSummary<N> {
    fn default() -> Self {
        RunSummary {
            outcome: RunOutcome {
                collided: false,
                rest_gap: None,
                brake: None,
                min_moving_gap: None,
            },
            periods: 0,
            modes: Vec::new(),
            sightings: Sightings::default(),
            last: None,
        }
    }
}

impl<N: Scalar> RunSummary<N> {
    /// What a leap must not skip: the sightings not yet made.
    pub fn watch(&self) -> Watch {
        Watch {
            radius: self.sightings.within_radius.is_none(),
            passed: self.sightings.passed.is_none(),
        }
    }

    /// The true observation at the world's next period while no sighting has been made (the
    /// one a first sighting there shows).
    fn truth(&self, world: &World<N>) -> Option<Observation<N>> {
        if self.sightings.first_seen.is_none() {
            world.observation()
        } else {
            None
        }
    }

    fn push_mode(&mut self, mode: Mode, length: usize) {
        match self.modes.last_mut() {
            Some(last) if last.mode == mode => last.length += length,
            _ => self.modes.push(ModeSegment {
                start: self.periods,
                length,
                mode,
            }),
        }
        self.periods += length;
    }

    fn lowest_moving(&mut self, low: N) {
        self.outcome.min_moving_gap = Some(match self.outcome.min_moving_gap.take() {
            Some(m) => N::min_of(m, low),
            None => low,
        });
    }

    /// Adds one period's record; `truth` is `RunSummary::truth` before it was stepped.
    pub fn record(&mut self, p: &Params<N>, rec: &StepRecord<N>, truth: Option<Observation<N>>) {
        let k = rec.k;
        self.push_mode(rec.robot.mode, 1);
        if let Some(reason) = rec.brake {
            self.outcome.brake = Some((k, reason));
        }
        if rec.motion.moving_for > N::zero() {
            self.lowest_moving(rec.rest_gap.clone().unwrap_or_else(|| rec.end_gap.clone()));
        }
        if rec.rest_gap.is_some() {
            self.outcome.rest_gap = rec.rest_gap.clone();
        }
        if rec.collision {
            self.outcome.collided = true;
        }
        if let Some(obs) = &rec.observation {
            let s = &mut self.sightings;
            if rec.brake.is_some() {
                s.seen_fast_at_brake = obs.speed > p.V_a;
            }
            if s.first_seen.is_none() {
                s.first_seen = Some(k);
                s.first_seen_gap = truth.map(|t| t.gap);
            }
            if obs.gap <= p.rho {
                s.within_radius.get_or_insert(k);
            }
            if obs.gap <= N::zero() {
                s.passed.get_or_insert(k);
            }
        }
        let past = if rec.rest_gap.is_some() {
            Some(rec.motion.moving_for.clone())
        } else if rec.collision && !rec.motion.came_to_rest() {
            Some(p.dt.clone())
        } else {
            None
        };
        self.last = Some((k, past));
    }

    /// Adds the periods of a leap ([`World::leap`], with [`RunSummary::watch`]): moving
    /// throughout, no brake, collision or rest, nothing watched seen.
    pub fn leap(&mut self, leap: Leap<N>) {
        self.push_mode(leap.mode, leap.periods);
        self.lowest_moving(leap.end_gap);
        if let Some(obs) = leap.first_seen
            && self.sightings.first_seen.is_none()
        {
            self.sightings.first_seen = Some(leap.k);
            self.sightings.first_seen_gap = Some(obs.gap);
        }
        self.last = Some((leap.k + leap.periods - 1, None));
    }

    /// The time of the trace's last row ([`trace`]); None for a run of no period.
    pub fn end_time(&self, p: &Params<N>) -> Option<N> {
        let (k, past) = self.last.as_ref()?;
        let t = N::int(*k as i64) * p.dt.clone();
        Some(match past {
            Some(d) => t + d.clone(),
            None => t,
        })
    }

    /// The number of rows of the run's trace ([`trace`]).
    pub fn trace_rows(&self) -> usize {
        self.periods + usize::from(self.last.as_ref().is_some_and(|(_, past)| past.is_some()))
    }
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
/// while the numbers fit), crossing quiescent stretches at once ([`World::leap`]): what it
/// keeps is the run's [`RunSummary`], and a record per period only when asked for
/// ([`replay_recorded`]), for a trace.
#[derive(Clone, Debug)]
pub struct Replay {
    /// The run, in fast exact numbers.
    pub run: RunSummary<Rational>,
    /// The parameters it ran with.
    pub params: Params<Rational>,
    /// A record per period, when recorded.
    records: Option<Vec<StepRecord<Rational>>>,
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
        self.run.periods
    }

    /// The time of the trace's last row (None: no period run).
    pub fn end_time(&self) -> Option<f64> {
        self.run.end_time(&self.params).map(|t| t.shown_f64())
    }

    /// The time period `k` starts, as a trace row shows it.
    pub fn period_start(&self, k: usize) -> f64 {
        (Rational::int(k as i64) * self.params.dt.clone()).shown_f64()
    }

    /// The records, one per period.
    ///
    /// # Panics
    /// If the replay was not recorded ([`replay_recorded`]).
    pub fn records(&self) -> &[StepRecord<Rational>] {
        self.records
            .as_deref()
            .expect("a replay recorded period by period (replay_recorded)")
    }

    /// The trace rows.
    ///
    /// # Panics
    /// If the replay was not recorded ([`replay_recorded`]).
    pub fn trace(&self) -> Vec<TraceRow> {
        trace_of(&self.params, self.records())
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
    let tail = Rational::from_exact(&params.W);
    replay_from(
        params,
        speeds,
        tail,
        aim,
        max_steps,
        stop_at_collision,
        false,
    )
}

/// [`replay_reacting_at`] with `tail` (not W) as the speed after the listed ones.
pub fn replay_with_tail(
    params: &Params<Exact>,
    speeds: &[f64],
    tail: f64,
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
) -> Replay {
    let tail = Rational::from_exact(&exact_float(tail));
    replay_from(
        params,
        speeds,
        tail,
        aim,
        max_steps,
        stop_at_collision,
        false,
    )
}

/// [`replay_reacting_at`] period by period, keeping a record of each (for a trace: grows
/// with the horizon).
pub fn replay_recorded(
    params: &Params<Exact>,
    speeds: &[f64],
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
) -> Replay {
    let tail = Rational::from_exact(&params.W);
    replay_from(
        params,
        speeds,
        tail,
        aim,
        max_steps,
        stop_at_collision,
        true,
    )
}

/// The replay: `speeds[k]` in period k and `tail` after them, with the environment's
/// [`Aim`], for at most `max_steps` periods until the robot rests (or, with
/// `stop_at_collision`, collides). Unrecorded, each constant-speed stretch is offered to
/// [`World::leap`] first, and stepped period by period where it declines.
fn replay_from(
    params: &Params<Exact>,
    speeds: &[f64],
    tail: Rational,
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
    record: bool,
) -> Replay {
    // Constant-speed runs: (end, speed), the tail endless.
    let mut runs: Vec<(usize, f64)> = Vec::new();
    for (k, &w) in speeds.iter().enumerate() {
        match runs.last_mut() {
            Some(last) if last.1.to_bits() == w.to_bits() => last.0 = k + 1,
            _ => runs.push((k + 1, w)),
        }
    }
    replay_runs(
        params,
        &runs,
        tail,
        aim,
        max_steps,
        stop_at_collision,
        record,
    )
}

/// [`replay_reacting_at`] of speeds given as contiguous segments from period 0, with `tail`
/// after them (None: W), leaping unless `record`ed ([`replay_recorded`]).
pub fn replay_segments(
    params: &Params<Exact>,
    segments: &[SpeedSegment],
    tail: Option<f64>,
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
    record: bool,
) -> Replay {
    let tail = match tail {
        Some(t) => Rational::from_exact(&exact_float(t)),
        None => Rational::from_exact(&params.W),
    };
    let runs: Vec<(usize, f64)> = segments
        .iter()
        .map(|s| (s.start + s.length, s.speed))
        .collect();
    replay_runs(
        params,
        &runs,
        tail,
        aim,
        max_steps,
        stop_at_collision,
        record,
    )
}

/// The replay of constant-speed `runs` ((end, speed), in order from period 0), then `tail`.
fn replay_runs(
    params: &Params<Exact>,
    runs: &[(usize, f64)],
    tail: Rational,
    aim: Aim,
    max_steps: usize,
    stop_at_collision: bool,
    record: bool,
) -> Replay {
    let params: Params<Rational> = params.map(Rational::from_exact);
    let mut run = 0;
    let mut speed: Option<Rational> = None;
    let mut world = World::new(params.clone());
    world.hide_until(aim.hidden_until);
    let mut summary = RunSummary::default();
    let mut records = record.then(Vec::new);
    while world.k() < max_steps && !world.stopped() {
        let k = world.k();
        while run < runs.len() && runs[run].0 <= k {
            run += 1;
            speed = None;
        }
        let (end, w) = match runs.get(run) {
            Some(&(end, w)) => (
                end,
                speed
                    .get_or_insert_with(|| Rational::from_exact(&exact_float(w)))
                    .clone(),
            ),
            None => (usize::MAX, tail.clone()),
        };
        if records.is_none()
            && let Some(leap) = world.leap(w.clone(), end.min(max_steps) - k, summary.watch())
        {
            summary.leap(leap);
            continue;
        }
        let react = aim.react_at.is_some_and(|t| k >= t);
        let truth = summary.truth(&world);
        let rec = world.step_with(w, react);
        summary.record(&params, &rec, truth);
        let hit = rec.collision;
        if let Some(r) = records.as_mut() {
            r.push(rec);
        }
        if hit && stop_at_collision {
            break;
        }
    }
    Replay {
        run: summary,
        params,
        records,
    }
}

/// The trace of a run: a row at every period start, and one at the instant the robot came
/// to rest (or, after a collision, at the end of the colliding period). Times are written
/// without the noise of float arithmetic (k·dt is 2.3, not 2.3000000000000003).
pub fn trace<N: Scalar>(params: &Params<N>, run: &Run<N>) -> Vec<TraceRow> {
    trace_of(params, &run.records)
}

/// The trace of a run's records ([`trace`]).
pub fn trace_of<N: Scalar>(params: &Params<N>, records: &[StepRecord<N>]) -> Vec<TraceRow> {
    let mut rows = Vec::new();
    let last = records.len().saturating_sub(1);
    for (i, rec) in records.iter().enumerate() {
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
