//! The planar answer as a certificate (`proof::planar::certificate`) that `check`
//! re-verifies without the solver: the problem's text, each bound run's leaves with their
//! multipliers, and the witness's exact record.

use crate::core::num::{Exact, exact_decimal, f64_at_least, f64_at_most};
use crate::core::planar::PlanarParams;
use crate::proof::planar::certificate::{BoundRun, PLANAR_FORMAT, PlanarCertificate};
use crate::proof::planar::exact_text::write;
use crate::proof::planar::witness_record::record;
use crate::proof::verdict::Verdict;

use super::certify::{PlanarAnswer, PlanarVerdict, claim};
use super::lower_bound::BoundOptions;

/// The problem as the certificate stores it: its file's text and `--set` overrides, as read.
pub struct ProblemText<'a> {
    /// The file's text.
    pub toml: &'a str,
    /// The overrides, in order.
    pub overrides: &'a [String],
}

/// The certificate of `answer` for the problem `text` states (read as `params`), its s*
/// stated when the bracket is at most `tolerance` wide.
pub fn planar_certificate(
    text: &ProblemText<'_>,
    name: &str,
    params: &PlanarParams,
    answer: &PlanarAnswer,
    options: &BoundOptions,
    tolerance: f64,
) -> PlanarCertificate {
    let witness = answer
        .witness
        .as_ref()
        .and_then(|w| record(params, &w.behaviour, &w.run));
    let min_separation = answer.upper.as_ref().and_then(|u| {
        // The bracket's middle, inside it after rounding (the check requires that).
        let middle = (u + &answer.lower) / Exact::from(2);
        (u - &answer.lower <= exact_decimal(tolerance)).then(|| middle.to_f64().value())
    });
    let runs = answer
        .runs
        .iter()
        .map(|(goal, bound)| BoundRun {
            goal: write(goal),
            step_limit: options.step_limit,
            claim: f64_at_most(&claim(bound, goal)),
            obstacles: bound.proofs.clone(),
        })
        .collect();
    let mut cert = PlanarCertificate {
        format: PLANAR_FORMAT.to_string(),
        problem: name.to_string(),
        verdict: match answer.verdict {
            PlanarVerdict::Certified => Verdict::Certified,
            PlanarVerdict::Refuted => Verdict::Refuted,
            PlanarVerdict::Inconclusive => Verdict::Inconclusive,
        },
        clearance: params.motion.clearance.to_f64().value(),
        lower_bound: f64_at_most(&answer.lower),
        lower_bound_exact: write(&answer.lower),
        upper_bound: answer.upper.as_ref().map(f64_at_least),
        min_separation,
        separation_tolerance: tolerance,
        programs: answer.programs,
        budget_exhausted: answer.exhausted,
        unsolved_leaves: answer.unsolved,
        witness,
        problem_toml: text.toml.to_string(),
        overrides: text.overrides.to_vec(),
        runs,
        digest: String::new(),
    };
    cert.digest = cert.compute_digest();
    cert
}
