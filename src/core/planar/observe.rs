//! What the robot sees of one obstacle and which guards that fires (docs/semantics.md
//! §13.3–§13.4), decided in exact rationals on positions relative to the robot's centre at
//! the observed instant (as the line's observed gap is the gap L periods ago).
//!
//! Every comparison of a length is made on squares: both sides are ≥ 0 where it is squared
//! (‖rel‖ ≤ λ with λ ≥ 0 ⟺ ‖rel‖² ≤ λ²). The field of view asks rel·h ≥ cos(θ/2)·‖rel‖:
//! for cos ≥ 0 that is rel·h ≥ 0 and (rel·h)² ≥ cos²·‖rel‖²; for cos < 0 it holds when
//! rel·h ≥ 0, and otherwise exactly when (rel·h)² ≤ cos²·‖rel‖² (both sides negative).

use crate::core::num::Exact;
use crate::core::plane::point::Point;
use crate::core::semantics::danger_distance;

use super::params::{DangerZone, PlanarParams};

/// Whether an obstacle whose true centre is `rel` from the robot's centre (at the observed
/// instant, robot heading `heading`, a unit vector) is within range and field of view.
pub fn visible(params: &PlanarParams, rel: &Point, heading: &Point) -> bool {
    let s = &params.sensing;
    let n2 = rel.norm_squared();
    if s.range.as_ref().is_some_and(|r| n2 > r * r) {
        return false;
    }
    match &s.view_cos_half {
        None => true,
        Some(cos) => {
            let along = rel.dot(heading);
            let (lhs, rhs) = (&along * &along, cos * cos * &n2);
            if *cos >= Exact::ZERO {
                along >= Exact::ZERO && lhs >= rhs
            } else {
                along >= Exact::ZERO || lhs <= rhs
            }
        }
    }
}

/// The danger guard on a seen centre `seen` (relative to the robot's centre at the observed
/// instant, heading `heading`) of obstacle `index`, the robot's speed now being `v`.
pub fn dangerous(
    params: &PlanarParams,
    index: usize,
    seen: &Point,
    heading: &Point,
    v: &Exact,
) -> bool {
    let r_i = &params.obstacles[index].radius;
    match &params.zone {
        DangerZone::Disc => {
            let m = &params.motion;
            let theta = match danger_distance(m, v) {
                Some(d) if d < m.rho => d,
                _ => m.rho.clone(),
            };
            within(seen, &(theta + &params.robot_radius + r_i))
        }
        DangerZone::Polygon(zone) => {
            // The robot's frame: x along the heading, y to its left.
            let local = Point::new(seen.dot(heading), heading.cross(seen));
            zone.distance_squared(&local) <= r_i * r_i
        }
    }
}

/// The wrong-assumption guard (when on): the seen centre within ρ (rims apart) and the seen
/// velocity faster than V_a.
pub fn wrong_assumption(
    params: &PlanarParams,
    index: usize,
    seen: &Point,
    velocity: &Point,
) -> bool {
    let m = &params.motion;
    if !m.wrong_assumption_brake {
        return false;
    }
    let reach = &m.rho + &params.robot_radius + &params.obstacles[index].radius;
    within(seen, &reach) && velocity.norm_squared() > &m.V_a * &m.V_a
}

/// ‖rel‖ ≤ λ, for λ ≥ 0.
fn within(rel: &Point, lambda: &Exact) -> bool {
    rel.norm_squared() <= lambda * lambda
}
