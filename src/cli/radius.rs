//! `safereach radius`: the smallest reaction radius that is still certified, per obstacle
//! speed bound — where certification ends along ρ.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};

use safereach::analysis::radius;

use super::boundary::{answer, certificate_text};
use super::exit::Exit;
use super::input;
use super::output::{Output, create_dir, write_file};

/// Arguments of `safereach radius`.
#[derive(clap::Args)]
pub struct RadiusArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Obstacle speed bounds W to answer for (comma-separated; default: the problem's).
    #[arg(long, value_delimiter = ',')]
    speeds: Vec<f64>,
    /// Print JSON.
    #[arg(long)]
    json: bool,
    /// Write the certificate just above each safe radius into this directory.
    #[arg(long, value_name = "DIR")]
    certificates: Option<PathBuf>,
}

/// Runs `safereach radius`: exit 0 when every speed has a safe radius, 1 otherwise.
pub fn run(args: RadiusArgs, out: &mut Output) -> Result<Exit> {
    let base = input::problem(&args.problem, &args.sets)?;
    let speeds = if args.speeds.is_empty() {
        vec![base.environment.obstacle_speed]
    } else {
        args.speeds.clone()
    };
    let mut answers = Vec::new();
    let mut all = true;
    for &w in &speeds {
        let mut sets = args.sets.clone();
        sets.push(format!("environment.obstacle_speed={w}"));
        let problem = input::problem(&args.problem, &sets)?;
        let b = radius::safe_radius(&problem).context("radius search failed")?;
        all &= b.value.is_some();
        if let (Some(dir), Some(a)) = (&args.certificates, &b.certified) {
            create_dir(dir)?;
            write_file(
                &dir.join(format!("radius-W{w}.json")),
                certificate_text(a)?.as_bytes(),
            )?;
        }
        if !args.json {
            writeln!(out, "{}", b.describe(&problem))?;
        }
        answers.push(answer(&problem, &b));
    }
    if args.json {
        if args.speeds.is_empty() {
            writeln!(out, "{}", serde_json::to_string_pretty(&answers[0])?)?;
        } else {
            writeln!(out, "{}", serde_json::to_string_pretty(&answers)?)?;
        }
    }
    Ok(Exit::fail_if(!all))
}
