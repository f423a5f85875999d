//! Checks of what the environment does: how fast obstacles approach (`obstacle_speed`, against
//! the obstacle's own W_i under a scene certificate), where they are first seen
//! (`first_detection_gap`), how exactly they are observed (`observation_noise`, which a trace
//! of observations cannot show), and that a scene's static obstacles stay put
//! (`static_obstacle`).

use super::{Carried, Check, PremiseCheck, rounding};
use crate::monitor::event::Violation;
use crate::monitor::scene::CertifiedObstacle;
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
    #[inline(always)]
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
    /// the obstacle's previous observation, against W — the certified obstacle's own W_i
    /// when the sample's obstacle was matched to one. Returns whether that previous
    /// observation must stay the reference (this one was taken at the same time).
    #[inline(always)]
    pub(in crate::monitor) fn check_obstacle_speed(
        &mut self,
        s: &Sample,
        track: &Track,
        certified: Option<CertifiedObstacle>,
    ) -> bool {
        let w = certified.map_or(self.bounds.obstacle_speed, |o| o.max_speed);
        match s.obstacle_v {
            Some(v) => {
                self.count(Check::ObstacleSpeed);
                if v > w {
                    self.raise(Violation::at(Check::ObstacleSpeed, s).observed(v).bound(w));
                }
                false
            }
            None if track.seen => match self.estimated_speed(s, track) {
                Some(estimate) => {
                    self.count(Check::ObstacleSpeed);
                    let slack = RELATIVE_TOLERANCE * w + estimate.slack;
                    if estimate.speed > w + slack {
                        let v = Violation::at(Check::ObstacleSpeed, s);
                        self.raise(v.observed(estimate.speed).bound(w));
                    }
                    false
                }
                None => true,
            },
            None => false,
        }
    }

    /// `static_obstacle`, for an obstacle the scene states static: it must not move, either
    /// way. The speed the sample states is compared exactly with 2σ/dt (the most that
    /// observation noise σ can make a period's displacement look like; 0 without noise); the
    /// speed its positions imply with 2σ/Δt plus their rounding error. One event at most.
    /// Returns whether the previous observation must stay the reference, as
    /// [`Monitor::check_obstacle_speed`]. Out of line, as `check_lanes`.
    #[inline(never)]
    pub(in crate::monitor) fn check_static(&mut self, s: &Sample, track: &Track) -> bool {
        let noise = 2.0 * self.bounds.observation_noise;
        let mut moved = None;
        if let Some(v) = s.obstacle_v {
            self.count(Check::StaticObstacle);
            let allowed = noise / self.bounds.control_period;
            if v.abs() > allowed {
                moved = Some((v.abs(), allowed));
            }
        }
        let mut keep_reference = false;
        if track.seen {
            match self.estimated_speed(s, track) {
                Some(estimate) => {
                    self.count(Check::StaticObstacle);
                    let allowed = noise / estimate.span;
                    if moved.is_none() && estimate.speed.abs() > allowed + estimate.rounding {
                        moved = Some((estimate.speed.abs(), allowed));
                    }
                }
                None => keep_reference = true,
            }
        }
        if let Some((observed, allowed)) = moved {
            let v = Violation::at(Check::StaticObstacle, s);
            self.raise(v.observed(observed).bound(allowed));
        }
        keep_reference
    }

    /// The obstacle's speed towards the robot estimated from its last observation, over
    /// observation times when both have them, else over sample times, with the slack its
    /// rounding error and observation noise (2σ/Δt) allow; `None` when the two were taken at
    /// the same time (estimate later, from the older one).
    #[inline(always)]
    fn estimated_speed(&self, s: &Sample, track: &Track) -> Option<Estimate> {
        let (t0, t1) = match s.obstacle_t {
            Some(o) if track.has_obs_t => (track.obs_t, o),
            _ => (track.t, s.t),
        };
        let span = t1 - t0;
        if span <= 0.0 {
            return None;
        }
        let speed = (track.x - s.obstacle_x) / span;
        let (positions, times) = (rounding(track.x, s.obstacle_x), rounding(t0, t1));
        let slack = (2.0 * self.bounds.observation_noise + positions + speed.abs() * times) / span;
        let rounded = positions + speed.abs() * times;
        Some(Estimate {
            speed,
            slack,
            rounding: rounded / span,
            span,
        })
    }
}

/// A speed estimated from two observations.
#[derive(Clone, Copy, Debug)]
struct Estimate {
    /// (x₀ − x₁)/Δt (m/s), towards the robot.
    speed: f64,
    /// What rounding and observation noise may add to it (m/s).
    slack: f64,
    /// What rounding alone may add to it (m/s).
    rounding: f64,
    /// Δt (s).
    span: f64,
}
