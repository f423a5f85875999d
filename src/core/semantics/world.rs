//! The robot and one obstacle under the model's semantics: the [`World`], its observation
//! history and its one step ([`World::step`]), with everything that happened in it
//! ([`StepRecord`]).

use std::collections::VecDeque;

use crate::core::model::Params;
use crate::core::num::Scalar;

use super::{
    BrakeReason, Mode, Motion, Observation, RobotState, danger_distance, guard, robot_motion,
};

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
    pub(super) params: Params<N>,
    pub(super) k: usize,
    pub(super) robot: RobotState<N>,
    pub(super) gap: N,
    /// Gaps at the starts of the last L+1 periods, newest last.
    pub(super) gaps: VecDeque<N>,
    /// Obstacle speeds over the last L+1 periods, newest last.
    pub(super) speeds: VecDeque<N>,
    /// Occlusion: the robot sees nothing at the starts of steps before this one.
    pub(super) hidden_until: usize,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::num::Exact;
    use crate::core::semantics::tests::params;

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
