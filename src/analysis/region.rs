//! Certifying a whole box of parameter values with one proof per piece.
//!
//! The box's pieces and programs come from
//! [`Decomposition::for_box`](crate::proof::schedule::Decomposition::for_box), taken at the
//! box's centre. Each piece's multipliers come from the parent box's proof of the same piece
//! or from Clarabel on the piece's lifted program, whose multipliers are the best any proof
//! over the box can have ([`crate::analysis::region_lift`]); the exact affine bound they prove
//! is then minimised over the box ([`box_proof_value`]). A bound that does not clear the
//! clearance may still belong to a piece whose strict system is empty (its closure holds only
//! on a guard's boundary): snapped Farkas multipliers of the lifted program are tried before
//! giving up.

use rustc_hash::FxHashMap;

use crate::analysis::analyse::prove_strictly_empty;
use crate::analysis::lp::{self, LpOutcome};
use crate::analysis::region_lift::lifted;
use crate::core::model::Problem;
use crate::core::num::{Exact, f64_at_most};
use crate::core::param_box::ParamBox;
use crate::core::parameter::{ParamAffine, Parameter};
use crate::proof::planar::certificate::PlanarCertificate;
use crate::proof::program::{Program, ProofKind};
use crate::proof::region_check::{box_proof_value, describe};
use crate::proof::region_map::BoxProof;
use crate::proof::schedule::{Decomposition, Piece};

/// Proofs found for a box's pieces (keyed by the obstacle in a scene), handed to its
/// halves to try before the solver.
pub type Hints = FxHashMap<(Option<usize>, Piece), (ProofKind, Vec<f64>)>;

/// A box certified: every piece proved, s* above the clearance everywhere in it.
#[derive(Clone, Debug)]
pub struct BoxCertificate {
    /// One proof per piece, in decomposition order.
    pub proofs: Vec<BoxProof>,
    /// The least lower bound on s* over the box.
    pub lower_bound: Exact,
    /// A planar box's proof instead of `proofs`: the certificate at its weak corner.
    pub planar: Option<Box<PlanarCertificate>>,
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
    let mut found = Hints::default();
    match certify_obstacle(&dec, &dec.pieces, None, hints, &mut found, solved) {
        Ok((proofs, lower_bound)) => Ok(BoxCertificate {
            proofs,
            lower_bound,
            planar: None,
        }),
        Err(reason) => Err(NotCertified {
            reason,
            hints: found,
        }),
    }
}

/// Proofs for `pieces` of one obstacle's box decomposition `dec` (tagged with `obstacle`
/// in a scene), each clearing the clearance over the whole box, and the least lower bound
/// they give (the least start when every piece is empty); else why not. Every proof found
/// goes into `found`.
pub(crate) fn certify_obstacle(
    dec: &Decomposition,
    pieces: &[Piece],
    obstacle: Option<usize>,
    hints: &Hints,
    found: &mut Hints,
    solved: &mut usize,
) -> Result<(Vec<BoxProof>, Exact), String> {
    let b = dec.region().expect("a box decomposition");
    let clearance = ParamAffine::parameter(Parameter::Clearance, &dec.params);
    let mut proofs = Vec::with_capacity(pieces.len());
    let mut lower: Option<Exact> = None;
    for piece in pieces {
        let program = dec.program(piece);
        let hint = hints.get(&(obstacle, *piece));
        let (kind, z, bound) = prove_piece(dec, b, &program, piece, &clearance, hint, solved)
            .map_err(|reason| format!("{}: {reason}", describe(piece)))?;
        let least = bound.as_ref().map(|f| b.min_of(f, &dec.params));
        if let Some(l) = &least
            && lower.as_ref().is_none_or(|x| l < x)
        {
            lower = Some(l.clone());
        }
        found.insert((obstacle, *piece), (kind.clone(), z.clone()));
        proofs.push(BoxProof {
            obstacle,
            piece: *piece,
            kind,
            multipliers: z,
            bound: least.as_ref().map(f64_at_most),
        });
    }
    if let Some(lower) = lower {
        return Ok((proofs, lower));
    }
    let start = ParamAffine::parameter(Parameter::InitialGap, &dec.params);
    if b.min_of(&(start.clone() - clearance), &dec.params) <= Exact::ZERO {
        return Err("the obstacle may start within the clearance".into());
    }
    Ok((proofs, b.min_of(&start, &dec.params)))
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
    // The lifted program (the ranged parameters as variables on the box, the clearance
    // subtracted): its multipliers are the best any proof of this piece over the box can
    // have, and its optimum is the least margin over the box (see `region_lift`).
    let lift = lifted(program, b, &dec.params, clearance);
    let rows = program.rows.len();
    *solved += 1;
    let reason = match lp::solve(&lift, 0.0) {
        LpOutcome::Optimal { z, value, .. } if piece.has_objective() => {
            // No multipliers clear the clearance everywhere when the optimum does not.
            if value > 0.0
                && let Some(v) = holds(&ProofKind::Bound, &z[..rows])
            {
                return Ok((ProofKind::Bound, z[..rows].to_vec(), v));
            }
            format!(
                "its worst case comes {:.6} m {} the clearance somewhere in the box",
                value.abs(),
                if value > 0.0 { "above" } else { "below" }
            )
        }
        LpOutcome::Optimal { .. } => "a robot that never brakes is possible in the box".into(),
        LpOutcome::Infeasible { z } => {
            if let Some(v) = holds(&ProofKind::Infeasible, &z[..rows]) {
                return Ok((ProofKind::Infeasible, z[..rows].to_vec(), v));
            }
            "empty over the box, but not provably so".into()
        }
        LpOutcome::Failed { status } => {
            // Without the solver's multipliers, the cheap Farkas candidates.
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
    // The closure may be reached only on a guard's boundary, which the semantics excludes.
    if let Some((z, _)) = prove_strictly_empty(&lift, solved)
        && let Some(v) = holds(&ProofKind::Infeasible, &z[..rows])
    {
        return Ok((ProofKind::Infeasible, z[..rows].to_vec(), v));
    }
    Err(reason)
}
