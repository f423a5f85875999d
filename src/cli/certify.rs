//! `safereach certify`: the verdict for one problem, with the certificate that proves it.
//!
//! The certificate is checked in exact arithmetic before anything is printed, so the command
//! never reports a verdict the checker would not accept.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};

use safereach::analysis;
use safereach::core::semantics::Mode;
use safereach::proof::certificate::{self, Certificate};

use super::exit::Exit;
use super::input::{self, Input};
use super::output::{Output, write_file};
use super::scene_certify;

/// Arguments of `safereach certify`.
#[derive(clap::Args)]
pub struct CertifyArgs {
    /// Problem file (TOML).
    problem: PathBuf,
    /// Override a key, e.g. `environment.obstacle_speed=0.25` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Print the certificate as JSON instead of a summary.
    #[arg(long)]
    json: bool,
    /// Write the certificate to this file (atomically).
    #[arg(long)]
    pub(super) out: Option<PathBuf>,
}

/// Runs `safereach certify`: exit 0 certified, 1 refuted, 3 inconclusive.
pub fn run(args: CertifyArgs, out: &mut Output) -> Result<Exit> {
    let problem = match input::problem_or_scene(&args.problem, &args.sets)? {
        Input::Problem(p) => p,
        Input::Scene(scene) => return scene_certify::run(&scene, &args.out, args.json, out),
    };
    let analysis = analysis::analyse(&problem).context("analysis failed")?;
    let cert = Certificate::from_analysis(&analysis);
    // Never print a verdict the exact checker would not accept.
    certificate::check(&cert)
        .map_err(|e| anyhow::anyhow!("internal error: the certificate does not verify: {e}"))?;
    let text = serde_json::to_string_pretty(&cert)? + "\n";
    if let Some(path) = &args.out {
        write_file(path, text.as_bytes())?;
    }
    if args.json {
        write!(out, "{text}")?;
    } else {
        write!(out, "{}", summary(&cert))?;
    }
    Ok(cert.verdict.into())
}

/// The human-readable answer: verdict, worst case, bound and premises.
fn summary(cert: &Certificate) -> String {
    let mut s = format!("{}: {}\n", cert.problem.name, cert.verdict.as_str());
    let sep = match (cert.min_separation, cert.never_stops) {
        (_, true) => "-inf (the robot can miss the obstacle entirely and never brake)".to_string(),
        (Some(x), _) => format!("{x:.6} m"),
        (None, _) => "unknown (no worst case could be realised)".to_string(),
    };
    s += &format!("  worst-case minimum separation s* = {sep}\n");
    match cert.lower_bound {
        Some(lb) => {
            s += &format!(
                "  rigorous lower bound {lb:.9} m vs clearance {} m\n",
                cert.clearance
            )
        }
        None => s += "  no finite lower bound proved\n",
    }
    if let Some(w) = &cert.witness {
        let brake = w.steps.iter().find(|r| r.robot_mode == Mode::Brake);
        let last = w.steps.last();
        s += &format!(
            "  worst case: {}{}{}\n",
            if w.collides {
                "collides"
            } else {
                "closest approach"
            },
            brake
                .map(|b| format!(", robot brakes at t = {:.3} s", b.t))
                .unwrap_or_default(),
            last.map(|l| format!(", ends at t = {:.3} s with gap {:.6} m", l.t, l.gap))
                .unwrap_or_default(),
        );
    }
    s += &format!(
        "  pieces: {} ({} linear programs solved)\n",
        cert.pieces, cert.programs_solved
    );
    s += "  premises:\n";
    for p in &cert.premises {
        s += &format!(
            "    {:<21} {} {} {}\n",
            p.name,
            p.description(),
            p.bound,
            p.unit()
        );
    }
    s
}
