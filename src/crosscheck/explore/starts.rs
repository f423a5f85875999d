//! The explorer's init-state choice for a range of initial gaps: a finite set of starts in
//! [g_min, g_max], both ends included, chosen like `--speeds` (the environment picks one;
//! the exploration covers exactly these, as it covers exactly the speeds of its set).

use super::ExploreError;
use crate::core::model::Params;
use crate::core::num::Exact;

/// Starts explored in a range of initial gaps unless `--starts` says otherwise.
pub const DEFAULT_STARTS: usize = 5;

/// Largest `--starts N` accepted (each start is a search of its own size).
pub const MAX_STARTS: usize = 1000;

/// `n` evenly spaced initial gaps from g_min to g_max, both included (n ≥ 2); a single
/// initial gap is the only start whatever `n`.
pub fn starts(p: &Params<Exact>, n: usize) -> Result<Vec<Exact>, ExploreError> {
    if !(2..=MAX_STARTS).contains(&n) {
        return Err(ExploreError::Options(format!(
            "--starts must be between 2 (both ends of the range) and {MAX_STARTS}; got {n}"
        )));
    }
    if !p.gap_is_range() {
        return Ok(vec![p.g0.clone()]);
    }
    let step = (p.g0_max.clone() - p.g0.clone()) / Exact::from(n - 1);
    Ok((0..n)
        .map(|i| p.g0.clone() + step.clone() * Exact::from(i))
        .collect())
}
