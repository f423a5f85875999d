//! Verdict colours, shared by the heat map's tiles and legend and the curve plot's dots and
//! line: refuted cells shade from pale to red with their Monte Carlo collision rate.

use crate::analysis::Verdict;
use crate::analysis::sweep::CellResult;

/// Certified cells, and the safe-radius curve drawn through them.
pub(super) const CERTIFIED: &str = "#3b6fb6";
const INCONCLUSIVE: &str = "#a0a0a0";
const NO_COLLISIONS: &str = "#f3e79b";
const UNDER_10: &str = "#f6c35b";
const UNDER_30: &str = "#ee8a3a";
const AT_LEAST_30: &str = "#d64b2b";
/// Where no radius is certified.
pub(super) const NONE: &str = "#c53030";

/// Each colour a cell can take and what it means, in legend order.
pub(super) const LEGEND: [(&str, &str); 6] = [
    (CERTIFIED, "certified"),
    (NO_COLLISIONS, "refuted, 0 collisions"),
    (UNDER_10, "refuted, < 10%"),
    (UNDER_30, "refuted, < 30%"),
    (AT_LEAST_30, "refuted, ≥ 30%"),
    (INCONCLUSIVE, "inconclusive"),
];

/// The cell's colour: its verdict, and for refuted cells the share of runs that collided
/// (without runs, the middle shade).
pub(super) fn color(r: &CellResult) -> &'static str {
    match r.verdict {
        Verdict::Certified => CERTIFIED,
        Verdict::Inconclusive => INCONCLUSIVE,
        Verdict::Refuted => match (r.collisions, r.runs) {
            (Some(c), Some(n)) if n > 0 => {
                let f = c as f64 / n as f64;
                if f == 0.0 {
                    NO_COLLISIONS
                } else if f < 0.1 {
                    UNDER_10
                } else if f < 0.3 {
                    UNDER_30
                } else {
                    AT_LEAST_30
                }
            }
            _ => UNDER_30,
        },
    }
}
