//! `safereach radius` and `safereach max-speed`: where certification ends.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use serde::Serialize;

use safereach::analysis::radius::{self, Boundary, Parameter};
use safereach::core::model::Problem;
use safereach::core::output::write_atomic;
use safereach::proof::certificate::Certificate;

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

/// One side of a boundary, as printed.
#[derive(Serialize)]
struct Side {
    at: f64,
    verdict: &'static str,
    min_separation: Option<f64>,
    lower_bound: Option<f64>,
    witness_collides: Option<bool>,
}

/// A boundary answer, as printed.
#[derive(Serialize)]
struct Answer {
    obstacle_speed: f64,
    reaction_radius: Option<f64>,
    safe_radius: Option<f64>,
    max_obstacle_speed: Option<f64>,
    accuracy: f64,
    reason: Option<String>,
    certified_side: Option<Side>,
    refuted_side: Option<Side>,
    analyses: usize,
}

fn side(a: &safereach::analysis::Analysis, param: Parameter) -> Side {
    let at = match param {
        Parameter::ReactionRadius => a.problem.controller.reaction_radius,
        Parameter::ObstacleSpeed => a.problem.environment.obstacle_speed,
    };
    Side {
        at,
        verdict: a.verdict.as_str(),
        min_separation: a.min_separation,
        lower_bound: a
            .lower_bound
            .as_ref()
            .map(safereach::core::num::f64_at_most),
        witness_collides: a.witness.as_ref().map(|w| w.collides),
    }
}

fn answer(problem: &Problem, b: &Boundary) -> Answer {
    let (safe_radius, max_obstacle_speed, reaction_radius) = match b.parameter {
        Parameter::ReactionRadius => (b.value, None, None),
        Parameter::ObstacleSpeed => (None, b.value, Some(problem.controller.reaction_radius)),
    };
    Answer {
        obstacle_speed: problem.environment.obstacle_speed,
        reaction_radius,
        safe_radius,
        max_obstacle_speed,
        accuracy: radius::TOLERANCE,
        reason: b.reason.clone(),
        certified_side: b.certified.as_ref().map(|a| side(a, b.parameter)),
        refuted_side: b.refuted.as_ref().map(|a| side(a, b.parameter)),
        analyses: b.analyses,
    }
}

fn certificate_text(a: &safereach::analysis::Analysis) -> Result<String> {
    let cert = Certificate::from_analysis(a);
    safereach::proof::certificate::check(&cert)
        .map_err(|e| anyhow::anyhow!("internal error: certificate does not verify: {e}"))?;
    Ok(serde_json::to_string_pretty(&cert)? + "\n")
}

/// Runs `safereach radius`: exit 0 when every speed has a safe radius, 1 otherwise.
pub fn run(args: RadiusArgs) -> Result<ExitCode> {
    let base = Problem::load_with_overrides(&args.problem, &args.sets)?;
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
        let problem = Problem::load_with_overrides(&args.problem, &sets)?;
        let b = radius::safe_radius(&problem).context("radius search failed")?;
        all &= b.value.is_some();
        if let (Some(dir), Some(a)) = (&args.certificates, &b.certified) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
            let path = dir.join(format!("radius-W{w}.json"));
            write_atomic(&path, certificate_text(a)?.as_bytes())
                .with_context(|| format!("writing {}", path.display()))?;
        }
        if !args.json {
            outln!("{}", b.describe(&problem));
        }
        answers.push(answer(&problem, &b));
    }
    if args.json {
        if args.speeds.is_empty() {
            outln!("{}", serde_json::to_string_pretty(&answers[0])?);
        } else {
            outln!("{}", serde_json::to_string_pretty(&answers)?);
        }
    }
    Ok(ExitCode::from(u8::from(!all)))
}

/// Runs `safereach max-speed`: exit 0 when some speed is certified, 1 otherwise.
pub fn max_speed(args: MaxSpeedArgs) -> Result<ExitCode> {
    let problem = Problem::load_with_overrides(&args.problem, &args.sets)?;
    let b = radius::max_speed(&problem).context("max-speed search failed")?;
    if let (Some(path), Some(a)) = (&args.out, &b.certified) {
        write_atomic(path, certificate_text(a)?.as_bytes())
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&answer(&problem, &b))?);
    } else {
        outln!("{}", b.describe(&problem));
    }
    Ok(ExitCode::from(u8::from(b.value.is_none())))
}
