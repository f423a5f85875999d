//! A scene's numbers in the number type an engine runs in (exact rationals for replay and
//! checks, `f64` for Monte Carlo), read from the scene file the way [`Problem::params`] reads
//! a problem: every decimal as the exact rational it denotes.

use crate::core::model::{Environment, Params, Problem};
use crate::core::num::Scalar;

use super::Scene;

/// One obstacle's numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleParams<N> {
    /// Its name (trace rows and reports name it).
    pub name: String,
    /// The lane it moves in.
    pub lane: i32,
    /// The nearest possible initial x (m): the start when its position is a number.
    pub start_min: N,
    /// The farthest possible initial x (m).
    pub start_max: N,
    /// W_i: bound on its speed towards −x (m/s).
    pub max_speed: N,
    /// Known to the robot as static: its danger rule has V_a = 0, the wrong-assumption guard
    /// ignores it, and a lane change assumes it does not move.
    pub is_static: bool,
}

/// How the controller changes lanes, in numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct LaneChangeParams<N> {
    /// P: whole control periods a lane change lasts (≥ 1).
    pub periods: usize,
    /// A lane is free when no seen obstacle in it is observed at a gap in [−rear_gap, ρ] (m).
    pub rear_gap: N,
}

/// A scene's numbers: the robot and its controller, the lanes, the obstacles.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneParams<N> {
    /// The robot's dynamics and its controller (v_max, a, b, dt, L, clearance, V_a, ρ, the
    /// danger rule, buffer, wrong-assumption flag). Its `W` is the largest moving bound and
    /// its `g0` the nearest obstacle start; the scene's step function uses neither.
    pub robot: Params<N>,
    /// `robot` with V_a = 0: the danger rule for static obstacles (only the robot's own
    /// braking counts).
    pub static_robot: Params<N>,
    /// Destination x (m): the controller brakes once x_r + v²/(2b) ≥ goal.
    pub goal: Option<N>,
    /// Sensing range R (m): an obstacle observed at a gap above R is not seen.
    pub sensing_range: Option<N>,
    /// Lane changes, when the controller may make them.
    pub lane_change: Option<LaneChangeParams<N>>,
    /// Lanes that exist, ascending.
    pub lanes: Vec<i32>,
    /// The obstacles, in the scene's order.
    pub obstacles: Vec<ObstacleParams<N>>,
}

impl Scene {
    /// The scene's numbers as `N` (exact decimals for rationals, as [`Problem::params`]).
    pub fn params<N: Scalar>(&self) -> SceneParams<N> {
        let nearest = self
            .obstacles
            .iter()
            .map(|o| o.position.min())
            .fold(f64::INFINITY, f64::min);
        let problem = Problem {
            name: self.name.clone(),
            robot: self.robot.clone(),
            controller: self.controller.clone(),
            environment: Environment {
                obstacle_speed: self.largest_moving_bound(),
                initial_gap: crate::core::model::Position::At(if nearest.is_finite() {
                    nearest
                } else {
                    0.0
                }),
            },
            sensing: self.sensing.clone(),
        };
        let robot: Params<N> = problem.params();
        let mut static_robot = robot.clone();
        static_robot.V_a = N::zero();
        SceneParams {
            robot,
            static_robot,
            goal: self.goal.map(N::decimal),
            sensing_range: self.sensing_range.map(N::decimal),
            lane_change: self.lane_change.map(|lc| LaneChangeParams {
                periods: lc.periods as usize,
                rear_gap: N::decimal(lc.rear_gap),
            }),
            lanes: self.lanes.clone(),
            obstacles: self
                .obstacles
                .iter()
                .map(|o| ObstacleParams {
                    name: o.name.clone(),
                    lane: o.lane,
                    start_min: N::decimal(o.position.min()),
                    start_max: N::decimal(o.position.max()),
                    max_speed: N::decimal(o.max_speed),
                    is_static: o.is_static,
                })
                .collect(),
        }
    }
}

impl<N: Scalar> SceneParams<N> {
    /// The same scene in another number type, converting every number with `f`.
    pub fn map<M>(&self, f: impl Fn(&N) -> M) -> SceneParams<M> {
        SceneParams {
            robot: self.robot.map(&f),
            static_robot: self.static_robot.map(&f),
            goal: self.goal.as_ref().map(&f),
            sensing_range: self.sensing_range.as_ref().map(&f),
            lane_change: self.lane_change.as_ref().map(|lc| LaneChangeParams {
                periods: lc.periods,
                rear_gap: f(&lc.rear_gap),
            }),
            lanes: self.lanes.clone(),
            obstacles: self
                .obstacles
                .iter()
                .map(|o| ObstacleParams {
                    name: o.name.clone(),
                    lane: o.lane,
                    start_min: f(&o.start_min),
                    start_max: f(&o.start_max),
                    max_speed: f(&o.max_speed),
                    is_static: o.is_static,
                })
                .collect(),
        }
    }

    /// The controller's parameters for obstacle `i`: [`Self::static_robot`] for a static
    /// obstacle, else [`Self::robot`].
    pub fn controller_for(&self, i: usize) -> &Params<N> {
        if self.obstacles[i].is_static {
            &self.static_robot
        } else {
            &self.robot
        }
    }

    /// Whether `lane` exists.
    pub fn has_lane(&self, lane: i32) -> bool {
        self.lanes.contains(&lane)
    }

    /// Each obstacle's nearest start: the start of every obstacle whose position is a number.
    pub fn nearest_starts(&self) -> Vec<N> {
        self.obstacles.iter().map(|o| o.start_min.clone()).collect()
    }

    /// P, the periods a lane change lasts (0 when lane changes are off).
    pub fn lane_change_periods(&self) -> usize {
        self.lane_change.as_ref().map_or(0, |lc| lc.periods)
    }
}
