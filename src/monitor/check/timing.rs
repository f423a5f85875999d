//! Checks of when the controller runs and how old what it sees is: `control_period` (between
//! instants, and between two observations of an obstacle that missed an instant) and
//! `latency` (the age of an observation, for samples that say when it was taken).

use super::{Carried, Check, PremiseCheck, rounding};
use crate::monitor::event::Violation;
use crate::monitor::{Monitor, RELATIVE_TOLERANCE, Sample};

/// `control_period`: the controller runs at least once every dt (a bound of 0 is unusable).
pub(super) const CONTROL_PERIOD: PremiseCheck = PremiseCheck {
    unit: "s",
    relation: ">",
    positive: true,
    not_checked: "fewer than two instants",
    not_monitored: super::always_monitored,
};

/// `latency`: observations are at most L control periods old.
pub(super) const LATENCY: PremiseCheck = PremiseCheck {
    unit: "periods",
    relation: ">",
    positive: false,
    not_checked: "no sample gave the opportunity",
    not_monitored: latency_not_monitored,
};

fn latency_not_monitored(carried: Carried) -> Option<&'static str> {
    (!carried.observation_time).then_some(
        "no sample carried obstacle_t (the time the observation was taken); \
         add that column to check latency",
    )
}

impl Monitor {
    /// `control_period` from time `from` to the sample's time.
    #[inline]
    pub(in crate::monitor) fn check_period(&mut self, from: f64, s: &Sample) {
        let dt = self.bounds.control_period;
        let step = s.t - from;
        self.count_with_slack(Check::ControlPeriod, dt - step, s.t);
        if step > dt + RELATIVE_TOLERANCE * dt + rounding(from, s.t) {
            self.raise(
                Violation::at(Check::ControlPeriod, s)
                    .observed(step)
                    .bound(dt),
            );
        }
    }

    /// `latency` of an observation taken at `obs_t`, in control periods.
    #[inline]
    pub(in crate::monitor) fn check_latency(&mut self, s: &Sample, obs_t: f64) {
        let dt = self.bounds.control_period;
        let age = (s.t - obs_t) / dt;
        let l = self.bounds.latency;
        self.count_with_slack(Check::Latency, l - age, s.t);
        if age > l + RELATIVE_TOLERANCE * l.max(1.0) + rounding(s.t, obs_t) / dt {
            self.raise(Violation::at(Check::Latency, s).observed(age).bound(l));
        }
    }
}
