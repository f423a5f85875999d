//! Certifying a whole box of parameter values with one proof per piece.
//!
//! The box's pieces and programs come from
//! [`Decomposition::for_box`](crate::proof::schedule::Decomposition::for_box), taken at the
//! box's centre. Each piece's multipliers come from the parent box's proof of the same piece
//! or from Clarabel at the centre (exact arithmetic, not the solver, is what costs here); the
//! exact affine bound they prove is then minimised over the box
//! ([`box_proof_value`]). A bound that does not clear the clearance may still belong to a
//! piece whose strict system is empty (its closure holds only on a guard's boundary): the
//! snapped Farkas multipliers of [`prove_strictly_empty`] are tried before giving up.

use rustc_hash::FxHashMap;

use crate::analysis::analyse::prove_strictly_empty;
use crate::analysis::lp::{self, LpOutcome};
use crate::core::model::Problem;
use crate::core::num::{Exact, f64_at_most};
use crate::core::param_box::ParamBox;
use crate::core::parameter::{ParamAffine, Parameter};
use crate::proof::program::{Program, ProofKind};
use crate::proof::region_check::{box_proof_value, describe};
use crate::proof::region_map::BoxProof;
use crate::proof::schedule::{Decomposition, Piece};

/// Proofs found for a box's pieces, handed to its halves to try before the solver.
pub type Hints = FxHashMap<Piece, (ProofKind, Vec<f64>)>;

/// A box certified: every piece proved, s* above the clearance everywhere in it.
#[derive(Clone, Debug)]
pub struct BoxCertificate {
    /// One proof per piece, in decomposition order.
    pub proofs: Vec<BoxProof>,
    /// The least lower bound on s* over the box.
    pub lower_bound: Exact,
}

/// A box not certified (yet): why, and the proofs found on the way.
#[derive(Clone, Debug)]
pub struct NotCertified {
    /// Why, in the model's words.
    pub reason: String,
    /// Proofs found for some pieces (the halves try them first).
    pub hints: Hints,
}

/// Tries to certify `problem` over every point of `b`.
pub fn certify_box(
    problem: &Problem,
    b: &ParamBox,
    hints: &Hints,
    solved: &mut usize,
) -> Result<BoxCertificate, NotCertified> {
    let dec = Decomposition::for_box(problem, b);
    let clearance = ParamAffine::parameter(Parameter::Clearance, &dec.params);
    let mut proofs = Vec::with_capacity(dec.pieces.len());
    let mut found = Hints::default();
    let mut lower: Option<Exact> = None;
    for piece in &dec.pieces {
        let program = dec.program(piece);
        let proved = prove_piece(
            &dec,
            b,
            &program,
            piece,
            &clearance,
            hints.get(piece),
            solved,
        );
        match proved {
            Ok((kind, z, bound)) => {
                let least = bound.as_ref().map(|f| b.min_of(f, &dec.params));
                if let Some(l) = &least
                    && lower.as_ref().is_none_or(|x| l < x)
                {
                    lower = Some(l.clone());
                }
                found.insert(*piece, (kind.clone(), z.clone()));
                proofs.push(BoxProof {
                    piece: *piece,
                    kind,
                    multipliers: z,
                    bound: least.as_ref().map(f64_at_most),
                });
            }
            Err(reason) => {
                return Err(NotCertified {
                    reason: format!("{}: {reason}", describe(piece)),
                    hints: found,
                });
            }
        }
    }
    let start = ParamAffine::parameter(Parameter::InitialGap, &dec.params);
    if proofs.iter().all(|p| p.kind == ProofKind::Infeasible)
        && b.min_of(&(start.clone() - clearance), &dec.params) <= Exact::ZERO
    {
        return Err(NotCertified {
            reason: "the obstacle may start within the clearance".into(),
            hints: found,
        });
    }
    Ok(BoxCertificate {
        proofs,
        lower_bound: lower.unwrap_or_else(|| b.min_of(&start, &dec.params)),
    })
}

/// A proof of one piece over the box: its kind, multipliers and (for a bound) the affine
/// bound, which clears the clearance at every point; else why not.
fn prove_piece(
    dec: &Decomposition,
    b: &ParamBox,
    program: &Program,
    piece: &Piece,
    clearance: &ParamAffine,
    hint: Option<&(ProofKind, Vec<f64>)>,
    solved: &mut usize,
) -> Result<(ProofKind, Vec<f64>, Option<ParamAffine>), String> {
    let holds = |kind: &ProofKind, z: &[f64]| -> Option<Option<ParamAffine>> {
        let value = box_proof_value(b, &dec.params, program, piece, kind, z).ok()?;
        match &value {
            Some(bound)
                if b.min_of(&(bound.clone() - clearance.clone()), &dec.params) <= Exact::ZERO =>
            {
                None
            }
            _ => Some(value),
        }
    };
    if let Some((kind, z)) = hint
        && z.len() == program.rows.len()
        && let Some(value) = holds(kind, z)
    {
        return Ok((kind.clone(), z.clone(), value));
    }
    *solved += 1;
    let reason = match lp::solve(program, 0.0) {
        LpOutcome::Optimal { z, value, .. } if piece.has_objective() => {
            // The affine bound at the centre is at most the optimum there: no need to
            // evaluate it exactly when the optimum does not clear the clearance.
            if value > clearance.value.to_f64().value()
                && let Some(v) = holds(&ProofKind::Bound, &z)
            {
                return Ok((ProofKind::Bound, z, v));
            }
            format!("its worst case at the centre is {value:.6} m, too close for the whole box")
        }
        LpOutcome::Optimal { .. } => "a robot that never brakes is possible at the centre".into(),
        LpOutcome::Infeasible { z } => {
            if let Some(v) = holds(&ProofKind::Infeasible, &z) {
                return Ok((ProofKind::Infeasible, z, v));
            }
            "empty at the centre, but not provably so over the whole box".into()
        }
        LpOutcome::Failed { status } => {
            // Without the solver's multipliers, the cheap Farkas candidates.
            let rows = program.rows.len();
            let mut candidates = vec![vec![1.0; rows]];
            if let Some(i) = program.infeasible_row() {
                let mut z = vec![0.0; rows];
                z[i] = 1.0;
                candidates.push(z);
            }
            for z in candidates {
                if let Some(v) = holds(&ProofKind::Infeasible, &z) {
                    return Ok((ProofKind::Infeasible, z, v));
                }
            }
            format!("the solver failed ({status})")
        }
    };
    // The closure may hold only on a guard's boundary, which the semantics excludes.
    if let Some((z, _)) = prove_strictly_empty(program, solved)
        && let Some(v) = holds(&ProofKind::Infeasible, &z)
    {
        return Ok((ProofKind::Infeasible, z, v));
    }
    Err(reason)
}
