//! From an analysis to its certificate: the proofs of every piece, the witness and the
//! premises, sealed with the digest. (The certificate format and its check live in
//! [`crate::proof`], which never depends on the analyser.)

use crate::analysis::scene::SceneAnalysis;
use crate::analysis::{Analysis, PieceOutcome, PieceResult};
use crate::core::num::f64_at_most;
use crate::proof::certificate::{Certificate, FORMAT, Proof, premises};
use crate::proof::scene_certificate::{
    ObstacleProofs, SCENE_FORMAT, SceneCertificate, scene_premises,
};
use crate::proof::separation::{Bracket, stated};

/// The proof written for one piece's outcome.
fn proof(o: &PieceOutcome) -> Proof {
    match &o.result {
        PieceResult::Proved { kind, z, bound, .. } => Proof {
            piece: o.piece,
            kind: Some(kind.clone()),
            multipliers: z.clone(),
            bound: Some(f64_at_most(bound)),
        },
        PieceResult::Unproved { .. } => Proof {
            piece: o.piece,
            kind: None,
            multipliers: Vec::new(),
            bound: None,
        },
    }
}

impl Certificate {
    /// The certificate of an analysis. Its witness is stored as runs (speed and mode
    /// segments), without the per-period rows.
    pub fn from_analysis(a: &Analysis) -> Self {
        Self::of_analysis(a, false)
    }

    /// The certificate of an analysis with its witness's per-period rows (`steps`) as well:
    /// `certify --steps`. They grow with the horizon; `check` compares them with the replay.
    pub fn from_analysis_with_steps(a: &Analysis) -> Self {
        Self::of_analysis(a, true)
    }

    fn of_analysis(a: &Analysis, steps: bool) -> Self {
        let mut witness = a.witness.clone();
        if let Some(w) = witness.as_mut() {
            w.steps = if steps {
                // The witness's run recorded period by period, as `check` replays it.
                crate::core::simulate::replay_segments(
                    &a.decomposition.params,
                    w.obstacle_speeds.segments(),
                    None,
                    w.aim(),
                    w.obstacle_speeds.len(),
                    false,
                    true,
                )
                .trace()
            } else {
                Vec::new()
            };
        }
        let proofs = a.outcomes.iter().map(proof).collect();
        let lower_bound = a.lower_bound.as_ref().map(f64_at_most);
        let bracket = Bracket::of(lower_bound, a.witness.as_ref().and_then(|w| w.separation));
        let (min_separation, separation_tolerance) = stated(a.verdict, a.min_separation, bracket);
        let mut cert = Certificate {
            format: FORMAT.into(),
            verdict: a.verdict,
            min_separation,
            separation_tolerance,
            never_stops: a.never_stops,
            lower_bound,
            clearance: a.problem.robot.clearance,
            premises: premises(&a.problem),
            witness,
            problem: a.problem.clone(),
            pieces: a.outcomes.len(),
            programs_solved: a.programs_solved,
            proofs,
            digest: String::new(),
        };
        cert.digest = cert.compute_digest();
        cert
    }
}

impl SceneCertificate {
    /// The certificate of a scene analysis, its witness without rows per period.
    pub fn from_analysis(a: &SceneAnalysis) -> Self {
        Self::of_scene_analysis(a, false)
    }

    /// The certificate with the witness's rows per period (`certify --steps`).
    pub fn from_analysis_with_steps(a: &SceneAnalysis) -> Self {
        Self::of_scene_analysis(a, true)
    }

    fn of_scene_analysis(a: &SceneAnalysis, steps: bool) -> Self {
        let obstacles = a
            .obstacles
            .iter()
            .map(|o| ObstacleProofs {
                obstacle: o.obstacle,
                name: a.scene.obstacles[o.obstacle].name.clone(),
                lower_bound: o.lower_bound.as_ref().map(f64_at_most),
                own: o.own.iter().map(proof).collect(),
                bystanders: o.bystanders.iter().map(proof).collect(),
            })
            .collect();
        let lower_bound = a.lower_bound.as_ref().map(f64_at_most);
        let bracket = Bracket::of(lower_bound, a.witness.as_ref().and_then(|w| w.separation));
        let (min_separation, separation_tolerance) = stated(a.verdict, a.min_separation, bracket);
        let mut cert = SceneCertificate {
            format: SCENE_FORMAT.into(),
            verdict: a.verdict,
            min_separation,
            separation_tolerance,
            never_stops: a.never_stops,
            lower_bound,
            clearance: a.scene.robot.clearance,
            premises: scene_premises(&a.scene),
            witness: a.witness.clone().map(|mut w| {
                if !steps {
                    w.steps.clear();
                }
                w
            }),
            scene: a.scene.clone(),
            obstacles,
            programs_solved: a.programs_solved,
            digest: String::new(),
        };
        cert.digest = cert.compute_digest();
        cert
    }
}
