//! The plane's analyser (docs/reductions.md §11; issue 36): lower bounds on the Euclidean
//! separation by anchored relaxation, one second-order cone program per leaf, refined by
//! branch and bound where the bound is lowest.

mod boundary;
mod certificate;
mod certify;
mod knobs;
mod leaf_solve;
mod lower_bound;
mod monte_carlo;
mod pursuit;
mod region;
mod trace;
mod witness;

pub use boundary::{
    BoundaryError, PlanarBoundary, PlanarProbe, Safer, TOLERANCE, Work, answer_text, certify_at,
    certify_text, planar_boundary,
};
pub use certificate::{ProblemText, planar_certificate};
pub use certify::{PlanarAnswer, PlanarVerdict, bound_planar, certify_planar};
pub use knobs::{KnobError, RESOLUTION, max_speed_search, safe_radius_search, speed_keys};
pub use leaf_solve::{LeafBound, bound_leaf};
pub use lower_bound::{BoundOptions, LowerBound, LowerBoundError, WorstLeaf, lower_bound};
pub use monte_carlo::{
    ClosestRun, MAX_RUN_STEPS, PlanarMonteCarlo, planar_monte_carlo, random_run,
};
pub use region::PlanarRegion;
pub use trace::{PlanarTraceRow, planar_trace};
pub use witness::{Witness, witness};
