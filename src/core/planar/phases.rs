//! The robot's arc length inside one control period as polynomials in τ, one per motion
//! phase ([`motion_phases`]): the form of [`state_within`](crate::core::semantics::state_within)
//! the planar replay composes with the path to get D(τ) (docs/semantics.md §13.1).

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::polynomial::Polynomial;
use crate::core::semantics::{Mode, RobotState};

/// One motion phase of a period: on [from, to] (τ since the period's start) the robot's arc
/// length is `arc(τ)`, a polynomial of degree ≤ 2, and it is moving at every instant of
/// [from, to) except possibly at τ = 0 when it starts from rest.
#[derive(Clone, Debug, PartialEq)]
pub struct Phase {
    /// The phase's first instant (τ).
    pub from: Exact,
    /// Its last instant (τ); > `from`.
    pub to: Exact,
    /// The arc length s(τ) on it.
    pub arc: Polynomial,
    /// The robot comes to rest at `to` (the last phase of a period in which it stops).
    pub rests_at_end: bool,
}

/// The moving phases of a period that starts in `state` (its mode the one chosen at the
/// period's start), with the clamps of [`robot_motion`](crate::core::semantics::robot_motion):
/// accelerating then cruising once v_max is reached; cruising; braking at b_min until at
/// rest. Empty when the robot does not move (Stop, Idle, or Brake at speed 0). Outside the
/// phases of a period whose last phase rests, the robot stands at that phase's end.
pub fn motion_phases(p: &Params<Exact>, state: &RobotState<Exact>) -> Vec<Phase> {
    let (x, v, dt) = (&state.position, &state.speed, &p.dt);
    let half = Exact::ONE / Exact::from(2);
    let line = |c0: Exact, c1: Exact| Polynomial::new(vec![c0, c1]);
    let phase = |from: Exact, to: Exact, arc: Polynomial, rests_at_end: bool| Phase {
        from,
        to,
        arc,
        rests_at_end,
    };
    match state.mode {
        Mode::Accelerate | Mode::Drive if *v >= p.v_max => {
            vec![phase(
                Exact::ZERO,
                dt.clone(),
                line(x.clone(), p.v_max.clone()),
                false,
            )]
        }
        Mode::Accelerate => {
            let speeding = Polynomial::new(vec![x.clone(), v.clone(), &p.a * &half]);
            let reach = (&p.v_max - v) / &p.a;
            if reach >= *dt {
                return vec![phase(Exact::ZERO, dt.clone(), speeding, false)];
            }
            // Cruise from `reach`: s = s(reach) + v_max·(τ − reach).
            let at_reach = speeding.eval(&reach);
            let cruise = line(&at_reach - &p.v_max * &reach, p.v_max.clone());
            vec![
                phase(Exact::ZERO, reach.clone(), speeding, false),
                phase(reach, dt.clone(), cruise, false),
            ]
        }
        Mode::Drive => vec![phase(
            Exact::ZERO,
            dt.clone(),
            line(x.clone(), v.clone()),
            false,
        )],
        Mode::Brake if *v > Exact::ZERO => {
            let slowing = Polynomial::new(vec![x.clone(), v.clone(), -(&p.b_min * &half)]);
            let stop = v / &p.b_min;
            if stop <= *dt {
                vec![phase(Exact::ZERO, stop, slowing, true)]
            } else {
                vec![phase(Exact::ZERO, dt.clone(), slowing, false)]
            }
        }
        Mode::Brake | Mode::Idle | Mode::Stop => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::rational::Rational;
    use crate::core::semantics::state_within;
    use crate::core::semantics::tests::{Lcg, random_params};

    /// Inside each phase the polynomial is `state_within`'s position, at dense rational
    /// instants and random problems and modes; phases tile [0, dt] or end at rest.
    #[test]
    fn phases_are_state_within() {
        let mut rng = Lcg(5);
        for _ in 0..200 {
            let p: Params<Exact> = random_params(&mut rng).map(Rational::to_exact);
            let mode = rng.pick(&[Mode::Accelerate, Mode::Drive, Mode::Brake, Mode::Stop]);
            let speed = match mode {
                Mode::Drive => p.v_max.clone(),
                Mode::Stop => Exact::ZERO,
                _ => &p.v_max * Exact::from(rng.below(11)) / Exact::from(10),
            };
            let state = RobotState {
                position: Exact::from(rng.below(5)),
                speed,
                mode,
            };
            let phases = motion_phases(&p, &state);
            let mut at = Exact::ZERO;
            for ph in &phases {
                assert_eq!(ph.from, at, "phases are contiguous");
                assert!(ph.to > ph.from);
                for i in 0..=8 {
                    let tau = &ph.from + (&ph.to - &ph.from) * Exact::from(i) / Exact::from(8);
                    let s = state_within(&p, &state, &tau);
                    assert_eq!(ph.arc.eval(&tau), s.position, "{mode:?}");
                }
                at = ph.to.clone();
            }
            if let Some(last) = phases.last() {
                assert!(last.rests_at_end || last.to == p.dt);
            }
        }
    }
}
