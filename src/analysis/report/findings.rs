//! The seed paper's findings checked against a sweep's cells: (a) small radii collide under
//! the assumption, (b) fast obstacles beat the largest radius, (c) a suitable radius is safe
//! beyond the assumption; and whether simulation agrees with the certificates.

use std::fmt::Write as _;

use super::cells::axis_value;
use super::{ASSUMED_KEY, RADIUS_KEY, SPEED_KEY};
use crate::analysis::Verdict;
use crate::analysis::sweep::CellResult;

/// The findings section as a Markdown list (`assumed`: the controller's assumed speed V_a).
pub(super) fn findings(results: &[CellResult], assumed: Option<f64>) -> String {
    let Some(va) = assumed else {
        return "The grid has no obstacle-speed axis; the paper's findings are not applicable.\n"
            .into();
    };
    let mut s = String::new();
    paper_findings(&mut s, results, va);
    simulation_agreement(&mut s, results);
    missed_worst_cases(&mut s, results);
    s
}

/// A cell named by its axis values, e.g. `(W = 0.25, ρ = 1.2)` (the assumed speed left out).
fn cell_name(r: &CellResult) -> String {
    let parts: Vec<String> = r
        .axes
        .iter()
        .filter(|(k, _)| k.as_str() != ASSUMED_KEY)
        .map(|(k, v)| {
            let short = match k.as_str() {
                SPEED_KEY => "W",
                RADIUS_KEY => "ρ",
                other => other,
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
fn paper_findings(s: &mut String, results: &[CellResult], va: f64) {
    let speed = |r: &CellResult| axis_value(r, SPEED_KEY);
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
            "(a) Too small a reaction radius collides even when the assumption holds (W ≤ V_a = {va})"
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
        "(c) A suitable radius keeps the robot safe beyond its assumption (W > V_a certified)",
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
