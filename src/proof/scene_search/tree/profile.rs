//! The robot along the drive profile (never braking), extended as the search needs it.

use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::semantics::{RobotState, robot_motion};

/// The robot along the drive profile, extended as the search needs it.
#[derive(Clone, Debug)]
pub struct Profile {
    states: Vec<RobotState<Rational>>,
}

impl Profile {
    /// The profile's first state: the robot at t = 0.
    pub fn new(p: &SceneParams<Rational>) -> Profile {
        Profile {
            states: vec![RobotState::initial(&p.robot)],
        }
    }

    /// The robot at step k's start if it has not braked.
    pub fn at(&mut self, p: &SceneParams<Rational>, k: usize) -> &RobotState<Rational> {
        while self.states.len() <= k {
            let last = self.states.last().expect("never empty");
            let next = robot_motion(&p.robot, last).end;
            self.states.push(next);
        }
        &self.states[k]
    }
}
