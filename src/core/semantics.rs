//! The model's semantics (DESIGN.md §1): the one step function every engine runs.
//!
//! A [`World`] holds the robot, the obstacle's gap and the observation history; its
//! [`World::step`] advances one control period given the obstacle's speed for that period.
//! The simulator, witness replay, the certificate checker and the explorer call it; the
//! analyser builds its robot trajectories from [`robot_motion`] and its guards from
//! [`danger_distance`], the same functions `step` uses.
//!
//! Facts the analyser relies on, each a property of this code and pinned by tests:
//! - the gap never increases (robot speed ≥ 0 forward, obstacle speed ≥ 0 towards it);
//! - while the robot accelerates or drives its speed never decreases, and `danger_distance`
//!   is nondecreasing in the speed, so guard thresholds only grow until the robot brakes;
//! - braking latches: once in Brake the robot slows at b until it rests (Stop), for good.

use std::collections::VecDeque;

use serde::{Deserialize, Serialize};

use crate::core::model::{DangerRule, Params};
use crate::core::num::Scalar;

/// The robot's automaton location (the seed's robot template).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Before t = 0.
    Idle,
    /// Speeding up at a until v_max.
    Accelerate,
    /// Cruising at v_max.
    Drive,
    /// Slowing at b (the plant: b_min) until at rest; latched.
    Brake,
    /// At rest after braking; final.
    Stop,
}

impl Mode {
    /// Name as written in traces.
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::Idle => "idle",
            Mode::Accelerate => "accelerate",
            Mode::Drive => "drive",
            Mode::Brake => "brake",
            Mode::Stop => "stop",
        }
    }

    /// Every mode, in the automaton's order.
    pub const ALL: [Mode; 5] = [
        Mode::Idle,
        Mode::Accelerate,
        Mode::Drive,
        Mode::Brake,
        Mode::Stop,
    ];

    /// The mode a trace names, in any ASCII case (`drive`, `Brake`, ...).
    pub fn from_name(text: &[u8]) -> Option<Mode> {
        Mode::ALL
            .into_iter()
            .find(|m| m.as_str().as_bytes().eq_ignore_ascii_case(text))
    }
}

/// The robot's state at an instant.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotState<N> {
    /// Position along the lane (m).
    pub position: N,
    /// Speed (m/s).
    pub speed: N,
    /// Automaton location.
    pub mode: Mode,
}

impl<N: Scalar> RobotState<N> {
    /// The robot at t = 0: at position 0 with speed v0, in Drive if v0 = v_max, else in
    /// Accelerate (a robot at rest leaves Idle at t = 0).
    pub fn initial(p: &Params<N>) -> Self {
        let mode = if p.v0 >= p.v_max {
            Mode::Drive
        } else {
            Mode::Accelerate
        };
        RobotState {
            position: N::zero(),
            speed: p.v0.clone(),
            mode,
        }
    }
}

/// The robot's motion over one control period in a given mode.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion<N> {
    /// State at the end of the period.
    pub end: RobotState<N>,
    /// How long into the period the robot was moving: the period itself, the instant it
    /// came to rest, or zero if it stood still throughout.
    pub moving_for: N,
}

impl<N: Scalar> Motion<N> {
    /// Whether the robot came to rest inside this period (it was moving and now is not).
    pub fn came_to_rest(&self) -> bool {
        self.moving_for > N::zero() && self.end.speed == N::zero()
    }
}

/// The robot's exact motion over one control period starting in `state`, with the speed
/// clamped at v_max and at 0 inside the period (a robot that stops mid-period has moved
/// v²/(2b), not v·dt). The mode in `state` is the one chosen at the period's start.
pub fn robot_motion<N: Scalar>(p: &Params<N>, state: &RobotState<N>) -> Motion<N> {
    let x = state.position.clone();
    let v = state.speed.clone();
    match state.mode {
        Mode::Accelerate | Mode::Drive if v >= p.v_max => Motion::to(
            x + p.k.v_max_dt.clone(),
            p.v_max.clone(),
            Mode::Drive,
            p.dt.clone(),
        ),
        Mode::Accelerate => accelerate(p, x, v),
        Mode::Drive => Motion::to(x + v.clone() * p.dt.clone(), v, Mode::Drive, p.dt.clone()),
        Mode::Brake => brake(p, x, v),
        Mode::Idle | Mode::Stop => Motion {
            end: state.clone(),
            moving_for: N::zero(),
        },
    }
}

impl<N: Scalar> Motion<N> {
    /// A motion ending at `position` with `speed` in `mode`, having moved for `moving_for`.
    #[inline]
    fn to(position: N, speed: N, mode: Mode, moving_for: N) -> Self {
        Motion {
            end: RobotState {
                position,
                speed,
                mode,
            },
            moving_for,
        }
    }
}

/// One period in Accelerate below v_max: reach v_max inside it and cruise, or gain a·dt.
#[inline]
fn accelerate<N: Scalar>(p: &Params<N>, x: N, v: N) -> Motion<N> {
    let (dt, k) = (&p.dt, &p.k);
    if p.v_max.clone() - v.clone() <= k.a_dt {
        // Reaches v_max inside the period (after `reach`), then cruises.
        let reach = (p.v_max.clone() - v.clone()) / p.a.clone();
        let position = x
            + v * reach.clone()
            + k.half.clone() * p.a.clone() * reach.clone() * reach.clone()
            + p.v_max.clone() * (dt.clone() - reach);
        Motion::to(position, p.v_max.clone(), Mode::Drive, dt.clone())
    } else {
        let position = x + v.clone() * dt.clone() + k.half_a_dt2.clone();
        Motion::to(position, v + k.a_dt.clone(), Mode::Accelerate, dt.clone())
    }
}

/// One period in Brake: at rest already, stop inside the period, or lose b_min·dt.
#[inline]
fn brake<N: Scalar>(p: &Params<N>, x: N, v: N) -> Motion<N> {
    let (dt, k) = (&p.dt, &p.k);
    if v <= N::zero() {
        return Motion::to(x, N::zero(), Mode::Stop, N::zero());
    }
    // The plant brakes at b_min, its guaranteed rate: the worst case of [b_min, b]
    // (docs/semantics.md, "Weaker brakes").
    if v <= k.b_min_dt {
        // Stops inside the period, after v/b_min, having moved v²/(2b_min).
        let stop = v.clone() / p.b_min.clone();
        let position = x + k.half.clone() * v * stop.clone();
        Motion::to(position, N::zero(), Mode::Stop, stop)
    } else {
        let position = x + v.clone() * dt.clone() - k.half_b_min_dt2.clone();
        Motion::to(position, v - k.b_min_dt.clone(), Mode::Brake, dt.clone())
    }
}

/// The collision-danger distance d_coll(v) of the controller's rule; `None` is infinite
/// (the `area` rule brakes on entering the reaction area).
pub fn danger_distance<N: Scalar>(p: &Params<N>, v: &N) -> Option<N> {
    let t_b = v.clone() / p.b.clone();
    match p.rule {
        DangerRule::Paper => Some(v.clone() * t_b.clone() + p.V_a.clone() * t_b + p.buffer.clone()),
        DangerRule::Kinematic => Some(
            v.clone() * v.clone() / (N::int(2) * p.b.clone())
                + p.V_a.clone() * t_b
                + p.buffer.clone(),
        ),
        DangerRule::Area => None,
    }
}

/// What the robot sees at the start of a step: the gap L periods ago and the obstacle's
/// speed over the period that ended then.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation<N> {
    /// Observed gap (m).
    pub gap: N,
    /// Observed obstacle speed (m/s).
    pub speed: N,
}

/// Why the controller commanded Brake.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum BrakeReason {
    /// Observed gap within the danger distance.
    CollisionDanger,
    /// Obstacle in the area seen faster than V_a.
    WrongAssumption,
    /// The robot's stopping point reached its goal (scenes only: `nearDestination`).
    Destination,
}

/// The controller's guard: whether, with its own speed `v` and observation `obs`, the robot
/// brakes (DESIGN.md §1, "Controller guards").
pub fn guard<N: Scalar>(p: &Params<N>, v: &N, obs: &Observation<N>) -> Option<BrakeReason> {
    let in_area = obs.gap > N::zero() && obs.gap <= p.rho;
    if !in_area {
        return None;
    }
    let danger = match danger_distance(p, v) {
        None => true,
        Some(d) => obs.gap <= d,
    };
    if danger {
        Some(BrakeReason::CollisionDanger)
    } else if p.wrong_assumption_brake && obs.speed > p.V_a {
        Some(BrakeReason::WrongAssumption)
    } else {
        None
    }
}

/// Everything that happened in one control period.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRecord<N> {
    /// Step index k; the period is [k·dt, (k+1)·dt].
    pub k: usize,
    /// The robot at the period's start, with the mode the controller chose for it.
    pub robot: RobotState<N>,
    /// Gap at the period's start.
    pub gap: N,
    /// The obstacle's speed over the period.
    pub obstacle_speed: N,
    /// What the robot saw at the period's start, if anything yet.
    pub observation: Option<Observation<N>>,
    /// Set when the controller commanded Brake at this period's start.
    pub brake: Option<BrakeReason>,
    /// The robot's motion over the period.
    pub motion: Motion<N>,
    /// Gap at the period's end.
    pub end_gap: N,
    /// Gap at the instant the robot came to rest, if it did in this period.
    pub rest_gap: Option<N>,
    /// The robot was moving with gap ≤ clearance at some instant of this period.
    pub collision: bool,
}

/// The robot and one obstacle under the model's semantics.
#[derive(Clone, Debug)]
pub struct World<N> {
    params: Params<N>,
    k: usize,
    robot: RobotState<N>,
    gap: N,
    /// Gaps at the starts of the last L+1 periods, newest last.
    gaps: VecDeque<N>,
    /// Obstacle speeds over the last L+1 periods, newest last.
    speeds: VecDeque<N>,
    /// Occlusion: the robot sees nothing at the starts of steps before this one.
    hidden_until: usize,
}

impl<N: Scalar> World<N> {
    /// The world at t = 0 with the obstacle at the problem's (nearest) initial gap.
    pub fn new(params: Params<N>) -> Self {
        let gap = params.g0.clone();
        Self::with_gap(params, gap)
    }

    /// The world at t = 0 with the obstacle at initial gap `gap` (a point of the problem's
    /// range): the robot at position 0 with speed v0 ([`RobotState::initial`]).
    pub fn with_gap(params: Params<N>, gap: N) -> Self {
        World {
            k: 0,
            robot: RobotState::initial(&params),
            gap,
            gaps: VecDeque::with_capacity(params.L + 2),
            speeds: VecDeque::with_capacity(params.L + 2),
            hidden_until: 0,
            params,
        }
    }

    /// The problem's parameters.
    pub fn params(&self) -> &Params<N> {
        &self.params
    }

    /// Index of the next period.
    pub fn k(&self) -> usize {
        self.k
    }

    /// The robot now.
    pub fn robot(&self) -> &RobotState<N> {
        &self.robot
    }

    /// The gap now.
    pub fn gap(&self) -> &N {
        &self.gap
    }

    /// Whether the robot has come to rest for good.
    pub fn stopped(&self) -> bool {
        self.robot.mode == Mode::Stop
    }

    /// Takes out the history the observations are read from — the gaps at the starts of
    /// the last L+1 periods and the obstacle's speeds over them, oldest first — leaving the
    /// world without it until [`World::restore_history`]. (The explorer keeps it shared
    /// between states rather than copied into each.)
    pub fn take_history(&mut self) -> (VecDeque<N>, VecDeque<N>) {
        (
            std::mem::take(&mut self.gaps),
            std::mem::take(&mut self.speeds),
        )
    }

    /// Puts back a history taken by [`World::take_history`].
    pub fn restore_history(&mut self, gaps: VecDeque<N>, speeds: VecDeque<N>) {
        self.gaps = gaps;
        self.speeds = speeds;
    }

    /// Occlusion (DESIGN.md §1.2): the robot sees nothing at the starts of steps before
    /// `k` (the environment keeps the obstacle hidden; the caller keeps the first sighting
    /// at a true gap ≥ d_det).
    pub fn hide_until(&mut self, k: usize) {
        self.hidden_until = k;
    }

    /// What the robot sees at the start of period k: the gap at (k−L)·dt and the obstacle's
    /// speed over period k−L−1 (0 before the first period); nothing before L·dt, nor while
    /// the obstacle is hidden ([`World::hide_until`]).
    pub fn observation(&self) -> Option<Observation<N>> {
        if self.k < self.hidden_until {
            return None;
        }
        self.observation_if_shown()
    }

    /// What the robot would see at the start of period k if the obstacle were shown now
    /// (hidden or not): what an environment deciding when to show it looks at.
    pub fn observation_if_shown(&self) -> Option<Observation<N>> {
        let l = self.params.L;
        if self.k < l {
            return None;
        }
        // gaps holds g_{k-L..=k} once k ≥ L (with g_k pushed in step); here g_k is self.gap.
        let gap = if l == 0 {
            self.gap.clone()
        } else {
            self.gaps[self.gaps.len() - l].clone()
        };
        let speed = if self.k < l + 1 {
            N::zero()
        } else {
            self.speeds[self.speeds.len() - l - 1].clone()
        };
        Some(Observation { gap, speed })
    }

    /// Advance one control period with the obstacle moving at `w` (the caller keeps
    /// 0 ≤ w ≤ W; the explorer and replay check that). With noisy sensing the environment
    /// keeps the robot from reacting for as long as the noise allows ([`World::step_with`]).
    pub fn step(&mut self, w: N) -> StepRecord<N> {
        self.step_with(w, false)
    }

    /// What the robot sees at the start of this period, with the observation error the
    /// environment picks within ±σ (DESIGN.md §1.2): the error that lets the guard fire if
    /// `react` and one is possible, else the one that keeps it quiet if one is possible.
    /// Without noise it is the observation itself.
    pub fn seen(&self, react: bool) -> Option<Observation<N>> {
        let truth = self.observation()?;
        let p = &self.params;
        if !p.noisy() {
            return Some(truth);
        }
        let (g, sg) = (truth.gap.clone(), p.sigma_g.clone());
        let (low, high) = (g.clone() - sg.clone(), g.clone() + sg);
        // A speed is measured (and can be off) only once a period has been observed.
        let speed = if self.k < p.L + 1 {
            truth.speed.clone()
        } else if react {
            truth.speed.clone() + p.sigma_w.clone()
        } else {
            truth.speed.clone() - p.sigma_w.clone()
        };
        let clamp = |x: N| N::min_of(N::max_of(x, low.clone()), high.clone());
        let gaps = if react {
            let theta = match danger_distance(p, &self.robot.speed) {
                Some(d) => N::min_of(d, p.rho.clone()),
                None => p.rho.clone(),
            };
            vec![
                low.clone(),
                clamp(theta),
                clamp(p.rho.clone()),
                high.clone(),
            ]
        } else {
            // Seen beyond the area, or seen as already passed (gap ≤ 0).
            vec![high.clone(), low.clone()]
        };
        let v = &self.robot.speed;
        let pick = gaps
            .iter()
            .find(|&gap| {
                let obs = Observation {
                    gap: gap.clone(),
                    speed: speed.clone(),
                };
                guard(p, v, &obs).is_some() == react
            })
            .unwrap_or(&gaps[0]);
        Some(Observation {
            gap: pick.clone(),
            speed,
        })
    }

    /// [`World::step`] with the environment's aim for this period's observation error:
    /// `react` lets the robot react if the noise allows, else it is kept from reacting if
    /// the noise allows ([`World::seen`]). Without noise `react` changes nothing.
    pub fn step_with(&mut self, w: N, react: bool) -> StepRecord<N> {
        let p = &self.params;
        let observation = self.seen(react);
        let mut brake = None;
        if matches!(self.robot.mode, Mode::Accelerate | Mode::Drive) {
            if let Some(obs) = &observation {
                brake = guard(p, &self.robot.speed, obs);
            }
            if brake.is_some() {
                self.robot.mode = Mode::Brake;
            }
        }
        if self.robot.mode == Mode::Brake && self.robot.speed <= N::zero() {
            self.robot.mode = Mode::Stop;
        }
        let start = self.robot.clone();
        let motion = robot_motion(p, &start);
        let gap = self.gap.clone();
        let travelled = motion.end.position.clone() - start.position.clone();
        let end_gap = gap.clone() - w.clone() * p.dt.clone() - travelled.clone();
        let mut rest_gap = None;
        let collision = if motion.came_to_rest() {
            let g = gap.clone() - w.clone() * motion.moving_for.clone() - travelled;
            let hit = g < p.clearance;
            rest_gap = Some(g);
            hit
        } else if motion.moving_for > N::zero() {
            // Still moving at the period's end; the gap is lowest there.
            end_gap <= p.clearance
        } else {
            false
        };
        let record = StepRecord {
            k: self.k,
            robot: start,
            gap: gap.clone(),
            obstacle_speed: w.clone(),
            observation,
            brake,
            motion: motion.clone(),
            end_gap: end_gap.clone(),
            rest_gap,
            collision,
        };
        // History: after this step, gaps holds g_{..=k+1}'s predecessors up to g_k.
        self.gaps.push_back(gap);
        self.speeds.push_back(w);
        while self.gaps.len() > p.L + 1 {
            self.gaps.pop_front();
        }
        while self.speeds.len() > p.L + 1 {
            self.speeds.pop_front();
        }
        self.robot = motion.end;
        self.gap = end_gap;
        self.k += 1;
        record
    }
}

/// What a [`World::leap`] must not jump past beyond what the semantics itself decides
/// (guards, collisions, coming to rest): the first observation within ρ and the first seen
/// passed, which a caller that still watches for them records ([`crate::core::simulate`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Watch {
    /// No observation within ρ may be skipped.
    pub radius: bool,
    /// No observation of a gap ≤ 0 may be skipped.
    pub passed: bool,
}

/// Periods a [`World::leap`] crossed at once, and what the caller needs of them: in each of
/// them the robot kept the mode it had, no guard fired, nothing collided or came to rest,
/// and no observation was within ρ (when watched) or at a gap ≤ 0 (when watched).
#[derive(Clone, Debug, PartialEq)]
pub struct Leap<N> {
    /// The first period crossed.
    pub k: usize,
    /// How many periods were crossed (at least 1).
    pub periods: usize,
    /// The robot's mode at every one of their starts.
    pub mode: Mode,
    /// What the robot would see at the first one's start without noise if it sees anything
    /// there; then it sees something at every one of their starts, else at none.
    pub first_seen: Option<Observation<N>>,
    /// The gap at the last one's end: the lowest gap of the stretch (the robot moved
    /// throughout).
    pub end_gap: N,
}

/// The robot's exact motion over `m` periods of one uniform mode from speed `v`: speed
/// change per period `s` and travel per period `v_i·dt + q`; positions then sum in closed
/// form, Σ_{i<m} (v + i·s)·dt + q = m·v·dt + s·dt·m(m−1)/2 + m·q.
/// Written as m·(v·dt + q) + (s·dt)·m(m−1)/2, with both factors computed once per leap: a
/// leap's bisection evaluates it at many m, and each exact product costs.
struct Uniform<N> {
    v: N,
    s: N,
    /// The first period's travel, v·dt + q.
    step: N,
    /// s·dt.
    sdt: N,
}

/// m(m−1)/2, the number of speed changes summed over the first m periods.
fn pairs<N: Scalar>(m: usize) -> N {
    N::int((m as i64) * (m as i64 - 1) / 2)
}

impl<N: Scalar> Uniform<N> {
    fn new(v: N, s: N, q: N, dt: &N) -> Uniform<N> {
        Uniform {
            step: v.clone() * dt.clone() + q,
            sdt: s.clone() * dt.clone(),
            v,
            s,
        }
    }
    /// Distance travelled over the first `m` periods.
    fn travelled(&self, m: usize) -> N {
        N::int(m as i64) * self.step.clone() + pairs::<N>(m) * self.sdt.clone()
    }
    /// Speed after `m` periods.
    fn speed(&self, m: usize) -> N {
        self.v.clone() + N::int(m as i64) * self.s.clone()
    }
}

/// The gap over a leap with the obstacle at speed w: it closes by w·dt + v·dt + q in the
/// first period and by s·dt more in each later one, so after j periods it is
/// gap − j·(w·dt + step) − (s·dt)·j(j−1)/2 (the same number as gap − j·w·dt − travelled(j)).
struct Closing<N> {
    gap: N,
    per_period: N,
    sdt: N,
}

impl<N: Scalar> Closing<N> {
    fn new(gap: &N, w: &N, dt: &N, uniform: &Uniform<N>) -> Closing<N> {
        Closing {
            gap: gap.clone(),
            per_period: w.clone() * dt.clone() + uniform.step.clone(),
            sdt: uniform.sdt.clone(),
        }
    }
    /// The gap after `j` periods.
    fn after(&self, j: usize) -> N {
        self.gap.clone()
            - N::int(j as i64) * self.per_period.clone()
            - pairs::<N>(j) * self.sdt.clone()
    }
}

impl<N: Scalar> World<N> {
    /// The multi-period step: crosses at once as many of the next `most` periods as can be
    /// crossed, with the obstacle at speed `w` throughout, when every one of them is a period
    /// in which "keep going as you are" is certain — the robot accelerating without reaching
    /// v_max, cruising, or braking without coming to rest; no guard able to fire whatever the
    /// observation error (every observed gap, less σ_g, beyond ρ and above 0); no gap ≤ the
    /// clearance; nothing `watch`ed skipped; not across the first period with an
    /// observation. The world ends exactly as `periods` calls of [`World::step_with`] leave it
    /// (with any error aims: none of them matters there), in exact numbers; None (and the
    /// world unchanged) when not even one period qualifies. Every condition is monotone in
    /// the number of periods (gaps never grow), so the longest stretch is found by bisection
    /// with exact comparisons. Only for exact number types: floats would round differently
    /// from period-by-period arithmetic.
    pub fn leap(&mut self, w: N, most: usize, watch: Watch) -> Option<Leap<N>> {
        let p = &self.params;
        let zero = N::zero();
        if most == 0 || w < zero || self.robot.speed < zero {
            return None;
        }
        let v = self.robot.speed.clone();
        let mode = self.robot.mode;
        let uniform = match mode {
            Mode::Accelerate if v < p.v_max => {
                Uniform::new(v, p.k.a_dt.clone(), p.k.half_a_dt2.clone(), &p.dt)
            }
            Mode::Drive if v <= p.v_max => Uniform::new(v, zero.clone(), zero.clone(), &p.dt),
            Mode::Brake if v > zero => {
                Uniform::new(v, -p.k.b_min_dt.clone(), -p.k.half_b_min_dt2.clone(), &p.dt)
            }
            _ => return None,
        };

        // Observations: from period max(L, hidden_until) on; a leap stays on one side.
        let sighting = p.L.max(self.hidden_until);
        let observed = self.k >= sighting;
        let most = if observed {
            most
        } else {
            most.min(sighting - self.k)
        };
        let limits = Limits {
            mode,
            v: uniform.v.clone(),
            s: uniform.s.clone(),
            closing: Closing::new(&self.gap, &w, &p.dt, &uniform),
            v_max: p.v_max.clone(),
            clearance: p.clearance.clone(),
            sigma_g: p.sigma_g.clone(),
            rho: p.rho.clone(),
            l: p.L,
            history: if observed {
                self.gaps.range(self.gaps.len() - p.L..).cloned().collect()
            } else {
                Vec::new()
            },
            observed,
            watch,
        };
        if !limits.hold(1) {
            return None;
        }
        let m = if limits.hold(most) {
            most
        } else {
            // The boundary in floats first (cheap), then settled exactly around it: every
            // condition is monotone in m, so exact probes at the guess and just past it
            // decide, and a guess off by rounding only narrows the exact bisection.
            let floats = limits.as_f64();
            let guess = last_holding(1, most - 1, |m| floats.hold(m));
            if !limits.hold(guess) {
                last_holding(1, guess - 1, |m| limits.hold(m))
            } else if limits.hold(guess + 1) {
                last_holding(guess + 1, most - 1, |m| limits.hold(m))
            } else {
                guess
            }
        };
        let closing = &limits.closing;
        let first_seen = if observed {
            self.observation_if_shown()
        } else {
            None
        };
        let p = &self.params;
        // History: the last L+1 period starts crossed (older ones stay).
        let keep = m.min(p.L + 1);
        let pushed: Vec<N> = (m - keep..m).map(|j| closing.after(j)).collect();
        let end_gap = closing.after(m);
        let position = self.robot.position.clone() + uniform.travelled(m);
        let speed = uniform.speed(m);
        let cap = p.L + 1;
        for g in pushed {
            self.gaps.push_back(g);
            self.speeds.push_back(w.clone());
        }
        while self.gaps.len() > cap {
            self.gaps.pop_front();
        }
        while self.speeds.len() > cap {
            self.speeds.pop_front();
        }
        let leap = Leap {
            k: self.k,
            periods: m,
            mode,
            first_seen,
            end_gap: end_gap.clone(),
        };
        self.robot = RobotState {
            position,
            speed,
            mode,
        };
        self.gap = end_gap;
        self.k += m;
        Some(leap)
    }
}

/// What decides how far a leap may go ([`World::leap`]), gathered once per leap: the
/// robot's uniform motion, the closing gap, the bounds it is compared with and the gaps the
/// first periods observe from the history. Generic so that the same conditions run on a
/// float copy, which guides the bisection, and exactly, which decides.
struct Limits<M> {
    mode: Mode,
    v: M,
    s: M,
    closing: Closing<M>,
    v_max: M,
    clearance: M,
    sigma_g: M,
    rho: M,
    l: usize,
    /// The last L gaps of the history, oldest first (what periods k … k+L−1 observe).
    history: Vec<M>,
    observed: bool,
    watch: Watch,
}

impl<M: Scalar> Limits<M> {
    /// Whether the next `m` periods can be crossed at once.
    fn hold(&self, m: usize) -> bool {
        let zero = M::zero();
        // The mode's branch of robot_motion in every period: Accelerate stays below
        // v_max − a·dt before its last period (v + m·a·dt < v_max), Brake above b_min·dt
        // (v − m·b_min·dt > 0); Drive at v ≤ v_max keeps v.
        let speed = || self.v.clone() + M::int(m as i64) * self.s.clone();
        let branch = match self.mode {
            Mode::Accelerate => speed() < self.v_max,
            Mode::Brake => speed() > zero,
            _ => true,
        };
        if !branch {
            return false;
        }
        // No collision: gaps fall, so the last end gap is the lowest moving one.
        if self.closing.after(m) <= self.clearance {
            return false;
        }
        if !self.observed {
            return true;
        }
        // Period k observes the gap at (k−L)·dt: from the history while k−L < the first
        // period, then in the stretch; the lowest is the last of each (gaps never grow).
        let mut lowest: Option<M> = None;
        for g in &self.history[..self.l.min(m)] {
            lowest = Some(match lowest {
                Some(x) => M::min_of(x, g.clone()),
                None => g.clone(),
            });
        }
        if m > self.l {
            let g = self.closing.after(m - 1 - self.l);
            lowest = Some(match lowest {
                Some(x) => M::min_of(x, g),
                None => g,
            });
        }
        let Some(lowest) = lowest else {
            return true;
        };
        // Whatever the error within ±σ_g, the observed gap is at least this.
        let seen_low = lowest - self.sigma_g.clone();
        let beyond_radius = seen_low > self.rho;
        let not_passed = seen_low > zero;
        match self.mode {
            // The guard fires only on a gap in (0, ρ].
            Mode::Accelerate | Mode::Drive => beyond_radius && not_passed,
            _ => (!self.watch.radius || beyond_radius) && (!self.watch.passed || not_passed),
        }
    }

    /// The same limits in floats: a guide only (rounding may put its boundary a period or
    /// so off the exact one).
    fn as_f64(&self) -> Limits<f64> {
        let f = |x: &M| x.as_f64();
        Limits {
            mode: self.mode,
            v: f(&self.v),
            s: f(&self.s),
            closing: Closing {
                gap: f(&self.closing.gap),
                per_period: f(&self.closing.per_period),
                sdt: f(&self.closing.sdt),
            },
            v_max: f(&self.v_max),
            clearance: f(&self.clearance),
            sigma_g: f(&self.sigma_g),
            rho: f(&self.rho),
            l: self.l,
            history: self.history.iter().map(f).collect(),
            observed: self.observed,
            watch: self.watch,
        }
    }
}

/// The largest m in [lo, hi] with `hold(m)`, for a condition that holds at `lo` and, past
/// some m, nowhere beyond.
fn last_holding(mut lo: usize, mut hi: usize, hold: impl Fn(usize) -> bool) -> usize {
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        if hold(mid) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::core::model::Problem;
    use crate::core::num::Exact;

    fn params() -> Params<Exact> {
        Problem::from_toml_str(
            "name = \"t\"\n[robot]\nmax_speed = 0.8\nacceleration = 0.3\nbraking = 0.5\ncontrol_period = 0.1\n\
             latency = 2\nclearance = 0.0\n[controller]\nassumed_obstacle_speed = 0.2\nreaction_radius = 1.4\n\
             danger_rule = \"kinematic\"\nbuffer = 0.1\nwrong_assumption_brake = true\n[environment]\n\
             obstacle_speed = 0.3\ninitial_gap = 3.0\n",
            "test",
        )
        .expect("valid")
        .params()
    }

    /// A robot that stops inside a period has moved v²/(2b) and rests at v/b, not v·dt.
    #[test]
    fn braking_stops_inside_the_period_exactly() {
        let p = params();
        let v = exact_of(0.03);
        let m = robot_motion(
            &p,
            &RobotState {
                position: Exact::ZERO,
                speed: v.clone(),
                mode: Mode::Brake,
            },
        );
        assert_eq!(m.end.speed, Exact::ZERO);
        assert_eq!(m.end.mode, Mode::Stop);
        assert_eq!(m.moving_for, v.clone() / p.b.clone());
        assert_eq!(
            m.end.position,
            v.clone() * v / (Exact::from(2) * p.b.clone())
        );
    }

    fn exact_of(x: f64) -> Exact {
        crate::core::num::exact_decimal(x)
    }

    /// A small deterministic generator (tests need no reproducibility beyond a fixed seed).
    pub(crate) struct Lcg(pub(crate) u64);

    impl Lcg {
        pub(crate) fn below(&mut self, n: u64) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 33) % n
        }
        pub(crate) fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
            xs[self.below(xs.len() as u64) as usize]
        }
    }

    /// Parameters across rules, latencies, speeds, radii, noise, occlusion, weaker brakes
    /// and start speeds.
    pub(crate) fn random_params(rng: &mut Lcg) -> Params<crate::core::rational::Rational> {
        let rule = rng.pick(&["paper", "kinematic", "area"]);
        let latency = rng.below(4);
        let dt = rng.pick(&[0.1, 0.05, 0.01, 0.25]);
        let w = rng.pick(&[0.15, 0.3, 0.25, 0.6]);
        let rho = rng.pick(&[1.4, 0.9, 1.6, 0.5]);
        let mut sensing = String::new();
        if rng.below(2) == 1 {
            sensing += &format!(
                "gap_noise = {}\nspeed_noise = {}\n",
                rng.pick(&[0.002, 0.05, 0.0]),
                rng.pick(&[0.01, 0.0, 0.1])
            );
        }
        if rng.below(3) == 0 {
            sensing += &format!("first_detection_gap = {}\n", rng.pick(&[0.4, 1.2, 2.0]));
        }
        let sensing = if sensing.is_empty() {
            sensing
        } else {
            format!("[sensing]\n{sensing}")
        };
        let v0 = rng.pick(&[0.0, 0.1, 0.8]);
        let b_min = rng.pick(&[0.5, 0.35]);
        let text = format!(
            "name = \"t\"\n[robot]\nmax_speed = 0.8\nacceleration = 0.3\nbraking = 0.5\n\
             braking_min = {b_min}\ninitial_speed = {v0}\ncontrol_period = {dt}\n\
             latency = {latency}\nclearance = {}\n[controller]\nassumed_obstacle_speed = 0.2\n\
             reaction_radius = {rho}\ndanger_rule = \"{rule}\"\nbuffer = 0.1\n\
             wrong_assumption_brake = {}\n[environment]\nobstacle_speed = {w}\n\
             initial_gap = {}\n{sensing}",
            rng.pick(&[0.0, 0.05]),
            rng.below(2) == 1,
            rng.pick(&[3.0, 2.5, 8.0, 30.0]),
        );
        Problem::from_toml_str(&text, "test")
            .expect("valid")
            .params()
    }

    /// The multi-period step is exactly `periods` ordinary steps: same world after, in
    /// exact numbers, and in every step crossed the mode kept, no guard, no collision, no
    /// rest, observations present all or none (the first as the leap says), nothing watched
    /// skipped, the lowest gap the leap's end gap — on random states of random parameter
    /// sets (noise, latency, occlusion, guards active) with random error aims.
    #[test]
    fn a_leap_is_exactly_its_periods_stepped_one_by_one() {
        use crate::core::rational::Rational;
        let mut rng = Lcg(12);
        let mut leapt = [0usize; 3];
        let mut long = [0usize; 3];
        for _ in 0..400 {
            let p = random_params(&mut rng);
            let eighth = p.W.clone() / Rational::int(8);
            let speed = |rng: &mut Lcg| eighth.clone() * Rational::int(rng.below(9) as i64);
            let gap = Rational::int(rng.below(80) as i64 + 5) / Rational::int(10);
            let mut world = World::with_gap(p.clone(), gap);
            world.hide_until(rng.pick(&[0, 0, 3, 12, 40]));
            let warmup = rng.below(60);
            for _ in 0..warmup {
                if world.stopped() {
                    break;
                }
                let (w, react) = (speed(&mut rng), rng.below(2) == 1);
                world.step_with(w, react);
            }
            for _ in 0..20 {
                if world.stopped() {
                    break;
                }
                let w = speed(&mut rng);
                let most = rng.pick(&[1, 2, 5, 40, 400, 3000]);
                let watch = Watch {
                    radius: rng.below(2) == 1,
                    passed: rng.below(2) == 1,
                };
                let mut stepped = world.clone();
                let Some(leap) = world.leap(w.clone(), most, watch) else {
                    let (w, react) = (speed(&mut rng), rng.below(2) == 1);
                    world.step_with(w, react);
                    continue;
                };
                assert!(leap.periods >= 1 && leap.periods <= most);
                assert_eq!(leap.k, stepped.k);
                let truth = stepped.observation();
                let mut lowest: Option<Rational> = None;
                for i in 0..leap.periods {
                    let rec = stepped.step_with(w.clone(), rng.below(2) == 1);
                    assert_eq!(rec.robot.mode, leap.mode, "mode in period {i}");
                    assert_eq!(rec.brake, None);
                    assert!(!rec.collision && rec.rest_gap.is_none());
                    assert!(rec.motion.moving_for > Rational::zero());
                    assert_eq!(rec.observation.is_some(), leap.first_seen.is_some());
                    if let Some(obs) = &rec.observation {
                        assert!(!watch.radius || obs.gap > p.rho);
                        assert!(!watch.passed || obs.gap > Rational::zero());
                    }
                    lowest = Some(match lowest {
                        Some(x) => Rational::min_of(x, rec.end_gap.clone()),
                        None => rec.end_gap.clone(),
                    });
                }
                if leap.first_seen.is_some() {
                    assert_eq!(leap.first_seen, truth);
                }
                assert_eq!(lowest, Some(leap.end_gap.clone()));
                assert_eq!(stepped.k, world.k);
                assert_eq!(stepped.robot, world.robot);
                assert_eq!(stepped.gap, world.gap);
                assert_eq!(stepped.gaps, world.gaps);
                assert_eq!(stepped.speeds, world.speeds);
                assert_eq!(stepped.hidden_until, world.hidden_until);
                let m = match leap.mode {
                    Mode::Accelerate => 0,
                    Mode::Drive => 1,
                    _ => 2,
                };
                leapt[m] += 1;
                if leap.periods >= 5 {
                    long[m] += 1;
                }
            }
        }
        // Every uniform mode was leapt, and over many periods at once.
        assert!(leapt.iter().all(|&n| n >= 20), "{leapt:?}");
        assert!(long.iter().all(|&n| n >= 5), "{long:?}");
    }

    /// The facts the analyser relies on, along arbitrary obstacle behaviours: the gap never
    /// grows, the speed stays in [0, v_max] and never falls before braking, braking latches.
    #[test]
    fn gap_never_grows_and_braking_latches() {
        let p = params();
        for pattern in 0..24u32 {
            let mut world = World::new(p.clone());
            let mut braked = false;
            let mut last_speed = Exact::ZERO;
            for k in 0..400 {
                let w = if (pattern >> (k % 5)) & 1 == 1 {
                    p.W.clone()
                } else {
                    Exact::ZERO
                };
                let before = world.gap().clone();
                let rec = world.step(w);
                assert!(rec.end_gap <= before, "gap grew at step {k}");
                let v = &rec.motion.end.speed;
                assert!(*v >= Exact::ZERO && *v <= p.v_max);
                if braked {
                    assert!(
                        matches!(rec.robot.mode, Mode::Brake | Mode::Stop),
                        "brake latched"
                    );
                } else if rec.robot.mode != Mode::Brake {
                    assert!(rec.robot.speed >= last_speed, "speed fell before braking");
                }
                braked |= rec.robot.mode == Mode::Brake;
                last_speed = rec.robot.speed.clone();
                if world.stopped() {
                    break;
                }
            }
        }
    }
}
