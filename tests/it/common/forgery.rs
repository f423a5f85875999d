//! Tampering with certificates: edits of their numbers and structure, each applied as a
//! careless editor would (the old digest left in place) or as a forger would (re-signed, with
//! consistent premises), and the loops that hold `check` against them. Solver-free (the proof
//! layer only), so a build without the analyser runs them too.

use safereach::core::model::Position;
use safereach::core::num::f64_at_most;
use safereach::proof::certificate::{Certificate, check, premises};
use safereach::proof::program::ProofKind;
use safereach::proof::schedule::{Decomposition, Ending};
use safereach::proof::verdict::Verdict;
use safereach::proof::witness_runs::Speeds;

/// An edit to a certificate; `None` when it does not apply to this certificate.
pub type Edit = fn(&mut Certificate) -> Option<()>;

/// Index of the first proof with a bound (not an infeasibility proof).
pub fn bound_proof(cert: &Certificate) -> Option<usize> {
    cert.proofs
        .iter()
        .position(|p| p.kind == Some(ProofKind::Bound))
}

/// Whether proof `i`'s multipliers now prove another bound than the one stated. (Any
/// multipliers ≥ 0 prove *some* bound; at an exact tie a changed multiplier can prove the
/// same one, and then the edit forges nothing.)
fn proves_another_bound(c: &Certificate, i: usize) -> bool {
    let proof = &c.proofs[i];
    let program = Decomposition::new(&c.problem).program(&proof.piece);
    program
        .bound(&proof.multipliers, true)
        .map(|b| f64_at_most(&b))
        != proof.bound
}

/// Changes one witness speed to another in [0, W].
fn change_witness_speed(c: &mut Certificate) -> Option<()> {
    let w_max = c.problem.environment.obstacle_speed;
    if w_max == 0.0 {
        return None;
    }
    let w = c.witness.as_mut()?;
    let mut speeds = w.obstacle_speeds.to_vec();
    let k = speeds.len().checked_sub(3)?;
    let s = &mut speeds[k];
    *s = if *s > w_max / 2.0 { 0.0 } else { w_max };
    w.obstacle_speeds = Speeds::from_periods(&speeds);
    Some(())
}

/// Edits of numbers (and one of structure) that any honest tool would have to re-sign.
pub const NUMBER_EDITS: &[(&str, Edit)] = &[
    ("obstacle speed W", |c| {
        c.problem.environment.obstacle_speed += 0.01;
        Some(())
    }),
    ("reaction radius", |c| {
        c.problem.controller.reaction_radius += 0.01;
        Some(())
    }),
    ("a multiplier", |c| {
        let i = bound_proof(c)?;
        let z = &mut c.proofs[i].multipliers[0];
        *z = *z * 2.0 + 1.0;
        Some(())
    }),
    ("the lower bound", |c| {
        let lb = c.lower_bound.as_mut()?;
        *lb += 1e-3;
        Some(())
    }),
    ("min_separation", |c| {
        let s = c.min_separation.as_mut()?;
        *s += 1e-3;
        Some(())
    }),
    ("a witness speed", change_witness_speed),
    ("the verdict", |c| {
        c.verdict = match c.verdict {
            Verdict::Certified => Verdict::Refuted,
            _ => Verdict::Certified,
        };
        Some(())
    }),
    ("a dropped proof", |c| {
        c.proofs.pop()?;
        Some(())
    }),
];

/// Applies each of [`NUMBER_EDITS`] to `cert` without re-signing it and asserts `check`
/// rejects the edit and names the digest; returns how many edits applied.
pub fn unsigned_edits_named_as_such(name: &str, cert: &Certificate) -> usize {
    let mut applied = 0;
    for (what, edit) in NUMBER_EDITS {
        let mut forged = cert.clone();
        if edit(&mut forged).is_none() {
            continue;
        }
        applied += 1;
        assert!(forged != *cert, "{what}: no edit");
        let err = check(&forged).expect_err(&format!("{name}: edited {what}, accepted"));
        assert!(
            err.0.contains("digest"),
            "{name}: edited {what}: the message does not name the digest: {err}"
        );
    }
    applied
}

/// Rewrites the derived fields of a forged certificate as a forger would (premises and
/// clearance from the edited problem, the piece count) and signs it again.
pub fn resign(c: &mut Certificate) {
    c.premises = premises(&c.problem);
    c.clearance = c.problem.robot.clearance;
    c.pieces = c.proofs.len();
    c.digest = c.compute_digest();
}

/// Forgeries: each edit is re-signed with a correct digest (and consistent premises), so
/// only the exact re-verification can reject it. Edits of the problem come first (see
/// [`PROBLEM_EDITS`]).
pub const FORGERIES: &[(&str, Edit)] = &[
    ("W raised", |c| {
        c.problem.environment.obstacle_speed += 0.05;
        Some(())
    }),
    ("W lowered", |c| {
        let w = &mut c.problem.environment.obstacle_speed;
        if *w < 0.02 {
            return None;
        }
        *w -= 0.01;
        Some(())
    }),
    ("reaction radius raised", |c| {
        c.problem.controller.reaction_radius += 0.1;
        Some(())
    }),
    ("reaction radius lowered", |c| {
        c.problem.controller.reaction_radius -= 0.1;
        Some(())
    }),
    ("initial gap raised", |c| {
        c.problem.environment.initial_gap =
            Position::At(c.problem.environment.initial_gap.min() + 1.0);
        Some(())
    }),
    ("latency raised", |c| {
        c.problem.robot.latency += 1;
        Some(())
    }),
    ("latency lowered", |c| {
        c.problem.robot.latency = c.problem.robot.latency.checked_sub(1)?;
        Some(())
    }),
    ("clearance raised above s* of a certified problem", |c| {
        if c.verdict != Verdict::Certified {
            return None;
        }
        c.problem.robot.clearance = c.min_separation? + 0.05;
        Some(())
    }),
    // ---- end of problem edits ----
    ("last proof dropped", |c| {
        c.proofs.pop()?;
        Some(())
    }),
    ("first proof dropped", |c| {
        if c.proofs.is_empty() {
            return None;
        }
        c.proofs.remove(0);
        Some(())
    }),
    ("proofs reordered", |c| {
        if c.proofs.len() < 2 {
            return None;
        }
        c.proofs.swap(0, 1);
        Some(())
    }),
    ("proofs reversed", |c| {
        if c.proofs.len() < 2 {
            return None;
        }
        c.proofs.reverse();
        Some(())
    }),
    ("a bound proof's stated bound raised", |c| {
        let i = bound_proof(c)?;
        let b = c.proofs[i].bound.as_mut()?;
        *b += 1e-6;
        Some(())
    }),
    ("a bound proof's stated bound lowered", |c| {
        let i = bound_proof(c)?;
        let b = c.proofs[i].bound.as_mut()?;
        *b -= 1.0;
        Some(())
    }),
    ("a bound proof turned into an infeasibility proof", |c| {
        let i = bound_proof(c)?;
        c.proofs[i].kind = Some(ProofKind::Infeasible);
        Some(())
    }),
    ("a proof removed from a fully proved certificate", |c| {
        c.lower_bound?;
        let i = bound_proof(c)?;
        c.proofs[i].kind = None;
        c.proofs[i].multipliers.clear();
        c.proofs[i].bound = None;
        Some(())
    }),
    ("the largest multiplier of a bound proof doubled", |c| {
        let i = bound_proof(c)?;
        let z = &mut c.proofs[i].multipliers;
        let j = (0..z.len()).max_by(|&a, &b| z[a].total_cmp(&z[b]))?;
        z[j] *= 2.0;
        proves_another_bound(c, i).then_some(())
    }),
    ("a zero multiplier of a bound proof set to 1", |c| {
        let i = bound_proof(c)?;
        let z = c.proofs[i].multipliers.iter_mut().find(|z| **z == 0.0)?;
        *z = 1.0;
        proves_another_bound(c, i).then_some(())
    }),
    ("a multiplier dropped", |c| {
        let i = bound_proof(c)?;
        c.proofs[i].multipliers.pop()?;
        Some(())
    }),
    ("lower bound raised", |c| {
        let lb = c.lower_bound.as_mut()?;
        *lb += 1e-3;
        Some(())
    }),
    ("lower bound invented", |c| {
        if c.lower_bound.is_some() {
            return None;
        }
        c.lower_bound = Some(1.0);
        Some(())
    }),
    ("refuted -> certified", |c| {
        if c.verdict != Verdict::Refuted {
            return None;
        }
        c.verdict = Verdict::Certified;
        Some(())
    }),
    ("refuted -> inconclusive", |c| {
        if c.verdict != Verdict::Refuted {
            return None;
        }
        c.verdict = Verdict::Inconclusive;
        Some(())
    }),
    ("certified -> inconclusive", |c| {
        if c.verdict != Verdict::Certified {
            return None;
        }
        c.verdict = Verdict::Inconclusive;
        Some(())
    }),
    ("certified -> refuted", |c| {
        if c.verdict != Verdict::Certified {
            return None;
        }
        c.verdict = Verdict::Refuted;
        Some(())
    }),
    ("a witness speed changed", change_witness_speed),
    ("a witness speed above W", |c| {
        let w_max = c.problem.environment.obstacle_speed;
        let w = c.witness.as_mut()?;
        let mut speeds = w.obstacle_speeds.to_vec();
        *speeds.first_mut()? = w_max * 1.5 + 0.01;
        w.obstacle_speeds = Speeds::from_periods(&speeds);
        Some(())
    }),
    ("witness speeds cut short", |c| {
        let w = c.witness.as_mut()?;
        let n = w.obstacle_speeds.len().checked_sub(1)?;
        w.obstacle_speeds.resize(n, 0.0);
        Some(())
    }),
    ("a robot mode segment moved by one period", |c| {
        let w = c.witness.as_mut()?;
        let (first, rest) = w.robot_modes.split_first_mut()?;
        let second = rest.first_mut()?;
        first.length += 1;
        second.start += 1;
        second.length = second.length.checked_sub(1).filter(|&n| n > 0)?;
        Some(())
    }),
    ("a robot mode segment's mode changed", |c| {
        let w = c.witness.as_mut()?;
        let last = w.robot_modes.last_mut()?;
        last.mode = if last.mode == safereach::core::semantics::Mode::Brake {
            safereach::core::semantics::Mode::Drive
        } else {
            safereach::core::semantics::Mode::Brake
        };
        Some(())
    }),
    ("the witness's collision flag flipped", |c| {
        let w = c.witness.as_mut()?;
        w.collides = !w.collides;
        Some(())
    }),
    ("the witness removed from a refutation", |c| {
        if c.verdict != Verdict::Refuted {
            return None;
        }
        c.witness.take()?;
        Some(())
    }),
    ("min_separation moved", |c| {
        let s = c.min_separation.as_mut()?;
        *s += 1e-3;
        Some(())
    }),
    ("never_stops claimed against a witness", |c| {
        if c.never_stops || c.witness.is_none() {
            return None;
        }
        c.never_stops = true;
        c.min_separation = None;
        Some(())
    }),
    // ---- s* against its bracket [lower_bound, witness.separation] ----
    ("min_separation just above the witness's separation", |c| {
        let r = c.witness.as_ref()?.separation?;
        c.min_separation?;
        c.min_separation = Some(r + 1e-9);
        Some(())
    }),
    ("min_separation just below the proved lower bound", |c| {
        let lb = c.lower_bound?;
        c.min_separation?;
        c.min_separation = Some(lb - 1e-9);
        Some(())
    }),
    ("separation_tolerance widened", |c| {
        c.separation_tolerance = 0.5;
        Some(())
    }),
    ("separation_tolerance narrowed", |c| {
        c.separation_tolerance /= 2.0;
        Some(())
    }),
    ("min_separation stated without a proved lower bound", |c| {
        if c.lower_bound.is_some() || c.min_separation.is_some() {
            return None;
        }
        c.min_separation = Some(c.witness.as_ref()?.separation?);
        Some(())
    }),
    // ---- the witness's piece and shift against its replay ----
    ("the witness's shift moved up", |c| {
        c.witness.as_mut()?.shift += 1;
        Some(())
    }),
    ("the witness's shift moved down", |c| {
        let w = c.witness.as_mut()?;
        w.shift = w.shift.checked_sub(1)?;
        Some(())
    }),
    ("the witness's piece moved a step later", |c| {
        c.witness.as_mut()?.piece.brake += 1;
        Some(())
    }),
    (
        "the witness's piece moved a step later, its shift one less",
        |c| {
            let w = c.witness.as_mut()?;
            w.shift = w.shift.checked_sub(1)?;
            w.piece.brake += 1;
            Some(())
        },
    ),
    // (Danger and wrong-assumption pieces overlap: a run may be in both, so relabelling one
    // as the other can be a true claim. Braking and not braking cannot both be.)
    ("the witness's piece given another ending", |c| {
        let piece = &mut c.witness.as_mut()?.piece;
        piece.ending = match piece.ending {
            Ending::PassThrough => Ending::Danger,
            _ => Ending::PassThrough,
        };
        Some(())
    }),
    ("the witness's entry moved a step earlier", |c| {
        let piece = &mut c.witness.as_mut()?.piece;
        piece.entry = Some(piece.entry?.checked_sub(1)?);
        Some(())
    }),
    ("the witness's entry moved a step later", |c| {
        let piece = &mut c.witness.as_mut()?.piece;
        piece.entry = Some(piece.entry? + 1);
        Some(())
    }),
    ("the witness's piece unmerged", |c| {
        let piece = &mut c.witness.as_mut()?.piece;
        if !piece.merged {
            return None;
        }
        piece.merged = false;
        Some(())
    }),
];

/// How many of [`FORGERIES`] edit the problem.
pub const PROBLEM_EDITS: usize = 8;

/// Checks every applicable forgery of `cert`; returns how many applied, or the first one
/// `check` accepted. An edit of the problem that leaves it valid is skipped when
/// `claims_still_true` says the certificate's claims hold of the edited problem (then the old
/// proofs may well prove it, and accepting them is no mistake).
pub fn forgeries_rejected(
    name: &str,
    cert: &Certificate,
    claims_still_true: impl Fn(&Certificate) -> bool,
) -> Result<usize, String> {
    check(cert).map_err(|e| format!("{name}: the honest certificate is rejected: {e}"))?;
    let mut applied = 0;
    for (i, (what, edit)) in FORGERIES.iter().enumerate() {
        let mut forged = cert.clone();
        if edit(&mut forged).is_none() {
            continue;
        }
        resign(&mut forged);
        if i < PROBLEM_EDITS
            && forged.problem.validate("forged").is_ok()
            && claims_still_true(&forged)
        {
            continue;
        }
        applied += 1;
        if forged == *cert {
            return Err(format!("{name}: {what}: no edit"));
        }
        match check(&forged) {
            Ok(report) => {
                return Err(format!(
                    "{name}: forgery accepted: {what} (report {report:?})"
                ));
            }
            Err(e) if e.0.contains("digest") => {
                return Err(format!(
                    "{name}: {what}: a re-signed forgery is blamed on the digest: {e}"
                ));
            }
            Err(_) => {}
        }
    }
    Ok(applied)
}

/// A region map re-signed after an edit, as a forger would.
pub fn resign_map(
    mut m: safereach::proof::region_map::RegionMap,
) -> safereach::proof::region_map::RegionMap {
    m.digest = m.compute_digest();
    m
}

/// `check_map` rejects the forged (re-signed) map `m`; `why` names the forgery.
pub fn map_rejected(m: safereach::proof::region_map::RegionMap, why: &str) {
    let e = safereach::proof::region_check::check_map(&resign_map(m)).expect_err(why);
    eprintln!("{why}: {}", e.0);
}

/// The map with its first axis's upper end moved to `hi` and every leaf's box following
/// its path in the new whole box.
pub fn with_first_axis_to(
    m: &safereach::proof::region_map::RegionMap,
    hi: f64,
) -> safereach::proof::region_map::RegionMap {
    use safereach::proof::region_map::{bounds_of, box_at};
    let mut x = m.clone();
    x.ranges[0].hi = hi;
    let whole = x.whole();
    for l in &mut x.leaves {
        l.bounds = bounds_of(&box_at(&whole, &l.path).expect("path"));
    }
    x
}

/// Halves the largest multiplier of the leaf's longest proof.
pub fn halve_largest_multiplier(leaf: &mut safereach::proof::region_map::Leaf) {
    let proof = leaf
        .proofs
        .iter_mut()
        .max_by_key(|p| p.multipliers.len())
        .expect("a proof");
    let k = (0..proof.multipliers.len())
        .max_by(|&a, &b| proof.multipliers[a].total_cmp(&proof.multipliers[b]))
        .expect("multipliers");
    proof.multipliers[k] *= 0.5;
}
