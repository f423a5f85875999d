//! The checks that use lanes, under a scene certificate: an obstacle the certificate names
//! stays in its lane (`obstacle_lane`), and the robot never moves at a separation ≤
//! clearance from an obstacle in a lane it occupies (`collision`, docs/semantics.md §11.6).
//!
//! Which obstacles count for `collision`: one whose lane (stated by the sample, else the
//! certified one of a named obstacle) the robot occupies (its lane, or the one it is leaving
//! during a lane change). When the sample does not say where the robot is, or the lane of an
//! unnamed object is not stated, the obstacle counts: a trace without lanes reads as one lane,
//! as a single-obstacle trace always has.
//!
//! The separation is the gap for an obstacle that was ahead when its lane became one the
//! robot occupies (its first sample then), and minus the gap for one that was beside or
//! behind (gap ≤ 0), as the semantics measures it.

use super::{Check, rounding};
use crate::monitor::event::Violation;
use crate::monitor::scene::CertifiedObstacle;
use crate::monitor::{Lanes, Monitor, RELATIVE_TOLERANCE, Sample, Track};

impl Monitor {
    /// `obstacle_lane` and `collision` for a sample stating `lanes` (the robot's from the
    /// instant). Returns the obstacle's side to remember: whether it was ahead when the robot
    /// entered its lane (`None`: the robot is not in its lane). Out of line: only a scene
    /// certificate's monitor calls it, and a single obstacle's stays as small as it was.
    #[inline(never)]
    pub(in crate::monitor) fn check_lanes(
        &mut self,
        s: &Sample,
        lanes: Lanes,
        track: &Track,
        certified: Option<CertifiedObstacle>,
    ) -> Option<bool> {
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
        if lane.and_then(|l| robot.robot_occupies(l)) == Some(false) {
            return None;
        }
        let gap = s.obstacle_x - s.robot_x;
        let ahead = track.ahead.unwrap_or(gap > 0.0);
        if s.robot_v > 0.0 {
            self.check_collision(s, if ahead { gap } else { -gap });
        }
        Some(ahead)
    }

    /// `collision`: the robot moves at `separation` ≤ clearance, less the rounding error of
    /// the gap (so a full-precision trace of a safe run raises nothing).
    #[inline]
    fn check_collision(&mut self, s: &Sample, separation: f64) {
        let Some(clearance) = self.scene.as_ref().map(|scene| scene.clearance) else {
            return;
        };
        self.count(Check::Collision);
        let slack = RELATIVE_TOLERANCE * clearance + rounding(s.obstacle_x, s.robot_x);
        if separation <= clearance - slack {
            let v = Violation::at(Check::Collision, s);
            self.raise(v.observed(separation).bound(clearance));
        }
    }
}
