//! Checks of what the environment does: how fast obstacles approach (`obstacle_speed`, against
//! the obstacle's own W_i under a scene certificate), whether stated speeds agree with
//! positions (`observation_inconsistent`), where they are first seen
//! (`first_detection_gap`), how exactly they are observed (`observation_noise`,
//! `speed_noise`, which a trace of observations cannot show: they widen the other bounds),
//! and that a scene's static obstacles stay put (`static_obstacle`).

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

/// `speed_noise`: observed speeds are off by at most σ_w. Never checked, as
/// `observation_noise`: it widens the bounds of stated speeds.
pub(super) const SPEED_NOISE: PremiseCheck = PremiseCheck {
    unit: "m/s",
    relation: ">",
    positive: false,
    not_checked: "no sample gave the opportunity",
    not_monitored: noise_not_monitored,
};

/// What the speed checks learnt of one sample's obstacle.
#[derive(Clone, Copy, Debug)]
pub(in crate::monitor) struct SpeedSeen {
    /// The obstacle's previous observation must stay the reference for estimates (this one
    /// was taken at the same time).
    pub(in crate::monitor) keep_reference: bool,
    /// The slowest it can truly be moving towards the robot, as far as the sample shows
    /// (the stated speed less σ_w, else the estimate less its slack; `None`: neither, or a
    /// static obstacle): what the wrong-assumption guard is checked against.
    pub(in crate::monitor) slowest: Option<f64>,
}

fn noise_not_monitored(_: Carried) -> Option<&'static str> {
    Some(
        "observation errors need the true positions, which a trace of \
         observations does not carry",
    )
}

impl Monitor {
    /// `first_detection_gap`, at an obstacle's first sighting: the observed gap may be σ_g
    /// below the bound (the true gap within σ_g of it may still be at the bound).
    #[inline(always)]
    pub(in crate::monitor) fn check_first_sighting(&mut self, s: &Sample) {
        let rho = self.bounds.first_detection_gap;
        let allowed = rho - self.bounds.observation_noise;
        let gap = s.obstacle_x - s.robot_x;
        self.count_with_slack(Check::FirstDetectionGap, gap - allowed, s.t);
        if gap < allowed - RELATIVE_TOLERANCE * rho - rounding(s.obstacle_x, s.robot_x) {
            self.raise(
                Violation::at(Check::FirstDetectionGap, s)
                    .observed(gap)
                    .bound(allowed),
            );
        }
    }

    /// `obstacle_speed`: the speed the sample states, against W + σ_w (exactly), and the
    /// speed estimated from the obstacle's previous observation, against W + 2σ_g/Δt (plus
    /// rounding) — the certified obstacle's own W_i when the sample's obstacle was matched
    /// to one. One event at most, with the bound it broke. Across a dropout the estimate
    /// spans the whole gap: an obstacle reappearing must have been able to get there
    /// (distance ≤ W·Δt + 2σ_g). Then `observation_inconsistent` when the sample states a
    /// speed and the estimate spans one step.
    #[inline(always)]
    pub(in crate::monitor) fn check_obstacle_speed(
        &mut self,
        s: &Sample,
        track: &Track,
        certified: Option<CertifiedObstacle>,
    ) -> SpeedSeen {
        let w = certified.map_or(self.bounds.obstacle_speed, |o| o.max_speed);
        let mut raised = false;
        let mut slowest = None;
        if let Some(v) = s.obstacle_v {
            let allowed = w + self.bounds.speed_noise;
            self.count_with_slack(Check::ObstacleSpeed, allowed - v, s.t);
            if v > allowed {
                let violation = Violation::at(Check::ObstacleSpeed, s);
                self.raise(violation.observed(v).bound(allowed));
                raised = true;
            }
            slowest = Some(v - self.bounds.speed_noise);
        }
        if !track.seen {
            return SpeedSeen {
                keep_reference: false,
                slowest,
            };
        }
        let Some(estimate) = self.estimated_speed(s, track) else {
            return SpeedSeen {
                keep_reference: true,
                slowest,
            };
        };
        let allowed = w + 2.0 * self.bounds.observation_noise / estimate.span;
        if s.obstacle_v.is_none() {
            self.count_with_slack(Check::ObstacleSpeed, allowed - estimate.speed, s.t);
        }
        if !raised && estimate.speed > w + RELATIVE_TOLERANCE * w + estimate.slack {
            let violation = Violation::at(Check::ObstacleSpeed, s);
            self.raise(violation.observed(estimate.speed).bound(allowed));
        }
        match s.obstacle_v {
            Some(v) if track.instant + 1 == self.instant => self.check_consistency(s, v, &estimate),
            Some(_) => {}
            None => slowest = Some(estimate.speed - estimate.slack),
        }
        SpeedSeen {
            keep_reference: false,
            slowest,
        }
    }

    /// `observation_inconsistent`: the stated speed `v` and the speed the positions imply
    /// over the same step differ by more than noise allows, σ_w + 2σ_g/Δt, plus the
    /// estimate's rounding and [`RELATIVE_TOLERANCE`] of the larger speed.
    #[inline(always)]
    fn check_consistency(&mut self, s: &Sample, v: f64, estimate: &Estimate) {
        let allowed = self.bounds.speed_noise + 2.0 * self.bounds.observation_noise / estimate.span;
        let differ = (v - estimate.speed).abs();
        self.count_with_slack(Check::ObservationInconsistent, allowed - differ, s.t);
        let tolerance = estimate.rounding + RELATIVE_TOLERANCE * v.abs().max(estimate.speed.abs());
        if differ > allowed + tolerance {
            let violation = Violation::at(Check::ObservationInconsistent, s);
            self.raise(violation.observed(differ).bound(allowed));
        }
    }

    /// `static_obstacle`, for an obstacle the scene states static: it must not move, either
    /// way. The speed the sample states is compared exactly with σ_w (the speed noise); the
    /// speed its positions imply with 2σ_g/Δt (the most that observation noise can make a
    /// displacement look like) plus their rounding error. One event at most. Returns what
    /// [`Monitor::check_obstacle_speed`] does (never a speed: the wrong-assumption guard
    /// ignores static obstacles). Out of line, as `check_lanes`.
    #[inline(never)]
    pub(in crate::monitor) fn check_static(&mut self, s: &Sample, track: &Track) -> SpeedSeen {
        let noise = 2.0 * self.bounds.observation_noise;
        let mut moved = None;
        if let Some(v) = s.obstacle_v {
            let allowed = self.bounds.speed_noise;
            self.count_with_slack(Check::StaticObstacle, allowed - v.abs(), s.t);
            if v.abs() > allowed {
                moved = Some((v.abs(), allowed));
            }
        }
        let mut keep_reference = false;
        if track.seen {
            match self.estimated_speed(s, track) {
                Some(estimate) => {
                    let allowed = noise / estimate.span;
                    let slack = allowed - estimate.speed.abs();
                    self.count_with_slack(Check::StaticObstacle, slack, s.t);
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
        SpeedSeen {
            keep_reference,
            slowest: None,
        }
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
