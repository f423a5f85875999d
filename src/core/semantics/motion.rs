//! The robot's exact motion over one control period in the mode chosen at its start
//! ([`robot_motion`]): accelerating, cruising or braking, with the speed clamped at v_max
//! and at 0 inside the period.

use crate::core::model::Params;
use crate::core::num::Scalar;

use super::{Mode, RobotState};

/// The robot's motion over one control period in a given mode.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion<N> {
    /// State at the end of the period.
    pub end: RobotState<N>,
    /// How long into the period the robot was moving: the period itself, the instant it
    /// came to rest, or zero if it stood still throughout.
    pub moving_for: N,
}

impl<N: Scalar> Motion<N> {
    /// Whether the robot came to rest inside this period (it was moving and now is not).
    pub fn came_to_rest(&self) -> bool {
        self.moving_for > N::zero() && self.end.speed == N::zero()
    }
}

/// The robot's exact motion over one control period starting in `state`, with the speed
/// clamped at v_max and at 0 inside the period (a robot that stops mid-period has moved
/// v²/(2b), not v·dt). The mode in `state` is the one chosen at the period's start.
pub fn robot_motion<N: Scalar>(p: &Params<N>, state: &RobotState<N>) -> Motion<N> {
    let x = state.position.clone();
    let v = state.speed.clone();
    match state.mode {
        Mode::Accelerate | Mode::Drive if v >= p.v_max => Motion::to(
            x + p.k.v_max_dt.clone(),
            p.v_max.clone(),
            Mode::Drive,
            p.dt.clone(),
        ),
        Mode::Accelerate => accelerate(p, x, v),
        Mode::Drive => Motion::to(x + v.clone() * p.dt.clone(), v, Mode::Drive, p.dt.clone()),
        Mode::Brake => brake(p, x, v),
        Mode::Idle | Mode::Stop => Motion {
            end: state.clone(),
            moving_for: N::zero(),
        },
    }
}

impl<N: Scalar> Motion<N> {
    /// A motion ending at `position` with `speed` in `mode`, having moved for `moving_for`.
    #[inline]
    fn to(position: N, speed: N, mode: Mode, moving_for: N) -> Self {
        Motion {
            end: RobotState {
                position,
                speed,
                mode,
            },
            moving_for,
        }
    }
}

/// One period in Accelerate below v_max: reach v_max inside it and cruise, or gain a·dt.
#[inline]
fn accelerate<N: Scalar>(p: &Params<N>, x: N, v: N) -> Motion<N> {
    let (dt, k) = (&p.dt, &p.k);
    if p.v_max.clone() - v.clone() <= k.a_dt {
        // Reaches v_max inside the period (after `reach`), then cruises.
        let reach = (p.v_max.clone() - v.clone()) / p.a.clone();
        let position = x
            + v * reach.clone()
            + k.half.clone() * p.a.clone() * reach.clone() * reach.clone()
            + p.v_max.clone() * (dt.clone() - reach);
        Motion::to(position, p.v_max.clone(), Mode::Drive, dt.clone())
    } else {
        let position = x + v.clone() * dt.clone() + k.half_a_dt2.clone();
        Motion::to(position, v + k.a_dt.clone(), Mode::Accelerate, dt.clone())
    }
}

/// One period in Brake: at rest already, stop inside the period, or lose b_min·dt.
#[inline]
fn brake<N: Scalar>(p: &Params<N>, x: N, v: N) -> Motion<N> {
    let (dt, k) = (&p.dt, &p.k);
    if v <= N::zero() {
        return Motion::to(x, N::zero(), Mode::Stop, N::zero());
    }
    // The plant brakes at b_min, its guaranteed rate: the worst case of [b_min, b]
    // (docs/semantics.md, "Weaker brakes").
    if v <= k.b_min_dt {
        // Stops inside the period, after v/b_min, having moved v²/(2b_min).
        let stop = v.clone() / p.b_min.clone();
        let position = x + k.half.clone() * v * stop.clone();
        Motion::to(position, N::zero(), Mode::Stop, stop)
    } else {
        let position = x + v.clone() * dt.clone() - k.half_b_min_dt2.clone();
        Motion::to(position, v - k.b_min_dt.clone(), Mode::Brake, dt.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::num::Exact;
    use crate::core::semantics::tests::params;

    /// A robot that stops inside a period has moved v²/(2b) and rests at v/b, not v·dt.
    #[test]
    fn braking_stops_inside_the_period_exactly() {
        let p = params();
        let v = exact_of(0.03);
        let m = robot_motion(
            &p,
            &RobotState {
                position: Exact::ZERO,
                speed: v.clone(),
                mode: Mode::Brake,
            },
        );
        assert_eq!(m.end.speed, Exact::ZERO);
        assert_eq!(m.end.mode, Mode::Stop);
        assert_eq!(m.moving_for, v.clone() / p.b.clone());
        assert_eq!(
            m.end.position,
            v.clone() * v / (Exact::from(2) * p.b.clone())
        );
    }

    fn exact_of(x: f64) -> Exact {
        crate::core::num::exact_decimal(x)
    }
}
