//! The seed paper's findings checked against a sweep's cells: (a) small radii collide under
//! the assumption, (b) fast obstacles beat the largest radius, (c) a suitable radius is safe
//! beyond the assumption; whether simulation agrees with the certificates; and for a scene
//! grid, which obstacle is the worst case in which cells, in which lane, and why.

use std::fmt::Write as _;

use super::axes::{is_speed_bound, obstacle_field};
use super::cells::{axis_value, separation};
use super::{ASSUMED_KEY, RADIUS_KEY};
use crate::analysis::Verdict;
use crate::analysis::sweep::CellResult;

/// Cells listed by name in a scene's worst-case lines before the rest are counted.
const LISTED: usize = 8;

/// The findings section as a Markdown list: `speed` is the obstacle speed-bound axis (W, or
/// a scene obstacle's W_i), `assumed` the controller's assumed speed V_a.
pub(super) fn findings(
    results: &[CellResult],
    speed: Option<&str>,
    assumed: Option<f64>,
) -> String {
    let (Some(speed), Some(va)) = (speed, assumed) else {
        return "The grid has no obstacle-speed axis; the paper's findings are not applicable.\n"
            .into();
    };
    let mut s = String::new();
    paper_findings(&mut s, results, speed, va);
    simulation_agreement(&mut s, results);
    missed_worst_cases(&mut s, results);
    s
}

/// A cell named by its axis values, e.g. `(W = 0.25, ρ = 1.2)` or `(W_1 = 0.3, ρ = 1.2)`
/// (the assumed speed left out).
fn cell_name(r: &CellResult) -> String {
    let parts: Vec<String> = r
        .axes
        .iter()
        .filter(|(k, _)| k.as_str() != ASSUMED_KEY)
        .map(|(k, v)| {
            let short = match (k.as_str(), obstacle_field(k)) {
                (RADIUS_KEY, _) => "ρ".to_string(),
                (_, Some((i, _))) if is_speed_bound(k) => format!("W_{i}"),
                (other, _) if is_speed_bound(other) => "W".to_string(),
                (other, _) => other.to_string(),
            };
            format!("{short} = {v}")
        })
        .collect();
    format!("({})", parts.join(", "))
}

fn list(cells: &[&CellResult]) -> String {
    let names: Vec<String> = cells.iter().map(|r| cell_name(r)).collect();
    names.join(", ")
}

fn select(results: &[CellResult], keep: impl Fn(&CellResult) -> bool) -> Vec<&CellResult> {
    results.iter().filter(|r| keep(r)).collect()
}

/// Findings (a), (b) and (c): each holds when some cell shows it.
fn paper_findings(s: &mut String, results: &[CellResult], key: &str, va: f64) {
    let speed = |r: &CellResult| axis_value(r, key);
    let w = match obstacle_field(key) {
        Some((i, _)) => format!("W_{i}"),
        None => "W".to_string(),
    };
    let rho = |r: &CellResult| axis_value(r, RADIUS_KEY);
    let max_rho = results
        .iter()
        .filter_map(rho)
        .fold(f64::NEG_INFINITY, f64::max);
    let refuted = |r: &CellResult| r.verdict == Verdict::Refuted;
    let a = select(results, |r| speed(r).is_some_and(|w| w <= va) && refuted(r));
    let b = select(results, |r| rho(r) == Some(max_rho) && refuted(r));
    let c = select(results, |r| {
        speed(r).is_some_and(|w| w > va) && r.verdict == Verdict::Certified
    });
    finding(
        s,
        &format!(
            "(a) Too small a reaction radius collides even when the assumption holds ({w} ≤ V_a = {va})"
        ),
        &a,
        "refuted",
    );
    finding(
        s,
        &format!("(b) Too fast an obstacle collides even with the largest radius (ρ = {max_rho})"),
        &b,
        "refuted",
    );
    finding(
        s,
        &format!(
            "(c) A suitable radius keeps the robot safe beyond its assumption ({w} > V_a certified)"
        ),
        &c,
        "certified",
    );
}

/// One finding's line: the claim, whether it holds, and the cells that show it.
fn finding(s: &mut String, claim: &str, cells: &[&CellResult], kind: &str) {
    let (verdict, shown) = if cells.is_empty() {
        ("**does not hold on this grid**", String::new())
    } else {
        ("**holds**", format!(" — {kind} cells {}", list(cells)))
    };
    let _ = writeln!(s, "- {claim}: {verdict}{shown}.");
}

/// Whether any certified cell collided in its Monte Carlo runs (that would be a bug).
fn simulation_agreement(s: &mut String, results: &[CellResult]) {
    let simulated: Vec<&CellResult> = results
        .iter()
        .filter(|r| r.verdict == Verdict::Certified && r.runs.is_some())
        .collect();
    let collided: Vec<&CellResult> = simulated
        .iter()
        .filter(|r| r.collisions.unwrap_or(0) > 0)
        .copied()
        .collect();
    if simulated.is_empty() {
        let _ = writeln!(
            s,
            "- No Monte Carlo runs were made, so simulation cannot confirm the certificates here."
        );
    } else if collided.is_empty() {
        let runs: usize = simulated.iter().filter_map(|r| r.runs).sum();
        let _ = writeln!(
            s,
            "- No certified cell ever collided in simulation ({} certified cells, {runs} runs in all).",
            simulated.len()
        );
    } else {
        let _ = writeln!(
            s,
            "- **A certified cell collided in simulation: {}. This is a bug; report it.**",
            list(&collided)
        );
    }
}

/// Refuted cells whose random runs never collided: Monte Carlo is no proof of safety.
fn missed_worst_cases(s: &mut String, results: &[CellResult]) {
    let missed: Vec<&CellResult> = results
        .iter()
        .filter(|r| r.verdict == Verdict::Refuted && r.collisions == Some(0))
        .collect();
    if !missed.is_empty() {
        let _ = writeln!(
            s,
            "- Random simulation misses worst cases: {} refuted cells never collided in their runs ({}). \
             A clean Monte Carlo record is no proof of safety.",
            missed.len(),
            list(&missed)
        );
    }
}

/// A scene grid's worst cases: for each (obstacle, lane, cause), the cells where it is the
/// worst case; then the cell with the least s*.
pub(super) fn scene_worst_cases(results: &[CellResult]) -> String {
    let mut s = String::new();
    let mut groups: Vec<(String, Vec<&CellResult>)> = Vec::new();
    for r in results {
        let what = match &r.worst {
            Some(w) => w.describe(),
            None => "no worst case was found (nothing in reach, or nothing realised)".into(),
        };
        match groups.iter_mut().find(|(d, _)| *d == what) {
            Some((_, cells)) => cells.push(r),
            None => groups.push((what, vec![r])),
        }
    }
    for (what, cells) in &groups {
        let shown: Vec<&CellResult> = cells.iter().take(LISTED).copied().collect();
        let more = match cells.len() - shown.len() {
            0 => String::new(),
            n => format!(" and {n} more"),
        };
        let _ = writeln!(
            s,
            "- {what} — {} of {} cells: {}{more}.",
            cells.len(),
            results.len(),
            list(&shown)
        );
    }
    let least = results
        .iter()
        .filter(|r| r.never_stops || r.min_separation.is_some())
        .min_by(|a, b| {
            let key = |r: &CellResult| {
                if r.never_stops {
                    f64::NEG_INFINITY
                } else {
                    r.min_separation.unwrap_or(f64::INFINITY)
                }
            };
            key(a).total_cmp(&key(b))
        });
    if let Some(r) = least {
        let why = r
            .worst
            .as_ref()
            .map(|w| format!(": {}", w.describe()))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "- The least s* on the grid is {} m, at cell {} {} ({}){why}.",
            separation(r),
            r.cell,
            cell_name(r),
            r.verdict.as_str()
        );
    }
    s
}
