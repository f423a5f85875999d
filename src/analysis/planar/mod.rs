//! The plane's analyser (docs/reductions.md §11; issue 36): lower bounds on the Euclidean
//! separation by anchored relaxation, one second-order cone program per leaf, refined by
//! branch and bound where the bound is lowest.

mod leaf_solve;
mod lower_bound;

pub use leaf_solve::{LeafBound, bound_leaf};
pub use lower_bound::{BoundOptions, LowerBound, LowerBoundError, WorstLeaf, lower_bound};
