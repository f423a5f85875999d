//! The planar monitor's checks of the robot, at each new instant: where it is on its path
//! (`robot_path`), the control period, braking at b_min, its envelope (v_max, a), its motion
//! along the path (`robot_motion`, the line's bounds on the arc length), the destination
//! guard, and the reaction its controller owed by now (`controller_reaction`).

use super::geometry::{dot, norm};
use super::{PlanarMonitor, PlanarRobotSample, RobotAt, within};
use crate::core::semantics::Mode;
use crate::monitor::check::{ROUNDING, StepRange, deceleration, rounding};
use crate::monitor::event::Violation;
use crate::monitor::{Check, Detail, RELATIVE_TOLERANCE};

impl PlanarMonitor {
    /// A new instant (its first sample `s`), after `previous` if there was one.
    pub(super) fn start_instant(&mut self, previous: Option<RobotAt>, s: &PlanarRobotSample) {
        let centre = (s.robot_x, s.robot_y);
        let near = previous.map_or(0.0, |r| r.arc);
        let on = self.rule.path.locate(centre, near);
        let now = RobotAt {
            t: s.t,
            centre,
            v: s.robot_v,
            mode: s.robot_mode,
            arc: on.arc,
            off: on.distance,
            heading: on.heading,
        };
        let drift = self.rule.drift;
        let extra = ROUNDING * (norm(centre) + on.arc.abs());
        self.count_with_slack(Check::RobotPath, drift - on.distance, s.t);
        if !within(on.distance, drift, extra) {
            let v = Violation::of_input(Check::RobotPath, Some(s.t), None);
            self.raise(v.observed(on.distance).bound(drift));
        }
        if let Some(r) = previous {
            self.check_dropouts(s.t);
            self.instant += 1;
            self.previous_t = Some(r.t);
            self.check_period(&r, s);
            let braked = self.check_braking(&r, s);
            let accelerated = self.check_acceleration(&r, s);
            self.check_motion(&r, &now, braked, accelerated);
        }
        self.robot = Some(now);
        self.check_top_speed(s);
        self.check_destination(&now);
        self.judge_reaction(&now);
    }

    /// `control_period`: successive instants at most dt apart.
    fn check_period(&mut self, r: &RobotAt, s: &PlanarRobotSample) {
        let dt = self.rule.motion.dt;
        let step = s.t - r.t;
        self.count_with_slack(Check::ControlPeriod, dt - step, s.t);
        if !within(step, dt, rounding(s.t, r.t)) {
            let v = Violation::of_input(Check::ControlPeriod, Some(s.t), None);
            self.raise(v.observed(step).bound(dt));
        }
    }

    /// `braking_deceleration`: a step begun braking while moving slows by at least b_min
    /// (or ends at rest). Whether it held or was not due.
    fn check_braking(&mut self, r: &RobotAt, s: &PlanarRobotSample) -> bool {
        if r.mode != Some(Mode::Brake) || r.v <= 0.0 {
            return true;
        }
        if s.robot_v <= 0.0 {
            self.count(Check::BrakingDeceleration);
            return true;
        }
        let b = self.rule.motion.b_min;
        let (decel, short) = deceleration(r.v, s.robot_v, s.t - r.t, b, rounding(r.t, s.t));
        self.count_with_slack(Check::BrakingDeceleration, decel - b, s.t);
        if short {
            let v = Violation::of_input(Check::BrakingDeceleration, Some(s.t), None);
            self.raise(v.observed(decel).bound(b));
            return false;
        }
        true
    }

    /// `robot_envelope`: speed at most v_max.
    fn check_top_speed(&mut self, s: &PlanarRobotSample) {
        let v_max = self.rule.motion.v_max;
        self.count_with_slack(Check::RobotEnvelope, v_max - s.robot_v, s.t);
        if !within(s.robot_v, v_max, 0.0) {
            let v = Violation::of_input(Check::RobotEnvelope, Some(s.t), None)
                .detail(Detail::AboveTopSpeed);
            self.raise(v.observed(s.robot_v).bound(v_max));
        }
    }

    /// `robot_envelope`: acceleration at most a. Whether it was.
    fn check_acceleration(&mut self, r: &RobotAt, s: &PlanarRobotSample) -> bool {
        let step = s.t - r.t;
        let a = self.rule.motion.a;
        self.count(Check::RobotEnvelope);
        if step <= 0.0 || s.robot_v <= r.v {
            return true;
        }
        let acceleration = (s.robot_v - r.v) / step;
        let tolerance =
            RELATIVE_TOLERANCE * a + (rounding(r.v, s.robot_v) + a * rounding(r.t, s.t)) / step;
        if acceleration > a + tolerance {
            let v = Violation::of_input(Check::RobotEnvelope, Some(s.t), None)
                .detail(Detail::AboveAcceleration);
            self.raise(v.observed(acceleration).bound(a));
            return false;
        }
        true
    }

    /// `robot_motion`: the arc length covered between the instants within what the speeds,
    /// the mode and the dynamics allow (the line's bounds, `StepRange`), widened by how far
    /// off the path the two centres are (their arcs are those of their nearest path points).
    fn check_motion(&mut self, r: &RobotAt, now: &RobotAt, braked: bool, accelerated: bool) {
        let span = now.t - r.t;
        if span <= 0.0 {
            return;
        }
        let mode = match r.mode {
            Some(Mode::Brake) if !braked => None,
            mode => mode,
        };
        let m = &self.rule.motion;
        let a = if accelerated { m.a } else { f64::INFINITY };
        let step = StepRange::of(mode, r.v, now.v, span, a, m.b_min, m.v_max);
        let covered = now.arc - r.arc;
        let tolerance = (RELATIVE_TOLERANCE + ROUNDING) * step.top * span
            + rounding(r.arc, now.arc)
            + ROUNDING * (norm(r.centre) + norm(now.centre))
            + step.top * rounding(r.t, now.t)
            + 2.0 * (r.off + now.off);
        self.count_with_slack(
            Check::RobotMotion,
            (step.most - covered).min(covered - step.least),
            now.t,
        );
        if covered > step.most + tolerance || covered < step.least - tolerance {
            let (bound, detail) = if covered > step.most {
                let standing = matches!(mode, Some(Mode::Stop | Mode::Idle));
                let detail = if standing {
                    Detail::MovedWhileStanding
                } else {
                    Detail::MovedTooFar
                };
                (step.most, detail)
            } else {
                (step.least, Detail::MovedTooLittle)
            };
            let v = Violation::of_input(Check::RobotMotion, Some(now.t), None).detail(detail);
            self.raise(v.observed(covered).bound(bound));
        }
    }

    /// `controller_reaction` for the destination guard: a robot that accelerates or drives
    /// although braking at b from here would not stop before its path's end.
    fn check_destination(&mut self, now: &RobotAt) {
        let length = self.rule.path.length;
        if !length.is_finite() || !matches!(now.mode, Some(Mode::Accelerate | Mode::Drive)) {
            return;
        }
        let b = self.rule.motion.b;
        let reach = now.arc + now.v * now.v / (2.0 * b);
        self.count(Check::ControllerReaction);
        let extra = ROUNDING * (reach + norm(now.centre)) + 2.0 * now.off;
        if reach >= length + RELATIVE_TOLERANCE * length + extra {
            let v = Violation::of_input(Check::ControllerReaction, Some(now.t), None)
                .detail(Detail::Destination);
            self.raise(v.observed(reach).bound(length));
        }
    }

    /// The reaction owed by this instant, if any, is judged: the robot must brake or be at
    /// rest.
    pub(super) fn judge_reaction(&mut self, now: &RobotAt) {
        let Some(owed) = self.reaction else {
            return;
        };
        let dt = self.rule.motion.dt;
        if owed.due > now.t + RELATIVE_TOLERANCE * dt + rounding(now.t, owed.due) {
            return;
        }
        self.reaction = None;
        let Some(mode) = now.mode else {
            return;
        };
        self.count(Check::ControllerReaction);
        if matches!(mode, Mode::Accelerate | Mode::Drive) && now.v > 0.0 {
            let detail = if owed.wrong {
                Detail::WrongAssumption
            } else {
                Detail::Danger
            };
            let v =
                Violation::of_input(Check::ControllerReaction, Some(now.t), Some(owed.obstacle))
                    .detail(detail);
            self.raise(v.observed(owed.separation).bound(owed.bound));
        }
    }

    /// The robot's heading-frame coordinates of `rel` (x along the heading, y to its left).
    pub(super) fn local(now: &RobotAt, rel: (f64, f64)) -> (f64, f64) {
        let h = now.heading;
        (dot(rel, h), h.0 * rel.1 - h.1 * rel.0)
    }

    /// `observation_dropout`, as the instant closes: an obstacle seen at the previous
    /// instant where it had to stay in view, missing from the closing one.
    fn check_dropouts(&mut self, t: f64) {
        let closing = self.instant;
        for i in 0..self.tracks.len() {
            let k = self.tracks[i];
            if !(k.seen && k.must_reappear && k.instant + 1 == closing) {
                continue;
            }
            self.tracks[i].must_reappear = false;
            self.count(Check::ObservationDropout);
            let v = Violation::of_input(Check::ObservationDropout, Some(t), Some(i as u32))
                .detail(Detail::DropoutInView);
            self.raise(v.observed(k.separation));
        }
    }
}
