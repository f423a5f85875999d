//! One cell's values, read and printed the same way by the page, the findings and both
//! figures, so a number never appears in two spellings.

use crate::analysis::sweep::CellResult;

/// The cell's value on the axis `key`, when it has one and it is a number.
pub(super) fn axis_value(r: &CellResult, key: &str) -> Option<f64> {
    r.axes.get(key).and_then(serde_json::Value::as_f64)
}

/// `x` with `digits` decimals, or a dash when there is none.
pub(super) fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    match x {
        Some(v) => format!("{v:.digits$}"),
        None => "–".into(),
    }
}

/// s* as printed: −∞ when the robot may never stop; for a planar cell whose bracket is too
/// wide to state s*, `≤` the witness's separation (the lower bound has its own column).
pub(super) fn separation(r: &CellResult) -> String {
    if r.never_stops {
        "−∞".into()
    } else if let (None, Some(up)) = (r.min_separation, r.upper_bound) {
        format!("≤ {}", crate::core::show::up(up, 3))
    } else {
        fmt_opt(r.min_separation, 3)
    }
}

/// Monte Carlo record as `collisions / runs` (None when no runs were made).
pub(super) fn collisions_per_runs(r: &CellResult) -> Option<String> {
    match (r.collisions, r.runs) {
        (Some(c), Some(n)) => Some(format!("{c} / {n}")),
        _ => None,
    }
}

/// The distinct values the cells take on the axis `key`, ascending.
pub(super) fn sorted_values(results: &[CellResult], key: &str) -> Vec<f64> {
    let mut v: Vec<f64> = results.iter().filter_map(|r| axis_value(r, key)).collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}
