//! The lanes a sample of a scene trace states: where the robot is (one lane, or two during a
//! lane change) and where the obstacle is. Traces without lane columns state none, and the
//! monitor then reads them as it always has.

/// The lanes one sample states (all `None` in a trace without lane columns).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Lanes {
    /// `robot_lane`: the lane the robot occupies from this instant on; during a lane change,
    /// the lane it moves into.
    pub robot: Option<i32>,
    /// `leaving_lane`: during a lane change, the lane the robot is leaving (it occupies both).
    pub leaving: Option<i32>,
    /// `obstacle_lane`: the obstacle's lane.
    pub obstacle: Option<i32>,
}

impl Lanes {
    /// No lane stated (a trace without lane columns).
    pub const UNKNOWN: Lanes = Lanes {
        robot: None,
        leaving: None,
        obstacle: None,
    };

    /// Whether the robot occupies `lane` (its lane, or the one it is leaving); `None` when
    /// the sample does not say where the robot is.
    #[inline]
    pub fn robot_occupies(&self, lane: i32) -> Option<bool> {
        self.robot
            .map(|robot| robot == lane || self.leaving == Some(lane))
    }
}
