//! `safereach max-speed`: the largest obstacle speed bound that is still certified for the
//! problem's reaction radius — where certification ends along W.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};

use safereach::analysis::radius;

use super::boundary::{answer, certificate_text};
use super::exit::Exit;
use super::input;
use super::output::{Output, write_file};

/// Arguments of `safereach max-speed`.
#[derive(clap::Args)]
pub struct MaxSpeedArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write the certificate just below the largest certified speed to this file.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
}

/// Runs `safereach max-speed`: exit 0 when some speed is certified, 1 otherwise.
pub fn run(args: MaxSpeedArgs, out: &mut Output) -> Result<Exit> {
    let problem = input::problem(&args.problem, &args.sets)?;
    let b = radius::max_speed(&problem).context("max-speed search failed")?;
    if let (Some(path), Some(a)) = (&args.out, &b.certified) {
        write_file(path, certificate_text(a)?.as_bytes())?;
    }
    if args.json {
        writeln!(
            out,
            "{}",
            serde_json::to_string_pretty(&answer(&problem, &b))?
        )?;
    } else {
        writeln!(out, "{}", b.describe(&problem))?;
    }
    Ok(Exit::fail_if(b.value.is_none()))
}
