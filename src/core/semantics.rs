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

#[cfg(test)]
mod tests {
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
