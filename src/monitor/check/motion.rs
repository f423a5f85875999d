//! The robot's own motion (`robot_motion`): its displacement from one instant to the next must
//! be one that its speeds at the two instants, its mode and the certified dynamics allow. A
//! robot whose position advances while it reports speed 0, or that covers more or less ground
//! than its speeds can explain, is not the robot the certificate speaks of; and the collision
//! check must know that it moved ([`Motion`]).
//!
//! **The dynamics.** Over the step [t₀, t₁] the speed v(t) starts at the reported v₀, ends at
//! v₁, stays ≥ 0, rises at most at a (`robot_envelope`'s bound) and not above max(v_max, v₀,
//! v₁); in mode `brake` at t₀ it falls at least at b while the robot moves (the
//! `braking_deceleration` premise); in `stop` and `idle` the robot stands. Outside `brake`
//! nothing bounds how fast it may slow down. The displacement x₁ − x₀ = ∫ v must then lie
//! between
//!
//! - the **most**: the fastest admissible speed profile from v₀, dropping to v₁ at the end:
//!   ∫ min(v₀ + a·s, max(v_max, v₀, v₁)) ds, or while braking ∫ max(v₀ − b·s, 0) ds, or 0
//!   in `stop` and `idle`;
//! - the **least**: the slowest profile that can still reach v₁ at t₁: ∫ max(v₁ − a·(Δt − s),
//!   0) ds, and while braking with v₁ > 0 at least v₁·Δt + b·Δt²/2 (it was faster before).
//!
//! The model's robot (docs/semantics.md §2) moves exactly at the most when it accelerates,
//! drives or brakes, and both ends meet when its speed changes at exactly a or b; so the
//! comparison carries the tolerance of every derived check: [`RELATIVE_TOLERANCE`] of the
//! largest distance the step allows, plus the rounding of the positions and times. The
//! robot's own state is exact in the model (it knows its speed; observation noise is the
//! obstacle's), so no noise widens it.

use super::{Check, PremiseCheck, ROUNDING, rounding};
use crate::core::semantics::Mode;
use crate::monitor::event::{Detail, Violation};
use crate::monitor::{Monitor, RELATIVE_TOLERANCE, RobotAt, Sample};

/// `robot_motion`: the displacement against the most (or the least) the step allows (m).
pub(super) const ROBOT_MOTION: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: ">",
    positive: false,
    not_checked: "fewer than two instants",
    not_monitored: super::always_monitored,
};

/// What the robot's motion over the step that ended at the current instant means for the
/// collision check.
#[derive(Clone, Copy, Debug)]
pub(in crate::monitor) struct Motion {
    /// It may have moved within the step: it was moving at its start, or its position
    /// changed (beyond rounding). Whether it moves at the instant itself is its speed.
    pub(in crate::monitor) moved: bool,
    /// It was at rest at the step's start and moved: it may have set off at once.
    pub(in crate::monitor) from_rest: bool,
    /// The latest time within the step at which it may still have been moving (s): the
    /// step's end, or, for a robot that braked at b or harder as its positions confirm,
    /// t₀ + v₀/b when that is earlier.
    pub(in crate::monitor) until: f64,
}

impl Motion {
    /// Before the second instant: no step.
    pub(in crate::monitor) const NONE: Motion = Motion {
        moved: false,
        from_rest: false,
        until: f64::NAN,
    };
}

/// The distance covered in `span` from speed `v0`, speeding up at `a` (∞: at once) up to
/// `top`.
#[inline]
fn speeding(v0: f64, a: f64, top: f64, span: f64) -> f64 {
    if a <= 0.0 {
        return v0 * span;
    }
    // Cruising at the top, and speeding up all step long, need no division (the common
    // cases: this runs once per instant).
    if a == f64::INFINITY || v0 >= top {
        return top * span;
    }
    if top - v0 >= a * span {
        return v0 * span + a * span * span / 2.0;
    }
    let r = (top - v0) / a;
    v0 * r + a * r * r / 2.0 + top * (span - r)
}

/// The distance covered in `span` from speed `v0`, slowing at `b` until at rest.
#[inline]
fn braking(v0: f64, b: f64, span: f64) -> f64 {
    if b <= 0.0 {
        v0 * span
    } else if v0 <= b * span {
        v0 * v0 / (2.0 * b)
    } else {
        v0 * span - b * span * span / 2.0
    }
}

/// The distances a robot may cover over one step (see the module docs): the most and the
/// least its speeds at the two ends, its mode at the start and the dynamics allow.
#[derive(Clone, Copy, Debug)]
pub(in crate::monitor) struct StepRange {
    /// The most (m).
    pub(in crate::monitor) most: f64,
    /// The least (m).
    pub(in crate::monitor) least: f64,
    /// The top speed of the step, max(v_max, v₀, v₁) (m/s): what its tolerance scales with.
    pub(in crate::monitor) top: f64,
}

impl StepRange {
    /// Over `span` from speed `v0` in `mode` to speed `v1`, speeding up at most at `a` (∞: no
    /// bound), braking at least at `b` in `brake`, cruising at most at v_max.
    #[inline(always)]
    pub(in crate::monitor) fn of(
        mode: Option<Mode>,
        v0: f64,
        v1: f64,
        span: f64,
        a: f64,
        b: f64,
        v_max: f64,
    ) -> StepRange {
        let top = v_max.max(v0).max(v1);
        let most = match mode {
            Some(Mode::Stop | Mode::Idle) => 0.0,
            Some(Mode::Brake) => braking(v0, b, span),
            _ => speeding(v0, a, top, span),
        };
        let mut least = if a == f64::INFINITY {
            0.0
        } else if a <= 0.0 {
            v1 * span
        } else if v1 <= a * span {
            v1 * v1 / (2.0 * a)
        } else {
            v1 * span - a * span * span / 2.0
        };
        if mode == Some(Mode::Brake) && v1 > 0.0 {
            least = least.max(v1 * span + b * span * span / 2.0);
        }
        StepRange { most, least, top }
    }
}

impl Monitor {
    /// `robot_motion` over the step from the previous instant `r` to the sample's, and what
    /// the step means for `collision` ([`Motion`]). A step begun in `brake` is bounded by
    /// braking at b only if `braked` (`braking_deceleration` held), and by speeding up at
    /// most at a only if `accelerated` (`robot_envelope`'s acceleration held): a robot
    /// already flagged for either is held to the rest, not flagged twice for one fault.
    #[inline(always)]
    pub(in crate::monitor) fn check_motion(
        &mut self,
        r: &RobotAt,
        s: &Sample,
        braked: bool,
        accelerated: bool,
    ) {
        let mode = match r.mode {
            Some(Mode::Brake) if !braked => None,
            mode => mode,
        };
        let span = s.t - r.t;
        let displacement = s.robot_x - r.x;
        if span <= 0.0 {
            self.motion = Motion::NONE;
            return;
        }
        let a = if accelerated {
            self.rule.moving.a
        } else {
            f64::INFINITY
        };
        let b = self.bounds.braking_deceleration;
        let (v0, v1) = (r.v, s.robot_v);
        let step = StepRange::of(mode, v0, v1, span, a, b, self.rule.moving.v_max);
        let (most, least, top) = (step.most, step.least, step.top);
        let tolerance = (RELATIVE_TOLERANCE + ROUNDING) * top * span
            + rounding(r.x, s.robot_x)
            + top * rounding(r.t, s.t);
        self.count_with_slack(
            Check::RobotMotion,
            (most - displacement).min(displacement - least),
            s.t,
        );
        let consistent = displacement <= most + tolerance && displacement >= least - tolerance;
        if !consistent {
            self.report_motion(s, displacement, most, least, mode);
        }
        let moved = v0 > 0.0 || displacement.abs() > tolerance;
        let until = match mode {
            Some(Mode::Brake) if consistent && b > 0.0 => s.t.min(r.t + v0 / b),
            _ => s.t,
        };
        self.motion = Motion {
            moved,
            from_rest: moved && v0 <= 0.0,
            until,
        };
    }

    /// The `robot_motion` event (out of line: rare).
    #[cold]
    #[inline(never)]
    fn report_motion(
        &mut self,
        s: &Sample,
        displacement: f64,
        most: f64,
        least: f64,
        mode: Option<Mode>,
    ) {
        let (bound, detail) = if displacement > most {
            let standing = matches!(mode, Some(Mode::Stop | Mode::Idle));
            let detail = if standing {
                Detail::MovedWhileStanding
            } else {
                Detail::MovedTooFar
            };
            (most, detail)
        } else {
            (least, Detail::MovedTooLittle)
        };
        let v = Violation::at(Check::RobotMotion, s).detail(detail);
        self.raise(v.observed(displacement).bound(bound));
    }
}
