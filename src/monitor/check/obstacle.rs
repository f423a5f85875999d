//! Checks of what the environment does: how fast obstacles approach (`obstacle_speed`), where
//! they are first seen (`first_detection_gap`), and how exactly they are observed
//! (`observation_noise`, which a trace of observations cannot show).

use super::{Carried, Check, PremiseCheck, rounding};
use crate::monitor::event::Violation;
use crate::monitor::{Monitor, RELATIVE_TOLERANCE, Sample, Track};

/// `obstacle_speed`: the obstacle's speed towards the robot is at most W.
pub(super) const OBSTACLE_SPEED: PremiseCheck = PremiseCheck {
    unit: "m/s",
    relation: ">",
    positive: false,
    not_checked: "no sample had obstacle_v and no obstacle was seen twice",
    not_monitored: super::always_monitored,
};

/// `first_detection_gap`: a new obstacle is first seen at a gap of at least ρ.
pub(super) const FIRST_DETECTION_GAP: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: "<",
    positive: false,
    not_checked: "no obstacle was seen",
    not_monitored: super::always_monitored,
};

/// `observation_noise`: observations are off by at most σ. Never checked: it only widens the
/// estimated speed's tolerance.
pub(super) const OBSERVATION_NOISE: PremiseCheck = PremiseCheck {
    unit: "m",
    relation: ">",
    positive: false,
    not_checked: "no sample gave the opportunity",
    not_monitored: noise_not_monitored,
};

fn noise_not_monitored(_: Carried) -> Option<&'static str> {
    Some(
        "observation errors need the true positions, which a trace of \
         observations does not carry",
    )
}

impl Monitor {
    /// `first_detection_gap`, at an obstacle's first sighting.
    #[inline]
    pub(in crate::monitor) fn check_first_sighting(&mut self, s: &Sample) {
        self.count(Check::FirstDetectionGap);
        let rho = self.bounds.first_detection_gap;
        let gap = s.obstacle_x - s.robot_x;
        if gap < rho - RELATIVE_TOLERANCE * rho - rounding(s.obstacle_x, s.robot_x) {
            self.raise(
                Violation::at(Check::FirstDetectionGap, s)
                    .observed(gap)
                    .bound(rho),
            );
        }
    }

    /// `obstacle_speed`: the speed the sample states, compared exactly, or one estimated from
    /// the obstacle's previous observation. Returns whether that previous observation must
    /// stay the reference (this one was taken at the same time).
    #[inline]
    pub(in crate::monitor) fn check_obstacle_speed(&mut self, s: &Sample, track: &Track) -> bool {
        match s.obstacle_v {
            Some(v) => {
                self.count(Check::ObstacleSpeed);
                let w = self.bounds.obstacle_speed;
                if v > w {
                    self.raise(Violation::at(Check::ObstacleSpeed, s).observed(v).bound(w));
                }
                false
            }
            None if track.seen => self.check_estimated_speed(s, track),
            None => false,
        }
    }

    /// `obstacle_speed` estimated from the last observation, over observation times when
    /// both have them, else over sample times; widened by the rounding error and by 2σ.
    #[inline]
    fn check_estimated_speed(&mut self, s: &Sample, track: &Track) -> bool {
        let (t0, t1) = match s.obstacle_t {
            Some(o) if track.has_obs_t => (track.obs_t, o),
            _ => (track.t, s.t),
        };
        let span = t1 - t0;
        if span <= 0.0 {
            // The same observation again: estimate later from the older one.
            return true;
        }
        self.count(Check::ObstacleSpeed);
        let w = self.bounds.obstacle_speed;
        let speed = (track.x - s.obstacle_x) / span;
        let slack = RELATIVE_TOLERANCE * w
            + (2.0 * self.bounds.observation_noise
                + rounding(track.x, s.obstacle_x)
                + speed.abs() * rounding(t0, t1))
                / span;
        if speed > w + slack {
            self.raise(
                Violation::at(Check::ObstacleSpeed, s)
                    .observed(speed)
                    .bound(w),
            );
        }
        false
    }
}
