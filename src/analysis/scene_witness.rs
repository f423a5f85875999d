//! A scene's worst case made concrete: the candidate pieces, least optimum first, turned
//! into per-obstacle speeds and replayed exactly through the scene's step function.
//!
//! The target obstacle follows its piece's solution (re-solved with strict rows a margin
//! inside); for a bystander piece the obstacle that makes the robot brake follows its own
//! firing piece's solution; every other obstacle stands still, which keeps it quiet up to
//! the brake step (that is how the pieces were cut).

use crate::analysis::analyse::{
    PieceResult, REPLAY_TOLERANCE, quantised as quantised_speed, speeds_from_point,
    witness_attempts,
};
use crate::analysis::lp::{self, LpOutcome, PointSource};
use crate::analysis::scene::{ObstacleAnalysis, proved_empty};
use crate::core::num::{Exact, f64_at_most};
use crate::core::scene::simulate;
use crate::proof::program::ProofKind;
use crate::proof::scene_certificate::{SceneWitness, Trigger};
use crate::proof::scene_check::scene_witness_realises;
use crate::proof::scene_schedule::SceneDecomposition;
use crate::proof::schedule::{Ending, Piece};
use crate::proof::witness_runs::Speeds;

/// The first candidate, least optimum first (a feasible pass-through first of all), whose
/// replay realises its optimum (or, for a pass-through, collides), with that optimum.
pub(crate) fn realise(
    dec: &SceneDecomposition,
    obstacles: &[ObstacleAnalysis],
    solved: &mut usize,
) -> Option<(SceneWitness, f64)> {
    let mut candidates: Vec<(f64, usize, Piece)> = Vec::new();
    for (a, o) in obstacles.iter().enumerate() {
        for outcome in o.outcomes() {
            match &outcome.result {
                PieceResult::Proved {
                    kind: ProofKind::Bound,
                    optimum: Some((v, _)),
                    ..
                } => candidates.push((*v, a, outcome.piece)),
                PieceResult::Unproved { point: Some(_), .. } if !outcome.piece.has_objective() => {
                    candidates.push((f64::NEG_INFINITY, a, outcome.piece))
                }
                _ => {}
            }
        }
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0));
    for (value, a, piece) in candidates {
        for (source, margin) in witness_attempts(&piece) {
            let how = PointSpec { margin, source };
            let Some(w) = attempt(dec, obstacles, a, &piece, how, solved) else {
                continue;
            };
            let realised = if piece.has_objective() {
                w.separation
                    .is_some_and(|s| (s - value).abs() <= REPLAY_TOLERANCE)
            } else {
                w.collides
            };
            if realised {
                return Some((w, value));
            }
        }
    }
    None
}

/// How a witness attempt solves for its points: strict rows `margin` inside, from `source`.
#[derive(Clone, Copy)]
struct PointSpec {
    margin: f64,
    source: PointSource,
}

/// Speeds for obstacle `a` of the lane from its piece's margin solution: (shift, speeds).
fn piece_speeds(
    dec: &SceneDecomposition,
    a: usize,
    piece: &Piece,
    how: PointSpec,
    solved: &mut usize,
) -> Option<(usize, Vec<f64>)> {
    let d = &dec.obstacles[a].decomposition;
    let program = d.program(piece);
    *solved += 1;
    let LpOutcome::Optimal { x, .. } = lp::solve_for_point(&program, how.margin, how.source) else {
        return None;
    };
    // (Scenes observe every obstacle from the start: no sighting to carry.)
    let (shift, speeds, _) = speeds_from_point(d, piece, &program, &x);
    Some((shift, speeds.to_vec()))
}

/// One witness attempt for obstacle `a`'s piece at one margin.
fn attempt(
    dec: &SceneDecomposition,
    obstacles: &[ObstacleAnalysis],
    a: usize,
    piece: &Piece,
    how: PointSpec,
    solved: &mut usize,
) -> Option<SceneWitness> {
    let scene = &dec.scene;
    let (shift, target) = piece_speeds(dec, a, piece, how, solved)?;
    let brake = piece.brake + shift;
    let mut trigger = None;
    let mut fired: Option<(usize, Vec<f64>)> = None;
    if piece.ending == Ending::Bystander {
        // (A merged bystander piece stands for its shifts: the step its solution brakes at.)
        let step = dec
            .bystander_steps(a)
            .into_iter()
            .find(|s| s.step == brake)?;
        if step.by_goal {
            trigger = Some(Trigger::Goal);
        } else {
            for &(b, p) in &step.by_pieces {
                if proved_empty(&obstacles[b].own[p].result) {
                    continue;
                }
                // The firing piece's own shift at this step (a merged piece stands for it).
                let Some(firing) = obstacles[b].own[p].piece.shifted_to(brake) else {
                    continue;
                };
                if let Some((0, speeds)) = piece_speeds(dec, b, &firing, how, solved) {
                    trigger = Some(Trigger::Obstacle {
                        obstacle: dec.obstacles[b].obstacle,
                        piece: firing,
                    });
                    fired = Some((b, speeds));
                    break;
                }
            }
            trigger.as_ref()?;
        }
    }
    let params = scene.params::<Exact>();
    let max_steps = brake + simulate::horizon(&scene.params::<f64>());
    let mut speeds: Vec<Vec<f64>> = vec![vec![0.0; max_steps]; scene.obstacles.len()];
    let mut place = |b: usize, mut s: Vec<f64>| {
        let i = dec.obstacles[b].obstacle;
        s.resize(max_steps, quantised_speed(&params.obstacles[i].max_speed));
        speeds[i] = s;
    };
    place(a, target);
    if let Some((b, s)) = fired {
        place(b, s);
    }
    let starts: Vec<Exact> = params
        .obstacles
        .iter()
        .map(|o| o.start_min.clone())
        .collect();
    let replay = simulate::replay(&params, &speeds, &starts, max_steps, !piece.has_objective());
    for s in &mut speeds {
        s.truncate(replay.periods());
    }
    let i = dec.obstacles[a].obstacle;
    let witness = SceneWitness {
        obstacle: i,
        lane: scene.obstacles[i].lane,
        piece: *piece,
        trigger,
        margin: how.margin,
        obstacle_speeds: speeds.iter().map(|s| Speeds::from_periods(s)).collect(),
        collides: replay.collided(),
        separation: replay.separations()[i].as_ref().map(f64_at_most),
        steps: replay.trace(),
    };
    // Only a run of the piece it names (check holds it to that).
    scene_witness_realises(&witness, &replay).ok()?;
    Some(witness)
}
