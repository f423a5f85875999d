//! A planar report's worst cases seen from above: the cell whose witness comes closest
//! among the refuted cells, and the one with the least proved margin among the certified
//! cells, each certified again (its certificate checked by `check`'s own code) and its
//! witness replayed exactly and drawn by [`top_view`]. Also the drawing of any planar
//! certificate's witness, which `certify --plot` and `simulate --replay --plot` write.

use super::top_view::{TopViewLabels, top_view};
use crate::analysis::Verdict;
use crate::analysis::planar::{certify_text, planar_trace};
use crate::analysis::sweep::{CellResult, Grid};
use crate::core::planar::PlanarProblem;
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::planar::witness_record;

/// One worst case of a planar grid, drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarView {
    /// The cell.
    pub cell: usize,
    /// Its verdict.
    pub verdict: Verdict,
    /// The figure's file name.
    pub file: String,
    /// The figure.
    pub svg: String,
}

/// The top view of `cert`'s witness (None: it has none); `origin` names the certificate in
/// errors.
pub fn witness_view(cert: &PlanarCertificate, origin: &str) -> Result<Option<String>, String> {
    let Some(witness) = cert.witness.as_ref() else {
        return Ok(None);
    };
    let problem = PlanarProblem::from_toml_str_with_overrides(
        &cert.problem_toml,
        &format!("{origin} (its problem)"),
        &cert.overrides,
    )
    .map_err(|e| e.to_string())?;
    let params = problem.params();
    let behaviour = witness_record::behaviour(&params, witness)
        .map_err(|e| format!("{origin}: the witness: {e}"))?;
    let (rows, _) = planar_trace(&params, &behaviour, witness.steps)
        .map_err(|e| format!("{origin}: the witness: {e}"))?;
    let closest = params
        .obstacles
        .iter()
        .position(|o| o.name == witness.obstacle)
        .map(|i| (i, witness.closest_at, cert.upper_bound.unwrap_or(f64::NAN)));
    let title = format!(
        "{}: {} (planar), worst case seen from above",
        cert.problem,
        cert.verdict.as_str()
    );
    let labels = TopViewLabels {
        title: &title,
        closest,
        brake_step: witness.brake_step,
    };
    Ok(Some(top_view(&params, &rows, &labels)))
}

/// The worst cases of a planar grid's `results` drawn (nothing for other grids): the
/// refuted cell with the least replayed separation, and the certified cell with the least
/// proved lower bound.
pub fn planar_views(grid: &Grid, results: &[CellResult]) -> Result<Vec<PlanarView>, String> {
    if grid.kind != crate::core::grid::BaseKind::Planar {
        return Ok(Vec::new());
    }
    let least = |verdict: Verdict, key: fn(&CellResult) -> Option<f64>| {
        results
            .iter()
            .filter(|r| r.verdict == verdict)
            .filter_map(|r| key(r).map(|k| (k, r)))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cell.cmp(&b.1.cell)))
            .map(|(_, r)| r)
    };
    let picks = [
        least(Verdict::Refuted, |r| r.upper_bound),
        least(Verdict::Certified, |r| r.lower_bound),
    ];
    let origin = grid.base_path.display().to_string();
    let mut views = Vec::new();
    for r in picks.into_iter().flatten() {
        let sets: Vec<String> = grid
            .cell_values(r.cell)
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        let (_, cert) = certify_text(&grid.base_text, &origin, &sets)
            .map_err(|e| format!("cell {}: {e}", r.cell))?;
        let cell_origin = format!("cell {} of {}", r.cell, grid.path.display());
        if let Some(svg) = witness_view(&cert, &cell_origin)? {
            views.push(PlanarView {
                cell: r.cell,
                verdict: cert.verdict,
                file: format!("{}-cell-{}-top.svg", grid.name, r.cell),
                svg,
            });
        }
    }
    Ok(views)
}
