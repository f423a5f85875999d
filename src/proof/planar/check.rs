//! `check` for planar certificates ([`PlanarCertificate`]), without the solver: every number
//! the verdict rests on is recomputed from the problem's text in exact rationals.
//!
//! 1. the digest must match, and the problem text (with its overrides) must read;
//! 2. per bound run and obstacle, the pieces are rebuilt from the problem and the run's
//!    goal (Lemmas P2, P5, P6), and the leaves must tile each piece's initial cover sets
//!    exactly ([`super::tiling`]);
//! 3. each leaf's second-order cone program is rebuilt (Lemma P4) and its bound recomputed
//!    from the stored multipliers ([`Program::bound`](crate::proof::program::Program::bound):
//!    SOC duals inside the dual cone, z₀ ≥ ‖z₁..‖ exactly), or its emptiness from a Farkas
//!    proof; a leaf without multipliers has the floor −(r_R + r_i + D), which holds always;
//! 4. a run proves s* ≥ min(least leaf bound, goal), since instants past its horizon are
//!    above the goal; the certificate's lower bound must be the greatest such claim;
//! 5. the witness is replayed exactly and must reproduce its record;
//! 6. the verdict must follow: `refuted` iff the witness collides; `certified` iff some run
//!    whose goal is at least the clearance has every leaf strictly above it; else
//!    `inconclusive`. Both at once is a contradiction, and rejected.

use crate::core::num::{Exact, f64_at_least, f64_at_most};
use crate::core::planar::{PlanarParams, PlanarProblem};
use crate::proof::check::{CheckReport, Invalid};
use crate::proof::verdict::Verdict;

use super::certificate::{BoundRun, LeafProof, PLANAR_FORMAT, PlanarCertificate};
use super::domain::ObstacleDomain;
use super::exact_text::{read, write};
use super::tiling::{self, Cell, Split};
use super::witness_record;

fn invalid<T>(why: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(why.into()))
}

/// What one run proves.
struct RunClaim {
    claim: Exact,
    above_clearance: bool,
}

/// Re-verifies `cert` without the solver.
pub fn check_planar(cert: &PlanarCertificate) -> Result<CheckReport, Invalid> {
    if cert.format != PLANAR_FORMAT {
        return invalid(format!(
            "format is {:?}, expected {PLANAR_FORMAT:?}",
            cert.format
        ));
    }
    if cert.compute_digest() != cert.digest {
        return invalid("digest mismatch: the certificate was edited after it was written");
    }
    let problem = PlanarProblem::from_toml_str_with_overrides(
        &cert.problem_toml,
        "the certificate's problem",
        &cert.overrides,
    )
    .map_err(|e| Invalid(format!("the certificate's problem does not read: {e}")))?;
    if problem.name != cert.problem {
        return invalid(format!(
            "it names the problem {:?}; its problem text is {:?}",
            cert.problem, problem.name
        ));
    }
    let params = problem.params();
    let clearance = params.motion.clearance.clone();
    if cert.clearance != clearance.to_f64().value() {
        return invalid(format!(
            "it states the clearance {}; the problem's is {}",
            cert.clearance,
            clearance.to_f64().value()
        ));
    }
    if cert.runs.is_empty() {
        return invalid("it has no bound run");
    }
    let mut lower: Option<Exact> = None;
    let mut above = false;
    for (r, run) in cert.runs.iter().enumerate() {
        let c = check_run(&params, run).map_err(|e| Invalid(format!("run {r}: {e}")))?;
        above |= c.above_clearance;
        if lower.as_ref().is_none_or(|l| c.claim > *l) {
            lower = Some(c.claim);
        }
    }
    let lower = lower.expect("a run");
    if cert.lower_bound_exact != write(&lower) || cert.lower_bound != f64_at_most(&lower) {
        return invalid(format!(
            "it states s* >= {} ({}); its runs prove s* >= {}",
            cert.lower_bound,
            cert.lower_bound_exact,
            write(&lower)
        ));
    }
    let upper = match &cert.witness {
        Some(w) => Some(
            witness_record::replay(&params, w).map_err(|e| Invalid(format!("the witness: {e}")))?,
        ),
        None => None,
    };
    if cert.upper_bound != upper.as_ref().map(f64_at_least) {
        return invalid(format!(
            "it states s* <= {:?}; the witness's replay gives {:?}",
            cert.upper_bound,
            upper.as_ref().map(f64_at_least)
        ));
    }
    if let Some(u) = &upper
        && *u < lower
    {
        return invalid("the witness separates less than the proved bound: they contradict");
    }
    check_bracket(cert, &lower, upper.as_ref())?;
    let collides = cert.witness.as_ref().is_some_and(|w| w.collides);
    if collides && above {
        return invalid("a run proves every instant above the clearance, yet the witness collides");
    }
    let verdict = if collides {
        Verdict::Refuted
    } else if above {
        Verdict::Certified
    } else {
        Verdict::Inconclusive
    };
    if verdict != cert.verdict {
        return invalid(format!(
            "it states {}; its proofs and witness give {}",
            cert.verdict.as_str(),
            verdict.as_str()
        ));
    }
    Ok(CheckReport {
        verdict,
        pieces: cert.leaves(),
        lower_bound: Some(lower),
    })
}

/// The stated s* must sit in the bracket, and be stated only when the bracket is narrower
/// than the tolerance.
fn check_bracket(
    cert: &PlanarCertificate,
    lower: &Exact,
    upper: Option<&Exact>,
) -> Result<(), Invalid> {
    let tol = cert.separation_tolerance;
    if !(tol.is_finite() && tol >= 0.0) {
        return invalid(format!("its separation tolerance {tol} is not a width"));
    }
    let narrow = upper.is_some_and(|u| u - lower <= crate::core::num::exact_decimal(tol));
    match (cert.min_separation, narrow, upper) {
        (None, false, _) => Ok(()),
        (Some(s), true, Some(u)) if f64_at_most(lower) <= s && s <= f64_at_least(u) => Ok(()),
        (Some(s), true, _) => invalid(format!("its s* {s} is outside its bracket")),
        (None, true, _) => invalid("it states no s* though its bracket is within tolerance"),
        (Some(s), false, _) => invalid(format!(
            "it states s* = {s} though its bracket is wider than its tolerance {tol}"
        )),
    }
}

fn check_run(params: &PlanarParams, run: &BoundRun) -> Result<RunClaim, String> {
    let goal = read(&run.goal).ok_or("its goal is not a rational")?;
    if run.obstacles.len() != params.obstacles.len() {
        return Err(format!(
            "it has leaves for {} obstacles; the problem has {}",
            run.obstacles.len(),
            params.obstacles.len()
        ));
    }
    let mut least: Option<Exact> = None;
    for (i, leaves) in run.obstacles.iter().enumerate() {
        let name = &params.obstacles[i].name;
        if leaves.name != *name {
            return Err(format!(
                "its obstacle {i} is {:?}; the problem's is {name:?}",
                leaves.name
            ));
        }
        let own = check_obstacle(params, i, &goal, run.step_limit, &leaves.leaves)
            .map_err(|e| format!("obstacle {name:?}: {e}"))?;
        if leaves.lower_bound != own.as_ref().map(f64_at_most) {
            return Err(format!(
                "obstacle {name:?}: it states the bound {:?}; its leaves prove {:?}",
                leaves.lower_bound,
                own.as_ref().map(|b| b.to_f64().value())
            ));
        }
        if let Some(b) = own
            && least.as_ref().is_none_or(|l| b < *l)
        {
            least = Some(b);
        }
    }
    let clearance = &params.motion.clearance;
    let claim = match &least {
        Some(l) if *l <= goal => l.clone(),
        _ => goal.clone(),
    };
    if run.claim != f64_at_most(&claim) {
        return Err(format!(
            "it claims {}; its leaves and goal prove {}",
            run.claim,
            write(&claim)
        ));
    }
    Ok(RunClaim {
        above_clearance: goal >= *clearance && least.as_ref().is_none_or(|l| l > clearance),
        claim,
    })
}

/// The least bound over obstacle `index`'s leaves (None: all empty), once they tile its
/// pieces and each proof holds.
fn check_obstacle(
    params: &PlanarParams,
    index: usize,
    goal: &Exact,
    step_limit: usize,
    leaves: &[LeafProof],
) -> Result<Option<Exact>, String> {
    let mut domain = ObstacleDomain::new(params, index, goal, step_limit)
        .map_err(|e| format!("its pieces cannot be listed: {e:?}"))?;
    let floor = -domain.radii.clone();
    let pieces = domain.pieces.clone();
    let roots: Vec<Vec<Cell>> = pieces
        .iter()
        .map(|p| {
            domain
                .initial_covers(p)
                .into_iter()
                .map(|cover| Cell {
                    from: p.from.clone(),
                    to: p.to.clone(),
                    cover,
                })
                .collect()
        })
        .collect();
    let mut names: Vec<Vec<Vec<Vec<Split>>>> =
        roots.iter().map(|c| vec![Vec::new(); c.len()]).collect();
    let mut least: Option<Exact> = None;
    for (n, leaf) in leaves.iter().enumerate() {
        let at = format!(
            "leaf {n} (piece {}, cover {}, {:?})",
            leaf.piece, leaf.cover, leaf.splits
        );
        let Some(root) = roots.get(leaf.piece).and_then(|c| c.get(leaf.cover)) else {
            return Err(format!("{at}: no such piece or cover set"));
        };
        let splits = tiling::read(&leaf.splits).ok_or(format!("{at}: unreadable splits"))?;
        let cell = root
            .descend(&splits)
            .ok_or(format!("{at}: splits an arc of a cover set that has none"))?;
        let program = domain
            .leaf(&pieces[leaf.piece], &cell.from, &cell.to, &cell.cover)
            .program();
        let z = &leaf.multipliers;
        if !z.is_empty() && z.len() != program.rows.len() {
            return Err(format!(
                "{at}: {} multipliers for {} rows",
                z.len(),
                program.rows.len()
            ));
        }
        if leaf.empty {
            let proved = if z.is_empty() {
                program.infeasible_row().is_some()
            } else {
                program.proves_empty(z).is_some()
            };
            if !proved || leaf.bound.is_some() {
                return Err(format!("{at}: its proof of emptiness does not hold"));
            }
        } else {
            let bound = if z.is_empty() {
                floor.clone()
            } else {
                let b = program
                    .bound(z, true)
                    .ok_or(format!("{at}: its multipliers prove no bound"))?;
                if b < floor { floor.clone() } else { b }
            };
            if leaf.bound != Some(f64_at_most(&bound)) {
                return Err(format!(
                    "{at}: it states the bound {:?}; its multipliers prove {}",
                    leaf.bound,
                    bound.to_f64().value()
                ));
            }
            if least.as_ref().is_none_or(|l| bound < *l) {
                least = Some(bound);
            }
        }
        names[leaf.piece][leaf.cover].push(splits);
    }
    for (p, covers) in names.iter().enumerate() {
        for (c, list) in covers.iter().enumerate() {
            let refs: Vec<&[Split]> = list.iter().map(|v| v.as_slice()).collect();
            tiling::tiles(&refs).map_err(|e| format!("piece {p}, cover set {c}: {e}"))?;
        }
    }
    Ok(least)
}
