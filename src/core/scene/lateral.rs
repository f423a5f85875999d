//! The robot across the lanes: one lane, or two during a lane change.
//!
//! A lane change starts at a step start k·dt and lasts P whole periods: the robot occupies
//! both lanes on [k·dt, (k+P)·dt] (closed) and the target lane only from then on. Lanes
//! change only at step starts, so within a step the occupied lanes are fixed.

use serde::{Deserialize, Serialize};

/// A lane change: when it started and between which lanes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct LaneChangeEvent {
    /// The step at whose start it began.
    pub step: usize,
    /// The lane the robot leaves.
    pub from: i32,
    /// The lane the robot moves into.
    pub to: i32,
}

/// Where the robot is across the lanes during a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lateral {
    /// The lane the robot is in, or (during a change) the lane it is moving into.
    pub lane: i32,
    /// The lane change in progress, if any.
    pub change: Option<LaneChangeEvent>,
}

impl Lateral {
    /// At t = 0: in lane 0, not changing.
    pub fn start() -> Lateral {
        Lateral {
            lane: 0,
            change: None,
        }
    }

    /// Whether the robot occupies `lane` (during a change: both lanes).
    pub fn occupies(&self, lane: i32) -> bool {
        self.lane == lane || self.leaving() == Some(lane)
    }

    /// The lane being left, during a lane change.
    pub fn leaving(&self) -> Option<i32> {
        self.change.map(|c| c.from)
    }

    /// The state at the start of step `k`, given lane changes last `periods` periods: a
    /// change begun at step s has completed at step s + P.
    pub fn at_step(self, k: usize, periods: usize) -> Lateral {
        match self.change {
            Some(c) if k >= c.step + periods => Lateral {
                lane: self.lane,
                change: None,
            },
            _ => self,
        }
    }

    /// Begins a change into `to` at the start of step `k`.
    pub fn begin_change(&mut self, k: usize, to: i32) -> LaneChangeEvent {
        let event = LaneChangeEvent {
            step: k,
            from: self.lane,
            to,
        };
        self.lane = to;
        self.change = Some(event);
        event
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A change occupies both lanes for exactly P periods, then the target lane only.
    #[test]
    fn a_change_occupies_both_lanes_for_its_periods() {
        let mut lateral = Lateral::start();
        lateral.begin_change(3, 1);
        for k in 3..8 {
            let now = lateral.at_step(k, 5);
            assert!(now.occupies(0) && now.occupies(1), "step {k}");
        }
        let done = lateral.at_step(8, 5);
        assert!(!done.occupies(0) && done.occupies(1));
        assert_eq!(done.leaving(), None);
    }
}
