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
    /// b: the deceleration the controller computes with (danger distances)
    pub b: N,
    /// b_min: the deceleration the plant brakes at (≤ b; the worst case of the plant's
    /// range [b_min, b], docs/semantics.md)
    pub b_min: N,
    /// v0: the robot's speed at t = 0
    pub v0: N,
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
    /// initial gap (the nearest, when the problem gives a range)
    pub g0: N,
    /// the farthest initial gap (= g0 unless the problem gives a range)
    pub g0_max: N,
    /// σ_g: how far an observed gap may be off the true one
    pub sigma_g: N,
    /// σ_w: how far an observed obstacle speed may be off the true one
    pub sigma_w: N,
    /// d_det: a hidden obstacle is first seen at a true gap ≥ d_det (None: never hidden)
    pub d_det: Option<N>,
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
    /// b_min·dt (the plant's braking)
    pub b_min_dt: N,
    /// b_min·dt²/2
    pub half_b_min_dt2: N,
}

impl<N: Scalar> StepConstants<N> {
    /// The constants of v_max, a, the plant's braking b_min and dt.
    pub fn of(v_max: &N, a: &N, b_min: &N, dt: &N) -> Self {
        let half = N::int(1) / N::int(2);
        let dt2 = dt.clone() * dt.clone();
        StepConstants {
            v_max_dt: v_max.clone() * dt.clone(),
            a_dt: a.clone() * dt.clone(),
            half_a_dt2: half.clone() * a.clone() * dt2.clone(),
            b_min_dt: b_min.clone() * dt.clone(),
            half_b_min_dt2: half.clone() * b_min.clone() * dt2,
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
        let (v_max, a, b, b_min, dt) = (
            N::decimal(r.max_speed),
            N::decimal(r.acceleration),
            N::decimal(r.braking),
            N::decimal(r.plant_braking()),
            N::decimal(r.control_period),
        );
        Params {
            k: StepConstants::of(&v_max, &a, &b_min, &dt),
            v_max,
            a,
            b,
            b_min,
            v0: N::decimal(r.start_speed()),
            dt,
            L: r.latency as usize,
            clearance: N::decimal(r.clearance),
            V_a: N::decimal(c.assumed_obstacle_speed),
            rho: N::decimal(c.reaction_radius),
            rule: c.danger_rule,
            buffer: N::decimal(c.buffer),
            wrong_assumption_brake: c.wrong_assumption_brake,
            W: N::decimal(e.obstacle_speed),
            g0: N::decimal(e.initial_gap.min()),
            g0_max: N::decimal(e.initial_gap.max()),
            sigma_g: N::decimal(self.gap_noise()),
            sigma_w: N::decimal(self.speed_noise()),
            d_det: self.first_detection_gap().map(N::decimal),
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
            b_min_dt: f(&self.b_min_dt),
            half_b_min_dt2: f(&self.half_b_min_dt2),
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
            b_min: f(&self.b_min),
            v0: f(&self.v0),
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
            g0_max: f(&self.g0_max),
            sigma_g: f(&self.sigma_g),
            sigma_w: f(&self.sigma_w),
            d_det: self.d_det.as_ref().map(&f),
            k: self.k.map(&f),
        }
    }

    /// Whether the wrong-assumption guard can ever fire: it is on and the environment can
    /// be *seen* faster than the controller assumes (W + σ_w > V_a).
    pub fn wrong_assumption_active(&self) -> bool {
        self.wrong_assumption_brake && self.W.clone() + self.sigma_w.clone() > self.V_a
    }

    /// Whether observations may be off the truth (σ_g > 0 or σ_w > 0).
    pub fn noisy(&self) -> bool {
        self.sigma_g > N::zero() || self.sigma_w > N::zero()
    }
}

impl<N: Scalar> Params<N> {
    /// Whether the initial gap is a range (the environment picks it; the analysis covers
    /// every point).
    pub fn gap_is_range(&self) -> bool {
        self.g0_max != self.g0
    }
}
