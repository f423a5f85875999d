//! The checks that use lanes, under a scene certificate: an obstacle the certificate names
//! stays in its lane (`obstacle_lane`), and the robot never moves at a separation ≤
//! clearance from an obstacle in a lane it occupies (`collision`, docs/semantics.md §11.6;
//! a single-obstacle certificate's monitor checks it too, every obstacle counting).
//!
//! Which obstacles count for `collision`: one whose lane (stated by the sample, else the
//! certified one of a named obstacle) the robot occupies (its lane, or the one it is leaving
//! during a lane change). When the sample does not say where the robot is, or the lane of an
//! unnamed object is not stated, the obstacle counts: a trace without lanes reads as one lane,
//! as a single-obstacle trace always has.
//!
//! The separation is the gap for an obstacle that was ahead when its lane became one the
//! robot occupies (its first sample then), and minus the gap for one that was beside or
//! behind (gap ≤ 0), as the semantics measures it; `collision.rs` checks it, at the instant
//! and over the step before it.

use super::Check;
use crate::monitor::event::Violation;
use crate::monitor::scene::CertifiedObstacle;
use crate::monitor::{Lanes, Monitor, Sample, Track};

/// Where an obstacle is relative to the robot's lanes, as one sample shows it.
#[derive(Clone, Copy, Debug)]
pub(in crate::monitor) struct LaneView {
    /// Whether it was ahead when the robot entered its lane (`None`: the robot is not in
    /// its lane); the side `collision` measures from.
    pub(in crate::monitor) ahead: Option<bool>,
    /// Its lane, when the sample or the certificate says.
    pub(in crate::monitor) lane: Option<i32>,
    /// Whether the controller's guards count it: it is in the robot's lane (during a lane
    /// change, the lane moved into), or either lane is unknown.
    pub(in crate::monitor) relevant: bool,
}

impl Monitor {
    /// `collision` for a single-obstacle certificate (no lanes: every obstacle counts).
    /// Returns the side to remember, as [`Monitor::check_lanes`].
    #[inline(always)]
    pub(in crate::monitor) fn check_collision_ahead(
        &mut self,
        s: &Sample,
        track: &Track,
    ) -> LaneView {
        let gap = s.obstacle_x - s.robot_x;
        let ahead = track.ahead.unwrap_or(gap > 0.0);
        self.check_separation(s, track, ahead, self.bounds.obstacle_speed);
        LaneView {
            ahead: Some(ahead),
            lane: None,
            relevant: true,
        }
    }

    /// `obstacle_lane` and `collision` for a sample stating `lanes` (the robot's from the
    /// instant). Returns where the obstacle is ([`LaneView`]). Out of line: only a scene
    /// certificate's monitor calls it, and a single obstacle's stays as small as it was.
    #[inline(never)]
    pub(in crate::monitor) fn check_lanes(
        &mut self,
        s: &Sample,
        lanes: Lanes,
        track: &Track,
        certified: Option<CertifiedObstacle>,
    ) -> LaneView {
        if let Some(stated) = lanes.obstacle {
            self.carried.obstacle_lane = true;
            if let Some(o) = certified {
                self.count(Check::ObstacleLane);
                if stated != o.lane {
                    let v = Violation::at(Check::ObstacleLane, s);
                    self.raise(v.observed(f64::from(stated)).bound(f64::from(o.lane)));
                }
            }
        }
        let lane = lanes.obstacle.or(certified.map(|o| o.lane));
        let robot = self.robot_lanes;
        let relevant = match (lane, robot.robot) {
            (Some(l), Some(r)) => l == r,
            _ => true,
        };
        if lane.and_then(|l| robot.robot_occupies(l)) == Some(false) {
            return LaneView {
                ahead: None,
                lane,
                relevant,
            };
        }
        let gap = s.obstacle_x - s.robot_x;
        let ahead = track.ahead.unwrap_or(gap > 0.0);
        let w = certified.map_or(self.bounds.obstacle_speed, |o| o.max_speed);
        self.check_separation(s, track, ahead, w);
        LaneView {
            ahead: Some(ahead),
            lane,
            relevant,
        }
    }
}
