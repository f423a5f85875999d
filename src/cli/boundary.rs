//! How `radius` and `max-speed` print a boundary of certification: the value found, and the
//! analyses on either side of it (as JSON), plus the certificate just inside it.

use anyhow::Result;
use serde::Serialize;

use safereach::analysis::Analysis;
use safereach::analysis::radius::{self, Boundary, Parameter};
use safereach::analysis::region_statement::region_statement;
use safereach::core::model::Problem;
use safereach::proof::certificate::{self, Certificate};
use safereach::proof::region_map::RegionMap;

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
    /// With `--region`: the region statement at the certified side.
    #[serde(skip_serializing_if = "Option::is_none")]
    region: Option<RegionJson>,
}

/// A region statement (or why there is none), as printed.
#[derive(Serialize)]
pub struct RegionJson {
    /// The statement holds: certified for every W ≤ `speed` at every ρ ≥ `radius`.
    holds: bool,
    speed: f64,
    radius: f64,
    /// ρ_sat = g0 + σ_g: the map's ρ range ends at max(radius, saturation).
    saturation: Option<f64>,
    leaves: Option<usize>,
    certified_fraction: Option<f64>,
    /// In words (or why region certificates do not cover the problem).
    text: String,
}

/// The region statement at the certified side of `b` (None: there is no certified side),
/// whether it holds, and its map when there is one.
pub fn region_at(b: &Boundary) -> Option<(RegionJson, Option<RegionMap>)> {
    let certified = b.certified.as_ref()?;
    let (speed, radius) = (
        certified.problem.environment.obstacle_speed,
        certified.problem.controller.reaction_radius,
    );
    Some(match region_statement(&certified.problem, speed, radius) {
        Ok(st) => (
            RegionJson {
                holds: st.holds(),
                speed: st.speed,
                radius: st.radius,
                saturation: Some(st.saturation),
                leaves: Some(st.map.leaves.len()),
                certified_fraction: Some(st.map.coverage.certified),
                text: st.describe(),
            },
            Some(st.map),
        ),
        Err(e) => (
            RegionJson {
                holds: false,
                speed,
                radius,
                saturation: None,
                leaves: None,
                certified_fraction: None,
                text: format!("not established: {e}"),
            },
            None,
        ),
    })
}

impl Answer {
    /// The answer with its region statement.
    pub fn with_region(mut self, region: Option<RegionJson>) -> Answer {
        self.region = region;
        self
    }
}

impl RegionJson {
    /// Whether the statement holds.
    pub fn holds(&self) -> bool {
        self.holds
    }

    /// The statement in words.
    pub fn text(&self) -> &str {
        &self.text
    }
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
        region: None,
    }
}

/// The certificate for `a` as written to a file, after it passed the exact check.
pub fn certificate_text(a: &Analysis) -> Result<String> {
    let cert = Certificate::from_analysis(a);
    certificate::check(&cert)
        .map_err(|e| anyhow::anyhow!("internal error: certificate does not verify: {e}"))?;
    Ok(serde_json::to_string_pretty(&cert)? + "\n")
}
