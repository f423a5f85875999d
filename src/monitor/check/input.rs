//! The fail-safe checks on the input itself: a sample that fails one is reported and
//! otherwise ignored (it changes no state). Non-finite numbers, obstacle ids beyond the
//! table, time going backwards, the same obstacle twice at one instant, and a robot state
//! (position, speed, mode, lanes) that differs from the instant's first sample.

use super::Check;
use crate::monitor::event::{Detail, Violation};
use crate::monitor::{Field, Lanes, Monitor, RobotAt, Sample, Track};

/// The first non-finite field of a sample.
#[inline]
pub(crate) fn non_finite(s: &Sample) -> Option<Field> {
    // x − x is +0 for a finite x and NaN for ±∞ and NaN, so the sum is 0 exactly when
    // every number is finite: one comparison instead of one per field.
    #[allow(clippy::eq_op)] // x − x is the point: it is not 0 for every x.
    let zero = |x: f64| x - x;
    let all = zero(s.t)
        + zero(s.robot_x)
        + zero(s.robot_v)
        + zero(s.obstacle_x)
        + zero(s.obstacle_v.unwrap_or(0.0))
        + zero(s.obstacle_t.unwrap_or(0.0));
    if all == 0.0 {
        return None;
    }
    [
        (Field::T, s.t),
        (Field::RobotX, s.robot_x),
        (Field::RobotV, s.robot_v),
        (Field::ObstacleX, s.obstacle_x),
        (Field::ObstacleV, s.obstacle_v.unwrap_or(0.0)),
        (Field::ObstacleT, s.obstacle_t.unwrap_or(0.0)),
    ]
    .into_iter()
    .find(|(_, x)| !x.is_finite())
    .map(|(f, _)| f)
}

impl Monitor {
    /// The obstacle's record, growing the table on a new largest id; `None` (reported) for a
    /// sample with a non-finite number or an id beyond the table.
    #[inline(always)]
    pub(in crate::monitor) fn admit(&mut self, s: &Sample) -> Option<Track> {
        let id = s.obstacle_id;
        if let Some(field) = non_finite(s) {
            self.count(Check::NonFinite);
            let t = Some(s.t).filter(|t| t.is_finite());
            let event = Violation::of_input(Check::NonFinite, t, Some(id));
            self.raise(event.detail(Detail::NonFinite(field)));
            return None;
        }
        if id >= self.max_obstacles {
            self.count(Check::MalformedSample);
            let detail = Detail::ObstacleIdOutOfRange {
                limit: self.max_obstacles,
            };
            self.raise(Violation::at(Check::MalformedSample, s).detail(detail));
            return None;
        }
        let idx = id as usize;
        if idx >= self.obstacles.len() {
            self.obstacles.resize(idx + 1, Track::default());
        }
        Some(self.obstacles[idx])
    }

    /// A robot-only sample is admitted unless a number is non-finite (reported).
    #[inline(always)]
    pub(in crate::monitor) fn admit_robot(&mut self, s: &Sample) -> bool {
        match non_finite(s) {
            None => true,
            Some(field) => {
                self.count(Check::NonFinite);
                let t = Some(s.t).filter(|t| t.is_finite());
                let event = Violation::of_input(Check::NonFinite, t, None);
                self.raise(event.detail(Detail::NonFinite(field)));
                false
            }
        }
    }

    /// A sample at or before the current instant `r` (`track`: its obstacle's record; `None`
    /// for a robot-only sample): time going backwards, the obstacle
    /// twice at the instant, or a robot state that differs from the instant's are rejected
    /// (reported); a robot mode or lanes the instant lacked are adopted. Whether it is
    /// accepted.
    #[inline(always)]
    pub(in crate::monitor) fn join_instant<const SCENE: bool>(
        &mut self,
        s: &Sample,
        lanes: Lanes,
        r: RobotAt,
        track: Option<&Track>,
    ) -> bool {
        if s.t < r.t {
            let event = Violation::at(Check::TimeBackwards, s);
            self.raise(event.observed(s.t).bound(r.t));
            return false;
        }
        if let Some(track) = track
            && track.seen
            && track.instant == self.instant
        {
            self.raise(Violation::at(Check::DuplicateSample, s).observed(s.t));
            return false;
        }
        let mode_differs = matches!((r.mode, s.robot_mode), (Some(a), Some(m)) if a != m);
        // The robot's lane and the one it is leaving are stated together (`leaving` empty
        // means no lane change), so they differ only where both samples state them.
        let held = self.robot_lanes;
        let lanes_differ = SCENE
            && held.robot.is_some()
            && lanes.robot.is_some()
            && (held.robot, held.leaving) != (lanes.robot, lanes.leaving);
        if r.x != s.robot_x || r.v != s.robot_v || mode_differs || lanes_differ {
            self.count(Check::MalformedSample);
            let event = Violation::at(Check::MalformedSample, s);
            self.raise(event.detail(Detail::RobotStateDiffers));
            return false;
        }
        if r.mode.is_none() && s.robot_mode.is_some() {
            self.robot = Some(RobotAt {
                mode: s.robot_mode,
                ..r
            });
        }
        if SCENE && held.robot.is_none() && lanes.robot.is_some() {
            self.robot_lanes = Lanes {
                obstacle: None,
                ..lanes
            };
        }
        true
    }
}
