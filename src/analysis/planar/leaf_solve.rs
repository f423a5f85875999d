//! One leaf's program solved by Clarabel and bounded exactly: the solver proposes dual
//! multipliers, `proof::program` turns them into a rational lower bound (or a Farkas proof
//! that the leaf is empty). A solver failure is reported, never read as a bound.

use crate::analysis::analyse::WITNESS_MARGIN;
use crate::analysis::lp::{LpOutcome, solve};
use crate::core::num::Exact;
use crate::proof::planar::leaf::Leaf;

/// What one leaf proves.
#[derive(Clone, Debug, PartialEq)]
pub enum LeafBound {
    /// No behaviour reaches the leaf (its program is proved empty): the Farkas
    /// multipliers (none: one row no point of the box meets).
    Empty(Vec<f64>),
    /// Every behaviour in the leaf separates by at least `lower`.
    Lower {
        /// The exact bound.
        lower: Exact,
        /// The solver's optimum (a float, ≥ `lower` up to the solver's gap).
        value: f64,
        /// The optimum's point: distance, p, x, y (and the fixed-direction distances).
        point: Vec<f64>,
        /// The dual multipliers that prove `lower`.
        multipliers: Vec<f64>,
    },
    /// The solver gave no usable answer (its status).
    Failed(String),
}

/// Solves `leaf` and bounds it exactly.
pub fn bound_leaf(leaf: &Leaf) -> LeafBound {
    let program = leaf.program();
    if program.infeasible_row().is_some() {
        return LeafBound::Empty(Vec::new()); // one row no point of the box meets
    }
    match solve(&program, 0.0) {
        LpOutcome::Optimal { x, z, value } => match program.bound(&z, true) {
            Some(lower) => LeafBound::Lower {
                lower,
                value,
                point: x,
                multipliers: z,
            },
            None => LeafBound::Failed("unusable multipliers".into()),
        },
        LpOutcome::Infeasible { z } => match program.proves_empty(&z) {
            Some(_) => LeafBound::Empty(z),
            None => LeafBound::Failed("infeasible without an exact Farkas proof".into()),
        },
        LpOutcome::Failed { status } => LeafBound::Failed(status),
    }
}

/// Whether `leaf` is empty once its strict rows are strict: the closure may hold only on a
/// guard's very threshold, where the guard fires (a static obstacle exactly at the reaction
/// distance). The solver proposes a Farkas certificate with the strict rows moved inside;
/// `proof::program` checks it exactly. Returns the proof's multipliers (none: one row no
/// point of the box meets).
pub fn strictly_empty(leaf: &Leaf) -> Option<Vec<f64>> {
    let program = leaf.program();
    if program.infeasible_row().is_some() {
        return Some(Vec::new());
    }
    match solve(&program, WITNESS_MARGIN) {
        LpOutcome::Infeasible { z } => program.proves_empty(&z).is_some().then_some(z),
        _ => None,
    }
}
