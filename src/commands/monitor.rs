//! `safereach monitor`: placeholder, to be written (issue 4).

use std::process::ExitCode;

use anyhow::Result;

/// Arguments of `safereach monitor`.
#[derive(clap::Args)]
pub struct MonitorArgs {}

/// Runs `safereach monitor`.
pub fn run(_args: MonitorArgs) -> Result<ExitCode> {
    anyhow::bail!("monitor is not implemented yet")
}
