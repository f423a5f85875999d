//! The controller's guard: the collision-danger distance, what the robot sees at a step's
//! start, and whether (and why) it brakes (DESIGN.md §1, "Controller guards").

use serde::{Deserialize, Serialize};

use crate::core::model::{DangerRule, Params};
use crate::core::num::Scalar;

/// The collision-danger distance d_coll(v) of the controller's rule; `None` is infinite
/// (the `area` rule brakes on entering the reaction area).
pub fn danger_distance<N: Scalar>(p: &Params<N>, v: &N) -> Option<N> {
    let t_b = v.clone() / p.b.clone();
    match p.rule {
        DangerRule::Paper => Some(v.clone() * t_b.clone() + p.V_a.clone() * t_b + p.buffer.clone()),
        DangerRule::Kinematic => Some(
            v.clone() * v.clone() / (N::int(2) * p.b.clone())
                + p.V_a.clone() * t_b
                + p.buffer.clone(),
        ),
        DangerRule::Area => None,
    }
}

/// What the robot sees at the start of a step: the gap L periods ago and the obstacle's
/// speed over the period that ended then.
#[derive(Clone, Debug, PartialEq)]
pub struct Observation<N> {
    /// Observed gap (m).
    pub gap: N,
    /// Observed obstacle speed (m/s).
    pub speed: N,
}

/// Why the controller commanded Brake.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum BrakeReason {
    /// Observed gap within the danger distance.
    CollisionDanger,
    /// Obstacle in the area seen faster than V_a.
    WrongAssumption,
    /// The robot's stopping point reached its goal (scenes only: `nearDestination`).
    Destination,
}

/// The controller's guard: whether, with its own speed `v` and observation `obs`, the robot
/// brakes (DESIGN.md §1, "Controller guards").
pub fn guard<N: Scalar>(p: &Params<N>, v: &N, obs: &Observation<N>) -> Option<BrakeReason> {
    let in_area = obs.gap > N::zero() && obs.gap <= p.rho;
    if !in_area {
        return None;
    }
    let danger = match danger_distance(p, v) {
        None => true,
        Some(d) => obs.gap <= d,
    };
    if danger {
        Some(BrakeReason::CollisionDanger)
    } else if p.wrong_assumption_brake && obs.speed > p.V_a {
        Some(BrakeReason::WrongAssumption)
    } else {
        None
    }
}
