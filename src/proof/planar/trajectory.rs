//! The robot's motion along its path when it brakes at a given step (docs/reductions.md
//! §11: c^T(t), s^T(t), τ_T), exact at rational instants.
//!
//! Before its brake step the robot follows the drive profile whatever the obstacles do
//! (reductions.md Lemma 1 holds in the plane: the motion rules never read an obstacle);
//! from it, it brakes at the plant's b_min until it rests. The destination guard (when the
//! path ends) brakes it at the first step whose stopping point with the controller's b
//! reaches the end (semantics.md §11.4 along the arc length), so no brake step lies beyond.

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::plane::point::Point;
use crate::core::plane::rational_path::RationalPath;
use crate::core::semantics::{Mode, RobotState, robot_motion, state_within};

/// The drive profile at step starts (no brake), grown on demand.
#[derive(Clone, Debug)]
pub struct DriveProfile {
    motion: Params<Exact>,
    starts: Vec<RobotState<Exact>>,
    /// The destination guard's step, once found (None: not yet, or the path has no end).
    destination: Option<usize>,
    goal: Option<Exact>,
}

impl DriveProfile {
    /// The profile of `motion`; `goal` is the path's length when it ends.
    pub fn new(motion: Params<Exact>, goal: Option<Exact>) -> Self {
        let first = RobotState::initial(&motion);
        DriveProfile {
            motion,
            starts: vec![first],
            destination: None,
            goal,
        }
    }

    /// The motion's numbers.
    pub fn motion(&self) -> &Params<Exact> {
        &self.motion
    }

    /// The robot's state at the start of step k along the drive profile.
    pub fn start(&mut self, k: usize) -> &RobotState<Exact> {
        while self.starts.len() <= k {
            let last = self.starts.last().expect("never empty");
            let next = robot_motion(&self.motion, last).end;
            self.starts.push(next);
        }
        &self.starts[k]
    }

    /// Whether the destination guard fires at step k on the drive profile: the stopping
    /// point with the controller's b reaches the path's end.
    fn destination_fires(&mut self, k: usize) -> bool {
        let Some(goal) = self.goal.clone() else {
            return false;
        };
        let b = self.motion.b.clone();
        let s = self.start(k);
        let stop = &s.position + &(&s.speed * &s.speed / (Exact::from(2) * b));
        stop >= goal
    }

    /// The destination guard's step: the last possible brake step (None: the path has no
    /// end). `limit` bounds the search; a path that ends is reached in finitely many steps
    /// because the profile's speed is ≥ a·dt after the first step, or the start speed.
    pub fn destination_step(&mut self, limit: usize) -> Option<usize> {
        if let Some(k) = self.destination {
            return Some(k);
        }
        self.goal.as_ref()?;
        let k = (0..=limit).find(|&k| self.destination_fires(k))?;
        self.destination = Some(k);
        Some(k)
    }
}

/// The robot's motion when it brakes at `brake` (None: never).
#[derive(Clone, Debug)]
pub struct BrakeTrajectory {
    /// The brake step.
    pub brake: Option<usize>,
    /// The state at the brake step's start (the profile's), when it brakes.
    pub at_brake: Option<RobotState<Exact>>,
    /// The rest instant τ_T (None: never rests).
    pub rest: Option<Exact>,
}

impl BrakeTrajectory {
    /// The trajectory with brake step `brake` on `profile`.
    pub fn new(profile: &mut DriveProfile, brake: Option<usize>) -> Self {
        let at_brake = brake.map(|k| profile.start(k).clone());
        let rest = match (brake, &at_brake) {
            (Some(k), Some(s)) => {
                let m = profile.motion();
                Some(Exact::from(k) * &m.dt + &s.speed / &m.b_min)
            }
            _ => None,
        };
        BrakeTrajectory {
            brake,
            at_brake,
            rest,
        }
    }

    /// The robot's arc length and speed at instant `t` ≥ 0 (clamped at rest after τ_T).
    pub fn state_at(&self, profile: &mut DriveProfile, t: &Exact) -> RobotState<Exact> {
        let dt = profile.motion().dt.clone();
        let step = floor_steps(t, &dt);
        match (self.brake, &self.at_brake) {
            (Some(k), Some(s)) if step >= k => {
                // Braking is one closed form from the brake step on (b_min throughout),
                // so the instant need not be cut into periods.
                let b = &profile.motion().b_min;
                let tau = t - Exact::from(k) * &dt;
                let stop = &s.speed / b;
                let tau = if tau < stop { tau } else { stop };
                let lost = b * &tau;
                RobotState {
                    position: &s.position + &(&s.speed * &tau) - &lost * &tau / Exact::from(2),
                    speed: &s.speed - &lost,
                    mode: Mode::Brake,
                }
            }
            _ => {
                let start = profile.start(step).clone();
                let tau = t - Exact::from(step) * &dt;
                state_within(profile.motion(), &start, &tau)
            }
        }
    }

    /// The robot's centre at `t` on `path`.
    pub fn centre_at(&self, profile: &mut DriveProfile, path: &RationalPath, t: &Exact) -> Point {
        path.point_at(&self.state_at(profile, t).position)
    }
}

/// ⌊t / dt⌋ for t ≥ 0.
pub(crate) fn floor_steps(t: &Exact, dt: &Exact) -> usize {
    usize::try_from((t / dt).floor()).unwrap_or(0)
}
