//! The runtime monitor for planar certificates (docs/semantics.md §13.12): checks, sample by
//! sample, that a robot driving its path among obstacles in the plane still stands where
//! the certificate's proof applies, and says the moment it does not, with the action
//! `brake`.
//!
//! [`PlanarMonitor::new`] takes a planar certificate, runs
//! `check_planar` (the planar certificate's solver-free check) on it, refuses any verdict but
//! `certified`, and reads what was assumed from the certificate's own problem. Then
//! [`PlanarMonitor::observe`] takes one [`PlanarSample`] (the robot's centre, speed and mode
//! and one obstacle's centre, optionally its velocity) and returns the standing verdict and
//! the [`Event`]s it raised, as the line's monitor does; [`PlanarMonitor::summary`] is the
//! same [`Summary`](super::Summary), with a `plane` part. Trace obstacles are matched to the certificate's by
//! name ([`PlanarMonitor::identify`]); an object no obstacle of the certificate names is an
//! `uncertified_obstacle` (the proof says nothing about it) and is held to the largest speed
//! bound.
//!
//! # What is checked
//!
//! Every length is Euclidean; t = 0 is the instant the robot set off (the certificate's
//! t = 0). Samples with equal `t` form an instant, as on the line.
//!
//! | name | violated when |
//! | --- | --- |
//! | `obstacle_speed` | the stated velocity's norm above W_i + σ_w, or the speed from the obstacle's previous centre above W_i + 2σ_p/Δt (across a dropout, over the whole gap) |
//! | `braking_deceleration` | after an instant in `brake` with the robot moving, it still moves and slowed by less than b_min·Δt |
//! | `control_period` | two successive instants more than dt apart |
//! | `first_detection_gap` | (all-round sensing) an obstacle first seen after the trace's first instant at a separation where, at the previous instant, it was surely within range (and, with d_det, within d_det): it was visible and was not seen |
//! | `observation_inconsistent` | a stated velocity and the one from the last two centres (successive instants) differ by more than σ_w + 2σ_p/Δt |
//! | `observation_dropout` | (all-round sensing) an obstacle seen at an instant where it must stay in range until the next is missing from the next |
//! | `controller_reaction` | (with `robot_mode`) the robot accelerates or drives at the instant its controller has an observation (the sample's, L periods on) showing danger or a wrong assumption for every centre within σ_p, of an obstacle surely in view; or it drives on where braking at b no longer stops it before its path's end |
//! | `robot_envelope` | speed above v_max, or acceleration above a |
//! | `robot_motion` | the arc length along the path between instants beyond the most, or below the least, its speeds and mode allow |
//! | `collision` | the robot moving (`robot_v` > 0) at a separation ‖c_R − c_i‖ − r_R − r_i ≤ clearance, for every centre within σ_p |
//! | `robot_path` | the robot's centre farther than the drift D from the certified path |
//! | `obstacle_start` | an obstacle first seen farther from its start (point or box) than W_i·t + σ_p |
//! | `obstacle_region` | an obstacle seen farther outside its region than σ_p |
//! | `uncertified_obstacle` | an object whose id names no obstacle of the certificate |
//!
//! and the fail-safe checks of the line (`malformed_sample`, `non_finite`, `time_backwards`,
//! `duplicate_sample`). Each derived value is compared with its bound widened by
//! [`RELATIVE_TOLERANCE`] and the rounding of the numbers it comes from, as on the line, so
//! that a full-precision trace of a run of the model (`simulate --replay --trace`) raises
//! nothing. `latency` is not monitored (planar traces carry no observation times), nor is
//! a fixed direction of motion; `collision` is judged at instants (not within the step).

use crate::core::planar::PlanarProblem;
use crate::core::semantics::Mode;
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::planar::check::check_planar;

use super::check::rounding;
use super::event::Violation;
use super::{
    Check, Detail, Event, Field, MAX_EVENTS_PER_SAMPLE, Margin, MonitorError, ObstacleId, Outcome,
    RELATIVE_TOLERANCE, Verdict, require_certified,
};

mod decoded;
mod geometry;
mod obstacle;
mod robot;
mod rule;
mod summary;

use geometry::Xy;
use rule::PlanarRule;
pub use summary::{PlanarObstacleSummary, PlaneSummary};

/// One line of a planar trace: the robot and one obstacle at an instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarSample {
    /// Time (s) since the robot set off.
    pub t: f64,
    /// The robot's centre (m).
    pub robot_x: f64,
    /// The robot's centre (m).
    pub robot_y: f64,
    /// The robot's speed along its path (m/s).
    pub robot_v: f64,
    /// The robot's mode from this instant on, if the trace records it.
    pub robot_mode: Option<Mode>,
    /// Which obstacle (an index into the monitor's table).
    pub obstacle_id: ObstacleId,
    /// The obstacle's observed centre (m).
    pub obstacle_x: f64,
    /// The obstacle's observed centre (m).
    pub obstacle_y: f64,
    /// Its observed velocity over the period that ends at `t` (m/s); `None`: estimated from
    /// successive centres.
    pub obstacle_velocity: Option<(f64, f64)>,
}

/// A planar trace line with the robot only: an instant at which no obstacle was observed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarRobotSample {
    /// Time (s).
    pub t: f64,
    /// The robot's centre (m).
    pub robot_x: f64,
    /// The robot's centre (m).
    pub robot_y: f64,
    /// The robot's speed (m/s).
    pub robot_v: f64,
    /// The robot's mode from this instant on, if the trace records it.
    pub robot_mode: Option<Mode>,
}

impl PlanarRobotSample {
    /// The robot's part of `s`.
    pub fn of(s: &PlanarSample) -> PlanarRobotSample {
        PlanarRobotSample {
            t: s.t,
            robot_x: s.robot_x,
            robot_y: s.robot_y,
            robot_v: s.robot_v,
            robot_mode: s.robot_mode,
        }
    }
}

/// The robot at the current instant.
#[derive(Clone, Copy, Debug)]
struct RobotAt {
    t: f64,
    centre: Xy,
    v: f64,
    mode: Option<Mode>,
    /// Arc length of its nearest path point, and its distance from the path (m).
    arc: f64,
    off: f64,
    /// The path's heading there.
    heading: Xy,
}

/// What the monitor remembers of one obstacle.
#[derive(Clone, Copy, Debug, Default)]
struct Track {
    seen: bool,
    /// [`PlanarMonitor::identify`] looked its name up, and the certificate's obstacle it
    /// matched.
    named: bool,
    certified: Option<usize>,
    /// Instant number and time of its last sample, and its centre then.
    instant: u64,
    t: f64,
    at: Xy,
    /// Its separation at its last sample (m).
    separation: f64,
    /// With d_det: some sample showed it within d_det for every centre within σ_p (so it
    /// no longer hides).
    revealed: bool,
    /// At its last sample it was where it stays in view until the next instant.
    must_reappear: bool,
}

/// A reaction the controller owes (see `obstacle.rs`).
#[derive(Clone, Copy, Debug)]
struct Reaction {
    due: f64,
    obstacle: ObstacleId,
    separation: f64,
    bound: f64,
    wrong: bool,
}

/// The runtime monitor for one planar certificate (see the module docs).
#[derive(Clone, Debug)]
pub struct PlanarMonitor {
    rule: PlanarRule,
    max_obstacles: u32,
    tracks: Vec<Track>,
    robot: Option<RobotAt>,
    /// The current instant's number (0-based) and the previous instant's time.
    instant: u64,
    previous_t: Option<f64>,
    reaction: Option<Reaction>,
    samples: u64,
    accepted: u64,
    distinct_obstacles: u64,
    /// Some sample had `robot_mode`; some had a stated velocity.
    carried_mode: bool,
    carried_velocity: bool,
    checks: [u64; Check::COUNT],
    violations: [u64; Check::COUNT],
    margins: [Margin; Check::COUNT],
    /// Premise and planar-check violations by each certified obstacle's samples.
    obstacle_violations: Vec<u64>,
    first: Option<Event>,
    events: Vec<Event>,
}

impl PlanarMonitor {
    /// A monitor for `cert`: runs `check_planar`, requires `certified`, reads the problem.
    /// Obstacle ids must be below [`super::DEFAULT_MAX_OBSTACLES`].
    pub fn new(cert: &PlanarCertificate) -> Result<PlanarMonitor, MonitorError> {
        let report = check_planar(cert).map_err(MonitorError::Invalid)?;
        require_certified(report.verdict)?;
        let problem = PlanarProblem::from_toml_str_with_overrides(
            &cert.problem_toml,
            "the certificate's problem",
            &cert.overrides,
        )
        .map_err(|e| MonitorError::Invalid(verdict_invalid(e.to_string())))?;
        Ok(Self::for_problem(&problem))
    }

    /// A monitor of the premises of `problem` as if certified (for tests and for callers
    /// that hold the certificate's problem already; [`PlanarMonitor::new`] is the checked
    /// way).
    pub fn for_problem(problem: &PlanarProblem) -> PlanarMonitor {
        let rule = PlanarRule::of(&problem.params());
        PlanarMonitor {
            obstacle_violations: vec![0; rule.obstacles.len()],
            rule,
            max_obstacles: super::DEFAULT_MAX_OBSTACLES,
            tracks: Vec::new(),
            robot: None,
            instant: 0,
            previous_t: None,
            reaction: None,
            samples: 0,
            accepted: 0,
            distinct_obstacles: 0,
            carried_mode: false,
            carried_velocity: false,
            checks: [0; Check::COUNT],
            violations: [0; Check::COUNT],
            margins: [Margin::NONE; Check::COUNT],
            first: None,
            events: Vec::with_capacity(MAX_EVENTS_PER_SAMPLE),
        }
    }

    /// Matches trace obstacle `id` to the certificate's obstacle called `name` (if any);
    /// call it before the id's first sample. Whether one is called so.
    pub fn identify(&mut self, id: ObstacleId, name: &str) -> bool {
        let index = self.rule.obstacles.iter().position(|o| o.name == name);
        if let Some(track) = self.track_mut(id) {
            track.certified = index;
            track.named = true;
        }
        index.is_some()
    }

    /// [`PlanarMonitor::identify`] at the id's first sample only (the track remembers that it
    /// was identified).
    pub fn identify_once(&mut self, id: ObstacleId, name: &str) {
        if self.tracks.get(id as usize).is_none_or(|t| !t.named) {
            self.identify(id, name);
        }
    }

    /// The standing verdict.
    pub fn verdict(&self) -> Verdict {
        if self.first.is_some() {
            Verdict::Violated
        } else {
            Verdict::Held
        }
    }

    /// Whether some sample reached the checks.
    pub fn checked_anything(&self) -> bool {
        self.accepted > 0
    }

    /// Violations of `check` so far.
    pub fn violations(&self, check: Check) -> u64 {
        self.violations[check.index()]
    }

    /// Evaluations of `check` so far.
    pub fn checks(&self, check: Check) -> u64 {
        self.checks[check.index()]
    }

    fn track_mut(&mut self, id: ObstacleId) -> Option<&mut Track> {
        let i = id as usize;
        if id >= self.max_obstacles {
            return None;
        }
        if self.tracks.len() <= i {
            self.tracks.resize(i + 1, Track::default());
        }
        self.tracks.get_mut(i)
    }

    fn outcome(&self) -> Outcome<'_> {
        Outcome {
            verdict: self.verdict(),
            events: &self.events,
        }
    }

    fn count(&mut self, check: Check) {
        self.checks[check.index()] += 1;
    }

    fn count_with_slack(&mut self, check: Check, slack: f64, t: f64) {
        let i = check.index();
        self.checks[i] += 1;
        if slack < self.margins[i].slack {
            self.margins[i] = Margin {
                slack,
                t,
                sample: self.samples - 1,
            };
        }
    }

    fn raise(&mut self, violation: Violation) {
        let event = violation.event(self.samples - 1);
        self.violations[violation.check.index()] += 1;
        if !violation.check.is_fail_safe()
            && let Some(id) = violation.obstacle_id
            && let Some(i) = self.tracks.get(id as usize).and_then(|t| t.certified)
        {
            self.obstacle_violations[i] += 1;
        }
        if self.first.is_none() {
            self.first = Some(event);
        }
        if self.events.len() < MAX_EVENTS_PER_SAMPLE {
            self.events.push(event);
        }
    }

    /// A line that could not be read as a sample (the reader says why): reported as
    /// `malformed_sample` (or `non_finite`), changing no state.
    pub fn malformed(&mut self, t: Option<f64>, detail: Detail) -> Outcome<'_> {
        self.events.clear();
        self.samples += 1;
        let check = match detail {
            Detail::NonFinite(_) => Check::NonFinite,
            _ => Check::MalformedSample,
        };
        self.count(check);
        let t = t.filter(|t| t.is_finite());
        self.raise(Violation::of_input(check, t, None).detail(detail));
        self.outcome()
    }

    /// Checks one sample (see the module docs).
    pub fn observe(&mut self, s: &PlanarSample) -> Outcome<'_> {
        self.events.clear();
        self.samples += 1;
        let velocity = s.obstacle_velocity.unwrap_or((0.0, 0.0));
        let numbers = [
            (Field::T, s.t),
            (Field::RobotX, s.robot_x),
            (Field::RobotY, s.robot_y),
            (Field::RobotV, s.robot_v),
            (Field::ObstacleX, s.obstacle_x),
            (Field::ObstacleY, s.obstacle_y),
            (Field::ObstacleVx, velocity.0),
            (Field::ObstacleVy, velocity.1),
        ];
        if !self.admit(s.t, Some(s.obstacle_id), &numbers) {
            return self.outcome();
        }
        if s.obstacle_id >= self.max_obstacles {
            let limit = self.max_obstacles;
            self.count(Check::MalformedSample);
            let v = Violation::of_input(Check::MalformedSample, Some(s.t), None);
            self.raise(v.detail(Detail::ObstacleIdOutOfRange { limit }));
            return self.outcome();
        }
        let track = *self.track_mut(s.obstacle_id).expect("below the limit");
        if track.seen && track.instant == self.instant && self.robot.is_some_and(|r| r.t == s.t) {
            self.count(Check::DuplicateSample);
            let v = Violation::of_input(Check::DuplicateSample, Some(s.t), Some(s.obstacle_id));
            self.raise(v.observed(s.t));
            return self.outcome();
        }
        if !self.enter_instant(&PlanarRobotSample::of(s), Some(s.obstacle_id)) {
            return self.outcome();
        }
        self.carried_velocity |= s.obstacle_velocity.is_some();
        self.check_obstacle(s, track);
        self.outcome()
    }

    /// Checks a robot-only sample: an instant at which no obstacle was observed.
    pub fn observe_robot(&mut self, r: &PlanarRobotSample) -> Outcome<'_> {
        self.events.clear();
        self.samples += 1;
        let numbers = [
            (Field::T, r.t),
            (Field::RobotX, r.robot_x),
            (Field::RobotY, r.robot_y),
            (Field::RobotV, r.robot_v),
        ];
        if self.admit(r.t, None, &numbers) {
            self.enter_instant(r, None);
        }
        self.outcome()
    }

    /// The fail-safe checks on numbers and time: whether the sample may touch any state.
    fn admit(&mut self, t: f64, id: Option<ObstacleId>, numbers: &[(Field, f64)]) -> bool {
        if let Some(&(field, _)) = numbers.iter().find(|(_, x)| !x.is_finite()) {
            self.count(Check::NonFinite);
            let t = t.is_finite().then_some(t);
            let v = Violation::of_input(Check::NonFinite, t, id);
            self.raise(v.detail(Detail::NonFinite(field)));
            return false;
        }
        self.count(Check::TimeBackwards);
        if let Some(r) = self.robot
            && t < r.t
        {
            let v = Violation::of_input(Check::TimeBackwards, Some(t), id);
            self.raise(v.observed(t).bound(r.t));
            return false;
        }
        true
    }

    /// Joins the current instant (the robot's state must be the same) or starts the next;
    /// whether the sample goes on to the obstacle checks.
    fn enter_instant(&mut self, s: &PlanarRobotSample, id: Option<ObstacleId>) -> bool {
        match self.robot {
            Some(r) if s.t == r.t => {
                if (s.robot_x, s.robot_y) != r.centre || s.robot_v != r.v || s.robot_mode != r.mode
                {
                    self.count(Check::MalformedSample);
                    let v = Violation::of_input(Check::MalformedSample, Some(s.t), id);
                    self.raise(v.detail(Detail::RobotStateDiffers));
                    return false;
                }
            }
            previous => self.start_instant(previous, s),
        }
        self.accepted += 1;
        self.carried_mode |= s.robot_mode.is_some();
        true
    }
}

/// A problem that does not read, as the certificate check's error.
fn verdict_invalid(why: String) -> crate::proof::certificate::Invalid {
    crate::proof::certificate::Invalid(format!("the certificate's problem does not read: {why}"))
}

/// `x ≤ bound` up to the relative tolerance and `extra` rounding.
fn within(x: f64, bound: f64, extra: f64) -> bool {
    x <= bound + RELATIVE_TOLERANCE * bound.abs() + extra
}

/// The rounding of a difference of two points' coordinates.
fn rounding_xy(a: Xy, b: Xy) -> f64 {
    rounding(a.0, b.0) + rounding(a.1, b.1)
}
