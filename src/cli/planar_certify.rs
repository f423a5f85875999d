//! `safereach certify` on a planar problem: the verdict, the bracket on s* and the witness
//! (docs/semantics.md §13). The lower end is proved from the SOC duals in exact rationals;
//! the upper end is a behaviour's exact replay.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;
use serde::Serialize;

use safereach::analysis::planar::{
    BoundOptions, LowerBoundError, PlanarAnswer, PlanarVerdict, certify_planar,
};
use safereach::core::num::Exact;
use safereach::core::planar::{PlanarGuard, PlanarParams, PlanarProblem};
use safereach::core::show::{down, up, value};
use safereach::proof::planar::domain::DomainError;

use super::exit::Exit;
use super::output::{Output, write_file};

/// The bracket the planar s* is refined to where the relaxation allows (issue 36: 1e-6).
const TOLERANCE: f64 = 1e-6;

/// The answer as `--json` prints it and `--out` writes it.
#[derive(Serialize)]
struct PlanarReport {
    problem: String,
    verdict: &'static str,
    clearance: f64,
    /// s* ≥ this (proved; rounded down).
    lower_bound: f64,
    /// The same, exact (a rational).
    lower_bound_exact: String,
    /// s* ≤ this: the witness's replayed separation (rounded up).
    upper_bound: Option<f64>,
    programs: usize,
    budget_exhausted: bool,
    unsolved_leaves: usize,
    witness: Option<WitnessReport>,
}

#[derive(Serialize)]
struct WitnessReport {
    /// The obstacle that comes closest.
    obstacle: String,
    /// When it is closest (s).
    closest_at: f64,
    /// The step the robot brakes at, and the guard.
    brake_step: Option<usize>,
    guard: Option<String>,
    /// When the robot rests (s).
    rest: Option<f64>,
    /// Each obstacle's start and per-step velocity (m, m/s), as replayed.
    obstacles: Vec<ObstacleMotion>,
}

#[derive(Serialize)]
struct ObstacleMotion {
    name: String,
    start: [f64; 2],
    velocities: Vec<[f64; 2]>,
}

/// Certifies the planar problem read from `path`.
pub fn run(
    problem: &PlanarProblem,
    path: &Path,
    out_path: &Option<PathBuf>,
    json: bool,
    out: &mut Output,
) -> Result<Exit> {
    let params = problem.params();
    let tolerance = safereach::core::num::exact_decimal(TOLERANCE);
    let answer = certify_planar(&params, &BoundOptions::default(), &tolerance)
        .map_err(|e| explain(path, e))?;
    let report = report(problem, &params, &answer);
    let text = serde_json::to_string_pretty(&report)? + "\n";
    if let Some(p) = out_path {
        write_file(p, text.as_bytes())?;
    }
    if json {
        write!(out, "{text}")?;
    } else {
        write!(out, "{}", summary(&report))?;
    }
    Ok(match answer.verdict {
        PlanarVerdict::Certified => Exit::Pass,
        PlanarVerdict::Refuted => Exit::Fail,
        PlanarVerdict::Inconclusive => Exit::Inconclusive,
    })
}

fn explain(path: &Path, e: LowerBoundError) -> anyhow::Error {
    let why = match e {
        LowerBoundError::Domain(DomainError::Unsupported(key)) => {
            format!("{key} is not analysed by the planar engine yet (issue 36)")
        }
        LowerBoundError::Domain(DomainError::Unbounded) => "the path has no end and an \
            obstacle can keep up with the robot without a bounded region: no finite horizon \
            (give the robot a path that ends, or the obstacle a region)"
            .to_string(),
    };
    anyhow::anyhow!("{}: {why}", path.display())
}

fn f(x: &Exact) -> f64 {
    x.to_f64().value()
}

fn report(problem: &PlanarProblem, params: &PlanarParams, answer: &PlanarAnswer) -> PlanarReport {
    let witness = answer.witness.as_ref().and_then(|w| {
        let (i, sep) = w.run.closest()?;
        Some(WitnessReport {
            obstacle: params.obstacles[i].name.clone(),
            closest_at: f(&sep.at),
            brake_step: w.run.brake.as_ref().map(|b| b.step),
            guard: w.run.brake.as_ref().map(|b| match b.guard {
                PlanarGuard::Danger { obstacle } => {
                    format!("danger ({})", params.obstacles[obstacle].name)
                }
                PlanarGuard::WrongAssumption { obstacle } => {
                    format!("wrong assumption ({})", params.obstacles[obstacle].name)
                }
                PlanarGuard::Destination => "destination".to_string(),
            }),
            rest: w.run.rest.as_ref().map(f),
            obstacles: w
                .behaviour
                .obstacles
                .iter()
                .zip(&params.obstacles)
                .map(|(b, o)| ObstacleMotion {
                    name: o.name.clone(),
                    start: [f(&b.start.x), f(&b.start.y)],
                    velocities: b.velocities.iter().map(|v| [f(&v.x), f(&v.y)]).collect(),
                })
                .collect(),
        })
    });
    PlanarReport {
        problem: problem.name.clone(),
        verdict: answer.verdict.as_str(),
        clearance: f(&params.motion.clearance),
        lower_bound: f(&answer.lower),
        lower_bound_exact: answer.lower.to_string(),
        upper_bound: answer.upper.as_ref().map(f),
        programs: answer.programs,
        budget_exhausted: answer.exhausted,
        unsolved_leaves: answer.unsolved,
        witness,
    }
}

fn summary(r: &PlanarReport) -> String {
    let mut s = format!("{}: {} (planar)\n", r.problem, r.verdict);
    let lower = down(r.lower_bound, 9);
    s += &match r.upper_bound {
        Some(u) => format!(
            "  worst-case minimum separation s* in [{lower}, {}] m (Euclidean, between the \
             discs, instants inside steps included)\n",
            up(u, 9)
        ),
        None => format!("  worst-case minimum separation s* >= {lower} m (no witness)\n"),
    };
    s += &format!(
        "  proved: s* >= {lower} m from {} second-order cone programs, each bound \
         recomputed from its duals in exact rationals; clearance {} m\n",
        r.programs,
        value(r.clearance)
    );
    if r.budget_exhausted {
        s += "  note: the refinement budget ran out; the bound is sound but may be loose\n";
    }
    if r.unsolved_leaves > 0 {
        s += &format!(
            "  note: {} leaves the solver could not bound were given the floor -(r_R + r_i)\n",
            r.unsolved_leaves
        );
    }
    if let Some(w) = &r.witness {
        let brake = match (&w.brake_step, &w.guard) {
            (Some(k), Some(g)) => format!("brakes at step {k} ({g})"),
            _ => "never brakes".to_string(),
        };
        s += &format!(
            "  witness: {} closest at t = {} s; the robot {brake}{}\n",
            w.obstacle,
            value(w.closest_at),
            w.rest
                .map(|t| format!(", rests at t = {} s", value(t)))
                .unwrap_or_default()
        );
    }
    if r.verdict == "inconclusive" {
        s += "  the clearance lies inside the bracket: the relaxation (reductions.md §11) \
              cannot decide it\n";
    }
    s
}
