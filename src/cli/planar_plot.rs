//! `--plot FILE.svg` of `certify` and `simulate --replay` on planar problems: the
//! certificate's witness replayed and drawn from above (`analysis::report::witness_view`).

use std::path::Path;

use anyhow::Result;

use safereach::analysis::report::witness_view;
use safereach::proof::planar::certificate::PlanarCertificate;

use super::output::write_file;

/// Draws `cert`'s witness into `file` (atomically); `origin` names the certificate in errors.
pub fn plot_witness(cert: &PlanarCertificate, origin: &str, file: &Path) -> Result<()> {
    let svg = witness_view(cert, origin)
        .map_err(anyhow::Error::msg)?
        .ok_or_else(|| anyhow::anyhow!("--plot: {origin} has no witness to draw"))?;
    write_file(file, svg.as_bytes())
}
