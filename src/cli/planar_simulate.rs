//! `safereach simulate` on a planar problem: random runs (random headings and speeds,
//! changed now and then), each replayed exactly, exit 1 when one collides; and `--replay`
//! of a planar certificate's witness, with its trace.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;

use safereach::analysis::planar::{
    MAX_RUN_STEPS, PlanarTraceRow, planar_monte_carlo, planar_trace,
};
use safereach::core::planar::PlanarProblem;
use safereach::core::show::{up, value};
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::planar::certificate::PlanarCertificate;
use safereach::proof::planar::witness_record;

use super::exit::Exit;
use super::output::{Output, write_file};

#[derive(Serialize)]
struct PlanarSimulation {
    problem: String,
    runs: usize,
    collisions: usize,
    /// The least separation seen (m, rounded up) and where.
    least_separation: Option<f64>,
    closest_obstacle: Option<String>,
    closest_at: Option<f64>,
    closest_seed: Option<u64>,
}

/// Runs `runs` random planar runs from `seed`.
pub fn random(
    problem: &PlanarProblem,
    path: &Path,
    runs: usize,
    seed: u64,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let params = problem.params();
    let found = planar_monte_carlo(&params, runs, seed, MAX_RUN_STEPS);
    let closest = found.closest.as_ref();
    let report = PlanarSimulation {
        problem: problem.name.clone(),
        runs: found.runs,
        collisions: found.collisions,
        least_separation: closest.map(|c| c.separation.upper.to_f64().value()),
        closest_obstacle: closest.map(|c| params.obstacles[c.obstacle].name.clone()),
        closest_at: closest.map(|c| c.separation.at.to_f64().value()),
        closest_seed: closest.map(|c| c.seed),
    };
    if json {
        writeln!(out, "{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        writeln!(
            out,
            "{} ({}): {} random planar runs, {} with a collision while the robot moved",
            report.problem,
            path.display(),
            report.runs,
            report.collisions
        )?;
        if let (Some(s), Some(o), Some(t), Some(k)) = (
            report.least_separation,
            &report.closest_obstacle,
            report.closest_at,
            report.closest_seed,
        ) {
            writeln!(
                out,
                "  closest: {o} at {} m, t = {} s (run seed {k}; exact replay)",
                up(s, 9),
                value(t)
            )?;
        }
    }
    Ok(Exit::fail_if(found.collisions > 0))
}

/// `simulate --replay` of a planar certificate (already checked): its witness replayed
/// exactly on the certificate's own problem, with every step's positions in `trace` (CSV,
/// or JSON Lines for `.jsonl`): one row per obstacle per step start.
pub fn replay(
    cert: &PlanarCertificate,
    path: &Path,
    trace: Option<&Path>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let problem = certificate_problem(cert, path)?;
    let params = problem.params();
    let witness = cert.witness.as_ref().with_context(|| {
        format!(
            "{}: the certificate has no witness to replay",
            path.display()
        )
    })?;
    let behaviour = witness_record::behaviour(&params, witness)
        .map_err(|e| anyhow::anyhow!("{}: the witness: {e}", path.display()))?;
    let (rows, replayed) = planar_trace(&params, &behaviour, witness.steps)
        .map_err(|e| anyhow::anyhow!("{}: the witness: {e}", path.display()))?;
    if let Some(t) = trace {
        write_file(t, trace_text(t, &rows)?.as_bytes())?;
    }
    let again = witness_record::record(&params, &behaviour, &replayed);
    if json {
        writeln!(out, "{}", serde_json::to_string_pretty(&again)?)?;
    } else {
        let collides = if witness.collides {
            "reaches the clearance"
        } else {
            "stays above the clearance"
        };
        writeln!(
            out,
            "{}: replayed the {} certificate's witness exactly over {} periods: {} closest at \
             t = {} s, separation <= {} m ({collides}); the robot {}",
            problem.name,
            cert.verdict.as_str(),
            witness.steps,
            witness.obstacle,
            value(witness.closest_at),
            up(cert.upper_bound.unwrap_or(f64::NAN), 9),
            match (&witness.brake_step, &witness.guard) {
                (Some(k), Some(g)) => format!("brakes at step {k} ({g})"),
                _ => "never brakes".to_string(),
            }
        )?;
    }
    Ok(if witness.collides {
        Exit::Fail
    } else {
        Exit::Pass
    })
}

fn trace_text(path: &Path, rows: &[PlanarTraceRow]) -> Result<String> {
    if path.extension().is_some_and(|e| e == "jsonl") {
        let mut s = String::new();
        for r in rows {
            s += &serde_json::to_string(r)?;
            s.push('\n');
        }
        return Ok(s);
    }
    let mut s = String::from(
        "t,robot_x,robot_y,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_y,obstacle_vx,\
         obstacle_vy,step\n",
    );
    let cell = |x: Option<f64>| x.map(|x| x.to_string()).unwrap_or_default();
    for r in rows {
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            r.t,
            r.robot_x,
            r.robot_y,
            r.robot_speed,
            r.mode,
            r.obstacle,
            r.x,
            r.y,
            cell(r.vx),
            cell(r.vy),
            r.step
        );
    }
    Ok(s)
}

/// The certificate's problem, read from its stored text.
fn certificate_problem(cert: &PlanarCertificate, path: &Path) -> Result<PlanarProblem> {
    PlanarProblem::from_toml_str_with_overrides(
        &cert.problem_toml,
        &format!("{} (its problem)", path.display()),
        &cert.overrides,
    )
    .map_err(|e| anyhow::anyhow!("{e}"))
}

/// Refuses a planar problem file that is not the planar certificate's problem.
pub fn same_problem(
    given: &PlanarProblem,
    problem: &Path,
    cert_path: &Path,
    cert: &CertificateFile,
) -> Result<()> {
    let same = match cert {
        CertificateFile::Planar(c) => certificate_problem(c, cert_path)? == *given,
        _ => false,
    };
    anyhow::ensure!(
        same,
        "{}: not the problem of {}; leave the problem out to replay the certificate's own",
        problem.display(),
        cert_path.display()
    );
    Ok(())
}
