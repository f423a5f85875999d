//! The robot's state at an instant inside a control period ([`state_within`]): what
//! [`robot_motion`](super::robot_motion) gives at the period's end, at any τ ∈ [0, dt].
//! The plane's bounds and replays read the robot's centre inside a step from it.

use crate::core::model::Params;
use crate::core::num::Scalar;

use super::{Mode, RobotState};

/// The robot's position and speed τ ∈ [0, dt] into a period that starts in `state` (the
/// mode is the one chosen at the period's start), with the same clamps at v_max and at
/// rest as [`robot_motion`](super::robot_motion); at τ = dt it is that function's end
/// state's position and speed. The mode returned is the period's (not updated inside it).
pub fn state_within<N: Scalar>(p: &Params<N>, state: &RobotState<N>, tau: &N) -> RobotState<N> {
    let (x, v) = (state.position.clone(), state.speed.clone());
    let half = p.k.half.clone();
    let (position, speed) = match state.mode {
        Mode::Accelerate | Mode::Drive if v >= p.v_max => {
            (x + p.v_max.clone() * tau.clone(), p.v_max.clone())
        }
        Mode::Accelerate => {
            let reach = (p.v_max.clone() - v.clone()) / p.a.clone();
            if *tau <= reach {
                let gained = p.a.clone() * tau.clone();
                (
                    x + v.clone() * tau.clone() + half * gained.clone() * tau.clone(),
                    v + gained,
                )
            } else {
                let accelerating =
                    v * reach.clone() + half * p.a.clone() * reach.clone() * reach.clone();
                (
                    x + accelerating + p.v_max.clone() * (tau.clone() - reach),
                    p.v_max.clone(),
                )
            }
        }
        Mode::Drive => (x + v.clone() * tau.clone(), v),
        Mode::Brake if v > N::zero() => {
            let stop = v.clone() / p.b_min.clone();
            if *tau <= stop {
                let lost = p.b_min.clone() * tau.clone();
                (
                    x + v.clone() * tau.clone() - half * lost.clone() * tau.clone(),
                    v - lost,
                )
            } else {
                (x + half * v.clone() * stop, N::zero())
            }
        }
        Mode::Brake | Mode::Idle | Mode::Stop => (x, v),
    };
    RobotState {
        position,
        speed,
        mode: state.mode,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::num::Scalar;
    use crate::core::rational::Rational;
    use crate::core::semantics::robot_motion;
    use crate::core::semantics::tests::{Lcg, random_params};

    /// At τ = dt the state inside the period is the period's end (position and speed), for
    /// every mode and random problems: the two functions are one motion.
    #[test]
    fn the_end_of_the_period_is_robot_motion() {
        let mut rng = Lcg(7);
        for _ in 0..300 {
            let p = random_params(&mut rng);
            let mode = rng.pick(&[Mode::Accelerate, Mode::Drive, Mode::Brake, Mode::Stop]);
            let speed = match mode {
                Mode::Drive => p.v_max.clone(),
                Mode::Stop => Rational::zero(),
                _ => p.v_max.clone() * Rational::int(rng.below(11) as i64) / Rational::int(10),
            };
            let state = RobotState {
                position: Rational::int(rng.below(5) as i64),
                speed,
                mode,
            };
            let end = robot_motion(&p, &state).end;
            let within = state_within(&p, &state, &p.dt);
            assert_eq!(within.position, end.position, "{mode:?}");
            assert_eq!(within.speed, end.speed, "{mode:?}");
        }
    }

    /// Inside a period the position is nondecreasing in τ and the speed within [0, v_max].
    #[test]
    fn positions_inside_a_period_never_go_back() {
        let mut rng = Lcg(11);
        for _ in 0..100 {
            let p = random_params(&mut rng);
            let mode = rng.pick(&[Mode::Accelerate, Mode::Brake]);
            let state = RobotState {
                position: Rational::zero(),
                speed: p.v_max.clone() * Rational::int(rng.below(11) as i64) / Rational::int(10),
                mode,
            };
            let mut last = Rational::zero();
            for i in 0..=16 {
                let tau = p.dt.clone() * Rational::int(i) / Rational::int(16);
                let s = state_within(&p, &state, &tau);
                assert!(s.position >= last);
                assert!(s.speed >= Rational::zero() && s.speed <= p.v_max);
                last = s.position;
            }
        }
    }
}
