//! What the environment shows the robot of a scene's obstacles in a replay: occlusion (each
//! obstacle hidden until a step) and the errors of single observations (docs/semantics.md
//! §12, for every obstacle of a scene alike). A plan is data, so a witness can carry it and
//! `check` can hold it to the premises.

use std::collections::BTreeMap;

use crate::core::num::Scalar;
use crate::core::semantics::Observation;

/// The robot's observations in one run, as the environment chose them.
#[derive(Clone, Debug, PartialEq)]
pub struct ObservationPlan<N> {
    /// Per obstacle, the first step whose start shows it (0: seen from the start); the
    /// observations at earlier step starts show nothing.
    pub hidden_until: Vec<usize>,
    /// Errors (gap, speed) of obstacle i's observation at step k's start, keyed (i, k); every
    /// other observation is exact.
    pub errors: BTreeMap<(usize, usize), (N, N)>,
}

impl<N: Scalar> ObservationPlan<N> {
    /// Exact observations of `obstacles` obstacles, all visible from the start.
    pub fn exact(obstacles: usize) -> Self {
        ObservationPlan {
            hidden_until: vec![0; obstacles],
            errors: BTreeMap::new(),
        }
    }

    /// Whether the plan hides nothing and makes no error.
    pub fn is_exact(&self) -> bool {
        self.errors.is_empty() && self.hidden_until.iter().all(|&h| h == 0)
    }

    /// What the robot is shown at step k's start of obstacle i, whose true observation is
    /// `truth`.
    pub fn shown(&self, i: usize, k: usize, truth: Observation<N>) -> Option<Observation<N>> {
        if k < self.hidden_until[i] {
            return None;
        }
        Some(match self.errors.get(&(i, k)) {
            Some((eg, ew)) => Observation {
                gap: truth.gap + eg.clone(),
                speed: truth.speed + ew.clone(),
            },
            None => truth,
        })
    }

    /// The same plan in another number type.
    pub fn map<M: Scalar>(&self, f: impl Fn(&N) -> M) -> ObservationPlan<M> {
        ObservationPlan {
            hidden_until: self.hidden_until.clone(),
            errors: self
                .errors
                .iter()
                .map(|(&key, (g, w))| (key, (f(g), f(w))))
                .collect(),
        }
    }
}
