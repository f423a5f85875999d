//! The planar verdict (docs/semantics.md §13.5): a proved lower bound on s* from the
//! anchored relaxation, a witness's exact replay from above, and the verdict only where
//! one of them decides it.
//!
//! The bound holds for the instants up to the horizon its goal sets; past the horizon
//! every separation is proved above the goal (Lemma P6), so what is claimed is
//! min(bound, goal). The goal is the clearance first; once a witness is replayed, it is the
//! witness's separation less the tolerance, so a tight relaxation closes the bracket.

use crate::core::num::Exact;
use crate::core::planar::{PlanarBehaviour, PlanarParams};

use super::lower_bound::{BoundOptions, LowerBound, LowerBoundError, lower_bound};
use super::pursuit::pursuit_witness;
use super::witness::{Witness, steps_after, witness_untried};

/// What the planar analysis decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanarVerdict {
    /// Every behaviour keeps every separation above the clearance while the robot moves.
    Certified,
    /// A replayed behaviour reaches the clearance while the robot moves.
    Refuted,
    /// The bound is at or below the clearance and no witness reaches it.
    Inconclusive,
}

impl PlanarVerdict {
    /// As the CLI prints it.
    pub fn as_str(self) -> &'static str {
        match self {
            PlanarVerdict::Certified => "certified",
            PlanarVerdict::Refuted => "refuted",
            PlanarVerdict::Inconclusive => "inconclusive",
        }
    }
}

/// The planar answer.
#[derive(Clone, Debug)]
pub struct PlanarAnswer {
    /// The verdict.
    pub verdict: PlanarVerdict,
    /// s* ≥ this, proved in exact arithmetic (with a certified verdict, every instant's
    /// separation is strictly above the clearance even when this equals it).
    pub lower: Exact,
    /// s* ≤ this: the witness's replayed separation (None: no witness).
    pub upper: Option<Exact>,
    /// The least replayed behaviour.
    pub witness: Option<Witness>,
    /// Programs solved in all.
    pub programs: usize,
    /// Some bound ran out of budget.
    pub exhausted: bool,
    /// Leaves the solver could not bound (given the floor instead).
    pub unsolved: usize,
    /// Each bound run's goal and bound, with its leaves' proofs: what the certificate
    /// stores.
    pub runs: Vec<(Exact, LowerBound)>,
}

/// The planar verdict for `params`, s* bracketed to `tolerance` where the relaxation
/// allows.
pub fn certify_planar(
    params: &PlanarParams,
    options: &BoundOptions,
    tolerance: &Exact,
) -> Result<PlanarAnswer, LowerBoundError> {
    let clearance = params.motion.clearance.clone();
    let first = lower_bound(params, &clearance, options)?;
    // Every instant strictly above the clearance: every leaf above it, or no leaf at all
    // (empty pieces, and instants past the horizon proved above it).
    let mut above = first.worst.is_none() || first.lower > clearance;
    let mut answer = PlanarAnswer {
        verdict: PlanarVerdict::Inconclusive,
        lower: claim(&first, &clearance),
        upper: None,
        witness: None,
        programs: first.programs,
        exhausted: first.exhausted,
        unsolved: first.unsolved,
        runs: Vec::new(),
    };
    let mut tried = Vec::new();
    consider(params, &first, &mut answer, &mut tried);
    consider_pursuit(params, &mut answer);
    answer.runs.push((clearance.clone(), first));
    if let Some(u) = answer.upper.clone()
        && u > clearance
        && answer.lower < &u - tolerance
    {
        // Refine towards the witness: the relaxation may prove all but the tolerance.
        let goal = &u - tolerance;
        let second = lower_bound(params, &goal, options)?;
        answer.programs += second.programs;
        answer.exhausted |= second.exhausted;
        answer.unsolved += second.unsolved;
        // Past its horizon this run proves only "above the goal": it shows every instant
        // above the clearance only when its goal is not below the clearance.
        above |= goal >= clearance && (second.worst.is_none() || second.lower > clearance);
        let l = claim(&second, &goal);
        if l > answer.lower {
            answer.lower = l;
        }
        consider(params, &second, &mut answer, &mut tried);
        answer.runs.push((goal, second));
    }
    let collides = answer
        .witness
        .as_ref()
        .and_then(|w| w.run.collides(&clearance));
    answer.verdict = if collides == Some(true) {
        PlanarVerdict::Refuted
    } else if above {
        PlanarVerdict::Certified
    } else {
        PlanarVerdict::Inconclusive
    };
    Ok(answer)
}

/// The bound alone, with the clearance as its goal and no witness: `certified` when it
/// proves every instant above the clearance, else `inconclusive` (never `refuted`). What a
/// region map needs at a box's corner, for about a quarter of [`certify_planar`]'s work.
pub fn bound_planar(
    params: &PlanarParams,
    options: &BoundOptions,
) -> Result<PlanarAnswer, LowerBoundError> {
    let clearance = params.motion.clearance.clone();
    let bound = lower_bound(params, &clearance, options)?;
    let above = bound.worst.is_none() || bound.lower > clearance;
    Ok(PlanarAnswer {
        verdict: if above {
            PlanarVerdict::Certified
        } else {
            PlanarVerdict::Inconclusive
        },
        lower: claim(&bound, &clearance),
        upper: None,
        witness: None,
        programs: bound.programs,
        exhausted: bound.exhausted,
        unsolved: bound.unsolved,
        runs: vec![(clearance, bound)],
    })
}

/// What a bound run with `goal` proves about every instant: min(bound, goal), or nothing
/// the goal when it has no leaf (every instant is past the horizon or in an empty piece,
/// so above the goal).
pub(super) fn claim(bound: &LowerBound, goal: &Exact) -> Exact {
    match &bound.worst {
        Some(_) if bound.lower <= *goal => bound.lower.clone(),
        _ => goal.clone(),
    }
}

/// The most periods a pursuit is replayed for.
const PURSUIT_STEPS: usize = 2000;

/// Replays pursuit witnesses (`pursuit`) for as long as the robot takes to drive its path
/// and brake, and keeps the least so far.
fn consider_pursuit(params: &PlanarParams, answer: &mut PlanarAnswer) {
    let m = &params.motion;
    let drive = params.path.length() / &m.v_max + &m.v_max / &m.a;
    let steps = steps_after(params, &drive).min(PURSUIT_STEPS);
    let Some(found) = pursuit_witness(params, steps) else {
        return;
    };
    if let Some(u) = found.upper()
        && answer.upper.as_ref().is_none_or(|a| u < *a)
    {
        answer.upper = Some(u);
        answer.witness = Some(found);
    }
}

/// Replays witnesses from `bound`'s lowest leaves and keeps the least so far.
fn consider(
    params: &PlanarParams,
    bound: &LowerBound,
    answer: &mut PlanarAnswer,
    tried: &mut Vec<(PlanarBehaviour, usize)>,
) {
    for leaf in &bound.low {
        let Some(found) = witness_untried(params, leaf, tried) else {
            continue;
        };
        let Some(u) = found.upper() else {
            continue;
        };
        if answer.upper.as_ref().is_none_or(|a| u < *a) {
            answer.upper = Some(u);
            answer.witness = Some(found);
        }
    }
}
