//! How `radius` and `max-speed` print a boundary of certification: the value found, and the
//! analyses on either side of it (as JSON), plus the certificate just inside it.

use anyhow::Result;
use serde::Serialize;

use safereach::analysis::Analysis;
use safereach::analysis::radius::{self, Boundary, Parameter};
use safereach::core::model::Problem;
use safereach::proof::certificate::{self, Certificate};

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
pub struct Answer {
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

fn side(a: &Analysis, param: Parameter) -> Side {
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

/// The printed answer for boundary `b` of `problem`.
pub fn answer(problem: &Problem, b: &Boundary) -> Answer {
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

/// The certificate for `a` as written to a file, after it passed the exact check.
pub fn certificate_text(a: &Analysis) -> Result<String> {
    let cert = Certificate::from_analysis(a);
    certificate::check(&cert)
        .map_err(|e| anyhow::anyhow!("internal error: certificate does not verify: {e}"))?;
    Ok(serde_json::to_string_pretty(&cert)? + "\n")
}
