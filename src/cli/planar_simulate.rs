//! `safereach simulate` on a planar problem: random runs (random headings and speeds,
//! changed now and then), each replayed exactly; exit 1 when one collides.

use std::io::Write;
use std::path::Path;

use anyhow::Result;
use serde::Serialize;

use safereach::analysis::planar::planar_monte_carlo;
use safereach::core::planar::PlanarProblem;
use safereach::core::show::{up, value};

use super::exit::Exit;
use super::output::Output;

/// The most control periods one planar run may take (it ends earlier at rest).
const MAX_STEPS: usize = 3000;

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
    let found = planar_monte_carlo(&params, runs, seed, MAX_STEPS);
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
