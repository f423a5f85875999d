//! From an analysis to its certificate: the proofs of every piece, the witness and the
//! premises, sealed with the digest. (The certificate format and its check live in
//! [`crate::proof`], which never depends on the analyser.)

use crate::analysis::{Analysis, PieceResult};
use crate::core::num::f64_at_most;
use crate::proof::certificate::{Certificate, FORMAT, Proof, premises};

impl Certificate {
    /// The certificate of an analysis.
    pub fn from_analysis(a: &Analysis) -> Self {
        let proofs = a
            .outcomes
            .iter()
            .map(|o| match &o.result {
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
            })
            .collect();
        let mut cert = Certificate {
            format: FORMAT.into(),
            verdict: a.verdict,
            min_separation: a.min_separation,
            never_stops: a.never_stops,
            lower_bound: a.lower_bound.as_ref().map(f64_at_most),
            clearance: a.problem.robot.clearance,
            premises: premises(&a.problem),
            witness: a.witness.clone(),
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
