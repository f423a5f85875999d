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
    /// The slowest it can truly be moving towards the robot, as far as the sample shows:
    /// what the wrong-assumption guard is checked against.
    pub(in crate::monitor) slowest: Slowest,
}

/// The slowest an obstacle can truly be moving towards the robot, as far as a sample shows:
/// the stated speed less σ_w, else the estimate less its slack. An estimate's slack costs a
/// division, and the guard needs it only for an obstacle in the reaction area, so it is
/// computed when asked for ([`Slowest::get`]).
#[derive(Clone, Copy, Debug)]
pub(in crate::monitor) enum Slowest {
    /// Neither a stated nor an estimated speed, or a static obstacle.
    Unknown,
    /// The stated speed less σ_w (m/s).
    Stated(f64),
    /// The speed estimated from positions, less its slack.
    Estimated(Estimate),
}

impl Slowest {
    /// The speed (m/s), if the sample shows one.
    #[inline]
    pub(in crate::monitor) fn get(self) -> Option<f64> {
        match self {
            Slowest::Unknown => None,
            Slowest::Stated(v) => Some(v),
            Slowest::Estimated(e) => Some(e.speed - e.slack()),
        }
    }
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
        let (w, stated_bound, estimated_bound) = match certified {
            None => (
                self.bounds.obstacle_speed,
                self.fast.stated_speed,
                self.fast.estimated_speed,
            ),
            Some(o) => (
                o.max_speed,
                o.max_speed + self.bounds.speed_noise,
                o.max_speed + RELATIVE_TOLERANCE * o.max_speed,
            ),
        };
        let mut raised = false;
        let mut slowest = Slowest::Unknown;
        if let Some(v) = s.obstacle_v {
            let allowed = stated_bound;
            self.count_with_slack(Check::ObstacleSpeed, allowed - v, s.t);
            if v > allowed {
                let violation = Violation::at(Check::ObstacleSpeed, s);
                self.raise(violation.observed(v).bound(allowed));
                raised = true;
            }
            slowest = Slowest::Stated(v - self.bounds.speed_noise);
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
        if s.obstacle_v.is_none() {
            let allowed = w + self.noise_over(estimate.span);
            self.count_with_slack(Check::ObstacleSpeed, allowed - estimate.speed, s.t);
        }
        // The slack is never negative: a speed within the bound alone is within it.
        if !raised
            && estimate.speed > estimated_bound
            && estimate.speed > estimated_bound + estimate.slack()
        {
            let allowed = w + self.noise_over(estimate.span);
            let violation = Violation::at(Check::ObstacleSpeed, s);
            self.raise(violation.observed(estimate.speed).bound(allowed));
        }
        match s.obstacle_v {
            Some(v) if track.instant + 1 == self.instant => self.check_consistency(s, v, &estimate),
            Some(_) => {}
            None => slowest = Slowest::Estimated(estimate),
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
        let allowed = self.bounds.speed_noise + self.noise_over(estimate.span);
        let differ = (v - estimate.speed).abs();
        self.count_with_slack(Check::ObservationInconsistent, allowed - differ, s.t);
        // The tolerance is the estimate's rounding plus a relative part. Computed for every
        // sample: far from the origin the rounding is comparable to the relative part, and a
        // test of the relative part first went either way at random (a mispredicted branch
        // costs more than the division).
        let relative = RELATIVE_TOLERANCE * v.abs().max(estimate.speed.abs());
        if differ > allowed + (estimate.rounding() + relative) {
            let violation = Violation::at(Check::ObservationInconsistent, s);
            self.raise(violation.observed(differ).bound(allowed));
        }
    }

    /// 2σ_g/Δt, the most observation noise can add to a speed estimated over `span` (s):
    /// exactly `2.0 * σ_g / span`, without the division when σ_g = 0 or `span` is the last
    /// one asked about (the obstacles of one instant share it).
    #[inline(always)]
    fn noise_over(&mut self, span: f64) -> f64 {
        let noise = self.fast.noise;
        if noise == 0.0 {
            // ±0 divided by a positive span is itself.
            return noise;
        }
        if span != self.fast.noise_span {
            self.fast.noise_span = span;
            self.fast.noise_per_span = noise / span;
        }
        self.fast.noise_per_span
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
                    if moved.is_none() && estimate.speed.abs() > allowed + estimate.rounding() {
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
            slowest: Slowest::Unknown,
        }
    }

    /// The obstacle's speed towards the robot estimated from its last observation, over
    /// observation times when both have them, else over sample times, with the slack its
    /// rounding error and observation noise (2σ/Δt) allow ([`Estimate::slack`]); `None`
    /// when the two were taken at the same time (estimate later, from the older one).
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
        Some(Estimate {
            speed,
            span,
            xs: (track.x, s.obstacle_x),
            ts: (t0, t1),
            noise: self.fast.noise,
        })
    }
}

/// A speed estimated from two observations. What rounding and noise may add to it costs a
/// division each, and is needed only near a bound, so it is computed when asked for.
#[derive(Clone, Copy, Debug)]
pub(in crate::monitor) struct Estimate {
    /// (x₀ − x₁)/Δt (m/s), towards the robot.
    speed: f64,
    /// Δt (s).
    span: f64,
    /// x₀ and x₁ (m): their rounding error is computed only when asked for.
    xs: (f64, f64),
    /// The times of the two observations (s), likewise.
    ts: (f64, f64),
    /// 2σ_g (m).
    noise: f64,
}

impl Estimate {
    /// What rounding and observation noise may add to the speed (m/s): never negative.
    #[inline]
    fn slack(&self) -> f64 {
        (self.noise + self.positions() + self.speed.abs() * self.times()) / self.span
    }

    /// The rounding error of x₀ − x₁ (m).
    #[inline]
    fn positions(&self) -> f64 {
        rounding(self.xs.0, self.xs.1)
    }

    /// The rounding error of Δt (s).
    #[inline]
    fn times(&self) -> f64 {
        rounding(self.ts.0, self.ts.1)
    }

    /// What rounding alone may add to the speed (m/s): never negative.
    #[inline]
    fn rounding(&self) -> f64 {
        (self.positions() + self.speed.abs() * self.times()) / self.span
    }
}
