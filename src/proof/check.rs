//! `check`: a certificate re-verified from the problem alone, in exact rationals, without
//! the solver (what it checks, step by step, is listed in [`crate::proof::certificate`]).

use crate::core::num::{Exact, exact_decimal, f64_at_most};
use crate::core::simulate;
use crate::proof::certificate::{Certificate, FORMAT, Proof, premises};
use crate::proof::program::ProofKind;
use crate::proof::schedule::{Decomposition, Piece};
use crate::proof::separation::{Stated, settle};
use crate::proof::verdict::{Verdict, Witness, rows_match};
use crate::proof::witness_schedule::replay_realises;

/// What `check` established.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckReport {
    /// The verdict, re-derived.
    pub verdict: Verdict,
    /// Pieces whose proofs were verified.
    pub pieces: usize,
    /// The exact least bound (None: not all pieces proved).
    pub lower_bound: Option<Exact>,
}

/// Why a certificate is rejected.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{0}")]
pub struct Invalid(pub String);

fn invalid<T>(msg: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(msg.into()))
}

/// Re-verifies a certificate without the solver (see the module docs for what is checked).
pub fn check(cert: &Certificate) -> Result<CheckReport, Invalid> {
    check_envelope(cert)?;
    if cert.problem.environment.initial_gap.is_range() {
        // This kind's witness has one start; ranges get scene search certificates.
        return invalid(
            "the problem's initial gap is a range, which this certificate kind does not cover; \
             a range is certified by a scene search certificate",
        );
    }
    let dec = Decomposition::new(&cert.problem);
    let lower = check_proofs(cert, &dec)?;
    check_claims(cert, lower.as_ref())?;
    let collides = match &cert.witness {
        // Without a witness there is nothing realising a worst case to report.
        None if cert.min_separation.is_some() || cert.never_stops => {
            return invalid("min_separation or never_stops is stated without a witness behind it");
        }
        None => false,
        Some(w) => check_witness(cert, w, &dec)?,
    };
    let certified = lower
        .as_ref()
        .is_some_and(|l| *l > exact_decimal(cert.problem.robot.clearance));
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
        pieces: dec.pieces.len(),
        lower_bound: lower,
    })
}

/// The format tag, the digest and the problem's validity.
fn check_envelope(cert: &Certificate) -> Result<(), Invalid> {
    if cert.format != FORMAT {
        return invalid(format!("format is {:?}, expected {FORMAT:?}", cert.format));
    }
    if cert.compute_digest() != cert.digest {
        return invalid("digest mismatch: the certificate was edited after it was written");
    }
    cert.problem
        .validate("certificate problem")
        .map_err(|e| Invalid(format!("the certificate's problem is invalid: {e}")))
}

/// Every proof against the piece rebuilt from the problem; returns the exact least bound
/// (None when some piece is unproved; the initial gap when every piece is empty).
fn check_proofs(cert: &Certificate, dec: &Decomposition) -> Result<Option<Exact>, Invalid> {
    if cert.pieces != dec.pieces.len() || cert.proofs.len() != dec.pieces.len() {
        return invalid(format!(
            "the problem has {} pieces; the certificate lists {} proofs",
            dec.pieces.len(),
            cert.proofs.len()
        ));
    }
    let mut lower: Option<Exact> = None;
    let mut all_proved = true;
    for (i, (proof, piece)) in cert.proofs.iter().zip(&dec.pieces).enumerate() {
        if proof.piece != *piece {
            return invalid(format!(
                "proof {i} is for {}, but piece {i} of the problem is {}",
                proof.piece.describe(),
                piece.describe()
            ));
        }
        match check_proof(i, proof, piece, dec)? {
            None => all_proved = false,
            Some((ProofKind::Bound, exact)) if lower.as_ref().is_none_or(|l| exact < *l) => {
                lower = Some(exact);
            }
            Some(_) => {}
        }
    }
    Ok(all_proved.then(|| lower.unwrap_or_else(|| dec.params.g0.clone())))
}

/// One proof: its bound recomputed exactly and equal to the stated one, an infeasibility
/// proof really proving the piece empty. None for a piece stated as unproved.
pub(crate) fn check_proof(
    i: usize,
    proof: &Proof,
    piece: &Piece,
    dec: &Decomposition,
) -> Result<Option<(ProofKind, Exact)>, Invalid> {
    let Some(kind) = &proof.kind else {
        return Ok(None);
    };
    let program = dec.program(piece);
    let objective = *kind == ProofKind::Bound;
    if objective && !piece.has_objective() {
        return invalid(format!(
            "proof {i}: a pass-through piece needs an infeasibility proof"
        ));
    }
    let Some(exact) = program.bound(&proof.multipliers, objective) else {
        return invalid(format!(
            "proof {i}: multipliers malformed or prove no finite bound"
        ));
    };
    if proof.bound != Some(f64_at_most(&exact)) {
        return invalid(format!(
            "proof {i}: stated bound {} but the multipliers prove {}",
            shown(proof.bound),
            f64_at_most(&exact)
        ));
    }
    if *kind == ProofKind::Infeasible && program.proves_empty(&proof.multipliers).is_none() {
        return invalid(format!(
            "proof {i}: the multipliers do not prove the piece empty"
        ));
    }
    Ok(Some((kind.clone(), exact)))
}

/// The stated lower bound, clearance and premises against what the proofs and problem give.
fn check_claims(cert: &Certificate, lower: Option<&Exact>) -> Result<(), Invalid> {
    if cert.lower_bound != lower.map(f64_at_most) {
        return invalid(format!(
            "stated lower bound {}, the proofs give {}",
            shown(cert.lower_bound),
            shown(lower.map(f64_at_most))
        ));
    }
    if cert.clearance != cert.problem.robot.clearance {
        return invalid("clearance differs from the problem's");
    }
    if cert.premises != premises(&cert.problem) {
        return invalid("premises differ from the problem's");
    }
    Ok(())
}

/// An optional number in words: the number, or "none" (for null).
pub(crate) fn shown(x: Option<f64>) -> String {
    x.map_or_else(|| "none".to_string(), |x| x.to_string())
}

/// Replays a witness exactly; returns whether it collides. The replay must reproduce the
/// stated trace, collision and separation, and be a run of the piece and shift it names.
fn check_witness(cert: &Certificate, w: &Witness, dec: &Decomposition) -> Result<bool, Invalid> {
    let params = &dec.params;
    let bound = &params.W;
    if let Some(k) = w
        .obstacle_speeds
        .segments()
        .iter()
        .find(|s| outside(s.speed, bound))
        .map(|s| s.start)
    {
        return invalid(format!("witness speed in period {k} is outside [0, W]"));
    }
    if !dec.pieces.contains(&w.piece) {
        return invalid(format!(
            "the witness's piece ({}) is not a piece of the problem",
            w.piece.describe()
        ));
    }
    if w.first_seen.is_some() && !(w.piece.detected && w.piece.early) {
        return invalid(
            "the witness states first_seen, but only a piece first seen in the area by its \
             early entry has one to choose",
        );
    }
    let speeds = w.obstacle_speeds.segments();
    let periods = w.obstacle_speeds.len();
    let replay = simulate::replay_segments(params, speeds, None, w.aim(), periods, false, false);
    if replay.periods() != periods {
        return invalid("witness lists speeds past the end of its run");
    }
    if replay.run.modes != w.robot_modes {
        return invalid("witness robot modes differ from its exact replay");
    }
    // The per-period rows are optional (`certify --steps`); when present they must match
    // the replay recorded period by period (the same run, every period stepped).
    let same = w.steps.is_empty() || {
        let steps =
            simulate::replay_segments(params, speeds, None, w.aim(), periods, false, true).trace();
        steps.len() == w.steps.len() && steps.iter().zip(&w.steps).all(|(a, b)| rows_match(a, b))
    };
    if !same {
        return invalid("witness trace differs from its exact replay");
    }
    if replay.collided() != w.collides {
        return invalid("witness collision flag differs from its exact replay");
    }
    if replay.rest_gap().as_ref().map(f64_at_most) != w.separation {
        return invalid("witness separation differs from its exact replay");
    }
    replay_realises(params, &replay, &w.piece, w.shift).map_err(Invalid)?;
    if cert.min_separation.is_none() && w.separation.is_some() && cert.never_stops {
        return invalid("never_stops, yet the witness stops");
    }
    if cert.never_stops && (w.separation.is_some() || !w.collides) {
        return invalid("never_stops requires a witness that collides without stopping");
    }
    Ok(replay.collided())
}

/// The first period whose speed is outside [0, `bound`] (NaN included), exactly; each run
/// of equal speeds is judged once, so a long constant stretch costs one comparison.
pub(crate) fn first_outside(speeds: &[f64], bound: &Exact) -> Option<usize> {
    let mut judged: Option<u64> = None;
    speeds.iter().position(|&s| {
        if judged == Some(s.to_bits()) {
            return false;
        }
        judged = Some(s.to_bits());
        outside(s, bound)
    })
}

/// Whether a speed is outside [0, `bound`] (NaN included), exactly.
fn outside(s: f64, bound: &Exact) -> bool {
    s.is_nan() || s < 0.0 || crate::core::num::exact_float(s) > *bound
}
