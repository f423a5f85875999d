//! The analyser for scenes: every piece of [`SceneDecomposition`] proved, the worst case
//! over all obstacles, and its witness replayed through the scene's step function.
//!
//! Own pieces of every obstacle in the robot's lane are proved first; a bystander step of
//! an obstacle is needed only where the destination or a firing piece of another obstacle
//! not proved empty can make the robot brake then (docs/reductions.md, "Scenes").

use crate::analysis::analyse::{PieceOutcome, PieceResult, Verdict, prove};
use crate::analysis::scene_witness::realise;
use crate::core::num::Exact;
use crate::core::scene::Scene;
use crate::proof::program::{Program, ProofKind};
use crate::proof::scene_certificate::SceneWitness;
use crate::proof::scene_check::least_start;
use crate::proof::scene_schedule::{SceneDecomposition, Unsupported};
use crate::proof::schedule::Piece;

/// What was proved about one obstacle of the robot's lane.
#[derive(Clone, Debug)]
pub struct ObstacleAnalysis {
    /// Index of the obstacle in the scene.
    pub obstacle: usize,
    /// Its own pieces (it fires or passes through), in its decomposition's order.
    pub own: Vec<PieceOutcome>,
    /// Its bystander pieces at the steps another obstacle or the destination can make the
    /// robot brake.
    pub bystanders: Vec<PieceOutcome>,
    /// Exact least bound on its separation (None: some piece is unproved).
    pub lower_bound: Option<Exact>,
    /// Its worst-case separation: the least optimum over its pieces (None: no piece has
    /// one, or a pass-through is feasible).
    pub min_separation: Option<f64>,
}

impl ObstacleAnalysis {
    /// Every outcome: own pieces, then bystanders.
    pub fn outcomes(&self) -> impl Iterator<Item = &PieceOutcome> {
        self.own.iter().chain(&self.bystanders)
    }
}

/// The analyser's answer for a scene.
#[derive(Clone, Debug)]
pub struct SceneAnalysis {
    /// The scene analysed.
    pub scene: Scene,
    /// Its pieces.
    pub decomposition: SceneDecomposition,
    /// Per obstacle of the robot's lane, in scene order.
    pub obstacles: Vec<ObstacleAnalysis>,
    /// Exact least bound over every obstacle (None: some piece is unproved).
    pub lower_bound: Option<Exact>,
    /// s*: the least piece optimum over every obstacle (None: none, or the robot can pass
    /// an obstacle without braking).
    pub min_separation: Option<f64>,
    /// Some obstacle can pass through the reaction area while the robot never brakes.
    pub never_stops: bool,
    /// The worst case: index into `obstacles` and the piece.
    pub worst: Option<(usize, Piece)>,
    /// The worst-case behaviour, replayed exactly through the scene's step function.
    pub witness: Option<SceneWitness>,
    /// The verdict.
    pub verdict: Verdict,
    /// Linear programs handed to Clarabel.
    pub programs_solved: usize,
}

/// Why a scene was not analysed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneAnalysisError {
    /// The scene uses something the analyser does not decide yet.
    #[error("not analysed: {0}")]
    Unsupported(#[from] Unsupported),
    /// The run search did not finish, or found an inconsistency.
    #[error("{0}")]
    Search(String),
    /// The engines disagree: a certified bound and a colliding witness. A bug, reported
    /// rather than resolved either way.
    #[error("internal inconsistency: {0}")]
    Inconsistent(String),
    /// A search would pass its budget of analysed control periods.
    #[error(transparent)]
    OverBudget(#[from] crate::core::budget::OverBudget),
}

/// Analyses a (validated) scene.
pub fn analyse_scene(scene: &Scene) -> Result<SceneAnalysis, SceneAnalysisError> {
    let dec = SceneDecomposition::new(scene)?;
    let mut solved = 0;
    let mut obstacles: Vec<ObstacleAnalysis> = dec
        .obstacles
        .iter()
        .map(|o| ObstacleAnalysis {
            obstacle: o.obstacle,
            own: prove_all(&o.decomposition, &o.decomposition.pieces, &mut solved),
            bystanders: Vec::new(),
            lower_bound: None,
            min_separation: None,
        })
        .collect();
    for a in 0..obstacles.len() {
        let d = &dec.obstacles[a].decomposition;
        let pieces = dec.bystanders_needed(a, |step| {
            step.by_goal
                || step
                    .by_pieces
                    .iter()
                    .any(|&(b, p)| !proved_empty(&obstacles[b].own[p].result))
        });
        obstacles[a].bystanders = prove_all(d, &pieces, &mut solved);
    }
    let mut lower_bound = Some(least_start(&dec));
    let mut min_separation: Option<f64> = None;
    let mut never_stops = false;
    let mut worst = None;
    for (a, o) in obstacles.iter_mut().enumerate() {
        let Summary {
            unproved,
            bound,
            optimum,
            passes,
        } = summarise(o.outcomes());
        o.lower_bound = if unproved { None } else { bound.clone() };
        o.min_separation = optimum.map(|(v, _)| v);
        lower_bound = match (lower_bound, bound) {
            _ if unproved => None,
            (Some(l), Some(b)) if b < l => Some(b),
            (l, _) => l,
        };
        if let Some(piece) = passes {
            if !never_stops {
                worst = Some((a, piece));
            }
            never_stops = true;
        }
        if let Some((v, piece)) = optimum
            && !never_stops
            && min_separation.is_none_or(|m| v < m)
        {
            min_separation = Some(v);
            worst = Some((a, piece));
        }
    }
    if never_stops {
        min_separation = None;
    }
    let clearance = dec.scene.robot_params::<Exact>().clearance;
    let certified = lower_bound.as_ref().is_some_and(|l| *l > clearance);
    let witness = realise(&dec, &obstacles, &mut solved);
    let collides = witness.as_ref().is_some_and(|(w, _)| w.collides);
    if certified && collides {
        return Err(SceneAnalysisError::Inconsistent(
            "a certified bound above the clearance and a colliding witness".into(),
        ));
    }
    match &witness {
        // s* is the optimum of the piece whose witness realised it (as for one obstacle).
        Some((w, value)) if w.piece.has_objective() => min_separation = Some(*value),
        Some(_) => {}
        None if !never_stops => min_separation = None,
        None => {}
    }
    let witness = witness.map(|(w, _)| w);
    let verdict = if certified {
        Verdict::Certified
    } else if collides {
        Verdict::Refuted
    } else {
        Verdict::Inconclusive
    };
    Ok(SceneAnalysis {
        scene: scene.clone(),
        decomposition: dec,
        obstacles,
        lower_bound,
        min_separation,
        never_stops,
        worst,
        witness,
        verdict,
        programs_solved: solved,
    })
}

/// Proves every piece of one obstacle.
fn prove_all(
    d: &crate::proof::schedule::Decomposition,
    pieces: &[Piece],
    solved: &mut usize,
) -> Vec<PieceOutcome> {
    pieces
        .iter()
        .map(|piece| {
            let program: Program = d.program(piece);
            PieceOutcome {
                piece: *piece,
                result: prove(&program, piece, solved),
            }
        })
        .collect()
}

pub(crate) fn proved_empty(r: &PieceResult) -> bool {
    matches!(
        r,
        PieceResult::Proved {
            kind: ProofKind::Infeasible,
            ..
        }
    )
}

/// What one obstacle's outcomes add up to.
struct Summary {
    /// Some piece is unproved.
    unproved: bool,
    /// The least proved bound (None: no piece has one).
    bound: Option<Exact>,
    /// The least optimum, with its piece.
    optimum: Option<(f64, Piece)>,
    /// A feasible pass-through piece.
    passes: Option<Piece>,
}

fn summarise<'a>(outcomes: impl Iterator<Item = &'a PieceOutcome>) -> Summary {
    let mut bound: Option<Exact> = None;
    let mut unproved = false;
    let mut optimum: Option<(f64, Piece)> = None;
    let mut passes = None;
    for o in outcomes {
        match &o.result {
            PieceResult::Proved {
                kind: ProofKind::Bound,
                bound: b,
                optimum: opt,
                ..
            } => {
                if bound.as_ref().is_none_or(|l| b < l) {
                    bound = Some(b.clone());
                }
                if let Some((v, _)) = opt
                    && optimum.as_ref().is_none_or(|(m, _)| v < m)
                {
                    optimum = Some((*v, o.piece));
                }
            }
            PieceResult::Proved { .. } => {}
            PieceResult::Unproved { point, .. } => {
                unproved = true;
                if point.is_some() && !o.piece.has_objective() {
                    passes = Some(o.piece);
                }
            }
        }
    }
    Summary {
        unproved,
        bound,
        optimum,
        passes,
    }
}
