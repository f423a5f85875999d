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
//!    reproduce the stated trace, collision and separation, and be a run of the piece (and
//!    shift) the witness names;
//! 5. the stated s* must lie in its bracket — the proved lower bound and the witness's
//!    separation — which may be no wider than the tolerance the certificate declares
//!    ([`crate::proof::separation`]);
//! 6. the verdict must follow: `certified` iff every piece is proved and the least bound
//!    exceeds the clearance, `refuted` iff the witness collides.

use serde::{Deserialize, Serialize};

use crate::core::model::Problem;
pub use crate::proof::premise::{Premise, PremiseKind, premises};
use crate::proof::program::ProofKind;
use crate::proof::schedule::Piece;
use crate::proof::verdict::{Verdict, Witness};

pub use crate::proof::check::{CheckReport, Invalid, check};

/// The format tag written into every certificate.
pub const FORMAT: &str = "safereach-certificate/3";

/// One piece's proof.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
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
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Certificate {
    /// Always [`FORMAT`].
    pub format: String,
    /// The verdict.
    pub verdict: Verdict,
    /// s*, the worst-case minimum separation (m), inside its bracket [`lower_bound`,
    /// `witness.separation`] ([`crate::proof::separation`]); null when the robot may never
    /// stop (s* = −∞) or nothing pins it (no bound, no witness that stops, or a bracket
    /// wider than a decided verdict may state).
    ///
    /// [`lower_bound`]: Certificate::lower_bound
    pub min_separation: Option<f64>,
    /// How wide the s* bracket may be (m): 1e-6, or for an inconclusive certificate the
    /// bracket's width rounded up when it is wider.
    pub separation_tolerance: f64,
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
        crate::proof::digest::json_sha256(&copy)
    }
}
