//! `safereach export-uppaal`: the finite model `explore` checks, written as UPPAAL timed
//! automata (XML) plus the safety query (`.q`), so a third tool can confirm the answer. A
//! scene file is exported as the scene network (one `Obstacle` process per obstacle, lanes,
//! lane changes, destination), with each obstacle's speed set read as `explore` reads it for
//! a scene.
//!
//! Exit codes: 0 written, 2 bad input or an I/O error.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;

use safereach::core::num::Exact;
use safereach::core::scene::Scene;
use safereach::crosscheck::explore::DEFAULT_STARTS;
use safereach::crosscheck::explore::scene::SceneSpeeds;
use safereach::crosscheck::uppaal;

use super::exit::Exit;
use super::explore::speed_set;
use super::input::{self, Input};
use super::output::{Output, write_file};

/// Arguments of `safereach export-uppaal`.
#[derive(clap::Args)]
pub struct ExportUppaalArgs {
    /// Problem or scene file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Obstacle speeds, as for `explore` (the obstacle automaton selects among them; default
    /// 5 for a problem, {0, W_i} for every obstacle of a scene).
    #[arg(long, value_name = "N|LIST")]
    speeds: Option<String>,
    /// For a range of initial gaps: the obstacle automaton starts from N evenly spaced
    /// initial gaps, both ends included (default 5), as `explore --starts N` explores them.
    #[arg(long, value_name = "N")]
    starts: Option<usize>,
    /// Model file to write (UPPAAL XML); the query goes beside it with extension `.q`.
    /// Default: the problem file's name with extension `.xml`, in the current directory.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
}

/// Runs `safereach export-uppaal`: exit 0 when the model and the query are written.
pub fn run(args: ExportUppaalArgs, out: &mut Output) -> Result<Exit> {
    // A range of initial gaps stays a problem: its network starts from the explorer's starts.
    let problem = match input::problem_with_range_or_scene(&args.problem, &args.sets)? {
        Input::Problem(problem) => problem,
        Input::Planar(_) => {
            return Err(input::planar_unsupported(&args.problem, "export-uppaal"));
        }
        Input::Scene(scene) => {
            if args.starts.is_some() {
                anyhow::bail!(
                    "--starts applies to single-obstacle problems; a scene's network starts \
                     from both ends of every obstacle's position range"
                );
            }
            return run_scene(&args, &scene, out);
        }
    };
    let spec = args.speeds.as_deref().unwrap_or("5");
    let speeds = speed_set(&problem, spec)?;
    let starts = args.starts.unwrap_or(DEFAULT_STARTS);
    let model = uppaal::export_with_starts(&problem, &speeds, starts)?;
    let starts_option = if model.grid.starts.len() > 1 {
        format!(" --starts {starts}")
    } else {
        String::new()
    };
    let (xml, query) = model_files(&args.problem, args.out.clone())?;
    write_file(&xml, model.xml.as_bytes())?;
    write_file(&query, model.query.as_bytes())?;
    writeln!(
        out,
        "{}: wrote {} and {}\n  integer grid: 1 distance unit = 1/{} m, 1 time unit = one control period ({} s), \
         speeds in distance units per period; exact for this problem (no rounding)\n  \
         obstacle speeds {} m/s; reference answer: safereach explore {} --speeds {}{}",
        problem.name,
        xml.display(),
        query.display(),
        model.grid.scale,
        problem.robot.control_period,
        speeds,
        args.problem.display(),
        spec,
        starts_option
    )?;
    Ok(Exit::Pass)
}

/// Exports a scene: every obstacle's speed set from `--speeds` as `explore` reads it.
fn run_scene(args: &ExportUppaalArgs, scene: &Scene, out: &mut Output) -> Result<Exit> {
    let params = scene.params::<Exact>();
    let speeds = match args.speeds.as_deref() {
        Some(spec) => SceneSpeeds::parse(spec, &params)?,
        None => SceneSpeeds::extremes(&params),
    };
    let model = uppaal::export_scene(scene, &speeds)?;
    let (xml, query) = model_files(&args.problem, args.out.clone())?;
    write_file(&xml, model.xml.as_bytes())?;
    write_file(&query, model.query.as_bytes())?;
    let option = args
        .speeds
        .as_deref()
        .map(|s| format!(" --speeds {s}"))
        .unwrap_or_default();
    writeln!(
        out,
        "{}: wrote {} and {}\n  integer grid: 1 distance unit = 1/{} m, 1 time unit = one control period ({} s), \
         speeds in distance units per period; exact for this scene (no rounding)\n  \
         {} obstacle processes, speeds (m/s) {}; reference answer: safereach explore {}{}",
        scene.name,
        xml.display(),
        query.display(),
        model.grid.scale,
        scene.robot.control_period,
        scene.obstacles.len(),
        speeds,
        args.problem.display(),
        option
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
