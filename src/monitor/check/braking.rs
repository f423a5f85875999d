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
        let step = s.t - r.t;
        let b = self.bounds.braking_deceleration;
        let decel = (r.v - s.robot_v) / step;
        self.count_with_slack(Check::BrakingDeceleration, decel - b, s.t);
        let slack =
            RELATIVE_TOLERANCE * b + (rounding(r.v, s.robot_v) + b * rounding(r.t, s.t)) / step;
        if decel < b - slack {
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
