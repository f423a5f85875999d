//! Certificates: the analyser's answer in a form `check` re-verifies without the solver.
//!
//! A [`Certificate`] holds the problem, the verdict, the worst-case witness and one
//! [`Proof`] per piece of the problem's decomposition: the dual multipliers and the bound
//! they prove. [`check`] trusts none of the numbers it is given:
//!
//! 1. the digest over the certificate's content must match (an edit after the fact is
//!    named as such);
//! 2. the problem must be valid; its pieces are rebuilt from it, and the proofs must list
//!    exactly those pieces in order (a dropped, added or reordered piece is rejected);
//! 3. each proof's bound is recomputed in exact rationals from its multipliers
//!    ([`Program::bound`](crate::proof::program::Program::bound)) and must equal the stated one;
//!    infeasibility proofs must be positive;
//! 4. the witness's obstacle speeds are replayed exactly through the semantics and must
//!    reproduce the stated trace, collision and separation;
//! 5. the verdict must follow: `certified` iff every piece is proved and the least bound
//!    exceeds the clearance, `refuted` iff the witness collides.

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::core::model::Problem;
use crate::core::num::{Exact, exact_decimal, f64_at_most};
use crate::core::simulate;
pub use crate::proof::premise::{Premise, PremiseKind, premises};
use crate::proof::program::ProofKind;
use crate::proof::schedule::{Decomposition, Piece};
use crate::proof::verdict::{REPLAY_TOLERANCE, TRACE_TOLERANCE, Verdict, Witness};

/// The format tag written into every certificate.
pub const FORMAT: &str = "safereach-certificate/1";

/// One piece's proof.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Proof {
    /// The piece.
    pub piece: Piece,
    /// What the multipliers prove (`None`: no proof for this piece).
    pub kind: Option<ProofKind>,
    /// One multiplier per row of the piece's program.
    pub multipliers: Vec<f64>,
    /// The proved value, rounded down to a float.
    pub bound: Option<f64>,
}

/// The certificate file (and `certify --json` output).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Certificate {
    /// Always [`FORMAT`].
    pub format: String,
    /// The verdict.
    pub verdict: Verdict,
    /// s*, the worst-case minimum separation (m); null when the robot may never stop
    /// (s* = −∞) or no worst case could be realised.
    pub min_separation: Option<f64>,
    /// The worst case is a robot that never brakes (s* = −∞).
    pub never_stops: bool,
    /// Rigorous lower bound on s*, rounded down (null: no finite bound is proved).
    pub lower_bound: Option<f64>,
    /// The clearance (m).
    pub clearance: f64,
    /// Premises of the verdict.
    pub premises: Vec<Premise>,
    /// The worst-case behaviour: colliding when refuted, closest approach when certified.
    pub witness: Option<Witness>,
    /// The problem answered.
    pub problem: Problem,
    /// Number of pieces in the decomposition.
    pub pieces: usize,
    /// Linear programs handed to the solver.
    pub programs_solved: usize,
    /// One proof per piece, in decomposition order.
    pub proofs: Vec<Proof>,
    /// SHA-256 (hex) of this certificate serialised with an empty digest.
    pub digest: String,
}

impl Certificate {
    /// SHA-256 of the certificate with an empty digest field.
    pub fn compute_digest(&self) -> String {
        let mut copy = self.clone();
        copy.digest.clear();
        let text = serde_json::to_string(&copy).expect("certificates serialise");
        let hash = Sha256::digest(text.as_bytes());
        hash.iter().map(|b| format!("{b:02x}")).collect()
    }
}

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
    if cert.format != FORMAT {
        return invalid(format!("format is {:?}, expected {FORMAT:?}", cert.format));
    }
    if cert.compute_digest() != cert.digest {
        return invalid("digest mismatch: the certificate was edited after it was written");
    }
    cert.problem
        .validate("certificate problem")
        .map_err(|e| Invalid(format!("the certificate's problem is invalid: {e}")))?;
    let dec = Decomposition::new(&cert.problem);
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
                "proof {i} is for {:?}, but piece {i} is {piece:?}",
                proof.piece
            ));
        }
        let Some(kind) = &proof.kind else {
            all_proved = false;
            continue;
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
                "proof {i}: stated bound {:?} but the multipliers prove {}",
                proof.bound,
                f64_at_most(&exact)
            ));
        }
        match kind {
            ProofKind::Infeasible if program.proves_empty(&proof.multipliers).is_none() => {
                return invalid(format!(
                    "proof {i}: the multipliers do not prove the piece empty"
                ));
            }
            ProofKind::Infeasible => {}
            ProofKind::Bound => {
                if lower.as_ref().is_none_or(|l| exact < *l) {
                    lower = Some(exact);
                }
            }
        }
    }
    let params = &dec.params;
    let lower = if !all_proved {
        None
    } else {
        Some(lower.unwrap_or_else(|| params.g0.clone()))
    };
    if cert.lower_bound != lower.as_ref().map(f64_at_most) {
        return invalid(format!(
            "stated lower bound {:?}, proofs give {:?}",
            cert.lower_bound,
            lower.as_ref().map(f64_at_most)
        ));
    }
    if cert.clearance != cert.problem.robot.clearance {
        return invalid("clearance differs from the problem's");
    }
    if cert.premises != premises(&cert.problem) {
        return invalid("premises differ from the problem's");
    }
    let collides = match &cert.witness {
        // Without a witness there is nothing realising a worst case to report.
        None if cert.min_separation.is_some() || cert.never_stops => {
            return invalid("min_separation or never_stops is stated without a witness behind it");
        }
        None => false,
        Some(w) => check_witness(cert, w)?,
    };
    let certified = lower
        .as_ref()
        .is_some_and(|l| *l > exact_decimal(cert.problem.robot.clearance));
    let verdict = match (certified, collides) {
        (true, true) => return invalid("the proofs certify, yet the witness collides"),
        (true, false) => Verdict::Certified,
        (false, true) => Verdict::Refuted,
        (false, false) => Verdict::Inconclusive,
    };
    if verdict != cert.verdict {
        return invalid(format!(
            "stated verdict {} does not follow; the evidence gives {}",
            cert.verdict.as_str(),
            verdict.as_str()
        ));
    }
    Ok(CheckReport {
        verdict,
        pieces: dec.pieces.len(),
        lower_bound: lower,
    })
}

/// Replays a witness exactly; returns whether it collides.
fn check_witness(cert: &Certificate, w: &Witness) -> Result<bool, Invalid> {
    let params = cert.problem.params::<Exact>();
    let bound = &params.W;
    if let Some(k) = w
        .obstacle_speeds
        .iter()
        .position(|&s| s.is_nan() || s < 0.0 || crate::core::num::exact_float(s) > *bound)
    {
        return invalid(format!("witness speed in period {k} is outside [0, W]"));
    }
    let replay = simulate::replay(&params, &w.obstacle_speeds, w.obstacle_speeds.len(), false);
    if replay.periods() != w.obstacle_speeds.len() {
        return invalid("witness lists speeds past the end of its run");
    }
    let steps = replay.trace();
    let close = |a: f64, b: f64| (a - b).abs() <= TRACE_TOLERANCE;
    let same = steps.len() == w.steps.len()
        && steps.iter().zip(&w.steps).all(|(a, b)| {
            a.robot_mode == b.robot_mode
                && close(a.t, b.t)
                && close(a.robot_position, b.robot_position)
                && close(a.robot_speed, b.robot_speed)
                && close(a.obstacle_position, b.obstacle_position)
                && close(a.obstacle_speed, b.obstacle_speed)
                && close(a.gap, b.gap)
        });
    if !same {
        return invalid("witness trace differs from its exact replay");
    }
    if replay.collided() != w.collides {
        return invalid("witness collision flag differs from its exact replay");
    }
    let sep = replay.rest_gap().as_ref().map(f64_at_most);
    if sep.is_some() != w.separation.is_some()
        || sep
            .zip(w.separation)
            .is_some_and(|(a, b)| (a - b).abs() > 1e-12)
    {
        return invalid("witness separation differs from its exact replay");
    }
    match (cert.min_separation, w.separation) {
        (Some(s), Some(r)) if !(r >= s - REPLAY_TOLERANCE && r - s <= REPLAY_TOLERANCE) => {
            return invalid("min_separation is not reproduced by the witness");
        }
        (Some(s), _) if cert.lower_bound.is_some_and(|l| s < l - REPLAY_TOLERANCE) => {
            return invalid("min_separation lies below the proved lower bound");
        }
        (None, Some(_)) if cert.never_stops => {
            return invalid("never_stops, yet the witness stops");
        }
        _ => {}
    }
    if cert.never_stops && (w.separation.is_some() || !w.collides) {
        return invalid("never_stops requires a witness that collides without stopping");
    }
    Ok(replay.collided())
}
