//! One cell of a planar grid: the base planar problem with the cell's overrides, certified
//! (`analysis::planar::certify_text`, whose certificate `check`'s own code re-verifies before
//! a number is kept), and, with runs asked for, its random planar runs replayed exactly.
//!
//! What a planar cell claims is what its certificate claims: the proved lower bound, the
//! witness's replayed separation as the upper bound, and s* itself only where that bracket
//! is within the certificate's tolerance.

use serde::{Deserialize, Serialize};

use crate::analysis::planar::{MAX_RUN_STEPS, certify_text, planar_monte_carlo};
use crate::analysis::sweep::{CellResult, SweepError};
use crate::core::num::f64_at_least;
use crate::core::planar::PlanarProblem;

/// A planar cell's worst case: the obstacle its witness brings closest, when, and the
/// guard the robot braked on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PlanarClosest {
    /// The obstacle's name.
    pub obstacle: String,
    /// When it is closest (s).
    pub at: f64,
    /// The guard that fired (`danger (name)`, `wrong assumption (name)`, `destination`;
    /// null: the robot never brakes in the witness).
    pub guard: Option<String>,
}

/// The result of planar cell `cell` of a grid whose base is `base_text` (read as from
/// `origin`), its axis values given as `sets` and as `axes`.
pub(crate) fn planar_cell(
    cell: usize,
    axes: serde_json::Map<String, serde_json::Value>,
    (base_text, origin): (&str, &str),
    sets: &[String],
    problem: &PlanarProblem,
    (runs, seed): (usize, u64),
) -> Result<CellResult, SweepError> {
    let (_, cert) = certify_text(base_text, origin, sets).map_err(|e| SweepError::Analysis {
        cell,
        reason: e.to_string(),
    })?;
    let mc = (runs > 0).then(|| planar_monte_carlo(&problem.params(), runs, seed, MAX_RUN_STEPS));
    let closest = cert.witness.as_ref().map(|w| PlanarClosest {
        obstacle: w.obstacle.clone(),
        at: w.closest_at,
        guard: w.guard.clone(),
    });
    Ok(CellResult {
        cell,
        axes,
        verdict: cert.verdict,
        min_separation: cert.min_separation,
        never_stops: false,
        lower_bound: Some(cert.lower_bound),
        collisions: mc.as_ref().map(|m| m.collisions),
        runs: mc.as_ref().map(|m| m.runs),
        simulated_min_separation: mc.as_ref().and_then(|m| {
            m.closest
                .as_ref()
                .map(|c| f64_at_least(&c.separation.upper))
        }),
        pieces: cert.leaves(),
        programs: cert.programs,
        worst: None,
        upper_bound: cert.upper_bound,
        closest,
    })
}
