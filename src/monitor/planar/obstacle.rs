//! The planar monitor's checks of one obstacle's sample: the certificate names it
//! (`uncertified_obstacle`), it could have come from its start (`obstacle_start`) and was
//! not in view unseen before (`first_detection_gap`), it keeps to its region
//! (`obstacle_region`), its speed (`obstacle_speed`, `observation_inconsistent`), safety
//! (`collision`), and what the controller owes for it (danger, wrong assumption).
//!
//! Noise is taken in the robot's favour everywhere: a violation about where the obstacle is
//! is reported only when every centre within σ_p of the sample's commits it; a reaction is
//! owed only when every such centre shows danger and is surely in view.

use super::geometry::{Xy, box_distance, norm, polygon_distance, sub};
use super::rule::Zone;
use super::{PlanarMonitor, PlanarSample, Reaction, RobotAt, Track, rounding_xy, within};
use crate::core::semantics::{Mode, danger_distance};
use crate::monitor::check::{ROUNDING, rounding};
use crate::monitor::event::Violation;
use crate::monitor::{Check, RELATIVE_TOLERANCE};

/// What one sample shows of a certified obstacle, for the reaction it may call for.
#[derive(Clone, Copy)]
struct Seen {
    /// Its centre relative to the robot's (m), and the separation (m).
    rel: Xy,
    separation: f64,
    /// Its speed from its last two centres, the least the noise allows (m/s).
    estimated: Option<f64>,
    /// It no longer hides.
    revealed: bool,
    /// The rounding of the separation.
    extra: f64,
}

impl PlanarMonitor {
    /// Every check of the obstacle sample `s`, whose track was `track` before it.
    pub(super) fn check_obstacle(&mut self, s: &PlanarSample, track: Track) {
        let robot = self.robot.expect("an instant has begun");
        let id = s.obstacle_id;
        let at = (s.obstacle_x, s.obstacle_y);
        let rel = sub(at, robot.centre);
        let centre_distance = norm(rel);
        let certified = track.certified;
        let radius = certified.map_or(0.0, |i| self.rule.obstacles[i].radius);
        let separation = centre_distance - self.rule.robot_radius - radius;
        let w = certified.map_or_else(
            || self.rule.largest_speed(),
            |i| self.rule.obstacles[i].max_speed,
        );
        let sigma = self.rule.position_noise;
        let extra = rounding_xy(at, robot.centre) + ROUNDING * centre_distance;
        if !track.seen {
            self.distinct_obstacles += 1;
            self.count(Check::UncertifiedObstacle);
            match certified {
                None => {
                    let v = Violation::of_input(Check::UncertifiedObstacle, Some(s.t), Some(id));
                    self.raise(v.detail(crate::monitor::Detail::NotInCertificate));
                }
                Some(i) => {
                    self.check_start(s, i, at);
                    self.check_first_detection(s, i, separation, extra);
                }
            }
        } else if track.must_reappear && track.instant + 1 == self.instant {
            self.count(Check::ObservationDropout);
        }
        let region = certified.and_then(|i| self.rule.obstacles[i].region.as_deref());
        if let Some(outside) = region.map(|r| polygon_distance(r, at)) {
            self.count_with_slack(Check::ObstacleRegion, sigma - outside, s.t);
            if !within(outside, sigma, ROUNDING * norm(at)) {
                let v = Violation::of_input(Check::ObstacleRegion, Some(s.t), Some(id));
                self.raise(v.observed(outside).bound(sigma));
            }
        }
        let estimated = self.check_speed(s, &track, at, w);
        self.check_collision(s, &robot, separation, extra);
        // With d_det: once surely within it, it no longer hides.
        let revealed = track.revealed
            || self
                .rule
                .first_detection
                .is_some_and(|d| separation + sigma + extra <= d);
        if let Some(i) = certified {
            let seen = Seen {
                rel,
                separation,
                estimated,
                revealed,
                extra,
            };
            self.owe_reaction(s, &robot, i, &seen);
        }
        let must_reappear = self.stays_in_view(&robot, centre_distance, w, extra);
        let instant = self.instant;
        let track = self.track_mut(id).expect("admitted");
        *track = Track {
            seen: true,
            named: track.named,
            certified,
            instant,
            t: s.t,
            at,
            separation,
            revealed,
            must_reappear,
        };
    }

    /// `obstacle_start`: first seen within W_i·t + σ_p of its start.
    fn check_start(&mut self, s: &PlanarSample, i: usize, at: Xy) {
        let o = &self.rule.obstacles[i];
        let (min, max) = o.start;
        let away = box_distance(min, max, at);
        let reach = o.max_speed * s.t.max(0.0) + self.rule.position_noise;
        let extra = ROUNDING * (norm(at) + norm(min) + norm(max)) + o.max_speed * ROUNDING * s.t;
        self.count_with_slack(Check::ObstacleStart, reach - away, s.t);
        if !within(away, reach, extra) {
            let v = Violation::of_input(Check::ObstacleStart, Some(s.t), Some(s.obstacle_id));
            self.raise(v.observed(away).bound(reach));
        }
    }

    /// `first_detection_gap` (all-round sensing only): an obstacle first seen after the
    /// trace's first instant must not have been surely in range, and with d_det surely
    /// within it, at the previous instant: it could not come nearer than (W_i + the robot's
    /// top speed)·Δt in between.
    fn check_first_detection(&mut self, s: &PlanarSample, i: usize, separation: f64, extra: f64) {
        if !self.rule.all_round() || self.instant == 0 {
            return;
        }
        let Some(span) = self.previous_t.map(|t0| s.t - t0) else {
            return;
        };
        let o = &self.rule.obstacles[i];
        let m = &self.rule.motion;
        let sigma = self.rule.position_noise;
        let closing = (o.max_speed + m.v_max.max(s.robot_v)) * span;
        let sum = self.rule.robot_radius + o.radius;
        // The separation below which it was surely visible and not hiding one instant ago.
        let visible = [self.rule.range.map(|r| r - sum), self.rule.first_detection]
            .into_iter()
            .flatten()
            .fold(f64::INFINITY, f64::min);
        let bound = visible - sigma - closing;
        self.count(Check::FirstDetectionGap);
        if bound.is_finite() {
            self.count_with_slack(Check::FirstDetectionGap, separation - bound, s.t);
        }
        let slack = RELATIVE_TOLERANCE * (visible + closing) + extra;
        // No range and nothing hides: every obstacle is in view from the first instant.
        if bound == f64::INFINITY || separation < bound - slack {
            let mut v =
                Violation::of_input(Check::FirstDetectionGap, Some(s.t), Some(s.obstacle_id))
                    .observed(separation);
            if bound.is_finite() {
                v = v.bound(bound);
            }
            self.raise(v);
        }
    }

    /// `obstacle_speed` (stated and estimated) and `observation_inconsistent`; the speed
    /// estimated from the previous centre at the previous instant, if any (m/s, the least
    /// the noise allows).
    fn check_speed(&mut self, s: &PlanarSample, track: &Track, at: Xy, w: f64) -> Option<f64> {
        let sigma = self.rule.position_noise;
        let sigma_w = self.rule.velocity_noise;
        if let Some(v) = s.obstacle_velocity {
            let speed = norm(v);
            self.count_with_slack(Check::ObstacleSpeed, w + sigma_w - speed, s.t);
            if !within(speed, w + sigma_w, ROUNDING * speed) {
                let e = Violation::of_input(Check::ObstacleSpeed, Some(s.t), Some(s.obstacle_id));
                self.raise(e.observed(speed).bound(w));
            }
        }
        let span = s.t - track.t;
        if !track.seen || span <= 0.0 {
            return None;
        }
        let moved = sub(at, track.at);
        let speed = norm(moved) / span;
        let noise = 2.0 * sigma / span;
        let extra = (rounding_xy(at, track.at) + w * rounding(s.t, track.t)) / span;
        self.count_with_slack(Check::ObstacleSpeed, w + noise - speed, s.t);
        if !within(speed, w + noise, extra) {
            let e = Violation::of_input(Check::ObstacleSpeed, Some(s.t), Some(s.obstacle_id));
            self.raise(e.observed(speed).bound(w));
        }
        let successive = track.instant + 1 == self.instant;
        if let (Some(v), true) = (s.obstacle_velocity, successive) {
            let implied = (moved.0 / span, moved.1 / span);
            let differ = norm(sub(v, implied));
            let bound = sigma_w + noise;
            let extra = extra + ROUNDING * (norm(v) + norm(implied));
            self.count_with_slack(Check::ObservationInconsistent, bound - differ, s.t);
            if !within(differ, bound, extra) {
                let e = Violation::of_input(
                    Check::ObservationInconsistent,
                    Some(s.t),
                    Some(s.obstacle_id),
                );
                self.raise(e.observed(differ).bound(bound));
            }
        }
        successive.then_some(speed - noise - extra)
    }

    /// `collision`: the robot moving at a separation ≤ clearance for every centre within σ_p.
    fn check_collision(&mut self, s: &PlanarSample, robot: &RobotAt, separation: f64, extra: f64) {
        if robot.v <= 0.0 {
            return;
        }
        let clearance = self.rule.motion.clearance;
        self.count_with_slack(Check::Collision, separation - clearance, s.t);
        let slack = RELATIVE_TOLERANCE * clearance.abs() + extra + self.rule.position_noise;
        if separation <= clearance - slack {
            let v = Violation::of_input(Check::Collision, Some(s.t), Some(s.obstacle_id));
            self.raise(v.observed(separation).bound(clearance));
        }
    }

    /// Whether the obstacle, `centre_distance` from the robot, stays in view until the next
    /// instant whatever it and the robot do: all-round sensing, and within range with room
    /// for both to move a period at their top speeds.
    fn stays_in_view(&self, robot: &RobotAt, centre_distance: f64, w: f64, extra: f64) -> bool {
        if !self.rule.all_round() {
            return false;
        }
        let m = &self.rule.motion;
        match self.rule.range {
            None => true,
            Some(r) => {
                let moving = (w + m.v_max.max(robot.v)) * m.dt;
                centre_distance + self.rule.position_noise + moving + extra
                    <= r - RELATIVE_TOLERANCE * r
            }
        }
    }

    /// Whether every centre within σ_p of the one seen is in view of the robot (range, field
    /// of view) and no longer hides.
    fn surely_in_view(&self, robot: &RobotAt, rel: Xy, track_revealed: bool, extra: f64) -> bool {
        let sigma = self.rule.position_noise;
        let c = norm(rel);
        if self
            .rule
            .range
            .is_some_and(|r| c + sigma + extra > r - RELATIVE_TOLERANCE * r)
        {
            return false;
        }
        if self.rule.first_detection.is_some() && !track_revealed {
            return false;
        }
        match self.rule.view_cos_half.filter(|_| !self.rule.all_round()) {
            None => true,
            Some(cos_half) => {
                if c <= sigma + extra {
                    return false;
                }
                let (along, side) = Self::local(robot, rel);
                let angle = side.atan2(along).abs();
                let wobble = (sigma / c).min(1.0).asin();
                angle + wobble + 1e-9 <= cos_half.clamp(-1.0, 1.0).acos()
            }
        }
    }

    /// The reaction the sample's observation calls for, if it shows danger or a wrong
    /// assumption while the robot accelerates or drives: due when the controller has it, L
    /// periods on; judged now if that is now.
    fn owe_reaction(&mut self, s: &PlanarSample, robot: &RobotAt, i: usize, seen: &Seen) {
        if !matches!(robot.mode, Some(Mode::Accelerate | Mode::Drive)) {
            return;
        }
        let Seen {
            rel,
            separation,
            estimated,
            revealed,
            extra,
        } = *seen;
        if !self.surely_in_view(robot, rel, revealed, extra) {
            return;
        }
        let m = &self.rule.motion;
        let o = &self.rule.obstacles[i];
        let sigma = self.rule.position_noise;
        // What the observation shows and the bound it is danger within: the separation and
        // min(ρ, d(v)) for the disc; the distance from the stop polygon and r_i for it.
        let danger = match &self.rule.zone {
            Zone::Disc => {
                let theta = danger_distance(m, &robot.v).map_or(m.rho, |d| d.min(m.rho));
                let ok = separation + sigma + extra <= theta - RELATIVE_TOLERANCE * theta.abs();
                ok.then_some((separation, theta))
            }
            Zone::Polygon(polygon) => {
                let gap = polygon_distance(polygon, Self::local(robot, rel));
                let ok = gap + sigma + extra <= o.radius - RELATIVE_TOLERANCE * o.radius;
                ok.then_some((gap, o.radius))
            }
        };
        let wrong = danger.is_none()
            && m.wrong_assumption_brake
            && separation + sigma + extra <= m.rho - RELATIVE_TOLERANCE * m.rho
            && {
                let limit = m.V_a + RELATIVE_TOLERANCE * m.V_a.max(1.0);
                let stated = s.obstacle_velocity.is_some_and(|v| {
                    norm(v) - self.rule.velocity_noise > limit + ROUNDING * norm(v)
                });
                stated || estimated.is_some_and(|e| e > limit)
            };
        let Some((observed, bound)) = danger.or(wrong.then_some((separation, m.rho))) else {
            return;
        };
        let reaction = Reaction {
            due: s.t + m.L as f64 * m.dt,
            obstacle: s.obstacle_id,
            separation: observed,
            bound,
            wrong,
        };
        if self.reaction.is_none_or(|r| reaction.due < r.due) {
            self.reaction = Some(reaction);
        }
        self.judge_reaction(robot);
    }
}
