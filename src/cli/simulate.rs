//! `safereach simulate`: random obstacle behaviours (Monte Carlo), or the replay of a
//! certificate's witness, on the same discrete-time semantics the analyser reasons about.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use safereach::analysis;
use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::core::output::trace_for_path;
use safereach::core::simulate;
use safereach::proof::certificate::Certificate;

use super::exit::Exit;
use super::input::{self, Input, Unreadable};
use super::output::{Output, write_file};
use super::scene_simulate;

/// Arguments of `safereach simulate`, as typed.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Number of random runs.
    #[arg(long, default_value_t = 1000)]
    pub(super) runs: usize,
    /// Seed of the first run (run i uses seed + i).
    #[arg(long, default_value_t = 0)]
    pub(super) seed: u64,
    /// Replay this certificate's witness instead of random runs.
    #[arg(long, value_name = "CERT")]
    pub(super) replay: Option<PathBuf>,
    /// Write the replayed run (or the random run that came closest): CSV, or JSON Lines for .jsonl.
    #[arg(long, value_name = "FILE")]
    pub(super) trace: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub(super) json: bool,
}

/// What to simulate, validated.
enum Runs {
    /// Replay the witness of the certificate read from `path`.
    Replay {
        path: PathBuf,
        cert: Box<Certificate>,
    },
    /// `runs` (at least 1) random runs from `seed`.
    Random { runs: usize, seed: u64 },
}

/// Runs `safereach simulate`: exit 0 no collision, 1 a collision.
pub fn run(args: SimulateArgs, out: &mut Output) -> Result<Exit> {
    let problem = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) => p,
        Input::Scene(scene) => {
            return scene_simulate::run(&scene, &args, out);
        }
    };
    let runs = match args.replay {
        Some(path) => Runs::Replay {
            cert: Box::new(input::certificate(&path, Unreadable::Reading)?),
            path,
        },
        None if args.runs == 0 => anyhow::bail!("--runs must be at least 1"),
        None => Runs::Random {
            runs: args.runs,
            seed: args.seed,
        },
    };
    let trace = args.trace.as_deref();
    match runs {
        Runs::Replay { path, cert } => replay(&problem, &path, &cert, trace, args.json, out),
        Runs::Random { runs, seed } => random(&problem, runs, seed, trace, args.json, out),
    }
}

/// Replays the certificate's witness: the obstacle's speeds, period by period.
fn replay(
    problem: &Problem,
    cert_path: &Path,
    cert: &Certificate,
    trace: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let exact = problem.params::<Exact>();
    let witness = cert.witness.as_ref().with_context(|| {
        format!(
            "{}: the certificate has no witness to replay",
            cert_path.display()
        )
    })?;
    let replay = simulate::replay_reacting_at(
        &exact,
        &witness.obstacle_speeds,
        witness.aim(),
        witness.obstacle_speeds.len(),
        false,
    );
    let rows = replay.trace();
    if let Some(path) = trace {
        write_file(path, trace_for_path(path, &rows, "0").as_bytes())?;
    }
    let sep = replay.rest_gap().map(|g| g.to_f64().value());
    if json {
        writeln!(
            out,
            "{}",
            serde_json::json!({"replay": cert_path, "collided": replay.collided(), "separation": sep, "steps": rows.len()})
        )?;
    } else {
        writeln!(
            out,
            "replayed {}: {} periods, {}, separation at rest {}",
            cert_path.display(),
            replay.periods(),
            if replay.collided() {
                "COLLISION"
            } else {
                "no collision"
            },
            sep.map(|s| format!("{s:.9} m"))
                .unwrap_or_else(|| "- (never stopped)".into())
        )?;
    }
    Ok(Exit::fail_if(replay.collided()))
}

/// `runs` random runs; the trace written is the run that came closest.
fn random(
    problem: &Problem,
    runs: usize,
    seed: u64,
    trace: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let floats = analysis::params_f64(&problem.params::<Exact>());
    let mc = analysis::monte_carlo(&floats, runs, seed);
    if let Some(path) = trace {
        let max = simulate::horizon(&floats);
        let run = simulate::run(
            floats.clone(),
            analysis::random_speeds(floats.W, seed, mc.closest_run),
            max,
            false,
        );
        let rows = simulate::trace(&floats, &run);
        write_file(path, trace_for_path(path, &rows, "0").as_bytes())?;
    }
    if json {
        writeln!(out, "{}", serde_json::to_string(&mc)?)?;
    } else {
        writeln!(
            out,
            "{}: {} runs (seed {}), {} collisions, minimum separation seen {:.6} m (run {})",
            problem.name, mc.runs, mc.seed, mc.collisions, mc.min_separation, mc.closest_run
        )?;
    }
    Ok(Exit::fail_if(mc.collisions > 0))
}
