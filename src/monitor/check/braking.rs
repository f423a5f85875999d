//! The check of what the robot does: `braking_deceleration`, the robot slowing by at least b
//! over a step that it began braking while moving.

use super::{Carried, Check, PremiseCheck, rounding};
use crate::core::semantics::Mode;
use crate::monitor::event::Violation;
use crate::monitor::{Monitor, RELATIVE_TOLERANCE, RobotAt, Sample};

/// `braking_deceleration`: the robot decelerates while braking by at least b.
pub(super) const BRAKING_DECELERATION: PremiseCheck = PremiseCheck {
    unit: "m/s^2",
    relation: "<",
    positive: false,
    not_checked: "the robot never braked while moving",
    not_monitored: braking_not_monitored,
};

fn braking_not_monitored(carried: Carried) -> Option<&'static str> {
    (!carried.mode).then_some("no sample carried robot_mode, so braking cannot be recognised")
}

/// The deceleration from speed `v0` to `v1` over `step` (the rounding of which is
/// `step_rounding`), and whether it falls short of `b` beyond [`RELATIVE_TOLERANCE`] and
/// the rounding of the speeds and times it is computed from.
#[inline]
pub(in crate::monitor) fn deceleration(
    v0: f64,
    v1: f64,
    step: f64,
    b: f64,
    step_rounding: f64,
) -> (f64, bool) {
    let decel = (v0 - v1) / step;
    let slack = RELATIVE_TOLERANCE * b + (rounding(v0, v1) + b * step_rounding) / step;
    (decel, decel < b - slack)
}

impl Monitor {
    /// `braking_deceleration` over the step from the previous instant `r` to the sample's.
    /// Whether it held (or was not due): `robot_motion` bounds the step by braking at b only
    /// when it did.
    #[inline]
    pub(in crate::monitor) fn check_braking(&mut self, r: &RobotAt, s: &Sample) -> bool {
        if r.mode != Some(Mode::Brake) || r.v <= 0.0 {
            return true;
        }
        // A robot at rest at the next instant decelerated fast enough (it may have stopped
        // inside the step); one still moving must have slowed by at least b over the step.
        if s.robot_v <= 0.0 {
            self.count(Check::BrakingDeceleration);
            return true;
        }
        let b = self.bounds.braking_deceleration;
        let (decel, short) = deceleration(r.v, s.robot_v, s.t - r.t, b, rounding(r.t, s.t));
        self.count_with_slack(Check::BrakingDeceleration, decel - b, s.t);
        if short {
            self.raise(
                Violation::at(Check::BrakingDeceleration, s)
                    .observed(decel)
                    .bound(b),
            );
            return false;
        }
        true
    }
}
