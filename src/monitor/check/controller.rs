//! Checks of what the controller and the robot did (ModelPlex's controller monitor,
//! DESIGN.md §3): `controller_reaction` — the robot brakes (or, in a scene, changes lanes)
//! by the instant its controller has an observation showing danger or a wrong assumption;
//! `robot_envelope` — speed ≤ v_max and acceleration ≤ a; and `observation_dropout` — an
//! obstacle inside the reaction area is observed at every instant.
//!
//! **When a reaction is due.** A sample's observation is what the controller has at the
//! sample's instant when the sample says when it was taken (`obstacle_t`); otherwise it is
//! the obstacle's position at `t` (as `simulate --trace` writes it), which the controller
//! has L periods later (the latency premise). The robot must be braking or at rest (or
//! changing lanes, or out of the obstacle's lane) at the first instant at or after that time.
//!
//! **Danger, with the noise in the robot's favour.** An observation at gap g shows danger
//! only if every gap within σ_g (and rounding) of it does: g − σ_g > 0 and g + σ_g ≤ min(ρ,
//! d(v)), with d the certificate's danger rule (`danger_distance`) at the robot's speed v
//! at that sample (d with V_a = 0 for a scene's static obstacle). While the robot
//! accelerates or drives, v does not fall and the gap does not grow, so danger at the sample
//! is danger when the controller sees it. A wrong assumption (when the controller has that
//! guard): in the area in the same sense, and the obstacle surely faster than V_a — its
//! stated speed less σ_w, else its estimated speed less its noise and rounding, above V_a.

use super::obstacle::Slowest;
use super::{Check, rounding};
use crate::core::semantics::{Mode, danger_distance};
use crate::monitor::event::{Detail, Violation};
use crate::monitor::{
    Monitor, ObstacleId, RELATIVE_TOLERANCE, ROBOT_ONLY, Reaction, RobotAt, Sample,
};

impl Monitor {
    /// `robot_envelope`: the robot's speed at the new instant is at most v_max (plus
    /// [`RELATIVE_TOLERANCE`]).
    #[inline(always)]
    pub(in crate::monitor) fn check_top_speed(&mut self, s: &Sample) {
        let v_max = self.rule.moving.v_max;
        self.count_with_slack(Check::RobotEnvelope, v_max - s.robot_v, s.t);
        if s.robot_v > v_max + RELATIVE_TOLERANCE * v_max {
            let v = Violation::at(Check::RobotEnvelope, s).detail(Detail::AboveTopSpeed);
            self.raise(v.observed(s.robot_v).bound(v_max));
        }
    }

    /// `robot_envelope`: the robot's acceleration from the previous instant `r` is at most a,
    /// plus [`RELATIVE_TOLERANCE`] and the rounding of the speeds and times it is computed
    /// from. Whether it was (`robot_motion` bounds the step by a only when it was).
    #[inline(always)]
    pub(in crate::monitor) fn check_acceleration(&mut self, r: &RobotAt, s: &Sample) -> bool {
        let step = s.t - r.t;
        if step <= 0.0 {
            return true;
        }
        let a = self.rule.moving.a;
        self.count(Check::RobotEnvelope);
        // A robot that did not speed up is within any a ≥ 0 (the tolerance is not negative);
        // skipping the divisions changes no verdict.
        if s.robot_v - r.v <= 0.0 && a >= 0.0 {
            return true;
        }
        let acceleration = (s.robot_v - r.v) / step;
        let tolerance =
            RELATIVE_TOLERANCE * a + (rounding(r.v, s.robot_v) + a * rounding(r.t, s.t)) / step;
        if acceleration > a + tolerance {
            let v = Violation::at(Check::RobotEnvelope, s).detail(Detail::AboveAcceleration);
            self.raise(v.observed(acceleration).bound(a));
            return false;
        }
        true
    }

    /// The distance within which an observed gap is danger at robot speed `v`: min(ρ, d(v))
    /// for moving obstacles and for a scene's static ones.
    #[inline(always)]
    pub(in crate::monitor) fn set_reaction_distance(&mut self, v: f64) {
        // A robot cruising or at rest keeps its speed: compute once per speed.
        if v == self.reaction_speed {
            return;
        }
        self.reaction_speed = v;
        let within = |p: &crate::core::model::Params<f64>| {
            danger_distance(p, &v).map_or(p.rho, |d| d.min(p.rho))
        };
        self.reaction_distance = [within(&self.rule.moving), within(&self.rule.fixed)];
    }

    /// Whether the sample's observation (gap `gap`, slowest true speed `slowest`, lane
    /// `lane`, a static obstacle when `fixed`) shows danger or a wrong assumption; if so, the
    /// reaction it calls for is judged now when it is due now, else kept until its instant.
    #[inline(always)]
    pub(in crate::monitor) fn check_danger(
        &mut self,
        s: &Sample,
        gap: f64,
        slowest: Slowest,
        lane: Option<i32>,
        fixed: bool,
    ) {
        let p = &self.rule.moving;
        let spread = self.bounds.observation_noise + rounding(s.obstacle_x, s.robot_x);
        let (low, high) = (gap - spread, gap + spread);
        if low <= 0.0 || high > p.rho {
            return;
        }
        let d = self.reaction_distance[usize::from(fixed)];
        let danger = high <= d - RELATIVE_TOLERANCE * d;
        let wrong = !danger
            && !fixed
            && p.wrong_assumption_brake
            && slowest
                .get()
                .is_some_and(|w| w > p.V_a + RELATIVE_TOLERANCE * p.V_a.max(1.0));
        if !(danger || wrong) {
            return;
        }
        self.owe_reaction(s, gap, if danger { d } else { p.rho }, lane, wrong);
    }

    /// Records the reaction an observation calls for (out of line: rare).
    #[cold]
    #[inline(never)]
    fn owe_reaction(&mut self, s: &Sample, gap: f64, bound: f64, lane: Option<i32>, wrong: bool) {
        let p = &self.rule.moving;
        let due = match s.obstacle_t {
            Some(_) => s.t,
            None => s.t + p.L as f64 * p.dt,
        };
        let reaction = Reaction {
            due,
            obstacle: s.obstacle_id,
            gap,
            bound,
            lane,
            wrong,
        };
        if due <= s.t + self.time_tolerance(s.t) {
            self.judge_reaction(&reaction, s);
        } else if self.reaction.is_none_or(|r| due < r.due) {
            self.reaction = Some(reaction);
        }
    }

    /// How far apart two times may be and still be the same instant: rounding of `t` and of
    /// the whole periods added to it.
    #[inline(always)]
    fn time_tolerance(&self, t: f64) -> f64 {
        let dt = self.rule.moving.dt;
        RELATIVE_TOLERANCE * dt + rounding(t, t + self.rule.moving.L as f64 * dt)
    }

    /// At a new instant (sample `s`): the reaction owed by now, if any, is judged.
    #[inline(always)]
    pub(in crate::monitor) fn check_reaction_due<const SCENE: bool>(&mut self, s: &Sample) {
        if let Some(r) = self.reaction
            && r.due <= s.t + self.time_tolerance(s.t)
        {
            self.reaction = None;
            self.judge_reaction(&r, s);
        }
    }

    /// `controller_reaction`: at the current instant the robot must be braking, stopped or
    /// at rest, changing lanes, or out of the obstacle's lane. Not judged when the instant
    /// states no mode.
    #[cold]
    #[inline(never)]
    fn judge_reaction(&mut self, r: &Reaction, s: &Sample) {
        let Some(robot) = self.robot else {
            return;
        };
        let Some(mode) = robot.mode else {
            return;
        };
        self.count(Check::ControllerReaction);
        let lanes = self.robot_lanes;
        let left = matches!((r.lane, lanes.robot), (Some(l), Some(at)) if l != at);
        let reacted = matches!(mode, Mode::Brake | Mode::Stop)
            || robot.v <= 0.0
            || lanes.leaving.is_some()
            || left;
        if reacted {
            return;
        }
        let detail = if r.wrong {
            Detail::WrongAssumption
        } else {
            Detail::Danger
        };
        let mut v = Violation::at(Check::ControllerReaction, s)
            .observed(r.gap)
            .bound(r.bound)
            .detail(detail);
        v.obstacle_id = (r.obstacle != ROBOT_ONLY).then_some(r.obstacle);
        self.raise(v);
    }

    /// `observation_dropout`, when a new instant (sample `s`) begins: obstacles observed
    /// inside the reaction area at the instant before the one that just ended, and missing
    /// from it, are reported (an instant is complete only when the next begins).
    #[inline(always)]
    pub(in crate::monitor) fn check_dropouts(&mut self, s: &Sample) {
        let evaluated = u64::from(self.area_previous);
        self.checks[Check::ObservationDropout.index()] += evaluated;
        if self.area_previous_seen < self.area_previous {
            self.report_dropouts(s);
        }
        self.area_previous = self.area_now;
        self.area_now = 0;
        self.area_previous_seen = 0;
    }

    /// The obstacles [`Monitor::check_dropouts`] found missing (a scan of the table: rare).
    #[cold]
    #[inline(never)]
    fn report_dropouts(&mut self, s: &Sample) {
        let rho = self.rule.moving.rho;
        let last = self.instant.wrapping_sub(1);
        for i in 0..self.obstacles.len() {
            let track = self.obstacles[i];
            if track.seen && track.in_area && track.instant == last {
                let mut v = Violation::at(Check::ObservationDropout, s)
                    .observed(track.gap)
                    .bound(rho)
                    .detail(Detail::Dropout);
                v.obstacle_id = Some(i as ObstacleId);
                self.raise(v);
            }
        }
    }
}
