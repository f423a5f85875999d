//! `check` for scene certificates: every proof re-verified from the scene alone, in exact
//! rationals, without the solver.
//!
//! 1. the format tag and digest; the scene must be valid and one the analyser decides;
//! 2. per obstacle of the robot's lane, the own pieces are rebuilt from the scene and the
//!    proofs must list exactly them, in order; each bound is recomputed exactly;
//! 3. the bystander pieces are rebuilt too: a bystander step is required unless every
//!    firing piece of another obstacle at that step carries a verified emptiness proof and
//!    the destination does not brake then — so a certificate cannot leave out a case by
//!    claiming a firing piece empty without proving it;
//! 4. the witness's speeds are replayed exactly through the scene's step function and must
//!    reproduce its trace, collision and separation;
//! 5. the verdict must follow.

use crate::core::num::{Exact, Scalar, exact_decimal, exact_float, f64_at_most};
use crate::core::scene::simulate;
use crate::core::scene::simulate::SceneTraceRow;
use crate::core::semantics::BrakeReason;
use crate::proof::check::shown;
use crate::proof::check::{CheckReport, Invalid, check_proof};
use crate::proof::program::ProofKind;
use crate::proof::scene_certificate::{
    ObstacleProofs, SCENE_FORMAT, SceneCertificate, SceneWitness, Trigger, scene_premises,
};
use crate::proof::scene_schedule::SceneDecomposition;
use crate::proof::schedule::{Ending, Piece};
use crate::proof::separation::{Stated, settle};
#[cfg(doc)]
use crate::proof::verdict::TRACE_TOLERANCE;
use crate::proof::verdict::rows_match;
use crate::proof::witness_runs::Speeds;
use crate::proof::witness_schedule::{RunSchedule, realises};

fn invalid<T>(msg: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(msg.into()))
}

/// Re-verifies a scene certificate without the solver.
pub fn check_scene(cert: &SceneCertificate) -> Result<CheckReport, Invalid> {
    if cert.format != SCENE_FORMAT {
        return invalid(format!(
            "format is {:?}, expected {SCENE_FORMAT:?}",
            cert.format
        ));
    }
    if cert.compute_digest() != cert.digest {
        return invalid("digest mismatch: the certificate was edited after it was written");
    }
    cert.scene
        .validate("certificate scene")
        .map_err(|e| Invalid(format!("the certificate's scene is invalid: {e}")))?;
    let dec = SceneDecomposition::new(&cert.scene)
        .map_err(|e| Invalid(format!("the certificate's scene is not analysable: {e}")))?;
    if cert.obstacles.len() != dec.obstacles.len() {
        return invalid(format!(
            "the robot's lane has {} obstacles; the certificate has proofs for {}",
            dec.obstacles.len(),
            cert.obstacles.len()
        ));
    }
    let mut empty: Vec<Vec<bool>> = Vec::new();
    let mut lower: Option<Exact> = None;
    let mut all_proved = true;
    let mut pieces = 0;
    for (a, proofs) in cert.obstacles.iter().enumerate() {
        let o = &dec.obstacles[a];
        let name = &cert.scene.obstacles[o.obstacle].name;
        if proofs.obstacle != o.obstacle || proofs.name != *name {
            return invalid(format!(
                "proofs {a} are for obstacle {} ({:?}); the lane's obstacle {a} is {} ({name:?})",
                proofs.obstacle, proofs.name, o.obstacle
            ));
        }
        let results = check_list(name, "own", &proofs.own, &o.decomposition.pieces, &dec, a)?;
        pieces += results.len();
        empty.push(
            results
                .iter()
                .map(|r| matches!(r, Some((ProofKind::Infeasible, _))))
                .collect(),
        );
        fold(&results, &mut lower, &mut all_proved);
    }
    for (a, proofs) in cert.obstacles.iter().enumerate() {
        let name = &cert.scene.obstacles[dec.obstacles[a].obstacle].name;
        let needed = required_bystanders(&dec, a, &empty);
        let results = check_list(name, "bystander", &proofs.bystanders, &needed, &dec, a)?;
        pieces += results.len();
        fold(&results, &mut lower, &mut all_proved);
        check_obstacle_bound(name, proofs)?;
    }
    let lower = all_proved.then(|| lower.unwrap_or_else(|| least_start(&dec)));
    check_claims(cert, lower.as_ref())?;
    let collides = match &cert.witness {
        None if cert.min_separation.is_some() || cert.never_stops => {
            return invalid("min_separation or never_stops is stated without a witness behind it");
        }
        None => false,
        Some(w) => check_witness(cert, w)?,
    };
    let certified = lower
        .as_ref()
        .is_some_and(|l| *l > exact_decimal(cert.scene.robot.clearance));
    let verdict = settle(
        certified,
        collides,
        Stated {
            verdict: cert.verdict,
            min_separation: cert.min_separation,
            tolerance: cert.separation_tolerance,
            lower_bound: cert.lower_bound,
            witness_separation: cert.witness.as_ref().and_then(|w| w.separation),
        },
    )
    .map_err(Invalid)?;
    Ok(CheckReport {
        verdict,
        pieces,
        lower_bound: lower,
    })
}

type Checked = Option<(ProofKind, Exact)>;

/// The bystander pieces obstacle `a` must have proofs for, given which own pieces of every
/// obstacle are proved empty.
fn required_bystanders(dec: &SceneDecomposition, a: usize, empty: &[Vec<bool>]) -> Vec<Piece> {
    dec.bystanders_needed(a, |step| {
        step.by_goal || step.by_pieces.iter().any(|&(b, p)| !empty[b][p])
    })
}

/// One list of proofs against the pieces rebuilt from the scene.
fn check_list(
    name: &str,
    what: &str,
    proofs: &[crate::proof::certificate::Proof],
    pieces: &[Piece],
    dec: &SceneDecomposition,
    a: usize,
) -> Result<Vec<Checked>, Invalid> {
    if proofs.len() != pieces.len() {
        return invalid(format!(
            "obstacle {name:?} has {} {what} pieces; the certificate lists {} proofs",
            pieces.len(),
            proofs.len()
        ));
    }
    let d = &dec.obstacles[a].decomposition;
    proofs
        .iter()
        .zip(pieces)
        .enumerate()
        .map(|(i, (proof, piece))| {
            if proof.piece != *piece {
                return invalid(format!(
                    "obstacle {name:?}: {what} proof {i} is for {}, but the piece is {}",
                    proof.piece.describe(),
                    piece.describe()
                ));
            }
            check_proof(i, proof, piece, d)
                .map_err(|e| Invalid(format!("obstacle {name:?}, {what}: {}", e.0)))
        })
        .collect()
}

fn fold(results: &[Checked], lower: &mut Option<Exact>, all_proved: &mut bool) {
    for r in results {
        match r {
            None => *all_proved = false,
            Some((ProofKind::Bound, b)) if lower.as_ref().is_none_or(|l| b < l) => {
                *lower = Some(b.clone());
            }
            Some(_) => {}
        }
    }
}

/// An obstacle's stated lower bound must be what its own and bystander proofs give.
fn check_obstacle_bound(name: &str, proofs: &ObstacleProofs) -> Result<(), Invalid> {
    let stated = proofs.lower_bound;
    let bounds = proofs
        .own
        .iter()
        .chain(&proofs.bystanders)
        .filter(|p| p.kind == Some(ProofKind::Bound))
        .filter_map(|p| p.bound);
    let unproved = proofs
        .own
        .iter()
        .chain(&proofs.bystanders)
        .any(|p| p.kind.is_none());
    let least = bounds.fold(None, |m: Option<f64>, b| Some(m.map_or(b, |m| m.min(b))));
    let expected = if unproved { None } else { least };
    if stated != expected {
        return invalid(format!(
            "obstacle {name:?}: stated lower bound {}, its proofs give {}",
            shown(stated),
            shown(expected)
        ));
    }
    Ok(())
}

/// The nearest start of an obstacle in the robot's lane (the bound when no piece has one).
pub fn least_start(dec: &SceneDecomposition) -> Exact {
    dec.obstacles
        .iter()
        .map(|o| <Exact as Scalar>::decimal(dec.scene.obstacles[o.obstacle].position.min()))
        .min()
        .unwrap_or(Exact::ONE)
}

fn check_claims(cert: &SceneCertificate, lower: Option<&Exact>) -> Result<(), Invalid> {
    if cert.lower_bound != lower.map(f64_at_most) {
        return invalid(format!(
            "stated lower bound {}, the proofs give {}",
            shown(cert.lower_bound),
            shown(lower.map(f64_at_most))
        ));
    }
    if cert.clearance != cert.scene.robot.clearance {
        return invalid("clearance differs from the scene's");
    }
    if cert.premises != scene_premises(&cert.scene) {
        return invalid("premises differ from the scene's");
    }
    Ok(())
}

/// Replays a scene witness exactly; returns whether it collides.
fn check_witness(cert: &SceneCertificate, w: &SceneWitness) -> Result<bool, Invalid> {
    let scene = &cert.scene;
    let params = scene.params::<Exact>();
    if w.obstacle_speeds.len() != scene.obstacles.len() {
        return invalid("witness lists speeds for another number of obstacles");
    }
    if w.obstacle >= scene.obstacles.len() || w.lane != scene.obstacles[w.obstacle].lane {
        return invalid("witness names an obstacle or lane the scene does not have");
    }
    for (i, speeds) in w.obstacle_speeds.iter().enumerate() {
        let bound = &params.obstacles[i].max_speed;
        if let Some(bad) = speeds
            .segments()
            .iter()
            .find(|s| s.speed.is_nan() || s.speed < 0.0 || exact_float(s.speed) > *bound)
        {
            return invalid(format!(
                "witness speed of obstacle {:?} in period {} is outside [0, W]",
                scene.obstacles[i].name, bad.start
            ));
        }
    }
    let periods = w.obstacle_speeds.iter().map(Speeds::len).max().unwrap_or(0);
    let per_period: Vec<Vec<f64>> = w.obstacle_speeds.iter().map(Speeds::to_vec).collect();
    let starts: Vec<Exact> = params
        .obstacles
        .iter()
        .map(|o| o.start_min.clone())
        .collect();
    let replay = simulate::replay(&params, &per_period, &starts, periods, false);
    if replay.periods() != periods {
        return invalid("witness lists speeds past the end of its run");
    }
    if !w.steps.is_empty() && !same_scene_trace(&replay.trace(), &w.steps) {
        return invalid("witness trace differs from its exact replay");
    }
    if replay.collided() != w.collides {
        return invalid("witness collision flag differs from its exact replay");
    }
    let sep = replay.separations()[w.obstacle].as_ref().map(f64_at_most);
    if sep != w.separation {
        return invalid("witness separation differs from its exact replay");
    }
    check_scene_piece(cert, w, &replay).map_err(Invalid)?;
    if cert.never_stops && !w.collides {
        return invalid("never_stops requires a witness that collides");
    }
    Ok(replay.collided())
}

/// What a scene replay shows of scene obstacle `i`'s schedule.
fn schedule_of(replay: &simulate::SceneReplay, i: usize) -> RunSchedule {
    let run = &replay.run;
    RunSchedule::of(
        run.records.iter().map(|r| r.obstacles[i].seen.as_ref()),
        run.outcome.brake,
        &replay.params.robot.rho,
        &replay.params.robot.V_a,
    )
}

/// The shift by which a run realises a merged piece: read off the step the run shows for
/// the piece's brake step (its brake, the obstacle seen passed, or the run's end).
fn shift_of(piece: &Piece, run: &RunSchedule) -> usize {
    if !piece.merged {
        return 0;
    }
    let t = match (run.brake, run.passed) {
        (Some((k, _)), _) => k,
        (None, Some(k)) => k,
        (None, None) => run.steps,
    };
    t.saturating_sub(piece.brake)
}

/// The scene witness is a run of the piece it names: one of its obstacle's pieces in the
/// certificate (and a trigger piece of another obstacle of the lane), realised by the replay
/// ([`scene_witness_realises`]).
fn check_scene_piece(
    cert: &SceneCertificate,
    w: &SceneWitness,
    replay: &simulate::SceneReplay,
) -> Result<(), String> {
    let proofs_of = |i: usize| cert.obstacles.iter().find(|o| o.obstacle == i);
    let Some(own) = proofs_of(w.obstacle) else {
        return Err("the witness's obstacle is not in the robot's lane".into());
    };
    let listed = if w.piece.ending == Ending::Bystander {
        &own.bystanders
    } else {
        &own.own
    };
    if !listed.iter().any(|p| p.piece == w.piece) {
        return Err(format!(
            "the witness's piece ({}) is not a piece of obstacle {:?}",
            w.piece.describe(),
            own.name
        ));
    }
    if let Some(Trigger::Obstacle { obstacle, piece }) = &w.trigger {
        // Listed itself, or one shift of a listed merged piece.
        let listed = proofs_of(*obstacle).is_some_and(|o| {
            *obstacle != w.obstacle
                && o.own
                    .iter()
                    .any(|p| p.piece.shifted_to(piece.brake) == Some(*piece))
        });
        if !listed {
            return Err(format!(
                "the witness's trigger ({}) is not a piece of another obstacle of the lane",
                piece.describe()
            ));
        }
    }
    scene_witness_realises(w, replay)
}

/// Whether a scene witness's replay is a run of its piece ([`realises`]): a bystander
/// piece's robot brakes at its step for the stated trigger — the destination, or another
/// obstacle through its own piece, which the replay realises too; other pieces name no
/// trigger. (The analyser keeps only witnesses that pass, and `check` holds them to it.)
pub fn scene_witness_realises(
    w: &SceneWitness,
    replay: &simulate::SceneReplay,
) -> Result<(), String> {
    let run = schedule_of(replay, w.obstacle);
    let shift = shift_of(&w.piece, &run);
    realises(&w.piece, shift, &run, true)?;
    // The step the robot brakes at (a merged bystander piece's shift of it).
    let t = w.piece.brake + shift;
    match (&w.trigger, w.piece.ending) {
        (None, Ending::Bystander) => Err("a bystander witness must name its trigger".into()),
        (None, _) => Ok(()),
        (Some(_), ending) if ending != Ending::Bystander => {
            Err("only a bystander witness names a trigger".into())
        }
        (Some(Trigger::Goal), _) => {
            if run.brake == Some((t, BrakeReason::Destination)) {
                Ok(())
            } else {
                Err(format!(
                    "the witness says the robot brakes for its destination at step {t}, but its \
                     replay does not"
                ))
            }
        }
        (Some(Trigger::Obstacle { obstacle, piece }), _) => {
            if piece.brake != t || *obstacle >= replay.params.obstacles.len() {
                return Err(format!(
                    "the witness's trigger ({}) does not fire at its brake step {t}",
                    piece.describe(),
                ));
            }
            let other = schedule_of(replay, *obstacle);
            realises(piece, 0, &other, true).map_err(|e| format!("the witness's trigger: {e}"))
        }
    }
}

/// Whether a witness's stated trace is its replay's: the same rows, lanes and modes, every
/// number within [`TRACE_TOLERANCE`] (search and scene witnesses alike).
pub(crate) fn same_scene_trace(replayed: &[SceneTraceRow], stated: &[SceneTraceRow]) -> bool {
    replayed.len() == stated.len()
        && replayed.iter().zip(stated).all(|(x, y)| {
            let (a, b) = (&x.row, &y.row);
            x.obstacle == y.obstacle
                && x.robot_lane == y.robot_lane
                && x.leaving_lane == y.leaving_lane
                && x.obstacle_lane == y.obstacle_lane
                && rows_match(a, b)
        })
}
