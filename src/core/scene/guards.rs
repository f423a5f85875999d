//! The scene controller (DESIGN.md §1.1, "Guards"): at a step start in Accelerate or Drive,
//! from the robot's own state and what it sees of each obstacle, go on, brake, or begin a
//! lane change.
//!
//! It is the single-obstacle [`guard`](crate::core::semantics::guard) extended: the danger
//! distance is [`danger_distance`] (with V_a = 0 for static obstacles), so with one moving
//! obstacle in the robot's lane it decides exactly as `guard` does.

use crate::core::num::Scalar;
use crate::core::semantics::{BrakeReason, Observation, RobotState, danger_distance};

use super::lateral::Lateral;
use super::params::SceneParams;

/// What the controller commands at a step start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Keep the current mode.
    Go,
    /// Brake (latched until Stop).
    Brake(BrakeReason),
    /// Begin a lane change into this lane.
    ChangeLane(i32),
}

/// The controller's decision at a step start, for a robot in Accelerate or Drive.
/// `seen[i]` is what it sees of obstacle i (None: nothing yet, or beyond the sensing range);
/// `lateral` is the robot's lateral state at this step start (a finished change completed).
///
/// Precedence: a brake is commanded on a wrong assumption, on the destination, or on danger
/// that no lane change answers; its reason is danger when danger holds (as in the
/// single-obstacle `guard`), else wrong assumption, else destination.
pub fn scene_guard<N: Scalar>(
    p: &SceneParams<N>,
    robot: &RobotState<N>,
    lateral: &Lateral,
    seen: &[Option<Observation<N>>],
) -> Command {
    let v = &robot.speed;
    let rho = &p.robot.rho;
    let relevant = |i: usize| -> Option<&Observation<N>> {
        let obs = seen[i].as_ref()?;
        (p.obstacles[i].lane == lateral.lane && obs.gap > N::zero() && obs.gap <= *rho)
            .then_some(obs)
    };
    let mut danger = false;
    let mut change_in_time = true;
    let mut wrong = false;
    for i in 0..p.obstacles.len() {
        let Some(obs) = relevant(i) else { continue };
        let is_static = p.obstacles[i].is_static;
        let dangerous = match danger_distance(p.controller_for(i), v) {
            None => true,
            Some(d) => obs.gap <= d,
        };
        if dangerous {
            danger = true;
            change_in_time &= obs.gap > lane_change_distance(p, v, is_static);
        }
        wrong |= p.robot.wrong_assumption_brake && !is_static && obs.speed > p.robot.V_a;
    }
    let destination = p.goal.as_ref().is_some_and(|goal| {
        robot.position.clone() + v.clone() * v.clone() / (N::int(2) * p.robot.b.clone()) >= *goal
    });
    if danger
        && !wrong
        && !destination
        && change_in_time
        && let Some(to) = free_adjacent_lane(p, lateral, seen)
    {
        return Command::ChangeLane(to);
    }
    if danger {
        Command::Brake(BrakeReason::CollisionDanger)
    } else if wrong {
        Command::Brake(BrakeReason::WrongAssumption)
    } else if destination {
        Command::Brake(BrakeReason::Destination)
    } else {
        Command::Go
    }
}

/// d_lc(v) = (v + V)·P·dt + buffer: how far a dangerous obstacle must be observed for a lane
/// change to finish in time (V = V_a for a moving obstacle, 0 for a static one). Infinite
/// (no change can be in time) when lane changes are off.
fn lane_change_distance<N: Scalar>(p: &SceneParams<N>, v: &N, is_static: bool) -> N {
    let Some(lc) = &p.lane_change else {
        // Never compared when lane changes are off; any number does.
        return N::zero();
    };
    let assumed = if is_static {
        N::zero()
    } else {
        p.robot.V_a.clone()
    };
    (v.clone() + assumed) * N::int(lc.periods as i64) * p.robot.dt.clone() + p.robot.buffer.clone()
}

/// The lane to change into: ℓ+1 if it exists and is free, else ℓ−1 if it exists and is free;
/// none when lane changes are off or one is in progress.
fn free_adjacent_lane<N: Scalar>(
    p: &SceneParams<N>,
    lateral: &Lateral,
    seen: &[Option<Observation<N>>],
) -> Option<i32> {
    let lc = p.lane_change.as_ref()?;
    if lateral.change.is_some() {
        return None;
    }
    let low = -lc.rear_gap.clone();
    let free = |lane: i32| {
        p.has_lane(lane)
            && p.obstacles.iter().zip(seen).all(|(o, obs)| {
                o.lane != lane
                    || obs
                        .as_ref()
                        .is_none_or(|obs| obs.gap < low || obs.gap > p.robot.rho)
            })
    };
    [lateral.lane + 1, lateral.lane - 1]
        .into_iter()
        .find(|&lane| free(lane))
}
