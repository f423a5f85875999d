//! `safereach export-uppaal`: the finite model `explore` checks, written as UPPAAL timed
//! automata (XML) plus the safety query (`.q`), so a third tool can confirm the answer.
//!
//! Exit codes: 0 written, 2 bad input or an I/O error.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;

use safereach::crosscheck::uppaal;

use super::exit::Exit;
use super::explore::speed_set;
use super::input;
use super::output::{Output, write_file};

/// Arguments of `safereach export-uppaal`.
#[derive(clap::Args)]
pub struct ExportUppaalArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Obstacle speeds, as for `explore` (the obstacle automaton selects among them).
    #[arg(long, value_name = "N|LIST", default_value = "5")]
    speeds: String,
    /// Model file to write (UPPAAL XML); the query goes beside it with extension `.q`.
    /// Default: the problem file's name with extension `.xml`, in the current directory.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
}

/// Runs `safereach export-uppaal`: exit 0 when the model and the query are written.
pub fn run(args: ExportUppaalArgs, out: &mut Output) -> Result<Exit> {
    let problem = input::problem(&args.problem, &args.sets)?;
    let speeds = speed_set(&problem, &args.speeds)?;
    let model = uppaal::export(&problem, &speeds)?;
    let (xml, query) = model_files(&args.problem, args.out.clone())?;
    write_file(&xml, model.xml.as_bytes())?;
    write_file(&query, model.query.as_bytes())?;
    writeln!(
        out,
        "{}: wrote {} and {}\n  integer grid: 1 distance unit = 1/{} m, 1 time unit = one control period ({} s), \
         speeds in distance units per period; exact for this problem (no rounding)\n  \
         obstacle speeds {} m/s; reference answer: safereach explore {} --speeds {}",
        problem.name,
        xml.display(),
        query.display(),
        model.grid.scale,
        problem.robot.control_period,
        speeds,
        args.problem.display(),
        args.speeds
    )?;
    Ok(Exit::Pass)
}

/// The model file (`--out`, else `<problem stem>.xml` here) and the query file beside it.
fn model_files(problem: &Path, out: Option<PathBuf>) -> Result<(PathBuf, PathBuf)> {
    let xml = out.unwrap_or_else(|| {
        let stem = problem
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "model".into());
        PathBuf::from(format!("{stem}.xml"))
    });
    let query = xml.with_extension("q");
    if query == xml {
        anyhow::bail!(
            "--out {}: the model file must not end in .q (the query file is written beside it)",
            xml.display()
        );
    }
    Ok((xml, query))
}
