//! One concrete choice of the planar adversary (docs/semantics.md §13.2–§13.3): per obstacle
//! a start, a velocity per step, the observation errors and whether it hides, validated
//! exactly against the problem's bounds before any replay reads it.

use std::fmt;

use crate::core::num::Exact;
use crate::core::plane::point::Point;

use super::params::{PlanarObstacle, PlanarParams, Start};

/// What every obstacle does in one behaviour.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct PlanarBehaviour {
    /// One entry per obstacle of the problem, in its order.
    pub obstacles: Vec<ObstacleBehaviour>,
}

/// What one obstacle does.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleBehaviour {
    /// Its centre at t = 0: the problem's point, or a point of its box.
    pub start: Point,
    /// Its constant velocity in step k, for k = 0, 1, …; past the list it stands still.
    pub velocities: Vec<Point>,
    /// The error added to the centre seen at the observation of step k (‖e‖ ≤ σ_p); past
    /// the list 0.
    pub position_errors: Vec<Point>,
    /// The error added to the velocity seen at the observation of step k (‖e‖ ≤ σ_w); past
    /// the list 0.
    pub velocity_errors: Vec<Point>,
    /// It stays unseen for as long as occlusion allows: until its separation first falls
    /// to d_det (needs `sensing.first_detection`).
    pub hide: bool,
}

impl ObstacleBehaviour {
    /// An obstacle starting at `start` with these velocities, seen exactly, not hiding.
    pub fn moving(start: Point, velocities: Vec<Point>) -> Self {
        ObstacleBehaviour {
            start,
            velocities,
            position_errors: Vec::new(),
            velocity_errors: Vec::new(),
            hide: false,
        }
    }

    /// Its velocity in step k (0 past the list).
    pub fn velocity(&self, k: usize) -> Point {
        self.velocities
            .get(k)
            .cloned()
            .unwrap_or_else(Point::origin)
    }

    /// The position error of the observation at step k (0 past the list).
    pub fn position_error(&self, k: usize) -> Point {
        self.position_errors
            .get(k)
            .cloned()
            .unwrap_or_else(Point::origin)
    }

    /// The velocity error of the observation at step k (0 past the list).
    pub fn velocity_error(&self, k: usize) -> Point {
        self.velocity_errors
            .get(k)
            .cloned()
            .unwrap_or_else(Point::origin)
    }
}

/// Why a behaviour is not one the problem allows (obstacles and steps numbered from 0).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BehaviourError {
    /// The behaviour lists a different number of obstacles than the problem.
    ObstacleCount {
        /// The problem's.
        expected: usize,
        /// The behaviour's.
        found: usize,
    },
    /// The start is not the problem's point, or not in its box.
    Start(usize),
    /// A velocity's norm exceeds W_i.
    TooFast {
        /// The obstacle.
        obstacle: usize,
        /// The step.
        step: usize,
    },
    /// A velocity is not w·d with w ∈ [0, W_i] for the obstacle's fixed direction d.
    OffDirection {
        /// The obstacle.
        obstacle: usize,
        /// The step.
        step: usize,
    },
    /// An observation error exceeds σ_p (position) or σ_w (velocity).
    Noise {
        /// The obstacle.
        obstacle: usize,
        /// The step whose observation it is.
        step: usize,
    },
    /// The obstacle is outside its region at the start of this step.
    LeavesRegion {
        /// The obstacle.
        obstacle: usize,
        /// The step.
        step: usize,
    },
    /// It hides, but the problem has no occlusion (`first_detection`).
    HidesWithoutOcclusion(usize),
}

impl fmt::Display for BehaviourError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BehaviourError::ObstacleCount { expected, found } => write!(
                f,
                "the problem has {expected} obstacles, the behaviour {found}"
            ),
            BehaviourError::Start(i) => {
                write!(f, "obstacle {i} does not start at its point or in its box")
            }
            BehaviourError::TooFast { obstacle, step } => write!(
                f,
                "obstacle {obstacle} is faster than its bound in step {step}"
            ),
            BehaviourError::OffDirection { obstacle, step } => write!(
                f,
                "obstacle {obstacle} leaves its direction or speed range in step {step}"
            ),
            BehaviourError::Noise { obstacle, step } => write!(
                f,
                "an observation error of obstacle {obstacle} at step {step} exceeds its bound"
            ),
            BehaviourError::LeavesRegion { obstacle, step } => write!(
                f,
                "obstacle {obstacle} is outside its region at the start of step {step}"
            ),
            BehaviourError::HidesWithoutOcclusion(i) => write!(
                f,
                "obstacle {i} hides but the problem has no first_detection"
            ),
        }
    }
}

impl std::error::Error for BehaviourError {}

impl PlanarBehaviour {
    /// Checks everything that does not depend on the replay (the region is checked at every
    /// step start as the replay reaches it): the start, every listed velocity and error.
    pub fn validate(&self, params: &PlanarParams) -> Result<(), BehaviourError> {
        if self.obstacles.len() != params.obstacles.len() {
            return Err(BehaviourError::ObstacleCount {
                expected: params.obstacles.len(),
                found: self.obstacles.len(),
            });
        }
        let s = &params.sensing;
        for (i, (b, o)) in self.obstacles.iter().zip(&params.obstacles).enumerate() {
            if !starts_in(&o.start, &b.start) {
                return Err(BehaviourError::Start(i));
            }
            for (k, u) in b.velocities.iter().enumerate() {
                velocity_allowed(o, u).map_err(|off| off.at(i, k))?;
            }
            let bounded = |errors: &[Point], sigma: &Exact| {
                let sigma2 = sigma * sigma;
                match errors.iter().position(|e| e.norm_squared() > sigma2) {
                    Some(k) => Err(BehaviourError::Noise {
                        obstacle: i,
                        step: k,
                    }),
                    None => Ok(()),
                }
            };
            bounded(&b.position_errors, &s.position_noise)?;
            bounded(&b.velocity_errors, &s.velocity_noise)?;
            if b.hide && s.first_detection.is_none() {
                return Err(BehaviourError::HidesWithoutOcclusion(i));
            }
        }
        Ok(())
    }
}

/// Whether `at` is the start's point, or in its box.
fn starts_in(start: &Start, at: &Point) -> bool {
    match start {
        Start::At(p) => p == at,
        Start::Box { min, max } => min.x <= at.x && at.x <= max.x && min.y <= at.y && at.y <= max.y,
    }
}

/// How a velocity breaks its obstacle's bound.
pub(super) enum Off {
    Fast,
    Direction,
}

impl Off {
    /// The error for obstacle `obstacle` in step `step`.
    pub(super) fn at(self, obstacle: usize, step: usize) -> BehaviourError {
        match self {
            Off::Fast => BehaviourError::TooFast { obstacle, step },
            Off::Direction => BehaviourError::OffDirection { obstacle, step },
        }
    }
}

/// ‖u‖ ≤ W (free direction), or u = w·d with w ∈ [0, W] (fixed: d is a unit vector, so u is
/// on its ray iff u × d = 0 and u·d ≥ 0, and then w = u·d).
pub(super) fn velocity_allowed(o: &PlanarObstacle, u: &Point) -> Result<(), Off> {
    match &o.direction {
        None => {
            if u.norm_squared() > &o.max_speed * &o.max_speed {
                return Err(Off::Fast);
            }
        }
        Some(d) => {
            let w = u.dot(d.unit());
            if u.cross(d.unit()) != Exact::ZERO || w < Exact::ZERO {
                return Err(Off::Direction);
            }
            if w > o.max_speed {
                return Err(Off::Fast);
            }
        }
    }
    Ok(())
}
