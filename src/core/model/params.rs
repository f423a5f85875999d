//! A problem as numbers of a chosen [`Scalar`] type, with the products every control period
//! uses computed once.

use crate::core::model::{DangerRule, Problem};
use crate::core::num::Scalar;

/// A problem's numbers in a chosen number type.
#[allow(non_snake_case)]
#[derive(Clone, Debug, PartialEq)]
pub struct Params<N> {
    /// v_max
    pub v_max: N,
    /// a
    pub a: N,
    /// b
    pub b: N,
    /// dt
    pub dt: N,
    /// L (control periods)
    pub L: usize,
    /// clearance
    pub clearance: N,
    /// V_a
    pub V_a: N,
    /// ρ
    pub rho: N,
    /// danger rule
    pub rule: DangerRule,
    /// buffer
    pub buffer: N,
    /// whether the wrong-assumption guard is on
    pub wrong_assumption_brake: bool,
    /// W
    pub W: N,
    /// initial gap
    pub g0: N,
    /// Products every control period uses, computed once from the numbers above.
    pub k: StepConstants<N>,
}

/// Products of a problem's numbers that the step function uses every control period:
/// computing them once takes a third of the exact arithmetic out of each step.
#[derive(Clone, Debug, PartialEq)]
pub struct StepConstants<N> {
    /// 1/2
    pub half: N,
    /// v_max·dt
    pub v_max_dt: N,
    /// a·dt
    pub a_dt: N,
    /// a·dt²/2
    pub half_a_dt2: N,
    /// b·dt
    pub b_dt: N,
    /// b·dt²/2
    pub half_b_dt2: N,
}

impl<N: Scalar> StepConstants<N> {
    /// The constants of v_max, a, b and dt.
    pub fn of(v_max: &N, a: &N, b: &N, dt: &N) -> Self {
        let half = N::int(1) / N::int(2);
        let dt2 = dt.clone() * dt.clone();
        StepConstants {
            v_max_dt: v_max.clone() * dt.clone(),
            a_dt: a.clone() * dt.clone(),
            half_a_dt2: half.clone() * a.clone() * dt2.clone(),
            b_dt: b.clone() * dt.clone(),
            half_b_dt2: half.clone() * b.clone() * dt2,
            half,
        }
    }
}

impl Problem {
    /// The problem's numbers as `N` (exact decimals for rationals).
    pub fn params<N: Scalar>(&self) -> Params<N> {
        let r = &self.robot;
        let c = &self.controller;
        let e = &self.environment;
        let (v_max, a, b, dt) = (
            N::decimal(r.max_speed),
            N::decimal(r.acceleration),
            N::decimal(r.braking),
            N::decimal(r.control_period),
        );
        Params {
            k: StepConstants::of(&v_max, &a, &b, &dt),
            v_max,
            a,
            b,
            dt,
            L: r.latency as usize,
            clearance: N::decimal(r.clearance),
            V_a: N::decimal(c.assumed_obstacle_speed),
            rho: N::decimal(c.reaction_radius),
            rule: c.danger_rule,
            buffer: N::decimal(c.buffer),
            wrong_assumption_brake: c.wrong_assumption_brake,
            W: N::decimal(e.obstacle_speed),
            g0: N::decimal(e.initial_gap),
        }
    }
}

impl<N: Scalar> StepConstants<N> {
    pub(crate) fn map<M>(&self, f: &impl Fn(&N) -> M) -> StepConstants<M> {
        StepConstants {
            half: f(&self.half),
            v_max_dt: f(&self.v_max_dt),
            a_dt: f(&self.a_dt),
            half_a_dt2: f(&self.half_a_dt2),
            b_dt: f(&self.b_dt),
            half_b_dt2: f(&self.half_b_dt2),
        }
    }
}

impl<N: Scalar> Params<N> {
    /// The same problem in another number type, converting every number with `f`.
    pub fn map<M>(&self, f: impl Fn(&N) -> M) -> Params<M> {
        Params {
            v_max: f(&self.v_max),
            a: f(&self.a),
            b: f(&self.b),
            dt: f(&self.dt),
            L: self.L,
            clearance: f(&self.clearance),
            V_a: f(&self.V_a),
            rho: f(&self.rho),
            rule: self.rule,
            buffer: f(&self.buffer),
            wrong_assumption_brake: self.wrong_assumption_brake,
            W: f(&self.W),
            g0: f(&self.g0),
            k: self.k.map(&f),
        }
    }

    /// Whether the wrong-assumption guard can ever fire: it is on and the environment can
    /// move faster than the controller assumes (W > V_a).
    pub fn wrong_assumption_active(&self) -> bool {
        self.wrong_assumption_brake && self.W > self.V_a
    }
}
