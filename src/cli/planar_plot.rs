//! `--plot FILE.svg` of `certify` and `simulate --replay` on planar problems: the
//! certificate's witness replayed and drawn from above (`analysis::report::top_view`).

use std::path::Path;

use anyhow::Result;

use safereach::analysis::planar::planar_trace;
use safereach::analysis::report::{TopViewLabels, top_view};
use safereach::core::planar::PlanarProblem;
use safereach::proof::planar::certificate::PlanarCertificate;
use safereach::proof::planar::witness_record;

use super::output::write_file;

/// Draws `cert`'s witness into `file` (atomically); `origin` names the certificate in errors.
pub fn plot_witness(cert: &PlanarCertificate, origin: &str, file: &Path) -> Result<()> {
    let problem = PlanarProblem::from_toml_str_with_overrides(
        &cert.problem_toml,
        &format!("{origin} (its problem)"),
        &cert.overrides,
    )?;
    let params = problem.params();
    let witness = cert
        .witness
        .as_ref()
        .ok_or_else(|| anyhow::anyhow!("--plot: {origin} has no witness to draw"))?;
    let behaviour = witness_record::behaviour(&params, witness)
        .map_err(|e| anyhow::anyhow!("{origin}: the witness: {e}"))?;
    let (rows, _) = planar_trace(&params, &behaviour, witness.steps)
        .map_err(|e| anyhow::anyhow!("{origin}: the witness: {e}"))?;
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
    write_file(file, top_view(&params, &rows, &labels).as_bytes())
}
