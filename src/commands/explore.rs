//! `safereach explore` and `safereach export-uppaal`: placeholders, to be written (issue 5).

use std::process::ExitCode;

use anyhow::Result;

/// Arguments of `safereach explore`.
#[derive(clap::Args)]
pub struct ExploreArgs {}

/// Arguments of `safereach export-uppaal`.
#[derive(clap::Args)]
pub struct ExportUppaalArgs {}

/// Runs `safereach explore`.
pub fn run(_args: ExploreArgs) -> Result<ExitCode> {
    anyhow::bail!("explore is not implemented yet")
}

/// Runs `safereach export-uppaal`.
pub fn export_uppaal(_args: ExportUppaalArgs) -> Result<ExitCode> {
    anyhow::bail!("export-uppaal is not implemented yet")
}
